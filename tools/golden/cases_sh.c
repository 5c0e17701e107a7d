/*
 * golden/cases_sh.c - sh_*: the SH basis (bands 0..4, Q2.30) over integer direction sweeps: a
 * lattice of directions at 1-LSB and near-full-range scales, random directions of every bit width,
 * hard cases (axes, poles, INT32_MIN components, near-axis tilts, the zero vector), every band
 * count (valid or not), and the unit-vector entry point. Each entry records the status and the
 * output array, which starts as a guard pattern so that "nothing written on failure" is hashed too.
 */
#include "golden/casesi.h"

#include <limits.h>

#include "qibl/fixed.h"
#include "qibl/sh.h"

#if QIBL_USE_SH /* the group exists only when config.h builds the module */

#define GUARD 0x5A5A5A5Au

static void eval(qtool_gbuf *b, const int32_t d[3], int bands)
{
    qibl_q30_t out[QIBL_SH_MAX_COUNT];
    for (int i = 0; i < QIBL_SH_MAX_COUNT; ++i)
        out[i] = qtool_gs32(GUARD);
    qtool_gbuf_u8(b, (uint32_t)qibl_sh_eval(d, bands, out));
    for (int i = 0; i < QIBL_SH_MAX_COUNT; ++i)
        qtool_gbuf_s32(b, out[i]);
}

/* every lattice point of [-R, R]^3 but the origin, times scale */
static int lattice(const qtool_goldens_sink_t *s, const char *name, int32_t scale)
{
    enum { R = 5 };
    qtool_gbuf b = {0};
    for (int x = -R; x <= R; ++x)
        for (int y = -R; y <= R; ++y)
            for (int z = -R; z <= R; ++z) {
                if (x == 0 && y == 0 && z == 0)
                    continue;
                const int32_t d[3] = {x * scale, y * scale, z * scale};
                eval(&b, d, QIBL_SH_MAX_BANDS);
            }
    return qtool_gbuf_emit(s, name, &b);
}

static int32_t any_width_s32(qtool_grng *r)
{
    unsigned bits = (unsigned)(qtool_grng_next(r) % 33u);
    uint32_t v = qtool_grng_u32(r);
    uint32_t u = bits == 0 ? 0u : bits == 32 ? v : v >> (32u - bits);
    return qtool_grng_next(r) & 1u ? qtool_gs32(0u - u) : qtool_gs32(u);
}

static int random_dirs(const qtool_goldens_sink_t *s)
{
    qtool_gbuf b = {0};
    qtool_grng r = {0x5B};
    for (int i = 0; i < 3000; ++i) {
        int32_t d[3] = {any_width_s32(&r), any_width_s32(&r), any_width_s32(&r)};
        if (i % 3 == 0) /* same magnitude on every axis: the common case */
            d[0] = qtool_gs32(qtool_grng_u32(&r)), d[1] = qtool_gs32(qtool_grng_u32(&r)), d[2] = qtool_gs32(qtool_grng_u32(&r));
        eval(&b, d, QIBL_SH_MAX_BANDS);
    }
    return qtool_gbuf_emit(s, "sh_basis_random", &b);
}

static int hard_cases(const qtool_goldens_sink_t *s)
{
    static const int32_t mags[] = {1, 2, 3, 65536, 0x40000000, INT32_MAX};
    qtool_gbuf b = {0};
    const int32_t zero[3] = {0, 0, 0};
    eval(&b, zero, QIBL_SH_MAX_BANDS);
    for (size_t m = 0; m < sizeof mags / sizeof mags[0]; ++m)
        for (int axis = 0; axis < 3; ++axis)
            for (int sign = -1; sign <= 1; sign += 2) {
                int32_t d[3] = {0, 0, 0};
                d[axis] = sign * mags[m];
                eval(&b, d, QIBL_SH_MAX_BANDS);
                d[axis] = sign < 0 ? INT32_MIN : INT32_MAX; /* full range, and a 1-LSB tilt of it */
                d[(axis + 1) % 3] = 1;
                eval(&b, d, QIBL_SH_MAX_BANDS);
                d[(axis + 2) % 3] = -1;
                eval(&b, d, QIBL_SH_MAX_BANDS);
                d[(axis + 1) % 3] = mags[m];
                eval(&b, d, QIBL_SH_MAX_BANDS);
            }
    static const int32_t all[][3] = {
        {INT32_MIN, INT32_MIN, INT32_MIN}, {INT32_MAX, INT32_MIN, 0},      {INT32_MIN, 1, 1},
        {INT32_MAX, INT32_MAX, INT32_MAX}, {1, 1, 1},                      {-1, -1, -1},
        {1, -1, 0},                        {46341, 46341, 0},              {0x7FFF0000, -0x7FFF0000, 1},
        {3, 4, 12},                        {-0x10000, 0x20000, -0x20000},  {INT32_MIN, INT32_MAX, INT32_MIN},
    };
    for (size_t i = 0; i < sizeof all / sizeof all[0]; ++i)
        eval(&b, all[i], QIBL_SH_MAX_BANDS);
    /* band counts 0 .. QIBL_SH_MAX_BANDS + 1, valid or not */
    const int32_t d[3] = {40000, 25000, 52000};
    for (int bands = -1; bands <= QIBL_SH_MAX_BANDS + 1; ++bands)
        eval(&b, d, bands);
    return qtool_gbuf_emit(s, "sh_basis_hard", &b);
}

/* qibl_sh_eval_unit on Q2.30 unit vectors from both normalisations */
static int unit_dirs(const qtool_goldens_sink_t *s)
{
    qtool_gbuf b = {0};
    qtool_grng r = {0x0117};
    for (int i = 0; i < 1000; ++i) {
        int32_t d[3] = {any_width_s32(&r), any_width_s32(&r), any_width_s32(&r)};
        qibl_q30_t u[3];
        for (int fast = 0; fast < 2; ++fast) {
            qibl_status_t st = fast ? qibl_vec3_normalize_fast_q30(d, u, NULL, NULL) : qibl_vec3_normalize_q30(d, u);
            if (st != QIBL_OK)
                continue; /* the zero vector: covered by sh_basis_hard */
            qibl_q30_t out[QIBL_SH_MAX_COUNT];
            qtool_gbuf_u8(&b, (uint32_t)qibl_sh_eval_unit(u, QIBL_SH_MAX_BANDS, out));
            for (int k = 0; k < QIBL_SH_MAX_COUNT; ++k)
                qtool_gbuf_s32(&b, out[k]);
        }
    }
    return qtool_gbuf_emit(s, "sh_basis_unit", &b);
}

int qtool_goldens_sh(const qtool_goldens_sink_t *s)
{
    int bad = lattice(s, "sh_basis_lattice_lsb", 1);
    bad += lattice(s, "sh_basis_lattice_mid", 46341); /* about 2^15.5: inexact lengths */
    bad += lattice(s, "sh_basis_lattice_wide", 0x19999999); /* 5 * that is just below 2^31 */
    return bad + random_dirs(s) + hard_cases(s) + unit_dirs(s);
}

#else
typedef int qtool_goldens_sh_off; /* ISO C wants a declaration in every file */
#endif /* QIBL_USE_SH */
