/* SPDX-License-Identifier: MIT */
/* Q15 operator runtime (integer only). */
#include <stddef.h>
#include <string.h>

#include "pf_q15_ops.h"

pf_status pf_fracop_init_q15(pf_fracop_q15 *S, const pf_fracop_coeffs_q15 *c)
{
    if (S == NULL || c == NULL)
        return PF_E_NULL;
    S->c = c;
    pf_fracop_reset_q15(S);
    return PF_OK;
}

void pf_fracop_reset_q15(pf_fracop_q15 *S)
{
    if (S == NULL)
        return;
    memset(S->s, 0, sizeof S->s);
    memset(S->si, 0, sizeof S->si);
    S->sv = 0;
    S->u1 = 0;
}

int16_t pf_fracop_step_q15(pf_fracop_q15 *S, int16_t u)
{
    const pf_fracop_coeffs_q15 *c = S->c;
    int64_t sf;
    int32_t ui;
    /* Held input: the sum of two samples is exact in int32; the 1/2 is
     * folded into in_q at design time. */
    ui = pf_mulc(c->in_q, c->hold ? (int32_t)u + S->u1 : (int32_t)u);
    S->u1 = u;
    (void)pf_q_op_state(S, &sf);
    return pf_q_to_q15(c->out_q, pf_q_op_update(S, ui, sf));
}
