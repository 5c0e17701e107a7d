/*
 * io/inflate.c - the tools' one inflate (RFC 1950 zlib around RFC 1951 deflate: stored, fixed and
 * dynamic Huffman blocks, Adler-32 checked), shared by the PNG and OpenEXR readers (io/zlib.h).
 * The output is the caller's buffer of a size it knows in advance: a stream inflating further
 * stops there, so a hostile stream costs at most that buffer and time linear in input plus output.
 */
#include "io/zlib.h"

#include <stdlib.h>
#include <string.h>

static uint32_t get32(const uint8_t *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

/* ---- inflate -------------------------------------------------------------------------------------- */

typedef struct {
    const uint8_t *in;
    size_t n, pos; /* pos in bits */
    uint8_t *out;
    size_t on, ocap;
    const char *why;
} inf;

static int bits(inf *s, int n, uint32_t *v)
{
    uint32_t r = 0;
    for (int i = 0; i < n; ++i) {
        if (s->pos >= s->n * 8) {
            s->why = "deflate stream truncated";
            return -1;
        }
        r |= (uint32_t)((s->in[s->pos >> 3] >> (s->pos & 7)) & 1) << i;
        s->pos++;
    }
    *v = r;
    return 0;
}

typedef struct {
    uint16_t count[16], sym[320];
} huff;

static int huff_build(huff *h, const uint8_t *len, int n)
{
    uint16_t offs[16];
    memset(h->count, 0, sizeof h->count);
    for (int i = 0; i < n; ++i)
        h->count[len[i]]++;
    h->count[0] = 0;
    int left = 1;
    for (int l = 1; l < 16; ++l) {
        left <<= 1;
        left -= h->count[l];
        if (left < 0)
            return -1; /* over-subscribed */
    }
    offs[1] = 0;
    for (int l = 1; l < 15; ++l)
        offs[l + 1] = (uint16_t)(offs[l] + h->count[l]);
    for (int i = 0; i < n; ++i)
        if (len[i])
            h->sym[offs[len[i]]++] = (uint16_t)i;
    return 0;
}

static int huff_decode(inf *s, const huff *h)
{
    int code = 0, first = 0, index = 0;
    for (int l = 1; l < 16; ++l) {
        uint32_t b;
        if (bits(s, 1, &b) != 0)
            return -1;
        code |= (int)b;
        int c = h->count[l];
        if (code - c < first)
            return h->sym[index + (code - first)];
        index += c;
        first += c;
        first <<= 1;
        code <<= 1;
    }
    s->why = "bad Huffman code";
    return -1;
}

/* the output buffer is exactly the size the caller expects, so a stream inflating further stops at once */
static int emit(inf *s, uint8_t b)
{
    if (s->on == s->ocap) {
        s->why = "inflates past the expected size";
        return -1;
    }
    s->out[s->on++] = b;
    return 0;
}

static const uint16_t lbase[29] = {3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 15, 17, 19, 23, 27, 31,
                                   35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258};
static const uint8_t lext[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
static const uint16_t dbase[30] = {1, 2, 3, 4, 5, 7, 9, 13, 17, 25, 33, 49, 65, 97, 129, 193,
                                   257, 385, 513, 769, 1025, 1537, 2049, 3073, 4097, 6145, 8193, 12289, 16385, 24577};
static const uint8_t dext[30] = {0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7, 8, 8, 9, 9, 10, 10, 11, 11, 12, 12, 13, 13};

static int codes(inf *s, const huff *lit, const huff *dist)
{
    for (;;) {
        int sym = huff_decode(s, lit);
        if (sym < 0)
            return -1;
        if (sym < 256) {
            if (emit(s, (uint8_t)sym) != 0)
                return -1;
        } else if (sym == 256) {
            return 0;
        } else {
            sym -= 257;
            if (sym >= 29) {
                s->why = "bad length symbol";
                return -1;
            }
            uint32_t e, de;
            if (bits(s, lext[sym], &e) != 0)
                return -1;
            size_t len = lbase[sym] + e;
            int ds = huff_decode(s, dist);
            if (ds < 0)
                return -1;
            if (ds >= 30) {
                s->why = "bad distance symbol";
                return -1;
            }
            if (bits(s, dext[ds], &de) != 0)
                return -1;
            size_t d = dbase[ds] + de;
            if (d > s->on) {
                s->why = "distance too far back";
                return -1;
            }
            for (size_t i = 0; i < len; ++i)
                if (emit(s, s->out[s->on - d]) != 0)
                    return -1;
        }
    }
}

static int inflate_raw(inf *s)
{
    uint32_t last = 0, type;
    while (!last) {
        if (bits(s, 1, &last) != 0 || bits(s, 2, &type) != 0)
            return -1;
        if (type == 0) {
            s->pos = (s->pos + 7) & ~(size_t)7;
            size_t p = s->pos >> 3;
            if (p + 4 > s->n) {
                s->why = "deflate stream truncated";
                return -1;
            }
            unsigned len = s->in[p] | (unsigned)s->in[p + 1] << 8, nlen = s->in[p + 2] | (unsigned)s->in[p + 3] << 8;
            if ((len ^ 0xFFFFu) != nlen) {
                s->why = "stored block length check failed";
                return -1;
            }
            if (p + 4 + len > s->n) {
                s->why = "deflate stream truncated";
                return -1;
            }
            for (unsigned i = 0; i < len; ++i)
                if (emit(s, s->in[p + 4 + i]) != 0)
                    return -1;
            s->pos = (p + 4 + len) * 8;
        } else if (type == 1) {
            huff flit, fdist; /* rebuilt per block: cheap, and no static state */
            uint8_t l[288];
            for (int i = 0; i < 288; ++i)
                l[i] = (uint8_t)(i < 144 ? 8 : i < 256 ? 9 : i < 280 ? 7 : 8);
            huff_build(&flit, l, 288);
            for (int i = 0; i < 30; ++i)
                l[i] = 5;
            huff_build(&fdist, l, 30);
            if (codes(s, &flit, &fdist) != 0)
                return -1;
        } else if (type == 2) {
            static const uint8_t order[19] = {16, 17, 18, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3, 13, 2, 14, 1, 15};
            uint32_t hlit, hdist, hclen, v;
            if (bits(s, 5, &hlit) || bits(s, 5, &hdist) || bits(s, 4, &hclen))
                return -1;
            hlit += 257, hdist += 1, hclen += 4;
            if (hlit > 286 || hdist > 30) {
                s->why = "bad dynamic block header";
                return -1;
            }
            uint8_t len[320] = {0};
            for (uint32_t i = 0; i < hclen; ++i) {
                if (bits(s, 3, &v) != 0)
                    return -1;
                len[order[i]] = (uint8_t)v;
            }
            huff lc, lit, dist;
            if (huff_build(&lc, len, 19) != 0) {
                s->why = "bad code-length code";
                return -1;
            }
            uint32_t idx = 0;
            memset(len, 0, sizeof len);
            while (idx < hlit + hdist) {
                int sym = huff_decode(s, &lc);
                if (sym < 0)
                    return -1;
                if (sym < 16) {
                    len[idx++] = (uint8_t)sym;
                    continue;
                }
                uint8_t rep = 0;
                uint32_t cnt;
                if (sym == 16) {
                    if (idx == 0) {
                        s->why = "repeat with no previous length";
                        return -1;
                    }
                    rep = len[idx - 1];
                    if (bits(s, 2, &cnt))
                        return -1;
                    cnt += 3;
                } else if (sym == 17) {
                    if (bits(s, 3, &cnt))
                        return -1;
                    cnt += 3;
                } else {
                    if (bits(s, 7, &cnt))
                        return -1;
                    cnt += 11;
                }
                if (idx + cnt > hlit + hdist) {
                    s->why = "too many code lengths";
                    return -1;
                }
                while (cnt--)
                    len[idx++] = rep;
            }
            if (huff_build(&lit, len, (int)hlit) != 0 || huff_build(&dist, len + hlit, (int)hdist) != 0) {
                s->why = "bad literal or distance code";
                return -1;
            }
            if (codes(s, &lit, &dist) != 0)
                return -1;
        } else {
            s->why = "bad deflate block type 3";
            return -1;
        }
    }
    return 0;
}

int qtool_zlib_inflate(const uint8_t *z, size_t n, uint8_t *out, size_t cap, size_t *outn, const char **why)
{
    if (n < 6 || (z[0] & 0x0F) != 8 || ((unsigned)z[0] << 8 | z[1]) % 31 != 0 || (z[1] & 0x20)) {
        *why = "bad zlib header";
        return -1;
    }
    inf s = {z + 2, n - 2, 0, out, 0, cap, NULL};
    if (inflate_raw(&s) != 0) {
        *why = s.why;
        return -1;
    }
    size_t p = ((s.pos + 7) >> 3) + 2;
    if (p + 4 > n) {
        *why = "zlib stream has no Adler-32";
        return -1;
    }
    uint32_t a = 1, b = 0;
    for (size_t i = 0; i < s.on; ++i) {
        a = (a + s.out[i]) % 65521u;
        b = (b + a) % 65521u;
    }
    if (get32(z + p) != (b << 16 | a)) {
        *why = "Adler-32 mismatch";
        return -1;
    }
    *outn = s.on;
    return 0;
}
