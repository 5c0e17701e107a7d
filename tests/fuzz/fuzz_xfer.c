/*
 * fuzz_xfer.c - libFuzzer target for the exported transfer's reader and span shade (core/src/
 * hemi_xfer.c: qibl_hemi_xfer_open, qibl_hemi_xfer_shade_span).
 *
 * Input: bytes 0..1 the span's first vertex, 2..3 its count (little-endian), 4 a light seed, then
 * an export (layout in qibl/hemi.h). Invariants checked (abort on violation): a refused export
 * leaves the view untouched and gets a hemi-export status; an accepted one has the size its fields
 * imply and 3..5 bands; a span past the vertices is refused with the output untouched; an accepted
 * span equals the documented sum (each product truncated by 14 bits, rounded half up by 16,
 * saturated) computed here independently, for every vertex of the span (ASan checks the reads).
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "qibl/hemi.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static int32_t s32le(const uint8_t *p)
{
    const uint32_t u = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
    return u <= 0x7FFFFFFFu ? (int32_t)u : -(int32_t)(~u) - 1;
}

/* floor(x / 2^n) without shifting a negative value */
static int64_t floor_shift(int64_t x, unsigned n)
{
    const int64_t d = (int64_t)1 << n;
    return x >= 0 ? x / d : -((-x + d - 1) / d);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 5)
        return 0;
    const uint32_t first = (uint32_t)data[0] | (uint32_t)data[1] << 8, count = (uint32_t)data[2] | (uint32_t)data[3] << 8;
    uint32_t seed = data[4] * 2654435761u + 1u;
    const uint8_t *f = data + 5;
    const size_t n = size - 5;
    qibl_hemi_xfer_t x, before;
    memset(&x, 0x5A, sizeof x);
    memcpy(&before, &x, sizeof x);
    const qibl_status_t st = qibl_hemi_xfer_open(&x, f, n);
    if (st != QIBL_OK) {
        if (memcmp(&x, &before, sizeof x) != 0 || st < QIBL_E_HEMI_XFER_SHORT || st > QIBL_E_HEMI_XFER_CRC)
            abort();
        return 0;
    }
    if (x.bands < 3 || x.bands > 5 || x.ncoef != x.bands * x.bands || x.count == 0 ||
        n != QIBL_HEMI_XFER_HEADER_SIZE + (size_t)x.count * x.ncoef * 4u || x.payload != f + QIBL_HEMI_XFER_HEADER_SIZE)
        abort();
    int32_t light[3][QIBL_HEMI_COEFFS];
    for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i < QIBL_HEMI_COEFFS; ++i)
            light[ch][i] = (int32_t)((seed = seed * 1664525u + 1013904223u) >> (ch + 1)) - (int32_t)(0x7FFFFFFFu >> (ch + 1));
    enum { MAXV = 64 };
    static qibl_q16_t out[MAXV + 1][3];
    const uint32_t want = count > MAXV ? MAXV : count;
    memset(out, 0xA5, sizeof out);
    const qibl_status_t ss = qibl_hemi_xfer_shade_span(&x, (const int32_t(*)[QIBL_HEMI_COEFFS])light, first, want, out);
    if (first > x.count || want > x.count - first) {
        for (size_t b = 0; b < sizeof out; ++b)
            if (((const uint8_t *)out)[b] != 0xA5)
                abort();
        if (ss != QIBL_E_HEMI_XFER_BOUNDS)
            abort();
        return 0;
    }
    if (ss != QIBL_OK)
        abort();
    for (uint32_t k = 0; k < want; ++k)
        for (int ch = 0; ch < 3; ++ch) {
            int64_t s = 0;
            for (uint32_t i = 0; i < x.ncoef; ++i)
                s += floor_shift((int64_t)light[ch][i] * s32le(x.payload + 4u * ((size_t)(first + k) * x.ncoef + i)), 14);
            int64_t r = floor_shift(s + ((int64_t)1 << 15), 16);
            r = r > INT32_MAX ? INT32_MAX : r < INT32_MIN ? INT32_MIN : r;
            if (out[k][ch] != (int32_t)r)
                abort();
        }
    return 0;
}
