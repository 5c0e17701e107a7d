/*
 * io/lightcsv.h - the light list `qibl lights --csv` writes, read back (`qibl relight --lights`).
 * Hosted (libc, libm).
 *
 * Format: the header line "x,y,z,r,g,b,u0,v0,u1,v1" exactly, then one light per line: x,y,z a
 * direction (any length but zero; normalised here), r,g,b finite radiance >= 0 and <= 1e30,
 * u0,v0,u1,v1 the region's pixel bounds (integers in 0 .. 2^32 - 1). Lines end in "\n" or "\r\n";
 * empty lines are skipped. Limits, each refused by name: QTOOL_LIGHTCSV_MAX lights, lines of at
 * most QTOOL_LIGHTCSV_LINE_MAX bytes, files of at most QTOOL_LIGHTCSV_MAX_BYTES; a NUL byte (this
 * is text) is named as one.
 * Work and memory: one pass over the bytes; 80 bytes of doubles per light while parsing, then
 * the result (40 bytes a light); the file is read whole (at most QTOOL_LIGHTCSV_MAX_BYTES).
 */
#ifndef QTOOL_IO_LIGHTCSV_H
#define QTOOL_IO_LIGHTCSV_H

#include <stddef.h>
#include <stdint.h>

#include "qibl/lightprobe.h"

#define QTOOL_LIGHTCSV_HEADER "x,y,z,r,g,b,u0,v0,u1,v1" /* what `qibl lights --csv` writes */
#define QTOOL_LIGHTCSV_MAX 65536u     /* rows (qibl_shlight_add_lights' limit) */
#define QTOOL_LIGHTCSV_LINE_MAX 1022u /* bytes of a line, without its end */
/* the header and QTOOL_LIGHTCSV_MAX rows of the longest length, with their "\r\n" */
#define QTOOL_LIGHTCSV_MAX_BYTES (((size_t)QTOOL_LIGHTCSV_MAX + 1) * (QTOOL_LIGHTCSV_LINE_MAX + 2))

/* Parses n bytes of a light list (name is used in messages only). *lights (malloc'd, the caller
 * frees): unit directions in Q2.30 (scaled before squaring, so 1e-300 and 1e200 components are as
 * good as 1), rgb integers (the largest channel below 2^30) times 2^*rgb_exp. 0, or -1 with one
 * line in err naming the source, the line and the value; nothing allocated then. */
int qtool_lightcsv_parse(const char *name, const char *buf, size_t n, qibl_lightprobe_light_t **lights,
                         uint32_t *count, int32_t *rgb_exp, char *err, size_t errlen);

/* The same from the file at path (a regular file of at most QTOOL_LIGHTCSV_MAX_BYTES). */
int qtool_lightcsv_read(const char *path, qibl_lightprobe_light_t **lights, uint32_t *count, int32_t *rgb_exp,
                        char *err, size_t errlen);

#endif
