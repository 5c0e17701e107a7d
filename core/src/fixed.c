/*
 * fixed.c - integer division, square roots and vector normalisation for qibl's Q formats.
 *
 * Invariants: every routine is exact or correctly rounded as fixed.h states; none calls a runtime
 * library helper (64-bit shifts here are by constants, 64-bit products go through
 * qibl_mul_u32_u64), so the file links freestanding on Cortex-M0.
 */
#include "qibl/fixed.h"
#include "qibli.h"

/* the out-of-line copies of qibli.h (calls in size-optimised builds) */
unsigned qibli_bitlen_u64_call(uint64_t x)
{
    return qibli_bitlen_u64_inline(x);
}

int32_t qibli_rshr_s64_call(int64_t x, unsigned n)
{
    return qibl_rshr_s64(x, n);
}

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
    /* the same digits: the 64-bit loop skips the empty top ones (no kernel calls this one) */
    return qibl_isqrt_u64(x, 0);
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
    uint32_t m = qibli_abs_u32(x);
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
        a[i] = qibli_abs_u32(v[i]); /* <= 2^31 */
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

/* Seeds for qibl_rsqrt_u64: round(2^34 / sqrt(i + 0.5) / 2^16) for i = 64..255, i.e. 1/sqrt at the
 * middle of each interval of t >> 24, in units of 2^-30 (relative error <= 2^-9). Also the seed of
 * the point kernel's one-step rsqrt (shmap.c, QIBL_POINT_POLY). */
const uint16_t qibli_rsqrt_seed[192] = {
    32641, 32391, 32146, 31907, 31673, 31445, 31221, 31002, 30787, 30577, 30371, 30169,
    29972, 29778, 29587, 29401, 29217, 29038, 28861, 28688, 28518, 28350, 28186, 28024,
    27866, 27709, 27556, 27405, 27256, 27110, 26966, 26825, 26686, 26548, 26413, 26280,
    26149, 26020, 25893, 25767, 25644, 25522, 25402, 25283, 25167, 25051, 24938, 24826,
    24715, 24606, 24498, 24392, 24287, 24184, 24081, 23980, 23881, 23782, 23685, 23589,
    23494, 23400, 23307, 23216, 23125, 23036, 22947, 22860, 22774, 22688, 22604, 22520,
    22437, 22356, 22275, 22195, 22116, 22037, 21960, 21883, 21808, 21732, 21658, 21585,
    21512, 21440, 21368, 21298, 21228, 21159, 21090, 21022, 20955, 20888, 20822, 20757,
    20692, 20628, 20564, 20501, 20439, 20377, 20316, 20255, 20195, 20135, 20076, 20017,
    19959, 19902, 19845, 19788, 19732, 19676, 19621, 19566, 19512, 19458, 19405, 19352,
    19299, 19247, 19196, 19144, 19093, 19043, 18993, 18943, 18894, 18845, 18797, 18749,
    18701, 18653, 18606, 18560, 18513, 18467, 18422, 18376, 18331, 18287, 18242, 18198,
    18155, 18111, 18068, 18025, 17983, 17941, 17899, 17857, 17816, 17775, 17734, 17694,
    17654, 17614, 17574, 17535, 17496, 17457, 17418, 17380, 17342, 17304, 17267, 17229,
    17192, 17155, 17119, 17082, 17046, 17010, 16974, 16939, 16904, 16869, 16834, 16799,
    16765, 16731, 16697, 16663, 16629, 16596, 16563, 16530, 16497, 16465, 16432, 16400,
};

uint32_t qibl_rsqrt_u64(uint64_t x, unsigned *e)
{
    if (x == 0u) {
        *e = 0u;
        return 0u;
    }
    /* even shift so that m = x * 2^sh lies in [2^62, 2^64): constant shifts only (Cortex-M0) */
    unsigned sh = 0u;
    if (x < ((uint64_t)1 << 32)) { x <<= 32; sh += 32u; }
    if (x < ((uint64_t)1 << 48)) { x <<= 16; sh += 16u; }
    if (x < ((uint64_t)1 << 56)) { x <<= 8; sh += 8u; }
    if (x < ((uint64_t)1 << 60)) { x <<= 4; sh += 4u; }
    if (x < ((uint64_t)1 << 62)) { x <<= 2; sh += 2u; }
    uint32_t t = (uint32_t)(x >> 32); /* [2^30, 2^32); dropping the low word costs <= 2^-31 */
    uint32_t y = (uint32_t)qibli_rsqrt_seed[(t >> 24) - 64u] << 16; /* ~ 2^46 / sqrt(t) */
    for (int it = 0; it < 2; ++it) {
        /* Newton for 1/sqrt: y' = y (3 - t y^2) / 2, with t y^2 = 2^92 at the root */
        uint32_t y2 = (uint32_t)(qibl_mul_u32_u64(y, y) >> 31); /* ~ 2^61 / t, <= 2^31 */
        uint32_t h = (uint32_t)(qibl_mul_u32_u64(t, y2) >> 31);  /* ~ 2^30 */
        uint32_t c = 0xC0000000u - h;                             /* ~ 2^31 (h < 3 * 2^30 always) */
        y = (uint32_t)((qibl_mul_u32_u64(y, c) + (1u << 30)) >> 31);
    }
    *e = 62u - sh / 2u;
    return y;
}

qibl_status_t qibl_vec3_normalize_fast_q30(const int32_t v[3], qibl_q30_t out[3], uint32_t *len_y, unsigned *len_e)
{
    if (v == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    uint64_t d2 = 0u;
    for (int i = 0; i < 3; ++i) {
        uint32_t a = qibli_abs_u32(v[i]);
        d2 += qibl_mul_u32_u64(a, a); /* <= 3 * 2^62 */
    }
    if (d2 == 0u)
        return QIBL_E_ZERO_VECTOR;
    unsigned e;
    uint32_t y = qibl_rsqrt_u64(d2, &e); /* 1/|v| = y / 2^e, e in 31..62 */
    qibl_q30_t r[3];
    qibli_unit_q30(v, y, e, r);
    for (int i = 0; i < 3; ++i)
        out[i] = r[i];
    if (len_y)
        *len_y = y;
    if (len_e)
        *len_e = e;
    return QIBL_OK;
}
