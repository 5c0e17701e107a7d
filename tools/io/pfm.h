/*
 * io/pfm.h - Portable Float Map reader and writer (PF: RGB, Pf: grey; binary32 samples, byte order
 * from the sign of the scale line: negative = little-endian; rows stored bottom to top). Hosted.
 */
#ifndef QIBL_IO_PFM_H
#define QIBL_IO_PFM_H

#include <stddef.h>
#include <stdint.h>

/* Reads path. On success returns 0 and sets *w, *h, *channels (1 or 3) and *px: channels * w * h
 * floats, rows TOP to bottom (flipped from the file's order), malloc'ed. On failure returns -1 with
 * a one-line reason naming the file in err and sets nothing. */
int qibl_pfm_read(const char *path, int *w, int *h, int *channels, float **px, char *err, size_t errlen);
/* The same from a file image in memory; the error text names no file. */
int qibl_pfm_decode(const uint8_t *buf, size_t len, int *w, int *h, int *channels, float **px, char *err,
                    size_t errlen);

/* Writes channels (1 or 3) * w * h floats (rows top to bottom) as a little-endian PFM, atomically
 * (io/atomic.h). A NaN or infinite sample is refused (nothing written). 0, or -1 with a one-line
 * reason naming the file. */
int qibl_pfm_write(const char *path, int w, int h, int channels, const float *px, char *err, size_t errlen);

#endif
