/* SPDX-License-Identifier: MIT */
#include "pfd_log.h"

#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

static enum pfd_log_level min_level = PFD_LOG_INFO;

void pfd_log_set_level(enum pfd_log_level lvl) { min_level = lvl; }

void pfd_log(enum pfd_log_level lvl, const char *msg, const char *fmt, ...)
{
    static const char *const names[] = {"debug", "info", "warn", "error"};
    char line[2048];
    struct timespec ts;
    struct tm tm;
    size_t n;
    int k;

    if (lvl < min_level)
        return;
    clock_gettime(CLOCK_REALTIME, &ts);
    gmtime_r(&ts.tv_sec, &tm);
    k = snprintf(line, sizeof line,
                 "pneufracd ts=%04d-%02d-%02dT%02d:%02d:%02d.%03ldZ level=%s msg=%s",
                 tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday, tm.tm_hour,
                 tm.tm_min, tm.tm_sec, ts.tv_nsec / 1000000L, names[lvl], msg);
    n = k < 0 ? 0 : (size_t)k < sizeof line ? (size_t)k : sizeof line - 1;
    if (fmt != NULL && *fmt != '\0' && n + 2 < sizeof line) {
        va_list ap;
        line[n++] = ' ';
        va_start(ap, fmt);
        k = vsnprintf(line + n, sizeof line - n, fmt, ap);
        va_end(ap);
        if (k > 0)
            n += (size_t)k < sizeof line - n ? (size_t)k : sizeof line - n - 1;
    }
    /* One fputs per line: stderr is unbuffered, and a single write keeps
     * lines from different threads whole. */
    if (n + 1 >= sizeof line)
        n = sizeof line - 2;
    line[n++] = '\n';
    line[n] = '\0';
    fputs(line, stderr);
}

void pfd_fatal(const char *fmt, ...)
{
    char line[1024];
    va_list ap;
    int k;

    memcpy(line, "pneufracd: ", 11);
    va_start(ap, fmt);
    k = vsnprintf(line + 11, sizeof line - 12, fmt, ap);
    va_end(ap);
    (void)k;
    strcat(line, "\n");
    fputs(line, stderr);
}

int pfd_log_ratelimit(pfd_ratelimit *rl)
{
    static pthread_mutex_t mx = PTHREAD_MUTEX_INITIALIZER;
    const long long window = (long long)PFD_RATELIMIT_WINDOW_S * 1000000000LL;
    struct timespec ts;
    long long now;
    unsigned dropped = 0;
    int ok;

    clock_gettime(CLOCK_MONOTONIC, &ts);
    now = (long long)ts.tv_sec * 1000000000LL + ts.tv_nsec;
    pthread_mutex_lock(&mx);
    if (rl->n == 0 || now - rl->start_ns >= window) {
        dropped = rl->dropped;
        rl->start_ns = now;
        rl->n = 0;
        rl->dropped = 0;
    }
    ok = rl->n < PFD_RATELIMIT_BURST;
    if (ok)
        rl->n++;
    else
        rl->dropped++;
    pthread_mutex_unlock(&mx);
    if (dropped > 0)
        pfd_log(PFD_LOG_WARN, "log-suppressed", "what=%s lines=%u window_s=%d", rl->what,
                dropped, PFD_RATELIMIT_WINDOW_S);
    return ok;
}
