/*
 * qibl/asset.h - the qibl asset container: versioned chunks, little-endian, CRC-32 per chunk,
 * parsed in place from caller memory (zero-copy, alignment-safe, no heap).
 *
 * Layout (all integers little-endian whatever the host; offsets from the first byte):
 *
 *   header (a 24-byte record)
 *     0  u8[8] magic        'Q' 'I' 'B' 'L' '\r' '\n' 0x1A '\n'   (catches text-mode mangling)
 *     8  u32   version      QIBL_ASSET_VERSION (1)
 *    12  u32   chunk_count  1..QIBL_ASSET_MAX_CHUNKS
 *    16  u32   file_size    bytes in the whole asset; the caller's buffer may be longer, not shorter
 *    20  u32   table_crc    CRC-32 of the chunk table (the 16 * chunk_count bytes at offset 24)
 *   chunk table, 16 bytes per chunk
 *     0  u32   type         four ASCII bytes in file order, read as a little-endian u32
 *                           (QIBL_CHUNK_SHMP = "SHMP" ...)
 *     4  u32   offset       of the payload; a multiple of 4, at or after the end of the table
 *     8  u32   size         payload bytes
 *    12  u32   crc          CRC-32 (ISO 3309, as zip/PNG) of the payload
 *   payloads: anywhere after the table, inside file_size, not overlapping each other.
 *
 * Chunk types known to this version (unknown types are CRC-checked and otherwise ignored; a known
 * type may appear at most once):
 *
 *   SHMP (required) - k SH maps, 8-bit range-packed (Wong et al.; qibl packs per map and channel)
 *     0  u32 width      1..QIBL_ASSET_MAX_DIM
 *     4  u32 height     1..QIBL_ASSET_MAX_DIM, width * height <= QIBL_ASSET_MAX_PIXELS
 *     8  u32 k          number of maps, 1..25 (bands 0..4, flat SH index i = l*l + l + m)
 *    12  u32 channels   1 (grey) or 3 (RGB)
 *    16  u32 flags      0 (planar) or QIBL_SHMP_FLAG_INTERLEAVED (0x10); other values reserved
 *    20  k * channels pairs {i32 scale, i32 bias}, Q8.24, map-major (pair index i*channels + ch):
 *        the decoded value of byte c is bias + scale * c (c in 0..255)
 *    20 + 8 * k * channels: the map bytes, height rows in the layout the flag names (shmaps.h):
 *        planar (flag clear): k * channels planes of width * height bytes, row-major, top row
 *        first, plane index i * channels + ch;
 *        interleaved (flag set): height rows of ceil(width / 16) * 16 * k * channels bytes, each
 *        row one contiguous range (stream it), groups of 16 pixels, [channel][map][16 bytes]
 *    size = 20 + 8 k channels + height * row size exactly (row size: width k channels planar)
 *
 *   Version policy: a layout is a flag of SHMP, not a new container version. Planar assets are
 *   byte for byte what they were (version 1, flags 0); a reader that predates the flag rejects an
 *   interleaved asset with QIBL_E_ASSET_BAD_FLAGS (named), never misreads it. QIBL_ASSET_VERSION
 *   changes only when a version-1 reader would misread a file; reserved bits must stay 0.
 *
 *   PMAP (optional; needed for point lights) - per-pixel scene point seen through the pixel (Wong
 *   eq. 2: depth along the pixel's viewing ray from the viewpoint E, here E = origin)
 *     0  u32 width, 4 u32 height (both equal to SHMP's), 8 u32 flags 0
 *    12  width * height * 3 i32: x, y, z in Q16.16 scene units, row-major
 *    size = 12 + 12 width height exactly
 *
 *   SHMU (optional) - unshadowed transfer: k SH maps of cosine x BRDF without visibility, the
 *   same layout and rules as SHMP (its own k and packing), width and height equal to SHMP's
 *   (else QIBL_E_ASSET_MISMATCH). Free point lights use it (visibility at infinity is wrong for a
 *   lamp inside the scene); light paths (lightpath.h) multiply it by their baked visibility.
 *
 *   YLUT (optional) - cube-map look-up tables of Y_i (Wong §"Relighting by a point source")
 *     0  u32 face_size N (1..QIBL_YLUT_MAX_FACE), 4 u32 k (>= SHMP k, <= 25), 8 u32 flags 0
 *    12  6 * N * N * k i16 in Q2.14: [face][row v][column u][i]; faces +X -X +Y -Y +Z -Z; texel
 *        (u, v) of face f is the direction of the OpenGL cube-map convention with
 *        s = 2 (u + 0.5) / N - 1, t = 2 (v + 0.5) / N - 1:
 *        +X (1, -t, -s)  -X (-1, -t, s)  +Y (s, 1, t)  -Y (s, -1, -t)  +Z (s, -t, 1)  -Z (-s, -t, -1)
 *    size = 12 + 12 N N k exactly
 *
 * Validation (qibl_asset_open) checks everything above once; afterwards the accessors cannot fail
 * on a validated asset. Each problem has its own status (see status.h, QIBL_E_ASSET_*) and the
 * first failing check is reported, in this order: header; table size and CRC; per entry its
 * alignment and bounds, then duplicate/overlap against the earlier entries; SHMP present; every
 * payload CRC; the fields of SHMP, then PMAP, then YLUT, then SHMU (a payload too short for its fixed fields
 * is QIBL_E_ASSET_CHUNK_SIZE). A buffer or a file_size shorter than header + table is
 * QIBL_E_ASSET_TRUNCATED_TABLE, a buffer shorter than file_size QIBL_E_ASSET_TRUNCATED. An empty
 * payload (size 0) overlaps nothing. A failing call writes nothing to its outputs.
 *
 * Three ways to open (same checks in the same order, same statuses, except as said):
 *   qibl_asset_open            every check and every CRC, nibble-table CRC (64 bytes of .rodata;
 *                              the slowest of the three per byte);
 *   qibl_asset_open_crc_table  the same result, CRCs by slicing-by-8 with an 8 KiB table the caller
 *                              fills once with qibl_crc32_table_init (a fraction of the instructions);
 *   qibl_asset_open_structure  header and structure only: every check above except the payload
 *                              CRCs (the table CRC is still checked). For assets verified at install
 *                              time (by one of the two above, or by the installer's own hash): it
 *                              does NOT detect bit flips inside payloads, which then relight wrongly
 *                              but safely (every size and offset is still checked, so no access
 *                              leaves the buffer).
 * Streaming (qibl_asset_head_size, qibl_asset_open_head, qibl_asset_row): the same structure checks
 * on the file's first bytes only, then the file offset of each row, for interleaved assets whose
 * rows are loaded one at a time (from disc, cartridge, network) and relit through one-row views.
 * The PMAP and YLUT fields lie outside the head: qibl_asset_head_pmap and qibl_asset_head_ylut check
 * them, when loaded, with the very checks qibl_asset_open applies, and build the views.
 */
#ifndef QIBL_ASSET_H
#define QIBL_ASSET_H

#include <stddef.h>
#include <stdint.h>
#include "qibl/config.h"
#include "qibl/fixed.h"
#include "qibl/shmaps.h"
#include "qibl/status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define QIBL_ASSET_VERSION 1u
#define QIBL_ASSET_HEADER_SIZE 24u
#define QIBL_ASSET_ENTRY_SIZE 16u
#define QIBL_ASSET_MAX_CHUNKS 64u
#define QIBL_ASSET_MAX_DIM 16384u
#define QIBL_ASSET_MAX_PIXELS (1u << 26) /* 64 Mpixel; sizes are computed in 64 bits and a size
                                          * that does not fit a u32 is QIBL_E_ASSET_SIZE_OVERFLOW */
#define QIBL_ASSET_MAX_LUT QIBL_YLUT_MAX_FACE
/* SHMP flags value 0x10 (bit 4, the group size 16): map bytes interleaved in groups of 16 pixels.
 * Bits 0..3 stay reserved, so a later group size (0x20 for 32) can be told apart. */
#define QIBL_SHMP_FLAG_INTERLEAVED 0x10u

/* four-character chunk codes, as the u32 read little-endian from the bytes "SHMP", ... */
#define QIBL_FOURCC(a, b, c, d)                                                                          \
    (QIBL_CAST(uint32_t, a) | QIBL_CAST(uint32_t, b) << 8 | QIBL_CAST(uint32_t, c) << 16 | QIBL_CAST(uint32_t, d) << 24)
#define QIBL_CHUNK_SHMP QIBL_FOURCC('S', 'H', 'M', 'P')
#define QIBL_CHUNK_PMAP QIBL_FOURCC('P', 'M', 'A', 'P')
#define QIBL_CHUNK_YLUT QIBL_FOURCC('Y', 'L', 'U', 'T')
#define QIBL_CHUNK_SHMU QIBL_FOURCC('S', 'H', 'M', 'U')

/* A validated asset: a view of the caller's bytes (which must outlive it). Zero-initialisable. */
typedef struct qibl_asset {
    const uint8_t *base;
    uint32_t size;        /* file_size */
    uint32_t chunk_count;
} qibl_asset_t;

/* One chunk's payload as a view into the asset bytes. */
typedef struct qibl_chunk {
    uint32_t type;
    uint32_t size;
    const uint8_t *data;
} qibl_chunk_t;

/* CRC-32 (ISO 3309 / zip / PNG polynomial 0xEDB88320, reflected, init and final xor 0xFFFFFFFF)
 * of n bytes, continuing from crc (pass 0 to start). A nibble-at-a-time loop over a 16-entry const
 * table (64 bytes of .rodata) instead of the usual 1 KiB byte table. */
uint32_t qibl_crc32(uint32_t crc, const uint8_t *data, size_t n);

/* Slicing-by-8 CRC tables: 8 * 256 u32 (8 KiB) in the caller's memory, filled once. */
#define QIBL_CRC32_TABLE_WORDS 2048u
/* Fills table[0..QIBL_CRC32_TABLE_WORDS) (any memory the caller owns: RAM, or flash written once).
 * Formats: none (CRC register values, native uint32). Bound: exact.
 * Errors, in this order: QIBL_E_NULL_POINTER (table NULL), QIBL_E_WORKSPACE (words <
 * QIBL_CRC32_TABLE_WORDS).
 * On failure: nothing is written. */
QIBL_NODISCARD qibl_status_t qibl_crc32_table_init(uint32_t *table, size_t words);
/* The same CRC as qibl_crc32, eight bytes per step through a table from qibl_crc32_table_init
 * (byte loads only: any alignment, either byte order). No checks (hot path). */
uint32_t qibl_crc32_fast(const uint32_t *table, uint32_t crc, const uint8_t *data, size_t n);

/* Validates bytes[0..n) as an asset (every rule above, every CRC) and fills *out.
 * Formats: none (little-endian u32 fields, CRC-32; no number is converted). Bound: exact.
 * Errors, in this order: QIBL_E_NULL_POINTER (out or bytes NULL); QIBL_E_ASSET_TRUNCATED_HEADER
 * (n < 24); QIBL_E_ASSET_MAGIC, _VERSION, _CHUNK_COUNT, _TRUNCATED_TABLE (file_size below header +
 * table); QIBL_E_ASSET_TRUNCATED_TABLE (n below header + table), QIBL_E_ASSET_TRUNCATED (n <
 * file_size); QIBL_E_ASSET_TABLE_CRC; per entry _CHUNK_MISALIGNED, _CHUNK_PAST_END, then against each
 * earlier entry _DUPLICATE_CHUNK (a known type twice) and _CHUNK_OVERLAP; _MISSING_CHUNK (no SHMP);
 * _CHUNK_CRC (first entry in table order); then SHMP's fields (_CHUNK_SIZE short of its 20-byte part,
 * _BAD_DIMENSIONS, _BAD_K, _BAD_CHANNELS, _BAD_FLAGS, _SIZE_OVERFLOW, _CHUNK_SIZE), PMAP's
 * (_CHUNK_SIZE, _BAD_DIMENSIONS, _MISMATCH, _BAD_FLAGS, _CHUNK_SIZE), YLUT's (_CHUNK_SIZE,
 * _BAD_DIMENSIONS, _BAD_K, _MISMATCH (k below SHMP's), _BAD_FLAGS, _CHUNK_SIZE), SHMU's (as SHMP's,
 * then _MISMATCH for a width or height other than SHMP's).
 * On failure: nothing is written (*out untouched). */
QIBL_NODISCARD qibl_status_t qibl_asset_open(qibl_asset_t *out, const void *bytes, size_t n);

/* qibl_asset_open with the CRCs through a qibl_crc32_table_init table: same checks, same statuses,
 * about a quarter of the instructions.
 * Formats: none (as qibl_asset_open; crc_table as qibl_crc32_table_init fills it). Bound: exact.
 * Errors, in this order: QIBL_E_NULL_POINTER (out, bytes or crc_table NULL), then those of
 * qibl_asset_open in its order (a table not from qibl_crc32_table_init gives QIBL_E_ASSET_CHUNK_CRC).
 * On failure: nothing is written (*out untouched). */
QIBL_NODISCARD qibl_status_t qibl_asset_open_crc_table(qibl_asset_t *out, const void *bytes, size_t n, const uint32_t *crc_table);

/* Header and structure only (see the top of this file): every check of qibl_asset_open except the
 * payload CRCs, so it costs nothing per payload byte. For assets verified at install time; payload
 * bit flips pass undetected.
 * Formats: none (as qibl_asset_open). Bound: exact.
 * Errors: those of qibl_asset_open in its order, minus QIBL_E_ASSET_CHUNK_CRC (the table CRC,
 * QIBL_E_ASSET_TABLE_CRC, is still checked).
 * On failure: nothing is written (*out untouched). */
QIBL_NODISCARD qibl_status_t qibl_asset_open_structure(qibl_asset_t *out, const void *bytes, size_t n);

/* The chunk of the given type (the first one, for an unknown type that appears more than once).
 * Formats: none (a view: type, size, data pointer). Bound: exact.
 * Errors, in this order: QIBL_E_NULL_POINTER (a or out NULL), QIBL_E_ASSET_MISSING_CHUNK (no chunk
 * of that type).
 * On failure: nothing is written (*out untouched). */
QIBL_NODISCARD qibl_status_t qibl_asset_find(const qibl_asset_t *a, uint32_t type, qibl_chunk_t *out);

/* ---- streaming by rows ----------------------------------------------------------------------
 * Only the head of the file is resident: header, chunk table and SHMP's fields and params. The
 * caller reads the first bytes, asks qibl_asset_head_size how many it needs (at most four rounds:
 * header, table, SHMP's fields, its params), opens the head, then loads each row it relights from the offsets
 * qibl_asset_row gives and relights through qibl_shmaps_row_view / qibl_pmap_row_view (shmaps.h).
 * Checks: those of qibl_asset_open_structure that the head holds (header, table CRC, every entry's
 * bounds, duplicates and overlaps against file_size, SHMP's fields, PMAP's and YLUT's payload sizes
 * against SHMP from the table); no payload CRC. PMAP's and YLUT's fields are not in the head: build
 * their views with qibl_asset_head_pmap and qibl_asset_head_ylut, which apply qibl_asset_open's
 * checks of those fields (never read the fields by hand: a YLUT whose fields lie about its size
 * would make relighting read past the loaded bytes; qibl_shmap_point_prepare refuses a LUT view
 * whose size does not cover its fields with QIBL_E_SHMAP_LUT_SHORT). SHMU is not streamed (the head
 * names no offset for it) and its fields are not checked here. */

/* A streamed asset: what the head holds and where the rows are (file offsets). */
typedef struct qibl_asset_head {
    qibl_shmaps_t maps;      /* params point into the caller's head bytes; planes NULL */
    uint32_t file_size;
    uint32_t maps_offset;    /* file offset of map row 0 */
    uint32_t row_size;       /* bytes per map row (qibl_shmaps_row_size) */
    uint32_t pmap_offset;    /* file offset of P-map row 0 (12 * width bytes per row); 0: no PMAP */
    uint32_t ylut_offset, ylut_size; /* the YLUT payload (load it whole); 0, 0: no YLUT */
} qibl_asset_head_t;

/* Where row y lies in the file. */
typedef struct qibl_asset_row_s {
    uint32_t maps_offset, maps_size; /* the row's map bytes (one contiguous range) */
    uint32_t pmap_offset, pmap_size; /* the row's P-map points; 0, 0 without PMAP */
} qibl_asset_row_t;

/* From the first n bytes of an asset file (n may be anything, even 0), *need = how many leading
 * bytes qibl_asset_open_head needs; if *need > n, read that many and ask again (it may grow as the
 * table and SHMP's fields become visible; never beyond the end of SHMP's params).
 * Formats: none (byte counts). Bound: exact.
 * Errors, in this order: QIBL_E_NULL_POINTER (need NULL, or head NULL with n != 0); then the
 * header, table and SHMP statuses of qibl_asset_open, in its order, that the bytes seen so far
 * already show (no TRUNCATED_* and no payload CRC: short bytes are answered with a larger *need).
 * On failure: nothing is written (*need untouched). */
QIBL_NODISCARD qibl_status_t qibl_asset_head_size(const void *head, size_t n, size_t *need);

/* Opens the head (the first n bytes of the file, which must outlive *out).
 * Formats: none (file offsets and sizes in bytes; the maps' params stay Q8.24 bytes). Bound: exact.
 * Errors, in this order: QIBL_E_NULL_POINTER (out or head NULL), those of qibl_asset_head_size,
 * QIBL_E_ASSET_HEAD_SHORT (n below what qibl_asset_head_size asks for), QIBL_E_ASSET_LAYOUT (planar
 * maps: a planar row is k*channels ranges; open the whole asset instead), QIBL_E_ASSET_CHUNK_SIZE
 * (PMAP's size, from the table, other than 12 + 12 width height; YLUT's below 12).
 * On failure: nothing is written (*out untouched). */
QIBL_NODISCARD qibl_status_t qibl_asset_open_head(qibl_asset_head_t *out, const void *head, size_t n);

/* File offsets and sizes of row y.
 * Formats: none (byte offsets and sizes). Bound: exact.
 * Errors, in this order: QIBL_E_NULL_POINTER (h or out NULL), QIBL_E_ASSET_ROW (y >= height).
 * On failure: nothing is written (*out untouched). */
QIBL_NODISCARD qibl_status_t qibl_asset_row(const qibl_asset_head_t *h, uint32_t y, qibl_asset_row_t *out);

/* The P map of an opened head: fields are the PMAP payload's first n bytes (its 12 field bytes lie
 * at file offset h->pmap_offset - 12), checked as qibl_asset_open checks them. *out = the whole
 * image's view with points NULL (rows stream in: qibl_pmap_row_view).
 * Formats: none (the fields are little-endian u32; the points, Q16.16, are not read). Bound: exact.
 * Errors, in this order: QIBL_E_NULL_POINTER (h, fields or out NULL), QIBL_E_ASSET_MISSING_CHUNK (no
 * PMAP), QIBL_E_ASSET_HEAD_SHORT (n < 12), QIBL_E_ASSET_BAD_DIMENSIONS, QIBL_E_ASSET_MISMATCH (not
 * SHMP's width and height), QIBL_E_ASSET_BAD_FLAGS.
 * On failure: nothing is written (*out untouched). */
QIBL_NODISCARD qibl_status_t qibl_asset_head_pmap(const qibl_asset_head_t *h, const void *fields, size_t n, qibl_pmap_t *out);

/* The Y LUT of an opened head: payload holds the n >= h->ylut_size bytes loaded from
 * h->ylut_offset (the whole YLUT payload), checked as qibl_asset_open checks them; *out's values
 * point into payload (which must outlive it) and out->size covers them.
 * Formats: none (fields little-endian u32; the values, Q2.14, are not read). Bound: exact.
 * Errors, in this order: QIBL_E_NULL_POINTER (h, payload or out NULL), QIBL_E_ASSET_MISSING_CHUNK
 * (no YLUT), QIBL_E_ASSET_HEAD_SHORT (n < ylut_size), QIBL_E_ASSET_BAD_DIMENSIONS, QIBL_E_ASSET_BAD_K,
 * QIBL_E_ASSET_MISMATCH (k below SHMP's), QIBL_E_ASSET_BAD_FLAGS, QIBL_E_ASSET_CHUNK_SIZE (ylut_size
 * other than 12 + 12 N N k).
 * On failure: nothing is written (*out untouched). */
QIBL_NODISCARD qibl_status_t qibl_asset_head_ylut(const qibl_asset_head_t *h, const void *payload, size_t n, qibl_ylut_t *out);

/* Typed views of the known chunks of a validated asset (SHMP, PMAP, YLUT).
 * Formats: none (views: params Q8.24, points Q16.16, LUT values Q2.14 stay little-endian bytes).
 * Bound: exact.
 * Errors, in this order: QIBL_E_NULL_POINTER (a or out NULL), QIBL_E_ASSET_MISSING_CHUNK.
 * On failure: nothing is written (*out untouched). */
QIBL_NODISCARD qibl_status_t qibl_asset_shmaps(const qibl_asset_t *a, qibl_shmaps_t *out);
QIBL_NODISCARD qibl_status_t qibl_asset_pmap(const qibl_asset_t *a, qibl_pmap_t *out);
QIBL_NODISCARD qibl_status_t qibl_asset_ylut(const qibl_asset_t *a, qibl_ylut_t *out);
/* The unshadowed maps (SHMU). qibl_asset_point_shmaps: the maps a free point light should use,
 * SHMU when present, else SHMP (older assets).
 * Formats: none (views, as qibl_asset_shmaps). Bound: exact.
 * Errors, in this order: QIBL_E_NULL_POINTER (a or out NULL), QIBL_E_ASSET_MISSING_CHUNK (no SHMU;
 * for qibl_asset_point_shmaps, neither SHMU nor SHMP).
 * On failure: nothing is written (*out untouched). */
QIBL_NODISCARD qibl_status_t qibl_asset_shmaps_unshadowed(const qibl_asset_t *a, qibl_shmaps_t *out);
QIBL_NODISCARD qibl_status_t qibl_asset_point_shmaps(const qibl_asset_t *a, qibl_shmaps_t *out);
/* The index-th chunk (0-based) of the given type, for types that may repeat (light paths).
 * Formats: none (a view). Bound: exact.
 * Errors, in this order: QIBL_E_NULL_POINTER (a or out NULL), QIBL_E_ASSET_MISSING_CHUNK (fewer
 * than index + 1 chunks of that type).
 * On failure: nothing is written (*out untouched). */
QIBL_NODISCARD qibl_status_t qibl_asset_find_nth(const qibl_asset_t *a, uint32_t type, uint32_t index, qibl_chunk_t *out);

#ifdef __cplusplus
}
#endif

#endif /* QIBL_ASSET_H */
