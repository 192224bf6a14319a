/* SPDX-License-Identifier: MIT */
#include "pfd_cli.h"

#include <string.h>

#include "pfd_start.h"

/* Cross-checks of options that the table cannot express row by row. */
static int check_combination(const pfd_cli *a, char *err, size_t errlen)
{
    pfd_mask inst = 0;
    unsigned i;
    char names[160] = "";
    for (i = 0; i < pfd_settings_count; i++)
        if (pfd_settings_table[i].group == PFD_SG_INSTANCES) {
            inst |= pfd_setting_bit(&pfd_settings_table[i]);
            if (names[0] != '\0')
                strncat(names, ", ", sizeof names - strlen(names) - 1);
            strncat(names, pfd_settings_table[i].flag, sizeof names - strlen(names) - 1);
        }
    if (a->run.config != NULL && (a->given & inst)) {
        snprintf(err, errlen, "%s describe the default instances; with --config set "
                 "them in the file", names);
        return -1;
    }
    if (a->run.fallback && a->run.config == NULL) {
        snprintf(err, errlen, "--config-fallback-defaults needs --config FILE");
        return -1;
    }
    return 0;
}

int pfd_cli_parse(int argc, char *const *argv, pfd_cli *a, char *err, size_t errlen)
{
    int i;

    memset(a, 0, sizeof *a);
    pfd_settings_default(&a->set);
    pfd_run_default(&a->run);
    for (i = 1; i < argc; i++) {
        const char *o = argv[i];
        const pfd_setting *r = pfd_setting_by_flag(o);
        char msg[300];

        if (r == NULL) {
            snprintf(err, errlen, "unknown option '%s' (see pneufracd --help)", o);
            return -1;
        }
        if (!pfd_setting_takes_value(r)) {
            (void)pfd_setting_parse(r, NULL, &a->set, &a->run, msg, sizeof msg);
        } else if (i + 1 >= argc) {
            snprintf(err, errlen, "%s needs a value", o);
            return -1;
        } else if (pfd_setting_parse(r, argv[++i], &a->set, &a->run, msg, sizeof msg) != 0) {
            snprintf(err, errlen, "%s: %s", o, msg);
            return -1;
        }
        a->given |= pfd_setting_bit(r);
        if (r->flags & PFD_SF_STOP)
            return 0;
    }
    return check_combination(a, err, errlen);
}

/* --help's layout: descriptions from column HELP_COL, wrapped before
 * HELP_WIDTH. */
#define HELP_COL 29
#define HELP_WIDTH 79

static const char *const group_title[PFD_SG_COUNT] = {
    "Daemon settings. Each is also a key of the config file's [daemon] section,\n"
    "shown in brackets; the command line wins over the file.",
    "The default instances (without --config):",
    "This run:",
    "Print something and exit:",
};

/* Append @p text at *col, wrapping to HELP_COL between words, or only
 * before it if @p whole. */
static void put_words(FILE *f, const char *text, int whole, int *col)
{
    while (*text != '\0') {
        size_t w = whole ? strlen(text) : strcspn(text, " ");
        if (*col > HELP_COL && *col + 1 + (int)w > HELP_WIDTH) {
            fprintf(f, "\n%*s", HELP_COL, "");
            *col = HELP_COL;
        } else if (*col > HELP_COL) {
            fputc(' ', f);
            (*col)++;
        }
        fprintf(f, "%.*s", (int)w, text);
        *col += (int)w;
        text += w;
        while (*text == ' ')
            text++;
    }
}

static void help_row(FILE *f, const pfd_setting *r, const pfd_settings *s0,
                     const pfd_run *run0)
{
    char head[96], extra[200], val[160];
    size_t k;
    int col, v;

    k = (size_t)snprintf(head, sizeof head, "  %s%s%s", r->flag, r->alias ? ", " : "",
                         r->alias ? r->alias : "");
    if (r->type == PFD_ST_CHOICE)
        for (v = 0; v <= (int)r->hi && k < sizeof head; v++)
            k += (size_t)snprintf(head + k, sizeof head - k, "%c%s", v ? '|' : ' ',
                                  r->choice(v));
    else if (r->metavar != NULL)
        snprintf(head + k, sizeof head - k, " %s", r->metavar);
    /* The description starts at HELP_COL, at least two spaces after the
     * flag, or on a line of its own. */
    col = fprintf(f, "%s", head);
    if (col + 2 > HELP_COL)
        fprintf(f, "\n%*s", HELP_COL, "");
    else
        fprintf(f, "%*s", HELP_COL - col, "");
    col = HELP_COL;
    put_words(f, r->help, 0, &col);

    extra[0] = '\0';
    pfd_setting_format(r, s0, run0, val, sizeof val);
    k = 0;
    if (r->type == PFD_ST_INT || r->type == PFD_ST_REAL)
        k = (size_t)snprintf(extra, sizeof extra, "(%.15g..%.15g%s", r->lo, r->hi,
                             (r->flags & PFD_SF_NODEF) ? ")" : "; ");
    else if (r->type != PFD_ST_BOOL && r->type != PFD_ST_PATH && r->type != PFD_ST_FILE)
        k = (size_t)snprintf(extra, sizeof extra, "(");
    if (k > 0 && !(r->flags & PFD_SF_NODEF))
        snprintf(extra + k, sizeof extra - k, "default %s)", val);
    if (extra[0] != '\0')
        put_words(f, extra, 0, &col);
    if (r->key != NULL) {
        pfd_settings flagged = *s0;
        if (r->type == PFD_ST_BOOL) {
            (void)pfd_setting_parse(r, NULL, &flagged, NULL, val, sizeof val);
            pfd_setting_format(r, &flagged, NULL, val, sizeof val);
            snprintf(extra, sizeof extra, "[%s = %s]", r->key, val);
        } else {
            snprintf(extra, sizeof extra, "[%s]", r->key);
        }
        put_words(f, extra, 1, &col);
    }
    fputc('\n', f);
}

void pfd_cli_help(FILE *f)
{
    pfd_settings s0;
    pfd_run run0;
    unsigned g, i;

    pfd_settings_default(&s0);
    pfd_run_default(&run0);
    fputs("usage: pneufracd [options]\n"
          "\n"
          "Runs the paper's controllers in real time and serves them over Modbus TCP.\n"
          "With no options: one instance, unit id 1, Example 6 (FrDD) at 1 kHz in\n"
          "float, on 127.0.0.1:1502. Register map: docs/register-map.md.\n", f);
    for (g = 0; g < PFD_SG_COUNT; g++) {
        fprintf(f, "\n%s\n", group_title[g]);
        for (i = 0; i < pfd_settings_count; i++)
            if (pfd_settings_table[i].group == g)
                help_row(f, &pfd_settings_table[i], &s0, &run0);
    }
    fprintf(f, "\nExit status: 0 clean stop (SIGTERM, SIGINT, --run-for) or printed what was\n"
               "asked; 1 run-time failure (socket, thread, persisting the config); %d bad\n"
               "arguments or config.\n", PFD_EXIT_USAGE);
}
