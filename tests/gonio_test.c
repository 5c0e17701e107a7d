/*
 * gonio_test.c - core/src/gonio.c: every refusal named (size, table entry, zero aim, up zero or
 * parallel, span bounds) with the output untouched; a table of 1.0 leaves a span's bytes exactly
 * as they were; texel centres looked up within 1 LSB (a step of 30000 between neighbours); random directions against the bilinear
 * interpolation in double (<= 1 LSB plus the 2^-16 texel position); the frame from aim and up
 * (a rotated lamp sees the same table); the span's rounding (ties away from zero, sign kept).
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "qibl/gonio.h"
#include "testutil.h"

#define N 16
static uint16_t tab[N * N];

static void smooth_table(uint16_t *t, uint32_t n)
{
    for (uint32_t j = 0; j < n; ++j)
        for (uint32_t i = 0; i < n; ++i)
            t[j * n + i] = (uint16_t)(1000 + (i * 977u + j * 1531u + i * j * 37u) % 31000u);
}

static const int32_t Z[3] = {0, 0, 65536}, Y[3] = {0, 65536, 0};

static void test_refusals(void **state)
{
    (void)state;
    qibl_gonio_t g, before;
    memset(&g, 0x3C, sizeof g);
    before = g;
    for (uint32_t i = 0; i < N * N; ++i)
        tab[i] = QIBL_GONIO_ONE;
    assert_int_equal(qibl_gonio_init(NULL, N, tab, Z, Y), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_gonio_init(&g, N, NULL, Z, Y), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_gonio_init(&g, 1, tab, Z, Y), QIBL_E_GONIO_SIZE);
    assert_int_equal(qibl_gonio_init(&g, QIBL_GONIO_MAX_N + 1, tab, Z, Y), QIBL_E_GONIO_SIZE);
    assert_int_equal(qibl_gonio_table_size(1), 0);
    assert_int_equal(qibl_gonio_table_size(QIBL_GONIO_MAX_N), (size_t)QIBL_GONIO_MAX_N * QIBL_GONIO_MAX_N * 2);
    tab[7] = QIBL_GONIO_ONE + 1;
    assert_int_equal(qibl_gonio_init(&g, N, tab, Z, Y), QIBL_E_GONIO_TABLE);
    tab[7] = QIBL_GONIO_ONE;
    int32_t zero[3] = {0, 0, 0}, par[3] = {0, 0, -5}, near[3] = {1, 0, 65536 * 4};
    assert_int_equal(qibl_gonio_init(&g, N, tab, zero, Y), QIBL_E_GONIO_AIM);
    assert_int_equal(qibl_gonio_init(&g, N, tab, Z, zero), QIBL_E_GONIO_UP);
    assert_int_equal(qibl_gonio_init(&g, N, tab, Z, par), QIBL_E_GONIO_UP);
    assert_int_equal(qibl_gonio_init(&g, N, tab, Z, near), QIBL_E_GONIO_UP);
    assert_memory_equal(&g, &before, sizeof g);
    assert_string_not_equal(qibl_status_str(QIBL_E_GONIO_UP), "unknown status");
    assert_string_not_equal(qibl_status_str(QIBL_E_GONIO_BOUNDS), "unknown status");
    /* span bounds */
    assert_int_equal(qibl_gonio_init(&g, N, tab, Z, Y), QIBL_OK);
    uint8_t pts[12 * 4] = {0};
    qibl_pmap_t pm = {4, 1, pts};
    int32_t out[12], keep[12];
    for (int i = 0; i < 12; ++i)
        out[i] = keep[i] = i * 1000 - 5000;
    qibl_q16_t pos[3] = {0, 0, 0};
    assert_int_equal(qibl_gonio_scale_span(&g, &pm, pos, 1, 0, 4, out), QIBL_E_GONIO_BOUNDS);
    assert_int_equal(qibl_gonio_scale_span(&g, &pm, pos, 0, 1, 1, out), QIBL_E_GONIO_BOUNDS);
    assert_int_equal(qibl_gonio_scale_span(&g, &pm, pos, 5, 0, 0, out), QIBL_E_GONIO_BOUNDS);
    assert_int_equal(qibl_gonio_scale_span(&g, NULL, pos, 0, 0, 1, out), QIBL_E_NULL_POINTER);
    assert_memory_equal(out, keep, sizeof out);
}

/* the unit direction of texel centre (i, j) (the octahedral inverse, gonio.h) */
static void texel_dir(uint32_t i, uint32_t j, uint32_t n, double d[3])
{
    double u = (2.0 * i + 1) / n - 1, v = (2.0 * j + 1) / n - 1, z = 1 - fabs(u) - fabs(v);
    if (z < 0) {
        double uu = (1 - fabs(v)) * (u < 0 ? -1 : 1), vv = (1 - fabs(u)) * (v < 0 ? -1 : 1);
        u = uu, v = vv;
    }
    double l = sqrt(u * u + v * v + z * z);
    d[0] = u / l, d[1] = v / l, d[2] = z / l;
}

/* the bilinear value in double at unit direction d (same mapping and clamping) */
static double ref_lookup(const uint16_t *t, uint32_t n, const double d[3])
{
    double s = fabs(d[0]) + fabs(d[1]) + fabs(d[2]), u = d[0] / s, v = d[1] / s;
    if (d[2] < 0) {
        double uu = (1 - fabs(v)) * (u < 0 ? -1 : 1), vv = (1 - fabs(u)) * (v < 0 ? -1 : 1);
        u = uu, v = vv;
    }
    double fx = (u + 1) / 2 * n - 0.5, fy = (v + 1) / 2 * n - 0.5;
    fx = fx < 0 ? 0 : fx > n - 1 ? n - 1 : fx;
    fy = fy < 0 ? 0 : fy > n - 1 ? n - 1 : fy;
    uint32_t i0 = (uint32_t)fx, j0 = (uint32_t)fy, i1 = i0 + 1 < n ? i0 + 1 : i0, j1 = j0 + 1 < n ? j0 + 1 : j0;
    double tx = fx - i0, ty = fy - j0;
    double a = t[j0 * n + i0] * (1 - tx) + t[j0 * n + i1] * tx, b = t[j1 * n + i0] * (1 - tx) + t[j1 * n + i1] * tx;
    return a * (1 - ty) + b * ty;
}

static void to_i64(const double d[3], double len, int64_t o[3])
{
    for (int k = 0; k < 3; ++k)
        o[k] = (int64_t)llround(d[k] * len);
}

static void test_centres_and_random(void **state)
{
    (void)state;
    smooth_table(tab, N);
    qibl_gonio_t g;
    assert_int_equal(qibl_gonio_init(&g, N, tab, Z, Y), QIBL_OK);
    for (uint32_t j = 0; j < N; ++j)
        for (uint32_t i = 0; i < N; ++i) {
            double d[3];
            int64_t q[3];
            texel_dir(i, j, N, d);
            to_i64(d, 1e9, q);
            /* the centre, or 2^-16 texel beside it after the direction's rounding: within 1 LSB */
            int e = abs((int)qibl_gonio_lookup(&g, q) - (int)tab[j * N + i]);
            assert_true(e <= 1);
        }
    tu_rng r = {42};
    double maxe = 0;
    for (int t = 0; t < 20000; ++t) {
        double d[3] = {tu_unit(&r) * 2 - 1, tu_unit(&r) * 2 - 1, tu_unit(&r) * 2 - 1};
        double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (l < 1e-3)
            continue;
        d[0] /= l, d[1] /= l, d[2] /= l;
        int64_t q[3];
        /* lengths from 2^-10 to 2^60 scene units: only the direction counts */
        double len = ldexp(1.0, (int)(tu_u32(&r) % 50u) + 10);
        to_i64(d, len, q);
        /* the reference at the direction the integers actually hold */
        double dq[3] = {(double)q[0], (double)q[1], (double)q[2]};
        double lq = sqrt(dq[0] * dq[0] + dq[1] * dq[1] + dq[2] * dq[2]);
        if (lq == 0)
            continue;
        dq[0] /= lq, dq[1] /= lq, dq[2] /= lq;
        double want = ref_lookup(tab, N, dq);
        double e = fabs((double)qibl_gonio_lookup(&g, q) - want);
        maxe = e > maxe ? e : maxe;
    }
    /* 0.5 LSB rounding plus the position's 2^-16 texel and the direction's reduction to 2^24 per
     * component, times texel steps up to 30000 */
    printf("  max |lookup - bilinear in double| = %.2f LSB\n", maxe);
    assert_true(maxe <= 2);
    int64_t zero[3] = {0, 0, 0};
    assert_int_equal(qibl_gonio_lookup(&g, zero), (uint32_t)lround(ref_lookup(tab, N, (double[3]){0, 0, 1})));
}

static void test_frame(void **state)
{
    (void)state;
    smooth_table(tab, N);
    qibl_gonio_t id, rot;
    /* aim +x, up +z: lamp z = world x, lamp y = world z, lamp x = y cross z = world y */
    int32_t aim[3] = {3 * 65536, 0, 0}, up[3] = {5 * 65536, 0, 65536}; /* up's part along the aim is removed */
    assert_int_equal(qibl_gonio_init(&id, N, tab, Z, Y), QIBL_OK);
    assert_int_equal(qibl_gonio_init(&rot, N, tab, aim, up), QIBL_OK);
    tu_rng r = {9};
    int worst = 0;
    for (int t = 0; t < 5000; ++t) {
        double d[3] = {tu_unit(&r) * 2 - 1, tu_unit(&r) * 2 - 1, tu_unit(&r) * 2 - 1};
        int64_t local[3], world[3];
        to_i64(d, 1e6, local);
        world[0] = local[2], world[1] = local[0], world[2] = local[1];
        int e = abs((int)qibl_gonio_lookup(&rot, world) - (int)qibl_gonio_lookup(&id, local));
        worst = e > worst ? e : worst;
    }
    assert_true(worst <= 16);
}

static void test_span(void **state)
{
    (void)state;
    /* a table of 1.0: the span untouched, whatever the values */
    for (uint32_t i = 0; i < N * N; ++i)
        tab[i] = QIBL_GONIO_ONE;
    qibl_gonio_t g;
    assert_int_equal(qibl_gonio_init(&g, N, tab, Z, Y), QIBL_OK);
    enum { W = 8 };
    uint8_t pts[12 * W];
    tu_rng r = {5};
    for (size_t i = 0; i < sizeof pts; ++i)
        pts[i] = (uint8_t)tu_u32(&r);
    qibl_pmap_t pm = {W, 1, pts};
    int32_t out[3 * W], keep[3 * W];
    for (int i = 0; i < 3 * W; ++i)
        out[i] = keep[i] = tu_s32(&r);
    qibl_q16_t pos[3] = {tu_s32(&r), tu_s32(&r), tu_s32(&r)};
    assert_int_equal(qibl_gonio_scale_span(&g, &pm, pos, 0, 0, W, out), QIBL_OK);
    assert_memory_equal(out, keep, sizeof out);
    /* a table of 0.5 everywhere: each value halved, ties away from zero, sign kept */
    for (uint32_t i = 0; i < N * N; ++i)
        tab[i] = QIBL_GONIO_ONE / 2;
    int32_t v[3 * W] = {3, -3, 1, -1, 0, 2147483647, -2147483647 - 1, 5, -5};
    int32_t want[3 * W] = {2, -2, 1, -1, 0, 1073741824, -1073741824, 3, -3};
    assert_int_equal(qibl_gonio_scale_span(&g, &pm, pos, 0, 0, 3, v), QIBL_OK);
    assert_memory_equal(v, want, sizeof(int32_t) * 9);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_centres_and_random),
        cmocka_unit_test(test_frame),
        cmocka_unit_test(test_span),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
