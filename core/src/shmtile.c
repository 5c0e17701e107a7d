/*
 * shmtile.c - SH maps per 16x16 tile with per-tile k (SHMT chunks): validation and tile views.
 *
 * Invariants: every size is summed in 64 bits from factors below 2^26 before any byte past the
 * fixed part is read; the offsets are checked against the running sum of the tiles' sizes, so a
 * view never leaves the payload. No division in the per-tile code (the tile size is a power of 2).
 */
#include "qibl/shmtile.h"
#include "qibli.h"

/* with the light paths (QIBL_USE_LIGHTPATH): the adaptive-k unshadowed maps serve them and free lamps;
 * a small build (QIBL_CONFIG_SMALL) without them stays within its 16 KiB */
#if QIBL_USE_SHMAP && QIBL_USE_LIGHTPATH

/* bytes of tile (tx, ty) with k maps (at most 25 * 3 * 256: 32-bit products, no 64-bit multiply,
 * which Cortex-M0 would call a library routine for) */
static uint32_t tile_bytes(uint32_t w, uint32_t h, uint32_t tx, uint32_t ty, uint32_t k, uint32_t ch)
{
    uint32_t x0 = tx * QIBL_SHMTILE_SIZE, y0 = ty * QIBL_SHMTILE_SIZE;
    uint32_t tw = w - x0 < QIBL_SHMTILE_SIZE ? w - x0 : QIBL_SHMTILE_SIZE;
    uint32_t th = h - y0 < QIBL_SHMTILE_SIZE ? h - y0 : QIBL_SHMTILE_SIZE;
    return k * ch * tw * th;
}

qibl_status_t qibl_shmtile_parse(const uint8_t *data, size_t size, qibl_shmtile_t *out)
{
    if (data == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    if (size < QIBL_SHMTILE_HEADER)
        return QIBL_E_ASSET_CHUNK_SIZE;
    uint32_t w = qibl_load_u32le(data), h = qibl_load_u32le(data + 4), kmax = qibl_load_u32le(data + 8);
    uint32_t ch = qibl_load_u32le(data + 12);
    if (w - 1u >= QIBL_ASSET_MAX_DIM || h - 1u >= QIBL_ASSET_MAX_DIM || w * h > QIBL_ASSET_MAX_PIXELS)
        return QIBL_E_ASSET_BAD_DIMENSIONS;
    if (kmax - 1u >= 25u)
        return QIBL_E_ASSET_BAD_K;
    if (ch != 1u && ch != 3u)
        return QIBL_E_ASSET_BAD_CHANNELS;
    if (qibl_load_u32le(data + 16) != QIBL_SHMTILE_SIZE || qibl_load_u32le(data + 20) != 0u)
        return QIBL_E_ASSET_BAD_FLAGS;
    uint32_t tx = (w + QIBL_SHMTILE_SIZE - 1u) >> 4, ty = (h + QIBL_SHMTILE_SIZE - 1u) >> 4, nt = tx * ty;
    uint32_t kpad = (nt + 3u) & ~3u;
    /* nt <= 2^20 and kmax * ch <= 75 after the checks above: every term fits 32 bits */
    uint64_t fixed = (uint64_t)QIBL_SHMTILE_HEADER + 8u * kmax * ch + kpad + (uint64_t)(4u * nt);
    if ((uint64_t)size < fixed)
        return QIBL_E_ASSET_CHUNK_SIZE;
    const uint8_t *params = data + QIBL_SHMTILE_HEADER;
    const uint8_t *ks = params + 8u * kmax * ch, *offs = ks + kpad, *d = offs + 4u * (size_t)nt;
    for (uint32_t i = nt; i < kpad; ++i)
        if (ks[i] != 0u)
            return QIBL_E_ASSET_BAD_FLAGS;
    /* the tiles' k and the offsets against the running sum (below 2^26 * 75, so exact in 64 bits) */
    uint64_t at = 0;
    for (uint32_t j = 0; j < ty; ++j)
        for (uint32_t i = 0; i < tx; ++i) {
            uint32_t t = j * tx + i, k = ks[t];
            if (k - 1u >= kmax)
                return QIBL_E_ASSET_BAD_K;
            if ((uint64_t)qibl_load_u32le(offs + 4u * t) != at)
                return QIBL_E_ASSET_CHUNK_SIZE;
            at += tile_bytes(w, h, i, j, k, ch);
        }
    if (fixed + at != (uint64_t)size)
        return QIBL_E_ASSET_CHUNK_SIZE;
    out->width = w, out->height = h, out->kmax = kmax, out->channels = ch, out->tiles_x = tx, out->tiles_y = ty;
    out->params = params, out->ks = ks, out->offsets = offs, out->data = d;
    return QIBL_OK;
}

#if QIBL_USE_ASSET
qibl_status_t qibl_shmtile_from_asset(const qibl_asset_t *a, qibl_shmtile_t *out)
{
    qibl_chunk_t c;
    qibl_shmaps_t m;
    qibl_shmtile_t t;
    if (a == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    qibl_status_t st = qibli_asset_sole_chunk(a, QIBL_CHUNK_SHMT, &c, &m);
    if (st == QIBL_OK)
        st = qibl_shmtile_parse(c.data, c.size, &t);
    if (st != QIBL_OK)
        return st;
    if (t.width != m.width || t.height != m.height)
        return QIBL_E_ASSET_MISMATCH;
    out->width = t.width, out->height = t.height, out->kmax = t.kmax, out->channels = t.channels;
    out->tiles_x = t.tiles_x, out->tiles_y = t.tiles_y;
    out->params = t.params, out->ks = t.ks, out->offsets = t.offsets, out->data = t.data;
    return QIBL_OK;
}
#endif

qibl_status_t qibl_shmtile_view(const qibl_shmtile_t *t, uint32_t tx, uint32_t ty, qibl_shmaps_t *view, uint32_t *x0,
                                uint32_t *y0)
{
    if (t == 0 || view == 0)
        return QIBL_E_NULL_POINTER;
    if (tx >= t->tiles_x || ty >= t->tiles_y)
        return QIBL_E_SHMAP_BOUNDS;
    uint32_t i = ty * t->tiles_x + tx, px = tx * QIBL_SHMTILE_SIZE, py = ty * QIBL_SHMTILE_SIZE;
    view->width = t->width - px < QIBL_SHMTILE_SIZE ? t->width - px : QIBL_SHMTILE_SIZE;
    view->height = t->height - py < QIBL_SHMTILE_SIZE ? t->height - py : QIBL_SHMTILE_SIZE;
    view->k = t->ks[i], view->channels = t->channels, view->layout = QIBL_SHMAPS_PLANAR;
    view->params = t->params;
    view->planes = t->data + qibl_load_u32le(t->offsets + 4u * i);
    if (x0)
        *x0 = px;
    if (y0)
        *y0 = py;
    return QIBL_OK;
}

#else
typedef int qibl_shmtile_disabled_t; /* ISO C forbids an empty translation unit */
#endif /* QIBL_USE_SHMAP && QIBL_USE_LIGHTPATH */
