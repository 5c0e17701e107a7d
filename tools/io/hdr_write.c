/*
 * io/hdr_write.c - Radiance .hdr writer (io/hdr_write.h): Ward's RGBE, new-style RLE scanlines.
 */
#include "io/hdr_write.h"
#include "io/atomic.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void rgbe_of(const float c[3], uint8_t out[4])
{
    double v = c[0] > c[1] ? c[0] : c[1];
    v = c[2] > v ? c[2] : v;
    if (v < 0x1p-100) { /* below any useful exponent: the zero pixel */
        memset(out, 0, 4);
        return;
    }
    int e;
    (void)frexp(v, &e); /* v = f 2^e, f in [1/2, 1) */
    double s = ldexp(256.0, -e);
    for (int i = 0; i < 3; ++i) {
        double x = floor(c[i] * s); /* < 256 since c <= v < 2^e */
        out[i] = (uint8_t)(x > 255 ? 255 : x);
    }
    out[3] = (uint8_t)(e + 128);
}

/* one component (n bytes, stride 1) as runs and literals; returns the bytes written to o */
static size_t rle_component(const uint8_t *b, size_t n, uint8_t *o)
{
    size_t i = 0, k = 0;
    while (i < n) {
        /* the next run of 4 or more equal bytes at or after i (a shorter one costs more than literals) */
        size_t j = i, run = 0;
        for (; j < n; ++j) {
            run = 1;
            while (j + run < n && run < 127 && b[j + run] == b[j])
                ++run;
            if (run >= 4)
                break;
        }
        while (i < j) {
            size_t cnt = j - i < 128 ? j - i : 128;
            o[k++] = (uint8_t)cnt;
            memcpy(o + k, b + i, cnt);
            k += cnt, i += cnt;
        }
        if (j < n) {
            o[k++] = (uint8_t)(128 + run);
            o[k++] = b[j];
            i = j + run;
        }
    }
    return k;
}

int qtool_hdr_encode(int w, int h, const float *rgb, uint8_t **out, size_t *outlen, char *err, size_t errlen)
{
    if (w < 1 || h < 1 || w > QTOOL_HDR_WRITE_MAX_DIM || h > QTOOL_HDR_WRITE_MAX_DIM) {
        snprintf(err, errlen, "bad image size %dx%d (1..%d a side)", w, h, QTOOL_HDR_WRITE_MAX_DIM);
        return -1;
    }
    size_t np = (size_t)w * (size_t)h;
    for (size_t i = 0; i < np * 3; ++i) {
        float v = rgb[i];
        if (!(v >= 0.0f) || !(v < 0x1p127f)) { /* NaN fails both */
            snprintf(err, errlen, "sample %g at pixel (%zu, %zu) channel %zu is not a finite value in 0..2^127",
                     (double)v, (i / 3) % (size_t)w, (i / 3) / (size_t)w, i % 3);
            return -1;
        }
    }
    char head[96];
    int hn = snprintf(head, sizeof head, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n", h, w);
    int rle = w >= 8 && w < 32768;
    /* worst case per RLE row: 4 + per component n + ceil(n / 128) count bytes */
    size_t row_max = rle ? 4 + 4 * ((size_t)w + ((size_t)w + 127) / 128) : 4 * (size_t)w;
    size_t cap = (size_t)hn + row_max * (size_t)h;
    uint8_t *buf = malloc(cap), *px = malloc(4 * (size_t)w), *comp = malloc((size_t)w);
    if (!buf || !px || !comp) {
        free(buf), free(px), free(comp);
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    memcpy(buf, head, (size_t)hn);
    size_t k = (size_t)hn;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x)
            rgbe_of(rgb + 3 * ((size_t)y * (size_t)w + (size_t)x), px + 4 * (size_t)x);
        if (!rle) {
            /* no pixel reads as an old-style run (01 01 01 n): the largest channel's byte is >= 128 */
            memcpy(buf + k, px, 4 * (size_t)w);
            k += 4 * (size_t)w;
            continue;
        }
        buf[k++] = 2, buf[k++] = 2, buf[k++] = (uint8_t)(w >> 8), buf[k++] = (uint8_t)(w & 255);
        for (int c = 0; c < 4; ++c) {
            for (int x = 0; x < w; ++x)
                comp[x] = px[4 * x + c];
            k += rle_component(comp, (size_t)w, buf + k);
        }
    }
    free(px), free(comp);
    *out = buf, *outlen = k;
    return 0;
}

int qtool_hdr_write(const char *path, int w, int h, const float *rgb, char *err, size_t errlen)
{
    uint8_t *b;
    size_t n;
    char why[256];
    if (qtool_hdr_encode(w, h, rgb, &b, &n, why, sizeof why) != 0) {
        snprintf(err, errlen, "%s: %s", path, why);
        return -1;
    }
    int rc = qtool_io_write_atomic(path, b, n, err, errlen);
    free(b);
    return rc;
}
