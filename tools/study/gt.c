/*
 * gt.c - the study's probe and its ground-truth irradiance (Madsen & Laursen eq. 4 over every pixel).
 *
 * Why rows and arcs: for a normal n and a row at theta, n . w(phi) = a + b cos(phi - phi_n) with
 * a = n_z cos theta, b = sin theta |n_xy|, so the lit pixels of the row are one arc of phi, and the
 * row's sum of Q max(0, n . w) is a S0 + sin theta (n_x Sc + n_y Ss) over that arc, from prefix sums
 * of Q, Q cos phi, Q sin phi. Same sum as the pixel loop (gt_brute measures the difference), O(H)
 * per normal instead of O(W H).
 */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/probe_layout.h"
#include "ref/lightprobe_ref.h"
#include "ref/sh_ref.h"
#include "study/study.h"
#include "qtool.h"


/* P of RGBE bytes (lightprobe.h: m 2^(E - 136), no +1/2) */
static double rgbe_p(const uint8_t *px, int c)
{
    return px[3] ? ldexp(px[c], px[3] - 136) : 0.0;
}

/* A lat-long wider than QTOOL_STUDY_MAX_W, box-averaged to QTOOL_STUDY_MAX_W x QTOOL_STUDY_MAX_W / 2
 * RGBE: every input pixel's Q = P sin theta dw goes whole to the output pixel holding its centre
 * (energy kept exactly), divided by that pixel's solid angle. One pass over the input; the sums are
 * the output's size (3 doubles a pixel), not the input's. NULL when out of memory. */
static uint8_t *box_down(int w, int h, const uint8_t *rgbe, int ow, int oh)
{
    double *acc = calloc(3 * (size_t)ow * (size_t)oh, sizeof *acc);
    uint8_t *out = malloc(4 * (size_t)ow * (size_t)oh);
    float *row = malloc(sizeof *row * 3 * (size_t)ow);
    if (!acc || !out || !row) {
        free(acc), free(out), free(row);
        return NULL;
    }
    for (int v = 0; v < h; ++v) {
        double s = sin((v + 0.5) * QTOOL_PI / h) / ((double)w * h);
        double *a = acc + 3 * (size_t)ow * (size_t)((long long)v * oh / h);
        for (int u = 0; u < w; ++u) {
            const uint8_t *px = rgbe + 4 * ((size_t)v * (size_t)w + (size_t)u);
            if (!px[3])
                continue;
            double *o = a + 3 * (size_t)((long long)u * ow / w);
            for (int c = 0; c < 3; ++c)
                o[c] += rgbe_p(px, c) * s;
        }
    }
    for (int v = 0; v < oh; ++v) {
        double s = sin((v + 0.5) * QTOOL_PI / oh) / ((double)ow * oh);
        for (int u = 0; u < ow; ++u)
            for (int c = 0; c < 3; ++c)
                row[3 * u + c] = (float)(acc[3 * ((size_t)v * (size_t)ow + (size_t)u) + (size_t)c] / s);
        qtool_probe_layout_rgbe_encode(row, (size_t)ow, out + 4 * (size_t)ow * (size_t)v);
    }
    free(acc), free(row);
    return out;
}

int qtool_study_probe_init(qtool_study_probe *p, int w, int h, const uint8_t *rgbe, char *err, size_t errlen)
{
    memset(p, 0, sizeof *p);
    if (w < 2 || h < 1 || w != 2 * h) {
        snprintf(err, errlen, "%d x %d is not a 2:1 lat-long probe", w, h);
        return -1;
    }
    p->src_w = w, p->src_h = h;
    if (w > QTOOL_STUDY_MAX_W) {
        int ow = QTOOL_STUDY_MAX_W, oh = QTOOL_STUDY_MAX_W / 2;
        p->rgbe = box_down(w, h, rgbe, ow, oh);
        if (!p->rgbe) {
            snprintf(err, errlen, "out of memory for a %d x %d probe", ow, oh);
            return -1;
        }
        w = ow, h = oh, rgbe = p->rgbe;
    }
    size_t np = (size_t)w * (size_t)h;
    if (!p->rgbe)
        p->rgbe = malloc(4 * np);
    p->q = malloc(3 * np * sizeof *p->q);
    if (!p->rgbe || !p->q) {
        free(p->rgbe), free(p->q);
        snprintf(err, errlen, "out of memory for a %d x %d probe", w, h);
        return -1;
    }
    if (p->rgbe != rgbe)
        memcpy(p->rgbe, rgbe, 4 * np);
    p->w = w, p->h = h;
    const double k = 2.0 * QTOOL_PI * QTOOL_PI / ((double)w * h);
    for (int v = 0; v < h; ++v) {
        double s = sin((v + 0.5) * QTOOL_PI / h) * k;
        for (int u = 0; u < w; ++u) {
            size_t i = (size_t)v * (size_t)w + (size_t)u;
            const uint8_t *px = p->rgbe + 4 * i;
            for (int c = 0; c < 3; ++c)
                p->q[3 * i + (size_t)c] = rgbe_p(px, c) * s;
        }
    }
    return 0;
}

int qtool_study_probe_lit(const qtool_study_probe *p, char *err, size_t errlen)
{
    /* the error measure (model.c) skips a channel without light, but with none at all every error
     * is 0 / 0 */
    size_t n = 3 * (size_t)p->w * (size_t)p->h;
    for (size_t i = 0; i < n; ++i)
        if (p->q[i] > 0)
            return 0;
    snprintf(err, errlen, "the probe is black everywhere: no light, so no relative error to measure");
    return -1;
}

void qtool_study_probe_free(qtool_study_probe *p)
{
    free(p->rgbe), free(p->q);
    memset(p, 0, sizeof *p);
}

typedef struct {
    const qtool_study_probe *p;
    const qtool_study_gt *g;
    const double *nphi, *nxy;
    int v0, v1;
    double *E; /* this thread's 3 m sums */
} gt_job;

static void *gt_rows(void *arg)
{
    gt_job *j = arg;
    const int w = j->p->w, m = j->g->m;
    double *pre = malloc(9 * (size_t)(w + 1) * sizeof *pre); /* [c][kind][u]: Q, Q cos, Q sin */
    if (!pre)
        return (void *)1;
    for (int v = j->v0; v < j->v1; ++v) {
        const double th = (v + 0.5) * QTOOL_PI / j->p->h, st = sin(th), ct = cos(th);
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k)
                pre[(size_t)(3 * c + k) * (size_t)(w + 1)] = 0.0;
        for (int u = 0; u < w; ++u) {
            const double ph = (u + 0.5) * 2.0 * QTOOL_PI / w, cp = cos(ph), sp = sin(ph);
            for (int c = 0; c < 3; ++c) {
                double q = j->p->q[3 * ((size_t)v * (size_t)w + (size_t)u) + (size_t)c];
                double *a = pre + (size_t)(3 * c) * (size_t)(w + 1);
                a[u + 1] = a[u] + q;
                a[(w + 1) + u + 1] = a[(w + 1) + u] + q * cp;
                a[2 * (w + 1) + u + 1] = a[2 * (w + 1) + u] + q * sp;
            }
        }
        for (int k = 0; k < m; ++k) {
            const double *n = j->g->nrm[k];
            const double a = n[2] * ct, b = st * j->nxy[k];
            int s, len;
            if (b <= 1e-300) {
                if (a <= 0)
                    continue;
                s = 0, len = w;
            } else {
                double c0 = -a / b;
                if (c0 >= 1.0)
                    continue;
                if (c0 < -1.0) {
                    s = 0, len = w;
                } else {
                    double al = acos(c0), sc = w / (2.0 * QTOOL_PI);
                    double lo = ceil((j->nphi[k] - al) * sc - 0.5), hi = floor((j->nphi[k] + al) * sc - 0.5);
                    if (hi < lo)
                        continue;
                    len = (int)(hi - lo) + 1;
                    if (len > w)
                        len = w;
                    long sl = (long)lo % w;
                    s = (int)(sl < 0 ? sl + w : sl);
                }
            }
            for (int c = 0; c < 3; ++c) {
                const double *P = pre + (size_t)(3 * c) * (size_t)(w + 1);
                double r[3];
                for (int t = 0; t < 3; ++t) {
                    const double *A = P + (size_t)t * (size_t)(w + 1);
                    r[t] = s + len <= w ? A[s + len] - A[s] : (A[w] - A[s]) + A[s + len - w];
                }
                j->E[3 * k + c] += a * r[0] + st * (n[0] * r[1] + n[1] * r[2]);
            }
        }
    }
    free(pre);
    return NULL;
}

int qtool_study_gt_compute(qtool_study_gt *g, const qtool_study_probe *p, int m, int threads)
{
    memset(g, 0, sizeof *g);
    if (m < 1)
        return -1;
    if (threads < 1)
        threads = 1;
    if (threads > 16)
        threads = 16;
    g->m = m;
    g->nrm = malloc(sizeof *g->nrm * (size_t)m);
    g->E = calloc(3 * (size_t)m, sizeof *g->E);
    g->Y = malloc(sizeof *g->Y * 25 * (size_t)m);
    double *nphi = malloc(sizeof *nphi * (size_t)m), *nxy = malloc(sizeof *nxy * (size_t)m);
    double *part = calloc(3 * (size_t)m * (size_t)threads, sizeof *part);
    if (!g->nrm || !g->E || !g->Y || !nphi || !nxy || !part) {
        free(nphi), free(nxy), free(part);
        qtool_study_gt_free(g);
        return -1;
    }
    qtool_ref_sphere_dirs(m, g->nrm);
    for (int k = 0; k < m; ++k) {
        nphi[k] = atan2(g->nrm[k][1], g->nrm[k][0]);
        nxy[k] = hypot(g->nrm[k][0], g->nrm[k][1]);
        (void)qtool_ref_sh_eval(g->nrm[k][0], g->nrm[k][1], g->nrm[k][2], 5, g->Y + 25 * (size_t)k);
    }
    pthread_t tid[16];
    gt_job jobs[16];
    int started[16] = {0}, bad = 0;
    for (int t = 0; t < threads; ++t) {
        jobs[t] = (gt_job){p, g, nphi, nxy, p->h * t / threads, p->h * (t + 1) / threads, part + 3 * (size_t)m * (size_t)t};
        if (threads > 1 && pthread_create(&tid[t], NULL, gt_rows, &jobs[t]) == 0)
            started[t] = 1;
        else
            bad |= gt_rows(&jobs[t]) != NULL;
    }
    for (int t = 0; t < threads; ++t)
        if (started[t]) {
            void *r;
            pthread_join(tid[t], &r);
            bad |= r != NULL;
        }
    for (int t = 0; t < threads; ++t) /* summed in thread order: the same bits for a thread count */
        for (size_t i = 0; i < 3 * (size_t)m; ++i)
            g->E[i] += part[3 * (size_t)m * (size_t)t + i];
    free(nphi), free(nxy), free(part);
    if (bad) {
        qtool_study_gt_free(g);
        return -1;
    }
    for (int c = 0; c < 3; ++c) {
        double s = 0;
        for (int k = 0; k < m; ++k)
            s += g->E[3 * k + c];
        g->mean[c] = s / m;
    }
    return 0;
}

void qtool_study_gt_free(qtool_study_gt *g)
{
    free(g->nrm), free(g->E), free(g->Y);
    memset(g, 0, sizeof *g);
}

void qtool_study_gt_brute(const qtool_study_probe *p, const double n[3], double E[3])
{
    long double s[3] = {0, 0, 0};
    for (int v = 0; v < p->h; ++v) {
        double th = (v + 0.5) * QTOOL_PI / p->h;
        for (int u = 0; u < p->w; ++u) {
            double ph = (u + 0.5) * 2.0 * QTOOL_PI / p->w;
            double d = n[0] * sin(th) * cos(ph) + n[1] * sin(th) * sin(ph) + n[2] * cos(th);
            if (d <= 0)
                continue;
            const double *q = p->q + 3 * ((size_t)v * (size_t)p->w + (size_t)u);
            for (int c = 0; c < 3; ++c)
                s[c] += (long double)q[c] * d;
        }
    }
    for (int c = 0; c < 3; ++c)
        E[c] = (double)s[c];
}

void qtool_study_gt_accuracy(const qtool_study_gt *g, const qtool_study_probe *p, int count, double *max_vs_brute,
                             double *mean_vs_half)
{
    double mx = 0;
    if (count > g->m)
        count = g->m;
    for (int i = 0; i < count; ++i) {
        int k = (int)((long)i * g->m / count);
        double E[3];
        qtool_study_gt_brute(p, g->nrm[k], E);
        for (int c = 0; c < 3; ++c) {
            double ref = fmax(E[c], 1e-12 * g->mean[c]);
            if (g->mean[c] > 0 && fabs(g->E[3 * k + c] - E[c]) / ref > mx)
                mx = fabs(g->E[3 * k + c] - E[c]) / ref;
        }
    }
    *max_vs_brute = mx;
    *mean_vs_half = NAN;
    if (p->w < 4 || p->h < 2)
        return;
    /* the probe box-downsampled 2x: Q sums of 2 x 2 blocks, re-encoded through the same path */
    int w2 = p->w / 2, h2 = p->h / 2;
    qtool_study_probe half;
    memset(&half, 0, sizeof half);
    half.w = w2, half.h = h2;
    half.q = calloc(3 * (size_t)w2 * (size_t)h2, sizeof *half.q);
    if (!half.q)
        return;
    for (int v = 0; v < 2 * h2; ++v)
        for (int u = 0; u < 2 * w2; ++u)
            for (int c = 0; c < 3; ++c)
                half.q[3 * ((size_t)(v / 2) * (size_t)w2 + (size_t)(u / 2)) + (size_t)c] +=
                    p->q[3 * ((size_t)v * (size_t)p->w + (size_t)u) + (size_t)c];
    qtool_study_gt gh;
    if (qtool_study_gt_compute(&gh, &half, g->m, 2) == 0) {
        double s = 0;
        int cnt = 0;
        for (int k = 0; k < g->m; ++k)
            for (int c = 0; c < 3; ++c)
                if (g->E[3 * k + c] > 0) {
                    s += fabs(gh.E[3 * k + c] - g->E[3 * k + c]) / g->E[3 * k + c];
                    ++cnt;
                }
        *mean_vs_half = cnt ? s / cnt : 0;
        qtool_study_gt_free(&gh);
    }
    free(half.q);
}
