/*
 * kmeans.c - LightGen-style clustering (Cohen & Debevec's HDRShop plug-in, as described by Madsen &
 * Laursen's references): the probe's pixels as points on the sphere weighted by their energy,
 * grouped by spherical k-means; a light per cluster at its energy centroid with the cluster's
 * summed Q. The probe is box-averaged to at most 256 x 128 first (LightGen works on a small image;
 * energy is summed, so nothing is lost but position).
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "study/study.h"
#include "qtool.h"


typedef struct {
    double d[3], q[3], e;
} point;

/* fixed-seed generator: the same clusters on every run and platform */
static double rnd(uint64_t *s)
{
    *s = *s * 6364136223846793005u + 1442695040888963407u;
    return (double)(*s >> 11) / 9007199254740992.0;
}

int qtool_study_kmeans(const qtool_study_probe *p, int n, int iters, qtool_study_model *md)
{
    if (n < 1 || n > QTOOL_STUDY_MAX_LIGHTS)
        return -1;
    int f = 1;
    while (p->w / f > 256 && p->w % (2 * f) == 0 && p->h % (2 * f) == 0)
        f *= 2;
    const int w = p->w / f, h = p->h / f;
    point *P = calloc((size_t)w * (size_t)h, sizeof *P);
    int *asg = malloc((size_t)w * (size_t)h * sizeof *asg);
    double *dist = malloc((size_t)w * (size_t)h * sizeof *dist);
    if (!P || !asg || !dist) {
        free(P), free(asg), free(dist);
        return -1;
    }
    int np = 0;
    for (int bv = 0; bv < h; ++bv)
        for (int bu = 0; bu < w; ++bu) {
            point pt;
            memset(&pt, 0, sizeof pt);
            for (int v = bv * f; v < bv * f + f; ++v)
                for (int u = bu * f; u < bu * f + f; ++u) {
                    const double *q = p->q + 3 * ((size_t)v * (size_t)p->w + (size_t)u);
                    double e = (q[0] + q[1] + q[2]) / 3, th = (v + 0.5) * QTOOL_PI / p->h, ph = (u + 0.5) * 2 * QTOOL_PI / p->w;
                    pt.d[0] += e * sin(th) * cos(ph), pt.d[1] += e * sin(th) * sin(ph), pt.d[2] += e * cos(th);
                    for (int c = 0; c < 3; ++c)
                        pt.q[c] += q[c];
                    pt.e += e;
                }
            double l = sqrt(pt.d[0] * pt.d[0] + pt.d[1] * pt.d[1] + pt.d[2] * pt.d[2]);
            if (!(pt.e > 0) || !(l > 0))
                continue;
            for (int c = 0; c < 3; ++c)
                pt.d[c] /= l;
            P[np++] = pt;
        }
    memset(md, 0, sizeof *md);
    if (np == 0) {
        free(P), free(asg), free(dist);
        return -1;
    }
    if (n > np)
        n = np;
    /* k-means++ seeding weighted by energy times squared chord distance */
    uint64_t seed = 0x5eed1234abcdull;
    double tot = 0;
    for (int i = 0; i < np; ++i)
        tot += P[i].e;
    double r = rnd(&seed) * tot, acc = 0;
    int first = np - 1;
    for (int i = 0; i < np; ++i)
        if ((acc += P[i].e) >= r) {
            first = i;
            break;
        }
    memcpy(md->dir[0], P[first].d, sizeof md->dir[0]);
    for (int i = 0; i < np; ++i)
        dist[i] = 2 - 2 * (P[i].d[0] * md->dir[0][0] + P[i].d[1] * md->dir[0][1] + P[i].d[2] * md->dir[0][2]);
    for (int k = 1; k < n; ++k) {
        double s = 0;
        for (int i = 0; i < np; ++i)
            s += P[i].e * dist[i];
        int pick = np - 1;
        r = rnd(&seed) * s, acc = 0;
        for (int i = 0; i < np; ++i)
            if ((acc += P[i].e * dist[i]) >= r && P[i].e * dist[i] > 0) {
                pick = i;
                break;
            }
        memcpy(md->dir[k], P[pick].d, sizeof md->dir[k]);
        for (int i = 0; i < np; ++i) {
            double d = 2 - 2 * (P[i].d[0] * md->dir[k][0] + P[i].d[1] * md->dir[k][1] + P[i].d[2] * md->dir[k][2]);
            if (d < dist[i])
                dist[i] = d;
        }
    }
    md->n = n;
    for (int it = 0; it <= iters; ++it) {
        int changed = 0;
        for (int i = 0; i < np; ++i) { /* nearest centre: the largest dot product */
            int best = 0;
            double bd = -2;
            for (int k = 0; k < n; ++k) {
                double d = P[i].d[0] * md->dir[k][0] + P[i].d[1] * md->dir[k][1] + P[i].d[2] * md->dir[k][2];
                if (d > bd)
                    bd = d, best = k;
            }
            changed += it == 0 || asg[i] != best;
            asg[i] = best;
        }
        double S[QTOOL_STUDY_MAX_LIGHTS][3];
        memset(S, 0, sizeof S);
        memset(md->rgb, 0, sizeof md->rgb);
        for (int i = 0; i < np; ++i)
            for (int c = 0; c < 3; ++c) {
                S[asg[i]][c] += P[i].e * P[i].d[c];
                md->rgb[asg[i]][c] += P[i].q[c];
            }
        for (int k = 0; k < n; ++k) {
            double l = sqrt(S[k][0] * S[k][0] + S[k][1] * S[k][1] + S[k][2] * S[k][2]);
            if (l > 0)
                for (int c = 0; c < 3; ++c)
                    md->dir[k][c] = S[k][c] / l;
        }
        if (!changed || it == iters)
            break;
    }
    /* drop empty clusters */
    int m = 0;
    for (int k = 0; k < n; ++k)
        if (md->rgb[k][0] + md->rgb[k][1] + md->rgb[k][2] > 0) {
            if (m != k) {
                memcpy(md->dir[m], md->dir[k], sizeof md->dir[m]);
                memcpy(md->rgb[m], md->rgb[k], sizeof md->rgb[m]);
            }
            ++m;
        }
    md->n = m;
    free(P), free(asg), free(dist);
    return 0;
}
