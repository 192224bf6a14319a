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

/* Each end of every float register's documented range can be written:
 * the float nearest an end (1e-9 is 9.99999972e-10 as a float) decodes to
 * the end itself, which the range check accepts (an open end stays
 * refused); the next float outward is refused. */
static void range_ends_writable(void **state)
{
    unsigned i, ends = 0;
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
            pfd_wlist wl;
            uint16_t w[2];
            if (!isfinite(f) || (k == 0 && pfd_reg_min_excl(r)))
                continue;
            pfd_f32_pack(f, PFD_WORDS_ABCD, w);
            assert_int_equal(pfd_regmap_decode(r->addr, 2, w, PFD_WORDS_ABCD, &wl), 0);
            assert_true(wl.w[0].v == end[k]);
            pfd_f32_pack(out, PFD_WORDS_ABCD, w);
            assert_int_equal(pfd_regmap_decode(r->addr, 2, w, PFD_WORDS_ABCD, &wl),
                             MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE);
            ends++;
        }
    }
    assert_true(ends >= 20);
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
        cmocka_unit_test(render_in_each_order),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
