/*
 * io/probe_layout.c - light-probe layouts: the direction maps of lat-long, angular map, mirror
 * ball and the two cube crosses, detection, and bilinear resampling between them (see
 * probe_layout.h for the conventions, the figure of the crosses and the size rule).
 *
 * Every map goes through the viewer frame (f, r, u) of probe_layout.h: world w = (-f, -r, u). Every
 * layout's picture has image right r and image up u (the discs were mirrored, image right -r, until
 * issue 24: a reflection of the frame Ramamoorthi & Hanrahan's table is in).
 */
#include "io/probe_layout.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "qtool.h"

#define MAX_DIM 65536
#define MAX_PIXELS ((size_t)1 << 28)
/* an unused area is black when its mean luminance is at most this share of the used area's */
#define BLACK_SHARE 1e-3
/* a disc's outside may hold this share of lit pixels (brighter than BLACK_SHARE of the disc's mean):
 * Debevec's angular probes carry a copyright caption in a corner, a few per cent of the corners */
#define DISC_LIT_SHARE 0.05

#define NAME_(id, name, description) name,
static const char *const names[QTOOL_PROBE_LAYOUT_COUNT] = {QTOOL_PROBE_LAYOUT_LIST(NAME_)};
#undef NAME_

const char *qtool_probe_layout_name(qtool_probe_layout_t layout)
{
    return (unsigned)layout < QTOOL_PROBE_LAYOUT_COUNT ? names[layout] : NULL;
}

const char *qtool_probe_layout_describe(qtool_probe_layout_t layout)
{
#define DESCRIPTION_(id, name, description) description,
    static const char *const d[QTOOL_PROBE_LAYOUT_COUNT] = {QTOOL_PROBE_LAYOUT_LIST(DESCRIPTION_)};
#undef DESCRIPTION_
    return (unsigned)layout < QTOOL_PROBE_LAYOUT_COUNT ? d[layout] : "unknown layout";
}

int qtool_probe_layout_parse(const char *s, qtool_probe_layout_t *out)
{
    if (!s || !out)
        return -1;
    for (int i = 0; i < QTOOL_PROBE_LAYOUT_COUNT; ++i)
        if (strcmp(s, names[i]) == 0) {
            *out = (qtool_probe_layout_t)i;
            return 0;
        }
    return -1;
}

/* ---- geometry ------------------------------------------------------------------------------- */

/* one cube face: its cell in the cross and its centre, right and up vectors in the viewer frame */
typedef struct face {
    int col, row;
    double c[3], rt[3], up[3];
} face;

/* viewer frame axes: F = (1,0,0), R = (0,1,0), U = (0,0,1) */
static const face vcross_faces[6] = {
    {1, 1, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}},   /* front */
    {2, 1, {0, 1, 0}, {-1, 0, 0}, {0, 0, 1}},  /* right */
    {0, 1, {0, -1, 0}, {1, 0, 0}, {0, 0, 1}},  /* left */
    {1, 0, {0, 0, 1}, {0, 1, 0}, {-1, 0, 0}},  /* up: lower edge on the front's upper edge */
    {1, 2, {0, 0, -1}, {0, 1, 0}, {1, 0, 0}},  /* down: upper edge on the front's lower edge */
    {1, 3, {-1, 0, 0}, {0, 1, 0}, {0, 0, -1}}, /* back, hanging below down: upside down */
};
static const face hcross_faces[6] = {
    {1, 1, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}},   {2, 1, {0, 1, 0}, {-1, 0, 0}, {0, 0, 1}},
    {0, 1, {0, -1, 0}, {1, 0, 0}, {0, 0, 1}},  {1, 0, {0, 0, 1}, {0, 1, 0}, {-1, 0, 0}},
    {1, 2, {0, 0, -1}, {0, 1, 0}, {1, 0, 0}},
    {3, 1, {-1, 0, 0}, {0, -1, 0}, {0, 0, 1}}, /* back, right of right: upright */
};

static const face *faces_of(qtool_probe_layout_t l)
{
    return l == QTOOL_PROBE_LAYOUT_VCROSS ? vcross_faces : hcross_faces;
}

static int is_cross(qtool_probe_layout_t l)
{
    return l == QTOOL_PROBE_LAYOUT_VCROSS || l == QTOOL_PROBE_LAYOUT_HCROSS;
}

static int is_disc(qtool_probe_layout_t l)
{
    return l == QTOOL_PROBE_LAYOUT_ANGULAR || l == QTOOL_PROBE_LAYOUT_BALL;
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* the face holding cell (col, row), or NULL */
static const face *face_at(qtool_probe_layout_t l, int col, int row)
{
    const face *f = faces_of(l);
    for (int i = 0; i < 6; ++i)
        if (f[i].col == col && f[i].row == row)
            return &f[i];
    return NULL;
}

/* the face a viewer-frame direction v goes through (largest component along its centre) */
static const face *face_of(qtool_probe_layout_t l, const double v[3])
{
    const face *f = faces_of(l), *best = &f[0];
    double bd = dot3(v, f[0].c);
    for (int i = 1; i < 6; ++i) {
        double d = dot3(v, f[i].c);
        if (d > bd)
            bd = d, best = &f[i];
    }
    return best;
}

static int face_size(qtool_probe_layout_t l, int w)
{
    return l == QTOOL_PROBE_LAYOUT_VCROSS ? w / 3 : w / 4;
}

/* is the pixel centre (i, j) of an n x n disc layout inside the disc */
static int disc_inside(int n, int i, int j)
{
    double a = 2.0 * (i + 0.5) / n - 1.0, b = 2.0 * (j + 0.5) / n - 1.0;
    return a * a + b * b <= 1.0;
}

int qtool_probe_layout_dir(qtool_probe_layout_t l, int w, int h, double x, double y, double d[3])
{
    if (w <= 0 || h <= 0 || !(x >= 0 && x <= w && y >= 0 && y <= h) || !d)
        return -1;
    double v[3];
    if (l == QTOOL_PROBE_LAYOUT_LATLONG) {
        double th = QTOOL_PI * y / h, ph = 2.0 * QTOOL_PI * x / w;
        d[0] = sin(th) * cos(ph), d[1] = sin(th) * sin(ph), d[2] = cos(th);
        return 0;
    } else if (is_disc(l)) {
        double a = 2.0 * x / w - 1.0, b = 1.0 - 2.0 * y / h, rho = sqrt(a * a + b * b);
        if (rho > 1.0)
            return -1;
        double th = l == QTOOL_PROBE_LAYOUT_ANGULAR ? QTOOL_PI * rho : 2.0 * asin(rho);
        if (rho == 0) {
            v[0] = 1, v[1] = 0, v[2] = 0;
        } else {
            double s = sin(th) / rho;
            v[0] = cos(th), v[1] = a * s, v[2] = b * s; /* image right is R, as in the lat-long */
        }
    } else if (is_cross(l)) {
        int F = face_size(l, w);
        int col = (int)(x / F), row = (int)(y / F);
        if (col * F == w) /* the image's right and bottom edges belong to the last cell */
            --col;
        if (row * F == h)
            --row;
        const face *f = face_at(l, col, row);
        if (!f)
            return -1;
        double s = 2.0 * (x - col * F) / F - 1.0, t = 1.0 - 2.0 * (y - row * F) / F;
        for (int k = 0; k < 3; ++k)
            v[k] = f->c[k] + s * f->rt[k] + t * f->up[k];
        double n = sqrt(dot3(v, v));
        for (int k = 0; k < 3; ++k)
            v[k] /= n;
    } else {
        return -1;
    }
    d[0] = -v[0], d[1] = -v[1], d[2] = v[2];
    return 0;
}

/* x into [0, hi]: atan2 at a pole or a disc's rim can land an ulp outside the image (atan2(0, -1) *
 * h / QTOOL_PI is h + 1 ulp), and callers index pixels with the result */
static double clamp_to(double x, double hi)
{
    return x < 0 ? 0 : x > hi ? hi : x;
}

/* image position of a unit world direction; for crosses also the face */
static void pos_of(qtool_probe_layout_t l, int w, int h, const double d[3], double *x, double *y, const face **fo)
{
    if (l == QTOOL_PROBE_LAYOUT_LATLONG) {
        double ph = atan2(d[1], d[0]);
        if (ph < 0)
            ph += 2.0 * QTOOL_PI;
        *x = ph * w / (2.0 * QTOOL_PI);
        if (*x >= w)
            *x -= w;
        *y = clamp_to(atan2(sqrt(d[0] * d[0] + d[1] * d[1]), d[2]) * h / QTOOL_PI, h); /* acos loses bits near the poles */
        return;
    }
    double v[3] = {-d[0], -d[1], d[2]};
    if (is_disc(l)) {
        double f = v[0], s = sqrt(v[1] * v[1] + v[2] * v[2]), a, b, rho;
        if (l == QTOOL_PROBE_LAYOUT_ANGULAR)
            rho = atan2(s, f) / QTOOL_PI;
        else /* sin(theta / 2) without trigonometry (a third of the resampling time): s / (2 cos(theta / 2))
              * on the front half, where 1 - f would cancel, sqrt((1 - f) / 2) on the back half */
            rho = f >= 0 ? s / sqrt(2.0 * (1.0 + f)) : sqrt(0.5 * (1.0 - f));
        if (s == 0) {
            a = f > 0 ? 0 : 1, b = 0;
        } else {
            a = v[1] / s * rho, b = v[2] / s * rho;
        }
        *x = clamp_to((a + 1.0) * w / 2.0, w), *y = clamp_to((1.0 - b) * h / 2.0, h);
        return;
    }
    const face *fc = face_of(l, v);
    int F = face_size(l, w);
    double c = dot3(v, fc->c), s = dot3(v, fc->rt) / c, t = dot3(v, fc->up) / c;
    s = s > 1 ? 1 : s < -1 ? -1 : s;
    t = t > 1 ? 1 : t < -1 ? -1 : t;
    *x = fc->col * F + (s + 1.0) * F / 2.0, *y = fc->row * F + (1.0 - t) * F / 2.0;
    if (fo)
        *fo = fc;
}

int qtool_probe_layout_pos(qtool_probe_layout_t l, int w, int h, const double d[3], double *x, double *y)
{
    if (!d || !x || !y || w <= 0 || h <= 0 || !(l == QTOOL_PROBE_LAYOUT_LATLONG || is_disc(l) || is_cross(l)))
        return -1;
    double n = sqrt(dot3(d, d));
    if (!(n > 0) || !isfinite(n))
        return -1;
    double u[3] = {d[0] / n, d[1] / n, d[2] / n};
    pos_of(l, w, h, u, x, y, NULL);
    return 0;
}

/* ---- sampling ------------------------------------------------------------------------------- */

/* A layout's pixels as float RGB or as the RGBE bytes they were read as: the RGBE path samples the
 * bytes where they lie (no float copy of the input, which was 3 times its size) */
typedef struct src {
    const float *f;   /* 3 floats a pixel, or NULL */
    const uint8_t *e; /* 4 RGBE bytes a pixel (when f is NULL) */
    double scale[256]; /* 2^(E - 136), 0 for E = 0 (lightprobe.h's decoding) */
} src;

static void src_float(src *s, const float *f)
{
    s->f = f, s->e = NULL;
}

static void src_rgbe(src *s, const uint8_t *e)
{
    s->f = NULL, s->e = e;
    s->scale[0] = 0;
    for (int k = 1; k < 256; ++k)
        s->scale[k] = ldexp(1.0, k - 136);
}

/* pixel i's RGB */
static void fetch(const src *s, size_t i, double out[3])
{
    if (s->f) {
        const float *p = s->f + 3 * i;
        out[0] = p[0], out[1] = p[1], out[2] = p[2];
    } else {
        const uint8_t *q = s->e + 4 * i;
        double k = s->scale[q[3]];
        out[0] = q[0] * k, out[1] = q[1] * k, out[2] = q[2] * k;
    }
}

/* bilinear lat-long sample: wraps in phi, clamps in theta */
static void sample_latlong(const src *img, int w, int h, double x, double y, double out[3])
{
    double fx = x - 0.5, fy = y - 0.5;
    double x0f = floor(fx), y0f = floor(fy), tx = fx - x0f, ty = fy - y0f;
    int x0 = (int)x0f % w, y0 = (int)y0f;
    if (x0 < 0)
        x0 += w;
    int x1 = x0 + 1 == w ? 0 : x0 + 1, y1 = y0 + 1;
    y0 = y0 < 0 ? 0 : y0 > h - 1 ? h - 1 : y0;
    y1 = y1 < 0 ? 0 : y1 > h - 1 ? h - 1 : y1;
    double p00[3], p01[3], p10[3], p11[3];
    fetch(img, (size_t)y0 * (size_t)w + (size_t)x0, p00), fetch(img, (size_t)y0 * (size_t)w + (size_t)x1, p01);
    fetch(img, (size_t)y1 * (size_t)w + (size_t)x0, p10), fetch(img, (size_t)y1 * (size_t)w + (size_t)x1, p11);
    for (int c = 0; c < 3; ++c)
        out[c] = (1 - ty) * ((1 - tx) * p00[c] + tx * p01[c]) + ty * ((1 - tx) * p10[c] + tx * p11[c]);
}

/* A lat-long with per-row prefix sums, for box filtering along rows: near the poles a pixel of
 * another layout covers many lat-long columns, and point samples there would alias (a sun near the
 * zenith is hit or missed). */
typedef struct ll_box {
    const float *img;
    int w, h;
    double *pre; /* h rows of 3 (w + 1) prefix sums */
} ll_box;

static int ll_box_init(ll_box *b, const float *img, int w, int h)
{
    b->img = img, b->w = w, b->h = h;
    b->pre = malloc(sizeof *b->pre * 3 * ((size_t)w + 1) * (size_t)h);
    if (!b->pre)
        return -1;
    for (int y = 0; y < h; ++y) {
        double *p = b->pre + 3 * ((size_t)w + 1) * (size_t)y;
        const float *r = img + 3 * (size_t)w * (size_t)y;
        p[0] = p[1] = p[2] = 0;
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c)
                p[3 * (x + 1) + c] = p[3 * x + c] + r[3 * x + c];
    }
    return 0;
}

/* integral of channel c of a row (piecewise constant, periodic) from 0 to x, any real x */
static double row_integral(const double *pre, int w, double x, int c)
{
    double k = floor(x / w), xr = x - k * w;
    int i = (int)xr;
    if (i >= w)
        i = w - 1;
    return k * pre[3 * w + c] + pre[3 * i + c] + (xr - i) * (pre[3 * (i + 1) + c] - pre[3 * i + c]);
}

/* mean over a box of span columns (>= 1) centred on x, linear between the two nearest rows; a span
 * of one column is bilinear interpolation */
static void sample_latlong_box(const ll_box *b, double x, double y, double span, double out[3])
{
    if (span < 1)
        span = 1;
    if (span > b->w)
        span = b->w;
    double fy = y - 0.5, y0f = floor(fy), ty = fy - y0f;
    int y0 = (int)y0f, y1 = y0 + 1;
    y0 = y0 < 0 ? 0 : y0 > b->h - 1 ? b->h - 1 : y0;
    y1 = y1 < 0 ? 0 : y1 > b->h - 1 ? b->h - 1 : y1;
    const double *p0 = b->pre + 3 * ((size_t)b->w + 1) * (size_t)y0, *p1 = b->pre + 3 * ((size_t)b->w + 1) * (size_t)y1;
    for (int c = 0; c < 3; ++c) {
        double v0 = (row_integral(p0, b->w, x + span / 2, c) - row_integral(p0, b->w, x - span / 2, c)) / span;
        double v1 = (row_integral(p1, b->w, x + span / 2, c) - row_integral(p1, b->w, x - span / 2, c)) / span;
        double v = (1 - ty) * v0 + ty * v1;
        out[c] = v > 0 ? v : 0; /* rounding of the prefix differences */
    }
}

/* bilinear sample of a disc layout, only from pixels whose centre is inside the disc */
static void sample_disc(const src *img, int n, double x, double y, double out[3])
{
    double a = 2.0 * x / n - 1.0, b = 1.0 - 2.0 * y / n, rho = sqrt(a * a + b * b);
    double rmax = 1.0 - 3.0 / n; /* 1.5 pixels inside the rim: the nearest tap is then inside */
    if (rmax < 0)
        rmax = 0;
    if (rho > rmax) {
        double k = rho > 0 ? rmax / rho : 0;
        a *= k, b *= k;
        x = (a + 1.0) * n / 2.0, y = (1.0 - b) * n / 2.0;
    }
    double fx = x - 0.5, fy = y - 0.5, x0f = floor(fx), y0f = floor(fy), tx = fx - x0f, ty = fy - y0f;
    int x0 = (int)x0f, y0 = (int)y0f;
    double acc[3] = {0, 0, 0}, ws = 0;
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            int xi = x0 + i, yj = y0 + j;
            double wt = (i ? tx : 1 - tx) * (j ? ty : 1 - ty);
            if (xi < 0 || yj < 0 || xi >= n || yj >= n || wt <= 0 || !disc_inside(n, xi, yj))
                continue;
            double p[3];
            fetch(img, (size_t)yj * (size_t)n + (size_t)xi, p);
            for (int c = 0; c < 3; ++c)
                acc[c] += wt * p[c];
            ws += wt;
        }
    if (ws <= 0) { /* cannot happen inside rmax; the nearest pixel as a last resort */
        int xi = (int)x, yj = (int)y;
        xi = xi < 0 ? 0 : xi >= n ? n - 1 : xi;
        yj = yj < 0 ? 0 : yj >= n ? n - 1 : yj;
        fetch(img, (size_t)yj * (size_t)n + (size_t)xi, out);
        return;
    }
    for (int c = 0; c < 3; ++c)
        out[c] = acc[c] / ws;
}

/* bilinear sample of one cube face, taps clamped to the face */
static void sample_face(const src *img, int w, int F, const face *f, double x, double y, double out[3])
{
    double fx = x - f->col * F - 0.5, fy = y - f->row * F - 0.5;
    fx = fx < 0 ? 0 : fx > F - 1 ? F - 1 : fx;
    fy = fy < 0 ? 0 : fy > F - 1 ? F - 1 : fy;
    double x0f = floor(fx), y0f = floor(fy), tx = fx - x0f, ty = fy - y0f;
    int x0 = (int)x0f, y0 = (int)y0f, x1 = x0 + 1 < F ? x0 + 1 : x0, y1 = y0 + 1 < F ? y0 + 1 : y0;
    size_t bx = (size_t)f->col * (size_t)F, by = (size_t)f->row * (size_t)F, W = (size_t)w;
    double p00[3], p01[3], p10[3], p11[3];
    fetch(img, (by + (size_t)y0) * W + bx + (size_t)x0, p00);
    fetch(img, (by + (size_t)y0) * W + bx + (size_t)x1, p01);
    fetch(img, (by + (size_t)y1) * W + bx + (size_t)x0, p10);
    fetch(img, (by + (size_t)y1) * W + bx + (size_t)x1, p11);
    for (int c = 0; c < 3; ++c)
        out[c] = (1 - ty) * ((1 - tx) * p00[c] + tx * p01[c]) + ty * ((1 - tx) * p10[c] + tx * p11[c]);
}

/* the layout's radiance along unit world direction d */
static void sample_dir(qtool_probe_layout_t l, const src *img, int w, int h, const double d[3], double out[3])
{
    double x, y;
    const face *f = NULL;
    pos_of(l, w, h, d, &x, &y, &f);
    if (l == QTOOL_PROBE_LAYOUT_LATLONG)
        sample_latlong(img, w, h, x, y, out);
    else if (is_disc(l))
        sample_disc(img, w, x, y, out);
    else
        sample_face(img, w, face_size(l, w), f, x, y, out);
}

/* ---- checks --------------------------------------------------------------------------------- */

int qtool_probe_layout_check(qtool_probe_layout_t l, int w, int h, char *err, size_t errlen)
{
    const char *n = qtool_probe_layout_name(l);
    if (!n || l == QTOOL_PROBE_LAYOUT_AUTO)
        return qtool_errf(err, errlen, "unknown probe layout %d (the layouts: %s)", (int)l, QTOOL_PROBE_LAYOUT_NAMES);
    if (w <= 0 || h <= 0)
        return qtool_errf(err, errlen, "empty probe image (%d x %d)", w, h);
    if (w > MAX_DIM || h > MAX_DIM || (size_t)w * (size_t)h > MAX_PIXELS)
        return qtool_errf(err, errlen, "probe image %d x %d is too large (at most %d per side, 2^28 pixels)", w, h,
                    MAX_DIM);
    switch (l) {
    case QTOOL_PROBE_LAYOUT_LATLONG:
        return 0;
    case QTOOL_PROBE_LAYOUT_ANGULAR:
    case QTOOL_PROBE_LAYOUT_BALL:
        if (w != h)
            return qtool_errf(err, errlen, "%s needs a square image, not %d x %d", n, w, h);
        if (w < 2)
            return qtool_errf(err, errlen, "%s needs at least 2 x 2 pixels, not %d x %d", n, w, h);
        return 0;
    case QTOOL_PROBE_LAYOUT_VCROSS:
        if (w % 3 != 0 || h % 4 != 0 || w / 3 != h / 4)
            return qtool_errf(err, errlen, "vcross needs 3F x 4F pixels (F x F faces), not %d x %d", w, h);
        return 0;
    default:
        if (w % 4 != 0 || h % 3 != 0 || w / 4 != h / 3)
            return qtool_errf(err, errlen, "hcross needs 4F x 3F pixels (F x F faces), not %d x %d", w, h);
        return 0;
    }
}

/* first sample that is NaN, infinite or negative: names its pixel */
static int check_samples(int w, int h, const float *rgb, char *err, size_t errlen)
{
    size_t n = (size_t)w * (size_t)h * 3;
    for (size_t i = 0; i < n; ++i)
        if (!(rgb[i] >= 0) || !isfinite(rgb[i])) {
            size_t p = i / 3;
            return qtool_errf(err, errlen, "probe pixel (%zu, %zu) has a %s sample (%g)", p % (size_t)w, p / (size_t)w,
                        isnan(rgb[i]) ? "NaN" : isinf(rgb[i]) ? "infinite" : "negative", (double)rgb[i]);
        }
    return 0;
}

static double luma(const src *s, size_t i)
{
    double p[3];
    fetch(s, i, p);
    return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
}

/* the share of a square image's outside-the-disc pixels (centre more than a pixel outside) that are
 * lit: luminance above BLACK_SHARE of the disc's mean (any light at all when the disc is black) */
static double disc_lit_share(int w, const src *rgb)
{
    double su = 0;
    size_t nu = 0, nx = 0, lit = 0;
    for (int pass = 0; pass < 2; ++pass) {
        double thr = pass ? (nu ? BLACK_SHARE * su / (double)nu : 0) : 0;
        for (int j = 0; j < w; ++j)
            for (int i = 0; i < w; ++i) {
                double a = 2.0 * (i + 0.5) / w - 1.0, b = 2.0 * (j + 0.5) / w - 1.0, r = sqrt(a * a + b * b);
                double y = luma(rgb, (size_t)j * (size_t)w + (size_t)i);
                if (!pass && r <= 1.0)
                    su += y, ++nu;
                else if (pass && r > 1.0 + 2.0 / w)
                    ++nx, lit += y > thr;
            }
    }
    return nx ? (double)lit / (double)nx : 0;
}

/* mean luminance of a cross's unused cells over its faces' (crosses keep the strict mean rule: 4:3
 * is a common photo shape, and a cross's cells leave no corner for a caption) */
static double unused_share(qtool_probe_layout_t l, int w, int h, const src *rgb)
{
    double su = 0, sx = 0;
    size_t nu = 0, nx = 0;
    int F = face_size(l, w);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            size_t p = (size_t)j * (size_t)w + (size_t)i;
            if (face_at(l, i / F, j / F) != NULL)
                su += luma(rgb, p), ++nu;
            else
                sx += luma(rgb, p), ++nx;
        }
    if (nx == 0 || sx == 0)
        return 0;
    if (su == 0)
        return HUGE_VAL;
    return (sx / (double)nx) / (su / (double)nu);
}

/* detection once the size is checked and the samples are valid */
static int detect_src(int w, int h, const src *rgb, qtool_probe_layout_t *out, char *err, size_t errlen)
{
    if ((size_t)w == 2 * (size_t)h) {
        *out = QTOOL_PROBE_LAYOUT_LATLONG;
        return 0;
    }
    qtool_probe_layout_t l = QTOOL_PROBE_LAYOUT_AUTO;
    const char *what = NULL;
    /* 4w = 3h forces 3 | w and 4 | h: an exact 3:4 image always has whole faces (and 4:3 likewise) */
    if (4 * (size_t)w == 3 * (size_t)h) {
        l = QTOOL_PROBE_LAYOUT_VCROSS, what = "the cells outside the vertical cross's faces";
    } else if (3 * (size_t)w == 4 * (size_t)h) {
        l = QTOOL_PROBE_LAYOUT_HCROSS, what = "the cells outside the horizontal cross's faces";
    } else if (w == h) {
        /* a disc on black, a caption or a few stray pixels allowed (a share of lit pixels, not a mean:
         * a bright caption would outweigh the black corners' mean) */
        double lit = disc_lit_share(w, rgb);
        if (lit > DISC_LIT_SHARE)
            return qtool_errf(err, errlen,
                        "%d x %d: a square image could be angular or ball, but the corners outside the disc are "
                        "not black (%.1f %% of their pixels lit, at most %.0f %% may be, for a caption), so it fits "
                        "no probe layout by itself; give --layout angular, --layout ball or --layout latlong to "
                        "read it as one (the layouts: %s)",
                        w, h, 100 * lit, 100 * DISC_LIT_SHARE, QTOOL_PROBE_LAYOUT_NAMES);
        return qtool_errf(err, errlen,
                    "%d x %d is a disc on black (%.1f %% of the outside lit): it could be angular (an angular "
                    "map) or ball (a mirror ball), which the pixels cannot tell apart; give --layout angular or "
                    "--layout ball (the layouts: %s)",
                    w, h, 100 * lit, QTOOL_PROBE_LAYOUT_NAMES);
    } else {
        return qtool_errf(err, errlen, "%d x %d fits no probe layout (%s); give --layout if it is one of them", w, h,
                    QTOOL_PROBE_LAYOUT_NAMES);
    }
    double share = unused_share(l, w, h, rgb);
    if (share > BLACK_SHARE)
        return qtool_errf(err, errlen,
                    "%d x %d: %s are not black (mean luminance %.3g of the picture's), so it fits no probe "
                    "layout (%s); give --layout to read it as one",
                    w, h, what, share, QTOOL_PROBE_LAYOUT_NAMES);
    *out = l;
    return 0;
}

int qtool_probe_layout_detect(int w, int h, const float *rgb, qtool_probe_layout_t *out, char *err, size_t errlen)
{
    if (!rgb || !out)
        return qtool_errf(err, errlen, "no probe image");
    if (w <= 0 || h <= 0)
        return qtool_errf(err, errlen, "empty probe image (%d x %d)", w, h);
    if (w > MAX_DIM || h > MAX_DIM || (size_t)w * (size_t)h > MAX_PIXELS)
        return qtool_errf(err, errlen, "probe image %d x %d is too large (at most %d per side, 2^28 pixels)", w, h,
                    MAX_DIM);
    if (check_samples(w, h, rgb, err, errlen) != 0)
        return -1;
    src sr;
    src_float(&sr, rgb);
    return detect_src(w, h, &sr, out, err, errlen);
}

/* pixels along the horizon circle (the 360-degree line through F) */
static int horizon_pixels(qtool_probe_layout_t l, int w)
{
    return is_cross(l) ? 4 * face_size(l, w) : w;
}

int qtool_probe_layout_latlong_size(qtool_probe_layout_t l, int w, int h, int *ow, int *oh, char *err, size_t errlen)
{
    if (!ow || !oh)
        return qtool_errf(err, errlen, "no output size");
    if (qtool_probe_layout_check(l, w, h, err, errlen) != 0)
        return -1;
    if (l == QTOOL_PROBE_LAYOUT_LATLONG) {
        *ow = w, *oh = h;
        return 0;
    }
    int wi = horizon_pixels(l, w);
    wi += wi & 1;
    if (wi > QTOOL_PROBE_LAYOUT_MAX_W)
        wi = QTOOL_PROBE_LAYOUT_MAX_W;
    *ow = wi, *oh = wi / 2;
    return 0;
}

/* sub-samples per axis: 2, or more when the output is much coarser than the input */
static int subsamples(int in_pixels, int out_pixels)
{
    int s = 2 * ((in_pixels + out_pixels - 1) / out_pixels);
    return s < 2 ? 2 : s > 16 ? 16 : s;
}

static int alloc_rgb(int w, int h, float **out, char *err, size_t errlen)
{
    *out = malloc(sizeof **out * 3 * (size_t)w * (size_t)h);
    return *out ? 0 : qtool_errf(err, errlen, "out of memory for a %d x %d probe", w, h);
}

/* Resamples img (a w x h image in layout l, checked) to an ow x oh lat-long one row at a time, into
 * float RGB (of) or RGBE bytes (oe): nothing but the output and one row is allocated. 0, or -1. */
static int resample(qtool_probe_layout_t l, int w, int h, const src *img, int ow, int oh, float *of, uint8_t *oe,
                    char *err, size_t errlen)
{
    int s = subsamples(horizon_pixels(l, w), ow);
    /* per sub-column and sub-row trigonometry, once */
    double *cs = malloc(sizeof *cs * 2 * (size_t)ow * (size_t)s), *st = malloc(sizeof *st * 2 * (size_t)oh * (size_t)s);
    float *row = oe ? malloc(sizeof *row * 3 * (size_t)ow) : NULL;
    if (!cs || !st || (oe && !row)) {
        free(cs), free(st), free(row);
        return qtool_errf(err, errlen, "out of memory for a %d x %d probe", ow, oh);
    }
    for (int i = 0; i < ow * s; ++i) {
        double ph = 2.0 * QTOOL_PI * (i + 0.5) / ((double)ow * s);
        cs[2 * i] = cos(ph), cs[2 * i + 1] = sin(ph);
    }
    for (int j = 0; j < oh * s; ++j) {
        double th = QTOOL_PI * (j + 0.5) / ((double)oh * s);
        st[2 * j] = sin(th), st[2 * j + 1] = cos(th);
    }
    double inv = 1.0 / ((double)s * s);
    for (int y = 0; y < oh; ++y) {
        float *r = oe ? row : of + 3 * (size_t)y * (size_t)ow;
        for (int x = 0; x < ow; ++x) {
            double acc[3] = {0, 0, 0}, v[3];
            for (int q = 0; q < s; ++q) {
                const double *t = st + 2 * ((size_t)y * (size_t)s + (size_t)q);
                for (int p = 0; p < s; ++p) {
                    const double *c = cs + 2 * ((size_t)x * (size_t)s + (size_t)p);
                    double d[3] = {t[0] * c[0], t[0] * c[1], t[1]};
                    sample_dir(l, img, w, h, d, v);
                    acc[0] += v[0], acc[1] += v[1], acc[2] += v[2];
                }
            }
            for (int c = 0; c < 3; ++c)
                r[3 * x + c] = (float)(acc[c] * inv);
        }
        if (oe)
            qtool_probe_layout_rgbe_encode(row, (size_t)ow, oe + 4 * (size_t)y * (size_t)ow);
    }
    free(cs), free(st), free(row);
    return 0;
}

int qtool_probe_layout_to_latlong(qtool_probe_layout_t l, int w, int h, const float *rgb, int ow, int oh, float **out,
                                 char *err, size_t errlen)
{
    if (!rgb || !out)
        return qtool_errf(err, errlen, "no probe image");
    if (qtool_probe_layout_check(l, w, h, err, errlen) != 0)
        return -1;
    if (ow <= 0 || oh <= 0 || ow > 32768 || oh > 32768 || (size_t)ow * (size_t)oh > MAX_PIXELS)
        return qtool_errf(err, errlen, "lat-long output size %d x %d out of range", ow, oh);
    if (check_samples(w, h, rgb, err, errlen) != 0)
        return -1;
    float *o;
    if (alloc_rgb(ow, oh, &o, err, errlen) != 0)
        return -1;
    if (l == QTOOL_PROBE_LAYOUT_LATLONG && ow == w && oh == h) {
        memcpy(o, rgb, sizeof *o * 3 * (size_t)w * (size_t)h);
        *out = o;
        return 0;
    }
    src sr;
    src_float(&sr, rgb);
    if (resample(l, w, h, &sr, ow, oh, o, NULL, err, errlen) != 0) {
        free(o);
        return -1;
    }
    *out = o;
    return 0;
}

int qtool_probe_layout_from_latlong(qtool_probe_layout_t l, int lw, int lh, const float *latlong, int w, int h,
                                   float **out, char *err, size_t errlen)
{
    if (!latlong || !out)
        return qtool_errf(err, errlen, "no probe image");
    if (qtool_probe_layout_check(QTOOL_PROBE_LAYOUT_LATLONG, lw, lh, err, errlen) != 0 ||
        qtool_probe_layout_check(l, w, h, err, errlen) != 0)
        return -1;
    if (check_samples(lw, lh, latlong, err, errlen) != 0)
        return -1;
    float *o;
    ll_box box;
    if (alloc_rgb(w, h, &o, err, errlen) != 0)
        return -1;
    if (ll_box_init(&box, latlong, lw, lh) != 0) {
        free(o);
        return qtool_errf(err, errlen, "out of memory for a %d x %d probe", lw, lh);
    }
    int s = subsamples(lw, horizon_pixels(l, w));
    const double col = 2.0 * QTOOL_PI / lw; /* radians per lat-long column on the equator */
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float *px = o + 3 * ((size_t)y * (size_t)w + (size_t)x);
            double acc[3] = {0, 0, 0}, v[3], d[3], c0[3], c1[3];
            int n = 0;
            if (is_disc(l) && !disc_inside(w, x, y)) {
                px[0] = px[1] = px[2] = 0;
                continue;
            }
            /* the pixel's angular size, from its neighbours (either side), for the box width */
            double size = 2.0 * QTOOL_PI / horizon_pixels(l, w);
            if (qtool_probe_layout_dir(l, w, h, x + 0.5, y + 0.5, c0) == 0) {
                double a = 0;
                for (int k = 0; k < 4; ++k) {
                    double ox = k == 0 ? 1 : k == 1 ? -1 : 0, oy = k == 2 ? 1 : k == 3 ? -1 : 0;
                    if (qtool_probe_layout_dir(l, w, h, x + 0.5 + ox, y + 0.5 + oy, c1) == 0) {
                        double cr[3] = {c0[1] * c1[2] - c0[2] * c1[1], c0[2] * c1[0] - c0[0] * c1[2],
                                        c0[0] * c1[1] - c0[1] * c1[0]};
                        double t = atan2(sqrt(dot3(cr, cr)), dot3(c0, c1));
                        a = t > a ? t : a;
                    }
                }
                if (a > 0)
                    size = a;
            }
            for (int q = 0; q < s; ++q)
                for (int p = 0; p < s; ++p) {
                    if (qtool_probe_layout_dir(l, w, h, x + (p + 0.5) / s, y + (q + 0.5) / s, d) != 0)
                        continue;
                    double px_x, px_y, st = sqrt(d[0] * d[0] + d[1] * d[1]);
                    pos_of(QTOOL_PROBE_LAYOUT_LATLONG, lw, lh, d, &px_x, &px_y, NULL);
                    double span = st > 0 ? size / s / (st * col) : lw;
                    sample_latlong_box(&box, px_x, px_y, span, v);
                    acc[0] += v[0], acc[1] += v[1], acc[2] += v[2];
                    ++n;
                }
            for (int c = 0; c < 3; ++c)
                px[c] = n ? (float)(acc[c] / n) : 0.0f;
        }
    free(box.pre);
    *out = o;
    return 0;
}

/* ---- RGBE ----------------------------------------------------------------------------------- */

void qtool_probe_layout_rgbe_encode(const float *rgb, size_t n, uint8_t *rgbe)
{
    for (size_t i = 0; i < n; ++i) {
        const float *p = rgb + 3 * i;
        uint8_t *q = rgbe + 4 * i;
        double m = p[0] > p[1] ? p[0] : p[1];
        m = m > p[2] ? m : p[2];
        if (!(m >= ldexp(1.0, -128))) {
            q[0] = q[1] = q[2] = q[3] = 0;
            continue;
        }
        int e;
        (void)frexp(m, &e);
        int E = e + 128;
        if (lrint(ldexp(m, 136 - E)) > 255)
            ++E; /* the largest channel rounded up to 256 */
        if (E > 255)
            E = 255;
        for (int c = 0; c < 3; ++c) {
            long v = lrint(ldexp((double)p[c], 136 - E));
            q[c] = (uint8_t)(v < 0 ? 0 : v > 255 ? 255 : v);
        }
        q[3] = (uint8_t)E;
    }
}

int qtool_probe_layout_rgbe_to_latlong(qtool_probe_layout_t want, int w, int h, const uint8_t *rgbe,
                                      qtool_probe_layout_t *used, int *ow, int *oh, uint8_t **out, char *err,
                                      size_t errlen)
{
    if (!rgbe || !used || !ow || !oh || !out)
        return qtool_errf(err, errlen, "no probe image");
    if ((unsigned)want >= QTOOL_PROBE_LAYOUT_COUNT)
        return qtool_errf(err, errlen, "unknown probe layout %d (the layouts: %s)", (int)want, QTOOL_PROBE_LAYOUT_NAMES);
    if (want != QTOOL_PROBE_LAYOUT_AUTO && qtool_probe_layout_check(want, w, h, err, errlen) != 0)
        return -1;
    if (w <= 0 || h <= 0)
        return qtool_errf(err, errlen, "empty probe image (%d x %d)", w, h);
    if (w > MAX_DIM || h > MAX_DIM || (size_t)w * (size_t)h > MAX_PIXELS)
        return qtool_errf(err, errlen, "probe image %d x %d is too large (at most %d per side, 2^28 pixels)", w, h,
                    MAX_DIM);
    size_t np = (size_t)w * (size_t)h;
    qtool_probe_layout_t l = want;
    /* the bytes are sampled where they lie (RGBE has no NaN or negative sample to check) */
    src *sr = malloc(sizeof *sr);
    if (!sr)
        return qtool_errf(err, errlen, "out of memory for a %d x %d probe", w, h);
    src_rgbe(sr, rgbe);
    if (l == QTOOL_PROBE_LAYOUT_AUTO && detect_src(w, h, sr, &l, err, errlen) != 0) {
        free(sr);
        return -1;
    }
    if (l == QTOOL_PROBE_LAYOUT_LATLONG) {
        free(sr);
        uint8_t *o = malloc(4 * np);
        if (!o)
            return qtool_errf(err, errlen, "out of memory for a %d x %d probe", w, h);
        memcpy(o, rgbe, 4 * np);
        *used = l, *ow = w, *oh = h, *out = o;
        return 0;
    }
    int lw = 0, lh = 0;
    if (qtool_probe_layout_latlong_size(l, w, h, &lw, &lh, err, errlen) != 0) {
        free(sr);
        return -1;
    }
    uint8_t *o = malloc(4 * (size_t)lw * (size_t)lh);
    if (!o) {
        free(sr);
        return qtool_errf(err, errlen, "out of memory for a %d x %d probe", lw, lh);
    }
    if (resample(l, w, h, sr, lw, lh, NULL, o, err, errlen) != 0) {
        free(sr), free(o);
        return -1;
    }
    free(sr);
    *used = l, *ow = lw, *oh = lh, *out = o;
    return 0;
}

uint8_t *qtool_probe_layout_rgbe_up4(const uint8_t *px, int w, int h)
{
    uint8_t *o = malloc(4 * (size_t)w * (size_t)h * 16);
    if (!o)
        return NULL;
    for (int v = 0; v < 4 * h; ++v)
        for (int u = 0; u < 4 * w; ++u)
            memcpy(o + 4 * ((size_t)v * 4 * (size_t)w + (size_t)u), px + 4 * ((size_t)(v / 4) * (size_t)w + (size_t)(u / 4)), 4);
    return o;
}
