/*
 * fuzz_layout.c - libFuzzer target: light-probe layouts (tools/io/probe_layout.c), the path the CLI
 * takes from a Radiance file's RGBE pixels to a lat-long (qtool_probe_layout_rgbe_to_latlong), with
 * detection, and the direction <-> position maps.
 *
 * Input: byte 0 the requested layout (AUTO included, sometimes out of range), bytes 1 and 2 the
 * width and height (1..64), then RGBE pixels (zeros past the end of the input), then two positions.
 *
 * Invariants: a failure writes nothing and gives one line; a success names a real layout the size
 * fits (qtool_probe_layout_check), returns the size qtool_probe_layout_latlong_size gives and a
 * buffer of exactly that many readable pixels, and a lat-long input comes back bit for bit;
 * qtool_probe_layout_dir gives unit vectors, and qtool_probe_layout_pos positions inside the image.
 */
#include <math.h>
#include <string.h>

#include "fuzz.h"
#include "io/probe_layout.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_in in = {data, size};
    const uint8_t lb = fuzz_u8(&in);
    const qtool_probe_layout_t want = (qtool_probe_layout_t)(lb % (QTOOL_PROBE_LAYOUT_COUNT + 1));
    const int w = 1 + fuzz_u8(&in) % 64, h = 1 + fuzz_u8(&in) % 64;
    const size_t n = (size_t)w * (size_t)h;
    uint8_t *rgbe = malloc(4 * n);
    for (size_t i = 0; i < 4 * n; ++i)
        rgbe[i] = fuzz_u8(&in);

    char err[256];
    memset(err, 0, sizeof err);
    qtool_probe_layout_t used = (qtool_probe_layout_t)77;
    int ow = -7, oh = -7;
    uint8_t *out = (uint8_t *)&err;
    int rc = qtool_probe_layout_rgbe_to_latlong(want, w, h, rgbe, &used, &ow, &oh, &out, err, sizeof err);
    if (rc != 0) {
        FUZZ_CHECK(rc == -1 && ow == -7 && oh == -7 && out == (uint8_t *)&err);
        FUZZ_CHECK(fuzz_one_line(err, sizeof err));
    } else {
        FUZZ_CHECK(used > QTOOL_PROBE_LAYOUT_AUTO && used < QTOOL_PROBE_LAYOUT_COUNT);
        FUZZ_CHECK(want == QTOOL_PROBE_LAYOUT_AUTO || used == want);
        FUZZ_CHECK(qtool_probe_layout_check(used, w, h, err, sizeof err) == 0);
        int ew = 0, eh = 0;
        FUZZ_CHECK(qtool_probe_layout_latlong_size(used, w, h, &ew, &eh, err, sizeof err) == 0);
        FUZZ_CHECK(ow == ew && oh == eh && ow >= 1 && oh >= 1);
        if (used == QTOOL_PROBE_LAYOUT_LATLONG)
            FUZZ_CHECK(ow == w && oh == h && memcmp(out, rgbe, 4 * n) == 0);
        volatile unsigned sum = 0;
        for (size_t i = 0; i < 4 * (size_t)ow * (size_t)oh; ++i)
            sum += out[i];
        (void)sum;
        free(out);
    }

    /* the maps between image positions and directions, for a real layout */
    const qtool_probe_layout_t lay = (qtool_probe_layout_t)(1 + lb % (QTOOL_PROBE_LAYOUT_COUNT - 1));
    if (qtool_probe_layout_check(lay, w, h, err, sizeof err) == 0) {
        const double x = (double)fuzz_u16(&in) / 65535.0 * w, y = (double)fuzz_u16(&in) / 65535.0 * h;
        double d[3] = {0, 0, 0}, px = -1, py = -1;
        if (qtool_probe_layout_dir(lay, w, h, x, y, d) == 0) {
            FUZZ_CHECK(fabs(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] - 1.0) < 1e-9);
            FUZZ_CHECK(qtool_probe_layout_pos(lay, w, h, d, &px, &py) == 0);
            FUZZ_CHECK(px >= 0 && px <= w && py >= 0 && py <= h);
        }
        const double z[3] = {0, 0, 0};
        FUZZ_CHECK(qtool_probe_layout_pos(lay, w, h, z, &px, &py) == -1);
    }
    free(rgbe);
    return 0;
}
