/*
 * qibl/shmaps.h - views of the data relighting reads: k 8-bit SH maps, the P map, the cube-map Y
 * LUT. Plain structs over the caller's bytes (read with byte loads: any alignment, either host byte
 * order), filled by qibl_asset_shmaps/_pmap/_ylut (asset.h) or by hand for data a game builds or
 * streams itself: relighting (shmap.h) needs this header, not the asset parser.
 *
 * Two layouts of the map bytes (the SHMP chunk of asset.h stores either):
 *
 *   QIBL_SHMAPS_PLANAR (0): k * channels planes of width * height bytes back to back, row-major,
 *     top row first, plane index i * channels + ch. One row of the image is k * channels pieces of
 *     width bytes, one per plane.
 *
 *   QIBL_SHMAPS_INTERLEAVED (1): rows back to back, each row_size = G * 16 * k * channels bytes
 *     with G = ceil(width / 16) groups of 16 pixels; within a row, group by group, channel by
 *     channel, map by map, the 16 pixels' bytes:
 *         byte (x, y, map i, channel ch) at y * row_size + (x / 16) * 16 k channels
 *                                           + (ch * k + i) * 16 + x % 16
 *     The last group's pixels past width are padding (written 0, read, never output). A row is one
 *     contiguous range (stream it from disc one row at a time), and a group's k maps of one channel
 *     are 16 k adjacent bytes (one run per channel for 16-pixel SIMD lanes; see ARCHITECTURE.md).
 *
 * In both layouts the image is height rows of qibl_shmaps_row_size bytes, and a one-row view
 * (qibl_shmaps_row_view) of a buffer holding one row relights exactly as row y of the whole image.
 */
#ifndef QIBL_SHMAPS_H
#define QIBL_SHMAPS_H

#include <stddef.h>
#include <stdint.h>
#include "qibl/config.h"
#include "qibl/fixed.h"
#include "qibl/status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define QIBL_SHMAPS_PLANAR 0u
#define QIBL_SHMAPS_INTERLEAVED 1u
#define QIBL_SHMAPS_GROUP 16u       /* pixels per group of the interleaved layout */
#define QIBL_YLUT_MAX_FACE 256u     /* largest cube-map LUT face size */

/* SH maps as a view. params holds k*channels {scale, bias} pairs (Q8.24, little-endian i32 each,
 * pair index i*channels + ch): the decoded value of byte c is bias + scale * c. planes holds the
 * map bytes in the given layout. A view filled by hand must set layout (or start from {0}: planar);
 * an unknown value is QIBL_E_SHMAP_LAYOUT in the kernels. */
typedef struct qibl_shmaps {
    uint32_t width, height, k, channels;
    const uint8_t *params;
    const uint8_t *planes;
    uint32_t layout; /* QIBL_SHMAPS_PLANAR or QIBL_SHMAPS_INTERLEAVED */
} qibl_shmaps_t;

/* Point map as a view: width*height points of 3 little-endian i32 (Q16.16), row-major. */
typedef struct qibl_pmap {
    uint32_t width, height;
    const uint8_t *points;
} qibl_pmap_t;

/* Cube-map Y LUT as a view: 6*N*N*k little-endian i16 (Q2.14), [face][row v][column u][i]
 * (asset.h, YLUT, has the face convention). size is the bytes the caller has at values: every
 * consumer (qibl_shmap_point_prepare, the gles2 upload) refuses a view whose face_size and k need
 * more (QIBL_E_SHMAP_LUT_SHORT), so fields read from a file cannot make it read past the buffer.
 * qibl_asset_ylut and qibl_asset_head_ylut (asset.h) fill it from a checked YLUT payload. */
typedef struct qibl_ylut {
    uint32_t face_size, k;
    const uint8_t *values;
    size_t size; /* bytes at values, >= qibl_ylut_values_size(face_size, k) (12 N N k) */
} qibl_ylut_t;

/* Accessors (no checks: the view must be valid and the indices in range). */
qibl_q24_t qibl_shmaps_scale(const qibl_shmaps_t *m, uint32_t i, uint32_t ch);
qibl_q24_t qibl_shmaps_bias(const qibl_shmaps_t *m, uint32_t i, uint32_t ch);
/* The plane of map i, channel ch (planar layout only). */
const uint8_t *qibl_shmaps_plane(const qibl_shmaps_t *m, uint32_t i, uint32_t ch);
/* The byte of map i, channel ch at pixel (x, y), in either layout. */
uint8_t qibl_shmaps_texel(const qibl_shmaps_t *m, uint32_t i, uint32_t ch, uint32_t x, uint32_t y);
void qibl_pmap_point(const qibl_pmap_t *p, uint32_t x, uint32_t y, qibl_q16_t out[3]);

/* Bytes of one row of the map data: width * k * channels (planar: the row's piece of every plane),
 * ceil(width / 16) * 16 * k * channels (interleaved). 0 for an unknown layout or k/channels/width
 * outside the format (k 1..25, channels 1 or 3, width 1..2^14). The whole image is height times it. */
size_t qibl_shmaps_row_size(const qibl_shmaps_t *m);

/* A one-row view (height 1) of maps m whose row bytes the caller loaded into row
 * (qibl_shmaps_row_size bytes; planar: the k*channels pieces back to back in plane order).
 * Relighting it at y = 0 gives the bytes row y of the whole image gives. m's fields are copied,
 * not checked (the kernels check the view).
 * Formats: none (a view; params Q8.24 shared with m). Bound: exact.
 * Errors: QIBL_E_NULL_POINTER (m, row or out NULL).
 * On failure: nothing is written (*out untouched). */
QIBL_NODISCARD qibl_status_t qibl_shmaps_row_view(const qibl_shmaps_t *m, const uint8_t *row, qibl_shmaps_t *out);

/* The same for a P map: row holds the row's 12 * width bytes.
 * Formats: none (a view; points Q16.16). Bound: exact.
 * Errors: QIBL_E_NULL_POINTER (p, row or out NULL).
 * On failure: nothing is written (*out untouched). */
QIBL_NODISCARD qibl_status_t qibl_pmap_row_view(const qibl_pmap_t *p, const uint8_t *row, qibl_pmap_t *out);

/* Writes the map bytes of planar maps m in the interleaved layout into out (height *
 * qibl_shmaps_row_size bytes of the interleaved view; padding pixels 0), for writers and for games
 * that build maps themselves.
 * Formats: u8 map bytes in and out, copied unchanged (params untouched). Bound: exact.
 * Errors, in this order: QIBL_E_NULL_POINTER (m, out or m->planes NULL), QIBL_E_SHMAP_LAYOUT (m not
 * planar), QIBL_E_SHMAP_K (k outside 1..25), QIBL_E_SHMAP_CHANNELS (not 1 or 3), QIBL_E_SHMAP_SIZE
 * (width or height 0 or above 16384), QIBL_E_WORKSPACE (out_size below height * row size).
 * On failure: nothing is written. */
QIBL_NODISCARD qibl_status_t qibl_shmaps_interleave(const qibl_shmaps_t *m, uint8_t *out, size_t out_size);

/* Little-endian loads that need no alignment (also used by the kernels). */
static inline uint32_t qibl_load_u32le(const uint8_t *p)
{
    return QIBL_CAST(uint32_t, p[0]) | QIBL_CAST(uint32_t, p[1]) << 8 | QIBL_CAST(uint32_t, p[2]) << 16 |
           QIBL_CAST(uint32_t, p[3]) << 24;
}
static inline int32_t qibl_load_s32le(const uint8_t *p)
{
    uint32_t u = qibl_load_u32le(p);
    /* two's complement without an implementation-defined conversion */
    return u <= 0x7FFFFFFFu ? QIBL_CAST(int32_t, u) : QIBL_CAST(int32_t, u - 0x80000000u) - 0x7FFFFFFF - 1;
}
static inline int16_t qibl_load_s16le(const uint8_t *p)
{
    uint32_t u = QIBL_CAST(uint32_t, p[0]) | QIBL_CAST(uint32_t, p[1]) << 8;
    return QIBL_CAST(int16_t, u <= 0x7FFFu ? QIBL_CAST(int32_t, u) : QIBL_CAST(int32_t, u) - 0x10000);
}

#ifdef __cplusplus
}
#endif

#endif /* QIBL_SHMAPS_H */
