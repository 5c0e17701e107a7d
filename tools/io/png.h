/*
 * io/png.h - minimal PNG writer (8-bit RGB, own deflate encoder): readable by every viewer, no
 * dependency beyond libc. Hosted.
 */
#ifndef QTOOL_IO_PNG_H
#define QTOOL_IO_PNG_H

#include <stddef.h>
#include <stdint.h>

/* Writes w x h 8-bit RGB pixels (rows top to bottom, 3 bytes per pixel, tightly packed) to path.
 * The file is written atomically (io/atomic.h), so a failure leaves no partial file.
 * Returns 0, or -1 with a one-line reason in err (errlen bytes). */
int qtool_png_write_rgb8(const char *path, int w, int h, const uint8_t *rgb, char *err, size_t errlen);

/* Animated PNG (APNG: acTL, then per frame fcTL and IDAT for the first frame, fdAT for the others;
 * viewers without APNG support show the first frame). frames >= 2 images of w x h RGB back to back;
 * each shown delay_num / delay_den seconds; loops forever. Atomic like qtool_png_write_rgb8. */
int qtool_apng_write_rgb8(const char *path, int w, int h, int frames, const uint8_t *rgb, int delay_num,
                         int delay_den, char *err, size_t errlen);

/* Reads a PNG as qibl's writers produce it and any viewer accepts as 8-bit RGB or RGBA (and, for
 * textures, 8-bit grey, grey + alpha and palette images, returned as RGB), non-interlaced
 * (every filter type; stored, fixed and dynamic Huffman deflate blocks), checking the signature, every
 * chunk CRC, the zlib header and Adler-32. For an APNG, *frames is set to the acTL frame count and
 * the fcTL/fdAT sequence is checked (all frames full size); the pixels returned are the first frame.
 * 0 with *rgb (3 * w * h bytes, malloc'ed) set, or -1 with a one-line reason naming the file. */
/* Reading limits (named one-line errors): the file regular, at most QTOOL_PNG_MAX_FILE_BYTES, its
 * signature checked before it is read (io/file.h); IHDR first, W, H in 1..QTOOL_PNG_MAX_DIM and
 * W H <= QIBL_PNG_MAX_PIXELS, checked before any image data is collected; the zlib stream may
 * inflate to exactly the (channels W + 1) H bytes IHDR implies, allocated once: a stream that
 * inflates further stops there ("inflates past"). Memory: the file, the IDAT bytes, that buffer
 * and the image; time linear in the file plus the image. */
#define QTOOL_PNG_MAX_DIM 65535u
#define QIBL_PNG_MAX_PIXELS ((uint32_t)1 << 26)
#define QTOOL_PNG_MAX_FILE_BYTES ((size_t)1 << 30)
int qtool_png_read_rgb8(const char *path, int *w, int *h, int *frames, uint8_t **rgb, char *err, size_t errlen);
int qtool_png_decode_rgb8(const uint8_t *buf, size_t len, int *w, int *h, int *frames, uint8_t **rgb, char *err,
                         size_t errlen);

#endif
