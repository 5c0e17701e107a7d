/*
 * fuzz_luminaire.c - libFuzzer target: the .qnf near-field source reader (tools/luminaire/format.c,
 * qtool_luminaire_decode), the writer's round trip, and the spotlights made from what it accepts.
 *
 * Invariants: a refused input leaves the output untouched and names its error; an accepted one
 * has every field within its documented bounds and every texel finite, encodes back to exactly
 * the input bytes, and its spotlights (when their intensities fit Q16.16) light a fixed set of
 * points, including extreme ones, with sums that stay within the per-pass bound (count 2^50 in Q8.24).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz.h"
#include "luminaire/luminaire.h"
#include "qibl/asset.h" /* qibl_crc32 */

static void put32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v, p[1] = (uint8_t)(v >> 8), p[2] = (uint8_t)(v >> 16), p[3] = (uint8_t)(v >> 24);
}

static int one(const uint8_t *data, size_t size);

/* Inputs whose last byte is 0xC5 have their CRCs made right first (header and payload as the
 * header's payload size says, where the input holds it), so the mutator reaches the field checks
 * and the spotlights behind the CRC gate; every other input is taken as it is. */
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 65 || data[size - 1] != 0xC5)
        return one(data, size);
    size_t n = size - 1;
    uint8_t *c = malloc(n);
    if (!c)
        return 0;
    memcpy(c, data, n);
    uint32_t pb = (uint32_t)c[40] | (uint32_t)c[41] << 8 | (uint32_t)c[42] << 16 | (uint32_t)c[43] << 24;
    put32(c + 44, qibl_crc32(0, c + 64, pb <= n - 64 ? pb : n - 64));
    put32(c + 48, qibl_crc32(0, c, 48));
    one(c, n);
    free(c);
    return 0;
}

static int one(const uint8_t *data, size_t size)
{
    qtool_luminaire l, before;
    memset(&l, 0x5A, sizeof l);
    before = l;
    qtool_luminaire_err e = qtool_luminaire_decode(data, size, &l);
    if (e != QTOOL_LUMINAIRE_OK) {
        FUZZ_CHECK(memcmp(&l, &before, sizeof l) == 0);
        FUZZ_CHECK(e > QTOOL_LUMINAIRE_OK && e <= QTOOL_LUMINAIRE_E_WRITE);
        FUZZ_CHECK(strcmp(qtool_luminaire_err_str(e), "unknown error") != 0);
        return 0;
    }
    FUZZ_CHECK(l.nx >= 1 && l.nx <= QTOOL_LUMINAIRE_MAX_GRID && l.ny >= 1 && l.ny <= QTOOL_LUMINAIRE_MAX_GRID);
    FUZZ_CHECK(l.res >= QTOOL_LUMINAIRE_MIN_RES && l.res <= QTOOL_LUMINAIRE_MAX_RES);
    FUZZ_CHECK((uint64_t)l.nx * l.ny * l.res * l.res <= QTOOL_LUMINAIRE_MAX_TEXELS);
    FUZZ_CHECK(l.basis == QTOOL_LUMINAIRE_BOX || l.basis == QTOOL_LUMINAIRE_TENT);
    FUZZ_CHECK(isfinite(l.spacing) && l.spacing > 0 && isfinite(l.distance) && l.distance > 0);
    FUZZ_CHECK(isfinite(l.half_tan) && l.half_tan >= 0.01f && l.half_tan <= 16);
    FUZZ_CHECK(qtool_luminaire_check(&l) == QTOOL_LUMINAIRE_OK);
    uint8_t *b = NULL;
    size_t n = 0;
    FUZZ_CHECK(qtool_luminaire_encode(&l, &b, &n) == QTOOL_LUMINAIRE_OK);
    FUZZ_CHECK(n == size && memcmp(b, data, size) == 0);
    free(b);
    /* the spotlights, near and far, on a few points below, on and above the plane, and extreme */
    static const int32_t pos[3] = {0, 0, 65536};
    /* far 2: the near field with the hierarchy (small grids only: its build is grid^2 per level) */
    for (int far = 0; far < 3; ++far) {
        qtool_luminaire_spots s;
        char err[128];
        err[0] = 0;
        if (far == 2 && l.nx * l.ny > 64)
            break;
        const qtool_luminaire_spots_opts so = {.n = 8, .far = far == 1, .tol = far == 2 ? 0.3 : 0};
        if (qtool_luminaire_spots_build(&l, pos, &so, &s, err, sizeof err) != 0) {
            FUZZ_CHECK(fuzz_one_line(err, sizeof err));
            continue;
        }
        FUZZ_CHECK(s.count <= (far == 1 ? 1u : l.nx * l.ny) && s.total >= s.count);
        int32_t pts[6 * 3] = {0, 0, 0, 30000, -20000, -65536, 0, 0, 65536, 0, 0, 65535,
                              INT32_MAX, INT32_MIN, INT32_MIN, INT32_MIN, INT32_MAX, INT32_MAX};
        int32_t base[4 * 6 * 3];
        for (int k = 0; k < 72; ++k)
            base[k] = k & 1 ? INT32_MIN : INT32_MAX;
        int64_t acc[18] = {0}, ws[6 * QTOOL_LUMINAIRE_WS_PER_PIXEL];
        qtool_luminaire_spots_span(&s, base, pts, 6, acc, ws);
        for (int k = 0; k < 18; ++k) {
            uint64_t m = acc[k] < 0 ? (uint64_t)0 - (uint64_t)acc[k] : (uint64_t)acc[k];
            FUZZ_CHECK(m <= (uint64_t)s.total << 50); /* a pixel's passes: one key's lamps */
        }
        qtool_luminaire_spots_free(&s);
    }
    qtool_luminaire_free(&l);
    return 0;
}
