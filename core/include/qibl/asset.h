/*
 * qibl/asset.h - the qibl asset container: versioned chunks, little-endian, CRC-32 per chunk,
 * parsed in place from caller memory (zero-copy, alignment-safe, no heap).
 *
 * Layout (all integers little-endian whatever the host; offsets from the first byte):
 *
 *   header, 24 bytes
 *     0  u8[8] magic        'Q' 'I' 'B' 'L' '\r' '\n' 0x1A '\n'   (catches text-mode mangling)
 *     8  u32   version      QIBL_ASSET_VERSION (1)
 *    12  u32   chunk_count  1..QIBL_ASSET_MAX_CHUNKS
 *    16  u32   file_size    bytes in the whole asset; the caller's buffer may be longer, not shorter
 *    20  u32   table_crc    CRC-32 of the chunk table (the 16 * chunk_count bytes at offset 24)
 *   chunk table, 16 bytes per chunk
 *     0  u32   type         four ASCII bytes in file order, read as a little-endian u32
 *                           (QIBL_CHUNK_SHMP = "SHMP" ...)
 *     4  u32   offset       of the payload; a multiple of 4, at or after the end of the table
 *     8  u32   size         payload bytes
 *    12  u32   crc          CRC-32 (ISO 3309, as zip/PNG) of the payload
 *   payloads: anywhere after the table, inside file_size, not overlapping each other.
 *
 * Chunk types known to this version (unknown types are CRC-checked and otherwise ignored; a known
 * type may appear at most once):
 *
 *   SHMP (required) - k SH maps, 8-bit range-packed (Wong et al.; qibl packs per map and channel)
 *     0  u32 width      1..QIBL_ASSET_MAX_DIM
 *     4  u32 height     1..QIBL_ASSET_MAX_DIM, width * height <= QIBL_ASSET_MAX_PIXELS
 *     8  u32 k          number of maps, 1..25 (bands 0..4, flat SH index i = l*l + l + m)
 *    12  u32 channels   1 (grey) or 3 (RGB)
 *    16  u32 flags      0 (reserved)
 *    20  k * channels pairs {i32 scale, i32 bias}, Q8.24, map-major (pair index i*channels + ch):
 *        the decoded value of byte c is bias + scale * c (c in 0..255)
 *    20 + 8 * k * channels: k * channels planes of width * height bytes, row-major, top row first,
 *        plane index i * channels + ch
 *    size = 20 + 8 k channels + width height k channels exactly
 *
 *   PMAP (optional; needed for point lights) - per-pixel scene point seen through the pixel (Wong
 *   eq. 2: depth along the pixel's viewing ray from the viewpoint E, here E = origin)
 *     0  u32 width, 4 u32 height (both equal to SHMP's), 8 u32 flags 0
 *    12  width * height * 3 i32: x, y, z in Q16.16 scene units, row-major
 *    size = 12 + 12 width height exactly
 *
 *   SHMU (optional) - unshadowed transfer: k SH maps of cosine x BRDF without visibility, the
 *   same layout and rules as SHMP (its own k and packing), width and height equal to SHMP's
 *   (else QIBL_E_ASSET_MISMATCH). Free point lights use it (visibility at infinity is wrong for a
 *   lamp inside the scene); light paths (lightpath.h) multiply it by their baked visibility.
 *
 *   YLUT (optional) - cube-map look-up tables of Y_i (Wong §"Relighting by a point source")
 *     0  u32 face_size N (1..QIBL_ASSET_MAX_LUT), 4 u32 k (>= SHMP k, <= 25), 8 u32 flags 0
 *    12  6 * N * N * k i16 in Q2.14: [face][row v][column u][i]; faces +X -X +Y -Y +Z -Z; texel
 *        (u, v) of face f is the direction of the OpenGL cube-map convention with
 *        s = 2 (u + 0.5) / N - 1, t = 2 (v + 0.5) / N - 1:
 *        +X (1, -t, -s)  -X (-1, -t, s)  +Y (s, 1, t)  -Y (s, -1, -t)  +Z (s, -t, 1)  -Z (-s, -t, -1)
 *    size = 12 + 12 N N k exactly
 *
 * Validation (qibl_asset_open) checks everything above once; afterwards the accessors cannot fail
 * on a validated asset. Each problem has its own status (see status.h, QIBL_E_ASSET_*) and the
 * first failing check is reported, in this order: header; table size and CRC; per entry its
 * alignment and bounds, then duplicate/overlap against the earlier entries; SHMP present; every
 * payload CRC; the fields of SHMP, then PMAP, then YLUT, then SHMU (a payload too short for its fixed fields
 * is QIBL_E_ASSET_CHUNK_SIZE). A buffer or a file_size shorter than header + table is
 * QIBL_E_ASSET_TRUNCATED_TABLE, a buffer shorter than file_size QIBL_E_ASSET_TRUNCATED. An empty
 * payload (size 0) overlaps nothing. A failing call writes nothing to its outputs.
 */
#ifndef QIBL_ASSET_H
#define QIBL_ASSET_H

#include <stddef.h>
#include <stdint.h>
#include "qibl/config.h"
#include "qibl/fixed.h"
#include "qibl/status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define QIBL_ASSET_VERSION 1u
#define QIBL_ASSET_HEADER_SIZE 24u
#define QIBL_ASSET_ENTRY_SIZE 16u
#define QIBL_ASSET_MAX_CHUNKS 64u
#define QIBL_ASSET_MAX_DIM 16384u
#define QIBL_ASSET_MAX_PIXELS (1u << 26) /* 64 Mpixel; sizes are computed in 64 bits and a size
                                          * that does not fit a u32 is QIBL_E_ASSET_SIZE_OVERFLOW */
#define QIBL_ASSET_MAX_LUT 256u

/* four-character chunk codes, as the u32 read little-endian from the bytes "SHMP", ... */
#define QIBL_FOURCC(a, b, c, d) ((uint32_t)(a) | (uint32_t)(b) << 8 | (uint32_t)(c) << 16 | (uint32_t)(d) << 24)
#define QIBL_CHUNK_SHMP QIBL_FOURCC('S', 'H', 'M', 'P')
#define QIBL_CHUNK_PMAP QIBL_FOURCC('P', 'M', 'A', 'P')
#define QIBL_CHUNK_YLUT QIBL_FOURCC('Y', 'L', 'U', 'T')
#define QIBL_CHUNK_SHMU QIBL_FOURCC('S', 'H', 'M', 'U')

/* A validated asset: a view of the caller's bytes (which must outlive it). Zero-initialisable. */
typedef struct qibl_asset {
    const uint8_t *base;
    uint32_t size;        /* file_size */
    uint32_t chunk_count;
} qibl_asset_t;

/* One chunk's payload as a view into the asset bytes. */
typedef struct qibl_chunk {
    uint32_t type;
    uint32_t size;
    const uint8_t *data;
} qibl_chunk_t;

/* SH maps (SHMP) as a view. May also be filled by hand for maps that live elsewhere in memory:
 * params holds k*channels {scale, bias} pairs as 8 little-endian bytes each, planes the
 * k*channels planes back to back. */
typedef struct qibl_shmaps {
    uint32_t width, height, k, channels;
    const uint8_t *params;
    const uint8_t *planes;
} qibl_shmaps_t;

/* Point map (PMAP) as a view: width*height points of 3 little-endian i32 (Q16.16). */
typedef struct qibl_pmap {
    uint32_t width, height;
    const uint8_t *points;
} qibl_pmap_t;

/* Cube-map Y LUT (YLUT) as a view: 6*N*N*k little-endian i16 (Q2.14), layout above. */
typedef struct qibl_ylut {
    uint32_t face_size, k;
    const uint8_t *values;
} qibl_ylut_t;

/* CRC-32 (ISO 3309 / zip / PNG polynomial 0xEDB88320, reflected, init and final xor 0xFFFFFFFF)
 * of n bytes, continuing from crc (pass 0 to start). A nibble-at-a-time loop over a 16-entry const
 * table (64 bytes of .rodata) instead of the usual 1 KiB byte table. */
uint32_t qibl_crc32(uint32_t crc, const uint8_t *data, size_t n);

/* Validates bytes[0..n) as an asset (every rule above, every CRC) and fills *out.
 * Errors: QIBL_E_NULL_POINTER and the QIBL_E_ASSET_* codes; *out untouched on failure. */
qibl_status_t qibl_asset_open(qibl_asset_t *out, const void *bytes, size_t n);

/* The chunk of the given type (the first one, for an unknown type that appears more than once).
 * QIBL_E_ASSET_MISSING_CHUNK if absent; *out untouched then. */
qibl_status_t qibl_asset_find(const qibl_asset_t *a, uint32_t type, qibl_chunk_t *out);

/* Typed views of the known chunks of a validated asset (missing chunk -> QIBL_E_ASSET_MISSING_CHUNK). */
qibl_status_t qibl_asset_shmaps(const qibl_asset_t *a, qibl_shmaps_t *out);
qibl_status_t qibl_asset_pmap(const qibl_asset_t *a, qibl_pmap_t *out);
qibl_status_t qibl_asset_ylut(const qibl_asset_t *a, qibl_ylut_t *out);
/* The unshadowed maps (SHMU). qibl_asset_point_shmaps: the maps a free point light should use,
 * SHMU when present, else SHMP (older assets). */
qibl_status_t qibl_asset_shmaps_unshadowed(const qibl_asset_t *a, qibl_shmaps_t *out);
qibl_status_t qibl_asset_point_shmaps(const qibl_asset_t *a, qibl_shmaps_t *out);
/* The index-th chunk (0-based) of the given type, for types that may repeat (light paths). */
qibl_status_t qibl_asset_find_nth(const qibl_asset_t *a, uint32_t type, uint32_t index, qibl_chunk_t *out);

/* Accessors (no checks: the view must be valid and the indices in range). */
qibl_q24_t qibl_shmaps_scale(const qibl_shmaps_t *m, uint32_t i, uint32_t ch);
qibl_q24_t qibl_shmaps_bias(const qibl_shmaps_t *m, uint32_t i, uint32_t ch);
const uint8_t *qibl_shmaps_plane(const qibl_shmaps_t *m, uint32_t i, uint32_t ch);
void qibl_pmap_point(const qibl_pmap_t *p, uint32_t x, uint32_t y, qibl_q16_t out[3]);

/* Little-endian loads that need no alignment (also used by the kernels). */
static inline uint32_t qibl_load_u32le(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}
static inline int32_t qibl_load_s32le(const uint8_t *p)
{
    uint32_t u = qibl_load_u32le(p);
    /* two's complement without an implementation-defined conversion */
    return u <= 0x7FFFFFFFu ? (int32_t)u : (int32_t)(u - 0x80000000u) - 0x7FFFFFFF - 1;
}
static inline int16_t qibl_load_s16le(const uint8_t *p)
{
    uint32_t u = (uint32_t)p[0] | (uint32_t)p[1] << 8;
    return (int16_t)(u <= 0x7FFFu ? (int32_t)u : (int32_t)u - 0x10000);
}

#ifdef __cplusplus
}
#endif

#endif /* QIBL_ASSET_H */
