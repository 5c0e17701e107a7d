/*
 * qibl/sh.h - real orthonormal spherical harmonics, bands 0..4 (up to 25 coefficients), integer
 * only.
 *
 * Convention (Wong et al., "Relighting compressed panoramas", Appendix), written out so that every
 * tool and test agrees:
 *   direction (x, y, z) = (sin t cos p, sin t sin p, cos t): t from +z, p from +x towards +y;
 *   Y(l,m) = N(l,m) Q(l,|m|)(cos t) cos(m p)     for m > 0
 *          = N(l,0) Q(l,0)(cos t) / sqrt(2)      for m = 0
 *          = N(l,m) Q(l,|m|)(cos t) sin(|m| p)   for m < 0
 *   N(l,m) = sqrt((2l + 1) / (2 pi) * (l - |m|)! / (l + |m|)!)
 *   Q(m,m)(x) = (1 - 2m) sqrt(1 - x^2) Q(m-1,m-1)(x), Q(0,0) = 1   (the Condon-Shortley phase:
 *   Q(m,m) = (-1)^m (2m-1)!! (1-x^2)^(m/2)), then the usual Legendre recurrence in l.
 *   Flat index i = l*l + l + m, so i = 0 is Y(0,0) = 1/(2 sqrt(pi)), i = 1..3 are
 *   Y(1,-1) = -c y, Y(1,0) = c z, Y(1,1) = -c x with c = sqrt(3 / (4 pi)).
 * The basis is orthonormal over the sphere: integral of Y_i Y_j dw = delta_ij.
 *
 * Memory: no workspace; outputs are caller arrays of bands*bands qibl_q30_t.
 */
#ifndef QIBL_SH_H
#define QIBL_SH_H

#include <stdint.h>
#include "qibl/config.h"
#include "qibl/fixed.h"
#include "qibl/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Number of coefficients for a band count (bands 1..5 -> 1, 4, 9, 16, 25). */
#define QIBL_SH_COUNT(bands) ((bands) * (bands))
#define QIBL_SH_MAX_COUNT QIBL_SH_COUNT(QIBL_SH_MAX_BANDS)

/* Evaluate Y_0 .. Y_{bands^2 - 1} at the direction of dir.
 *   dir:   three int32 in any common fixed-point scale (Q16.16 by convention); need not be unit
 *          length: any non-zero vector from 1 LSB to INT32_MIN components is accepted.
 *   bands: 1..QIBL_SH_MAX_BANDS.
 *   out:   bands^2 values in Q2.30, flat index i = l*l + l + m.
 * Cost: one normalisation (three 64/64 divisions and a 64-bit square root) + about 60 32x32->64
 * multiplies for 25 coefficients.
 * Formats: dir any common Q format (Q16.16 by convention; a direction only); out Q2.30.
 * Bound: |out_i - Y_i(dir / |dir|)| <= 2^-25 for every i and every input (bound from the analysis in
 * sh.c: 1 LSB from normalisation, a few LSB of Q3.29 rounding in the recurrences; the tests measure
 * the maximum over a 10^6-direction sweep and hard cases).
 * Errors, in this order: QIBL_E_NULL_POINTER (dir or out NULL), QIBL_E_BAD_BANDS (bands outside
 * 1..QIBL_SH_MAX_BANDS), QIBL_E_ZERO_VECTOR (dir = (0, 0, 0)).
 * On failure: nothing is written (out untouched). */
QIBL_NODISCARD qibl_status_t qibl_sh_eval(const qibl_q16_t dir[3], int bands, qibl_q30_t *out);

/* As qibl_sh_eval for a direction that is already a Q2.30 unit vector (for instance from
 * qibl_vec3_normalize_q30): skips the normalisation.
 * Formats: u Q2.30 unit vector; out Q2.30.
 * Bound: qibl_sh_eval's 2^-25 when the caller guarantees |u| = 1 within a few LSB; out scales with
 * |u|^l otherwise (u is not checked).
 * Errors, in this order: QIBL_E_NULL_POINTER (u or out NULL), QIBL_E_BAD_BANDS (bands outside
 * 1..QIBL_SH_MAX_BANDS).
 * On failure: nothing is written (out untouched). */
QIBL_NODISCARD qibl_status_t qibl_sh_eval_unit(const qibl_q30_t u[3], int bands, qibl_q30_t *out);

/* ---- rotation ------------------------------------------------------------------------------ */

/* A rotation of SH coefficients, bands 0..bands-1: one (2l+1) x (2l+1) matrix D^l per band, Q2.30,
 * row-major, band after band (1 + 9 + 25 + 49 + 81 = 165 entries for 5 bands): 4 + 4 x 165 = 664 bytes. */
#define QIBL_SH_ROT_ENTRIES 165
typedef struct qibl_sh_rotation {
    int32_t bands;
    qibl_q30_t d[QIBL_SH_ROT_ENTRIES];
} qibl_sh_rotation_t;

/* Prepares the rotation of SH coefficients by the 3 x 3 rotation r (Q2.30, r[row][col]): the
 * coefficients of f'(w) = f(r^T w), so that light arriving from direction d arrives from r d
 * afterwards (a directional light's coefficients Y(d) become Y(r d)).
 * Method: D^l[m][m'] = sum_k pinv_l[m][k] Y_lm'(r^T n_k) over 16 fixed sample directions n_k, with
 * pinv_l the least-squares inverse of the band's basis at the n_k (a const table made by
 * tools/scripts/gen-sh-rot-table.c and checked by tests/sh_test.c): exact in exact arithmetic for any
 * rotation, because a rotated band-l function stays in band l. It reuses qibl_sh_eval_unit, so it
 * cannot disagree with the basis convention.
 * r must be orthonormal within 2^-16 per entry of r r^T - I (2^14 LSB) with det r > 0.
 * Cost: 16 normalisations and SH evaluations, 165 x 16 multiply-adds (once per frame).
 * Formats: r Q2.30; rot's entries Q2.30.
 * Bound: each D entry within 2^-24 of the exact rotation matrix of r's normalised rows (bound: the
 * sum over k of |pinv| <= 6.4 times the basis error at r^T n_k, a few LSB of Q2.30 plus the
 * normalisation, plus one rounding; measured against a double reference in tests/sh_test.c).
 * Errors, in this order: QIBL_E_NULL_POINTER (rot or r NULL), QIBL_E_BAD_BANDS (bands outside
 * 1..QIBL_SH_MAX_BANDS), QIBL_E_SH_ROTATION (an entry beyond 1 + 2^-15 in magnitude, r r^T - I
 * beyond the tolerance, or det r <= 0).
 * On failure: nothing is written (rot untouched). */
QIBL_NODISCARD qibl_status_t qibl_sh_rotation_init(qibl_sh_rotation_t *rot, const qibl_q30_t r[3][3], int bands);

/* out = D in per band: rot->bands^2 coefficients (in and out may not alias).
 * out_lm = round(sum_m' D^l[m][m'] in_lm'), ties up, saturated to int32.
 * Formats: in and out any int32 fixed-point format, the same for both; D Q2.30.
 * Bound: <= 0.5 LSB + sum_m' |D error| |in_lm'| <= 0.5 LSB + 3 * 2^-24 * max |in| of the band
 * (band 0 copied exactly).
 * Errors, in this order: QIBL_E_NULL_POINTER (rot, in or out NULL), QIBL_E_BAD_BANDS (rot->bands
 * outside 1..QIBL_SH_MAX_BANDS: rot not initialised).
 * On failure: nothing is written (out untouched). */
QIBL_NODISCARD qibl_status_t qibl_sh_rotate(const qibl_sh_rotation_t *rot, const int32_t *in, int32_t *out);

#ifdef __cplusplus
}
#endif

#endif /* QIBL_SH_H */
