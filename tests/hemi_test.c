/*
 * hemi_test.c - hemispherical rasterization: table sizes and errors, triangle masks against a
 * double-precision cone test (mismatches only within the LUT's quantisation of the edge planes),
 * every hard case of the issue (degenerate and sliver triangles, vertices on the horizon, huge and
 * tiny triangles, blockers 1 LSB from the receiver, shared vertices, winding), transfer vectors
 * against a double-precision integral, frames and SH rotation against qibl_sh_rotation_init,
 * shading, and the golden cases.
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

#include "qibl/hemi.h"
#include "golden/cases.h"
#include "golden/check.h"
#include "io/golden.h"
#include "ref/sh_ref.h"
#include "twin/hemi_scalar.h"
#include "io/isa_env.h"
#include "qibl/isa.h"

#define PI 3.14159265358979323846

typedef struct fixture {
    qibl_hemi_t h;
    void *ws;
} fixture;

static fixture *make(int n, int face)
{
    fixture *f = calloc(1, sizeof *f);
    size_t sz = qibl_hemi_workspace_size(n, face);
    assert_true(sz > 0u);
    f->ws = malloc(sz);
    assert_non_null(f->ws);
    assert_int_equal(qibl_hemi_init(&f->h, n, face, f->ws, sz), QIBL_OK);
    return f;
}

static void drop(fixture *f)
{
    free(f->ws);
    free(f);
}

static uint64_t rng(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15u);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9u;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBu;
    return z ^ (z >> 31);
}

static double urand(uint64_t *s)
{
    return (double)(rng(s) >> 11) / 9007199254740992.0;
}

static int get_bit(const qibl_hemi_t *h, const uint32_t *m, int r, int c)
{
    const int wpr = h->n > 32 ? h->n / 32 : 1;
    return (int)(m[r * wpr + c / 32] >> (c % 32)) & 1;
}

/* pixel sample point and whether it meets the disk (the header's definition) */
static int sample(int n, int r, int c, double s[3])
{
    const int X = 2 * c + 1 - n, Y = 2 * r + 1 - n;
    int dx = abs(X) - 1, dy = abs(Y) - 1;
    dx = dx < 0 ? 0 : dx, dy = dy < 0 ? 0 : dy;
    if (dx * dx + dy * dy >= n * n)
        return 0;
    const double x = (double)X / n, y = (double)Y / n, q = 1.0 - x * x - y * y;
    if (q > 0) {
        s[0] = x, s[1] = y, s[2] = sqrt(q);
    } else {
        const double l = sqrt(x * x + y * y);
        s[0] = x / l, s[1] = y / l, s[2] = 0;
    }
    return 1;
}

static void dcross(const int32_t *a, const int32_t *b, double o[3])
{
    o[0] = (double)a[1] * b[2] - (double)a[2] * b[1];
    o[1] = (double)a[2] * b[0] - (double)a[0] * b[2];
    o[2] = (double)a[0] * b[1] - (double)a[1] * b[0];
}

/* Compares the mask of one triangle with the exact cone test; every mismatching pixel must lie
 * within delta (as |n.s| with n the unit edge normal) of an edge plane. Returns the mismatches. */
static int check_triangle(const qibl_hemi_t *h, const int32_t v[3][3], double delta, int *covered)
{
    uint32_t m[QIBL_HEMI_MAX_WORDS];
    const uint32_t tri[1][3] = {{0, 1, 2}};
    assert_int_equal(qibl_hemi_clear(h, m), QIBL_OK);
    assert_int_equal(qibl_hemi_raster(h, v, 3, tri, 1, m, NULL), QIBL_OK);
    assert_int_equal(qibl_hemi_clip(h, m), QIBL_OK);
    double e[3][3];
    dcross(v[0], v[1], e[0]);
    dcross(v[1], v[2], e[1]);
    dcross(v[2], v[0], e[2]);
    const double det = e[0][0] * v[2][0] + e[0][1] * v[2][1] + e[0][2] * v[2][2];
    for (int i = 0; i < 3; ++i) {
        double l = sqrt(e[i][0] * e[i][0] + e[i][1] * e[i][1] + e[i][2] * e[i][2]);
        for (int k = 0; k < 3; ++k)
            e[i][k] = l > 0 ? e[i][k] / l * (det < 0 ? -1 : 1) : 0;
    }
    const int below = v[0][2] <= 0 && v[1][2] <= 0 && v[2][2] <= 0;
    int bad = 0, cov = 0;
    for (int r = 0; r < h->n; ++r)
        for (int c = 0; c < h->n; ++c) {
            double s[3];
            if (!sample(h->n, r, c, s)) {
                assert_int_equal(get_bit(h, m, r, c), 0);
                continue;
            }
            int in = det != 0 && !below, near = 0;
            for (int i = 0; i < 3; ++i) {
                const double d = e[i][0] * s[0] + e[i][1] * s[1] + e[i][2] * s[2];
                in &= d > 0;
                near |= fabs(d) <= delta;
            }
            const int got = get_bit(h, m, r, c);
            cov += got;
            if (got != in && !near)
                ++bad;
        }
    if (covered)
        *covered = cov;
    return bad;
}

/* ---- sizes and errors --------------------------------------------------------------------------- */

static void test_sizes_and_errors(void **state)
{
    (void)state;
    assert_int_equal(qibl_hemi_workspace_size(24, 60), 0u);
    assert_int_equal(qibl_hemi_workspace_size(32, 61), 0u);
    assert_int_equal(qibl_hemi_workspace_size(32, 0), 0u);
    assert_int_equal(qibl_hemi_workspace_size(32, 130), 0u);
    /* the documented budgets: default within 1 MiB, the small configuration within 256 KiB */
    assert_true(qibl_hemi_workspace_size(32, 48) <= 1048576u); /* the default */
    assert_true(qibl_hemi_workspace_size(32, 50) > 1048576u);
    assert_true(qibl_hemi_workspace_size(32, 20) <= 262144u); /* the small configuration */
    assert_true(qibl_hemi_workspace_size(64, 128) > qibl_hemi_workspace_size(32, 128));
    qibl_hemi_t h;
    memset(&h, 0x5A, sizeof h);
    const qibl_hemi_t before = h;
    size_t sz = qibl_hemi_workspace_size(16, 8);
    void *ws = malloc(sz);
    assert_int_equal(qibl_hemi_init(NULL, 16, 8, ws, sz), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_hemi_init(&h, 16, 8, NULL, sz), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_hemi_init(&h, 17, 8, ws, sz), QIBL_E_HEMI_SIZE);
    assert_int_equal(qibl_hemi_init(&h, 16, 7, ws, sz), QIBL_E_HEMI_SIZE);
    assert_int_equal(qibl_hemi_init(&h, 16, 8, ws, sz - 1), QIBL_E_WORKSPACE);
    assert_memory_equal(&h, &before, sizeof h);
    /* any alignment */
    free(ws);
    ws = malloc(sz + 3);
    for (int off = 1; off <= 3; ++off) /* the init aligns its tables itself (slack in the size) */
        assert_int_equal(qibl_hemi_init(&h, 16, 8, (char *)ws + off, sz), QIBL_OK);
    free(ws);
    assert_string_not_equal(qibl_status_str(QIBL_E_HEMI_SIZE), "unknown status");
    assert_string_not_equal(qibl_status_str(QIBL_E_HEMI_RANGE), "unknown status");
    assert_string_not_equal(qibl_status_str(QIBL_E_HEMI_INDEX), "unknown status");
}

static void test_raster_errors(void **state)
{
    (void)state;
    fixture *f = make(16, 8);
    uint32_t m[QIBL_HEMI_MAX_WORDS];
    for (int i = 0; i < 128; ++i)
        m[i] = 0xA5A5A5A5u;
    int32_t v[3][3] = {{100, 0, 1000}, {0, 100, 1000}, {-100, -100, 1000}};
    const uint32_t good[2][3] = {{0, 1, 2}, {2, 1, 0}}, bad[2][3] = {{0, 1, 2}, {0, 1, 3}};
    qibl_hemi_stats_t st = {7, 7, 7};
    assert_int_equal(qibl_hemi_raster(&f->h, v, 3, bad, 2, m, &st), QIBL_E_HEMI_INDEX);
    v[2][0] = QIBL_HEMI_LOCAL_MAX + 1;
    assert_int_equal(qibl_hemi_raster(&f->h, v, 3, good, 2, m, &st), QIBL_E_HEMI_RANGE);
    v[2][0] = -QIBL_HEMI_LOCAL_MAX - 1;
    assert_int_equal(qibl_hemi_raster(&f->h, v, 3, good, 2, m, &st), QIBL_E_HEMI_RANGE);
    for (int i = 0; i < 128; ++i)
        assert_int_equal(m[i], 0xA5A5A5A5u);
    assert_int_equal(st.rasterized + st.below + st.through, 21u);
    assert_int_equal(qibl_hemi_raster(&f->h, NULL, 0, NULL, 0, m, NULL), QIBL_OK);
    assert_int_equal(qibl_hemi_raster(&f->h, NULL, 3, good, 1, m, NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_hemi_raster(NULL, v, 3, good, 1, m, NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_hemi_raster(&f->h, v, 3, good, 1, NULL, NULL), QIBL_E_NULL_POINTER);
    qibl_q30_t out[25];
    assert_int_equal(qibl_hemi_transfer(&f->h, NULL, out), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_hemi_clear(NULL, m), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_hemi_clip(&f->h, NULL), QIBL_E_NULL_POINTER);
    drop(f);
}

/* ---- masks against the cone test ----------------------------------------------------------------- */

static void random_triangles(int n, int face, int count)
{
    fixture *f = make(n, face);
    const double delta = 2.3 / face; /* cell half-diagonal on the cube face, as an angle bound */
    uint64_t s = 77 + (uint64_t)n * 1000 + (uint64_t)face;
    int total_bad = 0;
    for (int t = 0; t < count; ++t) {
        int32_t v[3][3];
        const double scale = t % 3 == 0 ? 4e6 : t % 3 == 1 ? 3e5 : 2e4;
        for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k)
                v[i][k] = (int32_t)((urand(&s) * 2 - 1) * scale);
        total_bad += check_triangle(&f->h, v, delta, NULL);
    }
    assert_int_equal(total_bad, 0);
    drop(f);
}

static void test_random_triangles_32(void **state)
{
    (void)state;
    random_triangles(32, 60, 400);
    random_triangles(32, 24, 200);
}

static void test_random_triangles_16_64(void **state)
{
    (void)state;
    random_triangles(16, 16, 200);
    random_triangles(64, 64, 100);
}

/* The library's raster call against the scalar twin on the same triangles: the same mask and
 * counts, and for the first 12 triangles each mask alone (not hidden by the union); the counts
 * returned. */
static qibl_hemi_stats_t raster_both(const fixture *f, const int32_t (*v)[3], uint32_t nv, const uint32_t (*tri)[3],
                                     uint32_t nt)
{
    uint32_t m1[QIBL_HEMI_MAX_WORDS], m2[QIBL_HEMI_MAX_WORDS];
    qibl_hemi_stats_t s1 = {0, 0, 0}, s2 = {0, 0, 0};
    assert_int_equal(qibl_hemi_clear(&f->h, m1), QIBL_OK);
    assert_int_equal(qibl_hemi_clear(&f->h, m2), QIBL_OK);
    assert_int_equal(qibl_hemi_raster(&f->h, v, nv, tri, nt, m1, &s1), QIBL_OK);
    assert_int_equal(qtool_hemi_raster_scalar(&f->h, v, nv, tri, nt, m2, &s2), QIBL_OK);
    assert_memory_equal(m1, m2, sizeof(uint32_t) * f->h.words);
    assert_int_equal(s1.rasterized, s2.rasterized);
    assert_int_equal(s1.below, s2.below);
    assert_int_equal(s1.through, s2.through);
    /* the other winding: the same mask (the exact setup orients its int64 normals before their
     * shift, so floor(-x / 2^s) never differs from -floor(x / 2^s) by the one that it can) */
    {
        uint32_t (*rev)[3] = malloc(sizeof *rev * (nt ? nt : 1u));
        assert_non_null(rev);
        for (uint32_t t = 0; t < nt; ++t)
            rev[t][0] = tri[t][0], rev[t][1] = tri[t][2], rev[t][2] = tri[t][1];
        assert_int_equal(qibl_hemi_clear(&f->h, m2), QIBL_OK);
        assert_int_equal(qibl_hemi_raster(&f->h, v, nv, (const uint32_t(*)[3])rev, nt, m2, NULL), QIBL_OK);
        assert_memory_equal(m1, m2, sizeof(uint32_t) * f->h.words);
        free(rev);
    }
    for (uint32_t t = 0; t < nt && t < 12u; ++t) {
        assert_int_equal(qibl_hemi_clear(&f->h, m1), QIBL_OK);
        assert_int_equal(qibl_hemi_clear(&f->h, m2), QIBL_OK);
        assert_int_equal(qibl_hemi_raster(&f->h, v, nv, tri + t, 1, m1, NULL), QIBL_OK);
        assert_int_equal(qtool_hemi_raster_scalar(&f->h, v, nv, tri + t, 1, m2, NULL), QIBL_OK);
        assert_memory_equal(m1, m2, sizeof(uint32_t) * f->h.words);
    }
    return s1;
}

/* The library's rasterizer (x86: the double look-up lanes; elsewhere the same code as the twin)
 * against the scalar twin, bit for bit: random meshes at every magnitude from 1 LSB to the full
 * local range, vertices on the horizon, shared and repeated vertices, every mask size and several
 * face sizes (odd cell counts, the smallest and the largest face), in batches that do not fill the
 * look-up lanes. */
static void test_lanes_match_twin(void **state)
{
    (void)state;
    const int cfg[][2] = {{32, 60}, {32, 24}, {32, 2}, {16, 16}, {64, 128}, {32, 126}, {16, 6}};
    uint64_t seed = 0x51DEu;
    for (size_t c = 0; c < sizeof cfg / sizeof cfg[0]; ++c) {
        fixture *f = make(cfg[c][0], cfg[c][1]);
        for (int round = 0; round < 60; ++round) {
            enum { NV = 40, NT = 150 };
            int32_t v[NV][3];
            uint32_t tri[NT][3];
            /* magnitude: 2^1 .. 2^26 - 1 */
            const int bitsz = 1 + (int)(rng(&seed) % 26u);
            const int32_t lim = bitsz >= 26 ? QIBL_HEMI_LOCAL_MAX : (int32_t)((1u << bitsz) - 1u);
            for (int i = 0; i < NV; ++i)
                for (int k = 0; k < 3; ++k) {
                    const uint64_t r = rng(&seed);
                    int32_t x = (int32_t)(r % (2u * (uint32_t)lim + 1u)) - lim;
                    if (k == 2 && (r >> 40) % 5u == 0u)
                        x = 0; /* on the horizon */
                    if ((r >> 44) % 7u == 0u)
                        x = (r >> 50) & 1u ? lim : -lim; /* at the limit */
                    v[i][k] = x;
                }
            const uint32_t nt = 1u + (uint32_t)(rng(&seed) % NT);
            for (uint32_t t = 0; t < nt; ++t)
                for (int k = 0; k < 3; ++k)
                    tri[t][k] = (uint32_t)(rng(&seed) % NV); /* repeats make degenerate triangles */
            raster_both(f, (const int32_t(*)[3])v, NV, (const uint32_t(*)[3])tri, nt);
        }
        drop(f);
    }
}

/* Vertex indices whose offsets 3 i pass an int32 (i >= 2^31 / 3: the lanes must not gather them):
 * triangles over the last vertices of a 3 2^28 + 40 vertex array (calloc'd: its untouched pages
 * read as zeros) give the masks and counts of the same triangles over a 40-vertex array. Skipped
 * where 9.7 GB of address space cannot be had. */
static void test_indices_past_int32_offsets(void **state)
{
    (void)state;
    enum { NV = 40, NT = 150 };
    const uint32_t base = 3u << 28;
    int32_t(*big)[3] = calloc((size_t)base + NV, sizeof *big);
    if (!big)
        skip();
    fixture *f = make(32, 60);
    uint64_t seed = 0xB16u;
    int32_t v[NV][3];
    uint32_t tri[NT][3], trib[NT][3];
    for (int i = 0; i < NV; ++i)
        for (int k = 0; k < 3; ++k) {
            v[i][k] = (int32_t)(rng(&seed) % (2u * 4096u + 1u)) - 4096;
            big[base + (uint32_t)i][k] = v[i][k];
        }
    for (uint32_t t = 0; t < NT; ++t)
        for (int k = 0; k < 3; ++k)
            tri[t][k] = (uint32_t)(rng(&seed) % NV), trib[t][k] = base + tri[t][k];
    uint32_t m1[QIBL_HEMI_MAX_WORDS], m2[QIBL_HEMI_MAX_WORDS];
    qibl_hemi_stats_t s1 = {0, 0, 0}, s2 = {0, 0, 0};
    assert_int_equal(qibl_hemi_clear(&f->h, m1), QIBL_OK);
    assert_int_equal(qibl_hemi_clear(&f->h, m2), QIBL_OK);
    assert_int_equal(qibl_hemi_raster(&f->h, (const int32_t(*)[3])v, NV, (const uint32_t(*)[3])tri, NT, m1, &s1), QIBL_OK);
    assert_int_equal(qibl_hemi_raster(&f->h, (const int32_t(*)[3])big, base + NV, (const uint32_t(*)[3])trib, NT, m2, &s2),
                     QIBL_OK);
    assert_true(s1.rasterized > 0);
    assert_memory_equal(m1, m2, sizeof(uint32_t) * f->h.words);
    assert_int_equal(s1.rasterized, s2.rasterized);
    assert_int_equal(s1.below, s2.below);
    assert_int_equal(s1.through, s2.through);
    free(big);
    drop(f);
}

/* Nearly edge-on triangles with large coordinates: det = a . (b x c) is -dx B (dx in 0..2, B near
 * 2^23) while the products of the lanes' determinant reach 2^72, so its sign is often not certain
 * in doubles and the lanes fall back to the exact integer setup (tests the filter and the fallback,
 * both orientations, the plane through the receiver, mixed in one batch with ordinary triangles). */
static void test_lanes_edge_on(void **state)
{
    (void)state;
    const int cfg[][2] = {{32, 48}, {16, 6}, {64, 8}};
    uint64_t seed = 0xED6Eu;
    for (size_t c = 0; c < sizeof cfg / sizeof cfg[0]; ++c) {
        fixture *f = make(cfg[c][0], cfg[c][1]);
        for (int round = 0; round < 40; ++round) {
            enum { NV = 60, NT = 90 };
            int32_t v[NV][3];
            uint32_t tri[NT][3];
            for (int i = 0; i < NV; i += 3) {
                const int32_t A = (int32_t)(0x800000u + (uint32_t)(rng(&seed) % 0x800000u));
                const int32_t B = (int32_t)(0x800000u + (uint32_t)(rng(&seed) % 0x800000u));
                const int32_t C = (int32_t)(0x800000u + (uint32_t)(rng(&seed) % 0x800000u));
                const int32_t dx = (int32_t)(rng(&seed) % 3u); /* 0: through the receiver */
                const int32_t sa = rng(&seed) & 1u ? -1 : 1, sb = rng(&seed) & 1u ? -1 : 1;
                v[i][0] = sa * A, v[i][1] = 0, v[i][2] = 1;
                v[i + 1][0] = 0, v[i + 1][1] = sb * B, v[i + 1][2] = C;
                v[i + 2][0] = sa * A + dx, v[i + 2][1] = sb * B, v[i + 2][2] = C + 1;
            }
            for (uint32_t t = 0; t < NT; ++t) {
                const uint32_t g = 3u * (uint32_t)(rng(&seed) % (NV / 3));
                if (t % 3u == 2u) { /* an ordinary triangle across groups */
                    for (int k = 0; k < 3; ++k)
                        tri[t][k] = (uint32_t)(rng(&seed) % NV);
                } else if (rng(&seed) & 1u) {
                    tri[t][0] = g, tri[t][1] = g + 1u, tri[t][2] = g + 2u;
                } else {
                    tri[t][0] = g, tri[t][1] = g + 2u, tri[t][2] = g + 1u;
                }
            }
            const qibl_hemi_stats_t s1 = raster_both(f, (const int32_t(*)[3])v, NV, (const uint32_t(*)[3])tri, NT);
            assert_true(s1.through > 0u);
        }
        drop(f);
    }
}

/* The refinement test against its definition in doubles, away from ties: receivers and bounds at
 * every scale up to the coordinate limit, k from 1/256 to 255; the empty group, k = 0, NULL, a
 * radius large enough for k r to pass 2^32, and a centre beyond the limit (refined). */
static void test_bound_near(void **state)
{
    (void)state;
    uint64_t seed = 0xB0u;
    const int32_t up[3] = {0, 0, 1 << 30};
    int near = 0, far = 0;
    for (int round = 0; round < 20000; ++round) {
        const int bits = 1 + (int)(rng(&seed) % 22u);
        const int32_t lim = bits >= 22 ? QIBL_HEMI_COORD_MAX : (int32_t)((1u << bits) - 1u);
        qibl_q16_t p[3];
        qibl_hemi_bound_t b;
        for (int k = 0; k < 3; ++k) {
            p[k] = (int32_t)(rng(&seed) % (2u * (uint32_t)lim + 1u)) - lim;
            b.c[k] = (int32_t)(rng(&seed) % (2u * (uint32_t)lim + 1u)) - lim;
        }
        b.r = (int32_t)(rng(&seed) % ((uint32_t)lim + 1u));
        const uint32_t kq = 1u + (uint32_t)(rng(&seed) % 65279u);
        qibl_hemi_frame_t fr;
        assert_int_equal(qibl_hemi_frame_init(&fr, p, up), QIBL_OK);
        double d2 = 0;
        for (int k = 0; k < 3; ++k)
            d2 += ((double)b.c[k] - p[k]) * ((double)b.c[k] - p[k]);
        const double kr = (double)kq / 256.0 * b.r, lhs = sqrt(d2);
        if (fabs(lhs - kr) <= 1e-6 * (lhs + kr) + 1.0)
            continue; /* a tie within doubles' reach */
        const int want = lhs < kr;
        assert_int_equal(qibl_hemi_bound_near(&fr, &b, kq), want);
        near += want, far += !want;
    }
    assert_true(near > 1000 && far > 1000);
    qibl_hemi_frame_t fr;
    const qibl_q16_t o[3] = {0, 0, 0};
    assert_int_equal(qibl_hemi_frame_init(&fr, o, up), QIBL_OK);
    qibl_hemi_bound_t b = {{QIBL_HEMI_COORD_MAX, -QIBL_HEMI_COORD_MAX, QIBL_HEMI_COORD_MAX}, 0x7FFFFFFF};
    assert_int_equal(qibl_hemi_bound_near(&fr, &b, 65535u), 1); /* k r > 2^32 */
    assert_int_equal(qibl_hemi_bound_near(&fr, &b, 0u), 0);
    assert_int_equal(qibl_hemi_bound_near(NULL, &b, 256u), 0);
    assert_int_equal(qibl_hemi_bound_near(&fr, NULL, 256u), 0);
    b.r = 1;
    assert_int_equal(qibl_hemi_bound_near(&fr, &b, 256u), 0);
    b.r = -1; /* empty */
    assert_int_equal(qibl_hemi_bound_near(&fr, &b, 65535u), 0);
    b.r = 1, b.c[0] = 0x7FFFFFFF; /* not a fitted bound: refined, and kept by the culling test */
    assert_int_equal(qibl_hemi_bound_near(&fr, &b, 256u), 1);
    assert_int_equal(qibl_hemi_bound_above(&fr, &b), 1);
    b.c[0] = -0x7FFFFFFF - 1;
    assert_int_equal(qibl_hemi_bound_near(&fr, &b, 256u), 1);
    assert_int_equal(qibl_hemi_bound_above(&fr, &b), 1);
}

/* The batched group culling gives the single tests' answers: random receivers (any normal) and
 * groups at every scale, empty groups, centres beyond the limit, k = 0; the named error and an
 * untouched output on failure. */
static void test_bound_cull(void **state)
{
    (void)state;
    enum { NG = 37 };
    uint64_t seed = 0xC011u;
    int seen[3] = {0, 0, 0};
    for (int round = 0; round < 3000; ++round) {
        const int bits = 1 + (int)(rng(&seed) % 22u);
        const int32_t lim = bits >= 22 ? QIBL_HEMI_COORD_MAX : (int32_t)((1u << bits) - 1u);
        qibl_q16_t p[3];
        int32_t nrm[3];
        for (int k = 0; k < 3; ++k) {
            p[k] = (int32_t)(rng(&seed) % (2u * (uint32_t)lim + 1u)) - lim;
            nrm[k] = (int32_t)(rng(&seed) % 2001u) - 1000;
        }
        if (nrm[0] == 0 && nrm[1] == 0 && nrm[2] == 0)
            nrm[2] = 1;
        qibl_hemi_frame_t fr;
        assert_int_equal(qibl_hemi_frame_init(&fr, p, nrm), QIBL_OK);
        qibl_hemi_bound_t nb[NG], fb[NG];
        for (int g = 0; g < NG; ++g)
            for (int w = 0; w < 2; ++w) {
                qibl_hemi_bound_t *b = w ? &fb[g] : &nb[g];
                for (int k = 0; k < 3; ++k)
                    b->c[k] = p[k] + (int32_t)(rng(&seed) % (2u * (uint32_t)lim + 1u)) - lim;
                for (int k = 0; k < 3; ++k)
                    b->c[k] = b->c[k] > QIBL_HEMI_COORD_MAX ? QIBL_HEMI_COORD_MAX : b->c[k] < -QIBL_HEMI_COORD_MAX ? -QIBL_HEMI_COORD_MAX : b->c[k];
                b->r = (int32_t)(rng(&seed) % ((uint32_t)lim + 1u));
                const uint32_t odd = (uint32_t)(rng(&seed) % 50u);
                if (odd == 0u)
                    b->r = -1; /* empty */
                else if (odd == 1u)
                    b->c[(int)(rng(&seed) % 3u)] = rng(&seed) & 1u ? 0x7FFFFFFF : -0x7FFFFFFF - 1; /* not fitted */
            }
        const uint32_t kq = round % 10 == 0 ? 0u : 1u + (uint32_t)(rng(&seed) % 1023u);
        uint8_t out[NG + 1];
        out[NG] = 0xA5u; /* guard */
        assert_int_equal(qibl_hemi_bound_cull(&fr, nb, fb, NG, kq, out), QIBL_OK);
        assert_int_equal(out[NG], 0xA5u);
        for (int g = 0; g < NG; ++g) {
            const int in = qibl_hemi_bound_near(&fr, &nb[g], kq);
            const int want = qibl_hemi_bound_above(&fr, in ? &nb[g] : &fb[g]) ? (in ? 2 : 1) : 0;
            assert_int_equal(out[g], want);
            ++seen[want];
        }
    }
    assert_true(seen[0] > 1000 && seen[1] > 1000 && seen[2] > 1000);
    qibl_hemi_frame_t fr;
    const qibl_q16_t o[3] = {0, 0, 0};
    const int32_t up[3] = {0, 0, 1};
    assert_int_equal(qibl_hemi_frame_init(&fr, o, up), QIBL_OK);
    const qibl_hemi_bound_t b = {{0, 0, 5}, 1};
    uint8_t out[1] = {7};
    assert_int_equal(qibl_hemi_bound_cull(NULL, &b, &b, 1, 256u, out), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_hemi_bound_cull(&fr, NULL, &b, 1, 256u, out), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_hemi_bound_cull(&fr, &b, NULL, 1, 256u, out), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_hemi_bound_cull(&fr, &b, &b, 1, 256u, NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(out[0], 7); /* untouched */
    assert_int_equal(qibl_hemi_bound_cull(&fr, NULL, NULL, 0, 256u, NULL), QIBL_OK);
    assert_int_equal(qibl_hemi_bound_cull(&fr, &b, &b, 1, 256u * 8u, out), QIBL_OK);
    assert_int_equal(out[0], 2); /* 5 < 8 r: near, and above */
}

/* Group bounds: every vertex inside, the radius tight to one LSB, the named errors; and the
 * culling test sound against the rasterizer: whenever a group is reported at or below a receiver's
 * tangent plane, rasterizing its triangles after the transform culls every one (the mask stays
 * empty); groups clearly above are kept. Random receivers, normals and groups at every scale,
 * groups grazing the plane included. */
static void test_group_bounds(void **state)
{
    (void)state;
    fixture *f = make(32, 24);
    uint64_t seed = 0xB0D5u;
    qibl_hemi_bound_t b = {{7, 7, 7}, 7};
    const qibl_q16_t far[1][3] = {{QIBL_HEMI_COORD_MAX + 1, 0, 0}};
    const uint32_t bad_idx[1] = {3};
    assert_int_equal(qibl_hemi_bound_fit(NULL, 1, NULL, 1, &b), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_hemi_bound_fit(far, 1, NULL, 1, NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_hemi_bound_fit(far, 1, NULL, 1, &b), QIBL_E_HEMI_RANGE);
    assert_int_equal(qibl_hemi_bound_fit(far, 1, bad_idx, 1, &b), QIBL_E_HEMI_INDEX);
    assert_int_equal(b.r, 7); /* untouched */
    assert_int_equal(qibl_hemi_bound_fit(NULL, 0, NULL, 0, &b), QIBL_OK);
    assert_int_equal(b.r, -1);
    qibl_hemi_frame_t fr;
    const qibl_q16_t o[3] = {0, 0, 0};
    const int32_t up[3] = {0, 0, 1};
    assert_int_equal(qibl_hemi_frame_init(&fr, o, up), QIBL_OK);
    assert_int_equal(qibl_hemi_bound_above(&fr, &b), 0); /* empty */
    assert_int_equal(qibl_hemi_bound_above(NULL, &b), 0);
    int culled_groups = 0, kept_groups = 0;
    for (int round = 0; round < 3000; ++round) {
        enum { NV = 12, NT = 10 };
        const int bitsz = 4 + (int)(rng(&seed) % 16u); /* group size 2^4 .. 2^19 LSB (within the coordinate range) */
        const int32_t span = (int32_t)(1u << bitsz);
        qibl_q16_t p[3], pos[NV][3];
        int32_t nrm[3];
        for (int k = 0; k < 3; ++k) {
            p[k] = (qibl_q16_t)(rng(&seed) % (2u * 0x100000u)) - 0x100000;
            nrm[k] = (int32_t)(rng(&seed) % 2001u) - 1000;
        }
        if (nrm[0] == 0 && nrm[1] == 0 && nrm[2] == 0)
            nrm[2] = 1;
        assert_int_equal(qibl_hemi_frame_init(&fr, p, nrm), QIBL_OK);
        /* the group around a point at a signed height near the plane: often grazing it */
        const double nl = sqrt((double)nrm[0] * nrm[0] + (double)nrm[1] * nrm[1] + (double)nrm[2] * nrm[2]);
        const double hgt = ((double)(rng(&seed) % 2001u) - 1000.0) / 1000.0 * 1.5 * span;
        qibl_q16_t c0[3];
        for (int k = 0; k < 3; ++k)
            c0[k] = (qibl_q16_t)(p[k] + (int32_t)((double)(rng(&seed) % 2001u) - 1000.0) * (span / 1000) +
                                 (int32_t)lrint(hgt * nrm[k] / nl));
        for (int i = 0; i < NV; ++i)
            for (int k = 0; k < 3; ++k)
                pos[i][k] = c0[k] + (qibl_q16_t)(rng(&seed) % (uint32_t)span) - span / 2;
        assert_int_equal(qibl_hemi_bound_fit((const qibl_q16_t(*)[3])pos, NV, NULL, NV, &b), QIBL_OK);
        double worst = 0;
        for (int i = 0; i < NV; ++i) {
            double d2 = 0;
            for (int k = 0; k < 3; ++k)
                d2 += ((double)pos[i][k] - b.c[k]) * ((double)pos[i][k] - b.c[k]);
            worst = sqrt(d2) > worst ? sqrt(d2) : worst;
        }
        assert_true(b.r >= worst && b.r <= worst + 1.0);
        uint32_t tri[NT][3];
        for (int t = 0; t < NT; ++t)
            for (int k = 0; k < 3; ++k)
                tri[t][k] = (uint32_t)(rng(&seed) % NV);
        int32_t loc[NV][3];
        assert_int_equal(qibl_hemi_transform(&fr, (const qibl_q16_t(*)[3])pos, NV, loc), QIBL_OK);
        int any_up = 0;
        for (int i = 0; i < NV; ++i)
            any_up |= loc[i][2] > 0;
        if (!qibl_hemi_bound_above(&fr, &b)) {
            ++culled_groups;
            assert_false(any_up);
            uint32_t m[QIBL_HEMI_MAX_WORDS];
            qibl_hemi_stats_t st = {0, 0, 0};
            assert_int_equal(qibl_hemi_clear(&f->h, m), QIBL_OK);
            assert_int_equal(qibl_hemi_raster(&f->h, (const int32_t(*)[3])loc, NV, (const uint32_t(*)[3])tri, NT, m, &st),
                             QIBL_OK);
            assert_int_equal(st.rasterized, 0u);
            assert_int_equal(st.below, (uint32_t)NT);
        } else {
            ++kept_groups;
            /* kept only when the sphere reaches above the plane: its lowest point is within r */
            double s = 0;
            for (int k = 0; k < 3; ++k)
                s += fr.axis[2][k] / 1073741824.0 * ((double)b.c[k] - p[k]);
            assert_true(s + b.r * 1.000001 > -2.0);
        }
    }
    assert_true(culled_groups > 500 && kept_groups > 500);
    drop(f);
}

static void test_winding_and_fusion(void **state)
{
    (void)state;
    fixture *f = make(32, 60);
    int32_t v[4][3] = {{200000, -300000, 400000}, {-100000, 250000, 300000}, {-300000, -200000, 500000},
                       {400000, 400000, 100000}};
    const uint32_t t1[1][3] = {{0, 1, 2}}, t2[1][3] = {{0, 2, 1}}, t3[1][3] = {{1, 0, 3}}, both[2][3] = {{0, 1, 2}, {1, 0, 3}};
    uint32_t a[32], b[32], c[32], d[32];
    assert_int_equal(qibl_hemi_clear(&f->h, a), QIBL_OK);
    assert_int_equal(qibl_hemi_clear(&f->h, b), QIBL_OK);
    assert_int_equal(qibl_hemi_clear(&f->h, c), QIBL_OK);
    assert_int_equal(qibl_hemi_clear(&f->h, d), QIBL_OK);
    assert_int_equal(qibl_hemi_raster(&f->h, v, 4, t1, 1, a, NULL), QIBL_OK);
    assert_int_equal(qibl_hemi_raster(&f->h, v, 4, t2, 1, b, NULL), QIBL_OK);
    assert_memory_equal(a, b, sizeof a); /* winding does not matter */
    assert_int_equal(qibl_hemi_raster(&f->h, v, 4, t3, 1, c, NULL), QIBL_OK);
    assert_int_equal(qibl_hemi_raster(&f->h, v, 4, both, 2, d, NULL), QIBL_OK);
    for (int i = 0; i < 32; ++i)
        assert_int_equal(d[i], a[i] | c[i]); /* occluder fusion: OR of the triangles */
    int cov = 0;
    for (int i = 0; i < 32; ++i)
        cov += a[i] != 0;
    assert_true(cov > 3);
    drop(f);
}

/* ---- hard cases --------------------------------------------------------------------------------- */

static int bits(const qibl_hemi_t *h, const uint32_t *m)
{
    int c = 0;
    for (uint32_t i = 0; i < h->words; ++i)
        for (uint32_t w = m[i] & h->disk[i]; w; w &= w - 1)
            ++c;
    return c;
}

static int disk_bits(const qibl_hemi_t *h)
{
    int c = 0;
    for (uint32_t i = 0; i < h->words; ++i)
        for (uint32_t w = h->disk[i]; w; w &= w - 1)
            ++c;
    return c;
}

static void raster1(const qibl_hemi_t *h, const int32_t v[3][3], uint32_t *m, qibl_hemi_stats_t *st)
{
    const uint32_t tri[1][3] = {{0, 1, 2}};
    assert_int_equal(qibl_hemi_clear(h, m), QIBL_OK);
    memset(st, 0, sizeof *st);
    assert_int_equal(qibl_hemi_raster(h, v, 3, tri, 1, m, st), QIBL_OK);
}

/* Every dispatch choice this CPU runs (scalar, SSE2, AVX2: qtool_isa_force) against the scalar
 * twin, bit for bit, on batches that mix ordinary triangles with the setup's special cases: huge
 * roofs a few LSB above or below the receiver, whose quantised vertices (|q| <= 512) lie on the
 * horizon so the quantised orientation is 0 and the exact setup decides (the lanes' fallback),
 * exactly edge-on ones (through the receiver), a vertex at the receiver, and cells on exact
 * multiples (small integer coordinates make num F / D an integer: the divide's floor correction). */
static void test_raster_every_isa(void **state)
{
    (void)state;
    const uint32_t have = qibl_isa_available();
    const int cfg[][2] = {{32, 48}, {16, 6}, {64, 128}, {32, 20}};
    int runs = 0;
    for (unsigned isa = 0; isa < QIBL_ISA_COUNT; ++isa) {
        if (!(have & QIBL_ISA_BIT(isa)))
            continue;
        qtool_isa_force(QIBL_ISA_BIT(isa));
        uint64_t seed = 0x15A0u; /* the same cases for every choice */
        for (size_t c = 0; c < sizeof cfg / sizeof cfg[0]; ++c) {
            fixture *f = make(cfg[c][0], cfg[c][1]);
            for (int round = 0; round < 30; ++round) {
                enum { NV = 48, NT = 120 };
                int32_t v[NV][3];
                uint32_t tri[NT][3];
                const int32_t B = QIBL_HEMI_LOCAL_MAX;
                for (int i = 0; i < NV; i += 3) {
                    const int kind = (int)(rng(&seed) % 4u);
                    for (int q = 0; q < 3; ++q) {
                        const int32_t e = (int32_t)(rng(&seed) % 0x100000u);
                        if (kind == 0) { /* a roof: z in -2 .. 300 */
                            v[i + q][0] = q == 0 ? -B + e : q == 1 ? B - e : (int32_t)(rng(&seed) % 2000u) - 1000;
                            v[i + q][1] = q == 2 ? B - e : -B + e;
                            v[i + q][2] = (int32_t)(rng(&seed) % 303u) - 2;
                        } else if (kind == 1) { /* small integers: exact cell boundaries */
                            for (int k = 0; k < 3; ++k)
                                v[i + q][k] = (int32_t)(rng(&seed) % 9u) - 4;
                        } else { /* anywhere, at any magnitude */
                            const int bitsz = 1 + (int)(rng(&seed) % 26u);
                            const int32_t lim = bitsz >= 26 ? B : (int32_t)((1u << bitsz) - 1u);
                            for (int k = 0; k < 3; ++k)
                                v[i + q][k] = (int32_t)(rng(&seed) % (2u * (uint32_t)lim + 1u)) - lim;
                        }
                    }
                    if (kind == 3) /* edge-on: the third vertex (a + b) / 2, in the plane of 0, a, b */
                        for (int k = 0; k < 3; ++k) {
                            v[i][k] -= v[i][k] % 2, v[i + 1][k] -= v[i + 1][k] % 2;
                            v[i + 2][k] = v[i][k] / 2 + v[i + 1][k] / 2;
                        }
                }
                v[NV - 1][0] = v[NV - 1][1] = v[NV - 1][2] = 0; /* the receiver itself */
                for (uint32_t t = 0; t < NT; ++t) {
                    const uint32_t g = 3u * (uint32_t)(rng(&seed) % (NV / 3));
                    if (t % 4u == 3u)
                        for (int k = 0; k < 3; ++k)
                            tri[t][k] = (uint32_t)(rng(&seed) % NV);
                    else
                        tri[t][0] = g, tri[t][1] = g + 1u + (uint32_t)(t & 1u), tri[t][2] = g + 2u - (uint32_t)(t & 1u);
                }
                raster_both(f, (const int32_t(*)[3])v, NV, (const uint32_t(*)[3])tri, NT);
            }
            drop(f);
        }
        /* edge normals whose float32 cell estimate (fl(num F) / fl(2 m), truncated) is one off (found
         * by search): one above at F = 128, one below at F = 126 (num F inexact in float32); only
         * the lanes' exact correction step gives the twin's cells */
        for (int fc = 0; fc < 2; ++fc) {
            static const int32_t abs_[2][6][6] = {
                {{-493, -188, -223, -358, 8, 403}, {511, 280, 299, -374, 333, -304}, {351, 503, -253, -383, 224, 98},
                 {-267, -401, 495, -371, -472, -439}, {-430, -474, -343, 69, 299, -400}, {-308, 24, 315, -453, 76, -405}},
                {{142, 0, -497, 402, 417, -65}, {443, -182, -174, -232, -419, 434}, {478, -75, 302, 239, -468, -95},
                 {-456, 419, 259, -507, -101, 153}, {130, -359, 378, -454, -359, -279}, {492, -95, -32, 369, 354, 273}}};
            const int32_t(*ab)[6] = abs_[fc];
            fixture *f = make(32, fc == 0 ? 128 : 126);
            for (size_t r = 0; r < 6; ++r) {
                const int32_t v[4][3] = {{ab[r][0], ab[r][1], ab[r][2]}, {ab[r][3], ab[r][4], ab[r][5]}, {0, 0, 300}, {-5, 7, 200}};
                const uint32_t tri[4][3] = {{0, 1, 2}, {1, 0, 2}, {0, 1, 3}, {1, 0, 3}};
                raster_both(f, v, 4, tri, 4);
            }
            drop(f);
        }
        /* the transform against the twin's, with tails of every length mod 8 */
        {
            enum { NP = 45 };
            qibl_q16_t pos[NP][3];
            int32_t o1[NP][3], o2[NP][3];
            qibl_hemi_frame_t fr;
            const qibl_q16_t p0[3] = {(int32_t)(rng(&seed) % 0x7FFFFFu) - 0x3FFFFF, 0x3FFFFF, -0x3FFFFF};
            const int32_t nrm[3] = {(int32_t)(rng(&seed) % 2001u) - 1000, -700, 300};
            assert_int_equal(qibl_hemi_frame_init(&fr, p0, nrm), QIBL_OK);
            for (int i = 0; i < NP; ++i)
                for (int k = 0; k < 3; ++k)
                    pos[i][k] = i < 3 ? (k == i ? -QIBL_HEMI_COORD_MAX : QIBL_HEMI_COORD_MAX)
                                      : (int32_t)(rng(&seed) % (2u * QIBL_HEMI_COORD_MAX + 1u)) - QIBL_HEMI_COORD_MAX;
            for (uint32_t n = 1; n <= NP; n += 7u) {
                assert_int_equal(qibl_hemi_transform(&fr, (const qibl_q16_t(*)[3])pos, n, o1), QIBL_OK);
                assert_int_equal(qtool_hemi_transform_scalar(&fr, (const qibl_q16_t(*)[3])pos, n, o2), QIBL_OK);
                assert_memory_equal(o1, o2, sizeof(int32_t) * 3u * n);
            }
        }
        /* the roof just above: rasterized (the exact setup), nearly the whole disk */
        fixture *f = make(32, 48);
        const int32_t B = QIBL_HEMI_LOCAL_MAX;
        const int32_t roof[3][3] = {{-B, -B, 3}, {B, -B, 3}, {0, B, 3}};
        uint32_t m[32];
        qibl_hemi_stats_t st;
        raster1(&f->h, roof, m, &st);
        assert_int_equal(st.rasterized, 1u);
        assert_true(bits(&f->h, m) >= disk_bits(&f->h) - 4 * 32);
        drop(f);
        ++runs;
    }
    qtool_isa_force(0u);
    assert_true(runs >= 1);
}

static void test_degenerate(void **state)
{
    (void)state;
    fixture *f = make(32, 60);
    uint32_t m[32];
    qibl_hemi_stats_t st;
    /* collinear, repeated vertex, one point: plane through the receiver or no plane: skipped */
    const int32_t col[3][3] = {{1000, 0, 5000}, {2000, 100, 5000}, {3000, 200, 5000}};
    const int32_t rep[3][3] = {{1000, 0, 5000}, {1000, 0, 5000}, {0, 3000, 5000}};
    const int32_t pt[3][3] = {{1000, 0, 5000}, {1000, 0, 5000}, {1000, 0, 5000}};
    /* collinear points span a plane through the receiver, but each vertex's direction is rounded
     * to 9 bits first (the int32 setup): here a sliver cone along that plane, a few pixels at most,
     * all near it */
    raster1(&f->h, col, m, &st);
    assert_int_equal(st.through + st.rasterized, 1u);
    int cov;
    assert_int_equal(check_triangle(&f->h, col, 2.3 / 60, &cov), 0);
    assert_true(cov <= 4);
    raster1(&f->h, rep, m, &st);
    assert_int_equal(st.through, 1u);
    assert_int_equal(bits(&f->h, m), 0);
    raster1(&f->h, pt, m, &st);
    assert_int_equal(st.through, 1u);
    /* collinear with the receiver (a line through the origin): plane through it */
    const int32_t line[3][3] = {{1000, 1000, 1000}, {2000, 2000, 2000}, {0, 5000, 3000}};
    raster1(&f->h, line, m, &st);
    assert_int_equal(st.through, 1u);
    /* edge-on: the triangle's plane contains the receiver */
    const int32_t edge_on[3][3] = {{100000, 0, 0}, {0, 100000, 100000}, {-50000, 50000, 50000}};
    raster1(&f->h, edge_on, m, &st);
    assert_int_equal(st.through, 1u);
    assert_int_equal(bits(&f->h, m), 0);
    /* sharing the receiver vertex (a vertex at the origin) */
    const int32_t shared[3][3] = {{0, 0, 0}, {100000, 0, 50000}, {0, 100000, 50000}};
    raster1(&f->h, shared, m, &st);
    assert_int_equal(st.through, 1u);
    assert_int_equal(bits(&f->h, m), 0);
    drop(f);
}

static void test_sliver(void **state)
{
    (void)state;
    fixture *f = make(32, 60);
    const double delta = 2.3 / 60;
    /* 1 LSB wide, long: covers at most the pixels its quantised planes allow, all near it */
    const int32_t sl[3][3] = {{-3000000, 0, 1000000}, {3000000, 0, 1000000}, {3000000, 1, 1000000}};
    int cov;
    assert_int_equal(check_triangle(&f->h, sl, delta, &cov), 0);
    assert_true(cov <= 32);
    /* thin but not degenerate: the cone test holds */
    const int32_t th[3][3] = {{-3000000, 0, 1000000}, {3000000, 0, 1000000}, {0, 20000, 1000000}};
    assert_int_equal(check_triangle(&f->h, th, delta, NULL), 0);
    drop(f);
}

static void test_horizon(void **state)
{
    (void)state;
    fixture *f = make(32, 60);
    uint32_t m[32];
    qibl_hemi_stats_t st;
    const double delta = 2.3 / 60;
    /* every vertex exactly on the horizon: culled */
    const int32_t flat[3][3] = {{100000, 0, 0}, {0, 100000, 0}, {-100000, -100000, 0}};
    raster1(&f->h, flat, m, &st);
    assert_int_equal(st.below, 1u);
    /* below: culled */
    const int32_t below[3][3] = {{100000, 0, -1}, {0, 100000, -5}, {-100000, -100000, -1}};
    raster1(&f->h, below, m, &st);
    assert_int_equal(st.below, 1u);
    assert_int_equal(bits(&f->h, m), 0);
    /* two on the horizon, one above: rasterized, as the cone test says */
    const int32_t two[3][3] = {{400000, -100000, 0}, {400000, 100000, 0}, {400000, 0, 300000}};
    raster1(&f->h, two, m, &st);
    assert_int_equal(st.rasterized, 1u);
    assert_int_equal(check_triangle(&f->h, two, delta, NULL), 0);
    /* crossing the horizon: no clipping needed */
    const int32_t cross_h[3][3] = {{300000, -200000, -300000}, {300000, 200000, -300000}, {300000, 0, 300000}};
    int cov;
    assert_int_equal(check_triangle(&f->h, cross_h, delta, &cov), 0);
    assert_true(cov > 10);
    drop(f);
}

static void test_huge_tiny_1lsb(void **state)
{
    (void)state;
    fixture *f = make(32, 60);
    uint32_t m[32];
    qibl_hemi_stats_t st;
    const double delta = 2.3 / 60;
    const int32_t B = QIBL_HEMI_LOCAL_MAX;
    /* huge, 1 LSB above the receiver: covers all but the horizon ring */
    const int32_t roof[3][3] = {{-B, -B, 1}, {B, -B, 1}, {0, B, 1}};
    raster1(&f->h, roof, m, &st);
    assert_int_equal(st.rasterized, 1u);
    assert_int_equal(check_triangle(&f->h, roof, delta, NULL), 0);
    const int all = disk_bits(&f->h), got = bits(&f->h, m);
    assert_true(got >= all - 4 * 32 && got < all);
    /* the same at height 0 passes through the receiver; at -1 it is below */
    const int32_t roof0[3][3] = {{-B, -B, 0}, {B, -B, 0}, {0, B, 0}};
    raster1(&f->h, roof0, m, &st);
    assert_int_equal(st.below, 1u);
    const int32_t tilt0[3][3] = {{-B, -B, -B / 4}, {B, -B, -B / 4}, {0, B, B / 4}};
    raster1(&f->h, tilt0, m, &st);
    assert_int_equal(st.through, 1u); /* plane z B = (B / 4) y contains the receiver */
    /* tiny: a 1 LSB triangle far away covers at most a few pixels, all near its direction */
    const int32_t tiny[3][3] = {{300000, 200000, 500000}, {300001, 200000, 500000}, {300000, 200001, 500000}};
    int cov;
    assert_int_equal(check_triangle(&f->h, tiny, delta, &cov), 0);
    assert_true(cov <= 4);
    /* huge extents in every direction (cross products near their 2^53 bound) */
    const int32_t big[3][3] = {{B, B, B}, {-B, B, B / 2}, {B, -B, B / 3}};
    assert_int_equal(check_triangle(&f->h, big, delta, NULL), 0);
    drop(f);
}

/* ---- transfer ----------------------------------------------------------------------------------- */

/* double reference: integral over the disk of Y_i V, V = 1 where not blocked by the triangles
 * (exact cone test per sample), on a g x g grid of the disk */
static void ref_transfer(const int32_t (*v)[3], const uint32_t (*tri)[3], int ntri, int g, double out[25])
{
    memset(out, 0, 25 * sizeof(double));
    double e[64][3][3];
    int ok[64];
    for (int t = 0; t < ntri; ++t) {
        const int32_t *a = v[tri[t][0]], *b = v[tri[t][1]], *c = v[tri[t][2]];
        dcross(a, b, e[t][0]), dcross(b, c, e[t][1]), dcross(c, a, e[t][2]);
        const double det = e[t][0][0] * c[0] + e[t][0][1] * c[1] + e[t][0][2] * c[2];
        ok[t] = det != 0;
        for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k)
                e[t][i][k] *= det < 0 ? -1 : 1;
    }
    const double dA = (2.0 / g) * (2.0 / g);
    for (int r = 0; r < g; ++r)
        for (int c = 0; c < g; ++c) {
            const double x = (2.0 * c + 1 - g) / g, y = (2.0 * r + 1 - g) / g, q = 1 - x * x - y * y;
            if (q <= 0)
                continue;
            const double s[3] = {x, y, sqrt(q)};
            int blocked = 0;
            for (int t = 0; t < ntri && !blocked; ++t) {
                int in = ok[t];
                for (int i = 0; i < 3; ++i)
                    in &= e[t][i][0] * s[0] + e[t][i][1] * s[1] + e[t][i][2] * s[2] > 0;
                blocked = in;
            }
            if (blocked)
                continue;
            double yv[25];
            qtool_ref_sh_eval(s[0], s[1], s[2], 5, yv);
            for (int i = 0; i < 25; ++i)
                out[i] += yv[i] * dA;
        }
}

static double rel_l2(const qibl_q30_t *got, const double *ref)
{
    double num = 0, den = 0;
    for (int i = 0; i < 25; ++i) {
        const double d = got[i] / 1073741824.0 - ref[i];
        num += d * d, den += ref[i] * ref[i];
    }
    return sqrt(num / den);
}

static void test_transfer_unblocked(void **state)
{
    (void)state;
    /* the clamped cosine: zonal, V*_(l,0) = 2 pi int_0^1 Y_l0(z) z dz; others 0 */
    const int sizes[3] = {16, 32, 64};
    for (int k = 0; k < 3; ++k) {
        fixture *f = make(sizes[k], 8);
        uint32_t m[QIBL_HEMI_MAX_WORDS];
        assert_int_equal(qibl_hemi_clear(&f->h, m), QIBL_OK);
        qibl_q30_t out[25];
        assert_int_equal(qibl_hemi_transfer(&f->h, m, out), QIBL_OK);
        double ref[25] = {0};
        const int steps = 200000;
        for (int j = 0; j < steps; ++j) {
            const double z = (j + 0.5) / steps, sxy = sqrt(1 - z * z);
            double yv[25];
            qtool_ref_sh_eval(sxy, 0, z, 5, yv);
            for (int l = 0; l <= 4; ++l)
                ref[l * l + l] += 2 * PI * yv[l * l + l] * z / steps;
        }
        assert_true(fabs(ref[0] - sqrt(PI) / 2) < 1e-9);
        for (int i = 0; i < 25; ++i)
            assert_true(fabs(out[i] / 1073741824.0 - ref[i]) < 1e-3); /* the sub-sampled disk edge */
        drop(f);
    }
}

static void test_transfer_blocked(void **state)
{
    (void)state;
    fixture *f = make(32, 60);
    /* a wall, a box-like pair and a random set, against the fine double integral */
    const int32_t v[8][3] = {{200000, -4000000, -100000}, {200000, 4000000, -100000}, {200000, 0, 4000000},
                             {-300000, 100000, 200000},  {-100000, 500000, 300000},  {-500000, 400000, 100000},
                             {0, -300000, 150000},       {-200000, -200000, 400000}};
    const uint32_t tri[4][3] = {{0, 1, 2}, {3, 4, 5}, {3, 6, 7}, {6, 7, 0}};
    for (int nt = 1; nt <= 4; ++nt) {
        uint32_t m[32];
        assert_int_equal(qibl_hemi_clear(&f->h, m), QIBL_OK);
        assert_int_equal(qibl_hemi_raster(&f->h, v, 8, tri, (uint32_t)nt, m, NULL), QIBL_OK);
        qibl_q30_t out[25];
        assert_int_equal(qibl_hemi_transfer(&f->h, m, out), QIBL_OK);
        double ref[25];
        ref_transfer(v, tri, nt, 1024, ref);
        const double e = rel_l2(out, ref);
        assert_true(e < 0.05); /* one to four triangles: 0.7 % .. 3.2 % at 32 x 32, F = 60 */
    }
    drop(f);
}

static void test_transfer_paths_agree(void **state)
{
    (void)state;
    /* transfer(M) + transfer(disk & ~M) == transfer(empty) bit for bit: one of the two masks is
     * more than half blocked, so both summation paths run, and wrapping sums are exact */
    const int sizes[3] = {16, 32, 64};
    uint64_t s = 5;
    for (int k = 0; k < 3; ++k) {
        fixture *f = make(sizes[k], 4);
        for (int rep = 0; rep < 20; ++rep) {
            uint32_t m[QIBL_HEMI_MAX_WORDS], c[QIBL_HEMI_MAX_WORDS], z[QIBL_HEMI_MAX_WORDS];
            const uint64_t density = rng(&s) % 4;
            for (uint32_t i = 0; i < f->h.words; ++i) {
                uint32_t w = (uint32_t)rng(&s);
                for (uint64_t d = 0; d < density; ++d)
                    w &= (uint32_t)rng(&s);
                m[i] = rep & 1 ? w : ~w;
                c[i] = ~m[i] & f->h.disk[i];
                z[i] = 0;
            }
            qibl_q30_t a[25], b[25], e[25];
            assert_int_equal(qibl_hemi_transfer(&f->h, m, a), QIBL_OK);
            assert_int_equal(qibl_hemi_transfer(&f->h, c, b), QIBL_OK);
            assert_int_equal(qibl_hemi_transfer(&f->h, z, e), QIBL_OK);
            for (int i = 0; i < 25; ++i)
                assert_int_equal((uint32_t)a[i] + (uint32_t)b[i], (uint32_t)e[i]);
        }
        drop(f);
    }
}

/* ---- glossy (Phong) transfer -------------------------------------------------------------------- */

/* the midpoint formula of the header in double: sum over visible pixels of T[p] max(0, r.s_p)^e */
static void phong_mid(const qibl_hemi_t *h, const uint32_t *m, const double r[3], uint32_t e, double out[25])
{
    for (int i = 0; i < 25; ++i)
        out[i] = 0;
    for (int row = 0; row < h->n; ++row)
        for (int c = 0; c < h->n; ++c) {
            double s[3];
            if (!sample(h->n, row, c, s) || get_bit(h, m, row, c))
                continue;
            const double d = r[0] * s[0] + r[1] * s[1] + r[2] * s[2];
            const double w = e == 0 ? 1.0 : d > 0 ? pow(d, (double)e) : 0.0;
            const uint32_t *t = h->basis + ((size_t)row * (size_t)h->n + (size_t)c) * 25;
            for (int i = 0; i < 25; ++i)
                out[i] += (int32_t)t[i] / 1073741824.0 * w;
        }
}

/* the true integral over the disk (fine quadrature, K x K points per pixel) with the mask as V */
static void phong_fine(const qibl_hemi_t *h, const uint32_t *m, const double r[3], uint32_t e, int K, double out[25])
{
    const int n = h->n;
    for (int i = 0; i < 25; ++i)
        out[i] = 0;
    const double da = (2.0 / n / K) * (2.0 / n / K);
    for (int row = 0; row < n; ++row)
        for (int c = 0; c < n; ++c) {
            if (get_bit(h, m, row, c))
                continue;
            for (int a = 0; a < K; ++a)
                for (int b = 0; b < K; ++b) {
                    const double x = -1 + 2.0 * (c + (b + 0.5) / K) / n, y = -1 + 2.0 * (row + (a + 0.5) / K) / n;
                    const double q = 1 - x * x - y * y;
                    if (q <= 0)
                        continue;
                    const double s[3] = {x, y, sqrt(q)};
                    const double d = r[0] * s[0] + r[1] * s[1] + r[2] * s[2];
                    if (d <= 0 && e > 0)
                        continue;
                    const double w = e == 0 ? 1.0 : pow(d, (double)e);
                    double yv[25];
                    qtool_ref_sh_eval(s[0], s[1], s[2], 5, yv);
                    for (int i = 0; i < 25; ++i)
                        out[i] += yv[i] * w * da;
                }
        }
}

static double rel_l2d(const qibl_q30_t *a, const double *ref)
{
    double d2 = 0, n2 = 0;
    for (int i = 0; i < 25; ++i) {
        const double d = a[i] / 1073741824.0 - ref[i];
        d2 += d * d, n2 += ref[i] * ref[i];
    }
    return n2 > 0 ? sqrt(d2 / n2) : sqrt(d2);
}

static void test_transfer_phong(void **state)
{
    (void)state;
    uint64_t s = 77;
    const int sizes[3] = {16, 32, 64};
    double worst_mid = 0, worst_fine[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) {
        fixture *f = make(sizes[k], 8);
        const qibl_hemi_t *h = &f->h;
        for (int rep = 0; rep < 24; ++rep) {
            uint32_t m[QIBL_HEMI_MAX_WORDS];
            for (uint32_t i = 0; i < h->words; ++i)
                m[i] = rep % 3 == 0 ? 0u : (uint32_t)rng(&s) & (uint32_t)rng(&s);
            /* e = 0 is the diffuse transfer, bit for bit */
            qibl_q30_t a[25], b[25];
            const qibl_q30_t up[3] = {1000, -2000, 1 << 20};
            assert_int_equal(qibl_hemi_transfer(h, m, a), QIBL_OK);
            assert_int_equal(qibl_hemi_transfer_phong(h, m, up, 0, b), QIBL_OK);
            for (int i = 0; i < 25; ++i)
                assert_int_equal(a[i], b[i]);
            /* the midpoint formula in double, any reflection direction (also below the horizon) */
            double r[3] = {urand(&s) * 2 - 1, urand(&s) * 2 - 1, urand(&s) * 2 - (rep % 4 == 1 ? 1.2 : 0.2)};
            const double l = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
            for (int j = 0; j < 3; ++j)
                r[j] /= l;
            const qibl_q30_t rq[3] = {(qibl_q30_t)(r[0] * 1073741823.0), (qibl_q30_t)(r[1] * 1073741823.0),
                                      (qibl_q30_t)(r[2] * 1073741823.0)};
            static const uint32_t es[] = {1, 4, 16, 100, 4096};
            for (size_t ei = 0; ei < sizeof es / sizeof es[0]; ++ei) {
                double ref[25], big = 0, d2 = 0;
                phong_mid(h, m, r, es[ei], ref);
                assert_int_equal(qibl_hemi_transfer_phong(h, m, rq, es[ei], b), QIBL_OK);
                for (int i = 0; i < 25; ++i) {
                    big = fmax(big, fabs(ref[i]));
                    d2 = fmax(d2, fabs(b[i] / 1073741824.0 - ref[i]));
                }
                /* the weights cut to 2^-15 (and a few Q30 LSB of d^e) per pixel: at most 2^-14 of
                 * each pixel's |T|, summed over the disk, plus 2e-4 relative */
                double tabs = 0;
                for (int p = 0; p < h->n * h->n; ++p) {
                    double mx = 0;
                    for (int i = 0; i < 25; ++i)
                        mx = fmax(mx, fabs((int32_t)h->basis[(size_t)p * 25 + (size_t)i] / 1073741824.0));
                    tabs += mx;
                }
                const double tol = 2e-4 * big + tabs / 16384.0;
                if (d2 > tol)
                    fail_msg("n %d e %u: |phong - midpoint| %.3g > %.3g", h->n, es[ei], d2, tol);
                if (big > 1e-3)
                    worst_mid = fmax(worst_mid, d2 / big);
            }
            /* the lobe constant per pixel against the true integral: small for low exponents */
            if (rep < 6 && sizes[k] <= 32 && r[2] > 0.3) { /* lobes well above the horizon */
                static const uint32_t ef[3] = {1, 8, 32};
                for (int ei = 0; ei < 3; ++ei) {
                    double ref[25];
                    phong_fine(h, m, r, ef[ei], 8, ref);
                    assert_int_equal(qibl_hemi_transfer_phong(h, m, rq, ef[ei], b), QIBL_OK);
                    const double e = rel_l2d(b, ref);
                    if (sizes[k] == 32)
                        worst_fine[ei] = fmax(worst_fine[ei], e);
                }
            }
        }
        drop(f);
    }
    printf("hemi: phong vs its midpoint formula: worst %.2e relative; vs the true integral at 32 x 32, "
           "exponent 1/8/32: %.2f %% / %.2f %% / %.2f %%\n", worst_mid, 100 * worst_fine[0], 100 * worst_fine[1],
           100 * worst_fine[2]);
    /* measured 0.20 / 0.22 / 0.34 %: the lobe taken constant per pixel costs little above the horizon */
    for (int i = 0; i < 3; ++i)
        assert_true(worst_fine[i] > 0 && worst_fine[i] < (i < 2 ? 0.01 : 0.02));
    assert_true(worst_mid < 0.01);
    /* errors, nothing written */
    fixture *f = make(32, 8);
    uint32_t m[32] = {0};
    qibl_q30_t out[25];
    for (int i = 0; i < 25; ++i)
        out[i] = 12345;
    const qibl_q30_t zero[3] = {0, 0, 0}, up[3] = {0, 0, 1 << 30};
    assert_int_equal(qibl_hemi_transfer_phong(&f->h, m, up, QIBL_HEMI_MAX_EXPONENT + 1u, out), QIBL_E_HEMI_EXPONENT);
    assert_int_equal(qibl_hemi_transfer_phong(&f->h, m, zero, 8, out), QIBL_E_ZERO_VECTOR);
    assert_int_equal(qibl_hemi_transfer_phong(NULL, m, up, 8, out), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_hemi_transfer_phong(&f->h, NULL, up, 8, out), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_hemi_transfer_phong(&f->h, m, NULL, 8, out), QIBL_E_NULL_POINTER);
    for (int i = 0; i < 25; ++i)
        assert_int_equal(out[i], 12345);
    assert_int_equal(qibl_hemi_transfer_phong(&f->h, m, up, 8, NULL), QIBL_E_NULL_POINTER);
    assert_string_not_equal(qibl_status_str(QIBL_E_HEMI_EXPONENT), "unknown status");
    drop(f);
}

/* ---- frames and rotation ------------------------------------------------------------------------ */

static void test_frame(void **state)
{
    (void)state;
    qibl_hemi_frame_t fr;
    const qibl_q16_t p[3] = {0, 0, 0};
    const int32_t zero[3] = {0, 0, 0}, up[3] = {0, 0, 5}, down[3] = {0, 0, -1};
    assert_int_equal(qibl_hemi_frame_init(&fr, p, zero), QIBL_E_ZERO_VECTOR);
    const qibl_q16_t far[3] = {QIBL_HEMI_COORD_MAX + 1, 0, 0};
    assert_int_equal(qibl_hemi_frame_init(&fr, far, up), QIBL_E_HEMI_RANGE);
    assert_int_equal(qibl_hemi_frame_init(NULL, p, up), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_hemi_frame_init(&fr, p, up), QIBL_OK);
    assert_int_equal(fr.axis[0][0], QIBL_Q30_ONE);
    assert_int_equal(fr.axis[2][2], QIBL_Q30_ONE);
    assert_int_equal(qibl_hemi_frame_init(&fr, p, down), QIBL_OK);
    assert_int_equal(fr.axis[2][2], -QIBL_Q30_ONE);
    uint64_t s = 9;
    for (int t = 0; t < 2000; ++t) {
        int32_t n[3];
        for (int k = 0; k < 3; ++k)
            n[k] = (int32_t)(rng(&s) % 2000001) - 1000000;
        if (t % 10 == 0)
            n[0] = n[1] = (int32_t)(t % 3) - 1; /* near the poles */
        if (!n[0] && !n[1] && !n[2])
            continue;
        assert_int_equal(qibl_hemi_frame_init(&fr, p, n), QIBL_OK);
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                double d = 0;
                for (int k = 0; k < 3; ++k)
                    d += fr.axis[i][k] / 1073741824.0 * (fr.axis[j][k] / 1073741824.0);
                assert_true(fabs(d - (i == j)) < 1e-8);
            }
        double nl = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
        for (int k = 0; k < 3; ++k)
            assert_true(fabs(fr.axis[2][k] / 1073741824.0 - n[k] / nl) < 1e-8);
        /* right-handed: t x b = n */
        const double t0 = fr.axis[0][0] / 1073741824.0, t1 = fr.axis[0][1] / 1073741824.0,
                     t2 = fr.axis[0][2] / 1073741824.0, b0 = fr.axis[1][0] / 1073741824.0,
                     b1 = fr.axis[1][1] / 1073741824.0, b2 = fr.axis[1][2] / 1073741824.0;
        assert_true(fabs(t1 * b2 - t2 * b1 - n[0] / nl) < 1e-8);
        assert_true(fabs(t0 * b1 - t1 * b0 - n[2] / nl) < 1e-8);
    }
}

static void test_transform(void **state)
{
    (void)state;
    qibl_hemi_frame_t fr;
    const qibl_q16_t p[3] = {65536, -131072, 30000};
    const int32_t n[3] = {3, -4, 12};
    assert_int_equal(qibl_hemi_frame_init(&fr, p, n), QIBL_OK);
    qibl_q16_t pos[4][3] = {{65536, -131072, 30000}, {QIBL_HEMI_COORD_MAX, -QIBL_HEMI_COORD_MAX, QIBL_HEMI_COORD_MAX},
                            {-QIBL_HEMI_COORD_MAX, QIBL_HEMI_COORD_MAX, -QIBL_HEMI_COORD_MAX}, {65536 + 3, -131072 - 4, 30000 + 12}};
    int32_t out[4][3];
    assert_int_equal(qibl_hemi_transform(&fr, pos, 4, out), QIBL_OK);
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 3; ++j) {
            double d = 0;
            for (int i = 0; i < 3; ++i)
                d += fr.axis[j][i] / 1073741824.0 * ((double)pos[k][i] - p[i]);
            assert_true(fabs(out[k][j] - d * 4) <= 0.5 + 1e-6 * fabs(d));
        }
    assert_int_equal(out[0][0], 0), assert_int_equal(out[0][2], 0);
    assert_int_equal(out[3][2], 13 * 4); /* along the normal: |(3,-4,12)| = 13 */
    int32_t keep[4][3];
    memcpy(keep, out, sizeof out);
    pos[2][1] = QIBL_HEMI_COORD_MAX + 1;
    assert_int_equal(qibl_hemi_transform(&fr, pos, 4, out), QIBL_E_HEMI_RANGE);
    assert_memory_equal(keep, out, sizeof out);
}

static void rot_from_frame(const qibl_hemi_frame_t *fr, qibl_q30_t r[3][3])
{
    /* R maps local to world: its columns are t, b, n (the frame's rows) */
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            r[i][j] = fr->axis[j][i];
}

static void test_rotation(void **state)
{
    (void)state;
    fixture *f = make(16, 4);
    uint64_t s = 31;
    double worst = 0;
    for (int t = 0; t < 300; ++t) {
        int32_t n[3];
        for (int k = 0; k < 3; ++k)
            n[k] = (int32_t)(rng(&s) % 2001) - 1000;
        if (t < 4)
            n[0] = n[1] = 0, n[2] = t % 2 ? 1 : -1;
        if (!n[0] && !n[1] && !n[2])
            continue;
        qibl_hemi_frame_t fr;
        const qibl_q16_t p[3] = {0, 0, 0};
        assert_int_equal(qibl_hemi_frame_init(&fr, p, n), QIBL_OK);
        qibl_q30_t r[3][3];
        rot_from_frame(&fr, r);
        qibl_sh_rotation_t rot;
        assert_int_equal(qibl_sh_rotation_init(&rot, r, 5), QIBL_OK);
        qibl_q30_t in[25], a[25], b[25], back[25];
        for (int i = 0; i < 25; ++i)
            in[i] = (int32_t)(rng(&s) % (1u << 29)) - (1 << 28);
        assert_int_equal(qibl_hemi_to_world(&f->h, &fr, in, a), QIBL_OK);
        assert_int_equal(qibl_sh_rotate(&rot, in, b), QIBL_OK);
        for (int i = 0; i < 25; ++i) {
            const double e = fabs((double)a[i] - b[i]) / (1 << 28);
            worst = e > worst ? e : worst;
        }
        assert_int_equal(qibl_hemi_to_frame(&f->h, &fr, a, back), QIBL_OK);
        for (int i = 0; i < 25; ++i)
            assert_true(fabs((double)back[i] - in[i]) / (1 << 28) < 1e-6);
    }
    assert_true(worst < 1e-6);
    /* shading is the same whichever side is rotated */
    fixture *g = f;
    qibl_hemi_frame_t fr;
    const qibl_q16_t p[3] = {0, 0, 0};
    const int32_t n[3] = {1, 2, -3};
    assert_int_equal(qibl_hemi_frame_init(&fr, p, n), QIBL_OK);
    int32_t light[3][25], lloc[3][25];
    qibl_q30_t v[25], vw[25];
    for (int i = 0; i < 25; ++i) {
        v[i] = (int32_t)(rng(&s) % (1u << 30)) - (1 << 29);
        for (int ch = 0; ch < 3; ++ch)
            light[ch][i] = (int32_t)(rng(&s) % (1u << 20));
    }
    assert_int_equal(qibl_hemi_to_world(&g->h, &fr, v, vw), QIBL_OK);
    for (int ch = 0; ch < 3; ++ch)
        assert_int_equal(qibl_hemi_to_frame(&g->h, &fr, light[ch], lloc[ch]), QIBL_OK);
    qibl_q16_t c1[3], c2[3];
    assert_int_equal(qibl_hemi_shade(light, vw, c1), QIBL_OK);
    assert_int_equal(qibl_hemi_shade(lloc, v, c2), QIBL_OK);
    for (int ch = 0; ch < 3; ++ch) {
        double d = 0;
        for (int i = 0; i < 25; ++i)
            d += light[ch][i] * (vw[i] / 1073741824.0);
        assert_true(fabs(c1[ch] - d) <= 1.0);
        assert_true(abs(c1[ch] - c2[ch]) <= 4);
    }
    assert_int_equal(qibl_hemi_shade(NULL, v, c1), QIBL_E_NULL_POINTER);
    drop(f);
}

/* ---- the tables blob (qibl_hemi_tables_*, qibl_hemi_open) ---------------------------------------- */

/* the payload of h's tables in the blob's order: disk, full, basis, lut, zc */
static void expect_payload(const qibl_hemi_t *h, const uint32_t *p)
{
    const uint32_t n2 = (uint32_t)h->n * (uint32_t)h->n, lutw = 3u * (uint32_t)h->face * (uint32_t)h->face * h->words;
    assert_memory_equal(p, h->disk, 4u * h->words);
    p += h->words;
    assert_memory_equal(p, h->full, 4u * 25u);
    p += 25;
    assert_memory_equal(p, h->basis, 4u * 25u * n2);
    p += 25u * n2;
    assert_memory_equal(p, h->lut, 4u * lutw);
    p += lutw;
    assert_memory_equal(p, h->zc, 4u * n2);
}

/* the blob for (n, face), built whole (malloc'd, words) */
static uint32_t *blob_of(int n, int face, size_t *size)
{
    *size = qibl_hemi_tables_size(n, face);
    assert_true(*size > 32u && *size % 4u == 0u);
    uint32_t *b = malloc(*size + 8u);
    assert_non_null(b);
    assert_int_equal(qibl_hemi_tables_build(n, face, 0, (uint32_t)(*size / 4u), b), QIBL_OK);
    return b;
}

/* qibl_hemi_init = build + open: the blob built whole and in chunks of odd sizes holds init's
 * tables word for word; the header's CRC word made alone (streamed) is the whole build's; the
 * opened h gives the same masks, transfers, glossy transfers and rotations as init's. */
static void test_tables_blob_is_init(void **state)
{
    (void)state;
    const int cfg[][2] = {{16, 8}, {32, 6}, {64, 4}, {32, 24}};
    uint64_t seed = 0x7AB1Eu;
    for (size_t c = 0; c < sizeof cfg / sizeof cfg[0]; ++c) {
        const int n = cfg[c][0], face = cfg[c][1];
        fixture *f = make(n, face);
        size_t size;
        uint32_t *whole = blob_of(n, face, &size);
        const uint32_t total = (uint32_t)(size / 4u);
        assert_int_equal(total * 4u, (uint32_t)qibl_hemi_workspace_size(n, face) - 2u * sizeof(qibl_sh_rotation_t) - 4u + 32u);
        assert_int_equal(whole[0], 0x544D4851u);
        assert_int_equal(whole[1], QIBL_HEMI_TABLES_VERSION);
        assert_int_equal(whole[2], (uint32_t)n);
        assert_int_equal(whole[3], (uint32_t)face);
        assert_int_equal(whole[4], (uint32_t)size);
        assert_int_equal(whole[6], 0u);
        assert_int_equal(whole[7], 0u);
        expect_payload(&f->h, whole + 8);
        /* chunks of odd sizes, each followed by a guard word that must stay */
        static const uint32_t sizes[] = {1u, 7u, 25u, 3u, 97u, 1001u, 5u, 24u, 26u, 4099u};
        uint32_t *chunked = malloc(size + 4u);
        assert_non_null(chunked);
        for (uint32_t first = 0, k = 0; first < total; ++k) {
            uint32_t cnt = sizes[k % (sizeof sizes / sizeof sizes[0])];
            cnt = cnt < total - first ? cnt : total - first;
            chunked[first + cnt] = 0xC0FFEEu;
            assert_int_equal(qibl_hemi_tables_build(n, face, first, cnt, chunked + first), QIBL_OK);
            assert_int_equal(chunked[first + cnt], 0xC0FFEEu);
            first += cnt;
        }
        assert_memory_equal(chunked, whole, size);
        uint32_t crc = 0;
        assert_int_equal(qibl_hemi_tables_build(n, face, 5, 1, &crc), QIBL_OK); /* the CRC word, streamed */
        assert_int_equal(crc, whole[5]);
        free(chunked);
        /* opened in place: the same tables, the same results */
        uint32_t rws[(QIBL_HEMI_OPEN_WORKSPACE_SIZE + 3u) / 4u];
        qibl_hemi_t g;
        assert_int_equal(qibl_hemi_open(&g, n, face, whole, size, rws, sizeof rws), QIBL_OK);
        assert_int_equal(g.n, n);
        assert_int_equal(g.face, face);
        assert_int_equal(g.words, f->h.words);
        assert_int_equal(g.wpr, f->h.wpr);
        expect_payload(&g, whole + 8);
        assert_memory_equal(g.rx_pos, f->h.rx_pos, sizeof(qibl_sh_rotation_t));
        assert_memory_equal(g.rx_neg, f->h.rx_neg, sizeof(qibl_sh_rotation_t));
        for (int round = 0; round < 20; ++round) {
            enum { NV = 24, NT = 30 };
            int32_t v[NV][3];
            uint32_t tri[NT][3];
            for (int i = 0; i < NV; ++i)
                for (int k = 0; k < 3; ++k)
                    v[i][k] = (int32_t)(rng(&seed) % (1u << 21)) - (1 << 20);
            for (int t = 0; t < NT; ++t)
                for (int k = 0; k < 3; ++k)
                    tri[t][k] = (uint32_t)(rng(&seed) % NV);
            uint32_t ma[QIBL_HEMI_MAX_WORDS], mb[QIBL_HEMI_MAX_WORDS];
            assert_int_equal(qibl_hemi_clear(&f->h, ma), QIBL_OK);
            assert_int_equal(qibl_hemi_clear(&g, mb), QIBL_OK);
            assert_int_equal(qibl_hemi_raster(&f->h, (const int32_t(*)[3])v, NV, (const uint32_t(*)[3])tri, NT, ma, NULL), QIBL_OK);
            assert_int_equal(qibl_hemi_raster(&g, (const int32_t(*)[3])v, NV, (const uint32_t(*)[3])tri, NT, mb, NULL), QIBL_OK);
            assert_memory_equal(ma, mb, 4u * f->h.words);
            qibl_q30_t ta[25], tb[25];
            assert_int_equal(qibl_hemi_transfer(&f->h, ma, ta), QIBL_OK);
            assert_int_equal(qibl_hemi_transfer(&g, mb, tb), QIBL_OK);
            assert_memory_equal(ta, tb, sizeof ta);
            const qibl_q30_t refl[3] = {(int32_t)(rng(&seed) >> 34) - (1 << 29), (int32_t)(rng(&seed) >> 34) - (1 << 29),
                                        1 << 29};
            assert_int_equal(qibl_hemi_transfer_phong(&f->h, ma, refl, 9u, ta), QIBL_OK);
            assert_int_equal(qibl_hemi_transfer_phong(&g, mb, refl, 9u, tb), QIBL_OK);
            assert_memory_equal(ta, tb, sizeof ta);
            const int32_t nrm[3] = {(int32_t)(rng(&seed) >> 40) - (1 << 23), 5, 1 << 22};
            const qibl_q16_t p[3] = {0, 0, 0};
            qibl_hemi_frame_t fr;
            assert_int_equal(qibl_hemi_frame_init(&fr, p, nrm), QIBL_OK);
            qibl_q30_t wa[25], wb[25];
            assert_int_equal(qibl_hemi_to_world(&f->h, &fr, ta, wa), QIBL_OK);
            assert_int_equal(qibl_hemi_to_world(&g, &fr, tb, wb), QIBL_OK);
            assert_memory_equal(wa, wb, sizeof wa);
        }
        free(whole);
        drop(f);
    }
}

static void test_tables_build_errors(void **state)
{
    (void)state;
    assert_int_equal(qibl_hemi_tables_size(24, 8), 0u);
    assert_int_equal(qibl_hemi_tables_size(32, 7), 0u);
    assert_int_equal(qibl_hemi_tables_size(32, 130), 0u);
    assert_int_equal(qibl_hemi_tables_size(32, 24), 327940u); /* 32 + 4 (M + 25 + 26 N^2 + 3 F^2 M) */
    assert_int_equal(qibl_hemi_tables_size(64, 8), 524932u);
    const uint32_t total = (uint32_t)(qibl_hemi_tables_size(16, 8) / 4u);
    uint32_t out[4] = {1u, 2u, 3u, 4u};
    assert_int_equal(qibl_hemi_tables_build(16, 8, 0, 1, NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_hemi_tables_build(17, 8, 0, 1, out), QIBL_E_HEMI_SIZE);
    assert_int_equal(qibl_hemi_tables_build(16, 9, 0, 1, out), QIBL_E_HEMI_SIZE);
    assert_int_equal(qibl_hemi_tables_build(16, 8, total, 1, out), QIBL_E_HEMI_TABLES_BOUNDS);
    assert_int_equal(qibl_hemi_tables_build(16, 8, total - 3u, 4, out), QIBL_E_HEMI_TABLES_BOUNDS);
    assert_int_equal(qibl_hemi_tables_build(16, 8, total + 1u, 0, out), QIBL_E_HEMI_TABLES_BOUNDS);
    assert_int_equal(qibl_hemi_tables_build(16, 8, 2, UINT32_MAX, out), QIBL_E_HEMI_TABLES_BOUNDS);
    assert_int_equal(out[0] + out[1] + out[2] + out[3], 10u); /* untouched */
    assert_int_equal(qibl_hemi_tables_build(16, 8, total, 0, NULL), QIBL_OK); /* the empty span at the end */
    assert_int_equal(qibl_hemi_tables_build(16, 8, total - 3u, 3, out), QIBL_OK);
    assert_int_equal(out[3], 4u);
}

/* opening a damaged blob: the named status, *h and the workspace untouched */
static void expect_open(const uint32_t *b, size_t size, int n, int face, qibl_status_t want)
{
    uint32_t rws[(QIBL_HEMI_OPEN_WORKSPACE_SIZE + 3u) / 4u], rws0[sizeof rws / 4u];
    memset(rws, 0xA5, sizeof rws);
    memcpy(rws0, rws, sizeof rws);
    qibl_hemi_t h, before;
    memset(&h, 0x5A, sizeof h);
    before = h;
    assert_int_equal(qibl_hemi_open(&h, n, face, b, size, rws, sizeof rws), want);
    assert_memory_equal(&h, &before, sizeof h);
    assert_memory_equal(rws, rws0, sizeof rws);
}

static void test_tables_open_errors(void **state)
{
    (void)state;
    size_t size;
    uint32_t *b = blob_of(16, 8, &size);
    const uint32_t total = (uint32_t)(size / 4u);
    uint32_t rws[(QIBL_HEMI_OPEN_WORKSPACE_SIZE + 3u) / 4u];
    qibl_hemi_t h;
    assert_int_equal(qibl_hemi_open(&h, 16, 8, b, size, rws, sizeof rws), QIBL_OK);
    assert_int_equal(qibl_hemi_open(NULL, 16, 8, b, size, rws, sizeof rws), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_hemi_open(&h, 16, 8, NULL, size, rws, sizeof rws), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_hemi_open(&h, 16, 8, b, size, NULL, sizeof rws), QIBL_E_NULL_POINTER);
    expect_open(b, size, 17, 8, QIBL_E_HEMI_SIZE);
    expect_open(b, size, 16, 0, QIBL_E_HEMI_SIZE);
    assert_int_equal(qibl_hemi_open(&h, 16, 8, b, size, rws, QIBL_HEMI_OPEN_WORKSPACE_SIZE - 1u), QIBL_E_WORKSPACE);
    /* any workspace alignment */
    uint8_t wsb[QIBL_HEMI_OPEN_WORKSPACE_SIZE + 3u];
    assert_int_equal(qibl_hemi_open(&h, 16, 8, b, size, wsb + 1, QIBL_HEMI_OPEN_WORKSPACE_SIZE), QIBL_OK);
    /* misaligned: the same bytes one byte on */
    uint8_t *mis = malloc(size + 1u);
    assert_non_null(mis);
    memcpy(mis + 1, b, size);
    expect_open((const uint32_t *)(const void *)(mis + 1), size, 16, 8, QIBL_E_HEMI_TABLES_ALIGN);
    free(mis);
    /* truncated, trailing, or made for other sizes */
    expect_open(b, size - 4u, 16, 8, QIBL_E_HEMI_TABLES_SIZE);
    expect_open(b, size - 1u, 16, 8, QIBL_E_HEMI_TABLES_SIZE);
    expect_open(b, size + 4u, 16, 8, QIBL_E_HEMI_TABLES_SIZE);
    expect_open(b, 16u, 16, 8, QIBL_E_HEMI_TABLES_SIZE);
    expect_open(b, size, 16, 10, QIBL_E_HEMI_TABLES_SIZE);
    expect_open(b, size, 32, 8, QIBL_E_HEMI_TABLES_SIZE);
    /* each header field, then a damaged byte in each table */
    static const struct {
        uint32_t word, flip;
        qibl_status_t want;
    } bad[] = {
        {0, 0x20u, QIBL_E_HEMI_TABLES_MAGIC},   {0, 0x544D4851u ^ 0x51484D54u, QIBL_E_HEMI_TABLES_MAGIC}, /* swapped */
        {1, 3u, QIBL_E_HEMI_TABLES_VERSION},    {2, 48u, QIBL_E_HEMI_TABLES_SHAPE},
        {3, 2u, QIBL_E_HEMI_TABLES_SHAPE},      {4, 4u, QIBL_E_HEMI_TABLES_HEADER},
        {6, 1u, QIBL_E_HEMI_TABLES_HEADER},     {7, 0x80000000u, QIBL_E_HEMI_TABLES_HEADER},
        {5, 1u, QIBL_E_HEMI_TABLES_CRC},        {8, 0x100u, QIBL_E_HEMI_TABLES_CRC},
        {8 + 16 + 3, 0x10000u, QIBL_E_HEMI_TABLES_CRC}, {8 + 41 + 300, 0x80u, QIBL_E_HEMI_TABLES_CRC},
        {0, 0u, QIBL_OK}, /* the LUT's last word and the last centre: below */
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; ++k) {
        const uint32_t w = bad[k].word == 0u && bad[k].flip == 0u ? total - 1u : bad[k].word;
        const uint32_t flip = bad[k].flip ? bad[k].flip : 0x01000000u;
        const qibl_status_t want = bad[k].flip ? bad[k].want : QIBL_E_HEMI_TABLES_CRC;
        b[w] ^= flip;
        expect_open(b, size, 16, 8, want);
        b[w] ^= flip;
        if (!bad[k].flip) { /* the LUT's last word (before the 256 centres) */
            b[total - 257u] ^= 4u;
            expect_open(b, size, 16, 8, QIBL_E_HEMI_TABLES_CRC);
            b[total - 257u] ^= 4u;
        }
    }
    assert_int_equal(qibl_hemi_open(&h, 16, 8, b, size, rws, sizeof rws), QIBL_OK);
    free(b);
    assert_string_not_equal(qibl_status_str(QIBL_E_HEMI_TABLES_CRC), "unknown status");
}

/* The golden group with a port's prebuilt blobs (the sink's hemi_tables hook, as the GBA's ROM):
 * every case still matches fixtures/golden; a damaged (32, 24) blob fails exactly the three cases
 * that use it, so they do read the blob. */
typedef struct blob_sink {
    uint32_t *blob[3];
    size_t size[3];
    int calls, errors;
} blob_sink;

static const void *blob_hook(void *user, int n, int face, size_t *size)
{
    blob_sink *b = (blob_sink *)user;
    const int k = n == 16 ? 0 : n == 32 ? 1 : 2;
    assert_int_equal(face, n == 16 ? 16 : n == 32 ? 24 : 8);
    ++b->calls;
    *size = b->size[k];
    return b->blob[k];
}

static int blob_emit(void *user, const char *name, const char *hex, uint64_t n)
{
    (void)user, (void)n;
    return qtool_golden_check(name, hex);
}

static void blob_error(void *user, const char *name, const char *what)
{
    blob_sink *b = (blob_sink *)user;
    ++b->errors;
    assert_non_null(strstr(what, "qibl_hemi_open"));
    assert_true(strcmp(name, "hemi_masks_32_f24") == 0 || strcmp(name, "hemi_phong_32") == 0 ||
                strcmp(name, "hemi_frames") == 0);
}

static void test_goldens_from_blobs(void **state)
{
    (void)state;
    blob_sink b = {{NULL, NULL, NULL}, {0, 0, 0}, 0, 0};
    const int cfg[3][2] = {{16, 16}, {32, 24}, {64, 8}};
    for (int k = 0; k < 3; ++k)
        b.blob[k] = blob_of(cfg[k][0], cfg[k][1], &b.size[k]);
    const qtool_goldens_sink_t sink = {.emit = blob_emit, .error = blob_error, .user = &b, .hemi_tables = blob_hook};
    assert_int_equal(qtool_goldens_run("hemi", &sink), 0);
    assert_int_equal(b.calls, 3);
    assert_int_equal(b.errors, 0);
    b.blob[1][8 + 5000] ^= 1u; /* a basis word */
    assert_int_equal(qtool_goldens_run("hemi", &sink), 3);
    assert_int_equal(b.errors, 3);
    for (int k = 0; k < 3; ++k)
        free(b.blob[k]);
}

static void test_goldens(void **state)
{
    (void)state;
    assert_int_equal(qtool_goldens_check("hemi"), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sizes_and_errors),
        cmocka_unit_test(test_raster_errors),
        cmocka_unit_test(test_random_triangles_32),
        cmocka_unit_test(test_random_triangles_16_64),
        cmocka_unit_test(test_lanes_match_twin),
        cmocka_unit_test(test_indices_past_int32_offsets),
        cmocka_unit_test(test_lanes_edge_on),
        cmocka_unit_test(test_raster_every_isa),
        cmocka_unit_test(test_group_bounds),
        cmocka_unit_test(test_bound_near),
        cmocka_unit_test(test_bound_cull),
        cmocka_unit_test(test_winding_and_fusion),
        cmocka_unit_test(test_degenerate),
        cmocka_unit_test(test_sliver),
        cmocka_unit_test(test_horizon),
        cmocka_unit_test(test_huge_tiny_1lsb),
        cmocka_unit_test(test_transfer_unblocked),
        cmocka_unit_test(test_transfer_blocked),
        cmocka_unit_test(test_transfer_paths_agree),
        cmocka_unit_test(test_transfer_phong),
        cmocka_unit_test(test_frame),
        cmocka_unit_test(test_transform),
        cmocka_unit_test(test_rotation),
        cmocka_unit_test(test_tables_blob_is_init),
        cmocka_unit_test(test_tables_build_errors),
        cmocka_unit_test(test_tables_open_errors),
        cmocka_unit_test(test_goldens_from_blobs),
        cmocka_unit_test(test_goldens),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
