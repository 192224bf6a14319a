/* SPDX-License-Identifier: MIT */
/**
 * @file pf_layout.h
 * @brief Sizes and layouts of the public structs, as this build of the
 *        library compiled them: the seam for bindings (ctypes, cffi, ...),
 *        which can then allocate instances and mirror the input structs
 *        without restating a size, an offset or a compile-time limit.
 *        C callers use sizeof and the struct definitions instead.
 */
#ifndef PNEUFRAC_PF_LAYOUT_H
#define PNEUFRAC_PF_LAYOUT_H

#include <stddef.h>

#include "pf_controller.h"

#ifdef __cplusplus
extern "C" {
#endif

/** The public structs a binding may allocate or fill. */
typedef enum pf_type {
    PF_TYPE_PARAMS = 0,          /**< pf_params */
    PF_TYPE_EFFECTS,             /**< pf_effects */
    PF_TYPE_DESIGN_OPTS,         /**< pf_design_opts */
    PF_TYPE_CTRL_DESIGN,         /**< pf_ctrl_design */
    PF_TYPE_CTRL_COEFFS_F64,     /**< pf_ctrl_coeffs_f64 */
    PF_TYPE_CTRL_COEFFS_F32,     /**< pf_ctrl_coeffs_f32 */
    PF_TYPE_CTRL_COEFFS_Q15,     /**< pf_ctrl_coeffs_q15 */
    PF_TYPE_CTRL_F64,            /**< pf_ctrl_f64 */
    PF_TYPE_CTRL_F32,            /**< pf_ctrl_f32 */
    PF_TYPE_CTRL_Q15,            /**< pf_ctrl_q15 */
    PF_TYPE_RUNTIME,             /**< pf_runtime */
    PF_TYPE_PARAM_SPEC,          /**< pf_param_spec */
    PF_TYPE_COUNT
} pf_type;

/** @return the C name of type @p t ("pf_params"), or "?". */
const char *pf_type_name(pf_type t);
/** @return sizeof the type, or 0 for an unknown one. None of the types
 *  needs more alignment than malloc() gives. */
size_t pf_sizeof(pf_type t);

/** What a struct member holds. */
typedef enum pf_field_kind {
    PF_FIELD_DOUBLE = 0, /**< double */
    PF_FIELD_INT = 1,    /**< int or an enum (int-sized on every supported ABI;
                              size says so) */
    PF_FIELD_STRUCT = 2  /**< a struct of type pf_field.type */
} pf_field_kind;

/** One member of a public struct. */
typedef struct pf_field {
    const char *name;   /**< member name; for parameters, the table's name */
    size_t offset;      /**< offsetof */
    size_t size;        /**< sizeof the member */
    pf_field_kind kind;
    pf_type type;       /**< PF_FIELD_STRUCT: the member's type */
} pf_field;

/** Member @p i (from 0, in declaration order) of pf_params, pf_effects,
 *  pf_design_opts or pf_ctrl_design (whose members p, fx, opt, rt are
 *  structs). Other types are opaque: allocate pf_sizeof() bytes.
 *  @return 0 with @p out filled, or -1 past the last member, for another
 *          type or a NULL @p out. */
int pf_field_get(pf_type t, int i, pf_field *out);

/** @return the length (elements) of the dead-time buffer the runtimes of
 *  design @p d need (its coefficient set's delay_len), or 0 for NULL. */
size_t pf_ctrl_design_delay_len(const pf_ctrl_design *d);

/** @return PF_MAX_ORDER of this build (pf_config.h), which sizes the
 *  operator and controller structs. */
int pf_max_order(void);

/** @return PF_BANK_MAX_ORDER of this build (pf_config.h): the most states
 *  a reduced-order bank (pf_bank.h) may have. */
int pf_bank_max_order(void);

/** @return PF_CTRL_MAX_STATES of this build (pf_controller.h): the room
 *  pf_ctrl_state_space needs (A holds its square). */
int pf_ctrl_max_states(void);

#ifdef __cplusplus
}
#endif
#endif /* PNEUFRAC_PF_LAYOUT_H */
