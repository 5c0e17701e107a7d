/*
 * luminaire_test.c - tools/luminaire: the .qnf file against its documented layout (a file built
 * here byte by byte, not by the writer), every named error with the output untouched, the atomic
 * writer; the simulated capture of the built-in luminaire (dark supports under the shade's solid
 * cells, the emitter's radiance where it is seen whole, flux against the truth integrated over a
 * plane); the spotlights' cull test exact; the near field against the ray-traced truth (>= 25 dB
 * and >= 6 dB above the far field at one lamp size); the passes (one at a time summing to the
 * one-call span, sRGBE accumulation within its stated bound of a double sum pass by pass, the two-
 * target sum within 2 of 255 over 64 passes); the kernel's lookup twin bit for bit; the hierarchy
 * (tol 0 the full sum bit for bit, random sources within a bound of it); `qibl luminaire` refusals
 * and outputs.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cliutil.h"
#include "testutil.h"
#include "io/png.h"
#include "luminaire/luminaire.h"
#include "qibl/asset.h"
#include "qibl/fixed.h"
#include "qibl/soft.h"
#include "qibl/srgbe.h"

CLI_FIXTURES("/tmp/qibl_lum_XXXXXX")

static void put32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v, p[1] = (uint8_t)(v >> 8), p[2] = (uint8_t)(v >> 16), p[3] = (uint8_t)(v >> 24);
}

static void putf(uint8_t *p, float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    put32(p, u);
}

/* The file of luminaire.h's table: nx 2, ny 1, res 2, box, h 0.5, D 2, w 1.5; texel k of the
 * payload (in file order) is k + 0.25. 64 + 2 * 4 * 12 = 160 bytes. */
#define HAND_N (64 + 2 * 4 * 12)
static void hand_file(uint8_t *b)
{
    memset(b, 0, HAND_N);
    memcpy(b, "QNF1", 4);
    b[4] = 1, b[5] = 0, b[6] = 64, b[7] = 0;
    put32(b + 8, 2), put32(b + 12, 1), put32(b + 16, 2), put32(b + 20, 1);
    putf(b + 24, 0.5f), putf(b + 28, 2.0f), putf(b + 32, 1.5f);
    put32(b + 36, 3), put32(b + 40, 96);
    for (int k = 0; k < 24; ++k)
        putf(b + 64 + 4 * k, (float)k + 0.25f);
    put32(b + 44, qibl_crc32(0, b + 64, 96));
    put32(b + 48, qibl_crc32(0, b, 48));
}

static void test_hand_made_file(void **state)
{
    (void)state;
    uint8_t b[HAND_N];
    hand_file(b);
    qtool_luminaire l;
    assert_int_equal(qtool_luminaire_decode(b, HAND_N, &l), QTOOL_LUMINAIRE_OK);
    assert_int_equal(l.nx, 2), assert_int_equal(l.ny, 1), assert_int_equal(l.res, 2);
    assert_int_equal(l.basis, QTOOL_LUMINAIRE_BOX);
    assert_true(l.spacing == 0.5f && l.distance == 2.0f && l.half_tan == 1.5f);
    /* support (ix 1, iy 0), row j 1, texel i 0: payload texel 4 + 2 + 0 = 6, floats 18..20 */
    const float *t = l.tex + qtool_luminaire_texel(&l, 1, 0, 0, 1);
    assert_true(t[0] == 18.25f && t[1] == 19.25f && t[2] == 20.25f);
    /* the writer gives the same bytes back */
    uint8_t *e;
    size_t n;
    assert_int_equal(qtool_luminaire_encode(&l, &e, &n), QTOOL_LUMINAIRE_OK);
    assert_int_equal(n, HAND_N);
    assert_memory_equal(e, b, HAND_N);
    free(e);
    qtool_luminaire_free(&l);
}

typedef struct {
    int off;        /* byte to change */
    uint32_t value; /* new 32-bit little-endian value at off (or byte when width 1) */
    int width;
    int fix_hcrc;   /* recompute the header CRC after the change */
    qtool_luminaire_err want;
} mutation;

static void expect(const uint8_t *b, size_t n, qtool_luminaire_err want)
{
    qtool_luminaire l, before;
    memset(&l, 0x5A, sizeof l);
    before = l;
    qtool_luminaire_err e = qtool_luminaire_decode(b, n, &l);
    if (e != want)
        fail_msg("got %d (%s), want %d (%s)", e, qtool_luminaire_err_str(e), want, qtool_luminaire_err_str(want));
    assert_memory_equal(&l, &before, sizeof l); /* nothing written on failure */
    assert_true(strlen(qtool_luminaire_err_str(e)) > 2);
}

static void test_every_error(void **state)
{
    (void)state;
    uint32_t nan_bits = 0x7FC00000u, inf_bits = 0x7F800000u, half = 0x3F000000u /* 0.5f */;
    const mutation ms[] = {
        {0, 'X', 1, 0, QTOOL_LUMINAIRE_E_MAGIC},
        {4, 2, 1, 0, QTOOL_LUMINAIRE_E_VERSION},
        {6, 63, 1, 0, QTOOL_LUMINAIRE_E_HEADER_SIZE},
        {8, 0, 4, 0, QTOOL_LUMINAIRE_E_GRID},
        {12, 65, 4, 0, QTOOL_LUMINAIRE_E_GRID},
        {16, 1, 4, 0, QTOOL_LUMINAIRE_E_RES},
        {16, 129, 4, 0, QTOOL_LUMINAIRE_E_RES},
        {20, 3, 4, 0, QTOOL_LUMINAIRE_E_BASIS},
        {20, 0, 4, 0, QTOOL_LUMINAIRE_E_BASIS},
        {24, nan_bits, 4, 0, QTOOL_LUMINAIRE_E_SPACING},
        {24, 0, 4, 0, QTOOL_LUMINAIRE_E_SPACING},
        {28, inf_bits, 4, 0, QTOOL_LUMINAIRE_E_DISTANCE},
        {28, 0xBF800000u /* -1 */, 4, 0, QTOOL_LUMINAIRE_E_DISTANCE},
        {32, 0x41880000u /* 17 */, 4, 0, QTOOL_LUMINAIRE_E_WINDOW},
        {32, 0, 4, 0, QTOOL_LUMINAIRE_E_WINDOW},
        {36, 4, 4, 0, QTOOL_LUMINAIRE_E_CHANNELS},
        {40, 95, 4, 0, QTOOL_LUMINAIRE_E_PAYLOAD_SIZE},
        {55, 1, 1, 0, QTOOL_LUMINAIRE_E_RESERVED},
        {48, 0, 4, 0, QTOOL_LUMINAIRE_E_HEADER_CRC},
        {24, half + 1, 4, 0, QTOOL_LUMINAIRE_E_HEADER_CRC}, /* a legal spacing, the CRC not updated */
        {44, 0, 4, 1, QTOOL_LUMINAIRE_E_PAYLOAD_CRC},
        {64, 0xAA, 1, 0, QTOOL_LUMINAIRE_E_PAYLOAD_CRC}, /* a payload byte changed */
    };
    for (size_t k = 0; k < sizeof ms / sizeof ms[0]; ++k) {
        uint8_t b[HAND_N];
        hand_file(b);
        if (ms[k].width == 1)
            b[ms[k].off] = (uint8_t)ms[k].value;
        else
            put32(b + ms[k].off, ms[k].value);
        if (ms[k].fix_hcrc)
            put32(b + 48, qibl_crc32(0, b, 48));
        expect(b, HAND_N, ms[k].want);
    }
    /* too many texels in all: 64 x 64 supports of 128^2 (each field alone is legal) */
    uint8_t b[HAND_N];
    hand_file(b);
    put32(b + 8, 64), put32(b + 12, 64), put32(b + 16, 128);
    expect(b, HAND_N, QTOOL_LUMINAIRE_E_TOO_BIG);
    /* a texel NaN (CRCs right): VALUE */
    hand_file(b);
    put32(b + 64 + 4 * 7, nan_bits);
    put32(b + 44, qibl_crc32(0, b + 64, 96));
    put32(b + 48, qibl_crc32(0, b, 48));
    expect(b, HAND_N, QTOOL_LUMINAIRE_E_VALUE);
    /* lengths: short header, short payload, one byte too many */
    hand_file(b);
    expect(b, 63, QTOOL_LUMINAIRE_E_TRUNCATED);
    expect(b, HAND_N - 1, QTOOL_LUMINAIRE_E_TRUNCATED);
    expect(NULL, 0, QTOOL_LUMINAIRE_E_TRUNCATED);
    uint8_t big[HAND_N + 1];
    memcpy(big, b, HAND_N), big[HAND_N] = 0;
    expect(big, HAND_N + 1, QTOOL_LUMINAIRE_E_TRAILING);
}

static void test_file_io(void **state)
{
    (void)state;
    uint8_t b[HAND_N];
    hand_file(b);
    qtool_luminaire l, r;
    assert_int_equal(qtool_luminaire_decode(b, HAND_N, &l), QTOOL_LUMINAIRE_OK);
    const char *f = at("a.qnf");
    char err[256];
    assert_int_equal(qtool_luminaire_write(f, &l, err, sizeof err), QTOOL_LUMINAIRE_OK);
    assert_int_equal(qtool_luminaire_read(f, &r), QTOOL_LUMINAIRE_OK);
    assert_memory_equal(r.tex, l.tex, 96);
    qtool_luminaire_free(&r);
    /* a refused source writes nothing and leaves the old file whole */
    l.tex[3] = NAN;
    assert_int_equal(qtool_luminaire_write(f, &l, err, sizeof err), QTOOL_LUMINAIRE_E_VALUE);
    assert_int_equal(qtool_luminaire_read(f, &r), QTOOL_LUMINAIRE_OK);
    qtool_luminaire_free(&r);
    l.tex[3] = 1;
    assert_int_equal(qtool_luminaire_write(at("no/such/dir.qnf"), &l, err, sizeof err), QTOOL_LUMINAIRE_E_WRITE);
    assert_int_equal(qtool_luminaire_read(at("missing.qnf"), &r), QTOOL_LUMINAIRE_E_IO);
    /* the reader's own length checks: a file cut short, one with a byte too many */
    FILE *o = fopen(at("short.qnf"), "wb");
    assert_non_null(o);
    assert_int_equal(fwrite(b, 1, HAND_N - 4, o), HAND_N - 4);
    fclose(o);
    assert_int_equal(qtool_luminaire_read(at("short.qnf"), &r), QTOOL_LUMINAIRE_E_TRUNCATED);
    o = fopen(at("long.qnf"), "wb");
    assert_non_null(o);
    assert_int_equal(fwrite(b, 1, HAND_N, o), HAND_N);
    fputc(0, o);
    fclose(o);
    assert_int_equal(qtool_luminaire_read(at("long.qnf"), &r), QTOOL_LUMINAIRE_E_TRAILING);
    qtool_luminaire_free(&l);
}

/* the built-in luminaire: 4 x 4 supports are its plate's cells, dark exactly under the solid ones */
static void test_capture(void **state)
{
    (void)state;
    qtool_luminaire_model *m = qtool_luminaire_builtin();
    assert_non_null(m);
    qtool_luminaire l;
    qtool_luminaire_capture_opts o = {.grid = 4, .res = 16, .samples = 4};
    assert_int_equal(qtool_luminaire_capture(m, &o, &l), 0);
    assert_int_equal(qtool_luminaire_check(&l), QTOOL_LUMINAIRE_OK);
    double peak = 0;
    for (uint32_t iy = 0; iy < 4; ++iy)
        for (uint32_t ix = 0; ix < 4; ++ix) {
            double sum = 0;
            for (uint32_t j = 0; j < 16; ++j)
                for (uint32_t i = 0; i < 16; ++i) {
                    const float *t = l.tex + qtool_luminaire_texel(&l, ix, iy, i, j);
                    sum += t[0];
                    peak = t[0] > peak ? t[0] : peak;
                    assert_true(t[0] >= 0 && t[1] <= t[0] && t[2] <= t[1]); /* the emitter's warm white */
                }
            if ((ix + iy) & 1)
                assert_true(sum == 0);
            else
                assert_true(sum > 0);
        }
    /* straight below a hole the filter sees the emitter whole: E' is its radiance (box filter) */
    assert_true(fabs(peak - QTOOL_LUMINAIRE_LE) < 0.02 * QTOOL_LUMINAIRE_LE);
    /* flux: the file's against the truth's irradiance integrated over a large plane 1 below */
    double flux[3], tf = 0;
    qtool_luminaire_flux(&l, flux);
    const int N = 40;
    const double half = 2.2, up[3] = {0, 0, 1};
    for (int y = 0; y < N; ++y)
        for (int x = 0; x < N; ++x) {
            double p[3] = {-half + (x + 0.5) * 2 * half / N, -half + (y + 0.5) * 2 * half / N, -1}, e[3];
            qtool_luminaire_model_irradiance(m, p, up, 8, e);
            tf += e[0] * (2 * half / N) * (2 * half / N);
        }
    print_message("flux %.5g, truth %.5g\n", flux[0], tf);
    assert_true(flux[0] > 0);
    if (fabs(flux[0] - tf) > 0.06 * tf)
        fail_msg("flux %.5g against the truth's %.5g", flux[0], tf);
    /* the tent basis (its filter a quasi-interpolant over two cells): the same flux */
    qtool_luminaire lt;
    qtool_luminaire_capture_opts ot = {.grid = 5, .res = 16, .samples = 3, .basis = QTOOL_LUMINAIRE_TENT};
    assert_int_equal(qtool_luminaire_capture(m, &ot, &lt), 0);
    assert_int_equal(lt.basis, QTOOL_LUMINAIRE_TENT);
    assert_true(fabs(lt.spacing - 0.1f) < 1e-7f);
    double ft[3];
    qtool_luminaire_flux(&lt, ft);
    print_message("tent flux %.5g\n", ft[0]);
    if (fabs(ft[0] - tf) > 0.06 * tf)
        fail_msg("tent flux %.5g against the truth's %.5g", ft[0], tf);
    qtool_luminaire_free(&lt);
    qtool_luminaire_free(&l);
    qtool_luminaire_model_free(m);
}

static double psnr(const double *a, const double *t, size_t n)
{
    double peak = 0, se = 0;
    for (size_t i = 0; i < n; ++i)
        peak = t[i] > peak ? t[i] : peak, se += (a[i] - t[i]) * (a[i] - t[i]);
    return 10 * log10(peak * peak / (se / (double)n));
}

static void ground(const qtool_luminaire_spots *s, double hgt, double half, uint32_t n, double *out)
{
    const uint32_t na = s->nanchor;
    int32_t *base = malloc(sizeof(int32_t) * 3 * n * na), *pts = malloc(sizeof(int32_t) * 3 * n);
    int64_t *acc = malloc(sizeof(int64_t) * 3 * n), *ws = malloc(qtool_luminaire_span_ws_size(n));
    assert_true(base && pts && acc && ws);
    for (uint32_t y = 0; y < n; ++y) {
        for (uint32_t x = 0; x < n; ++x) {
            double p[3] = {-half + (x + 0.5) * 2 * half / n, -half + (y + 0.5) * 2 * half / n, 0};
            for (int k = 0; k < 3; ++k)
                pts[3 * x + (uint32_t)k] = (int32_t)lround(p[k] * 65536);
            for (uint32_t a = 0; a < na; ++a) {
                double w[3] = {s->anchor[a][0] / 65536.0 - p[0], s->anchor[a][1] / 65536.0 - p[1], hgt};
                double r2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
                for (int k = 0; k < 3; ++k)
                    base[3 * ((size_t)a * n + x) + (size_t)k] = (int32_t)lround(hgt / sqrt(r2) / M_PI / r2 * 65536);
            }
        }
        memset(acc, 0, sizeof(int64_t) * 3 * n);
        qtool_luminaire_spots_span(s, base, pts, n, acc, ws);
        for (uint32_t i = 0; i < 3 * n; ++i)
            out[(size_t)y * 3 * n + i] = qtool_luminaire_q16(acc[i]) / 65536.0;
    }
    free(base), free(pts), free(acc), free(ws);
}

/* near field against the truth one lamp size below, beside the far field; the cull is exact */
static void test_near_field(void **state)
{
    (void)state;
    qtool_luminaire_model *m = qtool_luminaire_builtin();
    qtool_luminaire l;
    qtool_luminaire_capture_opts o = {.grid = 8, .res = 32};
    assert_int_equal(qtool_luminaire_capture(m, &o, &l), 0);
    const double hgt = QTOOL_LUMINAIRE_SIZE, half = 1.8 * hgt + QTOOL_LUMINAIRE_SIZE / 2;
    const uint32_t n = 40;
    double *t = malloc(sizeof(double) * 3 * n * n), *nr = malloc(sizeof(double) * 3 * n * n),
           *fr = malloc(sizeof(double) * 3 * n * n), *nc = malloc(sizeof(double) * 3 * n * n);
    assert_true(t && nr && fr && nc);
    const double up[3] = {0, 0, 1};
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x) {
            double p[3] = {-half + (x + 0.5) * 2 * half / n, -half + (y + 0.5) * 2 * half / n, -hgt}, e[3];
            qtool_luminaire_model_irradiance(m, p, up, 16, e);
            for (int k = 0; k < 3; ++k)
                t[3 * ((size_t)y * n + x) + (size_t)k] = e[k] / M_PI;
        }
    int32_t pos[3] = {0, 0, (int32_t)lround(hgt * 65536)};
    qtool_luminaire_spots sn, sf;
    char err[128];
    assert_int_equal(qtool_luminaire_spots_make(&l, pos, 64, 0, &sn, err, sizeof err), 0);
    assert_int_equal(qtool_luminaire_spots_make(&l, pos, 64, 1, &sf, err, sizeof err), 0);
    assert_int_equal(sf.count, 1);
    /* refusals with a reason: a table size outside the core's range, tables beyond the cap */
    qtool_luminaire_spots bad;
    err[0] = 0;
    assert_int_equal(qtool_luminaire_spots_make(&l, pos, 1, 0, &bad, err, sizeof err), -1);
    assert_true(strlen(err) > 0);
    qtool_luminaire big = l;
    big.nx = big.ny = 64; /* 4096 supports of 256^2 tables: 512 MiB (refused before any texel is read) */
    err[0] = 0;
    assert_int_equal(qtool_luminaire_spots_make(&big, pos, 256, 0, &bad, err, sizeof err), -1);
    assert_non_null(strstr(err, "MiB"));
    assert_true(sn.count >= 16 && sn.count < 64); /* the supports under the solid cells have no lamp */
    ground(&sn, hgt, half, n, nr);
    ground(&sf, hgt, half, n, fr);
    double pn = psnr(nr, t, 3 * (size_t)n * n), pf = psnr(fr, t, 3 * (size_t)n * n);
    print_message("near %.2f dB, far %.2f dB\n", pn, pf);
    assert_true(pn >= 25);
    assert_true(pn - pf >= 6);
    /* the cull bounds and occupancy bits only skip zeros: the same sums with them off, here and
     * a quarter lamp size below an off-centre lamp (every spotlight's footprint oblique) */
    qtool_luminaire_spots so;
    const int32_t pos2[3] = {3000, -7000, (int32_t)lround(0.1 * 65536)};
    assert_int_equal(qtool_luminaire_spots_make(&l, pos2, 64, 0, &so, err, sizeof err), 0);
    double *n2 = malloc(sizeof(double) * 3 * n * n), *c2 = malloc(sizeof(double) * 3 * n * n);
    assert_true(n2 && c2);
    ground(&so, 0.1, 0.5, n, n2);
    for (uint32_t j = 0; j < sn.count; ++j)
        sn.cull[j][0] = sn.cull[j][1] = -1;
    sn.cullmax[0] = sn.cullmax[1] = -1;
    for (uint32_t j = 0; j < so.count; ++j)
        so.cull[j][0] = so.cull[j][1] = -1;
    so.cullmax[0] = so.cullmax[1] = -1;
    ground(&sn, hgt, half, n, nc);
    assert_memory_equal(nc, nr, sizeof(double) * 3 * n * n);
    ground(&so, 0.1, 0.5, n, c2);
    assert_memory_equal(c2, n2, sizeof(double) * 3 * n * n);
    qtool_luminaire_spots_free(&so);
    free(n2), free(c2);
    /* points far outside the Q16.16 scene and on the lamp itself: finite, no overflow (UBSan) */
    int32_t base[48], pts[12] = {INT32_MAX, INT32_MAX, INT32_MIN, INT32_MIN, INT32_MIN, INT32_MIN, 0, 0, pos[2] - 1,
                                 sn.pos[0][0], sn.pos[0][1], sn.pos[0][2] - 1};
    for (int k = 0; k < 48; ++k)
        base[k] = k % 3 == 0 ? INT32_MAX : k % 3 == 1 ? INT32_MIN : 65536;
    int64_t acc[12] = {0}, ws[4 * QTOOL_LUMINAIRE_WS_PER_PIXEL];
    qtool_luminaire_spots_span(&sn, base, pts, 4, acc, ws);
    qtool_luminaire_spots_free(&sn), qtool_luminaire_spots_free(&sf);
    free(t), free(nr), free(fr), free(nc);
    qtool_luminaire_free(&l);
    qtool_luminaire_model_free(m);
}

static const char *out_text(void)
{
    static char buf[4096];
    FILE *f = fopen(outlog, "r");
    size_t n = f ? fread(buf, 1, sizeof buf - 1, f) : 0;
    if (f)
        fclose(f);
    buf[n] = 0;
    return buf;
}

/* The bound qtool_luminaire_srgbe_add(2) state, pass by pass against the exact (double) sum of the
 * same terms: |decoded - exact| <= sum over passes of (2^e / 510 + 3/2 LSB), e the exponent of the
 * code that pass wrote (the second target's for add2). */
static void check_accumulation(const qtool_luminaire_passes *r, int two)
{
    const size_t npix = (size_t)r->size * r->size;
    const int f = r->frac_bits;
    uint8_t *hi = malloc(4 * npix), *lo = malloc(4 * npix);
    double *exact = calloc(3 * npix, sizeof(double)), *bound = calloc(3 * npix, sizeof(double));
    assert_true(hi && lo && exact && bound);
    qtool_luminaire_srgbe_clear(hi, (uint32_t)npix);
    qtool_luminaire_srgbe_clear(lo, (uint32_t)npix);
    double worst = 0, lsb = ldexp(1, -f);
    for (uint32_t j = 0; j < r->passes; ++j) {
        const int64_t *t = r->terms + (size_t)j * 3 * npix;
        assert_int_equal(two ? qtool_luminaire_srgbe_add2(hi, lo, t, (uint32_t)npix, f)
                             : qtool_luminaire_srgbe_add(hi, t, (uint32_t)npix, f),
                         QIBL_OK);
        for (size_t i = 0; i < npix; ++i) {
            const uint8_t *c = (two ? lo : hi) + 4 * i;
            int32_t h[3], l[3] = {0, 0, 0};
            assert_int_equal(qibl_srgbe_decode_s32(hi + 4 * i, f, h), QIBL_OK);
            if (two)
                assert_int_equal(qibl_srgbe_decode_s32(lo + 4 * i, f, l), QIBL_OK);
            for (int k = 0; k < 3; ++k) {
                size_t x = 3 * i + (size_t)k;
                exact[x] += ldexp((double)t[x], -24);
                bound[x] += ldexp(1, c[3] - 126) / 510 + 1.5 * lsb;
                double err = fabs(ldexp((double)h[k] + l[k], -f) - exact[x]);
                assert_true(err <= bound[x]);
                worst = fmax(worst, err / bound[x]);
            }
        }
    }
    assert_true(worst > 0.01); /* the bound is not vacuous: some pass comes near it */
    free(hi), free(lo), free(exact), free(bound);
}

static void test_passes(void **state)
{
    (void)state;
    qtool_luminaire l;
    assert_int_equal(qtool_luminaire_synthetic(8, &l), 0);
    /* the passes one at a time sum to the one-call span exactly (any anchors' shading) */
    qtool_luminaire_spots s;
    char err[128];
    const int32_t pos[3] = {0, 0, 26214};
    assert_int_equal(qtool_luminaire_spots_make(&l, pos, 64, 0, &s, err, sizeof err), 0);
    assert_int_equal(s.count, 64);
    const uint32_t n = 32;
    int32_t *base = malloc(sizeof(int32_t) * 3 * n * 4), *pts = malloc(sizeof(int32_t) * 3 * n);
    int64_t *a1 = calloc(3 * n, sizeof(int64_t)), *a2 = calloc(3 * n, sizeof(int64_t)),
            *ws = malloc(qtool_luminaire_span_ws_size(n));
    assert_true(base && pts && a1 && a2 && ws);
    for (uint32_t i = 0; i < n; ++i) {
        pts[3 * i] = (int32_t)(i * 3000) - 48000, pts[3 * i + 1] = 7000, pts[3 * i + 2] = 0;
        for (uint32_t k = 0; k < 12; ++k)
            base[3 * ((k / 3) * n + i) + k % 3] = (int32_t)(20000 + 1000 * k + 37 * i);
    }
    qtool_luminaire_spots_span(&s, base, pts, n, a1, ws);
    for (uint32_t j = 0; j < s.count; ++j)
        qtool_luminaire_spot_pass(&s, j, base, pts, n, a2, ws);
    assert_memory_equal(a1, a2, sizeof(int64_t) * 3 * n);
    int lit = 0;
    for (uint32_t i = 0; i < 3 * n; ++i)
        lit += a1[i] > 0;
    assert_true(lit > (int)n);
    free(base), free(pts), free(a1), free(a2), free(ws), qtool_luminaire_spots_free(&s);

    /* 64 passes: both targets within their stated bound of the double sum, pass by pass; the
     * two-target sum within 2 of 255 of binary32 accumulation (the goal) */
    qtool_luminaire_passes r;
    assert_int_equal(qtool_luminaire_passes_run(&l, 24, QTOOL_LUMINAIRE_SIZE, &r), 0);
    assert_int_equal(r.passes, 64);
    check_accumulation(&r, 0);
    check_accumulation(&r, 1);
    assert_true(r.srgbe2_vs_float <= 2 && r.srgbe2_vs_core <= 2);
    assert_true(r.float_vs_core <= 1);
    assert_true(r.max_rel2 < r.max_rel); /* the second target is what buys the accuracy */
    qtool_luminaire_passes_free(&r);
    qtool_luminaire_free(&l);

    /* the working format: the largest frac_bits keeping every sum below 2^30 */
    assert_int_equal(qtool_luminaire_srgbe_frac(((uint64_t)1 << 30) - 2), 24);
    assert_int_equal(qtool_luminaire_srgbe_frac(((uint64_t)1 << 30) - 1), 23);
    assert_int_equal(qtool_luminaire_srgbe_frac((uint64_t)1 << 40), 13);

    /* refusals write nothing: a sum beyond int32 in the second pixel, frac_bits out of range */
    uint8_t c[8], c0[8], d[8];
    qtool_luminaire_srgbe_clear(c, 2);
    int64_t t[6] = {1 << 24, 0, 0, (int64_t)1 << 40, 0, 0};
    memcpy(c0, c, 8);
    assert_int_equal(qtool_luminaire_srgbe_add(c, t, 2, 24), QIBL_E_RANGE);
    assert_memory_equal(c, c0, 8);
    memcpy(d, c, 8);
    assert_int_equal(qtool_luminaire_srgbe_add2(c, d, t, 2, 24), QIBL_E_RANGE);
    assert_memory_equal(c, c0, 8);
    assert_memory_equal(d, c0, 8);
    assert_int_equal(qtool_luminaire_srgbe_add(c, t, 2, 25), QIBL_E_RANGE);
    assert_memory_equal(c, c0, 8);
    /* a zero pass keeps the zero code; 1.0 then decodes as 1.0 within half a step */
    int64_t z[6] = {0, 0, 0, 0, 0, 0};
    assert_int_equal(qtool_luminaire_srgbe_add(c, z, 2, 24), QIBL_OK);
    assert_memory_equal(c, c0, 8);
    assert_int_equal(qtool_luminaire_srgbe_add(c, t, 1, 24), QIBL_OK);
    int32_t v[3];
    assert_int_equal(qibl_srgbe_decode_s32(c, 24, v), QIBL_OK);
    assert_true(labs((long)v[0] - (1L << 24)) <= (1L << 24) * 4 / 510);
}

/* the span kernel's square root: qibl_isqrt_u64's floor, bit for bit, at every square, its
 * neighbours and a fixed-seed sweep up to the kernel's 2^48 (and the documented 2^52) */
static void test_isqrt_twin(void **state)
{
    (void)state;
    for (uint64_t r = 0; r <= ((uint64_t)1 << 26); r += r < 5000 ? 1 : 9973) {
        uint64_t sq = r * r;
        assert_int_equal(qtool_luminaire_isqrt(sq), qibl_isqrt_u64(sq, NULL));
        if (sq)
            assert_int_equal(qtool_luminaire_isqrt(sq - 1), qibl_isqrt_u64(sq - 1, NULL));
        assert_int_equal(qtool_luminaire_isqrt(sq + 1), qibl_isqrt_u64(sq + 1, NULL));
    }
    uint64_t x = 0x9E3779B97F4A7C15u;
    for (int k = 0; k < 200000; ++k) {
        x ^= x << 13, x ^= x >> 7, x ^= x << 17;
        uint64_t v = x >> (12 + (unsigned)(k % 40)); /* every magnitude up to 2^52 */
        assert_int_equal(qtool_luminaire_isqrt(v), qibl_isqrt_u64(v, NULL));
    }
    assert_int_equal(qtool_luminaire_isqrt((uint64_t)1 << 52), (uint64_t)1 << 26);
    assert_int_equal(qtool_luminaire_isqrt(((uint64_t)1 << 52) - 1), ((uint64_t)1 << 26) - 1);
}

/* the span kernel's bytes on fixed inputs (synthetic sources of 16 and 64 spotlights, 64 x 64 points
 * below them, anchors' shading varying): FNV-1a of the sums, recorded from the kernel before its
 * speed-ups (commit 019b602: the core's digit-by-digit square root, a bit loop for bit lengths), so
 * they changed no byte */
static void test_span_bytes(void **state)
{
    (void)state;
    uint64_t h = 1469598103934665603u;
    for (uint32_t g = 4; g <= 8; g += 4) {
        qtool_luminaire l;
        qtool_luminaire_spots s;
        char err[128];
        assert_int_equal(qtool_luminaire_synthetic(g, &l), 0);
        const int32_t pos[3] = {0, 0, 26214};
        assert_int_equal(qtool_luminaire_spots_make(&l, pos, 64, 0, &s, err, sizeof err), 0);
        const uint32_t n = 64;
        int32_t base[3 * 64 * 4], pts[3 * 64];
        int64_t acc[3 * 64], *ws = malloc(qtool_luminaire_span_ws_size(n));
        assert_non_null(ws);
        for (uint32_t y = 0; y < n; ++y) {
            for (uint32_t i = 0; i < n; ++i) {
                pts[3 * i] = (int32_t)(i * 1700) - 54400, pts[3 * i + 1] = (int32_t)(y * 1700) - 54400;
                pts[3 * i + 2] = -(int32_t)(y * 37);
                for (uint32_t k = 0; k < 12; ++k)
                    base[3 * ((k / 3) * n + i) + k % 3] = (int32_t)(20000 + 1000 * k + 37 * i - 11 * y);
            }
            memset(acc, 0, sizeof acc);
            qtool_luminaire_spots_span(&s, base, pts, n, acc, ws);
            for (size_t k = 0; k < 3 * 64; ++k) /* little-endian bytes, whatever the host's order */
                for (unsigned b = 0; b < 64; b += 8)
                    h = (h ^ (uint8_t)((uint64_t)acc[k] >> b)) * 1099511628211u;
        }
        free(ws), qtool_luminaire_spots_free(&s), qtool_luminaire_free(&l);
    }
    assert_true(h == 0x5cc420fd563744c4u);
}


/* the span kernel's lookup: qibl_gonio_lookup's result bit for bit (its divisions replaced by
 * corrected double quotients) on random tables of every size class, random frames and directions of
 * every magnitude, and the hard ones (0, the axes, the folds) */
static void test_lookup_twin(void **state)
{
    (void)state;
    uint64_t x = 0x2545F4914F6CDD1Du;
#define NEXT() (x ^= x << 13, x ^= x >> 7, x ^= x << 17, x)
    static const uint32_t ns[] = {2, 3, 17, 64, 100, 256};
    uint16_t *tab = malloc(sizeof(uint16_t) * 256 * 256);
    assert_non_null(tab);
    for (size_t t = 0; t < sizeof ns / sizeof ns[0]; ++t) {
        const uint32_t n = ns[t];
        for (uint32_t k = 0; k < n * n; ++k)
            tab[k] = (uint16_t)(NEXT() % 32769u);
        for (int f = 0; f < 4; ++f) {
            int32_t aim[3], up[3];
            for (int k = 0; k < 3; ++k)
                aim[k] = (int32_t)(NEXT() % 131073u) - 65536, up[k] = (int32_t)(NEXT() % 131073u) - 65536;
            if (f == 0)
                aim[0] = 0, aim[1] = 0, aim[2] = -65536, up[0] = 0, up[1] = 65536, up[2] = 0; /* the spotlights' */
            qibl_gonio_t g;
            if (qibl_gonio_init(&g, n, tab, aim, up) != QIBL_OK)
                continue;
            for (int r = 0; r < 20000; ++r) {
                int64_t d[3];
                for (int k = 0; k < 3; ++k) {
                    unsigned sh = (unsigned)(NEXT() % 63u); /* every magnitude up to 2^62 */
                    int64_t v = (int64_t)(NEXT() >> (1 + sh));
                    d[k] = NEXT() & 1 ? -v : v;
                }
                if (r < 27) /* 0, the axes and the diagonals */
                    d[0] = r % 3 - 1, d[1] = r / 3 % 3 - 1, d[2] = r / 9 - 1;
                assert_int_equal(qtool_luminaire_lookup(&g, d), qibl_gonio_lookup(&g, d));
            }
        }
    }
#undef NEXT
    free(tab);
}

/* a random source: the synthetic lobes, each support dark (p 1/4) or scaled, with random sharp
 * bright texels (a pattern finer than the lobes) */
static void random_source(uint32_t grid, uint64_t seed, qtool_luminaire *l)
{
    assert_int_equal(qtool_luminaire_synthetic(grid, l), 0);
    uint64_t x = seed;
#define NEXT() (x ^= x << 13, x ^= x >> 7, x ^= x << 17, x)
    for (uint32_t m = 0; m < grid * grid; ++m) {
        double f = NEXT() % 4u == 0 ? 0 : 0.25 + (double)(NEXT() % 1000u) / 500.0;
        for (uint32_t j = 0; j < l->res; ++j)
            for (uint32_t i = 0; i < l->res; ++i) {
                float *t = l->tex + qtool_luminaire_texel(l, m % grid, m / grid, i, j);
                double g = NEXT() % 8u == 0 ? 3.0 : 1.0;
                for (int k = 0; k < 3; ++k)
                    t[k] = (float)(t[k] * f * g);
            }
    }
#undef NEXT
}

/* The hierarchy: at tol 0 the same spotlights and sums as spots_make, bit for bit; at tol > 0 the
 * passes stay level 0's (they sum to the tol 0 frame); on random sources at random depths each
 * coarser level's frame stays within its bound of the full sum (merged lamps corrected for parallax;
 * without the correction, the sum of the members' tables toward the group's centre, this fails) */
static void test_hierarchy(void **state)
{
    (void)state;
    char err[128];
    qtool_luminaire l;
    random_source(8, 0x9E3779B97F4A7C15u, &l);
    const int32_t pos[3] = {1234, -4321, (int32_t)lround(0.4 * 65536)};
    qtool_luminaire_spots a, b;
    const qtool_luminaire_spots_opts o0 = {.n = 64};
    assert_int_equal(qtool_luminaire_spots_make(&l, pos, 64, 0, &a, err, sizeof err), 0);
    assert_int_equal(qtool_luminaire_spots_build(&l, pos, &o0, &b, err, sizeof err), 0);
    assert_int_equal(a.count, b.count);
    assert_int_equal(b.total, b.count);
    assert_int_equal(b.nlevel, 0);
    assert_memory_equal(a.tables, b.tables, sizeof(uint16_t) * 64 * 64 * a.count);
    assert_memory_equal(a.rgb, b.rgb, sizeof *a.rgb * a.count);
    assert_memory_equal(a.pos, b.pos, sizeof *a.pos * a.count);
    const uint32_t n = 48;
    const size_t nv = (size_t)3 * n * n;
    double *fa = malloc(sizeof(double) * nv), *fb = malloc(sizeof(double) * nv);
    assert_true(fa && fb);
    ground(&a, 0.4, 1.0, n, fa);
    ground(&b, 0.4, 1.0, n, fb);
    assert_memory_equal(fa, fb, sizeof(double) * nv);
    qtool_luminaire_spots_free(&b);
    /* out of range: refused with a reason, nothing allocated */
    const qtool_luminaire_spots_opts bad = {.n = 64, .tol = 1.5};
    err[0] = 0;
    assert_int_equal(qtool_luminaire_spots_build(&l, pos, &bad, &b, err, sizeof err), -1);
    assert_true(strlen(err) > 0);
    /* levels whose tables cannot fit the cap with enough bands: refused by name, before any table */
    {
        qtool_luminaire l16;
        assert_int_equal(qtool_luminaire_synthetic(16, &l16), 0);
        const qtool_luminaire_spots_opts huge = {.n = 256, .tol = 0.3}; /* 85 groups of 256^2 */
        err[0] = 0;
        assert_int_equal(qtool_luminaire_spots_build(&l16, pos, &huge, &b, err, sizeof err), -1);
        assert_non_null(strstr(err, "hierarchy"));
        qtool_luminaire_free(&l16);
    }
    /* a tolerance so small that no pixel reaches a coarser level: the full sum (and no cast beyond
     * uint64 under UBSan's float-cast-overflow) */
    const qtool_luminaire_spots_opts tiny = {.n = 64, .tol = 1e-300};
    assert_int_equal(qtool_luminaire_spots_build(&l, pos, &tiny, &b, err, sizeof err), 0);
    ground(&b, 0.4, 1.0, n, fb);
    assert_memory_equal(fa, fb, sizeof(double) * nv);
    qtool_luminaire_spots_free(&b);
    /* tol > 0: the passes one at a time still sum to the full (level 0) sum */
    const qtool_luminaire_spots_opts o1 = {.n = 64, .tol = 0.25};
    assert_int_equal(qtool_luminaire_spots_build(&l, pos, &o1, &b, err, sizeof err), 0);
    assert_int_equal(b.nlevel, 3);
    assert_int_equal(b.nband, QTOOL_LUMINAIRE_BANDS);
    assert_true(b.total > b.count);
    {
        const uint32_t m = 32;
        int32_t base[3 * 32 * 4], pts[3 * 32];
        int64_t s1[3 * 32] = {0}, s2[3 * 32] = {0}, *ws = malloc(qtool_luminaire_span_ws_size(m));
        assert_non_null(ws);
        for (uint32_t i = 0; i < m; ++i) {
            pts[3 * i] = pos[0] + (int32_t)(i * 4000) - 64000, pts[3 * i + 1] = pos[1] + 3000, pts[3 * i + 2] = 0;
            for (uint32_t k = 0; k < 12; ++k)
                base[3 * ((k / 3) * m + i) + k % 3] = (int32_t)(30000 + 997 * k + 31 * i);
        }
        qtool_luminaire_spots_span(&a, base, pts, m, s1, ws);
        for (uint32_t j = 0; j < b.count; ++j)
            qtool_luminaire_spot_pass(&b, j, base, pts, m, s2, ws);
        assert_memory_equal(s1, s2, sizeof s1);
        free(ws);
    }
    qtool_luminaire_spots_free(&b);
    qtool_luminaire_spots_free(&a);
    qtool_luminaire_free(&l);
    /* random sources at random depths (0.3 .. 3 lamp sizes): the hierarchy against the full sum */
    uint64_t x = 0xD1B54A32D192ED03u;
    for (int r = 0; r < 4; ++r) {
        x ^= x << 13, x ^= x >> 7, x ^= x << 17;
        random_source(r % 2 ? 16 : 8, x, &l);
        const double hgt = QTOOL_LUMINAIRE_SIZE * (0.3 + (double)(x % 1000u) / 1000.0 * 2.7), half = 2 * hgt + 0.2;
        const int32_t p2[3] = {0, 0, (int32_t)lround(hgt * 65536)};
        const double tols[2] = {0.1, 0.25};
        assert_int_equal(qtool_luminaire_spots_make(&l, p2, 64, 0, &a, err, sizeof err), 0);
        ground(&a, hgt, half, n, fa);
        double peak = 0;
        for (size_t i = 0; i < nv; ++i)
            peak = fa[i] > peak ? fa[i] : peak;
        for (int t = 0; t < 2; ++t) {
            const qtool_luminaire_spots_opts ot = {.n = 64, .tol = tols[t]};
            assert_int_equal(qtool_luminaire_spots_build(&l, p2, &ot, &b, err, sizeof err), 0);
            ground(&b, hgt, half, n, fb);
            double se = 0, worst = 0;
            for (size_t i = 0; i < nv; ++i) {
                se += (fb[i] - fa[i]) * (fb[i] - fa[i]);
                worst = fabs(fb[i] - fa[i]) > worst ? fabs(fb[i] - fa[i]) : worst;
            }
            double db = se > 0 ? 10 * log10(peak * peak / (se / (double)nv)) : 200;
            print_message("grid %u, %.2f lamp sizes, tol %g: %.2f dB against the full sum, worst %.4f of the peak\n",
                          l.nx, hgt / QTOOL_LUMINAIRE_SIZE, tols[t], db, worst / peak);
            assert_true(db >= 52); /* uncorrected: 45.8 .. 53.8 dB, worst up to 0.048 */
            assert_true(worst <= 0.025 * peak);
            qtool_luminaire_spots_free(&b);
        }
        qtool_luminaire_spots_free(&a);
        qtool_luminaire_free(&l);
    }
    free(fa), free(fb);
}

static void test_cli(void **state)
{
    (void)state;
    need_qibl();
    const char *q = at("s.qnf"), *x = at("x.png"), *g = at("g.qibl");
    assert_int_equal(run("luminaire", "capture", "builtin", "--out", q, "--grid", "4", "--res", "8", NULL), 0);
    assert_int_equal(run("luminaire", "info", q, NULL), 0);
    assert_non_null(strstr(out_text(), "grid 4x4 spacing 0.1\n"));
    assert_non_null(strstr(out_text(), "supports 16 dark 8\n"));
    assert_int_equal(run("gen", "-o", g, "--size", "64x16", "--k", "9", "--lut-size", "8", NULL), 0);
    assert_int_equal(run("luminaire", "render", g, q, "--at", "0", "1", "-0.5", "--out", x, NULL), 0);
    assert_int_equal(access(x, F_OK), 0);
    assert_int_equal(run("luminaire", "render", g, q, "--at", "0", "1", "-0.5", "--far", "--out", at("f.png"), NULL),
                     0);
    assert_non_null(strstr(out_text(), "1 far-field lamp"));
    /* refusals: bad arguments (2), a bad file (1), nothing written */
    const char *y = at("y.png");
    assert_int_equal(run("luminaire", NULL), 2);
    assert_int_equal(run("luminaire", "frob", NULL), 2);
    assert_int_equal(run("luminaire", "capture", "builtin", NULL), 2);
    assert_int_equal(run("luminaire", "capture", "builtin", "--out", at("z.qnf"), "--grid", "65", NULL), 2);
    assert_int_equal(run("luminaire", "capture", "builtin", "--out", at("z.qnf"), "--basis", "sinc", NULL), 2);
    assert_int_equal(access(at("z.qnf"), F_OK), -1);
    assert_int_equal(run("luminaire", "info", NULL), 2);
    assert_int_equal(run("luminaire", "info", at("missing.qnf"), NULL), 1);
    assert_int_equal(run("luminaire", "render", g, q, "--out", y, NULL), 2);
    assert_int_equal(run("luminaire", "render", g, q, "--at", "0", "0", "nan", "--out", y, NULL), 2);
    assert_int_equal(run("luminaire", "render", g, q, "--at", "0", "0", "1", "--out", y, "--table", "1", NULL), 2);
    assert_int_equal(run("luminaire", "render", g, g, "--at", "0", "0", "1", "--out", y, NULL), 1);
    assert_int_equal(run("luminaire", "render", q, q, "--at", "0", "0", "1", "--out", y, NULL), 1);
    assert_int_equal(access(y, F_OK), -1);
    assert_int_equal(run("luminaire", "study", "--frob", NULL), 2);
    assert_int_equal(run("luminaire", "passes", "--size", "7", NULL), 2);
    assert_int_equal(run("luminaire", "passes", "--size", "16", NULL), 0);
    assert_non_null(strstr(out_text(), "RESULT luminaire.passes64_srgbe2_vs_float_max8 "));
    assert_non_null(strstr(out_text(), "RESULT luminaire.passes256_srgbe_vs_core_max8 "));
    /* the README's picture: three images side by side; refusals write nothing */
    assert_int_equal(run("luminaire", "picture", "--out", at("p.png"), "--size", "16", NULL), 0);
    assert_non_null(strstr(out_text(), "56x16 (near field | truth | far field"));
    assert_int_equal(access(at("p.png"), F_OK), 0);
    assert_int_equal(run("luminaire", "picture", "--out", at("p2.png"), "--height", "0", NULL), 2);
    assert_int_equal(run("luminaire", "picture", NULL), 2);
    assert_int_equal(access(at("p2.png"), F_OK), -1);
}

/* luminaire render --gles: the spotlights evaluated on the GPU (EGL; skipped without it unless
 * QIBL_REQUIRE_GLES=1) on a lit courtyard frame: the RESULT lines within tests/gles2_test.c's bounds
 * (max 2, mean < 0.1 of 255) on both paths, the PNG still the soft frame's bytes; --frames 0 refused
 * with nothing written */
static void test_cli_gles(void **state)
{
    (void)state;
    need_qibl();
    const char *g = at("g.qibl"), *q = at("s.qnf"), *x = at("x.png"), *y = at("y.png");
    assert_int_equal(run("gen", "-o", g, "--size", "96x24", "--k", "9", "--lut-size", "8", NULL), 0);
    assert_int_equal(run("luminaire", "capture", "builtin", "--out", q, "--grid", "6", "--res", "8", NULL), 0);
    assert_int_equal(run("luminaire", "render", g, q, "--at", "0", "2", "-1", "--exposure", "4", "--out", y, "--gles",
                         "--frames", "0", NULL),
                     2);
    assert_int_equal(access(y, F_OK), -1);
    /* --gles draws every spotlight, and its soft frame (the PNG) is then the full sum: --tol 0's */
    assert_int_equal(run("luminaire", "render", g, q, "--at", "0", "2", "-1", "--exposure", "4", "--tol", "0", "--out",
                         x, NULL),
                     0);
    int w, h, fr, lit = 0;
    uint8_t *px = NULL, *py = NULL;
    char err[256];
    assert_int_equal(qtool_png_read_rgb8(x, &w, &h, &fr, &px, err, sizeof err), 0);
    for (size_t i = 0; i < (size_t)w * h * 3; ++i)
        lit += px[i] >= 16;
    assert_true(lit >= 60); /* the comparison is not between two black frames */
    if (run("luminaire", "render", g, q, "--at", "0", "2", "-1", "--exposure", "4", "--out", y, "--gles", "--frames",
            "1", NULL) != 0) {
        const char *r = getenv("QIBL_REQUIRE_GLES");
        char *e = text(errlog);
        if (r != NULL && strcmp(r, "1") == 0)
            fail_msg("QIBL_REQUIRE_GLES=1 and luminaire render --gles failed: %s", e);
        print_message("SKIP luminaire render --gles: %s", e);
        free(e), free(px);
        skip();
    }
    for (int core = 0; core < 2; ++core) {
        assert_int_equal(run("luminaire", "render", g, q, "--at", "0", "2", "-1", "--exposure", "4", "--out", y,
                             "--gles", "--frames", "1", core ? "--gles-core" : NULL, NULL),
                         0);
        const char *o = out_text(), *m = strstr(o, "RESULT luminaire.gles_vs_soft_max "),
                   *a = strstr(o, "RESULT luminaire.gles_vs_soft_mean ");
        assert_non_null(m), assert_non_null(a);
        assert_non_null(strstr(o, "RESULT luminaire.gles_pass_ms "));
        assert_non_null(strstr(o, "RESULT luminaire.gles_frame_ms "));
        const int mx = atoi(m + strlen("RESULT luminaire.gles_vs_soft_max "));
        const double mean = atof(a + strlen("RESULT luminaire.gles_vs_soft_mean "));
        printf("  luminaire render --gles%s: against the soft frame max %d, mean %.4f\n", core ? " --gles-core" : "",
               mx, mean);
        assert_true(mx <= 2 && mean < 0.1);
        assert_int_equal(qtool_png_read_rgb8(y, &w, &h, &fr, &py, err, sizeof err), 0);
        assert_memory_equal(px, py, (size_t)w * h * 3);
        free(py);
    }
    free(px);
}

/* qtool_luminaire_relight (anchors' spans only where a spotlight reaches) against the same frame
 * computed over whole rows here; a one-support source near and far give the same bytes */
static void test_relight_frame(void **state)
{
    (void)state;
    need_qibl();
    const char *g = at("g.qibl"), *q = at("s.qnf"), *q1 = at("one.qnf");
    assert_int_equal(run("gen", "-o", g, "--size", "96x24", "--k", "9", "--lut-size", "8", NULL), 0);
    assert_int_equal(run("luminaire", "capture", "builtin", "--out", q, "--grid", "6", "--res", "8", NULL), 0);
    uint8_t *bytes;
    size_t n;
    char err[256];
    assert_int_equal(qtool_io_read_asset(g, &bytes, &n, err, sizeof err), 0);
    qibl_asset_t a;
    qibl_shmaps_t mp;
    qibl_pmap_t pm;
    assert_int_equal(qibl_asset_open(&a, bytes, n), QIBL_OK);
    assert_int_equal(qibl_asset_point_shmaps(&a, &mp), QIBL_OK);
    assert_int_equal(qibl_asset_pmap(&a, &pm), QIBL_OK);
    qtool_luminaire l;
    assert_int_equal(qtool_luminaire_read(q, &l), QTOOL_LUMINAIRE_OK);
    const int32_t pos[3] = {0, 65536, -32768};
    qtool_luminaire_spots s;
    assert_int_equal(qtool_luminaire_spots_make(&l, pos, 32, 0, &s, err, sizeof err), 0);
    const uint32_t w = mp.width, h = mp.height;
    uint8_t *got = malloc((size_t)w * h * 3), *want = malloc((size_t)w * h * 4);
    int32_t *row = malloc(sizeof(int32_t) * 3 * w * 4), *pts = malloc(sizeof(int32_t) * 3 * w), *o = malloc(12 * w);
    int64_t *acc = malloc(sizeof(int64_t) * 3 * w), *ws = malloc(qtool_luminaire_span_ws_size(w));
    size_t wsn = qibl_shmap_point_workspace_size(mp.k, w);
    void *pws = malloc(wsn);
    assert_true(got && want && row && pts && o && acc && ws && pws);
    qibl_status_t st;
    assert_int_equal(qtool_luminaire_relight(&s, &mp, &pm, NULL, 65536, 1, got, NULL, NULL, &st), 0);
    qibl_fb_desc_t fb = {.pixels = want, .width = w, .height = h, .format = QIBL_FB_RGBA8888, .srgb = 1,
                         .exposure = 65536};
    qibl_shmap_point_t pt[4];
    for (uint32_t k = 0; k < s.nanchor; ++k) {
        qibl_pointlight_t pl = {.pos = {s.anchor[k][0], s.anchor[k][1], s.anchor[k][2]}, .rgb = {65536, 65536, 65536},
                                .falloff = QIBL_FALLOFF_INV_DIST2, .filter = QIBL_POINT_POLY};
        assert_int_equal(qibl_shmap_point_prepare(&mp, &pm, NULL, &pl, &pt[k]), QIBL_OK);
    }
    size_t lit = 0;
    for (uint32_t y = 0; y < h; ++y) {
        for (uint32_t k = 0; k < s.nanchor; ++k)
            assert_int_equal(qibl_shmap_point_span(&pt[k], 0, y, w, row + (size_t)k * 3 * w, pws, wsn), QIBL_OK);
        for (uint32_t x = 0; x < w; ++x)
            qibl_pmap_point(&pm, x, y, pts + 3 * (size_t)x);
        memset(acc, 0, sizeof(int64_t) * 3 * w);
        qtool_luminaire_spots_span(&s, row, pts, w, acc, ws);
        for (size_t i = 0; i < (size_t)3 * w; ++i)
            o[i] = qtool_luminaire_q16(acc[i]), lit += o[i] > 0;
        assert_int_equal(qibl_fb_write_row(&fb, 0, y, w, o), QIBL_OK);
    }
    assert_true(lit > 0);
    for (size_t i = 0; i < (size_t)w * h; ++i)
        assert_memory_equal(got + 3 * i, want + 4 * i, 3);
    qtool_luminaire_spots_free(&s);
    qtool_luminaire_free(&l);
    free(got), free(want), free(row), free(pts), free(o), free(acc), free(ws), free(pws), free(bytes);
    /* one support: its lamp is the far field's */
    assert_int_equal(run("luminaire", "capture", "builtin", "--out", q1, "--grid", "1", "--res", "8", NULL), 0);
    assert_int_equal(run("luminaire", "render", g, q1, "--at", "0", "1", "-0.5", "--out", at("n.png"), NULL), 0);
    assert_non_null(strstr(out_text(), "96x24, 1 spotlights")); /* lit, not two black frames */
    assert_int_equal(run("luminaire", "render", g, q1, "--at", "0", "1", "-0.5", "--far", "--out", at("f.png"), NULL),
                     0);
    size_t nn = 0, nf = 0;
    uint8_t *pn = qtool_io_read_all(at("n.png"), &nn), *pf = qtool_io_read_all(at("f.png"), &nf);
    assert_true(pn && pf);
    assert_int_equal(nn, nf);
    assert_memory_equal(pn, pf, nn);
    free(pn), free(pf);
}

/* the built-in luminaire's shade written as an OBJ (its triangles, in its order) */
static void write_builtin_obj(const char *path)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    int nv = 0;
    const double H = 0.2, c = 0.1, lo = 0.002, hi = 0.2;
    /* each quad a, b, c, d as triangles (a, b, c) and (a, c, d) */
#define QUAD(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz)                                                    \
    do {                                                                                                      \
        fprintf(f, "v %.17g %.17g %.17g\nv %.17g %.17g %.17g\nv %.17g %.17g %.17g\nv %.17g %.17g %.17g\n",   \
                ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz);                                              \
        fprintf(f, "f %d %d %d\nf %d %d %d\n", nv + 1, nv + 2, nv + 3, nv + 1, nv + 3, nv + 4);                \
        nv += 4;                                                                                              \
    } while (0)
    for (int iy = 0; iy < 4; ++iy)
        for (int ix = 0; ix < 4; ++ix) {
            if (((ix + iy) & 1) == 0)
                continue;
            double x0 = -H + ix * c, y0 = -H + iy * c, x1 = x0 + c, y1 = y0 + c;
            QUAD(x0, y0, lo, x1, y0, lo, x1, y1, lo, x0, y1, lo);
        }
    const double cx[4] = {-H, H, H, -H}, cy[4] = {-H, -H, H, H};
    for (int k = 0; k < 4; ++k) {
        int t = (k + 1) & 3;
        QUAD(cx[k], cy[k], lo, cx[t], cy[t], lo, cx[t], cy[t], hi, cx[k], cy[k], hi);
    }
    QUAD(-H, -H, hi, H, -H, hi, H, H, hi, -H, H, hi);
#undef QUAD
    fclose(f);
}

/* capture from a mesh: the built-in shade as an OBJ with the built-in emitter gives the built-in
 * capture's bytes; a mesh below S and an emitter outside it are refused, nothing written */
static void test_capture_mesh(void **state)
{
    (void)state;
    need_qibl();
    const char *obj = at("shade.obj"), *a = at("a.qnf"), *b = at("b.qnf");
    write_builtin_obj(obj);
    assert_int_equal(run("luminaire", "capture", "builtin", "--out", a, "--grid", "4", "--res", "8", NULL), 0);
    assert_int_equal(run("luminaire", "capture", obj, "--emitter", "0.16", "0.08", "--out", b, "--grid", "4", "--res",
                         "8", NULL), 0);
    size_t na = 0, nb = 0;
    uint8_t *pa = qtool_io_read_all(a, &na), *pb = qtool_io_read_all(b, &nb);
    assert_true(pa && pb && na == nb);
    assert_memory_equal(pa, pb, na);
    free(pa), free(pb);
    /* defaults: the built-in proportions of the mesh's box, the same emitter here */
    assert_int_equal(run("luminaire", "capture", obj, "--out", b, "--grid", "4", "--res", "8", NULL), 0);
    pb = qtool_io_read_all(b, &nb);
    pa = qtool_io_read_all(a, &na);
    assert_true(pa && pb && na == nb);
    qtool_luminaire la, lb;
    assert_int_equal(qtool_luminaire_decode(pa, na, &la), QTOOL_LUMINAIRE_OK);
    assert_int_equal(qtool_luminaire_decode(pb, nb, &lb), QTOOL_LUMINAIRE_OK);
    for (size_t k = 0; k < (size_t)16 * 64 * 3; ++k)
        assert_true(fabs(la.tex[k] - lb.tex[k]) <= 1e-4 * QTOOL_LUMINAIRE_LE);
    qtool_luminaire_free(&la), qtool_luminaire_free(&lb);
    free(pa), free(pb);
    FILE *f = fopen(at("low.obj"), "w");
    assert_non_null(f);
    fputs("v 0 0 0.1\nv 1 0 0.1\nv 0 1 -0.1\nf 1 2 3\n", f);
    fclose(f);
    const char *z = at("z.qnf");
    assert_int_equal(run("luminaire", "capture", at("low.obj"), "--out", z, NULL), 1);
    assert_int_equal(run("luminaire", "capture", obj, "--emitter", "0.5", "0.08", "--out", z, NULL), 1);
    assert_int_equal(run("luminaire", "capture", obj, "--emitter", "0.1", "0.3", "--out", z, NULL), 1);
    assert_int_equal(run("luminaire", "capture", at("missing.obj"), "--out", z, NULL), 1);
    assert_int_equal(run("luminaire", "capture", "builtin", "--emitter", "0.1", "0.05", "--out", z, NULL), 2);
    assert_int_equal(access(z, F_OK), -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hand_made_file),
        cmocka_unit_test(test_every_error),
        cmocka_unit_test_setup_teardown(test_file_io, setup, teardown),
        cmocka_unit_test(test_capture),
        cmocka_unit_test(test_near_field),
        cmocka_unit_test(test_passes),
        cmocka_unit_test(test_isqrt_twin),
        cmocka_unit_test(test_span_bytes),
        cmocka_unit_test(test_lookup_twin),
        cmocka_unit_test(test_hierarchy),
        cmocka_unit_test_setup_teardown(test_cli, setup, teardown),
        cmocka_unit_test_setup_teardown(test_cli_gles, setup, teardown),
        cmocka_unit_test_setup_teardown(test_relight_frame, setup, teardown),
        cmocka_unit_test_setup_teardown(test_capture_mesh, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
