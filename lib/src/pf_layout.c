/* SPDX-License-Identifier: MIT */
/* Sizes and member layouts of the public structs (pf_layout.h), from the
 * compiler that built the library. Member names of parameters come from
 * the parameter table, so a name is written once. */
#include "pneufrac/pf_layout.h"

#include "pneufrac/pneufrac.h"

typedef struct type_row {
    const char *name;
    size_t size;
} type_row;

#define TYPE(T) {#T, sizeof(T)}

static const type_row types[PF_TYPE_COUNT] = {
    [PF_TYPE_PARAMS] = TYPE(pf_params),
    [PF_TYPE_EFFECTS] = TYPE(pf_effects),
    [PF_TYPE_DESIGN_OPTS] = TYPE(pf_design_opts),
    [PF_TYPE_CTRL_DESIGN] = TYPE(pf_ctrl_design),
    [PF_TYPE_CTRL_COEFFS_F64] = TYPE(pf_ctrl_coeffs_f64),
    [PF_TYPE_CTRL_COEFFS_F32] = TYPE(pf_ctrl_coeffs_f32),
    [PF_TYPE_CTRL_COEFFS_Q15] = TYPE(pf_ctrl_coeffs_q15),
    [PF_TYPE_CTRL_F64] = TYPE(pf_ctrl_f64),
    [PF_TYPE_CTRL_F32] = TYPE(pf_ctrl_f32),
    [PF_TYPE_CTRL_Q15] = TYPE(pf_ctrl_q15),
    [PF_TYPE_RUNTIME] = TYPE(pf_runtime),
    [PF_TYPE_PARAM_SPEC] = TYPE(pf_param_spec),
};

const char *pf_type_name(pf_type t)
{
    return (unsigned)t < (unsigned)PF_TYPE_COUNT ? types[t].name : "?";
}

size_t pf_sizeof(pf_type t)
{
    return (unsigned)t < (unsigned)PF_TYPE_COUNT ? types[t].size : 0;
}

/* A member: a parameter (named by the table) or a named part. */
typedef struct member {
    pf_param_id param; /* PF_P_COUNT: not a parameter, use name */
    const char *name;
    size_t offset, size;
    pf_field_kind kind;
    pf_type type;
} member;

#define SIZE_OF(S, m) sizeof(((S *)0)->m)
#define PARAM(S, id, m, kind) {id, NULL, offsetof(S, m), SIZE_OF(S, m), kind, PF_TYPE_COUNT}
#define D(S, id, m) PARAM(S, id, m, PF_FIELD_DOUBLE)
#define I(S, id, m) PARAM(S, id, m, PF_FIELD_INT)
#define PART(S, m, t) {PF_P_COUNT, #m, offsetof(S, m), SIZE_OF(S, m), PF_FIELD_STRUCT, t}

static const member params_members[] = {
    /* the topology: the parameter "config", under its C name */
    {PF_P_COUNT, "topology", offsetof(pf_params, topology),
     SIZE_OF(pf_params, topology), PF_FIELD_INT, PF_TYPE_COUNT},
    D(pf_params, PF_P_A, a),
    D(pf_params, PF_P_B, b),            D(pf_params, PF_P_K1, k1),
    D(pf_params, PF_P_K2, k2),          D(pf_params, PF_P_AREA, A),
    D(pf_params, PF_P_KS, ks),          D(pf_params, PF_P_TAU, tau),
    D(pf_params, PF_P_PMIN, pmin),      D(pf_params, PF_P_PMAX, pmax),
    D(pf_params, PF_P_BETA, beta),      D(pf_params, PF_P_Q, q),
    D(pf_params, PF_P_NU, nu),          D(pf_params, PF_P_W, w),
    D(pf_params, PF_P_RC, RC),          D(pf_params, PF_P_RCD, RCd),
    D(pf_params, PF_P_RCI, RCi),
};

static const member effects_members[] = {
    D(pf_effects, PF_P_BACKLASH, backlash),
    D(pf_effects, PF_P_NOZZLE_XH, nozzle_xh),
    I(pf_effects, PF_P_SATURATE, saturate),
    D(pf_effects, PF_P_SAT_LO, sat_lo),
    D(pf_effects, PF_P_SAT_HI, sat_hi),
    D(pf_effects, PF_P_DEAD_TIME, dead_time),
    D(pf_effects, PF_P_LAG, lag),
    D(pf_effects, PF_P_NOZZLE_BIAS, nozzle_bias),
};

static const member opts_members[] = {
    D(pf_design_opts, PF_P_FS, fs),         D(pf_design_opts, PF_P_WB, wb),
    D(pf_design_opts, PF_P_WH, wh),         I(pf_design_opts, PF_P_ORDER, order),
    I(pf_design_opts, PF_P_APPROX, approx), D(pf_design_opts, PF_P_PREWARP, prewarp),
    D(pf_design_opts, PF_P_TSLOW, t_slow),  I(pf_design_opts, PF_P_INPUT, input),
};

static const member design_members[] = {
    PART(pf_ctrl_design, p, PF_TYPE_PARAMS),
    PART(pf_ctrl_design, fx, PF_TYPE_EFFECTS),
    PART(pf_ctrl_design, opt, PF_TYPE_DESIGN_OPTS),
    PART(pf_ctrl_design, rt, PF_TYPE_CTRL_COEFFS_F64),
};

#define COUNT(a) ((int)(sizeof a / sizeof a[0]))

int pf_field_get(pf_type t, int i, pf_field *out)
{
    const member *m;
    int n;
    switch (t) {
    case PF_TYPE_PARAMS: m = params_members; n = COUNT(params_members); break;
    case PF_TYPE_EFFECTS: m = effects_members; n = COUNT(effects_members); break;
    case PF_TYPE_DESIGN_OPTS: m = opts_members; n = COUNT(opts_members); break;
    case PF_TYPE_CTRL_DESIGN: m = design_members; n = COUNT(design_members); break;
    default: return -1;
    }
    if (out == NULL || i < 0 || i >= n)
        return -1;
    m += i;
    out->name = m->param != PF_P_COUNT ? pf_param_name(m->param) : m->name;
    out->offset = m->offset;
    out->size = m->size;
    out->kind = m->kind;
    out->type = m->type;
    return 0;
}

size_t pf_ctrl_design_delay_len(const pf_ctrl_design *d)
{
    return d != NULL ? d->rt.delay_len : 0;
}

int pf_max_order(void)
{
    return PF_MAX_ORDER;
}

int pf_bank_max_order(void)
{
    return PF_BANK_MAX_ORDER;
}

int pf_ctrl_max_states(void)
{
    return PF_CTRL_MAX_STATES;
}
