/*
 * io/atomic.c - atomic file output (see atomic.h): exclusive temporary file, fsync, rename.
 */
#include "io/atomic.h"

#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <time.h>
#include <unistd.h>
#include "qtool.h"

/* the longest destination base name copied into the temporary name (keeps it under NAME_MAX) */
#define BASE_KEEP 180

static const char *kind_of(mode_t m)
{
    return S_ISLNK(m)    ? "a symbolic link"
           : S_ISDIR(m)  ? "a directory"
           : S_ISFIFO(m) ? "a FIFO"
           : S_ISCHR(m)  ? "a character device"
           : S_ISBLK(m)  ? "a block device"
           : S_ISSOCK(m) ? "a socket"
                         : "a non-regular file";
}

int qtool_io_check_replaceable(const char *path, char *err, size_t errlen)
{
    struct stat st;
    if (lstat(path, &st) != 0)
        return errno == ENOENT ? 0 : qtool_errf(err, errlen, "%s: %s", path, strerror(errno));
    if (!S_ISREG(st.st_mode))
        return qtool_errf(err, errlen, "%s: refusing to replace %s", path, kind_of(st.st_mode));
    return 0;
}

/* 64 unpredictable bits: /dev/urandom, else the clock, the pid and a stack address mixed */
static uint64_t random_bits(void)
{
    uint64_t v = 0;
    int fd = open("/dev/urandom", O_RDONLY | O_CLOEXEC);
    if (fd >= 0) {
        ssize_t r = read(fd, &v, sizeof v);
        close(fd);
        if (r == (ssize_t)sizeof v)
            return v;
    }
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    v = (uint64_t)ts.tv_nsec ^ (uint64_t)ts.tv_sec << 30 ^ (uint64_t)getpid() << 40 ^ (uint64_t)(uintptr_t)&ts;
    return v;
}

/* splitmix64 step: the next name after a collision */
static uint64_t mix(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15u);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9u;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBu;
    return z ^ (z >> 31);
}

int qtool_io_atomic_open(qtool_io_atomic *a, const char *path, char *err, size_t errlen)
{
    memset(a, 0, sizeof *a);
    if (!path || !*path)
        return qtool_errf(err, errlen, "(empty path): no file name");
    if (qtool_io_check_replaceable(path, err, errlen) != 0)
        return -1;
    size_t len = strlen(path);
    const char *slash = strrchr(path, '/');
    size_t dlen = slash ? (size_t)(slash - path) + 1 : 0; /* directory part, with its '/' */
    const char *base = path + dlen;
    size_t blen = strlen(base);
    if (blen == 0)
        return qtool_errf(err, errlen, "%s: no file name (ends in '/')", path);
    if (blen > BASE_KEEP)
        blen = BASE_KEEP;
    /* dir/.BASE.XXXXXXXXXXXXXXXX.tmp */
    size_t tl = dlen + 1 + blen + 1 + 16 + 4 + 1;
    char *tmp = malloc(tl), *dst = malloc(len + 1);
    if (!tmp || !dst) {
        free(tmp), free(dst);
        return qtool_errf(err, errlen, "%s: out of memory", path);
    }
    memcpy(dst, path, len + 1);
    uint64_t seed = random_bits();
    int fd = -1, e = 0;
    for (int attempt = 0; attempt < 64; ++attempt) {
        snprintf(tmp, tl, "%.*s.%.*s.%016llx.tmp", (int)dlen, path, (int)blen, base, (unsigned long long)mix(&seed));
        fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
        e = errno;
        if (fd >= 0 || e != EEXIST)
            break;
    }
    if (fd < 0) {
        qtool_errf(err, errlen, "%s: cannot create a temporary file next to it: %s", path, strerror(e));
        free(tmp), free(dst);
        return -1;
    }
    FILE *f = fdopen(fd, "wb");
    if (!f) {
        e = errno;
        close(fd);
        unlink(tmp);
        qtool_errf(err, errlen, "%s: cannot open the temporary file %s: %s", path, tmp, strerror(e));
        free(tmp), free(dst);
        return -1;
    }
    a->f = f, a->path = dst, a->tmp = tmp;
    return 0;
}

static void release(qtool_io_atomic *a)
{
    free(a->path), free(a->tmp);
    memset(a, 0, sizeof *a);
}

void qtool_io_atomic_abort(qtool_io_atomic *a)
{
    if (a->f)
        fclose(a->f);
    if (a->tmp)
        unlink(a->tmp);
    release(a);
}

/* fsync, tolerating file systems that cannot (EINVAL/ENOTSUP: nothing to make durable there) */
static int sync_fd(int fd)
{
    return fsync(fd) == 0 || errno == EINVAL || errno == ENOTSUP ? 0 : -1;
}

int qtool_io_atomic_commit(qtool_io_atomic *a, char *err, size_t errlen)
{
    if (!a->f)
        return qtool_errf(err, errlen, "%s: not open for writing", a->path ? a->path : "(null)");
    int e = errno, bad = ferror(a->f) != 0;
    if (!bad && fflush(a->f) != 0)
        bad = 1, e = errno;
    if (!bad && !a->no_fsync && sync_fd(fileno(a->f)) != 0)
        bad = 1, e = errno;
    int c = fclose(a->f);
    a->f = NULL;
    if (!bad && c != 0)
        bad = 1, e = errno;
    if (bad) {
        qtool_errf(err, errlen, "%s: write failed: %s", a->path, e ? strerror(e) : "I/O error");
        unlink(a->tmp);
        release(a);
        return -1;
    }
    /* the destination may have been replaced by a link or a FIFO while we wrote */
    if (qtool_io_check_replaceable(a->path, err, errlen) != 0) {
        unlink(a->tmp);
        release(a);
        return -1;
    }
    if (rename(a->tmp, a->path) != 0) {
        e = errno;
        qtool_errf(err, errlen, "%s: cannot rename the temporary file over it: %s", a->path, strerror(e));
        unlink(a->tmp);
        release(a);
        return -1;
    }
    if (!a->no_fsync) { /* make the rename itself durable; best effort */
        const char *slash = strrchr(a->path, '/');
        size_t dl = slash ? (size_t)(slash - a->path) : 0;
        if (!slash) /* a->tmp is longer than the directory part: reuse it for the name */
            memcpy(a->tmp, ".", 2);
        else if (dl == 0)
            memcpy(a->tmp, "/", 2);
        else
            memcpy(a->tmp, a->path, dl), a->tmp[dl] = '\0';
        int dfd = open(a->tmp, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
        if (dfd >= 0) {
            (void)fsync(dfd);
            close(dfd);
        }
    }
    release(a);
    return 0;
}

int qtool_io_write_atomic(const char *path, const void *data, size_t n, char *err, size_t errlen)
{
    qtool_io_atomic a;
    if (qtool_io_atomic_open(&a, path, err, errlen) != 0)
        return -1;
    if (n > 0 && fwrite(data, 1, n, a.f) != n) {
        int e = errno;
        qtool_io_atomic_abort(&a);
        return qtool_errf(err, errlen, "%s: write failed: %s", path, strerror(e));
    }
    return qtool_io_atomic_commit(&a, err, errlen);
}

int qtool_io_write_encoded(const char *path, int enc, uint8_t *b, size_t n, char *err, size_t errlen)
{
    if (enc != 0)
        return qtool_errf(err, errlen, "%s: out of memory", path);
    int rc = qtool_io_write_atomic(path, b, n, err, errlen);
    free(b);
    return rc;
}
