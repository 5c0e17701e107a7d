/*
 * hdr_test.c - tools/io/hdr.c, the Radiance .hdr reader used by `qibl bench srgbe` and the bakers.
 *
 * Small synthetic files for every scanline encoding (flat, old-style RLE with its growing shift,
 * new-style RLE with runs and literals, mixed per scanline), the header quirks the real probes have,
 * and one test per kind of bad file (each must fail with one line of text and set nothing). The
 * real probes in ../shared/fixtures/probes are decoded when present and checked against the figures
 * in ../shared/fixtures/SOURCES.md; absent (any of the 11), the test is reported skipped.
 * Hostile files (tests/fileutil.h): zeros refused by the magic before the body is read, directories,
 * fifos and devices named, empty and one-byte files, headers claiming more than the core's limits.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <unistd.h>
#include <cmocka.h>

#include "io/hdr.h"
#include "fileutil.h"

typedef struct {
    uint8_t b[8192];
    size_t n;
} buf_t;

static void put_s(buf_t *f, const char *s)
{
    size_t k = strlen(s);
    memcpy(f->b + f->n, s, k);
    f->n += k;
}

static void put_px(buf_t *f, uint8_t r, uint8_t g, uint8_t b, uint8_t e)
{
    f->b[f->n++] = r, f->b[f->n++] = g, f->b[f->n++] = b, f->b[f->n++] = e;
}

static void put_bytes(buf_t *f, const uint8_t *p, size_t k)
{
    memcpy(f->b + f->n, p, k);
    f->n += k;
}

static float rgbe(uint8_t m, uint8_t e)
{
    return e ? (float)ldexp(m, e - 136) : 0.0f;
}

static void header(buf_t *f, int w, int h)
{
    char res[64];
    put_s(f, "#?RADIANCE\n# made by hdr_test\nFORMAT=32-bit_rle_rgbe\n\n");
    snprintf(res, sizeof res, "-Y %d +X %d\n", h, w);
    put_s(f, res);
}

static float *decode_ok(const buf_t *f, int want_w, int want_h)
{
    int w = -1, h = -1;
    float *rgb = NULL;
    char err[256] = "";
    int rc = qtool_hdr_decode(f->b, f->n, &w, &h, &rgb, err, sizeof err);
    if (rc != 0)
        fail_msg("decode failed: %s", err);
    assert_int_equal(w, want_w);
    assert_int_equal(h, want_h);
    assert_non_null(rgb);
    return rgb;
}

static void decode_fails(const buf_t *f, const char *want_substring)
{
    int w = -7, h = -7;
    float *rgb = (float *)(uintptr_t)0x1234;
    char err[256] = "";
    assert_int_equal(qtool_hdr_decode(f->b, f->n, &w, &h, &rgb, err, sizeof err), -1);
    assert_true(w == -7 && h == -7 && rgb == (float *)(uintptr_t)0x1234); /* nothing set */
    assert_true(strlen(err) > 0 && strchr(err, '\n') == NULL);           /* one line */
    if (strstr(err, want_substring) == NULL)
        fail_msg("error '%s' does not mention '%s'", err, want_substring);
}

static void test_flat_scanlines(void **state)
{
    (void)state;
    buf_t f = {{0}, 0};
    header(&f, 3, 2);
    const uint8_t px[6][4] = {{128, 64, 32, 129}, {255, 255, 255, 140}, {0, 0, 0, 0},
                              {1, 2, 3, 100},     {200, 0, 10, 136},    {128, 128, 128, 1}};
    for (int i = 0; i < 6; ++i)
        put_px(&f, px[i][0], px[i][1], px[i][2], px[i][3]);
    float *rgb = decode_ok(&f, 3, 2);
    for (int i = 0; i < 6; ++i)
        for (int c = 0; c < 3; ++c)
            assert_true(rgb[3 * i + c] == rgbe(px[i][c], px[i][3]));
    free(rgb);
}

static void test_old_style_runs(void **state)
{
    (void)state;
    /* 5 pixels: A, run of 3 (A), B */
    buf_t f = {{0}, 0};
    header(&f, 5, 1);
    put_px(&f, 10, 20, 30, 130);
    put_px(&f, 1, 1, 1, 3);
    put_px(&f, 40, 50, 60, 131);
    float *rgb = decode_ok(&f, 5, 1);
    for (int i = 0; i < 4; ++i)
        assert_true(rgb[3 * i] == rgbe(10, 130) && rgb[3 * i + 2] == rgbe(30, 130));
    assert_true(rgb[12] == rgbe(40, 131));
    free(rgb);
    /* 300 pixels: A, run 43, run 1 << 8 (consecutive runs shift by 8): 1 + 43 + 256 = 300 */
    buf_t g = {{0}, 0};
    header(&g, 300, 2);
    put_px(&g, 7, 8, 9, 140);
    put_px(&g, 1, 1, 1, 43);
    put_px(&g, 1, 1, 1, 1);
    /* second line starts with a run: repeats the last pixel of the line before */
    put_px(&g, 1, 1, 1, 200);
    for (int i = 200; i < 300; ++i)
        put_px(&g, (uint8_t)i, 0, 0, 128);
    rgb = decode_ok(&g, 300, 2);
    for (int i = 0; i < 300; ++i)
        assert_true(rgb[3 * i] == rgbe(7, 140) && rgb[3 * i + 1] == rgbe(8, 140));
    for (int i = 0; i < 200; ++i)
        assert_true(rgb[3 * (300 + i)] == rgbe(7, 140));
    for (int i = 200; i < 300; ++i)
        assert_true(rgb[3 * (300 + i)] == rgbe((uint8_t)i, 128));
    free(rgb);
}

/* new-style RLE of one component: alternately a run of 5 and a literal of the rest (or 3) */
static void put_rle_component(buf_t *f, const uint8_t *v, int w)
{
    int x = 0, run = 1;
    while (x < w) {
        if (run && x + 5 <= w) {
            f->b[f->n++] = 128 + 5;
            f->b[f->n++] = v[x];
            x += 5;
        } else {
            int k = w - x < 3 ? w - x : 3;
            f->b[f->n++] = (uint8_t)k;
            put_bytes(f, v + x, (size_t)k);
            x += k;
        }
        run = !run;
    }
}

static void test_new_style_rle_and_mixed_lines(void **state)
{
    (void)state;
    enum { W = 16 };
    uint8_t comp[2][4][W];
    for (int y = 0; y < 2; ++y)
        for (int c = 0; c < 4; ++c)
            for (int x = 0; x < W; ++x) /* runs of 5 equal values where the writer emits a run */
                comp[y][c][x] = (uint8_t)(c == 3 ? 120 + y : 10 * c + (x < 5 ? 1 : x < 8 ? x : x < 13 ? 99 : x) + y);
    buf_t f = {{0}, 0};
    header(&f, W, 3);
    for (int y = 0; y < 2; ++y) {
        const uint8_t start[4] = {2, 2, 0, W};
        put_bytes(&f, start, 4);
        for (int c = 0; c < 4; ++c)
            put_rle_component(&f, comp[y][c], W);
    }
    for (int x = 0; x < W; ++x) /* the third line flat: encodings may change per scanline */
        put_px(&f, (uint8_t)x, (uint8_t)(2 * x), 5, 129);
    float *rgb = decode_ok(&f, W, 3);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < W; ++x)
            for (int c = 0; c < 3; ++c)
                assert_true(rgb[3 * (y * W + x) + c] == rgbe(comp[y][c][x], comp[y][3][x]));
    for (int x = 0; x < W; ++x)
        assert_true(rgb[3 * (2 * W + x) + 1] == rgbe((uint8_t)(2 * x), 129));
    free(rgb);
}

static void test_header_quirks_accepted(void **state)
{
    (void)state;
    buf_t f = {{0}, 0};
    put_s(&f, "#?RGBE\n#?RADIANCE\nGAMMA=1\nPRIMARIES=0 0 0 0 0 0 0 0\nEXPOSURE=2\n"
              "FORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n");
    put_px(&f, 128, 0, 0, 129);
    put_px(&f, 0, 0, 0, 0);
    float *rgb = decode_ok(&f, 2, 1);
    assert_true(rgb[0] == 1.0f); /* EXPOSURE is not applied */
    free(rgb);
    buf_t g = {{0}, 0}; /* FORMAT may be absent */
    put_s(&g, "#?RADIANCE\n\n-Y 1 +X 1\n");
    put_px(&g, 128, 128, 128, 130);
    rgb = decode_ok(&g, 1, 1);
    assert_true(rgb[2] == 2.0f);
    free(rgb);
}

static void test_bad_files_fail_with_one_line(void **state)
{
    (void)state;
    buf_t f;
#define CASE(setup, want)                                                                                              \
    do {                                                                                                               \
        f.n = 0;                                                                                                       \
        setup;                                                                                                         \
        decode_fails(&f, want);                                                                                        \
    } while (0)
    CASE(put_s(&f, "P6\n3 2\n255\n"), "no #? magic");
    CASE(put_s(&f, ""), "no #? magic");
    CASE(put_s(&f, "#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\n"), "unsupported FORMAT");
    CASE(put_s(&f, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n"), "truncated header");
    CASE(put_s(&f, "#?RADIANCE\n\n"), "before the resolution");
    CASE(put_s(&f, "#?RADIANCE\n\n-Y two +X 3\n"), "bad resolution line");
    CASE(put_s(&f, "#?RADIANCE\n\n+Y 2 +X 3\n"), "unsupported orientation");
    CASE(put_s(&f, "#?RADIANCE\n\n-Y 0 +X 3\n"), "unsupported dimensions");
    CASE(put_s(&f, "#?RADIANCE\n\n-Y 100000 +X 3\n"), "unsupported dimensions");
    CASE(put_s(&f, "#?RADIANCE\n\n-Y 99999999999999999999 +X 3\n"), "bad resolution line"); /* no overflow */
    CASE(put_s(&f, "#?RADIANCE\n\n-Y 2 +X 3 4\n"), "bad resolution line");
    CASE(put_s(&f, "#?RADIANCE\n\n-Y 2x +X 3\n"), "bad resolution line");
    CASE((header(&f, 3, 1), put_px(&f, 1, 2, 3, 4)), "truncated at scanline 0");
    CASE((header(&f, 2, 2), put_px(&f, 1, 2, 3, 4), put_px(&f, 1, 2, 3, 4)), "truncated at scanline 1");
    CASE((header(&f, 8, 1), put_bytes(&f, (const uint8_t[]){2, 2, 0, 8, 128 + 8, 7}, 6)), "truncated in RLE");
    CASE((header(&f, 8, 1), put_bytes(&f, (const uint8_t[]){2, 2, 0, 8, 128 + 9, 7}, 6)), "run past the end");
    CASE((header(&f, 8, 1), put_bytes(&f, (const uint8_t[]){2, 2, 0, 8, 0}, 5)), "literal of length 0");
    CASE((header(&f, 8, 1), put_bytes(&f, (const uint8_t[]){2, 2, 0, 8, 9, 1, 2, 3, 4, 5, 6, 7, 8, 9}, 14)),
         "literal past the end");
    CASE((header(&f, 8, 1), put_bytes(&f, (const uint8_t[]){2, 2, 0, 9}, 4)), "differs from the image width");
    CASE((header(&f, 3, 1), put_px(&f, 1, 1, 1, 2)), "no pixel before it");
    CASE((header(&f, 3, 1), put_px(&f, 9, 9, 9, 9), put_px(&f, 1, 1, 1, 3)), "past the end of the line");
#undef CASE
}

static void test_read_file_and_missing_file(void **state)
{
    (void)state;
    char path[] = "/tmp/qibl_hdr_test_XXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    buf_t f = {{0}, 0};
    header(&f, 2, 1);
    put_px(&f, 128, 0, 0, 130);
    put_px(&f, 0, 128, 0, 131);
    assert_int_equal(write(fd, f.b, f.n), (ssize_t)f.n);
    close(fd);
    int w, h;
    float *rgb;
    char err[512];
    assert_int_equal(qtool_hdr_read(path, &w, &h, &rgb, err, sizeof err), 0);
    assert_true(w == 2 && h == 1 && rgb[0] == 2.0f && rgb[4] == 4.0f);
    free(rgb);
    /* a truncated copy: the message names the file */
    fd = open(path, O_WRONLY);
    assert_true(fd >= 0);
    assert_int_equal(ftruncate(fd, (off_t)f.n - 3), 0);
    close(fd);
    assert_int_equal(qtool_hdr_read(path, &w, &h, &rgb, err, sizeof err), -1);
    assert_non_null(strstr(err, path));
    assert_non_null(strstr(err, "truncated"));
    unlink(path);
    assert_int_equal(qtool_hdr_read("/nonexistent/qibl.hdr", &w, &h, &rgb, err, sizeof err), -1);
    assert_non_null(strstr(err, "/nonexistent/qibl.hdr"));
    assert_null(strchr(err, '\n'));
}

/* max luminance of each probe as ../shared/fixtures/SOURCES.md lists it (3 significant digits) */
static void test_real_probes_when_present(void **state)
{
    (void)state;
    static const struct {
        const char *name;
        double max_l;
    } probes[] = {
        {"quarry_01_1k.hdr", 6.37e4},         {"immenstadter_horn_1k.hdr", 6.7e3}, {"venice_sunset_1k.hdr", 43.8},
        {"pedestrian_overpass_1k.hdr", 22.0}, {"potsdamer_platz_1k.hdr", 10.9},    {"forest_slope_1k.hdr", 59.4},
        {"studio_small_03_1k.hdr", 3.35e3},   {"lebombo_1k.hdr", 23.3},            {"empty_warehouse_01_1k.hdr", 400.0},
        {"moonless_golf_1k.hdr", 6.5e3},      {"royal_esplanade_1k.hdr", 4.1e4},
    };
    int n = 0, missing = 0;
    for (size_t i = 0; i < sizeof probes / sizeof probes[0]; ++i) {
        char path[256], err[512];
        snprintf(path, sizeof path, "../shared/fixtures/probes/%s", probes[i].name);
        if (access(path, R_OK) != 0) {
            printf("hdr: %s missing\n", path);
            ++missing;
            continue;
        }
        int w, h;
        float *rgb;
        if (qtool_hdr_read(path, &w, &h, &rgb, err, sizeof err) != 0)
            fail_msg("%s", err);
        assert_true(w == 1024 && h == 512);
        double mx = 0.0;
        for (size_t p = 0; p < (size_t)w * (size_t)h; ++p) {
            double l = 0.2126 * rgb[3 * p] + 0.7152 * rgb[3 * p + 1] + 0.0722 * rgb[3 * p + 2];
            assert_true(l > 0.0); /* SOURCES.md: no L = 0 pixel in any probe */
            if (l > mx)
                mx = l;
        }
        if (fabs(mx / probes[i].max_l - 1.0) > 0.006)
            fail_msg("%s: max L %.4g, SOURCES.md says %.3g", probes[i].name, mx, probes[i].max_l);
        free(rgb);
        ++n;
    }
    printf("hdr: %d real probes decoded, 1024x512, max luminance as in SOURCES.md\n", n);
    if (missing)
        skip(); /* the present ones passed; the fixed list is incomplete */
}

/* ---- hostile files ---------------------------------------------------------------------------- */

static int rd_hdr(const char *path, char *err, size_t errlen)
{
    int w, h;
    float *rgb;
    int rc = qtool_hdr_read(path, &w, &h, &rgb, err, errlen);
    if (rc == 0)
        free(rgb);
    return rc;
}

/* first in the suite: it measures the peak memory */
static void test_zeros_refused_by_magic_before_reading(void **state)
{
    (void)state;
    fu_check_zeros_not_read(rd_hdr, (size_t)64 << 20, "no #? magic", QTOOL_HDR_MAX_FILE_BYTES);
}

static void test_not_regular_files_named(void **state)
{
    (void)state;
    fu_check_not_regular(rd_hdr);
}

static void test_empty_and_one_byte_files_named(void **state)
{
    (void)state;
    fu_check_empty_and_one_byte(rd_hdr, '#', "too short");
}

/* Headers claiming more than the light-probe core accepts are refused before any pixel memory;
 * within the limits, a body shorter than the header claims is refused before allocating (walked
 * first). 16384 x 16384 is 2^28 pixels, what the reader used to allow: a 196 KB file of old-style
 * runs decoded to 1 GB before the core said "too large". */
static void test_lying_header_refused(void **state)
{
    (void)state;
    static const int dims[][2] = {{16384, 16384}, {8193, 8192}, {65536, 1024}};
    for (size_t i = 0; i < sizeof dims / sizeof dims[0]; ++i) {
        buf_t f = {{0}, 0};
        header(&f, dims[i][0], dims[i][1]);
        put_px(&f, 128, 128, 128, 128);
        decode_fails(&f, i == 2 ? "QIBL_HDR_MAX_DIM" : "QIBL_HDR_MAX_PIXELS");
    }
    buf_t f = {{0}, 0};
    header(&f, 8192, 8192); /* at the limit, one pixel of body */
    put_px(&f, 128, 128, 128, 128);
    decode_fails(&f, "truncated");
    /* old-style runs (the 4-byte pixel 01 01 01 n, shift growing by 8 per run) fill any line from a
     * few bytes: at the limit the body is all there and decodes */
    f.n = 0;
    header(&f, 8192, 2);
    put_px(&f, 128, 64, 32, 130);
    put_px(&f, 1, 1, 1, 255);                         /* 255 more */
    put_px(&f, 1, 1, 1, 31);                          /* 31 << 8: 7936 more, 8192 in all */
    put_px(&f, 1, 1, 1, 0), put_px(&f, 1, 1, 1, 32); /* the second line: 0, then 32 << 8 */
    int w, h;
    uint8_t *px;
    char err[256];
    if (qtool_hdr_decode_rgbe(f.b, f.n, &w, &h, &px, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_true(w == 8192 && h == 2);
    for (size_t i = 0; i < 2 * 8192; ++i)
        assert_true(px[4 * i] == 128 && px[4 * i + 3] == 130);
    free(px);
    /* a header longer than QIBL_HDR_MAX_HEADER_BYTES */
    size_t big = QIBL_HDR_MAX_HEADER_BYTES + 4096;
    uint8_t *b = malloc(big);
    assert_non_null(b);
    memcpy(b, "#?RADIANCE\n", 11);
    for (size_t i = 11; i < big; ++i)
        b[i] = i % 16 == 15 ? '\n' : i % 16 == 11 ? '#' : 'x';
    w = h = -7;
    assert_int_equal(qtool_hdr_decode(b, big, &w, &h, (float **)&px, err, sizeof err), -1);
    assert_true(w == -7 && h == -7);
    assert_non_null(strstr(err, "QIBL_HDR_MAX_HEADER_BYTES"));
    free(b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_zeros_refused_by_magic_before_reading),
        cmocka_unit_test(test_not_regular_files_named),
        cmocka_unit_test(test_empty_and_one_byte_files_named),
        cmocka_unit_test(test_lying_header_refused),
        cmocka_unit_test(test_flat_scanlines),
        cmocka_unit_test(test_old_style_runs),
        cmocka_unit_test(test_new_style_rle_and_mixed_lines),
        cmocka_unit_test(test_header_quirks_accepted),
        cmocka_unit_test(test_bad_files_fail_with_one_line),
        cmocka_unit_test(test_read_file_and_missing_file),
        cmocka_unit_test(test_real_probes_when_present),
    };
    return cmocka_run_group_tests_name("hdr", tests, NULL, NULL);
}
