/*
 * golden/cases_srgbe.c - srgbe_*: encoding of a fixed set of binary32 bit patterns (zeros,
 * subnormals on both sides of the flush threshold, powers of two and their neighbours where the
 * exponent or a code rounds over, the largest finite, Inf, NaNs with payloads) in every channel
 * combination, of random binary32 and int32 inputs at many frac_bits, and decoding of a code sweep
 * (every E with every X, plus a stride through all 2^32 codes) to binary32, Q16.16 and int32 at
 * several frac_bits. One-pixel and bulk entry points each get their own case: the speed paths of
 * the bulk functions must give the same bytes on every port too.
 */
#include "golden/casesi.h"

#include <limits.h>
#include <stdlib.h>

#include "qibl/srgbe.h"

#if QIBL_USE_SRGBE /* the group exists only when config.h builds the module */

/* binary32 bit patterns; the sign bit is added separately */
static const uint32_t f32_edges[] = {
    0x00000000u, /* +0 */
    0x00000001u, /* smallest subnormal */
    0x001FFFFFu, /* below 2^-128: flushed */
    0x00200000u, /* 2^-128: the smallest encoded value */
    0x00200001u, 0x003FFFFFu, 0x00400000u, 0x007FFFFFu, /* subnormals, E = 0 / 1 */
    0x00800000u, /* smallest normal */
    0x00800001u, 0x01000000u, 0x3E800000u, /* 0.25 */
    0x3EFFFFFFu, 0x3F000000u, 0x3F7FFFFFu, 0x3F800000u, /* 1.0 */
    0x3F800001u, 0x3FBFFFFFu, 0x3FC00000u, 0x40000000u, 0x40490FDBu, /* pi */
    0x41200000u, 0x437F0000u, /* 255 */
    0x477FFF00u, 0x4B800000u, 0x7EFFFFFFu, 0x7F000000u, 0x7F7FFFFFu, /* FLT_MAX */
    0x7F800000u, /* Inf */
    0x7F800001u, /* signalling NaN */
    0x7FC00000u, /* quiet NaN */
    0x7FFFFFFFu, /* NaN, all payload bits */
};
#define NF32 (sizeof f32_edges / sizeof f32_edges[0])

/* edge pattern i, negated when neg */
static uint32_t edge(size_t i, unsigned neg)
{
    return f32_edges[i] | (neg ? 0x80000000u : 0u);
}

static void put_code(qtool_gbuf *b, qibl_status_t st, const uint8_t c[4])
{
    qtool_gbuf_u8(b, (uint32_t)st);
    qtool_gbuf_bytes(b, c, 4);
}

/* The bulk cases run their arrays in chunks of CHUNK pixels, the inputs of each chunk made again
 * from the pixel index (or the replayed PRNG), so that a case needs memory for one chunk, not for
 * its whole array (the GBA's 256 KiB could not hold them). The bytes are those of one call over
 * the whole array: the bulk functions are per pixel, and their status is the most severe per-pixel
 * one whatever the order (srgbe.h), so the whole array's is the most severe of the chunks'. It
 * precedes the pixels in a case's bytes, so each bulk case runs its chunks twice: once for the
 * status, once for the pixels. */
enum { CHUNK = 1024 };

static unsigned severity(qibl_status_t st)
{
    switch (st) {
    case QIBL_E_SRGBE_NAN:
        return 3;
    case QIBL_E_SRGBE_INF:
        return 2;
    case QIBL_E_SRGBE_OVERFLOW:
    case QIBL_E_SRGBE_DECODE_SAT:
        return 1;
    default:
        return st == QIBL_OK ? 0 : 4; /* anything else is a failure the case records as is */
    }
}

static qibl_status_t worse(qibl_status_t a, qibl_status_t b)
{
    return severity(b) > severity(a) ? b : a;
}

/* the edge triple of pixel i (signs varied by position) */
static void edges_pixel(size_t i, uint32_t rgb[3])
{
    size_t r = i / (NF32 * NF32), g = i / NF32 % NF32, bl = i % NF32;
    rgb[0] = edge(r, (unsigned)(i & 1u));
    rgb[1] = edge(g, (unsigned)(i >> 1 & 1u));
    rgb[2] = edge(bl, (unsigned)(i % 3u == 0u));
}

/* a chunk's float triples and their codes; 0, or -1 out of memory (nothing held) */
static int chunk_buffers(uint32_t **rgb, uint8_t **codes)
{
    *rgb = malloc(sizeof **rgb * 3 * CHUNK);
    *codes = malloc(4 * CHUNK);
    if (*rgb && *codes)
        return 0;
    free(*rgb), free(*codes);
    return -1;
}

/* every triple of edge values (signs varied by position), one pixel at a time and in bulk */
static int encode_f32_edges(const qtool_goldens_sink_t *s)
{
    const size_t n = NF32 * NF32 * NF32;
    uint32_t *rgb;
    uint8_t *codes;
    qtool_gbuf b = {0};
    if (chunk_buffers(&rgb, &codes) != 0)
        return qtool_gcase_oom(s, "srgbe_encode_f32_edges");
    qibl_status_t st = QIBL_OK;
    for (size_t i0 = 0; i0 < n; i0 += CHUNK) {
        size_t m = n - i0 < CHUNK ? n - i0 : CHUNK;
        for (size_t i = 0; i < m; ++i) {
            edges_pixel(i0 + i, rgb + 3 * i);
            uint8_t c[4] = {0xA5, 0xA5, 0xA5, 0xA5};
            put_code(&b, qibl_srgbe_encode_f32(rgb + 3 * i, c), c);
        }
        st = worse(st, qibl_srgbe_encode_f32_n(rgb, m, codes));
    }
    int bad = qtool_gbuf_emit(s, "srgbe_encode_f32_edges", &b);
    qtool_gbuf_u8(&b, (uint32_t)st);
    for (size_t i0 = 0; i0 < n; i0 += CHUNK) {
        size_t m = n - i0 < CHUNK ? n - i0 : CHUNK;
        for (size_t i = 0; i < m; ++i)
            edges_pixel(i0 + i, rgb + 3 * i);
        QIBL_DROP_STATUS(qibl_srgbe_encode_f32_n(rgb, m, codes));
        qtool_gbuf_bytes(&b, codes, 4 * m);
    }
    bad += qtool_gbuf_emit(s, "srgbe_encode_f32_n_edges", &b);
    free(rgb), free(codes);
    return bad;
}

/* the next m random pixels of r: any exponent, and clusters of nearby exponents (the common case)
 * at even pixel indices (i0 + i) */
static void random_pixels(qtool_grng *r, size_t i0, size_t m, uint32_t *rgb)
{
    for (size_t i = 0; i < m; ++i) {
        uint32_t base = qtool_grng_u32(r);
        for (int c = 0; c < 3; ++c) {
            uint32_t v = qtool_grng_u32(r);
            if ((i0 + i) % 2 == 0) /* exponent within +-4 of the pixel's base */
                v = (v & 0x807FFFFFu) | (((base >> 23 & 0xFFu) + (v >> 23 & 7u) - 4u) & 0xFFu) << 23;
            rgb[3 * i + (size_t)c] = v;
        }
    }
}

/* random bit patterns, one pixel at a time and in bulk */
static int encode_f32_random(const qtool_goldens_sink_t *s)
{
    enum { N = 20000 };
    uint32_t *rgb;
    uint8_t *codes;
    qtool_gbuf b = {0};
    if (chunk_buffers(&rgb, &codes) != 0)
        return qtool_gcase_oom(s, "srgbe_encode_f32_random");
    qtool_grng r = {0x5E};
    qibl_status_t st = QIBL_OK;
    for (size_t i0 = 0; i0 < N; i0 += CHUNK) {
        size_t m = N - i0 < CHUNK ? N - i0 : CHUNK;
        random_pixels(&r, i0, m, rgb);
        for (size_t i = 0; i < m; ++i) {
            uint8_t c[4];
            put_code(&b, qibl_srgbe_encode_f32(rgb + 3 * i, c), c);
        }
        st = worse(st, qibl_srgbe_encode_f32_n(rgb, m, codes));
    }
    int bad = qtool_gbuf_emit(s, "srgbe_encode_f32_random", &b);
    qtool_gbuf_u8(&b, (uint32_t)st);
    r.s = 0x5E; /* the same pixels again */
    for (size_t i0 = 0; i0 < N; i0 += CHUNK) {
        size_t m = N - i0 < CHUNK ? N - i0 : CHUNK;
        random_pixels(&r, i0, m, rgb);
        QIBL_DROP_STATUS(qibl_srgbe_encode_f32_n(rgb, m, codes));
        qtool_gbuf_bytes(&b, codes, 4 * m);
    }
    bad += qtool_gbuf_emit(s, "srgbe_encode_f32_n_random", &b);
    free(rgb), free(codes);
    return bad;
}

/* int32 channels at frac_bits across the whole range, one pixel, Q16 and bulk */
static int encode_s32(const qtool_goldens_sink_t *s)
{
    static const int32_t ev[] = {0, 1, -1, 2, 127, 255, 256, 65535, 65536, -65536, 0x3FFFFFFF, 0x40000000,
                                 INT32_MAX, INT32_MIN, INT32_MIN + 1, -0x40000000};
    static const int fracs[] = {-300, -128, -100, -98, -97, -96, -64, -31, -16, -1, 0, 1,
                                12,   16,   24,   31,  32,  40,  64,  100, 149, 150, 151, 300};
    enum { NE = sizeof ev / sizeof ev[0], NFR = sizeof fracs / sizeof fracs[0], NR = 2000 };
    qtool_gbuf b = {0}, bq = {0};
    qtool_grng r = {0x532};
    int32_t *rgb = malloc(sizeof *rgb * 3 * (NE * NE * NE + NR));
    uint8_t *codes = malloc(4 * (size_t)(NE * NE * NE + NR));
    if (rgb == NULL || codes == NULL) {
        free(rgb), free(codes);
        return qtool_gcase_oom(s, "srgbe_encode_s32");
    }
    size_t n = 0;
    for (int i = 0; i < NE * NE * NE; ++i, ++n)
        rgb[3 * n] = ev[i / (NE * NE)], rgb[3 * n + 1] = ev[i / NE % NE], rgb[3 * n + 2] = ev[i % NE];
    for (int i = 0; i < NR; ++i, ++n)
        for (int c = 0; c < 3; ++c) {
            uint32_t v = qtool_grng_u32(&r);
            rgb[3 * n + (size_t)c] = qtool_gs32(v >> (qtool_grng_u32(&r) % 32u));
        }
    for (int f = 0; f < NFR; ++f) {
        for (size_t i = 0; i < n; ++i) {
            uint8_t c[4];
            put_code(&b, qibl_srgbe_encode_s32(rgb + 3 * i, fracs[f], c), c);
        }
        qtool_gbuf_u8(&bq, (uint32_t)qibl_srgbe_encode_s32_n(rgb, n, fracs[f], codes));
        qtool_gbuf_bytes(&bq, codes, 4 * n);
    }
    for (size_t i = 0; i < n; ++i) {
        uint8_t c[4];
        put_code(&b, qibl_srgbe_encode_q16(rgb + 3 * i, c), c);
    }
    qtool_gbuf_u8(&bq, (uint32_t)qibl_srgbe_encode_q16_n(rgb, n, codes));
    qtool_gbuf_bytes(&bq, codes, 4 * n);
    int bad = qtool_gbuf_emit(s, "srgbe_encode_s32", &b);
    bad += qtool_gbuf_emit(s, "srgbe_encode_s32_n", &bq);
    free(rgb), free(codes);
    return bad;
}

/* code i of the sweep: every E with every X in R (G, B derived) for i < 2^16, then a golden-ratio
 * stride through 2^32 */
enum { DEC_NE = 256 * 256, DEC_NS = 16384, DEC_N = DEC_NE + DEC_NS };

static void sweep_code(uint32_t i, uint8_t c[4])
{
    if (i < DEC_NE) {
        c[0] = (uint8_t)i, c[1] = (uint8_t)(255u - (i & 0xFFu)), c[2] = (uint8_t)((i & 0xFFu) ^ 0x55u);
        c[3] = (uint8_t)(i >> 8);
    } else {
        qtool_gput_u32(c, (i - DEC_NE) * 0x9E3779B9u);
    }
}

/* which bulk decoder a pass runs */
typedef enum { DEC_F32, DEC_Q16, DEC_S32 } dec_kind;

static qibl_status_t decode_chunk(dec_kind k, const uint8_t *codes, size_t m, int frac, uint32_t *out)
{
    int32_t *io = (int32_t *)out;
    return k == DEC_F32 ? qibl_srgbe_decode_f32_n(codes, m, out)
         : k == DEC_Q16 ? qibl_srgbe_decode_q16_n(codes, m, io)
                        : qibl_srgbe_decode_s32_n(codes, m, frac, io);
}

/* one bulk decode over the whole sweep, in chunks: its status, then every step-th output word
 * (counted over the whole array) */
static void decode_bulk(qtool_gbuf *b, dec_kind k, int frac, size_t step, uint8_t *codes, uint32_t *out)
{
    qibl_status_t st = QIBL_OK;
    for (int pass = 0; pass < 2; ++pass) {
        if (pass == 1)
            qtool_gbuf_u8(b, (uint32_t)st);
        for (size_t i0 = 0; i0 < DEC_N; i0 += CHUNK) {
            size_t m = DEC_N - i0 < CHUNK ? DEC_N - i0 : CHUNK;
            for (size_t i = 0; i < m; ++i)
                sweep_code((uint32_t)(i0 + i), codes + 4 * i);
            qibl_status_t cs = decode_chunk(k, codes, m, frac, out);
            if (pass == 0) {
                st = worse(st, cs);
                continue;
            }
            size_t w0 = 3 * i0, first = (w0 + step - 1) / step * step;
            for (size_t w = first; w < w0 + 3 * m; w += step)
                qtool_gbuf_u32(b, out[w - w0]);
        }
    }
}

/* the sweep decoded to binary32, Q16.16 and int32 at several frac_bits, one pixel and in bulk */
static int decode_sweep(const qtool_goldens_sink_t *s)
{
    static const int fracs[] = {-140, -20, 0, 8, 16, 30, 31, 40, 160};
    uint8_t *codes = malloc(4 * (size_t)CHUNK);
    uint32_t *out = malloc(sizeof *out * 3 * (size_t)CHUNK);
    qtool_gbuf b = {0}, bn = {0};
    if (codes == NULL || out == NULL) {
        free(codes), free(out);
        return qtool_gcase_oom(s, "srgbe_decode");
    }
    /* binary32: every code */
    for (uint32_t i = 0; i < DEC_N; ++i) {
        uint8_t c[4];
        uint32_t v[3] = {0xA5A5A5A5u, 0xA5A5A5A5u, 0xA5A5A5A5u};
        sweep_code(i, c);
        qtool_gbuf_u8(&b, (uint32_t)qibl_srgbe_decode_f32(c, v));
        for (int k = 0; k < 3; ++k)
            qtool_gbuf_u32(&b, v[k]);
    }
    decode_bulk(&bn, DEC_F32, 0, 1, codes, out);
    int bad = qtool_gbuf_emit(s, "srgbe_decode_f32", &b);
    bad += qtool_gbuf_emit(s, "srgbe_decode_f32_n", &bn);
    /* Q16.16 and int32 at several frac_bits: every 5th code (every E, most X) */
    for (uint32_t i = 0; i < DEC_N; i += 5) {
        uint8_t c[4];
        int32_t v[3];
        sweep_code(i, c);
        qtool_gbuf_u8(&b, (uint32_t)qibl_srgbe_decode_q16(c, v));
        for (int k = 0; k < 3; ++k)
            qtool_gbuf_s32(&b, v[k]);
        for (size_t f = 0; f < sizeof fracs / sizeof fracs[0]; ++f) {
            qtool_gbuf_u8(&b, (uint32_t)qibl_srgbe_decode_s32(c, fracs[f], v));
            for (int k = 0; k < 3; ++k)
                qtool_gbuf_s32(&b, v[k]);
        }
    }
    decode_bulk(&bn, DEC_Q16, 0, 1, codes, out);
    for (size_t f = 0; f < sizeof fracs / sizeof fracs[0]; ++f)
        decode_bulk(&bn, DEC_S32, fracs[f], 7, codes, out);
    bad += qtool_gbuf_emit(s, "srgbe_decode_s32", &b);
    bad += qtool_gbuf_emit(s, "srgbe_decode_s32_n", &bn);
    free(codes), free(out);
    return bad;
}

int qtool_goldens_srgbe(const qtool_goldens_sink_t *s)
{
    return encode_f32_edges(s) + encode_f32_random(s) + encode_s32(s) + decode_sweep(s);
}

#else
typedef int qtool_goldens_srgbe_off; /* ISO C wants a declaration in every file */
#endif /* QIBL_USE_SRGBE */
