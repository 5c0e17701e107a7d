/*
 * lightpath.c - per-pixel visibility along a light path (LPTH chunks): validation, lookup, shading.
 *
 * Invariants: every read is a byte load; sizes are summed in 64 bits before any payload byte past
 * the header is touched; the row index is checked against the counts and every edge index against
 * nedges during validation, so the span functions need no checks beyond their arguments. No
 * division by a variable in the per-pixel code (Cortex-M0 has no divide): the soft window's
 * reciprocal is formed once per span with qibl_udiv_u64.
 */
#include "qibl/lightpath.h"
#include "qibli.h"

#if QIBL_USE_LIGHTPATH /* config.h: needs QIBL_USE_SHMAP (path lights are relit through the SH maps) */

static uint32_t load_u16(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8;
}

/* the keys: count, strictly increasing t from 0 to 65535, no zero direction */
static qibl_status_t check_keys(const uint8_t *k, uint32_t nkeys, uint32_t kind)
{
    uint32_t prev = 0;
    for (uint32_t i = 0; i < nkeys; ++i) {
        const uint8_t *e = k + 16u * i;
        uint32_t t = qibl_load_u32le(e);
        if (i == 0u ? t != 0u : t <= prev)
            return QIBL_E_LIGHTPATH_KEYS;
        prev = t;
        if (kind == QIBL_LIGHTPATH_DIRECTIONS && qibl_load_u32le(e + 4) == 0u && qibl_load_u32le(e + 8) == 0u &&
            qibl_load_u32le(e + 12) == 0u)
            return QIBL_E_LIGHTPATH_KEYS;
    }
    return prev == QIBL_LIGHTPATH_T_MAX ? QIBL_OK : QIBL_E_LIGHTPATH_KEYS;
}

qibl_status_t qibl_lightpath_parse(const uint8_t *data, size_t size, qibl_lightpath_t *out)
{
    if (data == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    if (size < QIBL_LIGHTPATH_HEADER)
        return QIBL_E_LIGHTPATH_SIZE;
    uint32_t w = qibl_load_u32le(data), h = qibl_load_u32le(data + 4), kind = qibl_load_u32le(data + 8);
    uint32_t nkeys = qibl_load_u32le(data + 16), nedges = qibl_load_u32le(data + 20);
    if (w - 1u >= QIBL_ASSET_MAX_DIM || h - 1u >= QIBL_ASSET_MAX_DIM || w * h > QIBL_ASSET_MAX_PIXELS)
        return QIBL_E_LIGHTPATH_DIMENSIONS;
    if (kind > QIBL_LIGHTPATH_POSITIONS || qibl_load_u32le(data + 12) != 0u)
        return QIBL_E_LIGHTPATH_KIND;
    if (nkeys < 2u || nkeys > QIBL_LIGHTPATH_MAX_KEYS)
        return QIBL_E_LIGHTPATH_KEYS;
    if (nedges > QIBL_LIGHTPATH_MAX_EDGES)
        return QIBL_E_LIGHTPATH_SIZE;
    /* every term is below 2^29, so the 64-bit sum is exact */
    uint64_t need = (uint64_t)QIBL_LIGHTPATH_HEADER + 16u * nkeys + 4u * ((uint64_t)h + 1u) + w * h + 2u * (uint64_t)nedges;
    if (need != (uint64_t)size)
        return QIBL_E_LIGHTPATH_SIZE;
    const uint8_t *keys = data + QIBL_LIGHTPATH_HEADER;
    const uint8_t *rows = keys + 16u * nkeys;
    const uint8_t *counts = rows + 4u * (h + 1u);
    const uint8_t *edges = counts + (size_t)w * h;
    qibl_status_t st = check_keys(keys, nkeys, kind);
    if (st != QIBL_OK)
        return st;
    /* rows against counts; row_start values stay <= nedges, so the sums below cannot wrap */
    if (qibl_load_u32le(rows) != 0u || qibl_load_u32le(rows + 4u * h) != nedges)
        return QIBL_E_LIGHTPATH_ROWS;
    uint32_t at = 0;
    for (uint32_t y = 0; y < h; ++y) {
        const uint8_t *c = counts + (size_t)y * w;
        for (uint32_t x = 0; x < w; ++x) {
            uint32_t n = c[x];
            if (n > nedges - at)
                return QIBL_E_LIGHTPATH_ROWS;
            at += n;
        }
        if (qibl_load_u32le(rows + 4u * (y + 1u)) != at)
            return QIBL_E_LIGHTPATH_ROWS;
    }
    /* edges strictly increasing within each pixel */
    at = 0;
    for (size_t i = 0; i < (size_t)w * h; ++i) {
        uint32_t n = counts[i], prev = 0;
        for (uint32_t j = 0; j < n; ++j) {
            uint32_t e = load_u16(edges + 2u * (at + j));
            if (j > 0u && e <= prev)
                return QIBL_E_LIGHTPATH_EDGES;
            prev = e;
        }
        at += n;
    }
    out->width = w, out->height = h, out->kind = kind, out->nkeys = nkeys, out->nedges = nedges;
    out->keys = keys, out->rows = rows, out->counts = counts, out->edges = edges;
    return QIBL_OK;
}

#if QIBL_USE_ASSET /* the asset-level helpers need the container reader; parsing a chunk does not */
uint32_t qibl_lightpath_count(const qibl_asset_t *a)
{
    uint32_t n = 0;
    qibl_chunk_t c;
    while (a != 0 && qibl_asset_find_nth(a, QIBL_CHUNK_LPTH, n, &c) == QIBL_OK)
        ++n;
    return n;
}

qibl_status_t qibl_lightpath_from_asset(const qibl_asset_t *a, uint32_t index, qibl_lightpath_t *out)
{
    qibl_chunk_t c;
    qibl_shmaps_t m;
    if (a == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    qibl_status_t st = qibl_asset_find_nth(a, QIBL_CHUNK_LPTH, index, &c);
    if (st == QIBL_OK)
        st = qibl_asset_shmaps(a, &m);
    if (st != QIBL_OK)
        return st;
    qibl_lightpath_t p;
    st = qibl_lightpath_parse(c.data, c.size, &p);
    if (st != QIBL_OK)
        return st;
    if (p.width != m.width || p.height != m.height)
        return QIBL_E_LIGHTPATH_DIMENSIONS;
    /* field by field: a struct copy may become a memcpy call, which freestanding targets lack */
    out->width = p.width, out->height = p.height, out->kind = p.kind, out->nkeys = p.nkeys, out->nedges = p.nedges;
    out->keys = p.keys, out->rows = p.rows, out->counts = p.counts, out->edges = p.edges;
    return QIBL_OK;
}
#endif

qibl_status_t qibl_lightpath_at(const qibl_lightpath_t *p, uint32_t t, qibl_q16_t out[3])
{
    if (p == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    if (t > QIBL_LIGHTPATH_T_MAX)
        return QIBL_E_LIGHTPATH_PARAM;
    uint32_t i = 0;
    while (i + 2u < p->nkeys && qibl_load_u32le(p->keys + 16u * (i + 1u)) <= t)
        ++i;
    const uint8_t *a = p->keys + 16u * i, *b = a + 16;
    uint32_t ta = qibl_load_u32le(a), tb = qibl_load_u32le(b);
    uint32_t num = t - ta, den = tb - ta; /* keys validated: ta <= t <= tb, tb > ta */
    for (unsigned c = 0; c < 3u; ++c) {
        int32_t va = qibl_load_s32le(a + 4u + 4u * c), vb = qibl_load_s32le(b + 4u + 4u * c);
        /* va + (vb - va) num / den, rounded half away from zero: |vb - va| < 2^32, num < 2^16, so the
         * product fits 48 bits and the result lies between va and vb */
        int64_t d = (int64_t)vb - va;
        uint64_t mag = qibl_mul_u32_u64((uint32_t)(d < 0 ? -d : d), num);
        int64_t q = (int64_t)qibl_udiv_u64(mag + (den >> 1), den, 0);
        out[c] = qibl_sat_s32((int64_t)va + (d < 0 ? -q : q));
    }
    return QIBL_OK;
}

/* first edge index of pixel x0 of row y */
static uint32_t first_edge(const qibl_lightpath_t *p, uint32_t x0, uint32_t y)
{
    uint32_t at = qibl_load_u32le(p->rows + 4u * y);
    const uint8_t *c = p->counts + (size_t)y * p->width;
    for (uint32_t x = 0; x < x0; ++x)
        at += c[x];
    return at;
}

/* lit length of [a, b) (a < b, may extend past 0..65535) for one pixel's n edges at e */
static uint32_t lit_measure(const uint8_t *e, uint32_t n, int32_t a, int32_t b)
{
    uint32_t lit = 0;
    /* segment j runs from edge j-1 (or -inf) to edge j (or +inf); it is lit when j is odd. An edge
     * at 0 starts a lit segment that extends left of the path, as V keeps its end values. */
    for (uint32_t j = 1; j <= n; j += 2u) {
        uint32_t e0 = load_u16(e + 2u * (j - 1u));
        int32_t s = e0 == 0u ? INT32_MIN : (int32_t)e0;
        int32_t t = j < n ? (int32_t)load_u16(e + 2u * j) : INT32_MAX;
        int32_t lo = s > a ? s : a, hi = t < b ? t : b;
        if (hi > lo)
            lit += (uint32_t)(hi - lo);
    }
    return lit;
}

static qibl_status_t span_args(const qibl_lightpath_t *p, uint32_t t, uint32_t radius, uint32_t x0, uint32_t y,
                               uint32_t n)
{
    if (p == 0)
        return QIBL_E_NULL_POINTER;
    if (t > QIBL_LIGHTPATH_T_MAX || radius > QIBL_LIGHTPATH_MAX_RADIUS)
        return QIBL_E_LIGHTPATH_PARAM;
    if (y >= p->height || x0 > p->width || n > p->width - x0)
        return QIBL_E_LIGHTPATH_BOUNDS;
    return QIBL_OK;
}

/* visibilities of n pixels whose counts start at c and edges at index at (arguments checked);
 * returns the edge index after them, so a caller walking a row in chunks never rescans it */
static uint32_t visibility(const qibl_lightpath_t *p, uint32_t t, uint32_t radius, uint32_t recip, uint32_t at,
                           const uint8_t *c, uint32_t n, uint32_t *vis)
{
    for (uint32_t i = 0; i < n; ++i) {
        uint32_t m = c[i];
        const uint8_t *e = p->edges + 2u * at;
        if (radius == 0u) {
            uint32_t k = 0;
            while (k < m && load_u16(e + 2u * k) <= t)
                ++k;
            vis[i] = (k & 1u) ? 65536u : 0u;
        } else {
            uint32_t lit = lit_measure(e, m, (int32_t)t - (int32_t)radius, (int32_t)(t + radius));
            uint64_t v = qibl_shr_u64(qibl_mul_u32_u64(lit, recip) + 32768u, 16);
            vis[i] = v > 65536u ? 65536u : (uint32_t)v;
        }
        at += m;
    }
    return at;
}

/* 2^32 / (2 radius) (< 2^31), 0 for a hard light */
static uint32_t window_recip(uint32_t radius)
{
    return radius > 0u ? (uint32_t)qibl_udiv_u64((uint64_t)1u << 32, 2u * radius, 0) : 0u;
}

qibl_status_t qibl_lightpath_visibility_span(const qibl_lightpath_t *p, uint32_t t, uint32_t radius, uint32_t x0,
                                             uint32_t y, uint32_t n, uint32_t *vis)
{
    qibl_status_t st = span_args(p, t, radius, x0, y, n);
    if (st != QIBL_OK)
        return st;
    if (vis == 0)
        return QIBL_E_NULL_POINTER;
    (void)visibility(p, t, radius, window_recip(radius), first_edge(p, x0, y), p->counts + (size_t)y * p->width + x0,
                     n, vis);
    return QIBL_OK;
}

qibl_status_t qibl_lightpath_shade_span(const qibl_lightpath_t *p, uint32_t t, uint32_t radius, uint32_t x0,
                                        uint32_t y, uint32_t n, const int32_t *light, int32_t *out, bool accumulate)
{
    qibl_status_t st = span_args(p, t, radius, x0, y, n);
    if (st != QIBL_OK)
        return st;
    if (light == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    if (radius == 0u) {
        /* the common case in one pass: a hard light (light may be out when not accumulating) */
        uint32_t at = first_edge(p, x0, y);
        const uint8_t *cnt = p->counts + (size_t)y * p->width + x0;
        for (uint32_t i = 0; i < n; ++i) {
            uint32_t m = cnt[i], k = 0;
            const uint8_t *e = p->edges + 2u * at;
            while (k < m && load_u16(e + 2u * k) <= t)
                ++k;
            at += m;
            bool lit = (k & 1u) != 0u;
            size_t o = 3u * (size_t)i;
            if (!accumulate) {
                out[o] = lit ? light[o] : 0;
                out[o + 1u] = lit ? light[o + 1u] : 0;
                out[o + 2u] = lit ? light[o + 2u] : 0;
            } else if (lit) {
                out[o] = qibl_add_sat_s32(out[o], light[o]);
                out[o + 1u] = qibl_add_sat_s32(out[o + 1u], light[o + 1u]);
                out[o + 2u] = qibl_add_sat_s32(out[o + 2u], light[o + 2u]);
            }
        }
        return QIBL_OK;
    }
    /* visibility in chunks on the stack: no workspace argument, no heap */
    enum { CHUNK = 64 };
    uint32_t vis[CHUNK], recip = window_recip(radius), at = first_edge(p, x0, y);
    const uint8_t *cnt = p->counts + (size_t)y * p->width + x0;
    for (uint32_t done = 0; done < n;) {
        uint32_t m = n - done < CHUNK ? n - done : (uint32_t)CHUNK; /* one type in both arms (C++: enum vs uint32_t) */
        at = visibility(p, t, radius, recip, at, cnt + done, m, vis);
        for (uint32_t i = 0; i < m; ++i) {
            size_t o = 3u * (size_t)(done + i);
            uint32_t v = vis[i];
            /* fully lit or dark (every pixel of a hard light, most of a soft one): no multiply */
            uint32_t mask = v == 65536u ? 0xFFFFFFFFu : 0u;
            for (unsigned c = 0; c < 3u; ++c) {
                int32_t l = light[o + c], r;
                if (v == 0u || v == 65536u)
                    r = mask ? l : 0;
                else
                    r = qibl_rshr_s64(qibl_mul_s32_s64(l, (int32_t)v), 16);
                out[o + c] = accumulate ? qibl_add_sat_s32(out[o + c], r) : r;
            }
        }
        done += m;
    }
    return QIBL_OK;
}

/* ---- lamp occlusion (LOCC) ---- */

qibl_status_t qibl_lightpath_occl_parse(const uint8_t *data, size_t size, qibl_lampocc_t *out)
{
    if (data == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    if (size < QIBL_LAMPOCC_HEADER)
        return QIBL_E_LIGHTPATH_SIZE;
    uint32_t w = qibl_load_u32le(data), h = qibl_load_u32le(data + 4);
    if (w - 1u >= QIBL_ASSET_MAX_DIM || h - 1u >= QIBL_ASSET_MAX_DIM || w * h > QIBL_ASSET_MAX_PIXELS)
        return QIBL_E_LIGHTPATH_DIMENSIONS;
    if ((uint64_t)QIBL_LAMPOCC_HEADER + (uint64_t)(w * h) != (uint64_t)size) /* w h <= 2^26 here */
        return QIBL_E_LIGHTPATH_SIZE;
    out->width = w, out->height = h, out->values = data + QIBL_LAMPOCC_HEADER;
    return QIBL_OK;
}

#if QIBL_USE_ASSET
qibl_status_t qibl_lightpath_occl_from_asset(const qibl_asset_t *a, qibl_lampocc_t *out)
{
    qibl_chunk_t c;
    qibl_shmaps_t m;
    qibl_lampocc_t o;
    if (a == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    qibl_status_t st = qibli_asset_sole_chunk(a, QIBL_CHUNK_LOCC, &c, &m);
    if (st == QIBL_OK)
        st = qibl_lightpath_occl_parse(c.data, c.size, &o);
    if (st != QIBL_OK)
        return st;
    if (o.width != m.width || o.height != m.height)
        return QIBL_E_LIGHTPATH_DIMENSIONS;
    out->width = o.width, out->height = o.height, out->values = o.values;
    return QIBL_OK;
}
#endif

qibl_status_t qibl_lightpath_occl_span(const qibl_lampocc_t *o, uint32_t x0, uint32_t y, uint32_t n, int32_t *io)
{
    if (o == 0 || io == 0)
        return QIBL_E_NULL_POINTER;
    if (y >= o->height || x0 > o->width || n > o->width - x0)
        return QIBL_E_LIGHTPATH_BOUNDS;
    const uint8_t *v = o->values + (size_t)y * o->width + x0;
    for (uint32_t i = 0; i < n; ++i) {
        /* a / 255 as f / 2^16 without a divide: f = 257 a + a / 128 maps 0 -> 0 and 255 -> 65536 */
        uint32_t a = v[i], f = 257u * a + (a >> 7);
        if (f == 65536u)
            continue;
        for (unsigned c = 0; c < 3u; ++c) {
            size_t k = 3u * (size_t)i + c;
            io[k] = qibl_rshr_s64(qibl_mul_s32_s64(io[k], (int32_t)f), 16);
        }
    }
    return QIBL_OK;
}

#else
typedef int qibl_lightpath_disabled_t; /* ISO C forbids an empty translation unit */
#endif /* QIBL_USE_LIGHTPATH */
