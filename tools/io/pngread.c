/*
 * io/pngread.c - PNG/APNG reader for checking what qibl writes (tests, `qibl check`): chunk CRCs,
 * the zlib stream through io/inflate.c (RFC 1951 stored, fixed and dynamic blocks, Adler-32),
 * the five scanline filters, APNG frame bookkeeping. 8-bit RGB/RGBA, non-interlaced only.
 */
#include "io/png.h"
#include "io/file.h"
#include "io/zlib.h"

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
