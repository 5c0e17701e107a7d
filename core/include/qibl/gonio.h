/*
 * qibl/gonio.h - goniometric lamps: a point light whose intensity depends on the direction from the
 * lamp, as a table of intensity scales over the sphere in the lamp's frame, integer only.
 *
 * The table: n x n texels of an octahedral map of the lamp's frame (x, y, z): a unit direction
 * d = (dx, dy, dz) maps to u = dx / s, v = dy / s with s = |dx| + |dy| + |dz|, folded for dz < 0 to
 * u' = sign(u) (1 - |v|), v' = sign(v) (1 - |u|); texel (i, j) (column i, row j) has its centre at
 * u = (2 i + 1) / n - 1, v = (2 j + 1) / n - 1. Each texel is an intensity scale, Q1.15 unsigned
 * (0 .. 32768 = 1.0), stored as native uint16 in caller memory (qibl_gonio_table_size bytes);
 * tools make it from a measured profile (an IES file: tools/io/ies.h, the profile divided by its
 * peak). The lamp's frame comes from an aim (z: the profile's axis, an IES type C nadir) and an up
 * (y: made orthogonal to z; an IES type C horizontal angle 0), x = y cross z.
 *
 * Lookup: bilinear between the four nearest texel centres, clamped at the map's edges (not wrapped
 * across the octahedron's folds: within half a texel of an edge the nearest edge texels are used).
 * The scale multiplies a pixel's light from the lamp (qibl_gonio_scale_span after
 * qibl_shmap_point_span), so a table of 32768 everywhere leaves the lamp exactly as it was.
 *
 * No heap, no state: the view points at the caller's table, which must outlive it.
 */
#ifndef QIBL_GONIO_H
#define QIBL_GONIO_H

#include <stddef.h>
#include <stdint.h>
#include "qibl/fixed.h"
#include "qibl/shmaps.h"
#include "qibl/status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define QIBL_GONIO_MIN_N 2u
#define QIBL_GONIO_MAX_N 256u   /* 128 KiB of table at most */
#define QIBL_GONIO_ONE 32768u   /* scale 1.0 in Q1.15 */

/* A goniometric lamp's table and frame (qibl_gonio_init). */
typedef struct qibl_gonio {
    uint32_t n;
    const uint16_t *table;      /* n * n scales, row j = v, column i = u, Q1.15 in 0 .. 32768 */
    qibl_q30_t x[3], y[3], z[3]; /* the lamp's frame in world coordinates, unit vectors, Q2.30 */
} qibl_gonio_t;

/* Bytes of an n x n table (n n * 2), or 0 for n outside QIBL_GONIO_MIN_N .. QIBL_GONIO_MAX_N. */
size_t qibl_gonio_table_size(uint32_t n);

/* Fills *g from table (n x n) and the lamp's aim and up (any lengths, Q16.16 or any common format).
 * z = aim / |aim|; y = up made orthogonal to z, normalised; x = y cross z. Cost: one pass over the
 * table.
 * Formats: aim, up int32 triples in any common Q format (directions only); table Q1.15 unsigned;
 * out frame Q2.30 unit vectors.
 * Bound: z within 1 LSB of Q2.30 per component (qibl_vec3_normalize_q30); y and x, built from
 * rounded vectors, within a few LSB of Q2.30.
 * Errors, in this order: QIBL_E_NULL_POINTER (g, table, aim or up NULL); QIBL_E_GONIO_SIZE (n
 * outside QIBL_GONIO_MIN_N .. QIBL_GONIO_MAX_N); QIBL_E_GONIO_TABLE (an entry above 32768);
 * QIBL_E_GONIO_AIM (aim zero); QIBL_E_GONIO_UP (up zero, or up so nearly parallel to aim that
 * every component of up's part orthogonal to aim is below 2^-11, i.e. within about 2^-11 to
 * 2^-10 rad).
 * On failure: nothing is written (*g untouched). */
QIBL_NODISCARD qibl_status_t qibl_gonio_init(qibl_gonio_t *g, uint32_t n, const uint16_t *table, const int32_t aim[3],
                              const int32_t up[3]);

/* The scale (Q1.15, 0 .. 32768) toward world direction d from the lamp (any length: d is only a
 * direction; components up to 2^62 in magnitude). d = 0 gives the aim's scale. The bilinear
 * interpolation of the table at the direction's texel position, that position computed from the
 * direction reduced to 24 bits per component and floored to 2^-16 texel, the result rounded to
 * nearest: at a texel centre the texel's value within 1 LSB; measured against the interpolation in
 * double at the same direction <= 2 LSB (1.2 measured, neighbours up to 30000 apart: gonio_test.c).
 * No checks (hot path): g from qibl_gonio_init. */
uint32_t qibl_gonio_lookup(const qibl_gonio_t *g, const int64_t d[3]);

/* Multiplies the Q16.16 RGB of a span (3 n int32, pixels x0 .. x0 + n - 1 of row y, as
 * qibl_shmap_point_span writes it) by the scale toward each pixel's point of the P map p from the
 * lamp at pos (Q16.16, the P map's units): out = round(out * scale / 32768), ties away from zero,
 * sign kept (|out| never grows: no saturation needed). n == 0 is a valid empty span.
 * Formats: pos and p's points Q16.16; out 3 n int32 in any Q format (Q16.16 RGB), in place;
 * scales Q1.15.
 * Bound: each product rounded to nearest (<= 0.5 LSB of out) against the scale qibl_gonio_lookup
 * returns (itself within 2 LSB of Q1.15, see there); a scale of exactly 1.0 leaves out exact.
 * Errors, in this order: QIBL_E_NULL_POINTER (g, p, p->points, pos or out NULL);
 * QIBL_E_GONIO_BOUNDS (y >= p's height or x0 + n > p's width).
 * On failure: nothing is written. */
QIBL_NODISCARD qibl_status_t qibl_gonio_scale_span(const qibl_gonio_t *g, const qibl_pmap_t *p, const qibl_q16_t pos[3],
                                    uint32_t x0, uint32_t y, uint32_t n, int32_t *out);

#ifdef __cplusplus
}
#endif

#endif /* QIBL_GONIO_H */
