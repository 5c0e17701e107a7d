/*
 * bake/tiled.c - per-tile adaptive k for the unshadowed maps (SHMT): bake-time choice and a relight
 * through the core kernels tile by tile.
 */
#include "bake/tiled.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bake/bake.h"
#include "io/asset_write.h"
#include "qibl/asset.h"
#include "qibl/lightpath.h"
#include "qibl/shmtile.h"
#include "qibl/soft.h"
#include "qtool.h"

enum { T = QIBL_SHMTILE_SIZE };

int qtool_bake_shmt_payload(const qtool_gen_maps *m, double drop, uint8_t **out, size_t *n, uint32_t tiles_k[26])
{
    uint32_t w = m->width, h = m->height, km = m->k, ch = 3;
    if (km < 1 || km > 25 || w < 1 || h < 1 || !(drop >= 0 && drop < 1))
        return -1;
    size_t np = (size_t)w * h, nplanes = (size_t)km * ch;
    uint32_t tx = (w + T - 1) / T, ty = (h + T - 1) / T, nt = tx * ty, kpad = (nt + 3) & ~3u;
    int32_t *scale = malloc(sizeof(int32_t) * nplanes), *bias = malloc(sizeof(int32_t) * nplanes);
    uint8_t *planes = malloc(np * nplanes), *ks = calloc(kpad, 1), *b = NULL;
    int rc = -1;
    if (!scale || !bias || !planes || !ks || qtool_pack_maps(m, QTOOL_PACK_MINMAX, scale, bias, planes, NULL) != 0)
        goto done;
    if (tiles_k)
        memset(tiles_k, 0, sizeof(uint32_t) * 26);
    size_t data = 0;
    for (uint32_t j = 0; j < ty; ++j)
        for (uint32_t i = 0; i < tx; ++i) {
            uint32_t x0 = i * T, y0 = j * T, tw = w - x0 < T ? w - x0 : T, th = h - y0 < T ? h - y0 : T;
            double band[25] = {0}, tot = 0;
            for (uint32_t q = 0; q < km; ++q)
                for (uint32_t c = 0; c < ch; ++c)
                    for (uint32_t y = y0; y < y0 + th; ++y)
                        for (uint32_t x = x0; x < x0 + tw; ++x) {
                            double v = m->t[((size_t)q * ch + c) * np + (size_t)y * w + x];
                            band[q] += v * v, tot += v * v;
                        }
            uint32_t k = km;
            for (uint32_t b2 = 1; b2 <= 5; ++b2) { /* band-complete k = 1, 4, 9, 16, 25 */
                uint32_t kk = b2 * b2;
                if (kk >= km)
                    break;
                double rest = 0;
                for (uint32_t q = kk; q < km; ++q)
                    rest += band[q];
                if (rest <= drop * tot) {
                    k = kk;
                    break;
                }
            }
            ks[j * tx + i] = (uint8_t)k;
            if (tiles_k)
                tiles_k[k]++;
            data += (size_t)k * ch * tw * th;
        }
    size_t fixed = QIBL_SHMTILE_HEADER + 8 * nplanes + kpad + 4 * (size_t)nt;
    b = malloc(fixed + data);
    if (!b)
        goto done;
    qtool_store_u32le(b, w), qtool_store_u32le(b + 4, h), qtool_store_u32le(b + 8, km), qtool_store_u32le(b + 12, ch);
    qtool_store_u32le(b + 16, T), qtool_store_u32le(b + 20, 0);
    for (size_t e = 0; e < nplanes; ++e)
        qtool_store_s32le(b + QIBL_SHMTILE_HEADER + 8 * e, scale[e]), qtool_store_s32le(b + QIBL_SHMTILE_HEADER + 8 * e + 4, bias[e]);
    uint8_t *kp = b + QIBL_SHMTILE_HEADER + 8 * nplanes, *op = kp + kpad, *dp = op + 4 * (size_t)nt;
    memcpy(kp, ks, kpad);
    size_t at = 0;
    for (uint32_t j = 0; j < ty; ++j)
        for (uint32_t i = 0; i < tx; ++i) {
            uint32_t x0 = i * T, y0 = j * T, tw = w - x0 < T ? w - x0 : T, th = h - y0 < T ? h - y0 : T;
            uint32_t k = ks[j * tx + i];
            qtool_store_u32le(op + 4 * (size_t)(j * tx + i), (uint32_t)at);
            for (uint32_t p = 0; p < k * ch; ++p)
                for (uint32_t y = y0; y < y0 + th; ++y) {
                    memcpy(dp + at, planes + (size_t)p * np + (size_t)y * w + x0, tw);
                    at += tw;
                }
        }
    *out = b, *n = fixed + data, b = NULL;
    rc = 0;
done:
    free(scale), free(bias), free(planes), free(ks), free(b);
    return rc;
}

int qtool_bake_relight_tiled8(const uint8_t *asset, size_t n, const qtool_rt_light *l, int path, uint32_t tq,
                             uint32_t radius, uint8_t *rgb8, double *ms, qibl_status_t *status)
{
    qibl_asset_t a;
    qibl_shmtile_t t;
    qibl_pmap_t pm;
    qibl_ylut_t lut;
    qibl_lightpath_t lp;
    qibl_lampocc_t occ;
    int use_lut = 0, use_occ = 0;
    qibl_status_t st = qtool_asset_open(&a, asset, n);
    if (st == QIBL_OK)
        st = qibl_shmtile_from_asset(&a, &t);
    if (st == QIBL_OK && path >= 0)
        st = qibl_lightpath_from_asset(&a, (uint32_t)path, &lp);
    if (st == QIBL_OK && l->point) {
        st = qibl_asset_pmap(&a, &pm);
        use_lut = qibl_asset_ylut(&a, &lut) == QIBL_OK && lut.k >= t.kmax;
        use_occ = path < 0 && qibl_lightpath_occl_from_asset(&a, &occ) == QIBL_OK;
    }
    uint32_t w = st == QIBL_OK ? t.width : 0, h = st == QIBL_OK ? t.height : 0;
    size_t wsn = st == QIBL_OK ? qibl_shmap_point_workspace_size(t.kmax, T) : 0, wsd = qibl_shmap_span_workspace_size(T);
    wsn = wsd > wsn ? wsd : wsn;
    qtool_bake_frame f; /* rows: a band of tiles; scratch: one tile's P-map points */
    if (qtool_bake_frame_alloc(st, w, h, T, T * T * 12, wsn, &f, status) != 0)
        return -1;
    uint8_t *pix = f.pix, *ptile = f.scratch;
    int32_t *row = f.row;
    void *ws = f.ws;
    qibl_fb_desc_t fb = qtool_bake_fb_srgb(pix, w, h);
    double t0 = qtool_bake_now();
    /* directional: one light, weights per distinct tile k made on first use */
    qibl_shlight_t sl;
    qibl_shmap_weights_t wk[26];
    uint8_t have[26] = {0};
    if (!l->point)
        st = qtool_bake_dir_shlight(l, t.kmax, &sl);
    qibl_pointlight_t pl = qtool_bake_pointlight(l, QIBL_LUT_BILINEAR);
    for (uint32_t ty = 0; st == QIBL_OK && ty < t.tiles_y; ++ty) {
        uint32_t th = 0;
        for (uint32_t tx = 0; st == QIBL_OK && tx < t.tiles_x; ++tx) {
            qibl_shmaps_t v;
            uint32_t x0, y0;
            st = qibl_shmtile_view(&t, tx, ty, &v, &x0, &y0);
            if (st != QIBL_OK)
                break;
            th = v.height;
            if (!l->point) {
                if (!have[v.k])
                    st = qibl_shmap_weights(&v, &sl, &wk[v.k]), have[v.k] = 1;
                for (uint32_t y = 0; st == QIBL_OK && y < v.height; ++y)
                    st = qibl_shmap_relight_span(&v, &wk[v.k], 0, y, v.width, row + 3 * ((size_t)y * w + x0), ws, wsn);
            } else {
                /* the tile's P-map points as a view of its own size */
                for (uint32_t y = 0; y < v.height; ++y)
                    memcpy(ptile + (size_t)y * v.width * 12, pm.points + ((size_t)(y0 + y) * w + x0) * 12,
                           (size_t)v.width * 12);
                qibl_pmap_t pv = {v.width, v.height, ptile};
                qibl_shmap_point_t pt;
                st = qibl_shmap_point_prepare(&v, &pv, use_lut ? &lut : NULL, &pl, &pt);
                for (uint32_t y = 0; st == QIBL_OK && y < v.height; ++y)
                    st = qibl_shmap_point_span(&pt, 0, y, v.width, row + 3 * ((size_t)y * w + x0), ws, wsn);
            }
        }
        for (uint32_t y = 0; st == QIBL_OK && y < th; ++y) {
            int32_t *r = row + 3 * (size_t)y * w;
            uint32_t yy = ty * T + y;
            if (path >= 0)
                st = qibl_lightpath_shade_span(&lp, tq, radius, 0, yy, w, r, r, false);
            else if (use_occ)
                st = qibl_lightpath_occl_span(&occ, 0, yy, w, r);
            if (st == QIBL_OK)
                st = qibl_soft_fb_write_row(&fb, 0, yy, w, r);
        }
    }
    return qtool_bake_frame_finish(&f, st, t0, ms, w, h, rgb8, status);
}
