/* SPDX-License-Identifier: MIT */
/*
 * "pneufrac step": the unit-step response as `simulate` writes it, plus
 * the exact response of the irrational controller (numerical inverse
 * Laplace transform, pfh_ref_step_fx) in a column pc_exact, and a plot.
 */
#include "cli_step.h"

#include "cli_args.h"
#include "cli_options.h"
#include "cli_plot.h"
#include "cli_simulate.h"

static const cli_command step_cmd = {
    "step", cli_step_usage,
    CLI_OPTS_DESIGN | CLI_OPTS_ARITH | CLI_OPT_DURATION | CLI_OPT_PLOT};

void cli_step_usage(FILE *f)
{
    fprintf(f,
"usage: pneufrac step --config {p,dd,id,pid} --fs HZ --duration S [options]\n"
"                     [--plot FILE.png]\n"
"\n"
"The unit-step response, as 'pneufrac simulate' writes it (t,e,pc, and\n"
"pc_q15 in q15), with one more column pc_exact: the exact response of the\n"
"paper's irrational controller (numerical inverse Laplace transform,\n"
"Talbot's contour), with the lag and dead time effects; nan at t = 0, where\n"
"it jumps. With backlash, nozzle or saturation there is no exact column.\n"
"The options are those of 'pneufrac simulate --help' except --input, and:\n"
"  --plot FILE.png    also draw it, with pneufrac-plot (the Python tools)\n"
"\n");
    cli_exit_status_help(f, 1);
}

int cli_step_main(int argc, char **argv)
{
    static pf_ctrl_design d;
    cli_opts a;
    cli_run run;
    cli_plot plot;
    int rc;

    rc = cli_opts_read(argc, argv, &step_cmd, &a, &run);
    if (rc != 0)
        return rc > 0 ? CLI_EXIT_OK : CLI_EXIT_USAGE;
    rc = cli_run_design(&run, &d);
    if (rc != CLI_EXIT_OK)
        return rc;
    run.exact = !d.rt.in_loop_fx;
    if (cli_plot_begin(&plot, a.plot) != 0)
        return CLI_EXIT_IO;
    rc = cli_run_write(&run, &d, plot.csv,
                       plot.png != NULL ? "the temporary CSV" : "standard output", NULL,
                       NULL);
    return cli_plot_finish(&plot, "step", rc);
}
