/*
 * exr_test.c - tools/io/exr.c: the OpenEXR reader against files other code wrote, the writer, the
 * limits and every named error.
 *
 * Independent files: fixtures/exr/ holds EXR files written by OpenImageIO's oiiotool (OpenEXR 3.1)
 * from PFM images (fixtures/exr/make_fixtures.py): NONE, RLE, ZIPS, ZIP (scanline and tiled, HALF and
 * FLOAT), PIZ (both wavelet widths), RGBA, a Y channel and a data window inside a larger display
 * window; each must decode bit for bit to its PFM. The files are skipped (reported) when absent.
 * Hand-made files: this suite's own encoders, written from the format's description (not the
 * reader's code): RLE, zlib in one fixed-Huffman deflate block, PIZ (bitmap, renumbering, the 14- and 16-bit
 * wavelets, a canonical Huffman code with the run pseudo-symbol), for HALF, FLOAT and UINT channels in
 * odd orders, extra channels, Y, tiles (with a MIPMAP level table), negative window origins.
 * The writer's files are read back bit for bit, and by oiiotool when it is installed (`oiiotool
 * OUT.exr SOURCE.pfm --fail 0 --diff`). QIBL_EXR_DIR (e.g. a checkout of openexr-images): every file
 * under it decodes equal to OpenEXR's own decoding (oiiotool) or is refused by name; skipped if unset.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cmocka.h>

#include "io/exr.h"
#include "io/hdr.h"
#include "io/pfm.h"
#include "io/probe_layout.h"
#include "fileutil.h"

/* ---- the suite's own encoders ---------------------------------------------------------------- */

typedef struct {
    uint8_t *b;
    size_t n, cap;
} buf_t;

static void bput(buf_t *b, const void *p, size_t n)
{
    if (b->n + n > b->cap) {
        b->cap = (b->n + n) * 2 + 1024;
        b->b = realloc(b->b, b->cap);
        assert_non_null(b->b);
    }
    memcpy(b->b + b->n, p, n);
    b->n += n;
}

static void b32(buf_t *b, uint32_t v)
{
    uint8_t q[4] = {(uint8_t)v, (uint8_t)(v >> 8), (uint8_t)(v >> 16), (uint8_t)(v >> 24)};
    bput(b, q, 4);
}

static void b16(buf_t *b, uint32_t v)
{
    uint8_t q[2] = {(uint8_t)v, (uint8_t)(v >> 8)};
    bput(b, q, 2);
}

static void battr(buf_t *b, const char *name, const char *type, const void *v, uint32_t n)
{
    bput(b, name, strlen(name) + 1);
    bput(b, type, strlen(type) + 1);
    b32(b, n);
    bput(b, v, n);
}

/* the format's byte transform for RLE and ZIP: even bytes then odd bytes, then deltas + 128 */
static void predict(const uint8_t *in, size_t n, uint8_t *t)
{
    size_t half = (n + 1) / 2;
    for (size_t i = 0; i < n; i += 2)
        t[i / 2] = in[i];
    for (size_t i = 1; i < n; i += 2)
        t[half + i / 2] = in[i];
    uint8_t prev = t[0];
    for (size_t i = 1; i < n; ++i) {
        uint8_t cur = t[i];
        t[i] = (uint8_t)(cur - prev + 128);
        prev = cur;
    }
}

static void rle_encode(const uint8_t *t, size_t n, buf_t *o)
{
    size_t i = 0;
    while (i < n) {
        size_t r = 1;
        while (i + r < n && r < 128 && t[i + r] == t[i])
            ++r;
        if (r >= 3) {
            uint8_t c = (uint8_t)(r - 1);
            bput(o, &c, 1);
            bput(o, &t[i], 1);
            i += r;
            continue;
        }
        size_t j = i; /* literals up to the next run of 3 */
        while (j < n && j - i < 127 && !(j + 2 < n && t[j] == t[j + 1] && t[j] == t[j + 2]))
            ++j;
        uint8_t c = (uint8_t)(256 - (j - i));
        bput(o, &c, 1);
        bput(o, t + i, j - i);
        i = j;
    }
}

/* zlib stream in one fixed-Huffman deflate block (RFC 1950/1951): literals, and runs of the previous
 * byte as matches at distance 1; Adler-32 at the end */
typedef struct {
    buf_t *o;
    uint32_t acc;
    int nacc;
} zbits;

static void zput(zbits *z, uint32_t v, int n) /* n bits of v, least significant first */
{
    for (int i = 0; i < n; ++i) {
        z->acc |= ((v >> i) & 1u) << z->nacc;
        if (++z->nacc == 8) {
            uint8_t c = (uint8_t)z->acc;
            bput(z->o, &c, 1);
            z->acc = 0, z->nacc = 0;
        }
    }
}

static void zcode(zbits *z, uint32_t code, int len) /* a Huffman code: most significant bit first */
{
    for (int i = len - 1; i >= 0; --i)
        zput(z, (code >> i) & 1u, 1);
}

static void zsym(zbits *z, int sym) /* the fixed literal/length code */
{
    if (sym < 144)
        zcode(z, 0x30u + (uint32_t)sym, 8);
    else if (sym < 256)
        zcode(z, 0x190u + (uint32_t)(sym - 144), 9);
    else if (sym < 280)
        zcode(z, (uint32_t)(sym - 256), 7);
    else
        zcode(z, 0xC0u + (uint32_t)(sym - 280), 8);
}

static void zlib_fixed(const uint8_t *in, size_t n, buf_t *o)
{
    static const uint16_t base[29] = {3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 15, 17, 19, 23, 27, 31,
                                      35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258};
    static const uint8_t ext[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
    uint8_t h[2] = {0x78, 0x01};
    bput(o, h, 2);
    zbits z = {o, 0, 0};
    zput(&z, 1, 1), zput(&z, 1, 2); /* final block, fixed codes */
    for (size_t i = 0; i < n;) {
        size_t r = 0;
        while (i > 0 && i + r < n && in[i + r] == in[i - 1] && r < 258)
            ++r;
        if (r >= 3) {
            int k = 28;
            while (base[k] > r)
                --k;
            zsym(&z, 257 + k);
            zput(&z, (uint32_t)(r - base[k]), ext[k]);
            zcode(&z, 0, 5); /* distance code 0: distance 1 */
            i += r;
        } else {
            zsym(&z, in[i++]);
        }
    }
    zsym(&z, 256);
    if (z.nacc)
        zput(&z, 0, 8 - z.nacc);
    uint32_t a = 1, s = 0;
    for (size_t j = 0; j < n; ++j)
        a = (a + in[j]) % 65521u, s = (s + a) % 65521u;
    uint32_t ad = s << 16 | a;
    uint8_t t[4] = {(uint8_t)(ad >> 24), (uint8_t)(ad >> 16), (uint8_t)(ad >> 8), (uint8_t)ad};
    bput(o, t, 4);
}

/* PIZ wavelet pair encoders: 14-bit (signed mean and difference) and 16-bit (modular) */
static void wenc14(uint16_t a, uint16_t b, uint16_t *l, uint16_t *h)
{
    int as = (int16_t)a, bs = (int16_t)b; /* tests: two's complement host */
    int s = as + bs, m = s >= 0 ? s / 2 : -((-s + 1) / 2);
    *l = (uint16_t)m, *h = (uint16_t)(as - bs);
}

static void wenc16(uint16_t a, uint16_t b, uint16_t *l, uint16_t *h)
{
    int ao = (a + 32768) & 0xFFFF, m = (ao + b) >> 1, d = ao - b;
    if (d < 0)
        m = (m + 32768) & 0xFFFF;
    *l = (uint16_t)m, *h = (uint16_t)(d & 0xFFFF);
}

static void wenc(int w14, uint16_t *pa, uint16_t *pb)
{
    uint16_t l, h;
    if (w14)
        wenc14(*pa, *pb, &l, &h);
    else
        wenc16(*pa, *pb, &l, &h);
    *pa = l, *pb = h;
}

/* forward 2D transform, finest level first: at level p, pairs p apart along x then y */
static void wav_encode(uint16_t *v, size_t nx, size_t ox, size_t ny, size_t oy, int w14)
{
    size_t n = nx < ny ? nx : ny;
    for (size_t p = 1, p2 = 2; p2 <= n; p = p2, p2 <<= 1) {
        size_t y = 0;
        for (; y + p2 <= ny; y += p2) {
            size_t x = 0;
            for (; x + p2 <= nx; x += p2) {
                uint16_t *a = v + y * oy + x * ox, *b = a + p * ox, *c = a + p * oy, *d = c + p * ox;
                wenc(w14, a, b); /* rows */
                wenc(w14, c, d);
                wenc(w14, a, c); /* then columns: low with low, high with high */
                wenc(w14, b, d);
            }
            if (nx & p) /* an odd column left over at this level: a vertical pair */
                wenc(w14, v + y * oy + x * ox, v + (y + p) * oy + x * ox);
        }
        if (ny & p) /* an odd row left over: horizontal pairs */
            for (size_t x = 0; x + p2 <= nx; x += p2)
                wenc(w14, v + y * oy + x * ox, v + y * oy + (x + p) * ox);
    }
}

typedef struct {
    uint8_t *b;
    size_t bits, cap;
} bitw_t;

static void putbits(bitw_t *w, uint64_t v, int n)
{
    for (int i = n - 1; i >= 0; --i) {
        if (w->bits / 8 >= w->cap) {
            w->cap = w->cap * 2 + 64;
            w->b = realloc(w->b, w->cap);
            assert_non_null(w->b);
        }
        if (w->bits % 8 == 0)
            w->b[w->bits / 8] = 0;
        if ((v >> i) & 1)
            w->b[w->bits / 8] |= (uint8_t)(0x80 >> (w->bits % 8));
        w->bits++;
    }
}

/* Huffman code lengths by repeated merging of the two lightest trees (fine for a test's alphabet) */
static void huff_lengths(const uint64_t *freq, size_t nsym, uint8_t *len)
{
    size_t n = 0;
    size_t *node = malloc(sizeof *node * 2 * nsym), *parent = malloc(sizeof *parent * 2 * nsym);
    uint64_t *w = malloc(sizeof *w * 2 * nsym);
    int *alive = malloc(sizeof *alive * 2 * nsym);
    size_t *leaf_of = malloc(sizeof *leaf_of * nsym);
    for (size_t s = 0; s < nsym; ++s) {
        len[s] = 0;
        if (freq[s]) {
            node[n] = s, w[n] = freq[s], alive[n] = 1, parent[n] = SIZE_MAX, leaf_of[s] = n;
            ++n;
        }
    }
    size_t leaves = n, total = n;
    if (leaves == 1) { /* one symbol still needs a one-bit code */
        len[node[0]] = 1;
    } else {
        for (size_t merges = 0; merges + 1 < leaves; ++merges) {
            size_t a = SIZE_MAX, b = SIZE_MAX;
            for (size_t i = 0; i < total; ++i)
                if (alive[i]) {
                    if (a == SIZE_MAX || w[i] < w[a])
                        b = a, a = i;
                    else if (b == SIZE_MAX || w[i] < w[b])
                        b = i;
                }
            alive[a] = alive[b] = 0;
            parent[a] = parent[b] = total;
            w[total] = w[a] + w[b], alive[total] = 1, parent[total] = SIZE_MAX;
            ++total;
        }
        for (size_t s = 0; s < nsym; ++s)
            if (freq[s]) {
                int d = 0;
                for (size_t i = leaf_of[s]; parent[i] != SIZE_MAX; i = parent[i])
                    ++d;
                assert_true(d <= 58);
                len[s] = (uint8_t)d;
            }
    }
    free(node), free(parent), free(w), free(alive), free(leaf_of);
}

/* the format's canonical code: the longest codes numbered first from 0; each shorter length starts at
 * half (rounded down) of the end of the one below */
static void canonical(const uint8_t *len, size_t nsym, uint64_t *code)
{
    uint64_t count[59] = {0}, start[59] = {0}, c = 0;
    for (size_t s = 0; s < nsym; ++s)
        count[len[s]]++;
    for (int l = 58; l > 0; --l) {
        start[l] = c;
        c = (c + count[l]) >> 1;
    }
    for (size_t s = 0; s < nsym; ++s)
        if (len[s])
            code[s] = start[len[s]]++;
}

/* Huffman stream of n values (the format's layout: im, iM, table bytes, bit count, 0, table, bits) */
static void huf_encode(const uint16_t *v, size_t n, buf_t *o)
{
    size_t nsym = 65537;
    uint64_t *freq = calloc(nsym, sizeof *freq), *code = calloc(nsym, sizeof *code);
    uint8_t *len = calloc(nsym, 1);
    assert_true(freq && code && len);
    uint32_t im = 65536, iM = 0;
    for (size_t i = 0; i < n; ++i) {
        freq[v[i]]++;
        im = v[i] < im ? v[i] : im;
        iM = v[i] > iM ? v[i] : iM;
    }
    uint32_t rlc = ++iM; /* the run pseudo-symbol: one past the largest value */
    freq[rlc] = 1;
    huff_lengths(freq, nsym, len);
    canonical(len, nsym, code);
    bitw_t t = {0}, d = {0};
    for (uint32_t s = im; s <= iM;) {
        if (len[s] == 0) {
            uint32_t z = 0;
            while (s + z <= iM && len[s + z] == 0 && z < 261)
                ++z;
            if (z >= 6)
                putbits(&t, 63, 6), putbits(&t, z - 6, 8);
            else if (z >= 2)
                putbits(&t, 59 + z - 2, 6);
            else
                putbits(&t, 0, 6);
            s += z;
        } else {
            putbits(&t, len[s], 6);
            ++s;
        }
    }
    for (size_t i = 0; i < n;) {
        size_t r = 1;
        while (i + r < n && v[i + r] == v[i] && r < 256)
            ++r;
        putbits(&d, code[v[i]], len[v[i]]);
        if (r >= 4) { /* the value, then the run symbol and how many more times */
            putbits(&d, code[rlc], len[rlc]);
            putbits(&d, r - 1, 8);
        } else {
            for (size_t k = 1; k < r; ++k)
                putbits(&d, code[v[i]], len[v[i]]);
        }
        i += r;
    }
    size_t tb = (t.bits + 7) / 8, db = (d.bits + 7) / 8;
    b32(o, im), b32(o, iM), b32(o, (uint32_t)tb), b32(o, (uint32_t)d.bits), b32(o, 0);
    bput(o, t.b, tb);
    bput(o, d.b, db);
    free(t.b), free(d.b), free(freq), free(code), free(len);
}

typedef struct {
    const char *name;
    int type;
} tch;

/* PIZ chunk of a block: nch channels, ny lines of nx samples, raw line-interleaved bytes in */
static void piz_encode(const uint8_t *raw, const tch *ch, int nch, size_t nx, size_t ny, buf_t *o)
{
    size_t nw = 0;
    for (int c = 0; c < nch; ++c)
        nw += nx * ny * (ch[c].type == QTOOL_EXR_HALF ? 1 : 2);
    uint16_t *v = malloc(nw * 2);
    size_t at = 0, q = 0;
    size_t *base = malloc(sizeof *base * (size_t)nch);
    for (int c = 0; c < nch; ++c) {
        base[c] = at;
        at += nx * ny * (ch[c].type == QTOOL_EXR_HALF ? 1 : 2);
    }
    for (size_t y = 0; y < ny; ++y)
        for (int c = 0; c < nch; ++c) {
            size_t words = nx * (ch[c].type == QTOOL_EXR_HALF ? 1 : 2);
            for (size_t i = 0; i < words; ++i, q += 2)
                v[base[c] + y * words + i] = (uint16_t)(raw[q] | raw[q + 1] << 8);
        }
    uint8_t bitmap[8192] = {0};
    for (size_t i = 0; i < nw; ++i)
        bitmap[v[i] >> 3] |= (uint8_t)(1u << (v[i] & 7));
    bitmap[0] &= 0xFE; /* zero is always there */
    uint16_t *fwd = calloc(65536, 2);
    uint32_t k = 0;
    for (uint32_t i = 0; i < 65536; ++i)
        if (i == 0 || (bitmap[i >> 3] >> (i & 7) & 1))
            fwd[i] = (uint16_t)k++;
    uint32_t maxv = k - 1;
    for (size_t i = 0; i < nw; ++i)
        v[i] = fwd[v[i]];
    for (int c = 0; c < nch; ++c) {
        size_t size = ch[c].type == QTOOL_EXR_HALF ? 1 : 2;
        for (size_t j = 0; j < size; ++j)
            wav_encode(v + base[c] + j, nx, size, ny, nx * size, maxv < (1u << 14));
    }
    uint32_t lo = 8191, hi = 0;
    for (uint32_t i = 0; i < 8192; ++i)
        if (bitmap[i]) {
            lo = i < lo ? i : lo;
            hi = i;
        }
    b16(o, lo), b16(o, hi);
    if (lo <= hi)
        bput(o, bitmap + lo, hi - lo + 1);
    buf_t hb = {0};
    huf_encode(v, nw, &hb);
    b32(o, (uint32_t)hb.n);
    bput(o, hb.b, hb.n);
    free(hb.b), free(v), free(fwd), free(base);
}

/* ---- building whole files --------------------------------------------------------------------- */

typedef struct {
    int nch;
    tch ch[8];
    int comp, tiled, tw, th, mode;
    int32_t x0, y0;
    int w, h;
    int32_t disp[4]; /* all 0: the data window */
    int allow_raw;   /* chunks that do not shrink are stored raw (else the test fails) */
} spec_t;

static uint32_t sample_bits(const spec_t *s, int c, int x, int y)
{
    /* smooth enough to compress, with some noise and extremes; a function of (c, x, y) */
    uint32_t hsh = (uint32_t)x * 73856093u ^ (uint32_t)y * 19349663u ^ (uint32_t)c * 83492791u;
    int t = s->ch[c].type;
    if (t == QTOOL_EXR_UINT)
        return (uint32_t)(x * 3 + y * 1000 + c) + ((hsh & 63) == 0 ? 16777217u : 0); /* one past 2^24: rounds */
    if (t == QTOOL_EXR_HALF) {
        uint32_t h = 0x3800u + (uint32_t)(x * 5 + y * 9 + c * 300) % 2000u; /* 0.5 .. */
        if ((hsh & 127) == 1)
            h = 0x0001u + (hsh >> 8) % 0x3FFu; /* subnormal */
        if ((hsh & 127) == 2)
            h = 0xC000u | (hsh >> 8 & 0x3FFu); /* negative */
        if ((hsh & 255) == 3)
            h = 0x7BFFu; /* 65504 */
        return h;
    }
    float f = 1.0f + (float)x * 0.01f + (float)y * 0.37f + (float)c;
    if ((hsh & 15) == 1)
        f = -f * 1e-20f;
    uint32_t u;
    memcpy(&u, &f, 4);
    return u;
}

static double half_value(uint32_t h)
{
    int e = (int)(h >> 10 & 31), m = (int)(h & 0x3FF);
    double v = e ? ldexp(1024 + m, e - 25) : ldexp(m, -24);
    return h & 0x8000u ? -v : v;
}

static float sample_value(const spec_t *s, int c, int x, int y)
{
    uint32_t u = sample_bits(s, c, x, y);
    if (s->ch[c].type == QTOOL_EXR_HALF)
        return (float)half_value(u);
    if (s->ch[c].type == QTOOL_EXR_UINT)
        return (float)(double)u;
    float f;
    memcpy(&f, &u, 4);
    return f;
}

static size_t sbytes(int t)
{
    return t == QTOOL_EXR_HALF ? 2 : 4;
}

/* the file for spec s; every compressed chunk must be smaller than its pixels (so the codec is used) */
static buf_t build(const spec_t *s)
{
    buf_t b = {0};
    uint8_t mg[4] = {0x76, 0x2f, 0x31, 0x01};
    bput(&b, mg, 4);
    b32(&b, 2u | (s->tiled ? 0x200u : 0));
    buf_t cl = {0};
    for (int c = 0; c < s->nch; ++c) {
        bput(&cl, s->ch[c].name, strlen(s->ch[c].name) + 1);
        b32(&cl, (uint32_t)s->ch[c].type), b32(&cl, 0), b32(&cl, 1), b32(&cl, 1);
    }
    uint8_t z = 0;
    bput(&cl, &z, 1);
    battr(&b, "channels", "chlist", cl.b, (uint32_t)cl.n);
    free(cl.b);
    uint8_t cm = (uint8_t)s->comp;
    battr(&b, "compression", "compression", &cm, 1);
    buf_t box = {0};
    b32(&box, (uint32_t)s->x0), b32(&box, (uint32_t)s->y0), b32(&box, (uint32_t)(s->x0 + s->w - 1));
    b32(&box, (uint32_t)(s->y0 + s->h - 1));
    battr(&b, "dataWindow", "box2i", box.b, 16);
    if (s->disp[2] || s->disp[3]) {
        box.n = 0;
        for (int i = 0; i < 4; ++i)
            b32(&box, (uint32_t)s->disp[i]);
    }
    battr(&b, "displayWindow", "box2i", box.b, 16);
    free(box.b);
    uint8_t lo = 0;
    battr(&b, "lineOrder", "lineOrder", &lo, 1);
    float par = 1.0f;
    battr(&b, "pixelAspectRatio", "float", &par, 4);
    battr(&b, "comments", "string", "made by exr_test", 16);
    size_t ntx = 1, nty, lines = 1;
    if (s->tiled) {
        buf_t td = {0};
        b32(&td, (uint32_t)s->tw), b32(&td, (uint32_t)s->th);
        uint8_t md = (uint8_t)s->mode;
        bput(&td, &md, 1);
        battr(&b, "tiles", "tiledesc", td.b, 9);
        free(td.b);
        ntx = ((size_t)s->w + (size_t)s->tw - 1) / (size_t)s->tw;
        nty = ((size_t)s->h + (size_t)s->th - 1) / (size_t)s->th;
    } else {
        static const size_t lpb[5] = {1, 1, 1, 16, 32};
        lines = lpb[s->comp];
        nty = ((size_t)s->h + lines - 1) / lines;
    }
    bput(&b, &z, 1);
    size_t nchunks = ntx * nty, extra = s->tiled && s->mode ? 3 : 0; /* a MIPMAP level table's further entries */
    size_t table = b.n, packed = 0;
    for (size_t i = 0; i < nchunks + extra; ++i)
        b32(&b, 0), b32(&b, 0);
    for (size_t k = 0; k < nchunks; ++k) {
        uint64_t off = b.n;
        memcpy(b.b + table + 8 * k, &off, 8); /* little-endian host */
        size_t x0, y0, nx, ny;
        if (s->tiled) {
            x0 = (k % ntx) * (size_t)s->tw, y0 = (k / ntx) * (size_t)s->th;
            nx = (size_t)s->w - x0 < (size_t)s->tw ? (size_t)s->w - x0 : (size_t)s->tw;
            ny = (size_t)s->h - y0 < (size_t)s->th ? (size_t)s->h - y0 : (size_t)s->th;
        } else {
            x0 = 0, y0 = k * lines, nx = (size_t)s->w;
            ny = (size_t)s->h - y0 < lines ? (size_t)s->h - y0 : lines;
        }
        buf_t raw = {0};
        for (size_t y = y0; y < y0 + ny; ++y)
            for (int c = 0; c < s->nch; ++c)
                for (size_t x = x0; x < x0 + nx; ++x) {
                    uint32_t u = sample_bits(s, c, (int)x, (int)y);
                    if (sbytes(s->ch[c].type) == 2)
                        b16(&raw, u);
                    else
                        b32(&raw, u);
                }
        buf_t pk = {0};
        if (s->comp == QTOOL_EXR_NONE) {
            bput(&pk, raw.b, raw.n);
        } else if (s->comp == QTOOL_EXR_PIZ) {
            piz_encode(raw.b, s->ch, s->nch, nx, ny, &pk);
        } else {
            uint8_t *t = malloc(raw.n);
            predict(raw.b, raw.n, t);
            if (s->comp == QTOOL_EXR_RLE)
                rle_encode(t, raw.n, &pk);
            else
                zlib_fixed(t, raw.n, &pk);
            free(t);
        }
        packed += s->comp != QTOOL_EXR_NONE && pk.n < raw.n;
        if (s->tiled) {
            b32(&b, (uint32_t)(k % ntx)), b32(&b, (uint32_t)(k / ntx)), b32(&b, 0), b32(&b, 0);
        } else {
            b32(&b, (uint32_t)(s->y0 + (int32_t)y0));
        }
        const buf_t *use = pk.n < raw.n || s->comp == QTOOL_EXR_NONE ? &pk : &raw;
        b32(&b, (uint32_t)use->n);
        bput(&b, use->b, use->n);
        free(raw.b), free(pk.b);
    }
    if (s->comp != QTOOL_EXR_NONE && !s->allow_raw && packed * 4 < nchunks)
        fail_msg("test image: %zu of %zu chunks compressed (%d): the codec would hardly be used", packed, nchunks, s->comp);
    for (size_t i = 0; i < extra; ++i) { /* lower levels: point at the first chunk, never read */
        memcpy(b.b + table + 8 * (nchunks + i), b.b + table, 8);
    }
    return b;
}

/* decodes s's file and checks every pixel against the samples (R G B, or Y copied) */
static void check_spec(const spec_t *s)
{
    buf_t f = build(s);
    qtool_exr_info info;
    float *px = NULL;
    char err[256] = "";
    if (qtool_exr_decode(f.b, f.n, &info, &px, err, sizeof err) != 0)
        fail_msg("comp %d tiled %d: %s", s->comp, s->tiled, err);
    assert_int_equal(info.w, s->w), assert_int_equal(info.h, s->h);
    assert_int_equal(info.data[0], s->x0), assert_int_equal(info.data[1], s->y0);
    assert_int_equal(info.compression, s->comp), assert_int_equal(info.tiled, s->tiled);
    int slot[8], rgb = 0;
    for (int c = 0; c < s->nch; ++c) {
        const char *n = s->ch[c].name;
        slot[c] = !strcmp(n, "R") ? 0 : !strcmp(n, "G") ? 1 : !strcmp(n, "B") ? 2 : !strcmp(n, "Y") ? 3 : -1;
        rgb += slot[c] >= 0 && slot[c] < 3;
    }
    int grey = rgb < 3; /* Y unless all of R, G, B are there */
    assert_int_equal(info.grey, grey);
    for (int y = 0; y < s->h; ++y)
        for (int x = 0; x < s->w; ++x)
            for (int c = 0; c < s->nch; ++c) {
                if (slot[c] < 0 || (slot[c] == 3) != grey)
                    continue;
                float want = sample_value(s, c, x, y);
                for (int k = slot[c] == 3 ? 0 : slot[c]; k <= (slot[c] == 3 ? 2 : slot[c]); ++k) {
                    float got = px[((size_t)y * (size_t)s->w + (size_t)x) * 3 + (size_t)k];
                    if (memcmp(&got, &want, 4) != 0)
                        fail_msg("comp %d tiled %d: pixel (%d, %d) channel %s: %a, expected %a", s->comp, s->tiled, x,
                                 y, s->ch[c].name, (double)got, (double)want);
                }
            }
    free(px);
    free(f.b);
}

static void test_handmade_every_compression(void **state)
{
    (void)state;
    spec_t s = {.nch = 4,
                .ch = {{"A", QTOOL_EXR_HALF}, {"B", QTOOL_EXR_HALF}, {"G", QTOOL_EXR_HALF}, {"R", QTOOL_EXR_HALF}},
                .w = 157, .h = 45, .x0 = -3, .y0 = 5};
    for (int comp = 0; comp <= 4; ++comp) {
        s.comp = comp;
        s.tiled = 0;
        check_spec(&s);
        /* PIZ's bitmap spans the extremes (subnormal to negative values): 8 KiB, so larger tiles */
        s.tiled = 1, s.tw = comp == QTOOL_EXR_PIZ ? 64 : 16, s.th = comp == QTOOL_EXR_PIZ ? 32 : 8;
        check_spec(&s);
    }
}

static void test_handmade_types_orders_y(void **state)
{
    (void)state;
    /* FLOAT and UINT, channels not sorted, a depth channel in between */
    spec_t s = {.nch = 4,
                .ch = {{"G", QTOOL_EXR_FLOAT}, {"Z", QTOOL_EXR_FLOAT}, {"R", QTOOL_EXR_UINT}, {"B", QTOOL_EXR_HALF}},
                .w = 150, .h = 40, .x0 = 100, .y0 = -7};
    for (int comp = 0; comp <= 4; ++comp) {
        s.comp = comp, s.tiled = 0, s.allow_raw = 0;
        check_spec(&s);
        /* MIPMAP: level 0 read; PIZ's tiles this small are stored raw (its bitmap alone is larger) */
        s.tiled = 1, s.tw = 7, s.th = 9, s.mode = 1, s.allow_raw = comp == QTOOL_EXR_PIZ;
        check_spec(&s);
        s.mode = 0;
    }
    /* grey: Y only (and a lone R that is not a full RGB) */
    spec_t y = {.nch = 2, .ch = {{"R", QTOOL_EXR_HALF}, {"Y", QTOOL_EXR_FLOAT}}, .w = 160, .h = 35};
    for (int comp = 0; comp <= 4; ++comp) {
        y.comp = comp;
        check_spec(&y);
    }
}

/* PIZ's 16-bit wavelet: more than 2^14 distinct values in one block */
static void test_handmade_piz_wide(void **state)
{
    (void)state;
    spec_t s = {.nch = 3, .ch = {{"B", QTOOL_EXR_FLOAT}, {"G", QTOOL_EXR_FLOAT}, {"R", QTOOL_EXR_FLOAT}}, .w = 200,
                .h = 32, .comp = QTOOL_EXR_PIZ};
    check_spec(&s);
}

/* chunks that do not shrink are stored raw, as the format says, and read as such */
static void test_raw_chunks_in_compressed_files(void **state)
{
    (void)state;
    spec_t s = {.nch = 1, .ch = {{"Y", QTOOL_EXR_HALF}}, .w = 2, .h = 3, .allow_raw = 1};
    for (int comp = 1; comp <= 4; ++comp) {
        s.comp = comp;
        check_spec(&s);
    }
}

/* ---- files written by OpenEXR (oiiotool) ---------------------------------------------------- */

static const char *fixture_dir(void)
{
    const char *root = getenv("QIBL_ROOT");
    static char dir[512];
    snprintf(dir, sizeof dir, "%s/fixtures/exr", root ? root : ".");
    return dir;
}

static void test_openexr_files(void **state)
{
    (void)state;
    static const struct {
        const char *exr, *pfm;
        int comp, tiled, type;
    } f[] = {
        {"a_none_half", "a", 0, 0, 1},   {"a_none_float", "a", 0, 0, 2},  {"a_rle_half", "a", 1, 0, 1},
        {"a_rle_float", "a", 1, 0, 2},   {"a_zips_half", "a", 2, 0, 1},   {"a_zips_float", "a", 2, 0, 2},
        {"a_zip_half", "a", 3, 0, 1},    {"a_zip_float", "a", 3, 0, 2},   {"at_none_half", "a", 0, 1, 1},
        {"at_none_float", "a", 0, 1, 2}, {"at_rle_half", "a", 1, 1, 1},   {"at_rle_float", "a", 1, 1, 2},
        {"at_zips_half", "a", 2, 1, 1},  {"at_zips_float", "a", 2, 1, 2}, {"at_zip_half", "a", 3, 1, 1},
        {"at_zip_float", "a", 3, 1, 2},  {"b_piz_half", "b", 4, 0, 1},    {"b_piz_float", "b", 4, 0, 2},
        {"bt_piz_half", "b", 4, 1, 1},   {"bt_piz_float", "b", 4, 1, 2},  {"b_rgba_zip_half", "b", 3, 0, 1},
        {"b_window_rle_half", "b", 1, 0, 1}, {"c_y_piz_float", "c", 4, 0, 2},
    };
    char p[600], err[512];
    snprintf(p, sizeof p, "%s/a.pfm", fixture_dir());
    if (access(p, R_OK) != 0) {
        print_message("fixtures/exr absent (run from the repository root or set QIBL_ROOT): skipped\n");
        skip();
    }
    for (size_t i = 0; i < sizeof f / sizeof f[0]; ++i) {
        int w, h, ch;
        float *ref, *px;
        qtool_exr_info info;
        snprintf(p, sizeof p, "%s/%s.pfm", fixture_dir(), f[i].pfm);
        assert_int_equal(qtool_pfm_read(p, &w, &h, &ch, &ref, err, sizeof err), 0);
        snprintf(p, sizeof p, "%s/%s.exr", fixture_dir(), f[i].exr);
        if (qtool_exr_read(p, &info, &px, err, sizeof err) != 0)
            fail_msg("%s", err);
        assert_int_equal(info.w, w), assert_int_equal(info.h, h);
        assert_int_equal(info.compression, f[i].comp), assert_int_equal(info.tiled, f[i].tiled);
        assert_int_equal(info.pixel_type, f[i].type);
        assert_int_equal(info.grey, ch == 1);
        for (size_t k = 0; k < (size_t)w * (size_t)h * 3; ++k) {
            float want = ch == 1 ? ref[k / 3] : ref[k];
            if (memcmp(&px[k], &want, 4) != 0)
                fail_msg("%s: sample %zu (pixel %zu, %zu) is %a, the PFM has %a", f[i].exr, k, (k / 3) % (size_t)w,
                         (k / 3) / (size_t)w, (double)px[k], (double)want);
        }
        if (strstr(f[i].exr, "window")) {
            static const int32_t dw[4] = {5, 7, 68, 54}, disp[4] = {0, 0, 79, 63};
            assert_memory_equal(info.data, dw, sizeof dw);
            assert_memory_equal(info.display, disp, sizeof disp);
        }
        free(ref), free(px);
    }
}

static int have_oiiotool(void)
{
    return system("oiiotool --help > /dev/null 2>&1") == 0;
}

/* ---- a directory of files from elsewhere (QIBL_EXR_DIR) ----------------------------------------- */

typedef struct {
    int oiio, decoded, refused, matched;
    char dir[64];
} walk_t;

/* one file: decoded (then, with oiiotool, equal to OpenEXR's decoding of the data window) or
 * refused with one line; never a crash (the suite runs under the sanitizers too) */
static void one_file(walk_t *wk, const char *path)
{
    qtool_exr_info info;
    float *px;
    char err[512] = "", pfm[128], cmd[2048];
    if (qtool_exr_read(path, &info, &px, err, sizeof err) != 0) {
        if (!*err || strchr(err, '\n'))
            fail_msg("%s: refused without a one-line reason: '%s'", path, err);
        wk->refused++;
        return;
    }
    wk->decoded++;
    if (wk->oiio && !strpbrk(path, "'\\\"$`")) {
        size_t n = (size_t)info.w * (size_t)info.h;
        if (info.grey)
            for (size_t i = 0; i < n; ++i)
                px[i] = px[3 * i];
        snprintf(pfm, sizeof pfm, "%s/ours.pfm", wk->dir);
        assert_int_equal(qtool_pfm_write(pfm, info.w, info.h, info.grey ? 1 : 3, px, err, sizeof err), 0);
        snprintf(cmd, sizeof cmd, "oiiotool '%s' --ch %s --origin +0+0 %s --fail 0 --warn 0 --diff > /dev/null 2>&1",
                 path, info.grey ? "Y" : "R,G,B", pfm);
        if (system(cmd) != 0)
            fail_msg("%s: the decoded pixels differ from OpenEXR's (oiiotool --diff)", path);
        wk->matched++;
        unlink(pfm);
    }
    free(px);
}

static void walk(walk_t *wk, const char *path, int depth)
{
    struct stat st;
    if (depth > 8 || lstat(path, &st) != 0)
        return;
    if (S_ISREG(st.st_mode)) {
        uint8_t head[4] = {0};
        FILE *f = fopen(path, "rb");
        size_t got = f ? fread(head, 1, 4, f) : 0;
        if (f)
            fclose(f);
        const char *ext = strrchr(path, '.');
        if ((got == 4 && qtool_exr_magic(head, 4)) || (ext && !strcmp(ext, ".exr")) || strstr(path, "/Damaged/"))
            one_file(wk, path);
        return;
    }
    if (!S_ISDIR(st.st_mode))
        return;
    DIR *d = opendir(path);
    if (!d)
        return;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.')
            continue;
        char sub[4096];
        snprintf(sub, sizeof sub, "%s/%s", path, e->d_name);
        walk(wk, sub, depth + 1);
    }
    closedir(d);
}

/* QIBL_EXR_DIR: e.g. a checkout of AcademySoftwareFoundation/openexr-images (BSD-3-Clause, not
 * copied here): every file decodes (bit for bit as OpenEXR does, when oiiotool is installed) or is
 * refused by name; its Damaged/ fuzz cases all end in one of the two */
static void test_exr_dir(void **state)
{
    (void)state;
    const char *root = getenv("QIBL_EXR_DIR");
    if (!root || !*root) {
        print_message("QIBL_EXR_DIR not set (a directory of OpenEXR files, e.g. openexr-images): skipped\n");
        skip();
    }
    walk_t wk = {.oiio = have_oiiotool()};
    fu_tmpdir(wk.dir);
    walk(&wk, root, 0);
    rmdir(wk.dir);
    print_message("%s: %d files decoded (%d equal to OpenEXR's decoding), %d refused by name\n", root, wk.decoded,
                  wk.matched, wk.refused);
    assert_true(wk.decoded + wk.refused > 0);
}

/* ---- named errors --------------------------------------------------------------------------- */

static size_t find(const buf_t *b, const char *s, size_t n)
{
    for (size_t i = 0; i + n <= b->n; ++i)
        if (memcmp(b->b + i, s, n) == 0)
            return i;
    fail_msg("'%s' not in the file", s);
    return 0;
}

static void refused(const buf_t *b, const char *needle)
{
    qtool_exr_info info;
    memset(&info, 0x5A, sizeof info);
    float *px = (float *)&info;
    char err[256] = "";
    if (qtool_exr_decode(b->b, b->n, &info, &px, err, sizeof err) != -1)
        fail_msg("accepted, '%s' expected", needle);
    assert_ptr_equal(px, (float *)&info);
    assert_int_equal(info.w, 0x5A5A5A5A);
    if (!strstr(err, needle) || strchr(err, '\n'))
        fail_msg("error '%s' does not say '%s' on one line", err, needle);
}

static void put_le32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v, p[1] = (uint8_t)(v >> 8), p[2] = (uint8_t)(v >> 16), p[3] = (uint8_t)(v >> 24);
}

static void test_named_errors(void **state)
{
    (void)state;
    spec_t s = {.nch = 3, .ch = {{"B", QTOOL_EXR_HALF}, {"G", QTOOL_EXR_HALF}, {"R", QTOOL_EXR_HALF}}, .w = 24, .h = 20};
    buf_t b = build(&s), m = {0};
#define MUT(code, needle)                                                                                      \
    do {                                                                                                       \
        m.n = 0;                                                                                               \
        bput(&m, b.b, b.n);                                                                                    \
        code;                                                                                                  \
        refused(&m, needle);                                                                                   \
    } while (0)
    MUT(m.b[0] = 0x77, "no 76 2f 31 01 magic");
    MUT(m.n = 3, "no 76 2f 31 01 magic");
    MUT(m.b[4] = 1, "version 1");
    MUT(m.b[5] |= 0x10, "multi-part");
    MUT(m.b[5] |= 0x08, "deep");
    MUT(m.b[6] = 1, "unknown OpenEXR version flags");
    MUT(m.b[5] |= 0x02, "tiled file without a tiles attribute");
    MUT(m.n = 40, "attribute channels: 55 bytes, past the end of the file");
    MUT(m.n = 10, "header attribute 1 truncated");
    MUT(m.b[find(&m, "compression\0compression", 24) + 24 + 4] = 5, "compression PXR24 is not read");
    MUT(m.b[find(&m, "compression\0compression", 24) + 24 + 4] = 9, "compression DWAB is not read");
    MUT(m.b[find(&m, "compression\0compression", 24) + 24 + 4] = 77, "compression unknown");
    MUT(memcpy(m.b + find(&m, "channels", 8), "chxnnels", 8), "lacks the required attribute channels");
    MUT(memcpy(m.b + find(&m, "dataWindow", 10), "dataWindoX", 10), "lacks the required attribute dataWindow");
    MUT(memcpy(m.b + find(&m, "lineOrder\0lineOrder", 19) + 10, "lineOrdeX", 9), "lineOrder twice or malformed");
    MUT(m.b[find(&m, "lineOrder\0lineOrder", 19) + 24] = 3, "lineOrder");
    {
        size_t c = find(&b, "chlist", 6) + 7 + 4; /* first channel entry: "B\0" then type */
        MUT(put_le32(m.b + c + 2, 3), "pixel type 3");
        MUT(put_le32(m.b + c + 2 + 8, 2), "subsampled 2 x 1");
        MUT(m.b[c] = 'X', "no R, G, B channels and no Y channel");
        MUT(m.b[c] = 'G', "channel G twice");
    }
    {
        size_t d = find(&b, "dataWindow\0box2i", 17) + 17 + 4;
        MUT(put_le32(m.b + d + 8, (uint32_t)-5), "empty or inverted data window");
        MUT(put_le32(m.b + d + 8, 40000), "above 32768 a side");
        MUT((put_le32(m.b + d + 8, 30000), put_le32(m.b + d + 12, 30000)), "pixel limit");
        MUT(put_le32(m.b + d + 12, 30000), "chunk offset table (30001 entries) runs past the end of the file");
        size_t p = find(&b, "displayWindow\0box2i", 20) + 20 + 4;
        MUT(put_le32(m.b + p, 100), "empty or inverted display window");
    }
    {
        size_t end = find(&b, "made by exr_test", 16) + 16 + 1; /* the table follows the header's NUL */
        MUT(put_le32(m.b + end, 3), "offset 3 outside the file's chunk area");
        MUT(put_le32(m.b + end + 4, 1), "outside the file's chunk area");
        uint64_t off0;
        memcpy(&off0, b.b + end, 8);
        MUT(put_le32(m.b + off0, 9), "chunk 0: y 9, expected 0");
        MUT(put_le32(m.b + off0 + 4, 0), "(or none)");
        MUT(put_le32(m.b + off0 + 4, 1u << 30), "past the end of the file");
        MUT(put_le32(m.b + off0 + 4, 24 * 3 * 2 + 1), "chunk 0: 145 bytes of data for 144 bytes of pixels");
        MUT(put_le32(m.b + off0 + 4, 100), "NONE chunk smaller than its pixels");
        MUT(memcpy(m.b + end + 8, m.b + end, 8), "chunk 1: y 0, expected 1");
        MUT((m.b[off0 + 8] = 0x00, m.b[off0 + 9] = 0x7C), "non-finite sample inf at pixel (0, 0)");
        MUT((m.b[off0 + 8] = 0x01, m.b[off0 + 9] = 0xFE), "non-finite sample nan at pixel (0, 0)");
    }
    free(b.b);
    /* codec damage: RLE, ZIP, PIZ */
    s.comp = QTOOL_EXR_RLE;
    b = build(&s);
    {
        size_t end = find(&b, "made by exr_test", 16) + 17;
        uint64_t off0;
        memcpy(&off0, b.b + end, 8);
        uint32_t n = b.b[off0 + 4] | (uint32_t)b.b[off0 + 5] << 8;
        MUT(put_le32(m.b + off0 + 4, n - 1), "RLE");
        MUT((m.b[off0 + 8] = 0x7F), "RLE data decodes past the chunk's pixels");
    }
    free(b.b);
    s.comp = QTOOL_EXR_ZIP;
    s.ch[0].type = s.ch[1].type = s.ch[2].type = QTOOL_EXR_FLOAT;
    /* a deflated chunk: take the writer's file (its ZIP chunks compress) */
    {
        float img[24 * 20 * 3];
        for (int i = 0; i < 24 * 20 * 3; ++i)
            img[i] = (float)(i / 7) * 0.5f;
        uint8_t *wb;
        size_t wn;
        char err[256];
        assert_int_equal(qtool_exr_encode(24, 20, img, QTOOL_EXR_FLOAT, QTOOL_EXR_ZIP, &wb, &wn, err, sizeof err), 0);
        b.b = wb, b.n = wn, b.cap = wn;
        size_t end = find(&b, "screenWindowWidth\0float", 24) + 24 + 4 + 4 + 1;
        uint64_t off0;
        memcpy(&off0, b.b + end, 8);
        uint32_t n = b.b[off0 + 4] | (uint32_t)b.b[off0 + 5] << 8;
        assert_true(n < 24 * 16 * 12);
        MUT(m.b[off0 + 8] = 0x79, "bad zlib header");
        MUT(m.b[off0 + 8 + n - 1] ^= 1, "Adler-32 mismatch");
        MUT(put_le32(m.b + off0 + 4, n - 5), "chunk 0 (ZIP)");
        free(wb);
    }
    s.comp = QTOOL_EXR_PIZ;
    s.w = 160; /* one block that PIZ shrinks */
    s.ch[0].type = s.ch[1].type = s.ch[2].type = QTOOL_EXR_HALF;
    b = build(&s);
    {
        size_t end = find(&b, "made by exr_test", 16) + 17;
        uint64_t off0;
        memcpy(&off0, b.b + end, 8);
        size_t d = off0 + 8;
        uint32_t lo = b.b[d] | (uint32_t)b.b[d + 1] << 8, hi = b.b[d + 2] | (uint32_t)b.b[d + 3] << 8;
        size_t hz = d + 4 + (lo <= hi ? hi - lo + 1 : 0); /* the Huffman length, then its header */
        MUT((m.b[d + 2] = 0x00, m.b[d + 3] = 0x20), "PIZ bitmap range past 8192 bytes");
        MUT(put_le32(m.b + hz, 1u << 30), "PIZ Huffman data runs past the chunk");
        MUT(put_le32(m.b + hz + 4, 70000), "PIZ Huffman symbol range out of bounds");
        MUT(put_le32(m.b + hz + 4 + 12, 1u << 30), "PIZ Huffman bit count runs past the chunk");
        MUT(put_le32(m.b + hz + 4 + 12, 3), "PIZ Huffman");
        /* the bitmap loses its values: the decoded indices point past it */
        MUT(memset(m.b + d + 4, 0, lo <= hi ? hi - lo + 1 : 0), "PIZ value beyond the bitmap's values");
    }
    free(b.b);
    free(m.b);
#undef MUT
}

/* more channels than the limit, more attributes than the limit */
static void test_limits(void **state)
{
    (void)state;
    spec_t s = {.nch = 3, .ch = {{"B", QTOOL_EXR_HALF}, {"G", QTOOL_EXR_HALF}, {"R", QTOOL_EXR_HALF}}, .w = 4, .h = 2};
    buf_t b = build(&s);
    /* 17 channels: rebuild the chlist by hand */
    buf_t f = {0};
    bput(&f, b.b, 8);
    buf_t cl = {0};
    for (int c = 0; c < QTOOL_EXR_MAX_CHANNELS + 1; ++c) {
        char n[16];
        snprintf(n, sizeof n, "c%02d", c);
        bput(&cl, n, strlen(n) + 1);
        b32(&cl, 1), b32(&cl, 0), b32(&cl, 1), b32(&cl, 1);
    }
    uint8_t z = 0;
    bput(&cl, &z, 1);
    battr(&f, "channels", "chlist", cl.b, (uint32_t)cl.n);
    bput(&f, &z, 1);
    refused(&f, "more than 16 channels");
    f.n = 8;
    for (int i = 0; i < QTOOL_EXR_MAX_ATTRIBUTES + 1; ++i)
        battr(&f, "x", "int", "abcd", 4);
    bput(&f, &z, 1);
    refused(&f, "more than 1024 header attributes");
    free(f.b), free(cl.b), free(b.b);
}

/* ---- the writer ------------------------------------------------------------------------------- */

static void test_writer_round_trip(void **state)
{
    (void)state;
    char dir[64], p[128], src[128], cmd[512], err[256];
    fu_tmpdir(dir);
    snprintf(p, sizeof p, "%s/out.exr", dir);
    snprintf(src, sizeof src, "%s/src.pfm", dir);
    enum { W = 53, H = 37 };
    float *img = malloc(sizeof(float) * W * H * 3);
    for (int i = 0; i < W * H * 3; ++i) {
        int x = (i / 3) % W, y = (i / 3) / W;
        img[i] = (float)half_value(0x3000u + (uint32_t)(x * 7 + y * 3 + (i % 3) * 100) % 0x4000u); /* halves */
        if (x == 3)
            img[i] = -img[i];
    }
    int oiio = have_oiiotool();
    assert_int_equal(qtool_pfm_write(src, W, H, 3, img, err, sizeof err), 0);
    size_t sizes[2][3];
    for (int t = 1; t <= 2; ++t)
        for (int c = 0; c < 3; ++c) {
            int comp = c == 0 ? QTOOL_EXR_NONE : c == 1 ? QTOOL_EXR_ZIPS : QTOOL_EXR_ZIP;
            assert_int_equal(qtool_exr_write(p, W, H, img, t, comp, err, sizeof err), 0);
            qtool_exr_info info;
            float *back;
            assert_int_equal(qtool_exr_read(p, &info, &back, err, sizeof err), 0);
            assert_int_equal(info.compression, comp), assert_int_equal(info.pixel_type, t);
            assert_memory_equal(back, img, sizeof(float) * W * H * 3);
            free(back);
            FILE *fp = fopen(p, "rb");
            fseek(fp, 0, SEEK_END);
            sizes[t - 1][c] = (size_t)ftell(fp);
            fclose(fp);
            if (oiio) { /* the OpenEXR library's reading of the file, compared with the PFM */
                snprintf(cmd, sizeof cmd, "oiiotool %s %s --fail 0 --warn 0 --diff > /dev/null 2>&1", p, src);
                if (system(cmd) != 0)
                    fail_msg("oiiotool reads %s (type %d, compression %d) differently from %s", p, t, comp, src);
            }
        }
    if (!oiio)
        print_message("oiiotool not installed: the writer's files were not read by OpenEXR\n");
    /* the deflate is used: ZIP and ZIPS files are smaller than NONE ones */
    for (int t = 0; t < 2; ++t)
        assert_true(sizes[t][2] < sizes[t][0] && sizes[t][1] < sizes[t][0]);
    /* refusals: nothing written */
    unlink(p);
    img[5] = NAN;
    assert_int_equal(qtool_exr_write(p, W, H, img, QTOOL_EXR_FLOAT, QTOOL_EXR_ZIP, err, sizeof err), -1);
    assert_non_null(strstr(err, "is not finite"));
    assert_non_null(strstr(err, p));
    img[5] = 65520.0f;
    assert_int_equal(qtool_exr_write(p, W, H, img, QTOOL_EXR_HALF, QTOOL_EXR_ZIP, err, sizeof err), -1);
    assert_non_null(strstr(err, "half range"));
    assert_int_equal(qtool_exr_write(p, W, H, img, QTOOL_EXR_FLOAT, QTOOL_EXR_PIZ, err, sizeof err), -1);
    assert_non_null(strstr(err, "compression 4 not written"));
    assert_int_equal(qtool_exr_write(p, 0, H, img, QTOOL_EXR_FLOAT, QTOOL_EXR_ZIP, err, sizeof err), -1);
    assert_int_equal(access(p, F_OK), -1);
    unlink(src);
    rmdir(dir);
    free(img);
}

/* HALF rounding: every pair of neighbouring positive halves a < b, written just below, at and just
 * above their midpoint: below gives a, above b, the midpoint the even one; 65519.99 gives 65504 */
static void test_writer_half_rounding(void **state)
{
    (void)state;
    enum { N = 0x7BFF };
    float *img = malloc(sizeof(float) * N * 3);
    for (uint32_t h = 0; h < N; ++h) {
        double a = half_value(h), b = half_value(h + 1), mid = (a + b) / 2;
        img[3 * h] = nextafterf((float)mid, 0.0f);
        img[3 * h + 1] = (float)mid;
        img[3 * h + 2] = nextafterf((float)mid, INFINITY);
        assert_true((double)(float)mid == mid);
    }
    img[3 * (N - 1) + 2] = 65519.99f;
    uint8_t *f;
    size_t n;
    char err[256];
    assert_int_equal(qtool_exr_encode(N, 1, img, QTOOL_EXR_HALF, QTOOL_EXR_NONE, &f, &n, err, sizeof err), 0);
    float *back;
    qtool_exr_info info;
    assert_int_equal(qtool_exr_decode(f, n, &info, &back, err, sizeof err), 0);
    for (uint32_t h = 0; h < N; ++h) {
        float lo = (float)half_value(h), hi = (float)half_value(h + 1), even = (h & 1) ? hi : lo;
        float want[3] = {lo, even, h == N - 1 ? (float)half_value(N) : hi};
        for (int k = 0; k < 3; ++k)
            if (back[3 * h + (uint32_t)k] != want[k])
                fail_msg("half %#x case %d: %a written as %a, expected %a", h, k, (double)img[3 * h + (uint32_t)k],
                         (double)back[3 * h + (uint32_t)k], (double)want[k]);
    }
    free(back), free(f), free(img);
}

/* ---- the probe path: qtool_hdr_read* take an EXR by its magic --------------------------------- */

static void test_hdr_reader_takes_exr(void **state)
{
    (void)state;
    char dir[64], p[128], err[256];
    fu_tmpdir(dir);
    snprintf(p, sizeof p, "%s/probe.hdr", dir); /* the name says .hdr: the magic decides */
    enum { W = 16, H = 8 };
    float img[W * H * 3];
    for (int i = 0; i < W * H * 3; ++i)
        img[i] = (float)((i * 37) % 101) * 0.125f - (i % 17 == 0 ? 1.0f : 0.0f);
    assert_int_equal(qtool_exr_write(p, W, H, img, QTOOL_EXR_FLOAT, QTOOL_EXR_ZIP, err, sizeof err), 0);
    int w, h;
    float *rgb;
    if (qtool_hdr_read(p, &w, &h, &rgb, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(w, W), assert_int_equal(h, H);
    float clamped[W * H * 3];
    for (int i = 0; i < W * H * 3; ++i)
        clamped[i] = img[i] < 0 ? 0.0f : img[i];
    assert_memory_equal(rgb, clamped, sizeof clamped);
    free(rgb);
    uint8_t *rgbe, want[W * H * 4];
    assert_int_equal(qtool_hdr_read_rgbe(p, &w, &h, &rgbe, err, sizeof err), 0);
    qtool_probe_layout_rgbe_encode(clamped, W * H, want);
    assert_memory_equal(rgbe, want, sizeof want);
    free(rgbe);
    /* a damaged EXR is named as such */
    FILE *fp = fopen(p, "r+b");
    fseek(fp, 4, SEEK_SET);
    fputc(9, fp);
    fclose(fp);
    assert_int_equal(qtool_hdr_read_rgbe(p, &w, &h, &rgbe, err, sizeof err), -1);
    assert_non_null(strstr(err, "OpenEXR version 9"));
    assert_non_null(strstr(err, p));
    unlink(p);
    rmdir(dir);
}

/* ---- hostile files ---------------------------------------------------------------------------- */

static int rd_exr(const char *path, char *err, size_t errlen)
{
    float *px;
    int rc = qtool_exr_read(path, NULL, &px, err, errlen);
    if (rc == 0)
        free(px);
    return rc;
}

static void test_zeros_not_read(void **state)
{
    (void)state;
    fu_check_zeros_not_read(rd_exr, (size_t)64 << 20, "no 76 2f 31 01 magic", QTOOL_EXR_MAX_FILE_BYTES);
}

static void test_not_regular_and_short(void **state)
{
    (void)state;
    fu_check_not_regular(rd_exr);
    fu_check_empty_and_one_byte(rd_exr, 0x76, "too short");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_zeros_not_read),
        cmocka_unit_test(test_handmade_every_compression),
        cmocka_unit_test(test_handmade_types_orders_y),
        cmocka_unit_test(test_handmade_piz_wide),
        cmocka_unit_test(test_raw_chunks_in_compressed_files),
        cmocka_unit_test(test_openexr_files),
        cmocka_unit_test(test_exr_dir),
        cmocka_unit_test(test_named_errors),
        cmocka_unit_test(test_limits),
        cmocka_unit_test(test_writer_round_trip),
        cmocka_unit_test(test_writer_half_rounding),
        cmocka_unit_test(test_hdr_reader_takes_exr),
        cmocka_unit_test(test_not_regular_and_short),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
