/*
 * ref/srgbe_ref.h - double-precision sRGBE written straight from Granier et al. (section 4.2 and
 * appendix A), as the ground truth for core/src/srgbe.c.
 *
 * Deliberately not the core's method: it takes the exponent from frexp of the largest |channel| and
 * picks each channel's code as the nearest odd multiple of 2^e/510 by comparing two candidates in
 * double, where the core shifts binary32 fields and integers. Exactness: every input the tests use
 * (a binary32, or an int32 times a power of two) has at most 32 significant bits, so c * 2^-e * 510
 * is exact in double and the candidate distances decide correctly (tiny |y| ties only where the
 * sign rule gives the true nearest anyway). Hosted (libm).
 */
#ifndef QTOOL_REF_SRGBE_REF_H
#define QTOOL_REF_SRGBE_REF_H

#include <stdint.h>

/* what qtool_ref_srgbe_encode reports (mirrors the core's statuses) */
enum { QTOOL_REF_SRGBE_OK = 0, QTOOL_REF_SRGBE_NAN, QTOOL_REF_SRGBE_INF, QTOOL_REF_SRGBE_OVERFLOW };

/* The paper's encoder for the exact values c[0..2] (sign of -0.0 respected), with qibl's edge
 * rules (srgbe.h): zero/below 2^-128 -> zero code with signs, Inf -> e = 129 and +-255, finite
 * above range -> e = 129 clamped, NaN -> 80 80 80 00. Returns one of the enum values above. */
int qtool_ref_srgbe_encode(const double c[3], uint8_t code[4]);

/* The paper's decode of one channel byte x under exponent byte E: (x/255 - 1/2) * 2^(E-126), as a
 * double: (2x - 255)/510 rounded once, times an exact power of two (relative error <= 2^-53). */
double qtool_ref_srgbe_channel(unsigned x, unsigned E);

/* The channel as binary32 bits: the double above converted to float (correct rounding: the exact
 * value is never a binary32 tie, and the double is close enough that converting it cannot cross
 * one), with +-2^128 saturated to +-FLT_MAX (*sat set to 1; it is left alone otherwise). */
uint32_t qtool_ref_srgbe_channel_f32(unsigned x, unsigned E, int *sat);

/* The channel in int32 with frac_bits fraction bits: floor(v * 2^frac_bits + 1/2) saturated
 * (*sat set to 1 when saturated). frac_bits in -400..400. */
int32_t qtool_ref_srgbe_channel_s32(unsigned x, unsigned E, int frac_bits, int *sat);

/* |c * 2^-e * 510 - (2x - 255)| for the code byte x at exponent byte E: the channel's error in units
 * of the bound 2^e/510 (<= 1 is within the bound). Exact for the inputs described above. */
double qtool_ref_srgbe_err_in_bounds(double c, unsigned x, unsigned E);

#endif
