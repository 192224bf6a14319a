/* SPDX-License-Identifier: MIT */
/*
 * "pneufrac bode": magnitude and phase of P_c/E at log-spaced omega, for
 *  - the ideal controller: the paper's irrational transfer function
 *    (pfh_ref_tf, principal branch) times the exact output line
 *    e^{-s T}/(1 + s lag), at s = j omega;
 *  - the realised one: the discrete controller designed at fs
 *    (pf_ctrl_freqresp), at z = exp(j omega/fs).
 * Phases are unwrapped along the grid, each from its principal value at
 * the lowest frequency.
 */
#include "cli_bode.h"

#include <complex.h>
#include <math.h>
#include <errno.h>
#include <string.h>

#include "cli_args.h"
#include "cli_csv.h"
#include "cli_options.h"
#include "cli_plot.h"
#include "pfh_fmt.h"
#include "pfh_ref.h"

/* Grid points per decade when --points is not given. */
#define POINTS_PER_DECADE 20

static const cli_command bode_cmd = {
    "bode", cli_bode_usage,
    CLI_OPTS_DESIGN | CLI_OPT_OMEGA | CLI_OPT_POINTS | CLI_OPT_PLOT};

void cli_bode_usage(FILE *f)
{
    fprintf(f,
"usage: pneufrac bode --config {p,dd,id,pid} --fs HZ [--set NAME=VALUE ...]\n"
"                     [--effect lag:tau=S] [--effect deadtime:t=S]\n"
"                     [--omega WMIN:WMAX] [--points N] [--plot FILE.png]\n"
"                     [--band WB:WH] [--order N] [--approx oustaloup|refined]\n"
"                     [--input-model hold|linear] [--t-slow S]\n"
"\n"
"Frequency response P_c/E of the controller, as CSV on standard output:\n"
"columns omega (rad/s), ideal_db, ideal_deg, discrete_db, discrete_deg\n"
"(magnitude in dB, phase in degrees, unwrapped), a '#' line with the units.\n"
"  ideal      the paper's irrational transfer function (eqs. 17, 18, 20;\n"
"             pid: docs/pid.md) at s = j omega, times e^(-s t)/(1 + s tau)\n"
"             for the dead time and lag effects\n"
"  discrete   the controller as realised at --fs (Oustaloup, Tustin, held\n"
"             input, the output line) at z = exp(j omega/fs)\n"
"Backlash, nozzle and saturation are nonlinear: no frequency response.\n"
"\n"
"  --omega WMIN:WMAX  frequency range, rad/s (default: a decade below the\n"
"                     band's lower edge to 0.99*pi*fs; at pi*fs the held\n"
"                     input's mean has its zero, -inf dB)\n"
"  --points N         log-spaced frequencies, 2..%d (default %d per decade)\n"
"  --plot FILE.png    also draw it, with pneufrac-plot (the Python tools)\n"
"The model and design options are those of 'pneufrac simulate --help'.\n"
"\n", CLI_MAX_POINTS, POINTS_PER_DECADE);
    cli_exit_status_help(f, 1);
}

/* prev + the multiple of 360 degrees that puts deg within 180 of prev */
static double unwrap(double deg, double prev)
{
    return deg - 360.0 * round((deg - prev) / 360.0);
}

/* The first failed write: saved when it fails, as the writes and the
 * formatting of the values after it (pfh_fmt's strtod) may set errno again,
 * and the first failure is the one to report. failed, not err, says whether
 * one was seen: a failing call that leaves errno 0 (a stream that sets none)
 * reads EIO, not "no failure yet". */
typedef struct {
    int failed, err;
} write_err;

static void failed_now(write_err *we)
{
    if (!we->failed) {
        we->failed = 1;
        we->err = errno != 0 ? errno : EIO;
    }
}

/* Writes v then @p after. errno is cleared first, so that a failing call
 * that sets none is told from one that does (failed_now's EIO). */
static void put(FILE *f, double v, const char *after, write_err *we)
{
    errno = 0;
    if (pfh_fput_double(f, v) == EOF || fputs(after, f) == EOF)
        failed_now(we);
}

/* Whether a write to @p f failed; @p we holds the first failed write's
 * errno (put), or, for an error no call reported, errno now. */
static int write_failed(FILE *f, write_err *we)
{
    if (!ferror(f))
        return 0;
    failed_now(we);
    return 1;
}

/* @return CLI_EXIT_OK, or CLI_EXIT_IO with the write's errno in @p we. */
static int write_bode(FILE *f, const pf_ctrl_design *d, const pf_effects *fx,
                      double w_lo, double w_hi, int points, write_err *we)
{
    char note[200];
    /* dead times: the exact one, and the realised one in whole samples */
    const double td_ideal = fx->dead_time, td_real = d->rt.delay_len / d->opt.fs;
    double prev_i = 0.0, prev_d = 0.0;
    int k, have_i = 0, have_d = 0;

    snprintf(note, sizeof note, "config %s, fs = %g Hz, band [%g, %g] rad/s, N = %d",
             pf_topology_name(d->p.topology), d->opt.fs, d->opt.wb, d->opt.wh,
             d->opt.order);
    if (cli_csv_head(f, "omega,ideal_db,ideal_deg,discrete_db,discrete_deg",
                     "rad/s,dB,degrees,dB,degrees") != 0 ||
        fprintf(f, "# pneufrac bode: %s\n", note) < 0) {
        failed_now(we);
        return CLI_EXIT_IO;
    }
    for (k = 0; k < points; k++) {
        double w = w_lo * pow(w_hi / w_lo, (double)k / (points - 1));
        /* The dead time's phase -omega T is added in closed form after the
         * unwrapping, which a grid could not follow at high frequency. */
        double complex hi = pfh_ref_tf(&d->p, I * w) * pfh_ref_line(fx, I * w) *
                            cexp(I * w * td_ideal);
        double complex hd;
        double re, im, mi, md, pi_, pd = NAN;
        pf_ctrl_freqresp(d, w, &re, &im);
        hd = (re + I * im) * cexp(I * w * td_real);
        mi = cabs(hi);
        md = cabs(hd);
        pi_ = carg(hi) * 180.0 / M_PI;
        pi_ = have_i ? unwrap(pi_, prev_i) : pi_;
        prev_i = pi_;
        have_i = 1;
        if (md > 0.0) {
            pd = carg(hd) * 180.0 / M_PI;
            pd = have_d ? unwrap(pd, prev_d) : pd;
            prev_d = pd;
            have_d = 1;
        }
        put(f, w, ",", we);
        put(f, 20.0 * log10(mi), ",", we);
        put(f, pi_ - w * td_ideal * 180.0 / M_PI, ",", we);
        put(f, md > 0.0 ? 20.0 * log10(md) : -INFINITY, ",", we);
        put(f, md > 0.0 ? pd - w * td_real * 180.0 / M_PI : NAN, "\n", we);
        if (write_failed(f, we))
            return CLI_EXIT_IO;
    }
    if (fflush(f) != 0 || ferror(f)) { /* each row was checked: this is the flush */
        failed_now(we);
        return CLI_EXIT_IO;
    }
    return CLI_EXIT_OK;
}

int cli_bode_main(int argc, char **argv)
{
    static pf_ctrl_design d;
    cli_opts a;
    cli_run run;
    cli_plot plot;
    double w_lo, w_hi;
    write_err we = {0, 0};
    int rc, points;

    rc = cli_opts_read(argc, argv, &bode_cmd, &a, &run);
    if (rc != 0)
        return rc > 0 ? CLI_EXIT_OK : CLI_EXIT_USAGE;
    if (cli_run_design(&run, &d) != CLI_EXIT_OK)
        return CLI_EXIT_USAGE;
    if (d.rt.in_loop_fx) {
        cli_error("bode: backlash, nozzle and saturation are nonlinear: no "
                  "frequency response (lag and deadtime are linear)");
        return CLI_EXIT_USAGE;
    }
    w_lo = (a.seen & CLI_OPT_OMEGA) ? a.w_lo : 0.1 * d.opt.wb;
    w_hi = (a.seen & CLI_OPT_OMEGA) ? a.w_hi : 0.99 * M_PI * d.opt.fs;
    if (!(w_hi > w_lo)) {
        cli_error("bode: the default range [%g, %g] rad/s is empty; give --omega",
                  w_lo, w_hi);
        return CLI_EXIT_USAGE;
    }
    points = a.points;
    if (points == 0)
        points = (int)fmin(CLI_MAX_POINTS,
                           ceil(POINTS_PER_DECADE * log10(w_hi / w_lo)) + 1.0);
    if (cli_plot_begin(&plot, a.plot) != 0)
        return CLI_EXIT_IO;
    rc = write_bode(plot.csv, &d, &run.fx, w_lo, w_hi, points, &we);
    if (rc != CLI_EXIT_OK)
        cli_error("bode: error writing the CSV: %s", strerror(we.err));
    return cli_plot_finish(&plot, "bode", rc);
}
