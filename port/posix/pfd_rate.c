/* SPDX-License-Identifier: MIT */
#include "pfd_rate.h"

#include <complex.h>
#include <errno.h>
#include <math.h>
#include <string.h>
#include <time.h>


/* Frequencies the loop-gain scan looks at, rad/s: from far above anything
 * the internal rate could resolve down to far below the slowest dynamics
 * the default band resolves (wb = 1e-3 rad/s). */
#define SCAN_W_TOP 1e9
#define SCAN_W_BOTTOM 1e-4
#define SCAN_STEP_DECADES 0.05

/* (x s)^a on s = jw (x > 0), principal branch: (x w)^a e^{j a pi/2}. */
static double complex jpow(double x, double w, double a)
{
    const double half_pi = 1.57079632679489661923;
    return pow(x * w, a) * cexp(I * (a * half_pi));
}

/* |L(jw)|: the gain around the flapper-bellows loop, from the flapper's x
 * back to itself (docs/pneufracd.md, "Substeps"): lever a/(a+b), nozzle
 * k1, relay, k2, and the bellows A/ks s^-q driven through the
 * configuration's restrictors. */
static double loop_gain(const pf_params *p, double w)
{
    const double complex u = jpow(p->tau, w, p->beta);
    const double complex relay = (1.0 + u) / (p->pmin + p->pmax * u);
    const double complex bellows = (p->A / p->ks) / jpow(1.0, w, p->q);
    double complex m = 1.0, rd, ri;

    switch (p->topology) {
    case PF_TOPO_DD:
        m = 1.0 / (p->RC * jpow(1.0, w, p->nu) + 1.0);
        break;
    case PF_TOPO_ID:
        ri = p->RC * jpow(1.0, w, p->w);
        m = ri / (ri + 1.0);
        break;
    case PF_TOPO_PID:
        rd = p->RCd * jpow(1.0, w, p->nu);
        ri = p->RCi * jpow(1.0, w, p->w);
        m = (ri - rd) / ((rd + 1.0) * (ri + 1.0));
        break;
    default:
        break;
    }
    return cabs(p->a / (p->a + p->b) * p->k1 * p->k2 * relay * bellows * m);
}

/* 1/w_c, w_c the highest frequency where |L| falls through 1; HUGE_VAL if
 * there is none. With q = 0 and no restrictor in the way at high
 * frequency (p, id), |L| tends to a constant: such a loop only scales the
 * relay's own pole, which stays at or below 1/tau, and adds no faster
 * time constant. */
static double loop_time(const pf_params *p)
{
    const int static_loop = p->q == 0.0 && (p->topology == PF_TOPO_P || p->topology == PF_TOPO_ID);
    double lw = log10(SCAN_W_TOP), lo, hi;
    int i;

    if (loop_gain(p, SCAN_W_TOP) >= 1.0)
        return static_loop ? HUGE_VAL : 1.0 / SCAN_W_TOP;
    while (lw > log10(SCAN_W_BOTTOM) && loop_gain(p, pow(10.0, lw)) < 1.0)
        lw -= SCAN_STEP_DECADES;
    if (lw <= log10(SCAN_W_BOTTOM))
        return HUGE_VAL;
    lo = lw;
    hi = lw + SCAN_STEP_DECADES;
    for (i = 0; i < 40; i++) {
        double mid = 0.5 * (lo + hi);
        if (loop_gain(p, pow(10.0, mid)) >= 1.0)
            lo = mid;
        else
            hi = mid;
    }
    return pow(10.0, -hi);
}

/* RC s^order = 1 at w = RC^(-1/order). */
static double restrictor_time(double rc, double order)
{
    return pow(rc, 1.0 / order);
}

double pfd_rate_fastest(const pf_params *p)
{
    double t = p->tau;

    switch (p->topology) {
    case PF_TOPO_DD:
        t = fmin(t, restrictor_time(p->RC, p->nu));
        break;
    case PF_TOPO_ID:
        t = fmin(t, restrictor_time(p->RC, p->w));
        break;
    case PF_TOPO_PID:
        t = fmin(t, fmin(restrictor_time(p->RCd, p->nu), restrictor_time(p->RCi, p->w)));
        break;
    default:
        break;
    }
    return fmin(t, loop_time(p));
}

double pfd_rate_wanted_fs(const pf_params *p)
{
    return PFD_RATE_STEPS_PER_TAU / pfd_rate_fastest(p);
}

unsigned pfd_rate_substeps(const pf_params *p, double fs)
{
    const double want = pfd_rate_wanted_fs(p);
    const double k_max = fmin((double)PFD_SUBSTEPS_MAX, floor(PFD_INTERNAL_FS_MAX / fs));
    /* The tolerance keeps an exact multiple (20 kHz at 1 kHz) from
     * becoming one more substep through rounding. */
    const double k = ceil(want / fs * (1.0 - 1e-12));

    if (!(k > 1.0) || k_max < 1.0)
        return 1;
    return (unsigned)fmin(k, k_max);
}

int pfd_rate_capped(const pfd_rate *r)
{
    return r->wanted_fs > r->internal_fs * (1.0 + 1e-9);
}

static double thread_cpu_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

static double mono_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

static double median(double *v, int n)
{
    int i, j;
    for (i = 1; i < n; i++)
        for (j = i; j > 0 && v[j - 1] > v[j]; j--) {
            double t = v[j];
            v[j] = v[j - 1];
            v[j - 1] = t;
        }
    return v[n / 2];
}

/* Rounds and steps per round of a measurement: long enough that the
 * clock's resolution does not matter, short enough for a commit. */
#define MEASURE_ROUNDS 5
#define MEASURE_STEPS 2000

void pfd_rate_measure(pfd_slot *s)
{
    /* Mid-scale: far from Q15 saturation, and the float states never
     * decay towards denormals under a constant input. */
    const float e = (float)(0.5 * s->ip.in_fs);
    double per[MEASURE_ROUNDS];
    int i;

    for (i = 0; i < MEASURE_ROUNDS; i++) {
        double t0 = thread_cpu_ns();
        pfd_slot_hold(s, e, MEASURE_STEPS);
        per[i] = (thread_cpu_ns() - t0) / MEASURE_STEPS;
    }
    /* Median: the rule must not rest on the luckiest round, nor on one
     * that an interrupt lengthened. */
    s->rate.step_ns = median(per, MEASURE_ROUNDS);
    pfd_slot_reset(s);
}

/* Wake-ups per round and their spacing: 5 rounds of 20 x 200 us. */
#define WAKE_COUNT 20
#define WAKE_SPACING_NS 200000.0

double pfd_rate_measure_wakeup(void)
{
    double per[MEASURE_ROUNDS];
    int i, j;

    for (i = 0; i < MEASURE_ROUNDS; i++) {
        double t = mono_ns(), c0 = thread_cpu_ns();
        for (j = 0; j < WAKE_COUNT; j++) {
            struct timespec ts;
            t += WAKE_SPACING_NS;
            ts.tv_sec = (time_t)(t / 1e9);
            ts.tv_nsec = (long)(t - (double)ts.tv_sec * 1e9);
            while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR) {
            }
        }
        per[i] = (thread_cpu_ns() - c0) / WAKE_COUNT;
    }
    return median(per, MEASURE_ROUNDS);
}

double pfd_rate_exchange_ns(const pfd_rate *r)
{
    return ((double)r->k + 1.0) * r->step_ns;
}

void pfd_load_init(pfd_load *l, double wake_ns)
{
    memset(l, 0, sizeof *l);
    l->wake_ns = wake_ns;
}

void pfd_load_add(pfd_load *l, double fs, const pfd_rate *r)
{
    const double c = pfd_rate_exchange_ns(r) * 1e-9;
    const uint64_t period = pfd_period_ns(fs);
    unsigned i;

    l->util += fs * c;
    l->cost_max = fmax(l->cost_max, c);
    l->fs_max = fmax(l->fs_max, fs);
    for (i = 0; i < l->n_periods && l->periods[i] != period; i++) {
    }
    if (i == l->n_periods && i < PFD_MAX_INSTANCES) {
        l->periods[l->n_periods++] = period;
        l->util += fs * l->wake_ns * 1e-9;
    }
}

double pfd_load_total(const pfd_load *l)
{
    return l->util + l->cost_max * l->fs_max;
}
