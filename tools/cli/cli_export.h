/* SPDX-License-Identifier: MIT */
/* Export of coefficient sets as C headers for firmware (static const data). */
#ifndef CLI_EXPORT_H
#define CLI_EXPORT_H

#include <stdio.h>

#include "pneufrac/pneufrac.h"

/* Write a header defining `static const pf_ctrl_coeffs_q15 <name>`.
 * @p comment is placed in the header's opening comment (may be NULL).
 * Returns 0, or -1 on a write error. */
int cli_export_c_q15(FILE *f, const char *name, const char *comment,
                     const pf_ctrl_coeffs_q15 *c);

/* Same for the float coefficient set (pf_ctrl_coeffs_f32). */
int cli_export_c_f32(FILE *f, const char *name, const char *comment,
                     const pf_ctrl_coeffs_f32 *c);

#endif
