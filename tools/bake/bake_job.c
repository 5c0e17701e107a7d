/*
 * bake/bake_job.c - `qibl bake`'s work (bake/job.h): the shadowed sums, the unshadowed maps with the
 * light paths and lamp occlusion (or a shard's share of them beside its partial sums), --budget's
 * held-out choice of k and LUT, and the asset.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bake/bake.h"
#include "bake/extras.h"
#include "bake/job.h"
#include "bake/job_internal.h"
#include "bake/probesun.h"
#include "bake/tile.h"
#include "io/atomic.h"
#include "qibl/asset.h"
#include "qibl/lightpath.h"
#include "qtool.h"
#include "ref/psnr.h"

int qtool_bake_opts_check(const qtool_bake_opts *o, char *err, size_t errlen)
{
    uint32_t nblocks = (uint32_t)((o->ndirs + QTOOL_BAKE_BLOCK - 1) / QTOOL_BAKE_BLOCK);
    if (!o->ntiles && (o->ranges_out || o->ranges_in || o->part_out || o->cache))
        qtool_errf(err, errlen, "--ranges-out, --ranges, --part and --cache are the passes of a tile shard: give --tile "
                   "I/N");
    else if (o->ntiles && (o->out || o->sums_out || o->nshards > 1 || o->budget > 0 || o->probe))
        qtool_errf(err, errlen, "--tile writes --ranges-out FILE (pass 1) or --part FILE (pass 2), and qibl merge the "
                   "asset: no -o, --sums, --shard, --budget or --probe with it");
    else if (o->ntiles && !((o->ranges_out && !o->ranges_in && !o->part_out) ||
                            (!o->ranges_out && o->ranges_in && o->part_out)))
        qtool_errf(err, errlen, "--tile needs either --ranges-out FILE (pass 1) or --ranges FILE and --part FILE "
                   "(pass 2)");
    else if (o->ntiles > (long)o->scene.h)
        qtool_errf(err, errlen, "--tile: %ld tiles but only %u rows", o->ntiles, o->scene.h);
    else if (o->nshards > 1 && !o->sums_out)
        qtool_errf(err, errlen, "bake --shard needs --sums FILE (the partial sums for qibl merge)");
    else if (!o->out && !o->sums_out && !o->ntiles)
        qtool_errf(err, errlen, "bake needs -o ASSET (or --sums FILE, or --tile)");
    else if ((uint32_t)o->nshards > nblocks)
        qtool_errf(err, errlen, "--shard: %ld shards but only %u blocks of %u directions", o->nshards, nblocks,
                   QTOOL_BAKE_BLOCK);
    else if (o->out && o->nshards > 1)
        qtool_errf(err, errlen, "a shard writes partial sums only (--sums); qibl merge writes the asset");
    else if (o->probe && (o->nshards > 1 || o->sums_out || o->budget > 0 || o->npaths || o->has_box || o->lsq))
        qtool_errf(err, errlen, "--probe bakes its own light paths and maps (quadrature) in one job: no --shard, --sums, "
                   "--budget, --lsq, --sun-path, --lamp-track or --lamp-box with it");
    else if (o->yaw != 0 && !o->probe)
        qtool_errf(err, errlen, "--yaw turns a --probe: give --probe PROBE.hdr");
    else if (!(o->yaw >= -QTOOL_PROBESUN_YAW_MAX && o->yaw <= QTOOL_PROBESUN_YAW_MAX))
        qtool_errf(err, errlen, "--yaw: %g is outside -%.0f..%.0f degrees", o->yaw, QTOOL_PROBESUN_YAW_MAX,
                   QTOOL_PROBESUN_YAW_MAX);
    else if ((o->npaths || o->has_box) && o->uk == 0)
        qtool_errf(err, errlen, "light paths and --lamp-box need the unshadowed maps (--unshadowed-k 1..25)");
    else
        return 0;
    return 2;
}

/* ---- evaluation set ------------------------------------------------------------------------------ */

void qtool_bake_eval_lights(int obj_prop, int ndir, int npoint, qtool_rt_light *out)
{
    for (int i = 0; i < ndir; ++i) {
        double el = 0.35 + 1.0 * (i + 0.37) / ndir, az = 2.39996 * i + 0.61;
        qtool_rt_light l = {0, {cos(el) * cos(az), cos(el) * sin(az), sin(el)}, {0, 0, 0}, {2.6, 2.4, 2.1}, 1};
        out[i] = l;
    }
    for (int i = 0; i < npoint; ++i) {
        double a = 2.39996 * i + 1.1, r = 1.6 + 1.2 * ((i * 7) % 5) / 5.0;
        double cx = obj_prop ? QTOOL_RT_PROP_X : 0.0;
        qtool_rt_light l = {1, {0, 0, 1}, {cx + r * cos(a), r * sin(a), -0.6 + 0.35 * (i % 4)}, {5.0, 4.4, 3.6}, 1};
        out[ndir + i] = l;
    }
}

typedef struct {
    int n, ndir;
    qtool_rt_light *l;
    uint8_t **truth, *mask;
    size_t np;
} evalset;

static int eval_build(evalset *e, const qtool_rt_scene *s, const qtool_scene_opts *so, int ndir, int npoint)
{
    e->n = ndir + npoint, e->ndir = ndir, e->np = (size_t)so->w * so->h;
    e->l = malloc(sizeof *e->l * (size_t)e->n);
    e->truth = calloc((size_t)e->n, sizeof *e->truth);
    e->mask = malloc(e->np);
    if (!e->l || !e->truth || !e->mask)
        return -1;
    qtool_bake_eval_lights(qtool_scene_is_mesh(so) && !so->raw, ndir, npoint, e->l);
    for (int i = 0; i < e->n; ++i) {
        e->truth[i] = malloc(e->np * 3);
        if (!e->truth[i] || qtool_bake_truth8(s, so->w, so->h, (qtool_pano_kind)so->kind, &e->l[i], so->threads,
                                              e->truth[i], e->mask) != 0)
            return -1;
    }
    return 0;
}

static void eval_free(evalset *e)
{
    for (int i = 0; e->truth && i < e->n; ++i)
        free(e->truth[i]);
    free(e->truth), free(e->l), free(e->mask);
}

/* PSNR (of the mean MSE) of an asset over the directional [0, ndir) or point [ndir, n) lights */
static double eval_psnr(const evalset *e, const uint8_t *asset, size_t n, int point, int use_lut, uint8_t *tmp)
{
    double mse = 0;
    int cnt = 0;
    for (int i = point ? e->ndir : 0; i < (point ? e->n : e->ndir); ++i) {
        if (qtool_bake_relight8(asset, n, &e->l[i], use_lut, tmp, NULL) != 0)
            return -1;
        mse += qtool_bake_mse(tmp, e->truth[i], e->mask, e->np), ++cnt;
    }
    mse /= cnt ? cnt : 1;
    return qtool_ref_psnr8(mse);
}

/* ---- the asset ----------------------------------------------------------------------------------- */

int qtool_bake_finish_asset(const qtool_bake_sums *sums, uint32_t k, uint32_t lut, qtool_proj_method method,
                             uint32_t layout, const char *out, const qtool_bake_asset_extras *x, FILE *rep, char *err,
                             size_t errlen)
{
    qtool_gen_maps m;
    uint8_t *bytes = NULL;
    size_t n = 0;
    if (qtool_bake_coeffs(sums, k, method, &m) != 0) {
        if (method == QTOOL_PROJ_LSQ)
            return qtool_errf(err, errlen, "%s: cannot project by least squares: %u directions are too few for k = %u "
                              "(or out of memory)", out, sums->ndirs, k);
        return qtool_errf(err, errlen, "%s: cannot project: out of memory", out);
    }
    int rc = qtool_bake_asset_full(&m, x->mu, lut, layout, x->paths, x->sizes, &bytes, &n);
    qtool_gen_free(&m);
    if (rc == 0 && x->locc) {
        uint8_t *b2 = NULL;
        size_t n2 = 0;
        rc = qtool_bake_asset_add(bytes, n, QIBL_CHUNK_LOCC, x->locc, x->locc_n, &b2, &n2);
        free(bytes);
        bytes = b2, n = n2;
    }
    if (rc != 0)
        return qtool_errf(err, errlen, "%s: cannot build the asset (out of memory)", out);
    rc = qtool_io_write_atomic(out, bytes, n, err, errlen);
    free(bytes);
    if (rc != 0)
        return -1;
    fprintf(rep, "wrote %s: %ux%u, k = %u (%s), %u light directions, %s", out, sums->w, sums->h, k,
            method == QTOOL_PROJ_LSQ ? "least squares" : "quadrature", sums->ndirs,
            lut ? "P map and cube-map Y LUT" : "P map");
    if (x->mu)
        fprintf(rep, ", unshadowed maps k = %u", x->mu->k);
    if (x->npaths)
        fprintf(rep, ", %d light path%s", x->npaths, x->npaths > 1 ? "s" : "");
    if (x->locc)
        fprintf(rep, ", lamp occlusion");
    fprintf(rep, ", %zu bytes\n", n);
    return 0;
}

/* --progress=lines for a stage without rows (a light path, the lamp occlusion): done of total */
static void progress_line(FILE *log, const char *stage, uint32_t done, uint32_t total)
{
    fprintf(log, "progress: stage=%s done=%u total=%u fraction=%.4f\n", stage, done, total, (double)done / total);
    fflush(log);
}

static qtool_proj_method method_of(const qtool_bake_opts *o)
{
    return o->lsq ? QTOOL_PROJ_LSQ : QTOOL_PROJ_QUADRATURE;
}

/* ---- the unshadowed maps, light paths and lamp occlusion ---------------------------------------- */

/* The light paths and the lamp occlusion into x (this shard's rows). 0, or -1 with err set. */
static int bake_paths_box(const qtool_bake_opts *o, const qtool_rt_scene *s, qtool_bake_asset_extras *x, FILE *log,
                          char *err, size_t errlen)
{
    const qtool_scene_opts *so = &o->scene;
    qtool_pano_kind kind = (qtool_pano_kind)so->kind;
    /* per-pixel chunks: each shard bakes its rows (y % nshards == shard), merge joins them */
    for (int p = 0; p < o->npaths; ++p) {
        double st[2];
        x->npaths = p + 1;
        if (qtool_bake_path_chunk_shard(s, so->w, so->h, kind, &o->paths[p], (uint32_t)o->steps, 65, (uint32_t)o->shard,
                                        (uint32_t)o->nshards, so->threads, &x->paths[p], &x->sizes[p], st) != 0)
            return qtool_errf(err, errlen, "bake: out of memory (light path %d)", p + 1);
        if (!o->quiet) {
            fprintf(log, "bake: light path %d (%s): %.2f visibility edges per pixel%s%s\n", p + 1,
                    o->paths[p].kind ? "lamp track" : "sun path", st[0], o->nshards > 1 ? " (this shard's rows)" : "",
                    st[1] > 0 ? " (some pixels clipped at 255 edges)" : "");
            if (o->progress == 2)
                progress_line(log, "path", (uint32_t)p + 1, (uint32_t)o->npaths);
        }
    }
    if (o->has_box) {
        uint8_t *occ = malloc((size_t)so->w * so->h);
        int bad = !occ || qtool_bake_lamp_occlusion_shard(s, so->w, so->h, kind, o->lamp_box, (uint32_t)o->lamp_samples,
                                                          (uint32_t)o->shard, (uint32_t)o->nshards, so->threads, occ) != 0 ||
                  qtool_bake_locc_payload(so->w, so->h, occ, &x->locc, &x->locc_n) != 0;
        free(occ);
        if (bad)
            return qtool_errf(err, errlen, "bake: out of memory (lamp occlusion)");
        if (o->progress == 2)
            progress_line(log, "occlusion", 1, 1);
    }
    return 0;
}

/* A shard's extras file (SUMS.x): written also with no chunk, so a shard baked without --sun-path
 * is then refused by name at the merge instead of its rows (or the whole path) going missing */
static int write_shard_extras(const qtool_bake_opts *o, const qtool_bake_asset_extras *x, const char *path, char *err,
                              size_t errlen)
{
    qtool_extras xf;
    memset(&xf, 0, sizeof xf);
    xf.shard = (uint32_t)o->shard, xf.nshards = (uint32_t)o->nshards;
    for (int p = 0; p < x->npaths; ++p)
        xf.type[xf.count] = QIBL_CHUNK_LPTH, xf.data[xf.count] = x->paths[p], xf.size[xf.count++] = x->sizes[p];
    if (x->locc)
        xf.type[xf.count] = QIBL_CHUNK_LOCC, xf.data[xf.count] = x->locc, xf.size[xf.count++] = x->locc_n;
    return qtool_extras_write(&xf, path, err, errlen);
}

/* What the asset (or a shard) carries beside the shadowed maps. A shard (partial sums, no asset)
 * carries its share of the unshadowed sums in SUMS.u and, from every shard, its rows of the
 * per-pixel chunks in SUMS.x, so qibl merge makes the same asset as one bake. 0, or -1. */
static int bake_extras(const qtool_bake_opts *o, const qtool_rt_scene *s, qtool_gen_maps *mu, qtool_bake_asset_extras *x,
                       FILE *log, char *err, size_t errlen)
{
    const qtool_scene_opts *so = &o->scene;
    int shard_mode = !o->out && o->sums_out;
    char side[2][4200];
    if (shard_mode)
        qtool_bake_side_name(side[0], sizeof side[0], o->sums_out, "u"),
            qtool_bake_side_name(side[1], sizeof side[1], o->sums_out, "x");
    if (!(o->out || shard_mode) || o->uk <= 0) {
        if (shard_mode)
            (void)unlink(side[0]), (void)unlink(side[1]);
        return 0;
    }
    qtool_bake_sums us;
    int rc = 0;
    double t1 = qtool_bake_now();
    if (qtool_bake_run_progress(s, so->w, so->h, (qtool_pano_kind)so->kind, (uint32_t)o->ndirs, (uint32_t)o->uk,
                                (uint32_t)o->shard, (uint32_t)o->nshards, so->threads, o->progress == 2 ? 2 : 0, 1,
                                &us) != 0 ||
        (o->out && qtool_bake_coeffs(&us, (uint32_t)o->uk, method_of(o), mu) != 0))
        rc = qtool_errf(err, errlen, "bake: out of memory (unshadowed maps)");
    else if (shard_mode && qtool_bake_sums_write(&us, side[0], err, errlen) != 0)
        rc = -1;
    qtool_bake_sums_free(&us);
    x->mu = rc == 0 && o->out ? mu : NULL;
    if (rc == 0)
        rc = bake_paths_box(o, s, x, log, err, errlen);
    if (rc == 0 && shard_mode)
        rc = write_shard_extras(o, x, side[1], err, errlen);
    if (!o->quiet && rc == 0)
        fprintf(log, "bake: unshadowed maps (k = %ld) and %d light path%s: %.1f s\n", o->uk, o->npaths,
                o->npaths == 1 ? "" : "s", qtool_bake_now() - t1);
    return rc;
}

/* ---- --budget ------------------------------------------------------------------------------------ */

/* the smallest band-complete k whose novel-sun PSNR reaches the budget (25 if none): its table on
 * rep; *chosen, *reached (whether it did), *pk its PSNR. 0 or -1. */
static int budget_k(const qtool_bake_opts *o, const qtool_bake_sums *sums, const evalset *e, uint8_t *tmp, FILE *rep,
                    uint32_t *chosen, int *reached, double *pk)
{
    for (uint32_t kk = 1; kk <= 25 && !*chosen; kk = (uint32_t)((sqrt(kk) + 1) * (sqrt(kk) + 1) + 0.5)) {
        qtool_gen_maps m;
        uint8_t *b = NULL;
        size_t n = 0;
        if (qtool_bake_coeffs(sums, kk, method_of(o), &m) != 0 || qtool_bake_asset(&m, 0, &b, &n) != 0)
            return -1;
        qtool_gen_free(&m);
        *pk = eval_psnr(e, b, n, 0, 0, tmp);
        fprintf(rep, "  k = %2u: %6.2f dB %s\n", kk, *pk, *pk >= o->budget ? "<- reaches the budget" : "");
        if (*pk >= o->budget || kk == 25)
            *chosen = kk, *reached = *pk >= o->budget;
        free(b);
    }
    return 0;
}

/* LUT: the smallest face size whose point-light PSNR is within 0.1 dB of direct SH evaluation */
static uint32_t budget_lut(const qtool_bake_opts *o, const qtool_bake_sums *sums, const evalset *e, uint8_t *tmp,
                           uint32_t chosen, FILE *rep, int *lut_reached)
{
    qtool_gen_maps m;
    uint8_t *b = NULL;
    size_t n = 0;
    uint32_t chosen_lut = 0;
    qtool_bake_coeffs(sums, chosen, method_of(o), &m);
    qtool_bake_asset(&m, 0, &b, &n);
    double direct = eval_psnr(e, b, n, 1, 0, tmp);
    free(b);
    fprintf(rep, "point lights (4 lamps), k = %u: direct SH evaluation %.2f dB; cube-map LUT face size:\n", chosen,
            direct);
    for (uint32_t f = 8; f <= 128; f *= 2) {
        qtool_bake_asset(&m, f, &b, &n);
        double p = eval_psnr(e, b, n, 1, 1, tmp);
        free(b);
        fprintf(rep, "  %3u^2: %6.2f dB%s\n", f, p, p >= direct - 0.1 ? " <- within 0.1 dB of direct evaluation" : "");
        if (p >= direct - 0.1 || f == 128) {
            chosen_lut = f, *lut_reached = p >= direct - 0.1;
            break;
        }
    }
    qtool_gen_free(&m);
    return chosen_lut;
}

/* --budget: smallest band-complete k (and LUT) whose held-out PSNR reaches the budget, then the asset */
static int bake_budget(const qtool_bake_opts *o, const qtool_rt_scene *s, const qtool_bake_sums *sums,
                       const qtool_bake_asset_extras *x, FILE *rep, char *err, size_t errlen)
{
    evalset e = {0};
    uint8_t *tmp = malloc(sums->w * (size_t)sums->h * 3);
    uint32_t chosen = 0, chosen_lut = 0;
    int reached = 0, lut_reached = 0; /* whether the chosen k (LUT) met its target, for the summary */
    double pk = 0;
    int rc = 0;
    if (!tmp || eval_build(&e, s, &o->scene, 8, 4) != 0)
        rc = qtool_errf(err, errlen, "bake: out of memory");
    fprintf(rep, "budget %.2f dB: PSNR of the core's relit frames against ground truth, 8 novel suns (mean MSE):\n",
            o->budget);
    if (rc == 0 && budget_k(o, sums, &e, tmp, rep, &chosen, &reached, &pk) != 0)
        rc = -1; /* as before the move: no message of its own */
    if (rc == 0) {
        if (pk < o->budget)
            fprintf(rep, "  no k <= 25 reaches %.2f dB; using k = 25 (more directions or a smoother scene would be "
                    "needed)\n", o->budget);
        chosen_lut = budget_lut(o, sums, &e, tmp, chosen, rep, &lut_reached);
        /* one summary that agrees with the table above: the k line says "reaches" only if it did */
        if (reached)
            fprintf(rep, "chose k = %u: the smallest k whose novel-sun PSNR reaches %.2f dB", chosen, o->budget);
        else
            fprintf(rep, "chose k = %u: the largest k, since none reaches %.2f dB (best %.2f dB)", chosen, o->budget,
                    pk);
        if (lut_reached)
            fprintf(rep, "; a %u^2 LUT: the smallest that costs point lights under 0.1 dB against evaluating the SH "
                    "polynomials per pixel\n", chosen_lut);
        else
            fprintf(rep, "; a %u^2 LUT: the largest tried, none within 0.1 dB of evaluating the SH polynomials per "
                    "pixel\n", chosen_lut);
        rc = qtool_bake_finish_asset(sums, chosen, chosen_lut, method_of(o), o->layout, o->out, x, rep, err, errlen);
    }
    eval_free(&e);
    free(tmp);
    return rc;
}

/* ---- the job ------------------------------------------------------------------------------------- */

static int bake_outputs(const qtool_bake_opts *o, const qtool_rt_scene *s, const qtool_bake_sums *sums,
                        const qtool_bake_asset_extras *x, FILE *rep, char *err, size_t errlen)
{
    if (o->sums_out) { /* "wrote" only for sums that were written (not after a failure) */
        if (qtool_bake_sums_write(sums, o->sums_out, err, errlen) != 0)
            return -1;
        fprintf(rep, "wrote %s: partial sums of shard %ld/%ld\n", o->sums_out, o->shard, o->nshards);
    }
    if (o->out && o->budget > 0)
        return bake_budget(o, s, sums, x, rep, err, errlen);
    if (o->out)
        return qtool_bake_finish_asset(sums, (uint32_t)o->k, (uint32_t)o->lut, method_of(o), o->layout, o->out, x, rep,
                                        err, errlen);
    return 0;
}

/* --probe: the probe read and its sources found before the bake (a probe without one is refused
 * first), the shadowed sums for the sky's k, then bake/probesun.h's asset */
static int bake_probe_job(const qtool_bake_opts *o, FILE *out, FILE *log, char *err, size_t errlen)
{
    const qtool_scene_opts *so = &o->scene;
    qtool_probesun ps;
    if (qtool_probesun_load(o->probe, o->yaw, QTOOL_PROBESUN_MAX_PARTS, &ps, err, errlen) != 0)
        return -1;
    int rc = -1;
    qtool_rt_scene s;
    qtool_bake_sums sums;
    if (ps.nsrc == 0) {
        rc = qtool_probesun_bake(NULL, 0, 0, 0, 1, NULL, 0, 0, 0, &ps, o->out, out, err, errlen);
    } else if (qtool_scene_load(so, &s, err, errlen) == 0) {
        double t0 = qtool_bake_now();
        if (qtool_bake_run_progress(&s, so->w, so->h, (qtool_pano_kind)so->kind, (uint32_t)o->ndirs,
                                    QTOOL_PROBESUN_SHADOWED_K, 0, 1, so->threads, o->progress, 0, &sums) != 0) {
            qtool_errf(err, errlen, "bake: out of memory");
        } else {
            if (!o->quiet)
                fprintf(log, "bake: %ux%u, %ld directions, %zu triangles, %.1f s on %d threads\n", so->w, so->h,
                        o->ndirs, s.ntri, qtool_bake_now() - t0, so->threads);
            rc = qtool_probesun_bake(&s, so->w, so->h, (qtool_pano_kind)so->kind, so->threads, &sums,
                                     (uint32_t)o->ndirs, (uint32_t)o->lut, o->layout, &ps, o->out, out, err, errlen);
            qtool_bake_sums_free(&sums);
        }
        qtool_rt_scene_free(&s);
    }
    qtool_probesun_free(&ps);
    return rc;
}

int qtool_bake_job(const qtool_bake_opts *o, FILE *out, FILE *log, char *err, size_t errlen)
{
    const qtool_scene_opts *so = &o->scene;
    if (o->probe)
        return bake_probe_job(o, out, log, err, errlen);
    if (o->ntiles)
        return qtool_tile_bake(o, out, log, err, errlen);
    qtool_rt_scene s;
    if (qtool_scene_load(so, &s, err, errlen) != 0)
        return -1;
    qtool_bake_sums sums;
    double t0 = qtool_bake_now();
    uint32_t kacc = o->budget > 0 ? 25 : (uint32_t)o->k;
    if (qtool_bake_run_progress(&s, so->w, so->h, (qtool_pano_kind)so->kind, (uint32_t)o->ndirs, kacc, (uint32_t)o->shard,
                                (uint32_t)o->nshards, so->threads, o->progress, 0, &sums) != 0) {
        qtool_rt_scene_free(&s);
        return qtool_errf(err, errlen, "bake: out of memory");
    }
    double secs = qtool_bake_now() - t0;
    if (!o->quiet)
        fprintf(log, "bake: %ux%u, %ld directions%s, %zu triangles, %.1f s on %d threads\n", so->w, so->h, o->ndirs,
                o->nshards > 1 ? " (this shard's share)" : "", s.ntri, secs, so->threads);
    /* the unshadowed maps and the light paths, for the asset (shards carry the shadowed sums only) */
    qtool_bake_asset_extras x;
    qtool_gen_maps mu = {0};
    memset(&x, 0, sizeof x);
    int rc = bake_extras(o, &s, &mu, &x, log, err, errlen);
    if (rc == 0)
        rc = bake_outputs(o, &s, &sums, &x, out, err, errlen);
    for (int p = 0; p < QTOOL_BAKE_JOB_MAX_PATHS; ++p)
        free(x.paths[p]);
    free(x.locc);
    qtool_gen_free(&mu);
    qtool_bake_sums_free(&sums);
    qtool_rt_scene_free(&s);
    return rc;
}

void qtool_bake_side_name(char *buf, size_t n, const char *sums, const char *ext)
{
    snprintf(buf, n, "%s.%s", sums, ext);
}
