/* SPDX-License-Identifier: MIT */
/**
 * @file pf_effects.h
 * @brief What the linear model leaves out, as blocks at their physical places.
 *
 * | place                | effect                                        |
 * |----------------------|-----------------------------------------------|
 * | flapper displacement | backlash (play operator), nozzle curve        |
 * | relay output p_c     | saturation at the supply limits (in the loop) |
 * | output line          | extra first-order lag, then dead time          |
 *
 * All are off in a zeroed struct. The in-loop effects are monotone, so the
 * loop equation stays uniquely solvable each sample (see pf_controller.h).
 *
 * Saturation comes in two placements (pf_effects.saturate):
 *  - PF_SAT_CLIP: p_c is clipped after the relay; the relay's fractional
 *    memory runs on with the unclipped output, so after a saturated
 *    stretch the output leaves the limit only once that memory has wound
 *    back (a delayed recovery).
 *  - PF_SAT_STOP: the relay's diaphragm sits on its seat (supply or
 *    exhaust). Eq. 11 is the diaphragm's own material law (a Zener model,
 *    stress ~ p_b, strain ~ z); on the seat the strain z is held at the
 *    limit and the seat carries the part of p_b the material does not, so
 *    the material's memory is that of the held z: with z = w + v and
 *    w = (tau s)^-beta v (pf_controller.h), v = (z_lim - S_P)/(1 + D_P)
 *    each sample on the seat. The diaphragm lifts off as soon as p_b falls
 *    below the material's own (relaxing) stress, which is where the free
 *    diaphragm's z comes back inside the limit: recovery follows the input
 *    at once. Off the seat the same v is the free relay's, so nothing
 *    jumps at the limit. The loop's solution within a sample is the
 *    clip's (the seat only changes what the relay remembers), so it stays
 *    uniquely solvable.
 *  - PF_SAT_WIND: the relay's output z stops at the limit (a stop on the
 *    stroke it drives, downstream of the diaphragm) while the diaphragm
 *    stays loaded by the whole p_b: eq. 11 written as pmin z + (pmax -
 *    pmin) v = p_b with z held gives v = (p_b - pmin z_lim)/(pmax - pmin),
 *    and the memory winds on with the excess for as long as the stop holds
 *    (as an integrator's windup). Recovery waits until that excess has
 *    faded: longer than the clip's. The three placements order the
 *    memory's load on a limit: seat <= clip <= wind (the same v at the
 *    limit itself, so nothing jumps there). pmax = pmin leaves v no part in
 *    z: the free v is kept.
 */
#ifndef PNEUFRAC_PF_EFFECTS_H
#define PNEUFRAC_PF_EFFECTS_H

#include "pf_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** pf_effects.saturate: where the supply limits act (see above). */
enum pf_sat_kind {
    PF_SAT_OFF = 0,  /**< no saturation */
    PF_SAT_CLIP = 1, /**< p_c clipped after the relay */
    PF_SAT_STOP = 2, /**< the relay's diaphragm stops at the limits */
    PF_SAT_WIND = 3  /**< the relay's output stops, its memory winds on */
};

/** Effect parameters; zero means off. */
typedef struct pf_effects {
    double backlash;  /**< dead-band full width on x (units of x), >= 0 */
    double nozzle_xh; /**< x_1/2 of p_b/p_s = 1/(1+(x/x_1/2)^2), units of x,
                           >= 0; 0 = linear nozzle (eq. 9) */
    int saturate;     /**< pf_sat_kind: 0 off, 1 clip p_c after the relay,
                           2 the relay stops at the limits (range in
                           pf_param_info, parameter "saturate") */
    double sat_lo, sat_hi; /**< supply limits on p_c, sat_lo < sat_hi */
    double dead_time; /**< output line transport delay, s, >= 0 */
    double lag;       /**< output line extra lag time constant, s, >= 0 */
    double nozzle_bias; /**< nozzle's operating point: the gap u0 = gap/x_1/2
                           there is 1/sqrt(3) + nozzle_bias, in [-0.5, 10];
                           0 = the curve's inflection (see pf_nozzle) */
} pf_effects;

/** Check effect parameters: each within its range (pf_param_info;
 *  saturate in {0, 1, 2, 3}; sat_lo and sat_hi only with saturate), and with
 *  saturate sat_lo < sat_hi (else names sat_hi). The design also caps dead_time at 4194304 samples.
 *  @return PF_OK or PF_E_PARAM(PF_P_BACKLASH ...) naming the parameter. */
pf_status pf_effects_validate(const pf_effects *fx);

/** @return non-zero if any effect is on. */
int pf_effects_any(const pf_effects *fx);

/** Play (backlash) operator of half-width @p r: the output stays at
 *  @p prev until the input moves more than r away, then follows it at
 *  distance r. Monotone non-decreasing in @p x. */
double pf_play(double prev, double x, double r);

/** Nozzle characteristic around its operating point, normalised to unit
 *  slope at x = 0: h(x) = xh*(F(u0) - F(u0 + x/xh))/|F'(u0)|, with
 *  F(u) = 1/(1+u^2) and u0 = 1/sqrt(3), the point of steepest slope (where
 *  a nozzle is biased for gain). The gap u cannot close below 0, where p_b
 *  reaches supply. Monotone non-decreasing; p_b = k1*h(x). */
double pf_nozzle(double x, double xh);

/** The nozzle characteristic biased at the gap u0 = 1/sqrt(3) + @p bias (in
 *  units of x_1/2), the equilibrium's own: h(x) = xh*(F(u0) -
 *  F(u0 + x/xh))/|F'(u0)|, unit slope at x = 0. Away from the inflection
 *  the curve is no longer odd: the gain rises on one side and falls on the
 *  other. @p bias in [-0.5, 10]; bias 0 is pf_nozzle(). */
double pf_nozzle_biased(double x, double xh, double bias);

#ifdef __cplusplus
}
#endif
#endif /* PNEUFRAC_PF_EFFECTS_H */
