/* SPDX-License-Identifier: MIT */
#include "cli_args.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void cli_exit_status_help(FILE *f, int with_plot)
{
    fputs("Exit status: 0 success; 1 output could not be written (or out of\n"
          "memory); 2 bad arguments, bad input or a design the library refuses",
          f);
    /* Status 3 exists only where --plot does: listing it elsewhere would
     * send a reader looking for an option the command has not got. */
    fputs(with_plot ? ";\n3 --plot could not make the plot (the CSV was written).\n"
                    : ".\n", f);
}

void cli_error(const char *fmt, ...)
{
    char msg[1024];
    va_list ap;
    int n;
    size_t i;

    va_start(ap, fmt);
    n = vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (n < 0)
        snprintf(msg, sizeof msg, "(error message could not be formatted)");
    else if ((size_t)n >= sizeof msg)
        memcpy(msg + sizeof msg - 4, "...", 4);
    /* The contract is one line per error, even when an argument or a CSV
     * field quoted in the message holds a newline. */
    for (i = 0; msg[i] != '\0'; i++)
        if ((unsigned char)msg[i] < 0x20 || msg[i] == 0x7f)
            msg[i] = '?';
    fprintf(stderr, "pneufrac: %s\n", msg);
}

const char *cli_quote(char *buf, size_t n, const char *s)
{
    return cli_quote_n(buf, n, s, strlen(s));
}

const char *cli_quote_n(char *buf, size_t n, const char *s, size_t len)
{
    if (n < 5) {
        if (n > 0)
            buf[0] = '\0';
        return buf;
    }
    if (len < n) {
        memcpy(buf, s, len);
        buf[len] = '\0';
    } else {
        memcpy(buf, s, n - 4);
        memcpy(buf + n - 4, "...", 4);
    }
    return buf;
}

int cli_parse_double(const char *s, double *out)
{
    char *end;
    double v;

    /* strtod would skip leading blanks; "  5" on a command line or in a
     * CSV field is more likely a mistake than intent, and so is "". */
    if (s == NULL || *s == '\0' || *s == ' ' || *s == '\t' || *s == '\n' ||
        *s == '\r' || *s == '\v' || *s == '\f')
        return -1;
    errno = 0;
    v = strtod(s, &end);
    /* ERANGE covers overflow and also results too small to be normal:
     * neither is a value anyone means to pass. */
    if (end == s || *end != '\0' || errno == ERANGE || !isfinite(v))
        return -1;
    *out = v;
    return 0;
}

int cli_parse_int(const char *s, int *out)
{
    char *end;
    long v;

    if (s == NULL || *s == '\0' || !(*s == '-' || *s == '+' ||
                                     (*s >= '0' && *s <= '9')))
        return -1;
    errno = 0;
    v = strtol(s, &end, 10);
    if (*end != '\0' || errno == ERANGE || v < INT_MIN || v > INT_MAX)
        return -1;
    *out = (int)v;
    return 0;
}

int cli_parse_positive(const char *opt, const char *s, double *out)
{
    char q[48];
    double v;
    if (cli_parse_double(s, &v) != 0) {
        cli_error("%s: '%s' is not a finite number", opt,
                  cli_quote(q, sizeof q, s));
        return -1;
    }
    if (!(v > 0.0)) {
        cli_error("%s must be > 0 (got %s)", opt, cli_quote(q, sizeof q, s));
        return -1;
    }
    *out = v;
    return 0;
}

void cli_param_range(pf_param_id id, char *buf, size_t n)
{
    const pf_param_spec *s = pf_param_info(id);
    if (s == NULL) {
        snprintf(buf, n, "?");
        return;
    }
    snprintf(buf, n, "%c%g, %g%c%s%s", (s->flags & PF_PARAM_LO_OPEN) ? '(' : '[',
             s->lo, s->hi, (s->flags & PF_PARAM_HI_OPEN) ? ')' : ']',
             *s->unit ? " " : "", s->unit);
}

/* Parses s[0..len) as a double: the pieces of --effect and --band are not
 * NUL-terminated in argv. Numbers longer than the buffer are rejected. */
static int parse_double_n(const char *s, size_t len, double *out)
{
    char buf[128];
    if (len >= sizeof buf)
        return -1;
    memcpy(buf, s, len);
    buf[len] = '\0';
    return cli_parse_double(buf, out);
}

static void model_param_list(char *buf, size_t n)
{
    size_t used = 0;
    int i;
    buf[0] = '\0';
    for (i = 0; i < (int)PF_P_CONFIG && used + 1 < n; i++) {
        int w = snprintf(buf + used, n - used, "%s%s", i ? " " : "",
                         pf_param_name((pf_param_id)i));
        if (w < 0)
            break;
        used += (size_t)w;
    }
}

int cli_parse_set(const char *arg, cli_set *out)
{
    char name[32], q[48], list[128];
    const char *eq = strchr(arg, '=');
    size_t len;
    pf_param_id id;

    if (eq == NULL) {
        cli_error("--set: expected NAME=VALUE, got '%s'",
                  cli_quote(q, sizeof q, arg));
        return -1;
    }
    len = (size_t)(eq - arg);
    model_param_list(list, sizeof list);
    if (len == 0 || len >= sizeof name) {
        cli_error("--set: bad parameter name in '%s' (valid: %s)",
                  cli_quote(q, sizeof q, arg), list);
        return -1;
    }
    memcpy(name, arg, len);
    name[len] = '\0';
    id = pf_param_lookup(name);
    if (id == PF_P_COUNT) {
        cli_error("--set: unknown parameter '%s' (valid: %s)", name, list);
        return -1;
    }
    if (id >= PF_P_CONFIG) {
        /* Design options, full scales and effects have options of their
         * own; one spelling per setting keeps command lines readable. */
        cli_error("--set: '%s' is not a model parameter; use its own option "
                  "(valid for --set: %s)", name, list);
        return -1;
    }
    if (cli_parse_double(eq + 1, &out->value) != 0) {
        cli_error("--set %s: '%s' is not a finite number", name,
                  cli_quote(q, sizeof q, eq + 1));
        return -1;
    }
    out->id = id;
    return 0;
}

enum { FX_BACKLASH, FX_NOZZLE, FX_SATURATION, FX_DEADTIME, FX_LAG, FX_COUNT };
#define FX_MAX_KEYS 3

static const char *const fx_names[FX_COUNT] = {
    "backlash", "nozzle", "saturation", "deadtime", "lag"};
static const char *const fx_keys[FX_COUNT][FX_MAX_KEYS] = {
    {"width", NULL, NULL}, {"xh", NULL, NULL}, {"lo", "hi", "kind"}, {"t", NULL, NULL},
    {"tau", NULL, NULL}};
/* Keys that may be left out, by effect (bit k: key k): saturation's kind,
 * where the limits act (pf_sat_kind; default 1, p_c clipped after the
 * relay; the library's table holds its range). */
static const unsigned fx_optional[FX_COUNT] = {0u, 0u, 1u << 2, 0u, 0u};

static int name_is(const char *s, size_t len, const char *name)
{
    return name != NULL && strlen(name) == len && memcmp(s, name, len) == 0;
}

static void fx_key_list(int fx, char *buf, size_t n)
{
    int k;
    size_t used = 0;
    buf[0] = '\0';
    for (k = 0; k < FX_MAX_KEYS && fx_keys[fx][k] != NULL; k++) {
        int w = snprintf(buf + used, n - used, "%s%s", k ? ", " : "",
                         fx_keys[fx][k]);
        if (w < 0 || (size_t)w >= n - used)
            break;
        used += (size_t)w;
    }
}

int cli_parse_effect(const char *arg, cli_effects *acc)
{
    static const char valid[] = "backlash:width=W, nozzle:xh=X, "
                                "saturation:lo=L,hi=H[,kind=K], deadtime:t=S, lag:tau=S";
    char q[48], keys[32];
    const char *colon = strchr(arg, ':');
    const char *p;
    double val[FX_MAX_KEYS] = {0.0, 0.0, 0.0};
    int have[FX_MAX_KEYS] = {0, 0, 0};
    int fx, k;
    size_t nlen;

    nlen = colon != NULL ? (size_t)(colon - arg) : strlen(arg);
    for (fx = 0; fx < FX_COUNT; fx++)
        if (name_is(arg, nlen, fx_names[fx]))
            break;
    if (fx == FX_COUNT) {
        cli_error("--effect: unknown effect '%s' (valid: %s)",
                  cli_quote_n(q, sizeof q, arg, nlen), valid);
        return -1;
    }
    fx_key_list(fx, keys, sizeof keys);
    if (colon == NULL || colon[1] == '\0') {
        cli_error("--effect %s: expected %s:KEY=VALUE (keys: %s)",
                  fx_names[fx], fx_names[fx], keys);
        return -1;
    }
    if (acc->seen & (1u << fx)) {
        cli_error("--effect %s given twice", fx_names[fx]);
        return -1;
    }

    for (p = colon + 1;;) {
        const char *comma = strchr(p, ',');
        size_t flen = comma != NULL ? (size_t)(comma - p) : strlen(p);
        const char *eq = memchr(p, '=', flen);
        size_t klen = eq != NULL ? (size_t)(eq - p) : flen;

        for (k = 0; k < FX_MAX_KEYS; k++)
            if (name_is(p, klen, fx_keys[fx][k]))
                break;
        if (k == FX_MAX_KEYS) {
            cli_error("--effect %s: unknown key '%s' (valid: %s)",
                      fx_names[fx], cli_quote_n(q, sizeof q, p, klen), keys);
            return -1;
        }
        if (eq == NULL) {
            cli_error("--effect %s: key '%s' needs a value (%s=VALUE)",
                      fx_names[fx], fx_keys[fx][k], fx_keys[fx][k]);
            return -1;
        }
        if (have[k]) {
            cli_error("--effect %s: key '%s' given twice", fx_names[fx],
                      fx_keys[fx][k]);
            return -1;
        }
        if (parse_double_n(eq + 1, flen - klen - 1, &val[k]) != 0) {
            char v[48];
            size_t vl = flen - klen - 1;
            size_t cl = vl < sizeof v ? vl : sizeof v - 1;
            memcpy(v, eq + 1, cl);
            v[cl] = '\0';
            cli_error("--effect %s: %s: '%s' is not a finite number",
                      fx_names[fx], fx_keys[fx][k], cli_quote(q, sizeof q, v));
            return -1;
        }
        have[k] = 1;
        if (comma == NULL)
            break;
        p = comma + 1;
    }
    for (k = 0; k < FX_MAX_KEYS && fx_keys[fx][k] != NULL; k++) {
        if (!have[k] && !(fx_optional[fx] & (1u << k))) {
            cli_error("--effect %s: missing key '%s' (needs: %s)",
                      fx_names[fx], fx_keys[fx][k], keys);
            return -1;
        }
    }

    /* Ranges are the library's to judge (pf_effects_validate), so that the
     * CLI cannot drift from it; the design step reports them. */
    switch (fx) {
    case FX_BACKLASH: acc->fx.backlash = val[0]; break;
    case FX_NOZZLE: acc->fx.nozzle_xh = val[0]; break;
    case FX_SATURATION:
        /* a whole number, or the cast below would not be defined, and not
         * 0, which would switch off the saturation asked for; the rest of
         * its range is the library's to judge */
        if (have[2] && !(val[2] == floor(val[2]) && val[2] >= 1 && val[2] <= 1e6)) {
            cli_error("--effect saturation: kind: %.10g is not a placement, a whole number "
                      "(1 p_c clipped after the relay, 2 the relay's diaphragm on its seat)",
                      val[2]);
            return -1;
        }
        acc->fx.saturate = have[2] ? (int)val[2] : PF_SAT_CLIP;
        acc->fx.sat_lo = val[0];
        acc->fx.sat_hi = val[1];
        break;
    case FX_DEADTIME: acc->fx.dead_time = val[0]; break;
    default: acc->fx.lag = val[0]; break;
    }
    acc->seen |= 1u << fx;
    return 0;
}

int cli_parse_range(const char *opt, const char *lo_name, const char *hi_name,
                    const char *arg, double *lo, double *hi)
{
    char q[48];
    const char *colon = strchr(arg, ':');
    double a, b;

    if (colon == NULL ||
        parse_double_n(arg, (size_t)(colon - arg), &a) != 0 ||
        cli_parse_double(colon + 1, &b) != 0) {
        cli_error("%s: expected %s:%s in rad/s (e.g. 0.01:60000), got "
                  "'%s'", opt, lo_name, hi_name, cli_quote(q, sizeof q, arg));
        return -1;
    }
    if (!(a > 0.0) || !(b > a)) {
        cli_error("%s: need 0 < %s < %s, got '%s'", opt, lo_name, hi_name,
                  cli_quote(q, sizeof q, arg));
        return -1;
    }
    *lo = a;
    *hi = b;
    return 0;
}
