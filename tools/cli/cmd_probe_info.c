/*
 * cmd_probe_info.c - `qibl probe info PROBE`: what a probe is (layout, size, dynamic range, how
 * concentrated its energy is) and which lighting scheme fits it: its SH (9 coefficients), N
 * median-cut lights (16, 64) or sun plus SH, each with the irradiance error it gives against the
 * probe's own irradiance, by the one measure of tools/study (study.h: |E - E_gt| / max(E_gt, mean
 * E_gt / 10) per normal and channel, over QTOOL_STUDY_ERR_NORMALS normals, the number `qibl lights
 * --auto` prints for the same representation).
 *
 * The schemes are made as relight makes them: SH by the core's projection (irradiance), lights by
 * the core's median cut, the sun as relight --probe-mode sunsky picks it (qcli_probe_suns) with the
 * rest of the probe's SH from the double reference (tools/ref/probe_ref.c) on the probe with the
 * sun's regions blacked out (what qibl_shlight_add_sun_sky computes in integers).
 *
 * Cost: size and dynamic range are read exactly in one pass over the decoded input; everything else
 * runs on the study's probe, box-averaged to at most QTOOL_STUDY_MAX_W x QTOOL_STUDY_MAX_W / 2 (the
 * ground truth was an exact sum of pixels x 1024 normals: 50 s and 405 MB for a 143 KB RLE file).
 * Output is all or nothing: the report is printed once everything has been computed.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/relight_light.h"
#include "qibl/probe.h"
#include "ref/lightprobe_ref.h"
#include "ref/probe_ref.h"
#include "ref/sh_ref.h"
#include "study/study.h"

#define PI_ 3.14159265358979323846
#define TIE 1.10  /* a scheme within 10 % of the best error counts as as good; the cheaper one is picked */
#define GOOD 0.01 /* so does one with a mean error of 1 % or less (a few 8-bit levels at most) */

static double rgbe_f(uint8_t m, uint8_t e)
{
    return e ? ldexp(m, e - 136) : 0.0;
}

static double luma(const double *c)
{
    return QTOOL_REF_LUMA_R * c[0] + QTOOL_REF_LUMA_G * c[1] + QTOOL_REF_LUMA_B * c[2];
}

typedef struct pix_e {
    double lum, dw;
} pix_e;

static int cmp_desc(const void *a, const void *b)
{
    double x = ((const pix_e *)a)->lum, y = ((const pix_e *)b)->lum;
    return x > y ? -1 : x < y;
}

/* median-cut lights of the probe by the core; count, or -1 after a message */
static int core_lights(const qibl_lightprobe_image_t *img, uint32_t n, qibl_lightprobe_light_t *L, int32_t *exp2)
{
    size_t wn = qibl_lightprobe_workspace_size(img->width, img->height, QIBL_LIGHTPROBE_MEDIANCUT);
    void *ws = wn ? malloc(wn) : NULL;
    if (!ws)
        return fprintf(stderr, "qibl: probe info: out of memory\n"), -1;
    qibl_lightprobe_t lp;
    qibl_lightprobe_result_t res;
    qibl_status_t st = qibl_lightprobe_build(&lp, img, QIBL_LIGHTPROBE_MEDIANCUT, ws, wn);
    if (st == QIBL_OK)
        st = qibl_lightprobe_lights(&lp, NULL, L, n, &res);
    free(ws);
    if (st != QIBL_OK)
        return fprintf(stderr, "qibl: probe info: %s\n", qibl_status_str(st)), -1;
    *exp2 = res.rgb_exp;
    return (int)res.count;
}

int qcli_cmd_probe(int argc, char **argv)
{
    const char *path = NULL;
    qtool_probe_layout_t layout = QTOOL_PROBE_LAYOUT_AUTO;
    if (argc < 2 || strcmp(argv[1], "info") != 0)
        return qcli_usage_error("usage: qibl probe info PROBE.hdr [--layout L]");
    for (int i = 2; i < argc; ++i) {
        if (strcmp(argv[i], "--layout") == 0) {
            if (i + 1 >= argc || qtool_probe_layout_parse(argv[i + 1], &layout) != 0)
                return qcli_usage_error("--layout: '%s' is not auto, latlong, angular, ball, vcross or hcross",
                                        i + 1 < argc ? argv[i + 1] : "");
            ++i;
        } else if (argv[i][0] == '-' || path) {
            return qcli_usage_error("probe info: unexpected '%s' (usage: qibl probe info PROBE.hdr [--layout L])",
                                    argv[i]);
        } else {
            path = argv[i];
        }
    }
    if (!path)
        return qcli_usage_error("usage: qibl probe info PROBE.hdr [--layout L]");
    if (qcli_parse_only) /* fuzz_cliopts: the options only */
        return 0;
    /* Nothing is printed until everything has been computed: a failure leaves stdout empty. */
    char note[4200 + 256], err[512];
    int w, h;
    uint8_t *px;
    if (qcli_probe_load_note(path, layout, note, sizeof note, &w, &h, &px, NULL) != 0)
        return 1;
    if ((size_t)w != 2 * (size_t)h) {
        free(px);
        return fprintf(stderr, "qibl: probe info: %s: %d x %d is not a 2:1 lat-long (the irradiance error is "
                               "measured on one)\n", path, w, h), 1;
    }
    /* size and dynamic range, exact, in one pass over the decoded input (no copy of it) */
    size_t np = (size_t)w * (size_t)h, black = 0;
    double lmax = 0, lmin = INFINITY, total_full = 0;
    for (int v = 0; v < h; ++v) {
        double dw = (2 * PI_ / w) * (PI_ / h) * sin((v + 0.5) * PI_ / h);
        for (int u = 0; u < w; ++u) {
            const uint8_t *q = px + 4 * ((size_t)v * (size_t)w + (size_t)u);
            double c[3] = {rgbe_f(q[0], q[3]), rgbe_f(q[1], q[3]), rgbe_f(q[2], q[3])}, l = luma(c);
            total_full += l * dw;
            if (l > 0)
                lmin = fmin(lmin, l), lmax = fmax(lmax, l);
            else
                ++black;
        }
    }
    if (total_full <= 0) {
        free(px);
        printf("%s", note);
        printf("size: %d x %d lat-long (%zu pixels, %.2f %% black)\n", w, h, np, 100.0 * (double)black / (double)np);
        printf("an all-black probe: no light; nothing to advise\n");
        return 0;
    }
    /* everything else on the study's probe: at most QTOOL_STUDY_MAX_W wide (box-averaged), so the
     * cost is one pass over the input plus a fixed amount (it was pixels x 1024 normals) */
    qtool_study_probe sp;
    int rc = qtool_study_probe_init(&sp, w, h, px, err, sizeof err);
    free(px);
    if (rc != 0)
        return fprintf(stderr, "qibl: probe info: %s: %s\n", path, err), 1;
    rc = 1;
    int sw = sp.w, sh = sp.h;
    size_t sn = (size_t)sw * (size_t)sh;
    double *d = malloc(sizeof *d * 3 * sn);
    pix_e *pe = malloc(sizeof *pe * sn);
    qibl_lightprobe_light_t *L = malloc(sizeof *L * 64);
    qtool_study_model *md = malloc(sizeof *md);
    qtool_study_gt g;
    int have_g = 0;
    if (!d || !pe || !L || !md) {
        fprintf(stderr, "qibl: probe info: out of memory\n");
        goto out;
    }
    /* energy concentration (pixels weighed by their solid angle) */
    double total = 0, sphere = 0, share[2] = {0, 0};
    for (int v = 0; v < sh; ++v) {
        double dw = (2 * PI_ / sw) * (PI_ / sh) * sin((v + 0.5) * PI_ / sh);
        for (int u = 0; u < sw; ++u) {
            size_t i = (size_t)v * (size_t)sw + (size_t)u;
            for (int c = 0; c < 3; ++c)
                d[3 * i + (size_t)c] = rgbe_f(sp.rgbe[4 * i + (size_t)c], sp.rgbe[4 * i + 3]);
            pe[i].lum = luma(d + 3 * i), pe[i].dw = dw;
            total += pe[i].lum * dw, sphere += dw;
        }
    }
    qsort(pe, sn, sizeof *pe, cmp_desc);
    {
        const double want[2] = {0.001, 0.01};
        double acc_w = 0, acc_e = 0;
        size_t i = 0;
        for (int k = 0; k < 2; ++k) {
            for (; i < sn && acc_w < want[k] * sphere; ++i)
                acc_w += pe[i].dw, acc_e += pe[i].lum * pe[i].dw;
            share[k] = total > 0 ? acc_e / total : 0;
        }
    }
    /* the probe's own irradiance and each scheme's, by the one measure of tools/study */
    if (qtool_study_gt_compute(&g, &sp, QTOOL_STUDY_ERR_NORMALS, 2) != 0) {
        fprintf(stderr, "qibl: probe info: out of memory\n");
        goto out;
    }
    have_g = 1;
    enum { S_SH = 0, S_SUNSKY, S_L16, S_L64, S_COUNT };
    const char *label[S_COUNT] = {"SH, 9 coefficients", "sun plus SH", "16 median-cut lights", "64 median-cut lights"};
    const char *flag[S_COUNT] = {"--probe-mode sh", "--probe-mode sunsky", "--probe-mode lights -n 16",
                                 "--probe-mode lights -n 64"};
    double me[S_COUNT], mx[S_COUNT];
    char extra[S_COUNT][64] = {"", "", "", ""};
    qtool_study_err e;
    if (qtool_study_core_sh(&sp, 9, md, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: probe info: %s: %s\n", path, err);
        goto out;
    }
    qtool_study_model_error(md, &g, &e);
    me[S_SH] = e.mean_rel, mx[S_SH] = e.max_rel;
    for (int s = S_L16; s <= S_L64; ++s) {
        if (qtool_study_core_lights(&sp, QTOOL_STUDY_MEDIANCUT, s == S_L16 ? 16 : 64, md, err, sizeof err) != 0) {
            fprintf(stderr, "qibl: probe info: %s: %s\n", path, err);
            goto out;
        }
        qtool_study_model_error(md, &g, &e);
        me[s] = e.mean_rel, mx[s] = e.max_rel;
    }
    {
        /* the sun as relight picks it (of 64 median-cut regions), exact; the rest of the probe as SH */
        qibl_lightprobe_image_t img = {sp.rgbe, (uint32_t)sw, (uint32_t)sh, 0, QIBL_LIGHTPROBE_RGBE, 0};
        int32_t e2;
        int n = core_lights(&img, 64, L, &e2);
        if (n < 0)
            goto out;
        uint32_t idx[QCLI_SUN_MAX];
        uint32_t ns = qcli_probe_suns(L, (uint32_t)n, (uint32_t)sw, (uint32_t)sh, idx);
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
        md->n = (int)ns;
        qtool_ref_probe_sh(sw, sh, d, 3, sky);
        qtool_ref_probe_band_factors(3, 1, 0, f);
        md->sh_n = 9;
        for (int l = 0; l < 3; ++l)
            for (int m = -l; m <= l; ++m)
                for (int c = 0; c < 3; ++c)
                    md->sh[c][l * l + l + m] = sky[c][l * l + l + m] * f[l];
        qtool_study_model_error(md, &g, &e);
        me[S_SUNSKY] = e.mean_rel, mx[S_SUNSKY] = e.max_rel;
        if (ns)
            snprintf(extra[S_SUNSKY], sizeof extra[S_SUNSKY], " (%u sun region%s, %.1f %% of the energy)", ns,
                     ns == 1 ? "" : "s", 100 * sunshare / total);
        else
            snprintf(extra[S_SUNSKY], sizeof extra[S_SUNSKY], " (no sun: no region %g x the mean radiance)",
                     QCLI_SUN_CONTRAST);
    }
    /* all computed: now the report */
    printf("%s", note);
    printf("size: %d x %d lat-long (%zu pixels, %.2f %% black)\n", w, h, np, 100.0 * (double)black / (double)np);
    printf("luminance: max %.6g, min non-zero %.6g: dynamic range %.1f stops\n", lmax, lmin, log2(lmax / lmin));
    printf("energy: the brightest 0.1 %% of the sphere holds %.1f %%, the brightest 1 %% holds %.1f %%%s\n",
           100 * share[0], 100 * share[1], sw != w ? " (at the evaluated size)" : "");
    printf("irradiance error against the probe's own over %d normals (mean, max of " QTOOL_STUDY_ERR_WHAT
           ", as qibl lights --auto)", g.m);
    if (sw != w)
        printf(", the probe box-averaged to %d x %d", sw, sh);
    printf(":\n");
    int best = 0;
    for (int s = 0; s < S_COUNT; ++s) {
        printf("  %-22s %8.3f %% %8.3f %%%s\n", label[s], 100 * me[s], 100 * mx[s], extra[s]);
        if (me[s] < me[best])
            best = s;
    }
    /* the cheapest scheme whose error is within TIE of the best or below GOOD: the order above is by cost */
    int pick = best;
    double enough = fmax(me[best] * TIE, GOOD);
    for (int s = S_COUNT - 1; s >= 0; --s)
        if (me[s] <= enough)
            pick = s;
    printf("advice: %s (qibl relight ... --probe %s %s): ", label[pick], path, flag[pick]);
    if (pick == S_SH)
        printf("the light is soft enough that 9 coefficients hold its irradiance %s\n",
               pick == best ? "best" : me[pick] <= me[best] * TIE ? "as well as the best, and they are the cheapest"
                                                                : "within 1 %, and they are the cheapest");
    else if (pick == S_SUNSKY)
        printf("a small bright source dominates: light it exactly and leave the rest to SH%s\n",
               pick != best ? " (good enough, and cheaper than the best)" : "");
    else
        printf("the lowest mean irradiance error; the light is too concentrated for 9 coefficients%s\n",
               me[S_SH] > 2 * me[pick] ? "" : " (SH is close: it is cheaper)");
    rc = 0;
out:
    if (have_g)
        qtool_study_gt_free(&g);
    qtool_study_probe_free(&sp);
    free(d), free(pe), free(L), free(md);
    return rc;
}
