/*
 * bake/bake.c - reference renders -> SH sums (exact int64 accumulation) -> coefficients -> asset;
 * held-out evaluation through the core.
 */
#include "bake/bake.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "io/asset_write.h"
#include "qibl/asset.h"
#include "qibl/shmap.h"
#include "qibl/soft.h"
#include "ref/sh_ref.h"

#define PI 3.14159265358979323846
#define UNIT 4294967296.0 /* 2^32 */

void qibl_bake_dir(uint32_t j, uint32_t n, double d[3])
{
    double z = 1.0 - (2.0 * j + 1.0) / n, r = sqrt(fmax(0.0, 1 - z * z));
    double phi = fmod(j * (PI * (3.0 - sqrt(5.0))), 2 * PI);
    d[0] = r * cos(phi), d[1] = r * sin(phi), d[2] = z;
}

typedef struct {
    const qibl_rt_scene *s;
    uint32_t w, h, k, ndirs, shard, nshards;
    qibl_pano_kind kind;
    double *dirs, *y; /* ndirs * 3, ndirs * 25 */
    qibl_bake_sums *out;
    int progress;
    double t0;
} bake_job;

static void bake_row(void *ctx, uint32_t row)
{
    const bake_job *j = ctx;
    uint32_t k = j->k, nblocks = (j->ndirs + QIBL_BAKE_BLOCK - 1) / QIBL_BAKE_BLOCK;
    for (uint32_t x = 0; x < j->w; ++x) {
        size_t pi = (size_t)row * j->w + x;
        double d[3];
        qibl_rt_hit h;
        qibl_rt_pixel_dir(j->w, j->h, j->kind, x, row, d);
        qibl_rt_primary(j->s, d, &h);
        for (int c = 0; c < 3; ++c)
            j->out->pmap[3 * pi + (size_t)c] = (int32_t)lrint((h.hit ? h.p[c] : d[c] * 1000.0) * 65536.0);
        int64_t *acc = j->out->acc + pi * 3 * k;
        memset(acc, 0, sizeof(int64_t) * 3 * k);
        if (!h.hit)
            continue;
        for (uint32_t b = j->shard; b < nblocks; b += j->nshards) {
            double sum[3][25];
            int any = 0;
            memset(sum, 0, sizeof sum);
            for (uint32_t l = b * QIBL_BAKE_BLOCK; l < (b + 1) * QIBL_BAKE_BLOCK && l < j->ndirs; ++l) {
                double df, gl;
                if (!qibl_rt_response(j->s, &h, j->dirs + 3 * l, 1e30, &df, &gl))
                    continue;
                any = 1;
                const double *y = j->y + 25 * (size_t)l;
                for (int c = 0; c < 3; ++c) {
                    double t = h.m->albedo[c] * df + h.m->ks * gl;
                    for (uint32_t i = 0; i < k; ++i)
                        sum[c][i] += t * y[i];
                }
            }
            if (any)
                for (int c = 0; c < 3; ++c)
                    for (uint32_t i = 0; i < k; ++i)
                        acc[(size_t)c * k + i] += (int64_t)llrint(sum[c][i] * UNIT);
        }
    }
}

static void bar(void *ctx, uint32_t done, uint32_t rows)
{
    const bake_job *j = ctx;
    if (!j->progress)
        return;
    int n = (int)(40.0 * done / rows);
    char b[41];
    for (int i = 0; i < 40; ++i)
        b[i] = i < n ? '#' : '.';
    b[40] = '\0';
    fprintf(stderr, "\rbake [%s] %3u%% %u/%u rows", b, (unsigned)(100.0 * done / rows), done, rows);
    if (done == rows)
        fputc('\n', stderr);
    fflush(stderr);
}

int qibl_bake_run(const qibl_rt_scene *s, uint32_t w, uint32_t h, qibl_pano_kind kind, uint32_t ndirs, uint32_t k,
                  uint32_t shard, uint32_t nshards, int threads, int progress, qibl_bake_sums *out)
{
    if (k < 1 || k > 25 || ndirs < 1 || nshards < 1 || shard >= nshards || w < 1 || h < 1)
        return -1;
    memset(out, 0, sizeof *out);
    size_t np = (size_t)w * h;
    out->pmap = malloc(np * 3 * sizeof(int32_t));
    out->acc = malloc(np * 3 * k * sizeof(int64_t));
    bake_job j = {s, w, h, k, ndirs, shard, nshards, kind, malloc(ndirs * 3 * sizeof(double)),
                  malloc(ndirs * 25 * sizeof(double)), out, progress && isatty(2), 0};
    if (!out->pmap || !out->acc || !j.dirs || !j.y) {
        free(j.dirs), free(j.y);
        qibl_bake_sums_free(out);
        return -1;
    }
    for (uint32_t l = 0; l < ndirs; ++l) {
        qibl_bake_dir(l, ndirs, j.dirs + 3 * l);
        qibl_ref_sh_eval(j.dirs[3 * l], j.dirs[3 * l + 1], j.dirs[3 * l + 2], 5, j.y + 25 * (size_t)l);
    }
    out->w = w, out->h = h, out->k = k, out->ndirs = ndirs, out->kind = (uint32_t)kind;
    out->shard = shard, out->nshards = nshards;
    qibl_rt_parallel(threads, h, bake_row, &j, bar);
    free(j.dirs), free(j.y);
    return 0;
}

void qibl_bake_sums_free(qibl_bake_sums *s)
{
    free(s->pmap), free(s->acc);
    memset(s, 0, sizeof *s);
}

/* ---- partial sums files -------------------------------------------------------------------------- */

int qibl_bake_sums_write(const qibl_bake_sums *s, const char *path, char *err, size_t errlen)
{
    size_t np = (size_t)s->w * s->h, tl = strlen(path) + 5;
    char *tmp = malloc(tl);
    if (!tmp) {
        snprintf(err, errlen, "%s: out of memory", path);
        return -1;
    }
    snprintf(tmp, tl, "%s.tmp", path);
    FILE *f = fopen(tmp, "wb");
    if (!f) {
        snprintf(err, errlen, "%s: cannot create: %s", tmp, strerror(errno));
        free(tmp);
        return -1;
    }
    uint8_t hdr[36];
    memcpy(hdr, "QIBLSUM1", 8);
    uint32_t f7[7] = {s->w, s->h, s->k, s->ndirs, s->kind, s->shard, s->nshards};
    for (int i = 0; i < 7; ++i)
        qibl_store_u32le(hdr + 8 + 4 * i, f7[i]);
    int bad = fwrite(hdr, 1, 36, f) != 36;
    uint8_t buf[8 * 75];
    for (size_t p = 0; p < np && !bad; ++p) {
        for (int c = 0; c < 3; ++c)
            qibl_store_s32le(buf + 4 * c, s->pmap[3 * p + (size_t)c]);
        bad |= fwrite(buf, 1, 12, f) != 12;
    }
    size_t per = 3 * (size_t)s->k;
    for (size_t p = 0; p < np && !bad; ++p) {
        for (size_t i = 0; i < per; ++i) {
            uint64_t u = (uint64_t)s->acc[p * per + i];
            qibl_store_u32le(buf + 8 * i, (uint32_t)u);
            qibl_store_u32le(buf + 8 * i + 4, (uint32_t)(u >> 32));
        }
        bad |= fwrite(buf, 8, per, f) != per;
    }
    bad |= fclose(f) != 0;
    if (bad || rename(tmp, path) != 0) {
        snprintf(err, errlen, "%s: write failed: %s", path, strerror(errno));
        remove(tmp);
        free(tmp);
        return -1;
    }
    free(tmp);
    return 0;
}

int qibl_bake_sums_read(const char *path, qibl_bake_sums *out, char *err, size_t errlen)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        snprintf(err, errlen, "%s: %s", path, strerror(errno));
        return -1;
    }
    uint8_t hdr[36];
    qibl_bake_sums s = {0};
    if (fread(hdr, 1, 36, f) != 36 || memcmp(hdr, "QIBLSUM1", 8) != 0) {
        fclose(f);
        snprintf(err, errlen, "%s: not a qibl partial-sums file (bad magic or too short)", path);
        return -1;
    }
    uint32_t v[7];
    for (int i = 0; i < 7; ++i)
        v[i] = qibl_load_u32le(hdr + 8 + 4 * i);
    s.w = v[0], s.h = v[1], s.k = v[2], s.ndirs = v[3], s.kind = v[4], s.shard = v[5], s.nshards = v[6];
    if (s.w < 1 || s.h < 1 || s.w > 16384 || s.h > 16384 || s.k < 1 || s.k > 25 || s.ndirs < 1 || s.kind > 1 ||
        s.nshards < 1 || s.shard >= s.nshards) {
        fclose(f);
        snprintf(err, errlen, "%s: bad header fields (size %ux%u, k %u, %u directions, shard %u/%u)", path, s.w, s.h,
                 s.k, s.ndirs, s.shard, s.nshards);
        return -1;
    }
    size_t np = (size_t)s.w * s.h, per = 3 * (size_t)s.k;
    s.pmap = malloc(np * 12);
    s.acc = malloc(np * per * 8);
    uint8_t *buf = malloc(np * per * 8 > np * 12 ? np * per * 8 : np * 12);
    int bad = !s.pmap || !s.acc || !buf;
    if (!bad && fread(buf, 12, np, f) == np)
        for (size_t i = 0; i < np * 3; ++i)
            s.pmap[i] = qibl_load_s32le(buf + 4 * i);
    else
        bad = 2;
    if (!bad && fread(buf, 8, np * per, f) == np * per)
        for (size_t i = 0; i < np * per; ++i)
            s.acc[i] = (int64_t)((uint64_t)qibl_load_u32le(buf + 8 * i) | (uint64_t)qibl_load_u32le(buf + 8 * i + 4) << 32);
    else
        bad = bad ? bad : 2;
    if (!bad && fgetc(f) != EOF)
        bad = 3;
    fclose(f);
    free(buf);
    if (bad) {
        snprintf(err, errlen, "%s: %s", path, bad == 1 ? "out of memory" : bad == 2 ? "truncated" : "trailing bytes after the sums");
        qibl_bake_sums_free(&s);
        return -1;
    }
    *out = s;
    return 0;
}

int qibl_bake_sums_add(qibl_bake_sums *a, const qibl_bake_sums *b, char *err, size_t errlen)
{
    if (a->w != b->w || a->h != b->h || a->k != b->k || a->ndirs != b->ndirs || a->kind != b->kind ||
        a->nshards != b->nshards) {
        snprintf(err, errlen, "shards of different bakes (size, k, directions, panorama or shard count differ)");
        return -1;
    }
    size_t np = (size_t)a->w * a->h;
    if (memcmp(a->pmap, b->pmap, np * 12) != 0) {
        snprintf(err, errlen, "shards of different scenes (P maps differ)");
        return -1;
    }
    for (size_t i = 0; i < np * 3 * a->k; ++i)
        a->acc[i] += b->acc[i];
    return 0;
}

/* ---- coefficients, asset ------------------------------------------------------------------------- */

/* inverse of the k x k Gram matrix of the directions, by Gauss-Jordan with partial pivoting */
static int gram_inverse(uint32_t ndirs, uint32_t k, double *inv)
{
    double a[25][50];
    memset(a, 0, sizeof a);
    for (uint32_t l = 0; l < ndirs; ++l) {
        double d[3], y[25];
        qibl_bake_dir(l, ndirs, d);
        qibl_ref_sh_eval(d[0], d[1], d[2], 5, y);
        for (uint32_t i = 0; i < k; ++i)
            for (uint32_t m = 0; m < k; ++m)
                a[i][m] += y[i] * y[m];
    }
    for (uint32_t i = 0; i < k; ++i)
        a[i][k + i] = 1;
    for (uint32_t c = 0; c < k; ++c) {
        uint32_t p = c;
        for (uint32_t r = c + 1; r < k; ++r)
            if (fabs(a[r][c]) > fabs(a[p][c]))
                p = r;
        if (fabs(a[p][c]) < 1e-12)
            return -1; /* too few directions for k */
        for (uint32_t m = 0; m < 2 * k; ++m) {
            double t = a[c][m];
            a[c][m] = a[p][m], a[p][m] = t;
        }
        double piv = a[c][c];
        for (uint32_t m = 0; m < 2 * k; ++m)
            a[c][m] /= piv;
        for (uint32_t r = 0; r < k; ++r)
            if (r != c && a[r][c] != 0) {
                double f = a[r][c];
                for (uint32_t m = 0; m < 2 * k; ++m)
                    a[r][m] -= f * a[c][m];
            }
    }
    for (uint32_t i = 0; i < k; ++i)
        for (uint32_t m = 0; m < k; ++m)
            inv[i * k + m] = a[i][k + m];
    return 0;
}

int qibl_bake_coeffs(const qibl_bake_sums *s, uint32_t k, qibl_proj_method method, qibl_gen_maps *out)
{
    if (k < 1 || k > s->k)
        return -1;
    size_t np = (size_t)s->w * s->h;
    double inv[625];
    if (method == QIBL_PROJ_LSQ && gram_inverse(s->ndirs, k, inv) != 0)
        return -1;
    memset(out, 0, sizeof *out);
    out->t = malloc(sizeof(double) * np * k * 3);
    out->p = malloc(sizeof(int32_t) * np * 3);
    if (!out->t || !out->p) {
        qibl_gen_free(out);
        return -1;
    }
    out->width = s->w, out->height = s->h, out->k = k;
    memcpy(out->p, s->pmap, sizeof(int32_t) * np * 3);
    double wq = 4 * PI / s->ndirs / UNIT;
    for (size_t p = 0; p < np; ++p)
        for (uint32_t c = 0; c < 3; ++c) {
            const int64_t *a = s->acc + (p * 3 + c) * s->k;
            for (uint32_t i = 0; i < k; ++i) {
                double v;
                if (method == QIBL_PROJ_QUADRATURE) {
                    v = (double)a[i] * wq;
                } else {
                    v = 0;
                    for (uint32_t m = 0; m < k; ++m)
                        v += inv[i * k + m] * (double)a[m];
                    v /= UNIT;
                }
                out->t[((size_t)i * 3 + c) * np + p] = v;
            }
        }
    return 0;
}

int qibl_bake_asset(const qibl_gen_maps *m, uint32_t lut, uint8_t **bytes, size_t *n)
{
    return qibl_bake_asset_layout(m, lut, QIBL_SHMAPS_PLANAR, bytes, n);
}

int qibl_bake_asset_layout(const qibl_gen_maps *m, uint32_t lut, uint32_t layout, uint8_t **bytes, size_t *n)
{
    size_t np = (size_t)m->width * m->height, nplanes = (size_t)m->k * 3;
    int32_t *scale = malloc(sizeof(int32_t) * nplanes), *bias = malloc(sizeof(int32_t) * nplanes);
    uint8_t *planes = malloc(np * nplanes);
    int16_t *lutv = NULL;
    uint8_t *le = NULL;
    qibl_asset_builder b;
    qibl_asset_builder_init(&b);
    int rc = -1;
    if (!scale || !bias || !planes || qibl_pack_maps(m, QIBL_PACK_MINMAX, scale, bias, planes, NULL) != 0)
        goto done;
    if (qibl_asset_add_shmp_layout(&b, m->width, m->height, m->k, 3, scale, bias, planes, layout) != 0 ||
        qibl_asset_add_pmap(&b, m->width, m->height, m->p) != 0)
        goto done;
    if (lut) {
        size_t vs = qibl_ylut_values_size(lut, m->k);
        le = malloc(vs);
        lutv = malloc(vs);
        if (!le || !lutv || qibl_ylut_build(lut, m->k, le, vs) != QIBL_OK)
            goto done;
        for (size_t i = 0; i < vs / 2; ++i)
            lutv[i] = qibl_load_s16le(le + 2 * i);
        if (qibl_asset_add_ylut(&b, lut, m->k, lutv) != 0)
            goto done;
    }
    if (qibl_asset_serialize(&b, bytes, n) != 0)
        goto done;
    rc = 0;
done:
    qibl_asset_builder_free(&b);
    free(scale), free(bias), free(planes), free(lutv), free(le);
    return rc;
}

/* ---- evaluation ---------------------------------------------------------------------------------- */

static void to_fb(const double *lin, uint32_t w, uint32_t h, uint8_t *rgb8)
{
    uint8_t *pix = malloc((size_t)w * 4);
    int32_t *row = malloc(sizeof(int32_t) * 3 * w);
    qibl_fb_desc_t fb = {0};
    fb.pixels = pix, fb.width = w, fb.height = 1, fb.format = QIBL_FB_RGBA8888, fb.srgb = 1;
    for (uint32_t y = 0; y < h; ++y) {
        for (size_t i = 0; i < (size_t)w * 3; ++i) {
            double v = lin[(size_t)y * w * 3 + i] * 65536.0;
            row[i] = v > 2e9 ? 2000000000 : v < -2e9 ? -2000000000 : (int32_t)lrint(v);
        }
        qibl_fb_write_row(&fb, 0, 0, w, row);
        for (uint32_t x = 0; x < w; ++x)
            memcpy(rgb8 + ((size_t)y * w + x) * 3, pix + 4 * (size_t)x, 3);
    }
    free(pix), free(row);
}

int qibl_bake_truth8(const qibl_rt_scene *s, uint32_t w, uint32_t h, qibl_pano_kind kind, const qibl_rt_light *l,
                     int threads, uint8_t *rgb8, uint8_t *mask)
{
    size_t np = (size_t)w * h;
    double *lin = malloc(np * 3 * sizeof(double));
    float *depth = malloc(np * sizeof(float));
    if (!lin || !depth) {
        free(lin), free(depth);
        return -1;
    }
    qibl_rt_render(s, w, h, kind, l, threads, lin, depth, NULL);
    to_fb(lin, w, h, rgb8);
    if (mask)
        for (size_t i = 0; i < np; ++i)
            mask[i] = depth[i] > 0;
    free(lin), free(depth);
    return 0;
}

static qibl_q16_t q16(double v)
{
    return (qibl_q16_t)lrint(v * 65536.0);
}

int qibl_bake_relight8_ex(const uint8_t *asset, size_t n, const qibl_rt_light *l, int lut_mode, qibl_uq16_t exposure,
                           int srgb, uint8_t *rgb8, double *ms, qibl_status_t *status)
{
    qibl_asset_t a;
    qibl_shmaps_t m;
    qibl_pmap_t pm;
    qibl_ylut_t lut;
    qibl_status_t st = qibl_asset_open(&a, asset, n);
    if (st == QIBL_OK)
        st = qibl_asset_shmaps(&a, &m);
    if (st == QIBL_OK && l->point)
        st = qibl_asset_pmap(&a, &pm);
    if (st == QIBL_OK && l->point && lut_mode)
        st = qibl_asset_ylut(&a, &lut);
    if (status)
        *status = st;
    if (st != QIBL_OK)
        return -1;
    uint32_t w = m.width, h = m.height;
    uint8_t *pix = malloc((size_t)w * h * 4);
    int32_t *row = malloc(sizeof(int32_t) * 3 * w);
    size_t wsn = l->point ? qibl_shmap_point_workspace_size(m.k, w) : qibl_shmap_span_workspace_size(w);
    void *ws = malloc(wsn);
    if (!pix || !row || !ws) {
        free(pix), free(row), free(ws);
        if (status)
            *status = QIBL_E_NULL_POINTER;
        return -1;
    }
    qibl_fb_desc_t fb = {0};
    fb.pixels = pix, fb.width = w, fb.height = h, fb.format = QIBL_FB_RGBA8888;
    fb.srgb = srgb ? 1 : 0, fb.exposure = exposure;
    qibl_q16_t rgb[3] = {q16(l->rgb[0]), q16(l->rgb[1]), q16(l->rgb[2])};
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    if (!l->point) {
        qibl_q16_t dir[3] = {q16(l->dir[0]), q16(l->dir[1]), q16(l->dir[2])};
        qibl_shlight_t sl;
        qibl_shmap_weights_t wt;
        st = qibl_shlight_init(&sl, m.k);
        if (st == QIBL_OK)
            st = qibl_shlight_add_dir(&sl, dir, rgb);
        if (st == QIBL_OK)
            st = qibl_shmap_weights(&m, &sl, &wt);
        for (uint32_t y = 0; st == QIBL_OK && y < h; ++y) {
            st = qibl_shmap_relight_span(&m, &wt, 0, y, w, row, ws, wsn);
            if (st == QIBL_OK)
                st = qibl_fb_write_row(&fb, 0, y, w, row);
        }
    } else {
        qibl_pointlight_t pl = {{q16(l->pos[0]), q16(l->pos[1]), q16(l->pos[2])}, {rgb[0], rgb[1], rgb[2]},
                                l->falloff == 2 ? QIBL_FALLOFF_INV_DIST2 : QIBL_FALLOFF_INV_DIST, 0,
                                lut_mode == 2 ? QIBL_LUT_NEAREST : QIBL_LUT_BILINEAR};
        qibl_shmap_point_t pt;
        st = qibl_shmap_point_prepare(&m, &pm, lut_mode ? &lut : NULL, &pl, &pt);
        for (uint32_t y = 0; st == QIBL_OK && y < h; ++y) {
            st = qibl_shmap_point_span(&pt, 0, y, w, row, ws, wsn);
            if (st == QIBL_OK)
                st = qibl_fb_write_row(&fb, 0, y, w, row);
        }
    }
    clock_gettime(CLOCK_MONOTONIC, &t1);
    if (ms)
        *ms = (double)(t1.tv_sec - t0.tv_sec) * 1e3 + (double)(t1.tv_nsec - t0.tv_nsec) * 1e-6;
    for (size_t i = 0; st == QIBL_OK && i < (size_t)w * h; ++i)
        memcpy(rgb8 + 3 * i, pix + 4 * i, 3);
    free(pix), free(row), free(ws);
    if (status)
        *status = st;
    return st == QIBL_OK ? 0 : -1;
}

int qibl_bake_relight8(const uint8_t *asset, size_t n, const qibl_rt_light *l, int use_lut, uint8_t *rgb8, double *ms)
{
    return qibl_bake_relight8_ex(asset, n, l, use_lut ? 1 : 0, 0, 1, rgb8, ms, NULL);
}

double qibl_bake_mse(const uint8_t *a, const uint8_t *b, const uint8_t *mask, size_t npix)
{
    double se = 0;
    size_t n = 0;
    for (size_t i = 0; i < npix; ++i) {
        if (mask && !mask[i])
            continue;
        for (int c = 0; c < 3; ++c) {
            double d = (double)a[3 * i + (size_t)c] - b[3 * i + (size_t)c];
            se += d * d;
        }
        n += 3;
    }
    return n ? se / (double)n : 0;
}

double qibl_bake_psnr(const uint8_t *a, const uint8_t *b, const uint8_t *mask, size_t npix)
{
    double mse = qibl_bake_mse(a, b, mask, npix);
    return mse > 0 ? 10 * log10(255.0 * 255.0 / mse) : 99.0;
}
