/* SPDX-License-Identifier: MIT */
#include "pfd_config.h"

#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "pfd_allow.h"
#include "pfd_regmap.h"

#define MAX_FILE (1024 * 1024)

unsigned long pfd_crc32(const unsigned char *p, size_t n)
{
    unsigned long c = 0xFFFFFFFFul;
    size_t i;
    int k;
    for (i = 0; i < n; i++) {
        c ^= p[i];
        for (k = 0; k < 8; k++)
            c = (c >> 1) ^ (0xEDB88320ul & (0ul - (c & 1ul)));
    }
    return c ^ 0xFFFFFFFFul;
}

void pfd_settings_default(pfd_settings *s)
{
    memset(s, 0, sizeof *s);
    strcpy(s->listen_addr, "127.0.0.1");
    s->listen_port = 1502;
    s->external_clock = 0;
    s->max_clients = 16;
    s->read_only = 0;
    s->param_lock = 0;
    s->allow[0] = '\0';
    s->rt_priority = 80;
    s->mlock = 1;
    s->byte_timeout_ms = 100;
    s->idle_timeout_s = 300;
}

void pfd_config_inst_default(pfd_config_inst *ci, int unit)
{
    memset(ci, 0, sizeof *ci);
    ci->unit = unit;
    pfd_iparams_default(&ci->ip);
}

int pfd_parse_listen(const char *v, pfd_settings *s)
{
    const char *colon = strrchr(v, ':');
    struct in_addr ia;
    char addr[64];
    char *e;
    long port;

    if (colon == NULL || (size_t)(colon - v) >= sizeof addr || colon == v)
        return -1;
    memcpy(addr, v, (size_t)(colon - v));
    addr[colon - v] = '\0';
    if (inet_pton(AF_INET, addr, &ia) != 1)
        return -1;
    errno = 0;
    port = strtol(colon + 1, &e, 10);
    if (errno != 0 || e == colon + 1 || *e != '\0' || port < 0 || port > 65535)
        return -1;
    strcpy(s->listen_addr, addr);
    s->listen_port = (int)port;
    return 0;
}

/* ---- reading --------------------------------------------------------- */

typedef struct parser {
    const char *path;
    int line;
    char *err;
    size_t errlen;
} parser;

static int perr(parser *ps, const char *fmt, ...)
{
    char msg[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (ps->line > 0)
        snprintf(ps->err, ps->errlen, "config %s:%d: %s", ps->path, ps->line, msg);
    else
        snprintf(ps->err, ps->errlen, "config %s: %s", ps->path, msg);
    return -1;
}

static int parse_long(const char *v, long lo, long hi, long *out)
{
    char *e;
    long x;
    errno = 0;
    x = strtol(v, &e, 10);
    if (errno != 0 || e == v || *e != '\0' || x < lo || x > hi)
        return -1;
    *out = x;
    return 0;
}

static int parse_bool(const char *v, int *out)
{
    if (!strcmp(v, "yes") || !strcmp(v, "true") || !strcmp(v, "1") || !strcmp(v, "on"))
        *out = 1;
    else if (!strcmp(v, "no") || !strcmp(v, "false") || !strcmp(v, "0") || !strcmp(v, "off"))
        *out = 0;
    else
        return -1;
    return 0;
}

static int daemon_key(parser *ps, pfd_config *c, const char *k, const char *v)
{
    pfd_settings *s = &c->set;
    unsigned bit;
    long x;
    char aerr[160];
    pfd_allow al;

    if (!strcmp(k, "listen")) {
        bit = PFD_K_LISTEN;
        if (pfd_parse_listen(v, s) != 0)
            return perr(ps, "listen: '%s' is not IPV4ADDR:PORT", v);
    } else if (!strcmp(k, "clock")) {
        bit = PFD_K_CLOCK;
        if (!strcmp(v, "internal"))
            s->external_clock = 0;
        else if (!strcmp(v, "external"))
            s->external_clock = 1;
        else
            return perr(ps, "clock: '%s' is not internal or external", v);
    } else if (!strcmp(k, "max_clients")) {
        bit = PFD_K_MAX_CLIENTS;
        if (parse_long(v, 1, 256, &x) != 0)
            return perr(ps, "max_clients: '%s' is not an integer in 1..256", v);
        s->max_clients = (int)x;
    } else if (!strcmp(k, "allow")) {
        bit = PFD_K_ALLOW;
        if (strlen(v) >= sizeof s->allow || pfd_allow_parse(v, &al, aerr, sizeof aerr) != 0)
            return perr(ps, "%s", strlen(v) >= sizeof s->allow ? "allow: list too long" : aerr);
        strcpy(s->allow, v);
    } else if (!strcmp(k, "read_only")) {
        bit = PFD_K_READ_ONLY;
        if (parse_bool(v, &s->read_only) != 0)
            return perr(ps, "read_only: '%s' is not yes or no", v);
    } else if (!strcmp(k, "param_lock")) {
        bit = PFD_K_PARAM_LOCK;
        if (parse_bool(v, &s->param_lock) != 0)
            return perr(ps, "param_lock: '%s' is not yes or no", v);
    } else if (!strcmp(k, "rt_priority")) {
        bit = PFD_K_RT_PRIORITY;
        if (parse_long(v, 0, 99, &x) != 0)
            return perr(ps, "rt_priority: '%s' is not an integer in 0..99", v);
        s->rt_priority = (int)x;
    } else if (!strcmp(k, "mlock")) {
        bit = PFD_K_MLOCK;
        if (parse_bool(v, &s->mlock) != 0)
            return perr(ps, "mlock: '%s' is not yes or no", v);
    } else if (!strcmp(k, "byte_timeout_ms")) {
        bit = PFD_K_BYTE_TIMEOUT;
        if (parse_long(v, 1, 10000, &x) != 0)
            return perr(ps, "byte_timeout_ms: '%s' is not an integer in 1..10000", v);
        s->byte_timeout_ms = (int)x;
    } else if (!strcmp(k, "idle_timeout_s")) {
        bit = PFD_K_IDLE_TIMEOUT;
        if (parse_long(v, 0, 86400, &x) != 0)
            return perr(ps, "idle_timeout_s: '%s' is not an integer in 0..86400", v);
        s->idle_timeout_s = (int)x;
    } else {
        return perr(ps, "unknown key '%s' in [daemon]", k);
    }
    if (c->set_mask & bit)
        return perr(ps, "'%s' given twice", k);
    c->set_mask |= bit;
    return 0;
}

/* Instance keys: the holding-register names of the staged parameters and
 * of the persisted live settings; the register table gives their ranges. */
static const char *const live_keys[] = {"sp", "input_sel", "mode", "manual_out",
                                        "failsafe_out", "watchdog_ms"};

static const pfd_reg *key_reg(const char *k)
{
    unsigned i;
    for (i = 0; i < pfd_nregs; i++) {
        const pfd_reg *r = &pfd_regs[i];
        if (r->space == PFD_HOLD && !strcmp(r->name, k) &&
            (r->flags & PFD_F_STAGED) && !(r->flags & PFD_F_ACTION))
            return r;
    }
    return NULL;
}

static int in_range(const pfd_reg *r, double v)
{
    if (!isfinite(v) || v > r->max)
        return 0;
    return (r->flags & PFD_F_MIN_EXCL) ? v > r->min : v >= r->min;
}

static const pfd_reg *live_reg(const char *k)
{
    unsigned i;
    for (i = 0; i < pfd_nregs; i++)
        if (pfd_regs[i].space == PFD_HOLD && !strcmp(pfd_regs[i].name, k))
            return &pfd_regs[i];
    return NULL;
}

typedef struct kv {
    char key[32];
    double v;
    int line;
} kv;

typedef struct section {
    pfd_config_inst *ci;
    kv keys[64];
    int n;
} section;

static int inst_key(parser *ps, section *sec, const char *k, const char *v)
{
    int i;
    double x;
    char *e;
    int is_live = 0;
    const pfd_reg *r;

    for (i = 0; i < sec->n; i++)
        if (!strcmp(sec->keys[i].key, k))
            return perr(ps, "'%s' given twice in [instance %d]", k, sec->ci->unit);
    if (sec->n >= (int)(sizeof sec->keys / sizeof sec->keys[0]))
        return perr(ps, "too many keys in [instance %d]", sec->ci->unit);

    for (i = 0; i < (int)(sizeof live_keys / sizeof live_keys[0]); i++)
        if (!strcmp(k, live_keys[i]))
            is_live = 1;
    r = is_live ? live_reg(k) : key_reg(k);
    if (r == NULL)
        return perr(ps, "unknown key '%s' in [instance %d]", k, sec->ci->unit);

    if (!strcmp(k, "config")) {
        pf_config cfg = pf_config_lookup(v);
        if (cfg == PF_CFG_COUNT)
            return perr(ps, "config: '%s' is not p, dd, id or pid", v);
        x = (double)cfg;
    } else if (!strcmp(k, "arith")) {
        if (!strcmp(v, "float"))
            x = PFD_ARITH_FLOAT;
        else if (!strcmp(v, "q15"))
            x = PFD_ARITH_Q15;
        else
            return perr(ps, "arith: '%s' is not float or q15", v);
    } else {
        errno = 0;
        x = strtod(v, &e);
        if (errno == ERANGE || e == v || *e != '\0' || !isfinite(x))
            return perr(ps, "%s: '%s' is not a number", k, v);
        if ((r->type == PFD_T_U16 || r->type == PFD_T_I16) && x != floor(x))
            return perr(ps, "%s: '%s' is not an integer", k, v);
        if (!in_range(r, x))
            return perr(ps, "%s = %s is out of range %s%.9g .. %.9g]", k, v,
                        (r->flags & PFD_F_MIN_EXCL) ? "(" : "[", r->min, r->max);
    }
    strcpy(sec->keys[sec->n].key, k);
    sec->keys[sec->n].v = x;
    sec->keys[sec->n].line = ps->line;
    sec->n++;
    return 0;
}

/* Defaults of the section's configuration first, then its keys. */
static void finish_section(section *sec)
{
    pfd_config_inst *ci = sec->ci;
    int i;

    for (i = 0; i < sec->n; i++)
        if (!strcmp(sec->keys[i].key, "config"))
            pf_params_default(&ci->ip.p, (pf_config)(int)sec->keys[i].v);
    for (i = 0; i < sec->n; i++) {
        const char *k = sec->keys[i].key;
        double v = sec->keys[i].v;
        pf_param_id id = pf_param_lookup(k);
        if (!strcmp(k, "config"))
            continue;
        else if (!strcmp(k, "arith"))
            ci->ip.arith = (int)v;
        else if (!strcmp(k, "fs"))
            ci->ip.fs = v;
        else if (!strcmp(k, "in_fs"))
            ci->ip.in_fs = v;
        else if (!strcmp(k, "out_fs"))
            ci->ip.out_fs = v;
        else if (!strcmp(k, "bump_tau"))
            ci->ip.bump_tau = v;
        else if (!strcmp(k, "sp"))
            ci->live.sp = (float)v;
        else if (!strcmp(k, "input_sel"))
            ci->live.input_sel = (uint16_t)v;
        else if (!strcmp(k, "mode"))
            ci->live.mode = (uint16_t)v;
        else if (!strcmp(k, "manual_out"))
            ci->live.manual_out = (float)v;
        else if (!strcmp(k, "failsafe_out"))
            ci->live.failsafe_out = (float)v;
        else if (!strcmp(k, "watchdog_ms"))
            ci->live.watchdog_ms = (uint16_t)v;
        else if (id < PF_P_CONFIG)
            (void)pf_params_set(&ci->ip.p, id, v);
    }
}

static char *trim(char *s)
{
    char *e;
    while (*s == ' ' || *s == '\t')
        s++;
    e = s + strlen(s);
    while (e > s && (e[-1] == ' ' || e[-1] == '\t' || e[-1] == '\r'))
        *--e = '\0';
    return s;
}

static int read_file(parser *ps, char **buf, size_t *len)
{
    FILE *f = fopen(ps->path, "rb");
    size_t n = 0, cap = 4096;
    char *b;

    if (f == NULL)
        return perr(ps, "cannot open: %s", strerror(errno));
    b = malloc(cap + 1);
    if (b == NULL) {
        fclose(f);
        return perr(ps, "out of memory");
    }
    for (;;) {
        size_t r;
        if (n == cap) {
            char *nb;
            if (cap >= MAX_FILE) {
                free(b);
                fclose(f);
                return perr(ps, "larger than %d bytes", MAX_FILE);
            }
            cap *= 2;
            nb = realloc(b, cap + 1);
            if (nb == NULL) {
                free(b);
                fclose(f);
                return perr(ps, "out of memory");
            }
            b = nb;
        }
        r = fread(b + n, 1, cap - n, f);
        n += r;
        if (r == 0)
            break;
    }
    if (ferror(f)) {
        free(b);
        fclose(f);
        return perr(ps, "read error: %s", strerror(errno));
    }
    fclose(f);
    b[n] = '\0';
    *buf = b;
    *len = n;
    return 0;
}

int pfd_config_load(const char *path, pfd_config *c, int need_checksum,
                    char *err, size_t errlen)
{
    parser ps;
    char *buf = NULL, *orig = NULL, *p, *end;
    size_t len = 0;
    static section secs[PFD_MAX_INSTANCES];
    section *cur = NULL;
    int in_daemon = 0, seen_daemon = 0, rc = -1, have_sum = 0, i;
    unsigned long sum_file = 0;

    ps.path = path;
    ps.line = 0;
    ps.err = err;
    ps.errlen = errlen;
    memset(c, 0, sizeof *c);
    pfd_settings_default(&c->set);
    if (read_file(&ps, &buf, &len) != 0)
        return -1;
    if (memchr(buf, '\0', len) != NULL) {
        perr(&ps, "contains NUL bytes: not a text file");
        goto out;
    }
    /* Parsing cuts lines in place; the checksum needs the bytes as read. */
    orig = malloc(len + 1);
    if (orig == NULL) {
        perr(&ps, "out of memory");
        goto out;
    }
    memcpy(orig, buf, len + 1);

    for (p = buf; p < buf + len; p = end + 1) {
        char *line, *eq, *k, *v;
        ps.line++;
        end = strchr(p, '\n');
        if (end == NULL) {
            /* Every line the daemon writes ends in a newline: a file cut
             * short in the middle of a line is caught here. */
            perr(&ps, "last line has no newline: the file is truncated");
            goto out;
        }
        *end = '\0';
        if (have_sum) {
            if (*trim(p) != '\0') {
                perr(&ps, "text after the checksum line");
                goto out;
            }
            continue;
        }
        line = trim(p);
        if (*line == '\0' || *line == '#' || *line == ';')
            continue;
        if (*line == '[') {
            char *close = strchr(line, ']');
            long unit;
            if (cur != NULL)
                finish_section(cur);
            cur = NULL;
            in_daemon = 0;
            if (close == NULL || close[1] != '\0') {
                perr(&ps, "malformed section header '%s'", line);
                goto out;
            }
            *close = '\0';
            k = trim(line + 1);
            if (!strcmp(k, "daemon")) {
                if (seen_daemon) {
                    perr(&ps, "[daemon] given twice");
                    goto out;
                }
                seen_daemon = in_daemon = 1;
                continue;
            }
            if (strncmp(k, "instance", 8) != 0 || (k[8] != ' ' && k[8] != '\t') ||
                parse_long(trim(k + 8), 1, 247, &unit) != 0) {
                perr(&ps, "unknown section [%s] (expected [daemon] or [instance UNIT], UNIT 1..247)", k);
                goto out;
            }
            for (i = 0; i < c->n; i++)
                if (c->inst[i].unit == unit) {
                    perr(&ps, "[instance %ld] given twice", unit);
                    goto out;
                }
            if (c->n >= PFD_MAX_INSTANCES) {
                perr(&ps, "more than %d instances", PFD_MAX_INSTANCES);
                goto out;
            }
            pfd_config_inst_default(&c->inst[c->n], (int)unit);
            c->inst[c->n].line = ps.line;
            cur = &secs[c->n];
            memset(cur, 0, sizeof *cur);
            cur->ci = &c->inst[c->n];
            c->n++;
            continue;
        }
        eq = strchr(line, '=');
        if (eq == NULL) {
            perr(&ps, "expected 'key = value', got '%s'", line);
            goto out;
        }
        *eq = '\0';
        k = trim(line);
        v = trim(eq + 1);
        if (!strcmp(k, "checksum")) {
            char *e;
            unsigned long want;
            if (strlen(v) != 8 || (want = strtoul(v, &e, 16), *e != '\0')) {
                perr(&ps, "checksum: '%s' is not 8 hex digits", v);
                goto out;
            }
            sum_file = want;
            have_sum = 1;
            if (need_checksum) {
                unsigned long got = pfd_crc32((const unsigned char *)orig,
                                              (size_t)(p - buf));
                if (got != sum_file) {
                    perr(&ps, "checksum mismatch (file %08lx, content %08lx): "
                         "the file is corrupt, or was edited without "
                         "`pneufracd --seal-config %s`", sum_file, got, path);
                    goto out;
                }
            }
            continue;
        }
        if (*k == '\0' || *v == '\0') {
            perr(&ps, "empty key or value");
            goto out;
        }
        if (in_daemon) {
            if (daemon_key(&ps, c, k, v) != 0)
                goto out;
        } else if (cur != NULL) {
            if (inst_key(&ps, cur, k, v) != 0)
                goto out;
        } else {
            perr(&ps, "'%s' outside a section", k);
            goto out;
        }
    }
    if (cur != NULL)
        finish_section(cur);
    ps.line = 0;
    if (need_checksum && !have_sum) {
        perr(&ps, "no checksum line: the file is incomplete, or was written "
             "by hand (check it, then run `pneufracd --seal-config %s`)", path);
        goto out;
    }
    if (c->n == 0) {
        perr(&ps, "no [instance UNIT] section");
        goto out;
    }
    rc = 0;
out:
    free(orig);
    free(buf);
    return rc;
}

/* ---- writing --------------------------------------------------------- */

static void print_body(const pfd_config *c, FILE *f)
{
    const pfd_settings *s = &c->set;
    int i, k;

    fputs("# pneufracd configuration (docs/pneufracd.md). pneufracd rewrites this\n"
          "# file on every commit and at shutdown; after editing it by hand, run\n"
          "# `pneufracd --seal-config FILE` to renew the checksum.\n", f);
    if (c->set_mask) {
        fputs("\n[daemon]\n", f);
        if (c->set_mask & PFD_K_LISTEN)
            fprintf(f, "listen = %s:%d\n", s->listen_addr, s->listen_port);
        if (c->set_mask & PFD_K_CLOCK)
            fprintf(f, "clock = %s\n", s->external_clock ? "external" : "internal");
        if (c->set_mask & PFD_K_MAX_CLIENTS)
            fprintf(f, "max_clients = %d\n", s->max_clients);
        if (c->set_mask & PFD_K_ALLOW)
            fprintf(f, "allow = %s\n", s->allow);
        if (c->set_mask & PFD_K_READ_ONLY)
            fprintf(f, "read_only = %s\n", s->read_only ? "yes" : "no");
        if (c->set_mask & PFD_K_PARAM_LOCK)
            fprintf(f, "param_lock = %s\n", s->param_lock ? "yes" : "no");
        if (c->set_mask & PFD_K_RT_PRIORITY)
            fprintf(f, "rt_priority = %d\n", s->rt_priority);
        if (c->set_mask & PFD_K_MLOCK)
            fprintf(f, "mlock = %s\n", s->mlock ? "yes" : "no");
        if (c->set_mask & PFD_K_BYTE_TIMEOUT)
            fprintf(f, "byte_timeout_ms = %d\n", s->byte_timeout_ms);
        if (c->set_mask & PFD_K_IDLE_TIMEOUT)
            fprintf(f, "idle_timeout_s = %d\n", s->idle_timeout_s);
    }
    for (i = 0; i < c->n; i++) {
        const pfd_config_inst *ci = &c->inst[i];
        const pfd_iparams *ip = &ci->ip;
        fprintf(f, "\n[instance %d]\n", ci->unit);
        fprintf(f, "config = %s\n", pf_config_name(ip->p.config));
        fprintf(f, "arith = %s\n", ip->arith == PFD_ARITH_Q15 ? "q15" : "float");
        /* %.17g: every double reads back bit for bit. */
        fprintf(f, "fs = %.17g\n", ip->fs);
        fprintf(f, "in_fs = %.17g\n", ip->in_fs);
        fprintf(f, "out_fs = %.17g\n", ip->out_fs);
        fprintf(f, "bump_tau = %.17g\n", ip->bump_tau);
        for (k = PF_P_A; k <= PF_P_RCI; k++)
            if (pf_param_used(ip->p.config, (pf_param_id)k))
                fprintf(f, "%s = %.17g\n", pf_param_name((pf_param_id)k),
                        pf_params_get(&ip->p, (pf_param_id)k));
        fprintf(f, "watchdog_ms = %u\n", (unsigned)ci->live.watchdog_ms);
        fprintf(f, "failsafe_out = %.9g\n", (double)ci->live.failsafe_out);
        fprintf(f, "mode = %u\n", (unsigned)ci->live.mode);
        fprintf(f, "manual_out = %.9g\n", (double)ci->live.manual_out);
        fprintf(f, "input_sel = %u\n", (unsigned)ci->live.input_sel);
        fprintf(f, "sp = %.9g\n", (double)ci->live.sp);
    }
}

/* The whole text in memory, so the checksum covers exactly what is written. */
static char *render(const pfd_config *c, size_t *len)
{
    char *body = NULL;
    size_t n = 0;
    FILE *f = open_memstream(&body, &n);
    if (f == NULL)
        return NULL;
    print_body(c, f);
    if (fclose(f) != 0) {
        free(body);
        return NULL;
    }
    {
        char *full = malloc(n + 32);
        if (full == NULL) {
            free(body);
            return NULL;
        }
        memcpy(full, body, n);
        n += (size_t)sprintf(full + n, "checksum = %08lx\n",
                             pfd_crc32((const unsigned char *)body, n));
        free(body);
        *len = n;
        return full;
    }
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

static int write_all(int fd, const char *p, size_t n)
{
    while (n > 0) {
        ssize_t w = write(fd, p, n);
        if (w < 0) {
            if (errno == EINTR)
                continue;
            return -1;
        }
        p += w;
        n -= (size_t)w;
    }
    return 0;
}

int pfd_config_write(const char *path, const pfd_config *c, char *err,
                     size_t errlen)
{
    char tmp[PATH_MAX], dir[PATH_MAX];
    const char *slash;
    size_t n;
    char *text = render(c, &n);
    int fd;

    if (text == NULL) {
        snprintf(err, errlen, "config %s: out of memory", path);
        return -1;
    }
    if (snprintf(tmp, sizeof tmp, "%s.tmp", path) >= (int)sizeof tmp) {
        free(text);
        snprintf(err, errlen, "config %s: path too long", path);
        return -1;
    }
    fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0 || write_all(fd, text, n) != 0 || fsync(fd) != 0) {
        snprintf(err, errlen, "config %s: writing %s: %s", path, tmp, strerror(errno));
        if (fd >= 0)
            close(fd);
        unlink(tmp);
        free(text);
        return -1;
    }
    free(text);
    if (close(fd) != 0 || rename(tmp, path) != 0) {
        snprintf(err, errlen, "config %s: replacing: %s", path, strerror(errno));
        unlink(tmp);
        return -1;
    }
    /* The rename itself is durable only once the directory is synced. */
    slash = strrchr(path, '/');
    if (slash == NULL)
        strcpy(dir, ".");
    else if (slash == path)
        strcpy(dir, "/");
    else
        snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
    fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0 || fsync(fd) != 0) {
        snprintf(err, errlen, "config %s: syncing directory %s: %s", path, dir,
                 strerror(errno));
        if (fd >= 0)
            close(fd);
        return -1;
    }
    close(fd);
    return 0;
}
