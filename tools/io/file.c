/*
 * io/file.c - whole-file reading shared by the readers and the CLI: stat first, no blocking open,
 * size and magic checked before the body is read (see file.h).
 */
#include "io/file.h"

#include "qibl/status.h"
#include "qtool.h"

#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

/* why load_impl failed, so qtool_io_read_all can map it to errno */
enum { LOAD_OK = 0, LOAD_ERRNO, LOAD_DIR, LOAD_NOT_REGULAR, LOAD_TOO_BIG, LOAD_FORMAT, LOAD_NOMEM, LOAD_IO };

static int fail(int code, char *err, size_t errlen, const char *path, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    qtool_verrf_at(err, errlen, path, 0, fmt, ap);
    va_end(ap);
    return code;
}

static const char *type_name(mode_t m)
{
    return S_ISFIFO(m) ? "a fifo" : S_ISCHR(m) ? "a character device" : S_ISBLK(m) ? "a block device"
         : S_ISSOCK(m) ? "a socket" : S_ISLNK(m) ? "a symbolic link" : "not a regular file";
}

/* reads exactly n bytes (less only at end of file); -1 with errno on a read error */
static ssize_t read_full(int fd, uint8_t *p, size_t n)
{
    size_t got = 0;
    while (got < n) {
        ssize_t r = read(fd, p + got, n - got);
        if (r < 0 && errno == EINTR)
            continue;
        if (r < 0)
            return -1;
        if (r == 0)
            break;
        got += (size_t)r;
    }
    return (ssize_t)got;
}

static int load_impl(const char *path, const qtool_io_kind *k, uint8_t **buf_out, size_t *n_out, char *err,
                     size_t errlen, int *eno)
{
    struct stat st;
    *eno = 0;
    /* stat before open: opening a fifo would block, reading /dev/zero would never end */
    if (stat(path, &st) != 0) {
        *eno = errno;
        return fail(LOAD_ERRNO, err, errlen, path, "%s", strerror(errno));
    }
    if (S_ISDIR(st.st_mode))
        return fail(LOAD_DIR, err, errlen, path, "is a directory");
    if (!S_ISREG(st.st_mode))
        return fail(LOAD_NOT_REGULAR, err, errlen, path, "is %s, not a regular file", type_name(st.st_mode));
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY);
    if (fd < 0) {
        *eno = errno;
        return fail(LOAD_ERRNO, err, errlen, path, "%s", strerror(errno));
    }
    struct stat fst;
    int rc;
    uint8_t *buf = NULL;
    if (fstat(fd, &fst) != 0) {
        *eno = errno;
        rc = fail(LOAD_ERRNO, err, errlen, path, "%s", strerror(errno));
        goto out;
    }
    /* the path may have been replaced between stat and open */
    if (!S_ISREG(fst.st_mode) || fst.st_dev != st.st_dev || fst.st_ino != st.st_ino) {
        rc = fail(LOAD_NOT_REGULAR, err, errlen, path, "changed while being opened (now %s)",
                  S_ISREG(fst.st_mode) ? "another file" : type_name(fst.st_mode));
        goto out;
    }
    if (fst.st_size < 0 || (uintmax_t)fst.st_size > (uintmax_t)k->max_bytes) {
        rc = fail(LOAD_TOO_BIG, err, errlen, path, "%jd bytes, above the %zu-byte limit for %s", (intmax_t)fst.st_size,
                  k->max_bytes, k->what);
        goto out;
    }
    size_t size = (size_t)fst.st_size;
    if (size == 0 && k->min_bytes > 0) {
        rc = fail(LOAD_FORMAT, err, errlen, path, "empty file (not %s)", k->what);
        goto out;
    }
    if (size < k->min_bytes) {
        rc = fail(LOAD_FORMAT, err, errlen, path, "%zu byte%s: too short for %s (at least %zu)", size,
                  size == 1 ? "" : "s", k->what, k->min_bytes);
        goto out;
    }
    uint8_t head[QTOOL_IO_MAX_HEAD_BYTES];
    size_t hn = k->head_bytes < sizeof head ? k->head_bytes : sizeof head;
    if (hn > size)
        hn = size;
    ssize_t got = read_full(fd, head, hn);
    if (got < 0 || (size_t)got != hn) {
        *eno = got < 0 ? errno : 0;
        rc = fail(LOAD_IO, err, errlen, path, "read error: %s", got < 0 ? strerror(errno) : "file shrank while being read");
        goto out;
    }
    const char *why = k->magic ? k->magic(head, hn) : NULL;
    if (why) {
        rc = fail(LOAD_FORMAT, err, errlen, path, "%s", why);
        goto out;
    }
    buf = malloc(size ? size : 1);
    if (!buf) {
        rc = fail(LOAD_NOMEM, err, errlen, path, "out of memory for %zu bytes", size);
        goto out;
    }
    memcpy(buf, head, hn);
    got = read_full(fd, buf + hn, size - hn);
    if (got < 0 || (size_t)got != size - hn) {
        *eno = got < 0 ? errno : 0;
        rc = fail(LOAD_IO, err, errlen, path, "read error: %s", got < 0 ? strerror(errno) : "file shrank while being read");
        free(buf);
        buf = NULL;
        goto out;
    }
    *buf_out = buf;
    *n_out = size;
    rc = LOAD_OK;
out:
    close(fd);
    return rc;
}

int qtool_io_load(const char *path, const qtool_io_kind *kind, uint8_t **buf, size_t *n, char *err, size_t errlen)
{
    int eno;
    return load_impl(path, kind, buf, n, err, errlen, &eno) == LOAD_OK ? 0 : -1;
}

static const char *asset_magic(const uint8_t *head, size_t n)
{
    static const uint8_t m[8] = {'Q', 'I', 'B', 'L', '\r', '\n', 0x1A, '\n'};
    return n >= 8 && memcmp(head, m, 8) == 0 ? NULL : qibl_status_str(QIBL_E_ASSET_MAGIC);
}

int qtool_io_read_asset(const char *path, uint8_t **buf, size_t *n, char *err, size_t errlen)
{
    static const qtool_io_kind k = {"a qibl asset", 8, QTOOL_IO_MAX_FILE_BYTES, 8, asset_magic};
    return qtool_io_load(path, &k, buf, n, err, errlen);
}

uint8_t *qtool_io_read_all(const char *path, size_t *n)
{
    static const qtool_io_kind k = {"a file", 0, QTOOL_IO_MAX_FILE_BYTES, 0, NULL};
    uint8_t *buf = NULL;
    size_t len = 0;
    int eno;
    switch (load_impl(path, &k, &buf, &len, NULL, 0, &eno)) {
    case LOAD_OK:
        *n = len;
        return buf;
    case LOAD_DIR:
        errno = EISDIR;
        break;
    case LOAD_NOT_REGULAR:
        errno = EINVAL;
        break;
    case LOAD_TOO_BIG:
        errno = EFBIG;
        break;
    case LOAD_NOMEM:
        errno = ENOMEM;
        break;
    case LOAD_IO:
        errno = eno ? eno : EIO;
        break;
    default:
        errno = eno ? eno : EIO;
        break;
    }
    return NULL;
}
