/* SPDX-License-Identifier: MIT */
#include "cli_plot.h"

#include <errno.h>
#include <spawn.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli_args.h"

extern char **environ;

/* The plotting program's name when PNEUFRAC_PLOT does not name another. */
#define PLOT_PROGRAM "pneufrac-plot"

int cli_plot_begin(cli_plot *p, const char *png)
{
    int fd;
    memset(p, 0, sizeof *p);
    p->png = png;
    if (png == NULL) {
        p->csv = stdout;
        return 0;
    }
    snprintf(p->path, sizeof p->path, "%s/pneufrac-plot-XXXXXX",
             getenv("TMPDIR") != NULL && strlen(getenv("TMPDIR")) < 32
                 ? getenv("TMPDIR") : "/tmp");
    fd = mkstemp(p->path);
    if (fd < 0 || (p->csv = fdopen(fd, "w+")) == NULL) {
        cli_error("--plot: cannot create a temporary file: %s", strerror(errno));
        if (fd >= 0) {
            close(fd);
            unlink(p->path);
        }
        return -1;
    }
    return 0;
}

static int copy_to_stdout(FILE *from)
{
    char buf[65536];
    size_t n;
    rewind(from);
    while ((n = fread(buf, 1, sizeof buf, from)) > 0)
        if (fwrite(buf, 1, n, stdout) != n)
            return -1;
    return ferror(from) || fflush(stdout) != 0 ? -1 : 0;
}

static int run_plotter(const char *kind, const char *csv, const char *png)
{
    const char *prog = getenv("PNEUFRAC_PLOT");
    posix_spawn_file_actions_t fa;
    char *argv[5];
    pid_t pid;
    int rc, status;

    if (prog == NULL || *prog == '\0')
        prog = PLOT_PROGRAM;
    argv[0] = (char *)prog;
    argv[1] = (char *)kind;
    argv[2] = (char *)csv;
    argv[3] = (char *)png;
    argv[4] = NULL;
    /* Standard output carries the CSV: the plotter's chatter goes to
     * standard error. */
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_adddup2(&fa, 2, 1);
    rc = posix_spawnp(&pid, prog, &fa, NULL, argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0) {
        cli_error("--plot: cannot run '%s': %s (it comes with the Python tools: "
                  "scripts/setup.sh puts it in .venv/bin, so put that on PATH or "
                  "set PNEUFRAC_PLOT to its full path; or pip install "
                  "./tools/python); the CSV was written", prog, strerror(rc));
        return CLI_EXIT_PLOT;
    }
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) {
            cli_error("--plot: waiting for '%s': %s", prog, strerror(errno));
            return CLI_EXIT_PLOT;
        }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        cli_error("--plot: '%s' failed (%s %d); the CSV was written", prog,
                  WIFEXITED(status) ? "exit status" : "signal",
                  WIFEXITED(status) ? WEXITSTATUS(status) : WTERMSIG(status));
        return CLI_EXIT_PLOT;
    }
    return CLI_EXIT_OK;
}

int cli_plot_finish(cli_plot *p, const char *kind, int rc)
{
    if (p->png == NULL)
        return rc;
    if (rc == CLI_EXIT_OK && (fflush(p->csv) != 0 || copy_to_stdout(p->csv) != 0)) {
        cli_error("error writing standard output: %s", strerror(errno));
        rc = CLI_EXIT_IO;
    }
    if (rc == CLI_EXIT_OK)
        rc = run_plotter(kind, p->path, p->png);
    fclose(p->csv);
    unlink(p->path);
    return rc;
}
