/*
 * io/hdr.h - minimal Radiance .hdr (RGBE) reader: float RGB out, no dependency beyond libc/libm.
 * Hosted.
 *
 * Reads the "#?" magic line (any program name; a repeated magic line later in the header is an
 * ordinary line), header lines up to the blank line (FORMAT must be 32-bit_rle_rgbe if present;
 * GAMMA, PRIMARIES, EXPOSURE, comments and unknown lines are ignored, EXPOSURE is NOT applied), the
 * standard "-Y H +X W" resolution line (other orientations are refused), then H scanlines each
 * in one of three encodings, detected per scanline as Radiance does:
 *   - new-style (adaptive) RLE: 02 02 W_hi W_lo, then each of R, G, B, E as runs (count > 128:
 *     count - 128 copies of one byte) and literals (count 1..128 bytes); only for 8 <= W < 32768;
 *   - old-style RLE: a pixel 01 01 01 n repeats the previous pixel n << shift times, the shift
 *     growing by 8 for each consecutive run pixel;
 *   - flat: W plain 4-byte pixels.
 * Pixels become R = mantissa * 2^(E - 136) (E = 0: zero), without Radiance's +1/2 offset, which is
 * the convention ../shared/fixtures/SOURCES.md uses for the probes' statistics.
 *
 * Limits (checked in this order, each a named one-line error, before any pixel memory is taken):
 *   - a file: regular, 2 .. QTOOL_HDR_MAX_FILE_BYTES bytes, starting "#?" (io/file.h), checked
 *     before the file is read;
 *   - the header (magic line to the resolution line) at most QIBL_HDR_MAX_HEADER_BYTES;
 *   - W, H in 1..QIBL_HDR_MAX_DIM and W H <= QIBL_HDR_MAX_PIXELS: the light-probe core's own
 *     limits (qibl/lightprobe.h), so no probe is decoded that the core would refuse;
 *   - the body is walked once without writing (every scanline complete and well formed) before the
 *     W H 4 bytes of pixels are allocated: a header that lies about its size costs no memory.
 * Memory: the file, plus 4 bytes per pixel (RGBE) or 4 + 12 per pixel while converting to float.
 * Time: linear in the file plus the pixels.
 */
#ifndef QTOOL_IO_HDR_H
#define QTOOL_IO_HDR_H

#include <stddef.h>
#include <stdint.h>

#include "qibl/lightprobe.h"

#define QIBL_HDR_MAX_DIM QIBL_LIGHTPROBE_MAX_DIM       /* 32768 */
#define QIBL_HDR_MAX_PIXELS QIBL_LIGHTPROBE_MAX_PIXELS /* 2^26 */
#define QIBL_HDR_MAX_HEADER_BYTES 65536u
/* the largest well-formed file: every pixel a new-style RLE literal (2 bytes per byte of RGBE) plus
 * 4 bytes of scanline header per row and the header */
#define QTOOL_HDR_MAX_FILE_BYTES \
    ((size_t)8 * QIBL_HDR_MAX_PIXELS + (size_t)4 * QIBL_HDR_MAX_DIM + QIBL_HDR_MAX_HEADER_BYTES)

/* A file starting with the OpenEXR magic (76 2f 31 01) is read by io/exr.h instead, whatever its name:
 * its data window's R G B (or Y), negative samples made 0; qtool_hdr_read_rgbe encodes them as
 * qtool_probe_layout_rgbe_encode does (largest channel rounded to nearest on 8 bits). This is how
 * every probe and image input of the CLI (relight --probe, sh project, probe info, lights, study,
 * bake, transfer, bench, demo) accepts .exr. The qtool_hdr_decode* functions read Radiance only. */

/* Reads path. On success returns 0 and sets *w, *h and *rgb: 3 * w * h floats, rows top to bottom,
 * R G B per pixel, allocated with malloc (the caller frees). On failure returns -1, writes a one-line
 * reason naming the file into err (errlen bytes) and sets nothing. */
int qtool_hdr_read(const char *path, int *w, int *h, float **rgb, char *err, size_t errlen);

/* The same from a file image in memory (len bytes); the error text names no file. */
int qtool_hdr_decode(const uint8_t *buf, size_t len, int *w, int *h, float **rgb, char *err, size_t errlen);

/* As qtool_hdr_read / qtool_hdr_decode, but the pixels are the decoded RGBE bytes themselves:
 * 4 * w * h bytes R G B E per pixel, rows top to bottom (what qibl/lightprobe.h reads as
 * QIBL_LIGHTPROBE_RGBE). */
int qtool_hdr_read_rgbe(const char *path, int *w, int *h, uint8_t **rgbe, char *err, size_t errlen);
int qtool_hdr_decode_rgbe(const uint8_t *buf, size_t len, int *w, int *h, uint8_t **rgbe, char *err, size_t errlen);

#endif
