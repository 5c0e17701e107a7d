/*
 * transfer/sheet.c - the pictures of `qibl transfer` (transfer/sheet.h).
 *
 * The panels go through the integer rasterizer of platform/soft: positions projected in double,
 * then Q28.4 screen coordinates, a 30-bit depth and Q16.16 colours clamped to [0, 2].
 */
#include "transfer/sheet.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "io/text.h"
#include "qibl/soft.h"
#include "qtool.h"
#include "transfer/run.h"

void qtool_transfer_heat(double t, double out[3])
{
    t = fmin(fmax(t, 0), 1);
    out[0] = fmin(1, 3 * t), out[1] = fmin(1, fmax(0, 3 * t - 1)), out[2] = fmin(1, fmax(0, 3 * t - 2));
}

void qtool_transfer_view_make(double az, double el, int size, const qtool_transfer_mesh *m, qtool_transfer_view *vw)
{
    const double a = az * QTOOL_PI / 180, e = el * QTOOL_PI / 180;
    const double eye[3] = {cos(e) * cos(a), cos(e) * sin(a), sin(e)};
    for (int k = 0; k < 3; ++k)
        vw->fwd[k] = -eye[k];
    /* right = fwd x z, up = right x fwd */
    double r[3] = {vw->fwd[1], -vw->fwd[0], 0};
    const double rl = sqrt(r[0] * r[0] + r[1] * r[1]);
    if (rl < 1e-9)
        r[0] = 1, r[1] = 0;
    else
        r[0] /= rl, r[1] /= rl;
    memcpy(vw->right, r, sizeof r);
    vw->up[0] = r[1] * vw->fwd[2] - r[2] * vw->fwd[1];
    vw->up[1] = r[2] * vw->fwd[0] - r[0] * vw->fwd[2];
    vw->up[2] = r[0] * vw->fwd[1] - r[1] * vw->fwd[0];
    /* fit the projection of every frame: its box fills 92 % of the panel */
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300}, rad = 0;
    for (size_t i = 0; i < (size_t)m->nv * m->nframes; ++i) {
        const double *p = m->pos + 3 * i;
        const double x = p[0] * vw->right[0] + p[1] * vw->right[1] + p[2] * vw->right[2];
        const double y = p[0] * vw->up[0] + p[1] * vw->up[1] + p[2] * vw->up[2];
        lo[0] = fmin(lo[0], x), hi[0] = fmax(hi[0], x), lo[1] = fmin(lo[1], y), hi[1] = fmax(hi[1], y);
        rad = fmax(rad, sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]));
    }
    const double ext = fmax(hi[0] - lo[0], hi[1] - lo[1]);
    vw->scale = 0.92 * size / (ext > 0 ? ext : 1);
    vw->cx = size / 2.0 - vw->scale * (lo[0] + hi[0]) / 2;
    vw->cy = size / 2.0 + vw->scale * (lo[1] + hi[1]) / 2;
    vw->zlo = -rad, vw->zhi = rad;
}

int qtool_transfer_panel_draw(const qtool_transfer_mesh *m, const double *P, const qtool_transfer_view *vw,
                              const double *rgb, int srgb, qtool_transfer_panel *pn, uint8_t *sheet, int sw, int x0,
                              int y0, char *err, size_t errlen)
{
    const int size = pn->size;
    for (uint32_t v = 0; v < m->nv; ++v) {
        const double *p = P + 3 * v;
        const double sx = vw->cx + vw->scale * (p[0] * vw->right[0] + p[1] * vw->right[1] + p[2] * vw->right[2]);
        const double sy = vw->cy - vw->scale * (p[0] * vw->up[0] + p[1] * vw->up[1] + p[2] * vw->up[2]);
        const double d = p[0] * vw->fwd[0] + p[1] * vw->fwd[1] + p[2] * vw->fwd[2];
        pn->rv[v].x = (int32_t)lrint(sx * 16), pn->rv[v].y = (int32_t)lrint(sy * 16);
        pn->rv[v].z = (int32_t)lrint((d - vw->zlo) / (vw->zhi - vw->zlo + 1e-12) * 1073741823.0);
        for (int c = 0; c < 3; ++c)
            pn->rv[v].rgb[c] = (qibl_q16_t)lrint(fmin(fmax(rgb[3 * v + c], 0), 2.0) * 65536.0);
    }
    qibl_raster_target_t t;
    memset(&t, 0, sizeof t);
    t.fb.pixels = pn->px, t.fb.width = (uint32_t)size, t.fb.height = (uint32_t)size, t.fb.srgb = (uint8_t)srgb;
    t.depth = pn->depth, t.depth_count = (size_t)size * (size_t)size;
    qibl_status_t st = qibl_fb_clear(&t.fb);
    if (st == QIBL_OK)
        st = qibl_raster_clear_depth(&t);
    if (st == QIBL_OK)
        st = qibl_raster_triangles(&t, pn->rv, m->nv, (const uint32_t(*)[3])m->tri, m->nt);
    if (st != QIBL_OK)
        return qtool_errf(err, errlen, "raster: %s", qibl_soft_status_str(st));
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            uint8_t *o = sheet + 3 * ((size_t)(y0 + y) * (size_t)sw + (size_t)(x0 + x));
            const uint8_t *s = pn->px + 4 * ((size_t)y * (size_t)size + (size_t)x);
            if (pn->depth[(size_t)y * (size_t)size + (size_t)x] == QIBL_RASTER_DEPTH_FAR)
                o[0] = o[1] = o[2] = 40; /* background */
            else
                memcpy(o, s, 3);
        }
    return 0;
}

void qtool_transfer_label(uint8_t *sheet, int sw, int sh, int x0, int w, int y, const char *s)
{
    static const uint8_t white[3] = {235, 235, 235};
    const int scale = w >= 300 ? 2 : 1; /* the same for every panel */
    qtool_text_draw(sheet, sw, sh, x0 + (w - qtool_text_width(s, scale)) / 2, y, s, scale, white);
}

void qtool_transfer_legend(uint8_t *sheet, int sw, int sh, int x0, int S)
{
    const int y0 = QTOOL_TRANSFER_LABEL_H + S;
    /* the colour scale, a linear ramp drawn as sRGB-free bytes */
    for (int x = 0; x < S - 16; ++x) {
        double c[3];
        qtool_transfer_heat((double)x / (S - 17), c);
        for (int y = 0; y < 8; ++y) {
            uint8_t *o = sheet + 3 * ((size_t)(y0 + 2 + y) * (size_t)sw + (size_t)(x0 + 8 + x));
            for (int k = 0; k < 3; ++k)
                o[k] = (uint8_t)lrint(255 * c[k]);
        }
    }
    static const uint8_t grey[3] = {200, 200, 200};
    char scale_txt[32];
    snprintf(scale_txt, sizeof scale_txt, "%.0f%%", QTOOL_TRANSFER_ERR_SCALE * 100);
    qtool_text_draw(sheet, sw, sh, x0 + 8, y0 + 12, "0", 1, grey);
    qtool_text_draw(sheet, sw, sh, x0 + S / 2 - 6, y0 + 12, "OF MEAN", 1, grey);
    qtool_text_draw(sheet, sw, sh, x0 + S - 8 - qtool_text_width(scale_txt, 1), y0 + 12, scale_txt, 1, grey);
}
