/*
 * png_test.c - tools/io/png.c: the files it writes are valid PNGs (signature, chunk CRCs, zlib
 * header and Adler-32) and decode back to the exact pixels, through all five row filters. The decoder
 * here is a small inflate (stored, fixed and dynamic Huffman blocks), written from RFC 1951.
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
#include "qibl/asset.h"
#include "testutil.h"

typedef struct {
    const uint8_t *p;
    size_t n, pos; /* in bits */
} bits;

static int getbit(bits *b)
{
    if (b->pos >= b->n * 8)
        return -1;
    int v = (b->p[b->pos >> 3] >> (b->pos & 7)) & 1;
    b->pos++;
    return v;
}

static long getbits(bits *b, int n) /* LSB first */
{
    long v = 0;
    for (int i = 0; i < n; ++i) {
        int x = getbit(b);
        if (x < 0)
            return -1;
        v |= (long)x << i;
    }
    return v;
}

/* fixed Huffman literal/length symbol: codes read MSB first */
static int fixed_lit(bits *b)
{
    int code = 0;
    for (int len = 1; len <= 9; ++len) {
        int x = getbit(b);
        if (x < 0)
            return -1;
        code = (code << 1) | x;
        if (len == 7 && code <= 0x17)
            return 256 + code;
        if (len == 8 && code >= 0x30 && code <= 0xBF)
            return code - 0x30;
        if (len == 8 && code >= 0xC0 && code <= 0xC7)
            return 280 + code - 0xC0;
        if (len == 9 && code >= 0x190)
            return 144 + code - 0x190;
    }
    return -1;
}

static const int lbase[29] = {3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 15, 17, 19, 23, 27, 31, 35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258};
static const int lext[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
static const int dbase[30] = {1, 2, 3, 4, 5, 7, 9, 13, 17, 25, 33, 49, 65, 97, 129, 193, 257, 385, 513, 769, 1025, 1537, 2049, 3073, 4097, 6145, 8193, 12289, 16385, 24577};
static const int dext[30] = {0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7, 8, 8, 9, 9, 10, 10, 11, 11, 12, 12, 13, 13};

/* a canonical Huffman code for decoding (RFC 1951 3.2.2): per length the count of codes, and the
 * symbols in code order */
typedef struct {
    int count[16], sym[320];
} huff;

static int huff_build(huff *h, const int *len, int n)
{
    int offs[16];
    memset(h->count, 0, sizeof h->count);
    for (int i = 0; i < n; ++i)
        h->count[len[i]]++;
    h->count[0] = 0;
    int left = 1;
    for (int b = 1; b < 16; ++b) {
        left = left * 2 - h->count[b];
        if (left < 0)
            return -1; /* over-subscribed */
    }
    offs[1] = 0;
    for (int b = 1; b < 15; ++b)
        offs[b + 1] = offs[b] + h->count[b];
    for (int i = 0; i < n; ++i)
        if (len[i])
            h->sym[offs[len[i]]++] = i;
    return 0;
}

/* one symbol, the code read MSB first a bit at a time */
static int huff_decode(bits *b, const huff *h)
{
    int code = 0, first = 0, index = 0;
    for (int len = 1; len < 16; ++len) {
        int x = getbit(b);
        if (x < 0)
            return -1;
        code |= x;
        int c = h->count[len];
        if (code - first < c)
            return h->sym[index + code - first];
        index += c, first = (first + c) << 1, code <<= 1;
    }
    return -1;
}

/* the code-length header of a dynamic block into the two codes */
static int dynamic_codes(bits *b, huff *lit, huff *dist)
{
    static const int order[19] = {16, 17, 18, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3, 13, 2, 14, 1, 15};
    long hlit = getbits(b, 5) + 257, hdist = getbits(b, 5) + 1, hclen = getbits(b, 4) + 4;
    if (hlit > 286 || hdist > 30 || hclen < 4)
        return -1;
    int cl[19] = {0}, len[316];
    for (long i = 0; i < hclen; ++i)
        cl[order[i]] = (int)getbits(b, 3);
    huff h;
    if (huff_build(&h, cl, 19) != 0)
        return -1;
    for (long i = 0; i < hlit + hdist;) {
        int sym = huff_decode(b, &h);
        if (sym < 0)
            return -1;
        if (sym < 16) {
            len[i++] = sym;
            continue;
        }
        int rep = 0, v = 0;
        if (sym == 16) {
            if (i == 0)
                return -1;
            v = len[i - 1], rep = 3 + (int)getbits(b, 2);
        } else {
            rep = sym == 17 ? 3 + (int)getbits(b, 3) : 11 + (int)getbits(b, 7);
        }
        if (i + rep > hlit + hdist)
            return -1;
        while (rep--)
            len[i++] = v;
    }
    if (len[256] == 0)
        return -1; /* no end-of-block code */
    return huff_build(lit, len, (int)hlit) != 0 || huff_build(dist, len + hlit, (int)hdist) != 0 ? -1 : 0;
}

/* inflate a zlib stream into out (cap bytes); returns bytes written or -1 */
static long inflate_zlib(const uint8_t *z, size_t n, uint8_t *out, size_t cap)
{
    if (n < 6 || (z[0] & 15) != 8 || ((z[0] << 8) | z[1]) % 31 != 0)
        return -1;
    bits b = {z + 2, n - 6, 0};
    size_t o = 0;
    int last = 0;
    while (!last) {
        last = getbit(&b);
        long type = getbits(&b, 2);
        if (last < 0 || type < 0)
            return -1;
        if (type == 0) {
            b.pos = (b.pos + 7) & ~(size_t)7;
            long len = getbits(&b, 16), nlen = getbits(&b, 16);
            if (len < 0 || (len ^ 0xFFFF) != nlen || o + (size_t)len > cap)
                return -1;
            for (long i = 0; i < len; ++i)
                out[o++] = (uint8_t)getbits(&b, 8);
        } else if (type == 1 || type == 2) {
            huff lit, dist;
            if (type == 2 && dynamic_codes(&b, &lit, &dist) != 0)
                return -1;
            for (;;) {
                int sym = type == 1 ? fixed_lit(&b) : huff_decode(&b, &lit);
                if (sym < 0 || sym > 285)
                    return -1;
                if (sym < 256) {
                    if (o >= cap)
                        return -1;
                    out[o++] = (uint8_t)sym;
                } else if (sym == 256) {
                    break;
                } else {
                    int li = sym - 257;
                    long len = lbase[li] + getbits(&b, lext[li]);
                    long dcode = 0;
                    if (type == 2)
                        dcode = huff_decode(&b, &dist);
                    else
                        for (int i = 0; i < 5; ++i)
                            dcode = (dcode << 1) | getbit(&b);
                    if (dcode < 0)
                        return -1;
                    if (dcode > 29)
                        return -1;
                    long dist = dbase[dcode] + getbits(&b, dext[dcode]);
                    if ((size_t)dist > o || o + (size_t)len > cap)
                        return -1;
                    for (long i = 0; i < len; ++i, ++o)
                        out[o] = out[o - (size_t)dist];
                }
            }
        } else {
            return -1; /* reserved block type */
        }
    }
    /* Adler-32 of the output, big-endian after the deflate data */
    uint32_t a = 1, s2 = 0;
    for (size_t i = 0; i < o; ++i)
        a = (a + out[i]) % 65521u, s2 = (s2 + a) % 65521u;
    const uint8_t *t = z + n - 4;
    uint32_t want = (uint32_t)t[0] << 24 | (uint32_t)t[1] << 16 | (uint32_t)t[2] << 8 | t[3];
    return want == ((s2 << 16) | a) ? (long)o : -1;
}

static uint32_t be32(const uint8_t *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

static int paeth(int a, int b, int c)
{
    int p = a + b - c, pa = abs(p - a), pb = abs(p - b), pc = abs(p - c);
    return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

/* parses path, checks every chunk CRC, and decodes the RGB pixels into out (w*h*3); filters[y] (may
 * be NULL) gets each row's filter type */
static void decode_png_filters(const char *path, int w, int h, uint8_t *out, uint8_t *filters)
{
    size_t n;
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    uint8_t *d = malloc(1 << 24);
    n = fread(d, 1, 1 << 24, f);
    fclose(f);
    static const uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    assert_memory_equal(d, sig, 8);
    size_t i = 8, zn = 0;
    uint8_t *z = malloc(n);
    int seen_end = 0;
    while (i + 12 <= n) {
        uint32_t len = be32(d + i);
        assert_true(i + 12 + len <= n);
        assert_int_equal(qibl_crc32(0, d + i + 4, len + 4), be32(d + i + 8 + len));
        if (memcmp(d + i + 4, "IHDR", 4) == 0) {
            assert_int_equal(be32(d + i + 8), (uint32_t)w);
            assert_int_equal(be32(d + i + 12), (uint32_t)h);
            assert_int_equal(d[i + 16], 8);
            assert_int_equal(d[i + 17], 2);
        } else if (memcmp(d + i + 4, "IDAT", 4) == 0) {
            memcpy(z + zn, d + i + 8, len);
            zn += len;
        } else if (memcmp(d + i + 4, "IEND", 4) == 0) {
            seen_end = 1;
        }
        i += 12 + len;
    }
    assert_true(seen_end);
    size_t row = (size_t)w * 3 + 1;
    uint8_t *raw = malloc(row * (size_t)h);
    assert_int_equal(inflate_zlib(z, zn, raw, row * (size_t)h), (long)(row * (size_t)h));
    for (int y = 0; y < h; ++y) {
        const uint8_t *r = raw + (size_t)y * row;
        assert_true(r[0] <= 4); /* None, Sub, Up, Average, Paeth (PNG spec 9.2) */
        if (filters)
            filters[y] = r[0];
        uint8_t *o = out + (size_t)y * w * 3;
        const uint8_t *up = y ? o - (size_t)w * 3 : NULL;
        for (size_t x = 0; x < (size_t)w * 3; ++x) {
            int a = x >= 3 ? o[x - 3] : 0, b = up ? up[x] : 0, c = up && x >= 3 ? up[x - 3] : 0;
            int pred = r[0] == 0 ? 0 : r[0] == 1 ? a : r[0] == 2 ? b : r[0] == 3 ? (a + b) / 2 : paeth(a, b, c);
            o[x] = (uint8_t)(r[1 + x] + pred);
        }
    }
    free(raw), free(z), free(d);
}

static void decode_png(const char *path, int w, int h, uint8_t *out)
{
    decode_png_filters(path, w, h, out, NULL);
}

static void roundtrip(int w, int h, uint32_t seed, int smooth)
{
    tu_rng r = {seed};
    uint8_t *img = malloc((size_t)w * h * 3), *back = malloc((size_t)w * h * 3);
    for (size_t i = 0; i < (size_t)w * h * 3; ++i)
        img[i] = smooth ? (uint8_t)((i / 3) % (size_t)w + (i % 3) * 40) : (uint8_t)tu_u32(&r);
    char path[64], err[256];
    snprintf(path, sizeof path, "/tmp/qibl_png_test_%d.png", (int)getpid());
    assert_int_equal(qtool_png_write_rgb8(path, w, h, img, err, sizeof err), 0);
    decode_png(path, w, h, back);
    assert_memory_equal(img, back, (size_t)w * h * 3);
    remove(path);
    free(img), free(back);
}

static void test_roundtrip(void **state)
{
    (void)state;
    roundtrip(1, 1, 1, 0);
    roundtrip(7, 3, 2, 0);
    roundtrip(300, 40, 3, 0);  /* noise: mostly literals */
    roundtrip(300, 200, 4, 1); /* smooth: long matches, > 32 KiB window */
}

/* Rows are filtered adaptively (minimum sum of absolute differences): a row equal to the one above
 * takes Up, a horizontal ramp Sub, flat noise None; every filter decodes back exactly. */
static void test_adaptive_filters(void **state)
{
    (void)state;
    enum { W = 64, H = 12 };
    static uint8_t img[W * H * 3], back[W * H * 3];
    uint8_t filters[H];
    tu_rng r = {9};
    for (int x = 0; x < W * 3; ++x)
        img[x] = (uint8_t)tu_u32(&r); /* row 0: noise (the row above is zero: None or Up) */
    for (int y = 1; y < 4; ++y)       /* rows 1..3: row 0 again */
        memcpy(img + y * W * 3, img, W * 3);
    for (int y = 4; y < 8; ++y) /* rows 5 and 7: a ramp along x under a row of noise: Sub */
        for (int x = 0; x < W * 3; ++x)
            img[y * W * 3 + x] = y % 2 ? (uint8_t)((x / 3) * 3 + y * 57) : (uint8_t)tu_u32(&r);
    for (int y = 8; y < H; ++y) /* rows 8..11: a smooth 2-D field (Average or Paeth likely) */
        for (int x = 0; x < W * 3; ++x)
            img[y * W * 3 + x] = (uint8_t)((x / 3) * 2 + y * 5 + (x % 3) * 30);
    char path[64], err[256];
    snprintf(path, sizeof path, "/tmp/qibl_png_filters_%d.png", (int)getpid());
    assert_int_equal(qtool_png_write_rgb8(path, W, H, img, err, sizeof err), 0);
    decode_png_filters(path, W, H, back, filters);
    assert_memory_equal(img, back, sizeof img);
    for (int y = 1; y < 4; ++y)
        assert_int_equal(filters[y], 2); /* Up: all zero */
    for (int y = 5; y < 8; y += 2)
        assert_int_equal(filters[y], 1); /* Sub: all 3s after the first pixel */
    remove(path);
    /* random sizes and contents through every filter path */
    for (uint32_t seed = 20; seed < 26; ++seed)
        roundtrip(3 + (int)seed % 7 * 13, 2 + (int)seed % 5, seed, (int)seed % 2);
}

/* the block type (BTYPE) of the first deflate block of the first IDAT */
static int first_btype(const char *path)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    uint8_t d[64];
    size_t n = fread(d, 1, sizeof d, f);
    fclose(f);
    assert_true(n >= 8 + 25 + 8 + 3);
    assert_memory_equal(d + 8 + 25 + 4, "IDAT", 4);
    return (d[8 + 25 + 8 + 2] >> 1) & 3; /* after the 2-byte zlib header: BFINAL, then BTYPE */
}

/* Deflate writes dynamic Huffman blocks (codes made for the data) where they are smaller, and the
 * stream still decodes: a smooth picture gets a dynamic block and is far below its fixed-code size. */
static void test_dynamic_blocks(void **state)
{
    (void)state;
    enum { W = 200, H = 100 };
    static uint8_t img[W * H * 3], back[W * H * 3];
    tu_rng r = {5};
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            for (int c = 0; c < 3; ++c) /* a shaded gradient with a little noise: few distinct residuals */
                img[(y * W + x) * 3 + c] = (uint8_t)(x / 2 + y + c * 20 + (tu_u32(&r) & 3));
    char path[64], err[256];
    snprintf(path, sizeof path, "/tmp/qibl_png_dyn_%d.png", (int)getpid());
    assert_int_equal(qtool_png_write_rgb8(path, W, H, img, err, sizeof err), 0);
    assert_int_equal(first_btype(path), 2);
    decode_png(path, W, H, back);
    assert_memory_equal(img, back, sizeof img);
    remove(path);
    /* a 1x1 picture: whichever block is smaller, it decodes */
    uint8_t px[3] = {7, 7, 7}, pb[3];
    assert_int_equal(qtool_png_write_rgb8(path, 1, 1, px, err, sizeof err), 0);
    decode_png(path, 1, 1, pb);
    assert_memory_equal(px, pb, 3);
    remove(path);
}

static void test_errors_leave_no_file(void **state)
{
    (void)state;
    uint8_t px[3] = {1, 2, 3};
    char err[256];
    assert_int_equal(qtool_png_write_rgb8("/nonexistent-dir/x.png", 1, 1, px, err, sizeof err), -1);
    assert_non_null(strstr(err, "/nonexistent-dir/x.png"));
    assert_int_equal(qtool_png_write_rgb8("/tmp/qtool_bad.png", 0, 1, px, err, sizeof err), -1);
    assert_int_equal(access("/tmp/qtool_bad.png", F_OK), -1);
    assert_int_equal(access("/tmp/qtool_bad.png.tmp", F_OK), -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_roundtrip),
        cmocka_unit_test(test_adaptive_filters),
        cmocka_unit_test(test_dynamic_blocks),
        cmocka_unit_test(test_errors_leave_no_file),
    };
    return cmocka_run_group_tests_name("png", tests, NULL, NULL);
}
