/*
 * golden/cases_raster.c - raster_*: z-buffered Gouraud triangles (qibl/raster.h) into an odd-sized
 * framebuffer: a jittered grid whose cells wind both ways and reach past every edge (shared edges,
 * clipping), then random triangles in the guard band (huge ones, slivers, degenerate ones,
 * interleaved depths, out-of-range colours). Each case hashes the framebuffer bytes followed by
 * the depth buffer as little-endian words. Integers only: the scene is the same on every port.
 */
#include "golden/casesi.h"

#include <stdlib.h>
#include <string.h>

#include "qibl/raster.h"

#define ONE 65536

enum { RW = 97, RH = 61, GX = 9, GY = 7, NRND = 24 };
enum { NV = GX * GY + 3 * NRND, NT = 2 * (GX - 1) * (GY - 1) + NRND };

static uint32_t lcg(uint32_t *s)
{
    *s = *s * 1664525u + 1013904223u;
    return *s >> 8; /* 24 bits */
}

/* uniform in [lo, lo + span) for span <= 2^24 */
static int32_t pick(uint32_t *s, int32_t lo, uint32_t span)
{
    return lo + (int32_t)(lcg(s) % span);
}

static void scene(qibl_raster_vertex_t *v, uint32_t (*tri)[3])
{
    uint32_t s = 0x2545F491u;
    uint32_t nv = 0, nt = 0;
    /* the grid spans -20 .. 117 px by -15 .. 76 px, jittered by up to 5 px */
    for (int j = 0; j < GY; ++j)
        for (int i = 0; i < GX; ++i, ++nv) {
            v[nv].x = (-20 + i * 137 / (GX - 1)) * 16 + pick(&s, -80, 161);
            v[nv].y = (-15 + j * 91 / (GY - 1)) * 16 + pick(&s, -80, 161);
            v[nv].z = pick(&s, 1 << 28, 1u << 24) << 2;
            for (int c = 0; c < 3; ++c)
                v[nv].rgb[c] = pick(&s, -ONE / 10, (uint32_t)(ONE * 14 / 10));
        }
    for (int j = 0; j + 1 < GY; ++j)
        for (int i = 0; i + 1 < GX; ++i) {
            const uint32_t a = (uint32_t)(j * GX + i), b = a + 1, c = a + GX, d = c + 1;
            const int flip = (i + j) & 1, rev = (i * 3 + j) % 4 == 0; /* both diagonals, both windings */
            uint32_t t0[3] = {a, b, flip ? d : c}, t1[3] = {flip ? a : b, d, c};
            if (rev) {
                uint32_t x = t0[1];
                t0[1] = t0[2], t0[2] = x;
                x = t1[1], t1[1] = t1[2], t1[2] = x;
            }
            memcpy(tri[nt++], t0, sizeof t0);
            memcpy(tri[nt++], t1, sizeof t1);
        }
    /* random triangles in front of and behind the grid */
    for (int k = 0; k < NRND; ++k) {
        const uint32_t base = nv;
        const int kind = k % 4; /* 0 ordinary, 1 huge (guard band), 2 sliver, 3 degenerate */
        for (int c = 0; c < 3; ++c, ++nv) {
            const int32_t r = kind == 1 ? 4000 : 60;
            v[nv].x = pick(&s, (48 - r) * 16, (uint32_t)(2 * r * 16));
            v[nv].y = pick(&s, (30 - r) * 16, (uint32_t)(2 * r * 16));
            v[nv].z = pick(&s, 1 << 20, 1u << 24) << 6;
            for (int ch = 0; ch < 3; ++ch)
                v[nv].rgb[ch] = pick(&s, -ONE / 4, (uint32_t)(ONE * 3 / 2));
        }
        if (kind == 2) /* third vertex 1/16 px off the line through the first two's midpoint */
            v[base + 2].x = (v[base].x + v[base + 1].x) / 2 + 1, v[base + 2].y = (v[base].y + v[base + 1].y) / 2;
        if (kind == 3)
            v[base + 2] = v[base + 1], v[base + 2].z = v[base].z;
        tri[nt][0] = base, tri[nt][1] = base + 1, tri[nt][2] = base + 2;
        ++nt;
    }
}

int qtool_goldens_raster(const qtool_goldens_sink_t *s)
{
    static const struct {
        qtool_gcase_fb fb;
        qibl_raster_cull_t cull;
    } cases[] = {
        {{"raster_mesh_rgba8888_srgb", QIBL_FB_RGBA8888, 1, 0, 0}, QIBL_RASTER_CULL_NONE},
        {{"raster_mesh_rgb565_dither_exp2", QIBL_FB_RGB565, 0, 1, 2 * ONE}, QIBL_RASTER_CULL_NONE},
        {{"raster_mesh_bgra8888_cull_cw", QIBL_FB_BGRA8888, 0, 0, 0}, QIBL_RASTER_CULL_CW},
    };
    qibl_raster_vertex_t *v = malloc(sizeof *v * NV);
    uint32_t(*tri)[3] = malloc(sizeof *tri * NT);
    uint32_t *depth = malloc(sizeof *depth * RW * RH);
    uint8_t *out = malloc((size_t)RW * RH * 8);
    int bad = 0;
    if (!v || !tri || !depth || !out) {
        free(v), free(tri), free(depth), free(out);
        return qtool_gcase_oom(s, "raster_mesh");
    }
    scene(v, tri);
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        qibl_raster_target_t t;
        memset(&t, 0, sizeof t);
        t.fb.pixels = out, t.fb.width = RW, t.fb.height = RH;
        qtool_gcase_fb_set(&t.fb, &cases[i].fb);
        t.depth = depth, t.depth_count = (size_t)RW * RH, t.cull = cases[i].cull;
        qibl_status_t st = qibl_soft_fb_clear(&t.fb);
        if (st == QIBL_OK)
            st = qibl_soft_raster_clear_depth(&t);
        if (st == QIBL_OK)
            st = qibl_soft_raster_triangles(&t, v, NV, (const uint32_t(*)[3])tri, NT);
        if (st != QIBL_OK) {
            bad += qtool_gcase_status_error(s, cases[i].fb.name, "qibl_soft_raster_triangles", st);
            continue;
        }
        const size_t fbn = (size_t)RW * RH * qibl_soft_fb_bytes_per_pixel(cases[i].fb.format);
        for (size_t k = 0; k < (size_t)RW * RH; ++k)
            for (int b = 0; b < 4; ++b)
                out[fbn + 4 * k + (size_t)b] = (uint8_t)(depth[k] >> (8 * b));
        bad += qtool_gcase_emit(s, cases[i].fb.name, out, fbn + (size_t)RW * RH * 4);
    }
    free(v), free(tri), free(depth), free(out);
    return bad;
}
