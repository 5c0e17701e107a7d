/*
 * fixed.c - integer division, square roots and vector normalisation for qibl's Q formats.
 *
 * Invariants: every routine is exact or correctly rounded as fixed.h states; none calls a runtime
 * library helper (64-bit shifts here are by constants, 64-bit products go through
 * qibl_mul_u32_u64), so the file links freestanding on Cortex-M0.
 */
#include "qibl/fixed.h"

uint64_t qibl_udiv_u64(uint64_t n, uint64_t d, uint64_t *rem)
{
    if (d == 0u)
        return 0u;
#if QIBL_CONFIG_NATIVE_DIV64
    if (rem)
        *rem = n % d;
    return n / d;
#else
    /* Restoring division, one quotient bit per step; n is shifted out from the top so that all
     * 64-bit shifts are by the constant 1. */
    uint64_t q = 0u, r = 0u;
    for (int i = 0; i < 64; ++i) {
        uint64_t carry = r >> 63; /* r < d; if r >= 2^63 then 2r + bit >= 2^64 > d */
        r = (r << 1) | (n >> 63);
        n <<= 1;
        q <<= 1;
        if (carry || r >= d) {
            r -= d; /* modulo 2^64: the true difference is < d, so this is exact */
            q |= 1u;
        }
    }
    if (rem)
        *rem = r;
    return q;
#endif
}

uint32_t qibl_isqrt_u64(uint64_t x, uint64_t *rem)
{
    /* Digit-by-digit (base 4) square root: exact floor, remainder left in x. */
    uint64_t res = 0u, bit = (uint64_t)1 << 62;
    while (bit > x)
        bit >>= 2;
    while (bit != 0u) {
        if (x >= res + bit) {
            x -= res + bit;
            res = (res >> 1) + bit;
        } else {
            res >>= 1;
        }
        bit >>= 2;
    }
    if (rem)
        *rem = x;
    return (uint32_t)res; /* floor(sqrt(x)) < 2^32 */
}

uint32_t qibl_isqrt_u32(uint32_t x)
{
    uint32_t res = 0u, bit = (uint32_t)1 << 30;
    while (bit > x)
        bit >>= 2;
    while (bit != 0u) {
        if (x >= res + bit) {
            x -= res + bit;
            res = (res >> 1) + bit;
        } else {
            res >>= 1;
        }
        bit >>= 2;
    }
    return res;
}

/* round(y) from floor(2y): floor(y + 1/2) = floor((floor(2y) + 1) / 2) for any real y >= 0, and
 * floor(sqrt(floor(M))) = floor(sqrt(M)) for real M >= 0. Together they give correctly rounded
 * roots from one exact integer square root. */
qibl_uq16_t qibl_sqrt_uq16(qibl_uq16_t x)
{
    /* sqrt(x / 2^16) * 2^16 = sqrt(x * 2^16); 2y = sqrt(x * 2^18) < 2^25 */
    return (qibl_isqrt_u64((uint64_t)x << 18, 0) + 1u) >> 1;
}

qibl_status_t qibl_rsqrt_uq16(qibl_uq16_t x, qibl_uq16_t *out)
{
    if (out == 0)
        return QIBL_E_NULL_POINTER;
    if (x == 0u)
        return QIBL_E_DIV_BY_ZERO;
    /* y = 2^16 / sqrt(x / 2^16) = 2^24 / sqrt(x), 2y = sqrt(2^50 / x) <= 2^25 */
    uint32_t two_y = qibl_isqrt_u64(qibl_udiv_u64((uint64_t)1 << 50, x, 0), 0);
    *out = (two_y + 1u) >> 1;
    return QIBL_OK;
}

qibl_status_t qibl_recip_q16(qibl_q16_t x, qibl_q16_t *out)
{
    if (out == 0)
        return QIBL_E_NULL_POINTER;
    if (x == 0)
        return QIBL_E_DIV_BY_ZERO;
    uint32_t m = x < 0 ? 0u - (uint32_t)x : (uint32_t)x;
    /* |y| = 2^32 / m; 2|y| = 2^33 / m, so q = round(|y|) <= 2^32 */
    uint64_t q = (qibl_udiv_u64((uint64_t)1 << 33, m, 0) + 1u) >> 1;
    if (x > 0) {
        if (q > (uint64_t)INT32_MAX)
            return QIBL_E_RANGE;
        *out = (qibl_q16_t)q;
    } else {
        if (q > (uint64_t)1 << 31)
            return QIBL_E_RANGE;
        *out = (qibl_q16_t)(-(int64_t)q);
    }
    return QIBL_OK;
}

qibl_status_t qibl_vec3_normalize_q30(const int32_t v[3], qibl_q30_t out[3])
{
    if (v == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    uint32_t a[3], max = 0u;
    for (int i = 0; i < 3; ++i) {
        a[i] = v[i] < 0 ? 0u - (uint32_t)v[i] : (uint32_t)v[i]; /* <= 2^31 */
        if (a[i] > max)
            max = a[i];
    }
    if (max == 0u)
        return QIBL_E_ZERO_VECTOR;
    /* Scale so the largest magnitude lies in [2^30, 2^31]: then |v| rounded to an integer has a
     * relative error <= 2^-31, whatever the input length (1 LSB up to INT32_MIN). */
    unsigned s = 0u;
    while ((max << s) < 0x40000000u)
        ++s;
    uint64_t sum = 0u;
    for (int i = 0; i < 3; ++i) {
        a[i] <<= s;
        sum += qibl_mul_u32_u64(a[i], a[i]); /* <= 3 * 2^62 < 2^64 */
    }
    uint64_t rem;
    uint64_t r = qibl_isqrt_u64(sum, &rem);
    if (rem > r)
        ++r; /* round(sqrt(sum)): sqrt(sum) >= r + 1/2  <=>  sum - r^2 >= r + 1 */
    /* out = round(a * 2^30 / r) = floor((a * 2^31 + r) / 2r); |error| <= 1/2 (from r) + 1/2 */
    qibl_q30_t res[3];
    for (int i = 0; i < 3; ++i) {
        int32_t c = (int32_t)qibl_udiv_u64(((uint64_t)a[i] << 31) + r, r << 1, 0); /* <= 2^30 */
        res[i] = v[i] < 0 ? -c : c;
    }
    for (int i = 0; i < 3; ++i)
        out[i] = res[i];
    return QIBL_OK;
}
