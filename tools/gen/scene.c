/*
 * gen/scene.c - procedural courtyard, analytic SH transfer maps, and range packing.
 */
#include "gen/scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ref/sh_ref.h"
#include "qtool.h"


typedef struct {
    double albedo[3], ks, shininess;
} material;

static const material mats[] = {
    {{0.55, 0.50, 0.42}, 0.00, 1},   /* 0 ground: sandstone */
    {{0.70, 0.32, 0.22}, 0.00, 1},   /* 1 walls: brick */
    {{0.80, 0.80, 0.78}, 0.20, 3},   /* 2 pillars: satin marble (a lobe SH bands 0..4 can hold) */
    {{0.20, 0.35, 0.75}, 0.35, 5},   /* 3 sphere: glazed blue */
    {{0.30, 0.60, 0.30}, 0.05, 8},   /* 4 box: painted green */
};

typedef struct {
    double t, n[3];
    int mat;
} hit;

static void try_hit(hit *h, double t, const double n[3], int mat)
{
    if (t > 1e-6 && t < h->t) {
        h->t = t;
        memcpy(h->n, n, sizeof h->n);
        h->mat = mat;
    }
}

/* axis-aligned box [lo, hi], normal of the entered face */
static void hit_box(hit *h, const double o[3], const double d[3], const double lo[3], const double hi[3], int mat,
                    int inside)
{
    double tmin = -1e30, tmax = 1e30;
    int amin = 0, amax = 0;
    for (int a = 0; a < 3; ++a) {
        if (fabs(d[a]) < 1e-12) {
            if (o[a] < lo[a] || o[a] > hi[a])
                return;
            continue;
        }
        double t0 = (lo[a] - o[a]) / d[a], t1 = (hi[a] - o[a]) / d[a];
        if (t0 > t1) {
            double tt = t0;
            t0 = t1, t1 = tt;
        }
        if (t0 > tmin)
            tmin = t0, amin = a;
        if (t1 < tmax)
            tmax = t1, amax = a;
    }
    if (tmin > tmax)
        return;
    double n[3] = {0, 0, 0};
    if (!inside) {
        n[amin] = d[amin] > 0 ? -1 : 1;
        try_hit(h, tmin, n, mat);
    } else {
        n[amax] = d[amax] > 0 ? -1 : 1; /* seen from inside: the far face, facing back in */
        try_hit(h, tmax, n, mat);
    }
}

static void hit_cylinder_z(hit *h, const double o[3], const double d[3], double cx, double cy, double r, double z0,
                           double z1, int mat)
{
    double ox = o[0] - cx, oy = o[1] - cy;
    double a = d[0] * d[0] + d[1] * d[1], b = 2 * (ox * d[0] + oy * d[1]), c = ox * ox + oy * oy - r * r;
    double disc = b * b - 4 * a * c;
    if (a < 1e-12 || disc < 0)
        return;
    double t = (-b - sqrt(disc)) / (2 * a);
    double z = o[2] + t * d[2];
    if (z < z0 || z > z1)
        return;
    double n[3] = {(ox + t * d[0]) / r, (oy + t * d[1]) / r, 0};
    try_hit(h, t, n, mat);
}

static void hit_sphere(hit *h, const double o[3], const double d[3], const double c[3], double r, int mat)
{
    double oc[3] = {o[0] - c[0], o[1] - c[1], o[2] - c[2]};
    double b = oc[0] * d[0] + oc[1] * d[1] + oc[2] * d[2];
    double cc = oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2] - r * r;
    double disc = b * b - cc;
    if (disc < 0)
        return;
    double t = -b - sqrt(disc);
    double n[3];
    for (int j = 0; j < 3; ++j)
        n[j] = (oc[j] + t * d[j]) / r;
    try_hit(h, t, n, mat);
}

static int trace(const double d[3], hit *h)
{
    static const double o[3] = {0, 0, 0};
    h->t = 1e30;
    h->mat = -1;
    /* ground at z = -1.6, walls: the inside of a 20 x 14 x 6 box with an open top */
    const double glo[3] = {-10, -7, -1.6}, ghi[3] = {10, 7, 4.4};
    hit_box(h, o, d, glo, ghi, 1, 1);
    if (h->mat == 1 && h->n[2] > 0.5)
        h->mat = 0; /* the floor face is ground */
    if (h->mat == 1 && h->n[2] < -0.5)
        h->mat = -1, h->t = 1e30; /* open sky */
    for (int i = 0; i < 4; ++i)
        hit_cylinder_z(h, o, d, i & 1 ? 4.0 : -4.0, i & 2 ? 3.0 : -3.0, 0.45, -1.6, 4.4, 2);
    const double sc[3] = {5.0, -1.0, -0.6};
    hit_sphere(h, o, d, sc, 1.0, 3);
    const double blo[3] = {-6.5, 1.5, -1.6}, bhi[3] = {-5.0, 3.2, -0.4};
    hit_box(h, o, d, blo, bhi, 4, 0);
    return h->mat >= 0;
}

/* zonal coefficients of max(0, cos)^s (s + 2) / (2 pi) by Funk-Hecke: 2 pi int_0^1 f(z) P_l(z) dz,
 * as the multiplier of Y_lm(axis) in the projection */
static void zonal(double s, double norm, double out[5])
{
    const int steps = 20000;
    for (int l = 0; l < 5; ++l) {
        double acc = 0.0;
        for (int i = 0; i < steps; ++i) {
            double z = (i + 0.5) / steps;
            double p;
            switch (l) {
            case 0: p = 1; break;
            case 1: p = z; break;
            case 2: p = 0.5 * (3 * z * z - 1); break;
            case 3: p = 0.5 * (5 * z * z * z - 3 * z); break;
            default: p = (35 * z * z * z * z - 30 * z * z + 3) / 8; break;
            }
            acc += norm * pow(z, s) * p;
        }
        out[l] = 2 * QTOOL_PI * acc / steps;
    }
}

void qtool_gen_pano_dir(uint32_t w, uint32_t h, qtool_pano_kind kind, uint32_t x, uint32_t y, double d[3])
{
    double phi = 2 * QTOOL_PI * (x + 0.5) / w;
    if (kind == QTOOL_PANO_CYLINDRICAL) {
        double tanv = QTOOL_PI * h / w;
        double hgt = (0.5 - (y + 0.5) / h) * 2 * tanv;
        double len = sqrt(1 + hgt * hgt);
        d[0] = cos(phi) / len, d[1] = sin(phi) / len, d[2] = hgt / len;
    } else {
        double th = QTOOL_PI * (y + 0.5) / h;
        d[0] = sin(th) * cos(phi), d[1] = sin(th) * sin(phi), d[2] = cos(th);
    }
}

int qtool_gen_scene(uint32_t width, uint32_t height, uint32_t k, qtool_pano_kind kind, qtool_gen_maps *out)
{
    if (width == 0 || height == 0 || width > 16384 || height > 16384 || k < 1 || k > 25)
        return -1;
    memset(out, 0, sizeof *out);
    size_t np = (size_t)width * height;
    out->t = malloc(sizeof(double) * np * k * 3);
    out->p = malloc(sizeof(int32_t) * np * 3);
    out->dir = malloc(sizeof(double) * np * 3);
    if (!out->t || !out->p || !out->dir) {
        qtool_gen_free(out);
        return -1;
    }
    out->width = width, out->height = height, out->k = k;
    double diff[5], gloss[sizeof mats / sizeof mats[0]][5];
    zonal(1, 1 / QTOOL_PI, diff); /* albedo / pi max(0, cos): pi, 2pi/3, pi/4, 0, -pi/24 over pi */
    for (size_t m = 0; m < sizeof mats / sizeof mats[0]; ++m)
        zonal(mats[m].shininess, (mats[m].shininess + 2) / (2 * QTOOL_PI), gloss[m]);
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) {
            double d[3];
            qtool_gen_pano_dir(width, height, kind, x, y, d);
            size_t pi = (size_t)y * width + x;
            memcpy(out->dir + 3 * pi, d, sizeof d);
            hit h;
            double yn[25], yr[25];
            if (!trace(d, &h)) { /* sky: no surface, no transfer; a far point for the P map */
                for (uint32_t i = 0; i < k; ++i)
                    for (int ch = 0; ch < 3; ++ch)
                        out->t[((size_t)i * 3 + ch) * np + pi] = 0.0;
                for (int j = 0; j < 3; ++j)
                    out->p[3 * pi + j] = (int32_t)lrint(d[j] * 1000.0 * 65536.0);
                continue;
            }
            const material *mt = &mats[h.mat];
            double dn = d[0] * h.n[0] + d[1] * h.n[1] + d[2] * h.n[2];
            double r[3] = {d[0] - 2 * dn * h.n[0], d[1] - 2 * dn * h.n[1], d[2] - 2 * dn * h.n[2]};
            qtool_ref_sh_eval(h.n[0], h.n[1], h.n[2], 5, yn);
            qtool_ref_sh_eval(r[0], r[1], r[2], 5, yr);
            for (uint32_t i = 0; i < k; ++i) {
                int l = (int)floor(sqrt((double)i) + 1e-9);
                for (int ch = 0; ch < 3; ++ch)
                    out->t[((size_t)i * 3 + ch) * np + pi] =
                        mt->albedo[ch] * diff[l] * yn[i] + mt->ks * gloss[h.mat][l] * yr[i];
            }
            for (int j = 0; j < 3; ++j)
                out->p[3 * pi + j] = (int32_t)lrint(d[j] * h.t * 65536.0);
        }
    return 0;
}

void qtool_gen_free(qtool_gen_maps *m)
{
    free(m->t);
    free(m->p);
    free(m->dir);
    memset(m, 0, sizeof *m);
}

double qtool_gen_eval(const qtool_gen_maps *m, uint32_t x, uint32_t y, uint32_t ch, const double *l)
{
    size_t np = (size_t)m->width * m->height, pi = (size_t)y * m->width + x;
    double s = 0.0;
    for (uint32_t i = 0; i < m->k; ++i)
        s += m->t[((size_t)i * 3 + ch) * np + pi] * l[i];
    return s;
}

static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

void qtool_pack_range(double lo, double hi, int32_t *scale, int32_t *bias)
{
    /* quantise the range to Q8.24 first, then the bytes against the quantised range */
    int32_t b = (int32_t)lrint(fmax(-128.0, fmin(127.99, lo)) * 16777216.0);
    int32_t s = (int32_t)lrint((hi - lo) / 255.0 * 16777216.0);
    if (s == 0 && hi > lo)
        s = 1;
    *scale = s, *bias = b;
}

uint8_t qtool_pack_code(double t, int32_t scale, int32_t bias)
{
    double c = scale ? (t * 16777216.0 - bias) / scale : 0.0;
    long q = lrint(c);
    return (uint8_t)(q < 0 ? 0 : q > 255 ? 255 : q);
}

int qtool_pack_maps(const qtool_gen_maps *m, qtool_pack_scheme scheme, int32_t *scale, int32_t *bias, uint8_t *planes,
                   qtool_pack_stats *stats)
{
    size_t np = (size_t)m->width * m->height;
    double *tmp = scheme == QTOOL_PACK_ROBUST ? malloc(sizeof(double) * np) : NULL;
    if (scheme == QTOOL_PACK_ROBUST && !tmp)
        return -1;
    double se = 0.0, mx = 0.0;
    uint64_t clipped = 0;
    for (uint32_t pl = 0; pl < m->k * 3; ++pl) {
        const double *t = m->t + (size_t)pl * np;
        double lo = t[0], hi = t[0];
        if (scheme == QTOOL_PACK_MINMAX) {
            for (size_t i = 1; i < np; ++i)
                lo = t[i] < lo ? t[i] : lo, hi = t[i] > hi ? t[i] : hi;
        } else {
            memcpy(tmp, t, sizeof(double) * np);
            qsort(tmp, np, sizeof(double), cmp_d);
            lo = tmp[(size_t)floor(0.001 * (np - 1))];
            hi = tmp[(size_t)ceil(0.999 * (np - 1))];
        }
        int32_t s, b;
        qtool_pack_range(lo, hi, &s, &b);
        scale[pl] = s, bias[pl] = b;
        uint8_t *o = planes + (size_t)pl * np;
        for (size_t i = 0; i < np; ++i) {
            double c = s ? (t[i] * 16777216.0 - b) / s : 0.0;
            if (c < -0.5 || c > 255.5)
                ++clipped;
            uint8_t q = qtool_pack_code(t[i], s, b);
            o[i] = q;
            double e = (b + (double)s * q) / 16777216.0 - t[i];
            se += e * e;
            if (fabs(e) > mx)
                mx = fabs(e);
        }
    }
    free(tmp);
    if (stats) {
        stats->rms = sqrt(se / ((double)np * m->k * 3));
        stats->max_abs = mx;
        stats->clipped = clipped;
    }
    return 0;
}
