/*
 * ref/probe_ref.h - double-precision references for SH projection of lat-long probes and for SH
 * rotation (hosted, libm). Written independently of core/src/probe.c and sh.c's rotation: the
 * projection is the plain Riemann sum over pixels with the basis of ref/sh_ref.c, the rotation is
 * the integral of Y_lm(w) Y_lm'(r^T w) by exact Gauss-Legendre x uniform-phi quadrature.
 */
#ifndef QTOOL_REF_PROBE_REF_H
#define QTOOL_REF_PROBE_REF_H

/* L[c][i] = sum_(u,v) rgb[3 (v w + u) + c] Y_i(w(u, v)) (2 pi / w) (pi / h) sin theta_v, i < bands^2,
 * lightprobe.h's pixel directions. */
void qtool_ref_probe_sh(int w, int h, const double *rgb, int bands, double out[3][25]);

/* Per-band factors of qibl_probe_sh_finish: A_l (irradiance) times the window sigma_l (0 none,
 * 1 Hann, 2 Lanczos), l < bands. */
void qtool_ref_probe_band_factors(int bands, int irradiance, int window, double f[5]);

/* D^l blocks (the layout of qibl_sh_rotation_t.d) of the rotation r (f'(w) = f(r^T w)). */
void qtool_ref_sh_rotation(const double r[3][3], int bands, double d[165]);

/* out = D in for one coefficient vector of bands^2 entries. */
void qtool_ref_sh_rotate(const double d[165], int bands, const double *in, double *out);

#endif
