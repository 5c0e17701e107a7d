/*
 * io/exr.h - OpenEXR reader and writer (single-part, flat images), libc only. Hosted.
 *
 * Reads: scanline and tiled files (a tiled file's level 0 only: ONE_LEVEL, and the full-resolution
 * level of MIPMAP / RIPMAP files); NONE, RLE, ZIPS, ZIP and PIZ compression (the zlib streams through
 * io/zlib.h, PIZ's Huffman code and Haar wavelet written here from the format's description);
 * HALF, FLOAT and UINT channels. The picture is R, G, B (any order in the file, any other channels
 * such as A decoded and dropped) or, with no R G B, Y (grey, copied to R G B). Channels must not be
 * subsampled. Refused with a named error: multi-part and deep files, PXR24 / B44 / B44A / DWAA / DWAB
 * compression, a file whose picture channels are missing.
 *
 * Windows: the data window is what is decoded (w x h = its size, rows top to bottom = increasing y);
 * the display window is checked (a valid box) and returned in qtool_exr_info, never applied: a probe
 * or frame is the data window's pixels. (A data window smaller than the display window is therefore
 * read as the smaller image; the CLI's probe readers need the full picture and get what was stored.)
 *
 * Values: HALF is widened exactly, FLOAT kept bit for bit, UINT converted to the nearest float.
 * A NaN or infinite sample in R, G, B or Y is refused with its position (as the PFM reader does).
 *
 * Limits (named one-line errors, each checked before it is trusted or allocated for):
 *  - the file: regular, 8 .. QTOOL_EXR_MAX_FILE_BYTES bytes, EXR magic checked before it is read;
 *  - version 2; the flags tiled / long names only; at most QTOOL_EXR_MAX_ATTRIBUTES header
 *    attributes, each inside the file; names at most 255 bytes;
 *  - 1 .. QTOOL_EXR_MAX_CHANNELS channels;
 *  - the data window 1 .. QTOOL_EXR_MAX_DIM a side and at most QTOOL_EXR_MAX_PIXELS pixels (the
 *    light-probe core's limits); tile sizes 1 .. QTOOL_EXR_MAX_DIM;
 *  - the chunk offset table (one entry per block of lines or per tile) inside the file; every
 *    entry's chunk header (its y or tile coordinates, its size inside the file and no larger than
 *    the pixels it holds) is checked in one pass over the table before the image is allocated;
 *  - each chunk decompresses to exactly its pixels' size: zlib and RLE output stop at that size,
 *    PIZ's Huffman stream must give exactly that many 16-bit values, its code table and bitmap are
 *    read sparsely (work proportional to the bytes present, not to the 65536-entry alphabet).
 * Memory: the file, the image (12 bytes per pixel), one chunk's raw bytes (at most the image's raw
 * bytes) and for PIZ its 16-bit copy plus 65537-entry tables (about 0.7 MiB).
 * Time: linear in the file plus the raw pixel bytes (at most QTOOL_EXR_MAX_CHANNELS * 4 bytes a
 * pixel, 64: 5.3 times the 12-byte decoded pixel).
 */
#ifndef QTOOL_IO_EXR_H
#define QTOOL_IO_EXR_H

#include <stddef.h>
#include <stdint.h>

#include "qibl/lightprobe.h"

#define QTOOL_EXR_MAX_DIM QIBL_LIGHTPROBE_MAX_DIM       /* 32768 */
#define QTOOL_EXR_MAX_PIXELS QIBL_LIGHTPROBE_MAX_PIXELS /* 2^26 */
#define QTOOL_EXR_MAX_CHANNELS 16
#define QTOOL_EXR_MAX_ATTRIBUTES 1024
/* an RGBA FLOAT image of the largest size stored uncompressed, plus 64 MiB of header and tables */
#define QTOOL_EXR_MAX_FILE_BYTES ((size_t)16 * QTOOL_EXR_MAX_PIXELS + ((size_t)1 << 26))

/* compression codes as the file stores them */
enum { QTOOL_EXR_NONE = 0, QTOOL_EXR_RLE = 1, QTOOL_EXR_ZIPS = 2, QTOOL_EXR_ZIP = 3, QTOOL_EXR_PIZ = 4 };
/* channel pixel types as the file stores them */
enum { QTOOL_EXR_UINT = 0, QTOOL_EXR_HALF = 1, QTOOL_EXR_FLOAT = 2 };

typedef struct qtool_exr_info {
    int w, h;             /* the data window's size: the decoded image */
    int32_t data[4];      /* data window xmin, ymin, xmax, ymax */
    int32_t display[4];   /* display window xmin, ymin, xmax, ymax (not applied) */
    int compression;      /* QTOOL_EXR_NONE .. QTOOL_EXR_PIZ */
    int tiled;            /* 0 scanline, 1 tiled (level 0 read) */
    int tile_w, tile_h;   /* tiled only */
    int channels;         /* channels in the file */
    int grey;             /* 1: the picture is the Y channel */
    int pixel_type;       /* of R (or Y): QTOOL_EXR_UINT / HALF / FLOAT */
    int line_order;       /* 0 increasing y, 1 decreasing, 2 random */
} qtool_exr_info;

/* 1 if the n bytes at head start with the OpenEXR magic number 0x762f3101 (76 2f 31 01). */
int qtool_exr_magic(const uint8_t *head, size_t n);

/* 1 if path is a regular file whose first four bytes are the EXR magic (the others: 0, nothing said);
 * lets a reader of another format hand an EXR over to this one. */
int qtool_exr_sniff(const char *path);

/* Decodes a file image in memory (len bytes). On success returns 0, fills *info (if not NULL) and
 * sets *rgb: 3 * w * h floats, rows top to bottom, R G B per pixel, malloc'ed (the caller frees).
 * On failure returns -1 with a one-line reason in err (errlen bytes); *info and *rgb untouched. */
int qtool_exr_decode(const uint8_t *buf, size_t len, qtool_exr_info *info, float **rgb, char *err, size_t errlen);

/* The same from path (io/file.h's checks first); the error names the file. */
int qtool_exr_read(const char *path, qtool_exr_info *info, float **rgb, char *err, size_t errlen);

/* Writer: a scanline file of w x h RGB floats (rows top to bottom), channels B G R of pixel_type
 * QTOOL_EXR_HALF (rounded to nearest even) or QTOOL_EXR_FLOAT (bit for bit), compression
 * QTOOL_EXR_NONE, QTOOL_EXR_ZIPS or QTOOL_EXR_ZIP (blocks whose deflate is no smaller are stored raw,
 * as the format asks), data and display window (0, 0) - (w - 1, h - 1), increasing y.
 * Refused with the sample named: NaN, infinity, and for HALF a magnitude that rounds past 65504.
 * w, h in 1 .. QTOOL_EXR_MAX_DIM, w h <= QTOOL_EXR_MAX_PIXELS. 0, or -1 with a one-line reason. */
int qtool_exr_encode(int w, int h, const float *rgb, int pixel_type, int compression, uint8_t **out, size_t *outlen,
                     char *err, size_t errlen);

/* The same written atomically to path (io/atomic.h): nothing is written on failure. */
int qtool_exr_write(const char *path, int w, int h, const float *rgb, int pixel_type, int compression, char *err,
                    size_t errlen);

#endif
