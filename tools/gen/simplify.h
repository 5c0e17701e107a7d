/*
 * gen/simplify.h - the coarse mesh of hemispherical rasterization's two-level hierarchy (Kautz et
 * al.): quadric-error simplification (Garland & Heckbert) by half-edge collapses, so every coarse
 * vertex IS a vertex of the full mesh and the coarse mesh deforms with it for free (its triangles
 * index the full mesh's vertices; animate the full mesh, the coarse one follows).
 */
#ifndef QTOOL_GEN_SIMPLIFY_H
#define QTOOL_GEN_SIMPLIFY_H

#include <stdint.h>

/* Simplifies the mesh (nv vertices pos[3 * nv], nt triangles tri) down to at most target
 * triangles, or as far as collapses stay valid (no fold-over: a collapse that turns a face's normal
 * by more than about 78 degrees or that would join two sheets is refused). Each collapse moves a
 * vertex onto a neighbour (the cheaper way by the summed plane quadrics, area weighted; boundary
 * edges add heavily weighted perpendicular planes, so borders stay while
 * cheaper collapses remain). *out gets malloc'd triangles indexing the
 * ORIGINAL vertices, *nout their count. 0, or -1 (no memory). */
int qtool_simplify(const double *pos, uint32_t nv, const uint32_t (*tri)[3], uint32_t nt, uint32_t target,
                   uint32_t (**out)[3], uint32_t *nout);

#endif
