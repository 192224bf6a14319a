/* SPDX-License-Identifier: MIT */
/**
 * @file pf_fracop.h
 * @brief The fractional operator gain * s^alpha: Oustaloup design in double,
 *        runtimes in double, float and Q15.
 *
 * Design (double, may use libm):
 *  - alpha = n + f is split with n = round-to-nearest(alpha), ties toward
 *    zero, so |f| <= 1/2. The integer part is realised exactly (Tustin
 *    integrators or differentiators); only s^f is approximated. Nearest
 *    rounding keeps the approximant's slope outside the band within half a
 *    decade per decade of the true slope, where floor rounding can be off by
 *    almost a whole one (s^-0.94 would become a flat gain below wb).
 *  - s^f is approximated over [wb, wh] with 2N+1 real zero/pole pairs
 *    (Oustaloup 1995, recursive distribution), or with the refined variant of
 *    Xue, Zhao and Chen (2006), whose extra second-order factor flattens the
 *    error near the band edges.
 *  - The rational approximant is discretised by Tustin, optionally prewarped,
 *    and realised in parallel form: a feedthrough plus one leaky integrator
 *    per real pole, each normalised to unit DC gain:
 *        s_k <- s_k + lam_k * (u - s_k),   y = d*u + sum_k G_k * s_k.
 *    lam_k = 1 - a_k stores the pole's distance from z = 1 directly, so
 *    poles within 1e-9 of z = 1 keep full relative precision (a coefficient
 *    a_k = 0.9999999 does not even exist in Q15 or float32).
 *
 * Every operator output over one sample is y = D*u + S, with D constant and
 * S known before u is: this is what lets the controllers solve their loops
 * exactly each sample.
 */
#ifndef PNEUFRAC_PF_FRACOP_H
#define PNEUFRAC_PF_FRACOP_H

#include <stdint.h>
#include "pf_config.h"
#include "pf_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Rational approximation method of s^f. */
typedef enum pf_approx {
    PF_APPROX_OUSTALOUP = 0, /**< Oustaloup's recursive filter (default) */
    PF_APPROX_REFINED = 1    /**< refined (modified) Oustaloup, b = 10, d = 9 */
} pf_approx;

/** How the runtime reads its input samples. */
typedef enum pf_input_model {
    /** Held between samples (a PLC register, a DAC, a sample-and-hold): the
     *  runtime feeds the mean of the last two samples to the Tustin
     *  realisation, which makes it second-order accurate for held inputs
     *  (a step is seen as a step at t = 0, not at t = -T/2). Default. */
    PF_INPUT_HOLD = 0,
    /** Linear between samples: plain Tustin. */
    PF_INPUT_LINEAR = 1
} pf_input_model;

/** Default slowest time scale of interest, s: sets the default lower band edge. */
#define PF_DEFAULT_TSLOW 10.0

/** Lowest wb/fs a design accepts: the slowest leak lam ~ wb/fs must stay
 *  above 2^-32, the finest the Q15 runtime represents with a normalised
 *  mantissa. */
#define PF_WB_MIN_PER_FS 1e-9

/** Design options shared by every operator of a design. Zero fields mean
 *  "use the default"; see pf_design_opts_resolve(). */
typedef struct pf_design_opts {
    double fs;        /**< sample rate, Hz (required) */
    double wb;        /**< lower band edge, rad/s; 0 = default
                           max(0.01/t_slow, 2*PF_WB_MIN_PER_FS*fs) */
    double wh;        /**< upper band edge, rad/s; 0 = default pi*fs; <= pi*fs */
    int order;        /**< Oustaloup N, up to PF_MAX_ORDER; 0 = default */
    pf_approx approx; /**< approximation method */
    double prewarp;   /**< Tustin prewarp frequency, rad/s, < pi*fs; 0 = none */
    double t_slow;    /**< slowest time scale of interest, s; 0 = 10 s */
    pf_input_model input; /**< input interpretation; default PF_INPUT_HOLD */
} pf_design_opts;

/** Fill @p o with defaults for sample rate @p fs: wb, wh and order are left
 *  at 0, to be derived by pf_design_opts_resolve (from t_slow and fs). */
void pf_design_opts_default(pf_design_opts *o, double fs);

/** Validate @p in and write it to @p out with every default filled in
 *  (pf_design_opts_default leaves wb, wh and order at 0: they are derived
 *  here, so that they follow t_slow).
 *  Defaults: wb = max(0.01/t_slow, 2*PF_WB_MIN_PER_FS*fs), wh = pi*fs,
 *  N = ceil(log10(wh/wb)) so that 2N+1 >= 2 sections per decade, capped at
 *  PF_MAX_ORDER.
 *  Limits: each option within its range (pf_param_info), and wb < wh;
 *  wh <= pi*fs (with 1e-12 relative slack for rounding); wb >=
 *  PF_WB_MIN_PER_FS*fs (a pole closer to z = 1 than the Q15 runtime can
 *  resolve); N >= 1 once defaulted; prewarp < 0.99*pi*fs; the refined
 *  method needs wh >= 2 rad/s (so
 *  its correction factor's poles are real).
 *  @return PF_OK, or PF_E_PARAM(PF_P_FS | _WB | _WH | _ORDER | _APPROX |
 *          _PREWARP | _TSLOW | _INPUT) naming the offending option. */
pf_status pf_design_opts_resolve(const pf_design_opts *in, pf_design_opts *out);

/** A designed operator gain * s^alpha in double precision (the master copy
 *  from which the float and Q15 coefficient sets are derived). */
typedef struct pf_fracop_design {
    double alpha;  /**< realised order */
    double gain;   /**< realised gain */
    double fs;     /**< sample rate, Hz */
    double c;      /**< Tustin constant: s = c (z-1)/(z+1); 2*fs unless prewarped */
    int n_int;     /**< integer part: < 0 integrators, > 0 differentiators */
    int n_sec;     /**< number of leaky branches */
    double d;      /**< feedthrough of the fractional part (includes gain) */
    double lam[PF_MAX_SEC]; /**< leak of branch k: 1 - pole, in (0, 2) */
    double G[PF_MAX_SEC];   /**< DC gain of branch k */
    double int_d;  /**< integer stage: y = int_d*u + s */
    double int_k;  /**< integer stage: s <- rho*s + int_k*u, rho = sign */
    int int_rho;   /**< +1 integrator, -1 differentiator */
    double D;      /**< total feedthrough of the operator */
    int hold;      /**< average consecutive inputs (PF_INPUT_HOLD) in step() */
} pf_fracop_design;

/** Design gain * s^alpha with the options @p opt (already resolved or not).
 *  The refined method falls back to Oustaloup's when the fractional part
 *  is within 1e-3 of an integer, where its correction factor degenerates.
 *  @param alpha order, within its range (pf_param_info: 0 < |alpha| < 2)
 *  @param gain  within its range (pf_param_info: finite, not 0)
 *  @return PF_OK, PF_E_PARAM(PF_P_ALPHA | PF_P_GAIN) or an options error;
 *          PF_E_PARAM(PF_P_ALPHA) also if a section would leave the range
 *          the sample rate can hold (a pole mapped onto z = -1). */
pf_status pf_fracop_design_make(pf_fracop_design *op, double alpha, double gain,
                                const pf_design_opts *opt);

/** Continuous-time approximant: the real zeros, poles and gain of the
 *  rational function that stands for s^f (f = alpha - n_int), before
 *  discretisation, so that s^alpha ~ s^m * k * prod(s+z_i)/prod(s+p_i).
 *  Sizes are at most PF_MAX_SEC. @return PF_OK or an options error. */
pf_status pf_fracop_zpk(double alpha, const pf_design_opts *opt, int *m,
                        double *k, double *zeros, int *nz, double *poles,
                        int *np);

/** Discrete frequency response of the designed operator at Omega rad/s
 *  (z = exp(j*Omega/fs)), as real and imaginary parts. */
void pf_fracop_freqresp(const pf_fracop_design *op, double omega, double *re,
                        double *im);

/* ---------------- runtimes ---------------- */

/** Double-precision runtime instance; state is caller-owned memory. */
typedef struct pf_fracop_f64 {
    const pf_fracop_design *c;
    double u1;     /**< previous input (held-input model) */
    double sum;    /**< sum_k G_k s_k of the current states */
    double s[PF_MAX_SEC];
    double si[PF_MAX_INT];
} pf_fracop_f64;

/** Float coefficient set, derived from a design; usable as static const. */
typedef struct pf_fracop_coeffs_f32 {
    int8_t n_int, int_rho;
    uint8_t n_sec, hold;
    float d, D, int_d, int_k;
    float lam[PF_MAX_SEC];
    float G[PF_MAX_SEC];
} pf_fracop_coeffs_f32;

/** Float runtime instance. */
typedef struct pf_fracop_f32 {
    const pf_fracop_coeffs_f32 *c;
    float u1;
    float sum;     /**< sum_k G_k s_k of the current states */
    float s[PF_MAX_SEC];
    float si[PF_MAX_INT];
} pf_fracop_f32;

/** Convert a design to a float coefficient set (no allocation). */
void pf_fracop_coeffs_f32_make(pf_fracop_coeffs_f32 *cf, const pf_fracop_design *op);

/** Bind coefficients and clear the state. @return PF_OK or PF_E_NULL. */
pf_status pf_fracop_init_f64(pf_fracop_f64 *S, const pf_fracop_design *c);
pf_status pf_fracop_init_f32(pf_fracop_f32 *S, const pf_fracop_coeffs_f32 *c);
/** Clear the state (zero initial conditions). */
void pf_fracop_reset_f64(pf_fracop_f64 *S);
void pf_fracop_reset_f32(pf_fracop_f32 *S);
/** One sample: y = op(u). Total: no error return. */
double pf_fracop_step_f64(pf_fracop_f64 *S, double u);
float pf_fracop_step_f32(pf_fracop_f32 *S, float u);

/* ---------------- Q15 ---------------- */

/** A fixed-point coefficient: value = m * 2^-sh, with m an int32 mantissa. */
typedef struct pf_qc {
    int32_t m;
    uint8_t sh;
} pf_qc;

/** Q15 coefficient set of one operator, including the scaling of its
 *  internal nodes. Internal signals are int32 with |x| <= 2^30.
 *  Branch k has leak lam_k = lam_m[k] 2^-lam_sh[k] (a 15-bit mantissa) and
 *  gain G_k = G_m[k] 2^-G_sh (frac-output units per input unit), and the
 *  sections are ordered by leak: the first n_slow (lam < 1/8) keep
 *  32 bits of fraction in their state, the others (near Nyquist) need none.
 *  See lib/src/pf_q15_ops.h for the arithmetic. */
typedef struct pf_fracop_coeffs_q15 {
    int8_t n_int, int_rho;
    uint8_t n_sec, hold;
    uint8_t n_slow;                   /**< sections 0..n_slow-1: lam_sh >= 18 */
    pf_qc d;                          /**< u -> frac output */
    uint8_t G_sh;                     /**< common shift of the G_m products */
    int16_t lam_m[PF_Q15_MAX_SEC];    /**< leak mantissas in [2^14, 2^15) */
    uint8_t lam_sh[PF_Q15_MAX_SEC];   /**< leak shifts in [14, 44] */
    int32_t G_m[PF_Q15_MAX_SEC];      /**< branch gains, |G_m| < 2^26 */
    pf_qc int_d[PF_MAX_INT];          /**< per integer stage feedthrough */
    pf_qc int_k[PF_MAX_INT];          /**< per integer stage state gain, |.| < 2 */
    pf_qc in_q, out_q;                /**< Q15 in -> internal, internal -> Q15 out */
} pf_fracop_coeffs_q15;

/** State of one Q15 section: s * 2^32, the integer part in hi, 32 bits of
 *  fraction in lo, so increments far below one LSB accumulate and slow
 *  poles decay at their designed rate. */
typedef struct pf_q15_sec {
    uint32_t lo;
    int32_t hi;
} pf_q15_sec;

/** Q15 runtime instance. */
typedef struct pf_fracop_q15 {
    const pf_fracop_coeffs_q15 *c;
    int16_t u1;                  /**< previous Q15 input (held-input model) */
    int64_t sv;                  /**< sum_k G_m[k] hi_k, for the next sample */
    pf_q15_sec s[PF_Q15_MAX_SEC];
    int64_t si[PF_MAX_INT];      /**< integer stages: s * 2^30 */
} pf_fracop_q15;

/** Derive a Q15 coefficient set. Physical input in_fs maps to Q15 +1.0 at
 *  the input, out_fs to +1.0 at the output (ranges: pf_param_info). For an
 *  operator with a differentiating integer part (alpha > 1/2) the state
 *  gain 2 fs, scaled from in_fs to out_fs, must stay below 2: otherwise
 *  PF_E_SCALE (out_fs must then be large against in_fs).
 *  @return PF_OK, PF_E_PARAM(PF_P_IN_FS | PF_P_OUT_FS) or PF_E_SCALE. */
pf_status pf_fracop_coeffs_q15_make(pf_fracop_coeffs_q15 *cq,
                                    const pf_fracop_design *op, double in_fs,
                                    double out_fs);
pf_status pf_fracop_init_q15(pf_fracop_q15 *S, const pf_fracop_coeffs_q15 *c);
void pf_fracop_reset_q15(pf_fracop_q15 *S);
/** One sample. Input and output in Q15 (-32768..32767); saturates. */
int16_t pf_fracop_step_q15(pf_fracop_q15 *S, int16_t u);

#ifdef __cplusplus
}
#endif
#endif /* PNEUFRAC_PF_FRACOP_H */
