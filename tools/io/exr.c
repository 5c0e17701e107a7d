/*
 * io/exr.c - OpenEXR reader and writer (io/exr.h).
 *
 * Layout read (all little-endian): magic 76 2f 31 01, version word (2 | flags << 8), attributes
 * (name NUL, type NUL, int32 size, value) up to an empty name, the chunk offset table (uint64 per
 * block of lines, or per tile of level 0 first), then chunks: int32 y (scanline) or int32 tx, ty,
 * lx, ly (tile), int32 size, data. A chunk's raw pixels are, line by line, each channel's samples for
 * the line in the channel list's order. A chunk whose data is as large as its raw pixels is stored
 * raw whatever the file's compression.
 * RLE and ZIP(S) code a transformed copy: bytes split into even and odd halves, then each byte
 * replaced by its difference from the previous one plus 128. PIZ: a bitmap of the 16-bit values
 * present, values renumbered through it, a 2D Haar-like wavelet per channel, then a Huffman code
 * with a run-length pseudo-symbol.
 */
#include "io/exr.h"
#include "io/atomic.h"
#include "io/file.h"
#include "io/zlib.h"

#include <fcntl.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "qtool.h"

static uint32_t rd32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static int32_t rds32(const uint8_t *p)
{
    uint32_t u = rd32(p);
    return u <= INT32_MAX ? (int32_t)u : (int32_t)(u - 2147483648u) - INT32_MAX - 1; /* no cast of a big unsigned */
}

static uint64_t rd64(const uint8_t *p)
{
    return (uint64_t)rd32(p) | (uint64_t)rd32(p + 4) << 32;
}

int qtool_exr_magic(const uint8_t *head, size_t n)
{
    return n >= 4 && head[0] == 0x76 && head[1] == 0x2f && head[2] == 0x31 && head[3] == 0x01;
}

int qtool_exr_sniff(const char *path)
{
    struct stat st;
    if (stat(path, &st) != 0 || !S_ISREG(st.st_mode))
        return 0;
    int fd = open(path, O_RDONLY | O_NONBLOCK);
    if (fd < 0)
        return 0;
    uint8_t b[4];
    ssize_t r = read(fd, b, 4);
    close(fd);
    return r == 4 && qtool_exr_magic(b, 4);
}

/* ---- half <-> float -------------------------------------------------------------------------- */

static float half_to_float(uint16_t h)
{
    uint32_t s = (uint32_t)(h >> 15) << 31, e = (h >> 10) & 31u, m = h & 0x3FFu, u;
    if (e == 0) {
        if (m == 0) {
            u = s;
        } else { /* subnormal: normalise */
            e = 113;
            while (!(m & 0x400u))
                m <<= 1, --e;
            u = s | e << 23 | (m & 0x3FFu) << 13;
        }
    } else if (e == 31) {
        u = s | 0x7F800000u | m << 13;
    } else {
        u = s | (e + 112) << 23 | m << 13;
    }
    float f;
    memcpy(&f, &u, 4);
    return f;
}

/* nearest half, ties to even; -1 if the value is NaN, infinite or rounds past 65504 */
static int float_to_half(float f, uint16_t *out)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    uint32_t s = (u >> 16) & 0x8000u, a = u & 0x7FFFFFFFu;
    if (a >= 0x477FF000u) /* 65520 and above (and Inf, NaN) round past the largest half */
        return -1;
    if (a < 0x38800000u) { /* below 2^-14: subnormal half (or zero) */
        if (a < 0x33000000u) { /* below 2^-25: rounds to zero (2^-25 itself is a tie, to even 0) */
            *out = (uint16_t)s;
            return 0;
        }
        uint32_t m = (a & 0x7FFFFFu) | 0x800000u, e = a >> 23; /* value m 2^(e - 150) */
        uint32_t shift = 126 - e;                             /* to units of 2^-24: 14 .. 24 */
        uint32_t q = m >> shift, rem = m & ((1u << shift) - 1), half = 1u << (shift - 1);
        if (rem > half || (rem == half && (q & 1)))
            ++q;
        *out = (uint16_t)(s | q);
        return 0;
    }
    uint32_t q = ((a >> 13) - (112u << 10)), rem = a & 0x1FFFu; /* exponent rebased by 127 - 15 */
    if (rem > 0x1000u || (rem == 0x1000u && (q & 1)))
        ++q; /* a carry into the exponent is the right rounding */
    *out = (uint16_t)(s | q);
    return 0;
}

/* ---- the byte transforms of RLE and ZIP ------------------------------------------------------- */

/* undo the predictor, then the even/odd split: t (n bytes) -> out */
static void unpredict_merge(uint8_t *t, size_t n, uint8_t *out)
{
    for (size_t i = 1; i < n; ++i)
        t[i] = (uint8_t)(t[i - 1] + t[i] - 128);
    size_t h = (n + 1) / 2;
    for (size_t i = 0; i < n; ++i)
        out[i] = (i & 1) ? t[h + i / 2] : t[i / 2];
}

static void split_predict(const uint8_t *in, size_t n, uint8_t *t)
{
    size_t h = (n + 1) / 2;
    for (size_t i = 0; i < n; ++i)
        t[(i & 1) ? h + i / 2 : i / 2] = in[i];
    for (size_t i = n; i-- > 1;)
        t[i] = (uint8_t)(t[i] - t[i - 1] + 128);
}

/* OpenEXR's RLE: a signed count byte c; c < 0: -c literal bytes follow; else one byte repeated c + 1 times */
static const char *unrle(const uint8_t *in, size_t n, uint8_t *out, size_t cap)
{
    size_t o = 0, i = 0;
    while (i < n) {
        uint8_t c = in[i++];
        if (c & 0x80) {
            size_t k = 256u - c;
            if (k > n - i)
                return "RLE literal runs past the chunk";
            if (k > cap - o)
                return "RLE data decodes past the chunk's pixels";
            memcpy(out + o, in + i, k);
            i += k, o += k;
        } else {
            size_t k = (size_t)c + 1;
            if (i >= n)
                return "RLE run without its byte";
            if (k > cap - o)
                return "RLE data decodes past the chunk's pixels";
            memset(out + o, in[i++], k);
            o += k;
        }
    }
    return o == cap ? NULL : "RLE data decodes short of the chunk's pixels";
}

/* ---- PIZ ---------------------------------------------------------------------------------------- */

#define HUF_SYMS 65537 /* 65536 values and the run-length pseudo-symbol */
#define HUF_MAXLEN 58

typedef struct {
    uint16_t lut[65536]; /* renumbered value -> value */
    uint32_t sym[HUF_SYMS];
    uint8_t len[HUF_SYMS];
    uint32_t sorted[HUF_SYMS]; /* symbols by (length, symbol) */
} piz_work;

typedef struct {
    const uint8_t *p;
    size_t nbits, pos;
} bitr;

static int getbits(bitr *b, int n, uint64_t *v)
{
    if ((size_t)n > b->nbits - b->pos)
        return -1;
    uint64_t r = 0;
    for (int i = 0; i < n; ++i, ++b->pos)
        r = r << 1 | ((b->p[b->pos >> 3] >> (7 - (b->pos & 7))) & 1u);
    *v = r;
    return 0;
}

static void wdec14(uint16_t l, uint16_t h, uint16_t *a, uint16_t *b)
{
    int32_t ls = l < 0x8000u ? (int32_t)l : (int32_t)l - 65536, hi = h < 0x8000u ? (int32_t)h : (int32_t)h - 65536;
    int32_t odd = (int32_t)(h & 1u), ai = ls + odd + (hi - odd) / 2; /* (hi - odd) / 2 = floor(hi / 2) */
    *a = (uint16_t)((uint32_t)ai & 0xFFFFu);
    *b = (uint16_t)((uint32_t)(ai - hi) & 0xFFFFu);
}

static void wdec16(uint16_t l, uint16_t h, uint16_t *a, uint16_t *b)
{
    uint32_t bb = ((uint32_t)l - (h >> 1)) & 0xFFFFu;
    *b = (uint16_t)bb;
    *a = (uint16_t)((h + bb - 32768u) & 0xFFFFu);
}

static void wdec(int w14, uint16_t l, uint16_t h, uint16_t *a, uint16_t *b)
{
    if (w14)
        wdec14(l, h, a, b);
    else
        wdec16(l, h, a, b);
}

/* inverse wavelet of an nx x ny array at in, ox apart along x and oy along y; levels from the
 * coarsest (the largest power of two <= min(nx, ny)) down to 1 */
static void wav_decode(uint16_t *in, size_t nx, size_t ox, size_t ny, size_t oy, int w14)
{
    size_t n = nx < ny ? nx : ny, p = 1, p2;
    while (p <= n)
        p <<= 1;
    p >>= 1;
    p2 = p;
    p >>= 1;
    while (p >= 1) {
        size_t oy1 = oy * p, oy2 = oy * p2, ox1 = ox * p, ox2 = ox * p2, ey = oy * (ny - p2), py = 0;
        uint16_t i00, i01, i10, i11;
        for (; py <= ey; py += oy2) {
            size_t px = py, ex = py + ox * (nx - p2);
            for (; px <= ex; px += ox2) {
                size_t p01 = px + ox1, p10 = px + oy1, p11 = p10 + ox1;
                wdec(w14, in[px], in[p10], &i00, &i10);
                wdec(w14, in[p01], in[p11], &i01, &i11);
                wdec(w14, i00, i01, &in[px], &in[p01]);
                wdec(w14, i10, i11, &in[p10], &in[p11]);
            }
            if (nx & p) {
                size_t p10 = px + oy1;
                wdec(w14, in[px], in[p10], &i00, &in[p10]);
                in[px] = i00;
            }
        }
        if (ny & p) {
            size_t px = py, ex = py + ox * (nx - p2);
            for (; px <= ex; px += ox2) {
                size_t p01 = px + ox1;
                wdec(w14, in[px], in[p01], &i00, &in[p01]);
                in[px] = i00;
            }
        }
        p2 = p;
        p >>= 1;
    }
}

/* Huffman stream (20-byte header, packed code lengths, code bits) -> exactly nraw values */
static const char *huf_decode(piz_work *wk, const uint8_t *in, size_t n, uint16_t *out, size_t nraw)
{
    if (n < 20)
        return "PIZ Huffman header truncated";
    uint32_t im = rd32(in), iM = rd32(in + 4), nbits = rd32(in + 12);
    if (im >= HUF_SYMS || iM >= HUF_SYMS || im > iM)
        return "PIZ Huffman symbol range out of bounds";
    bitr b = {in + 20, (n - 20) * 8, 0};
    /* code lengths, 6 bits each, with runs of zeros: 59..62 -> 2..5 zeros, 63 + 8 bits -> 6..261 */
    size_t ns = 0;
    uint32_t count[HUF_MAXLEN + 1] = {0};
    for (uint32_t i = im; i <= iM;) {
        uint64_t l, z;
        if (getbits(&b, 6, &l) != 0)
            return "PIZ Huffman code table truncated";
        if (l == 63) {
            if (getbits(&b, 8, &z) != 0)
                return "PIZ Huffman code table truncated";
            z += 6;
        } else if (l >= 59) {
            z = l - 57;
        } else {
            if (l) {
                wk->sym[ns] = i, wk->len[ns] = (uint8_t)l, ++ns;
                count[l]++;
            }
            ++i;
            continue;
        }
        if (z > (uint64_t)iM + 1 - i)
            return "PIZ Huffman zero run past the symbol range";
        i += (uint32_t)z;
    }
    /* canonical codes: the longest codes numbered first from 0, each shorter length from half the end of the longer */
    uint64_t start[HUF_MAXLEN + 1] = {0}, c = 0;
    for (int l = HUF_MAXLEN; l > 0; --l) {
        uint64_t nc = (c + count[l]) >> 1;
        start[l] = c;
        c = nc;
    }
    size_t first[HUF_MAXLEN + 2];
    first[1] = 0;
    for (int l = 1; l <= HUF_MAXLEN; ++l)
        first[l + 1] = first[l] + count[l];
    {
        size_t at[HUF_MAXLEN + 1];
        for (int l = 1; l <= HUF_MAXLEN; ++l)
            at[l] = first[l];
        for (size_t k = 0; k < ns; ++k) /* symbols come in increasing order: the sort is stable */
            wk->sorted[at[wk->len[k]]++] = wk->sym[k];
    }
    size_t data_bytes = (b.pos + 7) / 8;
    if ((uint64_t)nbits > (uint64_t)(n - 20 - data_bytes) * 8)
        return "PIZ Huffman bit count runs past the chunk";
    bitr d = {in + 20 + data_bytes, nbits, 0};
    size_t o = 0;
    while (d.pos < d.nbits) {
        uint64_t code = 0;
        uint32_t s = 0;
        int l = 0, found = 0;
        while (!found) {
            if (++l > HUF_MAXLEN || d.pos >= d.nbits)
                return l > HUF_MAXLEN ? "PIZ Huffman code not in the table" : "PIZ Huffman code cut short";
            code = code << 1 | ((d.p[d.pos >> 3] >> (7 - (d.pos & 7))) & 1u);
            ++d.pos;
            if (count[l] && code >= start[l] && code - start[l] < count[l]) {
                s = wk->sorted[first[l] + (size_t)(code - start[l])];
                found = 1;
            }
        }
        if (s == iM) { /* run: the previous value repeated 0..255 more times */
            uint64_t r;
            if (getbits(&d, 8, &r) != 0)
                return "PIZ Huffman run count cut short";
            if (o == 0)
                return "PIZ Huffman run with no value before it";
            if (r > nraw - o)
                return "PIZ Huffman data gives more values than the chunk holds";
            for (uint64_t k = 0; k < r; ++k, ++o)
                out[o] = out[o - 1];
        } else {
            if (o == nraw)
                return "PIZ Huffman data gives more values than the chunk holds";
            out[o++] = (uint16_t)s;
        }
    }
    return o == nraw ? NULL : "PIZ Huffman data gives fewer values than the chunk holds";
}

typedef struct {
    int type; /* QTOOL_EXR_UINT / HALF / FLOAT */
    int slot; /* 0 R, 1 G, 2 B, 3 Y, -1 not read */
    char name[256];
} channel;

static size_t type_bytes(int type)
{
    return type == QTOOL_EXR_HALF ? 2 : 4;
}

/* PIZ chunk (n bytes) -> raw (nraw bytes: ny lines of nx pixels of the channels) */
static const char *unpiz(piz_work *wk, const uint8_t *in, size_t n, const channel *ch, int nch, size_t nx, size_t ny,
                         uint16_t *tmp, uint8_t *raw, size_t nraw)
{
    if (n < 4)
        return "PIZ bitmap range truncated";
    size_t lo = in[0] | (size_t)in[1] << 8, hi = in[2] | (size_t)in[3] << 8, p = 4;
    if (hi >= 8192)
        return "PIZ bitmap range past 8192 bytes";
    /* values present: bit v of the bitmap (bytes lo..hi); 0 is always present */
    size_t k = 0;
    wk->lut[k++] = 0;
    if (lo <= hi) {
        if (hi - lo + 1 > n - p)
            return "PIZ bitmap runs past the chunk";
        for (size_t i = lo; i <= hi; ++i)
            for (unsigned bit = 0; bit < 8; ++bit) {
                size_t v = i * 8 + bit;
                if (v && (in[p + i - lo] >> bit & 1u))
                    wk->lut[k++] = (uint16_t)v;
            }
        p += hi - lo + 1;
    }
    size_t maxv = k - 1;
    if (n - p < 4)
        return "PIZ Huffman length missing";
    uint32_t hl = rd32(in + p);
    p += 4;
    if (hl > n - p)
        return "PIZ Huffman data runs past the chunk";
    size_t nw = nraw / 2;
    const char *why = huf_decode(wk, in + p, hl, tmp, nw);
    if (why)
        return why;
    /* each channel's block: ny rows of nx samples of (2 or 4 bytes) = size 16-bit words */
    size_t at = 0;
    for (int c = 0; c < nch; ++c) {
        size_t size = type_bytes(ch[c].type) / 2;
        for (size_t j = 0; j < size; ++j)
            wav_decode(tmp + at + j, nx, size, ny, nx * size, maxv < (1u << 14));
        at += nx * ny * size;
    }
    for (size_t i = 0; i < nw; ++i) {
        if (tmp[i] > maxv) /* the wavelet gives back the renumbered values: one past them is damage */
            return "PIZ value beyond the bitmap's values";
        tmp[i] = wk->lut[tmp[i]];
    }
    /* back to line-interleaved order, little-endian bytes */
    size_t o = 0, cstart = 0;
    for (size_t y = 0; y < ny; ++y) {
        cstart = 0;
        for (int c = 0; c < nch; ++c) {
            size_t words = nx * (type_bytes(ch[c].type) / 2);
            const uint16_t *src = tmp + cstart + y * words;
            for (size_t i = 0; i < words; ++i, o += 2)
                raw[o] = (uint8_t)(src[i] & 0xFF), raw[o + 1] = (uint8_t)(src[i] >> 8);
            cstart += words * ny;
        }
    }
    return NULL;
}

/* ---- reader ------------------------------------------------------------------------------------ */

static const char *const comp_names[10] = {"NONE", "RLE", "ZIPS", "ZIP", "PIZ", "PXR24", "B44", "B44A", "DWAA", "DWAB"};

/* a NUL-terminated name of 1..255 bytes at buf[*pos], inside end; its length, or -1 */
static int cstr(const uint8_t *buf, size_t end, size_t *pos, const char **s)
{
    size_t i = *pos;
    while (i < end && buf[i] && i - *pos < 256)
        ++i;
    if (i >= end || buf[i] || i == *pos)
        return -1;
    *s = (const char *)buf + *pos;
    int n = (int)(i - *pos);
    *pos = i + 1;
    return n;
}

/* a printable copy of an attribute or channel name for messages */
static const char *shown(const char *s, char out[40])
{
    size_t i = 0;
    for (; s[i] && i < 32; ++i)
        out[i] = s[i] >= 0x20 && s[i] < 0x7F ? s[i] : '?';
    out[i] = '\0';
    return out;
}

typedef struct {
    const uint8_t *buf;
    size_t len;
    channel ch[QTOOL_EXR_MAX_CHANNELS];
    int nch;
    size_t bpp; /* raw bytes per pixel, all channels */
    int comp, tiled, lines;
    int32_t xmin, ymin;
    size_t w, h, tw, th, ntx, nty, nchunks, table;
} exr_file;

/* what the header's attributes say, before it is checked as a whole */
typedef struct {
    int have_ch, have_comp, have_dw, have_disp, have_lo, have_tiles;
    int32_t dw[4], disp[4];
    int lo, mode;
    uint32_t txs, tys;
} exr_attrs;

/* the chlist attribute: full-resolution UINT, HALF or FLOAT channels */
static int read_chlist(exr_file *f, const uint8_t *v, uint32_t sz, char *err, size_t errlen)
{
    char sh[40];
    size_t q = 0;
    while (q < sz && v[q]) {
        const char *cn;
        if (f->nch == QTOOL_EXR_MAX_CHANNELS)
            return qtool_errf(err, errlen, "more than %d channels", QTOOL_EXR_MAX_CHANNELS);
        if (cstr(v, sz, &q, &cn) < 0 || sz - q < 16)
            return qtool_errf(err, errlen, "channel list truncated");
        channel *c = &f->ch[f->nch++];
        memcpy(c->name, cn, strlen(cn) + 1);
        uint32_t t = rd32(v + q);
        int32_t xs = rds32(v + q + 8), ys = rds32(v + q + 12);
        q += 16;
        if (t > 2)
            return qtool_errf(err, errlen, "channel %s: pixel type %u (0 UINT, 1 HALF, 2 FLOAT)", shown(cn, sh), (unsigned)t);
        if (xs != 1 || ys != 1)
            return qtool_errf(err, errlen, "channel %s: subsampled %d x %d (only full-resolution channels are read)",
                        shown(cn, sh), (int)xs, (int)ys);
        c->type = (int)t;
        c->slot = -1;
        f->bpp += type_bytes(c->type);
    }
    if (q >= sz)
        return qtool_errf(err, errlen, "channel list truncated (no terminating NUL)");
    return 0;
}

/* one attribute (name, type, sz bytes at v): the known ones kept in a, the rest skipped */
static int read_attr(exr_file *f, exr_attrs *at, const char *name, const char *type, const uint8_t *v, uint32_t sz,
                     char *err, size_t errlen)
{
#define ATTR(n_, t_) (strcmp(name, n_) != 0 ? 0 : strcmp(type, t_) == 0 ? 1 : -1) /* -1: known name, wrong type */
    int a;
    if ((a = ATTR("channels", "chlist")) != 0) {
        if (a < 0 || at->have_ch)
            return qtool_errf(err, errlen, "attribute channels twice or not of type chlist");
        at->have_ch = 1;
        return read_chlist(f, v, sz, err, errlen);
    } else if ((a = ATTR("compression", "compression")) != 0) {
        if (a < 0 || at->have_comp || sz != 1)
            return qtool_errf(err, errlen, "attribute compression twice or malformed");
        at->have_comp = 1;
        f->comp = v[0];
    } else if ((a = ATTR("dataWindow", "box2i")) != 0 || (a = ATTR("displayWindow", "box2i")) != 0) {
        int is_data = name[1] == 'a';
        if (a < 0 || sz != 16 || (is_data ? at->have_dw : at->have_disp))
            return qtool_errf(err, errlen, "attribute %s twice or malformed", name);
        int32_t *b = is_data ? at->dw : at->disp;
        for (int i = 0; i < 4; ++i)
            b[i] = rds32(v + 4 * i);
        *(is_data ? &at->have_dw : &at->have_disp) = 1;
    } else if ((a = ATTR("lineOrder", "lineOrder")) != 0) {
        if (a < 0 || sz != 1 || at->have_lo || v[0] > 2)
            return qtool_errf(err, errlen, "attribute lineOrder twice or malformed (0, 1 or 2)");
        at->have_lo = 1;
        at->lo = v[0];
    } else if ((a = ATTR("tiles", "tiledesc")) != 0) {
        if (a < 0 || sz != 9 || at->have_tiles)
            return qtool_errf(err, errlen, "attribute tiles twice or malformed");
        at->have_tiles = 1;
        at->txs = rd32(v), at->tys = rd32(v + 4), at->mode = v[8];
    }
#undef ATTR
    return 0;
}

/* the attributes from *pos to the header's closing NUL (*pos ends past it) */
static int read_attrs(exr_file *f, size_t *pos, exr_attrs *at, char *err, size_t errlen)
{
    const uint8_t *buf = f->buf;
    size_t len = f->len;
    int nattr = 0;
    char sh[40];
    for (;;) {
        if (*pos >= len)
            return qtool_errf(err, errlen, "header truncated (no end of attributes)");
        if (buf[*pos] == 0) {
            ++*pos;
            return 0;
        }
        if (++nattr > QTOOL_EXR_MAX_ATTRIBUTES)
            return qtool_errf(err, errlen, "more than %d header attributes", QTOOL_EXR_MAX_ATTRIBUTES);
        const char *name, *type;
        if (cstr(buf, len, pos, &name) < 0 || cstr(buf, len, pos, &type) < 0 || len - *pos < 4)
            return qtool_errf(err, errlen, "header attribute %d truncated or its name longer than 255 bytes", nattr);
        uint32_t sz = rd32(buf + *pos);
        *pos += 4;
        if (sz > len - *pos)
            return qtool_errf(err, errlen, "attribute %s: %u bytes, past the end of the file", shown(name, sh), (unsigned)sz);
        if (read_attr(f, at, name, type, buf + *pos, sz, err, errlen) != 0)
            return -1;
        *pos += sz;
    }
}

/* the required attributes present, the compression read, the windows sane and within the caps */
static int check_windows(exr_file *f, const exr_attrs *at, int tiled_flag, char *err, size_t errlen)
{
    const int32_t *dw = at->dw, *disp = at->disp;
    if (!at->have_ch || !at->have_comp || !at->have_dw || !at->have_disp || !at->have_lo)
        return qtool_errf(err, errlen, "header lacks the required attribute %s",
                    !at->have_ch ? "channels" : !at->have_comp ? "compression" : !at->have_dw ? "dataWindow" : !at->have_disp ? "displayWindow" : "lineOrder");
    if (f->nch == 0)
        return qtool_errf(err, errlen, "no channels");
    if (f->comp > 4)
        return qtool_errf(err, errlen, "compression %s is not read (NONE, RLE, ZIPS, ZIP and PIZ are)",
                    f->comp < 10 ? comp_names[f->comp] : "unknown");
    if (tiled_flag != at->have_tiles)
        return qtool_errf(err, errlen, tiled_flag ? "tiled file without a tiles attribute" : "tiles attribute in a scanline file");
    if (dw[2] < dw[0] || dw[3] < dw[1] || disp[2] < disp[0] || disp[3] < disp[1])
        return qtool_errf(err, errlen, "empty or inverted %s window (%d,%d)-(%d,%d)", dw[2] < dw[0] || dw[3] < dw[1] ? "data" : "display",
                    (int)(dw[2] < dw[0] || dw[3] < dw[1] ? dw : disp)[0], (int)(dw[2] < dw[0] || dw[3] < dw[1] ? dw : disp)[1],
                    (int)(dw[2] < dw[0] || dw[3] < dw[1] ? dw : disp)[2], (int)(dw[2] < dw[0] || dw[3] < dw[1] ? dw : disp)[3]);
    int64_t w = (int64_t)dw[2] - dw[0] + 1, h = (int64_t)dw[3] - dw[1] + 1;
    if (w > QTOOL_EXR_MAX_DIM || h > QTOOL_EXR_MAX_DIM)
        return qtool_errf(err, errlen, "data window %lld x %lld, above %u a side (QTOOL_EXR_MAX_DIM)", (long long)w, (long long)h,
                    (unsigned)QTOOL_EXR_MAX_DIM);
    if ((uint64_t)w * (uint64_t)h > QTOOL_EXR_MAX_PIXELS)
        return qtool_errf(err, errlen, "data window %lld x %lld pixels, above the %lu-pixel limit (QTOOL_EXR_MAX_PIXELS)",
                    (long long)w, (long long)h, (unsigned long)QTOOL_EXR_MAX_PIXELS);
    f->w = (size_t)w, f->h = (size_t)h, f->xmin = dw[0], f->ymin = dw[1];
    return 0;
}

/* R, G, B (slots 0..2) or else Y (slot 3): *pic the channel whose type is reported */
static int picture_channels(exr_file *f, int *grey, int *pic, char *err, size_t errlen)
{
    int ri = -1, gi = -1, bi = -1, yi = -1;
    for (int i = 0; i < f->nch; ++i) {
        const char *n = f->ch[i].name;
        int *slot = !strcmp(n, "R") ? &ri : !strcmp(n, "G") ? &gi : !strcmp(n, "B") ? &bi : !strcmp(n, "Y") ? &yi : NULL;
        if (slot && *slot >= 0)
            return qtool_errf(err, errlen, "channel %s twice", n);
        if (slot)
            *slot = i;
    }
    *grey = !(ri >= 0 && gi >= 0 && bi >= 0);
    if (*grey && yi < 0)
        return qtool_errf(err, errlen, "no R, G, B channels and no Y channel (the picture channels)");
    if (*grey) {
        f->ch[yi].slot = 3;
    } else {
        f->ch[ri].slot = 0, f->ch[gi].slot = 1, f->ch[bi].slot = 2;
    }
    *pic = *grey ? yi : ri;
    return 0;
}

/* tiles or scanline blocks, and the chunk offset table that must follow the header at pos */
static int chunk_layout(exr_file *f, const exr_attrs *at, size_t pos, char *err, size_t errlen)
{
    if (at->have_tiles) {
        uint32_t txs = at->txs, tys = at->tys;
        int mode = at->mode;
        if (txs < 1 || tys < 1 || txs > QTOOL_EXR_MAX_DIM || tys > QTOOL_EXR_MAX_DIM)
            return qtool_errf(err, errlen, "tile size %u x %u (1..%u a side)", (unsigned)txs, (unsigned)tys, (unsigned)QTOOL_EXR_MAX_DIM);
        if ((mode & 15) > 2 || (mode >> 4) > 1)
            return qtool_errf(err, errlen, "tile level mode %d, rounding %d (0..2, 0..1)", mode & 15, mode >> 4);
        f->tiled = 1;
        f->tw = txs, f->th = tys;
        f->ntx = (f->w + txs - 1) / txs, f->nty = (f->h + tys - 1) / tys;
        f->nchunks = f->ntx * f->nty;
    } else {
        static const int lines[5] = {1, 1, 1, 16, 32};
        f->lines = lines[f->comp];
        f->nchunks = (f->h + (size_t)f->lines - 1) / (size_t)f->lines;
    }
    if (f->nchunks > (f->len - pos) / 8)
        return qtool_errf(err, errlen, "chunk offset table (%zu entries) runs past the end of the file", f->nchunks);
    f->table = pos;
    return 0;
}

static int parse_header(exr_file *f, qtool_exr_info *info, char *err, size_t errlen)
{
    const uint8_t *buf = f->buf;
    size_t len = f->len;
    if (len < 8 || !qtool_exr_magic(buf, len))
        return qtool_errf(err, errlen, "not an OpenEXR file (no 76 2f 31 01 magic)");
    uint32_t ver = rd32(buf + 4);
    if ((ver & 0xFFu) != 2)
        return qtool_errf(err, errlen, "OpenEXR version %u (only 2 is read)", (unsigned)(ver & 0xFFu));
    if (ver & 0x1000u)
        return qtool_errf(err, errlen, "multi-part OpenEXR file (only single-part files are read)");
    if (ver & 0x800u)
        return qtool_errf(err, errlen, "deep OpenEXR data (only flat images are read)");
    if (ver & ~0x6FFu)
        return qtool_errf(err, errlen, "unknown OpenEXR version flags 0x%x", (unsigned)(ver >> 8));
    size_t pos = 8;
    exr_attrs at = {0};
    int grey = 0, pic = 0;
    if (read_attrs(f, &pos, &at, err, errlen) != 0 || check_windows(f, &at, (ver & 0x200u) != 0, err, errlen) != 0 ||
        picture_channels(f, &grey, &pic, err, errlen) != 0 || chunk_layout(f, &at, pos, err, errlen) != 0)
        return -1;
    if (info) {
        memset(info, 0, sizeof *info);
        info->w = (int)f->w, info->h = (int)f->h;
        memcpy(info->data, at.dw, sizeof at.dw);
        memcpy(info->display, at.disp, sizeof at.disp);
        info->compression = f->comp, info->tiled = f->tiled;
        info->tile_w = (int)f->tw, info->tile_h = (int)f->th;
        info->channels = f->nch, info->grey = grey;
        info->pixel_type = f->ch[pic].type;
        info->line_order = at.lo;
    }
    return 0;
}

/* chunk k's place: data pointer, packed size, pixel rectangle; checks its header */
static int chunk_at(const exr_file *f, size_t k, const uint8_t **data, size_t *n, size_t *x0, size_t *y0, size_t *nx,
                    size_t *ny, char *err, size_t errlen)
{
    uint64_t off = rd64(f->buf + f->table + 8 * k);
    size_t head = f->tiled ? 20 : 8;
    if (off < f->table + 8 * f->nchunks || off > f->len || f->len - off < head)
        return qtool_errf(err, errlen, "chunk %zu: offset %llu outside the file's chunk area", k, (unsigned long long)off);
    const uint8_t *c = f->buf + off;
    if (f->tiled) {
        size_t tx = k % f->ntx, ty = k / f->ntx;
        if (rds32(c) != (int32_t)tx || rds32(c + 4) != (int32_t)ty || rds32(c + 8) != 0 || rds32(c + 12) != 0)
            return qtool_errf(err, errlen, "chunk %zu: tile (%d, %d) level (%d, %d), expected tile (%zu, %zu) level (0, 0)", k,
                        (int)rds32(c), (int)rds32(c + 4), (int)rds32(c + 8), (int)rds32(c + 12), tx, ty);
        *x0 = tx * f->tw, *y0 = ty * f->th;
        *nx = f->w - *x0 < f->tw ? f->w - *x0 : f->tw;
        *ny = f->h - *y0 < f->th ? f->h - *y0 : f->th;
    } else {
        int64_t want = (int64_t)f->ymin + (int64_t)(k * (size_t)f->lines);
        if ((int64_t)rds32(c) != want)
            return qtool_errf(err, errlen, "chunk %zu: y %d, expected %lld", k, (int)rds32(c), (long long)want);
        *x0 = 0, *y0 = k * (size_t)f->lines;
        *nx = f->w;
        *ny = f->h - *y0 < (size_t)f->lines ? f->h - *y0 : (size_t)f->lines;
    }
    uint32_t sz = rd32(c + head - 4);
    size_t raw = *nx * *ny * f->bpp;
    if (sz == 0 || sz > f->len - off - head)
        return qtool_errf(err, errlen, "chunk %zu: %u bytes of data, past the end of the file (or none)", k, (unsigned)sz);
    if (sz > raw)
        return qtool_errf(err, errlen, "chunk %zu: %u bytes of data for %zu bytes of pixels", k, (unsigned)sz, raw);
    *data = c + head, *n = sz;
    return 0;
}

static int decode_impl(const uint8_t *buf, size_t len, qtool_exr_info *info_out, float **rgb_out, char *err,
                       size_t errlen)
{
    exr_file f;
    memset(&f, 0, sizeof f);
    f.buf = buf, f.len = len;
    qtool_exr_info info;
    if (parse_header(&f, &info, err, errlen) != 0)
        return -1;
    /* every chunk header first: nothing is allocated for a table that lies */
    size_t maxraw = 0;
    for (size_t k = 0; k < f.nchunks; ++k) {
        const uint8_t *d;
        size_t n, x0, y0, nx, ny;
        if (chunk_at(&f, k, &d, &n, &x0, &y0, &nx, &ny, err, errlen) != 0)
            return -1;
        if (nx * ny * f.bpp > maxraw)
            maxraw = nx * ny * f.bpp;
    }
    float *rgb = malloc(f.w * f.h * 3 * sizeof *rgb);
    uint8_t *raw = malloc(maxraw), *tmp = f.comp != QTOOL_EXR_NONE ? malloc(maxraw) : NULL;
    piz_work *wk = f.comp == QTOOL_EXR_PIZ ? malloc(sizeof *wk) : NULL;
    int rc = -1;
    if (!rgb || !raw || (f.comp != QTOOL_EXR_NONE && !tmp) || (f.comp == QTOOL_EXR_PIZ && !wk)) {
        qtool_errf(err, errlen, "out of memory for %zu x %zu pixels", f.w, f.h);
        goto out;
    }
    for (size_t k = 0; k < f.nchunks; ++k) {
        const uint8_t *d;
        size_t n, x0, y0, nx, ny;
        chunk_at(&f, k, &d, &n, &x0, &y0, &nx, &ny, err, errlen); /* checked above */
        size_t nraw = nx * ny * f.bpp;
        const char *why = NULL;
        const uint8_t *px = raw;
        if (n == nraw) {
            px = d; /* stored raw */
        } else if (f.comp == QTOOL_EXR_RLE) {
            why = unrle(d, n, tmp, nraw);
            if (!why)
                unpredict_merge(tmp, nraw, raw);
        } else if (f.comp == QTOOL_EXR_ZIPS || f.comp == QTOOL_EXR_ZIP) {
            size_t got = 0;
            if (qtool_zlib_inflate(d, n, tmp, nraw, &got, &why) == 0) {
                if (got != nraw)
                    why = "zlib data decodes short of the chunk's pixels";
                else
                    unpredict_merge(tmp, nraw, raw);
            }
        } else if (f.comp == QTOOL_EXR_PIZ) {
            why = unpiz(wk, d, n, f.ch, f.nch, nx, ny, (uint16_t *)(void *)tmp, raw, nraw);
        } else {
            why = "NONE chunk smaller than its pixels";
        }
        if (why) {
            qtool_errf(err, errlen, "chunk %zu (%s): %s", k, comp_names[f.comp], why);
            goto out;
        }
        size_t o = 0;
        for (size_t y = 0; y < ny; ++y)
            for (int c = 0; c < f.nch; ++c) {
                const channel *ch = &f.ch[c];
                size_t sb = type_bytes(ch->type);
                if (ch->slot < 0) {
                    o += nx * sb;
                    continue;
                }
                float *dst = rgb + ((y0 + y) * f.w + x0) * 3;
                for (size_t x = 0; x < nx; ++x, o += sb) {
                    float v;
                    if (ch->type == QTOOL_EXR_HALF) {
                        v = half_to_float((uint16_t)(px[o] | px[o + 1] << 8));
                    } else {
                        uint32_t u = rd32(px + o);
                        if (ch->type == QTOOL_EXR_FLOAT)
                            memcpy(&v, &u, 4);
                        else
                            v = (float)u;
                    }
                    if (!isfinite(v)) {
                        qtool_errf(err, errlen, "non-finite sample %s at pixel (%zu, %zu) of the data window, channel %s",
                             isnan(v) ? "nan" : v > 0 ? "inf" : "-inf", x0 + x, y0 + y, ch->name);
                        goto out;
                    }
                    if (ch->slot == 3)
                        dst[3 * x] = dst[3 * x + 1] = dst[3 * x + 2] = v;
                    else
                        dst[3 * x + (size_t)ch->slot] = v;
                }
            }
    }
    rc = 0;
out:
    free(raw), free(tmp), free(wk);
    if (rc != 0) {
        free(rgb);
        return -1;
    }
    if (info_out)
        *info_out = info;
    *rgb_out = rgb;
    return 0;
}

int qtool_exr_decode(const uint8_t *buf, size_t len, qtool_exr_info *info, float **rgb, char *err, size_t errlen)
{
    return decode_impl(buf, len, info, rgb, err, errlen);
}

static const char *exr_magic(const uint8_t *b, size_t n)
{
    return qtool_exr_magic(b, n) ? NULL : "not an OpenEXR file (no 76 2f 31 01 magic)";
}

int qtool_exr_read(const char *path, qtool_exr_info *info, float **rgb, char *err, size_t errlen)
{
    static const qtool_io_kind kind = {"an OpenEXR file", 8, QTOOL_EXR_MAX_FILE_BYTES, 4, exr_magic};
    uint8_t *buf = NULL;
    size_t n = 0;
    if (qtool_io_load(path, &kind, &buf, &n, err, errlen) != 0)
        return -1;
    char msg[256];
    int rc = decode_impl(buf, n, info, rgb, msg, sizeof msg);
    free(buf);
    if (rc != 0)
        return qtool_errf(err, errlen, "%s: %s", path, msg);
    return 0;
}

/* ---- writer ------------------------------------------------------------------------------------ */

typedef struct {
    uint8_t *b;
    size_t n;
} wbuf;

static void put(wbuf *w, const void *p, size_t n)
{
    memcpy(w->b + w->n, p, n);
    w->n += n;
}

static void put32(wbuf *w, uint32_t v)
{
    uint8_t b[4] = {(uint8_t)v, (uint8_t)(v >> 8), (uint8_t)(v >> 16), (uint8_t)(v >> 24)};
    put(w, b, 4);
}

static void attr(wbuf *w, const char *name, const char *type, const void *v, uint32_t n)
{
    put(w, name, strlen(name) + 1);
    put(w, type, strlen(type) + 1);
    put32(w, n);
    put(w, v, n);
}

int qtool_exr_encode(int w, int h, const float *rgb, int pixel_type, int compression, uint8_t **out, size_t *outlen,
                     char *err, size_t errlen)
{
    if (w < 1 || h < 1 || w > (int)QTOOL_EXR_MAX_DIM || h > (int)QTOOL_EXR_MAX_DIM ||
        (uint64_t)w * (uint64_t)h > QTOOL_EXR_MAX_PIXELS)
        return qtool_errf(err, errlen, "bad image size %dx%d (1..%u a side, %lu pixels)", w, h, (unsigned)QTOOL_EXR_MAX_DIM,
                    (unsigned long)QTOOL_EXR_MAX_PIXELS);
    if (pixel_type != QTOOL_EXR_HALF && pixel_type != QTOOL_EXR_FLOAT)
        return qtool_errf(err, errlen, "EXR pixel type %d not written (HALF or FLOAT)", pixel_type);
    if (compression != QTOOL_EXR_NONE && compression != QTOOL_EXR_ZIPS && compression != QTOOL_EXR_ZIP)
        return qtool_errf(err, errlen, "EXR compression %d not written (NONE, ZIPS or ZIP)", compression);
    size_t np = (size_t)w * (size_t)h, sb = pixel_type == QTOOL_EXR_HALF ? 2 : 4;
    for (size_t i = 0; i < np * 3; ++i) {
        uint16_t hv;
        if (!isfinite(rgb[i]) || (pixel_type == QTOOL_EXR_HALF && float_to_half(rgb[i], &hv) != 0))
            return qtool_errf(err, errlen, "sample %g at pixel (%zu, %zu) channel %c is not %s", (double)rgb[i],
                        (i / 3) % (size_t)w, (i / 3) / (size_t)w, "RGB"[i % 3],
                        pixel_type == QTOOL_EXR_HALF ? "a finite value within the half range (|v| < 65520)" : "finite");
    }
    int lines = compression == QTOOL_EXR_ZIP ? 16 : 1;
    size_t nblocks = ((size_t)h + (size_t)lines - 1) / (size_t)lines, row = (size_t)w * 3 * sb;
    size_t maxraw = row * (size_t)lines;
    /* header under 512 bytes; each block at most its raw bytes plus 8 of chunk header */
    size_t cap = 512 + 8 * nblocks + (np * 3 * sb) + 8 * nblocks;
    wbuf o = {malloc(cap), 0};
    uint8_t *raw = malloc(maxraw), *t = malloc(maxraw);
    if (!o.b || !raw || !t) {
        free(o.b), free(raw), free(t);
        return qtool_errf(err, errlen, "out of memory");
    }
    static const uint8_t magic[4] = {0x76, 0x2f, 0x31, 0x01};
    put(&o, magic, 4);
    put32(&o, 2);
    uint8_t chl[3 * 18 + 1], *c = chl;
    for (int i = 0; i < 3; ++i) { /* B G R: the list is sorted by name */
        *c++ = (uint8_t)"BGR"[i], *c++ = 0;
        c[0] = (uint8_t)pixel_type, c[1] = c[2] = c[3] = 0; /* type */
        c[4] = c[5] = c[6] = c[7] = 0;                       /* pLinear, reserved */
        c[8] = 1, c[9] = c[10] = c[11] = 0;                  /* xSampling */
        c[12] = 1, c[13] = c[14] = c[15] = 0;                /* ySampling */
        c += 16;
    }
    *c++ = 0;
    attr(&o, "channels", "chlist", chl, (uint32_t)(c - chl));
    uint8_t cm = (uint8_t)compression, lo = 0;
    attr(&o, "compression", "compression", &cm, 1);
    uint8_t box[16] = {0};
    box[8] = (uint8_t)(w - 1), box[9] = (uint8_t)((w - 1) >> 8), box[10] = (uint8_t)((w - 1) >> 16);
    box[12] = (uint8_t)(h - 1), box[13] = (uint8_t)((h - 1) >> 8), box[14] = (uint8_t)((h - 1) >> 16);
    attr(&o, "dataWindow", "box2i", box, 16);
    attr(&o, "displayWindow", "box2i", box, 16);
    attr(&o, "lineOrder", "lineOrder", &lo, 1);
    static const uint8_t one_f[4] = {0, 0, 0x80, 0x3f}, zero_v2[8] = {0};
    attr(&o, "pixelAspectRatio", "float", one_f, 4);
    attr(&o, "screenWindowCenter", "v2f", zero_v2, 8);
    attr(&o, "screenWindowWidth", "float", one_f, 4);
    uint8_t end = 0;
    put(&o, &end, 1);
    size_t table = o.n;
    o.n += 8 * nblocks;
    for (size_t b = 0; b < nblocks; ++b) {
        uint64_t off = o.n;
        for (int k = 0; k < 8; ++k)
            o.b[table + 8 * b + (size_t)k] = (uint8_t)(off >> (8 * k));
        size_t y0 = b * (size_t)lines, ny = (size_t)h - y0 < (size_t)lines ? (size_t)h - y0 : (size_t)lines;
        size_t nraw = ny * row, q = 0;
        for (size_t y = y0; y < y0 + ny; ++y)
            for (int ci = 2; ci >= 0; --ci) /* B, G, R */
                for (size_t x = 0; x < (size_t)w; ++x) {
                    float v = rgb[(y * (size_t)w + x) * 3 + (size_t)ci];
                    if (sb == 2) {
                        uint16_t hv = 0;
                        float_to_half(v, &hv); /* in range: checked above */
                        raw[q++] = (uint8_t)hv, raw[q++] = (uint8_t)(hv >> 8);
                    } else {
                        uint32_t u;
                        memcpy(&u, &v, 4);
                        raw[q++] = (uint8_t)u, raw[q++] = (uint8_t)(u >> 8);
                        raw[q++] = (uint8_t)(u >> 16), raw[q++] = (uint8_t)(u >> 24);
                    }
                }
        const uint8_t *data = raw;
        size_t dn = nraw;
        uint8_t *z = NULL;
        if (compression != QTOOL_EXR_NONE) {
            size_t zn;
            split_predict(raw, nraw, t);
            if (qtool_zlib_deflate(t, nraw, &z, &zn) != 0) {
                free(o.b), free(raw), free(t);
                return qtool_errf(err, errlen, "out of memory");
            }
            if (zn < nraw)
                data = z, dn = zn; /* otherwise stored raw, as the format asks */
        }
        put32(&o, (uint32_t)y0);
        put32(&o, (uint32_t)dn);
        put(&o, data, dn);
        free(z);
    }
    free(raw), free(t);
    *out = o.b, *outlen = o.n;
    return 0;
}

int qtool_exr_write(const char *path, int w, int h, const float *rgb, int pixel_type, int compression, char *err,
                    size_t errlen)
{
    uint8_t *b;
    size_t n;
    char why[256];
    if (qtool_exr_encode(w, h, rgb, pixel_type, compression, &b, &n, why, sizeof why) != 0)
        return qtool_errf(err, errlen, "%s: %s", path, why);
    int rc = qtool_io_write_atomic(path, b, n, err, errlen);
    free(b);
    return rc;
}
