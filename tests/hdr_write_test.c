/*
 * hdr_write_test.c - tools/io/hdr_write.c: Radiance files it writes read back through io/hdr.h's
 * reader within RGBE's precision (exactly for values m 2^(e-8)), in both scanline encodings (RLE for
 * 8 <= W < 32768, flat below), RLE smaller than flat on flat areas, and bad samples refused by name
 * with no file left behind.
 */
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "io/hdr.h"
#include "io/hdr_write.h"
#include "testutil.h"

/* encodes, decodes and checks every channel: low by less than 2^(e-8) of its pixel, never high */
static size_t roundtrip(int w, int h, const float *px)
{
    uint8_t *b;
    size_t n;
    char err[256];
    if (qtool_hdr_encode(w, h, px, &b, &n, err, sizeof err) != 0)
        fail_msg("%s", err);
    int w2, h2;
    float *back;
    if (qtool_hdr_decode(b, n, &w2, &h2, &back, err, sizeof err) != 0)
        fail_msg("%dx%d: %s", w, h, err);
    free(b);
    assert_int_equal(w2, w);
    assert_int_equal(h2, h);
    for (size_t i = 0; i < (size_t)w * (size_t)h; ++i) {
        const float *c = px + 3 * i;
        double v = fmax(c[0], fmax(c[1], c[2]));
        int e;
        frexp(v, &e);
        double step = v < 0x1p-100 ? 0x1p-100 : ldexp(1.0, e - 8);
        for (int k = 0; k < 3; ++k) {
            double d = (double)c[k] - back[3 * i + (size_t)k];
            if (!(d >= 0 && d < step))
                fail_msg("%dx%d pixel %zu channel %d: wrote %.9g, read %.9g", w, h, i, k, (double)c[k],
                         (double)back[3 * i + (size_t)k]);
        }
    }
    free(back);
    return n;
}

static void test_roundtrip_random(void **state)
{
    (void)state;
    tu_rng r = {11};
    static const int sizes[][2] = {{1, 1}, {7, 3}, {8, 2}, {300, 20}, {5, 40}};
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; ++s) {
        int w = sizes[s][0], h = sizes[s][1];
        float *px = malloc(sizeof(float) * 3 * (size_t)w * (size_t)h);
        for (size_t i = 0; i < 3 * (size_t)w * (size_t)h; ++i) {
            uint32_t u = tu_u32(&r);
            /* magnitudes 2^-40 .. 2^40, some zeros, and runs of equal pixels */
            px[i] = (u & 15) == 0 ? 0.0f : (float)ldexp((u >> 8) / 16777216.0 + 0.001, (int)(u % 81) - 40);
            if (i >= 3 && (u & 0x30) == 0x30)
                px[i] = px[i - 3];
        }
        roundtrip(w, h, px);
        free(px);
    }
}

static void test_exact_values(void **state)
{
    (void)state;
    /* m 2^(e-8) with the pixel's max in [2^(e-1), 2^e): exact through RGBE */
    float px[16 * 3];
    for (int i = 0; i < 16; ++i)
        px[3 * i] = (float)ldexp(128 + i * 8, i - 20), px[3 * i + 1] = (float)ldexp(i, i - 20), px[3 * i + 2] = 0;
    uint8_t *b;
    size_t n;
    char err[256];
    assert_int_equal(qtool_hdr_encode(16, 1, px, &b, &n, err, sizeof err), 0);
    int w, h;
    float *back;
    assert_int_equal(qtool_hdr_decode(b, n, &w, &h, &back, err, sizeof err), 0);
    assert_memory_equal(back, px, sizeof px);
    free(b), free(back);
}

static void test_rle_and_flat(void **state)
{
    (void)state;
    enum { W = 256, H = 8 };
    float *px = malloc(sizeof(float) * 3 * W * H);
    for (size_t i = 0; i < 3 * W * H; ++i)
        px[i] = 0.75f;
    size_t n = roundtrip(W, H, px);
    /* a flat area: each component of a row is two runs, far below 4 bytes a pixel */
    assert_true(n < 100 + (size_t)W * H / 4);
    /* flat rows (W < 8) of the same */
    roundtrip(6, 2, px);
    free(px);
}

static void test_bad_samples(void **state)
{
    (void)state;
    float px[4 * 3] = {1, 1, 1, 1, 1, 1, 1, NAN, 1, 1, 1, 1};
    uint8_t *b = NULL;
    size_t n;
    char err[256];
    assert_int_equal(qtool_hdr_encode(2, 2, px, &b, &n, err, sizeof err), -1);
    assert_non_null(strstr(err, "sample nan at pixel (0, 1) channel 1"));
    assert_null(b);
    px[7] = -0.5f;
    assert_int_equal(qtool_hdr_encode(2, 2, px, &b, &n, err, sizeof err), -1);
    assert_non_null(strstr(err, "sample -0.5 at pixel (0, 1) channel 1"));
    px[7] = INFINITY;
    assert_int_equal(qtool_hdr_encode(2, 2, px, &b, &n, err, sizeof err), -1);
    px[7] = 1;
    assert_int_equal(qtool_hdr_encode(0, 2, px, &b, &n, err, sizeof err), -1);
    assert_non_null(strstr(err, "bad image size 0x2"));
    char path[64];
    snprintf(path, sizeof path, "/tmp/qibl_hdr_write_%d.hdr", (int)getpid());
    px[0] = NAN;
    assert_int_equal(qtool_hdr_write(path, 2, 2, px, err, sizeof err), -1);
    assert_non_null(strstr(err, path));
    assert_int_equal(access(path, F_OK), -1);
    px[0] = 2;
    assert_int_equal(qtool_hdr_write(path, 2, 2, px, err, sizeof err), 0);
    int w, h;
    float *back;
    assert_int_equal(qtool_hdr_read(path, &w, &h, &back, err, sizeof err), 0);
    assert_true(back[0] == 2.0f && back[11] == 1.0f);
    free(back);
    remove(path);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_roundtrip_random),
        cmocka_unit_test(test_exact_values),
        cmocka_unit_test(test_rle_and_flat),
        cmocka_unit_test(test_bad_samples),
    };
    return cmocka_run_group_tests_name("hdr_write", tests, NULL, NULL);
}
