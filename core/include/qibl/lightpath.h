/*
 * qibl/lightpath.h - lights that move along a known path, with exact cast shadows, integer only.
 *
 * A game rarely moves a light anywhere: the sun follows the time of day, a torch or a car follows a
 * track. For such a light the bake stores, per pixel, its visibility along the path -- the light
 * above the surface (facing term) and not blocked (cast shadow) -- as on/off edges of the path
 * parameter t (0..65535). At run time a pixel is relit as
 *     out = unshadowed SH relight (SHMU maps, asset.h) x V(t)
 * so the smooth part (cosine x BRDF) comes from SH and the hard part (visibility) is exact to the
 * bake's edge precision. A soft sun or lamp filters V along the path over [t - r, t + r].
 * Sky plus sun: relight the environment through the shadowed maps (SHMP) into out, then add the path
 * light with accumulate = 1 (two passes over a span, no extra memory). Lights off every path fall
 * back to the shadowed maps (method-bound quality, see docs/ARCHITECTURE.md).
 *
 * Chunk LPTH (one per path; an asset may hold several, found with qibl_asset_find_nth), all
 * little-endian:
 *     0  u32 width, 4 u32 height     equal to the asset's SHMP (checked by qibl_lightpath_from_asset)
 *     8  u32 kind                    0 directions (sun path: keys are directions towards the light),
 *                                    1 positions (lamp track: keys are points, scene units)
 *    12  u32 flags                   0 (reserved)
 *    16  u32 nkeys                   2..QIBL_LIGHTPATH_MAX_KEYS
 *    20  u32 nedges                  total edges, <= QIBL_LIGHTPATH_MAX_EDGES
 *    24  nkeys keys of 16 bytes: u32 t (strictly increasing, first 0, last 65535), i32 x, y, z Q16.16
 *        (a direction key must not be zero); the path between keys is linear in t
 *    24 + 16 nkeys: (height + 1) u32 row starts: index of the first edge of each row; row_start[0] = 0,
 *        row_start[y + 1] = row_start[y] + the row's counts, row_start[height] = nedges
 *    then width * height u8 counts (edges per pixel, row-major)
 *    then nedges u16 edges: each pixel's edges strictly increasing, in 0..65535
 *    size = 24 + 16 nkeys + 4 (height + 1) + width height + 2 nedges exactly
 * Visibility: V(t) = 1 when an odd number of the pixel's edges are <= t (so it starts off; an edge
 * at 0 means visible from the start). Outside 0..65535 (soft windows) V keeps its end value.
 * Validation reads every byte once: O(size). After it no access can leave the payload.
 *
 * Chunk LOCC (optional, at most one; lamp occlusion for free point lights, those on no path):
 *     0  u32 width, 4 u32 height     equal to the asset's SHMP
 *     8  width * height u8           a(p) x 255: the expected visibility of a lamp in the region
 *                                    the bake was told lamps move in, weighted by the light the lamp
 *                                    would add (255 = never shadowed)
 *    size = 8 + width height exactly
 * A free lamp relit through the unshadowed maps lights the pixels its cast shadows should darken
 * (the demo measures the excess, all in cast-shadow pixels); scaling it by a(p) puts the shadows
 * back on average (the demo prints brightness and PSNR with and without it).
 */
#ifndef QIBL_LIGHTPATH_H
#define QIBL_LIGHTPATH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "qibl/asset.h"
#include "qibl/fixed.h"
#include "qibl/status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define QIBL_CHUNK_LPTH QIBL_FOURCC('L', 'P', 'T', 'H')
#define QIBL_LIGHTPATH_HEADER 24u
#define QIBL_LIGHTPATH_MAX_KEYS 4096u
#define QIBL_LIGHTPATH_MAX_EDGES (1u << 28) /* keeps 2 nedges and every size sum inside 32 bits */
#define QIBL_LIGHTPATH_T_MAX 65535u
#define QIBL_LIGHTPATH_MAX_RADIUS 32767u
#define QIBL_CHUNK_LOCC QIBL_FOURCC('L', 'O', 'C', 'C')
#define QIBL_LAMPOCC_HEADER 8u

typedef enum qibl_lightpath_kind {
    QIBL_LIGHTPATH_DIRECTIONS = 0, /* sun path */
    QIBL_LIGHTPATH_POSITIONS = 1   /* lamp track */
} qibl_lightpath_kind_t;

/* A validated path as a view of the chunk bytes (which must outlive it). */
typedef struct qibl_lightpath {
    uint32_t width, height, kind, nkeys, nedges;
    const uint8_t *keys, *rows, *counts, *edges;
} qibl_lightpath_t;

/* Validates an LPTH payload (layout above) and fills *out.
 * Formats: none (little-endian fields; keys Q16.16 and u16 edges are checked, not converted).
 * Bound: exact.
 * Errors, in this order: QIBL_E_NULL_POINTER (data or out NULL), QIBL_E_LIGHTPATH_SIZE (shorter
 * than the header), QIBL_E_LIGHTPATH_DIMENSIONS, QIBL_E_LIGHTPATH_KIND (kind or flags),
 * QIBL_E_LIGHTPATH_KEYS (nkeys outside 2..QIBL_LIGHTPATH_MAX_KEYS), QIBL_E_LIGHTPATH_SIZE (nedges
 * above QIBL_LIGHTPATH_MAX_EDGES, or size other than the fields imply), QIBL_E_LIGHTPATH_KEYS (t
 * not 0 first, not strictly increasing, not 65535 last, or a zero direction key),
 * QIBL_E_LIGHTPATH_ROWS, QIBL_E_LIGHTPATH_EDGES.
 * On failure: nothing is written (*out untouched). */
QIBL_NODISCARD qibl_status_t qibl_lightpath_parse(const uint8_t *data, size_t size, qibl_lightpath_t *out);

/* Number of LPTH chunks in a validated asset (0 when a is NULL). This and the next need
 * QIBL_USE_ASSET; the rest of the module does not. */
uint32_t qibl_lightpath_count(const qibl_asset_t *a);

/* The index-th path of a validated asset, parsed, its size checked against SHMP's.
 * Formats: none (as qibl_lightpath_parse). Bound: exact.
 * Errors, in this order: QIBL_E_NULL_POINTER (a or out NULL), QIBL_E_ASSET_MISSING_CHUNK (index
 * past the last LPTH, or no SHMP: a not validated), those of qibl_lightpath_parse,
 * QIBL_E_LIGHTPATH_DIMENSIONS (width or height other than SHMP's).
 * On failure: nothing is written (*out untouched). */
QIBL_NODISCARD qibl_status_t qibl_lightpath_from_asset(const qibl_asset_t *a, uint32_t index, qibl_lightpath_t *out);

/* The light at parameter t, linear between keys: a direction (not normalised) or a position.
 * Formats: t path parameter 0..65535; keys and out Q16.16.
 * Bound: rounded to nearest, ties away from zero (error <= 0.5 LSB); exact at the keys.
 * Errors, in this order: QIBL_E_NULL_POINTER (p or out NULL), QIBL_E_LIGHTPATH_PARAM (t > 65535).
 * On failure: nothing is written. */
QIBL_NODISCARD qibl_status_t qibl_lightpath_at(const qibl_lightpath_t *p, uint32_t t, qibl_q16_t out[3]);

/* Visibility of pixels x0..x0+n-1 of row y at t: hard (radius 0) or the fraction of
 * [t - radius, t + radius) lit (radius 1..32767). n == 0 is a valid empty span.
 * Formats: t, radius path parameter units; vis UQ16 (0..65536).
 * Bound: hard: exact (0 or 65536); soft: rounded to nearest, error <= 1 LSB.
 * Errors, in this order: QIBL_E_NULL_POINTER (p NULL), QIBL_E_LIGHTPATH_PARAM (t > 65535 or
 * radius > 32767), QIBL_E_LIGHTPATH_BOUNDS (y >= height or x0 + n > width), QIBL_E_NULL_POINTER
 * (vis NULL).
 * On failure: nothing is written. */
QIBL_NODISCARD qibl_status_t qibl_lightpath_visibility_span(const qibl_lightpath_t *p, uint32_t t, uint32_t radius, uint32_t x0,
                                             uint32_t y, uint32_t n, uint32_t *vis);

/* out = light x V(t) (accumulate false) or out += light x V(t) (true, saturating) for the span;
 * light may equal out when not accumulating.
 * Formats: light and out 3 int32 per pixel (Q16.16 RGB, as qibl_shmap_relight_span writes them);
 * V UQ16 as qibl_lightpath_visibility_span.
 * Bound: hard (radius 0), and soft pixels fully lit or dark: exact; otherwise each product rounded
 * to nearest, ties up (<= 0.5 LSB) against V (itself within 1 LSB of UQ16); sums saturate at the
 * int32 limits.
 * Errors, in this order: those of qibl_lightpath_visibility_span up to QIBL_E_LIGHTPATH_BOUNDS, then
 * QIBL_E_NULL_POINTER (light or out NULL).
 * On failure: nothing is written. */
QIBL_NODISCARD qibl_status_t qibl_lightpath_shade_span(const qibl_lightpath_t *p, uint32_t t, uint32_t radius, uint32_t x0,
                                        uint32_t y, uint32_t n, const int32_t *light, int32_t *out, bool accumulate);

/* A validated lamp-occlusion chunk as a view of its bytes. */
typedef struct qibl_lampocc {
    uint32_t width, height;
    const uint8_t *values;
} qibl_lampocc_t;

/* Validates a LOCC payload and fills *out.
 * Formats: none (little-endian u32 fields; the u8 values are not read). Bound: exact.
 * Errors, in this order: QIBL_E_NULL_POINTER (data or out NULL), QIBL_E_LIGHTPATH_SIZE (shorter
 * than the header), QIBL_E_LIGHTPATH_DIMENSIONS (zero or too large), QIBL_E_LIGHTPATH_SIZE (size
 * other than 8 + w h).
 * On failure: nothing is written (*out untouched). */
QIBL_NODISCARD qibl_status_t qibl_lightpath_occl_parse(const uint8_t *data, size_t size, qibl_lampocc_t *out);

/* The asset's LOCC, parsed, its size checked against SHMP's. Needs QIBL_USE_ASSET.
 * Formats: none (as qibl_lightpath_occl_parse). Bound: exact.
 * Errors, in this order: QIBL_E_NULL_POINTER (a or out NULL), QIBL_E_ASSET_MISSING_CHUNK (no LOCC),
 * QIBL_E_ASSET_DUPLICATE_CHUNK (two or more), QIBL_E_ASSET_MISSING_CHUNK (no SHMP: a not validated),
 * those of qibl_lightpath_occl_parse, QIBL_E_LIGHTPATH_DIMENSIONS (width or height other than SHMP's).
 * On failure: nothing is written (*out untouched). */
QIBL_NODISCARD qibl_status_t qibl_lightpath_occl_from_asset(const qibl_asset_t *a, qibl_lampocc_t *out);

/* io *= a(p) / 255 for pixels x0..x0+n-1 of row y, in place.
 * Formats: io 3 int32 per pixel (Q16.16 RGB); a(p) u8, used as the UQ16 factor 257 a + a / 128.
 * Bound: rounded to nearest, ties up (<= 0.5 LSB) against the factor, whose error is <= 2^-16
 * relative; 255 leaves a value unchanged, 0 gives 0.
 * Errors, in this order: QIBL_E_NULL_POINTER (o or io NULL), QIBL_E_LIGHTPATH_BOUNDS (y >= height
 * or x0 + n > width).
 * On failure: nothing is written. */
QIBL_NODISCARD qibl_status_t qibl_lightpath_occl_span(const qibl_lampocc_t *o, uint32_t x0, uint32_t y, uint32_t n, int32_t *io);

#ifdef __cplusplus
}
#endif

#endif /* QIBL_LIGHTPATH_H */
