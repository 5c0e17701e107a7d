/*
 * qibli.h - internal helpers shared by the core's modules (not installed, not API: names qibli_*).
 *
 * One definition of each integer idiom the modules used to write out themselves: magnitudes of
 * signed values as unsigned (defined for INT32_MIN/INT64_MIN), the left 64-bit shift that pairs
 * with fixed.h's qibl_shr_u64, bit lengths, the rounded 64-bit shift of fixed.h, and the last step
 * of the fast normalisation (fixed.c's qibl_vec3_normalize_fast_q30 and the point-light kernel).
 *
 * Code size against speed: built for size (-Os, __OPTIMIZE_SIZE__), the two larger helpers
 * (qibli_rshr_s64, qibli_bitlen_u64) are calls to the one out-of-line copy in fixed.c, so the image
 * holds each once (before, -Os left a private copy of qibl_rshr_s64 in sh.o and in shmap.o);
 * otherwise they are static inline, so hot loops keep them inlined. Same bits either way.
 * Only the freestanding headers, like every core file.
 */
#ifndef QIBLI_H
#define QIBLI_H

#include <stdint.h>
#include "qibl/fixed.h"

/* Keeps a function out of line where the compiler supports saying so (nothing otherwise): for
 * kernels whose vectorisation needs their restrict parameters intact. */
#if defined(__GNUC__) || defined(__clang__)
#define QIBLI_NOINLINE __attribute__((noinline))
#else
#define QIBLI_NOINLINE
#endif

/* |x| as an unsigned value: exact for every int32 / int64 including the most negative one. */
static inline uint32_t qibli_abs_u32(int32_t x)
{
    return x < 0 ? 0u - (uint32_t)x : (uint32_t)x;
}
static inline uint64_t qibli_abs_u64(int64_t x)
{
    return x < 0 ? 0u - (uint64_t)x : (uint64_t)x;
}

/* x << n for n in 0..63: the left twin of qibl_shr_u64, native where the target shifts 64-bit
 * values inline, else from 32-bit halves (QIBL_CONFIG_NATIVE_SHIFT64; no __aeabi_llsl). */
static inline uint64_t qibli_shl_u64(uint64_t x, unsigned n)
{
#if QIBL_CONFIG_NATIVE_SHIFT64
    return x << n;
#else
    uint32_t hi = (uint32_t)(x >> 32), lo = (uint32_t)x;
    if (n == 0u)
        return x;
    if (n >= 32u)
        return (uint64_t)(lo << (n - 32u)) << 32;
    return ((uint64_t)((hi << n) | (lo >> (32u - n))) << 32) | (uint32_t)(lo << n);
#endif
}

/* floor(log2 x) + 1 for a 32-bit x, 0 for 0 (constant shifts only) */
static inline unsigned qibli_bitlen_u32(uint32_t x)
{
    unsigned n = 0u;
    if (x >> 16) { x >>= 16; n += 16u; }
    if (x >> 8) { x >>= 8; n += 8u; }
    if (x >> 4) { x >>= 4; n += 4u; }
    if (x >> 2) { x >>= 2; n += 2u; }
    if (x >> 1) { x >>= 1; n += 1u; }
    return n + x;
}

/* bit length: 0 for 0, floor(log2 x) + 1 otherwise (the 32-bit steps on the half that holds the
 * top bit: constant shifts only, and no 64-bit shift beyond the first on 32-bit targets) */
static inline unsigned qibli_bitlen_u64_inline(uint64_t x)
{
    uint32_t hi = (uint32_t)(x >> 32);
    return hi ? 32u + qibli_bitlen_u32(hi) : qibli_bitlen_u32((uint32_t)x);
}

/* 1/sqrt seeds (fixed.c): round(2^30 / sqrt((i + 0.5) 2^24)) for i = 64..255, relative error <= 2^-9 */
extern const uint16_t qibli_rsqrt_seed[192];

/* The out-of-line copies (fixed.c), always defined so objects built with different flags link. */
unsigned qibli_bitlen_u64_call(uint64_t x);
int32_t qibli_rshr_s64_call(int64_t x, unsigned n);

#if defined(__OPTIMIZE_SIZE__)
#define qibli_bitlen_u64 qibli_bitlen_u64_call
#define qibli_rshr_s64 qibli_rshr_s64_call
#else
#define qibli_bitlen_u64 qibli_bitlen_u64_inline
#define qibli_rshr_s64 qibl_rshr_s64
#endif

/* u = l / |l| in Q2.30 from 1/|l| = iy / 2^e (qibl_rsqrt_u64 of |l|^2, e in 31..62): per component
 * round(|l_j| iy / 2^(e - 30)) (ties away from zero), clamped to 1.0 (rounding may overshoot it
 * by an LSB), sign restored. The product is <= 2^62 and the shift e - 30 is 1..32. */
static inline void qibli_unit_q30(const int32_t l[3], uint32_t iy, unsigned e, qibl_q30_t u[3])
{
    const unsigned sh = e - 30u;
    for (int j = 0; j < 3; ++j) {
        uint64_t q = qibl_shr_u64(qibl_mul_u32_u64(qibli_abs_u32(l[j]), iy) + qibl_shr_u64((uint64_t)1 << 63, 64u - sh), sh);
        int32_t m = (int32_t)(q > 0x40000000u ? 0x40000000u : q);
        u[j] = l[j] < 0 ? -m : m;
    }
}

/* Run-time kernel choice (qibl/isa.h, QIBL_CONFIG_DISPATCH): the first statement of each public
 * function whose work is a SIMD kernel. In the library's own copy of a module (the SSE2 build) it
 * hands the call to the AVX2 or scalar copy (core/src/x86/: the same source, every external name
 * suffixed) when qibl_isa_active() says so (the AVX-512 choice to the AVX2 copy; QIBLI_DISPATCH512,
 * for a function whose module has an AVX-512 copy, to that one); in those copies, in the scalar
 * twins of tools/twin and on every build without dispatch it is nothing. Cost: one
 * qibl_isa_active() per call. */
#if QIBL_CONFIG_DISPATCH && QIBL_CONFIG_SIMD == QIBL_SIMD_SSE2 && !defined(QIBLI_ISA_VARIANT)
#include "qibl/isa.h"
#define QIBLI_DISPATCH(fn, args)                                                                       \
    do {                                                                                               \
        extern __typeof__(fn) fn##_avx2, fn##_scalar;                                                  \
        const qibl_isa_t isa_ = qibl_isa_active();                                                     \
        if (isa_ == QIBL_ISA_AVX2 || isa_ == QIBL_ISA_AVX512)                                          \
            return fn##_avx2 args;                                                                     \
        if (isa_ == QIBL_ISA_SCALAR)                                                                   \
            return fn##_scalar args;                                                                   \
    } while (0)
#define QIBLI_DISPATCH512(fn, args)                                                                    \
    do {                                                                                               \
        extern __typeof__(fn) fn##_avx512, fn##_avx2, fn##_scalar;                                     \
        const qibl_isa_t isa_ = qibl_isa_active();                                                     \
        if (isa_ == QIBL_ISA_AVX512)                                                                   \
            return fn##_avx512 args;                                                                   \
        if (isa_ == QIBL_ISA_AVX2)                                                                     \
            return fn##_avx2 args;                                                                     \
        if (isa_ == QIBL_ISA_SCALAR)                                                                   \
            return fn##_scalar args;                                                                   \
    } while (0)
#else
#define QIBLI_DISPATCH(fn, args) ((void)0)
#define QIBLI_DISPATCH512(fn, args) ((void)0)
#endif

#if QIBL_USE_ASSET
#include "qibl/asset.h"
/* An optional chunk's one copy in the asset (a second one: QIBL_E_ASSET_DUPLICATE_CHUNK) and the
 * asset's SH maps, whose size the chunk must have: the first step of each *_from_asset. */
static inline qibl_status_t qibli_asset_sole_chunk(const qibl_asset_t *a, uint32_t type, qibl_chunk_t *c,
                                                   qibl_shmaps_t *m)
{
    qibl_status_t st = qibl_asset_find_nth(a, type, 0, c);
    if (st == QIBL_OK && qibl_asset_find_nth(a, type, 1, c) == QIBL_OK)
        return QIBL_E_ASSET_DUPLICATE_CHUNK;
    if (st == QIBL_OK)
        st = qibl_asset_shmaps(a, m);
    return st;
}
#endif

#endif /* QIBLI_H */
