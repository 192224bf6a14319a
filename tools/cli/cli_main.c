/* SPDX-License-Identifier: MIT */
/* pneufrac: the command-line front end (main and the command dispatch:
 * simulate, demo, design, reproduce). */
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>

#include "pneufrac/pneufrac.h"

#include "cli_args.h"
#include "cli_bode.h"
#include "cli_demo.h"
#include "cli_design.h"
#include "cli_reproduce.h"
#include "cli_simulate.h"
#include "cli_step.h"

/* Long runs write hundreds of megabytes of CSV; line or 4 KiB buffering
 * would spend more time in write(2) than in the controller. */
static char stdout_buf[1 << 20];

static void usage(FILE *f)
{
    fprintf(f,
"usage: pneufrac <command> [options]\n"
"       pneufrac --help | --version\n"
"\n"
"Fractional-order models of industrial pneumatic controllers (Razminia &\n"
"Baleanu), in double, float and Q15.\n"
"\n"
"commands:\n"
"  simulate   run a controller (p, dd, id, pid) and write t,e,pc as CSV\n"
"  step       its unit-step response beside the exact one, as CSV [--plot]\n"
"  bode       frequency response, ideal and realised at fs, as CSV [--plot]\n"
"  demo       the paper's Example 6 with a summary; writes example6.csv\n"
"  design     design a controller; export its coefficients (C header, JSON,\n"
"             CMSIS-DSP biquads) or the realised system (ss, zpk, sos)\n"
"  reproduce  the data of the paper's figures as CSV (plots: scripts/reproduce.sh)\n"
"\n"
"'pneufrac <command> --help' describes a command's options.\n"
"\n");
    cli_exit_status_help(f, 1);
}

static int dispatch(int argc, char **argv)
{
    char q[48];
    const char *cmd;

    if (argc < 2) {
        cli_error("no command given (try 'pneufrac --help')");
        return CLI_EXIT_USAGE;
    }
    cmd = argv[1];
    if (strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0 ||
        strcmp(cmd, "help") == 0) {
        usage(stdout);
        return CLI_EXIT_OK;
    }
    if (strcmp(cmd, "--version") == 0) {
        printf("pneufrac %s\n", PNEUFRAC_VERSION_STRING);
        return CLI_EXIT_OK;
    }
    if (strcmp(cmd, "simulate") == 0)
        return cli_simulate_main(argc - 1, argv + 1);
    if (strcmp(cmd, "step") == 0)
        return cli_step_main(argc - 1, argv + 1);
    if (strcmp(cmd, "bode") == 0)
        return cli_bode_main(argc - 1, argv + 1);
    if (strcmp(cmd, "demo") == 0)
        return cli_demo_main(argc - 1, argv + 1);
    if (strcmp(cmd, "design") == 0)
        return cli_design_main(argc - 1, argv + 1);
    if (strcmp(cmd, "reproduce") == 0)
        return cli_reproduce_main(argc - 1, argv + 1);
    cli_error("unknown command '%s' (valid: simulate, step, bode, demo, design, "
              "reproduce; try "
              "'pneufrac --help')", cli_quote(q, sizeof q, cmd));
    return CLI_EXIT_USAGE;
}

int main(int argc, char **argv)
{
    int rc, flush_err;

#ifdef SIGPIPE
    /* A closed pipe (| head) must surface as a write error we report with
     * exit status 1, not as a silent death by signal. */
    signal(SIGPIPE, SIG_IGN);
#endif
    setvbuf(stdout, stdout_buf, _IOFBF, sizeof stdout_buf);
    rc = dispatch(argc, argv);
    /* Help, version and the demo summary are output too: check them. A
     * failure already reported keeps its own status and message. errno is
     * the reason only when this fflush failed (read at once, before
     * ferror); a write that failed earlier, with the flush then finding
     * nothing to write, left no reason here: EIO, not a stale errno. A
     * failing flush that sets no errno also reads EIO. */
    errno = 0;
    flush_err = fflush(stdout) != 0 ? (errno != 0 ? errno : EIO) : 0;
    if (flush_err != 0 || ferror(stdout)) {
        if (rc == CLI_EXIT_OK) {
            cli_error("error writing standard output: %s",
                      strerror(flush_err != 0 ? flush_err : EIO));
            rc = CLI_EXIT_IO;
        }
    }
    return rc;
}
