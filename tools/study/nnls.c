/*
 * nnls.c - non-negative least squares (Lawson & Hanson's active-set method, on the normal
 * equations) and the refit that uses it: a light list's directions kept, its RGB solved against
 * the ground-truth irradiance. Linear in the RGB, so it always converges (unlike optimising the
 * directions too).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "study/study.h"

void qtool_study_chol_solve(const double *L, int k, double *b)
{
    for (int i = 0; i < k; ++i) {
        double s = b[i];
        for (int t = 0; t < i; ++t)
            s -= L[(size_t)i * (size_t)k + (size_t)t] * b[t];
        b[i] = s / L[(size_t)i * (size_t)k + (size_t)i];
    }
    for (int i = k; i-- > 0;) {
        double s = b[i];
        for (int t = i + 1; t < k; ++t)
            s -= L[(size_t)t * (size_t)k + (size_t)i] * b[t];
        b[i] = s / L[(size_t)i * (size_t)k + (size_t)i];
    }
}

/* Solves G_PP z = h_P (P: the indices with in[i]) by Cholesky; 0, or -1 if not positive definite. */
static int solve_passive(int n, const double *G, const double *h, const char *in, double *z, double *L, int *idx)
{
    int k = 0;
    for (int i = 0; i < n; ++i)
        if (in[i])
            idx[k++] = i;
    for (int i = 0; i < k; ++i)
        for (int j = 0; j <= i; ++j) {
            double s = G[(size_t)idx[i] * (size_t)n + (size_t)idx[j]];
            for (int t = 0; t < j; ++t)
                s -= L[(size_t)i * (size_t)k + (size_t)t] * L[(size_t)j * (size_t)k + (size_t)t];
            if (i == j) {
                if (!(s > 1e-300))
                    return -1;
                L[(size_t)i * (size_t)k + (size_t)i] = sqrt(s);
            } else {
                L[(size_t)i * (size_t)k + (size_t)j] = s / L[(size_t)j * (size_t)k + (size_t)j];
            }
        }
    double *y = z + n; /* scratch after z */
    for (int i = 0; i < k; ++i)
        y[i] = h[idx[i]];
    qtool_study_chol_solve(L, k, y);
    for (int i = 0; i < n; ++i)
        z[i] = 0;
    for (int i = 0; i < k; ++i)
        z[idx[i]] = y[i];
    return 0;
}

int qtool_study_nnls(int n, const double *G, const double *h, double *x)
{
    if (n < 1 || n > QTOOL_STUDY_MAX_LIGHTS)
        return -1;
    char *in = calloc((size_t)n, 1);
    double *z = malloc(2 * (size_t)n * sizeof *z), *wv = malloc((size_t)n * sizeof *wv);
    double *L = malloc((size_t)n * (size_t)n * sizeof *L);
    int *idx = malloc((size_t)n * sizeof *idx);
    if (!in || !z || !wv || !L || !idx) {
        free(in), free(z), free(wv), free(L), free(idx);
        return -1;
    }
    for (int i = 0; i < n; ++i)
        x[i] = 0;
    double hs = 0;
    for (int i = 0; i < n; ++i)
        hs = fmax(hs, fabs(h[i]));
    const double tol = 1e-12 * (hs > 0 ? hs : 1);
    int it = 0, ok = 0;
    for (; it < 3 * n + 3; ++it) {
        /* gradient of -1/2 |Ax - b|^2: w = h - G x */
        int best = -1;
        for (int i = 0; i < n; ++i) {
            double s = h[i];
            for (int j = 0; j < n; ++j)
                s -= G[(size_t)i * (size_t)n + (size_t)j] * x[j];
            wv[i] = s;
            if (!in[i] && s > tol && (best < 0 || s > wv[best]))
                best = i;
        }
        if (best < 0) {
            ok = 1;
            break;
        }
        in[best] = 1;
        for (;;) {
            if (solve_passive(n, G, h, in, z, L, idx) != 0) {
                in[best] = 0; /* dependent column: leave it out */
                ok = 1;
                break;
            }
            int allpos = 1;
            for (int i = 0; i < n; ++i)
                if (in[i] && z[i] <= 0)
                    allpos = 0;
            if (allpos) {
                memcpy(x, z, (size_t)n * sizeof *x);
                break;
            }
            double alpha = 2;
            int jmin = -1;
            for (int i = 0; i < n; ++i)
                if (in[i] && z[i] <= 0) {
                    double a = x[i] / (x[i] - z[i]);
                    if (a < alpha)
                        alpha = a, jmin = i;
                }
            for (int i = 0; i < n; ++i) {
                x[i] += alpha * (z[i] - x[i]);
                if (in[i] && (i == jmin || x[i] <= 0)) /* the blocking one leaves: progress */
                    in[i] = 0, x[i] = 0;
            }
        }
        if (ok)
            break;
    }
    free(in), free(z), free(wv), free(L), free(idx);
    return ok ? it : -1;
}

int qtool_study_refit(qtool_study_model *md, const qtool_study_gt *g)
{
    const int n = md->n;
    if (n < 1 || md->sh_n != 0)
        return -1;
    double *G = calloc((size_t)n * (size_t)n, sizeof *G), *a = malloc((size_t)n * sizeof *a);
    double *h = calloc(3 * (size_t)n, sizeof *h), *x = malloc((size_t)n * sizeof *x);
    int *act = malloc((size_t)n * sizeof *act);
    int rc = 0;
    if (!G || !a || !h || !x || !act) {
        rc = -1;
        goto done;
    }
    /* one weight per normal (luminance-like, the channels' mean): G is shared by the channels */
    const double mall = (g->mean[0] + g->mean[1] + g->mean[2]) / 3;
    for (int k = 0; k < g->m; ++k) {
        const double *nk = g->nrm[k];
        double e = (g->E[3 * k] + g->E[3 * k + 1] + g->E[3 * k + 2]) / 3;
        double w = 1.0 / (e + 0.1 * mall), w2 = w * w;
        int na = 0;
        for (int i = 0; i < n; ++i) {
            double d = nk[0] * md->dir[i][0] + nk[1] * md->dir[i][1] + nk[2] * md->dir[i][2];
            if (d > 0)
                a[na] = d, act[na++] = i;
        }
        for (int p = 0; p < na; ++p) {
            double ap = a[p] * w2;
            double *row = G + (size_t)act[p] * (size_t)n;
            for (int q = 0; q <= p; ++q)
                row[act[q]] += ap * a[q];
            for (int c = 0; c < 3; ++c)
                h[(size_t)c * (size_t)n + (size_t)act[p]] += ap * g->E[3 * k + c];
        }
    }
    for (int i = 0; i < n; ++i) /* filled the lower triangle in act order: mirror both ways */
        for (int j = 0; j < i; ++j) {
            double s = G[(size_t)i * (size_t)n + (size_t)j] + G[(size_t)j * (size_t)n + (size_t)i];
            G[(size_t)i * (size_t)n + (size_t)j] = G[(size_t)j * (size_t)n + (size_t)i] = s;
        }
    for (int c = 0; c < 3; ++c) {
        if (qtool_study_nnls(n, G, h + (size_t)c * (size_t)n, x) < 0) {
            rc = -1;
            goto done;
        }
        for (int i = 0; i < n; ++i)
            md->rgb[i][c] = x[i];
    }
done:
    free(G), free(a), free(h), free(x), free(act);
    return rc;
}
