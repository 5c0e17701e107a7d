/*
 * qibl/raster.h - z-buffered triangles with per-vertex colour (Gouraud) into a software
 * framebuffer (qibl/soft.h): how a handheld without a GPU draws a mesh shaded per vertex, e.g. by
 * the hemispherical-rasterization transfer (qibl/hemi.h).
 *
 * Same rules as qibl/soft.h: freestanding C99, integer only, no heap, no mutable state, identical
 * bytes on every port; nothing is written unless the call returns QIBL_OK.
 *
 * Coverage: a pixel (i, j) is covered when its centre (i + 1/2, j + 1/2) is inside the triangle;
 * a centre exactly on an edge belongs to one side only (a top-left style rule, antisymmetric in the
 * edge direction), so a closed mesh covers every pixel of its silhouette exactly once: no cracks,
 * no double blending. Vertex positions are in 1/16 pixel (Q27.4), |x|, |y| <= QIBL_RASTER_COORD_MAX
 * (a guard band of 8192 pixels; clip in the caller beyond it). Triangles of zero area draw nothing.
 *
 * Attributes (depth z and the three colour channels) are the plane through the three vertices
 * evaluated at the pixel centre: gradients are rounded to 2^-16 per 1/16 pixel, then the plane is
 * stepped in exact 64-bit additions (no per-pixel multiply or division), rounded half up and
 * clamped to the range of the three vertices' values. Error against the exact plane:
 * <= 0.5 LSB + 2^-17 (|dx| + |dy|) LSB, dx, dy the pixel centre's offset from the first vertex in
 * 1/16 pixel (under 0.6 LSB for triangles below 512 pixels across). A sliver whose gradient exceeds
 * 2^24 per 1/16 pixel has it capped; its pixels still lie within the vertices' range.
 *
 * Depth: smaller is nearer; a pixel is written when z < depth buffer (strictly, so the first of
 * equal-depth triangles wins), and the depth buffer then holds z. Colour: Q16.16 linear per channel
 * (negative values clamp to 0), converted exactly as qibl_soft_fb_write_row converts a row (exposure,
 * sRGB, dither at the absolute pixel position). 8-bit formats only: the accumulator format adds,
 * which overdraw would make meaningless.
 *
 * Cost per triangle: setup of 3 edges and 4 attribute planes (64-bit divisions by the area); per
 * pixel of the bounding box: 3 edge tests (64-bit add, compare); per covered pixel: a depth
 * compare, 4 plane steps and the framebuffer's own packing, written in runs through
 * qibl_soft_fb_write_row. Stack: about 1 KiB (a 64-pixel run buffer).
 */
#ifndef QIBL_RASTER_H
#define QIBL_RASTER_H

#include <stddef.h>
#include <stdint.h>
#include "qibl/fixed.h"
#include "qibl/soft.h"
#include "qibl/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* This module's statuses QIBL_E_RASTER_RANGE and QIBL_E_RASTER_INDEX are in soft.h, with the rest of
 * the soft backend's range and its one list of messages. */

#define QIBL_RASTER_SUBPIXEL 4                /* fraction bits of vertex x, y */
#define QIBL_RASTER_COORD_MAX (8192 * 16)     /* |x|, |y| limit, 1/16 pixel */
#define QIBL_RASTER_DEPTH_FAR 0xFFFFFFFFu     /* a cleared depth buffer */

/* A screen-space vertex. */
typedef struct qibl_raster_vertex {
    int32_t x, y;      /* 1/16 pixel (Q27.4), y down; |x|, |y| <= QIBL_RASTER_COORD_MAX */
    int32_t z;         /* depth, 0 .. 2^31 - 1, smaller = nearer, any scale */
    qibl_q16_t rgb[3]; /* linear colour, Q16.16, 1.0 = white after exposure */
} qibl_raster_vertex_t;

/* Which winding to skip, as seen on screen (y down). With CULL_CCW a mesh whose front faces wind
 * clockwise on screen draws its front faces only. */
typedef enum qibl_raster_cull {
    QIBL_RASTER_CULL_NONE = 0, /* default: draw both */
    QIBL_RASTER_CULL_CW,
    QIBL_RASTER_CULL_CCW
} qibl_raster_cull_t;

/* A caller-owned target. Zero-initialised fields mean the defaults noted. */
typedef struct qibl_raster_target {
    qibl_fb_desc_t fb;         /* colour: an 8-bit format (qibl/soft.h) */
    uint32_t *depth;           /* width * height depth values, row-major, no padding */
    size_t depth_count;        /* elements of depth (at least width * height) */
    qibl_raster_cull_t cull;   /* default: none */
} qibl_raster_target_t;

/* Sets every depth value to QIBL_RASTER_DEPTH_FAR (the colour is cleared by qibl_soft_fb_clear).
 * Formats: depth uint32. Bound: exact.
 * Errors: those of qibl_soft_fb_check, QIBL_E_NULL_POINTER (depth), QIBL_E_FB_SIZE (depth_count below
 * width * height).
 * On failure: nothing is written. */
QIBL_NODISCARD qibl_status_t qibl_soft_raster_clear_depth(const qibl_raster_target_t *t);

/* Draws ntri triangles, tri[k] indexing v[0 .. nv), in order, depth-tested.
 * Formats: vertices as qibl_raster_vertex_t above; colour through qibl_soft_fb_write_row.
 * Bound: coverage and depth exact (integer edge functions); colour as qibl_soft_fb_write_row.
 * Errors, in this order: those of qibl_soft_fb_check, QIBL_E_FB_FORMAT (QIBL_FB_ACCUM32),
 * QIBL_E_NULL_POINTER (depth, or v / tri with a non-zero count), QIBL_E_FB_SIZE (depth_count below
 * width * height), QIBL_E_RASTER_INDEX, QIBL_E_RASTER_RANGE (a referenced vertex with |x| or |y| >
 * QIBL_RASTER_COORD_MAX or z < 0).
 * On failure: nothing is written (everything is validated before the first pixel). */
QIBL_NODISCARD qibl_status_t qibl_soft_raster_triangles(const qibl_raster_target_t *t, const qibl_raster_vertex_t *v, uint32_t nv,
                                    const uint32_t (*tri)[3], uint32_t ntri);

/* Deprecated since 0.2 (removed in 0.3): the rasterizer's names before the backend took one prefix,
 * qibl_soft_. Define QIBL_SOFT_NO_DEPRECATED to leave them out. */
#ifndef QIBL_SOFT_NO_DEPRECATED
#define qibl_raster_clear_depth qibl_soft_raster_clear_depth /* deprecated */
#define qibl_raster_triangles qibl_soft_raster_triangles     /* deprecated */
#endif

#ifdef __cplusplus
}
#endif

#endif /* QIBL_RASTER_H */
