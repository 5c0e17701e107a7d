/*
 * gles.c - `qibl bench gles`: frames per second of platform/gles2 at 1024x256, k = 9/16/25,
 * a directional light and a point light (direct SH and cube-map LUT), on whatever GL the headless
 * EGL context gets. Here that is Mesa's llvmpipe, a CPU rasterizer: its figures say nothing about a
 * GPU, only that the path runs and how passes scale. Timing: glFinish around each frame, median.
 */
#include "bench/bench.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>


#if QIBL_HAVE_GLES2
#include <GLES2/gl2.h>

#include "gles/headless.h"
#include "qibl/gles2.h"

static uint32_t rng(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15u);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9u;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBu;
    return (uint32_t)((z ^ (z >> 31)) >> 32);
}

static void put32(uint8_t *p, int32_t v)
{
    uint32_t u = (uint32_t)v;
    p[0] = (uint8_t)u, p[1] = (uint8_t)(u >> 8), p[2] = (uint8_t)(u >> 16), p[3] = (uint8_t)(u >> 24);
}

static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

int qtool_bench_gles(int quick)
{
    enum { W = 1024, H = 256 };
    const int frames = quick ? 3 : 9;
    qt_gles_ctx c;
    char why[256];
    if (qt_gles_open(&c, W, H, why, sizeof why) != 0) {
        printf("== bench gles: SKIP (%s)\n", why);
        return 0;
    }
    uint8_t *params = malloc(8u * 75u), *planes = malloc((size_t)W * H * 75u), *points = malloc((size_t)W * H * 12u);
    if (!params || !planes || !points) {
        fprintf(stderr, "qibl: bench gles: out of memory\n");
        free(params), free(planes), free(points), qt_gles_close(&c);
        return 1;
    }
    uint64_t s = 7;
    for (int i = 0; i < 75; ++i)
        put32(params + 8 * i, (int32_t)(rng(&s) % 65536u) - 32768), put32(params + 8 * i + 4, (int32_t)(rng(&s) % 65536u));
    for (size_t i = 0; i < (size_t)W * H * 75u; ++i)
        planes[i] = (uint8_t)rng(&s);
    for (uint32_t y = 0; y < H; ++y)
        for (uint32_t x = 0; x < W; ++x) { /* a cylinder of radius 4 around the viewpoint */
            uint8_t *q = points + 12u * ((size_t)y * W + x);
            put32(q, (int32_t)(x * 512u) - 262144), put32(q + 4, (int32_t)((x * 37u) % 512u) * 1024 - 262144);
            put32(q + 8, (int32_t)(y * 1024u) - 131072);
        }
    printf("== bench gles: platform/gles2, %dx%d, median of %d frames (glFinish each) on %s%s\n", W, H, frames,
           c.renderer, strstr(c.renderer, "llvmpipe") ? " - a CPU rasterizer, not a GPU" : "");
    printf("%-6s %-14s %8s %10s\n", "k", "light", "passes", "fps");
    int rc = 0;
    for (uint32_t k = 9; k <= 25 && rc == 0; k += k == 9 ? 7u : 9u) {
        qibl_shmaps_t m = {W, H, k, 3, params, planes, QIBL_SHMAPS_PLANAR};
        qibl_pmap_t pm = {W, H, points};
        size_t vs = qibl_ylut_values_size(32, k);
        uint8_t *vals = malloc(vs);
        qibl_ylut_t lut = {32, k, vals, vs};
        qibl_gles2_t g;
        qibl_status_t st = vals ? qibl_ylut_build(32, k, vals, vs) : QIBL_E_NULL_POINTER;
        if (st == QIBL_OK)
            st = qibl_gles2_init(&g, NULL);
        if (st == QIBL_OK)
            st = qibl_gles2_upload(&g, &m, &pm, &lut);
        for (int mode = 0; mode < 3 && st == QIBL_OK; ++mode) {
            qibl_shlight_t l;
            qibl_shmap_weights_t w;
            qibl_shmap_point_t pt;
            const qibl_q16_t dir[3] = {30000, 20000, 50000}, rgb[3] = {65536, 60000, 50000};
            qibl_pointlight_t pl = {{20000, -30000, 10000}, {300000, 280000, 250000}, QIBL_FALLOFF_INV_DIST, 0,
                                    QIBL_LUT_BILINEAR};
            if (mode == 0) {
                st = qibl_shlight_init(&l, k);
                if (st == QIBL_OK)
                    st = qibl_shlight_add_dir(&l, dir, rgb);
                if (st == QIBL_OK)
                    st = qibl_shmap_weights(&m, &l, &w);
            } else {
                st = qibl_shmap_point_prepare(&m, &pm, mode == 2 ? &lut : NULL, &pl, &pt);
            }
            double t[16];
            for (int f = -1; f < frames && st == QIBL_OK; ++f) { /* frame -1 compiles the shaders */
                glBindFramebuffer(GL_FRAMEBUFFER, c.fbo);
                glFinish();
                double t0 = qtool_bench_now();
                st = mode == 0 ? qibl_gles2_relight(&g, &w, NULL) : qibl_gles2_point(&g, &pt, NULL);
                glFinish();
                if (f >= 0)
                    t[f] = qtool_bench_now() - t0;
            }
            if (st != QIBL_OK)
                break;
            qsort(t, (size_t)frames, sizeof t[0], cmp_d);
            const char *names[3] = {"dir", "point_direct", "point_lut32"};
            double fps = 1.0 / t[frames / 2];
            printf("%-6u %-14s %8u %10.1f\n", k, names[mode], qibl_gles2_passes(&g), fps);
            printf("RESULT gles.fps_%s_k%u %.1f\n", names[mode], k, fps);
        }
        if (st != QIBL_OK) {
            fprintf(stderr, "qibl: bench gles: k = %u: %s: %s\n", k, qibl_gles2_status_str(st), qibl_gles2_log(&g));
            rc = 1;
        }
        if (vals)
            qibl_gles2_destroy(&g);
        free(vals);
    }
    free(params), free(planes), free(points);
    qt_gles_close(&c);
    return rc;
}
#else
int qtool_bench_gles(int quick)
{
    (void)quick;
    printf("== bench gles: SKIP (this qibl was built without the EGL/GLES2 headers)\n");
    return 0;
}
#endif
