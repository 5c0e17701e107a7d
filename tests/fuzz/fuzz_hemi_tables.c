/*
 * fuzz_hemi_tables.c - libFuzzer target for the hemi tables blob (core/src/hemi_tables.c:
 * qibl_hemi_open, qibl_hemi_tables_build), the read-only tables a port keeps in ROM or flash.
 *
 * The target builds the valid blob of the smallest shape (n = 16, face = 2) once, then the input
 * changes it: byte 0 flags (bit 0: recompute the payload's CRC after the changes, so the header
 * and payload checks past the CRC are reached; bit 1: ask for another face; bit 2: open at an
 * address that is not 4-byte aligned), bytes 1..2 a new length (little-endian, taken modulo twice
 * the blob's), then (offset u16, value u8) triples XORed into the blob.
 * Invariants (abort on violation): a refused blob leaves *h and the workspace untouched and gets a
 * status of its own (workspace, size or hemi-tables); the unchanged blob opens; an accepted blob
 * has the asked shape, the right length and a valid header, and a mask rasterized and transferred
 * with it stays within its words (ASan checks the reads of the caller's tables); any span of the
 * blob built again equals the blob's words.
 */
#include <string.h>

#include "fuzz.h"
#include "qibl/asset.h"
#include "qibl/hemi.h"

enum { N = 16, FACE = 2 };

static uint32_t *g_valid; /* the blob of (N, FACE), built once */
static size_t g_size;

static void make_valid(void)
{
    if (g_valid != NULL)
        return;
    g_size = qibl_hemi_tables_size(N, FACE);
    FUZZ_CHECK(g_size > QIBL_HEMI_TABLES_HEADER_SIZE && g_size % 4u == 0);
    g_valid = malloc(g_size);
    FUZZ_CHECK(g_valid != NULL);
    FUZZ_CHECK(qibl_hemi_tables_build(N, FACE, 0, (uint32_t)(g_size / 4u), g_valid) == QIBL_OK);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    make_valid();
    fuzz_in in = {data, size};
    const uint8_t flags = fuzz_u8(&in);
    const uint32_t len_in = (uint32_t)fuzz_u8(&in) | (uint32_t)fuzz_u8(&in) << 8;
    const size_t len = len_in == 0 ? g_size : len_in % (2u * g_size);
    const int face = (flags & 2u) ? FACE + 2 : FACE;
    /* room for the misaligned view and a longer blob; the bytes past the valid blob are zero */
    uint8_t *buf = calloc(2u * g_size + 8u, 1);
    FUZZ_CHECK(buf != NULL);
    uint8_t *blob = buf + ((flags & 4u) ? 1u : 4u);
    memcpy(blob, g_valid, g_size);
    int changed = len != g_size || face != FACE;
    while (in.n >= 3) {
        const uint32_t off = (uint32_t)fuzz_u8(&in) | (uint32_t)fuzz_u8(&in) << 8;
        const uint8_t x = fuzz_u8(&in);
        const size_t at = (size_t)off % (g_size + 8u);
        blob[at] ^= x;
        changed |= x != 0 && at < g_size;
    }
    if ((flags & 1u) && len >= QIBL_HEMI_TABLES_HEADER_SIZE) {
        /* the CRC word (5) over the payload that is there */
        uint32_t crc = qibl_crc32(0, blob + QIBL_HEMI_TABLES_HEADER_SIZE, len - QIBL_HEMI_TABLES_HEADER_SIZE);
        memcpy(blob + 20, &crc, 4);
    }
    static uint8_t ws[QIBL_HEMI_OPEN_WORKSPACE_SIZE], ws_before[QIBL_HEMI_OPEN_WORKSPACE_SIZE];
    memset(ws, 0x5A, sizeof ws);
    memcpy(ws_before, ws, sizeof ws);
    qibl_hemi_t h, before;
    memset(&h, 0xA5, sizeof h);
    memcpy(&before, &h, sizeof h);
    const qibl_status_t st = qibl_hemi_open(&h, N, face, blob, len, ws, sizeof ws);
    if (st != QIBL_OK) {
        FUZZ_CHECK(memcmp(&h, &before, sizeof h) == 0 && memcmp(ws, ws_before, sizeof ws) == 0);
        FUZZ_CHECK(st == QIBL_E_HEMI_SIZE || (st >= QIBL_E_HEMI_TABLES_ALIGN && st <= QIBL_E_HEMI_TABLES_CRC));
        FUZZ_CHECK(changed || (flags & 4u)); /* the valid blob, aligned, must open */
        free(buf);
        return 0;
    }
    FUZZ_CHECK(!(flags & 4u) && len == g_size && face == FACE && h.n == N && h.face == FACE);
    const uint32_t *w = (const uint32_t *)(const void *)blob;
    FUZZ_CHECK(memcmp(w, g_valid, 20) == 0 && w[6] == 0 && w[7] == 0);
    /* a few triangles through the opened tables: every LUT and basis read inside the caller's blob */
    static const int32_t v[6][3] = {{-40000, -30000, 20000}, {50000, -20000, 30000}, {0, 60000, 10000},
                                    {-70000, 70000, 65536}, {90000, 10000, 4000}, {1, -90000, 2}};
    static const uint32_t tri[4][3] = {{0, 1, 2}, {3, 4, 5}, {0, 3, 5}, {1, 4, 2}};
    uint32_t m[QIBL_HEMI_MAX_WORDS];
    qibl_q30_t out[QIBL_HEMI_COEFFS];
    FUZZ_CHECK(qibl_hemi_clear(&h, m) == QIBL_OK);
    FUZZ_CHECK(qibl_hemi_raster(&h, v, 6, tri, 4, m, NULL) == QIBL_OK);
    FUZZ_CHECK(qibl_hemi_clip(&h, m) == QIBL_OK);
    FUZZ_CHECK(qibl_hemi_transfer(&h, m, out) == QIBL_OK);
    /* a span built again is the valid blob's (the build does not depend on the input) */
    uint32_t span[7];
    const uint32_t first = (uint32_t)(data[0] ^ (size > 1 ? data[1] : 0)) * 13u % (uint32_t)(g_size / 4u - 7u);
    FUZZ_CHECK(qibl_hemi_tables_build(N, FACE, first, 7, span) == QIBL_OK);
    FUZZ_CHECK(memcmp(span, g_valid + first, sizeof span) == 0);
    free(buf);
    return 0;
}
