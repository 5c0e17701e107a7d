/*
 * io/zlib.h - the tools' one zlib codec (RFC 1950 around RFC 1951), shared by the PNG and OpenEXR
 * readers and writers. Internal to tools/io. Hosted.
 */
#ifndef QTOOL_IO_ZLIB_H
#define QTOOL_IO_ZLIB_H

#include <stddef.h>
#include <stdint.h>

/* Inflates the zlib stream z[0 .. n) into out (cap bytes, the caller's), checking the header and the
 * Adler-32. A stream that would inflate past cap stops there ("inflates past the expected size").
 * 0 with *outn set (<= cap), or -1 with *why a short reason; out may be partly written on failure.
 * Time: linear in n plus cap. */
int qtool_zlib_inflate(const uint8_t *z, size_t n, uint8_t *out, size_t cap, size_t *outn, const char **why);

/* Deflates in[0 .. n) into a malloc'ed zlib stream (*out, *outn; the caller frees): io/png.c's
 * encoder (LZ77 over hash chains, dynamic or fixed Huffman blocks). 0, or -1 (out of memory). */
int qtool_zlib_deflate(const uint8_t *in, size_t n, uint8_t **out, size_t *outn);

#endif
