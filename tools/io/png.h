/*
 * io/png.h - minimal PNG writer (8-bit RGB, own deflate encoder): readable by every viewer, no
 * dependency beyond libc. Hosted.
 */
#ifndef QIBL_IO_PNG_H
#define QIBL_IO_PNG_H

#include <stddef.h>
#include <stdint.h>

/* Writes w x h 8-bit RGB pixels (rows top to bottom, 3 bytes per pixel, tightly packed) to path.
 * The file is written to "path.tmp" and renamed, so a failure leaves no partial file.
 * Returns 0, or -1 with a one-line reason in err (errlen bytes). */
int qibl_png_write_rgb8(const char *path, int w, int h, const uint8_t *rgb, char *err, size_t errlen);

#endif
