/*
 * paths.c - `qibl bench paths`: what a path light costs per frame against today's SH-only
 * relighting. Maps of the procedural courtyard (speed depends on k and size, not on the content),
 * a visibility chunk shaped like a sun's over the courtyard (smooth rise and set, round cast shadows;
 * about 1.7 edges per pixel, as the demo's bakes).
 * Core spans only (no framebuffer write), median of several frames.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/path.h"
#include "gen/scene.h"
#include "io/asset_write.h"
#include "bench/bench.h"
#include "qibl/lightpath.h"
#include "qibl/shmap.h"

#define REPS_MAX 15

typedef struct {
    qibl_shmaps_t m;
    uint8_t *params, *planes;
    qibl_ylut_t lut;
    uint8_t *lutv;
} bmaps;

static int bmaps_make(const qtool_gen_maps *g, uint32_t k, bmaps *b)
{
    qtool_gen_maps view = *g;
    view.k = k;
    memset(b, 0, sizeof *b); /* fields this file does not name (a layout) take their defaults */
    size_t np = (size_t)g->width * g->height;
    int32_t *scale = malloc(sizeof(int32_t) * k * 3), *bias = malloc(sizeof(int32_t) * k * 3);
    size_t vs = qibl_ylut_values_size(32, k);
    b->params = malloc(8u * k * 3), b->planes = malloc(np * k * 3), b->lutv = malloc(vs);
    int rc = -1;
    if (scale && bias && b->params && b->planes && b->lutv &&
        qtool_pack_maps(&view, QTOOL_PACK_MINMAX, scale, bias, b->planes, NULL) == 0 &&
        qibl_ylut_build(32, k, b->lutv, vs) == QIBL_OK) {
        for (uint32_t i = 0; i < k * 3; ++i) {
            qtool_store_s32le(b->params + 8 * i, scale[i]);
            qtool_store_s32le(b->params + 8 * i + 4, bias[i]);
        }
        b->m.width = g->width, b->m.height = g->height, b->m.k = k, b->m.channels = 3;
        b->m.params = b->params, b->m.planes = b->planes;
        b->lut.face_size = 32, b->lut.k = k, b->lut.values = b->lutv, b->lut.size = vs;
        rc = 0;
    }
    free(scale), free(bias);
    return rc;
}

static void bmaps_free(bmaps *b)
{
    free(b->params), free(b->planes), free(b->lutv);
}

typedef struct {
    const bmaps *sky, *light; /* sky: shadowed maps (NULL: no sky); light: today's or the unshadowed maps */
    const qibl_lightpath_t *path; /* NULL: SH only */
    const qibl_pmap_t *pmap;      /* NULL: directional */
    uint32_t radius;
} bcase;

static double run(const bcase *c, uint32_t w, uint32_t h, int reps, int32_t *row, int32_t *lrow, void *ws, size_t wsn)
{
    const qibl_q16_t dir[3] = {36044, 22938, 49807}, rgb[3] = {104858, 95027, 78643};
    qibl_pointlight_t lamp = {{98304, -131072, 52429}, {262144, 222822, 170394}, QIBL_FALLOFF_INV_DIST, 0,
                              QIBL_LUT_BILINEAR};
    double t[REPS_MAX];
    for (int r = 0; r < reps; ++r) {
        double t0 = qtool_bench_cpu_now();
        qibl_shlight_t sl, sky;
        qibl_shmap_weights_t wl, wsky;
        qibl_shmap_point_t pt;
        QTOOL_BENCH_CALL(qibl_shlight_init(&sl, 25));
        QTOOL_BENCH_CALL(qibl_shlight_add_dir(&sl, dir, rgb));
        if (c->pmap)
            QTOOL_BENCH_CALL(qibl_shmap_point_prepare(&c->light->m, c->pmap, &c->light->lut, &lamp, &pt));
        else
            QTOOL_BENCH_CALL(qibl_shmap_weights(&c->light->m, &sl, &wl));
        if (c->sky) {
            const qibl_q16_t up[3] = {0, 0, 65536}, sc[3] = {20000, 30000, 52000};
            QTOOL_BENCH_CALL(qibl_shlight_init(&sky, 25));
            QTOOL_BENCH_CALL(qibl_shlight_add_dir(&sky, up, sc));
            QTOOL_BENCH_CALL(qibl_shmap_weights(&c->sky->m, &sky, &wsky));
        }
        uint32_t tq = 20000u + 1000u * (uint32_t)r;
        for (uint32_t y = 0; y < h; ++y) {
            int32_t *dst = c->path ? lrow : row;
            if (c->sky)
                QTOOL_BENCH_CALL(qibl_shmap_relight_span(&c->sky->m, &wsky, 0, y, w, row, ws, wsn));
            if (c->pmap)
                QTOOL_BENCH_CALL(qibl_shmap_point_span(&pt, 0, y, w, dst, ws, wsn));
            else
                QTOOL_BENCH_CALL(qibl_shmap_relight_span(&c->light->m, &wl, 0, y, w, dst, ws, wsn));
            if (c->path)
                QTOOL_BENCH_CALL(qibl_lightpath_shade_span(c->path, tq, c->radius, 0, y, w, lrow, row, c->sky != NULL));
        }
        t[r] = qtool_bench_cpu_now() - t0;
    }
    return qtool_bench_median(t, reps) * 1e3;
}

int qtool_bench_paths(int quick)
{
    const uint32_t W = quick ? 256 : 1024, H = quick ? 64 : 256;
    const int reps = quick ? 3 : 11;
    size_t np = (size_t)W * H;
    qtool_gen_maps g;
    bmaps m9, m16;
    if (qtool_gen_scene(W, H, 16, QTOOL_PANO_CYLINDRICAL, &g) != 0 || bmaps_make(&g, 9, &m9) != 0 ||
        bmaps_make(&g, 16, &m16) != 0) {
        fprintf(stderr, "qibl: bench paths: out of memory\n");
        return 1;
    }
    /* visibility like a sun's over a courtyard: each pixel rises and sets at times that vary smoothly
     * across the panorama, and round cast shadows (two more edges) cover about a third of it */
    uint8_t *counts = malloc(np), *lp = NULL;
    uint16_t *edges = malloc(np * 5 * sizeof(uint16_t));
    uint32_t ne = 0, kt[2] = {0, 65535};
    int32_t kv[6] = {65536, 0, 0, 0, 0, 65536};
    for (uint32_t y = 0; counts && edges && y < H; ++y)
        for (uint32_t x = 0; x < W; ++x) {
            double u = (double)x / W, v = (double)y / H;
            uint32_t rise = (uint32_t)(6000 + 5000 * sin(6.2832 * u) + 3000 * v);
            uint32_t set = (uint32_t)(58000 - 5000 * cos(6.2832 * u) - 2000 * v), m = 0;
            uint8_t *c = counts + (size_t)y * W + x;
            if ((x / 37 + y / 23) % 3 == 0) { /* facing away all day */
                *c = 0;
                continue;
            }
            edges[ne++] = (uint16_t)rise, ++m;
            double dx = fmod(u * 7, 1.0) - 0.5, dy = v - 0.6;
            if (dx * dx + dy * dy < 0.1) { /* a cast shadow mid-day */
                uint32_t a = 20000 + (uint32_t)(20000 * (dx + 0.5)), b = a + 9000;
                edges[ne++] = (uint16_t)a, edges[ne++] = (uint16_t)b, m += 2;
            }
            edges[ne++] = (uint16_t)set, ++m;
            *c = (uint8_t)m;
        }
    size_t lpn = 0;
    qibl_lightpath_t path;
    qibl_pmap_t pm = {W, H, NULL};
    uint8_t *pts = malloc(np * 12);
    int32_t *row = malloc(sizeof(int32_t) * 3 * W), *lrow = malloc(sizeof(int32_t) * 3 * W);
    size_t wsn = qibl_shmap_point_workspace_size(25, W);
    void *ws = malloc(wsn);
    if (!counts || !edges || !pts || !row || !lrow || !ws ||
        qtool_bake_path_payload(W, H, 0, 2, kt, kv, counts, edges, ne, &lp, &lpn) != 0 ||
        qibl_lightpath_parse(lp, lpn, &path) != QIBL_OK) {
        fprintf(stderr, "qibl: bench paths: out of memory\n");
        return 1;
    }
    for (size_t i = 0; i < np * 3; ++i)
        qtool_store_s32le(pts + 4 * i, g.p[i]);
    pm.points = pts;
    static const char *names[] = {"sun: today, shadowed SH k16", "sun: unshadowed k9 x path", "sun: unshadowed k16 x path",
                                  "soft sun: k9 x path, radius 600", "sky (SH k16) + sun (k9 x path)",
                                  "lamp: today, SH k16 LUT 32", "lamp: unshadowed k9 LUT 32 x track",
                                  "lamp: free, unshadowed k9 LUT 32", "sun: unshadowed k9, no path (SH part)"};
    bcase cases[] = {{NULL, &m16, NULL, NULL, 0}, {NULL, &m9, &path, NULL, 0},  {NULL, &m16, &path, NULL, 0},
                     {NULL, &m9, &path, NULL, 600}, {&m16, &m9, &path, NULL, 0}, {NULL, &m16, NULL, &pm, 0},
                     {NULL, &m9, &path, &pm, 0},    {NULL, &m9, NULL, &pm, 0},   {NULL, &m9, NULL, NULL, 0}};
    enum { NC = sizeof cases / sizeof cases[0] };
    double ms[NC];
    /* Every scheme and its baseline in one loop: per repetition each scheme's frame right after its
     * baseline's (both run twice in a row, the second timed: their own warm caches), the order of
     * the schemes rotated; a ratio is the median over repetitions of scheme / baseline of the same
     * repetition (qtool_bench_paired_ratio), so load changes between repetitions cancel. ms: medians. */
    double tt[NC][REPS_MAX], xr[NC];
    for (int r = 0; r < reps; ++r)
        for (int j = 0; j < NC; ++j) {
            const int i = (j + r) % NC, base = i < 5 || i == 8 ? 0 : 5;
            const int seq[2] = {base, i};
            for (int q = 0; q < (i == base ? 1 : 2); ++q) {
                run(&cases[seq[q]], W, H, 1, row, lrow, ws, wsn);
                const double t = run(&cases[seq[q]], W, H, 1, row, lrow, ws, wsn);
                if (q == 1 || i == base)
                    tt[i][r] = t;
                else
                    xr[i] = t;
            }
            if (i != base)
                tt[i][r] = tt[i][r] / xr[i]; /* the paired ratio of this repetition */
        }
    for (int i = 0; i < NC; ++i) {
        const int base = i < 5 || i == 8 ? 0 : 5;
        double v[REPS_MAX];
        for (int r = 0; r < reps; ++r)
            v[r] = tt[i][r];
        xr[i] = i == base ? 1.0 : qtool_bench_median(v, reps);
    }
    for (int i = 0; i < NC; ++i) {
        const int base = i < 5 || i == 8 ? 0 : 5;
        if (i == base) {
            double v[REPS_MAX];
            for (int r = 0; r < reps; ++r)
                v[r] = tt[i][r];
            ms[i] = qtool_bench_median(v, reps);
        }
    }
    for (int i = 0; i < NC; ++i) {
        const int base = i < 5 || i == 8 ? 0 : 5;
        if (i != base)
            ms[i] = ms[base] * xr[i];
    }
    printf("== bench paths: %ux%u, core spans only (no framebuffer), thread CPU time, %d interleaved repetitions, "
           "each scheme paired with its baseline (ratios: median of the pairs); visibility %.2f edges/pixel\n",
           W, H, reps, (double)ne / (double)np);
    printf("%-36s %10s %8s\n", "scheme", "ms/frame", "x today");
    for (int i = 0; i < NC; ++i)
        printf("%-36s %10.3f %8.3f\n", names[i], ms[i], xr[i]);
    printf("RESULT paths.sun_k9_cost_ratio %.3f\nRESULT paths.sun_k16_cost_ratio %.3f\n", xr[1], xr[2]);
    printf("RESULT paths.soft_sun_k9_cost_ratio %.3f\nRESULT paths.sky_sun_cost_ratio %.3f\n", xr[3], xr[4]);
    printf("RESULT paths.track_lamp_k9_cost_ratio %.3f\nRESULT paths.free_lamp_k9_cost_ratio %.3f\n", xr[6], xr[7]);
    printf("RESULT paths.dir_k16_ms %.3f\n", ms[0]);
    qtool_gen_free(&g);
    bmaps_free(&m9), bmaps_free(&m16);
    free(counts), free(edges), free(lp), free(pts), free(row), free(lrow), free(ws);
    return 0;
}
