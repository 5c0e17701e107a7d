/*
 * io/sha256.h - SHA-256 (FIPS 180-4), incremental and one-shot. Hosted; used by the golden tests
 * to hash output bytes, so a golden is one 64-character line instead of a reference image.
 */
#ifndef QTOOL_IO_SHA256_H
#define QTOOL_IO_SHA256_H

#include <stddef.h>
#include <stdint.h>

typedef struct qtool_sha256 {
    uint32_t h[8];     /* chaining state */
    uint64_t bytes;    /* message length so far */
    uint8_t buf[64];   /* partial block */
    size_t fill;       /* bytes in buf, 0..63 */
} qtool_sha256_t;

void qtool_sha256_init(qtool_sha256_t *s);

/* Appends n bytes (any n, any number of calls; data may be NULL when n == 0). */
void qtool_sha256_update(qtool_sha256_t *s, const void *data, size_t n);

/* Pads, writes the 32-byte digest and leaves s needing qtool_sha256_init before reuse. */
void qtool_sha256_final(qtool_sha256_t *s, uint8_t out[32]);

/* The 32-byte digest as 64 lowercase hex digits plus a terminating NUL. */
void qtool_sha256_to_hex(const uint8_t digest[32], char out[65]);

/* One shot: lowercase hex digest of n bytes at data. */
void qtool_sha256_hex(const void *data, size_t n, char out[65]);

#endif
