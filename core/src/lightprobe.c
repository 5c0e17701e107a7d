/*
 * lightprobe.c - light-probe sampling: SATs of the sin-weighted luminance energy of a lat-long
 * probe, median cut / adaptive median cut / variance minimisation, light directions and colours.
 *
 * Invariants: integer only, no heap, no state; no 64-bit multiply, divide or variable shift that a
 * Cortex-M0 would turn into a library call (products through qibl_mul_u32_u64, divisions through
 * qibl_udiv_u64, variable shifts through qibl_shr_u64 / qibli_shl_u64); the same bits on every port.
 *
 * Number formats and bounds (the arguments lightprobe.h quotes):
 *   - Every pixel is decoded exactly to channel integers m_c >= 0 and an exponent eps with
 *     P_c = m_c 2^eps / D (D = 510 for sRGBE, else 1), and its luminance Y = sum w_c m_c (weights
 *     Q16, so Y 2^(eps-16) / D = L exactly). RGBE and sRGBE: m_c < 2^8, Y < 2^24. LINEAR_I32:
 *     m_c < 2^31. LINEAR_F32: the three channels are aligned to the largest one's exponent with 23
 *     extra bits, m_c < 2^47 (a channel more than 2^-47 below the pixel's largest is truncated).
 *   - Row weight sin theta_v = sig_v 2^-(32 + kap_v), sig_v in [2^31, 2^32), relative error
 *     <= 2^-30 (see sin_frac).
 *   - The first pass finds lb = max over pixels of (bitlen(max_c m_c) + eps) (for RGBE from the
 *     largest exponent byte alone, bitlen <= 8: at most a bit of headroom lost), so every channel
 *     and the luminance satisfy m 2^eps < 2^lb (Y <= 2^16 max m_c since the weights sum to 2^16).
 *     With p = 64 - ceil(log2(W H)) and g = p - lb, the pixel energy
 *         e = floor(Y sig_v 2^(eps - 16 + g - 32 - kap_v))  <  2^(lb + g) = 2^p
 *     (sig_v 2^-(32+kap_v) <= 1), and the channel energies x_c = floor(m_c sig_v 2^(eps+g-32-kap_v))
 *     obey the same bound. So every SAT entry and every region's channel sum is below
 *     W H 2^p <= 2^64: exact in uint64, no overflow for any input at any supported size.
 *     e 2^-g / D = L sin theta up to the floor (< 1 unit) and the sin error.
 *   - VARMIN's moment SATs hold sums of em = e >> k, em u, em u^2, em v, em v^2 with
 *     k = max(0, bitlen(T) + 2 bitlen(max(W, H) - 1) - 64), T the probe's total: then
 *     sum em u^2 <= (T >> k) (W-1)^2 < 2^64, and the same for v. Region moments are taken about the
 *     region's own corner with wrap-around uint64 arithmetic, exact because the true results are
 *     below 2^64, and a region's variance sum em (x - mean)^2 = S2 - S1^2 / S0 is computed exactly
 *     with a 128-bit square and a 128/64 division (the quotient is <= S2 by Cauchy-Schwarz).
 */
#include "qibl/lightprobe.h"
#include "qibli.h"
#include "lightprobe_internal.h"

/* compiler intrinsics header only (freestanding), only on the path config.h chose: the RGBE SAT
 * and colour passes need per-lane 64-bit variable shifts (vpsrlvq), which SSE2 lacks; SSE2 has the
 * prefetch hint */
#if QIBL_USE_LIGHTPROBE && QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
#include <immintrin.h>
#elif QIBL_USE_LIGHTPROBE && QIBL_CONFIG_SIMD == QIBL_SIMD_SSE2
#include <emmintrin.h> /* _mm_prefetch (the colour pass) */
#elif QIBL_USE_LIGHTPROBE && QIBL_CONFIG_SIMD == QIBL_SIMD_NEON
#include <arm_neon.h>
#endif
/* the paths with a vector SAT row and colour sum (RGBE, right-shift case) */
#define LP_VEC (QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2 || QIBL_CONFIG_SIMD == QIBL_SIMD_NEON)

#if QIBL_USE_LIGHTPROBE

/* ---- 64- and 128-bit helpers ----------------------------------------------------------------- */

typedef struct {
    uint64_t hi, lo;
} u128;

/* m 2^16 sig for a byte m (< 2^56): on 64-bit hosts (QIBL_CONFIG_NATIVE_DIV64 marks them; a
 * 64 x 64 product is native wherever a 64-bit division is) one product by the row's 2^16 sig,
 * else one 32 x 32 -> 64 product of m 2^16 (< 2^24) and sig. */
static inline uint64_t mul_m_sig16(uint32_t m, uint32_t sig, uint64_t sig16)
{
#if QIBL_CONFIG_NATIVE_DIV64
    (void)sig;
    return m * sig16;
#else
    (void)sig16;
    return qibl_mul_u32_u64(m << 16, sig);
#endif
}

/* a * b mod 2^64 for a 64-bit a and a 32-bit b (exact when the product fits) */
static inline uint64_t mul_lo_u64_u32(uint64_t a, uint32_t b)
{
    return qibl_mul_u32_u64((uint32_t)a, b) + ((uint64_t)((uint32_t)(a >> 32) * b) << 32);
}

/* The 128-bit helpers take and give values through pointers: a 16-byte struct passed or returned
 * by value becomes a memcpy call on some targets (Cortex-M0 at -Os). */

/* *r = a * b exactly */
static void mul64(uint64_t a, uint64_t b, u128 *r)
{
    uint32_t al = (uint32_t)a, ah = (uint32_t)(a >> 32), bl = (uint32_t)b, bh = (uint32_t)(b >> 32);
    uint64_t ll = qibl_mul_u32_u64(al, bl), lh = qibl_mul_u32_u64(al, bh);
    uint64_t hl = qibl_mul_u32_u64(ah, bl), hh = qibl_mul_u32_u64(ah, bh);
    uint64_t mid = (ll >> 32) + (uint32_t)lh + (uint32_t)hl; /* < 3 * 2^32 */
    r->lo = (mid << 32) | (uint32_t)ll;
    r->hi = hh + (lh >> 32) + (hl >> 32) + (mid >> 32);
}

/* floor(a b / 2^64) */
static uint64_t mulhi64(uint64_t a, uint64_t b)
{
    u128 r;
    mul64(a, b, &r);
    return r.hi;
}

/* *a += b */
static inline void add128(u128 *a, const u128 *b)
{
    uint64_t lo = a->lo + b->lo;
    a->hi += b->hi + (lo < b->lo);
    a->lo = lo;
}

static inline void add128_64(u128 *a, uint64_t b)
{
    a->lo += b;
    a->hi += a->lo < b;
}

static inline int cmp128(const u128 *a, const u128 *b)
{
    if (a->hi != b->hi)
        return a->hi < b->hi ? -1 : 1;
    return a->lo < b->lo ? -1 : a->lo > b->lo;
}

/* the low 64 bits of x >> n, n in 0..127 */
static uint64_t shr128_lo(const u128 *x, unsigned n)
{
    if (n == 0u)
        return x->lo;
    if (n >= 64u)
        return qibl_shr_u64(x->hi, n - 64u);
    return qibl_shr_u64(x->lo, n) | qibli_shl_u64(x->hi, 64u - n);
}

/* *x <<= n, n in 0..63 (the caller knows it fits) */
static void shl128(u128 *x, unsigned n)
{
    if (n == 0u)
        return;
    x->hi = qibli_shl_u64(x->hi, n) | qibl_shr_u64(x->lo, 64u - n);
    x->lo = qibli_shl_u64(x->lo, n);
}

static unsigned bitlen128(const u128 *x)
{
    return x->hi ? 64u + qibli_bitlen_u64(x->hi) : qibli_bitlen_u64(x->lo);
}

/* floor(x 2^s) for a signed shift s, the caller knowing that the result is below 2^64 */
static uint64_t shift128_to64(const u128 *x, int s)
{
    if (s >= 0) /* then x < 2^(64 - s); s >= 64 only for x = 0 */
        return s < 64 ? qibli_shl_u64(x->lo, (unsigned)s) : 0u;
    if (s <= -128)
        return 0u;
    return shr128_lo(x, (unsigned)-s);
}

/* div_digit is inlined at both digits, at -Os too: as a call it would cost div128's callers a frame
 * more on the small cores (the stack bounds in docs/porting.md) */
#if defined(__GNUC__) || defined(__clang__)
#define DIGIT_INLINE __attribute__((always_inline)) inline
#else
#define DIGIT_INLINE inline
#endif

/* One quotient digit of algorithm D below: top / vn1 estimated, then corrected down (at most twice)
 * against the divisor's second digit vn0 and the dividend's next digit un. */
static DIGIT_INLINE uint64_t div_digit(uint64_t top, uint32_t un, uint32_t vn1, uint32_t vn0)
{
    const uint64_t b = (uint64_t)1 << 32;
    uint64_t rhat = 0; /* always written (vn1 != 0); set for GCC, which sees the d == 0 path when
                        * fixed.c is inlined (the amalgamation, LTO) and warns */
    uint64_t q = qibl_udiv_u64(top, vn1, &rhat);
    while (q >= b || qibl_mul_u32_u64((uint32_t)q, vn0) > ((rhat << 32) | un)) {
        --q;
        rhat += vn1;
        if (rhat >= b)
            break;
    }
    return q;
}

/* floor(n / d) for d > 0 and n.hi < d (so the quotient fits 64 bits); *rem gets the remainder.
 * Knuth's algorithm D with two 32-bit digits (Hacker's Delight, divlu): two 64/32 divisions, which
 * are instructions on 64-bit hosts and qibl_udiv_u64's shift-subtract loop elsewhere. */
static uint64_t div128(const u128 *n, uint64_t d, uint64_t *rem)
{
    unsigned s = 64u - qibli_bitlen_u64(d);
    d = qibli_shl_u64(d, s);
    uint64_t un32 = s ? qibli_shl_u64(n->hi, s) | qibl_shr_u64(n->lo, 64u - s) : n->hi;
    uint64_t un10 = qibli_shl_u64(n->lo, s);
    uint32_t vn1 = (uint32_t)(d >> 32), vn0 = (uint32_t)d;
    uint32_t un1 = (uint32_t)(un10 >> 32), un0 = (uint32_t)un10;
    uint64_t q1 = div_digit(un32, un1, vn1, vn0);
    /* q1 < 2^32 now; the true value of un21 is below d, so arithmetic mod 2^64 gives it exactly */
    uint64_t un21 = (un32 << 32) + un1 - mul_lo_u64_u32(d, (uint32_t)q1);
    uint64_t q0 = div_digit(un21, un0, vn1, vn0);
    if (rem)
        *rem = qibl_shr_u64((un21 << 32) + un0 - mul_lo_u64_u32(d, (uint32_t)q0), s);
    return (q1 << 32) | q0;
}

/* ---- sin and cos from exact rational angles --------------------------------------------------- */

#define PI_Q62 14488038916154245685u          /* round(pi 2^62) */
#define TWO_PI_SQ_Q58 5689439577989151081u    /* round(2 pi^2 2^58) */

/* 1/3!, 1/5!, ..., 1/15! and 1/2!, 1/4!, ..., 1/16! in Q64, rounded */
static const uint64_t sin_c[7] = {3074457345618258603u, 153722867280912930u, 3660068268593165u,
                                  50834281508238u, 462129831893u, 2962370717u, 14106527u};
static const uint64_t cos_c[8] = {9223372036854775808u, 768614336404564651u, 25620477880152155u,
                                  457508533574146u, 5083428150824u, 38510819324u, 211597908u, 881658u};

/* 1 - c0 z + c1 z^2 - ... in Q63 for z = beta^2 in [0, 0.62) (Q64): the Taylor series of
 * sin(beta) / beta or cos(beta) to beta^15 / beta^16, truncation < 2^-49 at beta = pi/4. Horner
 * from the smallest coefficient, every partial sum positive (c_k > 0.62 c_(k+1)); each step floors
 * once, <= 1 LSB (2^-64), so the result is within 2^-60. */
static uint64_t poly_q63(uint64_t z, const uint64_t *c, int n)
{
    uint64_t t = c[n - 1];
    for (int k = n - 2; k >= 0; --k)
        t = c[k] - mulhi64(z, t);
    return ((uint64_t)1 << 63) - ((mulhi64(z, t) + 1u) >> 1);
}

/* floor(pi n / d 2^64) for 0 <= n / d <= 1/4 (d > 0, n, d < 2^40): the angle in Q64. */
static uint64_t beta_q64(uint64_t n, uint64_t d)
{
    u128 num;
    mul64(PI_Q62, n, &num);
    shl128(&num, 2); /* pi n 2^64: hi < 4n <= d, so the quotient fits */
    return div128(&num, d, 0);
}

/* sin(pi n / d) for 0 < n < d < 2^32, as *mant in [2^31, 2^32) times 2^-(32 + *kap). Reduces to an
 * angle beta in [0, pi/4] by symmetry (exactly, in the rational n / d), then sin = beta P(beta^2)
 * or cos(beta) = Q(beta^2): beta is good to 2^-64 absolute (>= 2^-16 relative precision is what
 * matters: beta >= pi / 2^32), P and Q to 2^-60, the product rounded once to 32 bits. Relative
 * error <= 2^-32 (rounding) + 2^-45 (the rest) <= 2^-31. */
static void sin_frac(uint64_t n, uint64_t d, uint32_t *mant, int32_t *kap)
{
    u128 v;     /* sin = v / 2^vexp */
    unsigned vexp;
    if (2u * n > d)
        n = d - n; /* sin(pi x) = sin(pi (1 - x)); now n / d <= 1/2 */
    if (4u * n <= d) {
        uint64_t b = beta_q64(n, d);
        mul64(b, poly_q63(mulhi64(b, b), sin_c, 7), &v);
        vexp = 127u;
    } else {
        /* sin(pi x) = cos(pi (1/2 - x)), 1/2 - x = (d - 2n) / 2d in [0, 1/4) */
        uint64_t b = beta_q64(d - 2u * n, 2u * d);
        v.hi = 0u;
        v.lo = poly_q63(mulhi64(b, b), cos_c, 8);
        vexp = 63u;
    }
    unsigned L = bitlen128(&v); /* >= 33: v >= 2^-16 2^vexp */
    /* top 32 bits, round half up; a carry to 2^32 renormalises */
    uint64_t m = (shr128_lo(&v, L - 33u) + 1u) >> 1;
    if (m >> 32) {
        m >>= 1;
        ++L;
    }
    *mant = (uint32_t)m;
    *kap = (int32_t)vexp - (int32_t)L;
}

/* sin and cos of pi f / 2^31 (f = angle / pi in Q31, the full circle [0, 2) in a uint32) in Q2.30,
 * each within 1 LSB (the polynomials are exact to 2^-60; one rounding to Q30). */
static void sincos_q30(uint32_t f, int32_t *s, int32_t *c)
{
    uint32_t q = f >> 30, r = f & 0x3FFFFFFFu; /* quadrant, angle in it: pi r / 2^31 < pi / 2 */
    int swap = r > 0x20000000u;
    if (swap)
        r = 0x40000000u - r; /* sin(pi/2 - a) = cos(a) */
    uint64_t b = beta_q64(r, (uint64_t)1 << 31);
    uint64_t z = mulhi64(b, b);
    u128 sv;
    mul64(b, poly_q63(z, sin_c, 7), &sv);                                 /* Q127 */
    int32_t s0 = (int32_t)((shr128_lo(&sv, 96u) + 1u) >> 1);              /* Q30, < 2^30 */
    int32_t c0 = (int32_t)(((poly_q63(z, cos_c, 8) >> 32) + 1u) >> 1);    /* Q30, <= 2^30 */
    if (swap) {
        int32_t t = s0;
        s0 = c0;
        c0 = t;
    }
    switch (q) {
    case 0: *s = s0; *c = c0; break;
    case 1: *s = c0; *c = -s0; break;
    case 2: *s = -s0; *c = -c0; break;
    default: *s = -c0; *c = s0; break;
    }
}

qibl_status_t qibl_lightprobe_row_weight(uint32_t h, uint32_t v, uint32_t *mant, int32_t *kap)
{
    if (mant == 0 || kap == 0)
        return QIBL_E_NULL_POINTER;
    if (h == 0u || h > QIBL_LIGHTPROBE_MAX_DIM || v >= h)
        return QIBL_E_PROBE_SIZE;
    sin_frac(2u * (uint64_t)v + 1u, 2u * (uint64_t)h, mant, kap);
    return QIBL_OK;
}

/* ---- pixel decoding --------------------------------------------------------------------------- */

#define LUMA_R QIBL_LIGHTPROBE_LUMA_R
#define LUMA_G QIBL_LIGHTPROBE_LUMA_G
#define LUMA_B QIBL_LIGHTPROBE_LUMA_B

/* A decoded pixel: P_c = m[c] 2^eps / D. */
typedef struct {
    uint64_t m[3];
    int32_t eps;
} pixel;

static size_t pixel_bytes(qibl_lightprobe_format_t f)
{
    return f == QIBL_LIGHTPROBE_RGBE || f == QIBL_LIGHTPROBE_SRGBE ? 4u : 12u;
}

/* sRGBE channel byte -> 2X - 255, with 127 and 128 read as 0 and X < 127 flagged negative */
static inline uint32_t srgbe_m(uint32_t x, unsigned *bad)
{
    if (x < 127u)
        *bad |= QIBLI_PROBE_BAD_NEGATIVE;
    return x > 128u ? 2u * x - 255u : 0u;
}

/* Decodes the generic formats (sRGBE, LINEAR_I32, LINEAR_F32; RGBE has its own loops); returns
 * the QIBLI_PROBE_BAD_ flags. p is aligned for the 32-bit formats (checked by build). */
static unsigned decode(qibl_lightprobe_format_t f, const uint8_t *p, int32_t frac_bits, pixel *o)
{
    unsigned bad = 0u;
    if (f == QIBL_LIGHTPROBE_RGBE) {
        o->m[0] = p[3] ? p[0] : 0u;
        o->m[1] = p[3] ? p[1] : 0u;
        o->m[2] = p[3] ? p[2] : 0u;
        o->eps = (int32_t)p[3] - 136;
    } else if (f == QIBL_LIGHTPROBE_SRGBE) {
        for (int c = 0; c < 3; ++c)
            o->m[c] = srgbe_m(p[c], &bad);
        o->eps = (int32_t)p[3] - 126;
    } else if (f == QIBL_LIGHTPROBE_LINEAR_I32) {
        const int32_t *q = (const int32_t *)(const void *)p;
        for (int c = 0; c < 3; ++c) {
            if (q[c] < 0)
                bad |= QIBLI_PROBE_BAD_NEGATIVE;
            o->m[c] = q[c] < 0 ? 0u : (uint32_t)q[c];
        }
        o->eps = -frac_bits;
    } else {
        const uint32_t *q = (const uint32_t *)(const void *)p;
        uint32_t mant[3];
        int32_t ex[3], emax = -1000;
        for (int c = 0; c < 3; ++c) {
            uint32_t b = q[c], e8 = (b >> 23) & 0xFFu, fr = b & 0x7FFFFFu;
            mant[c] = 0u;
            ex[c] = -149;
            if (e8 == 0xFFu) {
                bad |= QIBLI_PROBE_BAD_NOT_FINITE;
            } else if ((b & 0x7FFFFFFFu) != 0u) {
                if (b >> 31) {
                    bad |= QIBLI_PROBE_BAD_NEGATIVE;
                } else {
                    mant[c] = e8 ? fr | 0x800000u : fr;
                    ex[c] = e8 ? (int32_t)e8 - 150 : -149;
                    if (ex[c] > emax)
                        emax = ex[c];
                }
            }
        }
        for (int c = 0; c < 3; ++c) {
            unsigned d = (unsigned)(emax - ex[c]);
            o->m[c] = mant[c] && d < 48u ? qibl_shr_u64((uint64_t)mant[c] << 23, d) : 0u;
        }
        o->eps = emax - 23;
    }
    return bad;
}

static inline uint64_t max3(const uint64_t m[3])
{
    uint64_t a = m[0] > m[1] ? m[0] : m[1];
    return a > m[2] ? a : m[2];
}

/* luminance Y = sum w_c m_c, exact: <= 2^16 max m_c < 2^63 */
static inline uint64_t luma(const uint64_t m[3])
{
    return mul_lo_u64_u32(m[0], LUMA_R) + mul_lo_u64_u32(m[1], LUMA_G) + mul_lo_u64_u32(m[2], LUMA_B);
}

/* ---- shared with the SH projection (lightprobe_internal.h) ------------------------------ */

size_t qibli_lightprobe_pixel_bytes(qibl_lightprobe_format_t f)
{
    return pixel_bytes(f);
}

unsigned qibli_lightprobe_decode(qibl_lightprobe_format_t f, const uint8_t *p, int32_t frac_bits, uint64_t m[3],
                                 int32_t *eps)
{
    pixel px;
    unsigned bad = decode(f, p, frac_bits, &px);
    m[0] = px.m[0], m[1] = px.m[1], m[2] = px.m[2];
    *eps = px.eps;
    return bad; /* decode speaks the QIBLI_PROBE_BAD_ flags itself */
}

void qibli_lightprobe_sin_frac(uint64_t n, uint64_t d, uint32_t *mant, int32_t *kap)
{
    sin_frac(n, d, mant, kap);
}

/* ---- build ------------------------------------------------------------------------------------ */

static int size_ok(uint32_t w, uint32_t h)
{
    return w >= 1u && h >= 1u && w <= QIBL_LIGHTPROBE_MAX_DIM && h <= QIBL_LIGHTPROBE_MAX_DIM;
}

/* bytes of workspace as a uint64 (0 when the dimensions are outside the limits) */
static uint64_t ws_bytes(uint32_t w, uint32_t h, qibl_lightprobe_method_t method)
{
    if (!size_ok(w, h) || qibl_mul_u32_u64(w, h) > QIBL_LIGHTPROBE_MAX_PIXELS ||
        (unsigned)method >= QIBL_LIGHTPROBE_METHOD_COUNT)
        return 0u;
    uint64_t cells = qibl_mul_u32_u64(w + 1u, h + 1u); /* < 2^27 */
    uint32_t per_cell = method == QIBL_LIGHTPROBE_VARMIN ? 48u : 8u; /* SAT (+ 5 moments) */
    return mul_lo_u64_u32(cells, per_cell) + (((uint64_t)h + 1u) << 4) + 8u;
}

size_t qibl_lightprobe_workspace_size(uint32_t width, uint32_t height, qibl_lightprobe_method_t method)
{
    uint64_t n = ws_bytes(width, height, method);
    return n > (uint64_t)SIZE_MAX ? 0u : (size_t)n;
}

/* uint64 entries of the marginal path's scratch: one column (W + 1) and one row (H + 1) array of
 * energies, four of each with VARMIN's moments (see marg_arrays) */
static uint64_t marg_entries(uint32_t w, uint32_t h, qibl_lightprobe_method_t method)
{
    const uint64_t n = (uint64_t)w + h + 2u;
    return method == QIBL_LIGHTPROBE_VARMIN ? n << 2 : n;
}

/* the low-memory path's bytes: the marginals, the row tables, 8 for alignment (0: bad arguments) */
static uint64_t ws_min_bytes(uint32_t w, uint32_t h, qibl_lightprobe_method_t method)
{
    if (!size_ok(w, h) || qibl_mul_u32_u64(w, h) > QIBL_LIGHTPROBE_MAX_PIXELS ||
        (unsigned)method >= QIBL_LIGHTPROBE_METHOD_COUNT)
        return 0u;
    return (marg_entries(w, h, method) << 3) + (((uint64_t)h + 1u) << 4) + 8u;
}

size_t qibl_lightprobe_workspace_min(uint32_t width, uint32_t height, qibl_lightprobe_method_t method)
{
    uint64_t n = ws_min_bytes(width, height, method);
    return n > (uint64_t)SIZE_MAX ? 0u : (size_t)n;
}

/* First pass: the QIBLI_PROBE_BAD_ flags over the whole probe (so the status does not depend on pixel order)
 * and lb, the bound of lightprobe.c's header (INT32_MIN when every pixel is black). */
static unsigned scan(const qibl_lightprobe_image_t *img, size_t stride, int32_t *lb_out)
{
    const uint8_t *base = (const uint8_t *)img->pixels;
    unsigned bad = 0u;
    int32_t lb = INT32_MIN;
    if (img->format == QIBL_LIGHTPROBE_RGBE) {
        /* tightly packed rows are one run; branch-free so that compilers vectorise it */
        const int tight = stride == 4u * (size_t)img->width;
        const uint32_t runs = tight ? 1u : img->height;
        const size_t run = tight ? (size_t)img->width * img->height : img->width;
        uint32_t emax = 0u;
        for (uint32_t v = 0; v < runs; ++v) {
            const uint8_t *q = base + (size_t)v * stride;
            uint8_t m = 0u;
            for (size_t i = 0; i < run; ++i) {
                uint8_t lit = (uint8_t)(q[4 * i] | q[4 * i + 1] | q[4 * i + 2]) != 0u ? 0xFFu : 0u;
                uint8_t e = (uint8_t)(q[4 * i + 3] & lit);
                m = e > m ? e : m;
            }
            emax = m > emax ? m : emax;
        }
        if (emax)
            lb = (int32_t)emax - 136 + 8; /* mantissas are bytes: bitlen <= 8 */
    } else {
        size_t pb = pixel_bytes(img->format);
        for (uint32_t v = 0; v < img->height; ++v) {
            const uint8_t *q = base + (size_t)v * stride;
            for (uint32_t u = 0; u < img->width; ++u, q += pb) {
                pixel px;
                bad |= decode(img->format, q, img->frac_bits, &px);
                uint64_t mx = max3(px.m);
                if (mx) {
                    int32_t l = (int32_t)qibli_bitlen_u64(mx) + px.eps;
                    if (l > lb)
                        lb = l;
                }
            }
        }
    }
    *lb_out = lb;
    return bad;
}

/* 2^p bound of the per-pixel energy: p = 64 - ceil(log2(W H)) */
static int32_t pixel_bits(uint32_t w, uint32_t h)
{
    uint64_t n = qibl_mul_u32_u64(w, h);
    return 64 - (int32_t)qibli_bitlen_u64(n - 1u);
}

/* Row shift: e = floor(Y sig_v 2^(eps + rshift(v))) */
static inline int32_t rshift(const qibl_lightprobe_t *lp, uint32_t v)
{
    return lp->gshift - 48 - lp->row_kap[v];
}

/* RGBE right shifts by exponent byte for a row whose energies are y >> (r0 - E): 63 where that
 * is beyond 63 and for E = 0 (black in Radiance's convention), exact because every y = Y sig or
 * m 2^16 sig is below 2^56. The table depends on the row only through r0, which changes with
 * kap_v, so a handful of times per probe. */
static void rgbe_shifts(uint32_t r0, uint8_t sh[256])
{
    sh[0] = 63u;
    for (uint32_t e = 1u; e < 256u; ++e)
        sh[e] = (uint8_t)(r0 - e > 63u ? 63u : r0 - e);
}

/* The per-pixel energies e of n pixels of row v from column u0 into out[], the very integers the
 * SAT rows add up (sat_rgbe, sat_generic): the low-memory path reads the probe through this. */
static void row_energy(const qibl_lightprobe_t *lp, uint32_t v, uint32_t u0, uint32_t n, uint64_t *out)
{
    const size_t pb = pixel_bytes(lp->format);
    const uint8_t *q = lp->pixels + (size_t)v * lp->stride + (size_t)u0 * pb;
    const uint32_t sig = lp->row_sig[v];
    if (lp->format == QIBL_LIGHTPROBE_RGBE) {
        const int32_t s0 = rshift(lp, v) - 136; /* shift = E + s0 */
        if (s0 + lp->emax <= 0) {
            /* every shift to the right, by r0 - E (rgbe_shifts' table as arithmetic: no 256-byte
             * table on the stack; y < 2^56, so shifts of 56..63 give 0 as the table's 63 does) */
            const uint32_t r0 = (uint32_t)-s0;
            for (uint32_t i = 0; i < n; ++i, q += 4) {
                const uint32_t k = r0 - q[3];
                const uint64_t y = qibl_mul_u32_u64(LUMA_R * q[0] + LUMA_G * q[1] + LUMA_B * q[2], sig);
                out[i] = q[3] != 0u && k < 64u ? qibl_shr_u64(y, k) : 0u;
            }
        } else {
            for (uint32_t i = 0; i < n; ++i, q += 4) {
                int32_t s = (int32_t)q[3] + s0;
                uint64_t y = qibl_mul_u32_u64(LUMA_R * q[0] + LUMA_G * q[1] + LUMA_B * q[2], sig);
                uint64_t e = s >= 64 ? 0u : s >= 0 ? qibli_shl_u64(y, (unsigned)s) : s > -64 ? qibl_shr_u64(y, (unsigned)-s) : 0u;
                out[i] = q[3] ? e : 0u;
            }
        }
        return;
    }
    const int32_t s0 = rshift(lp, v);
    for (uint32_t i = 0; i < n; ++i, q += pb) {
        pixel px;
        (void)decode(lp->format, q, lp->frac_bits, &px);
        u128 y;
        mul64(luma(px.m), sig, &y);
        out[i] = shift128_to64(&y, px.eps + s0);
    }
}

/* pixels per row_energy call: the stack buffer of the low-memory path's loops */
#define ROW_CHUNK 16u

/* Energy of [u0, u1) x [v0, v1) from the pixels (the low-memory path's region sum) */
static uint64_t pixel_sum(const qibl_lightprobe_t *lp, uint32_t u0, uint32_t v0, uint32_t u1, uint32_t v1)
{
    uint64_t buf[ROW_CHUNK], s = 0u;
    for (uint32_t v = v0; v < v1; ++v)
        for (uint32_t u = u0; u < u1;) {
            uint32_t n = u1 - u < ROW_CHUNK ? u1 - u : ROW_CHUNK;
            row_energy(lp, v, u, n, buf);
            for (uint32_t i = 0; i < n; ++i)
                s += buf[i];
            u += n;
        }
    return s;
}

#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
/* Four RGBE pixels (16 bytes) as 64-bit lanes: the 32-bit word R | G << 8 | B << 16 | E << 24 */
static inline __m256i rgbe4_load(const uint8_t *q)
{
    return _mm256_cvtepu32_epi64(_mm_loadu_si128((const __m128i *)(const void *)q));
}

/* x >> (r0 - E) per lane, 0 where E = 0: the sh[] table of rgbe_shifts as arithmetic (vpsrlvq
 * gives 0 for counts >= 64, and every x here is below 2^56, so counts 56..63 give 0 as well) */
static inline __m256i rgbe4_shift(__m256i x, __m256i w, __m256i vr0)
{
    const __m256i e = _mm256_srli_epi64(w, 24);
    const __m256i black = _mm256_cmpeq_epi64(e, _mm256_setzero_si256());
    return _mm256_andnot_si256(black, _mm256_srlv_epi64(x, _mm256_sub_epi64(vr0, e)));
}

/* One SAT row, right-shift case (r0 = -s0 >= every exponent byte): the energies of four pixels
 * at a time, their prefix sum across the lanes, plus the running sum and the row above. Every
 * sum is mod 2^64 and exact (the totals are below 2^64), so the bits are the scalar loop's.
 * Returns the pixels done (a multiple of 4); the scalar loop finishes the row from acc. */
static uint32_t sat_row_avx2(const uint8_t *q, const uint64_t *above, uint64_t *row, uint32_t w, uint32_t sig,
                             uint32_t r0, uint64_t *acc_io)
{
    const __m256i vsig = _mm256_set1_epi64x((long long)sig), vr0 = _mm256_set1_epi64x((long long)r0);
    const __m256i lr = _mm256_set1_epi64x(LUMA_R), lg = _mm256_set1_epi64x(LUMA_G), lb = _mm256_set1_epi64x(LUMA_B);
    const __m256i ff = _mm256_set1_epi64x(0xFF);
    __m256i carry = _mm256_set1_epi64x((long long)*acc_io);
    uint32_t u = 0u;
    for (; u + 4u <= w; u += 4u, q += 16) {
        const __m256i px = rgbe4_load(q);
        const __m256i r = _mm256_and_si256(px, ff), g = _mm256_and_si256(_mm256_srli_epi64(px, 8), ff),
                      b = _mm256_and_si256(_mm256_srli_epi64(px, 16), ff);
        const __m256i luma = _mm256_add_epi64(_mm256_add_epi64(_mm256_mul_epu32(r, lr), _mm256_mul_epu32(g, lg)),
                                              _mm256_mul_epu32(b, lb)); /* < 2^24 */
        const __m256i e = rgbe4_shift(_mm256_mul_epu32(luma, vsig), px, vr0);
        /* prefix sum over the four lanes: + [0 a b c], then + [0 0 s0 s1] */
        __m256i s = _mm256_add_epi64(e, _mm256_blend_epi32(_mm256_permute4x64_epi64(e, 0x90), _mm256_setzero_si256(), 0x03));
        s = _mm256_add_epi64(s, _mm256_permute2x128_si256(s, s, 0x08));
        s = _mm256_add_epi64(s, carry);
        carry = _mm256_permute4x64_epi64(s, 0xFF);
        const __m256i a = _mm256_loadu_si256((const __m256i *)(const void *)(above + u + 1u));
        _mm256_storeu_si256((__m256i *)(void *)(row + u + 1u), _mm256_add_epi64(a, s));
    }
    *acc_io = (uint64_t)_mm256_extract_epi64(carry, 0);
    return u;
}
#elif QIBL_CONFIG_SIMD == QIBL_SIMD_NEON
/* NEON twin of sat_row_avx2, two pixels per step: vmull_n_u32 for luma sig, vshlq_u64 by a
 * negative count for the per-lane right shift (the count is the lane's low byte, so it is capped
 * at 64 first: any cap >= 56 gives the table's result, every x being below 2^56). */
/* all-ones 64-bit lanes where the exponent byte is 0 (black in Radiance's convention) */
static inline uint64x2_t rgbe2_black(uint32x2_t e)
{
    return vreinterpretq_u64_s64(vmovl_s32(vreinterpret_s32_u32(vceq_u32(e, vdup_n_u32(0u)))));
}

/* x >> min(r0 - E, 64) per lane (r0 >= every E here), 0 where E = 0 */
static inline uint64x2_t rgbe2_shift(uint64x2_t x, uint32x2_t e, uint32_t r0)
{
    const uint32x2_t k = vmin_u32(vsub_u32(vdup_n_u32(r0), e), vdup_n_u32(64u));
    const int64x2_t cnt = vsubq_s64(vdupq_n_s64(0), vreinterpretq_s64_u64(vmovl_u32(k)));
    return vbicq_u64(vshlq_u64(x, cnt), rgbe2_black(e));
}

static uint32_t sat_row_neon(const uint8_t *q, const uint64_t *above, uint64_t *row, uint32_t w, uint32_t sig,
                             uint32_t r0, uint64_t *acc_io)
{
    const uint32x2_t ff = vdup_n_u32(0xFFu);
    uint64x2_t carry = vdupq_n_u64(*acc_io);
    const uint64x2_t zero = vdupq_n_u64(0u);
    uint32_t u = 0u;
    for (; u + 2u <= w; u += 2u, q += 8) {
        /* the words R | G << 8 | B << 16 | E << 24 (the NEON targets qibl builds are little-endian) */
        const uint32x2_t px = vreinterpret_u32_u8(vld1_u8(q));
        const uint32x2_t r = vand_u32(px, ff), g = vand_u32(vshr_n_u32(px, 8), ff), b = vand_u32(vshr_n_u32(px, 16), ff);
        const uint32x2_t luma = vmla_n_u32(vmla_n_u32(vmul_n_u32(r, LUMA_R), g, LUMA_G), b, LUMA_B); /* < 2^24 */
        const uint64x2_t e = rgbe2_shift(vmull_n_u32(luma, sig), vshr_n_u32(px, 24), r0);
        uint64x2_t s = vaddq_u64(e, vextq_u64(zero, e, 1)); /* [a, a + b] */
        s = vaddq_u64(s, carry);
        carry = vdupq_n_u64(vgetq_lane_u64(s, 1));
        vst1q_u64(row + u + 1u, vaddq_u64(vld1q_u64(above + u + 1u), s));
    }
    *acc_io = vgetq_lane_u64(carry, 0);
    return u;
}
#endif

/* The SAT rows of an RGBE probe: the hot loop of the whole module. */
static void sat_rgbe(qibl_lightprobe_t *lp)
{
    const uint32_t w = lp->width, w1 = w + 1u;
    uint8_t sh[256];
    uint32_t sh_r0 = 0u; /* the r0 sh[] was made for (0: none yet) */
    for (uint32_t v = 0; v < lp->height; ++v) {
        const uint8_t *q = lp->pixels + (size_t)v * lp->stride;
        const uint64_t *above = lp->sat + (size_t)v * w1;
        uint64_t *row = lp->sat + (size_t)(v + 1u) * w1;
        const uint32_t sig = lp->row_sig[v];
        const int32_t s0 = rshift(lp, v) - 136; /* shift = E + s0 */
        uint64_t acc = 0u;
        row[0] = 0u;
        if (s0 + lp->emax <= 0) {
            /* every shift is to the right: the case for every probe above 512 pixels */
            if ((uint32_t)-s0 != sh_r0)
                rgbe_shifts(sh_r0 = (uint32_t)-s0, sh);
            uint32_t u = 0u;
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
            u = sat_row_avx2(q, above, row, w, sig, (uint32_t)-s0, &acc);
#elif QIBL_CONFIG_SIMD == QIBL_SIMD_NEON
            u = sat_row_neon(q, above, row, w, sig, (uint32_t)-s0, &acc);
#endif
            q += 4u * (size_t)u;
            for (; u < w; ++u, q += 4) {
                acc += qibl_shr_u64(qibl_mul_u32_u64(LUMA_R * q[0] + LUMA_G * q[1] + LUMA_B * q[2], sig), sh[q[3]]);
                row[u + 1u] = above[u + 1u] + acc;
            }
        } else {
            for (uint32_t u = 0; u < w; ++u, q += 4) {
                int32_t s = (int32_t)q[3] + s0;
                uint64_t y = qibl_mul_u32_u64(LUMA_R * q[0] + LUMA_G * q[1] + LUMA_B * q[2], sig);
                /* s >= 64 only where y = 0: a black pixel with a large exponent */
                uint64_t e = s >= 64 ? 0u : s >= 0 ? qibli_shl_u64(y, (unsigned)s) : s > -64 ? qibl_shr_u64(y, (unsigned)-s) : 0u;
                acc += q[3] ? e : 0u;
                row[u + 1u] = above[u + 1u] + acc;
            }
        }
    }
}

static void sat_generic(qibl_lightprobe_t *lp)
{
    const uint32_t w = lp->width, w1 = w + 1u;
    const size_t pb = pixel_bytes(lp->format);
    for (uint32_t v = 0; v < lp->height; ++v) {
        const uint8_t *q = lp->pixels + (size_t)v * lp->stride;
        const uint64_t *above = lp->sat + (size_t)v * w1;
        uint64_t *row = lp->sat + (size_t)(v + 1u) * w1;
        const uint32_t sig = lp->row_sig[v];
        const int32_t s0 = rshift(lp, v);
        uint64_t acc = 0u;
        row[0] = 0u;
        for (uint32_t u = 0; u < w; ++u, q += pb) {
            pixel px;
            (void)decode(lp->format, q, lp->frac_bits, &px);
            u128 y;
            mul64(luma(px.m), sig, &y);
            acc += shift128_to64(&y, px.eps + s0);
            row[u + 1u] = above[u + 1u] + acc;
        }
    }
}

/* VARMIN's moment SATs, from the per-pixel energies recovered from the SAT (exact differences). */
/* k of lightprobe.c's header: em = e >> k keeps every moment sum below 2^64 */
static uint32_t moment_shift(uint64_t total, uint32_t w, uint32_t h)
{
    uint32_t m = (w > h ? w : h) - 1u;
    int32_t k = (int32_t)qibli_bitlen_u64(total) + 2 * (int32_t)qibli_bitlen_u64(m) - 64;
    return k > 0 ? (uint32_t)k : 0u;
}

static void sat_moments(qibl_lightprobe_t *lp)
{
    const uint32_t w = lp->width, w1 = w + 1u, h = lp->height;
    lp->mshift = moment_shift(lp->total, w, h);
    uint64_t *mom = lp->mom;
    for (uint32_t u = 0; u <= w; ++u)
        for (int j = 0; j < 5; ++j)
            mom[5u * u + (unsigned)j] = 0u;
    for (uint32_t v = 0; v < h; ++v) {
        const uint64_t *s0 = lp->sat + (size_t)v * w1, *s1 = s0 + w1;
        const uint64_t *above = mom + (size_t)v * w1 * 5u;
        uint64_t *row = mom + (size_t)(v + 1u) * w1 * 5u;
        uint64_t a0 = 0u, a1 = 0u, a2 = 0u, a3 = 0u, a4 = 0u;
        const uint32_t v2 = v * v; /* < 2^30 */
        for (int j = 0; j < 5; ++j)
            row[j] = 0u;
        for (uint32_t u = 0; u < w; ++u) {
            uint64_t e = qibl_shr_u64(s1[u + 1u] - s1[u] - s0[u + 1u] + s0[u], lp->mshift);
            uint64_t eu = mul_lo_u64_u32(e, u);
            a0 += e;
            a1 += eu;
            a2 += mul_lo_u64_u32(eu, u);
            a3 += mul_lo_u64_u32(e, v);
            a4 += mul_lo_u64_u32(e, v2);
            uint64_t *o = row + 5u * (u + 1u);
            const uint64_t *a = above + 5u * (u + 1u);
            o[0] = a[0] + a0;
            o[1] = a[1] + a1;
            o[2] = a[2] + a2;
            o[3] = a[3] + a3;
            o[4] = a[4] + a4;
        }
    }
}

/* *d = *s member by member (no memcpy in a freestanding core) */
static void copy_probe(qibl_lightprobe_t *d, const qibl_lightprobe_t *s)
{
    d->pixels = s->pixels, d->stride = s->stride, d->width = s->width, d->height = s->height;
    d->format = s->format, d->frac_bits = s->frac_bits, d->built_for = s->built_for;
    d->energy_exp = s->energy_exp, d->energy_div = s->energy_div, d->gshift = s->gshift;
    d->emax = s->emax, d->mshift = s->mshift, d->sat = s->sat, d->mom = s->mom, d->row_sig = s->row_sig;
    d->row_kap = s->row_kap, d->row_sum = s->row_sum, d->total = s->total, d->marg = s->marg;
}

qibl_status_t qibl_lightprobe_build(qibl_lightprobe_t *lp, const qibl_lightprobe_image_t *img,
                                    qibl_lightprobe_method_t method, void *workspace, size_t workspace_size)
{
    QIBLI_DISPATCH(qibl_lightprobe_build, (lp, img, method, workspace, workspace_size));
    if (lp == 0 || img == 0 || img->pixels == 0 || workspace == 0)
        return QIBL_E_NULL_POINTER;
    const uint32_t w = img->width, h = img->height;
    if (!size_ok(w, h))
        return QIBL_E_PROBE_SIZE;
    if (qibl_mul_u32_u64(w, h) > QIBL_LIGHTPROBE_MAX_PIXELS)
        return QIBL_E_PROBE_OVERFLOW;
    if ((unsigned)img->format >= QIBL_LIGHTPROBE_FORMAT_COUNT || img->frac_bits < -128 || img->frac_bits > 128)
        return QIBL_E_PROBE_FORMAT;
    const size_t pb = pixel_bytes(img->format);
    const uint64_t row_bytes = qibl_mul_u32_u64(w, (uint32_t)pb); /* < 2^19 */
    const size_t stride = img->stride ? img->stride : (size_t)row_bytes;
    if ((uint64_t)stride < row_bytes)
        return QIBL_E_PROBE_FORMAT;
    /* the byte span of the image, stride (h - 1) + row_bytes, must be addressable */
    if (h > 1u && (uint64_t)stride > qibl_udiv_u64((uint64_t)SIZE_MAX - row_bytes, h - 1u, 0))
        return QIBL_E_PROBE_OVERFLOW;
    if (pb == 12u && (((uintptr_t)img->pixels & 3u) != 0u || (stride & 3u) != 0u))
        return QIBL_E_PROBE_FORMAT;
    if ((unsigned)method >= QIBL_LIGHTPROBE_METHOD_COUNT)
        return QIBL_E_PROBE_METHOD;
    const uint64_t need = ws_bytes(w, h, method), least = ws_min_bytes(w, h, method);
    if (least == 0u || least > (uint64_t)SIZE_MAX)
        return QIBL_E_PROBE_OVERFLOW;
    if ((uint64_t)workspace_size < least)
        return QIBL_E_WORKSPACE;
    /* the SAT when the workspace holds it, else the marginals (the same lights, bit for bit) */
    const int fast = (uint64_t)workspace_size >= need;

    int32_t lb;
    qibl_status_t st = qibli_probe_bad_status(scan(img, stride, &lb));
    if (st != QIBL_OK)
        return st;

    /* carve the workspace: 8-byte tables first, then the 4-byte row tables */
    uint8_t *ws = (uint8_t *)workspace;
    ws += (8u - ((uintptr_t)ws & 7u)) & 7u;
    const size_t cells = fast ? (size_t)(w + 1u) * (h + 1u) : 0u;
    qibl_lightprobe_t t;
    t.pixels = (const uint8_t *)img->pixels;
    t.stride = stride;
    t.width = w;
    t.height = h;
    t.format = img->format;
    t.frac_bits = img->frac_bits;
    t.built_for = method;
    t.sat = fast ? (uint64_t *)(void *)ws : 0;
    t.mom = fast && method == QIBL_LIGHTPROBE_VARMIN ? t.sat + cells : 0;
    t.marg = fast ? 0 : (uint64_t *)(void *)ws;
    t.row_sum = fast ? t.sat + cells * (method == QIBL_LIGHTPROBE_VARMIN ? 6u : 1u)
                     : t.marg + (size_t)marg_entries(w, h, method);
    t.row_sig = (uint32_t *)(void *)(t.row_sum + h + 1u);
    t.row_kap = (int32_t *)(void *)(t.row_sig + h);
    t.energy_div = img->format == QIBL_LIGHTPROBE_SRGBE ? 510u : 1u;
    t.mshift = 0u;

    t.row_sum[0] = 0u;
    for (uint32_t v = 0; v < h; ++v) {
        sin_frac(2u * (uint64_t)v + 1u, 2u * (uint64_t)h, &t.row_sig[v], &t.row_kap[v]);
        /* sin in Q31, rounded: kap >= -1, and kap <= 15 for h <= 2^15, so the shift is 0..16 */
        uint32_t n = (uint32_t)(t.row_kap[v] + 1);
        t.row_sum[v + 1u] = t.row_sum[v] + (n ? ((t.row_sig[v] >> (n - 1u)) + 1u) >> 1 : t.row_sig[v]);
    }
    /* lb = INT32_MIN (black probe): any shift gives zeros; keep the arithmetic in range */
    int32_t g = lb == INT32_MIN ? 0 : pixel_bits(w, h) - lb;
    t.gshift = g;
    t.emax = img->format == QIBL_LIGHTPROBE_RGBE && lb != INT32_MIN ? lb + 128 : 0;
    t.energy_exp = -g;
    t.total = 0u;
    if (!fast) {
        /* the low-memory path: the total alone now (one read), the marginals when lights asks */
        t.total = lb == INT32_MIN ? 0u : pixel_sum(&t, 0u, 0u, w, h);
        if (method == QIBL_LIGHTPROBE_VARMIN)
            t.mshift = moment_shift(t.total, w, h);
        copy_probe(lp, &t);
        return QIBL_OK;
    }
    for (uint32_t u = 0; u <= w; ++u)
        t.sat[u] = 0u;
    if (lb == INT32_MIN) {
        for (size_t i = w + 1u; i < cells; ++i)
            t.sat[i] = 0u;
    } else if (img->format == QIBL_LIGHTPROBE_RGBE) {
        sat_rgbe(&t);
    } else {
        sat_generic(&t);
    }
    t.total = t.sat[(size_t)h * (w + 1u) + w];
    if (t.mom)
        sat_moments(&t);
    copy_probe(lp, &t);
    return QIBL_OK;
}

/* ---- regions ---------------------------------------------------------------------------------- */

typedef struct {
    uint32_t u0, v0, u1, v1;
} rect;

static inline rect light_rect(const qibl_lightprobe_light_t *l)
{
    rect r;
    r.u0 = l->u0, r.v0 = l->v0, r.u1 = l->u1, r.v1 = l->v1;
    return r;
}

static inline void set_rect(qibl_lightprobe_light_t *l, const rect *r)
{
    l->u0 = r->u0, l->v0 = r->v0, l->u1 = r->u1, l->v1 = r->v1;
}

/* exact energy of [u0, u1) x [v0, v1) (wrap-around arithmetic: the true value is < 2^64) */
static inline uint64_t sat_sum(const qibl_lightprobe_t *lp, uint32_t u0, uint32_t v0, uint32_t u1, uint32_t v1)
{
    const size_t w1 = lp->width + 1u;
    const uint64_t *a = lp->sat + (size_t)v0 * w1, *b = lp->sat + (size_t)v1 * w1;
    return b[u1] - b[u0] - a[u1] + a[u0];
}

static inline uint64_t rect_energy(const qibl_lightprobe_t *lp, rect r)
{
    return sat_sum(lp, r.u0, r.v0, r.u1, r.v1);
}

qibl_status_t qibl_lightprobe_region_energy(const qibl_lightprobe_t *lp, uint32_t u0, uint32_t v0, uint32_t u1,
                                            uint32_t v1, uint64_t *energy)
{
    if (lp == 0 || energy == 0)
        return QIBL_E_NULL_POINTER;
    if (u0 > u1 || v0 > v1 || u1 > lp->width || v1 > lp->height)
        return QIBL_E_PROBE_RECT;
    *energy = lp->sat ? sat_sum(lp, u0, v0, u1, v1) : lp->total ? pixel_sum(lp, u0, v0, u1, v1) : 0u;
    return QIBL_OK;
}

/* ---- the low-memory path: a region's marginals ------------------------------------------------
 * Every decision below reads a region only through sums over whole columns or whole rows of it
 * (cut energies, moment sums, crops, centroids), and every such sum is an exact integer. One read
 * of a region's pixels into its per-column and per-row sums (its marginals) therefore gives each
 * of them as the same integer the SAT gives: the same cuts, keys and lights, bit for bit, in
 * O(W + H) memory, for O(w h) reads each time a region is looked at. */

/* The marginals of the region last scanned, indexed from its corner: per column ce = sum e and,
 * with the moments, c0 = sum em, c1 = sum em v, c2 = sum em v^2; per row re = sum e, r0 = sum em,
 * r1 = sum em u, r2 = sum em u^2. u and v are absolute, as in the moment SATs, so every sum is a
 * part of the probe's sums, below 2^64 (lightprobe.c's header). */
typedef struct {
    uint64_t *ce, *re, *c0, *c1, *c2, *r0, *r1, *r2;
} marg;

/* the arrays in the workspace (marg_entries): W + 1 entries per column array, H + 1 per row one */
static void marg_arrays(const qibl_lightprobe_t *lp, marg *m)
{
    const size_t w1 = (size_t)lp->width + 1u, h1 = (size_t)lp->height + 1u;
    uint64_t *p = lp->marg;
    m->ce = p, p += w1;
    m->re = p, p += h1;
    m->c0 = m->c1 = m->c2 = m->r0 = m->r1 = m->r2 = 0;
    if (lp->built_for == QIBL_LIGHTPROBE_VARMIN) {
        m->c0 = p, p += w1;
        m->c1 = p, p += w1;
        m->c2 = p, p += w1;
        m->r0 = p, p += h1;
        m->r1 = p, p += h1;
        m->r2 = p;
    }
}

/* One read of r's pixels into the marginals (mom: the moment ones too, for a probe built for
 * VARMIN); returns r's energy. */
static uint64_t marg_scan(const qibl_lightprobe_t *lp, const marg *m, rect r, int mom)
{
    uint64_t buf[ROW_CHUNK], total = 0u;
    const uint32_t w = r.u1 - r.u0, k = lp->mshift;
    for (uint32_t i = 0; i < w; ++i)
        m->ce[i] = 0u;
    if (mom)
        for (uint32_t i = 0; i < w; ++i)
            m->c0[i] = m->c1[i] = m->c2[i] = 0u;
    for (uint32_t v = r.v0; v < r.v1; ++v) {
        const uint32_t vv = v * v; /* < 2^30 */
        uint64_t se = 0u, s0 = 0u, s1 = 0u, s2 = 0u;
        for (uint32_t u = r.u0; u < r.u1;) {
            const uint32_t n = r.u1 - u < ROW_CHUNK ? r.u1 - u : ROW_CHUNK, o = u - r.u0;
            row_energy(lp, v, u, n, buf);
            if (!mom) {
                for (uint32_t i = 0; i < n; ++i) {
                    m->ce[o + i] += buf[i];
                    se += buf[i];
                }
            } else {
                for (uint32_t i = 0; i < n; ++i) {
                    const uint64_t e = buf[i], em = qibl_shr_u64(e, k), emu = mul_lo_u64_u32(em, u + i);
                    m->ce[o + i] += e;
                    m->c0[o + i] += em;
                    m->c1[o + i] += mul_lo_u64_u32(em, v);
                    m->c2[o + i] += mul_lo_u64_u32(em, vv);
                    se += e;
                    s0 += em;
                    s1 += emu;
                    s2 += mul_lo_u64_u32(emu, u + i);
                }
            }
            u += n;
        }
        m->re[v - r.v0] = se;
        if (mom)
            m->r0[v - r.v0] = s0, m->r1[v - r.v0] = s1, m->r2[v - r.v0] = s2;
        total += se;
    }
    return total;
}

/* a[0 .. n) -> a[0 .. n]: a[i] = the sum of the first i entries (the arrays hold n + 1) */
static void prefix(uint64_t *a, uint32_t n)
{
    uint64_t run = 0u;
    for (uint32_t i = 0; i < n; ++i) {
        uint64_t t = a[i];
        a[i] = run;
        run += t;
    }
    a[n] = run;
}

/* crop (below) from the marginals of a scan of r: the first and last lit column and row (an
 * unlit r becomes its last pixel, as crop's searches make it) */
static void marg_crop(const marg *m, rect *r)
{
    const uint32_t w = r->u1 - r->u0, h = r->v1 - r->v0;
    uint32_t a = 0u, b = w, c = 0u, d = h;
    while (a + 1u < w && m->ce[a] == 0u)
        ++a;
    while (b > a + 1u && m->ce[b - 1u] == 0u)
        --b;
    while (c + 1u < h && m->re[c] == 0u)
        ++c;
    while (d > c + 1u && m->re[d - 1u] == 0u)
        --d;
    r->u1 = r->u0 + b, r->u0 += a;
    r->v1 = r->v0 + d, r->v0 += c;
}

/* the moment sums of a column i (absolute u) or a row i (absolute v) added to s (see rect_sums) */
static inline void add_col(const marg *m, uint32_t i, uint32_t u, uint64_t s[5])
{
    const uint64_t a = m->c0[i], au = mul_lo_u64_u32(a, u);
    s[0] += a;
    s[1] += au;
    s[2] += mul_lo_u64_u32(au, u);
    s[3] += m->c1[i];
    s[4] += m->c2[i];
}

static inline void add_row(const marg *m, uint32_t i, uint32_t v, uint64_t s[5])
{
    const uint64_t a = m->r0[i], av = mul_lo_u64_u32(a, v);
    s[0] += a;
    s[1] += m->r1[i];
    s[2] += m->r2[i];
    s[3] += av;
    s[4] += mul_lo_u64_u32(av, v);
}

/* the moment sums of the scanned region r */
static void marg_sums(const marg *m, rect r, uint64_t s[5])
{
    for (int j = 0; j < 5; ++j)
        s[j] = 0u;
    for (uint32_t i = 0; i < r.u1 - r.u0; ++i)
        add_col(m, i, r.u0 + i, s);
}

/* F(c), the energy of a region before the cut c along one axis: from the SAT (pre NULL) or from
 * the prefix sums of the region's marginal, pre[c - start] */
typedef struct {
    const qibl_lightprobe_t *lp;
    rect r;
    int along_u;
    const uint64_t *pre;
} line;

static inline uint64_t line_f(const line *L, uint32_t c)
{
    if (L->pre)
        return L->pre[c - (L->along_u ? L->r.u0 : L->r.v0)];
    return L->along_u ? sat_sum(L->lp, L->r.u0, L->r.v0, c, L->r.v1) : sat_sum(L->lp, L->r.u0, L->r.v0, L->r.u1, c);
}

/* 2H times the mean sin theta over rows [v0, v1), in units of 2^-16, below 2^32: the factor that
 * turns a width in pixels into the same angular unit as a height in pixels times W
 * (angular width / angular height = w 2H mean_sin / (h W)). */
static uint32_t width_factor(const qibl_lightprobe_t *lp, uint32_t v0, uint32_t v1)
{
    uint64_t s = lp->row_sum[v1] - lp->row_sum[v0]; /* Q31, < 2^46 */
    uint64_t mean16 = qibl_udiv_u64(s, (uint64_t)(v1 - v0) << 15, 0); /* Q16, <= 2^16 */
    if (mean16 > 0xFFFFu)
        mean16 = 0xFFFFu;
    return (uint32_t)mean16 * (2u * lp->height); /* < 2^16 2^16 */
}

/* Does the region's angular width exceed its angular height? (ties: yes) */
static int wider(const qibl_lightprobe_t *lp, rect r)
{
    uint64_t aw = qibl_mul_u32_u64(width_factor(lp, r.v0, r.v1), r.u1 - r.u0); /* < 2^47 */
    uint64_t bh = qibl_mul_u32_u64(lp->width, r.v1 - r.v0) << 16;                 /* < 2^46 */
    return aw >= bh;
}

/* Variance-related quantities of a region, about its own corner. */
typedef struct {
    uint64_t s0, su, suu, sv, svv;
} moments;

/* The region's moment sums S0 = sum em, S1 = sum em u, S2 = sum em u^2, S3 = sum em v,
 * S4 = sum em v^2 (absolute u, v) from the moment SATs */
static void rect_sums(const qibl_lightprobe_t *lp, rect r, uint64_t s[5])
{
    const size_t w1 = lp->width + 1u;
    const uint64_t *a = lp->mom + 5u * ((size_t)r.v0 * w1), *b = lp->mom + 5u * ((size_t)r.v1 * w1);
    for (int j = 0; j < 5; ++j)
        s[j] = b[5u * r.u1 + (unsigned)j] - b[5u * r.u0 + (unsigned)j] - a[5u * r.u1 + (unsigned)j] +
               a[5u * r.u0 + (unsigned)j];
}

static void shift_moments(const uint64_t s[5], rect r, moments *m)
{
    /* shift the origin to (u0, v0): sum e (u - u0) = S1 - u0 S0, sum e (u - u0)^2 = S2 - 2 u0 S1 + u0^2 S0,
     * all mod 2^64, exact since the true values are below 2^64 */
    m->s0 = s[0];
    m->su = s[1] - mul_lo_u64_u32(s[0], r.u0);
    m->suu = s[2] - mul_lo_u64_u32(s[1], 2u * r.u0) + mul_lo_u64_u32(mul_lo_u64_u32(s[0], r.u0), r.u0);
    m->sv = s[3] - mul_lo_u64_u32(s[0], r.v0);
    m->svv = s[4] - mul_lo_u64_u32(s[3], 2u * r.v0) + mul_lo_u64_u32(mul_lo_u64_u32(s[0], r.v0), r.v0);
}

/* sum e (x - mean)^2 = S2 - S1^2 / S0 (floor of the quotient), exactly */
static uint64_t variance(uint64_t s0, uint64_t s1, uint64_t s2)
{
    if (s0 == 0u)
        return 0u;
    u128 sq;
    mul64(s1, s1, &sq);
    uint64_t q = div128(&sq, s0, 0);
    return s2 > q ? s2 - q : 0u;
}

/* Energy-weighted angular variance of a region with moment sums s: a^2 Var_u + b^2 Var_v with
 * a = 2H mean_sin and b = W (both in units of 2^-16), proportional to sum e d^2 with d the angular
 * distance to the centroid measured as (sin theta dphi, dtheta). Below 2^127: Var_u <= S0 w^2 / 4
 * < 2^62. */
static void sums_variance(const qibl_lightprobe_t *lp, rect r, const uint64_t s[5], u128 *out)
{
    moments m;
    shift_moments(s, r, &m);
    uint64_t a = width_factor(lp, r.v0, r.v1); /* < 2^32 */
    uint64_t b = (uint64_t)lp->width << 16;    /* <= 2^31 */
    u128 t;
    mul64(qibl_mul_u32_u64((uint32_t)a, (uint32_t)a), variance(m.s0, m.su, m.suu), out);
    mul64(qibl_mul_u32_u64((uint32_t)b, (uint32_t)b), variance(m.s0, m.sv, m.svv), &t);
    add128(out, &t);
}

/* ---- cut rules -------------------------------------------------------------------------------- */

/* |F - (T - F)|: how far a cut with F on one side is from the median */
static inline uint64_t imbalance(uint64_t f, uint64_t total)
{
    return f >= total - f ? f - (total - f) : (total - f) - f;
}

/* Median cut: split along the longer side on the sphere at the cut whose halves' energies are
 * closest (ties: the smaller cut), found by binary search on F (the SAT, or the prefix sums
 * pre_u / pre_v of the region's marginals). 0 if r cannot split. */
static int cut_median(const qibl_lightprobe_t *lp, rect r, uint64_t total, const uint64_t *pre_u,
                      const uint64_t *pre_v, rect *a, rect *b)
{
    uint32_t w = r.u1 - r.u0, h = r.v1 - r.v0;
    if (w < 2u && h < 2u)
        return 0;
    int along_u = h < 2u || (w >= 2u && wider(lp, r));
    line L;
    L.lp = lp, L.r = r, L.along_u = along_u, L.pre = along_u ? pre_u : pre_v;
    uint32_t lo = (along_u ? r.u0 : r.v0) + 1u, hi = (along_u ? r.u1 : r.v1) - 1u; /* cuts lo..hi */
    /* smallest c in [lo, hi] with F(c) >= T - F(c), else hi */
    uint32_t l = lo, e = hi;
    while (l < e) {
        uint32_t c = l + (e - l) / 2u;
        uint64_t f = line_f(&L, c);
        if (f >= total - f)
            e = c;
        else
            l = c + 1u;
    }
    uint32_t c = l;
    if (c > lo) {
        /* the cut before may be closer to the median: keep the closer one (ties: the smaller) */
        uint64_t f1 = line_f(&L, c);
        uint64_t f0 = line_f(&L, c - 1u);
        if (imbalance(f0, total) <= imbalance(f1, total)) {
            --c;
            f1 = f0;
        }
        /* a plateau (columns or rows without energy) gives the same imbalance all along: take its
         * first cut, the smallest c with F(c) = F(best) */
        l = lo;
        e = c;
        while (l < e) {
            uint32_t m = l + (e - l) / 2u;
            uint64_t f = line_f(&L, m);
            if (f >= f1)
                e = m;
            else
                l = m + 1u;
        }
        c = l;
    }
    *a = r;
    *b = r;
    if (along_u)
        a->u1 = b->u0 = c;
    else
        a->v1 = b->v0 = c;
    return 1;
}

/* Variance minimisation: among all cuts of both axes, the one minimising the larger of the two
 * halves' variances (Viriyothai & Debevec); ties: the smaller energy imbalance, then the longer
 * side on the sphere, then the smaller cut. The halves' sums come from the moment SATs (m NULL)
 * or, cut after cut, from the running sums of the marginals of a scan of r. 0 if r cannot split. */
static int cut_varmin(const qibl_lightprobe_t *lp, const marg *m, rect r, uint64_t total, rect *a, rect *b)
{
    uint32_t w = r.u1 - r.u0, h = r.v1 - r.v0;
    if (w < 2u && h < 2u)
        return 0;
    int first_u = h < 2u || (w >= 2u && wider(lp, r));
    int found = 0;
    u128 best = {0u, 0u}, vx, vy;
    uint64_t best_imb = 0u, all[5];
    if (m)
        marg_sums(m, r, all);
    for (int pass = 0; pass < 2; ++pass) {
        int along_u = pass == 0 ? first_u : !first_u;
        uint32_t lo = (along_u ? r.u0 : r.v0) + 1u, hi = along_u ? r.u1 : r.v1;
        uint64_t run[5], run_e = 0u;
        for (int j = 0; j < 5; ++j)
            run[j] = 0u; /* assigned one by one: an initialiser becomes a memset call */
        for (uint32_t c = lo; c < hi; ++c) {
            rect x = r, y = r;
            if (along_u)
                x.u1 = y.u0 = c;
            else
                x.v1 = y.v0 = c;
            uint64_t sx[5], sy[5], ex;
            if (m) {
                const uint32_t i = c - lo; /* the column or row just before the cut */
                if (along_u) {
                    add_col(m, i, c - 1u, run);
                    run_e += m->ce[i];
                } else {
                    add_row(m, i, c - 1u, run);
                    run_e += m->re[i];
                }
                for (int j = 0; j < 5; ++j)
                    sx[j] = run[j], sy[j] = all[j] - run[j];
                ex = run_e;
            } else {
                rect_sums(lp, x, sx);
                rect_sums(lp, y, sy);
                ex = rect_energy(lp, x);
            }
            sums_variance(lp, x, sx, &vx);
            sums_variance(lp, y, sy, &vy);
            const u128 *score = cmp128(&vx, &vy) >= 0 ? &vx : &vy;
            uint64_t imb = imbalance(ex, total);
            int k = found ? cmp128(score, &best) : -1;
            if (k < 0 || (k == 0 && imb < best_imb)) {
                found = 1;
                best.hi = score->hi;
                best.lo = score->lo;
                best_imb = imb;
                *a = x;
                *b = y;
            }
        }
    }
    return found;
}

/* ---- priorities ------------------------------------------------------------------------------- */

/* Greedy key of a region with energy e and moment sums s (VARIANCE only) (0: never split it). */
static void region_key(const qibl_lightprobe_t *lp, rect r, qibl_lightprobe_priority_t pr, uint64_t e,
                       const uint64_t s[5], u128 *k)
{
    k->hi = k->lo = 0u;
    if (pr == QIBL_LIGHTPROBE_PRIORITY_LEVELS || (r.u1 - r.u0 < 2u && r.v1 - r.v0 < 2u))
        return;
    if (pr == QIBL_LIGHTPROBE_PRIORITY_ENERGY) {
        k->lo = e;
    } else if (pr == QIBL_LIGHTPROBE_PRIORITY_ENERGY_SIZE) {
        uint64_t aw = qibl_mul_u32_u64(width_factor(lp, r.v0, r.v1), r.u1 - r.u0);
        uint64_t bh = qibl_mul_u32_u64(lp->width, r.v1 - r.v0) << 16;
        mul64(e, aw > bh ? aw : bh, k); /* energy times the longer side, < 2^111 */
    } else {
        sums_variance(lp, r, s, k);
    }
}

/* While regions split, each light holds its region's key and its cut in its dir and rgb members
 * (free until the colours and directions are written): 32-bit pieces, each stored as
 * piece - 2^31 so that an int32 holds it exactly. Key in dir[0] and rgb[0..2], cut in dir[1]
 * (see cut_code); then, for the sort and the directions, the energy in dir[1..2] (it outlives
 * the colour pass, which writes rgb and dir[0]). */
static inline int32_t piece_in(uint64_t x)
{
    return (int32_t)((int64_t)(uint32_t)x - ((int64_t)1 << 31));
}

static inline uint64_t piece_out(int32_t x)
{
    return (uint64_t)((int64_t)x + ((int64_t)1 << 31));
}

static void put_region(qibl_lightprobe_light_t *l, const rect *r, const u128 *k, uint32_t cut)
{
    set_rect(l, r);
    l->dir[1] = piece_in(cut), l->dir[2] = 0;
    l->dir[0] = piece_in(k->hi >> 32), l->rgb[0] = piece_in(k->hi), l->rgb[1] = piece_in(k->lo >> 32);
    l->rgb[2] = piece_in(k->lo);
}

static void put_energy(qibl_lightprobe_light_t *l, uint64_t e)
{
    l->dir[1] = piece_in(e >> 32), l->dir[2] = piece_in(e);
}

/* A region's median cut, decided on the low-memory path when the region is settled (that scan's
 * marginals are the region's, so no second read of it when it splits): 1 + 2 c + along_u, or 0
 * for none yet (one pixel; VARMIN, whose cut costs more than a read of the region on the small
 * targets and so is made only for the regions that split; the SAT path, which cuts when it
 * splits) */
static inline uint32_t cut_code(const rect *r, const rect *a)
{
    const uint32_t along_u = a->u1 != r->u1;
    return 1u + 2u * (along_u ? a->u1 : a->v1) + along_u;
}

static inline uint64_t light_energy(const qibl_lightprobe_light_t *l)
{
    return piece_out(l->dir[1]) << 32 | piece_out(l->dir[2]);
}

static inline void light_key(const qibl_lightprobe_light_t *l, u128 *k)
{
    k->hi = piece_out(l->dir[0]) << 32 | piece_out(l->rgb[0]);
    k->lo = piece_out(l->rgb[1]) << 32 | piece_out(l->rgb[2]);
}

/* *d = *s member by member (a struct assignment would call memcpy on some targets, which a
 * freestanding core does not link) */
static void copy_light(qibl_lightprobe_light_t *d, const qibl_lightprobe_light_t *s)
{
    for (int c = 0; c < 3; ++c)
        d->dir[c] = s->dir[c], d->rgb[c] = s->rgb[c];
    d->u0 = s->u0, d->v0 = s->v0, d->u1 = s->u1, d->v1 = s->v1;
}

/* Exchanges two lights member by member */
static void swap_lights(qibl_lightprobe_light_t *x, qibl_lightprobe_light_t *y)
{
    for (int c = 0; c < 3; ++c) {
        qibl_q30_t d = x->dir[c];
        int32_t k = x->rgb[c];
        x->dir[c] = y->dir[c], y->dir[c] = d;
        x->rgb[c] = y->rgb[c], y->rgb[c] = k;
    }
    rect r = light_rect(x), q = light_rect(y);
    set_rect(x, &q);
    set_rect(y, &r);
}

/* Ties of both orders below: smaller v0, then smaller u0 (a total, deterministic order: the regions
 * of one run never overlap) */
static int first_of_equals(const qibl_lightprobe_light_t *x, const qibl_lightprobe_light_t *y)
{
    if (x->v0 != y->v0)
        return x->v0 < y->v0;
    return x->u0 < y->u0;
}

/* the cut heap's order: larger key first */
static int before(const qibl_lightprobe_light_t *x, const qibl_lightprobe_light_t *y)
{
    u128 kx, ky;
    light_key(x, &kx);
    light_key(y, &ky);
    int k = cmp128(&kx, &ky);
    return k != 0 ? k > 0 : first_of_equals(x, y);
}

/* the result's order: more energy first */
static int brighter(const qibl_lightprobe_light_t *x, const qibl_lightprobe_light_t *y)
{
    uint64_t a = light_energy(x), b = light_energy(y);
    return a != b ? a > b : first_of_equals(x, y);
}

/* x goes above y in the cut heap (before) or in the final sort's (the dimmest on top, so that the
 * sorted array ends up brightest first) */
static int above(const qibl_lightprobe_light_t *x, const qibl_lightprobe_light_t *y, int dimmest_top)
{
    return dimmest_top ? brighter(y, x) : before(x, y);
}

static void sift_down(qibl_lightprobe_light_t *h, uint32_t n, uint32_t i, int dimmest_top)
{
    for (;;) {
        uint32_t l = 2u * i + 1u, top = i;
        if (l < n && above(&h[l], &h[top], dimmest_top))
            top = l;
        if (l + 1u < n && above(&h[l + 1u], &h[top], dimmest_top))
            top = l + 1u;
        if (top == i)
            return;
        swap_lights(&h[i], &h[top]);
        i = top;
    }
}

static void sift_up(qibl_lightprobe_light_t *h, uint32_t i)
{
    while (i > 0u) {
        uint32_t p = (i - 1u) / 2u;
        if (!before(&h[i], &h[p]))
            return;
        swap_lights(&h[i], &h[p]);
        i = p;
    }
}

/* ---- lights ----------------------------------------------------------------------------------- */

/* the energy of r with its range along u (or v) replaced by [a, b) */
static uint64_t band_sum(const qibl_lightprobe_t *lp, const rect *r, int along_u, uint32_t a, uint32_t b)
{
    return along_u ? sat_sum(lp, a, r->v0, b, r->v1) : sat_sum(lp, r->u0, a, r->u1, b);
}

/* r cut along u (or v) to its first lit line and the end of its last (r itself is written only at
 * the end, so the searches keep their bounds in registers) */
static inline void crop_axis(const qibl_lightprobe_t *lp, rect *r, int along_u)
{
    const uint32_t lo = along_u ? r->u0 : r->v0, hi = along_u ? r->u1 : r->v1;
    uint32_t l, e;
    /* first lit line: smallest c with energy in [lo, c + 1) */
    for (l = lo, e = hi - 1u; l < e;) {
        uint32_t c = l + (e - l) / 2u;
        if (band_sum(lp, r, along_u, lo, c + 1u) != 0u)
            e = c;
        else
            l = c + 1u;
    }
    const uint32_t first = l;
    /* end of the last lit line: largest c with energy in [c - 1, hi) */
    for (l = first + 1u, e = hi; l < e;) {
        uint32_t c = l + (e - l + 1u) / 2u;
        if (band_sum(lp, r, along_u, c - 1u, hi) != 0u)
            l = c;
        else
            e = c - 1u;
    }
    if (along_u)
        r->u0 = first, r->u1 = l;
    else
        r->v0 = first, r->v1 = l;
}

/* Shrinks a lit region to the bounding box of its energy (binary searches on the SAT: energy
 * beyond a cut only grows as the cut moves out). Dark margins carry no light, and once they are
 * gone the first and last column and row of a region are lit, so every cut leaves energy on both
 * sides and the place of a cut inside a dark gap makes no difference. */
static void crop(const qibl_lightprobe_t *lp, rect *r)
{
    crop_axis(lp, r, 1);
    crop_axis(lp, r, 0);
}

/* A new region: cropped to its energy's bounding box, with its greedy key *k and (low-memory
 * path, m non-NULL: from the one scan of it) its median cut *cut (cut_code) */
static void settle(const qibl_lightprobe_t *lp, const marg *m, int varmin, qibl_lightprobe_priority_t pr, rect *r,
                   u128 *k, uint32_t *cut)
{
    const int var = pr == QIBL_LIGHTPROBE_PRIORITY_VARIANCE;
    uint64_t s[5], e;
    for (int j = 0; j < 5; ++j)
        s[j] = 0u; /* assigned one by one: an initialiser becomes a memset call */
    *cut = 0u;
    if (m) {
        rect scanned; /* member by member: a struct copy becomes a memcpy call on some targets */
        scanned.u0 = r->u0, scanned.v0 = r->v0, scanned.u1 = r->u1, scanned.v1 = r->v1;
        e = marg_scan(lp, m, scanned, var);
        marg_crop(m, r);
        if (var)
            marg_sums(m, scanned, s); /* the cropped margins hold no energy */
        if (!varmin && !(r->u1 - r->u0 < 2u && r->v1 - r->v0 < 2u)) {
            /* the cropped region's marginals are the scan's from the crop's offsets (the columns
             * and rows cropped away hold no energy) */
            uint64_t *ce = m->ce + (r->u0 - scanned.u0), *re = m->re + (r->v0 - scanned.v0);
            rect a, b;
            prefix(ce, r->u1 - r->u0);
            prefix(re, r->v1 - r->v0);
            if (cut_median(lp, *r, e, ce, re, &a, &b))
                *cut = cut_code(r, &a);
        }
    } else {
        crop(lp, r);
        e = rect_energy(lp, *r);
        if (var && !(r->u1 - r->u0 < 2u && r->v1 - r->v0 < 2u))
            rect_sums(lp, *r, s);
    }
    region_key(lp, *r, pr, e, s, k);
}

/* Splits a cropped region (the light src) into two cropped, lit halves with their keys (la and
 * lb may be src); 0 if it is one pixel. */
static int split(const qibl_lightprobe_t *lp, const marg *m, int varmin, qibl_lightprobe_priority_t pr,
                 const qibl_lightprobe_light_t *src, qibl_lightprobe_light_t *la, qibl_lightprobe_light_t *lb)
{
    const rect r = light_rect(src);
    if (r.u1 - r.u0 < 2u && r.v1 - r.v0 < 2u)
        return 0;
    rect a, b;
    const uint32_t code = m ? (uint32_t)piece_out(src->dir[1]) : 0u;
    if (code != 0u) { /* settle decided it */
        const uint32_t c = (code - 1u) >> 1;
        a = r, b = r;
        if ((code - 1u) & 1u)
            a.u1 = b.u0 = c;
        else
            a.v1 = b.v0 = c;
    } else if (m) {
        /* VARMIN's cut (settle left it): the region read again, with the moments */
        const uint64_t t = marg_scan(lp, m, r, varmin);
        int ok;
        if (varmin) {
            ok = cut_varmin(lp, m, r, t, &a, &b);
        } else {
            prefix(m->ce, r.u1 - r.u0);
            prefix(m->re, r.v1 - r.v0);
            ok = cut_median(lp, r, t, m->ce, m->re, &a, &b);
        }
        if (!ok)
            return 0;
    } else {
        uint64_t t = rect_energy(lp, r);
        if (!(varmin ? cut_varmin(lp, 0, r, t, &a, &b) : cut_median(lp, r, t, 0, 0, &a, &b)))
            return 0;
    }
    u128 ka, kb;
    uint32_t ca, cb;
    settle(lp, m, varmin, pr, &a, &ka, &ca);
    settle(lp, m, varmin, pr, &b, &kb, &cb);
    put_region(la, &a, &ka, ca);
    put_region(lb, &b, &kb, cb);
    return 1;
}

/* Splits until max_lights regions or nothing splits; returns the count. Every region is the
 * bounding box of its energy (see crop), so each split adds one lit region; a region that cannot
 * split (one pixel) never stops the others, so the count is max_lights whenever the probe has
 * that many lit pixels. Each light holds its region's key and cut (put_region). */
static uint32_t make_regions(const qibl_lightprobe_t *lp, const marg *m, int varmin, qibl_lightprobe_priority_t pr,
                             qibl_lightprobe_light_t *L, uint32_t max_lights)
{
    rect all;
    all.u0 = all.v0 = 0u;
    all.u1 = lp->width;
    all.v1 = lp->height;
    u128 k;
    uint32_t cut;
    settle(lp, m, varmin, pr, &all, &k, &cut);
    put_region(&L[0], &all, &k, cut);
    uint32_t n = 1u;
    if (pr == QIBL_LIGHTPROBE_PRIORITY_LEVELS) {
        for (uint32_t round = 1u; round < max_lights; round <<= 1) {
            uint32_t cnt = n;
            for (uint32_t i = 0; i < cnt; ++i)
                if (split(lp, m, varmin, pr, &L[i], &L[i], &L[n]))
                    ++n;
        }
        /* One-pixel regions (a tiny sun) skipped a split: split the next splittable regions in
         * list order instead, so that max_lights lights come back whenever the probe has that
         * many lit pixels. */
        for (int grew = 1; grew && n < max_lights;) {
            grew = 0;
            for (uint32_t i = 0; i < n && n < max_lights; ++i) {
                if (!split(lp, m, varmin, pr, &L[i], &L[i], &L[n]))
                    continue;
                ++n;
                grew = 1;
            }
        }
        return n;
    }
    /* h regions in the heap L[0 .. h); d regions that cannot split set aside at the end of the
     * array, L[max_lights - d .. max_lights), so that the next best region is split instead */
    uint32_t h = 1u, d = 0u;
    while (h > 0u && h + d < max_lights) {
        u128 top;
        light_key(&L[0], &top);
        if (top.hi == 0u && top.lo == 0u)
            break; /* the best region gains nothing from a split: none does */
        /* the halves go to L[0] and L[h] (L[h] is free: h + d < max_lights) */
        if (!split(lp, m, varmin, pr, &L[0], &L[0], &L[h])) {
            ++d;
            copy_light(&L[max_lights - d], &L[0]);
            copy_light(&L[0], &L[h - 1u]);
            if (--h > 0u)
                sift_down(L, h, 0u, 0);
            continue;
        }
        sift_down(L, h, 0u, 0);
        sift_up(L, h);
        ++h;
    }
    /* the set-aside regions back behind the heap (ascending copy: the destination is never
     * after the source) */
    for (uint32_t i = 0; i < d; ++i)
        copy_light(&L[h + i], &L[max_lights - d + i]);
    return h + d;
}

/* sum over cuts k in (lo, hi) of the energy beyond k: sum e (x - lo) over the region, < 2^80 */
static void first_moment(const line *L, uint64_t total, u128 *acc)
{
    acc->hi = acc->lo = 0u;
    uint32_t lo = L->along_u ? L->r.u0 : L->r.v0, hi = L->along_u ? L->r.u1 : L->r.v1;
    for (uint32_t k = lo + 1u; k < hi; ++k)
        add128_64(acc, total - line_f(L, k));
}

/* Centroid (or centre) of the region in pixel units, Q32, measured from the left / top edge. */
static uint64_t place_q32(const line *L, uint64_t total, qibl_lightprobe_place_t place)
{
    uint32_t lo = L->along_u ? L->r.u0 : L->r.v0, hi = L->along_u ? L->r.u1 : L->r.v1;
    if (place == QIBL_LIGHTPROBE_PLACE_CENTRE)
        return (uint64_t)(lo + hi) << 31;
    /* mean of (x + 1/2) weighted by e = lo + 1/2 + sum e (x - lo) / T; the quotient is < 2^47 */
    u128 m;
    first_moment(L, total, &m);
    shl128(&m, 32);
    uint64_t frac = div128(&m, total, 0);
    return ((uint64_t)lo << 32) + ((uint64_t)1 << 31) + frac;
}

static void direction(const qibl_lightprobe_t *lp, const marg *mg, rect r, uint64_t total,
                      qibl_lightprobe_place_t place, qibl_q30_t dir[3])
{
    line lu, lv;
    lu.lp = lv.lp = lp, lu.r = lv.r = r, lu.along_u = 1, lv.along_u = 0, lu.pre = lv.pre = 0;
    if (mg && place != QIBL_LIGHTPROBE_PLACE_CENTRE) {
        (void)marg_scan(lp, mg, r, 0);
        prefix(mg->ce, r.u1 - r.u0);
        prefix(mg->re, r.v1 - r.v0);
        lu.pre = mg->ce, lv.pre = mg->re;
    }
    uint64_t cu = place_q32(&lu, total, place), cv = place_q32(&lv, total, place);
    /* phi / pi = 2 cu / W and theta / pi = cv / H, in Q31 */
    uint32_t fphi = (uint32_t)qibl_udiv_u64(cu + lp->width / 2u, lp->width, 0);
    uint32_t fth = (uint32_t)qibl_udiv_u64(cv + lp->height, 2u * (uint64_t)lp->height, 0);
    int32_t st, ct, sp, cp;
    sincos_q30(fth, &st, &ct);
    sincos_q30(fphi, &sp, &cp);
    int32_t d[3];
    d[0] = qibli_rshr_s64(qibl_mul_s32_s64(st, cp), 30);
    d[1] = qibli_rshr_s64(qibl_mul_s32_s64(st, sp), 30);
    d[2] = ct;
    /* |d| = 1 within a few LSB; renormalise (never zero: |d| > 1/2) */
    QIBL_DROP_STATUS(qibl_vec3_normalize_q30(d, dir));
}

#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
/* Eight pixels' colour terms added to s0..s2: (m_c sig 2^16) >> k written as (m_c sig) >> (k - 16)
 * when shl16 is 0 (the caller has k >= 16 for every lit pixel of the eight: the same floor without
 * the left shift), else as the scalar loop has it. k: per-pixel counts in 32-bit lanes, all ones
 * where E = 0 (black: vpsrlvq gives 0 for counts >= 64). vpmuludq reads the low half of each
 * 64-bit lane, so the words are split into even and odd pixels. */
#define RGB8_TERM(m, k, shl16)                                                                                       \
    (shl16 ? _mm256_srlv_epi64(_mm256_slli_epi64(_mm256_mul_epu32(m, vsig), 16), k)                                  \
           : _mm256_srlv_epi64(_mm256_mul_epu32(m, vsig), k))
#define RGB8(px, k, shl16)                                                                                           \
    do {                                                                                                             \
        const __m256i ke_ = _mm256_and_si256(k, lo32), ko_ = _mm256_srli_epi64(k, 32);                              \
        const __m256i po_ = _mm256_srli_epi64(px, 32);                                                               \
        s0 = _mm256_add_epi64(s0, _mm256_add_epi64(RGB8_TERM(_mm256_and_si256(px, ff), ke_, shl16),                  \
                                                   RGB8_TERM(_mm256_and_si256(po_, ff), ko_, shl16)));               \
        s1 = _mm256_add_epi64(s1, _mm256_add_epi64(RGB8_TERM(_mm256_and_si256(_mm256_srli_epi32(px, 8), ff), ke_,   \
                                                             shl16),                                                 \
                                                   RGB8_TERM(_mm256_and_si256(_mm256_srli_epi32(po_, 8), ff), ko_,  \
                                                             shl16)));                                               \
        s2 = _mm256_add_epi64(s2, _mm256_add_epi64(RGB8_TERM(_mm256_and_si256(_mm256_srli_epi32(px, 16), ff), ke_,  \
                                                             shl16),                                                 \
                                                   RGB8_TERM(_mm256_and_si256(_mm256_srli_epi32(po_, 16), ff), ko_, \
                                                             shl16)));                                               \
    } while (0)

/* The RGBE colour sums of one row piece, eight pixels at a time: x_c = (m_c sig 2^16) >> (r - E), as
 * the scalar loop (each term below 2^56, sums mod 2^64: the same bits in any order). Most blocks
 * have r - E >= 16 for every lit pixel and skip the left shift (RGB8); a block with a pixel within
 * 16 of r takes the scalar loop's form. Returns the pixels done (a multiple of 8). */
static uint32_t rgb_row_avx2(const uint8_t *q, uint32_t n, uint32_t sig, uint32_t r, uint64_t a[3])
{
    const __m256i vsig = _mm256_set1_epi64x((long long)sig), vr = _mm256_set1_epi32((int)r);
    const __m256i ff = _mm256_set1_epi32(0xFF), lo32 = _mm256_set1_epi64x(0xFFFFFFFFll);
    const __m256i c16 = _mm256_set1_epi32(16), zero = _mm256_setzero_si256();
    __m256i s0 = zero, s1 = zero, s2 = zero;
    uint32_t u = 0u;
    for (; u + 8u <= n; u += 8u, q += 32) {
        const __m256i px = _mm256_loadu_si256((const __m256i *)(const void *)q);
        const __m256i e = _mm256_srli_epi32(px, 24), black = _mm256_cmpeq_epi32(e, zero);
        const __m256i k = _mm256_sub_epi32(vr, e), k16 = _mm256_sub_epi32(k, c16); /* r - E <= 255 + r: no wrap */
        if (_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_andnot_si256(black, k16))) == 0) {
            const __m256i kk = _mm256_or_si256(k16, black);
            RGB8(px, kk, 0);
        } else {
            const __m256i kk = _mm256_or_si256(k, black);
            RGB8(px, kk, 1);
        }
    }
    uint64_t t[3][4];
    _mm256_storeu_si256((__m256i *)(void *)t[0], s0);
    _mm256_storeu_si256((__m256i *)(void *)t[1], s1);
    _mm256_storeu_si256((__m256i *)(void *)t[2], s2);
    for (int c = 0; c < 3; ++c)
        a[c] += t[c][0] + t[c][1] + t[c][2] + t[c][3];
    return u;
}
#undef RGB8
#undef RGB8_TERM
#elif QIBL_CONFIG_SIMD == QIBL_SIMD_NEON
/* NEON twin of rgb_row_avx2, two pixels per step: (m sig) shifted by 16 - (r - E) in one vshlq_u64
 * (m sig < 2^40: the left shift is exact, and the right one floors as the scalar (m sig 2^16) >> k) */
static uint32_t rgb_row_neon(const uint8_t *q, uint32_t n, uint32_t sig, uint32_t r, uint64_t a[3])
{
    const uint32x2_t ff = vdup_n_u32(0xFFu);
    uint64x2_t s0 = vdupq_n_u64(0u), s1 = s0, s2 = s0;
    uint32_t u = 0u;
    for (; u + 2u <= n; u += 2u, q += 8) {
        const uint32x2_t px = vreinterpret_u32_u8(vld1_u8(q));
        const uint32x2_t e = vshr_n_u32(px, 24);
        /* 16 - min(r - E, 80) (r >= every E here): 16 - 80 = -64 already gives 0 */
        const uint32x2_t k = vmin_u32(vsub_u32(vdup_n_u32(r), e), vdup_n_u32(80u));
        const int64x2_t cnt = vsubq_s64(vdupq_n_s64(16), vreinterpretq_s64_u64(vmovl_u32(k)));
        const uint64x2_t black = rgbe2_black(e);
        s0 = vaddq_u64(s0, vbicq_u64(vshlq_u64(vmull_n_u32(vand_u32(px, ff), sig), cnt), black));
        s1 = vaddq_u64(s1, vbicq_u64(vshlq_u64(vmull_n_u32(vand_u32(vshr_n_u32(px, 8), ff), sig), cnt), black));
        s2 = vaddq_u64(s2, vbicq_u64(vshlq_u64(vmull_n_u32(vand_u32(vshr_n_u32(px, 16), ff), sig), cnt), black));
    }
    a[0] += vgetq_lane_u64(s0, 0) + vgetq_lane_u64(s0, 1);
    a[1] += vgetq_lane_u64(s1, 0) + vgetq_lane_u64(s1, 1);
    a[2] += vgetq_lane_u64(s2, 0) + vgetq_lane_u64(s2, 1);
    return u;
}
#endif

/* Per-channel energy sums of a region in SAT units: one read of its pixels. */
static void region_rgb(const qibl_lightprobe_t *lp, rect r, uint64_t out[3])
{
    uint64_t a0 = 0u, a1 = 0u, a2 = 0u;
    uint8_t sh[256];
    uint32_t sh_r0 = 0u;
    const size_t pb = pixel_bytes(lp->format);
    for (uint32_t v = r.v0; v < r.v1; ++v) {
        const uint8_t *q = lp->pixels + (size_t)v * lp->stride + (size_t)r.u0 * pb;
        const uint32_t sig = lp->row_sig[v];
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2 || QIBL_CONFIG_SIMD == QIBL_SIMD_SSE2
        /* A region's rows are short runs a page apart, which the hardware prefetchers do not
         * follow: ask for the run two rows below (a hint: no fault, no change to any byte).
         * `qibl bench lights`: the cut stage of median cut 64 about a quarter faster. */
        if (v + 2u < r.v1) {
            const uint8_t *n2 = q + 2u * lp->stride; /* only addresses inside the run */
            const size_t len = (size_t)(r.u1 - r.u0) * pb;
            for (size_t o = 0; o < len; o += 64u)
                _mm_prefetch((const char *)(const void *)(n2 + o), _MM_HINT_T0);
            _mm_prefetch((const char *)(const void *)(n2 + len - 1u), _MM_HINT_T0);
        }
#endif
        const int32_t s0 = rshift(lp, v) + 16; /* channels on the luminance scale: m 2^16 */
        if (lp->format == QIBL_LIGHTPROBE_RGBE && s0 - 16 - 136 + lp->emax <= 0) {
            /* x_c = m_c (2^16 sig) >> r with the luminance's r = r0 - E >= 0; 2^16 sig is formed
             * once per row, so each channel is one product (< 2^56) and one shift */
            if ((uint32_t)(136 + 16 - s0) != sh_r0)
                rgbe_shifts(sh_r0 = (uint32_t)(136 + 16 - s0), sh);
            const uint64_t sig16 = (uint64_t)sig << 16;
            uint32_t u = r.u0;
#if LP_VEC
            uint64_t t[3] = {a0, a1, a2};
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
            const uint32_t done = rgb_row_avx2(q, r.u1 - r.u0, sig, sh_r0, t);
#else
            const uint32_t done = rgb_row_neon(q, r.u1 - r.u0, sig, sh_r0, t);
#endif
            a0 = t[0], a1 = t[1], a2 = t[2];
            u += done, q += 4u * (size_t)done;
#endif
            for (; u < r.u1; ++u, q += 4) {
                uint32_t k = sh[q[3]];
                a0 += qibl_shr_u64(mul_m_sig16(q[0], sig, sig16), k);
                a1 += qibl_shr_u64(mul_m_sig16(q[1], sig, sig16), k);
                a2 += qibl_shr_u64(mul_m_sig16(q[2], sig, sig16), k);
            }
        } else {
            for (uint32_t u = r.u0; u < r.u1; ++u, q += pb) {
                pixel px;
                (void)decode(lp->format, q, lp->frac_bits, &px);
                u128 y;
                mul64(px.m[0], sig, &y);
                a0 += shift128_to64(&y, px.eps + s0);
                mul64(px.m[1], sig, &y);
                a1 += shift128_to64(&y, px.eps + s0);
                mul64(px.m[2], sig, &y);
                a2 += shift128_to64(&y, px.eps + s0);
            }
        }
    }
    out[0] = a0, out[1] = a1, out[2] = a2;
}

/* heap sort of the lights by energy, brightest first (ties: smaller v0, then u0) */
static void sort_lights(qibl_lightprobe_light_t *L, uint32_t n)
{
    for (uint32_t i = n / 2u; i-- > 0u;)
        sift_down(L, n, i, 1);
    for (uint32_t end = n; end > 1u; --end) {
        swap_lights(&L[0], &L[end - 1u]);
        sift_down(L, end - 1u, 0u, 1);
    }
}

qibl_status_t qibl_lightprobe_lights(const qibl_lightprobe_t *lp, const qibl_lightprobe_opts_t *opts,
                                     qibl_lightprobe_light_t *lights, uint32_t max_lights,
                                     qibl_lightprobe_result_t *result)
{
    QIBLI_DISPATCH(qibl_lightprobe_lights, (lp, opts, lights, max_lights, result));
    if (lp == 0 || lights == 0 || result == 0)
        return QIBL_E_NULL_POINTER;
    qibl_lightprobe_opts_t o = {QIBL_LIGHTPROBE_MEDIANCUT, QIBL_LIGHTPROBE_PRIORITY_DEFAULT,
                                QIBL_LIGHTPROBE_PLACE_CENTROID};
    if (opts) {
        o.method = opts->method;
        o.priority = opts->priority;
        o.place = opts->place;
    }
    if ((unsigned)o.method >= QIBL_LIGHTPROBE_METHOD_COUNT || (unsigned)o.priority >= QIBL_LIGHTPROBE_PRIORITY_COUNT ||
        (unsigned)o.place >= QIBL_LIGHTPROBE_PLACE_COUNT)
        return QIBL_E_PROBE_METHOD;
    qibl_lightprobe_priority_t pr = o.priority;
    if (o.method == QIBL_LIGHTPROBE_MEDIANCUT) {
        if (pr != QIBL_LIGHTPROBE_PRIORITY_DEFAULT && pr != QIBL_LIGHTPROBE_PRIORITY_LEVELS)
            return QIBL_E_PROBE_METHOD; /* a priority makes it ADAPTIVE: say so */
        pr = QIBL_LIGHTPROBE_PRIORITY_LEVELS;
    } else if (pr == QIBL_LIGHTPROBE_PRIORITY_DEFAULT) {
        pr = o.method == QIBL_LIGHTPROBE_VARMIN ? QIBL_LIGHTPROBE_PRIORITY_VARIANCE
                                                : QIBL_LIGHTPROBE_PRIORITY_ENERGY_SIZE;
    }
    const int varmin = o.method == QIBL_LIGHTPROBE_VARMIN;
    if (max_lights == 0u || (pr == QIBL_LIGHTPROBE_PRIORITY_LEVELS && (max_lights & (max_lights - 1u)) != 0u))
        return QIBL_E_PROBE_COUNT;
    if ((varmin || pr == QIBL_LIGHTPROBE_PRIORITY_VARIANCE) && lp->built_for != QIBL_LIGHTPROBE_VARMIN)
        return QIBL_E_PROBE_MISMATCH; /* the moment tables (or marginals) are missing */
    if (lp->total == 0u)
        return QIBL_E_PROBE_BLACK;

    /* No failure is possible from here on: lights[] is the working list of regions. Without a
     * SAT, the workspace's marginals are the scratch of every region look. */
    marg mm;
    const marg *mg = 0;
    if (lp->sat == 0) {
        marg_arrays(lp, &mm);
        mg = &mm;
    }
    uint32_t n = make_regions(lp, mg, varmin, pr, lights, max_lights);
    for (uint32_t i = 0; i < n; ++i) {
        const rect r = light_rect(&lights[i]);
        put_energy(&lights[i], mg ? pixel_sum(lp, r.u0, r.v0, r.u1, r.v1) : rect_energy(lp, r));
    }
    sort_lights(lights, n);

    /* Colours: X_c = A_c K with K = 2 pi^2 2^j / (W H D) in [2^62, 2^64), so that
     * rgb_c = X_c 2^-(g + 58 + j). Each light is first rounded to 31 bits with its own exponent
     * (kept in dir[0] until the directions are computed), then all to the largest exponent. */
    const uint64_t nd = qibl_mul_u32_u64(lp->width * lp->height, lp->energy_div);
    const unsigned j = qibli_bitlen_u64(nd);
    u128 num = {0u, TWO_PI_SQ_Q58};
    shl128(&num, j);
    const uint64_t K = div128(&num, nd, 0);
    int32_t smax = INT32_MIN;
    for (uint32_t i = 0; i < n; ++i) {
        uint64_t a[3];
        region_rgb(lp, light_rect(&lights[i]), a);
        u128 x[3];
        unsigned L = 0u;
        for (int c = 0; c < 3; ++c) {
            mul64(a[c], K, &x[c]);
            unsigned l = bitlen128(&x[c]);
            if (l > L)
                L = l;
        }
        int32_t s = (int32_t)L - 31;
        for (int pass = 0; pass < 2; ++pass) {
            uint64_t m[3], top = 0u;
            for (int c = 0; c < 3; ++c) {
                m[c] = s > 0 ? (shr128_lo(&x[c], (unsigned)s - 1u) + 1u) >> 1 : qibli_shl_u64(x[c].lo, (unsigned)-s);
                if (m[c] > top)
                    top = m[c];
            }
            if (top >> 31) { /* rounded up to 2^31 */
                ++s;
                continue;
            }
            for (int c = 0; c < 3; ++c)
                lights[i].rgb[c] = (int32_t)m[c];
            break;
        }
        lights[i].dir[0] = s; /* the energy stays in dir[1..2] (put_region) */
        if (s > smax)
            smax = s;
    }
    for (uint32_t i = 0; i < n; ++i) {
        uint32_t d = (uint32_t)(smax - lights[i].dir[0]);
        for (int c = 0; c < 3; ++c) {
            uint32_t m = (uint32_t)lights[i].rgb[c];
            lights[i].rgb[c] = d == 0u ? (int32_t)m : d >= 32u ? 0 : (int32_t)((m + (1u << (d - 1u))) >> d);
        }
        direction(lp, mg, light_rect(&lights[i]), light_energy(&lights[i]), o.place, lights[i].dir);
    }
    result->count = n;
    result->rgb_exp = smax - (lp->gshift + 58 + (int32_t)j);
    return QIBL_OK;
}

#else
typedef int qibl_lightprobe_disabled_t; /* ISO C forbids an empty translation unit */
#endif /* QIBL_USE_LIGHTPROBE */
