/*
 * asset.c - the qibl asset container: validation once, then zero-copy typed views.
 *
 * Invariants: every read is a byte load (qibl_load_*le), so the caller's buffer may have any
 * alignment and the host any byte order. Every size is checked before the bytes it covers are
 * touched: header, then table, then each entry's bounds, then CRCs, then the payload fields. Sums of
 * offsets and sizes are formed in 64 bits (u32 + u32 cannot wrap there); the one product that can
 * exceed 32 bits (pixels * planes of SHMP) goes through qibl_mul_u32_u64, so Cortex-M0 needs no
 * __aeabi_lmul. All other products have small validated factors and stay below 2^31.
 * qibl_asset_open writes *out only after every check passed.
 */
#include <stdbool.h>
#include "qibl/asset.h"

#if QIBL_USE_ASSET

/* CRC-32 of one nibble (reflected polynomial 0xEDB88320): crc_nibble[i] = crc of i over 4 bits. */
static const uint32_t crc_nibble[16] = {
    0x00000000u, 0x1DB71064u, 0x3B6E20C8u, 0x26D930ACu, 0x76DC4190u, 0x6B6B51F4u, 0x4DB26158u, 0x5005713Cu,
    0xEDB88320u, 0xF00F9344u, 0xD6D6A3E8u, 0xCB61B38Cu, 0x9B64C2B0u, 0x86D3D2D4u, 0xA00AE278u, 0xBDBDF21Cu,
};

static const uint8_t asset_magic[8] = {'Q', 'I', 'B', 'L', '\r', '\n', 0x1A, '\n'};

uint32_t qibl_crc32(uint32_t crc, const uint8_t *data, size_t n)
{
    crc = ~crc;
    for (size_t i = 0; i < n; ++i) {
        crc ^= data[i];
        crc = (crc >> 4) ^ crc_nibble[crc & 15u];
        crc = (crc >> 4) ^ crc_nibble[crc & 15u];
    }
    return ~crc;
}

static bool known_type(uint32_t type)
{
    return type == QIBL_CHUNK_SHMP || type == QIBL_CHUNK_PMAP || type == QIBL_CHUNK_YLUT || type == QIBL_CHUNK_SHMU;
}

/* The table entry of the first chunk of the given type, or NULL. */
static const uint8_t *find_entry(const uint8_t *base, uint32_t count, uint32_t type)
{
    for (uint32_t i = 0; i < count; ++i) {
        const uint8_t *e = base + QIBL_ASSET_HEADER_SIZE + QIBL_ASSET_ENTRY_SIZE * i;
        if (qibl_load_u32le(e) == type)
            return e;
    }
    return 0;
}

/* SHMP fields; on success *pixels = width * height and *k = k (both validated). */
static qibl_status_t check_shmp(const uint8_t *p, uint32_t size, uint32_t *pixels, uint32_t *k_out)
{
    if (size < 20u)
        return QIBL_E_ASSET_CHUNK_SIZE;
    uint32_t w = qibl_load_u32le(p), h = qibl_load_u32le(p + 4), k = qibl_load_u32le(p + 8);
    uint32_t ch = qibl_load_u32le(p + 12);
    /* w - 1 wraps to UINT32_MAX for w == 0: one compare rejects zero and too large */
    if (w - 1u >= QIBL_ASSET_MAX_DIM || h - 1u >= QIBL_ASSET_MAX_DIM)
        return QIBL_E_ASSET_BAD_DIMENSIONS;
    uint32_t px = w * h; /* both <= 2^14: exact in 32 bits */
    if (px > QIBL_ASSET_MAX_PIXELS)
        return QIBL_E_ASSET_BAD_DIMENSIONS;
    if (k - 1u >= 25u)
        return QIBL_E_ASSET_BAD_K;
    if (ch != 1u && ch != 3u)
        return QIBL_E_ASSET_BAD_CHANNELS;
    if (qibl_load_u32le(p + 16) != 0u)
        return QIBL_E_ASSET_BAD_FLAGS;
    uint32_t planes = k * ch; /* <= 75 */
    uint64_t need = 20u + 8u * planes + qibl_mul_u32_u64(px, planes);
    if (need > UINT32_MAX)
        return QIBL_E_ASSET_SIZE_OVERFLOW;
    if (need != size)
        return QIBL_E_ASSET_CHUNK_SIZE;
    *pixels = px;
    *k_out = k;
    return QIBL_OK;
}

/* PMAP fields against SHMP's width and height (whose product px <= 2^26 was validated). */
static qibl_status_t check_pmap(const uint8_t *p, uint32_t size, const uint8_t *shmp, uint32_t px)
{
    if (size < 12u)
        return QIBL_E_ASSET_CHUNK_SIZE;
    uint32_t w = qibl_load_u32le(p), h = qibl_load_u32le(p + 4);
    if (w - 1u >= QIBL_ASSET_MAX_DIM || h - 1u >= QIBL_ASSET_MAX_DIM)
        return QIBL_E_ASSET_BAD_DIMENSIONS;
    if (w != qibl_load_u32le(shmp) || h != qibl_load_u32le(shmp + 4))
        return QIBL_E_ASSET_MISMATCH;
    if (qibl_load_u32le(p + 8) != 0u)
        return QIBL_E_ASSET_BAD_FLAGS;
    if (size != 12u + 12u * px) /* <= 12 + 12 * 2^26 < 2^30 */
        return QIBL_E_ASSET_CHUNK_SIZE;
    return QIBL_OK;
}

/* YLUT fields against SHMP's k. */
static qibl_status_t check_ylut(const uint8_t *p, uint32_t size, uint32_t shmp_k)
{
    if (size < 12u)
        return QIBL_E_ASSET_CHUNK_SIZE;
    uint32_t n = qibl_load_u32le(p), k = qibl_load_u32le(p + 4);
    if (n - 1u >= QIBL_ASSET_MAX_LUT)
        return QIBL_E_ASSET_BAD_DIMENSIONS;
    if (k - 1u >= 25u)
        return QIBL_E_ASSET_BAD_K;
    if (k < shmp_k)
        return QIBL_E_ASSET_MISMATCH;
    if (qibl_load_u32le(p + 8) != 0u)
        return QIBL_E_ASSET_BAD_FLAGS;
    if (size != 12u + 12u * n * n * k) /* <= 12 + 12 * 256^2 * 25 < 2^25 */
        return QIBL_E_ASSET_CHUNK_SIZE;
    return QIBL_OK;
}

qibl_status_t qibl_asset_open(qibl_asset_t *out, const void *bytes, size_t n)
{
    const uint8_t *b = (const uint8_t *)bytes;
    if (out == 0 || b == 0)
        return QIBL_E_NULL_POINTER;

    /* header */
    if (n < QIBL_ASSET_HEADER_SIZE)
        return QIBL_E_ASSET_TRUNCATED_HEADER;
    for (unsigned i = 0; i < 8u; ++i)
        if (b[i] != asset_magic[i])
            return QIBL_E_ASSET_MAGIC;
    if (qibl_load_u32le(b + 8) != QIBL_ASSET_VERSION)
        return QIBL_E_ASSET_VERSION;
    uint32_t count = qibl_load_u32le(b + 12);
    if (count - 1u >= QIBL_ASSET_MAX_CHUNKS)
        return QIBL_E_ASSET_CHUNK_COUNT;
    uint32_t file_size = qibl_load_u32le(b + 16);
    uint32_t table_end = QIBL_ASSET_HEADER_SIZE + QIBL_ASSET_ENTRY_SIZE * count; /* <= 1048 */
    if (n < table_end || file_size < table_end)
        return QIBL_E_ASSET_TRUNCATED_TABLE;
    if (n < file_size)
        return QIBL_E_ASSET_TRUNCATED;

    /* table: CRC first, so the entries below are the ones the writer meant */
    const uint8_t *table = b + QIBL_ASSET_HEADER_SIZE;
    if (qibl_crc32(0u, table, QIBL_ASSET_ENTRY_SIZE * count) != qibl_load_u32le(b + 20))
        return QIBL_E_ASSET_TABLE_CRC;
    for (uint32_t i = 0; i < count; ++i) {
        const uint8_t *e = table + QIBL_ASSET_ENTRY_SIZE * i;
        uint32_t type = qibl_load_u32le(e), off = qibl_load_u32le(e + 4), size = qibl_load_u32le(e + 8);
        if ((off & 3u) != 0u)
            return QIBL_E_ASSET_CHUNK_MISALIGNED;
        if (off < table_end || (uint64_t)off + size > file_size)
            return QIBL_E_ASSET_CHUNK_PAST_END;
        /* earlier entries passed the bound check, so every end below fits 32 bits */
        for (uint32_t j = 0; j < i; ++j) {
            const uint8_t *f = table + QIBL_ASSET_ENTRY_SIZE * j;
            uint32_t foff = qibl_load_u32le(f + 4), fsize = qibl_load_u32le(f + 8);
            if (type == qibl_load_u32le(f) && known_type(type))
                return QIBL_E_ASSET_DUPLICATE_CHUNK;
            /* empty payloads share no bytes with anything */
            if (size != 0u && fsize != 0u && off < foff + fsize && foff < off + size)
                return QIBL_E_ASSET_CHUNK_OVERLAP;
        }
    }
    const uint8_t *shmp_e = find_entry(b, count, QIBL_CHUNK_SHMP);
    if (shmp_e == 0)
        return QIBL_E_ASSET_MISSING_CHUNK;
    for (uint32_t i = 0; i < count; ++i) {
        const uint8_t *e = table + QIBL_ASSET_ENTRY_SIZE * i;
        if (qibl_crc32(0u, b + qibl_load_u32le(e + 4), qibl_load_u32le(e + 8)) != qibl_load_u32le(e + 12))
            return QIBL_E_ASSET_CHUNK_CRC;
    }

    /* payloads of the known chunks */
    const uint8_t *shmp = b + qibl_load_u32le(shmp_e + 4);
    uint32_t px = 0, k = 0;
    qibl_status_t st = check_shmp(shmp, qibl_load_u32le(shmp_e + 8), &px, &k);
    if (st != QIBL_OK)
        return st;
    const uint8_t *e = find_entry(b, count, QIBL_CHUNK_PMAP);
    if (e != 0 && (st = check_pmap(b + qibl_load_u32le(e + 4), qibl_load_u32le(e + 8), shmp, px)) != QIBL_OK)
        return st;
    e = find_entry(b, count, QIBL_CHUNK_YLUT);
    if (e != 0 && (st = check_ylut(b + qibl_load_u32le(e + 4), qibl_load_u32le(e + 8), k)) != QIBL_OK)
        return st;
    e = find_entry(b, count, QIBL_CHUNK_SHMU);
    if (e != 0) {
        const uint8_t *u = b + qibl_load_u32le(e + 4);
        uint32_t upx = 0, uk = 0;
        if ((st = check_shmp(u, qibl_load_u32le(e + 8), &upx, &uk)) != QIBL_OK)
            return st;
        if (qibl_load_u32le(u) != qibl_load_u32le(shmp) || qibl_load_u32le(u + 4) != qibl_load_u32le(shmp + 4))
            return QIBL_E_ASSET_MISMATCH;
    }

    out->base = b;
    out->size = file_size;
    out->chunk_count = count;
    return QIBL_OK;
}

qibl_status_t qibl_asset_find(const qibl_asset_t *a, uint32_t type, qibl_chunk_t *out)
{
    if (a == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    const uint8_t *e = find_entry(a->base, a->chunk_count, type);
    if (e == 0)
        return QIBL_E_ASSET_MISSING_CHUNK;
    out->type = type;
    out->size = qibl_load_u32le(e + 8);
    out->data = a->base + qibl_load_u32le(e + 4);
    return QIBL_OK;
}

/* The payload of a chunk of a validated asset, or the status of qibl_asset_find. */
static qibl_status_t payload(const qibl_asset_t *a, uint32_t type, const void *out, const uint8_t **p)
{
    qibl_chunk_t c;
    if (out == 0)
        return QIBL_E_NULL_POINTER;
    qibl_status_t st = qibl_asset_find(a, type, &c);
    if (st == QIBL_OK)
        *p = c.data;
    return st;
}

qibl_status_t qibl_asset_find_nth(const qibl_asset_t *a, uint32_t type, uint32_t index, qibl_chunk_t *out)
{
    if (a == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    for (uint32_t i = 0; i < a->chunk_count; ++i) {
        const uint8_t *e = a->base + QIBL_ASSET_HEADER_SIZE + QIBL_ASSET_ENTRY_SIZE * i;
        if (qibl_load_u32le(e) != type)
            continue;
        if (index-- == 0u) {
            out->type = type;
            out->size = qibl_load_u32le(e + 8);
            out->data = a->base + qibl_load_u32le(e + 4);
            return QIBL_OK;
        }
    }
    return QIBL_E_ASSET_MISSING_CHUNK;
}

/* SHMP and SHMU share one layout */
static qibl_status_t shmaps_of(const qibl_asset_t *a, uint32_t type, qibl_shmaps_t *out)
{
    const uint8_t *p = 0;
    qibl_status_t st = payload(a, type, out, &p);
    if (st != QIBL_OK)
        return st;
    out->width = qibl_load_u32le(p);
    out->height = qibl_load_u32le(p + 4);
    out->k = qibl_load_u32le(p + 8);
    out->channels = qibl_load_u32le(p + 12);
    out->params = p + 20;
    out->planes = p + 20u + 8u * out->k * out->channels;
    return QIBL_OK;
}

qibl_status_t qibl_asset_shmaps(const qibl_asset_t *a, qibl_shmaps_t *out)
{
    return shmaps_of(a, QIBL_CHUNK_SHMP, out);
}

qibl_status_t qibl_asset_shmaps_unshadowed(const qibl_asset_t *a, qibl_shmaps_t *out)
{
    return shmaps_of(a, QIBL_CHUNK_SHMU, out);
}

qibl_status_t qibl_asset_point_shmaps(const qibl_asset_t *a, qibl_shmaps_t *out)
{
    qibl_status_t st = shmaps_of(a, QIBL_CHUNK_SHMU, out);
    return st == QIBL_E_ASSET_MISSING_CHUNK ? shmaps_of(a, QIBL_CHUNK_SHMP, out) : st;
}

qibl_status_t qibl_asset_pmap(const qibl_asset_t *a, qibl_pmap_t *out)
{
    const uint8_t *p = 0;
    qibl_status_t st = payload(a, QIBL_CHUNK_PMAP, out, &p);
    if (st != QIBL_OK)
        return st;
    out->width = qibl_load_u32le(p);
    out->height = qibl_load_u32le(p + 4);
    out->points = p + 12;
    return QIBL_OK;
}

qibl_status_t qibl_asset_ylut(const qibl_asset_t *a, qibl_ylut_t *out)
{
    const uint8_t *p = 0;
    qibl_status_t st = payload(a, QIBL_CHUNK_YLUT, out, &p);
    if (st != QIBL_OK)
        return st;
    out->face_size = qibl_load_u32le(p);
    out->k = qibl_load_u32le(p + 4);
    out->values = p + 12;
    return QIBL_OK;
}

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

void qibl_pmap_point(const qibl_pmap_t *p, uint32_t x, uint32_t y, qibl_q16_t out[3])
{
    const uint8_t *q = p->points + 12u * ((size_t)y * p->width + x);
    out[0] = qibl_load_s32le(q);
    out[1] = qibl_load_s32le(q + 4);
    out[2] = qibl_load_s32le(q + 8);
}

#else
typedef int qibl_asset_disabled_t; /* ISO C forbids an empty translation unit */
#endif /* QIBL_USE_ASSET */
