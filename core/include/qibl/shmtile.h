/*
 * qibl/shmtile.h - SH maps stored per 16x16 tile with the bands each tile needs (adaptive k).
 *
 * The unshadowed transfer (cosine x BRDF) is smooth over most of a panorama: most tiles keep their
 * light to within a percent with k = 9 and some with k = 4, only tiles on sharp normal or material edges
 * need 16. Chunk SHMT stores the unshadowed maps that way (it replaces SHMU in an asset; a reader
 * takes either). Every tile keeps the first k_t of the kmax bands, with the same 8-bit packing
 * (scale, bias per map and channel) as the whole set, so a dropped band is exactly a zero
 * coefficient and a tile with k_t = kmax relights to the same values as SHMU.
 *
 * Layout (all little-endian):
 *     0  u32 width, 4 u32 height     equal to the asset's SHMP
 *     8  u32 kmax                    1..25
 *    12  u32 channels                1 or 3
 *    16  u32 tile                    16 (the only size so far)
 *    20  u32 flags                   0
 *    24  kmax * channels (i32 scale, i32 bias), Q8.24, entry i * channels + ch (as SHMP)
 *        then one u8 k_t per tile (1..kmax), tiles row-major (ceil(w/16) x ceil(h/16)), zero-padded
 *        to a multiple of 4
 *        then one u32 per tile: the byte offset of its data from the data start (the first 0, each
 *        the previous plus the previous tile's size)
 *        then the data: per tile k_t * channels planes of tw * th bytes (tw, th the tile's size, less
 *        than 16 on the right and bottom edges), plane i * channels + ch, rows top first
 *    size = the sum of the above exactly
 * A tile is read as an ordinary planar maps view (qibl_shmtile_view): width tw, height th, k = k_t,
 * the set's params (their first k_t entries are the tile's). Any kernel that takes a qibl_shmaps_t
 * relights it; a point light needs a P-map view of the same tile (the caller copies tw x th points).
 *
 * Built with QIBL_USE_LIGHTPATH (config.h; off in a QIBL_CONFIG_SMALL build unless asked for).
 */
#ifndef QIBL_SHMTILE_H
#define QIBL_SHMTILE_H

#include <stddef.h>
#include <stdint.h>
#include "qibl/asset.h"
#include "qibl/shmaps.h"
#include "qibl/status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define QIBL_CHUNK_SHMT QIBL_FOURCC('S', 'H', 'M', 'T')
#define QIBL_SHMTILE_HEADER 24u
#define QIBL_SHMTILE_SIZE 16u

/* A validated tiled set as a view of the chunk bytes. */
typedef struct qibl_shmtile {
    uint32_t width, height, kmax, channels, tiles_x, tiles_y;
    const uint8_t *params, *ks, *offsets, *data;
} qibl_shmtile_t;

/* Validates an SHMT payload and fills *out. Reads every header, k and offset byte once: O(tiles).
 * Formats: none (little-endian u32 fields; the params, Q8.24, and map bytes are not read).
 * Bound: exact.
 * Errors, in this order: QIBL_E_NULL_POINTER (data or out NULL), QIBL_E_ASSET_CHUNK_SIZE (shorter
 * than the 24-byte header), QIBL_E_ASSET_BAD_DIMENSIONS, QIBL_E_ASSET_BAD_K (kmax outside 1..25),
 * QIBL_E_ASSET_BAD_CHANNELS, QIBL_E_ASSET_BAD_FLAGS (tile size not 16, or flags), QIBL_E_ASSET_CHUNK_SIZE
 * (shorter than params, ks and offsets), QIBL_E_ASSET_BAD_FLAGS (non-zero padding after the ks),
 * then per tile in row-major order QIBL_E_ASSET_BAD_K (k outside 1..kmax) and QIBL_E_ASSET_CHUNK_SIZE
 * (an offset other than the running sum), and QIBL_E_ASSET_CHUNK_SIZE (size other than the fields
 * imply).
 * On failure: nothing is written (*out untouched). */
QIBL_NODISCARD qibl_status_t qibl_shmtile_parse(const uint8_t *data, size_t size, qibl_shmtile_t *out);

/* The asset's SHMT, parsed, its size checked against SHMP's. Needs QIBL_USE_ASSET.
 * Formats: none (as qibl_shmtile_parse). Bound: exact.
 * Errors, in this order: QIBL_E_NULL_POINTER (a or out NULL), QIBL_E_ASSET_MISSING_CHUNK (no SHMT),
 * QIBL_E_ASSET_DUPLICATE_CHUNK (two or more), QIBL_E_ASSET_MISSING_CHUNK (no SHMP: a not validated),
 * those of qibl_shmtile_parse, QIBL_E_ASSET_MISMATCH (width or height other than SHMP's).
 * On failure: nothing is written (*out untouched). */
QIBL_NODISCARD qibl_status_t qibl_shmtile_from_asset(const qibl_asset_t *a, qibl_shmtile_t *out);

/* Tile (tx, ty) as a planar maps view and its top-left pixel (*x0, *y0; either may be NULL).
 * Formats: none (a view: the set's Q8.24 params, the tile's u8 planes; pixel coordinates).
 * Bound: exact.
 * Errors, in this order: QIBL_E_NULL_POINTER (t or view NULL), QIBL_E_SHMAP_BOUNDS (tx >= tiles_x
 * or ty >= tiles_y).
 * On failure: nothing is written (*view, *x0, *y0 untouched). */
QIBL_NODISCARD qibl_status_t qibl_shmtile_view(const qibl_shmtile_t *t, uint32_t tx, uint32_t ty, qibl_shmaps_t *view, uint32_t *x0,
                                uint32_t *y0);

#ifdef __cplusplus
}
#endif

#endif /* QIBL_SHMTILE_H */
