/* SPDX-License-Identifier: MIT */
/*
 * pneufracd's config file below the daemon (port/posix): the sealed text
 * format (pfd_ini.c), the keys and their ranges, and a write that reads
 * back as the same configuration and rewrites to the same bytes
 * (pfd_config.c, pfd_file.c).
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "pfd_config.h"
#include "pfd_ini.h"
#include "pfd_regmap.h"

static char dir[64];

static int make_dir(void **state)
{
    (void)state;
    strcpy(dir, "/tmp/pfd_config_XXXXXX");
    return mkdtemp(dir) == NULL ? -1 : 0;
}

static int remove_dir(void **state)
{
    char cmd[128];
    (void)state;
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    return system(cmd) == 0 ? 0 : -1;
}

static const char *path_of(const char *name)
{
    static char p[128];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    return p;
}

static void put(const char *name, const char *text)
{
    FILE *f = fopen(path_of(name), "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(text, 1, strlen(text), f), strlen(text));
    assert_int_equal(fclose(f), 0);
}

static char *slurp(const char *name)
{
    FILE *f = fopen(path_of(name), "rb");
    char *b = calloc(1, 1 << 16);
    assert_non_null(f);
    assert_non_null(b);
    assert_true(fread(b, 1, (1 << 16) - 1, f) < (1 << 16) - 1);
    fclose(f);
    return b;
}

/* The standard check value of CRC-32/ISO-HDLC, and continuation. */
static void crc32_check_value(void **state)
{
    const unsigned char *s = (const unsigned char *)"123456789";
    (void)state;
    assert_int_equal(pfd_crc32(0, s, 9), 0xCBF43926ul);
    assert_int_equal(pfd_crc32(pfd_crc32(0, s, 4), s + 4, 5), 0xCBF43926ul);
    assert_int_equal(pfd_crc32(0, s, 0), 0);
}

typedef struct seen {
    int sections, keys;
    char last[64];
} seen;

static int on_section(pfd_ini *ini, void *ctx, const char *name)
{
    seen *s = (seen *)ctx;
    (void)ini;
    s->sections++;
    snprintf(s->last, sizeof s->last, "[%s]", name);
    return 0;
}

static int on_key(pfd_ini *ini, void *ctx, const char *k, const char *v)
{
    seen *s = (seen *)ctx;
    if (!strcmp(k, "refuse"))
        return pfd_ini_error(ini, "refused %s", v);
    s->keys++;
    snprintf(s->last, sizeof s->last, "%s=%s", k, v);
    return 0;
}

/* Parse @p body sealed (or as is); @return pfd_ini_parse()'s result. */
static int ini(const char *body, int seal, int need, seen *s, char *err, size_t n)
{
    pfd_ini_sink sink = {on_section, on_key, NULL};
    pfd_ini p = {"F", 0, NULL, 0};
    size_t len = strlen(body);
    char *text = seal ? pfd_ini_seal(body, len, &len) : strdup(body);
    int rc;
    assert_non_null(text);
    memset(s, 0, sizeof *s);
    sink.ctx = s;
    p.err = err;
    p.errlen = n;
    err[0] = '\0';
    rc = pfd_ini_parse(&p, text, len, need, &sink);
    free(text);
    return rc;
}

/* Text the parser refuses, and the message it gives. */
static const struct {
    const char *body;
    int seal, need;
    const char *err;
} bad[] = {
    {"[a]\nk = v\n", 0, 1, "config F: no checksum line"},
    {"[a]\nk = v", 0, 0, "config F:2: the file is truncated: its last line has no newline "
                        "(a hand edit without a final newline: add one)"},
    {"[a]\nk = v\nchecksum = 00000000\n", 0, 1, "config F:3: checksum mismatch"},
    {"[a]\nchecksum = 0000000g\n", 0, 0, "config F:2: checksum: '0000000g' is not 8 hex"},
    {"[a]\nchecksum = 00000000\nk = v\n", 0, 0, "config F:3: text after the checksum line"},
    {"[a\n", 1, 1, "config F:1: malformed section header '[a'"},
    {"[a]\nnovalue\n", 1, 1, "config F:2: expected 'key = value', got 'novalue'"},
    {"[a]\nk =\n", 1, 1, "config F:2: empty key or value"},
    {"[a]\n\nrefuse = it\n", 1, 1, "config F:3: refused it"},
};

static void ini_format(void **state)
{
    char err[400];
    unsigned i;
    seen s;
    (void)state;
    assert_int_equal(ini("# c\n; c\n\n[a]\n  k = v w \t\n[ b ]\nx=1\r\n", 1, 1, &s, err,
                         sizeof err), 0);
    assert_int_equal(s.sections, 2);
    assert_int_equal(s.keys, 2);
    assert_string_equal(s.last, "x=1");

    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        assert_int_equal(ini(bad[i].body, bad[i].seal, bad[i].need, &s, err, sizeof err), -1);
        if (strstr(err, bad[i].err) == NULL)
            fail_msg("'%s': got '%s', want '%s'", bad[i].body, err, bad[i].err);
    }
    assert_int_equal(ini("[a]\nk = v\n", 0, 0, &s, err, sizeof err), 0);

    /* A UTF-8 byte-order mark (Notepad's) starts the file, sealed or not:
     * the first line is the section, and the checksum covers the mark
     * (before: "expected 'key = value'", the mark read as part of it). */
    assert_int_equal(ini("\xEF\xBB\xBF[a]\nk = v\n", 1, 1, &s, err, sizeof err), 0);
    assert_int_equal(s.sections, 1);
    assert_string_equal(s.last, "k=v");
    assert_int_equal(ini("\xEF\xBB\xBF[a]\nk = v\n", 0, 0, &s, err, sizeof err), 0);
    {
        const char *body = "\xEF\xBB\xBF[a]\nk = v\n";
        size_t len;
        char *t = pfd_ini_seal(body, strlen(body), &len);
        pfd_ini_sink sink = {on_section, on_key, &s};
        pfd_ini p = {"F", 0, err, sizeof err};
        assert_non_null(t);
        /* the mark is sealed too: the file without it is caught */
        assert_int_equal(pfd_ini_parse(&p, t + 3, len - 3, 1, &sink), -1);
        assert_non_null(strstr(err, "checksum mismatch"));
        free(t);
    }

    /* A NUL byte is not text. */
    {
        char t[] = "[a]\nk = v\0w\n";
        pfd_ini_sink sink = {on_section, on_key, &s};
        pfd_ini p = {"F", 0, err, sizeof err};
        assert_int_equal(pfd_ini_parse(&p, t, sizeof t - 1, 0, &sink), -1);
        assert_non_null(strstr(err, "NUL"));
    }
}

/* Any byte changed before the checksum line is caught. */
static void every_byte_is_sealed(void **state)
{
    const char *body = "[a]\nk = 12345\n";
    size_t len = strlen(body), i;
    char *sealed = pfd_ini_seal(body, len, &len), err[400];
    seen s;
    (void)state;
    assert_non_null(sealed);
    for (i = 0; i < strlen(body); i++) {
        char *t = strdup(sealed);
        pfd_ini_sink sink = {on_section, on_key, &s};
        pfd_ini p = {"F", 0, err, sizeof err};
        assert_non_null(t);
        /* change the byte: flip a bit, or make a newline or bracket a space */
        t[i] = t[i] == '\n' || t[i] == '[' || t[i] == ']' ? ' ' : (char)(t[i] ^ 0x01);
        assert_int_equal(pfd_ini_parse(&p, t, len, 1, &sink), -1);
        free(t);
    }
    free(sealed);
}

static pfd_config *load(const char *name, const char *text, char *err, size_t n)
{
    static pfd_config c;
    put(name, text);
    return pfd_config_load(path_of(name), &c, 0, err, n) == 0 ? &c : NULL;
}

/* A register of a library parameter has the parameter's name (the config
 * key and the register name are the library's), staged and committed. */
static void parameter_registers_have_library_names(void **state)
{
    char want[64];
    unsigned i;
    int staged = 0, committed = 0;
    (void)state;
    for (i = 0; i < pfd_nregs; i++) {
        const pfd_reg *r = &pfd_regs[i];
        if (r->param == PFD_NO_PARAM)
            continue;
        snprintf(want, sizeof want, "%s%s", r->space == PFD_HOLD ? "" : "committed_",
                 pf_param_name((pf_param_id)r->param));
        assert_string_equal(r->name, want);
        assert_true(pf_param_info((pf_param_id)r->param) != NULL);
        staged += r->space == PFD_HOLD;
        committed += r->space == PFD_INPUT;
    }
    /* config, in_fs, out_fs and the paper's 16 */
    assert_int_equal(staged, 19);
    assert_int_equal(committed, 19);
}

/* Every instance key is a staged or a kept live holding register, read
 * with that register's range. */
static void instance_keys_have_register_ranges(void **state)
{
    char err[400], text[200];
    unsigned i;
    int tried = 0;
    (void)state;
    for (i = 0; i < pfd_nregs; i++) {
        const pfd_reg *r = &pfd_regs[i];
        if (r->space != PFD_HOLD || !(r->flags & PFD_F_STAGED) || (r->flags & PFD_F_ACTION) ||
            !strcmp(r->name, "config") || !strcmp(r->name, "arith"))
            continue;
        snprintf(text, sizeof text, "[instance 1]\n%s = %.17g\n", r->name, pfd_reg_max(r));
        if (load("k.conf", text, err, sizeof err) == NULL)
            fail_msg("%s at its maximum: %s", r->name, err);
        snprintf(text, sizeof text, "[instance 1]\n%s = %.17g\n", r->name,
                 pfd_reg_max(r) * 2 + 1);
        assert_null(load("k.conf", text, err, sizeof err));
        assert_non_null(strstr(err, "out of range"));
        if (pfd_reg_min_excl(r)) {
            snprintf(text, sizeof text, "[instance 1]\n%s = %.17g\n", r->name, pfd_reg_min(r));
            assert_null(load("k.conf", text, err, sizeof err));
        }
        tried++;
    }
    assert_true(tried >= 20);
    assert_non_null(load("k.conf", "[instance 1]\nwatchdog_ms = 60000\nmode = 1\n", err,
                         sizeof err));
    assert_null(load("k.conf", "[instance 1]\nwatchdog_ms = 60001\n", err, sizeof err));
    assert_null(load("k.conf", "[instance 1]\nmode = 0.5\n", err, sizeof err));
    assert_non_null(strstr(err, "is not an integer"));
    assert_null(load("k.conf", "[instance 1]\npv = 1\n", err, sizeof err));
    assert_non_null(strstr(err, "unknown key 'pv'")); /* live, but not kept */
    assert_null(load("k.conf", "[instance 1]\ncommit = 1\n", err, sizeof err));
    assert_null(load("k.conf", "[daemon]\nmax_clients = 257\n[instance 1]\n", err, sizeof err));
    assert_non_null(strstr(err, "max_clients: '257' is not an integer in 1..256"));
    assert_null(load("k.conf", "[daemon]\ninstances = 2\n[instance 1]\n", err, sizeof err));
    assert_non_null(strstr(err, "unknown key 'instances' in [daemon]"));
    assert_null(load("k.conf", "[instance 248]\n", err, sizeof err));
}

/* A configuration written reads back as itself, and rewrites to the same
 * bytes. */
static void write_read_back(void **state)
{
    static pfd_config c, back;
    char err[400], *one, *two;
    (void)state;
    memset(&c, 0, sizeof c);
    pfd_settings_default(&c.set);
    c.set.max_clients = 5;
    c.set.mlock = 0;
    c.set.external_clock = 1;
    c.set.word_order = PFD_WORDS_CDAB;
    strcpy(c.set.allow, "10.0.0.0/8, 127.0.0.1");
    c.set_mask = pfd_setting_bit(pfd_setting_by_key("max_clients")) |
                 pfd_setting_bit(pfd_setting_by_key("word_order")) |
                 pfd_setting_bit(pfd_setting_by_key("mlock")) |
                 pfd_setting_bit(pfd_setting_by_key("clock")) |
                 pfd_setting_bit(pfd_setting_by_key("allow"));
    c.n = 2;
    pfd_config_inst_default(&c.inst[0], 3);
    pf_params_default(&c.inst[0].ip.p, PF_TOPO_PID);
    c.inst[0].ip.arith = PFD_ARITH_Q15;
    c.inst[0].ip.fs = 2000.0 / 3.0;
    c.inst[0].ip.p.q = 0.1;
    c.inst[0].live.sp = 0.1f;
    c.inst[0].live.failsafe_out = -1e-7f;
    c.inst[0].live.mode = 1;
    c.inst[0].live.watchdog_ms = 250;
    pfd_config_inst_default(&c.inst[1], 247);

    assert_int_equal(pfd_config_write(path_of("w.conf"), &c, err, sizeof err), 0);
    assert_int_equal(pfd_config_load(path_of("w.conf"), &back, 1, err, sizeof err), 0);
    assert_int_equal(back.set_mask, c.set_mask);
    assert_memory_equal(&back.set, &c.set, sizeof c.set);
    assert_int_equal(back.n, 2);
    assert_int_equal(back.inst[0].unit, 3);
    assert_int_equal(back.inst[1].unit, 247);
    assert_memory_equal(&back.inst[0].ip, &c.inst[0].ip, sizeof c.inst[0].ip);
    assert_memory_equal(&back.inst[1].ip, &c.inst[1].ip, sizeof c.inst[1].ip);
    assert_memory_equal(&back.inst[0].live, &c.inst[0].live, sizeof c.inst[0].live);

    one = slurp("w.conf");
    /* Shortest round-trip text: a staged double and a live float 0.1 are
     * both "0.1" (not 0.10000000000000001 or 0.100000001). */
    assert_non_null(strstr(one, "\nq = 0.1\n"));
    assert_non_null(strstr(one, "\nsp = 0.1\n"));
    assert_non_null(strstr(one, "\nfs = 666.6666666666666\n"));
    assert_non_null(strstr(one, "\nfailsafe_out = -1e-07\n"));
    assert_int_equal(pfd_config_write(path_of("w.conf"), &back, err, sizeof err), 0);
    two = slurp("w.conf");
    assert_string_equal(one, two);
    assert_int_equal(access(path_of("w.conf.tmp"), F_OK), -1);
    free(one);
    free(two);

    assert_int_equal(pfd_config_write("/nonexistent-dir/x.conf", &c, err, sizeof err), -1);
    assert_non_null(strstr(err, "config /nonexistent-dir/x.conf: writing"));
}

/* pfd_config_create: a file that exists is never touched; one that does
 * not is written whole, with nothing left beside it. */
static void create_unless_it_exists(void **state)
{
    static pfd_config c, back;
    char err[400], *before, *after;
    (void)state;
    memset(&c, 0, sizeof c);
    pfd_settings_default(&c.set);
    c.n = 1;
    pfd_config_inst_default(&c.inst[0], 1);

    assert_int_equal(pfd_config_create(path_of("c.conf"), &c, err, sizeof err), 0);
    assert_int_equal(access(path_of("c.conf.tmp"), F_OK), -1);
    assert_int_equal(pfd_config_load(path_of("c.conf"), &back, 1, err, sizeof err), 0);
    assert_int_equal(back.n, 1);

    put("c.conf", "# not a config file at all\n");
    before = slurp("c.conf");
    assert_int_equal(pfd_config_create(path_of("c.conf"), &c, err, sizeof err), 1);
    after = slurp("c.conf");
    assert_string_equal(before, after);
    assert_int_equal(access(path_of("c.conf.tmp"), F_OK), -1);
    free(before);
    free(after);

    assert_int_equal(pfd_config_create("/nonexistent-dir/c.conf", &c, err, sizeof err), -1);
    assert_non_null(strstr(err, "config /nonexistent-dir/c.conf: writing"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(crc32_check_value),
        cmocka_unit_test(ini_format),
        cmocka_unit_test(every_byte_is_sealed),
        cmocka_unit_test(parameter_registers_have_library_names),
        cmocka_unit_test(instance_keys_have_register_ranges),
        cmocka_unit_test(write_read_back),
        cmocka_unit_test(create_unless_it_exists),
    };
    return cmocka_run_group_tests(tests, make_dir, remove_dir);
}
