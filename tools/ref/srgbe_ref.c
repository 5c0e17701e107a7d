/*
 * ref/srgbe_ref.c - double-precision sRGBE from the paper's formulas (see srgbe_ref.h).
 */
#include "ref/srgbe_ref.h"

#include <float.h>
#include <math.h>
#include <string.h>

static void zero_code(const double c[3], uint8_t code[4], int keep_sign)
{
    for (int i = 0; i < 3; ++i)
        code[i] = (uint8_t)(keep_sign && signbit(c[i]) ? 127 : 128);
    code[3] = 0;
}

int qtool_ref_srgbe_encode(const double c[3], uint8_t code[4])
{
    for (int i = 0; i < 3; ++i)
        if (isnan(c[i])) {
            zero_code(c, code, 0);
            return QTOOL_REF_SRGBE_NAN;
        }
    double mx = fmax(fabs(c[0]), fmax(fabs(c[1]), fabs(c[2])));
    int st = QTOOL_REF_SRGBE_OK, e;
    if (isinf(mx)) {
        e = 129;
        st = QTOOL_REF_SRGBE_INF;
    } else if (mx == 0.0) {
        zero_code(c, code, 1);
        return st;
    } else {
        int k;
        frexp(mx, &k); /* mx = f 2^k, f in [1/2, 1): floor(log2 mx) = k - 1 */
        e = (k - 1) + 2; /* the paper's exponent rule */
        if (e < -126) {
            zero_code(c, code, 1);
            return st;
        }
        if (e > 129) {
            e = 129;
            st = QTOOL_REF_SRGBE_OVERFLOW;
        }
    }
    for (int i = 0; i < 3; ++i) {
        double q;
        if (isinf(c[i])) {
            q = signbit(c[i]) ? -255.0 : 255.0;
        } else {
            /* X = round(255 (c 2^-e + 1/2))  <=>  2X - 255 = the odd integer nearest to y */
            double y = ldexp(c[i], -e) * 510.0;
            double lo = 2.0 * floor((y - 1.0) / 2.0) + 1.0, hi = lo + 2.0; /* odd, lo <= y < hi */
            double dlo = y - lo, dhi = hi - y;
            q = dlo < dhi ? lo : dhi < dlo ? hi : (signbit(c[i]) ? lo : hi);
            q = fmin(255.0, fmax(-255.0, q));
        }
        code[i] = (uint8_t)((q + 255.0) / 2.0);
    }
    code[3] = (uint8_t)(e + 126);
    return st;
}

double qtool_ref_srgbe_channel(unsigned x, unsigned E)
{
    return ldexp((2.0 * x - 255.0) / 510.0, (int)E - 126); /* one rounding (the quotient) */
}

uint32_t qtool_ref_srgbe_channel_f32(unsigned x, unsigned E, int *sat)
{
    double d = qtool_ref_srgbe_channel(x, E);
    if (fabs(d) > FLT_MAX) {
        *sat = 1;
        d = d < 0 ? -FLT_MAX : FLT_MAX;
    }
    float f = (float)d;
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

int32_t qtool_ref_srgbe_channel_s32(unsigned x, unsigned E, int frac_bits, int *sat)
{
    double y = ldexp((2.0 * x - 255.0) / 510.0, (int)E - 126 + frac_bits);
    double r = floor(y + 0.5);
    if (r > 2147483647.0) {
        *sat = 1;
        return INT32_MAX;
    }
    if (r < -2147483648.0) {
        *sat = 1;
        return INT32_MIN;
    }
    return (int32_t)r;
}

double qtool_ref_srgbe_err_in_bounds(double c, unsigned x, unsigned E)
{
    return fabs(ldexp(c, -((int)E - 126)) * 510.0 - (2.0 * x - 255.0));
}
