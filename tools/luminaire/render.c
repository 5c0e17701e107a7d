/*
 * luminaire/render.c - a near-field source as textured spotlights: per support a goniometric point
 * lamp of the core (qibl/gonio.h) whose table is the support's emission texture seen from its
 * centre; the far field of the same source as one such lamp; the integer pass-by-pass sum; an asset
 * frame relit by it.
 *
 * Invariants: tables and intensities are made in double once per placement; per pixel everything is
 * integer (qibl_gonio_lookup's twin, 64-bit products with stated bounds; the twin's and the distance
 * ratio's quotients are doubles corrected exactly), so a frame is the same bytes on every host. The
 * cull test only skips directions where the table's bilinear lookup is exactly 0. The hierarchy
 * (tol > 0) chooses each pixel's level and band by integer comparisons only.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bake/bake.h" /* qtool_bake_frame_row */
#include "io/asset_write.h"
#include "luminaire/luminaire.h"
#include "qibl/asset.h"
#include "qibl/soft.h"

/* The unit direction of octahedral texel position (a, b) (texel units, centres at integers) of an
 * n x n map, in the lamp's frame; the folded half for |u| + |v| > 1 (gonio.h). */
static void oct_dir(double a, double b, uint32_t n, double l[3])
{
    double u = (2 * a + 1) / n - 1, v = (2 * b + 1) / n - 1;
    if (fabs(u) + fabs(v) <= 1) {
        l[0] = u, l[1] = v, l[2] = 1 - fabs(u) - fabs(v);
    } else {
        l[0] = (u < 0 ? -1 : 1) * (1 - fabs(v)), l[1] = (v < 0 ? -1 : 1) * (1 - fabs(u));
        l[2] = -(fabs(u) + fabs(v) - 1);
    }
    double r = sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
    for (int k = 0; k < 3; ++k)
        l[k] /= r;
}

/* Bilinear sample of channel-summed luminance or one channel (ch 0..2; 3: luminance) of support
 * (ix, iy)'s texture at window coordinates (ta, tb) in -1..1; 0 outside the window. */
static double tex_sample(const qtool_luminaire *l, uint32_t ix, uint32_t iy, double ta, double tb, int ch)
{
    if (fabs(ta) > 1 || fabs(tb) > 1)
        return 0;
    const uint32_t r = l->res;
    double fx = (ta + 1) / 2 * r - 0.5, fy = (tb + 1) / 2 * r - 0.5;
    fx = fx < 0 ? 0 : fx > r - 1 ? r - 1 : fx;
    fy = fy < 0 ? 0 : fy > r - 1 ? r - 1 : fy;
    uint32_t i0 = (uint32_t)fx, j0 = (uint32_t)fy, i1 = i0 + 1 < r ? i0 + 1 : i0, j1 = j0 + 1 < r ? j0 + 1 : j0;
    double tx = fx - i0, ty = fy - j0;
    double v[4];
    const uint32_t ii[4] = {i0, i1, i0, i1}, jj[4] = {j0, j0, j1, j1};
    for (int k = 0; k < 4; ++k) {
        const float *t = l->tex + qtool_luminaire_texel(l, ix, iy, ii[k], jj[k]);
        v[k] = ch < 3 ? t[ch] : 0.2126 * t[0] + 0.7152 * t[1] + 0.0722 * t[2];
    }
    return (v[0] * (1 - tx) + v[1] * tx) * (1 - ty) + (v[2] * (1 - tx) + v[3] * tx) * ty;
}

/* tex_sample's luminance (ch 3) from a support's precomputed luminance texture (res^2) */
static double lum_sample(const double *lu, uint32_t r, double ta, double tb)
{
    if (fabs(ta) > 1 || fabs(tb) > 1)
        return 0;
    double fx = (ta + 1) / 2 * r - 0.5, fy = (tb + 1) / 2 * r - 0.5;
    fx = fx < 0 ? 0 : fx > r - 1 ? r - 1 : fx;
    fy = fy < 0 ? 0 : fy > r - 1 ? r - 1 : fy;
    uint32_t i0 = (uint32_t)fx, j0 = (uint32_t)fy, i1 = i0 + 1 < r ? i0 + 1 : i0, j1 = j0 + 1 < r ? j0 + 1 : j0;
    double tx = fx - i0, ty = fy - j0;
    const double *r0 = lu + (size_t)j0 * r, *r1 = lu + (size_t)j1 * r;
    return (r0[i0] * (1 - tx) + r0[i1] * tx) * (1 - ty) + (r1[i0] * (1 - tx) + r1[i1] * tx) * ty;
}

/* The lamp's frame for aim (0, 0, -1) and up (0, 1, 0) (qibl_gonio_init): x = (-1, 0, 0), so a
 * lamp-frame direction l is (-l_x, l_y, -l_z) in the source's frame. Intensity of support (ix, iy)
 * toward lamp-frame l, channel ch: A E'(s, t) cos(theta'). */
static double spot_intensity(const qtool_luminaire *l, uint32_t ix, uint32_t iy, const double ld[3], int ch)
{
    if (ld[2] <= 0)
        return 0;
    double tx = -ld[0] / ld[2], ty = ld[1] / ld[2];
    double A = (double)l->spacing * l->spacing;
    double e = tex_sample(l, ix, iy, tx / l->half_tan, ty / l->half_tan, ch);
    return e > 0 ? A * e * ld[2] : 0; /* negative lobes (a dual filter's ringing) are not light */
}

static uint64_t uabs64(int64_t v)
{
    return v < 0 ? (uint64_t)0 - (uint64_t)v : (uint64_t)v;
}

void qtool_luminaire_spots_free(qtool_luminaire_spots *s)
{
    if (!s)
        return;
    free(s->tables), free(s->gonio), free(s->pos), free(s->rgb), free(s->cull), free(s->aw), free(s->occ), free(s->kocc);
    memset(s, 0, sizeof *s);
}

/* The occupancy of spotlight c's table over its cull rectangle: an OCC x OCC grid of cells in
 * (tan_x, tan_y) = (d_x, d_y) / |d_z|, a bit set where some non-zero texel's lookup footprint (the
 * box of one texel around it) may fall, each footprint sampled on a 5 x 5 grid (its edges and the
 * axes it crosses) and padded by a cell: a direction in a clear cell looks up only zeros. */
static void occupancy(qtool_luminaire_spots *s, uint32_t c, const uint16_t *t, uint32_t n)
{
    uint32_t *occ = s->occ[c];
    memset(occ, 0, sizeof s->occ[c]);
    if (s->cull[c][0] < 0 || s->cull[c][1] < 0) {
        memset(occ, 0xFF, sizeof s->occ[c]); /* no rectangle: every cell may be lit */
        return;
    }
    const double T[2] = {s->cull[c][0] / 65536.0, s->cull[c][1] / 65536.0};
    for (uint32_t j = 0; j < n; ++j)
        for (uint32_t i = 0; i < n; ++i) {
            if (t[(size_t)j * n + i] == 0)
                continue;
            double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
            for (int b = 0; b <= 4; ++b)
                for (int a = 0; a <= 4; ++a) {
                    double u = (2.0 * ((double)i - 1 + a / 2.0) + 1) / n - 1, v = (2.0 * ((double)j - 1 + b / 2.0) + 1) / n - 1;
                    double lz = 1 - fabs(u) - fabs(v);
                    /* world tan: x = -l_x (the lamp's x is -x), y = l_y; lz > 0 inside the cull box */
                    double tx = lz > 0 ? -u / lz : 0, ty = lz > 0 ? v / lz : 0;
                    lo[0] = fmin(lo[0], tx), hi[0] = fmax(hi[0], tx), lo[1] = fmin(lo[1], ty), hi[1] = fmax(hi[1], ty);
                }
            /* the axes inside the box: |tan| is smallest there, not at a sample */
            for (int k = 0; k < 2; ++k)
                if (lo[k] < 0 && hi[k] > 0)
                    lo[k] = fmin(lo[k], 0), hi[k] = fmax(hi[k], 0);
            int c0[2], c1[2];
            for (int k = 0; k < 2; ++k) {
                c0[k] = (int)floor((lo[k] / T[k] + 1) / 2 * QTOOL_LUMINAIRE_OCC) - 1;
                c1[k] = (int)floor((hi[k] / T[k] + 1) / 2 * QTOOL_LUMINAIRE_OCC) + 1;
                c0[k] = c0[k] < 0 ? 0 : c0[k], c1[k] = c1[k] >= QTOOL_LUMINAIRE_OCC ? QTOOL_LUMINAIRE_OCC - 1 : c1[k];
            }
            for (int y = c0[1]; y <= c1[1]; ++y)
                for (int x = c0[0]; x <= c1[0]; ++x)
                    occ[y] |= 1u << x;
        }
}

/* Spotlight c's cull rectangle, occupancy bits and their cell factors, from its table t. */
static void cull_of(qtool_luminaire_spots *s, uint32_t c, const uint16_t *t, uint32_t n)
{
    double tmax[2] = {0, 0};
    int nocull = 0;
    for (uint32_t j = 0; j < n; ++j)
        for (uint32_t i = 0; i < n; ++i) {
            if (t[(size_t)j * n + i] == 0)
                continue;
            /* the lookup interpolates within one texel of a non-zero one: bound that box's slopes */
            for (int cy = -1; cy <= 1; cy += 2)
                for (int cx = -1; cx <= 1; cx += 2) {
                    double u = (2.0 * ((double)i + cx) + 1) / n - 1, v2 = (2.0 * ((double)j + cy) + 1) / n - 1;
                    double lz = 1 - fabs(u) - fabs(v2);
                    if (lz <= 0) {
                        nocull = 1;
                        continue;
                    }
                    tmax[0] = fmax(tmax[0], fabs(u) / lz), tmax[1] = fmax(tmax[1], fabs(v2) / lz);
                }
        }
    for (int k = 0; k < 2; ++k) {
        double b = ceil(tmax[k] * 1.01 * 65536.0) + 2;
        s->cull[c][k] = nocull || b > (double)(1u << 30) ? -1 : (int64_t)b;
    }
    occupancy(s, c, t, n);
    for (int k = 0; k < 2; ++k) /* cell = (tan + T) OCC / (2 T + 1), tan and T in Q16 */
        s->kocc[c][k] = s->cull[c][k] < 0 ? 0 : ((uint64_t)QTOOL_LUMINAIRE_OCC << 32) / (2u * (uint64_t)s->cull[c][k] + 1u);
}

/* Appends a lamp at (px, py, pz) (Q16.16, pz exact) whose intensity in double is iv (n n texels of
 * luminance then the three channels): its table (Q1.15 of its luminance peak), cull, peak colour and
 * gonio view. 1 added, 0 dark (no lamp), -1 with a reason in err. *peak_out: its luminance peak. */
static int add_lamp(qtool_luminaire_spots *s, const double *iv, uint32_t n, double px, double py, int32_t pz,
                    double *peak_out, char *err, size_t errlen)
{
    static const int32_t aim[3] = {0, 0, -65536}, up[3] = {0, 65536, 0};
    double peak = 0, sum[4] = {0, 0, 0, 0};
    for (size_t k = 0; k < (size_t)n * n; ++k) {
        peak = iv[4 * k] > peak ? iv[4 * k] : peak;
        for (int ch = 0; ch < 4; ++ch)
            sum[ch] += iv[4 * k + (size_t)ch];
    }
    if (peak <= 0)
        return 0; /* a dark support (under the shade): no lamp, no pass */
    if (!isfinite(peak) || !isfinite(sum[0])) {
        snprintf(err, errlen, "a spotlight's intensity is beyond Q16.16");
        return -1;
    }
    const uint32_t c = s->total;
    uint16_t *t = s->tables + (size_t)c * n * n;
    for (size_t k = 0; k < (size_t)n * n; ++k) {
        double v = iv[4 * k] / peak * 32768.0;
        t[k] = (uint16_t)(v > 32768 ? 32768 : v < 0 ? 0 : lround(v));
    }
    cull_of(s, c, t, n);
    /* the peak intensity per channel: the luminance peak times the support's colour */
    for (int ch = 0; ch < 3; ++ch) {
        double v = peak * (sum[0] > 0 ? sum[ch + 1] / sum[0] : 1) * 65536.0;
        if (!(v < 2147483647.0)) {
            snprintf(err, errlen, "a spotlight's intensity (%.4g) is beyond Q16.16", v / 65536.0);
            return -1;
        }
        s->rgb[c][ch] = (int32_t)lround(v);
    }
    if (!(fabs(px) < 2147483647.0 && fabs(py) < 2147483647.0)) {
        snprintf(err, errlen, "a spotlight's position is beyond Q16.16");
        return -1;
    }
    s->pos[c][0] = (int32_t)lround(px), s->pos[c][1] = (int32_t)lround(py), s->pos[c][2] = pz;
    if (qibl_gonio_init(&s->gonio[c], n, t, aim, up) != QIBL_OK) {
        snprintf(err, errlen, "the core refused a spotlight's table");
        return -1;
    }
    s->total = c + 1;
    *peak_out = peak;
    return 1;
}

/* The shading anchors: the corners of the spotlights' box on S (far: the centre alone), and each
 * lamp's bilinear weights among them (Q15, summing to 2^15). */
static void set_anchors(qtool_luminaire_spots *s, const int32_t pos[3], int far)
{
    int32_t lo[2] = {pos[0], pos[1]}, hi[2] = {pos[0], pos[1]};
    for (uint32_t c = 0; c < s->count; ++c)
        for (int k = 0; k < 2; ++k)
            lo[k] = s->pos[c][k] < lo[k] ? s->pos[c][k] : lo[k], hi[k] = s->pos[c][k] > hi[k] ? s->pos[c][k] : hi[k];
    s->nanchor = far ? 1 : 4;
    for (uint32_t k = 0; k < s->nanchor; ++k) {
        s->anchor[k][0] = far ? pos[0] : (k & 1) ? hi[0] : lo[0];
        s->anchor[k][1] = far ? pos[1] : (k & 2) ? hi[1] : lo[1];
        s->anchor[k][2] = pos[2];
    }
    for (uint32_t c = 0; c < s->total; ++c) {
        double fx = hi[0] > lo[0] ? (double)(s->pos[c][0] - lo[0]) / (hi[0] - lo[0]) : 0;
        double fy = hi[1] > lo[1] ? (double)(s->pos[c][1] - lo[1]) / (hi[1] - lo[1]) : 0;
        int32_t w1 = (int32_t)lround(fx * (1 - fy) * 32768), w2 = (int32_t)lround((1 - fx) * fy * 32768),
                w3 = (int32_t)lround(fx * fy * 32768);
        s->aw[c][0] = far ? 32768 : 32768 - w1 - w2 - w3, s->aw[c][1] = far ? 0 : w1, s->aw[c][2] = far ? 0 : w2,
        s->aw[c][3] = far ? 0 : w3;
    }
}

/* The lit members (level-0 lamps) of the group of supports x0 .. x0 + gs - 1, y0 .. y0 + gs - 1 into
 * mem, and their flux-weighted centroid relative to pos (Q16.16 units, in double); 0 when none. */
static uint32_t group_members(const qtool_luminaire_spots *s, const qtool_luminaire *l, const int32_t pos[3],
                              const uint32_t *sup, const double *lpk, uint32_t x0, uint32_t y0, uint32_t gs,
                              uint32_t *mem, double *cx, double *cy)
{
    const uint32_t n = s->n;
    double w = 0, sx = 0, sy = 0;
    uint32_t nm = 0;
    for (uint32_t c = 0; c < s->count; ++c) {
        const uint32_t mx = sup[c] % l->nx, my = sup[c] / l->nx;
        if (mx < x0 || mx >= x0 + gs || my < y0 || my >= y0 + gs)
            continue;
        const uint16_t *t = s->tables + (size_t)c * n * n;
        double f = 0;
        for (size_t k = 0; k < (size_t)n * n; ++k)
            f += t[k] / 32768.0 * lpk[c];
        w += f, sx += f * ((double)s->pos[c][0] - pos[0]), sy += f * ((double)s->pos[c][1] - pos[1]);
        mem[nm++] = c;
    }
    if (w <= 0)
        return 0;
    *cx = sx / w, *cy = sy / w;
    return nm;
}

/* A merged lamp's intensity (iv: n n texels of luminance then the three channels) for receivers at
 * 1 / depth u: toward tangent tau from the centroid (cx, cy), member m (offset e_m) is seen at
 * tau - e_m u, and the kernel's (|x - c| / |x - s|)^3 for the centroid instead of the member is off
 * by ((1 + |tau|^2) / (1 + |tau_m|^2))^(3/2); lum: the supports' luminance textures. */
static void merged_table(const qtool_luminaire_spots *s, const qtool_luminaire *l, const int32_t pos[3],
                         const uint32_t *sup, const double *lpk, const double *lum, const uint32_t *mem, uint32_t nm,
                         double cx, double cy, double u, double *iv)
{
    const uint32_t n = s->n;
    const double A = (double)l->spacing * l->spacing;
    memset(iv, 0, sizeof(double) * n * n * 4);
    for (uint32_t j = 0; j < n; ++j)
        for (uint32_t i = 0; i < n; ++i) {
            double ld[3];
            oct_dir(i, j, n, ld);
            if (ld[2] <= 0)
                continue;
            const double tx = ld[0] / ld[2], ty = ld[1] / ld[2], t2 = 1 + tx * tx + ty * ty;
            double *o = iv + 4 * ((size_t)j * n + i);
            for (uint32_t k = 0; k < nm; ++k) {
                const uint32_t c = mem[k];
                /* the lamp's x is world -x */
                const double ex = -((double)s->pos[c][0] - pos[0] - cx) / 65536.0,
                             ey = ((double)s->pos[c][1] - pos[1] - cy) / 65536.0;
                const double mx = tx - ex * u, my = ty - ey * u, m2 = 1 + mx * mx + my * my, r = sqrt(m2);
                /* spot_intensity's luminance at lamp-frame direction (mx, my, 1) / r */
                double e = lum_sample(lum + (size_t)sup[c] * l->res * l->res, l->res, -mx / l->half_tan,
                                      my / l->half_tan);
                if (e <= 0)
                    continue;
                const double q = t2 / m2, v = A * e / r * q * sqrt(q);
                o[0] += v;
                for (int ch = 0; ch < 3; ++ch)
                    o[1 + ch] += v * (s->rgb[c][ch] / 65536.0 / lpk[c]);
            }
        }
}

/* The hierarchy: each group of 2^L x 2^L supports as one lamp at its lit members' flux-weighted
 * centroid, in s->nband versions (QTOOL_LUMINAIRE_BANDS, fewer where the tables' cap says so) by
 * the receiver's depth H = |dz| below S: band b's table (merged_table) at its band's middle 1 / H
 * (bands uniform in 1 / H up to the level's shallowest receiver, (1 + T) / (its distance bound), T
 * the cones' widest tangent). Level L serves a pixel whose distance bound is at least the group's
 * side over tol. sup, lpk: each level-0 lamp's support and luminance peak; iv: n n 4 doubles of
 * scratch. 0, or -1 with a reason in err. */
static int build_levels(qtool_luminaire_spots *s, const qtool_luminaire *l, const int32_t pos[3], double tol,
                        uint32_t nlevel, const double *lpk, const uint32_t *sup, double *iv, char *err, size_t errlen)
{
    const uint32_t n = s->n, ns = l->nx * l->ny, NB = s->nband;
    s->kfirst[0] = 0, s->kfirst[1] = s->count;
    uint64_t rad2 = 0;
    for (uint32_t c = 0; c < s->count; ++c) {
        uint64_t dx = uabs64((int64_t)s->pos[c][0] - pos[0]) >> 8, dy = uabs64((int64_t)s->pos[c][1] - pos[1]) >> 8;
        rad2 = dx * dx + dy * dy > rad2 ? dx * dx + dy * dy : rad2;
    }
    s->rad256 = (uint64_t)ceil(sqrt((double)rad2)) + 1;
    s->nlevel = nlevel, s->tol = tol;
    if (nlevel == 0)
        return 0;
    const double T = s->cullmax[0] >= 0 && s->cullmax[1] >= 0
                         ? hypot((double)s->cullmax[0], (double)s->cullmax[1]) / 65536.0 : 4.0;
    /* each support's luminance texture, as tex_sample computes it per texel */
    double *lum = malloc(sizeof(double) * ns * l->res * l->res);
    uint32_t *mem = malloc(sizeof(uint32_t) * ns);
    if (!lum || !mem) {
        free(lum), free(mem);
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    for (uint32_t m = 0; m < ns; ++m)
        for (uint32_t j = 0; j < l->res; ++j)
            for (uint32_t i = 0; i < l->res; ++i) {
                const float *t = l->tex + qtool_luminaire_texel(l, m % l->nx, m / l->nx, i, j);
                lum[((size_t)m * l->res + j) * l->res + i] = 0.2126 * t[0] + 0.7152 * t[1] + 0.0722 * t[2];
            }
    for (uint32_t L = 1; L <= nlevel; ++L) {
        const uint32_t gs = 1u << L, gx = (l->nx + gs - 1) >> L, gy = (l->ny + gs - 1) >> L;
        /* the side in 1/256 unit over tol, and band = bandk / (|dz| in 1/256 unit); both kept below
         * 2^62 (a tiny tol: a level no pixel reaches, not a cast beyond uint64) */
        const double lm = fmin(ceil(gs * (double)l->spacing * 256.0 / tol), 4611686018427387904.0);
        s->lmin[L] = (uint64_t)lm;
        const double umax = (1 + T) / (lm / 256.0), du = umax / NB;
        s->bandk[L] = (uint64_t)fmin(floor(256.0 / du), 4611686018427387904.0);
        for (uint32_t b = 0; b < NB; ++b) {
            for (uint32_t g = 0; g < gx * gy; ++g) {
                double cx = 0, cy = 0, pk;
                uint32_t nm = group_members(s, l, pos, sup, lpk, (g % gx) << L, (g / gx) << L, gs, mem, &cx, &cy);
                if (nm == 0)
                    continue;
                merged_table(s, l, pos, sup, lpk, lum, mem, nm, cx, cy, (b + 0.5) * du, iv);
                if (add_lamp(s, iv, n, pos[0] + cx, pos[1] + cy, pos[2], &pk, err, errlen) < 0) {
                    free(lum), free(mem);
                    return -1;
                }
            }
            s->kfirst[1 + (L - 1) * NB + b + 1] = s->total;
        }
    }
    free(lum), free(mem);
    return 0;
}

int qtool_luminaire_spots_make(const qtool_luminaire *l, const int32_t pos[3], uint32_t n, int far,
                               qtool_luminaire_spots *out, char *err, size_t errlen)
{
    const qtool_luminaire_spots_opts o = {.n = n, .far = far};
    return qtool_luminaire_spots_build(l, pos, &o, out, err, errlen);
}

int qtool_luminaire_spots_build(const qtool_luminaire *l, const int32_t pos[3], const qtool_luminaire_spots_opts *o,
                                qtool_luminaire_spots *out, char *err, size_t errlen)
{
    const uint32_t n = o->n ? o->n : 64;
    const int far = o->far;
    const double tol = far ? 0 : o->tol;
    if (!(tol >= 0 && tol <= QTOOL_LUMINAIRE_MAX_TOL)) {
        snprintf(err, errlen, "a hierarchy tolerance outside 0..%g", QTOOL_LUMINAIRE_MAX_TOL);
        return -1;
    }
    const uint32_t ns = l->nx * l->ny, side = l->nx > l->ny ? l->nx : l->ny;
    /* the levels: groups of 2^L x 2^L supports, L = 1 .. until one group holds the grid */
    uint32_t nlevel = 0, groups = 0, nband = QTOOL_LUMINAIRE_BANDS, cap = far ? 1 : ns;
    while (tol > 0 && (1u << nlevel) < side) {
        ++nlevel;
        groups += ((l->nx + (1u << nlevel) - 1) >> nlevel) * ((l->ny + (1u << nlevel) - 1) >> nlevel);
    }
    /* as many bands as the tables' cap allows (halved until they fit: coarser bands, larger error),
     * but never so few that the hierarchy's error bound would not hold: then refused */
    while (nband > QTOOL_LUMINAIRE_MIN_BANDS && (uint64_t)(cap + groups * nband) * n * n * 2u > QTOOL_LUMINAIRE_MAX_TABLES)
        nband >>= 1;
    if (groups && (uint64_t)(cap + groups * nband) * n * n * 2u > QTOOL_LUMINAIRE_MAX_TABLES) {
        snprintf(err, errlen, "the hierarchy's %u x %u lamps of %ux%u tables: more than %u MiB (a smaller --table, "
                 "or --tol 0)", groups, nband, n, n, QTOOL_LUMINAIRE_MAX_TABLES >> 20);
        return -1;
    }
    cap += groups * nband;
    if (n < QIBL_GONIO_MIN_N || n > QIBL_GONIO_MAX_N || (uint64_t)cap * n * n * 2u > QTOOL_LUMINAIRE_MAX_TABLES) {
        snprintf(err, errlen, "%u spotlights of %ux%u tables: more than %u MiB (a smaller --table)", cap, n, n,
                 QTOOL_LUMINAIRE_MAX_TABLES >> 20);
        return -1;
    }
    qtool_luminaire_spots s = {.n = n};
    memcpy(s.centre, pos, sizeof s.centre);
    s.cullmax[0] = s.cullmax[1] = 0;
    s.tables = malloc(sizeof(uint16_t) * n * n * cap);
    s.gonio = malloc(sizeof *s.gonio * cap);
    s.pos = malloc(sizeof *s.pos * cap);
    s.rgb = malloc(sizeof *s.rgb * cap);
    s.cull = malloc(sizeof *s.cull * cap);
    s.aw = malloc(sizeof *s.aw * cap);
    s.occ = malloc(sizeof *s.occ * cap);
    s.kocc = malloc(sizeof *s.kocc * cap);
    double *iv = malloc(sizeof(double) * n * n * 4), *lpk = malloc(sizeof(double) * cap);
    uint32_t *sup = malloc(sizeof(uint32_t) * cap);
    if (!s.tables || !s.gonio || !s.pos || !s.rgb || !s.cull || !s.aw || !s.occ || !s.kocc || !iv || !lpk || !sup) {
        free(iv), free(lpk), free(sup), qtool_luminaire_spots_free(&s);
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    const double h = l->spacing;
    for (uint32_t m = 0; m < ns; m += far ? ns : 1) {
        /* the table in double: luminance and the three channels' sums (far: over every support) */
        memset(iv, 0, sizeof(double) * n * n * 4);
        for (uint32_t j = 0; j < n; ++j)
            for (uint32_t i = 0; i < n; ++i) {
                double ld[3];
                oct_dir(i, j, n, ld);
                for (uint32_t q = far ? 0 : m; q < (far ? ns : m + 1); ++q)
                    for (int ch = 0; ch < 4; ++ch)
                        iv[4 * ((size_t)j * n + i) + (size_t)ch] +=
                            spot_intensity(l, q % l->nx, q / l->nx, ld, ch == 0 ? 3 : ch - 1);
            }
        double ou = far ? 0 : ((m % l->nx) - (l->nx - 1) / 2.0) * h, ov = far ? 0 : ((m / l->nx) - (l->ny - 1) / 2.0) * h;
        const uint32_t c = s.total;
        int r = add_lamp(&s, iv, n, pos[0] + ou * 65536.0, pos[1] + ov * 65536.0, pos[2], &lpk[c], err, errlen);
        if (r < 0) {
            free(iv), free(lpk), free(sup), qtool_luminaire_spots_free(&s);
            return -1;
        }
        if (r == 0)
            continue;
        sup[c] = m;
        s.count = c + 1;
        for (int k = 0; k < 2; ++k) {
            uint64_t rr = uabs64((int64_t)s.pos[c][k] - pos[k]);
            s.reach[k] = rr > s.reach[k] ? rr : s.reach[k];
            if (s.cullmax[k] >= 0)
                s.cullmax[k] = s.cull[c][k] < 0 ? -1 : s.cull[c][k] > s.cullmax[k] ? s.cull[c][k] : s.cullmax[k];
        }
    }
    s.nband = nband;
    if (build_levels(&s, l, pos, tol, nlevel, lpk, sup, iv, err, errlen) != 0) {
        free(iv), free(lpk), free(sup), qtool_luminaire_spots_free(&s);
        return -1;
    }
    free(iv), free(lpk), free(sup);
    set_anchors(&s, pos, far);
    *out = s;
    return 0;
}

static unsigned bitlen64(uint64_t v)
{
#if defined(__GNUC__) || defined(__clang__)
    return v ? 64u - (unsigned)__builtin_clzll(v) : 0u; /* one instruction: called per pass, pixel, channel */
#else
    unsigned b = 0;
    while (v)
        ++b, v >>= 1;
    return b;
#endif
}

/* |d|^2 in (1/256 unit)^2 of a Q16.16 difference (each |component| <= 2^32: <= 3 2^48) */
static uint64_t d2_256(int64_t dx, int64_t dy, int64_t dz)
{
    uint64_t a = uabs64(dx) >> 8, b = uabs64(dy) >> 8, c = uabs64(dz) >> 8;
    return a * a + b * b + c * c;
}

/* |a|^2 / |b|^2 in Q16 for two (1/256 unit)^2 squared distances (b floored to 1), at most 2^32 */
static uint64_t ratio_q16(uint64_t a, uint64_t b)
{
    unsigned bl = bitlen64(a), sh = bl > 46 ? bl - 46 : 0;
    a >>= sh, b >>= sh;
    b = b ? b : 1;
    /* floor((a 2^16) / b), a < 2^46: a double quotient corrected exactly (the kernel's hottest
     * division; the hardware's 64-bit divide was slower); quotients beyond 2^33 saturate anyway */
    const uint64_t A = a << 16;
    double qd = (double)A / (double)b;
    if (qd > 8589934592.0)
        return (uint64_t)1 << 32;
    uint64_t r = (uint64_t)qd; /* within 2 of the floor: b (q + 2) < 2^63 */
    while (r * b > A)
        --r;
    while ((r + 1) * b <= A)
        ++r;
    return r > ((uint64_t)1 << 32) ? (uint64_t)1 << 32 : r;
}

/* qibl_gonio_lookup's texel position, its division a double quotient corrected exactly: num < 2^54
 * has at most 41 significant bits ((a + s) <= 2^31 times n <= 2^8, times 2^15), so (double)num is
 * exact, the quotient (< 2^24) correctly rounded, within 1 of the floor */
static uint32_t texel_pos_twin(int64_t a, uint64_t s, uint32_t n)
{
    uint64_t num = (uint64_t)(a + (int64_t)s) * ((uint64_t)n << 15);
    uint64_t q = (uint64_t)((double)num / (double)s);
    if (q * s > num)
        --q;
    else if ((q + 1) * s <= num)
        ++q;
    uint64_t hi = (uint64_t)(n - 1u) << 16;
    if (q < 32768u)
        return 0;
    q -= 32768u;
    return (uint32_t)(q > hi ? hi : q);
}

static int32_t shrink_twin(int64_t v, unsigned sh)
{
    uint32_t m = (uint32_t)(uabs64(v) >> sh);
    return v < 0 ? -(int32_t)m : (int32_t)m;
}

static int64_t dot3_twin(const int32_t a[3], const int32_t b[3])
{
    return (int64_t)a[0] * b[0] + (int64_t)a[1] * b[1] + (int64_t)a[2] * b[2];
}

/* qibl_gonio_lookup, bit for bit (tests/luminaire_test.c checks the twins on random directions),
 * with hardware shifts, products and a corrected double quotient for its two divisions */
uint32_t qtool_luminaire_lookup(const qibl_gonio_t *g, const int64_t d[3])
{
    uint64_t m = uabs64(d[0]);
    m = uabs64(d[1]) > m ? uabs64(d[1]) : m;
    m = uabs64(d[2]) > m ? uabs64(d[2]) : m;
    unsigned bl = bitlen64(m), sh = bl > 24u ? bl - 24u : 0u;
    int32_t w[3] = {shrink_twin(d[0], sh), shrink_twin(d[1], sh), shrink_twin(d[2], sh)};
    int64_t l[3] = {dot3_twin(w, g->x), dot3_twin(w, g->y), dot3_twin(w, g->z)};
    uint64_t al[3] = {uabs64(l[0]), uabs64(l[1]), uabs64(l[2])};
    uint64_t s = al[0] + al[1] + al[2];
    unsigned sl = bitlen64(s), sh2 = sl > 30u ? sl - 30u : 0u;
    for (int k = 0; k < 3; ++k)
        al[k] >>= sh2;
    s = al[0] + al[1] + al[2];
    int64_t ax = 0, ay = 0;
    if (s == 0u) {
        s = 1u;
    } else if (l[2] >= 0) {
        ax = (int64_t)al[0], ay = (int64_t)al[1];
    } else {
        ax = (int64_t)(s - al[1]), ay = (int64_t)(s - al[0]);
    }
    if (l[0] < 0)
        ax = -ax;
    if (l[1] < 0)
        ay = -ay;
    const uint32_t n = g->n;
    uint32_t fx = texel_pos_twin(ax, s, n), fy = texel_pos_twin(ay, s, n);
    uint32_t i0 = fx >> 16, j0 = fy >> 16, tx = fx & 0xFFFFu, ty = fy & 0xFFFFu;
    uint32_t i1 = i0 + 1u < n ? i0 + 1u : i0, j1 = j0 + 1u < n ? j0 + 1u : j0;
    const uint16_t *r0 = g->table + (size_t)j0 * n, *r1 = g->table + (size_t)j1 * n;
    uint32_t a = r0[i0] * (65536u - tx) + r0[i1] * tx;
    uint32_t b = r1[i0] * (65536u - tx) + r1[i1] * tx;
    uint64_t v = (uint64_t)a * (65536u - ty) + (uint64_t)b * ty;
    return (uint32_t)((v + ((uint64_t)1 << 31)) >> 32);
}

uint64_t qtool_luminaire_isqrt(uint64_t x)
{
    /* x <= 2^52 is exact in a double and its sqrt correctly rounded, so the estimate is within 1 of
     * floor(sqrt(x)); the integer steps make it exact (it was the kernel's hottest call as the core's
     * digit-by-digit qibl_isqrt_u64, 32 steps) */
    uint64_t r = (uint64_t)sqrt((double)x);
    while (r * r > x)
        --r;
    while ((r + 1) * (r + 1) <= x)
        ++r;
    return r;
}

/* r^(3/2) in Q16 for r in Q16 (<= 2^32), saturated at 2^31: (|a| / |b|)^3 from the squares' ratio */
static uint64_t pow15_q16(uint64_t r)
{
    uint64_t sq = qtool_luminaire_isqrt(r << 16); /* Q16, <= 2^24 (floor, as qibl_isqrt_u64) */
    uint64_t v = (r * sq + 32768u) >> 16;        /* <= 2^56 >> 16 */
    return v > ((uint64_t)1 << 31) ? (uint64_t)1 << 31 : v;
}

int qtool_luminaire_reaches(const qtool_luminaire_spots *s, const int32_t q[3])
{
    int64_t dz = (int64_t)q[2] - s->centre[2];
    if (dz >= 0)
        return 0; /* at or above S */
    uint64_t az = uabs64(dz);
    uint64_t ax = uabs64((int64_t)q[0] - s->centre[0]), ay = uabs64((int64_t)q[1] - s->centre[1]);
    /* |x - c| <= |x - s_j| + |s_j - c|: beyond cull |dz| + reach no spotlight sees it
     * (|a| 2^16 <= 2^48; cull <= 2^30 times |dz| <= 2^32) */
    if (s->cullmax[0] >= 0 && ax > s->reach[0] && ((ax - s->reach[0]) << 16) > (uint64_t)s->cullmax[0] * az)
        return 0;
    if (s->cullmax[1] >= 0 && ay > s->reach[1] && ((ay - s->reach[1]) << 16) > (uint64_t)s->cullmax[1] * az)
        return 0;
    return 1;
}

size_t qtool_luminaire_span_ws_size(uint32_t n)
{
    return (size_t)n * QTOOL_LUMINAIRE_WS_PER_PIXEL * sizeof(int64_t);
}

/* The key of pixel q's work (0: every spotlight; s->nlevel 0: always 0), or -1 when no spotlight
 * reaches it; *dc gets |q - c|^2 (1/256 unit). Level L serves q when a lower bound on q's distance
 * to every spotlight, max(|dz|, |q - c| - the farthest spotlight's distance from c), is at least
 * s->lmin[L] (1/256 unit): the group's side is then at most tol times that distance; then its band
 * by 1 / |dz|, key 1 + (L - 1) nband + band. */
static int pixel_key(const qtool_luminaire_spots *s, const int32_t q[3], uint64_t *dc)
{
    if (!qtool_luminaire_reaches(s, q))
        return -1;
    int64_t dz = (int64_t)q[2] - s->centre[2];
    *dc = d2_256((int64_t)q[0] - s->centre[0], (int64_t)q[1] - s->centre[1], dz);
    if (s->nlevel == 0)
        return 0;
    uint64_t r = qtool_luminaire_isqrt(*dc), az = uabs64(dz) >> 8;
    uint64_t lb = r > s->rad256 ? r - s->rad256 : 0;
    lb = lb > az ? lb : az;
    uint32_t L = 0;
    while (L < s->nlevel && lb >= s->lmin[L + 1])
        ++L;
    if (L == 0)
        return 0;
    uint64_t b = az ? s->bandk[L] / az : s->nband - 1;
    b = b < s->nband - 1 ? b : s->nband - 1;
    return (int)(1 + (L - 1) * s->nband + b);
}

/* Pixel i's record: its index, |x - c|^2 and B_k = base_k (|x - a_k| / |x - c|)^3 for each anchor
 * (the anchors' n.(a_k - x) V rho / pi, scaled by 1/|x - c|^3: linear in a_k, so interpolating it
 * at a spotlight and multiplying by (|x - c| / |x - s|)^3 gives that spotlight's shading) */
static void pixel_record(const qtool_luminaire_spots *s, const int32_t *base, const int32_t *p, uint32_t n, uint32_t i,
                         uint64_t dc, int64_t *w)
{
    const uint32_t na = s->nanchor;
    const int32_t *q = p + 3 * (size_t)i;
    int64_t dz = (int64_t)q[2] - s->centre[2];
    w[13] = (int64_t)i, w[12] = (int64_t)dc;
    w[14] = (int64_t)(((uint64_t)1 << 48) / uabs64(dz)); /* 2^48 / |dz|: tangents by one product */
    for (uint32_t k = 0; k < na; ++k) {
        const int32_t *a = s->anchor[k];
        uint64_t r3 = na == 1 ? 65536u
                              : pow15_q16(ratio_q16(d2_256((int64_t)q[0] - a[0], (int64_t)q[1] - a[1],
                                                           (int64_t)q[2] - a[2]), dc));
        for (int c = 0; c < 3; ++c) {
            int32_t b = base[3 * ((size_t)k * n + i) + (size_t)c];
            /* |b| r3 <= 2^31 2^31: rounded to Q16, kept within 2^40 */
            uint64_t m = ((uint64_t)(b < 0 ? -(int64_t)b : b) * r3 + 32768u) >> 16;
            m = m > ((uint64_t)1 << 40) ? (uint64_t)1 << 40 : m;
            w[3 * k + (uint32_t)c] = b < 0 ? -(int64_t)m : (int64_t)m;
        }
    }
}

/* The passes of spotlights j0 .. j1 - 1 over the records k0 .. k1 - 1 of ws. */
static void run_passes(const qtool_luminaire_spots *s, uint32_t j0, uint32_t j1, const int32_t *p, const int64_t *ws,
                       uint32_t k0, uint32_t k1, int64_t *acc)
{
    const uint32_t na = s->nanchor;
    for (uint32_t j = j0; j < j1; ++j) { /* one pass per spotlight */
        const int32_t *sp = s->pos[j];
        const int64_t c0 = s->cull[j][0], c1 = s->cull[j][1];
        const int32_t *aw = s->aw[j];
        for (uint32_t k = k0; k < k1; ++k) {
            const int64_t *wp = ws + (size_t)k * QTOOL_LUMINAIRE_WS_PER_PIXEL;
            const uint32_t i = (uint32_t)wp[13];
            const int32_t *q = p + 3 * (size_t)i;
            int64_t d[3] = {(int64_t)q[0] - sp[0], (int64_t)q[1] - sp[1], (int64_t)q[2] - sp[2]};
            if (d[2] >= 0)
                continue; /* at or above S: the table is 0 there (the cull bounds say so) */
            uint64_t az = uabs64(d[2]);
            /* |d_x| 2^16 <= 2^48, cull <= 2^30 times |d_z| <= 2^32: both below 2^63 */
            if (c0 >= 0 && (uabs64(d[0]) << 16) > (uint64_t)c0 * az)
                continue;
            if (c1 >= 0 && (uabs64(d[1]) << 16) > (uint64_t)c1 * az)
                continue;
            if (c0 >= 0 && c1 >= 0) {
                /* the occupancy cell: tan = |d| / |dz| in Q16 by the pixel's 2^48 / |dz| (below 2^62:
                 * |d| <= T |dz| with T <= 2^14 after the cull); (tan + T) < 2 T + 1, times kocc
                 * < OCC 2^32 */
                uint64_t r = (uint64_t)wp[14];
                uint64_t tx = (uabs64(d[0]) * r) >> 32, ty = (uabs64(d[1]) * r) >> 32;
                uint64_t ux = d[0] < 0 ? (uint64_t)c0 - tx : (uint64_t)c0 + tx;
                uint64_t uy = d[1] < 0 ? (uint64_t)c1 - ty : (uint64_t)c1 + ty;
                uint32_t cx = (uint32_t)((ux * s->kocc[j][0]) >> 32), cy = (uint32_t)((uy * s->kocc[j][1]) >> 32);
                cx = cx < QTOOL_LUMINAIRE_OCC ? cx : QTOOL_LUMINAIRE_OCC - 1;
                cy = cy < QTOOL_LUMINAIRE_OCC ? cy : QTOOL_LUMINAIRE_OCC - 1;
                if (!(s->occ[j][cy] >> cx & 1u))
                    continue;
            }
            uint32_t sc = qtool_luminaire_lookup(&s->gonio[j], d);
            if (sc == 0)
                continue;
            /* Q16 weight: the scale (Q1.15) times (|x - c| / |x - s|)^3 (<= 2^31) */
            uint64_t w = na == 1 ? (uint64_t)sc << 1
                                 : ((uint64_t)sc * pow15_q16(ratio_q16((uint64_t)wp[12], d2_256(d[0], d[1], d[2]))) +
                                    16384u) >> 15;
            for (int c = 0; c < 3; ++c) {
                /* the shading at the spotlight: the anchors' B interpolated (weights Q15, sum 2^15;
                 * |B| <= 2^40: the sum < 2^57); an anchor the surface faces away from gives 0, so at
                 * grazing incidence this is the interpolation of the clamped cosine */
                int64_t bs = 0;
                for (uint32_t a = 0; a < na; ++a)
                    bs += (int64_t)aw[a] * wp[3 * a + (uint32_t)c];
                bs = bs < 0 ? -(int64_t)(((uint64_t)-bs + 16384u) >> 15) : (int64_t)(((uint64_t)bs + 16384u) >> 15);
                int32_t b = bs > INT32_MAX ? INT32_MAX : bs < -INT32_MAX ? -INT32_MAX : (int32_t)bs;
                /* b (Q16.16) times w (Q16) times the peak (Q16.16), into Q8.24 with one rounding:
                 * t = w rgb < 2^62 kept to its top 31 bits (2^-31 relative), then |b| times that
                 * < 2^62; a pass adds at most 2^50, so 4096 passes stay below 2^62 */
                uint64_t t = w * (uint64_t)s->rgb[j][c];
                if (t == 0 || b == 0)
                    continue;
                unsigned bl = bitlen64(t), sh = bl > 31 ? bl - 31 : 0;
                uint64_t pr = (uint64_t)(b < 0 ? -(int64_t)b : b) * (t >> sh), mag;
                if (sh >= 24) {
                    unsigned l = sh - 24; /* <= 7 */
                    mag = pr >= ((uint64_t)1 << (50 - l)) ? (uint64_t)1 << 50 : pr << l;
                } else {
                    unsigned r = 24 - sh;
                    mag = (pr + ((uint64_t)1 << (r - 1))) >> r;
                    mag = mag > ((uint64_t)1 << 50) ? (uint64_t)1 << 50 : mag;
                }
                acc[3 * (size_t)i + (size_t)c] += b < 0 ? -(int64_t)mag : (int64_t)mag;
            }
        }
    }
}

void qtool_luminaire_spots_span(const qtool_luminaire_spots *s, const int32_t *base, const int32_t *p, uint32_t n,
                                int64_t *acc, int64_t *ws)
{
    /* the pixels any spotlight can reach (below S, inside the union of the cull cones), once per
     * span, their records grouped by key (a counting sort), so every pass visits only its own
     * pixels; integer sums, so the order changes nothing. The first sweep keeps each pixel's key and
     * |x - c|^2 in its slot's last word (dc < 2^50, key + 1 < 2^8), which no record writes */
    uint32_t cnt[QTOOL_LUMINAIRE_KEYS + 1];
    memset(cnt, 0, sizeof cnt);
    const uint32_t nk = s->nlevel ? 1 + s->nlevel * s->nband : 1;
    for (uint32_t i = 0; i < n; ++i) {
        uint64_t dc = 0;
        int key = pixel_key(s, p + 3 * (size_t)i, &dc);
        ws[(size_t)i * QTOOL_LUMINAIRE_WS_PER_PIXEL + 15] = (int64_t)(dc << 8 | (uint64_t)(key + 1));
        if (key >= 0)
            ++cnt[key + 1];
    }
    for (uint32_t k = 1; k <= nk; ++k)
        cnt[k] += cnt[k - 1]; /* cnt[k]: the first record of key k */
    uint32_t at[QTOOL_LUMINAIRE_KEYS];
    memcpy(at, cnt, sizeof(uint32_t) * nk);
    for (uint32_t i = 0; i < n; ++i) {
        const uint64_t kd = (uint64_t)ws[(size_t)i * QTOOL_LUMINAIRE_WS_PER_PIXEL + 15];
        const uint32_t key1 = (uint32_t)(kd & 0xFFu);
        if (key1)
            pixel_record(s, base, p, n, i, kd >> 8, ws + (size_t)at[key1 - 1]++ * QTOOL_LUMINAIRE_WS_PER_PIXEL);
    }
    for (uint32_t k = 0; k < nk; ++k) {
        const uint32_t j0 = k == 0 ? 0 : s->kfirst[k], j1 = k == 0 ? s->count : s->kfirst[k + 1];
        const uint32_t k0 = k == 0 ? 0 : cnt[k], k1 = at[k];
        if (j1 > j0 && k1 > k0)
            run_passes(s, j0, j1, p, ws, k0, k1, acc);
    }
}

int32_t qtool_luminaire_q16(int64_t acc)
{
    /* round half away from zero by magnitude (no shift of a negative value), then saturate */
    uint64_t m = acc < 0 ? (uint64_t)0 - (uint64_t)acc : (uint64_t)acc;
    m = (m + 128u) >> 8;
    if (m > INT32_MAX)
        m = INT32_MAX;
    return acc < 0 ? -(int32_t)m : (int32_t)m;
}

qibl_status_t qtool_luminaire_views_open(const uint8_t *asset, size_t n, qtool_luminaire_views *v)
{
    qibl_asset_t a;
    memset(v, 0, sizeof *v);
    qibl_status_t st = qtool_asset_open(&a, asset, n);
    if (st == QIBL_OK)
        st = qibl_asset_point_shmaps(&a, &v->mp);
    if (st == QIBL_OK)
        st = qibl_asset_pmap(&a, &v->pm);
    v->lut = st == QIBL_OK && qibl_asset_ylut(&a, &v->lut_view) == QIBL_OK ? &v->lut_view : NULL;
    return st;
}

int qtool_luminaire_relight(const qtool_luminaire_spots *s, const qibl_shmaps_t *mp, const qibl_pmap_t *pm,
                            const qibl_ylut_t *lut, uint32_t exposure, int srgb, uint8_t *rgb8, float *lin, double *ms,
                            qibl_status_t *status)
{
    const uint32_t w = mp->width, h = mp->height;
    size_t wsn = qibl_shmap_point_workspace_size(mp->k, w);
    uint8_t *pix = malloc((size_t)w * h * 4);
    int32_t *row = malloc(sizeof(int32_t) * 3 * w * 4), *pts = malloc(sizeof(int32_t) * 3 * w);
    int64_t *acc = malloc(sizeof(int64_t) * 3 * w);
    void *ws = malloc(wsn ? wsn : 1);
    int64_t *idx = malloc(qtool_luminaire_span_ws_size(w));
    qibl_status_t st = QIBL_OK;
    if (!pix || !row || !pts || !acc || !ws || !idx) {
        st = QIBL_E_NULL_POINTER;
        goto out;
    }
    qibl_fb_desc_t fb = {.pixels = pix, .width = w, .height = h, .format = QIBL_FB_RGBA8888, .srgb = srgb ? 1 : 0,
                         .exposure = exposure};
    /* a unit lamp at each shading anchor, 1/d^2: visibility, cosine and albedo for the spotlights */
    qibl_shmap_point_t pt[4];
    struct timespec t0, t1;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t0); /* CPU time: a shared machine's wall clock counts others' turns */
    for (uint32_t k = 0; st == QIBL_OK && k < s->nanchor; ++k) {
        qibl_pointlight_t pl = {.pos = {s->anchor[k][0], s->anchor[k][1], s->anchor[k][2]},
                                .rgb = {65536, 65536, 65536}, .falloff = QIBL_FALLOFF_INV_DIST2,
                                .filter = lut ? QIBL_LUT_BILINEAR : QIBL_POINT_POLY};
        st = qibl_shmap_point_prepare(mp, pm, lut, &pl, &pt[k]);
    }
    for (uint32_t y = 0; st == QIBL_OK && y < h; ++y) {
        /* the anchors' shading only over the row's pixels some spotlight reaches (x0 .. x1 - 1) */
        uint32_t x0 = w, x1 = 0;
        for (uint32_t x = 0; x < w; ++x) {
            qibl_pmap_point(pm, x, y, pts + 3 * (size_t)x);
            if (qtool_luminaire_reaches(s, pts + 3 * (size_t)x))
                x0 = x < x0 ? x : x0, x1 = x + 1;
        }
        memset(acc, 0, sizeof(int64_t) * 3 * w);
        const uint32_t nw = x1 > x0 ? x1 - x0 : 0;
        for (uint32_t k = 0; st == QIBL_OK && nw && k < s->nanchor; ++k)
            st = qibl_shmap_point_span(&pt[k], x0, y, nw, row + (size_t)k * 3 * nw, ws, wsn);
        if (st != QIBL_OK)
            break;
        if (nw)
            qtool_luminaire_spots_span(s, row, pts + 3 * (size_t)x0, nw, acc + 3 * (size_t)x0, idx);
        for (size_t i = 0; i < (size_t)w * 3; ++i) /* round and saturate once: the sum, not each pass */
            row[i] = qtool_luminaire_q16(acc[i]);
        st = qtool_bake_frame_row(&fb, y, w, row, lin);
    }
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t1);
    if (ms)
        *ms = (double)(t1.tv_sec - t0.tv_sec) * 1e3 + (double)(t1.tv_nsec - t0.tv_nsec) * 1e-6;
    for (size_t i = 0; st == QIBL_OK && i < (size_t)w * h; ++i)
        memcpy(rgb8 + 3 * i, pix + 4 * i, 3);
out:
    free(pix), free(row), free(pts), free(acc), free(ws), free(idx);
    if (status)
        *status = st;
    return st == QIBL_OK ? 0 : -1;
}
