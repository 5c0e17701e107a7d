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
#include "qibl/shmap.h"
#include "qibl/soft.h"
#include "qibl/status.h"

/* ---- output bytes ------------------------------------------------------------------------- */

/* A case's output bytes, hashed as they are produced (SHA-256, streamed): no buffer, so a case
 * needs no memory for its output however long it is. Zero-initialise; qtool_gbuf_emit reports the hash
 * and the count. */
typedef struct qtool_gbuf {
    qtool_sha256_t sha;
    uint64_t n;  /* bytes so far */
    int started; /* sha initialised */
} qtool_gbuf;

void qtool_gbuf_bytes(qtool_gbuf *b, const void *data, size_t n);
void qtool_gbuf_u8(qtool_gbuf *b, uint32_t v);
void qtool_gbuf_u16(qtool_gbuf *b, uint32_t v);
void qtool_gbuf_u32(qtool_gbuf *b, uint32_t v);
void qtool_gbuf_s32(qtool_gbuf *b, int32_t v);
void qtool_gbuf_u64(qtool_gbuf *b, uint64_t v);
void qtool_gbuf_free(qtool_gbuf *b);

/* Emits the hash of the bytes as case name and resets b. Returns 1 if the case failed, 0 if it
 * passed. */
int qtool_gbuf_emit(const qtool_goldens_sink_t *s, const char *name, qtool_gbuf *b);

/* Emits the hash of n bytes at data as case name. Returns 1 if the case failed. */
int qtool_gcase_emit(const qtool_goldens_sink_t *s, const char *name, const void *data, size_t n);

/* Reports an error for case name ("<call>: <status text>" or "out of memory"); returns 1. */
int qtool_gcase_status_error(const qtool_goldens_sink_t *s, const char *name, const char *call, qibl_status_t st);
int qtool_gcase_oom(const qtool_goldens_sink_t *s, const char *name);

/* l = the k-coefficient light of n directional lights, dir[i] of colour rgb[i]: qibl_shlight_init,
 * then qibl_shlight_add_dir for each in order (the relight cases' suns and skies). Its status. */
qibl_status_t qtool_gcase_dir_lights(qibl_shlight_t *l, uint32_t k, uint32_t n, const qibl_q16_t (*dir)[3],
                                     const qibl_q16_t (*rgb)[3]);
/* The same for a case whose working set of bytes (held at once) could not be allocated:
 * "out of memory: needs <bytes> bytes", so that a runner can tell a case that cannot fit its
 * machine's memory from one that should have (tools/gba/run.sh). bytes 0: beyond size_t. */
int qtool_gcase_oom_size(const qtool_goldens_sink_t *s, const char *name, size_t bytes);

/* A framebuffer a case is emitted for: its name, format and transfer (the soft, raster and relight
 * groups' tables). */
typedef struct qtool_gcase_fb {
    const char *name;
    qibl_fb_format_t format;
    uint8_t srgb, dither;
    qibl_uq16_t exposure;
} qtool_gcase_fb;

/* fb's format, srgb, dither and exposure from c; the rest of fb as it was. */
void qtool_gcase_fb_set(qibl_fb_desc_t *fb, const qtool_gcase_fb *c);

/* Little-endian stores into a byte array. */
void qtool_gput_u32(uint8_t *p, uint32_t v);
void qtool_gput_s32(uint8_t *p, int32_t v);

/* Two's complement reinterpretation without implementation-defined conversion. */
int32_t qtool_gs32(uint32_t u);

/* The relight group's fixed-camera cases (cases_camera.c: relight_camera_*). Returns the number of
 * failed cases. */
int qtool_goldens_relight_camera(const qtool_goldens_sink_t *s);

/* ---- fixed-seed PRNG (splitmix64, the tests' tu_rng sequence) ------------------------------ */

typedef struct qtool_grng {
    uint64_t s;
} qtool_grng;

uint64_t qtool_grng_next(qtool_grng *r);
uint32_t qtool_grng_u32(qtool_grng *r); /* the high 32 bits of qtool_grng_next */

#endif
