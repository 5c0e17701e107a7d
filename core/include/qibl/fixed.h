/*
 * qibl/fixed.h - the Q formats of qibl and the integer primitives every module builds on.
 *
 * Invariants: no floating point, no undefined or implementation-defined behaviour (no signed
 * overflow, no right shift of a negative value, no out-of-range signed conversion), no library
 * calls (no __aeabi_lmul, __aeabi_uldivmod, __aeabi_llsr, ... on any target). The same inputs give
 * the same bits on every compiler, optimisation level and architecture.
 *
 * Q formats (Qm.n: m integer bits including the sign, n fraction bits; value = integer / 2^n)
 *
 *   name          C type    format   range                     one LSB     used for
 *   qibl_q16_t    int32_t   Q16.16   [-32768, 32768 - 2^-16]   2^-16       positions, directions in
 *                                                                          (any length), colours
 *   qibl_uq16_t   uint32_t  UQ16.16  [0, 65536 - 2^-16]        2^-16       sqrt/rsqrt arguments
 *   qibl_q30_t    int32_t   Q2.30    [-2, 2 - 2^-30]           2^-30       unit vectors, SH basis
 *                                                                          values
 *   qibl_q29_t    int32_t   Q3.29    [-4, 4 - 2^-29]           2^-29       SH recurrence terms
 *   qibl_q24_t    int32_t   Q8.24    [-128, 128 - 2^-24]       2^-24       SH map scale and bias
 *                                                                          (decoded map values)
 *
 * Rounding rule, everywhere unless a function says otherwise: round to nearest, ties toward
 * +infinity ("half up": floor(x + 1/2)), applied once at the end of each primitive. Functions that
 * can saturate say so; saturation clamps to the format's end points.
 */
#ifndef QIBL_FIXED_H
#define QIBL_FIXED_H

#include <stdint.h>
#include "qibl/config.h"
#include "qibl/status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef int32_t qibl_q16_t;
typedef uint32_t qibl_uq16_t;
typedef int32_t qibl_q30_t;
typedef int32_t qibl_q29_t;
typedef int32_t qibl_q24_t;

/* int32_t constants (every Q type is int32_t); QIBL_I32_C: no cast for C++ warnings (config.h) */
#define QIBL_Q16_ONE QIBL_I32_C(0x00010000)
#define QIBL_Q30_ONE QIBL_I32_C(0x40000000)
#define QIBL_Q29_ONE QIBL_I32_C(0x20000000)
#define QIBL_Q24_ONE QIBL_I32_C(0x01000000)

/* ---- saturation and shifts ------------------------------------------------------------------ */

/* x clamped to [INT32_MIN, INT32_MAX]. Exact. */
static inline int32_t qibl_sat_s32(int64_t x)
{
    /* literals, not INT32_MAX/INT32_MIN: C++98 <stdint.h> may hide those (__STDC_LIMIT_MACROS) */
    if (x > 0x7FFFFFFF)
        return 0x7FFFFFFF;
    if (x < -0x7FFFFFFF - 1)
        return -0x7FFFFFFF - 1;
    return QIBL_CAST(int32_t, x);
}

/* a + b saturated to int32 (any Q format, both operands in the same one). Exact or saturated. */
static inline int32_t qibl_add_sat_s32(int32_t a, int32_t b)
{
    return qibl_sat_s32(QIBL_CAST(int64_t, a) + b);
}

/* a - b saturated to int32. Exact or saturated. */
static inline int32_t qibl_sub_sat_s32(int32_t a, int32_t b)
{
    return qibl_sat_s32(QIBL_CAST(int64_t, a) - b);
}

/* floor(x / 2^n) for any int32 x and n in 0..31: the arithmetic right shift C99 leaves
 * implementation-defined for negative x, defined here by offsetting into unsigned range:
 * floor((x + 2^31) / 2^n) - 2^(31-n) is the same floor because 2^31 is a multiple of 2^n.
 * Compilers reduce it to one shift instruction. */
static inline int32_t qibl_asr_s32(int32_t x, unsigned n)
{
    if (n == 0u)
        return x; /* u >> 0 would not fit int32 */
    uint32_t u = QIBL_CAST(uint32_t, x) ^ 0x80000000u; /* = x + 2^31, in 0..2^32-1 */
    return QIBL_CAST(int32_t, u >> n) - QIBL_CAST(int32_t, 0x80000000u >> n);
}

/* u >> n for any uint64 u and n in 0..63. Where a variable 64-bit shift would be a library call
 * (__aeabi_llsr on Cortex-M0, QIBL_CONFIG_NATIVE_SHIFT64 = 0) it is built from 32-bit halves. */
static inline uint64_t qibl_shr_u64(uint64_t u, unsigned n)
{
#if QIBL_CONFIG_NATIVE_SHIFT64
    return u >> n;
#else
    uint32_t hi = QIBL_CAST(uint32_t, u >> 32), lo = QIBL_CAST(uint32_t, u);
    if (n == 0u)
        return u;
    if (n >= 32u)
        return hi >> (n - 32u);
    /* hi << (32 - n) is already uint32_t (no cast: -Wuseless-cast) and drops the bits above 32 */
    return (QIBL_CAST(uint64_t, hi >> n) << 32) | (lo >> n) | (hi << (32u - n));
#endif
}

/* floor(x / 2^n) for any int64 x and n in 0..63. Same construction as qibl_asr_s32. */
static inline int64_t qibl_asr_s64(int64_t x, unsigned n)
{
    if (n == 0u)
        return x;
    /* 2^63 spelt as a shift: a 64-bit literal is a pedantic error in C++98 where long has 32 bits */
    uint64_t u = QIBL_CAST(uint64_t, x) ^ (QIBL_CAST(uint64_t, 1) << 63);
    return QIBL_CAST(int64_t, qibl_shr_u64(u, n)) - QIBL_CAST(int64_t, qibl_shr_u64(QIBL_CAST(uint64_t, 1) << 63, n));
}

/* round(x / 2^n), ties toward +infinity, for n in 1..62 and |x| <= 2^62, saturated to int32.
 * floor((x + 2^(n-1)) / 2^n) = floor((floor(x / 2^(n-1)) + 1) / 2), which needs no 64-bit
 * constant built from n and cannot overflow. */
static inline int32_t qibl_rshr_s64(int64_t x, unsigned n)
{
    return qibl_sat_s32(qibl_asr_s64(qibl_asr_s64(x, n - 1u) + 1, 1));
}

/* ---- exact products ------------------------------------------------------------------------- */

/* a * b exactly, for any uint32 a, b. Without a native 32x32->64 multiply (Cortex-M0) it is
 * assembled from four 16x16 products, so no runtime-library call is emitted. */
static inline uint64_t qibl_mul_u32_u64(uint32_t a, uint32_t b)
{
#if QIBL_CONFIG_NATIVE_MUL64
    return QIBL_CAST(uint64_t, a) * b;
#else
    uint32_t al = a & 0xFFFFu, ah = a >> 16, bl = b & 0xFFFFu, bh = b >> 16;
    uint64_t mid = QIBL_CAST(uint64_t, al * bh) + (ah * bl); /* < 2^33 */
    return (QIBL_CAST(uint64_t, ah * bh) << 32) + (mid << 16) + (al * bl);
#endif
}

/* a * b exactly, for any int32 a, b (|a*b| <= 2^62, so it always fits). */
static inline int64_t qibl_mul_s32_s64(int32_t a, int32_t b)
{
#if QIBL_CONFIG_NATIVE_MUL64
    return QIBL_CAST(int64_t, a) * b;
#else
    /* magnitudes in unsigned arithmetic: -INT32_MIN does not exist as an int32 */
    uint32_t ua = a < 0 ? 0u - QIBL_CAST(uint32_t, a) : QIBL_CAST(uint32_t, a);
    uint32_t ub = b < 0 ? 0u - QIBL_CAST(uint32_t, b) : QIBL_CAST(uint32_t, b);
    int64_t p = QIBL_CAST(int64_t, qibl_mul_u32_u64(ua, ub)); /* <= 2^62: conversion is exact */
    return (a < 0) != (b < 0) ? -p : p;
#endif
}

/* ---- fixed-point multiply ------------------------------------------------------------------- */

/* a * b in Q16.16: round half up, saturated. Error <= 0.5 LSB when not saturated. */
static inline qibl_q16_t qibl_mul_q16(qibl_q16_t a, qibl_q16_t b)
{
    return qibl_rshr_s64(qibl_mul_s32_s64(a, b), 16);
}

/* a * b in Q2.30: round half up, saturated to [-2, 2 - 2^-30]. Error <= 0.5 LSB when not
 * saturated. */
static inline qibl_q30_t qibl_mul_q30(qibl_q30_t a, qibl_q30_t b)
{
    return qibl_rshr_s64(qibl_mul_s32_s64(a, b), 30);
}

/* ---- division, roots, normalisation (fixed.c) ----------------------------------------------- */

/* floor(n / d) for d != 0, any uint64 n; *rem (may be NULL) gets n mod d. Uses a native divide only
 * where QIBL_CONFIG_NATIVE_DIV64 says it is an instruction, else 64 shift-subtract steps.
 * Returns 0 and writes nothing for d == 0 (callers check d first; see qibl_recip_q16). */
uint64_t qibl_udiv_u64(uint64_t n, uint64_t d, uint64_t *rem);

/* floor(sqrt(x)) for any uint64 x, exact; *rem (may be NULL) gets x - floor(sqrt(x))^2. */
uint32_t qibl_isqrt_u64(uint64_t x, uint64_t *rem);

/* floor(sqrt(x)) for any uint32 x, exact. */
uint32_t qibl_isqrt_u32(uint32_t x);

/* sqrt(x) for x in UQ16.16, result in UQ16.16, correctly rounded (error <= 0.5 LSB; a tie cannot
 * occur). Never fails: the result is at most 256. */
qibl_uq16_t qibl_sqrt_uq16(qibl_uq16_t x);

/* 1/sqrt(x) for x in UQ16.16, result in UQ16.16 (at most 256 = 1/sqrt(2^-16)), correctly rounded.
 * Formats: x and *out UQ16.16.
 * Bound: error <= 0.5 LSB (a tie cannot occur).
 * Errors, in this order: QIBL_E_NULL_POINTER (out NULL), QIBL_E_DIV_BY_ZERO (x == 0).
 * On failure: nothing is written (*out untouched). */
QIBL_NODISCARD qibl_status_t qibl_rsqrt_uq16(qibl_uq16_t x, qibl_uq16_t *out);

/* 1/x for x in Q16.16, result in Q16.16, correctly rounded.
 * Formats: x and *out Q16.16.
 * Bound: error <= 0.5 LSB (ties cannot occur).
 * Errors, in this order: QIBL_E_NULL_POINTER (out NULL), QIBL_E_DIV_BY_ZERO (x == 0), QIBL_E_RANGE
 * (1/x does not fit Q16.16: x = 1 or 2 LSB, x = -1 LSB).
 * On failure: nothing is written (*out untouched). */
QIBL_NODISCARD qibl_status_t qibl_recip_q16(qibl_q16_t x, qibl_q16_t *out);

/* v / |v| for any int32 triple v, as a Q2.30 unit vector. v and out may alias.
 * Formats: v any common Q format (a direction only: int32 triple); out Q2.30.
 * Bound: error <= 1 LSB (2^-30) per component against the exact quotient, for every input
 * including components of 1 LSB and of INT32_MIN.
 * Errors, in this order: QIBL_E_NULL_POINTER (v or out NULL), QIBL_E_ZERO_VECTOR (v = (0, 0, 0)).
 * On failure: nothing is written (out untouched). */
QIBL_NODISCARD qibl_status_t qibl_vec3_normalize_q30(const int32_t v[3], qibl_q30_t out[3]);

/* 1/sqrt(x) for x >= 1, returned as y / 2^*e with y in [2^30, 2^31] and *e in 31..62.
 * Relative error <= 2^-28 (table seed + two Newton steps; measured bound in fixed_test.c).
 * x == 0 returns 0 with *e = 0. About 8 multiplies: the fast path for per-pixel normalisation. */
uint32_t qibl_rsqrt_u64(uint64_t x, unsigned *e);

/* v / |v| as a Q2.30 unit vector through qibl_rsqrt_u64, several times faster than
 * qibl_vec3_normalize_q30 where division is slow. Optionally returns 1/|v| as *len_y / 2^*len_e
 * (either pointer may be NULL), in the reciprocal of v's units.
 * Formats: v any common Q format (int32 triple); out Q2.30; *len_y / 2^*len_e as qibl_rsqrt_u64.
 * Bound: error <= 4 LSB (2^-28) per component; 1/|v| to qibl_rsqrt_u64's relative 2^-28.
 * Errors, in this order: QIBL_E_NULL_POINTER (v or out NULL), QIBL_E_ZERO_VECTOR (v = (0, 0, 0)).
 * On failure: nothing is written (out and the lengths untouched). */
QIBL_NODISCARD qibl_status_t qibl_vec3_normalize_fast_q30(const int32_t v[3], qibl_q30_t out[3], uint32_t *len_y,
                                           unsigned *len_e);

#ifdef __cplusplus
}
#endif

#endif /* QIBL_FIXED_H */
