/*
 * shmap_test.c - relighting kernels (qibl/shmap.h) against a double-precision evaluation of
 * sum_i T_i(p) L_i from the same 8-bit maps; light coefficients against the double SH reference;
 * point lights (direct and cube-map LUT) against sum_i T_i(p) Y_i(L) att(|L|); accumulator bounds at
 * the extremes; every error status with nothing written.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdlib.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "golden/check.h"
#include "io/asset_write.h"
#include "io/isa_env.h"
#include "qibl/asset.h"
#include "qibl/isa.h"
#include "qibl/shmap.h"
#include "qibl/soft.h"
#include "ref/sh_ref.h"
#include "twin/shmap_scalar.h"
#include "testutil.h"

#define Q16 65536.0
#define Q24 16777216.0

/* ---- random maps held in memory (the qibl_shmaps_t view filled by hand) ----------------------- */
typedef struct {
    qibl_shmaps_t m;
    uint8_t *params, *planes;
} maps_buf;

static void put_s32(uint8_t *p, int32_t v)
{
    uint32_t u = (uint32_t)v;
    p[0] = (uint8_t)u, p[1] = (uint8_t)(u >> 8), p[2] = (uint8_t)(u >> 16), p[3] = (uint8_t)(u >> 24);
}

/* scale_mag: largest |scale| in Q8.24; biases up to 128 * scale_mag in magnitude */
static void maps_make(maps_buf *b, uint32_t w, uint32_t h, uint32_t k, uint32_t ch, tu_rng *r, int32_t scale_mag)
{
    b->m.width = w, b->m.height = h, b->m.k = k, b->m.channels = ch, b->m.layout = QIBL_SHMAPS_PLANAR;
    b->params = malloc(8u * k * ch);
    b->planes = malloc((size_t)w * h * k * ch);
    assert_non_null(b->params);
    assert_non_null(b->planes);
    for (uint32_t i = 0; i < k * ch; ++i) {
        int32_t sc = (int32_t)(tu_u32(r) % (uint32_t)scale_mag) - scale_mag / 2;
        int32_t bi = -128 * sc + (int32_t)(tu_u32(r) % 2001u) - 1000; /* centred ranges, as packing gives */
        put_s32(b->params + 8u * i, sc);
        put_s32(b->params + 8u * i + 4u, bi);
    }
    for (size_t i = 0; i < (size_t)w * h * k * ch; ++i)
        b->planes[i] = (uint8_t)tu_u32(r);
    b->m.params = b->params;
    b->m.planes = b->planes;
}

static void maps_free(maps_buf *b)
{
    free(b->params);
    free(b->planes);
}

static double decoded(const qibl_shmaps_t *m, uint32_t i, uint32_t ch, uint32_t x, uint32_t y)
{
    uint8_t c = qibl_shmaps_plane(m, i, ch)[(size_t)y * m->width + x];
    return (qibl_shmaps_bias(m, i, ch) + (double)qibl_shmaps_scale(m, i, ch) * c) / Q24;
}

/* ---- light coefficients ---------------------------------------------------------------------- */

static void test_shlight_add_dir_matches_reference(void **state)
{
    (void)state;
    tu_rng r = {41};
    for (int it = 0; it < 2000; ++it) {
        qibl_shlight_t l;
        assert_int_equal(qibl_shlight_init(&l, 25), QIBL_OK);
        qibl_q16_t d[3] = {tu_s32(&r) >> 8, tu_s32(&r) >> 8, tu_s32(&r) >> 8};
        qibl_q16_t rgb[3] = {(int32_t)(tu_u32(&r) % (40u << 16)), (int32_t)(tu_u32(&r) % (1u << 16)), 65536};
        if (!d[0] && !d[1] && !d[2])
            continue;
        assert_int_equal(qibl_shlight_add_dir(&l, d, rgb), QIBL_OK);
        double y[25];
        qtool_ref_sh_eval(d[0], d[1], d[2], 5, y);
        for (int ch = 0; ch < 3; ++ch)
            for (int i = 0; i < 25; ++i) {
                double want = rgb[ch] * y[i]; /* in Q16.16 LSB */
                assert_true(fabs(l.c[ch][i] - want) <= 0.5 + fabs((double)rgb[ch]) * 3e-8 + 1e-9);
            }
    }
    qibl_shlight_t l;
    assert_int_equal(qibl_shlight_init(&l, 0), QIBL_E_SHMAP_K);
    assert_int_equal(qibl_shlight_init(&l, 26), QIBL_E_SHMAP_K);
    assert_int_equal(qibl_shlight_init(0, 4), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_shlight_init(&l, 4), QIBL_OK);
    const qibl_q16_t z[3] = {0, 0, 0}, one[3] = {65536, 65536, 65536};
    assert_int_equal(qibl_shlight_add_dir(&l, z, one), QIBL_E_ZERO_VECTOR);
    for (int i = 0; i < 4; ++i)
        assert_int_equal(l.c[0][i], 0); /* untouched */
}

/* ---- directional / environment --------------------------------------------------------------- */

/* Mean relative error (error / bound) per output channel over every check_relight call, so the
 * suite can assert the mean as well as the max. */
static double mean_sum[3];
static long mean_n[3];

/* Relights the whole image with w and compares with the double evaluation of sum_i T_i L_i.
 * Returns the max error in units of the documented bound (must be <= 1). */
static double check_relight(const qibl_shmaps_t *m, const qibl_shlight_t *l, double *max_abs)
{
    qibl_shmap_weights_t w;
    assert_int_equal(qibl_shmap_weights(m, l, &w), QIBL_OK);
    uint32_t n = m->width;
    int32_t *out = malloc(sizeof(int32_t) * 3u * (n + 1u));
    void *ws = malloc(qibl_shmap_span_workspace_size(n));
    assert_non_null(out);
    assert_non_null(ws);
    double worst = 0.0, worst_abs = 0.0;
    for (uint32_t y = 0; y < m->height; ++y) {
        out[3u * n] = 0x7EADBEEF;
        assert_int_equal(qibl_shmap_relight_span(m, &w, 0, y, n, out, ws, qibl_shmap_span_workspace_size(n)), QIBL_OK);
        assert_int_equal(out[3u * n], 0x7EADBEEF);
        for (uint32_t x = 0; x < n; ++x)
            for (uint32_t ch = 0; ch < 3; ++ch) {
                uint32_t src = m->channels == 3 ? ch : 0;
                double want = 0.0;
                for (uint32_t i = 0; i < m->k; ++i)
                    want += decoded(m, i, src, x, y) * (l->c[ch][i] / Q16);
                double got = out[3u * x + ch] / Q16;
                if (fabs(want) * Q16 > 2147483000.0)
                    continue; /* saturated by design */
                /* bound: 0.5 weight-LSB per map times the byte, plus bias and final rounding */
                double bound = m->k * 127.5 * ldexp(1.0, w.shift[ch] - 16) + 2.0 / Q16 + 1e-12;
                double e = fabs(got - want);
                if (e / bound > worst)
                    worst = e / bound;
                if (e > worst_abs)
                    worst_abs = e;
                mean_sum[ch] += e / bound;
                mean_n[ch]++;
            }
    }
    free(out);
    free(ws);
    if (max_abs)
        *max_abs = worst_abs;
    return worst;
}

static void test_directional_against_double(void **state)
{
    (void)state;
    tu_rng r = {42};
    const uint32_t ks[] = {1, 4, 9, 10, 16, 25};
    double worst = 0.0, worst_abs = 0.0;
    for (size_t ki = 0; ki < sizeof ks / sizeof ks[0]; ++ki)
        for (uint32_t ch = 1; ch <= 3; ch += 2) {
            maps_buf b;
            maps_make(&b, 37, 5, ks[ki], ch, &r, 1 << 16);
            for (int it = 0; it < 8; ++it) {
                qibl_shlight_t l;
                assert_int_equal(qibl_shlight_init(&l, 25), QIBL_OK);
                qibl_q16_t d[3] = {tu_s32(&r) >> 4, tu_s32(&r) >> 4, tu_s32(&r) >> 4};
                qibl_q16_t rgb[3] = {(int32_t)(tu_u32(&r) % (8u << 16)), (int32_t)(tu_u32(&r) % (8u << 16)), 1 << 16};
                assert_int_equal(qibl_shlight_add_dir(&l, d, rgb), QIBL_OK);
                double a;
                double e = check_relight(&b.m, &l, &a);
                if (e > worst)
                    worst = e;
                if (a > worst_abs)
                    worst_abs = a;
            }
            maps_free(&b);
        }
    printf("shmap: directional, max error = %.3f of the documented bound (max abs %.3e); mean per channel "
           "%.3f %.3f %.3f\n", worst, worst_abs, mean_sum[0] / mean_n[0], mean_sum[1] / mean_n[1],
           mean_sum[2] / mean_n[2]);
    assert_true(worst <= 1.0);
    /* the k weight roundings are independent, so their sum grows like sqrt(k) while the bound grows
     * like k: the mean stays far below the worst case (measured about 0.09 over these k) */
    for (int ch = 0; ch < 3; ++ch)
        assert_true(mean_sum[ch] / mean_n[ch] <= 0.15);
}

static void test_environment_and_many_lights(void **state)
{
    (void)state;
    tu_rng r = {43};
    maps_buf b;
    maps_make(&b, 64, 3, 16, 3, &r, 1 << 15);
    /* an environment: arbitrary signed coefficients per channel */
    qibl_shlight_t env;
    assert_int_equal(qibl_shlight_init(&env, 16), QIBL_OK);
    for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i < 16; ++i)
            env.c[ch][i] = (int32_t)(tu_u32(&r) % (4u << 16)) - (2 << 16);
    assert_true(check_relight(&b.m, &env, NULL) <= 1.0);
    /* eight directional lights at once equal their summed coefficients */
    qibl_shlight_t many;
    assert_int_equal(qibl_shlight_init(&many, 16), QIBL_OK);
    for (int j = 0; j < 8; ++j) {
        qibl_q16_t d[3] = {tu_s32(&r) >> 8, tu_s32(&r) >> 8, tu_s32(&r) >> 8};
        qibl_q16_t rgb[3] = {1 << 15, 1 << 14, 1 << 16};
        assert_int_equal(qibl_shlight_add_dir(&many, d, rgb), QIBL_OK);
    }
    assert_true(check_relight(&b.m, &many, NULL) <= 1.0);
    maps_free(&b);
}

static void test_spans_equal_whole_rows(void **state)
{
    (void)state;
    tu_rng r = {44};
    maps_buf b;
    maps_make(&b, 203, 4, 9, 3, &r, 1 << 16);
    qibl_shlight_t l;
    assert_int_equal(qibl_shlight_init(&l, 9), QIBL_OK);
    const qibl_q16_t d[3] = {1 << 16, -(1 << 15), 3 << 14}, rgb[3] = {3 << 16, 2 << 16, 1 << 16};
    assert_int_equal(qibl_shlight_add_dir(&l, d, rgb), QIBL_OK);
    qibl_shmap_weights_t w;
    assert_int_equal(qibl_shmap_weights(&b.m, &l, &w), QIBL_OK);
    int32_t whole[203 * 3], part[203 * 3];
    int32_t ws[203 * 3];
    for (uint32_t y = 0; y < 4; ++y) {
        assert_int_equal(qibl_shmap_relight_span(&b.m, &w, 0, y, 203, whole, ws, sizeof ws), QIBL_OK);
        uint32_t x = 0;
        while (x < 203) {
            uint32_t n = 1 + tu_u32(&r) % 40u;
            if (n > 203 - x)
                n = 203 - x;
            assert_int_equal(qibl_shmap_relight_span(&b.m, &w, x, y, n, part + 3 * x, ws, sizeof ws), QIBL_OK);
            x += n;
        }
        assert_memory_equal(whole, part, sizeof whole);
    }
    maps_free(&b);
}

static void test_accumulator_extremes(void **state)
{
    (void)state;
    /* k = 25, every byte 255, every scale at the largest magnitude of either sign: the int16 weights hit
     * +-32767 and the accumulator its proven bound 25 * 255 * 32767 without overflow */
    for (int sign = -1; sign <= 1; sign += 2) {
        maps_buf b;
        tu_rng r = {45};
        maps_make(&b, 8, 1, 25, 1, &r, 2);
        for (uint32_t i = 0; i < 25; ++i) {
            put_s32(b.params + 8u * i, sign * 0x7FFF0000);
            put_s32(b.params + 8u * i + 4u, 0);
        }
        for (size_t i = 0; i < 8u * 25u; ++i)
            b.planes[i] = 255;
        qibl_shlight_t l;
        assert_int_equal(qibl_shlight_init(&l, 25), QIBL_OK);
        for (int ch = 0; ch < 3; ++ch)
            for (int i = 0; i < 25; ++i)
                l.c[ch][i] = 1 << 4; /* tiny light so the sum stays inside Q16.16 */
        qibl_shmap_weights_t w;
        assert_int_equal(qibl_shmap_weights(&b.m, &l, &w), QIBL_OK);
        for (int i = 0; i < 25; ++i)
            assert_int_equal(abs(w.w[0][i]), 32767);
        double e = check_relight(&b.m, &l, NULL);
        assert_true(e <= 1.0);
        /* and a light so bright that the result saturates cleanly instead of wrapping */
        for (int ch = 0; ch < 3; ++ch)
            for (int i = 0; i < 25; ++i)
                l.c[ch][i] = INT32_MAX;
        assert_int_equal(qibl_shmap_weights(&b.m, &l, &w), QIBL_OK);
        int32_t out[24], ws[24];
        assert_int_equal(qibl_shmap_relight_span(&b.m, &w, 0, 0, 8, out, ws, sizeof ws), QIBL_OK);
        for (int i = 0; i < 24; ++i)
            assert_int_equal(out[i], sign > 0 ? INT32_MAX : INT32_MIN);
        maps_free(&b);
    }
}

static void test_relight_errors_write_nothing(void **state)
{
    (void)state;
    tu_rng r = {46};
    maps_buf b;
    maps_make(&b, 16, 2, 4, 3, &r, 1 << 16);
    qibl_shlight_t l;
    assert_int_equal(qibl_shlight_init(&l, 4), QIBL_OK);
    qibl_shmap_weights_t w;
    assert_int_equal(qibl_shmap_weights(&b.m, &l, &w), QIBL_OK);
    int32_t out[16 * 3], ws[16 * 3];
    tu_fill_guard(out, sizeof out);
    assert_int_equal(qibl_shmap_relight_span(&b.m, &w, 0, 2, 16, out, ws, sizeof ws), QIBL_E_SHMAP_BOUNDS);
    assert_int_equal(qibl_shmap_relight_span(&b.m, &w, 1, 0, 16, out, ws, sizeof ws), QIBL_E_SHMAP_BOUNDS);
    assert_int_equal(qibl_shmap_relight_span(&b.m, &w, 17, 0, 0, out, ws, sizeof ws), QIBL_E_SHMAP_BOUNDS);
    assert_int_equal(qibl_shmap_relight_span(&b.m, &w, 0, 0, 16, out, ws, sizeof ws - 1), QIBL_E_WORKSPACE);
    assert_int_equal(qibl_shmap_relight_span(&b.m, &w, 0, 0, 16, out, 0, sizeof ws), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_shmap_relight_span(&b.m, 0, 0, 0, 16, out, ws, sizeof ws), QIBL_E_NULL_POINTER);
    qibl_shmap_weights_t w2 = w;
    w2.k = 5;
    assert_int_equal(qibl_shmap_relight_span(&b.m, &w2, 0, 0, 16, out, ws, sizeof ws), QIBL_E_SHMAP_MISMATCH);
    qibl_shmaps_t bad = b.m;
    bad.k = 0;
    assert_int_equal(qibl_shmap_relight_span(&bad, &w, 0, 0, 16, out, ws, sizeof ws), QIBL_E_SHMAP_K);
    bad = b.m, bad.k = 26;
    assert_int_equal(qibl_shmap_check(&bad), QIBL_E_SHMAP_K);
    bad = b.m, bad.channels = 2;
    assert_int_equal(qibl_shmap_relight_span(&bad, &w, 0, 0, 16, out, ws, sizeof ws), QIBL_E_SHMAP_CHANNELS);
    bad = b.m, bad.width = 0;
    assert_int_equal(qibl_shmap_check(&bad), QIBL_E_SHMAP_SIZE);
    bad = b.m, bad.planes = 0;
    assert_int_equal(qibl_shmap_check(&bad), QIBL_E_NULL_POINTER);
    assert_true(tu_guard_intact(out, sizeof out));
    /* weights: a light with fewer coefficients than the maps */
    qibl_shlight_t l3;
    assert_int_equal(qibl_shlight_init(&l3, 3), QIBL_OK);
    qibl_shmap_weights_t wg;
    tu_fill_guard(&wg, sizeof wg);
    assert_int_equal(qibl_shmap_weights(&b.m, &l3, &wg), QIBL_E_SHMAP_LIGHT_K);
    assert_true(tu_guard_intact(&wg, sizeof wg));
    maps_free(&b);
}

/* ---- point lights ---------------------------------------------------------------------------- */

typedef struct {
    uint8_t *bytes;
    qibl_pmap_t p;
} pmap_buf;

static void pmap_make(pmap_buf *pb, uint32_t w, uint32_t h, tu_rng *r)
{
    pb->bytes = malloc((size_t)w * h * 12u);
    assert_non_null(pb->bytes);
    for (size_t i = 0; i < (size_t)w * h * 3u; ++i) /* points within +-8 units */
        put_s32(pb->bytes + 4u * i, (int32_t)(tu_u32(r) % (16u << 16)) - (8 << 16));
    pb->p.width = w, pb->p.height = h, pb->p.points = pb->bytes;
}

/* double reference of one point-light pixel; y_of(u) gives Y_i at a unit direction */
static double point_ref(const qibl_shmaps_t *m, const qibl_pmap_t *p, const qibl_pointlight_t *pl, uint32_t x,
                        uint32_t y, uint32_t ch, const double *yv, double *dist)
{
    qibl_q16_t pt[3];
    qibl_pmap_point(p, x, y, pt);
    double l[3], d = 0.0;
    for (int j = 0; j < 3; ++j) {
        l[j] = (pl->pos[j] - (double)pt[j]) / Q16;
        d += l[j] * l[j];
    }
    d = sqrt(d);
    *dist = d;
    double md = (pl->min_dist ? pl->min_dist : 256) / Q16;
    double dd = d < md ? md : d;
    double att = pl->falloff == QIBL_FALLOFF_INV_DIST ? 1.0 / dd : 1.0 / (dd * dd);
    uint32_t src = m->channels == 3 ? ch : 0;
    double t = 0.0;
    for (uint32_t i = 0; i < m->k; ++i)
        t += decoded(m, i, src, x, y) * yv[i];
    return t * att * (pl->rgb[ch] / Q16);
}

static void check_point(const qibl_shmaps_t *m, const qibl_pmap_t *p, const qibl_ylut_t *lut,
                        const qibl_pointlight_t *pl, double tol_rel, double *worst_rel)
{
    size_t wsn = qibl_shmap_point_workspace_size(m->k, m->width);
    void *ws = malloc(wsn);
    qibl_shmap_point_t st;
    assert_int_equal(qibl_shmap_point_prepare(m, p, lut, pl, &st), QIBL_OK);
    int32_t *out = malloc(sizeof(int32_t) * 3u * m->width);
    for (uint32_t y = 0; y < m->height; ++y) {
        assert_int_equal(qibl_shmap_point_span(&st, 0, y, m->width, out, ws, wsn), QIBL_OK);
        for (uint32_t x = 0; x < m->width; ++x) {
            qibl_q16_t pt[3];
            qibl_pmap_point(p, x, y, pt);
            double yv[25], dist;
            if (qtool_ref_sh_eval(pl->pos[0] - (double)pt[0], pl->pos[1] - (double)pt[1], pl->pos[2] - (double)pt[2],
                                 5, yv) != 0) {
                assert_true(out[3 * x] == 0 && out[3 * x + 1] == 0 && out[3 * x + 2] == 0);
                continue;
            }
            /* scale of the error: sum_i |T_i| |Y_i| att C0, the size of the terms that were summed */
            for (uint32_t ch = 0; ch < 3; ++ch) {
                double want = point_ref(m, p, pl, x, y, ch, yv, &dist);
                double mag = 0.0;
                uint32_t src = m->channels == 3 ? ch : 0;
                for (uint32_t i = 0; i < m->k; ++i) {
                    /* the largest decoded magnitude of map i sets its rounding unit */
                    double a = fabs(qibl_shmaps_bias(m, i, src) / Q24);
                    double bb = fabs((qibl_shmaps_bias(m, i, src) + 255.0 * qibl_shmaps_scale(m, i, src)) / Q24);
                    mag += (a > bb ? a : bb) * 0.9;
                }
                double md = (pl->min_dist ? pl->min_dist : 256) / Q16, dd = dist < md ? md : dist;
                mag *= (pl->falloff == QIBL_FALLOFF_INV_DIST ? 1.0 / dd : 1.0 / (dd * dd)) * (pl->rgb[ch] / Q16);
                double e = fabs(out[3 * x + ch] / Q16 - want);
                if (fabs(want) * Q16 > 2.1e9)
                    continue;
                double rel = e / (mag + 1e-300);
                if (e > 2.0 / Q16 && rel > *worst_rel)
                    *worst_rel = rel;
                assert_true(e <= 2.0 / Q16 || rel <= tol_rel);
            }
        }
    }
    free(out);
    free(ws);
}

static void test_point_light_direct_and_lut(void **state)
{
    (void)state;
    tu_rng r = {47};
    maps_buf b;
    maps_make(&b, 40, 6, 16, 3, &r, 1 << 16);
    pmap_buf pb;
    pmap_make(&pb, 40, 6, &r);
    qibl_pointlight_t pl = {{1 << 16, -(2 << 16), 3 << 16}, {2 << 16, 1 << 16, 1 << 15}, QIBL_FALLOFF_INV_DIST, 0, 0};
    double w_direct = 0.0, w_lut[3] = {0, 0, 0}, w_near = 0.0;
    check_point(&b.m, &pb.p, NULL, &pl, 4e-4, &w_direct);
    pl.falloff = QIBL_FALLOFF_INV_DIST2;
    check_point(&b.m, &pb.p, NULL, &pl, 4e-4, &w_direct);
    const uint32_t ns[3] = {16, 32, 64};
    const double tol[3] = {0.05, 0.015, 0.004}; /* bilinear LUT error shrinks ~ 1/N^2 */
    for (int li = 0; li < 3; ++li) {
        size_t vs = qibl_ylut_values_size(ns[li], 16);
        uint8_t *vals = malloc(vs);
        assert_int_equal(qibl_ylut_build(ns[li], 16, vals, vs), QIBL_OK);
        qibl_ylut_t lut = {ns[li], 16, vals, vs};
        check_point(&b.m, &pb.p, &lut, &pl, tol[li], &w_lut[li]);
        if (li == 2) { /* nearest texel: error ~ the texel's angular size */
            pl.filter = QIBL_LUT_NEAREST;
            check_point(&b.m, &pb.p, &lut, &pl, 0.2, &w_near);
            pl.filter = QIBL_LUT_BILINEAR;
        }
        free(vals);
    }
    /* QIBL_POINT_POLY: Q2.14 polynomials (a LUT passed is ignored), both falloffs */
    double w_poly = 0.0;
    pl.filter = QIBL_POINT_POLY;
    check_point(&b.m, &pb.p, NULL, &pl, 2e-4, &w_poly);
    pl.falloff = QIBL_FALLOFF_INV_DIST;
    check_point(&b.m, &pb.p, NULL, &pl, 2e-4, &w_poly);
    pl.filter = QIBL_LUT_BILINEAR;
    printf("shmap: point light, max error / sum|T Y| att C0: direct %.2e, LUT 16^2 %.2e, 32^2 %.2e, 64^2 %.2e, "
           "64^2 nearest %.2e, poly Q2.14 %.2e\n", w_direct, w_lut[0], w_lut[1], w_lut[2], w_near, w_poly);
    free(pb.bytes);
    maps_free(&b);
}

/* QIBL_POINT_POLY's prepare-time exponents: bias much larger than scale * 2^13 (scale renormalised),
 * bias zero or far below the scale (bias renormalised), mixed; k = 25 (the int32 bias-sum bound) */
static void test_point_poly_exponents(void **state)
{
    (void)state;
    tu_rng r = {49};
    const int32_t bias_mul[4] = {0, 1, 1 << 14, -128};
    for (int c = 0; c < 4; ++c) {
        maps_buf b;
        maps_make(&b, 24, 3, 25, 3, &r, c == 2 ? 64 : 1 << 16);
        for (uint32_t i = 0; i < 25u * 3u; ++i) {
            int32_t sc = (int32_t)(b.params[8u * i] | b.params[8u * i + 1u] << 8 | b.params[8u * i + 2u] << 16 |
                                   (uint32_t)b.params[8u * i + 3u] << 24);
            put_s32(b.params + 8u * i + 4u, c == 2 ? (int32_t)(tu_u32(&r) % 2000001u) * 1000 - 1000000000
                                                   : sc * bias_mul[c] + (c == 3 ? 7 : 0));
        }
        pmap_buf pb;
        pmap_make(&pb, 24, 3, &r);
        qibl_pointlight_t pl = {{1 << 16, -(2 << 16), 3 << 16}, {3 << 16, 1 << 16, 1 << 14}, QIBL_FALLOFF_INV_DIST,
                                0, QIBL_POINT_POLY};
        double worst = 0.0;
        check_point(&b.m, &pb.p, NULL, &pl, 2e-3, &worst);
        pl.falloff = QIBL_FALLOFF_INV_DIST2;
        check_point(&b.m, &pb.p, NULL, &pl, 2e-3, &worst);
        qibl_shmap_point_t st;
        assert_int_equal(qibl_shmap_point_prepare(&b.m, &pb.p, NULL, &pl, &st), QIBL_OK);
        for (int ch = 0; ch < 3; ++ch) /* the documented range of the bias's relative exponent */
            assert_true(st.pd[ch] >= 1 && st.pd[ch] <= 14);
        free(pb.bytes);
        maps_free(&b);
    }
}

static void test_point_light_hard_cases(void **state)
{
    (void)state;
    tu_rng r = {48};
    maps_buf b;
    maps_make(&b, 4, 1, 9, 1, &r, 1 << 16);
    pmap_buf pb;
    pmap_make(&pb, 4, 1, &r);
    /* pixel 0 exactly at the light, pixel 1 closer than min_dist, pixel 2 at the far end of int32 */
    qibl_q16_t s[3] = {5 << 16, 6 << 16, -(7 << 16)};
    for (int j = 0; j < 3; ++j) {
        put_s32(pb.bytes + 4 * j, s[j]);
        put_s32(pb.bytes + 12 + 4 * j, s[j] + (j == 0 ? 3 : 0));
        put_s32(pb.bytes + 24 + 4 * j, j == 0 ? INT32_MIN : INT32_MAX);
    }
    qibl_pointlight_t pl = {{s[0], s[1], s[2]}, {1 << 16, 1 << 16, 1 << 16}, QIBL_FALLOFF_INV_DIST, 1 << 10, 0};
    double worst = 0.0;
    check_point(&b.m, &pb.p, NULL, &pl, 4e-4, &worst);
    pl.falloff = QIBL_FALLOFF_INV_DIST2;
    check_point(&b.m, &pb.p, NULL, &pl, 4e-4, &worst);
    pl.filter = QIBL_POINT_POLY; /* the same cases through the polynomial mode */
    check_point(&b.m, &pb.p, NULL, &pl, 2e-3, &worst);
    pl.falloff = QIBL_FALLOFF_INV_DIST;
    check_point(&b.m, &pb.p, NULL, &pl, 2e-3, &worst);
    /* light far outside: S at INT32_MIN corner */
    pl.pos[0] = INT32_MIN, pl.pos[1] = INT32_MIN, pl.pos[2] = INT32_MAX;
    check_point(&b.m, &pb.p, NULL, &pl, 2e-3, &worst);
    pl.filter = QIBL_LUT_BILINEAR;
    check_point(&b.m, &pb.p, NULL, &pl, 4e-4, &worst);
    /* errors */
    size_t wsn = qibl_shmap_point_workspace_size(9, 4);
    void *ws = malloc(wsn);
    qibl_shmap_point_t st;
    tu_fill_guard(&st, sizeof st);
    qibl_pointlight_t bad = pl;
    bad.rgb[1] = -1;
    assert_int_equal(qibl_shmap_point_prepare(&b.m, &pb.p, NULL, &bad, &st), QIBL_E_SHMAP_LIGHT);
    bad = pl, bad.min_dist = -5;
    assert_int_equal(qibl_shmap_point_prepare(&b.m, &pb.p, NULL, &bad, &st), QIBL_E_SHMAP_LIGHT);
    bad = pl, bad.falloff = (qibl_falloff_t)7;
    assert_int_equal(qibl_shmap_point_prepare(&b.m, &pb.p, NULL, &bad, &st), QIBL_E_SHMAP_LIGHT);
    bad = pl, bad.filter = (qibl_lut_filter_t)3;
    assert_int_equal(qibl_shmap_point_prepare(&b.m, &pb.p, NULL, &bad, &st), QIBL_E_SHMAP_LIGHT);
    qibl_pmap_t p2 = pb.p;
    p2.width = 5;
    assert_int_equal(qibl_shmap_point_prepare(&b.m, &p2, NULL, &pl, &st), QIBL_E_SHMAP_MISMATCH);
    uint8_t lutv[6 * 4 * 8 * 2];
    qibl_ylut_t small = {2, 8, lutv, sizeof lutv}; /* k 8 < maps' 9 */
    assert_int_equal(qibl_shmap_point_prepare(&b.m, &pb.p, &small, &pl, &st), QIBL_E_SHMAP_MISMATCH);
    assert_int_equal(qibl_shmap_point_prepare(&b.m, &pb.p, NULL, &pl, 0), QIBL_E_NULL_POINTER);
    assert_true(tu_guard_intact(&st, sizeof st));
    assert_int_equal(qibl_shmap_point_prepare(&b.m, &pb.p, NULL, &pl, &st), QIBL_OK);
    int32_t out[12];
    tu_fill_guard(out, sizeof out);
    assert_int_equal(qibl_shmap_point_span(&st, 2, 0, 3, out, ws, wsn), QIBL_E_SHMAP_BOUNDS);
    assert_int_equal(qibl_shmap_point_span(&st, 0, 1, 1, out, ws, wsn), QIBL_E_SHMAP_BOUNDS);
    assert_int_equal(qibl_shmap_point_span(&st, 0, 0, 4, out, ws, wsn - 1), QIBL_E_WORKSPACE);
    assert_int_equal(qibl_shmap_point_span(&st, 0, 0, 4, out, 0, wsn), QIBL_E_NULL_POINTER);
    assert_true(tu_guard_intact(out, sizeof out));
    free(ws);
    free(pb.bytes);
    maps_free(&b);
}

/* ---- cube-map LUT ---------------------------------------------------------------------------- */

static void test_ylut_build_and_lookup(void **state)
{
    (void)state;
    const uint32_t n = 8, k = 25;
    size_t vs = qibl_ylut_values_size(n, k);
    assert_int_equal(vs, 6u * 8 * 8 * 25 * 2);
    uint8_t *v = malloc(vs + 4);
    tu_fill_guard(v, vs + 4);
    assert_int_equal(qibl_ylut_build(n, k, v, vs), QIBL_OK);
    assert_true(tu_guard_intact(v + vs, 4));
    qibl_ylut_t t = {n, k, v, vs};
    /* at every texel centre the lookup returns the texel itself, which is Y there to 2^-14 */
    for (uint32_t f = 0; f < 6; ++f)
        for (uint32_t b = 0; b < n; ++b)
            for (uint32_t a = 0; a < n; ++a) {
                double s = (2.0 * a + 1) / n - 1, tt = (2.0 * b + 1) / n - 1, d[3];
                switch (f) {
                case 0: d[0] = 1, d[1] = -tt, d[2] = -s; break;
                case 1: d[0] = -1, d[1] = -tt, d[2] = s; break;
                case 2: d[0] = s, d[1] = 1, d[2] = tt; break;
                case 3: d[0] = s, d[1] = -1, d[2] = -tt; break;
                case 4: d[0] = s, d[1] = -tt, d[2] = 1; break;
                default: d[0] = -s, d[1] = -tt, d[2] = -1; break;
                }
                double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), yref[25];
                qtool_ref_sh_eval(d[0], d[1], d[2], 5, yref);
                qibl_q30_t u[3];
                for (int j = 0; j < 3; ++j)
                    u[j] = (int32_t)lrint(d[j] / len * 1073741824.0);
                int32_t y14[25];
                qibl_ylut_lookup(&t, u, k, y14);
                const uint8_t *texel = v + (((size_t)f * n + b) * n + a) * k * 2;
                for (uint32_t i = 0; i < k; ++i) {
                    assert_true(fabs(y14[i] - yref[i] * 16384.0) <= 1.0);
                    assert_true(abs(y14[i] - qibl_load_s16le(texel + 2 * i)) <= 1);
                }
            }
    assert_int_equal(qibl_ylut_build(0, k, v, vs), QIBL_E_SHMAP_LUT_SIZE);
    assert_int_equal(qibl_ylut_build(257, k, v, vs), QIBL_E_SHMAP_LUT_SIZE);
    assert_int_equal(qibl_ylut_build(n, 26, v, vs), QIBL_E_SHMAP_K);
    assert_int_equal(qibl_ylut_build(n, k, v, vs - 1), QIBL_E_WORKSPACE);
    assert_int_equal(qibl_ylut_build(n, k, 0, vs), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_ylut_values_size(0, 4), 0);
    free(v);
}

/* ---- goldens: fixed maps, lights and formats -> SHA-256 of the framebuffer bytes --------------- */

/* The fixture (integer-only maps and P map, a sun plus sky, a point light direct / LUT bilinear / LUT
 * nearest, four framebuffer formats) lives in tools/golden/cases_relight.c, shared with the golden
 * runner that `make ports` runs on every architecture. */
/* ---- the interleaved layout ------------------------------------------------------------------ */

/* The interleaved copy of planar maps b (same params). */
static void interleave(const maps_buf *b, maps_buf *il)
{
    il->m = b->m;
    il->m.layout = QIBL_SHMAPS_INTERLEAVED;
    size_t n = qibl_shmaps_row_size(&il->m) * b->m.height;
    il->params = NULL;
    il->planes = malloc(n);
    assert_non_null(il->planes);
    assert_int_equal(qibl_shmaps_interleave(&b->m, il->planes, n), QIBL_OK);
    il->m.planes = il->planes;
}

/* Every row of m under w (directional) or pt (point, if non-NULL) through random span splits. */
static void relight_rows(const qibl_shmaps_t *m, const qibl_shmap_weights_t *w, const qibl_shmap_point_t *pt,
                         tu_rng *r, int32_t *out)
{
    size_t wsn = qibl_shmap_point_workspace_size(25, m->width) + qibl_shmap_span_workspace_size(m->width);
    void *ws = malloc(wsn);
    assert_non_null(ws);
    for (uint32_t y = 0; y < m->height; ++y)
        for (uint32_t x = 0; x < m->width;) {
            uint32_t n = 1 + tu_u32(r) % 37u;
            n = n > m->width - x ? m->width - x : n;
            int32_t *o = out + 3u * ((size_t)y * m->width + x);
            if (pt)
                assert_int_equal(qibl_shmap_point_span(pt, x, y, n, o, ws, wsn), QIBL_OK);
            else
                assert_int_equal(qibl_shmap_relight_span(m, w, x, y, n, o, ws, wsn), QIBL_OK);
            x += n;
        }
    free(ws);
}

/* The kernel path config.h chose (QIBL_CONFIG_SIMD: SSE2/AVX2/NEON in the native flavour, scalar C
 * in the portable one) against the definition, computed here in int64 from the bytes: random maps,
 * weights, spans and every branch of the final scaling (shift -40..38: fast int32 path with left
 * shift, rounded right shift, the shift <= -31 constant; the exact 64-bit paths for a bias beyond
 * +-2^30 and a shift above 2; the saturating shift above 30). */
static int32_t exact_out(int64_t acc, int32_t shift, int64_t bias)
{
    int64_t v;
    if (shift > 30)
        return acc > 0 ? INT32_MAX : acc < 0 ? INT32_MIN : bias > INT32_MAX ? INT32_MAX : bias < INT32_MIN ? INT32_MIN : (int32_t)bias;
    if (shift >= 0)
        v = acc * ((int64_t)1 << shift) + bias;
    else {
        int64_t d = (int64_t)1 << -shift, t = acc + d / 2; /* round half up: floor((acc + d/2) / d) */
        v = (t >= 0 ? t / d : -((-t + d - 1) / d)) + bias;
    }
    return v > INT32_MAX ? INT32_MAX : v < INT32_MIN ? INT32_MIN : (int32_t)v;
}

static void test_kernel_path_matches_definition(void **state)
{
    (void)state;
    tu_rng r = {1606};
    static const int64_t bmag[4] = {1000, (int64_t)1 << 30, ((int64_t)1 << 30) + 1, (int64_t)1 << 40};
    for (int it = 0; it < 300; ++it) {
        uint32_t w = 1 + tu_u32(&r) % 80u, h = 1 + tu_u32(&r) % 2u, k = 1 + tu_u32(&r) % 25u;
        uint32_t ch = (it & 1) ? 3u : 1u;
        maps_buf b, il;
        maps_make(&b, w, h, k, ch, &r, 1 << 16);
        interleave(&b, &il);
        qibl_shmap_weights_t wt;
        wt.k = k, wt.channels = ch;
        for (uint32_t c = 0; c < 3u; ++c) {
            for (uint32_t i = 0; i < (uint32_t)QIBL_SH_MAX_COUNT; ++i) /* extremes now and then */
                wt.w[c][i] = i >= k ? 0 : (int16_t)(tu_u32(&r) % 8u == 0 ? ((tu_u32(&r) & 1u) ? 32767 : -32767)
                                                                       : (int32_t)(tu_u32(&r) % 65535u) - 32767);
            /* mostly the fast path (-30..2), else anything in -40..38 */
            wt.shift[c] = (it % 4 != 3) ? (int32_t)(tu_u32(&r) % 33u) - 30 : (int32_t)(tu_u32(&r) % 79u) - 40;
            int64_t bm = bmag[(it / 4) % 4], bv = (int64_t)(tu_u32(&r) % 2001u) - 1000;
            wt.bias[c] = bm > 1000 ? ((tu_u32(&r) & 1u) ? bm : -bm) + bv : bv;
        }
        size_t n = (size_t)w * h * 3u;
        int32_t *o1 = malloc(n * 4u), *o2 = malloc(n * 4u);
        assert_non_null(o1);
        assert_non_null(o2);
        relight_rows(&il.m, &wt, NULL, &r, o1);
        relight_rows(&b.m, &wt, NULL, &r, o2);
        for (uint32_t y = 0; y < h; ++y)
            for (uint32_t x = 0; x < w; ++x)
                for (uint32_t c = 0; c < 3u; ++c) {
                    uint32_t src = ch == 3u ? c : 0u;
                    int64_t acc = 0;
                    for (uint32_t i = 0; i < k; ++i)
                        acc += (int64_t)wt.w[c][i] * qibl_shmaps_plane(&b.m, i, src)[(size_t)y * w + x];
                    int32_t want = exact_out(acc, wt.shift[c], wt.bias[c]);
                    size_t at = 3u * ((size_t)y * w + x) + c;
                    if (o1[at] != want || o2[at] != want)
                        fail_msg("it %d k %u x %u ch %u shift %d bias %lld: interleaved %d planar %d, want %d", it, k,
                                 x, c, wt.shift[c], (long long)wt.bias[c], o1[at], o2[at], want);
                }
        free(o1), free(o2), free(il.planes);
        maps_free(&b);
    }
}

/* The directional kernels under every dispatch choice this CPU runs (qtool_isa_force) against the
 * scalar twin, bit for bit, on both layouts: every k (the AVX2 interleaved kernel's written-out
 * pairs and an odd k's last map), one and three channels, spans starting and ending anywhere in a
 * group (the whole-group path with its rounding term in the accumulators, and partial groups
 * through the workspace), every branch of the final scaling (left shifts, shift 0, rounded right
 * shifts, biases beyond +-2^30, saturation), the accumulator bound (bytes 255 under +-32767 and
 * -32768) and nothing written past the span. */
static void test_directional_every_isa(void **state)
{
    (void)state;
    const uint32_t have = qibl_isa_available();
    static const int32_t shifts[] = {2, 1, 0, -1, -9, -30, -31, 3, 31};
    int runs = 0;
    for (unsigned isa = 0; isa < QIBL_ISA_COUNT; ++isa) {
        if (!(have & QIBL_ISA_BIT(isa)))
            continue;
        qtool_isa_force(QIBL_ISA_BIT(isa));
        tu_rng r = {0xD1E5u}; /* the same cases for every choice */
        for (uint32_t k = 1; k <= (uint32_t)QIBL_SH_MAX_COUNT; ++k)
            for (uint32_t chn = 1; chn <= 3u; chn += 2u) {
                const uint32_t w = 53, h = 2;
                maps_buf b, il;
                maps_make(&b, w, h, k, chn, &r, 1 << 16);
                if (k % 4u == 1u) /* the bound: every byte 255 */
                    memset(b.planes, 255, (size_t)w * h * k * chn);
                interleave(&b, &il);
                for (size_t si = 0; si < sizeof shifts / sizeof shifts[0]; ++si) {
                    qibl_shmap_weights_t wt;
                    memset(&wt, 0, sizeof wt);
                    wt.k = k, wt.channels = chn;
                    for (uint32_t c = 0; c < 3u; ++c) {
                        for (uint32_t i = 0; i < k; ++i)
                            wt.w[c][i] = k % 4u == 1u ? (int16_t)((i + c + si) % 3u == 0u ? -32768 : 32767)
                                                      : (int16_t)((int32_t)(tu_u32(&r) % 65536u) - 32768);
                        wt.shift[c] = shifts[(si + c * (si / 7u)) % (sizeof shifts / sizeof shifts[0])];
                        wt.bias[c] = (int64_t)(tu_u32(&r) % 2001u) - 1000;
                    }
                    if (si == 5u)
                        wt.bias[1] = ((int64_t)1 << 30) + 1; /* beyond the int32 path */
                    size_t wsn = qibl_shmap_span_workspace_size(w);
                    void *ws = malloc(wsn);
                    int32_t oa[3 * 53 + 3], ob[3 * 53 + 3];
                    assert_non_null(ws);
                    for (int lay = 0; lay < 2; ++lay) {
                        const qibl_shmaps_t *m = lay ? &il.m : &b.m;
                        for (uint32_t y = 0; y < h; ++y)
                            for (uint32_t x0 = 0; x0 < 20u; x0 += 1u + x0 / 4u) {
                                const uint32_t n = w - x0 - (x0 * 7u) % 18u;
                                memset(oa, 0x5A, sizeof oa), memset(ob, 0x5A, sizeof ob);
                                assert_int_equal(qibl_shmap_relight_span(m, &wt, x0, y, n, oa, ws, wsn), QIBL_OK);
                                assert_int_equal(qtool_shmap_relight_span_scalar(m, &wt, x0, y, n, ob, ws, wsn),
                                                 QIBL_OK);
                                for (uint32_t i = 0; i < 3u * n; ++i)
                                    if (oa[i] != ob[i])
                                        fail_msg("isa %u k %u ch %u layout %d shift %d y %u x %u ch %u: %d, twin %d",
                                                 isa, k, chn, lay, wt.shift[i % 3u], y, x0 + i / 3u, i % 3u, oa[i],
                                                 ob[i]);
                                assert_int_equal(oa[3u * n], 0x5A5A5A5A); /* nothing past the span */
                            }
                    }
                    free(ws);
                }
                free(il.planes);
                maps_free(&b);
            }
        ++runs;
    }
    qtool_isa_force(0u);
    assert_true(runs >= 1);
}

/* The planar SIMD passes (8 planes each, 16 pixels a step, the last n % 16 pixels apart) against the
 * definition: every k, planes a multiple of 4 KiB apart (4096-pixel rows), whole rows and spans at
 * odd offsets, the accumulator bound itself (all bytes 255 under +-32767) and random bytes, on
 * the fast final scaling and a random one. */
static void test_planar_passes_match_definition(void **state)
{
    (void)state;
    tu_rng r = {2816};
    const uint32_t w = 4096u;
    int32_t *o = malloc((size_t)w * 3u * 4u);
    void *ws = malloc(qibl_shmap_span_workspace_size(w));
    assert_non_null(o);
    assert_non_null(ws);
    for (uint32_t k = 1; k <= (uint32_t)QIBL_SH_MAX_COUNT; ++k) {
        maps_buf b;
        maps_make(&b, w, 1, k, 3, &r, 1 << 16);
        const int extreme = k % 3 == 0;
        if (extreme)
            memset(b.planes, 255, (size_t)w * k * 3u);
        qibl_shmap_weights_t wt;
        wt.k = k, wt.channels = 3;
        for (uint32_t c = 0; c < 3u; ++c) {
            for (uint32_t i = 0; i < (uint32_t)QIBL_SH_MAX_COUNT; ++i)
                wt.w[c][i] = i >= k ? 0 : extreme ? (c == 1 ? -32767 : 32767) : (int16_t)((int32_t)(tu_u32(&r) % 65535u) - 32767);
            wt.shift[c] = k % 2 ? -(int32_t)(tu_u32(&r) % 20u) : (int32_t)(tu_u32(&r) % 43u) - 40;
            wt.bias[c] = (int64_t)(tu_u32(&r) % 2001u) - 1000;
        }
        const uint32_t x0 = k % 2 ? 0u : 1u + tu_u32(&r) % 37u, n = k % 2 ? w : w - x0 - tu_u32(&r) % 29u;
        assert_int_equal(qibl_shmap_relight_span(&b.m, &wt, x0, 0, n, o, ws, qibl_shmap_span_workspace_size(w)), QIBL_OK);
        for (uint32_t x = 0; x < n; ++x)
            for (uint32_t c = 0; c < 3u; ++c) {
                int64_t acc = 0;
                for (uint32_t i = 0; i < k; ++i)
                    acc += (int64_t)wt.w[c][i] * qibl_shmaps_plane(&b.m, i, c)[x0 + x];
                const int32_t want = exact_out(acc, wt.shift[c], wt.bias[c]);
                if (o[3u * x + c] != want)
                    fail_msg("k %u x0 %u x %u ch %u shift %d: %d, want %d", k, x0, x, c, wt.shift[c], o[3u * x + c], want);
            }
        maps_free(&b);
    }
    free(o), free(ws);
}

/* The portable planar kernel (QIBL_CONFIG_SIMD=0, the -portable flavour of this suite; the SIMD
 * flavours run it as their planar path's twin too): eight pixels a step from aligned 32-bit words,
 * one pixel at a time up to the first aligned word, four-pixel byte steps when the plane stride is
 * not a multiple of 4, the last pixels one by one, the fast final scaling in the kernel and the raw
 * sums for any other shift or bias. Plane bases 0..3 bytes past an aligned address, strides
 * w * h * channels both multiples of 4 and not, spans at every offset, the accumulator bound (all
 * bytes 255 under +-32767), against the definition; the values around the span stay untouched. */
static void test_planar_kernel_alignment_and_strides(void **state)
{
    (void)state;
    tu_rng r = {8421};
    static const uint32_t dims[][2] = {{24, 2}, {13, 3}, {40, 1}, {37, 2}, {64, 3}, {9, 1}};
    for (int it = 0; it < 240; ++it) {
        const uint32_t w = dims[it % 6][0], h = dims[it % 6][1], k = 1u + tu_u32(&r) % 25u;
        const uint32_t ch = (it / 6) % 2 ? 3u : 1u, lead = (uint32_t)(it / 12) % 4u;
        maps_buf b;
        maps_make(&b, w, h, k, ch, &r, 1 << 16);
        const size_t bytes = (size_t)w * h * k * ch;
        const int extreme = it % 5 == 4;
        if (extreme)
            memset(b.planes, 255, bytes);
        /* the same bytes lead bytes past an aligned base */
        uint32_t *store = malloc(bytes + 8u);
        assert_non_null(store);
        uint8_t *moved = (uint8_t *)store + lead;
        memcpy(moved, b.planes, bytes);
        qibl_shmaps_t m = b.m;
        m.planes = moved;
        qibl_shmap_weights_t wt;
        wt.k = k, wt.channels = ch;
        for (uint32_t c = 0; c < 3u; ++c) {
            for (uint32_t i = 0; i < (uint32_t)QIBL_SH_MAX_COUNT; ++i)
                wt.w[c][i] = i >= k ? 0
                             : extreme ? (c == 1u ? -32767 : 32767)
                                       : (int16_t)((int32_t)(tu_u32(&r) % 65535u) - 32767);
            /* shifts -31..3 (fast path -30..-1, raw path otherwise), biases in and out of +-2^30 */
            wt.shift[c] = (int32_t)(tu_u32(&r) % 35u) - 31;
            const int64_t big = (int64_t)1 << 30;
            wt.bias[c] = it % 7 == 6 ? ((tu_u32(&r) & 1u) ? big + 1 : -big - 1) : (int64_t)(tu_u32(&r) % 2001u) - 1000;
        }
        const uint32_t y = tu_u32(&r) % h, x0 = tu_u32(&r) % w, n = tu_u32(&r) % (w - x0 + 1u);
        int32_t out[3 * 64 + 6];
        int32_t ws[3 * 64];
        for (size_t i = 0; i < sizeof out / sizeof out[0]; ++i)
            out[i] = 0x5EED;
        assert_int_equal(qibl_shmap_relight_span(&m, &wt, x0, y, n, out + 3, ws, sizeof ws), QIBL_OK);
        for (uint32_t x = 0; x < n; ++x)
            for (uint32_t c = 0; c < 3u; ++c) {
                const uint32_t src = ch == 3u ? c : 0u;
                int64_t acc = 0;
                for (uint32_t i = 0; i < k; ++i)
                    acc += (int64_t)wt.w[c][i] * qibl_shmaps_plane(&m, i, src)[(size_t)y * w + x0 + x];
                const int32_t want = exact_out(acc, wt.shift[c], wt.bias[c]);
                if (out[3u + 3u * x + c] != want)
                    fail_msg("it %d %ux%u k %u ch %u lead %u x0 %u x %u c %u shift %d bias %lld: %d, want %d", it, w, h,
                             k, ch, lead, x0, x, c, wt.shift[c], (long long)wt.bias[c], out[3u + 3u * x + c], want);
            }
        for (uint32_t i = 0; i < 3u; ++i)
            assert_int_equal(out[i], 0x5EED);
        for (size_t i = 3u + 3u * n; i < sizeof out / sizeof out[0]; ++i)
            assert_int_equal(out[i], 0x5EED);
        free(store);
        maps_free(&b);
    }
}

/* ---- the point kernel's SIMD path against its scalar twin -------------------------------------- */

/* qibl_shmap_point_span (the library's QIBL_CONFIG_SIMD path) and the scalar twin (tools/twin) give
 * the same int32 outputs over random maps, lights and spans, on both layouts, both falloffs, every
 * k, with the rare lanes in the spans: the light on a surface point, closer than min_dist, S - P
 * needing 33 bits, and outputs that saturate or leave the final scaling's common case. */
static void test_point_simd_equals_scalar_twin(void **state)
{
    (void)state;
    tu_rng r = {0x9017};
    static const uint32_t ks[] = {1, 4, 9, 16, 25};
    const uint32_t w = 53, h = 2;
    for (size_t ki = 0; ki < sizeof ks / sizeof ks[0]; ++ki)
        for (uint32_t chn = 1; chn <= 3; chn += 2)
            for (int mag = 0; mag < 2; ++mag) {
                maps_buf b, il;
                maps_make(&b, w, h, ks[ki], chn, &r, mag ? 1 << 22 : 64);
                interleave(&b, &il);
                pmap_buf pb;
                pmap_make(&pb, w, h, &r);
                for (int lt = 0; lt < 6; ++lt) {
                    qibl_pointlight_t pl = {{(int32_t)(tu_u32(&r) % (16u << 16)) - (8 << 16),
                                             (int32_t)(tu_u32(&r) % (16u << 16)) - (8 << 16), 3 << 16},
                                            {(int32_t)(tu_u32(&r) % (4u << 16)), 1 << 16, 1 << 12},
                                            (lt & 1) ? QIBL_FALLOFF_INV_DIST2 : QIBL_FALLOFF_INV_DIST,
                                            (lt & 2) ? 1 << 14 : 0, QIBL_POINT_POLY};
                    if (lt == 4) /* far corner: S - P needs 33 bits for most pixels */
                        pl.pos[0] = INT32_MIN, pl.pos[1] = INT32_MAX, pl.pos[2] = INT32_MIN;
                    if (lt == 5) /* huge colour: saturation and the scaling's rare branches */
                        pl.rgb[0] = INT32_MAX, pl.rgb[1] = 1 << 30, pl.rgb[2] = 1;
                    /* rare points: on the light, 1 LSB from it, and at the int32 corner */
                    for (int j = 0; j < 3; ++j) {
                        put_s32(pb.bytes + 12u * 9u + 4u * (unsigned)j, pl.pos[j]);
                        put_s32(pb.bytes + 12u * 20u + 4u * (unsigned)j,
                                j != 1 ? pl.pos[j] : pl.pos[j] > 0 ? pl.pos[j] - 1 : pl.pos[j] + 1);
                        put_s32(pb.bytes + 12u * 33u + 4u * (unsigned)j, j == 1 ? INT32_MIN : INT32_MAX);
                    }
                    for (int lay = 0; lay < 2; ++lay) {
                        const qibl_shmaps_t *m = lay ? &il.m : &b.m;
                        qibl_shmap_point_t sa, sb;
                        assert_int_equal(qibl_shmap_point_prepare(m, &pb.p, NULL, &pl, &sa), QIBL_OK);
                        assert_int_equal(qtool_shmap_point_prepare_scalar(m, &pb.p, NULL, &pl, &sb), QIBL_OK);
                        size_t wsn = qibl_shmap_point_workspace_size(m->k, w);
                        void *ws = malloc(wsn);
                        int32_t oa[3 * 53 + 3], ob[3 * 53 + 3];
                        assert_non_null(ws);
                        for (uint32_t y = 0; y < h; ++y)
                            for (uint32_t x0 = 0; x0 < 11u; x0 += 1u + x0 / 3u) {
                                const uint32_t n = w - x0 - (x0 % 4u);
                                memset(oa, 0x5A, sizeof oa), memset(ob, 0x5A, sizeof ob);
                                assert_int_equal(qibl_shmap_point_span(&sa, x0, y, n, oa, ws, wsn), QIBL_OK);
                                assert_int_equal(qtool_shmap_point_span_scalar(&sb, x0, y, n, ob, ws, wsn), QIBL_OK);
                                for (uint32_t i = 0; i < 3u * n; ++i)
                                    if (oa[i] != ob[i])
                                        fail_msg("k %u ch %u light %d layout %d y %u x %u ch %u: SIMD %d scalar %d",
                                                 m->k, chn, lt, lay, y, x0 + i / 3u, i % 3u, oa[i], ob[i]);
                                assert_int_equal(oa[3u * n], ob[3u * n]); /* nothing past the span */
                            }
                        free(ws);
                    }
                }
                free(pb.bytes);
                maps_free(&b);
                free(il.planes);
            }
}

/* The AVX2 point kernel splits each int16 scale factor as sn = 2^8 a + b (b its low byte, signed)
 * and sums a c and b c in int32 groups of ten maps: factors at every edge of that split (+-32767,
 * low bytes 0x80 and 0x7F, 0, +-1), all map bytes 255 or random, lights all around the points (so
 * Y takes its largest sums), k up to 25 on both layouts: the same int32 outputs as the scalar twin. */
static void test_point_simd_extreme_factors(void **state)
{
    (void)state;
    tu_rng r = {0x5EED};
    static const int32_t edge[] = {32767, -32767, -32640, 32640, 32639, -32641, 127, -128, -129, 128, 1, -1, 0, 255, -256};
    static const uint32_t ks[] = {9, 10, 11, 16, 21, 25};
    const uint32_t w = 77, h = 2, ne = sizeof edge / sizeof edge[0];
    for (size_t ki = 0; ki < sizeof ks / sizeof ks[0]; ++ki)
        for (int fill = 0; fill < 2; ++fill) {
            const uint32_t k = ks[ki];
            maps_buf b, il;
            maps_make(&b, w, h, k, 3, &r, 64);
            for (uint32_t i = 0; i < k * 3u; ++i) { /* scales in Q8.24 equal to the int16 factors */
                const int32_t sc = i % 3u == 0u ? edge[(i / 3u) % ne] : edge[(i / 3u + i % 3u + ki) % ne];
                put_s32(b.params + 8u * i, sc);
                put_s32(b.params + 8u * i + 4u, (int32_t)(tu_u32(&r) % 2001u) - 1000);
            }
            put_s32(b.params, 32767); /* the largest factor 32767: no renormalisation */
            for (size_t i = 0; i < (size_t)w * h * k * 3u; ++i)
                b.planes[i] = fill ? (uint8_t)tu_u32(&r) : 255u;
            interleave(&b, &il);
            pmap_buf pb;
            pmap_make(&pb, w, h, &r);
            for (int lt = 0; lt < 12; ++lt) {
                qibl_pointlight_t pl = {{(int32_t)(tu_u32(&r) % (24u << 16)) - (12 << 16),
                                         (int32_t)(tu_u32(&r) % (24u << 16)) - (12 << 16),
                                         (int32_t)(tu_u32(&r) % (24u << 16)) - (12 << 16)},
                                        {1 << 16, 3 << 15, 1 << 14},
                                        (lt & 1) ? QIBL_FALLOFF_INV_DIST2 : QIBL_FALLOFF_INV_DIST, 0, QIBL_POINT_POLY};
                for (int lay = 0; lay < 2; ++lay) {
                    const qibl_shmaps_t *m = lay ? &il.m : &b.m;
                    qibl_shmap_point_t sa, sb;
                    assert_int_equal(qibl_shmap_point_prepare(m, &pb.p, NULL, &pl, &sa), QIBL_OK);
                    assert_int_equal(qtool_shmap_point_prepare_scalar(m, &pb.p, NULL, &pl, &sb), QIBL_OK);
                    size_t wsn = qibl_shmap_point_workspace_size(k, w);
                    void *ws = malloc(wsn);
                    int32_t oa[3 * 77], ob[3 * 77];
                    assert_non_null(ws);
                    for (uint32_t y = 0; y < h; ++y) {
                        assert_int_equal(qibl_shmap_point_span(&sa, 0, y, w, oa, ws, wsn), QIBL_OK);
                        assert_int_equal(qtool_shmap_point_span_scalar(&sb, 0, y, w, ob, ws, wsn), QIBL_OK);
                        for (uint32_t i = 0; i < 3u * w; ++i)
                            if (oa[i] != ob[i])
                                fail_msg("k %u fill %d light %d layout %d y %u x %u ch %u: SIMD %d scalar %d", k, fill,
                                         lt, lay, y, i / 3u, i % 3u, oa[i], ob[i]);
                    }
                    free(ws);
                }
            }
            free(pb.bytes);
            maps_free(&b);
            free(il.planes);
        }
}

/* The int32 groups' bound itself: every point at the origin, the light along the direction d
 * (of 4000 random ones) with the largest sum |Y_i(d)|, every factor +-32767 with Y_i(d)'s sign and
 * every byte 255, so each group's sum is near its bound (one int32 sum over all 25 maps would wrap):
 * the same outputs as the scalar twin. */
static void test_point_simd_aligned_sums(void **state)
{
    (void)state;
    tu_rng r = {0xA11};
    static const uint32_t ks[] = {16, 25};
    const uint32_t w = 40, h = 1;
    for (size_t ki = 0; ki < sizeof ks / sizeof ks[0]; ++ki) {
        const uint32_t k = ks[ki];
        const int bands = k > 16u ? 5 : 4;
        qibl_q16_t best[3] = {0, 0, 1 << 16};
        int64_t best_sum = -1;
        for (int it = 0; it < 4000; ++it) {
            qibl_q16_t d[3] = {tu_s32(&r) >> 8, tu_s32(&r) >> 8, tu_s32(&r) >> 8};
            qibl_q30_t yv[QIBL_SH_MAX_COUNT];
            if (qibl_sh_eval(d, bands, yv) != QIBL_OK)
                continue;
            int64_t sum = 0;
            for (uint32_t i = 0; i < k; ++i)
                sum += yv[i] < 0 ? -(int64_t)yv[i] : yv[i];
            if (sum > best_sum)
                best_sum = sum, best[0] = d[0], best[1] = d[1], best[2] = d[2];
        }
        qibl_q30_t yb[QIBL_SH_MAX_COUNT];
        assert_int_equal(qibl_sh_eval(best, bands, yb), QIBL_OK);
        maps_buf b;
        maps_make(&b, w, h, k, 3, &r, 64);
        for (uint32_t i = 0; i < k * 3u; ++i) {
            put_s32(b.params + 8u * i, yb[i / 3u] < 0 ? -32767 : 32767);
            put_s32(b.params + 8u * i + 4u, 0);
        }
        memset(b.planes, 255, (size_t)w * h * k * 3u);
        pmap_buf pb;
        pmap_make(&pb, w, h, &r);
        memset(pb.bytes, 0, (size_t)w * h * 12u);
        /* the light 4 units along best (best's largest component is at least 2^15 in Q16.16) */
        qibl_pointlight_t pl = {{best[0] / 4, best[1] / 4, best[2] / 4}, {1 << 16, 1 << 16, 1 << 16},
                                QIBL_FALLOFF_INV_DIST, 0, QIBL_POINT_POLY};
        qibl_shmap_point_t sa, sb;
        assert_int_equal(qibl_shmap_point_prepare(&b.m, &pb.p, NULL, &pl, &sa), QIBL_OK);
        assert_int_equal(qtool_shmap_point_prepare_scalar(&b.m, &pb.p, NULL, &pl, &sb), QIBL_OK);
        size_t wsn = qibl_shmap_point_workspace_size(k, w);
        void *ws = malloc(wsn);
        int32_t oa[3 * 40], ob[3 * 40];
        assert_non_null(ws);
        assert_int_equal(qibl_shmap_point_span(&sa, 0, 0, w, oa, ws, wsn), QIBL_OK);
        assert_int_equal(qtool_shmap_point_span_scalar(&sb, 0, 0, w, ob, ws, wsn), QIBL_OK);
        for (uint32_t i = 0; i < 3u * w; ++i)
            if (oa[i] != ob[i])
                fail_msg("k %u x %u ch %u: SIMD %d scalar %d", k, i / 3u, i % 3u, oa[i], ob[i]);
        free(ws);
        free(pb.bytes);
        maps_free(&b);
    }
}

/* The point kernel under every dispatch choice this CPU runs (qtool_isa_force) against the scalar
 * twin, bit for bit: spans of up to 150 pixels, so the AVX-512 kernel's blocks of four 16-pixel
 * chunks run whole and partial, heads (interleaved: up to the next 16-pixel group) and tails of
 * every length 0..15, and rare lanes at a chunk's first and last lane and several in one chunk
 * (the light on the point, S - P needing 33 bits, a light closer than min_dist, a huge colour whose
 * scaling leaves the common case), each redone alone while its neighbours stay in the vector path,
 * and directions whose scaled components reach 2^15. */
static void test_point_every_isa(void **state)
{
    (void)state;
    const uint32_t have = qibl_isa_available();
    static const uint32_t ks[] = {1, 4, 9, 11, 16, 25};
    static const uint32_t rare_at[] = {16, 31, 47, 48, 66, 67, 75, 120};
    const uint32_t w = 150, h = 1;
    int runs = 0;
    for (unsigned isa = 0; isa < QIBL_ISA_COUNT; ++isa) {
        if (!(have & QIBL_ISA_BIT(isa)))
            continue;
        qtool_isa_force(QIBL_ISA_BIT(isa));
        tu_rng r = {0x16A5u}; /* the same cases for every choice */
        for (size_t ki = 0; ki < sizeof ks / sizeof ks[0]; ++ki)
            for (uint32_t chn = 1; chn <= 3u; chn += 2u) {
                maps_buf b, il;
                maps_make(&b, w, h, ks[ki], chn, &r, ki & 1u ? 1 << 22 : 64);
                interleave(&b, &il);
                pmap_buf pb;
                pmap_make(&pb, w, h, &r);
                for (int lt = 0; lt < 4; ++lt) {
                    qibl_pointlight_t pl = {{(int32_t)(tu_u32(&r) % (16u << 16)) - (8 << 16),
                                             (int32_t)(tu_u32(&r) % (16u << 16)) - (8 << 16), 2 << 16},
                                            {(int32_t)(tu_u32(&r) % (4u << 16)), 1 << 16, 1 << 12},
                                            (lt & 1) ? QIBL_FALLOFF_INV_DIST2 : QIBL_FALLOFF_INV_DIST,
                                            (lt & 2) ? 1 << 15 : 0, QIBL_POINT_POLY};
                    if (lt == 3) /* the scaling's rare branches in every lane of some chunks */
                        pl.rgb[0] = INT32_MAX;
                    for (size_t ri = 0; ri < sizeof rare_at / sizeof rare_at[0]; ++ri)
                        for (int j = 0; j < 3; ++j) {
                            /* on the light; S - P needing 33 bits; closer than min_dist */
                            const int32_t v = ri % 3u == 0u   ? pl.pos[j]
                                              : ri % 3u == 1u ? (j == 0 ? INT32_MIN : INT32_MAX)
                                                              : pl.pos[j] + (j == 2 ? 7 : 0);
                            put_s32(pb.bytes + 12u * rare_at[ri] + 4u * (unsigned)j, v);
                        }
                    /* |L| scaled to 2^15 in one and in two components (L = -(2^17 - 1) floors to -2^15:
                     * the squares' int16 edge, d2 = 2^30 and 2^31) */
                    for (int j = 0; j < 3; ++j) {
                        put_s32(pb.bytes + 12u * 100u + 4u * (unsigned)j, pl.pos[j] + (j == 0 ? 131071 : 0));
                        put_s32(pb.bytes + 12u * 101u + 4u * (unsigned)j, pl.pos[j] + (j < 2 ? 131071 : 0));
                    }
                    for (int lay = 0; lay < 2; ++lay) {
                        const qibl_shmaps_t *m = lay ? &il.m : &b.m;
                        qibl_shmap_point_t sa, sb;
                        assert_int_equal(qibl_shmap_point_prepare(m, &pb.p, NULL, &pl, &sa), QIBL_OK);
                        assert_int_equal(qtool_shmap_point_prepare_scalar(m, &pb.p, NULL, &pl, &sb), QIBL_OK);
                        size_t wsn = qibl_shmap_point_workspace_size(m->k, w);
                        void *ws = malloc(wsn);
                        int32_t oa[3 * 150 + 3], ob[3 * 150 + 3];
                        assert_non_null(ws);
                        for (uint32_t x0 = 0; x0 < 40u; x0 += 1u + x0 / 2u) {
                            const uint32_t n = w - x0 - (x0 * 5u) % 16u;
                            memset(oa, 0x5A, sizeof oa), memset(ob, 0x5A, sizeof ob);
                            assert_int_equal(qibl_shmap_point_span(&sa, x0, 0, n, oa, ws, wsn), QIBL_OK);
                            assert_int_equal(qtool_shmap_point_span_scalar(&sb, x0, 0, n, ob, ws, wsn), QIBL_OK);
                            for (uint32_t i = 0; i < 3u * n; ++i)
                                if (oa[i] != ob[i])
                                    fail_msg("isa %u k %u ch %u light %d layout %d x0 %u x %u ch %u: %d, twin %d", isa,
                                             m->k, chn, lt, lay, x0, x0 + i / 3u, i % 3u, oa[i], ob[i]);
                            assert_int_equal(oa[3u * n], 0x5A5A5A5A); /* nothing past the span */
                        }
                        free(ws);
                    }
                }
                free(pb.bytes);
                free(il.planes);
                maps_free(&b);
            }
        ++runs;
    }
    qtool_isa_force(0u);
    assert_true(runs >= 1);
}

static void test_interleaved_equals_planar(void **state)
{
    (void)state;
    tu_rng r = {48};
    static const int32_t mags[4] = {2, 1 << 8, 1 << 16, 1 << 23};
    for (int it = 0; it < 120; ++it) {
        uint32_t w = 1 + tu_u32(&r) % 70u, h = 1 + tu_u32(&r) % 3u, k = 1 + tu_u32(&r) % 25u;
        uint32_t ch = (it & 1) ? 3u : 1u;
        maps_buf b, il;
        maps_make(&b, w, h, k, ch, &r, mags[it % 4]);
        interleave(&b, &il);
        size_t n = (size_t)w * h * 3u;
        int32_t *o1 = malloc(n * 4u), *o2 = malloc(n * 4u);
        assert_non_null(o1);
        assert_non_null(o2);
        /* directional: a dim, a normal and a saturating light (every finishing path) */
        qibl_shlight_t l;
        assert_int_equal(qibl_shlight_init(&l, k), QIBL_OK);
        for (uint32_t c = 0; c < 3; ++c)
            for (uint32_t i = 0; i < k; ++i)
                l.c[c][i] = it % 3 == 0 ? tu_s32(&r) >> 20 : it % 3 == 1 ? tu_s32(&r) >> 12 : tu_s32(&r);
        qibl_shmap_weights_t wp, wi;
        assert_int_equal(qibl_shmap_weights(&b.m, &l, &wp), QIBL_OK);
        assert_int_equal(qibl_shmap_weights(&il.m, &l, &wi), QIBL_OK);
        assert_memory_equal(wp.w, wi.w, sizeof wp.w);
        assert_memory_equal(wp.shift, wi.shift, sizeof wp.shift);
        assert_memory_equal(wp.bias, wi.bias, sizeof wp.bias);
        relight_rows(&b.m, &wp, NULL, &r, o1);
        relight_rows(&il.m, &wi, NULL, &r, o2);
        assert_memory_equal(o1, o2, n * 4u);
        /* point light: direct SH and a bilinear or nearest LUT */
        pmap_buf pb;
        pmap_make(&pb, w, h, &r);
        size_t vs = qibl_ylut_values_size(8, k);
        uint8_t *vals = malloc(vs);
        assert_int_equal(qibl_ylut_build(8, k, vals, vs), QIBL_OK);
        qibl_ylut_t lut = {8, k, vals, vs};
        qibl_pointlight_t pl = {{tu_s32(&r) >> 12, tu_s32(&r) >> 12, tu_s32(&r) >> 12}, {2 << 16, 1 << 16, 1 << 15},
                                (it & 2) ? QIBL_FALLOFF_INV_DIST2 : QIBL_FALLOFF_INV_DIST, 0,
                                (it & 16) ? QIBL_POINT_POLY : (it & 4) ? QIBL_LUT_NEAREST : QIBL_LUT_BILINEAR};
        qibl_shmap_point_t pp, pi;
        const qibl_ylut_t *lp = (it & 8) ? &lut : NULL;
        assert_int_equal(qibl_shmap_point_prepare(&b.m, &pb.p, lp, &pl, &pp), QIBL_OK);
        assert_int_equal(qibl_shmap_point_prepare(&il.m, &pb.p, lp, &pl, &pi), QIBL_OK);
        relight_rows(&b.m, NULL, &pp, &r, o1);
        relight_rows(&il.m, NULL, &pi, &r, o2);
        assert_memory_equal(o1, o2, n * 4u);
        free(vals), free(pb.bytes), free(o1), free(o2), free(il.planes);
        maps_free(&b);
    }
    /* errors: an unknown layout is named; the conversion writes nothing when it fails */
    maps_buf b;
    maps_make(&b, 5, 2, 4, 3, &r, 1 << 16);
    qibl_shmaps_t bad = b.m;
    bad.layout = 2;
    qibl_shlight_t l;
    assert_int_equal(qibl_shlight_init(&l, 4), QIBL_OK);
    qibl_shmap_weights_t w;
    assert_int_equal(qibl_shmap_check(&bad), QIBL_E_SHMAP_LAYOUT);
    assert_int_equal(qibl_shmap_weights(&bad, &l, &w), QIBL_E_SHMAP_LAYOUT);
    assert_int_equal(qibl_shmaps_row_size(&bad), 0u);
    /* weights read only the params (a streamed head has no planes); the spans need the planes */
    bad = b.m, bad.planes = NULL;
    int32_t o[15], ws1[15];
    assert_int_equal(qibl_shmap_weights(&bad, &l, &w), QIBL_OK);
    assert_int_equal(qibl_shmap_relight_span(&bad, &w, 0, 0, 5, o, ws1, sizeof ws1), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_shmaps_interleave(&bad, (uint8_t *)o, sizeof o), QIBL_E_NULL_POINTER);
    bad = b.m, bad.layout = 2;
    uint8_t buf[2 * 16 * 12 + 1];
    memset(buf, 0xA5, sizeof buf);
    assert_int_equal(qibl_shmaps_interleave(&bad, buf, sizeof buf), QIBL_E_SHMAP_LAYOUT);
    assert_int_equal(qibl_shmaps_interleave(&b.m, buf, sizeof buf - 2), QIBL_E_WORKSPACE);
    assert_int_equal(qibl_shmaps_interleave(NULL, buf, sizeof buf), QIBL_E_NULL_POINTER);
    bad = b.m, bad.k = 26;
    assert_int_equal(qibl_shmaps_interleave(&bad, buf, sizeof buf), QIBL_E_SHMAP_K);
    for (size_t i = 0; i < sizeof buf; ++i)
        assert_int_equal(buf[i], 0xA5);
    assert_int_equal(qibl_shmaps_interleave(&b.m, buf, sizeof buf - 1), QIBL_OK);
    assert_int_equal(buf[sizeof buf - 1], 0xA5);
    qibl_shmaps_t rv;
    assert_int_equal(qibl_shmaps_row_view(NULL, buf, &rv), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_shmaps_row_view(&b.m, NULL, &rv), QIBL_E_NULL_POINTER);
    maps_free(&b);
}

/* A frame relit while its rows stream from a file: only the head, one map row, one P-map row and
 * the YLUT are in memory (fread into small buffers), and the bytes equal those of the whole planar
 * asset relit in memory. */
static void test_stream_rows_from_file(void **state)
{
    (void)state;
    enum { W = 37, H = 5, K = 16 };
    tu_rng r = {49};
    maps_buf b;
    maps_make(&b, W, H, K, 3, &r, 1 << 16);
    pmap_buf pb;
    pmap_make(&pb, W, H, &r);
    int32_t sc[K * 3], bi[K * 3], xyz[W * H * 3];
    for (uint32_t i = 0; i < K * 3; ++i)
        sc[i] = qibl_load_s32le(b.params + 8 * i), bi[i] = qibl_load_s32le(b.params + 8 * i + 4);
    for (uint32_t i = 0; i < W * H * 3; ++i)
        xyz[i] = qibl_load_s32le(pb.bytes + 4 * i);
    size_t vs = qibl_ylut_values_size(8, K);
    uint8_t *vals = malloc(vs);
    int16_t lutv[6 * 8 * 8 * K];
    assert_int_equal(qibl_ylut_build(8, K, vals, vs), QIBL_OK);
    for (size_t i = 0; i < vs / 2; ++i)
        lutv[i] = qibl_load_s16le(vals + 2 * i);
    char path[] = "/tmp/qibl_stream_test_XXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    close(fd);
    qtool_asset_builder ab;
    qtool_asset_builder_init(&ab);
    assert_int_equal(qtool_asset_add_shmp_layout(&ab, W, H, K, 3, sc, bi, b.planes, QIBL_SHMAPS_INTERLEAVED), 0);
    assert_int_equal(qtool_asset_add_pmap(&ab, W, H, xyz), 0);
    assert_int_equal(qtool_asset_add_ylut(&ab, 8, K, lutv), 0);
    assert_int_equal(qtool_asset_write_file(&ab, path, 0), 0);
    qtool_asset_builder_free(&ab);

    /* the reference: planar maps in memory, whole frame */
    qibl_shlight_t l;
    assert_int_equal(qibl_shlight_init(&l, K), QIBL_OK);
    const qibl_q16_t d[3] = {3 << 15, -(1 << 16), 1 << 14}, rgb[3] = {3 << 16, 2 << 16, 1 << 16};
    assert_int_equal(qibl_shlight_add_dir(&l, d, rgb), QIBL_OK);
    qibl_shmap_weights_t w;
    assert_int_equal(qibl_shmap_weights(&b.m, &l, &w), QIBL_OK);
    qibl_ylut_t lut = {8, K, vals, vs};
    qibl_pointlight_t pl = {{1 << 16, -(2 << 16), 3 << 16}, {2 << 16, 1 << 16, 1 << 15}, QIBL_FALLOFF_INV_DIST, 0, 0};
    qibl_shmap_point_t pt;
    assert_int_equal(qibl_shmap_point_prepare(&b.m, &pb.p, &lut, &pl, &pt), QIBL_OK);
    static int32_t want_dir[W * H * 3], want_pt[W * H * 3], got_dir[W * H * 3], got_pt[W * H * 3];
    relight_rows(&b.m, &w, NULL, &r, want_dir);
    relight_rows(&b.m, NULL, &pt, &r, want_pt);

    /* streaming: the head in (at most four) growing reads, then one row at a time */
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    uint8_t *head = NULL;
    size_t have = 0, need = 0;
    for (;;) {
        assert_int_equal(qibl_asset_head_size(head, have, &need), QIBL_OK);
        if (need <= have)
            break;
        head = realloc(head, need);
        assert_non_null(head);
        assert_int_equal(fread(head + have, 1, need - have, f), need - have);
        have = need;
    }
    qibl_asset_head_t hd;
    assert_int_equal(qibl_asset_open_head(&hd, head, have), QIBL_OK);
    uint8_t *ylut = malloc(hd.ylut_size), *row = malloc(hd.row_size), *prow = malloc(12u * W);
    assert_true(ylut && row && prow);
    assert_int_equal(fseek(f, (long)hd.ylut_offset, SEEK_SET), 0);
    assert_int_equal(fread(ylut, 1, hd.ylut_size, f), hd.ylut_size);
    qibl_ylut_t slut;
    assert_int_equal(qibl_asset_head_ylut(&hd, ylut, hd.ylut_size, &slut), QIBL_OK);
    uint8_t pfields[12];
    assert_int_equal(fseek(f, (long)hd.pmap_offset - 12, SEEK_SET), 0);
    assert_int_equal(fread(pfields, 1, 12, f), 12u);
    qibl_pmap_t whole_p;
    assert_int_equal(qibl_asset_head_pmap(&hd, pfields, sizeof pfields, &whole_p), QIBL_OK);
    qibl_shmap_weights_t sw;
    assert_int_equal(qibl_shmap_weights(&hd.maps, &l, &sw), QIBL_OK);
    int32_t ws[W * (2 * K + 32) / 4 + 1];
    for (uint32_t y = 0; y < H; ++y) {
        qibl_asset_row_t rr;
        assert_int_equal(qibl_asset_row(&hd, y, &rr), QIBL_OK);
        assert_int_equal(fseek(f, (long)rr.maps_offset, SEEK_SET), 0);
        assert_int_equal(fread(row, 1, rr.maps_size, f), rr.maps_size);
        assert_int_equal(fseek(f, (long)rr.pmap_offset, SEEK_SET), 0);
        assert_int_equal(fread(prow, 1, rr.pmap_size, f), rr.pmap_size);
        qibl_shmaps_t mv;
        qibl_pmap_t pv;
        assert_int_equal(qibl_shmaps_row_view(&hd.maps, row, &mv), QIBL_OK);
        assert_int_equal(qibl_pmap_row_view(&whole_p, prow, &pv), QIBL_OK);
        assert_int_equal(qibl_shmap_relight_span(&mv, &sw, 0, 0, W, got_dir + 3 * W * y, ws, sizeof ws), QIBL_OK);
        qibl_shmap_point_t spt;
        assert_int_equal(qibl_shmap_point_prepare(&mv, &pv, &slut, &pl, &spt), QIBL_OK);
        assert_int_equal(qibl_shmap_point_span(&spt, 0, 0, W, got_pt + 3 * W * y, ws, sizeof ws), QIBL_OK);
    }
    fclose(f);
    assert_memory_equal(got_dir, want_dir, sizeof want_dir);
    assert_memory_equal(got_pt, want_pt, sizeof want_pt);
    printf("shmap: %ux%u k %u relit from a %ld-byte file reading %zu head + %u bytes per row\n", W, H, K,
           (long)hd.file_size, have, hd.row_size + 12u * W);
    free(head), free(ylut), free(row), free(prow), free(vals), free(pb.bytes);
    maps_free(&b);
    remove(path);
}

/* Both span calls keep int32 tables in ws: a workspace off the 4-byte boundary (a uint8_t array, or
 * a pointer into one) is refused with QIBL_E_WORKSPACE_ALIGN whatever the layout or method (even
 * where this path would not touch ws, so a port cannot pass on one layout and fault on another),
 * and neither out nor ws is written. At offset 4 the same bytes relight exactly as aligned storage. */
static void test_workspace_alignment(void **state)
{
    (void)state;
    enum { W = 13, K = 9 };
    tu_rng r = {57};
    maps_buf b, il;
    maps_make(&b, W, 2, K, 3, &r, 1 << 16);
    interleave(&b, &il);
    pmap_buf pb;
    pmap_make(&pb, W, 2, &r);
    qibl_shlight_t l;
    assert_int_equal(qibl_shlight_init(&l, K), QIBL_OK);
    const qibl_q16_t d[3] = {1 << 16, 1 << 15, -(1 << 14)}, rgb[3] = {1 << 16, 2 << 16, 3 << 16};
    assert_int_equal(qibl_shlight_add_dir(&l, d, rgb), QIBL_OK);
    qibl_shmap_weights_t w;
    assert_int_equal(qibl_shmap_weights(&b.m, &l, &w), QIBL_OK);
    const size_t dn = qibl_shmap_span_workspace_size(W), pn = qibl_shmap_point_workspace_size(K, W);
    const size_t big = (dn > pn ? dn : pn) + 8u;
    uint32_t *store = malloc(big); /* malloc: aligned for any type, so store + off is off bytes from 4 */
    int32_t ref[3 * W], out[3 * W];
    assert_non_null(store);
    for (int kind = 0; kind < 4; ++kind) {
        /* 0: directional planar, 1: directional interleaved, 2: point direct SH, 3: point polynomial */
        qibl_shmap_point_t pt;
        qibl_pointlight_t pl = {{1 << 18, -(1 << 17), 3 << 16}, {1 << 16, 1 << 16, 1 << 16}, QIBL_FALLOFF_INV_DIST,
                                1 << 10, kind == 3 ? QIBL_POINT_POLY : QIBL_LUT_BILINEAR};
        if (kind >= 2)
            assert_int_equal(qibl_shmap_point_prepare(&b.m, &pb.p, NULL, &pl, &pt), QIBL_OK);
        const qibl_shmaps_t *m = kind == 1 ? &il.m : &b.m;
        const size_t need = kind < 2 ? dn : pn;
        int32_t *aligned = (int32_t *)(void *)store;
        assert_int_equal(kind < 2 ? qibl_shmap_relight_span(m, &w, 0, 1, W, ref, aligned, need)
                                  : qibl_shmap_point_span(&pt, 0, 1, W, ref, aligned, need),
                         QIBL_OK);
        for (size_t off = 1; off <= 4; ++off) {
            void *ws = (uint8_t *)(void *)store + off;
            memset(store, 0x5A, big);
            tu_fill_guard(out, sizeof out);
            qibl_status_t st = kind < 2 ? qibl_shmap_relight_span(m, &w, 0, 1, W, out, ws, need)
                                        : qibl_shmap_point_span(&pt, 0, 1, W, out, ws, need);
            if (off < 4) {
                assert_int_equal(st, QIBL_E_WORKSPACE_ALIGN);
                assert_true(tu_guard_intact(out, sizeof out));
                for (size_t i = 0; i < big; ++i)
                    assert_int_equal(((const uint8_t *)(const void *)store)[i], 0x5A);
                /* a zero-length span is refused the same way: the contract does not depend on n */
                st = kind < 2 ? qibl_shmap_relight_span(m, &w, 0, 1, 0, out, ws, need)
                              : qibl_shmap_point_span(&pt, 0, 1, 0, out, ws, need);
                assert_int_equal(st, QIBL_E_WORKSPACE_ALIGN);
            } else {
                assert_int_equal(st, QIBL_OK);
                assert_memory_equal(out, ref, sizeof ref);
            }
        }
    }
    assert_string_equal(qibl_status_str(QIBL_E_WORKSPACE_ALIGN),
                        "workspace not 4-byte aligned (declare it as uint32_t or int32_t)");
    free(store);
    free(pb.bytes);
    maps_free(&il);
    maps_free(&b);
}

static void test_goldens(void **state)
{
    (void)state;
    assert_int_equal(qtool_goldens_check("relight"), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shlight_add_dir_matches_reference),
        cmocka_unit_test(test_directional_against_double),
        cmocka_unit_test(test_environment_and_many_lights),
        cmocka_unit_test(test_spans_equal_whole_rows),
        cmocka_unit_test(test_accumulator_extremes),
        cmocka_unit_test(test_relight_errors_write_nothing),
        cmocka_unit_test(test_workspace_alignment),
        cmocka_unit_test(test_point_light_direct_and_lut),
        cmocka_unit_test(test_point_light_hard_cases),
        cmocka_unit_test(test_point_poly_exponents),
        cmocka_unit_test(test_point_simd_equals_scalar_twin),
        cmocka_unit_test(test_point_every_isa),
        cmocka_unit_test(test_point_simd_extreme_factors),
        cmocka_unit_test(test_point_simd_aligned_sums),
        cmocka_unit_test(test_ylut_build_and_lookup),
        cmocka_unit_test(test_interleaved_equals_planar),
        cmocka_unit_test(test_directional_every_isa),
        cmocka_unit_test(test_kernel_path_matches_definition),
        cmocka_unit_test(test_planar_passes_match_definition),
        cmocka_unit_test(test_planar_kernel_alignment_and_strides),
        cmocka_unit_test(test_stream_rows_from_file),
        cmocka_unit_test(test_goldens),
    };
    return cmocka_run_group_tests_name(QIBL_CONFIG_NATIVE_MUL64 ? "shmap (native paths)" : "shmap (portable M0 paths)",
                                       tests, NULL, NULL);
}
