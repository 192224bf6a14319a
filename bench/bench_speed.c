/* SPDX-License-Identifier: MIT */
/*
 * Speed, structure and memory benchmark. Prints Markdown tables; never
 * passes or fails on a time (tests do the checking).
 *   bench_speed                       every table (host ns/sample)
 *   bench_speed run WHAT N SAMPLES    one workload for callgrind, where WHAT
 *                                     is ctrl-{p,dd,id,pid}-{f32,q15} or
 *                                     op-{relay,bellows,restrictor}-{ours,df1}-{f32,q15};
 *                                     N = Oustaloup order (0: default)
 * The alternative to the library's parallel leaky form is a direct-form-I
 * biquad cascade of the same design and total order (pfh_sos.c, run with
 * CMSIS's DF1 semantics by pfh_df1.c), in float and in CMSIS-style Q15.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "pfh_sos.h"
#include "pfh_df1.h"
#include "pneufrac/pneufrac.h"

#define FS 20000.0
#define LEN 20000   /* samples per timed run: 1 s at 20 kHz */
#define REPS 15     /* timed runs; the median is reported */
#define MAX_INST 256

static volatile double sink; /* keeps the optimiser from dropping work */

static double now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e9 + ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* ---- workloads ---------------------------------------------------------- */

typedef struct ctrl_work {
    pf_ctrl_design d;
    pf_ctrl_coeffs_f32 cf;
    pf_ctrl_coeffs_q15 cq;
    pf_ctrl_f32 f[MAX_INST];
    pf_ctrl_q15 q[MAX_INST];
} ctrl_work;

static ctrl_work cw;

/* Peak of the double step response over 2 s: the Q15 output full scale. */
static double peak_f64(const pf_ctrl_design *d)
{
    static pf_ctrl_f64 c;
    double peak = 0.0;
    long n;
    pf_ctrl_init_f64(&c, &d->rt, NULL, 0);
    for (n = 0; n < 2 * (long)d->opt.fs; n++) {
        double y = fabs(pf_ctrl_step_f64(&c, 1.0));
        if (y > peak)
            peak = y;
    }
    return peak;
}

static int ctrl_setup(pf_topology cfg, int order)
{
    pf_params p;
    pf_design_opts o;
    pf_params_default(&p, cfg);
    pf_design_opts_default(&o, FS);
    o.order = order;
    if (pf_ctrl_design_make(&cw.d, &p, NULL, &o) != PF_OK)
        return -1;
    pf_ctrl_coeffs_f32_make(&cw.cf, &cw.d.rt);
    /* a unit step is half of in_fs = 2 */
    return pf_ctrl_coeffs_q15_make(&cw.cq, &cw.d, 2.0, 1.25 * peak_f64(&cw.d)) == PF_OK
               ? 0 : -1;
}

/* Run ninst instances for len samples each of a unit step. */
static void ctrl_run(int q15, int ninst, long len)
{
    int i;
    long n;
    double acc = 0.0;
    for (i = 0; i < ninst; i++) {
        if (q15)
            pf_ctrl_init_q15(&cw.q[i], &cw.cq, NULL, 0);
        else
            pf_ctrl_init_f32(&cw.f[i], &cw.cf, NULL, 0);
    }
    for (n = 0; n < len; n++)
        for (i = 0; i < ninst; i++)
            acc += q15 ? pf_ctrl_step_q15(&cw.q[i], 16384) : pf_ctrl_step_f32(&cw.f[i], 1.0f);
    sink = acc;
}

/* MACs per sample counted from the structure: an operator does two per
 * leaky section (lam (u - s), G s), one for its feedthrough and two per
 * integer stage; the loop solution of pf_ctrl_float.inc adds 13
 * multiplications, 2 per restrictor and 1 for a linear-spring bellows. */
static int op_macs(const pf_fracop_design *op)
{
    return 2 * op->n_sec + 1 + 2 * abs(op->n_int);
}

static int ctrl_macs(const pf_ctrl_coeffs_f64 *c)
{
    int m = 13 + op_macs(&c->P);
    m += c->has_q ? op_macs(&c->Q) : 1;
    m += c->has_v ? 2 + op_macs(&c->V) : 0;
    m += c->has_w ? 2 + op_macs(&c->W) : 0;
    return m;
}

static int ctrl_sections(const pf_ctrl_coeffs_f64 *c)
{
    return c->P.n_sec + (c->has_q ? c->Q.n_sec : 0) + (c->has_v ? c->V.n_sec : 0) +
           (c->has_w ? c->W.n_sec : 0);
}

/* One operator four ways: ours (float, Q15) and the DF1 cascade (float,
 * Q15). Q15 maps a half-scale step to 1.25 x the exact peak at 2 s. */
typedef struct op_work {
    const char *name;
    double alpha, gain, peak;
    pf_fracop_design d;
    pf_design_opts opt;
    pf_fracop_coeffs_f32 cf;
    pf_fracop_coeffs_q15 cq;
    pfh_sos sos_f, sos_q;
    float df1_f[5 * PFH_SOS_MAX];
    pfh_sos_q15 df1_q;
} op_work;

static op_work ow;

static int op_setup(const char *name, int order)
{
    double out_fs;
    pf_design_opts_default(&ow.opt, FS);
    ow.opt.order = order;
    if (pf_design_opts_resolve(&ow.opt, &ow.opt) != PF_OK)
        return -1;
    ow.name = name;
    /* Example 6's operators: relay (tau s)^-0.8, bellows (A/ks) s^-0.9,
     * restrictor (1/RC) s^-0.94. */
    if (strcmp(name, "relay") == 0) {
        ow.alpha = -0.8;
        ow.gain = pow(1e-3, -0.8);
    } else if (strcmp(name, "bellows") == 0) {
        ow.alpha = -0.9;
        ow.gain = 0.1;
    } else {
        ow.alpha = -0.94;
        ow.gain = 10.0;
    }
    /* exact step response gain t^-alpha / Gamma(1 - alpha), peak at 2 s */
    ow.peak = ow.gain * pow(2.0, -ow.alpha) / tgamma(1.0 - ow.alpha);
    out_fs = 1.25 * ow.peak;
    if (pf_fracop_design_make(&ow.d, ow.alpha, ow.gain, &ow.opt) != PF_OK)
        return -1;
    pf_fracop_coeffs_f32_make(&ow.cf, &ow.d);
    if (pf_fracop_coeffs_q15_make(&ow.cq, &ow.d, 2.0, out_fs) != PF_OK)
        return -1;
    if (pfh_sos_from_op(&ow.sos_f, &ow.d, &ow.opt, 1.0) != PF_OK ||
        pfh_sos_from_op(&ow.sos_q, &ow.d, &ow.opt, 2.0 / out_fs) != PF_OK ||
        pfh_sos_q15_make(&ow.sos_q, &ow.df1_q) != PF_OK)
        return -1;
    pfh_sos_f32(&ow.sos_f, ow.df1_f);
    return 0;
}

enum { IMPL_OURS_F32, IMPL_OURS_Q15, IMPL_DF1_F32, IMPL_DF1_Q15 };

/* Run len samples of a unit step; y (if not NULL) gets the physical output. */
static void op_run(int impl, long len, double *y)
{
    static float xf[LEN], yf[LEN];
    static int16_t xq[LEN], yq[LEN];
    static pf_fracop_f32 f;
    static pf_fracop_q15 q;
    float stf[4 * PFH_SOS_MAX];
    int16_t stq[4 * PFH_SOS_MAX];
    pfh_df1_f32 df = {ow.sos_f.n, ow.df1_f, stf};
    pfh_df1_q15 dq = {ow.df1_q.n, ow.df1_q.post_shift, ow.df1_q.c, stq};
    double acc = 0.0, out_fs = 1.25 * ow.peak;
    long n = 0, i;

    memset(stf, 0, sizeof stf);
    memset(stq, 0, sizeof stq);
    pf_fracop_init_f32(&f, &ow.cf);
    pf_fracop_init_q15(&q, &ow.cq);
    for (i = 0; i < LEN; i++) {
        xf[i] = 1.0f;
        xq[i] = 16384;
    }
    while (n < len) {
        long blk = len - n < LEN ? len - n : LEN;
        for (i = 0; i < blk; i++) {
            double v;
            switch (impl) {
            case IMPL_OURS_F32: v = pf_fracop_step_f32(&f, 1.0f); break;
            case IMPL_OURS_Q15: v = pf_fracop_step_q15(&q, 16384) * out_fs / 32768.0; break;
            default: v = 0.0; break;
            }
            if (impl <= IMPL_OURS_Q15) {
                acc += v;
                if (y != NULL)
                    y[n + i] = v;
            }
        }
        if (impl == IMPL_DF1_F32)
            pfh_df1_run_f32(&df, xf, yf, (size_t)blk);
        else if (impl == IMPL_DF1_Q15)
            pfh_df1_run_q15(&dq, xq, yq, (size_t)blk);
        if (impl >= IMPL_DF1_F32)
            for (i = 0; i < blk; i++) {
                double v = impl == IMPL_DF1_F32 ? yf[i] : yq[i] * out_fs / 32768.0;
                acc += v;
                if (y != NULL)
                    y[n + i] = v;
            }
        n += blk;
    }
    sink = acc;
}

/* Max |y - exact| over [1 ms, 2 s] relative to the exact peak. */
static double op_error(int impl)
{
    static double y[2 * (long)FS + 1];
    double worst = 0.0;
    long n;
    op_run(impl, 2 * (long)FS + 1, y);
    for (n = (long)(1e-3 * FS); n <= 2 * (long)FS; n++) {
        double ex = ow.gain * pow(n / FS, -ow.alpha) / tgamma(1.0 - ow.alpha);
        if (!(fabs(y[n] - ex) <= worst))
            worst = isfinite(y[n]) ? fabs(y[n] - ex) : INFINITY;
    }
    return worst / ow.peak;
}

/* ---- timing ------------------------------------------------------------- */

typedef void (*work_fn)(int arg, int ninst);

static void w_ctrl(int q15, int ninst) { ctrl_run(q15, ninst, LEN); }
static void w_op(int impl, int ninst) { (void)ninst; op_run(impl, LEN, NULL); }

/* Median over REPS runs of ns per sample per instance. */
static double time_ns(work_fn fn, int arg, int ninst)
{
    double t[REPS];
    int r;
    fn(arg, ninst); /* warm the caches and the branch predictors */
    for (r = 0; r < REPS; r++) {
        double t0 = now_ns();
        fn(arg, ninst);
        t[r] = (now_ns() - t0) / ((double)LEN * ninst);
    }
    qsort(t, REPS, sizeof t[0], cmp_double);
    return t[REPS / 2];
}

/* ---- tables ------------------------------------------------------------- */

static const char *cfg_names[] = {"p", "dd", "id", "pid"};
static const char *op_names[] = {"relay", "bellows", "restrictor"};

static void table_configs(void)
{
    int c;
    printf("## Per-sample cost of the controllers\n\n");
    printf("Default design at 20 kHz (band [1e-3, pi fs], N = 8), unit step, "
           "median of %d runs of %d samples.\n\n", REPS, LEN);
    printf("| config | sections | MACs/sample | float ns/sample | Q15 ns/sample |\n");
    printf("|---|---|---|---|---|\n");
    for (c = 0; c < 4; c++) {
        if (ctrl_setup((pf_topology)c, 0) != 0) {
            printf("| %s | design refused | | | |\n", cfg_names[c]);
            continue;
        }
        fprintf(stderr, "[bench] speed: controller %s\n", cfg_names[c]);
        printf("| %s | %d | %d | %.1f | %.1f |\n", cfg_names[c], ctrl_sections(&cw.d.rt),
               ctrl_macs(&cw.d.rt), time_ns(w_ctrl, 0, 1), time_ns(w_ctrl, 1, 1));
    }
}

static void table_alternative(void)
{
    int k, i;
    const char *impl[] = {"pneufrac float (parallel leaky)", "pneufrac Q15 (leaky, 32.30-bit states)",
                          "DF1 biquads float", "DF1 biquads Q15 (CMSIS style)"};
    printf("\n## The obvious alternative: a DF1 biquad cascade of the same design\n\n");
    printf("Example 6's operators alone at 20 kHz, default band and N = 8. The "
           "cascade has the same poles and zeros (pfh_sos.c) and runs with "
           "CMSIS's arm_biquad_cascade_df1 semantics (pfh_df1.c; Q15: 16-bit "
           "coefficients with postShift, 64-bit accumulator, 16-bit stage outputs). "
           "Error: max |y - exact| over t in [1 ms, 2 s], relative to the peak, "
           "for a step, exact = gain t^-alpha / Gamma(1 - alpha). Poles: first-order "
           "sections (ours) or 2 x biquads (DF1).\n\n");
    printf("| operator | implementation | poles | MACs/sample | ns/sample | ns/pole | error |\n");
    printf("|---|---|---|---|---|---|---|\n");
    for (k = 0; k < 3; k++) {
        if (op_setup(op_names[k], 0) != 0) {
            printf("| %s | design refused | | | | | |\n", op_names[k]);
            continue;
        }
        fprintf(stderr, "[bench] speed: operator %s, four ways\n", op_names[k]);
        for (i = 0; i < 4; i++) {
            int poles = i < 2 ? ow.d.n_sec + abs(ow.d.n_int) : 2 * ow.sos_f.n;
            int macs = i < 2 ? op_macs(&ow.d) : 5 * ow.sos_f.n;
            double ns = time_ns(w_op, i, 1), e = op_error(i);
            printf("| %s | %s | %d | %d | %.1f | %.2f | %s%.3g %% |\n", op_names[k], impl[i],
                   poles, macs, ns, ns / poles, e >= 1.0 ? "**" : "", 100 * e);
        }
    }
}

static void table_memory(void)
{
    printf("\n## Memory (host, x86_64; PF_MAX_ORDER = %d sizes every array)\n\n",
           PF_MAX_ORDER);
    printf("| object | bytes |\n|---|---|\n");
    printf("| pf_ctrl_f32 (instance) | %zu |\n", sizeof(pf_ctrl_f32));
    printf("| pf_ctrl_q15 (instance) | %zu |\n", sizeof(pf_ctrl_q15));
    printf("| pf_ctrl_coeffs_f32 (coefficient set) | %zu |\n", sizeof(pf_ctrl_coeffs_f32));
    printf("| pf_ctrl_coeffs_q15 (coefficient set) | %zu |\n", sizeof(pf_ctrl_coeffs_q15));
    printf("| pf_nozzle_q15 (the nozzle curve's table, with a nozzle only) | %zu |\n",
           sizeof(pf_nozzle_q15));
    printf("| pf_fracop_f32 (one operator) | %zu |\n", sizeof(pf_fracop_f32));
    printf("| pf_fracop_q15 (one operator) | %zu |\n", sizeof(pf_fracop_q15));
    printf("| pf_ctrl_design (double, design time only) | %zu |\n", sizeof(pf_ctrl_design));
    if (op_setup("relay", 0) == 0)
        printf("| DF1 relay state, float / Q15 (%d stages x 4) | %zu / %zu |\n", ow.sos_f.n,
               4 * (size_t)ow.sos_f.n * sizeof(float), 4 * (size_t)ow.sos_f.n * sizeof(int16_t));
}

static void table_scale(void)
{
    static const int insts[] = {1, 4, 16, 64, 256};
    int n, i;
    printf("\n## Scale\n\n### Cost against the order N (dd controller, 20 kHz)\n\n");
    printf("| N | sections | MACs/sample | float ns/sample | Q15 ns/sample |\n");
    printf("|---|---|---|---|---|\n");
    for (n = 1; n <= PF_MAX_ORDER; n++) {
        if (ctrl_setup(PF_TOPO_DD, n) != 0)
            continue;
        fprintf(stderr, "[bench] scale: N = %d\n", n);
        printf("| %d | %d | %d | %.1f | %.1f |\n", n, ctrl_sections(&cw.d.rt),
               ctrl_macs(&cw.d.rt), time_ns(w_ctrl, 0, 1), time_ns(w_ctrl, 1, 1));
    }
    printf("\n### Cost against the number of instances (dd, default N)\n\n");
    printf("| instances | float ns/sample/instance | Q15 ns/sample/instance |\n");
    printf("|---|---|---|\n");
    if (ctrl_setup(PF_TOPO_DD, 0) != 0)
        return;
    for (i = 0; i < 5; i++) {
        fprintf(stderr, "[bench] scale: %d instances\n", insts[i]);
        printf("| %d | %.1f | %.1f |\n", insts[i], time_ns(w_ctrl, 0, insts[i]),
               time_ns(w_ctrl, 1, insts[i]));
    }
}

/* ---- one workload for callgrind ----------------------------------------- */

/* Runs one workload and prints its structure count "macs=M poles=P". */
static int run_one(const char *what, int order, long len)
{
    char name[16], impl[8], ar[8];
    int c;
    if (sscanf(what, "ctrl-%15[a-z]-%7s", name, ar) == 2) {
        for (c = 0; c < 4 && strcmp(cfg_names[c], name) != 0; c++)
            ;
        if (c == 4 || ctrl_setup((pf_topology)c, order) != 0)
            return 2;
        ctrl_run(strcmp(ar, "q15") == 0, 1, len);
        printf("macs=%d poles=%d\n", ctrl_macs(&cw.d.rt), ctrl_sections(&cw.d.rt));
        return 0;
    }
    if (sscanf(what, "op-%15[a-z]-%7[a-z0-9]-%7s", name, impl, ar) == 3) {
        int df1 = strcmp(impl, "df1") == 0;
        if (op_setup(name, order) != 0)
            return 2;
        op_run(2 * df1 + (strcmp(ar, "q15") == 0), len, NULL);
        printf("macs=%d poles=%d\n", df1 ? 5 * ow.sos_f.n : op_macs(&ow.d),
               df1 ? 2 * ow.sos_f.n : ow.d.n_sec + abs(ow.d.n_int));
        return 0;
    }
    return 2;
}

int main(int argc, char **argv)
{
    if (argc == 5 && strcmp(argv[1], "run") == 0)
        return run_one(argv[2], atoi(argv[3]), atol(argv[4]));
    if (argc != 1) {
        fprintf(stderr, "usage: bench_speed [run WHAT N SAMPLES]\n");
        return 2;
    }
    table_configs();
    table_alternative();
    table_memory();
    table_scale();
    return 0;
}
