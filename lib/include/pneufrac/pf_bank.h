/* SPDX-License-Identifier: MIT */
/**
 * @file pf_bank.h
 * @brief A linear controller run as a bank of parallel first-order sections
 *        and 2x2 blocks: the reduced-order realisation that pneufrac-reduce
 *        (tools/python/pneufrac_reduce) designs on the host from a full
 *        design, exported as a C header. Runtimes in float and Q15.
 *
 * The full controller (pf_controller.h) keeps one state per Oustaloup
 * section of every operator (51 for Example 6) and solves its loops every
 * sample. Without backlash, the nozzle curve or saturation that controller
 * is one linear time-invariant system e -> p_c (pf_ctrl_state_space); the
 * host reduces it by balanced truncation or residualisation to the fewest
 * states that keep its step response within a requested accuracy over a
 * requested horizon, and realises the result in modal form:
 *
 *     y     = D u + sum_k c_k s_k + sum_j c_j s_j,1
 *     real section k:  s_k <- s_k + lam_k (beta_k u - s_k)
 *     pair j (states s_j = (s_j,1, s_j,2)):
 *                      s_j <- s_j + [alpha_j  omega_j; -omega_j  alpha_j] (beta_j u - s_j)
 *
 * then the output line's dead time (an output lag is a pole of the reduced
 * system itself). lam_k = 1 - pole is stored directly, as in the full
 * design, so a pole within 1e-9 of z = 1 keeps its precision; a complex
 * pair 1 - alpha +- j omega likewise stores its distances from z = 1. The
 * output reads each section's current state (before the update), so the
 * bank's output at sample n is y[n] = C x[n] + D u[n].
 *
 * Normalisation: each section's input gain beta_k is chosen so that the
 * section's state, for any input within the input's full scale, stays within
 * that full scale (its impulse response's l1 norm times |beta_k| is at most
 * 0.98), and its output gain c_k is then a power of two (the sign sits in
 * beta_k). A pair's output reads its first state only. So no state can
 * overflow, no state is clamped, and the Q15 output sum is shifts and adds.
 *
 * With backlash, the nozzle curve or saturation inside the loop there is no
 * linear system to reduce: run the full controller (pf_ctrl_*).
 */
#ifndef PNEUFRAC_PF_BANK_H
#define PNEUFRAC_PF_BANK_H

#include <stddef.h>
#include <stdint.h>
#include "pf_config.h"
#include "pf_fracop.h"
#include "pf_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------- float ---------------- */

/** Float real section: s <- s + lam (beta u - s), output c s. */
typedef struct pf_bank_sec_f32 {
    float lam, beta, c;
} pf_bank_sec_f32;

/** Float pair: two states, output c s_1 (see the head of the file). */
typedef struct pf_bank_pair_f32 {
    float alpha, omega, beta1, beta2, c;
} pf_bank_pair_f32;

/** Float coefficient set, physical units in and out (as pf_ctrl_step_f32). */
typedef struct pf_bank_coeffs_f32 {
    uint8_t n_sec, n_pair;          /**< n_sec + 2 n_pair <= PF_BANK_MAX_ORDER */
    float d;                        /**< feedthrough D */
    uint32_t delay_len;             /**< output dead time, samples */
    pf_bank_sec_f32 sec[PF_BANK_MAX_ORDER];
    pf_bank_pair_f32 pair[PF_BANK_MAX_ORDER / 2];
} pf_bank_coeffs_f32;

/** One float state with its compensation term: a slow section's increment
 *  lam (beta u - s) can be far below half an ulp of s (lam = 1e-8 against
 *  float's 6e-8 spacing below 1), so the update is compensated (Kahan)
 *  and the state decays at its designed rate. */
typedef struct pf_bank_state_f32 {
    float s, comp;
} pf_bank_state_f32;

/** Float instance: sections first, then two states per pair. */
typedef struct pf_bank_f32 {
    const pf_bank_coeffs_f32 *c;
    pf_bank_state_f32 s[PF_BANK_MAX_ORDER];
    float *dbuf;
    uint32_t didx;
} pf_bank_f32;

/* ---------------- Q15 ---------------- */

/** Q15 real section (8 bytes, read through one pointer per sample).
 *  beta  = beta_k 2^29, |beta_k| < 1: input gain;
 *  lam_m, lam_v: lam_k = lam_m 2^(lam_v - 46), lam_m in [2^15, 2^16),
 *        lam_v in [1, 31], so lam_k in [2^-30, 2);
 *  out_sh: the state's right shift into the output sum. */
typedef struct pf_bank_sec_q15 {
    int32_t beta;
    uint16_t lam_m;
    uint8_t lam_v, out_sh;
} pf_bank_sec_q15;

/** Q15 pair: alpha and omega in the format of lam (mantissa, v), the input
 *  gains of both states, the first state's output shift. */
typedef struct pf_bank_pair_q15 {
    int32_t beta1, beta2;
    uint16_t alpha_m, omega_m;
    uint8_t alpha_v, omega_v, out_sh;
} pf_bank_pair_q15;

/** Q15 coefficient set: integers only, usable as static const data.
 *  Scaling: u = the Q15 input (in_fs maps to 32768); a state is s 2^28 in
 *  the hi word of a pf_q15_sec, with 32 bits of fraction in lo; the output
 *  sum is acc = sum_k hi_k 2^-out_sh_k + floor(d_m u / 2^16), and the Q15
 *  output round-half-up(acc / 2^out_q), saturated to the int16 range.
 *  The design keeps |acc| <= 2^30 for any input. */
typedef struct pf_bank_coeffs_q15 {
    uint8_t n_sec, n_pair;          /**< n_sec + 2 n_pair <= PF_BANK_MAX_ORDER */
    uint8_t out_q;                  /**< output shift, 1..13 */
    int32_t d_m;                    /**< feedthrough */
    uint32_t delay_len;             /**< output dead time, samples */
    pf_bank_sec_q15 sec[PF_BANK_MAX_ORDER];
    pf_bank_pair_q15 pair[PF_BANK_MAX_ORDER / 2];
} pf_bank_coeffs_q15;

/** Q15 instance: sections first, then two states per pair. */
typedef struct pf_bank_q15 {
    const pf_bank_coeffs_q15 *c;
    pf_q15_sec s[PF_BANK_MAX_ORDER];
    int16_t *dbuf;
    uint32_t didx;
} pf_bank_q15;

/** Bind a coefficient set and clear the state. @p dbuf must hold
 *  c->delay_len samples (NULL if 0).
 *  @return PF_OK, PF_E_NULL, PF_E_BUFFER (dead-time buffer too short) or
 *          PF_E_SCALE (more states than PF_BANK_MAX_ORDER, or a Q15 shift
 *          out of its range: a set this library did not write). */
pf_status pf_bank_init_f32(pf_bank_f32 *S, const pf_bank_coeffs_f32 *c, float *dbuf,
                           size_t dlen);
pf_status pf_bank_init_q15(pf_bank_q15 *S, const pf_bank_coeffs_q15 *c, int16_t *dbuf,
                           size_t dlen);
/** Back to rest: every state and the dead-time buffer zero. */
void pf_bank_reset_f32(pf_bank_f32 *S);
void pf_bank_reset_q15(pf_bank_q15 *S);
/** One sample, total. Float: physical units; a NaN input counts as 0, and
 *  the input and the output saturate at +-1e30. Q15: saturates. */
float pf_bank_step_f32(pf_bank_f32 *S, float u);
int16_t pf_bank_step_q15(pf_bank_q15 *S, int16_t u);
/** Block of n samples, identical to n calls of step; @p u and @p y may alias. */
void pf_bank_run_f32(pf_bank_f32 *S, const float *u, float *y, size_t n);
void pf_bank_run_q15(pf_bank_q15 *S, const int16_t *u, int16_t *y, size_t n);

#ifdef __cplusplus
}
#endif
#endif /* PNEUFRAC_PF_BANK_H */
