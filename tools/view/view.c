/*
 * view/view.c - the viewer's state, input mapping, frame and overlay (view/view.h). Hosted, no
 * window system: view/x11.c shows what this draws.
 */
#include "view/view.h"
#include "io/asset_write.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "bake/path.h"
#include "io/text.h"
#include "qibl/probe.h"
#include "qibl/sh.h"
#include "qibl/soft.h"
#include "qtool.h"


int qtool_view_init(qtool_view *v, const qibl_shmaps_t *m)
{
    memset(v, 0, sizeof *v);
    if (!m || qibl_shmap_check(m) != QIBL_OK)
        return -1;
    v->maps = *m;
    v->az = 45.0, v->el = 30.0;
    v->sun_rgb[0] = v->sun_rgb[1] = v->sun_rgb[2] = 65536;
    v->exposure = 65536;
    v->k = m->k;
    v->psnr = -1.0;
    return 0;
}

void qtool_view_sun_q16(const qtool_view *v, qibl_q16_t dir[3])
{
    double a = (v->az + v->yaw) * QTOOL_PI / 180.0, e = v->el * QTOOL_PI / 180.0;
    double d[3] = {cos(e) * cos(a), cos(e) * sin(a), sin(e)};
    for (int c = 0; c < 3; ++c)
        dir[c] = (qibl_q16_t)lrint(d[c] * 65536.0);
    if (dir[0] == 0 && dir[1] == 0 && dir[2] == 0) /* cannot happen for |el| <= 89, kept non-zero anyway */
        dir[2] = 65536;
}

void qtool_view_drag(qtool_view *v, int dx, int dy, uint32_t w, uint32_t h)
{
    if (w == 0 || h == 0)
        return;
    if (v->mesh) { /* the lighting turns */
        v->yaw = fmod(v->yaw + 360.0 * dx / (double)w, 360.0);
        v->yaw += v->yaw < 0 ? 360.0 : 0;
        v->pitch += 180.0 * dy / (double)h;
        v->pitch = v->pitch > 90.0 ? 90.0 : v->pitch < -90.0 ? -90.0 : v->pitch;
        return;
    }
    v->az -= 360.0 * dx / (double)w;
    v->az = fmod(v->az, 360.0);
    if (v->az < 0)
        v->az += 360.0;
    v->el -= 180.0 * dy / (double)h;
    if (v->el > QTOOL_VIEW_EL_MAX)
        v->el = QTOOL_VIEW_EL_MAX;
    if (v->el < -QTOOL_VIEW_EL_MAX)
        v->el = -QTOOL_VIEW_EL_MAX;
}

static int key_common(qtool_view *v, int key);

/* mesh mode's keys: probe, yaw, exposure, camera azimuth */
static int mesh_key(qtool_view *v, int key)
{
    switch (key) {
    case 'p':
    case 'y':
    case 'Y':
    case '+':
    case '=':
    case '-':
        return key_common(v, key);
    case '[':
    case ']':
        v->cam_az = fmod(v->cam_az + (key == ']' ? QTOOL_VIEW_YAW_STEP : 360.0 - QTOOL_VIEW_YAW_STEP), 360.0);
        return 1;
    default:
        return 0;
    }
}

int qtool_view_key(qtool_view *v, int key)
{
    return v->mesh ? mesh_key(v, key) : key_common(v, key);
}

/* asset mode's keys (and those mesh mode shares) */
static int key_common(qtool_view *v, int key)
{
    switch (key) {
    case 's': /* the next scheme this view can show */
        for (int i = 1; i < QTOOL_VIEW_SCHEME_COUNT; ++i) {
            qtool_view_scheme s = (qtool_view_scheme)(((int)v->scheme + i) % QTOOL_VIEW_SCHEME_COUNT);
            int ok = s == QTOOL_VIEW_SUN || (s == QTOOL_VIEW_LAMP && v->have_lamp) ||
                     (s == QTOOL_VIEW_PATH && v->npaths) ||
                     (s != QTOOL_VIEW_LAMP && s != QTOOL_VIEW_PATH && v->nprobes &&
                      (s != QTOOL_VIEW_LIGHTS || v->have_lights));
            if (ok) {
                v->scheme = s;
                return 1;
            }
        }
        return 0;
    case 't':
    case 'T':
        if (!v->npaths)
            return 0;
        v->path_t = (v->path_t + (key == 't' ? QTOOL_VIEW_PATH_STEP
                                             : QIBL_LIGHTPATH_T_MAX + 1 - QTOOL_VIEW_PATH_STEP)) %
                    (QIBL_LIGHTPATH_T_MAX + 1);
        return 1;
    case 'P':
        if (v->npaths < 2)
            return 0;
        v->path_index = (v->path_index + 1) % v->npaths;
        return 1;
    case 'p':
        if (v->nprobes < 2)
            return 0;
        v->cur_probe = (v->cur_probe + 1) % v->nprobes;
        return 1;
    case 'y':
    case 'Y':
        v->yaw = fmod(v->yaw + (key == 'Y' ? QTOOL_VIEW_YAW_STEP : 360.0 - QTOOL_VIEW_YAW_STEP), 360.0);
        return 1;
    case '+':
    case '=':
        if (v->exposure > QTOOL_VIEW_EXPOSURE_MAX / 2)
            return 0;
        v->exposure *= 2;
        return 1;
    case '-':
        if (v->exposure < QTOOL_VIEW_EXPOSURE_MIN * 2)
            return 0;
        v->exposure /= 2;
        return 1;
    case 'k': { /* 25 -> 16 -> 9 -> 4 -> 1 -> all */
        uint32_t b = 1;
        while ((b + 1) * (b + 1) < v->k)
            ++b;
        v->k = v->k <= 1 ? v->maps.k : b * b;
        return 1;
    }
    case 'l':
        v->linear = !v->linear;
        return 1;
    default:
        return 0;
    }
}

/* the span workspace: the larger of the SH and the lamp kernels' */
static size_t span_ws(const qtool_view *v)
{
    size_t n = qibl_shmap_span_workspace_size(v->maps.width);
    if (v->have_lamp && qibl_shmap_point_workspace_size(v->point_maps.k, v->maps.width) > n)
        n = qibl_shmap_point_workspace_size(v->point_maps.k, v->maps.width);
    return (n + 7) & ~(size_t)7;
}

size_t qtool_view_workspace_size(const qtool_view *v)
{
    if (v->mesh) /* mesh mode holds its own buffers (view/mesh.c) */
        return 8;
    /* the path scheme's RGB8 frame after the row */
    return span_ws(v) + sizeof(int32_t) * 3 * v->maps.width +
           (v->npaths ? (size_t)v->maps.width * v->maps.height * 3 : 0);
}

void qtool_view_scrub(qtool_view *v, int dx, uint32_t w)
{
    if (w == 0)
        return;
    double t = v->path_t + (double)dx * QIBL_LIGHTPATH_T_MAX / w;
    v->path_t = t < 0 ? 0 : t > QIBL_LIGHTPATH_T_MAX ? QIBL_LIGHTPATH_T_MAX : (uint32_t)lrint(t);
}

/* the path scheme: relight --path's frame (qtool_bake_relight_path8) into BGRX */
static qibl_status_t render_path(const qtool_view *v, uint8_t *bgrx, size_t stride, uint8_t *rgb)
{
    qibl_asset_t a;
    qibl_lightpath_t p;
    qibl_q16_t q[3];
    qibl_status_t st = qtool_asset_open(&a, v->asset, v->asset_n);
    if (st == QIBL_OK)
        st = qibl_lightpath_from_asset(&a, v->path_index, &p);
    if (st == QIBL_OK)
        st = qibl_lightpath_at(&p, v->path_t, q);
    if (st != QIBL_OK)
        return st;
    qtool_rt_light l = {.point = p.kind == QIBL_LIGHTPATH_POSITIONS, .rgb = {1, 1, 1}, .falloff = 1};
    for (int c = 0; c < 3; ++c)
        (l.point ? l.pos : l.dir)[c] = q[c] / 65536.0;
    double ms;
    if (qtool_bake_relight_path8(v->asset, v->asset_n, &l, v->path_index, v->path_t, 0, NULL, rgb, NULL, &ms, &st) != 0)
        return st;
    for (uint32_t y = 0; y < v->maps.height; ++y)
        for (uint32_t x = 0; x < v->maps.width; ++x) {
            const uint8_t *i = rgb + 3 * ((size_t)y * v->maps.width + x);
            uint8_t *o = bgrx + (size_t)y * stride + 4 * (size_t)x;
            o[0] = i[2], o[1] = i[1], o[2] = i[0], o[3] = 255;
        }
    return QIBL_OK;
}

int qtool_view_pick(qtool_view *v, int x, int y)
{
    if (!v->have_lamp || x < 0 || y < 0 || (uint32_t)x >= v->pmap.width || (uint32_t)y >= v->pmap.height)
        return 0;
    qibl_q16_t p[3];
    qibl_pmap_point(&v->pmap, (uint32_t)x, (uint32_t)y, p);
    for (int c = 0; c < 3; ++c)
        if (p[c] >= QTOOL_VIEW_SKY_DIST * 65536 || p[c] <= -QTOOL_VIEW_SKY_DIST * 65536)
            return 0;
    for (int c = 0; c < 3; ++c) /* |p| < 1000 units: p - p/10 cannot overflow */
        v->lamp_pos[c] = p[c] - p[c] / 10;
    return 1;
}

qibl_status_t qtool_view_light(const qtool_view *v, qibl_shlight_t *l)
{
    qibl_status_t st = qibl_shlight_init(l, v->maps.k);
    if (st == QIBL_OK && v->scheme != QTOOL_VIEW_SUN && v->nprobes) {
        qibl_shlight_t p = v->scheme == QTOOL_VIEW_LIGHTS && v->have_lights ? v->probe_lights[v->cur_probe]
                                                                             : v->probe[v->cur_probe];
        if (v->yaw != 0.0) {
            double t = v->yaw * QTOOL_PI / 180.0, c = cos(t), s = sin(t);
            double r[3][3] = {{c, -s, 0}, {s, c, 0}, {0, 0, 1}}; /* about +z, as relight's --yaw */
            qibl_q30_t q[3][3];
            qibl_sh_rotation_t rot;
            int bands = 1;
            while ((uint32_t)(bands * bands) < p.k)
                ++bands;
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j)
                    q[i][j] = (qibl_q30_t)lrint(r[i][j] * 1073741824.0);
            st = qibl_sh_rotation_init(&rot, q, bands);
            if (st == QIBL_OK)
                st = qibl_shlight_rotate(&p, &rot);
        }
        *l = p;
    }
    if (st == QIBL_OK && (v->scheme == QTOOL_VIEW_SUN || v->scheme == QTOOL_VIEW_SUN_SH)) {
        qibl_q16_t d[3];
        qtool_view_sun_q16(v, d);
        st = qibl_shlight_add_dir(l, d, v->sun_rgb);
    }
    for (int c = 0; st == QIBL_OK && c < 3; ++c)
        for (uint32_t i = v->k; i < l->k; ++i)
            l->c[c][i] = 0;
    return st;
}

int qtool_view_render(qtool_view *v, uint8_t *bgrx, size_t stride, void *ws, qibl_status_t *status)
{
    if (v->mesh)
        return qtool_view_mesh_render(v, bgrx, stride, status);
    const uint32_t w = v->maps.width, h = v->maps.height;
    const size_t wsn = span_ws(v);
    int32_t *row = (int32_t *)(void *)((uint8_t *)ws + wsn); /* after the span workspace, aligned */
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    qibl_shlight_t l;
    qibl_shmap_weights_t wt;
    qibl_fb_desc_t fb = {.pixels = bgrx, .width = w, .height = h, .stride = stride, .format = QIBL_FB_BGRA8888,
                         .exposure = v->exposure, .srgb = (uint8_t)(v->linear ? 0 : 1)};
    if (v->scheme == QTOOL_VIEW_PATH && v->npaths) {
        qibl_status_t pst = render_path(v, bgrx, stride, (uint8_t *)(row + 3 * (size_t)w));
        clock_gettime(CLOCK_MONOTONIC, &t1);
        v->ms = (double)(t1.tv_sec - t0.tv_sec) * 1e3 + (double)(t1.tv_nsec - t0.tv_nsec) * 1e-6;
        if (status)
            *status = pst;
        return pst == QIBL_OK ? 0 : -1;
    }
    const int lamp = v->scheme == QTOOL_VIEW_LAMP && v->have_lamp;
    qibl_shmap_point_t pt;
    qibl_status_t st = QIBL_OK;
    if (lamp) { /* as relight --point: poly Y, falloff 1/d, default min_dist */
        qibl_pointlight_t pl = {.pos = {v->lamp_pos[0], v->lamp_pos[1], v->lamp_pos[2]},
                                .rgb = {v->lamp_rgb[0], v->lamp_rgb[1], v->lamp_rgb[2]},
                                .falloff = QIBL_FALLOFF_INV_DIST, .filter = QIBL_POINT_POLY};
        st = qibl_shmap_point_prepare(&v->point_maps, &v->pmap, NULL, &pl, &pt);
    } else {
        st = qtool_view_light(v, &l);
        if (st == QIBL_OK)
            st = qibl_shmap_weights(&v->maps, &l, &wt);
    }
    for (uint32_t y = 0; st == QIBL_OK && y < h; ++y) {
        if (lamp) {
            st = qibl_shmap_point_span(&pt, 0, y, w, row, ws, wsn);
            if (st == QIBL_OK && v->have_occ)
                st = qibl_lightpath_occl_span(&v->occ, 0, y, w, row);
        } else {
            st = qibl_shmap_relight_span(&v->maps, &wt, 0, y, w, row, ws, wsn);
        }
        if (st == QIBL_OK)
            st = qibl_soft_fb_write_row(&fb, 0, y, w, row);
    }
    clock_gettime(CLOCK_MONOTONIC, &t1);
    v->ms = (double)(t1.tv_sec - t0.tv_sec) * 1e3 + (double)(t1.tv_nsec - t0.tv_nsec) * 1e-6;
    if (status)
        *status = st;
    return st == QIBL_OK ? 0 : -1;
}

static const char *scheme_name(qtool_view_scheme s)
{
    return s == QTOOL_VIEW_SUN      ? "SUN"
           : s == QTOOL_VIEW_SH     ? "SH"
           : s == QTOOL_VIEW_LIGHTS ? "LIGHTS"
           : s == QTOOL_VIEW_LAMP   ? "LAMP"
           : s == QTOOL_VIEW_PATH   ? "PATH"
                                    : "SUN+SH";
}

void qtool_view_describe(const qtool_view *v, double fps, char *line1, char *line2, size_t n)
{
    if (v->mesh) {
        qtool_view_mesh_describe(v, fps, line1, line2, n);
        return;
    }
    qibl_q16_t d[3];
    qtool_view_sun_q16(v, d);
    char probe[96] = "";
    if (v->scheme != QTOOL_VIEW_SUN && v->nprobes)
        snprintf(probe, sizeof probe, " | PROBE %u/%u %.40s YAW %.0f", v->cur_probe + 1, v->nprobes,
                 v->probe_name[v->cur_probe] ? v->probe_name[v->cur_probe] : "", v->yaw);
    if (v->scheme == QTOOL_VIEW_SH || v->scheme == QTOOL_VIEW_LIGHTS)
        snprintf(line1, n, "%s%s", scheme_name(v->scheme), probe);
    else if (v->scheme == QTOOL_VIEW_PATH)
        snprintf(line1, n, "PATH %u/%u | T %.4f (T / SHIFT-T STEP, DRAG SCRUBS) | SRGB, EXPOSURE 1", v->path_index + 1,
                 v->npaths, v->path_t / (double)QIBL_LIGHTPATH_T_MAX);
    else if (v->scheme == QTOOL_VIEW_LAMP)
        snprintf(line1, n, "LAMP | AT %.3f %.3f %.3f C0 %.3g%s", v->lamp_pos[0] / 65536.0, v->lamp_pos[1] / 65536.0,
                 v->lamp_pos[2] / 65536.0, v->lamp_rgb[0] / 65536.0, v->have_occ ? " | LAMP OCCLUSION" : "");
    else
        snprintf(line1, n, "%s | DIR %.3f %.3f %.3f AZ %.1f EL %.1f%s", scheme_name(v->scheme), d[0] / 65536.0,
                 d[1] / 65536.0, d[2] / 65536.0, fmod(v->az + v->yaw, 360.0), v->el, probe);
    char ps[80] = "";
    if (v->psnr >= 0)
    {
        if (v->truth_label)
            snprintf(ps, sizeof ps, " | PSNR %.2f DB VS %.24s (%.1f DEG)", v->psnr, v->truth_label, v->truth_angle);
        else
            snprintf(ps, sizeof ps, " | PSNR %.2f DB", v->psnr);
    }
    snprintf(line2, n, "K %u | EXP %.4g %s | %.2f MS %.0f FPS%s", v->k, v->exposure / 65536.0,
             v->linear ? "LINEAR" : "SRGB",
             v->ms, fps, ps);
}

void qtool_view_overlay(const qtool_view *v, double fps, uint8_t *bgrx, uint32_t w, size_t stride)
{
    /* io/text.h draws RGB8: draw into a small RGB strip, then copy as BGRX */
    enum { MAXW = 4096 };
    static const uint8_t fg[3] = {255, 230, 120};
    uint8_t rgb[3 * MAXW * QTOOL_VIEW_LINE_H];
    char l1[160], l2[160];
    qtool_view_describe(v, fps, l1, l2, sizeof l1);
    uint32_t ww = w < MAXW ? w : MAXW;
    for (int line = 0; line < 2; ++line) {
        memset(rgb, 24, sizeof rgb);
        /* scale 2 where the window is wide enough for it, else 1 */
        const int sc = w >= 1000 ? QTOOL_VIEW_OVERLAY_SCALE : 1;
        qtool_text_draw(rgb, (int)ww, QTOOL_VIEW_LINE_H, 4, 2 + (QTOOL_VIEW_LINE_H - 4 - 7 * sc) / 2,
                        line ? l2 : l1, sc, fg);
        for (uint32_t y = 0; y < QTOOL_VIEW_LINE_H; ++y) {
            uint8_t *o = bgrx + (size_t)(2 + line * QTOOL_VIEW_LINE_H + y) * stride;
            for (uint32_t x = 0; x < w; ++x) {
                const uint8_t *p = x < ww ? rgb + 3 * ((size_t)y * ww + x) : rgb;
                o[4 * x] = p[2], o[4 * x + 1] = p[1], o[4 * x + 2] = p[0], o[4 * x + 3] = 255;
            }
        }
    }
    for (uint32_t y = 0; y < 4; ++y) { /* the border rows above and below the lines, opaque as the rest */
        uint8_t *o = bgrx + (size_t)(y < 2 ? y : QTOOL_VIEW_OVERLAY_H - 1 - (y - 2)) * stride;
        for (uint32_t x = 0; x < w; ++x)
            o[4 * x] = o[4 * x + 1] = o[4 * x + 2] = 24, o[4 * x + 3] = 255;
    }
}

double qtool_view_psnr(const uint8_t *bgrx, size_t stride, uint32_t w, uint32_t h, const uint8_t *truth)
{
    double se = 0;
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) {
                double d = (double)bgrx[(size_t)y * stride + 4 * x + (size_t)(2 - c)] -
                           (double)truth[3 * ((size_t)y * w + x) + (size_t)c];
                se += d * d;
            }
    double mse = se / (3.0 * w * h);
    return mse == 0 ? 99.0 : 10.0 * log10(255.0 * 255.0 / mse);
}
