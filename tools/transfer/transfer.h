/*
 * transfer/transfer.h - the mesh pipeline of `qibl transfer` (hemispherical rasterization of a
 * mesh, Kautz et al.): welding a triangle soup into indexed vertices, the triangles around each
 * vertex, the two-level hierarchy (the full mesh within a few rings of each vertex + a coarse mesh
 * from gen/simplify.h further away) and the static PVS over an animation's frames. Hosted, double
 * precision where positions are concerned; the lists it builds feed qibl_hemi_raster.
 *
 * Contract: caller-owned inputs are checked before they are trusted (indices in range, counts
 * within the caps below, adjacency consistent with the triangles); every function returns a
 * qtool_transfer_status and a failing call leaves its outputs empty (zeroed), with nothing
 * allocated. Memory: the hierarchy and the PVS are sized exactly by a counting pass before they
 * are allocated and refused (QTOOL_TRANSFER_E_TOO_BIG) past QTOOL_TRANSFER_MAX_LIST entries, so
 * their memory is bounded whatever the mesh's valences.
 */
#ifndef QTOOL_TRANSFER_TRANSFER_H
#define QTOOL_TRANSFER_TRANSFER_H

#include <stddef.h>
#include <stdint.h>

#include "qibl/fixed.h"
#include "qtool.h"

#define QTOOL_TRANSFER_MAX_TRIANGLES 1048576u /* 2^20 triangles per mesh */
#define QTOOL_TRANSFER_MAX_VERTICES 3145728u  /* 3 * 2^20: every corner its own vertex */
#define QTOOL_TRANSFER_MAX_RING 16
/* entries of a hierarchy's or a PVS's vertex list and of its blocker list, each: 2^26 blockers are
 * 768 MiB, 2^26 vertex entries 256 MiB */
#define QTOOL_TRANSFER_MAX_LIST ((size_t)1 << 26)

/* QTOOL_TRANSFER_STATUS_LIST(X): every status in value order as X(name, message), the one list the
 * enum and qtool_transfer_status_str are made from. */
#define QTOOL_TRANSFER_STATUS_LIST(X) \
    X(QTOOL_TRANSFER_OK, "ok") \
    X(QTOOL_TRANSFER_E_NOMEM, "out of memory") \
    X(QTOOL_TRANSFER_E_EMPTY, "the mesh has no triangles") \
    X(QTOOL_TRANSFER_E_TRIANGLES, "more than 1048576 triangles (QTOOL_TRANSFER_MAX_TRIANGLES)") \
    X(QTOOL_TRANSFER_E_VERTICES, "more than 3145728 vertices (QTOOL_TRANSFER_MAX_VERTICES)") \
    X(QTOOL_TRANSFER_E_CORNER, "a corner position is not finite") \
    /* a triangle (mesh or coarse) indexes past the vertices */ \
    X(QTOOL_TRANSFER_E_INDEX, "a triangle indexes past the vertices") \
    X(QTOOL_TRANSFER_E_ADJACENCY, "the triangles around a vertex do not match the triangles") \
    X(QTOOL_TRANSFER_E_RING, "ring outside 1..16") \
    X(QTOOL_TRANSFER_E_TOO_BIG, "the hierarchy or PVS lists would exceed 2^26 entries (QTOOL_TRANSFER_MAX_LIST)") \
    /* no frames, or positions missing */ \
    X(QTOOL_TRANSFER_E_FRAMES, "no frames of positions")

typedef enum qtool_transfer_status {
#define QTOOL_TRANSFER_STATUS_ENUM_(name, message) name,
    QTOOL_TRANSFER_STATUS_LIST(QTOOL_TRANSFER_STATUS_ENUM_)
#undef QTOOL_TRANSFER_STATUS_ENUM_
    QTOOL_TRANSFER_STATUS_COUNT /* not a status */
} qtool_transfer_status;

/* one line naming the status */
const char *qtool_transfer_status_str(qtool_transfer_status st);

/* An indexed mesh: nv vertices, nt triangles, nframes frames of positions (nframes * nv * 3). */
typedef struct qtool_transfer_mesh {
    uint32_t nv, nt, nframes;
    uint32_t (*tri)[3];
    double *pos;
} qtool_transfer_mesh;

/* Per vertex v: the vertices to transform vl[voff[v] .. voff[v + 1]) (global indices) and the
 * blockers blk[boff[v] .. boff[v + 1]) in local indices into that list, local index (count of the
 * list) being the nadir of the crease wedges. */
typedef struct qtool_transfer_hier {
    size_t *voff, *boff; /* nv + 1 each */
    uint32_t *vl;
    uint32_t (*blk)[3];
} qtool_transfer_hier;

/* Welds a triangle soup (ntri triangles, corner positions pos[9 * ntri]) by exact position (-0 and
 * +0 weld): tri[ntri] gets each triangle's vertices, first[3 * ntri] the first corner of each
 * vertex (its first *nv entries), vof[3 * ntri] the vertex of each corner. Fails with E_EMPTY,
 * E_TRIANGLES, E_CORNER or E_NOMEM, writing nothing. */
QTOOL_NODISCARD qtool_transfer_status qtool_transfer_weld(const double *pos, size_t ntri, uint32_t (*tri)[3], uint32_t *first,
                                          uint32_t *vof, uint32_t *nv);

/* Checks a mesh's counts and indices (E_EMPTY, E_TRIANGLES, E_VERTICES, E_INDEX). */
QTOOL_NODISCARD qtool_transfer_status qtool_transfer_check(const qtool_transfer_mesh *m);

/* The triangles around each vertex: (*adj)[(*off)[v] .. (*off)[v + 1]) (a triangle listing a vertex
 * twice counts once); malloc'd. Checks the mesh first. */
QTOOL_NODISCARD qtool_transfer_status qtool_transfer_adjacency(const qtool_transfer_mesh *m, uint32_t **off, uint32_t **adj);

/* The two-level hierarchy of every vertex: the full mesh's triangles touching vertices fewer than
 * `ring` edges away, the coarse triangles ctri[nct] (indexing the mesh's vertices) none of whose
 * vertices is within `ring` edges and, with crease, the wedges (nadir, b, c) of the faces (v, b, c)
 * around v. Sized by a counting pass: E_TOO_BIG past QTOOL_TRANSFER_MAX_LIST entries, before the
 * lists are allocated. Also E_RING, E_INDEX (mesh or coarse), E_ADJACENCY, E_NOMEM. */
QTOOL_NODISCARD qtool_transfer_status qtool_transfer_hier_build(const qtool_transfer_mesh *m, const uint32_t *adj_off,
                                                const uint32_t *adj, const uint32_t (*ctri)[3], uint32_t nct, int ring,
                                                int crease, qtool_transfer_hier *h);

/* Per vertex, the blockers that are ever above its horizon over the frames (pos and nrm: nframes *
 * nv integer positions Q16.16 and unit normals Q2.30), from the lists of src (a hierarchy) or, src
 * NULL, every triangle plus (crease) the wedges around the vertex. The same masks with fewer
 * blockers. Without src the worst case, every triangle kept for every vertex, must fit
 * QTOOL_TRANSFER_MAX_LIST (else E_TOO_BIG, before any work). threads: as qtool_rt_parallel. */
QTOOL_NODISCARD qtool_transfer_status qtool_transfer_pvs_build(const qtool_transfer_mesh *m, const qtool_transfer_hier *src,
                                               const qibl_q16_t (*pos)[3], const int32_t (*nrm)[3],
                                               const uint32_t *adj_off, const uint32_t *adj, int crease, int threads,
                                               qtool_transfer_hier *out);

void qtool_transfer_hier_free(qtool_transfer_hier *h);

/* Edges used by one triangle only (returned) and all distinct edges (*edges); -1 without memory. */
long qtool_transfer_boundary_edges(const qtool_transfer_mesh *m, long *edges);

/* The signed volume enclosed by the triangles at positions P (3 * nv). */
double qtool_transfer_signed_volume(const qtool_transfer_mesh *m, const double *P);

#endif
