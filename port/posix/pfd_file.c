/* SPDX-License-Identifier: MIT */
#include "pfd_file.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int pfd_file_read(const char *path, size_t max, char **buf, size_t *len,
                  char *err, size_t errlen)
{
    FILE *f = fopen(path, "rb");
    size_t n = 0, cap = 4096;
    char *b;

    if (f == NULL) {
        int missing = errno == ENOENT;
        snprintf(err, errlen, "cannot open: %s", strerror(errno));
        return missing ? PFD_FILE_MISSING : -1;
    }
    b = malloc(cap + 1);
    for (;;) {
        size_t r;
        if (b == NULL) {
            snprintf(err, errlen, "out of memory");
            fclose(f);
            return -1;
        }
        if (n == cap) {
            char *nb;
            if (cap >= max) {
                snprintf(err, errlen, "larger than %zu bytes", max);
                free(b);
                fclose(f);
                return -1;
            }
            cap *= 2;
            nb = realloc(b, cap + 1);
            if (nb == NULL)
                free(b);
            b = nb;
            continue;
        }
        r = fread(b + n, 1, cap - n, f);
        n += r;
        if (r == 0)
            break;
    }
    if (ferror(f)) {
        snprintf(err, errlen, "read error: %s", strerror(errno));
        free(b);
        fclose(f);
        return -1;
    }
    fclose(f);
    b[n] = '\0';
    *buf = b;
    *len = n;
    return 0;
}

static int write_all(int fd, const char *p, size_t n)
{
    while (n > 0) {
        ssize_t w = write(fd, p, n);
        if (w < 0) {
            if (errno == EINTR)
                continue;
            return -1;
        }
        p += w;
        n -= (size_t)w;
    }
    return 0;
}

/* The rename itself is durable only once the directory is synced. */
static int sync_dir_of(const char *path, char *err, size_t errlen)
{
    char dir[PATH_MAX];
    const char *slash = strrchr(path, '/');
    int fd;

    if (slash == NULL)
        strcpy(dir, ".");
    else if (slash == path)
        strcpy(dir, "/");
    else
        snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
    fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0 || fsync(fd) != 0) {
        snprintf(err, errlen, "syncing directory %s: %s", dir, strerror(errno));
        if (fd >= 0)
            close(fd);
        return -1;
    }
    close(fd);
    return 0;
}

/* PATH.tmp written with the @p n bytes at @p text and synced, its name in
 * @p tmp (PATH_MAX bytes). @return 0, or -1 with @p err (nothing left). */
static int write_temp(const char *path, const char *text, size_t n, char *tmp,
                      char *err, size_t errlen)
{
    int fd;

    if (snprintf(tmp, PATH_MAX, "%s.tmp", path) >= PATH_MAX) {
        snprintf(err, errlen, "path too long");
        return -1;
    }
    fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0 || write_all(fd, text, n) != 0 || fsync(fd) != 0) {
        snprintf(err, errlen, "writing %s: %s", tmp, strerror(errno));
        if (fd >= 0)
            close(fd);
        unlink(tmp);
        return -1;
    }
    if (close(fd) != 0) {
        snprintf(err, errlen, "writing %s: %s", tmp, strerror(errno));
        unlink(tmp);
        return -1;
    }
    return 0;
}

int pfd_file_replace(const char *path, const char *text, size_t n, char *err,
                     size_t errlen)
{
    char tmp[PATH_MAX];

    if (write_temp(path, text, n, tmp, err, errlen) != 0)
        return -1;
    if (rename(tmp, path) != 0) {
        snprintf(err, errlen, "replacing: %s", strerror(errno));
        unlink(tmp);
        return -1;
    }
    return sync_dir_of(path, err, errlen);
}

int pfd_file_create(const char *path, const char *text, size_t n, char *err,
                    size_t errlen)
{
    char tmp[PATH_MAX];
    int rc;

    if (access(path, F_OK) == 0)
        return 1;
    if (write_temp(path, text, n, tmp, err, errlen) != 0)
        return -1;
    if (link(tmp, path) == 0) {
        rc = 0;
    } else if (errno == EEXIST) {
        rc = 1;
    } else {
        snprintf(err, errlen, "creating: %s", strerror(errno));
        rc = -1;
    }
    unlink(tmp);
    if (rc == 0 && sync_dir_of(path, err, errlen) != 0)
        return -1;
    return rc;
}
