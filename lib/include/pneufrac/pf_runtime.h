/* SPDX-License-Identifier: MIT */
/**
 * @file pf_runtime.h
 * @brief A controller runtime of any arithmetic (double, float or Q15)
 *        behind one interface, in physical units: for tools that choose
 *        the arithmetic at run time (the CLI, the daemon, the accuracy
 *        runner). Firmware that knows its arithmetic calls pf_ctrl_*_f32
 *        or _q15 directly and needs none of this.
 *
 * Q15 quantises the input with pf_q15_quantize(e, in_fs) and scales the
 * output back with pf_q15_value(., out_fs); float rounds e to float. The
 * results are those of the typed runtimes, sample for sample.
 */
#ifndef PNEUFRAC_PF_RUNTIME_H
#define PNEUFRAC_PF_RUNTIME_H

#include <stddef.h>
#include <stdint.h>

#include "pf_controller.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Arithmetic of a runtime. */
typedef enum pf_arith {
    PF_ARITH_F64 = 0, /**< double: pf_ctrl_f64 */
    PF_ARITH_F32 = 1, /**< float: pf_ctrl_f32 */
    PF_ARITH_Q15 = 2, /**< Q15: pf_ctrl_q15 */
    PF_ARITH_COUNT
} pf_arith;

/** @return "double", "float", "q15", or "?". */
const char *pf_arith_name(pf_arith arith);
/** @return the arithmetic named @p name, or PF_ARITH_COUNT. */
pf_arith pf_arith_lookup(const char *name);
/** @return the size of one dead-time buffer element in @p arith (double,
 *  float or int16_t), or 0 for an unknown arithmetic. */
size_t pf_arith_sample_size(pf_arith arith);

/** A runtime of any arithmetic. Fields are read-only for the caller. The
 *  instance points into this struct: do not move it after init. */
typedef struct pf_runtime {
    pf_arith arith;
    double in_fs, out_fs; /**< Q15 full scales of e and p_c */
    double pb_fs;         /**< k1*in_fs: the full scale of p_b's Q15 view */
    int16_t out_q15;      /**< Q15: raw output of the last sample */
    union {
        pf_ctrl_f64 f64; /**< coefficients: the design's own (d->rt) */
        struct {
            pf_ctrl_coeffs_f32 c;
            pf_ctrl_f32 S;
        } f32;
        struct {
            pf_ctrl_coeffs_q15 c;
            pf_nozzle_q15 nz; /**< the nozzle curve's table, if any */
            pf_ctrl_q15 S;
        } q15;
    } u;
} pf_runtime;

/** The signals of the last sample, physical and as Q15 views. */
typedef struct pf_runtime_signals {
    double x, pb, y, pc;  /**< physical; pc is the output (after the line) */
    int16_t x_q15, pb_q15, y_q15, pc_q15; /**< Q15 of in_fs, k1*in_fs,
                                               in_fs, out_fs */
} pf_runtime_signals;

/** Bind a design in arithmetic @p arith, at rest. The double runtime uses
 *  the design's coefficients in place (@p d must outlive @p S); float and
 *  Q15 derive theirs into @p S. @p in_fs and @p out_fs are the Q15 full
 *  scales: required for Q15 (checked by pf_ctrl_coeffs_q15_make); in double
 *  and float they only scale the Q15 views of pf_runtime_signals_get, and
 *  0 leaves those views 0. @p dbuf holds @p dlen elements of
 *  pf_arith_sample_size(arith) bytes, at least d->rt.delay_len (NULL if 0).
 *  @return PF_OK, PF_E_NULL, PF_E_BUFFER, PF_E_PARAM(PF_P_IN_FS |
 *          PF_P_OUT_FS), PF_E_UNSUPPORTED or PF_E_SCALE (Q15), or
 *          PF_E_UNSUPPORTED for an unknown arithmetic. */
pf_status pf_runtime_init(pf_runtime *S, const pf_ctrl_design *d,
                          pf_arith arith, double in_fs, double out_fs,
                          void *dbuf, size_t dlen);
/** Back to rest. */
void pf_runtime_reset(pf_runtime *S);
/** One sample: e in, p_c out, physical units. Total. */
double pf_runtime_step(pf_runtime *S, double e);
/** Block of n samples, as n calls of pf_runtime_step; @p e and @p pc may
 *  alias. */
void pf_runtime_run(pf_runtime *S, const double *e, double *pc, size_t n);
/** The signals of the last sample. Q15: the physical values are the Q15
 *  monitors scaled back; double and float: the Q15 views are quantised. */
void pf_runtime_signals_get(const pf_runtime *S, pf_runtime_signals *sig);

#ifdef __cplusplus
}
#endif
#endif /* PNEUFRAC_PF_RUNTIME_H */
