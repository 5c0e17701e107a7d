/*
 * lightpath_test.c - light paths (qibl/lightpath.h): LPTH validation (every named status, every
 * truncation, random corruptions never read out of bounds), hard and soft visibility against a
 * double-precision reference, shading and accumulation, key interpolation, assets holding SHMU and
 * several LPTH chunks; the bake's visibility edges against brute-force sampling on a tiny scene.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdlib.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "bake/bake.h"
#include "bake/path.h"
#include "golden/check.h"
#include "io/asset_write.h"
#include "qibl/lightpath.h"
#include "render/rt.h"
#include "testutil.h"

/* ---- a random valid path ------------------------------------------------------------------------ */

typedef struct {
    uint32_t w, h, kind, nkeys, nedges;
    uint32_t kt[8];
    int32_t kv[24];
    uint8_t *counts;
    uint16_t *edges;
    uint8_t *buf;
    size_t n;
} tpath;

static void tpath_make(tpath *p, uint32_t w, uint32_t h, uint32_t kind, uint64_t seed)
{
    tu_rng r = {seed};
    memset(p, 0, sizeof *p);
    p->w = w, p->h = h, p->kind = kind, p->nkeys = 2 + (uint32_t)(tu_next(&r) % 7);
    for (uint32_t i = 0; i < p->nkeys; ++i) {
        p->kt[i] = i == 0 ? 0 : i == p->nkeys - 1 ? 65535u : (uint32_t)(65535.0 * i / (p->nkeys - 1)) - (uint32_t)(tu_next(&r) % 100);
        for (int c = 0; c < 3; ++c)
            p->kv[3 * i + (uint32_t)c] = (int32_t)(tu_s32(&r) >> 4) | 1; /* non-zero */
    }
    p->counts = malloc((size_t)w * h);
    p->edges = malloc((size_t)w * h * 8 * sizeof(uint16_t));
    for (size_t i = 0; i < (size_t)w * h; ++i) {
        uint32_t c = (uint32_t)(tu_next(&r) % 7), last = 0;
        if (tu_next(&r) % 5 == 0) /* some pixels lit from the start */
            p->edges[p->nedges++] = 0, c = c ? c - 1 : 0, last = 0, p->counts[i] = 1;
        else
            p->counts[i] = 0;
        for (uint32_t j = 0; j < c; ++j) {
            uint32_t room = 65535u - last;
            if (room < 2)
                break;
            last += 1 + (uint32_t)(tu_next(&r) % (room / (c - j) > 1 ? room / (c - j) : 1));
            if (last > 65535u)
                break;
            p->edges[p->nedges++] = (uint16_t)last;
            p->counts[i]++;
        }
    }
    assert_int_equal(qtool_bake_path_payload(w, h, kind, p->nkeys, p->kt, p->kv, p->counts, p->edges, p->nedges,
                                            &p->buf, &p->n), 0);
}

static void tpath_free(tpath *p)
{
    free(p->counts), free(p->edges), free(p->buf);
}

/* reference visibility of pixel i: hard, or the lit fraction of [t - r, t + r) with end values kept */
static double ref_vis(const tpath *p, size_t i, uint32_t t, uint32_t r)
{
    size_t at = 0;
    for (size_t q = 0; q < i; ++q)
        at += p->counts[q];
    const uint16_t *e = p->edges + at;
    uint32_t n = p->counts[i];
    if (r == 0) {
        uint32_t k = 0;
        while (k < n && e[k] <= t)
            ++k;
        return k & 1 ? 1.0 : 0.0;
    }
    double lit = 0;
    for (long u = (long)t - (long)r; u < (long)t + (long)r; ++u) {
        long uc = u < 0 ? 0 : u > 65535 ? 65535 : u;
        uint32_t k = 0;
        while (k < n && e[k] <= uc)
            ++k;
        /* left of 0 the value at 0 holds only if an edge sits at 0; a pixel dark at 0 stays dark */
        lit += k & 1;
    }
    return lit / (2.0 * r);
}

static void test_parse_and_visibility(void **state)
{
    (void)state;
    for (uint64_t seed = 1; seed <= 6; ++seed) {
        tpath p;
        tpath_make(&p, 13, 5, (uint32_t)(seed & 1), seed);
        qibl_lightpath_t lp;
        assert_int_equal(qibl_lightpath_parse(p.buf, p.n, &lp), QIBL_OK);
        assert_int_equal(lp.width, 13);
        assert_int_equal(lp.nedges, p.nedges);
        tu_rng r = {seed * 77};
        for (int trial = 0; trial < 40; ++trial) {
            uint32_t t = trial < 3 ? (trial == 0 ? 0u : trial == 1 ? 65535u : p.edges[0]) : tu_u32(&r) & 65535u;
            uint32_t rad = trial % 3 == 0 ? 0u : trial == 5 ? 32767u : 1u + tu_u32(&r) % (trial % 3 == 1 ? 50u : 5000u);
            uint32_t y = tu_u32(&r) % 5, x0 = tu_u32(&r) % 13, n = 13 - x0;
            uint32_t vis[14];
            vis[n] = 0xDEADBEEFu;
            assert_int_equal(qibl_lightpath_visibility_span(&lp, t, rad, x0, y, n, vis), QIBL_OK);
            assert_int_equal(vis[n], 0xDEADBEEFu);
            for (uint32_t i = 0; i < n; ++i) {
                double ref = ref_vis(&p, (size_t)y * 13 + x0 + i, t, rad) * 65536.0;
                assert_true(fabs((double)vis[i] - ref) <= 1.0);
            }
        }
        tpath_free(&p);
    }
}

static void test_shade(void **state)
{
    (void)state;
    tpath p;
    tpath_make(&p, 9, 3, 0, 42);
    qibl_lightpath_t lp;
    assert_int_equal(qibl_lightpath_parse(p.buf, p.n, &lp), QIBL_OK);
    tu_rng r = {5};
    int32_t light[27], out[27], base[27];
    uint32_t vis[9];
    for (int trial = 0; trial < 50; ++trial) {
        uint32_t t = tu_u32(&r) & 65535u, rad = trial & 1 ? 0u : tu_u32(&r) % 2000u, y = tu_u32(&r) % 3;
        for (int i = 0; i < 27; ++i)
            light[i] = trial == 0 ? (i & 1 ? INT32_MAX : INT32_MIN) : tu_s32(&r) >> (tu_u32(&r) % 20), base[i] = tu_s32(&r);
        assert_int_equal(qibl_lightpath_visibility_span(&lp, t, rad, 0, y, 9, vis), QIBL_OK);
        memcpy(out, base, sizeof out);
        assert_int_equal(qibl_lightpath_shade_span(&lp, t, rad, 0, y, 9, light, out, false), QIBL_OK);
        for (int i = 0; i < 27; ++i) {
            double want = floor((double)light[i] * vis[i / 3] / 65536.0 + 0.5);
            assert_true(fabs((double)out[i] - want) <= 0.0);
        }
        int32_t prod[27];
        memcpy(prod, out, sizeof prod);
        memcpy(out, base, sizeof out);
        assert_int_equal(qibl_lightpath_shade_span(&lp, t, rad, 0, y, 9, light, out, true), QIBL_OK);
        for (int i = 0; i < 27; ++i) {
            double s = (double)base[i] + prod[i];
            s = s > INT32_MAX ? INT32_MAX : s < INT32_MIN ? INT32_MIN : s;
            assert_true((double)out[i] == s);
        }
        /* in place */
        memcpy(out, light, sizeof out);
        assert_int_equal(qibl_lightpath_shade_span(&lp, t, rad, 0, y, 9, out, out, false), QIBL_OK);
        assert_memory_equal(out, prod, sizeof out);
    }
    tpath_free(&p);
}

static void test_at(void **state)
{
    (void)state;
    tpath p;
    tpath_make(&p, 2, 2, 1, 9);
    qibl_lightpath_t lp;
    assert_int_equal(qibl_lightpath_parse(p.buf, p.n, &lp), QIBL_OK);
    for (uint32_t t = 0; t <= 65535u; t += 997u) {
        qibl_q16_t v[3];
        assert_int_equal(qibl_lightpath_at(&lp, t, v), QIBL_OK);
        uint32_t i = 0;
        while (i + 2 < p.nkeys && p.kt[i + 1] <= t)
            ++i;
        double f = (double)(t - p.kt[i]) / (p.kt[i + 1] - p.kt[i]);
        for (int c = 0; c < 3; ++c) {
            double want = p.kv[3 * i + (uint32_t)c] + f * ((double)p.kv[3 * (i + 1) + (uint32_t)c] - p.kv[3 * i + (uint32_t)c]);
            assert_true(fabs(v[c] - want) <= 1.0);
        }
    }
    qibl_q16_t v[3] = {7, 7, 7};
    assert_int_equal(qibl_lightpath_at(&lp, 65536u, v), QIBL_E_LIGHTPATH_PARAM);
    assert_int_equal(v[0], 7);
    assert_int_equal(qibl_lightpath_at(NULL, 0, v), QIBL_E_NULL_POINTER);
    tpath_free(&p);
}

static void test_span_errors(void **state)
{
    (void)state;
    tpath p;
    tpath_make(&p, 4, 2, 0, 3);
    qibl_lightpath_t lp;
    assert_int_equal(qibl_lightpath_parse(p.buf, p.n, &lp), QIBL_OK);
    uint32_t vis[5] = {9, 9, 9, 9, 9};
    int32_t l[15] = {0}, o[15] = {5};
    assert_int_equal(qibl_lightpath_visibility_span(&lp, 65536u, 0, 0, 0, 4, vis), QIBL_E_LIGHTPATH_PARAM);
    assert_int_equal(qibl_lightpath_visibility_span(&lp, 0, 32768u, 0, 0, 4, vis), QIBL_E_LIGHTPATH_PARAM);
    assert_int_equal(qibl_lightpath_visibility_span(&lp, 0, 0, 0, 2, 4, vis), QIBL_E_LIGHTPATH_BOUNDS);
    assert_int_equal(qibl_lightpath_visibility_span(&lp, 0, 0, 1, 0, 4, vis), QIBL_E_LIGHTPATH_BOUNDS);
    assert_int_equal(qibl_lightpath_visibility_span(&lp, 0, 0, 5, 0, 0, vis), QIBL_E_LIGHTPATH_BOUNDS);
    assert_int_equal(qibl_lightpath_visibility_span(&lp, 0, 0, 0, 0, 4, NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_lightpath_visibility_span(NULL, 0, 0, 0, 0, 4, vis), QIBL_E_NULL_POINTER);
    assert_int_equal(vis[0], 9);
    assert_int_equal(qibl_lightpath_shade_span(&lp, 0, 0, 0, 0, 5, l, o, false), QIBL_E_LIGHTPATH_BOUNDS);
    assert_int_equal(qibl_lightpath_shade_span(&lp, 0, 0, 0, 0, 4, NULL, o, false), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_lightpath_shade_span(&lp, 0, 0, 0, 0, 4, l, NULL, false), QIBL_E_NULL_POINTER);
    assert_int_equal(o[0], 5);
    /* an empty span at the end of a row is fine */
    assert_int_equal(qibl_lightpath_visibility_span(&lp, 0, 0, 4, 1, 0, vis), QIBL_OK);
    tpath_free(&p);
}

/* ---- hostile payloads ----------------------------------------------------------------------------- */

static void put32(uint8_t *b, size_t off, uint32_t v)
{
    qtool_store_u32le(b + off, v);
}

static qibl_status_t parse_edit(const tpath *p, size_t off, uint32_t v)
{
    uint8_t *b = malloc(p->n);
    memcpy(b, p->buf, p->n);
    put32(b, off, v);
    qibl_lightpath_t lp;
    memset(&lp, 0xAB, sizeof lp);
    qibl_status_t st = qibl_lightpath_parse(b, p->n, &lp);
    if (st != QIBL_OK) {
        qibl_lightpath_t untouched;
        memset(&untouched, 0xAB, sizeof untouched);
        assert_memory_equal(&lp, &untouched, sizeof lp);
    }
    free(b);
    return st;
}

static void test_named_errors(void **state)
{
    (void)state;
    tpath p;
    tpath_make(&p, 5, 3, 0, 11);
    assert_true(p.nedges >= 3);
    size_t keys = QIBL_LIGHTPATH_HEADER, rows = keys + 16 * p.nkeys, counts = rows + 4 * (p.h + 1);
    size_t edges = counts + (size_t)p.w * p.h;
    qibl_lightpath_t lp;
    assert_int_equal(qibl_lightpath_parse(p.buf, p.n, NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_lightpath_parse(NULL, p.n, &lp), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_lightpath_parse(p.buf, 23, &lp), QIBL_E_LIGHTPATH_SIZE);
    assert_int_equal(qibl_lightpath_parse(p.buf, p.n + 1, &lp), QIBL_E_LIGHTPATH_SIZE);
    assert_int_equal(parse_edit(&p, 0, 0), QIBL_E_LIGHTPATH_DIMENSIONS);
    assert_int_equal(parse_edit(&p, 4, QIBL_ASSET_MAX_DIM + 1), QIBL_E_LIGHTPATH_DIMENSIONS);
    assert_int_equal(parse_edit(&p, 0, 6), QIBL_E_LIGHTPATH_SIZE); /* size no longer matches */
    assert_int_equal(parse_edit(&p, 8, 2), QIBL_E_LIGHTPATH_KIND);
    assert_int_equal(parse_edit(&p, 12, 1), QIBL_E_LIGHTPATH_KIND);
    assert_int_equal(parse_edit(&p, 16, 1), QIBL_E_LIGHTPATH_KEYS);
    assert_int_equal(parse_edit(&p, 16, QIBL_LIGHTPATH_MAX_KEYS + 1), QIBL_E_LIGHTPATH_KEYS);
    assert_int_equal(parse_edit(&p, 20, QIBL_LIGHTPATH_MAX_EDGES + 1), QIBL_E_LIGHTPATH_SIZE);
    assert_int_equal(parse_edit(&p, 20, UINT32_MAX), QIBL_E_LIGHTPATH_SIZE);
    assert_int_equal(parse_edit(&p, keys, 1), QIBL_E_LIGHTPATH_KEYS);                    /* first t not 0 */
    assert_int_equal(parse_edit(&p, keys + 16, 0), QIBL_E_LIGHTPATH_KEYS);               /* not increasing */
    assert_int_equal(parse_edit(&p, keys + 16 * (p.nkeys - 1), 65534), QIBL_E_LIGHTPATH_KEYS); /* last not 65535 */
    assert_int_equal(parse_edit(&p, keys + 16 * (p.nkeys - 1), 65536), QIBL_E_LIGHTPATH_KEYS);
    {   /* a zero direction (kind 0) is refused; the same point of a track (kind 1) is fine */
        uint8_t *b = malloc(p.n);
        memcpy(b, p.buf, p.n);
        put32(b, keys + 4, 0), put32(b, keys + 8, 0), put32(b, keys + 12, 0);
        assert_int_equal(qibl_lightpath_parse(b, p.n, &lp), QIBL_E_LIGHTPATH_KEYS);
        put32(b, 8, 1);
        assert_int_equal(qibl_lightpath_parse(b, p.n, &lp), QIBL_OK);
        free(b);
    }
    assert_int_equal(parse_edit(&p, rows, 1), QIBL_E_LIGHTPATH_ROWS);
    assert_int_equal(parse_edit(&p, rows + 4 * p.h, p.nedges - 1), QIBL_E_LIGHTPATH_ROWS);
    assert_int_equal(parse_edit(&p, rows + 4, qibl_load_u32le(p.buf + rows + 4) + 1), QIBL_E_LIGHTPATH_ROWS);
    {   /* counts that overrun nedges, and a count moved between rows */
        uint8_t *b = malloc(p.n);
        memcpy(b, p.buf, p.n);
        b[counts] = 255;
        assert_int_equal(qibl_lightpath_parse(b, p.n, &lp), QIBL_E_LIGHTPATH_ROWS);
        memcpy(b, p.buf, p.n);
        size_t last = counts + (size_t)p.w * p.h - 1;
        if (b[counts] > 0) {
            b[counts]--, b[last]++;
            assert_int_equal(qibl_lightpath_parse(b, p.n, &lp), QIBL_E_LIGHTPATH_ROWS);
        }
        /* edges: a pixel with two equal edges */
        memcpy(b, p.buf, p.n);
        size_t at = 0, i = 0;
        while (p.counts[i] < 2)
            at += p.counts[i++];
        b[edges + 2 * (at + 1)] = b[edges + 2 * at], b[edges + 2 * (at + 1) + 1] = b[edges + 2 * at + 1];
        assert_int_equal(qibl_lightpath_parse(b, p.n, &lp), QIBL_E_LIGHTPATH_EDGES);
        free(b);
    }
    tpath_free(&p);
}

static void test_truncations_and_flips(void **state)
{
    (void)state;
    tpath p;
    tpath_make(&p, 6, 4, 1, 21);
    qibl_lightpath_t lp;
    for (size_t n = 0; n < p.n; ++n) {
        uint8_t *b = malloc(n ? n : 1); /* an exact-size copy: ASan sees any read past it */
        memcpy(b, p.buf, n);
        assert_int_not_equal(qibl_lightpath_parse(b, n, &lp), QIBL_OK);
        free(b);
    }
    tu_rng r = {99};
    uint8_t *b = malloc(p.n);
    for (int trial = 0; trial < 3000; ++trial) {
        memcpy(b, p.buf, p.n);
        for (int k = 0; k < 1 + trial % 4; ++k)
            b[tu_u32(&r) % p.n] ^= (uint8_t)(1u << (tu_u32(&r) % 8));
        qibl_status_t st = qibl_lightpath_parse(b, p.n, &lp);
        assert_true(st == QIBL_OK || (st >= QIBL_E_LIGHTPATH_SIZE && st <= QIBL_E_LIGHTPATH_EDGES));
        if (st == QIBL_OK) { /* whatever passed is safe to use */
            uint32_t vis[6];
            int32_t l[18] = {0};
            for (uint32_t y = 0; y < lp.height && y < 4; ++y) {
                assert_int_equal(qibl_lightpath_visibility_span(&lp, tu_u32(&r) & 65535u, 100, 0, y, lp.width < 6 ? lp.width : 6, vis), QIBL_OK);
                assert_int_equal(qibl_lightpath_shade_span(&lp, 7, 0, 0, y, lp.width < 6 ? lp.width : 6, l, l, false), QIBL_OK);
            }
        }
    }
    free(b);
    tpath_free(&p);
}

/* ---- in an asset ----------------------------------------------------------------------------------- */

static void add_shm(qtool_asset_builder *b, uint32_t type, uint32_t w, uint32_t h, uint32_t k)
{
    int32_t scale[78], bias[78];
    uint8_t *planes = calloc((size_t)w * h * k * 3, 1);
    for (uint32_t i = 0; i < k * 3; ++i)
        scale[i] = 1 << 16, bias[i] = 0;
    if (type == QIBL_CHUNK_SHMP)
        assert_int_equal(qtool_asset_add_shmp(b, w, h, k, 3, scale, bias, planes), 0);
    else
        assert_int_equal(qtool_asset_add_shmu(b, w, h, k, 3, scale, bias, planes), 0);
    free(planes);
}

static void test_asset(void **state)
{
    (void)state;
    tpath p1, p2, p3;
    tpath_make(&p1, 6, 2, 0, 1), tpath_make(&p2, 6, 2, 1, 2), tpath_make(&p3, 5, 2, 1, 3);
    qtool_asset_builder b;
    uint8_t *buf;
    size_t n;
    qibl_asset_t a;
    qibl_shmaps_t m;
    qibl_lightpath_t lp;
    /* SHMP k4 + SHMU k9 + two paths */
    qtool_asset_builder_init(&b);
    add_shm(&b, QIBL_CHUNK_SHMP, 6, 2, 4);
    add_shm(&b, QIBL_CHUNK_SHMU, 6, 2, 9);
    assert_int_equal(qtool_asset_builder_add(&b, QIBL_CHUNK_LPTH, p1.buf, p1.n), 0);
    assert_int_equal(qtool_asset_builder_add(&b, QIBL_CHUNK_LPTH, p2.buf, p2.n), 0);
    assert_int_equal(qtool_asset_serialize(&b, &buf, &n), 0);
    qtool_asset_builder_free(&b);
    assert_int_equal(qibl_asset_open(&a, buf, n), QIBL_OK);
    assert_int_equal(qibl_asset_shmaps(&a, &m), QIBL_OK);
    assert_int_equal(m.k, 4);
    assert_int_equal(qibl_asset_shmaps_unshadowed(&a, &m), QIBL_OK);
    assert_int_equal(m.k, 9);
    assert_int_equal(qibl_asset_point_shmaps(&a, &m), QIBL_OK);
    assert_int_equal(m.k, 9);
    assert_int_equal(qibl_lightpath_count(&a), 2);
    assert_int_equal(qibl_lightpath_count(NULL), 0);
    assert_int_equal(qibl_lightpath_from_asset(&a, 1, &lp), QIBL_OK);
    assert_int_equal(lp.kind, 1);
    assert_int_equal(qibl_lightpath_from_asset(&a, 2, &lp), QIBL_E_ASSET_MISSING_CHUNK);
    assert_int_equal(qibl_lightpath_from_asset(NULL, 0, &lp), QIBL_E_NULL_POINTER);
    free(buf);
    /* an older asset: no SHMU, point lights get SHMP; a path of another size */
    qtool_asset_builder_init(&b);
    add_shm(&b, QIBL_CHUNK_SHMP, 6, 2, 4);
    assert_int_equal(qtool_asset_builder_add(&b, QIBL_CHUNK_LPTH, p3.buf, p3.n), 0);
    assert_int_equal(qtool_asset_serialize(&b, &buf, &n), 0);
    qtool_asset_builder_free(&b);
    assert_int_equal(qibl_asset_open(&a, buf, n), QIBL_OK);
    assert_int_equal(qibl_asset_shmaps_unshadowed(&a, &m), QIBL_E_ASSET_MISSING_CHUNK);
    assert_int_equal(qibl_asset_point_shmaps(&a, &m), QIBL_OK);
    assert_int_equal(m.k, 4);
    assert_int_equal(qibl_lightpath_from_asset(&a, 0, &lp), QIBL_E_LIGHTPATH_DIMENSIONS);
    free(buf);
    /* SHMU of another size, twice SHMU, SHMU with bad fields */
    for (int v = 0; v < 3; ++v) {
        qtool_asset_builder_init(&b);
        add_shm(&b, QIBL_CHUNK_SHMP, 6, 2, 4);
        add_shm(&b, QIBL_CHUNK_SHMU, v == 0 ? 5 : 6, 2, v == 2 ? 26 : 4);
        if (v == 1)
            add_shm(&b, QIBL_CHUNK_SHMU, 6, 2, 4);
        assert_int_equal(qtool_asset_serialize(&b, &buf, &n), 0);
        qtool_asset_builder_free(&b);
        assert_int_equal(qibl_asset_open(&a, buf, n),
                         v == 0 ? QIBL_E_ASSET_MISMATCH : v == 1 ? QIBL_E_ASSET_DUPLICATE_CHUNK : QIBL_E_ASSET_BAD_K);
        free(buf);
    }
    tpath_free(&p1), tpath_free(&p2), tpath_free(&p3);
}

/* ---- lamp occlusion (LOCC) ------------------------------------------------------------------------- */

static void test_lampocc(void **state)
{
    (void)state;
    enum { W = 7, H = 3 };
    tu_rng r = {77};
    uint8_t v[W * H], *pl, *buf, *b2;
    size_t pn, n, n2;
    for (int i = 0; i < W * H; ++i)
        v[i] = i == 0 ? 0 : i == 1 ? 255 : (uint8_t)tu_next(&r);
    assert_int_equal(qtool_bake_locc_payload(W, H, v, &pl, &pn), 0);
    assert_int_equal(pn, 8 + W * H);
    qibl_lampocc_t o, untouched;
    memset(&untouched, 0xA5, sizeof untouched);
    /* named errors, *out untouched */
    o = untouched;
    assert_int_equal(qibl_lightpath_occl_parse(NULL, pn, &o), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_lightpath_occl_parse(pl, pn, NULL), QIBL_E_NULL_POINTER);
    for (size_t cut = 0; cut < pn; ++cut)
        assert_int_equal(qibl_lightpath_occl_parse(pl, cut, &o), QIBL_E_LIGHTPATH_SIZE);
    assert_memory_equal(&o, &untouched, sizeof o);
    uint8_t bad[8 + W * H];
    memcpy(bad, pl, pn);
    qtool_store_u32le(bad, 0);
    assert_int_equal(qibl_lightpath_occl_parse(bad, pn, &o), QIBL_E_LIGHTPATH_DIMENSIONS);
    qtool_store_u32le(bad, 20000);
    assert_int_equal(qibl_lightpath_occl_parse(bad, pn, &o), QIBL_E_LIGHTPATH_DIMENSIONS);
    qtool_store_u32le(bad, W + 1);
    assert_int_equal(qibl_lightpath_occl_parse(bad, pn, &o), QIBL_E_LIGHTPATH_SIZE);
    assert_memory_equal(&o, &untouched, sizeof o);
    assert_int_equal(qibl_lightpath_occl_parse(pl, pn, &o), QIBL_OK);
    assert_int_equal(o.width, W);
    /* the span against double: io * a / 255, rounded, within 1 LSB plus the factor's 2^-16 */
    for (uint32_t y = 0; y < H; ++y) {
        int32_t io[3 * W], ref[3 * W];
        for (int i = 0; i < 3 * W; ++i)
            io[i] = ref[i] = i % 5 == 0 ? INT32_MIN : i % 5 == 1 ? INT32_MAX : tu_s32(&r);
        assert_int_equal(qibl_lightpath_occl_span(&o, 2, y, W - 2, io + 6), QIBL_OK);
        assert_int_equal(qibl_lightpath_occl_span(&o, 0, y, 2, io), QIBL_OK);
        for (int i = 0; i < 3 * W; ++i) {
            double a = v[y * W + (uint32_t)i / 3], e = ref[i] * a / 255.0;
            assert_true(fabs((double)io[i] - e) <= 1.0 + fabs((double)ref[i]) * 0x1p-16);
            if (a == 255)
                assert_int_equal(io[i], ref[i]);
            if (a == 0)
                assert_int_equal(io[i], 0);
        }
    }
    int32_t io[3 * W] = {0}, keep[3 * W];
    memcpy(keep, io, sizeof io);
    assert_int_equal(qibl_lightpath_occl_span(&o, 0, H, 1, io), QIBL_E_LIGHTPATH_BOUNDS);
    assert_int_equal(qibl_lightpath_occl_span(&o, W + 1, 0, 0, io), QIBL_E_LIGHTPATH_BOUNDS);
    assert_int_equal(qibl_lightpath_occl_span(&o, 1, 0, W, io), QIBL_E_LIGHTPATH_BOUNDS);
    assert_int_equal(qibl_lightpath_occl_span(&o, 0, 0, W, NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_lightpath_occl_span(NULL, 0, 0, W, io), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_lightpath_occl_span(&o, W, 0, 0, io), QIBL_OK);
    assert_memory_equal(io, keep, sizeof io);
    /* in an asset: appended to a valid one, found; missing, twice, another size */
    qtool_asset_builder b;
    qibl_asset_t a;
    qtool_asset_builder_init(&b);
    add_shm(&b, QIBL_CHUNK_SHMP, W, H, 4);
    assert_int_equal(qtool_asset_serialize(&b, &buf, &n), 0);
    qtool_asset_builder_free(&b);
    assert_int_equal(qibl_asset_open(&a, buf, n), QIBL_OK);
    assert_int_equal(qibl_lightpath_occl_from_asset(&a, &o), QIBL_E_ASSET_MISSING_CHUNK);
    assert_int_equal(qibl_lightpath_occl_from_asset(NULL, &o), QIBL_E_NULL_POINTER);
    assert_int_equal(qtool_bake_asset_add(buf, n, QIBL_CHUNK_LOCC, pl, pn, &b2, &n2), 0);
    assert_int_equal(qibl_asset_open(&a, b2, n2), QIBL_OK);
    assert_int_equal(qibl_lightpath_occl_from_asset(&a, &o), QIBL_OK);
    assert_memory_equal(o.values, v, sizeof v);
    uint8_t *b3;
    size_t n3;
    assert_int_equal(qtool_bake_asset_add(b2, n2, QIBL_CHUNK_LOCC, pl, pn, &b3, &n3), 0);
    assert_int_equal(qibl_asset_open(&a, b3, n3), QIBL_OK);
    assert_int_equal(qibl_lightpath_occl_from_asset(&a, &o), QIBL_E_ASSET_DUPLICATE_CHUNK);
    free(b2), free(b3);
    uint8_t *pl2;
    size_t pn2;
    assert_int_equal(qtool_bake_locc_payload(W - 1, H, v, &pl2, &pn2), 0);
    assert_int_equal(qtool_bake_asset_add(buf, n, QIBL_CHUNK_LOCC, pl2, pn2, &b2, &n2), 0);
    assert_int_equal(qibl_asset_open(&a, b2, n2), QIBL_OK);
    assert_int_equal(qibl_lightpath_occl_from_asset(&a, &o), QIBL_E_LIGHTPATH_DIMENSIONS);
    free(b2), free(pl2), free(buf), free(pl);
}

/* ---- the bake: edges against brute force --------------------------------------------------------- */

static void test_bake_edges(void **state)
{
    (void)state;
    qtool_rt_scene s;
    assert_int_equal(qtool_rt_scene_builtin(&s), 0);
    qtool_bake_path sun = {0};
    char err[200];
    assert_int_equal(qtool_bake_path_parse_sun("40,15,7,17", &sun, err, sizeof err), 0);
    assert_int_equal(qtool_bake_path_parse_sun("40,15,17,7", &sun, err, sizeof err), -1);
    assert_non_null(strstr(err, "T0 < T1"));
    assert_int_equal(qtool_bake_path_parse_sun("40,15,7", &sun, err, sizeof err), -1);
    /* a sun that never rises is refused by name (issue 24): polar night, and the hours after dusk */
    static const char *never[] = {"80,-20,0,24", "40,15,20,24", "-60,23,0,6", "90,-0.5,0,24"};
    for (int i = 0; i < 4; ++i) {
        if (qtool_bake_path_parse_sun(never[i], &sun, err, sizeof err) != -1)
            fail_msg("--sun-path %s: accepted, but the sun never rises", never[i]);
        assert_non_null(strstr(err, "the sun never rises"));
    }
    /* ... against brute force: each accepted path has a sample above the horizon, each refused none */
    for (int lat = -90; lat <= 90; lat += 15)
        for (int de = -23; de <= 23; de += 23)
            for (int t0 = 0; t0 < 24; t0 += 5)
                for (int t1 = t0 + 1; t1 <= 24; t1 += 7) {
                    char spec[64];
                    snprintf(spec, sizeof spec, "%d,%d,%d,%d", lat, de, t0, t1);
                    qtool_bake_path q = {0};
                    int ok = qtool_bake_path_parse_sun(spec, &q, err, sizeof err) == 0;
                    q.kind = 0, q.lat = lat, q.decl = de, q.t0 = t0, q.t1 = t1;
                    double zmax = -2;
                    for (int k = 0; k <= 2000; ++k) {
                        qtool_rt_light sl;
                        qtool_bake_path_light(&q, k / 2000.0, &sl);
                        zmax = fmax(zmax, sl.dir[2]);
                    }
                    if (fabs(zmax) > 1e-3 && ok != (zmax > 0))
                        fail_msg("--sun-path %s: %s, highest sample z %.4f", spec, ok ? "accepted" : "refused", zmax);
                }
    qtool_bake_path tr = {0};
    assert_int_equal(qtool_bake_path_parse_track("0,0,0;1,0,0;1,1,0", &tr, err, sizeof err), 0);
    assert_int_equal(tr.npts, 3);
    assert_int_equal(qtool_bake_path_parse_track("0,0,0;0,0,0", &tr, err, sizeof err), -1);
    assert_int_equal(qtool_bake_path_parse_track("0,0,0;1,x,0", &tr, err, sizeof err), -1);
    assert_non_null(strstr(err, "point 2"));
    /* t = 1/2 of the track is its arc-length midpoint */
    assert_int_equal(qtool_bake_path_parse_track("0,0,0;1,0,0;1,1,0", &tr, err, sizeof err), 0);
    qtool_rt_light l;
    qtool_bake_path_light(&tr, 0.5, &l);
    assert_true(fabs(l.pos[0] - 1) < 1e-12 && fabs(l.pos[1]) < 1e-12);
    /* noon at the equator on an equinox: straight up */
    qtool_bake_path eq = {0};
    assert_int_equal(qtool_bake_path_parse_sun("0,0,11,13", &eq, err, sizeof err), 0);
    qtool_bake_path_light(&eq, 0.5, &l);
    assert_true(fabs(l.dir[2] - 1) < 1e-12);

    uint32_t w = 24, h = 6;
    uint8_t *buf;
    size_t n;
    double stats[2];
    assert_int_equal(qtool_bake_path_chunk(&s, w, h, QTOOL_PANO_CYLINDRICAL, &sun, 16, 9, 2, &buf, &n, stats), 0);
    qibl_lightpath_t lp;
    assert_int_equal(qibl_lightpath_parse(buf, n, &lp), QIBL_OK);
    /* the stored visibility agrees with the ray tracer away from the edges (one 16-bit step) */
    int bad = 0, checked = 0;
    for (uint32_t y = 0; y < h; ++y) {
        uint32_t vis[24];
        for (uint32_t t = 300; t < 65535; t += 4093) {
            assert_int_equal(qibl_lightpath_visibility_span(&lp, t, 0, 0, y, w, vis), QIBL_OK);
            for (uint32_t x = 0; x < w; ++x) {
                double d[3], wv[3], df, gl;
                qtool_rt_hit hit;
                qtool_rt_pixel_dir(w, h, QTOOL_PANO_CYLINDRICAL, x, y, d);
                qtool_rt_primary(&s, d, &hit);
                qtool_bake_path_light(&sun, t / 65535.0, &l);
                double len = sqrt(l.dir[0] * l.dir[0] + l.dir[1] * l.dir[1] + l.dir[2] * l.dir[2]);
                for (int c = 0; c < 3; ++c)
                    wv[c] = l.dir[c] / len;
                int lit = hit.hit && qtool_rt_response(&s, &hit, wv, 1e30, &df, &gl);
                checked++;
                bad += (vis[x] == 65536u) != (lit != 0);
            }
        }
    }
    /* only changes that undo themselves between two of the 16 samples may be missed */
    assert_true(bad * 50 <= checked);
    free(buf);
    qtool_rt_scene_free(&s);
}

/* fixed payload, maps and lights -> SHA-256 (tools/golden/cases_lightpath.c, shared with the runner) */
static void test_goldens(void **state)
{
    (void)state;
    assert_int_equal(qtool_goldens_check("lightpath"), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_parse_and_visibility), cmocka_unit_test(test_shade),
        cmocka_unit_test(test_at),                   cmocka_unit_test(test_span_errors),
        cmocka_unit_test(test_named_errors),         cmocka_unit_test(test_truncations_and_flips),
        cmocka_unit_test(test_asset),                cmocka_unit_test(test_bake_edges),
        cmocka_unit_test(test_goldens),              cmocka_unit_test(test_lampocc),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
