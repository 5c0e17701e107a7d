/*
 * fuzz_png.c - libFuzzer target: the PNG/APNG reader (tools/io/pngread.c, qtool_png_decode_rgb8).
 *
 * Each input is decoded twice: as it is, and with every chunk CRC repaired, so that mutations get
 * past the CRC check to IHDR, the APNG bookkeeping and inflate.
 *
 * Invariants: a failure leaves the outputs untouched and gives a one-line reason; a success gives
 * 1 <= w, h, at least one frame and 3 w h bytes (every one of them readable: ASan checks), and the
 * IHDR's own width and height. With repaired CRCs no CRC mismatch can be reported.
 */
#include <string.h>

#include "fuzz.h"
#include "io/png.h"
#include "qibl/asset.h" /* qibl_crc32 */

static uint32_t be32(const uint8_t *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

static void decode(const uint8_t *data, size_t size, int repaired)
{
    char err[256];
    int w = -7, h = -7, frames = -7;
    uint8_t *rgb = (uint8_t *)&err;
    memset(err, 0, sizeof err);
    int rc = qtool_png_decode_rgb8(data, size, &w, &h, &frames, &rgb, err, sizeof err);
    if (rc != 0) {
        FUZZ_CHECK(rc == -1 && w == -7 && h == -7 && frames == -7 && rgb == (uint8_t *)&err);
        FUZZ_CHECK(fuzz_one_line(err, sizeof err));
        FUZZ_CHECK(!repaired || strstr(err, "CRC mismatch") == NULL);
        return;
    }
    /* signature (8) + IHDR length and type (8): width and height follow */
    FUZZ_CHECK(w >= 1 && h >= 1 && frames >= 1 && size >= 24);
    FUZZ_CHECK(be32(data + 16) == (uint32_t)w && be32(data + 20) == (uint32_t)h);
    volatile unsigned sum = 0; /* every byte of the buffer is readable (ASan checks) */
    for (size_t i = 0; i < 3 * (size_t)w * (size_t)h; ++i)
        sum += rgb[i];
    (void)sum;
    free(rgb);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    decode(data, size, 0);
    /* repair the chunk CRCs (as far as the chunk lengths stay inside the input) and decode again */
    if (size < 8)
        return 0;
    uint8_t *b = malloc(size);
    memcpy(b, data, size);
    size_t pos = 8;
    while (size - pos >= 12) {
        uint32_t n = be32(b + pos);
        if (n > size - pos - 12)
            break;
        uint32_t crc = qibl_crc32(0, b + pos + 4, 4 + (size_t)n);
        uint8_t *c = b + pos + 8 + n;
        c[0] = (uint8_t)(crc >> 24), c[1] = (uint8_t)(crc >> 16), c[2] = (uint8_t)(crc >> 8), c[3] = (uint8_t)crc;
        pos += 12 + (size_t)n;
    }
    decode(b, size, 1);
    free(b);
    return 0;
}
