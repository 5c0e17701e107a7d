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

qibl_status_t qibl_crc32_table_init(uint32_t *table, size_t words)
{
    if (table == 0)
        return QIBL_E_NULL_POINTER;
    if (words < QIBL_CRC32_TABLE_WORDS)
        return QIBL_E_WORKSPACE;
    /* table j, entry i: the CRC register after byte i followed by j zero bytes */
    for (uint32_t i = 0; i < 256u; ++i) {
        uint32_t c = i;
        c = (c >> 4) ^ crc_nibble[c & 15u];
        table[i] = (c >> 4) ^ crc_nibble[c & 15u];
    }
    for (uint32_t i = 256u; i < QIBL_CRC32_TABLE_WORDS; ++i)
        table[i] = (table[i - 256u] >> 8) ^ table[table[i - 256u] & 255u];
    return QIBL_OK;
}

uint32_t qibl_crc32_fast(const uint32_t *t, uint32_t crc, const uint8_t *data, size_t n)
{
    crc = ~crc;
    /* eight bytes per step: the register's four bytes and the next four each look up the table
     * that carries them past the rest of the step (byte loads: any alignment, any byte order) */
    for (; n >= 8u; n -= 8u, data += 8) {
        uint32_t a = crc ^ qibl_load_u32le(data), b = qibl_load_u32le(data + 4);
        crc = t[1792u + (a & 255u)] ^ t[1536u + ((a >> 8) & 255u)] ^ t[1280u + ((a >> 16) & 255u)] ^
              t[1024u + (a >> 24)] ^ t[768u + (b & 255u)] ^ t[512u + ((b >> 8) & 255u)] ^
              t[256u + ((b >> 16) & 255u)] ^ t[b >> 24];
    }
    for (; n > 0u; --n)
        crc = (crc >> 8) ^ t[(crc ^ *data++) & 255u];
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

/* SHMP fields; on success *pixels = width * height, *k = k and *layout the map layout (all
 * validated). Reads only the 20 fixed bytes: the head of a streamed asset suffices. */
static qibl_status_t check_shmp(const uint8_t *p, uint32_t size, uint32_t *pixels, uint32_t *k_out, uint32_t *layout)
{
    if (size < 20u)
        return QIBL_E_ASSET_CHUNK_SIZE;
    uint32_t w = qibl_load_u32le(p), h = qibl_load_u32le(p + 4), k = qibl_load_u32le(p + 8);
    uint32_t ch = qibl_load_u32le(p + 12), flags = qibl_load_u32le(p + 16);
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
    if (flags != 0u && (!QIBL_USE_INTERLEAVED || flags != QIBL_SHMP_FLAG_INTERLEAVED))
        return QIBL_E_ASSET_BAD_FLAGS;
    uint32_t planes = k * ch; /* <= 75 */
    /* interleaved rows are padded to whole groups of 16: h * padded w <= 2^14 (2^14 + 15) < 2^29 */
    uint32_t cells = (flags & QIBL_SHMP_FLAG_INTERLEAVED) ? h * ((w + 15u) & ~15u) : px;
    uint64_t need = 20u + 8u * planes + qibl_mul_u32_u64(cells, planes);
    if (need > UINT32_MAX)
        return QIBL_E_ASSET_SIZE_OVERFLOW;
    if (need != size)
        return QIBL_E_ASSET_CHUNK_SIZE;
    *pixels = px;
    *k_out = k;
    *layout = (flags & QIBL_SHMP_FLAG_INTERLEAVED) ? QIBL_SHMAPS_INTERLEAVED : QIBL_SHMAPS_PLANAR;
    return QIBL_OK;
}

/* PMAP payload bytes for px pixels (px <= 2^26 validated: 12 + 12 * 2^26 < 2^30). */
static uint32_t pmap_size(uint32_t px)
{
    return 12u + 12u * px;
}

/* PMAP fields against SHMP's width sw and height sh (validated, so sw * sh <= 2^26). The full open
 * and the streamed head (qibl_asset_head_pmap) both check through here. */
static qibl_status_t check_pmap(const uint8_t *p, uint32_t size, uint32_t sw, uint32_t sh)
{
    if (size < 12u)
        return QIBL_E_ASSET_CHUNK_SIZE;
    uint32_t w = qibl_load_u32le(p), h = qibl_load_u32le(p + 4);
    if (w - 1u >= QIBL_ASSET_MAX_DIM || h - 1u >= QIBL_ASSET_MAX_DIM)
        return QIBL_E_ASSET_BAD_DIMENSIONS;
    if (w != sw || h != sh)
        return QIBL_E_ASSET_MISMATCH;
    if (qibl_load_u32le(p + 8) != 0u)
        return QIBL_E_ASSET_BAD_FLAGS;
    if (size != pmap_size(sw * sh))
        return QIBL_E_ASSET_CHUNK_SIZE;
    return QIBL_OK;
}

/* YLUT fields against SHMP's k; the full open and qibl_asset_head_ylut both check through here. */
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

/* The view of a checked YLUT payload of size bytes (check_ylut passed: size = 12 + 12 N N k). */
static void ylut_view(const uint8_t *p, uint32_t size, qibl_ylut_t *out)
{
    out->face_size = qibl_load_u32le(p);
    out->k = qibl_load_u32le(p + 4);
    out->values = p + 12;
    out->size = size - 12u;
}

/* Header fields (needs n >= 24): magic, version, chunk count; *table_end and *file_size. */
static qibl_status_t check_header(const uint8_t *b, uint32_t *count, uint32_t *table_end, uint32_t *file_size)
{
    for (unsigned i = 0; i < 8u; ++i)
        if (b[i] != asset_magic[i])
            return QIBL_E_ASSET_MAGIC;
    if (qibl_load_u32le(b + 8) != QIBL_ASSET_VERSION)
        return QIBL_E_ASSET_VERSION;
    uint32_t c = qibl_load_u32le(b + 12);
    if (c - 1u >= QIBL_ASSET_MAX_CHUNKS)
        return QIBL_E_ASSET_CHUNK_COUNT;
    *count = c;
    *table_end = QIBL_ASSET_HEADER_SIZE + QIBL_ASSET_ENTRY_SIZE * c; /* <= 1048 */
    *file_size = qibl_load_u32le(b + 16);
    if (*file_size < *table_end)
        return QIBL_E_ASSET_TRUNCATED_TABLE;
    return QIBL_OK;
}

/* Table CRC, then every entry's alignment and bounds, then duplicates and overlaps against the
 * earlier entries (needs the whole table in b). */
static qibl_status_t check_table(const uint8_t *b, uint32_t count, uint32_t table_end, uint32_t file_size)
{
    /* CRC first, so the entries below are the ones the writer meant */
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
    if (find_entry(b, count, QIBL_CHUNK_SHMP) == 0)
        return QIBL_E_ASSET_MISSING_CHUNK;
    return QIBL_OK;
}

/* How payload CRCs are checked */
enum { CRC_NIBBLE, CRC_TABLE, CRC_NONE };

static qibl_status_t open_asset(qibl_asset_t *out, const void *bytes, size_t n, int crc_mode, const uint32_t *crc_table)
{
    const uint8_t *b = (const uint8_t *)bytes;
    if (out == 0 || b == 0 || (crc_mode == CRC_TABLE && crc_table == 0))
        return QIBL_E_NULL_POINTER;

    if (n < QIBL_ASSET_HEADER_SIZE)
        return QIBL_E_ASSET_TRUNCATED_HEADER;
    uint32_t count = 0, table_end = 0, file_size = 0;
    qibl_status_t st = check_header(b, &count, &table_end, &file_size);
    if (st != QIBL_OK)
        return st;
    if (n < table_end)
        return QIBL_E_ASSET_TRUNCATED_TABLE;
    if (n < file_size)
        return QIBL_E_ASSET_TRUNCATED;
    if ((st = check_table(b, count, table_end, file_size)) != QIBL_OK)
        return st;
    for (uint32_t i = 0; i < count && crc_mode != CRC_NONE; ++i) {
        const uint8_t *e = b + QIBL_ASSET_HEADER_SIZE + QIBL_ASSET_ENTRY_SIZE * i;
        const uint8_t *p = b + qibl_load_u32le(e + 4);
        uint32_t size = qibl_load_u32le(e + 8);
        uint32_t crc = crc_mode == CRC_TABLE ? qibl_crc32_fast(crc_table, 0u, p, size) : qibl_crc32(0u, p, size);
        if (crc != qibl_load_u32le(e + 12))
            return QIBL_E_ASSET_CHUNK_CRC;
    }

    /* payloads of the known chunks */
    const uint8_t *shmp_e = find_entry(b, count, QIBL_CHUNK_SHMP);
    const uint8_t *shmp = b + qibl_load_u32le(shmp_e + 4);
    uint32_t px = 0, k = 0, layout = 0;
    st = check_shmp(shmp, qibl_load_u32le(shmp_e + 8), &px, &k, &layout);
    if (st != QIBL_OK)
        return st;
    const uint8_t *e = find_entry(b, count, QIBL_CHUNK_PMAP);
    if (e != 0 && (st = check_pmap(b + qibl_load_u32le(e + 4), qibl_load_u32le(e + 8), qibl_load_u32le(shmp),
                                   qibl_load_u32le(shmp + 4))) != QIBL_OK)
        return st;
    e = find_entry(b, count, QIBL_CHUNK_YLUT);
    if (e != 0 && (st = check_ylut(b + qibl_load_u32le(e + 4), qibl_load_u32le(e + 8), k)) != QIBL_OK)
        return st;
    e = find_entry(b, count, QIBL_CHUNK_SHMU);
    if (e != 0) {
        const uint8_t *u = b + qibl_load_u32le(e + 4);
        uint32_t upx = 0, uk = 0, ulayout = 0;
        if ((st = check_shmp(u, qibl_load_u32le(e + 8), &upx, &uk, &ulayout)) != QIBL_OK)
            return st;
        if (qibl_load_u32le(u) != qibl_load_u32le(shmp) || qibl_load_u32le(u + 4) != qibl_load_u32le(shmp + 4))
            return QIBL_E_ASSET_MISMATCH;
    }

    out->base = b;
    out->size = file_size;
    out->chunk_count = count;
    return QIBL_OK;
}

qibl_status_t qibl_asset_open(qibl_asset_t *out, const void *bytes, size_t n)
{
    return open_asset(out, bytes, n, CRC_NIBBLE, 0);
}

qibl_status_t qibl_asset_open_crc_table(qibl_asset_t *out, const void *bytes, size_t n, const uint32_t *crc_table)
{
    return open_asset(out, bytes, n, CRC_TABLE, crc_table);
}

qibl_status_t qibl_asset_open_structure(qibl_asset_t *out, const void *bytes, size_t n)
{
    return open_asset(out, bytes, n, CRC_NONE, 0);
}

#if QIBL_USE_INTERLEAVED
/* ---- streaming by rows ----------------------------------------------------------------------- */

/* The head checks; *need = leading bytes needed so far. On QIBL_OK with *need <= n the whole head
 * was checked and *shmp_e is SHMP's entry; px, k, layout are SHMP's. */
static qibl_status_t parse_head(const uint8_t *b, size_t n, size_t *need, const uint8_t **shmp_e, uint32_t *px,
                                uint32_t *k, uint32_t *layout)
{
    *need = QIBL_ASSET_HEADER_SIZE;
    if (n < QIBL_ASSET_HEADER_SIZE)
        return QIBL_OK;
    uint32_t count = 0, table_end = 0, file_size = 0;
    qibl_status_t st = check_header(b, &count, &table_end, &file_size);
    if (st != QIBL_OK)
        return st;
    *need = table_end;
    if (n < table_end)
        return QIBL_OK;
    if ((st = check_table(b, count, table_end, file_size)) != QIBL_OK)
        return st;
    const uint8_t *e = find_entry(b, count, QIBL_CHUNK_SHMP);
    uint32_t off = qibl_load_u32le(e + 4), size = qibl_load_u32le(e + 8);
    if (size < 20u)
        return QIBL_E_ASSET_CHUNK_SIZE;
    *need = (size_t)off + 20u;
    if (n < *need)
        return QIBL_OK;
    if ((st = check_shmp(b + off, size, px, k, layout)) != QIBL_OK)
        return st;
    *need = (size_t)off + 20u + 8u * *k * qibl_load_u32le(b + off + 12);
    *shmp_e = e;
    return QIBL_OK;
}

qibl_status_t qibl_asset_head_size(const void *head, size_t n, size_t *need)
{
    const uint8_t *e = 0;
    uint32_t px = 0, k = 0, layout = 0;
    size_t nd = 0;
    if (need == 0 || (head == 0 && n != 0u))
        return QIBL_E_NULL_POINTER;
    qibl_status_t st = parse_head((const uint8_t *)head, n, &nd, &e, &px, &k, &layout);
    if (st == QIBL_OK)
        *need = nd;
    return st;
}

qibl_status_t qibl_asset_open_head(qibl_asset_head_t *out, const void *head, size_t n)
{
    const uint8_t *b = (const uint8_t *)head, *se = 0;
    uint32_t px = 0, k = 0, layout = 0;
    size_t need = 0;
    if (out == 0 || b == 0)
        return QIBL_E_NULL_POINTER;
    qibl_status_t st = parse_head(b, n, &need, &se, &px, &k, &layout);
    if (st != QIBL_OK)
        return st;
    if (need > n)
        return QIBL_E_ASSET_HEAD_SHORT;
    if (layout != QIBL_SHMAPS_INTERLEAVED)
        return QIBL_E_ASSET_LAYOUT;
    uint32_t count = qibl_load_u32le(b + 12), soff = qibl_load_u32le(se + 4);
    const uint8_t *shmp = b + soff;
    /* PMAP and YLUT: their sizes against SHMP, from the table; their fields are not in the head and
     * are checked when loaded (qibl_asset_head_pmap, qibl_asset_head_ylut: the same checks) */
    const uint8_t *pe = find_entry(b, count, QIBL_CHUNK_PMAP), *ye = find_entry(b, count, QIBL_CHUNK_YLUT);
    if (pe != 0 && qibl_load_u32le(pe + 8) != pmap_size(px))
        return QIBL_E_ASSET_CHUNK_SIZE;
    if (ye != 0 && qibl_load_u32le(ye + 8) < 12u)
        return QIBL_E_ASSET_CHUNK_SIZE;
    uint32_t ch = qibl_load_u32le(shmp + 12);
    out->maps.width = qibl_load_u32le(shmp);
    out->maps.height = qibl_load_u32le(shmp + 4);
    out->maps.k = k;
    out->maps.channels = ch;
    out->maps.params = shmp + 20;
    out->maps.planes = 0;
    out->maps.layout = layout;
    out->file_size = qibl_load_u32le(b + 16);
    out->maps_offset = soff + 20u + 8u * k * ch;
    out->row_size = (uint32_t)qibl_shmaps_row_size(&out->maps);
    out->pmap_offset = pe != 0 ? qibl_load_u32le(pe + 4) + 12u : 0u;
    out->ylut_offset = ye != 0 ? qibl_load_u32le(ye + 4) : 0u;
    out->ylut_size = ye != 0 ? qibl_load_u32le(ye + 8) : 0u;
    return QIBL_OK;
}

qibl_status_t qibl_asset_row(const qibl_asset_head_t *h, uint32_t y, qibl_asset_row_t *out)
{
    if (h == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    if (y >= h->maps.height)
        return QIBL_E_ASSET_ROW;
    /* both within the validated chunks, so below file_size < 2^32 */
    out->maps_offset = h->maps_offset + y * h->row_size;
    out->maps_size = h->row_size;
    out->pmap_offset = h->pmap_offset != 0u ? h->pmap_offset + 12u * h->maps.width * y : 0u;
    out->pmap_size = h->pmap_offset != 0u ? 12u * h->maps.width : 0u;
    return QIBL_OK;
}

qibl_status_t qibl_asset_head_pmap(const qibl_asset_head_t *h, const void *fields, size_t n, qibl_pmap_t *out)
{
    const uint8_t *p = (const uint8_t *)fields;
    if (h == 0 || p == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    if (h->pmap_offset == 0u)
        return QIBL_E_ASSET_MISSING_CHUNK;
    if (n < 12u)
        return QIBL_E_ASSET_HEAD_SHORT;
    /* the payload size was checked against SHMP by qibl_asset_open_head */
    qibl_status_t st = check_pmap(p, pmap_size(h->maps.width * h->maps.height), h->maps.width, h->maps.height);
    if (st != QIBL_OK)
        return st;
    out->width = h->maps.width;
    out->height = h->maps.height;
    out->points = 0; /* rows stream: qibl_pmap_row_view */
    return QIBL_OK;
}

qibl_status_t qibl_asset_head_ylut(const qibl_asset_head_t *h, const void *payload, size_t n, qibl_ylut_t *out)
{
    const uint8_t *p = (const uint8_t *)payload;
    if (h == 0 || p == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    if (h->ylut_size == 0u)
        return QIBL_E_ASSET_MISSING_CHUNK;
    if (n < h->ylut_size)
        return QIBL_E_ASSET_HEAD_SHORT;
    qibl_status_t st = check_ylut(p, h->ylut_size, h->maps.k);
    if (st == QIBL_OK)
        ylut_view(p, h->ylut_size, out);
    return st;
}
#endif /* QIBL_USE_INTERLEAVED */

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
    out->layout = (qibl_load_u32le(p + 16) & QIBL_SHMP_FLAG_INTERLEAVED) ? QIBL_SHMAPS_INTERLEAVED : QIBL_SHMAPS_PLANAR;
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
    qibl_chunk_t c;
    if (out == 0)
        return QIBL_E_NULL_POINTER;
    qibl_status_t st = qibl_asset_find(a, QIBL_CHUNK_YLUT, &c);
    if (st == QIBL_OK)
        ylut_view(c.data, c.size, out);
    return st;
}

#else
typedef int qibl_asset_disabled_t; /* ISO C forbids an empty translation unit */
#endif /* QIBL_USE_ASSET */
