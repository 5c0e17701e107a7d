/*
 * relight/gles.c - `qibl relight --gles` (gles.h): the same light through platform/gles2 on a
 * headless EGL context, so both paths can be compared by eye or by bytes.
 */
#include "relight/gles.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#if QIBL_HAVE_GLES2
#include "gles/headless.h"
#include "qibl/gles2.h"

int qtool_gles_relight(const qtool_gles_relight_req *r, uint8_t *rgb, uint32_t *passes, char *renderer)
{
    const qibl_shmaps_t *m = r->maps;
    qt_gles_ctx c;
    char why[256];
    if (qt_gles_open(&c, m->width, m->height, why, sizeof why) != 0) {
        fprintf(stderr, "qibl: relight --gles: %s\n", why);
        return 1;
    }
    snprintf(renderer, 64, "%.63s", c.renderer);
    uint8_t *rgba = malloc((size_t)m->width * m->height * 4u);
    qibl_gles2_t g;
    qibl_status_t st = rgba ? qibl_gles2_init(&g, NULL) : QIBL_E_NULL_POINTER;
    if (st == QIBL_OK)
        st = qibl_gles2_upload(&g, m, r->pmap, r->lut);
    const qibl_gles2_out_t out = {r->exposure, (uint8_t)!r->linear};
    if (st == QIBL_OK && r->pmap == NULL) {
        qibl_shlight_t l;
        qibl_shmap_weights_t w;
        st = qibl_shlight_init(&l, m->k);
        if (st == QIBL_OK)
            st = qibl_shlight_add_dir(&l, r->sun, r->rgb);
        if (st == QIBL_OK)
            st = qibl_shmap_weights(m, &l, &w);
        if (st == QIBL_OK)
            st = qibl_gles2_relight(&g, &w, &out);
    } else if (st == QIBL_OK) {
        qibl_pointlight_t pl = {{r->pos[0], r->pos[1], r->pos[2]}, {r->rgb[0], r->rgb[1], r->rgb[2]},
                                r->falloff == 2 ? QIBL_FALLOFF_INV_DIST2 : QIBL_FALLOFF_INV_DIST, 0,
                                r->nearest ? QIBL_LUT_NEAREST : QIBL_LUT_BILINEAR};
        qibl_shmap_point_t pt;
        st = qibl_shmap_point_prepare(m, r->pmap, r->lut, &pl, &pt);
        if (st == QIBL_OK)
            st = r->gonio ? qibl_gles2_point_gonio(&g, &pt, r->gonio, &out) : qibl_gles2_point(&g, &pt, &out);
    }
    int rc = 0;
    if (st != QIBL_OK) {
        const char *log = rgba ? qibl_gles2_log(&g) : "";
        fprintf(stderr, "qibl: relight --gles: %s%s%s\n", rgba ? qibl_gles2_status_str(st) : "out of memory",
                log[0] ? ": " : "", log);
        rc = 1;
    } else if (qt_gles_read(&c, rgba) != 0) {
        fprintf(stderr, "qibl: relight --gles: glReadPixels failed\n");
        rc = 1;
    } else {
        for (size_t i = 0; i < (size_t)m->width * m->height; ++i)
            memcpy(rgb + 3u * i, rgba + 4u * i, 3);
        *passes = qibl_gles2_passes(&g);
    }
    if (rgba)
        qibl_gles2_destroy(&g);
    free(rgba);
    qt_gles_close(&c);
    return rc;
}
#else
int qtool_gles_relight(const qtool_gles_relight_req *r, uint8_t *rgb, uint32_t *passes, char *renderer)
{
    (void)r, (void)rgb, (void)passes, (void)renderer;
    fprintf(stderr, "qibl: relight --gles: this qibl was built without the EGL/GLES2 headers "
                    "(Debian: apt-get install libegl-dev libgles-dev libegl-mesa0 libgl1-mesa-dri)\n");
    return 1;
}
#endif
