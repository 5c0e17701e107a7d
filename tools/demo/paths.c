/*
 * demo/paths.c - the light-path part of `qibl demo`: a sun path and a lamp track baked as per-pixel
 * visibility (LPTH) beside the unshadowed maps (SHMU), relit by the core at 16 positions between
 * the baked steps and compared with the ray-traced truth next to today's shadowed SH.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/bake.h"
#include "bake/path.h"
#include "bake/tiled.h"
#include "demo/demo.h"
#include "io/text.h"
#include "qibl/asset.h"
#include "qibl/lightpath.h"
#include "qibl/shmtile.h"
#include "qtool.h"
#include "ref/psnr.h"
#include "render/rt.h"

enum { NPOS = 16, NCLS = 4, NROWS = 9, NDROP = 3, NSOFT = 4, NDISC = 8 };

typedef struct {
    const char *name;
    double bytes_px, ms, psnr, psnr_cls[NCLS], share_cls[NCLS], bright, excess_cls[NCLS];
} row_stats;

typedef struct {
    double se_cls[NCLS], n_cls[NCLS], ms[NPOS], lr_cls[NCLS], lt_cls[NCLS];
    int frames;
} acc_t;

/* rows: 0 today sun, 1 path k9, 2 path k16, 3 today lamp, 4 free lamp k9, 5 free lamp k16 (both with the
 * lamp occlusion), 6 track k9, 7 track k16, 8 free lamp k9 without the occlusion */
static const char *const row_names[NROWS] = {
    "sun: today, shadowed SH k16",        "sun: unshadowed k9 x path visibility",
    "sun: unshadowed k16 x path visibility", "lamp: today, shadowed SH k16 (LUT)",
    "lamp: free, unshadowed k9 x occlusion (LUT)", "lamp: free, unshadowed k16 x occlusion (LUT)",
    "lamp: unshadowed k9 x track visibility", "lamp: unshadowed k16 x track visibility",
    "lamp: free, unshadowed k9, no occlusion"};
/* the adaptive-k rows: the energy share each tile may drop */
static const double drops[NDROP] = {0.003, 0.01, 0.03};
static const double sky_rgb[3] = {0.25, 0.32, 0.45};

/* What the part bakes, measures and prints; every pointer owned (freed by ctx_free). */
typedef struct {
    const qtool_demo_view *v;
    const qtool_demo_size *sz;
    const qtool_bake_sums *sums_shadowed; /* the main bake's, for the shadowed k16 maps */
    const uint8_t *today;
    size_t today_n, np;
    char *err;
    size_t errlen;
    double lut[256], bake_s;
    qtool_bake_path sun, track;
    qtool_bake_sums us;
    qtool_gen_maps msh, mu9, mu16;
    uint8_t *lp[3], *asset9, *asset16, *asset9o, *asset16o, *occv;
    size_t lpn[2], n9, n16, n9o, n16o, occn;
    uint8_t *truth, *cls, *tmp, *keep[4];
    double st_sun[2], st_trk[2];
    qtool_rt_light L[2][NPOS];
    uint32_t tq[NPOS];
    qibl_status_t st;
    /* results */
    double shmp, pmap, ylut, u9, u16, sky_noise, ad_bytes[NDROP];
    uint32_t ad_tiles[NDROP][26];
    char ad_names[NDROP][2][64];
    row_stats rs[NROWS], ad_rs[NDROP][2], sky_rs[2], soft_rs[3];
} paths_ctx;

static void acc_frame(acc_t *a, const uint8_t *relit, const uint8_t *truth, const uint8_t *cls, size_t np, double ms,
                      const double *lut)
{
    for (size_t i = 0; i < np; ++i) {
        if (!cls[i])
            continue;
        for (int c = 0; c < 3; ++c) {
            double d = (double)relit[3 * i + (size_t)c] - truth[3 * i + (size_t)c];
            a->se_cls[cls[i]] += d * d;
            a->lr_cls[cls[i]] += lut[relit[3 * i + (size_t)c]];
            a->lt_cls[cls[i]] += lut[truth[3 * i + (size_t)c]];
        }
        a->n_cls[cls[i]] += 3;
    }
    a->ms[a->frames++] = ms;
}

static void finish(const acc_t *a, const char *name, double bytes_px, row_stats *r)
{
    double se = 0, n = 0;
    memset(r, 0, sizeof *r);
    for (int c = 1; c < NCLS; ++c)
        se += a->se_cls[c], n += a->n_cls[c];
    r->name = name, r->bytes_px = bytes_px;
    r->psnr = qtool_ref_psnr8(n > 0 ? se / n : 0);
    for (int c = 1; c < NCLS; ++c) {
        r->psnr_cls[c] = a->n_cls[c] > 0 ? qtool_ref_psnr8(a->se_cls[c] / a->n_cls[c]) : 0;
        r->share_cls[c] = se > 0 ? 100 * a->se_cls[c] / se : 0;
    }
    double lr = 0, lt = 0;
    for (int c = 1; c < NCLS; ++c)
        lr += a->lr_cls[c], lt += a->lt_cls[c];
    r->bright = lt > 0 ? lr / lt : 0;
    /* where the brightness error sits: each class's (relit - truth) as a share of the truth's total */
    for (int c = 1; c < NCLS; ++c)
        r->excess_cls[c] = lt > 0 ? (a->lr_cls[c] - a->lt_cls[c]) / lt : 0;
    double ms[NPOS];
    memcpy(ms, a->ms, sizeof(double) * (size_t)a->frames);
    r->ms = qtool_demo_median(ms, a->frames);
}

static void print_row(FILE *o, const row_stats *r)
{
    fprintf(o, "| %-44s | %8.1f | %8.3f | %7.2f | %6.2f (%4.1f%%) | %6.2f (%4.1f%%) | %6.2f (%4.1f%%) | %5.3f |\n", r->name,
            r->bytes_px, r->ms, r->psnr, r->psnr_cls[1], r->share_cls[1], r->psnr_cls[2], r->share_cls[2],
            r->psnr_cls[3], r->share_cls[3], r->bright);
}

/* the brightness error split by pixel class: (relit - truth) per class over the truth's whole sum */
static void print_split(FILE *o, const row_stats *r)
{
    fprintf(o, "| %-44s | %5.3f | %+7.4f | %+7.4f | %+7.4f |\n", r->name, r->bright, r->excess_cls[1], r->excess_cls[2],
            r->excess_cls[3]);
}

/* the paths: a summer day at 40 N from 7 to 17 h; a lamp carried round the courtyard */
static void define_paths(paths_ctx *c)
{
    qtool_bake_path *sun = &c->sun, *track = &c->track;
    sun->kind = 0, sun->lat = 40, sun->decl = 15, sun->t0 = 7, sun->t1 = 17;
    sun->rgb[0] = 2.6, sun->rgb[1] = 2.4, sun->rgb[2] = 2.1;
    track->kind = 1, track->npts = 9;
    double cx = c->v->prop ? QTOOL_RT_PROP_X : 0.0, rr = c->v->prop ? 2.2 : 2.8;
    for (int i = 0; i < track->npts; ++i) {
        double a = 2 * QTOOL_DEMO_PI15 * i / (track->npts - 1) + 0.3;
        track->pts[i][0] = cx + rr * cos(a), track->pts[i][1] = rr * sin(a), track->pts[i][2] = -0.5 + 0.4 * sin(2 * a);
    }
    track->rgb[0] = 5.0, track->rgb[1] = 4.4, track->rgb[2] = 3.6;
}

/* the unshadowed maps, both paths' visibility and the k9 / k16 assets with them */
static int bake_paths(paths_ctx *c, uint32_t ndirs)
{
    const qtool_demo_view *v = c->v;
    size_t np = c->np;
    uint32_t steps = c->sz->path_steps;
    c->occv = malloc(np);
    c->truth = malloc(np * 3 * NPOS * 2), c->cls = malloc(np * NPOS * 2), c->tmp = malloc(np * 3);
    for (int i = 0; i < 4; ++i)
        c->keep[i] = malloc(np * 3);
    if (!c->occv || !c->truth || !c->cls || !c->tmp || !c->keep[0] || !c->keep[1] || !c->keep[2] || !c->keep[3] ||
        qtool_bake_run_unshadowed(v->scene, v->w, v->h, v->kind, ndirs, 16, v->threads, &c->us) != 0 ||
        qtool_bake_coeffs(c->sums_shadowed, 16, QTOOL_PROJ_QUADRATURE, &c->msh) != 0 ||
        qtool_bake_coeffs(&c->us, 9, QTOOL_PROJ_QUADRATURE, &c->mu9) != 0 ||
        qtool_bake_coeffs(&c->us, 16, QTOOL_PROJ_QUADRATURE, &c->mu16) != 0 ||
        qtool_bake_path_chunk(v->scene, v->w, v->h, v->kind, &c->sun, steps, 65, v->threads, &c->lp[0], &c->lpn[0],
                              c->st_sun) != 0 ||
        qtool_bake_path_chunk(v->scene, v->w, v->h, v->kind, &c->track, steps, 65, v->threads, &c->lp[1], &c->lpn[1],
                              c->st_trk) != 0 ||
        qtool_bake_asset_ex(&c->msh, &c->mu9, 32, c->lp, c->lpn, &c->asset9, &c->n9) != 0 ||
        qtool_bake_asset_ex(&c->msh, &c->mu16, 32, c->lp, c->lpn, &c->asset16, &c->n16) != 0)
        return qtool_errf(c->err, c->errlen, "demo: out of memory (light paths)");
    return 0;
}

/* lamp occlusion for free lamps: the region lamps move in is the track's bounding box grown by
 * half a unit (a designer's box, not the track: the 16 free positions are not sampled) */
static int lamp_occlusion(paths_ctx *c)
{
    const qtool_demo_view *v = c->v;
    uint8_t *occp = NULL;
    double box[6] = {1e30, 1e30, 1e30, -1e30, -1e30, -1e30};
    for (int i = 0; i < c->track.npts; ++i)
        for (int k = 0; k < 3; ++k)
            box[k] = fmin(box[k], c->track.pts[i][k] - 0.5), box[3 + k] = fmax(box[3 + k], c->track.pts[i][k] + 0.5);
    int bad = qtool_bake_lamp_occlusion(v->scene, v->w, v->h, v->kind, box, 64, v->threads, c->occv) != 0 ||
              qtool_bake_locc_payload(v->w, v->h, c->occv, &occp, &c->occn) != 0 ||
              qtool_bake_asset_add(c->asset9, c->n9, QIBL_CHUNK_LOCC, occp, c->occn, &c->asset9o, &c->n9o) != 0 ||
              qtool_bake_asset_add(c->asset16, c->n16, QIBL_CHUNK_LOCC, occp, c->occn, &c->asset16o, &c->n16o) != 0;
    free(occp);
    return bad ? qtool_errf(c->err, c->errlen, "demo: out of memory (lamp occlusion)") : 0;
}

/* 16 positions on each path, between the baked steps; truth and pixel classes once */
static int path_truths(paths_ctx *c)
{
    const qtool_demo_view *v = c->v;
    size_t np = c->np;
    for (int i = 0; i < NPOS; ++i) {
        c->tq[i] = (uint32_t)lrint(65535.0 * (i + 0.37) / NPOS);
        qtool_bake_path_light(&c->sun, c->tq[i] / 65535.0, &c->L[0][i]);
        qtool_bake_path_light(&c->track, c->tq[i] / 65535.0, &c->L[1][i]);
        for (int p = 0; p < 2; ++p) {
            size_t f = (size_t)p * NPOS + (size_t)i;
            if (qtool_bake_truth8(v->scene, v->w, v->h, v->kind, &c->L[p][i], v->threads, c->truth + f * np * 3, NULL) != 0 ||
                qtool_rt_classify(v->scene, v->w, v->h, v->kind, &c->L[p][i], v->threads, c->cls + f * np) != 0)
                return qtool_errf(c->err, c->errlen, "demo: out of memory (light-path truth)");
        }
    }
    return 0;
}

/* row r's frame at position i into c->tmp */
static int relight_row(paths_ctx *c, int r, int p, int i, double *ms)
{
    const uint8_t *as = (r == 2 || r == 5 || r == 7) ? c->asset16 : c->asset9;
    size_t an = (r == 2 || r == 5 || r == 7) ? c->n16 : c->n9;
    const qtool_rt_light *l = &c->L[p][i];
    if (r == 0 || r == 3)
        return qtool_bake_relight8_lin(c->today, c->today_n, l, 1, 0, 1, c->tmp, NULL, ms, &c->st);
    if (r == 4 || r == 5) /* a free point light: qibl_asset_point_shmaps picks SHMU */
        return qtool_bake_relight8_lin(r == 4 ? c->asset9o : c->asset16o, r == 4 ? c->n9o : c->n16o, l, 1, 0, 1, c->tmp,
                                       NULL, ms, &c->st);
    if (r == 8) /* the same asset without the lamp occlusion */
        return qtool_bake_relight8_lin(c->asset9, c->n9, l, 1, 0, 1, c->tmp, NULL, ms, &c->st);
    return qtool_bake_relight_path8(as, an, l, (uint32_t)p, c->tq[i], 0, NULL, c->tmp, NULL, ms, &c->st);
}

static int score_rows(paths_ctx *c)
{
    size_t np = c->np;
    acc_t acc[NROWS];
    memset(acc, 0, sizeof acc);
    for (int r = 0; r < NROWS; ++r) {
        int p = r < 3 ? 0 : 1;
        for (int i = 0; i < NPOS; ++i) {
            size_t f = (size_t)p * NPOS + (size_t)i;
            double ms = 0;
            if (relight_row(c, r, p, i, &ms) != 0)
                return qtool_errf(c->err, c->errlen, "demo: relight (%s) failed: %s", row_names[r], qibl_status_str(c->st));
            acc_frame(&acc[r], c->tmp, c->truth + f * np * 3, c->cls + f * np, np, ms, c->lut);
            if (i == 5 && (r == 0 || r == 1 || r == 3 || r == 6))
                memcpy(c->keep[r == 0 ? 0 : r == 1 ? 1 : r == 3 ? 2 : 3], c->tmp, np * 3);
        }
    }
    /* bytes per pixel of what each scheme reads (fixed-size YLUT included, spread over the pixels) */
    c->shmp = qtool_demo_chunk_bytes(c->today, c->today_n, QIBL_CHUNK_SHMP, 0);
    c->pmap = qtool_demo_chunk_bytes(c->asset9, c->n9, QIBL_CHUNK_PMAP, 0);
    c->ylut = qtool_demo_chunk_bytes(c->today, c->today_n, QIBL_CHUNK_YLUT, 0);
    c->u9 = qtool_demo_chunk_bytes(c->asset9, c->n9, QIBL_CHUNK_SHMU, 0);
    c->u16 = qtool_demo_chunk_bytes(c->asset16, c->n16, QIBL_CHUNK_SHMU, 0);
    double shmp = c->shmp, pmap = c->pmap, ylut = c->ylut, u9 = c->u9, u16 = c->u16, oc = (double)c->occn;
    double l0 = (double)c->lpn[0], l1 = (double)c->lpn[1];
    double bytes[NROWS] = {shmp, u9 + l0, u16 + l0, shmp + pmap + ylut, u9 + pmap + ylut + oc,
                           u16 + pmap + ylut + oc, u9 + pmap + ylut + l1, u16 + pmap + ylut + l1,
                           u9 + pmap + ylut};
    for (int r = 0; r < NROWS; ++r)
        finish(&acc[r], row_names[r], bytes[r] / (double)np, &c->rs[r]);
    return 0;
}

/* the asset of drop share d: shadowed k16 and both paths, the SHMT chunk, the lamp occlusion */
static int adaptive_asset(paths_ctx *c, int d, uint8_t **ad2, size_t *ad2n)
{
    uint8_t *pay = NULL, *base = NULL, *ad = NULL, *occp = NULL;
    size_t payn = 0, basen = 0, adn = 0, occn = 0;
    int bad = qtool_bake_shmt_payload(&c->mu16, drops[d], &pay, &payn, c->ad_tiles[d]) != 0 ||
              qtool_bake_asset_ex(&c->msh, NULL, 32, c->lp, c->lpn, &base, &basen) != 0 ||
              qtool_bake_asset_add(base, basen, QIBL_CHUNK_SHMT, pay, payn, &ad, &adn) != 0 ||
              qtool_bake_locc_payload(c->v->w, c->v->h, c->occv, &occp, &occn) != 0 ||
              qtool_bake_asset_add(ad, adn, QIBL_CHUNK_LOCC, occp, occn, ad2, ad2n) != 0;
    c->ad_bytes[d] = (double)payn;
    free(pay), free(base), free(ad), free(occp);
    return bad ? qtool_errf(c->err, c->errlen, "demo: adaptive k failed (out of memory)") : 0;
}

/* per-tile adaptive k for the unshadowed maps (SHMT, qibl/shmtile.h): each 16x16 tile keeps the
 * fewest band-complete k of the k16 set whose dropped coefficients hold at most `drop` of the
 * tile's energy; relit through the core kernels tile by tile. Bytes are the SHMT chunk's. */
static int score_adaptive(paths_ctx *c)
{
    size_t np = c->np;
    for (int d = 0; d < NDROP; ++d) {
        acc_t acc[2];
        memset(acc, 0, sizeof acc);
        uint8_t *ad2 = NULL;
        size_t ad2n = 0;
        if (adaptive_asset(c, d, &ad2, &ad2n) != 0) {
            free(ad2);
            return -1;
        }
        int bad = 0;
        for (int p = 0; !bad && p < 2; ++p)
            for (int i = 0; !bad && i < NPOS; ++i) {
                size_t f = (size_t)p * NPOS + (size_t)i;
                double ms = 0;
                bad = qtool_bake_relight_tiled8(ad2, ad2n, &c->L[p][i], p, c->tq[i], 0, c->tmp, &ms, &c->st) != 0;
                if (!bad)
                    acc_frame(&acc[p], c->tmp, c->truth + f * np * 3, c->cls + f * np, np, ms, c->lut);
            }
        free(ad2);
        if (bad)
            return qtool_errf(c->err, c->errlen, "demo: adaptive k failed (%s)", qibl_status_str(c->st));
        snprintf(c->ad_names[d][0], sizeof c->ad_names[d][0], "sun: SHMT adaptive k (drop %.1f%%) x path", 100 * drops[d]);
        snprintf(c->ad_names[d][1], sizeof c->ad_names[d][1], "lamp: SHMT adaptive k (drop %.1f%%) x track",
                 100 * drops[d]);
        finish(&acc[0], c->ad_names[d][0], (c->ad_bytes[d] + (double)c->lpn[0]) / (double)np, &c->ad_rs[d][0]);
        finish(&acc[1], c->ad_names[d][1], (c->ad_bytes[d] + c->pmap + c->ylut + (double)c->lpn[1]) / (double)np,
               &c->ad_rs[d][1]);
    }
    return 0;
}

/* the sky + sun frame at position i: the truth t8 (sun render + the sky's mean), then today (sky and
 * sun in one SH light through the shadowed maps, into acc[0]) and the hybrid (acc[1]) */
static int sky_sun_frame(paths_ctx *c, int i, const double *ha, const double *hb, double *lin, uint8_t *t8,
                         const qibl_shlight_t *skysh, acc_t acc[2])
{
    const qtool_demo_view *v = c->v;
    size_t np = c->np;
    const qtool_rt_light *l = &c->L[0][i];
    if (qtool_rt_render(v->scene, v->w, v->h, v->kind, l, v->threads, lin, NULL, NULL) != 0)
        return -1;
    for (size_t q = 0; q < np * 3; ++q)
        lin[q] += 0.5 * (ha[q] + hb[q]);
    qtool_bake_lin_to8(lin, v->w, v->h, t8);
    qibl_shlight_t both = *skysh;
    qibl_q16_t dq[3], rq[3];
    for (int k = 0; k < 3; ++k)
        dq[k] = (qibl_q16_t)lrint(l->dir[k] * 65536), rq[k] = (qibl_q16_t)lrint(l->rgb[k] * 65536);
    double ms = 0;
    c->st = qibl_shlight_add_dir(&both, dq, rq);
    if (c->st != QIBL_OK || qtool_bake_relight_env8(c->today, c->today_n, &both, c->tmp, &ms, &c->st) != 0)
        return -1;
    acc_frame(&acc[0], c->tmp, t8, c->cls + (size_t)i * np, np, ms, c->lut);
    if (qtool_bake_relight_path8(c->asset9, c->n9, l, 0, c->tq[i], 0, skysh, c->tmp, NULL, &ms, &c->st) != 0)
        return -1;
    acc_frame(&acc[1], c->tmp, t8, c->cls + (size_t)i * np, np, ms, c->lut);
    return 0;
}

/* sky + sun: the sky ray-traced once (two half estimates: their agreement states its noise), the sun
 * at the 16 positions; today's SH with sky and sun in one light against the hybrid */
static int score_sky(paths_ctx *c)
{
    const qtool_demo_view *v = c->v;
    size_t np = c->np;
    acc_t acc[2];
    memset(acc, 0, sizeof acc);
    double *ha = malloc(np * 3 * sizeof(double)), *hb = malloc(np * 3 * sizeof(double));
    double *lin = malloc(np * 3 * sizeof(double));
    uint8_t *t8 = malloc(np * 3), *u8 = malloc(np * 3);
    int bad = !ha || !hb || !lin || !t8 || !u8 ||
              qtool_bake_sky_truth(v->scene, v->w, v->h, v->kind, sky_rgb, c->sz->sky_dirs, v->threads, ha, hb) != 0;
    if (!bad) {
        qtool_bake_lin_to8(ha, v->w, v->h, t8);
        qtool_bake_lin_to8(hb, v->w, v->h, u8);
        c->sky_noise = qtool_ref_psnr8(qtool_bake_mse(t8, u8, c->cls, np)); /* class 0 = sky pixels left out */
    }
    qibl_shlight_t skysh;
    qtool_bake_sky_sh(sky_rgb, 16, &skysh);
    for (int i = 0; !bad && i < NPOS; ++i)
        bad = sky_sun_frame(c, i, ha, hb, lin, t8, &skysh, acc) != 0;
    free(ha), free(hb), free(lin), free(t8), free(u8);
    if (bad)
        return qtool_errf(c->err, c->errlen, "demo: sky + sun failed (%s)", qibl_status_str(c->st));
    double px = (double)np;
    finish(&acc[0], "sky + sun: today, one SH light, shadowed k16", c->shmp / px, &c->sky_rs[0]);
    finish(&acc[1], "sky + sun: sky SH k16 + sun k9 x path", (c->shmp + c->u9 + (double)c->lpn[0]) / px, &c->sky_rs[1]);
    return 0;
}

/* the truth of the soft sun at position i: the mean of NDISC renders over the disc, into lin */
static int soft_truth(paths_ctx *c, int i, double alpha, double *lin, double *one)
{
    const qtool_demo_view *v = c->v;
    size_t np = c->np;
    const double *s = c->L[0][i].dir;
    /* an orthonormal frame around the sun's direction */
    double a[3] = {-s[1], s[0], 0}, la = sqrt(a[0] * a[0] + a[1] * a[1]);
    for (int k = 0; k < 3; ++k)
        a[k] /= la > 0 ? la : 1;
    double b[3] = {s[1] * a[2] - s[2] * a[1], s[2] * a[0] - s[0] * a[2], s[0] * a[1] - s[1] * a[0]};
    memset(lin, 0, np * 3 * sizeof(double));
    for (int d = 0; d < NDISC; ++d) { /* sunflower points over the disc */
        double r = alpha * sqrt((d + 0.5) / NDISC), ph = d * 2.39996323;
        qtool_rt_light dl = c->L[0][i];
        for (int k = 0; k < 3; ++k)
            dl.dir[k] = s[k] + r * (cos(ph) * a[k] + sin(ph) * b[k]);
        if (qtool_rt_render(v->scene, v->w, v->h, v->kind, &dl, v->threads, one, NULL, NULL) != 0)
            return -1;
        for (size_t z = 0; z < np * 3; ++z)
            lin[z] += one[z] / NDISC;
    }
    return 0;
}

/* the disc's radius in path units at position i: alpha over the sun's angle per step of t */
static uint32_t soft_radius(const paths_ctx *c, int i, double alpha)
{
    const double *s = c->L[0][i].dir;
    qtool_rt_light nx;
    qtool_bake_path_light(&c->sun, (c->tq[i] + 1) / 65535.0, &nx);
    double dot = 0, l0 = 0, l1 = 0;
    for (int k = 0; k < 3; ++k)
        dot += s[k] * nx.dir[k], l0 += s[k] * s[k], l1 += nx.dir[k] * nx.dir[k];
    double step = acos(fmin(1.0, dot / sqrt(l0 * l1)));
    return step > 0 ? (uint32_t)fmin(32767, lrint(alpha / step)) : 0;
}

/* soft sun: a disc of angular radius 1.5 degrees (three times the real sun's, so the penumbrae show
 * at this resolution); truth = mean of 8 renders over the disc; the runtime filters V along the path
 * over the disc's extent in t (the disc's width across the path is not modelled) */
static int score_soft(paths_ctx *c)
{
    size_t np = c->np;
    const double alpha = 1.5 * QTOOL_DEMO_PI15 / 180;
    acc_t soft[3];
    memset(soft, 0, sizeof soft);
    double *lin = malloc(np * 3 * sizeof(double)), *one = malloc(np * 3 * sizeof(double));
    uint8_t *t8 = malloc(np * 3);
    int bad = !lin || !one || !t8;
    for (int q = 0; !bad && q < NSOFT; ++q) {
        int i = 2 + 4 * q;
        if (soft_truth(c, i, alpha, lin, one) != 0) {
            bad = 1;
            break;
        }
        qtool_bake_lin_to8(lin, c->v->w, c->v->h, t8);
        uint32_t rad = soft_radius(c, i, alpha);
        double ms = 0;
        const uint8_t *cl = c->cls + (size_t)i * np;
        if (qtool_bake_relight8_lin(c->today, c->today_n, &c->L[0][i], 1, 0, 1, c->tmp, NULL, &ms, &c->st) != 0)
            bad = 1;
        else
            acc_frame(&soft[0], c->tmp, t8, cl, np, ms, c->lut);
        for (int v = 0; !bad && v < 2; ++v) {
            if (qtool_bake_relight_path8(c->asset9, c->n9, &c->L[0][i], 0, c->tq[i], v ? rad : 0, NULL, c->tmp, NULL, &ms,
                                         &c->st) != 0)
                bad = 1;
            else
                acc_frame(&soft[1 + v], c->tmp, t8, cl, np, ms, c->lut);
        }
    }
    free(lin), free(one), free(t8);
    if (bad)
        return qtool_errf(c->err, c->errlen, "demo: soft sun failed (%s)", qibl_status_str(c->st));
    double px = (double)np, path9 = c->u9 + (double)c->lpn[0];
    finish(&soft[0], "soft sun: today, shadowed SH k16", c->shmp / px, &c->soft_rs[0]);
    finish(&soft[1], "soft sun: k9 x path, hard edges", path9 / px, &c->soft_rs[1]);
    finish(&soft[2], "soft sun: k9 x path, filtered along the path", path9 / px, &c->soft_rs[2]);
    return 0;
}

/* contact sheet: truth | today | path shadows | error of the path frame, one sun and one lamp row,
 * each under a label strip; then the README picture: truth, today, path shadows of the same sun,
 * one above the other */
static int sheets(paths_ctx *c)
{
    static const char *cols[4] = {"truth: ray-traced", "today: shadowed SH k16", "SHMU k9 x path visibility",
                                  "error, 0 .. 48+ of 255"};
    static const uint8_t fg[3] = {235, 235, 235};
    uint32_t w = c->v->w, h = c->v->h;
    size_t np = c->np;
    int ts = w >= 512 ? 2 : 1, strip = (QTOOL_TEXT_HEIGHT + 3) * ts;
    size_t shh = 2 * ((size_t)h + (size_t)strip), sw = (size_t)w * 4;
    uint8_t *sheet = malloc(sw * 3 * shh), *hb = malloc(np * 3);
    int rc = !sheet || !hb ? qtool_errf(c->err, c->errlen, "demo: out of memory") : 0;
    if (rc == 0)
        memset(sheet, 24, sw * 3 * shh);
    for (int r = 0; rc == 0 && r < 2; ++r) {
        size_t f = (size_t)r * NPOS + 5, y0 = (size_t)r * (h + (size_t)strip);
        qtool_demo_heat(c->keep[2 * r + 1], c->truth + f * np * 3, c->cls + f * np, np, hb);
        const uint8_t *src[4] = {c->truth + f * np * 3, c->keep[2 * r], c->keep[2 * r + 1], hb};
        for (int col = 0; col < 4; ++col) {
            char lab[96];
            snprintf(lab, sizeof lab, "%s: %s", r ? "lamp" : "sun", cols[col]);
            qtool_text_draw(sheet, (int)sw, (int)shh, col * (int)w + 4, (int)y0 + ts, lab, ts, fg);
            qtool_demo_blit(sheet, sw, (size_t)col * w, y0 + (size_t)strip, src[col], w, h);
        }
    }
    if (rc == 0)
        rc = qtool_demo_save_png(c->v->dir, "paths_sheet.png", (int)sw, (int)shh, sheet, c->err, c->errlen);
    if (rc == 0) {
        const uint8_t *src[3] = {c->truth + 5 * np * 3, c->keep[0], c->keep[1]};
        for (int r = 0; r < 3; ++r)
            memcpy(sheet + (size_t)r * np * 3, src[r], np * 3);
        rc = qtool_demo_save_png(c->v->dir, "paths_readme.png", (int)w, (int)h * 3, sheet, c->err, c->errlen);
    }
    free(sheet), free(hb);
    return rc;
}

static void print_tables(const paths_ctx *c, FILE *o)
{
    double px = (double)c->np;
    fprintf(o, "\nlight paths (%s): sun path lat 40 decl 15 from 7 to 17 h, lamp track of %d points; %u steps + bisection "
               "to 1/65535 of the path; bake %.1f s\n", c->v->prop ? "mesh" : "courtyard", c->track.npts,
            c->sz->path_steps, c->bake_s);
    fprintf(o, "edges per pixel: sun %.2f, track %.2f (pixels clipped at 255 edges: %.0f, %.0f)\n", c->st_sun[0],
            c->st_trk[0], c->st_sun[1], c->st_trk[1]);
    fprintf(o, "16 positions between the baked steps; PSNR (dB) overall and per pixel class with its share of the squared "
               "error; brightness = linear mean relit / truth\n\n");
    fprintf(o, "| %-44s | bytes/px | ms/frame | PSNR dB | lit            | cast shadow    | facing away    | bright |\n",
            "scheme");
    fprintf(o, "|%s|---------:|---------:|--------:|---------------:|---------------:|---------------:|------:|\n",
            "----------------------------------------------");
    for (int r = 0; r < NROWS; ++r)
        print_row(o, &c->rs[r]);
    print_row(o, &c->sky_rs[0]);
    print_row(o, &c->sky_rs[1]);
    for (int r = 0; r < 3; ++r)
        print_row(o, &c->soft_rs[r]);
    for (int d = 0; d < NDROP; ++d)
        print_row(o, &c->ad_rs[d][0]), print_row(o, &c->ad_rs[d][1]);
    fprintf(o, "\nbrightness split: relit - truth (linear) per pixel class, as a share of the truth's total "
               "(the three add up to bright - 1)\n\n| %-44s | bright | lit     | cast    | facing  |\n"
               "|%s|------:|--------:|--------:|--------:|\n", "scheme", "----------------------------------------------");
    for (int r = 0; r < NROWS; ++r)
        print_split(o, &c->rs[r]);
    print_split(o, &c->sky_rs[1]);
    fprintf(o, "\nsky: radiance (0.25, 0.32, 0.45) x (0.3 + 0.7 z) above the horizon, ray-traced over %u directions "
               "(not the bake's); its two halves agree to %.2f dB (the truth, their mean, is about 6 dB less noisy)\n",
            c->sz->sky_dirs, c->sky_noise);
    fprintf(o, "soft sun: a disc of 1.5 degrees, truth the mean of %d renders over it, %d of the positions\n", NDISC, NSOFT);
    fprintf(o, "\nadaptive k (SHMT, qibl/shmtile.h): bytes of the unshadowed maps against PSNR; k16 stored whole (SHMU) "
               "is %.1f bytes/px\n\n| drop | tiles k=1/4/9/16 | SHMT bytes/px | sun x path dB | lamp x track dB |\n"
               "|-----:|-----------------|--------------:|--------------:|----------------:|\n", c->u16 / px);
    for (int d = 0; d < NDROP; ++d)
        fprintf(o, "| %4.1f%% | %u / %u / %u / %u | %13.2f | %13.2f | %15.2f |\n", 100 * drops[d], c->ad_tiles[d][1],
                c->ad_tiles[d][4], c->ad_tiles[d][9], c->ad_tiles[d][16], c->ad_bytes[d] / px, c->ad_rs[d][0].psnr,
                c->ad_rs[d][1].psnr);
    fprintf(o, "suns off every path fall back to today's shadowed SH: the 8 novel suns above score demo.psnr_k16_dir\n");
}

static void print_results(const paths_ctx *c, FILE *o)
{
    const row_stats *rs = c->rs;
    double px = (double)c->np;
    fprintf(o, "\nRESULT demo.path_sun_psnr %.2f\nRESULT demo.path_sun_bytes_px %.1f\nRESULT demo.path_sun_cost_ratio %.3f\n",
            rs[1].psnr, rs[1].bytes_px, rs[0].ms > 0 ? rs[1].ms / rs[0].ms : 0);
    fprintf(o, "RESULT demo.path_sun_k16_psnr %.2f\nRESULT demo.path_sun_today_psnr %.2f\n", rs[2].psnr, rs[0].psnr);
    fprintf(o, "RESULT demo.track_lamp_psnr %.2f\nRESULT demo.track_lamp_bytes_px %.1f\nRESULT demo.track_lamp_cost_ratio %.3f\n",
            rs[6].psnr, rs[6].bytes_px, rs[3].ms > 0 ? rs[6].ms / rs[3].ms : 0);
    fprintf(o, "RESULT demo.track_lamp_today_psnr %.2f\n", rs[3].psnr);
    fprintf(o, "RESULT demo.free_lamp_psnr %.2f\nRESULT demo.free_lamp_brightness %.3f\nRESULT demo.today_lamp_brightness %.3f\n",
            rs[4].psnr, rs[4].bright, rs[3].bright);
    fprintf(o, "RESULT demo.free_lamp_bytes_px %.1f\nRESULT demo.free_lamp_no_occl_psnr %.2f\n"
               "RESULT demo.free_lamp_no_occl_brightness %.3f\n", rs[4].bytes_px, rs[8].psnr, rs[8].bright);
    fprintf(o, "RESULT demo.sky_sun_psnr %.2f\nRESULT demo.sky_sun_today_psnr %.2f\nRESULT demo.sky_truth_halves_psnr %.2f\n",
            c->sky_rs[1].psnr, c->sky_rs[0].psnr, c->sky_noise);
    fprintf(o, "RESULT demo.soft_sun_psnr %.2f\nRESULT demo.soft_sun_hard_psnr %.2f\nRESULT demo.soft_sun_today_psnr %.2f\n",
            c->soft_rs[2].psnr, c->soft_rs[1].psnr, c->soft_rs[0].psnr);
    fprintf(o, "RESULT demo.adaptive_sun_psnr %.2f\nRESULT demo.adaptive_sun_bytes_px %.1f\n", c->ad_rs[1][0].psnr,
            c->ad_rs[1][0].bytes_px);
    fprintf(o, "RESULT demo.adaptive_track_psnr %.2f\nRESULT demo.adaptive_track_bytes_px %.1f\n", c->ad_rs[1][1].psnr,
            c->ad_rs[1][1].bytes_px);
    fprintf(o, "RESULT demo.adaptive_shmt_bytes_px %.2f\nRESULT demo.shmu_k16_bytes_px %.2f\n", c->ad_bytes[1] / px,
            c->u16 / px);
    fprintf(o, "RESULT demo.paths_bake_s %.2f\n", c->bake_s);
    fprintf(o, "wrote %s/paths_sheet.png (rows: sun, lamp; columns: truth | today | path shadows | error 0..48) and "
               "paths_readme.png (truth, today, path shadows of one sun)\n", c->v->dir);
}

static void ctx_free(paths_ctx *c)
{
    qtool_bake_sums_free(&c->us);
    qtool_gen_free(&c->msh), qtool_gen_free(&c->mu9), qtool_gen_free(&c->mu16);
    free(c->lp[0]), free(c->lp[1]), free(c->asset9), free(c->asset16), free(c->asset9o), free(c->asset16o);
    free(c->occv), free(c->truth), free(c->cls), free(c->tmp);
    for (int i = 0; i < 4; ++i)
        free(c->keep[i]);
    free(c);
}

int qtool_demo_paths(const qtool_demo_view *v, uint32_t ndirs, const qtool_demo_size *sz, const qtool_bake_sums *sums,
                     const uint8_t *today, size_t today_n, char *err, size_t errlen)
{
    /* the context is a few kB of results: on the heap, not the stack */
    paths_ctx *c = calloc(1, sizeof *c);
    if (!c)
        return qtool_errf(err, errlen, "demo: out of memory (light paths)");
    c->v = v, c->sz = sz, c->sums_shadowed = sums, c->today = today, c->today_n = today_n;
    c->np = (size_t)v->w * v->h, c->err = err, c->errlen = errlen;
    double t0 = qtool_demo_now();
    for (int i = 0; i < 256; ++i)
        c->lut[i] = qtool_demo_lin8(i);
    define_paths(c);
    int rc = bake_paths(c, ndirs);
    if (rc == 0)
        c->bake_s = qtool_demo_now() - t0;
    /* the steps after the bake, in order; each 0, or -1 with c->err */
    static int (*const steps[])(paths_ctx *) = {lamp_occlusion, path_truths, score_rows, score_adaptive,
                                                score_sky,      score_soft,  sheets};
    for (size_t i = 0; rc == 0 && i < sizeof steps / sizeof steps[0]; ++i)
        rc = steps[i](c);
    if (rc == 0) {
        print_tables(c, v->out);
        print_results(c, v->out);
        /* the IES lamp row on the same track asset (ies.c), after everything this part prints */
        rc = qtool_demo_ies(v, c->asset16, c->n16, 1, &c->track, sz->ies_pos, err, errlen);
    }
    ctx_free(c);
    return rc;
}
