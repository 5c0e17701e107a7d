/*
 * ref/rgb9e5.c - RGB9E5 from the EXT_texture_shared_exponent pseudo-code.
 */
#include "ref/rgb9e5.h"

#include <math.h>

#define N 9            /* mantissa bits */
#define B 15           /* exponent bias */
#define EMAX 31        /* largest exponent */
#define SHAREDEXP_MAX 65408.0 /* (2^N - 1) / 2^N * 2^(EMAX - B) */

static double clamp_range(float x)
{
    /* NaN fails both comparisons and becomes 0, as the spec asks */
    return x > 0.0f ? (x < SHAREDEXP_MAX ? (double)x : SHAREDEXP_MAX) : 0.0;
}

uint32_t qtool_ref_rgb9e5_encode(const float rgb[3])
{
    double rc = clamp_range(rgb[0]), gc = clamp_range(rgb[1]), bc = clamp_range(rgb[2]);
    double maxc = rc > gc ? rc : gc;
    if (bc > maxc)
        maxc = bc;
    int fl = -B - 1; /* max(-B - 1, floor(log2(maxc))), log2(0) = -inf */
    if (maxc > 0.0) {
        int k;
        frexp(maxc, &k);
        if (k - 1 > fl)
            fl = k - 1;
    }
    int exp_shared = fl + 1 + B;
    double maxs = floor(ldexp(maxc, -(exp_shared - B - N)) + 0.5);
    if (maxs == (double)(1 << N))
        exp_shared += 1;
    uint32_t rs = (uint32_t)floor(ldexp(rc, -(exp_shared - B - N)) + 0.5);
    uint32_t gs = (uint32_t)floor(ldexp(gc, -(exp_shared - B - N)) + 0.5);
    uint32_t bs = (uint32_t)floor(ldexp(bc, -(exp_shared - B - N)) + 0.5);
    return rs | gs << 9 | bs << 18 | (uint32_t)exp_shared << 27;
}

void qtool_ref_rgb9e5_decode(uint32_t v, float rgb[3])
{
    int e = (int)(v >> 27) - B - N;
    rgb[0] = (float)ldexp((double)(v & 511u), e);
    rgb[1] = (float)ldexp((double)((v >> 9) & 511u), e);
    rgb[2] = (float)ldexp((double)((v >> 18) & 511u), e);
}

void qtool_ref_rgb9e5_encode_n(const float *rgb, size_t n, uint32_t *out)
{
    for (size_t i = 0; i < n; ++i)
        out[i] = qtool_ref_rgb9e5_encode(rgb + 3 * i);
}

void qtool_ref_rgb9e5_decode_n(const uint32_t *in, size_t n, float *rgb)
{
    for (size_t i = 0; i < n; ++i)
        qtool_ref_rgb9e5_decode(in[i], rgb + 3 * i);
}
