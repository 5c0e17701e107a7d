/*
 * gles2_test.c - platform/gles2 on a real GL: a headless EGL context on Mesa (llvmpipe here), the
 * golden relight scenes drawn by the backend and by platform/soft, compared pixel by pixel; the
 * GLSL sRGBE codec against the C codec; named errors; no GL object left behind; the near-field
 * source's passes (tools/luminaire) accumulated in sRGBE pairs on the GPU against soft.
 *
 * Without EGL/GLES2 (headers at build time, or a display at run time) every test skips with one
 * line; QIBL_REQUIRE_GLES=1 (CI) turns that into a failure.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include <math.h>

#include "qibl/gonio.h"
#include "qibl/shmap.h"
#include "qibl/soft.h"
#include "qibl/srgbe.h"

static int require_gles(void)
{
    const char *r = getenv("QIBL_REQUIRE_GLES");
    return r != NULL && strcmp(r, "1") == 0;
}

#if QIBL_HAVE_GLES2
#include <GLES2/gl2.h>

#include "gles/headless.h"
#include "golden/casesi.h"
#include "luminaire/luminaire.h"
#include "luminaire/spots_gles.h"
#include "qibl/gles2.h"

enum { GW = 64, GH = 16 };

static qt_gles_ctx ctx;

/* one context for the suite; NULL state means "skip" */
static int setup(void **state)
{
    char why[256];
    if (qt_gles_open(&ctx, GW, GH, why, sizeof why) != 0) {
        if (require_gles()) {
            fprintf(stderr, "gles2_test: QIBL_REQUIRE_GLES=1 and %s\n", why);
            return -1;
        }
        printf("SKIP gles2_test: %s\n", why);
        *state = NULL;
        return 0;
    }
    printf("gles2_test: GL_RENDERER %s\n", ctx.renderer);
    *state = &ctx;
    return 0;
}

static int teardown(void **state)
{
    if (*state != NULL)
        qt_gles_close(&ctx);
    return 0;
}

#define NEED_GL(state)                                                                                                 \
    do {                                                                                                               \
        if ((state) == NULL)                                                                                           \
            skip();                                                                                                    \
    } while (0)

/* The golden relight fixture of tools/golden/cases_relight.c (same PRNG seed and draw order, so the
 * same bytes as the goldens for k = 9 and 16; k = 25 continues the pattern). */
typedef struct {
    qibl_shmaps_t m;
    qibl_pmap_t p;
    uint8_t *params, *planes, *points;
} gmaps;

static void gmaps_make(gmaps *g, uint32_t w, uint32_t h, uint32_t k)
{
    const uint32_t ch = 3;
    const int32_t scale_mag = 1 << 17;
    qtool_grng r = {2026};
    memset(&g->m, 0, sizeof g->m); /* zero: the planar layout */
    g->m.width = w, g->m.height = h, g->m.k = k, g->m.channels = ch;
    g->params = malloc(8u * k * ch);
    g->planes = malloc((size_t)w * h * k * ch);
    g->points = malloc((size_t)w * h * 12u);
    assert_non_null(g->params), assert_non_null(g->planes), assert_non_null(g->points);
    for (uint32_t i = 0; i < k * ch; ++i) {
        int32_t sc = (int32_t)(qtool_grng_u32(&r) % (uint32_t)scale_mag) - scale_mag / 2;
        int32_t bi = -128 * sc + (int32_t)(qtool_grng_u32(&r) % 2001u) - 1000;
        qtool_gput_s32(g->params + 8u * i, sc);
        qtool_gput_s32(g->params + 8u * i + 4u, bi);
    }
    for (size_t i = 0; i < (size_t)w * h * k * ch; ++i)
        (void)qtool_grng_u32(&r);
    for (uint32_t pl = 0; pl < k * ch; ++pl)
        for (uint32_t y = 0; y < h; ++y)
            for (uint32_t x = 0; x < w; ++x)
                g->planes[((size_t)pl * h + y) * w + x] =
                    (uint8_t)((x * (pl + 3) + y * (2 * pl + 1) + (qtool_grng_u32(&r) & 15u)) & 0xFFu);
    g->m.params = g->params;
    g->m.planes = g->planes;
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            uint8_t *q = g->points + ((size_t)y * w + x) * 12u;
            qtool_gput_s32(q, (int32_t)(x * 40000u) - (int32_t)(w * 20000u));
            qtool_gput_s32(q + 4, (int32_t)((x * 7u + y * 3u) % 11u) * 30000 - 150000);
            qtool_gput_s32(q + 8, (int32_t)(y * 50000u) - (int32_t)(h * 25000u));
        }
    g->p.width = w, g->p.height = h, g->p.points = g->points;
}

static void gmaps_free(gmaps *g)
{
    free(g->params), free(g->planes), free(g->points);
}

/* platform/soft's RGBA8888 sRGB frame of a scene (mode 0 directional, else a point light) */
static void soft_frame(const gmaps *g, const qibl_shmap_weights_t *w, const qibl_shmap_point_t *pt, uint8_t *rgba)
{
    qibl_fb_desc_t fb = {0};
    fb.pixels = rgba, fb.width = GW, fb.height = GH, fb.srgb = 1;
    int32_t row[3 * GW];
    static int32_t ws[(GW * (2 * 25 + 32) + 3) / 4]; /* 4-byte aligned, as the span calls need */
    for (uint32_t y = 0; y < GH; ++y) {
        qibl_status_t st = w ? qibl_shmap_relight_span(&g->m, w, 0, y, GW, row, ws, sizeof ws)
                             : qibl_shmap_point_span(pt, 0, y, GW, row, ws, sizeof ws);
        assert_int_equal(st, QIBL_OK);
        assert_int_equal(qibl_soft_fb_write_row(&fb, 0, y, GW, row), QIBL_OK);
    }
}

/* worst figures: [0] one pass (what the GL's own limits give here), [1] the capped multipass path */
static unsigned worst_max[3];
static double worst_mean[3];

/* Compares RGBA frames (alpha ignored): max 2 and mean 0.5 in 8-bit sRGB levels, one pass or many
 * (the accumulator keeps two sRGBE codes per pixel, so it adds ~2^-18 of the partial sum, not the
 * 1/510 one code would: one code cost up to 12 levels in a dark channel beside a bright one).
 * Nearest LUT texels: a direction exactly on a texel edge (the fixture's lattice makes some) may
 * round to either texel in float and in the core's integers, so there at most 0.5 % of the
 * channels may differ by more than 2 (measured: one pixel). */
static void compare(const char *name, uint32_t k, uint32_t units, uint32_t passes, const uint8_t *a, const uint8_t *b)
{
    unsigned mx = 0, over2 = 0;
    double sum = 0.0;
    for (size_t i = 0; i < (size_t)GW * GH * 4u; ++i) {
        if (i % 4u == 3u)
            continue;
        unsigned d = (unsigned)abs((int)a[i] - (int)b[i]);
        mx = d > mx ? d : mx;
        over2 += d > 2u;
        if (d > 2u && getenv("QIBL_GLES_DEBUG") != NULL)
            printf("  pixel %zu ch %zu soft %u gpu %u\n", i / 4u, i % 4u, a[i], b[i]);
        sum += d;
    }
    double mean = sum / (GW * GH * 3.0);
    int multi = strstr(name, "float") != NULL ? 2 : passes > 1u, nearest = strstr(name, "near") != NULL;
    printf("gles: k=%-2u %-22s units %-2u passes %-2u  max %-2u  mean %.3f\n", k, name, units, passes, mx, mean);
    if (!nearest) {
        worst_max[multi] = mx > worst_max[multi] ? mx : worst_max[multi];
        worst_mean[multi] = mean > worst_mean[multi] ? mean : worst_mean[multi];
    }
    if (getenv("QIBL_GLES_DEBUG") != NULL)
        return; /* print every case */
    if (nearest)
        assert_true(over2 <= GW * GH * 3u / 200u); /* texel-edge flips: a few pixels */
    else
        assert_true(mx <= 2u);
    assert_true(mean <= 0.5);
}

static void test_relight_scenes_match_soft(void **state)
{
    NEED_GL(*state);
    static uint8_t soft[GW * GH * 4], gpu[GW * GH * 4];
    const qibl_gles2_out_t out = {0, 1};
    memset(worst_max, 0, sizeof worst_max), worst_mean[0] = worst_mean[1] = worst_mean[2] = 0.0;
    for (uint32_t k = 9; k <= 25; k += k == 9 ? 7u : 9u) {
        gmaps g;
        gmaps_make(&g, GW, GH, k);
        size_t vs = qibl_ylut_values_size(16, k);
        uint8_t *vals = malloc(vs);
        assert_non_null(vals);
        assert_int_equal(qibl_ylut_build(16, k, vals, vs), QIBL_OK);
        qibl_ylut_t lut = {16, k, vals, vs};
        /* every GL limit, then a cap of 8 units / 16 uniform vectors (GLES2's guaranteed minimum),
         * which forces the sRGBE multipass path for points at every k and directional from k = 16 */
        const uint32_t caps[3][3] = {{0, 0, 0}, {8, 16, 0}, {8, 16, 1}};
        for (int c = 0; c < 3; ++c) {
            qibl_gles2_t gl;
            qibl_gles2_desc_t d = {caps[c][0], caps[c][1], caps[c][2]};
            assert_int_equal(qibl_gles2_init(&gl, &d), QIBL_OK);
            qibl_status_t st = qibl_gles2_upload(&gl, &g.m, &g.p, &lut);
            if (st != QIBL_OK)
                fprintf(stderr, "upload: %s: %s\n", qibl_gles2_status_str(st), qibl_gles2_log(&gl));
            assert_int_equal(st, QIBL_OK);
            /* directional: the goldens' warm sun and cool sky */
            qibl_shlight_t l;
            qibl_shmap_weights_t w;
            const qibl_q16_t sun[3] = {40000, 25000, 52000}, sun_rgb[3] = {150000, 120000, 90000};
            const qibl_q16_t sky[3] = {0, 0, 65536}, sky_rgb[3] = {20000, 30000, 52000};
            assert_int_equal(qibl_shlight_init(&l, k), QIBL_OK);
            assert_int_equal(qibl_shlight_add_dir(&l, sun, sun_rgb), QIBL_OK);
            assert_int_equal(qibl_shlight_add_dir(&l, sky, sky_rgb), QIBL_OK);
            assert_int_equal(qibl_shmap_weights(&g.m, &l, &w), QIBL_OK);
            soft_frame(&g, &w, NULL, soft);
            glBindFramebuffer(GL_FRAMEBUFFER, ctx.fbo);
            st = qibl_gles2_relight(&gl, &w, &out);
            if (st != QIBL_OK)
                fprintf(stderr, "relight: %s: %s\n", qibl_gles2_status_str(st), qibl_gles2_log(&gl));
            assert_int_equal(st, QIBL_OK);
            assert_int_equal(qt_gles_read(&ctx, gpu), 0);
            if (c == 2 && !gl.float_acc) {
                printf("gles: OES_texture_float accumulation not available here: not measured\n");
                qibl_gles2_destroy(&gl);
                break;
            }
            compare(c == 2 ? "dir float" : "dir", k, gl.units, qibl_gles2_passes(&gl), soft, gpu);
            /* point: direct SH (1/d), LUT bilinear (1/d^2), LUT nearest (1/d), as the goldens */
            const char *modes[3] = {"point_direct", "point_lut16", "point_lut16_near"};
            for (int mode = 0; mode < 3; ++mode) {
                qibl_shmap_point_t pt;
                qibl_pointlight_t pl = {{30000, -90000, 20000}, {200000, 160000, 120000},
                                        mode == 1 ? QIBL_FALLOFF_INV_DIST2 : QIBL_FALLOFF_INV_DIST, 0,
                                        mode == 2 ? QIBL_LUT_NEAREST : QIBL_LUT_BILINEAR};
                assert_int_equal(qibl_shmap_point_prepare(&g.m, &g.p, mode ? &lut : NULL, &pl, &pt), QIBL_OK);
                soft_frame(&g, NULL, &pt, soft);
                glBindFramebuffer(GL_FRAMEBUFFER, ctx.fbo);
                st = qibl_gles2_point(&gl, &pt, &out);
                if (st != QIBL_OK)
                    fprintf(stderr, "point: %s: %s\n", qibl_gles2_status_str(st), qibl_gles2_log(&gl));
                assert_int_equal(st, QIBL_OK);
                assert_int_equal(qt_gles_read(&ctx, gpu), 0);
                char label[40];
                snprintf(label, sizeof label, "%s%s", modes[mode], c == 2 ? " float" : "");
                compare(label, k, gl.units, qibl_gles2_passes(&gl), soft, gpu);
            }
            if (c >= 1)
                assert_true(qibl_gles2_passes(&gl) > 1u); /* the cap really took the multipass path */
            if (c >= 1 && k > 9u) {
                glBindFramebuffer(GL_FRAMEBUFFER, ctx.fbo);
                assert_int_equal(qibl_gles2_relight(&gl, &w, &out), QIBL_OK);
                assert_true(qibl_gles2_passes(&gl) > 1u);
            }
            qibl_gles2_destroy(&gl);
        }
        free(vals);
        gmaps_free(&g);
    }
    printf("RESULT gles.max_diff %u\nRESULT gles.mean_diff %.4f\n", worst_max[0], worst_mean[0]);
    printf("RESULT gles.multipass_max_diff %u\nRESULT gles.multipass_mean_diff %.4f\n", worst_max[1], worst_mean[1]);
    printf("RESULT gles.float_accum_max_diff %u\nRESULT gles.float_accum_mean_diff %.4f\n", worst_max[2], worst_mean[2]);
}

/* A goniometric lamp's table for the tests: a beam toward the aim with three lobes around it and
 * a dim back, smooth across the octahedron (n x n, Q1.15). */
static void gonio_table(uint32_t n, uint16_t *t)
{
    for (uint32_t j = 0; j < n; ++j)
        for (uint32_t i = 0; i < n; ++i) {
            double u = (2.0 * i + 1.0) / n - 1.0, v = (2.0 * j + 1.0) / n - 1.0, r2 = u * u + v * v;
            double lobe = 0.75 + 0.25 * cos(3.0 * atan2(v, u));
            double x = 0.08 + 0.92 * (r2 < 1.0 ? (1.0 - r2) * (1.0 - r2) : 0.0) * lobe;
            t[(size_t)j * n + i] = (uint16_t)lrint(x * 32768.0);
        }
}

/* the soft frame of a goniometric point lamp: qibl_shmap_point_span, then qibl_gonio_scale_span,
 * as tools/relight does */
static void soft_gonio_frame(const gmaps *g, const qibl_shmap_point_t *pt, const qibl_q16_t pos[3],
                             const qibl_gonio_t *go, uint8_t *rgba)
{
    qibl_fb_desc_t fb = {0};
    fb.pixels = rgba, fb.width = GW, fb.height = GH, fb.srgb = 1;
    int32_t row[3 * GW];
    static int32_t ws[(GW * (2 * 25 + 32) + 3) / 4];
    for (uint32_t y = 0; y < GH; ++y) {
        assert_int_equal(qibl_shmap_point_span(pt, 0, y, GW, row, ws, sizeof ws), QIBL_OK);
        assert_int_equal(qibl_gonio_scale_span(go, &g->p, pos, 0, y, GW, row), QIBL_OK);
        assert_int_equal(qibl_soft_fb_write_row(&fb, 0, y, GW, row), QIBL_OK);
    }
}

/* qibl_gles2_point_gonio against platform/soft with qibl_gonio_scale_span: the limits of the point
 * lamps (max 2, mean 0.5 levels), direct SH and LUT, one pass and the capped multipass path, two
 * lamp frames and table sizes; the lamp's shape must show (the frame differs from the isotropic
 * lamp's); refusals by name. */
static void test_gonio_point_matches_soft(void **state)
{
    NEED_GL(*state);
    static uint8_t soft[GW * GH * 4], gpu[GW * GH * 4], iso[GW * GH * 4];
    static uint16_t table[64 * 64];
    const qibl_gles2_out_t out = {0, 1};
    const int32_t frames[2][2][3] = {{{0, 0, 65536}, {65536, 0, 0}}, {{20000, 50000, 40000}, {0, 0, 65536}}};
    gmaps g;
    gmaps_make(&g, GW, GH, 16);
    size_t vs = qibl_ylut_values_size(16, 16);
    uint8_t *vals = malloc(vs);
    assert_non_null(vals);
    assert_int_equal(qibl_ylut_build(16, 16, vals, vs), QIBL_OK);
    qibl_ylut_t lut = {16, 16, vals, vs};
    for (int c = 0; c < 2; ++c) {
        qibl_gles2_t gl;
        /* capped: 16 uniform vectors force a pass per map texture; the LUT's pass may need 9 units */
        qibl_gles2_desc_t d = {c ? 10u : 0u, c ? 16u : 0u, 0};
        assert_int_equal(qibl_gles2_init(&gl, &d), QIBL_OK);
        assert_int_equal(qibl_gles2_upload(&gl, &g.m, &g.p, &lut), QIBL_OK);
        for (int f = 0; f < 2; ++f)
            for (int mode = 0; mode < 2; ++mode) {
                uint32_t n = f ? 64u : 17u;
                gonio_table(n, table);
                qibl_gonio_t go;
                assert_int_equal(qibl_gonio_init(&go, n, table, frames[f][0], frames[f][1]), QIBL_OK);
                qibl_shmap_point_t pt;
                qibl_pointlight_t pl = {{30000, -90000, -60000}, {300000, 240000, 180000},
                                        mode ? QIBL_FALLOFF_INV_DIST2 : QIBL_FALLOFF_INV_DIST, 0, QIBL_LUT_BILINEAR};
                assert_int_equal(qibl_shmap_point_prepare(&g.m, &g.p, mode ? &lut : NULL, &pl, &pt), QIBL_OK);
                soft_gonio_frame(&g, &pt, pl.pos, &go, soft);
                soft_frame(&g, NULL, &pt, iso);
                glBindFramebuffer(GL_FRAMEBUFFER, ctx.fbo);
                qibl_status_t st = qibl_gles2_point_gonio(&gl, &pt, &go, &out);
                if (st != QIBL_OK)
                    fprintf(stderr, "point_gonio: %s: %s\n", qibl_gles2_status_str(st), qibl_gles2_log(&gl));
                assert_int_equal(st, QIBL_OK);
                assert_int_equal(qt_gles_read(&ctx, gpu), 0);
                if (c)
                    assert_true(qibl_gles2_passes(&gl) > 1u);
                unsigned shaped = 0;
                for (size_t i = 0; i < sizeof iso; ++i)
                    shaped += i % 4u != 3u && abs((int)iso[i] - (int)soft[i]) > 8;
                assert_true(shaped > GW * GH / 4u); /* the table really shapes the lamp */
                char label[40];
                snprintf(label, sizeof label, "gonio%u %s f%d", n, mode ? "lut16" : "direct", f);
                compare(label, 16, gl.units, qibl_gles2_passes(&gl), soft, gpu);
            }
        /* refusals: what qibl_gles2_point refuses, then the table's size */
        qibl_gonio_t go;
        assert_int_equal(qibl_gonio_init(&go, 17u, table, frames[0][0], frames[0][1]), QIBL_OK);
        qibl_shmap_point_t pt;
        qibl_pointlight_t pl = {{30000, -90000, -60000}, {300000, 240000, 180000}, QIBL_FALLOFF_INV_DIST, 0,
                                QIBL_LUT_BILINEAR};
        assert_int_equal(qibl_shmap_point_prepare(&g.m, &g.p, NULL, &pl, &pt), QIBL_OK);
        assert_int_equal(qibl_gles2_point_gonio(&gl, &pt, NULL, &out), QIBL_E_NULL_POINTER);
        assert_int_equal(qibl_gles2_point_gonio(NULL, &pt, &go, &out), QIBL_E_NULL_POINTER);
        qibl_gonio_t bad = go;
        bad.n = 1;
        assert_int_equal(qibl_gles2_point_gonio(&gl, &pt, &bad, &out), QIBL_E_GONIO_SIZE);
        bad.table = NULL;
        assert_int_equal(qibl_gles2_point_gonio(&gl, &pt, &bad, &out), QIBL_E_NULL_POINTER);
        qibl_gles2_destroy(&gl);
    }
    free(vals);
    gmaps_free(&g);
}

/* sRGBE: the GLSL decode/encode pair against the C codec over a sweep of codes. */
static void test_srgbe_shader_matches_codec(void **state)
{
    NEED_GL(*state);
    qibl_gles2_t gl;
    assert_int_equal(qibl_gles2_init(&gl, NULL), QIBL_OK);
    enum { N = 4096 };
    static uint8_t codes[4 * N], back[4 * N];
    qtool_grng r = {77};
    /* canonical codes of random binary32 colours over 2^-40 .. 2^40, both signs, mixed magnitudes */
    for (uint32_t i = 0; i < N; ++i) {
        uint32_t rgb[3];
        uint32_t ebase = 87u + qtool_grng_u32(&r) % 80u;
        for (int c = 0; c < 3; ++c) {
            uint32_t e = ebase - (qtool_grng_u32(&r) % 4u == 0 ? qtool_grng_u32(&r) % 12u : 0u);
            rgb[c] = (qtool_grng_u32(&r) & 0x80000000u) | e << 23 | (qtool_grng_u32(&r) & 0x7FFFFFu);
        }
        assert_int_equal(qibl_srgbe_encode_f32(rgb, codes + 4u * i), QIBL_OK);
    }
    const float muls[3] = {1.0f, 3.0f, 0.7f};
    for (int mi = 0; mi < 3; ++mi) {
        qibl_status_t st = qibl_gles2_srgbe_check(&gl, codes, N, muls[mi], back);
        if (st != QIBL_OK)
            fprintf(stderr, "srgbe_check: %s: %s\n", qibl_gles2_status_str(st), qibl_gles2_log(&gl));
        assert_int_equal(st, QIBL_OK);
        unsigned exact = 0, worst = 0;
        for (uint32_t i = 0; i < N; ++i) {
            uint32_t f[3];
            uint8_t want[4];
            assert_int_equal(qibl_srgbe_decode_f32(codes + 4u * i, f), QIBL_OK);
            for (int c = 0; c < 3; ++c) {
                float v;
                memcpy(&v, &f[c], 4);
                v *= muls[mi];
                memcpy(&f[c], &v, 4);
            }
            assert_int_equal(qibl_srgbe_encode_f32(f, want), QIBL_OK);
            if (memcmp(want, back + 4u * i, 4) == 0) {
                ++exact;
                continue;
            }
            /* the GPU's decode is within 2^(e-23) of the C decoder's: a value that close to a
             * rounding boundary may land one code over, never further, and the exponent agrees */
            if (getenv("QIBL_GLES_DEBUG"))
                printf("code %02x%02x%02x%02x want %02x%02x%02x%02x got %02x%02x%02x%02x\n", codes[4 * i],
                       codes[4 * i + 1], codes[4 * i + 2], codes[4 * i + 3], want[0], want[1], want[2], want[3],
                       back[4 * i], back[4 * i + 1], back[4 * i + 2], back[4 * i + 3]);
            assert_int_equal(want[3], back[4u * i + 3u]);
            for (int c = 0; c < 3; ++c) {
                unsigned d = (unsigned)abs((int)want[c] - (int)back[4u * i + c]);
                worst = d > worst ? d : worst;
            }
        }
        printf("gles: sRGBE shader x%.1f: %u of %u codes identical to the C codec, others within %u\n",
               (double)muls[mi], exact, N, worst);
        assert_true(worst <= 1u);
        assert_true(exact >= N - N / 256u); /* the rest sit on a rounding boundary of the decoded value */
    }
    qibl_gles2_destroy(&gl);
}

static void test_named_errors(void **state)
{
    NEED_GL(*state);
    qibl_gles2_t gl;
    memset(&gl, 0, sizeof gl);
    gmaps g;
    gmaps_make(&g, GW, GH, 9);
    assert_int_equal(qibl_gles2_init(NULL, NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_gles2_upload(&gl, &g.m, NULL, NULL), QIBL_E_GLES2_STATE); /* not initialised */
    qibl_gles2_desc_t one = {1, 0, 0};
    assert_int_equal(qibl_gles2_init(&gl, &one), QIBL_E_GLES2_UNITS);
    assert_true(strlen(qibl_gles2_log(&gl)) > 0);
    qibl_gles2_destroy(&gl);
    /* one unit left after the P map's three: point lights cannot run, directional can */
    qibl_gles2_desc_t four = {4, 0, 0};
    assert_int_equal(qibl_gles2_init(&gl, &four), QIBL_OK);
    qibl_shmap_weights_t w;
    qibl_shlight_t l;
    const qibl_q16_t up[3] = {0, 0, 65536}, rgb[3] = {65536, 65536, 65536};
    assert_int_equal(qibl_shlight_init(&l, 9), QIBL_OK);
    assert_int_equal(qibl_shlight_add_dir(&l, up, rgb), QIBL_OK);
    assert_int_equal(qibl_shmap_weights(&g.m, &l, &w), QIBL_OK);
    assert_int_equal(qibl_gles2_relight(&gl, &w, NULL), QIBL_E_GLES2_STATE); /* nothing uploaded */
    qibl_shmaps_t bad = g.m;
    bad.k = 0;
    assert_int_equal(qibl_gles2_upload(&gl, &bad, NULL, NULL), QIBL_E_SHMAP_K);
    qibl_pmap_t smallp = g.p;
    smallp.width = GW - 1;
    assert_int_equal(qibl_gles2_upload(&gl, &g.m, &smallp, NULL), QIBL_E_SHMAP_MISMATCH);
    assert_int_equal(qibl_gles2_upload(&gl, &g.m, NULL, NULL), QIBL_OK);
    glBindFramebuffer(GL_FRAMEBUFFER, ctx.fbo);
    assert_int_equal(qibl_gles2_relight(&gl, &w, NULL), QIBL_OK);
    qibl_shmap_weights_t w2 = w;
    w2.k = 16;
    assert_int_equal(qibl_gles2_relight(&gl, &w2, NULL), QIBL_E_GLES2_MISMATCH);
    qibl_shmap_point_t pt;
    qibl_pointlight_t pl = {{0, 0, 0}, {65536, 65536, 65536}, QIBL_FALLOFF_INV_DIST, 0, QIBL_LUT_BILINEAR};
    assert_int_equal(qibl_shmap_point_prepare(&g.m, &g.p, NULL, &pl, &pt), QIBL_OK);
    assert_int_equal(qibl_gles2_point(&gl, &pt, NULL), QIBL_E_GLES2_STATE); /* no P map uploaded */
    assert_int_equal(qibl_gles2_upload(&gl, &g.m, &g.p, NULL), QIBL_OK);
    assert_int_equal(qibl_gles2_point(&gl, &pt, NULL), QIBL_E_GLES2_UNITS); /* 3 + 1 + acc > 4 */
    assert_true(strstr(qibl_gles2_log(&gl), "units") != NULL);
    qibl_gles2_destroy(&gl);
    /* every status of the range has its own text */
    for (int i = 1; i <= 10; ++i) {
        const char *a = qibl_gles2_status_str((qibl_status_t)(QIBL_STATUS_GLES2_BASE + i));
        assert_true(strncmp(a, "gles2: ", 7) == 0);
        for (int j = 1; j < i; ++j)
            assert_string_not_equal(a, qibl_gles2_status_str((qibl_status_t)(QIBL_STATUS_GLES2_BASE + j)));
    }
    assert_string_equal(qibl_gles2_status_str(QIBL_E_SHMAP_K), qibl_status_str(QIBL_E_SHMAP_K));
    /* the one list (gles2.h) holds the range in value order, each with the text given above */
    int n = 0;
#define CHECK_(name, message) \
    assert_int_equal((int)(name), (int)QIBL_STATUS_GLES2_BASE + 1 + n); \
    assert_string_equal(qibl_gles2_status_str(name), message); \
    ++n;
    QIBL_GLES2_STATUS_LIST(CHECK_)
#undef CHECK_
    assert_int_equal(n, 10);
    gmaps_free(&g);
}

/* the near-field source's passes (tools/luminaire) accumulated on the GPU in sRGBE pairs: within
 * 2 of 255 of the soft two-target sum and of the core's one-call sum, over 16 and 64 passes; the
 * caller's framebuffer binding restored */
static void test_luminaire_passes_match_soft(void **state)
{
    NEED_GL(state);
    static const uint32_t grids[] = {4, 8};
    for (int k = 0; k < 2; ++k) {
        qtool_luminaire l;
        qtool_luminaire_passes r;
        char err[256];
        assert_int_equal(qtool_luminaire_synthetic(grids[k], &l), 0);
        assert_int_equal(qtool_luminaire_passes_run(&l, 20, QTOOL_LUMINAIRE_SIZE, &r), 0);
        assert_int_equal(r.passes, grids[k] * grids[k]);
        GLint before = 0, after = 0;
        glGetIntegerv(GL_FRAMEBUFFER_BINDING, &before);
        r.gles_vs_core = r.gles_vs_srgbe2 = 99;
        assert_int_equal(qtool_luminaire_passes_gles(&r, err, sizeof err), 0);
        glGetIntegerv(GL_FRAMEBUFFER_BINDING, &after);
        assert_int_equal(before, after);
        assert_int_equal(r.gles, 1);
        printf("luminaire passes %u: gles vs core %d, vs soft pair %d (8-bit sRGB)\n", r.passes, r.gles_vs_core,
               r.gles_vs_srgbe2);
        assert_true(r.gles_vs_core <= 2 && r.gles_vs_srgbe2 <= 2);
        qtool_luminaire_passes_free(&r);
        qtool_luminaire_free(&l);
    }
}

/* The near-field spotlights evaluated on the GPU (tools/luminaire/spots_gles.c), one pass per
 * spotlight, against the soft kernel's frame: the built-in synthetic source of 64 spotlights one lamp
 * size above a ground patch it lights everywhere, each anchor's unit lamp an analytic Lambertian
 * ground with its own tint (so the interpolation among anchors shows); its far field; a patch twice
 * as wide (passes drawn over part of it), and there the spotlights pushed apart in turn. Within 2 of
 * 255 and a mean below 0.1 (8-bit sRGB, the exact sum's peak at 1.0), on both of its paths. Much of
 * the frame is lit and each term varies over it by far more than that: a shader without the gonio
 * table missed by 92 levels (mean 78), without the 1/|x - s|^3 by 178, with equal anchor weights by
 * 5 (mean 0.9); tiles culled 30 % too tightly by 3; the core way's ping-pong without the previous
 * pass's tiles by 174 (spotlights apart); each tried by hand. The caller's framebuffer binding is
 * restored. */
static void test_luminaire_spots_match_soft(void **state)
{
    NEED_GL(state);
    enum { W = 96, H = 64 };
    const double hg = QTOOL_LUMINAIRE_SIZE, half = 1.8 * hg + QTOOL_LUMINAIRE_SIZE / 2;
    static const double tint[4][3] = {{1, 0.9, 0.8}, {0.8, 1, 0.9}, {0.9, 0.8, 1}, {1, 1, 0.7}};
    qtool_luminaire l;
    assert_int_equal(qtool_luminaire_synthetic(8, &l), 0);
    int32_t *pts = malloc(sizeof(int32_t) * 3 * W * H), *base = malloc(sizeof(int32_t) * 3 * W * H * 4);
    int32_t *row = malloc(sizeof(int32_t) * 3 * W);
    int64_t *acc = malloc(sizeof(int64_t) * 3 * W * H), *ws = malloc(qtool_luminaire_span_ws_size(W));
    uint8_t *pix = malloc(4 * W * H), *soft = malloc(3 * W * H), *gpu = malloc(3 * W * H);
    assert_true(pts && base && row && acc && ws && pix && soft && gpu);
    /* near field, far field, near field over a wider patch (the tiles' cull at work), and that with
     * the spotlights pushed apart in turn (odd ones to +x, even ones to -x: consecutive passes light
     * different tiles, which the core way's ping-pong must carry over) */
    static const char *const names[4] = {"near field", "far field", "near field, wide patch",
                                         "spotlights apart, wide patch"};
    for (int cfg = 0; cfg < 4; ++cfg) {
        const int far = cfg == 1;
        const double hp = cfg >= 2 ? 2 * half : half;
        qtool_luminaire_spots s;
        char err[256];
        const int32_t gpos[3] = {0, 0, (int32_t)lround(hg * 65536)};
        assert_int_equal(qtool_luminaire_spots_make(&l, gpos, 64, far, &s, err, sizeof err), 0);
        assert_int_equal(s.count, far ? 1u : 64u);
        if (cfg == 3) {
            const int32_t apart = (int32_t)lround(1.5 * hg * 65536);
            for (uint32_t j = 0; j < s.count; ++j)
                s.pos[j][0] += j & 1u ? apart : -apart;
            s.reach[0] += (uint64_t)apart; /* qtool_luminaire_reaches stays exact */
        }
        for (uint32_t y = 0; y < H; ++y)
            for (uint32_t x = 0; x < W; ++x) {
                const double p[3] = {-hp + (x + 0.5) * 2 * hp / W, -hp + (y + 0.5) * 2 * hp / H, 0};
                const size_t o = 3 * ((size_t)y * W + x);
                for (int k = 0; k < 3; ++k)
                    pts[o + (size_t)k] = (int32_t)lround(p[k] * 65536);
                for (uint32_t a = 0; a < s.nanchor; ++a) {
                    const double d[3] = {s.anchor[a][0] / 65536.0 - p[0], s.anchor[a][1] / 65536.0 - p[1], hg};
                    const double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                    for (int k = 0; k < 3; ++k)
                        base[(size_t)a * 3 * W * H + o + (size_t)k] =
                            (int32_t)lround(tint[a][k] * hg / sqrt(r2) / 3.14159265358979 / r2 * 65536);
                }
            }
        /* the soft frame: the kernel row by row, rounded once, the exposure putting its peak at 1.0 */
        memset(acc, 0, sizeof(int64_t) * 3 * W * H);
        int32_t peak = 1;
        for (uint32_t y = 0; y < H; ++y) {
            int32_t rb[3 * W * 4];
            for (uint32_t a = 0; a < s.nanchor; ++a)
                memcpy(rb + (size_t)a * 3 * W, base + (size_t)a * 3 * W * H + (size_t)y * 3 * W,
                       sizeof(int32_t) * 3 * W);
            qtool_luminaire_spots_span(&s, rb, pts + (size_t)y * 3 * W, W, acc + (size_t)y * 3 * W, ws);
            for (size_t i = 0; i < 3 * (size_t)W; ++i) {
                int32_t v = qtool_luminaire_q16(acc[(size_t)y * 3 * W + i]);
                peak = v > peak ? v : peak;
            }
        }
        const uint32_t expo = (uint32_t)(((uint64_t)1 << 32) / (uint64_t)peak);
        qibl_fb_desc_t fb = {.pixels = pix, .width = W, .height = H, .format = QIBL_FB_RGBA8888, .srgb = 1,
                             .exposure = expo};
        uint32_t lit = 0;
        for (uint32_t y = 0; y < H; ++y) {
            for (size_t i = 0; i < 3 * (size_t)W; ++i)
                row[i] = qtool_luminaire_q16(acc[(size_t)y * 3 * W + i]);
            assert_int_equal(qibl_fb_write_row(&fb, 0, y, W, row), QIBL_OK);
        }
        for (size_t i = 0; i < (size_t)W * H; ++i) {
            memcpy(soft + 3 * i, pix + 4 * i, 3);
            lit += soft[3 * i + 1] >= 32;
        }
        GLint before = 0, after = 0;
        glGetIntegerv(GL_FRAMEBUFFER_BINDING, &before);
        for (int core = 0; core < 2; ++core) { /* the extensions' path where the GL has them, and GLES2's */
            qtool_luminaire_gles_stats gs;
            const qtool_luminaire_gles_opts go = {.frames = 1, .core_only = core};
            memset(gpu, 0xA5, 3 * W * H);
            int rc = qtool_luminaire_spots_gles(&s, W, H, pts, base, expo, 1, &go, gpu, &gs, err, sizeof err);
            if (rc != 0)
                fail_msg("qtool_luminaire_spots_gles: %s", err);
            glGetIntegerv(GL_FRAMEBUFFER_BINDING, &after);
            assert_int_equal(before, after);
            int mx;
            double mean;
            qtool_luminaire_diff8(gpu, soft, 3 * (size_t)W * H, &mx, &mean);
            printf("luminaire spots on the GPU (%s, %s, %u passes, %.0f%% of the frame each, %u of %u pixels lit): "
                   "against the soft frame max %d, mean %.4f (8-bit sRGB)\n",
                   names[cfg],
                   gs.fetch ? "framebuffer fetch" : "GLES2 core", gs.passes, 100 * gs.coverage, lit, W * H, mx, mean);
            assert_int_equal(gs.fetch && core, 0);
            assert_int_equal(gs.passes, s.count);
            assert_true(lit > W * H / (cfg >= 2 ? 8 : 3));
            assert_true(mx <= 2);
            assert_true(mean < 0.1);
        }
        qtool_luminaire_spots_free(&s);
    }
    { /* spotlights merged by the hierarchy (tol > 0): the shader evaluates level 0 only, so they are
       * refused by name and nothing is written */
        qtool_luminaire_spots s;
        char err[256] = "";
        const int32_t gpos[3] = {0, 0, (int32_t)lround(hg * 65536)};
        const qtool_luminaire_spots_opts ot = {.n = 64, .tol = 0.25};
        assert_int_equal(qtool_luminaire_spots_build(&l, gpos, &ot, &s, err, sizeof err), 0);
        assert_true(s.nlevel > 0u);
        memset(gpu, 0xA5, 3 * W * H);
        assert_int_equal(qtool_luminaire_spots_gles(&s, W, H, pts, base, 65536, 1, NULL, gpu, NULL, err, sizeof err), -1);
        assert_non_null(strstr(err, "hierarchy"));
        for (size_t i = 0; i < 3 * (size_t)W * H; ++i)
            assert_int_equal(gpu[i], 0xA5);
        qtool_luminaire_spots_free(&s);
    }
    free(pts), free(base), free(row), free(acc), free(ws), free(pix), free(soft), free(gpu);
    qtool_luminaire_free(&l);
}

/* destroy deletes every texture, framebuffer, buffer and program the backend made */
static void test_nothing_leaks(void **state)
{
    NEED_GL(*state);
    gmaps g;
    gmaps_make(&g, GW, GH, 16);
    qibl_gles2_t gl;
    qibl_gles2_desc_t d = {6, 0, 0}; /* 3 P map units, 1 map texture, 2 accumulator codes */
    assert_int_equal(qibl_gles2_init(&gl, &d), QIBL_OK);
    assert_int_equal(qibl_gles2_upload(&gl, &g.m, &g.p, NULL), QIBL_OK);
    qibl_shmap_point_t pt;
    qibl_pointlight_t pl = {{30000, -90000, 20000}, {200000, 160000, 120000}, QIBL_FALLOFF_INV_DIST, 0,
                            QIBL_LUT_BILINEAR};
    assert_int_equal(qibl_shmap_point_prepare(&g.m, &g.p, NULL, &pl, &pt), QIBL_OK);
    glBindFramebuffer(GL_FRAMEBUFFER, ctx.fbo);
    assert_int_equal(qibl_gles2_point(&gl, &pt, NULL), QIBL_OK);
    assert_true(qibl_gles2_passes(&gl) > 1u);
    qibl_gles2_t copy = gl;
    qibl_gles2_destroy(&gl);
    for (uint32_t i = 0; i < QIBL_GLES2_MAX_TEX; ++i)
        assert_false(copy.map_tex[i] != 0u && glIsTexture(copy.map_tex[i]));
    for (uint32_t i = 0; i < 3; ++i)
        assert_false(glIsTexture(copy.p_tex[i]));
    for (uint32_t i = 0; i < 4; ++i)
        assert_false(glIsTexture(copy.acc_tex[i]) || glIsFramebuffer(copy.fbo[i % 2u]));
    for (uint32_t p = 0; p < QIBL_GLES2_MAX_PASSES; ++p)
        assert_false(copy.prog[QIBL_GLES2_MODE_POINT_SH][p] != 0u && glIsProgram(copy.prog[QIBL_GLES2_MODE_POINT_SH][p]));
    assert_false(glIsBuffer(copy.vbo) || glIsShader(copy.vs));
    qibl_gles2_destroy(&gl); /* twice is safe */
    gmaps_free(&g);
}

/* Under `make test-asan`: Mesa's drivers keep a few hundred bytes past eglTerminate, from a module
 * already unloaded (so no suppression can name it). Leak checking is off for this suite only;
 * ASan and UBSan still check every access of ours. */
#if defined(__SANITIZE_ADDRESS__)
#define QTOOL_LSAN_OFF 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define QTOOL_LSAN_OFF 1
#endif
#endif
#ifdef QTOOL_LSAN_OFF
void __lsan_disable(void);
#endif

int main(void)
{
#ifdef QTOOL_LSAN_OFF
    __lsan_disable();
#endif
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_relight_scenes_match_soft),
        cmocka_unit_test(test_srgbe_shader_matches_codec),
        cmocka_unit_test(test_named_errors),
        cmocka_unit_test(test_nothing_leaks),
        cmocka_unit_test(test_luminaire_passes_match_soft),
        cmocka_unit_test(test_luminaire_spots_match_soft),
        cmocka_unit_test(test_gonio_point_matches_soft),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

#else /* built without the EGL/GLES2 headers */

static void test_gles_absent(void **state)
{
    (void)state;
    if (require_gles())
        fail_msg("QIBL_REQUIRE_GLES=1 but qibl was built without the EGL/GLES2 headers");
    printf("SKIP gles2_test: built without the EGL/GLES2 headers\n");
    skip();
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_gles_absent)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
#endif
