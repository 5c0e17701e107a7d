/*
 * fuzz_exr.c - libFuzzer target: the OpenEXR reader (tools/io/exr.c, qtool_exr_decode) and, on what
 * it accepts, the writer.
 *
 * Invariants: a failure leaves the outputs untouched and gives a one-line reason; a success gives
 * 1 <= w, h <= QTOOL_EXR_MAX_DIM, w h <= QTOOL_EXR_MAX_PIXELS, a data window of that size, a display
 * window that is a box, a compression the reader names (0..4), 3 w h finite samples (a grey image has
 * R = G = B), and the input holds at least 8 bytes of offset table per chunk. The decoded image
 * written as FLOAT (NONE and ZIP) decodes back bit for bit.
 */
#include <math.h>
#include <string.h>

#include "fuzz.h"
#include "io/exr.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char err[256];
    qtool_exr_info info;
    memset(&info, 0x5A, sizeof info);
    float *px = (float *)&err;
    memset(err, 0, sizeof err);
    int rc = qtool_exr_decode(data, size, &info, &px, err, sizeof err);
    if (rc != 0) {
        FUZZ_CHECK(rc == -1 && px == (float *)&err && info.w == 0x5A5A5A5A);
        FUZZ_CHECK(fuzz_one_line(err, sizeof err));
        return 0;
    }
    FUZZ_CHECK(info.w >= 1 && info.h >= 1 && info.w <= (int)QTOOL_EXR_MAX_DIM && info.h <= (int)QTOOL_EXR_MAX_DIM);
    FUZZ_CHECK((uint64_t)info.w * (uint64_t)info.h <= QTOOL_EXR_MAX_PIXELS);
    FUZZ_CHECK((int64_t)info.data[2] - info.data[0] + 1 == info.w && (int64_t)info.data[3] - info.data[1] + 1 == info.h);
    FUZZ_CHECK(info.display[2] >= info.display[0] && info.display[3] >= info.display[1]);
    FUZZ_CHECK(info.compression >= 0 && info.compression <= 4 && info.channels >= 1 &&
               info.channels <= QTOOL_EXR_MAX_CHANNELS);
    size_t n = (size_t)info.w * (size_t)info.h;
    size_t chunks = info.tiled ? (size_t)((info.w + info.tile_w - 1) / info.tile_w) *
                                     (size_t)((info.h + info.tile_h - 1) / info.tile_h)
                               : (size_t)info.h; /* at least one line per chunk */
    FUZZ_CHECK(info.tiled ? size / 8 >= chunks : size / 8 >= chunks / 32);
    for (size_t i = 0; i < 3 * n; ++i)
        FUZZ_CHECK(isfinite(px[i]));
    if (info.grey)
        for (size_t i = 0; i < n; ++i)
            FUZZ_CHECK(!memcmp(&px[3 * i], &px[3 * i + 1], 4) && !memcmp(&px[3 * i], &px[3 * i + 2], 4));
    for (int comp = QTOOL_EXR_NONE; comp <= QTOOL_EXR_ZIP; comp += QTOOL_EXR_ZIP) {
        uint8_t *f;
        size_t fn;
        FUZZ_CHECK(qtool_exr_encode(info.w, info.h, px, QTOOL_EXR_FLOAT, comp, &f, &fn, err, sizeof err) == 0);
        float *back;
        qtool_exr_info bi;
        FUZZ_CHECK(qtool_exr_decode(f, fn, &bi, &back, err, sizeof err) == 0);
        FUZZ_CHECK(bi.w == info.w && bi.h == info.h && memcmp(back, px, 3 * n * sizeof(float)) == 0);
        free(back);
        free(f);
    }
    free(px);
    return 0;
}
