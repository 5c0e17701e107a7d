/*
 * sunsky.c - sun plus sky: the few brightest regions of the probe as directional lights, the rest
 * of the probe (those regions' pixels taken out) as 9 SH irradiance coefficients, the number of
 * lights chosen by an error budget. What qibl_shlight_add_sun_sky builds at run time; here in
 * double for the study: regions from the core's variance minimisation (64 regions, brightest
 * first: tight around a sun), the sky from the core's SH projection minus the regions' own
 * projection.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "qibl/lightprobe.h"
#include "ref/sh_ref.h"
#include "study/study.h"
#include "qtool.h"

#define REGIONS 64

typedef struct {
    int count;
    qibl_lightprobe_light_t L[REGIONS];
    int32_t rgb_exp;
    qtool_study_model sky; /* the full probe's SH9 */
} sunsky_base;

static int prepare(const qtool_study_probe *p, sunsky_base *b, char *err, size_t errlen)
{
    if (qtool_study_core_sh(p, 9, &b->sky, err, errlen) != 0)
        return -1;
    qibl_lightprobe_result_t res;
    if (qtool_study_probe_lights(p, QIBL_LIGHTPROBE_VARMIN, b->L, REGIONS, &res, "sun+sky", err, errlen) != 0)
        return -1;
    b->count = (int)res.count;
    b->rgb_exp = res.rgb_exp;
    return 0;
}

static void compose(const qtool_study_probe *p, const sunsky_base *b, int k, qtool_study_model *md)
{
    static const double A[3] = {QTOOL_PI, 2 * QTOOL_PI / 3, QTOOL_PI / 4};
    *md = b->sky;
    if (k > b->count)
        k = b->count;
    md->n = k;
    for (int i = 0; i < k; ++i) {
        const qibl_lightprobe_light_t *l = &b->L[i];
        for (int c = 0; c < 3; ++c) {
            md->dir[i][c] = l->dir[c] / 1073741824.0;
            md->rgb[i][c] = ldexp(l->rgb[c], b->rgb_exp);
        }
        for (uint32_t v = l->v0; v < l->v1; ++v) {
            double th = (v + 0.5) * QTOOL_PI / p->h;
            for (uint32_t u = l->u0; u < l->u1; ++u) {
                const double *q = p->q + 3 * ((size_t)v * (size_t)p->w + u);
                if (q[0] == 0 && q[1] == 0 && q[2] == 0)
                    continue;
                double ph = (u + 0.5) * 2 * QTOOL_PI / p->w, Y[9];
                (void)qtool_ref_sh_eval(sin(th) * cos(ph), sin(th) * sin(ph), cos(th), 3, Y);
                for (int j = 0; j < 9; ++j) {
                    double a = A[j == 0 ? 0 : j < 4 ? 1 : 2] * Y[j];
                    for (int c = 0; c < 3; ++c)
                        md->sh[c][j] -= q[c] * a;
                }
            }
        }
    }
}

int qtool_study_sunsky(const qtool_study_probe *p, int k, qtool_study_model *md, char *err, size_t errlen)
{
    sunsky_base *b = malloc(sizeof *b);
    if (!b) {
        snprintf(err, errlen, "sun+sky: out of memory");
        return -1;
    }
    int rc = prepare(p, b, err, errlen);
    if (rc == 0)
        compose(p, b, k, md);
    free(b);
    return rc;
}

/* the base and a trial model, on the heap (both are large) */
static int scratch(sunsky_base **b, qtool_study_model **t, char *err, size_t errlen)
{
    *b = malloc(sizeof **b);
    *t = malloc(sizeof **t);
    if (*b && *t)
        return 0;
    free(*b), free(*t);
    snprintf(err, errlen, "sun+sky: out of memory");
    return -1;
}

int qtool_study_sunsky_budget(const qtool_study_probe *p, const qtool_study_gt *g, double budget, int kmax,
                              qtool_study_model *md, int *k_out, qtool_study_err *e_out, char *err, size_t errlen)
{
    sunsky_base *b;
    qtool_study_model *t;
    if (scratch(&b, &t, err, errlen) != 0)
        return -1;
    int rc = prepare(p, b, err, errlen);
    if (rc == 0) {
        rc = 0;
        double best = INFINITY;
        if (kmax > b->count)
            kmax = b->count;
        for (int k = 0; k <= kmax; ++k) {
            qtool_study_err e;
            compose(p, b, k, t);
            qtool_study_model_error(t, g, &e);
            if (e.mean_rel < best) {
                best = e.mean_rel;
                *md = *t, *k_out = k, *e_out = e;
            }
            if (e.mean_rel <= budget) {
                *md = *t, *k_out = k, *e_out = e;
                rc = 1;
                break;
            }
        }
    }
    free(b), free(t);
    return rc;
}

static double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec * 1e3 + t.tv_nsec / 1e6;
}

int qtool_study_sunsky_sweep(const qtool_study_probe *p, const qtool_study_gt *g, int kmax, qtool_study_err *e,
                             double *ms, qtool_study_model *at16, char *err, size_t errlen)
{
    sunsky_base *b;
    qtool_study_model *t;
    if (scratch(&b, &t, err, errlen) != 0)
        return -1;
    double t0 = now_ms();
    int rc = prepare(p, b, err, errlen);
    double tp = now_ms() - t0;
    for (int k = 0; rc == 0 && k <= kmax; ++k) {
        double t1 = now_ms();
        compose(p, b, k, t);
        ms[k] = tp + now_ms() - t1;
        qtool_study_model_error(t, g, &e[k]);
        if (at16 && (k == kmax || k == 16))
            *at16 = *t;
    }
    free(b), free(t);
    return rc;
}
