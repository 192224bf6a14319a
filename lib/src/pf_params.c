/* SPDX-License-Identifier: MIT */
/* Paper parameters: defaults (Examples 4, 6, 7), validation, access by id. */
#include "pneufrac/pf_params.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

#include "pneufrac/pf_param_info.h"
#include "pf_names.h"

/* Bound on the bellows compliance A/ks, the one ratio of two free
 * parameters that becomes an operator gain (each on its own is bounded by
 * the parameter table). */
#define PF_KA_MAX 1e12

void pf_params_default(pf_params *p, pf_topology topo)
{
    if (p == NULL)
        return;
    memset(p, 0, sizeof *p);
    p->topology = topo;
    /* Example 4 (shared by Examples 6 and 7 unless overridden). */
    p->b = 9.0;
    p->a = 1.0;
    p->k1 = 0.1;
    p->k2 = 0.1;
    p->A = 2.0;
    p->ks = 20.0;
    p->tau = 0.001;
    p->pmin = 1.0;
    p->pmax = 10.0;
    p->beta = 0.8;
    p->q = 0.9;
    /* Example 6: nu = 0.94, RC = 0.1. Example 7: w = 0.94, RC = 0.1. */
    p->nu = 0.94;
    p->w = 0.94;
    p->RC = 0.1;
    /* pid has no example in the paper: a derivative restrictor ten times
     * faster than the reset one, as in a commercial pneumatic PID. */
    p->RCd = 0.01;
    p->RCi = 0.1;
    if (topo == PF_TOPO_ID || topo == PF_TOPO_PID) {
        /* Example 7 */
        p->k1 = 2.0;
        p->k2 = 5.0;
        p->q = 0.0;
    }
}

static double *field(pf_params *p, pf_param_id id)
{
    switch (id) {
    case PF_P_A: return &p->a;
    case PF_P_B: return &p->b;
    case PF_P_K1: return &p->k1;
    case PF_P_K2: return &p->k2;
    case PF_P_AREA: return &p->A;
    case PF_P_KS: return &p->ks;
    case PF_P_TAU: return &p->tau;
    case PF_P_PMIN: return &p->pmin;
    case PF_P_PMAX: return &p->pmax;
    case PF_P_BETA: return &p->beta;
    case PF_P_Q: return &p->q;
    case PF_P_NU: return &p->nu;
    case PF_P_W: return &p->w;
    case PF_P_RC: return &p->RC;
    case PF_P_RCD: return &p->RCd;
    case PF_P_RCI: return &p->RCi;
    default: return NULL;
    }
}

pf_status pf_params_set(pf_params *p, pf_param_id id, double v)
{
    double *f;
    if (p == NULL)
        return PF_E_NULL;
    f = field(p, id);
    if (f == NULL)
        return PF_E_PARAM(id);
    *f = v;
    return PF_OK;
}

double pf_params_get(const pf_params *p, pf_param_id id)
{
    double *f;
    if (p == NULL)
        return NAN;
    f = field((pf_params *)p, id);
    return f ? *f : NAN;
}

int pf_param_used(pf_topology topo, pf_param_id id)
{
    const pf_param_spec *s = pf_param_info(id);
    if (s == NULL || (unsigned)topo >= (unsigned)PF_TOPO_COUNT)
        return 0;
    return (s->topologies >> topo) & 1u;
}

/* The rules between two parameters, each naming the parameter refused and
 * the one it is checked against: one table for pf_params_validate and for
 * every message that must say which rule broke (pf_params_broken_rule). */
#define PF_STR_(x) #x
#define PF_STR(x) PF_STR_(x)

static int pmin_le_pmax(const pf_params *p)
{
    /* Psi_max and Psi_min are the maximum and minimum stiffness (eq. 11). */
    return !(p->pmax < p->pmin);
}

static int bellows_gain_bounded(const pf_params *p)
{
    return p->A / p->ks <= PF_KA_MAX && p->A / p->ks >= 1.0 / PF_KA_MAX;
}

/* The pid's bellows feedback R_d - R_i must stay negative (docs/pid.md): at
 * high frequency that needs nu <= w (else R_i decays slower and the net
 * feedback turns positive), and then RCd < RCi. */
static int pid_nu_le_w(const pf_params *p)
{
    return p->topology != PF_TOPO_PID || p->nu <= p->w;
}

static int pid_rcd_lt_rci(const pf_params *p)
{
    return p->topology != PF_TOPO_PID || p->RCd < p->RCi;
}

static const struct {
    pf_param_rule rule;
    int (*holds)(const pf_params *p);
} rules[] = {
    {{PF_P_PMAX, PF_P_PMIN, "pmin <= pmax"}, pmin_le_pmax},
    {{PF_P_KS, PF_P_AREA, "1/" PF_STR(PF_KA_MAX) " <= A/ks <= " PF_STR(PF_KA_MAX)},
     bellows_gain_bounded},
    {{PF_P_W, PF_P_NU, "nu <= w"}, pid_nu_le_w},
    {{PF_P_RCD, PF_P_RCI, "RCd < RCi"}, pid_rcd_lt_rci},
};

const pf_param_rule *pf_params_broken_rule(const pf_params *p)
{
    size_t i;
    if (p == NULL)
        return NULL;
    for (i = 0; i < sizeof rules / sizeof rules[0]; i++)
        if (!rules[i].holds(p))
            return &rules[i].rule;
    return NULL;
}

pf_status pf_params_validate(const pf_params *p)
{
    int i;
    const pf_param_rule *broken;
    if (p == NULL)
        return PF_E_NULL;
    if (pf_param_check(PF_P_CONFIG, (double)p->topology) != PF_OK)
        return PF_E_PARAM(PF_P_CONFIG);
    for (i = 0; i <= (int)PF_P_RCI; i++) {
        pf_param_id id = (pf_param_id)i;
        if (pf_param_used(p->topology, id) &&
            pf_param_check(id, pf_params_get(p, id)) != PF_OK)
            return PF_E_PARAM(id);
    }
    broken = pf_params_broken_rule(p);
    return broken != NULL ? PF_E_PARAM(broken->refused) : PF_OK;
}

static const char *const topology_names[PF_TOPO_COUNT] = {"p", "dd", "id", "pid"};

const char *pf_topology_name(pf_topology topo)
{
    return pf_name_of(topology_names, PF_TOPO_COUNT, (int)topo);
}

pf_topology pf_topology_lookup(const char *name)
{
    return (pf_topology)pf_name_find(topology_names, PF_TOPO_COUNT, name);
}
