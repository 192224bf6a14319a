/* SPDX-License-Identifier: MIT */
/*
 * pneufracd's settings table (port/posix/pfd_settings.c) and the command
 * line read through it (pfd_cli.c): every row is complete and consistent,
 * every default reads back as itself, and parsing refuses what is out of
 * range or not a value at all, leaving the field as it was.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pfd_cli.h"
#include "pneufrac/pneufrac.h"

static void *field_of(const pfd_setting *r, pfd_settings *s, pfd_run *run)
{
    return (char *)(r->group == PFD_SG_DAEMON ? (void *)s : (void *)run) + r->off;
}

static void rows_are_complete(void **state)
{
    unsigned i, j;
    (void)state;
    /* One bit each in a pfd_mask (pfd_setting_bit). */
    assert_true(pfd_settings_count > 0 && pfd_settings_count <= 8 * sizeof(pfd_mask));
    for (i = 0; i < pfd_settings_count; i++) {
        const pfd_setting *r = &pfd_settings_table[i];
        const size_t whole = r->group == PFD_SG_DAEMON ? sizeof(pfd_settings) : sizeof(pfd_run);
        assert_non_null(r->flag);
        assert_true(strncmp(r->flag, "--", 2) == 0 && strlen(r->flag) > 2);
        assert_non_null(r->help);
        assert_true(strlen(r->help) > 0);
        assert_true(r->group < PFD_SG_COUNT);
        /* Daemon-wide settings, and only they, are config keys. */
        assert_int_equal(r->key != NULL, r->group == PFD_SG_DAEMON);
        assert_true(r->off + r->size <= whole);
        assert_int_equal(r->choice != NULL, r->type == PFD_ST_CHOICE);
        if (r->type == PFD_ST_INT || r->type == PFD_ST_REAL || r->type == PFD_ST_CHOICE)
            assert_true(r->lo <= r->hi);
        if (r->type == PFD_ST_CHOICE)
            assert_true(r->lo == 0 && r->hi >= 1);
        if (pfd_setting_takes_value(r) && r->type != PFD_ST_CHOICE)
            assert_non_null(r->metavar);
        if (r->type == PFD_ST_BOOL)
            assert_true(r->flag_value == 0 || r->flag_value == 1);
        for (j = 0; j < i; j++) {
            const pfd_setting *o = &pfd_settings_table[j];
            assert_string_not_equal(r->flag, o->flag);
            if (r->key != NULL && o->key != NULL)
                assert_string_not_equal(r->key, o->key);
        }
        assert_ptr_equal(pfd_setting_by_flag(r->flag), r);
        if (r->alias != NULL)
            assert_ptr_equal(pfd_setting_by_flag(r->alias), r);
        if (r->key != NULL)
            assert_ptr_equal(pfd_setting_by_key(r->key), r);
    }
}

/* A config key and its flag are the same word: max_clients and
 * --max-clients, or mlock and --no-mlock for a flag that turns it off. */
static void flags_spell_their_keys(void **state)
{
    unsigned i;
    (void)state;
    for (i = 0; i < pfd_settings_count; i++) {
        const pfd_setting *r = &pfd_settings_table[i];
        char want[64];
        size_t k;
        if (r->key == NULL)
            continue;
        snprintf(want, sizeof want, "--%s%s",
                 r->type == PFD_ST_BOOL && r->flag_value == 0 ? "no-" : "", r->key);
        for (k = 0; want[k] != '\0'; k++)
            if (want[k] == '_')
                want[k] = '-';
        assert_string_equal(r->flag, want);
    }
}

/* Every default, written out, reads back as the same value. */
static void defaults_read_back(void **state)
{
    pfd_settings s0, s1;
    pfd_run run0, run1;
    unsigned i;
    (void)state;
    pfd_settings_default(&s0);
    pfd_run_default(&run0);
    for (i = 0; i < pfd_settings_count; i++) {
        const pfd_setting *r = &pfd_settings_table[i];
        char text[600], msg[300];
        if (r->type == PFD_ST_PATH)
            continue;
        memset(&s1, 0x55, sizeof s1);
        memset(&run1, 0x55, sizeof run1);
        pfd_setting_format(r, &s0, &run0, text, sizeof text);
        if (r->flags & PFD_SF_NODEF)
            continue; /* "off", outside the range on purpose */
        if (pfd_setting_parse(r, text, &s1, &run1, msg, sizeof msg) != 0)
            fail_msg("%s: default '%s' does not parse: %s", r->flag, text, msg);
        if (r->type == PFD_ST_NETS || r->type == PFD_ST_ENDPOINT || r->type == PFD_ST_FILE ||
            r->type == PFD_ST_ROLES) {
            /* text fields: what follows the string's end is not the value */
            char again[600];
            pfd_setting_format(r, &s1, &run1, again, sizeof again);
            assert_string_equal(again, text);
        } else {
            assert_memory_equal(field_of(r, &s1, &run1), field_of(r, &s0, &run0), r->size);
        }
    }
}

static int parses(const pfd_setting *r, const char *text)
{
    pfd_settings s;
    pfd_run run;
    char before[600], msg[300];
    int rc;
    pfd_settings_default(&s);
    pfd_run_default(&run);
    memcpy(before, field_of(r, &s, &run), r->size);
    rc = pfd_setting_parse(r, text, &s, &run, msg, sizeof msg);
    if (rc != 0) {
        /* Refused: the message quotes the text, and nothing changed. */
        assert_memory_equal(before, field_of(r, &s, &run), r->size);
        if (r->type != PFD_ST_NETS)
            assert_non_null(strstr(msg, text));
    }
    return rc == 0;
}

/* Each number row takes its bounds, and refuses what lies past them and
 * what is no number. */
static void numbers_in_range_only(void **state)
{
    static const char *const junk[] = {"", "x", "1x", " 1", "1 ", "0x10", "nan", "inf",
                                       "-inf", "1e400", "1,5", "--1", "1e", "+"};
    unsigned i, j;
    (void)state;
    for (i = 0; i < pfd_settings_count; i++) {
        const pfd_setting *r = &pfd_settings_table[i];
        char t[64];
        if (r->type != PFD_ST_INT && r->type != PFD_ST_REAL)
            continue;
        snprintf(t, sizeof t, "%.17g", r->lo);
        assert_true(parses(r, t));
        snprintf(t, sizeof t, "%.17g", r->hi);
        assert_true(parses(r, t));
        snprintf(t, sizeof t, "%.17g", r->type == PFD_ST_INT ? r->lo - 1 : r->lo - (r->lo > 0 ? r->lo / 2 : 1));
        assert_false(parses(r, t));
        snprintf(t, sizeof t, "%.17g", r->type == PFD_ST_INT ? r->hi + 1 : r->hi * 2 + 1);
        assert_false(parses(r, t));
        for (j = 0; j < sizeof junk / sizeof junk[0]; j++)
            if (parses(r, junk[j]))
                fail_msg("%s accepted '%s'", r->flag, junk[j]);
        if (r->type == PFD_ST_INT && r->lo < r->hi) {
            snprintf(t, sizeof t, "%.17g", r->lo + 0.5);
            assert_false(parses(r, t));
        }
    }
}

static void choices_by_name_only(void **state)
{
    unsigned i;
    int v;
    (void)state;
    for (i = 0; i < pfd_settings_count; i++) {
        const pfd_setting *r = &pfd_settings_table[i];
        pfd_settings s;
        pfd_run run;
        char msg[300];
        if (r->type != PFD_ST_CHOICE)
            continue;
        pfd_settings_default(&s);
        pfd_run_default(&run);
        for (v = 0; v <= (int)r->hi; v++) {
            assert_int_equal(pfd_setting_parse(r, r->choice(v), &s, &run, msg, sizeof msg), 0);
            assert_int_equal(*(int *)field_of(r, &s, &run), v);
        }
        assert_false(parses(r, "bogus"));
        assert_false(parses(r, ""));
        assert_false(parses(r, "0"));
        /* The refusal names every choice. */
        assert_int_not_equal(pfd_setting_parse(r, "bogus", &s, &run, msg, sizeof msg), 0);
        for (v = 0; v <= (int)r->hi; v++)
            assert_non_null(strstr(msg, r->choice(v)));
    }
}

static void bools_and_bare_flags(void **state)
{
    const pfd_setting *r = pfd_setting_by_key("mlock");
    pfd_settings s;
    char msg[300];
    (void)state;
    assert_non_null(r);
    pfd_settings_default(&s);
    assert_int_equal(s.mlock, 1);
    assert_int_equal(pfd_setting_parse(r, NULL, &s, NULL, msg, sizeof msg), 0);
    assert_int_equal(s.mlock, 0); /* --no-mlock */
    assert_int_equal(pfd_setting_parse(r, "on", &s, NULL, msg, sizeof msg), 0);
    assert_int_equal(s.mlock, 1);
    assert_int_equal(pfd_setting_parse(r, "false", &s, NULL, msg, sizeof msg), 0);
    assert_int_equal(s.mlock, 0);
    assert_false(parses(r, "maybe"));
    assert_false(parses(r, "YES"));
    assert_false(parses(r, ""));
}

static void addresses(void **state)
{
    const pfd_setting *listen = pfd_setting_by_key("listen");
    const pfd_setting *allow = pfd_setting_by_key("allow");
    char longlist[600];
    (void)state;
    assert_true(parses(listen, "127.0.0.1:1502"));
    assert_true(parses(listen, "0.0.0.0:0"));
    assert_true(parses(listen, "10.1.2.3:65535"));
    assert_false(parses(listen, "localhost:1502"));
    assert_false(parses(listen, "1.2.3.4"));
    assert_false(parses(listen, "1.2.3.4:"));
    assert_false(parses(listen, ":80"));
    assert_false(parses(listen, "1.2.3.4:65536"));
    assert_false(parses(listen, "1.2.3.4:-1"));
    assert_false(parses(listen, "1.2.3:80"));
    assert_false(parses(listen, "1.2.3.4:80x"));
    assert_true(parses(allow, "10.0.0.0/8, 127.0.0.1"));
    assert_true(parses(allow, "0.0.0.0/0"));
    assert_false(parses(allow, "10.0.0.0/33"));
    assert_false(parses(allow, "10.0.0.0/"));
    assert_false(parses(allow, "10.0.0.0/-1"));
    assert_false(parses(allow, "10.0.0.0,,10.0.0.1"));
    assert_false(parses(allow, "a.b.c.d"));
    memset(longlist, '1', sizeof longlist - 1);
    longlist[sizeof longlist - 1] = '\0';
    assert_false(parses(allow, longlist));
}

static int cli(pfd_cli *a, char *err, size_t n, ...)
{
    char *argv[32];
    int argc = 0;
    va_list ap;
    argv[argc++] = (char *)"pneufracd";
    va_start(ap, n);
    while ((argv[argc] = va_arg(ap, char *)) != NULL)
        argc++;
    va_end(ap);
    err[0] = '\0';
    return pfd_cli_parse(argc, argv, a, err, n);
}

static void command_line(void **state)
{
    pfd_cli a;
    pfd_settings merged;
    char err[400];
    (void)state;

    assert_int_equal(cli(&a, err, sizeof err, "--listen", "0.0.0.0:502", "--no-mlock",
                         "--clock", "external", "--fs", "2500", "--controller", "pid",
                         "-h", "--bogus", NULL), 0);
    assert_string_equal(a.set.listen.addr, "0.0.0.0");
    assert_int_equal(a.set.listen.port, 502);
    assert_int_equal(a.set.mlock, 0);
    assert_int_equal(a.set.external_clock, 1);
    assert_true(a.run.fs == 2500.0);
    assert_int_equal(a.run.controller, PF_TOPO_PID);
    assert_int_equal(a.run.help, 1); /* and parsing stopped there */
    assert_int_equal(a.given, pfd_setting_bit(pfd_setting_by_key("listen")) |
                                  pfd_setting_bit(pfd_setting_by_key("mlock")) |
                                  pfd_setting_bit(pfd_setting_by_key("clock")) |
                                  pfd_setting_bit(pfd_setting_by_flag("--fs")) |
                                  pfd_setting_bit(pfd_setting_by_flag("--controller")) |
                                  pfd_setting_bit(pfd_setting_by_flag("--help")));

    /* Only the settings given override a file's. */
    pfd_settings_default(&merged);
    merged.max_clients = 7;
    merged.mlock = 1;
    pfd_settings_copy(&merged, &a.set, a.given);
    assert_int_equal(merged.max_clients, 7);
    assert_int_equal(merged.mlock, 0);
    assert_int_equal(merged.listen.port, 502);

    assert_int_equal(cli(&a, err, sizeof err, "--max-clients", "0", NULL), -1);
    assert_string_equal(err, "--max-clients: '0' is not an integer in 1..256");
    assert_int_equal(cli(&a, err, sizeof err, "--max-clients", NULL), -1);
    assert_string_equal(err, "--max-clients needs a value");
    assert_int_equal(cli(&a, err, sizeof err, "--bogus", NULL), -1);
    assert_non_null(strstr(err, "unknown option '--bogus'"));
    assert_int_equal(cli(&a, err, sizeof err, "--config", "x.conf", "--arith", "q15", NULL), -1);
    assert_non_null(strstr(err, "with --config"));
    assert_int_equal(cli(&a, err, sizeof err, "--config-fallback-defaults", NULL), -1);
    assert_non_null(strstr(err, "needs --config"));
    assert_int_equal(cli(&a, err, sizeof err, "--config", "x.conf",
                         "--config-fallback-defaults", "--read-only", NULL), 0);
    assert_string_equal(a.run.config, "x.conf");
    assert_int_equal(a.run.fallback, 1);
    assert_int_equal(a.set.read_only, 1);
}

/* --help names every flag, and shows each default as it parses. */
static void help_lists_every_row(void **state)
{
    char *text = NULL;
    size_t n = 0;
    FILE *f = open_memstream(&text, &n);
    unsigned i;
    (void)state;
    assert_non_null(f);
    pfd_cli_help(f);
    assert_int_equal(fclose(f), 0);
    for (i = 0; i < pfd_settings_count; i++) {
        const pfd_setting *r = &pfd_settings_table[i];
        char want[80];
        snprintf(want, sizeof want, "  %s", r->flag);
        if (strstr(text, want) == NULL)
            fail_msg("--help does not list %s", r->flag);
        if (r->key != NULL) {
            snprintf(want, sizeof want, "[%s", r->key);
            assert_non_null(strstr(text, want));
        }
    }
    assert_non_null(strstr(text, "(1..256; default 16)"));
    free(text);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(rows_are_complete),
        cmocka_unit_test(flags_spell_their_keys),
        cmocka_unit_test(defaults_read_back),
        cmocka_unit_test(numbers_in_range_only),
        cmocka_unit_test(choices_by_name_only),
        cmocka_unit_test(bools_and_bare_flags),
        cmocka_unit_test(addresses),
        cmocka_unit_test(command_line),
        cmocka_unit_test(help_lists_every_row),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
