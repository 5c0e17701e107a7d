/*
 * luminaire/study.c - `qibl luminaire study`: the built-in luminaire captured, then rendered as its
 * near field (textured spotlights) and as its far field (one gonio lamp) on a ground plane at
 * several heights, both against the luminaire ray-traced (the truth), and the near field timed on a
 * 1024 x 256 panorama of the built-in courtyard.
 *
 * Invariants: the receiver images share one shading for both renderings (a unit lamp at the
 * centre, 1/d^2, Lambert; the quantity an asset's point maps give), so the PSNR difference is the
 * light model's alone; the truth integrates the emitter with its own cosines and visibility.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "luminaire/luminaire.h"
#include "render/rt.h"

#define PI_ 3.14159265358979323846

typedef struct truth_ctx {
    const qtool_luminaire_model *m;
    uint32_t size, ns;
    double hgt, half; /* the lamp's height above the ground; the image's half side */
    double *rgb;
} truth_ctx;

static void ground_point(const truth_ctx *c, uint32_t x, uint32_t y, double p[3])
{
    p[0] = -c->half + (x + 0.5) * 2 * c->half / c->size;
    p[1] = -c->half + (y + 0.5) * 2 * c->half / c->size;
    p[2] = 0;
}

static void truth_row(void *vctx, uint32_t y)
{
    const truth_ctx *c = vctx;
    static const double up[3] = {0, 0, 1};
    for (uint32_t x = 0; x < c->size; ++x) {
        double p[3], e[3];
        ground_point(c, x, y, p);
        p[2] -= c->hgt; /* the source's frame: S at the lamp's height */
        qtool_luminaire_model_irradiance(c->m, p, up, c->ns, e);
        for (int k = 0; k < 3; ++k)
            c->rgb[3 * ((size_t)y * c->size + x) + (size_t)k] = e[k] / PI_; /* albedo 1, Lambert */
    }
}

static double psnr(const double *a, const double *t, size_t n)
{
    double peak = 0, se = 0;
    for (size_t i = 0; i < n; ++i)
        peak = t[i] > peak ? t[i] : peak;
    for (size_t i = 0; i < n; ++i)
        se += (a[i] - t[i]) * (a[i] - t[i]);
    se /= (double)n;
    return se > 0 ? 10 * log10(peak * peak / se) : 200;
}

static int32_t q16(double v)
{
    v = v * 65536.0;
    return v >= 2147483647.0 ? INT32_MAX : v <= -2147483647.0 ? -INT32_MAX : (int32_t)lround(v);
}

void qtool_luminaire_ground_pixel(const qtool_luminaire_spots *s, const double p[3], uint32_t x, uint32_t n,
                                  int32_t *pts, int32_t *base)
{
    for (int k = 0; k < 3; ++k)
        pts[3 * x + (uint32_t)k] = q16(p[k]);
    for (uint32_t a = 0; a < s->nanchor; ++a) {
        double w[3] = {s->anchor[a][0] / 65536.0 - p[0], s->anchor[a][1] / 65536.0 - p[1],
                       s->anchor[a][2] / 65536.0 - p[2]};
        double r2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2], shade = w[2] / sqrt(r2) / PI_ / r2;
        for (int k = 0; k < 3; ++k)
            base[3 * ((size_t)a * n + x) + (size_t)k] = q16(shade);
    }
}

/* near and far renderings of the ground image with the lamp at height hgt (Q16.16 integer path) */
static int render_ground(const qtool_luminaire *l, const truth_ctx *c, int far, double tol, double *out)
{
    int32_t pos[3] = {0, 0, q16(c->hgt)};
    qtool_luminaire_spots s;
    char err[128];
    const qtool_luminaire_spots_opts so = {.n = 64, .far = far, .tol = tol};
    if (qtool_luminaire_spots_build(l, pos, &so, &s, err, sizeof err) != 0)
        return -1;
    const uint32_t n = c->size, na = s.nanchor;
    int32_t *base = malloc(sizeof(int32_t) * 3 * n * na), *pts = malloc(sizeof(int32_t) * 3 * n);
    int64_t *acc = malloc(sizeof(int64_t) * 3 * n), *ws = malloc(qtool_luminaire_span_ws_size(n));
    if (!base || !pts || !acc || !ws) {
        free(base), free(pts), free(acc), free(ws), qtool_luminaire_spots_free(&s);
        return -1;
    }
    for (uint32_t y = 0; y < n; ++y) {
        for (uint32_t x = 0; x < n; ++x) {
            double p[3];
            ground_point(c, x, y, p);
            qtool_luminaire_ground_pixel(&s, p, x, n, pts, base);
        }
        memset(acc, 0, sizeof(int64_t) * 3 * n);
        qtool_luminaire_spots_span(&s, base, pts, n, acc, ws);
        for (size_t i = 0; i < (size_t)3 * n; ++i)
            out[(size_t)y * 3 * n + i] = qtool_luminaire_q16(acc[i]) / 65536.0; /* the frame's Q16.16 */
    }
    free(base), free(pts), free(acc), free(ws), qtool_luminaire_spots_free(&s);
    return 0;
}

/* ---- the courtyard: the lamp in the built-in scene (tools/render), its shadows and materials ---- */

typedef struct yard_ctx {
    const qtool_luminaire_model *m;
    const qtool_rt_scene *sc;
    uint32_t w, h, ns;
    double lp[3];
    double *rgb;
} yard_ctx;

/* the truth: every pixel's radiance from the luminaire, the emitter sampled ns x ns, each sample
 * traced through the shade (source frame) and through the scene (rt.h's response: its shadows,
 * Lambert and gloss), as qtool_rt_render shades a point lamp */
static void yard_row(void *vctx, uint32_t y)
{
    const yard_ctx *c = vctx;
    for (uint32_t x = 0; x < c->w; ++x) {
        double d[3], *o = c->rgb + 3 * ((size_t)y * c->w + x);
        qtool_rt_hit h;
        o[0] = o[1] = o[2] = 0;
        qtool_rt_pixel_dir(c->w, c->h, QTOOL_PANO_CYLINDRICAL, x, y, d);
        qtool_rt_primary(c->sc, d, &h);
        if (!h.hit || h.p[2] >= c->lp[2])
            continue;
        double ps[3] = {h.p[0] - c->lp[0], h.p[1] - c->lp[1], h.p[2] - c->lp[2]};
        qtool_luminaire_yard_sample(c->m, ps, c->ns, c->sc, &h, o);
    }
}

static int yard_psnr(const qtool_luminaire *l, const qtool_luminaire_model *m, double hl, int threads, double tol,
                     double *pn, double *pf, double *lit)
{
    const uint32_t W = 256, H = 64;
    qtool_rt_scene sc;
    if (qtool_rt_scene_builtin(&sc) != 0)
        return -1;
    const double lp[3] = {0, 2.5, -1.6 + hl * QTOOL_LUMINAIRE_SIZE};
    const size_t np = (size_t)W * H;
    double *truth = malloc(sizeof(double) * 3 * np), *rgb = malloc(sizeof(double) * 3 * np),
           *img = malloc(sizeof(double) * 3 * np), *mask_near = malloc(sizeof(double) * 3 * np);
    int32_t *pm = malloc(sizeof(int32_t) * 3 * np), *base = malloc(sizeof(int32_t) * 3 * np * 4),
            *rowb = malloc(sizeof(int32_t) * 3 * W * 4);
    int64_t *acc = malloc(sizeof(int64_t) * 3 * W), *ws = malloc(qtool_luminaire_span_ws_size(W));
    int rc = -1;
    yard_ctx yc = {.m = m, .sc = &sc, .w = W, .h = H, .ns = 16, .lp = {lp[0], lp[1], lp[2]}, .rgb = truth};
    if (!truth || !rgb || !img || !mask_near || !pm || !base || !rowb || !acc || !ws ||
        qtool_rt_parallel(threads, H, yard_row, &yc, NULL) != 0)
        goto out;
    int32_t pos[3] = {q16(lp[0]), q16(lp[1]), q16(lp[2])};
    for (int far = 0; far < 2; ++far) {
        qtool_luminaire_spots s;
        char err[128];
        const qtool_luminaire_spots_opts so = {.n = 64, .far = far, .tol = tol};
        if (qtool_luminaire_spots_build(l, pos, &so, &s, err, sizeof err) != 0)
            goto out;
        for (uint32_t a = 0; a < s.nanchor; ++a) {
            qtool_rt_light li = {.point = 1, .pos = {s.anchor[a][0] / 65536.0, s.anchor[a][1] / 65536.0,
                                                     s.anchor[a][2] / 65536.0}, .rgb = {1, 1, 1}, .falloff = 2};
            if (qtool_rt_render(&sc, W, H, QTOOL_PANO_CYLINDRICAL, &li, threads, rgb, NULL, pm) != 0) {
                qtool_luminaire_spots_free(&s);
                goto out;
            }
            for (size_t i = 0; i < 3 * np; ++i)
                base[(size_t)a * 3 * np + i] = q16(rgb[i]);
        }
        for (uint32_t y = 0; y < H; ++y) {
            for (uint32_t a = 0; a < s.nanchor; ++a)
                memcpy(rowb + (size_t)a * 3 * W, base + (size_t)a * 3 * np + (size_t)y * 3 * W, sizeof(int32_t) * 3 * W);
            memset(acc, 0, sizeof(int64_t) * 3 * W);
            qtool_luminaire_spots_span(&s, rowb, pm + (size_t)y * 3 * W, W, acc, ws);
            for (size_t i = 0; i < (size_t)3 * W; ++i)
                img[(size_t)y * 3 * W + i] = qtool_luminaire_q16(acc[i]) / 65536.0;
        }
        qtool_luminaire_spots_free(&s);
        memcpy(far ? rgb : mask_near, img, sizeof(double) * 3 * np); /* rgb: free now */
    }
    /* PSNR over the lit region only (truth, near or far above 1/1000 of the truth's peak): the
     * panorama is mostly dark, and its zeros would inflate the figure */
    double peak = 0;
    for (size_t i = 0; i < 3 * np; ++i)
        peak = truth[i] > peak ? truth[i] : peak;
    double sn = 0, sf = 0;
    size_t cnt = 0;
    for (size_t i = 0; i < 3 * np; ++i)
        if (truth[i] > 1e-3 * peak || mask_near[i] > 1e-3 * peak || rgb[i] > 1e-3 * peak) {
            sn += (mask_near[i] - truth[i]) * (mask_near[i] - truth[i]), sf += (rgb[i] - truth[i]) * (rgb[i] - truth[i]);
            ++cnt;
        }
    *pn = cnt && sn > 0 ? 10 * log10(peak * peak * (double)cnt / sn) : 200;
    *pf = cnt && sf > 0 ? 10 * log10(peak * peak * (double)cnt / sf) : 200;
    *lit = (double)cnt / (3.0 * (double)np);
    rc = 0;
out:
    free(truth), free(rgb), free(img), free(mask_near), free(pm), free(base), free(rowb), free(acc), free(ws);
    qtool_rt_scene_free(&sc);
    return rc;
}

static double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

/* this thread's CPU time: on a shared machine the wall clock counts other processes' turns */
static double cpu_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* The near field on the courtyard panorama: the centre lamp's shading from the ray tracer (as an
 * asset's point maps would give it), then the spotlight passes, timed alone on one core. */
static int time_courtyard(const qtool_luminaire *l, FILE *f, int threads, double tol, double *fps, uint32_t *spots,
                          double *lit, double *fps_all, double *fps_full)
{
    const uint32_t W = 1024, H = 256;
    qtool_rt_scene sc;
    if (qtool_rt_scene_builtin(&sc) != 0)
        return -1;
    /* the lamp 2 lamp sizes above the ground (z = -1.6), 2.5 units along +y from the viewpoint */
    const double lp[3] = {0, 2.5, -1.6 + 2 * QTOOL_LUMINAIRE_SIZE};
    double *rgb = malloc(sizeof(double) * 3 * W * H);
    int32_t *pm = malloc(sizeof(int32_t) * 3 * W * H), *base = malloc(sizeof(int32_t) * 3 * W * H * 4),
            *rowb = malloc(sizeof(int32_t) * 3 * W * 4);
    int64_t *acc = malloc(sizeof(int64_t) * 3 * W), *ws = malloc(qtool_luminaire_span_ws_size(W));
    int rc = -1;
    qtool_luminaire_spots s = {0};
    char err[128];
    int32_t pos[3] = {q16(lp[0]), q16(lp[1]), q16(lp[2])};
    const qtool_luminaire_spots_opts so = {.n = 64, .tol = tol};
    if (!rgb || !pm || !base || !rowb || !acc || !ws || qtool_luminaire_spots_build(l, pos, &so, &s, err, sizeof err) != 0)
        goto out;
    /* each anchor's unit lamp (1/d^2) by the ray tracer: the shading an asset's point maps hold */
    for (uint32_t a = 0; a < s.nanchor; ++a) {
        qtool_rt_light li = {.point = 1, .pos = {s.anchor[a][0] / 65536.0, s.anchor[a][1] / 65536.0,
                                                 s.anchor[a][2] / 65536.0}, .rgb = {1, 1, 1}, .falloff = 2};
        if (qtool_rt_render(&sc, W, H, QTOOL_PANO_CYLINDRICAL, &li, threads, rgb, NULL, pm) != 0)
            goto out;
        for (size_t i = 0; i < (size_t)3 * W * H; ++i)
            base[(size_t)a * 3 * W * H + i] = q16(rgb[i]);
    }
    size_t nlit = 0;
    double t[7], tw[7];
    for (int r = 0; r < 7; ++r) {
        double t0 = cpu_ms(), w0 = now_ms();
        nlit = 0;
        for (uint32_t y = 0; y < H; ++y) {
            for (uint32_t a = 0; a < s.nanchor; ++a) /* the anchors' rows side by side, as an asset gives them */
                memcpy(rowb + (size_t)a * 3 * W, base + (size_t)a * 3 * W * H + (size_t)y * 3 * W,
                       sizeof(int32_t) * 3 * W);
            memset(acc, 0, sizeof(int64_t) * 3 * W);
            qtool_luminaire_spots_span(&s, rowb, pm + (size_t)y * 3 * W, W, acc, ws);
            for (uint32_t x = 0; x < W; ++x)
                nlit += qtool_luminaire_q16(acc[3 * x]) > 0 || qtool_luminaire_q16(acc[3 * x + 1]) > 0;
        }
        t[r] = cpu_ms() - t0, tw[r] = now_ms() - w0;
    }
    qsort(t, 7, sizeof t[0], cmp_d);
    qsort(tw, 7, sizeof tw[0], cmp_d);
    *fps = 1000.0 / t[3];
    *spots = s.count;
    *lit = (double)nlit / ((double)W * H);
    fprintf(f, "courtyard 1024x256: %u spotlights (of %u supports), %.1f ms CPU per frame on one thread (median "
               "of 7; wall %.1f ms), %.1f fps, %.1f %% of pixels lit\n", s.count, l->nx * l->ny, t[3], tw[3], *fps,
            100 * *lit);
    /* the worst case: every pixel under the lamp (a 1024 x 256 ground patch one lamp size below it,
     * the lit region's width across), so every pass visits the whole frame's reachable part */
    qtool_luminaire_spots_free(&s);
    const double hg = QTOOL_LUMINAIRE_SIZE, half = 1.8 * hg + QTOOL_LUMINAIRE_SIZE / 2;
    int32_t gpos[3] = {0, 0, q16(hg)};
    if (qtool_luminaire_spots_build(l, gpos, &so, &s, err, sizeof err) != 0)
        goto out;
    for (uint32_t y = 0; y < H; ++y)
        for (uint32_t x = 0; x < W; ++x) {
            double p[3] = {-half + (x + 0.5) * 2 * half / W, -half / 4 + (y + 0.5) * half / 2 / H, 0};
            size_t o = 3 * ((size_t)y * W + x);
            for (int k = 0; k < 3; ++k)
                pm[o + (size_t)k] = q16(p[k]);
            for (uint32_t a = 0; a < s.nanchor; ++a) {
                double w[3] = {s.anchor[a][0] / 65536.0 - p[0], s.anchor[a][1] / 65536.0 - p[1], hg};
                double r2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
                for (int k = 0; k < 3; ++k)
                    base[(size_t)a * 3 * W * H + o + (size_t)k] = q16(hg / sqrt(r2) / PI_ / r2);
            }
        }
    /* with a hierarchy, the full sum (tol 0: the same anchors) timed too, the two interleaved so
     * a load on the shared machine falls on both alike; minimum and median of 7 each */
    qtool_luminaire_spots full = {0};
    const qtool_luminaire_spots_opts fo = {.n = 64};
    const int both = tol > 0;
    if (both && qtool_luminaire_spots_build(l, gpos, &fo, &full, err, sizeof err) != 0)
        goto out;
    double tf[7];
    for (int r = 0; r < 7; ++r)
        for (int v = 0; v <= both; ++v) {
            const qtool_luminaire_spots *sv = v ? &full : &s;
            double t0 = cpu_ms();
            for (uint32_t y = 0; y < H; ++y) {
                for (uint32_t a = 0; a < sv->nanchor; ++a)
                    memcpy(rowb + (size_t)a * 3 * W, base + (size_t)a * 3 * W * H + (size_t)y * 3 * W,
                           sizeof(int32_t) * 3 * W);
                memset(acc, 0, sizeof(int64_t) * 3 * W);
                qtool_luminaire_spots_span(sv, rowb, pm + (size_t)y * 3 * W, W, acc, ws);
            }
            (v ? tf : t)[r] = cpu_ms() - t0;
        }
    qtool_luminaire_spots_free(&full);
    qsort(t, 7, sizeof t[0], cmp_d);
    *fps_all = 1000.0 / t[3];
    fprintf(f, "ground patch 1024x256 one lamp size below (every pixel lit): %.1f ms CPU per frame, %.1f fps\n", t[3],
            *fps_all);
    if (both) {
        qsort(tf, 7, sizeof tf[0], cmp_d);
        *fps_full = 1000.0 / tf[3];
        fprintf(f, "  interleaved, ms CPU min / median of 7: hierarchy (tol %g) %.1f / %.1f, full sum %.1f / %.1f\n", tol,
                t[0], t[3], tf[0], tf[3]);
    }
    rc = 0;
out:
    qtool_luminaire_spots_free(&s);
    free(rgb), free(pm), free(base), free(rowb), free(acc), free(ws);
    qtool_rt_scene_free(&sc);
    return rc;
}

/* linear to 8-bit sRGB (IEC 61966-2-1), clamped */
static uint8_t srgb8(double v)
{
    v = v < 0 ? 0 : v > 1 ? 1 : v;
    v = v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1 / 2.4) - 0.055;
    return (uint8_t)lround(255 * v);
}

int qtool_luminaire_picture(const qtool_luminaire_study_opts *o, double lamps, uint8_t **rgb, uint32_t *w,
                            uint32_t *h)
{
    const int threads = o->threads > 0 ? o->threads : 1;
    const uint32_t size = o->size ? o->size : 96, gap = 4;
    qtool_luminaire_model *m = qtool_luminaire_builtin();
    if (!m)
        return -1;
    qtool_luminaire l;
    qtool_luminaire_capture_opts co = {.grid = o->grid ? o->grid : 8, .res = o->res ? o->res : 32, .threads = threads};
    if (qtool_luminaire_capture(m, &co, &l) != 0) {
        qtool_luminaire_model_free(m);
        return -1;
    }
    const size_t nv = (size_t)3 * size * size;
    double *img[3] = {malloc(sizeof(double) * nv), malloc(sizeof(double) * nv), malloc(sizeof(double) * nv)};
    const uint32_t W = 3 * size + 2 * gap;
    uint8_t *out = calloc((size_t)W * size * 3, 1);
    int rc = img[0] && img[1] && img[2] && out ? 0 : -1;
    const double hgt = lamps * QTOOL_LUMINAIRE_SIZE;
    truth_ctx c = {.m = m, .size = size, .ns = o->truth_ns ? o->truth_ns : 24, .hgt = hgt,
                   .half = 1.8 * hgt + QTOOL_LUMINAIRE_SIZE / 2, .rgb = img[1]};
    /* near field | truth | far field, one exposure: the truth's peak at 1.0 */
    if (rc == 0 && (qtool_rt_parallel(threads, size, truth_row, &c, NULL) != 0 || render_ground(&l, &c, 0, o->tol, img[0]) != 0 ||
                    render_ground(&l, &c, 1, 0, img[2]) != 0))
        rc = -1;
    double peak = 0;
    for (size_t i = 0; rc == 0 && i < nv; ++i)
        peak = img[1][i] > peak ? img[1][i] : peak;
    for (int k = 0; rc == 0 && k < 3; ++k)
        for (uint32_t y = 0; y < size; ++y)
            for (uint32_t x = 0; x < size; ++x)
                for (int ch = 0; ch < 3; ++ch)
                    out[3 * ((size_t)y * W + (uint32_t)k * (size + gap) + x) + (size_t)ch] =
                        srgb8(peak > 0 ? img[k][3 * ((size_t)y * size + x) + (size_t)ch] / peak : 0);
    free(img[0]), free(img[1]), free(img[2]);
    qtool_luminaire_free(&l);
    qtool_luminaire_model_free(m);
    if (rc != 0) {
        free(out);
        return -1;
    }
    *rgb = out, *w = W, *h = size;
    return 0;
}

int qtool_luminaire_study(const qtool_luminaire_study_opts *o, FILE *f)
{
    const int threads = o->threads > 0 ? o->threads : 1;
    qtool_luminaire_model *m = qtool_luminaire_builtin();
    if (!m)
        return -1;
    qtool_luminaire l;
    qtool_luminaire_capture_opts co = {.grid = o->grid ? o->grid : 8, .res = o->res ? o->res : 32, .threads = threads};
    double t0 = now_ms();
    if (qtool_luminaire_capture(m, &co, &l) != 0) {
        qtool_luminaire_model_free(m);
        return -1;
    }
    fprintf(f, "capture: %ux%u supports, %u^2 texels each, %.0f ms\n", l.nx, l.ny, l.res, now_ms() - t0);
    static const double hs_full[] = {0.5, 1, 2, 4, 8}, hs_quick[] = {0.5, 1, 4};
    const double *hs = o->quick ? hs_quick : hs_full;
    const int nh = o->quick ? 3 : 5;
    const uint32_t size = o->size ? o->size : 96;
    double *truth = malloc(sizeof(double) * 3 * size * size), *nearr = malloc(sizeof(double) * 3 * size * size),
           *farr = malloc(sizeof(double) * 3 * size * size);
    int rc = truth && nearr && farr ? 0 : -1;
    double worst_near = 1e9, worst_gain = 1e9;
    fprintf(f, "%-12s %-8s %-10s %-10s %-8s\n", "height/lamp", "height", "near_dB", "far_dB", "gain_dB");
    for (int k = 0; rc == 0 && k < nh; ++k) {
        double hgt = hs[k] * QTOOL_LUMINAIRE_SIZE;
        truth_ctx c = {.m = m, .size = size, .ns = o->truth_ns ? o->truth_ns : 24, .hgt = hgt,
                       .half = 1.8 * hgt + QTOOL_LUMINAIRE_SIZE / 2, .rgb = truth};
        if (qtool_rt_parallel(threads, size, truth_row, &c, NULL) != 0 || render_ground(&l, &c, 0, o->tol, nearr) != 0 ||
            render_ground(&l, &c, 1, 0, farr) != 0) {
            rc = -1;
            break;
        }
        size_t nv = (size_t)3 * size * size;
        double pn = psnr(nearr, truth, nv), pf = psnr(farr, truth, nv);
        fprintf(f, "%-12g %-8.3g %-10.2f %-10.2f %-8.2f\n", hs[k], hgt, pn, pf, pn - pf);
        if (o->tol > 0) {
            /* the hierarchy's own error: against the full sum (tol 0), peak the full sum's */
            if (render_ground(&l, &c, 0, 0, farr) != 0) {
                rc = -1;
                break;
            }
            double ph = psnr(nearr, farr, nv);
            fprintf(f, "  hierarchy (tol %g) against the full sum: %.2f dB\nRESULT luminaire.hier_vs_full_psnr_h%g %.2f\n",
                    o->tol, ph, hs[k], ph);
        }
        fprintf(f, "RESULT luminaire.near_psnr_h%g %.2f\nRESULT luminaire.far_psnr_h%g %.2f\n", hs[k], pn, hs[k], pf);
        if (hs[k] <= 1) {
            worst_near = pn < worst_near ? pn : worst_near;
            worst_gain = pn - pf < worst_gain ? pn - pf : worst_gain;
        }
    }
    /* the same luminaire hanging in the courtyard (2.5 units from the viewpoint, 256 x 64 panorama):
     * the scene's own shadows and materials, the truth traced through shade and scene */
    static const double yh[] = {0.5, 1, 2};
    for (int k = 0; rc == 0 && k < (o->quick ? 2 : 3); ++k) {
        double pn = 0, pf = 0, yl = 0;
        if (yard_psnr(&l, m, yh[k], threads, o->tol, &pn, &pf, &yl) != 0) {
            rc = -1;
            break;
        }
        fprintf(f, "courtyard, lamp %g lamp sizes above the ground: near %.2f dB, far %.2f dB over the lit %.1f %% "
                   "of the panorama\n", yh[k], pn, pf, 100 * yl);
        fprintf(f, "RESULT luminaire.courtyard_near_psnr_h%g %.2f\nRESULT luminaire.courtyard_far_psnr_h%g %.2f\n",
                yh[k], pn, yh[k], pf);
    }
    double fps = 0, lit = 0, fps_all = 0, fps_full = 0;
    uint32_t spots = 0;
    if (rc == 0)
        rc = time_courtyard(&l, f, threads, o->tol, &fps, &spots, &lit, &fps_all, &fps_full);
    if (rc == 0) {
        fprintf(f, "RESULT luminaire.near_psnr_within_1_lamp_min %.2f\n", worst_near);
        fprintf(f, "RESULT luminaire.near_minus_far_db_within_1_lamp_min %.2f\n", worst_gain);
        fprintf(f, "RESULT luminaire.spotlights %u\nRESULT luminaire.fps_1024x256 %.1f\n", spots, fps);
        fprintf(f, "RESULT luminaire.fps_1024x256_all_lit %.1f\n", fps_all);
        if (o->tol > 0)
            fprintf(f, "RESULT luminaire.fps_1024x256_all_lit_full_sum %.1f\n", fps_full);
    }
    free(truth), free(nearr), free(farr);
    qtool_luminaire_free(&l);
    qtool_luminaire_model_free(m);
    return rc;
}
