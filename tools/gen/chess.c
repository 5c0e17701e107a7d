/*
 * gen/chess.c - the procedural chess set (gen/chess.h).
 */
#include "gen/chess.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/atomic.h"
#include "qtool.h"

#define GRID 16     /* board quads per side */
#define LIFT 0.005  /* pieces stand this far above the board (no vertex shared with it) */

enum { PAWN, ROOK, KNIGHT, BISHOP, QUEEN, KING, KINDS };

/* profiles: (radius, height) from the base up; the top pole closes the last ring */
typedef struct profile {
    int n;
    double r[8], z[8], top;
} profile;

static const profile profiles[KINDS] = {
    {6, {0.34, 0.34, 0.20, 0.11, 0.17, 0.10}, {0.0, 0.08, 0.15, 0.38, 0.47, 0.60}, 0.63},
    {6, {0.36, 0.36, 0.25, 0.21, 0.29, 0.29}, {0.0, 0.10, 0.20, 0.60, 0.70, 0.86}, 0.86},
    {6, {0.36, 0.36, 0.24, 0.19, 0.27, 0.14}, {0.0, 0.10, 0.20, 0.45, 0.66, 0.86}, 0.92},
    {6, {0.35, 0.35, 0.22, 0.13, 0.20, 0.09}, {0.0, 0.10, 0.20, 0.62, 0.78, 0.98}, 1.06},
    {6, {0.38, 0.38, 0.26, 0.14, 0.28, 0.19}, {0.0, 0.10, 0.20, 0.78, 0.98, 1.08}, 1.16},
    {7, {0.38, 0.38, 0.26, 0.15, 0.28, 0.11, 0.11}, {0.0, 0.10, 0.20, 0.82, 1.02, 1.12, 1.26}, 1.30},
};

static const int back_rank[8] = {ROOK, KNIGHT, BISHOP, QUEEN, KING, BISHOP, KNIGHT, ROOK};

typedef struct piece {
    int kind, col, row; /* square of frame 0 */
    double lean;        /* the knight's head: rings above the waist shift by lean * height (x) */
} piece;

static uint32_t piece_verts(int kind, int seg)
{
    return (uint32_t)(profiles[kind].n * seg + 2);
}

static uint32_t piece_tris(int kind, int seg)
{
    return (uint32_t)(2 * seg * (profiles[kind].n - 1) + 2 * seg);
}

/* piece vertices at (x, y) on the board (z at the base) */
static void piece_pos(const piece *p, int seg, double x, double y, double z, double *out)
{
    const profile *pr = &profiles[p->kind];
    double *o = out;
    o[0] = x, o[1] = y, o[2] = z + LIFT, o += 3; /* bottom pole */
    for (int i = 0; i < pr->n; ++i) {
        const double dx = pr->z[i] > 0.4 ? p->lean * (pr->z[i] - 0.4) : 0;
        for (int s = 0; s < seg; ++s) {
            const double a = 2 * QTOOL_PI * s / seg;
            o[0] = x + dx + pr->r[i] * cos(a), o[1] = y + pr->r[i] * sin(a), o[2] = z + LIFT + pr->z[i], o += 3;
        }
    }
    o[0] = x + (p->lean != 0 ? p->lean * (pr->top - 0.4) : 0), o[1] = y, o[2] = z + LIFT + pr->top; /* top pole */
}

static void piece_tri(int kind, int seg, uint32_t base, uint32_t (*t)[3])
{
    const int n = profiles[kind].n;
    const uint32_t bot = base, top = base + (uint32_t)(n * seg) + 1;
    size_t k = 0;
    for (int s = 0; s < seg; ++s) { /* bottom cap, facing down */
        const uint32_t a = base + 1 + (uint32_t)s, b = base + 1 + (uint32_t)((s + 1) % seg);
        t[k][0] = bot, t[k][1] = b, t[k][2] = a, ++k;
    }
    for (int i = 0; i + 1 < n; ++i)
        for (int s = 0; s < seg; ++s) {
            const uint32_t a = base + 1 + (uint32_t)(i * seg + s), b = base + 1 + (uint32_t)(i * seg + (s + 1) % seg);
            const uint32_t c = b + (uint32_t)seg, d = a + (uint32_t)seg;
            t[k][0] = a, t[k][1] = b, t[k][2] = c, ++k;
            t[k][0] = a, t[k][1] = c, t[k][2] = d, ++k;
        }
    for (int s = 0; s < seg; ++s) { /* top cap */
        const uint32_t a = base + 1 + (uint32_t)((n - 1) * seg + s), b = base + 1 + (uint32_t)((n - 1) * seg + (s + 1) % seg);
        t[k][0] = a, t[k][1] = b, t[k][2] = top, ++k;
    }
}

void qtool_chess_free(qtool_chess *c)
{
    free(c->tri), free(c->pos);
    memset(c, 0, sizeof *c);
}

/* where piece i stands in frame f of nf: the movers' paths (t in [0, 1]) */
static void place(const piece *p, int i, int f, int nf, double *x, double *y, double *z)
{
    const double t = nf > 1 ? (double)f / (nf - 1) : 0;
    *x = p->col + 0.5, *y = p->row + 0.5, *z = 0;
    if (i == 12) /* white e-pawn: e2 -> e4 */
        *y += 2 * t;
    else if (i == 6) /* white g-knight: g1 -> f3, hopping */
        *x -= t, *y += 2 * t, *z = 0.8 * sin(QTOOL_PI * t);
    else if (i == 16 + 8 + 3) /* black d-pawn: d7 -> d5, in the second half */
        *y -= 2 * (t < 0.5 ? 0 : 2 * (t - 0.5));
}

int qtool_chess_make(int nframes, int segments, qtool_chess *out)
{
    memset(out, 0, sizeof *out);
    if (nframes < 1 || nframes > 64 || segments < 3 || segments > 64)
        return -1;
    piece pc[32];
    for (int i = 0; i < 32; ++i) { /* 0..15 white (ranks 1, 2), 16..31 black (ranks 8, 7) */
        const int black = i >= 16, k = i % 16;
        pc[i].col = k % 8;
        pc[i].row = black ? (k < 8 ? 7 : 6) : (k < 8 ? 0 : 1);
        pc[i].kind = k < 8 ? back_rank[k] : PAWN;
        pc[i].lean = pc[i].kind == KNIGHT ? (black ? -0.35 : 0.35) : 0;
    }
    uint32_t nv = (GRID + 1) * (GRID + 1), nt = 2 * GRID * GRID;
    for (int i = 0; i < 32; ++i)
        nv += piece_verts(pc[i].kind, segments), nt += piece_tris(pc[i].kind, segments);
    out->tri = malloc(sizeof *out->tri * nt);
    out->pos = malloc(sizeof(double) * 3 * nv * (size_t)nframes);
    if (!out->tri || !out->pos) {
        qtool_chess_free(out);
        return -1;
    }
    out->nv = nv, out->nt = nt, out->nframes = (uint32_t)nframes;
    /* triangles: the board's grid, then the pieces */
    uint32_t k = 0, base = (GRID + 1) * (GRID + 1);
    for (uint32_t j = 0; j < GRID; ++j)
        for (uint32_t i = 0; i < GRID; ++i) {
            const uint32_t a = j * (GRID + 1) + i, b = a + 1, c = a + GRID + 2, d = a + GRID + 1;
            out->tri[k][0] = a, out->tri[k][1] = b, out->tri[k][2] = c, ++k;
            out->tri[k][0] = a, out->tri[k][1] = c, out->tri[k][2] = d, ++k;
        }
    for (int i = 0; i < 32; ++i) {
        piece_tri(pc[i].kind, segments, base, out->tri + k);
        k += piece_tris(pc[i].kind, segments), base += piece_verts(pc[i].kind, segments);
    }
    for (int f = 0; f < nframes; ++f) {
        double *P = out->pos + 3 * (size_t)nv * (size_t)f;
        for (uint32_t j = 0; j <= GRID; ++j)
            for (uint32_t i = 0; i <= GRID; ++i) {
                double *q = P + 3 * (j * (GRID + 1) + i);
                q[0] = 8.0 * i / GRID, q[1] = 8.0 * j / GRID, q[2] = 0;
            }
        size_t o = 3 * (size_t)(GRID + 1) * (GRID + 1);
        for (int i = 0; i < 32; ++i) {
            double x, y, z;
            place(&pc[i], i, f, nframes, &x, &y, &z);
            piece_pos(&pc[i], segments, x, y, z, P + o);
            o += 3 * (size_t)piece_verts(pc[i].kind, segments);
        }
    }
    return 0;
}

int qtool_chess_write_obj(const qtool_chess *c, uint32_t f, const char *path, char *err, size_t errlen)
{
    if (f >= c->nframes) {
        snprintf(err, errlen, "%s: frame %u of %u", path, f, c->nframes);
        return -1;
    }
    qtool_io_atomic a;
    if (qtool_io_atomic_open(&a, path, err, errlen) != 0)
        return -1;
    const double *P = c->pos + 3 * (size_t)c->nv * f;
    fprintf(a.f, "# qibl procedural chess set, frame %u of %u (z up)\n", f + 1, c->nframes);
    for (uint32_t v = 0; v < c->nv; ++v)
        fprintf(a.f, "v %.9g %.9g %.9g\n", P[3 * v], P[3 * v + 1], P[3 * v + 2]);
    for (uint32_t t = 0; t < c->nt; ++t)
        fprintf(a.f, "f %u %u %u\n", c->tri[t][0] + 1, c->tri[t][1] + 1, c->tri[t][2] + 1);
    return qtool_io_atomic_commit(&a, err, errlen);
}
