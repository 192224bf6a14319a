/* SPDX-License-Identifier: MIT */
/* Firmware-style use of the copied Q15 runtime (tests/consumer/run.sh):
 * the exported coefficient header, a static instance, integers only.
 * Prints pc_q15 for a half-scale step, one line per sample, to be compared
 * with `pneufrac simulate --arith q15`. */
#include <stdio.h>
#include <stdlib.h>

#include "pneufrac/pf_controller.h"
#include "pf_example6_q15.h"

static pf_ctrl_q15 controller;

int main(int argc, char **argv)
{
    long n, samples = argc > 1 ? atol(argv[1]) : 100;
    if (pf_ctrl_init_q15(&controller, &pf_example6_q15, NULL, 0) != PF_OK)
        return 1;
    for (n = 0; n < samples; n++)
        printf("%d\n", pf_ctrl_step_q15(&controller, 16384));
    return 0;
}
