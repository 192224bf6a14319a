/* SPDX-License-Identifier: MIT */
/*
 * Shortest round-trip number text (tools/host/pfh_fmt.c): every double and
 * float reads back bit for bit, and known values come out as the shortest
 * text (expected strings are Python's repr and numpy's float32 repr, both
 * shortest-digit algorithms independent of this one). The pytest
 * tests/interface/test_csv_numbers.py compares 10^5 random values with
 * Python's repr through `pneufrac simulate`.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pfh_fmt.h"

static uint64_t rng = 0x9e3779b97f4a7c15ull;

static uint64_t next64(void)
{
    /* xorshift64*: any bit pattern, so subnormals and huge exponents too */
    rng ^= rng >> 12;
    rng ^= rng << 25;
    rng ^= rng >> 27;
    return rng * 2685821657736338717ull;
}

static void every_double_reads_back(void **state)
{
    long i;
    (void)state;
    for (i = 0; i < 300000; i++) {
        uint64_t bits = next64();
        double v, back;
        char buf[PFH_FMT_LEN];
        int n;
        memcpy(&v, &bits, sizeof v);
        if (!isfinite(v))
            continue;
        n = pfh_fmt_double(buf, v);
        assert_true(n > 0 && n < PFH_FMT_LEN);
        assert_int_equal((size_t)n, strlen(buf));
        back = strtod(buf, NULL);
        assert_memory_equal(&back, &v, sizeof v);
    }
}

static void every_float_reads_back(void **state)
{
    long i;
    (void)state;
    for (i = 0; i < 300000; i++) {
        uint32_t bits = (uint32_t)(next64() >> 32);
        float v, back;
        char buf[PFH_FMT_LEN];
        memcpy(&v, &bits, sizeof v);
        if (!isfinite(v))
            continue;
        pfh_fmt_float(buf, v);
        back = strtof(buf, NULL);
        assert_memory_equal(&back, &v, sizeof v);
    }
}

static void check_double(double v, const char *want)
{
    char buf[PFH_FMT_LEN];
    pfh_fmt_double(buf, v);
    assert_string_equal(buf, want);
}

static void known_doubles(void **state)
{
    (void)state;
    check_double(0.1, "0.1");
    check_double(0.3, "0.3");
    check_double(1.0 / 3.0, "0.3333333333333333");
    check_double(2000.0 / 3.0, "666.6666666666666");
    check_double(100.0, "100");
    check_double(1e-4, "0.0001");
    check_double(1e-5, "1e-05");
    check_double(1.5e16, "1.5e+16");
    check_double(123456789012345.6, "123456789012345.6");
    check_double(1e22, "1e+22");
    check_double(1e23, "1e+23");
    check_double(5e-324, "5e-324");
    check_double(DBL_MAX, "1.7976931348623157e+308");
    check_double(DBL_MIN, "2.2250738585072014e-308");
    /* 2^-1022 * 2^... powers of two: the gap below is half the one above */
    check_double(ldexp(1.0, 1023), "8.98846567431158e+307");
    check_double(ldexp(1.0, -1000), "9.332636185032189e-302");
    check_double(0.0, "0");
    check_double(-0.0, "-0");
    check_double(-2.5, "-2.5");
    check_double(NAN, "nan");
    check_double(INFINITY, "inf");
    check_double(-INFINITY, "-inf");
}

static void known_floats(void **state)
{
    char buf[PFH_FMT_LEN];
    (void)state;
    pfh_fmt_float(buf, 0.1f);
    assert_string_equal(buf, "0.1");
    pfh_fmt_float(buf, 1.0f / 3.0f);
    assert_string_equal(buf, "0.33333334");
    pfh_fmt_float(buf, FLT_MAX);
    assert_string_equal(buf, "3.4028235e+38");
    pfh_fmt_float(buf, 1e-45f);
    assert_string_equal(buf, "1e-45");
    pfh_fmt_float(buf, 16777216.0f);
    assert_string_equal(buf, "16777216");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(every_double_reads_back),
        cmocka_unit_test(every_float_reads_back),
        cmocka_unit_test(known_doubles),
        cmocka_unit_test(known_floats),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
