/*
 * transfer/job.c - the per-vertex work of `qibl transfer` (transfer/job.h), run on threads by
 * qtool_rt_parallel: each vertex writes only its own entries of the job's arrays.
 *
 * Per vertex: the frame (qibl_hemi_frame_init), the blockers transformed into it and rasterized into
 * the mask (every triangle plus the crease wedges, or a hierarchy's lists), the transfer vector, in
 * world space, shaded with the light (qibl_hemi_shade); the phases timed on the thread's CPU clock;
 * with a PVS the same vertex again from its PVS, masks compared; with a reference, the ray cast of
 * the same position and frame (tools/ref/hemi_ref.c) shaded with the same coefficients in double.
 */
#include "transfer/job.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "ref/hemi_ref.h"

static double thread_cpu(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* The hemi work of one vertex from hierarchy-style lists (its vertices, its blockers in local
 * indices, local index n the nadir of the crease wedges): the mask, and the transform's time
 * unless t_transform is NULL (no clock read). */
static qibl_status_t mask_from_lists(const qtool_transfer_job *j, const qtool_transfer_hier *L,
                                     const qibl_hemi_frame_t *fr, uint32_t v, int32_t (*loc)[3], qibl_q16_t (*gp)[3],
                                     uint32_t *mask, qibl_hemi_stats_t *hs, double *t_transform)
{
    const double t0 = t_transform ? thread_cpu() : 0;
    const size_t n = L->voff[v + 1] - L->voff[v];
    for (size_t k = 0; k < n; ++k)
        memcpy(gp[k], j->pos[L->vl[L->voff[v] + k]], sizeof gp[k]);
    qibl_status_t st = qibl_hemi_transform(fr, (const qibl_q16_t(*)[3])gp, (uint32_t)n, loc);
    if (t_transform)
        *t_transform = thread_cpu() - t0;
    loc[n][0] = 0, loc[n][1] = 0, loc[n][2] = -(1 << 20); /* the nadir of the crease wedges */
    if (st == QIBL_OK)
        st = qibl_hemi_clear(j->h, mask);
    if (st == QIBL_OK)
        st = qibl_hemi_raster(j->h, (const int32_t(*)[3])loc, (uint32_t)n + 1, L->blk + L->boff[v],
                              (uint32_t)(L->boff[v + 1] - L->boff[v]), mask, hs);
    return st;
}

/* The faces around the receiver: the rasterizer skips them (their planes pass through it), yet the
 * surface hides what lies behind them: at a crease (a box's floor meeting its walls) the averaged
 * normal's hemisphere reaches behind a face. The solid's side of the fan of faces is the union of
 * the wedges (nadir, b, c) of each face (v, b, c), the nadir -n being inside; at a convex vertex
 * every wedge lies below the horizon and blocks nothing. No winding needed. (The hierarchy's lists
 * carry these wedges already.) loc holds nv transformed vertices and room for the nadir. */
static qibl_status_t raster_crease(const qtool_transfer_job *j, uint32_t v, int32_t (*loc)[3], uint32_t *mask,
                                   qibl_hemi_stats_t *hs, uint32_t *nblk)
{
    const qtool_transfer_mesh *m = j->m;
    qibl_status_t st = QIBL_OK;
    uint32_t fan[64][3], nf = 0;
    loc[m->nv][0] = 0, loc[m->nv][1] = 0, loc[m->nv][2] = -(1 << 20); /* 4 units straight down */
    for (uint32_t k = j->adj_off[v]; st == QIBL_OK && k < j->adj_off[v + 1]; ++k) {
        const uint32_t *t = m->tri[j->adj[k]];
        const int r = t[0] == v ? 0 : t[1] == v ? 1 : 2;
        fan[nf][0] = m->nv, fan[nf][1] = t[(r + 1) % 3], fan[nf][2] = t[(r + 2) % 3];
        if (++nf == 64 || k + 1 == j->adj_off[v + 1]) {
            *nblk += nf;
            st = qibl_hemi_raster(j->h, (const int32_t(*)[3])loc, m->nv + 1, (const uint32_t(*)[3])fan, nf, mask, hs);
            nf = 0;
        }
    }
    return st;
}

/* The same vertex from its PVS: same work after the mask, timed, the mask compared with mask. */
static void from_pvs(const qtool_transfer_job *j, const qibl_hemi_frame_t *fr, uint32_t v, int32_t (*loc)[3],
                     qibl_q16_t (*gp)[3], const uint32_t *mask, double *ph)
{
    uint32_t pm[QIBL_HEMI_MAX_WORDS];
    qibl_q30_t pl[25], pw[25];
    qibl_q16_t pe[3];
    qibl_hemi_stats_t ps = {0, 0, 0};
    double tt = 0;
    const double p0 = thread_cpu();
    qibl_status_t s2 = mask_from_lists(j, j->pvs, fr, v, loc, gp, pm, &ps, &tt);
    if (s2 == QIBL_OK)
        s2 = qibl_hemi_transfer(j->h, pm, pl);
    if (s2 == QIBL_OK)
        s2 = qibl_hemi_to_world(j->h, fr, pl, pw);
    if (s2 == QIBL_OK)
        s2 = qibl_hemi_shade(j->light, pw, pe);
    ph[QTOOL_PH_PVS_CPU] = thread_cpu() - p0;
    ph[QTOOL_PH_PVS_BLOCKERS] = (double)(j->pvs->boff[v + 1] - j->pvs->boff[v]);
    ph[QTOOL_PH_PVS_DIFF] = s2 != QIBL_OK || memcmp(pm, mask, sizeof(uint32_t) * j->h->words) != 0;
}

/* The ray-cast reference of vertex v in frame fr: its L2 distance from qibl's transfer, its noise,
 * its shading with the same light in double. */
static void reference(const qtool_transfer_job *j, const qibl_hemi_frame_t *fr, uint32_t v, double *ph)
{
    double ax[3][3], p[3], ref[25];
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k)
            ax[i][k] = fr->axis[i][k] / 1073741824.0;
    for (int k = 0; k < 3; ++k)
        p[k] = j->pos[v][k] / 65536.0;
    const double tr = thread_cpu();
    qtool_hemi_ref(j->rt, p, ax, j->side, 1, 0x5EED0000u + v * 0x9E3779B97F4A7C15u, ref, &j->noise[v]);
    ph[QTOOL_PH_REF] = thread_cpu() - tr;
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

/* a vertex without its scratch or without a frame (no normal): black, no figures */
static void vertex_none(const qtool_transfer_job *j, uint32_t v)
{
    memset(j->vw[v], 0, sizeof j->vw[v]);
    memset(j->e[v], 0, sizeof j->e[v]);
    for (int c = 0; c < 3; ++c)
        j->eq[3 * v + c] = j->er[3 * v + c] = 0;
    j->l2[v] = j->noise[v] = j->cpu[v] = 0;
    memset(j->ph + QTOOL_PH_N * v, 0, sizeof(double) * QTOOL_PH_N);
}

void qtool_transfer_vertex_job(void *ctx, uint32_t v)
{
    const qtool_transfer_job *j = ctx;
    const qtool_transfer_mesh *m = j->m;
    int32_t(*loc)[3] = malloc(sizeof *loc * (m->nv + 1)); /* + the nadir */
    qibl_q16_t(*gp)[3] = j->hi || j->pvs ? malloc(sizeof *gp * m->nv) : NULL;
    uint32_t mask[QIBL_HEMI_MAX_WORDS];
    qibl_q30_t vl[25];
    qibl_hemi_frame_t fr;
    if (!loc || ((j->hi || j->pvs) && !gp) || qibl_hemi_frame_init(&fr, j->pos[v], j->nrm[v]) != QIBL_OK) {
        vertex_none(j, v);
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
    if (j->crease && !j->hi && st == QIBL_OK)
        st = raster_crease(j, v, loc, mask, &hs, &nblk);
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
    double *ph = j->ph + QTOOL_PH_N * v;
    ph[QTOOL_PH_TRANSFORM] = t1 - t0, ph[QTOOL_PH_RASTER] = t2 - t1, ph[QTOOL_PH_INTEGRATE] = t3 - t2;
    ph[QTOOL_PH_OTHER] = j->cpu[v] - (t3 - t0);
    ph[QTOOL_PH_BLOCKERS] = nblk, ph[QTOOL_PH_RASTERIZED] = hs.rasterized, ph[QTOOL_PH_REF] = 0;
    ph[QTOOL_PH_PVS_CPU] = ph[QTOOL_PH_PVS_BLOCKERS] = ph[QTOOL_PH_PVS_DIFF] = 0;
    if (j->pvs && st == QIBL_OK)
        from_pvs(j, &fr, v, loc, gp, mask, ph);
    free(loc), free(gp);
    if (st != QIBL_OK) /* cannot happen for validated inputs; shown black rather than dropped */
        memset(j->vw[v], 0, sizeof j->vw[v]), e[0] = e[1] = e[2] = 0;
    for (int c = 0; c < 3; ++c)
        j->eq[3 * v + c] = e[c] / 65536.0, j->e[v][c] = e[c];
    j->l2[v] = j->noise[v] = 0;
    if (j->rt)
        reference(j, &fr, v, ph);
}

double qtool_transfer_frame_block(const qtool_transfer_job *j, int pvs)
{
    const qtool_transfer_mesh *m = j->m;
    const qtool_transfer_hier *L = pvs ? j->pvs : j->hi;
    int32_t(*loc)[3] = malloc(sizeof *loc * (m->nv + 1));
    qibl_q16_t(*gp)[3] = L ? malloc(sizeof *gp * m->nv) : NULL;
    if (!loc || (L && !gp)) {
        free(loc), free(gp);
        return -1;
    }
    uint32_t mask[QIBL_HEMI_MAX_WORDS];
    qibl_q30_t vl[25], vw[25];
    qibl_q16_t e[3];
    volatile int32_t sink = 0; /* the shading is used: nothing of the block is dead */
    const double t0 = thread_cpu();
    for (uint32_t v = 0; v < m->nv; ++v) {
        qibl_hemi_frame_t fr;
        if (qibl_hemi_frame_init(&fr, j->pos[v], j->nrm[v]) != QIBL_OK)
            continue; /* as the job: no normal, no hemi work */
        qibl_hemi_stats_t hs = {0, 0, 0};
        uint32_t nblk = 0;
        qibl_status_t st;
        if (L) {
            st = mask_from_lists(j, L, &fr, v, loc, gp, mask, &hs, NULL);
        } else {
            st = qibl_hemi_transform(&fr, j->pos, m->nv, loc);
            if (st == QIBL_OK)
                st = qibl_hemi_clear(j->h, mask);
            if (st == QIBL_OK)
                st = qibl_hemi_raster(j->h, (const int32_t(*)[3])loc, m->nv, (const uint32_t(*)[3])m->tri, m->nt,
                                      mask, &hs);
            if (j->crease && st == QIBL_OK)
                st = raster_crease(j, v, loc, mask, &hs, &nblk);
        }
        if (st == QIBL_OK)
            st = qibl_hemi_transfer(j->h, mask, vl);
        if (st == QIBL_OK)
            st = qibl_hemi_to_world(j->h, &fr, vl, vw);
        if (st == QIBL_OK)
            st = qibl_hemi_shade(j->light, vw, e);
        sink += st == QIBL_OK ? e[0] + e[1] + e[2] : 0;
    }
    const double t = thread_cpu() - t0;
    free(loc), free(gp);
    (void)sink;
    return t;
}
