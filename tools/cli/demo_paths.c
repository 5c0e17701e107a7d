/*
 * demo_paths.c - the light-path part of `qibl demo`: a sun path and a lamp track baked as per-pixel
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
#include "io/png.h"
#include "io/text.h"
#include "qibl/asset.h"
#include "qibl/lightpath.h"
#include "qibl/shmtile.h"
#include "cli/cli.h"
#include "ref/psnr.h"
#include "render/rt.h"

enum { NPOS = 16, NCLS = 4 };

typedef struct {
    const char *name;
    double bytes_px, ms, psnr, psnr_cls[NCLS], share_cls[NCLS], bright, excess_cls[NCLS];
} row_stats;

typedef struct {
    double se_cls[NCLS], n_cls[NCLS], ms[NPOS], lr_cls[NCLS], lt_cls[NCLS];
    int frames;
} acc_t;

static double lin8(int v)
{
    double c = v / 255.0;
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

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
    r->ms = qcli_median(ms, a->frames);
}

static void print_row(const row_stats *r)
{
    printf("| %-44s | %8.1f | %8.3f | %7.2f | %6.2f (%4.1f%%) | %6.2f (%4.1f%%) | %6.2f (%4.1f%%) | %5.3f |\n", r->name,
           r->bytes_px, r->ms, r->psnr, r->psnr_cls[1], r->share_cls[1], r->psnr_cls[2], r->share_cls[2],
           r->psnr_cls[3], r->share_cls[3], r->bright);
}

/* the brightness error split by pixel class: (relit - truth) per class over the truth's whole sum */
static void print_split(const row_stats *r)
{
    printf("| %-44s | %5.3f | %+7.4f | %+7.4f | %+7.4f |\n", r->name, r->bright, r->excess_cls[1], r->excess_cls[2],
           r->excess_cls[3]);
}

void qcli_demo_heat(const uint8_t *a, const uint8_t *b, const uint8_t *cls, size_t np, uint8_t *out)
{
    for (size_t i = 0; i < np; ++i) {
        int d = 0;
        for (int c = 0; c < 3; ++c) {
            int x = abs((int)a[3 * i + (size_t)c] - (int)b[3 * i + (size_t)c]);
            d = x > d ? x : d;
        }
        double t = cls[i] ? fmin(1.0, d / 48.0) : 0;
        double r = fmin(1, fmax(0, 3 * t - 1)), g = fmin(1, fmax(0, 3 * t - 2)), bl = t < 1.0 / 3 ? 3 * t : fmax(0, 2 - 3 * t);
        out[3 * i] = (uint8_t)lrint(255 * r), out[3 * i + 1] = (uint8_t)lrint(255 * g);
        out[3 * i + 2] = (uint8_t)lrint(255 * fmax(bl, 0.25 * g));
    }
}

/* chunk bytes of a type in an asset (0 if absent) */
double qcli_asset_chunk_bytes(const uint8_t *asset, size_t n, uint32_t type, uint32_t index)
{
    qibl_asset_t a;
    qibl_chunk_t c;
    if (qibl_asset_open(&a, asset, n) != QIBL_OK || qibl_asset_find_nth(&a, type, index, &c) != QIBL_OK)
        return 0;
    return c.size;
}

int qtool_demo_paths(const qtool_rt_scene *s, const qcli_scene *so, uint32_t ndirs, int prop, const qcli_demo_size *sz,
                    const qtool_bake_sums *sums, const uint8_t *today, size_t today_n, const char *dir)
{
    uint32_t w = so->w, h = so->h;
    qtool_pano_kind kind = (qtool_pano_kind)so->kind;
    size_t np = (size_t)w * h;
    int rc = 1;
    double t0 = qcli_now(), lut[256];
    for (int i = 0; i < 256; ++i)
        lut[i] = lin8(i);

    /* the paths: a summer day at 40 N from 7 to 17 h; a lamp carried round the courtyard */
    qtool_bake_path sun = {0}, track = {0};
    sun.kind = 0, sun.lat = 40, sun.decl = 15, sun.t0 = 7, sun.t1 = 17;
    sun.rgb[0] = 2.6, sun.rgb[1] = 2.4, sun.rgb[2] = 2.1;
    track.kind = 1, track.npts = 9;
    double cx = prop ? QTOOL_RT_PROP_X : 0.0, rr = prop ? 2.2 : 2.8;
    for (int i = 0; i < track.npts; ++i) {
        double a = 2 * 3.14159265358979 * i / (track.npts - 1) + 0.3;
        track.pts[i][0] = cx + rr * cos(a), track.pts[i][1] = rr * sin(a), track.pts[i][2] = -0.5 + 0.4 * sin(2 * a);
    }
    track.rgb[0] = 5.0, track.rgb[1] = 4.4, track.rgb[2] = 3.6;

    qtool_bake_sums us;
    qtool_gen_maps msh = {0}, mu9 = {0}, mu16 = {0};
    uint8_t *lp[3] = {NULL, NULL, NULL}, *asset9 = NULL, *asset16 = NULL, *asset9o = NULL, *asset16o = NULL;
    uint8_t *occv = malloc(np);
    size_t lpn[2] = {0, 0}, n9 = 0, n16 = 0, n9o = 0, n16o = 0;
    uint8_t *truth = malloc(np * 3 * NPOS * 2), *cls = malloc(np * NPOS * 2), *tmp = malloc(np * 3);
    uint8_t *keep[4] = {malloc(np * 3), malloc(np * 3), malloc(np * 3), malloc(np * 3)};
    double st_sun[2], st_trk[2];
    uint32_t steps = sz->path_steps;
    memset(&us, 0, sizeof us);
    if (!truth || !cls || !tmp || !keep[0] || !keep[1] || !keep[2] || !keep[3] ||
        qtool_bake_run_unshadowed(s, w, h, kind, ndirs, 16, so->threads, &us) != 0 ||
        qtool_bake_coeffs(sums, 16, QTOOL_PROJ_QUADRATURE, &msh) != 0 ||
        qtool_bake_coeffs(&us, 9, QTOOL_PROJ_QUADRATURE, &mu9) != 0 ||
        qtool_bake_coeffs(&us, 16, QTOOL_PROJ_QUADRATURE, &mu16) != 0 ||
        qtool_bake_path_chunk(s, w, h, kind, &sun, steps, 65, so->threads, &lp[0], &lpn[0], st_sun) != 0 ||
        qtool_bake_path_chunk(s, w, h, kind, &track, steps, 65, so->threads, &lp[1], &lpn[1], st_trk) != 0 ||
        qtool_bake_asset_ex(&msh, &mu9, 32, lp, lpn, &asset9, &n9) != 0 ||
        qtool_bake_asset_ex(&msh, &mu16, 32, lp, lpn, &asset16, &n16) != 0) {
        fprintf(stderr, "qibl: demo: out of memory (light paths)\n");
        goto done;
    }
    double bake_s = qcli_now() - t0;

    /* lamp occlusion for free lamps: the region lamps move in is the track's bounding box grown by
     * half a unit (a designer's box, not the track: the 16 free positions are not sampled) */
    uint8_t *occ = occv, *occp = NULL;
    size_t occn = 0;
    double box[6] = {1e30, 1e30, 1e30, -1e30, -1e30, -1e30};
    for (int i = 0; i < track.npts; ++i)
        for (int c = 0; c < 3; ++c)
            box[c] = fmin(box[c], track.pts[i][c] - 0.5), box[3 + c] = fmax(box[3 + c], track.pts[i][c] + 0.5);
    if (!occ || qtool_bake_lamp_occlusion(s, w, h, kind, box, 64, so->threads, occ) != 0 ||
        qtool_bake_locc_payload(w, h, occ, &occp, &occn) != 0 ||
        qtool_bake_asset_add(asset9, n9, QIBL_CHUNK_LOCC, occp, occn, &asset9o, &n9o) != 0 ||
        qtool_bake_asset_add(asset16, n16, QIBL_CHUNK_LOCC, occp, occn, &asset16o, &n16o) != 0) {
        fprintf(stderr, "qibl: demo: out of memory (lamp occlusion)\n");
        free(occp);
        goto done;
    }
    free(occp), occp = NULL;
    /* 16 positions on each path, between the baked steps; truth and pixel classes once */
    qtool_rt_light L[2][NPOS];
    uint32_t tq[NPOS];
    for (int i = 0; i < NPOS; ++i) {
        tq[i] = (uint32_t)lrint(65535.0 * (i + 0.37) / NPOS);
        qtool_bake_path_light(&sun, tq[i] / 65535.0, &L[0][i]);
        qtool_bake_path_light(&track, tq[i] / 65535.0, &L[1][i]);
        for (int p = 0; p < 2; ++p) {
            size_t f = (size_t)p * NPOS + (size_t)i;
            if (qtool_bake_truth8(s, w, h, kind, &L[p][i], so->threads, truth + f * np * 3, NULL) != 0 ||
                qtool_bake_classify(s, w, h, kind, &L[p][i], so->threads, cls + f * np) != 0)
                goto done;
        }
    }

    /* rows: 0 today sun, 1 path k9, 2 path k16, 3 today lamp, 4 free lamp k9, 5 free lamp k16 (both with the
     * lamp occlusion), 6 track k9, 7 track k16, 8 free lamp k9 without the occlusion */
    enum { NROWS = 9 };
    static const char *names[NROWS] = {
        "sun: today, shadowed SH k16",        "sun: unshadowed k9 x path visibility",
        "sun: unshadowed k16 x path visibility", "lamp: today, shadowed SH k16 (LUT)",
        "lamp: free, unshadowed k9 x occlusion (LUT)", "lamp: free, unshadowed k16 x occlusion (LUT)",
        "lamp: unshadowed k9 x track visibility", "lamp: unshadowed k16 x track visibility",
        "lamp: free, unshadowed k9, no occlusion"};
    acc_t acc[NROWS];
    memset(acc, 0, sizeof acc);
    qibl_status_t st = QIBL_OK;
    for (int r = 0; r < NROWS; ++r) {
        int p = r < 3 ? 0 : 1;
        for (int i = 0; i < NPOS; ++i) {
            size_t f = (size_t)p * NPOS + (size_t)i;
            double ms = 0;
            int e;
            const uint8_t *as = (r == 2 || r == 5 || r == 7) ? asset16 : asset9;
            size_t an = (r == 2 || r == 5 || r == 7) ? n16 : n9;
            if (r == 0 || r == 3)
                e = qtool_bake_relight8_lin(today, today_n, &L[p][i], 1, 0, 1, tmp, NULL, &ms, &st);
            else if (r == 4 || r == 5) { /* a free point light: qibl_asset_point_shmaps picks SHMU */
                e = qtool_bake_relight8_lin(r == 4 ? asset9o : asset16o, r == 4 ? n9o : n16o, &L[p][i], 1, 0, 1, tmp,
                                           NULL, &ms, &st);
            } else if (r == 8) /* the same asset without the lamp occlusion */
                e = qtool_bake_relight8_lin(asset9, n9, &L[p][i], 1, 0, 1, tmp, NULL, &ms, &st);
            else
                e = qtool_bake_relight_path8(as, an, &L[p][i], (uint32_t)p, tq[i], 0, NULL, tmp, NULL, &ms, &st);
            if (e != 0) {
                fprintf(stderr, "qibl: demo: relight (%s) failed: %s\n", names[r], qibl_status_str(st));
                goto done;
            }
            acc_frame(&acc[r], tmp, truth + f * np * 3, cls + f * np, np, ms, lut);
            if (i == 5 && (r == 0 || r == 1 || r == 3 || r == 6))
                memcpy(keep[r == 0 ? 0 : r == 1 ? 1 : r == 3 ? 2 : 3], tmp, np * 3);
        }
    }
    /* bytes per pixel of what each scheme reads (fixed-size YLUT included, spread over the pixels) */
    double shmp = qcli_asset_chunk_bytes(today, today_n, QIBL_CHUNK_SHMP, 0);
    double pmap = qcli_asset_chunk_bytes(asset9, n9, QIBL_CHUNK_PMAP, 0);
    double ylut = qcli_asset_chunk_bytes(today, today_n, QIBL_CHUNK_YLUT, 0);
    double u9 = qcli_asset_chunk_bytes(asset9, n9, QIBL_CHUNK_SHMU, 0);
    double u16 = qcli_asset_chunk_bytes(asset16, n16, QIBL_CHUNK_SHMU, 0);
    double oc = (double)occn;
    double bytes[NROWS] = {shmp, u9 + lpn[0], u16 + lpn[0], shmp + pmap + ylut, u9 + pmap + ylut + oc,
                           u16 + pmap + ylut + oc, u9 + pmap + ylut + lpn[1], u16 + pmap + ylut + lpn[1],
                           u9 + pmap + ylut};
    row_stats rs[NROWS];
    for (int r = 0; r < NROWS; ++r)
        finish(&acc[r], names[r], bytes[r] / (double)np, &rs[r]);

    /* per-tile adaptive k for the unshadowed maps (SHMT, qibl/shmtile.h): each 16x16 tile keeps the
     * fewest band-complete k of the k16 set whose dropped coefficients hold at most `drop` of the
     * tile's energy; relit through the core kernels tile by tile. Bytes are the SHMT chunk's. */
    enum { NDROP = 3 };
    static const double drops[NDROP] = {0.003, 0.01, 0.03};
    acc_t adacc[NDROP][2];
    double ad_bytes[NDROP] = {0, 0, 0};
    uint32_t ad_tiles[NDROP][26];
    memset(adacc, 0, sizeof adacc);
    for (int d = 0; d < NDROP; ++d) {
        uint8_t *pay = NULL, *base = NULL, *ad = NULL, *ad2 = NULL;
        size_t payn = 0, basen = 0, adn = 0, ad2n = 0;
        int bad = qtool_bake_shmt_payload(&mu16, drops[d], &pay, &payn, ad_tiles[d]) != 0 ||
                  qtool_bake_asset_ex(&msh, NULL, 32, lp, lpn, &base, &basen) != 0 ||
                  qtool_bake_asset_add(base, basen, QIBL_CHUNK_SHMT, pay, payn, &ad, &adn) != 0 ||
                  qtool_bake_locc_payload(w, h, occv, &occp, &occn) != 0 ||
                  qtool_bake_asset_add(ad, adn, QIBL_CHUNK_LOCC, occp, occn, &ad2, &ad2n) != 0;
        free(occp), occp = NULL;
        ad_bytes[d] = (double)payn;
        for (int p = 0; !bad && p < 2; ++p)
            for (int i = 0; i < NPOS; ++i) {
                size_t f = (size_t)p * NPOS + (size_t)i;
                double ms = 0;
                if (qtool_bake_relight_tiled8(ad2, ad2n, &L[p][i], p, tq[i], 0, tmp, &ms, &st) != 0) {
                    bad = 1;
                    break;
                }
                acc_frame(&adacc[d][p], tmp, truth + f * np * 3, cls + f * np, np, ms, lut);
            }
        free(pay), free(base), free(ad), free(ad2);
        if (bad) {
            fprintf(stderr, "qibl: demo: adaptive k failed (%s)\n", qibl_status_str(st));
            goto done;
        }
    }
    row_stats ad_rs[NDROP][2];
    for (int d = 0; d < NDROP; ++d) {
        static char names_ad[NDROP][2][64];
        snprintf(names_ad[d][0], sizeof names_ad[d][0], "sun: SHMT adaptive k (drop %.1f%%) x path", 100 * drops[d]);
        snprintf(names_ad[d][1], sizeof names_ad[d][1], "lamp: SHMT adaptive k (drop %.1f%%) x track", 100 * drops[d]);
        finish(&adacc[d][0], names_ad[d][0], (ad_bytes[d] + lpn[0]) / (double)np, &ad_rs[d][0]);
        finish(&adacc[d][1], names_ad[d][1], (ad_bytes[d] + pmap + ylut + lpn[1]) / (double)np, &ad_rs[d][1]);
    }

    /* sky + sun: the sky ray-traced once (two half estimates: their agreement states its noise), the sun
     * at the 16 positions; today's SH with sky and sun in one light against the hybrid */
    double sky_rgb[3] = {0.25, 0.32, 0.45}, sky_noise = 0;
    uint32_t nsky = sz->sky_dirs;
    acc_t sacc[2];
    memset(sacc, 0, sizeof sacc);
    {
        double *ha = malloc(np * 3 * sizeof(double)), *hb = malloc(np * 3 * sizeof(double));
        double *lin = malloc(np * 3 * sizeof(double));
        uint8_t *t8 = malloc(np * 3), *u8 = malloc(np * 3);
        int bad = !ha || !hb || !lin || !t8 || !u8 ||
                  qtool_bake_sky_truth(s, w, h, kind, sky_rgb, nsky, so->threads, ha, hb) != 0;
        if (!bad) {
            qtool_bake_lin_to8(ha, w, h, t8);
            qtool_bake_lin_to8(hb, w, h, u8);
            sky_noise = qtool_ref_psnr8(qtool_bake_mse(t8, u8, cls, np)); /* class 0 = sky pixels left out */
        }
        qibl_shlight_t skysh;
        qtool_bake_sky_sh(sky_rgb, 16, &skysh);
        for (int i = 0; !bad && i < NPOS; ++i) {
            qtool_rt_render(s, w, h, kind, &L[0][i], so->threads, lin, NULL, NULL);
            for (size_t q = 0; q < np * 3; ++q)
                lin[q] += 0.5 * (ha[q] + hb[q]);
            qtool_bake_lin_to8(lin, w, h, t8);
            /* today: sky and sun in one SH light through the shadowed maps */
            qibl_shlight_t both = skysh;
            qibl_q16_t dq[3], rq[3];
            for (int c = 0; c < 3; ++c)
                dq[c] = (qibl_q16_t)lrint(L[0][i].dir[c] * 65536), rq[c] = (qibl_q16_t)lrint(L[0][i].rgb[c] * 65536);
            double ms = 0;
            if (qibl_shlight_add_dir(&both, dq, rq) != QIBL_OK ||
                qtool_bake_relight_env8(today, today_n, &both, tmp, &ms, &st) != 0) {
                bad = 1;
                break;
            }
            acc_frame(&sacc[0], tmp, t8, cls + (size_t)i * np, np, ms, lut);
            if (qtool_bake_relight_path8(asset9, n9, &L[0][i], 0, tq[i], 0, &skysh, tmp, NULL, &ms, &st) != 0) {
                bad = 1;
                break;
            }
            acc_frame(&sacc[1], tmp, t8, cls + (size_t)i * np, np, ms, lut);
        }
        free(ha), free(hb), free(lin), free(t8), free(u8);
        if (bad) {
            fprintf(stderr, "qibl: demo: sky + sun failed (%s)\n", qibl_status_str(st));
            goto done;
        }
    }
    /* soft sun: a disc of angular radius 1.5 degrees (three times the real sun's, so the penumbrae show
     * at this resolution); truth = mean of 8 renders over the disc; the runtime filters V along the path
     * over the disc's extent in t (the disc's width across the path is not modelled) */
    enum { NSOFT = 4, NDISC = 8 };
    const double alpha = 1.5 * 3.14159265358979 / 180;
    acc_t soft[3];
    memset(soft, 0, sizeof soft);
    {
        double *lin = malloc(np * 3 * sizeof(double)), *one = malloc(np * 3 * sizeof(double));
        uint8_t *t8 = malloc(np * 3);
        int bad = !lin || !one || !t8;
        for (int q = 0; !bad && q < NSOFT; ++q) {
            int i = 2 + 4 * q;
            const double *c = L[0][i].dir;
            /* an orthonormal frame around the sun's direction */
            double a[3] = {-c[1], c[0], 0}, la = sqrt(a[0] * a[0] + a[1] * a[1]);
            for (int k = 0; k < 3; ++k)
                a[k] /= la > 0 ? la : 1;
            double b[3] = {c[1] * a[2] - c[2] * a[1], c[2] * a[0] - c[0] * a[2], c[0] * a[1] - c[1] * a[0]};
            memset(lin, 0, np * 3 * sizeof(double));
            for (int d = 0; d < NDISC; ++d) { /* sunflower points over the disc */
                double r = alpha * sqrt((d + 0.5) / NDISC), ph = d * 2.39996323;
                qtool_rt_light dl = L[0][i];
                for (int k = 0; k < 3; ++k)
                    dl.dir[k] = c[k] + r * (cos(ph) * a[k] + sin(ph) * b[k]);
                qtool_rt_render(s, w, h, kind, &dl, so->threads, one, NULL, NULL);
                for (size_t z = 0; z < np * 3; ++z)
                    lin[z] += one[z] / NDISC;
            }
            qtool_bake_lin_to8(lin, w, h, t8);
            /* the disc's radius in path units: alpha over the sun's angle per step of t */
            qtool_rt_light nx;
            qtool_bake_path_light(&sun, (tq[i] + 1) / 65535.0, &nx);
            double dot = 0, l0 = 0, l1 = 0;
            for (int k = 0; k < 3; ++k)
                dot += c[k] * nx.dir[k], l0 += c[k] * c[k], l1 += nx.dir[k] * nx.dir[k];
            double step = acos(fmin(1.0, dot / sqrt(l0 * l1)));
            uint32_t rad = step > 0 ? (uint32_t)fmin(32767, lrint(alpha / step)) : 0;
            double ms = 0;
            const uint8_t *cl = cls + (size_t)i * np;
            if (qtool_bake_relight8_lin(today, today_n, &L[0][i], 1, 0, 1, tmp, NULL, &ms, &st) != 0)
                bad = 1;
            else
                acc_frame(&soft[0], tmp, t8, cl, np, ms, lut);
            for (int v = 0; !bad && v < 2; ++v) {
                if (qtool_bake_relight_path8(asset9, n9, &L[0][i], 0, tq[i], v ? rad : 0, NULL, tmp, NULL, &ms, &st) != 0)
                    bad = 1;
                else
                    acc_frame(&soft[1 + v], tmp, t8, cl, np, ms, lut);
            }
        }
        free(lin), free(one), free(t8);
        if (bad) {
            fprintf(stderr, "qibl: demo: soft sun failed (%s)\n", qibl_status_str(st));
            goto done;
        }
    }
    row_stats soft_rs[3];
    finish(&soft[0], "soft sun: today, shadowed SH k16", shmp / (double)np, &soft_rs[0]);
    finish(&soft[1], "soft sun: k9 x path, hard edges", (u9 + lpn[0]) / (double)np, &soft_rs[1]);
    finish(&soft[2], "soft sun: k9 x path, filtered along the path", (u9 + lpn[0]) / (double)np, &soft_rs[2]);
    row_stats sky_rs[2];
    finish(&sacc[0], "sky + sun: today, one SH light, shadowed k16", shmp / (double)np, &sky_rs[0]);
    finish(&sacc[1], "sky + sun: sky SH k16 + sun k9 x path", (shmp + u9 + lpn[0]) / (double)np, &sky_rs[1]);

    /* contact sheet: truth | today | path shadows | error of the path frame, one sun and one lamp row,
     * each under a label strip */
    int ts = w >= 512 ? 2 : 1, strip = (QTOOL_TEXT_HEIGHT + 3) * ts;
    size_t shh = 2 * ((size_t)h + (size_t)strip);
    {
        static const char *cols[4] = {"truth: ray-traced", "today: shadowed SH k16", "SHMU k9 x path visibility",
                                      "error, 0 .. 48+ of 255"};
        static const uint8_t fg[3] = {235, 235, 235};
        size_t sw = (size_t)w * 4;
        uint8_t *sheet = malloc(sw * 3 * shh), *hb = malloc(np * 3);
        if (sheet)
            memset(sheet, 24, sw * 3 * shh);
        for (int r = 0; sheet && hb && r < 2; ++r) {
            size_t f = (size_t)r * NPOS + 5, y0 = (size_t)r * (h + (size_t)strip);
            qcli_demo_heat(keep[2 * r + 1], truth + f * np * 3, cls + f * np, np, hb);
            const uint8_t *src[4] = {truth + f * np * 3, keep[2 * r], keep[2 * r + 1], hb};
            for (int c = 0; c < 4; ++c) {
                char lab[96];
                snprintf(lab, sizeof lab, "%s: %s", r ? "lamp" : "sun", cols[c]);
                qtool_text_draw(sheet, (int)sw, (int)shh, c * (int)w + 4, (int)y0 + ts, lab, ts, fg);
            }
            for (uint32_t y = 0; y < h; ++y)
                for (int c = 0; c < 4; ++c)
                    memcpy(sheet + ((y0 + (size_t)strip + y) * sw + (size_t)c * w) * 3, src[c] + (size_t)y * w * 3,
                           (size_t)w * 3);
        }
        char err[1200], path[4096];
        snprintf(path, sizeof path, "%s/paths_sheet.png", dir);
        int bad = !sheet || !hb || qtool_png_write_rgb8(path, (int)sw, (int)shh, sheet, err, sizeof err) != 0;
        if (bad)
            fprintf(stderr, "qibl: %s\n", sheet && hb ? err : "demo: out of memory");
        /* the README picture: truth, today, path shadows of the same sun, one above the other */
        if (!bad) {
            const uint8_t *src[3] = {truth + 5 * np * 3, keep[0], keep[1]};
            for (int r = 0; r < 3; ++r)
                memcpy(sheet + (size_t)r * np * 3, src[r], np * 3);
            snprintf(path, sizeof path, "%s/paths_readme.png", dir);
            bad = qtool_png_write_rgb8(path, (int)w, (int)h * 3, sheet, err, sizeof err) != 0;
            if (bad)
                fprintf(stderr, "qibl: %s\n", err);
        }
        free(sheet), free(hb);
        if (bad)
            goto done;
    }

    printf("\nlight paths (%s): sun path lat 40 decl 15 from 7 to 17 h, lamp track of %d points; %u steps + bisection "
           "to 1/65535 of the path; bake %.1f s\n", prop ? "mesh" : "courtyard", track.npts, steps, bake_s);
    printf("edges per pixel: sun %.2f, track %.2f (pixels clipped at 255 edges: %.0f, %.0f)\n", st_sun[0], st_trk[0],
           st_sun[1], st_trk[1]);
    printf("16 positions between the baked steps; PSNR (dB) overall and per pixel class with its share of the squared "
           "error; brightness = linear mean relit / truth\n\n");
    printf("| %-44s | bytes/px | ms/frame | PSNR dB | lit            | cast shadow    | facing away    | bright |\n",
           "scheme");
    printf("|%s|---------:|---------:|--------:|---------------:|---------------:|---------------:|------:|\n",
           "----------------------------------------------");
    for (int r = 0; r < NROWS; ++r)
        print_row(&rs[r]);
    print_row(&sky_rs[0]);
    print_row(&sky_rs[1]);
    for (int r = 0; r < 3; ++r)
        print_row(&soft_rs[r]);
    for (int d = 0; d < NDROP; ++d)
        print_row(&ad_rs[d][0]), print_row(&ad_rs[d][1]);
    printf("\nbrightness split: relit - truth (linear) per pixel class, as a share of the truth's total "
           "(the three add up to bright - 1)\n\n| %-44s | bright | lit     | cast    | facing  |\n"
           "|%s|------:|--------:|--------:|--------:|\n", "scheme", "----------------------------------------------");
    for (int r = 0; r < NROWS; ++r)
        print_split(&rs[r]);
    print_split(&sky_rs[1]);
    printf("\nsky: radiance (0.25, 0.32, 0.45) x (0.3 + 0.7 z) above the horizon, ray-traced over %u directions "
           "(not the bake's); its two halves agree to %.2f dB (the truth, their mean, is about 6 dB less noisy)\n",
           nsky, sky_noise);
    printf("soft sun: a disc of 1.5 degrees, truth the mean of %d renders over it, %d of the positions\n", NDISC, NSOFT);
    printf("\nadaptive k (SHMT, qibl/shmtile.h): bytes of the unshadowed maps against PSNR; k16 stored whole (SHMU) "
           "is %.1f bytes/px\n\n| drop | tiles k=1/4/9/16 | SHMT bytes/px | sun x path dB | lamp x track dB |\n"
           "|-----:|-----------------|--------------:|--------------:|----------------:|\n", u16 / (double)np);
    for (int d = 0; d < NDROP; ++d)
        printf("| %4.1f%% | %u / %u / %u / %u | %13.2f | %13.2f | %15.2f |\n", 100 * drops[d], ad_tiles[d][1],
               ad_tiles[d][4], ad_tiles[d][9], ad_tiles[d][16], ad_bytes[d] / (double)np, ad_rs[d][0].psnr,
               ad_rs[d][1].psnr);
    printf("suns off every path fall back to today's shadowed SH: the 8 novel suns above score demo.psnr_k16_dir\n");
    printf("\nRESULT demo.path_sun_psnr %.2f\nRESULT demo.path_sun_bytes_px %.1f\nRESULT demo.path_sun_cost_ratio %.3f\n",
           rs[1].psnr, rs[1].bytes_px, rs[0].ms > 0 ? rs[1].ms / rs[0].ms : 0);
    printf("RESULT demo.path_sun_k16_psnr %.2f\nRESULT demo.path_sun_today_psnr %.2f\n", rs[2].psnr, rs[0].psnr);
    printf("RESULT demo.track_lamp_psnr %.2f\nRESULT demo.track_lamp_bytes_px %.1f\nRESULT demo.track_lamp_cost_ratio %.3f\n",
           rs[6].psnr, rs[6].bytes_px, rs[3].ms > 0 ? rs[6].ms / rs[3].ms : 0);
    printf("RESULT demo.track_lamp_today_psnr %.2f\n", rs[3].psnr);
    printf("RESULT demo.free_lamp_psnr %.2f\nRESULT demo.free_lamp_brightness %.3f\nRESULT demo.today_lamp_brightness %.3f\n",
           rs[4].psnr, rs[4].bright, rs[3].bright);
    printf("RESULT demo.free_lamp_bytes_px %.1f\nRESULT demo.free_lamp_no_occl_psnr %.2f\n"
           "RESULT demo.free_lamp_no_occl_brightness %.3f\n", rs[4].bytes_px, rs[8].psnr, rs[8].bright);
    printf("RESULT demo.sky_sun_psnr %.2f\nRESULT demo.sky_sun_today_psnr %.2f\nRESULT demo.sky_truth_halves_psnr %.2f\n",
           sky_rs[1].psnr, sky_rs[0].psnr, sky_noise);
    printf("RESULT demo.soft_sun_psnr %.2f\nRESULT demo.soft_sun_hard_psnr %.2f\nRESULT demo.soft_sun_today_psnr %.2f\n",
           soft_rs[2].psnr, soft_rs[1].psnr, soft_rs[0].psnr);
    printf("RESULT demo.adaptive_sun_psnr %.2f\nRESULT demo.adaptive_sun_bytes_px %.1f\n", ad_rs[1][0].psnr,
           ad_rs[1][0].bytes_px);
    printf("RESULT demo.adaptive_track_psnr %.2f\nRESULT demo.adaptive_track_bytes_px %.1f\n", ad_rs[1][1].psnr,
           ad_rs[1][1].bytes_px);
    printf("RESULT demo.adaptive_shmt_bytes_px %.2f\nRESULT demo.shmu_k16_bytes_px %.2f\n", ad_bytes[1] / (double)np,
           u16 / (double)np);
    printf("RESULT demo.paths_bake_s %.2f\n", bake_s);
    printf("wrote %s/paths_sheet.png (rows: sun, lamp; columns: truth | today | path shadows | error 0..48) and "
           "paths_readme.png (truth, today, path shadows of one sun)\n", dir);
    rc = 0;
done:
    qtool_bake_sums_free(&us);
    qtool_gen_free(&msh), qtool_gen_free(&mu9), qtool_gen_free(&mu16);
    free(lp[0]), free(lp[1]), free(asset9), free(asset16), free(asset9o), free(asset16o), free(occv), free(truth), free(cls), free(tmp);
    for (int i = 0; i < 4; ++i)
        free(keep[i]);
    return rc;
}
