/*
 * fuzz_lightcsv.c - libFuzzer target: the light list reader of `qibl relight --lights`
 * (tools/io/lightcsv.c, qtool_lightcsv_parse).
 *
 * Invariants: a failure leaves the outputs untouched, allocates nothing (the leak checker sees it)
 * and gives a one-line reason; a success gives at most QTOOL_LIGHTCSV_MAX lights, every direction
 * of unit length in Q2.30 (within 2 LSB: the scaling before squaring keeps tiny and huge
 * components), every channel in 0 .. 2^30 and an exponent that puts the largest below 2^30.
 */
#include <math.h>
#include <string.h>

#include "fuzz.h"
#include "io/lightcsv.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char err[256];
    qibl_lightprobe_light_t *L = (qibl_lightprobe_light_t *)(uintptr_t)0x1;
    uint32_t n = 0xA5A5A5A5u;
    int32_t e = 0x5A5A5A5A;
    memset(err, 0, sizeof err);
    int rc = qtool_lightcsv_parse("fuzz.csv", (const char *)data, size, &L, &n, &e, err, sizeof err);
    if (rc != 0) {
        FUZZ_CHECK(rc == -1);
        FUZZ_CHECK(L == (qibl_lightprobe_light_t *)(uintptr_t)0x1 && n == 0xA5A5A5A5u && e == 0x5A5A5A5A);
        FUZZ_CHECK(fuzz_one_line(err, sizeof err));
        return 0;
    }
    FUZZ_CHECK(L != NULL && n <= QTOOL_LIGHTCSV_MAX);
    int32_t mx = 0;
    for (uint32_t i = 0; i < n; ++i) {
        double d2 = 0;
        for (int c = 0; c < 3; ++c) {
            d2 += (double)L[i].dir[c] * L[i].dir[c];
            FUZZ_CHECK(L[i].rgb[c] >= 0 && L[i].rgb[c] <= (1 << 30));
            mx = L[i].rgb[c] > mx ? L[i].rgb[c] : mx;
        }
        FUZZ_CHECK(fabs(sqrt(d2) - 1073741824.0) <= 2.0);
    }
    FUZZ_CHECK(mx == 0 || mx >= (1 << 28)); /* the largest channel keeps at least 28 bits */
    FUZZ_CHECK(e >= -1200 && e <= 1100);
    free(L);
    return 0;
}
