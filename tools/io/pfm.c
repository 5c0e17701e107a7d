/*
 * io/pfm.c - Portable Float Map reader and writer.
 *
 * Header: "PF" or "Pf", whitespace, width, whitespace, height, whitespace, scale (a non-zero finite
 * decimal; its sign gives the byte order, its magnitude is ignored), then exactly one whitespace
 * byte and the samples. Comments are not part of the format and are refused.
 */
#include "io/pfm.h"
#include "io/atomic.h"
#include "io/file.h"

#include "qtool.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int is_ws(uint8_t c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r';
}

/* next whitespace-delimited token of at most 63 printable bytes into tok; -1 at end of data, -2 on
 * a non-printable byte (a NUL would cut the number short for strtol, a \v or \f is skipped by
 * strtod: the header is text) */
static int token(const uint8_t *buf, size_t len, size_t *pos, char tok[64])
{
    while (*pos < len && *pos < QTOOL_PFM_MAX_HEADER_BYTES && is_ws(buf[*pos]))
        ++*pos;
    size_t n = 0;
    while (*pos < len && !is_ws(buf[*pos]) && n < 63) {
        if (buf[*pos] < 0x21 || buf[*pos] > 0x7E)
            return -2; /* *pos stays on the byte */
        tok[n++] = (char)buf[(*pos)++];
    }
    tok[n] = '\0';
    if (n == 0 || (*pos < len && !is_ws(buf[*pos])))
        return -1;
    return 0;
}

static int decode_impl(const char *name, const uint8_t *buf, size_t len, int *w_out, int *h_out, int *ch_out,
                       float **px_out, char *err, size_t errlen)
{
    if (len < 2 || buf[0] != 'P' || (buf[1] != 'F' && buf[1] != 'f') || (len > 2 && !is_ws(buf[2])))
        return qtool_errf_at(err, errlen, name, 0, "not a PFM file (magic must be PF or Pf)");
    int ch = buf[1] == 'F' ? 3 : 1;
    size_t pos = 2;
    char t[3][64];
    for (int i = 0; i < 3; ++i) {
        int r = token(buf, len, &pos, t[i]);
        if (r == -2)
            return qtool_errf_at(err, errlen, name, 0, "byte 0x%02x at offset %zu in the header (not text)", buf[pos], pos);
        if (r != 0)
            return qtool_errf_at(err, errlen, name, 0, "truncated or malformed header");
    }
    char *end;
    errno = 0;
    long w = strtol(t[0], &end, 10);
    if (*end || errno || w < 1 || w > (long)QTOOL_PFM_MAX_DIM)
        return qtool_errf_at(err, errlen, name, 0, "bad width '%s' (1..%u)", t[0], QTOOL_PFM_MAX_DIM);
    long h = strtol(t[1], &end, 10);
    if (*end || errno || h < 1 || h > (long)QTOOL_PFM_MAX_DIM)
        return qtool_errf_at(err, errlen, name, 0, "bad height '%s' (1..%u)", t[1], QTOOL_PFM_MAX_DIM);
    if ((uint64_t)w * (uint64_t)h > QIBL_PFM_MAX_PIXELS)
        return qtool_errf_at(err, errlen, name, 0, "%ld x %ld pixels, above the %lu-pixel limit (QIBL_PFM_MAX_PIXELS)", w, h,
                    (unsigned long)QIBL_PFM_MAX_PIXELS);
    double scale = strtod(t[2], &end);
    if (*end || !isfinite(scale) || scale == 0.0)
        return qtool_errf_at(err, errlen, name, 0, "bad scale '%s' (a non-zero number; negative means little-endian)", t[2]);
    if (pos >= len || !is_ws(buf[pos]))
        return qtool_errf_at(err, errlen, name, 0, pos >= QTOOL_PFM_MAX_HEADER_BYTES ? "header longer than %u bytes" : "truncated header",
                    QTOOL_PFM_MAX_HEADER_BYTES);
    ++pos; /* the single whitespace byte before the data */
    size_t n = (size_t)w * (size_t)h * (size_t)ch;
    if (len - pos < n * 4)
        return qtool_errf_at(err, errlen, name, 0, "truncated: %zu bytes of samples, %zu expected", len - pos, n * 4);
    float *px = malloc(n * sizeof(float));
    if (!px)
        return qtool_errf_at(err, errlen, name, 0, "out of memory");
    int little = scale < 0;
    size_t row = (size_t)w * (size_t)ch;
    for (long y = 0; y < h; ++y) {
        const uint8_t *src = buf + pos + (size_t)y * row * 4;
        float *dst = px + (size_t)(h - 1 - y) * row; /* bottom row first in the file */
        for (size_t i = 0; i < row; ++i) {
            const uint8_t *b = src + 4 * i;
            uint32_t u = little ? (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24
                                : (uint32_t)b[3] | (uint32_t)b[2] << 8 | (uint32_t)b[1] << 16 | (uint32_t)b[0] << 24;
            float f;
            memcpy(&f, &u, 4);
            if (!isfinite(f)) {
                free(px);
                return qtool_errf_at(err, errlen, name, 0, "non-finite sample %s at column %zu, row %ld from the top, channel %zu",
                            isnan(f) ? "nan" : f > 0 ? "inf" : "-inf", i / (size_t)ch, h - 1 - y, i % (size_t)ch);
            }
            dst[i] = f;
        }
    }
    *w_out = (int)w, *h_out = (int)h, *ch_out = ch, *px_out = px;
    return 0;
}

int qtool_pfm_decode(const uint8_t *buf, size_t len, int *w, int *h, int *channels, float **px, char *err,
                    size_t errlen)
{
    return decode_impl(NULL, buf, len, w, h, channels, px, err, errlen);
}

static const char *pfm_magic(const uint8_t *b, size_t n)
{
    return n >= 3 && b[0] == 'P' && (b[1] == 'F' || b[1] == 'f') && is_ws(b[2]) ? NULL
                                                                               : "not a PFM file (magic must be PF or Pf)";
}

int qtool_pfm_read(const char *path, int *w, int *h, int *channels, float **px, char *err, size_t errlen)
{
    static const qtool_io_kind kind = {"a PFM file", 3, QTOOL_PFM_MAX_FILE_BYTES, 3, pfm_magic};
    size_t n = 0;
    uint8_t *buf = NULL;
    if (qtool_io_load(path, &kind, &buf, &n, err, errlen) != 0)
        return -1;
    int rc = decode_impl(path, buf, n, w, h, channels, px, err, errlen);
    free(buf);
    return rc;
}

int qtool_pfm_write(const char *path, int w, int h, int channels, const float *px, char *err, size_t errlen)
{
    if (w < 1 || h < 1 || w > 65535 || h > 65535 || (channels != 1 && channels != 3))
        return qtool_errf_at(err, errlen, path, 0, "bad PFM size %dx%d or channel count %d", w, h, channels);
    size_t row = (size_t)w * (size_t)channels;
    /* a non-finite sample is refused: no reader could tell it from a corrupt file */
    for (size_t i = 0; i < row * (size_t)h; ++i)
        if (!isfinite(px[i]))
            return qtool_errf_at(err, errlen, path, 0, "refusing to write a non-finite sample (%g at pixel %zu, channel %zu)",
                        (double)px[i], i / (size_t)channels, i % (size_t)channels);
    uint8_t *line = malloc(row * 4);
    if (!line)
        return qtool_errf_at(err, errlen, path, 0, "out of memory");
    qtool_io_atomic a;
    if (qtool_io_atomic_open(&a, path, err, errlen) != 0) {
        free(line);
        return -1;
    }
    int bad = fprintf(a.f, "%s\n%d %d\n-1.0\n", channels == 3 ? "PF" : "Pf", w, h) < 0;
    for (int y = h - 1; y >= 0 && !bad; --y) {
        for (size_t i = 0; i < row; ++i) {
            uint32_t u;
            memcpy(&u, &px[(size_t)y * row + i], 4);
            line[4 * i] = (uint8_t)u, line[4 * i + 1] = (uint8_t)(u >> 8);
            line[4 * i + 2] = (uint8_t)(u >> 16), line[4 * i + 3] = (uint8_t)(u >> 24);
        }
        bad |= fwrite(line, 4, row, a.f) != row;
    }
    free(line);
    if (bad) {
        qtool_errf_at(err, errlen, path, 0, "write failed: %s", strerror(errno));
        qtool_io_atomic_abort(&a);
        return -1;
    }
    return qtool_io_atomic_commit(&a, err, errlen);
}
