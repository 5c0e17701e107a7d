/*
 * cmd_transfer.c - `qibl transfer MESH... --probe PROBE.hdr --png OUT`: a mesh self-shadowed by
 * hemispherical rasterization (qibl/hemi.h) under a real probe's SH, drawn by the integer z-buffer
 * rasterizer of platform/soft (qibl/raster.h), beside the ray-cast reference and the error.
 *
 * Per frame: every vertex's transfer vector from ALL triangles of the mesh (no hierarchy: the
 * figure is the method's error, not the culling's), turned to world space, shaded with the probe's
 * radiance SH (bands 0..4, qibl_hemi_shade: irradiance, shown with an automatic exposure). The
 * reference ray-casts the same positions (tools/ref/hemi_ref.c, stratified cosine-weighted rays) and
 * shades with the same
 * coefficients in double, so the error is visibility and integration only. Several MESH files are
 * frames of one animation (same triangles in the same order, e.g. sydney_run_01..06.obj): an APNG.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli/cli.h"
#include "io/hdr.h"
#include "io/mesh.h"
#include "io/obj.h"
#include "io/ply.h"
#include "io/png.h"
#include "io/probe_layout.h"
#include "io/text.h"
#include "qibl/hemi.h"
#include "qibl/lightprobe.h"
#include "qibl/probe.h"
#include "qibl/raster.h"
#include "qibl/soft.h"
#include "gen/simplify.h"
#include "transfer/transfer.h"
#include "ref/hemi_ref.h"
#include "render/rt.h"

#define PI 3.14159265358979323846
#define MAX_FRAMES 64
#define LABEL_H 24  /* title bar, pixels */
#define LEGEND_H 22 /* colour-scale bar under the error panel */
#define ERR_SCALE 0.10 /* the error panel's full scale: 10 % of the mean shading */
/* what a run may hold for its frames: the --png sheet of every frame (the APNG writer takes them
 * all at once) and --pvs's integer positions of every frame; refused up front beyond it */
#define QCLI_TRANSFER_MAX_HELD ((uint64_t)256 << 20)

#define TRANSFER_USAGE                                                                                        \
    "usage: qibl transfer MESH [MESH...] --probe PROBE.hdr [--layout L] [--png OUT] [--size N] [--mask 16|32|64]\n" \
    "                     [--face F] [--rays S] [--coarse T [--ring K]] [--pvs] [--lights N] [--tween N] [--zup] [--flip] [--skip-adjacent] [--view AZ,EL] [--threads N]"

/* the mesh: positions nframes * nv * 3, normalised, z up */
typedef qtool_transfer_mesh mesh;
typedef qtool_transfer_hier hier;

static double thread_cpu(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static int read_mesh(const char *path, qtool_obj_mesh *m, char *err, size_t errlen)
{
    const size_t n = strlen(path);
    if (n > 4 && (strcmp(path + n - 4, ".ply") == 0 || strcmp(path + n - 4, ".PLY") == 0))
        return qtool_ply_read_max(path, QTOOL_TRANSFER_MAX_TRIANGLES, m, err, errlen);
    if (qtool_mesh_is_gltf_name(path)) /* glTF: the scene's meshes in world space (io/gltf.h) */
        return qtool_mesh_read_max(path, QTOOL_TRANSFER_MAX_TRIANGLES, m, NULL, NULL, err, errlen);
    return qtool_obj_read_max(path, QTOOL_TRANSFER_MAX_TRIANGLES, m, err, errlen);
}

/* Loads every frame, welds on frame 0, checks the others share its topology, normalises all frames
 * with frame 0's box (centre, largest half-extent 1) and turns Y-up to Z-up unless zup. */
static int load_frames(char **paths, int n, int zup, mesh *out)
{
    char err[512];
    qtool_obj_mesh m0;
    memset(out, 0, sizeof *out);
    if (read_mesh(paths[0], &m0, err, sizeof err) != 0)
        return fprintf(stderr, "qibl: transfer: %s\n", err), -1;
    const size_t nc = m0.ntri * 3;
    if (m0.ntri == 0 || m0.ntri > QTOOL_TRANSFER_MAX_TRIANGLES) {
        qtool_obj_free(&m0);
        return fprintf(stderr, "qibl: transfer: %s: %zu triangles (1 .. %u supported)\n", paths[0], m0.ntri,
                       QTOOL_TRANSFER_MAX_TRIANGLES), -1;
    }
    uint32_t *vof = malloc(sizeof *vof * nc), *first = malloc(sizeof *first * nc), nv = 0;
    out->tri = malloc(sizeof *out->tri * m0.ntri);
    qtool_transfer_status ws = vof && first && out->tri ? QTOOL_TRANSFER_OK : QTOOL_TRANSFER_E_NOMEM;
    if (ws == QTOOL_TRANSFER_OK)
        ws = qtool_transfer_weld(m0.pos, m0.ntri, out->tri, first, vof, &nv);
    if (ws == QTOOL_TRANSFER_OK) {
        out->nv = nv, out->nt = (uint32_t)m0.ntri, out->nframes = (uint32_t)n;
        out->pos = malloc(sizeof(double) * 3 * nv * (size_t)n);
        ws = out->pos ? QTOOL_TRANSFER_OK : QTOOL_TRANSFER_E_NOMEM;
    }
    if (ws != QTOOL_TRANSFER_OK) {
        free(vof), free(first), free(out->tri), free(out->pos), qtool_obj_free(&m0);
        memset(out, 0, sizeof *out);
        return fprintf(stderr, "qibl: transfer: %s: %s\n", paths[0], qtool_transfer_status_str(ws)), -1;
    }
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0}, ctr[3] = {0, 0, 0}, scale = 0;
    for (int f = 0; f < n; ++f) {
        qtool_obj_mesh mf;
        if (f == 0) {
            mf = m0;
        } else if (read_mesh(paths[f], &mf, err, sizeof err) != 0) {
            fprintf(stderr, "qibl: transfer: %s\n", err);
            goto fail;
        } else if (mf.ntri != m0.ntri) {
            fprintf(stderr, "qibl: transfer: %s: %zu triangles, frame 1 (%s) has %zu: frames must share triangles\n",
                    paths[f], mf.ntri, paths[0], m0.ntri);
            qtool_obj_free(&mf);
            goto fail;
        }
        double *P = out->pos + 3 * (size_t)nv * (size_t)f;
        for (uint32_t v = 0; v < nv; ++v)
            memcpy(P + 3 * v, mf.pos + 3 * (size_t)first[v], 3 * sizeof(double));
        for (size_t c = 0; c < nc; ++c) /* corners welded in frame 0 must coincide in every frame */
            if (mf.pos[3 * c] != P[3 * (size_t)vof[c]] || mf.pos[3 * c + 1] != P[3 * (size_t)vof[c] + 1] ||
                mf.pos[3 * c + 2] != P[3 * (size_t)vof[c] + 2]) { /* ==, not memcmp: -0 and +0 weld */
                fprintf(stderr, "qibl: transfer: %s: corner %zu moved apart from its vertex in frame 1 (%s): frames "
                        "must share topology\n", paths[f], c, paths[0]);
                if (f)
                    qtool_obj_free(&mf);
                goto fail;
            }
        if (f)
            qtool_obj_free(&mf);
        if (f == 0) {
            for (int k = 0; k < 3; ++k)
                lo[k] = hi[k] = P[k];
            for (uint32_t v = 0; v < nv; ++v)
                for (int k = 0; k < 3; ++k)
                    lo[k] = fmin(lo[k], P[3 * v + k]), hi[k] = fmax(hi[k], P[3 * v + k]);
            for (int k = 0; k < 3; ++k)
                ctr[k] = (lo[k] + hi[k]) / 2, scale = fmax(scale, (hi[k] - lo[k]) / 2);
            if (!(scale > 0) || !isfinite(scale)) {
                fprintf(stderr, "qibl: transfer: %s: the mesh has no extent\n", paths[0]);
                goto fail;
            }
        }
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

/* Frame f's positions: with t > 1, t - 1 frames between each pair of the nkeys key frames, linear
 * per vertex, the last blending back into the first (an animation cycle, like the paper's
 * interpolated keyframes), made one at a time into buf (3 nv doubles): only the key frames are
 * held, so --tween costs one frame of memory, not t times the animation. */
static const double *frame_pos(const mesh *m, uint32_t nkeys, uint32_t t, uint32_t f, double *buf)
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

/* area-weighted vertex normals of one frame; flip < 0 turns them (a mesh wound clockwise) */
static void normals(const mesh *m, const double *P, double flip, double *N)
{
    memset(N, 0, sizeof(double) * 3 * m->nv);
    for (uint32_t t = 0; t < m->nt; ++t) {
        const double *a = P + 3 * m->tri[t][0], *b = P + 3 * m->tri[t][1], *c = P + 3 * m->tri[t][2];
        const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        const double fn[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
        for (int k = 0; k < 3; ++k)
            for (int j = 0; j < 3; ++j)
                N[3 * m->tri[t][k] + j] += flip * fn[j];
    }
}

/* One frame's integer inputs: positions Q16.16, unit normals Q2.30 (zero where a vertex has none);
 * returns how many vertices have no normal. N: 3 nv doubles of scratch. */
static int frame_ints(const mesh *m, const double *P, double flip, double *N, qibl_q16_t (*pos)[3], int32_t (*nrm)[3])
{
    normals(m, P, flip, N);
    int zero = 0;
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

/* ---- per-vertex work, threaded --------------------------------------------------------------- */

typedef struct job {
    const mesh *m;
    const qibl_hemi_t *h;
    const qtool_rt_scene *rt;
    const qibl_q16_t (*pos)[3];
    const int32_t (*nrm)[3];
    const int32_t (*light)[25];
    int side;
    qibl_q30_t (*vw)[25];   /* world transfer */
    double *eq;             /* qibl shading, 3 per vertex */
    double *er;             /* reference shading */
    double *l2, *noise;     /* per vertex */
    double *cpu;            /* per vertex hemi CPU seconds */
    double *ph;             /* per vertex PH_N: the split of cpu, reference CPU, blockers, rasterized */
    const uint32_t *adj_off, *adj; /* triangles around each vertex (CSR) */
    int crease;             /* the solid behind the faces around each vertex blocks */
    const hier *hi;         /* with a hierarchy: each vertex's vertices and blockers (NULL: every triangle) */
    const hier *pvs;        /* with --pvs: the same vertex again from its PVS, timed, masks compared */
} job;

/* the per-vertex figures of job.ph */
enum { PH_TRANSFORM, PH_RASTER, PH_INTEGRATE, PH_OTHER, PH_REF, PH_BLOCKERS, PH_RASTERIZED, PH_PVS_CPU, PH_PVS_BLOCKERS,
       PH_PVS_DIFF, PH_N };

/* The hemi work of one vertex from hierarchy-style lists (its vertices, its blockers in local
 * indices, local index n the nadir of the crease wedges): the mask and the phase times. */
static qibl_status_t mask_from_lists(const job *j, const hier *L, const qibl_hemi_frame_t *fr, uint32_t v,
                                     int32_t (*loc)[3], qibl_q16_t (*gp)[3], uint32_t *mask, qibl_hemi_stats_t *hs,
                                     double *t_transform)
{
    const double t0 = thread_cpu();
    const size_t n = L->voff[v + 1] - L->voff[v];
    for (size_t k = 0; k < n; ++k)
        memcpy(gp[k], j->pos[L->vl[L->voff[v] + k]], sizeof gp[k]);
    qibl_status_t st = qibl_hemi_transform(fr, (const qibl_q16_t(*)[3])gp, (uint32_t)n, loc);
    *t_transform = thread_cpu() - t0;
    loc[n][0] = 0, loc[n][1] = 0, loc[n][2] = -(1 << 20); /* the nadir of the crease wedges */
    if (st == QIBL_OK)
        st = qibl_hemi_clear(j->h, mask);
    if (st == QIBL_OK)
        st = qibl_hemi_raster(j->h, (const int32_t(*)[3])loc, (uint32_t)n + 1, L->blk + L->boff[v],
                              (uint32_t)(L->boff[v + 1] - L->boff[v]), mask, hs);
    return st;
}

static void vertex_job(void *ctx, uint32_t v)
{
    job *j = ctx;
    const mesh *m = j->m;
    int32_t(*loc)[3] = malloc(sizeof *loc * (m->nv + 1)); /* + the nadir */
    qibl_q16_t(*gp)[3] = j->hi || j->pvs ? malloc(sizeof *gp * m->nv) : NULL;
    uint32_t mask[QIBL_HEMI_MAX_WORDS];
    qibl_q30_t vl[25];
    qibl_hemi_frame_t fr;
    if (!loc || ((j->hi || j->pvs) && !gp) || qibl_hemi_frame_init(&fr, j->pos[v], j->nrm[v]) != QIBL_OK) {
        memset(j->vw[v], 0, sizeof j->vw[v]);
        for (int c = 0; c < 3; ++c)
            j->eq[3 * v + c] = j->er[3 * v + c] = 0;
        j->l2[v] = j->noise[v] = j->cpu[v] = 0;
        memset(j->ph + PH_N * v, 0, sizeof(double) * PH_N);
        free(loc), free(gp);
        return;
    }
    qibl_status_t st = QIBL_OK;
    qibl_hemi_stats_t hs = {0, 0, 0};
    uint32_t nblk = 0;
    const double t0 = thread_cpu();
    double t1 = t0;
    if (j->hi) { /* the hierarchy: only this vertex's vertices, blockers in their local indices */
        double tt = 0;
        st = mask_from_lists(j, j->hi, &fr, v, loc, gp, mask, &hs, &tt);
        t1 = t0 + tt;
        nblk = (uint32_t)(j->hi->boff[v + 1] - j->hi->boff[v]);
    } else {
        st = qibl_hemi_transform(&fr, j->pos, m->nv, loc);
        t1 = thread_cpu();
        nblk = m->nt;
        if (st == QIBL_OK)
            st = qibl_hemi_clear(j->h, mask);
        if (st == QIBL_OK)
            st = qibl_hemi_raster(j->h, (const int32_t(*)[3])loc, m->nv, (const uint32_t(*)[3])m->tri, m->nt, mask,
                                  &hs);
    }
    /* The faces around the receiver: the rasterizer skips them (their planes pass through it), yet
     * the surface hides what lies behind them: at a crease (a box's floor meeting its walls) the
     * averaged normal's hemisphere reaches behind a face. The solid's side of the fan of faces is
     * the union of the wedges (nadir, b, c) of each face (v, b, c), the nadir -n being inside;
     * at a convex vertex every wedge lies below the horizon and blocks nothing. No winding needed.
     * (The hierarchy's lists carry these wedges already.) */
    if (j->crease && !j->hi && st == QIBL_OK) {
        uint32_t fan[64][3], nf = 0;
        loc[m->nv][0] = 0, loc[m->nv][1] = 0, loc[m->nv][2] = -(1 << 20); /* 4 units straight down */
        for (uint32_t k = j->adj_off[v]; st == QIBL_OK && k < j->adj_off[v + 1]; ++k) {
            const uint32_t *t = m->tri[j->adj[k]];
            const int r = t[0] == v ? 0 : t[1] == v ? 1 : 2;
            fan[nf][0] = m->nv, fan[nf][1] = t[(r + 1) % 3], fan[nf][2] = t[(r + 2) % 3];
            if (++nf == 64 || k + 1 == j->adj_off[v + 1]) {
                nblk += nf;
                st = qibl_hemi_raster(j->h, (const int32_t(*)[3])loc, m->nv + 1, (const uint32_t(*)[3])fan, nf,
                                      mask, &hs);
                nf = 0;
            }
        }
    }
    const double t2 = thread_cpu();
    if (st == QIBL_OK)
        st = qibl_hemi_transfer(j->h, mask, vl);
    const double t3 = thread_cpu();
    if (st == QIBL_OK)
        st = qibl_hemi_to_world(j->h, &fr, vl, j->vw[v]);
    qibl_q16_t e[3] = {0, 0, 0};
    if (st == QIBL_OK)
        st = qibl_hemi_shade(j->light, j->vw[v], e);
    j->cpu[v] = thread_cpu() - t0;
    double *ph = j->ph + PH_N * v;
    ph[PH_TRANSFORM] = t1 - t0, ph[PH_RASTER] = t2 - t1, ph[PH_INTEGRATE] = t3 - t2, ph[PH_OTHER] = j->cpu[v] - (t3 - t0);
    ph[PH_BLOCKERS] = nblk, ph[PH_RASTERIZED] = hs.rasterized, ph[PH_REF] = 0;
    ph[PH_PVS_CPU] = ph[PH_PVS_BLOCKERS] = ph[PH_PVS_DIFF] = 0;
    if (j->pvs && st == QIBL_OK) { /* the same vertex from its PVS: same work after the mask */
        uint32_t pm[QIBL_HEMI_MAX_WORDS];
        qibl_q30_t pl[25], pw[25];
        qibl_q16_t pe[3];
        qibl_hemi_stats_t ps = {0, 0, 0};
        double tt = 0;
        const double p0 = thread_cpu();
        qibl_status_t s2 = mask_from_lists(j, j->pvs, &fr, v, loc, gp, pm, &ps, &tt);
        if (s2 == QIBL_OK)
            s2 = qibl_hemi_transfer(j->h, pm, pl);
        if (s2 == QIBL_OK)
            s2 = qibl_hemi_to_world(j->h, &fr, pl, pw);
        if (s2 == QIBL_OK)
            s2 = qibl_hemi_shade(j->light, pw, pe);
        ph[PH_PVS_CPU] = thread_cpu() - p0;
        ph[PH_PVS_BLOCKERS] = (double)(j->pvs->boff[v + 1] - j->pvs->boff[v]);
        ph[PH_PVS_DIFF] = s2 != QIBL_OK || memcmp(pm, mask, sizeof(uint32_t) * j->h->words) != 0;
    }
    free(loc), free(gp);
    if (st != QIBL_OK) /* cannot happen for validated inputs; shown black rather than dropped */
        memset(j->vw[v], 0, sizeof j->vw[v]), e[0] = e[1] = e[2] = 0;
    for (int c = 0; c < 3; ++c)
        j->eq[3 * v + c] = e[c] / 65536.0;
    j->l2[v] = j->noise[v] = 0;
    if (!j->rt)
        return;
    double ax[3][3], p[3], ref[25];
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k)
            ax[i][k] = fr.axis[i][k] / 1073741824.0;
    for (int k = 0; k < 3; ++k)
        p[k] = j->pos[v][k] / 65536.0;
    const double tr = thread_cpu();
    qtool_hemi_ref(j->rt, p, ax, j->side, 1, 0x5EED0000u + v * 0x9E3779B97F4A7C15u, ref, &j->noise[v]);
    ph[PH_REF] = thread_cpu() - tr;
    double d2 = 0, n2 = 0;
    for (int i = 0; i < 25; ++i) {
        const double d = j->vw[v][i] / 1073741824.0 - ref[i];
        d2 += d * d, n2 += ref[i] * ref[i];
    }
    j->l2[v] = n2 > 0 ? sqrt(d2 / n2) : 0;
    for (int c = 0; c < 3; ++c) {
        double s = 0;
        for (int i = 0; i < 25; ++i)
            s += j->light[c][i] / 65536.0 * ref[i];
        j->er[3 * v + c] = s;
    }
}

/* ---- pictures ------------------------------------------------------------------------------- */

static double lum(const double *c)
{
    return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* heat ramp, linear: black -> red -> yellow -> white */
static void heat(double t, double out[3])
{
    t = fmin(fmax(t, 0), 1);
    out[0] = fmin(1, 3 * t), out[1] = fmin(1, fmax(0, 3 * t - 1)), out[2] = fmin(1, fmax(0, 3 * t - 2));
}

typedef struct view {
    double right[3], up[3], fwd[3];
    double scale, cx, cy, zlo, zhi;
} view;

static void view_make(double az, double el, int size, const mesh *m, view *vw)
{
    const double a = az * PI / 180, e = el * PI / 180;
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

/* Draws one panel: per-vertex linear colours rgb (3 per vertex), into a size x size RGB8 block of
 * the sheet at column x0, row y0. Integer path: platform/soft's z-buffer rasterizer. */
static int draw_panel(const mesh *m, const double *P, const view *vw, const double *rgb, int srgb, int size,
                      uint8_t *sheet, int sw, int x0, int y0, qibl_raster_vertex_t *rv, uint8_t *fbpx, uint32_t *depth)
{
    for (uint32_t v = 0; v < m->nv; ++v) {
        const double *p = P + 3 * v;
        const double sx = vw->cx + vw->scale * (p[0] * vw->right[0] + p[1] * vw->right[1] + p[2] * vw->right[2]);
        const double sy = vw->cy - vw->scale * (p[0] * vw->up[0] + p[1] * vw->up[1] + p[2] * vw->up[2]);
        const double d = p[0] * vw->fwd[0] + p[1] * vw->fwd[1] + p[2] * vw->fwd[2];
        rv[v].x = (int32_t)lrint(sx * 16), rv[v].y = (int32_t)lrint(sy * 16);
        rv[v].z = (int32_t)lrint((d - vw->zlo) / (vw->zhi - vw->zlo + 1e-12) * 1073741823.0);
        for (int c = 0; c < 3; ++c)
            rv[v].rgb[c] = (qibl_q16_t)lrint(fmin(fmax(rgb[3 * v + c], 0), 2.0) * 65536.0);
    }
    qibl_raster_target_t t;
    memset(&t, 0, sizeof t);
    t.fb.pixels = fbpx, t.fb.width = (uint32_t)size, t.fb.height = (uint32_t)size, t.fb.srgb = (uint8_t)srgb;
    t.depth = depth, t.depth_count = (size_t)size * (size_t)size;
    qibl_status_t st = qibl_fb_clear(&t.fb);
    if (st == QIBL_OK)
        st = qibl_raster_clear_depth(&t);
    if (st == QIBL_OK)
        st = qibl_raster_triangles(&t, rv, m->nv, (const uint32_t(*)[3])m->tri, m->nt);
    if (st != QIBL_OK)
        return fprintf(stderr, "qibl: transfer: raster: %s\n", qibl_soft_status_str(st)), -1;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            uint8_t *o = sheet + 3 * ((size_t)(y0 + y) * (size_t)sw + (size_t)(x0 + x));
            const uint8_t *s = fbpx + 4 * ((size_t)y * (size_t)size + (size_t)x);
            if (depth[(size_t)y * (size_t)size + (size_t)x] == QIBL_RASTER_DEPTH_FAR)
                o[0] = o[1] = o[2] = 40; /* background */
            else
                memcpy(o, s, 3);
        }
    return 0;
}

static void label(uint8_t *sheet, int sw, int sh, int x0, int w, int y, const char *s)
{
    static const uint8_t white[3] = {235, 235, 235};
    const int scale = w >= 300 ? 2 : 1; /* the same for every panel */
    qtool_text_draw(sheet, sw, sh, x0 + (w - qtool_text_width(s, scale)) / 2, y, s, scale, white);
}

/* ---- the command ---------------------------------------------------------------------------- */

static int parse_view(const char *s, double *az, double *el)
{
    char *end;
    *az = strtod(s, &end);
    if (end == s || *end != ',' || !isfinite(*az))
        return -1;
    const char *t = end + 1;
    *el = strtod(t, &end);
    return end == t || *end || !isfinite(*el) || fabs(*el) > 89.9 ? -1 : 0;
}

/* A light list from median cut, projected to SH (qibl_shlight_add_lights), the same Q16.16 radiance
 * SH as the probe's own projection; 0 or -1 */
static int lights_light(const uint8_t *ll, int ow, int oh, long nlights, int32_t light[3][25])
{
    const size_t n = qibl_lightprobe_workspace_size((uint32_t)ow, (uint32_t)oh, QIBL_LIGHTPROBE_MEDIANCUT);
    void *ws = n ? malloc(n) : NULL;
    qibl_lightprobe_light_t *lt = malloc(sizeof *lt * (size_t)nlights);
    int rc = -1;
    if (ws && lt) {
        const qibl_lightprobe_image_t img = {ll, (uint32_t)ow, (uint32_t)oh, 0, QIBL_LIGHTPROBE_RGBE, 0};
        qibl_lightprobe_t lp;
        qibl_lightprobe_result_t res;
        qibl_shlight_t sl;
        qibl_status_t st = qibl_lightprobe_build(&lp, &img, QIBL_LIGHTPROBE_MEDIANCUT, ws, n);
        if (st == QIBL_OK)
            st = qibl_lightprobe_lights(&lp, NULL, lt, (uint32_t)nlights, &res);
        if (st == QIBL_OK)
            st = qibl_shlight_init(&sl, 25);
        /* the brightest channel's rgb is in [2^30, 2^31): 2^-16 of it per light keeps the sum of up
         * to 1024 lights within Q16.16 */
        if (st == QIBL_OK)
            st = qibl_shlight_add_lights(&sl, lt, res.count, res.rgb_exp, -16 - res.rgb_exp);
        if (st == QIBL_OK) {
            /* the probe path's scale: the largest |coefficient| in [1/4, 1/2) (the image's exposure
             * is automatic; this keeps the shading sums as far from int32 as the probe's) */
            int32_t mx = 0;
            for (int ch = 0; ch < 3; ++ch)
                for (int i = 0; i < 25; ++i)
                    mx = abs(sl.c[ch][i]) > mx ? abs(sl.c[ch][i]) : mx;
            int sh = 0;
            while (mx > 0 && (mx >> sh) >= (1 << 15))
                ++sh;
            for (int ch = 0; ch < 3; ++ch)
                for (int i = 0; i < 25; ++i)
                    light[ch][i] = sl.c[ch][i] / (1 << sh);
            rc = 0;
        } else {
            fprintf(stderr, "qibl: transfer: --lights %ld: %s\n", nlights, qibl_status_str(st));
        }
    } else {
        fprintf(stderr, "qibl: transfer: --lights: out of memory\n");
    }
    free(ws), free(lt);
    return rc;
}

/* probe -> radiance SH (bands 0..4) as Q16.16, scaled so the largest |coefficient| is 1/2; with
 * nlights > 0, the probe's median-cut lights projected to SH instead */
static int probe_light(const char *path, const char *layout, long nlights, int32_t light[3][25], char *desc,
                       size_t dlen)
{
    char err[512];
    int w, h, ow, oh;
    uint8_t *px, *ll;
    qtool_probe_layout_t want = QTOOL_PROBE_LAYOUT_AUTO, used;
    if (layout && qtool_probe_layout_parse(layout, &want) != 0)
        return qcli_usage_error("--layout: unknown layout '%s'", layout), -1;
    if (qtool_hdr_read_rgbe(path, &w, &h, &px, err, sizeof err) != 0)
        return fprintf(stderr, "qibl: transfer: %s\n", err), -1;
    int rc = qtool_probe_layout_rgbe_to_latlong(want, w, h, px, &used, &ow, &oh, &ll, err, sizeof err);
    free(px);
    if (rc != 0)
        return fprintf(stderr, "qibl: transfer: %s\n", err), -1;
    int32_t ml[3][25];
    if (nlights > 0 && lights_light(ll, ow, oh, nlights, ml) != 0)
        return free(ll), -1;
    const size_t n = qibl_probe_sh_workspace_size((uint32_t)ow, (uint32_t)oh);
    void *ws = n ? malloc(n) : NULL;
    if (!ws) {
        free(ll);
        return fprintf(stderr, "qibl: transfer: %s: %dx%d is beyond the probe limits or out of memory\n", path, ow,
                       oh), -1;
    }
    qibl_probe_sh_t ps;
    qibl_probe_coeffs_t c;
    qibl_status_t st = qibl_probe_sh_begin(&ps, (uint32_t)ow, (uint32_t)oh, QIBL_LIGHTPROBE_RGBE, 0, 5, ws, n);
    for (int v = 0; v < oh && st == QIBL_OK; ++v)
        st = qibl_probe_sh_add_row(&ps, (uint32_t)v, ll + 4 * (size_t)ow * (size_t)v);
    if (st == QIBL_OK)
        st = qibl_probe_sh_finish(&ps, NULL, &c);
    free(ws), free(ll);
    if (st != QIBL_OK)
        return fprintf(stderr, "qibl: transfer: %s: %s\n", path, qibl_status_str(st)), -1;
    /* the largest |c| is in [2^30, 2^31): shift to [2^15, 2^16) / 2, i.e. 0.25 .. 0.5 in Q16.16 */
    for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i < 25; ++i)
            light[ch][i] = c.c[ch][i] / (1 << 16); /* truncation toward zero: 2^-16 relative */
    snprintf(desc, dlen, "%dx%d %s", ow, oh, qtool_probe_layout_name(used));
    if (nlights > 0) { /* the lights replace the projection; how far apart, each scaled by its own DC */
        double d2 = 0, n2 = 0;
        for (int ch = 0; ch < 3 && ml[1][0] != 0 && light[1][0] != 0; ++ch)
            for (int i = 0; i < 25; ++i) {
                const double a = (double)ml[ch][i] / ml[1][0], b = (double)light[ch][i] / light[1][0];
                d2 += (a - b) * (a - b), n2 += b * b;
            }
        for (int ch = 0; ch < 3; ++ch)
            for (int i = 0; i < 25; ++i)
                light[ch][i] = ml[ch][i];
        snprintf(desc, dlen, "%dx%d %s, %ld median-cut lights as SH: relative L2 %.4f from its own projection", ow, oh,
                 qtool_probe_layout_name(used), nlights, n2 > 0 ? sqrt(d2 / n2) : 0.0);
    }
    return 0;
}

typedef struct topts {
    char **files;
    int nfiles, zup, force_flip, skip_adjacent, pvs;
    const char *probe, *png, *layout;
    long size, mask_n, face, side, threads, coarse, ring, tween;
    double az, el;
    long lights; /* > 0: the probe's median-cut lights projected to SH light the mesh */
} topts;

/* The whole run; verbose prints the report (the command), otherwise only errors (the bench). */
static int transfer_run(const topts *o, qcli_transfer_stats *stats, int verbose)
{
    char **files = o->files;
    const int nfiles = o->nfiles, zup = o->zup, force_flip = o->force_flip, skip_adjacent = o->skip_adjacent;
    const int use_pvs = o->pvs;
    const char *probe = o->probe, *png = o->png, *layout = o->layout;
    const long size = o->size, mask_n = o->mask_n, face = o->face, side = o->side, coarse = o->coarse,
               ring = o->ring, tween = o->tween;
    long threads = o->threads;
    const double az = o->az, el = o->el;
    memset(stats, 0, sizeof *stats);
    if (threads == 0) {
        qcli_scene sd;
        qcli_scene_defaults(&sd);
        threads = sd.threads;
    }
    if (png) { /* the sheet of every frame, from the request alone, before anything is read */
        const uint64_t frames = nfiles > 1 ? (uint64_t)nfiles * (uint64_t)tween : 1, panels = side > 0 ? 3 : 1;
        const uint64_t fw = panels * (uint64_t)size, fh = LABEL_H + (uint64_t)size + (panels == 3 ? LEGEND_H : 0);
        if (frames * fw * fh * 3 > QCLI_TRANSFER_MAX_HELD) {
            fprintf(stderr, "qibl: transfer: --png of %llu frames of %llux%llu is %.0f MiB of frames held for the "
                    "APNG (at most %d MiB): fewer frames or --tween, a smaller --size, or --rays 0 (one panel)\n",
                    (unsigned long long)frames, (unsigned long long)fw, (unsigned long long)fh,
                    (double)(frames * fw * fh * 3) / 1048576.0, (int)(QCLI_TRANSFER_MAX_HELD >> 20));
            return 1;
        }
    }
    int32_t light[3][25];
    char pdesc[128];
    if (probe_light(probe, layout, o->lights, light, pdesc, sizeof pdesc) != 0)
        return 1;
    mesh m;
    if (load_frames(files, nfiles, zup, &m) != 0)
        return 1;
    /* from here m.nframes counts every frame drawn; the key frames alone are held (frame_pos) */
    const uint32_t nkeys = m.nframes, tw = tween > 1 && nkeys > 1 ? (uint32_t)tween : 1;
    m.nframes = nkeys * tw;
    if (use_pvs && (uint64_t)m.nv * m.nframes * (sizeof(qibl_q16_t[3]) + sizeof(int32_t[3])) > QCLI_TRANSFER_MAX_HELD) {
        fprintf(stderr, "qibl: transfer: --pvs over %u frames of %u vertices needs %.0f MiB of integer positions and "
                "normals (at most %d MiB): fewer frames or --tween\n", m.nframes, m.nv,
                (double)m.nv * m.nframes * 24 / 1048576.0, (int)(QCLI_TRANSFER_MAX_HELD >> 20));
        free(m.tri), free(m.pos);
        return 1;
    }
    /* winding: turned by --flip, or when a (nearly) closed mesh has a negative volume */
    long nedges = 0, open_edges = qtool_transfer_boundary_edges(&m, &nedges);
    const double vol = qtool_transfer_signed_volume(&m, m.pos);
    const int closed = open_edges >= 0 && open_edges * 50 <= nedges;
    const double flip = force_flip || (closed && vol < 0) ? -1 : 1;

    const size_t wsz = qibl_hemi_workspace_size((int)mask_n, (int)face);
    void *ws = malloc(wsz);
    qibl_hemi_t h;
    const size_t nv = m.nv;
    qibl_q16_t(*pos)[3] = malloc(sizeof *pos * nv);
    int32_t(*nrm)[3] = malloc(sizeof *nrm * nv);
    qibl_q30_t(*vw)[25] = malloc(sizeof *vw * nv);
    double *eq = malloc(sizeof(double) * 3 * nv), *er = malloc(sizeof(double) * 3 * nv), *N = malloc(sizeof(double) * 3 * nv);
    double *l2 = malloc(sizeof(double) * nv), *noise = malloc(sizeof(double) * nv), *cpu = malloc(sizeof(double) * nv);
    double *ph = malloc(sizeof(double) * PH_N * nv), phs[PH_N] = {0};
    double *col = malloc(sizeof(double) * 3 * nv), *tmp = malloc(sizeof(double) * nv);
    double *fbuf = malloc(sizeof(double) * 3 * nv); /* a tweened frame */
    const int panels = side > 0 ? 3 : 1, S = (int)size;
    const int sw = panels * S, sh = LABEL_H + S + (panels == 3 ? LEGEND_H : 0);
    uint8_t *sheet = calloc(png ? (size_t)sw * (size_t)sh * (size_t)m.nframes : 1, 3);
    uint8_t *fbpx = malloc((size_t)S * (size_t)S * 4);
    uint32_t *depth = malloc(sizeof(uint32_t) * (size_t)S * (size_t)S);
    qibl_raster_vertex_t *rv = malloc(sizeof *rv * nv);
    uint32_t *adj_off = NULL, *adj = NULL, (*ctri)[3] = NULL, nct = 0;
    hier hi, pv;
    memset(&hi, 0, sizeof hi);
    memset(&pv, 0, sizeof pv);
    qibl_q16_t(*apos)[3] = NULL; /* --pvs: every frame's integer inputs */
    int32_t(*anrm)[3] = NULL;
    int rc = 1;
    if (!ws || !pos || !nrm || !vw || !eq || !er || !N || !l2 || !noise || !cpu || !ph || !col || !tmp || !sheet || !fbpx ||
        !depth || !rv || !fbuf) {
        fprintf(stderr, "qibl: transfer: out of memory\n");
        goto done;
    }
    qibl_status_t st = qibl_hemi_init(&h, (int)mask_n, (int)face, ws, wsz);
    if (st != QIBL_OK) {
        fprintf(stderr, "qibl: transfer: hemi init: %s\n", qibl_status_str(st));
        goto done;
    }
    qtool_transfer_status ts = qtool_transfer_adjacency(&m, &adj_off, &adj);
    if (ts != QTOOL_TRANSFER_OK) {
        fprintf(stderr, "qibl: transfer: %s\n", qtool_transfer_status_str(ts));
        goto done;
    }
    if (coarse > 0) {
        if (qtool_simplify(m.pos, m.nv, (const uint32_t(*)[3])m.tri, m.nt, (uint32_t)coarse, &ctri, &nct) != 0) {
            fprintf(stderr, "qibl: transfer: out of memory (coarse mesh)\n");
            goto done;
        }
        ts = qtool_transfer_hier_build(&m, adj_off, adj, (const uint32_t(*)[3])ctri, nct, (int)ring, !skip_adjacent, &hi);
        if (ts != QTOOL_TRANSFER_OK) {
            fprintf(stderr, "qibl: transfer: hierarchy (--coarse %ld --ring %ld): %s\n", coarse, ring,
                    qtool_transfer_status_str(ts));
            goto done;
        }
    }
    if (use_pvs) {
        apos = malloc(sizeof *apos * nv * m.nframes), anrm = malloc(sizeof *anrm * nv * m.nframes);
        if (!apos || !anrm) {
            fprintf(stderr, "qibl: transfer: out of memory (PVS)\n");
            goto done;
        }
        for (uint32_t f = 0; f < m.nframes; ++f)
            (void)frame_ints(&m, frame_pos(&m, nkeys, tw, f, fbuf), flip, N, apos + nv * f, anrm + nv * f);
        ts = qtool_transfer_pvs_build(&m, coarse > 0 ? &hi : NULL, (const qibl_q16_t(*)[3])apos,
                                      (const int32_t(*)[3])anrm, adj_off, adj, !skip_adjacent, (int)threads, &pv);
        if (ts != QTOOL_TRANSFER_OK) {
            fprintf(stderr, "qibl: transfer: PVS: %s\n", qtool_transfer_status_str(ts));
            goto done;
        }
    }
    view vwp;
    mesh keys = m; /* a linear projection's box and the largest radius are reached at the key frames */
    keys.nframes = nkeys;
    view_make(az, el, S, &keys, &vwp);
    if (verbose)
        printf("transfer: %s%s: %u vertices, %u triangles, %u frame%s; %s%s; probe %s (%s)\n", files[0],
           nfiles > 1 ? " ..." : "", m.nv, m.nt, m.nframes, m.nframes > 1 ? "s" : "",
           zup ? "z up" : "y up turned to z up",
           force_flip ? ", normals turned (--flip)" : flip < 0 ? ", closed and wound clockwise (normals turned)" : "",
           probe, pdesc);
    if (verbose)
        printf("  hemi: %ldx%ld mask, face %ld (%.1f KiB of tables), %s\n", mask_n, mask_n, face, wsz / 1024.0,
               skip_adjacent ? "adjacent faces skipped (--skip-adjacent)" : "the solid behind the faces around each vertex blocks");
    if (verbose && coarse > 0)
        printf("  hierarchy: coarse mesh of %u triangles (QEM half-edge collapses, vertices a subset of the mesh's) +\n"
               "  the full mesh within %ld rings of each vertex: %.1f blockers per vertex (of %u, crease wedges included)\n",
               nct, ring, (double)hi.boff[m.nv] / (double)m.nv, m.nt);
    else if (verbose)
        printf("  every triangle a blocker of every vertex (--coarse T: a two-level hierarchy instead)\n");
    if (side > 0)
        if (verbose)
            printf("  reference: %ld x %ld stratified cosine-weighted rays per vertex (tools/ref/hemi_ref.c)\n", side, side);
    double sum_l2 = 0, sum_noise = 0, sum_cpu = 0, sum_err = 0, sum_e = 0;
    for (uint32_t f = 0; f < m.nframes; ++f) {
        const double *P = frame_pos(&m, nkeys, tw, f, fbuf);
        const int zero = frame_ints(&m, P, flip, N, pos, nrm);
        qtool_rt_scene rt;
        int have_rt = 0;
        if (side > 0) {
            qtool_obj_mesh om;
            memset(&om, 0, sizeof om);
            om.ntri = m.nt;
            om.pos = malloc(sizeof(double) * 9 * m.nt), om.nrm = malloc(sizeof(double) * 9 * m.nt);
            if (!om.pos || !om.nrm) {
                free(om.pos), free(om.nrm);
                fprintf(stderr, "qibl: transfer: out of memory\n");
                goto done;
            }
            for (uint32_t t = 0; t < m.nt; ++t)
                for (int k = 0; k < 3; ++k)
                    for (int j = 0; j < 3; ++j) {
                        om.pos[9 * t + 3 * k + j] = pos[m.tri[t][k]][j] / 65536.0; /* what the core sees */
                        om.nrm[9 * t + 3 * k + j] = j == 2;
                    }
            const int brc = qtool_rt_scene_from_obj(&rt, &om, 1, 1);
            free(om.pos), free(om.nrm);
            if (brc != 0) {
                fprintf(stderr, "qibl: transfer: out of memory (BVH)\n");
                goto done;
            }
            have_rt = 1;
        }
        job j = {&m, &h, have_rt ? &rt : NULL, (const qibl_q16_t(*)[3])pos, (const int32_t(*)[3])nrm,
                 (const int32_t(*)[25])light, (int)side, vw, eq, er, l2, noise, cpu, ph, adj_off, adj, !skip_adjacent,
                 coarse > 0 ? &hi : NULL, use_pvs ? &pv : NULL};
        qtool_rt_parallel((int)threads, m.nv, vertex_job, &j, NULL);
        if (have_rt)
            qtool_rt_scene_free(&rt);
        double fcpu = 0, fl2 = 0, fnoise = 0;
        for (size_t v = 0; v < nv; ++v)
            fcpu += cpu[v], fl2 += l2[v], fnoise += noise[v], sum_e += lum(eq + 3 * v);
        for (size_t v = 0; v < nv; ++v)
            for (int k = 0; k < PH_N; ++k)
                phs[k] += ph[PH_N * v + (size_t)k];
        sum_cpu += fcpu, sum_l2 += fl2, sum_noise += fnoise;
        if (zero)
            if (verbose)
                printf("  frame %u: %d vertices without a normal (isolated or degenerate): shaded black\n", f + 1, zero);
        /* exposure from frame 0's reference (or qibl's without one): its 99th percentile at 0.6 */
        const double *base = side > 0 ? er : eq;
        static double expo;
        if (f == 0) {
            for (size_t v = 0; v < nv; ++v)
                tmp[v] = lum(base + 3 * v);
            qsort(tmp, nv, sizeof(double), cmp_double);
            const double p99 = tmp[(size_t)(0.99 * (double)(nv - 1))];
            expo = p99 > 0 ? 0.6 / p99 : 1;
        }
        if (!png) { /* the bench: figures only */
            if (side > 0) {
                double mean = 0, ferr = 0;
                for (size_t v = 0; v < nv; ++v)
                    mean += lum(er + 3 * v);
                mean /= (double)nv;
                for (size_t v = 0; v < nv; ++v)
                    ferr += mean > 0 ? fabs(lum(eq + 3 * v) - lum(er + 3 * v)) / mean : 0;
                sum_err += ferr;
            }
            continue;
        }
        uint8_t *fs = sheet + (size_t)sw * (size_t)sh * 3 * f;
        for (size_t v = 0; v < nv; ++v)
            for (int c = 0; c < 3; ++c)
                col[3 * v + c] = eq[3 * v + c] * expo;
        if (draw_panel(&m, P, &vwp, col, 1, S, fs, sw, 0, LABEL_H, rv, fbpx, depth) != 0)
            goto done;
        char title[96];
        snprintf(title, sizeof title, "QIBL HEMI %ldX%ld: %.0f MS", mask_n, mask_n, fcpu * 1e3);
        label(fs, sw, sh, 0, S, 5, title);
        if (side > 0) {
            double mean = 0;
            for (size_t v = 0; v < nv; ++v)
                mean += lum(er + 3 * v);
            mean /= (double)nv;
            for (size_t v = 0; v < nv; ++v)
                for (int c = 0; c < 3; ++c)
                    col[3 * v + c] = er[3 * v + c] * expo;
            if (draw_panel(&m, P, &vwp, col, 1, S, fs, sw, S, LABEL_H, rv, fbpx, depth) != 0)
                goto done;
            snprintf(title, sizeof title, "RAY CAST: %ld RAYS", side * side);
            label(fs, sw, sh, S, S, 5, title);
            double ferr = 0;
            for (size_t v = 0; v < nv; ++v) {
                const double e = mean > 0 ? fabs(lum(eq + 3 * v) - lum(er + 3 * v)) / mean : 0;
                ferr += e;
                heat(e / ERR_SCALE, col + 3 * v);
            }
            sum_err += ferr;
            if (draw_panel(&m, P, &vwp, col, 0, S, fs, sw, 2 * S, LABEL_H, rv, fbpx, depth) != 0)
                goto done;
            snprintf(title, sizeof title, "ERROR: MEAN %.1f%%", 100 * ferr / (double)nv);
            label(fs, sw, sh, 2 * S, S, 5, title);
            /* the colour scale under the error panel, linear ramp drawn as sRGB-free bytes */
            for (int x = 0; x < S - 16; ++x) {
                double c[3];
                heat((double)x / (S - 17), c);
                for (int y = 0; y < 8; ++y) {
                    uint8_t *o = fs + 3 * ((size_t)(LABEL_H + S + 2 + y) * (size_t)sw + (size_t)(2 * S + 8 + x));
                    for (int k = 0; k < 3; ++k)
                        o[k] = (uint8_t)lrint(255 * c[k]);
                }
            }
            static const uint8_t grey[3] = {200, 200, 200};
            char scale_txt[32];
            snprintf(scale_txt, sizeof scale_txt, "%.0f%%", ERR_SCALE * 100);
            qtool_text_draw(fs, sw, sh, 2 * S + 8, LABEL_H + S + 12, "0", 1, grey);
            qtool_text_draw(fs, sw, sh, 2 * S + S / 2 - 6, LABEL_H + S + 12, "OF MEAN", 1, grey);
            qtool_text_draw(fs, sw, sh, 2 * S + S - 8 - qtool_text_width(scale_txt, 1), LABEL_H + S + 12, scale_txt, 1,
                            grey);
        }
    }
    if (verbose)
        printf("  hemi: %.2f ms per frame on one core (%.1f us per vertex, %u blockers each)\n",
           sum_cpu / m.nframes * 1e3, sum_cpu / (double)(nv * m.nframes) * 1e6, m.nt);
    if (verbose)
        printf("RESULT transfer.ms_per_frame %.3f\n", sum_cpu / m.nframes * 1e3);
    if (use_pvs) {
        const double n = (double)(nv * m.nframes);
        if (verbose)
            printf("  PVS over the %u frame%s: %.1f blockers per vertex (of %.1f), %.2f ms per frame (of %.2f); masks "
                   "identical on %.0f of %.0f vertex-frames\n",
                   m.nframes, m.nframes > 1 ? "s" : "", phs[PH_PVS_BLOCKERS] / n, phs[PH_BLOCKERS] / n,
                   phs[PH_PVS_CPU] / m.nframes * 1e3, sum_cpu / m.nframes * 1e3, n - phs[PH_PVS_DIFF], n);
        if (verbose)
            printf("RESULT transfer.pvs_ms_per_frame %.3f\nRESULT transfer.pvs_blockers %.1f\n",
                   phs[PH_PVS_CPU] / m.nframes * 1e3, phs[PH_PVS_BLOCKERS] / n);
        stats->pvs_ms_per_frame = phs[PH_PVS_CPU] / m.nframes * 1e3;
        stats->pvs_blockers = phs[PH_PVS_BLOCKERS] / n;
        stats->pvs_diff = phs[PH_PVS_DIFF];
        if (phs[PH_PVS_DIFF] > 0) {
            fprintf(stderr, "qibl: transfer: the PVS changed %.0f masks (a bug)\n", phs[PH_PVS_DIFF]);
            goto done;
        }
    }
    /* in the probe's units times 2^-k (the light's scaling): comparable between meshes under one probe */
    if (verbose)
        printf("RESULT transfer.mean_irradiance %.6f\n", sum_e / (double)(nv * m.nframes));
    if (side > 0) {
        const double n = (double)(nv * m.nframes);
        if (verbose)
            printf("  error of V* against the reference: mean relative L2 %.4f (reference noise %.4f, same measure)\n",
               sum_l2 / n, sum_noise / n);
        if (verbose)
            printf("  shading error: mean |E - E_ref| / mean E_ref = %.4f\n", sum_err / n);
        if (verbose)
            printf("RESULT transfer.l2err %.5f\nRESULT transfer.ref_noise %.5f\nRESULT transfer.shade_err %.5f\n",
               sum_l2 / n, sum_noise / n, sum_err / n);
    }
    stats->nv = m.nv, stats->nt = m.nt, stats->nframes = m.nframes;
    stats->ms_per_frame = sum_cpu / m.nframes * 1e3;
    {
        const double hsum = phs[PH_TRANSFORM] + phs[PH_RASTER] + phs[PH_INTEGRATE] + phs[PH_OTHER];
        for (int k = 0; k < 4; ++k)
            stats->share[k] = hsum > 0 ? phs[k] / hsum : 0;
        stats->ref_ms_per_frame = phs[PH_REF] / m.nframes * 1e3;
        stats->blockers = phs[PH_BLOCKERS] / ((double)nv * m.nframes);
        stats->rasterized = phs[PH_RASTERIZED] / ((double)nv * m.nframes);
    }
    if (side > 0) {
        const double n = (double)(nv * m.nframes);
        stats->l2err = sum_l2 / n, stats->ref_noise = sum_noise / n, stats->shade_err = sum_err / n;
    }
    if (png) {
        char err[512];
        const int wr = m.nframes > 1
                           ? qtool_apng_write_rgb8(png, sw, sh, (int)m.nframes, sheet, 1, 8, err, sizeof err)
                           : qtool_png_write_rgb8(png, sw, sh, sheet, err, sizeof err);
        if (wr != 0) {
            fprintf(stderr, "qibl: %s\n", err);
            goto done;
        }
        if (verbose)
            printf("  wrote %s (%dx%d%s)\n", png, sw, sh, m.nframes > 1 ? ", animated" : "");
    }
    rc = 0;
done:
    free(ws), free(pos), free(nrm), free(vw), free(eq), free(er), free(N), free(l2), free(noise), free(cpu), free(ph), free(col);
    free(tmp), free(fbuf), free(sheet), free(fbpx), free(depth), free(rv), free(m.tri), free(m.pos), free(adj_off), free(adj);
    qtool_transfer_hier_free(&hi), qtool_transfer_hier_free(&pv), free(ctri), free(apos), free(anrm);
    return rc;
}

int qcli_cmd_transfer(int argc, char **argv)
{
    char *files[MAX_FRAMES];
    int nfiles = 0, zup = 0, force_flip = 0, skip_adjacent = 0, pvs = 0;
    const char *probe = NULL, *png = NULL, *layout = NULL;
    long size = 320, mask_n = 32, face = 64, side = 32, threads = 0, coarse = 0, ring = 3, tween = 1, lights = 0;
    double az = 35, el = 20;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        const int more = i + 1 < argc;
        if (strcmp(a, "--probe") == 0 && more)
            probe = argv[++i];
        else if (strcmp(a, "--png") == 0 && more)
            png = argv[++i];
        else if (strcmp(a, "--layout") == 0 && more)
            layout = argv[++i];
        else if (strcmp(a, "--zup") == 0)
            zup = 1;
        else if (strcmp(a, "--flip") == 0)
            force_flip = 1;
        else if (strcmp(a, "--skip-adjacent") == 0)
            skip_adjacent = 1;
        else if (strcmp(a, "--pvs") == 0)
            pvs = 1;
        else if (strcmp(a, "--coarse") == 0) {
            if (!more || qcli_parse_int(argv[++i], 0, 1 << 20, &coarse) != 0)
                return qcli_usage_error("--coarse needs a triangle count in 0..1048576 (0: no hierarchy)");
        } else if (strcmp(a, "--lights") == 0) {
            if (!more || qcli_parse_int(argv[++i], 1, 1024, &lights) != 0 || (lights & (lights - 1)) != 0)
                return qcli_usage_error("--lights needs a power of two in 1..1024 (median-cut lights of the probe)");
        } else if (strcmp(a, "--tween") == 0) {
            if (!more || qcli_parse_int(argv[++i], 1, 16, &tween) != 0)
                return qcli_usage_error("--tween needs an integer in 1..16 (frames per key frame)");
        } else if (strcmp(a, "--ring") == 0) {
            if (!more || qcli_parse_int(argv[++i], 1, 16, &ring) != 0)
                return qcli_usage_error("--ring needs an integer in 1..16");
        }
        else if (strcmp(a, "--size") == 0) {
            if (!more || qcli_parse_int(argv[++i], 64, 2048, &size) != 0)
                return qcli_usage_error("--size needs an integer in 64..2048 (pixels per panel)");
        } else if (strcmp(a, "--mask") == 0) {
            if (!more || qcli_parse_int(argv[++i], 16, 64, &mask_n) != 0 || (mask_n != 16 && mask_n != 32 && mask_n != 64))
                return qcli_usage_error("--mask needs 16, 32 or 64");
        } else if (strcmp(a, "--face") == 0) {
            if (!more || qcli_parse_int(argv[++i], 2, QIBL_HEMI_MAX_FACE, &face) != 0 || (face & 1))
                return qcli_usage_error("--face needs an even integer in 2..%d", QIBL_HEMI_MAX_FACE);
        } else if (strcmp(a, "--rays") == 0) {
            if (!more || qcli_parse_int(argv[++i], 0, 256, &side) != 0)
                return qcli_usage_error("--rays needs S in 0..256 (S x S rays per vertex; 0: no reference)");
        } else if (strcmp(a, "--threads") == 0) {
            if (!more || qcli_parse_int(argv[++i], 1, 256, &threads) != 0)
                return qcli_usage_error("--threads needs an integer in 1..256");
        } else if (strcmp(a, "--view") == 0) {
            if (!more || parse_view(argv[++i], &az, &el) != 0)
                return qcli_usage_error("--view needs AZ,EL in degrees (|EL| < 90), e.g. 35,20");
        } else if (a[0] == '-') {
            return qcli_usage_error("transfer: unknown or incomplete option '%s' (%s)", a, TRANSFER_USAGE);
        } else if (nfiles == MAX_FRAMES) {
            return qcli_usage_error("transfer: at most %d frames", MAX_FRAMES);
        } else {
            files[nfiles++] = argv[i];
        }
    }
    if (nfiles == 0 || !probe)
        return qcli_usage_error(TRANSFER_USAGE);
    if (qcli_parse_only) /* fuzz_cliopts: the options only */
        return 0;
    const topts o = {files, nfiles, zup, force_flip, skip_adjacent, pvs, probe, png, layout, size, mask_n, face, side,
                     threads, coarse, ring, tween, az, el, lights};
    qcli_transfer_stats st;
    return transfer_run(&o, &st, 1);
}

int qcli_transfer_measure(char **files, int nframes, int zup, const char *probe, int mask, int face, int rays,
                          int coarse, int ring, int pvs, qcli_transfer_stats *st)
{
    const topts o = {files, nframes, zup, 0, 0, pvs, probe, NULL, NULL, 64, mask, face, rays, 0, coarse, ring, 1, 35, 20, 0};
    return transfer_run(&o, st, 0);
}
