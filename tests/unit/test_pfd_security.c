/* SPDX-License-Identifier: MIT */
/*
 * The pure parts of pneufracd's defences (port/posix): who gets a client
 * slot (pfd_slots.c), certificate roles and the access a write needs
 * (pfd_access.c), per-client staging (pfd_stage.c), and the settings a
 * fallback run uses (pfd_settings_fallback): every security setting is at
 * least as strict as its default, whatever the file said.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <string.h>

#include "pfd_access.h"
#include "pfd_regmap.h"
#include "pfd_settings.h"
#include "pfd_slots.h"
#include "pfd_stage.h"
#include "pfd_tls.h"

#define MS 1000000LL

static pfd_slot_view slot(uint32_t addr, int active, int heard, int64_t since_ms)
{
    pfd_slot_view v;
    memset(&v, 0, sizeof v);
    v.in_use = 1;
    v.addr = addr;
    v.active = active;
    v.heard = heard;
    v.since_ns = since_ms * MS;
    return v;
}

/* The table of the policy tests: 8 slots, at most 4 clients and 8 per
 * address, a newcomer from address 9 at t = 10 s; an active client is
 * protected for 2 s after its last request. */
static pfd_slot_choice choose(const pfd_slot_view *v)
{
    return pfd_slots_choose(v, 8, 9, 4, 8, 10000 * MS, 2000 * MS);
}

/* The policy picks `victim` (choose); it is evicted, and the newcomer it
 * made room for takes slot `at`. */
static void evict(pfd_slot_view *v, int victim, int at, pfd_slot_view newcomer)
{
    assert_int_equal(choose(v).victim, victim);
    v[victim].evicted = 1;
    v[at] = newcomer;
}

static void slots_free_table(void **state)
{
    pfd_slot_view v[4];
    pfd_slot_choice c;
    (void)state;
    memset(v, 0, sizeof v);
    v[0] = slot(1, 1, 1, 0);
    c = pfd_slots_choose(v, 4, 2, 2, 8, 10 * MS, 2000 * MS);
    assert_int_equal(c.slot, 1);
    assert_int_equal(c.victim, -1);
}

static void slots_full_table_order(void **state)
{
    pfd_slot_view v[8];
    pfd_slot_choice c;
    (void)state;
    memset(v, 0, sizeof v);
    v[0] = slot(1, 1, 1, 0);    /* active, idle 10 s */
    v[1] = slot(2, 0, 1, 9000); /* newcomer that spoke, oldest newcomer */
    v[2] = slot(3, 0, 0, 9500); /* silent newcomer */
    v[3] = slot(4, 0, 0, 9900); /* younger silent newcomer */
    /* 4 of 4 taken: the oldest silent newcomer goes first */
    c = choose(v);
    assert_int_equal(c.victim, 2);
    assert_int_equal(c.slot, 4);
    assert_string_equal(c.why, "max-clients");
    v[2].evicted = v[3].evicted = 1;
    v[4] = slot(5, 1, 1, 9990);
    v[5] = slot(6, 1, 1, 9990);
    /* then the newcomer that spoke */
    evict(v, 1, 6, slot(7, 1, 1, 9995));
    /* then the active client idle longest, once idle past the protection */
    assert_int_equal(choose(v).victim, 0);
    /* no one idle long enough: refused, nobody evicted */
    c = pfd_slots_choose(v, 8, 9, 4, 8, 10000 * MS, 20000 * MS);
    assert_int_equal(c.slot, -1);
    assert_int_equal(c.victim, -1);
    /* a busy one is never a victim */
    v[0].busy = 1;
    c = choose(v);
    assert_int_equal(c.slot, -1);
}

/* A complete request waiting unread makes no one a victim: not the oldest
 * newcomer that has spoken (a client whose first request its thread has
 * not read yet), not the client idle longest (its next poll came, the
 * thread is late). The others go in the usual order. */
static void slots_pending_request(void **state)
{
    pfd_slot_view v[8];
    pfd_slot_choice c;
    (void)state;
    memset(v, 0, sizeof v);
    v[0] = slot(1, 0, 1, 9000); /* first request waiting, oldest newcomer */
    v[0].pending = 1;
    v[1] = slot(2, 0, 1, 9500); /* half a header */
    v[2] = slot(3, 1, 1, 0);    /* active, idle 10 s, its poll waiting */
    v[2].pending = 1;
    v[3] = slot(4, 1, 1, 1000); /* active, idle 9 s */
    evict(v, 1, 4, slot(5, 1, 1, 9990));
    evict(v, 3, 5, slot(6, 1, 1, 9995));
    /* only pending and protected ones left: refused */
    c = choose(v);
    assert_int_equal(c.slot, -1);
    assert_int_equal(c.victim, -1);
    /* the same within one address */
    c = pfd_slots_choose(v, 8, 1, 16, 1, 10000 * MS, 2000 * MS);
    assert_int_equal(c.victim, -1);
    v[0].pending = 0;
    c = pfd_slots_choose(v, 8, 1, 16, 1, 10000 * MS, 2000 * MS);
    assert_int_equal(c.victim, 0);
}

/* What a look at a socket means (pfd_slots_pending()). Plain TCP: a whole
 * frame waiting, unless the thread's count moved (it is serving). TLS:
 * never during the handshake (a ClientHello is anyone's, and a TLS 1.3
 * Finished has the outer type of application data); past it, a whole
 * application-data record, and a count that moved during the look even
 * with nothing whole waiting (the thread took a record that may have left
 * it part of a frame, the rest whole behind it). */
static void slots_pending_look(void **state)
{
    (void)state;
    /* tls, up, moved, whole, app_data */
    assert_int_equal(pfd_slots_pending(0, 0, 0, 1, 0), 1);
    assert_int_equal(pfd_slots_pending(0, 0, 1, 1, 0), 0);
    assert_int_equal(pfd_slots_pending(0, 0, 0, 0, 0), 0);
    assert_int_equal(pfd_slots_pending(1, 1, 0, 1, 1), 1);
    assert_int_equal(pfd_slots_pending(1, 1, 1, 0, 0), 1);
    assert_int_equal(pfd_slots_pending(1, 1, 0, 1, 0), 0);
    assert_int_equal(pfd_slots_pending(1, 1, 0, 0, 1), 0);
    assert_int_equal(pfd_slots_pending(1, 0, 0, 1, 1), 0);
    assert_int_equal(pfd_slots_pending(1, 0, 1, 1, 1), 0);
}

/* The record header the TLS shield reads (pfd_server.c, unread()): the
 * whole length from the header's last two bytes, and none beyond what TLS
 * allows (a record the session would refuse is never whole). */
static void tls_record_header(void **state)
{
    const unsigned char app[PFD_TLS_HDR] = {PFD_TLS_APP_DATA, 3, 3, 0x00, 0x20};
    const unsigned char empty[PFD_TLS_HDR] = {PFD_TLS_APP_DATA, 3, 3, 0, 0};
    const unsigned char most[PFD_TLS_HDR] = {PFD_TLS_APP_DATA, 3, 3, 0x48, 0x00};
    const unsigned char over[PFD_TLS_HDR] = {PFD_TLS_APP_DATA, 3, 3, 0x48, 0x01};
    const unsigned char junk[PFD_TLS_HDR] = {0, 0, 0, 0xFF, 0xFF};
    (void)state;
    assert_int_equal(pfd_tls_record_length(app), 5 + 32);
    assert_int_equal(pfd_tls_record_length(empty), 5);
    assert_int_equal(pfd_tls_record_length(most), 5 + 16384 + 2048);
    assert_int_equal(pfd_tls_record_length(over), -1);
    assert_int_equal(pfd_tls_record_length(junk), -1);
}

static void slots_per_address(void **state)
{
    pfd_slot_view v[8];
    pfd_slot_choice c;
    (void)state;
    memset(v, 0, sizeof v);
    v[0] = slot(7, 1, 1, 100);
    v[1] = slot(7, 1, 1, 50); /* address 7, idle longer */
    v[2] = slot(8, 0, 0, 0);  /* someone else's silent newcomer: not touched */
    /* a third from address 7 replaces address 7's own idle one */
    c = pfd_slots_choose(v, 8, 7, 16, 2, 3000 * MS, 2000 * MS);
    assert_int_equal(c.victim, 1);
    assert_string_equal(c.why, "max-clients-per-addr");
    /* but not a poller, idle for less than the protection time: refused */
    c = pfd_slots_choose(v, 8, 7, 16, 2, 200 * MS, 2000 * MS);
    assert_int_equal(c.slot, -1);
    assert_int_equal(c.victim, -1);
    /* a newcomer of its own goes first, however young */
    v[0] = slot(7, 0, 1, 190);
    c = pfd_slots_choose(v, 8, 7, 16, 2, 200 * MS, 2000 * MS);
    assert_int_equal(c.victim, 0);
    /* a connection whose thread has ended does not count */
    v[0].evicted = 1;
    c = pfd_slots_choose(v, 8, 7, 16, 2, 200 * MS, 2000 * MS);
    assert_int_equal(c.victim, -1);
    assert_true(c.slot >= 3);
    /* another address is unaffected */
    v[0].evicted = 0;
    c = pfd_slots_choose(v, 8, 9, 16, 2, 200 * MS, 2000 * MS);
    assert_int_equal(c.victim, -1);
    assert_true(c.slot >= 3);
}

static void roles(void **state)
{
    pfd_roles r;
    char err[200];
    (void)state;
    assert_int_equal(pfd_roles_parse("viewer:read, operator:operate,eng:engineer,x:none", &r,
                                     err, sizeof err), 0);
    assert_int_equal(r.n, 4);
    assert_int_equal(pfd_roles_lookup(&r, "viewer"), PFD_ACCESS_READ);
    assert_int_equal(pfd_roles_lookup(&r, "operator"), PFD_ACCESS_OPERATE);
    assert_int_equal(pfd_roles_lookup(&r, "eng"), PFD_ACCESS_ENGINEER);
    assert_int_equal(pfd_roles_lookup(&r, "x"), PFD_ACCESS_NONE);
    assert_int_equal(pfd_roles_lookup(&r, "Viewer"), -1);
    assert_int_equal(pfd_roles_parse("", &r, err, sizeof err), 0);
    assert_int_equal(r.n, 0);
    {
        static const char *const bad[] = {"viewer", "viewer:", ":read", "a:read,",
                                          "a:read,a:operate", "a:god", "a b:read",
                                          "a:read;b:read", "a:readx"};
        unsigned i;
        for (i = 0; i < sizeof bad / sizeof bad[0]; i++)
            if (pfd_roles_parse(bad[i], &r, err, sizeof err) == 0)
                fail_msg("accepted '%s'", bad[i]);
    }
}

/* The access a write needs comes from the register table: the process
 * inputs, mode, manual output and tick for operators, the rest for
 * engineers; only the process inputs and tick stay open under a lock. */
static void access_per_register(void **state)
{
    static const char *const operate[] = {"e", "sp", "pv", "e_i16", "sp_i16", "pv_i16",
                                          "input_sel", "mode", "manual_out", "tick"};
    static const char *const open_[] = {"e", "sp", "pv", "e_i16", "sp_i16", "pv_i16", "tick"};
    unsigned i, j;
    (void)state;
    for (i = 0; i < pfd_nregs; i++) {
        const pfd_reg *r = &pfd_regs[i];
        int want_op = 0, want_open = 0;
        if (r->space != PFD_HOLD || r->access == PFD_R)
            continue;
        for (j = 0; j < sizeof operate / sizeof operate[0]; j++)
            want_op |= !strcmp(r->name, operate[j]);
        for (j = 0; j < sizeof open_ / sizeof open_[0]; j++)
            want_open |= !strcmp(r->name, open_[j]);
        assert_int_equal(pfd_access_to_write(r),
                         want_op ? PFD_ACCESS_OPERATE : PFD_ACCESS_ENGINEER);
        assert_int_equal((r->flags & PFD_F_OPEN) != 0, want_open);
    }
}

static void staging(void **state)
{
    pfd_iparams committed, out;
    pfd_stage st;
    pfd_wlist wl;
    uint16_t w[2];
    (void)state;
    pfd_iparams_default(&committed);
    memset(&st, 0, sizeof st);
    assert_false(pfd_stage_any(&st));
    pfd_f32_pack(0.5f, PFD_WORDS_ABCD, w);
    assert_int_equal(
        pfd_regmap_decode(pfd_reg_named(PFD_HOLD, "q")->addr, 2, w, PFD_WORDS_ABCD, &wl), 0);
    pfd_stage_record(&st, &wl);
    assert_true(pfd_stage_any(&st));
    /* The committed set changes meanwhile (another client's commit): the
     * staged q goes on top of it, the other change is kept. */
    committed.p.k2 = 0.3;
    pfd_stage_compose(&st, NULL, &committed, &out);
    assert_true(out.p.q == (double)0.5f && out.p.k2 == 0.3);
    /* A live write is not staged. */
    pfd_f32_pack(1.0f, PFD_WORDS_ABCD, w);
    assert_int_equal(
        pfd_regmap_decode(pfd_reg_named(PFD_HOLD, "e")->addr, 2, w, PFD_WORDS_ABCD, &wl), 0);
    memset(&st, 0, sizeof st);
    pfd_stage_record(&st, &wl);
    assert_false(pfd_stage_any(&st));
    /* Nothing staged: the committed set. */
    pfd_stage_compose(NULL, NULL, &committed, &out);
    assert_memory_equal(&out, &committed, sizeof out);
}

/* A fallback run: read-only and locked, and no security setting weaker
 * than its default (the file it could not use gives nothing). */
static void fallback_settings(void **state)
{
    pfd_settings def, fb;
    unsigned i;
    (void)state;
    pfd_settings_default(&def);
    pfd_settings_fallback(&fb);
    assert_int_equal(fb.read_only, 1);
    assert_int_equal(fb.param_lock, 1);
    for (i = 0; i < pfd_settings_count; i++) {
        const pfd_setting *r = &pfd_settings_table[i];
        char a[600], b[600], msg[200];
        if (!(r->flags & PFD_SF_SECURE))
            continue;
        assert_true(r->group == PFD_SG_DAEMON);
        pfd_setting_format(r, &fb, NULL, b, sizeof b);
        if (r->fallback != NULL) {
            pfd_settings t = def;
            assert_int_equal(pfd_setting_parse(r, r->fallback, &t, NULL, msg, sizeof msg), 0);
            pfd_setting_format(r, &t, NULL, a, sizeof a);
        } else {
            pfd_setting_format(r, &def, NULL, a, sizeof a);
        }
        assert_string_equal(a, b);
    }
    /* These are the security settings, and no others (the list
     * docs/pneufracd.md gives). */
    {
        static const char *const keys[] = {
            "listen", "max_clients", "allow", "read_only", "param_lock",
            "byte_timeout_ms", "idle_timeout_s", "max_clients_per_addr",
            "first_request_timeout_ms", "plain_access", "tls_listen", "tls_cert",
            "tls_key", "tls_ca", "tls_roles", "loop_budget"};
        const unsigned n_keys = sizeof keys / sizeof keys[0];
        unsigned n_secure = 0;
        for (i = 0; i < n_keys; i++)
            assert_true(pfd_setting_by_key(keys[i])->flags & PFD_SF_SECURE);
        for (i = 0; i < pfd_settings_count; i++)
            n_secure += (pfd_settings_table[i].flags & PFD_SF_SECURE) != 0;
        assert_int_equal(n_secure, n_keys);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(slots_free_table),
        cmocka_unit_test(slots_full_table_order),
        cmocka_unit_test(slots_per_address),
        cmocka_unit_test(slots_pending_request),
        cmocka_unit_test(slots_pending_look),
        cmocka_unit_test(tls_record_header),
        cmocka_unit_test(roles),
        cmocka_unit_test(access_per_register),
        cmocka_unit_test(staging),
        cmocka_unit_test(fallback_settings),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
