/*
 * auto.c - `qibl lights --auto --error E`: the cheapest representation of a probe whose mean
 * relative irradiance error is within the budget, counted in floats stored (6 per light: direction
 * and RGB; 3 per SH coefficient). Candidates are what the runtime can use: SH irradiance
 * (4, 9, 16, 25 coefficients), the core's variance-minimisation lights, the same directions with
 * refitted RGB, and sun plus sky (k lights plus SH9, qibl_shlight_add_sun_sky).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "study/study.h"


typedef struct {
    char what[64];
    int floats;
    double err;
} cand;

static void show(FILE *log, const cand *c)
{
    fprintf(log, "  %-34s %6d floats  mean error %7.3f %%\n", c->what, c->floats, 100 * c->err);
}

int qtool_study_auto(const qtool_study_probe *p, double budget, int threads, FILE *log, qtool_study_pick *pick,
                     char *err, size_t errlen)
{
    if (qtool_study_probe_lit(p, err, errlen) != 0)
        return -1;
    qtool_study_gt g;
    if (qtool_study_gt_compute(&g, p, QTOOL_STUDY_ERR_NORMALS, threads) != 0) {
        snprintf(err, errlen, "out of memory for the ground truth");
        return -1;
    }
    /* md: the candidate being evaluated; lm: the last lights candidate measured (a refit that fails
     * leaves md unlike it); bm, cm: the models of best and closest, so the pick can be written */
    qtool_study_model *md = malloc(4 * sizeof *md);
    qtool_study_model *lm = md + 1, *bm = md + 2, *cm = md + 3;
    if (!md) {
        qtool_study_gt_free(&g);
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    cand best = {"", 0, INFINITY}, closest = {"", 0, INFINITY};
    int found = 0, rc = 0;
    qtool_study_err e;
    fprintf(log, "auto: budget %.2f %% mean irradiance error (" QTOOL_STUDY_ERR_WHAT ") over %d normals",
            100 * budget, g.m);
    if (p->w != p->src_w)
        fprintf(log, ", the %d x %d probe box-averaged to %d x %d", p->src_w, p->src_h, p->w, p->h);
    fprintf(log, "; candidates (cheapest meeting it per kind):\n");
    memset(lm, 0, 3 * sizeof *lm); /* lm, bm, cm */
#define CONSIDER(c, m)                                                                                               \
    do {                                                                                                             \
        show(log, &(c));                                                                                             \
        if ((c).err < closest.err)                                                                                   \
            closest = (c), *cm = *(m);                                                                               \
        if ((c).err <= budget && (!found || (c).floats < best.floats))                                              \
            best = (c), *bm = *(m), found = 1;                                                                       \
    } while (0)
    static const int shn[4] = {4, 9, 16, 25};
    for (int k = 0; k < 4; ++k) {
        if (qtool_study_core_sh(p, shn[k], md, err, errlen) != 0) {
            rc = -1;
            goto done;
        }
        qtool_study_model_error(md, &g, &e);
        cand c;
        snprintf(c.what, sizeof c.what, "SH irradiance, %d coefficients", shn[k]);
        c.floats = qtool_study_model_numbers(md), c.err = e.mean_rel;
        if (e.mean_rel <= budget || k == 3) {
            CONSIDER(c, md);
            break;
        }
    }
    /* lights: the smallest N of 1, 2, 3, 4, 6, 8, ... 256 meeting the budget, as sampled and refitted */
    for (int refit = 0; refit < 2; ++refit) {
        cand c = {"", 0, INFINITY};
        for (int n = 1; n <= QTOOL_STUDY_MAX_LIGHTS; n = n < 4 ? n + 1 : n + n / 2) {
            if (qtool_study_core_lights(p, 2 /* varmin */, n, md, err, errlen) != 0) {
                rc = -1;
                goto done;
            }
            if (refit && qtool_study_refit(md, &g) != 0)
                continue;
            qtool_study_model_error(md, &g, &e);
            snprintf(c.what, sizeof c.what, "%d lights (varmin%s)", md->n, refit ? ", RGB refitted" : "");
            c.floats = qtool_study_model_numbers(md), c.err = e.mean_rel;
            *lm = *md;
            if (e.mean_rel <= budget)
                break;
        }
        CONSIDER(c, lm);
    }
    int k;
    int r = qtool_study_sunsky_budget(p, &g, budget, 16, md, &k, &e, err, errlen);
    if (r < 0) {
        rc = -1;
        goto done;
    }
    cand c;
    snprintf(c.what, sizeof c.what, "sun plus sky: %d light%s + SH9", k, k == 1 ? "" : "s");
    c.floats = qtool_study_model_numbers(md), c.err = e.mean_rel;
    CONSIDER(c, md);
    if (found) {
        fprintf(log,
                "auto: choose %s: %d floats, mean error %.3f %% <= %.2f %%; the cheapest candidate within the budget\n",
                best.what, best.floats, 100 * best.err, 100 * budget);
    } else {
        fprintf(log, "auto: no candidate meets %.2f %%; the most accurate is %s (%d floats, %.3f %%)\n", 100 * budget,
                closest.what, closest.floats, 100 * closest.err);
        rc = 1;
    }
    if (pick) {
        const cand *w = found ? &best : &closest;
        memcpy(pick->what, w->what, sizeof pick->what);
        pick->floats = w->floats, pick->err = w->err, pick->met = found;
        pick->model = found ? *bm : *cm;
    }
#undef CONSIDER
done:
    free(md);
    qtool_study_gt_free(&g);
    return rc;
}
