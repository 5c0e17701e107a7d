/*
 * golden/casesi.h - helpers shared by the cases_<module>.c files (not for other users): a growable
 * little-endian byte buffer, the fixed-seed PRNG, status checks that report through the sink.
 */
#ifndef QTOOL_GOLDEN_CASESI_H
#define QTOOL_GOLDEN_CASESI_H

#include <stddef.h>
#include <stdint.h>

#include "golden/cases.h"
#include "io/sha256.h"
#include "qibl/status.h"

/* ---- output bytes ------------------------------------------------------------------------- */

/* A case's output bytes, hashed as they are produced (SHA-256, streamed): no buffer, so a case
 * needs no memory for its output however long it is. Zero-initialise; gbuf_emit reports the hash
 * and the count. */
typedef struct gbuf {
    qtool_sha256_t sha;
    uint64_t n;  /* bytes so far */
    int started; /* sha initialised */
} gbuf;

void gbuf_bytes(gbuf *b, const void *data, size_t n);
void gbuf_u8(gbuf *b, uint32_t v);
void gbuf_u16(gbuf *b, uint32_t v);
void gbuf_u32(gbuf *b, uint32_t v);
void gbuf_s32(gbuf *b, int32_t v);
void gbuf_u64(gbuf *b, uint64_t v);
void gbuf_free(gbuf *b);

/* Emits the hash of the bytes as case name and resets b. Returns 1 if the case failed, 0 if it
 * passed. */
int gbuf_emit(const qtool_goldens_sink_t *s, const char *name, gbuf *b);

/* Emits the hash of n bytes at data as case name. Returns 1 if the case failed. */
int gcase_emit(const qtool_goldens_sink_t *s, const char *name, const void *data, size_t n);

/* Reports an error for case name ("<call>: <status text>" or "out of memory"); returns 1. */
int gcase_status_error(const qtool_goldens_sink_t *s, const char *name, const char *call, qibl_status_t st);
int gcase_oom(const qtool_goldens_sink_t *s, const char *name);
/* The same for a case whose working set of bytes (held at once) could not be allocated:
 * "out of memory: needs <bytes> bytes", so that a runner can tell a case that cannot fit its
 * machine's memory from one that should have (tools/gba/run.sh). bytes 0: beyond size_t. */
int gcase_oom_size(const qtool_goldens_sink_t *s, const char *name, size_t bytes);

/* Little-endian stores into a byte array. */
void gput_u32(uint8_t *p, uint32_t v);
void gput_s32(uint8_t *p, int32_t v);

/* Two's complement reinterpretation without implementation-defined conversion. */
int32_t gs32(uint32_t u);

/* ---- fixed-seed PRNG (splitmix64, the tests' tu_rng sequence) ------------------------------ */

typedef struct grng {
    uint64_t s;
} grng;

uint64_t grng_next(grng *r);
uint32_t grng_u32(grng *r); /* the high 32 bits of grng_next */

#endif
