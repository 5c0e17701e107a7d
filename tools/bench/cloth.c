/*
 * cloth.c - the animated cloth of `qibl bench hemi` and qibl-bench's raster comparison (cloth.h):
 * a mass-spring grid simulated in double, its coarse mesh and each vertex's blocker lists.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bench/cloth.h"

static void relax(double *x, int a, int b, double rest)
{
    double d[3], l = 0;
    for (int k = 0; k < 3; ++k)
        d[k] = x[3 * b + k] - x[3 * a + k], l += d[k] * d[k];
    l = sqrt(l);
    if (l <= 0)
        return;
    const double c = 0.5 * (l - rest) / l;
    for (int k = 0; k < 3; ++k)
        x[3 * a + k] += c * d[k], x[3 * b + k] -= c * d[k];
}

int qtool_bench_cloth_make(qtool_bench_cloth *s, int nframes)
{
    const int nv = CLOTH_G * CLOTH_G;
    const double h = 2.0 / (CLOTH_G - 1), R = 0.55;
    double *x = malloc(sizeof(double) * 3 * nv), *xp = malloc(sizeof(double) * 3 * nv);
    s->frames = malloc(sizeof(double) * 3 * (size_t)nv * (size_t)nframes);
    s->tri = malloc(sizeof *s->tri * 2 * (CLOTH_G - 1) * (CLOTH_G - 1));
    if (!x || !xp || !s->frames || !s->tri)
        return -1;
    s->nv = nv, s->nframes = nframes, s->ntri = 0;
    for (int j = 0; j < CLOTH_G; ++j)
        for (int i = 0; i < CLOTH_G; ++i) {
            double *p = x + 3 * (j * CLOTH_G + i);
            /* a slight skew so the folds are not symmetric */
            p[0] = -1 + i * h, p[1] = -1 + j * h + 0.05 * (i * h - 1) * (i * h - 1), p[2] = 0.75 + 0.1 * i * h;
        }
    memcpy(xp, x, sizeof(double) * 3 * nv);
    for (int j = 0; j + 1 < CLOTH_G; ++j)
        for (int i = 0; i + 1 < CLOTH_G; ++i) {
            const uint32_t a = (uint32_t)(j * CLOTH_G + i), b = a + 1, c = a + CLOTH_G + 1, d = a + CLOTH_G;
            s->tri[s->ntri][0] = a, s->tri[s->ntri][1] = b, s->tri[s->ntri][2] = c, s->ntri++;
            s->tri[s->ntri][0] = a, s->tri[s->ntri][1] = c, s->tri[s->ntri][2] = d, s->ntri++;
        }
    const double dt = 1.0 / 120, gz = -9.8 * dt * dt;
    const int first = 70, every = 12;
    int f = 0;
    for (int step = 0; f < nframes; ++step) {
        for (int v = 0; v < nv; ++v)
            for (int k = 0; k < 3; ++k) {
                const double cur = x[3 * v + k], vel = (cur - xp[3 * v + k]) * 0.995;
                xp[3 * v + k] = cur;
                x[3 * v + k] = cur + vel + (k == 2 ? gz : 0);
            }
        for (int it = 0; it < 12; ++it) {
            for (int j = 0; j < CLOTH_G; ++j)
                for (int i = 0; i < CLOTH_G; ++i) {
                    const int a = j * CLOTH_G + i;
                    if (i + 1 < CLOTH_G)
                        relax(x, a, a + 1, h);
                    if (j + 1 < CLOTH_G)
                        relax(x, a, a + CLOTH_G, h);
                    if (i + 1 < CLOTH_G && j + 1 < CLOTH_G)
                        relax(x, a, a + CLOTH_G + 1, h * sqrt(2.0)), relax(x, a + 1, a + CLOTH_G, h * sqrt(2.0));
                    if (i + 2 < CLOTH_G)
                        relax(x, a, a + 2, 2 * h);
                    if (j + 2 < CLOTH_G)
                        relax(x, a, a + 2 * CLOTH_G, 2 * h);
                }
            for (int v = 0; v < nv; ++v) { /* the sphere, and a floor at z = -1 */
                double *p = x + 3 * v, l = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
                if (l < R + 0.01)
                    for (int k = 0; k < 3; ++k)
                        p[k] *= (R + 0.01) / l;
                if (p[2] < -1)
                    p[2] = -1;
            }
        }
        if (step >= first && (step - first) % every == 0)
            memcpy(s->frames + 3 * (size_t)nv * (size_t)f++, x, sizeof(double) * 3 * nv);
    }
    free(x), free(xp);
    /* coarse mesh: every CLOTH_STEP-th grid vertex */
    s->ncv = CLOTH_CG * CLOTH_CG, s->nct = 0;
    s->cvert = malloc(sizeof(int) * (size_t)s->ncv);
    s->ctri = malloc(sizeof *s->ctri * 2 * (CLOTH_CG - 1) * (CLOTH_CG - 1));
    if (!s->cvert || !s->ctri)
        return -1;
    for (int j = 0; j < CLOTH_CG; ++j)
        for (int i = 0; i < CLOTH_CG; ++i)
            s->cvert[j * CLOTH_CG + i] = (j * CLOTH_STEP) * CLOTH_G + i * CLOTH_STEP;
    for (int j = 0; j + 1 < CLOTH_CG; ++j)
        for (int i = 0; i + 1 < CLOTH_CG; ++i) {
            const uint32_t a = (uint32_t)(j * CLOTH_CG + i), b = a + 1, c = a + CLOTH_CG + 1, d = a + CLOTH_CG;
            s->ctri[s->nct][0] = a, s->ctri[s->nct][1] = b, s->ctri[s->nct][2] = c, s->nct++;
            s->ctri[s->nct][0] = a, s->ctri[s->nct][1] = c, s->ctri[s->nct][2] = d, s->nct++;
        }
    return 0;
}

/* Per vertex blockers: the coarse triangles except those of the coarse cells that overlap the
 * vertex's two-ring window, and in their place the full-resolution triangles of those cells (a
 * coarse triangle passing just above a receiver in a concave fold would otherwise cover its whole
 * hemisphere). Local vertex indices: 0..ncv-1 the coarse vertices, then the patch's vertices. */
void qtool_bench_cloth_window(int v, int W, int *c0, int *c1, int *r0, int *r1)
{
    const int i = v % CLOTH_G, j = v / CLOTH_G;
    /* coarse cells overlapping the window [i - W, i + W] x [j - W, j + W] (floor division) */
    *c0 = (i - W + 64 * CLOTH_STEP) / CLOTH_STEP - 64, *c1 = (i + W - 1 + 64 * CLOTH_STEP) / CLOTH_STEP - 64;
    *r0 = (j - W + 64 * CLOTH_STEP) / CLOTH_STEP - 64, *r1 = (j + W - 1 + 64 * CLOTH_STEP) / CLOTH_STEP - 64;
    *c0 = *c0 < 0 ? 0 : *c0, *r0 = *r0 < 0 ? 0 : *r0;
    *c1 = *c1 > CLOTH_CG - 2 ? CLOTH_CG - 2 : *c1, *r1 = *r1 > CLOTH_CG - 2 ? CLOTH_CG - 2 : *r1;
}

static void free_rings(qtool_bench_cloth *s)
{
    free(s->nring), free(s->nrv), free(s->ring_off), free(s->rv_off), free(s->ringf), free(s->rvf);
    s->nring = s->nrv = NULL, s->ring_off = s->rv_off = NULL, s->ringf = NULL, s->rvf = NULL;
}

int qtool_bench_cloth_rings(qtool_bench_cloth *s, int W)
{
    free_rings(s);
    s->near = W;
    s->nring = calloc((size_t)s->nv, sizeof(int));
    s->nrv = calloc((size_t)s->nv, sizeof(int));
    s->ring_off = calloc((size_t)s->nv + 1, sizeof(size_t));
    s->rv_off = calloc((size_t)s->nv + 1, sizeof(size_t));
    if (!s->nring || !s->nrv || !s->ring_off || !s->rv_off)
        return -1;
    for (int v = 0; v < s->nv; ++v) { /* sizes */
        int c0, c1, r0, r1;
        qtool_bench_cloth_window(v, W, &c0, &c1, &r0, &r1);
        const int cells = (c1 - c0 + 1) * (r1 - r0 + 1);
        s->ring_off[v + 1] = s->ring_off[v] + (size_t)(s->nct - 2 * cells + 2 * cells * CLOTH_STEP * CLOTH_STEP);
        s->rv_off[v + 1] = s->rv_off[v] + (size_t)(((c1 - c0 + 1) * CLOTH_STEP + 1) * ((r1 - r0 + 1) * CLOTH_STEP + 1));
    }
    s->ringf = malloc(sizeof *s->ringf * s->ring_off[s->nv]);
    s->rvf = malloc(sizeof(int) * s->rv_off[s->nv]);
    if (!s->ringf || !s->rvf)
        return -1;
    for (int v = 0; v < s->nv; ++v) {
        int c0, c1, r0, r1;
        qtool_bench_cloth_window(v, W, &c0, &c1, &r0, &r1);
        uint32_t (*ring)[3] = s->ringf + s->ring_off[v];
        int *rv = s->rvf + s->rv_off[v];
        int nt = 0, nr = 0;
        for (int cj = 0; cj + 1 < CLOTH_CG; ++cj)
            for (int ci = 0; ci + 1 < CLOTH_CG; ++ci) {
                const int t = 2 * (cj * (CLOTH_CG - 1) + ci);
                if (ci >= c0 && ci <= c1 && cj >= r0 && cj <= r1)
                    continue;
                for (int q = 0; q < 2; ++q, ++nt)
                    for (int k = 0; k < 3; ++k)
                        ring[nt][k] = s->ctri[t + q][k];
            }
        const int fi0 = c0 * CLOTH_STEP, fi1 = (c1 + 1) * CLOTH_STEP, fj0 = r0 * CLOTH_STEP, fj1 = (r1 + 1) * CLOTH_STEP;
        for (int fj = fj0; fj <= fj1; ++fj)
            for (int fi = fi0; fi <= fi1; ++fi)
                rv[nr++] = fj * CLOTH_G + fi;
        const int w = fi1 - fi0 + 1;
        for (int fj = fj0; fj < fj1; ++fj)
            for (int fi = fi0; fi < fi1; ++fi) {
                const uint32_t a = (uint32_t)(s->ncv + (fj - fj0) * w + (fi - fi0)), b = a + 1, c = a + (uint32_t)w + 1,
                               d = a + (uint32_t)w;
                ring[nt][0] = a, ring[nt][1] = b, ring[nt][2] = c, nt++;
                ring[nt][0] = a, ring[nt][1] = c, ring[nt][2] = d, nt++;
            }
        s->nring[v] = nt, s->nrv[v] = nr;
    }
    return 0;
}

void qtool_bench_cloth_free(qtool_bench_cloth *s)
{
    free(s->tri), free(s->frames), free(s->cvert), free(s->ctri);
    free_rings(s);
}

int qtool_bench_cloth_frame(const qtool_bench_cloth *s, int f, qibl_q16_t (*pos)[3], int32_t (*nrm)[3])
{
    const double *x = s->frames + 3 * (size_t)s->nv * (size_t)f;
    double *n = calloc((size_t)s->nv * 3, sizeof(double));
    if (!n)
        return -1;
    for (int t = 0; t < s->ntri; ++t) {
        const double *a = x + 3 * s->tri[t][0], *b = x + 3 * s->tri[t][1], *c = x + 3 * s->tri[t][2];
        const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        const double fn[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
        for (int k = 0; k < 3; ++k)
            for (int j = 0; j < 3; ++j)
                n[3 * s->tri[t][k] + j] += fn[j];
    }
    for (int v = 0; v < s->nv; ++v) {
        const double l = sqrt(n[3 * v] * n[3 * v] + n[3 * v + 1] * n[3 * v + 1] + n[3 * v + 2] * n[3 * v + 2]);
        for (int k = 0; k < 3; ++k) {
            pos[v][k] = (qibl_q16_t)lrint(x[3 * v + k] * 65536.0);
            nrm[v][k] = l > 0 ? (int32_t)lrint(n[3 * v + k] / l * 1073741824.0 * 0.999) : (k == 2 ? 1 : 0);
        }
    }
    free(n);
    return 0;
}

uint32_t qtool_bench_cloth_gather(const qtool_bench_cloth *s, const qibl_q16_t (*pos)[3], int v, int coarse,
                                  qibl_q16_t (*gp)[3])
{
    const int ncv = s->ncv;
    for (int c = 0; coarse && c < ncv; ++c)
        for (int k = 0; k < 3; ++k)
            gp[c][k] = pos[s->cvert[c]][k];
    for (int r = 0; r < s->nrv[v]; ++r)
        for (int k = 0; k < 3; ++k)
            gp[ncv + r][k] = pos[s->rvf[s->rv_off[v] + (size_t)r]][k];
    return (uint32_t)(ncv + s->nrv[v]);
}
