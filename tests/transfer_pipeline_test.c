/*
 * transfer_pipeline_test.c - the mesh pipeline of `qibl transfer` through its library
 * (tools/transfer/transfer.c): welding, adjacency, the two-level hierarchy and the PVS, on closed
 * meshes the test generates (cones, cylinders, UV spheres, double fans, grids) at many sizes, coarse
 * targets, rings and with and without crease wedges. Each hierarchy is compared with a brute-force
 * one built here from graph distances; every refusal has its named status and leaves the output
 * empty; the list caps refuse before allocating.
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
#include "qibl/hemi.h"
#include "transfer/transfer.h"

typedef struct gen {
    uint32_t nv, nt, capv, capt;
    double *p;
    uint32_t (*t)[3];
} gen;

static uint32_t add_v(gen *g, double x, double y, double z)
{
    assert_true(g->nv < g->capv);
    g->p[3 * g->nv] = x, g->p[3 * g->nv + 1] = y, g->p[3 * g->nv + 2] = z;
    return g->nv++;
}

static void add_t(gen *g, uint32_t a, uint32_t b, uint32_t c)
{
    assert_true(g->nt < g->capt);
    g->t[g->nt][0] = a, g->t[g->nt][1] = b, g->t[g->nt][2] = c, ++g->nt;
}

static void gen_init(gen *g, uint32_t capv, uint32_t capt)
{
    g->nv = g->nt = 0, g->capv = capv, g->capt = capt;
    g->p = malloc(sizeof(double) * 3 * capv), g->t = malloc(sizeof *g->t * capt);
    assert_non_null(g->p), assert_non_null(g->t);
}

static void gen_free(gen *g)
{
    free(g->p), free(g->t);
}

/* A surface of revolution about z: the profile (r[i], z[i]) from top to bottom, a point with r = 0
 * a pole (one vertex, a fan), the others rings of s vertices; closed when both ends are poles. */
static void revolve(gen *g, const double *r, const double *z, int np, int s)
{
    gen_init(g, (uint32_t)(np * s), (uint32_t)(2 * np * s));
    uint32_t first[64];
    assert_true(np <= 64);
    for (int i = 0; i < np; ++i) {
        first[i] = g->nv;
        if (r[i] == 0)
            add_v(g, 0, 0, z[i]);
        else
            for (int k = 0; k < s; ++k) {
                const double a = 6.283185307179586 * k / s;
                add_v(g, r[i] * cos(a), r[i] * sin(a), z[i]);
            }
    }
    for (int i = 0; i + 1 < np; ++i)
        for (int k = 0; k < s; ++k) {
            const uint32_t k1 = (uint32_t)((k + 1) % s);
            if (r[i] == 0 && r[i + 1] == 0)
                continue;
            if (r[i] == 0)
                add_t(g, first[i], first[i + 1] + (uint32_t)k, first[i + 1] + k1);
            else if (r[i + 1] == 0)
                add_t(g, first[i] + (uint32_t)k, first[i + 1], first[i] + k1);
            else
                add_t(g, first[i] + (uint32_t)k, first[i + 1] + (uint32_t)k, first[i + 1] + k1),
                    add_t(g, first[i] + (uint32_t)k, first[i + 1] + k1, first[i] + k1);
        }
}

/* kind 0 cone, 1 cylinder, 2 UV sphere, 3 double fan (a closed flat disc: two hubs), 4 grid (open) */
static void make_mesh(gen *g, int kind, int s, int rings)
{
    double r[64], z[64];
    int np = 0;
    if (kind == 0) {
        r[0] = 0, z[0] = 1, r[1] = 1, z[1] = 0, r[2] = 0, z[2] = 0, np = 3;
    } else if (kind == 1) {
        r[np] = 0, z[np++] = 1;
        for (int i = 0; i <= rings; ++i)
            r[np] = 1, z[np++] = 1 - 2.0 * i / rings;
        r[np] = 0, z[np++] = -1;
    } else if (kind == 2) {
        for (int i = 0; i <= rings + 1; ++i) {
            const double th = 3.141592653589793 * i / (rings + 1);
            r[np] = i == 0 || i == rings + 1 ? 0 : sin(th), z[np++] = cos(th);
        }
    } else if (kind == 3) {
        r[0] = 0, z[0] = 0.01, r[1] = 1, z[1] = 0, r[2] = 0, z[2] = -0.01, np = 3;
    } else {
        gen_init(g, (uint32_t)((s + 1) * (rings + 1)), (uint32_t)(2 * s * rings));
        for (int j = 0; j <= rings; ++j)
            for (int i = 0; i <= s; ++i)
                add_v(g, i, j, 0);
        for (int j = 0; j < rings; ++j)
            for (int i = 0; i < s; ++i) {
                const uint32_t a = (uint32_t)(j * (s + 1) + i), b = a + 1, c = a + (uint32_t)s + 1, d = c + 1;
                add_t(g, a, b, d), add_t(g, a, d, c);
            }
        return;
    }
    revolve(g, r, z, np, s);
}

static void as_mesh(const gen *g, qtool_transfer_mesh *m)
{
    m->nv = g->nv, m->nt = g->nt, m->nframes = 1, m->tri = g->t, m->pos = g->p;
}

static int cmp_tri(const void *a, const void *b)
{
    const uint32_t *x = a, *y = b;
    for (int k = 0; k < 3; ++k)
        if (x[k] != y[k])
            return x[k] < y[k] ? -1 : 1;
    return 0;
}

static void sort3(uint32_t t[3])
{
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2 - i; ++j)
            if (t[j] > t[j + 1]) {
                const uint32_t x = t[j];
                t[j] = t[j + 1], t[j + 1] = x;
            }
}

/* The hierarchy of every vertex against a brute-force one: graph distances by breadth-first search
 * over the edges, near = every triangle with a vertex at distance <= ring (the faces of the ring's
 * edge included), far = the coarse triangles with no vertex that near, wedges = one per face around
 * v; the blockers, mapped back to global vertices (the nadir as nv), are the same multiset. */
static void check_hier(const qtool_transfer_mesh *m, const uint32_t *off, const uint32_t *adj, const uint32_t (*ct)[3],
                       uint32_t nct, int ring, int crease, const qtool_transfer_hier *h)
{
    int *dist = malloc(sizeof(int) * m->nv);
    uint32_t *queue = malloc(sizeof(uint32_t) * m->nv);
    size_t cap = (size_t)m->nt + nct + 3 * (size_t)m->nt + 1;
    uint32_t (*want)[3] = malloc(sizeof *want * cap), (*got)[3] = malloc(sizeof *got * cap);
    assert_non_null(dist), assert_non_null(queue), assert_non_null(want), assert_non_null(got);
    assert_int_equal(h->voff[0], 0), assert_int_equal(h->boff[0], 0);
    for (uint32_t v = 0; v < m->nv; ++v) {
        for (uint32_t i = 0; i < m->nv; ++i)
            dist[i] = -1;
        uint32_t head = 0, tail = 0;
        dist[v] = 0, queue[tail++] = v;
        while (head < tail) {
            const uint32_t x = queue[head++];
            for (uint32_t k = off[x]; k < off[x + 1]; ++k)
                for (int c = 0; c < 3; ++c) {
                    const uint32_t y = m->tri[adj[k]][c];
                    if (dist[y] < 0)
                        dist[y] = dist[x] + 1, queue[tail++] = y;
                }
        }
        size_t nw = 0;
        for (uint32_t t = 0; t < m->nt; ++t) {
            int near = 0;
            for (int c = 0; c < 3; ++c)
                near |= dist[m->tri[t][c]] >= 0 && dist[m->tri[t][c]] <= ring;
            if (near)
                memcpy(want[nw++], m->tri[t], sizeof want[0]);
        }
        for (uint32_t t = 0; t < nct; ++t) {
            int near = 0;
            for (int c = 0; c < 3; ++c)
                near |= dist[ct[t][c]] >= 0 && dist[ct[t][c]] <= ring;
            if (!near)
                memcpy(want[nw++], ct[t], sizeof want[0]);
        }
        if (crease)
            for (uint32_t k = off[v]; k < off[v + 1]; ++k) {
                const uint32_t *t = m->tri[adj[k]];
                const int r = t[0] == v ? 0 : t[1] == v ? 1 : 2;
                want[nw][0] = m->nv, want[nw][1] = t[(r + 1) % 3], want[nw][2] = t[(r + 2) % 3], ++nw;
            }
        assert_true(h->voff[v + 1] >= h->voff[v]);
        assert_int_equal(h->boff[v + 1] - h->boff[v], nw);
        const size_t n = h->voff[v + 1] - h->voff[v];
        int self = 0;
        for (size_t i = 0; i < n; ++i) {
            assert_true(h->vl[h->voff[v] + i] < m->nv);
            self |= h->vl[h->voff[v] + i] == v;
            for (size_t j = 0; j < i; ++j) /* each vertex once */
                assert_true(h->vl[h->voff[v] + i] != h->vl[h->voff[v] + j]);
        }
        assert_true(self);
        for (size_t b = 0; b < nw; ++b)
            for (int c = 0; c < 3; ++c) {
                const uint32_t l = h->blk[h->boff[v] + b][c];
                assert_true(l <= n);
                got[b][c] = l == n ? m->nv : h->vl[h->voff[v] + l];
            }
        for (size_t b = 0; b < nw; ++b)
            sort3(want[b]), sort3(got[b]);
        qsort(want, nw, sizeof want[0], cmp_tri), qsort(got, nw, sizeof got[0], cmp_tri);
        assert_memory_equal(want, got, sizeof want[0] * nw);
    }
    free(dist), free(queue), free(want), free(got);
}

/* issue 24, class 1: the faces around a ring's edge bring in vertices one ring further, more than
 * the lists were grown for (a fan's hub: every rim vertex). Many closed meshes, every coarse size
 * from 1 triangle to the whole mesh, rings 1..4 and the default 3, with and without wedges. */
static void test_hierarchy_many_meshes(void **state)
{
    (void)state;
    static const int sizes[][2] = {{3, 1}, {4, 2}, {5, 3}, {8, 2}, {12, 4}, {17, 6}, {32, 3}, {36, 5}};
    int built = 0;
    for (int kind = 0; kind < 5; ++kind)
        for (size_t si = 0; si < sizeof sizes / sizeof sizes[0]; ++si) {
            gen g;
            make_mesh(&g, kind, sizes[si][0], sizes[si][1]);
            qtool_transfer_mesh m;
            as_mesh(&g, &m);
            uint32_t *off, *adj;
            assert_int_equal(qtool_transfer_adjacency(&m, &off, &adj), QTOOL_TRANSFER_OK);
            const uint32_t targets[] = {1, 2, 8, m.nt / 4 + 1, m.nt};
            for (size_t ti = 0; ti < sizeof targets / sizeof targets[0]; ++ti) {
                uint32_t (*ct)[3] = NULL, nct = 0;
                assert_int_equal(qtool_simplify(m.pos, m.nv, (const uint32_t(*)[3])m.tri, m.nt, targets[ti], &ct, &nct), 0);
                for (int ring = 1; ring <= 4; ++ring)
                    for (int crease = 0; crease < 2; ++crease) {
                        qtool_transfer_hier h;
                        assert_int_equal(qtool_transfer_hier_build(&m, off, adj, (const uint32_t(*)[3])ct, nct, ring,
                                                                   crease, &h),
                                         QTOOL_TRANSFER_OK);
                        check_hier(&m, off, adj, (const uint32_t(*)[3])ct, nct, ring, crease, &h);
                        qtool_transfer_hier_free(&h);
                        ++built;
                    }
                free(ct);
            }
            free(off), free(adj), gen_free(&g);
        }
    assert_int_equal(built, 5 * 8 * 5 * 8);
}

/* every bad input by name, the output left empty */
static void test_hierarchy_refusals(void **state)
{
    (void)state;
    gen g;
    make_mesh(&g, 2, 6, 3);
    qtool_transfer_mesh m;
    as_mesh(&g, &m);
    uint32_t *off, *adj;
    assert_int_equal(qtool_transfer_adjacency(&m, &off, &adj), QTOOL_TRANSFER_OK);
    const qtool_transfer_hier empty = {NULL, NULL, NULL, NULL};
    qtool_transfer_hier h;
    uint32_t ct[1][3] = {{0, 1, g.nv}};
    assert_int_equal(qtool_transfer_hier_build(&m, off, adj, NULL, 0, 0, 1, &h), QTOOL_TRANSFER_E_RING);
    assert_memory_equal(&h, &empty, sizeof h);
    assert_int_equal(qtool_transfer_hier_build(&m, off, adj, NULL, 0, QTOOL_TRANSFER_MAX_RING + 1, 1, &h),
                     QTOOL_TRANSFER_E_RING);
    assert_int_equal(qtool_transfer_hier_build(&m, off, adj, (const uint32_t(*)[3])ct, 1, 2, 1, &h), QTOOL_TRANSFER_E_INDEX);
    assert_memory_equal(&h, &empty, sizeof h);
    const uint32_t a0 = adj[off[5]];
    adj[off[5]] = adj[off[0]] == a0 ? adj[off[0] + 1] : adj[off[0]]; /* a face of 0 listed around 5 */
    int holds5 = 0;
    for (int c = 0; c < 3; ++c)
        holds5 |= m.tri[adj[off[5]]][c] == 5;
    if (!holds5) {
        assert_int_equal(qtool_transfer_hier_build(&m, off, adj, NULL, 0, 2, 1, &h), QTOOL_TRANSFER_E_ADJACENCY);
        assert_memory_equal(&h, &empty, sizeof h);
    }
    adj[off[5]] = a0;
    const uint32_t o1 = off[1];
    off[1] = off[2] + 1; /* offsets not rising */
    assert_int_equal(qtool_transfer_hier_build(&m, off, adj, NULL, 0, 2, 1, &h), QTOOL_TRANSFER_E_ADJACENCY);
    off[1] = o1;
    m.tri[3][1] = m.nv; /* a mesh index past the vertices */
    assert_int_equal(qtool_transfer_hier_build(&m, off, adj, NULL, 0, 2, 1, &h), QTOOL_TRANSFER_E_INDEX);
    assert_memory_equal(&h, &empty, sizeof h);
    uint32_t *o2, *a2;
    assert_int_equal(qtool_transfer_adjacency(&m, &o2, &a2), QTOOL_TRANSFER_E_INDEX);
    assert_null(o2), assert_null(a2);
    free(off), free(adj), gen_free(&g);
    for (int i = 0; i < QTOOL_TRANSFER_E_FRAMES + 1; ++i) /* every status has its own line */
        for (int j = 0; j < i; ++j)
            assert_string_not_equal(qtool_transfer_status_str((qtool_transfer_status)i),
                                    qtool_transfer_status_str((qtool_transfer_status)j));
}

/* A fan whose hub has 8200 faces: at ring 1 every rim vertex reaches all of them, 8200^2 blockers,
 * past QTOOL_TRANSFER_MAX_LIST: refused by the counting pass (nothing allocated for the lists); the
 * PVS over every triangle is refused up front by its worst case. */
static void test_list_caps(void **state)
{
    (void)state;
    gen g;
    make_mesh(&g, 3, 8200, 0);
    qtool_transfer_mesh m;
    as_mesh(&g, &m);
    uint32_t *off, *adj;
    assert_int_equal(qtool_transfer_adjacency(&m, &off, &adj), QTOOL_TRANSFER_OK);
    qtool_transfer_hier h;
    assert_int_equal(qtool_transfer_hier_build(&m, off, adj, NULL, 0, 1, 1, &h), QTOOL_TRANSFER_E_TOO_BIG);
    assert_null(h.vl), assert_null(h.blk), assert_null(h.voff);
    assert_true((uint64_t)m.nv * m.nt > QTOOL_TRANSFER_MAX_LIST);
    qibl_q16_t (*pos)[3] = calloc(m.nv, sizeof *pos);
    int32_t (*nrm)[3] = calloc(m.nv, sizeof *nrm);
    assert_non_null(pos), assert_non_null(nrm);
    assert_int_equal(qtool_transfer_pvs_build(&m, NULL, (const qibl_q16_t(*)[3])pos, (const int32_t(*)[3])nrm, off,
                                              adj, 1, 1, &h),
                     QTOOL_TRANSFER_E_TOO_BIG);
    assert_null(h.vl);
    free(pos), free(nrm), free(off), free(adj), gen_free(&g);
}

/* the PVS keeps a subset of its source's blockers, in range, for every frame of a moving sphere */
static void test_pvs_subset(void **state)
{
    (void)state;
    gen g;
    make_mesh(&g, 2, 10, 5);
    qtool_transfer_mesh m;
    as_mesh(&g, &m);
    m.nframes = 2;
    uint32_t *off, *adj;
    assert_int_equal(qtool_transfer_adjacency(&m, &off, &adj), QTOOL_TRANSFER_OK);
    qibl_q16_t (*pos)[3] = malloc(sizeof *pos * 2 * m.nv);
    int32_t (*nrm)[3] = malloc(sizeof *nrm * 2 * m.nv);
    assert_non_null(pos), assert_non_null(nrm);
    for (uint32_t f = 0; f < 2; ++f)
        for (uint32_t v = 0; v < m.nv; ++v) {
            const double *p = g.p + 3 * v;
            const double l = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
            for (int k = 0; k < 3; ++k) {
                pos[f * m.nv + v][k] = (qibl_q16_t)lrint((p[k] * (f ? 0.8 : 1)) * 65536.0);
                nrm[f * m.nv + v][k] = (int32_t)lrint(p[k] / l * 1073741824.0 * 0.999);
            }
        }
    uint32_t (*ct)[3] = NULL, nct = 0;
    assert_int_equal(qtool_simplify(m.pos, m.nv, (const uint32_t(*)[3])m.tri, m.nt, 20, &ct, &nct), 0);
    qtool_transfer_hier h, pv;
    assert_int_equal(qtool_transfer_hier_build(&m, off, adj, (const uint32_t(*)[3])ct, nct, 1, 1, &h), QTOOL_TRANSFER_OK);
    for (int src = 0; src < 2; ++src) {
        assert_int_equal(qtool_transfer_pvs_build(&m, src ? &h : NULL, (const qibl_q16_t(*)[3])pos,
                                                  (const int32_t(*)[3])nrm, off, adj, 1, 2, &pv),
                         QTOOL_TRANSFER_OK);
        for (uint32_t v = 0; v < m.nv; ++v) {
            const size_t n = pv.voff[v + 1] - pv.voff[v];
            assert_true(pv.boff[v + 1] - pv.boff[v] <= (src ? h.boff[v + 1] - h.boff[v] : m.nt + off[v + 1] - off[v]));
            for (size_t b = pv.boff[v]; b < pv.boff[v + 1]; ++b)
                for (int k = 0; k < 3; ++k)
                    assert_true(pv.blk[b][k] <= n);
            for (size_t k = pv.voff[v]; k < pv.voff[v + 1]; ++k)
                assert_true(pv.vl[k] < m.nv);
        }
        qtool_transfer_hier_free(&pv);
    }
    /* a hierarchy whose local index points past its list is refused, nothing written */
    h.blk[h.boff[3]][1] = (uint32_t)(h.voff[4] - h.voff[3]) + 1;
    assert_int_equal(qtool_transfer_pvs_build(&m, &h, (const qibl_q16_t(*)[3])pos, (const int32_t(*)[3])nrm, off, adj, 1,
                                              1, &pv),
                     QTOOL_TRANSFER_E_INDEX);
    assert_null(pv.vl), assert_null(pv.blk);
    qtool_transfer_hier_free(&h);
    free(ct), free(pos), free(nrm), free(off), free(adj), gen_free(&g);
}

static void test_weld(void **state)
{
    (void)state;
    /* two triangles sharing an edge, one corner written as -0: 4 vertices */
    const double p[18] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 0, -0.0, 1, 1, 0, 0, 1, 0};
    uint32_t tri[2][3], first[6], vof[6], nv = 99;
    assert_int_equal(qtool_transfer_weld(p, 2, tri, first, vof, &nv), QTOOL_TRANSFER_OK);
    assert_int_equal(nv, 4);
    assert_int_equal(tri[0][1], tri[1][0]), assert_int_equal(tri[0][2], tri[1][2]);
    for (int c = 0; c < 6; ++c)
        assert_memory_equal(&(uint32_t){vof[first[vof[c]]]}, &vof[c], sizeof vof[c]);
    double q[18];
    memcpy(q, p, sizeof q);
    q[7] = NAN;
    uint32_t t2[2][3] = {{7, 7, 7}, {7, 7, 7}};
    nv = 99;
    assert_int_equal(qtool_transfer_weld(q, 2, t2, first, vof, &nv), QTOOL_TRANSFER_E_CORNER);
    assert_int_equal(nv, 99), assert_int_equal(t2[0][0], 7);
    assert_int_equal(qtool_transfer_weld(p, 0, t2, first, vof, &nv), QTOOL_TRANSFER_E_EMPTY);
    assert_int_equal(qtool_transfer_weld(p, (size_t)QTOOL_TRANSFER_MAX_TRIANGLES + 1, t2, first, vof, &nv),
                     QTOOL_TRANSFER_E_TRIANGLES);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hierarchy_many_meshes), cmocka_unit_test(test_hierarchy_refusals),
        cmocka_unit_test(test_list_caps),            cmocka_unit_test(test_pvs_subset),
        cmocka_unit_test(test_weld),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
