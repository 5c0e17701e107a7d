/*
 * pfm_test.c - tools/io/pfm.c: both byte orders, colour and grey, row order, round trip through the
 * writer, and every malformed header/truncation giving a one-line error that names the file with
 * nothing returned. Hostile files (tests/fileutil.h): zeros refused by the magic before the body is
 * read, directories, fifos and devices named, empty and one-byte files, a header claiming more
 * pixels than the limit or than the file holds, and non-finite samples named with their position.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "io/pfm.h"
#include "fileutil.h"

/* builds a PFM image: header text, then samples in the given byte order, rows bottom first */
static size_t make(uint8_t *buf, const char *hdr, const float *px, int w, int h, int ch, int little)
{
    size_t n = strlen(hdr);
    memcpy(buf, hdr, n);
    for (int y = h - 1; y >= 0; --y)
        for (int i = 0; i < w * ch; ++i) {
            uint32_t u;
            memcpy(&u, &px[(size_t)y * (size_t)(w * ch) + (size_t)i], 4);
            for (int b = 0; b < 4; ++b)
                buf[n++] = (uint8_t)(u >> (little ? 8 * b : 24 - 8 * b));
        }
    return n;
}

static void test_both_endians_and_kinds(void **state)
{
    (void)state;
    float rgb[2 * 3 * 3], grey[5 * 2];
    for (int i = 0; i < 18; ++i)
        rgb[i] = (float)i * 0.25f - 1.0f;
    for (int i = 0; i < 10; ++i)
        grey[i] = (float)i * 1e-3f;
    uint8_t buf[512];
    char err[256];
    for (int little = 0; little < 2; ++little) {
        int w, h, ch;
        float *px = NULL;
        size_t n = make(buf, little ? "PF\n2 3\n-1.0\n" : "PF\n2 3\n1.0\n", rgb, 2, 3, 3, little);
        assert_int_equal(qtool_pfm_decode(buf, n, &w, &h, &ch, &px, err, sizeof err), 0);
        assert_int_equal(w, 2), assert_int_equal(h, 3), assert_int_equal(ch, 3);
        assert_memory_equal(px, rgb, sizeof rgb);
        free(px);
        n = make(buf, little ? "Pf 5 2 -4.5 " : "Pf\r\n5\t2\r\n+2\n", grey, 5, 2, 1, little);
        assert_int_equal(qtool_pfm_decode(buf, n, &w, &h, &ch, &px, err, sizeof err), 0);
        assert_int_equal(w, 5), assert_int_equal(h, 2), assert_int_equal(ch, 1);
        assert_memory_equal(px, grey, sizeof grey);
        free(px);
    }
}

static void test_malformed(void **state)
{
    (void)state;
    static const char *bad[] = {
        "",                   /* empty */
        "P6\n2 2\n255\n",     /* a PPM */
        "PFX\n1 1\n-1\n",     /* magic not followed by whitespace */
        "PF\n0 1\n-1\n",      /* zero width */
        "PF\n1 -1\n-1\n",     /* negative height */
        "PF\n1 1\n0\n",       /* zero scale */
        "PF\n1 1\nnan\n",     /* NaN scale */
        "PF\n1x 1\n-1\n",     /* junk in a number */
        "PF\n1 1\n",          /* no scale */
        "PF\n2 2\n-1\nabcd",  /* truncated samples */
        "PF\n99999 1\n-1\n",  /* too wide */
    };
    char err[256];
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        int w = -7, h = -7, ch = -7;
        float *px = (float *)&w;
        err[0] = '\0';
        assert_int_equal(qtool_pfm_decode((const uint8_t *)bad[i], strlen(bad[i]), &w, &h, &ch, &px, err, sizeof err), -1);
        assert_int_equal(w, -7), assert_int_equal(h, -7), assert_int_equal(ch, -7);
        assert_ptr_equal(px, (float *)&w);
        assert_true(strlen(err) > 0 && strchr(err, '\n') == NULL);
    }
    /* the file name is in the message */
    char path[64];
    snprintf(path, sizeof path, "/tmp/qibl_pfm_bad_%d.pfm", (int)getpid());
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fputs("PF\n4 4\n-1\n", f);
    fclose(f);
    int w, h, ch;
    float *px;
    assert_int_equal(qtool_pfm_read(path, &w, &h, &ch, &px, err, sizeof err), -1);
    assert_non_null(strstr(err, path));
    assert_non_null(strstr(err, "truncated"));
    remove(path);
    assert_int_equal(qtool_pfm_read("/nonexistent/x.pfm", &w, &h, &ch, &px, err, sizeof err), -1);
    assert_non_null(strstr(err, "/nonexistent/x.pfm"));
}

static void test_write_round_trip(void **state)
{
    (void)state;
    char path[64], err[256];
    snprintf(path, sizeof path, "/tmp/qibl_pfm_rt_%d.pfm", (int)getpid());
    float px[3 * 4 * 3];
    for (int i = 0; i < 36; ++i)
        px[i] = (float)(i * i) - 17.5f;
    for (int ch = 1; ch <= 3; ch += 2) {
        assert_int_equal(qtool_pfm_write(path, 4, 3, ch, px, err, sizeof err), 0);
        int w, h, c;
        float *back;
        assert_int_equal(qtool_pfm_read(path, &w, &h, &c, &back, err, sizeof err), 0);
        assert_int_equal(w, 4), assert_int_equal(h, 3), assert_int_equal(c, ch);
        assert_memory_equal(back, px, sizeof(float) * 12 * (size_t)ch);
        free(back);
    }
    remove(path);
    /* bad arguments: nothing written */
    assert_int_equal(qtool_pfm_write(path, 0, 3, 3, px, err, sizeof err), -1);
    assert_int_equal(access(path, F_OK), -1);
    assert_int_equal(qtool_pfm_write("/nonexistent/dir/x.pfm", 1, 1, 1, px, err, sizeof err), -1);
    assert_non_null(strstr(err, "/nonexistent/dir/x.pfm"));
}

/* ---- hostile files ---------------------------------------------------------------------------- */

static int rd_pfm(const char *path, char *err, size_t errlen)
{
    int w, h, ch;
    float *px;
    int rc = qtool_pfm_read(path, &w, &h, &ch, &px, err, errlen);
    if (rc == 0)
        free(px);
    return rc;
}

/* first in the suite: it measures the peak memory */
static void test_zeros_refused_by_magic_before_reading(void **state)
{
    (void)state;
    fu_check_zeros_not_read(rd_pfm, (size_t)64 << 20, "not a PFM", QTOOL_PFM_MAX_FILE_BYTES);
}

static void test_not_regular_files_named(void **state)
{
    (void)state;
    fu_check_not_regular(rd_pfm);
}

static void test_empty_and_one_byte_files_named(void **state)
{
    (void)state;
    fu_check_empty_and_one_byte(rd_pfm, 'P', "too short");
}

static void decode_fails(const char *hdr, size_t body, const char *needle)
{
    size_t n = strlen(hdr);
    uint8_t *b = calloc(1, n + body + 1);
    assert_non_null(b);
    memcpy(b, hdr, n);
    int w = -7, h = -7, ch = -7;
    float *px = NULL;
    char err[256] = "";
    assert_int_equal(qtool_pfm_decode(b, n + body, &w, &h, &ch, &px, err, sizeof err), -1);
    assert_true(w == -7 && h == -7 && ch == -7 && px == NULL);
    if (!strstr(err, needle))
        fail_msg("error '%s' does not mention '%s'", err, needle);
    free(b);
}

/* dimensions past QIBL_PFM_MAX_PIXELS (the core's 2^26) are refused from the header; within it, a
 * body shorter than the header claims is refused before allocating */
static void test_lying_header_refused(void **state)
{
    (void)state;
    decode_fails("PF\n65535 65535\n-1\n", 16, "QIBL_PFM_MAX_PIXELS");
    decode_fails("Pf\n8193 8192\n-1\n", 16, "QIBL_PFM_MAX_PIXELS");
    decode_fails("PF\n8192 8192\n-1\n", 16, "truncated");
    decode_fails("PF\n2 2\n-1\n", 47, "truncated"); /* one byte short of 48 */
}

/* the header is text: a NUL inside a number (strtol would stop at it and accept "2") or a \v before
 * the scale (strtod would skip it) is named with its offset (found by the fuzzer) */
static void test_header_control_bytes_named(void **state)
{
    (void)state;
    static const struct {
        const char *h;
        size_t n;
        const char *needle;
    } bad[] = {
        {"Pf 2\0 1 -1.0\n", 13, "byte 0x00 at offset 4"},
        {"Pf 2 1 \v-1.0\n", 13, "byte 0x0b at offset 7"},
        {"Pf 2 1\f -1.0\n", 13, "byte 0x0c at offset 6"},
        {"PF 1 1 -1\x80\n", 12, "byte 0x80 at offset 9"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        uint8_t b[64] = {0};
        memcpy(b, bad[i].h, bad[i].n);
        int w = -7, h = -7, ch = -7;
        float *px = NULL;
        char err[256] = "";
        assert_int_equal(qtool_pfm_decode(b, bad[i].n + 24, &w, &h, &ch, &px, err, sizeof err), -1);
        assert_true(w == -7 && px == NULL);
        if (!strstr(err, bad[i].needle))
            fail_msg("case %zu: error '%s' does not mention '%s'", i, err, bad[i].needle);
    }
}

/* a NaN or an infinity anywhere is refused with its value and position (qibl check used to accept
 * the infinities `render --rgb 1e308` wrote) */
static void test_non_finite_samples_named(void **state)
{
    (void)state;
    static const struct {
        uint32_t bits;
        const char *name;
    } bad[] = {{0x7F800000u, "inf"}, {0xFF800000u, "-inf"}, {0x7FC00000u, "nan"}, {0xFFFFFFFFu, "nan"}};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; ++k) {
        float px[3 * 3 * 2];
        for (int i = 0; i < 18; ++i)
            px[i] = (float)i;
        memcpy(&px[3 * (3 * 1 + 2) + 1], &bad[k].bits, 4); /* column 2, row 1 from the top, green */
        uint8_t buf[256];
        size_t n = make(buf, "PF\n3 2\n-1\n", px, 3, 2, 3, 1);
        int w = -7, h = -7, ch = -7;
        float *out = NULL;
        char err[256] = "", want[96];
        assert_int_equal(qtool_pfm_decode(buf, n, &w, &h, &ch, &out, err, sizeof err), -1);
        assert_true(w == -7 && h == -7 && ch == -7 && out == NULL);
        snprintf(want, sizeof want, "sample %s at column 2, row 1 from the top, channel 1", bad[k].name);
        if (!strstr(err, want))
            fail_msg("error '%s' does not say '%s'", err, want);
    }
    /* the largest finite values are fine */
    float big[3] = {3.4028235e38f, -3.4028235e38f, 1e-45f};
    uint8_t buf[64];
    size_t n = make(buf, "PF\n1 1\n-1\n", big, 1, 1, 3, 1);
    int w, h, ch;
    float *out;
    char err[256];
    assert_int_equal(qtool_pfm_decode(buf, n, &w, &h, &ch, &out, err, sizeof err), 0);
    assert_memory_equal(out, big, sizeof big);
    free(out);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_zeros_refused_by_magic_before_reading),
        cmocka_unit_test(test_not_regular_files_named),
        cmocka_unit_test(test_empty_and_one_byte_files_named),
        cmocka_unit_test(test_lying_header_refused),
        cmocka_unit_test(test_non_finite_samples_named),
        cmocka_unit_test(test_header_control_bytes_named),
        cmocka_unit_test(test_both_endians_and_kinds),
        cmocka_unit_test(test_malformed),
        cmocka_unit_test(test_write_round_trip),
    };
    return cmocka_run_group_tests_name("pfm", tests, NULL, NULL);
}
