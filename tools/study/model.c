/*
 * model.c - a study model (directional lights plus optional SH irradiance), its irradiance at the
 * ground-truth normals and its error there (Madsen & Laursen's per-normal relative measure, floored
 * at a tenth of the mean irradiance, and the same normalised by the mean irradiance).
 */
#include <math.h>

#include "study/study.h"

int qtool_study_model_numbers(const qtool_study_model *md)
{
    return QTOOL_STUDY_FLOATS_PER_LIGHT * md->n + 3 * md->sh_n;
}

void qtool_study_model_eval(const qtool_study_model *md, const qtool_study_gt *g, int k, double E[3])
{
    const double *n = g->nrm[k];
    E[0] = E[1] = E[2] = 0;
    for (int i = 0; i < md->n; ++i) {
        double d = n[0] * md->dir[i][0] + n[1] * md->dir[i][1] + n[2] * md->dir[i][2];
        if (d > 0)
            for (int c = 0; c < 3; ++c)
                E[c] += md->rgb[i][c] * d;
    }
    const double *Y = g->Y + 25 * (size_t)k;
    for (int i = 0; i < md->sh_n; ++i)
        for (int c = 0; c < 3; ++c)
            E[c] += md->sh[c][i] * Y[i];
}

void qtool_study_model_error(const qtool_study_model *md, const qtool_study_gt *g, qtool_study_err *e)
{
    double sr = 0, mr = 0, sn = 0, mn = 0;
    long nr = 0, nn = 0;
    for (int k = 0; k < g->m; ++k) {
        double E[3];
        qtool_study_model_eval(md, g, k, E);
        for (int c = 0; c < 3; ++c) {
            if (!(g->mean[c] > 0))
                continue;
            double d = fabs(E[c] - g->E[3 * k + c]);
            double r = d / fmax(g->E[3 * k + c], QTOOL_STUDY_ERR_FLOOR * g->mean[c]);
            sr += r, ++nr;
            if (r > mr)
                mr = r;
            double q = d / g->mean[c];
            sn += q, ++nn;
            if (q > mn)
                mn = q;
        }
    }
    e->mean_rel = nr ? sr / nr : NAN;
    e->max_rel = nr ? mr : NAN;
    e->mean_norm = nn ? sn / nn : NAN;
    e->max_norm = nn ? mn : NAN;
}
