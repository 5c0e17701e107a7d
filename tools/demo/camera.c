/*
 * demo/camera.c - the fixed-camera part of `qibl demo`: the demo's scene seen from a corner by a
 * perspective camera (a pre-rendered background), baked as shadowed SH (k = 16) and as unshadowed
 * k = 9 maps x a sun path's visibility, relit by the core at positions between the baked steps and
 * scored against the ray-traced render of the same camera.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/bake.h"
#include "bake/path.h"
#include "demo/demo.h"
#include "qtool.h"
#include "ref/psnr.h"
#include "render/rt.h"

enum { NPOS = 8 };

/* The corner camera: the courtyard's, as tests/camera_test.c frames it; a mesh prop's, the same
 * corner offset toward the prop at QTOOL_RT_PROP_X. 0 or -1 (err). */
static int corner_camera(const qtool_demo_view *v, qtool_rt_camera *c, char *err, size_t errlen)
{
    double eye[3] = {3.5, -3.5, 0.5}, target[3] = {-2.5, 1.5, -1.0};
    const double up[3] = {0, 0, 1};
    if (v->prop)
        eye[0] = QTOOL_RT_PROP_X + 3.5, target[0] = QTOOL_RT_PROP_X, target[1] = 0, target[2] = -0.6;
    return qtool_rt_camera_init(c, eye, target, up, 70, err, errlen);
}

int qtool_demo_camera(const qtool_demo_view *v, uint32_t ndirs, const qtool_demo_size *sz, char *err, size_t errlen)
{
    /* a quarter of the panorama's width, 4:3: the camera frame costs less than the main bake */
    const uint32_t w = v->w / 4 > 4 ? v->w / 4 : 4, h = w * 3 / 4;
    const size_t np = (size_t)w * h;
    qtool_rt_scene cs = *v->scene; /* the same geometry, seen through the camera (nothing owned) */
    if (corner_camera(v, &cs.cam, err, errlen) != 0)
        return -1;
    cs.has_cam = 1;
    qtool_bake_sums sh, us;
    qtool_gen_maps m16, mu9;
    memset(&sh, 0, sizeof sh), memset(&us, 0, sizeof us), memset(&m16, 0, sizeof m16), memset(&mu9, 0, sizeof mu9);
    qtool_bake_path p;
    memset(&p, 0, sizeof p);
    p.rgb[0] = p.rgb[1] = p.rgb[2] = 1;
    uint8_t *paths[2] = {NULL, NULL}, *asset = NULL, *truth = malloc(np * 3), *relit = malloc(np * 3),
            *today = malloc(np * 3), *mask = malloc(np), *sheet = malloc(np * 3 * 3);
    size_t sizes[2] = {0, 0}, n = 0;
    double se_path = 0, se_sh = 0, t0 = qtool_demo_now();
    int rc = -1;
    if (!truth || !relit || !today || !mask || !sheet) {
        qtool_errf(err, errlen, "camera: out of memory");
        goto out;
    }
    if (qtool_bake_path_parse_sun("40,15,7,17", &p, err, errlen) != 0)
        goto out;
    if (qtool_bake_run(&cs, w, h, QTOOL_PANO_CYLINDRICAL, ndirs, 16, 0, 1, v->threads, 0, &sh) != 0 ||
        qtool_bake_coeffs(&sh, 16, QTOOL_PROJ_QUADRATURE, &m16) != 0 ||
        qtool_bake_run_unshadowed(&cs, w, h, QTOOL_PANO_CYLINDRICAL, ndirs, 9, v->threads, &us) != 0 ||
        qtool_bake_coeffs(&us, 9, QTOOL_PROJ_QUADRATURE, &mu9) != 0 ||
        qtool_bake_path_chunk(&cs, w, h, QTOOL_PANO_CYLINDRICAL, &p, sz->path_steps, 65, v->threads, &paths[0],
                              &sizes[0], NULL) != 0 ||
        qtool_bake_asset_full(&m16, &mu9, 0, QIBL_SHMAPS_PLANAR, paths, sizes, &asset, &n) != 0) {
        qtool_errf(err, errlen, "camera: the %ux%u bake failed (out of memory)", w, h);
        goto out;
    }
    double bake_s = qtool_demo_now() - t0, npx = 0;
    for (int i = 0; i < NPOS; ++i) {
        /* between the baked steps: the half-way points of NPOS equal parts of the day */
        const double t = (i + 0.5) / NPOS;
        qtool_rt_light l;
        qtool_bake_path_light(&p, t, &l);
        qibl_status_t st;
        if (qtool_bake_truth8(&cs, w, h, QTOOL_PANO_CYLINDRICAL, &l, v->threads, truth, mask) != 0 ||
            qtool_bake_relight_path8(asset, n, &l, 0, (uint32_t)(t * 65535 + 0.5), 0, NULL, relit, NULL, NULL,
                                     &st) != 0 ||
            qtool_bake_relight8(asset, n, &l, 0, today, NULL) != 0) {
            qtool_errf(err, errlen, "camera: relighting the %ux%u frame failed", w, h);
            goto out;
        }
        double mp = qtool_bake_mse(relit, truth, mask, np), ms = qtool_bake_mse(today, truth, mask, np);
        se_path += mp, se_sh += ms, npx += 1;
        if (i == NPOS / 2) { /* the sheet: relit (path) | truth | error, stacked */
            qtool_demo_blit(sheet, w, 0, 0, relit, w, h);
            qtool_demo_blit(sheet, w, 0, h, truth, w, h);
            qtool_demo_heat(relit, truth, mask, np, sheet + 2 * np * 3);
        }
    }
    double psnr_path = qtool_ref_psnr8(se_path / npx), psnr_sh = qtool_ref_psnr8(se_sh / npx);
    FILE *o = v->out;
    fprintf(o, "\n== fixed camera: the scene from a corner, %ux%u perspective frame (70 degrees), %u directions, "
               "bake %.1f s\n", w, h, ndirs, bake_s);
    fprintf(o, "PSNR against the ray-traced render of the same camera, mean MSE over %d sun positions between the "
               "baked steps of the path 40,15,7,17\n\n", NPOS);
    fprintf(o, "| camera row | PSNR dB |\n|---|---:|\n");
    fprintf(o, "| sun: shadowed SH k16 | %.2f |\n| sun: unshadowed k9 x path visibility | %.2f |\n", psnr_sh,
            psnr_path);
    fprintf(o, "RESULT demo.camera_psnr_sh_k16 %.2f\nRESULT demo.camera_psnr_path_k9 %.2f\n", psnr_sh, psnr_path);
    rc = qtool_demo_save_png(v->dir, "camera_sheet.png", (int)w, (int)h * 3, sheet, err, errlen);
out:
    free(paths[0]), free(asset), free(truth), free(relit), free(today), free(mask), free(sheet);
    qtool_gen_free(&m16), qtool_gen_free(&mu9);
    qtool_bake_sums_free(&sh), qtool_bake_sums_free(&us);
    return rc;
}
