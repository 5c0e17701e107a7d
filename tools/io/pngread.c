/*
 * io/pngread.c - PNG/APNG reader for checking what qibl writes (tests, `qibl check`): chunk CRCs,
 * a complete inflate (RFC 1951: stored, fixed and dynamic Huffman blocks), zlib header and Adler-32,
 * the five scanline filters, APNG frame bookkeeping. 8-bit RGB/RGBA, non-interlaced only.
 */
#include "io/png.h"
#include "io/file.h"

#include "qibl/asset.h" /* qibl_crc32 */

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int fail(char *err, size_t errlen, const char *name, const char *fmt, ...)
{
    va_list ap;
    size_t o = 0;
    if (name) {
        snprintf(err, errlen, "%s: ", name);
        o = strlen(err);
    }
    va_start(ap, fmt);
    if (o < errlen)
        vsnprintf(err + o, errlen - o, fmt, ap);
    va_end(ap);
    return -1;
}

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

/* the output buffer is exactly what IHDR implies, so a stream inflating further stops at once */
static int emit(inf *s, uint8_t b)
{
    if (s->on == s->ocap) {
        s->why = "inflates past the size IHDR implies";
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

/* zlib stream -> malloc'ed bytes (at most cap); NULL with *why set */
static uint8_t *unzlib(const uint8_t *z, size_t n, size_t cap, size_t *outn, const char **why)
{
    if (n < 6 || (z[0] & 0x0F) != 8 || ((unsigned)z[0] << 8 | z[1]) % 31 != 0 || (z[1] & 0x20)) {
        *why = "bad zlib header";
        return NULL;
    }
    inf s = {z + 2, n - 2, 0, malloc(cap ? cap : 1), 0, cap, NULL};
    if (!s.out) {
        *why = "out of memory";
        return NULL;
    }
    if (inflate_raw(&s) != 0) {
        *why = s.why;
        free(s.out);
        return NULL;
    }
    size_t p = ((s.pos + 7) >> 3) + 2;
    if (p + 4 > n) {
        *why = "zlib stream has no Adler-32";
        free(s.out);
        return NULL;
    }
    uint32_t a = 1, b = 0;
    for (size_t i = 0; i < s.on; ++i) {
        a = (a + s.out[i]) % 65521u;
        b = (b + a) % 65521u;
    }
    if (get32(z + p) != (b << 16 | a)) {
        *why = "Adler-32 mismatch";
        free(s.out);
        return NULL;
    }
    *outn = s.on;
    return s.out;
}

/* ---- PNG ------------------------------------------------------------------------------------------ */

static int paeth(int a, int b, int c)
{
    int p = a + b - c, pa = abs(p - a), pb = abs(p - b), pc = abs(p - c);
    return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

/* a chunk type for messages: its four letters, or its bytes in hex when they are not all letters
 * (a raw byte such as a newline would break the one-line error) */
static const char *type_name(const uint8_t *t, char out[16])
{
    int letters = 1;
    for (int i = 0; i < 4; ++i)
        letters &= (t[i] >= 'A' && t[i] <= 'Z') || (t[i] >= 'a' && t[i] <= 'z');
    if (letters)
        snprintf(out, 16, "%c%c%c%c", t[0], t[1], t[2], t[3]);
    else
        snprintf(out, 16, "0x%02x%02x%02x%02x", t[0], t[1], t[2], t[3]);
    return out;
}

static int read_impl(const char *name, const uint8_t *buf, size_t len, int *w_out, int *h_out, int *frames_out,
                     uint8_t **rgb_out, char *err, size_t errlen)
{
    static const uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    if (len < 8 || memcmp(buf, sig, 8) != 0)
        return fail(err, errlen, name, "not a PNG (bad signature)");
    size_t pos = 8, idat_n = 0, idat_cap = 0;
    uint8_t *idat = NULL;
    uint32_t w = 0, h = 0, frames = 1, nfctl = 0, nfdat_frames = 0, seq = 0;
    uint8_t plte[768];
    unsigned nplte = 0, ctype = 0;
    int ch = 0, seen_ihdr = 0, seen_iend = 0, seen_actl = 0, idat_done = 0, last_fdat_frame = -1;
    int rc = -1;
    char tn[16];
    while (pos < len) {
        if (len - pos < 12) {
            fail(err, errlen, name, "truncated chunk at byte %zu", pos);
            goto out;
        }
        uint32_t n = get32(buf + pos);
        const uint8_t *type = buf + pos + 4, *data = buf + pos + 8;
        if (n > len - pos - 12) {
            fail(err, errlen, name, "chunk %s at byte %zu runs past the end of the file", type_name(type, tn), pos);
            goto out;
        }
        if (qibl_crc32(0, type, 4 + (size_t)n) != get32(data + n)) {
            fail(err, errlen, name, "CRC mismatch in chunk %s at byte %zu", type_name(type, tn), pos);
            goto out;
        }
        if (!seen_ihdr && memcmp(type, "IHDR", 4) != 0) {
            fail(err, errlen, name, "first chunk is %s, not IHDR", type_name(type, tn));
            goto out;
        }
        if (memcmp(type, "IHDR", 4) == 0) {
            if (seen_ihdr || n != 13) {
                fail(err, errlen, name, "bad IHDR");
                goto out;
            }
            w = get32(data), h = get32(data + 4);
            if (w == 0 || h == 0 || w > QTOOL_PNG_MAX_DIM || h > QTOOL_PNG_MAX_DIM) {
                fail(err, errlen, name, "bad image size %ux%u (each 1..%u)", w, h, QTOOL_PNG_MAX_DIM);
                goto out;
            }
            if ((uint64_t)w * h > QIBL_PNG_MAX_PIXELS) {
                fail(err, errlen, name, "%ux%u pixels, above the %u-pixel limit (QIBL_PNG_MAX_PIXELS)", w, h,
                     (unsigned)QIBL_PNG_MAX_PIXELS);
                goto out;
            }
            /* 8-bit RGB and RGBA (what qibl writes), and for textures 8-bit grey, grey + alpha and
             * palette images (returned as RGB) */
            if (data[8] != 8 || (data[9] != 0 && data[9] != 2 && data[9] != 3 && data[9] != 4 && data[9] != 6) ||
                data[10] || data[11] || data[12]) {
                fail(err, errlen, name, "unsupported format (bit depth %u, colour type %u, interlace %u): only 8-bit grey, RGB, palette, grey+alpha or RGBA",
                     data[8], data[9], data[12]);
                goto out;
            }
            ctype = data[9];
            ch = ctype == 2 ? 3 : ctype == 6 ? 4 : ctype == 4 ? 2 : 1;
            seen_ihdr = 1;
        } else if (memcmp(type, "PLTE", 4) == 0) {
            if (nplte || n == 0 || n % 3 || n > 768 || idat_n) {
                fail(err, errlen, name, "bad PLTE (%u bytes)", n);
                goto out;
            }
            memcpy(plte, data, n);
            nplte = n / 3;
        } else if (memcmp(type, "acTL", 4) == 0) {
            if (n != 8 || idat_n || get32(data) == 0) {
                fail(err, errlen, name, "bad acTL");
                goto out;
            }
            frames = get32(data), seen_actl = 1;
        } else if (memcmp(type, "fcTL", 4) == 0 || memcmp(type, "fdAT", 4) == 0) {
            int is_fctl = type[1] == 'c';
            if (!seen_actl || n < 4 || get32(data) != seq) {
                fail(err, errlen, name, "%s out of sequence or without acTL", type_name(type, tn));
                goto out;
            }
            seq++;
            if (is_fctl) {
                if (n != 26 || get32(data + 4) != w || get32(data + 8) != h || get32(data + 12) || get32(data + 16)) {
                    fail(err, errlen, name, "fcTL %u is not a full-size frame", nfctl);
                    goto out;
                }
                nfctl++;
            } else {
                if (nfctl < 2) {
                    fail(err, errlen, name, "fdAT before the second fcTL");
                    goto out;
                }
                if (last_fdat_frame != (int)nfctl) {
                    nfdat_frames++;
                    last_fdat_frame = (int)nfctl;
                }
            }
        } else if (memcmp(type, "IDAT", 4) == 0) {
            if (idat_done) {
                fail(err, errlen, name, "IDAT chunks are not consecutive");
                goto out;
            }
            if (idat_n + n + 1 > idat_cap) { /* doubling: many small IDATs stay linear */
                size_t cap = idat_cap ? idat_cap : 65536;
                while (cap < idat_n + n + 1)
                    cap *= 2;
                uint8_t *nb = realloc(idat, cap);
                if (!nb) {
                    fail(err, errlen, name, "out of memory");
                    goto out;
                }
                idat = nb, idat_cap = cap;
            }
            memcpy(idat + idat_n, data, n);
            idat_n += n;
        } else if (memcmp(type, "IEND", 4) == 0) {
            seen_iend = 1;
            break;
        } else if (!(type[0] & 0x20)) {
            fail(err, errlen, name, "unknown critical chunk %s", type_name(type, tn));
            goto out;
        }
        if (idat_n && memcmp(type, "IDAT", 4) != 0)
            idat_done = 1;
        pos += 12 + (size_t)n;
    }
    if (!seen_iend) {
        fail(err, errlen, name, "no IEND chunk (truncated file?)");
        goto out;
    }
    if (!idat_n) {
        fail(err, errlen, name, "no image data (IDAT)");
        goto out;
    }
    if (ctype == 3 && !nplte) {
        fail(err, errlen, name, "a palette image without PLTE");
        goto out;
    }
    if (seen_actl && (nfctl != frames || nfdat_frames + 1 != frames)) {
        fail(err, errlen, name, "acTL says %u frames but the file holds %u fcTL and %u fdAT frames", frames, nfctl,
             nfdat_frames + 1);
        goto out;
    }
    {
        const char *why = NULL;
        size_t rn = 0;
        size_t stride = (size_t)w * (size_t)ch;
        uint8_t *raw = unzlib(idat, idat_n, (stride + 1) * h, &rn, &why);
        if (!raw) {
            fail(err, errlen, name, "image data: %s", why);
            goto out;
        }
        if (rn != (stride + 1) * h) {
            free(raw);
            fail(err, errlen, name, "image data holds %zu bytes, expected %zu", rn, (stride + 1) * h);
            goto out;
        }
        uint8_t *img = malloc(stride * h), *rgb = malloc((size_t)w * h * 3);
        if (!img || !rgb) {
            free(raw), free(img), free(rgb);
            fail(err, errlen, name, "out of memory");
            goto out;
        }
        for (uint32_t y = 0; y < h; ++y) {
            const uint8_t *r = raw + (size_t)y * (stride + 1) + 1;
            uint8_t *o = img + (size_t)y * stride, *u = y ? o - stride : NULL;
            int ft = r[-1];
            if (ft > 4) {
                free(raw), free(img), free(rgb);
                fail(err, errlen, name, "bad filter type %d on row %u", ft, y);
                goto out;
            }
            for (size_t x = 0; x < stride; ++x) {
                int a = x >= (size_t)ch ? o[x - (size_t)ch] : 0, b = u ? u[x] : 0,
                    c = u && x >= (size_t)ch ? u[x - (size_t)ch] : 0;
                int p = ft == 0 ? 0 : ft == 1 ? a : ft == 2 ? b : ft == 3 ? (a + b) / 2 : paeth(a, b, c);
                o[x] = (uint8_t)(r[x] + p);
            }
        }
        for (size_t i = 0; i < (size_t)w * h; ++i) {
            const uint8_t *px = img + (size_t)ch * i;
            if (ctype == 3) {
                if (px[0] >= nplte) {
                    unsigned bad = px[0];
                    free(raw), free(img), free(rgb);
                    fail(err, errlen, name, "palette index %u past the %u PLTE entries (pixel %zu)", bad, nplte, i);
                    goto out;
                }
                memcpy(rgb + 3 * i, plte + 3 * (size_t)px[0], 3);
            } else if (ch <= 2) {
                rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = px[0];
            } else {
                memcpy(rgb + 3 * i, px, 3);
            }
        }
        free(raw), free(img);
        *w_out = (int)w, *h_out = (int)h, *rgb_out = rgb;
        if (frames_out)
            *frames_out = (int)frames;
        rc = 0;
    }
out:
    free(idat);
    return rc;
}

int qtool_png_decode_rgb8(const uint8_t *buf, size_t len, int *w, int *h, int *frames, uint8_t **rgb, char *err,
                         size_t errlen)
{
    return read_impl(NULL, buf, len, w, h, frames, rgb, err, errlen);
}

static const char *png_magic(const uint8_t *b, size_t n)
{
    static const uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    return n >= 8 && memcmp(b, sig, 8) == 0 ? NULL : "not a PNG (bad signature)";
}

int qtool_png_read_rgb8(const char *path, int *w, int *h, int *frames, uint8_t **rgb, char *err, size_t errlen)
{
    static const qtool_io_kind kind = {"a PNG file", 8, QTOOL_PNG_MAX_FILE_BYTES, 8, png_magic};
    size_t n = 0;
    uint8_t *buf = NULL;
    if (qtool_io_load(path, &kind, &buf, &n, err, errlen) != 0)
        return -1;
    int rc = read_impl(path, buf, n, w, h, frames, rgb, err, errlen);
    free(buf);
    return rc;
}
