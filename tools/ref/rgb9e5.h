/*
 * ref/rgb9e5.h - GL_RGB9_E5 (EXT_texture_shared_exponent / OpenGL 3.0, section "Encoding of
 * special internal formats"): three unsigned 9-bit mantissas and a 5-bit exponent in one uint32
 * (GL_UNSIGNED_INT_5_9_9_9_REV: red in bits 0..8, green 9..17, blue 18..26, exponent 27..31).
 * Written from the extension's pseudo-code with frexp/ldexp: channels clamped to
 * [0, sharedexp_max = 65408] (NaN -> 0), exponent from floor(log2(max)) with the spec's
 * re-normalisation when the rounded maximum reaches 2^9, mantissas rounded half up.
 * Hosted (libm); the comparison point for `qibl bench srgbe`, not used by the core.
 */
#ifndef QTOOL_REF_RGB9E5_H
#define QTOOL_REF_RGB9E5_H

#include <stddef.h>
#include <stdint.h>

uint32_t qtool_ref_rgb9e5_encode(const float rgb[3]);
void qtool_ref_rgb9e5_decode(uint32_t v, float rgb[3]);

void qtool_ref_rgb9e5_encode_n(const float *rgb, size_t n, uint32_t *out);
void qtool_ref_rgb9e5_decode_n(const uint32_t *in, size_t n, float *rgb);

#endif
