/*
 * io/png.c - PNG writer: IHDR, one IDAT holding a zlib stream (one deflate block with the fixed
 * Huffman code of RFC 1951 over LZ77 matches from hash chains), IEND. Sub filter on every row.
 * No dynamic Huffman tables: a few tens of percent larger than zlib -9, far smaller than stored.
 */
#include "io/png.h"
#include "io/atomic.h"

#include "qibl/asset.h" /* qibl_crc32: the same CRC-32 as PNG */

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void put32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v >> 24), p[1] = (uint8_t)(v >> 16), p[2] = (uint8_t)(v >> 8), p[3] = (uint8_t)v;
}

static int write_chunk(FILE *f, const char *type, const uint8_t *data, size_t n)
{
    uint8_t hdr[8];
    put32(hdr, (uint32_t)n);
    memcpy(hdr + 4, type, 4);
    uint32_t crc = qibl_crc32(qibl_crc32(0, (const uint8_t *)type, 4), data, n);
    uint8_t tail[4];
    put32(tail, crc);
    return fwrite(hdr, 1, 8, f) == 8 && (n == 0 || fwrite(data, 1, n, f) == n) && fwrite(tail, 1, 4, f) == 4 ? 0 : -1;
}

/* ---- deflate: LZ77 (hash chains, 32 KiB window) + the fixed Huffman code of RFC 1951 ---------- */

typedef struct {
    uint8_t *buf;
    size_t n, cap;
    uint32_t bits; /* pending bits, LSB first */
    int nbits;
    int oom;
} bitw;

static void bw_put(bitw *w, uint32_t v, int n) /* n <= 16 bits, LSB first */
{
    w->bits |= v << w->nbits;
    w->nbits += n;
    while (w->nbits >= 8) {
        if (w->n == w->cap) {
            size_t cap = w->cap ? w->cap * 2 : 65536;
            uint8_t *nb = realloc(w->buf, cap);
            if (!nb) {
                w->oom = 1;
                w->n = 0; /* keep going harmlessly; the caller checks oom */
            } else {
                w->buf = nb, w->cap = cap;
            }
        }
        if (w->cap)
            w->buf[w->n++] = (uint8_t)w->bits;
        w->bits >>= 8;
        w->nbits -= 8;
    }
}

static void bw_huff(bitw *w, uint32_t code, int len) /* Huffman codes go MSB first */
{
    uint32_t r = 0;
    for (int i = 0; i < len; ++i)
        r |= ((code >> i) & 1u) << (len - 1 - i);
    bw_put(w, r, len);
}

static void put_lit(bitw *w, int v)
{
    if (v < 144)
        bw_huff(w, 0x30u + (uint32_t)v, 8);
    else if (v < 256)
        bw_huff(w, 0x190u + (uint32_t)(v - 144), 9);
    else if (v < 280)
        bw_huff(w, (uint32_t)(v - 256), 7);
    else
        bw_huff(w, 0xC0u + (uint32_t)(v - 280), 8);
}

static const uint16_t len_base[29] = {3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 15, 17, 19, 23, 27, 31,
                                      35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258};
static const uint8_t len_extra[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2,
                                      3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
static const uint16_t dist_base[30] = {1, 2, 3, 4, 5, 7, 9, 13, 17, 25, 33, 49, 65, 97, 129, 193,
                                       257, 385, 513, 769, 1025, 1537, 2049, 3073, 4097, 6145, 8193,
                                       12289, 16385, 24577};
static const uint8_t dist_extra[30] = {0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6,
                                       7, 7, 8, 8, 9, 9, 10, 10, 11, 11, 12, 12, 13, 13};

static void put_match(bitw *w, int len, int dist)
{
    int i = 28;
    while (len_base[i] > len)
        --i;
    put_lit(w, 257 + i);
    bw_put(w, (uint32_t)(len - len_base[i]), len_extra[i]);
    int d = 29;
    while (dist_base[d] > dist)
        --d;
    bw_huff(w, (uint32_t)d, 5);
    bw_put(w, (uint32_t)(dist - dist_base[d]), dist_extra[d]);
}

#define HBITS 15
#define WSIZE 32768
#define MAXCHAIN 48

/* One fixed-Huffman block over the whole input. Returns 0 or -1 (out of memory). */
static int deflate_fixed(const uint8_t *in, size_t n, bitw *w)
{
    int32_t *head = malloc(sizeof(int32_t) << HBITS);
    int32_t *prev = malloc(sizeof(int32_t) * WSIZE);
    if (!head || !prev) {
        free(head), free(prev);
        return -1;
    }
    for (size_t i = 0; i < ((size_t)1 << HBITS); ++i)
        head[i] = -1;
    bw_put(w, 1, 1); /* BFINAL */
    bw_put(w, 1, 2); /* BTYPE = 01, fixed Huffman */
    size_t i = 0;
    while (i < n) {
        int best = 0, bdist = 0;
        if (i + 2 < n) {
            uint32_t h = ((uint32_t)in[i] << 10 ^ (uint32_t)in[i + 1] << 5 ^ in[i + 2]) & ((1u << HBITS) - 1);
            int32_t c = head[h];
            int chain = MAXCHAIN;
            size_t maxlen = n - i < 258 ? n - i : 258;
            while (c >= 0 && i - (size_t)c <= WSIZE - 1 && chain-- > 0) {
                size_t l = 0;
                while (l < maxlen && in[(size_t)c + l] == in[i + l])
                    ++l;
                if ((int)l > best) {
                    best = (int)l, bdist = (int)(i - (size_t)c);
                    if (l == maxlen)
                        break;
                }
                int32_t pc = prev[(size_t)c % WSIZE];
                if (pc >= c)
                    break;
                c = pc;
            }
        }
        size_t adv = best >= 3 ? (size_t)best : 1;
        if (best >= 3)
            put_match(w, best, bdist);
        else
            put_lit(w, in[i]);
        for (size_t k = 0; k < adv; ++k, ++i)
            if (i + 2 < n) {
                uint32_t h = ((uint32_t)in[i] << 10 ^ (uint32_t)in[i + 1] << 5 ^ in[i + 2]) & ((1u << HBITS) - 1);
                prev[i % WSIZE] = head[h];
                head[h] = (int32_t)i;
            }
    }
    put_lit(w, 256);
    if (w->nbits > 0)
        bw_put(w, 0, 8 - w->nbits); /* pad to a byte boundary */
    free(head), free(prev);
    return w->oom ? -1 : 0;
}

/* zlib stream of the filtered scanlines of a w x h RGB image (filter Sub on every row). */
static int zlib_rgb(int w, int h, const uint8_t *rgb, uint8_t **zout, size_t *zn)
{
    /* raw scanlines: filter byte 1 (Sub) on every row, which suits smooth images */
    size_t row = (size_t)w * 3 + 1, raw_n = row * (size_t)h;
    uint8_t *raw = malloc(raw_n);
    bitw bw = {0};
    if (!raw)
        return -1;
    for (int y = 0; y < h; ++y) {
        uint8_t *r = raw + (size_t)y * row;
        const uint8_t *s = rgb + (size_t)y * (size_t)w * 3;
        r[0] = 1;
        for (size_t x = 0; x < (size_t)w * 3; ++x)
            r[1 + x] = (uint8_t)(s[x] - (x >= 3 ? s[x - 3] : 0));
    }
    uint32_t a = 1, b = 0; /* Adler-32 of the raw scanlines */
    for (size_t i = 0; i < raw_n; ++i) {
        a += raw[i];
        if (a >= 65521u)
            a -= 65521u;
        b += a;
        if (b >= 65521u)
            b -= 65521u;
    }
    bw_put(&bw, 0x78, 8); /* zlib header: deflate, 32 KiB window; 0x7801 is a multiple of 31 */
    bw_put(&bw, 0x01, 8);
    if (deflate_fixed(raw, raw_n, &bw) != 0) {
        free(raw), free(bw.buf);
        return -1;
    }
    free(raw);
    for (int k = 3; k >= 0; --k)
        bw_put(&bw, (((b << 16) | a) >> (8 * k)) & 0xFFu, 8);
    if (bw.oom) {
        free(bw.buf);
        return -1;
    }
    *zout = bw.buf, *zn = bw.n;
    return 0;
}

/* PNG (frames == 1, delay ignored) or APNG (frames > 1: acTL, then per frame fcTL + IDAT/fdAT),
 * written atomically (io/atomic.h). */
static int write_png_frames(const char *path, int w, int h, int frames, const uint8_t *rgb, int delay_num,
                            int delay_den, char *err, size_t errlen)
{
    if (w <= 0 || h <= 0 || w > 65535 || h > 65535) {
        snprintf(err, errlen, "%s: bad image size %dx%d", path, w, h);
        return -1;
    }
    if (frames < 1 || delay_num < 0 || delay_num > 65535 || delay_den < 0 || delay_den > 65535) {
        snprintf(err, errlen, "%s: bad frame count %d or delay %d/%d", path, frames, delay_num, delay_den);
        return -1;
    }
    uint8_t ihdr[13];
    put32(ihdr, (uint32_t)w);
    put32(ihdr + 4, (uint32_t)h);
    ihdr[8] = 8, ihdr[9] = 2, ihdr[10] = 0, ihdr[11] = 0, ihdr[12] = 0; /* 8-bit RGB */

    qibl_io_atomic at;
    if (qibl_io_atomic_open(&at, path, err, errlen) != 0)
        return -1;
    FILE *f = at.f;
    static const uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    int bad = fwrite(sig, 1, 8, f) != 8 || write_chunk(f, "IHDR", ihdr, 13), oom = 0;
    uint32_t seq = 0;
    if (frames > 1) {
        uint8_t actl[8];
        put32(actl, (uint32_t)frames);
        put32(actl + 4, 0); /* loop forever */
        bad |= write_chunk(f, "acTL", actl, 8);
    }
    for (int fr = 0; fr < frames && !bad; ++fr) {
        uint8_t *z = NULL;
        size_t zn = 0;
        if (zlib_rgb(w, h, rgb + (size_t)fr * (size_t)w * (size_t)h * 3, &z, &zn) != 0) {
            oom = bad = 1;
            break;
        }
        if (frames > 1) {
            uint8_t fctl[26];
            put32(fctl, seq++);
            put32(fctl + 4, (uint32_t)w);
            put32(fctl + 8, (uint32_t)h);
            put32(fctl + 12, 0);
            put32(fctl + 16, 0);
            fctl[20] = (uint8_t)(delay_num >> 8), fctl[21] = (uint8_t)delay_num;
            fctl[22] = (uint8_t)(delay_den >> 8), fctl[23] = (uint8_t)delay_den;
            fctl[24] = 0, fctl[25] = 0; /* dispose none, blend source */
            bad |= write_chunk(f, "fcTL", fctl, 26);
        }
        if (fr == 0) {
            bad |= write_chunk(f, "IDAT", z, zn);
        } else {
            uint8_t *fd = malloc(zn + 4);
            if (!fd) {
                oom = bad = 1;
            } else {
                put32(fd, seq++);
                memcpy(fd + 4, z, zn);
                bad |= write_chunk(f, "fdAT", fd, zn + 4);
                free(fd);
            }
        }
        free(z);
    }
    bad |= write_chunk(f, "IEND", NULL, 0);
    if (bad) {
        if (oom)
            snprintf(err, errlen, "%s: out of memory", path);
        else
            snprintf(err, errlen, "%s: write failed: %s", path, strerror(errno));
        qibl_io_atomic_abort(&at);
        return -1;
    }
    return qibl_io_atomic_commit(&at, err, errlen);
}

int qibl_png_write_rgb8(const char *path, int w, int h, const uint8_t *rgb, char *err, size_t errlen)
{
    return write_png_frames(path, w, h, 1, rgb, 0, 0, err, errlen);
}

int qibl_apng_write_rgb8(const char *path, int w, int h, int frames, const uint8_t *rgb, int delay_num,
                         int delay_den, char *err, size_t errlen)
{
    if (frames < 2) {
        snprintf(err, errlen, "%s: an animated PNG needs at least 2 frames, got %d", path, frames);
        return -1;
    }
    return write_png_frames(path, w, h, frames, rgb, delay_num, delay_den, err, errlen);
}
