/*
 * io/png.c - PNG writer: IHDR, one IDAT holding a zlib stream, IEND. Each row's filter (None, Sub,
 * Up, Average, Paeth) is chosen by the minimum sum of absolute differences, as libpng does. Deflate:
 * LZ77 matches from hash chains (32 KiB window, one step of lazy matching), then blocks of 64 Ki tokens, each with its own
 * Huffman code (RFC 1951 dynamic block, lengths limited to 15 bits) or the fixed code when smaller.
 */
#include "io/png.h"
#include "io/atomic.h"
#include "io/zlib.h"

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

/* ---- deflate: LZ77 (hash chains, 32 KiB window) + Huffman blocks of RFC 1951 -------------------- */

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

static const uint16_t len_base[29] = {3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 15, 17, 19, 23, 27, 31,
                                      35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258};
static const uint8_t len_extra[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2,
                                      3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
static const uint16_t dist_base[30] = {1, 2, 3, 4, 5, 7, 9, 13, 17, 25, 33, 49, 65, 97, 129, 193,
                                       257, 385, 513, 769, 1025, 1537, 2049, 3073, 4097, 6145, 8193,
                                       12289, 16385, 24577};
static const uint8_t dist_extra[30] = {0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6,
                                       7, 7, 8, 8, 9, 9, 10, 10, 11, 11, 12, 12, 13, 13};

#define HBITS 15
#define WSIZE 32768
#define MAXCHAIN 48
#define NLIT 288 /* literal/length symbols with the fixed code's two unused ones: its canonical codes need all 288 */
#define NDIST 30
#define BLOCK_TOKENS 65536 /* tokens per deflate block: each block gets its own Huffman code */

/* An LZ77 token: a literal byte (< 256), or MATCH | length << 16 | distance. */
#define MATCH 0x80000000u

static int len_code(int len)
{
    int i = 28;
    while (len_base[i] > len)
        --i;
    return i;
}

static int dist_code(int dist)
{
    int d = 29;
    while (dist_base[d] > dist)
        --d;
    return d;
}

typedef struct {
    const uint8_t *in;
    size_t n;
    int32_t *head, *prev;
} chains;

static uint32_t hash3(const uint8_t *p)
{
    return ((uint32_t)p[0] << 10 ^ (uint32_t)p[1] << 5 ^ p[2]) & ((1u << HBITS) - 1);
}

static void insert(chains *c, size_t i)
{
    if (i + 2 < c->n) {
        uint32_t h = hash3(c->in + i);
        c->prev[i % WSIZE] = c->head[h];
        c->head[h] = (int32_t)i;
    }
}

/* the longest match for position i among the earlier positions on its chain (MAXCHAIN of them,
 * within the window); its length (0 if under 3) and distance */
static int longest(const chains *c, size_t i, int *dist)
{
    const uint8_t *in = c->in;
    int best = 0;
    if (i + 2 >= c->n)
        return 0;
    int32_t p = c->head[hash3(in + i)];
    int chain = MAXCHAIN;
    size_t maxlen = c->n - i < 258 ? c->n - i : 258;
    while (p >= 0 && i - (size_t)p <= WSIZE - 1 && chain-- > 0) {
        size_t l = 0;
        while (l < maxlen && in[(size_t)p + l] == in[i + l])
            ++l;
        if ((int)l > best) {
            best = (int)l, *dist = (int)(i - (size_t)p);
            if (l == maxlen)
                break;
        }
        int32_t pp = c->prev[(size_t)p % WSIZE];
        if (pp >= p)
            break;
        p = pp;
    }
    return best >= 3 ? best : 0;
}

/* LZ77 over the whole input into tokens (n of them at most), with one step of lazy matching as
 * zlib does: a match is put off by a literal when the next position has a longer one. Returns the
 * token count, or -1 (out of memory). */
static long lz77(const uint8_t *in, size_t n, uint32_t *tok)
{
    chains c = {in, n, malloc(sizeof(int32_t) << HBITS), malloc(sizeof(int32_t) * WSIZE)};
    if (!c.head || !c.prev) {
        free(c.head), free(c.prev);
        return -1;
    }
    for (size_t i = 0; i < ((size_t)1 << HBITS); ++i)
        c.head[i] = -1;
    size_t i = 0, nt = 0;
    while (i < n) {
        int dist = 0, len = longest(&c, i, &dist);
        insert(&c, i);
        if (len >= 3 && len < 258 && i + 1 < n) {
            int d2 = 0, l2 = longest(&c, i + 1, &d2);
            if (l2 > len) {
                tok[nt++] = in[i++];
                continue;
            }
        }
        if (len < 3) {
            tok[nt++] = in[i++];
            continue;
        }
        tok[nt++] = MATCH | (uint32_t)len << 16 | (uint32_t)dist;
        for (size_t k = 1; k < (size_t)len; ++k)
            insert(&c, i + k);
        i += (size_t)len;
    }
    free(c.head), free(c.prev);
    return (long)nt;
}

/* Huffman code lengths (each <= maxbits) for n symbols of the given frequencies: an optimal code
 * (two-queue merge of the sorted leaves); if it is deeper than maxbits the frequencies are halved
 * (keeping every used symbol) and the code rebuilt. Fewer than two used symbols: two codes of
 * length 1 (the used one and symbol 0 or 1). */
static void code_lengths(const uint32_t *freq, int n, int maxbits, uint8_t *len)
{
    uint32_t f[NLIT];
    int leaf[NLIT], nl = 0;
    for (int i = 0; i < n; ++i)
        f[i] = freq[i], len[i] = 0;
    for (int i = 0; i < n; ++i)
        if (f[i])
            leaf[nl++] = i;
    if (nl < 2) { /* as zlib: two codes of one bit, so every code is complete */
        int a = nl ? leaf[0] : 0;
        len[a] = 1, len[a == 0 ? 1 : 0] = 1;
        return;
    }
    for (;;) {
        /* leaves by frequency (insertion sort: n <= 286; ties by symbol, so the result is deterministic) */
        for (int i = 1; i < nl; ++i)
            for (int j = i; j > 0 && f[leaf[j]] < f[leaf[j - 1]]; --j) {
                int t = leaf[j];
                leaf[j] = leaf[j - 1], leaf[j - 1] = t;
            }
        uint64_t w[2 * NLIT];
        int parent[2 * NLIT], qi = 0, qn = nl, ni = nl; /* leaves 0..nl-1, internal nodes nl.. */
        for (int i = 0; i < nl; ++i)
            w[i] = f[leaf[i]];
        for (int k = 0; k < nl - 1; ++k) {
            int pick[2];
            for (int m = 0; m < 2; ++m) /* the lighter of the next leaf and the next internal node */
                pick[m] = qi < nl && (qn >= ni || w[qi] <= w[qn]) ? qi++ : qn++;
            w[ni] = w[pick[0]] + w[pick[1]];
            parent[pick[0]] = parent[pick[1]] = ni;
            ++ni;
        }
        int depth[2 * NLIT], deepest = 0;
        depth[ni - 1] = 0;
        for (int i = ni - 2; i >= 0; --i) /* parents come after their children */
            depth[i] = depth[parent[i]] + 1;
        for (int i = 0; i < nl; ++i)
            deepest = depth[i] > deepest ? depth[i] : deepest;
        if (deepest <= maxbits) {
            for (int i = 0; i < nl; ++i)
                len[leaf[i]] = (uint8_t)depth[i];
            return;
        }
        for (int i = 0; i < nl; ++i)
            f[leaf[i]] = (f[leaf[i]] + 1) / 2;
    }
}

/* canonical codes from lengths (RFC 1951 3.2.2) */
static void canonical(const uint8_t *len, int n, uint16_t *code)
{
    uint16_t count[16] = {0}, next[16];
    for (int i = 0; i < n; ++i)
        count[len[i]]++;
    count[0] = 0;
    uint16_t c = 0;
    for (int b = 1; b < 16; ++b)
        c = (uint16_t)((c + count[b - 1]) << 1), next[b] = c;
    for (int i = 0; i < n; ++i)
        code[i] = len[i] ? next[len[i]]++ : 0;
}

/* the fixed code's lengths (RFC 1951 3.2.6) */
static void fixed_lengths(uint8_t *ll, uint8_t *dl)
{
    for (int i = 0; i < NLIT; ++i)
        ll[i] = i < 144 ? 8 : i < 256 ? 9 : i < 280 ? 7 : 8;
    for (int i = 0; i < NDIST; ++i)
        dl[i] = 5;
}

static const uint8_t cl_order[19] = {16, 17, 18, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3, 13, 2, 14, 1, 15};

/* The code lengths of a dynamic header, run-length coded (16: repeat the previous 3..6 times, 17:
 * 3..10 zeros, 18: 11..138 zeros) as symbol | extra << 8; returns the count. */
static int rle_lengths(const uint8_t *l, int n, uint16_t *out)
{
    int k = 0;
    for (int i = 0; i < n;) {
        int r = 1;
        while (i + r < n && l[i + r] == l[i])
            ++r;
        if (l[i] == 0 && r >= 3) {
            int m = r > 138 ? 138 : r;
            out[k++] = m >= 11 ? (uint16_t)(18 | (m - 11) << 8) : (uint16_t)(17 | (m - 3) << 8);
            i += m;
        } else if (l[i] != 0 && r >= 4) {
            out[k++] = l[i];
            int m = r - 1 > 6 ? 6 : r - 1;
            out[k++] = (uint16_t)(16 | (m - 3) << 8);
            i += 1 + m;
        } else {
            out[k++] = l[i++];
        }
    }
    return k;
}

/* One deflate block of tokens [0, nt) plus the end-of-block code: dynamic Huffman (codes made for
 * these tokens) or the fixed code, whichever takes fewer bits. */
static void emit_block(bitw *w, const uint32_t *tok, size_t nt, int final)
{
    uint32_t lf[NLIT] = {0}, df[NDIST] = {0};
    for (size_t i = 0; i < nt; ++i) {
        if (tok[i] & MATCH)
            lf[257 + len_code((int)(tok[i] >> 16 & 0x1FF))]++, df[dist_code((int)(tok[i] & 0xFFFF))]++;
        else
            lf[tok[i]]++;
    }
    lf[256] = 1;
    uint8_t ll[NLIT], dl[NDIST], fll[NLIT], fdl[NDIST];
    code_lengths(lf, NLIT, 15, ll);
    code_lengths(df, NDIST, 15, dl);
    int hlit = NLIT, hdist = NDIST;
    while (hlit > 257 && ll[hlit - 1] == 0)
        --hlit;
    while (hdist > 1 && dl[hdist - 1] == 0)
        --hdist;
    uint8_t all[NLIT + NDIST];
    memcpy(all, ll, (size_t)hlit), memcpy(all + hlit, dl, (size_t)hdist);
    uint16_t rle[NLIT + NDIST];
    int nr = rle_lengths(all, hlit + hdist, rle);
    uint32_t cf[19] = {0};
    for (int i = 0; i < nr; ++i)
        cf[rle[i] & 0xFF]++;
    uint8_t cl[19];
    code_lengths(cf, 19, 7, cl);
    int hclen = 19;
    while (hclen > 4 && cl[cl_order[hclen - 1]] == 0)
        --hclen;
    /* sizes in bits (the extra bits of lengths and distances are the same in both) */
    fixed_lengths(fll, fdl);
    uint64_t dyn = 14 + 3 * (uint64_t)hclen, fix = 0;
    for (int i = 0; i < nr; ++i) {
        int sym = rle[i] & 0xFF;
        dyn += cl[sym] + (sym == 16 ? 2u : sym == 17 ? 3u : sym == 18 ? 7u : 0u);
    }
    for (int i = 0; i < NLIT; ++i)
        dyn += (uint64_t)lf[i] * ll[i], fix += (uint64_t)lf[i] * fll[i];
    for (int i = 0; i < NDIST; ++i)
        dyn += (uint64_t)df[i] * dl[i], fix += (uint64_t)df[i] * fdl[i];
    int use_dyn = dyn < fix;
    bw_put(w, final ? 1u : 0u, 1);
    bw_put(w, use_dyn ? 2u : 1u, 2);
    const uint8_t *L = use_dyn ? ll : fll, *D = use_dyn ? dl : fdl;
    if (use_dyn) {
        uint16_t cc[19];
        canonical(cl, 19, cc);
        bw_put(w, (uint32_t)(hlit - 257), 5);
        bw_put(w, (uint32_t)(hdist - 1), 5);
        bw_put(w, (uint32_t)(hclen - 4), 4);
        for (int i = 0; i < hclen; ++i)
            bw_put(w, cl[cl_order[i]], 3);
        for (int i = 0; i < nr; ++i) {
            int sym = rle[i] & 0xFF, extra = rle[i] >> 8;
            bw_huff(w, cc[sym], cl[sym]);
            if (sym >= 16)
                bw_put(w, (uint32_t)extra, sym == 16 ? 2 : sym == 17 ? 3 : 7);
        }
    }
    uint16_t lc[NLIT], dc[NDIST];
    canonical(L, NLIT, lc);
    canonical(D, NDIST, dc);
    for (size_t i = 0; i < nt; ++i) {
        if (tok[i] & MATCH) {
            int len = (int)(tok[i] >> 16 & 0x1FF), dist = (int)(tok[i] & 0xFFFF);
            int li = len_code(len), di = dist_code(dist);
            bw_huff(w, lc[257 + li], L[257 + li]);
            bw_put(w, (uint32_t)(len - len_base[li]), len_extra[li]);
            bw_huff(w, dc[di], D[di]);
            bw_put(w, (uint32_t)(dist - dist_base[di]), dist_extra[di]);
        } else {
            bw_huff(w, lc[tok[i]], L[tok[i]]);
        }
    }
    bw_huff(w, lc[256], L[256]);
}

/* The deflate stream of the input: LZ77, then blocks of BLOCK_TOKENS tokens. 0 or -1 (no memory). */
static int deflate_stream(const uint8_t *in, size_t n, bitw *w)
{
    uint32_t *tok = calloc(n ? n : 1, sizeof *tok); /* zeroed: gcc cannot see lz77 fills what emit_block reads */
    long nt = tok ? lz77(in, n, tok) : -1;
    if (nt < 0) {
        free(tok);
        return -1;
    }
    size_t at = 0;
    do {
        size_t m = (size_t)nt - at < BLOCK_TOKENS ? (size_t)nt - at : BLOCK_TOKENS;
        emit_block(w, tok + at, m, at + m == (size_t)nt);
        at += m;
    } while (at < (size_t)nt);
    free(tok);
    if (w->nbits > 0)
        bw_put(w, 0, 8 - w->nbits); /* pad to a byte boundary */
    return w->oom ? -1 : 0;
}

/* Paeth predictor (PNG spec 9.4): whichever of left, up, upper-left is nearest to left + up - upper-left */
static uint8_t paeth(int a, int b, int c)
{
    int p = a + b - c, pa = p > a ? p - a : a - p, pb = p > b ? p - b : b - p, pc = p > c ? p - c : c - p;
    return (uint8_t)(pa <= pb && pa <= pc ? a : pb <= pc ? b : c);
}

/* Row s (n bytes, 3 per pixel) filtered with type f against the previous row up (NULL: the first
 * row, all zero) into out; returns the sum of the output bytes taken as signed (|v| for v < 128,
 * 256 - v above): the "minimum sum of absolute differences" estimate libpng uses to pick a filter. */
static unsigned long filter_row(int f, const uint8_t *s, const uint8_t *up, size_t n, uint8_t *out)
{
    unsigned long sum = 0;
    for (size_t x = 0; x < n; ++x) {
        int a = x >= 3 ? s[x - 3] : 0, b = up ? up[x] : 0, c = up && x >= 3 ? up[x - 3] : 0;
        int pred = f == 0 ? 0 : f == 1 ? a : f == 2 ? b : f == 3 ? (a + b) / 2 : paeth(a, b, c);
        uint8_t v = (uint8_t)(s[x] - pred);
        out[x] = v;
        sum += v < 128 ? v : 256u - v;
    }
    return sum;
}

/* zlib stream of the filtered scanlines of a w x h RGB image: each row with the filter (None, Sub,
 * Up, Average, Paeth) whose output has the smallest sum of absolute values, as libpng chooses. */
static int zlib_rgb(int w, int h, const uint8_t *rgb, uint8_t **zout, size_t *zn)
{
    size_t row = (size_t)w * 3 + 1, raw_n = row * (size_t)h, n = (size_t)w * 3;
    uint8_t *raw = malloc(raw_n), *tmp = malloc(n);
    if (!raw || !tmp) {
        free(raw), free(tmp);
        return -1;
    }
    for (int y = 0; y < h; ++y) {
        uint8_t *r = raw + (size_t)y * row;
        const uint8_t *s = rgb + (size_t)y * n, *up = y ? s - n : NULL;
        unsigned long best = filter_row(0, s, up, n, r + 1);
        r[0] = 0;
        for (int f = 1; f <= 4; ++f) {
            unsigned long sum = filter_row(f, s, up, n, tmp);
            if (sum < best) {
                best = sum, r[0] = (uint8_t)f;
                memcpy(r + 1, tmp, n);
            }
        }
    }
    free(tmp);
    int rc = qtool_zlib_deflate(raw, raw_n, zout, zn);
    free(raw);
    return rc;
}

int qtool_zlib_deflate(const uint8_t *in, size_t n, uint8_t **out, size_t *outn)
{
    bitw bw = {0};
    uint32_t a = 1, b = 0; /* Adler-32 of the input */
    for (size_t i = 0; i < n; ++i) {
        a += in[i];
        if (a >= 65521u)
            a -= 65521u;
        b += a;
        if (b >= 65521u)
            b -= 65521u;
    }
    bw_put(&bw, 0x78, 8); /* zlib header: deflate, 32 KiB window; 0x7801 is a multiple of 31 */
    bw_put(&bw, 0x01, 8);
    if (deflate_stream(in, n, &bw) != 0) {
        free(bw.buf);
        return -1;
    }
    for (int k = 3; k >= 0; --k)
        bw_put(&bw, (((b << 16) | a) >> (8 * k)) & 0xFFu, 8);
    if (bw.oom) {
        free(bw.buf);
        return -1;
    }
    *out = bw.buf, *outn = bw.n;
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

    qtool_io_atomic at;
    if (qtool_io_atomic_open(&at, path, err, errlen) != 0)
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
        qtool_io_atomic_abort(&at);
        return -1;
    }
    return qtool_io_atomic_commit(&at, err, errlen);
}

int qtool_png_write_rgb8(const char *path, int w, int h, const uint8_t *rgb, char *err, size_t errlen)
{
    return write_png_frames(path, w, h, 1, rgb, 0, 0, err, errlen);
}

int qtool_apng_write_rgb8(const char *path, int w, int h, int frames, const uint8_t *rgb, int delay_num,
                         int delay_den, char *err, size_t errlen)
{
    if (frames < 2) {
        snprintf(err, errlen, "%s: an animated PNG needs at least 2 frames, got %d", path, frames);
        return -1;
    }
    return write_png_frames(path, w, h, frames, rgb, delay_num, delay_den, err, errlen);
}
