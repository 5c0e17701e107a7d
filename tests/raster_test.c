/*
 * raster_test.c - platform/soft z-buffered triangles (qibl/raster.h): coverage rule (a tiling
 * covers each pixel exactly once, both windings), attribute planes against a double reference
 * within the header's bound, depth order independence, culling, guard band and off-screen
 * triangles, degenerate and sliver triangles, every error status with nothing written, and the
 * raster_* goldens (tools/golden/cases_raster.c).
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

#include "qibl/raster.h"
#include "golden/check.h"
#include "testutil.h"

#define ONE 65536
enum { W = 40, H = 29 };

typedef struct target {
    uint8_t px[W * H * 4];
    uint32_t depth[W * H];
    qibl_raster_target_t t;
} target;

static void target_init(target *g, qibl_fb_format_t f)
{
    memset(g, 0, sizeof *g);
    g->t.fb.pixels = g->px, g->t.fb.width = W, g->t.fb.height = H, g->t.fb.format = f;
    g->t.depth = g->depth, g->t.depth_count = W * H;
    assert_int_equal(qibl_soft_fb_clear(&g->t.fb), QIBL_OK);
    assert_int_equal(qibl_soft_raster_clear_depth(&g->t), QIBL_OK);
}

static qibl_raster_vertex_t vx(int32_t x, int32_t y, int32_t z, int32_t r, int32_t gg, int32_t b)
{
    qibl_raster_vertex_t v;
    v.x = x, v.y = y, v.z = z, v.rgb[0] = r, v.rgb[1] = gg, v.rgb[2] = b;
    return v;
}

static uint32_t seed = 12345u;
static int32_t rnd(int32_t lo, int32_t hi) /* inclusive */
{
    seed = seed * 1103515245u + 12345u;
    return lo + (int32_t)((seed >> 8) % (uint32_t)(hi - lo + 1));
}

/* a pixel was written: depth below far */
static int written(const target *g, int i, int j)
{
    return g->depth[j * W + i] != QIBL_RASTER_DEPTH_FAR;
}

/* exact inside test with the header's rule, in doubles: the reference for coverage */
static int ref_inside(const qibl_raster_vertex_t *a, const qibl_raster_vertex_t *b, const qibl_raster_vertex_t *c,
                      int i, int j)
{
    double area = (double)(b->x - a->x) * (c->y - a->y) - (double)(b->y - a->y) * (c->x - a->x);
    if (area == 0)
        return 0;
    if (area < 0) {
        const qibl_raster_vertex_t *s = b;
        b = c, c = s;
    }
    const qibl_raster_vertex_t *v[3] = {a, b, c};
    const double px = i * 16 + 8, py = j * 16 + 8;
    for (int k = 0; k < 3; ++k) {
        const qibl_raster_vertex_t *p = v[k], *q = v[(k + 1) % 3];
        const double dx = q->x - p->x, dy = q->y - p->y;
        const double e = dx * (py - p->y) - dy * (px - p->x);
        if (e < 0 || (e == 0 && !(dy > 0 || (dy == 0 && dx < 0))))
            return 0;
    }
    return 1;
}

/* A jittered grid of quads, each split into two triangles of random winding, drawn one triangle
 * per target: every pixel whose centre lies inside the grid's outline is covered exactly once,
 * and each triangle covers exactly what the double reference says. */
static void test_tiling_covers_once(void **state)
{
    (void)state;
    enum { N = 6 };
    static target g;
    for (int trial = 0; trial < 20; ++trial) {
        qibl_raster_vertex_t v[(N + 1) * (N + 1)];
        for (int j = 0; j <= N; ++j)
            for (int i = 0; i <= N; ++i) {
                /* interior vertices jittered (some exactly on pixel centres, some on edges) */
                int32_t x = 16 * (2 + i * 6), y = 16 * (2 + j * 4);
                if (i > 0 && i < N && j > 0 && j < N) {
                    const int mode = rnd(0, 3);
                    x += mode == 0 ? 8 : rnd(-23, 23), y += mode == 0 ? 8 : mode == 1 ? 0 : rnd(-15, 15); /* convex cells */
                }
                v[j * (N + 1) + i] = vx(x, y, 100, ONE, ONE, ONE);
            }
        int count[W * H];
        memset(count, 0, sizeof count);
        for (int j = 0; j < N; ++j)
            for (int i = 0; i < N; ++i) {
                const uint32_t a = (uint32_t)(j * (N + 1) + i), b = a + 1, c = a + N + 1, d = c + 1;
                uint32_t tris[2][3] = {{a, b, d}, {a, d, c}};
                if (rnd(0, 1))
                    tris[0][0] = a, tris[0][1] = b, tris[0][2] = c, tris[1][0] = b, tris[1][1] = d, tris[1][2] = c;
                for (int k = 0; k < 2; ++k) {
                    if (rnd(0, 1)) {
                        uint32_t x = tris[k][1];
                        tris[k][1] = tris[k][2], tris[k][2] = x;
                    }
                    target_init(&g, QIBL_FB_RGBA8888);
                    assert_int_equal(qibl_soft_raster_triangles(&g.t, v, (N + 1) * (N + 1),
                                                           (const uint32_t(*)[3])&tris[k], 1), QIBL_OK);
                    for (int y = 0; y < H; ++y)
                        for (int x = 0; x < W; ++x) {
                            const int in = ref_inside(&v[tris[k][0]], &v[tris[k][1]], &v[tris[k][2]], x, y);
                            assert_int_equal(written(&g, x, y), in);
                            count[y * W + x] += in;
                        }
                }
            }
        /* the outline is the axis-aligned rectangle (border vertices are not jittered) */
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const int px = x * 16 + 8, py = y * 16 + 8;
                const int inside = px > 32 && px < 16 * (2 + N * 6) && py > 32 && py < 16 * (2 + N * 4);
                if (inside)
                    assert_int_equal(count[y * W + x], 1);
                else
                    assert_true(count[y * W + x] <= 1);
            }
    }
}

/* Attributes against the exact plane at each covered centre: depth and colour within
 * 0.5 + 2^-17 (|dx| + |dy|) + 2^-10 LSB (the framebuffer rounding is checked via ACCUM-free
 * linear RGBA: one 8-bit LSB is 257 Q16.16 LSB, so colour is checked through depth-like planes). */
static void test_planes_match_reference(void **state)
{
    (void)state;
    static target g;
    for (int trial = 0; trial < 300; ++trial) {
        qibl_raster_vertex_t v[3];
        const int big = trial % 3 == 0;
        for (int k = 0; k < 3; ++k)
            v[k] = vx(rnd(big ? -2000 : -40, big ? 2600 : 700), rnd(big ? -2000 : -40, big ? 2000 : 500),
                      rnd(0, 0x7FFFFFFF - 1), rnd(0, ONE), rnd(0, ONE), rnd(0, ONE));
        target_init(&g, QIBL_FB_RGBA8888);
        const uint32_t t[1][3] = {{0, 1, 2}};
        assert_int_equal(qibl_soft_raster_triangles(&g.t, v, 3, t, 1), QIBL_OK);
        const double x0 = v[0].x, y0 = v[0].y;
        const double ax = v[1].x - x0, ay = v[1].y - y0, bx = v[2].x - x0, by = v[2].y - y0;
        const double area = ax * by - ay * bx;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const int in = ref_inside(&v[0], &v[1], &v[2], x, y);
                assert_int_equal(written(&g, x, y), in);
                if (!in)
                    continue;
                const double px = x * 16 + 8 - x0, py = y * 16 + 8 - y0;
                /* barycentrics of the centre */
                const double l1 = (px * by - py * bx) / area, l2 = (ax * py - ay * px) / area;
                const double z = v[0].z + l1 * (v[1].z - v[0].z) + l2 * (v[2].z - v[0].z);
                const double bound = 0.5 + (fabs(px) + fabs(py)) / 131072.0 + 1e-6;
                assert_true(fabs(g.depth[y * W + x] - z) <= bound + 0.0 ||
                            (g.depth[y * W + x] == (uint32_t)fmin(fmax(z, 0), 2147483647.0)));
                /* colour: linear RGBA8888 is round(255 * clamp(c)), so within 0.5 + a hair */
                for (int c = 0; c < 3; ++c) {
                    const double cv = v[0].rgb[c] + l1 * (v[1].rgb[c] - v[0].rgb[c]) + l2 * (v[2].rgb[c] - v[0].rgb[c]);
                    const double want = 255.0 * fmin(fmax(cv / ONE, 0), 1);
                    assert_true(fabs(g.px[4 * (y * W + x) + c] - want) <= 0.5 + 255.0 * (bound + 1) / ONE);
                }
            }
    }
}

/* Two crossing triangles: the nearer wins per pixel whichever is drawn first. */
static void test_depth_order_independent(void **state)
{
    (void)state;
    static target a, b;
    for (int trial = 0; trial < 50; ++trial) {
        qibl_raster_vertex_t v[6];
        for (int k = 0; k < 6; ++k)
            v[k] = vx(rnd(-100, 700), rnd(-100, 500), rnd(0, 1 << 30) * 2 + (k < 3), rnd(0, ONE), rnd(0, ONE),
                      rnd(0, ONE));
        const uint32_t ab[2][3] = {{0, 1, 2}, {3, 4, 5}}, ba[2][3] = {{3, 4, 5}, {0, 1, 2}};
        target_init(&a, QIBL_FB_BGRA8888), target_init(&b, QIBL_FB_BGRA8888);
        assert_int_equal(qibl_soft_raster_triangles(&a.t, v, 6, ab, 2), QIBL_OK);
        assert_int_equal(qibl_soft_raster_triangles(&b.t, v, 6, ba, 2), QIBL_OK);
        /* odd / even z: no two planes are equal at a pixel except by rounding; compare depth and
         * take pixels where depths differ by more than rounding as the test */
        for (int i = 0; i < W * H; ++i) {
            assert_int_equal(a.depth[i], b.depth[i]);
            if (a.depth[i] == b.depth[i])
                assert_memory_equal(a.px + 4 * i, b.px + 4 * i, 4);
        }
    }
}

static void test_cull_and_degenerate(void **state)
{
    (void)state;
    static target g;
    /* clockwise on screen (y down): (0,0) -> (right) -> (down) */
    qibl_raster_vertex_t v[5] = {vx(16, 16, 5, ONE, 0, 0), vx(500, 16, 5, ONE, 0, 0), vx(16, 400, 5, ONE, 0, 0),
                                 vx(200, 200, 5, ONE, 0, 0), vx(400, 400, 5, ONE, 0, 0)};
    const uint32_t cw[1][3] = {{0, 1, 2}}, ccw[1][3] = {{0, 2, 1}}, line[1][3] = {{0, 3, 4}}, pt[1][3] = {{3, 3, 3}};
    int n = 0;
    target_init(&g, QIBL_FB_RGBA8888);
    g.t.cull = QIBL_RASTER_CULL_CW;
    assert_int_equal(qibl_soft_raster_triangles(&g.t, v, 5, cw, 1), QIBL_OK);
    for (int i = 0; i < W * H; ++i)
        n += g.depth[i] != QIBL_RASTER_DEPTH_FAR;
    assert_int_equal(n, 0);
    assert_int_equal(qibl_soft_raster_triangles(&g.t, v, 5, ccw, 1), QIBL_OK);
    for (int i = 0; i < W * H; ++i)
        n += g.depth[i] != QIBL_RASTER_DEPTH_FAR;
    assert_true(n > 100);
    g.t.cull = QIBL_RASTER_CULL_CCW;
    target_init(&g, QIBL_FB_RGBA8888);
    g.t.cull = QIBL_RASTER_CULL_CCW;
    assert_int_equal(qibl_soft_raster_triangles(&g.t, v, 5, ccw, 1), QIBL_OK);
    assert_int_equal(qibl_soft_raster_triangles(&g.t, v, 5, line, 1), QIBL_OK); /* collinear: nothing */
    assert_int_equal(qibl_soft_raster_triangles(&g.t, v, 5, pt, 1), QIBL_OK);   /* a point: nothing */
    for (int i = 0; i < W * H; ++i)
        assert_int_equal(g.depth[i], QIBL_RASTER_DEPTH_FAR);
}

/* A triangle far larger than the framebuffer (guard band) fills it; one wholly off-screen draws
 * nothing; a sliver 1/16 px wide covers only centres the reference says. */
static void test_guard_band_offscreen_sliver(void **state)
{
    (void)state;
    static target g;
    const int32_t M = QIBL_RASTER_COORD_MAX;
    qibl_raster_vertex_t v[9] = {vx(-M, -16, 7, ONE / 2, ONE / 2, ONE / 2), vx(M, -16, 7, ONE / 2, ONE / 2, ONE / 2),
                                 vx(320, M, 7, ONE / 2, ONE / 2, ONE / 2), vx(-5000, -5000, 1, ONE, 0, 0),
                                 vx(-100, -5000, 1, ONE, 0, 0), vx(-5000, -100, 1, ONE, 0, 0),
                                 vx(8, 8, 1, ONE, ONE, ONE), vx(630, 400, 1, ONE, ONE, ONE), vx(319, 205, 1, 0, 0, 0)};
    const uint32_t huge[1][3] = {{0, 1, 2}}, off[1][3] = {{3, 4, 5}}, sliver[1][3] = {{6, 7, 8}};
    target_init(&g, QIBL_FB_RGBA8888);
    assert_int_equal(qibl_soft_raster_triangles(&g.t, v, 9, huge, 1), QIBL_OK);
    for (int i = 0; i < W * H; ++i) {
        assert_int_equal(g.depth[i], 7);
        assert_int_equal(g.px[4 * i], 128); /* round(255 * 0.5) half up */
    }
    target_init(&g, QIBL_FB_RGBA8888);
    assert_int_equal(qibl_soft_raster_triangles(&g.t, v, 9, off, 1), QIBL_OK);
    assert_int_equal(qibl_soft_raster_triangles(&g.t, v, 9, sliver, 1), QIBL_OK);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            assert_int_equal(written(&g, x, y), ref_inside(&v[6], &v[7], &v[8], x, y));
}

/* Every error, in the documented order, and nothing written. */
static void test_errors_write_nothing(void **state)
{
    (void)state;
    static target g, before;
    qibl_raster_vertex_t v[3] = {vx(0, 0, 1, ONE, ONE, ONE), vx(300, 0, 1, ONE, ONE, ONE), vx(0, 300, 1, ONE, ONE, ONE)};
    const uint32_t t[1][3] = {{0, 1, 2}}, bad_index[1][3] = {{0, 1, 3}};
    target_init(&g, QIBL_FB_RGBA8888);
    before = g;
    assert_int_equal(qibl_soft_raster_triangles(NULL, v, 3, t, 1), QIBL_E_NULL_POINTER);
    qibl_raster_target_t x = g.t;
    x.fb.format = QIBL_FB_ACCUM32;
    assert_int_equal(qibl_soft_raster_triangles(&x, v, 3, t, 1), QIBL_E_FB_FORMAT);
    x = g.t, x.fb.format = (qibl_fb_format_t)99;
    assert_int_equal(qibl_soft_raster_triangles(&x, v, 3, t, 1), QIBL_E_FB_FORMAT);
    x = g.t, x.fb.width = 0;
    assert_int_equal(qibl_soft_raster_triangles(&x, v, 3, t, 1), QIBL_E_FB_SIZE);
    x = g.t, x.depth = NULL;
    assert_int_equal(qibl_soft_raster_triangles(&x, v, 3, t, 1), QIBL_E_NULL_POINTER);
    x = g.t, x.depth_count = W * H - 1;
    assert_int_equal(qibl_soft_raster_triangles(&x, v, 3, t, 1), QIBL_E_FB_SIZE);
    assert_int_equal(qibl_soft_raster_clear_depth(&x), QIBL_E_FB_SIZE);
    assert_int_equal(qibl_soft_raster_triangles(&g.t, NULL, 3, t, 1), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_soft_raster_triangles(&g.t, v, 3, NULL, 1), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_soft_raster_triangles(&g.t, v, 3, bad_index, 1), QIBL_E_RASTER_INDEX);
    /* a bad second triangle: the first is not drawn either */
    const uint32_t two[2][3] = {{0, 1, 2}, {0, 1, 5}};
    assert_int_equal(qibl_soft_raster_triangles(&g.t, v, 3, two, 2), QIBL_E_RASTER_INDEX);
    v[2].x = QIBL_RASTER_COORD_MAX + 1;
    assert_int_equal(qibl_soft_raster_triangles(&g.t, v, 3, t, 1), QIBL_E_RASTER_RANGE);
    v[2].x = 0, v[2].y = -QIBL_RASTER_COORD_MAX - 1;
    assert_int_equal(qibl_soft_raster_triangles(&g.t, v, 3, t, 1), QIBL_E_RASTER_RANGE);
    v[2].y = 300, v[2].z = -1;
    assert_int_equal(qibl_soft_raster_triangles(&g.t, v, 3, t, 1), QIBL_E_RASTER_RANGE);
    assert_memory_equal(g.px, before.px, sizeof g.px);
    assert_memory_equal(g.depth, before.depth, sizeof g.depth);
    /* zero triangles with NULL arrays is a valid empty draw */
    assert_int_equal(qibl_soft_raster_triangles(&g.t, NULL, 0, NULL, 0), QIBL_OK);
    assert_string_equal(qibl_soft_status_str(QIBL_E_RASTER_RANGE), "raster: vertex beyond the coordinate or depth range");
    assert_string_equal(qibl_soft_status_str(QIBL_E_RASTER_INDEX), "raster: triangle index beyond the vertex count");
}

static void test_goldens(void **state)
{
    (void)state;
    assert_int_equal(qtool_goldens_check("raster"), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tiling_covers_once),
        cmocka_unit_test(test_planes_match_reference),
        cmocka_unit_test(test_depth_order_independent),
        cmocka_unit_test(test_cull_and_degenerate),
        cmocka_unit_test(test_guard_band_offscreen_sliver),
        cmocka_unit_test(test_errors_write_nothing),
        cmocka_unit_test(test_goldens),
    };
    return cmocka_run_group_tests_name("raster", tests, NULL, NULL);
}
