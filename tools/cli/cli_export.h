/* SPDX-License-Identifier: MIT */
/* Export of coefficient sets as C headers for firmware (static const data). */
#ifndef CLI_EXPORT_H
#define CLI_EXPORT_H

#include <stdio.h>

#include "pneufrac/pneufrac.h"

/* Write a header defining `static const pf_ctrl_coeffs_q15 <name>` (and,
 * with a nozzle curve, the table it points to, <name>_nozzle).
 * @p comment is placed in the header's opening comment (may be NULL).
 * Returns 0, or -1 on a write error. */
int cli_export_c_q15(FILE *f, const char *name, const char *comment,
                     const pf_ctrl_coeffs_q15 *c);

/* Same for the float coefficient set (pf_ctrl_coeffs_f32). */
int cli_export_c_f32(FILE *f, const char *name, const char *comment,
                     const pf_ctrl_coeffs_f32 *c);

/* Write each fractional operator of design @p d as coefficient arrays for
 * CMSIS-DSP's arm_biquad_cascade_df1_f32 (@p q15 == 0) or _q15, named
 * <name>_<operator>_coeffs with <name>_<operator>_num_stages (and
 * _post_shift for q15); see pfh_sos.h for the conversion. Every operator
 * is scaled by @p scale (Q15: in_fs/out_fs, the full scales of its input
 * and output). Nothing is written unless every operator converts.
 * Returns 0, -1 on a write error, or -2 with *st set when an operator
 * cannot be converted (PF_E_SCALE: a Q15 coefficient needs postShift > 15). */
int cli_export_cmsis(FILE *f, const char *name, const char *comment,
                     const pf_ctrl_design *d, int q15, double scale,
                     pf_status *st);

#endif
