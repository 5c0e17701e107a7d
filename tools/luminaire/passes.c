/*
 * luminaire/passes.c - the near-field source summed pass by pass (one pass per spotlight), as the
 * paper's GPU does it: in an 8-bit sRGBE target (decode, add, re-encode with the core's codec,
 * integers only), beside a binary32 accumulation and the core's one-call integer sum; the report of
 * `qibl luminaire passes`.
 *
 * Invariants: a pass's terms are qtool_luminaire_spots_span's own for that spotlight (a view of the
 * spots with one spotlight), so the passes' integer sum is the one-call sum exactly; the sRGBE
 * target never saturates (its fixed-point format is chosen from the sum of the terms' magnitudes).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "luminaire/luminaire.h"
#include "qibl/soft.h"
#include "qibl/srgbe.h"


void qtool_luminaire_spot_pass(const qtool_luminaire_spots *s, uint32_t j, const int32_t *base, const int32_t *p,
                               uint32_t n, int64_t *acc, int64_t *ws)
{
    /* the same spots with spotlight j alone: the union cull (centre, reach, cullmax) and the
     * anchors stay, so each pixel's shading is the one the full call computes */
    qtool_luminaire_spots v = *s;
    v.count = 1, v.total = 1, v.nlevel = 0; /* level 0: the passes are the exact sum's */
    v.tables = s->tables + (size_t)j * s->n * s->n;
    v.gonio = s->gonio + j, v.pos = s->pos + j, v.rgb = s->rgb + j, v.cull = s->cull + j;
    v.occ = s->occ + j, v.kocc = s->kocc + j, v.aw = s->aw + j;
    qtool_luminaire_spots_span(&v, base, p, n, acc, ws);
}

int qtool_luminaire_srgbe_frac(uint64_t maxabs)
{
    /* the largest F <= 24 with maxabs (Q8.24) at F fraction bits, plus a rounding, below 2^30 */
    int f = 24;
    while (f > -32 && (maxabs >> (24 - f)) + 1u >= ((uint64_t)1 << 30))
        --f;
    return f;
}

/* v (Q8.24) at f fraction bits (f <= 24), rounded half away from zero */
static int64_t to_frac(int64_t v, int f)
{
    if (f >= 24)
        return v;
    unsigned sh = (unsigned)(24 - f);
    uint64_t m = v < 0 ? (uint64_t)0 - (uint64_t)v : (uint64_t)v;
    m = sh >= 64 ? 0 : (m + ((uint64_t)1 << (sh - 1))) >> sh;
    return v < 0 ? -(int64_t)m : (int64_t)m;
}

/* hi (+ lo, when not NULL) + term of pixel i at frac_bits into v: QIBL_OK, or QIBL_E_RANGE (a sum at
 * or beyond 2^31, or frac_bits outside -64..24), or the decoder's status */
static qibl_status_t pixel_sum(const uint8_t *hi, const uint8_t *lo, const int64_t *term, uint32_t i, int frac_bits,
                               int32_t v[3])
{
    int32_t h[3], r[3] = {0, 0, 0};
    if (frac_bits < -64 || frac_bits > 24)
        return QIBL_E_RANGE;
    qibl_status_t st = qibl_srgbe_decode_s32(hi + 4 * (size_t)i, frac_bits, h);
    if (st == QIBL_OK && lo)
        st = qibl_srgbe_decode_s32(lo + 4 * (size_t)i, frac_bits, r);
    if (st != QIBL_OK)
        return st;
    for (int k = 0; k < 3; ++k) {
        /* |h|, |r| < 2^31; a term beyond 2^62 is refused before it is rounded */
        int64_t t = term[3 * (size_t)i + (size_t)k];
        if (t > ((int64_t)1 << 62) || t < -((int64_t)1 << 62))
            return QIBL_E_RANGE;
        t = to_frac(t, frac_bits);
        int64_t s = (int64_t)h[k] + r[k] + t; /* each below 2^62 in magnitude: no overflow */
        if (s > INT32_MAX || s < -INT32_MAX)
            return QIBL_E_RANGE;
        v[k] = (int32_t)s;
    }
    return QIBL_OK;
}

/* srgbe_add (lo NULL) and srgbe_add2 */
static qibl_status_t add_pass(uint8_t *hi, uint8_t *lo, const int64_t *term, uint32_t n, int frac_bits)
{
    int32_t v[3], h[3], e[3];
    for (uint32_t i = 0; i < n; ++i) { /* every pixel checked before any is written */
        qibl_status_t st = pixel_sum(hi, lo, term, i, frac_bits, v);
        if (st != QIBL_OK)
            return st;
    }
    /* an int32 at frac_bits >= -64 is below 2^95, in the codec's range: the checked calls below
     * cannot fail once the check above passed */
    qibl_status_t st = QIBL_OK;
    for (uint32_t i = 0; st == QIBL_OK && i < n; ++i) {
        st = pixel_sum(hi, lo, term, i, frac_bits, v);
        if (st == QIBL_OK)
            st = qibl_srgbe_encode_s32(v, frac_bits, hi + 4 * (size_t)i);
        if (!lo)
            continue;
        /* hi's code is within half a step of v, so it decodes without saturating */
        if (st == QIBL_OK)
            st = qibl_srgbe_decode_s32(hi + 4 * (size_t)i, frac_bits, h);
        for (int k = 0; st == QIBL_OK && k < 3; ++k)
            e[k] = v[k] - h[k]; /* what hi rounded away: at most half its step */
        if (st == QIBL_OK)
            st = qibl_srgbe_encode_s32(e, frac_bits, lo + 4 * (size_t)i);
    }
    return st;
}

qibl_status_t qtool_luminaire_srgbe_add(uint8_t *codes, const int64_t *term, uint32_t n, int frac_bits)
{
    return add_pass(codes, NULL, term, n, frac_bits);
}

qibl_status_t qtool_luminaire_srgbe_add2(uint8_t *hi, uint8_t *lo, const int64_t *term, uint32_t n, int frac_bits)
{
    return add_pass(hi, lo, term, n, frac_bits);
}

void qtool_luminaire_srgbe_clear(uint8_t *codes, uint32_t n)
{
    for (uint32_t i = 0; i < n; ++i) {
        codes[4 * (size_t)i] = codes[4 * (size_t)i + 1] = codes[4 * (size_t)i + 2] = QIBL_SRGBE_ZERO_X;
        codes[4 * (size_t)i + 3] = QIBL_SRGBE_ZERO_E;
    }
}

int qtool_luminaire_synthetic(uint32_t grid, qtool_luminaire *out)
{
    /* every support lit: a smooth lobe per support, tinted by its place, so every pass adds light
     * of its own colour and shape; E' is independent of the grid, A = h^2 shrinks with it, so the
     * total light is about the same for any pass count */
    const uint32_t res = 16;
    qtool_luminaire l = {.nx = grid, .ny = grid, .res = res, .basis = QTOOL_LUMINAIRE_BOX,
                         .spacing = (float)(QTOOL_LUMINAIRE_SIZE / grid), .distance = 1.0f, .half_tan = 2.0f};
    l.tex = malloc(sizeof(float) * 3 * grid * grid * res * res);
    if (!l.tex)
        return -1;
    for (uint32_t iy = 0; iy < grid; ++iy)
        for (uint32_t ix = 0; ix < grid; ++ix) {
            double fx = (ix + 0.5) / grid, fy = (iy + 0.5) / grid;
            double tint[3] = {0.6 + 0.4 * fx, 0.7 + 0.3 * fy, 1.0 - 0.5 * fx * fy};
            double ax = 0.6 * (fx - 0.5), ay = 0.6 * (fy - 0.5); /* the lobe leans outward */
            for (uint32_t j = 0; j < res; ++j)
                for (uint32_t i = 0; i < res; ++i) {
                    double s = (2.0 * i + 1) / res - 1, t = (2.0 * j + 1) / res - 1;
                    double r2 = (s - ax) * (s - ax) + (t - ay) * (t - ay);
                    double e = QTOOL_LUMINAIRE_LE * exp(-2.5 * r2) * (1 + 0.25 * cos(9 * s + 5 * t));
                    float *o = l.tex + qtool_luminaire_texel(&l, ix, iy, i, j);
                    for (int k = 0; k < 3; ++k)
                        o[k] = (float)(e * tint[k]);
                }
        }
    *out = l;
    return 0;
}

static int32_t q16d(double v)
{
    v *= 65536.0;
    return v >= 2147483647.0 ? INT32_MAX : v <= -2147483647.0 ? -INT32_MAX : (int32_t)lround(v);
}

void qtool_luminaire_passes_free(qtool_luminaire_passes *r)
{
    if (!r)
        return;
    free(r->terms), free(r->shown);
    memset(r, 0, sizeof *r);
}

int qtool_luminaire_passes_run(const qtool_luminaire *l, uint32_t size, double hgt, qtool_luminaire_passes *out)
{
    qtool_luminaire_spots s;
    char err[128];
    int32_t pos[3] = {0, 0, q16d(hgt)};
    if (qtool_luminaire_spots_make(l, pos, 64, 0, &s, err, sizeof err) != 0)
        return -1;
    const uint32_t n = size, np = s.count, na = s.nanchor;
    const size_t npix = (size_t)n * n;
    qtool_luminaire_passes r = {.passes = np, .size = n};
    int32_t *base = malloc(sizeof(int32_t) * 3 * n * na), *pts = malloc(sizeof(int32_t) * 3 * n);
    int64_t *ws = malloc(qtool_luminaire_span_ws_size(n));
    r.terms = calloc((size_t)np * 3 * npix, sizeof(int64_t));
    r.shown = malloc(4 * 4 * npix);
    int rc = base && pts && ws && r.terms && r.shown ? 0 : -1;
    const double half = 1.8 * hgt + QTOOL_LUMINAIRE_SIZE / 2;
    for (uint32_t y = 0; rc == 0 && y < n; ++y) {
        /* the ground plane below the source, shaded as the study's (a unit lamp at each anchor,
         * 1/d^2, Lambert, albedo 1) */
        for (uint32_t x = 0; x < n; ++x) {
            const double p[3] = {-half + (x + 0.5) * 2 * half / n, -half + (y + 0.5) * 2 * half / n, 0};
            qtool_luminaire_ground_pixel(&s, p, x, n, pts, base);
        }
        for (uint32_t j = 0; j < np; ++j)
            qtool_luminaire_spot_pass(&s, j, base, pts, n, r.terms + ((size_t)j * npix + (size_t)y * n) * 3, ws);
    }
    free(base), free(pts), free(ws), qtool_luminaire_spots_free(&s);
    if (rc != 0) {
        qtool_luminaire_passes_free(&r);
        return -1;
    }
    /* the four sums, each in Q16.16 for the display: the exact one (int64: the core's one-call sum,
     * rounded once), binary32 pass by pass, sRGBE pass by pass; and the double reference */
    uint64_t maxabs = 0;
    double peak = 0;
    for (size_t i = 0; i < 3 * npix; ++i) {
        uint64_t m = 0;
        double d = 0;
        for (uint32_t j = 0; j < np; ++j) {
            int64_t t = r.terms[(size_t)j * 3 * npix + i];
            m += t < 0 ? (uint64_t)0 - (uint64_t)t : (uint64_t)t, d += (double)t;
        }
        maxabs = m > maxabs ? m : maxabs;
        peak = d > peak ? d : peak;
    }
    r.frac_bits = qtool_luminaire_srgbe_frac(maxabs);
    int32_t *q = malloc(sizeof(int32_t) * 4 * 3 * npix);
    uint8_t *codes = malloc(4 * npix), *hi = malloc(4 * npix), *lo = malloc(4 * npix);
    float *facc = calloc(3 * npix, sizeof(float));
    if (!q || !codes || !hi || !lo || !facc) {
        free(q), free(codes), free(hi), free(lo), free(facc), qtool_luminaire_passes_free(&r);
        return -1;
    }
    qtool_luminaire_srgbe_clear(codes, (uint32_t)npix);
    qtool_luminaire_srgbe_clear(hi, (uint32_t)npix);
    qtool_luminaire_srgbe_clear(lo, (uint32_t)npix);
    qibl_status_t st = QIBL_OK;
    for (uint32_t j = 0; st == QIBL_OK && j < np; ++j) {
        const int64_t *t = r.terms + (size_t)j * 3 * npix;
        st = qtool_luminaire_srgbe_add(codes, t, (uint32_t)npix, r.frac_bits);
        if (st == QIBL_OK)
            st = qtool_luminaire_srgbe_add2(hi, lo, t, (uint32_t)npix, r.frac_bits);
        for (size_t i = 0; i < 3 * npix; ++i)
            facc[i] += (float)((double)t[i] / 16777216.0); /* a float target: one rounding per pass */
    }
    for (size_t i = 0; st == QIBL_OK && i < npix; ++i) {
        int32_t c[3], h[3], l2[3];
        st = qibl_srgbe_decode_q16(codes + 4 * i, c);
        if (st == QIBL_OK)
            st = qibl_srgbe_decode_s32(hi + 4 * i, 24, h);
        if (st == QIBL_OK)
            st = qibl_srgbe_decode_s32(lo + 4 * i, 24, l2);
        for (int k = 0; k < 3; ++k) {
            int64_t sum = 0;
            for (uint32_t j = 0; j < np; ++j)
                sum += r.terms[(size_t)j * 3 * npix + 3 * i + (size_t)k];
            q[3 * i + (size_t)k] = qtool_luminaire_q16(sum);                   /* core */
            q[3 * npix + 3 * i + (size_t)k] = q16d((double)facc[3 * i + (size_t)k]); /* float */
            q[6 * npix + 3 * i + (size_t)k] = c[k];                            /* sRGBE */
            q[9 * npix + 3 * i + (size_t)k] = qtool_luminaire_q16((int64_t)h[k] + l2[k]); /* two sRGBE */
            r.max_rel = fmax(r.max_rel, fabs(ldexp(c[k], -16) - (double)sum / 16777216.0) / (peak / 16777216.0));
            r.max_rel2 = fmax(r.max_rel2, fabs(ldexp((double)h[k] + l2[k], -24) - (double)sum / 16777216.0) /
                                              (peak / 16777216.0));
        }
    }
    free(codes), free(hi), free(lo), free(facc);
    /* to 8 bits through platform/soft: sRGB, exposure putting the reference's peak at 1.0; the four
     * images stacked (core, float, sRGBE, two sRGBE) */
    double e = peak > 0 ? 16777216.0 / peak * 65536.0 : 65536.0;
    r.exposure = (qibl_uq16_t)(e > 4294967295.0 ? 4294967295.0 : e);
    qibl_fb_desc_t fb = {.pixels = r.shown, .width = n, .height = 4 * n, .format = QIBL_FB_RGBA8888, .srgb = 1,
                         .exposure = r.exposure};
    for (uint32_t y = 0; st == QIBL_OK && y < 4 * n; ++y)
        st = qibl_soft_fb_write_row(&fb, 0, y, n, q + (size_t)y * 3 * n);
    free(q);
    for (size_t i = 0; st == QIBL_OK && i < npix; ++i)
        for (int k = 0; k < 3; ++k) {
            int c = r.shown[4 * i + (size_t)k], f = r.shown[4 * (npix + i) + (size_t)k],
                g = r.shown[4 * (2 * npix + i) + (size_t)k], g2 = r.shown[4 * (3 * npix + i) + (size_t)k];
            r.srgbe2_vs_core = abs(g2 - c) > r.srgbe2_vs_core ? abs(g2 - c) : r.srgbe2_vs_core;
            r.srgbe2_vs_float = abs(g2 - f) > r.srgbe2_vs_float ? abs(g2 - f) : r.srgbe2_vs_float;
            r.srgbe_vs_core = abs(g - c) > r.srgbe_vs_core ? abs(g - c) : r.srgbe_vs_core;
            r.srgbe_vs_float = abs(g - f) > r.srgbe_vs_float ? abs(g - f) : r.srgbe_vs_float;
            r.float_vs_core = abs(f - c) > r.float_vs_core ? abs(f - c) : r.float_vs_core;
        }
    if (st != QIBL_OK) {
        qtool_luminaire_passes_free(&r);
        return -1;
    }
    *out = r;
    return 0;
}

int qtool_luminaire_passes_report(uint32_t size, qtool_luminaire_gpu_fn gpu, FILE *f, char *err, size_t errlen)
{
    static const uint32_t counts[] = {16, 64, 256};
    const double hgt = QTOOL_LUMINAIRE_SIZE; /* one lamp size: the near field */
    fprintf(f, "8-bit sRGB differences (max over pixels and channels); srgbe: one target, decode-add-encode per\n"
               "pass (the paper's); srgbe2: two targets, the second holding the first's rounding (signed)%s\n",
            gpu ? ";\ngles: the same pairs on the GPU" : "");
    fprintf(f, "%-7s %-10s %-15s %-14s %-16s %-15s %-14s %-10s %-10s%s\n", "passes", "frac_bits", "srgbe_vs_float",
            "srgbe_vs_core", "srgbe2_vs_float", "srgbe2_vs_core", "float_vs_core", "rel", "rel2",
            gpu ? " gles_vs_core gles_vs_srgbe2" : "");
    snprintf(err, errlen, "out of memory");
    for (int k = 0; k < 3; ++k) {
        qtool_luminaire l;
        qtool_luminaire_passes r;
        uint32_t g = 1;
        while (g * g < counts[k])
            ++g;
        if (qtool_luminaire_synthetic(g, &l) != 0)
            return -1;
        int rc = qtool_luminaire_passes_run(&l, size, hgt, &r);
        qtool_luminaire_free(&l);
        if (rc != 0)
            return -1;
        if (gpu && gpu(&r, err, errlen) != 0) {
            qtool_luminaire_passes_free(&r);
            return -1;
        }
        fprintf(f, "%-7u %-10d %-15d %-14d %-16d %-15d %-14d %-10.3g %-10.3g", r.passes, r.frac_bits,
                r.srgbe_vs_float, r.srgbe_vs_core, r.srgbe2_vs_float, r.srgbe2_vs_core, r.float_vs_core, r.max_rel,
                r.max_rel2);
        if (gpu)
            fprintf(f, " %-12d %d", r.gles_vs_core, r.gles_vs_srgbe2);
        fprintf(f, "\n");
        fprintf(f, "RESULT luminaire.passes%u_srgbe_vs_float_max8 %d\n", counts[k], r.srgbe_vs_float);
        fprintf(f, "RESULT luminaire.passes%u_srgbe_vs_core_max8 %d\n", counts[k], r.srgbe_vs_core);
        fprintf(f, "RESULT luminaire.passes%u_srgbe2_vs_float_max8 %d\n", counts[k], r.srgbe2_vs_float);
        fprintf(f, "RESULT luminaire.passes%u_srgbe2_vs_core_max8 %d\n", counts[k], r.srgbe2_vs_core);
        fprintf(f, "RESULT luminaire.passes%u_float_vs_core_max8 %d\n", counts[k], r.float_vs_core);
        if (gpu) {
            fprintf(f, "RESULT luminaire.passes%u_gles_vs_core_max8 %d\n", counts[k], r.gles_vs_core);
            fprintf(f, "RESULT luminaire.passes%u_gles_vs_srgbe2_max8 %d\n", counts[k], r.gles_vs_srgbe2);
        }
        qtool_luminaire_passes_free(&r);
    }
    err[0] = 0;
    return 0;
}
