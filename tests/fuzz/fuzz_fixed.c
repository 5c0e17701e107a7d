/*
 * fuzz_fixed.c - libFuzzer target: the core's fixed-point helpers (qibl/fixed.h) and the SH basis
 * (qibl/sh.h), against exact integer (__int128) or long-double references, for the stated bounds.
 *
 * Input: records of 20 bytes (three u32, one u64), each driving every function:
 *   exact:   qibl_sat_s32, qibl_add_sat_s32, qibl_sub_sat_s32, qibl_mul_u32_u64, qibl_mul_s32_s64,
 *            qibl_asr_s32, qibl_shr_u64, qibl_asr_s64,
 *            qibl_udiv_u64 (quotient and remainder), qibl_isqrt_u64 (with remainder), qibl_isqrt_u32;
 *   rounded: qibl_mul_q16, qibl_mul_q30, qibl_rshr_s64 (half up, saturated), qibl_sqrt_uq16,
 *            qibl_rsqrt_uq16, qibl_recip_q16 (correctly rounded: within half an LSB, checked exactly);
 *   bounded: qibl_vec3_normalize_q30 (1 LSB), qibl_rsqrt_u64 (2^-28 relative),
 *            qibl_vec3_normalize_fast_q30 (4 LSB), qibl_sh_eval and qibl_sh_eval_unit (2^-25 against
 *            Cartesian Legendre polynomials in long double, themselves checked against the reference
 *            tools/ref/sh_ref.c away from the poles);
 *   errors:  zero divisors and vectors, out-of-range reciprocals, bad band counts: the named status
 *            and nothing written.
 */
#include <math.h>
#include <string.h>

#include "fuzz.h"
#include "qibl/fixed.h"
#include "qibl/sh.h"
#include "ref/sh_ref.h"

typedef __int128 i128;

static i128 floor_div(i128 a, i128 d) /* d > 0 */
{
    i128 q = a / d;
    return (a % d != 0 && a < 0) ? q - 1 : q;
}

static int32_t sat32(i128 v)
{
    return v > INT32_MAX ? INT32_MAX : v < INT32_MIN ? INT32_MIN : (int32_t)v;
}

static void exact(uint32_t a, uint32_t b, uint32_t c, uint64_t x)
{
    const int32_t sa = (int32_t)a, sb = (int32_t)b;
    FUZZ_CHECK(qibl_sat_s32((int64_t)x) == sat32((int64_t)x));
    FUZZ_CHECK(qibl_add_sat_s32(sa, sb) == sat32((i128)sa + sb));
    FUZZ_CHECK(qibl_sub_sat_s32(sa, sb) == sat32((i128)sa - sb));
    FUZZ_CHECK(qibl_mul_u32_u64(a, b) == (uint64_t)a * b);
    FUZZ_CHECK(qibl_mul_s32_s64(sa, sb) == (int64_t)sa * sb);
    const unsigned n32 = c % 32u, n64 = c % 64u;
    FUZZ_CHECK(qibl_asr_s32(sa, n32) == (int32_t)floor_div(sa, (i128)1 << n32));
    FUZZ_CHECK(qibl_shr_u64(x, n64) == x >> n64);
    FUZZ_CHECK(qibl_asr_s64((int64_t)x, n64) == (int64_t)floor_div((int64_t)x, (i128)1 << n64));

    /* round(x / 2^n) half up, for n in 1..62 and |x| <= 2^62, saturated */
    const int64_t x62 = (int64_t)x / 2; /* |x62| <= 2^62 */
    const unsigned n = 1u + c % 62u;
    FUZZ_CHECK(qibl_rshr_s64(x62, n) == sat32(floor_div((i128)x62 + ((i128)1 << (n - 1u)), (i128)1 << n)));
    FUZZ_CHECK(qibl_mul_q16(sa, sb) == sat32(floor_div((i128)sa * sb + (1 << 15), (i128)1 << 16)));
    FUZZ_CHECK(qibl_mul_q30(sa, sb) == sat32(floor_div((i128)sa * sb + (1 << 29), (i128)1 << 30)));

    /* division: a divisor of any size, sometimes 0 */
    const uint64_t d = (c & 1u) ? ((uint64_t)b << 32 | c) >> (c % 64u) : b >> (c % 32u);
    uint64_t rem = 0x5555u;
    const uint64_t q = qibl_udiv_u64(x, d, &rem);
    if (d == 0)
        FUZZ_CHECK(q == 0 && rem == 0x5555u);
    else
        FUZZ_CHECK(q == x / d && rem == x % d);

    /* integer square roots */
    const uint32_t r = qibl_isqrt_u64(x, &rem);
    FUZZ_CHECK((i128)r * r <= x && ((i128)r + 1) * ((i128)r + 1) > x && rem == x - (uint64_t)r * r);
    const uint32_t r32 = qibl_isqrt_u32(a);
    FUZZ_CHECK((uint64_t)r32 * r32 <= a && ((uint64_t)r32 + 1) * ((uint64_t)r32 + 1) > a);

    /* sqrt in UQ16.16: |s - sqrt(a 2^16)| <= 1/2, i.e. (2s - 1)^2 <= 4 a 2^16 <= (2s + 1)^2 */
    const i128 a4 = (i128)a << 18;
    const i128 s = qibl_sqrt_uq16(a);
    FUZZ_CHECK((s == 0 || (2 * s - 1) * (2 * s - 1) <= a4) && a4 <= (2 * s + 1) * (2 * s + 1));

    /* 1/sqrt in UQ16.16: |t - 2^24 / sqrt(a)| <= 1/2, i.e. (2t - 1)^2 a <= 2^50 <= (2t + 1)^2 a */
    qibl_uq16_t t = 0xABCDu;
    qibl_status_t st = qibl_rsqrt_uq16(a, &t);
    if (a == 0) {
        FUZZ_CHECK(st == QIBL_E_DIV_BY_ZERO && t == 0xABCDu);
    } else {
        const i128 tt = t;
        FUZZ_CHECK(st == QIBL_OK && tt >= 1 && (2 * tt - 1) * (2 * tt - 1) * a <= (i128)1 << 50 &&
                   ((i128)1 << 50) <= (2 * tt + 1) * (2 * tt + 1) * a);
    }

    /* 1/x in Q16.16: |v - 2^32 / x| <= 1/2, i.e. |2^33 - 2 v x| <= |x|; out of range for 1, 2, -1 */
    qibl_q16_t v = 0x1234;
    st = qibl_recip_q16(sa, &v);
    if (sa == 0) {
        FUZZ_CHECK(st == QIBL_E_DIV_BY_ZERO && v == 0x1234);
    } else if (sa == 1 || sa == 2 || sa == -1) {
        FUZZ_CHECK(st == QIBL_E_RANGE && v == 0x1234);
    } else {
        i128 e = ((i128)1 << 33) - 2 * (i128)v * sa;
        FUZZ_CHECK(st == QIBL_OK && (e < 0 ? -e : e) <= (sa < 0 ? -(i128)sa : sa));
    }
}

/* Y_0 .. Y_{bands^2-1} at unit (x, y, z) in long double, from Cartesian polynomials that stay
 * accurate at the poles (tools/ref/sh_ref.c goes through acos and loses ~1e-8 there):
 * Y(l, m) = N(l, |m|) (-1)^m (d^m P_l / dz^m)(z) Re or Im (x + i y)^|m|, N as in sh.h (m = 0:
 * sqrt((2l + 1) / 4 pi)). Cross-checked against sh_ref away from the poles below. */
static void sh_cartesian(long double x, long double y, long double z, int bands, long double *out)
{
    static const long double P[5][5] = {/* Legendre P_l coefficients of z^0 .. z^4 */
                                        {1, 0, 0, 0, 0},
                                        {0, 1, 0, 0, 0},
                                        {-0.5L, 0, 1.5L, 0, 0},
                                        {0, -1.5L, 0, 2.5L, 0},
                                        {0.375L, 0, -3.75L, 0, 4.375L}};
    const long double pi = 3.14159265358979323846264338327950288L;
    for (int l = 0; l < bands; ++l)
        for (int m = 0; m <= l; ++m) {
            long double c[5], d = 0, re = 1, im = 0, f = 1;
            for (int k = 0; k < 5; ++k)
                c[k] = P[l][k];
            for (int j = 0; j < m; ++j) /* differentiate m times */
                for (int k = 0; k < 5; ++k)
                    c[k] = k + 1 < 5 ? (k + 1) * c[k + 1] : 0;
            for (int k = 4; k >= 0; --k)
                d = d * z + c[k];
            for (int j = 0; j < m; ++j) { /* (x + i y)^m */
                long double r2 = re * x - im * y;
                im = re * y + im * x, re = r2;
            }
            for (int j = l - m + 1; j <= l + m; ++j)
                f *= j; /* (l + m)! / (l - m)! */
            const long double sign = (m & 1) ? -1 : 1;
            if (m == 0) {
                out[l * l + l] = sqrtl((2 * l + 1) / (4 * pi)) * d;
            } else {
                const long double n = sqrtl((2 * l + 1) / (2 * pi) / f);
                out[l * l + l + m] = n * sign * d * re;
                out[l * l + l - m] = n * sign * d * im;
            }
        }
}

static void vectors(uint32_t a, uint32_t b, uint32_t c, uint64_t x)
{
    const int32_t v[3] = {(int32_t)a, (int32_t)b, (int32_t)c};
    const long double len = sqrtl((long double)v[0] * v[0] + (long double)v[1] * v[1] + (long double)v[2] * v[2]);
    qibl_q30_t u[3] = {7, 7, 7}, f[3] = {7, 7, 7};
    uint32_t ly = 9u;
    unsigned le = 9u;
    qibl_status_t st = qibl_vec3_normalize_q30(v, u);
    qibl_status_t sf = qibl_vec3_normalize_fast_q30(v, f, &ly, &le);
    if (len == 0) {
        FUZZ_CHECK(st == QIBL_E_ZERO_VECTOR && sf == QIBL_E_ZERO_VECTOR);
        FUZZ_CHECK(u[0] == 7 && u[1] == 7 && u[2] == 7 && f[0] == 7 && f[1] == 7 && f[2] == 7 && ly == 9u && le == 9u);
    } else {
        FUZZ_CHECK(st == QIBL_OK && sf == QIBL_OK);
        for (int i = 0; i < 3; ++i) {
            const long double want = v[i] / len * 1073741824.0L;
            FUZZ_CHECK(fabsl(u[i] - want) <= 1.0L + 1e-9L);
            FUZZ_CHECK(fabsl(f[i] - want) <= 4.0L + 1e-9L);
        }
        /* 1/|v| = ly / 2^le, to the accuracy of qibl_rsqrt_u64 */
        FUZZ_CHECK(fabsl(ldexpl((long double)ly, -(int)le) * len - 1.0L) <= ldexpl(1.0L, -27));
        /* aliasing is allowed for the exact one */
        int32_t w[3] = {v[0], v[1], v[2]};
        FUZZ_CHECK(qibl_vec3_normalize_q30(w, w) == QIBL_OK && memcmp(w, u, sizeof w) == 0);
    }

    /* 1/sqrt(x) = y / 2^e, y in [2^30, 2^31], e in 31..62, relative error <= 2^-28 */
    unsigned e = 99u;
    const uint32_t y = qibl_rsqrt_u64(x, &e);
    if (x == 0) {
        FUZZ_CHECK(y == 0 && e == 0);
    } else {
        FUZZ_CHECK(y >= (1u << 30) && y <= (1u << 31) && e >= 31u && e <= 62u);
        FUZZ_CHECK(fabsl(ldexpl((long double)y, -(int)e) * sqrtl((long double)x) - 1.0L) <= ldexpl(1.0L, -28));
    }

    /* the SH basis at v, from the direction and from its Q2.30 unit vector */
    const int bands = 1 + (int)(x % 5u);
    qibl_q30_t sh[25], shu[25];
    for (int i = 0; i < 25; ++i)
        sh[i] = 11, shu[i] = 11;
    st = qibl_sh_eval(v, bands, sh);
    if (len == 0) {
        FUZZ_CHECK(st == QIBL_E_ZERO_VECTOR && sh[0] == 11);
    } else {
        FUZZ_CHECK(st == QIBL_OK);
        FUZZ_CHECK(qibl_sh_eval_unit(u, bands, shu) == QIBL_OK);
        long double ref[25];
        sh_cartesian(v[0] / len, v[1] / len, v[2] / len, bands, ref);
        double ref_d[25];
        FUZZ_CHECK(qtool_ref_sh_eval((double)v[0], (double)v[1], (double)v[2], bands, ref_d) == 0);
        for (int i = 0; i < bands * bands; ++i) {
            if (fabsl(v[2] / len) < 0.9L) /* the two references agree away from the poles */
                FUZZ_CHECK(fabsl(ref[i] - ref_d[i]) <= 1e-12L);
            FUZZ_CHECK(fabsl(sh[i] - ref[i] * 1073741824.0L) <= 32.0L + 1e-6L);
            FUZZ_CHECK(fabsl(shu[i] - ref[i] * 1073741824.0L) <= 32.0L + 1e-6L);
        }
        for (int i = bands * bands; i < 25; ++i)
            FUZZ_CHECK(sh[i] == 11 && shu[i] == 11);
    }
    const int bad = (x >> 8 & 1u) ? 0 : 6 + (int)(x >> 9 & 7u);
    st = qibl_sh_eval(v, bad, sh);
    FUZZ_CHECK(st == QIBL_E_BAD_BANDS || (len == 0 && st == QIBL_E_ZERO_VECTOR));
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_in in = {data, size};
    do {
        const uint32_t a = fuzz_u32(&in), b = fuzz_u32(&in), c = fuzz_u32(&in);
        const uint64_t x = fuzz_u32(&in) | (uint64_t)fuzz_u32(&in) << 32;
        exact(a, b, c, x);
        vectors(a, b, c, x);
    } while (in.n > 0);
    return 0;
}
