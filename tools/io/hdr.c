/*
 * io/hdr.c - Radiance .hdr reader: header, resolution line, new-style RLE, old-style RLE and flat
 * scanlines (see hdr.h). Every read is bounds-checked against the buffer; a bad file gives one line
 * of error text and no output.
 */
#include "io/hdr.h"
#include "io/exr.h"
#include "io/file.h"
#include "io/probe_layout.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "qtool.h"


/* next header line [*pos, eol) without the newline; returns its length or -1 at end of buffer */
static long next_line(const uint8_t *buf, size_t len, size_t *pos, const char **line)
{
    size_t s = *pos, e = s;
    while (e < len && buf[e] != '\n')
        ++e;
    if (e >= len)
        return -1;
    *line = (const char *)buf + s;
    *pos = e + 1;
    return (long)(e - s);
}

static float rgbe_channel(uint8_t m, uint8_t e)
{
    return e == 0 ? 0.0f : (float)ldexp((double)m, (int)e - 136);
}

/* one scanline of w RGBE pixels into px (4 bytes each), or, with px NULL, only walked and checked
 * (the pass that runs before any pixel memory exists); have_prev: a scanline came before, whose
 * last pixel is px[-4 .. -1] (for an old-style run at the start of a line) */
static int read_scanline(const uint8_t *buf, size_t len, size_t *pos, int w, uint8_t *px, int have_prev, int row,
                         char *err, size_t errlen)
{
    size_t p = *pos;
    if (p + 4 > len)
        return qtool_errf(err, errlen, "truncated at scanline %d of the pixel data", row);
    if (w >= 8 && w < 32768 && buf[p] == 2 && buf[p + 1] == 2 && (buf[p + 2] & 0x80) == 0) {
        int enc_w = buf[p + 2] << 8 | buf[p + 3];
        if (enc_w != w)
            return qtool_errf(err, errlen, "scanline %d: RLE width %d differs from the image width %d", row, enc_w, w);
        p += 4;
        for (int c = 0; c < 4; ++c) {
            int x = 0;
            while (x < w) {
                if (p >= len)
                    return qtool_errf(err, errlen, "truncated in RLE scanline %d", row);
                int count = buf[p++];
                if (count > 128) {
                    count -= 128;
                    if (x + count > w)
                        return qtool_errf(err, errlen, "scanline %d: RLE run past the end of the line", row);
                    if (p >= len)
                        return qtool_errf(err, errlen, "truncated in RLE scanline %d", row);
                    uint8_t v = buf[p++];
                    if (px)
                        for (int k = 0; k < count; ++k)
                            px[4 * (x + k) + c] = v;
                    x += count;
                } else {
                    if (count == 0)
                        return qtool_errf(err, errlen, "scanline %d: RLE literal of length 0", row);
                    if (x + count > w)
                        return qtool_errf(err, errlen, "scanline %d: RLE literal past the end of the line", row);
                    if (p + (size_t)count > len)
                        return qtool_errf(err, errlen, "truncated in RLE scanline %d", row);
                    if (px)
                        for (int k = 0; k < count; ++k)
                            px[4 * (x + k) + c] = buf[p + (size_t)k];
                    x += count;
                    p += (size_t)count;
                }
            }
        }
        *pos = p;
        return 0;
    }
    /* flat pixels, possibly with old-style runs */
    int x = 0, shift = 0;
    while (x < w) {
        if (p + 4 > len)
            return qtool_errf(err, errlen, "truncated at scanline %d of the pixel data", row);
        const uint8_t *q = buf + p;
        p += 4;
        if (q[0] == 1 && q[1] == 1 && q[2] == 1) {
            if (x == 0 && !have_prev)
                return qtool_errf(err, errlen, "scanline %d: old-style run with no pixel before it", row);
            if (shift > 16)
                return qtool_errf(err, errlen, "scanline %d: old-style run count too large", row);
            long count = (long)q[3] << shift;
            if (x + count > w)
                return qtool_errf(err, errlen, "scanline %d: old-style run past the end of the line", row);
            if (px) {
                uint8_t v[4];
                memcpy(v, px + 4 * x - 4, 4); /* x = 0: the previous scanline's last pixel */
                for (long k = 0; k < count; ++k)
                    memcpy(px + 4 * (x + k), v, 4);
            }
            x += (int)count;
            shift += 8;
        } else {
            if (px)
                memcpy(px + 4 * x, q, 4);
            ++x;
            shift = 0;
        }
    }
    *pos = p;
    return 0;
}

int qtool_hdr_decode_rgbe(const uint8_t *buf, size_t len, int *w_out, int *h_out, uint8_t **rgbe_out, char *err,
                         size_t errlen)
{
    size_t pos = 0;
    const char *line;
    long n = next_line(buf, len, &pos, &line);
    if (n < 2 || line[0] != '#' || line[1] != '?')
        return qtool_errf(err, errlen, "not a Radiance .hdr file (no #? magic line)");
    for (;;) {
        if (pos > QIBL_HDR_MAX_HEADER_BYTES)
            return qtool_errf(err, errlen, "header longer than %u bytes (QIBL_HDR_MAX_HEADER_BYTES)", QIBL_HDR_MAX_HEADER_BYTES);
        n = next_line(buf, len, &pos, &line);
        if (n < 0)
            return qtool_errf(err, errlen, "truncated header (no blank line before the resolution)");
        if (n == 0 || (n == 1 && line[0] == '\r'))
            break;
        if (n >= 7 && memcmp(line, "FORMAT=", 7) == 0) {
            const char *v = line + 7;
            long vn = n - 7;
            while (vn > 0 && (v[vn - 1] == '\r' || v[vn - 1] == ' ' || v[vn - 1] == '\t'))
                --vn;
            if (!(vn == 15 && memcmp(v, "32-bit_rle_rgbe", 15) == 0))
                return qtool_errf(err, errlen, "unsupported FORMAT=%.*s (only 32-bit_rle_rgbe)", (int)(vn > 40 ? 40 : vn), v);
        }
    }
    n = next_line(buf, len, &pos, &line);
    if (n < 0)
        return qtool_errf(err, errlen, "truncated before the resolution line");
    char res[128];
    size_t rn = (size_t)n < sizeof res - 1 ? (size_t)n : sizeof res - 1;
    memcpy(res, line, rn);
    res[rn] = '\0';
    char line_copy[sizeof res];
    memcpy(line_copy, res, rn + 1); /* res is cut into tokens below */
    /* four tokens "-Y H +X W"; strtol, not sscanf, whose behaviour on a number out of range is
     * undefined */
    char *tok[5], *save = NULL;
    int nt = 0;
    for (char *t = strtok_r(res, " \t\r", &save); t && nt < 5; t = strtok_r(NULL, " \t\r", &save))
        tok[nt++] = t;
    long hh = 0, ww = 0;
    char *e1 = NULL, *e2 = NULL;
    if (nt == 4) {
        errno = 0;
        hh = strtol(tok[1], &e1, 10);
        ww = strtol(tok[3], &e2, 10);
    }
    if (nt != 4 || e1 == tok[1] || *e1 || e2 == tok[3] || *e2 || errno == ERANGE)
        return qtool_errf(err, errlen, "bad resolution line '%.60s'", line_copy);
    if (strcmp(tok[0], "-Y") != 0 || strcmp(tok[2], "+X") != 0)
        return qtool_errf(err, errlen, "unsupported orientation '%.60s' (only -Y H +X W)", line_copy);
    if (ww < 1 || hh < 1 || ww > (long)QIBL_HDR_MAX_DIM || hh > (long)QIBL_HDR_MAX_DIM)
        return qtool_errf(err, errlen, "unsupported dimensions %ld x %ld (each 1..%u, QIBL_HDR_MAX_DIM)", ww, hh,
                    (unsigned)QIBL_HDR_MAX_DIM);
    if ((uint64_t)ww * (uint64_t)hh > QIBL_HDR_MAX_PIXELS)
        return qtool_errf(err, errlen, "%ld x %ld pixels, above the %lu-pixel limit (QIBL_HDR_MAX_PIXELS)", ww, hh,
                    (unsigned long)QIBL_HDR_MAX_PIXELS);
    int w = (int)ww, h = (int)hh;
    /* a lying header must not cost memory: every scanline is checked before the pixels exist */
    size_t body = pos;
    for (int y = 0; y < h; ++y)
        if (read_scanline(buf, len, &pos, w, NULL, y > 0, y, err, errlen))
            return -1;
    pos = body;
    uint8_t *px = malloc((size_t)w * (size_t)h * 4);
    if (!px)
        return qtool_errf(err, errlen, "out of memory for %d x %d pixels", w, h);
    for (int y = 0; y < h; ++y)
        if (read_scanline(buf, len, &pos, w, px + (size_t)y * (size_t)w * 4, y > 0, y, err, errlen)) {
            free(px);
            return -1;
        }
    *w_out = w;
    *h_out = h;
    *rgbe_out = px;
    return 0;
}

/* RGBE pixels (freed here whatever happens) to a new float RGB array */
static int to_float(uint8_t *px, int w, int h, float **rgb_out, char *err, size_t errlen)
{
    float *rgb = malloc((size_t)w * (size_t)h * 3 * sizeof *rgb);
    if (!rgb) {
        free(px);
        return qtool_errf(err, errlen, "out of memory for %d x %d pixels", w, h);
    }
    for (size_t i = 0; i < (size_t)w * (size_t)h; ++i) {
        const uint8_t *q = px + 4 * i;
        rgb[3 * i + 0] = rgbe_channel(q[0], q[3]);
        rgb[3 * i + 1] = rgbe_channel(q[1], q[3]);
        rgb[3 * i + 2] = rgbe_channel(q[2], q[3]);
    }
    free(px);
    *rgb_out = rgb;
    return 0;
}

int qtool_hdr_decode(const uint8_t *buf, size_t len, int *w_out, int *h_out, float **rgb_out, char *err,
                    size_t errlen)
{
    int w, h;
    uint8_t *px;
    float *rgb;
    if (qtool_hdr_decode_rgbe(buf, len, &w, &h, &px, err, errlen) != 0 || to_float(px, w, h, &rgb, err, errlen) != 0)
        return -1;
    *w_out = w;
    *h_out = h;
    *rgb_out = rgb;
    return 0;
}

static const char *hdr_magic(const uint8_t *head, size_t n)
{
    return n >= 2 && head[0] == '#' && head[1] == '?' ? NULL : "not a Radiance .hdr file (no #? magic line)";
}

/* An OpenEXR file given where a probe or image is read: its data window as RGB floats (io/exr.h),
 * negative samples (which light cannot have and RGBE cannot hold) made 0. */
static int read_exr(const char *path, int *w, int *h, float **rgb, char *err, size_t errlen)
{
    qtool_exr_info info;
    if (qtool_exr_read(path, &info, rgb, err, errlen) != 0)
        return -1;
    for (size_t i = 0; i < (size_t)info.w * (size_t)info.h * 3; ++i)
        if (!((*rgb)[i] > 0.0f)) /* negatives and -0 */
            (*rgb)[i] = 0.0f;
    *w = info.w, *h = info.h;
    return 0;
}

int qtool_hdr_read(const char *path, int *w_out, int *h_out, float **rgb_out, char *err, size_t errlen)
{
    int w, h;
    uint8_t *px;
    float *rgb;
    if (qtool_exr_sniff(path))
        return read_exr(path, w_out, h_out, rgb_out, err, errlen);
    if (qtool_hdr_read_rgbe(path, &w, &h, &px, err, errlen) != 0 || to_float(px, w, h, &rgb, err, errlen) != 0)
        return -1;
    *w_out = w;
    *h_out = h;
    *rgb_out = rgb;
    return 0;
}

int qtool_hdr_read_rgbe(const char *path, int *w, int *h, uint8_t **rgbe, char *err, size_t errlen)
{
    static const qtool_io_kind kind = {"a Radiance .hdr file", 2, QTOOL_HDR_MAX_FILE_BYTES, 2, hdr_magic};
    uint8_t *buf = NULL; /* set by qtool_io_load on success; initialised for the compiler's flow analysis */
    size_t n = 0;
    if (qtool_exr_sniff(path)) {
        float *rgb;
        int ew, eh;
        if (read_exr(path, &ew, &eh, &rgb, err, errlen) != 0)
            return -1;
        uint8_t *px = malloc((size_t)ew * (size_t)eh * 4);
        if (!px) {
            free(rgb);
            return qtool_errf(err, errlen, "%s: out of memory for %d x %d pixels", path, ew, eh);
        }
        qtool_probe_layout_rgbe_encode(rgb, (size_t)ew * (size_t)eh, px);
        free(rgb);
        *w = ew, *h = eh, *rgbe = px;
        return 0;
    }
    if (qtool_io_load(path, &kind, &buf, &n, err, errlen) != 0)
        return -1;
    char msg[256];
    int rc = qtool_hdr_decode_rgbe(buf, n, w, h, rgbe, msg, sizeof msg);
    free(buf);
    if (rc != 0)
        return qtool_errf(err, errlen, "%s: %s", path, msg);
    return 0;
}
