/*
 * simplify_test.c - the coarse mesh of the hemi hierarchy (tools/gen/simplify.c): a flat grid keeps
 * its outline and orientation, a closed sphere stays closed and keeps its volume, targets at or
 * above the count change nothing, degenerate triangles are dropped, and every coarse triangle
 * indexes the original vertices.
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

#include "gen/simplify.h"

static void normal(const double *p, const uint32_t *t, double n[3])
{
    const double *a = p + 3 * t[0], *b = p + 3 * t[1], *c = p + 3 * t[2];
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    n[0] = u[1] * w[2] - u[2] * w[1], n[1] = u[2] * w[0] - u[0] * w[2], n[2] = u[0] * w[1] - u[1] * w[0];
}

static void test_grid_keeps_outline_and_orientation(void **state)
{
    (void)state;
    enum { G = 17 };
    static double p[G * G * 3];
    static uint32_t t[2 * (G - 1) * (G - 1)][3];
    uint32_t nt = 0;
    for (int j = 0; j < G; ++j)
        for (int i = 0; i < G; ++i)
            p[3 * (j * G + i)] = i, p[3 * (j * G + i) + 1] = j, p[3 * (j * G + i) + 2] = 0;
    for (int j = 0; j + 1 < G; ++j)
        for (int i = 0; i + 1 < G; ++i) {
            const uint32_t a = (uint32_t)(j * G + i), b = a + 1, c = a + G, d = c + 1;
            t[nt][0] = a, t[nt][1] = b, t[nt][2] = d, ++nt;
            t[nt][0] = a, t[nt][1] = d, t[nt][2] = c, ++nt;
        }
    uint32_t(*out)[3] = NULL, n = 0;
    assert_int_equal(qtool_simplify(p, G * G, (const uint32_t(*)[3])t, nt, 100, &out, &n), 0);
    assert_true(n <= 100 && n >= 2);
    double area = 0;
    for (uint32_t k = 0; k < n; ++k) {
        double nn[3];
        for (int c = 0; c < 3; ++c)
            assert_true(out[k][c] < G * G);
        normal(p, out[k], nn);
        assert_true(nn[2] > 0); /* nothing folded over */
        area += nn[2] / 2;
    }
    assert_true(fabs(area - (G - 1) * (G - 1)) < 1e-9); /* the square's border stayed where it was */
    free(out);
}

/* an icosphere-like closed mesh: an octahedron subdivided twice, pushed onto the unit sphere */
static uint32_t sphere(double *p, uint32_t (*t)[3])
{
    static const double o[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    static const uint32_t f[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    uint32_t nv = 0, nt = 0;
    /* subdivide each face into 16 by barycentric grid points (N = 4), duplicates welded by value */
    enum { N = 4 };
    for (int k = 0; k < 8; ++k) {
        uint32_t idx[N + 1][N + 1];
        for (int i = 0; i <= N; ++i)
            for (int j = 0; i + j <= N; ++j) {
                double q[3];
                for (int c = 0; c < 3; ++c)
                    q[c] = (o[f[k][0]][c] * (N - i - j) + o[f[k][1]][c] * i + o[f[k][2]][c] * j) / N;
                const double l = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
                for (int c = 0; c < 3; ++c)
                    q[c] /= l;
                uint32_t found = nv;
                for (uint32_t v = 0; v < nv; ++v)
                    if (fabs(p[3 * v] - q[0]) + fabs(p[3 * v + 1] - q[1]) + fabs(p[3 * v + 2] - q[2]) < 1e-12)
                        found = v;
                if (found == nv)
                    memcpy(p + 3 * nv++, q, sizeof q);
                idx[i][j] = found;
            }
        for (int i = 0; i < N; ++i)
            for (int j = 0; i + j < N; ++j) {
                t[nt][0] = idx[i][j], t[nt][1] = idx[i + 1][j], t[nt][2] = idx[i][j + 1], ++nt;
                if (i + j + 1 < N)
                    t[nt][0] = idx[i + 1][j], t[nt][1] = idx[i + 1][j + 1], t[nt][2] = idx[i][j + 1], ++nt;
            }
    }
    return nt;
}

static double volume(const double *p, const uint32_t (*t)[3], uint32_t n)
{
    double v = 0;
    for (uint32_t k = 0; k < n; ++k) {
        const double *a = p + 3 * t[k][0], *b = p + 3 * t[k][1], *c = p + 3 * t[k][2];
        v += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6;
    }
    return v;
}

static void test_sphere_stays_closed(void **state)
{
    (void)state;
    static double p[200 * 3];
    static uint32_t t[200][3];
    const uint32_t nt = sphere(p, t);
    assert_int_equal(nt, 128);
    const double v0 = volume(p, (const uint32_t(*)[3])t, nt);
    uint32_t(*out)[3] = NULL, n = 0;
    assert_int_equal(qtool_simplify(p, 66, (const uint32_t(*)[3])t, nt, 64, &out, &n), 0);
    assert_true(n <= 64 && n >= 8);
    /* closed: every edge used by exactly two triangles, in opposite directions */
    for (uint32_t k = 0; k < n; ++k)
        for (int e = 0; e < 3; ++e) {
            const uint32_t a = out[k][e], b = out[k][(e + 1) % 3];
            int rev = 0, same = 0;
            for (uint32_t q = 0; q < n; ++q)
                for (int g = 0; g < 3; ++g) {
                    rev += out[q][g] == b && out[q][(g + 1) % 3] == a;
                    same += out[q][g] == a && out[q][(g + 1) % 3] == b;
                }
            assert_int_equal(rev, 1);
            assert_int_equal(same, 1);
        }
    const double v1 = volume(p, (const uint32_t(*)[3])out, n);
    /* inscribed in the fine one (its vertices are a subset of the sphere's): smaller, not by much */
    assert_true(v1 > 0.75 * v0 && v1 <= v0 * (1 + 1e-9));
    free(out);
}

static void test_target_above_count_and_degenerates(void **state)
{
    (void)state;
    static double p[200 * 3];
    static uint32_t t[201][3];
    uint32_t nt = sphere(p, t);
    t[nt][0] = 3, t[nt][1] = 3, t[nt][2] = 7, ++nt; /* degenerate: dropped */
    uint32_t(*out)[3] = NULL, n = 0;
    assert_int_equal(qtool_simplify(p, 66, (const uint32_t(*)[3])t, nt, 1000, &out, &n), 0);
    assert_int_equal(n, nt - 1);
    assert_memory_equal(out, t, sizeof t[0] * (nt - 1));
    free(out);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_grid_keeps_outline_and_orientation),
        cmocka_unit_test(test_sphere_stays_closed),
        cmocka_unit_test(test_target_above_count_and_degenerates),
    };
    return cmocka_run_group_tests_name("simplify", tests, NULL, NULL);
}
