/*
 * transfer/run.c - qtool_transfer_measure (transfer/run.h): the frames, the hemi tables, the
 * adjacency, the hierarchy and the PVS set up once; then per frame the integer inputs, every
 * vertex's job on threads (transfer/job.c), the figures summed and, with a sheet, its panels drawn.
 *
 * Invariants: every allocation of a run hangs off one struct freed in one place; the result is
 * filled only when the whole run succeeded (else zeroed, with err set).
 */
#include "transfer/run.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gen/simplify.h"
#include "io/obj.h"
#include "qtool.h"
#include "transfer/frames.h"
#include "transfer/job.h"
#include "transfer/sheet.h"

typedef struct run {
    const qtool_transfer_opts *o;
    qtool_transfer_mesh m;         /* m.nframes: every frame; the key frames alone are held */
    uint32_t nkeys, tw;            /* key frames, frames per key frame */
    double flip;                   /* -1: normals turned */
    size_t wsz;
    void *ws;
    qibl_hemi_t h;
    qibl_q16_t (*pos)[3];
    int32_t (*nrm)[3];
    qibl_q30_t (*vw)[25];
    qibl_q16_t (*e)[3];
    double *eq, *er, *N, *l2, *noise, *cpu, *ph, *col, *tmp, *fbuf;
    double phs[QTOOL_PH_N];
    uint32_t *adj_off, *adj, (*ctri)[3], nct;
    qtool_transfer_hier hi, pv;
    qibl_q16_t (*apos)[3]; /* pvs: every frame's integer inputs */
    int32_t (*anrm)[3];
    int S, sw, sh;         /* the sheet: panel size, width, height */
    uint8_t *sheet;
    qtool_transfer_panel pn;
    qtool_transfer_view vwp;
    double sum_l2, sum_noise, sum_cpu, sum_err, sum_e, expo;
    uint32_t no_normal[QTOOL_TRANSFER_MAX_FRAMES * QTOOL_TRANSFER_MAX_TWEEN];
} run;

static void run_free(run *R)
{
    free(R->ws), free(R->pos), free(R->nrm), free(R->vw), free(R->e), free(R->eq), free(R->er), free(R->N);
    free(R->l2), free(R->noise), free(R->cpu), free(R->ph), free(R->col), free(R->tmp), free(R->fbuf);
    free(R->sheet), free(R->pn.px), free(R->pn.depth), free(R->pn.rv), free(R->m.tri), free(R->m.pos);
    free(R->adj_off), free(R->adj), free(R->ctri), free(R->apos), free(R->anrm);
    qtool_transfer_hier_free(&R->hi), qtool_transfer_hier_free(&R->pv);
}

static double lum(const double *c)
{
    return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* the sheet of every frame, from the request alone, before anything is read */
static int check_sheet(const qtool_transfer_opts *o, char *err, size_t errlen)
{
    const uint64_t frames = o->nfiles > 1 ? (uint64_t)o->nfiles * (uint64_t)o->tween : 1, panels = o->rays > 0 ? 3 : 1;
    const uint64_t fw = panels * (uint64_t)o->size,
                   fh = QTOOL_TRANSFER_LABEL_H + (uint64_t)o->size + (panels == 3 ? QTOOL_TRANSFER_LEGEND_H : 0);
    if (frames * fw * fh * 3 <= QTOOL_TRANSFER_MAX_HELD)
        return 0;
    return qtool_errf(err, errlen, "--png of %llu frames of %llux%llu is %.0f MiB of frames held for the APNG (at "
                      "most %d MiB): fewer frames or --tween, a smaller --size, or --rays 0 (one panel)",
                      (unsigned long long)frames, (unsigned long long)fw, (unsigned long long)fh,
                      (double)(frames * fw * fh * 3) / 1048576.0, (int)(QTOOL_TRANSFER_MAX_HELD >> 20));
}

/* the frames, their count with tweening, the --pvs cap and the winding */
static int load(run *R, char *err, size_t errlen)
{
    const qtool_transfer_opts *o = R->o;
    if (qtool_transfer_frames_load(o->files, o->nfiles, o->zup, &R->m, err, errlen) != 0)
        return -1;
    R->nkeys = R->m.nframes, R->tw = o->tween > 1 && R->nkeys > 1 ? (uint32_t)o->tween : 1;
    R->m.nframes = R->nkeys * R->tw;
    const qtool_transfer_mesh *m = &R->m;
    if (o->pvs && (uint64_t)m->nv * m->nframes * (sizeof(qibl_q16_t[3]) + sizeof(int32_t[3])) > QTOOL_TRANSFER_MAX_HELD)
        return qtool_errf(err, errlen, "--pvs over %u frames of %u vertices needs %.0f MiB of integer positions and "
                          "normals (at most %d MiB): fewer frames or --tween", m->nframes, m->nv,
                          (double)m->nv * m->nframes * 24 / 1048576.0, (int)(QTOOL_TRANSFER_MAX_HELD >> 20));
    /* winding: turned by flip, or when a (nearly) closed mesh has a negative volume */
    long nedges = 0, open_edges = qtool_transfer_boundary_edges(m, &nedges);
    const double vol = qtool_transfer_signed_volume(m, m->pos);
    const int closed = open_edges >= 0 && open_edges * 50 <= nedges;
    R->flip = o->flip || (closed && vol < 0) ? -1 : 1;
    return 0;
}

static int alloc_all(run *R, char *err, size_t errlen)
{
    const qtool_transfer_opts *o = R->o;
    const size_t nv = R->m.nv;
    R->wsz = qibl_hemi_workspace_size(o->mask, o->face);
    R->ws = malloc(R->wsz);
    R->pos = malloc(sizeof *R->pos * nv), R->nrm = malloc(sizeof *R->nrm * nv), R->vw = malloc(sizeof *R->vw * nv);
    R->e = malloc(sizeof *R->e * nv);
    R->eq = malloc(sizeof(double) * 3 * nv), R->er = malloc(sizeof(double) * 3 * nv);
    R->N = malloc(sizeof(double) * 3 * nv), R->fbuf = malloc(sizeof(double) * 3 * nv); /* fbuf: a tweened frame */
    R->l2 = malloc(sizeof(double) * nv), R->noise = malloc(sizeof(double) * nv), R->cpu = malloc(sizeof(double) * nv);
    R->ph = malloc(sizeof(double) * QTOOL_PH_N * nv), R->tmp = malloc(sizeof(double) * nv);
    int ok = R->ws && R->pos && R->nrm && R->vw && R->e && R->eq && R->er && R->N && R->fbuf && R->l2 && R->noise &&
             R->cpu && R->ph && R->tmp;
    if (o->sheet) {
        const int panels = o->rays > 0 ? 3 : 1;
        R->S = o->size;
        R->sw = panels * R->S, R->sh = QTOOL_TRANSFER_LABEL_H + R->S + (panels == 3 ? QTOOL_TRANSFER_LEGEND_H : 0);
        R->sheet = calloc((size_t)R->sw * (size_t)R->sh * (size_t)R->m.nframes, 3);
        R->col = malloc(sizeof(double) * 3 * nv);
        R->pn.size = R->S, R->pn.px = malloc((size_t)R->S * (size_t)R->S * 4);
        R->pn.depth = malloc(sizeof(uint32_t) * (size_t)R->S * (size_t)R->S);
        R->pn.rv = malloc(sizeof *R->pn.rv * nv);
        ok = ok && R->sheet && R->col && R->pn.px && R->pn.depth && R->pn.rv;
    }
    return ok ? 0 : qtool_errf(err, errlen, "out of memory");
}

/* the hemi tables, the adjacency, the hierarchy (coarse > 0) and the PVS (pvs) */
static int prepare(run *R, char *err, size_t errlen)
{
    const qtool_transfer_opts *o = R->o;
    qtool_transfer_mesh *m = &R->m;
    qibl_status_t st = qibl_hemi_init(&R->h, o->mask, o->face, R->ws, R->wsz);
    if (st != QIBL_OK)
        return qtool_errf(err, errlen, "hemi init: %s", qibl_status_str(st));
    qtool_transfer_status ts = qtool_transfer_adjacency(m, &R->adj_off, &R->adj);
    if (ts != QTOOL_TRANSFER_OK)
        return qtool_errf(err, errlen, "%s", qtool_transfer_status_str(ts));
    if (o->coarse > 0) {
        if (qtool_simplify(m->pos, m->nv, (const uint32_t(*)[3])m->tri, m->nt, (uint32_t)o->coarse, &R->ctri, &R->nct) != 0)
            return qtool_errf(err, errlen, "out of memory (coarse mesh)");
        ts = qtool_transfer_hier_build(m, R->adj_off, R->adj, (const uint32_t(*)[3])R->ctri, R->nct, o->ring,
                                       !o->skip_adjacent, &R->hi);
        if (ts != QTOOL_TRANSFER_OK)
            return qtool_errf(err, errlen, "hierarchy (--coarse %d --ring %d): %s", o->coarse, o->ring,
                              qtool_transfer_status_str(ts));
    }
    if (!o->pvs)
        return 0;
    const size_t nv = m->nv;
    R->apos = malloc(sizeof *R->apos * nv * m->nframes), R->anrm = malloc(sizeof *R->anrm * nv * m->nframes);
    if (!R->apos || !R->anrm)
        return qtool_errf(err, errlen, "out of memory (PVS)");
    for (uint32_t f = 0; f < m->nframes; ++f)
        (void)qtool_transfer_frame_ints(m, qtool_transfer_frame_pos(m, R->nkeys, R->tw, f, R->fbuf), R->flip, R->N,
                                        R->apos + nv * f, R->anrm + nv * f);
    ts = qtool_transfer_pvs_build(m, o->coarse > 0 ? &R->hi : NULL, (const qibl_q16_t(*)[3])R->apos,
                                  (const int32_t(*)[3])R->anrm, R->adj_off, R->adj, !o->skip_adjacent, o->threads,
                                  &R->pv);
    if (ts != QTOOL_TRANSFER_OK)
        return qtool_errf(err, errlen, "PVS: %s", qtool_transfer_status_str(ts));
    return 0;
}

/* the reference's scene: the triangles at the integer positions the core sees */
static int ref_scene(const run *R, qtool_rt_scene *rt, char *err, size_t errlen)
{
    const qtool_transfer_mesh *m = &R->m;
    qtool_obj_mesh om;
    memset(&om, 0, sizeof om);
    om.ntri = m->nt;
    om.pos = malloc(sizeof(double) * 9 * m->nt), om.nrm = malloc(sizeof(double) * 9 * m->nt);
    if (!om.pos || !om.nrm) {
        free(om.pos), free(om.nrm);
        return qtool_errf(err, errlen, "out of memory");
    }
    for (uint32_t t = 0; t < m->nt; ++t)
        for (int k = 0; k < 3; ++k)
            for (int j = 0; j < 3; ++j) {
                om.pos[9 * t + 3 * k + j] = R->pos[m->tri[t][k]][j] / 65536.0; /* what the core sees */
                om.nrm[9 * t + 3 * k + j] = j == 2;
            }
    const int brc = qtool_rt_scene_from_obj(rt, &om, 1, 1);
    free(om.pos), free(om.nrm);
    return brc != 0 ? qtool_errf(err, errlen, "out of memory (BVH)") : 0;
}

/* the mean relative shading error of a frame against its reference (sum over vertices), and the
 * reference's mean luminance */
static double frame_err(const run *R, double *mean_out)
{
    const size_t nv = R->m.nv;
    double mean = 0, ferr = 0;
    for (size_t v = 0; v < nv; ++v)
        mean += lum(R->er + 3 * v);
    mean /= (double)nv;
    for (size_t v = 0; v < nv; ++v)
        ferr += mean > 0 ? fabs(lum(R->eq + 3 * v) - lum(R->er + 3 * v)) / mean : 0;
    *mean_out = mean;
    return ferr;
}

/* frame f's panels: qibl's shading, the reference and the error with its scale */
static int draw_frame(run *R, uint32_t f, const double *P, double fcpu, char *err, size_t errlen)
{
    const qtool_transfer_mesh *m = &R->m;
    const size_t nv = m->nv;
    const int S = R->S, sw = R->sw, sh = R->sh;
    uint8_t *fs = R->sheet + (size_t)sw * (size_t)sh * 3 * f;
    for (size_t v = 0; v < nv; ++v)
        for (int c = 0; c < 3; ++c)
            R->col[3 * v + c] = R->eq[3 * v + c] * R->expo;
    if (qtool_transfer_panel_draw(m, P, &R->vwp, R->col, 1, &R->pn, fs, sw, 0, QTOOL_TRANSFER_LABEL_H, err, errlen))
        return -1;
    char title[96];
    snprintf(title, sizeof title, "QIBL HEMI %dX%d: %.0f MS", R->o->mask, R->o->mask, fcpu * 1e3);
    qtool_transfer_label(fs, sw, sh, 0, S, 5, title);
    if (R->o->rays <= 0)
        return 0;
    for (size_t v = 0; v < nv; ++v)
        for (int c = 0; c < 3; ++c)
            R->col[3 * v + c] = R->er[3 * v + c] * R->expo;
    if (qtool_transfer_panel_draw(m, P, &R->vwp, R->col, 1, &R->pn, fs, sw, S, QTOOL_TRANSFER_LABEL_H, err, errlen))
        return -1;
    snprintf(title, sizeof title, "RAY CAST: %d RAYS", R->o->rays * R->o->rays);
    qtool_transfer_label(fs, sw, sh, S, S, 5, title);
    double mean;
    const double ferr = frame_err(R, &mean);
    for (size_t v = 0; v < nv; ++v) {
        const double e = mean > 0 ? fabs(lum(R->eq + 3 * v) - lum(R->er + 3 * v)) / mean : 0;
        qtool_transfer_heat(e / QTOOL_TRANSFER_ERR_SCALE, R->col + 3 * v);
    }
    if (qtool_transfer_panel_draw(m, P, &R->vwp, R->col, 0, &R->pn, fs, sw, 2 * S, QTOOL_TRANSFER_LABEL_H, err, errlen))
        return -1;
    snprintf(title, sizeof title, "ERROR: MEAN %.1f%%", 100 * ferr / (double)nv);
    qtool_transfer_label(fs, sw, sh, 2 * S, S, 5, title);
    qtool_transfer_legend(fs, sw, sh, 2 * S, S);
    return 0;
}

/* frame 0's exposure from its reference (or qibl's without one): its 99th percentile at 0.6 */
static void exposure(run *R)
{
    const size_t nv = R->m.nv;
    const double *base = R->o->rays > 0 ? R->er : R->eq;
    for (size_t v = 0; v < nv; ++v)
        R->tmp[v] = lum(base + 3 * v);
    qsort(R->tmp, nv, sizeof(double), cmp_double);
    const double p99 = R->tmp[(size_t)(0.99 * (double)(nv - 1))];
    R->expo = p99 > 0 ? 0.6 / p99 : 1;
}

/* time_reps: the frame's hemi work again as whole-frame blocks, the every-blocker and PVS passes
 * alternated in one loop, their minima replacing the pass's per-vertex sums (which a reference ray
 * cast between two vertices makes depend on what it left in the caches) */
static int frame_blocks(run *R, const qtool_transfer_job *j, double *fcpu, char *err, size_t errlen)
{
    double best = -1, best_pvs = -1;
    for (int k = 0; k < R->o->time_reps; ++k) {
        const double t = qtool_transfer_frame_block(j, 0), tp = j->pvs ? qtool_transfer_frame_block(j, 1) : 0;
        if (t < 0 || tp < 0)
            return qtool_errf(err, errlen, "out of memory (the timed passes)");
        best = best < 0 || t < best ? t : best;
        best_pvs = best_pvs < 0 || tp < best_pvs ? tp : best_pvs;
    }
    *fcpu = best;
    R->phs[QTOOL_PH_PVS_CPU] += best_pvs; /* frame() left the pass's PVS clocks out */
    return 0;
}

static int frame(run *R, uint32_t f, const int32_t light[3][25], qtool_transfer_result *r, char *err, size_t errlen)
{
    const qtool_transfer_opts *o = R->o;
    const qtool_transfer_mesh *m = &R->m;
    const size_t nv = m->nv;
    const double *P = qtool_transfer_frame_pos(m, R->nkeys, R->tw, f, R->fbuf);
    R->no_normal[f] = qtool_transfer_frame_ints(m, P, R->flip, R->N, R->pos, R->nrm);
    qtool_rt_scene rt;
    const int have_rt = o->rays > 0;
    if (have_rt && ref_scene(R, &rt, err, errlen) != 0)
        return -1;
    const qtool_transfer_job j = {
        .m = m, .h = &R->h, .rt = have_rt ? &rt : NULL, .pos = (const qibl_q16_t(*)[3])R->pos,
        .nrm = (const int32_t(*)[3])R->nrm, .light = light, .side = o->rays, .vw = R->vw, .e = R->e, .eq = R->eq,
        .er = R->er, .l2 = R->l2, .noise = R->noise, .cpu = R->cpu, .ph = R->ph, .adj_off = R->adj_off,
        .adj = R->adj, .crease = !o->skip_adjacent, .hi = o->coarse > 0 ? &R->hi : NULL, .pvs = o->pvs ? &R->pv : NULL};
    qtool_rt_parallel(o->threads, m->nv, qtool_transfer_vertex_job, (void *)&j, NULL);
    if (have_rt)
        qtool_rt_scene_free(&rt);
    double fcpu = 0, fl2 = 0, fnoise = 0;
    for (size_t v = 0; v < nv; ++v)
        fcpu += R->cpu[v], fl2 += R->l2[v], fnoise += R->noise[v], R->sum_e += lum(R->eq + 3 * v);
    for (size_t v = 0; v < nv; ++v)
        for (int k = 0; k < QTOOL_PH_N; ++k)
            if (k != QTOOL_PH_PVS_CPU || o->time_reps == 0)
                R->phs[k] += R->ph[QTOOL_PH_N * v + (size_t)k];
    if (o->time_reps > 0 && frame_blocks(R, &j, &fcpu, err, errlen) != 0)
        return -1;
    R->sum_cpu += fcpu, R->sum_l2 += fl2, R->sum_noise += fnoise;
    if (f == 0)
        exposure(R);
    if (f == 0 && o->keep_transfer) {
        memcpy(r->transfer, R->vw, sizeof *R->vw * nv);
        memcpy(r->shade, R->e, sizeof *R->e * nv);
    }
    if (have_rt) {
        double mean;
        R->sum_err += frame_err(R, &mean);
    }
    return o->sheet ? draw_frame(R, f, P, fcpu, err, errlen) : 0;
}

/* the run's figures into r */
static void figures(const run *R, qtool_transfer_result *r)
{
    const qtool_transfer_mesh *m = &R->m;
    const double n = (double)m->nv * m->nframes;
    r->nv = m->nv, r->nt = m->nt, r->nframes = m->nframes;
    r->flipped = R->flip < 0;
    r->hemi_bytes = R->wsz;
    r->coarse_nt = R->nct;
    r->hier_blockers = R->o->coarse > 0 ? (double)R->hi.boff[m->nv] / (double)m->nv : 0;
    r->ms_per_frame = R->sum_cpu / m->nframes * 1e3;
    r->mean_irradiance = R->sum_e / n;
    const double hsum = R->phs[QTOOL_PH_TRANSFORM] + R->phs[QTOOL_PH_RASTER] + R->phs[QTOOL_PH_INTEGRATE] +
                        R->phs[QTOOL_PH_OTHER];
    for (int k = 0; k < 4; ++k)
        r->share[k] = hsum > 0 ? R->phs[k] / hsum : 0;
    r->ref_ms_per_frame = R->phs[QTOOL_PH_REF] / m->nframes * 1e3;
    r->blockers = R->phs[QTOOL_PH_BLOCKERS] / n;
    r->rasterized = R->phs[QTOOL_PH_RASTERIZED] / n;
    if (R->o->pvs) {
        r->pvs_ms_per_frame = R->phs[QTOOL_PH_PVS_CPU] / m->nframes * 1e3;
        r->pvs_blockers = R->phs[QTOOL_PH_PVS_BLOCKERS] / n;
        r->pvs_diff = R->phs[QTOOL_PH_PVS_DIFF];
    }
    if (R->o->rays > 0)
        r->l2err = R->sum_l2 / n, r->ref_noise = R->sum_noise / n, r->shade_err = R->sum_err / n;
    memcpy(r->no_normal, R->no_normal, sizeof r->no_normal);
}

/* the options' ranges (the CLI checks them with their own messages first) */
static int check_opts(const qtool_transfer_opts *o, char *err, size_t errlen)
{
    if (!o->files || o->nfiles < 1 || o->nfiles > QTOOL_TRANSFER_MAX_FRAMES || !o->probe)
        return qtool_errf(err, errlen, "1..%d meshes and a probe needed", QTOOL_TRANSFER_MAX_FRAMES);
    if (o->time_reps < 0 || o->time_reps > QTOOL_TRANSFER_MAX_TIME_REPS)
        return qtool_errf(err, errlen, "time_reps %d out of 0..%d", o->time_reps, QTOOL_TRANSFER_MAX_TIME_REPS);
    if (o->tween < 1 || o->tween > QTOOL_TRANSFER_MAX_TWEEN || o->threads < 1 || o->rays < 0 || o->rays > 256 ||
        o->coarse < 0 || o->ring < 1 || o->ring > QTOOL_TRANSFER_MAX_RING || o->lights < 0 || o->lights > 1024 ||
        (o->lights & (o->lights - 1)) != 0 || (o->sheet && (o->size < 64 || o->size > 2048)))
        return qtool_errf(err, errlen, "an option out of its range (tween, threads, rays, coarse, ring, lights, size)");
    return 0;
}

int qtool_transfer_measure(const qtool_transfer_opts *o, qtool_transfer_result *r, char *err, size_t errlen)
{
    memset(r, 0, sizeof *r);
    if (check_opts(o, err, errlen) != 0 || (o->sheet && check_sheet(o, err, errlen) != 0))
        return -1;
    if (qtool_transfer_probe_light(o->probe, o->layout, o->lights, r->light, r->probe_desc, sizeof r->probe_desc, err,
                                   errlen) != 0)
        return memset(r, 0, sizeof *r), -1;
    run R;
    memset(&R, 0, sizeof R);
    R.o = o;
    int rc = load(&R, err, errlen) == 0 && alloc_all(&R, err, errlen) == 0 && prepare(&R, err, errlen) == 0 ? 0 : -1;
    if (rc == 0 && o->keep_transfer) {
        r->transfer = malloc(sizeof *r->transfer * R.m.nv), r->shade = malloc(sizeof *r->shade * R.m.nv);
        rc = r->transfer && r->shade ? 0 : qtool_errf(err, errlen, "out of memory");
    }
    if (rc == 0 && o->sheet) {
        qtool_transfer_mesh keys = R.m; /* a linear projection's box and the largest radius are reached at the key frames */
        keys.nframes = R.nkeys;
        qtool_transfer_view_make(o->az, o->el, R.S, &keys, &R.vwp);
    }
    for (uint32_t f = 0; rc == 0 && f < R.m.nframes; ++f)
        rc = frame(&R, f, (const int32_t(*)[25])r->light, r, err, errlen);
    if (rc == 0) {
        figures(&R, r);
        if (r->pvs_diff > 0)
            rc = qtool_errf(err, errlen, "the PVS changed %.0f masks (a bug)", r->pvs_diff);
    }
    if (rc == 0 && o->sheet)
        r->sheet = R.sheet, r->sheet_w = R.sw, r->sheet_h = R.sh, R.sheet = NULL;
    run_free(&R);
    if (rc != 0)
        qtool_transfer_result_free(r), memset(r, 0, sizeof *r);
    return rc;
}

void qtool_transfer_result_free(qtool_transfer_result *r)
{
    free(r->sheet), free(r->transfer), free(r->shade);
    r->sheet = NULL, r->transfer = NULL, r->shade = NULL, r->sheet_w = r->sheet_h = 0;
}
