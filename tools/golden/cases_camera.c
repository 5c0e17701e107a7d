/*
 * golden/cases_camera.c - relight_camera_*: a small fixed-camera asset (a perspective frame, not a
 * panorama: tools/golden/camera_asset.inc, fixtures/gltf/TexturedRoom.gltf baked from its own
 * camera by tools/scripts/gen-golden-camera.sh) opened by the core and relit by a sun and by a
 * lamp through its camera P map, into platform/soft's sRGB RGBA8888 framebuffer. Part of the relight
 * group (qtool_goldens_relight calls it). The asset bytes are committed, so the hashes are the
 * core's alone, the same on every port.
 */
#include "golden/casesi.h"

#include <stdio.h>
#include <stdlib.h>

#include "qibl/asset.h"
#include "qibl/shmap.h"
#include "qibl/soft.h"

#if QIBL_USE_SHMAP && QIBL_USE_ASSET

static const uint8_t camera_asset[] = {
#include "golden/camera_asset.inc"
};

enum { CW = 16, CH = 12, CK = 9 };

/* Writes rows 0..CH-1 of the frame (one light: weights w, or the prepared lamp pt) into an sRGB
 * RGBA8888 framebuffer and emits its bytes as name. Returns 1 if the case failed. */
static int emit_frame(const qtool_goldens_sink_t *s, const char *name, const qibl_shmaps_t *m,
                      const qibl_shmap_weights_t *w, const qibl_shmap_point_t *pt)
{
    uint8_t pixels[CW * CH * 4] = {0};
    int32_t row[3 * CW], ws[(CW * (2 * 25 + 32) + 3) / 4]; /* int32 storage: 4-byte aligned workspace */
    qibl_fb_desc_t fb = {.width = CW, .height = CH, .format = QIBL_FB_RGBA8888, .srgb = 1, .pixels = pixels};
    qibl_status_t st = qibl_soft_fb_check(&fb);
    for (uint32_t y = 0; y < CH && st == QIBL_OK; ++y) {
        st = w ? qibl_shmap_relight_span(m, w, 0, y, CW, row, ws, sizeof ws)
               : qibl_shmap_point_span(pt, 0, y, CW, row, ws, sizeof ws);
        if (st == QIBL_OK)
            st = qibl_soft_fb_write_row(&fb, 0, y, CW, row);
    }
    return st == QIBL_OK ? qtool_gcase_emit(s, name, pixels, sizeof pixels)
                         : qtool_gcase_status_error(s, name, "relight", st);
}

int qtool_goldens_relight_camera(const qtool_goldens_sink_t *s)
{
    qibl_asset_t a;
    qibl_shmaps_t m;
    qibl_pmap_t p;
    qibl_status_t st = qibl_asset_open(&a, camera_asset, sizeof camera_asset);
    if (st == QIBL_OK)
        st = qibl_asset_shmaps(&a, &m);
    if (st == QIBL_OK)
        st = qibl_asset_pmap(&a, &p);
    if (st == QIBL_OK && (m.width != CW || m.height != CH || m.k != CK))
        st = QIBL_E_SHMAP_MISMATCH;
    if (st != QIBL_OK)
        return qtool_gcase_status_error(s, "relight_camera_k9", "asset", st);
    int bad = 0;
    /* a sun from above the room's open side, and a cool sky light */
    qibl_shlight_t l;
    qibl_shmap_weights_t w;
    const qibl_q16_t dirs[2][3] = {{22938, -19661, 58327}, {0, 0, 65536}}; /* sun, sky */
    const qibl_q16_t rgbs[2][3] = {{170000, 157000, 137000}, {16000, 21000, 30000}};
    st = qtool_gcase_dir_lights(&l, CK, 2, dirs, rgbs);
    if (st == QIBL_OK)
        st = qibl_shmap_weights(&m, &l, &w);
    bad += st == QIBL_OK ? emit_frame(s, "relight_camera_k9_sun_rgba8888_srgb", &m, &w, NULL)
                         : qtool_gcase_status_error(s, "relight_camera_k9_sun_rgba8888_srgb", "weights", st);
    /* a lamp in front of the box: direct SH at each pixel's point of the camera's P map */
    qibl_shmap_point_t pt;
    qibl_pointlight_t pl = {{-196608, 65536, 0}, {200000, 170000, 130000}, QIBL_FALLOFF_INV_DIST, 0, QIBL_LUT_BILINEAR};
    st = qibl_shmap_point_prepare(&m, &p, NULL, &pl, &pt);
    bad += st == QIBL_OK ? emit_frame(s, "relight_camera_k9_point_rgba8888_srgb", &m, NULL, &pt)
                         : qtool_gcase_status_error(s, "relight_camera_k9_point_rgba8888_srgb", "point_prepare", st);
    return bad;
}

#else
typedef int qtool_goldens_camera_off; /* ISO C wants a declaration in every file */
#endif
