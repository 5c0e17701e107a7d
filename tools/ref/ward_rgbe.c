/*
 * ref/ward_rgbe.c - Ward's RGBE with frexp/ldexp, as in Graphics Gems II and Radiance.
 */
#include "ref/ward_rgbe.h"

#include <math.h>

void qtool_ref_rgbe_encode(const float rgb[3], uint8_t code[4])
{
    double r = rgb[0] > 0.0f ? rgb[0] : 0.0, g = rgb[1] > 0.0f ? rgb[1] : 0.0, b = rgb[2] > 0.0f ? rgb[2] : 0.0;
    double d = r > g ? r : g;
    if (b > d)
        d = b;
    if (d <= 1e-32) {
        code[0] = code[1] = code[2] = code[3] = 0;
        return;
    }
    int e;
    d = frexp(d, &e) * 256.0 / d; /* the largest channel becomes its mantissa in [128, 256) */
    if (e > 127) {                /* beyond the exponent byte: saturate */
        code[0] = code[1] = code[2] = 255;
        code[3] = 255;
        return;
    }
    if (e < -128) { /* below the exponent byte: zero */
        code[0] = code[1] = code[2] = code[3] = 0;
        return;
    }
    code[0] = (uint8_t)(r * d);
    code[1] = (uint8_t)(g * d);
    code[2] = (uint8_t)(b * d);
    code[3] = (uint8_t)(e + 128);
}

void qtool_ref_rgbe_decode(const uint8_t code[4], float rgb[3])
{
    if (code[3] == 0) {
        rgb[0] = rgb[1] = rgb[2] = 0.0f;
        return;
    }
    double f = ldexp(1.0, (int)code[3] - (128 + 8));
    rgb[0] = (float)((code[0] + 0.5) * f);
    rgb[1] = (float)((code[1] + 0.5) * f);
    rgb[2] = (float)((code[2] + 0.5) * f);
}

void qtool_ref_rgbe_encode_n(const float *rgb, size_t n, uint8_t *codes)
{
    for (size_t i = 0; i < n; ++i)
        qtool_ref_rgbe_encode(rgb + 3 * i, codes + 4 * i);
}

void qtool_ref_rgbe_decode_n(const uint8_t *codes, size_t n, float *rgb)
{
    for (size_t i = 0; i < n; ++i)
        qtool_ref_rgbe_decode(codes + 4 * i, rgb + 3 * i);
}
