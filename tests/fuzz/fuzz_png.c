/*
 * fuzz_png.c - libFuzzer target: the PNG/APNG reader (tools/io/pngread.c, qibl_png_decode_rgb8).
 *
 * Invariants: a failure leaves the outputs untouched and gives a one-line reason; a success gives
 * 1 <= w, h, at least one frame and 3 w h bytes (every one of them readable: ASan checks), and the
 * IHDR's own width and height.
 */
#include <string.h>

#include "fuzz.h"
#include "io/png.h"

static uint32_t be32(const uint8_t *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char err[256];
    int w = -7, h = -7, frames = -7;
    uint8_t *rgb = (uint8_t *)&err;
    memset(err, 0, sizeof err);
    int rc = qibl_png_decode_rgb8(data, size, &w, &h, &frames, &rgb, err, sizeof err);
    if (rc != 0) {
        FUZZ_CHECK(rc == -1 && w == -7 && h == -7 && frames == -7 && rgb == (uint8_t *)&err);
        FUZZ_CHECK(fuzz_one_line(err, sizeof err));
        return 0;
    }
    /* signature (8) + IHDR length and type (8): width and height follow */
    FUZZ_CHECK(w >= 1 && h >= 1 && frames >= 1 && size >= 24);
    FUZZ_CHECK(be32(data + 16) == (uint32_t)w && be32(data + 20) == (uint32_t)h);
    unsigned sum = 0;
    for (size_t i = 0; i < 3 * (size_t)w * (size_t)h; ++i)
        sum += rgb[i];
    free(rgb);
    return (int)(sum & 0); /* the loop only proves every byte is inside the buffer */
}
