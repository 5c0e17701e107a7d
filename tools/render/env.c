/*
 * render/env.c - ground truth under a whole light probe (env.h): bright set and rest, stratified
 * CDF sampling, cosine sampling, balance heuristic, one shadow ray per useful sample.
 */
#include "render/env.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "qtool.h"

static double luma(const float *p)
{
    return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
}

/* the first pixel i of [lo, hi) with cdf[i + 1] > t (hi - 1 if none): the inverse CDF */
static size_t cdf_find(const double *cdf, size_t lo, size_t hi, double t)
{
    --hi;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (cdf[mid + 1] > t)
            hi = mid;
        else
            lo = mid + 1;
    }
    return lo;
}

void qtool_env_free(qtool_env *e)
{
    free(e->rgb), free(e->cdf_b), free(e->cdf_r), free(e->guide_b), free(e->guide_r);
    free(e->row_dw), free(e->row_c), free(e->in_b);
    memset(e, 0, sizeof *e);
}

int qtool_env_build(qtool_env *e, uint32_t w, uint32_t h, const float *rgb, char *err, size_t errlen)
{
    memset(e, 0, sizeof *e);
    if (w < 1 || h < 1 || (uint64_t)w * h > ((uint64_t)1 << 28) || !rgb) {
        snprintf(err, errlen, "env: probe size %ux%u outside 1..2^28 pixels (or no pixels)", w, h);
        return -1;
    }
    size_t np = (size_t)w * h;
    for (size_t i = 0; i < np * 3; ++i)
        if (!isfinite(rgb[i]) || rgb[i] < 0) {
            snprintf(err, errlen, "env: probe pixel (%zu, %zu) has a %s sample (%g)", i / 3 % w, i / 3 / w,
                     isfinite(rgb[i]) ? "negative" : "non-finite", (double)rgb[i]);
            return -1;
        }
    e->w = w, e->h = h;
    e->rgb = malloc(np * 3 * sizeof(float));
    e->cdf_b = malloc((np + 1) * sizeof(double));
    e->cdf_r = malloc((np + 1) * sizeof(double));
    e->row_dw = malloc(h * sizeof(double));
    e->row_c = malloc((h + 1) * sizeof(double));
    e->in_b = malloc(np);
    for (e->guide = 1; e->guide < np / 4; e->guide *= 2) {
    }
    e->guide_b = malloc((e->guide + 1) * sizeof(uint32_t));
    e->guide_r = malloc((e->guide + 1) * sizeof(uint32_t));
    if (!e->rgb || !e->cdf_b || !e->cdf_r || !e->row_dw || !e->row_c || !e->in_b || !e->guide_b || !e->guide_r) {
        qtool_env_free(e);
        snprintf(err, errlen, "env: out of memory for a %ux%u probe", w, h);
        return -1;
    }
    memcpy(e->rgb, rgb, np * 3 * sizeof(float));
    for (uint32_t v = 0; v <= h; ++v)
        e->row_c[v] = cos(QTOOL_PI * v / h);
    for (uint32_t v = 0; v < h; ++v)
        e->row_dw[v] = 2 * QTOOL_PI / w * (e->row_c[v] - e->row_c[v + 1]);
    double tot = 0;
    for (size_t i = 0; i < np; ++i)
        tot += luma(rgb + 3 * i) * e->row_dw[i / w];
    if (!(tot > 0)) {
        qtool_env_free(e);
        snprintf(err, errlen, "env: the probe is black (no luminance)");
        return -1;
    }
    /* radiance above QTOOL_ENV_BRIGHT x the mean (total / 4 pi) is the bright set */
    double thr = QTOOL_ENV_BRIGHT * tot / (4 * QTOOL_PI);
    e->cdf_b[0] = e->cdf_r[0] = 0;
    for (size_t i = 0; i < np; ++i) {
        double y = luma(rgb + 3 * i), en = y * e->row_dw[i / w];
        e->in_b[i] = y >= thr;
        e->nb += e->in_b[i];
        e->cdf_b[i + 1] = e->cdf_b[i] + (e->in_b[i] ? en : 0);
        e->cdf_r[i + 1] = e->cdf_r[i] + (e->in_b[i] ? 0 : en);
    }
    e->e_b = e->cdf_b[np], e->e_r = e->cdf_r[np];
    for (size_t k = 0; k <= e->guide; ++k) {
        const double f = (double)k / (double)e->guide; /* exact: guide is a power of two */
        e->guide_b[k] = (uint32_t)cdf_find(e->cdf_b, 0, np, e->cdf_b[np] * f);
        e->guide_r[k] = (uint32_t)cdf_find(e->cdf_r, 0, np, e->cdf_r[np] * f);
    }
    return 0;
}

static size_t pixel_of(const qtool_env *e, const double d[3])
{
    double z = d[2] < -1 ? -1 : d[2] > 1 ? 1 : d[2];
    double ph = atan2(d[1], d[0]);
    if (ph < 0)
        ph += 2 * QTOOL_PI;
    long u = (long)floor(ph / (2 * QTOOL_PI) * e->w), v = (long)floor(acos(z) / QTOOL_PI * e->h);
    u = u < 0 ? 0 : u >= (long)e->w ? (long)e->w - 1 : u;
    v = v < 0 ? 0 : v >= (long)e->h ? (long)e->h - 1 : v;
    return (size_t)v * e->w + (size_t)u;
}

void qtool_env_lookup(const qtool_env *e, const double d[3], double rgb[3])
{
    const float *p = e->rgb + 3 * pixel_of(e, d);
    rgb[0] = p[0], rgb[1] = p[1], rgb[2] = p[2];
}

/* A pixel drawn proportionally to its energy from (a, b) in [0, 1)^2: a picks the row (marginal),
 * b the pixel within it (conditional), so a stratified grid of (a, b) is stratified on the sphere. */
static size_t cdf_sample(const double *cdf, const uint32_t *guide, size_t ng, uint32_t w, size_t np, double a,
                         double b)
{
    /* cdf_find over [0, np) gives a pixel between the guide's entries for the fractions k / ng
     * and (k + 1) / ng around a (it is monotone in t, and cdf[np] * k / ng <= cdf[np] * a by
     * monotone rounding): the same pixel from a search of that short range */
    const double ak = a * (double)ng;
    const size_t k = ak < (double)(ng - 1) ? (size_t)ak : ng - 1;
    size_t i = cdf_find(cdf, guide[k], (size_t)guide[k + 1] + 1, cdf[np] * a), r0 = i / w * w, r1 = r0 + w;
    size_t j = cdf_find(cdf, r0, r1, cdf[r0] + b * (cdf[r1] - cdf[r0]));
    return cdf[j + 1] > cdf[j] ? j : i; /* rounding at the row's end: keep the marginal's pixel */
}

size_t qtool_env_sample(const qtool_env *e, int bright, double a, double b)
{
    return cdf_sample(bright ? e->cdf_b : e->cdf_r, bright ? e->guide_b : e->guide_r, e->guide, e->w,
                      (size_t)e->w * e->h, a, b);
}

/* direction of probe pixel i at fractions (a, b) across it: uniform in phi and in cos theta; without
 * jitter its centre (theta and phi at the middle, as lightprobe.h places pixels) */
static void pixel_dir(const qtool_env *e, size_t i, int jitter, double a, double b, double d[3])
{
    uint32_t u = (uint32_t)(i % e->w), v = (uint32_t)(i / e->w);
    double ph = (u + (jitter ? a : 0.5)) * 2 * QTOOL_PI / e->w, z, s;
    if (jitter) {
        z = e->row_c[v] - b * (e->row_c[v] - e->row_c[v + 1]), s = sqrt(fmax(0.0, 1 - z * z));
    } else {
        double th = (v + 0.5) * QTOOL_PI / e->h;
        z = cos(th), s = sin(th);
    }
    d[0] = s * cos(ph), d[1] = s * sin(ph), d[2] = z;
}

static uint64_t splitmix(uint64_t *x)
{
    uint64_t z = (*x += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static double unit(uint64_t *x)
{
    return (double)(splitmix(x) >> 11) * (1.0 / 9007199254740992.0);
}

/* the k-th of n points on the unit square: the first g^2 one per cell of a g x g grid, the rest
 * stratified in a only; jittered by st */
static void stratified(uint32_t k, uint32_t n, uint32_t g, uint64_t *st, double *a, double *b)
{
    if (k < g * g)
        *a = (k % g + unit(st)) / g, *b = (k / g + unit(st)) / g;
    else
        *a = (k - g * g + unit(st)) / (n - g * g), *b = unit(st);
}

typedef struct {
    const qtool_rt_scene *s;
    const qtool_env *e;
    uint32_t w, h, spp;
    qtool_pano_kind kind;
    uint64_t seed;
    int jitter;
    double *rgb;
} env_job;

/* adds wgt * L * T(d) to o (T 0 when d faces away or is blocked) */
static void shade(const env_job *j, const qtool_rt_hit *hh, const double d[3], const float *L, double wgt, double o[3])
{
    double df, gl;
    if (!qtool_rt_response(j->s, hh, d, 1e30, &df, &gl))
        return;
    for (int c = 0; c < 3; ++c)
        o[c] += wgt * L[c] * (hh->albedo[c] * df + hh->m->ks * gl);
}

static void env_row(void *ctx, uint32_t y)
{
    const env_job *j = ctx;
    const qtool_env *e = j->e;
    size_t np = (size_t)e->w * e->h;
    uint32_t spp = j->spp, nb = 0, ncos = 0, nenv = 0, g = 0;
    /* the sample budget: B by its energy share (1 .. spp / 2), the rest half cosine, half by R's
     * energy, each on a g x g jittered grid; B takes what the grids leave */
    double tot = e->e_b + e->e_r;
    if (e->e_r <= 0)
        nb = spp;
    else if (e->e_b > 0) {
        nb = (uint32_t)lrint(spp * e->e_b / tot);
        nb = nb < 1 ? 1 : nb > spp / 2 ? spp / 2 : nb;
    }
    if (nb < spp) {
        g = (uint32_t)floor(sqrt((spp - nb) / 2.0));
        ncos = nenv = g * g;
        nb = spp - 2 * g * g;
        if (e->e_b <= 0)
            ncos += nb, nb = 0, nenv = g * g; /* leftovers: more cosine samples (stratified in a only) */
    }
    for (uint32_t x = 0; x < j->w; ++x) {
        size_t pi = (size_t)y * j->w + x;
        double *o = j->rgb + 3 * pi, d[3];
        o[0] = o[1] = o[2] = 0;
        qtool_rt_hit hh;
        qtool_rt_pixel_ray(j->s, j->w, j->h, j->kind, x, y, d);
        qtool_rt_primary(j->s, d, &hh);
        if (!hh.hit)
            continue;
        uint64_t st = j->seed * 0x2545F4914F6CDD1Dull ^ ((uint64_t)pi + 1) * 0x9E3779B97F4A7C15ull;
        splitmix(&st);
        double wd[3];
        /* the bright set: stratified over its CDF */
        uint32_t gb = (uint32_t)floor(sqrt((double)nb));
        for (uint32_t k = 0; k < nb; ++k) {
            double a, b;
            stratified(k, nb, gb, &st, &a, &b);
            size_t i = cdf_sample(e->cdf_b, e->guide_b, e->guide, e->w, np, a, b);
            a = unit(&st), b = unit(&st);
            pixel_dir(e, i, j->jitter, a, b, wd);
            const float *L = e->rgb + 3 * i;
            shade(j, &hh, wd, L, e->e_b / (nb * luma(L)), o);
        }
        /* the rest: balance heuristic of R's CDF and the cosine lobe; every sample contributes
         * L T / (nenv p_env + ncos p_cos) */
        for (uint32_t k = 0; k < nenv; ++k) {
            size_t i =
                cdf_sample(e->cdf_r, e->guide_r, e->guide, e->w, np, (k % g + unit(&st)) / g, (k / g + unit(&st)) / g);
            double a = unit(&st), b = unit(&st);
            pixel_dir(e, i, j->jitter, a, b, wd);
            const float *L = e->rgb + 3 * i;
            double cn = hh.n[0] * wd[0] + hh.n[1] * wd[1] + hh.n[2] * wd[2];
            if (cn <= 0)
                continue;
            double pe = luma(L) / e->e_r, pc = cn / QTOOL_PI;
            shade(j, &hh, wd, L, 1.0 / (nenv * pe + ncos * pc), o);
        }
        if (ncos) {
            double t1[3], t2[3], *n = hh.n;
            /* an orthonormal frame about the shading normal */
            double ax[3] = {fabs(n[0]) < 0.9 ? 1.0 : 0.0, fabs(n[0]) < 0.9 ? 0.0 : 1.0, 0};
            t1[0] = ax[1] * n[2] - ax[2] * n[1], t1[1] = ax[2] * n[0] - ax[0] * n[2], t1[2] = ax[0] * n[1] - ax[1] * n[0];
            double l = sqrt(t1[0] * t1[0] + t1[1] * t1[1] + t1[2] * t1[2]);
            for (int c = 0; c < 3; ++c)
                t1[c] /= l;
            t2[0] = n[1] * t1[2] - n[2] * t1[1], t2[1] = n[2] * t1[0] - n[0] * t1[2], t2[2] = n[0] * t1[1] - n[1] * t1[0];
            for (uint32_t k = 0; k < ncos; ++k) {
                double a, b;
                stratified(k, ncos, g, &st, &a, &b);
                double r = sqrt(a), ph = 2 * QTOOL_PI * b, cz = sqrt(fmax(0.0, 1 - a));
                for (int c = 0; c < 3; ++c)
                    wd[c] = r * cos(ph) * t1[c] + r * sin(ph) * t2[c] + cz * n[c];
                size_t i = pixel_of(e, wd);
                if (e->in_b[i])
                    continue;
                const float *L = e->rgb + 3 * i;
                double pe = e->e_r > 0 ? luma(L) / e->e_r : 0, pc = cz / QTOOL_PI;
                if (pc <= 0 || (L[0] == 0 && L[1] == 0 && L[2] == 0))
                    continue;
                shade(j, &hh, wd, L, 1.0 / (nenv * pe + ncos * pc), o);
            }
        }
    }
}

int qtool_env_render(const qtool_rt_scene *s, uint32_t pw, uint32_t ph, qtool_pano_kind kind, const qtool_env *e,
                     uint32_t spp, uint64_t seed, int jitter, int threads, double *rgb)
{
    if (!s || !e || !e->rgb || !rgb || spp < 4 || pw < 1 || ph < 1)
        return -1;
    env_job j = {s, e, pw, ph, spp, kind, seed, jitter, rgb};
    return qtool_rt_parallel(threads, ph, env_row, &j, NULL);
}
