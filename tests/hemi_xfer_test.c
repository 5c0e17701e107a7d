/*
 * hemi_xfer_test.c - exported transfer in the core (qibl/hemi.h, qibl_hemi_xfer_*): a file made by
 * hand from the layout the header documents opens with its fields; every bad file gets its own
 * status with the view untouched; the span shade against a double-precision sum (and bit for bit
 * against qibl_hemi_shade with 25 coefficients); spans past the end refused with the output
 * untouched; and the tools' writer (transfer/export.h) gives the hand-made bytes.
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

#include "qibl/asset.h"
#include "qibl/hemi.h"
#include "testutil.h"
#include "transfer/export.h"

enum { NV = 7 };

static void le16(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v & 0xFF), p[1] = (uint8_t)(v >> 8);
}

static void le32(uint8_t *p, uint32_t v)
{
    for (int k = 0; k < 4; ++k)
        p[k] = (uint8_t)(v >> (8 * k));
}

/* The header's table, byte by byte: magic, version, bands, count, frac_bits, reserved, CRC, then
 * the payload vertex after vertex. Returns the size. */
static size_t hand_made(uint8_t *b, int bands, const int32_t (*t)[25], uint32_t nv)
{
    const uint32_t nc = (uint32_t)(bands * bands);
    b[0] = 'Q', b[1] = 'T', b[2] = 'R', b[3] = 'X';
    le16(b + 4, 1), le16(b + 6, (uint32_t)bands), le32(b + 8, nv), le32(b + 12, 30), le32(b + 16, 0);
    for (uint32_t v = 0; v < nv; ++v)
        for (uint32_t i = 0; i < nc; ++i)
            le32(b + 24 + 4 * (v * nc + i), (uint32_t)t[v][i]);
    le32(b + 20, qibl_crc32(0, b + 24, 4 * nv * nc));
    return 24 + 4 * (size_t)nv * nc;
}

static void random_transfer(tu_rng *r, int32_t (*t)[25], uint32_t nv)
{
    for (uint32_t v = 0; v < nv; ++v)
        for (int i = 0; i < 25; ++i)
            t[v][i] = v == 0 && i < 2 ? (i ? INT32_MIN : INT32_MAX) : tu_s32(r) >> (i % 4); /* extremes first */
}

static void random_light(tu_rng *r, int32_t light[3][25])
{
    for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i < 25; ++i)
            light[ch][i] = tu_s32(r) >> (8 + (ch + i) % 9); /* up to +-2^23: 128 in Q16.16 */
}

static void test_hand_made_opens(void **state)
{
    (void)state;
    tu_rng r = {25};
    int32_t t[NV][25];
    random_transfer(&r, t, NV);
    static uint8_t b[24 + 4 * NV * 25];
    for (int bands = 3; bands <= 5; ++bands) {
        const size_t n = hand_made(b, bands, (const int32_t(*)[25])t, NV);
        qibl_hemi_xfer_t x;
        assert_int_equal(qibl_hemi_xfer_open(&x, b, n), QIBL_OK);
        assert_int_equal(x.count, NV), assert_int_equal(x.bands, bands), assert_int_equal(x.ncoef, bands * bands);
        assert_ptr_equal(x.payload, b + 24);
        /* the tools' writer makes the same bytes */
        uint8_t *w;
        size_t wn;
        char err[256];
        assert_int_equal(qtool_transfer_export_bytes((const qibl_q30_t(*)[25])t, NV, bands, &w, &wn, err, sizeof err), 0);
        assert_int_equal(wn, n);
        assert_memory_equal(w, b, n);
        free(w);
    }
}

/* one bad byte or size at a time: its status, the view untouched */
static void test_bad_files(void **state)
{
    (void)state;
    tu_rng r = {7};
    int32_t t[NV][25];
    random_transfer(&r, t, NV);
    static uint8_t good[24 + 4 * NV * 16 + 4], b[sizeof good];
    const size_t n = hand_made(good, 4, (const int32_t(*)[25])t, NV);
    const struct {
        size_t off;
        int len; /* bytes of the field (1, 2 or 4) */
        uint32_t val;
        qibl_status_t want;
    } cases[] = {
        {0, 1, 'q', QIBL_E_HEMI_XFER_MAGIC},  {3, 1, 'Y', QIBL_E_HEMI_XFER_MAGIC},
        {4, 2, 2, QIBL_E_HEMI_XFER_FORMAT},   {4, 2, 0, QIBL_E_HEMI_XFER_FORMAT},
        {6, 2, 2, QIBL_E_HEMI_XFER_FORMAT},   {6, 2, 6, QIBL_E_HEMI_XFER_FORMAT},
        {8, 4, 0, QIBL_E_HEMI_XFER_FORMAT},   {8, 4, QIBL_HEMI_XFER_MAX_VERTICES + 1u, QIBL_E_HEMI_XFER_FORMAT},
        {12, 4, 16, QIBL_E_HEMI_XFER_FORMAT}, {16, 4, 1, QIBL_E_HEMI_XFER_FORMAT},
        {8, 4, NV - 1, QIBL_E_HEMI_XFER_SIZE}, {8, 4, NV + 1, QIBL_E_HEMI_XFER_SIZE},
        {6, 2, 3, QIBL_E_HEMI_XFER_SIZE},     {6, 2, 5, QIBL_E_HEMI_XFER_SIZE},
        {20, 1, 0x5A, QIBL_E_HEMI_XFER_CRC},  {24 + 4 * 3 + 1, 1, 0x77, QIBL_E_HEMI_XFER_CRC},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        memcpy(b, good, n);
        if (cases[k].len == 1) {
            if (b[cases[k].off] == (uint8_t)cases[k].val)
                b[cases[k].off] ^= 0x01; /* a CRC byte that happened to be the value */
            else
                b[cases[k].off] = (uint8_t)cases[k].val;
        } else if (cases[k].len == 2) {
            le16(b + cases[k].off, cases[k].val);
        } else {
            le32(b + cases[k].off, cases[k].val);
        }
        qibl_hemi_xfer_t x;
        memset(&x, 0x5A, sizeof x);
        const qibl_hemi_xfer_t before = x;
        print_message("case %zu\n", k);
        assert_int_equal(qibl_hemi_xfer_open(&x, b, n), cases[k].want);
        assert_memory_equal(&x, &before, sizeof x);
    }
    qibl_hemi_xfer_t x;
    for (size_t m = 0; m < 24; ++m) /* every length short of the header */
        assert_int_equal(qibl_hemi_xfer_open(&x, good, m), QIBL_E_HEMI_XFER_SHORT);
    assert_int_equal(qibl_hemi_xfer_open(&x, good, n - 1), QIBL_E_HEMI_XFER_SIZE); /* truncated */
    memcpy(b, good, n), b[n] = 0;
    assert_int_equal(qibl_hemi_xfer_open(&x, b, n + 1), QIBL_E_HEMI_XFER_SIZE); /* a trailing byte */
    assert_int_equal(qibl_hemi_xfer_open(NULL, good, n), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_hemi_xfer_open(&x, NULL, n), QIBL_E_NULL_POINTER);
    /* the tools' writer refuses what the format cannot hold */
    uint8_t *w;
    size_t wn;
    char err[256];
    assert_int_equal(qtool_transfer_export_bytes((const qibl_q30_t(*)[25])t, NV, 2, &w, &wn, err, sizeof err), -1);
    assert_null(w);
    assert_int_equal(qtool_transfer_export_bytes((const qibl_q30_t(*)[25])t, 0, 3, &w, &wn, err, sizeof err), -1);
}

/* the span shade against the exact sum in double: within 0.5 + n 2^-14 LSB (Q16.16), and with 25
 * coefficients qibl_hemi_shade's result bit for bit */
static void test_shade_against_double(void **state)
{
    (void)state;
    tu_rng r = {2026};
    static int32_t t[NV][25];
    static uint8_t b[24 + 4 * NV * 25];
    for (int round = 0; round < 200; ++round) {
        const int bands = 3 + round % 3, nc = bands * bands;
        random_transfer(&r, t, NV);
        int32_t light[3][25];
        random_light(&r, light);
        const size_t n = hand_made(b, bands, (const int32_t(*)[25])t, NV);
        qibl_hemi_xfer_t x;
        assert_int_equal(qibl_hemi_xfer_open(&x, b, n), QIBL_OK);
        qibl_q16_t out[NV + 1][3];
        tu_fill_guard(out, sizeof out);
        assert_int_equal(qibl_hemi_xfer_shade_span(&x, (const int32_t(*)[25])light, 0, NV, out), QIBL_OK);
        assert_true(tu_guard_intact(out[NV], sizeof out[NV])); /* nothing past the span */
        for (int v = 0; v < NV; ++v)
            for (int ch = 0; ch < 3; ++ch) {
                double s = 0;
                for (int i = 0; i < nc; ++i)
                    s += (double)light[ch][i] / 65536.0 * ((double)t[v][i] / 1073741824.0);
                const double want = fmin(fmax(s * 65536.0, -2147483648.0), 2147483647.0);
                assert_true(fabs((double)out[v][ch] - want) <= 0.5 + nc / 16384.0 + 1e-6);
            }
        if (bands == 5)
            for (int v = 0; v < NV; ++v) {
                qibl_q16_t e[3];
                assert_int_equal(qibl_hemi_shade((const int32_t(*)[25])light, t[v], e), QIBL_OK);
                assert_memory_equal(e, out[v], sizeof e);
            }
        /* a span in the middle gives the same vertices' values */
        qibl_q16_t mid[2][3];
        assert_int_equal(qibl_hemi_xfer_shade_span(&x, (const int32_t(*)[25])light, 3, 2, mid), QIBL_OK);
        assert_memory_equal(mid, out[3], sizeof mid);
    }
}

static void test_span_bounds(void **state)
{
    (void)state;
    tu_rng r = {3};
    int32_t t[NV][25], light[3][25];
    random_transfer(&r, t, NV);
    random_light(&r, light);
    static uint8_t b[24 + 4 * NV * 9];
    const size_t n = hand_made(b, 3, (const int32_t(*)[25])t, NV);
    qibl_hemi_xfer_t x;
    assert_int_equal(qibl_hemi_xfer_open(&x, b, n), QIBL_OK);
    qibl_q16_t out[NV][3];
    const uint32_t spans[][2] = {{0, NV + 1}, {NV, 1}, {NV + 1, 0}, {1, UINT32_MAX}, {UINT32_MAX, 2}};
    for (size_t k = 0; k < sizeof spans / sizeof spans[0]; ++k) {
        tu_fill_guard(out, sizeof out);
        assert_int_equal(qibl_hemi_xfer_shade_span(&x, (const int32_t(*)[25])light, spans[k][0], spans[k][1], out),
                         QIBL_E_HEMI_XFER_BOUNDS);
        assert_true(tu_guard_intact(out, sizeof out));
    }
    assert_int_equal(qibl_hemi_xfer_shade_span(&x, (const int32_t(*)[25])light, NV, 0, out), QIBL_OK); /* empty */
    assert_true(tu_guard_intact(out, sizeof out));
    assert_int_equal(qibl_hemi_xfer_shade_span(NULL, (const int32_t(*)[25])light, 0, 1, out), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_hemi_xfer_shade_span(&x, NULL, 0, 1, out), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_hemi_xfer_shade_span(&x, (const int32_t(*)[25])light, 0, 1, NULL), QIBL_E_NULL_POINTER);
    assert_string_equal(qibl_status_str(QIBL_E_HEMI_XFER_CRC), "transfer export CRC-32 mismatch");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hand_made_opens),
        cmocka_unit_test(test_bad_files),
        cmocka_unit_test(test_shade_against_double),
        cmocka_unit_test(test_span_bounds),
    };
    return cmocka_run_group_tests_name("hemi_xfer", tests, NULL, NULL);
}
