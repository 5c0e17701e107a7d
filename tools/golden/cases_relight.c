/*
 * golden/cases_relight.c - relight_*: fixed 8-bit SH maps and a P map, relit by directional and
 * point lights (direct SH, cube-map LUT bilinear and nearest, Q2.14 polynomials, both falloffs), written into every
 * framebuffer format of platform/soft. Moved here from tests/shmap_test.c (same data, same hashes).
 * relight_il_*: the same maps in the interleaved layout (shmaps.h) through the same calls; their
 * fixtures/golden files hold the planar cases' hashes, so the runner proves both layouts give the
 * same bytes on every port. relight_camera_*: a fixed-camera asset (cases_camera.c).
 */
#include "golden/casesi.h"

#include <stdio.h>
#include <stdlib.h>

#include "qibl/shmap.h"
#include "qibl/soft.h"

#if QIBL_USE_SHMAP /* the group exists only when config.h builds the module */

enum { GW = 64, GH = 16 };

typedef struct {
    qibl_shmaps_t m;
    qibl_pmap_t p;
    uint8_t *params, *planes, *points;
} gmaps;

/* Integer-only fixture: scale/bias like packed maps from the PRNG, planes of ramps plus a little
 * noise, a P map on a cylinder around the origin. The PRNG draws are in the order the fixture was
 * first made in (params, then one draw per plane byte that the ramps then replace, then the
 * noise), so the hashes stay those of fixtures/golden. */
static int gmaps_make(gmaps *g, uint32_t w, uint32_t h, uint32_t k)
{
    const uint32_t ch = 3;
    const int32_t scale_mag = 1 << 17;
    qtool_grng r = {2026};
    g->m.width = w, g->m.height = h, g->m.k = k, g->m.channels = ch, g->m.layout = QIBL_SHMAPS_PLANAR;
    g->params = malloc(8u * k * ch);
    g->planes = malloc((size_t)w * h * k * ch);
    g->points = malloc((size_t)w * h * 12u);
    if (g->params == NULL || g->planes == NULL || g->points == NULL)
        return -1;
    for (uint32_t i = 0; i < k * ch; ++i) {
        int32_t sc = (int32_t)(qtool_grng_u32(&r) % (uint32_t)scale_mag) - scale_mag / 2;
        int32_t bi = -128 * sc + (int32_t)(qtool_grng_u32(&r) % 2001u) - 1000; /* centred ranges, as packing gives */
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
    return 0;
}

static void gmaps_free(gmaps *g)
{
    free(g->params), free(g->planes), free(g->points);
}

static const qtool_gcase_fb fbs[] = {
    {"rgba8888_srgb", QIBL_FB_RGBA8888, 1, 0, 0},
    {"bgra8888_linear_exp2", QIBL_FB_BGRA8888, 0, 0, 2u << 16},
    {"rgb565_dither", QIBL_FB_RGB565, 1, 1, 0},
    {"accum32", QIBL_FB_ACCUM32, 0, 0, 0},
};

/* A row renderer: fills out (3 * GW int32) for row y; returns QIBL_OK or the failing status. */
typedef qibl_status_t (*row_fn)(void *ctx, uint32_t y, int32_t *out);

/* Renders every row through render into every framebuffer format and emits each as
 * relight_<prefix>_<format>. Returns the number of failed cases. */
static int emit_formats(const qtool_goldens_sink_t *s, const char *prefix, row_fn render, void *ctx)
{
    int bad = 0;
    int32_t row[3 * GW];
    for (size_t f = 0; f < sizeof fbs / sizeof fbs[0]; ++f) {
        char name[96];
        snprintf(name, sizeof name, "relight_%s_%s", prefix, fbs[f].name);
        qibl_fb_desc_t fb = {0};
        fb.width = GW, fb.height = GH;
        qtool_gcase_fb_set(&fb, &fbs[f]);
        size_t bytes = (size_t)GW * GH * qibl_soft_fb_bytes_per_pixel(fb.format);
        fb.pixels = calloc(bytes, 1);
        if (fb.pixels == NULL) {
            bad += qtool_gcase_oom(s, name);
            continue;
        }
        qibl_status_t st = qibl_soft_fb_check(&fb);
        const char *call = "qibl_soft_fb_check";
        for (uint32_t y = 0; y < GH && st == QIBL_OK; ++y) {
            st = render(ctx, y, row), call = "relight span";
            if (st == QIBL_OK)
                st = qibl_soft_fb_write_row(&fb, 0, y, GW, row), call = "qibl_soft_fb_write_row";
        }
        bad += st == QIBL_OK ? qtool_gcase_emit(s, name, fb.pixels, bytes) : qtool_gcase_status_error(s, name, call, st);
        free(fb.pixels);
    }
    return bad;
}

typedef struct {
    const qibl_shmaps_t *m;
    qibl_shmap_weights_t w;
    int32_t ws[GW * 3];
} dir_ctx;

static qibl_status_t dir_row(void *c, uint32_t y, int32_t *out)
{
    dir_ctx *d = (dir_ctx *)c;
    /* two spans per row, as a caller splitting work would */
    qibl_status_t st = qibl_shmap_relight_span(d->m, &d->w, 0, y, 23, out, d->ws, sizeof d->ws);
    return st != QIBL_OK ? st : qibl_shmap_relight_span(d->m, &d->w, 23, y, GW - 23, out + 3 * 23, d->ws, sizeof d->ws);
}

typedef struct {
    qibl_shmap_point_t st;
    int32_t ws[(GW * (2 * 25 + 32) + 3) / 4]; /* int32 storage: the span calls need 4-byte alignment */
} point_ctx;

static qibl_status_t point_row(void *c, uint32_t y, int32_t *out)
{
    point_ctx *p = (point_ctx *)c;
    return qibl_shmap_point_span(&p->st, 0, y, GW, out, p->ws, sizeof p->ws);
}

/* g's planes rewritten in the interleaved layout (same bytes, other order) */
static int gmaps_interleave(gmaps *g)
{
#if !QIBL_USE_INTERLEAVED
    (void)g;
    return -1;
#else
    qibl_shmaps_t il = g->m;
    il.layout = QIBL_SHMAPS_INTERLEAVED;
    size_t n = qibl_shmaps_row_size(&il) * g->m.height;
    uint8_t *b = malloc(n);
    if (b == NULL || qibl_shmaps_interleave(&g->m, b, n) != QIBL_OK) {
        free(b);
        return -1;
    }
    free(g->planes);
    g->planes = b;
    g->m.planes = b;
    g->m.layout = QIBL_SHMAPS_INTERLEAVED;
    return 0;
#endif
}

int qtool_goldens_relight(const qtool_goldens_sink_t *s)
{
    int bad = 0;
    /* the interleaved cases exist when config.h builds the layout */
    for (uint32_t kl = 0; kl < (QIBL_USE_INTERLEAVED ? 4u : 2u); ++kl) {
        const uint32_t k = kl % 2u ? 16u : 9u, il = kl / 2u;
        const char *lay = il ? "il_" : "";
        char prefix[40];
        snprintf(prefix, sizeof prefix, "%sk%u", lay, k);
        gmaps g;
        if (gmaps_make(&g, GW, GH, k) != 0 || (il && gmaps_interleave(&g) != 0)) {
            gmaps_free(&g);
            bad += qtool_gcase_oom(s, prefix);
            continue;
        }
        /* directional: a warm sun and a cool sky light together */
        dir_ctx dc;
        dc.m = &g.m;
        qibl_shlight_t l;
        const qibl_q16_t dirs[2][3] = {{40000, 25000, 52000}, {0, 0, 65536}}; /* sun, sky */
        const qibl_q16_t rgbs[2][3] = {{150000, 120000, 90000}, {20000, 30000, 52000}};
        qibl_status_t st = qtool_gcase_dir_lights(&l, k, 2, dirs, rgbs);
        if (st == QIBL_OK)
            st = qibl_shmap_weights(&g.m, &l, &dc.w);
        snprintf(prefix, sizeof prefix, "%sdir_k%u", lay, k);
        bad += st == QIBL_OK ? emit_formats(s, prefix, dir_row, &dc) : qtool_gcase_status_error(s, prefix, "weights", st);
        /* point light: direct SH, LUT bilinear, LUT nearest, Q2.14 polynomials; both falloffs */
        size_t vs = qibl_ylut_values_size(16, k);
        uint8_t *vals = malloc(vs);
        st = vals ? qibl_ylut_build(16, k, vals, vs) : QIBL_E_WORKSPACE;
        qibl_ylut_t lut = {16, k, vals, vs};
        const char *modes[5] = {"direct", "lut16", "lut16_nearest", "poly", "poly_d2"};
        for (int mode = 0; mode < 5; ++mode) {
            point_ctx pc;
            qibl_pointlight_t pl = {{30000, -90000, 20000}, {200000, 160000, 120000},
                                    mode == 1 || mode == 4 ? QIBL_FALLOFF_INV_DIST2 : QIBL_FALLOFF_INV_DIST, 0,
                                    mode == 2 ? QIBL_LUT_NEAREST : mode >= 3 ? QIBL_POINT_POLY : QIBL_LUT_BILINEAR};
            snprintf(prefix, sizeof prefix, "%spoint_k%u_%s", lay, k, modes[mode]);
            qibl_status_t pst = st == QIBL_OK ? qibl_shmap_point_prepare(&g.m, &g.p, mode == 1 || mode == 2 ? &lut : NULL, &pl, &pc.st) : st;
            bad += pst == QIBL_OK ? emit_formats(s, prefix, point_row, &pc)
                                  : qtool_gcase_status_error(s, prefix, "ylut_build / point_prepare", pst);
        }
        free(vals);
        gmaps_free(&g);
    }
#if QIBL_USE_ASSET
    bad += qtool_goldens_relight_camera(s); /* a perspective frame's asset (cases_camera.c) */
#endif
    return bad;
}

#else
typedef int qtool_goldens_relight_off; /* ISO C wants a declaration in every file */
#endif /* QIBL_USE_SHMAP */
