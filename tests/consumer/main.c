/* SPDX-License-Identifier: MIT */
/* The tiny program of the consumer test: design Example 6 at 20 kHz, run
 * it in double and float on a unit step, check they agree, print p_c. */
#include <math.h>
#include <stdio.h>

#include "pneufrac/pneufrac.h"

int main(void)
{
    static pf_ctrl_design d;
    static pf_ctrl_coeffs_f32 cf;
    static pf_ctrl_f64 a;
    static pf_ctrl_f32 b;
    pf_params p;
    pf_design_opts o;
    double ya = 0.0, yb = 0.0;
    int n;

    pf_params_default(&p, PF_TOPO_DD);
    pf_design_opts_default(&o, 20000.0);
    if (pf_ctrl_design_make(&d, &p, NULL, &o) != PF_OK)
        return 1;
    pf_ctrl_coeffs_f32_make(&cf, &d.rt);
    if (pf_ctrl_init_f64(&a, &d.rt, NULL, 0) != PF_OK ||
        pf_ctrl_init_f32(&b, &cf, NULL, 0) != PF_OK)
        return 1;
    for (n = 0; n < 2000; n++) {
        ya = pf_ctrl_step_f64(&a, 1.0);
        yb = pf_ctrl_step_f32(&b, 1.0f);
    }
    printf("pneufrac %s: p_c(0.1 s) = %.6g (double), %.6g (float)\n",
           PNEUFRAC_VERSION_STRING, ya, yb);
    /* The step response is positive and float follows double. */
    return ya > 0.0 && fabs(yb - ya) <= 1e-5 * fabs(ya) ? 0 : 1;
}
