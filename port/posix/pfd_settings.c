/* SPDX-License-Identifier: MIT */
#include "pfd_settings.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "pfd_access.h"
#include "pfd_parse.h"
#include "pfd_regmap.h"
#include "pfd_state.h"
#include "pfh_fmt.h"

const char *pfd_clock_name(int external)
{
    return external == 1 ? "external" : external == 0 ? "internal" : "?";
}

#define SECURE .flags = PFD_SF_SECURE
#define IN_SETTINGS(m) .off = offsetof(pfd_settings, m), .size = sizeof(((pfd_settings *)0)->m)
#define IN_RUN(m) .off = offsetof(pfd_run, m), .size = sizeof(((pfd_run *)0)->m)

/* The daemon group keeps the order in which the daemon writes the
 * [daemon] section; --help lists the groups in enum order. */
const pfd_setting pfd_settings_table[] = {
    /* daemon-wide: command line and config file */
    /* A security setting: it decides who can reach the port at all
     * (docs/pneufracd.md, "What each setting protects"). */
    {.flag = "--listen", .key = "listen", .type = PFD_ST_ENDPOINT, .group = PFD_SG_DAEMON,
     SECURE, IN_SETTINGS(listen), .metavar = "ADDR:PORT",
     .help = "IPv4 address and port to serve; port 0 picks a free one, logged as "
             "msg=listening"},
    {.flag = "--clock", .key = "clock", .type = PFD_ST_CHOICE, .group = PFD_SG_DAEMON,
     .lo = 0, .hi = 1, .choice = pfd_clock_name, IN_SETTINGS(external_clock),
     .help = "external: only the tick register advances samples, for lockstep"},
    {.flag = "--word-order", .key = "word_order", .type = PFD_ST_CHOICE,
     .group = PFD_SG_DAEMON, .lo = 0, .hi = PFD_WORDS_COUNT - 1,
     .choice = pfd_word_order_name, IN_SETTINGS(word_order),
     .help = "register order of every 32-bit value (f32, u32), read and written: "
             "abcd high word first, cdab low word first (docs/register-map.md)"},
    {.flag = "--max-clients", .key = "max_clients", .type = PFD_ST_INT,
     .group = PFD_SG_DAEMON, SECURE, .lo = 1, .hi = 256, IN_SETTINGS(max_clients),
     .metavar = "N", .help = "simultaneous clients"},
    {.flag = "--allow", .key = "allow", .type = PFD_ST_NETS, .group = PFD_SG_DAEMON,
     SECURE, IN_SETTINGS(allow), .metavar = "CIDR[,CIDR...]",
     .help = "client networks allowed to connect"},
    {.flag = "--read-only", .key = "read_only", .type = PFD_ST_BOOL,
     .group = PFD_SG_DAEMON, SECURE, .flag_value = 1, IN_SETTINGS(read_only),
     .help = "refuse every write (exception 01)", .fallback = "yes"},
    {.flag = "--param-lock", .key = "param_lock", .type = PFD_ST_BOOL,
     .group = PFD_SG_DAEMON, SECURE, .flag_value = 1, IN_SETTINGS(param_lock),
     .help = "lock parameters, commit, commands and the output settings for this run, "
             "for every client", .fallback = "yes"},
    {.flag = "--rt-priority", .key = "rt_priority", .type = PFD_ST_INT,
     .group = PFD_SG_DAEMON, .lo = 0, .hi = 99, IN_SETTINGS(rt_priority),
     .metavar = "N", .help = "SCHED_FIFO priority of the loop; 0 = do not ask"},
    /* A security setting: it bounds what a client that may commit can make
     * the loop cost (issue 12, O4), so a fallback never takes it from the
     * file; it runs at the default (docs/pneufracd.md, "Loop budget"). */
    {.flag = "--loop-budget", .key = "loop_budget", .type = PFD_ST_INT,
     .group = PFD_SG_DAEMON, SECURE, .lo = 1, .hi = 95, IN_SETTINGS(loop_budget),
     .metavar = "PERCENT",
     .help = "share of one core the loop may need, by the costs measured at start and "
             "at each commit; a start or commit that needs more is refused (internal "
             "clock)"},
    {.flag = "--no-mlock", .key = "mlock", .type = PFD_ST_BOOL, .group = PFD_SG_DAEMON,
     .flag_value = 0, IN_SETTINGS(mlock), .help = "do not mlockall()"},
    {.flag = "--overrun-report-s", .key = "overrun_report_s", .type = PFD_ST_INT,
     .group = PFD_SG_DAEMON, .lo = 1, .hi = 3600, IN_SETTINGS(overrun_report_s),
     .metavar = "N", .help = "at most one msg=overruns line this often, with the "
                             "overruns of every instance since the line before"},
    {.flag = "--byte-timeout-ms", .key = "byte_timeout_ms", .type = PFD_ST_INT,
     .group = PFD_SG_DAEMON, SECURE, .lo = 1, .hi = 10000, IN_SETTINGS(byte_timeout_ms),
     .metavar = "N", .help = "drop a client that stalls this long mid-frame"},
    {.flag = "--idle-timeout-s", .key = "idle_timeout_s", .type = PFD_ST_INT,
     .group = PFD_SG_DAEMON, SECURE, .lo = 0, .hi = 86400, IN_SETTINGS(idle_timeout_s),
     .metavar = "N", .help = "drop a client that has completed no request for this long; "
                             "0 = never"},
    {.flag = "--max-clients-per-addr", .key = "max_clients_per_addr", .type = PFD_ST_INT,
     .group = PFD_SG_DAEMON, SECURE, .lo = 1, .hi = 256, IN_SETTINGS(max_per_addr),
     .metavar = "N", .help = "simultaneous clients from one IPv4 address; one more from "
                             "that address replaces one of its own, idle ones first"},
    {.flag = "--first-request-timeout-ms", .key = "first_request_timeout_ms",
     .type = PFD_ST_INT, .group = PFD_SG_DAEMON, SECURE, .lo = 100, .hi = 60000,
     IN_SETTINGS(first_request_ms), .metavar = "N",
     .help = "drop a connection that has not completed its TLS handshake and a "
             "first request this long after it was accepted"},
    {.flag = "--plain-access", .key = "plain_access", .type = PFD_ST_CHOICE,
     .group = PFD_SG_DAEMON, SECURE, .lo = 0, .hi = PFD_ACCESS_COUNT - 1,
     .choice = pfd_access_name, IN_SETTINGS(plain_access),
     .help = "what plain Modbus TCP clients may do (docs/register-map.md, column "
             "Write); none: no plain listener"},
    {.flag = "--tls-listen", .key = "tls_listen", .type = PFD_ST_ENDPOINT,
     .group = PFD_SG_DAEMON, .flags = PFD_SF_SECURE | PFD_SF_OFF, .lo = 802,
     IN_SETTINGS(tls_listen), .metavar = "ADDR[:PORT]|none",
     .help = "Modbus/TCP Security listener: TLS 1.2+, client certificate required "
             "(port 802 if omitted)"},
    {.flag = "--tls-cert", .key = "tls_cert", .type = PFD_ST_FILE, .group = PFD_SG_DAEMON,
     SECURE, IN_SETTINGS(tls_cert), .metavar = "FILE",
     .help = "the server's certificate chain (PEM)"},
    {.flag = "--tls-key", .key = "tls_key", .type = PFD_ST_FILE, .group = PFD_SG_DAEMON,
     SECURE, IN_SETTINGS(tls_key), .metavar = "FILE",
     .help = "the server's private key (PEM)"},
    {.flag = "--tls-ca", .key = "tls_ca", .type = PFD_ST_FILE, .group = PFD_SG_DAEMON,
     SECURE, IN_SETTINGS(tls_ca), .metavar = "FILE",
     .help = "CA certificates (PEM) that client certificates must chain to"},
    {.flag = "--tls-roles", .key = "tls_roles", .type = PFD_ST_ROLES,
     .group = PFD_SG_DAEMON, SECURE, IN_SETTINGS(tls_roles),
     .metavar = "ROLE:ACCESS[,...]",
     .help = "access granted to each role a client certificate carries (OID "
             "1.3.6.1.4.1.50316.802.1); other roles are refused"},

    /* the default instances */
    {.flag = "--instances", .type = PFD_ST_INT, .group = PFD_SG_INSTANCES, .lo = 1,
     .hi = PFD_MAX_INSTANCES, IN_RUN(instances), .metavar = "N",
     .help = "N instances, unit ids 1..N"},
    {.flag = "--controller", .type = PFD_ST_CHOICE, .group = PFD_SG_INSTANCES, .lo = 0,
     .hi = PF_TOPO_COUNT - 1, .choice = pfd_topology_name, IN_RUN(controller),
     .help = "their configuration"},
    {.flag = "--fs", .type = PFD_ST_REAL, .group = PFD_SG_INSTANCES, .lo = PFD_FS_MIN,
     .hi = PFD_FS_MAX, IN_RUN(fs), .metavar = "HZ",
     .help = "their exchange rate: the loop takes e and publishes p_c this often"},
    {.flag = "--substeps", .type = PFD_ST_INT, .group = PFD_SG_INSTANCES, .lo = 0,
     .hi = PFD_SUBSTEPS_MAX, IN_RUN(substeps), .metavar = "K",
     .help = "their controller steps per exchange, the input held; 0 = from the "
             "design's fastest time constant"},
    {.flag = "--arith", .type = PFD_ST_CHOICE, .group = PFD_SG_INSTANCES, .lo = 0,
     .hi = PFD_ARITH_COUNT - 1, .choice = pfd_arith_name, IN_RUN(arith),
     .help = "their arithmetic"},

    /* this run */
    {.flag = "--config", .type = PFD_ST_PATH, .group = PFD_SG_RUN, IN_RUN(config),
     .metavar = "FILE",
     .help = "instances and settings (docs/pneufracd.md); commits and the state at "
             "shutdown are written back to it"},
    {.flag = "--config-fallback-defaults", .type = PFD_ST_BOOL, .group = PFD_SG_RUN,
     .flag_value = 1, IN_RUN(fallback),
     .help = "if FILE is missing, corrupt or holds a set that cannot be designed, "
             "run the default instances read-only and with parameters locked, and "
             "log why; FILE is left as it is and never rewritten by this run"},
    {.flag = "--run-for", .type = PFD_ST_REAL, .group = PFD_SG_RUN, .flags = PFD_SF_NODEF,
     .lo = 0.001, .hi = 1e7, IN_RUN(run_for), .metavar = "S",
     .help = "stop by itself after S seconds, for tests"},
    {.flag = "--verbose", .type = PFD_ST_BOOL, .group = PFD_SG_RUN, .flag_value = 1,
     IN_RUN(verbose), .help = "also log debug lines (client connects and drops)"},

    /* print and exit */
    {.flag = "--print-register-map", .type = PFD_ST_BOOL, .group = PFD_SG_EXIT,
     .flag_value = 1, IN_RUN(print_map), .help = "print the register table (Markdown)"},
    {.flag = "--print-default-config", .type = PFD_ST_BOOL, .group = PFD_SG_EXIT,
     .flag_value = 1, IN_RUN(print_config),
     .help = "print a config file for the default instances"},
    {.flag = "--init-config", .type = PFD_ST_PATH, .group = PFD_SG_EXIT, IN_RUN(init),
     .metavar = "FILE",
     .help = "write that config file to FILE, unless FILE exists, which is left as it "
             "is: a first start's config (the service's ExecStartPre)"},
    {.flag = "--seal-config", .type = PFD_ST_PATH, .group = PFD_SG_EXIT, IN_RUN(seal),
     .metavar = "FILE", .help = "check FILE and rewrite its checksum"},
    {.flag = "--version", .type = PFD_ST_BOOL, .group = PFD_SG_EXIT,
     .flags = PFD_SF_STOP, .flag_value = 1, IN_RUN(version),
     .help = "print the version and the register map's version"},
    {.flag = "--help", .alias = "-h", .type = PFD_ST_BOOL, .group = PFD_SG_EXIT,
     .flags = PFD_SF_STOP, .flag_value = 1, IN_RUN(help), .help = "print this help"},
};
const unsigned pfd_settings_count = sizeof pfd_settings_table / sizeof pfd_settings_table[0];

/* Masks of given settings have one bit a row. */
typedef char pfd_settings_fit_a_mask[sizeof pfd_settings_table /
                                     sizeof pfd_settings_table[0] <= 64 ? 1 : -1];

const pfd_setting *pfd_setting_by_flag(const char *flag)
{
    unsigned i;
    for (i = 0; i < pfd_settings_count; i++) {
        const pfd_setting *r = &pfd_settings_table[i];
        if (!strcmp(r->flag, flag) || (r->alias != NULL && !strcmp(r->alias, flag)))
            return r;
    }
    return NULL;
}

const pfd_setting *pfd_setting_by_key(const char *key)
{
    unsigned i;
    for (i = 0; i < pfd_settings_count; i++) {
        const pfd_setting *r = &pfd_settings_table[i];
        if (r->key != NULL && !strcmp(r->key, key))
            return r;
    }
    return NULL;
}

pfd_mask pfd_setting_bit(const pfd_setting *r)
{
    return (pfd_mask)1 << (unsigned)(r - pfd_settings_table);
}

int pfd_setting_takes_value(const pfd_setting *r)
{
    return r->type != PFD_ST_BOOL;
}

static void *field(const pfd_setting *r, pfd_settings *s, pfd_run *run)
{
    return (char *)(r->group == PFD_SG_DAEMON ? (void *)s : (void *)run) + r->off;
}

static const void *cfield(const pfd_setting *r, const pfd_settings *s, const pfd_run *run)
{
    return field(r, (pfd_settings *)s, (pfd_run *)run);
}

static int parse_bool(const char *text, int *out)
{
    static const char *const yes[] = {"yes", "true", "1", "on"};
    static const char *const no[] = {"no", "false", "0", "off"};
    unsigned i;
    for (i = 0; i < sizeof yes / sizeof yes[0]; i++) {
        if (!strcmp(text, yes[i])) {
            *out = 1;
            return 0;
        }
        if (!strcmp(text, no[i])) {
            *out = 0;
            return 0;
        }
    }
    return -1;
}

static int refuse(char *msg, size_t n, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, n, fmt, ap);
    va_end(ap);
    return -1;
}

/* ADDR:PORT; with a default port (lo > 0) also ADDR alone, and with
 * PFD_SF_OFF also "none" (addr ""). */
static int parse_endpoint(const pfd_setting *r, const char *text, pfd_endpoint *out)
{
    char buf[64];
    if ((r->flags & PFD_SF_OFF) && !strcmp(text, "none")) {
        out->addr[0] = '\0';
        out->port = 0;
        return 0;
    }
    if (r->lo > 0 && strchr(text, ':') == NULL && strlen(text) < 40) {
        snprintf(buf, sizeof buf, "%s:%d", text, (int)r->lo);
        text = buf;
    }
    return pfd_endpoint_parse(text, out);
}

int pfd_setting_parse(const pfd_setting *r, const char *text, pfd_settings *s,
                      pfd_run *run, char *msg, size_t n)
{
    void *f = field(r, s, run);
    char names[128];
    pfd_allow al;
    pfd_roles roles;
    long l;
    double x;
    int v;

    switch (r->type) {
    case PFD_ST_BOOL:
        if (text == NULL)
            v = r->flag_value;
        else if (parse_bool(text, &v) != 0)
            return refuse(msg, n, "'%s' is not yes or no", text);
        *(int *)f = v;
        break;
    case PFD_ST_INT:
        if (pfd_parse_int(text, (long)r->lo, (long)r->hi, &l) != 0)
            return refuse(msg, n, "'%s' is not an integer in %.15g..%.15g", text, r->lo,
                          r->hi);
        *(int *)f = (int)l;
        break;
    case PFD_ST_REAL:
        if (pfd_parse_number(text, &x) != 0 || x < r->lo || x > r->hi)
            return refuse(msg, n, "'%s' is not a number in %g..%g", text, r->lo, r->hi);
        *(double *)f = x;
        break;
    case PFD_ST_CHOICE:
        v = pfd_parse_name(text, r->choice, (int)r->hi + 1);
        if (v < 0) {
            pfd_parse_names(r->choice, (int)r->hi + 1, names, sizeof names);
            return refuse(msg, n, "'%s' is not %s", text, names);
        }
        *(int *)f = v;
        break;
    case PFD_ST_ENDPOINT:
        if (parse_endpoint(r, text, (pfd_endpoint *)f) != 0)
            return refuse(msg, n, "'%s' is not IPV4ADDR:PORT%s (e.g. 127.0.0.1:1502)", text,
                          (r->flags & PFD_SF_OFF) ? ", IPV4ADDR or none" : "");
        break;
    case PFD_ST_FILE:
    case PFD_ST_ROLES:
    case PFD_ST_NETS:
        /* Text kept as given, once it is known to mean something. */
        if (strlen(text) >= r->size || strchr(text, '\n') != NULL)
            return refuse(msg, n, "'%.40s...' is too long", text);
        if ((r->type == PFD_ST_NETS && pfd_allow_parse(text, &al, msg, n) != 0) ||
            (r->type == PFD_ST_ROLES && pfd_roles_parse(text, &roles, msg, n) != 0))
            return -1;
        strcpy((char *)f, text);
        break;
    default: /* PFD_ST_PATH: the text itself, which outlives the run */
        *(const char **)f = text;
        break;
    }
    return 0;
}

void pfd_setting_format(const pfd_setting *r, const pfd_settings *s,
                        const pfd_run *run, char *buf, size_t n)
{
    const void *f = cfield(r, s, run);

    switch (r->type) {
    case PFD_ST_BOOL:
        snprintf(buf, n, "%s", *(const int *)f ? "yes" : "no");
        break;
    case PFD_ST_INT:
        snprintf(buf, n, "%d", *(const int *)f);
        break;
    case PFD_ST_REAL: {
        char num[PFH_FMT_LEN]; /* shortest text that reads back exactly */
        pfh_fmt_double(num, *(const double *)f);
        snprintf(buf, n, "%s", num);
        break;
    }
    case PFD_ST_CHOICE:
        snprintf(buf, n, "%s", r->choice(*(const int *)f));
        break;
    case PFD_ST_ENDPOINT: {
        const pfd_endpoint *e = (const pfd_endpoint *)f;
        if (e->addr[0] == '\0')
            snprintf(buf, n, "none");
        else
            snprintf(buf, n, "%s:%d", e->addr, e->port);
        break;
    }
    case PFD_ST_NETS:
    case PFD_ST_FILE:
    case PFD_ST_ROLES:
        snprintf(buf, n, "%s", (const char *)f);
        break;
    default:
        snprintf(buf, n, "%s", *(const char *const *)f ? *(const char *const *)f : "");
        break;
    }
}

void pfd_settings_copy(pfd_settings *dst, const pfd_settings *src, pfd_mask mask)
{
    unsigned i;
    for (i = 0; i < pfd_settings_count; i++) {
        const pfd_setting *r = &pfd_settings_table[i];
        if (r->group == PFD_SG_DAEMON && (mask & pfd_setting_bit(r)))
            memcpy((char *)dst + r->off, (const char *)src + r->off, r->size);
    }
}

void pfd_settings_default(pfd_settings *s)
{
    memset(s, 0, sizeof *s);
    strcpy(s->listen.addr, "127.0.0.1");
    s->listen.port = 1502;
    s->external_clock = 0;
    s->word_order = PFD_WORDS_ABCD;
    s->max_clients = 16;
    strcpy(s->allow, PFD_ALLOW_DEFAULT);
    s->read_only = 0;
    s->param_lock = 0;
    s->rt_priority = 80;
    s->loop_budget = 50;
    s->mlock = 1;
    s->overrun_report_s = 10;
    s->byte_timeout_ms = 100;
    s->idle_timeout_s = 300;
    s->max_per_addr = 8;
    s->first_request_ms = 2000;
    s->plain_access = PFD_ACCESS_ENGINEER;
    s->tls_listen.addr[0] = '\0';
    strcpy(s->tls_roles, "viewer:read,operator:operate,engineer:engineer");
}

void pfd_settings_fallback(pfd_settings *s)
{
    unsigned i;
    pfd_settings_default(s);
    for (i = 0; i < pfd_settings_count; i++) {
        const pfd_setting *r = &pfd_settings_table[i];
        char msg[200];
        /* The table is tested: a fallback value always parses. */
        if ((r->flags & PFD_SF_SECURE) && r->fallback != NULL)
            (void)pfd_setting_parse(r, r->fallback, s, NULL, msg, sizeof msg);
    }
}

void pfd_run_default(pfd_run *run)
{
    pfd_iparams ip;

    memset(run, 0, sizeof *run);
    pfd_iparams_default(&ip);
    run->instances = 1;
    run->controller = (int)ip.p.topology;
    run->fs = ip.fs;
    run->substeps = (int)ip.substeps;
    run->arith = ip.arith;
}

/* A file the TLS listener loads: readable now, or why not (OpenSSL's own
 * error for a missing file reads only "failed"). */
static int check_readable(const char *flag, const char *key, const char *path, char *err,
                          size_t n)
{
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        snprintf(err, n, "%s %s (config key %s): cannot read: %s", flag, path, key,
                 strerror(errno));
        return -1;
    }
    fclose(f);
    return 0;
}

int pfd_settings_check(const pfd_settings *s, char *err, size_t n)
{
    const int tls = s->tls_listen.addr[0] != '\0';

    if (tls && (s->tls_cert[0] == '\0' || s->tls_key[0] == '\0' || s->tls_ca[0] == '\0')) {
        snprintf(err, n, "--tls-listen needs --tls-cert, --tls-key and --tls-ca (config "
                 "keys tls_listen, tls_cert, tls_key, tls_ca)");
        return -1;
    }
    if (tls && (check_readable("--tls-cert", "tls_cert", s->tls_cert, err, n) != 0 ||
                check_readable("--tls-key", "tls_key", s->tls_key, err, n) != 0 ||
                check_readable("--tls-ca", "tls_ca", s->tls_ca, err, n) != 0))
        return -1;
    if (s->plain_access == PFD_ACCESS_NONE && !tls) {
        snprintf(err, n, "--plain-access none needs --tls-listen (config keys plain_access, "
                 "tls_listen): there would be no listener");
        return -1;
    }
    return 0;
}
