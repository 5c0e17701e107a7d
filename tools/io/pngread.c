/*
 * io/pngread.c - PNG/APNG reader for checking what qibl writes (tests, `qibl check`): chunk CRCs,
 * the zlib stream through io/inflate.c (RFC 1951 stored, fixed and dynamic blocks, Adler-32),
 * the five scanline filters, APNG frame bookkeeping. 8-bit RGB/RGBA, non-interlaced only.
 */
#include "io/png.h"
#include "io/file.h"
#include "io/zlib.h"

#include "qibl/asset.h" /* qibl_crc32 */

#include "qtool.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static uint32_t get32(const uint8_t *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

/* zlib stream -> malloc'ed bytes (at most cap); NULL with *why set */
static uint8_t *unzlib(const uint8_t *z, size_t n, size_t cap, size_t *outn, const char **why)
{
    uint8_t *out = malloc(cap ? cap : 1);
    if (!out) {
        *why = "out of memory";
        return NULL;
    }
    if (qtool_zlib_inflate(z, n, out, cap, outn, why) != 0) {
        free(out);
        return NULL;
    }
    return out;
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

/* what the chunks read so far say about the image */
typedef struct {
    const char *name;
    char *err;
    size_t errlen;
    uint32_t w, h, frames, nfctl, nfdat_frames, seq;
    uint8_t plte[768];
    unsigned nplte, ctype;
    int ch, seen_ihdr, seen_actl, idat_done, last_fdat_frame;
    uint8_t *idat;
    size_t idat_n, idat_cap;
} png_read;

#define PERR(s, ...) qtool_errf_at((s)->err, (s)->errlen, (s)->name, 0, __VA_ARGS__)

static int png_ihdr(png_read *s, const uint8_t *data, uint32_t n)
{
    if (s->seen_ihdr || n != 13)
        return PERR(s, "bad IHDR");
    uint32_t w = get32(data), h = get32(data + 4);
    if (w == 0 || h == 0 || w > QTOOL_PNG_MAX_DIM || h > QTOOL_PNG_MAX_DIM)
        return PERR(s, "bad image size %ux%u (each 1..%u)", w, h, QTOOL_PNG_MAX_DIM);
    if ((uint64_t)w * h > QIBL_PNG_MAX_PIXELS)
        return PERR(s, "%ux%u pixels, above the %u-pixel limit (QIBL_PNG_MAX_PIXELS)", w, h,
                    (unsigned)QIBL_PNG_MAX_PIXELS);
    /* 8-bit RGB and RGBA (what qibl writes), and for textures 8-bit grey, grey + alpha and
     * palette images (returned as RGB) */
    if (data[8] != 8 || (data[9] != 0 && data[9] != 2 && data[9] != 3 && data[9] != 4 && data[9] != 6) || data[10] ||
        data[11] || data[12])
        return PERR(s, "unsupported format (bit depth %u, colour type %u, interlace %u): only 8-bit grey, RGB, palette, grey+alpha or RGBA",
                    data[8], data[9], data[12]);
    s->w = w, s->h = h;
    s->ctype = data[9];
    s->ch = s->ctype == 2 ? 3 : s->ctype == 6 ? 4 : s->ctype == 4 ? 2 : 1;
    s->seen_ihdr = 1;
    return 0;
}

/* APNG's fcTL and fdAT: only full-size frames, in sequence; counted to check acTL */
static int png_frame(png_read *s, const uint8_t *type, const uint8_t *data, uint32_t n)
{
    char tn[16];
    if (!s->seen_actl || n < 4 || get32(data) != s->seq)
        return PERR(s, "%s out of sequence or without acTL", type_name(type, tn));
    s->seq++;
    if (type[1] == 'c') {
        if (n != 26 || get32(data + 4) != s->w || get32(data + 8) != s->h || get32(data + 12) || get32(data + 16))
            return PERR(s, "fcTL %u is not a full-size frame", s->nfctl);
        s->nfctl++;
    } else {
        if (s->nfctl < 2)
            return PERR(s, "fdAT before the second fcTL");
        if (s->last_fdat_frame != (int)s->nfctl) {
            s->nfdat_frames++;
            s->last_fdat_frame = (int)s->nfctl;
        }
    }
    return 0;
}

static int png_idat(png_read *s, const uint8_t *data, uint32_t n)
{
    if (s->idat_done)
        return PERR(s, "IDAT chunks are not consecutive");
    if (s->idat_n + n + 1 > s->idat_cap) { /* doubling: many small IDATs stay linear */
        size_t cap = s->idat_cap ? s->idat_cap : 65536;
        while (cap < s->idat_n + n + 1)
            cap *= 2;
        uint8_t *nb = realloc(s->idat, cap);
        if (!nb)
            return PERR(s, "out of memory");
        s->idat = nb, s->idat_cap = cap;
    }
    memcpy(s->idat + s->idat_n, data, n);
    s->idat_n += n;
    return 0;
}

/* one chunk whose length and CRC are checked: 0 read, 1 IEND, -1 refused */
static int png_chunk(png_read *s, const uint8_t *type, const uint8_t *data, uint32_t n)
{
    char tn[16];
    int r = 0;
    if (!s->seen_ihdr && memcmp(type, "IHDR", 4) != 0)
        return PERR(s, "first chunk is %s, not IHDR", type_name(type, tn));
    if (memcmp(type, "IHDR", 4) == 0) {
        r = png_ihdr(s, data, n);
    } else if (memcmp(type, "PLTE", 4) == 0) {
        if (s->nplte || n == 0 || n % 3 || n > 768 || s->idat_n)
            return PERR(s, "bad PLTE (%u bytes)", n);
        memcpy(s->plte, data, n);
        s->nplte = n / 3;
    } else if (memcmp(type, "acTL", 4) == 0) {
        if (n != 8 || s->idat_n || get32(data) == 0)
            return PERR(s, "bad acTL");
        s->frames = get32(data), s->seen_actl = 1;
    } else if (memcmp(type, "fcTL", 4) == 0 || memcmp(type, "fdAT", 4) == 0) {
        r = png_frame(s, type, data, n);
    } else if (memcmp(type, "IDAT", 4) == 0) {
        r = png_idat(s, data, n);
    } else if (memcmp(type, "IEND", 4) == 0) {
        return 1;
    } else if (!(type[0] & 0x20)) {
        return PERR(s, "unknown critical chunk %s", type_name(type, tn));
    }
    if (s->idat_n && memcmp(type, "IDAT", 4) != 0)
        s->idat_done = 1;
    return r;
}

/* the chunks from the signature to IEND, then what the whole file must hold */
static int png_chunks(png_read *s, const uint8_t *buf, size_t len)
{
    static const uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    if (len < 8 || memcmp(buf, sig, 8) != 0)
        return PERR(s, "not a PNG (bad signature)");
    size_t pos = 8;
    int seen_iend = 0;
    char tn[16];
    while (pos < len) {
        if (len - pos < 12)
            return PERR(s, "truncated chunk at byte %zu", pos);
        uint32_t n = get32(buf + pos);
        const uint8_t *type = buf + pos + 4, *data = buf + pos + 8;
        if (n > len - pos - 12)
            return PERR(s, "chunk %s at byte %zu runs past the end of the file", type_name(type, tn), pos);
        if (qibl_crc32(0, type, 4 + (size_t)n) != get32(data + n))
            return PERR(s, "CRC mismatch in chunk %s at byte %zu", type_name(type, tn), pos);
        int r = png_chunk(s, type, data, n);
        if (r < 0)
            return -1;
        if (r == 1) {
            seen_iend = 1;
            break;
        }
        pos += 12 + (size_t)n;
    }
    if (!seen_iend)
        return PERR(s, "no IEND chunk (truncated file?)");
    if (!s->idat_n)
        return PERR(s, "no image data (IDAT)");
    if (s->ctype == 3 && !s->nplte)
        return PERR(s, "a palette image without PLTE");
    if (s->seen_actl && (s->nfctl != s->frames || s->nfdat_frames + 1 != s->frames))
        return PERR(s, "acTL says %u frames but the file holds %u fcTL and %u fdAT frames", s->frames, s->nfctl,
                    s->nfdat_frames + 1);
    return 0;
}

/* undoes the row filters of raw (each row its filter byte, then stride bytes) into img */
static int png_unfilter(png_read *s, const uint8_t *raw, size_t stride, uint8_t *img)
{
    size_t ch = (size_t)s->ch;
    for (uint32_t y = 0; y < s->h; ++y) {
        const uint8_t *r = raw + (size_t)y * (stride + 1) + 1;
        uint8_t *o = img + (size_t)y * stride, *u = y ? o - stride : NULL;
        int ft = r[-1];
        if (ft > 4)
            return PERR(s, "bad filter type %d on row %u", ft, y);
        for (size_t x = 0; x < stride; ++x) {
            int a = x >= ch ? o[x - ch] : 0, b = u ? u[x] : 0, c = u && x >= ch ? u[x - ch] : 0;
            int p = ft == 0 ? 0 : ft == 1 ? a : ft == 2 ? b : ft == 3 ? (a + b) / 2 : paeth(a, b, c);
            o[x] = (uint8_t)(r[x] + p);
        }
    }
    return 0;
}

/* grey, grey + alpha, palette, RGB or RGBA pixels to RGB */
static int png_to_rgb(png_read *s, const uint8_t *img, uint8_t *rgb)
{
    for (size_t i = 0; i < (size_t)s->w * s->h; ++i) {
        const uint8_t *px = img + (size_t)s->ch * i;
        if (s->ctype == 3) {
            if (px[0] >= s->nplte)
                return PERR(s, "palette index %u past the %u PLTE entries (pixel %zu)", (unsigned)px[0], s->nplte, i);
            memcpy(rgb + 3 * i, s->plte + 3 * (size_t)px[0], 3);
        } else if (s->ch <= 2) {
            rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = px[0];
        } else {
            memcpy(rgb + 3 * i, px, 3);
        }
    }
    return 0;
}

/* the image data inflated, unfiltered and turned to RGB: a new buffer, or NULL with the message */
static uint8_t *png_pixels(png_read *s)
{
    const char *why = NULL;
    size_t rn = 0, stride = (size_t)s->w * (size_t)s->ch;
    uint8_t *raw = unzlib(s->idat, s->idat_n, (stride + 1) * s->h, &rn, &why);
    if (!raw) {
        PERR(s, "image data: %s", why);
        return NULL;
    }
    uint8_t *img = NULL, *rgb = NULL;
    if (rn != (stride + 1) * s->h)
        PERR(s, "image data holds %zu bytes, expected %zu", rn, (stride + 1) * s->h);
    else if (!(img = malloc(stride * s->h)) || !(rgb = malloc((size_t)s->w * s->h * 3)))
        PERR(s, "out of memory");
    else if (png_unfilter(s, raw, stride, img) != 0 || png_to_rgb(s, img, rgb) != 0)
        free(rgb), rgb = NULL;
    free(raw), free(img);
    return rgb;
}

static int read_impl(const char *name, const uint8_t *buf, size_t len, int *w_out, int *h_out, int *frames_out,
                     uint8_t **rgb_out, char *err, size_t errlen)
{
    png_read s = {.name = name, .err = err, .errlen = errlen, .frames = 1, .last_fdat_frame = -1};
    uint8_t *rgb = png_chunks(&s, buf, len) == 0 ? png_pixels(&s) : NULL;
    free(s.idat);
    if (!rgb)
        return -1;
    *w_out = (int)s.w, *h_out = (int)s.h, *rgb_out = rgb;
    if (frames_out)
        *frames_out = (int)s.frames;
    return 0;
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
