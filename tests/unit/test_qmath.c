/* SPDX-License-Identifier: MIT */
/*
 * The narrow forms of the Q15 primitives (PF_Q15_NARROW_MUL: 32-bit
 * multiplies and shifts only, what an ARMv6-M build compiles) against their
 * definitions in 64-bit arithmetic, which every other build compiles: they
 * must give the same integers, or M0+ and host outputs would differ.
 * Edge values and a million pseudo-random operands per primitive.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#define PF_Q15_NARROW_MUL 1
#include "pf_qmath.h"

static const int32_t edges[] = {0, 1, -1, 2, -2, 65535, 65536, -65536, -65537, 32767,
                                -32768, 1 << 30, -(1 << 30), INT32_MAX, -INT32_MAX,
                                INT32_MIN, 0x12345678, -0x12345678};
#define NEDGES (sizeof edges / sizeof edges[0])

/* xorshift32: a fixed, portable sequence */
static uint32_t next(uint32_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 17;
    *s ^= *s << 5;
    return *s;
}

static int32_t any32(uint32_t *s)
{
    /* mix full-range values with small ones, whose high half is 0 or -1 */
    uint32_t r = next(s);
    return (r & 3) == 0 ? (int32_t)(next(s) >> ((r >> 27) | 1)) * ((r & 4) ? -1 : 1)
                        : (int32_t)next(s);
}

static void test_mul64(void **state)
{
    uint32_t s = 12345;
    size_t i, j;
    long n;
    (void)state;
    for (i = 0; i < NEDGES; i++)
        for (j = 0; j < NEDGES; j++)
            assert_true(pf_q_mul64(edges[i], edges[j]) == (int64_t)edges[i] * edges[j]);
    for (n = 0; n < 1000000; n++) {
        int32_t a = any32(&s), b = any32(&s);
        assert_true(pf_q_mul64(a, b) == (int64_t)a * b);
    }
}

static void test_mul16(void **state)
{
    uint32_t s = 777;
    size_t i, j;
    long n;
    (void)state;
    for (i = 0; i < NEDGES; i++)
        for (j = 0; j < NEDGES; j++) {
            int32_t c = (int32_t)(int16_t)edges[i] == -32768 ? -32767 : (int16_t)edges[i];
            assert_int_equal(pf_q_mul16(c, edges[j]), (int32_t)(((int64_t)c * edges[j]) >> 16));
        }
    for (n = 0; n < 1000000; n++) {
        int32_t c = (int32_t)(next(&s) % 65535u) - 32767, x = any32(&s);
        assert_int_equal(pf_q_mul16(c, x), (int32_t)(((int64_t)c * x) >> 16));
    }
}

static void test_asr64(void **state)
{
    uint32_t s = 99;
    unsigned sh;
    long n;
    (void)state;
    for (n = 0; n < 200000; n++) {
        int64_t v = (int64_t)((uint64_t)next(&s) << 32 | next(&s));
        for (sh = 0; sh < 64; sh += 1 + (unsigned)(n % 7))
            assert_true(pf_q_asr64(v, sh) == v >> sh);
    }
    assert_true(pf_q_asr64(INT64_MIN, 63) == -1);
    assert_true(pf_q_asr64(INT64_MAX, 63) == 0);
}

/* round half up, written as its definition in 128-bit-free terms: the
 * sum p + 2^(sh-1) fits int64 for |p| < 2^62 */
static void test_round_shift(void **state)
{
    uint32_t s = 4242;
    unsigned sh;
    long n;
    (void)state;
    for (n = 0; n < 200000; n++) {
        int64_t p = (int64_t)((uint64_t)next(&s) << 32 | next(&s)) >> (2 + n % 40);
        for (sh = 0; sh <= 62; sh++) {
            int64_t want = sh == 0 ? p : (p + ((int64_t)1 << (sh - 1))) >> sh;
            assert_true(pf_round_shift(p, sh) == want);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mul64),
        cmocka_unit_test(test_mul16),
        cmocka_unit_test(test_asr64),
        cmocka_unit_test(test_round_shift),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
