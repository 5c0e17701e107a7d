/*
 * pngread_test.c - tools/io/pngread.c against hostile input: PNGs built here chunk by chunk (CRCs
 * from qibl_crc32, zlib streams of stored or fixed-Huffman blocks written bit by bit), plus the
 * hostile files of tests/fileutil.h. An IHDR claiming more than QIBL_PNG_MAX_PIXELS is refused
 * before any image data is collected; a zlib stream inflating past what IHDR implies stops there
 * (a 261 KB file used to inflate to 264 MB before its size was checked); a truncated file is named.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "io/png.h"
#include "qibl/asset.h" /* qibl_crc32 */
#include "fileutil.h"

typedef struct {
    uint8_t *b;
    size_t n, cap;
    uint32_t bitbuf;
    int nbits;
} out_t;

static void put(out_t *o, const void *p, size_t k)
{
    if (o->n + k > o->cap) {
        o->cap = (o->n + k) * 2 + 256;
        o->b = realloc(o->b, o->cap);
        assert_non_null(o->b);
    }
    memcpy(o->b + o->n, p, k);
    o->n += k;
}

static void put32(out_t *o, uint32_t v)
{
    uint8_t b[4] = {(uint8_t)(v >> 24), (uint8_t)(v >> 16), (uint8_t)(v >> 8), (uint8_t)v};
    put(o, b, 4);
}

static void chunk(out_t *o, const char *type, const uint8_t *data, uint32_t n)
{
    put32(o, n);
    size_t at = o->n;
    put(o, type, 4);
    if (n)
        put(o, data, n);
    put32(o, qibl_crc32(0, o->b + at, 4 + (size_t)n));
}

static void sig_ihdr(out_t *o, uint32_t w, uint32_t h)
{
    static const uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    put(o, sig, 8);
    uint8_t ihdr[13] = {(uint8_t)(w >> 24), (uint8_t)(w >> 16), (uint8_t)(w >> 8), (uint8_t)w,
                        (uint8_t)(h >> 24), (uint8_t)(h >> 16), (uint8_t)(h >> 8), (uint8_t)h, 8, 2, 0, 0, 0};
    chunk(o, "IHDR", ihdr, 13);
}

/* deflate bits, LSB first; Huffman codes go MSB first */
static void bits(out_t *z, uint32_t v, int n)
{
    for (int i = 0; i < n; ++i) {
        z->bitbuf |= ((v >> i) & 1u) << z->nbits;
        if (++z->nbits == 8) {
            uint8_t c = (uint8_t)z->bitbuf;
            put(z, &c, 1);
            z->bitbuf = 0, z->nbits = 0;
        }
    }
}

static void code(out_t *z, uint32_t c, int n)
{
    for (int i = n - 1; i >= 0; --i)
        bits(z, (c >> i) & 1u, 1);
}

static void flush_bits(out_t *z)
{
    if (z->nbits)
        bits(z, 0, 8 - z->nbits);
}

static uint32_t adler(const uint8_t *p, size_t n)
{
    uint32_t a = 1, b = 0;
    for (size_t i = 0; i < n; ++i)
        a = (a + p[i]) % 65521u, b = (b + a) % 65521u;
    return b << 16 | a;
}

/* the zlib stream of raw (filter bytes included) as one stored block */
static void zlib_stored(out_t *z, const uint8_t *raw, uint16_t n)
{
    uint8_t h[7] = {0x78, 0x01, 1, (uint8_t)n, (uint8_t)(n >> 8), (uint8_t)~n, (uint8_t)(~n >> 8)};
    put(z, h, 7);
    put(z, raw, n);
    put32(z, adler(raw, n));
}

/* a fixed-Huffman block: one literal 0, then `runs` copies of (length 258, distance 1): inflates to
 * 1 + 258 runs zero bytes from about runs bytes */
static void zlib_bomb(out_t *z, size_t runs)
{
    uint8_t h[2] = {0x78, 0x01};
    put(z, h, 2);
    bits(z, 1, 1), bits(z, 1, 2); /* last block, fixed Huffman */
    code(z, 0x30, 8);             /* literal 0 */
    for (size_t i = 0; i < runs; ++i) {
        code(z, 0xC0 + (285 - 280), 8); /* length 258 */
        code(z, 0, 5);                  /* distance code 0: 1 */
    }
    code(z, 0, 7); /* end of block */
    flush_bits(z);
    put32(z, 0); /* an Adler-32 that is never reached */
}

static int decode(const out_t *o, int *w, int *h, uint8_t **rgb, char *err, size_t errlen)
{
    int frames;
    return qtool_png_decode_rgb8(o->b, o->n, w, h, &frames, rgb, err, errlen);
}

static void decode_fails(const out_t *o, const char *needle)
{
    int w = -7, h = -7;
    uint8_t *rgb = NULL;
    char err[256] = "";
    assert_int_equal(decode(o, &w, &h, &rgb, err, sizeof err), -1);
    assert_true(w == -7 && h == -7 && rgb == NULL);
    assert_null(strchr(err, '\n'));
    if (!strstr(err, needle))
        fail_msg("error '%s' does not mention '%s'", err, needle);
}

/* a valid 2 x 2 RGB PNG (stored deflate) */
static void small_png(out_t *o)
{
    sig_ihdr(o, 2, 2);
    const uint8_t raw[14] = {0, 1, 2, 3, 4, 5, 6, 0, 7, 8, 9, 10, 11, 12};
    out_t z = {0};
    zlib_stored(&z, raw, sizeof raw);
    chunk(o, "IDAT", z.b, (uint32_t)z.n);
    chunk(o, "IEND", NULL, 0);
    free(z.b);
}

/* ---- hostile files ---------------------------------------------------------------------------- */

static int rd_png(const char *path, char *err, size_t errlen)
{
    int w, h, fr;
    uint8_t *rgb;
    int rc = qtool_png_read_rgb8(path, &w, &h, &fr, &rgb, err, errlen);
    if (rc == 0)
        free(rgb);
    return rc;
}

/* first in the suite: it measures the peak memory */
static void test_zeros_refused_by_signature_before_reading(void **state)
{
    (void)state;
    fu_check_zeros_not_read(rd_png, (size_t)64 << 20, "bad signature", QTOOL_PNG_MAX_FILE_BYTES);
}

static void test_not_regular_files_named(void **state)
{
    (void)state;
    fu_check_not_regular(rd_png);
}

static void test_empty_and_one_byte_files_named(void **state)
{
    (void)state;
    fu_check_empty_and_one_byte(rd_png, 0x89, "too short");
}

/* IHDR's dimensions are checked before any IDAT is collected or inflated */
static void test_lying_ihdr_refused(void **state)
{
    (void)state;
    static const uint32_t dims[][2] = {{65535, 65535}, {8193, 8192}, {1, 65535 + 1u}};
    for (size_t i = 0; i < 3; ++i) {
        out_t o = {0};
        sig_ihdr(&o, dims[i][0], dims[i][1]);
        out_t z = {0};
        zlib_bomb(&z, 4);
        chunk(&o, "IDAT", z.b, (uint32_t)z.n);
        chunk(&o, "IEND", NULL, 0);
        decode_fails(&o, i < 2 ? "QIBL_PNG_MAX_PIXELS" : "bad image size");
        free(o.b), free(z.b);
    }
}

/* 16 x 16 RGB implies (3 16 + 1) 16 = 784 bytes; a 4 KB stream that inflates to 1 MB stops at
 * byte 784 (the old reader inflated all of it, then compared sizes) */
static void test_inflate_capped_at_ihdr_size(void **state)
{
    (void)state;
    out_t o = {0}, z = {0};
    sig_ihdr(&o, 16, 16);
    zlib_bomb(&z, 4096);
    chunk(&o, "IDAT", z.b, (uint32_t)z.n);
    chunk(&o, "IEND", NULL, 0);
    decode_fails(&o, "inflates past");
    free(o.b), free(z.b);
    /* exactly the size IHDR implies decodes (10 literals + 3 runs of 258 = 784) */
    o = (out_t){0}, z = (out_t){0};
    sig_ihdr(&o, 16, 16);
    uint8_t hz[2] = {0x78, 0x01};
    put(&z, hz, 2);
    bits(&z, 1, 1), bits(&z, 1, 2);
    for (int i = 0; i < 10; ++i)
        code(&z, 0x30, 8); /* 10 literal zeros */
    for (int i = 0; i < 3; ++i)
        code(&z, 0xC0 + 5, 8), code(&z, 0, 5);
    code(&z, 0, 7);
    flush_bits(&z);
    uint8_t *zeros = calloc(784, 1);
    put32(&z, adler(zeros, 784));
    chunk(&o, "IDAT", z.b, (uint32_t)z.n);
    chunk(&o, "IEND", NULL, 0);
    int w, h;
    uint8_t *rgb;
    char err[256];
    if (decode(&o, &w, &h, &rgb, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_true(w == 16 && h == 16);
    assert_memory_equal(rgb, zeros, 768);
    free(rgb), free(zeros), free(o.b), free(z.b);
}

/* a valid file decodes; every truncation of it is refused with a named reason, and from a file the
 * message names the file */
static void test_truncated_body_named(void **state)
{
    (void)state;
    out_t o = {0};
    small_png(&o);
    int w, h;
    uint8_t *rgb;
    char err[512];
    if (decode(&o, &w, &h, &rgb, err, sizeof err) != 0)
        fail_msg("%s", err);
    static const uint8_t want[12] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
    assert_memory_equal(rgb, want, 12);
    free(rgb);
    size_t full = o.n;
    for (size_t n = 0; n < full; ++n) {
        o.n = n;
        int ww = -7, hh = -7;
        uint8_t *px = NULL;
        err[0] = '\0';
        assert_int_equal(decode(&o, &ww, &hh, &px, err, sizeof err), -1);
        assert_true(ww == -7 && px == NULL && strlen(err) > 0 && !strchr(err, '\n'));
    }
    char dir[64], p[128];
    fu_tmpdir(dir);
    snprintf(p, sizeof p, "%s/cut.png", dir);
    fu_write(p, o.b, full - 1);
    fu_refused(rd_png, p, "truncated", NULL);
    unlink(p);
    rmdir(dir);
    free(o.b);
}

/* chunk types are printed as letters or in hex: a raw newline in a type cannot split the one-line
 * error (found by the fuzzer) */
static void test_chunk_type_printed_safely(void **state)
{
    (void)state;
    static const uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    out_t o = {0};
    put(&o, sig, 8);
    chunk(&o, "a\nb\x01", (const uint8_t *)"", 0);
    decode_fails(&o, "first chunk is 0x610a6201, not IHDR");
    o.n = 0;
    small_png(&o);
    o.b[8 + 25 + 4 + 1] = '\n'; /* IDAT's type, its CRC now wrong */
    decode_fails(&o, "CRC mismatch in chunk 0x490a4154");
    free(o.b);
    o = (out_t){0};
    sig_ihdr(&o, 2, 2);
    chunk(&o, "QDAT", (const uint8_t *)"x", 1);
    decode_fails(&o, "unknown critical chunk QDAT");
    free(o.b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_zeros_refused_by_signature_before_reading),
        cmocka_unit_test(test_not_regular_files_named),
        cmocka_unit_test(test_empty_and_one_byte_files_named),
        cmocka_unit_test(test_lying_ihdr_refused),
        cmocka_unit_test(test_inflate_capped_at_ihdr_size),
        cmocka_unit_test(test_truncated_body_named),
        cmocka_unit_test(test_chunk_type_printed_safely),
    };
    return cmocka_run_group_tests_name("pngread", tests, NULL, NULL);
}
