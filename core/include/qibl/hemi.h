/*
 * qibl/hemi.h - hemispherical rasterization (Kautz, Lehtinen & Aila): per-vertex visibility of a
 * deforming mesh as a 1-bit mask over the unit disk, and its SH transfer vector, integer only.
 *
 * The mask: the hemisphere above a receiver vertex, in the vertex's tangent frame (z = normal),
 * projected onto the unit disk by dropping z (the Nusselt analog: area on the disk is projected
 * solid angle, so the disk is importance-sampled by the cosine). N x N pixels, N = 16, 32 or 64;
 * pixel (row r, column c) has its centre at x = (2c + 1 - N) / N, y = (2r + 1 - N) / N. A pixel is
 * in the disk when its square meets the disk; its LUT sample point is its centre lifted onto the
 * hemisphere, or, for a centre outside the disk, the nearest point of the horizon. Storage: N rows
 * of max(1, N / 32) uint32 words, bit c % 32 of word c / 32 (16 x 16 uses the low half of a word).
 * Set bit = blocked.
 *
 * Rasterization: a blocker triangle (a, b, c) seen from the receiver at the origin covers exactly
 * the directions above its three edge planes (planes through the origin and an edge, normals
 * a x b, b x c, c x a, oriented by det = a . (b x c)); the cone they bound is the triangle's, so a
 * triangle crossing the horizon needs no clipping (the mask holds only the upper hemisphere). Each
 * plane's mask comes from a look-up table indexed by a cube-map parameterisation of its normal
 * (F x F cells per face, the cell's centre normal decides: bit set where centre . s > 0); the
 * triangle's mask is the AND of the three and is ORed into the vertex's mask (occluder fusion).
 * Setup: each vertex's direction is first quantised (scaled by its own power of two, rounded to
 * |q| <= 512: within 2^-9 rad), so the edge normals and det are exact int32 (no 64-bit product)
 * and identical on every port and dispatch choice; where the quantised det is 0 the exact int64
 * setup on the unquantised vertices decides. The masks are the quantised triangle's (a near-
 * degenerate triangle may become a sliver of a few pixels along its plane).
 * Skipped: triangles with every vertex at or below the horizon (z <= 0), and triangles whose
 * plane passes through the receiver (exact det = 0: degenerate triangles, triangles sharing the
 * receiver vertex, edge-on triangles).
 * The table folds one symmetry, so it holds 3 F^2 masks instead of 6 F^2: the plane -p gives the
 * complement of p's mask (the -x, -y and -z faces), an XOR at run time. The disk's mirror
 * symmetries (row reversals) would halve it again but are not folded: a mirrored entry is read in
 * another row order, a branch or shuffle per triangle that measured slower (docs/ARCHITECTURE.md).
 *
 * Transfer: V*_i = integral of Y_i(s) V(s) max(0, n.s) ds = integral over the disk of
 * Y_i(x, y, sqrt(1 - x^2 - y^2)) V dx dy, per pixel exactly as a table: T[p][i] = the integral of Y_i
 * over pixel p's square cut by the disk, integrated at init by (256 / N)^2 sub-samples per pixel
 * with qibl_sh_eval_unit. V*_i is the sum of T over the visible pixels, in Q2.30, summed with
 * wrapping uint32 arithmetic (exact: the true sum is below 2 by Cauchy-Schwarz, sqrt(pi) < 1.78), so
 * summing the visible pixels or subtracting the blocked ones from the unblocked transfer gives the
 * same bits; the cheaper side is taken per mask.
 *
 * Frame: qibl_hemi_frame_init builds the tangent frame R = Rz(alpha) Ry(beta) whose z axis is the
 * normal n = (sin b cos a, sin b sin a, cos b): x axis t = (cos b cos a, cos b sin a, -sin b),
 * y axis (-sin a, cos a, 0) (alpha = 0 when n is +-z). That choice makes the SH rotation of the
 * frame cheap: D(R) = Dz(alpha) D(Rx(-90)) Dz(beta) D(Rx(90)), two constant band matrices made at
 * init with qibl_sh_rotation_init and two z rotations (cos/sin m theta by recurrence).
 *
 * Memory: qibl_hemi_workspace_size(N, F) bytes, any alignment: the two rotations (twice sizeof(qibl_sh_rotation_t)), the
 * disk mask and unblocked transfer, the basis table (100 N^2 bytes), the LUT (3 F^2 masks of
 * 4 N max(1, N/32) bytes) and the pixel centres (4 N^2 bytes). N = 32: F = QIBL_HEMI_FACE_DEFAULT
 * (48, the largest whose workspace fits in 1 MiB), F = 20 (small: within 256 KiB).
 * Init cost: 3 F^2 N^2 exact pixel tests and 65536 SH evaluations.
 * All but the rotations are pure functions of (N, F), the same bytes on every port and read-only:
 * a machine with little RAM keeps them in ROM, flash or a mapped file as one blob
 * (qibl_hemi_tables_build, any span of its words at a time, e.g. baked on the host) and opens it
 * in place (qibl_hemi_open), with only the rotations (QIBL_HEMI_OPEN_WORKSPACE_SIZE bytes) in RAM.
 */
#ifndef QIBL_HEMI_H
#define QIBL_HEMI_H

#include <stddef.h>
#include <stdint.h>
#include "qibl/config.h"
#include "qibl/fixed.h"
#include "qibl/sh.h"
#include "qibl/status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define QIBL_HEMI_COEFFS 25          /* transfer vectors: SH bands 0..4 */
/* The LUT face size the tools use unless told otherwise: the largest whose N = 32 tables fit 1 MiB. */
#define QIBL_HEMI_FACE_DEFAULT 48u
#define QIBL_HEMI_MAX_WORDS 128u     /* uint32 words of the largest mask (64 x 64) */
#define QIBL_HEMI_MAX_FACE 128       /* largest cube-map face (even sizes 2..128) */
#define QIBL_HEMI_COORD_MAX 0x3FFFFF /* |position coordinate| limit, Q16.16 (64 units) */
#define QIBL_HEMI_LOCAL_FRAC 18      /* fraction bits of frame-local coordinates (Q14.18) */
#define QIBL_HEMI_LOCAL_MAX 0x3FFFFFF /* |frame-local coordinate| limit accepted by the rasterizer */
#define QIBL_HEMI_MAX_EXPONENT 4096u  /* largest Phong exponent of qibl_hemi_transfer_phong */

/* uint32 words of an N x N mask (N = 16, 32, 64). */
#define QIBL_HEMI_MASK_WORDS(n) ((n) * ((n) > 32 ? (n) / 32 : 1))

/* A rasterizer: mask size, face size and views into the caller's workspace (read-only after init;
 * one instance may serve any number of threads). Fields are private. */
typedef struct qibl_hemi {
    int32_t n, face;
    uint32_t wpr, words;
    const qibl_sh_rotation_t *rx_pos, *rx_neg; /* D(Rx(+90 deg)), D(Rx(-90 deg)) */
    const uint32_t *disk;                      /* [words] pixels meeting the disk */
    const uint32_t *full;                      /* [25] transfer of the unblocked hemisphere (Q2.30) */
    const uint32_t *basis;                     /* [N * N][25] per-pixel integrals (Q2.30, two's complement) */
    const uint32_t *lut;                       /* [3 F^2][words]: faces +x, +y, +z */
    const uint32_t *zc;                        /* [N * N] z of the pixel centres on the hemisphere (Q2.30) */
} qibl_hemi_t;

/* A receiver's tangent frame (qibl_hemi_frame_init). */
typedef struct qibl_hemi_frame {
    qibl_q16_t p[3];       /* receiver position */
    qibl_q30_t axis[3][3]; /* rows: t, b, n (world -> local) */
    qibl_q30_t ca, sa;     /* cos, sin alpha */
    qibl_q30_t cb, sb;     /* cos, sin beta */
} qibl_hemi_frame_t;

/* Counters that qibl_hemi_raster adds to (NULL: not counted). */
typedef struct qibl_hemi_stats {
    uint32_t rasterized; /* triangles ANDed and ORed into the mask */
    uint32_t below;      /* every vertex at or below the horizon */
    uint32_t through;    /* plane through the receiver (degenerate, sharing it, edge-on) */
} qibl_hemi_stats_t;

/* Workspace bytes for mask size n (16, 32, 64) and cube-map face size face (even, 2..128);
 * 0 for other sizes. */
size_t qibl_hemi_workspace_size(int n, int face);

/* Builds the tables into workspace (deterministic, integer; any alignment) and fills *h.
 * Formats: tables Q2.30 (basis integrals, unblocked transfer, centre heights), u32 bit masks.
 * Bound: each basis entry within 2^-30 of the (256 / N)^2-point sub-sampled integral of its pixel.
 * Errors, in this order: QIBL_E_NULL_POINTER (h or workspace NULL), QIBL_E_HEMI_SIZE (n not 16, 32
 * or 64, or face not even in 2..128), QIBL_E_WORKSPACE (workspace_size below
 * qibl_hemi_workspace_size).
 * On failure: *h and the workspace untouched (every check precedes the first write). */
QIBL_NODISCARD qibl_status_t qibl_hemi_init(qibl_hemi_t *h, int n, int face, void *workspace, size_t workspace_size);

/* ---- the tables as one blob (ROM, flash, a mapped file) -----------------------------------------
 * The read-only tables of qibl_hemi_init as uint32 words in the machine's byte order, exactly
 * qibl_hemi_tables_size(n, face) bytes, 4-byte aligned:
 *   word  field
 *    0    magic "QHMT" (0x544D4851; another value: another format or the other byte order)
 *    1    version, QIBL_HEMI_TABLES_VERSION
 *    2    n (16, 32 or 64)
 *    3    face (even, 2..128)
 *    4    size: the blob's bytes
 *    5    CRC-32 (qibl_crc32, as the asset's chunks) of the payload, each word little-endian
 *    6-7  reserved, 0
 *    8..  payload: the disk mask (M = N max(1, N/32) words), the unblocked transfer (25), the
 *         basis table (25 N^2, pixel after pixel), the LUT (3 F^2 masks of M words: faces +x, +y,
 *         +z) and the pixel centres' heights (N^2)
 * Needs QIBL_USE_ASSET (its CRC-32). A port bakes its blobs on the host (`qibl-hemi-tables`,
 * tools/gba/hemi_tables.c) or builds them itself, a span at a time. */
#define QIBL_HEMI_TABLES_HEADER_SIZE 32u
#define QIBL_HEMI_TABLES_VERSION 1u
/* Workspace bytes of qibl_hemi_open: the two rotations, any alignment. */
#define QIBL_HEMI_OPEN_WORKSPACE_SIZE (2u * sizeof(qibl_sh_rotation_t) + 4u)

/* Bytes of the tables blob for mask size n (16, 32, 64) and face size face (even, 2..128); 0 for
 * other sizes: 32 + 4 (M + 25 + 26 N^2 + 3 F^2 M), the workspace of qibl_hemi_init less the
 * rotations and its slack plus the header. */
size_t qibl_hemi_tables_size(int n, int face);

/* Words [first, first + count) of the blob for (n, face) into out[0 .. count): any span, so that a
 * machine with little RAM makes, checks or hashes the blob chunk by chunk; the words do not depend
 * on how the blob is cut. Cost: each table word asked for is made; the unblocked transfer (words
 * 8 + M .. 8 + M + 25), or the header's CRC word when the span does not hold the whole payload,
 * costs one pass over every basis row (65536 SH evaluations) without storing them.
 * Formats: u32 words as documented above (tables Q2.30 and u32 bit masks, as qibl_hemi_init's).
 * Bound: exact (qibl_hemi_init's tables, bit for bit).
 * Errors, in this order: QIBL_E_NULL_POINTER (out NULL with count != 0), QIBL_E_HEMI_SIZE (n not 16,
 * 32 or 64, or face not even in 2..128), QIBL_E_HEMI_TABLES_BOUNDS (the span runs past the blob's
 * qibl_hemi_tables_size(n, face) / 4 words; count 0 is a valid empty span).
 * On failure: nothing is written (out untouched). */
QIBL_NODISCARD qibl_status_t qibl_hemi_tables_build(int n, int face, uint32_t first, uint32_t count, uint32_t *out);

/* Opens a blob in place (the caller's bytes must outlive *h and stay unchanged): checks every header
 * field, the size, the alignment and the payload's CRC-32, makes the two rotations in workspace and
 * fills *h, which then serves every call as qibl_hemi_init's does (the same tables, the same results).
 * Formats: the blob as documented above. Cost: one CRC-32 over the blob.
 * Bound: exact (views of the caller's words).
 * Errors, in this order: QIBL_E_NULL_POINTER (h, tables or workspace NULL), QIBL_E_HEMI_SIZE (n, face
 * as qibl_hemi_init), QIBL_E_WORKSPACE (workspace_size below QIBL_HEMI_OPEN_WORKSPACE_SIZE),
 * QIBL_E_HEMI_TABLES_ALIGN (tables not 4-byte aligned), QIBL_E_HEMI_TABLES_SIZE (tables_size not
 * qibl_hemi_tables_size(n, face)), QIBL_E_HEMI_TABLES_MAGIC, QIBL_E_HEMI_TABLES_VERSION,
 * QIBL_E_HEMI_TABLES_SHAPE (the header's n or face not those asked for), QIBL_E_HEMI_TABLES_HEADER
 * (the header's size or reserved words), QIBL_E_HEMI_TABLES_CRC.
 * On failure: *h and the workspace untouched (every check precedes the first write). */
QIBL_NODISCARD qibl_status_t qibl_hemi_open(qibl_hemi_t *h, int n, int face, const void *tables, size_t tables_size,
                                            void *workspace, size_t workspace_size);

/* The receiver frame at position p (|coordinate| <= QIBL_HEMI_COORD_MAX) with normal nrm (any
 * non-zero int32 vector).
 * Formats: p Q16.16; nrm any common Q format (a direction only); axes and angles Q2.30.
 * Bound: n within 1 LSB of Q2.30 per component; the axes within a few LSB of Q2.30 of orthonormal.
 * Errors, in this order: QIBL_E_NULL_POINTER (f, p or nrm NULL), QIBL_E_HEMI_RANGE (a coordinate of
 * p beyond QIBL_HEMI_COORD_MAX), QIBL_E_ZERO_VECTOR (nrm zero).
 * On failure: nothing is written (*f untouched). */
QIBL_NODISCARD qibl_status_t qibl_hemi_frame_init(qibl_hemi_frame_t *f, const qibl_q16_t p[3], const int32_t nrm[3]);

/* Blocker vertices into the frame: out[k] = R^T (pos[k] - p), rounded half up. Transform each
 * vertex once per receiver, then rasterize any number of triangles that index it.
 * Formats: pos Q16.16; out Q14.18 (QIBL_HEMI_LOCAL_FRAC); the frame's axes Q2.30.
 * Bound: error <= 0.5 LSB + 2^-28 |pos - p| (the axes).
 * Errors, in this order: QIBL_E_NULL_POINTER (f NULL, or pos or out NULL with count != 0),
 * QIBL_E_HEMI_RANGE (a coordinate of pos beyond QIBL_HEMI_COORD_MAX).
 * On failure: nothing is written (out untouched). */
QIBL_NODISCARD qibl_status_t qibl_hemi_transform(const qibl_hemi_frame_t *f, const qibl_q16_t (*pos)[3], uint32_t count,
                                  int32_t (*out)[3]);

/* Clears a mask (h->words words).
 * Formats: mask u32 bit words. Bound: exact.
 * Errors: QIBL_E_NULL_POINTER (h or mask NULL).
 * On failure: nothing is written. */
QIBL_NODISCARD qibl_status_t qibl_hemi_clear(const qibl_hemi_t *h, uint32_t *mask);

/* ORs the triangles tri[0..ntri) (indices into the frame-local vertices v[0..nv)) into mask.
 * Faces around the receiver are skipped (their planes pass through it), but at a crease the solid
 * behind them still hides part of the averaged normal's hemisphere: a caller that knows the faces
 * (v, b, c) around the receiver rasterizes the wedges (nadir, b, c) too, the nadir a vertex at
 * (0, 0, -D) (any winding; at a convex vertex the wedges lie below the horizon and cost a test
 * each). `qibl transfer` does; it cuts a box's error against the ray cast by an order of magnitude.
 * Culling and skipping as above; a triangle is the same mask whichever way it winds.
 * Formats: v Q14.18 (frame-local, from qibl_hemi_transform); mask u32 bit words.
 * Bound: the LUT's masks of the quantised triangle's planes (setup above), bit for bit on every
 * port and dispatch choice (x86 AVX2: 8-wide int32 lanes, the cell divide in float32 lanes with its
 * floor corrected exactly).
 * Errors, in this order: QIBL_E_NULL_POINTER (h or mask NULL, or v/tri NULL with ntri != 0),
 * QIBL_E_HEMI_INDEX (an index >= nv), QIBL_E_HEMI_RANGE (a coordinate of v[0..nv) beyond
 * QIBL_HEMI_LOCAL_MAX).
 * On failure: nothing is written (checked before anything is: mask and stats untouched). */
QIBL_NODISCARD qibl_status_t qibl_hemi_raster(const qibl_hemi_t *h, const int32_t (*v)[3], uint32_t nv, const uint32_t (*tri)[3],
                               uint32_t ntri, uint32_t *mask, qibl_hemi_stats_t *stats);

/* Group culling (the paper's hierarchical culling): a bounding sphere per group of blocker
 * triangles, remade each frame from the group's vertices, tested against each receiver's tangent
 * plane before the group's vertices are transformed. */
typedef struct qibl_hemi_bound {
    qibl_q16_t c[3]; /* centre: the middle of the vertices' box (rounded down), Q16.16 */
    int32_t r;       /* radius, Q16.16, rounded up (>= every vertex's distance); -1: empty group */
} qibl_hemi_bound_t;

/* The bound of pos[idx[0..n)] (idx NULL: pos[0..n)); n = 0 gives the empty group.
 * Formats: pos, out's centre and radius Q16.16.
 * Bound: centre rounded down, radius rounded up: conservative (no vertex outside the sphere).
 * Errors, in this order: QIBL_E_NULL_POINTER (out NULL, or pos NULL with n != 0), then vertex by
 * vertex QIBL_E_HEMI_INDEX (idx[k], or k without idx, >= nv) and QIBL_E_HEMI_RANGE (a coordinate
 * beyond QIBL_HEMI_COORD_MAX).
 * On failure: nothing is written (*out untouched). */
QIBL_NODISCARD qibl_status_t qibl_hemi_bound_fit(const qibl_q16_t (*pos)[3], uint32_t nv, const uint32_t *idx, uint32_t n,
                              qibl_hemi_bound_t *out);

/* 0 when every point of the sphere is at or below the tangent plane of f's receiver, so every
 * triangle of the group would be culled by qibl_hemi_raster after qibl_hemi_transform (their local
 * z <= 0): skipping the group changes no mask. 1 otherwise (conservative: the normal's length is
 * rounded up). Exact integer test, |normal . (c - p)| + r |normal| < 2^56. NULL or empty: 0; a
 * centre beyond QIBL_HEMI_COORD_MAX (no bound of qibl_hemi_bound_fit): 1. */
int qibl_hemi_bound_above(const qibl_hemi_frame_t *f, const qibl_hemi_bound_t *b);

/* 1 when f's receiver is closer to the bound's centre than k radii (k in Q8.8: 512 = 2), i.e. the
 * group may subtend more than 2 asin(1 / k) from it: refine such a group (rasterize its
 * full-resolution triangles, its coarse ones elsewhere) so that a fold of a deforming mesh that
 * comes close is seen at full resolution. Exact integer test: |c - p|^2 2^16 < (k r)^2. NULL,
 * empty or k = 0: 0; a centre beyond QIBL_HEMI_COORD_MAX: 1. */
int qibl_hemi_bound_near(const qibl_hemi_frame_t *f, const qibl_hemi_bound_t *b, uint32_t k_q8);

/* Both tests for n groups of one receiver in one pass (a mesh's coarse groups far[c] and their
 * full-resolution groups near[c]): out[c] = 2 when qibl_hemi_bound_near(f, &near[c], k_q8) and
 * qibl_hemi_bound_above(f, &near[c]) (rasterize the full-resolution group), 1 when not near and
 * qibl_hemi_bound_above(f, &far[c]) (the coarse group), else 0 (neither: culled). k_q8 = 0: no
 * group is near. The same answers as those calls; the normal's length is rounded up once, not per
 * group.
 * Formats: the bounds' centres and radii Q16.16 (qibl_hemi_bound_fit), k_q8 Q8.8; out one byte per
 * group.
 * Bound: exact integer tests, as qibl_hemi_bound_near and qibl_hemi_bound_above.
 * Errors: QIBL_E_NULL_POINTER (f NULL, or near, far or out NULL with n != 0).
 * On failure: nothing is written. */
QIBL_NODISCARD qibl_status_t qibl_hemi_bound_cull(const qibl_hemi_frame_t *f, const qibl_hemi_bound_t *near,
                                                  const qibl_hemi_bound_t *far, uint32_t n, uint32_t k_q8, uint8_t *out);

/* mask &= the disk (clears bits of pixels outside it: complemented table entries set them).
 * Formats: mask u32 bit words. Bound: exact.
 * Errors: QIBL_E_NULL_POINTER (h or mask NULL).
 * On failure: nothing is written. */
QIBL_NODISCARD qibl_status_t qibl_hemi_clip(const qibl_hemi_t *h, uint32_t *mask);

/* The local transfer vector of a mask (blocked bits outside the disk are ignored): out[i] = V*_i.
 * Formats: mask u32 bit words; out Q2.30.
 * Bound: the exact sum of the per-pixel tables (each within 2^-30 plus the sub-sampling of the
 * pixel's integral).
 * Errors: QIBL_E_NULL_POINTER (h, mask or out NULL).
 * On failure: nothing is written (out untouched). */
QIBL_NODISCARD qibl_status_t qibl_hemi_transfer(const qibl_hemi_t *h, const uint32_t *mask, qibl_q30_t out[QIBL_HEMI_COEFFS]);

/* The glossy (Phong) transfer for one view: out[i] = sum over the visible pixels p of the disk of
 * T[p][i] max(0, r . s_p)^e, r the mirror direction of the view about the normal in the vertex's
 * frame (refl, any non-zero int32 vector; normalised here), e the Phong exponent (0 gives the
 * diffuse transfer of qibl_hemi_transfer, to the rounding), s_p the pixel's centre lifted onto the
 * hemisphere (the horizon point for a centre outside the disk): the lobe is taken constant over
 * each pixel, so its error grows with e (measured in tests/hemi_test.c against a fine quadrature).
 * Times (e + 2) / (2 pi) for the normalised Phong BRDF; dot with the lighting as the diffuse V*.
 * Q2.30 out; arithmetic: r . s_p in Q30 (error <= 2 LSB), its power by squaring in Q30 (each
 * product truncated: error <= 2 log2(e) + 2 LSB), the weight cut to 15 bits, the sum T w exact in
 * int64. Cost: per visible pixel with a non-zero weight, up to 2 log2(e) products and 25
 * multiply-adds (many times the diffuse transfer, which sums set bits only; `qibl bench hemi`
 * measures both).
 * Formats: mask u32 bit words; refl any common Q format (a direction only); out Q2.30.
 * Bound: |out - the midpoint sum| <= 2^-14 of the sum of |T| over the disk.
 * Errors, in this order: QIBL_E_NULL_POINTER (h, mask, refl or out NULL), QIBL_E_HEMI_EXPONENT
 * (e > QIBL_HEMI_MAX_EXPONENT), QIBL_E_ZERO_VECTOR (refl zero).
 * On failure: nothing is written (out untouched). */
QIBL_NODISCARD qibl_status_t qibl_hemi_transfer_phong(const qibl_hemi_t *h, const uint32_t *mask, const qibl_q30_t refl[3],
                                       uint32_t exponent, qibl_q30_t out[QIBL_HEMI_COEFFS]);

/* Transfer out of the frame: world = D(R) local (in and out may not alias).
 * Formats: in and out 25 coefficients Q2.30.
 * Bound: a few LSB of Q2.30 times the largest |in| (four rotations, each rounded).
 * Errors: QIBL_E_NULL_POINTER (h, f, in or out NULL).
 * On failure: nothing is written. */
QIBL_NODISCARD qibl_status_t qibl_hemi_to_world(const qibl_hemi_t *h, const qibl_hemi_frame_t *f, const qibl_q30_t *in,
                                 qibl_q30_t *out);

/* Lighting into the frame: local = D(R)^T world, one channel per call; the alternative to
 * qibl_hemi_to_world (costs one call per channel instead of one per vertex). in and out may not
 * alias.
 * Formats: in and out 25 coefficients in any int32 fixed-point format, the same for both
 * (saturated).
 * Bound: as qibl_hemi_to_world, a few LSB of the format times the largest |in|, unless saturated.
 * Errors: QIBL_E_NULL_POINTER (h, f, in or out NULL).
 * On failure: nothing is written. */
QIBL_NODISCARD qibl_status_t qibl_hemi_to_frame(const qibl_hemi_t *h, const qibl_hemi_frame_t *f, const int32_t *in,
                                 int32_t *out);

/* Shading: out[ch] = sum_i light[ch][i] v[i] (irradiance; times albedo / pi gives the diffuse
 * exitant radiance), rounded half up, saturated.
 * Formats: light Q16.16 (radiance SH, as qibl_shlight_t); v Q2.30 (same frame as the light); out
 * Q16.16.
 * Bound: each product is truncated by 2^-14 LSB before the sum: error <= 0.5 + 25 * 2^-14 LSB,
 * unless saturated.
 * Errors: QIBL_E_NULL_POINTER (light, v or out NULL).
 * On failure: nothing is written. */
QIBL_NODISCARD qibl_status_t qibl_hemi_shade(const int32_t light[3][QIBL_HEMI_COEFFS], const qibl_q30_t v[QIBL_HEMI_COEFFS],
                              qibl_q16_t out[3]);

/* ---- exported transfer (`qibl transfer --export FILE.qtr`): PRT at run time ---------------------
 * A static mesh's per-vertex world-space transfer vectors, shaded by the engine under any (rotated)
 * SH light: out = transfer . light per vertex, the very sum qibl_hemi_shade makes. The file, all
 * fields little-endian, 4-byte aligned, exactly QIBL_HEMI_XFER_HEADER_SIZE + count * n * 4 bytes:
 *   offset size  field
 *    0      4    magic "QTRX"
 *    4      2    version, 1
 *    6      2    bands: 3, 4 or 5 (n = bands^2 = 9, 16 or 25 coefficients per vertex)
 *    8      4    count: vertices, 1 .. QIBL_HEMI_XFER_MAX_VERTICES
 *   12      4    frac_bits: 30 (coefficients Q2.30, world frame: qibl_hemi_to_world's output)
 *   16      4    reserved, 0
 *   20      4    CRC-32 (qibl_crc32, as the asset's chunks) of the payload bytes
 *   24      ...  payload: count * n int32, vertex after vertex, coefficient i = l (l + 1) + m
 * Needs QIBL_USE_ASSET (its CRC-32). No workspace: the calls read the caller's bytes in place. */
#define QIBL_HEMI_XFER_HEADER_SIZE 24u
#define QIBL_HEMI_XFER_VERSION 1u
#define QIBL_HEMI_XFER_MAX_VERTICES 16777216u /* 2^24: the payload stays below 2^31 bytes */

/* A validated export: a view of the caller's bytes (they must outlive it). */
typedef struct qibl_hemi_xfer_t {
    const uint8_t *payload; /* count * ncoef int32 little-endian, Q2.30 */
    uint32_t count;         /* vertices */
    uint32_t bands, ncoef;  /* 3..5, bands^2 */
} qibl_hemi_xfer_t;

/* Validates bytes[0 .. n) once (header, size, CRC) and fills x. Errors, one per bad input, x
 * untouched: QIBL_E_NULL_POINTER, QIBL_E_HEMI_XFER_SHORT (n below the header), QIBL_E_HEMI_XFER_MAGIC,
 * QIBL_E_HEMI_XFER_FORMAT (version, bands, frac_bits or reserved not as above, count 0 or above
 * the limit), QIBL_E_HEMI_XFER_SIZE (n not the header plus the payload the fields imply),
 * QIBL_E_HEMI_XFER_CRC. Cost: one CRC-32 over the payload. */
qibl_status_t qibl_hemi_xfer_open(qibl_hemi_xfer_t *x, const uint8_t *bytes, size_t n);

/* Shades vertices first .. first + count - 1: out[k][ch] = sum_i light[ch][i] v[i] over the
 * export's n coefficients, light Q16.16 radiance SH in the export's (world) frame (rotate the light,
 * not the mesh: qibl_sh_rotate), v Q2.30, out Q16.16 irradiance, rounded half up, saturated; each
 * product truncated by 2^-14 LSB before the sum, so with 25 coefficients the result is
 * qibl_hemi_shade's bit for bit (error <= 0.5 + n 2^-14 LSB against the exact sum). Light terms
 * past n are not read. Errors, out untouched: QIBL_E_NULL_POINTER, QIBL_E_HEMI_XFER_BOUNDS (the
 * span runs past the vertices; count 0 is a valid empty span). */
qibl_status_t qibl_hemi_xfer_shade_span(const qibl_hemi_xfer_t *x, const int32_t light[3][QIBL_HEMI_COEFFS],
                                        uint32_t first, uint32_t count, qibl_q16_t (*out)[3]);

#ifdef __cplusplus
}
#endif

#endif /* QIBL_HEMI_H */
