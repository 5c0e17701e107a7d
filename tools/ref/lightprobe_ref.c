/*
 * ref/lightprobe_ref.c - double-precision light-probe sampling (see lightprobe_ref.h).
 */
#include "ref/lightprobe_ref.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include "qtool.h"


static size_t cell(const qtool_ref_probe *p, int u, int v)
{
    return (size_t)v * (size_t)(p->w + 1) + (size_t)u;
}

int qtool_ref_probe_init(qtool_ref_probe *p, int w, int h, const double *rgb)
{
    memset(p, 0, sizeof *p);
    if (w < 1 || h < 1)
        return -1;
    size_t n = (size_t)w * (size_t)h, cells = (size_t)(w + 1) * (size_t)(h + 1);
    p->w = w;
    p->h = h;
    p->rgb = malloc(3 * n * sizeof *p->rgb);
    p->sat = calloc(cells, sizeof *p->sat);
    p->mom = calloc(5 * cells, sizeof *p->mom);
    p->rowsin = malloc((size_t)h * sizeof *p->rowsin);
    if (!p->rgb || !p->sat || !p->mom || !p->rowsin) {
        qtool_ref_probe_free(p);
        return -1;
    }
    memcpy(p->rgb, rgb, 3 * n * sizeof *p->rgb);
    for (int v = 0; v < h; ++v)
        p->rowsin[v] = sin((v + 0.5) * QTOOL_PI / h);
    for (int v = 0; v < h; ++v) {
        long double acc[5] = {0};
        for (int u = 0; u < w; ++u) {
            const double *q = rgb + 3 * ((size_t)v * (size_t)w + (size_t)u);
            long double e = (QTOOL_REF_LUMA_R * q[0] + QTOOL_REF_LUMA_G * q[1] + QTOOL_REF_LUMA_B * q[2]) * p->rowsin[v];
            acc[0] += e;
            acc[1] += e * u;
            acc[2] += e * u * u;
            acc[3] += e * v;
            acc[4] += e * v * v;
            p->sat[cell(p, u + 1, v + 1)] = p->sat[cell(p, u + 1, v)] + acc[0];
            for (int j = 0; j < 5; ++j)
                p->mom[5 * cell(p, u + 1, v + 1) + (size_t)j] = p->mom[5 * cell(p, u + 1, v) + (size_t)j] + acc[j];
        }
    }
    return 0;
}

void qtool_ref_probe_free(qtool_ref_probe *p)
{
    free(p->rgb), free(p->sat), free(p->mom), free(p->rowsin);
    memset(p, 0, sizeof *p);
}

void qtool_ref_probe_dir(const qtool_ref_probe *p, double x, double y, double d[3])
{
    double t = y * QTOOL_PI / p->h, f = x * 2.0 * QTOOL_PI / p->w;
    d[0] = sin(t) * cos(f);
    d[1] = sin(t) * sin(f);
    d[2] = cos(t);
}

long double qtool_ref_probe_energy(const qtool_ref_probe *p, int u0, int v0, int u1, int v1)
{
    long double s = 0;
    for (int v = v0; v < v1; ++v)
        for (int u = u0; u < u1; ++u) {
            const double *q = p->rgb + 3 * ((size_t)v * (size_t)p->w + (size_t)u);
            s += (long double)(QTOOL_REF_LUMA_R * q[0] + QTOOL_REF_LUMA_G * q[1] + QTOOL_REF_LUMA_B * q[2]) * p->rowsin[v];
        }
    return s;
}

void qtool_ref_probe_rgb(const qtool_ref_probe *p, int u0, int v0, int u1, int v1, double rgb[3])
{
    long double s[3] = {0};
    for (int v = v0; v < v1; ++v)
        for (int u = u0; u < u1; ++u)
            for (int c = 0; c < 3; ++c)
                s[c] += (long double)p->rgb[3 * ((size_t)v * (size_t)p->w + (size_t)u) + (size_t)c] * p->rowsin[v];
    double k = 2.0 * QTOOL_PI * QTOOL_PI / ((double)p->w * p->h);
    for (int c = 0; c < 3; ++c)
        rgb[c] = (double)s[c] * k;
}

void qtool_ref_probe_place(const qtool_ref_probe *p, int u0, int v0, int u1, int v1, int centre, double d[3])
{
    double x = 0.5 * (u0 + u1), y = 0.5 * (v0 + v1);
    if (!centre) {
        long double s = 0, sx = 0, sy = 0;
        for (int v = v0; v < v1; ++v)
            for (int u = u0; u < u1; ++u) {
                const double *q = p->rgb + 3 * ((size_t)v * (size_t)p->w + (size_t)u);
                long double e = (QTOOL_REF_LUMA_R * q[0] + QTOOL_REF_LUMA_G * q[1] + QTOOL_REF_LUMA_B * q[2]) * p->rowsin[v];
                s += e;
                sx += e * (u + 0.5);
                sy += e * (v + 0.5);
            }
        if (s > 0) {
            x = (double)(sx / s);
            y = (double)(sy / s);
        }
    }
    qtool_ref_probe_dir(p, x, y, d);
}

/* ---- samplers -------------------------------------------------------------------------------- */

typedef struct {
    int u0, v0, u1, v1;
} rect;

static long double sat_sum(const qtool_ref_probe *p, int u0, int v0, int u1, int v1)
{
    return p->sat[cell(p, u1, v1)] - p->sat[cell(p, u0, v1)] - p->sat[cell(p, u1, v0)] + p->sat[cell(p, u0, v0)];
}

/* exact zero test for dropping dark halves: direct, since SAT differences of long doubles are not */
static int lit(const qtool_ref_probe *p, rect r)
{
    for (int v = r.v0; v < r.v1; ++v)
        for (int u = r.u0; u < r.u1; ++u) {
            const double *q = p->rgb + 3 * ((size_t)v * (size_t)p->w + (size_t)u);
            if (q[0] > 0 || q[1] > 0 || q[2] > 0)
                return 1;
        }
    return 0;
}

static int px_lit(const qtool_ref_probe *p, int u, int v)
{
    const double *q = p->rgb + 3 * ((size_t)v * (size_t)p->w + (size_t)u);
    return q[0] > 0 || q[1] > 0 || q[2] > 0;
}

/* the bounding box of the lit pixels of a lit region, by plain scans */
static void crop(const qtool_ref_probe *p, rect *r)
{
    int u0 = r->u1, u1 = r->u0, v0 = r->v1, v1 = r->v0;
    for (int v = r->v0; v < r->v1; ++v)
        for (int u = r->u0; u < r->u1; ++u)
            if (px_lit(p, u, v)) {
                if (u < u0) u0 = u;
                if (u + 1 > u1) u1 = u + 1;
                if (v < v0) v0 = v;
                if (v + 1 > v1) v1 = v + 1;
            }
    r->u0 = u0, r->u1 = u1, r->v0 = v0, r->v1 = v1;
}

static double mean_sin(const qtool_ref_probe *p, int v0, int v1)
{
    double s = 0;
    for (int v = v0; v < v1; ++v)
        s += p->rowsin[v];
    return s / (v1 - v0);
}

/* angular width and height of a region, in radians */
static void sides(const qtool_ref_probe *p, rect r, double *aw, double *ah)
{
    *aw = (r.u1 - r.u0) * 2.0 * QTOOL_PI / p->w * mean_sin(p, r.v0, r.v1);
    *ah = (r.v1 - r.v0) * QTOOL_PI / p->h;
}

/* the axis to cut r across: 1 along u (the angularly longer side, or the only one two pixels wide),
 * 0 along v, -1 when neither side is two pixels wide */
static int long_axis(const qtool_ref_probe *p, rect r)
{
    int w = r.u1 - r.u0, h = r.v1 - r.v0;
    if (w < 2 && h < 2)
        return -1;
    double aw, ah;
    sides(p, r, &aw, &ah);
    return h < 2 || (w >= 2 && aw >= ah);
}

static int cut_median(const qtool_ref_probe *p, rect r, rect *a, rect *b)
{
    int along_u = long_axis(p, r);
    if (along_u < 0)
        return 0;
    int lo = (along_u ? r.u0 : r.v0) + 1, hi = (along_u ? r.u1 : r.v1) - 1;
    long double t = sat_sum(p, r.u0, r.v0, r.u1, r.v1);
    int best = lo;
    long double bd = INFINITY;
    for (int c = lo; c <= hi; ++c) { /* a linear scan: the reference need not be fast */
        long double f = along_u ? sat_sum(p, r.u0, r.v0, c, r.v1) : sat_sum(p, r.u0, r.v0, r.u1, c);
        long double d = fabsl(2 * f - t);
        if (d < bd) {
            bd = d;
            best = c;
        }
    }
    *a = *b = r;
    if (along_u)
        a->u1 = b->u0 = best;
    else
        a->v1 = b->v0 = best;
    return 1;
}

static double variance(const qtool_ref_probe *p, rect r)
{
    long double m[5];
    for (int j = 0; j < 5; ++j)
        m[j] = p->mom[5 * cell(p, r.u1, r.v1) + (size_t)j] - p->mom[5 * cell(p, r.u0, r.v1) + (size_t)j] -
               p->mom[5 * cell(p, r.u1, r.v0) + (size_t)j] + p->mom[5 * cell(p, r.u0, r.v0) + (size_t)j];
    if (m[0] <= 0)
        return 0;
    long double vu = m[2] - m[1] * m[1] / m[0], vv = m[4] - m[3] * m[3] / m[0];
    if (vu < 0)
        vu = 0;
    if (vv < 0)
        vv = 0;
    /* angular: (sin theta dphi)^2 + dtheta^2 with dphi = du 2 pi / W, dtheta = dv pi / H */
    double k = 2.0 * QTOOL_PI / p->w * mean_sin(p, r.v0, r.v1), l = QTOOL_PI / p->h;
    return (double)(vu * k * k + vv * l * l);
}

static int cut_varmin(const qtool_ref_probe *p, rect r, rect *a, rect *b)
{
    int first_u = long_axis(p, r), found = 0;
    if (first_u < 0)
        return 0;
    long double t = sat_sum(p, r.u0, r.v0, r.u1, r.v1);
    double best = 0;
    long double best_imb = 0;
    for (int pass = 0; pass < 2; ++pass) {
        int along_u = pass == 0 ? first_u : !first_u;
        int lo = (along_u ? r.u0 : r.v0) + 1, hi = along_u ? r.u1 : r.v1;
        for (int c = lo; c < hi; ++c) {
            rect x = r, y = r;
            if (along_u)
                x.u1 = y.u0 = c;
            else
                x.v1 = y.v0 = c;
            double vx = variance(p, x), vy = variance(p, y), s = vx > vy ? vx : vy;
            long double imb = fabsl(2 * sat_sum(p, x.u0, x.v0, x.u1, x.v1) - t);
            if (!found || s < best || (s == best && imb < best_imb)) {
                found = 1;
                best = s;
                best_imb = imb;
                *a = x;
                *b = y;
            }
        }
    }
    return found;
}

static double key(const qtool_ref_probe *p, rect r, int pri)
{
    if (r.u1 - r.u0 < 2 && r.v1 - r.v0 < 2)
        return 0;
    double e = (double)sat_sum(p, r.u0, r.v0, r.u1, r.v1);
    if (pri == QTOOL_REF_PRI_ENERGY)
        return e;
    if (pri == QTOOL_REF_PRI_ENERGY_SIZE) {
        double aw, ah;
        sides(p, r, &aw, &ah);
        return e * (aw > ah ? aw : ah);
    }
    return variance(p, r);
}

static double light_energy(const qtool_ref_probe *p, const qtool_ref_light *l)
{
    return (double)sat_sum(p, l->u0, l->v0, l->u1, l->v1);
}

static const qtool_ref_probe *sort_probe;

static int cmp_bright(const void *x, const void *y)
{
    const qtool_ref_light *a = x, *b = y;
    double ea = light_energy(sort_probe, a), eb = light_energy(sort_probe, b);
    if (ea != eb)
        return ea > eb ? -1 : 1;
    if (a->v0 != b->v0)
        return a->v0 < b->v0 ? -1 : 1;
    return (a->u0 > b->u0) - (a->u0 < b->u0);
}

/* region i cut in two (cropped): it keeps one half, the other is appended at *n; 1 if it was cut */
static int split(const qtool_ref_probe *p, int (*cut)(const qtool_ref_probe *, rect, rect *, rect *), rect *R, int i,
                 int *n)
{
    rect a, b;
    if (!cut(p, R[i], &a, &b))
        return 0;
    crop(p, &a);
    crop(p, &b);
    R[i] = a;
    R[(*n)++] = b;
    return 1;
}

int qtool_ref_lights(const qtool_ref_probe *p, int method, int priority, int centre, int max, qtool_ref_light *out)
{
    if (max < 1 || method < 0 || method > 2)
        return -1;
    int pri = priority;
    if (method == QTOOL_REF_MEDIANCUT)
        pri = QTOOL_REF_PRI_LEVELS;
    else if (pri == QTOOL_REF_PRI_DEFAULT)
        pri = method == QTOOL_REF_VARMIN ? QTOOL_REF_PRI_VARIANCE : QTOOL_REF_PRI_ENERGY_SIZE;
    if (pri == QTOOL_REF_PRI_LEVELS && (max & (max - 1)) != 0)
        return -1;
    rect all = {0, 0, p->w, p->h};
    if (!lit(p, all))
        return 0;
    rect *R = malloc((size_t)max * sizeof *R);
    if (!R)
        return -1;
    int n = 1;
    crop(p, &all);
    R[0] = all;
    int (*cut)(const qtool_ref_probe *, rect, rect *, rect *) = method == QTOOL_REF_VARMIN ? cut_varmin : cut_median;
    if (pri == QTOOL_REF_PRI_LEVELS) {
        for (int round = 1; round < max; round <<= 1) {
            int m = n;
            for (int i = 0; i < m; ++i)
                split(p, cut, R, i, &n);
        }
        /* one-pixel regions skipped their split: split the others in list order up to max */
        for (int grew = 1; grew && n < max;) {
            grew = 0;
            for (int i = 0; i < n && n < max; ++i)
                grew |= split(p, cut, R, i, &n);
        }
    } else {
        char *done = calloc((size_t)max, 1); /* regions that cannot split: the next best is split */
        if (!done) {
            free(R);
            return -1;
        }
        while (n < max) {
            int best = -1;
            double bk = 0;
            for (int i = 0; i < n; ++i) { /* linear search for the largest key, ties: (v0, u0) */
                double k = key(p, R[i], pri);
                if (k <= 0 || done[i])
                    continue;
                if (best < 0 || k > bk || (k == bk && (R[i].v0 < R[best].v0 || (R[i].v0 == R[best].v0 && R[i].u0 < R[best].u0)))) {
                    best = i;
                    bk = k;
                }
            }
            if (best < 0)
                break;
            if (!split(p, cut, R, best, &n))
                done[best] = 1;
        }
        free(done);
    }
    for (int i = 0; i < n; ++i) {
        qtool_ref_light *l = &out[i];
        l->u0 = R[i].u0, l->v0 = R[i].v0, l->u1 = R[i].u1, l->v1 = R[i].v1;
        qtool_ref_probe_rgb(p, l->u0, l->v0, l->u1, l->v1, l->rgb);
        qtool_ref_probe_place(p, l->u0, l->v0, l->u1, l->v1, centre, l->dir);
    }
    free(R);
    sort_probe = p;
    qsort(out, (size_t)n, sizeof *out, cmp_bright);
    return n;
}

/* ---- irradiance ------------------------------------------------------------------------------ */

void qtool_ref_sphere_dirs(int n, double (*d)[3])
{
    const double ga = QTOOL_PI * (3.0 - sqrt(5.0));
    for (int i = 0; i < n; ++i) {
        double z = 1.0 - (2.0 * i + 1.0) / n, r = sqrt(1.0 - z * z), a = ga * i;
        d[i][0] = r * cos(a);
        d[i][1] = r * sin(a);
        d[i][2] = z;
    }
}

typedef struct {
    const qtool_ref_probe *p;
    const double (*normals)[3];
    double *E;
    int i0, i1;
    const double (*pixdir)[3];
    const double *q;
} irr_job;

static void *irr_run(void *arg)
{
    irr_job *j = arg;
    size_t np = (size_t)j->p->w * (size_t)j->p->h;
    for (int i = j->i0; i < j->i1; ++i) {
        const double *n = j->normals[i];
        double s = 0;
        for (size_t k = 0; k < np; ++k) {
            double c = n[0] * j->pixdir[k][0] + n[1] * j->pixdir[k][1] + n[2] * j->pixdir[k][2];
            if (c > 0)
                s += j->q[k] * c;
        }
        j->E[i] = s;
    }
    return NULL;
}

void qtool_ref_probe_irradiance(const qtool_ref_probe *p, int n, const double (*normals)[3], double *E, int threads)
{
    size_t np = (size_t)p->w * (size_t)p->h;
    double (*pd)[3] = malloc(np * sizeof *pd);
    double *q = malloc(np * sizeof *q);
    if (!pd || !q) {
        free(pd), free(q);
        for (int i = 0; i < n; ++i)
            E[i] = NAN;
        return;
    }
    double k = 2.0 * QTOOL_PI * QTOOL_PI / ((double)p->w * p->h);
    for (int v = 0; v < p->h; ++v)
        for (int u = 0; u < p->w; ++u) {
            size_t i = (size_t)v * (size_t)p->w + (size_t)u;
            qtool_ref_probe_dir(p, u + 0.5, v + 0.5, pd[i]);
            const double *c = p->rgb + 3 * i;
            q[i] = (QTOOL_REF_LUMA_R * c[0] + QTOOL_REF_LUMA_G * c[1] + QTOOL_REF_LUMA_B * c[2]) * p->rowsin[v] * k;
        }
    if (threads < 1)
        threads = 1;
    if (threads > 64)
        threads = 64;
    pthread_t tid[64];
    irr_job jobs[64];
    for (int t = 0; t < threads; ++t) {
        jobs[t] = (irr_job){p, normals, E, n * t / threads, n * (t + 1) / threads, (const double (*)[3])pd, q};
        if (threads == 1 || pthread_create(&tid[t], NULL, irr_run, &jobs[t]) != 0) {
            irr_run(&jobs[t]);
            tid[t] = 0;
        }
    }
    for (int t = 0; t < threads; ++t)
        if (threads > 1 && tid[t])
            pthread_join(tid[t], NULL);
    free(pd), free(q);
}

double qtool_ref_lights_irradiance(const qtool_ref_light *l, int count, const double n[3])
{
    double s = 0;
    for (int i = 0; i < count; ++i) {
        double c = n[0] * l[i].dir[0] + n[1] * l[i].dir[1] + n[2] * l[i].dir[2];
        if (c > 0)
            s += (QTOOL_REF_LUMA_R * l[i].rgb[0] + QTOOL_REF_LUMA_G * l[i].rgb[1] + QTOOL_REF_LUMA_B * l[i].rgb[2]) * c;
    }
    return s;
}

void qtool_ref_irradiance_error(const qtool_ref_light *l, int count, int n, const double (*normals)[3],
                               const double *E_probe, double *mean_err, double *max_err)
{
    double mean = 0, se = 0, mx = 0;
    for (int i = 0; i < n; ++i)
        mean += E_probe[i];
    mean /= n;
    for (int i = 0; i < n; ++i) {
        double e = fabs(qtool_ref_lights_irradiance(l, count, normals[i]) - E_probe[i]);
        se += e;
        if (e > mx)
            mx = e;
    }
    *mean_err = mean > 0 ? se / n / mean : 0;
    *max_err = mean > 0 ? mx / mean : 0;
}
