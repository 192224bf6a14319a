/* SPDX-License-Identifier: MIT */
/* Structured log lines on stderr: "pneufracd ts=... level=... msg=... k=v". */
#ifndef PFD_LOG_H
#define PFD_LOG_H

enum pfd_log_level { PFD_LOG_DEBUG = 0, PFD_LOG_INFO, PFD_LOG_WARN, PFD_LOG_ERROR };

/** Lowest level printed; PFD_LOG_INFO unless --verbose. */
void pfd_log_set_level(enum pfd_log_level lvl);

/** One line: ts, level, msg=<msg>, then @p fmt (key=value pairs, printf
 *  style). Never called from the real-time thread: it may block. */
void pfd_log(enum pfd_log_level lvl, const char *msg, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/** A limit on one kind of warning that a client can provoke at will. */
typedef struct pfd_ratelimit {
    const char *what;   /**< named in the line that reports drops */
    long long start_ns; /**< the current window's start */
    unsigned n, dropped;
} pfd_ratelimit;
#define PFD_RATELIMIT(what) {what, 0, 0, 0}

/** Lines a limiter lets through per window, and the window. */
#define PFD_RATELIMIT_BURST 10
#define PFD_RATELIMIT_WINDOW_S 10

/** Whether one more line of @p rl's kind may be logged now. A window that
 *  dropped lines is reported, with their count, by the next line let
 *  through (msg=log-suppressed). Thread-safe. */
int pfd_log_ratelimit(pfd_ratelimit *rl);

/** A fatal start-up error in the plain form "pneufracd: <text>". */
void pfd_fatal(const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 1, 2)))
#endif
    ;

#endif
