/*
 * io/asset_write.h - hosted writer of the qibl asset container (layout: core/include/qibl/asset.h).
 *
 * A builder collects chunks (type + payload bytes, in the order added) and serialises them: header,
 * chunk table, then each payload at the next multiple of 4 (zero padding), all integers
 * little-endian whatever the host, table and payload CRC-32s filled in. The payload helpers turn
 * plain arrays into SHMP/PMAP/YLUT payloads; they check only what memory safety needs (sizes that
 * fit), so tests can build payloads the core must reject. qtool_asset_write_file validates the
 * result with qibl_asset_open before anything touches the disk.
 *
 * Errors: every function returns 0 or -1; on -1 a one-line reason is in b->err (for the file
 * functions it names the file). Usage:
 *
 *   qtool_asset_builder b;
 *   qtool_asset_builder_init(&b);
 *   if (qtool_asset_add_shmp(&b, w, h, k, 3, scale, bias, planes) != 0 ||
 *       qtool_asset_write_file(&b, "out.qibl", 1) != 0)
 *       fprintf(stderr, "%s\n", b.err);
 *   qtool_asset_builder_free(&b);
 */
#ifndef QTOOL_IO_ASSET_WRITE_H
#define QTOOL_IO_ASSET_WRITE_H

#include <stddef.h>
#include <stdint.h>

#include "qibl/asset.h"

typedef struct qtool_asset_builder {
    uint32_t count;
    struct {
        uint32_t type;
        uint8_t *data; /* owned (malloc), NULL when size is 0 */
        size_t size;
    } chunks[QIBL_ASSET_MAX_CHUNKS];
    char err[320];
} qtool_asset_builder;

void qtool_asset_builder_init(qtool_asset_builder *b);
/* qibl_asset_open for hosted tools: the same checks, statuses and views, the CRCs by the core's
 * slicing-by-8 path (qibl_asset_open_crc_table) with one 8 KiB table made once per process
 * (thread-safe), several times faster per byte than the nibble table on multi-megabyte assets. */
qibl_status_t qtool_asset_open(qibl_asset_t *out, const void *bytes, size_t n);

/* Frees every payload; the builder is empty (init state) afterwards. */
void qtool_asset_builder_free(qtool_asset_builder *b);

/* Appends a chunk with a copy of size bytes of data (data may be NULL when size is 0).
 * Fails if the builder already holds QIBL_ASSET_MAX_CHUNKS chunks, size > UINT32_MAX, or no memory. */
int qtool_asset_builder_add(qtool_asset_builder *b, uint32_t type, const void *data, size_t size);
/* Same, taking ownership of a malloc'ed buffer (freed by the builder, also when this fails). */
int qtool_asset_builder_take(qtool_asset_builder *b, uint32_t type, uint8_t *data, size_t size);

/* Payload builders: *out gets a malloc'ed payload (caller frees), *size its length.
 *   SHMP: scale[i * channels + ch] and bias[...] in Q8.24 for the k * channels (map, channel)
 *         pairs; planes holds the k * channels planes of w * h bytes back to back, plane index
 *         i * channels + ch (rows top first).
 *   PMAP: xyz holds w * h points of 3 Q16.16 values, row-major.
 *   YLUT: values holds 6 * face_size^2 * k Q2.14 values, [face][v][u][i], faces +X -X +Y -Y +Z -Z.
 * Fail (b->err) only if the size does not fit 32 bits or no memory. */
int qtool_asset_shmp_payload(qtool_asset_builder *b, uint32_t w, uint32_t h, uint32_t k, uint32_t channels,
                            const int32_t *scale, const int32_t *bias, const uint8_t *planes,
                            uint8_t **out, size_t *size);
int qtool_asset_pmap_payload(qtool_asset_builder *b, uint32_t w, uint32_t h, const int32_t *xyz,
                            uint8_t **out, size_t *size);
int qtool_asset_ylut_payload(qtool_asset_builder *b, uint32_t face_size, uint32_t k, const int16_t *values,
                            uint8_t **out, size_t *size);

/* SHMP in a chosen layout (QIBL_SHMAPS_PLANAR or QIBL_SHMAPS_INTERLEAVED, shmaps.h): planes are
 * given planar as above and rewritten by qibl_shmaps_interleave for the interleaved layout (flags
 * QIBL_SHMP_FLAG_INTERLEAVED). Fails also for an unknown layout, or k/channels/sizes the core's
 * conversion refuses. */
int qtool_asset_shmp_payload_layout(qtool_asset_builder *b, uint32_t w, uint32_t h, uint32_t k, uint32_t channels,
                                   const int32_t *scale, const int32_t *bias, const uint8_t *planes, uint32_t layout,
                                   uint8_t **out, size_t *size);

/* Payload builder + qtool_asset_builder_take in one call. */
int qtool_asset_add_shmp(qtool_asset_builder *b, uint32_t w, uint32_t h, uint32_t k, uint32_t channels,
                        const int32_t *scale, const int32_t *bias, const uint8_t *planes);
/* SHMU (unshadowed transfer): the SHMP payload layout under its own chunk type */
int qtool_asset_add_shmu(qtool_asset_builder *b, uint32_t w, uint32_t h, uint32_t k, uint32_t channels,
                        const int32_t *scale, const int32_t *bias, const uint8_t *planes);
int qtool_asset_add_shmp_layout(qtool_asset_builder *b, uint32_t w, uint32_t h, uint32_t k, uint32_t channels,
                               const int32_t *scale, const int32_t *bias, const uint8_t *planes, uint32_t layout);
int qtool_asset_add_pmap(qtool_asset_builder *b, uint32_t w, uint32_t h, const int32_t *xyz);
int qtool_asset_add_ylut(qtool_asset_builder *b, uint32_t face_size, uint32_t k, const int16_t *values);

/* Serialises to a malloc'ed buffer (*out, *size; caller frees). No validation beyond the
 * container limits (1..QIBL_ASSET_MAX_CHUNKS chunks, total size fits 32 bits). */
int qtool_asset_serialize(qtool_asset_builder *b, uint8_t **out, size_t *size);

/* Serialises, validates with qibl_asset_open and writes path atomically (io/atomic.h: an
 * exclusively created temporary file, flushed, fsync'ed if do_fsync, renamed over path; a path
 * that is not a regular file is refused); on any failure path is left as it was. */
int qtool_asset_write_file(qtool_asset_builder *b, const char *path, int do_fsync);

/* Little-endian stores (the writer's counterparts of qibl_load_*le). */
void qtool_store_u32le(uint8_t *p, uint32_t v);
void qtool_store_s32le(uint8_t *p, int32_t v);
void qtool_store_s16le(uint8_t *p, int16_t v);

#endif
