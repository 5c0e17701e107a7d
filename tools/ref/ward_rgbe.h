/*
 * ref/ward_rgbe.h - Ward's RGBE (G. Ward, "Real Pixels", Graphics Gems II, 1991; Radiance's
 * setcolr/colr_color), the classic way: frexp on the largest channel, mantissas truncated to a
 * byte, decode (m + 1/2) * 2^(E - 136) with ldexp. Unsigned: negative channels are clamped to 0
 * (the original code would store garbage). Hosted (libm); the comparison point for `qibl bench
 * srgbe`, not used by the core.
 *
 * Byte order {R, G, B, E}; E = 0 is zero (largest channel <= 1e-32). The classic code never
 * checks the top of the range; here an exponent above the byte (values >= 2^128) saturates.
 */
#ifndef QTOOL_REF_WARD_RGBE_H
#define QTOOL_REF_WARD_RGBE_H

#include <stddef.h>
#include <stdint.h>

void qtool_ref_rgbe_encode(const float rgb[3], uint8_t code[4]);
void qtool_ref_rgbe_decode(const uint8_t code[4], float rgb[3]);

/* n pixels: rgb[3i..3i+2] <-> code[4i..4i+3] */
void qtool_ref_rgbe_encode_n(const float *rgb, size_t n, uint8_t *codes);
void qtool_ref_rgbe_decode_n(const uint8_t *codes, size_t n, float *rgb);

#endif
