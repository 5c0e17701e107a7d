/*
 * sh_test.c - qibl/sh.h against the double reference written from Wong et al.'s appendix
 * (tools/ref/sh_ref.c: theta, phi, recursive Q(l,m)), over a 10^6-direction fixed-seed sweep and the
 * hard cases; orthonormality by exact quadrature; errors and output bounds. Rotation (bands 0..4)
 * against a double reference that integrates rotated basis functions (tools/ref/probe_ref.c), the
 * sample table's left-inverse property, composition, directional lights, and its errors.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "qibl/sh.h"
#include "ref/probe_ref.h"
#include "ref/sh_ref.h"
#include "testutil.h"

#define Q30 1073741824.0
#define GOAL (1.0 / 16384.0) /* the goal, 2^-14 */
#define BOUND (1.0 / 33554432.0) /* what sh.h promises, 2^-25 */

typedef struct {
    double max_err[25];
    long n;
} err_stats;

/* Evaluate core and reference at v and fold |difference| into st; returns the worst of this call. */
static double compare(const int32_t v[3], err_stats *st)
{
    qibl_q30_t y[25 + 1];
    double ref[25];
    y[25] = 0x1BADB002;
    assert_int_equal(qibl_sh_eval(v, 5, y), QIBL_OK);
    assert_int_equal(y[25], 0x1BADB002); /* nothing written past bands^2 */
    assert_int_equal(qtool_ref_sh_eval(v[0], v[1], v[2], 5, ref), 0);
    double worst = 0.0;
    for (int i = 0; i < 25; ++i) {
        double e = fabs(y[i] / Q30 - ref[i]);
        if (e > st->max_err[i])
            st->max_err[i] = e;
        if (e > worst)
            worst = e;
    }
    st->n++;
    return worst;
}

static double stats_max(const err_stats *st)
{
    double m = 0.0;
    for (int i = 0; i < 25; ++i)
        if (st->max_err[i] > m)
            m = st->max_err[i];
    return m;
}

static void to_int(double x, double y, double z, double len, int32_t v[3])
{
    v[0] = (int32_t)lrint(x * len);
    v[1] = (int32_t)lrint(y * len);
    v[2] = (int32_t)lrint(z * len);
}

static void test_sweep_million_directions(void **state)
{
    (void)state;
    err_stats st = {{0}, 0};
    tu_rng r = {0x5eed};
    while (st.n < 1000000) {
        double z = 2.0 * tu_unit(&r) - 1.0, p = 2.0 * M_PI * tu_unit(&r);
        double s = sqrt(1.0 - z * z);
        double len = pow(2.0, 30.99 * tu_unit(&r)); /* 1 LSB .. ~2^31 */
        int32_t v[3];
        to_int(s * cos(p), s * sin(p), z, len, v);
        if (v[0] == 0 && v[1] == 0 && v[2] == 0)
            continue;
        compare(v, &st);
    }
    double m = stats_max(&st);
    printf("sh: max |Y_core - Y_ref| over %ld directions = %.3e = 2^%.2f (goal 2^-14, bound 2^-25)\n", st.n, m,
           log2(m));
    printf("sh: per basis function (x 2^-30):");
    for (int i = 0; i < 25; ++i)
        printf(" %.1f", st.max_err[i] * Q30);
    printf("\n");
    assert_true(m <= BOUND);
    assert_true(m <= GOAL);
}

static void test_hard_cases(void **state)
{
    (void)state;
    err_stats st = {{0}, 0};
    /* poles and axes at every length from 1 LSB to INT32_MIN */
    for (int e = 0; e <= 31; ++e) {
        int64_t k = (int64_t)1 << e;
        int32_t a = k > INT32_MAX ? INT32_MAX : (int32_t)k;
        int32_t b = (int32_t)-k; /* reaches INT32_MIN at e = 31 */
        const int32_t axes[6][3] = {{a, 0, 0}, {b, 0, 0}, {0, a, 0}, {0, b, 0}, {0, 0, a}, {0, 0, b}};
        for (int i = 0; i < 6; ++i)
            assert_true(compare(axes[i], &st) <= BOUND);
        /* at the poles every m != 0 function is exactly zero */
        qibl_q30_t y[25];
        assert_int_equal(qibl_sh_eval(axes[4], 5, y), QIBL_OK);
        for (int l = 1; l < 5; ++l)
            for (int m = -l; m <= l; ++m)
                if (m != 0)
                    assert_int_equal(y[l * l + l + m], 0);
    }
    /* the equator, 3600 longitudes, unit and huge */
    for (int i = 0; i < 3600; ++i) {
        double p = i * (2.0 * M_PI / 3600.0);
        int32_t v[3];
        to_int(cos(p), sin(p), 0.0, 1073741824.0, v);
        assert_true(compare(v, &st) <= BOUND);
        to_int(cos(p), sin(p), 0.0, 65536.0, v);
        assert_true(compare(v, &st) <= BOUND);
    }
    /* 1e-6 rad (and 1e-5, 1e-7) from either pole, at many longitudes: needs a long vector to be
     * representable at all (1e-6 of 2^31 is ~2000 LSB) */
    const double eps[] = {1e-5, 1e-6, 1e-7};
    for (int k = 0; k < 3; ++k)
        for (int i = 0; i < 360; ++i) {
            double p = i * (2.0 * M_PI / 360.0), t = eps[k];
            int32_t v[3];
            to_int(sin(t) * cos(p), sin(t) * sin(p), cos(t), 2147483000.0, v);
            assert_true(compare(v, &st) <= BOUND);
            to_int(sin(t) * cos(p), sin(t) * sin(p), -cos(t), 2147483000.0, v);
            assert_true(compare(v, &st) <= BOUND);
        }
    /* tiny and huge non-unit vectors, diagonals, extremes */
    const int32_t odd[][3] = {
        {1, 1, 1}, {-1, 1, -1}, {1, -1, 0}, {1, 0, 1}, {0, 1, -1}, {2, 1, 0}, {1, 2, 3},
        {INT32_MAX, INT32_MAX, INT32_MAX}, {INT32_MIN, INT32_MIN, INT32_MIN}, {INT32_MIN, INT32_MAX, 0},
        {INT32_MAX, 1, 0}, {1, 0, INT32_MIN}, {INT32_MIN, 1, 1}, {3, 4, 12}, {-65536, 65536, 65536},
    };
    for (size_t i = 0; i < sizeof odd / sizeof odd[0]; ++i)
        assert_true(compare(odd[i], &st) <= BOUND);
    double m = stats_max(&st);
    printf("sh: hard cases (poles, axes, equator, 1e-7..1e-5 rad from poles, 1 LSB..INT32_MIN lengths): "
           "%ld directions, max |error| = %.3e = 2^%.2f\n", st.n, m, log2(m));
}

/* The convention written in sh.h, checked by value (catches a flipped sign or swapped m). */
static void test_convention(void **state)
{
    (void)state;
    const double c0 = 0.28209479177387814, c1 = 0.4886025119029199;
    qibl_q30_t y[25];
    const int32_t px[3] = {QIBL_Q16_ONE, 0, 0}, py[3] = {0, QIBL_Q16_ONE, 0}, pz[3] = {0, 0, QIBL_Q16_ONE};
    assert_int_equal(qibl_sh_eval(px, 2, y), QIBL_OK);
    assert_true(fabs(y[0] / Q30 - c0) < 1e-8);
    assert_true(fabs(y[3] / Q30 + c1) < 1e-8); /* Y(1,1) = -c x: Condon-Shortley phase */
    assert_true(y[1] == 0 && y[2] == 0);
    assert_int_equal(qibl_sh_eval(py, 2, y), QIBL_OK);
    assert_true(fabs(y[1] / Q30 + c1) < 1e-8); /* Y(1,-1) = -c y */
    assert_int_equal(qibl_sh_eval(pz, 2, y), QIBL_OK);
    assert_true(fabs(y[2] / Q30 - c1) < 1e-8); /* Y(1,0) = c z */
}

/* Gauss-Legendre nodes in z (exact for degree <= 2n-1) x uniform phi (exact for trig degree < nphi):
 * Y_i Y_j has degree <= 8 in each, so the quadrature is exact up to the basis's own error. */
static void gauss_legendre(int n, double *x, double *w)
{
    for (int i = 0; i < n; ++i) {
        double z = cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 1.0;
        for (int it = 0; it < 100; ++it) {
            double p0 = 1.0, p1 = z;
            for (int k = 2; k <= n; ++k) {
                double p2 = ((2.0 * k - 1) * z * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            dp = n * (z * p1 - p0) / (z * z - 1.0);
            double dz = p1 / dp;
            z -= dz;
            if (fabs(dz) < 1e-16)
                break;
        }
        x[i] = z;
        w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
    }
}

static void test_orthonormality(void **state)
{
    (void)state;
    enum { NZ = 12, NP = 24 };
    double zx[NZ], zw[NZ], g[25][25] = {{0}};
    gauss_legendre(NZ, zx, zw);
    for (int a = 0; a < NZ; ++a)
        for (int b = 0; b < NP; ++b) {
            double p = (b + 0.5) * (2.0 * M_PI / NP), s = sqrt(1.0 - zx[a] * zx[a]);
            int32_t v[3];
            to_int(s * cos(p), s * sin(p), zx[a], 1073741824.0, v);
            qibl_q30_t y[25];
            assert_int_equal(qibl_sh_eval(v, 5, y), QIBL_OK);
            double w = zw[a] * (2.0 * M_PI / NP);
            for (int i = 0; i < 25; ++i)
                for (int j = 0; j < 25; ++j)
                    g[i][j] += w * (y[i] / Q30) * (y[j] / Q30);
        }
    double worst = 0.0;
    for (int i = 0; i < 25; ++i)
        for (int j = 0; j < 25; ++j) {
            double e = fabs(g[i][j] - (i == j ? 1.0 : 0.0));
            if (e > worst)
                worst = e;
        }
    printf("sh: orthonormality, max |<Y_i,Y_j> - delta_ij| = %.3e (%d x %d Gauss-Legendre x uniform)\n", worst, NZ,
           NP);
    assert_true(worst < 1e-6);
}

static void test_bands_prefix_and_output_size(void **state)
{
    (void)state;
    const int32_t v[3] = {12345, -67890, 23456};
    qibl_q30_t full[25];
    assert_int_equal(qibl_sh_eval(v, 5, full), QIBL_OK);
    for (int b = 1; b <= 5; ++b) {
        qibl_q30_t y[26];
        tu_fill_guard(y, sizeof y);
        assert_int_equal(qibl_sh_eval(v, b, y), QIBL_OK);
        for (int i = 0; i < b * b; ++i)
            assert_int_equal(y[i], full[i]); /* lower bands do not depend on how many are asked */
        assert_true(tu_guard_intact(&y[b * b], sizeof y - (size_t)(b * b) * sizeof y[0]));
    }
}

static void test_errors_write_nothing(void **state)
{
    (void)state;
    qibl_q30_t y[25];
    const int32_t zero[3] = {0, 0, 0}, v[3] = {1, 2, 3};
    tu_fill_guard(y, sizeof y);
    assert_int_equal(qibl_sh_eval(zero, 5, y), QIBL_E_ZERO_VECTOR);
    assert_int_equal(qibl_sh_eval(v, 0, y), QIBL_E_BAD_BANDS);
    assert_int_equal(qibl_sh_eval(v, 6, y), QIBL_E_BAD_BANDS);
    assert_int_equal(qibl_sh_eval(v, -1, y), QIBL_E_BAD_BANDS);
    assert_int_equal(qibl_sh_eval(0, 5, y), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_sh_eval(v, 5, 0), QIBL_E_NULL_POINTER);
    const qibl_q30_t u[3] = {0, 0, QIBL_Q30_ONE};
    assert_int_equal(qibl_sh_eval_unit(u, 9, y), QIBL_E_BAD_BANDS);
    assert_int_equal(qibl_sh_eval_unit(0, 5, y), QIBL_E_NULL_POINTER);
    assert_true(tu_guard_intact(y, sizeof y));
}

static void test_unit_entry_matches(void **state)
{
    (void)state;
    tu_rng r = {77};
    for (int k = 0; k < 10000; ++k) {
        int32_t v[3] = {tu_s32(&r), tu_s32(&r), tu_s32(&r)};
        qibl_q30_t u[3], a[25], b[25];
        assert_int_equal(qibl_vec3_normalize_q30(v, u), QIBL_OK);
        assert_int_equal(qibl_sh_eval(v, 5, a), QIBL_OK);
        assert_int_equal(qibl_sh_eval_unit(u, 5, b), QIBL_OK);
        assert_memory_equal(a, b, sizeof a);
    }
}

/* ---- rotation ------------------------------------------------------------------------------ */

#define ROT_BOUND (1.0 / 16777216.0) /* sh.h: each D entry within 2^-24 */

/* rotation matrix of a unit quaternion (w, x, y, z) in double and rounded to Q2.30 */
static void quat_matrix(double w, double x, double y, double z, double r[3][3], qibl_q30_t q[3][3])
{
    double n = sqrt(w * w + x * x + y * y + z * z);
    w /= n, x /= n, y /= n, z /= n;
    double m[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                      {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                      {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            q[i][j] = (int32_t)lrint(m[i][j] * Q30);
            r[i][j] = q[i][j] / Q30; /* the reference rotates by exactly what the core was given */
        }
}

static double rotation_error(double w, double x, double y, double z)
{
    double r[3][3], ref[165];
    qibl_q30_t q[3][3];
    quat_matrix(w, x, y, z, r, q);
    qibl_sh_rotation_t rot;
    assert_int_equal(qibl_sh_rotation_init(&rot, (const qibl_q30_t(*)[3])q, 5), QIBL_OK);
    qtool_ref_sh_rotation(r, 5, ref);
    double worst = 0.0;
    for (int i = 0; i < 165; ++i)
        worst = fmax(worst, fabs(rot.d[i] / Q30 - ref[i]));
    return worst;
}

static void test_rotation_against_reference(void **state)
{
    (void)state;
    const double h = sqrt(0.5);
    /* identity and the quarter / half turns about each axis */
    double worst = rotation_error(1, 0, 0, 0);
    static const double axes[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int a = 0; a < 3; ++a) {
        worst = fmax(worst, rotation_error(h, h * axes[a][0], h * axes[a][1], h * axes[a][2]));
        worst = fmax(worst, rotation_error(0, axes[a][0], axes[a][1], axes[a][2]));
        worst = fmax(worst, rotation_error(h, -h * axes[a][0], -h * axes[a][1], -h * axes[a][2]));
    }
    tu_rng r = {4242};
    for (int k = 0; k < 300; ++k) {
        double q[4];
        for (int i = 0; i < 4; ++i)
            q[i] = 2.0 * tu_unit(&r) - 1.0;
        worst = fmax(worst, rotation_error(q[0], q[1], q[2], q[3]));
    }
    printf("sh rotation: max |D - D_ref| over 310 rotations %.3e (bound 2^-24 = %.3e)\n", worst, ROT_BOUND);
    assert_true(worst <= ROT_BOUND);
}

/* the identity gives D = I within the bound, and rotate(in) = in within 1 LSB + the bound */
static void test_rotation_identity_and_lights(void **state)
{
    (void)state;
    double r[3][3];
    qibl_q30_t q[3][3];
    quat_matrix(0.8, 0.1, -0.5, 0.3, r, q);
    qibl_sh_rotation_t rot;
    assert_int_equal(qibl_sh_rotation_init(&rot, (const qibl_q30_t(*)[3])q, 5), QIBL_OK);
    /* a directional light: Y(d) rotates to Y(r d) */
    tu_rng g = {99};
    double worst = 0.0;
    for (int k = 0; k < 1000; ++k) {
        double d[3] = {tu_unit(&g) - 0.5, tu_unit(&g) - 0.5, tu_unit(&g) - 0.5}, rd[3], y[25];
        int32_t dq[3], in[25], out[25];
        for (int i = 0; i < 3; ++i)
            dq[i] = (int32_t)lrint(d[i] * 65536.0);
        assert_int_equal(qibl_sh_eval(dq, 5, in), QIBL_OK);
        for (int i = 0; i < 3; ++i)
            rd[i] = r[i][0] * dq[0] + r[i][1] * dq[1] + r[i][2] * dq[2];
        assert_int_equal(qtool_ref_sh_eval(rd[0], rd[1], rd[2], 5, y), 0);
        assert_int_equal(qibl_sh_rotate(&rot, in, out), QIBL_OK);
        for (int i = 0; i < 25; ++i)
            worst = fmax(worst, fabs(out[i] / Q30 - y[i]));
    }
    printf("sh rotation: directional light Y(d) -> Y(r d), max error %.3e\n", worst);
    assert_true(worst <= 3.0 * ROT_BOUND + 2.0 * BOUND);
    /* identity: exactly the input within 1 LSB + 3 * 2^-24 of full scale */
    quat_matrix(1, 0, 0, 0, r, q);
    assert_int_equal(qibl_sh_rotation_init(&rot, (const qibl_q30_t(*)[3])q, 5), QIBL_OK);
    int32_t in[25], out[25];
    for (int i = 0; i < 25; ++i)
        in[i] = tu_s32(&g) / 2;
    assert_int_equal(qibl_sh_rotate(&rot, in, out), QIBL_OK);
    for (int i = 0; i < 25; ++i)
        assert_true(fabs((double)out[i] - in[i]) <= 1.0 + 3.0 * ROT_BOUND * 1073741824.0);
}

/* composition: rotating by a then by b is rotating by b a (within the bound of three rotations) */
static void test_rotation_composition(void **state)
{
    (void)state;
    double ra[3][3], rb[3][3], rc[3][3];
    qibl_q30_t qa[3][3], qb[3][3], qc[3][3];
    quat_matrix(0.3, 0.9, -0.2, 0.1, ra, qa);
    quat_matrix(-0.6, 0.2, 0.7, 0.4, rb, qb);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            rc[i][j] = rb[i][0] * ra[0][j] + rb[i][1] * ra[1][j] + rb[i][2] * ra[2][j];
            qc[i][j] = (int32_t)lrint(rc[i][j] * Q30);
        }
    qibl_sh_rotation_t a, b, c;
    assert_int_equal(qibl_sh_rotation_init(&a, (const qibl_q30_t(*)[3])qa, 5), QIBL_OK);
    assert_int_equal(qibl_sh_rotation_init(&b, (const qibl_q30_t(*)[3])qb, 5), QIBL_OK);
    assert_int_equal(qibl_sh_rotation_init(&c, (const qibl_q30_t(*)[3])qc, 5), QIBL_OK);
    tu_rng g = {5};
    int32_t in[25], t[25], o1[25], o2[25];
    for (int i = 0; i < 25; ++i)
        in[i] = (int32_t)(tu_s32(&g) / 4);
    assert_int_equal(qibl_sh_rotate(&a, in, t), QIBL_OK);
    assert_int_equal(qibl_sh_rotate(&b, t, o1), QIBL_OK);
    assert_int_equal(qibl_sh_rotate(&c, in, o2), QIBL_OK);
    for (int i = 0; i < 25; ++i)
        assert_true(fabs((double)o1[i] - o2[i]) <= 2.0 + 9.0 * ROT_BOUND * 536870912.0 * 3.0);
}

/* The sample table: pinv_l is a left inverse of the band's basis at the sample directions, so
 * sum_k pinv_l[m][k] Y_lm'(n_k) = delta within rounding. Checked through the core itself: the
 * rotation by the identity is D = pinv Y(n), so this is the same property, measured entry by entry. */
static void test_rotation_table_left_inverse(void **state)
{
    (void)state;
    qibl_q30_t q[3][3] = {{1 << 30, 0, 0}, {0, 1 << 30, 0}, {0, 0, 1 << 30}};
    qibl_sh_rotation_t rot;
    assert_int_equal(qibl_sh_rotation_init(&rot, (const qibl_q30_t(*)[3])q, 5), QIBL_OK);
    int off = 0;
    double worst = 0.0;
    for (int l = 0; l < 5; ++l) {
        int n = 2 * l + 1;
        for (int m = 0; m < n; ++m)
            for (int mp = 0; mp < n; ++mp)
                worst = fmax(worst, fabs(rot.d[off + m * n + mp] / Q30 - (m == mp)));
        off += n * n;
    }
    printf("sh rotation: identity gives I within %.3e\n", worst);
    assert_true(worst <= ROT_BOUND);
}

/* full-range entries (found by fuzz_probe): the sum of three products overflowed int64 in the
 * orthonormality check (undefined behaviour, caught by make test-asan); now refused, rot untouched */
static void test_rotation_full_range_entries(void **state)
{
    (void)state;
    const int32_t vals[3] = {INT32_MIN, INT32_MAX, -(1 << 30) - (1 << 16)};
    for (int t = 0; t < 3; ++t) {
        qibl_q30_t q[3][3];
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                q[i][j] = vals[t];
        qibl_sh_rotation_t rot;
        memset(&rot, 0x5A, sizeof rot);
        assert_int_equal(qibl_sh_rotation_init(&rot, (const qibl_q30_t(*)[3])q, 5), QIBL_E_SH_ROTATION);
        assert_int_equal(rot.bands, 0x5A5A5A5A);
    }
}

static void test_rotation_errors(void **state)
{
    (void)state;
    qibl_q30_t q[3][3] = {{1 << 30, 0, 0}, {0, 1 << 30, 0}, {0, 0, 1 << 30}};
    qibl_sh_rotation_t rot;
    rot.bands = 123;
    rot.d[0] = 77;
    assert_int_equal(qibl_sh_rotation_init(NULL, (const qibl_q30_t(*)[3])q, 5), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_sh_rotation_init(&rot, NULL, 5), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_sh_rotation_init(&rot, (const qibl_q30_t(*)[3])q, 0), QIBL_E_BAD_BANDS);
    assert_int_equal(qibl_sh_rotation_init(&rot, (const qibl_q30_t(*)[3])q, 6), QIBL_E_BAD_BANDS);
    q[1][1] = -(1 << 30); /* a reflection: orthonormal, det -1 */
    assert_int_equal(qibl_sh_rotation_init(&rot, (const qibl_q30_t(*)[3])q, 5), QIBL_E_SH_ROTATION);
    q[1][1] = (1 << 30) + (1 << 15); /* scaled by 1 + 2^-15: beyond the 2^-16 tolerance */
    assert_int_equal(qibl_sh_rotation_init(&rot, (const qibl_q30_t(*)[3])q, 5), QIBL_E_SH_ROTATION);
    q[1][1] = 1 << 30, q[0][2] = 1 << 20; /* a shear */
    assert_int_equal(qibl_sh_rotation_init(&rot, (const qibl_q30_t(*)[3])q, 5), QIBL_E_SH_ROTATION);
    q[0][2] = 1 << 12; /* within the tolerance: accepted */
    assert_int_equal(rot.bands, 123);
    assert_int_equal(rot.d[0], 77);
    assert_int_equal(qibl_sh_rotation_init(&rot, (const qibl_q30_t(*)[3])q, 3), QIBL_OK);
    int32_t in[25] = {0}, out[25];
    out[9] = 0x5A5A5A5A;
    assert_int_equal(qibl_sh_rotate(&rot, in, out), QIBL_OK);
    assert_int_equal(out[9], 0x5A5A5A5A); /* 3 bands: 9 outputs */
    assert_int_equal(qibl_sh_rotate(NULL, in, out), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_sh_rotate(&rot, NULL, out), QIBL_E_NULL_POINTER);
    rot.bands = 0;
    assert_int_equal(qibl_sh_rotate(&rot, in, out), QIBL_E_BAD_BANDS);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_convention),
        cmocka_unit_test(test_sweep_million_directions),
        cmocka_unit_test(test_hard_cases),
        cmocka_unit_test(test_orthonormality),
        cmocka_unit_test(test_bands_prefix_and_output_size),
        cmocka_unit_test(test_errors_write_nothing),
        cmocka_unit_test(test_unit_entry_matches),
        cmocka_unit_test(test_rotation_against_reference),
        cmocka_unit_test(test_rotation_identity_and_lights),
        cmocka_unit_test(test_rotation_composition),
        cmocka_unit_test(test_rotation_table_left_inverse),
        cmocka_unit_test(test_rotation_errors),
        cmocka_unit_test(test_rotation_full_range_entries),
    };
    return cmocka_run_group_tests_name(QIBL_CONFIG_NATIVE_MUL64 ? "sh (native paths)" : "sh (portable M0 paths)", tests,
                                       NULL, NULL);
}
