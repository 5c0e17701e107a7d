/*
 * shmaps.c - accessors of the SH-map, P-map and Y-LUT views (shmaps.h), in either map layout.
 *
 * Invariants: no checks on the hot accessors (the view is valid, indices in range); sizes in
 * size_t from factors each below 2^15, so products of three cannot wrap a 32-bit size_t until the
 * image itself would not fit the address space (width <= 2^14, k * channels <= 75).
 */
#include "qibl/shmaps.h"

#if QIBL_USE_SHMAP || QIBL_USE_ASSET

qibl_q24_t qibl_shmaps_scale(const qibl_shmaps_t *m, uint32_t i, uint32_t ch)
{
    return qibl_load_s32le(m->params + 8u * (i * m->channels + ch));
}

qibl_q24_t qibl_shmaps_bias(const qibl_shmaps_t *m, uint32_t i, uint32_t ch)
{
    return qibl_load_s32le(m->params + 8u * (i * m->channels + ch) + 4u);
}

const uint8_t *qibl_shmaps_plane(const qibl_shmaps_t *m, uint32_t i, uint32_t ch)
{
    return m->planes + (size_t)(i * m->channels + ch) * ((size_t)m->width * m->height);
}

size_t qibl_shmaps_row_size(const qibl_shmaps_t *m)
{
    if (m == 0 || m->k - 1u >= 25u || (m->channels != 1u && m->channels != 3u) || m->width - 1u >= 16384u)
        return 0u;
    size_t per_px = (size_t)m->k * m->channels;
    if (m->layout == QIBL_SHMAPS_PLANAR)
        return per_px * m->width;
    if (QIBL_USE_INTERLEAVED && m->layout == QIBL_SHMAPS_INTERLEAVED)
        return per_px * ((m->width + QIBL_SHMAPS_GROUP - 1u) / QIBL_SHMAPS_GROUP * QIBL_SHMAPS_GROUP);
    return 0u;
}

uint8_t qibl_shmaps_texel(const qibl_shmaps_t *m, uint32_t i, uint32_t ch, uint32_t x, uint32_t y)
{
    if (m->layout == QIBL_SHMAPS_INTERLEAVED) {
        size_t kc = (size_t)m->k * m->channels;
        return m->planes[y * qibl_shmaps_row_size(m) + (x / QIBL_SHMAPS_GROUP) * QIBL_SHMAPS_GROUP * kc +
                         (ch * m->k + i) * QIBL_SHMAPS_GROUP + x % QIBL_SHMAPS_GROUP];
    }
    return qibl_shmaps_plane(m, i, ch)[(size_t)y * m->width + x];
}

void qibl_pmap_point(const qibl_pmap_t *p, uint32_t x, uint32_t y, qibl_q16_t out[3])
{
    const uint8_t *q = p->points + 12u * ((size_t)y * p->width + x);
    out[0] = qibl_load_s32le(q);
    out[1] = qibl_load_s32le(q + 4);
    out[2] = qibl_load_s32le(q + 8);
}

/* Views are filled field by field: a struct copy may become a memcpy call on freestanding targets. */
qibl_status_t qibl_shmaps_row_view(const qibl_shmaps_t *m, const uint8_t *row, qibl_shmaps_t *out)
{
    if (m == 0 || row == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    out->width = m->width;
    out->height = 1u;
    out->k = m->k;
    out->channels = m->channels;
    out->params = m->params;
    out->planes = row;
    out->layout = m->layout;
    return QIBL_OK;
}

qibl_status_t qibl_pmap_row_view(const qibl_pmap_t *p, const uint8_t *row, qibl_pmap_t *out)
{
    if (p == 0 || row == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    out->width = p->width;
    out->height = 1u;
    out->points = row;
    return QIBL_OK;
}

#if QIBL_USE_INTERLEAVED
qibl_status_t qibl_shmaps_interleave(const qibl_shmaps_t *m, uint8_t *out, size_t out_size)
{
    if (m == 0 || out == 0 || m->planes == 0)
        return QIBL_E_NULL_POINTER;
    if (m->layout != QIBL_SHMAPS_PLANAR)
        return QIBL_E_SHMAP_LAYOUT;
    if (m->k - 1u >= 25u)
        return QIBL_E_SHMAP_K;
    if (m->channels != 1u && m->channels != 3u)
        return QIBL_E_SHMAP_CHANNELS;
    if (m->width - 1u >= 16384u || m->height - 1u >= 16384u)
        return QIBL_E_SHMAP_SIZE;
    const uint32_t k = m->k, C = m->channels, gw = (m->width + QIBL_SHMAPS_GROUP - 1u) / QIBL_SHMAPS_GROUP;
    const size_t row = (size_t)gw * QIBL_SHMAPS_GROUP * k * C;
    /* row <= 1025 * 16 * 75 < 2^21: the product is exact (and no division: Cortex-M0 has none) */
    if (qibl_mul_u32_u64((uint32_t)row, m->height) > out_size)
        return QIBL_E_WORKSPACE;
    for (uint32_t y = 0; y < m->height; ++y)
        for (uint32_t g = 0; g < gw; ++g)
            for (uint32_t ch = 0; ch < C; ++ch)
                for (uint32_t i = 0; i < k; ++i) {
                    uint8_t *o = out + y * row + ((size_t)(g * C + ch) * k + i) * QIBL_SHMAPS_GROUP;
                    const uint8_t *src = qibl_shmaps_plane(m, i, ch) + (size_t)y * m->width;
                    for (uint32_t p = 0; p < QIBL_SHMAPS_GROUP; ++p) {
                        uint32_t x = g * QIBL_SHMAPS_GROUP + p;
                        o[p] = x < m->width ? src[x] : 0u; /* assignments: a zeroing loop becomes memset */
                    }
                }
    return QIBL_OK;
}
#endif /* QIBL_USE_INTERLEAVED */

#else
typedef int qibl_shmaps_disabled_t; /* ISO C forbids an empty translation unit */
#endif /* QIBL_USE_SHMAP || QIBL_USE_ASSET */
