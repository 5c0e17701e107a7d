/*
 * cmd_probe_info.c - `qibl probe info PROBE`: what a probe is (layout, size, dynamic range, how
 * concentrated its energy is) and which lighting scheme fits it: its SH (9 coefficients), N
 * median-cut lights (16, 64) or sun plus SH, each with the irradiance error it gives against the
 * probe's own irradiance (the exact sum over every pixel of tools/ref/lightprobe_ref.c, the measure
 * of `qibl lights --error` and `qibl bench lights`).
 *
 * The schemes are made as relight makes them: SH by the core's projection (qibl_probe_sh_project,
 * irradiance), lights by the core's median cut, the sun as relight --probe-mode sunsky picks it
 * (qcli_probe_suns) with the rest of the probe's SH from the double reference (tools/ref/probe_ref.c)
 * on the probe with the sun's regions blacked out (what qibl_shlight_add_sun_sky computes in integers).
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

#define PI_ 3.14159265358979323846
#define NNORM 1024
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

/* mean and max |E - E_probe| over the normals, as fractions of the mean E_probe */
static void err_of(const double *E, const double *Ep, double *me, double *mx)
{
    double mean = 0, s = 0, m = 0;
    for (int i = 0; i < NNORM; ++i)
        mean += Ep[i];
    mean /= NNORM;
    for (int i = 0; i < NNORM; ++i) {
        double e = fabs(E[i] - Ep[i]);
        s += e, m = fmax(m, e);
    }
    *me = mean > 0 ? s / NNORM / mean : 0;
    *mx = mean > 0 ? m / mean : 0;
}

/* E(n) of luminance irradiance SH (9 coefficients) at the normals */
static void sh_irr(const double lum[9], const double (*nrm)[3], double *E)
{
    for (int k = 0; k < NNORM; ++k) {
        double y[9], e = 0;
        qtool_ref_sh_eval(nrm[k][0], nrm[k][1], nrm[k][2], 3, y);
        for (int i = 0; i < 9; ++i)
            e += lum[i] * y[i];
        E[k] = e;
    }
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

static void to_ref(const qibl_lightprobe_light_t *L, int n, int32_t e, qtool_ref_light *R)
{
    for (int i = 0; i < n; ++i) {
        memset(&R[i], 0, sizeof R[i]);
        for (int c = 0; c < 3; ++c) {
            R[i].dir[c] = L[i].dir[c] / 1073741824.0;
            R[i].rgb[c] = ldexp(L[i].rgb[c], e);
        }
    }
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
    int w, h;
    uint8_t *px;
    if (qcli_probe_load(path, layout, stdout, &w, &h, &px, NULL) != 0)
        return 1;
    size_t np = (size_t)w * (size_t)h;
    double *d = malloc(sizeof *d * 3 * np);
    pix_e *pe = malloc(sizeof *pe * np);
    double (*nrm)[3] = malloc(sizeof *nrm * NNORM);
    double *Ep = malloc(sizeof *Ep * NNORM), *E = malloc(sizeof *E * NNORM);
    qibl_lightprobe_light_t *L = malloc(sizeof *L * 64);
    qtool_ref_light *R = malloc(sizeof *R * 64);
    size_t wsn = qibl_probe_sh_workspace_size((uint32_t)w, (uint32_t)h);
    void *ws = wsn ? malloc(wsn) : NULL;
    qtool_ref_probe rp;
    int rc = 1, have_rp = 0;
    if (!d || !pe || !nrm || !Ep || !E || !L || !R || !ws) {
        fprintf(stderr, "qibl: probe info: %s\n", wsn ? "out of memory" : "probe beyond the size limits");
        goto out;
    }
    /* size, dynamic range, energy concentration (pixels weighed by their solid angle) */
    double lmax = 0, lmin = INFINITY, total = 0, sphere = 0;
    size_t black = 0;
    for (int v = 0; v < h; ++v) {
        double dw = (2 * PI_ / w) * (PI_ / h) * sin((v + 0.5) * PI_ / h);
        for (int u = 0; u < w; ++u) {
            size_t i = (size_t)v * (size_t)w + (size_t)u;
            for (int c = 0; c < 3; ++c)
                d[3 * i + (size_t)c] = rgbe_f(px[4 * i + (size_t)c], px[4 * i + 3]);
            double l = luma(d + 3 * i);
            pe[i].lum = l, pe[i].dw = dw;
            total += l * dw, sphere += dw;
            if (l > 0)
                lmin = fmin(lmin, l), lmax = fmax(lmax, l);
            else
                ++black;
        }
    }
    printf("size: %d x %d lat-long (%zu pixels, %.2f %% black)\n", w, h, np, 100.0 * (double)black / (double)np);
    if (total <= 0) {
        printf("an all-black probe: no light; nothing to advise\n");
        rc = 0;
        goto out;
    }
    printf("luminance: max %.6g, min non-zero %.6g: dynamic range %.1f stops\n", lmax, lmin, log2(lmax / lmin));
    qsort(pe, np, sizeof *pe, cmp_desc);
    {
        const double want[2] = {0.001, 0.01};
        double acc_w = 0, acc_e = 0, share[2] = {0, 0};
        size_t i = 0;
        for (int k = 0; k < 2; ++k) {
            for (; i < np && acc_w < want[k] * sphere; ++i)
                acc_w += pe[i].dw, acc_e += pe[i].lum * pe[i].dw;
            share[k] = acc_e / total;
        }
        printf("energy: the brightest 0.1 %% of the sphere holds %.1f %%, the brightest 1 %% holds %.1f %%\n",
               100 * share[0], 100 * share[1]);
    }
    /* the probe's own irradiance, exact, and each scheme's */
    if (qtool_ref_probe_init(&rp, w, h, d) != 0) {
        fprintf(stderr, "qibl: probe info: out of memory\n");
        goto out;
    }
    have_rp = 1;
    qtool_ref_sphere_dirs(NNORM, nrm);
    qtool_ref_probe_irradiance(&rp, NNORM, (const double (*)[3])nrm, Ep, 2);
    enum { S_SH = 0, S_SUNSKY, S_L16, S_L64, S_COUNT };
    const char *label[S_COUNT] = {"SH, 9 coefficients", "sun plus SH", "16 median-cut lights", "64 median-cut lights"};
    const char *flag[S_COUNT] = {"--probe-mode sh", "--probe-mode sunsky", "--probe-mode lights -n 16",
                                 "--probe-mode lights -n 64"};
    double me[S_COUNT], mx[S_COUNT];
    char extra[S_COUNT][64] = {"", "", "", ""};
    qibl_lightprobe_image_t img = {px, (uint32_t)w, (uint32_t)h, 0, QIBL_LIGHTPROBE_RGBE, 0};
    {
        qibl_probe_sh_opts_t o = {1, QIBL_PROBE_WINDOW_NONE, 0};
        qibl_probe_coeffs_t c;
        qibl_status_t st = qibl_probe_sh_project(&img, 3, &o, ws, wsn, &c);
        if (st != QIBL_OK) {
            fprintf(stderr, "qibl: %s: %s\n", path, qibl_status_str(st));
            goto out;
        }
        double lum[9];
        for (int i = 0; i < 9; ++i) {
            double rgb[3] = {ldexp(c.c[0][i], c.exp), ldexp(c.c[1][i], c.exp), ldexp(c.c[2][i], c.exp)};
            lum[i] = luma(rgb);
        }
        sh_irr(lum, (const double (*)[3])nrm, E);
        err_of(E, Ep, &me[S_SH], &mx[S_SH]);
    }
    int32_t e2;
    for (int s = S_L16; s <= S_L64; ++s) {
        int n = core_lights(&img, s == S_L16 ? 16 : 64, L, &e2);
        if (n < 0)
            goto out;
        to_ref(L, n, e2, R);
        qtool_ref_irradiance_error(R, n, NNORM, (const double (*)[3])nrm, Ep, &me[s], &mx[s]);
    }
    {
        /* L holds the 64 lights: the sun as relight picks it, exact; the rest of the probe as SH */
        int n = core_lights(&img, 64, L, &e2);
        if (n < 0)
            goto out;
        uint32_t idx[QCLI_SUN_MAX];
        uint32_t ns = qcli_probe_suns(L, (uint32_t)n, (uint32_t)w, (uint32_t)h, idx);
        qibl_lightprobe_light_t sun[QCLI_SUN_MAX];
        memset(sun, 0, sizeof sun); /* gcc -O2 cannot see that to_ref reads only the ns set above */
        double sky[3][25], f[5], lum[9], sunshare = 0;
        for (uint32_t k = 0; k < ns; ++k) {
            sun[k] = L[idx[k]];
            for (uint32_t v = sun[k].v0; v < sun[k].v1; ++v)
                for (uint32_t u = sun[k].u0; u < sun[k].u1; ++u)
                    memset(d + 3 * ((size_t)v * (size_t)w + u), 0, 3 * sizeof *d);
        }
        to_ref(sun, (int)ns, e2, R);
        for (uint32_t k = 0; k < ns; ++k)
            sunshare += luma(R[k].rgb);
        qtool_ref_probe_sh(w, h, d, 3, sky);
        qtool_ref_probe_band_factors(3, 1, 0, f);
        for (int l = 0; l < 3; ++l)
            for (int m = -l; m <= l; ++m) {
                int i = l * l + l + m;
                double rgb[3] = {sky[0][i] * f[l], sky[1][i] * f[l], sky[2][i] * f[l]};
                lum[i] = luma(rgb);
            }
        sh_irr(lum, (const double (*)[3])nrm, E);
        for (int k = 0; k < NNORM; ++k)
            E[k] += qtool_ref_lights_irradiance(R, (int)ns, nrm[k]);
        err_of(E, Ep, &me[S_SUNSKY], &mx[S_SUNSKY]);
        /* luminance irradiance share: sum rgb is the region's integral of L dw */
        if (ns)
            snprintf(extra[S_SUNSKY], sizeof extra[S_SUNSKY], " (%u sun region%s, %.1f %% of the energy)", ns,
                     ns == 1 ? "" : "s", 100 * sunshare / total);
        else
            snprintf(extra[S_SUNSKY], sizeof extra[S_SUNSKY], " (no sun: no region %g x the mean radiance)",
                     QCLI_SUN_CONTRAST);
    }
    printf("irradiance error against the probe's own over %d normals (mean, max; of the mean irradiance):\n", NNORM);
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
    if (have_rp)
        qtool_ref_probe_free(&rp);
    free(px), free(d), free(pe), free(nrm), free(Ep), free(E), free(L), free(R), free(ws);
    return rc;
}
