/*
 * golden/cases_fixed.c - fixed_*: the fixed-point primitives of qibl/fixed.h over curated edge
 * values and fixed-seed random inputs of every bit width: the inline shifts and products (whose
 * native and 16-bit/halves paths must agree), division, square roots, reciprocals and the two
 * normalisations.
 */
#include "golden/casesi.h"

#include <limits.h>

#include "qibl/fixed.h"

/* a uint64 with a random bit length 0..64 */
static uint64_t any_width_u64(qtool_grng *r)
{
    unsigned bits = (unsigned)(qtool_grng_next(r) % 65u);
    uint64_t v = qtool_grng_next(r);
    return bits == 0 ? 0u : bits == 64 ? v : v >> (64u - bits);
}

/* an int32 with a random bit length and sign */
static int32_t any_width_s32(qtool_grng *r)
{
    uint64_t v = any_width_u64(r) & 0xFFFFFFFFu;
    unsigned bits = (unsigned)(qtool_grng_next(r) % 33u);
    uint32_t u = bits == 0 ? 0u : bits == 32 ? (uint32_t)v : (uint32_t)v >> (32u - bits);
    return qtool_grng_next(r) & 1u ? qtool_gs32(0u - u) : qtool_gs32(u);
}

static const uint64_t edges64[] = {
    0u, 1u, 2u, 3u, 4u, 0x7Fu, 0x80u, 0xFFFFu, 0x10000u, 0x10001u, 0x7FFFFFFFu, 0x80000000u, 0xFFFFFFFFu,
    0x100000000u, 0x100000001u, 0x3FFFFFFFFFFFFFFFu, 0x4000000000000000u, 0x7FFFFFFFFFFFFFFFu,
    0x8000000000000000u, 0xFFFFFFFFFFFFFFFEu, 0xFFFFFFFFFFFFFFFFu, 0xFFFFFFFE00000001u, 0x0123456789ABCDEFu,
};
#define NEDGE (sizeof edges64 / sizeof edges64[0])

/* shifts, saturation and exact products from fixed.h */
static int inline_ops(const qtool_goldens_sink_t *s)
{
    qtool_gbuf b = {0};
    qtool_grng r = {0xF1DE};
    for (int i = 0; i < 3000; ++i) {
        uint64_t u = i < (int)NEDGE ? edges64[i] : any_width_u64(&r);
        /* int64 from the bits, without an implementation-defined conversion */
        int64_t sx = u <= (uint64_t)INT64_MAX ? (int64_t)u : (int64_t)(u - 0x8000000000000000u) - INT64_MAX - 1;
        int32_t a = i < (int)NEDGE ? qtool_gs32((uint32_t)u) : any_width_s32(&r), c = any_width_s32(&r);
        unsigned n = (unsigned)(qtool_grng_next(&r) % 64u);
        qtool_gbuf_u64(&b, qibl_shr_u64(u, n));
        qtool_gbuf_u64(&b, (uint64_t)qibl_asr_s64(sx, n));
        qtool_gbuf_s32(&b, qibl_asr_s32(a, n & 31u));
        /* qibl_rshr_s64 needs |x| <= 2^62 and n in 1..62 */
        int64_t x62 = qibl_asr_s64(sx, 1);
        qtool_gbuf_s32(&b, qibl_rshr_s64(x62, 1u + n % 62u));
        qtool_gbuf_u64(&b, qibl_mul_u32_u64((uint32_t)a, (uint32_t)c));
        qtool_gbuf_u64(&b, (uint64_t)qibl_mul_s32_s64(a, c));
        qtool_gbuf_s32(&b, qibl_mul_q16(a, c));
        qtool_gbuf_s32(&b, qibl_mul_q30(a, c));
        qtool_gbuf_s32(&b, qibl_add_sat_s32(a, c));
        qtool_gbuf_s32(&b, qibl_sub_sat_s32(a, c));
    }
    return qtool_gbuf_emit(s, "fixed_inline_ops", &b);
}

/* division, square roots, reciprocals */
static int div_roots(const qtool_goldens_sink_t *s)
{
    qtool_gbuf b = {0};
    qtool_grng r = {0xD1F};
    for (int i = 0; i < 3000; ++i) {
        uint64_t n = i < (int)(NEDGE * NEDGE) ? edges64[(size_t)i / NEDGE] : any_width_u64(&r);
        uint64_t d = i < (int)(NEDGE * NEDGE) ? edges64[(size_t)i % NEDGE] : any_width_u64(&r);
        uint64_t rem = 0x5A5A5A5A5A5A5A5Au;
        qtool_gbuf_u64(&b, qibl_udiv_u64(n, d, &rem));
        qtool_gbuf_u64(&b, rem);
        rem = 0x5A5A5A5A5A5A5A5Au;
        qtool_gbuf_u32(&b, qibl_isqrt_u64(n, &rem));
        qtool_gbuf_u64(&b, rem);
        uint32_t x = (uint32_t)d;
        qtool_gbuf_u32(&b, qibl_isqrt_u32(x));
        qtool_gbuf_u32(&b, qibl_sqrt_uq16(x));
        qibl_uq16_t ro = 0xA5A5A5A5u;
        qtool_gbuf_u8(&b, (uint32_t)qibl_rsqrt_uq16(x, &ro));
        qtool_gbuf_u32(&b, ro);
        qibl_q16_t rc = qtool_gs32(0xA5A5A5A5u);
        qtool_gbuf_u8(&b, (uint32_t)qibl_recip_q16(qtool_gs32(x), &rc));
        qtool_gbuf_s32(&b, rc);
        unsigned e = 99;
        qtool_gbuf_u32(&b, qibl_rsqrt_u64(n, &e));
        qtool_gbuf_u32(&b, e);
    }
    return qtool_gbuf_emit(s, "fixed_div_roots", &b);
}

/* qibl_vec3_normalize_q30 and qibl_vec3_normalize_fast_q30 */
static int normalize(const qtool_goldens_sink_t *s)
{
    static const int32_t ev[] = {0, 1, -1, 2, 65536, -65536, INT32_MAX, INT32_MIN, INT32_MIN + 1, 0x40000000, 46341};
    enum { NE = sizeof ev / sizeof ev[0] };
    qtool_gbuf b = {0};
    qtool_grng r = {0x0A0B};
    for (int i = 0; i < NE * NE * NE + 3000; ++i) {
        int32_t v[3];
        if (i < NE * NE * NE)
            v[0] = ev[i / (NE * NE)], v[1] = ev[i / NE % NE], v[2] = ev[i % NE];
        else
            v[0] = any_width_s32(&r), v[1] = any_width_s32(&r), v[2] = any_width_s32(&r);
        qibl_q30_t o[3] = {qtool_gs32(0xA5A5A5A5u), qtool_gs32(0xA5A5A5A5u), qtool_gs32(0xA5A5A5A5u)};
        qtool_gbuf_u8(&b, (uint32_t)qibl_vec3_normalize_q30(v, o));
        for (int c = 0; c < 3; ++c)
            qtool_gbuf_s32(&b, o[c]);
        qibl_q30_t f[3] = {qtool_gs32(0xA5A5A5A5u), qtool_gs32(0xA5A5A5A5u), qtool_gs32(0xA5A5A5A5u)};
        uint32_t ly = 0xA5A5A5A5u;
        unsigned le = 0xA5u;
        qtool_gbuf_u8(&b, (uint32_t)qibl_vec3_normalize_fast_q30(v, f, &ly, &le));
        for (int c = 0; c < 3; ++c)
            qtool_gbuf_s32(&b, f[c]);
        qtool_gbuf_u32(&b, ly), qtool_gbuf_u32(&b, le);
    }
    return qtool_gbuf_emit(s, "fixed_normalize", &b);
}

int qtool_goldens_fixed(const qtool_goldens_sink_t *s)
{
    return inline_ops(s) + div_roots(s) + normalize(s);
}
