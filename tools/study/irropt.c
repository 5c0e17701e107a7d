/*
 * irropt.c - irradiance optimisation (Madsen, Sorensen & Vittrup 2003, as Madsen & Laursen 2006
 * describe it): N directional lights, 5 parameters each (RGB and the two angles of the direction),
 * fitted to the ground-truth irradiance of many normals by Levenberg-Marquardt with the analytic
 * Jacobian of E(n) = sum_i rgb_i max(0, n . w(theta_i, phi_i)). RGB is kept >= 0 by projection (a
 * channel at 0 whose gradient pushes it below is held for that step). Rows are weighted as the
 * refit's, 1 / (E_gt + mean E_gt / 10).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "study/study.h"

typedef struct {
    int n, fit, P;
    const qtool_study_gt *g;
    int *rows;      /* the fit normals' indices in g */
    double *wt;     /* their weights */
} problem;

static void dir_of(double th, double ph, double d[3], double dth[3], double dph[3])
{
    double st = sin(th), ct = cos(th), sp = sin(ph), cp = cos(ph);
    d[0] = st * cp, d[1] = st * sp, d[2] = ct;
    if (dth)
        dth[0] = ct * cp, dth[1] = ct * sp, dth[2] = -st;
    if (dph)
        dph[0] = -st * sp, dph[1] = st * cp, dph[2] = 0;
}

static double cost(const problem *pr, const double *x)
{
    double s = 0;
    for (int r = 0; r < pr->fit; ++r) {
        const double *nk = pr->g->nrm[pr->rows[r]];
        double E[3] = {0, 0, 0};
        for (int i = 0; i < pr->n; ++i) {
            double d[3];
            dir_of(x[5 * i], x[5 * i + 1], d, 0, 0);
            double c = nk[0] * d[0] + nk[1] * d[1] + nk[2] * d[2];
            if (c > 0)
                for (int ch = 0; ch < 3; ++ch)
                    E[ch] += x[5 * i + 2 + ch] * c;
        }
        for (int ch = 0; ch < 3; ++ch) {
            double e = pr->wt[r] * (E[ch] - pr->g->E[3 * pr->rows[r] + ch]);
            s += e * e;
        }
    }
    return s;
}

/* J^T J (upper triangle, then mirrored) and J^T r at x */
static void normal_eq(const problem *pr, const double *x, double *A, double *b, int *idx, double *val,
                      double (*D)[9])
{
    const int P = pr->P;
    memset(A, 0, sizeof *A * (size_t)P * (size_t)P);
    memset(b, 0, sizeof *b * (size_t)P);
    for (int i = 0; i < pr->n; ++i)
        dir_of(x[5 * i], x[5 * i + 1], D[i], D[i] + 3, D[i] + 6);
    for (int r = 0; r < pr->fit; ++r) {
        const double *nk = pr->g->nrm[pr->rows[r]];
        const double w = pr->wt[r];
        int na = 0;
        double E[3] = {0, 0, 0};
        int act[QTOOL_STUDY_MAX_LIGHTS];
        double cs[QTOOL_STUDY_MAX_LIGHTS], ct[QTOOL_STUDY_MAX_LIGHTS], cp[QTOOL_STUDY_MAX_LIGHTS];
        for (int i = 0; i < pr->n; ++i) {
            double c = nk[0] * D[i][0] + nk[1] * D[i][1] + nk[2] * D[i][2];
            if (c <= 0)
                continue;
            act[na] = i, cs[na] = c;
            ct[na] = nk[0] * D[i][3] + nk[1] * D[i][4] + nk[2] * D[i][5];
            cp[na] = nk[0] * D[i][6] + nk[1] * D[i][7] + nk[2] * D[i][8];
            ++na;
            for (int ch = 0; ch < 3; ++ch)
                E[ch] += x[5 * i + 2 + ch] * c;
        }
        for (int ch = 0; ch < 3; ++ch) {
            double res = w * (E[ch] - pr->g->E[3 * pr->rows[r] + ch]);
            int m = 0;
            for (int a = 0; a < na; ++a) {
                int i = act[a];
                double L = x[5 * i + 2 + ch];
                idx[m] = 5 * i, val[m++] = w * L * ct[a];
                idx[m] = 5 * i + 1, val[m++] = w * L * cp[a];
                idx[m] = 5 * i + 2 + ch, val[m++] = w * cs[a];
            }
            for (int p = 0; p < m; ++p) {
                double vp = val[p];
                double *row = A + (size_t)idx[p] * (size_t)P;
                for (int q = p; q < m; ++q)
                    row[idx[q]] += vp * val[q];
                b[idx[p]] += vp * res;
            }
        }
    }
    /* idx is ascending within a row, so every product landed in the upper triangle */
    for (int i = 0; i < P; ++i)
        for (int j = i + 1; j < P; ++j)
            A[(size_t)j * (size_t)P + (size_t)i] = A[(size_t)i * (size_t)P + (size_t)j];
}

/* solves M d = rhs in place (M P x P symmetric positive definite, destroyed); 0 or -1 */
static int cholesky_solve(int P, double *M, double *rhs)
{
    for (int j = 0; j < P; ++j) {
        double *rj = M + (size_t)j * (size_t)P;
        double s = rj[j];
        for (int k = 0; k < j; ++k)
            s -= rj[k] * rj[k];
        if (!(s > 0))
            return -1;
        rj[j] = sqrt(s);
        for (int i = j + 1; i < P; ++i) {
            double *ri = M + (size_t)i * (size_t)P;
            double t = ri[j];
            for (int k = 0; k < j; ++k)
                t -= ri[k] * rj[k];
            ri[j] = t / rj[j];
        }
    }
    qtool_study_chol_solve(M, P, rhs);
    return 0;
}

int qtool_study_irropt(qtool_study_model *md, const qtool_study_gt *g, int fit, int max_iter, int *iters)
{
    *iters = 0;
    if (md->n < 1 || md->sh_n != 0 || fit < 1)
        return -1;
    if (fit > g->m)
        fit = g->m;
    problem pr = {md->n, fit, 5 * md->n, g, NULL, NULL};
    const int P = pr.P;
    pr.rows = malloc(sizeof *pr.rows * (size_t)fit);
    pr.wt = malloc(sizeof *pr.wt * (size_t)fit);
    double *x = malloc(sizeof *x * (size_t)P), *xn = malloc(sizeof *xn * (size_t)P);
    double *A = malloc(sizeof *A * (size_t)P * (size_t)P), *M = malloc(sizeof *M * (size_t)P * (size_t)P);
    double *b = malloc(sizeof *b * (size_t)P), *d = malloc(sizeof *d * (size_t)P);
    int *idx = malloc(sizeof *idx * 3 * (size_t)md->n);
    double *val = malloc(sizeof *val * 3 * (size_t)md->n);
    double (*D)[9] = malloc(sizeof *D * (size_t)md->n);
    char *hold = malloc((size_t)P);
    int rc = -1;
    if (!pr.rows || !pr.wt || !x || !xn || !A || !M || !b || !d || !idx || !val || !D || !hold)
        goto done;
    const double mall = (g->mean[0] + g->mean[1] + g->mean[2]) / 3;
    for (int r = 0; r < fit; ++r) {
        int k = (int)((long)r * g->m / fit);
        pr.rows[r] = k;
        pr.wt[r] = 1.0 / ((g->E[3 * k] + g->E[3 * k + 1] + g->E[3 * k + 2]) / 3 + 0.1 * mall);
    }
    for (int i = 0; i < md->n; ++i) {
        const double *v = md->dir[i];
        x[5 * i] = acos(fmax(-1.0, fmin(1.0, v[2])));
        x[5 * i + 1] = atan2(v[1], v[0]);
        for (int c = 0; c < 3; ++c)
            x[5 * i + 2 + c] = md->rgb[i][c];
    }
    double f = cost(&pr, x), lambda = 1e-3;
    int converged = 0, it = 0;
    for (; it < max_iter && !converged; ++it) {
        normal_eq(&pr, x, A, b, idx, val, D);
        double gmax = 0;
        for (int p = 0; p < P; ++p) {
            /* an RGB parameter at 0 that the gradient pushes below 0 is held this step */
            hold[p] = p % 5 >= 2 && x[p] <= 0 && b[p] > 0;
            if (!hold[p])
                gmax = fmax(gmax, fabs(b[p]) / sqrt(A[(size_t)p * (size_t)P + (size_t)p] + 1e-300));
        }
        if (gmax <= 1e-12 * sqrt(f + 1e-300)) {
            converged = 1;
            break;
        }
        for (;;) {
            memcpy(M, A, sizeof *M * (size_t)P * (size_t)P);
            for (int p = 0; p < P; ++p) {
                double *row = M + (size_t)p * (size_t)P;
                if (hold[p]) {
                    for (int q = 0; q < P; ++q)
                        row[q] = M[(size_t)q * (size_t)P + (size_t)p] = 0;
                    row[p] = 1;
                    d[p] = 0;
                } else {
                    row[p] += lambda * row[p] + 1e-12 * (row[p] + 1e-300);
                    d[p] = -b[p];
                }
            }
            for (int p = 0; p < P; ++p) /* a held column may have been re-filled by a later row */
                if (hold[p])
                    for (int q = 0; q < P; ++q)
                        if (q != p)
                            M[(size_t)p * (size_t)P + (size_t)q] = M[(size_t)q * (size_t)P + (size_t)p] = 0;
            int ok = cholesky_solve(P, M, d) == 0;
            if (ok) {
                for (int p = 0; p < P; ++p) {
                    xn[p] = x[p] + d[p];
                    if (p % 5 >= 2 && xn[p] < 0)
                        xn[p] = 0;
                }
                double fn = cost(&pr, xn);
                if (fn < f) {
                    if ((f - fn) < 1e-6 * f)
                        converged = 1;
                    memcpy(x, xn, sizeof *x * (size_t)P);
                    f = fn;
                    lambda = fmax(lambda / 3, 1e-9);
                    break;
                }
            }
            lambda *= 4;
            if (lambda > 1e10)
                break;
        }
        if (lambda > 1e10)
            break; /* no step lowers the cost any more, yet the gradient is not zero */
    }
    *iters = it;
    for (int i = 0; i < md->n; ++i) {
        dir_of(x[5 * i], x[5 * i + 1], md->dir[i], 0, 0);
        for (int c = 0; c < 3; ++c)
            md->rgb[i][c] = x[5 * i + 2 + c];
    }
    rc = converged;
done:
    free(pr.rows), free(pr.wt), free(x), free(xn), free(A), free(M), free(b), free(d), free(idx), free(val), free(D),
        free(hold);
    return rc;
}
