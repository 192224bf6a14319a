/* SPDX-License-Identifier: MIT */
/*
 * The parameter table (pf_param_info.h): every parameter's name, range,
 * unit and description, written once. Constant data and lookups only (no
 * arithmetic on the bounds here), so the integer-only M0+ build keeps the
 * names.
 */
#include "pneufrac/pf_param_info.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

#include "pneufrac/pf_config.h"
#include "pneufrac/pf_params.h"

/* Positive model parameters: far wider than any physical device in the
 * paper's units, narrow enough that the products formed in the design stay
 * finite in double and in float. */
#define MODEL_MIN 1e-9
#define MODEL_MAX 1e9
/* Effects: widths, limits and the lag, in the units of their signal. */
#define EFFECT_MAX 1e9
/* Operator gains and Q15 full scales: a coefficient between two scales
 * must still fit the design's arithmetic. */
#define GAIN_MAX 1e12
#define FULL_SCALE_MAX 1e12

#define OPEN_LO PF_PARAM_LO_OPEN
#define WHOLE PF_PARAM_INTEGER
#define ALL_TOPOLOGIES ((1u << PF_TOPO_COUNT) - 1u)
#define T(cfg) (1u << (cfg))

static const pf_param_spec table[PF_P_COUNT] = {
    /* model parameters (pf_params) */
    [PF_P_A] = {"a", "", "flapper lever arm a (eq. 15)",
                MODEL_MIN, MODEL_MAX, 0, ALL_TOPOLOGIES},
    [PF_P_B] = {"b", "", "flapper lever arm b (eq. 15)",
                MODEL_MIN, MODEL_MAX, 0, ALL_TOPOLOGIES},
    [PF_P_K1] = {"k1", "", "nozzle gain, p_b = k1 x (eq. 9)",
                 MODEL_MIN, MODEL_MAX, 0, ALL_TOPOLOGIES},
    [PF_P_K2] = {"k2", "", "relay gain, p_c = k2 z (eq. 13)",
                 MODEL_MIN, MODEL_MAX, 0, ALL_TOPOLOGIES},
    [PF_P_AREA] = {"A", "", "bellows effective area (eq. 16)",
                   MODEL_MIN, MODEL_MAX, 0, ALL_TOPOLOGIES},
    [PF_P_KS] = {"ks", "", "bellows pseudo-spring constant (eq. 16)",
                 MODEL_MIN, MODEL_MAX, 0, ALL_TOPOLOGIES},
    [PF_P_TAU] = {"tau", "s", "relay time constant (eq. 11)",
                  MODEL_MIN, MODEL_MAX, 0, ALL_TOPOLOGIES},
    [PF_P_PMIN] = {"pmin", "", "relay Psi_min, <= pmax (eq. 11)",
                   MODEL_MIN, MODEL_MAX, 0, ALL_TOPOLOGIES},
    [PF_P_PMAX] = {"pmax", "", "relay Psi_max (eq. 11)",
                   MODEL_MIN, MODEL_MAX, 0, ALL_TOPOLOGIES},
    [PF_P_BETA] = {"beta", "", "relay diaphragm order",
                   0.0, 1.0, OPEN_LO, ALL_TOPOLOGIES},
    [PF_P_Q] = {"q", "", "bellows order; 0 is a linear spring",
                0.0, 1.0, 0, ALL_TOPOLOGIES},
    [PF_P_NU] = {"nu", "", "derivative restrictor order (dd, pid)",
                 0.0, 1.0, OPEN_LO, T(PF_TOPO_DD) | T(PF_TOPO_PID)},
    [PF_P_W] = {"w", "", "reset restrictor order (id, pid; pid: >= nu)",
                0.0, 1.0, OPEN_LO, T(PF_TOPO_ID) | T(PF_TOPO_PID)},
    [PF_P_RC] = {"RC", "s", "restrictor time constant (dd, id)",
                 MODEL_MIN, MODEL_MAX, 0, T(PF_TOPO_DD) | T(PF_TOPO_ID)},
    [PF_P_RCD] = {"RCd", "s", "pid derivative restrictor, < RCi",
                  MODEL_MIN, MODEL_MAX, 0, T(PF_TOPO_PID)},
    [PF_P_RCI] = {"RCi", "s", "pid reset restrictor",
                  MODEL_MIN, MODEL_MAX, 0, T(PF_TOPO_PID)},

    /* design options (pf_params.topology, pf_design_opts, the operator) */
    [PF_P_CONFIG] = {"config", "",
                     "configuration: 0 p (eq. 17), 1 dd (FrDD, eq. 18), "
                     "2 id (FrID, eq. 20), 3 pid (Remark 3)",
                     0.0, PF_TOPO_COUNT - 1, WHOLE, 0},
    [PF_P_FS] = {"fs", "Hz", "sample rate",
                 0.0, 1e7, OPEN_LO, 0},
    [PF_P_WB] = {"wb", "rad/s",
                 "lower band edge of the approximation; 0 = default from "
                 "t_slow; below wh, not too slow for fs",
                 0.0, HUGE_VAL, 0, 0},
    [PF_P_WH] = {"wh", "rad/s",
                 "upper band edge of the approximation; 0 = default pi*fs; "
                 "at most pi*fs",
                 0.0, HUGE_VAL, 0, 0},
    [PF_P_ORDER] = {"order", "",
                    "Oustaloup order N (2N+1 sections per operator); "
                    "0 = default from the band",
                    0.0, PF_MAX_ORDER, WHOLE, 0},
    [PF_P_APPROX] = {"approx", "",
                     "approximation: 0 Oustaloup, 1 refined (Xue, Zhao "
                     "and Chen)",
                     0.0, 1.0, WHOLE, 0},
    [PF_P_PREWARP] = {"prewarp", "rad/s",
                      "Tustin prewarp frequency; 0 = none; below 0.99 pi*fs",
                      0.0, HUGE_VAL, 0, 0},
    [PF_P_TSLOW] = {"t_slow", "s",
                    "slowest time scale of interest (sets the default wb); "
                    "0 = 10 s",
                    0.0, 1e9, 0, 0},
    [PF_P_INPUT] = {"input", "",
                    "input model: 0 hold (samples held, default), 1 linear "
                    "(plain Tustin)",
                    0.0, 1.0, WHOLE, 0},
    [PF_P_ALPHA] = {"alpha", "", "operator order, gain s^alpha",
                    -2.0, 2.0,
                    PF_PARAM_LO_OPEN | PF_PARAM_HI_OPEN | PF_PARAM_NONZERO, 0},
    [PF_P_GAIN] = {"gain", "", "operator gain, gain s^alpha",
                   -GAIN_MAX, GAIN_MAX, PF_PARAM_NONZERO, 0},

    /* fixed-point full scales */
    [PF_P_IN_FS] = {"in_fs", "", "Q15 full scale of e: e = in_fs is +1.0",
                    0.0, FULL_SCALE_MAX, OPEN_LO, 0},
    [PF_P_OUT_FS] = {"out_fs", "",
                     "Q15 full scale of p_c: p_c = out_fs is +1.0",
                     0.0, FULL_SCALE_MAX, OPEN_LO, 0},

    /* effects (pf_effects) */
    [PF_P_BACKLASH] = {"backlash", "",
                       "dead-band full width on the flapper displacement x "
                       "(units of x); 0 = off",
                       0.0, EFFECT_MAX, 0, 0},
    [PF_P_NOZZLE_XH] = {"nozzle_xh", "",
                        "nozzle curve's x_1/2 (units of x); 0 = linear "
                        "nozzle (eq. 9)",
                        0.0, EFFECT_MAX, 0, 0},
    [PF_P_SAT_LO] = {"sat_lo", "", "lower supply limit on p_c, below sat_hi",
                     -EFFECT_MAX, EFFECT_MAX, 0, 0},
    [PF_P_SAT_HI] = {"sat_hi", "", "upper supply limit on p_c",
                     -EFFECT_MAX, EFFECT_MAX, 0, 0},
    [PF_P_DEAD_TIME] = {"dead_time", "s",
                        "output line transport delay; 0 = off",
                        0.0, 3600.0, 0, 0},
    [PF_P_LAG] = {"lag", "s",
                  "output line extra first-order lag time constant; 0 = off",
                  0.0, EFFECT_MAX, 0, 0},
    /* The bias is the gap u0 = gap/x_1/2 at the operating point, less the
     * inflection 1/sqrt(3): at -0.5 the slope |F'(u0)| is still a quarter
     * of its peak; at 10 the nozzle works far out on the flat tail. */
    [PF_P_NOZZLE_BIAS] = {"nozzle_bias", "",
                          "nozzle bias point: the gap at the operating point above "
                          "the curve's inflection, in units of x_1/2; 0 = at the "
                          "inflection",
                          -0.5, 10.0, 0, 0},
    /* Where the supply limits act (pf_effects.h, pf_sat_kind). */
    [PF_P_SATURATE] = {"saturate", "",
                       "saturation: 0 off, 1 p_c clipped after the relay, "
                       "2 the relay's diaphragm stops at the limits, "
                       "3 the relay's output stops and its memory winds on",
                       0.0, 3.0, WHOLE, 0},
};

const pf_param_spec *pf_param_info(pf_param_id id)
{
    if ((unsigned)id >= (unsigned)PF_P_COUNT)
        return NULL;
    return &table[id];
}

int pf_param_count(void)
{
    return (int)PF_P_COUNT;
}

const char *pf_param_name(pf_param_id id)
{
    const pf_param_spec *s = pf_param_info(id);
    return s != NULL ? s->name : "?";
}

pf_param_id pf_param_lookup(const char *name)
{
    int i;
    if (name == NULL)
        return PF_P_COUNT;
    for (i = 0; i < (int)PF_P_COUNT; i++)
        if (strcmp(name, table[i].name) == 0)
            return (pf_param_id)i;
    return PF_P_COUNT;
}
