/*
 * fuzz_hdr.c - libFuzzer target: the Radiance .hdr reader (tools/io/hdr.c), both decoders.
 *
 * Invariants: a failure leaves the outputs untouched and gives a one-line reason; a success gives
 * 1 <= w, h and a buffer of exactly 4 w h (RGBE) or 3 w h (float) values; the float decoder accepts
 * nothing the RGBE one refuses, and each float is the RGBE pixel's m * 2^(E - 136) (0 for E = 0), as
 * hdr.h states.
 */
#include <math.h>
#include <string.h>

#include "fuzz.h"
#include "io/hdr.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char err[256], err2[256];
    int w = -7, h = -7, w2 = -7, h2 = -7;
    uint8_t *rgbe = (uint8_t *)&err; /* sentinels: a failing call must not touch them */
    float *rgb = (float *)&err2;
    memset(err, 0, sizeof err);
    memset(err2, 0, sizeof err2);
    int rc = qtool_hdr_decode_rgbe(data, size, &w, &h, &rgbe, err, sizeof err);
    int rc2 = qtool_hdr_decode(data, size, &w2, &h2, &rgb, err2, sizeof err2);
    if (rc != 0) {
        FUZZ_CHECK(rc == -1 && w == -7 && h == -7 && rgbe == (uint8_t *)&err);
        FUZZ_CHECK(fuzz_one_line(err, sizeof err));
    }
    if (rc2 != 0) {
        FUZZ_CHECK(rc2 == -1 && w2 == -7 && h2 == -7 && rgb == (float *)&err2);
        FUZZ_CHECK(fuzz_one_line(err2, sizeof err2));
    }
    /* the float decoder is the RGBE one plus a conversion: it cannot accept what the RGBE one
     * refuses (it may refuse more: a limit on the float output) */
    FUZZ_CHECK(rc2 != 0 || rc == 0);
    if (rc == 0 && rc2 != 0)
        free(rgbe);
    if (rc == 0 && rc2 == 0) {
        FUZZ_CHECK(w >= 1 && h >= 1 && w == w2 && h == h2);
        size_t n = (size_t)w * (size_t)h;
        for (size_t i = 0; i < n; ++i) {
            const uint8_t *q = rgbe + 4 * i;
            for (int c = 0; c < 3; ++c) {
                float want = q[3] == 0 ? 0.0f : (float)ldexp((double)q[c], (int)q[3] - 136);
                FUZZ_CHECK(memcmp(&rgb[3 * i + (size_t)c], &want, sizeof want) == 0);
            }
        }
        free(rgbe);
        free(rgb);
    }
    return 0;
}
