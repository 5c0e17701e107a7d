/*
 * io/hdr_write.h - Radiance .hdr (RGBE) writer, the counterpart of io/hdr.h's reader. Hosted.
 *
 * Writes "#?RADIANCE", "FORMAT=32-bit_rle_rgbe", a blank line, "-Y H +X W", then H scanlines top to
 * bottom: new-style RLE (02 02 W_hi W_lo, then R, G, B, E each as runs of 4..127 equal bytes and
 * literals of 1..128) for 8 <= W < 32768, flat 4-byte pixels otherwise (as Radiance does).
 * Pixel encoding (Ward's): v = max(R, G, B); v < 2^-100 -> 0 0 0 0; else with v = f 2^e,
 * f in [1/2, 1): byte c = floor(c 256 / 2^e), E = e + 128. io/hdr.h decodes byte x as x 2^(E-136),
 * so a channel comes back low by less than 2^(e-8) <= v/128 (exact for values m 2^(e-8), m integer).
 */
#ifndef QTOOL_IO_HDR_WRITE_H
#define QTOOL_IO_HDR_WRITE_H

#include <stddef.h>
#include <stdint.h>

/* Largest width and height written (the reader's RLE limit is per scanline; flat rows have none,
 * but the resolution line and the product w * h * 4 stay far from int and size_t limits). */
#define QTOOL_HDR_WRITE_MAX_DIM 65535

/* Encodes w * h RGB floats (rows top to bottom) into a malloc'ed file image (*out, *outlen).
 * A NaN, infinite, negative or too large (>= 2^127) sample is refused with its value and pixel
 * named in err; nothing is allocated then. 0, or -1. */
int qtool_hdr_encode(int w, int h, const float *rgb, uint8_t **out, size_t *outlen, char *err, size_t errlen);

/* Writes the same atomically to path (io/atomic.h). 0, or -1 with a one-line reason naming the
 * file in err (nothing written). */
int qtool_hdr_write(const char *path, int w, int h, const float *rgb, char *err, size_t errlen);

#endif
