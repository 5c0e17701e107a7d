/*
 * gen/simplify.c - quadric-error simplification by half-edge collapses (gen/simplify.h).
 *
 * A collapse u -> v removes u and the faces on edge uv and re-indexes u's other faces to v; v keeps
 * its position, so the result indexes the original vertices. Candidates sit in a binary heap with
 * lazy invalidation: each vertex has a version bumped whenever its neighbourhood changes, and a
 * popped candidate whose versions are stale is dropped (its fresh twin was pushed then).
 */
#include "gen/simplify.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct cand {
    double cost;
    uint32_t u, v, vu, vv; /* collapse u onto v; versions when pushed */
} cand;

typedef struct state {
    const double *pos;
    uint32_t nv, nt, alive;
    uint32_t (*tri)[3];
    uint8_t *tri_alive, *gone;
    uint32_t **vf, *nvf, *cap; /* faces per vertex (dead ones filtered when read) */
    uint32_t *ver;
    double (*q)[10];
    cand *heap;
    size_t nheap, capheap;
    uint32_t *mark, stamp; /* scratch for neighbour sets */
} state;

/* symmetric 4x4 as 10 entries: a2 ab ac ad b2 bc bd c2 cd d2 */
static void quad_add_plane(double q[10], const double n[3], double d, double w)
{
    const double p[4] = {n[0], n[1], n[2], d};
    int k = 0;
    for (int i = 0; i < 4; ++i)
        for (int j = i; j < 4; ++j)
            q[k++] += w * p[i] * p[j];
}

static double quad_eval(const double a[10], const double b[10], const double *x)
{
    const double v[4] = {x[0], x[1], x[2], 1};
    double s = 0;
    int k = 0;
    for (int i = 0; i < 4; ++i)
        for (int j = i; j < 4; ++j, ++k)
            s += (a[k] + b[k]) * v[i] * v[j] * (i == j ? 1 : 2);
    return s;
}

static int push(state *s, uint32_t u, uint32_t v)
{
    if (s->nheap == s->capheap) {
        const size_t nc = s->capheap ? 2 * s->capheap : 1024;
        cand *h = realloc(s->heap, nc * sizeof *h);
        if (!h)
            return -1;
        s->heap = h, s->capheap = nc;
    }
    cand c = {fmax(0, quad_eval(s->q[u], s->q[v], s->pos + 3 * (size_t)v)), u, v, s->ver[u], s->ver[v]};
    size_t i = s->nheap++;
    while (i > 0 && s->heap[(i - 1) / 2].cost > c.cost) {
        s->heap[i] = s->heap[(i - 1) / 2];
        i = (i - 1) / 2;
    }
    s->heap[i] = c;
    return 0;
}

static cand pop(state *s)
{
    cand top = s->heap[0], last = s->heap[--s->nheap];
    size_t i = 0;
    for (;;) {
        size_t c = 2 * i + 1;
        if (c >= s->nheap)
            break;
        if (c + 1 < s->nheap && s->heap[c + 1].cost < s->heap[c].cost)
            ++c;
        if (s->heap[c].cost >= last.cost)
            break;
        s->heap[i] = s->heap[c], i = c;
    }
    if (s->nheap)
        s->heap[i] = last;
    return top;
}

static int add_face(state *s, uint32_t v, uint32_t f)
{
    if (s->nvf[v] == s->cap[v]) {
        const uint32_t nc = s->cap[v] ? 2 * s->cap[v] : 8;
        uint32_t *a = realloc(s->vf[v], nc * sizeof *a);
        if (!a)
            return -1;
        s->vf[v] = a, s->cap[v] = nc;
    }
    s->vf[v][s->nvf[v]++] = f;
    return 0;
}

/* The next live face on v's list from position *k on, into *f, with *k moved past it; 0 when there
 * is none left (the lists keep the faces that died: they are skipped here, as read). */
static int next_live(const state *s, uint32_t v, uint32_t *k, uint32_t *f)
{
    while (*k < s->nvf[v]) {
        *f = s->vf[v][(*k)++];
        if (s->tri_alive[*f])
            return 1;
    }
    return 0;
}

static uint64_t edge_key(uint32_t a, uint32_t b)
{
    return a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
}

static int cmp_u64(const void *x, const void *y)
{
    const uint64_t a = *(const uint64_t *)x, b = *(const uint64_t *)y;
    return a < b ? -1 : a > b;
}

/* how many faces use edge ab: a run in the sorted keys */
static size_t edge_uses(const uint64_t *e, size_t n, uint32_t a, uint32_t b)
{
    const uint64_t k = edge_key(a, b);
    size_t lo = 0, hi = n;
    while (lo < hi) {
        const size_t mid = lo + (hi - lo) / 2;
        if (e[mid] < k)
            lo = mid + 1;
        else
            hi = mid;
    }
    size_t c = 0;
    while (lo + c < n && e[lo + c] == k)
        ++c;
    return c;
}

static int has(const uint32_t *t, uint32_t v)
{
    return t[0] == v || t[1] == v || t[2] == v;
}

static void normal(const double *a, const double *b, const double *c, double n[3])
{
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    n[0] = u[1] * w[2] - u[2] * w[1], n[1] = u[2] * w[0] - u[0] * w[2], n[2] = u[0] * w[1] - u[1] * w[0];
}

/* u -> v keeps the mesh a manifold (link condition) and folds no face over */
static int valid(state *s, uint32_t u, uint32_t v)
{
    /* neighbours of u marked; the faces on uv give the allowed common neighbours */
    ++s->stamp;
    uint32_t shared = 0;
    for (uint32_t k = 0, f; next_live(s, u, &k, &f);) {
        const uint32_t *t = s->tri[f];
        for (int j = 0; j < 3; ++j)
            s->mark[t[j]] = s->stamp;
        shared += (uint32_t)has(t, v); /* each face on uv has one opposite vertex */
    }
    if (shared == 0 || shared > 2)
        return 0;
    ++s->stamp; /* second stamp: common neighbours */
    uint32_t common = 0;
    for (uint32_t k = 0, f; next_live(s, v, &k, &f);) {
        for (int j = 0; j < 3; ++j) {
            const uint32_t w = s->tri[f][j];
            if (w == u || w == v)
                continue;
            if (s->mark[w] == s->stamp - 1) { /* a neighbour of u too, counted once */
                s->mark[w] = s->stamp;
                ++common;
            }
        }
    }
    if (common != shared) /* more common neighbours than faces on uv: two sheets would join */
        return 0;
    /* fold-over: u's remaining faces keep their orientation */
    for (uint32_t k = 0, f; next_live(s, u, &k, &f);) {
        if (has(s->tri[f], v))
            continue;
        const double *p[3], *q[3];
        for (int j = 0; j < 3; ++j) {
            const uint32_t w = s->tri[f][j];
            p[j] = s->pos + 3 * (size_t)w;
            q[j] = s->pos + 3 * (size_t)(w == u ? v : w);
        }
        double a[3], b[3];
        normal(p[0], p[1], p[2], a), normal(q[0], q[1], q[2], b);
        const double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]), lb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
        if (!(lb > 1e-12 * (la + 1e-300)) || a[0] * b[0] + a[1] * b[1] + a[2] * b[2] < 0.2 * la * lb)
            return 0;
    }
    return 1;
}

static int collapse(state *s, uint32_t u, uint32_t v)
{
    for (uint32_t k = 0, f; next_live(s, u, &k, &f);) {
        uint32_t *t = s->tri[f];
        if (has(t, v)) {
            s->tri_alive[f] = 0, --s->alive;
            continue;
        }
        for (int j = 0; j < 3; ++j)
            if (t[j] == u)
                t[j] = v;
        if (add_face(s, v, f) != 0)
            return -1;
    }
    s->gone[u] = 1;
    for (int k = 0; k < 10; ++k)
        s->q[v][k] += s->q[u][k];
    /* v and its neighbours changed: fresh candidates both ways on every edge at v */
    ++s->ver[v];
    for (uint32_t k = 0, f; next_live(s, v, &k, &f);) {
        for (int j = 0; j < 3; ++j)
            if (s->tri[f][j] != v)
                ++s->ver[s->tri[f][j]];
    }
    for (uint32_t k = 0, f; next_live(s, v, &k, &f);) {
        for (int j = 0; j < 3; ++j) {
            const uint32_t w = s->tri[f][j];
            if (w != v && (push(s, v, w) != 0 || push(s, w, v) != 0))
                return -1;
        }
    }
    return 0;
}

int qtool_simplify(const double *pos, uint32_t nv, const uint32_t (*tri)[3], uint32_t nt, uint32_t target,
                   uint32_t (**out)[3], uint32_t *nout)
{
    state s;
    memset(&s, 0, sizeof s);
    s.pos = pos, s.nv = nv, s.nt = nt, s.alive = nt;
    s.tri = malloc(sizeof *s.tri * (nt ? nt : 1));
    s.tri_alive = malloc(nt ? nt : 1), s.gone = calloc(nv ? nv : 1, 1);
    s.vf = calloc(nv ? nv : 1, sizeof *s.vf), s.nvf = calloc(nv ? nv : 1, sizeof *s.nvf);
    s.cap = calloc(nv ? nv : 1, sizeof *s.cap), s.ver = calloc(nv ? nv : 1, sizeof *s.ver);
    s.q = calloc(nv ? nv : 1, sizeof *s.q), s.mark = calloc(nv ? nv : 1, sizeof *s.mark);
    uint64_t *edges = NULL;
    int rc = -1;
    if (!s.tri || !s.tri_alive || !s.gone || !s.vf || !s.nvf || !s.cap || !s.ver || !s.q || !s.mark)
        goto done;
    memcpy(s.tri, tri, sizeof *s.tri * nt);
    edges = malloc(sizeof *edges * 3 * (size_t)(nt ? nt : 1));
    if (!edges)
        goto done;
    for (uint32_t f = 0; f < nt; ++f)
        for (int j = 0; j < 3; ++j)
            edges[3 * (size_t)f + (size_t)j] = edge_key(tri[f][j], tri[f][(j + 1) % 3]);
    qsort(edges, 3 * (size_t)nt, sizeof *edges, cmp_u64);
    memset(s.tri_alive, 1, nt);
    for (uint32_t f = 0; f < nt; ++f) {
        const uint32_t *t = s.tri[f];
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) { /* degenerate: dropped */
            s.tri_alive[f] = 0, --s.alive;
            continue;
        }
        double n[3];
        normal(pos + 3 * (size_t)t[0], pos + 3 * (size_t)t[1], pos + 3 * (size_t)t[2], n);
        const double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int j = 0; j < 3; ++j)
            if (add_face(&s, t[j], f) != 0)
                goto done;
        if (!(l > 0))
            continue;
        const double un[3] = {n[0] / l, n[1] / l, n[2] / l};
        const double d = -(un[0] * pos[3 * t[0]] + un[1] * pos[3 * t[0] + 1] + un[2] * pos[3 * t[0] + 2]);
        for (int j = 0; j < 3; ++j)
            quad_add_plane(s.q[t[j]], un, d, l / 2);
        /* border edges (no other live face on them) keep their place: a plane through the edge,
         * perpendicular to the face, weighted heavily */
        for (int j = 0; j < 3; ++j) {
            const uint32_t a = t[j], b = t[(j + 1) % 3];
            if (edge_uses(edges, 3 * (size_t)nt, a, b) > 1)
                continue;
            const double *pa = pos + 3 * (size_t)a, *pb = pos + 3 * (size_t)b;
            const double e[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
            double m[3] = {e[1] * un[2] - e[2] * un[1], e[2] * un[0] - e[0] * un[2], e[0] * un[1] - e[1] * un[0]};
            const double lm = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
            if (!(lm > 0))
                continue;
            for (int k = 0; k < 3; ++k)
                m[k] /= lm;
            const double dm = -(m[0] * pa[0] + m[1] * pa[1] + m[2] * pa[2]);
            quad_add_plane(s.q[a], m, dm, 100 * lm * lm), quad_add_plane(s.q[b], m, dm, 100 * lm * lm);
        }
    }
    for (uint32_t f = 0; f < nt; ++f)
        for (int j = 0; s.tri_alive[f] && j < 3; ++j)
            if (push(&s, s.tri[f][j], s.tri[f][(j + 1) % 3]) != 0 || push(&s, s.tri[f][(j + 1) % 3], s.tri[f][j]) != 0)
                goto done;
    while (s.alive > target && s.nheap > 0) {
        const cand c = pop(&s);
        if (s.gone[c.u] || s.gone[c.v] || c.vu != s.ver[c.u] || c.vv != s.ver[c.v])
            continue;
        if (!valid(&s, c.u, c.v))
            continue;
        if (collapse(&s, c.u, c.v) != 0)
            goto done;
    }
    *out = malloc(sizeof **out * (s.alive ? s.alive : 1));
    if (!*out)
        goto done;
    *nout = 0;
    for (uint32_t f = 0; f < nt; ++f)
        if (s.tri_alive[f])
            memcpy((*out)[(*nout)++], s.tri[f], sizeof s.tri[f]);
    rc = 0;
done:
    for (uint32_t v = 0; s.vf && v < nv; ++v)
        free(s.vf[v]);
    free(s.tri), free(s.tri_alive), free(s.gone), free(s.vf), free(s.nvf), free(s.cap), free(s.ver), free(s.q);
    free(s.mark), free(s.heap), free(edges);
    return rc;
}
