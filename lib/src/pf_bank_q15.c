/* SPDX-License-Identifier: MIT */
/*
 * Q15 runtime of a reduced-order bank (pf_bank.h): integer only, built for
 * the Cortex-M0+ (no 32 x 32 -> 64 multiplier) and fast on the M4 too.
 *
 * Per real section and sample, exactly:
 *   acc += hi >> out_sh                         (the state before the update)
 *   d    = floor(beta u / 2^16) - hi            |d| < 2^29
 *   p    = floor(lam_m d / 2^14)                |p| < 2^31
 *   s    = s + p 2^lam_v                        (hi:lo, 32 fraction bits)
 * i.e. s <- s + lam (beta u - s) with s = hi + lo 2^-32 in units of 2^-28 of
 * the input's full scale. The products are 32 x 16 bits: two 32-bit
 * multiplies each on an M0+ (one on an M4), four in all, no 64-bit helper;
 * the output sum needs none (its gains are powers of two).
 *
 * Overflow: the design keeps each exact state within 0.98 2^28 for any
 * input. The floor of p biases a state by the bias of one step,
 * 2^(lam_v - 32) units of hi, over the section's decay per step, 1 - |1 -
 * lam|: at most 1/2 unit for lam <= 1 (lam >= 2^(lam_v - 31)), at most 50
 * for lam <= 1.99 (the design's limit), so |d| < 2^29 and |p| < 2^31. The
 * output sum stays within 2^30 (pf_bank.h) and saturates once, to the
 * int16 range.
 *
 * Rounding: floors inside (each far below an output LSB: one unit of hi is
 * 2^-13 LSB), round half up at the output. Arithmetic right shifts of
 * negative values are required (checked in pf_qmath.h).
 */
#include <stddef.h>
#include <string.h>

#include "pf_qmath.h"
#include "pneufrac/pf_bank.h"

/* The ARMv6-M assembly loop (below) with GCC or Clang on a Cortex-M0/M0+,
 * unless PF_BANK_ASM_M0 is defined 0: the C is the same integers. */
#ifndef PF_BANK_ASM_M0
#if defined(__ARM_ARCH_6M__) && defined(__GNUC__)
#define PF_BANK_ASM_M0 1
#else
#define PF_BANK_ASM_M0 0
#endif
#endif

/* floor(b u / 2^16) for |b| < 2^31 and a Q15 u: |result| < 2^30. */
static inline int32_t mul_in(int32_t b, int32_t u)
{
#if PF_Q15_NARROW_MUL
    /* b = bh 2^16 + bl with bl in [0, 2^16): bl u fits 31 bits. */
    return (b >> 16) * u + (((int32_t)((uint32_t)b & 0xFFFFu) * u) >> 16);
#else
    return (int32_t)(((int64_t)b * u) >> 16);
#endif
}

/* s <- s + m 2^(v - 46) d, exactly as the head of the file: m < 2^16,
 * |d| < 2^29, v in [1, 31]. */
#if defined(__GNUC__)
__attribute__((always_inline))
#endif
static inline void add_leak(pf_q15_sec *s, uint32_t m, unsigned v, int32_t d)
{
#if PF_Q15_NARROW_MUL
    /* d = dh 2^16 + dl: m dh 4 stays below 2^31, m dl below 2^32. */
    int32_t p = (int32_t)m * (d >> 16) * 4 + (int32_t)((m * ((uint32_t)d & 0xFFFFu)) >> 14);
#else
    int32_t p = (int32_t)(((int64_t)m * d) >> 14);
#endif
    /* p 2^v as two words; the 64-bit sum is an add and an add with carry */
    uint64_t t = ((uint64_t)(uint32_t)s->hi << 32 | s->lo) +
                 ((uint64_t)(uint32_t)(p >> (32u - v)) << 32 | (uint32_t)p << v);
    s->hi = (int32_t)(uint32_t)(t >> 32);
    s->lo = (uint32_t)t;
}

/* The real sections: their share of the output (from the states before
 * the update), then the update. */
#if PF_BANK_ASM_M0
/* The same loop in ARMv6-M assembly, beside the C one below and the same
 * integers, instruction for instruction of the arithmetic (tests/target
 * runs the M0+ build bit for bit against the host's C). GCC keeps the C
 * loop's sum, input and temporaries on the stack (Thumb-1 has eight low
 * registers), 70 cycles a section; this keeps them in r0-r8 and ip.
 * Arguments: r0 the states, r1 the sections, r2 their number, r3 u;
 * returns the sum in r0. Offsets: pf_q15_sec {lo 0, hi 4},
 * pf_bank_sec_q15 {beta 0, lam_m 4, lam_v 6, out_sh 7}. */
#define PF_ASM_ARG __attribute__((unused)) /* read by the assembly, as r0-r3 */
/* The offsets and sizes the assembly reads, checked when it is built. */
typedef char pf_bank_asm_layout[offsetof(pf_q15_sec, lo) == 0 && offsetof(pf_q15_sec, hi) == 4 &&
                                        sizeof(pf_q15_sec) == 8 &&
                                        offsetof(pf_bank_sec_q15, beta) == 0 &&
                                        offsetof(pf_bank_sec_q15, lam_m) == 4 &&
                                        offsetof(pf_bank_sec_q15, lam_v) == 6 &&
                                        offsetof(pf_bank_sec_q15, out_sh) == 7 &&
                                        sizeof(pf_bank_sec_q15) == 8
                                    ? 1
                                    : -1];
__attribute__((naked, noinline)) static int32_t sections(pf_q15_sec *s PF_ASM_ARG,
                                                         const pf_bank_sec_q15 *k PF_ASM_ARG,
                                                         uint32_t n PF_ASM_ARG,
                                                         int32_t u PF_ASM_ARG)
{
    __asm__ volatile(
        /* GCC hands Thumb-1 inline assembly over in divided syntax */
        "    .syntax unified\n"
        "    push  {r4, r5, r6, r7, lr}\n"
        "    mov   r4, r8\n"
        "    push  {r4}\n"
        "    movs  r4, #0\n"
        "    mov   ip, r4\n"              /* acc = 0 */
        "    lsls  r2, r2, #3\n"
        "    adds  r2, r1, r2\n"
        "    mov   r8, r2\n"              /* end of the sections */
        "    cmp   r1, r2\n"
        "    bhs   2f\n"
        "1:  ldr   r7, [r0, #4]\n"        /* hi */
        "    ldrb  r4, [r1, #7]\n"
        "    movs  r5, r7\n"
        "    asrs  r5, r4\n"
        "    add   ip, r5\n"              /* acc += hi >> out_sh */
        "    ldr   r4, [r1, #0]\n"        /* beta */
        "    uxth  r5, r4\n"
        "    muls  r5, r3\n"
        "    asrs  r5, r5, #16\n"
        "    asrs  r4, r4, #16\n"
        "    muls  r4, r3\n"
        "    adds  r4, r4, r5\n"          /* floor(beta u / 2^16) */
        "    subs  r4, r4, r7\n"          /* d */
        "    ldrh  r6, [r1, #4]\n"        /* lam_m */
        "    asrs  r5, r4, #16\n"
        "    muls  r5, r6\n"
        "    lsls  r5, r5, #2\n"
        "    uxth  r4, r4\n"
        "    muls  r4, r6\n"
        "    lsrs  r4, r4, #14\n"
        "    adds  r5, r5, r4\n"          /* p = floor(lam_m d / 2^14) */
        "    ldrb  r6, [r1, #6]\n"        /* v */
        "    movs  r4, r5\n"
        "    lsls  r4, r6\n"              /* p << v */
        "    movs  r2, #32\n"
        "    subs  r2, r2, r6\n"
        "    asrs  r5, r2\n"              /* p >> (32 - v) */
        "    ldr   r6, [r0, #0]\n"        /* lo */
        "    adds  r6, r6, r4\n"
        "    adcs  r7, r5\n"              /* (hi:lo) += p 2^v */
        "    str   r6, [r0, #0]\n"
        "    str   r7, [r0, #4]\n"
        "    adds  r0, #8\n"
        "    adds  r1, #8\n"
        "    cmp   r1, r8\n"
        "    blo   1b\n"
        "2:  mov   r0, ip\n"
        "    pop   {r4}\n"
        "    mov   r8, r4\n"
        "    pop   {r4, r5, r6, r7, pc}\n");
}
#else
static int32_t sections(pf_q15_sec *s, const pf_bank_sec_q15 *k, uint32_t n, int32_t u)
{
    const pf_bank_sec_q15 *end = k + n;
    int32_t acc = 0;
    for (; k < end; k++, s++) {
        int32_t hi = s->hi;
        acc += hi >> k->out_sh;
        add_leak(s, k->lam_m, k->lam_v, mul_in(k->beta, u) - hi);
    }
    return acc;
}
#endif

static int16_t output(pf_bank_q15 *S, int32_t acc)
{
    const pf_bank_coeffs_q15 *c = S->c;
    int32_t y = ((acc >> (c->out_q - 1u)) + 1) >> 1;
    int16_t o = (int16_t)(y > 32767 ? 32767 : (y < -32768 ? -32768 : y));
    if (c->delay_len > 0) {
        int16_t d = S->dbuf[S->didx];
        S->dbuf[S->didx] = o;
        if (++S->didx >= c->delay_len)
            S->didx = 0;
        o = d;
    }
    return o;
}

int16_t pf_bank_step_q15(pf_bank_q15 *S, int16_t u_q15)
{
    const pf_bank_coeffs_q15 *c = S->c;
    const pf_bank_pair_q15 *pr = c->pair, *pend = pr + c->n_pair;
    pf_q15_sec *s = S->s + c->n_sec;
    int32_t u = u_q15, acc = mul_in(c->d_m, u) + sections(S->s, c->sec, c->n_sec, u);

    for (; pr < pend; pr++, s += 2) {
        int32_t h1 = s[0].hi, h2 = s[1].hi;
        int32_t d1 = mul_in(pr->beta1, u) - h1, d2 = mul_in(pr->beta2, u) - h2;
        acc += h1 >> pr->out_sh;
        add_leak(&s[0], pr->alpha_m, pr->alpha_v, d1);
        add_leak(&s[0], pr->omega_m, pr->omega_v, d2);
        add_leak(&s[1], pr->alpha_m, pr->alpha_v, d2);
        add_leak(&s[1], pr->omega_m, pr->omega_v, -d1);
    }
    return output(S, acc);
}

void pf_bank_run_q15(pf_bank_q15 *S, const int16_t *u, int16_t *y, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++)
        y[i] = pf_bank_step_q15(S, u[i]);
}

void pf_bank_reset_q15(pf_bank_q15 *S)
{
    if (S == NULL || S->c == NULL)
        return;
    memset(S->s, 0, sizeof S->s);
    S->didx = 0;
    if (S->dbuf != NULL)
        memset(S->dbuf, 0, sizeof(int16_t) * S->c->delay_len);
}

/* Every shift within its range, so that no step can shift by 32 or more. */
static int well_formed(const pf_bank_coeffs_q15 *c)
{
    int k;
    if (c->n_sec + 2 * c->n_pair > PF_BANK_MAX_ORDER || c->out_q < 1 || c->out_q > 13)
        return 0;
    for (k = 0; k < c->n_sec; k++)
        if (c->sec[k].lam_v < 1 || c->sec[k].lam_v > 31 || c->sec[k].out_sh > 31)
            return 0;
    for (k = 0; k < c->n_pair; k++) {
        const pf_bank_pair_q15 *p = &c->pair[k];
        if (p->alpha_v < 1 || p->alpha_v > 31 || p->omega_v < 1 || p->omega_v > 31 ||
            p->out_sh > 31)
            return 0;
    }
    return 1;
}

pf_status pf_bank_init_q15(pf_bank_q15 *S, const pf_bank_coeffs_q15 *c, int16_t *dbuf,
                           size_t dlen)
{
    if (S == NULL || c == NULL)
        return PF_E_NULL;
    if (!well_formed(c))
        return PF_E_SCALE;
    if (c->delay_len > 0 && (dbuf == NULL || dlen < c->delay_len))
        return PF_E_BUFFER;
    S->c = c;
    S->dbuf = c->delay_len > 0 ? dbuf : NULL;
    pf_bank_reset_q15(S);
    return PF_OK;
}
