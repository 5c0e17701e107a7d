/*
 * srgbe_test.c - qibl/srgbe.h against the double reference written from Granier et al.'s formulas
 * (tools/ref/srgbe_ref.c: frexp exponent, nearest odd multiple of 2^e/510 picked in double).
 *
 * Every edge case of the header has its own test; the error bound is checked exactly (in units of
 * 2^e/510, exact in double for binary32 and int32 inputs) over every binary32 exponent times a dense
 * mantissa sweep times signs times the position of the largest channel, and over 10^7 random
 * triples; every (channel byte, exponent byte) pair is decoded in each position and 2^22 random
 * codes are decoded whole (the full 2^32 sweep is `make check-exhaustive`). Bulk and one-pixel
 * calls are compared byte for byte at every output alignment. Built twice (native and portable).
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "qibl/srgbe.h"
#include "ref/srgbe_ref.h"
#include "testutil.h"

#define N_RANDOM 10000000
#define N_CODES (1u << 22)

static uint32_t bits_of(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

static float float_of(uint32_t u)
{
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

static uint32_t code_u32(const uint8_t c[4]) /* as written: R G B E, for messages and compares */
{
    return (uint32_t)c[0] << 24 | (uint32_t)c[1] << 16 | (uint32_t)c[2] << 8 | c[3];
}

static qibl_status_t status_of_ref(int r)
{
    switch (r) {
    case QTOOL_REF_SRGBE_NAN: return QIBL_E_SRGBE_NAN;
    case QTOOL_REF_SRGBE_INF: return QIBL_E_SRGBE_INF;
    case QTOOL_REF_SRGBE_OVERFLOW: return QIBL_E_SRGBE_OVERFLOW;
    default: return QIBL_OK;
    }
}

/* ---- the central check: one binary32 pixel against the reference and the bound --------------- */

typedef struct {
    double max_err;    /* max |c - exact decode| in units of 2^e/510 (in-range channels) */
    double max_err_nz; /* the same over channels c != 0 (zero channels sit exactly on the bound) */
    double max_rt;     /* max |c - decode_f32| in the same units */
    double max_rel;    /* max relative error of the largest channel (exact decode) */
    long pixels, in_range;
} stats;

/* Encodes in with the core, checks code and status against the reference, and for in-range finite
 * channels checks |c - decode(code)| <= 2^e/510 exactly and through the binary32 decoder. */
static void check_f32(const uint32_t in[3], stats *st)
{
    uint8_t code[4 + 4], ref[4];
    memset(code, 0xA5, sizeof code);
    double c[3] = {float_of(in[0]), float_of(in[1]), float_of(in[2])};
    int rs = qtool_ref_srgbe_encode(c, ref);
    qibl_status_t s = qibl_srgbe_encode_f32(in, code);
    if (memcmp(code, ref, 4) != 0 || s != status_of_ref(rs))
        fail_msg("encode %08x %08x %08x: core %08x status %d, reference %08x status %d", in[0], in[1], in[2],
                 code_u32(code), s, code_u32(ref), status_of_ref(rs));
    assert_true(tu_guard_intact(code + 4, 4));
    st->pixels++;
    double mx = fmax(fabs(c[0]), fmax(fabs(c[1]), fabs(c[2])));
    if (s == QIBL_E_SRGBE_NAN || mx < 0x1p-128)
        return; /* NaN pixels and flushed pixels have no bound */
    st->in_range++;
    uint32_t dec[3];
    qibl_status_t ds = qibl_srgbe_decode_f32(code, dec);
    assert_true(ds == QIBL_OK || ds == QIBL_E_SRGBE_DECODE_SAT);
    double step = ldexp(1.0, (int)code[3] - 126) / 510.0; /* the bound 2^e/510 */
    for (int i = 0; i < 3; ++i) {
        if (isinf(c[i]))
            continue;
        double e = qtool_ref_srgbe_err_in_bounds(c[i], code[i], code[3]);
        if (e > 1.0)
            fail_msg("bound: channel %d of %08x %08x %08x: %.9g half-steps (code %08x)", i, in[0], in[1], in[2], e,
                     code_u32(code));
        if (e > st->max_err)
            st->max_err = e;
        if (c[i] != 0.0 && e > st->max_err_nz)
            st->max_err_nz = e;
        /* through the binary32 decoder: plus its own rounding, <= 2^(e-25) */
        double rt = fabs(c[i] - (double)float_of(dec[i])) / step;
        assert_true(rt <= 1.0 + 510.0 * 0x1p-25);
        if (rt > st->max_rt)
            st->max_rt = rt;
        if (fabs(c[i]) == mx && s == QIBL_OK) {
            double rel = fabs(c[i] - qtool_ref_srgbe_channel(code[i], code[3])) / mx;
            if (rel > st->max_rel)
                st->max_rel = rel;
        }
    }
}

static void report(const char *what, const stats *st)
{
    printf("srgbe: %s: %ld pixels (%ld in range): max |c - decode(encode(c))| = %.9f x 2^e/510 "
           "(%.9f over c != 0; via the binary32 decoder %.9f), max rel. err. of the largest channel %.4f%%\n",
           what, st->pixels, st->in_range, st->max_err, st->max_err_nz, st->max_rt, 100.0 * st->max_rel);
}

static void enc_f(float r, float g, float b, uint8_t code[4], qibl_status_t want)
{
    uint32_t in[3] = {bits_of(r), bits_of(g), bits_of(b)};
    assert_int_equal(qibl_srgbe_encode_f32(in, code), want);
}

/* ---- edge cases, one test each -------------------------------------------------------------- */

static void test_zero_and_negative_zero(void **state)
{
    (void)state;
    uint8_t c[4];
    enc_f(0.0f, 0.0f, 0.0f, c, QIBL_OK);
    assert_int_equal(code_u32(c), 0x80808000u); /* QTOOL_SRGBE_ZERO */
    enc_f(-0.0f, -0.0f, -0.0f, c, QIBL_OK);
    assert_int_equal(code_u32(c), 0x7F7F7F00u);
    enc_f(0.0f, -0.0f, 0.0f, c, QIBL_OK);
    assert_int_equal(code_u32(c), 0x807F8000u);
    /* a zero channel inside a non-zero pixel: 128 / 127 by sign, decoding to +-2^e/510 */
    enc_f(1.0f, 0.0f, -0.0f, c, QIBL_OK);
    assert_int_equal(c[3], 128); /* e = floor(log2 1) + 2 = 2 */
    assert_int_equal(c[1], 128);
    assert_int_equal(c[2], 127);
    uint32_t d[3];
    assert_int_equal(qibl_srgbe_decode_f32(c, d), QIBL_OK);
    assert_true(float_of(d[1]) == (float)(4.0 / 510.0));
    assert_true(float_of(d[2]) == (float)(-4.0 / 510.0));
    /* the zero code decodes to the smallest magnitude, 2^-127/255, a binary32 subnormal */
    const uint8_t zero[4] = {128, 128, 128, 0}, nzero[4] = {127, 127, 127, 0};
    assert_int_equal(qibl_srgbe_decode_f32(zero, d), QIBL_OK);
    for (int i = 0; i < 3; ++i)
        assert_true(d[i] == 0x00004040u && float_of(d[i]) == (float)ldexp(1.0 / 255.0, -127));
    assert_int_equal(qibl_srgbe_decode_f32(nzero, d), QIBL_OK);
    for (int i = 0; i < 3; ++i)
        assert_true(d[i] == 0x80004040u);
    int32_t q[3];
    assert_int_equal(qibl_srgbe_decode_q16(zero, q), QIBL_OK);
    assert_true(q[0] == 0 && q[1] == 0 && q[2] == 0);
    assert_int_equal(qibl_srgbe_decode_q16(nzero, q), QIBL_OK);
    assert_true(q[0] == 0 && q[1] == 0 && q[2] == 0);
    /* integers have no -0: the zero pixel is QTOOL_SRGBE_ZERO */
    const int32_t iz[3] = {0, 0, 0};
    assert_int_equal(qibl_srgbe_encode_q16(iz, c), QIBL_OK);
    assert_int_equal(code_u32(c), 0x80808000u);
}

static void test_denormals(void **state)
{
    (void)state;
    uint8_t c[4];
    /* 2^-128 = subnormal 0x00200000: the smallest in-range maximum, e = -126, E = 0 */
    uint32_t in[3] = {0x00200000u, 0, 0x80000000u};
    assert_int_equal(qibl_srgbe_encode_f32(in, c), QIBL_OK);
    assert_int_equal(code_u32(c), 0xBF807F00u); /* 128 + floor(255/4) = 191 */
    /* [2^-127, 2^-126): E = 1 */
    in[0] = 0x00400000u;
    assert_int_equal(qibl_srgbe_encode_f32(in, c), QIBL_OK);
    assert_int_equal(code_u32(c), 0xBF807F01u);
    in[0] = 0x007FFFFFu; /* largest subnormal: rounds up to 2^-126, X = 255 */
    assert_int_equal(qibl_srgbe_encode_f32(in, c), QIBL_OK);
    assert_int_equal(code_u32(c), 0xFF807F01u);
    /* subnormals as smaller channels of a normal pixel, and every subnormal exponent as maximum */
    stats st = {0};
    tu_rng r = {11};
    for (int k = 0; k < 23; ++k)
        for (int j = 0; j < 2000; ++j) {
            uint32_t m = (uint32_t)1 << k | (tu_u32(&r) & (((uint32_t)1 << k) - 1u));
            uint32_t px[3] = {m | (tu_u32(&r) & 0x80000000u), tu_u32(&r) & 0x801FFFFFu, tu_u32(&r) & 0x807FFFFFu};
            check_f32(px, &st);
            uint32_t px2[3] = {0x00800000u | (tu_u32(&r) & 0x807FFFFFu), m, tu_u32(&r) & 0x807FFFFFu};
            check_f32(px2, &st);
        }
    report("subnormals", &st);
    assert_true(st.max_err <= 1.0);
}

static void test_below_range_flushes_to_zero(void **state)
{
    (void)state;
    uint8_t c[4];
    /* just below 2^-128: flushed, channel signs kept */
    uint32_t in[3] = {0x001FFFFFu, 0x80000001u, 0x00000001u};
    assert_int_equal(qibl_srgbe_encode_f32(in, c), QIBL_OK);
    assert_int_equal(code_u32(c), 0x807F8000u);
    uint32_t in2[3] = {0x80000001u, 0x80100000u, 0x801FFFFFu};
    assert_int_equal(qibl_srgbe_encode_f32(in2, c), QIBL_OK);
    assert_int_equal(code_u32(c), 0x7F7F7F00u);
    /* int32 * 2^-f: 2^-128 is in range, 2^-129 is not */
    const int32_t one[3] = {1, -1, 0};
    assert_int_equal(qibl_srgbe_encode_s32(one, 128, c), QIBL_OK);
    assert_int_equal(code_u32(c), 0xBF408000u);
    assert_int_equal(qibl_srgbe_encode_s32(one, 129, c), QIBL_OK);
    assert_int_equal(code_u32(c), 0x807F8000u);
    const int32_t big[3] = {INT32_MIN, INT32_MAX, 7};
    assert_int_equal(qibl_srgbe_encode_s32(big, 159, c), QIBL_OK); /* 2^31 2^-159 = 2^-128 */
    assert_int_equal(c[3], 0);
    assert_int_equal(qibl_srgbe_encode_s32(big, 160, c), QIBL_OK);
    assert_int_equal(code_u32(c), 0x7F808000u);
    assert_int_equal(qibl_srgbe_encode_s32(big, INT_MAX, c), QIBL_OK); /* no overflow inside */
    assert_int_equal(code_u32(c), 0x7F808000u);
}

static void test_above_range_saturates(void **state)
{
    (void)state;
    uint8_t c[4];
    /* every finite binary32 is in range: FLT_MAX has e = 129 and rounds to X = 255 (2^128) */
    enc_f(FLT_MAX, -FLT_MAX, 1.0f, c, QIBL_OK);
    assert_int_equal(code_u32(c), 0xFF0080FFu);
    /* ... whose binary32 decode saturates to +-FLT_MAX, and is reported */
    uint32_t d[3] = {0, 0, 0};
    assert_int_equal(qibl_srgbe_decode_f32(c, d), QIBL_E_SRGBE_DECODE_SAT);
    assert_true(d[0] == 0x7F7FFFFFu && d[1] == 0xFF7FFFFFu && d[2] == bits_of((float)ldexp(1.0 / 510.0, 129)));
    /* int32 * 2^-f: 2^128 (e = 130) is above range: E = 255, largest codes, reported */
    const int32_t v[3] = {1, -1, 0};
    assert_int_equal(qibl_srgbe_encode_s32(v, -127, c), QIBL_OK); /* 2^127: e = 129, fine */
    assert_int_equal(code_u32(c), 0xBF4080FFu);
    assert_int_equal(qibl_srgbe_encode_s32(v, -128, c), QIBL_E_SRGBE_OVERFLOW);
    assert_int_equal(code_u32(c), 0xFF0080FFu);
    /* a smaller channel that still fits at e = 129 keeps its nearest code */
    const int32_t w[3] = {1 << 30, -(1 << 20), 1 << 10};
    assert_int_equal(qibl_srgbe_encode_s32(w, -120, c), QIBL_E_SRGBE_OVERFLOW); /* 2^150 */
    uint8_t ref[4];
    double cw[3] = {ldexp(1.0, 150), -ldexp(1.0, 140), ldexp(1.0, 130)};
    assert_int_equal(qtool_ref_srgbe_encode(cw, ref), QTOOL_REF_SRGBE_OVERFLOW);
    assert_memory_equal(c, ref, 4);
    assert_int_equal(c[0], 255);
    assert_int_equal(c[2], 255); /* 2^130 > 2^128 too */
    assert_int_equal(c[1], 0);
    const int32_t x[3] = {1 << 30, 1 << 20, 1};
    assert_int_equal(qibl_srgbe_encode_s32(x, -100, c), QIBL_E_SRGBE_OVERFLOW); /* 2^130, 2^120, 2^100 */
    double cx[3] = {ldexp(1.0, 130), ldexp(1.0, 120), ldexp(1.0, 100)};
    assert_int_equal(qtool_ref_srgbe_encode(cx, ref), QTOOL_REF_SRGBE_OVERFLOW);
    assert_memory_equal(c, ref, 4);
    assert_int_equal(c[1], 128 + (int)floor(255.0 * 0x1p-9)); /* 2^120 at e = 129: not saturated */
    assert_int_equal(qibl_srgbe_encode_s32(x, INT_MIN, c), QIBL_E_SRGBE_OVERFLOW); /* no overflow inside */
    assert_int_equal(code_u32(c), 0xFFFFFFFFu);
}

static void test_infinities_saturate(void **state)
{
    (void)state;
    uint8_t c[4];
    enc_f(INFINITY, 1.0f, -2.0f, c, QIBL_E_SRGBE_INF);
    assert_int_equal(code_u32(c), 0xFF807FFFu);
    enc_f(-INFINITY, INFINITY, -INFINITY, c, QIBL_E_SRGBE_INF);
    assert_int_equal(code_u32(c), 0x00FF00FFu);
    /* a finite channel next to an infinity is rounded at e = 129 */
    enc_f(FLT_MAX, -INFINITY, 0x1p126f, c, QIBL_E_SRGBE_INF);
    assert_int_equal(code_u32(c), 0xFF009FFFu); /* 2^126 at e = 129: 128 + floor(255/8) = 159 */
    /* bulk reports it too */
    uint32_t px[6] = {bits_of(1.0f), 0, 0, bits_of(INFINITY), 0, 0};
    uint8_t cc[8];
    assert_int_equal(qibl_srgbe_encode_f32_n(px, 2, cc), QIBL_E_SRGBE_INF);
}

static void test_nan_in_any_channel(void **state)
{
    (void)state;
    const uint32_t nans[] = {0x7FC00000u, 0xFFC00000u, 0x7F800001u, 0xFFFFFFFFu, 0x7FBFFFFFu};
    for (size_t k = 0; k < sizeof nans / sizeof nans[0]; ++k)
        for (int pos = 0; pos < 3; ++pos) {
            uint32_t in[3] = {bits_of(-3.0f), bits_of(INFINITY), bits_of(1e-3f)};
            in[pos] = nans[k];
            uint8_t c[4] = {1, 2, 3, 4};
            assert_int_equal(qibl_srgbe_encode_f32(in, c), QIBL_E_SRGBE_NAN); /* over Inf, too */
            assert_int_equal(code_u32(c), 0x80808000u);                     /* the zero code */
        }
    uint32_t all[3] = {0x7FC00000u, 0xFFC00000u, 0x7FC00001u};
    uint8_t c[4];
    assert_int_equal(qibl_srgbe_encode_f32(all, c), QIBL_E_SRGBE_NAN);
    assert_int_equal(code_u32(c), 0x80808000u);
    /* bulk: NaN outranks Inf, the other pixels are written normally */
    uint32_t px[9] = {bits_of(INFINITY), 0, 0, 0x7FC00000u, 0, 0, bits_of(1.0f), bits_of(-1.0f), 0};
    uint8_t cc[12], one[4];
    assert_int_equal(qibl_srgbe_encode_f32_n(px, 3, cc), QIBL_E_SRGBE_NAN);
    assert_int_equal(code_u32(cc + 4), 0x80808000u);
    assert_int_equal(qibl_srgbe_encode_f32(px + 6, one), QIBL_OK);
    assert_memory_equal(cc + 8, one, 4);
}

static void test_mixed_signs(void **state)
{
    (void)state;
    uint8_t c[4];
    enc_f(3.0f, -1.5f, 0.25f, c, QIBL_OK);
    /* max 3: e = floor(log2 3) + 2 = 3; X = round(255 (c/8 + 1/2)) */
    assert_int_equal(c[3], 129);
    assert_int_equal(c[0], 128 + (int)floor(255.0 * 3.0 / 8.0));
    assert_int_equal(c[1], 127 - (int)floor(255.0 * 1.5 / 8.0));
    assert_int_equal(c[2], 128 + (int)floor(255.0 * 0.25 / 8.0));
    uint32_t d[3];
    assert_int_equal(qibl_srgbe_decode_f32(c, d), QIBL_OK);
    assert_true(float_of(d[0]) > 0 && float_of(d[1]) < 0 && float_of(d[2]) > 0);
    stats st = {0};
    tu_rng r = {12};
    for (int k = 0; k < 200000; ++k) {
        float a = (float)(tu_unit(&r) * 10.0), b = (float)(tu_unit(&r) * 10.0), cc = (float)(tu_unit(&r) * 10.0);
        uint32_t in[3] = {bits_of(a), bits_of(-b), bits_of((k & 1) ? cc : -cc)};
        check_f32(in, &st);
    }
    assert_true(st.max_err <= 1.0);
}

static void test_all_channels_equal(void **state)
{
    (void)state;
    stats st = {0};
    tu_rng r = {13};
    for (int k = 0; k < 100000; ++k) {
        uint32_t v = tu_u32(&r) % 0x7F800000u;
        uint32_t in[3] = {v, v, v};
        uint8_t c[4];
        check_f32(in, &st);
        assert_int_equal(qibl_srgbe_encode_f32(in, c), QIBL_OK);
        assert_true(c[0] == c[1] && c[1] == c[2]);
        if (v >= 0x00200000u)
            assert_true(c[0] >= 191); /* every channel is the largest one */
        uint32_t n[3] = {v | 0x80000000u, v | 0x80000000u, v | 0x80000000u};
        uint8_t cn[4];
        assert_int_equal(qibl_srgbe_encode_f32(n, cn), QIBL_OK);
        assert_true(cn[0] == 255 - c[0] && cn[1] == cn[0] && cn[2] == cn[0] && cn[3] == c[3]);
    }
}

static void test_power_of_two_channels(void **state)
{
    (void)state;
    stats st = {0};
    for (int k = -128; k <= 127; ++k) {
        float p = (float)ldexp(1.0, k);
        uint8_t c[4];
        enc_f(p, 0.0f, -p, c, QIBL_OK);
        /* 2^k is the bottom of its exponent's range: e = k + 2, y = 255/4 -> X = 191 / 64 */
        assert_int_equal(c[3], k + 2 + 126);
        assert_int_equal(c[0], 191);
        assert_int_equal(c[2], 64);
        uint32_t in[3] = {bits_of(p), bits_of(p * 0.5f), bits_of(-p * 0.25f)};
        check_f32(in, &st);
        /* just below 2^k: the previous exponent, rounding up to X = 255 (exactly 2^(k)) */
        if (k > -128) {
            uint32_t below[3] = {bits_of(p) - 1u, 0, 0};
            check_f32(below, &st);
            uint8_t cb[4];
            assert_int_equal(qibl_srgbe_encode_f32(below, cb), QIBL_OK);
            assert_int_equal(cb[3], k + 1 + 126);
            assert_int_equal(cb[0], 255);
            uint32_t d[3];
            assert_int_equal(qibl_srgbe_decode_f32(cb, d), QIBL_OK);
            assert_true(float_of(d[0]) == p); /* X = 255 decodes to exactly 2^(e-1) */
        }
    }
    assert_true(st.max_err <= 1.0);
}

static void test_largest_channel_negative(void **state)
{
    (void)state;
    uint8_t c[4];
    enc_f(1.0f, -8.0f, 2.0f, c, QIBL_OK);
    assert_int_equal(c[3], 126 + 5);
    assert_int_equal(c[1], 64); /* 127 - floor(255/4) */
    assert_true(c[1] <= 64);
    stats st = {0};
    tu_rng r = {14};
    for (int k = 0; k < 200000; ++k) {
        uint32_t big = (tu_u32(&r) % 0x7F000000u) + 0x00800000u;
        uint32_t in[3] = {big | 0x80000000u, tu_u32(&r) % big, (tu_u32(&r) % big) | 0x80000000u};
        int rot = k % 3; /* the negative maximum in every position */
        uint32_t px[3];
        for (int i = 0; i < 3; ++i)
            px[(rot + i) % 3] = in[i]; /* the maximum lands at px[rot] */
        check_f32(px, &st);
        assert_int_equal(qibl_srgbe_encode_f32(px, c), QIBL_OK);
        assert_true(c[rot] <= 64);
    }
    assert_true(st.max_err <= 1.0);
}

static void test_null_pointers_write_nothing(void **state)
{
    (void)state;
    uint32_t f[3] = {0, 0, 0};
    int32_t s[3] = {0, 0, 0};
    uint8_t c[8];
    tu_fill_guard(c, sizeof c);
    assert_int_equal(qibl_srgbe_encode_f32(NULL, c), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_srgbe_encode_s32(NULL, 0, c), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_srgbe_encode_q16(NULL, c), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_srgbe_encode_f32_n(NULL, 1, c), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_srgbe_encode_s32_n(NULL, 1, 0, c), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_srgbe_encode_q16_n(NULL, 1, c), QIBL_E_NULL_POINTER);
    assert_true(tu_guard_intact(c, sizeof c));
    assert_int_equal(qibl_srgbe_encode_f32(f, NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_srgbe_encode_s32(s, 0, NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_srgbe_encode_q16(s, NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_srgbe_encode_f32_n(f, 0, NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_srgbe_encode_s32_n(s, 0, 0, NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_srgbe_encode_q16_n(s, 0, NULL), QIBL_E_NULL_POINTER);
    uint32_t fo[4];
    int32_t so[4];
    tu_fill_guard(fo, sizeof fo);
    tu_fill_guard(so, sizeof so);
    const uint8_t code[4] = {200, 100, 50, 130};
    assert_int_equal(qibl_srgbe_decode_f32(NULL, fo), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_srgbe_decode_s32(NULL, 16, so), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_srgbe_decode_q16(NULL, so), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_srgbe_decode_f32_n(NULL, 1, fo), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_srgbe_decode_s32_n(NULL, 1, 16, so), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_srgbe_decode_q16_n(NULL, 1, so), QIBL_E_NULL_POINTER);
    assert_true(tu_guard_intact(fo, sizeof fo) && tu_guard_intact(so, sizeof so));
    assert_int_equal(qibl_srgbe_decode_f32(code, NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_srgbe_decode_s32(code, 16, NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_srgbe_decode_q16(code, NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_srgbe_decode_f32_n(code, 0, NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_srgbe_decode_s32_n(code, 0, 16, NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_srgbe_decode_q16_n(code, 0, NULL), QIBL_E_NULL_POINTER);
    /* n = 0 with valid pointers: OK, nothing written */
    assert_int_equal(qibl_srgbe_encode_f32_n(f, 0, c), QIBL_OK);
    assert_int_equal(qibl_srgbe_encode_s32_n(s, 0, 3, c), QIBL_OK);
    assert_int_equal(qibl_srgbe_decode_f32_n(code, 0, fo), QIBL_OK);
    assert_int_equal(qibl_srgbe_decode_s32_n(code, 0, 3, so), QIBL_OK);
    assert_true(tu_guard_intact(c, sizeof c) && tu_guard_intact(fo, sizeof fo) && tu_guard_intact(so, sizeof so));
}

/* ---- the bound, exhaustively over exponents ------------------------------------------------- */

/* every binary32 exponent field (subnormals included) as the largest channel, a dense mantissa
 * sweep (4096 evenly spaced, the two sides of every rounding boundary of the largest channel, and
 * the ends), both signs, the largest channel in each position, the others random below it */
static void test_bound_all_exponents_dense_mantissas(void **state)
{
    (void)state;
    stats st = {0};
    tu_rng r = {15};
    uint32_t mant[4096 + 2 * 128 + 4];
    for (uint32_t be = 0; be <= 254; ++be) {
        int nm = 0;
        for (uint32_t k = 0; k < 4096; ++k)
            mant[nm++] = (k << 11) | (tu_u32(&r) & 0x7FFu);
        /* the largest channel's code changes where 255 sig / 2^25 crosses an integer j */
        for (uint32_t j = 64; j <= 127; ++j) {
            uint32_t sig = (uint32_t)(((uint64_t)j << 25) / 255u) + 1u; /* first sig with floor >= j */
            mant[nm++] = (sig - 1u) & 0x7FFFFFu;
            mant[nm++] = sig & 0x7FFFFFu;
        }
        mant[nm++] = 0;
        mant[nm++] = 1;
        mant[nm++] = 0x7FFFFFu;
        mant[nm++] = 0x400000u;
        for (int i = 0; i < nm; ++i)
            for (uint32_t sign = 0; sign < 2; ++sign)
                for (int pos = 0; pos < 3; ++pos) {
                    uint32_t big = sign << 31 | be << 23 | mant[i];
                    uint32_t absb = big & 0x7FFFFFFFu;
                    uint32_t px[3];
                    for (int k = 0; k < 3; ++k) {
                        /* others: random magnitudes below, with random exponent gaps */
                        uint32_t lo = absb ? tu_u32(&r) % (absb + 1u) : 0u;
                        if (tu_next(&r) & 1u)
                            lo >>= tu_next(&r) % 31u;
                        px[k] = lo | (tu_u32(&r) & 0x80000000u);
                    }
                    px[pos] = big;
                    check_f32(px, &st);
                }
    }
    report("all exponents x dense mantissas x signs x positions", &st);
    assert_true(st.max_err <= 1.0);
    assert_true(st.max_rel <= 4.0 / 510.0);
}

/* a random finite binary32 of the chosen kind */
static uint32_t rnd_f32(tu_rng *r, int kind, double scale)
{
    switch (kind) {
    case 0: { /* any finite bit pattern */
        uint32_t u;
        do
            u = tu_u32(r);
        while ((u & 0x7F800000u) == 0x7F800000u);
        return u;
    }
    case 1: /* HDR-like: scale * [-1, 1] */
        return bits_of((float)(scale * (2.0 * tu_unit(r) - 1.0)));
    case 2: { /* specials mixed in */
        const uint32_t sp[] = {0, 0x80000000u, 1, 0x80000001u, 0x00200000u, 0x007FFFFFu, 0x00800000u,
                               0x7F7FFFFFu, 0xFF7FFFFFu, 0x3F800000u, 0xBF800000u, 0x3F7FFFFFu};
        return sp[tu_next(r) % (sizeof sp / sizeof sp[0])];
    }
    default: /* log-uniform magnitude over +-2^40, random sign */
        return bits_of((float)(ldexp(1.0 + tu_unit(r), (int)(tu_next(r) % 81u) - 40) * ((tu_next(r) & 1) ? -1 : 1)));
    }
}

static void test_bound_ten_million_random_triples(void **state)
{
    (void)state;
    stats st = {0};
    tu_rng r = {16};
    for (long k = 0; k < N_RANDOM; ++k) {
        double scale = ldexp(1.0, (int)(tu_next(&r) % 61u) - 30);
        uint32_t px[3];
        int mode = (int)(tu_next(&r) % 8u);
        for (int i = 0; i < 3; ++i) {
            int kind = mode < 3 ? 1 : mode < 5 ? 3 : mode < 7 ? 0 : (int)(tu_next(&r) % 4u);
            px[i] = rnd_f32(&r, kind, scale);
        }
        check_f32(px, &st);
    }
    report("10^7 random triples", &st);
    assert_true(st.max_err <= 1.0);
    assert_true(st.max_rel <= 4.0 / 510.0);
}

/* ---- int32 * 2^-frac_bits and Q16.16 -------------------------------------------------------- */

static void check_s32(const int32_t v[3], int f, double *max_err)
{
    uint8_t code[4], ref[4];
    double c[3] = {ldexp(v[0], -f), ldexp(v[1], -f), ldexp(v[2], -f)};
    int rs = qtool_ref_srgbe_encode(c, ref);
    qibl_status_t s = qibl_srgbe_encode_s32(v, f, code);
    if (memcmp(code, ref, 4) != 0 || s != status_of_ref(rs))
        fail_msg("encode_s32 %d %d %d f=%d: core %08x status %d, reference %08x", v[0], v[1], v[2], f, code_u32(code),
                 s, code_u32(ref));
    if (f == 16) {
        uint8_t cq[4];
        assert_int_equal(qibl_srgbe_encode_q16(v, cq), s);
        assert_memory_equal(cq, code, 4);
    }
    double mx = fmax(fabs(c[0]), fmax(fabs(c[1]), fabs(c[2])));
    if (s == QIBL_OK && mx >= 0x1p-128)
        for (int i = 0; i < 3; ++i) {
            double e = qtool_ref_srgbe_err_in_bounds(c[i], code[i], code[3]);
            assert_true(e <= 1.0);
            if (e > *max_err)
                *max_err = e;
        }
}

static void test_encode_int32_any_frac_bits_and_q16(void **state)
{
    (void)state;
    double max_err = 0.0;
    const int32_t edge[] = {0, 1, -1, 2, 3, 255, 256, 65535, 65536, -65536, INT32_MAX, INT32_MIN, INT32_MIN + 1,
                            0x40000000, -0x40000000, 0x3FFFFFFF, 12345678};
    const size_t ne = sizeof edge / sizeof edge[0];
    for (int f = -300; f <= 300; f += (f > -40 && f < 60) ? 1 : 7)
        for (size_t a = 0; a < ne; ++a)
            for (size_t b = 0; b < ne; ++b) {
                int32_t v[3] = {edge[a], edge[b], edge[(a + b) % ne]};
                check_s32(v, f, &max_err);
            }
    tu_rng r = {17};
    for (int k = 0; k < 1000000; ++k) {
        int32_t v[3];
        for (int i = 0; i < 3; ++i)
            v[i] = qibl_asr_s32(tu_s32(&r), (unsigned)(tu_next(&r) % 32u));
        int f = (k & 3) == 0 ? 16 : (int)(tu_next(&r) % 601u) - 300;
        check_s32(v, f, &max_err);
    }
    printf("srgbe: int32 * 2^-f, f in -300..300 and Q16.16: max |c - decode(encode(c))| = %.9f x 2^e/510\n",
           max_err);
    assert_true(max_err <= 1.0);
    /* Q16.16 is always in range: e = msb + 2 - 16 in -14..17 */
    uint8_t c[4];
    const int32_t lsb[3] = {1, 0, 0}, top[3] = {INT32_MIN, 0, 0};
    assert_int_equal(qibl_srgbe_encode_q16(lsb, c), QIBL_OK);
    assert_int_equal(c[3], 126 - 14);
    assert_int_equal(qibl_srgbe_encode_q16(top, c), QIBL_OK);
    assert_int_equal(c[3], 126 + 17);
    assert_int_equal(c[0], 64);
}

/* ---- decode --------------------------------------------------------------------------------- */

static const int frac_list[] = {-300, -140, -40, -8, -1, 0, 1, 8, 15, 16, 24, 30, 31, 32, 40, 60, 120, 150, 300};

static void test_decode_every_channel_byte_and_exponent(void **state)
{
    (void)state;
    tu_rng r = {18};
    long nsat = 0;
    for (int pos = 0; pos < 3; ++pos)
        for (unsigned E = 0; E < 256; ++E)
            for (unsigned X = 0; X < 256; ++X) {
                uint8_t code[4] = {(uint8_t)tu_u32(&r), (uint8_t)tu_u32(&r), (uint8_t)tu_u32(&r), (uint8_t)E};
                code[pos] = (uint8_t)X;
                uint32_t d[3 + 1];
                d[3] = 0xDEADBEEFu;
                qibl_status_t s = qibl_srgbe_decode_f32(code, d);
                assert_int_equal(d[3], 0xDEADBEEFu);
                int sat = 0;
                for (int i = 0; i < 3; ++i) {
                    uint32_t want = qtool_ref_srgbe_channel_f32(code[i], E, &sat);
                    if (d[i] != want)
                        fail_msg("decode_f32 %08x channel %d: %08x, reference %08x", code_u32(code), i, d[i], want);
                }
                assert_int_equal(s, sat ? QIBL_E_SRGBE_DECODE_SAT : QIBL_OK);
                nsat += sat;
                for (size_t k = 0; k < sizeof frac_list / sizeof frac_list[0]; ++k) {
                    int f = frac_list[k], ssat = 0;
                    int32_t q[3 + 1];
                    q[3] = 0x5EED;
                    qibl_status_t qs = qibl_srgbe_decode_s32(code, f, q);
                    assert_int_equal(q[3], 0x5EED);
                    for (int i = 0; i < 3; ++i) {
                        int32_t want = qtool_ref_srgbe_channel_s32(code[i], E, f, &ssat);
                        if (q[i] != want)
                            fail_msg("decode_s32 %08x f=%d channel %d: %d, reference %d", code_u32(code), f, i, q[i],
                                     want);
                    }
                    assert_int_equal(qs, ssat ? QIBL_E_SRGBE_DECODE_SAT : QIBL_OK);
                    if (f == 16) {
                        int32_t q16[3];
                        assert_int_equal(qibl_srgbe_decode_q16(code, q16), qs);
                        assert_memory_equal(q16, q, sizeof q16);
                    }
                }
            }
    printf("srgbe: decode: every (X, E) in every channel position matches the double reference (binary32 and "
           "int32 at %zu fraction widths); %ld codes saturated binary32\n",
           sizeof frac_list / sizeof frac_list[0], nsat);
}

static void test_decode_saturation_and_ties(void **state)
{
    (void)state;
    int32_t q[3];
    /* X = 255 / 0 are exactly +-2^(E-127): ties at +-1/2 LSB go toward +infinity */
    uint8_t c[4] = {255, 0, 128, 126 - 16}; /* 2^(e-1) 2^16 = 1/2 */
    assert_int_equal(qibl_srgbe_decode_q16(c, q), QIBL_OK);
    assert_int_equal(q[0], 1);  /* +1/2 -> 1 */
    assert_int_equal(q[1], 0);  /* -1/2 -> 0 */
    assert_int_equal(q[2], 0);
    c[3] = 126 - 16 + 1; /* +-1 exactly */
    assert_int_equal(qibl_srgbe_decode_q16(c, q), QIBL_OK);
    assert_true(q[0] == 1 && q[1] == -1 && q[2] == 0);
    /* INT32_MIN is reachable exactly, INT32_MAX saturates */
    c[3] = 126 + 32 - 16; /* 2^(e-1) 2^16 = 2^31 */
    assert_int_equal(qibl_srgbe_decode_q16(c, q), QIBL_E_SRGBE_DECODE_SAT);
    assert_true(q[0] == INT32_MAX && q[1] == INT32_MIN);
    const uint8_t neg_only[4] = {0, 128, 128, 126 + 32 - 16};
    assert_int_equal(qibl_srgbe_decode_q16(neg_only, q), QIBL_OK);
    assert_int_equal(q[0], INT32_MIN);
    /* Q16.16 saturates from E = 142 only */
    const uint8_t e141[4] = {254, 1, 128, 141}, e142[4] = {254, 128, 128, 142};
    assert_int_equal(qibl_srgbe_decode_q16(e141, q), QIBL_OK);
    assert_int_equal(qibl_srgbe_decode_q16(e142, q), QIBL_OK); /* 253/255 2^15 still fits */
    const uint8_t e142s[4] = {255, 128, 128, 142};
    assert_int_equal(qibl_srgbe_decode_q16(e142s, q), QIBL_E_SRGBE_DECODE_SAT);
    /* binary32: only E = 255 with X in {0, 255} saturates */
    uint32_t d[3];
    const uint8_t big[4] = {254, 1, 128, 255};
    assert_int_equal(qibl_srgbe_decode_f32(big, d), QIBL_OK);
    assert_true(float_of(d[0]) == (float)ldexp(253.0 / 255.0, 128));
    const uint8_t top[4] = {255, 0, 128, 255};
    assert_int_equal(qibl_srgbe_decode_f32(top, d), QIBL_E_SRGBE_DECODE_SAT);
    assert_true(d[0] == 0x7F7FFFFFu && d[1] == 0xFF7FFFFFu);
    /* bulk reports saturation anywhere in the array */
    uint8_t codes[8] = {200, 100, 50, 130, 255, 128, 128, 255};
    uint32_t out[6];
    assert_int_equal(qibl_srgbe_decode_f32_n(codes, 2, out), QIBL_E_SRGBE_DECODE_SAT);
    assert_int_equal(qibl_srgbe_decode_f32_n(codes, 1, out), QIBL_OK);
}

/* reference binary32 decode of every (X, E) pair, for the whole-code sweeps */
static uint32_t ref_table[256][256];
static unsigned char ref_sat[256][256];

static void fill_ref_table(void)
{
    static int done;
    if (done)
        return;
    for (unsigned E = 0; E < 256; ++E)
        for (unsigned X = 0; X < 256; ++X) {
            int sat = 0;
            ref_table[E][X] = qtool_ref_srgbe_channel_f32(X, E, &sat);
            ref_sat[E][X] = (unsigned char)sat;
        }
    done = 1;
}

/* canonical: the largest |2X - 255| is 129..253, so decoding lands inside [2^(e-2), 2^(e-1)) and
 * re-encoding must give the same code back */
static int canonical(const uint8_t c[4])
{
    int m = 0;
    for (int i = 0; i < 3; ++i) {
        int a = abs(2 * c[i] - 255);
        if (a > m)
            m = a;
    }
    return m >= 129 && m <= 253;
}

static void test_decode_random_codes_and_canonical_roundtrip(void **state)
{
    (void)state;
    fill_ref_table();
    tu_rng r = {19};
    long ncanon = 0;
    for (uint32_t k = 0; k < N_CODES; ++k) {
        uint32_t u = tu_u32(&r);
        uint8_t c[4] = {(uint8_t)(u >> 24), (uint8_t)(u >> 16), (uint8_t)(u >> 8), (uint8_t)u};
        uint32_t d[3];
        qibl_status_t s = qibl_srgbe_decode_f32(c, d);
        int sat = 0;
        for (int i = 0; i < 3; ++i) {
            assert_int_equal(d[i], ref_table[c[3]][c[i]]);
            sat |= ref_sat[c[3]][c[i]];
        }
        assert_int_equal(s, sat ? QIBL_E_SRGBE_DECODE_SAT : QIBL_OK);
        if (canonical(c)) {
            uint8_t back[4];
            assert_int_equal(qibl_srgbe_encode_f32(d, back), QIBL_OK);
            if (memcmp(back, c, 4) != 0)
                fail_msg("canonical code %08x decodes and re-encodes as %08x", code_u32(c), code_u32(back));
            ++ncanon;
        }
    }
    printf("srgbe: %u random codes decoded as the reference; %ld canonical ones re-encode to themselves\n", N_CODES,
           ncanon);
}

/* ---- symmetry, determinism, bulk ------------------------------------------------------------ */

static void test_sign_symmetry(void **state)
{
    (void)state;
    tu_rng r = {20};
    for (int k = 0; k < 1000000; ++k) {
        uint32_t in[3], neg[3];
        for (int i = 0; i < 3; ++i) {
            in[i] = rnd_f32(&r, (int)(tu_next(&r) % 4u), 100.0);
            neg[i] = in[i] ^ 0x80000000u;
        }
        uint8_t a[4], b[4];
        qibl_status_t sa = qibl_srgbe_encode_f32(in, a), sb = qibl_srgbe_encode_f32(neg, b);
        assert_int_equal(sa, sb);
        assert_true(b[0] == 255 - a[0] && b[1] == 255 - a[1] && b[2] == 255 - a[2] && b[3] == a[3]);
        /* and decoding a mirrored code negates exactly */
        uint32_t da[3], db[3];
        const qibl_status_t da_st = qibl_srgbe_decode_f32(a, da), db_st = qibl_srgbe_decode_f32(b, db);
        assert_int_equal(da_st, db_st); /* saturation is sign-symmetric too */
        for (int i = 0; i < 3; ++i)
            assert_int_equal(db[i], da[i] ^ 0x80000000u);
    }
}

/* The bulk binary32 encoder's kernel (QIBL_CONFIG_SIMD: SSE2/AVX2/NEON in the native and AVX2
 * flavours, enc_blk or the per-pixel loop in the portable one) against the one-pixel encoder, the
 * scalar reference: random arrays where every pixel is built from edge values (+-0 and ties, the
 * subnormal boundaries, +-Inf, NaNs of any payload and sign, FLT_MAX, powers of two, the largest
 * exponent field em = 6, 7, 254, 255 around the kernel's range) or random channels with exponent
 * fields close to one another (every shift d = 0..8), at every length and output alignment;
 * arrays longer than the encoder's prefetch distance (srgbe.c ENC_PF_PX, 1280 pixels), so its
 * blocks with and without the hint ahead both run. */
static void test_bulk_kernel_matches_one_pixel_on_edges(void **state)
{
    (void)state;
    enum { N = 1600 };
    static const uint32_t edge[] = {0u, 0x80000000u, 1u, 0x80000001u, 0x001FFFFFu, 0x00200000u, 0x003FFFFFu,
                                    0x00400000u, 0x007FFFFFu, 0x00800000u, 0x80800000u, 0x037FFFFFu, 0x03800000u,
                                    0x03FFFFFFu, 0x04000000u, 0x3F800000u, 0xBF800000u, 0x3F7FFFFFu, 0x7EFFFFFFu,
                                    0x7F000000u, 0x7F7FFFFFu, 0xFF7FFFFFu, 0x7F800000u, 0xFF800000u, 0x7F800001u,
                                    0x7FC00000u, 0xFFFFFFFFu, 0xFFC00001u};
    static uint32_t in[3 * N];
    static uint8_t bulk[4 * N + 8];
    uint8_t one[4];
    tu_rng r = {1616};
    for (int it = 0; it < 400; ++it) {
        const uint32_t base = tu_u32(&r) % 256u; /* exponent fields near base */
        for (int i = 0; i < 3 * N; ++i) {
            uint32_t kind = tu_u32(&r) % 8u, x = tu_u32(&r);
            if (kind == 0u)
                x = edge[tu_u32(&r) % (sizeof edge / sizeof edge[0])];
            else if (kind >= 4u) /* exponent field base - 8 .. base + 1, clamped to 0..255 */
            {
                int e = (int)base - 8 + (int)(tu_u32(&r) % 10u);
                e = e < 0 ? 0 : e > 255 ? 255 : e;
                x = (x & 0x807FFFFFu) | (uint32_t)e << 23;
            }
            in[i] = x;
        }
        const size_t n = N - tu_u32(&r) % 40u, off = tu_u32(&r) % 4u;
        tu_fill_guard(bulk, sizeof bulk);
        qibl_status_t st = qibl_srgbe_encode_f32_n(in, n, bulk + off), worst = QIBL_OK;
        for (size_t i = 0; i < n; ++i) {
            qibl_status_t s1 = qibl_srgbe_encode_f32(in + 3 * i, one);
            if (s1 == QIBL_E_SRGBE_NAN || (s1 == QIBL_E_SRGBE_INF && worst != QIBL_E_SRGBE_NAN))
                worst = s1;
            assert_memory_equal(bulk + off + 4 * i, one, 4);
        }
        assert_int_equal(st, worst);
        assert_true(tu_guard_intact(bulk, off) && tu_guard_intact(bulk + off + 4 * n, sizeof bulk - off - 4 * n));
    }
}

/* Every (X, E) pair through the bulk decoder against the one-pixel one (the other channels
 * random), all codes of one E in one call. */
static void test_bulk_decode_every_channel_code(void **state)
{
    (void)state;
    static uint8_t codes[4 * 256];
    static uint32_t bulk[3 * 256];
    uint32_t one[3];
    tu_rng r = {1617};
    for (uint32_t e = 0; e < 256u; ++e)
        for (int ch = 0; ch < 3; ++ch) {
            for (uint32_t x = 0; x < 256u; ++x) {
                for (int k = 0; k < 3; ++k)
                    codes[4 * x + (uint32_t)k] = (uint8_t)tu_u32(&r);
                codes[4 * x + (uint32_t)ch] = (uint8_t)x;
                codes[4 * x + 3] = (uint8_t)e;
            }
            qibl_status_t st = qibl_srgbe_decode_f32_n(codes, 256, bulk), worst = QIBL_OK;
            for (uint32_t x = 0; x < 256u; ++x) {
                if (qibl_srgbe_decode_f32(codes + 4 * x, one) != QIBL_OK)
                    worst = QIBL_E_SRGBE_DECODE_SAT;
                assert_memory_equal(bulk + 3 * x, one, sizeof one);
            }
            assert_int_equal(st, worst);
        }
}

static void test_bulk_matches_scalar_at_every_alignment(void **state)
{
    (void)state;
    enum { N = 1000 };
    static uint32_t fin[3 * N];
    static int32_t sin_[3 * N];
    static uint8_t codes[4 * N + 16], one[4];
    static uint32_t fout[3 * N + 4];
    static int32_t sout[3 * N + 4];
    tu_rng r = {21};
    for (int i = 0; i < 3 * N; ++i) {
        fin[i] = rnd_f32(&r, (int)(tu_next(&r) % 4u), 1000.0);
        sin_[i] = qibl_asr_s32(tu_s32(&r), (unsigned)(tu_next(&r) % 32u));
    }
    fin[3 * 17] = 0x7FC00000u;          /* a NaN pixel */
    fin[3 * 400 + 1] = 0xFF800000u;     /* an infinite one */
    const int fracs[] = {16, 0, -110, 150, 31};
    for (int off = 0; off < 4; ++off) {
        uint8_t *c = codes + off;
        /* binary32 */
        tu_fill_guard(codes, sizeof codes);
        qibl_status_t worst = QIBL_OK;
        assert_int_equal(qibl_srgbe_encode_f32_n(fin, N, c), QIBL_E_SRGBE_NAN);
        for (int i = 0; i < N; ++i) {
            qibl_status_t s = qibl_srgbe_encode_f32(fin + 3 * i, one);
            if (s == QIBL_E_SRGBE_NAN || (s == QIBL_E_SRGBE_INF && worst != QIBL_E_SRGBE_NAN))
                worst = s;
            assert_memory_equal(c + 4 * i, one, 4);
        }
        assert_int_equal(worst, QIBL_E_SRGBE_NAN);
        assert_true(tu_guard_intact(c + 4 * N, 16 - (size_t)off));
        assert_true(off == 0 || tu_guard_intact(codes, (size_t)off));
        assert_int_equal(qibl_srgbe_encode_f32_n(fin + 3 * 18, 300, c), QIBL_OK);
        /* decode of those codes, bulk against one pixel */
        assert_int_equal(qibl_srgbe_encode_f32_n(fin, N, c), QIBL_E_SRGBE_NAN);
        tu_fill_guard(fout, sizeof fout);
        qibl_status_t ds = qibl_srgbe_decode_f32_n(c, N, fout);
        assert_true(tu_guard_intact(fout + 3 * N, 4 * sizeof *fout));
        qibl_status_t dworst = QIBL_OK;
        for (int i = 0; i < N; ++i) {
            uint32_t d[3];
            if (qibl_srgbe_decode_f32(c + 4 * i, d) != QIBL_OK)
                dworst = QIBL_E_SRGBE_DECODE_SAT;
            assert_memory_equal(fout + 3 * i, d, sizeof d);
        }
        assert_int_equal(ds, dworst);
        for (size_t fi = 0; fi < sizeof fracs / sizeof fracs[0]; ++fi) {
            int f = fracs[fi];
            tu_fill_guard(codes, sizeof codes);
            qibl_status_t bs = qibl_srgbe_encode_s32_n(sin_, N, f, c);
            qibl_status_t sw = QIBL_OK;
            for (int i = 0; i < N; ++i) {
                qibl_status_t s = qibl_srgbe_encode_s32(sin_ + 3 * i, f, one);
                if (s != QIBL_OK)
                    sw = s;
                assert_memory_equal(c + 4 * i, one, 4);
            }
            assert_int_equal(bs, sw);
            assert_true(tu_guard_intact(c + 4 * N, 16 - (size_t)off));
            if (f == 16) {
                uint8_t c16[4 * N];
                assert_int_equal(qibl_srgbe_encode_q16_n(sin_, N, c16), bs);
                assert_memory_equal(c16, c, sizeof c16);
            }
            tu_fill_guard(sout, sizeof sout);
            qibl_status_t sd = qibl_srgbe_decode_s32_n(c, N, f, sout);
            qibl_status_t sdw = QIBL_OK;
            for (int i = 0; i < N; ++i) {
                int32_t d[3];
                if (qibl_srgbe_decode_s32(c + 4 * i, f, d) != QIBL_OK)
                    sdw = QIBL_E_SRGBE_DECODE_SAT;
                assert_memory_equal(sout + 3 * i, d, sizeof d);
            }
            assert_int_equal(sd, sdw);
            assert_true(tu_guard_intact(sout + 3 * N, 4 * sizeof *sout));
            if (f == 16) {
                int32_t q16[3 * N];
                assert_int_equal(qibl_srgbe_decode_q16_n(c, N, q16), sd);
                assert_memory_equal(q16, sout, sizeof q16);
            }
        }
    }
}

static void test_one_pixel_calls_may_overlap(void **state)
{
    (void)state;
    tu_rng r = {22};
    for (int k = 0; k < 10000; ++k) {
        uint32_t in[3] = {rnd_f32(&r, 3, 1.0), rnd_f32(&r, 3, 1.0), rnd_f32(&r, 1, 1.0)};
        uint8_t want[4];
        uint32_t buf[3] = {in[0], in[1], in[2]};
        qibl_status_t s = qibl_srgbe_encode_f32(in, want);
        assert_int_equal(qibl_srgbe_encode_f32(buf, (uint8_t *)buf), s); /* code over the input */
        assert_memory_equal(buf, want, 4);
        uint32_t dwant[3];
        s = qibl_srgbe_decode_f32(want, dwant);
        assert_int_equal(qibl_srgbe_decode_f32((const uint8_t *)buf, buf), s); /* values over the code */
        assert_memory_equal(buf, dwant, sizeof dwant);
        int32_t sb[3] = {(int32_t)(in[0] & 0x7FFFFFFFu), -(int32_t)(in[1] & 0x7FFFFFFFu), 5};
        int32_t iv[3] = {sb[0], sb[1], sb[2]};
        s = qibl_srgbe_encode_s32(iv, 20, want);
        assert_int_equal(qibl_srgbe_encode_s32(sb, 20, (uint8_t *)sb), s);
        assert_memory_equal(sb, want, 4);
        int32_t qwant[3];
        s = qibl_srgbe_decode_s32(want, 20, qwant);
        assert_int_equal(qibl_srgbe_decode_s32((const uint8_t *)sb, 20, sb), s);
        assert_memory_equal(sb, qwant, sizeof qwant);
    }
}

/* The GLES path: a shader samples t = X/255 (rounded to float) and computes (t - 0.5) * 2^e in
 * float. That value equals the C decoder's within 2^(e-23) (t's rounding 2^-25, the subtraction's
 * 2^-26, the decoder's half ulp 2^-25, all times 2^e), for every code whose 2^e the float range holds. */
static void test_gles_formula_agrees(void **state)
{
    (void)state;
    for (unsigned E = 30; E <= 253; ++E)
        for (unsigned X = 0; X < 256; ++X) {
            volatile float t = (float)X / 255.0f; /* volatile: float arithmetic, as the GPU does it */
            volatile float a = (float)E / 255.0f;
            float e = floorf(a * 255.0f + 0.5f) - 126.0f;
            float v = (t - 0.5f) * ldexpf(1.0f, (int)e);
            const uint8_t c[4] = {(uint8_t)X, 128, 128, (uint8_t)E};
            uint32_t d[3];
            assert_int_equal(qibl_srgbe_decode_f32(c, d), QIBL_OK);
            double diff = fabs((double)v - (double)float_of(d[0]));
            assert_true(diff <= ldexp(1.0, (int)E - 126 - 23));
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_zero_and_negative_zero),
        cmocka_unit_test(test_denormals),
        cmocka_unit_test(test_below_range_flushes_to_zero),
        cmocka_unit_test(test_above_range_saturates),
        cmocka_unit_test(test_infinities_saturate),
        cmocka_unit_test(test_nan_in_any_channel),
        cmocka_unit_test(test_mixed_signs),
        cmocka_unit_test(test_all_channels_equal),
        cmocka_unit_test(test_power_of_two_channels),
        cmocka_unit_test(test_largest_channel_negative),
        cmocka_unit_test(test_null_pointers_write_nothing),
        cmocka_unit_test(test_bound_all_exponents_dense_mantissas),
        cmocka_unit_test(test_bound_ten_million_random_triples),
        cmocka_unit_test(test_encode_int32_any_frac_bits_and_q16),
        cmocka_unit_test(test_decode_every_channel_byte_and_exponent),
        cmocka_unit_test(test_decode_saturation_and_ties),
        cmocka_unit_test(test_decode_random_codes_and_canonical_roundtrip),
        cmocka_unit_test(test_sign_symmetry),
        cmocka_unit_test(test_bulk_matches_scalar_at_every_alignment),
        cmocka_unit_test(test_bulk_kernel_matches_one_pixel_on_edges),
        cmocka_unit_test(test_bulk_decode_every_channel_code),
        cmocka_unit_test(test_one_pixel_calls_may_overlap),
        cmocka_unit_test(test_gles_formula_agrees),
    };
    return cmocka_run_group_tests_name("srgbe", tests, NULL, NULL);
}
