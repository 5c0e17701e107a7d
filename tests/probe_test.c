/*
 * probe_test.c - qibl/probe.h: SH projection of lat-long probes against the double reference
 * (tools/ref/probe_ref.c) in every pixel format and size from 1 x 1 (folded and direct paths), the
 * stated error bound, rows in any order, hard cases (poles, a single bright pixel, an all-zero probe,
 * NaN / Inf / negative pixels, the largest size at the largest pixel values), irradiance and windows,
 * lights and sun plus sky into a qibl_shlight_t, rotation against re-projection (an exact quarter
 * turn of the pixel grid and an arbitrary rotation of a smooth probe), every error status, goldens,
 * and the real probes of ../shared/fixtures/probes when present (SKIP line otherwise).
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "qibl/isa.h"
#include "qibl/probe.h"
#include "golden/check.h"
#include "io/hdr.h"
#include "io/isa_env.h"
#include "ref/probe_ref.h"
#include "ref/sh_ref.h"
#include "testutil.h"

#define Q30 1073741824.0

/* ---- helpers -------------------------------------------------------------------------------- */

typedef struct {
    int w, h;
    uint8_t *rgbe;   /* RGBE bytes */
    double *d;       /* the same values */
} probe;

static void probe_free(probe *p)
{
    free(p->rgbe), free(p->d);
}

static void fill_double(probe *p)
{
    p->d = malloc(sizeof *p->d * 3 * (size_t)p->w * (size_t)p->h);
    assert_non_null(p->d);
    for (size_t i = 0; i < (size_t)p->w * (size_t)p->h; ++i)
        for (int c = 0; c < 3; ++c)
            p->d[3 * i + (size_t)c] = p->rgbe[4 * i + 3] ? ldexp(p->rgbe[4 * i + (size_t)c], p->rgbe[4 * i + 3] - 136) : 0.0;
}

/* random RGBE: exponents e0 .. e0 + span, 1 in 8 pixels black, optionally one pixel 2^20 brighter */
static probe random_probe(uint64_t seed, int w, int h, int e0, int span, int sun)
{
    probe p = {w, h, malloc(4 * (size_t)w * (size_t)h), NULL};
    assert_non_null(p.rgbe);
    tu_rng r = {seed};
    for (size_t i = 0; i < (size_t)w * (size_t)h; ++i) {
        uint32_t n = tu_u32(&r);
        p.rgbe[4 * i] = (uint8_t)n, p.rgbe[4 * i + 1] = (uint8_t)(n >> 8) | 128u, p.rgbe[4 * i + 2] = (uint8_t)(n >> 16);
        p.rgbe[4 * i + 3] = (n >> 29) == 0 ? 0 : (uint8_t)(e0 + (int)(tu_u32(&r) % (uint32_t)(span + 1)));
    }
    if (sun) {
        size_t i = tu_u32(&r) % ((size_t)w * (size_t)h);
        p.rgbe[4 * i] = 250, p.rgbe[4 * i + 1] = 240, p.rgbe[4 * i + 2] = 200, p.rgbe[4 * i + 3] = (uint8_t)(e0 + span + 20);
    }
    fill_double(&p);
    return p;
}

static qibl_lightprobe_image_t image(const void *px, int w, int h, qibl_lightprobe_format_t f, int32_t fb)
{
    qibl_lightprobe_image_t img;
    memset(&img, 0, sizeof img);
    img.pixels = px, img.width = (uint32_t)w, img.height = (uint32_t)h, img.format = f, img.frac_bits = fb;
    return img;
}

static qibl_status_t project(const qibl_lightprobe_image_t *img, int bands, const qibl_probe_sh_opts_t *o,
                             qibl_probe_coeffs_t *c)
{
    size_t n = qibl_probe_sh_workspace_size(img->width, img->height);
    void *ws = malloc(n ? n : 1);
    assert_non_null(ws);
    qibl_status_t st = qibl_probe_sh_project(img, bands, o, ws, n, c);
    free(ws);
    return st;
}

/* B' for RGBE: M_v = 2^(emax_v - 128), the row bound the RGBE path uses (probe.h) */
static double row_bound_rgbe(const uint8_t *px, int w, int h)
{
    double b = 0.0;
    for (int v = 0; v < h; ++v) {
        int emax = 0;
        for (int u = 0; u < w; ++u) {
            const uint8_t *q = px + 4 * ((size_t)v * (size_t)w + (size_t)u);
            if ((q[0] | q[1] | q[2]) && q[3] > emax)
                emax = q[3];
        }
        if (emax)
            b += w * ldexp(1.0, emax - 128) * (2.0 * M_PI / w) * (M_PI / h) * sin((v + 0.5) * M_PI / h);
    }
    return b;
}

/* B' = sum_v W (max over the row's channels) dw_v: the quantity the error bound is stated in */
static double row_bound(const double *d, int w, int h)
{
    double b = 0.0;
    for (int v = 0; v < h; ++v) {
        double mx = 0.0;
        for (int i = 0; i < 3 * w; ++i)
            mx = fmax(mx, d[3 * (size_t)v * (size_t)w + (size_t)i]);
        b += w * mx * (2.0 * M_PI / w) * (M_PI / h) * sin((v + 0.5) * M_PI / h);
    }
    return b;
}

typedef struct {
    double abs, rel_max, bound; /* worst |err|, worst |err| / max |ref|, the stated bound */
} errs;

/* c against ref * factor[l]; the stated bound: 2^-26 B' + 2^-29 max |ref| */
static errs compare(const qibl_probe_coeffs_t *c, double ref[3][25], const double f[5], int bands, double bprime)
{
    errs e = {0, 0, 0};
    double mx = 0.0;
    for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i < bands * bands; ++i)
            mx = fmax(mx, fabs(ref[ch][i] * f[(int)sqrt((double)i)]));
    for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i < QIBL_SH_MAX_COUNT; ++i) {
            double want = i < bands * bands ? ref[ch][i] * f[(int)sqrt((double)i)] : 0.0;
            e.abs = fmax(e.abs, fabs(ldexp(c->c[ch][i], c->exp) - want));
        }
    e.rel_max = mx > 0 ? e.abs / mx : e.abs;
    e.bound = ldexp(bprime, -26) + ldexp(mx, -29);
    return e;
}

static const double ones[5] = {1, 1, 1, 1, 1};

/* projects p (RGBE) and checks it against the reference within the bound; returns the error */
static errs check_probe(const probe *p, int bands)
{
    qibl_lightprobe_image_t img = image(p->rgbe, p->w, p->h, QIBL_LIGHTPROBE_RGBE, 0);
    qibl_probe_coeffs_t c;
    assert_int_equal(project(&img, bands, NULL, &c), QIBL_OK);
    assert_int_equal(c.bands, bands);
    double ref[3][25];
    qtool_ref_probe_sh(p->w, p->h, p->d, bands, ref);
    errs e = compare(&c, ref, ones, bands, row_bound_rgbe(p->rgbe, p->w, p->h));
    if (e.abs > e.bound)
        printf("probe %dx%d bands %d: error %.3e above the bound %.3e\n", p->w, p->h, bands, e.abs, e.bound);
    assert_true(e.abs <= e.bound);
    return e;
}

/* ---- against the reference ------------------------------------------------------------------ */

static void test_matches_reference(void **state)
{
    (void)state;
    static const int sz[][2] = {{1, 1}, {2, 1}, {1, 5}, {3, 7}, {4, 2}, {8, 4}, {30, 15}, {63, 32}, {64, 32}, {256, 128}};
    double worst = 0.0;
    for (size_t i = 0; i < sizeof sz / sizeof sz[0]; ++i)
        for (int bands = 1; bands <= 5; ++bands) {
            probe p = random_probe(10 + i, sz[i][0], sz[i][1], 110, 30, (int)(i & 1));
            worst = fmax(worst, check_probe(&p, bands).rel_max);
            probe_free(&p);
        }
    printf("probe: random probes 1x1 .. 256x128, bands 1..5: max |err| / max |L| = %.3e\n", worst);
}

/* every pixel format: the same values as RGBE, binary32 (exact: bit-identical results), int32 with
 * 12 fraction bits and sRGBE (both carry their own quantisation, compared with their own doubles) */
static void test_formats(void **state)
{
    (void)state;
    const int w = 32, h = 16;
    probe p = random_probe(3, w, h, 120, 10, 0); /* int32 Q12 holds these values */
    size_t n = (size_t)w * h;
    uint32_t *f32 = malloc(12 * n);
    int32_t *i32 = malloc(12 * n);
    uint8_t *sr = malloc(4 * n);
    double *di = malloc(sizeof *di * 3 * n), *ds = malloc(sizeof *ds * 3 * n);
    assert_true(f32 && i32 && sr && di && ds);
    for (size_t i = 0; i < 3 * n; ++i) {
        float f = (float)p.d[i];
        memcpy(&f32[i], &f, 4);
        i32[i] = (int32_t)lrint(p.d[i] * 4096.0);
        di[i] = i32[i] / 4096.0;
    }
    for (size_t i = 0; i < n; ++i) { /* sRGBE bytes: X in 128..255, E in 100..130 */
        sr[4 * i] = (uint8_t)(128 + (i * 7) % 128), sr[4 * i + 1] = (uint8_t)(128 + (i * 13) % 128);
        sr[4 * i + 2] = (uint8_t)(128 + (i * 29) % 128), sr[4 * i + 3] = (uint8_t)(100 + i % 31);
        for (int c = 0; c < 3; ++c) {
            int x = sr[4 * i + (size_t)c];
            ds[3 * i + (size_t)c] = x > 128 ? ldexp(2.0 * x - 255.0, sr[4 * i + 3] - 126) / 510.0 : 0.0;
        }
    }
    qibl_probe_coeffs_t a, b, c, d;
    qibl_lightprobe_image_t img = image(p.rgbe, w, h, QIBL_LIGHTPROBE_RGBE, 0);
    assert_int_equal(project(&img, 5, NULL, &a), QIBL_OK);
    img = image(f32, w, h, QIBL_LIGHTPROBE_LINEAR_F32, 0);
    assert_int_equal(project(&img, 5, NULL, &b), QIBL_OK);
    assert_memory_equal(&a, &b, sizeof a); /* the same values, the same per-row quantisation */
    img = image(i32, w, h, QIBL_LIGHTPROBE_LINEAR_I32, 12);
    assert_int_equal(project(&img, 5, NULL, &c), QIBL_OK);
    double ref[3][25];
    qtool_ref_probe_sh(w, h, di, 5, ref);
    errs e = compare(&c, ref, ones, 5, row_bound(di, w, h));
    assert_true(e.abs <= e.bound);
    img = image(sr, w, h, QIBL_LIGHTPROBE_SRGBE, 0);
    assert_int_equal(project(&img, 5, NULL, &d), QIBL_OK);
    qtool_ref_probe_sh(w, h, ds, 5, ref);
    e = compare(&d, ref, ones, 5, row_bound(ds, w, h));
    printf("probe: formats: RGBE = binary32 bit for bit; int32 Q12 and sRGBE within the bound (sRGBE %.3e)\n", e.rel_max);
    assert_true(e.abs <= e.bound);
    free(f32), free(i32), free(sr), free(di), free(ds);
    probe_free(&p);
}

/* Widths that take every part of the vector paths (fewer than 8 column pairs, exactly 8, several
 * steps and flushes, a scalar tail, an odd quarter width with its middle column) and rows with black
 * pixels (E = 0, mantissas set), unlit pixels of huge exponent and pixels far below the row's top:
 * RGBE (vector scan and conversion where QIBL_CONFIG_SIMD has them) and the same values as binary32
 * (the scalar decoder) give the same bits. The folded sums are checked across paths by the golden
 * probe_sh_widths, which every flavour and port must reproduce. */
static void test_vector_widths(void **state)
{
    (void)state;
    static const int ws[] = {8, 16, 64, 68, 192, 200, 204, 1028};
    for (size_t k = 0; k < sizeof ws / sizeof ws[0]; ++k) {
        const int w = ws[k], h = 5;
        probe p = random_probe(40 + k, w, h, 100, 40, 1);
        for (int i = 3; i < w * h; i += 11) /* unlit, exponent above every lit one */
            p.rgbe[4 * i] = p.rgbe[4 * i + 1] = p.rgbe[4 * i + 2] = 0, p.rgbe[4 * i + 3] = 255, p.d[3 * i] = 0.0,
            p.d[3 * i + 1] = p.d[3 * i + 2] = 0.0;
        uint32_t *f32 = malloc(12 * (size_t)w * h);
        assert_non_null(f32);
        for (size_t i = 0; i < 3 * (size_t)w * h; ++i) {
            float f = (float)p.d[i]; /* m 2^(E - 136), E in 100..160: exact */
            memcpy(&f32[i], &f, 4);
        }
        qibl_probe_coeffs_t a, b;
        memset(&a, 0x5A, sizeof a);
        memset(&b, 0x3C, sizeof b);
        qibl_lightprobe_image_t img = image(p.rgbe, w, h, QIBL_LIGHTPROBE_RGBE, 0);
        assert_int_equal(project(&img, 5, NULL, &a), QIBL_OK);
        img = image(f32, w, h, QIBL_LIGHTPROBE_LINEAR_F32, 0);
        assert_int_equal(project(&img, 5, NULL, &b), QIBL_OK);
        assert_memory_equal(&a, &b, sizeof a);
        free(f32);
        probe_free(&p);
    }
}

/* Fewer bands sum only the Fourier orders they need (m <= bands - 1, each number of orders its own
 * copy of the folded kernel): the accumulators of coefficients i < bands^2 are bit for bit those of
 * a 5-band projection of the same rows, at widths that take the folded vector steps, their scalar
 * tail, an odd quarter width, the direct path (W % 4 != 0, even and odd) and the even-width trig
 * table built from W/2 + 1 sines. */
static void test_band_orders(void **state)
{
    (void)state;
    static const int ws[] = {8, 30, 31, 64, 68, 200, 204, 1028};
    for (size_t k = 0; k < sizeof ws / sizeof ws[0]; ++k) {
        const int w = ws[k], h = 4;
        probe p = random_probe(70 + k, w, h, 110, 30, 1);
        const size_t n = qibl_probe_sh_workspace_size((uint32_t)w, (uint32_t)h);
        void *w5 = malloc(n), *wb = malloc(n);
        assert_non_null(w5);
        assert_non_null(wb);
        qibl_probe_sh_t p5, pb;
        assert_int_equal(qibl_probe_sh_begin(&p5, (uint32_t)w, (uint32_t)h, QIBL_LIGHTPROBE_RGBE, 0, 5, w5, n), QIBL_OK);
        for (uint32_t v = 0; v < (uint32_t)h; ++v)
            assert_int_equal(qibl_probe_sh_add_row(&p5, v, p.rgbe + 4 * (size_t)v * (size_t)w), QIBL_OK);
        for (int bands = 1; bands <= 4; ++bands) {
            assert_int_equal(qibl_probe_sh_begin(&pb, (uint32_t)w, (uint32_t)h, QIBL_LIGHTPROBE_RGBE, 0, bands, wb, n),
                             QIBL_OK);
            for (uint32_t v = 0; v < (uint32_t)h; ++v)
                assert_int_equal(qibl_probe_sh_add_row(&pb, v, p.rgbe + 4 * (size_t)v * (size_t)w), QIBL_OK);
            for (size_t c = 0; c < 3; ++c)
                for (size_t i = 0; i < (size_t)(bands * bands); ++i)
                    assert_memory_equal(pb.acc + (c * 25 + i) * QIBL_PROBE_ACC_LIMBS,
                                        p5.acc + (c * 25 + i) * QIBL_PROBE_ACC_LIMBS, 4 * QIBL_PROBE_ACC_LIMBS);
        }
        free(w5), free(wb);
        probe_free(&p);
    }
}

/* Every kernel set this CPU runs (qtool_isa_force: scalar, SSE2, AVX2, and AVX-512 whose RGBE fold
 * converts the bytes itself, 16 column pairs a step) leaves the scalar set's accumulators bit for bit:
 * random rows with black pixels (E = 0, mantissas set), unlit ones of exponent 255, E = 1 and lit
 * E = 255 pixels (a row whose scale pushes the rest far down), at widths of whole 16-pair steps, of a
 * scalar tail of pairs, of an odd quarter width (its middle column), W % 4 != 0 (the direct path),
 * for 1 to 5 bands. */
static void test_every_isa_bits(void **state)
{
    (void)state;
    static const int ws[] = {4, 8, 60, 64, 68, 124, 128, 132, 192, 260, 516, 1024, 1028, 30, 31, 66};
    const uint32_t have = qibl_isa_available();
    const size_t nacc = 3u * 25u * QIBL_PROBE_ACC_LIMBS;
    uint32_t *ref = malloc(4 * nacc);
    assert_non_null(ref);
    for (size_t k = 0; k < sizeof ws / sizeof ws[0]; ++k) {
        const int w = ws[k], h = 4;
        uint8_t *px = malloc(4 * (size_t)w * h);
        assert_non_null(px);
        tu_rng r = {900 + k};
        for (int i = 0; i < w * h; ++i) {
            const uint32_t n = tu_u32(&r), v = (uint32_t)(i / w), kind = (n >> 24) & 7u;
            uint8_t *q = px + 4 * (size_t)i;
            q[0] = (uint8_t)n, q[1] = (uint8_t)(n >> 8), q[2] = (uint8_t)(n >> 16);
            q[3] = (uint8_t)(100u + (tu_u32(&r) % 60u)); /* row 0: lit in 100..159 */
            if (kind == 0)
                q[3] = 0; /* black, mantissas set */
            else if (kind == 1)
                q[0] = q[1] = q[2] = 0, q[3] = 255; /* unlit, exponent above every lit one */
            else if (kind == 2 && v >= 1)
                q[3] = 1;
            else if (kind == 3 && v == 2 && (n & 0x10000000u))
                q[3] = 255; /* lit at the top exponent: the row's others shift far right */
            else if (v == 3)
                q[3] = (uint8_t)(120u + (n >> 29)); /* a narrow range: every bit kept */
        }
        for (int bands = 1; bands <= 5; ++bands) {
            int first = -1;
            for (unsigned isa = 0; isa < QIBL_ISA_COUNT; ++isa) {
                if (!(have & QIBL_ISA_BIT(isa)))
                    continue;
                qtool_isa_force(QIBL_ISA_BIT(isa));
                const size_t n = qibl_probe_sh_workspace_size((uint32_t)w, (uint32_t)h);
                void *wsp = malloc(n);
                assert_non_null(wsp);
                qibl_probe_sh_t ps;
                assert_int_equal(qibl_probe_sh_begin(&ps, (uint32_t)w, (uint32_t)h, QIBL_LIGHTPROBE_RGBE, 0, bands, wsp, n),
                                 QIBL_OK);
                for (uint32_t v = 0; v < (uint32_t)h; ++v)
                    assert_int_equal(qibl_probe_sh_add_row(&ps, v, px + 4 * (size_t)v * (size_t)w), QIBL_OK);
                if (first < 0) /* scalar where the build dispatches; a compile-time build has one set */
                    memcpy(ref, ps.acc, 4 * nacc), first = (int)isa;
                else if (memcmp(ref, ps.acc, 4 * nacc) != 0)
                    fail_msg("width %d bands %d: %s accumulators differ from %s", w, bands,
                             qibl_isa_name((qibl_isa_t)isa), qibl_isa_name((qibl_isa_t)first));
                free(wsp);
            }
        }
        qtool_isa_force(0);
        free(px);
    }
    free(ref);
}

/* rows in any order give the same bits (exact integer accumulation) */
static void test_row_order(void **state)
{
    (void)state;
    const int w = 48, h = 24;
    probe p = random_probe(21, w, h, 100, 40, 1);
    size_t n = qibl_probe_sh_workspace_size(w, h);
    void *ws = malloc(n);
    assert_non_null(ws);
    qibl_probe_coeffs_t first, c;
    tu_rng r = {8};
    for (int trial = 0; trial < 6; ++trial) {
        int order[24];
        for (int v = 0; v < h; ++v)
            order[v] = v;
        for (int v = h - 1; trial && v > 0; --v) { /* trial 0: top to bottom, then shuffles */
            int j = (int)(tu_u32(&r) % (uint32_t)(v + 1)), t = order[v];
            order[v] = order[j], order[j] = t;
        }
        qibl_probe_sh_t ps;
        assert_int_equal(qibl_probe_sh_begin(&ps, w, h, QIBL_LIGHTPROBE_RGBE, 0, 5, ws, n), QIBL_OK);
        for (int k = 0; k < h; ++k)
            assert_int_equal(qibl_probe_sh_add_row(&ps, (uint32_t)order[k], p.rgbe + 4 * (size_t)w * (size_t)order[k]),
                             QIBL_OK);
        assert_int_equal(qibl_probe_sh_finish(&ps, NULL, trial ? &c : &first), QIBL_OK);
        if (trial)
            assert_memory_equal(&c, &first, sizeof c);
    }
    free(ws);
    probe_free(&p);
}

/* ---- hard cases ----------------------------------------------------------------------------- */

/* a single bright pixel: L = P Y(w) dw, the same as a directional light of colour P dw */
static void test_single_bright_pixel(void **state)
{
    (void)state;
    const int w = 40, h = 20;
    static const int at[][2] = {{0, 0}, {39, 19}, {13, 7}, {20, 10}, {5, 19}};
    for (size_t k = 0; k < sizeof at / sizeof at[0]; ++k) {
        probe p = {w, h, calloc(4 * (size_t)w * h, 1), NULL};
        uint8_t *q = p.rgbe + 4 * ((size_t)at[k][1] * w + (size_t)at[k][0]);
        q[0] = 255, q[1] = 128, q[2] = 1, q[3] = 200; /* 2^64 bright */
        fill_double(&p);
        check_probe(&p, 5);
        /* against qibl_shlight_add_dir with the pixel's direction and P dw (scaled into Q16.16) */
        double t = (at[k][1] + 0.5) * M_PI / h, ph = (at[k][0] + 0.5) * 2.0 * M_PI / w;
        double dw = (2.0 * M_PI / w) * (M_PI / h) * sin(t);
        qibl_shlight_t a, b;
        assert_int_equal(qibl_shlight_init(&a, 25), QIBL_OK);
        assert_int_equal(qibl_shlight_init(&b, 25), QIBL_OK);
        qibl_lightprobe_image_t img = image(p.rgbe, w, h, QIBL_LIGHTPROBE_RGBE, 0);
        qibl_probe_sh_opts_t o = {0, QIBL_PROBE_WINDOW_NONE, -64 + 8}; /* 2^64 -> 2^8 */
        size_t n = qibl_probe_sh_workspace_size(w, h);
        void *ws = malloc(n);
        assert_int_equal(qibl_shlight_add_probe(&a, &img, &o, ws, n), QIBL_OK);
        free(ws);
        int32_t dir[3] = {(int32_t)lrint(sin(t) * cos(ph) * 65536.0), (int32_t)lrint(sin(t) * sin(ph) * 65536.0),
                          (int32_t)lrint(cos(t) * 65536.0)};
        int32_t rgb[3];
        for (int c = 0; c < 3; ++c)
            rgb[c] = (int32_t)lrint(ldexp(q[c], 200 - 136 - 64 + 8) * dw * 65536.0);
        assert_int_equal(qibl_shlight_add_dir(&b, dir, rgb), QIBL_OK);
        for (int c = 0; c < 3; ++c)
            for (int i = 0; i < 25; ++i) /* the direction's Q16 rounding moves Y by ~2^-16 */
                assert_true(abs(a.c[c][i] - b.c[c][i]) <= 2 + (int)(fabs((double)rgb[c]) * 4e-5));
        probe_free(&p);
    }
}

/* the poles: only the top row, only the bottom row, a one-column probe, a 1 x H probe */
static void test_poles(void **state)
{
    (void)state;
    for (int k = 0; k < 3; ++k) {
        const int w = k == 2 ? 1 : 64, h = 32;
        probe p = {w, h, calloc(4 * (size_t)w * h, 1), NULL};
        for (int v = 0; v < h; ++v)
            for (int u = 0; u < w; ++u) {
                if ((k == 0 && v != 0) || (k == 1 && v != h - 1))
                    continue;
                uint8_t *q = p.rgbe + 4 * ((size_t)v * w + (size_t)u);
                q[0] = (uint8_t)(100 + u), q[1] = 200, q[2] = (uint8_t)(50 + v), q[3] = 140;
            }
        fill_double(&p);
        check_probe(&p, 5);
        probe_free(&p);
    }
}

/* RGBE with small (not normalised) mantissas: the row scale from the exponent alone gives up to
 * 7 bits, and the bound (stated with M_v = 2^(emax - 128)) still holds */
static void test_rgbe_small_mantissas(void **state)
{
    (void)state;
    probe p = random_probe(44, 64, 32, 120, 6, 0);
    for (size_t i = 0; i < 64 * 32; ++i)
        for (int c = 0; c < 3; ++c)
            p.rgbe[4 * i + (size_t)c] = (uint8_t)(1 + p.rgbe[4 * i + (size_t)c] % 3);
    free(p.d);
    fill_double(&p);
    errs e = check_probe(&p, 5);
    printf("probe: RGBE mantissas 1..3: max |err| / max |L| %.3e\n", e.rel_max);
    probe_free(&p);
}

static void test_all_zero(void **state)
{
    (void)state;
    const int w = 16, h = 8;
    uint8_t *px = calloc(4 * (size_t)w * h, 1);
    for (int i = 0; i < w * h; i += 3)
        px[4 * i + 3] = 200; /* exponent without mantissa: still black */
    qibl_lightprobe_image_t img = image(px, w, h, QIBL_LIGHTPROBE_RGBE, 0);
    qibl_probe_coeffs_t c;
    memset(&c, 0x5A, sizeof c);
    assert_int_equal(project(&img, 5, NULL, &c), QIBL_OK);
    assert_int_equal(c.exp, 0);
    assert_int_equal(c.bands, 5);
    for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i < 25; ++i)
            assert_int_equal(c.c[ch][i], 0);
    free(px);
}

/* An unlit pixel (mantissas 0) whose exponent is above the row's largest lit one adds nothing and
 * must not shift by more than the word (found by fuzz_probe: undefined behaviour in row_convert for
 * RGBE and in quant for sRGBE, caught by make test-asan; inputs in tests/fuzz/crashes-found/probe) */
static void test_unlit_high_exponent(void **state)
{
    (void)state;
    const int w = 4, h = 2;
    for (int f = 0; f < 2; ++f) {
        const qibl_lightprobe_format_t fmt = f ? QIBL_LIGHTPROBE_SRGBE : QIBL_LIGHTPROBE_RGBE;
        const uint8_t zero = f ? 128 : 0; /* a zero channel of the format */
        uint8_t a[4 * 4 * 2], b[4 * 4 * 2];
        for (int i = 0; i < w * h; ++i)
            a[4 * i] = a[4 * i + 1] = a[4 * i + 2] = zero, a[4 * i + 3] = 0;
        for (int i = 0; i < w * h; i += 2)
            a[4 * i] = 200, a[4 * i + 1] = 140, a[4 * i + 3] = f ? 10 : 175; /* lit, below 255 - 80 */
        memcpy(b, a, sizeof a);
        a[4 * 1 + 3] = 255, a[4 * 7 + 3] = 250; /* unlit pixels of huge exponent */
        qibl_lightprobe_image_t ia = image(a, w, h, fmt, 0), ib = image(b, w, h, fmt, 0);
        qibl_probe_coeffs_t ca, cb;
        memset(&ca, 0x5A, sizeof ca);
        memset(&cb, 0x3C, sizeof cb);
        assert_int_equal(project(&ia, 5, NULL, &ca), QIBL_OK);
        assert_int_equal(project(&ib, 5, NULL, &cb), QIBL_OK);
        assert_memory_equal(&ca, &cb, sizeof ca);
    }
}

/* NaN, Inf, negative binary32 (including -0, which is fine, and the smallest negative subnormal),
 * negative int32, negative sRGBE: named statuses, and a failing row changes nothing */
static void test_bad_pixels(void **state)
{
    (void)state;
    const int w = 8, h = 4;
    uint32_t f[3 * 8 * 4];
    static const struct {
        uint32_t bits;
        qibl_status_t want;
    } cases[] = {{0x7FC00000u, QIBL_E_PROBE_NOT_FINITE}, {0xFFC00001u, QIBL_E_PROBE_NOT_FINITE},
                 {0x7F800000u, QIBL_E_PROBE_NOT_FINITE}, {0xFF800000u, QIBL_E_PROBE_NOT_FINITE},
                 {0xBF800000u, QIBL_E_PROBE_NEGATIVE},   {0x80000001u, QIBL_E_PROBE_NEGATIVE},
                 {0x80000000u, QIBL_OK},                 {0x00000001u, QIBL_OK}};
    size_t n = qibl_probe_sh_workspace_size(w, h);
    void *ws = malloc(n);
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        for (int i = 0; i < 3 * w * h; ++i)
            f[i] = 0x3F800000u + (uint32_t)i;
        qibl_probe_sh_t ps;
        assert_int_equal(qibl_probe_sh_begin(&ps, w, h, QIBL_LIGHTPROBE_LINEAR_F32, 0, 5, ws, n), QIBL_OK);
        qibl_probe_coeffs_t clean, c;
        for (int v = 0; v < h; ++v)
            assert_int_equal(qibl_probe_sh_add_row(&ps, (uint32_t)v, f + 3 * w * v), QIBL_OK);
        assert_int_equal(qibl_probe_sh_finish(&ps, NULL, &clean), QIBL_OK);
        /* the same with row 2 first offered with a bad channel */
        assert_int_equal(qibl_probe_sh_begin(&ps, w, h, QIBL_LIGHTPROBE_LINEAR_F32, 0, 5, ws, n), QIBL_OK);
        uint32_t good = f[3 * (w * 2 + 5) + 1];
        f[3 * (w * 2 + 5) + 1] = cases[k].bits;
        qibl_status_t st = qibl_probe_sh_add_row(&ps, 2, f + 3 * w * 2);
        assert_int_equal(st, cases[k].want);
        if (st != QIBL_OK) {
            assert_int_equal(qibl_probe_sh_finish(&ps, NULL, &c), QIBL_E_PROBE_ROW); /* row 2 missing */
            f[3 * (w * 2 + 5) + 1] = good;
            assert_int_equal(qibl_probe_sh_add_row(&ps, 2, f + 3 * w * 2), QIBL_OK);
            for (int v = 0; v < h; ++v)
                if (v != 2)
                    assert_int_equal(qibl_probe_sh_add_row(&ps, (uint32_t)v, f + 3 * w * v), QIBL_OK);
            assert_int_equal(qibl_probe_sh_finish(&ps, NULL, &c), QIBL_OK);
            assert_memory_equal(&c, &clean, sizeof c);
        }
    }
    /* a NaN and a negative in one row: NOT_FINITE is reported first, whatever the order */
    for (int i = 0; i < 3 * w; ++i)
        f[i] = 0x3F800000u;
    f[4] = 0xBF800000u, f[20] = 0x7FC00000u;
    qibl_probe_sh_t ps;
    assert_int_equal(qibl_probe_sh_begin(&ps, w, h, QIBL_LIGHTPROBE_LINEAR_F32, 0, 5, ws, n), QIBL_OK);
    assert_int_equal(qibl_probe_sh_add_row(&ps, 0, f), QIBL_E_PROBE_NOT_FINITE);
    /* int32 and sRGBE negatives */
    int32_t iv[3 * 8] = {0};
    iv[7] = -1;
    assert_int_equal(qibl_probe_sh_begin(&ps, w, h, QIBL_LIGHTPROBE_LINEAR_I32, 4, 5, ws, n), QIBL_OK);
    assert_int_equal(qibl_probe_sh_add_row(&ps, 0, iv), QIBL_E_PROBE_NEGATIVE);
    uint8_t sr[4 * 8];
    memset(sr, 200, sizeof sr);
    sr[9] = 126;
    assert_int_equal(qibl_probe_sh_begin(&ps, w, h, QIBL_LIGHTPROBE_SRGBE, 0, 5, ws, n), QIBL_OK);
    assert_int_equal(qibl_probe_sh_add_row(&ps, 0, sr), QIBL_E_PROBE_NEGATIVE);
    sr[9] = 127; /* 127 and 128 read as zero */
    assert_int_equal(qibl_probe_sh_add_row(&ps, 0, sr), QIBL_OK);
    free(ws);
}

/* The largest sizes at the largest pixel values, streamed as one row buffer: 2^26 pixels of
 * binary32 FLT_MAX (32768 x 2048), 2^26 pixels of int32 INT32_MAX with frac_bits -128 (2^159, the
 * largest value of any format) in the most rows a probe can have (2048 x 32768), and RGBE's largest
 * (255, 255) at 4096 x 2048. Nothing overflows (probe.c: 480-bit accumulators, every row term below
 * 2^177, 2^15 rows below 2^192 of 2^223): L_00 is the Riemann sum of a constant, L_lm (l > 0)
 * vanish within the bound except the m = 0 terms the discretisation leaves, computed here. */
static void test_largest_size_and_values(void **state)
{
    (void)state;
    for (int k = 0; k < 3; ++k) {
        const uint32_t w = k == 0 ? 32768u : k == 1 ? 2048u : 4096u, h = k == 1 ? 32768u : 2048u;
        const size_t pb = k < 2 ? 12u : 4u;
        uint8_t *row = malloc(pb * w);
        assert_non_null(row);
        double value;
        if (k == 0) {
            uint32_t *f = (uint32_t *)(void *)row;
            for (size_t i = 0; i < 3u * w; ++i)
                f[i] = 0x7F7FFFFFu;
            value = ldexp(16777215.0, 104);
        } else if (k == 1) {
            int32_t *q = (int32_t *)(void *)row;
            for (size_t i = 0; i < 3u * w; ++i)
                q[i] = INT32_MAX;
            value = ldexp((double)INT32_MAX, 128);
        } else {
            memset(row, 255, pb * w);
            value = ldexp(255.0, 255 - 136);
        }
        size_t n = qibl_probe_sh_workspace_size(w, h);
        assert_true(n > 0);
        void *ws = malloc(n);
        qibl_probe_sh_t ps;
        const qibl_lightprobe_format_t f = k == 0 ? QIBL_LIGHTPROBE_LINEAR_F32 : k == 1 ? QIBL_LIGHTPROBE_LINEAR_I32
                                                                                      : QIBL_LIGHTPROBE_RGBE;
        assert_int_equal(qibl_probe_sh_begin(&ps, w, h, f, k == 1 ? -128 : 0, 5, ws, n), QIBL_OK);
        for (uint32_t v = 0; v < h; ++v)
            assert_int_equal(qibl_probe_sh_add_row(&ps, v, row), QIBL_OK);
        qibl_probe_coeffs_t c;
        assert_int_equal(qibl_probe_sh_finish(&ps, NULL, &c), QIBL_OK);
        double s = 0.0;
        for (uint32_t v = 0; v < h; ++v)
            s += sin((v + 0.5) * M_PI / h);
        double l00 = value * 0.5 / sqrt(M_PI) * (2.0 * M_PI) * (M_PI / h) * s, bprime = value * (2.0 * M_PI) * (M_PI / h) * s;
        double bound = ldexp(bprime, -26) + ldexp(l00, -29), worst = 0.0;
        for (int ch = 0; ch < 3; ++ch)
            for (int i = 0; i < 25; ++i) {
                double want = 0.0;
                if (i == 0)
                    want = l00;
                else if (i == 6 || i == 20) { /* the m = 0 bands 2 and 4 of a constant: the Riemann sum of Y_l0 */
                    double t = 0.0, y[25];
                    for (uint32_t v = 0; v < h; ++v) {
                        double th = (v + 0.5) * M_PI / h;
                        qtool_ref_sh_eval(sin(th), 0, cos(th), 5, y);
                        t += y[i] * sin(th);
                    }
                    want = value * (2.0 * M_PI) * (M_PI / h) * t;
                }
                worst = fmax(worst, fabs(ldexp(c.c[ch][i], c.exp) - want));
            }
        printf("probe: %ux%u at the largest %s value: max |err| %.3e of L_00 %.3e (bound %.3e)\n", w, h,
               k == 0 ? "binary32" : k == 1 ? "int32" : "RGBE", worst, l00, bound);
        assert_true(worst <= bound);
        free(ws), free(row);
    }
}

static void test_errors(void **state)
{
    (void)state;
    const uint32_t w = 8, h = 4;
    size_t n = qibl_probe_sh_workspace_size(w, h);
    uint8_t *ws = malloc(n + 4);
    uint8_t px[4 * 8 * 4];
    memset(px, 130, sizeof px);
    qibl_probe_sh_t ps;
    memset(&ps, 0x5A, sizeof ps);
    const qibl_probe_sh_t guard = ps;
    assert_int_equal(qibl_probe_sh_workspace_size(0, 4), 0);
    assert_int_equal(qibl_probe_sh_workspace_size(32769, 4), 0);
    assert_int_equal(qibl_probe_sh_workspace_size(32768, 4096), 0); /* 2^27 pixels */
    assert_true(qibl_probe_sh_workspace_size(32768, 2048) > 0);
    assert_int_equal(qibl_probe_sh_begin(NULL, w, h, 0, 0, 5, ws, n), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_probe_sh_begin(&ps, w, h, 0, 0, 5, NULL, n), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_probe_sh_begin(&ps, w, h, 0, 0, 0, ws, n), QIBL_E_BAD_BANDS);
    assert_int_equal(qibl_probe_sh_begin(&ps, w, h, 0, 0, 6, ws, n), QIBL_E_BAD_BANDS);
    assert_int_equal(qibl_probe_sh_begin(&ps, 0, h, 0, 0, 5, ws, n), QIBL_E_PROBE_SIZE);
    assert_int_equal(qibl_probe_sh_begin(&ps, w, 32769, 0, 0, 5, ws, n), QIBL_E_PROBE_SIZE);
    assert_int_equal(qibl_probe_sh_begin(&ps, 32768, 4096, 0, 0, 5, ws, n), QIBL_E_PROBE_OVERFLOW);
    assert_int_equal(qibl_probe_sh_begin(&ps, w, h, QIBL_LIGHTPROBE_FORMAT_COUNT, 0, 5, ws, n), QIBL_E_PROBE_FORMAT);
    assert_int_equal(qibl_probe_sh_begin(&ps, w, h, QIBL_LIGHTPROBE_LINEAR_I32, -129, 5, ws, n), QIBL_E_PROBE_FORMAT);
    assert_int_equal(qibl_probe_sh_begin(&ps, w, h, 0, 0, 5, ws, n - 1), QIBL_E_WORKSPACE);
    assert_memory_equal(&ps, &guard, sizeof ps);
    /* any alignment of the workspace (the begin aligns its tables itself: 4 bytes of slack) */
    assert_int_equal(qibl_probe_sh_begin(&ps, w, h, QIBL_LIGHTPROBE_LINEAR_F32, 0, 5, ws + 3, n), QIBL_OK);
    assert_int_equal(qibl_probe_sh_begin(&ps, w, h, QIBL_LIGHTPROBE_LINEAR_F32, 0, 5, ws + 2, n), QIBL_OK);
    assert_int_equal(qibl_probe_sh_begin(&ps, w, h, QIBL_LIGHTPROBE_LINEAR_F32, 0, 5, ws + 1, n), QIBL_OK);
    uint32_t frow[3 * 8 + 1];
    for (int i = 0; i < 3 * 8 + 1; ++i)
        frow[i] = 0x3F000000u;
    assert_int_equal(qibl_probe_sh_add_row(&ps, 0, (uint8_t *)frow + 2), QIBL_E_PROBE_FORMAT); /* misaligned */
    assert_int_equal(qibl_probe_sh_add_row(&ps, h, frow), QIBL_E_PROBE_ROW);
    assert_int_equal(qibl_probe_sh_add_row(NULL, 0, frow), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_probe_sh_add_row(&ps, 0, NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_probe_sh_add_row(&ps, 1, frow), QIBL_OK);
    assert_int_equal(qibl_probe_sh_add_row(&ps, 1, frow), QIBL_E_PROBE_ROW); /* twice */
    qibl_probe_coeffs_t c, cg;
    memset(&c, 0x5A, sizeof c);
    cg = c;
    assert_int_equal(qibl_probe_sh_finish(&ps, NULL, &c), QIBL_E_PROBE_ROW); /* rows missing */
    for (uint32_t v = 0; v < h; ++v)
        if (v != 1)
            assert_int_equal(qibl_probe_sh_add_row(&ps, v, frow), QIBL_OK);
    qibl_probe_sh_opts_t o = {0, QIBL_PROBE_WINDOW_COUNT, 0};
    assert_int_equal(qibl_probe_sh_finish(&ps, &o, &c), QIBL_E_PROBE_METHOD);
    assert_int_equal(qibl_probe_sh_finish(&ps, NULL, NULL), QIBL_E_NULL_POINTER);
    assert_memory_equal(&c, &cg, sizeof c);
    assert_int_equal(qibl_probe_sh_finish(&ps, NULL, &c), QIBL_OK);
    /* resident images: a stride shorter than a row, a misaligned 32-bit image */
    qibl_lightprobe_image_t img = image(px, (int)w, (int)h, QIBL_LIGHTPROBE_RGBE, 0);
    img.stride = 4 * w - 1;
    assert_int_equal(qibl_probe_sh_project(&img, 5, NULL, ws, n, &c), QIBL_E_PROBE_FORMAT);
    img = image((uint8_t *)frow + 1, 8, 1, QIBL_LIGHTPROBE_LINEAR_F32, 0);
    assert_int_equal(qibl_probe_sh_project(&img, 5, NULL, ws, n, &c), QIBL_E_PROBE_FORMAT);
    assert_int_equal(qibl_probe_sh_project(NULL, 5, NULL, ws, n, &c), QIBL_E_NULL_POINTER);
    /* a stride longer than a row is honoured */
    uint8_t wide[2 * 4 * 8 * 4];
    memset(wide, 0, sizeof wide);
    for (uint32_t v = 0; v < h; ++v)
        memcpy(wide + v * 64, px + v * 32, 32);
    qibl_probe_coeffs_t c1, c2;
    img = image(px, (int)w, (int)h, QIBL_LIGHTPROBE_RGBE, 0);
    assert_int_equal(qibl_probe_sh_project(&img, 5, NULL, ws, n, &c1), QIBL_OK);
    img = image(wide, (int)w, (int)h, QIBL_LIGHTPROBE_RGBE, 0);
    img.stride = 64;
    assert_int_equal(qibl_probe_sh_project(&img, 5, NULL, ws, n, &c2), QIBL_OK);
    assert_memory_equal(&c1, &c2, sizeof c1);
    free(ws);
}

/* ---- irradiance and windows ----------------------------------------------------------------- */

static void test_irradiance_and_windows(void **state)
{
    (void)state;
    probe p = random_probe(77, 64, 32, 120, 12, 1);
    qibl_lightprobe_image_t img = image(p.rgbe, p.w, p.h, QIBL_LIGHTPROBE_RGBE, 0);
    double ref[3][25];
    for (int bands = 1; bands <= 5; ++bands) {
        qtool_ref_probe_sh(p.w, p.h, p.d, bands, ref);
        for (int irr = 0; irr < 2; ++irr)
            for (int win = 0; win < 3; ++win) {
                qibl_probe_sh_opts_t o = {irr, (qibl_probe_window_t)win, 0};
                qibl_probe_coeffs_t c;
                assert_int_equal(project(&img, bands, &o, &c), QIBL_OK);
                double f[5];
                qtool_ref_probe_band_factors(bands, irr, win, f);
                errs e = compare(&c, ref, f, bands, row_bound(p.d, p.w, p.h) * M_PI);
                assert_true(e.abs <= e.bound);
                if (irr && bands >= 4)
                    for (int ch = 0; ch < 3; ++ch)
                        for (int i = 9; i < 16; ++i)
                            assert_int_equal(c.c[ch][i], 0); /* A_3 = 0 */
            }
    }
    /* a constant probe of radiance 1 has irradiance pi at every normal */
    const int w = 64, h = 32;
    uint8_t *px = malloc(4 * (size_t)w * h);
    for (int i = 0; i < w * h; ++i)
        px[4 * i] = px[4 * i + 1] = px[4 * i + 2] = 128, px[4 * i + 3] = 129;
    img = image(px, w, h, QIBL_LIGHTPROBE_RGBE, 0);
    qibl_probe_sh_opts_t o = {1, QIBL_PROBE_WINDOW_NONE, 0};
    qibl_probe_coeffs_t c;
    assert_int_equal(project(&img, 3, &o, &c), QIBL_OK);
    double y[25];
    qtool_ref_sh_eval(0.3, -0.4, 0.5, 3, y);
    double e = 0.0;
    for (int i = 0; i < 9; ++i)
        e += ldexp(c.c[1][i], c.exp) * y[i];
    assert_true(fabs(e - M_PI) < 2e-3); /* the Riemann sum of a constant at 32 rows */
    free(px);
    probe_free(&p);
}

/* ---- into a light --------------------------------------------------------------------------- */

static void test_shlight_add_probe_and_saturation(void **state)
{
    (void)state;
    probe p = random_probe(5, 32, 16, 125, 6, 0);
    qibl_lightprobe_image_t img = image(p.rgbe, p.w, p.h, QIBL_LIGHTPROBE_RGBE, 0);
    size_t n = qibl_probe_sh_workspace_size(32, 16);
    void *ws = malloc(n);
    qibl_probe_coeffs_t c;
    assert_int_equal(qibl_probe_sh_project(&img, 3, NULL, ws, n, &c), QIBL_OK);
    qibl_shlight_t l, g;
    assert_int_equal(qibl_shlight_init(&l, 9), QIBL_OK);
    l.c[0][0] = 1000;
    qibl_probe_sh_opts_t o = {0, QIBL_PROBE_WINDOW_NONE, 3};
    assert_int_equal(qibl_shlight_add_probe(&l, &img, &o, ws, n), QIBL_OK);
    for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i < 9; ++i) {
            double want = (ch == 0 && i == 0 ? 1000 : 0) + ldexp(c.c[ch][i], c.exp + 16 + 3);
            assert_true(fabs(l.c[ch][i] - want) <= 0.5);
        }
    for (int ch = 0; ch < 3; ++ch)
        for (int i = 9; i < 25; ++i)
            assert_int_equal(l.c[ch][i], 0);
    /* saturation: named, and the light untouched */
    g = l;
    o.scale_log2 = 40;
    assert_int_equal(qibl_shlight_add_probe(&l, &img, &o, ws, n), QIBL_E_PROBE_SATURATED);
    assert_memory_equal(&l, &g, sizeof l);
    /* errors */
    qibl_shlight_t bad;
    memset(&bad, 0, sizeof bad);
    assert_int_equal(qibl_shlight_add_probe(&bad, &img, NULL, ws, n), QIBL_E_SHMAP_K);
    assert_int_equal(qibl_shlight_add_probe(NULL, &img, NULL, ws, n), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_shlight_add_coeffs(&l, NULL, 0), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_shlight_add_coeffs(&l, &c, 513), QIBL_E_RANGE);
    assert_int_equal(qibl_shlight_add_coeffs(&l, &c, -100), QIBL_OK); /* far below 1 LSB: adds 0 */
    c.bands = 6;
    assert_int_equal(qibl_shlight_add_coeffs(&l, &c, 0), QIBL_E_BAD_BANDS);
    assert_int_equal(qibl_shlight_add_probe(&l, &img, NULL, ws, n - 1), QIBL_E_WORKSPACE);
    assert_memory_equal(&l, &g, sizeof l);
    free(ws);
    probe_free(&p);
}

/* a light list as SH: sum rgb 2^rgb_exp Y(dir) in double */
static void test_lights_to_sh(void **state)
{
    (void)state;
    probe p = random_probe(9, 64, 32, 120, 8, 1);
    qibl_lightprobe_image_t img = image(p.rgbe, p.w, p.h, QIBL_LIGHTPROBE_RGBE, 0);
    size_t n = qibl_lightprobe_workspace_size(64, 32, QIBL_LIGHTPROBE_MEDIANCUT);
    void *ws = malloc(n);
    qibl_lightprobe_t lp;
    assert_int_equal(qibl_lightprobe_build(&lp, &img, QIBL_LIGHTPROBE_MEDIANCUT, ws, n), QIBL_OK);
    qibl_lightprobe_light_t L[64];
    qibl_lightprobe_result_t res;
    assert_int_equal(qibl_lightprobe_lights(&lp, NULL, L, 64, &res), QIBL_OK);
    qibl_shlight_t l;
    assert_int_equal(qibl_shlight_init(&l, 25), QIBL_OK);
    const int32_t scale = -res.rgb_exp - 31 + 12; /* the brightest light near 2^12 in Q16.16 units */
    assert_int_equal(qibl_shlight_add_lights(&l, L, res.count, res.rgb_exp, scale), QIBL_OK);
    double ref[3][25] = {{0}}, mx = 0.0, worst = 0.0;
    for (uint32_t k = 0; k < res.count; ++k) {
        double y[25];
        qtool_ref_sh_eval(L[k].dir[0], L[k].dir[1], L[k].dir[2], 5, y);
        for (int ch = 0; ch < 3; ++ch)
            for (int i = 0; i < 25; ++i)
                ref[ch][i] += ldexp(L[k].rgb[ch], res.rgb_exp + scale + 16) * y[i];
    }
    for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i < 25; ++i)
            mx = fmax(mx, fabs(ref[ch][i])), worst = fmax(worst, fabs(l.c[ch][i] - ref[ch][i]));
    printf("probe: 64 median-cut lights as SH: max error %.3f LSB of Q16.16 (max |L| %.0f LSB)\n", worst, mx);
    assert_true(worst <= 0.5 + 64 * ldexp(1.0, 31 + 16 + 12 - 31) * ldexp(1.0, -25) + 1e-9);
    /* and the lights' SH approximates the probe's SH (median cut keeps the energy: L_00 within 1%) */
    qibl_probe_coeffs_t c;
    qibl_probe_sh_opts_t o = {0, QIBL_PROBE_WINDOW_NONE, 0};
    assert_int_equal(project(&img, 5, &o, &c), QIBL_OK);
    for (int ch = 0; ch < 3; ++ch) {
        double a = ldexp(c.c[ch][0], c.exp), b = ldexp(l.c[ch][0], -16 - scale);
        assert_true(fabs(a - b) <= 0.01 * a);
    }
    /* errors: untouched light */
    qibl_shlight_t g = l;
    assert_int_equal(qibl_shlight_add_lights(&l, L, res.count, res.rgb_exp, scale + 30), QIBL_E_PROBE_SATURATED);
    assert_int_equal(qibl_shlight_add_lights(&l, NULL, 3, 0, 0), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_shlight_add_lights(&l, L, 65537, 0, 0), QIBL_E_PROBE_COUNT);
    assert_memory_equal(&l, &g, sizeof l);
    free(ws);
    probe_free(&p);
}

/* sun plus sky: a sky with a one-pixel sun; the sun given as a light on exactly its pixel. The
 * result matches the plain projection (sky + the sun pixel) within the direction's rounding. */
static void test_sun_sky(void **state)
{
    (void)state;
    const int w = 64, h = 32, su = 20, sv = 9;
    probe p = random_probe(31, w, h, 120, 4, 0);
    uint8_t *q = p.rgbe + 4 * ((size_t)sv * w + su);
    q[0] = 255, q[1] = 240, q[2] = 200, q[3] = 150; /* 2^14 brighter than the sky */
    qibl_lightprobe_image_t img = image(p.rgbe, w, h, QIBL_LIGHTPROBE_RGBE, 0);
    size_t n = qibl_probe_sh_workspace_size(w, h);
    void *ws = malloc(n);
    double t = (sv + 0.5) * M_PI / h, ph = (su + 0.5) * 2.0 * M_PI / w;
    double dw = (2.0 * M_PI / w) * (M_PI / h) * sin(t);
    qibl_lightprobe_light_t sun;
    memset(&sun, 0, sizeof sun);
    sun.dir[0] = (int32_t)lrint(sin(t) * cos(ph) * Q30), sun.dir[1] = (int32_t)lrint(sin(t) * sin(ph) * Q30);
    sun.dir[2] = (int32_t)lrint(cos(t) * Q30);
    for (int c = 0; c < 3; ++c)
        sun.rgb[c] = (int32_t)lrint(ldexp(q[c], 150 - 136) * dw * 65536.0); /* rgb_exp -16 */
    sun.u0 = su, sun.u1 = su + 1, sun.v0 = sv, sun.v1 = sv + 1;
    qibl_shlight_t a, b;
    assert_int_equal(qibl_shlight_init(&a, 25), QIBL_OK);
    assert_int_equal(qibl_shlight_init(&b, 25), QIBL_OK);
    qibl_probe_sh_opts_t o = {0, QIBL_PROBE_WINDOW_NONE, 0};
    assert_int_equal(qibl_shlight_add_sun_sky(&a, &img, &o, &sun, 1, -16, ws, n), QIBL_OK);
    assert_int_equal(qibl_shlight_add_probe(&b, &img, &o, ws, n), QIBL_OK);
    int worst = 0;
    for (int c = 0; c < 3; ++c)
        for (int i = 0; i < 25; ++i)
            worst = abs(a.c[c][i] - b.c[c][i]) > worst ? abs(a.c[c][i] - b.c[c][i]) : worst;
    printf("probe: sun + sky against the whole probe's SH: max difference %d LSB of Q16.16 (L_00 %d)\n", worst,
           b.c[1][0]);
    assert_true(worst <= 3);
    /* the sky alone (sun light with zero colour) has no sun: its L_00 is the sky's */
    qibl_lightprobe_light_t dark = sun;
    dark.rgb[0] = dark.rgb[1] = dark.rgb[2] = 0;
    qibl_shlight_t s;
    assert_int_equal(qibl_shlight_init(&s, 25), QIBL_OK);
    assert_int_equal(qibl_shlight_add_sun_sky(&s, &img, &o, &dark, 1, -16, ws, n), QIBL_OK);
    assert_true(s.c[1][0] < b.c[1][0] / 2);
    /* errors */
    qibl_lightprobe_light_t out = sun;
    out.u1 = w + 1;
    qibl_shlight_t g = s;
    assert_int_equal(qibl_shlight_add_sun_sky(&s, &img, &o, &out, 1, -16, ws, n), QIBL_E_PROBE_RECT);
    assert_int_equal(qibl_shlight_add_sun_sky(&s, &img, &o, NULL, 1, -16, ws, n), QIBL_E_NULL_POINTER);
    assert_memory_equal(&s, &g, sizeof s);
    free(ws);
    probe_free(&p);
}

/* ---- rotation against re-projection ---------------------------------------------------------- */

/* A quarter turn about z is an exact shift of W/4 columns of the pixel grid: the SH of the shifted
 * probe and the rotated SH of the probe differ only by the projection and rotation errors. */
static double yaw_check(const uint8_t *px, int w, int h)
{
    uint8_t *sh = malloc(4 * (size_t)w * h);
    for (int v = 0; v < h; ++v)
        for (int u = 0; u < w; ++u)
            memcpy(sh + 4 * ((size_t)v * w + (size_t)((u + w / 4) % w)), px + 4 * ((size_t)v * w + (size_t)u), 4);
    qibl_lightprobe_image_t a = image(px, w, h, QIBL_LIGHTPROBE_RGBE, 0), b = image(sh, w, h, QIBL_LIGHTPROBE_RGBE, 0);
    qibl_probe_coeffs_t ca, cb;
    assert_int_equal(project(&a, 5, NULL, &ca), QIBL_OK);
    assert_int_equal(project(&b, 5, NULL, &cb), QIBL_OK);
    /* content moved to phi + pi/2: f'(w) = f(r^T w), r the quarter turn about +z */
    qibl_q30_t r[3][3] = {{0, -(1 << 30), 0}, {1 << 30, 0, 0}, {0, 0, 1 << 30}};
    qibl_sh_rotation_t rot;
    assert_int_equal(qibl_sh_rotation_init(&rot, (const qibl_q30_t(*)[3])r, 5), QIBL_OK);
    double worst = 0.0, mx = 0.0;
    for (int ch = 0; ch < 3; ++ch) {
        int32_t out[25];
        assert_int_equal(qibl_sh_rotate(&rot, ca.c[ch], out), QIBL_OK);
        for (int i = 0; i < 25; ++i) {
            double x = ldexp(out[i], ca.exp), y = ldexp(cb.c[ch][i], cb.exp);
            worst = fmax(worst, fabs(x - y)), mx = fmax(mx, fabs(y));
        }
    }
    free(sh);
    return worst / mx;
}

static void test_rotation_reprojection(void **state)
{
    (void)state;
    probe p = random_probe(17, 64, 32, 118, 10, 1);
    double e = yaw_check(p.rgbe, 64, 32);
    printf("probe: quarter turn about z, rotated SH against re-projection: %.3e of max |L|\n", e);
    assert_true(e <= 1e-7);
    probe_free(&p);
    /* an arbitrary rotation of a smooth probe: f = 2 + sum a_i Y_i sampled at 256 x 128, and
     * f(r^T w) sampled the same way; the Riemann sums of the two differ from the exact SH by the
     * quadrature error (O(1/H^2) for smooth f), far above the integer errors */
    const int w = 256, h = 128;
    double a[25];
    tu_rng g = {12};
    for (int i = 0; i < 25; ++i)
        a[i] = (i == 0 ? 2.0 * sqrt(4.0 * M_PI) : 0.3 * (tu_unit(&g) - 0.5));
    const double qw = 0.6, qx = -0.3, qy = 0.5, qz = 0.55, qn = sqrt(qw * qw + qx * qx + qy * qy + qz * qz);
    const double W_ = qw / qn, X = qx / qn, Y = qy / qn, Z = qz / qn;
    double rm[3][3] = {{1 - 2 * (Y * Y + Z * Z), 2 * (X * Y - W_ * Z), 2 * (X * Z + W_ * Y)},
                       {2 * (X * Y + W_ * Z), 1 - 2 * (X * X + Z * Z), 2 * (Y * Z - W_ * X)},
                       {2 * (X * Z - W_ * Y), 2 * (Y * Z + W_ * X), 1 - 2 * (X * X + Y * Y)}};
    uint32_t *f0 = malloc(12 * (size_t)w * h), *f1 = malloc(12 * (size_t)w * h);
    for (int v = 0; v < h; ++v)
        for (int u = 0; u < w; ++u) {
            double t = (v + 0.5) * M_PI / h, ph = (u + 0.5) * 2.0 * M_PI / w, y[25];
            double d[3] = {sin(t) * cos(ph), sin(t) * sin(ph), cos(t)}, e3[3];
            for (int k = 0; k < 2; ++k) {
                if (k == 0)
                    e3[0] = d[0], e3[1] = d[1], e3[2] = d[2];
                else
                    for (int i = 0; i < 3; ++i)
                        e3[i] = rm[0][i] * d[0] + rm[1][i] * d[1] + rm[2][i] * d[2];
                qtool_ref_sh_eval(e3[0], e3[1], e3[2], 5, y);
                double val = 0.0;
                for (int i = 0; i < 25; ++i)
                    val += a[i] * y[i];
                float fv = (float)val;
                for (int c = 0; c < 3; ++c)
                    memcpy((k ? f1 : f0) + 3 * ((size_t)v * w + (size_t)u) + c, &fv, 4);
            }
        }
    qibl_lightprobe_image_t i0 = image(f0, w, h, QIBL_LIGHTPROBE_LINEAR_F32, 0);
    qibl_lightprobe_image_t i1 = image(f1, w, h, QIBL_LIGHTPROBE_LINEAR_F32, 0);
    qibl_probe_coeffs_t c0, c1;
    assert_int_equal(project(&i0, 5, NULL, &c0), QIBL_OK);
    assert_int_equal(project(&i1, 5, NULL, &c1), QIBL_OK);
    qibl_q30_t rq[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            rq[i][j] = (int32_t)lrint(rm[i][j] * Q30);
    qibl_sh_rotation_t rot;
    assert_int_equal(qibl_sh_rotation_init(&rot, (const qibl_q30_t(*)[3])rq, 5), QIBL_OK);
    int32_t out[25];
    assert_int_equal(qibl_sh_rotate(&rot, c0.c[1], out), QIBL_OK);
    double worst = 0.0;
    for (int i = 0; i < 25; ++i)
        worst = fmax(worst, fabs(ldexp(out[i], c0.exp) - ldexp(c1.c[1][i], c1.exp)));
    printf("probe: arbitrary rotation of a smooth 256x128 probe: rotated SH against re-projection %.3e "
           "(L_00 %.3f; quadrature error dominates)\n", worst, ldexp(c1.c[1][0], c1.exp));
    assert_true(worst <= 1e-3 * ldexp(c1.c[1][0], c1.exp));
    free(f0), free(f1);
}

/* qibl_shlight_rotate: a directional light's coefficients move with the rotation */
static void test_shlight_rotate(void **state)
{
    (void)state;
    qibl_q30_t r[3][3] = {{0, 0, 1 << 30}, {1 << 30, 0, 0}, {0, 1 << 30, 0}}; /* x -> y -> z -> x */
    qibl_sh_rotation_t rot;
    assert_int_equal(qibl_sh_rotation_init(&rot, (const qibl_q30_t(*)[3])r, 5), QIBL_OK);
    const int32_t d[3] = {20000, -30000, 50000}, rd[3] = {50000, 20000, -30000}; /* r d */
    const int32_t rgb[3] = {3 << 16, 1 << 16, 1 << 15};
    qibl_shlight_t a, b;
    assert_int_equal(qibl_shlight_init(&a, 16), QIBL_OK);
    assert_int_equal(qibl_shlight_init(&b, 16), QIBL_OK);
    assert_int_equal(qibl_shlight_add_dir(&a, d, rgb), QIBL_OK);
    assert_int_equal(qibl_shlight_add_dir(&b, rd, rgb), QIBL_OK);
    assert_int_equal(qibl_shlight_rotate(&a, &rot), QIBL_OK);
    for (int c = 0; c < 3; ++c)
        for (int i = 0; i < 25; ++i)
            assert_true(abs(a.c[c][i] - b.c[c][i]) <= 2);
    /* errors */
    qibl_sh_rotation_t small;
    assert_int_equal(qibl_sh_rotation_init(&small, (const qibl_q30_t(*)[3])r, 3), QIBL_OK);
    qibl_shlight_t g = a;
    assert_int_equal(qibl_shlight_rotate(&a, &small), QIBL_E_BAD_BANDS); /* 16 coefficients need 4 bands */
    assert_int_equal(qibl_shlight_rotate(&a, NULL), QIBL_E_NULL_POINTER);
    assert_memory_equal(&a, &g, sizeof a);
    qibl_shlight_t bad;
    memset(&bad, 0, sizeof bad);
    assert_int_equal(qibl_shlight_rotate(&bad, &rot), QIBL_E_SHMAP_K);
}

/* ---- goldens and the real probes ------------------------------------------------------------ */

static void test_goldens(void **state)
{
    (void)state;
    assert_int_equal(qtool_goldens_check("probe"), 0);
}

static const char *probe_dir(void)
{
    const char *d = getenv("QIBL_PROBE_DIR");
    return d && *d ? d : "../shared/fixtures/probes";
}

static void test_real_probes(void **state)
{
    (void)state;
    DIR *dir = opendir(probe_dir());
    if (!dir) {
        printf("SKIP probe real probes: %s not found (set QIBL_PROBE_DIR)\n", probe_dir());
        skip();
    }
    char names[64][256];
    int np = 0;
    struct dirent *de;
    while ((de = readdir(dir)) != NULL && np < 64) {
        size_t l = strlen(de->d_name);
        if (l > 4 && strcmp(de->d_name + l - 4, ".hdr") == 0)
            snprintf(names[np++], sizeof names[0], "%.250s", de->d_name);
    }
    closedir(dir);
    if (np == 0) {
        printf("SKIP probe real probes: no .hdr in %s\n", probe_dir());
        skip();
    }
    qsort(names, (size_t)np, sizeof names[0], (int (*)(const void *, const void *))strcmp);
    double worst = 0.0, worst_yaw = 0.0;
    for (int i = 0; i < np; ++i) {
        char path[512], err[512];
        snprintf(path, sizeof path, "%.250s/%.250s", probe_dir(), names[i]);
        probe p = {0, 0, NULL, NULL};
        assert_int_equal(qtool_hdr_read_rgbe(path, &p.w, &p.h, &p.rgbe, err, sizeof err), 0);
        fill_double(&p);
        errs e = check_probe(&p, 5);
        worst = fmax(worst, e.rel_max);
        if (p.w % 4 == 0)
            worst_yaw = fmax(worst_yaw, yaw_check(p.rgbe, p.w, p.h));
        probe_free(&p);
    }
    printf("probe: %d real probes: projection max |err| / max |L| %.3e (each within the stated bound); "
           "quarter-turn re-projection %.3e\n", np, worst, worst_yaw);
    assert_true(worst_yaw <= 1e-7);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_matches_reference),
        cmocka_unit_test(test_formats),
        cmocka_unit_test(test_vector_widths),
        cmocka_unit_test(test_band_orders),
        cmocka_unit_test(test_row_order),
        cmocka_unit_test(test_single_bright_pixel),
        cmocka_unit_test(test_poles),
        cmocka_unit_test(test_rgbe_small_mantissas),
        cmocka_unit_test(test_all_zero),
        cmocka_unit_test(test_unlit_high_exponent),
        cmocka_unit_test(test_bad_pixels),
        cmocka_unit_test(test_largest_size_and_values),
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_irradiance_and_windows),
        cmocka_unit_test(test_shlight_add_probe_and_saturation),
        cmocka_unit_test(test_lights_to_sh),
        cmocka_unit_test(test_sun_sky),
        cmocka_unit_test(test_rotation_reprojection),
        cmocka_unit_test(test_shlight_rotate),
        cmocka_unit_test(test_every_isa_bits),
        cmocka_unit_test(test_goldens),
        cmocka_unit_test(test_real_probes),
    };
    return cmocka_run_group_tests_name(QIBL_CONFIG_NATIVE_MUL64 ? "probe (native paths)" : "probe (portable M0 paths)",
                                       tests, NULL, NULL);
}
