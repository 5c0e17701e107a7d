/*
 * srgbe.c - sRGBE (Granier et al. 4.2, appendix A): signed shared-exponent colour, integer only.
 *
 * Invariants: no floating point (binary32 values are read as bit patterns), no division, one const
 * table (1 KiB, decode), no state, no library helper: products are 32-bit except one
 * qibl_mul_u32_u64 (int32 input), and 64-bit shifts by a variable go through qibl_shr_u64.
 * The one-pixel and bulk entry points call the same static per-pixel functions, except the bulk
 * binary32 encoder's block path (enc_blk), which computes enc_word_fast's bytes in another order of
 * operations (proved equal there, and tested against the one-pixel encoder on every kind of input).
 *
 * Encoding a channel. With the exponent e fixed, let y = 255 |c| 2^-e. The paper's byte is
 * round(y' + 127.5) with y' = +-y, and y is never an integer for c != 0 (c 2^-e is dyadic, 255 is
 * odd), so no tie occurs and
 *     X = 128 + floor(y)   for c > 0,     X = 127 - floor(y)   for c < 0;
 * the same two lines give the tie rule for c = +0 / -0 (X = 128 / 127). For an in-range pixel
 * y < 127.5, so floor(y) <= 127 and X stays in 0..255.
 *
 * Binary32 channel c = sig * 2^(be - 150) (be = biased exponent field, sig with the hidden bit;
 * subnormals: be = 1, no hidden bit). With E = e + 126 the exponent byte,
 *     y = 255 sig 2^-(24 + E - be),
 * and for the largest channel (be_max, E = be_max + 1) the shift is exactly 25: y in [63.75, 127.5).
 * Every other channel has a larger shift, never below 23 (subnormal maxima), so sig * 255 < 2^32
 * fits one 32-bit product and shifts >= 32 give 0.
 *
 * Decoding a channel: c = +-m 2^(e-1) / 255 with m = |2X - 255| odd. For m < 255 the binary
 * expansion of m / 255 is the 8 bits of m repeated forever (1/255 = 0.00000001 00000001 ...), so
 * m * 0x01010101 holds its first 32 bits, the bits after any position are never all zero, and the
 * correctly rounded binary32 only needs the one bit after the kept ones: no tie, no division.
 */
#include "qibl/srgbe.h"
#include "qibli.h"

#if QIBL_USE_SRGBE
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
#include <immintrin.h>
#elif QIBL_CONFIG_SIMD == QIBL_SIMD_SSE2
#include <emmintrin.h>
#elif QIBL_CONFIG_SIMD == QIBL_SIMD_NEON
#include <arm_neon.h>
#endif

/* per-pixel outcome flags, folded into one status by status_of() */
#define F_OVERFLOW 1u
#define F_INF 2u
#define F_NAN 4u
#define F_DSAT 8u

static qibl_status_t status_of(unsigned flags)
{
    /* precedence stated in srgbe.h; a pixel sets at most one encoder flag */
    if (flags & F_NAN)
        return QIBL_E_SRGBE_NAN;
    if (flags & F_INF)
        return QIBL_E_SRGBE_INF;
    if (flags & F_OVERFLOW)
        return QIBL_E_SRGBE_OVERFLOW;
    if (flags & F_DSAT)
        return QIBL_E_SRGBE_DECODE_SAT;
    return QIBL_OK;
}

/* A code as one word, byte k = bits 8k..8k+7 (byte 0 = R): every encoder builds it and one store
 * site writes it, so the compiler needs no byte shuffling to merge paths. */
static uint32_t pack(uint32_t x0, uint32_t x1, uint32_t x2, uint32_t e)
{
    return x0 | x1 << 8 | x2 << 16 | e << 24;
}

static void put_code(uint32_t w, uint8_t *out)
{
    out[0] = (uint8_t)w; /* byte stores: any alignment, any byte order of the target */
    out[1] = (uint8_t)(w >> 8);
    out[2] = (uint8_t)(w >> 16);
    out[3] = (uint8_t)(w >> 24);
}

/* The zero code with the sign of each channel kept (tie rule: +0 -> 128, -0 -> 127). */
static uint32_t zero_code(uint32_t sr, uint32_t sg, uint32_t sb)
{
    return pack(128u - sr, 128u - sg, 128u - sb, QIBL_SRGBE_ZERO_E);
}

/* ---- encode from binary32 ------------------------------------------------------------------- */

/* Code byte of binary32 channel x at exponent byte xe (see the header comment: shift >= 23).
 * Also right for an infinite channel at xe = 255: bits 7F800000 read as sig = 2^23, be = 255 give
 * y = 127.5, floor 127, X = 255 or 0. */
static uint8_t enc_chan_f32(uint32_t x, uint32_t xe)
{
    uint32_t be = (x >> 23) & 0xFFu;
    uint32_t sig = x & 0x007FFFFFu;
    uint32_t sh;
    if (be != 0u) {
        sig |= 0x00800000u;
        sh = 24u + xe - be;
    } else {
        sh = 23u + xe; /* subnormal: be counts as 1 */
    }
    uint32_t q = sh < 32u ? (sig * 255u) >> sh : 0u;
    return (uint8_t)((x >> 31) != 0u ? 127u - q : 128u + q);
}

/* The general per-pixel encoder: every binary32 input, including zero, subnormal, Inf and NaN. */
static uint32_t enc_px_f32_general(uint32_t r, uint32_t g, uint32_t b, unsigned *flags)
{
    /* |x| of a binary32 orders like its bit pattern without the sign */
    uint32_t ar = r & 0x7FFFFFFFu, ag = g & 0x7FFFFFFFu, ab = b & 0x7FFFFFFFu;
    uint32_t mx = ar > ag ? ar : ag;
    if (ab > mx)
        mx = ab;
    uint32_t xe;
    if (mx - 0x00800000u < 0x7F800000u - 0x00800000u) {
        xe = (mx >> 23) + 1u; /* normal maximum: e = be - 127 + 2, E = e + 126 */
    } else if (mx >= 0x7F800000u) {
        if (ar > 0x7F800000u || ag > 0x7F800000u || ab > 0x7F800000u) {
            *flags |= F_NAN;
            return zero_code(0u, 0u, 0u);
        }
        xe = 255u; /* an infinity: saturate at the largest exponent */
        *flags |= F_INF;
    } else if (mx >= 0x00400000u) {
        xe = 1u; /* subnormal maximum in [2^-127, 2^-126): e = -125 */
    } else if (mx >= 0x00200000u) {
        xe = 0u; /* [2^-128, 2^-127): e = -126 */
    } else {
        return zero_code(r >> 31, g >> 31, b >> 31); /* below 2^-128, or zero: flush */
    }
    return pack(enc_chan_f32(r, xe), enc_chan_f32(g, xe), enc_chan_f32(b, xe), xe);
}

/* Fast path, branch-free, exact for a largest exponent field em in 7..254 (|max| in [2^-120, 2^128):
 * every finite pixel of real data). With d = em - be a channel's shift is 25 + d, and
 *     floor(255 sig / 2^(25+d)) = floor(u / 2^d),   u = floor(255 sig / 2^25) in 63..127
 * (nested floors), with 255 sig = 255 frac + 0x7F800000 < 2^32 for sig = 2^23 + frac. For d >= 7
 * the result is 0, so be is raised to em - 7 first. Channels with be = 0 (zero, subnormal) get the
 * hidden bit too: harmless, as there d >= 7 gives 0, also their exact result. The three bytes are
 * packed in one word, 128 added to each at once, and negative channels flipped by XOR with 0xFF
 * (127 - q = (128 + q) ^ 0xFF); no byte carries into the next (128 + q <= 255).
 * For em outside 7..254 the word is meaningless but computed without undefined behaviour (lo
 * wraps, so d is still in 0..7); callers replace it with enc_px_f32_general's. */
static uint32_t enc_word_fast(uint32_t r, uint32_t g, uint32_t b, uint32_t er, uint32_t eg, uint32_t eb,
                              uint32_t em)
{
    uint32_t lo = em - 7u;
    uint32_t dr = em - (er > lo ? er : lo), dg = em - (eg > lo ? eg : lo), db = em - (eb > lo ? eb : lo);
    uint32_t ur = ((r & 0x007FFFFFu) * 255u + 0x7F800000u) >> 25;
    uint32_t ug = ((g & 0x007FFFFFu) * 255u + 0x7F800000u) >> 25;
    uint32_t ub = ((b & 0x007FFFFFu) * 255u + 0x7F800000u) >> 25;
    uint32_t neg = ((r >> 31) | (g >> 31) << 8 | (b >> 31) << 16) * 0xFFu;
    /* E = e + 126 = (em - 127 + 2) + 126 in the top byte, which the add and the XOR leave alone */
    return (pack(ur >> dr, ug >> dg, ub >> db, (em + 1u) & 0xFFu) + 0x00808080u) ^ neg;
}

static uint32_t max3(uint32_t a, uint32_t b, uint32_t c)
{
    uint32_t m = a > b ? a : b;
    return c > m ? c : m;
}

static unsigned enc_px_f32(uint32_t r, uint32_t g, uint32_t b, uint8_t *out)
{
    uint32_t er = (r >> 23) & 0xFFu, eg = (g >> 23) & 0xFFu, eb = (b >> 23) & 0xFFu;
    uint32_t em = max3(er, eg, eb);
    unsigned flags = 0u;
    /* em < 7 (tiny, zero, subnormal) or em = 255 (Inf, NaN) take the general path */
    put_code(em - 7u < 248u ? enc_word_fast(r, g, b, er, eg, eb, em) : enc_px_f32_general(r, g, b, &flags), out);
    return flags;
}

#if QIBL_CONFIG_SRGBE_BLOCKS && QIBL_CONFIG_SIMD == QIBL_SIMD_SCALAR
/* ---- bulk binary32 encoder: blocks of planar 16-bit lanes ------------------------------------
 *
 * The same bytes as enc_word_fast, computed so that compilers vectorise it with plain SSE2 / NEON
 * 16-bit operations (no per-lane variable shift, no 32-bit multiply): a block of BLK pixels is
 * split into planes, every stage is a fixed-trip-count loop over one or three planes.
 *
 *   1. De-interleave: R, G, B words of the block into three uint32 planes (four pixels per step,
 *      which gcc turns into vector gathers; neither gcc 12 nor clang 14 vectorises a stride-3
 *      32-bit load for SSE2).
 *   2. Split each word x into h = x >> 16 (sign, exponent field be, 7 fraction bits) and
 *      l = x & 0xFFFF, 16-bit planes.
 *   3. Per pixel em = max be, kept as em - 7 (int16: signed 16-bit max is an SSE2 instruction,
 *      unsigned is not).
 *   4. Per channel, with S = 128 + (h & 0x7F) (the top 8 significand bits, hidden bit set as in
 *      enc_word_fast, harmless for the same reason) and sig = S 2^16 + l:
 *          PL = 255 S + floor(255 l / 2^16) = floor(255 sig / 2^16)          (< 2^16)
 *      and with d = min(em - be, 7), k = 7 - d = max(be - (em - 7), 0) in 0..7,
 *          q = floor(PL 2^k / 2^16) = floor(PL / 2^(9 + d)) = floor(255 sig / 2^(25 + d))
 *      by nested floors: enc_word_fast's floor(u / 2^d). 2^k comes from the bits of k by Horner,
 *      ((1 + k2)^2 (1 + k1))^2 (1 + k0), four 16-bit products instead of a variable shift. The
 *      byte is 128 + q, XOR 0xFF for a negative channel (127 - q), as in enc_word_fast.
 *   5. Interleave the three byte planes and E = em + 1 into the codes.
 * Pixels with em outside 7..254 get garbage here (every intermediate stays defined: k <= 7 as
 * be <= em, PL < 2^16, products < 2^23) and are rewritten by enc_px_f32 afterwards, which
 * enc_blk reports. Stack: 30 bytes per pixel of the block. Compiled where config.h's
 * QIBL_CONFIG_SRGBE_BLOCKS says the compiler has a vector unit to give this code to; elsewhere
 * qibl_srgbe_encode_f32_n runs enc_word_fast pixel by pixel, which is smaller and faster there. */
#define BLK 16

/* step 2 for one plane */
static void blk_split(const uint32_t *restrict x, uint16_t *restrict h, uint16_t *restrict l)
{
    for (int i = 0; i < BLK; ++i) {
        h[i] = (uint16_t)(x[i] >> 16);
        l[i] = (uint16_t)x[i];
    }
}

/* step 4 for one plane: code bytes of the channel given h, l and em - 7 */
static void blk_chan(const uint16_t *restrict hh, const uint16_t *restrict ll, const int16_t *restrict em7,
                     uint8_t *restrict o)
{
    for (int i = 0; i < BLK; ++i) {
        uint16_t h = hh[i];
        uint16_t pl = (uint16_t)((uint16_t)(((h & 0x7Fu) | 0x80u) * 255u) + (uint16_t)(((uint32_t)ll[i] * 255u) >> 16));
        int16_t be = (int16_t)((h >> 7) & 0xFFu), m = em7[i];
        uint16_t k = (uint16_t)((be > m ? be : m) - m);
        uint16_t p = (uint16_t)(1u + (k >> 2));
        p = (uint16_t)(p * p);
        p = (uint16_t)(p * (1u + ((k >> 1) & 1u)));
        p = (uint16_t)(p * p);
        p = (uint16_t)(p * (1u + (k & 1u)));
        uint16_t q = (uint16_t)(((uint32_t)pl * p) >> 16);
        o[i] = (uint8_t)((128u + q) ^ (0u - (uint32_t)(h >> 15)));
    }
}

/* Codes of BLK pixels; nonzero if some pixel has em outside 7..254 (its code must be redone). */
static unsigned enc_blk(const uint32_t *restrict x, uint8_t *restrict out)
{
    uint32_t r[BLK], g[BLK], b[BLK];
    uint16_t hr[BLK], hg[BLK], hb[BLK], lr[BLK], lg[BLK], lb[BLK];
    int16_t em7[BLK];
    uint8_t xr[BLK], xg[BLK], xb[BLK];
    for (int i = 0; i < BLK; i += 4) {
        const uint32_t *p = x + 3 * i;
        r[i] = p[0], r[i + 1] = p[3], r[i + 2] = p[6], r[i + 3] = p[9];
        g[i] = p[1], g[i + 1] = p[4], g[i + 2] = p[7], g[i + 3] = p[10];
        b[i] = p[2], b[i + 1] = p[5], b[i + 2] = p[8], b[i + 3] = p[11];
    }
    blk_split(r, hr, lr);
    blk_split(g, hg, lg);
    blk_split(b, hb, lb);
    uint16_t special = 0u;
    for (int i = 0; i < BLK; ++i) {
        int16_t e0 = (int16_t)((hr[i] >> 7) & 0xFFu), e1 = (int16_t)((hg[i] >> 7) & 0xFFu);
        int16_t e2 = (int16_t)((hb[i] >> 7) & 0xFFu);
        int16_t m = e0 > e1 ? e0 : e1;
        m = e2 > m ? e2 : m;
        em7[i] = (int16_t)(m - 7);
        special |= (uint16_t)(m - 7) >= 248u;
    }
    blk_chan(hr, lr, em7, xr);
    blk_chan(hg, lg, em7, xg);
    blk_chan(hb, lb, em7, xb);
    for (int i = 0; i < BLK; ++i) {
        out[4 * i] = xr[i];
        out[4 * i + 1] = xg[i];
        out[4 * i + 2] = xb[i];
        out[4 * i + 3] = (uint8_t)(em7[i] + 8); /* E = em + 1; garbage only where special */
    }
    return special;
}
#endif /* QIBL_CONFIG_SRGBE_BLOCKS */

#if QIBL_CONFIG_SIMD != QIBL_SIMD_SCALAR
/* ---- bulk binary32 encoder: intrinsics (QIBL_CONFIG_SIMD) -----------------------------------
 *
 * enc_word_fast's arithmetic lane by lane in 32-bit lanes (4 pixels per SSE2 / NEON register, 8
 * per AVX2 one). Every step is an exact integer operation on the same values, so the bytes are
 * enc_word_fast's by construction:
 *   be = x << 1 >> 24; em = max be (0..255: SSE2's signed 16-bit max is exact on such lanes);
 *   d = em - max(be, em - 7) in 0..7; u = (255 frac + 0x7F800000) >> 25 in 63..127 (SSE2: 255 frac
 *   as (frac << 8) - frac, no 32-bit multiply); q = u >> d; the byte is 128 + q or 127 - q:
 *   (q ^ s), s = x >> 31 arithmetic, is q or -q - 1, a signed byte exactly, and XOR 0x80 maps it
 *   to 128 + q or 127 - q.
 * The per-lane shift u >> d: AVX2 vpsrlvd, NEON vshl by -d. SSE2 has none, so there
 *   q = floor(W / 2^(32 - k)), the high half of the 16-bit product (W >> 16) 2^k (nested floors),
 * W = 255 frac + 0x7F800000 (u = W >> 25), k = 7 - d in 0..7; the exponent fields stay in place
 * (be << 23: the signed 16-bit max is still exact), so max(be, em - 7) - em + 134, in place, is
 * (k + 127) << 23, the binary32 bits of 2^k (pow2k). Channels: SSE2/AVX2 separate R, G, B of 4 pixels (three loads) with five shufps
 * (bit moves), NEON with vld3q; codes: signed saturating packs (exact: every value is in
 * -128..127) and byte unpacks, NEON vst4. A pixel with em outside 7..254 gets a meaningless code
 * (every step stays defined) and is redone by the caller; enc_simd says whether a block has one. */
#if QIBL_CONFIG_SIMD == QIBL_SIMD_SSE2 || QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
typedef __m256i vi_t;
typedef __m256 vf_t;
#define V_(op) _mm256_##op
#define V_PS(op) _mm256_##op##_ps
#define V_I(v) _mm256_castps_si256(v)
#define V_SI(op) _mm256_##op##_si256
#define VL 8
#else
typedef __m128i vi_t;
typedef __m128 vf_t;
#define V_(op) _mm_##op
#define V_PS(op) _mm_##op##_ps
#define V_I(v) _mm_castps_si128(v)
#define V_SI(op) _mm_##op##_si128
#define VL 4
#endif
#define V_SET1(c) V_(set1_epi32)((int32_t)(c))

#if defined(QIBLI_SRGBE_AVX512)
/* The AVX-512 copy (x86/srgbe_avx512.c): 16 pixels a step, one pixel a 32-bit lane.
 *   Channels: three 64-byte loads, two vpermt2d per channel (words 0..31, then 32..47).
 *   q = W >> (25 + d) in one vpsrlvd, W = 255 sig = (sig << 8) - sig with sig = (x & 0x7FFFFF) |
 *   0x800000 (one vpternlogd), and the count em + 25 - be with no clamp at d = 7: for em - be >= 7
 *   the count is >= 32, where vpsrlvd gives 0, which is also floor(u / 2^d) (u <= 127).
 *   q ^ s (s = x >> 31 arithmetic) is a signed byte as in the kernel below; E as em - 127
 *   (-127..128: only em = 255, a redone pixel, saturates). Codes: vpackssdw, vpacksswb (per 128-bit
 *   lane: pixels 4L..4L+3, R G B E four bytes each) and one vpshufb to R G B E order, XOR 0x80. */
static __m512i enc_chan16(__m512i x, __m512i em25)
{
    const __m512i be = _mm512_srli_epi32(_mm512_slli_epi32(x, 1), 24);
    const __m512i sig = _mm512_ternarylogic_epi32(x, _mm512_set1_epi32(0x007FFFFF), _mm512_set1_epi32(0x00800000),
                                                  0xEA); /* (x & b) | c */
    const __m512i w = _mm512_sub_epi32(_mm512_slli_epi32(sig, 8), sig);
    const __m512i q = _mm512_srlv_epi32(w, _mm512_sub_epi32(em25, be));
    return _mm512_xor_si512(q, _mm512_srai_epi32(x, 31));
}

/* codes of 16 pixels (rgb at p, codes at o); nonzero if one of them has em outside 7..254 */
static unsigned enc_simd(const uint32_t *p, uint8_t *o)
{
    const __m512i l0 = _mm512_loadu_si512((const void *)p), l1 = _mm512_loadu_si512((const void *)(p + 16));
    const __m512i l2 = _mm512_loadu_si512((const void *)(p + 32));
    /* channel c of pixel i is word 3i + c: from l0:l1 where 3i + c < 32, then from l2 */
#define IDX_A(c) _mm512_setr_epi32(c, 3 + c, 6 + c, 9 + c, 12 + c, 15 + c, 18 + c, 21 + c, 24 + c, 27 + c,    \
                                   (30 + c) & 31, (33 + c) & 31, (36 + c) & 31, (39 + c) & 31, (42 + c) & 31,         \
                                   (45 + c) & 31)
#define IDX_B(c) _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 30 + c < 32 ? 10 : c + 14, c + 17, c + 20,     \
                                   c + 23, c + 26, c + 29) /* 16 + j: word j of l2 */
    const __m512i r = _mm512_permutex2var_epi32(_mm512_permutex2var_epi32(l0, IDX_A(0), l1), IDX_B(0), l2);
    const __m512i g = _mm512_permutex2var_epi32(_mm512_permutex2var_epi32(l0, IDX_A(1), l1), IDX_B(1), l2);
    const __m512i b = _mm512_permutex2var_epi32(_mm512_permutex2var_epi32(l0, IDX_A(2), l1), IDX_B(2), l2);
#undef IDX_A
#undef IDX_B
    const __m512i em = _mm512_max_epu32(_mm512_max_epu32(_mm512_srli_epi32(_mm512_slli_epi32(r, 1), 24),
                                                         _mm512_srli_epi32(_mm512_slli_epi32(g, 1), 24)),
                                        _mm512_srli_epi32(_mm512_slli_epi32(b, 1), 24));
    const __m512i em25 = _mm512_add_epi32(em, _mm512_set1_epi32(25));
    const __mmask16 bad = _mm512_cmpge_epu32_mask(_mm512_sub_epi32(em, _mm512_set1_epi32(7)), _mm512_set1_epi32(248));
    const __m512i rg = _mm512_packs_epi32(enc_chan16(r, em25), enc_chan16(g, em25));
    const __m512i be = _mm512_packs_epi32(enc_chan16(b, em25), _mm512_sub_epi32(em, _mm512_set1_epi32(127)));
    const __m512i c = _mm512_shuffle_epi8(_mm512_packs_epi16(rg, be),
                                          _mm512_broadcast_i32x4(_mm_setr_epi8(0, 4, 8, 12, 1, 5, 9, 13, 2, 6, 10, 14,
                                                                               3, 7, 11, 15)));
    _mm512_storeu_si512((void *)o, _mm512_xor_si512(c, _mm512_set1_epi8((char)0x80)));
    return (unsigned)bad;
}
#define ENC_SIMD_PX 16
#else

/* R, G, B planes of VL pixels (AVX2: pixels 0..3 in the low half, 4..7 in the high half) */
static void enc_load3(const uint32_t *p, vi_t *r, vi_t *g, vi_t *b)
{
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
#define LD(o)                                                                                           \
    _mm256_castsi256_ps(_mm256_inserti128_si256(                                                        \
        _mm256_castsi128_si256(_mm_loadu_si128((const __m128i *)(const void *)(p + (o)))),              \
        _mm_loadu_si128((const __m128i *)(const void *)(p + 12 + (o))), 1))
#else
#define LD(o) _mm_castsi128_ps(_mm_loadu_si128((const __m128i *)(const void *)(p + (o))))
#endif
    const vf_t l0 = LD(0), l1 = LD(4), l2 = LD(8); /* r0 g0 b0 r1, g1 b1 r2 g2, b2 r3 g3 b3 */
#undef LD
    const vf_t t = V_PS(shuffle)(l1, l2, _MM_SHUFFLE(2, 1, 3, 2)); /* r2 g2 r3 g3 */
    const vf_t u = V_PS(shuffle)(l0, l1, _MM_SHUFFLE(1, 0, 2, 1)); /* g0 b0 g1 b1 */
    *r = V_I(V_PS(shuffle)(l0, t, _MM_SHUFFLE(2, 0, 3, 0)));
    *g = V_I(V_PS(shuffle)(u, t, _MM_SHUFFLE(3, 1, 2, 0)));
    *b = V_I(V_PS(shuffle)(u, l2, _MM_SHUFFLE(3, 0, 3, 1)));
}

/* AVX2: the exponent field be; SSE2: be << 23 (where it is, one AND) */
static vi_t enc_be(vi_t x)
{
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
    return V_(srli_epi32)(V_(slli_epi32)(x, 1), 24);
#else
    return _mm_and_si128(x, V_SET1(0x7F800000u));
#endif
}

#if QIBL_CONFIG_SIMD == QIBL_SIMD_SSE2
/* 2^k (k in 0..7) in each 32-bit lane from kb = (k + 127) << 23: the binary32 bits of 2^k,
 * converted by cvttps2dq (exact and raising no flag: an integral normal value); SRGBE_SSE2_HORNER
 * builds it from k's bits instead, ((1 + k2)^2 (1 + k1))^2 (1 + k0), integer products only (the
 * slower alternative measured in the report of this kernel) */
static vi_t pow2k(vi_t kb)
{
#ifndef SRGBE_SSE2_HORNER
    return _mm_cvttps_epi32(_mm_castsi128_ps(kb));
#else
    const vi_t one = V_SET1(1), k = _mm_sub_epi32(_mm_srli_epi32(kb, 23), V_SET1(127));
    vi_t p = _mm_add_epi32(_mm_srli_epi32(k, 2), one);
    p = _mm_mullo_epi16(p, p);
    p = _mm_mullo_epi16(p, _mm_add_epi32(_mm_and_si128(_mm_srli_epi32(k, 1), one), one));
    p = _mm_mullo_epi16(p, p);
    return _mm_mullo_epi16(p, _mm_add_epi32(_mm_and_si128(k, one), one));
#endif
}
#endif

/* one channel: q ^ s (a signed byte) given x, its enc_be and lo = em - 7, hi = em - 134 (SSE2:
 * both << 23). W = 255 sig = 255 frac + 0x7F800000 < 2^32, u = W >> 25, q = u >> d = W >> (32 - k)
 * (nested floors), which SSE2 takes as the high half of the 16-bit product (W >> 16) 2^k. */
static vi_t enc_chan(vi_t x, vi_t be, vi_t lo, vi_t hi)
{
    const vi_t f = V_SI(and)(x, V_SET1(0x007FFFFFu));
    const vi_t w = V_(add_epi32)(V_(sub_epi32)(V_(slli_epi32)(f, 8), f), V_SET1(0x7F800000u));
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
    (void)hi;
    const vi_t q = _mm256_srlv_epi32(_mm256_srli_epi32(w, 25),
                                     _mm256_sub_epi32(_mm256_add_epi32(lo, V_SET1(7)), _mm256_max_epi32(be, lo)));
#else
    /* (max(be, em - 7) - em + 134) << 23 = (k + 127) << 23; the signed 16-bit max is exact: the
     * upper halves hold be << 7 >= 0 or (em - 7) << 7, the lower halves 0 */
    const vi_t q = _mm_mulhi_epu16(_mm_srli_epi32(w, 16), pow2k(_mm_sub_epi32(_mm_max_epi16(be, lo), hi)));
#endif
    return V_SI(xor)(q, V_(srai_epi32)(x, 31));
}

/* codes of 2 VL pixels (rgb at p, codes at o); nonzero if one of them has em outside 7..254 */
static unsigned enc_simd(const uint32_t *p, uint8_t *o)
{
    vi_t v[2][4], bad = V_SI(setzero)();
    for (int h = 0; h < 2; ++h) {
        vi_t r, g, b;
        enc_load3(p + 3 * VL * h, &r, &g, &b);
        const vi_t er = enc_be(r), eg = enc_be(g), eb = enc_be(b);
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
        const vi_t em = _mm256_max_epi32(_mm256_max_epi32(er, eg), eb);
        const vi_t lo = V_(sub_epi32)(em, V_SET1(7)), hi = lo;
#else
        const vi_t em23 = _mm_max_epi16(_mm_max_epi16(er, eg), eb), em = _mm_srli_epi32(em23, 23);
        const vi_t lo = _mm_sub_epi32(em23, V_SET1(7u << 23)), hi = _mm_sub_epi32(em23, V_SET1(134u << 23));
#endif
        v[h][0] = enc_chan(r, er, lo, hi);
        v[h][1] = enc_chan(g, eg, lo, hi);
        v[h][2] = enc_chan(b, eb, lo, hi);
        /* E = (em + 1) mod 256 as a signed byte; em outside 7..254 is exactly E <= 7 */
        v[h][3] = V_(sub_epi32)(V_SI(and)(V_(add_epi32)(em, V_SET1(1)), V_SET1(0xFF)), V_SET1(128));
        bad = V_SI(or)(bad, V_(cmpgt_epi32)(V_SET1(-120), v[h][3]));
    }
    /* AVX2: v[0] holds pixels 0..7, v[1] 8..15; packs and unpacks work per 128-bit half, which
     * puts pixels 0..3 | 4..7 in c0 and 8..11 | 12..15 in c1 */
    const vi_t rg = V_(packs_epi16)(V_(packs_epi32)(v[0][0], v[1][0]), V_(packs_epi32)(v[0][1], v[1][1]));
    const vi_t be = V_(packs_epi16)(V_(packs_epi32)(v[0][2], v[1][2]), V_(packs_epi32)(v[0][3], v[1][3]));
    const vi_t lo = V_(unpacklo_epi8)(rg, be), hi = V_(unpackhi_epi8)(rg, be); /* r b ..., g e ... */
    const vi_t x80 = V_(set1_epi8)((char)0x80);
    V_SI(storeu)((vi_t *)(void *)o, V_SI(xor)(V_(unpacklo_epi8)(lo, hi), x80));
    V_SI(storeu)((vi_t *)(void *)(o + 4 * VL), V_SI(xor)(V_(unpackhi_epi8)(lo, hi), x80));
    return (unsigned)V_(movemask_epi8)(bad);
}
#define ENC_SIMD_PX (2 * VL)
#endif /* QIBLI_SRGBE_AVX512 */

/* The bulk encoder reads 12 bytes and writes 4 a pixel, and a big buffer comes from memory, not
 * cache: there the load stalls, not the arithmetic, set its speed (AVX2, 1024 x 512 pixels: 1.8
 * ns/px from memory against 0.8 from cache). Each block asks for the input and output lines
 * ENC_PF_PX pixels ahead (hints: no fault, the bytes unchanged; only addresses inside the arrays):
 * `qibl bench srgbe` (a), min of interleaved runs, 1.86 -> 1.38 ns/px with the input 7.5 KB ahead,
 * 1.27 with the output too, ~1.1 at 15 KB ahead (3 KB ahead did not cover the latency). The
 * AVX-512 copy, twice as fast in cache, does best 4 KB ahead (a 6 MB buffer alone: 0.58-0.61 ns/px
 * at 160-320 pixels, 0.63-0.67 at 1280; the bench: round5-designs.txt, round 7). */
#if defined(QIBLI_SRGBE_AVX512)
#define ENC_PF_PX 320
#else
#define ENC_PF_PX 1280
#endif
static void enc_prefetch(const uint32_t *p)
{
    for (int k = 0; k < 3 * ENC_SIMD_PX; k += 16) /* one hint per 64-byte line */
        _mm_prefetch((const char *)(const void *)(p + k), _MM_HINT_T0);
}

#elif QIBL_CONFIG_SIMD == QIBL_SIMD_NEON
/* codes of 8 pixels (rgb at p, codes at o); nonzero if one of them has em outside 7..254 */
static unsigned enc_simd(const uint32_t *p, uint8_t *o)
{
    uint16x4_t n[4][2];
    uint32x4_t bad = vdupq_n_u32(0u);
    for (int h = 0; h < 2; ++h) {
        const uint32x4x3_t x = vld3q_u32(p + 12 * h);
        uint32x4_t be[3];
        for (int c = 0; c < 3; ++c)
            be[c] = vshrq_n_u32(vshlq_n_u32(x.val[c], 1), 24);
        const uint32x4_t em = vmaxq_u32(vmaxq_u32(be[0], be[1]), be[2]);
        const int32x4_t lo = vreinterpretq_s32_u32(vsubq_u32(em, vdupq_n_u32(7u)));
        for (int c = 0; c < 3; ++c) {
            const int32x4_t d = vsubq_s32(vreinterpretq_s32_u32(em), vmaxq_s32(vreinterpretq_s32_u32(be[c]), lo));
            const uint32x4_t f = vandq_u32(x.val[c], vdupq_n_u32(0x007FFFFFu));
            const uint32x4_t u = vshrq_n_u32(vmlaq_n_u32(vdupq_n_u32(0x7F800000u), f, 255u), 25);
            const uint32x4_t q = vshlq_u32(u, vnegq_s32(d));
            const uint32x4_t s = vreinterpretq_u32_s32(vshrq_n_s32(vreinterpretq_s32_u32(x.val[c]), 31));
            n[c][h] = vmovn_u32(veorq_u32(q, s));
        }
        n[3][h] = vmovn_u32(vaddq_u32(em, vdupq_n_u32(1u))); /* E = em + 1, low byte */
        bad = vorrq_u32(bad, vcgeq_u32(vsubq_u32(em, vdupq_n_u32(7u)), vdupq_n_u32(248u)));
    }
    uint8x8x4_t c;
    for (int k = 0; k < 3; ++k)
        c.val[k] = veor_u8(vmovn_u16(vcombine_u16(n[k][0], n[k][1])), vdup_n_u8(0x80u));
    c.val[3] = vmovn_u16(vcombine_u16(n[3][0], n[3][1]));
    vst4_u8(o, c);
    const uint32x2_t m = vorr_u32(vget_low_u32(bad), vget_high_u32(bad));
    return vget_lane_u32(m, 0) | vget_lane_u32(m, 1);
}
#define ENC_SIMD_PX 8
#endif
#endif /* QIBL_CONFIG_SIMD != QIBL_SIMD_SCALAR */

/* ---- encode from int32 * 2^-frac_bits ------------------------------------------------------- */

/* min(127, floor(255 a / 2^sh)) for any sh <= 33 (sh <= 0 only on the overflow path) */
static uint32_t enc_quant_s32(uint32_t a, int sh)
{
    if (sh <= 0)
        return a != 0u ? 127u : 0u; /* 255 a 2^-sh >= 255 a */
    uint64_t p = qibl_mul_u32_u64(a, 255u); /* < 2^40; (a << 8) - a would become __aeabi_lmul */
    uint64_t q = qibl_shr_u64(p, (unsigned)sh);
    return q > 127u ? 127u : (uint32_t)q;
}

static unsigned enc_px_s32(int32_t r, int32_t g, int32_t b, int frac_bits, uint8_t *out)
{
    /* magnitudes in unsigned arithmetic: -INT32_MIN is not an int32 */
    uint32_t ar = qibli_abs_u32(r);
    uint32_t ag = qibli_abs_u32(g);
    uint32_t ab = qibli_abs_u32(b);
    uint32_t mx = ar > ag ? ar : ag;
    if (ab > mx)
        mx = ab;
    if (mx == 0u) {
        put_code(zero_code(0u, 0u, 0u), out); /* integers have no -0 */
        return 0u;
    }
    /* Clamping frac_bits to +-300 changes no result (e would still be far below -126 or above
     * 129) and keeps k + 2 - f inside int. */
    int f = frac_bits > 300 ? 300 : frac_bits < -300 ? -300 : frac_bits;
    int k = (int)qibli_bitlen_u32(mx) - 1;
    int e = k + 2 - f; /* paper: floor(log2(max)) + 2 */
    unsigned flags = 0u;
    int sh = k + 2; /* = e + f: 255 |c| 2^-e = 255 a 2^-sh; the maximum gives y in [63.75, 127.5) */
    if (e < QIBL_SRGBE_E_MIN) {
        put_code(zero_code(r < 0, g < 0, b < 0), out); /* flush, signs kept as for binary32 */
        return 0u;
    }
    if (e > QIBL_SRGBE_E_MAX) {
        e = QIBL_SRGBE_E_MAX;
        sh = QIBL_SRGBE_E_MAX + f; /* < k + 2: the largest channels clamp to 127 */
        flags = F_OVERFLOW;
    }
    uint32_t qr = enc_quant_s32(ar, sh), qg = enc_quant_s32(ag, sh), qb = enc_quant_s32(ab, sh);
    put_code(pack(r < 0 ? 127u - qr : 128u + qr, g < 0 ? 127u - qg : 128u + qg, b < 0 ? 127u - qb : 128u + qb,
                  (uint32_t)(e + QIBL_SRGBE_E_BIAS)),
             out);
    return flags;
}

/* ---- decode to binary32 --------------------------------------------------------------------- */

static uint32_t dec_chan_f32(uint32_t x, uint32_t xe, unsigned *flags)
{
    uint32_t sign = x < 128u ? 0x80000000u : 0u;
    uint32_t m = x < 128u ? 255u - 2u * x : 2u * x - 255u; /* odd, 1..255 */
    if (m == 255u) { /* exactly 2^(e-1) = 2^(xe - 127) */
        if (xe == 255u) {
            *flags |= F_DSAT;
            return sign | 0x7F7FFFFFu; /* 2^128: saturate to FLT_MAX */
        }
        return sign | (xe != 0u ? xe << 23 : 0x00400000u);
    }
    uint32_t f = m * 0x01010101u; /* first 32 bits of m/255; the leading one is at bit 24..30 */
    uint32_t n = 0u;
    /* normalise the leading one to bit 31 (n <= 7, so bits 31..7 stay exact: zeros shifted in at
     * the bottom are below every bit used) */
    if (f < 0x10000000u) {
        f <<= 4;
        n = 4u;
    }
    if (f < 0x40000000u) {
        f <<= 2;
        n += 2u;
    }
    if (f < 0x80000000u) {
        f <<= 1;
        n += 1u;
    }
    /* |c| = (f / 2^31) * 2^(xe - 128 - n): biased binary32 exponent B = xe - 1 - n */
    if (xe > n + 1u) /* B >= 1: normal; (B - 1) << 23 plus the 24-bit significand carries right */
        return sign | (((xe - 2u - n) << 23) + (f >> 8) + ((f >> 7) & 1u));
    /* B in -8..0: subnormal field round(f * 2^(B - 9)), shift 9 - B in 9..17 */
    uint32_t s = 10u + n - xe;
    return sign | ((f >> s) + ((f >> (s - 1u)) & 1u));
}

/* For E in 9..254 every channel decodes to a normal binary32 whose bits are
 *     sign 2^31 + ((E - 2 - n) << 23) + rounded 24-bit significand      (dec_chan_f32's normal case)
 * = (E << 23) + dec_base[X]   (mod 2^32),
 * with dec_base[X] = sign 2^31 + significand - ((n + 2) << 23) independent of E (for X = 0 / 255:
 * the sign bit alone, as +-2^(E-127) = sign | E << 23). So decoding is one add per channel. The
 * table is dec_chan_f32(X, E) - (E << 23) for any such E; tests compare every (X, E) with the
 * double reference, so table and computed path are both checked for every code. 1 KiB. */
static const uint32_t dec_base[256] = {
    0x80000000u, 0x7FFDFDFEu, 0x7FFBFBFCu, 0x7FF9F9FAu, 0x7FF7F7F8u, 0x7FF5F5F6u,
    0x7FF3F3F4u, 0x7FF1F1F2u, 0x7FEFEFF0u, 0x7FEDEDEEu, 0x7FEBEBECu, 0x7FE9E9EAu,
    0x7FE7E7E8u, 0x7FE5E5E6u, 0x7FE3E3E4u, 0x7FE1E1E2u, 0x7FDFDFE0u, 0x7FDDDDDEu,
    0x7FDBDBDCu, 0x7FD9D9DAu, 0x7FD7D7D8u, 0x7FD5D5D6u, 0x7FD3D3D4u, 0x7FD1D1D2u,
    0x7FCFCFD0u, 0x7FCDCDCEu, 0x7FCBCBCCu, 0x7FC9C9CAu, 0x7FC7C7C8u, 0x7FC5C5C6u,
    0x7FC3C3C4u, 0x7FC1C1C2u, 0x7FBFBFC0u, 0x7FBDBDBEu, 0x7FBBBBBCu, 0x7FB9B9BAu,
    0x7FB7B7B8u, 0x7FB5B5B6u, 0x7FB3B3B4u, 0x7FB1B1B2u, 0x7FAFAFB0u, 0x7FADADAEu,
    0x7FABABACu, 0x7FA9A9AAu, 0x7FA7A7A8u, 0x7FA5A5A6u, 0x7FA3A3A4u, 0x7FA1A1A2u,
    0x7F9F9FA0u, 0x7F9D9D9Eu, 0x7F9B9B9Cu, 0x7F99999Au, 0x7F979798u, 0x7F959596u,
    0x7F939394u, 0x7F919192u, 0x7F8F8F90u, 0x7F8D8D8Eu, 0x7F8B8B8Cu, 0x7F89898Au,
    0x7F878788u, 0x7F858586u, 0x7F838384u, 0x7F818182u, 0x7F7EFEFFu, 0x7F7AFAFBu,
    0x7F76F6F7u, 0x7F72F2F3u, 0x7F6EEEEFu, 0x7F6AEAEBu, 0x7F66E6E7u, 0x7F62E2E3u,
    0x7F5EDEDFu, 0x7F5ADADBu, 0x7F56D6D7u, 0x7F52D2D3u, 0x7F4ECECFu, 0x7F4ACACBu,
    0x7F46C6C7u, 0x7F42C2C3u, 0x7F3EBEBFu, 0x7F3ABABBu, 0x7F36B6B7u, 0x7F32B2B3u,
    0x7F2EAEAFu, 0x7F2AAAABu, 0x7F26A6A7u, 0x7F22A2A3u, 0x7F1E9E9Fu, 0x7F1A9A9Bu,
    0x7F169697u, 0x7F129293u, 0x7F0E8E8Fu, 0x7F0A8A8Bu, 0x7F068687u, 0x7F028283u,
    0x7EFCFCFDu, 0x7EF4F4F5u, 0x7EECECEDu, 0x7EE4E4E5u, 0x7EDCDCDDu, 0x7ED4D4D5u,
    0x7ECCCCCDu, 0x7EC4C4C5u, 0x7EBCBCBDu, 0x7EB4B4B5u, 0x7EACACADu, 0x7EA4A4A5u,
    0x7E9C9C9Du, 0x7E949495u, 0x7E8C8C8Du, 0x7E848485u, 0x7E78F8F9u, 0x7E68E8E9u,
    0x7E58D8D9u, 0x7E48C8C9u, 0x7E38B8B9u, 0x7E28A8A9u, 0x7E189899u, 0x7E088889u,
    0x7DF0F0F1u, 0x7DD0D0D1u, 0x7DB0B0B1u, 0x7D909091u, 0x7D60E0E1u, 0x7D20A0A1u,
    0x7CC0C0C1u, 0x7C008081u, 0xFC008081u, 0xFCC0C0C1u, 0xFD20A0A1u, 0xFD60E0E1u,
    0xFD909091u, 0xFDB0B0B1u, 0xFDD0D0D1u, 0xFDF0F0F1u, 0xFE088889u, 0xFE189899u,
    0xFE28A8A9u, 0xFE38B8B9u, 0xFE48C8C9u, 0xFE58D8D9u, 0xFE68E8E9u, 0xFE78F8F9u,
    0xFE848485u, 0xFE8C8C8Du, 0xFE949495u, 0xFE9C9C9Du, 0xFEA4A4A5u, 0xFEACACADu,
    0xFEB4B4B5u, 0xFEBCBCBDu, 0xFEC4C4C5u, 0xFECCCCCDu, 0xFED4D4D5u, 0xFEDCDCDDu,
    0xFEE4E4E5u, 0xFEECECEDu, 0xFEF4F4F5u, 0xFEFCFCFDu, 0xFF028283u, 0xFF068687u,
    0xFF0A8A8Bu, 0xFF0E8E8Fu, 0xFF129293u, 0xFF169697u, 0xFF1A9A9Bu, 0xFF1E9E9Fu,
    0xFF22A2A3u, 0xFF26A6A7u, 0xFF2AAAABu, 0xFF2EAEAFu, 0xFF32B2B3u, 0xFF36B6B7u,
    0xFF3ABABBu, 0xFF3EBEBFu, 0xFF42C2C3u, 0xFF46C6C7u, 0xFF4ACACBu, 0xFF4ECECFu,
    0xFF52D2D3u, 0xFF56D6D7u, 0xFF5ADADBu, 0xFF5EDEDFu, 0xFF62E2E3u, 0xFF66E6E7u,
    0xFF6AEAEBu, 0xFF6EEEEFu, 0xFF72F2F3u, 0xFF76F6F7u, 0xFF7AFAFBu, 0xFF7EFEFFu,
    0xFF818182u, 0xFF838384u, 0xFF858586u, 0xFF878788u, 0xFF89898Au, 0xFF8B8B8Cu,
    0xFF8D8D8Eu, 0xFF8F8F90u, 0xFF919192u, 0xFF939394u, 0xFF959596u, 0xFF979798u,
    0xFF99999Au, 0xFF9B9B9Cu, 0xFF9D9D9Eu, 0xFF9F9FA0u, 0xFFA1A1A2u, 0xFFA3A3A4u,
    0xFFA5A5A6u, 0xFFA7A7A8u, 0xFFA9A9AAu, 0xFFABABACu, 0xFFADADAEu, 0xFFAFAFB0u,
    0xFFB1B1B2u, 0xFFB3B3B4u, 0xFFB5B5B6u, 0xFFB7B7B8u, 0xFFB9B9BAu, 0xFFBBBBBCu,
    0xFFBDBDBEu, 0xFFBFBFC0u, 0xFFC1C1C2u, 0xFFC3C3C4u, 0xFFC5C5C6u, 0xFFC7C7C8u,
    0xFFC9C9CAu, 0xFFCBCBCCu, 0xFFCDCDCEu, 0xFFCFCFD0u, 0xFFD1D1D2u, 0xFFD3D3D4u,
    0xFFD5D5D6u, 0xFFD7D7D8u, 0xFFD9D9DAu, 0xFFDBDBDCu, 0xFFDDDDDEu, 0xFFDFDFE0u,
    0xFFE1E1E2u, 0xFFE3E3E4u, 0xFFE5E5E6u, 0xFFE7E7E8u, 0xFFE9E9EAu, 0xFFEBEBECu,
    0xFFEDEDEEu, 0xFFEFEFF0u, 0xFFF1F1F2u, 0xFFF3F3F4u, 0xFFF5F5F6u, 0xFFF7F7F8u,
    0xFFF9F9FAu, 0xFFFBFBFCu, 0xFFFDFDFEu, 0x00000000u,
};

static unsigned dec_px_f32(const uint8_t *code, uint32_t *out)
{
    uint32_t xe = code[3];
    uint32_t r, g, b;
    unsigned flags = 0u;
    if (xe - 9u < 246u) {
        uint32_t eb = xe << 23;
        r = dec_base[code[0]] + eb;
        g = dec_base[code[1]] + eb;
        b = dec_base[code[2]] + eb;
    } else { /* subnormal results (E <= 8) or the saturating E = 255 */
        r = dec_chan_f32(code[0], xe, &flags);
        g = dec_chan_f32(code[1], xe, &flags);
        b = dec_chan_f32(code[2], xe, &flags);
    }
    out[0] = r; /* all code bytes are read before the first write: code and out may overlap */
    out[1] = g;
    out[2] = b;
    return flags;
}

#if QIBL_CONFIG_SIMD != QIBL_SIMD_SCALAR
/* ---- bulk decoder to binary32: intrinsics -----------------------------------------------------
 *
 * dec_base[X] + (E << 23) for E in 9..254 (dec_px_f32's table path) computed instead of looked up:
 * with m = |2X - 255| (odd), n its leading zeros in 8 bits and M = m << n (128..255),
 *     dec_base[X] = sign 2^31 + M 0x010101 + 1 - ((n + 2) << 23)   (mod 2^32),
 * dec_chan_f32's normal case: m 0x01010101 << n = M 0x01010101, whose rounding bit (bit 7 of M)
 * is 1 (for X = 0 / 255, M = 255 and n = 0 give the sign bit alone, as in the table).
 * NEON counts n with vclz and shifts by it. SSE2/AVX2 have neither; there v = 2X - 255 is converted
 * to binary32 (cvtdq2ps: exact as |v| < 2^24, so no rounding, no flag, the same bits under any
 * rounding mode), whose bits are F = sign 2^31 + ((134 - n) << 23) + (M - 128) 2^16, so
 *     dec_base[X] = F + 257 (M - 128) + 0x8081 - (135 << 23)   (mod 2^32),
 * M - 128 = (F >> 16) & 0x7F: integer operations on F's bits. A code with E outside 9..254 gets
 * meaningless words and is redone by dec_px_f32; dec_simd says whether a group has one. */
#if QIBL_CONFIG_SIMD == QIBL_SIMD_SSE2 || QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
#define V_F(v) _mm256_castsi256_ps(v)
#else
#define V_F(v) _mm_castsi128_ps(v)
#endif
#if defined(QIBLI_SRGBE_AVX512)
/* one channel of 16 codes, as dec_chan below */
static __m512i dec_chan16(__m512i x2, __m512i base)
{
    const __m512i f = _mm512_castps_si512(_mm512_cvtepi32_ps(_mm512_sub_epi32(x2, _mm512_set1_epi32(255))));
    const __m512i lo7 = _mm512_and_si512(_mm512_srli_epi32(f, 16), _mm512_set1_epi32(0x7F));
    return _mm512_add_epi32(_mm512_add_epi32(f, base), _mm512_add_epi32(_mm512_slli_epi32(lo7, 8), lo7));
}

/* 16 codes at c decoded to binary32 words at o (the AVX-512 copy: one 64-byte load, the R, G, B
 * planes interleaved by two vpermt2d per 64-byte store); nonzero if one has E outside 9..254 */
static unsigned dec_simd(const uint8_t *c, uint32_t *o)
{
    const __m512i w = _mm512_loadu_si512((const void *)c);
    const __m512i e = _mm512_srli_epi32(w, 24);
    const __m512i base = _mm512_add_epi32(_mm512_slli_epi32(e, 23), _mm512_set1_epi32(-0x437F7F7F));
    const __m512i mask = _mm512_set1_epi32(0x1FE);
    const __m512i r = dec_chan16(_mm512_and_si512(_mm512_slli_epi32(w, 1), mask), base);
    const __m512i g = dec_chan16(_mm512_and_si512(_mm512_srli_epi32(w, 7), mask), base);
    const __m512i b = dec_chan16(_mm512_and_si512(_mm512_srli_epi32(w, 15), mask), base);
    const __mmask16 bad = _mm512_cmpge_epu32_mask(_mm512_sub_epi32(e, _mm512_set1_epi32(9)), _mm512_set1_epi32(246));
    /* output word j (of 48) is channel j % 3 of pixel j / 3: R and G first (index 16 + i: G of
     * pixel i; B's lanes get R's placeholder), then B placed over them (16 + i: B of pixel i) */
#define RG(j0) _mm512_setr_epi32(RG1(j0), RG1(j0 + 1), RG1(j0 + 2), RG1(j0 + 3), RG1(j0 + 4), RG1(j0 + 5),        \
                                 RG1(j0 + 6), RG1(j0 + 7), RG1(j0 + 8), RG1(j0 + 9), RG1(j0 + 10), RG1(j0 + 11),  \
                                 RG1(j0 + 12), RG1(j0 + 13), RG1(j0 + 14), RG1(j0 + 15))
#define RG1(j) ((j) % 3 == 1 ? 16 + (j) / 3 : (j) / 3)
#define PB(j0) _mm512_setr_epi32(PB1(j0, 0), PB1(j0, 1), PB1(j0, 2), PB1(j0, 3), PB1(j0, 4), PB1(j0, 5),           \
                                 PB1(j0, 6), PB1(j0, 7), PB1(j0, 8), PB1(j0, 9), PB1(j0, 10), PB1(j0, 11),        \
                                 PB1(j0, 12), PB1(j0, 13), PB1(j0, 14), PB1(j0, 15))
#define PB1(j0, k) (((j0) + (k)) % 3 == 2 ? 16 + ((j0) + (k)) / 3 : (k))
    for (int k = 0; k < 3; ++k) {
        const __m512i rg = _mm512_permutex2var_epi32(r, k == 0 ? RG(0) : k == 1 ? RG(16) : RG(32), g);
        const __m512i x = _mm512_permutex2var_epi32(rg, k == 0 ? PB(0) : k == 1 ? PB(16) : PB(32), b);
        _mm512_storeu_si512((void *)(o + 16 * k), x);
    }
#undef RG
#undef RG1
#undef PB
#undef PB1
    return (unsigned)bad;
}
#define DEC_SIMD_PX 16
/* the input line and the three output lines 320 codes ahead, as the encoder's ENC_PF_PX (512 K codes
 * alone: 0.59 ns/px against 0.65 without; 160 to 640 ahead alike, 1280 0.60) */
#define DEC_PF_PX 320
#else
/* one channel of VL codes: x2 = 2X, base = (E << 23) + 0x8081 - (135 << 23) */
static vi_t dec_chan(vi_t x2, vi_t base)
{
    const vi_t f = V_I(V_PS(cvtepi32)(V_(sub_epi32)(x2, V_SET1(255))));
    const vi_t lo7 = V_SI(and)(V_(srli_epi32)(f, 16), V_SET1(0x7F));
    return V_(add_epi32)(V_(add_epi32)(f, base), V_(add_epi32)(V_(slli_epi32)(lo7, 8), lo7));
}

/* VL codes at c decoded to binary32 words at o; nonzero if one of them has E outside 9..254 */
static unsigned dec_simd(const uint8_t *c, uint32_t *o)
{
    const vi_t w = V_SI(loadu)((const vi_t *)(const void *)c);
    const vi_t e = V_(srli_epi32)(w, 24);
    /* 0x8081 - (135 << 23) = -0x437F7F7F */
    const vi_t base = V_(add_epi32)(V_(slli_epi32)(e, 23), V_(set1_epi32)(-0x437F7F7F));
    const vi_t mask = V_SET1(0x1FE);
    const vf_t r = V_F(dec_chan(V_SI(and)(V_(slli_epi32)(w, 1), mask), base));
    const vf_t g = V_F(dec_chan(V_SI(and)(V_(srli_epi32)(w, 7), mask), base));
    const vf_t b = V_F(dec_chan(V_SI(and)(V_(srli_epi32)(w, 15), mask), base));
    const vi_t bad = V_SI(or)(V_(cmpgt_epi32)(V_SET1(9), e), V_(cmpgt_epi32)(e, V_SET1(254)));
    /* R, G, B planes (bit moves) to r0 g0 b0 r1 | g1 b1 r2 g2 | b2 r3 g3 b3 per 128-bit half */
    const vf_t rg = V_PS(shuffle)(r, g, _MM_SHUFFLE(2, 0, 2, 0)); /* r0 r2 g0 g2 */
    const vf_t br = V_PS(shuffle)(b, r, _MM_SHUFFLE(3, 1, 2, 0)); /* b0 b2 r1 r3 */
    const vf_t gb = V_PS(shuffle)(g, b, _MM_SHUFFLE(3, 1, 3, 1)); /* g1 g3 b1 b3 */
    const vi_t l0 = V_I(V_PS(shuffle)(rg, br, _MM_SHUFFLE(2, 0, 2, 0)));
    const vi_t l1 = V_I(V_PS(shuffle)(gb, rg, _MM_SHUFFLE(3, 1, 2, 0)));
    const vi_t l2 = V_I(V_PS(shuffle)(br, gb, _MM_SHUFFLE(3, 1, 3, 1)));
#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
    /* halves: pixels 0..3 (words 0..11) low, 4..7 (words 12..23) high */
    _mm256_storeu_si256((__m256i *)(void *)o, _mm256_permute2x128_si256(l0, l1, 0x20));
    _mm256_storeu_si256((__m256i *)(void *)(o + 8), _mm256_permute2x128_si256(l2, l0, 0x30));
    _mm256_storeu_si256((__m256i *)(void *)(o + 16), _mm256_permute2x128_si256(l1, l2, 0x31));
#else
    _mm_storeu_si128((__m128i *)(void *)o, l0);
    _mm_storeu_si128((__m128i *)(void *)(o + 4), l1);
    _mm_storeu_si128((__m128i *)(void *)(o + 8), l2);
#endif
    return (unsigned)V_(movemask_epi8)(bad);
}
#define DEC_SIMD_PX VL
#endif /* QIBLI_SRGBE_AVX512 */

#elif QIBL_CONFIG_SIMD == QIBL_SIMD_NEON
/* 4 codes at c decoded to binary32 words at o; nonzero if one of them has E outside 9..254 */
static unsigned dec_simd(const uint8_t *c, uint32_t *o)
{
    const uint32x4_t w = vreinterpretq_u32_u8(vld1q_u8(c)); /* little-endian lanes: byte 0 = R */
    const uint32x4_t e = vshrq_n_u32(w, 24);
    /* (E << 23) + 1 - (2 << 23) */
    const uint32x4_t base = vaddq_u32(vshlq_n_u32(e, 23), vdupq_n_u32(1u - (2u << 23)));
    uint32x4x3_t v;
    for (int k = 0; k < 3; ++k) {
        const int32x4_t x2 = vreinterpretq_s32_u32(vandq_u32(
            k == 0 ? vshlq_n_u32(w, 1) : k == 1 ? vshrq_n_u32(w, 7) : vshrq_n_u32(w, 15), vdupq_n_u32(0x1FEu)));
        const int32x4_t sv = vsubq_s32(x2, vdupq_n_s32(255));
        const uint32x4_t m = vreinterpretq_u32_s32(vabsq_s32(sv));
        const uint32x4_t n = vsubq_u32(vclzq_u32(m), vdupq_n_u32(24u));
        const uint32x4_t mm = vshlq_u32(m, vreinterpretq_s32_u32(n)); /* M */
        const uint32x4_t sign = vandq_u32(vreinterpretq_u32_s32(sv), vdupq_n_u32(0x80000000u));
        const uint32x4_t t = vmlaq_n_u32(vsubq_u32(base, vshlq_n_u32(n, 23)), mm, 0x010101u);
        v.val[k] = vaddq_u32(t, sign);
    }
    vst3q_u32(o, v);
    const uint32x4_t bad = vorrq_u32(vcltq_u32(e, vdupq_n_u32(9u)), vcgtq_u32(e, vdupq_n_u32(254u)));
    const uint32x2_t mb = vorr_u32(vget_low_u32(bad), vget_high_u32(bad));
    return vget_lane_u32(mb, 0) | vget_lane_u32(mb, 1);
}
#define DEC_SIMD_PX 4
#endif
#endif /* QIBL_CONFIG_SIMD != QIBL_SIMD_SCALAR */

/* ---- decode to int32 * 2^-frac_bits --------------------------------------------------------- */

/* round_half_up(+-m 2^s / 255) saturated to int32, s = E - 127 + frac_bits. All 32-bit: with
 * x = m/255 and f = m * 0x01010101 = floor(x 2^32),
 *   round(x 2^s) = floor((floor(x 2^(s+1)) + 1) / 2) = ((f >> (31 - s)) + 1) >> 1   for s in 0..31
 * (the tail of x below f's last bit is < 1 unit, so it cannot move these floors), and since
 * 256 x = m + x (the period-8 expansion),
 *   round(x 2^s) = m 2^(s-8) + round(x 2^(s-8))                                     for s in 32..39. */
static int32_t dec_chan_s32(uint32_t x, int s, unsigned *flags)
{
    int neg = x < 128u;
    uint32_t m = neg ? 255u - 2u * x : 2u * x - 255u;
    uint32_t mag = 0u; /* round(|c|) (no tie for m < 255), or exactly 2^s for m = 255 */
    int sat = 0;
    if (m == 255u) {
        if (s >= 32)
            sat = 1;
        else if (s >= 0)
            mag = (uint32_t)1u << s;
        else
            return s == -1 && !neg ? 1 : 0; /* +-1/2 LSB: ties toward +infinity; below: 0 */
    } else if (s < 0) {
        return 0; /* |c| 2^frac_bits < 2^s <= 1/2: rounds to 0 with either sign */
    } else {
        uint32_t f = m * 0x01010101u;
        if (s <= 31) {
            mag = ((f >> (31 - s)) + 1u) >> 1; /* <= round(253/255 2^31) < 2^31 */
        } else if (s <= 39) {
            unsigned t = (unsigned)s - 8u; /* 24..31 */
            if (m >= (0x80000000u >> t))
                sat = 1; /* m 2^t >= 2^31 and the rounded rest is >= 1: beyond either end */
            else
                mag = (m << t) + (((f >> (39 - s)) + 1u) >> 1);
        } else {
            sat = 1; /* |c| > 2^(s-8) >= 2^32 */
        }
    }
    if (neg) {
        if (sat || mag > 0x80000000u) {
            *flags |= F_DSAT;
            return INT32_MIN;
        }
        return mag == 0x80000000u ? INT32_MIN : -(int32_t)mag;
    }
    if (sat || mag > 0x7FFFFFFFu) {
        *flags |= F_DSAT;
        return INT32_MAX;
    }
    return (int32_t)mag;
}

static unsigned dec_px_s32(const uint8_t *code, int frac_bits, int32_t *out)
{
    unsigned flags = 0u;
    /* clamping to +-300 changes no result (s stays above 39 or below -1) and keeps s inside int */
    int f = frac_bits > 300 ? 300 : frac_bits < -300 ? -300 : frac_bits;
    int s = (int)code[3] - 127 + f;
    int32_t r = dec_chan_s32(code[0], s, &flags);
    int32_t g = dec_chan_s32(code[1], s, &flags);
    int32_t b = dec_chan_s32(code[2], s, &flags);
    out[0] = r;
    out[1] = g;
    out[2] = b;
    return flags;
}

/* ---- public entry points -------------------------------------------------------------------- */

qibl_status_t qibl_srgbe_encode_f32(const uint32_t rgb[3], uint8_t code[4])
{
    if (rgb == 0 || code == 0)
        return QIBL_E_NULL_POINTER;
    return status_of(enc_px_f32(rgb[0], rgb[1], rgb[2], code));
}

qibl_status_t qibl_srgbe_encode_s32(const int32_t rgb[3], int frac_bits, uint8_t code[4])
{
    if (rgb == 0 || code == 0)
        return QIBL_E_NULL_POINTER;
    return status_of(enc_px_s32(rgb[0], rgb[1], rgb[2], frac_bits, code));
}

qibl_status_t qibl_srgbe_encode_q16(const qibl_q16_t rgb[3], uint8_t code[4])
{
    return qibl_srgbe_encode_s32(rgb, 16, code);
}

qibl_status_t qibl_srgbe_decode_f32(const uint8_t code[4], uint32_t rgb[3])
{
    if (code == 0 || rgb == 0)
        return QIBL_E_NULL_POINTER;
    return status_of(dec_px_f32(code, rgb));
}

qibl_status_t qibl_srgbe_decode_s32(const uint8_t code[4], int frac_bits, int32_t rgb[3])
{
    if (code == 0 || rgb == 0)
        return QIBL_E_NULL_POINTER;
    return status_of(dec_px_s32(code, frac_bits, rgb));
}

qibl_status_t qibl_srgbe_decode_q16(const uint8_t code[4], qibl_q16_t rgb[3])
{
    return qibl_srgbe_decode_s32(code, 16, rgb);
}

qibl_status_t qibl_srgbe_encode_f32_n(const uint32_t *restrict rgb, size_t n, uint8_t *restrict codes)
{
    QIBLI_DISPATCH512(qibl_srgbe_encode_f32_n, (rgb, n, codes));
    if (rgb == 0 || codes == 0)
        return QIBL_E_NULL_POINTER;
    unsigned flags = 0u;
#if QIBL_CONFIG_SIMD != QIBL_SIMD_SCALAR || QIBL_CONFIG_SRGBE_BLOCKS
#if QIBL_CONFIG_SIMD != QIBL_SIMD_SCALAR
#define ENC_BULK_PX ENC_SIMD_PX
#define ENC_BULK(p, c) enc_simd(p, c)
#else
#define ENC_BULK_PX BLK
#define ENC_BULK(p, c) enc_blk(p, c)
#endif
    /* Whole blocks through enc_simd or enc_blk; a block holding a pixel they do not cover (zero,
     * subnormal or tiny maximum, Inf, NaN) has those pixels redone by enc_px_f32, as is the tail of
     * fewer than a block. The final bytes are enc_px_f32's for every pixel. */
    size_t i = 0;
    for (; n - i >= ENC_BULK_PX; i += ENC_BULK_PX) {
#ifdef ENC_PF_PX
        if (n - i >= ENC_PF_PX + ENC_BULK_PX) {
            enc_prefetch(rgb + 3 * (i + ENC_PF_PX));
            _mm_prefetch((const char *)(const void *)(codes + 4 * (i + ENC_PF_PX)), _MM_HINT_T0); /* <= 64 bytes */
        }
#endif
        if (ENC_BULK(rgb + 3 * i, codes + 4 * i))
            for (size_t j = i; j < i + ENC_BULK_PX; ++j) {
                const uint32_t *p = rgb + 3 * j;
                if (max3((p[0] >> 23) & 0xFFu, (p[1] >> 23) & 0xFFu, (p[2] >> 23) & 0xFFu) - 7u >= 248u)
                    flags |= enc_px_f32(p[0], p[1], p[2], codes + 4 * j);
            }
    }
    for (; i < n; ++i)
        flags |= enc_px_f32(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2], codes + 4 * i);
#else
    /* Every pixel through the branch-free fast path first; the rare pixels it does not cover are
     * rewritten by a second pass, so the hot loop has no branch and one store per pixel. The final
     * bytes are enc_px_f32's for every pixel. */
    uint32_t special = 0u;
    const uint32_t *p = rgb;
    uint8_t *c = codes;
    for (size_t i = 0; i < n; ++i, p += 3, c += 4) {
        uint32_t er = (p[0] >> 23) & 0xFFu, eg = (p[1] >> 23) & 0xFFu, eb = (p[2] >> 23) & 0xFFu;
        uint32_t em = max3(er, eg, eb);
        special |= em - 7u >= 248u;
        put_code(enc_word_fast(p[0], p[1], p[2], er, eg, eb, em), c);
    }
    if (special)
        for (size_t i = 0; i < n; ++i, rgb += 3, codes += 4) {
            uint32_t em = max3((rgb[0] >> 23) & 0xFFu, (rgb[1] >> 23) & 0xFFu, (rgb[2] >> 23) & 0xFFu);
            if (em - 7u >= 248u)
                put_code(enc_px_f32_general(rgb[0], rgb[1], rgb[2], &flags), codes);
        }
#endif
    return status_of(flags);
}

qibl_status_t qibl_srgbe_encode_s32_n(const int32_t *restrict rgb, size_t n, int frac_bits,
                                      uint8_t *restrict codes)
{
    QIBLI_DISPATCH(qibl_srgbe_encode_s32_n, (rgb, n, frac_bits, codes));
    if (rgb == 0 || codes == 0)
        return QIBL_E_NULL_POINTER;
    unsigned flags = 0u;
    for (size_t i = 0; i < n; ++i, rgb += 3, codes += 4)
        flags |= enc_px_s32(rgb[0], rgb[1], rgb[2], frac_bits, codes);
    return status_of(flags);
}

qibl_status_t qibl_srgbe_encode_q16_n(const qibl_q16_t *restrict rgb, size_t n, uint8_t *restrict codes)
{
    QIBLI_DISPATCH(qibl_srgbe_encode_q16_n, (rgb, n, codes));
    return qibl_srgbe_encode_s32_n(rgb, n, 16, codes);
}

qibl_status_t qibl_srgbe_decode_f32_n(const uint8_t *restrict codes, size_t n, uint32_t *restrict rgb)
{
    QIBLI_DISPATCH512(qibl_srgbe_decode_f32_n, (codes, n, rgb));
    if (codes == 0 || rgb == 0)
        return QIBL_E_NULL_POINTER;
    unsigned flags = 0u;
#if QIBL_CONFIG_SIMD != QIBL_SIMD_SCALAR
    /* groups through dec_simd; codes it does not cover (E <= 8: subnormal results, E = 255:
     * saturation) redone by dec_px_f32, which gives every pixel's final words */
    for (; n >= DEC_SIMD_PX; n -= DEC_SIMD_PX, codes += 4 * DEC_SIMD_PX, rgb += 3 * DEC_SIMD_PX) {
#ifdef DEC_PF_PX
        if (n >= DEC_PF_PX + DEC_SIMD_PX) {
            _mm_prefetch((const char *)(const void *)(codes + 4 * DEC_PF_PX), _MM_HINT_T0);
            for (int k = 0; k < 3 * DEC_SIMD_PX; k += 16)
                _mm_prefetch((const char *)(const void *)(rgb + 3 * DEC_PF_PX + k), _MM_HINT_T0);
        }
#endif
        if (dec_simd(codes, rgb))
            for (size_t j = 0; j < DEC_SIMD_PX; ++j)
                if (codes[4 * j + 3] - 9u >= 246u)
                    flags |= dec_px_f32(codes + 4 * j, rgb + 3 * j);
    }
#endif
    for (size_t i = 0; i < n; ++i, codes += 4, rgb += 3)
        flags |= dec_px_f32(codes, rgb);
    return status_of(flags);
}

qibl_status_t qibl_srgbe_decode_s32_n(const uint8_t *restrict codes, size_t n, int frac_bits,
                                      int32_t *restrict rgb)
{
    QIBLI_DISPATCH(qibl_srgbe_decode_s32_n, (codes, n, frac_bits, rgb));
    if (codes == 0 || rgb == 0)
        return QIBL_E_NULL_POINTER;
    unsigned flags = 0u;
    for (size_t i = 0; i < n; ++i, codes += 4, rgb += 3)
        flags |= dec_px_s32(codes, frac_bits, rgb);
    return status_of(flags);
}

qibl_status_t qibl_srgbe_decode_q16_n(const uint8_t *restrict codes, size_t n, qibl_q16_t *restrict rgb)
{
    QIBLI_DISPATCH(qibl_srgbe_decode_q16_n, (codes, n, rgb));
    return qibl_srgbe_decode_s32_n(codes, n, 16, rgb);
}

#else
typedef int qibl_srgbe_disabled_t; /* ISO C forbids an empty translation unit */
#endif /* QIBL_USE_SRGBE */
