/*
 * view/gles.c - `qibl view --gles`: the viewer's frame drawn by platform/gles2 on a headless EGL
 * context opened once (gles/headless.h), the maps uploaded once, each frame's weights from the same
 * light as the soft path (qtool_view_light), read back into the window's BGRX buffer.
 */
#include "view/view.h"

#include <stdio.h>
#include <stdlib.h>

#if QIBL_HAVE_GLES2
#include "gles/headless.h"
#include "qibl/gles2.h"

struct qtool_view_gles {
    qt_gles_ctx c;
    qibl_gles2_t g;
    uint8_t *rgba;
    int have_g;
};

qtool_view_gles *qtool_view_gles_open(const qtool_view *v, char *err, size_t errlen)
{
    qtool_view_gles *vg = calloc(1, sizeof *vg);
    if (!vg)
        return snprintf(err, errlen, "view --gles: out of memory"), NULL;
    char why[256];
    if (qt_gles_open(&vg->c, v->maps.width, v->maps.height, why, sizeof why) != 0) {
        snprintf(err, errlen, "view --gles: %s", why);
        free(vg);
        return NULL;
    }
    vg->rgba = malloc((size_t)v->maps.width * v->maps.height * 4u);
    qibl_status_t st = vg->rgba ? qibl_gles2_init(&vg->g, NULL) : QIBL_E_NULL_POINTER;
    vg->have_g = st == QIBL_OK;
    if (st == QIBL_OK)
        st = qibl_gles2_upload(&vg->g, &v->maps, NULL, NULL);
    if (st != QIBL_OK) {
        snprintf(err, errlen, "view --gles: %s", vg->rgba ? qibl_gles2_status_str(st) : "out of memory");
        qtool_view_gles_close(vg);
        return NULL;
    }
    return vg;
}

int qtool_view_gles_frame(void *user, qtool_view *v, uint8_t *bgrx, size_t stride)
{
    qtool_view_gles *vg = user;
    qibl_shlight_t l;
    qibl_shmap_weights_t w;
    const qibl_gles2_out_t out = {v->exposure, (uint8_t)!v->linear};
    qibl_status_t st = qtool_view_light(v, &l);
    if (st == QIBL_OK)
        st = qibl_shmap_weights(&v->maps, &l, &w);
    if (st == QIBL_OK)
        st = qibl_gles2_relight(&vg->g, &w, &out);
    if (st != QIBL_OK) {
        fprintf(stderr, "qibl: view --gles: %s\n", qibl_gles2_status_str(st));
        return -1;
    }
    if (qt_gles_read(&vg->c, vg->rgba) != 0) {
        fprintf(stderr, "qibl: view --gles: glReadPixels failed\n");
        return -1;
    }
    for (uint32_t y = 0; y < v->maps.height; ++y)
        for (uint32_t x = 0; x < v->maps.width; ++x) {
            const uint8_t *p = vg->rgba + 4 * ((size_t)y * v->maps.width + x);
            uint8_t *o = bgrx + (size_t)y * stride + 4 * (size_t)x;
            o[0] = p[2], o[1] = p[1], o[2] = p[0], o[3] = 255;
        }
    return 0;
}

void qtool_view_gles_close(qtool_view_gles *vg)
{
    if (!vg)
        return;
    if (vg->have_g)
        qibl_gles2_destroy(&vg->g);
    free(vg->rgba);
    qt_gles_close(&vg->c);
    free(vg);
}
#else
struct qtool_view_gles {
    int unused;
};

qtool_view_gles *qtool_view_gles_open(const qtool_view *v, char *err, size_t errlen)
{
    (void)v;
    snprintf(err, errlen, "view --gles: this qibl was built without the EGL/GLES2 headers (Debian: apt-get install "
                          "libegl-dev libgles-dev libegl-mesa0 libgl1-mesa-dri)");
    return NULL;
}

int qtool_view_gles_frame(void *user, qtool_view *v, uint8_t *bgrx, size_t stride)
{
    (void)user, (void)v, (void)bgrx, (void)stride;
    return -1;
}

void qtool_view_gles_close(qtool_view_gles *g)
{
    (void)g;
}
#endif
