/* SPDX-License-Identifier: MIT */
/**
 * @file pf_params.h
 * @brief Controller topologies and their physical parameters, named as
 *        in Razminia & Baleanu, "Fractional Order Models of Industrial
 *        Pneumatic Controllers" (the paper).
 */
#ifndef PNEUFRAC_PF_PARAMS_H
#define PNEUFRAC_PF_PARAMS_H

#include "pf_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Controller topology: which of the paper's controllers. Every user
 *  interface (CLI --config, the daemon's register and config key, JSON, the
 *  parameter table's PF_P_CONFIG) calls it "config", its established name. */
typedef enum pf_topology {
    PF_TOPO_P = 0,  /**< nozzle-flapper-relay with bellows feedback, eq. 17 */
    PF_TOPO_DD = 1, /**< restrictor in the feedback path (FrDD), eq. 18 */
    PF_TOPO_ID = 2, /**< restricted positive-feedback bellows (FrID), eq. 20 */
    PF_TOPO_PID = 3,/**< both restrictors (fractional PID, Remark 3), docs/pid.md */
    PF_TOPO_COUNT
} pf_topology;

/** Physical parameters. Units are the paper's (consistent, unspecified);
 *  times in seconds. Ranges, units and descriptions: pf_param_info(). */
typedef struct pf_params {
    pf_topology topology; /**< which controller (PF_P_CONFIG, "config") */
    double a, b;      /**< flapper lever arms (eq. 15) */
    double k1;        /**< nozzle gain p_b = k1 x (eq. 9) */
    double k2;        /**< relay gain p_c = k2 z (eq. 13) */
    double A;         /**< bellows effective area (eq. 16) */
    double ks;        /**< bellows pseudo-spring constant (eq. 16) */
    double tau;       /**< relay time constant tau_new, s (eq. 11) */
    double pmin, pmax;/**< Psi_min <= Psi_max (eq. 11) */
    double beta;      /**< relay diaphragm order */
    double q;         /**< bellows order; 0 is a linear spring */
    double nu;        /**< derivative restrictor order (dd, pid) */
    double w;         /**< reset restrictor order (id, pid); pid: >= nu */
    double RC;        /**< restrictor time constant, s (dd, id) */
    double RCd;       /**< pid derivative restrictor, s, < RCi */
    double RCi;       /**< pid reset restrictor, s */
} pf_params;

/** Defaults: Example 4 (p, q = 0.9), Example 6 (dd, q = 0.9), Example 7
 *  (id), and for pid Example 7's values with nu = w = 0.94, RCd = 0.01 s,
 *  RCi = 0.1 s (the paper gives none; see docs/pid.md). */
void pf_params_default(pf_params *p, pf_topology topo);

/** Check the topology and every parameter it uses (others are ignored):
 *  each within its range (pf_param_info); then pmin <= pmax (else names
 *  pmax); A/ks in [1e-12, 1e12] (else names ks); for pid, nu <= w (else
 *  names w: with nu > w the reset restrictor's bellows wins at high
 *  frequency and the net feedback turns positive) and RCd < RCi (else
 *  names RCd). See docs/pid.md.
 *  @return PF_OK or PF_E_PARAM(id) naming the first offending parameter. */
pf_status pf_params_validate(const pf_params *p);

/** A rule between two parameters that pf_params_validate checks once each
 *  is within its own range. */
typedef struct {
    pf_param_id refused;   /**< the parameter PF_E_PARAM names */
    pf_param_id other;     /**< the parameter it is checked against */
    const char *text;      /**< the rule, e.g. "pmin <= pmax" */
} pf_param_rule;

/** The first rule between two parameters that @p p breaks, in
 *  pf_params_validate's order (the one whose parameter it names), or NULL
 *  when all hold or @p p is NULL. Each parameter's own range is
 *  pf_param_check's, not a rule here. For messages that must say what to
 *  change: the rules are stated once, in the library. */
const pf_param_rule *pf_params_broken_rule(const pf_params *p);

/** Set or get a parameter by id (PF_P_A .. PF_P_RCI). Set does not validate.
 *  @return PF_OK or PF_E_PARAM(id) for an id that is not a model parameter. */
pf_status pf_params_set(pf_params *p, pf_param_id id, double v);
double pf_params_get(const pf_params *p, pf_param_id id);

/** @return non-zero if topology @p topo uses parameter @p id (the
 *  table's pf_param_spec.topologies); 0 for an unknown topo or id. */
int pf_param_used(pf_topology topo, pf_param_id id);

/** @return "p", "dd", "id", "pid", or "?". */
const char *pf_topology_name(pf_topology topo);
/** @return the topology named @p name, or PF_TOPO_COUNT. */
pf_topology pf_topology_lookup(const char *name);

#ifdef __cplusplus
}
#endif
#endif /* PNEUFRAC_PF_PARAMS_H */
