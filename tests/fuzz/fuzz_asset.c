/*
 * fuzz_asset.c - libFuzzer target: the asset container (core/include/qibl/asset.h), every chunk
 * accessor, and the relighting kernels (shmap.h) and software framebuffer (soft.h) on whatever
 * parses.
 *
 * Each input is parsed twice: as it is, and with the CRCs repaired (every payload CRC whose entry
 * lies inside the buffer, then the table CRC), so mutations of the fields get past the CRC checks
 * to the deep ones. Bytes after the header's file_size (the buffer may be longer) choose the light
 * directions, point light and framebuffer settings. Buffers have exactly the documented sizes, so
 * ASan sees any access past them.
 *
 * Invariants: a failing open leaves *out untouched; with repaired CRCs no CRC error is possible;
 * on success every chunk of the table is found where the table says, the typed views match the
 * payload bytes and lie inside the asset, the kernels accept the validated views (no error for an
 * in-range span), a row relit as one span equals the row relit as two, a span past the maps is
 * refused with nothing written, and the framebuffer writer accepts every relit row.
 */
#include <math.h>
#include <string.h>

#include "fuzz.h"
#include "qibl/asset.h"
#include "qibl/shmap.h"
#include "qibl/soft.h"

static uint32_t le32(const uint8_t *p)
{
    return qibl_load_u32le(p);
}

static void put32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v, p[1] = (uint8_t)(v >> 8), p[2] = (uint8_t)(v >> 16), p[3] = (uint8_t)(v >> 24);
}

/* repairs the CRCs a writer would have computed; 1 if the table could be repaired */
static int fix_crcs(uint8_t *b, size_t n)
{
    if (n < QIBL_ASSET_HEADER_SIZE)
        return 0;
    uint32_t count = le32(b + 12);
    if (count < 1u || count > QIBL_ASSET_MAX_CHUNKS || n < QIBL_ASSET_HEADER_SIZE + QIBL_ASSET_ENTRY_SIZE * count)
        return 0;
    for (uint32_t i = 0; i < count; ++i) {
        uint8_t *e = b + QIBL_ASSET_HEADER_SIZE + QIBL_ASSET_ENTRY_SIZE * i;
        uint64_t off = le32(e + 4), sz = le32(e + 8);
        if (off + sz <= n)
            put32(e + 12, qibl_crc32(0u, b + off, (size_t)sz));
    }
    put32(b + 20, qibl_crc32(0u, b + QIBL_ASSET_HEADER_SIZE, QIBL_ASSET_ENTRY_SIZE * count));
    return 1;
}

static int inside(const qibl_asset_t *a, const uint8_t *p, uint64_t len)
{
    return p >= a->base && (uint64_t)(p - a->base) + len <= a->size;
}

/* relights row y as one span and as two; both must succeed and agree */
static void relight_rows(const qibl_shmaps_t *m, const qibl_shmap_weights_t *w, fuzz_in *prm)
{
    const uint32_t n = m->width;
    const size_t wsz = qibl_shmap_span_workspace_size(n);
    int32_t *out = malloc(12u * n), *out2 = malloc(12u * n);
    void *ws = malloc(wsz);
    for (uint32_t y = 0; y < m->height; ++y) {
        FUZZ_CHECK(qibl_shmap_relight_span(m, w, 0, y, n, out, ws, wsz) == QIBL_OK);
        const uint32_t a = n / 2u;
        FUZZ_CHECK(qibl_shmap_relight_span(m, w, 0, y, a, out2, ws, wsz) == QIBL_OK);
        FUZZ_CHECK(qibl_shmap_relight_span(m, w, a, y, n - a, out2 + 3u * a, ws, wsz) == QIBL_OK);
        FUZZ_CHECK(memcmp(out, out2, 12u * n) == 0);
    }
    /* past the maps, or too little workspace: refused, nothing written */
    memset(out2, 0x77, 12u * n);
    FUZZ_CHECK(qibl_shmap_relight_span(m, w, 1, 0, n, out2, ws, wsz) == QIBL_E_SHMAP_BOUNDS);
    FUZZ_CHECK(qibl_shmap_relight_span(m, w, 0, m->height, 1, out2, ws, wsz) == QIBL_E_SHMAP_BOUNDS);
    FUZZ_CHECK(wsz == 0 || qibl_shmap_relight_span(m, w, 0, 0, n, out2, ws, wsz - 1u) == QIBL_E_WORKSPACE);
    for (size_t i = 0; i < 3u * n; ++i)
        FUZZ_CHECK(out2[i] == 0x77777777);

    /* the last row through the framebuffer shim, in a fuzzed format */
    qibl_fb_desc_t fb, acc;
    memset(&fb, 0, sizeof fb);
    const uint8_t f = fuzz_u8(prm);
    fb.width = n, fb.height = 1, fb.format = (qibl_fb_format_t)(f % QIBL_FB_FORMAT_COUNT);
    fb.exposure = fuzz_u32(prm), fb.srgb = f >> 2 & 1u, fb.dither = f >> 3 & 1u;
    fb.pixels = malloc((size_t)n * qibl_soft_fb_bytes_per_pixel(fb.format));
    FUZZ_CHECK(qibl_soft_fb_clear(&fb) == QIBL_OK);
    FUZZ_CHECK(qibl_soft_fb_write_row(&fb, 0, 0, n, out) == QIBL_OK);
    FUZZ_CHECK(qibl_soft_fb_write_row(&fb, 0, 0, n, out) == QIBL_OK); /* ACCUM32 saturates */
    if (fb.format == QIBL_FB_ACCUM32) {
        acc = fb;
        fb.format = (qibl_fb_format_t)((f >> 4) % 3u);
        void *px8 = malloc((size_t)n * 4u);
        fb.pixels = px8;
        FUZZ_CHECK(qibl_soft_fb_resolve(&fb, &acc) == QIBL_OK);
        free(px8);
        fb.pixels = acc.pixels;
    }
    free(fb.pixels);
    free(ws), free(out), free(out2);
}

static void point_rows(const qibl_shmaps_t *m, const qibl_pmap_t *p, const qibl_ylut_t *lut, fuzz_in *prm)
{
    qibl_pointlight_t L;
    memset(&L, 0, sizeof L);
    for (int j = 0; j < 3; ++j) {
        L.pos[j] = (int32_t)fuzz_u32(prm);
        L.rgb[j] = (int32_t)(fuzz_u32(prm) & 0x7FFFFFFFu);
    }
    const uint8_t f = fuzz_u8(prm);
    L.falloff = (qibl_falloff_t)(f & 1u);
    L.filter = (qibl_lut_filter_t)(f >> 1 & 1u);
    L.min_dist = (int32_t)(fuzz_u32(prm) & 0x7FFFFFFFu);
    qibl_shmap_point_t pt;
    FUZZ_CHECK(qibl_shmap_point_prepare(m, p, lut, &L, &pt) == QIBL_OK);
    const uint32_t n = m->width;
    const size_t wsz = qibl_shmap_point_workspace_size(m->k, n);
    int32_t *out = malloc(12u * n), *out2 = malloc(12u * n);
    void *ws = malloc(wsz);
    for (uint32_t y = 0; y < m->height; ++y) {
        FUZZ_CHECK(qibl_shmap_point_span(&pt, 0, y, n, out, ws, wsz) == QIBL_OK);
        const uint32_t a = n / 2u;
        FUZZ_CHECK(qibl_shmap_point_span(&pt, 0, y, a, out2, ws, wsz) == QIBL_OK);
        FUZZ_CHECK(qibl_shmap_point_span(&pt, a, y, n - a, out2 + 3u * a, ws, wsz) == QIBL_OK);
        FUZZ_CHECK(memcmp(out, out2, 12u * n) == 0);
    }
    memset(out2, 0x77, 12u * n);
    FUZZ_CHECK(qibl_shmap_point_span(&pt, 0, m->height, 1, out2, ws, wsz) == QIBL_E_SHMAP_BOUNDS);
    FUZZ_CHECK(qibl_shmap_point_span(&pt, 1, 0, n, out2, ws, wsz) == QIBL_E_SHMAP_BOUNDS);
    for (size_t i = 0; i < 3u * n; ++i)
        FUZZ_CHECK(out2[i] == 0x77777777);
    L.rgb[1] = -1;
    FUZZ_CHECK(qibl_shmap_point_prepare(m, p, lut, &L, &pt) == QIBL_E_SHMAP_LIGHT);
    free(ws), free(out), free(out2);
}

static void use_asset(const qibl_asset_t *a, fuzz_in *prm)
{
    /* every table entry: found (first of its type) where the table says */
    for (uint32_t i = 0; i < a->chunk_count; ++i) {
        const uint8_t *e = a->base + QIBL_ASSET_HEADER_SIZE + QIBL_ASSET_ENTRY_SIZE * i;
        qibl_chunk_t c;
        FUZZ_CHECK(qibl_asset_find(a, le32(e), &c) == QIBL_OK && c.type == le32(e));
        FUZZ_CHECK(inside(a, c.data, c.size));
        uint32_t first = 0;
        while (le32(a->base + QIBL_ASSET_HEADER_SIZE + QIBL_ASSET_ENTRY_SIZE * first) != le32(e))
            ++first;
        const uint8_t *fe = a->base + QIBL_ASSET_HEADER_SIZE + QIBL_ASSET_ENTRY_SIZE * first;
        FUZZ_CHECK(c.data == a->base + le32(fe + 4) && c.size == le32(fe + 8));
    }

    qibl_shmaps_t m;
    FUZZ_CHECK(qibl_asset_shmaps(a, &m) == QIBL_OK && qibl_shmap_check(&m) == QIBL_OK);
    FUZZ_CHECK(m.k >= 1u && m.k <= 25u && (m.channels == 1u || m.channels == 3u) && m.width && m.height);
    const uint64_t plane = (uint64_t)m.width * m.height;
    FUZZ_CHECK(inside(a, m.params, 8u * m.k * m.channels) && inside(a, m.planes, plane * m.k * m.channels));
    unsigned sum = 0;
    for (uint32_t i = 0; i < m.k; ++i)
        for (uint32_t ch = 0; ch < m.channels; ++ch) {
            const uint8_t *q = m.params + 8u * (i * m.channels + ch);
            FUZZ_CHECK(qibl_shmaps_scale(&m, i, ch) == qibl_load_s32le(q));
            FUZZ_CHECK(qibl_shmaps_bias(&m, i, ch) == qibl_load_s32le(q + 4));
            const uint8_t *pl = qibl_shmaps_plane(&m, i, ch);
            FUZZ_CHECK(inside(a, pl, plane));
            for (uint64_t j = 0; j < plane; ++j)
                sum += pl[j];
        }
    (void)sum;

    qibl_pmap_t p;
    int have_p = qibl_asset_pmap(a, &p) == QIBL_OK;
    if (have_p) {
        FUZZ_CHECK(p.width == m.width && p.height == m.height && inside(a, p.points, 12u * plane));
        for (uint32_t y = 0; y < p.height; ++y)
            for (uint32_t x = 0; x < p.width; ++x) {
                qibl_q16_t v[3];
                qibl_pmap_point(&p, x, y, v);
                FUZZ_CHECK(v[2] == qibl_load_s32le(p.points + 12u * ((size_t)y * p.width + x) + 8u));
            }
    }
    qibl_ylut_t t;
    int have_t = qibl_asset_ylut(a, &t) == QIBL_OK;
    if (have_t) {
        FUZZ_CHECK(t.face_size >= 1u && t.face_size <= QIBL_ASSET_MAX_LUT && t.k >= m.k && t.k <= 25u);
        FUZZ_CHECK(inside(a, t.values, qibl_ylut_values_size(t.face_size, t.k)));
        FUZZ_CHECK(t.size == qibl_ylut_values_size(t.face_size, t.k)); /* the view states what it covers */
        FUZZ_CHECK(qibl_ylut_check(&t) == QIBL_OK);
        /* a fuzzed direction of small integers, normalised in Q2.30 */
        int32_t d[3];
        int64_t l2 = 0;
        for (int j = 0; j < 3; ++j) {
            d[j] = (int8_t)fuzz_u8(prm);
            l2 += (int64_t)d[j] * d[j];
        }
        if (l2 == 0)
            d[2] = 1, l2 = 1;
        qibl_q30_t u[3];
        for (int j = 0; j < 3; ++j) /* within 1 LSB of unit length */
            u[j] = (qibl_q30_t)llround(d[j] / sqrt((double)l2) * 1073741824.0);
        int32_t *y14 = malloc(sizeof(int32_t) * t.k);
        qibl_ylut_lookup(&t, u, t.k, y14);
        for (uint32_t i = 0; i < t.k; ++i)
            FUZZ_CHECK(y14[i] >= -32768 && y14[i] <= 32767);
        free(y14);
    }

    /* a LUT built by the core for these maps: exact size accepted, one byte less refused */
    {
        const uint32_t nf = 1u + fuzz_u8(prm) % 6u;
        const size_t lsz = qibl_ylut_values_size(nf, m.k);
        uint8_t *vals = malloc(lsz);
        FUZZ_CHECK(lsz > 0 && qibl_ylut_build(nf, m.k, vals, lsz - 1u) == QIBL_E_WORKSPACE);
        FUZZ_CHECK(qibl_ylut_build(nf, m.k, vals, lsz) == QIBL_OK);
        free(vals);
    }

    /* directional lights from the parameter bytes: any of them may be the zero vector */
    qibl_shlight_t light;
    const uint32_t lk = m.k + fuzz_u8(prm) % (26u - m.k);
    FUZZ_CHECK(qibl_shlight_init(&light, lk) == QIBL_OK);
    const unsigned nl = 1u + fuzz_u8(prm) % 4u;
    for (unsigned i = 0; i < nl; ++i) {
        qibl_q16_t dir[3], rgb[3];
        for (int j = 0; j < 3; ++j)
            dir[j] = (int32_t)fuzz_u32(prm), rgb[j] = (int32_t)fuzz_u32(prm);
        qibl_status_t st = qibl_shlight_add_dir(&light, dir, rgb);
        FUZZ_CHECK(st == ((dir[0] | dir[1] | dir[2]) ? QIBL_OK : QIBL_E_ZERO_VECTOR));
    }
    qibl_shmap_weights_t w;
    FUZZ_CHECK(qibl_shmap_weights(&m, &light, &w) == QIBL_OK);
    relight_rows(&m, &w, prm);
    if (m.k > 1u) {
        qibl_shlight_t small;
        FUZZ_CHECK(qibl_shlight_init(&small, m.k - 1u) == QIBL_OK);
        FUZZ_CHECK(qibl_shmap_weights(&m, &small, &w) == QIBL_E_SHMAP_LIGHT_K);
    }
    if (have_p) {
        point_rows(&m, &p, NULL, prm);
        if (have_t)
            point_rows(&m, &p, &t, prm);
    }
}

static void parse(const uint8_t *buf, size_t n, int repaired)
{
    qibl_asset_t a, a0;
    memset(&a, 0xC3, sizeof a);
    a0 = a;
    qibl_status_t st = qibl_asset_open(&a, buf, n);
    if (repaired)
        FUZZ_CHECK(st != QIBL_E_ASSET_TABLE_CRC && st != QIBL_E_ASSET_CHUNK_CRC);
    if (st != QIBL_OK) {
        FUZZ_CHECK(memcmp(&a, &a0, sizeof a) == 0);
        FUZZ_CHECK(st > QIBL_OK && st < QIBL_STATUS_COUNT);
        return;
    }
    FUZZ_CHECK(a.base == buf && a.size == le32(buf + 16) && a.size <= n && a.chunk_count == le32(buf + 12));
    fuzz_in prm = {buf + a.size, n - a.size};
    use_asset(&a, &prm);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    /* a copy of exactly size bytes: ASan then sees any read past the caller's buffer */
    uint8_t *buf = malloc(size ? size : 1u);
    memcpy(buf, data, size);
    parse(buf, size, 0);
    if (fix_crcs(buf, size))
        parse(buf, size, 1);
    free(buf);
    return 0;
}
