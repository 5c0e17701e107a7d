/*
 * qibl/shmap.h - relighting a panorama from k 8-bit SH maps (Wong et al.), integer only.
 *
 * Model: each pixel stores its light-transport function as k SH coefficients per colour channel,
 * range-packed to bytes: T_i(p) = bias_i + scale_i * c_i(p) (views and layouts: shmaps.h). Incident light with
 * SH coefficients L_i gives radiance sum_i T_i(p) L_i (Wong eq. 1; L_i = Y_i(L0) for a directional
 * light of unit colour).
 *
 * Directional lights and environments. All per-pixel work is sum_i c_i(p) W_i + B: the per-frame
 * weights W_i = scale_i L_i (int16, one shared power-of-two unit per channel) and B = sum_i bias_i L_i
 * fold the range packing in, so the inner loop is bytes times int16 into int32 over planar rows,
 * which compilers vectorise. Any number of directional lights, or an environment, only changes L.
 * Accumulator bound: |sum| <= 25 * 255 * 32767 = 208,890,375 < 2^31 for any data and k <= 25.
 *
 * Point lights (Wong "Relighting by a point source"): per pixel L = S - P(p) from the P map;
 * Y_i(L) either from cube-map LUTs (bilinear, edge-clamped per face) or from the core SH polynomials
 * (qibl_sh_eval_unit on a qibl_rsqrt_u64-normalised L); attenuation C0/|L| (Wong) or C0/|L|^2,
 * with distances below min_dist clamped (a light at a pixel's own position gives that pixel 0).
 * Light behind a surface needs no special case: the transfer functions hold the cosine/visibility;
 * the small negative values SH ringing leaves are clamped by the framebuffer writer.
 *
 * Units of work: spans (x0, n) of one row. A frame is any set of spans, so callers split it across
 * threads, tiles or frames. Outputs are 3 int32 per pixel, Q16.16 linear radiance (as
 * platform/soft expects). No heap: the caller provides the workspace each call needs.
 */
#ifndef QIBL_SHMAP_H
#define QIBL_SHMAP_H

#include <stddef.h>
#include <stdint.h>
#include "qibl/shmaps.h"
#include "qibl/config.h"
#include "qibl/fixed.h"
#include "qibl/sh.h"
#include "qibl/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* SH coefficients of incident light, per colour channel, Q16.16. k of the 25 are used. */
typedef struct qibl_shlight {
    uint32_t k;
    qibl_q16_t c[3][QIBL_SH_MAX_COUNT];
} qibl_shlight_t;

/* Per-frame weights for qibl_shmap_relight_span (made by qibl_shmap_weights). */
typedef struct qibl_shmap_weights_s { /* tag != the function qibl_shmap_weights (C++ -Wshadow) */
    uint32_t k, channels;              /* of the maps they were made for */
    int16_t w[3][QIBL_SH_MAX_COUNT];   /* [output channel][map] */
    int32_t shift[3];                  /* out = acc * 2^shift + bias (shift < 0: rounded right shift) */
    int64_t bias[3];                   /* Q16.16 */
} qibl_shmap_weights_t;

/* Attenuation of a point light. 0 is the default. */
typedef enum qibl_falloff {
    QIBL_FALLOFF_INV_DIST = 0, /* C0 / |L|, as Wong et al. */
    QIBL_FALLOFF_INV_DIST2     /* C0 / |L|^2, physical */
} qibl_falloff_t;

/* How a cube-map LUT is sampled. 0 is the default. */
typedef enum qibl_lut_filter {
    QIBL_LUT_BILINEAR = 0, /* between the four nearest texel centres of the face, clamped at its edges */
    QIBL_LUT_NEAREST,      /* the texel the direction falls in: cheapest, error ~ texel size */
    /* No LUT (one passed to prepare is checked, then ignored): Y_i from the SH recurrences with int16
     * operands in Q2.14/Q3.13, 1/|L| from fixed.c's seed table and one Newton step; pixel by pixel,
     * no workspace traffic. The fastest point mode (fewer instructions per pixel than direct SH on
     * Cortex-M4 and than LUT 32^2 on x86: docs/porting.md, `qibl bench relight`) and as accurate as
     * direct SH (bounds at qibl_shmap_point_span). Its own goldens (relight_point_k*_poly*). */
    QIBL_POINT_POLY
} qibl_lut_filter_t;

/* A point light. Zero-initialisable: rgb 0 is dark, min_dist 0 means 1/256 scene unit. */
typedef struct qibl_pointlight {
    qibl_q16_t pos[3];          /* S, scene units (the P map's), Q16.16 */
    qibl_q16_t rgb[3];          /* C0 per channel, >= 0, Q16.16 */
    qibl_falloff_t falloff;
    qibl_q16_t min_dist;        /* distances below it count as it, Q16.16 > 0 */
    qibl_lut_filter_t filter;   /* when a LUT is used */
} qibl_pointlight_t;

/* Prepared point-light state (qibl_shmap_point_prepare): the light and the maps' packing folded
 * into int16 per-map factors, so the per-pixel work is Y_i(L) (scalar) then two int16 products
 * per map and channel over the span (vectorisable). Holds pointers to the views it was made from. */
typedef struct qibl_shmap_point {
    const qibl_shmaps_t *maps;
    const qibl_pmap_t *pmap;
    const qibl_ylut_t *lut;             /* NULL: evaluate the SH polynomials per pixel */
    int16_t sn[3][QIBL_SH_MAX_COUNT];   /* scale_i / 2^es[ch], [output channel][map] */
    int16_t bn[3][QIBL_SH_MAX_COUNT];   /* bias_i / 2^eb[ch] */
    int32_t es[3], eb[3];
    int64_t pos[3];
    uint32_t rgb[3];                    /* C0 per channel, Q16.16, >= 0 */
    uint32_t falloff, filter;
    uint64_t min_d2;                    /* min_dist^2 in (2^-16)^2 units */
    uint32_t clamp_y;                   /* 1 / min_dist = clamp_y / 2^clamp_e in 1/(2^-16) units */
    unsigned clamp_e;
    uint32_t bands;
    /* QIBL_POINT_POLY only: V = acc + accb 2^(14 - pd) (1 <= pd <= 14), out = V am c0m 2^-(ae + pk) with
     * c0m <= 2^15 the colour's mantissa; the min_dist clamp as mantissa and exponent (am, ae) */
    uint32_t method;                    /* 1: QIBL_POINT_POLY */
    int32_t pd[3], pk[3];
    int32_t c0m[3];
    int32_t clamp_am, clamp_ae;
    int32_t bs[3][QIBL_SH_MAX_COUNT];   /* POLY: bn 2^(14 - pd), the bias in the scale term's unit */
} qibl_shmap_point_t;

/* ---- light coefficients ---------------------------------------------------------------------- */

/* Zeroes l and sets l->k.
 * Formats: l's coefficients Q16.16 (set to 0). Bound: exact.
 * Errors, in this order: QIBL_E_NULL_POINTER (l NULL), QIBL_E_SHMAP_K (k outside
 * 1..QIBL_SH_MAX_COUNT).
 * On failure: nothing is written (*l untouched). */
QIBL_NODISCARD qibl_status_t qibl_shlight_init(qibl_shlight_t *l, uint32_t k);

/* Adds a directional light of colour rgb from direction dir (any non-zero length):
 * c[ch][i] += rgb[ch] * Y_i(dir), rounded half up, saturating.
 * Formats: rgb and l's coefficients Q16.16; dir any common Q format (a direction only).
 * Bound: per call and coefficient <= 0.5 LSB + |rgb| 2^-25 (qibl_sh_eval's bound), unless saturated.
 * Errors, in this order: QIBL_E_NULL_POINTER (l, dir or rgb NULL), QIBL_E_SHMAP_K (l->k outside
 * 1..QIBL_SH_MAX_COUNT: l not initialised), QIBL_E_ZERO_VECTOR (dir zero).
 * On failure: nothing is written (*l untouched). */
QIBL_NODISCARD qibl_status_t qibl_shlight_add_dir(qibl_shlight_t *l, const qibl_q16_t dir[3], const qibl_q16_t rgb[3]);

/* ---- directional / environment relighting ---------------------------------------------------- */

/* Checks a maps view (filled by qibl_asset_shmaps or by hand).
 * Formats: none (reads the view's fields only). Bound: exact.
 * Errors, in this order: QIBL_E_NULL_POINTER (m, m->params or m->planes NULL), QIBL_E_SHMAP_K (k
 * outside 1..QIBL_SH_MAX_COUNT), QIBL_E_SHMAP_CHANNELS (not 1 or 3), QIBL_E_SHMAP_SIZE (zero
 * width/height), QIBL_E_SHMAP_LAYOUT (unknown layout, or interleaved without QIBL_USE_INTERLEAVED).
 * On failure: nothing is written (it writes nothing, ever). */
QIBL_NODISCARD qibl_status_t qibl_shmap_check(const qibl_shmaps_t *m);

/* Per-frame weights from maps and light (light->k must be >= maps->k; extra coefficients are
 * ignored). Each channel's int16 weights share one power-of-two unit, the smallest that keeps the
 * largest weight <= 32767 (so it lies in [16384, 32767] unless every product scale * L is already an
 * exact integer below 16384 in Q40): weight quantisation adds at most 0.5 weight-LSB per map, i.e. a
 * relative error <= k * 2^-16 of the brightest map's full-scale contribution.
 * m->planes may be NULL (only the params are read: the maps view of a streamed asset's head).
 * Formats: params Q8.24, light Q16.16; out int16 weights per channel with a power-of-two shift,
 * bias int64 Q16.16.
 * Bound: as above, <= 0.5 weight-LSB per map (relative <= k * 2^-16 of the brightest map's
 * full-scale contribution).
 * Errors, in this order: those of qibl_shmap_check (m->planes not required), QIBL_E_NULL_POINTER
 * (light or out NULL), QIBL_E_SHMAP_LIGHT_K (light->k below m->k or above QIBL_SH_MAX_COUNT).
 * On failure: nothing is written (*out untouched). */
QIBL_NODISCARD qibl_status_t qibl_shmap_weights(const qibl_shmaps_t *m, const qibl_shlight_t *light, qibl_shmap_weights_t *out);

/* Workspace bytes qibl_shmap_relight_span needs for a span of n pixels (4-byte aligned storage). */
size_t qibl_shmap_span_workspace_size(uint32_t n);

/* Relights pixels x0 .. x0+n-1 of row y into out. out = sat32(acc * 2^shift + bias) per channel.
 * n == 0 is a valid empty span.
 * Formats: map bytes u8, weights as qibl_shmap_weights makes them; out 3n int32, Q16.16, RGB
 * interleaved.
 * Bound: exact integer arithmetic, so the only errors are the weights' quantisation (above) and the
 * final rounding (<= 0.5 LSB of Q16.16), unless saturated.
 * Errors, in this order: those of qibl_shmap_check, QIBL_E_NULL_POINTER (w, out or ws NULL),
 * QIBL_E_SHMAP_MISMATCH (weights made for other k/channels), QIBL_E_SHMAP_BOUNDS (span outside the
 * maps), QIBL_E_WORKSPACE (ws_size too small), QIBL_E_WORKSPACE_ALIGN (ws not on a 4-byte boundary:
 * declare it as int32_t/uint32_t storage, whatever the layout).
 * On failure: nothing is written (out and the workspace untouched). */
QIBL_NODISCARD qibl_status_t qibl_shmap_relight_span(const qibl_shmaps_t *m, const qibl_shmap_weights_t *w, uint32_t x0, uint32_t y,
                                      uint32_t n, int32_t *out, void *ws, size_t ws_size);

/* ---- point lights ---------------------------------------------------------------------------- */

/* Prepares a point light for maps m, point map p (same size) and optionally a cube-map LUT (NULL:
 * direct SH evaluation). No workspace: the state holds all it needs (sizeof(qibl_shmap_point_t)).
 * Formats: params Q8.24; light pos, rgb, min_dist Q16.16; out's factors int16 with power-of-two
 * exponents (see qibl_shmap_point_t).
 * Bound: the factors scale_i and bias_i rounded to 2^-15 of the channel's largest (POLY: 2^-15 and
 * 2^-14), as stated at qibl_shmap_point_span.
 * Errors, in this order: those of qibl_shmap_check, QIBL_E_NULL_POINTER (p, p->points, light or out
 * NULL), QIBL_E_SHMAP_MISMATCH (P map not the maps' size; or a LUT that does not fit the maps:
 * values NULL, k below the maps' or above QIBL_SH_MAX_COUNT, face size outside
 * 1..QIBL_YLUT_MAX_FACE),
 * QIBL_E_SHMAP_LUT_SHORT (lut->size below the 12 N N k bytes its fields need), QIBL_E_SHMAP_LIGHT
 * (negative colour or min_dist, unknown falloff or filter).
 * On failure: nothing is written (*out untouched). */
QIBL_NODISCARD qibl_status_t qibl_shmap_point_prepare(const qibl_shmaps_t *m, const qibl_pmap_t *p, const qibl_ylut_t *lut,
                                       const qibl_pointlight_t *light, qibl_shmap_point_t *out);

/* Workspace bytes qibl_shmap_point_span needs for a span of n pixels with k maps
 * (n * (2k + 32) bytes, 4-byte aligned storage: per-pixel Y_i, attenuation and two int32 accumulators). */
size_t qibl_shmap_point_workspace_size(uint32_t k, uint32_t n);

/* Relights a span under a prepared point light, into out as qibl_shmap_relight_span.
 * Per pixel: L = S - P(p); d = |L| (clamped below by min_dist); Y_i(L / |L|) in Q2.14 from the LUT
 * or from qibl_sh_eval_unit; then sum_i Y_i (bias_i + scale_i c_i) C0 att(d).
 * Error against that sum in double from the same bytes: each product Y_i scale_i and Y_i bias_i
 * is rounded to 2^-15 of the channel's largest |scale| (|bias|), Y to 2^-15 (direct) plus the LUT's
 * interpolation error, 1/|L| to 2^-28 relative; measured in shmap_test.c and `qibl bench relight`.
 * QIBL_POINT_POLY: L scaled so its largest |component| is in [2^14, 2^15] (floored: 2^-14 relative),
 * 1/|L| to 2^-15 relative (seed 2^-9, one Newton step 2^-17.4, then floored to 16 bits), the unit
 * vector to 2 LSB of Q2.14, each Y_i to a few LSB of Q2.14; the factors scale_i and bias_i rounded
 * to 2^-15 and 2^-14 of the channel's largest, then every product summed exactly (int64 for
 * Y scale c, int32 for Y bias: sum |Y_i| <= k / sqrt(4 pi)) and rounded once; C0 and the attenuation
 * to 15 bits. tests/shmap_test.c measures max error / sum|T Y| att C0 against each mode's bound.
 * Formats: pt as qibl_shmap_point_prepare makes it (P map Q16.16, LUT Q2.14); out 3n int32, Q16.16
 * RGB interleaved.
 * Bound: as the paragraph above, per mode (no single LSB figure: it scales with sum|T Y| att C0).
 * Errors, in this order: QIBL_E_NULL_POINTER (pt, out, pt->maps, pt->maps->planes or ws NULL),
 * QIBL_E_SHMAP_BOUNDS (span outside the maps), QIBL_E_WORKSPACE (ws_size below
 * qibl_shmap_point_workspace_size), QIBL_E_WORKSPACE_ALIGN (ws not on a 4-byte boundary, whatever
 * the method).
 * On failure: nothing is written (out and the workspace untouched). */
QIBL_NODISCARD qibl_status_t qibl_shmap_point_span(const qibl_shmap_point_t *pt, uint32_t x0, uint32_t y, uint32_t n, int32_t *out,
                                    void *ws, size_t ws_size);

/* ---- cube-map Y LUTs ------------------------------------------------------------------------- */

/* Bytes of the YLUT values for face size N and k maps (6 N N k int16), 0 if N or k out of range. */
size_t qibl_ylut_values_size(uint32_t face_size, uint32_t k);

/* Fills values (qibl_ylut_values_size bytes, the asset.h YLUT layout) with Y_0..Y_{k-1} at every
 * texel centre, rounded to nearest from the Q2.30 basis.
 * Formats: values little-endian int16 Q2.14.
 * Bound: <= 0.5 LSB of Q2.14 plus qibl_sh_eval's 2^-25 (texel centres are exact integer directions).
 * Errors, in this order: QIBL_E_NULL_POINTER (values NULL), QIBL_E_SHMAP_K (k outside
 * 1..QIBL_SH_MAX_COUNT), QIBL_E_SHMAP_LUT_SIZE (N outside 1..QIBL_YLUT_MAX_FACE), QIBL_E_WORKSPACE
 * (size below qibl_ylut_values_size).
 * On failure: nothing is written. */
QIBL_NODISCARD qibl_status_t qibl_ylut_build(uint32_t face_size, uint32_t k, uint8_t *values, size_t size);

/* Whether view t may be read. The views of qibl_asset_ylut / qibl_asset_head_ylut always pass;
 * check a view built any other way before qibl_ylut_lookup (qibl_shmap_point_prepare checks its
 * LUT itself).
 * Formats: none (reads the view's fields only). Bound: exact.
 * Errors, in this order: QIBL_E_NULL_POINTER (t or its values NULL), QIBL_E_SHMAP_K (k outside
 * 1..QIBL_SH_MAX_COUNT), QIBL_E_SHMAP_LUT_SIZE (face size outside 1..QIBL_YLUT_MAX_FACE),
 * QIBL_E_SHMAP_LUT_SHORT (t->size below the 12 N N k bytes the fields need).
 * On failure: nothing is written (it writes nothing, ever). */
QIBL_NODISCARD qibl_status_t qibl_ylut_check(const qibl_ylut_t *t);

/* Y_0..Y_{k-1} (Q2.14, bilinear between texel centres, clamped at face edges) for a Q2.30 unit
 * direction u, from LUT t. No checks (hot path): t must pass qibl_ylut_check, k <= t->k. */
void qibl_ylut_lookup(const qibl_ylut_t *t, const qibl_q30_t u[3], uint32_t k, int32_t *y14);

#ifdef __cplusplus
}
#endif

#endif /* QIBL_SHMAP_H */
