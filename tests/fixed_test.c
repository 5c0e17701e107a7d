/*
 * fixed_test.c - qibl/fixed.h: shifts, saturation, exact products, division, roots, normalise.
 *
 * Exact functions are checked against integer identities (r^2 <= x < (r+1)^2, ...), not against
 * doubles; the 16-bit input ranges are swept exhaustively and the 32/64-bit ones by fixed-seed
 * property tests. Built twice: native paths and the Cortex-M0 paths (QIBL_CONFIG_NATIVE_*=0).
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <math.h>
#include <stdio.h>
#include <cmocka.h>

#include "qibl/fixed.h"
#include "testutil.h"

#define N_PROP 1000000

/* ---- 128-bit helpers for the exactness checks (portable: 32-bit limbs) ----------------------- */
typedef struct { uint64_t hi, lo; } u128;

static u128 mul_u64(uint64_t a, uint64_t b)
{
    uint64_t a0 = (uint32_t)a, a1 = a >> 32, b0 = (uint32_t)b, b1 = b >> 32;
    uint64_t p00 = a0 * b0, p01 = a0 * b1, p10 = a1 * b0, p11 = a1 * b1;
    uint64_t mid = (p00 >> 32) + (uint32_t)p01 + (uint32_t)p10;
    u128 r;
    r.lo = (mid << 32) | (uint32_t)p00;
    r.hi = p11 + (p01 >> 32) + (p10 >> 32) + (mid >> 32);
    return r;
}

static int cmp128(u128 a, u128 b)
{
    if (a.hi != b.hi)
        return a.hi < b.hi ? -1 : 1;
    return a.lo < b.lo ? -1 : a.lo > b.lo;
}

/* ---- shifts and saturation ------------------------------------------------------------------ */

static void test_asr_s32(void **state)
{
    (void)state;
    const int32_t edge[] = {0, 1, -1, 2, -2, 3, -3, INT32_MAX, INT32_MIN, INT32_MIN + 1, 12345, -12345};
    tu_rng r = {1};
    for (unsigned n = 0; n < 32; ++n) {
        for (size_t i = 0; i < sizeof edge / sizeof edge[0]; ++i)
            assert_int_equal(qibl_asr_s32(edge[i], n), tu_floor_div_pow2(edge[i], n));
        for (int k = 0; k < 20000; ++k) {
            int32_t x = tu_s32(&r);
            assert_int_equal(qibl_asr_s32(x, n), tu_floor_div_pow2(x, n));
        }
    }
}

static void test_asr_s64_and_shr_u64(void **state)
{
    (void)state;
    const int64_t edge[] = {0, 1, -1, INT64_MAX, INT64_MIN, INT64_MIN + 1, (int64_t)1 << 40, -((int64_t)1 << 40) - 7};
    tu_rng r = {2};
    for (unsigned n = 0; n < 64; ++n) {
        for (size_t i = 0; i < sizeof edge / sizeof edge[0]; ++i) {
            int64_t want = n == 63 ? (edge[i] < 0 ? -1 : 0) : tu_floor_div_pow2(edge[i], n);
            assert_true(qibl_asr_s64(edge[i], n) == want);
        }
        for (int k = 0; k < 20000; ++k) {
            int64_t x = tu_s64(&r);
            int64_t want = n == 63 ? (x < 0 ? -1 : 0) : tu_floor_div_pow2(x, n);
            assert_true(qibl_asr_s64(x, n) == want);
            uint64_t u = tu_next(&r);
            assert_true(qibl_shr_u64(u, n) == u >> n);
        }
    }
}

static void test_rshr_s64_rounds_half_up_and_saturates(void **state)
{
    (void)state;
    /* exact halves go up: +2.5 -> 3, -2.5 -> -2 */
    assert_int_equal(qibl_rshr_s64(5, 1), 3);
    assert_int_equal(qibl_rshr_s64(-5, 1), -2);
    assert_int_equal(qibl_rshr_s64(-3, 1), -1);
    assert_int_equal(qibl_rshr_s64((int64_t)1 << 62, 1), INT32_MAX);
    assert_int_equal(qibl_rshr_s64(-((int64_t)1 << 62), 1), INT32_MIN);
    tu_rng r = {3};
    for (unsigned n = 1; n <= 62; ++n) {
        for (int k = 0; k < 20000; ++k) {
            int64_t x = qibl_asr_s64(tu_s64(&r), 1); /* |x| <= 2^62 */
            int64_t want = tu_floor_div_pow2(x + ((int64_t)1 << (n - 1)), n);
            int32_t sat = want > INT32_MAX ? INT32_MAX : want < INT32_MIN ? INT32_MIN : (int32_t)want;
            assert_int_equal(qibl_rshr_s64(x, n), sat);
        }
    }
}

static void test_saturating_add_sub(void **state)
{
    (void)state;
    assert_int_equal(qibl_add_sat_s32(INT32_MAX, 1), INT32_MAX);
    assert_int_equal(qibl_add_sat_s32(INT32_MIN, -1), INT32_MIN);
    assert_int_equal(qibl_add_sat_s32(INT32_MAX, INT32_MIN), -1);
    assert_int_equal(qibl_sub_sat_s32(INT32_MIN, 1), INT32_MIN);
    assert_int_equal(qibl_sub_sat_s32(0, INT32_MIN), INT32_MAX);
    assert_int_equal(qibl_sub_sat_s32(-1, INT32_MIN), INT32_MAX);
    tu_rng r = {4};
    for (int k = 0; k < N_PROP; ++k) {
        int32_t a = tu_s32(&r), b = tu_s32(&r);
        int64_t s = (int64_t)a + b, d = (int64_t)a - b;
        assert_int_equal(qibl_add_sat_s32(a, b), s > INT32_MAX ? INT32_MAX : s < INT32_MIN ? INT32_MIN : s);
        assert_int_equal(qibl_sub_sat_s32(a, b), d > INT32_MAX ? INT32_MAX : d < INT32_MIN ? INT32_MIN : d);
    }
}

/* ---- products ------------------------------------------------------------------------------- */

static void test_exact_products(void **state)
{
    (void)state;
    const int32_t edge[] = {0, 1, -1, INT32_MAX, INT32_MIN, 65535, 65536, -65536, 0x7FFF8000};
    for (size_t i = 0; i < sizeof edge / sizeof edge[0]; ++i)
        for (size_t j = 0; j < sizeof edge / sizeof edge[0]; ++j) {
            assert_true(qibl_mul_s32_s64(edge[i], edge[j]) == (int64_t)edge[i] * edge[j]);
            assert_true(qibl_mul_u32_u64((uint32_t)edge[i], (uint32_t)edge[j]) ==
                        (uint64_t)(uint32_t)edge[i] * (uint32_t)edge[j]);
        }
    tu_rng r = {5};
    for (int k = 0; k < N_PROP; ++k) {
        int32_t a = tu_s32(&r), b = tu_s32(&r);
        assert_true(qibl_mul_s32_s64(a, b) == (int64_t)a * b);
        uint32_t ua = tu_u32_any_width(&r), ub = tu_u32(&r);
        assert_true(qibl_mul_u32_u64(ua, ub) == (uint64_t)ua * ub);
    }
}

static void test_mul_q16_q30(void **state)
{
    (void)state;
    assert_int_equal(qibl_mul_q16(QIBL_Q16_ONE, QIBL_Q16_ONE), QIBL_Q16_ONE);
    assert_int_equal(qibl_mul_q16(INT32_MAX, INT32_MAX), INT32_MAX); /* saturates */
    assert_int_equal(qibl_mul_q16(INT32_MIN, INT32_MAX), INT32_MIN);
    assert_int_equal(qibl_mul_q16(1, QIBL_Q16_ONE / 2), 1);  /* 0.5 LSB rounds up */
    assert_int_equal(qibl_mul_q16(-1, QIBL_Q16_ONE / 2), 0); /* -0.5 LSB rounds up */
    assert_int_equal(qibl_mul_q30(QIBL_Q30_ONE, -QIBL_Q30_ONE), -QIBL_Q30_ONE);
    assert_int_equal(qibl_mul_q30(INT32_MIN, INT32_MIN), INT32_MAX); /* 4 saturates to 2 - LSB */
    tu_rng r = {6};
    for (int k = 0; k < N_PROP; ++k) {
        int32_t a = tu_s32(&r), b = (int32_t)qibl_asr_s32(tu_s32(&r), (unsigned)(tu_next(&r) % 32u));
        int64_t p = (int64_t)a * b;
        int64_t w16 = tu_floor_div_pow2(p + (1 << 15), 16), w30 = tu_floor_div_pow2(p + (1 << 29), 30);
        assert_int_equal(qibl_mul_q16(a, b), w16 > INT32_MAX ? INT32_MAX : w16 < INT32_MIN ? INT32_MIN : w16);
        assert_int_equal(qibl_mul_q30(a, b), w30 > INT32_MAX ? INT32_MAX : w30 < INT32_MIN ? INT32_MIN : w30);
    }
}

/* ---- division ------------------------------------------------------------------------------- */

static void test_udiv_u64(void **state)
{
    (void)state;
    uint64_t rem = 99;
    assert_true(qibl_udiv_u64(123, 0, &rem) == 0 && rem == 99); /* d == 0: 0, rem untouched */
    assert_true(qibl_udiv_u64(UINT64_MAX, 1, &rem) == UINT64_MAX && rem == 0);
    assert_true(qibl_udiv_u64(UINT64_MAX, UINT64_MAX, &rem) == 1 && rem == 0);
    assert_true(qibl_udiv_u64(UINT64_MAX - 1, UINT64_MAX, &rem) == 0 && rem == UINT64_MAX - 1);
    assert_true(qibl_udiv_u64(UINT64_MAX, ((uint64_t)1 << 63) + 1, &rem) == 1 && rem == ((uint64_t)1 << 63) - 2);
    tu_rng r = {7};
    for (int k = 0; k < N_PROP / 4; ++k) {
        uint64_t n = tu_next(&r) >> (tu_next(&r) % 64u);
        uint64_t d = tu_next(&r) >> (tu_next(&r) % 64u);
        if (d == 0)
            d = 1;
        assert_true(qibl_udiv_u64(n, d, &rem) == n / d);
        assert_true(rem == n % d);
    }
}

/* ---- square roots --------------------------------------------------------------------------- */

static void check_isqrt64(uint64_t x)
{
    uint64_t rem;
    uint64_t s = qibl_isqrt_u64(x, &rem);
    u128 lo = mul_u64(s, s), hi = mul_u64(s + 1, s + 1);
    u128 xx = {0, x};
    assert_true(cmp128(lo, xx) <= 0 && cmp128(xx, hi) < 0);
    assert_true(rem == x - s * s);
}

static void test_isqrt_exhaustive_16bit_and_property(void **state)
{
    (void)state;
    for (uint32_t x = 0; x <= 0xFFFFu; ++x) {
        uint32_t s = qibl_isqrt_u32(x);
        assert_true(s * s <= x && (s + 1) * (s + 1) > x);
        check_isqrt64(x);
    }
    for (uint32_t s = 0; s <= 0xFFFFu; ++s) { /* every perfect square of a 16-bit root, +-1 */
        uint32_t sq = s * s;
        assert_int_equal(qibl_isqrt_u32(sq), s);
        if (sq > 0)
            assert_int_equal(qibl_isqrt_u32(sq - 1), s - 1);
        check_isqrt64((uint64_t)sq + 1);
    }
    assert_int_equal(qibl_isqrt_u32(UINT32_MAX), 65535);
    check_isqrt64(UINT64_MAX);
    assert_int_equal(qibl_isqrt_u64(UINT64_MAX, 0), UINT32_MAX);
    tu_rng r = {8};
    for (int k = 0; k < N_PROP; ++k) {
        uint32_t x = tu_u32_any_width(&r);
        uint64_t s = qibl_isqrt_u32(x);
        assert_true(s * s <= x && (s + 1) * (s + 1) > x);
        check_isqrt64(tu_next(&r) >> (tu_next(&r) % 64u));
    }
}

/* y = sqrt_uq16(x) is correctly rounded iff (2y-1)^2 <= 4 x 2^16 < (2y+1)^2 (no ties exist) */
static void check_sqrt_uq16(uint32_t x)
{
    uint64_t y = qibl_sqrt_uq16(x);
    uint64_t four_x = (uint64_t)x << 18;
    if (y > 0)
        assert_true((2 * y - 1) * (2 * y - 1) <= four_x);
    assert_true(four_x < (2 * y + 1) * (2 * y + 1));
}

static void test_sqrt_uq16_correctly_rounded(void **state)
{
    (void)state;
    for (uint32_t x = 0; x <= 0xFFFFu; ++x) {
        check_sqrt_uq16(x);             /* every fraction below 1.0 */
        check_sqrt_uq16(x << 16);       /* every integer part */
        check_sqrt_uq16((x << 16) | x); /* both halves busy */
    }
    check_sqrt_uq16(UINT32_MAX);
    assert_int_equal(qibl_sqrt_uq16(QIBL_Q16_ONE), QIBL_Q16_ONE);
    assert_int_equal(qibl_sqrt_uq16(4u << 16), 2u << 16);
    tu_rng r = {9};
    double worst = 0.0;
    for (int k = 0; k < N_PROP; ++k) {
        uint32_t x = tu_u32_any_width(&r);
        check_sqrt_uq16(x);
        double e = fabs(qibl_sqrt_uq16(x) - sqrt((double)x / 65536.0) * 65536.0);
        if (e > worst)
            worst = e;
    }
    assert_true(worst <= 0.5);
    printf("fixed: sqrt_uq16 max |error| = %.4f LSB (bound 0.5) over 2^16 x 3 + 10^6 inputs\n", worst);
}

/* y = rsqrt_uq16(x) correctly rounded iff (2y-1)^2 x <= 2^50 < (2y+1)^2 x */
static void check_rsqrt_uq16(uint32_t x)
{
    uint32_t y = 0xDEADBEEF;
    assert_int_equal(qibl_rsqrt_uq16(x, &y), QIBL_OK);
    u128 lo = mul_u64((2 * (uint64_t)y - 1) * (2 * (uint64_t)y - 1), x);
    u128 hi = mul_u64((2 * (uint64_t)y + 1) * (2 * (uint64_t)y + 1), x);
    u128 t = {0, (uint64_t)1 << 50};
    assert_true(cmp128(lo, t) <= 0 && cmp128(t, hi) < 0);
}

static void test_rsqrt_uq16_correctly_rounded(void **state)
{
    (void)state;
    for (uint32_t x = 1; x <= 0xFFFFu; ++x) {
        check_rsqrt_uq16(x);
        check_rsqrt_uq16(x << 16);
        check_rsqrt_uq16((x << 16) | x);
    }
    uint32_t y = 7;
    assert_int_equal(qibl_rsqrt_uq16(0, &y), QIBL_E_DIV_BY_ZERO);
    assert_int_equal(y, 7); /* untouched */
    assert_int_equal(qibl_rsqrt_uq16(1, 0), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_rsqrt_uq16(1, &y), QIBL_OK);
    assert_int_equal(y, 256u << 16); /* 1/sqrt(2^-16) = 256 exactly */
    assert_int_equal(qibl_rsqrt_uq16(4u << 16, &y), QIBL_OK);
    assert_int_equal(y, QIBL_Q16_ONE / 2);
    check_rsqrt_uq16(UINT32_MAX);
    tu_rng r = {10};
    for (int k = 0; k < N_PROP; ++k) {
        uint32_t x = tu_u32_any_width(&r);
        if (x)
            check_rsqrt_uq16(x);
    }
}

static void check_recip(int32_t x)
{
    int32_t y = 0x5A5A5A5A;
    qibl_status_t st = qibl_recip_q16(x, &y);
    uint64_t m = x < 0 ? (uint64_t)(-(int64_t)x) : (uint64_t)x;
    /* exact quotient 2^32/m; the correctly rounded q satisfies |2^33 - 2 q m| < m */
    uint64_t q = (((uint64_t)1 << 33) / m + 1) >> 1;
    int64_t want = x < 0 ? -(int64_t)q : (int64_t)q;
    if (want > INT32_MAX || want < INT32_MIN) {
        assert_int_equal(st, QIBL_E_RANGE);
        assert_int_equal(y, 0x5A5A5A5A);
        return;
    }
    assert_int_equal(st, QIBL_OK);
    assert_true((int64_t)y == want);
    uint64_t prod = q * m * 2, t = (uint64_t)1 << 33;
    assert_true((prod > t ? prod - t : t - prod) < m);
}

static void test_recip_q16(void **state)
{
    (void)state;
    for (int32_t x = -65536; x <= 65536; ++x)
        if (x)
            check_recip(x);
    int32_t y = 3;
    assert_int_equal(qibl_recip_q16(0, &y), QIBL_E_DIV_BY_ZERO);
    assert_int_equal(y, 3);
    assert_int_equal(qibl_recip_q16(1, &y), QIBL_E_RANGE);
    assert_int_equal(qibl_recip_q16(2, &y), QIBL_E_RANGE);
    assert_int_equal(qibl_recip_q16(-1, &y), QIBL_E_RANGE);
    assert_int_equal(y, 3);
    assert_int_equal(qibl_recip_q16(-2, &y), QIBL_OK);
    assert_int_equal(y, INT32_MIN); /* -32768 exactly */
    assert_int_equal(qibl_recip_q16(QIBL_Q16_ONE, 0), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_recip_q16(QIBL_Q16_ONE * 4, &y), QIBL_OK);
    assert_int_equal(y, QIBL_Q16_ONE / 4);
    check_recip(INT32_MAX);
    check_recip(INT32_MIN);
    tu_rng r = {11};
    for (int k = 0; k < N_PROP; ++k) {
        int32_t x = qibl_asr_s32(tu_s32(&r), (unsigned)(tu_next(&r) % 32u));
        if (x)
            check_recip(x);
    }
}

/* ---- normalisation -------------------------------------------------------------------------- */

static double normalize_err(const int32_t v[3])
{
    qibl_q30_t u[3];
    assert_int_equal(qibl_vec3_normalize_q30(v, u), QIBL_OK);
    double x = v[0], y = v[1], z = v[2];
    double len = sqrt(x * x + y * y + z * z);
    double e = 0.0;
    for (int i = 0; i < 3; ++i) {
        double d = fabs(u[i] - (double)v[i] / len * 1073741824.0);
        if (d > e)
            e = d;
    }
    return e;
}

static void test_normalize(void **state)
{
    (void)state;
    const int32_t hard[][3] = {
        {1, 0, 0}, {0, -1, 0}, {0, 0, 1}, {1, 1, 1}, {-1, 1, -1}, {1, 2, 2}, {3, 4, 0},
        {INT32_MAX, 0, 0}, {INT32_MIN, 0, 0}, {INT32_MIN, INT32_MIN, INT32_MIN},
        {INT32_MAX, INT32_MAX, INT32_MAX}, {INT32_MIN, INT32_MAX, 1}, {INT32_MAX, 1, 1},
        {0x40000000, 1, 0}, {65536, 65536, 0}, {1, 0, INT32_MIN},
    };
    double worst = 0.0;
    for (size_t i = 0; i < sizeof hard / sizeof hard[0]; ++i) {
        double e = normalize_err(hard[i]);
        assert_true(e <= 1.0 + 1e-6);
        if (e > worst)
            worst = e;
    }
    qibl_q30_t u[3];
    const int32_t ax[3] = {0, 0, -77};
    assert_int_equal(qibl_vec3_normalize_q30(ax, u), QIBL_OK);
    assert_true(u[0] == 0 && u[1] == 0 && u[2] == -QIBL_Q30_ONE); /* axes are exact */
    tu_rng r = {12};
    for (int k = 0; k < N_PROP; ++k) {
        unsigned sh = (unsigned)(tu_next(&r) % 32u);
        int32_t v[3] = {qibl_asr_s32(tu_s32(&r), sh), qibl_asr_s32(tu_s32(&r), sh), qibl_asr_s32(tu_s32(&r), sh)};
        if (v[0] == 0 && v[1] == 0 && v[2] == 0)
            continue;
        double e = normalize_err(v);
        assert_true(e <= 1.0 + 1e-6);
        if (e > worst)
            worst = e;
    }
    /* in-place use is allowed */
    int32_t w[3] = {3, 0, -4};
    assert_int_equal(qibl_vec3_normalize_q30(w, w), QIBL_OK);
    assert_int_equal(w[0], 644245094); /* round(0.6 * 2^30) */
    assert_int_equal(w[2], -858993459);
    printf("fixed: vec3_normalize_q30 max |error| = %.4f LSB (bound 1) over 10^6 vectors + hard cases\n", worst);
}

static void test_normalize_errors(void **state)
{
    (void)state;
    const int32_t zero[3] = {0, 0, 0};
    qibl_q30_t u[4];
    tu_fill_guard(u, sizeof u);
    assert_int_equal(qibl_vec3_normalize_q30(zero, u), QIBL_E_ZERO_VECTOR);
    assert_true(tu_guard_intact(u, sizeof u));
    assert_int_equal(qibl_vec3_normalize_q30(0, u), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_vec3_normalize_q30(zero, 0), QIBL_E_NULL_POINTER);
    const int32_t one[3] = {0, 5, 0};
    assert_int_equal(qibl_vec3_normalize_q30(one, u), QIBL_OK);
    assert_true(tu_guard_intact(&u[3], sizeof u[3])); /* writes exactly three values */
}

/* qibl_rsqrt_u64: y / 2^e = 1/sqrt(x) within 2^-28 relative, checked in long double */
static void test_rsqrt_u64(void **state)
{
    (void)state;
    unsigned e = 99;
    assert_int_equal(qibl_rsqrt_u64(0, &e), 0);
    assert_int_equal(e, 0);
    tu_rng r = {13};
    long double worst = 0;
    for (int k = 0; k < N_PROP + 70; ++k) {
        uint64_t x = k < 64 ? (uint64_t)1 << k : k < 70 ? UINT64_MAX - (uint64_t)(k - 64) : tu_next(&r) >> (tu_next(&r) % 64u);
        if (x == 0)
            x = 1;
        uint32_t y = qibl_rsqrt_u64(x, &e);
        assert_true(e >= 31 && e <= 62);
        assert_true(y >= (1u << 30) && y <= (1u << 31));
        long double got = ldexpl((long double)y, -(int)e), want = 1.0L / sqrtl((long double)x);
        long double rel = fabsl(got / want - 1.0L);
        if (rel > worst)
            worst = rel;
        assert_true(rel <= ldexpl(1.0L, -28));
    }
    printf("fixed: rsqrt_u64 max relative error = %.3Le = 2^%.2f (bound 2^-28)\n", worst, (double)log2l(worst));
}

static void test_normalize_fast(void **state)
{
    (void)state;
    tu_rng r = {14};
    double worst = 0.0;
    for (int k = 0; k < N_PROP; ++k) {
        unsigned sh = (unsigned)(tu_next(&r) % 32u);
        int32_t v[3] = {qibl_asr_s32(tu_s32(&r), sh), qibl_asr_s32(tu_s32(&r), sh), qibl_asr_s32(tu_s32(&r), sh)};
        if (k < 8) /* extremes */
            v[0] = k & 1 ? INT32_MIN : 1, v[1] = k & 2 ? INT32_MIN : 0, v[2] = k & 4 ? INT32_MAX : 0;
        if (!v[0] && !v[1] && !v[2])
            continue;
        qibl_q30_t u[3];
        uint32_t ly;
        unsigned le;
        assert_int_equal(qibl_vec3_normalize_fast_q30(v, u, &ly, &le), QIBL_OK);
        double len = sqrt((double)v[0] * v[0] + (double)v[1] * v[1] + (double)v[2] * v[2]);
        for (int i = 0; i < 3; ++i) {
            double e = fabs(u[i] - v[i] / len * 1073741824.0);
            if (e > worst)
                worst = e;
            assert_true(e <= 4.0);
        }
        assert_true(fabs(ldexp((double)ly, -(int)le) * len - 1.0) < 1e-8);
    }
    const int32_t zero[3] = {0, 0, 0};
    qibl_q30_t u[3] = {7, 7, 7};
    assert_int_equal(qibl_vec3_normalize_fast_q30(zero, u, 0, 0), QIBL_E_ZERO_VECTOR);
    assert_true(u[0] == 7 && u[1] == 7 && u[2] == 7);
    assert_int_equal(qibl_vec3_normalize_fast_q30(0, u, 0, 0), QIBL_E_NULL_POINTER);
    printf("fixed: vec3_normalize_fast_q30 max |error| = %.3f LSB (bound 4)\n", worst);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_asr_s32),
        cmocka_unit_test(test_asr_s64_and_shr_u64),
        cmocka_unit_test(test_rshr_s64_rounds_half_up_and_saturates),
        cmocka_unit_test(test_saturating_add_sub),
        cmocka_unit_test(test_exact_products),
        cmocka_unit_test(test_mul_q16_q30),
        cmocka_unit_test(test_udiv_u64),
        cmocka_unit_test(test_isqrt_exhaustive_16bit_and_property),
        cmocka_unit_test(test_sqrt_uq16_correctly_rounded),
        cmocka_unit_test(test_rsqrt_uq16_correctly_rounded),
        cmocka_unit_test(test_recip_q16),
        cmocka_unit_test(test_normalize),
        cmocka_unit_test(test_normalize_errors),
        cmocka_unit_test(test_rsqrt_u64),
        cmocka_unit_test(test_normalize_fast),
    };
    return cmocka_run_group_tests_name(QIBL_CONFIG_NATIVE_MUL64 ? "fixed (native paths)" : "fixed (portable M0 paths)",
                                       tests, NULL, NULL);
}
