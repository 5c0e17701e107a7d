/*
 * fileutil.h - hostile files for the reader suites (hdr, pfm, obj, png, file): a directory, a fifo,
 * a character device, an empty and a one-byte file, a sparse file of zeros. Each check runs a
 * reader on one of them and asserts a one-line error naming the file and the reason. Include after
 * <cmocka.h>. A fifo read must not block: an alarm turns a hang into a failed (killed) suite.
 */
#ifndef QTOOL_FILEUTIL_H
#define QTOOL_FILEUTIL_H

#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

/* a reader under test: 0 or -1 with a message in err; frees whatever it returned */
typedef int (*fu_reader)(const char *path, char *err, size_t errlen);

/* a fresh private directory for one suite's files */
static inline void fu_tmpdir(char dir[64])
{
    snprintf(dir, 64, "/tmp/qibl_fu_XXXXXX");
    assert_non_null(mkdtemp(dir));
}

static inline void fu_write(const char *path, const void *b, size_t n)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(b, 1, n, f), n);
    assert_int_equal(fclose(f), 0);
}

/* runs rd on path: must fail with one line naming path and containing every needle (NULL-ended) */
static inline void fu_refused(fu_reader rd, const char *path, const char *needle, const char *needle2)
{
    char err[512] = "";
    alarm(20); /* a blocking open or an endless read is a failure, not a hung suite */
    int rc = rd(path, err, sizeof err);
    alarm(0);
    if (rc != -1)
        fail_msg("%s: read succeeded, a refusal naming '%s' was expected", path, needle);
    if (!strstr(err, path))
        fail_msg("error '%s' does not name the file %s", err, path);
    if (strchr(err, '\n'))
        fail_msg("error '%s' is more than one line", err);
    if (!strstr(err, needle))
        fail_msg("error '%s' does not mention '%s'", err, needle);
    if (needle2 && !strstr(err, needle2))
        fail_msg("error '%s' does not mention '%s'", err, needle2);
}

/* a directory, a fifo (no writer: a blocking open would hang), /dev/null (a character device) */
static inline void fu_check_not_regular(fu_reader rd)
{
    char dir[64], p[128];
    fu_tmpdir(dir);
    fu_refused(rd, dir, "is a directory", NULL);
    snprintf(p, sizeof p, "%s/fifo", dir);
    assert_int_equal(mkfifo(p, 0600), 0);
    fu_refused(rd, p, "fifo", "not a regular file");
    unlink(p);
    rmdir(dir);
    fu_refused(rd, "/dev/null", "character device", "not a regular file");
}

/* an empty file, and a file of one byte b */
static inline void fu_check_empty_and_one_byte(fu_reader rd, uint8_t b, const char *one_byte_needle)
{
    char dir[64], p[128];
    fu_tmpdir(dir);
    snprintf(p, sizeof p, "%s/empty", dir);
    fu_write(p, "", 0);
    fu_refused(rd, p, "empty file", NULL);
    fu_write(p, &b, 1);
    fu_refused(rd, p, one_byte_needle, NULL);
    unlink(p);
    rmdir(dir);
}

/* peak resident set in KiB (Linux reports ru_maxrss in KiB) */
static inline long fu_maxrss_kib(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return ru.ru_maxrss;
}

/* A sparse file of `bytes` zeros (no disk used): refused by its first bytes (needle), and the peak
 * resident memory grows by less than 16 MiB - the body was never read. Run it before anything else
 * in a suite raises the peak. Then a sparse file one byte above the limit: refused by its size. */
static inline void fu_check_zeros_not_read(fu_reader rd, size_t bytes, const char *needle, size_t limit)
{
    char dir[64], p[128];
    fu_tmpdir(dir);
    snprintf(p, sizeof p, "%s/zeros", dir);
    int fd = open(p, O_WRONLY | O_CREAT | O_TRUNC, 0600);
    assert_true(fd >= 0);
    assert_int_equal(ftruncate(fd, (off_t)bytes), 0);
    close(fd);
    long before = fu_maxrss_kib();
    fu_refused(rd, p, needle, NULL);
    long grew = fu_maxrss_kib() - before;
    if (grew > 16 * 1024)
        fail_msg("refusing %zu bytes of zeros raised the peak memory by %ld KiB: the body was read", bytes, grew);
    fd = open(p, O_WRONLY);
    assert_true(fd >= 0);
    assert_int_equal(ftruncate(fd, (off_t)limit + 1), 0);
    close(fd);
    fu_refused(rd, p, "limit", NULL);
    unlink(p);
    rmdir(dir);
}

#endif
