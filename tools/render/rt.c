/*
 * render/rt.c - triangle ray tracer with a BVH, the built-in courtyard, panorama rendering.
 */
#include "render/rt.h"
#include "qtool.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>


/* ---- scene building ------------------------------------------------------------------------------ */

typedef struct {
    qtool_rt_scene *s;
    size_t cap;
    int oom;
} builder;

static void add_tri(builder *b, const double a[3], const double c1[3], const double c2[3], const double na[3],
                    const double n1[3], const double n2[3], int mat)
{
    qtool_rt_scene *s = b->s;
    if (b->oom)
        return;
    if (s->ntri == b->cap) {
        size_t cap = b->cap ? b->cap * 2 : 1024;
        double *v = realloc(s->v, cap * 9 * sizeof *v);
        if (v)
            s->v = v;
        double *n = realloc(s->n, cap * 9 * sizeof *n);
        if (n)
            s->n = n;
        uint8_t *m = realloc(s->mat, cap);
        if (m)
            s->mat = m;
        if (!v || !n || !m) {
            b->oom = 1;
            return;
        }
        b->cap = cap;
    }
    const double *pv[3] = {a, c1, c2}, *pn[3] = {na, n1, n2};
    for (int q = 0; q < 3; ++q)
        for (int j = 0; j < 3; ++j) {
            s->v[9 * s->ntri + 3 * q + j] = pv[q][j];
            s->n[9 * s->ntri + 3 * q + j] = pn[q][j];
        }
    s->mat[s->ntri++] = (uint8_t)mat;
}

static void flat_normal(const double a[3], const double b[3], const double c[3], double n[3])
{
    double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    n[0] = e1[1] * e2[2] - e1[2] * e2[1], n[1] = e1[2] * e2[0] - e1[0] * e2[2], n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int j = 0; j < 3; ++j)
        n[j] = l > 0 ? n[j] / l : 0;
}

static void add_quad(builder *b, const double a[3], const double c1[3], const double c2[3], const double c3[3], int mat)
{
    double n[3];
    flat_normal(a, c1, c2, n);
    add_tri(b, a, c1, c2, n, n, n, mat);
    add_tri(b, a, c2, c3, n, n, n, mat);
}

static void add_box(builder *b, const double lo[3], const double hi[3], int mat)
{
    double c[8][3];
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 3; ++j)
            c[i][j] = (i >> j) & 1 ? hi[j] : lo[j];
    static const int f[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
    for (int i = 0; i < 6; ++i)
        add_quad(b, c[f[i][0]], c[f[i][1]], c[f[i][2]], c[f[i][3]], mat);
}

static void add_cylinder(builder *b, double cx, double cy, double r, double z0, double z1, int seg, int mat)
{
    for (int i = 0; i < seg; ++i) {
        double a0 = 2 * QTOOL_PI * i / seg, a1 = 2 * QTOOL_PI * (i + 1) / seg;
        double n0[3] = {cos(a0), sin(a0), 0}, n1[3] = {cos(a1), sin(a1), 0};
        double p00[3] = {cx + r * n0[0], cy + r * n0[1], z0}, p01[3] = {cx + r * n0[0], cy + r * n0[1], z1};
        double p10[3] = {cx + r * n1[0], cy + r * n1[1], z0}, p11[3] = {cx + r * n1[0], cy + r * n1[1], z1};
        add_tri(b, p00, p10, p11, n0, n1, n1, mat);
        add_tri(b, p00, p11, p01, n0, n1, n0, mat);
    }
}

static void add_sphere(builder *b, const double c[3], double r, int nu, int nv, int mat)
{
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            double n[4][3], p[4][3];
            for (int q = 0; q < 4; ++q) {
                int ii = i + (q == 1 || q == 2), jj = j + (q >= 2);
                double th = QTOOL_PI * jj / nv, ph = 2 * QTOOL_PI * ii / nu;
                n[q][0] = sin(th) * cos(ph), n[q][1] = sin(th) * sin(ph), n[q][2] = cos(th);
                for (int k = 0; k < 3; ++k)
                    p[q][k] = c[k] + r * n[q][k];
            }
            if (j > 0)
                add_tri(b, p[0], p[2], p[1], n[0], n[2], n[1], mat);
            if (j < nv - 1)
                add_tri(b, p[0], p[3], p[2], n[0], n[3], n[2], mat);
        }
}

/* A round arch spanning x in [cx - half, cx + half], springing at z0, its block up to z1, between
 * y0 and y1: the intrados (half cylinder of radius r), the two faces and the top. */
static void add_arch(builder *b, double cx, double half, double r, double z0, double z1, double y0, double y1, int mat)
{
    enum { SEG = 20 };
    double th[SEG + 3];
    int n = 0;
    for (int i = 0; i <= SEG; ++i)
        th[n++] = QTOOL_PI * i / SEG;
    th[n++] = atan2(z1 - z0, half), th[n++] = atan2(z1 - z0, -half);
    for (int i = 1; i < n; ++i) /* insertion sort: the corner angles join the arc samples */
        for (int j = i; j > 0 && th[j] < th[j - 1]; --j) {
            double t = th[j];
            th[j] = th[j - 1], th[j - 1] = t;
        }
    for (int i = 0; i + 1 < n; ++i) {
        double a[2][3], o[2][3], nn[2][3];
        for (int q = 0; q < 2; ++q) {
            double c = cos(th[i + q]), s = sin(th[i + q]);
            double t = fabs(c) > 1e-12 ? half / fabs(c) : 1e30;
            if (s > 1e-12 && (z1 - z0) / s < t)
                t = (z1 - z0) / s;
            a[q][0] = cx + r * c, a[q][2] = z0 + r * s;
            o[q][0] = cx + t * c, o[q][2] = z0 + t * s;
            nn[q][0] = -c, nn[q][1] = 0, nn[q][2] = -s;
        }
        for (int side = 0; side < 2; ++side) {
            double y = side ? y1 : y0;
            double p0[3] = {a[0][0], y, a[0][2]}, p1[3] = {a[1][0], y, a[1][2]};
            double q1[3] = {o[1][0], y, o[1][2]}, q0[3] = {o[0][0], y, o[0][2]};
            add_quad(b, p0, p1, q1, q0, mat);
        }
        double i00[3] = {a[0][0], y0, a[0][2]}, i10[3] = {a[1][0], y0, a[1][2]};
        double i01[3] = {a[0][0], y1, a[0][2]}, i11[3] = {a[1][0], y1, a[1][2]};
        add_tri(b, i00, i10, i11, nn[0], nn[1], nn[1], mat);
        add_tri(b, i00, i11, i01, nn[0], nn[1], nn[0], mat);
    }
    double t0[3] = {cx - half, y0, z1}, t1[3] = {cx + half, y0, z1}, t2[3] = {cx + half, y1, z1}, t3[3] = {cx - half, y1, z1};
    add_quad(b, t0, t1, t2, t3, mat);
}

/* ---- BVH ----------------------------------------------------------------------------------------- */

typedef struct {
    qtool_rt_scene *s;
    double *cent;
    uint32_t *idx;
    size_t cap;
} bvh_build;

static void tri_bounds(const qtool_rt_scene *s, uint32_t t, double lo[3], double hi[3])
{
    for (int j = 0; j < 3; ++j) {
        lo[j] = hi[j] = s->v[9 * (size_t)t + j];
        for (int q = 1; q < 3; ++q) {
            double x = s->v[9 * (size_t)t + 3 * q + j];
            lo[j] = x < lo[j] ? x : lo[j];
            hi[j] = x > hi[j] ? x : hi[j];
        }
    }
}

static const double *g_cent; /* qsort has no context argument; only used under build_lock */
static int g_axis;
static pthread_mutex_t build_lock = PTHREAD_MUTEX_INITIALIZER;

static int cmp_cent(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    double cx = g_cent[3 * (size_t)x + g_axis], cy = g_cent[3 * (size_t)y + g_axis];
    return cx < cy ? -1 : cx > cy ? 1 : (x > y) - (x < y); /* total order: deterministic */
}

static void build_node(bvh_build *bb, size_t node, uint32_t first, uint32_t count)
{
    qtool_rt_scene *s = bb->s;
    qtool_rt_node *nd = &s->nodes[node];
    double clo[3] = {1e300, 1e300, 1e300}, chi[3] = {-1e300, -1e300, -1e300};
    for (int j = 0; j < 3; ++j)
        nd->lo[j] = 1e300, nd->hi[j] = -1e300;
    for (uint32_t i = first; i < first + count; ++i) {
        double lo[3], hi[3];
        tri_bounds(s, bb->idx[i], lo, hi);
        for (int j = 0; j < 3; ++j) {
            nd->lo[j] = lo[j] < nd->lo[j] ? lo[j] : nd->lo[j];
            nd->hi[j] = hi[j] > nd->hi[j] ? hi[j] : nd->hi[j];
            double c = bb->cent[3 * (size_t)bb->idx[i] + j];
            clo[j] = c < clo[j] ? c : clo[j];
            chi[j] = c > chi[j] ? c : chi[j];
        }
    }
    if (count <= 4) {
        nd->first = first, nd->count = count;
        return;
    }
    int axis = 0;
    for (int j = 1; j < 3; ++j)
        if (chi[j] - clo[j] > chi[axis] - clo[axis])
            axis = j;
    g_cent = bb->cent, g_axis = axis;
    qsort(bb->idx + first, count, sizeof(uint32_t), cmp_cent);
    size_t left = s->nnodes;
    s->nnodes += 2;
    nd->first = (uint32_t)left, nd->count = 0;
    uint32_t half = count / 2;
    build_node(bb, left, first, half);
    build_node(bb, left + 1, first + half, count - half);
}

static int build_bvh(qtool_rt_scene *s)
{
    bvh_build bb = {s, malloc(s->ntri * 3 * sizeof(double)), malloc(s->ntri * sizeof(uint32_t)), 0};
    s->nodes = malloc((2 * s->ntri + 1) * sizeof(qtool_rt_node));
    if (!bb.cent || !bb.idx || !s->nodes) {
        free(bb.cent), free(bb.idx);
        return -1;
    }
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    for (size_t t = 0; t < s->ntri; ++t) {
        bb.idx[t] = (uint32_t)t;
        for (int j = 0; j < 3; ++j) {
            bb.cent[3 * t + j] = (s->v[9 * t + j] + s->v[9 * t + 3 + j] + s->v[9 * t + 6 + j]) / 3;
            for (int q = 0; q < 3; ++q) {
                double x = s->v[9 * t + 3 * q + j];
                lo[j] = x < lo[j] ? x : lo[j];
                hi[j] = x > hi[j] ? x : hi[j];
            }
        }
    }
    s->scale = fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2]));
    s->nnodes = 1;
    pthread_mutex_lock(&build_lock);
    build_node(&bb, 0, 0, (uint32_t)s->ntri);
    pthread_mutex_unlock(&build_lock);
    /* reorder the triangles into BVH order so leaves index them directly */
    double *v = malloc(s->ntri * 9 * sizeof(double)), *n = malloc(s->ntri * 9 * sizeof(double));
    uint8_t *m = malloc(s->ntri);
    double *alb = s->alb ? malloc(s->ntri * 3 * sizeof(double)) : NULL;
    double *uv = s->uv ? malloc(s->ntri * 6 * sizeof(double)) : NULL;
    int32_t *tx = s->tex ? malloc(s->ntri * sizeof(int32_t)) : NULL;
    if (!v || !n || !m || (s->alb && !alb) || (s->uv && !uv) || (s->tex && !tx)) {
        free(v), free(n), free(m), free(alb), free(uv), free(tx), free(bb.cent), free(bb.idx);
        return -1;
    }
    for (size_t t = 0; t < s->ntri; ++t) {
        size_t k = bb.idx[t];
        memcpy(v + 9 * t, s->v + 9 * k, 9 * sizeof(double));
        memcpy(n + 9 * t, s->n + 9 * k, 9 * sizeof(double));
        m[t] = s->mat[k];
        if (alb)
            memcpy(alb + 3 * t, s->alb + 3 * k, 3 * sizeof(double));
        if (uv)
            memcpy(uv + 6 * t, s->uv + 6 * k, 6 * sizeof(double));
        if (tx)
            tx[t] = s->tex[k];
    }
    free(s->v), free(s->n), free(s->mat), free(s->alb), free(s->uv), free(s->tex);
    s->v = v, s->n = n, s->mat = m, s->alb = alb, s->uv = uv, s->tex = tx;
    free(bb.cent), free(bb.idx);
    return 0;
}

static int finish(builder *b)
{
    if (b->oom || b->s->ntri == 0 || build_bvh(b->s) != 0) {
        qtool_rt_scene_free(b->s);
        return -1;
    }
    return 0;
}

int qtool_rt_scene_builtin(qtool_rt_scene *s)
{
    memset(s, 0, sizeof *s);
    static const qtool_rt_material mats[] = {
        {{0.55, 0.50, 0.42}, 0.00, 1},  /* 0 ground: sandstone */
        {{0.70, 0.32, 0.22}, 0.00, 1},  /* 1 walls: brick */
        {{0.80, 0.80, 0.78}, 0.20, 3},  /* 2 pillars and arches: satin marble */
        {{0.20, 0.35, 0.75}, 0.35, 5},  /* 3 sphere: glazed blue */
        {{0.30, 0.60, 0.30}, 0.05, 8},  /* 4 boxes: painted green */
        {{0.75, 0.55, 0.25}, 0.30, 4},  /* 5 small sphere: brass */
        {{0.62, 0.60, 0.55}, 0.00, 1},  /* 6 arcade walls: plaster */
    };
    memcpy(s->mats, mats, sizeof mats);
    s->nmat = (int)(sizeof mats / sizeof mats[0]);
    builder b = {s, 0, 0};
    const double zg = -1.6, zt = 0.6;
    /* ground and the four walls (2.2 high) of a 20 x 14 courtyard, open to the sky */
    double g0[3] = {-10, -7, zg}, g1[3] = {10, -7, zg}, g2[3] = {10, 7, zg}, g3[3] = {-10, 7, zg};
    add_quad(&b, g0, g1, g2, g3, 0);
    double w0[3] = {-10, -7, zt}, w1[3] = {10, -7, zt}, w2[3] = {10, 7, zt}, w3[3] = {-10, 7, zt};
    add_quad(&b, g0, g1, w1, w0, 1);
    add_quad(&b, g1, g2, w2, w1, 1);
    add_quad(&b, g2, g3, w3, w2, 1);
    add_quad(&b, g3, g0, w0, w3, 1);
    /* two arcades along y = +-4: five pillars each and four round arches carrying a wall band */
    for (int side = -1; side <= 1; side += 2) {
        double y = 4.0 * side;
        for (int i = 0; i < 5; ++i)
            add_cylinder(&b, -6.0 + 3.0 * i, y, 0.35, zg, 1.4, 20, 2);
        for (int i = 0; i < 4; ++i)
            add_arch(&b, -4.5 + 3.0 * i, 1.5, 1.15, 1.4, 2.9, y - 0.3, y + 0.3, 2);
        /* a wall on the arcade's top, shading the walkway behind it */
        double a0[3] = {-7.5, y - 0.3, 2.9}, a1[3] = {7.5, y + 0.3, 3.4};
        add_box(&b, a0, a1, 6);
    }
    /* the end arches' outer pillars are at x = -6 and 6; free-standing pillars at the ends */
    add_cylinder(&b, -8.5, 0.0, 0.45, zg, 3.0, 24, 2);
    add_cylinder(&b, 8.5, 0.0, 0.45, zg, 3.0, 24, 2);
    /* boxes: a stack on the left, a long low one on the right */
    double b0[3] = {-4.0, 0.8, zg}, b1[3] = {-2.6, 2.2, -0.4};
    add_box(&b, b0, b1, 4);
    double b2[3] = {-3.7, 1.1, -0.4}, b3[3] = {-2.9, 1.9, 0.4};
    add_box(&b, b2, b3, 4);
    double b4[3] = {2.0, -2.8, zg}, b5[3] = {4.5, -2.0, -0.9};
    add_box(&b, b4, b5, 4);
    /* spheres: a large glazed one, a brass one on the low box */
    double c0[3] = {4.0, 1.2, -0.6};
    add_sphere(&b, c0, 1.0, 40, 20, 3);
    double c1[3] = {3.0, -2.4, -0.45};
    add_sphere(&b, c1, 0.45, 28, 14, 5);
    return finish(&b);
}

/* a mesh's point or normal in the scene's frame (see qtool_rt_scene_from_obj) */
static void to_scene(const double *p, int zup, int raw, double q[3])
{
    if (raw) {
        q[0] = p[0], q[1] = p[1], q[2] = p[2];
        return;
    }
    double z[3] = {p[0], zup ? p[1] : -p[2], zup ? p[2] : p[1]};
    q[0] = -z[1], q[1] = z[0], q[2] = z[2];
}

/* Y-up (x, y, z) -> Z-up (x, -z, y), then a quarter turn about z, (x, y) -> (-y, x), so the
 * model's front (+z of a Y-up model, -y of a Z-up one) faces the viewer at the origin: rotations,
 * so windings and normals stay right; then the scale and offset that stand the prop */
static void placement(const qtool_obj_mesh *m, int zup, int raw, double *sc_out, double off[3])
{
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    for (size_t i = 0; i < m->ntri * 3; ++i) {
        double q[3];
        to_scene(m->pos + 3 * i, zup, raw, q);
        for (int j = 0; j < 3; ++j)
            lo[j] = q[j] < lo[j] ? q[j] : lo[j], hi[j] = q[j] > hi[j] ? q[j] : hi[j];
    }
    double size = fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2]));
    double sc = raw || size <= 0 ? 1.0 : 2.5 / size;
    off[0] = raw ? 0 : QTOOL_RT_PROP_X - sc * (lo[0] + hi[0]) / 2;
    off[1] = raw ? 0 : -sc * (lo[1] + hi[1]) / 2;
    off[2] = raw ? 0 : -1.6 - sc * lo[2];
    *sc_out = sc;
}

void qtool_rt_prop_place(const qtool_obj_mesh *m, int zup, int raw, const double p[3], int direction, double out[3])
{
    double sc, off[3], q[3];
    placement(m, zup, raw, &sc, off);
    to_scene(p, zup, raw, q);
    for (int j = 0; j < 3; ++j)
        out[j] = direction ? q[j] : q[j] * sc + off[j];
}

/* the mesh's colours per triangle: its triangles come first, the ground after them */
static int carry_materials(qtool_rt_scene *s, const qtool_obj_mesh *m)
{
    s->alb = malloc(s->ntri * 3 * sizeof(double));
    if (!s->alb)
        return -1;
    for (size_t t = 0; t < s->ntri; ++t)
        for (int j = 0; j < 3; ++j)
            s->alb[3 * t + j] = t < m->ntri && m->albedo ? m->albedo[3 * t + j] : s->mats[s->mat[t]].albedo[j];
    if (!m->tex || !m->uv || !m->ntex)
        return 0;
    s->uv = calloc(s->ntri * 6, sizeof(double));
    s->tex = malloc(s->ntri * sizeof(int32_t));
    s->texs = calloc(m->ntex, sizeof *s->texs);
    if (!s->uv || !s->tex || !s->texs)
        return -1;
    for (size_t t = 0; t < s->ntri; ++t) {
        int32_t k = t < m->ntri ? m->tex[t] : -1;
        s->tex[t] = k >= 0 && (size_t)k < m->ntex ? k : -1;
        if (t < m->ntri)
            memcpy(s->uv + 6 * t, m->uv + 6 * t, 6 * sizeof(double));
    }
    for (size_t i = 0; i < m->ntex; ++i) {
        size_t nb = (size_t)m->texs[i].w * (size_t)m->texs[i].h * 3;
        s->texs[i].rgb = malloc(nb ? nb : 1);
        if (!s->texs[i].rgb)
            return -1;
        memcpy(s->texs[i].rgb, m->texs[i].rgb, nb);
        s->texs[i].w = m->texs[i].w, s->texs[i].h = m->texs[i].h;
        s->ntex = i + 1;
    }
    return 0;
}

int qtool_rt_scene_from_obj(qtool_rt_scene *s, const qtool_obj_mesh *m, int zup, int raw)
{
    memset(s, 0, sizeof *s);
    static const qtool_rt_material mats[] = {
        {{0.55, 0.50, 0.42}, 0.00, 1}, /* 0 ground */
        {{0.75, 0.72, 0.68}, 0.15, 4}, /* 1 the mesh: glazed clay */
    };
    memcpy(s->mats, mats, sizeof mats);
    s->nmat = 2;
    builder b = {s, 0, 0};
    double sc, off[3];
    placement(m, zup, raw, &sc, off);
    for (size_t t = 0; t < m->ntri; ++t) {
        double p[3][3], n[3][3];
        for (int q = 0; q < 3; ++q) {
            double pa[3], pn[3];
            to_scene(m->pos + 9 * t + 3 * q, zup, raw, pa);
            to_scene(m->nrm + 9 * t + 3 * q, zup, raw, pn);
            for (int j = 0; j < 3; ++j)
                p[q][j] = pa[j] * sc + off[j], n[q][j] = pn[j];
        }
        add_tri(&b, p[0], p[1], p[2], n[0], n[1], n[2], 1);
    }
    if (!raw) {
        double g0[3] = {-20, -20, -1.6}, g1[3] = {20, -20, -1.6}, g2[3] = {20, 20, -1.6}, g3[3] = {-20, 20, -1.6};
        add_quad(&b, g0, g1, g2, g3, 0);
    }
    if (!b.oom && (m->albedo || m->tex) && carry_materials(s, m) != 0)
        b.oom = 1;
    return finish(&b);
}

void qtool_rt_scene_free(qtool_rt_scene *s)
{
    free(s->v), free(s->n), free(s->mat), free(s->nodes);
    free(s->alb), free(s->uv), free(s->tex);
    for (size_t i = 0; s->texs && i < s->ntex; ++i)
        free(s->texs[i].rgb);
    free(s->texs);
    memset(s, 0, sizeof *s);
}

/* ---- tracing ------------------------------------------------------------------------------------- */

static int box_hit(const qtool_rt_node *nd, const double o[3], const double inv[3], double tmax)
{
    double t0 = 0, t1 = tmax;
    for (int j = 0; j < 3; ++j) {
        double a = (nd->lo[j] - o[j]) * inv[j], b = (nd->hi[j] - o[j]) * inv[j];
        if (a > b) {
            double t = a;
            a = b, b = t;
        }
        t0 = a > t0 ? a : t0;
        t1 = b < t1 ? b : t1;
        if (t0 > t1)
            return 0;
    }
    return 1;
}

/* Moller-Trumbore; returns t in (tmin, tmax) or -1, with barycentrics */
static double tri_hit(const double *v, const double o[3], const double d[3], double tmin, double tmax, double *bu,
                      double *bv)
{
    double e1[3] = {v[3] - v[0], v[4] - v[1], v[5] - v[2]}, e2[3] = {v[6] - v[0], v[7] - v[1], v[8] - v[2]};
    double p[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0]};
    double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (fabs(det) < 1e-14)
        return -1;
    double inv = 1.0 / det;
    double tv[3] = {o[0] - v[0], o[1] - v[1], o[2] - v[2]};
    double u = (tv[0] * p[0] + tv[1] * p[1] + tv[2] * p[2]) * inv;
    if (u < 0 || u > 1)
        return -1;
    double q[3] = {tv[1] * e1[2] - tv[2] * e1[1], tv[2] * e1[0] - tv[0] * e1[2], tv[0] * e1[1] - tv[1] * e1[0]};
    double w = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) * inv;
    if (w < 0 || u + w > 1)
        return -1;
    double t = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) * inv;
    if (t <= tmin || t >= tmax)
        return -1;
    *bu = u, *bv = w;
    return t;
}

/* closest hit (any = 0) or any hit (any = 1) in (tmin, tmax); returns the triangle or -1 */
static long trace(const qtool_rt_scene *s, const double o[3], const double d[3], double tmin, double tmax, int any,
                  double *t_out, double *bu, double *bv)
{
    double inv[3];
    for (int j = 0; j < 3; ++j)
        inv[j] = d[j] != 0 ? 1.0 / d[j] : (d[j] >= 0 ? 1e300 : -1e300);
    /* the children's order depends on the ray alone: its largest axis, once per ray */
    const int axis_first = d[0] * d[0] >= d[1] * d[1] ? (d[0] * d[0] >= d[2] * d[2] ? 0 : 2)
                                                      : (d[1] * d[1] >= d[2] * d[2] ? 1 : 2);
    const uint32_t neg = d[axis_first] < 0;
    uint32_t stack[128];
    int sp = 0;
    long best = -1;
    stack[sp++] = 0;
    while (sp > 0) {
        const qtool_rt_node *nd = &s->nodes[stack[--sp]];
        if (!box_hit(nd, o, inv, tmax))
            continue;
        if (nd->count) {
            for (uint32_t i = nd->first; i < nd->first + nd->count; ++i) {
                double u, v;
                double t = tri_hit(s->v + 9 * (size_t)i, o, d, tmin, tmax, &u, &v);
                if (t > 0) {
                    tmax = t, best = (long)i;
                    if (t_out)
                        *t_out = t, *bu = u, *bv = v;
                    if (any)
                        return best;
                }
            }
        } else if (sp + 2 <= 128) {
            /* near child last so it is popped first */
            stack[sp++] = nd->first + !neg;
            stack[sp++] = nd->first + neg;
        }
    }
    return best;
}

void qtool_rt_pixel_dir(uint32_t w, uint32_t h, qtool_pano_kind kind, uint32_t x, uint32_t y, double d[3])
{
    qtool_gen_pano_dir(w, h, kind, x, y, d);
}

static int finite_in(const double v[3])
{
    for (int j = 0; j < 3; ++j)
        if (!(fabs(v[j]) <= QTOOL_RT_CAMERA_MAX_COORD))
            return 0;
    return 1;
}

int qtool_rt_camera_init(qtool_rt_camera *c, const double eye[3], const double target[3], const double up[3],
                         double fov_deg, char *err, size_t errlen)
{
    if (!finite_in(eye) || !finite_in(target) || !finite_in(up))
        return qtool_errf(err, errlen, "camera: a coordinate is not a number or beyond %g", QTOOL_RT_CAMERA_MAX_COORD);
    if (!(fov_deg > 0 && fov_deg < 180))
        return qtool_errf(err, errlen, "camera: field of view %g degrees is outside (0, 180)", fov_deg);
    double f[3] = {target[0] - eye[0], target[1] - eye[1], target[2] - eye[2]};
    double fl = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    if (!(fl > 1e-9 * (1 + fabs(eye[0]) + fabs(eye[1]) + fabs(eye[2]))))
        return qtool_errf(err, errlen, "camera: the eye is the target (no view direction)");
    for (int j = 0; j < 3; ++j)
        f[j] /= fl;
    double ul = sqrt(up[0] * up[0] + up[1] * up[1] + up[2] * up[2]);
    double r[3] = {f[1] * up[2] - f[2] * up[1], f[2] * up[0] - f[0] * up[2], f[0] * up[1] - f[1] * up[0]};
    double rl = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    /* degenerate up: zero, or within about 0.06 degrees of the view direction */
    if (!(ul > 0) || !(rl > 1e-3 * ul))
        return qtool_errf(err, errlen, "camera: the up vector is zero or parallel to the view direction");
    for (int j = 0; j < 3; ++j)
        c->eye[j] = eye[j], c->fwd[j] = f[j], c->right[j] = r[j] / rl;
    c->up[0] = c->right[1] * f[2] - c->right[2] * f[1];
    c->up[1] = c->right[2] * f[0] - c->right[0] * f[2];
    c->up[2] = c->right[0] * f[1] - c->right[1] * f[0];
    c->tan_half = tan(fov_deg * QTOOL_PI / 360);
    return 0;
}

void qtool_rt_pixel_ray(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, uint32_t x, uint32_t y,
                        double d[3])
{
    if (!s->has_cam) {
        qtool_rt_pixel_dir(w, h, kind, x, y, d);
        return;
    }
    const qtool_rt_camera *c = &s->cam;
    double a = (2 * (x + 0.5) / w - 1) * c->tan_half * w / h, b = (1 - 2 * (y + 0.5) / h) * c->tan_half, l = 0;
    for (int j = 0; j < 3; ++j)
        d[j] = c->fwd[j] + a * c->right[j] + b * c->up[j], l += d[j] * d[j];
    l = sqrt(l);
    for (int j = 0; j < 3; ++j)
        d[j] /= l;
}

void qtool_rt_sky_point(const qtool_rt_scene *s, const double d[3], double dist, double out[3])
{
    for (int j = 0; j < 3; ++j)
        out[j] = s->has_cam ? s->cam.eye[j] + d[j] * dist : d[j] * dist;
}

static double srgb_linear(uint8_t c)
{
    double x = c / 255.0;
    return x <= 0.04045 ? x / 12.92 : pow((x + 0.055) / 1.055, 2.4);
}

/* the triangle's albedo, times its texture bilinearly sampled (repeating) at the barycentric uv */
static void hit_albedo(const qtool_rt_scene *s, size_t tri, double u, double v, double out[3])
{
    const double *a = s->alb ? s->alb + 3 * tri : s->mats[s->mat[tri]].albedo;
    out[0] = a[0], out[1] = a[1], out[2] = a[2];
    if (!s->tex || s->tex[tri] < 0)
        return;
    const qtool_mesh_texture *tx = &s->texs[s->tex[tri]];
    const double *c = s->uv + 6 * tri;
    double tu = (1 - u - v) * c[0] + u * c[2] + v * c[4], tv = (1 - u - v) * c[1] + u * c[3] + v * c[5];
    double fx = (tu - floor(tu)) * tx->w - 0.5, fy = (tv - floor(tv)) * tx->h - 0.5;
    double x0 = floor(fx), y0 = floor(fy), wx = fx - x0, wy = fy - y0;
    double acc[3] = {0, 0, 0};
    for (int k = 0; k < 4; ++k) {
        long xi = (long)x0 + (k & 1), yi = (long)y0 + (k >> 1);
        xi = ((xi % tx->w) + tx->w) % tx->w, yi = ((yi % tx->h) + tx->h) % tx->h;
        double wgt = ((k & 1) ? wx : 1 - wx) * ((k >> 1) ? wy : 1 - wy);
        const uint8_t *p = tx->rgb + 3 * ((size_t)yi * (size_t)tx->w + (size_t)xi);
        for (int j = 0; j < 3; ++j)
            acc[j] += wgt * srgb_linear(p[j]);
    }
    for (int j = 0; j < 3; ++j)
        out[j] *= acc[j];
}

void qtool_rt_primary(const qtool_rt_scene *s, const double d[3], qtool_rt_hit *h)
{
    static const double origin[3] = {0, 0, 0};
    const double *o = s->has_cam ? s->cam.eye : origin;
    double t = 0, u = 0, v = 0;
    long tri = trace(s, o, d, 1e-9, 1e30, 0, &t, &u, &v);
    memset(h, 0, sizeof *h);
    if (tri < 0)
        return;
    const double *vv = s->v + 9 * (size_t)tri, *nn = s->n + 9 * (size_t)tri;
    h->hit = 1, h->t = t;
    h->m = &s->mats[s->mat[tri]];
    hit_albedo(s, (size_t)tri, u, v, h->albedo);
    flat_normal(vv, vv + 3, vv + 6, h->ng);
    double l = 0;
    for (int j = 0; j < 3; ++j) {
        h->p[j] = s->has_cam ? o[j] + d[j] * t : d[j] * t;
        h->n[j] = (1 - u - v) * nn[j] + u * nn[3 + j] + v * nn[6 + j];
        l += h->n[j] * h->n[j];
    }
    l = sqrt(l);
    int nz = l > 1e-12;
    for (int j = 0; j < 3; ++j)
        h->n[j] = nz ? h->n[j] / l : h->ng[j];
    /* both normals towards the viewer */
    if (h->ng[0] * d[0] + h->ng[1] * d[1] + h->ng[2] * d[2] > 0)
        for (int j = 0; j < 3; ++j)
            h->ng[j] = -h->ng[j];
    if (h->n[0] * h->ng[0] + h->n[1] * h->ng[1] + h->n[2] * h->ng[2] < 0)
        for (int j = 0; j < 3; ++j)
            h->n[j] = -h->n[j];
    double dn = d[0] * h->n[0] + d[1] * h->n[1] + d[2] * h->n[2];
    for (int j = 0; j < 3; ++j)
        h->r[j] = d[j] - 2 * dn * h->n[j];
}

int qtool_rt_occluded(const qtool_rt_scene *s, const qtool_rt_hit *h, const double w[3], double tmax)
{
    double eps = 1e-5 * (s->scale > 0 ? s->scale : 1) + 1e-6 * h->t;
    double o[3];
    for (int j = 0; j < 3; ++j)
        o[j] = h->p[j] + eps * h->ng[j];
    return trace(s, o, w, 0, tmax, 1, NULL, NULL, NULL) >= 0;
}

int qtool_rt_response(const qtool_rt_scene *s, const qtool_rt_hit *h, const double w[3], double tmax, double *diff,
                     double *gloss)
{
    *diff = *gloss = 0;
    if (!h->hit)
        return 0;
    double cg = h->ng[0] * w[0] + h->ng[1] * w[1] + h->ng[2] * w[2];
    double cn = h->n[0] * w[0] + h->n[1] * w[1] + h->n[2] * w[2];
    if (cg <= 0 || cn <= 0)
        return 0;
    if (tmax > 0 && qtool_rt_occluded(s, h, w, tmax))
        return 0;
    *diff = cn / QTOOL_PI;
    if (h->m->ks > 0) {
        double cr = h->r[0] * w[0] + h->r[1] * w[1] + h->r[2] * w[2];
        *gloss = cr > 0 ? (h->m->shininess + 2) / (2 * QTOOL_PI) * pow(cr, h->m->shininess) : 0;
    }
    return 1;
}

/* ---- rendering ----------------------------------------------------------------------------------- */

/* a pass over the panorama's pixels under light l: a render (rgb, depth, pmap) or a classification */
typedef struct {
    const qtool_rt_scene *s;
    uint32_t w, h;
    qtool_pano_kind kind;
    const qtool_rt_light *l;
    double *rgb;
    float *depth;
    int32_t *pmap;
    double (*gonio)(const void *ctx, const double d[3]); /* NULL: isotropic */
    const void *gonio_ctx;
    uint8_t *cls;
} render_job;

/* The unit direction from p toward l into w, and the distance to a point light (a directional
 * light: its direction's length); w is 0 when that is 0. */
static double toward_light(const qtool_rt_light *l, const double p[3], double w[3])
{
    double len = 0;
    for (int c = 0; c < 3; ++c) {
        w[c] = l->point ? l->pos[c] - p[c] : l->dir[c];
        len += w[c] * w[c];
    }
    len = sqrt(len);
    for (int c = 0; c < 3; ++c)
        w[c] = len > 0 ? w[c] / len : 0;
    return len;
}

static void render_row(void *ctx, uint32_t y)
{
    const render_job *j = ctx;
    for (uint32_t x = 0; x < j->w; ++x) {
        size_t pi = (size_t)y * j->w + x;
        double d[3];
        qtool_rt_hit h;
        qtool_rt_pixel_ray(j->s, j->w, j->h, j->kind, x, y, d);
        qtool_rt_primary(j->s, d, &h);
        if (j->pmap) {
            double sky[3];
            qtool_rt_sky_point(j->s, d, 1000.0, sky);
            for (int k = 0; k < 3; ++k)
                j->pmap[3 * pi + (size_t)k] = (int32_t)lrint((h.hit ? h.p[k] : sky[k]) * 65536.0);
        }
        if (j->depth)
            j->depth[pi] = h.hit ? (float)h.t : 0.0f;
        if (!j->rgb)
            continue;
        double *o = j->rgb + 3 * pi;
        o[0] = o[1] = o[2] = 0;
        if (!h.hit)
            continue;
        double wv[3], tmax = 1e30, att = 1, df, gl;
        const double len = toward_light(j->l, h.p, wv);
        if (j->l->point) {
            if (len < 1.0 / 256)
                continue;
            tmax = len;
            att = j->l->falloff == 2 ? 1 / (len * len) : 1 / len;
            if (j->gonio) {
                double out_dir[3] = {-wv[0], -wv[1], -wv[2]};
                att *= j->gonio(j->gonio_ctx, out_dir);
            }
        }
        if (!qtool_rt_response(j->s, &h, wv, tmax, &df, &gl))
            continue;
        for (int c = 0; c < 3; ++c)
            o[c] = j->l->rgb[c] * att * (h.albedo[c] * df + h.m->ks * gl);
    }
}

int qtool_rt_render(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, const qtool_rt_light *l,
                   int threads, double *rgb, float *depth, int32_t *pmap)
{
    render_job j = {s, w, h, kind, l, rgb, depth, pmap, NULL, NULL, NULL};
    return qtool_rt_parallel(threads, h, render_row, &j, NULL);
}

int qtool_rt_render_gonio(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind,
                         const qtool_rt_light *l, double (*gonio)(const void *ctx, const double d[3]),
                         const void *ctx, int threads, double *rgb, float *depth, int32_t *pmap)
{
    render_job j = {s, w, h, kind, l, rgb, depth, pmap, gonio, ctx, NULL};
    return qtool_rt_parallel(threads, h, render_row, &j, NULL);
}

static void classify_row(void *ctx, uint32_t y)
{
    const render_job *j = ctx;
    for (uint32_t x = 0; x < j->w; ++x) {
        double d[3], w[3];
        qtool_rt_hit h;
        uint8_t *o = j->cls + (size_t)y * j->w + x;
        qtool_rt_pixel_ray(j->s, j->w, j->h, j->kind, x, y, d);
        qtool_rt_primary(j->s, d, &h);
        if (!h.hit) {
            *o = 0;
            continue;
        }
        const double len = toward_light(j->l, h.p, w);
        double cg = h.ng[0] * w[0] + h.ng[1] * w[1] + h.ng[2] * w[2];
        double cn = h.n[0] * w[0] + h.n[1] * w[1] + h.n[2] * w[2];
        if (cg <= 0 || cn <= 0 || len < 1.0 / 256)
            *o = 3;
        else
            *o = qtool_rt_occluded(j->s, &h, w, j->l->point ? len : 1e30) ? 2 : 1;
    }
}

int qtool_rt_classify(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, const qtool_rt_light *l,
                      int threads, uint8_t *cls)
{
    render_job j = {.s = s, .w = w, .h = h, .kind = kind, .l = l, .cls = cls};
    return qtool_rt_parallel(threads, h, classify_row, &j, NULL);
}

/* ---- threads ------------------------------------------------------------------------------------- */

typedef struct {
    pthread_mutex_t lock;
    uint32_t next, done, rows;
    void (*fn)(void *, uint32_t);
    void (*progress)(void *, uint32_t, uint32_t);
    void *ctx;
} pool;

static void *worker(void *arg)
{
    pool *p = arg;
    for (;;) {
        pthread_mutex_lock(&p->lock);
        uint32_t r = p->next < p->rows ? p->next++ : UINT32_MAX;
        pthread_mutex_unlock(&p->lock);
        if (r == UINT32_MAX)
            return NULL;
        p->fn(p->ctx, r);
        pthread_mutex_lock(&p->lock);
        p->done++;
        if (p->progress)
            p->progress(p->ctx, p->done, p->rows);
        pthread_mutex_unlock(&p->lock);
    }
}

int qtool_rt_parallel(int threads, uint32_t rows, void (*fn)(void *ctx, uint32_t row), void *ctx,
                     void (*progress)(void *ctx, uint32_t done, uint32_t rows))
{
    pool p;
    pthread_mutex_init(&p.lock, NULL);
    p.next = 0, p.done = 0, p.rows = rows, p.fn = fn, p.progress = progress, p.ctx = ctx;
    if (threads < 1)
        threads = 1;
    if (threads > 256)
        threads = 256;
    pthread_t tid[256];
    int started = 0;
    for (int i = 1; i < threads; ++i) {
        if (pthread_create(&tid[started], NULL, worker, &p) != 0)
            break; /* fewer threads: same result */
        ++started;
    }
    worker(&p);
    for (int i = 0; i < started; ++i)
        pthread_join(tid[i], NULL);
    pthread_mutex_destroy(&p.lock);
    return 0;
}
