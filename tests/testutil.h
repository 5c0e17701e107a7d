/*
 * testutil.h - shared helpers for the CMocka suites: a fixed-seed PRNG and guard-byte checks.
 * Include after <cmocka.h>.
 */
#ifndef QTOOL_TESTUTIL_H
#define QTOOL_TESTUTIL_H

#include <stdint.h>
#include <string.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* splitmix64: fixed seed in, same sequence on every platform */
typedef struct { uint64_t s; } tu_rng;

static inline uint64_t tu_next(tu_rng *r)
{
    uint64_t z = (r->s += 0x9E3779B97F4A7C15u);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9u;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBu;
    return z ^ (z >> 31);
}

static inline uint32_t tu_u32(tu_rng *r) { return (uint32_t)(tu_next(r) >> 32); }

static inline int32_t tu_s32(tu_rng *r)
{
    uint32_t u = tu_u32(r);
    int32_t v;
    memcpy(&v, &u, sizeof v); /* two's complement reinterpretation without a signed overflow */
    return v;
}

static inline int64_t tu_s64(tu_rng *r)
{
    uint64_t u = tu_next(r);
    int64_t v;
    memcpy(&v, &u, sizeof v);
    return v;
}

/* uniform double in [0, 1) */
static inline double tu_unit(tu_rng *r) { return (double)(tu_next(r) >> 11) * (1.0 / 9007199254740992.0); }

/* a uint32 with a random bit length: exercises small and large magnitudes equally */
static inline uint32_t tu_u32_any_width(tu_rng *r)
{
    unsigned bits = (unsigned)(tu_next(r) % 33u);
    uint32_t v = tu_u32(r);
    return bits == 0 ? 0u : bits == 32 ? v : v >> (32u - bits);
}

/* floor(x / 2^n) computed with C division (which truncates), n in 0..62 */
static inline int64_t tu_floor_div_pow2(int64_t x, unsigned n)
{
    int64_t d = (int64_t)1 << n;
    int64_t q = x / d;
    if (x % d != 0 && x < 0)
        q -= 1;
    return q;
}

#define TU_GUARD 0xA5
static inline void tu_fill_guard(void *p, size_t n) { memset(p, TU_GUARD, n); }
static inline int tu_guard_intact(const void *p, size_t n)
{
    const unsigned char *b = (const unsigned char *)p;
    for (size_t i = 0; i < n; ++i)
        if (b[i] != TU_GUARD)
            return 0;
    return 1;
}

#endif
