/*
 * file_test.c - tools/io/file.c, the whole-file reading every reader and the CLI share: the order
 * of its checks (stat, non-blocking open, size, first bytes, body), each refusal's named message,
 * the magic check seeing only the first bytes, and qtool_io_read_all's errno for callers that print
 * strerror (a directory used to read as "Input/output error").
 */
#include <errno.h>
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "io/file.h"
#include "fileutil.h"

static size_t magic_calls, magic_seen;

/* accepts a head starting "OK" and records what it was shown */
static const char *ok_magic(const uint8_t *head, size_t n)
{
    ++magic_calls;
    magic_seen = n;
    return n >= 2 && head[0] == 'O' && head[1] == 'K' ? NULL : "not an OK file";
}

static const qtool_io_kind ok_kind = {"an OK file", 2, 4096, 8, ok_magic};

static int rd_ok(const char *path, char *err, size_t errlen)
{
    uint8_t *b;
    size_t n;
    int rc = qtool_io_load(path, &ok_kind, &b, &n, err, errlen);
    if (rc == 0)
        free(b);
    return rc;
}

static int rd_asset(const char *path, char *err, size_t errlen)
{
    uint8_t *b;
    size_t n;
    int rc = qtool_io_read_asset(path, &b, &n, err, errlen);
    if (rc == 0)
        free(b);
    return rc;
}

/* first in the suite: it measures the peak memory */
static void test_zeros_refused_before_reading(void **state)
{
    (void)state;
    fu_check_zeros_not_read(rd_asset, (size_t)64 << 20, "not a qibl asset", QTOOL_IO_MAX_FILE_BYTES);
}

static void test_not_regular_files_named(void **state)
{
    (void)state;
    fu_check_not_regular(rd_ok);
    fu_check_not_regular(rd_asset);
}

static void test_sizes_and_magic_in_order(void **state)
{
    (void)state;
    char dir[64], p[128];
    fu_tmpdir(dir);
    snprintf(p, sizeof p, "%s/f", dir);
    fu_check_empty_and_one_byte(rd_ok, 'O', "1 byte: too short for an OK file (at least 2)");
    /* above the limit: refused from the size, the magic never consulted */
    uint8_t *big = malloc(4097);
    assert_non_null(big);
    memset(big, 'x', 4097);
    big[0] = 'O', big[1] = 'K';
    fu_write(p, big, 4097);
    magic_calls = 0;
    fu_refused(rd_ok, p, "4097 bytes, above the 4096-byte limit for an OK file", NULL);
    assert_int_equal(magic_calls, 0);
    /* at the limit: the magic sees head_bytes, the buffer holds the whole file */
    fu_write(p, big, 4096);
    uint8_t *b = NULL;
    size_t n = 0;
    char err[256];
    magic_calls = 0;
    assert_int_equal(qtool_io_load(p, &ok_kind, &b, &n, err, sizeof err), 0);
    assert_int_equal(magic_calls, 1);
    assert_int_equal(magic_seen, 8);
    assert_int_equal(n, 4096);
    assert_memory_equal(b, big, 4096);
    free(b);
    /* shorter than head_bytes: the magic sees what there is */
    fu_write(p, "OK!", 3);
    assert_int_equal(qtool_io_load(p, &ok_kind, &b, &n, err, sizeof err), 0);
    assert_int_equal(magic_seen, 3);
    assert_true(n == 3 && memcmp(b, "OK!", 3) == 0);
    free(b);
    /* a wrong magic: the kind's reason, naming the file; nothing returned */
    fu_write(p, "NO", 2);
    b = (uint8_t *)big;
    n = 77;
    assert_int_equal(qtool_io_load(p, &ok_kind, &b, &n, err, sizeof err), -1);
    assert_true(b == big && n == 77);
    assert_non_null(strstr(err, "not an OK file"));
    assert_non_null(strstr(err, p));
    /* unreadable and missing */
    fu_refused(rd_ok, "/nonexistent/qibl/f", "No such file", NULL);
    unlink(p);
    rmdir(dir);
    free(big);
}

/* qtool_io_read_all keeps its errno contract, with the right errno for each refusal */
static void test_read_all_errno(void **state)
{
    (void)state;
    char dir[64], p[128];
    fu_tmpdir(dir);
    size_t n = 0;
    errno = 0;
    assert_null(qtool_io_read_all(dir, &n));
    assert_int_equal(errno, EISDIR);
    snprintf(p, sizeof p, "%s/fifo", dir);
    assert_int_equal(mkfifo(p, 0600), 0);
    alarm(20);
    assert_null(qtool_io_read_all(p, &n));
    alarm(0);
    assert_int_equal(errno, EINVAL);
    unlink(p);
    assert_null(qtool_io_read_all("/dev/null", &n));
    assert_int_equal(errno, EINVAL);
    assert_null(qtool_io_read_all("/nonexistent/qibl/f", &n));
    assert_int_equal(errno, ENOENT);
    /* an empty file is a zero-length buffer (the asset parser names what is wrong with it) */
    snprintf(p, sizeof p, "%s/e", dir);
    fu_write(p, "", 0);
    uint8_t *b = qtool_io_read_all(p, &n);
    assert_non_null(b);
    assert_int_equal(n, 0);
    free(b);
    fu_write(p, "abc", 3);
    b = qtool_io_read_all(p, &n);
    assert_true(b && n == 3 && memcmp(b, "abc", 3) == 0);
    free(b);
    unlink(p);
    rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_zeros_refused_before_reading),
        cmocka_unit_test(test_not_regular_files_named),
        cmocka_unit_test(test_sizes_and_magic_in_order),
        cmocka_unit_test(test_read_all_errno),
    };
    return cmocka_run_group_tests_name("file", tests, NULL, NULL);
}
