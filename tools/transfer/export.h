/*
 * transfer/export.h - `qibl transfer --export FILE.qtr`: frame 0's per-vertex world-space transfer
 * vectors in the layout qibl/hemi.h documents (magic "QTRX", little-endian header with the count,
 * bands and a CRC-32 of the payload, then Q2.30 coefficients), which the core validates with
 * qibl_hemi_xfer_open and shades with qibl_hemi_xfer_shade_span. Written through io/atomic.h:
 * complete or not at all.
 */
#ifndef QTOOL_TRANSFER_EXPORT_H
#define QTOOL_TRANSFER_EXPORT_H

#include <stddef.h>
#include <stdint.h>

#include "qibl/hemi.h"

#define QTOOL_TRANSFER_EXPORT_BANDS_DEFAULT 5 /* 25 coefficients: shades as `qibl transfer` does, bit for bit */

/* The export's bytes for nv vectors t (25 Q2.30 each; the first bands^2 kept, bands 3..5):
 * malloc'd into *out (*n bytes). 0, or -1 with a one-line reason (bands, count, memory). */
int qtool_transfer_export_bytes(const qibl_q30_t (*t)[QIBL_HEMI_COEFFS], uint32_t nv, int bands, uint8_t **out,
                                size_t *n, char *err, size_t errlen);

/* The same written to path atomically; 0, or -1 with a one-line reason naming path. */
int qtool_transfer_export_write(const char *path, const qibl_q30_t (*t)[QIBL_HEMI_COEFFS], uint32_t nv, int bands,
                                char *err, size_t errlen);

/* The same bytes as a C header for a build without a file system (ROM): `static const unsigned
 * char IDENT[N]` (N = IDENT_SIZE, a #define) that qibl_hemi_xfer_open takes as it is; IDENT made of
 * the file name's stem (letters, digits, '_'; "qtr_" before a leading digit) unless ident is given.
 * Written atomically; 0, or -1 with a one-line reason naming path. */
int qtool_transfer_export_write_c(const char *path, const uint8_t *bytes, size_t n, const char *ident, char *err,
                                  size_t errlen);

/* Reads an export (magic checked, at most the largest valid size) into a malloc'd buffer; the core
 * validates the rest (qibl_hemi_xfer_open). 0, or -1 with a one-line reason naming path. */
int qtool_transfer_export_read(const char *path, uint8_t **buf, size_t *n, char *err, size_t errlen);

#endif
