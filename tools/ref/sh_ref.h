/*
 * ref/sh_ref.h - double-precision SH basis written straight from Wong et al.'s appendix.
 *
 * Deliberately not from the core's polynomial recurrences: it goes through (theta, phi), the
 * appendix's recursive Q(l,m) and factorial N(l,m), so that a shared mistake is unlikely. Hosted
 * (libm); used by tests and benchmarks as the ground truth for core/src/sh.c.
 */
#ifndef QTOOL_REF_SH_REF_H
#define QTOOL_REF_SH_REF_H

/* Y_i, i = l*l + l + m, for l < bands (bands 1..8), at direction (x, y, z) (any non-zero length).
 * Returns 0, or -1 for a zero vector or bad bands. */
int qtool_ref_sh_eval(double x, double y, double z, int bands, double *out);

/* The appendix's Q(l,m)(x) for 0 <= m <= l, by its recursive definition. */
double qtool_ref_sh_q(int l, int m, double x);

#endif
