/* SPDX-License-Identifier: MIT */
#include "pfd_regmap.h"

#include <float.h>
#include <math.h>
#include <modbus/modbus.h>
#include <string.h>

#include "pfd_access.h"
#include "pfd_rate.h"

#ifndef PFD_VERSION_MAJOR
#define PFD_VERSION_MAJOR 0
#define PFD_VERSION_MINOR 0
#define PFD_VERSION_PATCH 0
#endif

/* What a register reads or writes. */
enum {
    /* holding */
    F_E, F_SP, F_PV, F_E_I16, F_SP_I16, F_PV_I16, F_INPUT_SEL, F_MODE,
    F_MANUAL, F_FAILSAFE, F_WATCHDOG, F_LOCK, F_COMMIT, F_COMMAND, F_TICK,
    /* input */
    F_PC, F_X, F_PB, F_Y, F_EU, F_PC_I16, F_X_I16, F_PB_I16, F_Y_I16,
    F_EU_I16, F_STATUS, F_CRESULT, F_CADDR, F_CPARAM, F_COMMITS, F_SAMPLES,
    F_OVERRUNS, F_JLAST, F_JMAX, F_WDTRIPS, F_VMAJOR, F_VMINOR, F_VPATCH,
    F_VMAP, F_UNIT, F_NINST, F_K_USED, F_INTERNAL_FS, F_STEP_NS, F_LOAD,
    /* parameter k of a set (see ip_get): staged or committed */
    F_STAGED = 100, F_COMMITTED = 200
};

/* Parameter k of a set: 0 config, 1 arith, 2 fs, 3 in_fs, 4 out_fs,
 * 5 bump_tau, 6.. the paper's parameters in pf_param_id order. */
#define K_CONFIG 0
#define K_ARITH 1
#define K_FS 2
#define K_IN_FS 3
#define K_OUT_FS 4
#define K_BUMP 5
#define K_P0 6
#define K_COUNT (K_P0 + 16)
/* Added in version 2, after the blocks above so that no address moved. */
#define K_SUBSTEPS K_COUNT

/* The live signals' write range (e, sp, pv, manual and fail-safe output):
 * the daemon's own bound, far beyond any process value and finite in f32. */
#define BIG 1e9

/* Staged parameters from holding 20, their committed mirrors from input
 * 36; u16 first, then f32. */
#define HS(k) (uint16_t)((k) < 2 ? 20 + (k) : 22 + 2 * ((k) - 2))
#define IC(k) (uint16_t)((k) < 2 ? 36 + (k) : 38 + 2 * ((k) - 2))

/* The parameter set, staged and committed. OWN rows are the daemon's own
 * settings, with their range, unit and description here; LIB rows are
 * the library's parameters, whose range (and unit and description, where
 * the row gives none) the library's table holds. The register name is
 * the parameter's name (test_pfd_config checks that they agree); the
 * register map adds "staged: " or "committed: " to the description. */
#define PARAMS(OWN, LIB)                                                       \
    LIB(K_CONFIG, PFD_T_U16, "config", PF_P_CONFIG, NULL)                      \
    OWN(K_ARITH, PFD_T_U16, "arith", "", 0, PFD_ARITH_COUNT - 1,               \
        "arithmetic: 0 float, 1 q15")                                          \
    OWN(K_FS, PFD_T_F32, "fs", "Hz", PFD_FS_MIN, PFD_FS_MAX,                   \
        "exchange rate: e is taken and p_c published this often")              \
    LIB(K_IN_FS, PFD_T_F32, "in_fs", PF_P_IN_FS,                               \
        "full scale of e: Q15 +1.0 in q15, and the scale of the int16 mirrors of e, x, p_b/k1, y") \
    LIB(K_OUT_FS, PFD_T_F32, "out_fs", PF_P_OUT_FS,                            \
        "full scale of p_c: Q15 +1.0 in q15, and the scale of pc_i16")         \
    OWN(K_BUMP, PFD_T_F32, "bump_tau", "s", 0, PFD_BUMP_TAU_MAX,               \
        "time constant of the bumpless transfer's offset bleed; 0 = none")     \
    LIB(K_P0 + 0, PFD_T_F32, "a", PF_P_A, NULL)                                \
    LIB(K_P0 + 1, PFD_T_F32, "b", PF_P_B, NULL)                                \
    LIB(K_P0 + 2, PFD_T_F32, "k1", PF_P_K1, NULL)                              \
    LIB(K_P0 + 3, PFD_T_F32, "k2", PF_P_K2, NULL)                              \
    LIB(K_P0 + 4, PFD_T_F32, "A", PF_P_AREA, NULL)                             \
    LIB(K_P0 + 5, PFD_T_F32, "ks", PF_P_KS, NULL)                              \
    LIB(K_P0 + 6, PFD_T_F32, "tau", PF_P_TAU, NULL)                            \
    LIB(K_P0 + 7, PFD_T_F32, "pmin", PF_P_PMIN, NULL)                          \
    LIB(K_P0 + 8, PFD_T_F32, "pmax", PF_P_PMAX, NULL)                          \
    LIB(K_P0 + 9, PFD_T_F32, "beta", PF_P_BETA, NULL)                          \
    LIB(K_P0 + 10, PFD_T_F32, "q", PF_P_Q, NULL)                               \
    LIB(K_P0 + 11, PFD_T_F32, "nu", PF_P_NU, NULL)                             \
    LIB(K_P0 + 12, PFD_T_F32, "w", PF_P_W, NULL)                               \
    LIB(K_P0 + 13, PFD_T_F32, "RC", PF_P_RC, NULL)                             \
    LIB(K_P0 + 14, PFD_T_F32, "RCd", PF_P_RCD, NULL)                           \
    LIB(K_P0 + 15, PFD_T_F32, "RCi", PF_P_RCI, NULL)

#define STAGED_OWN(k, t, nm, un, lo, hi, ds)                                   \
    {PFD_HOLD, t, PFD_RW, PFD_F_STAGED, HS(k), F_STAGED + (k), PFD_NO_PARAM,   \
     lo, hi, nm, un, ds},
#define STAGED_LIB(k, t, nm, id, ds)                                           \
    {PFD_HOLD, t, PFD_RW, PFD_F_STAGED, HS(k), F_STAGED + (k), id, 0, 0, nm,   \
     NULL, ds},
#define COMMITTED_OWN(k, t, nm, un, lo, hi, ds)                                \
    {PFD_INPUT, t, PFD_R, 0, IC(k), F_COMMITTED + (k), PFD_NO_PARAM, 0, 0,     \
     "committed_" nm, un, ds},
#define COMMITTED_LIB(k, t, nm, id, ds)                                        \
    {PFD_INPUT, t, PFD_R, 0, IC(k), F_COMMITTED + (k), id, 0, 0,               \
     "committed_" nm, NULL, ds},

#define H(addr, type, acc, fl, field, lo, hi, name, unit, desc)                \
    {PFD_HOLD, type, acc, fl, addr, field, PFD_NO_PARAM, lo, hi, name, unit, desc},
#define I(addr, type, field, name, unit, desc)                                 \
    {PFD_INPUT, type, PFD_R, 0, addr, field, PFD_NO_PARAM, 0, 0, name, unit, desc},

/* The process inputs: operators write them, and a lock leaves them open. */
#define LIVE_IN (PFD_F_LIVE | PFD_F_REFRESH | PFD_F_OPERATE | PFD_F_OPEN)

const pfd_reg pfd_regs[] = {
    H(0, PFD_T_F32, PFD_RW, LIVE_IN, F_E, -BIG, BIG, "e", "",
      "error input e (used when input_sel = 0)")
    H(2, PFD_T_F32, PFD_RW, LIVE_IN, F_SP, -BIG, BIG, "sp", "",
      "setpoint (used when input_sel = 1: e = sp - pv)")
    H(4, PFD_T_F32, PFD_RW, LIVE_IN, F_PV, -BIG, BIG, "pv", "",
      "process value (used when input_sel = 1)")
    H(6, PFD_T_I16, PFD_RW, LIVE_IN, F_E_I16, -32768, 32767, "e_i16", "in_fs/32768",
      "e as a scaled int16: writes e = v*in_fs/32768; reads e likewise, rounded and saturated")
    H(7, PFD_T_I16, PFD_RW, LIVE_IN, F_SP_I16, -32768, 32767, "sp_i16", "in_fs/32768",
      "sp as a scaled int16")
    H(8, PFD_T_I16, PFD_RW, LIVE_IN, F_PV_I16, -32768, 32767, "pv_i16", "in_fs/32768",
      "pv as a scaled int16")
    H(9, PFD_T_U16, PFD_RW, PFD_F_LIVE | PFD_F_OPERATE, F_INPUT_SEL, 0, 1, "input_sel", "",
      "input: 0 e, 1 sp - pv")
    H(10, PFD_T_U16, PFD_RW, PFD_F_LIVE | PFD_F_OPERATE, F_MODE, 0, 1, "mode", "",
      "0 auto, 1 manual (output = manual_out; back to auto is bumpless)")
    H(11, PFD_T_F32, PFD_RW, PFD_F_LIVE | PFD_F_OPERATE, F_MANUAL, -BIG, BIG, "manual_out", "",
      "output in manual mode")
    H(13, PFD_T_F32, PFD_RW, PFD_F_LIVE, F_FAILSAFE, -BIG, BIG, "failsafe_out", "",
      "output while the watchdog is tripped")
    H(15, PFD_T_U16, PFD_RW, PFD_F_LIVE, F_WATCHDOG, 0, 60000, "watchdog_ms", "ms",
      "trip to failsafe_out when e/sp/pv are not written for this long (counted in samples); 0 = off")
    H(16, PFD_T_U16, PFD_RW, 0, F_LOCK, 0, 1, "param_lock", "",
      "1: lock this instance for the client that writes it, until it writes 0 or "
      "disconnects; meanwhile other clients may write only the registers marked open "
      "(exception 01); fixed at 1 for every client by --param-lock")
    H(17, PFD_T_U16, PFD_W, PFD_F_ACTION | PFD_F_STAGED, F_COMMIT, 1, 1, "commit", "",
      "write 1: validate the staged set and switch it in between two samples, bumplessly; "
      "refused (exception 03, nothing changes) if invalid; exception 04 with commit_result 5 "
      "if it runs but the config file could not be written; reads 0")
    H(18, PFD_T_U16, PFD_W, PFD_F_ACTION, F_COMMAND, 1, 3, "command", "",
      "write 1: discard staged changes, 2: reset the controller state, 3: clear statistics; reads 0")
    H(19, PFD_T_U16, PFD_W, PFD_F_ACTION | PFD_F_OPERATE | PFD_F_OPEN, F_TICK, 1, 65535, "tick", "samples",
      "--clock external only (else exception 01): advance exactly N samples (exchanges, "
      "each of substeps_used controller steps), answered when they are done; reads 0")
    PARAMS(STAGED_OWN, STAGED_LIB)
    /* Read-only copies for clients that can only read holding registers
     * (and for FC23: write tick, read the output, in one transaction). */
    H(62, PFD_T_F32, PFD_R, 0, F_PC, 0, 0, "hold_pc", "", "copy of input register pc")
    H(64, PFD_T_I16, PFD_R, 0, F_PC_I16, 0, 0, "hold_pc_i16", "out_fs/32768",
      "copy of input register pc_i16")
    H(65, PFD_T_U16, PFD_R, 0, F_STATUS, 0, 0, "hold_status", "bits",
      "copy of input register status")
    H(66, PFD_T_U16, PFD_RW, PFD_F_STAGED, F_STAGED + K_SUBSTEPS, 0, PFD_SUBSTEPS_MAX,
      "substeps", "", "controller steps per exchange, the input held (the set "
      "is designed at fs x substeps); 0 = chosen from the design's fastest time constant")

    I(0, PFD_T_F32, F_PC, "pc", "", "output p_c (after manual, fail-safe and bumpless transfer)")
    I(2, PFD_T_F32, F_X, "x", "", "flapper displacement x")
    I(4, PFD_T_F32, F_PB, "pb", "", "nozzle back pressure p_b")
    I(6, PFD_T_F32, F_Y, "y", "", "bellows displacement y")
    I(8, PFD_T_F32, F_EU, "e_used", "", "input the loop used in the last sample (e or sp - pv)")
    I(10, PFD_T_I16, F_PC_I16, "pc_i16", "out_fs/32768",
      "p_c as int16; q15: the controller's raw Q15 output (plus any transfer offset)")
    I(11, PFD_T_I16, F_X_I16, "x_i16", "in_fs/32768", "x as int16")
    I(12, PFD_T_I16, F_PB_I16, "pb_i16", "k1*in_fs/32768", "p_b as int16")
    I(13, PFD_T_I16, F_Y_I16, "y_i16", "in_fs/32768", "y as int16")
    I(14, PFD_T_I16, F_EU_I16, "e_used_i16", "in_fs/32768", "e_used as int16")
    I(15, PFD_T_U16, F_STATUS, "status", "bits",
      "0 running, 1 watchdog tripped, 2 last commit not ok (commit_result not 0), 3 manual, "
      "4 parameters locked, 5 read-only server, 6 external clock, "
      "7 staged differs from committed, 8 commit not yet switched in, 9 q15, "
      "10 bumpless transfer in progress, 11 the last write of the config file failed")
    I(16, PFD_T_U16, F_CRESULT, "commit_result", "",
      "last commit: 0 ok, 1 invalid parameter, 2 q15 scaling failed, 3 busy, 4 other error, "
      "5 applied and running but not persisted (config file write failed), "
      "6 the sampled loop would be unstable, "
      "7 the loop could not run it within loop_budget, "
      "8 substeps 0 and the substep rule needs an internal rate beyond the limits "
      "(10000 substeps, 200 kHz): its accuracy aim cannot be met; give substeps to "
      "choose the rate")
    I(17, PFD_T_U16, F_CADDR, "commit_err_addr", "",
      "holding address of the staged parameter that made the last commit fail "
      "(results 6 and 8: the one whose change alone made the set so; result 7: substeps "
      "if the set runs more than one, else fs); 65535 none")
    I(18, PFD_T_U16, F_CPARAM, "commit_err_param", "",
      "the library's pf_param_id of that parameter (pf_param_name); 65535 none, or one "
      "of the daemon's own registers (arith, bump_tau, substeps), which only "
      "commit_err_addr names")
    I(19, PFD_T_U16, F_COMMITS, "commits", "", "accepted commits, modulo 65536")
    I(20, PFD_T_U32, F_SAMPLES, "samples", "", "samples (exchanges) run, modulo 2^32")
    I(22, PFD_T_U32, F_OVERRUNS, "overruns", "samples",
      "samples skipped because the loop was late by a period or more")
    I(24, PFD_T_U32, F_JLAST, "jitter_last_us", "us",
      "last period jitter abs(t_k - t_(k-1) - T) (internal clock)")
    I(26, PFD_T_U32, F_JMAX, "jitter_max_us", "us", "largest period jitter since start or clear")
    I(28, PFD_T_U32, F_WDTRIPS, "watchdog_trips", "", "watchdog trips since start or clear")
    I(30, PFD_T_U16, F_VMAJOR, "version_major", "", "pneufracd version")
    I(31, PFD_T_U16, F_VMINOR, "version_minor", "", "")
    I(32, PFD_T_U16, F_VPATCH, "version_patch", "", "")
    I(33, PFD_T_U16, F_VMAP, "regmap_version", "", "version of this register map")
    I(34, PFD_T_U16, F_UNIT, "unit_id", "", "this instance's unit id")
    I(35, PFD_T_U16, F_NINST, "instances", "", "instances in this daemon")
    PARAMS(COMMITTED_OWN, COMMITTED_LIB)
    I(78, PFD_T_U16, F_COMMITTED + K_SUBSTEPS, "committed_substeps", "",
      "substeps as staged (0 = chosen)")
    I(79, PFD_T_U16, F_K_USED, "substeps_used", "",
      "controller steps per exchange the committed set runs")
    I(80, PFD_T_F32, F_INTERNAL_FS, "internal_fs", "Hz",
      "the committed set's internal rate, fs x substeps_used")
    I(82, PFD_T_F32, F_STEP_NS, "step_cost_ns", "ns",
      "CPU time of one controller step of the committed set, measured at start or at its commit")
    I(84, PFD_T_F32, F_LOAD, "load_pct", "%",
      "this instance's share of one core: fs x (substeps_used + 1) x step_cost_ns")
};
const unsigned pfd_nregs = sizeof pfd_regs / sizeof pfd_regs[0];

unsigned pfd_type_words(int type)
{
    return type == PFD_T_F32 || type == PFD_T_U32 ? 2u : 1u;
}

const pfd_reg *pfd_reg_at(int space, unsigned addr)
{
    unsigned i;
    for (i = 0; i < pfd_nregs; i++) {
        const pfd_reg *r = &pfd_regs[i];
        if (r->space == space && addr >= r->addr &&
            addr < r->addr + pfd_type_words(r->type))
            return r;
    }
    return NULL;
}

const pfd_reg *pfd_reg_named(int space, const char *name)
{
    unsigned i;
    for (i = 0; i < pfd_nregs; i++)
        if (pfd_regs[i].space == space && !strcmp(pfd_regs[i].name, name))
            return &pfd_regs[i];
    return NULL;
}

double pfd_reg_min(const pfd_reg *r)
{
    return r->param >= 0 ? pf_param_info((pf_param_id)r->param)->lo : r->min;
}

double pfd_reg_max(const pfd_reg *r)
{
    return r->param >= 0 ? pf_param_info((pf_param_id)r->param)->hi : r->max;
}

int pfd_reg_min_excl(const pfd_reg *r)
{
    return r->param >= 0 &&
           (pf_param_info((pf_param_id)r->param)->flags & PF_PARAM_LO_OPEN);
}

const char *pfd_reg_unit(const pfd_reg *r)
{
    if (r->unit != NULL || r->param < 0)
        return r->unit != NULL ? r->unit : "";
    return pf_param_info((pf_param_id)r->param)->unit;
}

const char *pfd_reg_desc(const pfd_reg *r)
{
    if (r->desc != NULL || r->param < 0)
        return r->desc != NULL ? r->desc : "";
    return pf_param_info((pf_param_id)r->param)->desc;
}

int pfd_reg_in_range(const pfd_reg *r, double v)
{
    if (r->param >= 0)
        return pf_param_check((pf_param_id)r->param, v) == PF_OK;
    return isfinite(v) && v >= r->min && v <= r->max;
}

void pfd_reg_format_range(const pfd_reg *r, char *buf, size_t n)
{
    snprintf(buf, n, "%s%.9g .. %.9g]", pfd_reg_min_excl(r) ? "(" : "[",
             pfd_reg_min(r), pfd_reg_max(r));
}

const char *pfd_word_order_name(int order)
{
    return order == PFD_WORDS_ABCD ? "abcd" : order == PFD_WORDS_CDAB ? "cdab" : "?";
}

void pfd_u32_pack(uint32_t u, int word_order, uint16_t *w)
{
    const int lo_first = word_order == PFD_WORDS_CDAB;
    w[lo_first ? 1 : 0] = (uint16_t)(u >> 16);
    w[lo_first ? 0 : 1] = (uint16_t)(u & 0xFFFFu);
}

uint32_t pfd_u32_unpack(const uint16_t *w, int word_order)
{
    const int lo_first = word_order == PFD_WORDS_CDAB;
    return ((uint32_t)w[lo_first ? 1 : 0] << 16) | w[lo_first ? 0 : 1];
}

void pfd_f32_pack(float v, int word_order, uint16_t *w)
{
    uint32_t u;
    memcpy(&u, &v, sizeof u);
    pfd_u32_pack(u, word_order, w);
}

float pfd_f32_unpack(const uint16_t *w, int word_order)
{
    uint32_t u = pfd_u32_unpack(w, word_order);
    float v;
    memcpy(&v, &u, sizeof v);
    return v;
}

static double ip_get(const pfd_iparams *ip, int k)
{
    switch (k) {
    case K_CONFIG: return (double)ip->p.topology;
    case K_ARITH: return (double)ip->arith;
    case K_FS: return ip->fs;
    case K_IN_FS: return ip->in_fs;
    case K_OUT_FS: return ip->out_fs;
    case K_BUMP: return ip->bump_tau;
    case K_SUBSTEPS: return (double)ip->substeps;
    default: return pf_params_get(&ip->p, (pf_param_id)(k - K_P0));
    }
}

static void ip_set(pfd_iparams *ip, int k, double v)
{
    switch (k) {
    case K_CONFIG: ip->p.topology = (pf_topology)(int)v; break;
    case K_ARITH: ip->arith = (int)v; break;
    case K_FS: ip->fs = v; break;
    case K_IN_FS: ip->in_fs = v; break;
    case K_OUT_FS: ip->out_fs = v; break;
    case K_BUMP: ip->bump_tau = v; break;
    case K_SUBSTEPS: ip->substeps = (unsigned)v; break;
    default: (void)pf_params_set(&ip->p, (pf_param_id)(k - K_P0), v); break;
    }
}

uint16_t pfd_regmap_staged_addr(int param)
{
    if (param >= (int)PF_P_A && param <= (int)PF_P_RCI)
        return HS(K_P0 + param);
    switch (param) {
    case PF_P_CONFIG: return HS(K_CONFIG);
    /* The band follows fs, so a band error is fixed through fs. */
    case PF_P_FS: case PF_P_WB: case PF_P_WH: case PF_P_ORDER: return HS(K_FS);
    case PF_P_IN_FS: return HS(K_IN_FS);
    case PF_P_OUT_FS: return HS(K_OUT_FS);
    case PFD_P_BUMP_TAU: return HS(K_BUMP);
    case PFD_P_ARITH: return HS(K_ARITH);
    case PFD_P_SUBSTEPS: return pfd_reg_named(PFD_HOLD, "substeps")->addr;
    default: return 0xFFFFu;
    }
}

double pfd_regmap_hold_value(const pfd_reg *r, const pfd_hold *h,
                             const pfd_iparams *committed)
{
    const pfd_live *l = &h->live;
    const double in_fs = committed->in_fs;

    if (r->field >= F_STAGED && r->field < F_COMMITTED)
        return ip_get(&h->staged, r->field - F_STAGED);
    switch (r->field) {
    case F_E: return l->e;
    case F_SP: return l->sp;
    case F_PV: return l->pv;
    case F_E_I16: return pf_q15_quantize(l->e, in_fs);
    case F_SP_I16: return pf_q15_quantize(l->sp, in_fs);
    case F_PV_I16: return pf_q15_quantize(l->pv, in_fs);
    case F_INPUT_SEL: return l->input_sel;
    case F_MODE: return l->mode;
    case F_MANUAL: return l->manual_out;
    case F_FAILSAFE: return l->failsafe_out;
    case F_WATCHDOG: return l->watchdog_ms;
    case F_LOCK: return h->param_lock;
    default: return 0; /* the actions read 0 */
    }
}

static double field_value(const pfd_reg *r, const pfd_view *v)
{
    const pfd_inst *in = v->inst;
    const pfd_snap *s = v->snap;

    if (r->field >= F_COMMITTED)
        return ip_get(&in->committed, r->field - F_COMMITTED);
    if (r->space == PFD_HOLD && r->access != PFD_R)
        return pfd_regmap_hold_value(r, v->hold, &in->committed);
    switch (r->field) {
    case F_PC: return s->sig.pc;
    case F_X: return s->sig.x;
    case F_PB: return s->sig.pb;
    case F_Y: return s->sig.y;
    case F_EU: return s->e_used;
    case F_PC_I16: return s->sig.pc_q15;
    case F_X_I16: return s->sig.x_q15;
    case F_PB_I16: return s->sig.pb_q15;
    case F_Y_I16: return s->sig.y_q15;
    case F_EU_I16: return pf_q15_quantize(s->e_used, in->committed.in_fs);
    case F_STATUS: return v->status;
    case F_CRESULT: return in->commit_result;
    case F_CADDR: return in->err_addr;
    case F_CPARAM: return in->err_param;
    case F_COMMITS: return in->gen & 0xFFFFu; /* one per accepted commit */
    case F_SAMPLES: return s->samples;
    case F_OVERRUNS: return s->overruns;
    case F_JLAST: return s->jit_last_us;
    case F_JMAX: return s->jit_max_us;
    case F_WDTRIPS: return s->wd_trips;
    case F_VMAJOR: return PFD_VERSION_MAJOR;
    case F_VMINOR: return PFD_VERSION_MINOR;
    case F_VPATCH: return PFD_VERSION_PATCH;
    case F_VMAP: return PFD_REGMAP_VERSION;
    case F_UNIT: return in->unit;
    case F_NINST: return v->n_instances;
    case F_K_USED: return in->rate.k;
    case F_INTERNAL_FS: return in->rate.internal_fs;
    case F_STEP_NS: return in->rate.step_ns;
    case F_LOAD: return 100.0 * in->committed.fs * pfd_rate_exchange_ns(&in->rate) * 1e-9;
    default: return 0;
    }
}

void pfd_regmap_render(int space, const pfd_view *v, uint16_t *img)
{
    unsigned i;
    for (i = 0; i < pfd_nregs; i++) {
        const pfd_reg *r = &pfd_regs[i];
        double x;
        if (r->space != space)
            continue;
        x = field_value(r, v);
        switch (r->type) {
        case PFD_T_F32:
            pfd_f32_pack((float)x, v->word_order, img + r->addr);
            break;
        case PFD_T_U32:
            pfd_u32_pack((uint32_t)x, v->word_order, img + r->addr);
            break;
        case PFD_T_I16:
            img[r->addr] = (uint16_t)(int16_t)x; /* two's complement on the wire */
            break;
        default:
            img[r->addr] = (uint16_t)x;
            break;
        }
    }
}

/* A 32-bit float holds a range's ends only to float precision (1e-9 is
 * 9.99999972e-10 as a float, below the bound), so a client writing the
 * documented end would be refused. A float that the rounding of a closed
 * end put outside the range is taken as that end; a float inside the range
 * is kept bit for bit (-0 stays -0, 999999995904 stays itself), and an
 * open end is never snapped onto. */
static double f32_value(const pfd_reg *r, const uint16_t *w, int word_order)
{
    const float f = pfd_f32_unpack(w, word_order);
    const double lo = pfd_reg_min(r), hi = pfd_reg_max(r);

    if (!isfinite(f))
        return (double)f;
    if (f < lo && !pfd_reg_min_excl(r) && fabs(lo) <= FLT_MAX && f == (float)lo)
        return lo;
    if (f > hi && fabs(hi) <= FLT_MAX && f == (float)hi)
        return hi;
    return (double)f;
}

int pfd_regmap_decode(unsigned addr, unsigned count, const uint16_t *vals,
                      int word_order, pfd_wlist *out)
{
    unsigned a = addr;

    memset(out, 0, sizeof *out);
    /* Addresses first, for the whole request: a bad address anywhere
     * refuses it before any value is looked at. */
    while (a < addr + count) {
        const pfd_reg *r = pfd_reg_at(PFD_HOLD, a);
        unsigned nw;
        if (r == NULL || r->access == PFD_R || r->addr != a)
            return MODBUS_EXCEPTION_ILLEGAL_DATA_ADDRESS;
        nw = pfd_type_words(r->type);
        if (a + nw > addr + count)
            return MODBUS_EXCEPTION_ILLEGAL_DATA_ADDRESS; /* half of a 32-bit field */
        a += nw;
    }
    for (a = addr; a < addr + count;) {
        const pfd_reg *r = pfd_reg_at(PFD_HOLD, a);
        const uint16_t *w = vals + (a - addr);
        double v;
        int ok;

        switch (r->type) {
        case PFD_T_F32:
            v = f32_value(r, w, word_order);
            ok = pfd_reg_in_range(r, v);
            break;
        case PFD_T_I16:
            v = (double)(int16_t)w[0];
            ok = 1;
            break;
        default:
            v = (double)w[0];
            ok = pfd_reg_in_range(r, v);
            break;
        }
        if (!ok)
            return MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE;
        if (r->flags & PFD_F_ACTION) {
            if (r->field == F_COMMIT)
                out->commit = (uint16_t)v;
            else if (r->field == F_COMMAND)
                out->command = (uint16_t)v;
            else
                out->tick = (uint16_t)v;
        } else {
            out->w[out->n].r = r;
            out->w[out->n].v = v;
            out->n++;
        }
        if (r->flags & PFD_F_STAGED)
            out->staged = 1;
        if (r->flags & PFD_F_REFRESH)
            out->refresh = 1;
        if (r->flags & PFD_F_LIVE)
            out->live = 1;
        if (r->field == F_LOCK)
            out->lock = 1;
        if (!(r->flags & PFD_F_OPEN))
            out->guarded = 1;
        if (pfd_access_to_write(r) > out->access)
            out->access = pfd_access_to_write(r);
        a += pfd_type_words(r->type);
    }
    return 0;
}

/* The f32 register an int16 mirror writes (by its field), or NULL. */
static const pfd_reg *mirror_target(const pfd_reg *r)
{
    const int field = r->field == F_E_I16 ? F_E
                      : r->field == F_SP_I16 ? F_SP
                      : r->field == F_PV_I16 ? F_PV : -1;
    unsigned i;

    for (i = 0; field >= 0 && i < pfd_nregs; i++)
        if (pfd_regs[i].space == PFD_HOLD && pfd_regs[i].field == field)
            return &pfd_regs[i];
    return NULL;
}

/* What an int16 mirror write stores: one conversion for the check and the
 * apply, so that what is checked is what is stored. */
static float mirror_value(double raw, double in_fs)
{
    return (float)pf_q15_value((int16_t)raw, in_fs);
}

const pfd_reg *pfd_regmap_check_mirrors(const pfd_wlist *wl, const pfd_iparams *committed)
{
    unsigned i;

    for (i = 0; i < wl->n; i++) {
        const pfd_reg *t = mirror_target(wl->w[i].r);
        if (t != NULL &&
            !pfd_reg_in_range(t, (double)mirror_value(wl->w[i].v, committed->in_fs)))
            return wl->w[i].r;
    }
    return NULL;
}

void pfd_regmap_apply(pfd_hold *h, const pfd_iparams *committed,
                      const pfd_wlist *wl)
{
    const double in_fs = committed->in_fs;
    pfd_live *l = &h->live;
    unsigned i;

    for (i = 0; i < wl->n; i++) {
        const pfd_reg *r = wl->w[i].r;
        double v = wl->w[i].v;
        if (r->field >= F_STAGED) {
            ip_set(&h->staged, r->field - F_STAGED, v);
            continue;
        }
        switch (r->field) {
        case F_E: l->e = (float)v; break;
        case F_SP: l->sp = (float)v; break;
        case F_PV: l->pv = (float)v; break;
        case F_E_I16: l->e = mirror_value(v, in_fs); break;
        case F_SP_I16: l->sp = mirror_value(v, in_fs); break;
        case F_PV_I16: l->pv = mirror_value(v, in_fs); break;
        case F_INPUT_SEL: l->input_sel = (uint16_t)v; break;
        case F_MODE: l->mode = (uint16_t)v; break;
        case F_MANUAL: l->manual_out = (float)v; break;
        case F_FAILSAFE: l->failsafe_out = (float)v; break;
        case F_WATCHDOG: l->watchdog_ms = (uint16_t)v; break;
        case F_LOCK: h->param_lock = (uint16_t)v; break;
        default: break;
        }
    }
    if (wl->refresh)
        l->refresh++;
}

static const char *type_name(int t)
{
    static const char *const names[] = {"u16", "i16", "u32", "f32"};
    return names[t];
}

static void print_range(FILE *f, const pfd_reg *r)
{
    if (r->access == PFD_R)
        return;
    if (r->type == PFD_T_I16) {
        const pfd_reg *t = mirror_target(r);
        /* A mirror's raw value is any int16, but what it writes is held
         * to its target's range, which in_fs can reach. */
        if (t != NULL)
            fprintf(f, "any, with v*in_fs/32768 in %s's range", t->name);
        else
            fputs("any", f);
    } else {
        char range[64];
        pfd_reg_format_range(r, range, sizeof range);
        fputs(range, f);
    }
}

/* Who may write it (pfd_access.h), and whether a lock leaves it open. */
static void print_writers(FILE *f, const pfd_reg *r)
{
    if (r->access == PFD_R)
        return;
    fputs((r->flags & PFD_F_OPERATE) ? "operate" : "engineer", f);
    if (r->flags & PFD_F_OPEN)
        fputs(", open", f);
}

/* A parameter's description says which set it belongs to. */
static const char *desc_prefix(const pfd_reg *r)
{
    if (r->field >= F_COMMITTED)
        return "committed: ";
    return r->field >= F_STAGED ? "staged: " : "";
}

static void print_space(FILE *f, int space)
{
    unsigned i;
    fputs("| Address | Name | Type | Access | Unit | Range | Write | Description |\n"
          "|---:|---|---|---|---|---|---|---|\n", f);
    for (i = 0; i < pfd_nregs; i++) {
        const pfd_reg *r = &pfd_regs[i];
        static const char *const acc[] = {"R", "RW", "W"};
        if (r->space != space)
            continue;
        if (pfd_type_words(r->type) == 2)
            fprintf(f, "| %u-%u | ", (unsigned)r->addr, r->addr + 1u);
        else
            fprintf(f, "| %u | ", (unsigned)r->addr);
        fprintf(f, "`%s` | %s | %s | %s | ", r->name, type_name(r->type),
                acc[r->access], pfd_reg_unit(r));
        print_range(f, r);
        fputs(" | ", f);
        print_writers(f, r);
        fprintf(f, " | %s%s |\n", desc_prefix(r), pfd_reg_desc(r));
    }
}

void pfd_regmap_print_md(FILE *f)
{
    fprintf(f,
"<!-- SPDX-License-Identifier: MIT -->\n"
"# pneufracd register map (version %d)\n"
"\n"
"Generated by `pneufracd --print-register-map` from the table in\n"
"`port/posix/pfd_regmap.c`, whose rows for the library's parameters take\n"
"their range, unit and description from the library's parameter table\n"
"(`pf_param_info`, `lib/src/pf_param_table.c`); the test `regmap_doc` fails\n"
"if this file and the program disagree. Do not edit by hand.\n"
"\n"
"- Every instance has this map; the Modbus unit id selects the instance.\n"
"  An unknown unit id is answered with exception 0B (gateway target failed).\n"
"- Addresses are 0-based PDU addresses (mbpoll: add `-0`, or add 1).\n"
"- `f32`: IEEE-754 binary32 in two registers; `u32`: an unsigned 32-bit\n"
"  integer in two registers. Each register is big-endian, and the word\n"
"  order is the daemon's `--word-order` (config key `word_order`), the\n"
"  same for every 32-bit register of every instance, read or written:\n"
"  `abcd` (the default) high word first (mbpoll `-B`; pymodbus\n"
"  `word_order=\"big\"`), `cdab` low word first (mbpoll without `-B`;\n"
"  pymodbus `word_order=\"little\"`). 0.5 is `3F00 0000` in abcd and\n"
"  `0000 3F00` in cdab. `i16`: two's complement.\n"
"- Function codes: 03 read holding, 04 read input, 06 write one, 16 write\n"
"  many, 23 write-and-read. Anything else: exception 01.\n"
"- Exceptions: 01 a function code other than those above (also 0x80 and\n"
"  up: the answer's function code is the request's with bit 7 set), writes\n"
"  in read-only mode, writes the client's access does not allow (column\n"
"  Write), writes of registers that are not open while another client\n"
"  holds `param_lock` (or with --param-lock), `tick` with the internal\n"
"  clock; 02 an address that is not in the table, a write to a read-only\n"
"  register or to half of a 32-bit field; 03 a count out of range (reads\n"
"  1..125, writes 1..123, FC23 1..121), a value out of range, NaN or\n"
"  infinity, a refused commit; 04 a commit that was applied but could not\n"
"  be persisted (`commit_result` 5), or an unexpected library error\n"
"  (`commit_result` 4); 06 a commit while no parameter slot is free (only\n"
"  if the loop stalls mid-switch for 10 ms); 0B an unknown unit id. A\n"
"  request that gets an exception changes nothing, except 04 with\n"
"  `commit_result` 5: that set runs.\n"
"- Write: the access a client needs to write the register (docs/pneufracd.md,\n"
"  \"Security\"): operate or engineer; reading needs read. Open: writable\n"
"  while another client holds `param_lock`.\n"
"- Staged registers belong to the connection that writes them: each client\n"
"  reads its own staged set (the committed set plus its own staged writes),\n"
"  and its commit applies exactly those writes.\n"
"- A multi-register write is validated whole, then applied together;\n"
"  `commit`, `command` and `tick` act after the data registers of the same\n"
"  request, in that order.\n"
"\n"
"## Holding registers (FC03 read; FC06, FC16, FC23 write)\n"
"\n", PFD_REGMAP_VERSION);
    print_space(f, PFD_HOLD);
    fputs("\n## Input registers (FC04 read)\n\n", f);
    print_space(f, PFD_INPUT);
}
