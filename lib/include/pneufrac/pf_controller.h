/* SPDX-License-Identifier: MIT */
/**
 * @file pf_controller.h
 * @brief The paper's pneumatic controllers as one sampled instance each.
 *
 * Block diagram (Figs. 3, 5, 7 of the paper), every configuration:
 *
 *     x   = b/(a+b) e - a/(a+b) y                   flapper lever, eq. 15
 *     p_b = k1 x                                    nozzle, eq. 9
 *     z   = (1+(tau s)^beta)/(pmin+pmax (tau s)^beta) p_b   relay, eqs. 11-14
 *     p_c = k2 z                                    eq. 13
 *     y   = (A/ks) s^-q m                           bellows, eq. 16
 *     m   = p_c                 (p,  eq. 17)
 *         = Rv p_c              (dd, eq. 18)
 *         = p_c - Rw p_c        (id, eq. 20)
 *         = Rv p_c - Rw p_c     (pid, docs/pid.md)
 *     Rv  = 1/(RC s^nu + 1),  Rw = 1/(RC s^w + 1)   restrictors
 *
 * Each fractional operator is realised as y = D*u + S over a sample (see
 * pf_fracop.h), so the loops flapper-bellows, relay-diaphragm and the
 * restrictors are solved exactly each sample, with no unit delay:
 *  - relay: with v = (tau s)^beta w, pmin w + pmax v = p_b, where
 *    w = (tau s)^-beta v is the operator; one division by a constant;
 *  - restrictor: r = (1/RC) s^-nu (p_c - r), likewise;
 *  - main loop: affine in x, one multiplication by a precomputed reciprocal.
 * With backlash, nozzle curve or saturation on, the main loop equation
 * g(x) = 0 has slope 1 + L0 s, with L0 the in-sample loop gain and s >= 0
 * the effects' slope (all three are monotone; backlash and saturation
 * have s in [0, 1], the nozzle curve s up to |F'| at its inflection over
 * |F'| at its bias, 1 at the inflection), so it is strictly increasing
 * whenever 1 + min(0, L0 s) > 0 for every such s, which the design
 * ensures, and has exactly one root. Newton steps, then false position
 * (Anderson-Bjorck); see pf_ctrl_float.inc.
 */
#ifndef PNEUFRAC_PF_CONTROLLER_H
#define PNEUFRAC_PF_CONTROLLER_H

#include <stddef.h>
#include <stdint.h>
#include "pf_effects.h"
#include "pf_fracop.h"
#include "pf_params.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Runtime coefficients in double (the f64 runtime's coefficient set). */
typedef struct pf_ctrl_coeffs_f64 {
    uint8_t has_q, has_v, has_w;  /**< which operators the configuration uses */
    uint8_t in_loop_fx;           /**< backlash, nozzle or saturation is on */
    uint8_t hold;                 /**< held-input model (pf_input_model) */
    pf_fracop_design P, Q, V, W;  /**< relay (tau s)^-beta, bellows (A/ks) s^-q,
                                       restrictors (1/RC) s^-nu, s^-w */
    double ce, cy;                /**< lever ratios b/(a+b), a/(a+b) */
    double k1, k2, kA;            /**< nozzle, relay, A/ks (bellows if q = 0) */
    double k2_inv;                /**< 1/k2 (z = p_c/k2, recorded) */
    double pmin;                  /**< Psi_min */
    double relay_den_inv;         /**< 1/(pmax + pmin*D_P) */
    double relay_d0, relay_w;     /**< 1/pmax, 1 - pmin/pmax */
    double relay_sz;              /**< sigma_z per S_P: (pmax-pmin)/(pmax+pmin D_P) */
    double v_a, v_den_inv;        /**< D_V/(1+D_V), 1/(1+D_V) */
    double w_a, w_den_inv;        /**< D_W/(1+D_W), 1/(1+D_W) */
    double alpha_z, alpha_y;      /**< dz/dp_b and dy/dp_c within one sample */
    double loop_inv;              /**< 1/(1 + L0), L0 = cy*alpha_y*k2*alpha_z*k1 */
    double slope_inv;             /**< 1/(1 + min(0, L0 s)), s the effects' largest slope */
    double play_r, nozzle_xh;     /**< backlash half-width; nozzle x_1/2 */
    double nozzle_xh_inv;         /**< 1/x_1/2 */
    double nozzle_u0, nozzle_f0;  /**< nozzle's gap at the bias point, F there */
    double nozzle_g;              /**< x_1/2/|F'(u0)|: unit slope at the bias */
    uint8_t saturate;
    double sat_lo, sat_hi;
    double lag_lam;               /**< 1 - exp(-1/(fs*lag)); 0 = off */
    uint32_t delay_len;           /**< dead time in samples */
} pf_ctrl_coeffs_f64;

/** Runtime coefficients in float (same fields, float operators). */
typedef struct pf_ctrl_coeffs_f32 {
    uint8_t has_q, has_v, has_w, in_loop_fx, hold;
    pf_fracop_coeffs_f32 P, Q, V, W;
    float ce, cy, k1, k2, kA, k2_inv, pmin;
    float relay_den_inv, relay_d0, relay_w, relay_sz;
    float v_a, v_den_inv, w_a, w_den_inv;
    float alpha_z, alpha_y, loop_inv, slope_inv;
    float play_r, nozzle_xh, nozzle_xh_inv, nozzle_u0, nozzle_f0, nozzle_g;
    uint8_t saturate;
    float sat_lo, sat_hi, lag_lam;
    uint32_t delay_len;
} pf_ctrl_coeffs_f32;

/** A complete controller design: what was asked and what was derived. */
typedef struct pf_ctrl_design {
    pf_params p;
    pf_effects fx;
    pf_design_opts opt;       /**< resolved: every default filled in */
    pf_ctrl_coeffs_f64 rt;
} pf_ctrl_design;

/** Design a controller. @p fx may be NULL (no effects).
 *  Beyond pf_params_validate, the design refuses, naming the parameter:
 *  an order the approximation cannot realise at this rate (beta, q, nu,
 *  w); a dead time over 4194304 samples (dead_time); and restrictor
 *  settings that make the in-sample loop equation (nearly) singular,
 *  1 + L0 < 0.01 (RCd for pid, RC otherwise), or a nozzle biased so far
 *  off its inflection that 1 + L0 s < 0.01 on its steepest part, s its
 *  largest slope relative to the bias point (nozzle_bias): there the
 *  sample's solution would not be unique. L0 < 0 needs net positive
 *  feedback within one sample: for a validated parameter set that happens
 *  only for pid, at extreme sample rates or bands.
 *  @return PF_OK or the status of the first invalid parameter; on error
 *          @p d is left unchanged. */
pf_status pf_ctrl_design_make(pf_ctrl_design *d, const pf_params *p,
                              const pf_effects *fx, const pf_design_opts *opt);

/** Internal signals of the last sample (see pf_ctrl_f64.sig). */
typedef struct pf_ctrl_signals_f64 { double e, x, pb, z, pc, y, out; } pf_ctrl_signals_f64;
typedef struct pf_ctrl_signals_f32 { float e, x, pb, z, pc, y, out; } pf_ctrl_signals_f32;

/** Internal signals of the last sample, physical units; e is the input as
 *  the lever sees it (with PF_INPUT_HOLD, the mean of the last two). The
 *  float runtimes saturate every solved node at +-1e30 (f32) or +-1e300
 *  (f64), so extreme inputs never produce inf or NaN; a NaN input counts
 *  as zero error. */
/** Double runtime instance. The dead-time buffer is caller-owned. */
typedef struct pf_ctrl_f64 {
    const pf_ctrl_coeffs_f64 *c;
    pf_fracop_f64 P, Q, V, W;
    double e1, xb, lag, lag_c;
    double *dbuf;
    uint32_t didx;
    /** Samples since the last reset (or init) on which the relay's output
     *  before the supply limits lay beyond them (NaN included), whatever
     *  the placement (pf_effects.saturate); stays at UINT32_MAX. While it
     *  is 0 the three placements have given the same output bit for bit:
     *  they differ only in what the relay remembers on a limit. */
    uint32_t limited;
    pf_ctrl_signals_f64 sig;
} pf_ctrl_f64;

/** Float runtime instance. */
typedef struct pf_ctrl_f32 {
    const pf_ctrl_coeffs_f32 *c;
    pf_fracop_f32 P, Q, V, W;
    float e1, xb, lag, lag_c;
    float *dbuf;
    uint32_t didx;
    /** Samples since the last reset (or init) on which the relay's output
     *  before the supply limits lay beyond them (NaN included), whatever
     *  the placement (pf_effects.saturate); stays at UINT32_MAX. While it
     *  is 0 the three placements have given the same output bit for bit:
     *  they differ only in what the relay remembers on a limit. */
    uint32_t limited;
    pf_ctrl_signals_f32 sig;
} pf_ctrl_f32;

/** Discrete frequency response P_c/E of the designed controller at omega
 *  rad/s, z = exp(j omega/fs): the output of pf_ctrl_step_f64 per input,
 *  including the held-input mean and the output line (lag, dead time).
 *  Backlash, the nozzle curve and saturation are nonlinear and left out
 *  (the response is that of the linear controller beneath them). */
void pf_ctrl_freqresp(const pf_ctrl_design *d, double omega, double *re,
                      double *im);

/** Most states a controller's linear runtime has: the held input, each of
 *  the four operators' leaky branches and integer stages, the output lag. */
#define PF_CTRL_MAX_STATES (2 + 4 * (PF_MAX_SEC + PF_MAX_INT))

/** The design's linear runtime as a discrete state space, read off the
 *  double runtime (one step from each unit state with e = 0, one from rest
 *  with e = 1): x[k+1] = A x[k] + B e[k], p_c[k] = C x[k] + D e[k], in the
 *  runtime's own coordinates: the held input (when held), then per used
 *  operator its leaky branches and integer stages, then with @p with_lag
 *  the output lag. Backlash, the nozzle curve, saturation and the dead time
 *  are left out (and the lag without @p with_lag). A is n x n, row-major,
 *  in room for PF_CTRL_MAX_STATES^2 values; B and C hold n; B, C and D may
 *  be NULL. See pf_ctrl_lti.c.
 *  @return n (1..PF_CTRL_MAX_STATES), or -1 for a NULL @p d or @p A. */
int pf_ctrl_state_space(const pf_ctrl_design *d, int with_lag, double *A, double *B,
                        double *C, double *D);

/** Work space of pf_ctrl_spectral_radius(): two square matrices. */
typedef struct pf_ctrl_check_work {
    double a[PF_CTRL_MAX_STATES * PF_CTRL_MAX_STATES];
    double b[PF_CTRL_MAX_STATES * PF_CTRL_MAX_STATES];
} pf_ctrl_check_work;

/** A sampled loop is unstable, its output growing without bound, when
 *  rho > 1 + PF_CTRL_RHO_TOL. Poles on the unit circle are not: z = 1 is
 *  an integrator (FrID and pid with q = 1 integrate, by design). The
 *  tolerance covers the estimate's error: against numpy's eigenvalues of
 *  the same matrices, over 71 designs (the paper's and random gains,
 *  100 Hz to 50 kHz), the largest difference was 9e-13. */
#define PF_CTRL_RHO_TOL 1e-11

/** Spectral radius of the design's sampled loop: the largest |z| of the
 *  discrete closed-loop poles of its linear runtime (backlash, nozzle
 *  curve, saturation, lag and dead time left out); see PF_CTRL_RHO_TOL.
 *  Costs about 50 products of n x n matrices, n <= PF_CTRL_MAX_STATES
 *  (n = 49 for Example 6 at 1 kHz: milliseconds). See pf_ctrl_check.c.
 *  @return PF_OK, or PF_E_NULL. */
pf_status pf_ctrl_spectral_radius(const pf_ctrl_design *d, pf_ctrl_check_work *w,
                                  double *rho);

/** Derive the float coefficient set from a design's double one. */
void pf_ctrl_coeffs_f32_make(pf_ctrl_coeffs_f32 *cf, const pf_ctrl_coeffs_f64 *c);

/** Bind a coefficient set. @p dbuf must hold c->delay_len elements (NULL if
 *  0). @return PF_OK, PF_E_NULL or PF_E_BUFFER. The state starts at rest. */
pf_status pf_ctrl_init_f64(pf_ctrl_f64 *S, const pf_ctrl_coeffs_f64 *c,
                           double *dbuf, size_t dlen);
pf_status pf_ctrl_init_f32(pf_ctrl_f32 *S, const pf_ctrl_coeffs_f32 *c,
                           float *dbuf, size_t dlen);
void pf_ctrl_reset_f64(pf_ctrl_f64 *S);
void pf_ctrl_reset_f32(pf_ctrl_f32 *S);
/** One sample: error e in, line output p_c out (physical units). Total. */
double pf_ctrl_step_f64(pf_ctrl_f64 *S, double e);
float pf_ctrl_step_f32(pf_ctrl_f32 *S, float e);
/** Block of n samples; identical to n calls of step (any split of a
 *  sequence into blocks gives the same output). @p e and @p pc may alias. */
void pf_ctrl_run_f64(pf_ctrl_f64 *S, const double *e, double *pc, size_t n);
void pf_ctrl_run_f32(pf_ctrl_f32 *S, const float *e, float *pc, size_t n);
/** pf_ctrl_f64.limited (for callers that do not mirror the struct). */
uint32_t pf_ctrl_limited_f64(const pf_ctrl_f64 *S);

/* ---------------- Q15 ---------------- */

/** Internal nodes of the Q15 controller (also the order of its scales). */
enum pf_ctrl_node {
    PF_N_E, PF_N_X, PF_N_PB, PF_N_V, PF_N_W, PF_N_PC, PF_N_DV, PF_N_RV,
    PF_N_DW, PF_N_RW, PF_N_M, PF_N_Y, PF_N_FP, PF_N_FQ, PF_N_FV, PF_N_FW,
    PF_N_COUNT
};

/** The nozzle curve on x in Q15 (built by pf_ctrl_coeffs_q15_make_nz, run
 *  by pf_nozzle_q15.c), kept apart from the coefficient set so that only a
 *  firmware with a nozzle pays for its table (38 bytes per piece; see
 *  docs/architecture.md, "Effects in Q15"). Knots x_k on x carry the
 *  curve, h_k = h(x_k), and the in-sample loop map W_k = (x_k + L0 h_k)/
 *  max(1, 1 + L0), which increases with x because the curve does (the
 *  divisor keeps it within +-2^31 for any accepted L0). Between two knots
 *  h is a cubic in x, and x one in W, each through both knots:
 *    h = h_k + (h_{k+1} - h_k) P(r),  r = (x - x_k)/(x_{k+1} - x_k)
 *    x = x_k + (x_{k+1} - x_k) P(r),  r = (W - W_k)/(W_{k+1} - W_k)
 *    P(r) = r + r (1 - r) (a + b r),  a, b in Q24, r in Q27
 *  The loop is solved by one search among the W_k and one piece: no
 *  iteration. */
typedef struct pf_nozzle_q15 {
    int32_t x[PF_Q15_NOZZLE_CAP + 1]; /**< knots (internal x), increasing, from -2^30 to 2^30 */
    int32_t h[PF_Q15_NOZZLE_CAP + 1]; /**< the curve at the knots, x's scale times 2^h_sh */
    int32_t w[PF_Q15_NOZZLE_CAP + 1]; /**< the loop map at the knots, non-decreasing */
    int32_t ha[PF_Q15_NOZZLE_CAP], hb[PF_Q15_NOZZLE_CAP]; /**< the curve's P, per piece */
    int32_t xa[PF_Q15_NOZZLE_CAP], xb[PF_Q15_NOZZLE_CAP]; /**< the inverse's P */
    int32_t rx_m[PF_Q15_NOZZLE_CAP], rw_m[PF_Q15_NOZZLE_CAP]; /**< 2^27 over the piece's */
    uint8_t rx_sh[PF_Q15_NOZZLE_CAP], rw_sh[PF_Q15_NOZZLE_CAP]; /**< width in x, in W */
    uint8_t h_sh;                   /**< h's scale: x's times 2^h_sh (k1, pc_x take h) */
    uint8_t n;                      /**< knots in use, 3 to PF_Q15_NOZZLE_SEG + 1 */
    uint8_t direct;                 /**< 1: W = x within half a unit (L0 too small to
                                         move the solution): x is W's target */
    pf_qc t_x;                      /**< linear solution x_lin -> W: (1 + L0)/max(1, 1 + L0) */
    int32_t t_r;                    /**< backlash half-width r in W: r/max(1, 1 + L0) */
} pf_nozzle_q15;

/** Q15 coefficient set: integers only, usable as static const data on an
 *  MCU without FPU. Every pf_qc multiplies one internal signal into the
 *  scale of another; scales were chosen at design time
 *  (pf_ctrl_q15_design.c). Every node is formed as a sum of unsaturated
 *  64-bit products and saturated once, so a node that is a small
 *  difference of large terms (x, p_c - r) keeps its precision. */
typedef struct pf_ctrl_coeffs_q15 {
    uint8_t has_q, has_v, has_w, saturate, hold;
    pf_fracop_coeffs_q15 P, Q, V, W;
    pf_qc e_in;                    /**< Q15 e -> internal e */
    /* The loop solution, folded from the operators' state contributions
     * (S_Q, S_V, S_W, S_P) straight into x, so that no intermediate (such
     * as sigma_y, larger than the small x it helps to form) needs a scale:
     *   x = x_e e - x_q S_Q - x_v S_V + x_w S_W - x_p S_P          (linear)
     *   x = ce e - x_pc p_c - (t_q S_Q + t_v S_V - t_w S_W)   (p_c clipped) */
    pf_qc x_e, x_q, x_v, x_w, x_p;
    pf_qc ce, x_pc, t_q, t_v, t_w;
    pf_qc pc_x, pc_p;              /**< p_c before clipping: from x and S_P */
    pf_qc k1;                      /**< x -> p_b */
    pf_qc relay_v_pb, relay_v_s;   /**< p_b, S_P -> v */
    pf_qc relay_z_pb, relay_z_w;   /**< p_b, w -> p_c (k2 folded in) */
    pf_qc stop_v_pc, stop_v_s;     /**< held p_c, S_P -> v with the relay on
                                        its seat (PF_SAT_STOP; else 0) */
    pf_qc v_a, v_b, w_a, w_b;      /**< restrictors: p_c, S -> r */
    pf_qc m_v, m_pc, m_w;          /**< r_V or p_c, r_W -> m */
    pf_qc kA_m;                    /**< m -> y when q = 0 */
    pf_qc dv_pc, dv_r, dw_pc, dw_r;/**< p_c, r -> restrictor operator input */
    pf_qc pc_out;                  /**< internal p_c -> Q15 output (also p_c's monitor) */
    int32_t sat_lo, sat_hi;        /**< saturation limits, internal p_c */
    int32_t play_r, play_ri;       /**< backlash: half-width r and r/(1 + L0),
                                        internal x (0: no backlash) */
    const pf_nozzle_q15 *nz;       /**< nozzle curve, caller-owned
                                        (pf_ctrl_coeffs_q15_make_nz); NULL: linear */
    int32_t lag_m; uint8_t lag_sh; /**< output lag leak */
    uint32_t delay_len;
    pf_qc mon_x, mon_pb, mon_y;    /**< monitored node -> Q15 of its full scale */
} pf_ctrl_coeffs_q15;

/** Q15 runtime instance. */
typedef struct pf_ctrl_q15 {
    const pf_ctrl_coeffs_q15 *c;
    pf_fracop_q15 P, Q, V, W;
    int32_t x, pb, y, pc;          /**< last internal values, for monitoring */
    int32_t xb;                    /**< backlash output (internal x) */
    int16_t e1;                    /**< previous input (held-input model) */
    int64_t lag;                   /**< output-line lag state (30 fraction bits) */
    int16_t *dbuf;
    uint32_t didx;
} pf_ctrl_q15;

/** Derive the Q15 coefficient set. e = in_fs maps to Q15 +1.0 at the input,
 *  p_c = out_fs to +1.0 at the output (ranges: pf_param_info).
 *  Supports backlash, saturation, lag and dead time; the nozzle curve needs
 *  room for its table (pf_ctrl_coeffs_q15_make_nz); the refined
 *  approximation and a relay whose memory winds on at the limits
 *  (PF_SAT_WIND, whose state outgrows any fixed scale) are float/double
 *  only (PF_E_UNSUPPORTED).
 *  @return PF_OK, PF_E_PARAM(PF_P_IN_FS | PF_P_OUT_FS), PF_E_UNSUPPORTED,
 *          PF_E_BUFFER for a nozzle curve, or PF_E_SCALE when a
 *          coefficient between two node scales does not fit a 31-bit
 *          mantissa with a shift in [0, 62]. */
pf_status pf_ctrl_coeffs_q15_make(pf_ctrl_coeffs_q15 *cq,
                                  const pf_ctrl_design *d, double in_fs,
                                  double out_fs);
/** pf_ctrl_coeffs_q15_make with room @p nz for the nozzle curve's table
 *  (caller-owned, like the dead-time buffer: @p cq points to it, so it
 *  must outlive @p cq); @p nz may be NULL for a design without one. The
 *  curve then runs in Q15 within the bound of docs/architecture.md
 *  ("Effects in Q15").
 *  @return as pf_ctrl_coeffs_q15_make; PF_E_BUFFER if the design has a
 *          nozzle curve and @p nz is NULL; PF_E_UNSUPPORTED if the
 *          in-sample loop through the curve is not monotone (a loop gain
 *          L0 < 0 with a curve steeper than 1/|L0|, which
 *          pf_ctrl_design_make already refuses: a guard for designs it
 *          did not make), or
 *          the build leaves the curve out (PF_Q15_NOZZLE_SEG = 0). */
pf_status pf_ctrl_coeffs_q15_make_nz(pf_ctrl_coeffs_q15 *cq, pf_nozzle_q15 *nz,
                                     const pf_ctrl_design *d, double in_fs,
                                     double out_fs);
/** Bind an instance to a coefficient set, at rest. @return PF_OK,
 *  PF_E_NULL, or PF_E_BUFFER when the dead-time buffer is missing or short,
 *  or a nozzle table claims more knots than PF_Q15_NOZZLE_SEG + 1 (any,
 *  in a build without the curve) or fewer than 3. */
pf_status pf_ctrl_init_q15(pf_ctrl_q15 *S, const pf_ctrl_coeffs_q15 *c,
                           int16_t *dbuf, size_t dlen);
void pf_ctrl_reset_q15(pf_ctrl_q15 *S);
/** One sample. e and the result in Q15 of in_fs and out_fs; saturates. */
int16_t pf_ctrl_step_q15(pf_ctrl_q15 *S, int16_t e);
/** Block of n samples, as n calls of pf_ctrl_step_q15(). */
void pf_ctrl_run_q15(pf_ctrl_q15 *S, const int16_t *e, int16_t *pc, size_t n);

/** Full scales of the monitored signals in Q15 mode: x and y use in_fs,
 *  p_b uses k1*in_fs, p_c uses out_fs. Writes Q15 values of x, p_b, y, p_c. */
void pf_ctrl_monitor_q15(const pf_ctrl_q15 *S, int16_t *x, int16_t *pb,
                         int16_t *y, int16_t *pc);

#ifdef __cplusplus
}
#endif
#endif /* PNEUFRAC_PF_CONTROLLER_H */
