/* SPDX-License-Identifier: MIT */
/* "pneufrac design --format ss|zpk|sos": the realised controller as a
 * discrete LTI system in scipy's conventions, as JSON. */
#ifndef PNEUFRAC_CLI_LTI_H
#define PNEUFRAC_CLI_LTI_H

#include <stdio.h>

#include "pneufrac/pneufrac.h"

/** @return 1 if @p format is one of ss, zpk, sos. */
int cli_lti_is_format(const char *format);

/** Write design @p d in @p format (ss, zpk or sos) to @p f; prints the
 *  error. @return CLI_EXIT_OK, CLI_EXIT_USAGE (nonlinear effect, dead
 *  time) or CLI_EXIT_IO. */
int cli_lti_write(FILE *f, const char *format, const pf_ctrl_design *d);

#endif
