/*
 * probe/info.c - `qibl probe info`'s measures and report (probe/info.h). Output is all or nothing:
 * the caller prints the report once everything has been computed.
 */
#include "probe/info.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "qtool.h"
#include "ref/lightprobe_ref.h"
#include "ref/probe_ref.h"
#include "ref/sh_ref.h"
#include "study/study.h"

static double rgbe_f(uint8_t m, uint8_t e)
{
    return e ? ldexp(m, e - 136) : 0.0;
}

static double luma(const double *c)
{
    return QTOOL_REF_LUMA_R * c[0] + QTOOL_REF_LUMA_G * c[1] + QTOOL_REF_LUMA_B * c[2];
}

/* solid angle of a pixel of row v of a w x h lat-long */
static double pixel_dw(int v, int w, int h)
{
    return (2 * QTOOL_PI / w) * (QTOOL_PI / h) * sin((v + 0.5) * QTOOL_PI / h);
}

typedef struct pix_e {
    double lum, dw;
} pix_e;

static int cmp_desc(const void *a, const void *b)
{
    double x = ((const pix_e *)a)->lum, y = ((const pix_e *)b)->lum;
    return x > y ? -1 : x < y;
}

/* median-cut lights of the probe by the core; count, or -1 with err set */
static int core_lights(const qibl_lightprobe_image_t *img, uint32_t n, qibl_lightprobe_light_t *L, int32_t *exp2,
                       char *err, size_t errlen)
{
    size_t wn = qibl_lightprobe_workspace_size(img->width, img->height, QIBL_LIGHTPROBE_MEDIANCUT);
    void *ws = wn ? malloc(wn) : NULL;
    if (!ws)
        return qtool_errf(err, errlen, "probe info: out of memory");
    qibl_lightprobe_t lp;
    qibl_lightprobe_result_t res;
    qibl_status_t st = qibl_lightprobe_build(&lp, img, QIBL_LIGHTPROBE_MEDIANCUT, ws, wn);
    if (st == QIBL_OK)
        st = qibl_lightprobe_lights(&lp, NULL, L, n, &res);
    free(ws);
    if (st != QIBL_OK)
        return qtool_errf(err, errlen, "probe info: %s", qibl_status_str(st));
    *exp2 = res.rgb_exp;
    return (int)res.count;
}

/* size and dynamic range, exact, in one pass over the decoded input (no copy of it); the
 * luminance-weighted solid angle in *total */
static void range_pass(const uint8_t *px, int w, int h, qtool_probe_info *in, double *total)
{
    in->w = w, in->h = h, in->np = (size_t)w * (size_t)h, in->black = 0;
    in->lmax = 0, in->lmin = INFINITY, *total = 0;
    for (int v = 0; v < h; ++v) {
        double dw = pixel_dw(v, w, h);
        for (int u = 0; u < w; ++u) {
            const uint8_t *q = px + 4 * ((size_t)v * (size_t)w + (size_t)u);
            double c[3] = {rgbe_f(q[0], q[3]), rgbe_f(q[1], q[3]), rgbe_f(q[2], q[3])}, l = luma(c);
            *total += l * dw;
            if (l > 0)
                in->lmin = fmin(in->lmin, l), in->lmax = fmax(in->lmax, l);
            else
                ++in->black;
        }
    }
}

/* energy concentration (pixels weighed by their solid angle) on the study's probe, decoded into d */
static void concentration(const qtool_study_probe *sp, double *d, pix_e *pe, qtool_probe_info *in, double *total)
{
    int sw = sp->w, sh = sp->h;
    size_t sn = (size_t)sw * (size_t)sh;
    double sphere = 0;
    *total = 0;
    for (int v = 0; v < sh; ++v) {
        double dw = pixel_dw(v, sw, sh);
        for (int u = 0; u < sw; ++u) {
            size_t i = (size_t)v * (size_t)sw + (size_t)u;
            for (int c = 0; c < 3; ++c)
                d[3 * i + (size_t)c] = rgbe_f(sp->rgbe[4 * i + (size_t)c], sp->rgbe[4 * i + 3]);
            pe[i].lum = luma(d + 3 * i), pe[i].dw = dw;
            *total += pe[i].lum * dw, sphere += dw;
        }
    }
    qsort(pe, sn, sizeof *pe, cmp_desc);
    const double want[2] = {0.001, 0.01};
    double acc_w = 0, acc_e = 0;
    size_t i = 0;
    for (int k = 0; k < 2; ++k) {
        for (; i < sn && acc_w < want[k] * sphere; ++i)
            acc_w += pe[i].dw, acc_e += pe[i].lum * pe[i].dw;
        in->share[k] = *total > 0 ? acc_e / *total : 0;
    }
}

/* sun plus SH: the sun as the caller picks it (of 64 median-cut regions), exact; the rest of the
 * probe (d, with the suns' regions blacked out) as SH. 0, or -1 with err set. */
static int sunsky(const qtool_probe_info_opts *o, const qtool_study_probe *sp, double *d, double total,
                  const qtool_study_gt *g, qtool_study_model *md, qtool_probe_info *in, char *err, size_t errlen)
{
    int sw = sp->w, sh = sp->h;
    qibl_lightprobe_light_t *L = malloc(sizeof *L * 64);
    if (!L)
        return qtool_errf(err, errlen, "probe info: out of memory");
    qibl_lightprobe_image_t img = {sp->rgbe, (uint32_t)sw, (uint32_t)sh, 0, QIBL_LIGHTPROBE_RGBE, 0};
    int32_t e2 = 0;
    int n = core_lights(&img, 64, L, &e2, err, errlen);
    if (n < 0) {
        free(L);
        return -1;
    }
    uint32_t idx[QTOOL_PROBE_INFO_MAX_SUNS];
    uint32_t ns = o->pick_suns(L, (uint32_t)n, (uint32_t)sw, (uint32_t)sh, idx);
    double sky[3][25], f[5], sunshare = 0;
    memset(md, 0, sizeof *md);
    for (uint32_t k = 0; k < ns; ++k) {
        const qibl_lightprobe_light_t *sun = &L[idx[k]];
        for (uint32_t v = sun->v0; v < sun->v1; ++v)
            for (uint32_t u = sun->u0; u < sun->u1; ++u)
                memset(d + 3 * ((size_t)v * (size_t)sw + u), 0, 3 * sizeof *d);
        for (int c = 0; c < 3; ++c) {
            md->dir[k][c] = sun->dir[c] / 1073741824.0;
            md->rgb[k][c] = ldexp(sun->rgb[c], e2);
        }
        sunshare += luma(md->rgb[k]); /* luminance irradiance: the region's integral of L dw */
    }
    free(L);
    md->n = (int)ns;
    qtool_ref_probe_sh(sw, sh, d, 3, sky);
    qtool_ref_probe_band_factors(3, 1, 0, f);
    md->sh_n = 9;
    for (int l = 0; l < 3; ++l)
        for (int m = -l; m <= l; ++m)
            for (int c = 0; c < 3; ++c)
                md->sh[c][l * l + l + m] = sky[c][l * l + l + m] * f[l];
    qtool_study_err e;
    qtool_study_model_error(md, g, &e);
    in->me[QTOOL_PROBE_SCHEME_SUNSKY] = e.mean_rel, in->mx[QTOOL_PROBE_SCHEME_SUNSKY] = e.max_rel;
    char *x = in->extra[QTOOL_PROBE_SCHEME_SUNSKY];
    if (ns)
        snprintf(x, sizeof in->extra[0], " (%u sun region%s, %.1f %% of the energy)", ns, ns == 1 ? "" : "s",
                 100 * sunshare / total);
    else
        snprintf(x, sizeof in->extra[0], " (no sun: no region %g x the mean radiance)", o->sun_contrast);
    return 0;
}

/* each scheme's error against the probe's own irradiance g; the best and the pick. 0, or -1. */
static int schemes(const qtool_probe_info_opts *o, const char *path, const qtool_study_probe *sp, double *d,
                   double total, const qtool_study_gt *g, qtool_study_model *md, qtool_probe_info *in, char *err,
                   size_t errlen)
{
    char e2[512];
    qtool_study_err e;
    if (qtool_study_core_sh(sp, 9, md, e2, sizeof e2) != 0)
        return qtool_errf(err, errlen, "probe info: %s: %s", path, e2);
    qtool_study_model_error(md, g, &e);
    in->me[QTOOL_PROBE_SCHEME_SH] = e.mean_rel, in->mx[QTOOL_PROBE_SCHEME_SH] = e.max_rel;
    for (int s = QTOOL_PROBE_SCHEME_L16; s <= QTOOL_PROBE_SCHEME_L64; ++s) {
        if (qtool_study_core_lights(sp, QTOOL_STUDY_MEDIANCUT, s == QTOOL_PROBE_SCHEME_L16 ? 16 : 64, md, e2,
                                    sizeof e2) != 0)
            return qtool_errf(err, errlen, "probe info: %s: %s", path, e2);
        qtool_study_model_error(md, g, &e);
        in->me[s] = e.mean_rel, in->mx[s] = e.max_rel;
    }
    if (sunsky(o, sp, d, total, g, md, in, err, errlen) != 0)
        return -1;
    in->best = 0;
    for (int s = 0; s < QTOOL_PROBE_SCHEMES; ++s)
        if (in->me[s] < in->me[in->best])
            in->best = s;
    /* the cheapest scheme whose error is within tie of the best or below good: the order is by cost */
    in->pick = in->best;
    double enough = fmax(in->me[in->best] * o->tie, o->good);
    for (int s = QTOOL_PROBE_SCHEMES - 1; s >= 0; --s)
        if (in->me[s] <= enough)
            in->pick = s;
    return 0;
}

int qtool_probe_info_compute(const qtool_probe_info_opts *o, const char *path, const uint8_t *px, int w, int h,
                             qtool_probe_info *out, char *err, size_t errlen)
{
    qtool_probe_info in;
    memset(&in, 0, sizeof in);
    if (!o->pick_suns)
        return qtool_errf(err, errlen, "probe info: no sun rule (pick_suns)");
    if ((size_t)w != 2 * (size_t)h)
        return qtool_errf(err, errlen, "probe info: %s: %d x %d is not a 2:1 lat-long (the irradiance error is "
                          "measured on one)", path, w, h);
    double total_full, total;
    range_pass(px, w, h, &in, &total_full);
    if (total_full <= 0) {
        in.all_black = 1;
        *out = in;
        return 0;
    }
    /* everything else on the study's probe: at most QTOOL_STUDY_MAX_W wide (box-averaged), so the
     * cost is one pass over the input plus a fixed amount (it was pixels x 1024 normals) */
    qtool_study_probe sp;
    char e2[512];
    if (qtool_study_probe_init(&sp, w, h, px, e2, sizeof e2) != 0)
        return qtool_errf(err, errlen, "probe info: %s: %s", path, e2);
    int rc = -1;
    in.sw = sp.w, in.sh = sp.h;
    size_t sn = (size_t)sp.w * (size_t)sp.h;
    double *d = malloc(sizeof *d * 3 * sn);
    pix_e *pe = malloc(sizeof *pe * sn);
    qtool_study_model *md = malloc(sizeof *md);
    qtool_study_gt g;
    int have_g = 0;
    if (!d || !pe || !md) {
        qtool_errf(err, errlen, "probe info: out of memory");
        goto out;
    }
    concentration(&sp, d, pe, &in, &total);
    /* the probe's own irradiance and each scheme's, by the one measure of tools/study */
    if (qtool_study_gt_compute(&g, &sp, QTOOL_STUDY_ERR_NORMALS, 2) != 0) {
        qtool_errf(err, errlen, "probe info: out of memory");
        goto out;
    }
    have_g = 1, in.normals = g.m;
    if (schemes(o, path, &sp, d, total, &g, md, &in, err, errlen) != 0)
        goto out;
    *out = in;
    rc = 0;
out:
    if (have_g)
        qtool_study_gt_free(&g);
    qtool_study_probe_free(&sp);
    free(d), free(pe), free(md);
    return rc;
}

void qtool_probe_info_write(const qtool_probe_info_opts *o, const qtool_probe_info *in, const char *path,
                            const char *note, FILE *out)
{
    static const char *label[QTOOL_PROBE_SCHEMES] = {"SH, 9 coefficients", "sun plus SH", "16 median-cut lights",
                                                     "64 median-cut lights"};
    static const char *flag[QTOOL_PROBE_SCHEMES] = {"--probe-mode sh", "--probe-mode sunsky",
                                                    "--probe-mode lights -n 16", "--probe-mode lights -n 64"};
    fprintf(out, "%s", note);
    fprintf(out, "size: %d x %d lat-long (%zu pixels, %.2f %% black)\n", in->w, in->h, in->np,
            100.0 * (double)in->black / (double)in->np);
    if (in->all_black) {
        fprintf(out, "an all-black probe: no light; nothing to advise\n");
        return;
    }
    fprintf(out, "luminance: max %.6g, min non-zero %.6g: dynamic range %.1f stops\n", in->lmax, in->lmin,
            log2(in->lmax / in->lmin));
    fprintf(out, "energy: the brightest 0.1 %% of the sphere holds %.1f %%, the brightest 1 %% holds %.1f %%%s\n",
            100 * in->share[0], 100 * in->share[1], in->sw != in->w ? " (at the evaluated size)" : "");
    fprintf(out, "irradiance error against the probe's own over %d normals (mean, max of " QTOOL_STUDY_ERR_WHAT
            ", as qibl lights --auto)", in->normals);
    if (in->sw != in->w)
        fprintf(out, ", the probe box-averaged to %d x %d", in->sw, in->sh);
    fprintf(out, ":\n");
    for (int s = 0; s < QTOOL_PROBE_SCHEMES; ++s)
        fprintf(out, "  %-22s %8.3f %% %8.3f %%%s\n", label[s], 100 * in->me[s], 100 * in->mx[s], in->extra[s]);
    int pick = in->pick, best = in->best;
    const double *me = in->me;
    fprintf(out, "advice: %s (qibl relight ... --probe %s %s): ", label[pick], path, flag[pick]);
    if (pick == QTOOL_PROBE_SCHEME_SH)
        fprintf(out, "the light is soft enough that 9 coefficients hold its irradiance %s\n",
                pick == best ? "best" : me[pick] <= me[best] * o->tie ? "as well as the best, and they are the cheapest"
                                                                      : "within 1 %, and they are the cheapest");
    else if (pick == QTOOL_PROBE_SCHEME_SUNSKY)
        fprintf(out, "a small bright source dominates: light it exactly and leave the rest to SH%s\n",
                pick != best ? " (good enough, and cheaper than the best)" : "");
    else
        fprintf(out, "the lowest mean irradiance error; the light is too concentrated for 9 coefficients%s\n",
                me[QTOOL_PROBE_SCHEME_SH] > 2 * me[pick] ? "" : " (SH is close: it is cheaper)");
}
