/* SPDX-License-Identifier: MIT */
/*
 * Whole-file I/O for the config file: a bounded read, and a replacement
 * that is atomic and durable (temp file, fsync, rename, fsync of the
 * directory), so that a crash leaves the old file or the new one, never a
 * mix. Messages name the step and errno, never the path itself.
 */
#ifndef PFD_FILE_H
#define PFD_FILE_H

#include <stddef.h>

/** pfd_file_read's return when the file does not exist (ENOENT): a first
 *  start names a file not yet written, and the caller can say how to make
 *  one. */
#define PFD_FILE_MISSING (-2)

/** Read all of @p path, at most @p max bytes, into a NUL-terminated
 *  buffer from malloc() (the caller frees it). @return 0, or -1 (or
 *  PFD_FILE_MISSING) with a message in @p err. */
int pfd_file_read(const char *path, size_t max, char **buf, size_t *len,
                  char *err, size_t errlen);

/** Replace @p path by the @p n bytes at @p text, through PATH.tmp.
 *  @return 0, or -1 with a message in @p err (PATH.tmp is removed). */
int pfd_file_replace(const char *path, const char *text, size_t n, char *err,
                     size_t errlen);

/** Create @p path with the @p n bytes at @p text, as durably as
 *  pfd_file_replace(), unless it exists: an existing file is never
 *  touched, even one that appears meanwhile (the temp file is linked in,
 *  which fails if the name is taken). @return 0 created, 1 it exists, or
 *  -1 with a message in @p err. */
int pfd_file_create(const char *path, const char *text, size_t n, char *err,
                    size_t errlen);

#endif
