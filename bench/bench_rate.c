/* SPDX-License-Identifier: MIT */
/*
 * pneufracd's model at its own rate (port/posix/pfd_rate.c), measured.
 *
 *   bench_rate accuracy          Markdown tables (bench/bench_daemon.py puts
 *                                them into docs/benchmarks-daemon.md):
 *     1. every case of the exact reference at exchange rates 100 Hz to
 *        50 kHz: one step per exchange (before substeps) and the rule's
 *        substeps, float and Q15;
 *     2. the rule's constant: relays of every order and ratio;
 *     3. beyond the paper: random parameter sets, moderate and high loop
 *        gains;
 *     4. the internal-rate limit: Example 6 up to 1 MHz inside.
 *   bench_rate run CONFIG ARITH FS N
 *                                N exchanges of a default instance (q15:
 *                                in_fs 1, out_fs 16) with the rule's
 *                                substeps, for callgrind's instructions per
 *                                exchange; prints k.
 *
 * Every error is max |p_c - exact| over the window, in % of the peak of
 * the exact response there, at the exchange instants (pfd_accuracy.c).
 * Measures; never passes or fails.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pfh_accuracy.h"
#include "pfh_ref.h"
#include "pfh_ref_cases.h"
#include "pfd_accuracy.h"
#include "pfd_commit.h"
#include "pfd_parse.h"
#include "pfd_rate.h"
#include "pfd_sample.h"

static double pct(double x)
{
    return 100.0 * x;
}

/* 1. The paper's cases, before and after. */
static int paper_table(const pfh_ref_cases *cs)
{
    static const double rates[] = {100.0, 1000.0, 2000.0, 10000.0, 50000.0};
    const unsigned nr = sizeof rates / sizeof rates[0];
    double worst[3][5] = {{0.0}};
    unsigned i;
    int c;

    printf("| case |");
    for (i = 0; i < nr; i++)
        printf(" %g Hz |", rates[i]);
    printf("\n|---|");
    for (i = 0; i < nr; i++)
        printf("---|");
    printf("\n");
    for (c = 0; c < cs->n; c++) {
        printf("| %s |", cs->name[c]);
        for (i = 0; i < nr; i++) {
            pfh_acc_ref r;
            pfd_acc_result b, f, q;
            if (pfh_acc_ref_make(&r, &cs->p[c], rates[i], 1e-3, 2.0) != 0 ||
                pfd_acc_error(&r, PFD_ARITH_FLOAT, 1, &b) != 0 ||
                pfd_acc_error(&r, PFD_ARITH_FLOAT, 0, &f) != 0 ||
                pfd_acc_error(&r, PFD_ARITH_Q15, 0, &q) != 0) {
                fprintf(stderr, "bench_rate: %s at %g Hz failed\n", cs->name[c], rates[i]);
                return -1;
            }
            printf(" %.3f → %.4f / %.4f (k %u) |", pct(b.err), pct(f.err), pct(q.err), f.k);
            worst[0][i] = fmax(worst[0][i], b.err);
            worst[1][i] = fmax(worst[1][i], f.err);
            worst[2][i] = fmax(worst[2][i], q.err);
            pfh_acc_ref_free(&r);
        }
        printf("\n");
    }
    printf("| **worst** |");
    for (i = 0; i < nr; i++)
        printf(" **%.3f → %.4f / %.4f** |", pct(worst[0][i]), pct(worst[1][i]),
               pct(worst[2][i]));
    printf("\n\n");
    return 0;
}

/* Max error of a float instance exchanging at fs with @p substeps (0:
 * the rule's) over [t0, t1], against a reference that is checked for its
 * own convergence at a few points (48 against 32 quadrature nodes). */
typedef struct sweep_point {
    double err, t_worst, ref_dev;
    unsigned k;
} sweep_point;

static int sweep_error(const pf_params *p, double fs, unsigned substeps, double t0, double t1,
                       sweep_point *sp)
{
    pfh_acc_ref r;
    pfd_acc_result f;
    long n;

    if (pfh_acc_ref_make(&r, p, fs, t0, t1) != 0)
        return -1;
    sp->ref_dev = 0.0;
    for (n = r.n0; n <= r.n1; n += (r.n1 - r.n0) / 40 + 1)
        sp->ref_dev = fmax(sp->ref_dev, fabs(pfh_ref_step_n(p, (double)n / fs, 48) -
                                              r.y[n - r.n0]) / r.peak);
    if (pfd_acc_error(&r, PFD_ARITH_FLOAT, substeps, &f) != 0) {
        pfh_acc_ref_free(&r);
        return -1;
    }
    sp->err = f.err;
    sp->t_worst = f.t_worst;
    sp->k = f.k;
    pfh_acc_ref_free(&r);
    return 0;
}

/* 2. The constant: p controllers with Example 4's gains (the loop is
 * negligible, the relay is the fastest), tau = 1 ms, relays of every
 * order and ratio, exchanging at 10 kHz: with the rule's 2 substeps
 * (f tau = 20) and with one (f tau = 10); the window starts at tau. */
static void constant_table(void)
{
    static const double betas[] = {0.2, 0.4, 0.6, 0.8, 1.0};
    static const double ratios[] = {0.01, 0.1, 0.5, 0.9};
    double w20 = 0.0, w10 = 0.0;
    unsigned i, j;

    printf("| beta | pmin/pmax | f tau = 20 (the rule) | at t | f tau = 10 | at t |\n"
           "|---|---|---|---|---|---|\n");
    for (i = 0; i < sizeof betas / sizeof betas[0]; i++)
        for (j = 0; j < sizeof ratios / sizeof ratios[0]; j++) {
            pf_params p;
            sweep_point a, b;
            pf_params_default(&p, PF_TOPO_P);
            p.beta = betas[i];
            p.pmax = 10.0;
            p.pmin = 10.0 * ratios[j];
            if (sweep_error(&p, 10000.0, 0, p.tau, 2.0, &a) != 0 ||
                sweep_error(&p, 10000.0, 1, p.tau, 2.0, &b) != 0)
                continue;
            w20 = fmax(w20, a.err);
            w10 = fmax(w10, b.err);
            printf("| %.1f | %.2f | %.4f %% | %.3g s | %.4f %% | %.3g s |\n", betas[i],
                   ratios[j], pct(a.err), a.t_worst, pct(b.err), b.t_worst);
        }
    printf("| **worst** | | **%.4f %%** | | **%.4f %%** | |\n\n", pct(w20), pct(w10));
}

static double lu(double lo, double hi)
{
    return lo * pow(hi / lo, (double)rand() / RAND_MAX);
}

static double un(double lo, double hi)
{
    return lo + (hi - lo) * (double)rand() / RAND_MAX;
}

static double loop_gain_dc(const pf_params *p)
{
    return p->a / (p->a + p->b) * p->k1 * p->k2 * p->A / p->ks;
}

/* 3. Random sets: config, tau in [0.1, 10] ms, beta in [0.3, 1], and so
 * on (see the text printed), in two families of gains. */
static void random_table(unsigned n_sets, double k_lo, double k_hi, unsigned seed)
{
    unsigned i, over = 0, done = 0, unsure = 0;
    double worst = 0.0;
    char worst_row[400] = "";

    srand(seed);
    for (i = 0; i < n_sets; i++) {
        pf_params p;
        sweep_point sp;
        double tf;
        pf_params_default(&p, (pf_topology)(rand() % PF_TOPO_COUNT));
        p.tau = lu(1e-4, 1e-2);
        p.beta = un(0.3, 1.0);
        p.pmin = lu(0.1, 10.0);
        p.pmax = p.pmin * lu(1.0, 100.0);
        p.q = rand() % 4 == 0 ? 0.0 : un(0.2, 1.0);
        p.nu = un(0.5, 1.0);
        p.w = un(p.nu, 1.0);
        p.RC = lu(1e-3, 1.0);
        p.RCd = lu(1e-3, 0.1);
        p.RCi = p.RCd * lu(1.5, 100.0);
        p.k1 = lu(k_lo, k_hi);
        p.k2 = lu(k_lo, k_hi);
        if (pf_params_validate(&p) != PF_OK)
            continue;
        tf = pfd_rate_fastest(&p);
        if (sweep_error(&p, 10000.0, 0, fmax(tf, 1e-4), fmax(0.2, 200.0 * tf), &sp) != 0)
            continue;
        if (sp.ref_dev > 1e-4) {
            unsure++; /* the reference itself is not converged: not counted */
            continue;
        }
        done++;
        if (sp.err > 1e-3)
            over++;
        if (sp.err > worst) {
            worst = sp.err;
            snprintf(worst_row, sizeof worst_row,
                     "%s, tau %.3g s, beta %.2f, pmin/pmax %.3f, q %.2f, loop gain %.3g, "
                     "tau_fast %.3g s, k %u at 10 kHz: %.4f %% at t = %.3g s",
                     pf_topology_name(p.topology), p.tau, p.beta, p.pmin / p.pmax, p.q,
                     loop_gain_dc(&p), tf, sp.k, pct(sp.err), sp.t_worst);
        }
    }
    printf("| k1, k2 in [%g, %g] | %u | %u | %.4f %% | %u | %s |\n", k_lo, k_hi, done,
           over, pct(worst), unsure, worst_row);
}

/* Example 6's error at 1 kHz exchanges with k steps each, run on the
 * library directly (the daemon refuses more than 200 kHz inside). */
static double library_error(const pfh_acc_ref *r, unsigned k, int q15)
{
    static pf_ctrl_design d;
    static pf_ctrl_coeffs_f32 cf;
    static pf_ctrl_f32 f;
    static pf_ctrl_coeffs_q15 cq;
    static pf_ctrl_q15 q;
    const double out_fs = 1.25 * r->peak;
    pf_design_opts o;
    double worst = 0.0;
    long n;
    unsigned j;

    memset(&o, 0, sizeof o);
    o.fs = r->fs * k;
    if (pf_ctrl_design_make(&d, &r->p, NULL, &o) != PF_OK)
        return -1.0;
    pf_ctrl_coeffs_f32_make(&cf, &d.rt);
    pf_ctrl_init_f32(&f, &cf, NULL, 0);
    if (pf_ctrl_coeffs_q15_make(&cq, &d, 2.0, out_fs) != PF_OK)
        return -1.0;
    pf_ctrl_init_q15(&q, &cq, NULL, 0);
    for (n = 0; n <= r->n1; n++) {
        /* a unit step: Q15 16384 of in_fs = 2 */
        double y = q15 ? pf_ctrl_step_q15(&q, 16384) * out_fs / 32768.0
                       : (double)pf_ctrl_step_f32(&f, 1.0f);
        for (j = 1; j < k; j++) {
            if (q15)
                (void)pf_ctrl_step_q15(&q, 16384);
            else
                (void)pf_ctrl_step_f32(&f, 1.0f);
        }
        if (n >= r->n0)
            worst = fmax(worst, fabs(y - r->y[n - r->n0]));
    }
    return worst / r->peak;
}

/* 4. Example 6 at 1 kHz exchanges, the internal rate raised past the
 * limit: float's resolution against the slowest leaks. */
static void limit_table(const pfh_ref_cases *cs)
{
    static const unsigned ks[] = {20, 50, 100, 200, 500, 1000};
    const pf_params *p = pfh_ref_cases_find(cs, "ex6_q0.9");
    pfh_acc_ref r;
    unsigned i;

    if (p == NULL || pfh_acc_ref_make(&r, p, 1000.0, 1e-3, 2.0) != 0)
        return;
    printf("| internal rate | float | Q15 |\n|---|---|---|\n");
    for (i = 0; i < sizeof ks / sizeof ks[0]; i++)
        printf("| %u kHz | %.4f %% | %.4f %% |\n", ks[i], pct(library_error(&r, ks[i], 0)),
               pct(library_error(&r, ks[i], 1)));
    pfh_acc_ref_free(&r);
    printf("\n");
}

static int accuracy(void)
{
    pfh_ref_cases cs;

    if (pfh_ref_cases_load(REF_DATA_DIR "/paper_step_cases.json", &cs) != 0) {
        fprintf(stderr, "bench_rate: cannot read the reference cases\n");
        return 1;
    }
    printf("### Accuracy at the exchange instants\n\n");
    printf("Each cell: one step per exchange (before substeps, float) → the rule's "
           "substeps in float / in Q15, and k; %% of the peak over [1 ms, 2 s].\n\n");
    if (paper_table(&cs) != 0)
        return 1;
    printf("### The rule's constant\n\n");
    printf("p controllers with Example 4's gains (a negligible loop: the relay is the "
           "fastest), tau = 1 ms, every relay order beta and ratio pmin/pmax, exchanging at "
           "10 kHz with the rule's 2 substeps (f tau = 20) and with one (f tau = 10); error "
           "over [tau, 2 s]. Where the worst error is at t = tau it halves as the rate "
           "doubles; where it is near 2 s it does not depend on the rate (the band's low "
           "edge and Oustaloup's ripple).\n\n");
    constant_table();
    printf("### Beyond the paper's cases\n\n");
    printf("Random sets (fixed seeds): every configuration, tau log-uniform in [0.1, 10] ms, "
           "beta in [0.3, 1], pmin log-uniform in [0.1, 10] and pmax/pmin in [1, 100], q = 0 "
           "for a quarter and else in [0.2, 1], nu in [0.5, 1], w in [nu, 1], RC in [1 ms, "
           "1 s], RCd in [1, 100] ms and RCi/RCd in [1.5, 100], k1 and k2 log-uniform in the "
           "range given; invalid sets are skipped. Float, 10 kHz exchanges with the "
           "rule's substeps, error over [max(tau_fast, 0.1 ms), max(0.2 s, 200 tau_fast)]. "
           "Sets whose exact reference moves by more than 1e-4 of the peak between 32 and 48 "
           "quadrature nodes are left out. Loop gain: a/(a+b) k1 k2 A/ks; the paper's are "
           "1e-4 to 0.1.\n\n");
    printf("| gains | sets | over 0.1 %% | worst | reference not converged (skipped) | "
           "worst set |\n|---|---|---|---|---|---|\n");
    random_table(150, 0.1, 100.0, 1);
    random_table(150, 1.0, 3000.0, 2);
    printf("\n### The internal-rate limit\n\n");
    printf("Example 6 exchanging at 1 kHz with ever more steps inside, on the library "
           "directly (the daemon stops at 200 kHz): float's error grows again past 200 kHz, "
           "where the slowest leaks approach float's resolution.\n\n");
    limit_table(&cs);
    return 0;
}

/* N exchanges of a default instance, for callgrind. */
static int run(const char *config, const char *arith, const char *fs_text, const char *n_text)
{
    pfd_daemon *d = malloc(sizeof *d);
    pfd_settings set;
    pfd_config_inst ci;
    pfd_fail why;
    double fs;
    long n, i;
    int cfg = pfd_parse_name(config, pfd_topology_name, PF_TOPO_COUNT);
    int ar = pfd_parse_name(arith, pfd_arith_name, PFD_ARITH_COUNT);

    if (d == NULL || cfg < 0 || ar < 0 || pfd_parse_number(fs_text, &fs) != 0 ||
        pfd_parse_int(n_text, 1, 100000000, &n) != 0) {
        fprintf(stderr, "usage: bench_rate run p|dd|id|pid float|q15 FS N\n");
        free(d);
        return 2;
    }
    pfd_settings_default(&set);
    if (pfd_daemon_init(d, &set) != 0)
        return 1;
    pfd_config_inst_default(&ci, 1);
    pf_params_default(&ci.ip.p, (pf_topology)cfg);
    ci.ip.arith = ar;
    ci.ip.fs = fs;
    ci.ip.out_fs = 16.0;
    ci.live.e = 0.5f;
    if (pfd_inst_add(d, &ci, &why) != 0) {
        fprintf(stderr, "bench_rate: the instance was refused\n");
        return 1;
    }
    for (i = 0; i < n; i++)
        pfd_sample_run(d->inst[0], &d->loop.jitter, 0, -1);
    printf("k=%u step_ns=%.1f\n", d->inst[0]->rate.k, d->inst[0]->rate.step_ns);
    pfd_daemon_free(d);
    free(d);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc == 2 && !strcmp(argv[1], "accuracy"))
        return accuracy();
    if (argc == 6 && !strcmp(argv[1], "run"))
        return run(argv[2], argv[3], argv[4], argv[5]);
    fprintf(stderr, "usage: bench_rate accuracy | bench_rate run CONFIG ARITH FS N\n");
    return 2;
}
