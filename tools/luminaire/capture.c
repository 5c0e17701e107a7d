/*
 * luminaire/capture.c - the built-in luminaire (a shade traced with tools/render's ray tracer around
 * an analytic emitter), its true irradiance, and the simulated acquisition of the paper's Figure 1.
 *
 * Invariants: everything is in the source's frame (S is z = 0, light toward -z); every ray is traced
 * independently in double with fixed sample positions, so a capture is the same whatever the thread
 * count.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "luminaire/luminaire.h"
#include "render/rt.h"

#define PLATE_Z 0.002
#define TOP_Z 0.2
#define EMIT_Z 0.16
#define EMIT_HALF 0.08
#define HALF (QTOOL_LUMINAIRE_SIZE / 2)
#define CELLS 4

struct qtool_luminaire_model {
    qtool_rt_scene shade;
    double le[3];
    double emit_z, emit_half; /* the square emitter facing down */
    double half;              /* S's grid covers -half..half in x and y */
};

static void tri(double *pos, double *nrm, size_t *k, const double a[3], const double b[3], const double c[3])
{
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int j = 0; j < 3; ++j) {
        pos[9 * *k + j] = a[j], pos[9 * *k + 3 + j] = b[j], pos[9 * *k + 6 + j] = c[j];
        nrm[9 * *k + j] = nrm[9 * *k + 3 + j] = nrm[9 * *k + 6 + j] = n[j] / l;
    }
    ++*k;
}

static void quad(double *pos, double *nrm, size_t *k, const double a[3], const double b[3], const double c[3],
                 const double d[3])
{
    tri(pos, nrm, k, a, b, c);
    tri(pos, nrm, k, a, c, d);
}

qtool_luminaire_model *qtool_luminaire_builtin(void)
{
    qtool_luminaire_model *m = calloc(1, sizeof *m);
    const size_t ntri = 2 * (CELLS * CELLS / 2) + 2 * 4 + 2;
    double *pos = calloc(ntri * 9, sizeof(double)), *nrm = calloc(ntri * 9, sizeof(double));
    if (!m || !pos || !nrm) {
        free(m), free(pos), free(nrm);
        return NULL;
    }
    size_t k = 0;
    const double c = QTOOL_LUMINAIRE_SIZE / CELLS;
    /* the plate: solid cells where ix + iy is odd, holes elsewhere (a checkerboard) */
    for (int iy = 0; iy < CELLS; ++iy)
        for (int ix = 0; ix < CELLS; ++ix) {
            if (((ix + iy) & 1) == 0)
                continue;
            double x0 = -HALF + ix * c, y0 = -HALF + iy * c, x1 = x0 + c, y1 = y0 + c;
            double a[3] = {x0, y0, PLATE_Z}, b[3] = {x1, y0, PLATE_Z}, cc[3] = {x1, y1, PLATE_Z},
                   d[3] = {x0, y1, PLATE_Z};
            quad(pos, nrm, &k, a, b, cc, d);
        }
    /* four walls and the top: nothing leaves but through the plate's holes */
    const double lo = PLATE_Z, hi = TOP_Z;
    const double cx[4] = {-HALF, HALF, HALF, -HALF}, cy[4] = {-HALF, -HALF, HALF, HALF};
    for (int s = 0; s < 4; ++s) {
        int t = (s + 1) & 3;
        double a[3] = {cx[s], cy[s], lo}, b[3] = {cx[t], cy[t], lo}, cc[3] = {cx[t], cy[t], hi},
               d[3] = {cx[s], cy[s], hi};
        quad(pos, nrm, &k, a, b, cc, d);
    }
    double a[3] = {-HALF, -HALF, hi}, b[3] = {HALF, -HALF, hi}, cc[3] = {HALF, HALF, hi}, d[3] = {-HALF, HALF, hi};
    quad(pos, nrm, &k, a, b, cc, d);
    qtool_obj_mesh mesh = {.ntri = k, .pos = pos, .nrm = nrm};
    int rc = qtool_rt_scene_from_obj(&m->shade, &mesh, 1, 1);
    free(pos), free(nrm);
    if (rc != 0) {
        free(m);
        return NULL;
    }
    m->le[0] = QTOOL_LUMINAIRE_LE, m->le[1] = 0.9 * QTOOL_LUMINAIRE_LE, m->le[2] = 0.75 * QTOOL_LUMINAIRE_LE;
    m->emit_z = EMIT_Z, m->emit_half = EMIT_HALF, m->half = HALF;
    return m;
}

qtool_luminaire_model *qtool_luminaire_from_mesh(const qtool_obj_mesh *mesh, double emit_z, double emit_half,
                                                 char *err, size_t errlen)
{
    double half = 0, top = 0;
    for (size_t i = 0; i < mesh->ntri * 3; ++i) {
        const double *v = mesh->pos + 3 * i;
        if (!(v[2] > 0)) {
            snprintf(err, errlen, "a vertex at z = %g: the luminaire must lie above its sampling plane z = 0", v[2]);
            return NULL;
        }
        half = fmax(half, fmax(fabs(v[0]), fabs(v[1]))), top = fmax(top, v[2]);
    }
    emit_z = emit_z > 0 ? emit_z : 0.8 * top;         /* the built-in one's proportions */
    emit_half = emit_half > 0 ? emit_half : 0.4 * half;
    if (mesh->ntri == 0 || !(emit_z > 0 && emit_z < top) || !(emit_half > 0 && emit_half < half)) {
        snprintf(err, errlen, "the emitter (z %g, half-size %g) must lie inside the mesh (top %g, half-width %g)",
                 emit_z, emit_half, top, half);
        return NULL;
    }
    qtool_luminaire_model *m = calloc(1, sizeof *m);
    if (!m || qtool_rt_scene_from_obj(&m->shade, mesh, 1, 1) != 0) {
        free(m);
        snprintf(err, errlen, "out of memory");
        return NULL;
    }
    m->le[0] = QTOOL_LUMINAIRE_LE, m->le[1] = 0.9 * QTOOL_LUMINAIRE_LE, m->le[2] = 0.75 * QTOOL_LUMINAIRE_LE;
    m->emit_z = emit_z, m->emit_half = emit_half, m->half = half;
    return m;
}

void qtool_luminaire_model_free(qtool_luminaire_model *m)
{
    if (m) {
        qtool_rt_scene_free(&m->shade);
        free(m);
    }
}

/* 1 if the segment from o along unit d up to tmax crosses the shade (rt.h: a hit with no normal
 * offset, so the ray starts exactly at o) */
static int blocked(const qtool_luminaire_model *m, const double o[3], const double d[3], double tmax)
{
    qtool_rt_hit h;
    memset(&h, 0, sizeof h);
    h.hit = 1;
    memcpy(h.p, o, sizeof h.p);
    return qtool_rt_occluded(&m->shade, &h, d, tmax);
}

void qtool_luminaire_model_radiance(const qtool_luminaire_model *m, const double o[3], const double d[3],
                                    double rgb[3])
{
    rgb[0] = rgb[1] = rgb[2] = 0;
    if (d[2] <= 0)
        return;
    double t = (m->emit_z - o[2]) / d[2];
    double x = o[0] + t * d[0], y = o[1] + t * d[1];
    if (t <= 0 || fabs(x) > m->emit_half || fabs(y) > m->emit_half || blocked(m, o, d, t))
        return;
    memcpy(rgb, m->le, sizeof m->le);
}

/* a fixed, well-spread jitter in [0, 1) for sample k of a stratified grid (no random state) */
static double jitter(uint32_t k, uint32_t salt)
{
    uint32_t h = k * 2654435761u ^ salt * 2246822519u;
    h ^= h >> 15, h *= 2246822519u, h ^= h >> 13;
    return (h & 0xFFFFFFu) / 16777216.0;
}

void qtool_luminaire_model_irradiance(const qtool_luminaire_model *m, const double p[3], const double nrm[3],
                                      uint32_t ns, double rgb[3])
{
    const double eh = m->emit_half;
    double e = 0, da = (2 * eh / ns) * (2 * eh / ns);
    for (uint32_t j = 0; j < ns; ++j)
        for (uint32_t i = 0; i < ns; ++i) {
            uint32_t k = j * ns + i;
            double q[3] = {-eh + (i + jitter(k, 1)) * 2 * eh / ns, -eh + (j + jitter(k, 2)) * 2 * eh / ns, m->emit_z};
            double w[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
            double r = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
            if (r <= 0)
                continue;
            for (int c = 0; c < 3; ++c)
                w[c] /= r;
            double ce = w[2], cp = w[0] * nrm[0] + w[1] * nrm[1] + w[2] * nrm[2];
            if (ce <= 0 || cp <= 0 || blocked(m, p, w, r))
                continue;
            e += ce * cp / (r * r) * da;
        }
    for (int c = 0; c < 3; ++c)
        rgb[c] = m->le[c] * e;
}

void qtool_luminaire_yard_sample(const qtool_luminaire_model *m, const double p[3], uint32_t ns,
                                 const qtool_rt_scene *sc, const qtool_rt_hit *h, double rgb[3])
{
    const double eh = m->emit_half, da = (2 * eh / ns) * (2 * eh / ns);
    for (uint32_t j = 0; j < ns; ++j)
        for (uint32_t i = 0; i < ns; ++i) {
            uint32_t k = j * ns + i;
            double q[3] = {-eh + (i + jitter(k, 1)) * 2 * eh / ns, -eh + (j + jitter(k, 2)) * 2 * eh / ns, m->emit_z};
            double w[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
            double r = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]), df, gl;
            if (r <= 0)
                continue;
            for (int c = 0; c < 3; ++c)
                w[c] /= r;
            if (w[2] <= 0 || blocked(m, p, w, r) || !qtool_rt_response(sc, h, w, r, &df, &gl))
                continue;
            double g = w[2] / (r * r) * da; /* the emitter's cosine over r^2, its area */
            for (int c = 0; c < 3; ++c)
                rgb[c] += m->le[c] * g * (h->albedo[c] * df + h->m->ks * gl);
        }
}

typedef struct cap_ctx {
    const qtool_luminaire_model *m;
    qtool_luminaire *l;
    uint32_t q;
} cap_ctx;

static double tent(double a)
{
    a = fabs(a);
    return a < 1 ? 1 - a : 0;
}

/* one support (the row index of qtool_rt_parallel): every texel of its emission texture */
static void cap_support(void *vctx, uint32_t row)
{
    const cap_ctx *c = vctx;
    qtool_luminaire *l = c->l;
    const uint32_t ix = row % l->nx, iy = row / l->nx, res = l->res;
    const double h = l->spacing, D = l->distance, w = l->half_tan;
    const double u0 = (ix - (l->nx - 1) / 2.0) * h, v0 = (iy - (l->ny - 1) / 2.0) * h;
    const int tentb = l->basis == QTOOL_LUMINAIRE_TENT;
    /* the filter's support: the cell (box) or two cells (tent), c->q midpoints per cell and axis */
    const uint32_t nq = tentb ? 2 * c->q : c->q;
    const double ext = tentb ? h : h / 2, step = 2 * ext / nq, da = step * step;
    for (uint32_t j = 0; j < res; ++j)
        for (uint32_t i = 0; i < res; ++i) {
            double s = u0 + ((2.0 * i + 1) / res - 1) * D * w, t = v0 + ((2.0 * j + 1) / res - 1) * D * w;
            double e[3] = {0, 0, 0};
            for (uint32_t b = 0; b < nq; ++b)
                for (uint32_t a = 0; a < nq; ++a) {
                    double du = -ext + (a + 0.5) * step, dv = -ext + (b + 0.5) * step;
                    double phi = tentb ? tent(du / h) * tent(dv / h) / (h * h) : 1 / (h * h);
                    double o[3] = {u0 + du, v0 + dv, 0};
                    double d[3] = {o[0] - s, o[1] - t, D};
                    double r2 = d[0] * d[0] + d[1] * d[1] + D * D, r = sqrt(r2), L[3];
                    for (int k = 0; k < 3; ++k)
                        d[k] /= r;
                    qtool_luminaire_model_radiance(c->m, o, d, L);
                    double g = (D / r) * (D / r) / r2 * phi * da; /* cos^2 / R^2, the filter, du dv */
                    for (int k = 0; k < 3; ++k)
                        e[k] += g * L[k];
                }
            /* E' = E / g at the support's centre (eq. 9-10) */
            double rc2 = (u0 - s) * (u0 - s) + (v0 - t) * (v0 - t) + D * D, ginv = rc2 * rc2 / (D * D);
            float *o = l->tex + qtool_luminaire_texel(l, ix, iy, i, j);
            for (int k = 0; k < 3; ++k)
                o[k] = (float)(e[k] * ginv);
        }
}

int qtool_luminaire_capture(const qtool_luminaire_model *m, const qtool_luminaire_capture_opts *o,
                            qtool_luminaire *out)
{
    qtool_luminaire l = {.nx = o->grid ? o->grid : 8, .res = o->res ? o->res : 32,
                         .basis = o->basis ? o->basis : QTOOL_LUMINAIRE_BOX};
    l.ny = l.nx;
    /* box: the cells tile the extent; tent: the outer centres on its edges, so the tents sum to 1
     * over all of it (a partition of unity: no light near the edge is lost) */
    l.spacing = (float)(l.basis == QTOOL_LUMINAIRE_TENT && l.nx > 1 ? 2 * m->half / (l.nx - 1) : 2 * m->half / l.nx);
    l.distance = (float)(o->distance > 0 ? o->distance : 1.0);
    l.half_tan = (float)(o->half_tan > 0 ? o->half_tan : 2.0);
    l.tex = calloc((size_t)l.nx * l.ny * l.res * l.res * 3, sizeof(float));
    if (!l.tex)
        return -1;
    cap_ctx c = {.m = m, .l = &l, .q = o->samples ? o->samples : 6};
    if (qtool_rt_parallel(o->threads > 0 ? o->threads : 1, l.nx * l.ny, cap_support, &c, NULL) != 0) {
        free(l.tex);
        return -1;
    }
    *out = l;
    return 0;
}

void qtool_luminaire_flux(const qtool_luminaire *l, double rgb[3])
{
    const double h = l->spacing, D = l->distance, w = l->half_tan, A = h * h;
    const uint32_t res = l->res;
    const double ds = 2 * D * w / res; /* texel side on M */
    rgb[0] = rgb[1] = rgb[2] = 0;
    for (uint32_t iy = 0; iy < l->ny; ++iy)
        for (uint32_t ix = 0; ix < l->nx; ++ix)
            for (uint32_t j = 0; j < res; ++j)
                for (uint32_t i = 0; i < res; ++i) {
                    double a = ((2.0 * i + 1) / res - 1) * D * w, b = ((2.0 * j + 1) / res - 1) * D * w;
                    double r2 = a * a + b * b + D * D;
                    /* irradiance on M from spotlight m: A E' cos * cos / R^2 with cos = D / R */
                    double g = A * D * D / (r2 * r2) * ds * ds;
                    const float *t = l->tex + qtool_luminaire_texel(l, ix, iy, i, j);
                    for (int k = 0; k < 3; ++k)
                        rgb[k] += g * t[k];
                }
}
