/* SPDX-License-Identifier: MIT */
/*
 * pneufracd's register encoding (port/posix/pfd_regmap.c): the two word
 * orders of a 32-bit register, checked against values written out by hand
 * (IEEE-754 binary32 of 0.5 is 0x3F000000), and a request decoded and an
 * image rendered in each order.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <modbus/modbus.h>
#include <math.h>
#include <string.h>

#include "pfd_regmap.h"

static void known_words(void **state)
{
    uint16_t w[2];
    (void)state;
    pfd_f32_pack(0.5f, PFD_WORDS_ABCD, w);
    assert_int_equal(w[0], 0x3F00);
    assert_int_equal(w[1], 0x0000);
    pfd_f32_pack(0.5f, PFD_WORDS_CDAB, w);
    assert_int_equal(w[0], 0x0000);
    assert_int_equal(w[1], 0x3F00);
    pfd_u32_pack(0x12345678u, PFD_WORDS_ABCD, w);
    assert_int_equal(w[0], 0x1234);
    assert_int_equal(w[1], 0x5678);
    pfd_u32_pack(0x12345678u, PFD_WORDS_CDAB, w);
    assert_int_equal(w[0], 0x5678);
    assert_int_equal(w[1], 0x1234);
    assert_int_equal(pfd_u32_unpack(w, PFD_WORDS_CDAB), 0x12345678u);
    assert_int_equal(pfd_u32_unpack(w, PFD_WORDS_ABCD), 0x56781234u);
    /* -1.5 is 0xBFC00000: the sign travels in the high word, wherever it is. */
    w[0] = 0x0000;
    w[1] = 0xBFC0;
    assert_true(pfd_f32_unpack(w, PFD_WORDS_CDAB) == -1.5f);
    assert_true(pfd_f32_unpack(w, PFD_WORDS_ABCD) != -1.5f);
    assert_string_equal(pfd_word_order_name(PFD_WORDS_ABCD), "abcd");
    assert_string_equal(pfd_word_order_name(PFD_WORDS_CDAB), "cdab");
}

/* A write of q = 0.8 decodes to 0.8 in the order it was packed in; the
 * other order reads other bits (here a value out of q's range, refused). */
static void decode_in_each_order(void **state)
{
    const unsigned addr = pfd_reg_named(PFD_HOLD, "q")->addr;
    pfd_wlist wl;
    uint16_t w[2];
    int order;
    (void)state;
    for (order = 0; order < PFD_WORDS_COUNT; order++) {
        pfd_f32_pack(0.8f, order, w);
        assert_int_equal(pfd_regmap_decode(addr, 2, w, order, &wl), 0);
        assert_int_equal(wl.n, 1);
        assert_true(wl.w[0].v == (double)0.8f);
        assert_int_equal(pfd_regmap_decode(addr, 2, w, !order, &wl),
                         MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE);
    }
}

/* Decode one f32 write of @p f to @p r: 0 and the decoded value, or the
 * exception. */
static int decode_f32(const pfd_reg *r, float f, double *v)
{
    pfd_wlist wl;
    uint16_t w[2];
    int rc;
    pfd_f32_pack(f, PFD_WORDS_ABCD, w);
    rc = pfd_regmap_decode(r->addr, 2, w, PFD_WORDS_ABCD, &wl);
    if (rc == 0)
        *v = wl.w[0].v;
    return rc;
}

/* Each closed end of every writable float register's documented range can
 * be written: where rounding to float puts the end outside the range (1e-9
 * is 9.99999972e-10 as a float), that float decodes to the end itself;
 * where it lands inside (1e12 is 999999995904), it decodes unchanged; the
 * next float outward is refused. An open end is refused and the next float
 * inward decodes unchanged. */
static void range_ends_writable(void **state)
{
    unsigned i, snapped = 0, ends = 0;
    (void)state;
    for (i = 0; i < pfd_nregs; i++) {
        const pfd_reg *r = &pfd_regs[i];
        const double end[2] = {pfd_reg_min(r), pfd_reg_max(r)};
        int k;
        if (r->space != PFD_HOLD || r->type != PFD_T_F32 || r->access == PFD_R)
            continue;
        for (k = 0; k < 2; k++) {
            const float f = (float)end[k];
            const float out = nextafterf(f, k == 0 ? -INFINITY : INFINITY);
            const float in = nextafterf(f, k == 0 ? INFINITY : -INFINITY);
            const int inside = k == 0 ? (double)f >= end[k] : (double)f <= end[k];
            double v = 0.0;
            if (k == 0 && pfd_reg_min_excl(r)) {
                assert_int_equal(decode_f32(r, f, &v), MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE);
                assert_int_equal(decode_f32(r, in, &v), 0);
                assert_true(v == (double)in);
                continue;
            }
            assert_int_equal(decode_f32(r, f, &v), 0);
            assert_true(v == (inside ? (double)f : end[k]));
            snapped += !inside;
            assert_int_equal(decode_f32(r, out, &v), MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE);
            ends++;
        }
    }
    assert_true(snapped > 0 && ends > snapped);
}

/* A float inside the range keeps its bits: -0 written to a register whose
 * closed lower end is 0 stays -0. */
static void negative_zero_kept(void **state)
{
    double v = 1.0;
    (void)state;
    assert_int_equal(decode_f32(pfd_reg_named(PFD_HOLD, "bump_tau"), -0.0f, &v), 0);
    assert_true(v == 0.0 && signbit(v));
}

/* Every 32-bit register of a rendered image swaps its two words, and
 * nothing else changes. */
static void render_in_each_order(void **state)
{
    static pfd_inst in;
    pfd_hold h;
    pfd_snap s;
    pfd_view v;
    uint16_t abcd[PFD_INPUT_SIZE], cdab[PFD_INPUT_SIZE];
    unsigned i, swapped = 0;
    (void)state;
    memset(&in, 0, sizeof in);
    memset(&h, 0, sizeof h);
    memset(&s, 0, sizeof s);
    pfd_iparams_default(&in.committed);
    in.unit = 1;
    s.sig.pc = 0.25f;
    s.samples = 0x00010002u;
    v.inst = &in;
    v.hold = &h;
    v.snap = &s;
    v.status = 1;
    v.n_instances = 1;
    v.word_order = PFD_WORDS_ABCD;
    pfd_regmap_render(PFD_INPUT, &v, abcd);
    v.word_order = PFD_WORDS_CDAB;
    pfd_regmap_render(PFD_INPUT, &v, cdab);
    assert_int_equal(abcd[pfd_reg_named(PFD_INPUT, "pc")->addr], 0x3E80);
    assert_int_equal(cdab[pfd_reg_named(PFD_INPUT, "pc")->addr + 1], 0x3E80);
    assert_int_equal(cdab[pfd_reg_named(PFD_INPUT, "samples")->addr], 0x0002);
    for (i = 0; i < pfd_nregs; i++) {
        const pfd_reg *r = &pfd_regs[i];
        if (r->space != PFD_INPUT)
            continue;
        if (pfd_type_words(r->type) == 2) {
            assert_int_equal(abcd[r->addr], cdab[r->addr + 1]);
            assert_int_equal(abcd[r->addr + 1], cdab[r->addr]);
            swapped += abcd[r->addr] != abcd[r->addr + 1];
        } else {
            assert_int_equal(abcd[r->addr], cdab[r->addr]);
        }
    }
    assert_true(swapped >= 3); /* pc, samples, committed fs at least */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(known_words),
        cmocka_unit_test(decode_in_each_order),
        cmocka_unit_test(range_ends_writable),
        cmocka_unit_test(negative_zero_kept),
        cmocka_unit_test(render_in_each_order),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
