/* SPDX-License-Identifier: MIT */
/*
 * One controller instance's parameter set and its runtime ("slot"): the
 * design, the float or Q15 coefficient set and the runtime state, in one
 * block of memory allocated at start-up. Building a slot (design, Q15
 * scaling, settling) is slow and runs outside the real-time thread; the
 * real-time thread only steps a built slot.
 */
#ifndef PFD_INSTANCE_H
#define PFD_INSTANCE_H

#include <stdint.h>

#include "pneufrac/pneufrac.h"

/* The daemon's own limits; the library's parameter table holds the rest.
 * The real-time loop runs at most at 50 kHz, and at least at 1 Hz. */
#define PFD_FS_MIN 1.0
#define PFD_FS_MAX 50000.0
/* Substeps per exchange (pfd_iparams.substeps; 0 = the rule of pfd_rate.h)
 * and the internal rate they may reach, fs x substeps. Above 200 kHz the
 * float runtime's slowest leaks approach float's resolution and its error
 * grows (Example 6 against the exact response: 0.021 % of the peak at
 * 200 kHz, 0.074 % at 500 kHz, 0.16 % at 1 MHz; bench/bench_rate). */
#define PFD_SUBSTEPS_MAX 10000
#define PFD_INTERNAL_FS_MAX 200000.0
#define PFD_BUMP_TAU_MAX 3600.0

enum pfd_arith { PFD_ARITH_FLOAT = 0, PFD_ARITH_Q15 = 1, PFD_ARITH_COUNT };

/** "float" or "q15" (the config file's and the command line's words). */
const char *pfd_arith_name(int arith);

/** The library's arithmetic of an enum pfd_arith value. */
pf_arith pfd_arith_lib(int arith);

/** "p", "dd", "id" or "pid": pf_topology_name() for an int, to go with
 *  pfd_arith_name() wherever a name is looked up (pfd_parse_name). */
const char *pfd_topology_name(int config);

/** Everything a commit sets: configuration, the paper's parameters,
 *  arithmetic, exchange rate and substeps, Q15 full scales and the
 *  bumpless time constant. */
typedef struct pfd_iparams {
    pf_params p;        /**< config and the paper's parameters */
    int arith;          /**< enum pfd_arith */
    double fs;          /**< exchange rate, Hz, [PFD_FS_MIN, PFD_FS_MAX]: the
                             loop takes e and publishes p_c this often */
    unsigned substeps;  /**< controller steps per exchange, the input held;
                             0 = chosen by pfd_rate_substeps() */
    double in_fs;       /**< e = in_fs is Q15 +1.0 (also the int16 mirrors' scale) */
    double out_fs;      /**< p_c = out_fs is Q15 +1.0 */
    double bump_tau;    /**< s, time constant of the bumpless offset bleed; 0 = none */
} pfd_iparams;

/** Example 6 (FrDD), float, 1 kHz, substeps 0 (the rule's), in_fs 1,
 *  out_fs 0.01, bump_tau 1 s. */
void pfd_iparams_default(pfd_iparams *ip);

/** Parameters the daemon adds to the library's pf_param_id. */
#define PFD_P_BUMP_TAU ((int)PF_P_COUNT + 1)
#define PFD_P_ARITH ((int)PF_P_COUNT + 2)
#define PFD_P_SUBSTEPS ((int)PF_P_COUNT + 3)
/** Status of a parameter only the daemon checks (bump_tau, arith). */
#define PFD_E_DAEMON (-100)

/** Why a build failed: the library status (or PFD_E_DAEMON) and the
 *  parameter it names: a pf_param_id, PFD_P_*, or PF_P_COUNT if none. */
typedef struct pfd_fail {
    pf_status st;
    int param;
} pfd_fail;

/** Name of a parameter id as in pfd_fail ("beta", "bump_tau", "?"). */
const char *pfd_param_name(int id);

/** Signals of one sample, physical units, plus their Q15 views. */
typedef struct pfd_sig {
    float e, x, pb, y, pc;          /**< pc: controller output (before transfers) */
    int16_t pc_q15;                 /**< raw Q15 output (q15), else scaled */
    int16_t x_q15, pb_q15, y_q15;
} pfd_sig;

/** How a built set runs: its substeps, the internal rate they give, and
 *  the CPU time one controller step took when it was measured. */
typedef struct pfd_rate {
    unsigned k;         /**< controller steps per exchange, >= 1 */
    double internal_fs; /**< fs x k, Hz: the rate the set is designed at */
    double step_ns;     /**< measured CPU ns per step (pfd_rate_measure); 0 = not yet */
    double wanted_fs;   /**< the rule's internal rate (pfd_rate_wanted_fs); 0 with
                             substeps given */
} pfd_rate;

/** A built runtime. Never moved once built: the runtime points into it. */
typedef struct pfd_slot {
    pfd_iparams ip;
    pfd_rate rate;
    pf_runtime rt;        /**< float or Q15, with its own coefficient set */
    uint64_t period_ns;   /**< round(1e9/fs): one exchange */
    double decay;         /**< per-exchange factor of the bumpless offset */
    uint32_t gen;         /**< set by the commit that built it (pfd_inst.gen) */
} pfd_slot;

/** round(1e9/fs): one exchange, ns. */
uint64_t pfd_period_ns(double fs);

/** Check @p ip (daemon limits, then the library's), choose its substeps,
 *  design it at the internal rate with @p scratch, and bind @p s at rest
 *  (rate.step_ns 0: not measured). @return 0, or -1 with @p why set. */
int pfd_slot_build(pfd_slot *s, const pfd_iparams *ip, pf_ctrl_design *scratch,
                   pfd_fail *why);

/** Run @p n controller steps with the input held at @p e, outputs
 *  discarded: the substeps after an exchange's first, and the settling
 *  before a bumpless hand-over (docs/pneufracd.md). Real-time safe. */
void pfd_slot_hold(pfd_slot *s, float e, uint32_t n);

/** Back to rest. */
void pfd_slot_reset(pfd_slot *s);

/** One controller step, with every signal: an exchange's first substep.
 *  Real-time safe: no allocation, no locks, no libm. The int16 mirrors
 *  follow the library's rule (pf_q15_quantize), as `pneufrac simulate`
 *  does. */
void pfd_slot_step(pfd_slot *s, float e, pfd_sig *out);

#endif
