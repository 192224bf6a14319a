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

/** A fatal start-up error in the plain form "pneufracd: <text>". */
void pfd_fatal(const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 1, 2)))
#endif
    ;

#endif
