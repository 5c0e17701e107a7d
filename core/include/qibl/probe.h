/*
 * qibl/probe.h - image-based lighting from a real probe: a lat-long HDR probe projected onto SH
 * bands 0..4 (radiance, or irradiance by the clamped cosine), row by row, integer only, no heap.
 *
 * Conventions: those of lightprobe.h (pixel (u, v) at theta = (v + 1/2) pi / H from +z, phi =
 * (u + 1/2) 2 pi / W from +x towards +y; the same four pixel formats) and of sh.h (the basis).
 * The result is the Riemann sum
 *     L_lm = sum_(u,v) P(u, v) Y_lm(w(u, v)) dw_v,   dw_v = (2 pi / W) (pi / H) sin theta_v,
 * the solid-angle weights of qibl_lightprobe_row_weight, so a directional light of colour c from d
 * (qibl_shlight_add_dir: c Y_lm(d)) and a one-pixel probe holding c / dw agree. With irradiance,
 * E_lm = A_l L_lm (Ramamoorthi & Hanrahan: A_0 = pi, A_1 = 2 pi / 3, A_2 = pi / 4, A_3 = 0,
 * A_4 = -pi / 24), so sum_lm E_lm Y_lm(n) is the irradiance at normal n. A window multiplies band l
 * by sigma_l (N = bands): Hann (1 + cos(pi l / N)) / 2, Lanczos sin(pi l / N) / (pi l / N).
 *
 * Row by row: qibl_probe_sh_begin, then qibl_probe_sh_add_row for every row in ANY order (a
 * streaming decoder never holds the probe), then qibl_probe_sh_finish (any number of times, with
 * different options). qibl_probe_sh_project does the three for a resident image.
 *
 * How it is exact (details in probe.c):
 *   - Each row is quantised on its own scale: every channel becomes x = round(P 2^(27 - T_v)) <=
 *     2^27 with T_v the row's top bit (every channel of the row is below 2^T_v).
 *   - The row's Fourier sums S_m = sum_u x T_m(phi_u) (T_m = cos or sin m phi in Q2.30) are exact
 *     integer sums (int64 chunks into 128 bits; when W % 4 == 0 the four quarter turns and the
 *     mirror phi -> pi/2 - phi are folded first: 1.5 multiplies per pixel and channel instead of 8).
 *   - Each row's term S_m times the row factor Y_l|m|(theta_v, 0) sin theta_v (32-bit mantissa) is
 *     added to a 480-bit fixed-point accumulator per coefficient (bits 2^-256 .. 2^223, wide enough
 *     for every row term of every format at every size, proved in probe.c): integer addition is
 *     associative, so the result does not depend on the order of the rows.
 * Error bound, per coefficient, against the exact Riemann sum above:
 *     |L_lm - exact| <= 2^-26 B' + 2^-29 max |L|,   B' = sum_v W M_v dw_v,
 * M_v the largest channel value of row v (B' <= 4 pi max P; for rows of even brightness it is about
 * the probe's total sum P dw); for RGBE, M_v = 2^(emax_v - 128) from the row's largest lit exponent
 * (the row is scaled from its exponents alone: equal to the largest value within a factor of two when the largest
 * channel's mantissa is in 128..255, as Radiance's encoders write it; 7 bits lost at worst). Terms: each channel's rounding to its row scale (<= 2^-27 M_v, times
 * |Y| <= 0.85 and W pixels), the Q2.30 trig table and row factors (<= 2^-29 relative per pixel: the
 * basis of sh.h and the row weight's 32-bit sine), the 2^-62 rounding of each row sum, and in
 * finish the 32-bit constants and the output rounding (<= 2^-29 of the largest coefficient).
 * Measured errors are far below the bound, largest on night probes (dim rows quantised against a
 * few bright lamps).
 * tests/probe_test.c measures it against a double reference (tools/ref/probe_ref.c) on every fixture
 * probe and on hard cases; `qibl bench probe` prints RESULT probe.sh_max_rel_err.
 *
 * Memory: qibl_probe_sh_workspace_size(W, H) bytes, any alignment: the accumulators (3 x 25 x 15
 * uint32 = 4500 bytes), the trig table (32 W/4 bytes, or 32 W if W % 4 != 0), one row of channel
 * integers (12 W) and a bitmap of the rows added (H / 8). Stack: under 1 KiB.
 */
#ifndef QIBL_PROBE_H
#define QIBL_PROBE_H

#include <stddef.h>
#include <stdint.h>
#include "qibl/config.h"
#include "qibl/fixed.h"
#include "qibl/lightprobe.h"
#include "qibl/sh.h"
#include "qibl/shmap.h"
#include "qibl/status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define QIBL_PROBE_ACC_LIMBS 15u

typedef enum qibl_probe_window {
    QIBL_PROBE_WINDOW_NONE = 0, /* default */
    QIBL_PROBE_WINDOW_HANN,
    QIBL_PROBE_WINDOW_LANCZOS,
    QIBL_PROBE_WINDOW_COUNT
} qibl_probe_window_t;

/* Options of qibl_probe_sh_finish. Zero-initialisable; NULL means all defaults. */
typedef struct qibl_probe_sh_opts {
    int32_t irradiance;          /* non-zero: E_lm = A_l L_lm (clamped cosine) */
    qibl_probe_window_t window;  /* NONE (0), HANN or LANCZOS */
    int32_t scale_log2;          /* qibl_shlight_add_probe / _add_coeffs: coefficients times 2^scale_log2 */
} qibl_probe_sh_opts_t;

/* SH coefficients: value = c[ch][i] * 2^exp, i = l*l + l + m < bands^2; the largest |c| is in
 * [2^30, 2^31) unless all are 0 (then exp = 0). */
typedef struct qibl_probe_coeffs {
    int32_t bands;
    int32_t exp;
    int32_t c[3][QIBL_SH_MAX_COUNT];
} qibl_probe_coeffs_t;

/* A projection in progress (qibl_probe_sh_begin). Fields are private; the state lives in the
 * caller's workspace. */
typedef struct qibl_probe_sh {
    uint32_t width, height, rows;
    qibl_lightprobe_format_t format;
    int32_t frac_bits;
    int32_t bands;
    uint32_t *acc;      /* [3][25][15] */
    int32_t *trig;      /* [W/4 or W][8]: cos, sin of m phi_u, m = 1..4 */
    uint32_t *x;        /* [3][W] one row of channel integers */
    uint8_t *seen;      /* [ceil(H / 8)] rows added */
} qibl_probe_sh_t;

/* Workspace bytes for a W x H probe; 0 outside the limits of lightprobe.h (W, H in
 * 1..QIBL_LIGHTPROBE_MAX_DIM, W H <= QIBL_LIGHTPROBE_MAX_PIXELS). */
size_t qibl_probe_sh_workspace_size(uint32_t width, uint32_t height);

/* Starts a projection onto bands 1..QIBL_SH_MAX_BANDS of a width x height probe in format
 * (frac_bits for LINEAR_I32, -128..128). Clears the accumulators and fills the trig table
 * (8 sines per folded column from exact rational angles).
 * Formats: the probe's pixel format (lightprobe.h); trig table Q2.30.
 * Bound: trig entries within 1 LSB of Q2.30; the projection's bound is the one at the top.
 * Errors, in this order: QIBL_E_NULL_POINTER (ps or workspace NULL), QIBL_E_BAD_BANDS (bands
 * outside 1..QIBL_SH_MAX_BANDS), QIBL_E_PROBE_SIZE (W or H zero or above QIBL_LIGHTPROBE_MAX_DIM),
 * QIBL_E_PROBE_OVERFLOW (W H above QIBL_LIGHTPROBE_MAX_PIXELS), QIBL_E_PROBE_FORMAT (unknown format
 * or frac_bits outside -128..128), QIBL_E_PROBE_OVERFLOW (workspace size beyond size_t),
 * QIBL_E_WORKSPACE (workspace_size below qibl_probe_sh_workspace_size).
 * On failure: nothing is written (*ps and the workspace untouched). */
QIBL_NODISCARD qibl_status_t qibl_probe_sh_begin(qibl_probe_sh_t *ps, uint32_t width, uint32_t height,
                                  qibl_lightprobe_format_t format, int32_t frac_bits, int bands, void *workspace,
                                  size_t workspace_size);

/* Adds row v (W pixels in the begin format, 4-byte aligned for the 32-bit formats).
 * Formats: row in the begin format (RGBE, sRGBE bytes, int32 / 2^frac_bits, binary32 bit patterns);
 * accumulators exact 480-bit fixed point.
 * Bound: the row's share of the bound at the top (its rounding to the row scale, 2^-27 M_v per
 * channel; the accumulation itself is exact).
 * Errors, in this order: QIBL_E_NULL_POINTER (ps, row or ps->acc NULL), QIBL_E_PROBE_ROW (v >= H,
 * or row v already added), QIBL_E_PROBE_FORMAT (a 32-bit format row misaligned),
 * QIBL_E_PROBE_NOT_FINITE, QIBL_E_PROBE_NEGATIVE (one scan of the row: NaN / Inf win over a
 * negative value).
 * On failure: the projection is unchanged (nothing is accumulated, the row is not marked).
 * Cost: one pass over the row to find its scale and check it, one to convert it, then 1.5
 * (W % 4 == 0) or 8 multiply-adds per pixel and channel at 5 bands (0.75 or 4 at 3 bands: only the
 * orders m < bands are summed), and 3 bands^2 accumulator additions per row.
 * With QIBL_CONFIG_SIMD == AVX2 the RGBE scan and conversion and the folded sums take 8 columns per
 * instruction (vpsrlvd, vpmuldq; the same integers, so the same bits as the scalar path), faster
 * than scalar/SSE2 (`qibl bench probe` measures both). */
QIBL_NODISCARD qibl_status_t qibl_probe_sh_add_row(qibl_probe_sh_t *ps, uint32_t v, const void *row);

/* The coefficients of the rows added so far, with opts applied (irradiance, window; scale_log2 is
 * not used here).
 * Formats: out c[ch][i] int32 times 2^exp, largest |c| in [2^30, 2^31).
 * Bound: the bound at the top, |L_lm - exact| <= 2^-26 B' + 2^-29 max |L|.
 * Errors, in this order: QIBL_E_NULL_POINTER (ps, out or ps->acc NULL), QIBL_E_PROBE_METHOD
 * (unknown window), QIBL_E_PROBE_ROW (not every row added).
 * On failure: nothing is written (*out untouched). */
QIBL_NODISCARD qibl_status_t qibl_probe_sh_finish(const qibl_probe_sh_t *ps, const qibl_probe_sh_opts_t *opts,
                                   qibl_probe_coeffs_t *out);

/* begin + every row of img + finish, for a resident image (img->stride as in lightprobe.h).
 * Formats: img as lightprobe.h; out as qibl_probe_sh_finish.
 * Bound: as qibl_probe_sh_finish (the bound at the top).
 * Errors, in this order: QIBL_E_NULL_POINTER (out, img or img->pixels NULL), those of
 * qibl_probe_sh_begin, QIBL_E_PROBE_FORMAT (stride shorter than a row), QIBL_E_PROBE_OVERFLOW (the
 * image's byte span beyond size_t), QIBL_E_PROBE_FORMAT (12-byte pixels or their stride not 4-byte
 * aligned), those of qibl_probe_sh_add_row row by row from the top, those of qibl_probe_sh_finish
 * (an unknown window is reported only after every row is projected).
 * On failure: *out untouched; the workspace may have been written. */
QIBL_NODISCARD qibl_status_t qibl_probe_sh_project(const qibl_lightprobe_image_t *img, int bands, const qibl_probe_sh_opts_t *opts,
                                    void *workspace, size_t workspace_size, qibl_probe_coeffs_t *out);

/* ---- into a light ---------------------------------------------------------------------------- */

/* l->c[ch][i] += round(c[ch][i] 2^(exp + 16 + scale_log2)) for i < min(l->k, bands^2): the
 * coefficients as Q16.16 radiance SH.
 * Formats: c int32 times 2^exp; l's coefficients Q16.16.
 * Bound: each term rounded half up (<= 0.5 LSB of Q16.16; exact when exp + 16 + scale_log2 >= 0),
 * the sum exact.
 * Errors, in this order: QIBL_E_NULL_POINTER (l or c NULL), QIBL_E_SHMAP_K (l->k outside
 * 1..QIBL_SH_MAX_COUNT: l not initialised), QIBL_E_BAD_BANDS (c->bands outside
 * 1..QIBL_SH_MAX_BANDS), QIBL_E_RANGE (|scale_log2| > 512 or |c->exp| > 1024),
 * QIBL_E_PROBE_SATURATED (a sum beyond int32: lower scale_log2).
 * On failure: nothing is written (*l untouched). */
QIBL_NODISCARD qibl_status_t qibl_shlight_add_coeffs(qibl_shlight_t *l, const qibl_probe_coeffs_t *c, int32_t scale_log2);

/* Projects img onto the bands l->k needs (qibl_probe_sh_project, opts as there) and adds it to l
 * (qibl_shlight_add_coeffs with opts->scale_log2).
 * Formats: img as lightprobe.h; l's coefficients Q16.16.
 * Bound: the projection's bound (top) plus qibl_shlight_add_coeffs's 0.5 LSB.
 * Errors, in this order: QIBL_E_NULL_POINTER (l NULL), QIBL_E_SHMAP_K (l not initialised), those of
 * qibl_probe_sh_project, those of qibl_shlight_add_coeffs.
 * On failure: *l untouched; the workspace may have been written. */
QIBL_NODISCARD qibl_status_t qibl_shlight_add_probe(qibl_shlight_t *l, const qibl_lightprobe_image_t *img,
                                     const qibl_probe_sh_opts_t *opts, void *workspace, size_t workspace_size);

/* A light list (qibl_lightprobe_lights) as SH: l->c[ch][i] += sum_n rgb_n 2^(rgb_exp + scale_log2)
 * Y_i(dir_n) in Q16.16. Each light's product rgb Y is rounded to 2^-16 of its own unit (2^s LSB of
 * Q16.16, s = rgb_exp + scale_log2 + 2), summed in 64 bits and rounded once per coefficient. A light
 * with a zero direction adds nothing.
 * Formats: lights' dir Q2.30 and rgb int32 times 2^rgb_exp; l's coefficients Q16.16.
 * Bound: <= 0.5 LSB + count 2^(s - 1) LSB (the per-light rounding) + count |rgb|max
 * 2^(rgb_exp + scale_log2) 2^-25 (the basis).
 * Errors, in this order: QIBL_E_NULL_POINTER (l NULL, or lights NULL with count != 0),
 * QIBL_E_SHMAP_K (l not initialised), QIBL_E_PROBE_COUNT (count above 2^16),
 * QIBL_E_PROBE_SATURATED (a sum beyond int32).
 * On failure: nothing is written (*l untouched). */
QIBL_NODISCARD qibl_status_t qibl_shlight_add_lights(qibl_shlight_t *l, const qibl_lightprobe_light_t *lights, uint32_t count,
                                      int32_t rgb_exp, int32_t scale_log2);

/* Sun plus sky in one call: the probe's SH with the regions of the `count` given lights (the
 * brightest of a qibl_lightprobe_lights list, e.g. its first one) taken out, plus those lights as
 * directional lights (qibl_shlight_add_lights). The regions' pixels are projected again and
 * subtracted from the accumulators (the same per-row quantisation, so what is removed is what the
 * full projection added, within the 2^-62 rounding of each row sum). opts as qibl_shlight_add_probe.
 * The regions of one list must be disjoint (qibl_lightprobe_lights' are); that is not checked.
 * Formats: img as lightprobe.h; sun as qibl_lightprobe_lights writes it (dir Q2.30, rgb int32 times
 * 2^rgb_exp); l's coefficients Q16.16.
 * Bound: the sums of the bounds of qibl_shlight_add_probe and qibl_shlight_add_lights.
 * Errors, in this order: QIBL_E_NULL_POINTER (l NULL, or sun NULL with count != 0), QIBL_E_SHMAP_K
 * (l not initialised), those of the projection as in qibl_probe_sh_project up to the rows,
 * QIBL_E_PROBE_RECT (a region empty or outside the probe), QIBL_E_PROBE_METHOD (unknown window),
 * those of qibl_shlight_add_coeffs, then those of qibl_shlight_add_lights.
 * On failure: *l untouched (both additions are made on a copy); the workspace may have been
 * written. */
QIBL_NODISCARD qibl_status_t qibl_shlight_add_sun_sky(qibl_shlight_t *l, const qibl_lightprobe_image_t *img,
                                       const qibl_probe_sh_opts_t *opts, const qibl_lightprobe_light_t *sun,
                                       uint32_t count, int32_t rgb_exp, void *workspace, size_t workspace_size);

/* Rotates the light's coefficients in place (per channel, qibl_sh_rotate).
 * Formats: l's coefficients Q16.16; rot Q2.30.
 * Bound: qibl_sh_rotate's, <= 0.5 LSB + 3 * 2^-24 * max |c| of the band.
 * Errors, in this order: QIBL_E_NULL_POINTER (l or rot NULL), QIBL_E_SHMAP_K (l not initialised),
 * QIBL_E_BAD_BANDS (rot has fewer bands than l->k needs, or more than QIBL_SH_MAX_BANDS: rot not
 * initialised).
 * On failure: nothing is written (*l untouched). */
QIBL_NODISCARD qibl_status_t qibl_shlight_rotate(qibl_shlight_t *l, const qibl_sh_rotation_t *rot);

#ifdef __cplusplus
}
#endif

#endif /* QIBL_PROBE_H */
