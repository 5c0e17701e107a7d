/*
 * shmap.c - relighting kernels for 8-bit SH maps: per-frame weights, directional/environment spans,
 * point-light spans (cube-map LUT or direct SH), cube-map LUT build and lookup.
 *
 * Invariants: integer only, no heap, no state; int32 accumulators whose bounds are proven in
 * shmap.h; every 64-bit product through fixed.h (no library calls on Cortex-M0).
 */
#include "qibl/shmap.h"
#include "qibli.h"

/* compiler intrinsics headers only (freestanding), only on the path config.h chose */
#if QIBL_USE_SHMAP
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
#include <immintrin.h>
#elif QIBL_CONFIG_SIMD == QIBL_SIMD_SSE2
#include <emmintrin.h>
#elif QIBL_CONFIG_SIMD == QIBL_SIMD_NEON
#include <arm_neon.h>
#endif
#endif

#if QIBL_USE_SHMAP

#define SHMAP_MAX_W 32767 /* int16 weights */

/* ---- light coefficients ---------------------------------------------------------------------- */

qibl_status_t qibl_shlight_init(qibl_shlight_t *l, uint32_t k)
{
    if (l == 0)
        return QIBL_E_NULL_POINTER;
    if (k < 1u || k > (uint32_t)QIBL_SH_MAX_COUNT)
        return QIBL_E_SHMAP_K;
    l->k = k;
    for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i < QIBL_SH_MAX_COUNT; ++i)
            l->c[ch][i] = 0;
    return QIBL_OK;
}

static int bands_for(uint32_t k)
{
    int b = 1;
    while ((uint32_t)(b * b) < k)
        ++b;
    return b;
}

qibl_status_t qibl_shlight_add_dir(qibl_shlight_t *l, const qibl_q16_t dir[3], const qibl_q16_t rgb[3])
{
    if (l == 0 || dir == 0 || rgb == 0)
        return QIBL_E_NULL_POINTER;
    if (l->k < 1u || l->k > (uint32_t)QIBL_SH_MAX_COUNT)
        return QIBL_E_SHMAP_K;
    qibl_q30_t y[QIBL_SH_MAX_COUNT];
    qibl_status_t st = qibl_sh_eval(dir, bands_for(l->k), y);
    if (st != QIBL_OK)
        return st;
    for (int ch = 0; ch < 3; ++ch)
        for (uint32_t i = 0; i < l->k; ++i)
            l->c[ch][i] = qibl_add_sat_s32(l->c[ch][i], qibli_rshr_s64(qibl_mul_s32_s64(rgb[ch], y[i]), 30));
    return QIBL_OK;
}

/* ---- maps, weights --------------------------------------------------------------------------- */

/* The view's fields; the map bytes only when the call reads them (weights and point_prepare read
 * only the params, so the maps view of a streamed asset's head, planes NULL, makes weights). */
static qibl_status_t check_view(const qibl_shmaps_t *m, int need_planes)
{
    if (m == 0 || m->params == 0 || (need_planes && m->planes == 0))
        return QIBL_E_NULL_POINTER;
    if (m->k < 1u || m->k > (uint32_t)QIBL_SH_MAX_COUNT)
        return QIBL_E_SHMAP_K;
    if (m->channels != 1u && m->channels != 3u)
        return QIBL_E_SHMAP_CHANNELS;
    if (m->width == 0u || m->height == 0u)
        return QIBL_E_SHMAP_SIZE;
    if (m->layout != QIBL_SHMAPS_PLANAR && (!QIBL_USE_INTERLEAVED || m->layout != QIBL_SHMAPS_INTERLEAVED))
        return QIBL_E_SHMAP_LAYOUT;
    return QIBL_OK;
}

qibl_status_t qibl_shmap_check(const qibl_shmaps_t *m)
{
    return check_view(m, 1);
}

qibl_status_t qibl_shmap_weights(const qibl_shmaps_t *m, const qibl_shlight_t *light, qibl_shmap_weights_t *out)
{
    qibl_status_t st = check_view(m, 0);
    if (st != QIBL_OK)
        return st;
    if (light == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    if (light->k < m->k || light->k > (uint32_t)QIBL_SH_MAX_COUNT)
        return QIBL_E_SHMAP_LIGHT_K;
    /* everything that can fail is checked above: build the weights in place (a struct copy would
     * be a memcpy call on some freestanding targets) */
    out->k = m->k;
    out->channels = m->channels;
    for (uint32_t ch = 0; ch < 3u; ++ch) {
        uint32_t src = m->channels == 3u ? ch : 0u;
        /* exact products scale * L in Q40 (Q8.24 x Q16.16), |.| <= 2^62 */
        int64_t r[QIBL_SH_MAX_COUNT];
        uint64_t maxr = 0u;
        int64_t bias32 = 0; /* sum of bias * L in Q32: each term <= 2^54, 25 terms < 2^59 */
        for (uint32_t i = 0; i < m->k; ++i) {
            qibl_q16_t li = light->c[ch][i];
            r[i] = qibl_mul_s32_s64(qibl_shmaps_scale(m, i, src), li);
            if (qibli_abs_u64(r[i]) > maxr)
                maxr = qibli_abs_u64(r[i]);
            bias32 += qibl_asr_s64(qibl_mul_s32_s64(qibl_shmaps_bias(m, i, src), li), 8);
        }
        /* smallest shift s with round(max / 2^s) <= 32767 */
        unsigned s = 0u;
        while (s < 62u && qibl_shr_u64(maxr + (s ? qibl_shr_u64((uint64_t)1 << 63, 64u - s) : 0u), s) > SHMAP_MAX_W)
            ++s;
        for (uint32_t i = 0; i < (uint32_t)QIBL_SH_MAX_COUNT; ++i) {
            int32_t v = 0;
            if (i < m->k)
                v = s == 0u ? (int32_t)r[i] : qibli_rshr_s64(r[i], s);
            out->w[ch][i] = (int16_t)(v > SHMAP_MAX_W ? SHMAP_MAX_W : v < -SHMAP_MAX_W ? -SHMAP_MAX_W : v);
        }
        /* acc unit is 2^(s-40); Q16.16 output unit is 2^-16: out = acc * 2^(s-24) */
        out->shift[ch] = (int32_t)s - 24;
        out->bias[ch] = qibl_asr_s64(bias32 + ((int64_t)1 << 15), 16); /* Q32 -> Q16.16, round half up */
    }
    return QIBL_OK;
}

size_t qibl_shmap_span_workspace_size(uint32_t n)
{
    return (size_t)n * 3u * sizeof(int32_t);
}

#if QIBL_CONFIG_SIMD == QIBL_SIMD_SCALAR && !QIBL_CONFIG_SHMAP_BLOCKS
/* acc[p] (+)= sum of up to four planes times their int16 weights. Plain loops over restrict
 * pointers with 16-bit operands: compilers vectorise them (bytes widened to 16 bits, 16x16->32
 * products). Four maps per pass keeps the accumulator traffic at one load/store per four maps. */
static void acc_set4(int32_t *restrict acc, const uint8_t *restrict a, const uint8_t *restrict b,
                     const uint8_t *restrict c, const uint8_t *restrict d, int16_t wa, int16_t wb, int16_t wc,
                     int16_t wd, uint32_t n)
{
    for (uint32_t p = 0; p < n; ++p)
        acc[p] = wa * (int16_t)a[p] + wb * (int16_t)b[p] + wc * (int16_t)c[p] + wd * (int16_t)d[p];
}

static void acc_add4(int32_t *restrict acc, const uint8_t *restrict a, const uint8_t *restrict b,
                     const uint8_t *restrict c, const uint8_t *restrict d, int16_t wa, int16_t wb, int16_t wc,
                     int16_t wd, uint32_t n)
{
    for (uint32_t p = 0; p < n; ++p)
        acc[p] += wa * (int16_t)a[p] + wb * (int16_t)b[p] + wc * (int16_t)c[p] + wd * (int16_t)d[p];
}
#endif

/* Final pass of one channel: out = sat32(acc * 2^shift + bias) into the interleaved RGB row.
 * The common case (small shift, bias within +-2^30) stays in int32, which vectorises:
 * |acc| < 2^28 (shmap.h bound) so acc + 2^(n-1) and acc * 2^shift (shift <= 2) cannot overflow,
 * and |acc * 2^shift| + |bias| < 2^31. Other cases take the exact 64-bit path. */
static void finish_channel(const int32_t *restrict acc, int32_t shift, int64_t bias, int32_t *restrict out, uint32_t n)
{
    if (bias >= -(INT64_C(1) << 30) && bias <= (INT64_C(1) << 30) && shift <= 2) {
        const int32_t b32 = (int32_t)bias;
        if (shift >= 0) {
            const int32_t mul = (int32_t)1 << shift;
            for (uint32_t p = 0; p < n; ++p)
                out[3u * p] = acc[p] * mul + b32;
        } else if (shift > -31) {
            const unsigned rs = (unsigned)-shift;
            const int32_t half = (int32_t)1 << (rs - 1u);
            for (uint32_t p = 0; p < n; ++p)
                out[3u * p] = qibl_asr_s32(acc[p] + half, rs) + b32;
        } else {
            for (uint32_t p = 0; p < n; ++p)
                out[3u * p] = b32; /* round(acc / 2^31) = 0 for |acc| < 2^28 */
        }
    } else if (shift > 30) { /* any non-zero acc saturates */
        for (uint32_t p = 0; p < n; ++p)
            out[3u * p] = acc[p] > 0 ? INT32_MAX : acc[p] < 0 ? INT32_MIN : qibl_sat_s32(bias);
    } else if (shift >= 0) {
        const int32_t mul = (int32_t)1 << shift;
        for (uint32_t p = 0; p < n; ++p)
            out[3u * p] = qibl_sat_s32(qibl_mul_s32_s64(acc[p], mul) + bias);
    } else {
        const unsigned rs = (unsigned)-shift;
        for (uint32_t p = 0; p < n; ++p)
            out[3u * p] = qibl_sat_s32((int64_t)qibli_rshr_s64(acc[p], rs) + bias);
    }
}

/* The final pass's per-span constants. Common case: every channel takes the int32 path (see
 * finish_channel); finishing all three in one loop writes whole RGB pixels, which compilers
 * vectorise better than stride-3 stores. */
typedef struct finish {
    int fast;
    int32_t mu[3], h[3], b[3];
    unsigned r[3];
} finish_t;

static void finish_prepare(const qibl_shmap_weights_t *w, finish_t *f)
{
    f->fast = 1;
    for (uint32_t ch = 0; ch < 3u; ++ch) {
        int32_t sh = w->shift[ch];
        f->fast &= w->bias[ch] >= -(INT64_C(1) << 30) && w->bias[ch] <= (INT64_C(1) << 30) && sh > -31 && sh <= 2;
        f->mu[ch] = sh > 0 && sh <= 2 ? (int32_t)1 << sh : 1;
        f->r[ch] = sh < 0 && sh > -31 ? (unsigned)-sh : 0u;
        f->h[ch] = f->r[ch] != 0u ? (int32_t)1 << (f->r[ch] - 1u) : 0;
        f->b[ch] = f->fast ? (int32_t)w->bias[ch] : 0;
    }
}

#if QIBL_USE_INTERLEAVED || QIBL_CONFIG_SIMD != QIBL_SIMD_SCALAR || !QIBL_CONFIG_SHMAP_BLOCKS
/* out[3p + ch] = sat32(a_ch[p] * 2^shift + bias) for the n pixels of one span piece */
static void finish_rgb(const finish_t *f, const qibl_shmap_weights_t *w, const int32_t *restrict a0,
                       const int32_t *restrict a1, const int32_t *restrict a2, int32_t *restrict out, uint32_t n)
{
    if (f->fast) {
        const int32_t mu0 = f->mu[0], mu1 = f->mu[1], mu2 = f->mu[2], h0 = f->h[0], h1 = f->h[1], h2 = f->h[2];
        const int32_t b0 = f->b[0], b1 = f->b[1], b2 = f->b[2];
        const unsigned r0 = f->r[0], r1 = f->r[1], r2 = f->r[2];
        for (uint32_t p = 0; p < n; ++p) {
            out[3u * p] = qibl_asr_s32(a0[p] * mu0 + h0, r0) + b0;
            out[3u * p + 1u] = qibl_asr_s32(a1[p] * mu1 + h1, r1) + b1;
            out[3u * p + 2u] = qibl_asr_s32(a2[p] * mu2 + h2, r2) + b2;
        }
    } else {
        finish_channel(a0, w->shift[0], w->bias[0], out, n);
        finish_channel(a1, w->shift[1], w->bias[1], out + 1, n);
        finish_channel(a2, w->shift[2], w->bias[2], out + 2, n);
    }
}
#endif

#if QIBL_CONFIG_SIMD == QIBL_SIMD_SCALAR && QIBL_CONFIG_SHMAP_BLOCKS
/* ---- planar relight, portable scalar kernel (QIBL_CONFIG_SHMAP_BLOCKS, config.h) (the SIMD paths are further down) ---------------
 * One channel at a time, eight adjacent pixels per step: the k maps' bytes of
 * those pixels (aligned 32-bit words where the target and the alignment allow) go into one
 * accumulator per pixel held in registers, every map in one pass (no workspace round trip, no k
 * padded to a multiple), and the final scaling follows at once. Made for 32-bit cores without
 * SIMD (ARM7TDMI, Cortex-M): the products are 32x32->32 multiply-accumulates with the map byte as
 * the multiplier (ARMv4T's early termination: bits 8..31 zero). Same integers as every other path:
 * each product w * c has |.| <= 32767 * 255 < 2^23 and any partial sum of at most 25 of them is
 * below 2^28 in magnitude, so the sums are exact in any order. */

/* Word loads: with GCC or Clang on a little-endian target, the four bytes of a plane at an
 * aligned address are one 32-bit load, byte j in bits 8j..8j+7 (may_alias: the uint32 read of
 * map bytes is defined there); the caller proves the alignment (SHMAP_ALIGNED). Elsewhere bytes. */
#if (defined(__GNUC__) || defined(__clang__)) && defined(__BYTE_ORDER__) && defined(__ORDER_LITTLE_ENDIAN__) && \
    __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
#define SHMAP_WORD_LOADS 1
typedef uint32_t __attribute__((__may_alias__)) shmap_word_t;
#define SHMAP_ALIGNED(p) (((uintptr_t)(const void *)(p) & 3u) == 0u)
#define SHMAP_WORD(p) (*(const shmap_word_t *)(const void *)(p))
#else
#define SHMAP_WORD_LOADS 0
#endif

/* Pixels per step of the word kernel (8: measured best on ARM7TDMI ARM code, Cortex-M4 and, even
 * with its spills to the stack, Cortex-M0; 4 is kept for targets with few registers). */
#ifndef SHMAP_STEP
#define SHMAP_STEP 8u
#endif

/* One channel's span piece: map i of the channel at pixel p is q[i * stride + p]. The sums run
 * in uint32 from a start value u0 (wrapping arithmetic is defined there, and the true value
 * u0 + sum stays inside 0..2^32-1, see chan_fast); a pixel's result is (int32_t)(u >> r) + bb. */
typedef struct chan {
    const uint8_t *q; /* map 0's plane at the span's first pixel */
    size_t stride;    /* bytes from one map's plane to the next of the same channel */
    const int16_t *w; /* the channel's k weights */
    uint32_t k;
} chan_t;

static inline uint32_t px_sum(const chan_t *c, uint32_t p, uint32_t u0)
{
    const uint8_t *s = c->q + p;
    uint32_t a = u0;
    for (uint32_t i = 0; i < c->k; ++i, s += c->stride)
        a += (uint32_t)(int32_t)c->w[i] * *s;
    return a;
}

#if SHMAP_WORD_LOADS
/* out[3p] = (int32_t)(u_p >> r) + bb from pixel p on, SHMAP_STEP pixels at a time, one aligned
 * 32-bit load per plane and four pixels (eight: the plane's two words are one sequential burst,
 * and its weight load and loop step serve eight pixels); returns the first pixel not done. */
static uint32_t chan_words(const chan_t *c, uint32_t p, uint32_t n, uint32_t u0, unsigned r, int32_t bb,
                           int32_t *out)
{
    const size_t stride = c->stride;
    const int16_t *w = c->w, *wend = c->w + c->k;
    for (; p + SHMAP_STEP <= n; p += SHMAP_STEP) {
        const uint8_t *s = c->q + p;
        uint32_t a0 = u0, a1 = u0, a2 = u0, a3 = u0;
#if SHMAP_STEP == 8u
        uint32_t a4 = u0, a5 = u0, a6 = u0, a7 = u0;
#endif
        for (const int16_t *wi = w; wi < wend; ++wi, s += stride) {
            const uint32_t m = (uint32_t)(int32_t)*wi, v = SHMAP_WORD(s);
            a0 += m * (v & 255u), a1 += m * (v >> 8 & 255u), a2 += m * (v >> 16 & 255u), a3 += m * (v >> 24);
#if SHMAP_STEP == 8u
            const uint32_t x = SHMAP_WORD(s + 4);
            a4 += m * (x & 255u), a5 += m * (x >> 8 & 255u), a6 += m * (x >> 16 & 255u), a7 += m * (x >> 24);
#endif
        }
        int32_t *o = out + 3u * p;
        o[0] = (int32_t)(a0 >> r) + bb, o[3] = (int32_t)(a1 >> r) + bb;
        o[6] = (int32_t)(a2 >> r) + bb, o[9] = (int32_t)(a3 >> r) + bb;
#if SHMAP_STEP == 8u
        o[12] = (int32_t)(a4 >> r) + bb, o[15] = (int32_t)(a5 >> r) + bb;
        o[18] = (int32_t)(a6 >> r) + bb, o[21] = (int32_t)(a7 >> r) + bb;
#endif
    }
    return p;
}
#endif

/* The same four pixels at a time from bytes (no alignment known, or no word loads). Built for
 * size (-Os: the Cortex-M .text goal), those spans go one pixel at a time instead. */
#if !defined(__OPTIMIZE_SIZE__)
static uint32_t chan_bytes(const chan_t *c, uint32_t p, uint32_t n, uint32_t u0, unsigned r, int32_t bb, int32_t *out)
{
    const size_t stride = c->stride;
    for (; p + 4u <= n; p += 4u) {
        const uint8_t *s = c->q + p;
        uint32_t a0 = u0, a1 = u0, a2 = u0, a3 = u0;
        for (uint32_t i = 0; i < c->k; ++i, s += stride) {
            const uint32_t m = (uint32_t)(int32_t)c->w[i];
            a0 += m * s[0], a1 += m * s[1], a2 += m * s[2], a3 += m * s[3];
        }
        int32_t *o = out + 3u * p;
        o[0] = (int32_t)(a0 >> r) + bb, o[3] = (int32_t)(a1 >> r) + bb;
        o[6] = (int32_t)(a2 >> r) + bb, o[9] = (int32_t)(a3 >> r) + bb;
    }
    return p;
}
#endif

/* The fast final scaling of one channel straight into the RGB row (out: the channel's first
 * value, stride 3), for -31 < shift < 0 and |bias| <= 2^30 (finish_channel's first branch, same
 * integers): r = -shift, h = 2^(r-1), u0 = h + 2^31, so u = u0 + sum lies in (2^31 - 2^28,
 * 2^31 + 2^29 + 2^28) and u >> r = floor((sum + h) / 2^r) + 2^(31-r) < 2^31; bb = b - 2^(31-r)
 * is in [-2^31, 2^30] as r >= 1, and (int32_t)(u >> r) + bb = floor((sum + h) / 2^r) + b. */
static void chan_fast(const chan_t *c, uint32_t n, unsigned r, int32_t h, int32_t b, int32_t *out)
{
    const uint32_t u0 = (uint32_t)h + 0x80000000u;
    const int32_t bb = b - (int32_t)(0x80000000u >> r);
    uint32_t p = 0;
#if SHMAP_WORD_LOADS
    if (c->stride % 4u == 0u) {
        /* pixels one at a time up to the first aligned word; every plane is then aligned too */
        for (; p < n && !SHMAP_ALIGNED(c->q + p); ++p)
            out[3u * p] = (int32_t)(px_sum(c, p, u0) >> r) + bb;
        p = chan_words(c, p, n, u0, r, bb, out);
    }
#endif
#if !defined(__OPTIMIZE_SIZE__)
    p = chan_bytes(c, p, n, u0, r, bb, out);
#endif
    for (; p < n; ++p)
        out[3u * p] = (int32_t)(px_sum(c, p, u0) >> r) + bb;
}

/* The raw sums of one channel into acc (the workspace) for the general final scaling: int32 sums
 * inside the bound above, one pixel at a time (the rare case: a large shift or bias). */
static void chan_raw(const chan_t *c, uint32_t n, int32_t *acc)
{
    for (uint32_t p = 0; p < n; ++p) {
        const uint8_t *s = c->q + p;
        int32_t a = 0;
        for (uint32_t i = 0; i < c->k; ++i, s += c->stride)
            a += c->w[i] * (int32_t)*s;
        acc[p] = a;
    }
}
#endif /* scalar planar kernel */

#if QIBL_USE_INTERLEAVED || QIBL_CONFIG_SIMD != QIBL_SIMD_SCALAR
/* The weights of one span as the group and planar kernels take them: SSE2/AVX2 pmaddwd multiplies pairs of
 * maps, so the weights are int16 pairs (w_i, w_i+1) broadcast to every 32-bit lane, the pair of an
 * odd k's last map (w, 0); scalar C and NEON take the int16 weights as they are. */
#define SHMAP_PAIRS ((QIBL_SH_MAX_COUNT + 1) / 2)
typedef struct wprep {
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
    __m256i v[3][SHMAP_PAIRS];
    __m256i h8[3], b8[3]; /* the fast final scaling's constants in every lane */
#elif QIBL_CONFIG_SIMD == QIBL_SIMD_SSE2
    __m128i v[3][SHMAP_PAIRS];
#else
    const int16_t *w[3];
#endif
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2 || QIBL_CONFIG_SIMD == QIBL_SIMD_SSE2
    const int16_t *ws[3]; /* the int16 weights as they are (the planar kernel's last pixels) */
    __m128i sl[3], r[3], h[3], b[3]; /* the fast final scaling: shift counts and constants */
#elif QIBL_CONFIG_SIMD == QIBL_SIMD_NEON
    int32x4_t sl[3], r[3], h[3], b[3]; /* r negative: vshlq shifts right */
#endif
} wprep_t;

static void wprep_init(wprep_t *wp, const qibl_shmap_weights_t *w, const finish_t *f, uint32_t k)
{
#if QIBL_CONFIG_SIMD != QIBL_SIMD_SCALAR
    for (uint32_t ch = 0; ch < 3u; ++ch) {
        /* mu = 2^sl, as finish_prepare chose it */
        const int32_t sl = f->mu[ch] == 4 ? 2 : f->mu[ch] == 2 ? 1 : 0;
#if QIBL_CONFIG_SIMD == QIBL_SIMD_NEON
        wp->sl[ch] = vdupq_n_s32(sl), wp->r[ch] = vdupq_n_s32(-(int32_t)f->r[ch]);
        wp->h[ch] = vdupq_n_s32(f->h[ch]), wp->b[ch] = vdupq_n_s32(f->b[ch]);
#else
        wp->sl[ch] = _mm_cvtsi32_si128(sl), wp->r[ch] = _mm_cvtsi32_si128((int32_t)f->r[ch]);
        wp->h[ch] = _mm_set1_epi32(f->h[ch]), wp->b[ch] = _mm_set1_epi32(f->b[ch]);
#endif
    }
#else
    (void)f;
#endif
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2 || QIBL_CONFIG_SIMD == QIBL_SIMD_SSE2
    for (uint32_t ch = 0; ch < 3u; ++ch)
        for (uint32_t i = 0; i < k; i += 2u) {
            const int16_t a = w->w[ch][i], b = i + 1u < k ? w->w[ch][i + 1u] : 0;
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
            wp->v[ch][i / 2u] = _mm256_unpacklo_epi16(_mm256_set1_epi16(a), _mm256_set1_epi16(b));
#else
            wp->v[ch][i / 2u] = _mm_unpacklo_epi16(_mm_set1_epi16(a), _mm_set1_epi16(b));
#endif
        }
    for (uint32_t ch = 0; ch < 3u; ++ch)
        wp->ws[ch] = w->w[ch];
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
    for (uint32_t ch = 0; ch < 3u; ++ch)
        wp->h8[ch] = _mm256_set1_epi32(f->h[ch]), wp->b8[ch] = _mm256_set1_epi32(f->b[ch]);
#endif
#else
    (void)k;
    for (uint32_t ch = 0; ch < 3u; ++ch)
        wp->w[ch] = w->w[ch];
#endif
}

#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
/* w_i c_i + w_i+1 c_i+1 of one channel's 16 pixels added to lo (pixels 0..7) and hi (8..15);
 * y = zero bytes for an odd k's last map (its partner weight is 0) */
#define SHMAP_PAIR_AVX2(lo, hi, x, y, wv)                                                              \
    do {                                                                                               \
        lo = _mm256_add_epi32(lo, _mm256_madd_epi16(_mm256_cvtepu8_epi16(_mm_unpacklo_epi8(x, y)), wv)); \
        hi = _mm256_add_epi32(hi, _mm256_madd_epi16(_mm256_cvtepu8_epi16(_mm_unpackhi_epi8(x, y)), wv)); \
    } while (0)
#define SHMAP_LOAD16(p) _mm_loadu_si128((const __m128i *)(const void *)(p))
#endif
#endif /* wprep */

#if QIBL_USE_INTERLEAVED
/* One group of 16 pixels, one channel (AVX2: all three, group_sums): acc[p] = sum_i w_i
 * c[16 i + p] over the k maps' 16 adjacent bytes each (the interleaved layout). Same integer sums on
 * every path (exact: every partial sum is inside the int32 bound of shmap.h, whatever the order). */
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
/* Pairs of maps, the three channels in one pass, their six accumulators in registers. One 32-byte
 * load holds maps i | i+1; vpermq puts the same eight pixels of both in one lane (pixels 0-7 |
 * 8-15) and one vpshufb per four pixels makes the zero-extended int16 pairs (c_i, c_i+1) that
 * vpmaddwd multiplies by (w_i, w_i+1): three shuffles per two vpmaddwd (vpmovzxbw of unpacked
 * 16-byte halves took four, docs/results/dir-designs.txt), and the lanes hold pixels, not maps, so
 * nothing is folded at the end. s[ch][0] holds pixels 0-3 | 8-11, s[ch][1] pixels 4-7 | 12-15.
 * init: the accumulators' start (the final scaling's rounding term, or 0). An odd k's last map
 * is loaded alone (16 bytes: never past the channel), its partner zero under weight 0. */
static inline void group_sums(__m256i s[3][2], const uint8_t *c, uint32_t cs, const wprep_t *wp, uint32_t k,
                              const __m256i init[3])
{
    const __m256i m0 = _mm256_setr_epi8(0, -1, 8, -1, 1, -1, 9, -1, 2, -1, 10, -1, 3, -1, 11, -1, 0, -1, 8, -1, 1, -1,
                                        9, -1, 2, -1, 10, -1, 3, -1, 11, -1);
    const __m256i m1 = _mm256_setr_epi8(4, -1, 12, -1, 5, -1, 13, -1, 6, -1, 14, -1, 7, -1, 15, -1, 4, -1, 12, -1, 5,
                                        -1, 13, -1, 6, -1, 14, -1, 7, -1, 15, -1);
    __m256i r0 = init[0], r1 = init[0], g0 = init[1], g1 = init[1], b0 = init[2], b1 = init[2];
    const uint8_t *c1 = c + cs, *c2 = c + 2u * cs;
#define SHMAP_PAIR3(a0, a1, x, w)                                                                     \
    do {                                                                                               \
        const __m256i y_ = _mm256_permute4x64_epi64(x, 0xD8);                                          \
        a0 = _mm256_add_epi32(a0, _mm256_madd_epi16(_mm256_shuffle_epi8(y_, m0), w));                  \
        a1 = _mm256_add_epi32(a1, _mm256_madd_epi16(_mm256_shuffle_epi8(y_, m1), w));                  \
    } while (0)
#define SHMAP_LOAD32(p) _mm256_loadu_si256((const __m256i *)(const void *)(p))
#define SHMAP_PAIRS3_AT(j)                                                                             \
    do {                                                                                               \
        SHMAP_PAIR3(r0, r1, SHMAP_LOAD32(c + 32u * (j)), wp->v[0][j]);                                 \
        SHMAP_PAIR3(g0, g1, SHMAP_LOAD32(c1 + 32u * (j)), wp->v[1][j]);                                \
        SHMAP_PAIR3(b0, b1, SHMAP_LOAD32(c2 + 32u * (j)), wp->v[2][j]);                                \
    } while (0)
    /* whole pairs written out (k <= 25): as a loop, gcc copied the six accumulators and rebuilt the
     * indices at every step */
    switch (k / 2u) {
    case 12u:
        SHMAP_PAIRS3_AT(11u); /* fallthrough */
    case 11u:
        SHMAP_PAIRS3_AT(10u); /* fallthrough */
    case 10u:
        SHMAP_PAIRS3_AT(9u); /* fallthrough */
    case 9u:
        SHMAP_PAIRS3_AT(8u); /* fallthrough */
    case 8u:
        SHMAP_PAIRS3_AT(7u); /* fallthrough */
    case 7u:
        SHMAP_PAIRS3_AT(6u); /* fallthrough */
    case 6u:
        SHMAP_PAIRS3_AT(5u); /* fallthrough */
    case 5u:
        SHMAP_PAIRS3_AT(4u); /* fallthrough */
    case 4u:
        SHMAP_PAIRS3_AT(3u); /* fallthrough */
    case 3u:
        SHMAP_PAIRS3_AT(2u); /* fallthrough */
    case 2u:
        SHMAP_PAIRS3_AT(1u); /* fallthrough */
    case 1u:
        SHMAP_PAIRS3_AT(0u); /* fallthrough */
    default:
        break;
    }
    if (k & 1u) { /* an odd k's last map: 16 bytes, zero above them under weight 0 */
        const uint32_t o = 16u * (k - 1u);
        const __m256i z = _mm256_setzero_si256();
        SHMAP_PAIR3(r0, r1, _mm256_inserti128_si256(z, SHMAP_LOAD16(c + o), 0), wp->v[0][k / 2u]);
        SHMAP_PAIR3(g0, g1, _mm256_inserti128_si256(z, SHMAP_LOAD16(c1 + o), 0), wp->v[1][k / 2u]);
        SHMAP_PAIR3(b0, b1, _mm256_inserti128_si256(z, SHMAP_LOAD16(c2 + o), 0), wp->v[2][k / 2u]);
    }
#undef SHMAP_PAIRS3_AT
#undef SHMAP_LOAD32
#undef SHMAP_PAIR3
    s[0][0] = r0, s[0][1] = r1, s[1][0] = g0, s[1][1] = g1, s[2][0] = b0, s[2][1] = b1;
}

/* The fast final scaling of a whole group from the registers: (s << sl) >> r + b per channel (the
 * rounding term h already in s; sl > 0 only where r = 0 = h, shl says whether any channel has it),
 * then per 128-bit lane (4 pixels) the unpacks and shuffles of finish4: lane 0 of s[.][0] and
 * s[.][1] holds pixels 0-3 and 4-7, lane 1 pixels 8-11 and 12-15, each lane stored as 16 bytes. */
static inline void group_finish(int32_t *o, __m256i s[3][2], const wprep_t *wp, int shl)
{
    for (int half = 0; half < 2; ++half) {
        __m256i v[3];
        for (int ch = 0; ch < 3; ++ch) {
            __m256i a = s[ch][half];
            if (shl)
                a = _mm256_sll_epi32(a, wp->sl[ch]);
            v[ch] = _mm256_add_epi32(_mm256_sra_epi32(a, wp->r[ch]), wp->b8[ch]);
        }
        const __m256 rg = _mm256_castsi256_ps(_mm256_unpacklo_epi32(v[0], v[1]));
        const __m256 rgh = _mm256_castsi256_ps(_mm256_unpackhi_epi32(v[0], v[1]));
        const __m256 br = _mm256_castsi256_ps(_mm256_unpacklo_epi32(v[2], v[0]));
        const __m256 brh = _mm256_castsi256_ps(_mm256_unpackhi_epi32(v[2], v[0]));
        const __m256 gb = _mm256_castsi256_ps(_mm256_unpacklo_epi32(v[1], v[2]));
        const __m256 gbh = _mm256_castsi256_ps(_mm256_unpackhi_epi32(v[1], v[2]));
        const __m256i o0 = _mm256_castps_si256(_mm256_shuffle_ps(rg, br, _MM_SHUFFLE(3, 0, 1, 0)));
        const __m256i o1 = _mm256_castps_si256(_mm256_shuffle_ps(gb, rgh, _MM_SHUFFLE(1, 0, 3, 2)));
        const __m256i o2 = _mm256_castps_si256(_mm256_shuffle_ps(brh, gbh, _MM_SHUFFLE(3, 2, 3, 0)));
        int32_t *d = o + 12 * half, *e = d + 24;
        _mm_storeu_si128((__m128i *)(void *)d, _mm256_castsi256_si128(o0));
        _mm_storeu_si128((__m128i *)(void *)(d + 4), _mm256_castsi256_si128(o1));
        _mm_storeu_si128((__m128i *)(void *)(d + 8), _mm256_castsi256_si128(o2));
        _mm_storeu_si128((__m128i *)(void *)e, _mm256_extracti128_si256(o0, 1));
        _mm_storeu_si128((__m128i *)(void *)(e + 4), _mm256_extracti128_si256(o1, 1));
        _mm_storeu_si128((__m128i *)(void *)(e + 8), _mm256_extracti128_si256(o2, 1));
    }
}
#if defined(QIBLI_SHMAP_AVX512)
/* AVX-512 VNNI (x86/shmap_avx512.c only): a whole group, all three channels, from four maps a
 * step. One 64-byte load holds maps 4j..4j+3 (16 bytes each); vpermd and vpshufb transpose it so
 * that dword p holds pixel p's four bytes, one per map, and vpdpbusd sums four byte products a
 * lane. Its operands are unsigned by signed bytes, so each weight is split w = 256 (w >> 8) +
 * (w & 255), both parts as bytes: sum c (w >> 8) with the maps' bytes unsigned, and sum (w & 255)
 * (c - 128) with the low parts unsigned and c ^ 0x80 signed, 128 sum (w & 255) added back in the
 * start value. Exact for every int16 weight: |sum c (w >> 8)| <= 25 * 255 * 128 < 2^20, so 256
 * times it and the low sum stay inside int32, and the total is the sum of the AVX2 kernel (its
 * bound in shmap.h). Three uops on the shuffle port and two multiply-adds per four maps and
 * channel, against six and four per four maps for the AVX2 pairs. */
#define SHMAP_QUADS ((QIBL_SH_MAX_COUNT + 3) / 4)
typedef struct wprep16 {
    __m512i wh[3][SHMAP_QUADS], wl[3][SHMAP_QUADS]; /* the weights' bytes, four maps in every lane */
    __m512i init[3], b[3]; /* h + 128 sum (w & 255); the bias */
} wprep16_t;

static void wprep16_init(wprep16_t *wq, const qibl_shmap_weights_t *w, const finish_t *f, uint32_t k)
{
    for (uint32_t ch = 0; ch < 3u; ++ch) {
        int32_t lsum = 0;
        for (uint32_t j = 0; j < (k + 3u) / 4u; ++j) {
            uint32_t hi = 0u, lo = 0u;
            for (uint32_t b = 0; b < 4u; ++b) {
                const uint32_t i = 4u * j + b;
                const uint32_t wu = i < k ? (uint32_t)(uint16_t)w->w[ch][i] : 0u;
                hi |= (wu >> 8) << (8u * b), lo |= (wu & 255u) << (8u * b); /* w >> 8 as a signed byte */
                lsum += (int32_t)(wu & 255u);
            }
            wq->wh[ch][j] = _mm512_set1_epi32((int32_t)hi), wq->wl[ch][j] = _mm512_set1_epi32((int32_t)lo);
        }
        wq->init[ch] = _mm512_set1_epi32(f->h[ch] + 128 * lsum);
        wq->b[ch] = _mm512_set1_epi32(f->b[ch]);
    }
}

/* group_sums and group_finish of one whole group in 512-bit lanes: the same integers */
static inline void group16(int32_t *o, const uint8_t *c, uint32_t cs, uint32_t k, const wprep16_t *wq,
                           const wprep_t *wp, int shl)
{
    const __m512i tp = _mm512_setr_epi32(0, 4, 8, 12, 1, 5, 9, 13, 2, 6, 10, 14, 3, 7, 11, 15);
    const __m512i tb = _mm512_broadcast_i32x4(_mm_setr_epi8(0, 4, 8, 12, 1, 5, 9, 13, 2, 6, 10, 14, 3, 7, 11, 15));
    const __m512i x80 = _mm512_set1_epi32((int32_t)0x80808080u);
    __m512i ah[3], al[3];
    for (uint32_t ch = 0; ch < 3u; ++ch)
        ah[ch] = _mm512_setzero_si512(), al[ch] = wq->init[ch];
    /* lane L dword m of the transposed load: pixels 4L..4L+3 of map m; then byte m of dword p is
     * map m of pixel p */
#define SHMAP_QUAD(ch, x)                                                                               \
    do {                                                                                                \
        const __m512i t_ = _mm512_shuffle_epi8(_mm512_permutexvar_epi32(tp, (x)), tb);                  \
        ah[ch] = _mm512_dpbusd_epi32(ah[ch], t_, wq->wh[ch][j]);                                         \
        al[ch] = _mm512_dpbusd_epi32(al[ch], wq->wl[ch][j], _mm512_xor_si512(t_, x80));                  \
    } while (0)
    uint32_t j = 0;
    for (; 4u * j + 4u <= k; ++j)
        for (uint32_t ch = 0; ch < 3u; ++ch)
            SHMAP_QUAD(ch, _mm512_loadu_si512((const void *)(c + ch * cs + 64u * j)));
    if (k & 3u) { /* the last 1-3 maps: a masked load (no byte past the channel), zeros under weight 0 */
        const __mmask64 mk = ((__mmask64)1 << (16u * (k & 3u))) - 1u;
        for (uint32_t ch = 0; ch < 3u; ++ch)
            SHMAP_QUAD(ch, _mm512_maskz_loadu_epi8(mk, (const void *)(c + ch * cs + 64u * j)));
    }
#undef SHMAP_QUAD
    __m512i v[3];
    for (uint32_t ch = 0; ch < 3u; ++ch) {
        __m512i a = _mm512_add_epi32(_mm512_slli_epi32(ah[ch], 8), al[ch]);
        if (shl)
            a = _mm512_sll_epi32(a, wp->sl[ch]);
        v[ch] = _mm512_add_epi32(_mm512_sra_epi32(a, wp->r[ch]), wq->b[ch]);
    }
    /* RGB interleaved: output word j is channel j % 3 of pixel j / 3 (as p16_finish) */
    _mm512_storeu_si512((void *)o, _mm512_permutex2var_epi32(
        _mm512_permutex2var_epi32(v[0], _mm512_setr_epi32(0, 16, 0, 1, 17, 0, 2, 18, 0, 3, 19, 0, 4, 20, 0, 5), v[1]),
        _mm512_setr_epi32(0, 1, 16, 3, 4, 17, 6, 7, 18, 9, 10, 19, 12, 13, 20, 15), v[2]));
    _mm512_storeu_si512((void *)(o + 16), _mm512_permutex2var_epi32(
        _mm512_permutex2var_epi32(v[0], _mm512_setr_epi32(21, 0, 6, 22, 0, 7, 23, 0, 8, 24, 0, 9, 25, 0, 10, 26), v[1]),
        _mm512_setr_epi32(0, 21, 2, 3, 22, 5, 6, 23, 8, 9, 24, 11, 12, 25, 14, 15), v[2]));
    _mm512_storeu_si512((void *)(o + 32), _mm512_permutex2var_epi32(
        _mm512_permutex2var_epi32(v[0], _mm512_setr_epi32(0, 11, 27, 0, 12, 28, 0, 13, 29, 0, 14, 30, 0, 15, 31, 0), v[1]),
        _mm512_setr_epi32(26, 1, 2, 27, 4, 5, 28, 7, 8, 29, 10, 11, 30, 13, 14, 31), v[2]));
}
#endif
#elif QIBL_CONFIG_SIMD == QIBL_SIMD_SSE2
/* as the AVX2 kernel, 4 pixels per pmaddwd */
static void group_acc(int32_t *acc, const uint8_t *c, const wprep_t *wp, uint32_t ch, uint32_t k)
{
    const __m128i z = _mm_setzero_si128();
    __m128i a0 = z, a1 = z, a2 = z, a3 = z;
    const __m128i *wv = wp->v[ch];
    const uint8_t *m = c, *end = c + 16u * (k & ~1u);
    /* one channel per call: three channels' 12 accumulators in one loop spill the 16 registers */
    for (; m < end; m += 32, ++wv) {
        const __m128i x = _mm_loadu_si128((const __m128i *)(const void *)m);
        const __m128i y = _mm_loadu_si128((const __m128i *)(const void *)(m + 16));
        const __m128i lo = _mm_unpacklo_epi8(x, y), hi = _mm_unpackhi_epi8(x, y);
        a0 = _mm_add_epi32(a0, _mm_madd_epi16(_mm_unpacklo_epi8(lo, z), *wv));
        a1 = _mm_add_epi32(a1, _mm_madd_epi16(_mm_unpackhi_epi8(lo, z), *wv));
        a2 = _mm_add_epi32(a2, _mm_madd_epi16(_mm_unpacklo_epi8(hi, z), *wv));
        a3 = _mm_add_epi32(a3, _mm_madd_epi16(_mm_unpackhi_epi8(hi, z), *wv));
    }
    if (k & 1u) { /* an odd k: the last map, its missing partner zero bytes under weight 0 */
        const __m128i x = _mm_loadu_si128((const __m128i *)(const void *)m);
        const __m128i lo = _mm_unpacklo_epi8(x, z), hi = _mm_unpackhi_epi8(x, z);
        a0 = _mm_add_epi32(a0, _mm_madd_epi16(_mm_unpacklo_epi16(lo, z), *wv));
        a1 = _mm_add_epi32(a1, _mm_madd_epi16(_mm_unpackhi_epi16(lo, z), *wv));
        a2 = _mm_add_epi32(a2, _mm_madd_epi16(_mm_unpacklo_epi16(hi, z), *wv));
        a3 = _mm_add_epi32(a3, _mm_madd_epi16(_mm_unpackhi_epi16(hi, z), *wv));
    }
    _mm_storeu_si128((__m128i *)(void *)acc, a0);
    _mm_storeu_si128((__m128i *)(void *)(acc + 4), a1);
    _mm_storeu_si128((__m128i *)(void *)(acc + 8), a2);
    _mm_storeu_si128((__m128i *)(void *)(acc + 12), a3);
}
#elif QIBL_CONFIG_SIMD == QIBL_SIMD_NEON
/* bytes widened to int16 (vmovl_u8), then int32 += int16 * weight (vmlal_n_s16), 4 pixels a lane */
static void group_acc(int32_t *acc, const uint8_t *c, const wprep_t *wp, uint32_t ch, uint32_t k)
{
    int32x4_t a0 = vdupq_n_s32(0), a1 = a0, a2 = a0, a3 = a0;
    const int16_t *wc = wp->w[ch];
    for (uint32_t i = 0; i < k; ++i) {
        const uint8x16_t x = vld1q_u8(c + 16u * i);
        const int16x8_t lo = vreinterpretq_s16_u16(vmovl_u8(vget_low_u8(x)));
        const int16x8_t hi = vreinterpretq_s16_u16(vmovl_u8(vget_high_u8(x)));
        const int16_t wi = wc[i];
        a0 = vmlal_n_s16(a0, vget_low_s16(lo), wi);
        a1 = vmlal_n_s16(a1, vget_high_s16(lo), wi);
        a2 = vmlal_n_s16(a2, vget_low_s16(hi), wi);
        a3 = vmlal_n_s16(a3, vget_high_s16(hi), wi);
    }
    vst1q_s32(acc, a0);
    vst1q_s32(acc + 4, a1);
    vst1q_s32(acc + 8, a2);
    vst1q_s32(acc + 12, a3);
}
#else
/* Scalar reference, four maps per pass as the planar passes. Not inlined (QIBLI_NOINLINE):
 * inlined, the compiler loses the restrict parameters and checks aliasing or scalarises the loops;
 * as a call it vectorises them (one call per channel and 16 pixels). */
static QIBLI_NOINLINE void group_acc(int32_t *restrict acc, const uint8_t *restrict c, const wprep_t *wp, uint32_t ch,
                                     uint32_t k)
{
    enum { G = QIBL_SHMAPS_GROUP };
    const int16_t *restrict wc = wp->w[ch];
    uint32_t i = 0;
    for (uint32_t p = 0; p < G; ++p)
        acc[p] = 0;
    for (; i + 4u <= k; i += 4u) {
        const int16_t w0 = wc[i], w1 = wc[i + 1u], w2 = wc[i + 2u], w3 = wc[i + 3u];
        const uint8_t *m = c + G * i;
        for (uint32_t p = 0; p < G; ++p)
            acc[p] += w0 * (int16_t)m[p] + w1 * (int16_t)m[G + p] + w2 * (int16_t)m[2 * G + p] +
                      w3 * (int16_t)m[3 * G + p];
    }
    for (; i < k; ++i) {
        const int16_t w0 = wc[i];
        const uint8_t *m = c + G * i;
        for (uint32_t p = 0; p < G; ++p)
            acc[p] += w0 * (int16_t)m[p];
    }
}
#endif
#endif /* QIBL_USE_INTERLEAVED */

#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2 || QIBL_CONFIG_SIMD == QIBL_SIMD_SSE2
/* 4 pixels of the fast final scaling, (acc << sl + h) >> r + b per channel (as finish_rgb: the
 * int32 products cannot overflow there), stored as RGB triples: unpacks and shuffles put
 * r0 g0 b0 r1 | g1 b1 r2 g2 | b2 r3 g3 b3 in three stores */
static void finish4(int32_t *o, const int32_t *a0, const int32_t *a1, const int32_t *a2, const wprep_t *wp)
{
    __m128i v[3];
    const int32_t *a[3] = {a0, a1, a2};
    for (int ch = 0; ch < 3; ++ch) {
        const __m128i x = _mm_loadu_si128((const __m128i *)(const void *)a[ch]);
        v[ch] = _mm_add_epi32(_mm_sra_epi32(_mm_add_epi32(_mm_sll_epi32(x, wp->sl[ch]), wp->h[ch]), wp->r[ch]),
                              wp->b[ch]);
    }
    const __m128 rg = _mm_castsi128_ps(_mm_unpacklo_epi32(v[0], v[1])), rgh = _mm_castsi128_ps(_mm_unpackhi_epi32(v[0], v[1]));
    const __m128 br = _mm_castsi128_ps(_mm_unpacklo_epi32(v[2], v[0])), brh = _mm_castsi128_ps(_mm_unpackhi_epi32(v[2], v[0]));
    const __m128 gb = _mm_castsi128_ps(_mm_unpacklo_epi32(v[1], v[2])), gbh = _mm_castsi128_ps(_mm_unpackhi_epi32(v[1], v[2]));
    _mm_storeu_si128((__m128i *)(void *)o, _mm_castps_si128(_mm_shuffle_ps(rg, br, _MM_SHUFFLE(3, 0, 1, 0))));
    _mm_storeu_si128((__m128i *)(void *)(o + 4), _mm_castps_si128(_mm_shuffle_ps(gb, rgh, _MM_SHUFFLE(1, 0, 3, 2))));
    _mm_storeu_si128((__m128i *)(void *)(o + 8), _mm_castps_si128(_mm_shuffle_ps(brh, gbh, _MM_SHUFFLE(3, 2, 3, 0))));
}
#elif QIBL_CONFIG_SIMD == QIBL_SIMD_NEON
/* as above; vshlq shifts left by sl, then right by r (a negative count: an arithmetic shift, the
 * same floor as qibl_asr_s32), and vst3q stores the RGB triples */
static void finish4(int32_t *o, const int32_t *a0, const int32_t *a1, const int32_t *a2, const wprep_t *wp)
{
    int32x4x3_t v;
    v.val[0] = vaddq_s32(vshlq_s32(vaddq_s32(vshlq_s32(vld1q_s32(a0), wp->sl[0]), wp->h[0]), wp->r[0]), wp->b[0]);
    v.val[1] = vaddq_s32(vshlq_s32(vaddq_s32(vshlq_s32(vld1q_s32(a1), wp->sl[1]), wp->h[1]), wp->r[1]), wp->b[1]);
    v.val[2] = vaddq_s32(vshlq_s32(vaddq_s32(vshlq_s32(vld1q_s32(a2), wp->sl[2]), wp->h[2]), wp->r[2]), wp->b[2]);
    vst3q_s32(o, v);
}
#endif

#if QIBL_CONFIG_SIMD != QIBL_SIMD_SCALAR
/* Planar layout, SIMD: planes in passes of at most SHMAP_PASS, each pass adding its planes into the
 * channel's int32 accumulators (the span workspace) 16 pixels at a time, the accumulators in
 * registers across the pass. Why passes: the planes of an asset lie a multiple of 4 KiB apart, so
 * the same pixel of every plane falls in one L1 set; 16 planes read side by side evict each other
 * from an 8-way L1 before the next 16 pixels use the rest of their lines. Same integers as the
 * scalar passes (exact sums inside the int32 bound of shmap.h, in any order). */
#define SHMAP_PASS 8u /* planar_pass writes out its 8 plane pointers (q0..q7) */

/* acc[p] (+)= sum_j w_(i0+j) pl[j][p] for p < n, cnt <= SHMAP_PASS planes from map i0 (even) */
static void planar_pass(int32_t *acc, const uint8_t *const *pl, const wprep_t *wp, uint32_t ch, uint32_t i0,
                        uint32_t cnt, uint32_t n, int first)
{
    uint32_t p = 0;
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2 || QIBL_CONFIG_SIMD == QIBL_SIMD_SSE2
    /* pairs of planes, written out (a loop over a variable count costs a third at gcc -O2): np
     * pairs; an odd count's last plane pairs with itself under its pair weights (w, 0) */
    const uint32_t np = (cnt + 1u) / 2u;
    const uint8_t *q[SHMAP_PASS];
    for (uint32_t j = 0; j < SHMAP_PASS; ++j)
        q[j] = pl[j < cnt ? j : cnt - 1u];
    const uint8_t *q0 = q[0], *q1 = q[1], *q2 = q[2], *q3 = q[3], *q4 = q[4], *q5 = q[5], *q6 = q[6], *q7 = q[7];
#endif
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
    /* bytes of two planes interleaved, widened to int16, one _mm256_madd_epi16 per 8 pixels */
    const __m256i *wv = wp->v[ch] + i0 / 2u, zw = _mm256_setzero_si256();
    const __m256i w0 = wv[0], w1 = np > 1u ? wv[1] : zw, w2 = np > 2u ? wv[2] : zw, w3 = np > 3u ? wv[3] : zw;
    for (; p + 16u <= n; p += 16u) {
        __m256i a0 = zw, a1 = zw;
        if (!first) {
            a0 = _mm256_loadu_si256((const __m256i *)(const void *)(acc + p));
            a1 = _mm256_loadu_si256((const __m256i *)(const void *)(acc + p + 8u));
        }
        SHMAP_PAIR_AVX2(a0, a1, SHMAP_LOAD16(q0 + p), SHMAP_LOAD16(q1 + p), w0);
        if (np > 1u)
            SHMAP_PAIR_AVX2(a0, a1, SHMAP_LOAD16(q2 + p), SHMAP_LOAD16(q3 + p), w1);
        if (np > 2u)
            SHMAP_PAIR_AVX2(a0, a1, SHMAP_LOAD16(q4 + p), SHMAP_LOAD16(q5 + p), w2);
        if (np > 3u)
            SHMAP_PAIR_AVX2(a0, a1, SHMAP_LOAD16(q6 + p), SHMAP_LOAD16(q7 + p), w3);
        _mm256_storeu_si256((__m256i *)(void *)(acc + p), a0);
        _mm256_storeu_si256((__m256i *)(void *)(acc + p + 8u), a1);
    }
#elif QIBL_CONFIG_SIMD == QIBL_SIMD_SSE2
    const __m128i *wv = wp->v[ch] + i0 / 2u, z = _mm_setzero_si128();
    const __m128i w0 = wv[0], w1 = np > 1u ? wv[1] : z, w2 = np > 2u ? wv[2] : z, w3 = np > 3u ? wv[3] : z;
/* w_j c_j + w_j+1 c_j+1 of 16 pixels into a0..a3: bytes interleaved, widened against zero */
#define SHMAP_PAIR_SSE2(xp, yp, wpair)                                                                 \
    do {                                                                                               \
        const __m128i x_ = _mm_loadu_si128((const __m128i *)(const void *)(xp));                       \
        const __m128i y_ = _mm_loadu_si128((const __m128i *)(const void *)(yp));                       \
        const __m128i lo_ = _mm_unpacklo_epi8(x_, y_), hi_ = _mm_unpackhi_epi8(x_, y_);                \
        a0 = _mm_add_epi32(a0, _mm_madd_epi16(_mm_unpacklo_epi8(lo_, z), wpair));                      \
        a1 = _mm_add_epi32(a1, _mm_madd_epi16(_mm_unpackhi_epi8(lo_, z), wpair));                      \
        a2 = _mm_add_epi32(a2, _mm_madd_epi16(_mm_unpacklo_epi8(hi_, z), wpair));                      \
        a3 = _mm_add_epi32(a3, _mm_madd_epi16(_mm_unpackhi_epi8(hi_, z), wpair));                      \
    } while (0)
    for (; p + 16u <= n; p += 16u) {
        __m128i a0 = z, a1 = z, a2 = z, a3 = z;
        if (!first) {
            a0 = _mm_loadu_si128((const __m128i *)(const void *)(acc + p));
            a1 = _mm_loadu_si128((const __m128i *)(const void *)(acc + p + 4u));
            a2 = _mm_loadu_si128((const __m128i *)(const void *)(acc + p + 8u));
            a3 = _mm_loadu_si128((const __m128i *)(const void *)(acc + p + 12u));
        }
        SHMAP_PAIR_SSE2(q0 + p, q1 + p, w0);
        if (np > 1u)
            SHMAP_PAIR_SSE2(q2 + p, q3 + p, w1);
        if (np > 2u)
            SHMAP_PAIR_SSE2(q4 + p, q5 + p, w2);
        if (np > 3u)
            SHMAP_PAIR_SSE2(q6 + p, q7 + p, w3);
        _mm_storeu_si128((__m128i *)(void *)(acc + p), a0);
        _mm_storeu_si128((__m128i *)(void *)(acc + p + 4u), a1);
        _mm_storeu_si128((__m128i *)(void *)(acc + p + 8u), a2);
        _mm_storeu_si128((__m128i *)(void *)(acc + p + 12u), a3);
    }
#undef SHMAP_PAIR_SSE2
#else /* NEON: bytes widened to int16, int32 += int16 * weight (vmlal_n_s16) */
    const int16_t *wc = wp->w[ch] + i0;
    for (; p + 16u <= n; p += 16u) {
        int32x4_t a0 = vdupq_n_s32(0), a1 = a0, a2 = a0, a3 = a0;
        if (!first)
            a0 = vld1q_s32(acc + p), a1 = vld1q_s32(acc + p + 4u), a2 = vld1q_s32(acc + p + 8u),
            a3 = vld1q_s32(acc + p + 12u);
        for (uint32_t j = 0; j < cnt; ++j) {
            const uint8x16_t x = vld1q_u8(pl[j] + p);
            const int16x8_t lo = vreinterpretq_s16_u16(vmovl_u8(vget_low_u8(x)));
            const int16x8_t hi = vreinterpretq_s16_u16(vmovl_u8(vget_high_u8(x)));
            a0 = vmlal_n_s16(a0, vget_low_s16(lo), wc[j]);
            a1 = vmlal_n_s16(a1, vget_high_s16(lo), wc[j]);
            a2 = vmlal_n_s16(a2, vget_low_s16(hi), wc[j]);
            a3 = vmlal_n_s16(a3, vget_high_s16(hi), wc[j]);
        }
        vst1q_s32(acc + p, a0), vst1q_s32(acc + p + 4u, a1), vst1q_s32(acc + p + 8u, a2);
        vst1q_s32(acc + p + 12u, a3);
    }
#endif
    /* the last n % 16 pixels */
#if QIBL_CONFIG_SIMD == QIBL_SIMD_NEON
    const int16_t *ws = wc;
#else
    const int16_t *ws = wp->ws[ch] + i0;
#endif
    for (; p < n; ++p) {
        int32_t a = first ? 0 : acc[p];
        for (uint32_t j = 0; j < cnt; ++j)
            a += ws[j] * (int32_t)pl[j][p];
        acc[p] = a;
    }
}

/* Directional relighting on the planar layout: per channel, passes of SHMAP_PASS planes into the
 * workspace, then the final scaling 4 pixels at a time (finish4) in the common case. */
static void relight_planar(const qibl_shmaps_t *m, const qibl_shmap_weights_t *w, const finish_t *f, size_t off,
                           uint32_t n, int32_t *out, int32_t *acc)
{
    wprep_t wp;
    wprep_init(&wp, w, f, m->k);
    for (uint32_t ch = 0; ch < 3u; ++ch) {
        const uint32_t src = m->channels == 3u ? ch : 0u;
        for (uint32_t i0 = 0; i0 < m->k; i0 += SHMAP_PASS) {
            const uint32_t cnt = m->k - i0 < SHMAP_PASS ? m->k - i0 : SHMAP_PASS;
            const uint8_t *pl[SHMAP_PASS];
            for (uint32_t j = 0; j < cnt; ++j)
                pl[j] = qibl_shmaps_plane(m, i0 + j, src) + off;
            planar_pass(acc + (size_t)ch * n, pl, &wp, ch, i0, cnt, n, i0 == 0u);
        }
    }
    const int32_t *a0 = acc, *a1 = acc + n, *a2 = acc + 2u * n;
    uint32_t p = 0;
    if (f->fast)
        for (; p + 4u <= n; p += 4u)
            finish4(out + 3u * p, a0 + p, a1 + p, a2 + p, &wp);
    if (p < n)
        finish_rgb(f, w, a0 + p, a1 + p, a2 + p, out + 3u * p, n - p);
}
#endif /* SIMD planar */

#if QIBL_USE_INTERLEAVED
/* Directional relighting on the interleaved layout: group by group, no workspace (the 16-pixel
 * accumulators live on the stack); whole groups in the common case finish in a fixed-length loop,
 * pixels of a partial group outside the span are computed from the row's bytes (padding included)
 * and not written. */
static void relight_interleaved(const qibl_shmaps_t *m, const qibl_shmap_weights_t *w, const finish_t *f,
                                uint32_t x0, uint32_t y, uint32_t n, int32_t *out)
{
    const uint32_t k = m->k, gbytes = QIBL_SHMAPS_GROUP * k * m->channels;
    const uint32_t cs = m->channels == 3u ? QIBL_SHMAPS_GROUP * k : 0u; /* channel stride in a group */
    const uint8_t *row = m->planes + (size_t)y * qibl_shmaps_row_size(m);
    int32_t acc[3][QIBL_SHMAPS_GROUP];
    wprep_t wp;
    wprep_init(&wp, w, f, k);
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
    const __m256i zero3[3] = {_mm256_setzero_si256(), _mm256_setzero_si256(), _mm256_setzero_si256()};
    const int shl = f->mu[0] != 1 || f->mu[1] != 1 || f->mu[2] != 1;
#endif
#if defined(QIBLI_SHMAP_AVX512)
    wprep16_t wq;
    if (f->fast)
        wprep16_init(&wq, w, f, k);
#endif
    for (uint32_t x = x0, end = x0 + n; x < end;) {
        const uint32_t p0 = x % QIBL_SHMAPS_GROUP, left = QIBL_SHMAPS_GROUP - p0;
        const uint32_t cnt = end - x < left ? end - x : left;
        const uint8_t *grp = row + (size_t)(x / QIBL_SHMAPS_GROUP) * gbytes;
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
        /* the sums in registers, the rounding term in them from the start when the whole group
         * takes the fast final scaling, which then runs from the registers */
        __m256i s[3][2];
        const int whole = cnt == QIBL_SHMAPS_GROUP && f->fast;
#if defined(QIBLI_SHMAP_AVX512)
        if (whole) {
            group16(out + 3u * (x - x0), grp, cs, k, &wq, &wp, shl);
            x += cnt;
            continue;
        }
#endif
        group_sums(s, grp, cs, &wp, k, whole ? wp.h8 : zero3);
        if (whole) {
            group_finish(out + 3u * (x - x0), s, &wp, shl);
            x += cnt;
            continue;
        }
        for (uint32_t ch = 0; ch < 3u; ++ch) { /* lanes: pixels 0-3 | 8-11 and 4-7 | 12-15 */
            _mm256_storeu_si256((__m256i *)(void *)acc[ch], _mm256_permute2x128_si256(s[ch][0], s[ch][1], 0x20));
            _mm256_storeu_si256((__m256i *)(void *)(acc[ch] + 8), _mm256_permute2x128_si256(s[ch][0], s[ch][1], 0x31));
        }
#else
        group_acc(acc[0], grp, &wp, 0u, k);
        group_acc(acc[1], grp + cs, &wp, 1u, k);
        group_acc(acc[2], grp + 2u * cs, &wp, 2u, k);
#endif
        int32_t *o = out + 3u * (x - x0);
        if (cnt == QIBL_SHMAPS_GROUP && f->fast) {
#if QIBL_CONFIG_SIMD != QIBL_SIMD_SCALAR
            for (uint32_t p = 0; p < QIBL_SHMAPS_GROUP; p += 4u)
                finish4(o + 3u * p, acc[0] + p, acc[1] + p, acc[2] + p, &wp);
#else
            for (uint32_t p = 0; p < QIBL_SHMAPS_GROUP; ++p) {
                o[3u * p] = qibl_asr_s32(acc[0][p] * f->mu[0] + f->h[0], f->r[0]) + f->b[0];
                o[3u * p + 1u] = qibl_asr_s32(acc[1][p] * f->mu[1] + f->h[1], f->r[1]) + f->b[1];
                o[3u * p + 2u] = qibl_asr_s32(acc[2][p] * f->mu[2] + f->h[2], f->r[2]) + f->b[2];
            }
#endif
        } else {
            finish_rgb(f, w, acc[0] + p0, acc[1] + p0, acc[2] + p0, o, cnt);
        }
        x += cnt;
    }
}
#endif /* QIBL_USE_INTERLEAVED */

qibl_status_t qibl_shmap_relight_span(const qibl_shmaps_t *m, const qibl_shmap_weights_t *w, uint32_t x0, uint32_t y,
                                      uint32_t n, int32_t *out, void *ws, size_t ws_size)
{
    QIBLI_DISPATCH512(qibl_shmap_relight_span, (m, w, x0, y, n, out, ws, ws_size));
    qibl_status_t st = qibl_shmap_check(m);
    if (st != QIBL_OK)
        return st;
    if (w == 0 || out == 0 || ws == 0)
        return QIBL_E_NULL_POINTER;
    if (w->k != m->k || w->channels != m->channels)
        return QIBL_E_SHMAP_MISMATCH;
    if (y >= m->height || x0 > m->width || n > m->width - x0)
        return QIBL_E_SHMAP_BOUNDS;
    if (ws_size < qibl_shmap_span_workspace_size(n))
        return QIBL_E_WORKSPACE;
    if (((uintptr_t)ws & 3u) != 0u) /* int32 accumulators: a uint8_t array faults on Cortex-M0 */
        return QIBL_E_WORKSPACE_ALIGN;
    if (n == 0u)
        return QIBL_OK;
    finish_t f;
    finish_prepare(w, &f);
#if QIBL_USE_INTERLEAVED
    if (m->layout == QIBL_SHMAPS_INTERLEAVED) {
        relight_interleaved(m, w, &f, x0, y, n, out); /* no workspace: 192 bytes of stack */
        return QIBL_OK;
    }
#endif
    int32_t *acc = (int32_t *)ws; /* 4-byte aligned: checked above */
    size_t off = (size_t)y * m->width + x0;
#if QIBL_CONFIG_SIMD != QIBL_SIMD_SCALAR
    relight_planar(m, w, &f, off, n, out, acc);
    return QIBL_OK;
#elif QIBL_CONFIG_SHMAP_BLOCKS
    /* per channel: the fast final scaling inside the kernel (chan_fast) when this channel's shift
     * and bias allow it (then finish_channel's first branch gives the same integers), else the raw
     * sums into the workspace and finish_channel */
    const size_t plane = (size_t)m->width * m->height;
    for (uint32_t ch = 0; ch < 3u; ++ch) {
        const uint32_t src = m->channels == 3u ? ch : 0u;
        const chan_t c = {qibl_shmaps_plane(m, 0u, src) + off, plane * m->channels, w->w[ch], m->k};
        const int32_t sh = w->shift[ch];
        const int64_t bias = w->bias[ch];
        if (sh < 0 && sh > -31 && bias >= -(INT64_C(1) << 30) && bias <= (INT64_C(1) << 30)) {
            const unsigned r = (unsigned)-sh;
            chan_fast(&c, n, r, (int32_t)1 << (r - 1u), (int32_t)bias, out + ch);
        } else {
            chan_raw(&c, n, acc);
            finish_channel(acc, sh, bias, out + ch, n);
        }
    }
    (void)f;
    return QIBL_OK;
#else
    for (uint32_t ch = 0; ch < 3u; ++ch) {
        uint32_t src = m->channels == 3u ? ch : 0u;
        const int16_t *wc = w->w[ch];
        int32_t *a = acc + (size_t)ch * n;
        /* maps in groups of four; a missing map in the last group reads plane 0 with weight 0 */
        for (uint32_t i = 0; i < m->k; i += 4u) {
            const uint8_t *pl[4];
            int16_t wt[4];
            for (uint32_t j = 0; j < 4u; ++j) {
                pl[j] = qibl_shmaps_plane(m, i + j < m->k ? i + j : 0u, src) + off;
                wt[j] = i + j < m->k ? wc[i + j] : 0;
            }
            if (i == 0u)
                acc_set4(a, pl[0], pl[1], pl[2], pl[3], wt[0], wt[1], wt[2], wt[3], n);
            else
                acc_add4(a, pl[0], pl[1], pl[2], pl[3], wt[0], wt[1], wt[2], wt[3], n);
        }
    }
    finish_rgb(&f, w, acc, acc + n, acc + 2u * n, out, n);
    return QIBL_OK;
#endif
}

/* ---- cube-map Y LUTs ------------------------------------------------------------------------- */

size_t qibl_ylut_values_size(uint32_t face_size, uint32_t k)
{
    if (face_size < 1u || face_size > QIBL_YLUT_MAX_FACE || k < 1u || k > (uint32_t)QIBL_SH_MAX_COUNT)
        return 0u;
    return (size_t)6u * face_size * face_size * k * 2u;
}

/* Direction of texel (u, v) of face f, as the OpenGL cube-map convention (asset.h), in units of
 * 1/N: s = (2u + 1 - N) / N is carried as the integer 2u + 1 - N. Each component is
 * a*N + b*s + c*t with {a, b, c} from this table (a table, not a switch: a switch becomes a call to
 * a libgcc case helper on Cortex-M0). */
static const int8_t face_basis[6][3][3] = {
    {{1, 0, 0}, {0, 0, -1}, {0, -1, 0}},  /* +X ( 1, -t, -s) */
    {{-1, 0, 0}, {0, 0, -1}, {0, 1, 0}},  /* -X (-1, -t,  s) */
    {{0, 1, 0}, {1, 0, 0}, {0, 0, 1}},    /* +Y ( s,  1,  t) */
    {{0, 1, 0}, {-1, 0, 0}, {0, 0, -1}},  /* -Y ( s, -1, -t) */
    {{0, 1, 0}, {0, 0, -1}, {1, 0, 0}},   /* +Z ( s, -t,  1) */
    {{0, -1, 0}, {0, 0, -1}, {-1, 0, 0}}, /* -Z (-s, -t, -1) */
};

static void texel_dir(uint32_t f, uint32_t u, uint32_t v, uint32_t n, int32_t d[3])
{
    int32_t s = (int32_t)(2u * u + 1u) - (int32_t)n, t = (int32_t)(2u * v + 1u) - (int32_t)n, one = (int32_t)n;
    for (int j = 0; j < 3; ++j)
        d[j] = face_basis[f][j][0] * one + face_basis[f][j][1] * s + face_basis[f][j][2] * t;
}

qibl_status_t qibl_ylut_check(const qibl_ylut_t *t)
{
    if (t == 0 || t->values == 0)
        return QIBL_E_NULL_POINTER;
    if (t->k < 1u || t->k > (uint32_t)QIBL_SH_MAX_COUNT)
        return QIBL_E_SHMAP_K;
    if (t->face_size < 1u || t->face_size > QIBL_YLUT_MAX_FACE)
        return QIBL_E_SHMAP_LUT_SIZE;
    if (t->size < qibl_ylut_values_size(t->face_size, t->k))
        return QIBL_E_SHMAP_LUT_SHORT;
    return QIBL_OK;
}

qibl_status_t qibl_ylut_build(uint32_t face_size, uint32_t k, uint8_t *values, size_t size)
{
    QIBLI_DISPATCH(qibl_ylut_build, (face_size, k, values, size));
    if (values == 0)
        return QIBL_E_NULL_POINTER;
    if (k < 1u || k > (uint32_t)QIBL_SH_MAX_COUNT)
        return QIBL_E_SHMAP_K;
    if (face_size < 1u || face_size > QIBL_YLUT_MAX_FACE)
        return QIBL_E_SHMAP_LUT_SIZE;
    if (size < qibl_ylut_values_size(face_size, k))
        return QIBL_E_WORKSPACE;
    int bands = bands_for(k);
    uint8_t *o = values;
    for (uint32_t f = 0; f < 6u; ++f)
        for (uint32_t v = 0; v < face_size; ++v)
            for (uint32_t u = 0; u < face_size; ++u) {
                int32_t d[3];
                qibl_q30_t y[QIBL_SH_MAX_COUNT];
                texel_dir(f, u, v, face_size, d);
                QIBL_DROP_STATUS(qibl_sh_eval(d, bands, y)); /* d is never zero: one component is +-N */
                for (uint32_t i = 0; i < k; ++i) {
                    int32_t q = qibli_rshr_s64(y[i], 16); /* Q2.30 -> Q2.14, |Y| < 1 */
                    uint32_t b = (uint32_t)q;
                    *o++ = (uint8_t)b;
                    *o++ = (uint8_t)(b >> 8);
                }
            }
    return QIBL_OK;
}

/* Texel coordinate in 1/256 texel from a face coordinate sc / ma (Q2.30 both, |sc| <= ma):
 * round(((sc / ma + 1) N / 2 - 0.5) * 256), via 1 / ma = iy / 2^ie. At texel centres it is exact. */
static int32_t face_coord(int32_t sc, uint32_t iy, unsigned ie, uint32_t n)
{
    /* s24 = sc / ma in Q24: |sc| iy / 2^(ie - 24); ie is 60..61 for ma^2 in [2^58.4, 2^60] */
    uint32_t a = qibli_abs_u32(sc);
    uint32_t m24 = (uint32_t)qibl_shr_u64(qibl_mul_u32_u64(a, iy) + qibl_shr_u64((uint64_t)1 << 63, 88u - ie), ie - 24u);
    if (m24 > (1u << 24))
        m24 = 1u << 24;
    uint32_t s1 = sc < 0 ? (1u << 24) - m24 : (1u << 24) + m24; /* (s + 1) in Q24, 0..2^25 */
    return (int32_t)((qibl_mul_u32_u64(s1, n) + (1u << 16)) >> 17) - 128;
}

/* Samples Y_0..Y_{k-1} (Q2.14) of LUT t at unit direction u into y14[i * stride]. */
static void lut_sample(const qibl_ylut_t *t, const qibl_q30_t u[3], uint32_t k, int nearest, int16_t *y14,
                       size_t stride)
{
    uint32_t ax = qibli_abs_u32(u[0]), ay = qibli_abs_u32(u[1]), az = qibli_abs_u32(u[2]);
    uint32_t f, ma;
    int32_t sc, tc;
    if (ax >= ay && ax >= az) {
        ma = ax;
        f = u[0] >= 0 ? 0u : 1u;
        sc = u[0] >= 0 ? -u[2] : u[2];
        tc = -u[1];
    } else if (ay >= az) {
        ma = ay;
        f = u[1] >= 0 ? 2u : 3u;
        sc = u[0];
        tc = u[1] >= 0 ? u[2] : -u[2];
    } else {
        ma = az;
        f = u[2] >= 0 ? 4u : 5u;
        sc = u[2] >= 0 ? u[0] : -u[0];
        tc = -u[1];
    }
    unsigned ie;
    uint32_t iy = qibl_rsqrt_u64(qibl_mul_u32_u64(ma, ma), &ie); /* 1/ma */
    const uint32_t n = t->face_size;
    int32_t fu = face_coord(sc, iy, ie, n), fv = face_coord(tc, iy, ie, n);
    size_t tstride = (size_t)t->k * 2u;
    if (nearest) {
        /* the texel containing the direction: floor(fu / 256 + 1/2), clamped */
        int32_t iu = qibl_asr_s32(fu + 128, 8), iv = qibl_asr_s32(fv + 128, 8);
        iu = iu < 0 ? 0 : iu > (int32_t)n - 1 ? (int32_t)n - 1 : iu;
        iv = iv < 0 ? 0 : iv > (int32_t)n - 1 ? (int32_t)n - 1 : iv;
        const uint8_t *p = t->values + (((size_t)f * n + (uint32_t)iv) * n + (uint32_t)iu) * tstride;
        for (uint32_t i = 0; i < k; ++i)
            y14[i * stride] = qibl_load_s16le(p + 2u * i);
        return;
    }
    int32_t iu = qibl_asr_s32(fu, 8), iv = qibl_asr_s32(fv, 8);
    int32_t wu = fu - iu * 256, wv = fv - iv * 256; /* 0..255 */
    /* clamp at the face's edges (no cross-face filtering) */
    if (iu < 0)
        iu = 0, wu = 0;
    if (iu >= (int32_t)n - 1)
        iu = (int32_t)n - 1, wu = 0;
    if (iv < 0)
        iv = 0, wv = 0;
    if (iv >= (int32_t)n - 1)
        iv = (int32_t)n - 1, wv = 0;
    uint32_t du = wu ? 1u : 0u, dv = wv ? (uint32_t)n : 0u;
    const uint8_t *p00 = t->values + (((size_t)f * n + (uint32_t)iv) * n + (uint32_t)iu) * tstride;
    const uint8_t *p10 = p00 + du * tstride, *p01 = p00 + dv * tstride, *p11 = p01 + du * tstride;
    int32_t w00 = (256 - wu) * (256 - wv), w10 = wu * (256 - wv), w01 = (256 - wu) * wv, w11 = wu * wv;
    for (uint32_t i = 0; i < k; ++i) {
        /* |Y| <= 0.9 * 2^14 and the weights sum to 2^16: |sum| < 2^30 */
        int32_t sm = w00 * qibl_load_s16le(p00 + 2u * i) + w10 * qibl_load_s16le(p10 + 2u * i) +
                     w01 * qibl_load_s16le(p01 + 2u * i) + w11 * qibl_load_s16le(p11 + 2u * i);
        y14[i * stride] = (int16_t)qibl_asr_s32(sm + 32768, 16);
    }
}

void qibl_ylut_lookup(const qibl_ylut_t *t, const qibl_q30_t u[3], uint32_t k, int32_t *y14)
{
    int16_t y[QIBL_SH_MAX_COUNT];
    lut_sample(t, u, k, 0, y, 1u);
    for (uint32_t i = 0; i < k; ++i)
        y14[i] = y[i];
}

/* ---- point lights ---------------------------------------------------------------------------- */

/* v / 2^e as int16 with the smallest e >= 0 that keeps max |v| <= 32767 over the k values */
static int32_t norm16(const int32_t *v, uint32_t k, size_t stride, int16_t *out)
{
    uint32_t mx = 0u;
    for (uint32_t i = 0; i < k; ++i) {
        uint32_t a = qibli_abs_u32(v[i * stride]);
        mx = a > mx ? a : mx;
    }
    unsigned e = 0u;
    while (((mx + (e ? 1u << (e - 1u) : 0u)) >> e) > 32767u)
        ++e;
    for (uint32_t i = 0; i < k; ++i)
        out[i] = (int16_t)(e ? qibli_rshr_s64(v[i * stride], e) : v[i * stride]);
    return (int32_t)e;
}

/* ---- QIBL_POINT_POLY: Y_i in Q2.14 from their polynomials, one-step rsqrt ------------------------
 * The recurrences of sh.c (see there) with int16 operands: unit vector and T_m in Q2.14, P and the
 * constants in Q3.13 (|P| <= 2.84, |A| <= 3: int16), every product int16 x int16 in int32, rounded
 * half up once. Measured against qibl_sh_eval_unit (shmap_test.c): |Y14 - 2^14 Y| <= POLY_Y_TOL. */

/* {A or K, B} in Q3.13 (round half up of sh.c's constants), at index l(l+1)/2 + m, m <= l */
static const int16_t poly_rec[15][2] = {
    {2311, 0},      /* l=0 m=0 K  0.282095 */
    {14189, 0},     /* l=1 m=0 A  1.732051 */
    {-4003, 0},     /* l=1 m=1 K -0.488603 */
    {15864, 9159},  /* l=2 m=0 A  1.936492, B 1.118034 */
    {18318, 0},     /* l=2 m=1 A  2.236068 */
    {4475, 0},      /* l=2 m=2 K  0.546274 */
    {16155, 8342},  /* l=3 m=0 A  1.972027, B 1.018350 */
    {17135, 7663},  /* l=3 m=1 A  2.091650, B 0.935414 */
    {21674, 0},     /* l=3 m=2 A  2.645751 */
    {-4834, 0},     /* l=3 m=3 K -0.590044 */
    {16255, 8243},  /* l=4 m=0 A  1.984313, B 1.006231 */
    {16789, 8026},  /* l=4 m=1 A  2.049390, B 0.979796 */
    {18770, 7094},  /* l=4 m=2 A  2.291288, B 0.866025 */
    {24576, 0},     /* l=4 m=3 A  3.000000 */
    {5127, 0},      /* l=4 m=4 K  0.625836 */
};

/* round(v / 2^s), half up, for |v| < 2^31 - 2^(s-1) */
#define POLY_RS(v, s) qibl_asr_s32((v) + (1 << ((s) - 1)), (s))

#if defined(__OPTIMIZE_SIZE__)
/* Built for size: the same recurrences as loops (the same integers as the written-out version
 * below, which the bare-metal Cortex-M0 build at -Os checks against the poly goldens). */
static void poly_eval(int32_t x, int32_t y, int32_t z, uint32_t bands, int16_t *o)
{
    int32_t c = 16384, s = 0; /* T_m, T_-m in Q2.14 */
    for (uint32_t m = 0; m < bands; ++m) {
        if (m > 0u) { /* (c + is)(x + iy) */
            const int32_t c2 = POLY_RS(x * c - y * s, 14);
            s = POLY_RS(x * s + y * c, 14);
            c = c2;
        }
        int32_t p2 = 0, p1 = poly_rec[m * (m + 1u) / 2u + m][0];
        for (uint32_t l = m; l < bands; ++l) {
            if (l > m) {
                const int16_t *k = poly_rec[l * (l + 1u) / 2u + m];
                const int32_t p = POLY_RS(POLY_RS(k[0] * z, 14) * p1 - k[1] * p2, 13);
                p2 = p1;
                p1 = p;
            }
            int16_t *q = o + l * l + l;
            if (m == 0u) {
                q[0] = (int16_t)(2 * p1);
            } else {
                q[m] = (int16_t)POLY_RS(p1 * c, 13);
                q[-(int32_t)m] = (int16_t)POLY_RS(p1 * s, 13);
            }
        }
    }
}
#else
/* P(l,m) from P(l-1,m) and P(l-2,m): A z P1 - B P2 (|A z| <= 3 2^13, |A z P1| + |B P2| < 2^30) */
#define POLY_REC(l, m, p1, p2)                                                                          \
    POLY_RS(POLY_RS(poly_rec[(l) * ((l) + 1) / 2 + (m)][0] * z, 14) * (p1) - poly_rec[(l) * ((l) + 1) / 2 + (m)][1] * (p2), 13)
/* Y(l,+-m) = P(l,m) T_+-m (Q3.13 x Q2.14 -> Q2.14) */
#define POLY_PAIR(l, m, p)                                                                              \
    (o[(l) * (l) + (l) + (m)] = (int16_t)POLY_RS((p) * c##m, 13), o[(l) * (l) + (l) - (m)] = (int16_t)POLY_RS((p) * s##m, 13))

/* Y_0..Y_{bands^2-1} (Q2.14) of the unit vector (x, y, z) in Q2.14 into o[]: the recurrences of
 * sh.c written out band by band (constant indices, no loops: about half the instructions) */
static void poly_eval(int32_t x, int32_t y, int32_t z, uint32_t bands, int16_t *o)
{
    const int32_t p00 = poly_rec[0][0];
    o[0] = (int16_t)(2 * p00); /* Q3.13 -> Q2.14 */
    if (bands < 2u)
        return;
    const int32_t c1 = x, s1 = y; /* T_1 = x + iy */
    const int32_t p10 = POLY_REC(1, 0, p00, 0), p11 = poly_rec[2][0];
    o[2] = (int16_t)(2 * p10);
    POLY_PAIR(1, 1, p11);
    if (bands < 3u)
        return;
    const int32_t c2 = POLY_RS(x * c1 - y * s1, 14), s2 = POLY_RS(x * s1 + y * c1, 14); /* |.| <= 2^28 */
    const int32_t p20 = POLY_REC(2, 0, p10, p00), p21 = POLY_REC(2, 1, p11, 0), p22 = poly_rec[5][0];
    o[6] = (int16_t)(2 * p20);
    POLY_PAIR(2, 1, p21);
    POLY_PAIR(2, 2, p22);
    if (bands < 4u)
        return;
    const int32_t c3 = POLY_RS(x * c2 - y * s2, 14), s3 = POLY_RS(x * s2 + y * c2, 14);
    const int32_t p30 = POLY_REC(3, 0, p20, p10), p31 = POLY_REC(3, 1, p21, p11), p32 = POLY_REC(3, 2, p22, 0);
    const int32_t p33 = poly_rec[9][0];
    o[12] = (int16_t)(2 * p30);
    POLY_PAIR(3, 1, p31);
    POLY_PAIR(3, 2, p32);
    POLY_PAIR(3, 3, p33);
    if (bands < 5u)
        return;
    const int32_t c4 = POLY_RS(x * c3 - y * s3, 14), s4 = POLY_RS(x * s3 + y * c3, 14);
    const int32_t p40 = POLY_REC(4, 0, p30, p20), p41 = POLY_REC(4, 1, p31, p21), p42 = POLY_REC(4, 2, p32, p22);
    const int32_t p43 = POLY_REC(4, 3, p33, 0), p44 = poly_rec[14][0];
    o[20] = (int16_t)(2 * p40);
    POLY_PAIR(4, 1, p41);
    POLY_PAIR(4, 2, p42);
    POLY_PAIR(4, 3, p43);
    POLY_PAIR(4, 4, p44);
}
#endif

/* The direction and attenuation of l != 0 (int32 components): l scaled by 2^-sc so that its
 * largest |component| lies in [2^14, 2^15] (exact when scaled up, floored down), d2 = |l|^2 in
 * [2^28, 3 2^30]; 1/sqrt(d2) from the rsqrt seed and one Newton step (relative error <= 2^-17.4,
 * then y16 floored: <= 2^-15). Unit vector u14 (Q2.14, error <= 2 LSB) and 1/|l| = a 2^-ae,
 * a in [2^14, 2^15] (also for the min_dist clamp, so both compare as mantissa and exponent). */
#if (defined(__GNUC__) || defined(__clang__)) && !defined(__OPTIMIZE_SIZE__)
#define POLY_INLINE __attribute__((always_inline)) inline /* once per pixel: no call, u and a in registers */
#else
#define POLY_INLINE inline
#endif
static POLY_INLINE void poly_dir(int32_t l0, int32_t l1, int32_t l2, int32_t *u0, int32_t *u1, int32_t *u2, int32_t *a,
                                 int32_t *ae)
{
    const uint32_t mx = qibli_abs_u32(l0) | qibli_abs_u32(l1) | qibli_abs_u32(l2);
#if defined(__GNUC__) && (defined(__ARM_FEATURE_CLZ) || defined(__x86_64__) || defined(__aarch64__))
    const int32_t sc = 17 - __builtin_clz(mx); /* top bit of mx to bit 14 (one instruction, same value) */
#else
    const int32_t sc = (int32_t)qibli_bitlen_u32(mx) - 15; /* top bit of mx to bit 14 */
#endif
    uint32_t v0, v1, v2; /* |l| 2^-sc, <= 2^15 (written out: loops over arrays stayed loops on Cortex-M4) */
    if (sc >= 0) {
        v0 = qibli_abs_u32(qibl_asr_s32(l0, (unsigned)sc));
        v1 = qibli_abs_u32(qibl_asr_s32(l1, (unsigned)sc));
        v2 = qibli_abs_u32(qibl_asr_s32(l2, (unsigned)sc));
    } else {
        const unsigned ls = (unsigned)-sc;
        v0 = qibli_abs_u32(l0) << ls, v1 = qibli_abs_u32(l1) << ls, v2 = qibli_abs_u32(l2) << ls;
    }
    const uint32_t d2 = v0 * v0 + v1 * v1 + v2 * v2; /* in [2^28, 3 2^30]: no wrap */
    const unsigned h = d2 < (1u << 30) ? 1u : 0u;    /* t = d2 4^h in [2^30, 2^32) */
    const uint32_t t = d2 << (2u * h);
    const uint32_t y0 = qibli_rsqrt_seed[(t >> 24) - 64u];                         /* ~ 2^30 / sqrt(t), < 2^15 */
    const uint32_t hh = (uint32_t)(qibl_mul_u32_u64(y0 * y0, t) >> 32);            /* ~ 2^28 */
    const uint32_t y16 = (uint32_t)(qibl_mul_u32_u64(y0, 0x30000000u - hh) >> 28); /* ~ 2^31 / sqrt(t) */
    /* u = v / sqrt(d2) = v y16 2^(h - 31) in Q2.14; v y16 <= 2^31 and the rounding term fit */
    const unsigned r = 17u - h;
    const uint32_t half = 1u << (r - 1u);
    uint32_t q0 = (v0 * y16 + half) >> r, q1 = (v1 * y16 + half) >> r, q2 = (v2 * y16 + half) >> r;
    q0 = q0 > 16384u ? 16384u : q0, q1 = q1 > 16384u ? 16384u : q1, q2 = q2 > 16384u ? 16384u : q2;
    *u0 = l0 < 0 ? -(int32_t)q0 : (int32_t)q0;
    *u1 = l1 < 0 ? -(int32_t)q1 : (int32_t)q1;
    *u2 = l2 < 0 ? -(int32_t)q2 : (int32_t)q2;
    /* 1/|l| = 2^-sc / sqrt(d2) = (y16 / 2) 2^(h - 30 - sc) */
    *a = (int32_t)(y16 >> 1);
    *ae = 30 - (int32_t)h + sc;
}

/* the smallest e >= 0 with every |round(v / 2^e)| <= lim */
static int32_t norm_lim(const int32_t *v, uint32_t k, uint32_t lim)
{
    uint32_t mx = 0u;
    for (uint32_t i = 0; i < k; ++i) {
        uint32_t a = qibli_abs_u32(v[i]);
        mx = a > mx ? a : mx;
    }
    unsigned e = 0u;
    while (((mx + (e ? 1u << (e - 1u) : 0u)) >> e) > lim)
        ++e;
    return (int32_t)e;
}

/* v / 2^e as int16 for a given e at least norm16's (so no value exceeds 32767) */
static int32_t norm16_at(const int32_t *v, uint32_t k, int32_t e, int16_t *out)
{
    for (uint32_t i = 0; i < k; ++i)
        out[i] = (int16_t)(e ? qibli_rshr_s64(v[i], (unsigned)e) : v[i]);
    return e;
}

qibl_status_t qibl_shmap_point_prepare(const qibl_shmaps_t *m, const qibl_pmap_t *p, const qibl_ylut_t *lut,
                                       const qibl_pointlight_t *light, qibl_shmap_point_t *out)
{
    QIBLI_DISPATCH(qibl_shmap_point_prepare, (m, p, lut, light, out));
    qibl_status_t st = qibl_shmap_check(m);
    if (st != QIBL_OK)
        return st;
    if (p == 0 || p->points == 0 || light == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    if (p->width != m->width || p->height != m->height)
        return QIBL_E_SHMAP_MISMATCH;
    if (lut != 0 && (lut->values == 0 || lut->k < m->k || lut->k > (uint32_t)QIBL_SH_MAX_COUNT ||
                     lut->face_size < 1u || lut->face_size > QIBL_YLUT_MAX_FACE))
        return QIBL_E_SHMAP_MISMATCH;
    /* the view's fields may come from a file: the lookups reach 12 N N k bytes, which must be there
     * (after the checks above only QIBL_E_SHMAP_LUT_SHORT remains) */
    if (lut != 0 && (st = qibl_ylut_check(lut)) != QIBL_OK)
        return st;
    if (light->rgb[0] < 0 || light->rgb[1] < 0 || light->rgb[2] < 0 || light->min_dist < 0 ||
        (light->falloff != QIBL_FALLOFF_INV_DIST && light->falloff != QIBL_FALLOFF_INV_DIST2) ||
        (light->filter != QIBL_LUT_BILINEAR && light->filter != QIBL_LUT_NEAREST && light->filter != QIBL_POINT_POLY))
        return QIBL_E_SHMAP_LIGHT;
    const int poly = light->filter == QIBL_POINT_POLY;
    /* built in place (nothing below can fail): a struct copy would be a memcpy call */
    for (uint32_t ch = 0; ch < 3u; ++ch) {
        uint32_t src = m->channels == 3u ? ch : 0u;
        int32_t sv[QIBL_SH_MAX_COUNT], bv[QIBL_SH_MAX_COUNT];
        for (uint32_t i = 0; i < m->k; ++i) {
            sv[i] = qibl_shmaps_scale(m, i, src);
            bv[i] = qibl_shmaps_bias(m, i, src);
        }
        for (uint32_t i = m->k; i < (uint32_t)QIBL_SH_MAX_COUNT; ++i)
            out->sn[ch][i] = 0, out->bn[ch][i] = 0;
        out->es[ch] = norm16(sv, m->k, 1u, out->sn[ch]);
        out->eb[ch] = norm16(bv, m->k, 1u, out->bn[ch]);
        out->pd[ch] = 0;
        if (poly) {
            /* bias factors to 14 bits, so sum_i Y_i bn_i is exact in int32: sum_i |Y_i| <= k / sqrt(4 pi)
             * (|Y|_2^2 = k / (4 pi)), so |sum| <= 25 * 4622 * 16383 < 1.9 2^30 */
            if (norm_lim(bv, m->k, 16383u) > out->eb[ch])
                out->eb[ch] = norm16_at(bv, m->k, out->eb[ch] + 1, out->bn[ch]);
            /* V = (acc + accb 2^(14 - pd)) / 2^14 in units of 2^es, pd = es + 14 - eb >= 1: |V| < 2^28 + 2^30 */
            if (out->es[ch] < out->eb[ch] - 13)
                out->es[ch] = norm16_at(sv, m->k, out->eb[ch] - 13, out->sn[ch]);
            /* and pd <= 14: a bias below the scale term's size keeps the scale's unit */
            if (out->eb[ch] < out->es[ch])
                out->eb[ch] = norm16_at(bv, m->k, out->es[ch], out->bn[ch]);
            out->pd[ch] = out->es[ch] + 14 - out->eb[ch];
        }
        /* |bs| <= 32767 2^13 < 2^28, so sn c + bs fits int32 (poly_span's fused term) */
        for (uint32_t i = 0; i < (uint32_t)QIBL_SH_MAX_COUNT; ++i)
            out->bs[ch][i] = poly ? out->bn[ch][i] * ((int32_t)1 << (14 - out->pd[ch])) : 0;
        /* C0 = c0m 2^ce, c0m <= 2^15 (floored) */
        const uint32_t c0 = (uint32_t)light->rgb[ch];
        const int32_t ce = (int32_t)qibli_bitlen_u32(c0) > 15 ? (int32_t)qibli_bitlen_u32(c0) - 15 : 0;
        out->c0m[ch] = (int32_t)(c0 >> ce);
        out->pk[ch] = 24 - out->es[ch] - ce;
    }
    out->method = poly ? 1u : 0u;
    out->maps = m;
    out->pmap = p;
    out->lut = lut;
    for (int j = 0; j < 3; ++j) {
        out->pos[j] = light->pos[j];
        out->rgb[j] = (uint32_t)light->rgb[j];
    }
    out->falloff = (uint32_t)light->falloff;
    out->filter = (uint32_t)light->filter;
    uint32_t md = light->min_dist > 0 ? (uint32_t)light->min_dist : 256u; /* default 1/256 unit */
    out->min_d2 = qibl_mul_u32_u64(md, md);
    out->clamp_y = qibl_rsqrt_u64(out->min_d2, &out->clamp_e);
    int32_t u0, u1, u2;
    poly_dir((int32_t)md, 0, 0, &u0, &u1, &u2, &out->clamp_am, &out->clamp_ae);
    out->bands = (uint32_t)bands_for(m->k);
    return QIBL_OK;
}

size_t qibl_shmap_point_workspace_size(uint32_t k, uint32_t n)
{
    return (size_t)n * (2u * k + 32u);
}

/* x * 2^s for |x| < 2^31, saturated to +-2^62 (no 64-bit variable shift: Cortex-M0) */
static int64_t shl_sat(int32_t x, unsigned s)
{
    if (x == 0)
        return 0;
    if (s > 31u)
        return x > 0 ? INT64_C(1) << 62 : -(INT64_C(1) << 62);
    int64_t v = qibl_mul_s32_s64(x, (int32_t)1 << (s > 30u ? 30u : s));
    return s > 30u ? v + v : v;
}

/* Phase B, one map of one channel: acc[p] (+)= round(Y sn / 2^14) c, accb[p] (+)= round(Y bn / 2^14).
 * Bounds: |Y| <= 14746, |sn|, |bn| <= 32767, so each rounded product is <= 29492 and over 25 maps
 * |acc| <= 25 * 29492 * 255 < 2^28, |accb| < 2^20. Restrict parameters and no calls: vectorisable.
 * The first map assigns instead of adding (no zeroing loop, which compilers turn into memset). */
static void point_map(int32_t *restrict acc, int32_t *restrict accb, const int16_t *restrict y,
                      const uint8_t *restrict c, int32_t sn, int32_t bn, uint32_t n, int first)
{
    if (first) {
        for (uint32_t p = 0; p < n; ++p) {
            acc[p] = (int16_t)qibl_asr_s32(y[p] * sn + 8192, 14) * (int16_t)c[p];
            accb[p] = qibl_asr_s32(y[p] * bn + 8192, 14);
        }
    } else {
        for (uint32_t p = 0; p < n; ++p) {
            acc[p] += (int16_t)qibl_asr_s32(y[p] * sn + 8192, 14) * (int16_t)c[p];
            accb[p] += qibl_asr_s32(y[p] * bn + 8192, 14);
        }
    }
}

#if QIBL_USE_INTERLEAVED
/* Phase B on one whole 16-pixel group of the interleaved layout, all k maps of one channel: the
 * products of point_map in fixed-length loops over restrict parameters (out of line, so they
 * vectorise as group_acc does). y holds Y_i of the group's pixels at y[i * ystride + p]. */
static QIBLI_NOINLINE void point_group(int32_t *restrict acc, int32_t *restrict accb, const int16_t *restrict y,
                                       size_t ystride, const uint8_t *restrict c, const int16_t *restrict sn,
                                       const int16_t *restrict bn, uint32_t k)
{
    for (uint32_t p = 0; p < QIBL_SHMAPS_GROUP; ++p) {
        acc[p] = (int16_t)qibl_asr_s32(y[p] * sn[0] + 8192, 14) * (int16_t)c[p];
        accb[p] = qibl_asr_s32(y[p] * bn[0] + 8192, 14);
    }
    for (uint32_t i = 1; i < k; ++i) {
        const int16_t *yi = y + i * ystride;
        const uint8_t *ci = c + QIBL_SHMAPS_GROUP * i;
        const int32_t s = sn[i], b = bn[i];
        for (uint32_t p = 0; p < QIBL_SHMAPS_GROUP; ++p) {
            acc[p] += (int16_t)qibl_asr_s32(yi[p] * s + 8192, 14) * (int16_t)ci[p];
            accb[p] += qibl_asr_s32(yi[p] * b + 8192, 14);
        }
    }
}

/* Phase B of one channel on the interleaved layout: whole groups through point_group, the pieces
 * of partial groups at the span's ends through point_map. Same per-pixel integers as planar. */
static void point_interleaved(const qibl_shmaps_t *m, const qibl_shmap_point_t *pt, uint32_t ch, uint32_t src,
                              uint32_t x0, uint32_t y, uint32_t n, int32_t *acc, int32_t *accb, const int16_t *ybuf)
{
    const uint32_t k = m->k;
    const uint8_t *row = m->planes + (size_t)y * qibl_shmaps_row_size(m) + (size_t)src * k * QIBL_SHMAPS_GROUP;
    for (uint32_t x = x0, end = x0 + n; x < end;) {
        const uint32_t p0 = x % QIBL_SHMAPS_GROUP, left = QIBL_SHMAPS_GROUP - p0;
        const uint32_t cnt = end - x < left ? end - x : left, j = x - x0;
        const uint8_t *g = row + (size_t)(x / QIBL_SHMAPS_GROUP) * QIBL_SHMAPS_GROUP * k * m->channels + p0;
        if (cnt == QIBL_SHMAPS_GROUP)
            point_group(acc + j, accb + j, ybuf + j, n, g, pt->sn[ch], pt->bn[ch], k);
        else
            for (uint32_t i = 0; i < k; ++i)
                point_map(acc + j, accb + j, ybuf + (size_t)i * n + j, g + QIBL_SHMAPS_GROUP * i, pt->sn[ch][i],
                          pt->bn[ch][i], cnt, i == 0u);
        x += cnt;
    }
}
#endif /* QIBL_USE_INTERLEAVED */

/* QIBL_POINT_POLY, pixel by pixel (no workspace traffic: Y and the sums stay in registers or on
 * the stack; the order of exact integer sums does not change them). Per pixel: l = S - P, Y_i in
 * Q2.14 and the attenuation a 2^-ae (poly_dir, poly_eval); per channel
 *   acc  = sum_i Y_i sn_i c_i (exact, int64)     |acc| < 25 * 14746 * 32767 * 255 < 2^42
 *   accb = sum_i Y_i bn_i (exact)               |accb| < 1.9 2^30 (prepare)
 *   V = round((acc + accb 2^(14 - pd)) / 2^14)   1 <= pd <= 14, |V| < 2^28 + 2^30, units 2^(es - 24)
 * (summed as one: sum_i Y_i (sn_i c_i + bs_i), bs_i = bn_i 2^(14 - pd))
 *   out = round(V g / 2^(ae + pk)), g = am c0m <= 2^30, saturated to int32. */
static void poly_span(const qibl_shmap_point_t *pt, uint32_t x0, uint32_t y, uint32_t n, int32_t *out)
{
    const qibl_shmaps_t *m = pt->maps;
    const uint32_t k = m->k, bands = pt->bands;
    const size_t off = (size_t)y * m->width + x0;
    const uint8_t *pp = pt->pmap->points + off * 12u;
    const int il = QIBL_USE_INTERLEAVED && m->layout == QIBL_SHMAPS_INTERLEAVED;
    /* map stride and the pixel's first byte per channel: planar planes (i channels + ch) W H apart,
     * interleaved 16 bytes apart inside the pixel's group */
    const size_t ms = il ? QIBL_SHMAPS_GROUP : (size_t)m->channels * m->width * m->height;
    const size_t cs = il ? (size_t)QIBL_SHMAPS_GROUP * k : (size_t)m->width * m->height;
    const size_t gbytes = (size_t)QIBL_SHMAPS_GROUP * k * m->channels;
    const uint8_t *row = m->planes + (il ? (size_t)y * qibl_shmaps_row_size(m) : off);
    for (uint32_t px = 0; px < n; ++px, pp += 12, out += 3) {
        /* L = S - P, halved once if it needs 33 bits (r0 = 1) */
        const int64_t d0 = pt->pos[0] - (int64_t)qibl_load_s32le(pp), d1 = pt->pos[1] - (int64_t)qibl_load_s32le(pp + 4),
                      d2 = pt->pos[2] - (int64_t)qibl_load_s32le(pp + 8);
        /* some component outside int32: d + 2^31 outside [0, 2^32) (each term < 2^33, so the OR is exact) */
        const int32_t r0 = (((uint64_t)(d0 + INT32_MAX + 1) | (uint64_t)(d1 + INT32_MAX + 1) |
                             (uint64_t)(d2 + INT32_MAX + 1)) >> 32) != 0u;
        int32_t l0, l1, l2;
        if (r0)
            l0 = (int32_t)qibl_asr_s64(d0, 1u), l1 = (int32_t)qibl_asr_s64(d1, 1u), l2 = (int32_t)qibl_asr_s64(d2, 1u);
        else
            l0 = (int32_t)d0, l1 = (int32_t)d1, l2 = (int32_t)d2;
        if ((l0 | l1 | l2) == 0) { /* the light sits on this pixel's surface point */
            out[0] = 0, out[1] = 0, out[2] = 0;
            continue;
        }
        int32_t u0, u1, u2, am, ae;
        poly_dir(l0, l1, l2, &u0, &u1, &u2, &am, &ae);
        ae += r0;
        if (ae < pt->clamp_ae || (ae == pt->clamp_ae && am > pt->clamp_am))
            am = pt->clamp_am, ae = pt->clamp_ae; /* closer than min_dist */
        if (pt->falloff == QIBL_FALLOFF_INV_DIST) { /* 1/D = am 2^(16 - ae) */
            ae -= 16;
        } else { /* 1/D^2 = (am^2 / 2^15) 2^(15 - 2 (ae - 16)) */
            am = (int32_t)(((uint32_t)am * (uint32_t)am) >> 15);
            ae = 2 * ae - 47;
        }
        int16_t yv[QIBL_SH_MAX_COUNT];
        poly_eval(u0, u1, u2, bands, yv);
        const uint32_t x = x0 + px;
        const uint8_t *c0 = il ? row + (size_t)(x / QIBL_SHMAPS_GROUP) * gbytes + x % QIBL_SHMAPS_GROUP : row + px;
        /* per map and channel one multiply-add and one long multiply-accumulate on Cortex-M4:
         * sum_i Y_i (sn_i c_i + bs_i) = acc + accb 2^(14 - pd), exact: |sn c + bs| < 2^29,
         * |sum| < 25 * 14746 * 2^29 < 2^48 */
        int64_t a0 = 0, a1 = 0, a2 = 0;
        {
            const size_t c1 = m->channels == 3u ? cs : 0u, c2 = 2u * c1;
            const uint8_t *c = c0;
            for (uint32_t i = 0; i < k; ++i, c += ms) { /* maps outside, channels inside: Y_i loaded once */
                const int32_t yi = yv[i];
                a0 += qibl_mul_s32_s64(yi, pt->sn[0][i] * (int32_t)c[0] + pt->bs[0][i]);
                a1 += qibl_mul_s32_s64(yi, pt->sn[1][i] * (int32_t)c[c1] + pt->bs[1][i]);
                a2 += qibl_mul_s32_s64(yi, pt->sn[2][i] * (int32_t)c[c2] + pt->bs[2][i]);
            }
        }
        for (uint32_t ch = 0; ch < 3u; ++ch) {
            /* V = round((acc + accb 2^(14 - pd)) / 2^14) */
            const int32_t v = (int32_t)qibl_asr_s64((ch == 0u ? a0 : ch == 1u ? a1 : a2) + 8192, 14);
            const int64_t prod = qibl_mul_s32_s64(v, am * pt->c0m[ch]);
            const int32_t sr = ae + pt->pk[ch];
            int32_t o;
            if ((uint32_t)(sr - 33) <= 29u) { /* the common case, from the high word alone: */
                /* floor((floor(p / 2^32) + 2^j) / 2^(j+1)) = round(p / 2^(33 + j)), |hi| < 2^29 */
                const unsigned j = (unsigned)sr - 33u;
                o = qibl_asr_s32((int32_t)qibl_asr_s64(prod, 32u) + ((int32_t)1 << j), j + 1u);
            } else if (sr > 0)
                o = sr > 62 ? 0 : qibli_rshr_s64(prod, (unsigned)sr);
            else if (prod > INT32_MAX || prod < INT32_MIN || sr < -30)
                o = prod > 0 ? INT32_MAX : prod < 0 ? INT32_MIN : 0;
            else
                o = qibl_sat_s32(qibl_mul_s32_s64((int32_t)prod, (int32_t)1 << -sr));
            out[ch] = o;
        }
    }
}

#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2 || defined(QIBLI_SHMAP_AVX512)
/* What the vector point spans (8 and 16 lanes) need of the maps' layout for row y from x0: the
 * distance between maps (ms), the second channel's offset (c1), an interleaved group's bytes, the
 * pixel offset and the row's bytes. 0 if the light's position is outside int32 (the lanes'
 * subtraction): poly_span takes the span then. */
typedef struct {
    int il;
    size_t ms, c1, gbytes, off;
    const uint8_t *row;
} poly_geom_t;

static int poly_geom(const qibl_shmap_point_t *pt, uint32_t x0, uint32_t y, poly_geom_t *g)
{
    const qibl_shmaps_t *m = pt->maps;
    const uint32_t k = m->k;
    if (pt->pos[0] != (int32_t)pt->pos[0] || pt->pos[1] != (int32_t)pt->pos[1] || pt->pos[2] != (int32_t)pt->pos[2])
        return 0;
    g->il = QIBL_USE_INTERLEAVED && m->layout == QIBL_SHMAPS_INTERLEAVED;
    g->ms = g->il ? QIBL_SHMAPS_GROUP : (size_t)m->channels * m->width * m->height;
    g->c1 = m->channels == 3u ? (g->il ? (size_t)QIBL_SHMAPS_GROUP * k : (size_t)m->width * m->height) : 0u;
    g->gbytes = (size_t)QIBL_SHMAPS_GROUP * k * m->channels;
    g->off = (size_t)y * m->width + x0;
    g->row = m->planes + (g->il ? (size_t)y * qibl_shmaps_row_size(m) : g->off);
    return 1;
}
#endif

#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2 && !defined(QIBLI_SHMAP_AVX512) /* (that copy: poly_span_avx512) */
/* ---- QIBL_POINT_POLY, eight pixels at a time (AVX2) -------------------------------------------
 * poly_span's integers lane by lane, so the bytes are the scalar twin's: int32 lanes for the
 * direction, the one-step rsqrt (seed by gather), the attenuation and the Y recurrences; the sums
 * sum_i Y_i (sn_i c_i + bs_i) in int64 lanes (vpmuldq on the even and the odd lanes); the final
 * scaling's common case from the product's high words. A chunk with a rare lane (S - P needing 33
 * bits, the light on the surface point, an output scale outside the common case) is done whole by
 * poly_span, before anything of it is written. */
/* the rounding terms 2^12, 2^13 of poly_eval8, filled per span out of line and read as memory
 * operands: as immediates gcc rebuilt them (mov, vmovd, vpbroadcastd) at nearly every use */
typedef struct p8_half {
    __m256i h[2];
} p8_half_t;
static QIBLI_NOINLINE void p8_half_fill(p8_half_t *k)
{
    k->h[0] = _mm256_set1_epi32(1 << 12), k->h[1] = _mm256_set1_epi32(1 << 13);
}
/* round(v / 2^s), half up, as POLY_RS (s = 13 or 14) */
#define p8_rs(v, s) _mm256_srai_epi32(_mm256_add_epi32((v), hk->h[(s) - 13]), (s))
#define P8_MUL(a, b) _mm256_mullo_epi32((a), (b))
#define P8_C(v) _mm256_set1_epi32(v)
/* poly_eval's products, every operand an int16 value (|z|, |x|, |y|, |T_m| <= 2^14 + 2, |P| < 23300,
 * rounded A z <= 3 2^13, constants <= 24576), as vpmaddwd (one uop, against vpmulld's two): an
 * int32 lane holding an int16 value times one whose high half is 0 is lo x lo + hi x 0, the
 * product; a sum of two products is one vpmaddwd of (a, b) and (c, d) pairs. Same integers. */
#define P8_CZ(v) _mm256_set1_epi32((int32_t)(uint16_t)(int16_t)(v)) /* v in the low half, 0 above */
#define P8_LO(v) _mm256_blend_epi16((v), zero, 0xAA)                  /* v's low half, 0 above */
#define P8_PR(a, b) _mm256_blend_epi16((a), _mm256_slli_epi32((b), 16), 0xAA) /* (a, b) int16 pair */
#define P8_K(l, m, j) poly_rec[(l) * ((l) + 1) / 2 + (m)][j]
/* P(l,m) = rs(rs(A z, 14) P1 - B P2, 13): (rs(A z), P2) . (P1, -B) as one vpmaddwd */
#define P8_REC(l, m, p1, p2)                                                                            \
    p8_rs(_mm256_madd_epi16(P8_PR(p8_rs(_mm256_madd_epi16(z, P8_CZ(P8_K(l, m, 0))), 14), (p2)),           \
                            _mm256_blend_epi16((p1), P8_C((int32_t)((uint32_t)(uint16_t)(int16_t)-P8_K(l, m, 1) << 16)), 0xAA)), 13)
/* P(l,m) with P2 = 0 */
#define P8_REC0(l, m, p1) p8_rs(_mm256_madd_epi16(p8_rs(_mm256_madd_epi16(z, P8_CZ(P8_K(l, m, 0))), 14), P8_LO(p1)), 13)
/* Y(l,+-m) = rs(P T_+-m, 13); cz##m, sz##m are T_+-m with 0 above; P8_PAIRK for a constant P */
#define P8_PAIR(l, m, p)                                                                                \
    (o[(l) * (l) + (l) + (m)] = p8_rs(_mm256_madd_epi16((p), cz##m), 13), o[(l) * (l) + (l) - (m)] = p8_rs(_mm256_madd_epi16((p), sz##m), 13))
#define P8_PAIRK(l, m, k)                                                                               \
    (o[(l) * (l) + (l) + (m)] = p8_rs(_mm256_madd_epi16(c##m, P8_CZ(k)), 13), o[(l) * (l) + (l) - (m)] = p8_rs(_mm256_madd_epi16(s##m, P8_CZ(k)), 13))
/* T_(m+1) = T_m (x + iy): x c - y s = (x, -y) . (c, s), x s + y c = (x, y) . (s, c) */
#define P8_ROT(m, n)                                                                                    \
    const __m256i c##n = p8_rs(_mm256_madd_epi16(xny, P8_PR(c##m, s##m)), 14);                          \
    const __m256i s##n = p8_rs(_mm256_madd_epi16(xy, P8_PR(s##m, c##m)), 14)

/* poly_eval on eight unit vectors (Q2.14 lanes) as int16 pairs: yp[j] = (Y_2j, Y_2j+1) (|Y| <= 14746),
 * an odd count's last with 0 (pairs at constant indices: the values stay in registers) */
#define P8_OUT(n)                                                                                       \
    do {                                                                                                \
        o[(n)] = zero;                                                                                  \
        for (uint32_t j_ = 0; j_ < ((n) + 1u) / 2u; ++j_)                                               \
            yp[j_] = _mm256_blend_epi16(o[2u * j_], _mm256_slli_epi32(o[2u * j_ + 1u], 16), 0xAA);        \
    } while (0)
static POLY_INLINE void poly_eval8(__m256i x, __m256i y, __m256i z, uint32_t bands, const p8_half_t *hk, __m256i *yp)
{
    const __m256i zero = _mm256_setzero_si256();
    __m256i o[QIBL_SH_MAX_COUNT + 1];
    const int32_t p00 = poly_rec[0][0];
    o[0] = P8_C(2 * p00);
    if (bands < 2u) {
        P8_OUT(1u);
        return;
    }
    const __m256i c1 = x, s1 = y, cz1 = P8_LO(x), sz1 = P8_LO(y);
    const __m256i p10 = p8_rs(_mm256_madd_epi16(p8_rs(_mm256_madd_epi16(z, P8_CZ(P8_K(1, 0, 0))), 14), P8_CZ(p00)), 13);
    o[2] = _mm256_add_epi32(p10, p10);
    P8_PAIRK(1, 1, P8_K(1, 1, 0));
    if (bands < 3u) {
        P8_OUT(4u);
        return;
    }
    const __m256i xy = P8_PR(x, y), xny = P8_PR(x, _mm256_sub_epi32(zero, y));
    P8_ROT(1, 2);
    const __m256i cz2 = P8_LO(c2), sz2 = P8_LO(s2);
    const __m256i p20 = P8_REC(2, 0, p10, P8_C(p00));
    const __m256i p21 = p8_rs(_mm256_madd_epi16(p8_rs(_mm256_madd_epi16(z, P8_CZ(P8_K(2, 1, 0))), 14), P8_CZ(P8_K(1, 1, 0))), 13);
    o[6] = _mm256_add_epi32(p20, p20);
    P8_PAIR(2, 1, p21);
    P8_PAIRK(2, 2, P8_K(2, 2, 0));
    if (bands < 4u) {
        P8_OUT(9u);
        return;
    }
    P8_ROT(2, 3);
    const __m256i cz3 = P8_LO(c3), sz3 = P8_LO(s3);
    const __m256i p30 = P8_REC(3, 0, p20, p10), p31 = P8_REC(3, 1, p21, P8_C(P8_K(1, 1, 0)));
    const __m256i p32 = p8_rs(_mm256_madd_epi16(p8_rs(_mm256_madd_epi16(z, P8_CZ(P8_K(3, 2, 0))), 14), P8_CZ(P8_K(2, 2, 0))), 13);
    o[12] = _mm256_add_epi32(p30, p30);
    P8_PAIR(3, 1, p31);
    P8_PAIR(3, 2, p32);
    P8_PAIRK(3, 3, P8_K(3, 3, 0));
    if (bands < 5u) {
        P8_OUT(16u);
        return;
    }
    P8_ROT(3, 4);
    const __m256i p40 = P8_REC(4, 0, p30, p20), p41 = P8_REC(4, 1, p31, p21), p42 = P8_REC(4, 2, p32, P8_C(P8_K(2, 2, 0)));
    const __m256i p43 = p8_rs(_mm256_madd_epi16(p8_rs(_mm256_madd_epi16(z, P8_CZ(P8_K(4, 3, 0))), 14), P8_CZ(P8_K(3, 3, 0))), 13);
    o[20] = _mm256_add_epi32(p40, p40);
    P8_PAIR(4, 1, p41);
    P8_PAIR(4, 2, p42);
    P8_PAIR(4, 3, p43);
    P8_PAIRK(4, 4, P8_K(4, 4, 0));
    P8_OUT(25u);
}
#undef P8_OUT
#undef P8_ROT
#undef P8_PAIRK
#undef P8_REC0
#undef P8_REC
#undef P8_K
#undef P8_PR
#undef P8_LO
#undef P8_CZ

/* (a b) >> s per uint32 lane, the 64-bit product's bits s .. s + 31 */
static inline __m256i p8_mulshr(__m256i a, __m256i b, int s)
{
    const __m256i e = _mm256_srli_epi64(_mm256_mul_epu32(a, b), s);
    const __m256i o = _mm256_srli_epi64(_mm256_mul_epu32(_mm256_srli_epi64(a, 32), _mm256_srli_epi64(b, 32)), s);
    return _mm256_blend_epi32(e, _mm256_slli_epi64(o, 32), 0xAA);
}

/* bits 32 .. 63 of two int64 vectors (even lanes, odd lanes) as one vector of int32 lanes */
static inline __m256i p8_hi(__m256i pe, __m256i po)
{
    return _mm256_blend_epi32(_mm256_srli_epi64(pe, 32), po, 0xAA);
}

/* Eight pixels from x (their map bytes contiguous per map and channel at c0); 0 if a lane is rare
 * (nothing written then) */
/* The per-pixel front of eight pixels: Y_i and the attenuation am 2^-ae, all in lanes */
#define P8_PAIRS ((QIBL_SH_MAX_COUNT + 1) / 2)
typedef struct p8_front {
    __m256i yp[P8_PAIRS], am, ae; /* (Y_2j, Y_2j+1) as int16 pairs per int32 lane (an odd k's last with 0) */
} p8_front_t;

static POLY_INLINE int poly_front8(const qibl_shmap_point_t *pt, const uint8_t *pp, const uint32_t *seed,
                                   const p8_half_t *hk, p8_front_t *f)
{
    /* the eight points' 96 bytes by three loads, x, y, z separated by blends and one permute each
     * (no vpgatherdd: microcoded and slow on current x86, more so with the gather-data-sampling fix) */
    const __m256i w0 = _mm256_loadu_si256((const __m256i *)(const void *)pp),
                  w1 = _mm256_loadu_si256((const __m256i *)(const void *)(pp + 32)),
                  w2 = _mm256_loadu_si256((const __m256i *)(const void *)(pp + 64));
    /* word j of w0 w1 w2 is coordinate j % 3 of point j / 3 (j = 0 .. 23): x at j = 0, 3, .. 21 */
    const __m256i P0 = _mm256_permutevar8x32_epi32(_mm256_blend_epi32(_mm256_blend_epi32(w0, w1, 0x92), w2, 0x24),
                                                   _mm256_setr_epi32(0, 3, 6, 1, 4, 7, 2, 5));
    const __m256i P1 = _mm256_permutevar8x32_epi32(_mm256_blend_epi32(_mm256_blend_epi32(w0, w1, 0x24), w2, 0x49),
                                                   _mm256_setr_epi32(1, 4, 7, 2, 5, 0, 3, 6));
    const __m256i P2 = _mm256_permutevar8x32_epi32(_mm256_blend_epi32(_mm256_blend_epi32(w0, w1, 0x49), w2, 0x92),
                                                   _mm256_setr_epi32(2, 5, 0, 3, 6, 1, 4, 7));
    const __m256i S0 = P8_C((int32_t)pt->pos[0]), S1 = P8_C((int32_t)pt->pos[1]), S2 = P8_C((int32_t)pt->pos[2]);
    const __m256i l0 = _mm256_sub_epi32(S0, P0), l1 = _mm256_sub_epi32(S1, P1), l2 = _mm256_sub_epi32(S2, P2);
    /* S - P outside int32 (overflow of the lane's subtraction), or L = 0: poly_span */
    const __m256i ovf = _mm256_or_si256(
        _mm256_or_si256(_mm256_and_si256(_mm256_xor_si256(S0, P0), _mm256_xor_si256(S0, l0)),
                        _mm256_and_si256(_mm256_xor_si256(S1, P1), _mm256_xor_si256(S1, l1))),
        _mm256_and_si256(_mm256_xor_si256(S2, P2), _mm256_xor_si256(S2, l2)));
    const __m256i zero = _mm256_setzero_si256();
    const __m256i lz = _mm256_cmpeq_epi32(_mm256_or_si256(_mm256_or_si256(l0, l1), l2), zero);
    if (_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_or_si256(ovf, lz))) != 0)
        return 0;
    /* poly_dir: sc = bitlen(max |l|) - 15, the bit length from an exact int -> float conversion of a
     * value below 2^24 (mx >> 8 when mx needs more bits) */
    const __m256i a0 = _mm256_abs_epi32(l0), a1 = _mm256_abs_epi32(l1), a2 = _mm256_abs_epi32(l2);
    const __m256i mx = _mm256_or_si256(_mm256_or_si256(a0, a1), a2);
    const __m256i big = _mm256_cmpeq_epi32(_mm256_srli_epi32(mx, 24), zero); /* -1 where mx < 2^24 */
    const __m256i mv = _mm256_blendv_epi8(_mm256_srli_epi32(mx, 8), mx, big);
    const __m256i fexp = _mm256_srli_epi32(_mm256_castps_si256(_mm256_cvtepi32_ps(mv)), 23);
    const __m256i bitlen = _mm256_add_epi32(_mm256_sub_epi32(fexp, P8_C(126)), _mm256_andnot_si256(big, P8_C(8)));
    const __m256i sc = _mm256_sub_epi32(bitlen, P8_C(15));
    const __m256i rs = _mm256_max_epi32(sc, zero), ls = _mm256_max_epi32(_mm256_sub_epi32(zero, sc), zero);
    const __m256i v0 = _mm256_sllv_epi32(_mm256_abs_epi32(_mm256_srav_epi32(l0, rs)), ls);
    const __m256i v1 = _mm256_sllv_epi32(_mm256_abs_epi32(_mm256_srav_epi32(l1, rs)), ls);
    const __m256i v2 = _mm256_sllv_epi32(_mm256_abs_epi32(_mm256_srav_epi32(l2, rs)), ls);
    const __m256i d2 = _mm256_add_epi32(_mm256_add_epi32(P8_MUL(v0, v0), P8_MUL(v1, v1)), P8_MUL(v2, v2));
    const __m256i h = _mm256_and_si256(_mm256_cmpeq_epi32(_mm256_srli_epi32(d2, 30), zero), P8_C(1));
    const __m256i t = _mm256_sllv_epi32(d2, _mm256_add_epi32(h, h));
    const __m256i y0 = _mm256_i32gather_epi32((const int *)(const void *)seed,
                                              _mm256_sub_epi32(_mm256_srli_epi32(t, 24), P8_C(64)), 4);
    const __m256i hh = p8_mulshr(P8_MUL(y0, y0), t, 32);
    const __m256i y16 = p8_mulshr(y0, _mm256_sub_epi32(P8_C(0x30000000), hh), 28);
    const __m256i r = _mm256_sub_epi32(P8_C(17), h), half = _mm256_sllv_epi32(P8_C(1), _mm256_sub_epi32(r, P8_C(1)));
    const __m256i lim = P8_C(16384);
    const __m256i u0 = _mm256_sign_epi32(_mm256_min_epu32(_mm256_srlv_epi32(_mm256_add_epi32(P8_MUL(v0, y16), half), r), lim), l0);
    const __m256i u1 = _mm256_sign_epi32(_mm256_min_epu32(_mm256_srlv_epi32(_mm256_add_epi32(P8_MUL(v1, y16), half), r), lim), l1);
    const __m256i u2 = _mm256_sign_epi32(_mm256_min_epu32(_mm256_srlv_epi32(_mm256_add_epi32(P8_MUL(v2, y16), half), r), lim), l2);
    __m256i am = _mm256_srli_epi32(y16, 1), ae = _mm256_add_epi32(_mm256_sub_epi32(P8_C(30), h), sc);
    {
        const __m256i cae = P8_C(pt->clamp_ae), cam = P8_C(pt->clamp_am);
        const __m256i cl = _mm256_or_si256(_mm256_cmpgt_epi32(cae, ae),
                                           _mm256_and_si256(_mm256_cmpeq_epi32(ae, cae), _mm256_cmpgt_epi32(am, cam)));
        am = _mm256_blendv_epi8(am, cam, cl), ae = _mm256_blendv_epi8(ae, cae, cl);
    }
    if (pt->falloff == QIBL_FALLOFF_INV_DIST) {
        ae = _mm256_sub_epi32(ae, P8_C(16));
    } else {
        am = _mm256_srli_epi32(P8_MUL(am, am), 15);
        ae = _mm256_sub_epi32(_mm256_add_epi32(ae, ae), P8_C(47));
    }
    /* bands^2 >= k values: a pair past k pairs with factors 0 (p8_tab_fill) */
    poly_eval8(u0, u1, u2, pt->bands, hk, f->yp);
    f->am = am, f->ae = ae;
    return 1;
}

/* The sums of eight pixels in 16-bit products (vpmaddwd), exact in int32 lanes, no int64:
 *   S = sum_i Y_i (sn_i c_i + bs_i) = 2^8 SA + SB + 2^(14 - pd) SN,
 *   SA = sum_i Y_i (a_i c_i), SB = sum_i Y_i (b_i c_i), SN = sum_i Y_i bn_i,
 * with sn_i = 2^8 a_i + b_i, b_i in [-128, 127] (sn's low byte, signed), |a_i| <= 128, so |a_i c|,
 * |b_i c| <= 32640 are int16 (one vpmullw each) and Y_i (|Y_i| <= 14746) pairs with them: one
 * vpmaddwd per two maps. Bounds: SN is prepare's (|SN| < 1.9 2^30, any order). SA and SB run in
 * one int32 accumulator per P8_GROUP pairs (maps 10g .. 10g + 9), each < 2^31: for real orthonormal
 * SH, sum_m Y_lm^2 = (2l + 1) / (4 pi), so n of band l's values have sum |Y| <= sqrt(n (2l + 1) / (4 pi));
 * maps 0-9 (bands 0-2 and one of band 3) 3.29, maps 10-19 (six of band 3, four of band 4) 3.53,
 * maps 20-24 1.90, so sum |Y14| <= 3.53 2^14 + 10 * 16 LSB of Y error < 58000 and
 * 58000 * 32640 < 1.9e9 < 2^31 (shmap_test's aligned case wraps one sum over all maps). Then
 * V = round(S / 2^14) without 64 bits: per group
 * 2^8 SA + SB = 2^14 d + e with d = (SA + (SB >> 8)) >> 6 and 0 <= e < 2^14, likewise
 * 2^(14 - pd) SN = 2^14 (SN >> pd) + e', so S + 2^13 = 2^14 Q + R with |Q| < 2^31 and
 * 0 <= R < 2^16: R is exact from wrapping int32 arithmetic, and V = Q + (R >> 14). */
#define P8_GROUP 5u
/* the per-span tables of poly_back8: (a_2j, a_2j+1), (b_2j, b_2j+1), (bn_2j, bn_2j+1) as int16
 * pairs in every int32 lane, [kind][channel][pair] */
typedef struct p8_tab {
    __m256i v[3][3][P8_PAIRS];
} p8_tab_t;

static void p8_tab_fill(const qibl_shmap_point_t *pt, uint32_t k, p8_tab_t *t)
{
    for (uint32_t ch = 0; ch < 3u; ++ch)
        for (uint32_t j = 0; j < (k + 1u) / 2u; ++j) {
            int16_t a[2], b[2], n[2];
            for (uint32_t h = 0; h < 2u; ++h) {
                const uint32_t i = 2u * j + h;
                const int32_t sn = i < k ? pt->sn[ch][i] : 0;
                b[h] = (int16_t)(((sn + 128) & 255) - 128); /* the low byte, signed */
                a[h] = (int16_t)((sn - b[h]) / 256);       /* exact */
                n[h] = i < k ? pt->bn[ch][i] : 0;
            }
            t->v[0][ch][j] = _mm256_blend_epi16(_mm256_set1_epi16(a[0]), _mm256_set1_epi16(a[1]), 0xAA);
            t->v[1][ch][j] = _mm256_blend_epi16(_mm256_set1_epi16(b[0]), _mm256_set1_epi16(b[1]), 0xAA);
            t->v[2][ch][j] = _mm256_blend_epi16(_mm256_set1_epi16(n[0]), _mm256_set1_epi16(n[1]), 0xAA);
        }
}

/* SA and SB of one chunk's maps 2 j0 .. 2 jend - 1 (whole pairs) of one channel (its bytes at c, maps
 * ms apart; an odd k's last map, tail, pairs with its own bytes), folded into the chunk's q, r */
static POLY_INLINE void p8_group(const p8_front_t *f, const __m256i *ap, const __m256i *bp, const uint8_t *c, size_t ms,
                                 uint32_t j0, uint32_t jend, int tail, __m256i *q, __m256i *r)
{
    const __m256i zero = _mm256_setzero_si256();
    __m256i sa = zero, sb = zero;
#define P8_LD(p) _mm_loadl_epi64((const __m128i *)(const void *)(p))
#define P8_MP(pc, o2)                                                                                                \
    do {                                                                                                            \
        const __m256i cp = _mm256_cvtepu8_epi16(_mm_unpacklo_epi8(P8_LD(pc), P8_LD((pc) + (o2))));                  \
        sa = _mm256_add_epi32(_mm256_madd_epi16(_mm256_mullo_epi16(cp, ap[j]), f->yp[j]), sa);                      \
        sb = _mm256_add_epi32(_mm256_madd_epi16(_mm256_mullo_epi16(cp, bp[j]), f->yp[j]), sb);                      \
    } while (0)
    uint32_t j = j0;
    for (const uint8_t *pc = c + 2u * j0 * ms; j < jend; ++j, pc += 2u * ms)
        P8_MP(pc, ms);
    if (tail)
        P8_MP(c + 2u * j * ms, 0u);
#undef P8_MP
#undef P8_LD
    const __m256i d = _mm256_srai_epi32(_mm256_add_epi32(sa, _mm256_srai_epi32(sb, 8)), 6);
    *q = _mm256_add_epi32(*q, d);
    *r = _mm256_add_epi32(*r, _mm256_sub_epi32(_mm256_add_epi32(_mm256_slli_epi32(sa, 8), sb), _mm256_slli_epi32(d, 14)));
}

/* SN, V and the final scaling of one chunk whose front is f and whose SA, SB are in q, r (per
 * channel), into out; 0 if a lane's scaling is rare (nothing written then) */
static POLY_INLINE int p8_finish(const qibl_shmap_point_t *pt, const p8_front_t *f, const p8_tab_t *tab, const __m256i *q,
                                 const __m256i *r, int32_t *out)
{
    const uint32_t np = (pt->maps->k + 1u) / 2u;
    const __m256i am = f->am, ae = f->ae, zero = _mm256_setzero_si256();
    __m256i n0 = zero, n1 = zero, n2 = zero;
    for (uint32_t j = 0; j < np; ++j) {
        n0 = _mm256_add_epi32(_mm256_madd_epi16(tab->v[2][0][j], f->yp[j]), n0);
        n1 = _mm256_add_epi32(_mm256_madd_epi16(tab->v[2][1][j], f->yp[j]), n1);
        n2 = _mm256_add_epi32(_mm256_madd_epi16(tab->v[2][2][j], f->yp[j]), n2);
    }
    /* 2^(14 - pd) SN = 2^14 (SN >> pd) + e', 0 <= e' < 2^14 */
    __m256i V[3];
    for (uint32_t ch = 0; ch < 3u; ++ch) {
        const __m256i sn = ch == 0u ? n0 : ch == 1u ? n1 : n2;
        const __m256i qn = _mm256_sra_epi32(sn, _mm_cvtsi32_si128(pt->pd[ch]));
        const __m256i rr = _mm256_add_epi32(r[ch], _mm256_sub_epi32(_mm256_sll_epi32(sn, _mm_cvtsi32_si128(14 - pt->pd[ch])),
                                                                   _mm256_slli_epi32(qn, 14)));
        V[ch] = _mm256_add_epi32(_mm256_add_epi32(q[ch], qn), _mm256_srli_epi32(rr, 14));
    }
    __m256i res[3];
    for (int ch = 0; ch < 3; ++ch) {
        const __m256i g = P8_MUL(am, P8_C(pt->c0m[ch])); /* <= 2^30 */
        const __m256i pe = _mm256_mul_epi32(V[ch], g),
                      po = _mm256_mul_epi32(_mm256_srli_epi64(V[ch], 32), _mm256_srli_epi64(g, 32));
        const __m256i sr = _mm256_add_epi32(ae, P8_C(pt->pk[ch]));
        /* the common case 33 <= sr <= 62 only: round(p / 2^sr) from the high word */
        const __m256i ok = _mm256_and_si256(_mm256_cmpgt_epi32(sr, P8_C(32)), _mm256_cmpgt_epi32(P8_C(63), sr));
        if (_mm256_movemask_ps(_mm256_castsi256_ps(ok)) != 0xFF)
            return 0;
        const __m256i sj = _mm256_sub_epi32(sr, P8_C(33));
        const __m256i o = _mm256_srav_epi32(_mm256_add_epi32(p8_hi(pe, po), _mm256_sllv_epi32(P8_C(1), sj)),
                                            _mm256_add_epi32(sj, P8_C(1)));
        res[ch] = o;
    }
    /* RGB interleaved: each output vector takes its lanes from R, G and B by one permute each */
    const __m256i vr = res[0], vg = res[1], vb = res[2];
    const __m256i w0 = _mm256_blend_epi32(
        _mm256_blend_epi32(_mm256_permutevar8x32_epi32(vr, _mm256_setr_epi32(0, 0, 0, 1, 0, 0, 2, 0)),
                           _mm256_permutevar8x32_epi32(vg, _mm256_setr_epi32(0, 0, 0, 0, 1, 0, 0, 2)), 0x92),
        _mm256_permutevar8x32_epi32(vb, _mm256_setr_epi32(0, 0, 0, 0, 0, 1, 0, 0)), 0x24);
    const __m256i w1 = _mm256_blend_epi32(
        _mm256_blend_epi32(_mm256_permutevar8x32_epi32(vr, _mm256_setr_epi32(0, 3, 0, 0, 4, 0, 0, 5)),
                           _mm256_permutevar8x32_epi32(vg, _mm256_setr_epi32(0, 0, 3, 0, 0, 4, 0, 0)), 0x24),
        _mm256_permutevar8x32_epi32(vb, _mm256_setr_epi32(2, 0, 0, 3, 0, 0, 4, 0)), 0x49);
    const __m256i w2 = _mm256_blend_epi32(
        _mm256_blend_epi32(_mm256_permutevar8x32_epi32(vr, _mm256_setr_epi32(0, 0, 6, 0, 0, 7, 0, 0)),
                           _mm256_permutevar8x32_epi32(vg, _mm256_setr_epi32(5, 0, 0, 6, 0, 0, 7, 0)), 0x49),
        _mm256_permutevar8x32_epi32(vb, _mm256_setr_epi32(0, 5, 0, 0, 6, 0, 0, 7)), 0x92);
    _mm256_storeu_si256((__m256i *)(void *)out, w0);
    _mm256_storeu_si256((__m256i *)(void *)(out + 8), w1);
    _mm256_storeu_si256((__m256i *)(void *)(out + 16), w2);
    return 1;
}

/* poly_span in blocks of up to P8_BLOCK chunks of eight pixels (interleaved: chunks aligned to half
 * groups, so their bytes are contiguous): the fronts of the block's chunks, then per channel and
 * group of maps the sums over the block's chunks (the block's bytes of a plane are one cache line,
 * read by one pass: the planes of one pixel share an L1 set, so reading all of them per chunk
 * missed L1), then the finishing; the head, the tail and rare chunks by poly_span */
#define P8_BLOCK 8u
static void poly_span_avx2(const qibl_shmap_point_t *pt, uint32_t x0, uint32_t y, uint32_t n, int32_t *out)
{
    const uint32_t k = pt->maps->k, np = (k + 1u) / 2u;
    poly_geom_t g;
    if (!poly_geom(pt, x0, y, &g)) {
        poly_span(pt, x0, y, n, out);
        return;
    }
    const int il = g.il;
    const size_t ms = g.ms, c1 = g.c1, gbytes = g.gbytes, off = g.off;
    const uint8_t *row = g.row;
    uint32_t seed[192];
    for (uint32_t i = 0; i < 192u; ++i)
        seed[i] = qibli_rsqrt_seed[i];
    p8_tab_t tab;
    p8_tab_fill(pt, k, &tab);
    p8_half_t hk;
    p8_half_fill(&hk);
    uint32_t px = 0u;
    if (il && x0 % 8u != 0u) {
        px = 8u - x0 % 8u < n ? 8u - x0 % 8u : n;
        poly_span(pt, x0, y, px, out);
    }
    p8_front_t fr[P8_BLOCK];
    __m256i q[P8_BLOCK][3], r[P8_BLOCK][3];
    const uint8_t *cb[P8_BLOCK];
    int ok[P8_BLOCK];
    while (px + 8u <= n) {
        const uint32_t nb = (n - px) / 8u < P8_BLOCK ? (n - px) / 8u : P8_BLOCK;
        for (uint32_t b = 0; b < nb; ++b) {
            const uint32_t x = x0 + px + 8u * b;
            ok[b] = poly_front8(pt, pt->pmap->points + (off + px + 8u * b) * 12u, seed, &hk, &fr[b]);
            cb[b] = il ? row + (size_t)(x / QIBL_SHMAPS_GROUP) * gbytes + x % QIBL_SHMAPS_GROUP : row + px + 8u * b;
            for (uint32_t ch = 0; ch < 3u; ++ch)
                q[b][ch] = _mm256_setzero_si256(), r[b][ch] = _mm256_set1_epi32(8192);
        }
        for (uint32_t ch = 0; ch < 3u; ++ch)
            for (uint32_t j0 = 0; j0 < np; j0 += P8_GROUP) {
                const uint32_t jend = j0 + P8_GROUP < k / 2u ? j0 + P8_GROUP : k / 2u;
                const int tail = (k & 1u) && j0 + P8_GROUP >= np;
                for (uint32_t b = 0; b < nb; ++b)
                    if (ok[b])
                        p8_group(&fr[b], tab.v[0][ch], tab.v[1][ch], cb[b] + ch * c1, ms, j0, jend, tail, &q[b][ch], &r[b][ch]);
            }
        for (uint32_t b = 0; b < nb; ++b, px += 8u)
            if (!ok[b] || !p8_finish(pt, &fr[b], &tab, q[b], r[b], out + 3u * px))
                poly_span(pt, x0 + px, y, 8u, out + 3u * px);
    }
    if (px < n)
        poly_span(pt, x0 + px, y, n - px, out + 3u * px);
}
#endif

#if defined(QIBLI_SHMAP_AVX512)
/* ---- QIBL_POINT_POLY, sixteen pixels at a time (AVX-512: x86/shmap_avx512.c only) --------------
 * poly_span_avx2's integers on 512-bit lanes (see there for every bound): compares into mask
 * registers; each vpmaddwd + vpaddd pair, the rounding terms of poly_eval's products included, as
 * one vpdpwssd (VNNI: the same wrapping int32 sum of two int16 products); the bit length by
 * vplzcntd (CD); the seed by word permutes. A rare lane (S - P needing 33 bits, the light on the
 * surface point, an output scale outside the common case) is stored with the chunk, then redone
 * alone by poly_span: only that pixel takes the slow path. */
typedef struct p16_half {
    __m512i h[2]; /* 2^12, 2^13: read as memory operands (see p8_half_t) */
} p16_half_t;
static QIBLI_NOINLINE void p16_half_fill(p16_half_t *k)
{
    k->h[0] = _mm512_set1_epi32(1 << 12), k->h[1] = _mm512_set1_epi32(1 << 13);
}
/* round((a . b) / 2^s), half up, a . b the pairwise int16 dot product (s = 13 or 14) */
#define P16_RS(a, b, s) _mm512_srai_epi32(_mm512_dpwssd_epi32(hk->h[(s) - 13], (a), (b)), (s))
#define P16_C(v) _mm512_set1_epi32(v)
#define P16_CZ(v) _mm512_set1_epi32((int32_t)(uint16_t)(int16_t)(v))                 /* v in the low half */
#define P16_LO(v) _mm512_maskz_mov_epi16(0x55555555u, (v))                              /* v's low half, 0 above */
/* (a, b) int16 pair: b's low half moved up by a byte shift (a shuffle-port uop; shifts, multiplies
 * and vpdpwssd all queue for the one other 512-bit port, which bounds this kernel) */
#define P16_PR(a, b) _mm512_mask_blend_epi16(0xAAAAAAAAu, (a), _mm512_bslli_epi128((b), 2))
#define P16_K(l, m, j) poly_rec[(l) * ((l) + 1) / 2 + (m)][j]
/* P(l,m) = rs(rs(A z, 14) P1 - B P2, 13) */
#define P16_NB(l, m) P16_C((int32_t)((uint32_t)(uint16_t)(int16_t)-P16_K(l, m, 1) << 16)) /* -B in the high half */
#define P16_REC(l, m, p1, p2)                                                                                      \
    P16_RS(P16_PR(P16_RS(z, P16_CZ(P16_K(l, m, 0)), 14), (p2)),                                                     \
           _mm512_mask_blend_epi16(0xAAAAAAAAu, (p1), P16_NB(l, m)), 13)
/* P(l,m) with P2 = 0 and a constant P1 */
#define P16_REC0(l, m, k1) P16_RS(P16_RS(z, P16_CZ(P16_K(l, m, 0)), 14), P16_CZ(k1), 13)
#define P16_PAIR(l, m, p)                                                                                          \
    (o[(l) * (l) + (l) + (m)] = P16_RS((p), cz##m, 13), o[(l) * (l) + (l) - (m)] = P16_RS((p), sz##m, 13))
#define P16_PAIRK(l, m, k)                                                                                         \
    (o[(l) * (l) + (l) + (m)] = P16_RS(c##m, P16_CZ(k), 13), o[(l) * (l) + (l) - (m)] = P16_RS(s##m, P16_CZ(k), 13))
#define P16_ROT(m, n)                                                                                              \
    const __m512i c##n = P16_RS(xny, P16_PR(c##m, s##m), 14);                                                       \
    const __m512i s##n = P16_RS(xy, P16_PR(s##m, c##m), 14)
#define P16_OUT(n)                                                                                                 \
    do {                                                                                                           \
        o[(n)] = zero;                                                                                             \
        for (uint32_t j_ = 0; j_ < ((n) + 1u) / 2u; ++j_)                                                          \
            yp[j_] = P16_PR(o[2u * j_], o[2u * j_ + 1u]);                                                          \
    } while (0)
/* poly_eval8 on sixteen unit vectors: yp[j] = (Y_2j, Y_2j+1) as int16 pairs */
static POLY_INLINE void poly_eval16(__m512i x, __m512i y, __m512i z, uint32_t bands, const p16_half_t *hk, __m512i *yp)
{
    const __m512i zero = _mm512_setzero_si512();
    __m512i o[QIBL_SH_MAX_COUNT + 1];
    const int32_t p00 = poly_rec[0][0];
    o[0] = P16_C(2 * p00);
    if (bands < 2u) {
        P16_OUT(1u);
        return;
    }
    const __m512i c1 = x, s1 = y, cz1 = P16_LO(x), sz1 = P16_LO(y);
    const __m512i p10 = P16_REC0(1, 0, p00);
    o[2] = _mm512_add_epi32(p10, p10);
    P16_PAIRK(1, 1, P16_K(1, 1, 0));
    if (bands < 3u) {
        P16_OUT(4u);
        return;
    }
    const __m512i xy = P16_PR(x, y), xny = P16_PR(x, _mm512_sub_epi32(zero, y));
    P16_ROT(1, 2);
    const __m512i cz2 = P16_LO(c2), sz2 = P16_LO(s2);
    const __m512i p20 = P16_REC(2, 0, p10, P16_C(p00));
    const __m512i p21 = P16_REC0(2, 1, P16_K(1, 1, 0));
    o[6] = _mm512_add_epi32(p20, p20);
    P16_PAIR(2, 1, p21);
    P16_PAIRK(2, 2, P16_K(2, 2, 0));
    if (bands < 4u) {
        P16_OUT(9u);
        return;
    }
    P16_ROT(2, 3);
    const __m512i cz3 = P16_LO(c3), sz3 = P16_LO(s3);
    const __m512i p30 = P16_REC(3, 0, p20, p10), p31 = P16_REC(3, 1, p21, P16_C(P16_K(1, 1, 0)));
    const __m512i p32 = P16_REC0(3, 2, P16_K(2, 2, 0));
    o[12] = _mm512_add_epi32(p30, p30);
    P16_PAIR(3, 1, p31);
    P16_PAIR(3, 2, p32);
    P16_PAIRK(3, 3, P16_K(3, 3, 0));
    if (bands < 5u) {
        P16_OUT(16u);
        return;
    }
    P16_ROT(3, 4);
    const __m512i p40 = P16_REC(4, 0, p30, p20), p41 = P16_REC(4, 1, p31, p21);
    const __m512i p42 = P16_REC(4, 2, p32, P16_C(P16_K(2, 2, 0)));
    const __m512i p43 = P16_REC0(4, 3, P16_K(3, 3, 0));
    o[20] = _mm512_add_epi32(p40, p40);
    P16_PAIR(4, 1, p41);
    P16_PAIR(4, 2, p42);
    P16_PAIR(4, 3, p43);
    P16_PAIRK(4, 4, P16_K(4, 4, 0));
    P16_OUT(25u);
}
#undef P16_OUT
#undef P16_ROT
#undef P16_PAIRK
#undef P16_PAIR
#undef P16_REC0
#undef P16_REC
#undef P16_NB
#undef P16_K
#undef P16_PR
#undef P16_LO
#undef P16_CZ
#undef P16_RS

/* (a, b) int16 pair of two lanes whose high halves are 0 (poly_eval16's P16_PR) */
#define P16_PRV(a, b) _mm512_mask_blend_epi16(0xAAAAAAAAu, (a), _mm512_bslli_epi128((b), 2))
/* (a b) >> s per uint32 lane (s <= 32), the 64-bit product's bits s .. s + 31: the odd lanes moved
 * down by a shuffle, their result taken from the high half of the product shifted left by 32 - s */
static inline __m512i p16_mulshr(__m512i a, __m512i b, int s)
{
    const __m512i e = _mm512_srli_epi64(_mm512_mul_epu32(a, b), (unsigned)s);
    const __m512i o = _mm512_mul_epu32(_mm512_shuffle_epi32(a, _MM_PERM_DDBB), _mm512_shuffle_epi32(b, _MM_PERM_DDBB));
    return _mm512_mask_blend_epi32(0xAAAAu, e, s == 32 ? o : _mm512_slli_epi64(o, (unsigned)(32 - s)));
}

#define P16_PAIRS ((QIBL_SH_MAX_COUNT + 1) / 2)
typedef struct p16_front {
    __m512i yp[P16_PAIRS], am, ae; /* as p8_front_t */
} p16_front_t;

/* The direction (unit vectors u, Q2.14) and attenuation (into f) of sixteen pixels (points at pp);
 * returns the lanes poly_span must redo. Y comes after, by poly_eval16 over the block's chunks:
 * two shorter dependency chains per chunk, which out-of-order execution overlaps across chunks. */
static POLY_INLINE __mmask16 poly_front16(const qibl_shmap_point_t *pt, const uint8_t *pp, const __m512i *seed,
                                          __m512i *u, p16_front_t *f)
{
    /* the 192 bytes by three loads; coordinate c of point i is word 3i + c: two permutes each */
    const __m512i w0 = _mm512_loadu_si512((const void *)pp), w1 = _mm512_loadu_si512((const void *)(pp + 64)),
                  w2 = _mm512_loadu_si512((const void *)(pp + 128));
    const __m512i P0 = _mm512_permutex2var_epi32(
        _mm512_permutex2var_epi32(w0, _mm512_setr_epi32(0, 3, 6, 9, 12, 15, 18, 21, 24, 27, 30, 0, 0, 0, 0, 0), w1),
        _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 17, 20, 23, 26, 29), w2);
    const __m512i P1 = _mm512_permutex2var_epi32(
        _mm512_permutex2var_epi32(w0, _mm512_setr_epi32(1, 4, 7, 10, 13, 16, 19, 22, 25, 28, 31, 0, 0, 0, 0, 0), w1),
        _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 18, 21, 24, 27, 30), w2);
    const __m512i P2 = _mm512_permutex2var_epi32(
        _mm512_permutex2var_epi32(w0, _mm512_setr_epi32(2, 5, 8, 11, 14, 17, 20, 23, 26, 29, 0, 0, 0, 0, 0, 0), w1),
        _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 16, 19, 22, 25, 28, 31), w2);
    const __m512i S0 = P16_C((int32_t)pt->pos[0]), S1 = P16_C((int32_t)pt->pos[1]), S2 = P16_C((int32_t)pt->pos[2]);
    const __m512i l0 = _mm512_sub_epi32(S0, P0), l1 = _mm512_sub_epi32(S1, P1), l2 = _mm512_sub_epi32(S2, P2);
    const __m512i zero = _mm512_setzero_si512();
    /* S - P outside int32 (the lane's subtraction overflowed), or L = 0 */
    const __m512i ovf = _mm512_or_si512(
        _mm512_or_si512(_mm512_and_si512(_mm512_xor_si512(S0, P0), _mm512_xor_si512(S0, l0)),
                        _mm512_and_si512(_mm512_xor_si512(S1, P1), _mm512_xor_si512(S1, l1))),
        _mm512_and_si512(_mm512_xor_si512(S2, P2), _mm512_xor_si512(S2, l2)));
    const __m512i lor = _mm512_or_si512(_mm512_or_si512(l0, l1), l2);
    const __mmask16 bad = (__mmask16)(_mm512_cmplt_epi32_mask(ovf, zero) | _mm512_testn_epi32_mask(lor, lor));
    /* poly_dir: sc = 17 - clz(max |l|) */
    const __m512i a0 = _mm512_abs_epi32(l0), a1 = _mm512_abs_epi32(l1), a2 = _mm512_abs_epi32(l2);
    const __m512i sc = _mm512_sub_epi32(P16_C(17), _mm512_lzcnt_epi32(_mm512_or_si512(_mm512_or_si512(a0, a1), a2)));
    const __m512i rs = _mm512_max_epi32(sc, zero), ls = _mm512_max_epi32(_mm512_sub_epi32(zero, sc), zero);
    const __m512i v0 = _mm512_sllv_epi32(_mm512_abs_epi32(_mm512_srav_epi32(l0, rs)), ls);
    const __m512i v1 = _mm512_sllv_epi32(_mm512_abs_epi32(_mm512_srav_epi32(l1, rs)), ls);
    const __m512i v2 = _mm512_sllv_epi32(_mm512_abs_epi32(_mm512_srav_epi32(l2, rs)), ls);
    /* d2 = v0^2 + v1^2 + v2^2 by one vpmaddwd and one vpdpwssd: v <= 2^15 with 0 above, as int16
     * -2^15 when it is 2^15, whose square is the same 2^30; the sum wraps as uint32 arithmetic does */
    const __m512i d2 = _mm512_dpwssd_epi32(_mm512_madd_epi16(P16_PRV(v0, v1), P16_PRV(v0, v1)), v2, v2);
    const __mmask16 hm = _mm512_testn_epi32_mask(d2, P16_C((int32_t)0xC0000000u)); /* d2 < 2^30: h = 1 */
    const __m512i h = _mm512_maskz_mov_epi32(hm, P16_C(1));
    const __m512i t = _mm512_mask_slli_epi32(d2, hm, d2, 2);
    /* the seed: qibli_rsqrt_seed's 192 int16 values in six registers, looked up 64 at a time by
     * vpermt2w (index in the low half of each lane; the high half's word is masked off). A gather
     * cost more (microcoded, slower with the gather-data-sampling fix); a bad lane reads any entry. */
    const __m512i ix = _mm512_sub_epi32(_mm512_srli_epi32(t, 24), P16_C(64));
    __m512i y0 = _mm512_permutex2var_epi16(seed[0], ix, seed[1]);
    y0 = _mm512_mask_mov_epi32(y0, _mm512_cmpge_epu32_mask(ix, P16_C(64)),
                               _mm512_permutex2var_epi16(seed[2], ix, seed[3]));
    y0 = _mm512_mask_mov_epi32(y0, _mm512_cmpge_epu32_mask(ix, P16_C(128)),
                               _mm512_permutex2var_epi16(seed[4], ix, seed[5]));
    y0 = _mm512_maskz_mov_epi16(0x55555555u, y0);
    const __m512i hh = p16_mulshr(_mm512_madd_epi16(y0, y0), t, 32); /* y0 < 2^15, 0 above: y0^2 */
    const __m512i y16 = p16_mulshr(y0, _mm512_sub_epi32(P16_C(0x30000000), hh), 28);
    const __m512i r = _mm512_sub_epi32(P16_C(17), h), half = _mm512_mask_mov_epi32(P16_C(1 << 16), hm, P16_C(1 << 15));
    const __m512i lim = P16_C(16384);
    const __m512i q0 = _mm512_min_epu32(_mm512_srlv_epi32(_mm512_add_epi32(_mm512_mullo_epi32(v0, y16), half), r), lim);
    const __m512i q1 = _mm512_min_epu32(_mm512_srlv_epi32(_mm512_add_epi32(_mm512_mullo_epi32(v1, y16), half), r), lim);
    const __m512i q2 = _mm512_min_epu32(_mm512_srlv_epi32(_mm512_add_epi32(_mm512_mullo_epi32(v2, y16), half), r), lim);
    const __m512i u0 = _mm512_mask_sub_epi32(q0, _mm512_cmplt_epi32_mask(l0, zero), zero, q0);
    const __m512i u1 = _mm512_mask_sub_epi32(q1, _mm512_cmplt_epi32_mask(l1, zero), zero, q1);
    const __m512i u2 = _mm512_mask_sub_epi32(q2, _mm512_cmplt_epi32_mask(l2, zero), zero, q2);
    __m512i am = _mm512_srli_epi32(y16, 1), ae = _mm512_add_epi32(_mm512_sub_epi32(P16_C(30), h), sc);
    {
        const __m512i cae = P16_C(pt->clamp_ae), cam = P16_C(pt->clamp_am);
        const __mmask16 cl = (__mmask16)(_mm512_cmpgt_epi32_mask(cae, ae) |
                                         (_mm512_cmpeq_epi32_mask(ae, cae) & _mm512_cmpgt_epi32_mask(am, cam)));
        am = _mm512_mask_mov_epi32(am, cl, cam), ae = _mm512_mask_mov_epi32(ae, cl, cae);
    }
    if (pt->falloff == QIBL_FALLOFF_INV_DIST) {
        ae = _mm512_sub_epi32(ae, P16_C(16));
    } else {
        am = _mm512_srli_epi32(_mm512_mullo_epi32(am, am), 15);
        ae = _mm512_sub_epi32(_mm512_add_epi32(ae, ae), P16_C(47));
    }
    u[0] = u0, u[1] = u1, u[2] = u2;
    f->am = am, f->ae = ae;
    return bad;
}

/* p8_tab_t on sixteen lanes: (x_2j, x_2j+1) int16 pairs, [kind][channel][pair] */
typedef struct p16_tab {
    __m512i v[3][3][P16_PAIRS];
} p16_tab_t;

static void p16_tab_fill(const qibl_shmap_point_t *pt, uint32_t k, p16_tab_t *t)
{
    for (uint32_t ch = 0; ch < 3u; ++ch)
        for (uint32_t j = 0; j < (k + 1u) / 2u; ++j) {
            uint32_t a = 0u, b = 0u, n = 0u;
            for (uint32_t h = 0; h < 2u; ++h) {
                const uint32_t i = 2u * j + h;
                const int32_t sn = i < k ? pt->sn[ch][i] : 0;
                const int32_t lo = ((sn + 128) & 255) - 128; /* the low byte, signed */
                a |= (uint32_t)(uint16_t)(int16_t)((sn - lo) / 256) << (16u * h);
                b |= (uint32_t)(uint16_t)(int16_t)lo << (16u * h);
                n |= (uint32_t)(uint16_t)(i < k ? pt->bn[ch][i] : 0) << (16u * h);
            }
            t->v[0][ch][j] = _mm512_set1_epi32((int32_t)a);
            t->v[1][ch][j] = _mm512_set1_epi32((int32_t)b);
            t->v[2][ch][j] = _mm512_set1_epi32((int32_t)n);
        }
}

/* p8_group on sixteen lanes (the same sums and bounds) */
static POLY_INLINE void p16_group(const p16_front_t *f, const __m512i *ap, const __m512i *bp, const uint8_t *c,
                                  size_t ms, uint32_t j0, uint32_t jend, int tail, __m512i *q, __m512i *r)
{
    __m512i sa = _mm512_setzero_si512(), sb = _mm512_setzero_si512();
    /* the bytes of maps 2j and 2j + 1 as (c_2j, c_2j+1) int16 pairs */
#define P16_LD(p) _mm512_cvtepu8_epi32(_mm_loadu_si128((const __m128i *)(const void *)(p)))
#define P16_MP(pc, o2)                                                                                              \
    do {                                                                                                            \
        const __m512i cp = _mm512_or_si512(P16_LD(pc), _mm512_bslli_epi128(P16_LD((pc) + (o2)), 2));              \
        sa = _mm512_dpwssd_epi32(sa, _mm512_mullo_epi16(cp, ap[j]), f->yp[j]);                                      \
        sb = _mm512_dpwssd_epi32(sb, _mm512_mullo_epi16(cp, bp[j]), f->yp[j]);                                      \
    } while (0)
    uint32_t j = j0;
    for (const uint8_t *pc = c + 2u * j0 * ms; j < jend; ++j, pc += 2u * ms)
        P16_MP(pc, ms);
    if (tail)
        P16_MP(c + 2u * j * ms, 0u);
#undef P16_MP
#undef P16_LD
    const __m512i d = _mm512_srai_epi32(_mm512_add_epi32(sa, _mm512_srai_epi32(sb, 8)), 6);
    *q = _mm512_add_epi32(*q, d);
    const __m512i e = _mm512_sub_epi32(_mm512_add_epi32(_mm512_slli_epi32(sa, 8), sb), _mm512_slli_epi32(d, 14));
    *r = _mm512_add_epi32(*r, e);
}

/* p8_finish on sixteen lanes: stores all of them; returns the lanes whose scaling is rare */
static POLY_INLINE __mmask16 p16_finish(const qibl_shmap_point_t *pt, const p16_front_t *f, const p16_tab_t *tab,
                                        const __m512i *q, const __m512i *r, int32_t *out)
{
    const uint32_t np = (pt->maps->k + 1u) / 2u;
    const __m512i am = f->am, ae = f->ae;
    __m512i n0 = _mm512_setzero_si512(), n1 = n0, n2 = n0;
    for (uint32_t j = 0; j < np; ++j) {
        n0 = _mm512_dpwssd_epi32(n0, tab->v[2][0][j], f->yp[j]);
        n1 = _mm512_dpwssd_epi32(n1, tab->v[2][1][j], f->yp[j]);
        n2 = _mm512_dpwssd_epi32(n2, tab->v[2][2][j], f->yp[j]);
    }
    __mmask16 rare = 0;
    __m512i res[3];
    for (uint32_t ch = 0; ch < 3u; ++ch) {
        const __m512i sn = ch == 0u ? n0 : ch == 1u ? n1 : n2;
        const __m512i qn = _mm512_sra_epi32(sn, _mm_cvtsi32_si128(pt->pd[ch]));
        const __m512i sl = _mm512_sll_epi32(sn, _mm_cvtsi32_si128(14 - pt->pd[ch]));
        const __m512i rr = _mm512_add_epi32(r[ch], _mm512_sub_epi32(sl, _mm512_slli_epi32(qn, 14)));
        const __m512i V = _mm512_add_epi32(_mm512_add_epi32(q[ch], qn), _mm512_srli_epi32(rr, 14));
        const __m512i g = _mm512_mullo_epi32(am, P16_C(pt->c0m[ch])); /* <= 2^30 */
        const __m512i pe = _mm512_mul_epi32(V, g);
        const __m512i po = _mm512_mul_epi32(_mm512_shuffle_epi32(V, _MM_PERM_DDBB),
                                            _mm512_shuffle_epi32(g, _MM_PERM_DDBB));
        const __m512i sj = _mm512_sub_epi32(_mm512_add_epi32(ae, P16_C(pt->pk[ch])), P16_C(33));
        /* the common case 33 <= sr <= 62 only: round(p / 2^sr) from the high word */
        rare |= _mm512_cmpgt_epu32_mask(sj, P16_C(29));
        const __m512i hi = _mm512_mask_blend_epi32(0xAAAAu, _mm512_srli_epi64(pe, 32), po);
        const __m512i sh = _mm512_add_epi32(sj, P16_C(1));
        res[ch] = _mm512_srav_epi32(_mm512_add_epi32(hi, _mm512_sllv_epi32(P16_C(1), sj)), sh);
    }
    /* RGB interleaved: output word j is channel j % 3 of pixel j / 3, two permutes per vector */
    const __m512i vr = res[0], vg = res[1], vb = res[2];
    _mm512_storeu_si512((void *)out, _mm512_permutex2var_epi32(
        _mm512_permutex2var_epi32(vr, _mm512_setr_epi32(0, 16, 0, 1, 17, 0, 2, 18, 0, 3, 19, 0, 4, 20, 0, 5), vg),
        _mm512_setr_epi32(0, 1, 16, 3, 4, 17, 6, 7, 18, 9, 10, 19, 12, 13, 20, 15), vb));
    _mm512_storeu_si512((void *)(out + 16), _mm512_permutex2var_epi32(
        _mm512_permutex2var_epi32(vr, _mm512_setr_epi32(21, 0, 6, 22, 0, 7, 23, 0, 8, 24, 0, 9, 25, 0, 10, 26), vg),
        _mm512_setr_epi32(0, 21, 2, 3, 22, 5, 6, 23, 8, 9, 24, 11, 12, 25, 14, 15), vb));
    _mm512_storeu_si512((void *)(out + 32), _mm512_permutex2var_epi32(
        _mm512_permutex2var_epi32(vr, _mm512_setr_epi32(0, 11, 27, 0, 12, 28, 0, 13, 29, 0, 14, 30, 0, 15, 31, 0), vg),
        _mm512_setr_epi32(26, 1, 2, 27, 4, 5, 28, 7, 8, 29, 10, 11, 30, 13, 14, 31), vb));
    return rare;
}

/* poly_span_avx2's blocks with chunks of sixteen pixels (interleaved: chunks on whole groups), eight
 * chunks a block (128 pixels: more independent chunks between the phases, whose dependency chains
 * out-of-order execution overlaps; 2 and 4 chunks measured slower); each rare lane redone by
 * poly_span after its chunk */
#define P16_BLOCK 8u
#define P16_GROUP 5u
#ifndef P16_AHEAD
#define P16_AHEAD 512u
#endif /* pairs of maps per int32 sum (P8_GROUP's bound) */
static void poly_span_avx512(const qibl_shmap_point_t *pt, uint32_t x0, uint32_t y, uint32_t n, int32_t *out)
{
    const uint32_t k = pt->maps->k, np = (k + 1u) / 2u;
    poly_geom_t g;
    if (!poly_geom(pt, x0, y, &g)) {
        poly_span(pt, x0, y, n, out);
        return;
    }
    const int il = g.il;
    const size_t ms = g.ms, c1 = g.c1, gbytes = g.gbytes, off = g.off;
    const uint8_t *row = g.row;
    __m512i seed[6]; /* 384 bytes: qibli_rsqrt_seed's 192 values */
    for (uint32_t i = 0; i < 6u; ++i)
        seed[i] = _mm512_loadu_si512((const void *)(qibli_rsqrt_seed + 32u * i));
    p16_tab_t tab;
    p16_tab_fill(pt, k, &tab);
    p16_half_t hk;
    p16_half_fill(&hk);
    uint32_t px = 0u;
    if (il && x0 % QIBL_SHMAPS_GROUP != 0u) {
        px = QIBL_SHMAPS_GROUP - x0 % QIBL_SHMAPS_GROUP < n ? QIBL_SHMAPS_GROUP - x0 % QIBL_SHMAPS_GROUP : n;
        poly_span(pt, x0, y, px, out);
    }
    p16_front_t fr[P16_BLOCK];
    __m512i q[P16_BLOCK][3], r[P16_BLOCK][3];
    const uint8_t *cb[P16_BLOCK];
    __mmask16 bad[P16_BLOCK];
    __m512i u[P16_BLOCK][3];
    while (px + 16u <= n) {
        const uint32_t nb = (n - px) / 16u < P16_BLOCK ? (n - px) / 16u : P16_BLOCK;
        for (uint32_t b = 0; b < nb; ++b) {
            const uint32_t x = x0 + px + 16u * b;
            bad[b] = poly_front16(pt, pt->pmap->points + (off + px + 16u * b) * 12u, seed, u[b], &fr[b]);
            cb[b] = il ? row + (size_t)(x / QIBL_SHMAPS_GROUP) * gbytes : row + px + 16u * b;
            for (uint32_t ch = 0; ch < 3u; ++ch)
                q[b][ch] = _mm512_setzero_si512(), r[b][ch] = P16_C(8192);
        }
        for (uint32_t b = 0; b < nb; ++b)
            poly_eval16(u[b][0], u[b][1], u[b][2], pt->bands, &hk, fr[b].yp);
        for (uint32_t ch = 0; ch < 3u; ++ch)
            for (uint32_t j0 = 0; j0 < np; j0 += P16_GROUP) {
                const uint32_t jend = j0 + P16_GROUP < k / 2u ? j0 + P16_GROUP : k / 2u;
                const int tail = (k & 1u) && j0 + P16_GROUP >= np;
                for (uint32_t b = 0; b < nb; ++b)
                    p16_group(&fr[b], tab.v[0][ch], tab.v[1][ch], cb[b] + ch * c1, ms, j0, jend, tail, &q[b][ch],
                              &r[b][ch]);
            }
        for (uint32_t b = 0; b < nb; ++b, px += 16u) {
            uint32_t redo = (uint32_t)(bad[b] | p16_finish(pt, &fr[b], &tab, q[b], r[b], out + 3u * px));
            for (; redo != 0u; redo &= redo - 1u) {
                const uint32_t i = (uint32_t)__builtin_ctz(redo);
                poly_span(pt, x0 + px + i, y, 1u, out + 3u * (px + i));
            }
        }
    }
    if (px < n)
        poly_span(pt, x0 + px, y, n - px, out + 3u * px);
}
#undef P16_PRV
#undef P16_C
#endif /* QIBLI_SHMAP_AVX512 */

qibl_status_t qibl_shmap_point_span(const qibl_shmap_point_t *pt, uint32_t x0, uint32_t y, uint32_t n, int32_t *out,
                                    void *ws, size_t ws_size)
{
    QIBLI_DISPATCH512(qibl_shmap_point_span, (pt, x0, y, n, out, ws, ws_size));
    if (pt == 0 || out == 0 || pt->maps == 0 || pt->maps->planes == 0 || ws == 0)
        return QIBL_E_NULL_POINTER;
    const qibl_shmaps_t *m = pt->maps;
    if (y >= m->height || x0 > m->width || n > m->width - x0)
        return QIBL_E_SHMAP_BOUNDS;
    const uint32_t k = m->k;
    if (ws_size < qibl_shmap_point_workspace_size(k, n))
        return QIBL_E_WORKSPACE;
    if (((uintptr_t)ws & 3u) != 0u) /* int32 tables: a uint8_t array faults on Cortex-M0 */
        return QIBL_E_WORKSPACE_ALIGN;
    /* workspace: acc[n], accb[n], attm[n] (int32), atte[n] (int32), ybuf[k][n] (int16) */
    int32_t *acc = (int32_t *)ws, *accb = acc + n, *attm = accb + n, *atte = attm + n;
    int16_t *ybuf = (int16_t *)(atte + n);
    const size_t off = (size_t)y * m->width + x0;
    const uint8_t *pp = pt->pmap->points + off * 12u;

    if (pt->method == 1u) { /* QIBL_POINT_POLY */
#if defined(QIBLI_SHMAP_AVX512)
        poly_span_avx512(pt, x0, y, n, out);
#elif QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
        poly_span_avx2(pt, x0, y, n, out);
#else
        poly_span(pt, x0, y, n, out);
#endif
        return QIBL_OK;
    }
    /* Phase A, per pixel: direction, Y_i, attenuation as attm / 2^atte (in 2^16 / scene unit) */
    for (uint32_t px = 0; px < n; ++px, pp += 12) {
        int64_t l64[3];
        int32_t l[3];
        unsigned r0 = 0u;
        for (int j = 0; j < 3; ++j) {
            l64[j] = pt->pos[j] - (int64_t)qibl_load_s32le(pp + 4 * j);
            if (l64[j] > INT32_MAX || l64[j] < -(int64_t)INT32_MAX)
                r0 = 1u; /* S - P needs 33 bits: halve once (both are int32, so once is enough) */
        }
        uint64_t d2 = 0u;
        for (int j = 0; j < 3; ++j) {
            l[j] = (int32_t)qibl_asr_s64(l64[j], r0);
            uint32_t a = qibli_abs_u32(l[j]);
            d2 += qibl_mul_u32_u64(a, a);
        }
        if (d2 == 0u) { /* the light sits on this pixel's surface point: no direction, no light */
            attm[px] = 0, atte[px] = 0;
            for (uint32_t i = 0; i < k; ++i)
                ybuf[(size_t)i * n + px] = 0;
            continue;
        }
        unsigned e;
        uint32_t iy = qibl_rsqrt_u64(d2, &e); /* 1/|l| = iy / 2^e, e in 31..62 */
        qibl_q30_t u[3];
        qibli_unit_q30(l, iy, e, u); /* as qibl_vec3_normalize_fast_q30 */
        if (pt->lut) {
            lut_sample(pt->lut, u, k, pt->filter == QIBL_LUT_NEAREST, ybuf + px, n);
        } else {
            qibl_q30_t yq[QIBL_SH_MAX_COUNT];
            QIBL_DROP_STATUS(qibl_sh_eval_unit(u, (int)pt->bands, yq));
            for (uint32_t i = 0; i < k; ++i)
                ybuf[(size_t)i * n + px] = (int16_t)qibli_rshr_s64(yq[i], 16);
        }
        /* distance clamp: |L|^2 against min_dist^2, both in (2^-16)^2 units */
        uint32_t ay = iy;
        unsigned ae = e, rr = r0;
        if (r0 ? d2 < (pt->min_d2 >> 2) : d2 < pt->min_d2)
            ay = pt->clamp_y, ae = pt->clamp_e, rr = 0u;
        if (pt->falloff == QIBL_FALLOFF_INV_DIST) {
            attm[px] = (int32_t)(ay >> 1);                 /* 1/D = ay 2^(16 - rr - ae) */
            atte[px] = (int32_t)ae + (int32_t)rr - 16 - 1; /* attm / 2^atte, attm <= 2^30 */
        } else {
            attm[px] = (int32_t)(qibl_mul_u32_u64(ay, ay) >> 33);      /* 1/D^2 = ay^2 2^(32 - 2rr - 2ae) */
            atte[px] = 2 * (int32_t)ae + 2 * (int32_t)rr - 32 - 33;
        }
    }

    /* Phase B per channel (vectorisable), then Phase C: out = (acc 2^es + accb 2^eb) 2^-24 att C0 */
    for (uint32_t ch = 0; ch < 3u; ++ch) {
        uint32_t src = m->channels == 3u ? ch : 0u;
#if QIBL_USE_INTERLEAVED
        if (m->layout == QIBL_SHMAPS_INTERLEAVED)
            point_interleaved(m, pt, ch, src, x0, y, n, acc, accb, ybuf);
        else
#endif
            for (uint32_t i = 0; i < k; ++i)
                point_map(acc, accb, ybuf + (size_t)i * n, qibl_shmaps_plane(m, i, src) + off, pt->sn[ch][i],
                          pt->bn[ch][i], n, i == 0u);
        const int32_t es = pt->es[ch], eb = pt->eb[ch], e0 = es < eb ? es : eb;
        const uint32_t rgb = pt->rgb[ch];
        for (uint32_t px = 0; px < n; ++px) {
            /* V 2^(e0 - 24) is the radiance before attenuation and colour */
            int64_t v = shl_sat(acc[px], (unsigned)(es - e0)) + shl_sat(accb[px], (unsigned)(eb - e0));
            int32_t t = 0;
            while (v > INT32_MAX || v < -(int64_t)INT32_MAX) { /* rare: keep V within int32 */
                v = qibl_asr_s64(v, 1);
                ++t;
            }
            /* g = attm C0 / 2^31 <= 2^30; out = V g 2^(e0 + 7 - atte + t) in Q16.16 */
            int32_t g = (int32_t)(qibl_mul_u32_u64((uint32_t)attm[px], rgb) >> 31);
            int64_t prod = qibl_mul_s32_s64((int32_t)v, g); /* <= 2^61 */
            int32_t sr = atte[px] - e0 - 7 - t;
            if (sr > 0)
                out[3u * px + ch] = sr > 62 ? 0 : qibli_rshr_s64(prod, (unsigned)sr);
            else if (prod > INT32_MAX || prod < INT32_MIN || sr < -30)
                out[3u * px + ch] = prod > 0 ? INT32_MAX : prod < 0 ? INT32_MIN : 0;
            else
                out[3u * px + ch] = qibl_sat_s32(qibl_mul_s32_s64((int32_t)prod, (int32_t)1 << -sr));
        }
    }
    return QIBL_OK;
}

#else
typedef int qibl_shmap_disabled_t; /* ISO C forbids an empty translation unit */
#endif /* QIBL_USE_SHMAP */
