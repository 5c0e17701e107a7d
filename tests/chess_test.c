/*
 * chess_test.c - the procedural chess set of `qibl bench hemi` (tools/gen/chess.c): the counts the
 * header states, the board's grid and every piece closed and wound outward (each piece's edges
 * used twice in opposite directions, positive volume), only the three movers moving (the knight
 * off the board mid-hop), the same triangles in every frame, bad arguments refused with nothing
 * allocated, and a frame written as OBJ reading back through the project's OBJ reader.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "gen/chess.h"
#include "io/obj.h"

#define BOARD_V (17 * 17)
#define BOARD_T (2 * 16 * 16)

static void test_counts_and_refusals(void **state)
{
    (void)state;
    qtool_chess c;
    assert_int_equal(qtool_chess_make(6, 8, &c), 0);
    /* 16 pawns (6 rings), 14 officers of 6 rings, 2 kings of 7: 8 around, two poles */
    assert_int_equal(c.nv, BOARD_V + 30 * (6 * 8 + 2) + 2 * (7 * 8 + 2));
    assert_int_equal(c.nt, BOARD_T + 30 * (2 * 8 * 5 + 16) + 2 * (2 * 8 * 6 + 16));
    assert_int_equal(c.nframes, 6);
    for (uint32_t t = 0; t < c.nt; ++t)
        for (int k = 0; k < 3; ++k)
            assert_true(c.tri[t][k] < c.nv);
    qtool_chess_free(&c);
    assert_null(c.tri);
    const int bad[][2] = {{0, 8}, {65, 8}, {6, 2}, {6, 65}, {-1, -1}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        assert_int_equal(qtool_chess_make(bad[i][0], bad[i][1], &c), -1);
        assert_null(c.tri), assert_null(c.pos);
        assert_int_equal(c.nv, 0);
    }
}

/* signed volume of the triangles [t0, t1) */
static double volume(const qtool_chess *c, uint32_t f, uint32_t t0, uint32_t t1)
{
    const double *P = c->pos + 3 * (size_t)c->nv * f;
    double v = 0;
    for (uint32_t t = t0; t < t1; ++t) {
        const double *a = P + 3 * c->tri[t][0], *b = P + 3 * c->tri[t][1], *d = P + 3 * c->tri[t][2];
        v += (a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0]) + a[2] * (b[0] * d[1] - b[1] * d[0])) / 6;
    }
    return v;
}

static void test_closed_and_outward(void **state)
{
    (void)state;
    qtool_chess c;
    assert_int_equal(qtool_chess_make(3, 8, &c), 0);
    /* the board's triangles face up */
    for (uint32_t t = 0; t < BOARD_T; ++t) {
        const double *a = c.pos + 3 * c.tri[t][0], *b = c.pos + 3 * c.tri[t][1], *d = c.pos + 3 * c.tri[t][2];
        assert_true((b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0]) > 0);
    }
    /* pieces: consecutive triangle ranges over disjoint vertex ranges; each directed edge once, its
     * reverse once (closed, consistently wound), and a positive volume (outward) in every frame */
    uint32_t t0 = BOARD_T, pieces = 0;
    while (t0 < c.nt) {
        uint32_t lo = c.tri[t0][0], hi = lo, t1 = t0;
        for (; t1 < c.nt; ++t1) { /* a piece's triangles reference only its own vertex range */
            uint32_t mn = c.tri[t1][0], mx = mn;
            for (int k = 1; k < 3; ++k)
                mn = c.tri[t1][k] < mn ? c.tri[t1][k] : mn, mx = c.tri[t1][k] > mx ? c.tri[t1][k] : mx;
            if (t1 > t0 && mn > hi)
                break;
            lo = mn < lo ? mn : lo, hi = mx > hi ? mx : hi;
        }
        for (uint32_t t = t0; t < t1; ++t)
            for (int k = 0; k < 3; ++k) {
                const uint32_t a = c.tri[t][k], b = c.tri[t][(k + 1) % 3];
                int same = 0, rev = 0;
                for (uint32_t u = t0; u < t1; ++u)
                    for (int q = 0; q < 3; ++q) {
                        same += c.tri[u][q] == a && c.tri[u][(q + 1) % 3] == b;
                        rev += c.tri[u][q] == b && c.tri[u][(q + 1) % 3] == a;
                    }
                assert_int_equal(same, 1);
                assert_int_equal(rev, 1);
            }
        for (uint32_t f = 0; f < c.nframes; ++f)
            assert_true(volume(&c, f, t0, t1) > 0.01);
        ++pieces;
        t0 = t1;
    }
    assert_int_equal(pieces, 32);
    qtool_chess_free(&c);
}

static void test_movers(void **state)
{
    (void)state;
    qtool_chess c;
    assert_int_equal(qtool_chess_make(5, 6, &c), 0);
    const double *A = c.pos, *Z = c.pos + 3 * (size_t)c.nv * 4, *M = c.pos + 3 * (size_t)c.nv * 2;
    uint32_t moved = 0;
    double top = 0;
    for (uint32_t v = 0; v < c.nv; ++v) {
        const double d = fabs(A[3 * v] - Z[3 * v]) + fabs(A[3 * v + 1] - Z[3 * v + 1]) + fabs(A[3 * v + 2] - Z[3 * v + 2]);
        moved += d > 1e-9;
        if (v < BOARD_V)
            assert_true(d == 0);
        top = M[3 * v + 2] - A[3 * v + 2] > top ? M[3 * v + 2] - A[3 * v + 2] : top;
    }
    /* two pawns and a knight (6 around: 6 x 6 + 2 vertices each) */
    assert_int_equal(moved, 3 * (6 * 6 + 2));
    assert_true(top > 0.5); /* the knight mid-hop */
    qtool_chess_free(&c);
}

static void test_obj_round_trip(void **state)
{
    (void)state;
    qtool_chess c;
    assert_int_equal(qtool_chess_make(2, 8, &c), 0);
    char path[] = "/tmp/qibl_chess_test_XXXXXX";
    const int fd = mkstemp(path);
    assert_true(fd >= 0);
    close(fd);
    char err[256];
    assert_int_equal(qtool_chess_write_obj(&c, 1, path, err, sizeof err), 0);
    assert_int_equal(qtool_chess_write_obj(&c, 2, path, err, sizeof err), -1); /* no frame 3 */
    assert_non_null(strstr(err, "frame"));
    qtool_obj_mesh m;
    assert_int_equal(qtool_obj_read(path, &m, err, sizeof err), 0);
    assert_int_equal(m.ntri, c.nt);
    const double *P = c.pos + 3 * (size_t)c.nv;
    for (uint32_t t = 0; t < c.nt; t += 97)
        for (int k = 0; k < 3; ++k)
            for (int j = 0; j < 3; ++j)
                assert_true(fabs(m.pos[9 * t + 3 * k + j] - P[3 * c.tri[t][k] + j]) < 1e-7);
    qtool_obj_free(&m);
    remove(path);
    qtool_chess_free(&c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_counts_and_refusals),
        cmocka_unit_test(test_closed_and_outward),
        cmocka_unit_test(test_movers),
        cmocka_unit_test(test_obj_round_trip),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
