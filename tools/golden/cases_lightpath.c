/*
 * golden/cases_lightpath.c - lightpath_*: an integer-made LPTH payload (random edges per pixel,
 * some lit from the start), its hard and soft visibility spans, key interpolation, the statuses of
 * damaged payloads, and a sun relit through integer-made k = 9 maps x visibility (alone, and added
 * to a sky through other maps) in two framebuffer formats.
 */
#include "golden/casesi.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "qibl/lightpath.h"
#include "qibl/shmtile.h"
#include "qibl/shmap.h"
#include "qibl/soft.h"

#if QIBL_USE_LIGHTPATH

enum { LW = 48, LH = 12, LK = 9, NKEYS = 5 };

/* The payload: kind, keys on a quarter circle (directions) or a line (positions), 0..6 edges per
 * pixel. Returns a malloc'ed buffer and its size in *n, NULL on out of memory. */
static uint8_t *make_path(uint32_t kind, uint64_t seed, size_t *n)
{
    qtool_grng r = {seed};
    uint8_t counts[LW * LH];
    uint16_t edges[LW * LH * 7];
    uint32_t ne = 0;
    for (uint32_t i = 0; i < LW * LH; ++i) {
        uint32_t c = qtool_grng_u32(&r) % 7u, last = 0, m = 0;
        if (qtool_grng_u32(&r) % 4u == 0u)
            edges[ne++] = 0, ++m;
        for (uint32_t j = 0; j < c; ++j) {
            last += 1u + qtool_grng_u32(&r) % 9000u;
            if (last > 65535u)
                break;
            edges[ne++] = (uint16_t)last, ++m;
        }
        counts[i] = (uint8_t)m;
    }
    *n = QIBL_LIGHTPATH_HEADER + 16u * NKEYS + 4u * (LH + 1u) + LW * LH + 2u * ne;
    uint8_t *b = malloc(*n);
    if (b == NULL)
        return NULL;
    qtool_gput_u32(b, LW), qtool_gput_u32(b + 4, LH), qtool_gput_u32(b + 8, kind), qtool_gput_u32(b + 12, 0);
    qtool_gput_u32(b + 16, NKEYS), qtool_gput_u32(b + 20, ne);
    static const int32_t dirs[NKEYS][3] = {
        {65536, 0, 3000}, {46341, 20000, 46341}, {0, 26000, 65536}, {-46341, 20000, 46341}, {-65536, 0, 3000}};
    for (uint32_t i = 0; i < NKEYS; ++i) {
        uint8_t *k = b + QIBL_LIGHTPATH_HEADER + 16u * i;
        qtool_gput_u32(k, i == NKEYS - 1 ? 65535u : 16384u * i - (i == 2 ? 1000u : 0u));
        for (uint32_t c = 0; c < 3; ++c)
            qtool_gput_s32(k + 4 + 4 * c, kind == 0 ? dirs[i][c] : (int32_t)(i * 70000u) - 140000 + (int32_t)c * 9000);
    }
    uint8_t *rows = b + QIBL_LIGHTPATH_HEADER + 16u * NKEYS, *cnt = rows + 4u * (LH + 1u), *ed = cnt + LW * LH;
    uint32_t at = 0;
    for (uint32_t y = 0; y < LH; ++y) {
        qtool_gput_u32(rows + 4u * y, at);
        for (uint32_t x = 0; x < LW; ++x)
            at += counts[y * LW + x];
    }
    qtool_gput_u32(rows + 4u * LH, at);
    memcpy(cnt, counts, sizeof counts);
    for (uint32_t i = 0; i < ne; ++i)
        ed[2 * i] = (uint8_t)edges[i], ed[2 * i + 1] = (uint8_t)(edges[i] >> 8);
    return b;
}

/* integer-made maps: scale/bias from the PRNG, planes of ramps and noise */
static int make_maps(qibl_shmaps_t *m, uint8_t **params, uint8_t **planes, uint64_t seed)
{
    qtool_grng r = {seed};
    memset(m, 0, sizeof *m); /* fields this file does not name (a layout) take their defaults */
    *params = malloc(8u * LK * 3u);
    *planes = malloc((size_t)LW * LH * LK * 3u);
    if (*params == NULL || *planes == NULL)
        return -1;
    for (uint32_t i = 0; i < LK * 3u; ++i) {
        int32_t sc = (int32_t)(qtool_grng_u32(&r) % 100000u) - 30000;
        qtool_gput_s32(*params + 8u * i, sc);
        qtool_gput_s32(*params + 8u * i + 4u, -100 * sc + (int32_t)(qtool_grng_u32(&r) % 4001u) - 2000);
    }
    for (uint32_t pl = 0; pl < LK * 3u; ++pl)
        for (uint32_t i = 0; i < LW * LH; ++i)
            (*planes)[(size_t)pl * LW * LH + i] = (uint8_t)((i * (pl + 1u) + (qtool_grng_u32(&r) & 31u)) & 0xFFu);
    m->width = LW, m->height = LH, m->k = LK, m->channels = 3, m->params = *params, m->planes = *planes;
    return 0;
}

/* a parse status as a number that does not depend on where the light-path statuses sit in the
 * enum (other modules append theirs too): 0 OK, 1.. the QIBL_E_LIGHTPATH_* in order, 255 anything else */
static uint32_t status_code(qibl_status_t st)
{
    if (st == QIBL_OK)
        return 0;
    if (st >= QIBL_E_LIGHTPATH_SIZE && st <= QIBL_E_LIGHTPATH_BOUNDS)
        return 1u + (uint32_t)(st - QIBL_E_LIGHTPATH_SIZE);
    return 255;
}

static int case_vis(const qtool_goldens_sink_t *s, const qibl_lightpath_t *p, const char *name, uint32_t radius)
{
    qtool_gbuf g = {0};
    uint32_t vis[LW];
    for (uint32_t t = 0; t <= 65535u; t += 4369u)
        for (uint32_t y = 0; y < LH; ++y) {
            /* two spans per row */
            qibl_status_t st = qibl_lightpath_visibility_span(p, t, radius, 0, y, 17, vis);
            if (st == QIBL_OK)
                st = qibl_lightpath_visibility_span(p, t, radius, 17, y, LW - 17, vis + 17);
            if (st != QIBL_OK) {
                qtool_gbuf_free(&g);
                return qtool_gcase_status_error(s, name, "qibl_lightpath_visibility_span", st);
            }
            for (uint32_t x = 0; x < LW; ++x)
                qtool_gbuf_u32(&g, vis[x]);
        }
    return qtool_gbuf_emit(s, name, &g);
}

static int case_relight(const qtool_goldens_sink_t *s, const qibl_lightpath_t *p, const qibl_shmaps_t *mu,
                        const qibl_shmaps_t *msky, const char *name, qibl_fb_format_t fmt, int srgb)
{
    qibl_shlight_t sun, sky;
    qibl_shmap_weights_t wsun, wsky;
    const qibl_q16_t dir[1][3] = {{20000, 30000, 52000}}, rgb[1][3] = {{150000, 120000, 90000}};
    const qibl_q16_t up[1][3] = {{0, 0, 65536}}, skyc[1][3] = {{20000, 30000, 52000}};
    qibl_status_t st = qtool_gcase_dir_lights(&sun, LK, 1, dir, rgb);
    if (st == QIBL_OK)
        st = qtool_gcase_dir_lights(&sky, LK, 1, up, skyc);
    if (st == QIBL_OK)
        st = qibl_shmap_weights(mu, &sun, &wsun);
    if (st == QIBL_OK && msky)
        st = qibl_shmap_weights(msky, &sky, &wsky);
    if (st != QIBL_OK)
        return qtool_gcase_status_error(s, name, "weights", st);
    qibl_fb_desc_t fb = {0};
    fb.width = LW, fb.height = LH, fb.format = fmt, fb.srgb = srgb ? 1 : 0;
    size_t bytes = (size_t)LW * LH * qibl_soft_fb_bytes_per_pixel(fmt);
    fb.pixels = calloc(bytes, 1);
    if (fb.pixels == NULL)
        return qtool_gcase_oom(s, name);
    int32_t row[3 * LW], light[3 * LW], ws[3 * LW];
    for (uint32_t y = 0; y < LH && st == QIBL_OK; ++y) {
        uint32_t t = 9000u + 4000u * y, radius = y & 1u ? 700u : 0u;
        if (msky)
            st = qibl_shmap_relight_span(msky, &wsky, 0, y, LW, row, ws, sizeof ws);
        if (st == QIBL_OK)
            st = qibl_shmap_relight_span(mu, &wsun, 0, y, LW, light, ws, sizeof ws);
        if (st == QIBL_OK)
            st = qibl_lightpath_shade_span(p, t, radius, 0, y, LW, light, row, msky != NULL);
        if (st == QIBL_OK)
            st = qibl_soft_fb_write_row(&fb, 0, y, LW, row);
    }
    int bad = st == QIBL_OK ? qtool_gcase_emit(s, name, fb.pixels, bytes) : qtool_gcase_status_error(s, name, "relight", st);
    free(fb.pixels);
    return bad;
}

/* lightpath_shmt (the tiled maps of qibl/shmtile.h, kept in this group as the light paths' companion):
 * an SHMT made from the integer maps (3 tiles of 16x12 with k 9, 4, 1), a sun relit through each
 * tile's view, Q16.16 rows hashed, then the statuses of single-byte changes to the header and k bytes */
static int case_shmt(const qtool_goldens_sink_t *s, const qibl_shmaps_t *mu)
{
    enum { NT = LW / 16 };
    static const uint8_t ks[NT] = {9, 4, 1};
    size_t fixed = QIBL_SHMTILE_HEADER + 8u * LK * 3u + 4u + 4u * NT, data = 0;
    for (uint32_t i = 0; i < NT; ++i)
        data += (size_t)ks[i] * 3u * 16u * LH;
    uint8_t *b = malloc(fixed + data);
    if (b == NULL)
        return qtool_gcase_oom(s, "lightpath_shmt");
    qtool_gput_u32(b, LW), qtool_gput_u32(b + 4, LH), qtool_gput_u32(b + 8, LK), qtool_gput_u32(b + 12, 3), qtool_gput_u32(b + 16, 16);
    qtool_gput_u32(b + 20, 0);
    memcpy(b + QIBL_SHMTILE_HEADER, mu->params, 8u * LK * 3u);
    uint8_t *kp = b + QIBL_SHMTILE_HEADER + 8u * LK * 3u, *op = kp + 4, *dp = op + 4u * NT;
    memset(kp, 0, 4);
    size_t at = 0;
    for (uint32_t i = 0; i < NT; ++i) {
        kp[i] = ks[i];
        qtool_gput_u32(op + 4u * i, (uint32_t)at);
        for (uint32_t pl = 0; pl < ks[i] * 3u; ++pl)
            for (uint32_t y = 0; y < LH; ++y, at += 16u)
                memcpy(dp + at, mu->planes + (size_t)pl * LW * LH + (size_t)y * LW + 16u * i, 16u);
    }
    qtool_gbuf g = {0};
    qibl_shmtile_t t;
    qibl_shlight_t sun;
    const qibl_q16_t dir[1][3] = {{20000, 30000, 52000}}, rgb[1][3] = {{150000, 120000, 90000}};
    qibl_status_t st = qibl_shmtile_parse(b, fixed + data, &t);
    if (st == QIBL_OK)
        st = qtool_gcase_dir_lights(&sun, LK, 1, dir, rgb);
    for (uint32_t i = 0; st == QIBL_OK && i < NT; ++i) {
        qibl_shmaps_t v;
        qibl_shmap_weights_t wt;
        int32_t row[3 * 16], ws[3 * 16];
        st = qibl_shmtile_view(&t, i, 0, &v, NULL, NULL);
        if (st == QIBL_OK)
            st = qibl_shmap_weights(&v, &sun, &wt);
        for (uint32_t y = 0; st == QIBL_OK && y < LH; ++y) {
            st = qibl_shmap_relight_span(&v, &wt, 0, y, v.width, row, ws, sizeof ws);
            for (uint32_t q = 0; st == QIBL_OK && q < 3u * v.width; ++q)
                qtool_gbuf_s32(&g, row[q]);
        }
    }
    for (size_t i = 0; st == QIBL_OK && i < 24u + 4u; ++i) {
        size_t o = i < 24u ? i : (size_t)(kp - b) + (i - 24u);
        qibl_shmtile_t q;
        b[o] ^= 0x11u;
        qibl_status_t e = qibl_shmtile_parse(b, fixed + data, &q);
        qtool_gbuf_u32(&g, e == QIBL_OK ? 0u : e >= QIBL_E_ASSET_TRUNCATED_HEADER && e <= QIBL_E_ASSET_MISMATCH
                                              ? 1u + (uint32_t)(e - QIBL_E_ASSET_TRUNCATED_HEADER) : 255u);
        b[o] ^= 0x11u;
    }
    free(b);
    return st == QIBL_OK ? qtool_gbuf_emit(s, "lightpath_shmt", &g) : qtool_gcase_status_error(s, "lightpath_shmt", "shmtile", st);
}

int qtool_goldens_lightpath(const qtool_goldens_sink_t *s)
{
    int bad = 0;
    size_t n0 = 0, n1 = 0;
    uint8_t *b0 = make_path(0, 715, &n0), *b1 = make_path(1, 716, &n1);
    uint8_t *pa = NULL, *pl = NULL, *qa = NULL, *ql = NULL;
    qibl_shmaps_t mu, msky;
    qibl_lightpath_t p0, p1;
    if (b0 == NULL || b1 == NULL || make_maps(&mu, &pa, &pl, 31) != 0 || make_maps(&msky, &qa, &ql, 32) != 0) {
        bad += qtool_gcase_oom(s, "lightpath");
        goto done;
    }
    qibl_status_t st = qibl_lightpath_parse(b0, n0, &p0);
    if (st == QIBL_OK)
        st = qibl_lightpath_parse(b1, n1, &p1);
    if (st != QIBL_OK) {
        bad += qtool_gcase_status_error(s, "lightpath", "qibl_lightpath_parse", st);
        goto done;
    }
    bad += case_vis(s, &p0, "lightpath_vis_hard", 0);
    bad += case_vis(s, &p0, "lightpath_vis_soft", 1500);
    {   /* key interpolation of both kinds */
        qtool_gbuf g = {0};
        for (uint32_t t = 0; t <= 65535u; t += 257u) {
            qibl_q16_t v[3], u[3];
            if (qibl_lightpath_at(&p0, t, v) != QIBL_OK || qibl_lightpath_at(&p1, t, u) != QIBL_OK)
                break;
            for (int c = 0; c < 3; ++c)
                qtool_gbuf_s32(&g, v[c]), qtool_gbuf_s32(&g, u[c]);
        }
        bad += qtool_gbuf_emit(s, "lightpath_at", &g);
    }
    {   /* the status of damaged payloads: every single-byte change of the first 200 bytes, and truncations */
        qtool_gbuf g = {0};
        uint8_t *c = malloc(n1);
        qibl_lightpath_t q;
        if (c == NULL) {
            bad += qtool_gcase_oom(s, "lightpath_damaged");
        } else {
            for (size_t i = 0; i < 200u && i < n1; ++i) {
                memcpy(c, b1, n1);
                c[i] ^= (uint8_t)(1u << (i % 8u));
                qtool_gbuf_u32(&g, status_code(qibl_lightpath_parse(c, n1, &q)));
            }
            for (size_t m = 0; m < n1; m += 13u)
                qtool_gbuf_u32(&g, status_code(qibl_lightpath_parse(b1, m, &q)));
            free(c);
            bad += qtool_gbuf_emit(s, "lightpath_damaged", &g);
        }
    }
    bad += case_relight(s, &p0, &mu, NULL, "lightpath_sun_k9_rgba8888_srgb", QIBL_FB_RGBA8888, 1);
    bad += case_relight(s, &p0, &mu, NULL, "lightpath_sun_k9_accum32", QIBL_FB_ACCUM32, 0);
    bad += case_relight(s, &p0, &mu, &msky, "lightpath_skysun_k9_rgba8888_srgb", QIBL_FB_RGBA8888, 1);
    bad += case_relight(s, &p0, &mu, &msky, "lightpath_skysun_k9_accum32", QIBL_FB_ACCUM32, 0);
    bad += case_shmt(s, &mu);
    {   /* lamp occlusion: an integer-made LOCC (ramps, both ends present) scaling PRNG Q16.16 rows */
        qtool_gbuf g = {0};
        uint8_t occ[QIBL_LAMPOCC_HEADER + LW * LH];
        qtool_grng r = {717};
        qibl_lampocc_t o;
        qtool_gput_u32(occ, LW), qtool_gput_u32(occ + 4, LH);
        for (uint32_t i = 0; i < LW * LH; ++i)
            occ[QIBL_LAMPOCC_HEADER + i] = (uint8_t)(i % 5u == 0u ? 255u : i % 7u == 0u ? 0u : qtool_grng_u32(&r) & 0xFFu);
        st = qibl_lightpath_occl_parse(occ, sizeof occ, &o);
        for (uint32_t y = 0; st == QIBL_OK && y < LH; ++y) {
            int32_t row[3 * LW];
            for (uint32_t i = 0; i < 3u * LW; ++i)
                row[i] = (int32_t)qtool_grng_u32(&r);
            st = qibl_lightpath_occl_span(&o, 0, y, LW, row);
            for (uint32_t i = 0; st == QIBL_OK && i < 3u * LW; ++i)
                qtool_gbuf_s32(&g, row[i]);
        }
        qtool_gbuf_u32(&g, status_code(qibl_lightpath_occl_parse(occ, sizeof occ - 1u, &o)));
        bad += st != QIBL_OK ? qtool_gcase_status_error(s, "lightpath_occl", "qibl_lightpath_occl_span", st)
                             : qtool_gbuf_emit(s, "lightpath_occl", &g);
    }
done:
    free(b0), free(b1), free(pa), free(pl), free(qa), free(ql);
    return bad;
}

#else
typedef int qtool_goldens_lightpath_off; /* ISO C wants a declaration in every file */
#endif /* QIBL_USE_LIGHTPATH */
