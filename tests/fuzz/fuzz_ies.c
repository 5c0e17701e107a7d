/*
 * fuzz_ies.c - libFuzzer target: the IES LM-63 reader (tools/io/ies.c, qtool_ies_decode), the flux
 * integral and the candela lookup.
 *
 * Invariants: a failure leaves the output untouched and gives a one-line reason; a success gives
 * counts within the caps, angles strictly increasing inside their type's range, a symmetry that
 * matches the horizontal grid, candela values finite and in [cd_min, cd_max], a flux finite and
 * between 0 and 4 pi cd_max times the ballast factors, and a lookup toward any direction finite and
 * within [0, cd_max] times the same factors (bilinear interpolation cannot leave the data's range).
 */
#include <math.h>
#include <string.h>

#include "fuzz.h"
#include "io/ies.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char err[256];
    qtool_ies e, before;
    memset(&e, 0x5A, sizeof e);
    before = e;
    memset(err, 0, sizeof err);
    int rc = qtool_ies_decode(data, size, &e, err, sizeof err);
    if (rc != 0) {
        FUZZ_CHECK(rc == -1 && memcmp(&e, &before, sizeof e) == 0);
        FUZZ_CHECK(fuzz_one_line(err, sizeof err));
        return 0;
    }
    FUZZ_CHECK(e.nv >= 2 && e.nv <= QTOOL_IES_MAX_ANGLES && e.nh >= 1 && e.nh <= QTOOL_IES_MAX_ANGLES);
    FUZZ_CHECK((uint64_t)e.nv * e.nh <= QTOOL_IES_MAX_VALUES);
    FUZZ_CHECK(e.type >= 1 && e.type <= 3 && e.units >= 1 && e.units <= 2);
    FUZZ_CHECK(e.multiplier > 0 && e.ballast_factor > 0 && e.nlamps >= 1);
    int c = e.type == QTOOL_IES_TYPE_C;
    for (uint32_t i = 0; i < e.nv; ++i)
        FUZZ_CHECK(e.v[i] >= (c ? 0 : -90) && e.v[i] <= (c ? 180 : 90) && (i == 0 || e.v[i] > e.v[i - 1]));
    for (uint32_t j = 0; j < e.nh; ++j)
        FUZZ_CHECK(e.h[j] >= (c ? 0 : -90) && e.h[j] <= (c ? 360 : 90) && (j == 0 || e.h[j] > e.h[j - 1]));
    FUZZ_CHECK(c ? e.sym >= QTOOL_IES_SYM_AXIAL && e.sym <= QTOOL_IES_SYM_FULL
                 : e.sym == QTOOL_IES_SYM_AB_HALF || e.sym == QTOOL_IES_SYM_AB_FULL);
    FUZZ_CHECK((e.sym == QTOOL_IES_SYM_AXIAL) == (e.nh == 1));
    for (size_t k = 0; k < (size_t)e.nv * e.nh; ++k)
        FUZZ_CHECK(isfinite(e.cd[k]) && e.cd[k] >= e.cd_min && e.cd[k] <= e.cd_max);
    FUZZ_CHECK(e.cd_min >= 0);
    double f = e.ballast_factor * (e.version <= 1995 ? e.factor2 : 1.0);
    double top = e.cd_max * f;
    double lm = qtool_ies_lumens(&e);
    FUZZ_CHECK(isfinite(lm) && lm >= -1e-9 * top && lm <= 4 * 3.14159265358979323846 * top * (1 + 1e-9) + 1e-300);
    /* the lookup along a fixed set of directions (poles, axes, diagonals, a spiral) */
    for (int t = 0; t < 64; ++t) {
        double z = 1 - (t + 0.5) / 32.0, r = sqrt(fmax(0, 1 - z * z)), a = t * 2.39996322972865332;
        double d[3] = {r * cos(a), r * sin(a), z};
        if (t == 0)
            d[0] = 0, d[1] = 0, d[2] = 1;
        if (t == 63)
            d[0] = 0, d[1] = 0, d[2] = -1;
        double x = qtool_ies_candela(&e, d);
        FUZZ_CHECK(isfinite(x) && x >= 0 && x <= top * (1 + 1e-9));
    }
    qtool_ies_free(&e);
    return 0;
}
