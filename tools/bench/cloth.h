/*
 * tools/bench/cloth.h - internal to tools/bench: the cloth scene of the hemi benches (hemi.c, and
 * twin_hemi.c in the qibl-bench program). A 37 x 37 mass-spring cloth (1369 vertices, 2592
 * triangles) dropped onto a sphere, frames sampled while it drapes; its coarse mesh (every 4th grid
 * vertex, 10 x 10, 162 triangles) and, per vertex, the blockers of the paper's two-level hierarchy.
 */
#ifndef QTOOL_BENCH_CLOTH_H
#define QTOOL_BENCH_CLOTH_H

#include <stddef.h>
#include <stdint.h>

#include "qibl/fixed.h"

#define CLOTH_G 37   /* cloth grid */
#define CLOTH_STEP 4 /* coarse grid step */
#define CLOTH_CG (CLOTH_G / CLOTH_STEP + 1)
#define CLOTH_LOCAL_MAX (CLOTH_CG * CLOTH_CG + CLOTH_G * CLOTH_G) /* local vertices of a receiver, at most */

typedef struct qtool_bench_cloth {
    int nv, ntri, nframes;
    uint32_t (*tri)[3];
    double *frames; /* nframes * nv * 3 */
    /* hierarchy */
    int ncv, nct;
    int *cvert;            /* coarse vertex -> full vertex */
    uint32_t (*ctri)[3];   /* coarse triangles, indices into the coarse vertices */
    int near;              /* the window (grid steps) the rings were made for */
    int *nring, *nrv;      /* per vertex: blocker triangles and near-field vertices */
    size_t *ring_off, *rv_off;
    uint32_t (*ringf)[3];  /* local indices: < ncv coarse, ncv + k the k-th near-field vertex */
    int *rvf;
} qtool_bench_cloth;

/* Simulates nframes frames into a zeroed *s. 0, or -1 out of memory (free with _free either way). */
int qtool_bench_cloth_make(qtool_bench_cloth *s, int nframes);

/* Per vertex blockers for the window W (grid steps; CLOTH_G: the full mesh). 0, or -1 out of memory. */
int qtool_bench_cloth_rings(qtool_bench_cloth *s, int W);

/* The coarse cells [c0, c1] x [r0, r1] whose full-resolution triangles replace them for vertex v. */
void qtool_bench_cloth_window(int v, int W, int *c0, int *c1, int *r0, int *r1);

/* Frame f's integer inputs: positions (Q16.16) and area-weighted unit normals (Q2.30). 0, or -1
 * out of memory (nothing written). */
int qtool_bench_cloth_frame(const qtool_bench_cloth *s, int f, qibl_q16_t (*pos)[3], int32_t (*nrm)[3]);

/* Vertex v's blocker vertices into gp: the coarse vertices, then its near field; returns the count
 * (at most CLOTH_LOCAL_MAX). coarse 0: the coarse part is already there (it is the same for every v). */
uint32_t qtool_bench_cloth_gather(const qtool_bench_cloth *s, const qibl_q16_t (*pos)[3], int v, int coarse,
                                  qibl_q16_t (*gp)[3]);

void qtool_bench_cloth_free(qtool_bench_cloth *s);

#endif
