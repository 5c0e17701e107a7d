/*
 * soft_test.c - platform/soft (qibl/soft.h): pixel packing of every format, exposure, the sRGB
 * table against the exact IEC 61966-2-1 curve, RGB565 rounding and ordered dither, saturating
 * accumulation and resolve, strides and unaligned pixels, every error status (nothing written),
 * and golden SHA-256 hashes of a fixed gradient in every format (fixtures/golden/soft_*.sha256, cases
 * in tools/golden/cases_soft.c; QIBL_UPDATE_GOLDEN=1 rewrites them, see tools/io/golden.h).
 *
 * References are computed here in doubles or 64-bit integers from the definitions in soft.h, not
 * from soft.c's tables. Built twice like every suite (native and portable core paths): the bytes,
 * and so the golden hashes, must not differ.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "qibl/soft.h"
#include "golden/check.h"
#include "testutil.h"

#define ONE 65536

/* ---- references, from the definitions in soft.h --------------------------------------------- */

/* x = clamp(round(v * e), 0, 1.0) in Q16.16, half up; e = 0 means 1.0 */
static uint32_t ref_x(int32_t v, uint32_t e)
{
    if (e == 0)
        e = ONE;
    if (v <= 0)
        return 0;
    uint64_t x = ((uint64_t)v * e + 32768u) >> 16; /* v * e < 2^63 */
    return x > ONE ? ONE : (uint32_t)x;
}

static double srgb_exact(double x)
{
    return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}

static unsigned ref_lin8(uint32_t x) { return (unsigned)floor(x * 255.0 / 65536.0 + 0.5); }

/* 255 * srgb(x) is never closer than 1.6e-5 to a tie over x in 0..65536, so doubles decide
 * every rounding correctly */
static unsigned ref_srgb8(uint32_t x) { return (unsigned)floor(255.0 * srgb_exact(x / 65536.0) + 0.5); }

static const unsigned bayer_ref[4][4] = {{0, 8, 2, 10}, {12, 4, 14, 6}, {3, 11, 1, 9}, {15, 7, 13, 5}};

/* rounding offset of the RGB565 quantiser at (x, y) as a fraction of one output LSB */
static double ref_dither(int dither, uint32_t x, uint32_t y)
{
    return dither ? (2.0 * bayer_ref[y & 3][x & 3] + 1.0) / 32.0 : 0.5;
}

/* one RGB565 channel: u is x (linear) or c * 257 + (c >> 7) for the sRGB code c */
static unsigned ref_q565(uint32_t x, int srgb, unsigned m, double d)
{
    uint32_t u = x;
    if (srgb) {
        unsigned c = ref_srgb8(x);
        u = c * 257u + (c >> 7);
    }
    return (unsigned)floor(u * (double)m / 65536.0 + d);
}

/* expected bytes of one pixel in an 8-bit format */
static void ref_pixel(const qibl_fb_desc_t *fb, uint32_t px, uint32_t py, const int32_t rgb[3], uint8_t *out)
{
    uint32_t x[3];
    for (int c = 0; c < 3; ++c)
        x[c] = ref_x(rgb[c], fb->exposure);
    if (fb->format == QIBL_FB_RGB565) {
        double d = ref_dither(fb->dither, px, py);
        unsigned v = ref_q565(x[0], fb->srgb, 31, d) << 11 | ref_q565(x[1], fb->srgb, 63, d) << 5 |
                     ref_q565(x[2], fb->srgb, 31, d);
        out[0] = (uint8_t)v;
        out[1] = (uint8_t)(v >> 8);
        return;
    }
    unsigned c[3];
    for (int k = 0; k < 3; ++k)
        c[k] = fb->srgb ? ref_srgb8(x[k]) : ref_lin8(x[k]);
    int bgr = fb->format == QIBL_FB_BGRA8888;
    out[0] = (uint8_t)c[bgr ? 2 : 0];
    out[1] = (uint8_t)c[1];
    out[2] = (uint8_t)c[bgr ? 0 : 2];
    out[3] = 255;
}

static int32_t sat_add(int32_t a, int32_t b)
{
    int64_t s = (int64_t)a + b;
    return s > INT32_MAX ? INT32_MAX : s < INT32_MIN ? INT32_MIN : (int32_t)s;
}

static int32_t get_s32le(const uint8_t *p)
{
    uint32_t u = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
    int32_t v;
    memcpy(&v, &u, sizeof v);
    return v;
}

static qibl_fb_desc_t fb_make(void *pixels, qibl_fb_format_t f, uint32_t w, uint32_t h, size_t stride)
{
    qibl_fb_desc_t fb;
    memset(&fb, 0, sizeof fb);
    fb.pixels = pixels;
    fb.format = f;
    fb.width = w;
    fb.height = h;
    fb.stride = stride;
    return fb;
}

/* one pixel written at (0, 0) of a 1x1 framebuffer */
static void write1(qibl_fb_desc_t fb, int32_t r, int32_t g, int32_t b, uint8_t *out)
{
    const int32_t rgb[3] = {r, g, b};
    fb.pixels = out;
    fb.width = fb.height = 1;
    fb.stride = 0;
    assert_int_equal(qibl_soft_fb_write_row(&fb, 0, 0, 1, rgb), QIBL_OK);
}

static const qibl_fb_format_t eight_bit[] = {QIBL_FB_RGBA8888, QIBL_FB_BGRA8888, QIBL_FB_RGB565};

/* ---- formats and packing ------------------------------------------------------------------------ */

static void test_bytes_per_pixel(void **state)
{
    (void)state;
    assert_int_equal(qibl_soft_fb_bytes_per_pixel(QIBL_FB_RGBA8888), 4);
    assert_int_equal(qibl_soft_fb_bytes_per_pixel(QIBL_FB_BGRA8888), 4);
    assert_int_equal(qibl_soft_fb_bytes_per_pixel(QIBL_FB_RGB565), 2);
    assert_int_equal(qibl_soft_fb_bytes_per_pixel(QIBL_FB_ACCUM32), 12);
    assert_int_equal(qibl_soft_fb_bytes_per_pixel(QIBL_FB_FORMAT_COUNT), 0);
    assert_int_equal(qibl_soft_fb_bytes_per_pixel((qibl_fb_format_t)77), 0);
}

static void test_8888_known_values(void **state)
{
    (void)state;
    qibl_fb_desc_t fb = fb_make(NULL, QIBL_FB_RGBA8888, 1, 1, 0);
    uint8_t p[4];
    write1(fb, 0, ONE, ONE / 2, p); /* 0, 1.0, 0.5 (127.5 rounds half up) */
    assert_memory_equal(p, ((uint8_t[]){0, 255, 128, 255}), 4);
    write1(fb, -1, INT32_MIN, -ONE, p); /* negatives clamp to 0 */
    assert_memory_equal(p, ((uint8_t[]){0, 0, 0, 255}), 4);
    write1(fb, ONE + 1, 2 * ONE, INT32_MAX, p); /* > 1 clamps to 255 */
    assert_memory_equal(p, ((uint8_t[]){255, 255, 255, 255}), 4);
    write1(fb, ONE / 4, 1, 128, p); /* 63.75 -> 64; 1 LSB -> 0; 128/65536 * 255 = 0.498 -> 0 */
    assert_memory_equal(p, ((uint8_t[]){64, 0, 0, 255}), 4);
    write1(fb, 129, 385, 384, p); /* 0.502 -> 1; 1.498 -> 1; 1.494 -> 1 */
    assert_memory_equal(p, ((uint8_t[]){1, 1, 1, 255}), 4);

    fb.format = QIBL_FB_BGRA8888;
    write1(fb, ONE, ONE / 2, 0, p);
    assert_memory_equal(p, ((uint8_t[]){0, 128, 255, 255}), 4);

    fb.format = QIBL_FB_RGBA8888;
    fb.srgb = 1; /* sRGB(0.5) = 0.7354 -> 187.5 + ... = 188; sRGB(0.18) = 0.4614 -> 118 */
    write1(fb, ONE / 2, 11796 /* 0.18 */, ONE, p);
    assert_memory_equal(p, ((uint8_t[]){188, 118, 255, 255}), 4);
    write1(fb, -5, 0, 9, p); /* 9/65536 * 12.92 * 255 = 0.45 -> 0 */
    assert_memory_equal(p, ((uint8_t[]){0, 0, 0, 255}), 4);
    write1(fb, 10, 30, INT32_MAX, p); /* 0.50 -> 1 (first code boundary at 9.95), 1.51 -> 2 */
    assert_memory_equal(p, ((uint8_t[]){1, 2, 255, 255}), 4);
}

static void test_565_known_values(void **state)
{
    (void)state;
    qibl_fb_desc_t fb = fb_make(NULL, QIBL_FB_RGB565, 1, 1, 0);
    uint8_t p[2];
    write1(fb, ONE, ONE, ONE, p);
    assert_memory_equal(p, ((uint8_t[]){0xFF, 0xFF}), 2);
    write1(fb, ONE, 0, 0, p); /* little-endian 0xF800 */
    assert_memory_equal(p, ((uint8_t[]){0x00, 0xF8}), 2);
    write1(fb, 0, ONE, 0, p); /* 0x07E0 */
    assert_memory_equal(p, ((uint8_t[]){0xE0, 0x07}), 2);
    write1(fb, -1, 5 * ONE, ONE, p); /* 0x07FF */
    assert_memory_equal(p, ((uint8_t[]){0xFF, 0x07}), 2);
    write1(fb, ONE / 2, ONE / 2, ONE / 2, p); /* 15.5 -> 16, 31.5 -> 32: 0x8410 */
    assert_memory_equal(p, ((uint8_t[]){0x10, 0x84}), 2);
    write1(fb, INT32_MIN, INT32_MIN, INT32_MIN, p);
    assert_memory_equal(p, ((uint8_t[]){0x00, 0x00}), 2);
    fb.srgb = 1; /* sRGB(0.5) = 188 -> 188/255 * 31 = 22.85 -> 23, * 63 = 46.45 -> 46 */
    write1(fb, ONE / 2, ONE / 2, ONE / 2, p);
    unsigned v = 23u << 11 | 46u << 5 | 23u;
    assert_int_equal(p[0] | p[1] << 8, v);
}

static void test_accum32_known_values(void **state)
{
    (void)state;
    uint8_t p[12] = {0};
    qibl_fb_desc_t fb = fb_make(p, QIBL_FB_ACCUM32, 1, 1, 0);
    fb.exposure = 3 * ONE; /* all ignored by the accumulator */
    fb.srgb = 1;
    fb.dither = 1;
    const int32_t a[3] = {ONE, -2, 0x12345678};
    assert_int_equal(qibl_soft_fb_write_row(&fb, 0, 0, 1, a), QIBL_OK);
    const uint8_t want[12] = {0x00, 0x00, 0x01, 0x00, 0xFE, 0xFF, 0xFF, 0xFF, 0x78, 0x56, 0x34, 0x12};
    assert_memory_equal(p, want, 12);
    assert_int_equal(qibl_soft_fb_write_row(&fb, 0, 0, 1, a), QIBL_OK); /* adds */
    assert_int_equal(get_s32le(p), 2 * ONE);
    assert_int_equal(get_s32le(p + 4), -4);
    assert_int_equal(get_s32le(p + 8), 0x2468ACF0);
}

static void test_accum32_saturates(void **state)
{
    (void)state;
    uint8_t p[12] = {0};
    qibl_fb_desc_t fb = fb_make(p, QIBL_FB_ACCUM32, 1, 1, 0);
    const int32_t big[3] = {INT32_MAX, INT32_MIN, INT32_MAX};
    const int32_t nudge[3] = {1, -1, INT32_MIN};
    assert_int_equal(qibl_soft_fb_write_row(&fb, 0, 0, 1, big), QIBL_OK);
    assert_int_equal(qibl_soft_fb_write_row(&fb, 0, 0, 1, nudge), QIBL_OK);
    assert_int_equal(get_s32le(p), INT32_MAX);
    assert_int_equal(get_s32le(p + 4), INT32_MIN);
    assert_int_equal(get_s32le(p + 8), -1);
    assert_int_equal(qibl_soft_fb_write_row(&fb, 0, 0, 1, big), QIBL_OK); /* MAX + MAX, MIN + MIN */
    assert_int_equal(get_s32le(p), INT32_MAX);
    assert_int_equal(get_s32le(p + 4), INT32_MIN);
    assert_int_equal(get_s32le(p + 8), INT32_MAX - 1);
    assert_memory_equal(p, ((uint8_t[]){0xFF, 0xFF, 0xFF, 0x7F, 0x00, 0x00, 0x00, 0x80}), 8);

    /* property: a row of random sums against 64-bit saturation */
    enum { N = 64 };
    uint8_t row[N * 12] = {0};
    int32_t want[3 * N] = {0}, v[3 * N];
    fb = fb_make(row, QIBL_FB_ACCUM32, N, 1, 0);
    tu_rng r = {7};
    for (int pass = 0; pass < 200; ++pass) {
        for (int i = 0; i < 3 * N; ++i) {
            v[i] = (tu_next(&r) & 3) == 0 ? tu_s32(&r) : (int32_t)(tu_u32(&r) % 0x40000u) - 0x20000;
            want[i] = sat_add(want[i], v[i]);
        }
        assert_int_equal(qibl_soft_fb_write_row(&fb, 0, 0, N, v), QIBL_OK);
        for (int i = 0; i < 3 * N; ++i)
            assert_int_equal(get_s32le(row + 4 * i), want[i]);
    }
}

/* ---- conversions against the exact definitions -------------------------------------------------- */

/* All 65537 values of x (exposure 1.0 makes x = v) through an fb one row wide per value block. */
static void sweep(qibl_fb_format_t f, int srgb, uint8_t *out /* 65537 pixels */)
{
    enum { W = 4099 }; /* 65537 = 16 * 4096 + 1: the last row is partial */
    int32_t rgb[3 * W];
    qibl_fb_desc_t fb = fb_make(out, f, W, 16, 0);
    fb.srgb = (uint8_t)srgb;
    for (uint32_t y = 0, v = 0; v <= ONE; ++y) {
        uint32_t n = 0;
        for (; n < W && v <= ONE; ++n, ++v)
            rgb[3 * n] = rgb[3 * n + 1] = rgb[3 * n + 2] = (int32_t)v;
        assert_int_equal(qibl_soft_fb_write_row(&fb, 0, y, n, rgb), QIBL_OK);
    }
}

static void test_linear8_exact_rounding(void **state)
{
    (void)state;
    uint8_t *out = malloc(4099u * 16u * 4u);
    assert_non_null(out);
    sweep(QIBL_FB_RGBA8888, 0, out);
    for (uint32_t x = 0; x <= ONE; ++x) {
        unsigned want = ref_lin8(x);
        if (out[4 * x] != want || out[4 * x + 1] != want || out[4 * x + 2] != want || out[4 * x + 3] != 255)
            fail_msg("linear 8-bit at x = %u: got %u, want %u", x, out[4 * x], want);
    }
    free(out);
}

static void test_srgb_table_against_exact_curve(void **state)
{
    (void)state;
    uint8_t *out = malloc(4099u * 16u * 4u);
    assert_non_null(out);
    sweep(QIBL_FB_BGRA8888, 1, out);
    double maxerr = 0;
    uint32_t at = 0;
    for (uint32_t x = 0; x <= ONE; ++x) {
        double exact = 255.0 * srgb_exact(x / 65536.0);
        double err = fabs(out[4 * x] - exact);
        if (err > maxerr)
            maxerr = err, at = x;
        if (out[4 * x] != ref_srgb8(x) || out[4 * x + 1] != out[4 * x] || out[4 * x + 2] != out[4 * x])
            fail_msg("sRGB 8-bit at x = %u: got %u, want %u (exact %.6f)", x, out[4 * x], ref_srgb8(x), exact);
    }
    printf("soft: sRGB table: max |error| %.5f LSB (at x = %u) over all 65537 Q16.16 inputs 0..1; bound 0.5\n",
           maxerr, at);
    assert_true(maxerr <= 0.5);
    free(out);
}

static void test_rgb565_rounding_and_srgb_bound(void **state)
{
    (void)state;
    uint8_t *out = malloc(4099u * 16u * 2u);
    assert_non_null(out);
    for (int srgb = 0; srgb < 2; ++srgb) {
        sweep(QIBL_FB_RGB565, srgb, out);
        double max5 = 0, max6 = 0;
        for (uint32_t x = 0; x <= ONE; ++x) {
            unsigned v = out[2 * x] | out[2 * x + 1] << 8;
            unsigned r = v >> 11, g = (v >> 5) & 63, b = v & 31;
            assert_int_equal(r, ref_q565(x, srgb, 31, 0.5));
            assert_int_equal(g, ref_q565(x, srgb, 63, 0.5));
            assert_int_equal(b, r);
            double t = srgb ? srgb_exact(x / 65536.0) : x / 65536.0;
            max5 = fmax(max5, fabs(r - 31.0 * t));
            max6 = fmax(max6, fabs(g - 63.0 * t));
        }
        printf("soft: RGB565 %s: max |error| %.4f LSB (5 bits), %.4f LSB (6 bits)\n", srgb ? "sRGB" : "linear",
               max5, max6);
        assert_true(max5 <= (srgb ? 0.63 : 0.5));
        assert_true(max6 <= (srgb ? 0.63 : 0.5));
    }
    free(out);
}

static void test_exposure(void **state)
{
    (void)state;
    qibl_fb_desc_t fb = fb_make(NULL, QIBL_FB_RGBA8888, 1, 1, 0);
    uint8_t p[4];
    fb.exposure = 2 * ONE;
    write1(fb, ONE / 2, ONE / 4, ONE, p); /* 1.0, 0.5, 2.0 */
    assert_memory_equal(p, ((uint8_t[]){255, 128, 255, 255}), 4);
    fb.exposure = ONE / 2;
    write1(fb, ONE, 2 * ONE, -ONE, p); /* 0.5, 1.0, -0.5 */
    assert_memory_equal(p, ((uint8_t[]){128, 255, 0, 255}), 4);
    fb.exposure = 0xFFFFFFFFu; /* the largest: 1 LSB * 65536 - 2^-16 rounds up to 1.0 */
    write1(fb, 1, 0, INT32_MAX, p);
    assert_memory_equal(p, ((uint8_t[]){255, 0, 255, 255}), 4);
    fb.exposure = 1; /* the smallest: 2^-16 */
    write1(fb, INT32_MAX, 32767, 32768, p); /* 32768 - 2^-16 -> 0.5 -> 128; 0.49999 -> 0 */
    assert_memory_equal(p, ((uint8_t[]){128, 0, 0, 255}), 4);
    fb.exposure = 0; /* 0 means 1.0 */
    write1(fb, ONE / 2, ONE, ONE + 1, p);
    assert_memory_equal(p, ((uint8_t[]){128, 255, 255, 255}), 4);

    /* property: random v and e, every 8-bit path, against ref_x */
    tu_rng r = {11};
    enum { N = 32 };
    int32_t rgb[3 * N];
    uint8_t got[4 * N], want[4];
    for (int iter = 0; iter < 4000; ++iter) {
        qibl_fb_desc_t f = fb_make(got, eight_bit[iter % 3], N, 1, 0);
        f.srgb = (uint8_t)(iter / 3 % 2);
        switch (iter % 5) {
        case 0: f.exposure = tu_u32(&r); break;
        case 1: f.exposure = tu_u32(&r) % (4 * ONE); break;
        case 2: f.exposure = tu_u32_any_width(&r); break;
        case 3: f.exposure = ONE; break;
        default: f.exposure = 0; break;
        }
        for (int i = 0; i < 3 * N; ++i)
            rgb[i] = (i & 1) ? (int32_t)tu_u32_any_width(&r) >> 1 : (int32_t)(tu_u32(&r) % (3 * ONE)) - ONE / 2;
        assert_int_equal(qibl_soft_fb_write_row(&f, 0, 0, N, rgb), QIBL_OK);
        uint32_t bpp = qibl_soft_fb_bytes_per_pixel(f.format);
        for (uint32_t i = 0; i < N; ++i) {
            ref_pixel(&f, i, 0, rgb + 3 * i, want);
            if (memcmp(got + bpp * i, want, bpp) != 0)
                fail_msg("format %d srgb %d exposure %u pixel (%d, %d, %d)", f.format, f.srgb, f.exposure,
                         rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]);
        }
    }
}

/* ---- dither ------------------------------------------------------------------------------------ */

/* a flat field of value v over a w x h RGB565 image */
static void flat565(uint8_t *buf, uint32_t w, uint32_t h, int32_t v, int dither, int srgb)
{
    qibl_fb_desc_t fb = fb_make(buf, QIBL_FB_RGB565, w, h, 0);
    fb.dither = (uint8_t)dither;
    fb.srgb = (uint8_t)srgb;
    int32_t rgb[3 * 64];
    for (uint32_t i = 0; i < 3 * w; ++i)
        rgb[i] = v;
    for (uint32_t y = 0; y < h; ++y)
        assert_int_equal(qibl_soft_fb_write_row(&fb, 0, y, w, rgb), QIBL_OK);
}

static void test_dither_pattern(void **state)
{
    (void)state;
    uint8_t buf[8 * 8 * 2];
    /* a flat 0.5: exact means 15.5 (R, B) and 31.5 (G) over every aligned 4x4 block */
    flat565(buf, 8, 8, ONE / 2, 1, 0);
    for (int by = 0; by < 8; by += 4)
        for (int bx = 0; bx < 8; bx += 4) {
            unsigned sr = 0, sg = 0;
            for (int y = by; y < by + 4; ++y)
                for (int x = bx; x < bx + 4; ++x) {
                    unsigned v = buf[2 * (8 * y + x)] | buf[2 * (8 * y + x) + 1] << 8;
                    sr += v >> 11, sg += (v >> 5) & 63;
                    assert_int_equal(v & 31, v >> 11);
                    /* the Bayer order: thresholds below 16 of 32 push 15.5 up */
                    assert_int_equal(v >> 11, bayer_ref[y & 3][x & 3] >= 8 ? 16 : 15);
                }
            assert_int_equal(sr, 16 * 31 / 2);
            assert_int_equal(sg, 16 * 63 / 2);
        }
    /* random flat values: block mean within 1/32 LSB of the exact u * M, each pixel within 1 LSB */
    tu_rng r = {5};
    double worst = 0;
    for (int iter = 0; iter < 3000; ++iter) {
        int32_t v = (int32_t)(tu_u32(&r) % (ONE + 1));
        int srgb = iter & 1;
        flat565(buf, 4, 4, v, 1, srgb);
        uint32_t u = ref_x(v, 0);
        if (srgb) {
            unsigned c = ref_srgb8(u);
            u = c * 257u + (c >> 7);
        }
        double er = u * 31.0 / 65536.0, eg = u * 63.0 / 65536.0, sr = 0, sg = 0;
        for (int i = 0; i < 16; ++i) {
            unsigned p = buf[2 * i] | buf[2 * i + 1] << 8;
            sr += p >> 11, sg += (p >> 5) & 63;
            assert_true(fabs((p >> 11) - er) < 1.0 && fabs(((p >> 5) & 63) - eg) < 1.0);
        }
        worst = fmax(worst, fmax(fabs(sr / 16 - er), fabs(sg / 16 - eg)));
    }
    printf("soft: RGB565 dither: worst 4x4 block mean error %.5f LSB (bound 1/32)\n", worst);
    assert_true(worst <= 1.0 / 32 + 1e-12);

    /* dither is ignored by the 8888 formats */
    uint8_t a[4], b[4];
    for (int f = 0; f < 2; ++f) {
        qibl_fb_desc_t fb = fb_make(NULL, eight_bit[f], 1, 1, 0);
        write1(fb, 12345, 40000, 777, a);
        fb.dither = 1;
        write1(fb, 12345, 40000, 777, b);
        assert_memory_equal(a, b, 4);
    }
}

/* The pattern is indexed by absolute framebuffer position: a row written as one span and the
 * same row written as many short spans (any starting x) give the same bytes. */
static void test_dither_tiles_across_spans(void **state)
{
    (void)state;
    enum { W = 29, H = 11 };
    uint8_t whole[W * H * 2], parts[W * H * 2];
    int32_t rgb[3 * W * H];
    tu_rng r = {9};
    for (int i = 0; i < 3 * W * H; ++i)
        rgb[i] = (int32_t)(tu_u32(&r) % (ONE + ONE / 4)) - ONE / 8;
    for (int srgb = 0; srgb < 2; ++srgb) {
        qibl_fb_desc_t fa = fb_make(whole, QIBL_FB_RGB565, W, H, 0), fp = fb_make(parts, QIBL_FB_RGB565, W, H, 0);
        fa.dither = fp.dither = 1;
        fa.srgb = fp.srgb = (uint8_t)srgb;
        fa.exposure = fp.exposure = ONE + ONE / 3;
        memset(parts, 0, sizeof parts);
        for (uint32_t y = 0; y < H; ++y) {
            assert_int_equal(qibl_soft_fb_write_row(&fa, 0, y, W, rgb + 3 * W * y), QIBL_OK);
            for (uint32_t x = 0; x < W;) { /* spans of 1..7 pixels, rows in reverse order */
                uint32_t yy = H - 1 - y, n = 1 + tu_u32(&r) % 7;
                if (n > W - x)
                    n = W - x;
                assert_int_equal(qibl_soft_fb_write_row(&fp, x, yy, n, rgb + 3 * (W * yy + x)), QIBL_OK);
                x += n;
            }
        }
        assert_memory_equal(whole, parts, sizeof whole);
        /* and each pixel is the reference at its absolute position */
        for (uint32_t y = 0; y < H; ++y)
            for (uint32_t x = 0; x < W; ++x) {
                uint8_t want[4];
                ref_pixel(&fa, x, y, rgb + 3 * (W * y + x), want);
                assert_memory_equal(whole + 2 * (W * y + x), want, 2);
            }
    }
}

/* ---- resolve ------------------------------------------------------------------------------------ */

static void test_resolve_equals_direct_write(void **state)
{
    (void)state;
    enum { W = 37, H = 5 }; /* more than one 16-pixel chunk, a partial last one */
    static uint8_t acc[H * (W * 12 + 8)], got[H * (W * 4 + 5)], want[H * (W * 4 + 5)];
    int32_t a[3 * W], sum[3 * W * H];
    tu_rng r = {13};
    qibl_fb_desc_t src = fb_make(acc, QIBL_FB_ACCUM32, W, H, W * 12 + 8);
    assert_int_equal(qibl_soft_fb_clear(&src), QIBL_OK);
    memset(sum, 0, sizeof sum);
    for (int pass = 0; pass < 3; ++pass)
        for (uint32_t y = 0; y < H; ++y) {
            for (int i = 0; i < 3 * W; ++i) {
                a[i] = (i % 11 == 0) ? tu_s32(&r) : (int32_t)(tu_u32(&r) % (ONE / 2)) - ONE / 8;
                sum[3 * W * y + i] = sat_add(sum[3 * W * y + i], a[i]);
            }
            assert_int_equal(qibl_soft_fb_write_row(&src, 0, y, W, a), QIBL_OK);
        }
    for (int cfg = 0; cfg < 3 * 2 * 2 * 3; ++cfg) {
        qibl_fb_format_t f = eight_bit[cfg % 3];
        uint32_t bpp = qibl_soft_fb_bytes_per_pixel(f);
        size_t stride = (size_t)W * bpp + (cfg & 1 ? 5 : 0);
        qibl_fb_desc_t d = fb_make(got, f, W, H, stride), e = fb_make(want, f, W, H, stride);
        d.srgb = e.srgb = (uint8_t)(cfg / 3 % 2);
        d.dither = e.dither = (uint8_t)(cfg / 6 % 2);
        d.exposure = e.exposure = (uint32_t[]){0, ONE * 3 / 2, ONE / 3}[cfg / 12];
        tu_fill_guard(got, sizeof got);
        tu_fill_guard(want, sizeof want);
        assert_int_equal(qibl_soft_fb_resolve(&d, &src), QIBL_OK);
        for (uint32_t y = 0; y < H; ++y)
            assert_int_equal(qibl_soft_fb_write_row(&e, 0, y, W, sum + 3 * W * y), QIBL_OK);
        assert_memory_equal(got, want, sizeof got); /* padding bytes too: both untouched */
    }
}

static void test_resolve_in_place(void **state)
{
    (void)state;
    enum { W = 21, H = 6 };
    static uint8_t acc[W * H * 12], ref[W * H * 4];
    int32_t rgb[3 * W];
    tu_rng r = {17};
    for (int fi = 0; fi < 3; ++fi) {
        qibl_fb_desc_t src = fb_make(acc, QIBL_FB_ACCUM32, W, H, 0);
        qibl_fb_desc_t dst = fb_make(acc, eight_bit[fi], W, H, 0); /* same memory, packed rows */
        qibl_fb_desc_t e = fb_make(ref, eight_bit[fi], W, H, 0);
        dst.srgb = e.srgb = 1;
        dst.dither = e.dither = 1;
        assert_int_equal(qibl_soft_fb_clear(&src), QIBL_OK);
        for (uint32_t y = 0; y < H; ++y) {
            for (int i = 0; i < 3 * W; ++i)
                rgb[i] = (int32_t)(tu_u32(&r) % (ONE + ONE / 8));
            assert_int_equal(qibl_soft_fb_write_row(&src, 0, y, W, rgb), QIBL_OK);
            assert_int_equal(qibl_soft_fb_write_row(&e, 0, y, W, rgb), QIBL_OK);
        }
        assert_int_equal(qibl_soft_fb_resolve(&dst, &src), QIBL_OK);
        assert_memory_equal(acc, ref, (size_t)W * H * qibl_soft_fb_bytes_per_pixel(eight_bit[fi]));
    }
}

/* ---- layout: strides, unaligned pixels, clear ---------------------------------------------------- */

static void test_stride_and_unaligned_pixels(void **state)
{
    (void)state;
    enum { W = 9, H = 4 };
    int32_t rgb[3 * W * H];
    tu_rng r = {19};
    for (int i = 0; i < 3 * W * H; ++i)
        rgb[i] = (int32_t)(tu_u32(&r) % (ONE + ONE / 2)) - ONE / 4;
    for (int f = 0; f < QIBL_FB_FORMAT_COUNT; ++f)
        for (size_t off = 0; off < 4; ++off)
            for (size_t pad = 0; pad < 8; pad += 7) {
                uint32_t bpp = qibl_soft_fb_bytes_per_pixel((qibl_fb_format_t)f);
                size_t row = (size_t)W * bpp, stride = row + pad;
                uint8_t tight[W * H * 12], buf[4 + H * (W * 12 + 7) + 16];
                qibl_fb_desc_t t = fb_make(tight, (qibl_fb_format_t)f, W, H, 0);
                qibl_fb_desc_t b = fb_make(buf + off, (qibl_fb_format_t)f, W, H, pad ? stride : 0);
                t.srgb = b.srgb = 1;
                t.dither = b.dither = 1;
                t.exposure = b.exposure = 40000;
                memset(tight, 0, sizeof tight);
                tu_fill_guard(buf, sizeof buf);
                if (f == QIBL_FB_ACCUM32) { /* start from zero in the padded one too */
                    assert_int_equal(qibl_soft_fb_clear(&b), QIBL_OK);
                }
                for (uint32_t y = 0; y < H; ++y) {
                    assert_int_equal(qibl_soft_fb_write_row(&t, 0, y, W, rgb + 3 * W * y), QIBL_OK);
                    assert_int_equal(qibl_soft_fb_write_row(&b, 0, y, W, rgb + 3 * W * y), QIBL_OK);
                }
                assert_true(tu_guard_intact(buf, off));
                for (uint32_t y = 0; y < H; ++y) {
                    assert_memory_equal(buf + off + y * stride, tight + y * row, row);
                    size_t gap = y + 1 < H ? pad : sizeof buf - off - y * stride - row;
                    assert_true(tu_guard_intact(buf + off + y * stride + row, gap));
                }
            }
}

static void test_clear(void **state)
{
    (void)state;
    enum { W = 5, H = 3, PAD = 3 };
    uint8_t buf[1 + H * (W * 12 + PAD)];
    for (int f = 0; f < QIBL_FB_FORMAT_COUNT; ++f) {
        uint32_t bpp = qibl_soft_fb_bytes_per_pixel((qibl_fb_format_t)f);
        size_t row = (size_t)W * bpp, stride = row + PAD;
        qibl_fb_desc_t fb = fb_make(buf + 1, (qibl_fb_format_t)f, W, H, stride);
        tu_fill_guard(buf, sizeof buf);
        assert_int_equal(qibl_soft_fb_clear(&fb), QIBL_OK);
        assert_int_equal(buf[0], TU_GUARD);
        for (uint32_t y = 0; y < H; ++y) {
            const uint8_t *p = buf + 1 + y * stride;
            for (size_t i = 0; i < row; ++i)
                assert_int_equal(p[i], bpp == 4 && i % 4 == 3 ? 255 : 0);
            if (y + 1 < H)
                assert_true(tu_guard_intact(p + row, PAD));
        }
        /* and black written is what clear writes */
        if (f != QIBL_FB_ACCUM32) {
            uint8_t px[4];
            write1(fb_make(NULL, (qibl_fb_format_t)f, 1, 1, 0), 0, -7, 0, px);
            assert_memory_equal(px, buf + 1, bpp);
        }
    }
}

/* ---- errors: each status, nothing written ------------------------------------------------------- */

static void test_errors_write_nothing(void **state)
{
    (void)state;
    enum { W = 6, H = 3 };
    static uint8_t buf[W * H * 12], acc[W * H * 12];
    const int32_t rgb[3 * (W + 1)] = {ONE, ONE, ONE};
    tu_fill_guard(buf, sizeof buf);
    tu_fill_guard(acc, sizeof acc);
    qibl_fb_desc_t ok = fb_make(buf, QIBL_FB_RGBA8888, W, H, 0), fb;
    qibl_fb_desc_t src = fb_make(acc, QIBL_FB_ACCUM32, W, H, 0);
    assert_int_equal(qibl_soft_fb_check(&ok), QIBL_OK);
    assert_int_equal(qibl_soft_fb_check(&src), QIBL_OK);

    /* descriptor errors, through every entry point */
    struct { qibl_fb_desc_t fb; qibl_status_t st; } bad[12];
    int nb = 0;
    fb = ok, fb.pixels = NULL, bad[nb].fb = fb, bad[nb++].st = QIBL_E_NULL_POINTER;
    fb = ok, fb.format = QIBL_FB_FORMAT_COUNT, bad[nb].fb = fb, bad[nb++].st = QIBL_E_FB_FORMAT;
    fb = ok, fb.format = (qibl_fb_format_t)1000, bad[nb].fb = fb, bad[nb++].st = QIBL_E_FB_FORMAT;
    fb = ok, fb.width = 0, bad[nb].fb = fb, bad[nb++].st = QIBL_E_FB_SIZE;
    fb = ok, fb.height = 0, bad[nb].fb = fb, bad[nb++].st = QIBL_E_FB_SIZE;
    fb = ok, fb.stride = W * 4 - 1, bad[nb].fb = fb, bad[nb++].st = QIBL_E_FB_STRIDE;
    fb = ok, fb.stride = 1, bad[nb].fb = fb, bad[nb++].st = QIBL_E_FB_STRIDE;
    fb = ok, fb.stride = SIZE_MAX / 2, bad[nb].fb = fb, bad[nb++].st = QIBL_E_FB_STRIDE; /* 2 rows overflow */
    fb = ok, fb.stride = SIZE_MAX, fb.height = 2, bad[nb].fb = fb, bad[nb++].st = QIBL_E_FB_STRIDE;
    fb = ok, fb.width = UINT32_MAX, fb.height = UINT32_MAX, bad[nb].fb = fb, bad[nb++].st = QIBL_E_FB_STRIDE;
    for (int i = 0; i < nb; ++i) {
        qibl_fb_desc_t d = bad[i].fb;
        assert_int_equal(qibl_soft_fb_check(&d), bad[i].st);
        assert_int_equal(qibl_soft_fb_write_row(&d, 0, 0, 1, rgb), bad[i].st);
        assert_int_equal(qibl_soft_fb_write_row(&d, 0, 0, 1, NULL), bad[i].st); /* descriptor checked first */
        assert_int_equal(qibl_soft_fb_clear(&d), bad[i].st);
        assert_int_equal(qibl_soft_fb_resolve(&d, &src), bad[i].st);
        d.format = QIBL_FB_ACCUM32;
        if (bad[i].st != QIBL_E_FB_FORMAT) /* as a bad source */
            assert_int_equal(qibl_soft_fb_resolve(&ok, &d), bad[i].st);
    }
    assert_int_equal(qibl_soft_fb_check(NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_soft_fb_write_row(NULL, 0, 0, 1, rgb), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_soft_fb_clear(NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_soft_fb_resolve(NULL, &src), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_soft_fb_resolve(&ok, NULL), QIBL_E_NULL_POINTER);

    /* write_row: rgb NULL, then bounds */
    for (int f = 0; f < QIBL_FB_FORMAT_COUNT; ++f) {
        fb = fb_make(f == QIBL_FB_ACCUM32 ? acc : buf, (qibl_fb_format_t)f, W, H, 0);
        assert_int_equal(qibl_soft_fb_write_row(&fb, 0, 0, 1, NULL), QIBL_E_NULL_POINTER);
        assert_int_equal(qibl_soft_fb_write_row(&fb, 0, H, 1, rgb), QIBL_E_FB_BOUNDS);
        assert_int_equal(qibl_soft_fb_write_row(&fb, 0, UINT32_MAX, 1, rgb), QIBL_E_FB_BOUNDS);
        assert_int_equal(qibl_soft_fb_write_row(&fb, 0, 0, W + 1, rgb), QIBL_E_FB_BOUNDS);
        assert_int_equal(qibl_soft_fb_write_row(&fb, 1, 0, W, rgb), QIBL_E_FB_BOUNDS);
        assert_int_equal(qibl_soft_fb_write_row(&fb, W + 1, 0, 0, rgb), QIBL_E_FB_BOUNDS);
        assert_int_equal(qibl_soft_fb_write_row(&fb, 2, 1, UINT32_MAX, rgb), QIBL_E_FB_BOUNDS); /* x0 + n wraps */
        assert_int_equal(qibl_soft_fb_write_row(&fb, UINT32_MAX, 1, 2, rgb), QIBL_E_FB_BOUNDS);
        /* empty spans are fine and write nothing */
        assert_int_equal(qibl_soft_fb_write_row(&fb, W, H - 1, 0, rgb), QIBL_OK);
        assert_int_equal(qibl_soft_fb_write_row(&fb, 0, 0, 0, rgb), QIBL_OK);
    }

    /* resolve: formats, then sizes */
    qibl_fb_desc_t s8 = fb_make(acc, QIBL_FB_RGBA8888, W, H, 0), dacc = fb_make(buf, QIBL_FB_ACCUM32, W, H, 0);
    assert_int_equal(qibl_soft_fb_resolve(&ok, &s8), QIBL_E_FB_FORMAT);
    assert_int_equal(qibl_soft_fb_resolve(&dacc, &src), QIBL_E_FB_FORMAT);
    fb = ok, fb.width = W - 1;
    assert_int_equal(qibl_soft_fb_resolve(&fb, &src), QIBL_E_FB_SIZE);
    fb = ok, fb.height = H - 1;
    assert_int_equal(qibl_soft_fb_resolve(&fb, &src), QIBL_E_FB_SIZE);

    assert_true(tu_guard_intact(buf, sizeof buf));
    assert_true(tu_guard_intact(acc, sizeof acc));
}

/* ---- goldens ------------------------------------------------------------------------------------ */

/* The fixed gradient (extreme values, spans of 1..13 pixels, every format, two accumulation passes
 * and the resolves) lives in tools/golden/cases_soft.c, shared with the golden runner that
 * `make ports` runs on every architecture. */
static void test_golden_gradient(void **state)
{
    (void)state;
    assert_int_equal(qtool_goldens_check("soft"), 0);
}

/* The backend's statuses live in its own range (status.h) and have their own texts. */
static void test_status_range_and_names(void **state)
{
    (void)state;
    const qibl_status_t fb[4] = {QIBL_E_FB_FORMAT, QIBL_E_FB_SIZE, QIBL_E_FB_STRIDE, QIBL_E_FB_BOUNDS};
    for (int i = 0; i < 4; ++i) {
        assert_true((unsigned)fb[i] > (unsigned)QIBL_STATUS_SOFT_BASE);
        assert_true((unsigned)fb[i] < (unsigned)QIBL_STATUS_SOFT_BASE + 256u);
        const char *a = qibl_soft_status_str(fb[i]);
        assert_true(strncmp(a, "framebuffer: ", 13) == 0);
        assert_string_equal(qibl_status_str(fb[i]), "platform backend status");
        for (int j = 0; j < i; ++j)
            assert_string_not_equal(a, qibl_soft_status_str(fb[j]));
    }
    /* the core's own values pass through */
    assert_string_equal(qibl_soft_status_str(QIBL_E_NULL_POINTER), qibl_status_str(QIBL_E_NULL_POINTER));
}

/* The one list (soft.h) holds every value of the range in order from base + 1, each with the
 * message qibl_soft_status_str gives, non-empty and distinct; values are ABI, a few pinned. */
static void test_status_list(void **state)
{
    (void)state;
    const char *msg[16];
    unsigned n = 0;
#define CHECK_(name, message) \
    assert_int_equal((unsigned)(name), (unsigned)QIBL_STATUS_SOFT_BASE + 1u + n); \
    assert_string_equal(qibl_soft_status_str(name), message); \
    assert_true(strlen(message) > 0); \
    msg[n++] = message;
    QIBL_SOFT_STATUS_LIST(CHECK_)
#undef CHECK_
    assert_int_equal(n, 6);
    for (unsigned i = 0; i < n; ++i)
        for (unsigned j = 0; j < i; ++j)
            assert_string_not_equal(msg[i], msg[j]);
    assert_int_equal((int)QIBL_E_FB_FORMAT, 0x101);
    assert_int_equal((int)QIBL_E_RASTER_INDEX, 0x106);
    /* one past the list: not this backend's */
    assert_string_equal(qibl_soft_status_str((qibl_status_t)(QIBL_STATUS_SOFT_BASE + 1 + (int)n)),
                        "platform backend status");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bytes_per_pixel),
        cmocka_unit_test(test_8888_known_values),
        cmocka_unit_test(test_565_known_values),
        cmocka_unit_test(test_accum32_known_values),
        cmocka_unit_test(test_accum32_saturates),
        cmocka_unit_test(test_linear8_exact_rounding),
        cmocka_unit_test(test_srgb_table_against_exact_curve),
        cmocka_unit_test(test_rgb565_rounding_and_srgb_bound),
        cmocka_unit_test(test_exposure),
        cmocka_unit_test(test_dither_pattern),
        cmocka_unit_test(test_dither_tiles_across_spans),
        cmocka_unit_test(test_resolve_equals_direct_write),
        cmocka_unit_test(test_resolve_in_place),
        cmocka_unit_test(test_stride_and_unaligned_pixels),
        cmocka_unit_test(test_clear),
        cmocka_unit_test(test_errors_write_nothing),
        cmocka_unit_test(test_golden_gradient),
        cmocka_unit_test(test_status_range_and_names),
        cmocka_unit_test(test_status_list),
    };
    return cmocka_run_group_tests_name("soft", tests, NULL, NULL);
}
