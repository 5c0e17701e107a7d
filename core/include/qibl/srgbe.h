/*
 * qibl/srgbe.h - sRGBE: a signed RGB triple in 4 bytes with one shared exponent (Granier et al.,
 * "Interactive visualization of complex real-world light sources", section 4.2 and appendix A),
 * integer only. Used for signed HDR data in assets, the 8-bit accumulation buffers of the GLES2
 * backend, and light colours.
 *
 * Format - the paper's, bit for bit. A code is 4 bytes {R, G, B, E} in that order in memory (an
 * RGBA8 texel). With e = E - 126 (E = 0..255, so e = -126..129) each channel X in {R, G, B} means
 *
 *     c = (X / 255 - 1/2) * 2^e = (2X - 255) * 2^e / 510,
 *
 * which is the paper's decode ([R,G,B] - 0.5) * exp2(255 * A - 126) with the texel values
 * [R,G,B] = X / 255 and A = E / 255. A channel is an odd multiple of 2^e / 510 (half the step
 * 2^e / 255 between codes): 2X - 255 takes the odd values -255, -253, ..., 253, 255.
 *
 * Encoding follows the paper's rule:
 *     e = floor(log2(max(|r|, |g|, |b|))) + 2,    E = e + 126,
 *     X = round(255 * (c * 2^-e + 1/2))           (nearest code; see ties below),
 * so the largest channel has |c| * 2^-e in [1/4, 1/2) and X in [191, 255] (positive) or [0, 64]
 * (negative); X = 255 or 0 is reached when |c| rounds up to 2^(e-1).
 *
 * Rounding and ties. 255 * c * 2^-e + 127.5 is halfway between two codes only when c = 0: for any
 * other binary32 or fixed-point input c * 2^-e is a dyadic rational and 255 is odd. So the tie rule
 * is about zero only: +0 gives X = 128 (+2^e/510), -0 gives X = 127 (-2^e/510). Hence encoding
 * is sign-symmetric: negating every input channel maps each X to 255 - X and keeps E.
 *
 * No exact zero. A zero channel inside a non-zero pixel has no code (127.5 is not a code): the
 * encoder writes 128 or 127 by the sign bit, which decodes to +-2^e/510, an error of exactly the
 * bound below. A channel smaller than half a step likewise becomes +-2^e/510. Data that needs
 * exact zeros (masks, sparse sums) must threshold |c| <= 2^e/510 itself after decoding.
 *
 * Edge cases of the encoder (every input has a defined result):
 *   - zero pixel (all channels +-0): the zero code {128 or 127 by sign, ..., E = 0}; +0 everywhere
 *     gives the zero code 80 80 80 00 (hex, memory order; QIBL_SRGBE_ZERO_X, _X, _X, QIBL_SRGBE_ZERO_E).
 *     Returns QIBL_OK.
 *   - below range, max|c| < 2^-128 (e < -126): flushed to the zero code, signs kept. For binary32
 *     input exactly the subnormals with fraction field < 2^21 (and +-0); subnormals from 2^-128 up
 *     are in range and encoded normally (E = 0 or 1). Returns QIBL_OK.
 *   - above range, max|c| >= 2^128 (e > 129; reachable only from int32 input, with frac_bits <=
 *     -97): E = 255 and each channel is the nearest code at e = 129 clamped to X in [0, 255], so
 *     the out-of-range channels get the largest codes X = 255 / 0 (+-2^128). Returns
 *     QIBL_E_SRGBE_OVERFLOW. Every finite binary32 is in range: the largest, (2 - 2^-23) * 2^127,
 *     has e = 129 and encodes as X = 255 (2^128, within half a step).
 *   - +-Inf in a channel (no NaN): E = 255, infinite channels X = 255 / 0, finite ones the nearest
 *     code at e = 129. Returns QIBL_E_SRGBE_INF.
 *   - NaN in any channel (any payload, either sign; takes precedence over Inf): the code written
 *     is the zero code 80 80 80 00, whatever the other channels. Returns QIBL_E_SRGBE_NAN.
 *
 * Error bound (tested exhaustively, see tests/srgbe_test.c and `make check-exhaustive`): for
 * every finite channel c of an in-range pixel, with e the exponent chosen for the pixel,
 *     |c - decode(encode(c))| <= 2^e / 510    (half a step; the exact decoded value),
 * with equality only for zero channels. For the largest channel this is a relative error below
 * 4/510 of its value. The binary32 decoder adds its own correct rounding (<= 1/2 ulp of the result,
 * at most 2^(e-25)); the fixed-point decoder adds <= 1/2 LSB of its output format.
 *
 * GLES: a shader that samples the RGBA8 texel t and computes (t.rgb - 0.5) * exp2(t.a * 255.0 -
 * 126.0) (better: exp2(floor(t.a * 255.0 + 0.5) - 126.0), immune to an inexact t.a * 255) gets the
 * value qibl_srgbe_decode_f32 returns to within 2^(e-23) (the GPU's rounding of X / 255 and of the
 * subtraction, plus the decoder's half ulp), provided 2^e is representable in the shader's float
 * precision (fp32: E <= 253; mediump: far fewer). tests/srgbe_test.c checks this in binary32.
 *
 * Memory: no workspace; one 1 KiB const table (binary32 decode). Codes are byte arrays with no
 * alignment requirement. qibl_srgbe_encode_f32_n uses a few hundred bytes of stack where
 * QIBL_CONFIG_SRGBE_BLOCKS is 1 and QIBL_CONFIG_SIMD scalar (config.h), a few words elsewhere.
 * All functions are reentrant; inputs may be any values (no precondition beyond valid pointers).
 */
#ifndef QIBL_SRGBE_H
#define QIBL_SRGBE_H

#include <stddef.h>
#include <stdint.h>
#include "qibl/config.h"
#include "qibl/fixed.h"
#include "qibl/status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define QIBL_SRGBE_BYTES 4      /* bytes per code */
#define QIBL_SRGBE_E_BIAS 126   /* E = e + 126 */
#define QIBL_SRGBE_E_MIN (-126) /* smallest exponent, E = 0 */
#define QIBL_SRGBE_E_MAX 129    /* largest exponent, E = 255 */
/* The zero code (all channels +0, flushed input, NaN): bytes R, G, B, E. */
#define QIBL_SRGBE_ZERO_X 128u
#define QIBL_SRGBE_ZERO_E 0u

/* ---- encode --------------------------------------------------------------------------------- */

/* Encode one pixel given as IEEE-754 binary32 bit patterns (r, g, b), read as integers: no floating
 * point is used. Writes the 4 bytes of code. Rounding, ties and edge cases as above. rgb and code
 * may overlap.
 * Formats: rgb binary32 bit patterns (uint32); code sRGBE bytes R, G, B, E.
 * Bound: error <= 2^e/510 per channel for every finite input (every finite binary32 is in range).
 * Errors, in this order: QIBL_E_NULL_POINTER (rgb or code NULL), QIBL_E_SRGBE_NAN (a NaN channel),
 * QIBL_E_SRGBE_INF (an infinite channel, no NaN).
 * On failure: NULL_POINTER writes nothing; NAN writes the zero code, INF the code stated above. */
QIBL_NODISCARD qibl_status_t qibl_srgbe_encode_f32(const uint32_t rgb[3], uint8_t code[4]);

/* Encode one pixel of int32 values rgb[i] * 2^-frac_bits. Any frac_bits is accepted (negative
 * means the integers count 2^-frac_bits units); the value is exact, so the code is the nearest one
 * as for binary32. A pixel below 2^-128 is flushed to the zero code with QIBL_OK.
 * rgb and code may overlap.
 * Formats: rgb int32 with frac_bits fraction bits (any int); code sRGBE bytes R, G, B, E.
 * Bound: error <= 2^e/510 per channel when in range.
 * Errors, in this order: QIBL_E_NULL_POINTER (rgb or code NULL), QIBL_E_SRGBE_OVERFLOW (largest
 * |channel| at or above 2^128).
 * On failure: NULL_POINTER writes nothing; OVERFLOW writes the saturated code stated above. */
QIBL_NODISCARD qibl_status_t qibl_srgbe_encode_s32(const int32_t rgb[3], int frac_bits, uint8_t code[4]);

/* qibl_srgbe_encode_s32 with frac_bits = 16: a Q16.16 colour. Always in range: e is in -14..17.
 * Formats: rgb Q16.16; code sRGBE bytes. Bound: error <= 2^e/510 per channel.
 * Errors: QIBL_E_NULL_POINTER (rgb or code NULL); never QIBL_E_SRGBE_OVERFLOW.
 * On failure: nothing is written. */
QIBL_NODISCARD qibl_status_t qibl_srgbe_encode_q16(const qibl_q16_t rgb[3], uint8_t code[4]);

/* ---- decode --------------------------------------------------------------------------------- */

/* Decode one code to binary32 bit patterns: each channel is the correctly rounded binary32 value of
 * (2X - 255) * 2^(E - 126) / 510 (round to nearest; a tie cannot occur: the quotient has a
 * non-terminating binary expansion unless X is 0 or 255, where it is exactly +-2^(E-127)).
 * Small E gives correctly rounded subnormals (the zero code decodes to 2^-127/255, bits 00004040).
 * The only values beyond binary32 are +-2^128 (E = 255 with X = 255 or 0): such a channel is
 * written as +-FLT_MAX (7F7FFFFF / FF7FFFFF) and QIBL_E_SRGBE_DECODE_SAT returned, the other
 * channels decoded normally. Never gives Inf, NaN or -0. code and rgb may overlap.
 * Formats: code sRGBE bytes; rgb binary32 bit patterns (uint32).
 * Bound: correctly rounded (<= 1/2 ulp of each channel), except +-2^128 written as +-FLT_MAX.
 * Errors, in this order: QIBL_E_NULL_POINTER (code or rgb NULL), QIBL_E_SRGBE_DECODE_SAT (E = 255
 * with a channel X = 255 or 0).
 * On failure: NULL_POINTER writes nothing; DECODE_SAT writes all three channels as stated. */
QIBL_NODISCARD qibl_status_t qibl_srgbe_decode_f32(const uint8_t code[4], uint32_t rgb[3]);

/* Decode one code to int32 with frac_bits fraction bits (any int): each channel is
 * round((2X - 255) * 2^(E - 126 + frac_bits) / 510), ties toward +infinity (fixed.h's rule; a tie
 * happens only for X in {0, 255} at E - 126 + frac_bits = 0, i.e. +-1/2 LSB), error <= 1/2 LSB.
 * Channels beyond [INT32_MIN, INT32_MAX] are saturated to the nearer end and
 * QIBL_E_SRGBE_DECODE_SAT returned, the other channels decoded normally. code and rgb may overlap.
 * Formats: code sRGBE bytes; rgb int32 with frac_bits fraction bits (any int).
 * Bound: error <= 1/2 LSB of the output format (saturated channels excepted).
 * Errors, in this order: QIBL_E_NULL_POINTER (code or rgb NULL), QIBL_E_SRGBE_DECODE_SAT (a channel
 * beyond the int32 range).
 * On failure: NULL_POINTER writes nothing; DECODE_SAT writes all three channels as stated. */
QIBL_NODISCARD qibl_status_t qibl_srgbe_decode_s32(const uint8_t code[4], int frac_bits, int32_t rgb[3]);

/* qibl_srgbe_decode_s32 with frac_bits = 16: Q16.16. Saturation (to +-32768) needs E >= 142.
 * Formats: code sRGBE bytes; rgb Q16.16. Bound: error <= 1/2 LSB (saturated channels excepted).
 * Errors, in this order: QIBL_E_NULL_POINTER (code or rgb NULL), QIBL_E_SRGBE_DECODE_SAT.
 * On failure: NULL_POINTER writes nothing; DECODE_SAT writes all three channels, saturated ones at
 * the int32 limits. */
QIBL_NODISCARD qibl_status_t qibl_srgbe_decode_q16(const uint8_t code[4], qibl_q16_t rgb[3]);

/* ---- bulk: n pixels --------------------------------------------------------------------------
 * Pixel i reads rgb[3i .. 3i+2] and writes codes[4i .. 4i+3] (or the reverse for decode), exactly
 * as the one-pixel function does: bulk and one-pixel calls give identical bytes, and every pixel is
 * written whatever the status. codes may have any alignment. The two arrays must not overlap.
 * Returns QIBL_E_NULL_POINTER (nothing written) if a pointer is NULL, even for n = 0; otherwise
 * the most severe per-pixel status over the array, independent of pixel order:
 * QIBL_E_SRGBE_NAN > QIBL_E_SRGBE_INF > QIBL_E_SRGBE_OVERFLOW > QIBL_OK for encoders,
 * QIBL_E_SRGBE_DECODE_SAT > QIBL_OK for decoders.
 * Formats: as the one-pixel function of the same name (binary32 bit patterns, int32 with
 * frac_bits, Q16.16; codes sRGBE bytes).
 * Bound: as the one-pixel function, byte for byte (every SIMD and block path included).
 * Errors, in this order: QIBL_E_NULL_POINTER (rgb or codes NULL, even for n = 0), then the most
 * severe per-pixel status as above (encode_f32_n: NAN, INF; encode_s32_n: OVERFLOW; encode_q16_n:
 * none; decoders: DECODE_SAT).
 * On failure: NULL_POINTER writes nothing; a per-pixel status still writes every pixel, each as the
 * one-pixel function writes it. */
QIBL_NODISCARD qibl_status_t qibl_srgbe_encode_f32_n(const uint32_t *QIBL_RESTRICT rgb, size_t n,
                                      uint8_t *QIBL_RESTRICT codes);
QIBL_NODISCARD qibl_status_t qibl_srgbe_encode_s32_n(const int32_t *QIBL_RESTRICT rgb, size_t n, int frac_bits,
                                      uint8_t *QIBL_RESTRICT codes);
QIBL_NODISCARD qibl_status_t qibl_srgbe_encode_q16_n(const qibl_q16_t *QIBL_RESTRICT rgb, size_t n,
                                      uint8_t *QIBL_RESTRICT codes);
QIBL_NODISCARD qibl_status_t qibl_srgbe_decode_f32_n(const uint8_t *QIBL_RESTRICT codes, size_t n,
                                      uint32_t *QIBL_RESTRICT rgb);
QIBL_NODISCARD qibl_status_t qibl_srgbe_decode_s32_n(const uint8_t *QIBL_RESTRICT codes, size_t n, int frac_bits,
                                      int32_t *QIBL_RESTRICT rgb);
QIBL_NODISCARD qibl_status_t qibl_srgbe_decode_q16_n(const uint8_t *QIBL_RESTRICT codes, size_t n,
                                      qibl_q16_t *QIBL_RESTRICT rgb);

#ifdef __cplusplus
}
#endif

#endif /* QIBL_SRGBE_H */
