/*
 * view/mesh.c - mesh mode of `qibl view` (view/view.h): a static mesh's hemi transfer, computed once
 * (tools/transfer, as `qibl transfer` computes it) or read from a `qibl transfer --export` file,
 * shaded each frame by the core under a probe's SH turned live, drawn by platform/soft's
 * rasterizer from an orbit camera.
 *
 * Invariants: the frame always goes through qibl_hemi_xfer_open's view of export bytes (computed
 * transfers are exported in memory first), so a file and a computation draw alike; the frame is a
 * function of (mesh, transfer, probe, yaw, pitch, cam_az, cam_el, exposure) alone, which the
 * viewer's log line prints exactly (`--png` reproduces it without a window).
 */
#include "view/view.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "qibl/hemi.h"
#include "qibl/raster.h"
#include "qibl/sh.h"
#include "qibl/soft.h"
#include "qtool.h"
#include "transfer/export.h"
#include "transfer/frames.h"
#include "transfer/job.h"
#include "transfer/run.h"

struct qtool_view_mesh {
    qtool_transfer_mesh m;                           /* frame 0: welded, normalised, z up */
    uint8_t *xbytes;                                 /* the export's bytes (qibl_hemi_xfer_t views them) */
    qibl_hemi_xfer_t x;
    int32_t light[QTOOL_VIEW_MAX_PROBES][3][25];     /* each probe's SH, as qibl transfer's */
    double rad;                                      /* the largest |position| */
    qibl_raster_vertex_t *rv;
    qibl_q16_t (*shade)[3];
    uint32_t *depth;
    char name[64];                                   /* the mesh file's name, for the overlay */
};

int qtool_view_is_mesh(const char *path)
{
    static const char *const ext[] = {".obj", ".ply", ".gltf", ".glb"};
    const size_t n = strlen(path);
    for (size_t i = 0; i < sizeof ext / sizeof ext[0]; ++i) {
        const size_t e = strlen(ext[i]);
        if (n > e && strcmp(path + n - e, ext[i]) == 0)
            return 1;
    }
    return 0;
}

void qtool_view_close_mesh(qtool_view *v)
{
    struct qtool_view_mesh *M = v->mesh;
    if (!M)
        return;
    free(M->m.tri), free(M->m.pos), free(M->xbytes), free(M->rv), free(M->shade), free(M->depth);
    free(M);
    v->mesh = NULL;
}

void qtool_view_mesh_counts(const qtool_view *v, uint32_t *nv, uint32_t *nt, uint32_t *ncoef)
{
    *nv = v->mesh ? v->mesh->m.nv : 0, *nt = v->mesh ? v->mesh->m.nt : 0, *ncoef = v->mesh ? v->mesh->x.ncoef : 0;
}

/* the transfer's export bytes: read from o->transfer, or computed by tools/transfer and exported */
static int transfer_bytes(const qtool_view_mesh_opts *o, struct qtool_view_mesh *M, size_t *n, char *err, size_t errlen)
{
    if (o->transfer)
        return qtool_transfer_export_read(o->transfer, &M->xbytes, n, err, errlen);
    char *files[1] = {(char *)(uintptr_t)o->mesh};
    qtool_transfer_opts to = QTOOL_TRANSFER_OPTS_DEFAULT;
    to.files = files, to.nfiles = 1, to.probe = o->probes[0], to.zup = o->zup, to.rays = 0;
    to.threads = o->threads > 0 ? o->threads : 1, to.keep_transfer = 1;
    qtool_transfer_result r;
    if (qtool_transfer_measure(&to, &r, err, errlen) != 0)
        return -1;
    int rc = qtool_transfer_export_bytes((const qibl_q30_t(*)[QIBL_HEMI_COEFFS])r.transfer, r.nv, 5, &M->xbytes, n, err,
                                         errlen);
    qtool_transfer_result_free(&r);
    return rc;
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* the first frame's exposure: its 99th percentile of irradiance at 0.6 (as qibl transfer's sheet),
 * clamped to the viewer's range */
static int auto_exposure(qtool_view *v, char *err, size_t errlen)
{
    struct qtool_view_mesh *M = v->mesh;
    int32_t l[3][25];
    qibl_status_t st = qtool_view_mesh_light(v, l);
    if (st == QIBL_OK)
        st = qibl_hemi_xfer_shade_span(&M->x, (const int32_t(*)[QIBL_HEMI_COEFFS])l, 0, M->x.count, M->shade);
    if (st != QIBL_OK)
        return qtool_errf(err, errlen, "view: shade: %s", qibl_status_str(st));
    double *lum = malloc(sizeof *lum * M->x.count);
    if (!lum)
        return qtool_errf(err, errlen, "view: out of memory");
    for (uint32_t i = 0; i < M->x.count; ++i)
        lum[i] = (0.2126 * M->shade[i][0] + 0.7152 * M->shade[i][1] + 0.0722 * M->shade[i][2]) / 65536.0;
    qsort(lum, M->x.count, sizeof *lum, cmp_double);
    const double p99 = lum[(size_t)(0.99 * (double)(M->x.count - 1))];
    free(lum);
    double e = p99 > 0 ? 0.6 / p99 * 65536.0 : 65536.0;
    e = e < QTOOL_VIEW_EXPOSURE_MIN ? QTOOL_VIEW_EXPOSURE_MIN : e > QTOOL_VIEW_EXPOSURE_MAX ? QTOOL_VIEW_EXPOSURE_MAX : e;
    v->exposure = (uint32_t)lrint(e);
    return 0;
}

int qtool_view_open_mesh(qtool_view *v, const qtool_view_mesh_opts *o, char *note, size_t notelen, char *err,
                         size_t errlen)
{
    memset(v, 0, sizeof *v);
    if (notelen)
        note[0] = '\0';
    if (!o->mesh || o->nprobes < 1 || o->nprobes > QTOOL_VIEW_MAX_PROBES)
        return qtool_errf(err, errlen, "view: a mesh needs 1..%u --probe", QTOOL_VIEW_MAX_PROBES);
    if (o->size < QTOOL_VIEW_MESH_SIZE_MIN || o->size > QTOOL_VIEW_MESH_SIZE_MAX)
        return qtool_errf(err, errlen, "view: --size %u outside %u..%u", o->size, QTOOL_VIEW_MESH_SIZE_MIN,
                          QTOOL_VIEW_MESH_SIZE_MAX);
    struct qtool_view_mesh *M = calloc(1, sizeof *M);
    if (!M)
        return qtool_errf(err, errlen, "view: out of memory");
    v->mesh = M;
    char *files[1] = {(char *)(uintptr_t)o->mesh};
    size_t xn = 0;
    if (qtool_transfer_frames_load(files, 1, o->zup, &M->m, err, errlen) != 0 ||
        transfer_bytes(o, M, &xn, err, errlen) != 0)
        goto fail;
    qibl_status_t st = qibl_hemi_xfer_open(&M->x, M->xbytes, xn);
    if (st != QIBL_OK) {
        qtool_errf(err, errlen, "%s: %s", o->transfer ? o->transfer : "view: the transfer", qibl_status_str(st));
        goto fail;
    }
    if (M->x.count != M->m.nv) {
        qtool_errf(err, errlen, "%s holds %u vertices, %s has %u (not its export, or another --zup)", o->transfer,
                   M->x.count, o->mesh, M->m.nv);
        goto fail;
    }
    for (uint32_t j = 0; j < o->nprobes; ++j) {
        char desc[160];
        if (qtool_transfer_probe_light(o->probes[j], QTOOL_PROBE_LAYOUT_AUTO, 0, M->light[j], desc, sizeof desc, err,
                                       errlen) != 0)
            goto fail;
        const char *slash = strrchr(o->probes[j], '/');
        v->probe_name[j] = slash ? slash + 1 : o->probes[j];
    }
    const size_t nv = M->m.nv, np = (size_t)o->size * o->size;
    M->rv = malloc(sizeof *M->rv * nv), M->shade = malloc(sizeof *M->shade * nv);
    M->depth = malloc(sizeof *M->depth * np);
    if (!M->rv || !M->shade || !M->depth) {
        qtool_errf(err, errlen, "view: out of memory");
        goto fail;
    }
    for (size_t i = 0; i < nv; ++i) {
        const double *p = M->m.pos + 3 * i;
        M->rad = fmax(M->rad, sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]));
    }
    const char *slash = strrchr(o->mesh, '/');
    snprintf(M->name, sizeof M->name, "%s", slash ? slash + 1 : o->mesh);
    v->maps.width = v->maps.height = o->size; /* the frame's size: the window takes it from here */
    v->nprobes = o->nprobes, v->scheme = QTOOL_VIEW_SH, v->k = M->x.ncoef;
    v->yaw = o->yaw, v->pitch = o->pitch, v->cam_az = o->cam_az, v->cam_el = o->cam_el;
    v->psnr = -1.0;
    v->exposure = (uint32_t)lrint(o->exposure * 65536.0);
    if (o->exposure == 0 && auto_exposure(v, err, errlen) != 0)
        goto fail;
    return 0;
fail:
    qtool_view_close_mesh(v);
    return -1;
}

/* Q2.30 of a rotation entry */
static qibl_q30_t q30(double x)
{
    return (qibl_q30_t)lrint(x * 1073741824.0);
}

qibl_status_t qtool_view_mesh_light(const qtool_view *v, int32_t light[3][25])
{
    const struct qtool_view_mesh *M = v->mesh;
    if (!M)
        return QIBL_E_NULL_POINTER;
    const double a = v->yaw * QTOOL_PI / 180.0, b = v->pitch * QTOOL_PI / 180.0;
    const double ca = cos(a), sa = sin(a), cb = cos(b), sb = sin(b);
    /* Rz(yaw) Rx(pitch): tilt about +x, then turn about +z */
    const double r[3][3] = {{ca, -sa * cb, sa * sb}, {sa, ca * cb, -ca * sb}, {0, sb, cb}};
    qibl_q30_t q[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            q[i][j] = q30(r[i][j]);
    qibl_sh_rotation_t rot;
    qibl_status_t st = qibl_sh_rotation_init(&rot, (const qibl_q30_t(*)[3])q, 5);
    for (int c = 0; st == QIBL_OK && c < 3; ++c)
        st = qibl_sh_rotate(&rot, M->light[v->cur_probe][c], light[c]);
    return st;
}

void qtool_view_orbit(qtool_view *v, int dx, int dy, uint32_t w, uint32_t h)
{
    if (w == 0 || h == 0)
        return;
    v->cam_az = fmod(v->cam_az - 360.0 * dx / (double)w, 360.0);
    if (v->cam_az < 0)
        v->cam_az += 360.0;
    v->cam_el += 180.0 * dy / (double)h;
    v->cam_el = v->cam_el > QTOOL_VIEW_CAM_EL_MAX    ? QTOOL_VIEW_CAM_EL_MAX
                : v->cam_el < -QTOOL_VIEW_CAM_EL_MAX ? -QTOOL_VIEW_CAM_EL_MAX
                                                     : v->cam_el;
}

/* the vertices on screen: an orthographic camera at cam_az, cam_el looking at the origin (z up, as
 * qibl transfer's --view), the mesh's bounding sphere filling 92 % of the frame whatever the angle,
 * depth in 30 bits over the sphere */
static void project(const qtool_view *v, uint32_t size)
{
    struct qtool_view_mesh *M = v->mesh;
    const double a = v->cam_az * QTOOL_PI / 180, e = v->cam_el * QTOOL_PI / 180;
    const double fwd[3] = {-cos(e) * cos(a), -cos(e) * sin(a), -sin(e)};
    double right[3] = {fwd[1], -fwd[0], 0};
    const double rl = sqrt(right[0] * right[0] + right[1] * right[1]);
    right[0] /= rl, right[1] /= rl; /* |cam_el| <= 89: never vertical */
    const double up[3] = {right[1] * fwd[2] - right[2] * fwd[1], right[2] * fwd[0] - right[0] * fwd[2],
                          right[0] * fwd[1] - right[1] * fwd[0]};
    const double rad = M->rad > 0 ? M->rad : 1, scale = 0.92 * size / (2 * rad), c = size / 2.0;
    for (uint32_t i = 0; i < M->m.nv; ++i) {
        const double *p = M->m.pos + 3 * (size_t)i;
        const double sx = c + scale * (p[0] * right[0] + p[1] * right[1] + p[2] * right[2]);
        const double sy = c - scale * (p[0] * up[0] + p[1] * up[1] + p[2] * up[2]);
        const double d = p[0] * fwd[0] + p[1] * fwd[1] + p[2] * fwd[2];
        M->rv[i].x = (int32_t)lrint(sx * 16), M->rv[i].y = (int32_t)lrint(sy * 16);
        M->rv[i].z = (int32_t)lrint((d + rad) / (2 * rad) * 1073741823.0);
        for (int ch = 0; ch < 3; ++ch)
            M->rv[i].rgb[ch] = M->shade[i][ch];
    }
}

int qtool_view_mesh_render(qtool_view *v, uint8_t *bgrx, size_t stride, qibl_status_t *status)
{
    struct qtool_view_mesh *M = v->mesh;
    const uint32_t size = v->maps.width;
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    int32_t l[3][25];
    qibl_status_t st = qtool_view_mesh_light(v, l);
    if (st == QIBL_OK)
        st = qibl_hemi_xfer_shade_span(&M->x, (const int32_t(*)[QIBL_HEMI_COEFFS])l, 0, M->x.count, M->shade);
    qibl_raster_target_t t = {.fb = {.pixels = bgrx, .width = size, .height = size, .stride = stride,
                                     .format = QIBL_FB_BGRA8888, .exposure = v->exposure, .srgb = 1},
                              .depth = M->depth, .depth_count = (size_t)size * size, .cull = QIBL_RASTER_CULL_NONE};
    if (st == QIBL_OK) {
        project(v, size);
        st = qibl_soft_fb_clear(&t.fb);
    }
    if (st == QIBL_OK)
        st = qibl_soft_raster_clear_depth(&t);
    if (st == QIBL_OK)
        st = qibl_soft_raster_triangles(&t, M->rv, M->m.nv, (const uint32_t(*)[3])M->m.tri, M->m.nt);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    v->ms = (double)(t1.tv_sec - t0.tv_sec) * 1e3 + (double)(t1.tv_nsec - t0.tv_nsec) * 1e-6;
    if (status)
        *status = st;
    return st == QIBL_OK ? 0 : -1;
}

void qtool_view_mesh_describe(const qtool_view *v, double fps, char *line1, char *line2, size_t n)
{
    snprintf(line1, n, "MESH %.32s | PROBE %u/%u %.32s | LIGHT YAW %.1f PITCH %.1f | CAMERA %.1f %.1f", v->mesh->name,
             v->cur_probe + 1, v->nprobes, v->probe_name[v->cur_probe] ? v->probe_name[v->cur_probe] : "", v->yaw,
             v->pitch, v->cam_az, v->cam_el);
    snprintf(line2, n, "%u VERTICES X %u SH | EXP %.4g SRGB | %.2f MS %.0f FPS", v->mesh->x.count, v->mesh->x.ncoef,
             v->exposure / 65536.0, v->ms, fps);
}
