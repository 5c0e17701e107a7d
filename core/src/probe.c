/*
 * probe.c - SH projection of a lat-long probe, row by row, into exact wide accumulators.
 *
 * Invariants: integer only, no heap, no state; products through qibl_mul_*, shifts of signed values
 * through fixed.h, no library calls on Cortex-M0; any row order gives the same bits.
 *
 * Per row v (width W, 3 channels):
 *   1. T_v = max over the row's channels of (bitlen(m) + eps) (lightprobe_internal.h decoding; for
 *      sRGBE the values are 510 P; for RGBE the bound emax - 128 from the lit exponents, see
 *      row_scan). Ranges over the formats: RGBE [-127, 127], sRGBE [-118, 137], LINEAR_I32
 *      [-127, 159], LINEAR_F32 [-148, 128]; so s_v = T_v - 27 is in [-175, 132].
 *   2. x = round(m 2^(eps - s_v)) <= 2^27 (an exact left shift or a rounded right shift).
 *   3. S_0 = sum x, S_mc = sum x cos(m phi_u), S_ms = sum x sin(m phi_u), m = 1..4, trig Q2.30
 *      (|t| <= 2^30). Folded path (W % 4 == 0): the four columns u + k W/4 fold into
 *      A = x0+x1+x2+x3 <= 2^29, B = x0-x1+x2-x3, C = x0-x2, D = x1-x3 (|.| <= 2^28), since
 *      e^(im(phi + k pi/2)) = i^(mk) e^(im phi); then quarter column u and its mirror q-1-u
 *      (phi' = pi/2 - phi) combine, e.g. S_1c += (C - D') cos phi - (D - C') sin phi and
 *      S_4s += (A - A') sin 4 phi (every m written out in row_sums_folded), each update <= 2^60, so
 *      chunks of 7 pairs stay below 2^63 in int64; direct path: products <= 2^57, chunks of 63.
 *      Chunks are added into 128-bit sums; |S| <= W 2^57 <= 2^72.
 *   4. Row factor f_l|m| = Y_l|m|(theta_v, phi = 0) sin theta_v = f 2^-(31 + kap_v), |f| < 2^32
 *      (|Y| < 1.1, sin from the 32-bit row weight), kap_v in [-1, 15].
 *   5. S is rounded to |S'| <= 2^62 (shift r = max(0, bitlen - 62) <= 11), and S' f (< 2^94) is
 *      added at bit e = s_v - 61 - kap_v + r in [-251, 83] of the accumulator. Each term is below
 *      2^(83 + 94) = 2^177, H <= 2^15 rows below 2^192: with the sign, bits -256 .. 223 (15 limbs
 *      of 32, two's complement) hold every sum exactly.
 * finish: value = acc 2^-256 (2 pi^2 / (W H D)) sigma_l A_l, each constant a 32-bit mantissa
 * (relative error 2^-31 each), the accumulator's top 63 bits, one rounding to the shared output
 * exponent.
 */
#include "qibl/probe.h"

#if QIBL_USE_PROBE

#include "lightprobe_internal.h"
#include "qibli.h"

#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
#include <immintrin.h>
/* the trig table planar (trig[i tc + u]): the vector loops load 8 columns of one entry; the scalar
 * builds keep it by column (trig[8 u + i]), fewer live pointers on small cores */
#define TRIG_PLANAR 1
#define TRIG(ps, tc, i, u) ((ps)->trig[(size_t)(i) * (tc) + (u)])
#else
#define TRIG_PLANAR 0
#define TRIG(ps, tc, i, u) ((ps)->trig[8u * (size_t)(u) + (i)])
#endif

/* the folded sums are written once and inlined per number of orders (a constant there) */
#if (defined(__GNUC__) || defined(__clang__)) && !defined(__OPTIMIZE_SIZE__)
#define FOLD_INLINE __attribute__((always_inline)) inline
#else
#define FOLD_INLINE inline
#endif

#define LIMBS QIBL_PROBE_ACC_LIMBS
#define ACC_LSB (-256)  /* the accumulators' bit 0 is 2^-256 */
#define XBITS 27        /* channel integers <= 2^27 */
#define CHUNK_PAIR 7u   /* folded column pairs per int64 chunk: 7 updates <= 2^60 < 2^63 */
#define CHUNK 63u       /* direct columns per int64 chunk: 63 products <= 2^57 < 2^63 */
#define TWO_PI_SQ_Q58 5689439577989151081u /* round(2 pi^2 2^58), as lightprobe.c */

/* sigma_l in Q2.30 for N = bands (rows) and l (columns) (1 + cos(pi l / N)) / 2 and
 * sin(pi l / N) / (pi l / N), rounded from double */
static const int32_t win_hann[5][5] = {
    {1073741824, 0, 0, 0, 0},
    {1073741824, 536870912, 0, 0, 0},
    {1073741824, 805306368, 268435456, 0, 0},
    {1073741824, 916495974, 536870912, 157245850, 0},
    {1073741824, 971208604, 702773148, 370968676, 102533220},
};
static const int32_t win_lanczos[5][5] = {
    {1073741824, 0, 0, 0, 0},
    {1073741824, 683565276, 0, 0, 0},
    {1073741824, 887977341, 443988670, 0, 0},
    {1073741824, 966707283, 683565276, 322235761, 0},
    {1073741824, 1004473970, 812636512, 541757675, 251118492},
};
/* A_l in Q3.29: pi, 2 pi / 3, pi / 4, 0, -pi / 24 */
static const int32_t irr_a[5] = {1686629713, 1124419809, 421657428, 0, -70276238};

/* ---- small helpers ---------------------------------------------------------------------------- */


typedef struct {
    uint64_t hi, lo; /* two's complement 128-bit */
} s128;


/* round(x / 2^n) half up for n in 0..64 (0 for n = 64 unless x >= 2^63) */
static inline uint64_t rshr_u64(uint64_t x, unsigned n)
{
    if (n == 0u)
        return x;
    if (n > 64u)
        return 0u;
    uint64_t h = qibl_shr_u64(x, n - 1u); /* n - 1 <= 63 */
    return (h >> 1) + (h & 1u);
}

static inline void s128_add64(s128 *a, int64_t v)
{
    uint64_t u = (uint64_t)v;
    uint64_t lo = a->lo + u;
    a->hi += (lo < u) + (v < 0 ? ~(uint64_t)0 : 0u);
    a->lo = lo;
}

/* |x| as (hi, lo) and the sign */
static inline int s128_abs(const s128 *x, uint64_t *hi, uint64_t *lo)
{
    if (x->hi >> 63) {
        *lo = 0u - x->lo;
        *hi = ~x->hi + (x->lo == 0u);
        return 1;
    }
    *hi = x->hi, *lo = x->lo;
    return 0;
}

/* a * b as three 32-bit limbs (a < 2^64, b < 2^32: < 2^96) */
static void mul_64_32(uint64_t a, uint32_t b, uint32_t out[3])
{
    uint64_t lo = qibl_mul_u32_u64((uint32_t)a, b);
    uint64_t hi = qibl_mul_u32_u64((uint32_t)(a >> 32), b);
    uint64_t mid = (lo >> 32) + (uint32_t)hi;
    out[0] = (uint32_t)lo;
    out[1] = (uint32_t)mid;
    out[2] = (uint32_t)((hi >> 32) + (mid >> 32));
}

/* acc +=/-= mag (3 limbs) 2^e, e in 0..(32 LIMBS - 97): exact two's complement over LIMBS limbs */
static void kadd(uint32_t *acc, const uint32_t mag[3], unsigned e, int neg)
{
    unsigned q = e >> 5, b = e & 31u;
#if QIBL_CONFIG_NATIVE_SHIFT64 && QIBL_CONFIG_NATIVE_DIV64
    {
        /* the same sum in two 64-bit words on 64-bit hosts (NATIVE_DIV64 marks them; 64-bit
         * shifts inline there): mag 2^b < 2^127 */
        const uint64_t m01 = (uint64_t)mag[0] | (uint64_t)mag[1] << 32;
        const uint64_t w0 = m01 << b, w1 = (uint64_t)mag[2] << b | (b ? m01 >> (64u - b) : 0u);
        uint32_t *a = acc + q;
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2 && (defined(__GNUC__) || defined(__clang__))
        uint64_t a0, a1; /* little-endian x86: limbs q, q + 1 are one 64-bit word */
        __builtin_memcpy(&a0, a, 8), __builtin_memcpy(&a1, a + 2, 8);
#else
        const uint64_t a0 = (uint64_t)a[0] | (uint64_t)a[1] << 32, a1 = (uint64_t)a[2] | (uint64_t)a[3] << 32;
#endif
        uint64_t r0, r1;
        uint32_t carry;
        if (!neg) {
            r0 = a0 + w0, r1 = a1 + w1;
            carry = (uint32_t)(r1 < w1);
            const uint32_t c0 = (uint32_t)(r0 < w0);
            r1 += c0;
            carry |= (uint32_t)(r1 < c0);
        } else {
            r0 = a0 - w0, r1 = a1 - w1;
            carry = (uint32_t)(a1 < w1); /* borrow */
            const uint32_t c0 = (uint32_t)(a0 < w0);
            carry |= (uint32_t)(r1 < c0);
            r1 -= c0;
        }
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2 && (defined(__GNUC__) || defined(__clang__))
        __builtin_memcpy(a, &r0, 8), __builtin_memcpy(a + 2, &r1, 8);
#else
        a[0] = (uint32_t)r0, a[1] = (uint32_t)(r0 >> 32), a[2] = (uint32_t)r1, a[3] = (uint32_t)(r1 >> 32);
#endif
        if (!neg)
            for (unsigned i = q + 4u; carry != 0u && i < LIMBS; ++i)
                carry = ++acc[i] == 0u;
        else
            for (unsigned i = q + 4u; carry != 0u && i < LIMBS; ++i)
                carry = acc[i]-- == 0u;
    }
#else
    uint32_t t[4];
    t[0] = mag[0] << b;
    t[1] = b ? (mag[1] << b) | (mag[0] >> (32u - b)) : mag[1];
    t[2] = b ? (mag[2] << b) | (mag[1] >> (32u - b)) : mag[2];
    t[3] = b ? mag[2] >> (32u - b) : 0u;
    /* q + 3 < LIMBS (e <= 32 LIMBS - 97): the four limbs unrolled, then the carry (borrow) ripples */
    uint32_t *a = acc + q;
    uint32_t carry = 0u;
    if (!neg) {
        for (unsigned i = 0; i < 4u; ++i) {
            uint64_t s = (uint64_t)a[i] + t[i] + carry;
            a[i] = (uint32_t)s;
            carry = (uint32_t)(s >> 32);
        }
        for (unsigned i = q + 4u; carry != 0u && i < LIMBS; ++i)
            carry = ++acc[i] == 0u;
    } else {
        for (unsigned i = 0; i < 4u; ++i) {
            uint64_t d = (uint64_t)a[i] - t[i] - carry;
            a[i] = (uint32_t)d;
            carry = (uint32_t)(d >> 63); /* borrow */
        }
        for (unsigned i = q + 4u; carry != 0u && i < LIMBS; ++i)
            carry = acc[i]-- == 0u;
    }
#endif
}

/* sin(pi n / d) in Q2.30 for any n >= 0, 0 < d < 2^31 (within 1 LSB) */
static int32_t sin_pi_q30(uint64_t n, uint64_t d)
{
    uint64_t r = 0u; /* (written by the division: 2d > 0) */
    (void)qibl_udiv_u64(n, 2u * d, &r);
    int neg = r >= d;
    if (neg)
        r -= d;
    if (r == 0u)
        return 0;
    uint32_t mant;
    int32_t kap;
    qibli_lightprobe_sin_frac(r, d, &mant, &kap); /* kap >= -1 */
    int32_t v = (int32_t)rshr_u64(mant, (unsigned)(2 + kap));
    return neg ? -v : v;
}

static int32_t cos_pi_q30(uint64_t n, uint64_t d)
{
    return sin_pi_q30(2u * n + d, 2u * d); /* cos a = sin(a + pi / 2) */
}

#ifndef __OPTIMIZE_SIZE__
/* sin_pi_q30(n, w) from sn[j] = sin_pi_q30(j, w), j = 0..w/2: the same reduction modulo 2w, the
 * sign of the second half turn, and the reflection j -> w - j that sin_frac makes itself */
static int32_t sin_table(const int32_t *sn, uint32_t n, uint32_t w)
{
    while (n >= 2u * w) /* n < 9 w here: no division (a library call on Cortex-M0) */
        n -= 2u * w;
    const int neg = n >= w;
    if (neg)
        n -= w;
    if (2u * n > w)
        n = w - n;
    return neg ? -sn[n] : sn[n];
}
#endif

/* ---- workspace -------------------------------------------------------------------------------- */

static int dims_ok(uint32_t w, uint32_t h)
{
    return w >= 1u && h >= 1u && w <= QIBL_LIGHTPROBE_MAX_DIM && h <= QIBL_LIGHTPROBE_MAX_DIM;
}

static uint32_t trig_cols(uint32_t w)
{
    return (w & 3u) == 0u ? w / 4u : w;
}

static uint64_t ws_bytes(uint32_t w, uint32_t h)
{
    if (!dims_ok(w, h) || qibl_mul_u32_u64(w, h) > QIBL_LIGHTPROBE_MAX_PIXELS)
        return 0u;
    return 4u * 3u * 25u * LIMBS + 32u * (uint64_t)trig_cols(w) + qibl_mul_u32_u64(12u, w) + ((h + 31u) / 32u) * 4u + 4u;
}

size_t qibl_probe_sh_workspace_size(uint32_t width, uint32_t height)
{
    uint64_t n = ws_bytes(width, height);
    return n > (uint64_t)SIZE_MAX ? 0u : (size_t)n;
}

qibl_status_t qibl_probe_sh_begin(qibl_probe_sh_t *ps, uint32_t width, uint32_t height,
                                  qibl_lightprobe_format_t format, int32_t frac_bits, int bands, void *workspace,
                                  size_t workspace_size)
{
    QIBLI_DISPATCH512(qibl_probe_sh_begin, (ps, width, height, format, frac_bits, bands, workspace, workspace_size));
    if (ps == 0 || workspace == 0)
        return QIBL_E_NULL_POINTER;
    if (bands < 1 || bands > QIBL_SH_MAX_BANDS)
        return QIBL_E_BAD_BANDS;
    if (!dims_ok(width, height))
        return QIBL_E_PROBE_SIZE;
    if (qibl_mul_u32_u64(width, height) > QIBL_LIGHTPROBE_MAX_PIXELS)
        return QIBL_E_PROBE_OVERFLOW;
    if ((unsigned)format >= QIBL_LIGHTPROBE_FORMAT_COUNT || frac_bits < -128 || frac_bits > 128)
        return QIBL_E_PROBE_FORMAT;
    uint64_t need = ws_bytes(width, height);
    if (need > (uint64_t)SIZE_MAX)
        return QIBL_E_PROBE_OVERFLOW;
    if ((uint64_t)workspace_size < need)
        return QIBL_E_WORKSPACE;
    uint8_t *ws = (uint8_t *)workspace;
    ws += (4u - ((uintptr_t)ws & 3u)) & 3u;
    const uint32_t tc = trig_cols(width);
    ps->width = width, ps->height = height, ps->rows = 0u;
    ps->format = format, ps->frac_bits = frac_bits, ps->bands = bands;
    ps->acc = (uint32_t *)(void *)ws;
    ps->trig = (int32_t *)(void *)(ps->acc + 3u * 25u * LIMBS);
    ps->x = (uint32_t *)(void *)(ps->trig + 8u * (size_t)tc);
    ps->seen = (uint8_t *)(void *)(ps->x + 3u * (size_t)width);
    for (uint32_t i = 0; i < 3u * 25u * LIMBS; ++i)
        ps->acc[i] = 0u;
    for (uint32_t i = 0; i < (height + 7u) / 8u; ++i)
        ps->seen[i] = 0u;
    /* phi_u = pi (2u + 1) / W; m phi_u = pi m (2u + 1) / W */
#ifndef __OPTIMIZE_SIZE__ /* size-optimised builds keep the direct loop below (one less path) */
    if ((width & 1u) == 0u) {
        /* sin_pi_q30 depends on n / W only (sin_frac: a floor of pi n / d, and the reflection
         * n -> d - n made inside it), so every entry is +-sin_pi_q30(j, W) for one j <= W/2, and
         * cos_pi_q30(n, W) = sin_pi_q30(2n + W, 2W) is sin_pi_q30(n + W/2, W) for even W: W/2 + 1
         * evaluations instead of 8 per column, into the row buffer (unused until the first row) */
        int32_t *sn = (int32_t *)(void *)ps->x;
        for (uint32_t j = 0; j <= width / 2u; ++j)
            sn[j] = sin_pi_q30(j, width);
        for (uint32_t u = 0; u < tc; ++u) {
            for (uint32_t m = 1; m <= 4u; ++m) {
                const uint32_t n = m * (2u * u + 1u); /* < 8 W <= 2^18 */
                TRIG(ps, tc, 2u * (m - 1u), u) = sin_table(sn, n + width / 2u, width);
                TRIG(ps, tc, 2u * (m - 1u) + 1u, u) = sin_table(sn, n, width);
            }
        }
        return QIBL_OK;
    }
#endif
    for (uint32_t u = 0; u < tc; ++u) {
        for (uint32_t m = 1; m <= 4u; ++m) {
            uint64_t n = qibl_mul_u32_u64(m, 2u * u + 1u);
            TRIG(ps, tc, 2u * (m - 1u), u) = cos_pi_q30(n, width);
            TRIG(ps, tc, 2u * (m - 1u) + 1u, u) = sin_pi_q30(n, width);
        }
    }
    return QIBL_OK;
}

/* ---- one row ---------------------------------------------------------------------------------- */

/* Pass 1 over a row: BAD flags and T (INT32_MIN for a black row). */
static unsigned row_scan(const qibl_probe_sh_t *ps, const uint8_t *row, int32_t *t_out)
{
    unsigned bad = 0u;
    int32_t t = INT32_MIN;
    if (ps->format == QIBL_LIGHTPROBE_RGBE) {
        /* T = emax - 128 (emax the largest exponent of a lit pixel): m < 2^8 puts every channel below
         * 2^T, and Radiance's encoders store the largest channel in 128..255, so the bound is tight
         * for them (otherwise up to 7 bits of the row's precision are given up). Branch-free, so
         * compilers vectorise it. */
        uint8_t emax = 0u;
        uint32_t u = 0;
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
        /* 8 pixels (little-endian words) at once: exponent where R, G or B is non-zero, running max */
        const __m256i rgb = _mm256_set1_epi32(0x00FFFFFF);
        __m256i em = _mm256_setzero_si256();
        for (; u + 8u <= ps->width; u += 8u) {
            const __m256i p = _mm256_loadu_si256((const __m256i *)(const void *)(row + 4u * (size_t)u));
            const __m256i dark = _mm256_cmpeq_epi32(_mm256_and_si256(p, rgb), _mm256_setzero_si256());
            em = _mm256_max_epu32(em, _mm256_andnot_si256(dark, _mm256_srli_epi32(p, 24)));
        }
        uint32_t lanes[8];
        _mm256_storeu_si256((__m256i *)(void *)lanes, em);
        for (int i = 0; i < 8; ++i)
            emax = (uint8_t)lanes[i] > emax ? (uint8_t)lanes[i] : emax;
#endif
        for (; u < ps->width; ++u) {
            const uint8_t *q = row + 4u * (size_t)u;
            uint8_t lit = (uint8_t)(q[0] | q[1] | q[2]) != 0u ? 0xFFu : 0u;
            uint8_t e = (uint8_t)(q[3] & lit);
            emax = e > emax ? e : emax;
        }
        if (emax)
            t = (int32_t)emax - 128;
    } else {
        const size_t pb = qibli_lightprobe_pixel_bytes(ps->format);
        for (uint32_t u = 0; u < ps->width; ++u) {
            uint64_t m[3];
            int32_t eps;
            bad |= qibli_lightprobe_decode(ps->format, row + pb * u, ps->frac_bits, m, &eps);
            uint64_t mx = m[0] > m[1] ? m[0] : m[1];
            mx = mx > m[2] ? mx : m[2];
            if (mx) {
                int32_t b = (int32_t)qibli_bitlen_u64(mx) + eps;
                t = b > t ? b : t;
            }
        }
    }
    *t_out = t;
    return bad;
}

/* round(m 2^k) for k <= 27 - bitlen(m) (so the result is <= 2^27). A zero channel may come with
 * any k (an sRGBE 128 with exponent 255 in a dim row): k is capped, as 0 << 27 is 0 too. */
static inline uint32_t quant(uint64_t m, int32_t k)
{
    if (k >= 0)
        return (uint32_t)qibli_shl_u64(m, (unsigned)(k > 27 ? 27 : k));
    return (uint32_t)rshr_u64(m, (unsigned)(k < -65 ? 65 : -k));
}

/* Pass 2: the channel integers of the row into ps->x (planar), scale 2^(T - 27). */
static void row_convert(const qibl_probe_sh_t *ps, const uint8_t *row, int32_t t)
{
    const uint32_t w = ps->width;
    uint32_t *x0 = ps->x, *x1 = x0 + w, *x2 = x1 + w;
    if (ps->format == QIBL_LIGHTPROBE_RGBE) {
        /* x = round(m 2^k), k = E + k0 <= 19: with d = 20 - k >= 1, x = ((m 2^20 >> (d - 1)) + 1) >> 1,
         * branch-free from a per-row table of d - 1 (31 for E = 0 and far below: m 2^20 < 2^28
         * then gives 0) */
        const int32_t k0 = XBITS - 136 - t;
        uint8_t sh[256];
        for (int32_t e = 0; e < 256; ++e) {
            int32_t d1 = 19 - (e + k0);
            /* d1 < 0 only for exponents above the row's largest lit one, i.e. unlit pixels (all
             * mantissas 0): a shift by (uint8_t)d1 would be undefined, 31 gives the same 0 */
            sh[e] = (uint8_t)(e == 0 || d1 > 31 || d1 < 0 ? 31 : d1);
        }
        uint32_t u = 0;
#if defined(QIBLI_PROBE_AVX512)
        {
            /* 16 pixels at once, the same integers as below: each channel byte moved to bits 24..31
             * by one byte shuffle, m 2^24 >> (k + 4) = m 2^20 >> k, E = 0 by the masked shift */
            const __m512i c23 = _mm512_set1_epi32(23 - k0), one = _mm512_set1_epi32(1);
            const __m512i top = _mm512_set1_epi32((int)0xFF000000u);
            /* byte 3 of dword j (of each 128-bit lane) from byte 4 j + c, bytes 0..2 zero (0x80) */
#define SHUF(c) _mm512_broadcast_i32x4(_mm_setr_epi32((int)(0x00808080u | (0u + (c)) << 24), \
                                                       (int)(0x00808080u | (4u + (c)) << 24), \
                                                       (int)(0x00808080u | (8u + (c)) << 24), \
                                                       (int)(0x00808080u | (12u + (c)) << 24)))
            const __m512i b0 = SHUF(0u), b1 = SHUF(1u), b2 = SHUF(2u);
#undef SHUF
            for (; u + 16u <= w; u += 16u) {
                const __m512i p = _mm512_loadu_si512((const void *)(row + 4u * (size_t)u));
                const __mmask16 lit = _mm512_test_epi32_mask(p, top);
                const __m512i k = _mm512_sub_epi32(c23, _mm512_srli_epi32(p, 24));
                _mm512_storeu_si512((void *)(x0 + u), _mm512_srli_epi32(_mm512_add_epi32(
                    _mm512_maskz_srlv_epi32(lit, _mm512_shuffle_epi8(p, b0), k), one), 1));
                _mm512_storeu_si512((void *)(x1 + u), _mm512_srli_epi32(_mm512_add_epi32(
                    _mm512_maskz_srlv_epi32(lit, _mm512_shuffle_epi8(p, b1), k), one), 1));
                _mm512_storeu_si512((void *)(x2 + u), _mm512_srli_epi32(_mm512_add_epi32(
                    _mm512_maskz_srlv_epi32(lit, _mm512_shuffle_epi8(p, b2), k), one), 1));
            }
        }
#endif
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
        /* 8 pixels at once, the same integers: the shift 19 - E - k0 straight from the exponent, as
         * vpsrlvd gives 0 for a count >= 32 (the table's 31 gives 0 too: m 2^20 < 2^28 and unlit
         * pixels have m = 0), E = 0 masked to 0; a pixel is a little-endian word (R low) on x86 */
        const __m256i c19 = _mm256_set1_epi32(19 - k0), ff = _mm256_set1_epi32(0xFF), one = _mm256_set1_epi32(1);
        for (; u + 8u <= w; u += 8u) {
            const __m256i p = _mm256_loadu_si256((const __m256i *)(const void *)(row + 4u * (size_t)u));
            const __m256i e = _mm256_srli_epi32(p, 24);
            const __m256i k = _mm256_sub_epi32(c19, e);
            const __m256i z = _mm256_cmpeq_epi32(e, _mm256_setzero_si256());
            const __m256i m0 = _mm256_slli_epi32(_mm256_and_si256(p, ff), 20);
            const __m256i m1 = _mm256_slli_epi32(_mm256_and_si256(_mm256_srli_epi32(p, 8), ff), 20);
            const __m256i m2 = _mm256_slli_epi32(_mm256_and_si256(_mm256_srli_epi32(p, 16), ff), 20);
            _mm256_storeu_si256((__m256i *)(void *)(x0 + u),
                                _mm256_andnot_si256(z, _mm256_srli_epi32(_mm256_add_epi32(_mm256_srlv_epi32(m0, k), one), 1)));
            _mm256_storeu_si256((__m256i *)(void *)(x1 + u),
                                _mm256_andnot_si256(z, _mm256_srli_epi32(_mm256_add_epi32(_mm256_srlv_epi32(m1, k), one), 1)));
            _mm256_storeu_si256((__m256i *)(void *)(x2 + u),
                                _mm256_andnot_si256(z, _mm256_srli_epi32(_mm256_add_epi32(_mm256_srlv_epi32(m2, k), one), 1)));
        }
#endif
        for (; u < w; ++u) {
            const uint8_t *q = row + 4u * (size_t)u;
            const unsigned k = sh[q[3]];
            x0[u] = ((((uint32_t)q[0] << 20) >> k) + 1u) >> 1;
            x1[u] = ((((uint32_t)q[1] << 20) >> k) + 1u) >> 1;
            x2[u] = ((((uint32_t)q[2] << 20) >> k) + 1u) >> 1;
        }
    } else {
        const size_t pb = qibli_lightprobe_pixel_bytes(ps->format);
        for (uint32_t u = 0; u < w; ++u) {
            uint64_t m[3];
            int32_t eps;
            (void)qibli_lightprobe_decode(ps->format, row + pb * u, ps->frac_bits, m, &eps);
            int32_t k = eps + XBITS - t;
            x0[u] = quant(m[0], k), x1[u] = quant(m[1], k), x2[u] = quant(m[2], k);
        }
    }
}

#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
/* The vector fold, written once for both widths: pv_* are 8 int32 lanes (AVX2) or, in the avx512
 * copy, 16 (AVX-512); the same operations lane for lane, so the same exact integers. */
#if defined(QIBLI_PROBE_AVX512)
typedef __m512i pv;
#define PV_LANES 16u
#define PV_LD(p) _mm512_loadu_si512((const void *)(p))
#define PV_ST(p, v) _mm512_storeu_si512((void *)(p), (v))
#define PV_ZERO() _mm512_setzero_si512()
#define PV_ADD32 _mm512_add_epi32
#define PV_SUB32 _mm512_sub_epi32
#define PV_ADD64 _mm512_add_epi64
#define PV_SUB64 _mm512_sub_epi64
#define PV_AND _mm512_and_si512
#define PV_SRL64 _mm512_srli_epi64
#define PV_MUL32 _mm512_mul_epi32
#define PV_SET64(c) _mm512_set1_epi64(c)
#define PV_REVERSED() _mm512_setr_epi32(15, 14, 13, 12, 11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1, 0)
#define PV_PERMUTE(v, idx) _mm512_permutexvar_epi32((idx), (v))

/* (hi, lo) += v in each 64-bit lane: 128-bit two's complement sums, exact (mask registers) */
static inline void pv_add128(pv *hi, pv *lo, pv v)
{
    const __m512i nl = _mm512_add_epi64(*lo, v), one = _mm512_set1_epi64(1);
    const __mmask8 carry = _mm512_cmplt_epu64_mask(nl, *lo), neg = _mm512_cmplt_epi64_mask(v, _mm512_setzero_si512());
    const __m512i h = _mm512_mask_add_epi64(*hi, carry, *hi, one); /* +1 where lo wrapped */
    *hi = _mm512_mask_sub_epi64(h, neg, h, one);                     /* -1 where v < 0 */
    *lo = nl;
}
#else
typedef __m256i pv;
#define PV_LANES 8u
#define PV_LD(p) _mm256_loadu_si256((const __m256i *)(const void *)(p))
#define PV_ST(p, v) _mm256_storeu_si256((__m256i *)(void *)(p), (v))
#define PV_ZERO() _mm256_setzero_si256()
#define PV_ADD32 _mm256_add_epi32
#define PV_SUB32 _mm256_sub_epi32
#define PV_ADD64 _mm256_add_epi64
#define PV_SUB64 _mm256_sub_epi64
#define PV_AND _mm256_and_si256
#define PV_SRL64 _mm256_srli_epi64
#define PV_MUL32 _mm256_mul_epi32
#define PV_SET64(c) _mm256_set1_epi64x(c)
#define PV_REVERSED() _mm256_setr_epi32(7, 6, 5, 4, 3, 2, 1, 0)
#define PV_PERMUTE(v, idx) _mm256_permutevar8x32_epi32((v), (idx))

/* (hi, lo) += v in each 64-bit lane: 128-bit two's complement sums, exact (AVX2 has no unsigned
 * compare: both sides biased by 2^63) */
static inline void pv_add128(pv *hi, pv *lo, pv v)
{
    const __m256i sb = _mm256_set1_epi64x((long long)INT64_MIN);
    const __m256i nl = _mm256_add_epi64(*lo, v);
    const __m256i carry = _mm256_cmpgt_epi64(_mm256_xor_si256(*lo, sb), _mm256_xor_si256(nl, sb)); /* -1: lo wrapped */
    const __m256i sgn = _mm256_cmpgt_epi64(_mm256_setzero_si256(), v);                            /* -1: v < 0 */
    *hi = _mm256_add_epi64(*hi, _mm256_sub_epi64(sgn, carry));
    *lo = nl;
}
#endif

/* a t for the even and the odd int32 lanes, summed per 64-bit lane (two exact products) */
static inline pv pv_mul2(pv a, pv t)
{
    return PV_ADD64(PV_MUL32(a, t), PV_MUL32(PV_SRL64(a, 32), PV_SRL64(t, 32)));
}

/* The folded sums of row_sums_folded for pairs 0 .. L floor(half / L) - 1 (L = PV_LANES pairs per
 * step, the mirrors loaded backwards), added to s; returns the pairs done. Every product and sum is
 * exact, so the totals are the scalar loop's integers. Per 64-bit lane and step an update is at
 * most 2 2^60 (two pairs), so 3 steps stay below 2^63 before they go into the 128-bit lane sums.
 * Only the orders m <= mm (a constant where it is inlined) are summed: s[2m - 1], s[2m] stay 0 above. */
static FOLD_INLINE uint32_t folded_vec(const qibl_probe_sh_t *ps, const uint32_t *x, s128 s[9], const int mm)
{
    const uint32_t q = ps->width / 4u, half = q / 2u;
    const int32_t *tr = ps->trig;
    const pv rev = PV_REVERSED(), lo32 = PV_SET64(0xFFFFFFFFll);
    pv hi[9], lo[9];
    for (int i = 0; i < 9; ++i)
        hi[i] = lo[i] = PV_ZERO();
    uint32_t u = 0;
    while (half - u >= PV_LANES) {
        pv a[9];
        for (int i = 0; i < 9; ++i)
            a[i] = PV_ZERO();
        for (int step = 0; step < 3 && half - u >= PV_LANES; ++step, u += PV_LANES) {
            const uint32_t v = q - PV_LANES - u; /* lanes v .. v+L-1 reversed: the mirrors of u .. u+L-1 */
            const pv p0 = PV_LD(x + u), p1 = PV_LD(x + u + q), p2 = PV_LD(x + u + 2u * q), p3 = PV_LD(x + u + 3u * q);
            const pv r0 = PV_PERMUTE(PV_LD(x + v), rev), r1 = PV_PERMUTE(PV_LD(x + v + q), rev);
            const pv r2 = PV_PERMUTE(PV_LD(x + v + 2u * q), rev), r3 = PV_PERMUTE(PV_LD(x + v + 3u * q), rev);
            const pv s02 = PV_ADD32(p0, p2), s13 = PV_ADD32(p1, p3);
            const pv z02 = PV_ADD32(r0, r2), z13 = PV_ADD32(r1, r3);
            const pv A = PV_ADD32(s02, s13), B = PV_SUB32(s02, s13);
            const pv A2 = PV_ADD32(z02, z13), B2 = PV_SUB32(z02, z13);
            const pv C = PV_SUB32(p0, p2), D = PV_SUB32(p1, p3);
            const pv C2 = PV_SUB32(r0, r2), D2 = PV_SUB32(r1, r3);
            const pv E = PV_SUB32(C, D2), F = PV_SUB32(D, C2);
            const pv G = PV_ADD32(C, D2), H = PV_ADD32(D, C2);
            const pv AA = PV_ADD32(A, A2); /* <= 2^30, non-negative */
            a[0] = PV_ADD64(a[0], PV_ADD64(PV_AND(AA, lo32), PV_SRL64(AA, 32)));
            if (mm >= 1) {
                const pv t0 = PV_LD(tr + u), t1 = PV_LD(tr + q + u);
                a[1] = PV_ADD64(a[1], PV_SUB64(pv_mul2(E, t0), pv_mul2(F, t1)));
                a[2] = PV_ADD64(a[2], PV_ADD64(pv_mul2(G, t1), pv_mul2(H, t0)));
            }
            if (mm >= 2) {
                const pv t2 = PV_LD(tr + 2u * q + u), t3 = PV_LD(tr + 3u * q + u);
                a[3] = PV_ADD64(a[3], pv_mul2(PV_SUB32(B, B2), t2));
                a[4] = PV_ADD64(a[4], pv_mul2(PV_ADD32(B, B2), t3));
            }
            if (mm >= 3) {
                const pv t4 = PV_LD(tr + 4u * q + u), t5 = PV_LD(tr + 5u * q + u);
                a[5] = PV_ADD64(a[5], PV_ADD64(pv_mul2(E, t4), pv_mul2(F, t5)));
                a[6] = PV_ADD64(a[6], PV_SUB64(pv_mul2(G, t5), pv_mul2(H, t4)));
            }
            if (mm >= 4) {
                const pv t6 = PV_LD(tr + 6u * q + u), t7 = PV_LD(tr + 7u * q + u);
                a[7] = PV_ADD64(a[7], pv_mul2(AA, t6));
                a[8] = PV_ADD64(a[8], pv_mul2(PV_SUB32(A, A2), t7));
            }
        }
        for (int i = 0; i <= 2 * mm; ++i)
            pv_add128(&hi[i], &lo[i], a[i]);
    }
    for (int i = 0; i <= 2 * mm; ++i) {
        uint64_t h[PV_LANES / 2u], l[PV_LANES / 2u];
        PV_ST(h, hi[i]);
        PV_ST(l, lo[i]);
        for (uint32_t j = 0; j < PV_LANES / 2u; ++j) {
            const uint64_t nl = s[i].lo + l[j];
            s[i].hi += h[j] + (nl < l[j]);
            s[i].lo = nl;
        }
    }
    return u;
}
#endif

/* Fourier sums of one channel: s[0] = S_0, s[2m - 1] = S_mc, s[2m] = S_ms for m = 1..mm (the orders
 * the bands need, a constant where it is inlined; the others stay 0). */
static FOLD_INLINE void folded(const qibl_probe_sh_t *ps, const uint32_t *x, s128 s[9], const int mm)
{
    const uint32_t q = ps->width / 4u, half = q / 2u;
    for (int i = 0; i < 9; ++i)
        s[i].hi = s[i].lo = 0u;
    uint32_t start = 0u;
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
    start = folded_vec(ps, x, s, mm); /* 8 or 16 pairs a step */
#endif
    /* Quarter column u and its mirror u' = q - 1 - u (phi' = pi/2 - phi) share u's trig values:
     * cos m phi' and sin m phi' are +-sin m phi and +-cos m phi, so the two columns' folds combine
     * before the products (identities in probe.c's header): 12 products per pair and channel, 1.5
     * per pixel. Terms: |A + A'| <= 2^30, |E|, |F|, |G|, |H|, |B +- B'| <= 2^28, so each update is
     * at most 2^60 and chunks of 7 pairs stay below 2^63. */
#if TRIG_PLANAR
    const int32_t *t0 = ps->trig, *t1 = t0 + q, *t2 = t1 + q, *t3 = t2 + q, *t4 = t3 + q, *t5 = t4 + q, *t6 = t5 + q,
                  *t7 = t6 + q; /* the planar table's 8 rows */
#endif
    for (uint32_t u0 = start; u0 < half; u0 += CHUNK_PAIR) {
        const uint32_t u1 = half - u0 < CHUNK_PAIR ? half : u0 + CHUNK_PAIR;
        int64_t a0 = 0, c1 = 0, s1 = 0, c2 = 0, s2 = 0, c3 = 0, s3 = 0, c4 = 0, s4 = 0;
        for (uint32_t u = u0; u < u1; ++u) {
            const uint32_t v = q - 1u - u;
#if TRIG_PLANAR
            const int32_t t[8] = {t0[u], t1[u], t2[u], t3[u], t4[u], t5[u], t6[u], t7[u]};
#else
            const int32_t *t = ps->trig + 8u * (size_t)u;
#endif
            const int32_t p0 = (int32_t)x[u], p1 = (int32_t)x[u + q], p2 = (int32_t)x[u + 2u * q],
                          p3 = (int32_t)x[u + 3u * q];
            const int32_t r0 = (int32_t)x[v], r1 = (int32_t)x[v + q], r2 = (int32_t)x[v + 2u * q],
                          r3 = (int32_t)x[v + 3u * q];
            const int32_t A = p0 + p1 + p2 + p3, B = p0 - p1 + p2 - p3, C = p0 - p2, D = p1 - p3;
            const int32_t A2 = r0 + r1 + r2 + r3, B2 = r0 - r1 + r2 - r3, C2 = r0 - r2, D2 = r1 - r3;
            const int32_t E = C - D2, F = D - C2, G = C + D2, H = D + C2;
            a0 += (int64_t)A + A2;
            if (mm >= 1) {
                c1 += qibl_mul_s32_s64(E, t[0]) - qibl_mul_s32_s64(F, t[1]);
                s1 += qibl_mul_s32_s64(G, t[1]) + qibl_mul_s32_s64(H, t[0]);
            }
            if (mm >= 2) {
                c2 += qibl_mul_s32_s64(B - B2, t[2]);
                s2 += qibl_mul_s32_s64(B + B2, t[3]);
            }
            if (mm >= 3) {
                c3 += qibl_mul_s32_s64(E, t[4]) + qibl_mul_s32_s64(F, t[5]);
                s3 += qibl_mul_s32_s64(G, t[5]) - qibl_mul_s32_s64(H, t[4]);
            }
            if (mm >= 4) {
                c4 += qibl_mul_s32_s64(A + A2, t[6]);
                s4 += qibl_mul_s32_s64(A - A2, t[7]);
            }
        }
        s128_add64(&s[0], a0);
        s128_add64(&s[1], c1), s128_add64(&s[2], s1);
        s128_add64(&s[3], c2), s128_add64(&s[4], s2);
        s128_add64(&s[5], c3), s128_add64(&s[6], s3);
        s128_add64(&s[7], c4), s128_add64(&s[8], s4);
    }
    if (q & 1u) { /* the middle quarter column is its own mirror (phi = pi/4) */
        const uint32_t u = half;
        int32_t t[8];
        for (uint32_t i = 0; i < 8u; ++i)
            t[i] = TRIG(ps, q, i, u);
        const int32_t p0 = (int32_t)x[u], p1 = (int32_t)x[u + q], p2 = (int32_t)x[u + 2u * q],
                      p3 = (int32_t)x[u + 3u * q];
        const int32_t A = p0 + p1 + p2 + p3, B = p0 - p1 + p2 - p3, C = p0 - p2, D = p1 - p3;
        s128_add64(&s[0], A);
        if (mm >= 1) {
            s128_add64(&s[1], qibl_mul_s32_s64(C, t[0]) - qibl_mul_s32_s64(D, t[1]));
            s128_add64(&s[2], qibl_mul_s32_s64(C, t[1]) + qibl_mul_s32_s64(D, t[0]));
        }
        if (mm >= 2) {
            s128_add64(&s[3], qibl_mul_s32_s64(B, t[2]));
            s128_add64(&s[4], qibl_mul_s32_s64(B, t[3]));
        }
        if (mm >= 3) {
            s128_add64(&s[5], qibl_mul_s32_s64(C, t[4]) + qibl_mul_s32_s64(D, t[5]));
            s128_add64(&s[6], qibl_mul_s32_s64(C, t[5]) - qibl_mul_s32_s64(D, t[4]));
        }
        if (mm >= 4) {
            s128_add64(&s[7], qibl_mul_s32_s64(A, t[6]));
            s128_add64(&s[8], qibl_mul_s32_s64(A, t[7]));
        }
    }
}

/* folded() for the orders the projection's bands need (m <= bands - 1): 3 bands sum 5 of the 9
 * and take 6 of the 12 products per column pair, so fewer bands cost less */
static void row_sums_folded(const qibl_probe_sh_t *ps, const uint32_t *x, s128 s[9])
{
#ifdef __OPTIMIZE_SIZE__
    folded(ps, x, s, ps->bands - 1); /* one copy where size is what counts (the cross builds) */
#else
    switch (ps->bands) {
    case 1: folded(ps, x, s, 0); break;
    case 2: folded(ps, x, s, 1); break;
    case 3: folded(ps, x, s, 2); break;
    case 4: folded(ps, x, s, 3); break;
    default: folded(ps, x, s, 4); break;
    }
#endif
}

/* cos and sin of m phi_u (m = 1..4) at any column u, from the table (by quarter turns if folded) */
static void trig_at(const qibl_probe_sh_t *ps, uint32_t u, int32_t t[8])
{
    if ((ps->width & 3u) != 0u) {
        for (uint32_t i = 0; i < 8u; ++i)
            t[i] = TRIG(ps, ps->width, i, u);
        return;
    }
    const uint32_t q = ps->width / 4u;
    uint32_t k = 0u; /* u / q without a division (a library call on Cortex-M0) */
    while (u >= q)
        u -= q, ++k;
    for (uint32_t m = 1; m <= 4u; ++m) {
        int32_t c = TRIG(ps, q, 2u * (m - 1u), u), s = TRIG(ps, q, 2u * (m - 1u) + 1u, u);
        /* times i^(m k): a quarter turn maps (c, s) to (-s, c) */
        for (uint32_t r = (m * k) & 3u; r > 0u; --r) {
            int32_t c2 = -s;
            s = c, c = c2;
        }
        t[2u * (m - 1u)] = c, t[2u * (m - 1u) + 1u] = s;
    }
}

/* Direct sums over columns u0 .. u1-1 (any width; products <= 2^57, chunks of 8 below 2^60). */
static void row_sums_direct(const qibl_probe_sh_t *ps, const uint32_t *x, uint32_t u0, uint32_t u1, s128 s[9])
{
    const int nt = 2 * (ps->bands - 1);
    for (int i = 0; i < 9; ++i)
        s[i].hi = s[i].lo = 0u;
    for (uint32_t c0 = u0; c0 < u1; c0 += CHUNK) {
        const uint32_t c1 = u1 - c0 < CHUNK ? u1 : c0 + CHUNK;
        int64_t a[9];
        for (int i = 0; i < 9; ++i) /* assigned one by one: an initialiser becomes a memset call */
            a[i] = 0;
        for (uint32_t u = c0; u < c1; ++u) {
            int32_t t[8];
            trig_at(ps, u, t);
            const int32_t xv = (int32_t)x[u];
            a[0] += xv;
            for (int i = 0; i < nt; ++i) /* the orders the bands need */
                a[i + 1] += qibl_mul_s32_s64(xv, t[i]);
        }
        for (int i = 0; i < 9; ++i)
            s128_add64(&s[i], a[i]);
    }
}

/* The row factors f_(l,|m|) = Y_l|m|(theta_v, 0) sin theta_v = f 2^-(31 + kap): magnitudes and
 * signs at index l*l + l + |m|. */
static void row_factors(const qibl_probe_sh_t *ps, uint32_t v, uint32_t fmag[QIBL_SH_MAX_COUNT],
                        int fneg[QIBL_SH_MAX_COUNT], int32_t *kap)
{
    uint32_t sig;
    qibli_lightprobe_sin_frac(2u * (uint64_t)v + 1u, 2u * (uint64_t)ps->height, &sig, kap);
    qibl_q30_t u[3], y[QIBL_SH_MAX_COUNT];
    u[0] = (int32_t)rshr_u64(sig, (unsigned)(2 + *kap)); /* sin theta in Q30 */
    u[1] = 0;
    u[2] = cos_pi_q30(2u * (uint64_t)v + 1u, 2u * (uint64_t)ps->height);
    QIBL_DROP_STATUS(qibl_sh_eval_unit(u, ps->bands, y));
    for (int i = 0; i < ps->bands * ps->bands; ++i) {
        uint32_t a = y[i] < 0 ? 0u - (uint32_t)y[i] : (uint32_t)y[i]; /* < 1.1 2^30 */
        fmag[i] = (uint32_t)rshr_u64(qibl_mul_u32_u64(a, sig), 31u); /* < 1.1 2^31 */
        fneg[i] = y[i] < 0;
    }
}

/* bit length of a non-zero value: on the x86 copies (GCC or Clang) one instruction; the portable
 * search branches on the data, and S's signs and sizes change from row to row (mispredictions
 * were about a third of row_accumulate) */
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2 && (defined(__GNUC__) || defined(__clang__))
#define BITLEN_NZ(x) (64u - (unsigned)__builtin_clzll(x))
#else
#define BITLEN_NZ(x) qibli_bitlen_u64(x)
#endif

/* Adds (or subtracts) S_m f_l|m| 2^(s_v - 61 - kap) for every coefficient of one channel. */
static void row_accumulate(qibl_probe_sh_t *ps, uint32_t *acc, const s128 s[9], const uint32_t *fmag,
                           const int *fneg, int32_t sv, int32_t kap, int negate)
{
    for (int sel = 0; sel < 9; ++sel) {
        uint64_t hi, lo;
        int neg = s128_abs(&s[sel], &hi, &lo);
        if ((hi | lo) == 0u)
            continue;
        unsigned bl = hi ? 64u + BITLEN_NZ(hi) : BITLEN_NZ(lo), r = bl > 62u ? bl - 62u : 0u;
        uint64_t mag; /* round(|S| / 2^r), <= 2^62 */
        if (r == 0u) {
            mag = lo;
        } else {
            /* r <= 11; hi != 0 only when bl >= 65, i.e. r >= 3 */
            uint64_t h = qibl_shr_u64(lo, r - 1u) | (hi ? qibli_shl_u64(hi, 65u - r) : 0u);
            mag = (h >> 1) + (h & 1u);
        }
        /* sel 0: m = 0; sel 2m - 1: +m (cos); sel 2m: -m (sin) */
        const int m = sel == 0 ? 0 : (sel + 1) / 2, ms = sel == 0 ? 0 : (sel & 1 ? m : -m);
        for (int l = m; l < ps->bands; ++l) {
            const int fi = l * l + l + m;
            if (fmag[fi] == 0u)
                continue;
            uint32_t p[3];
            mul_64_32(mag, fmag[fi], p);
            /* S_0 has no Q2.30 trig factor: it counts 2^30 more */
            const int32_t e = sv - 61 - kap + (int32_t)r - ACC_LSB + (sel == 0 ? 30 : 0); /* >= 5 */
            kadd(acc + (size_t)(l * l + l + ms) * LIMBS, p, (unsigned)e, (neg ^ fneg[fi]) ^ negate);
        }
    }
}

/* Adds columns u0 .. u1-1 of row v (whole rows take the folded path when W % 4 == 0). */
static qibl_status_t add_span(qibl_probe_sh_t *ps, uint32_t v, const void *row, uint32_t u0, uint32_t u1, int negate)
{
    const uint8_t *p = (const uint8_t *)row;
    if (ps->format >= QIBL_LIGHTPROBE_LINEAR_I32 && ((uintptr_t)p & 3u) != 0u)
        return QIBL_E_PROBE_FORMAT;
    int32_t t;
    qibl_status_t st = qibli_probe_bad_status(row_scan(ps, p, &t));
    if (st != QIBL_OK)
        return st;
    if (t == INT32_MIN)
        return QIBL_OK; /* a black row adds nothing */
    row_convert(ps, p, t);
    uint32_t fmag[QIBL_SH_MAX_COUNT];
    int fneg[QIBL_SH_MAX_COUNT];
    int32_t kap;
    row_factors(ps, v, fmag, fneg, &kap);
    for (uint32_t c = 0; c < 3u; ++c) {
        s128 s[9];
        const uint32_t *x = ps->x + (size_t)c * ps->width;
        if (u0 == 0u && u1 == ps->width && (ps->width & 3u) == 0u)
            row_sums_folded(ps, x, s);
        else
            row_sums_direct(ps, x, u0, u1, s);
        row_accumulate(ps, ps->acc + (size_t)c * 25u * LIMBS, s, fmag, fneg, t - XBITS, kap, negate);
    }
    return QIBL_OK;
}

qibl_status_t qibl_probe_sh_add_row(qibl_probe_sh_t *ps, uint32_t v, const void *row)
{
    QIBLI_DISPATCH512(qibl_probe_sh_add_row, (ps, v, row));
    if (ps == 0 || row == 0 || ps->acc == 0)
        return QIBL_E_NULL_POINTER;
    if (v >= ps->height || ((unsigned)ps->seen[v >> 3] >> (v & 7u)) & 1u)
        return QIBL_E_PROBE_ROW;
    qibl_status_t st = add_span(ps, v, row, 0u, ps->width, 0);
    if (st != QIBL_OK)
        return st;
    ps->seen[v >> 3] = (uint8_t)((unsigned)ps->seen[v >> 3] | (1u << (v & 7u)));
    ps->rows++;
    return QIBL_OK;
}

/* ---- finish ----------------------------------------------------------------------------------- */

/* top 32 bits of a * b (a < 2^64, b < 2^32), rounded, as mantissa in [2^31, 2^32) and the shift
 * *e such that a b ~ mant 2^*e; 0 for a zero product */
static uint32_t mul_norm32(uint64_t a, uint32_t b, int32_t *e)
{
    uint32_t p[3];
    mul_64_32(a, b, p);
    uint64_t hi = ((uint64_t)p[2] << 32) | p[1];
    unsigned bl = hi ? 32u + qibli_bitlen_u64(hi) : qibli_bitlen_u32(p[0]);
    if (bl == 0u) {
        *e = 0;
        return 0u;
    }
    /* take bits bl-1 .. bl-33 (one extra for rounding) */
    uint64_t top;
    if (bl >= 33u) {
        unsigned sh = bl - 33u; /* from the 96-bit value */
        top = sh >= 32u ? qibl_shr_u64(hi, sh - 32u) : (qibli_shl_u64(hi, 32u - sh) | (p[0] >> sh));
    } else {
        top = qibli_shl_u64(p[0], 33u - bl);
    }
    uint64_t m = (top >> 1) + (top & 1u);
    int32_t ex = (int32_t)bl - 32;
    if (m >> 32) {
        m >>= 1;
        ++ex;
    }
    *e = ex;
    return (uint32_t)m;
}

/* K_l = 2 pi^2 sigma_l A_l / (W H D) as a 32-bit mantissa (sign apart) times 2^*e; 0 if it is 0 */
static uint32_t band_constant(const qibl_probe_sh_t *ps, int l, const qibl_probe_sh_opts_t *o, int *neg, int32_t *e)
{
    int32_t ex, e2;
    uint32_t k = mul_norm32(TWO_PI_SQ_Q58, 1u << 31, &ex); /* 2 pi^2 = k 2^(ex - 58 - 31) */
    ex -= 89;
    *neg = 0;
    if (o->window != QIBL_PROBE_WINDOW_NONE) {
        const int b = ps->bands - 1;
        const int32_t s = o->window == QIBL_PROBE_WINDOW_HANN ? win_hann[b][l] : win_lanczos[b][l];
        k = mul_norm32(k, (uint32_t)s, &e2), ex += e2 - 30;
    }
    if (o->irradiance) {
        const int32_t a = irr_a[l];
        if (a < 0)
            *neg = 1;
        k = mul_norm32(k, a < 0 ? 0u - (uint32_t)a : (uint32_t)a, &e2), ex += e2 - 29;
    }
    if (k == 0u) {
        *e = 0;
        return 0u;
    }
    /* divide by W H D (< 2^35): two long-division steps of 28 bits give >= 56 quotient bits */
    uint64_t den = qibl_mul_u32_u64(ps->width, ps->height);
    if (ps->format == QIBL_LIGHTPROBE_SRGBE)
        den = qibl_mul_u32_u64((uint32_t)den, 510u); /* < 2^35 */
    uint64_t rem, q, num = (uint64_t)k << 28;          /* < 2^60 */
    q = qibl_udiv_u64(num, den, &rem);                 /* >= 2^31 when den < 2^28 */
    ex -= 28;
    if (den >> 28) { /* one more digit: q < 2^32, rem < 2^35, so both steps fit */
        q = (q << 28) + qibl_udiv_u64(rem << 28, den, 0);
        ex -= 28;
    }
    unsigned bl = qibli_bitlen_u64(q);
    uint64_t m = bl > 32u ? rshr_u64(q, bl - 32u) : qibli_shl_u64(q, 32u - bl);
    ex += (int32_t)bl - 32;
    if (m >> 32) {
        m >>= 1;
        ++ex;
    }
    *e = ex;
    return (uint32_t)m;
}

/* the accumulator as sign, top 63 bits (rounded) and exponent: |acc| ~ mant 2^(*e + ACC_LSB) */
static uint64_t acc_top(const uint32_t *acc, int *neg, int32_t *e)
{
    uint32_t a[LIMBS];
    *neg = (int)(acc[LIMBS - 1u] >> 31);
    uint32_t borrow = 1u;
    for (unsigned i = 0; i < LIMBS; ++i) {
        if (*neg) { /* two's complement negation: ~a + 1 */
            uint64_t s = (uint64_t)(uint32_t)~acc[i] + borrow;
            a[i] = (uint32_t)s;
            borrow = (uint32_t)(s >> 32);
        } else {
            a[i] = acc[i];
        }
    }
    int top = (int)LIMBS - 1;
    while (top >= 0 && a[top] == 0u)
        --top;
    if (top < 0) {
        *e = 0;
        return 0u;
    }
    unsigned bl = 32u * (unsigned)top + qibli_bitlen_u32(a[top]); /* total bit length */
    if (bl <= 63u) {
        uint64_t v = top >= 1 ? ((uint64_t)a[1] << 32) | a[0] : a[0];
        *e = ACC_LSB;
        return v;
    }
    /* bits bl-1 .. bl-64 into one uint64 (63 kept + 1 for rounding) */
    const unsigned lo_bit = bl - 64u, q = lo_bit >> 5, b = lo_bit & 31u;
    const uint32_t l0 = a[q], l1 = q + 1u < LIMBS ? a[q + 1u] : 0u, l2 = q + 2u < LIMBS ? a[q + 2u] : 0u;
    /* 32-bit shifts only (a variable 64-bit shift is a library call on Cortex-M0) */
    const uint64_t w = b == 0u ? ((uint64_t)l1 << 32) | l0
                               : ((uint64_t)((l2 << (32u - b)) | (l1 >> b)) << 32) | ((l1 << (32u - b)) | (l0 >> b));
    uint64_t m = (w >> 1) + (w & 1u);
    *e = (int32_t)lo_bit + 1 + ACC_LSB;
    return m;
}

qibl_status_t qibl_probe_sh_finish(const qibl_probe_sh_t *ps, const qibl_probe_sh_opts_t *opts,
                                   qibl_probe_coeffs_t *out)
{
    QIBLI_DISPATCH512(qibl_probe_sh_finish, (ps, opts, out));
    if (ps == 0 || out == 0 || ps->acc == 0)
        return QIBL_E_NULL_POINTER;
    qibl_probe_sh_opts_t o = {0, QIBL_PROBE_WINDOW_NONE, 0};
    if (opts)
        o.irradiance = opts->irradiance, o.window = opts->window;
    if ((unsigned)o.window >= QIBL_PROBE_WINDOW_COUNT)
        return QIBL_E_PROBE_METHOD;
    if (ps->rows != ps->height)
        return QIBL_E_PROBE_ROW;
    const int n = ps->bands * ps->bands;
    uint32_t mant[3][QIBL_SH_MAX_COUNT];
    int32_t ex[3][QIBL_SH_MAX_COUNT];
    int sgn[3][QIBL_SH_MAX_COUNT];
    int32_t top = INT32_MIN;
    for (int l = 0; l < ps->bands; ++l) {
        int kneg;
        int32_t ke;
        uint32_t k = band_constant(ps, l, &o, &kneg, &ke);
        for (int i = l * l; i < (l + 1) * (l + 1); ++i)
            for (int c = 0; c < 3; ++c) {
                int aneg;
                int32_t ae, pe;
                uint64_t a = acc_top(ps->acc + ((size_t)c * 25u + (size_t)i) * LIMBS, &aneg, &ae);
                uint32_t p = k ? mul_norm32(a, k, &pe) : 0u;
                mant[c][i] = p;
                ex[c][i] = p ? pe + ae + ke : 0;
                sgn[c][i] = aneg ^ kneg;
                if (p && ex[c][i] > top)
                    top = ex[c][i];
            }
    }
    /* shared exponent: the largest mantissa (< 2^32) 2^top becomes < 2^31 */
    int32_t oe = top == INT32_MIN ? 0 : top + 1;
    out->bands = ps->bands;
    out->exp = oe;
    for (int c = 0; c < 3; ++c)
        for (int i = 0; i < QIBL_SH_MAX_COUNT; ++i) {
            int32_t v = 0;
            if (i < n && mant[c][i]) {
                int32_t d = oe - ex[c][i]; /* >= 1 */
                uint64_t r = rshr_u64(mant[c][i], (unsigned)(d > 64 ? 64 : d));
                if (r > (uint64_t)INT32_MAX)
                    r = (uint64_t)INT32_MAX; /* a rounding carry to 2^31 */
                v = sgn[c][i] ? -(int32_t)r : (int32_t)r;
            }
            out->c[c][i] = v;
        }
    return QIBL_OK;
}

/* ---- resident images and lights --------------------------------------------------------------- */

static qibl_status_t image_stride(const qibl_lightprobe_image_t *img, size_t *stride)
{
    const size_t pb = qibli_lightprobe_pixel_bytes(img->format);
    const uint64_t row_bytes = qibl_mul_u32_u64(img->width, (uint32_t)pb);
    *stride = img->stride ? img->stride : (size_t)row_bytes;
    if ((uint64_t)*stride < row_bytes)
        return QIBL_E_PROBE_FORMAT;
    if (img->height > 1u && (uint64_t)*stride > qibl_udiv_u64((uint64_t)SIZE_MAX - row_bytes, img->height - 1u, 0))
        return QIBL_E_PROBE_OVERFLOW;
    if (pb == 12u && (((uintptr_t)img->pixels & 3u) != 0u || (*stride & 3u) != 0u))
        return QIBL_E_PROBE_FORMAT;
    return QIBL_OK;
}

static qibl_status_t project(const qibl_lightprobe_image_t *img, int bands, void *workspace, size_t workspace_size,
                             qibl_probe_sh_t *ps, size_t *stride)
{
    if (img == 0 || img->pixels == 0)
        return QIBL_E_NULL_POINTER;
    qibl_status_t st = qibl_probe_sh_begin(ps, img->width, img->height, img->format, img->frac_bits, bands,
                                           workspace, workspace_size);
    if (st != QIBL_OK)
        return st;
    if ((st = image_stride(img, stride)) != QIBL_OK)
        return st;
    const uint8_t *p = (const uint8_t *)img->pixels;
    for (uint32_t v = 0; v < img->height; ++v)
        if ((st = qibl_probe_sh_add_row(ps, v, p + (size_t)v * *stride)) != QIBL_OK)
            return st;
    return QIBL_OK;
}

qibl_status_t qibl_probe_sh_project(const qibl_lightprobe_image_t *img, int bands, const qibl_probe_sh_opts_t *opts,
                                    void *workspace, size_t workspace_size, qibl_probe_coeffs_t *out)
{
    QIBLI_DISPATCH512(qibl_probe_sh_project, (img, bands, opts, workspace, workspace_size, out));
    if (out == 0)
        return QIBL_E_NULL_POINTER;
    qibl_probe_sh_t ps;
    size_t stride;
    qibl_status_t st = project(img, bands, workspace, workspace_size, &ps, &stride);
    return st != QIBL_OK ? st : qibl_probe_sh_finish(&ps, opts, out);
}

static int bands_for(uint32_t k)
{
    int b = 1;
    while ((uint32_t)(b * b) < k)
        ++b;
    return b;
}

/* round(c 2^s) as int64 for |c| < 2^31 and any s, saturating far beyond int32 */
static int64_t scale_s64(int32_t c, int32_t s)
{
    if (c == 0)
        return 0;
    if (s >= 0) {
        if (s > 32)
            return c < 0 ? INT64_MIN / 2 : INT64_MAX / 2;
        uint64_t m = qibli_shl_u64(c < 0 ? 0u - (uint32_t)c : (uint32_t)c, (unsigned)s); /* < 2^63 */
        return c < 0 ? -(int64_t)m : (int64_t)m;
    }
    return qibl_asr_s64(qibl_asr_s64(c, (unsigned)(-s - 1 > 62 ? 62 : -s - 1)) + 1, 1);
}

qibl_status_t qibl_shlight_add_coeffs(qibl_shlight_t *l, const qibl_probe_coeffs_t *c, int32_t scale_log2)
{
    if (l == 0 || c == 0)
        return QIBL_E_NULL_POINTER;
    if (l->k < 1u || l->k > (uint32_t)QIBL_SH_MAX_COUNT)
        return QIBL_E_SHMAP_K;
    if (c->bands < 1 || c->bands > QIBL_SH_MAX_BANDS)
        return QIBL_E_BAD_BANDS;
    if (scale_log2 < -512 || scale_log2 > 512 || c->exp < -1024 || c->exp > 1024)
        return QIBL_E_RANGE; /* keeps exp + 16 + scale_log2 far from int32's ends */
    const uint32_t n = l->k < (uint32_t)(c->bands * c->bands) ? l->k : (uint32_t)(c->bands * c->bands);
    const int32_t s = c->exp + 16 + scale_log2;
    for (int ch = 0; ch < 3; ++ch)
        for (uint32_t i = 0; i < n; ++i) {
            int64_t v = (int64_t)l->c[ch][i] + scale_s64(c->c[ch][i], s);
            if (v > INT32_MAX || v < INT32_MIN)
                return QIBL_E_PROBE_SATURATED;
        }
    for (int ch = 0; ch < 3; ++ch)
        for (uint32_t i = 0; i < n; ++i)
            l->c[ch][i] = (int32_t)((int64_t)l->c[ch][i] + scale_s64(c->c[ch][i], s));
    return QIBL_OK;
}

qibl_status_t qibl_shlight_add_probe(qibl_shlight_t *l, const qibl_lightprobe_image_t *img,
                                     const qibl_probe_sh_opts_t *opts, void *workspace, size_t workspace_size)
{
    QIBLI_DISPATCH512(qibl_shlight_add_probe, (l, img, opts, workspace, workspace_size));
    if (l == 0)
        return QIBL_E_NULL_POINTER;
    if (l->k < 1u || l->k > (uint32_t)QIBL_SH_MAX_COUNT)
        return QIBL_E_SHMAP_K;
    qibl_probe_coeffs_t c;
    qibl_status_t st = qibl_probe_sh_project(img, bands_for(l->k), opts, workspace, workspace_size, &c);
    if (st != QIBL_OK)
        return st;
    return qibl_shlight_add_coeffs(l, &c, opts ? opts->scale_log2 : 0);
}

qibl_status_t qibl_shlight_add_lights(qibl_shlight_t *l, const qibl_lightprobe_light_t *lights, uint32_t count,
                                      int32_t rgb_exp, int32_t scale_log2)
{
    if (l == 0 || (lights == 0 && count))
        return QIBL_E_NULL_POINTER;
    if (l->k < 1u || l->k > (uint32_t)QIBL_SH_MAX_COUNT)
        return QIBL_E_SHMAP_K;
    if (count > 65536u)
        return QIBL_E_PROBE_COUNT;
    const int bands = bands_for(l->k);
    /* rgb Y < 2^31 2^30.2; summed as round(rgb Y / 2^16) < 2^45.2, 2^16 lights < 2^62 */
    int64_t acc[3][QIBL_SH_MAX_COUNT];
    for (int ch = 0; ch < 3; ++ch)
        for (uint32_t i = 0; i < l->k; ++i)
            acc[ch][i] = 0;
    for (uint32_t n = 0; n < count; ++n) {
        qibl_q30_t y[QIBL_SH_MAX_COUNT];
        if (qibl_sh_eval(lights[n].dir, bands, y) != QIBL_OK)
            continue; /* a zero direction carries no light */
        for (int ch = 0; ch < 3; ++ch)
            for (uint32_t i = 0; i < l->k; ++i)
                acc[ch][i] += qibl_asr_s64(qibl_mul_s32_s64(lights[n].rgb[ch], y[i]) + (1 << 15), 16);
    }
    /* value = acc 2^(16 - 30 + rgb_exp + scale) in units, Q16.16: times 2^(rgb_exp + scale + 2) */
    const int32_t s = rgb_exp + scale_log2 + 2;
    int32_t res[3][QIBL_SH_MAX_COUNT];
    for (int ch = 0; ch < 3; ++ch)
        for (uint32_t i = 0; i < l->k; ++i) {
            int64_t a = acc[ch][i], v;
            if (a == 0)
                v = 0;
            else if (s >= 0) /* |a| < 2^62: beyond 2^33 the sum saturates anyway */
                v = s > 28 || qibl_shr_u64((uint64_t)(a < 0 ? -a : a), 33u - (unsigned)s) ? (a < 0 ? INT64_MIN / 4 : INT64_MAX / 4)
                    : (a < 0 ? -(int64_t)qibli_shl_u64((uint64_t)-a, (unsigned)s) : (int64_t)qibli_shl_u64((uint64_t)a, (unsigned)s));
            else
                v = qibl_asr_s64(qibl_asr_s64(a, (unsigned)(-s - 1 > 62 ? 62 : -s - 1)) + 1, 1);
            v += l->c[ch][i];
            if (v > INT32_MAX || v < INT32_MIN)
                return QIBL_E_PROBE_SATURATED;
            res[ch][i] = (int32_t)v;
        }
    for (int ch = 0; ch < 3; ++ch)
        for (uint32_t i = 0; i < l->k; ++i)
            l->c[ch][i] = res[ch][i];
    return QIBL_OK;
}

qibl_status_t qibl_shlight_add_sun_sky(qibl_shlight_t *l, const qibl_lightprobe_image_t *img,
                                       const qibl_probe_sh_opts_t *opts, const qibl_lightprobe_light_t *sun,
                                       uint32_t count, int32_t rgb_exp, void *workspace, size_t workspace_size)
{
    QIBLI_DISPATCH512(qibl_shlight_add_sun_sky, (l, img, opts, sun, count, rgb_exp, workspace, workspace_size));
    if (l == 0 || (sun == 0 && count))
        return QIBL_E_NULL_POINTER;
    if (l->k < 1u || l->k > (uint32_t)QIBL_SH_MAX_COUNT)
        return QIBL_E_SHMAP_K;
    qibl_probe_sh_t ps;
    size_t stride;
    qibl_status_t st = project(img, bands_for(l->k), workspace, workspace_size, &ps, &stride);
    if (st != QIBL_OK)
        return st;
    for (uint32_t n = 0; n < count; ++n)
        if (sun[n].u0 >= sun[n].u1 || sun[n].v0 >= sun[n].v1 || sun[n].u1 > img->width || sun[n].v1 > img->height)
            return QIBL_E_PROBE_RECT;
    /* take the regions out (regions of one list are disjoint); rows were checked by the projection */
    const uint8_t *p = (const uint8_t *)img->pixels;
    for (uint32_t n = 0; n < count; ++n)
        for (uint32_t v = sun[n].v0; v < sun[n].v1; ++v)
            (void)add_span(&ps, v, p + (size_t)v * stride, sun[n].u0, sun[n].u1, 1);
    qibl_probe_coeffs_t c;
    if ((st = qibl_probe_sh_finish(&ps, opts, &c)) != QIBL_OK)
        return st;
    /* both additions must succeed or neither happens: work on a copy (member by member) */
    qibl_shlight_t t;
    t.k = l->k;
    for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i < QIBL_SH_MAX_COUNT; ++i)
            t.c[ch][i] = l->c[ch][i];
    if ((st = qibl_shlight_add_coeffs(&t, &c, opts ? opts->scale_log2 : 0)) != QIBL_OK)
        return st;
    if ((st = qibl_shlight_add_lights(&t, sun, count, rgb_exp, opts ? opts->scale_log2 : 0)) != QIBL_OK)
        return st;
    for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i < QIBL_SH_MAX_COUNT; ++i)
            l->c[ch][i] = t.c[ch][i];
    return QIBL_OK;
}

qibl_status_t qibl_shlight_rotate(qibl_shlight_t *l, const qibl_sh_rotation_t *rot)
{
    if (l == 0 || rot == 0)
        return QIBL_E_NULL_POINTER;
    if (l->k < 1u || l->k > (uint32_t)QIBL_SH_MAX_COUNT)
        return QIBL_E_SHMAP_K;
    const int bands = bands_for(l->k);
    if (rot->bands < bands)
        return QIBL_E_BAD_BANDS;
    for (int ch = 0; ch < 3; ++ch) {
        int32_t in[QIBL_SH_MAX_COUNT], out[QIBL_SH_MAX_COUNT];
        for (int i = 0; i < QIBL_SH_MAX_COUNT; ++i)
            in[i] = i < bands * bands ? l->c[ch][i] : 0;
        qibl_status_t st = qibl_sh_rotate(rot, in, out);
        if (st != QIBL_OK)
            return st;
        for (uint32_t i = 0; i < l->k; ++i)
            l->c[ch][i] = out[i];
    }
    return QIBL_OK;
}

#else
typedef int qibl_probe_disabled_t; /* ISO C forbids an empty translation unit */
#endif /* QIBL_USE_PROBE */
