/*
 * bake/probesun.c - a probe's compact bright sources as baked single-direction light paths, the
 * rest as SH (probesun.h): finding and splitting the sources, their paths, the sun + SH relight
 * through the core, the PSUN chunk that names the probe, the truth and the bake of `--probe`.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bake/bake.h"
#include "io/asset_write.h"
#include "bake/path.h"
#include "bake/probesun.h"
#include "io/atomic.h"
#include "io/hdr.h"
#include "qibl/asset.h"
#include "qibl/lightpath.h"
#include "qibl/lightprobe.h"
#include "qibl/probe.h"
#include "qibl/soft.h"
#include "qtool.h"

/* a compact source holds at least this share of the energy within SUN_RADIUS degrees */
#define SUN_SHARE 0.01
#define SUN_RADIUS 12.0

typedef struct {
    double x, y, en, rgb[3], d[3];
} part_px;

static int cmp_x(const void *a, const void *b)
{
    double u = ((const part_px *)a)->x, v = ((const part_px *)b)->x;
    return u < v ? -1 : u > v;
}

static int cmp_y(const void *a, const void *b)
{
    double u = ((const part_px *)a)->y, v = ((const part_px *)b)->y;
    return u < v ? -1 : u > v;
}

/* median cut of a source's pixels (tangent-plane coordinates about its centroid) into k parts
 * (k a power of two) of equal energy; appends them to out. Returns the number appended. */
static int split_source(part_px *px, size_t n, int k, double tot, qtool_probesun_src *out)
{
    if (n == 0)
        return 0;
    if (k <= 1 || n == 1) {
        double en = 0, c[3] = {0, 0, 0}, rgb[3] = {0, 0, 0};
        for (size_t i = 0; i < n; ++i) {
            en += px[i].en;
            for (int q = 0; q < 3; ++q)
                c[q] += px[i].en * px[i].d[q], rgb[q] += px[i].rgb[q];
        }
        double l = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        for (int q = 0; q < 3; ++q)
            out->dir[q] = l > 0 ? c[q] / l : px[0].d[q], out->rgb[q] = rgb[q];
        out->share = en / tot, out->radius_deg = 0;
        return 1;
    }
    double mx = 0, my = 0, sx = 0, sy = 0, en = 0;
    for (size_t i = 0; i < n; ++i)
        en += px[i].en, mx += px[i].en * px[i].x, my += px[i].en * px[i].y;
    mx /= en, my /= en;
    for (size_t i = 0; i < n; ++i)
        sx += px[i].en * (px[i].x - mx) * (px[i].x - mx), sy += px[i].en * (px[i].y - my) * (px[i].y - my);
    qsort(px, n, sizeof *px, sx >= sy ? cmp_x : cmp_y);
    size_t m = 0;
    for (double acc = 0; m < n - 1 && acc + px[m].en <= en / 2; ++m)
        acc += px[m].en;
    if (m == 0)
        m = 1;
    int a = split_source(px, m, k / 2, tot, out);
    return a + split_source(px + m, n - m, k / 2, tot, out + a);
}

int qtool_probesun_find(const qtool_env *e, float *sky, qtool_probesun_src *suns, qtool_probesun_src *parts, int *part_src,
                        int *nparts, int kparts)
{
    *nparts = 0;
    uint32_t w = e->w, h = e->h;
    size_t np = (size_t)w * h;
    int32_t *lab = malloc(np * sizeof(int32_t));
    size_t *stack = malloc(np * sizeof(size_t));
    int ns = 0;
    if (!lab || !stack) {
        free(lab), free(stack);
        return -1;
    }
    double tot = e->e_b + e->e_r;
    for (size_t i = 0; i < np; ++i)
        lab[i] = -1;
    int32_t ncomp = 0;
    qtool_probesun_src cand[64];
    int32_t cand_lab[64];
    int ncand = 0;
    for (size_t s0 = 0; s0 < np; ++s0) {
        if (!e->in_b[s0] || lab[s0] >= 0)
            continue;
        size_t sp = 0;
        stack[sp++] = s0, lab[s0] = ncomp;
        double en = 0, c[3] = {0, 0, 0}, rgb[3] = {0, 0, 0};
        size_t first = s0;
        /* first pass: energy, centroid, colour (midpoint solid angle, as the core's lights use) */
        while (sp) {
            size_t i = stack[--sp];
            uint32_t u = (uint32_t)(i % w), v = (uint32_t)(i / w);
            double th = (v + 0.5) * QTOOL_PI / h, ph = (u + 0.5) * 2 * QTOOL_PI / w, dw = 2 * QTOOL_PI * QTOOL_PI / ((double)w * h) * sin(th);
            const float *L = e->rgb + 3 * i;
            double y = (0.2126 * L[0] + 0.7152 * L[1] + 0.0722 * L[2]) * e->row_dw[v];
            en += y;
            c[0] += y * sin(th) * cos(ph), c[1] += y * sin(th) * sin(ph), c[2] += y * cos(th);
            for (int q = 0; q < 3; ++q)
                rgb[q] += L[q] * dw;
            for (int dv = -1; dv <= 1; ++dv)
                for (int du = -1; du <= 1; ++du) {
                    long vv = (long)v + dv;
                    if (vv < 0 || vv >= (long)h)
                        continue;
                    size_t j = (size_t)vv * w + (size_t)(((long)u + du + (long)w) % (long)w);
                    if (e->in_b[j] && lab[j] < 0)
                        lab[j] = ncomp, stack[sp++] = j;
                }
        }
        (void)first;
        double l = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        if (en >= SUN_SHARE * tot && l > 0 && ncand < 64) {
            qtool_probesun_src *s = &cand[ncand];
            for (int q = 0; q < 3; ++q)
                s->dir[q] = c[q] / l, s->rgb[q] = rgb[q];
            s->share = en / tot, s->radius_deg = 0;
            cand_lab[ncand++] = ncomp;
        }
        ++ncomp;
    }
    /* angular radius of each candidate */
    for (size_t i = 0; i < np; ++i)
        for (int k = 0; k < ncand; ++k)
            if (lab[i] == cand_lab[k]) {
                uint32_t u = (uint32_t)(i % w), v = (uint32_t)(i / w);
                double th = (v + 0.5) * QTOOL_PI / h, ph = (u + 0.5) * 2 * QTOOL_PI / w;
                double d = sin(th) * cos(ph) * cand[k].dir[0] + sin(th) * sin(ph) * cand[k].dir[1] + cos(th) * cand[k].dir[2];
                double a = acos(fmin(1, fmax(-1, d))) * 180 / QTOOL_PI;
                if (a > cand[k].radius_deg)
                    cand[k].radius_deg = a;
            }
    /* the largest compact ones */
    int used[64] = {0};
    while (ns < QTOOL_PROBESUN_MAX_SRC) {
        int best = -1;
        for (int k = 0; k < ncand; ++k)
            if (!used[k] && cand[k].radius_deg <= SUN_RADIUS && (best < 0 || cand[k].share > cand[best].share))
                best = k;
        if (best < 0)
            break;
        used[best] = 1;
        suns[ns++] = cand[best];
        const double *cd = cand[best].dir;
        double t1[3] = {-cd[1], cd[0], 0}, l1 = sqrt(cd[0] * cd[0] + cd[1] * cd[1]);
        if (l1 < 1e-6)
            t1[0] = 1, t1[1] = 0, l1 = 1;
        for (int q = 0; q < 3; ++q)
            t1[q] /= l1;
        double t2[3] = {cd[1] * t1[2] - cd[2] * t1[1], cd[2] * t1[0] - cd[0] * t1[2], cd[0] * t1[1] - cd[1] * t1[0]};
        size_t npx = 0;
        part_px *px;
        for (size_t i = 0; i < np; ++i)
            npx += lab[i] == cand_lab[best];
        px = malloc(npx * sizeof *px);
        npx = 0;
        for (size_t i = 0; px && i < np; ++i)
            if (lab[i] == cand_lab[best]) {
                uint32_t u = (uint32_t)(i % w), v = (uint32_t)(i / w);
                double th = (v + 0.5) * QTOOL_PI / h, ph = (u + 0.5) * 2 * QTOOL_PI / w, dw = 2 * QTOOL_PI * QTOOL_PI / ((double)w * h) * sin(th);
                const float *L = e->rgb + 3 * i;
                part_px *q = &px[npx++];
                q->d[0] = sin(th) * cos(ph), q->d[1] = sin(th) * sin(ph), q->d[2] = cos(th);
                q->x = q->d[0] * t1[0] + q->d[1] * t1[1] + q->d[2] * t1[2];
                q->y = q->d[0] * t2[0] + q->d[1] * t2[1] + q->d[2] * t2[2];
                q->en = (0.2126 * L[0] + 0.7152 * L[1] + 0.0722 * L[2]) * e->row_dw[v];
                for (int c = 0; c < 3; ++c)
                    q->rgb[c] = L[c] * dw;
                sky[3 * i] = sky[3 * i + 1] = sky[3 * i + 2] = 0;
            }
        if (px) {
            int a = split_source(px, npx, kparts, tot, parts + *nparts);
            for (int k = 0; k < a; ++k)
                part_src[*nparts + k] = ns - 1;
            *nparts += a;
        }
        free(px);
    }
    free(lab), free(stack);
    return ns;
}

/* probe (floats) -> the core's LINEAR_F32 image (bit patterns) */
void qtool_probesun_f32_image(const float *p, uint32_t w, uint32_t h, uint32_t *bits, qibl_lightprobe_image_t *img)
{
    memcpy(bits, p, sizeof(float) * 3 * (size_t)w * h);
    memset(img, 0, sizeof *img);
    img->pixels = bits, img->width = w, img->height = h, img->format = QIBL_LIGHTPROBE_LINEAR_F32;
}

int qtool_probesun_sh(const float *p, uint32_t w, uint32_t h, uint32_t k, qibl_shlight_t *l, double *ms)
{
    uint32_t *bits = malloc(sizeof(float) * 3 * (size_t)w * h);
    size_t wsn = qibl_probe_sh_workspace_size(w, h);
    void *ws = malloc(wsn);
    qibl_lightprobe_image_t img;
    int rc = -1;
    if (bits && ws) {
        qtool_probesun_f32_image(p, w, h, bits, &img);
        double t0 = qtool_bake_now();
        if (qibl_shlight_init(l, k) == QIBL_OK && qibl_shlight_add_probe(l, &img, NULL, ws, wsn) == QIBL_OK)
            rc = 0;
        if (ms)
            *ms = (qtool_bake_now() - t0) * 1e3;
    }
    free(bits), free(ws);
    return rc;
}

/* scales the probe in place so that a surface facing up receives QTOOL_PROBESUN_TARGET_E_UP; returns the factor */
double qtool_probesun_scale(float *probe, uint32_t pw, uint32_t ph)
{
    double eup = 0;
    for (uint32_t v = 0; v < ph; ++v) {
        double th = (v + 0.5) * QTOOL_PI / ph, cz = cos(th), dw = 2 * QTOOL_PI * QTOOL_PI / ((double)pw * ph) * sin(th);
        if (cz <= 0)
            continue;
        for (uint32_t u = 0; u < pw; ++u) {
            const float *L = probe + 3 * ((size_t)v * pw + u);
            eup += (0.2126 * L[0] + 0.7152 * L[1] + 0.0722 * L[2]) * cz * dw;
        }
    }
    double scale = eup > 0 ? QTOOL_PROBESUN_TARGET_E_UP / eup : 1;
    for (size_t i = 0; i < (size_t)pw * ph * 3; ++i)
        probe[i] = (float)(probe[i] * scale);
    return scale;
}


/* LPTH payload of one fixed direction: each pixel visible (one edge at 0) or not (none) */
int qtool_probesun_path(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, int threads,
                        const qtool_probesun_src *sun, uint8_t *cls, uint8_t **out, size_t *n)
{
    size_t np = (size_t)w * h;
    qtool_rt_light l = {0, {sun->dir[0], sun->dir[1], sun->dir[2]}, {0, 0, 0}, {1, 1, 1}, 1};
    if (qtool_rt_classify(s, w, h, kind, &l, threads, cls) != 0)
        return -1;
    uint8_t *counts = malloc(np);
    uint16_t *edges = malloc(np * sizeof(uint16_t));
    uint32_t kt[2] = {0, 65535}, ne = 0;
    int32_t kv[6];
    for (int c = 0; c < 3; ++c)
        kv[c] = kv[3 + c] = (int32_t)lrint(sun->dir[c] * 65536.0);
    int rc = -1;
    if (counts && edges) {
        for (size_t i = 0; i < np; ++i) {
            counts[i] = cls[i] == 1;
            if (counts[i])
                edges[ne++] = 0;
        }
        rc = qtool_bake_path_payload(w, h, 0, 2, kt, kv, counts, edges, ne, out, n);
    }
    free(counts), free(edges);
    return rc;
}

/* Sun + SH through the core, per row: the sky SH through the shadowed maps (SHMP), then per source
 * one relight of the unshadowed maps (SHMU) under the whole source from its centroid, added once
 * per part scaled by the part's share of the source's colour and times the part's visibility (its
 * single-direction path, LPTH number k): out = sky + sum_k (rgb_k / rgb_src) U_src V_k. One SHMU
 * pass per source however many parts. rgb8 (sRGB, as the other frames). 0, or -1 (err). */
int qtool_probesun_relight(const uint8_t *asset, size_t n, const qibl_shlight_t *sky, const qtool_probesun_src *src, int nsrc,
                          const qtool_probesun_src *parts, const int *part_src, int nparts, uint8_t *rgb8, double *ms, char *err,
                          size_t errlen)
{
    qibl_asset_t a;
    qibl_shmaps_t mu, msh;
    qibl_lightpath_t lp[QTOOL_PROBESUN_MAX_PATHS];
    qibl_shmap_weights_t wsky, wsrc[QTOOL_PROBESUN_MAX_SRC];
    int32_t wq[QTOOL_PROBESUN_MAX_PATHS][3];
    qibl_status_t st = qtool_asset_open(&a, asset, n);
    if (st == QIBL_OK)
        st = qibl_asset_shmaps_unshadowed(&a, &mu);
    if (st == QIBL_OK)
        st = qibl_asset_shmaps(&a, &msh);
    for (int k = 0; st == QIBL_OK && k < nparts; ++k) {
        st = qibl_lightpath_from_asset(&a, (uint32_t)k, &lp[k]);
        for (int c = 0; c < 3; ++c) /* the part's share of its source's colour, Q16 */
            wq[k][c] = src[part_src[k]].rgb[c] > 0 ? (int32_t)lrint(65536.0 * parts[k].rgb[c] / src[part_src[k]].rgb[c]) : 0;
    }
    if (st == QIBL_OK)
        st = qibl_shmap_weights(&msh, sky, &wsky);
    for (int i = 0; st == QIBL_OK && i < nsrc; ++i) {
        qibl_shlight_t sl;
        qibl_q16_t dir[3], rgb[3];
        for (int c = 0; c < 3; ++c)
            dir[c] = (qibl_q16_t)lrint(src[i].dir[c] * 65536.0), rgb[c] = (qibl_q16_t)lrint(src[i].rgb[c] * 65536.0);
        st = qibl_shlight_init(&sl, mu.k);
        if (st == QIBL_OK)
            st = qibl_shlight_add_dir(&sl, dir, rgb);
        if (st == QIBL_OK)
            st = qibl_shmap_weights(&mu, &sl, &wsrc[i]);
    }
    if (st != QIBL_OK)
        return qtool_errf(err, errlen, "sun + SH: %s", qibl_status_str(st));
    uint32_t w = mu.width, h = mu.height;
    size_t wsn = qibl_shmap_span_workspace_size(w);
    uint8_t *pix = malloc((size_t)w * h * 4);
    int32_t *row = malloc(sizeof(int32_t) * 3 * w), *urow = malloc(sizeof(int32_t) * 3 * w);
    int32_t *prow = malloc(sizeof(int32_t) * 3 * w);
    void *ws = malloc(wsn);
    if (!pix || !row || !urow || !prow || !ws) {
        free(pix), free(row), free(urow), free(prow), free(ws);
        return qtool_errf(err, errlen, "sun + SH: out of memory");
    }
    qibl_fb_desc_t fb = {0};
    fb.pixels = pix, fb.width = w, fb.height = h, fb.format = QIBL_FB_RGBA8888, fb.srgb = 1;
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    for (uint32_t y = 0; st == QIBL_OK && y < h; ++y) {
        st = qibl_shmap_relight_span(&msh, &wsky, 0, y, w, row, ws, wsn);
        for (int i = 0; st == QIBL_OK && i < nsrc; ++i) {
            st = qibl_shmap_relight_span(&mu, &wsrc[i], 0, y, w, urow, ws, wsn);
            for (int k = 0; st == QIBL_OK && k < nparts; ++k) {
                if (part_src[k] != i)
                    continue;
                for (uint32_t x = 0; x < w; ++x)
                    for (int c = 0; c < 3; ++c) {
                        int64_t v = (int64_t)urow[3 * x + (uint32_t)c] * wq[k][c];
                        prow[3 * x + (uint32_t)c] = (int32_t)((v + 32768) >> 16);
                    }
                st = qibl_lightpath_shade_span(&lp[k], 0, 0, 0, y, w, prow, row, true);
            }
        }
        if (st == QIBL_OK)
            st = qibl_fb_write_row(&fb, 0, y, w, row);
    }
    clock_gettime(CLOCK_MONOTONIC, &t1);
    *ms = (double)(t1.tv_sec - t0.tv_sec) * 1e3 + (double)(t1.tv_nsec - t0.tv_nsec) * 1e-6;
    for (size_t i = 0; st == QIBL_OK && i < (size_t)w * h; ++i)
        memcpy(rgb8 + 3 * i, pix + 4 * i, 3);
    free(pix), free(row), free(urow), free(prow), free(ws);
    if (st != QIBL_OK)
        return qtool_errf(err, errlen, "sun + SH: %s", qibl_status_str(st));
    return 0;
}
/* ---- a whole probe, for the CLI ----------------------------------------------------------------- */

/* the picture turned by yaw degrees: column u takes the probe at phi - yaw (linear between columns;
 * a yaw of whole columns copies them) */
static void turn(const float *in, uint32_t w, uint32_t h, double yaw, float *out)
{
    double s = fmod(yaw / 360.0 * w, (double)w);
    if (s < 0)
        s += w;
    uint32_t whole = (uint32_t)s;
    double f = s - whole;
    for (uint32_t v = 0; v < h; ++v)
        for (uint32_t u = 0; u < w; ++u) {
            /* source column u - s: between a = u - whole - 1 (weight f) and b = u - whole (1 - f) */
            uint32_t b = (u + w - whole % w) % w, a = (b + w - 1) % w;
            const float *pa = in + 3 * ((size_t)v * w + a), *pb = in + 3 * ((size_t)v * w + b);
            float *o = out + 3 * ((size_t)v * w + u);
            for (int c = 0; c < 3; ++c)
                o[c] = f == 0 ? pb[c] : (float)((1 - f) * pb[c] + f * pa[c]);
        }
}

static uint32_t pixels_crc(const float *p, size_t nf)
{
    uint32_t crc = 0;
    for (size_t i = 0; i < nf; ++i) {
        uint32_t u;
        memcpy(&u, &p[i], 4);
        uint8_t b[4] = {(uint8_t)u, (uint8_t)(u >> 8), (uint8_t)(u >> 16), (uint8_t)(u >> 24)};
        crc = qibl_crc32(crc, b, 4);
    }
    return crc;
}

void qtool_probesun_free(qtool_probesun *ps)
{
    free(ps->probe), free(ps->sky);
    qtool_env_free(&ps->env);
    memset(ps, 0, sizeof *ps);
}

int qtool_probesun_load(const char *path, double yaw, int kparts, qtool_probesun *ps, char *err, size_t errlen)
{
    memset(ps, 0, sizeof *ps);
    if (!(yaw >= -QTOOL_PROBESUN_YAW_MAX && yaw <= QTOOL_PROBESUN_YAW_MAX))
        return qtool_errf(err, errlen, "--yaw: %g is outside -%.0f..%.0f degrees (a probe-lit bake's turn)", yaw,
                          QTOOL_PROBESUN_YAW_MAX, QTOOL_PROBESUN_YAW_MAX);
    if (kparts < 1 || kparts > QTOOL_PROBESUN_MAX_PARTS || (kparts & (kparts - 1)))
        return qtool_errf(err, errlen, "%d parts per source is not a power of two in 1..%d", kparts,
                          QTOOL_PROBESUN_MAX_PARTS);
    int w = 0, h = 0;
    float *raw = NULL;
    char why[1200];
    if (qtool_hdr_read(path, &w, &h, &raw, why, sizeof why) != 0)
        return qtool_errf(err, errlen, "%s", why);
    if ((size_t)w != 2 * (size_t)h) {
        free(raw);
        return qtool_errf(err, errlen, "%s: %d x %d is not a 2:1 lat-long probe (a probe-lit bake needs one)", path, w, h);
    }
    size_t nf = 3 * (size_t)w * (size_t)h;
    const char *base = strrchr(path, '/');
    snprintf(ps->name, sizeof ps->name, "%s", base ? base + 1 : path);
    ps->w = (uint32_t)w, ps->h = (uint32_t)h, ps->yaw = yaw, ps->kparts = kparts;
    ps->id = pixels_crc(raw, nf);
    ps->probe = malloc(sizeof(float) * nf), ps->sky = malloc(sizeof(float) * nf);
    if (!ps->probe || !ps->sky) {
        free(raw), qtool_probesun_free(ps);
        return qtool_errf(err, errlen, "%s: out of memory", path);
    }
    turn(raw, ps->w, ps->h, yaw, ps->probe);
    free(raw);
    ps->scale = qtool_probesun_scale(ps->probe, ps->w, ps->h);
    if (qtool_env_build(&ps->env, ps->w, ps->h, ps->probe, why, sizeof why) != 0) {
        qtool_probesun_free(ps);
        return qtool_errf(err, errlen, "%s: %s", path, why);
    }
    memcpy(ps->sky, ps->probe, sizeof(float) * nf);
    ps->nsrc = qtool_probesun_find(&ps->env, ps->sky, ps->src, ps->parts, ps->part_src, &ps->nparts, kparts);
    if (ps->nsrc < 0) {
        qtool_probesun_free(ps);
        return qtool_errf(err, errlen, "%s: out of memory", path);
    }
    return 0;
}

/* ---- PSUN ---------------------------------------------------------------------------------------- */

static uint8_t *put32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v, p[1] = (uint8_t)(v >> 8), p[2] = (uint8_t)(v >> 16), p[3] = (uint8_t)(v >> 24);
    return p + 4;
}

static uint8_t *putd(uint8_t *p, double d)
{
    uint64_t u;
    memcpy(&u, &d, 8);
    p = put32(p, (uint32_t)u);
    return put32(p, (uint32_t)(u >> 32));
}

static uint32_t get32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static double getd(const uint8_t *p)
{
    uint64_t u = (uint64_t)get32(p) | (uint64_t)get32(p + 4) << 32;
    double d;
    memcpy(&d, &u, 8);
    return d;
}

#define PSUN_HEAD 36u
#define PSUN_SRC 56u  /* 7 doubles */
#define PSUN_PART 52u /* u32 + 6 doubles */

int qtool_probesun_chunk(const qtool_probesun *ps, uint8_t **out, size_t *n)
{
    size_t len = strlen(ps->name) > 255 ? 255 : strlen(ps->name);
    size_t sz = PSUN_HEAD + PSUN_SRC * (size_t)ps->nsrc + PSUN_PART * (size_t)ps->nparts + 4 + len;
    uint8_t *b = malloc(sz), *p = b;
    if (!b)
        return -1;
    p = put32(p, 1), p = put32(p, ps->id), p = put32(p, ps->w), p = put32(p, ps->h);
    p = putd(p, ps->yaw), p = put32(p, (uint32_t)ps->kparts), p = put32(p, (uint32_t)ps->nsrc);
    p = put32(p, (uint32_t)ps->nparts);
    for (int i = 0; i < ps->nsrc; ++i) {
        for (int c = 0; c < 3; ++c)
            p = putd(p, ps->src[i].dir[c]);
        for (int c = 0; c < 3; ++c)
            p = putd(p, ps->src[i].rgb[c]);
        p = putd(p, ps->src[i].share);
    }
    for (int k = 0; k < ps->nparts; ++k) {
        p = put32(p, (uint32_t)ps->part_src[k]);
        for (int c = 0; c < 3; ++c)
            p = putd(p, ps->parts[k].dir[c]);
        for (int c = 0; c < 3; ++c)
            p = putd(p, ps->parts[k].rgb[c]);
    }
    p = put32(p, (uint32_t)len);
    memcpy(p, ps->name, len);
    *out = b, *n = sz;
    return 0;
}

int qtool_probesun_check(const qibl_asset_t *a, const char *asset, const qtool_probesun *ps, char *err, size_t errlen)
{
    qibl_chunk_t ch;
    if (qibl_asset_find(a, QTOOL_PROBESUN_CHUNK, &ch) != QIBL_OK)
        return 1;
    const uint8_t *p = ch.data;
    if (ch.size < PSUN_HEAD || get32(p) != 1)
        return qtool_errf(err, errlen, "%s: its PSUN chunk (the probe it was baked with) is not version 1", asset);
    uint32_t id = get32(p + 4), w = get32(p + 8), h = get32(p + 12), kparts = get32(p + 24), nsrc = get32(p + 28),
             nparts = get32(p + 32);
    double yaw = getd(p + 16);
    size_t at = PSUN_HEAD + (size_t)PSUN_SRC * (nsrc <= QTOOL_PROBESUN_MAX_SRC ? nsrc : 0) +
                (size_t)PSUN_PART * (nparts <= QTOOL_PROBESUN_MAX_PATHS ? nparts : 0);
    if (nsrc > QTOOL_PROBESUN_MAX_SRC || nparts > QTOOL_PROBESUN_MAX_PATHS || ch.size < at + 4 ||
        ch.size != at + 4 + get32(p + at) || get32(p + at) > 255)
        return qtool_errf(err, errlen, "%s: its PSUN chunk (the probe it was baked with) is malformed", asset);
    char name[256];
    memcpy(name, p + at + 4, get32(p + at));
    name[get32(p + at)] = 0;
    if (id != ps->id || w != ps->w || h != ps->h)
        return qtool_errf(err, errlen,
                          "%s was baked with the probe %s (%u x %u, %u compact source%s, pixels CRC %08x): %s (%u x %u, "
                          "CRC %08x) is another probe; bake again with --probe %s",
                          asset, name, w, h, nsrc, nsrc == 1 ? "" : "s", id, ps->name, ps->w, ps->h, ps->id, ps->name);
    if (yaw != ps->yaw)
        return qtool_errf(err, errlen, "%s was baked with %s turned by --yaw %g, not %g: give the same --yaw", asset, name,
                          yaw, ps->yaw);
    if (kparts != (uint32_t)ps->kparts || nsrc != (uint32_t)ps->nsrc || nparts != (uint32_t)ps->nparts)
        return qtool_errf(err, errlen, "%s: its PSUN chunk holds %u sources in %u parts, the probe %s gives %d in %d",
                          asset, nsrc, nparts, name, ps->nsrc, ps->nparts);
    for (uint32_t k = 0; k < nparts; ++k) {
        qibl_chunk_t lp;
        if (qibl_asset_find_nth(a, QIBL_CHUNK_LPTH, k, &lp) != QIBL_OK)
            return qtool_errf(err, errlen, "%s: the light path of source part %u (LPTH %u) is missing", asset, k, k);
    }
    return 0;
}

/* ---- truth and bake ------------------------------------------------------------------------------- */

int qtool_probesun_truth(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, const qtool_probesun *ps,
                         uint32_t spp, uint64_t seed, int threads, double *lin)
{
    size_t nv = (size_t)w * h * 3;
    double *hb = malloc(nv * sizeof(double));
    int rc = -1;
    if (hb && qtool_env_render(s, w, h, kind, &ps->env, spp, 2 * seed + 1, 1, threads, lin) == 0 &&
        qtool_env_render(s, w, h, kind, &ps->env, spp, 2 * seed + 2, 1, threads, hb) == 0) {
        for (size_t i = 0; i < nv; ++i)
            lin[i] = 0.5 * (lin[i] + hb[i]);
        rc = 0;
    }
    free(hb);
    return rc;
}

int qtool_probesun_bake(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, int threads,
                        const qtool_bake_sums *sums, uint32_t ndirs, uint32_t lut, uint32_t layout, const qtool_probesun *ps,
                        const char *out, FILE *rep, char *err, size_t errlen)
{
    if (ps->nsrc == 0)
        return qtool_errf(err, errlen,
                          "--probe %s: no compact bright source (nothing holding 1 %% of the energy within %.0f degrees): "
                          "relight it as SH (relight --probe) instead", ps->name, SUN_RADIUS);
    qtool_gen_maps m = {0}, mu = {0};
    qtool_bake_sums us;
    memset(&us, 0, sizeof us);
    uint8_t *lp[QTOOL_PROBESUN_MAX_PATHS + 1] = {NULL}, *cls = malloc((size_t)w * h), *a1 = NULL, *chunk = NULL,
            *a2 = NULL;
    size_t lpn[QTOOL_PROBESUN_MAX_PATHS + 1] = {0}, n1 = 0, cn = 0, n2 = 0;
    int rc = cls ? 0 : -1;
    for (int k = 0; rc == 0 && k < ps->nparts; ++k)
        rc = qtool_probesun_path(s, w, h, kind, threads, &ps->parts[k], cls, &lp[k], &lpn[k]);
    if (rc == 0 && (qtool_bake_coeffs(sums, QTOOL_PROBESUN_SHADOWED_K, QTOOL_PROJ_QUADRATURE, &m) != 0 ||
                    qtool_bake_run_unshadowed(s, w, h, kind, ndirs, QTOOL_PROBESUN_UNSHADOWED_K, threads, &us) != 0 ||
                    qtool_bake_coeffs(&us, QTOOL_PROBESUN_UNSHADOWED_K, QTOOL_PROJ_QUADRATURE, &mu) != 0 ||
                    qtool_bake_asset_full(&m, &mu, lut, layout, lp, lpn, &a1, &n1) != 0 ||
                    qtool_probesun_chunk(ps, &chunk, &cn) != 0 ||
                    qtool_bake_asset_add(a1, n1, QTOOL_PROBESUN_CHUNK, chunk, cn, &a2, &n2) != 0))
        rc = -1;
    if (rc != 0)
        qtool_errf(err, errlen, "%s: cannot build the probe-lit asset (out of memory)", out);
    else
        rc = qtool_io_write_atomic(out, a2, n2, err, errlen);
    if (rc == 0) {
        fprintf(rep, "wrote %s: %ux%u, sun + SH of %s (yaw %g): %d compact source%s", out, w, h, ps->name, ps->yaw,
                ps->nsrc, ps->nsrc == 1 ? "" : "s");
        for (int i = 0; i < ps->nsrc; ++i)
            fprintf(rep, "%s %.0f %% of the energy within %.1f deg", i ? ";" : ":", 100 * ps->src[i].share,
                    ps->src[i].radius_deg);
        fprintf(rep, "; %d light paths, shadowed maps k = %d, unshadowed k = %d, %u light directions, %zu bytes\n",
                ps->nparts, QTOOL_PROBESUN_SHADOWED_K, QTOOL_PROBESUN_UNSHADOWED_K, sums->ndirs, n2);
    }
    for (int k = 0; k < QTOOL_PROBESUN_MAX_PATHS; ++k)
        free(lp[k]);
    free(cls), free(a1), free(chunk), free(a2);
    qtool_gen_free(&m), qtool_gen_free(&mu);
    qtool_bake_sums_free(&us);
    return rc;
}
