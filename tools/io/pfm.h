/*
 * io/pfm.h - Portable Float Map reader and writer (PF: RGB, Pf: grey; binary32 samples, byte order
 * from the sign of the scale line: negative = little-endian; rows stored bottom to top). Hosted.
 */
#ifndef QTOOL_IO_PFM_H
#define QTOOL_IO_PFM_H

#include <stddef.h>
#include <stdint.h>

#include "qibl/lightprobe.h"

/* Reading limits, checked from the header before any sample memory is taken: W, H in
 * 1..QTOOL_PFM_MAX_DIM, W H <= QIBL_PFM_MAX_PIXELS (the light-probe core's limit, qibl/lightprobe.h),
 * and the samples must all be in the file (a header claiming more than the file holds is refused
 * before allocating). The file: regular, at most QTOOL_PFM_MAX_FILE_BYTES, magic checked before it
 * is read (io/file.h). Every sample must be finite: the first NaN or infinity is refused with its
 * value and position. Memory: the file plus the decoded samples; time linear in the file. */
#define QTOOL_PFM_MAX_DIM 65535u
#define QIBL_PFM_MAX_PIXELS QIBL_LIGHTPROBE_MAX_PIXELS /* 2^26 */
#define QTOOL_PFM_MAX_HEADER_BYTES 4096u
#define QTOOL_PFM_MAX_FILE_BYTES ((size_t)12 * QIBL_PFM_MAX_PIXELS + QTOOL_PFM_MAX_HEADER_BYTES)

/* Reads path. On success returns 0 and sets *w, *h, *channels (1 or 3) and *px: channels * w * h
 * floats, rows TOP to bottom (flipped from the file's order), malloc'ed. On failure returns -1 with
 * a one-line reason naming the file in err and sets nothing. */
int qtool_pfm_read(const char *path, int *w, int *h, int *channels, float **px, char *err, size_t errlen);
/* The same from a file image in memory; the error text names no file. */
int qtool_pfm_decode(const uint8_t *buf, size_t len, int *w, int *h, int *channels, float **px, char *err,
                    size_t errlen);

/* Writes channels (1 or 3) * w * h floats (rows top to bottom) as a little-endian PFM, atomically
 * (io/atomic.h). A NaN or infinite sample is refused (nothing written). 0, or -1 with a one-line
 * reason naming the file. */
int qtool_pfm_write(const char *path, int w, int h, int channels, const float *px, char *err, size_t errlen);

#endif
