/*
 * bake/path.c - sun paths and lamp tracks: exact light along the path, per-pixel visibility edges
 * (sampled, then bisected), the LPTH payload, and relighting a path light through the core.
 */
#include "bake/path.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bake/bake.h"
#include "io/asset_write.h"
#include "qibl/asset.h"
#include "qibl/lightpath.h"
#include "qibl/soft.h"
#include "qtool.h"
#include "ref/sh_ref.h"


/* ---- parsing ------------------------------------------------------------------------------------- */

/* up to max comma-separated finite numbers from s into v; the count, or -1 on a bad number */
static int numbers(const char *s, char sep, double *v, int max, const char **end)
{
    int n = 0;
    for (;;) {
        char *e;
        double x = strtod(s, &e);
        if (e == s || !isfinite(x) || n == max)
            return -1;
        v[n++] = x;
        s = e;
        if (*s != sep)
            break;
        ++s;
    }
    *end = s;
    return n;
}

int qtool_bake_path_parse_sun(const char *s, qtool_bake_path *p, char *err, size_t errlen)
{
    double v[4];
    const char *end;
    if (numbers(s, ',', v, 4, &end) != 4 || *end)
        return snprintf(err, errlen, "--sun-path '%s': needs LAT,DECL,T0,T1 (degrees, degrees, hours, hours)", s), -1;
    if (fabs(v[0]) > 90 || fabs(v[1]) > 23.5 || v[2] < 0 || v[3] > 24 || v[3] <= v[2])
        return snprintf(err, errlen,
                        "--sun-path '%s': latitude in -90..90, declination in -23.5..23.5, 0 <= T0 < T1 <= 24", s), -1;
    /* the highest the sun gets: elevation falls with |hour angle|, so at the hour angle nearest
     * noon within T0..T1; a path wholly below the horizon would bake frames that are all black */
    double h0 = (v[2] - 12) * 15, h1 = (v[3] - 12) * 15, hn = h0 > 0 ? h0 : h1 < 0 ? h1 : 0;
    double la = v[0] * QTOOL_PI / 180, de = v[1] * QTOOL_PI / 180;
    double zmax = sin(de) * sin(la) + cos(de) * cos(la) * cos(hn * QTOOL_PI / 180);
    if (!(zmax > 0))
        return snprintf(err, errlen, "--sun-path '%s': the sun never rises between %gh and %gh (highest elevation "
                        "%.1f degrees): every frame would be unlit", s, v[2], v[3], asin(fmax(-1, fmin(1, zmax))) * 180 / QTOOL_PI),
               -1;
    p->kind = 0, p->lat = v[0], p->decl = v[1], p->t0 = v[2], p->t1 = v[3];
    return 0;
}

int qtool_bake_path_parse_track(const char *s, qtool_bake_path *p, char *err, size_t errlen)
{
    int n = 0;
    const char *q = s;
    double len = 0;
    for (;;) {
        double v[3];
        const char *end;
        if (n == QTOOL_BAKE_PATH_MAX_POINTS)
            return snprintf(err, errlen, "--lamp-track: more than %d points", QTOOL_BAKE_PATH_MAX_POINTS), -1;
        if (numbers(q, ',', v, 3, &end) != 3 || (*end && *end != ';'))
            return snprintf(err, errlen, "--lamp-track '%s': point %d is not x,y,z (points separated by ';')", s, n + 1), -1;
        for (int c = 0; c < 3; ++c) {
            if (fabs(v[c]) > 30000)
                return snprintf(err, errlen, "--lamp-track: point %d coordinate %g outside -30000..30000", n + 1, v[c]), -1;
            p->pts[n][c] = v[c];
        }
        if (n > 0)
            len += sqrt(pow(v[0] - p->pts[n - 1][0], 2) + pow(v[1] - p->pts[n - 1][1], 2) + pow(v[2] - p->pts[n - 1][2], 2));
        ++n;
        if (!*end)
            break;
        q = end + 1;
    }
    if (n < 2 || len <= 0)
        return snprintf(err, errlen, "--lamp-track '%s': needs at least two distinct points", s), -1;
    p->kind = 1, p->npts = n;
    return 0;
}

/* ---- the light along the path -------------------------------------------------------------------- */

void qtool_bake_path_light(const qtool_bake_path *p, double t, qtool_rt_light *out)
{
    memset(out, 0, sizeof *out);
    memcpy(out->rgb, p->rgb, sizeof out->rgb);
    if (p->kind == 0) {
        double hr = (p->t0 + (p->t1 - p->t0) * t - 12) * 15 * QTOOL_PI / 180, la = p->lat * QTOOL_PI / 180, de = p->decl * QTOOL_PI / 180;
        out->dir[0] = -cos(de) * sin(hr);
        out->dir[1] = sin(de) * cos(la) - cos(de) * sin(la) * cos(hr);
        out->dir[2] = sin(de) * sin(la) + cos(de) * cos(la) * cos(hr);
        return;
    }
    double total = 0, seg[QTOOL_BAKE_PATH_MAX_POINTS] = {0};
    for (int i = 1; i < p->npts; ++i) {
        seg[i] = sqrt(pow(p->pts[i][0] - p->pts[i - 1][0], 2) + pow(p->pts[i][1] - p->pts[i - 1][1], 2) +
                      pow(p->pts[i][2] - p->pts[i - 1][2], 2));
        total += seg[i];
    }
    double at = t * total;
    int i = 1;
    while (i < p->npts - 1 && at > seg[i])
        at -= seg[i++];
    double f = seg[i] > 0 ? fmin(1, fmax(0, at / seg[i])) : 0;
    out->point = 1, out->falloff = 1;
    for (int c = 0; c < 3; ++c)
        out->pos[c] = p->pts[i - 1][c] + f * (p->pts[i][c] - p->pts[i - 1][c]);
}

/* ---- visibility edges ---------------------------------------------------------------------------- */

typedef struct {
    const qtool_rt_scene *s;
    const qtool_bake_path *p;
    uint32_t w, h, steps;
    qtool_pano_kind kind;
    uint8_t *counts;     /* w * h */
    uint16_t **row_edges; /* per row, malloc'ed */
    uint32_t *row_n;
    uint32_t clipped;
    int oom;
    uint32_t shard, nshards; /* the rows shard + i nshards (a band: its first row, 1); the others stay empty */
} path_job;

/* the truth's lighting condition (rt.c render_row): facing, not shadowed, not at the lamp */
static int vis_at(const path_job *j, const qtool_rt_hit *h, uint32_t q)
{
    qtool_rt_light l;
    qtool_bake_path_light(j->p, q / 65535.0, &l);
    double w[3], tmax = 1e30, df, gl, len = 0;
    for (int c = 0; c < 3; ++c) {
        w[c] = l.point ? l.pos[c] - h->p[c] : l.dir[c];
        len += w[c] * w[c];
    }
    len = sqrt(len);
    if (len <= 0 || (l.point && len < 1.0 / 256))
        return 0;
    for (int c = 0; c < 3; ++c)
        w[c] /= len;
    if (l.point)
        tmax = len;
    return qtool_rt_response(j->s, h, w, tmax, &df, &gl);
}

static void path_row(void *ctx, uint32_t y)
{
    path_job *j = ctx;
    size_t cap = (size_t)j->w * 2 + 16, n = 0;
    uint16_t *e = malloc(cap * sizeof *e);
    uint32_t clipped = 0;
    for (uint32_t x = 0; e && x < j->w; ++x) {
        double d[3];
        qtool_rt_hit hit;
        qtool_rt_pixel_ray(j->s, j->w, j->h, j->kind, x, y, d);
        qtool_rt_primary(j->s, d, &hit);
        size_t start = n;
        if (hit.hit) {
            uint32_t qa = 0;
            int va = vis_at(j, &hit, 0);
            uint16_t buf[512];
            size_t m = 0;
            if (va)
                buf[m++] = 0;
            for (uint32_t s = 1; s <= j->steps; ++s) {
                uint32_t qb = (uint32_t)lrint(65535.0 * s / j->steps);
                int vb = vis_at(j, &hit, qb);
                if (vb != va) { /* bisection to one step of the 16-bit parameter */
                    uint32_t lo = qa, hi = qb;
                    while (hi - lo > 1) {
                        uint32_t mid = lo + (hi - lo) / 2;
                        if (vis_at(j, &hit, mid) == va)
                            lo = mid;
                        else
                            hi = mid;
                    }
                    if (m < sizeof buf / sizeof buf[0])
                        buf[m++] = (uint16_t)hi;
                }
                qa = qb, va = vb;
            }
            if (m > 255) { /* keep an even prefix: the pixel ends dark */
                clipped++;
                m = 254;
            }
            if (n + m > cap) {
                cap = (n + m) * 2;
                uint16_t *ne = realloc(e, cap * sizeof *e);
                if (!ne) {
                    free(e);
                    e = NULL;
                    break;
                }
                e = ne;
            }
            memcpy(e + n, buf, m * sizeof *buf);
            n += m;
        }
        j->counts[(size_t)y * j->w + x] = (uint8_t)(n - start);
    }
    /* rows are disjoint: no lock needed for the per-row slots; the shared counters are summed later */
    j->row_edges[y] = e;
    j->row_n[y] = e ? (uint32_t)n : 0;
    if (!e)
        j->oom = 1; /* benign race: only ever set to 1 */
    if (clipped)
        __atomic_fetch_add(&j->clipped, clipped, __ATOMIC_RELAXED);
}

/* the i-th row this shard owns */
static void path_row_shard(void *ctx, uint32_t i)
{
    path_job *j = ctx;
    path_row(ctx, j->shard + i * j->nshards);
}

int qtool_bake_path_chunk(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, const qtool_bake_path *p,
                         uint32_t steps, uint32_t nkeys, int threads, uint8_t **out, size_t *n, double stats[2])
{
    return qtool_bake_path_chunk_shard(s, w, h, kind, p, steps, nkeys, 0, 1, threads, out, n, stats);
}

/* the rows first, first + stride, ... (count of them) baked; the others stay empty */
static int path_chunk_rows(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, const qtool_bake_path *p,
                           uint32_t steps, uint32_t nkeys, uint32_t first, uint32_t stride, uint32_t count, int threads,
                           uint8_t **out, size_t *n, double stats[2]);

int qtool_bake_path_chunk_shard(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind,
                               const qtool_bake_path *p, uint32_t steps, uint32_t nkeys, uint32_t shard, uint32_t nshards,
                               int threads, uint8_t **out, size_t *n, double stats[2])
{
    if (nshards < 1 || shard >= nshards)
        return -1;
    uint32_t count = shard < h ? (h - shard + nshards - 1) / nshards : 0;
    return path_chunk_rows(s, w, h, kind, p, steps, nkeys, shard, nshards, count, threads, out, n, stats);
}

int qtool_bake_path_chunk_band(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind,
                              const qtool_bake_path *p, uint32_t steps, uint32_t nkeys, uint32_t y0, uint32_t y1,
                              int threads, uint8_t **out, size_t *n, double stats[2])
{
    if (y0 >= y1 || y1 > h)
        return -1;
    return path_chunk_rows(s, w, h, kind, p, steps, nkeys, y0, 1, y1 - y0, threads, out, n, stats);
}

static int path_chunk_rows(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, const qtool_bake_path *p,
                           uint32_t steps, uint32_t nkeys, uint32_t first, uint32_t stride, uint32_t count, int threads,
                           uint8_t **out, size_t *n, double stats[2])
{
    if (w < 1 || h < 1 || steps < 1 || steps > 65535 || nkeys < 2 || nkeys > QIBL_LIGHTPATH_MAX_KEYS)
        return -1;
    size_t np = (size_t)w * h;
    path_job j = {s, p, w, h, steps, kind, calloc(np, 1), calloc(h, sizeof(uint16_t *)), calloc(h, sizeof(uint32_t)), 0, 0,
                  first, stride};
    int rc = -1;
    if (!j.counts || !j.row_edges || !j.row_n)
        goto done;
    if (count) /* rows of other shards stay empty: counts 0, no edges */
        qtool_rt_parallel(threads, count, path_row_shard, &j, NULL);
    if (j.oom)
        goto done;
    uint64_t total = 0;
    for (uint32_t y = 0; y < h; ++y)
        total += j.row_n[y];
    if (total > QIBL_LIGHTPATH_MAX_EDGES)
        goto done;
    /* keys: uniform in t for a sun, the polyline's vertices (deduplicated in t) for a track */
    uint32_t kt[QIBL_LIGHTPATH_MAX_KEYS], nk = 0;
    if (p->kind == 0) {
        for (uint32_t i = 0; i < nkeys; ++i)
            kt[nk++] = (uint32_t)lrint(65535.0 * i / (nkeys - 1));
    } else {
        double cum = 0, tot = 0;
        for (int i = 1; i < p->npts; ++i)
            tot += sqrt(pow(p->pts[i][0] - p->pts[i - 1][0], 2) + pow(p->pts[i][1] - p->pts[i - 1][1], 2) +
                        pow(p->pts[i][2] - p->pts[i - 1][2], 2));
        kt[nk++] = 0;
        for (int i = 1; i < p->npts; ++i) {
            cum += sqrt(pow(p->pts[i][0] - p->pts[i - 1][0], 2) + pow(p->pts[i][1] - p->pts[i - 1][1], 2) +
                        pow(p->pts[i][2] - p->pts[i - 1][2], 2));
            uint32_t q = i == p->npts - 1 ? 65535u : (uint32_t)lrint(65535.0 * cum / tot);
            if (q > kt[nk - 1])
                kt[nk++] = q;
        }
        if (kt[nk - 1] != 65535u)
            kt[nk - 1] = 65535u;
    }
    int32_t kv[QIBL_LIGHTPATH_MAX_KEYS * 3];
    for (uint32_t i = 0; i < nk; ++i) {
        qtool_rt_light l;
        qtool_bake_path_light(p, kt[i] / 65535.0, &l);
        for (int c = 0; c < 3; ++c)
            kv[3 * i + (uint32_t)c] = (int32_t)lrint((p->kind == 0 ? l.dir[c] : l.pos[c]) * 65536.0);
    }
    uint16_t *all = malloc(sizeof(uint16_t) * (total ? total : 1));
    if (!all)
        goto done;
    size_t at = 0;
    for (uint32_t y = 0; y < h; ++y) {
        if (j.row_n[y])
            memcpy(all + at, j.row_edges[y], sizeof(uint16_t) * j.row_n[y]);
        at += j.row_n[y];
    }
    uint8_t *b = NULL;
    size_t size = 0;
    int e = qtool_bake_path_payload(w, h, (uint32_t)p->kind, nk, kt, kv, j.counts, all, (uint32_t)total, &b, &size);
    free(all);
    if (e != 0)
        goto done;
    *out = b, *n = size;
    if (stats)
        stats[0] = (double)total / (double)np, stats[1] = j.clipped;
    rc = 0;
done:
    for (uint32_t y = 0; j.row_edges && y < h; ++y)
        free(j.row_edges[y]);
    free(j.counts), free(j.row_edges), free(j.row_n);
    return rc;
}

int qtool_bake_path_payload(uint32_t w, uint32_t h, uint32_t kind, uint32_t nkeys, const uint32_t *kt,
                           const int32_t *kv, const uint8_t *counts, const uint16_t *edges, uint32_t nedges,
                           uint8_t **out, size_t *n)
{
    size_t np = (size_t)w * h;
    size_t size = QIBL_LIGHTPATH_HEADER + 16u * (size_t)nkeys + 4u * ((size_t)h + 1) + np + 2 * (size_t)nedges;
    uint8_t *b = malloc(size);
    if (!b)
        return -1;
    qtool_store_u32le(b, w), qtool_store_u32le(b + 4, h), qtool_store_u32le(b + 8, kind);
    qtool_store_u32le(b + 12, 0), qtool_store_u32le(b + 16, nkeys), qtool_store_u32le(b + 20, nedges);
    uint8_t *k = b + QIBL_LIGHTPATH_HEADER;
    for (uint32_t i = 0; i < nkeys; ++i) {
        qtool_store_u32le(k + 16 * (size_t)i, kt[i]);
        for (uint32_t c = 0; c < 3; ++c)
            qtool_store_u32le(k + 16 * (size_t)i + 4 + 4 * c, (uint32_t)kv[3 * (size_t)i + c]);
    }
    uint8_t *rows = k + 16 * (size_t)nkeys, *cnt = rows + 4 * ((size_t)h + 1), *ed = cnt + np;
    uint32_t at = 0;
    for (uint32_t y = 0; y < h; ++y) {
        qtool_store_u32le(rows + 4 * (size_t)y, at);
        for (uint32_t x = 0; x < w; ++x)
            at += counts[(size_t)y * w + x];
    }
    qtool_store_u32le(rows + 4 * (size_t)h, at);
    memcpy(cnt, counts, np);
    for (uint32_t i = 0; i < nedges; ++i)
        ed[2 * (size_t)i] = (uint8_t)edges[i], ed[2 * (size_t)i + 1] = (uint8_t)(edges[i] >> 8);
    *out = b, *n = size;
    return 0;
}

/* ---- relighting ---------------------------------------------------------------------------------- */

int qtool_bake_relight_path8(const uint8_t *asset, size_t n, const qtool_rt_light *l, uint32_t path, uint32_t tq,
                            uint32_t radius, const qibl_shlight_t *sky, uint8_t *rgb8, float *lin, double *ms,
                            qibl_status_t *status)
{
    return qtool_bake_relight_path8_gonio(asset, n, l, NULL, path, tq, radius, sky, rgb8, lin, ms, status);
}

int qtool_bake_relight_path8_gonio(const uint8_t *asset, size_t n, const qtool_rt_light *l, const qibl_gonio_t *gonio,
                                  uint32_t path, uint32_t tq, uint32_t radius, const qibl_shlight_t *sky,
                                  uint8_t *rgb8, float *lin, double *ms, qibl_status_t *status)
{
    qibl_asset_t a;
    qibl_shmaps_t mu, ms_sh;
    qibl_pmap_t pm;
    qibl_ylut_t lut;
    qibl_lightpath_t lp;
    int use_lut = 0;
    qibl_status_t st = qtool_asset_open(&a, asset, n);
    if (st == QIBL_OK)
        st = qibl_asset_shmaps_unshadowed(&a, &mu);
    if (st == QIBL_OK)
        st = qibl_asset_shmaps(&a, &ms_sh);
    if (st == QIBL_OK)
        st = qibl_lightpath_from_asset(&a, path, &lp);
    if (st == QIBL_OK && l->point) {
        st = qibl_asset_pmap(&a, &pm);
        use_lut = qibl_asset_ylut(&a, &lut) == QIBL_OK && lut.k >= mu.k;
    }
    uint32_t w = st == QIBL_OK ? mu.width : 0, h = st == QIBL_OK ? mu.height : 0;
    size_t wsn = st != QIBL_OK ? 0 : qibl_shmap_point_workspace_size(mu.k > ms_sh.k ? mu.k : ms_sh.k, w);
    size_t wsd = qibl_shmap_span_workspace_size(w);
    if (wsd > wsn)
        wsn = wsd;
    qtool_bake_frame f; /* scratch: the light's own rows before the path's shading */
    if (qtool_bake_frame_alloc(st, w, h, 1, sizeof(int32_t) * 3 * w, wsn, &f, status) != 0)
        return -1;
    uint8_t *pix = f.pix;
    int32_t *row = f.row, *prow = f.scratch;
    void *ws = f.ws;
    qibl_fb_desc_t fb = qtool_bake_fb_srgb(pix, w, h);
    double t0 = qtool_bake_now();
    qibl_shmap_weights_t wt, wsky;
    qibl_shmap_point_t pt;
    const qibl_pointlight_t pl = qtool_bake_pointlight(l, QIBL_LUT_BILINEAR);
    if (!l->point) {
        qibl_shlight_t sl;
        st = qtool_bake_dir_shlight(l, mu.k, &sl);
        if (st == QIBL_OK)
            st = qibl_shmap_weights(&mu, &sl, &wt);
    } else {
        st = qibl_shmap_point_prepare(&mu, &pm, use_lut ? &lut : NULL, &pl, &pt);
    }
    if (st == QIBL_OK && sky)
        st = qibl_shmap_weights(&ms_sh, sky, &wsky);
    for (uint32_t y = 0; st == QIBL_OK && y < h; ++y) {
        if (sky)
            st = qibl_shmap_relight_span(&ms_sh, &wsky, 0, y, w, row, ws, wsn);
        if (st == QIBL_OK)
            st = l->point ? qibl_shmap_point_span(&pt, 0, y, w, prow, ws, wsn)
                          : qibl_shmap_relight_span(&mu, &wt, 0, y, w, prow, ws, wsn);
        /* a goniometric lamp: its intensity toward each pixel's point, before the visibility */
        if (st == QIBL_OK && l->point && gonio)
            st = qibl_gonio_scale_span(gonio, &pm, pl.pos, 0, y, w, prow);
        if (st == QIBL_OK)
            st = qibl_lightpath_shade_span(&lp, tq, radius, 0, y, w, prow, row, sky != NULL);
        if (st == QIBL_OK)
            st = qtool_bake_frame_row(&fb, y, w, row, lin);
    }
    return qtool_bake_frame_finish(&f, st, t0, ms, w, h, rgb8, status);
}

/* ---- sky ----------------------------------------------------------------------------------------- */

/* the demo's sky: brighter towards the zenith, nothing below the horizon */
static double sky_radiance(const double w[3])
{
    return w[2] > 0 ? 0.3 + 0.7 * w[2] : 0;
}

void qtool_bake_sky_dir(uint32_t j, uint32_t n, double d[3])
{
    /* upper-hemisphere Fibonacci set, turned by an irrational offset: not the bake's directions */
    double z = 1.0 - (j + 0.5) / n, r = sqrt(fmax(0.0, 1 - z * z));
    double phi = fmod(j * (QTOOL_PI * (3.0 - sqrt(5.0))) + 0.7236, 2 * QTOOL_PI);
    d[0] = r * cos(phi), d[1] = r * sin(phi), d[2] = z;
}

typedef struct {
    const qtool_rt_scene *s;
    uint32_t w, h, ndirs;
    qtool_pano_kind kind;
    const double *rgb;
    double *half[2];
} sky_job;

static void sky_row(void *ctx, uint32_t y)
{
    const sky_job *j = ctx;
    double wgt = 2 * QTOOL_PI / (j->ndirs / 2); /* each half is an estimate on its own */
    for (uint32_t x = 0; x < j->w; ++x) {
        double d[3], acc[2][3] = {{0, 0, 0}, {0, 0, 0}};
        qtool_rt_hit hit;
        qtool_rt_pixel_ray(j->s, j->w, j->h, j->kind, x, y, d);
        qtool_rt_primary(j->s, d, &hit);
        for (uint32_t l = 0; hit.hit && l < j->ndirs; ++l) {
            double wv[3], df, gl;
            qtool_bake_sky_dir(l, j->ndirs, wv);
            if (!qtool_rt_response(j->s, &hit, wv, 1e30, &df, &gl))
                continue;
            double L = sky_radiance(wv) * wgt;
            for (int c = 0; c < 3; ++c)
                acc[l & 1][c] += L * j->rgb[c] * (hit.albedo[c] * df + hit.m->ks * gl);
        }
        for (int hh = 0; hh < 2; ++hh)
            for (int c = 0; c < 3; ++c)
                j->half[hh][3 * ((size_t)y * j->w + x) + (size_t)c] = acc[hh][c];
    }
}

int qtool_bake_sky_truth(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, const double rgb[3],
                        uint32_t ndirs, int threads, double *half_a, double *half_b)
{
    if (ndirs < 2 || ndirs % 2)
        return -1;
    sky_job j = {s, w, h, ndirs, kind, rgb, {half_a, half_b}};
    return qtool_rt_parallel(threads, h, sky_row, &j, NULL);
}

void qtool_bake_sky_sh(const double rgb[3], uint32_t k, qibl_shlight_t *out)
{
    /* L_i = integral of L(w) Y_i(w) over the sphere, by the midpoint rule on a fine latitude-longitude grid */
    enum { NT = 256, NP = 512 };
    if (qibl_shlight_init(out, k) != QIBL_OK)
        return; /* k outside 1..25: out untouched (and c below never overrun) */
    double c[25] = {0};
    for (int a = 0; a < NT / 2; ++a) { /* upper hemisphere only: the sky is 0 below */
        double th = QTOOL_PI * (a + 0.5) / NT, dw = (QTOOL_PI / NT) * (2 * QTOOL_PI / NP) * sin(th);
        for (int b = 0; b < NP; ++b) {
            double ph = 2 * QTOOL_PI * (b + 0.5) / NP, wv[3] = {sin(th) * cos(ph), sin(th) * sin(ph), cos(th)}, y[25];
            qtool_ref_sh_eval(wv[0], wv[1], wv[2], 5, y);
            double L = sky_radiance(wv) * dw;
            for (uint32_t i = 0; i < k; ++i)
                c[i] += L * y[i];
        }
    }
    for (int ch = 0; ch < 3; ++ch)
        for (uint32_t i = 0; i < k; ++i)
            out->c[ch][i] = (qibl_q16_t)lrint(c[i] * rgb[ch] * 65536.0);
}

int qtool_bake_relight_env8(const uint8_t *asset, size_t n, const qibl_shlight_t *env, uint8_t *rgb8, double *ms,
                           qibl_status_t *status)
{
    qibl_asset_t a;
    qibl_shmaps_t m;
    qibl_shmap_weights_t wt;
    qibl_status_t st = qtool_asset_open(&a, asset, n);
    if (st == QIBL_OK)
        st = qibl_asset_shmaps(&a, &m);
    if (st == QIBL_OK)
        st = qibl_shmap_weights(&m, env, &wt);
    uint32_t w = st == QIBL_OK ? m.width : 0, h = st == QIBL_OK ? m.height : 0;
    qtool_bake_frame f;
    if (qtool_bake_frame_alloc(st, w, h, 1, 0, qibl_shmap_span_workspace_size(w), &f, status) != 0)
        return -1;
    qibl_fb_desc_t fb = qtool_bake_fb_srgb(f.pix, w, h);
    double t0 = qtool_bake_now();
    for (uint32_t y = 0; st == QIBL_OK && y < h; ++y) {
        st = qibl_shmap_relight_span(&m, &wt, 0, y, w, f.row, f.ws, f.wsn);
        if (st == QIBL_OK)
            st = qibl_soft_fb_write_row(&fb, 0, y, w, f.row);
    }
    return qtool_bake_frame_finish(&f, st, t0, ms, w, h, rgb8, status);
}

/* ---- lamp occlusion (LOCC) -------------------------------------------------------------------------- */

typedef struct {
    const qtool_rt_scene *s;
    uint32_t w, h, n;
    qtool_pano_kind kind;
    const double *box;
    uint8_t *out;
    uint32_t shard, nshards;
} occ_job;

/* the i-th of n lamp positions in the box: a 3-D Halton set (bases 2, 3, 5), the same for every pixel */
static double halton(uint32_t i, uint32_t b)
{
    double f = 1, r = 0;
    for (; i > 0; i /= b)
        f /= b, r += f * (double)(i % b);
    return r;
}

static void occ_row(void *ctx, uint32_t y)
{
    const occ_job *j = ctx;
    for (uint32_t x = 0; x < j->w; ++x) {
        double d[3], sw = 0, sv = 0;
        qtool_rt_hit h;
        qtool_rt_pixel_ray(j->s, j->w, j->h, j->kind, x, y, d);
        qtool_rt_primary(j->s, d, &h);
        for (uint32_t i = 0; h.hit && i < j->n; ++i) {
            double p[3] = {halton(i + 1, 2), halton(i + 1, 3), halton(i + 1, 5)}, w[3], len = 0;
            for (int c = 0; c < 3; ++c) {
                p[c] = j->box[c] + p[c] * (j->box[3 + c] - j->box[c]);
                w[c] = p[c] - h.p[c], len += w[c] * w[c];
            }
            len = sqrt(len);
            if (len < 1.0 / 256)
                continue;
            for (int c = 0; c < 3; ++c)
                w[c] /= len;
            double df, gl;
            /* weight: what the lamp would add unshadowed (Lambert x C0/|L|), so a(p) is the share of
             * the pixel's expected light that reaches it */
            if (!qtool_rt_response(j->s, &h, w, 0, &df, &gl) || df <= 0)
                continue;
            double wt = df / len;
            sw += wt;
            if (!qtool_rt_occluded(j->s, &h, w, len))
                sv += wt;
        }
        j->out[(size_t)y * j->w + x] = sw > 0 ? (uint8_t)lrint(255 * sv / sw) : 255;
    }
}

static void occ_row_shard(void *ctx, uint32_t i)
{
    const occ_job *j = ctx;
    occ_row(ctx, j->shard + i * j->nshards);
}

int qtool_bake_lamp_occlusion(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, const double box[6],
                             uint32_t nsamples, int threads, uint8_t *out)
{
    return qtool_bake_lamp_occlusion_shard(s, w, h, kind, box, nsamples, 0, 1, threads, out);
}

static int occlusion_rows(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, const double box[6],
                          uint32_t nsamples, uint32_t first, uint32_t stride, uint32_t count, int threads, uint8_t *out)
{
    if (w < 1 || h < 1 || nsamples < 1 || !box || !out)
        return -1;
    occ_job j = {s, w, h, nsamples, kind, box, out, first, stride};
    memset(out, 0, (size_t)w * h); /* rows of other shards: 0 */
    if (count == 0)
        return 0;
    return qtool_rt_parallel(threads, count, occ_row_shard, &j, NULL);
}

int qtool_bake_lamp_occlusion_shard(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind,
                                   const double box[6], uint32_t nsamples, uint32_t shard, uint32_t nshards, int threads,
                                   uint8_t *out)
{
    if (nshards < 1 || shard >= nshards)
        return -1;
    uint32_t count = shard < h ? (h - shard + nshards - 1) / nshards : 0;
    return occlusion_rows(s, w, h, kind, box, nsamples, shard, nshards, count, threads, out);
}

int qtool_bake_lamp_occlusion_band(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind,
                                  const double box[6], uint32_t nsamples, uint32_t y0, uint32_t y1, int threads,
                                  uint8_t *out)
{
    if (y0 >= y1 || y1 > h)
        return -1;
    return occlusion_rows(s, w, h, kind, box, nsamples, y0, 1, y1 - y0, threads, out);
}

int qtool_bake_locc_payload(uint32_t w, uint32_t h, const uint8_t *values, uint8_t **out, size_t *n)
{
    size_t np = (size_t)w * h;
    uint8_t *b = malloc(QIBL_LAMPOCC_HEADER + np);
    if (!b)
        return -1;
    qtool_store_u32le(b, w), qtool_store_u32le(b + 4, h);
    memcpy(b + QIBL_LAMPOCC_HEADER, values, np);
    *out = b, *n = QIBL_LAMPOCC_HEADER + np;
    return 0;
}

int qtool_bake_asset_add(const uint8_t *asset, size_t n, uint32_t type, const uint8_t *payload, size_t size,
                        uint8_t **out, size_t *outn)
{
    qibl_asset_t a;
    qtool_asset_builder b;
    uint32_t seen[QIBL_ASSET_MAX_CHUNKS], types[QIBL_ASSET_MAX_CHUNKS];
    if (qtool_asset_open(&a, asset, n) != QIBL_OK)
        return -1;
    qtool_asset_builder_init(&b);
    int rc = -1;
    /* every chunk in table order (the n-th of its type), then the new one */
    for (uint32_t i = 0; i < a.chunk_count; ++i) {
        qibl_chunk_t c;
        uint32_t t = qibl_load_u32le(asset + QIBL_ASSET_HEADER_SIZE + QIBL_ASSET_ENTRY_SIZE * i), nth = 0;
        types[i] = t;
        for (uint32_t j = 0; j < i; ++j)
            nth += types[j] == t;
        seen[i] = nth;
        if (qibl_asset_find_nth(&a, t, seen[i], &c) != QIBL_OK || qtool_asset_builder_add(&b, t, c.data, c.size) != 0)
            goto done;
    }
    if (qtool_asset_builder_add(&b, type, payload, size) != 0 || qtool_asset_serialize(&b, out, outn) != 0)
        goto done;
    rc = 0;
done:
    qtool_asset_builder_free(&b);
    return rc;
}
