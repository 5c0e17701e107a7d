/*
 * io/asset_write.c - hosted writer of the qibl asset container (see asset_write.h).
 *
 * Bytes are stored one at a time with shifts, so the output is little-endian on any host; signed
 * values go through uint32_t (a well-defined modular conversion), never through type punning.
 */
#include <errno.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/asset_write.h"
#include "io/atomic.h"
#include "qtool.h"

static int fail(qtool_asset_builder *b, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    qtool_verrf_at(b->err, sizeof b->err, NULL, 0, fmt, ap);
    va_end(ap);
    return -1;
}

void qtool_store_u32le(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
    p[2] = (uint8_t)(v >> 16);
    p[3] = (uint8_t)(v >> 24);
}

void qtool_store_s32le(uint8_t *p, int32_t v)
{
    qtool_store_u32le(p, (uint32_t)v);
}

void qtool_store_s16le(uint8_t *p, int16_t v)
{
    uint16_t u = (uint16_t)v;
    p[0] = (uint8_t)u;
    p[1] = (uint8_t)(u >> 8);
}

void qtool_asset_builder_init(qtool_asset_builder *b)
{
    memset(b, 0, sizeof *b);
}

void qtool_asset_builder_free(qtool_asset_builder *b)
{
    for (uint32_t i = 0; i < b->count; ++i)
        free(b->chunks[i].data);
    qtool_asset_builder_init(b);
}

int qtool_asset_builder_take(qtool_asset_builder *b, uint32_t type, uint8_t *data, size_t size)
{
    if (b->count >= QIBL_ASSET_MAX_CHUNKS) {
        free(data);
        return fail(b, "asset: more than %u chunks", QIBL_ASSET_MAX_CHUNKS);
    }
    if ((uint64_t)size > UINT32_MAX) {
        free(data);
        return fail(b, "asset: chunk of %zu bytes does not fit 32 bits", size);
    }
    b->chunks[b->count].type = type;
    b->chunks[b->count].data = data;
    b->chunks[b->count].size = size;
    b->count++;
    return 0;
}

int qtool_asset_builder_add(qtool_asset_builder *b, uint32_t type, const void *data, size_t size)
{
    uint8_t *copy = NULL;
    if (size > 0) {
        if ((uint64_t)size > UINT32_MAX)
            return fail(b, "asset: chunk of %zu bytes does not fit 32 bits", size);
        copy = malloc(size);
        if (!copy)
            return fail(b, "asset: out of memory");
        memcpy(copy, data, size);
    }
    return qtool_asset_builder_take(b, type, copy, size);
}

/* header + items * item_size bytes, or -1 if it does not fit 32 bits; items given as factors */
static int payload_alloc(qtool_asset_builder *b, const char *what, uint64_t header, uint64_t items,
                         uint64_t item_size, uint8_t **out, size_t *size)
{
    /* every factor is a u32 (or small), so checking items against the limit first avoids wrap */
    if (items > UINT32_MAX || header + items * item_size > UINT32_MAX)
        return fail(b, "asset: %s payload does not fit 32 bits", what);
    size_t n = (size_t)(header + items * item_size);
    uint8_t *p = calloc(n, 1);
    if (!p)
        return fail(b, "asset: %s payload: out of memory", what);
    *out = p;
    *size = n;
    return 0;
}

/* a PMAP or YLUT payload: its 12-byte head (a, b, 0) written, the items left to the caller */
static int table_payload(qtool_asset_builder *b, const char *what, uint32_t a, uint32_t bb, uint64_t items,
                         uint64_t item_size, uint8_t **out, size_t *size)
{
    if (payload_alloc(b, what, 12, items, item_size, out, size) != 0)
        return -1;
    qtool_store_u32le(*out, a);
    qtool_store_u32le(*out + 4, bb);
    qtool_store_u32le(*out + 8, 0);
    return 0;
}

int qtool_asset_shmp_payload(qtool_asset_builder *b, uint32_t w, uint32_t h, uint32_t k, uint32_t channels,
                            const int32_t *scale, const int32_t *bias, const uint8_t *planes,
                            uint8_t **out, size_t *size)
{
    return qtool_asset_shmp_payload_layout(b, w, h, k, channels, scale, bias, planes, QIBL_SHMAPS_PLANAR, out, size);
}

int qtool_asset_shmp_payload_layout(qtool_asset_builder *b, uint32_t w, uint32_t h, uint32_t k, uint32_t channels,
                                   const int32_t *scale, const int32_t *bias, const uint8_t *planes, uint32_t layout,
                                   uint8_t **out, size_t *size)
{
    uint64_t pairs = (uint64_t)k * channels, pixels = (uint64_t)w * h;
    if (layout != QIBL_SHMAPS_PLANAR && layout != QIBL_SHMAPS_INTERLEAVED)
        return fail(b, "asset: unknown SHMP layout %u", layout);
    /* interleaved rows are padded to whole groups of 16 pixels */
    uint64_t cells = layout == QIBL_SHMAPS_INTERLEAVED ? (uint64_t)h * ((w + 15ull) / 16 * 16) : pixels;
    if (pairs > UINT32_MAX || cells > UINT32_MAX || pairs * cells > UINT32_MAX)
        return fail(b, "asset: SHMP payload does not fit 32 bits");
    uint8_t *p = NULL;
    size_t n = 0;
    if (payload_alloc(b, "SHMP", 20, pairs, 8 + cells, &p, &n) != 0)
        return -1;
    qtool_store_u32le(p, w);
    qtool_store_u32le(p + 4, h);
    qtool_store_u32le(p + 8, k);
    qtool_store_u32le(p + 12, channels);
    qtool_store_u32le(p + 16, layout == QIBL_SHMAPS_INTERLEAVED ? QIBL_SHMP_FLAG_INTERLEAVED : 0u);
    for (uint64_t i = 0; i < pairs; ++i) {
        qtool_store_s32le(p + 20 + 8 * i, scale[i]);
        qtool_store_s32le(p + 24 + 8 * i, bias[i]);
    }
    if (layout == QIBL_SHMAPS_INTERLEAVED && pairs * cells > 0) {
        /* the core's own conversion (it checks k, channels and sizes; refuse what it refuses) */
        qibl_shmaps_t m = {w, h, k, channels, p + 20, planes, QIBL_SHMAPS_PLANAR};
        qibl_status_t st = qibl_shmaps_interleave(&m, p + 20 + 8 * pairs, (size_t)(pairs * cells));
        if (st != QIBL_OK) {
            free(p);
            return fail(b, "asset: SHMP %ux%u k %u channels %u: %s", w, h, k, channels, qibl_status_str(st));
        }
    } else if (pairs * cells > 0) {
        memcpy(p + 20 + 8 * pairs, planes, (size_t)(pairs * cells));
    }
    *out = p;
    *size = n;
    return 0;
}

int qtool_asset_pmap_payload(qtool_asset_builder *b, uint32_t w, uint32_t h, const int32_t *xyz,
                            uint8_t **out, size_t *size)
{
    uint64_t pixels = (uint64_t)w * h; /* < 2^64: no wrap */
    if (pixels > UINT32_MAX)
        return fail(b, "asset: PMAP payload does not fit 32 bits");
    uint64_t values = pixels * 3;
    if (table_payload(b, "PMAP", w, h, values, 4, out, size) != 0)
        return -1;
    for (uint64_t i = 0; i < values; ++i)
        qtool_store_s32le(*out + 12 + 4 * i, xyz[i]);
    return 0;
}

int qtool_asset_ylut_payload(qtool_asset_builder *b, uint32_t face_size, uint32_t k, const int16_t *values,
                            uint8_t **out, size_t *size)
{
    uint64_t count = (uint64_t)face_size * face_size; /* < 2^64: no wrap */
    if (count > UINT32_MAX || 6 * count * k > UINT32_MAX)
        return fail(b, "asset: YLUT payload does not fit 32 bits");
    count *= 6 * (uint64_t)k;
    if (table_payload(b, "YLUT", face_size, k, count, 2, out, size) != 0)
        return -1;
    for (uint64_t i = 0; i < count; ++i)
        qtool_store_s16le(*out + 12 + 2 * i, values[i]);
    return 0;
}

int qtool_asset_add_shmp(qtool_asset_builder *b, uint32_t w, uint32_t h, uint32_t k, uint32_t channels,
                        const int32_t *scale, const int32_t *bias, const uint8_t *planes)
{
    return qtool_asset_add_shmp_layout(b, w, h, k, channels, scale, bias, planes, QIBL_SHMAPS_PLANAR);
}

int qtool_asset_add_shmp_layout(qtool_asset_builder *b, uint32_t w, uint32_t h, uint32_t k, uint32_t channels,
                               const int32_t *scale, const int32_t *bias, const uint8_t *planes, uint32_t layout)
{
    uint8_t *p = NULL;
    size_t n = 0;
    if (qtool_asset_shmp_payload_layout(b, w, h, k, channels, scale, bias, planes, layout, &p, &n) != 0)
        return -1;
    return qtool_asset_builder_take(b, QIBL_CHUNK_SHMP, p, n);
}

int qtool_asset_add_shmu(qtool_asset_builder *b, uint32_t w, uint32_t h, uint32_t k, uint32_t channels,
                        const int32_t *scale, const int32_t *bias, const uint8_t *planes)
{
    uint8_t *p = NULL;
    size_t n = 0;
    if (qtool_asset_shmp_payload(b, w, h, k, channels, scale, bias, planes, &p, &n) != 0)
        return -1;
    return qtool_asset_builder_take(b, QIBL_CHUNK_SHMU, p, n);
}

int qtool_asset_add_pmap(qtool_asset_builder *b, uint32_t w, uint32_t h, const int32_t *xyz)
{
    uint8_t *p = NULL;
    size_t n = 0;
    if (qtool_asset_pmap_payload(b, w, h, xyz, &p, &n) != 0)
        return -1;
    return qtool_asset_builder_take(b, QIBL_CHUNK_PMAP, p, n);
}

int qtool_asset_add_ylut(qtool_asset_builder *b, uint32_t face_size, uint32_t k, const int16_t *values)
{
    uint8_t *p = NULL;
    size_t n = 0;
    if (qtool_asset_ylut_payload(b, face_size, k, values, &p, &n) != 0)
        return -1;
    return qtool_asset_builder_take(b, QIBL_CHUNK_YLUT, p, n);
}

int qtool_asset_serialize(qtool_asset_builder *b, uint8_t **out, size_t *size)
{
    if (b->count == 0)
        return fail(b, "asset: no chunks");
    uint64_t table_end = QIBL_ASSET_HEADER_SIZE + (uint64_t)QIBL_ASSET_ENTRY_SIZE * b->count;
    uint64_t end = table_end, offs[QIBL_ASSET_MAX_CHUNKS];
    for (uint32_t i = 0; i < b->count; ++i) {
        end = (end + 3) & ~(uint64_t)3;
        offs[i] = end;
        end += b->chunks[i].size;
        if (end > UINT32_MAX)
            return fail(b, "asset: total size exceeds 4 GiB");
    }
    uint8_t *p = calloc((size_t)end, 1);
    if (!p)
        return fail(b, "asset: out of memory (%llu bytes)", (unsigned long long)end);
    static const uint8_t magic[8] = {'Q', 'I', 'B', 'L', '\r', '\n', 0x1A, '\n'};
    memcpy(p, magic, 8);
    qtool_store_u32le(p + 8, QIBL_ASSET_VERSION);
    qtool_store_u32le(p + 12, b->count);
    qtool_store_u32le(p + 16, (uint32_t)end);
    for (uint32_t i = 0; i < b->count; ++i) {
        uint8_t *e = p + QIBL_ASSET_HEADER_SIZE + QIBL_ASSET_ENTRY_SIZE * i;
        const uint8_t *d = b->chunks[i].data;
        size_t n = b->chunks[i].size;
        if (n > 0)
            memcpy(p + offs[i], d, n);
        qtool_store_u32le(e, b->chunks[i].type);
        qtool_store_u32le(e + 4, (uint32_t)offs[i]);
        qtool_store_u32le(e + 8, (uint32_t)n);
        qtool_store_u32le(e + 12, qibl_crc32(0, p + offs[i], n));
    }
    qtool_store_u32le(p + 20, qibl_crc32(0, p + QIBL_ASSET_HEADER_SIZE, (size_t)(table_end - QIBL_ASSET_HEADER_SIZE)));
    *out = p;
    *size = (size_t)end;
    return 0;
}

static uint32_t crc_table[QIBL_CRC32_TABLE_WORDS];
static pthread_once_t crc_once = PTHREAD_ONCE_INIT;
static qibl_status_t crc_status = QIBL_E_NULL_POINTER;

static void crc_init(void)
{
    crc_status = qibl_crc32_table_init(crc_table, QIBL_CRC32_TABLE_WORDS);
}

qibl_status_t qtool_asset_open(qibl_asset_t *out, const void *bytes, size_t n)
{
    (void)pthread_once(&crc_once, crc_init);
    /* (the table cannot fail to fill; the nibble path keeps the result the same if it did) */
    return crc_status == QIBL_OK ? qibl_asset_open_crc_table(out, bytes, n, crc_table) : qibl_asset_open(out, bytes, n);
}

int qtool_asset_write_file(qtool_asset_builder *b, const char *path, int do_fsync)
{
    uint8_t *buf = NULL;
    size_t n = 0;
    if (qtool_asset_serialize(b, &buf, &n) != 0) {
        char why[sizeof b->err];
        snprintf(why, sizeof why, "%s", b->err);
        return fail(b, "%s: %s", path, why);
    }
    qibl_asset_t a;
    qibl_status_t st = qtool_asset_open(&a, buf, n);
    if (st != QIBL_OK) {
        free(buf);
        return fail(b, "%s: refusing to write an invalid asset: %s", path, qibl_status_str(st));
    }
    qtool_io_atomic at;
    int rc = qtool_io_atomic_open(&at, path, b->err, sizeof b->err);
    if (rc == 0) {
        at.no_fsync = !do_fsync;
        if (fwrite(buf, 1, n, at.f) != n) {
            rc = fail(b, "%s: write failed: %s", path, strerror(errno));
            qtool_io_atomic_abort(&at);
        } else {
            rc = qtool_io_atomic_commit(&at, b->err, sizeof b->err);
        }
    }
    free(buf);
    return rc;
}
