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
 * Error: |out_i - Y_i(dir / |dir|)| <= 2^-25 for every i and every input (bound from the analysis in
 * sh.c: 1 LSB from normalisation, a few LSB of Q3.29 rounding in the recurrences; the tests measure
 * the maximum over a 10^6-direction sweep and hard cases).
 * Errors: QIBL_E_NULL_POINTER, QIBL_E_BAD_BANDS, QIBL_E_ZERO_VECTOR; out untouched on failure.
 * Cost: one normalisation (three 64/64 divisions and a 64-bit square root) + about 60 32x32->64
 * multiplies for 25 coefficients. */
qibl_status_t qibl_sh_eval(const qibl_q16_t dir[3], int bands, qibl_q30_t *out);

/* As qibl_sh_eval for a direction that is already a Q2.30 unit vector (for instance from
 * qibl_vec3_normalize_q30): skips the normalisation. The caller guarantees |u| = 1 within a few
 * LSB; the error bound above then holds, and out scales with |u|^l otherwise.
 * Errors: QIBL_E_NULL_POINTER, QIBL_E_BAD_BANDS; out untouched on failure. */
qibl_status_t qibl_sh_eval_unit(const qibl_q30_t u[3], int bands, qibl_q30_t *out);

#ifdef __cplusplus
}
#endif

#endif /* QIBL_SH_H */
