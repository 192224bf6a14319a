/* SPDX-License-Identifier: MIT */
#include "pfd_config.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pfd_file.h"
#include "pfd_ini.h"
#include "pfd_parse.h"
#include "pfd_regmap.h"
#include "pfh_fmt.h"

#define MAX_FILE (1024 * 1024)

/* An instance's keys are the names of its holding registers: the staged
 * parameters, and these live settings, in the order the file lists them.
 * The register table gives their ranges. */
static const char *const kept_live[] = {"watchdog_ms", "failsafe_out", "mode",
                                        "manual_out", "input_sel", "sp"};
#define N_KEPT (sizeof kept_live / sizeof kept_live[0])

/* Staged registers whose values are written as names. */
static const struct {
    const char *key;
    const char *(*name)(int);
    int n;
} named[] = {{"config", pfd_topology_name, PF_TOPO_COUNT},
             {"arith", pfd_arith_name, PFD_ARITH_COUNT}};
#define N_NAMED (sizeof named / sizeof named[0])

static int is_param(const pfd_reg *r)
{
    return r->space == PFD_HOLD && (r->flags & PFD_F_STAGED) && !(r->flags & PFD_F_ACTION);
}

/* The holding register that instance key @p k names, or NULL. */
static const pfd_reg *instance_reg(const char *k)
{
    const pfd_reg *r = pfd_reg_named(PFD_HOLD, k);
    unsigned i;
    if (r == NULL || is_param(r))
        return r;
    for (i = 0; i < N_KEPT; i++)
        if (!strcmp(k, kept_live[i]))
            return r;
    return NULL;
}

void pfd_config_inst_default(pfd_config_inst *ci, int unit)
{
    memset(ci, 0, sizeof *ci);
    ci->unit = unit;
    pfd_iparams_default(&ci->ip);
}

/* ---- reading --------------------------------------------------------- */

typedef struct loader {
    pfd_config *c;
    int in_daemon, seen_daemon;
    pfd_config_inst *ci; /* the [instance] section being read, or NULL */
    pfd_wlist keys;      /* its keys so far, checked */
} loader;

static int daemon_key(pfd_ini *ini, pfd_config *c, const char *k, const char *v)
{
    const pfd_setting *r = pfd_setting_by_key(k);
    char msg[300];

    if (r == NULL)
        return pfd_ini_error(ini, "unknown key '%s' in [daemon]", k);
    if (pfd_setting_parse(r, v, &c->set, NULL, msg, sizeof msg) != 0)
        return pfd_ini_error(ini, "%s: %s", k, msg);
    if (c->set_mask & pfd_setting_bit(r))
        return pfd_ini_error(ini, "'%s' given twice", k);
    c->set_mask |= pfd_setting_bit(r);
    return 0;
}

static int instance_key(pfd_ini *ini, loader *ld, const char *k, const char *v)
{
    const pfd_reg *r = instance_reg(k);
    const int unit = ld->ci->unit;
    pfd_wlist *wl = &ld->keys;
    char buf[128];
    unsigned i;
    double x;

    if (r == NULL)
        return pfd_ini_error(ini, "unknown key '%s' in [instance %d]", k, unit);
    for (i = 0; i < wl->n; i++)
        if (wl->w[i].r == r)
            return pfd_ini_error(ini, "'%s' given twice in [instance %d]", k, unit);
    for (i = 0; i < N_NAMED && strcmp(k, named[i].key) != 0; i++) {
    }
    if (i < N_NAMED) {
        int val = pfd_parse_name(v, named[i].name, named[i].n);
        if (val < 0) {
            pfd_parse_names(named[i].name, named[i].n, buf, sizeof buf);
            return pfd_ini_error(ini, "%s: '%s' is not %s", k, v, buf);
        }
        x = val;
    } else {
        if (pfd_parse_number(v, &x) != 0)
            return pfd_ini_error(ini, "%s: '%s' is not a number", k, v);
        if ((r->type == PFD_T_U16 || r->type == PFD_T_I16) && x != floor(x))
            return pfd_ini_error(ini, "%s: '%s' is not an integer", k, v);
        if (!pfd_reg_in_range(r, x)) {
            pfd_reg_format_range(r, buf, sizeof buf);
            return pfd_ini_error(ini, "%s = %s is out of range %s", k, v, buf);
        }
    }
    wl->w[wl->n].r = r;
    wl->w[wl->n].v = x;
    wl->n++;
    return 0;
}

/* The defaults of the section's configuration first, then its keys, as a
 * write of those registers would set them. */
static void finish_instance(loader *ld)
{
    pfd_config_inst *ci = ld->ci;
    pfd_hold h;
    unsigned i;

    if (ci == NULL)
        return;
    for (i = 0; i < ld->keys.n; i++)
        if (!strcmp(ld->keys.w[i].r->name, "config"))
            pf_params_default(&ci->ip.p, (pf_topology)(int)ld->keys.w[i].v);
    memset(&h, 0, sizeof h);
    h.live = ci->live;
    h.staged = ci->ip;
    pfd_regmap_apply(&h, &ci->ip, &ld->keys);
    ci->live = h.live;
    ci->ip = h.staged;
    ld->ci = NULL;
}

static int on_section(pfd_ini *ini, void *ctx, const char *name)
{
    loader *ld = (loader *)ctx;
    pfd_config *c = ld->c;
    const char *p = name + 8;
    long unit;
    int i;

    finish_instance(ld);
    ld->in_daemon = 0;
    if (!strcmp(name, "daemon")) {
        if (ld->seen_daemon)
            return pfd_ini_error(ini, "[daemon] given twice");
        ld->seen_daemon = ld->in_daemon = 1;
        return 0;
    }
    if (strncmp(name, "instance", 8) == 0 && (*p == ' ' || *p == '\t'))
        p += strspn(p, " \t");
    else
        p = "";
    if (pfd_parse_int(p, PFD_UNIT_MIN, PFD_UNIT_MAX, &unit) != 0)
        return pfd_ini_error(ini, "unknown section [%s] (expected [daemon] or "
                             "[instance UNIT], UNIT %d..%d)", name, PFD_UNIT_MIN,
                             PFD_UNIT_MAX);
    for (i = 0; i < c->n; i++)
        if (c->inst[i].unit == unit)
            return pfd_ini_error(ini, "[instance %ld] given twice", unit);
    if (c->n >= PFD_MAX_INSTANCES)
        return pfd_ini_error(ini, "more than %d instances", PFD_MAX_INSTANCES);
    ld->ci = &c->inst[c->n++];
    pfd_config_inst_default(ld->ci, (int)unit);
    ld->ci->line = ini->line;
    memset(&ld->keys, 0, sizeof ld->keys);
    return 0;
}

static int on_key(pfd_ini *ini, void *ctx, const char *k, const char *v)
{
    loader *ld = (loader *)ctx;
    if (ld->in_daemon)
        return daemon_key(ini, ld->c, k, v);
    if (ld->ci != NULL)
        return instance_key(ini, ld, k, v);
    return pfd_ini_error(ini, "'%s' outside a section", k);
}

int pfd_config_load(const char *path, pfd_config *c, int need_checksum,
                    char *err, size_t errlen)
{
    pfd_ini ini;
    pfd_ini_sink sink;
    loader *ld;
    char *text, why[200];
    size_t len;
    int rc;

    memset(c, 0, sizeof *c);
    pfd_settings_default(&c->set);
    ini.path = path;
    ini.line = 0;
    ini.err = err;
    ini.errlen = errlen;
    rc = pfd_file_read(path, MAX_FILE, &text, &len, why, sizeof why);
    if (rc != 0) {
        /* A first start names a file that is not there yet: say how to make
         * one rather than leave the user to find the option. */
        if (rc == PFD_FILE_MISSING)
            return pfd_ini_error(&ini, "%s (pneufracd --init-config FILE writes one "
                                 "for the default instances)", why);
        return pfd_ini_error(&ini, "%s", why);
    }
    ld = calloc(1, sizeof *ld);
    if (ld == NULL) {
        free(text);
        return pfd_ini_error(&ini, "out of memory");
    }
    ld->c = c;
    sink.section = on_section;
    sink.key = on_key;
    sink.ctx = ld;
    rc = pfd_ini_parse(&ini, text, len, need_checksum, &sink);
    finish_instance(ld);
    if (rc == 0 && c->n == 0)
        rc = pfd_ini_error(&ini, "no [instance UNIT] section");
    free(ld);
    free(text);
    return rc;
}

/* ---- writing --------------------------------------------------------- */

static void print_value(FILE *f, const pfd_reg *r, double v)
{
    unsigned i;
    for (i = 0; i < N_NAMED; i++)
        if (!strcmp(r->name, named[i].key)) {
            fprintf(f, "%s = %s\n", r->name, named[i].name((int)v));
            return;
        }
    if (r->type == PFD_T_U16) {
        fprintf(f, "%s = %u\n", r->name, (unsigned)v);
    } else {
        /* A staged value is a double, a live one a float: the shortest
         * text of each reads back bit for bit ("0.1", not
         * "0.10000000000000001"). */
        char num[PFH_FMT_LEN];
        if (r->flags & PFD_F_STAGED)
            pfh_fmt_double(num, v);
        else
            pfh_fmt_float(num, (float)v);
        fprintf(f, "%s = %s\n", r->name, num);
    }
}

static void print_instance(FILE *f, const pfd_config_inst *ci)
{
    pfd_hold h;
    unsigned i;

    memset(&h, 0, sizeof h);
    h.live = ci->live;
    h.staged = ci->ip;
    fprintf(f, "\n[instance %d]\n", ci->unit);
    for (i = 0; i < pfd_nregs; i++) {
        const pfd_reg *r = &pfd_regs[i];
        pf_param_id id;
        if (!is_param(r))
            continue;
        id = pf_param_lookup(r->name);
        /* A paper parameter that this configuration does not use. */
        if (id < PF_P_CONFIG && !pf_param_used(ci->ip.p.topology, id))
            continue;
        print_value(f, r, pfd_regmap_hold_value(r, &h, &ci->ip));
    }
    for (i = 0; i < N_KEPT; i++) {
        const pfd_reg *r = pfd_reg_named(PFD_HOLD, kept_live[i]);
        print_value(f, r, pfd_regmap_hold_value(r, &h, &ci->ip));
    }
}

static void print_body(const pfd_config *c, FILE *f)
{
    unsigned i;
    int k;

    fputs("# pneufracd configuration (docs/pneufracd.md). pneufracd rewrites this\n"
          "# file on every commit and at shutdown; after editing it by hand, run\n"
          "# `pneufracd --seal-config FILE` to renew the checksum.\n", f);
    if (c->set_mask)
        fputs("\n[daemon]\n", f);
    for (i = 0; i < pfd_settings_count; i++) {
        const pfd_setting *r = &pfd_settings_table[i];
        char v[600];
        if (r->key == NULL || !(c->set_mask & pfd_setting_bit(r)))
            continue;
        pfd_setting_format(r, &c->set, NULL, v, sizeof v);
        fprintf(f, "%s = %s\n", r->key, v);
    }
    for (k = 0; k < c->n; k++)
        print_instance(f, &c->inst[k]);
}

/* The whole text in memory, so the checksum covers exactly what is written. */
static char *render(const pfd_config *c, size_t *len)
{
    char *body = NULL, *text;
    size_t n = 0;
    FILE *f = open_memstream(&body, &n);
    if (f == NULL)
        return NULL;
    print_body(c, f);
    if (fclose(f) != 0) {
        free(body);
        return NULL;
    }
    text = pfd_ini_seal(body, n, len);
    free(body);
    return text;
}

int pfd_config_print(const pfd_config *c, FILE *f)
{
    size_t n;
    char *t = render(c, &n);
    int rc;
    if (t == NULL)
        return -1;
    rc = fwrite(t, 1, n, f) == n ? 0 : -1;
    free(t);
    return rc;
}

/* Write @p c's text to @p path with @p put (pfd_file_replace or
 * pfd_file_create); its result, with "config PATH: ..." in @p err. */
static int put_text(const char *path, const pfd_config *c,
                    int (*put)(const char *, const char *, size_t, char *, size_t),
                    char *err, size_t errlen)
{
    size_t n;
    char *text = render(c, &n);
    char why[400];
    int rc;

    if (text == NULL) {
        snprintf(err, errlen, "config %s: out of memory", path);
        return -1;
    }
    rc = put(path, text, n, why, sizeof why);
    free(text);
    if (rc < 0)
        snprintf(err, errlen, "config %s: %s", path, why);
    return rc;
}

int pfd_config_write(const char *path, const pfd_config *c, char *err,
                     size_t errlen)
{
    return put_text(path, c, pfd_file_replace, err, errlen);
}

int pfd_config_create(const char *path, const pfd_config *c, char *err,
                      size_t errlen)
{
    return put_text(path, c, pfd_file_create, err, errlen);
}
