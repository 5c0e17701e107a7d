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
 * (the row is scaled from its exponents alone: equal to the largest value within 2x when the largest
 * channel's mantissa is in 128..255, as Radiance's encoders write it; 7 bits lost at worst). Terms: each channel's rounding to its row scale (<= 2^-27 M_v, times
 * |Y| <= 0.85 and W pixels), the Q2.30 trig table and row factors (<= 2^-29 relative per pixel: the
 * basis of sh.h and the row weight's 32-bit sine), the 2^-62 rounding of each row sum, and in
 * finish the 32-bit constants and the output rounding (<= 2^-29 of the largest coefficient).
 * Measured: 3e-8 of max |L| on random probes; on the 11 fixture probes 1.6e-9 .. 3.6e-8, and 2.7e-7
 * on moonless_golf (a night probe: dim rows quantised against a few bright lamps).
 * tests/probe_test.c measures it against a double reference (tools/ref/probe_ref.c) on every fixture
 * probe and on hard cases; `qibl bench probe` prints RESULT probe.sh_max_rel_err.
 *
 * Memory: qibl_probe_sh_workspace_size(W, H) bytes, any alignment: the accumulators (3 x 25 x 15
 * uint32 = 4500 bytes), the trig table (32 W/4 bytes, or 32 W if W % 4 != 0), one row of channel
 * integers (12 W) and a bitmap of the rows added (H / 8). 1024 x 512: 25 KB. Stack: under 1 KB.
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
 * (8 sines per folded column from exact rational angles, within 1 LSB of Q2.30).
 * Errors: QIBL_E_NULL_POINTER, QIBL_E_BAD_BANDS, QIBL_E_PROBE_SIZE, QIBL_E_PROBE_OVERFLOW,
 * QIBL_E_PROBE_FORMAT, QIBL_E_WORKSPACE; *ps untouched on failure. */
QIBL_NODISCARD qibl_status_t qibl_probe_sh_begin(qibl_probe_sh_t *ps, uint32_t width, uint32_t height,
                                  qibl_lightprobe_format_t format, int32_t frac_bits, int bands, void *workspace,
                                  size_t workspace_size);

/* Adds row v (W pixels in the begin format, 4-byte aligned for the 32-bit formats).
 * Errors: QIBL_E_NULL_POINTER, QIBL_E_PROBE_ROW (v >= H, or row v already added),
 * QIBL_E_PROBE_FORMAT (a 32-bit format row misaligned), QIBL_E_PROBE_NOT_FINITE, QIBL_E_PROBE_NEGATIVE
 * (NaN / Inf first, found before anything is accumulated); on failure the projection is unchanged.
 * Cost: one pass over the row to find its scale and check it, one to convert it, then 1.5
 * (W % 4 == 0) or 8 multiply-adds per pixel and channel at 5 bands (0.75 or 4 at 3 bands: only the
 * orders m < bands are summed), and 3 bands^2 accumulator additions per row.
 * With QIBL_CONFIG_SIMD == AVX2 the RGBE scan and conversion and the folded sums take 8 columns per
 * instruction (vpsrlvd, vpmuldq; the same integers, so the same bits as the scalar path): 1024 x 512
 * RGBE, gcc 12 -O3, ~2.1 ns per pixel against ~5.8 scalar/SSE2 (`qibl bench probe`). */
QIBL_NODISCARD qibl_status_t qibl_probe_sh_add_row(qibl_probe_sh_t *ps, uint32_t v, const void *row);

/* The coefficients of the rows added so far, with opts applied (irradiance, window).
 * Errors: QIBL_E_NULL_POINTER (ps or out), QIBL_E_PROBE_ROW (not every row added),
 * QIBL_E_PROBE_METHOD (unknown window); *out untouched on failure. */
QIBL_NODISCARD qibl_status_t qibl_probe_sh_finish(const qibl_probe_sh_t *ps, const qibl_probe_sh_opts_t *opts,
                                   qibl_probe_coeffs_t *out);

/* begin + every row of img + finish, for a resident image (img->stride as in lightprobe.h).
 * Errors: those of the three, and QIBL_E_PROBE_FORMAT for a bad stride; *out untouched on failure. */
QIBL_NODISCARD qibl_status_t qibl_probe_sh_project(const qibl_lightprobe_image_t *img, int bands, const qibl_probe_sh_opts_t *opts,
                                    void *workspace, size_t workspace_size, qibl_probe_coeffs_t *out);

/* ---- into a light ---------------------------------------------------------------------------- */

/* l->c[ch][i] += round(c[ch][i] 2^(exp + 16 + scale_log2)) for i < min(l->k, bands^2): the
 * coefficients as Q16.16 radiance SH. QIBL_E_NULL_POINTER, QIBL_E_SHMAP_K (l not initialised),
 * QIBL_E_BAD_BANDS (c->bands outside 1..5), QIBL_E_RANGE (|scale_log2| > 512 or |c->exp| > 1024),
 * QIBL_E_PROBE_SATURATED (a sum beyond int32: lower scale_log2); l untouched on failure. */
QIBL_NODISCARD qibl_status_t qibl_shlight_add_coeffs(qibl_shlight_t *l, const qibl_probe_coeffs_t *c, int32_t scale_log2);

/* Projects img onto the bands l->k needs (qibl_probe_sh_project, opts as there) and adds it to l
 * (qibl_shlight_add_coeffs with opts->scale_log2). Errors: those two; l untouched on failure. */
QIBL_NODISCARD qibl_status_t qibl_shlight_add_probe(qibl_shlight_t *l, const qibl_lightprobe_image_t *img,
                                     const qibl_probe_sh_opts_t *opts, void *workspace, size_t workspace_size);

/* A light list (qibl_lightprobe_lights) as SH: l->c[ch][i] += sum_n rgb_n 2^(rgb_exp + scale_log2)
 * Y_i(dir_n) in Q16.16. Each light's products are exact, summed in 64 bits and rounded once per
 * coefficient: error <= 0.5 LSB + count |rgb|max 2^(rgb_exp + scale_log2) 2^-25 (the basis).
 * QIBL_E_NULL_POINTER, QIBL_E_SHMAP_K, QIBL_E_PROBE_COUNT (count above 2^16),
 * QIBL_E_PROBE_SATURATED; l untouched on failure. */
QIBL_NODISCARD qibl_status_t qibl_shlight_add_lights(qibl_shlight_t *l, const qibl_lightprobe_light_t *lights, uint32_t count,
                                      int32_t rgb_exp, int32_t scale_log2);

/* Sun plus sky in one call: the probe's SH with the regions of the `count` given lights (the
 * brightest of a qibl_lightprobe_lights list, e.g. its first one) taken out, plus those lights as
 * directional lights (qibl_shlight_add_lights). The regions' pixels are projected again and
 * subtracted from the accumulators (the same per-row quantisation, so what is removed is what the
 * full projection added, within the 2^-62 rounding of each row sum). opts as qibl_shlight_add_probe.
 * Errors: those of qibl_shlight_add_probe and qibl_shlight_add_lights, QIBL_E_PROBE_RECT (a region
 * outside the probe); l untouched on failure. */
QIBL_NODISCARD qibl_status_t qibl_shlight_add_sun_sky(qibl_shlight_t *l, const qibl_lightprobe_image_t *img,
                                       const qibl_probe_sh_opts_t *opts, const qibl_lightprobe_light_t *sun,
                                       uint32_t count, int32_t rgb_exp, void *workspace, size_t workspace_size);

/* Rotates the light's coefficients in place (per channel, qibl_sh_rotate): QIBL_E_NULL_POINTER,
 * QIBL_E_SHMAP_K, QIBL_E_BAD_BANDS (rot has fewer bands than l->k needs). */
QIBL_NODISCARD qibl_status_t qibl_shlight_rotate(qibl_shlight_t *l, const qibl_sh_rotation_t *rot);

#ifdef __cplusplus
}
#endif

#endif /* QIBL_PROBE_H */
