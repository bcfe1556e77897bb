/* cgs_state — atomic state files. */
#include "cgs_state.h"

#include <errno.h>
#include <fcntl.h>
#include <libgen.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int cgs_state_mkdir (const char *dir)
{
    char tmp[4096];
    size_t n = strlen (dir);
    if (n == 0)
        return 0;
    if (n >= sizeof tmp)
        return -ENAMETOOLONG;
    memcpy (tmp, dir, n + 1);
    for (char *p = tmp + 1; *p; p++) {
        if (*p != '/')
            continue;
        *p = '\0';
        if (mkdir (tmp, 0755) < 0 && errno != EEXIST)
            return -errno;
        *p = '/';
    }
    if (mkdir (tmp, 0755) < 0 && errno != EEXIST)
        return -errno;
    return 0;
}

int cgs_state_path (char *buf, size_t size, const char *dir, const char *name)
{
    int n = snprintf (buf, size, "%s/%s", dir, name);
    return n < 0 || (size_t)n >= size ? -ENAMETOOLONG : 0;
}

static int s_fsync_dir (const char *path)
{
    char copy[4096];
    snprintf (copy, sizeof copy, "%s", path);
    int fd = open (dirname (copy), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0)
        return -errno;
    int rc = fsync (fd) < 0 ? -errno : 0;
    close (fd);
    return rc;
}

int cgs_state_write (const char *path, const void *data, size_t len)
{
    char dir[4096], tmp[4200];
    snprintf (dir, sizeof dir, "%s", path);
    int rc = cgs_state_mkdir (dirname (dir));
    if (rc < 0)
        return rc;
    if (snprintf (tmp, sizeof tmp, "%s.tmp.%ld", path, (long)getpid ()) >= (int)sizeof tmp)
        return -ENAMETOOLONG;
    int fd = open (tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0)
        return -errno;
    const char *p = data;
    size_t left = len;
    while (left > 0) {
        ssize_t n = write (fd, p, left);
        if (n < 0) {
            if (errno == EINTR)
                continue;
            rc = -errno;
            goto fail;
        }
        p += n;
        left -= (size_t)n;
    }
    if (fsync (fd) < 0) {
        rc = -errno;
        goto fail;
    }
    if (close (fd) < 0) {
        fd = -1;
        rc = -errno;
        goto fail;
    }
    fd = -1;
    if (rename (tmp, path) < 0) {
        rc = -errno;
        goto fail;
    }
    return s_fsync_dir (path);
fail:
    if (fd >= 0)
        close (fd);
    unlink (tmp);
    return rc;
}

int cgs_state_read (const char *path, size_t max, void **ret_data, size_t *ret_len)
{
    int fd = open (path, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return -errno;
    struct stat st;
    if (fstat (fd, &st) < 0) {
        int e = -errno;
        close (fd);
        return e;
    }
    if ((size_t)st.st_size > max) {
        close (fd);
        return -EFBIG;
    }
    size_t size = (size_t)st.st_size;
    char *buf = malloc (size + 1);
    if (!buf) {
        close (fd);
        return -ENOMEM;
    }
    size_t got = 0;
    while (got < size) {
        ssize_t n = read (fd, buf + got, size - got);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0) {
            int e = -errno;
            close (fd);
            free (buf);
            return e;
        }
        if (n == 0)
            break; // the file shrank under us: what is there is what it holds
        got += (size_t)n;
    }
    close (fd);
    buf[got] = '\0';
    *ret_data = buf;
    *ret_len = got;
    return 0;
}
