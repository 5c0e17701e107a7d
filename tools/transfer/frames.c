/*
 * transfer/frames.c - the frames of `qibl transfer` (transfer/frames.h): meshes read, welded on the
 * first, checked to share its topology, normalised with its box and turned z up; tweened frames made
 * one at a time; each frame's integer inputs (positions Q16.16, unit normals Q2.30).
 */
#include "transfer/frames.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/mesh.h"
#include "io/obj.h"
#include "io/ply.h"
#include "qtool.h"
#include "transfer/run.h"

static int read_mesh(const char *path, qtool_obj_mesh *m, char *err, size_t errlen)
{
    const size_t n = strlen(path);
    if (n > 4 && (strcmp(path + n - 4, ".ply") == 0 || strcmp(path + n - 4, ".PLY") == 0))
        return qtool_ply_read_max(path, QTOOL_TRANSFER_MAX_TRIANGLES, m, err, errlen);
    if (qtool_mesh_is_gltf_name(path)) /* glTF: the scene's meshes in world space (io/gltf.h) */
        return qtool_mesh_read_max(path, QTOOL_TRANSFER_MAX_TRIANGLES, m, NULL, NULL, err, errlen);
    return qtool_obj_read_max(path, QTOOL_TRANSFER_MAX_TRIANGLES, m, err, errlen);
}

/* frame 0 welded: out's triangles and position storage for n frames, first/vof as qtool_transfer_weld */
static int weld_first(const char *path, const qtool_obj_mesh *m0, int n, qtool_transfer_mesh *out, uint32_t **first,
                      uint32_t **vof, char *err, size_t errlen)
{
    const size_t nc = m0->ntri * 3;
    if (m0->ntri == 0 || m0->ntri > QTOOL_TRANSFER_MAX_TRIANGLES)
        return qtool_errf(err, errlen, "%s: %zu triangles (1 .. %u supported)", path, m0->ntri,
                          QTOOL_TRANSFER_MAX_TRIANGLES);
    uint32_t nv = 0;
    *vof = malloc(sizeof **vof * nc), *first = malloc(sizeof **first * nc);
    out->tri = malloc(sizeof *out->tri * m0->ntri);
    qtool_transfer_status ws = *vof && *first && out->tri ? QTOOL_TRANSFER_OK : QTOOL_TRANSFER_E_NOMEM;
    if (ws == QTOOL_TRANSFER_OK)
        ws = qtool_transfer_weld(m0->pos, m0->ntri, out->tri, *first, *vof, &nv);
    if (ws == QTOOL_TRANSFER_OK) {
        out->nv = nv, out->nt = (uint32_t)m0->ntri, out->nframes = (uint32_t)n;
        out->pos = malloc(sizeof(double) * 3 * nv * (size_t)n);
        ws = out->pos ? QTOOL_TRANSFER_OK : QTOOL_TRANSFER_E_NOMEM;
    }
    if (ws == QTOOL_TRANSFER_OK)
        return 0;
    free(*vof), free(*first), free(out->tri), free(out->pos);
    *vof = *first = NULL;
    memset(out, 0, sizeof *out);
    return qtool_errf(err, errlen, "%s: %s", path, qtool_transfer_status_str(ws));
}

/* frame 0's box: its centre and largest half-extent */
static int frame_box(const char *path, const double *P, uint32_t nv, double ctr[3], double *scale, char *err,
                     size_t errlen)
{
    double lo[3], hi[3];
    *scale = 0;
    for (int k = 0; k < 3; ++k)
        lo[k] = hi[k] = P[k];
    for (uint32_t v = 0; v < nv; ++v)
        for (int k = 0; k < 3; ++k)
            lo[k] = fmin(lo[k], P[3 * v + k]), hi[k] = fmax(hi[k], P[3 * v + k]);
    for (int k = 0; k < 3; ++k)
        ctr[k] = (lo[k] + hi[k]) / 2, *scale = fmax(*scale, (hi[k] - lo[k]) / 2);
    if (!(*scale > 0) || !isfinite(*scale))
        return qtool_errf(err, errlen, "%s: the mesh has no extent", path);
    return 0;
}

/* Frame mf into P by the weld of frame 0: the first corner that moved apart from its vertex, or -1. */
static long gather(const qtool_obj_mesh *mf, uint32_t nv, const uint32_t *first, const uint32_t *vof, double *P)
{
    for (uint32_t v = 0; v < nv; ++v)
        memcpy(P + 3 * v, mf->pos + 3 * (size_t)first[v], 3 * sizeof(double));
    for (size_t c = 0; c < mf->ntri * 3; ++c) /* corners welded in frame 0 must coincide in every frame */
        if (mf->pos[3 * c] != P[3 * (size_t)vof[c]] || mf->pos[3 * c + 1] != P[3 * (size_t)vof[c] + 1] ||
            mf->pos[3 * c + 2] != P[3 * (size_t)vof[c] + 2]) /* ==, not memcmp: -0 and +0 weld */
            return (long)c;
    return -1;
}

int qtool_transfer_frames_load(char *const *paths, int n, int zup, qtool_transfer_mesh *out, char *err, size_t errlen)
{
    qtool_obj_mesh m0;
    memset(out, 0, sizeof *out);
    if (read_mesh(paths[0], &m0, err, errlen) != 0)
        return -1;
    uint32_t *vof = NULL, *first = NULL;
    if (weld_first(paths[0], &m0, n, out, &first, &vof, err, errlen) != 0)
        return qtool_obj_free(&m0), -1;
    const uint32_t nv = out->nv;
    double ctr[3] = {0, 0, 0}, scale = 0;
    for (int f = 0; f < n; ++f) {
        qtool_obj_mesh mf;
        if (f == 0) {
            mf = m0;
        } else if (read_mesh(paths[f], &mf, err, errlen) != 0) {
            goto fail;
        } else if (mf.ntri != m0.ntri) {
            qtool_errf(err, errlen, "%s: %zu triangles, frame 1 (%s) has %zu: frames must share triangles", paths[f],
                       mf.ntri, paths[0], m0.ntri);
            qtool_obj_free(&mf);
            goto fail;
        }
        double *P = out->pos + 3 * (size_t)nv * (size_t)f;
        const long c = gather(&mf, nv, first, vof, P);
        if (f)
            qtool_obj_free(&mf);
        if (c >= 0) {
            qtool_errf(err, errlen, "%s: corner %ld moved apart from its vertex in frame 1 (%s): frames must share "
                       "topology", paths[f], c, paths[0]);
            goto fail;
        }
        if (f == 0 && frame_box(paths[0], P, nv, ctr, &scale, err, errlen) != 0)
            goto fail;
        for (uint32_t v = 0; v < nv; ++v) {
            double q[3];
            for (int k = 0; k < 3; ++k)
                q[k] = (P[3 * v + k] - ctr[k]) / scale;
            if (!zup) /* Y-up to Z-up: (x, y, z) -> (x, -z, y), a proper rotation */
                P[3 * v] = q[0], P[3 * v + 1] = -q[2], P[3 * v + 2] = q[1];
            else
                memcpy(P + 3 * v, q, sizeof q);
        }
    }
    qtool_obj_free(&m0), free(vof), free(first);
    return 0;
fail:
    qtool_obj_free(&m0), free(vof), free(first), free(out->tri), free(out->pos);
    memset(out, 0, sizeof *out);
    return -1;
}

const double *qtool_transfer_frame_pos(const qtool_transfer_mesh *m, uint32_t nkeys, uint32_t t, uint32_t f,
                                       double *buf)
{
    const size_t n = 3 * (size_t)m->nv;
    if (t <= 1)
        return m->pos + n * f;
    const double *a = m->pos + n * (f / t), *b = m->pos + n * ((f / t + 1) % nkeys);
    const double w = (double)(f % t) / t;
    for (size_t i = 0; i < n; ++i)
        buf[i] = a[i] + w * (b[i] - a[i]);
    return buf;
}

void qtool_transfer_normals(uint32_t nv, uint32_t nt, const uint32_t (*tri)[3], const double *P, double flip,
                            double *N)
{
    memset(N, 0, sizeof(double) * 3 * nv);
    for (uint32_t t = 0; t < nt; ++t) {
        const double *a = P + 3 * tri[t][0], *b = P + 3 * tri[t][1], *c = P + 3 * tri[t][2];
        const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        const double fn[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
        for (int k = 0; k < 3; ++k)
            for (int j = 0; j < 3; ++j)
                N[3 * tri[t][k] + j] += flip * fn[j];
    }
}

uint32_t qtool_transfer_frame_ints(const qtool_transfer_mesh *m, const double *P, double flip, double *N,
                                   qibl_q16_t (*pos)[3], int32_t (*nrm)[3])
{
    qtool_transfer_normals(m->nv, m->nt, (const uint32_t(*)[3])m->tri, P, flip, N);
    uint32_t zero = 0;
    for (size_t v = 0; v < m->nv; ++v) {
        const double l = sqrt(N[3 * v] * N[3 * v] + N[3 * v + 1] * N[3 * v + 1] + N[3 * v + 2] * N[3 * v + 2]);
        for (int k = 0; k < 3; ++k) {
            pos[v][k] = (qibl_q16_t)lrint(P[3 * v + k] * 65536.0);
            nrm[v][k] = l > 0 ? (int32_t)lrint(N[3 * v + k] / l * 1073741824.0 * 0.999) : 0;
        }
        zero += l == 0;
    }
    return zero;
}
