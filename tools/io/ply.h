/*
 * io/ply.h - Stanford PLY mesh reader (geometry only), into the same triangle soup as io/obj.h so
 * render, bake and demo take either. Hosted, double precision.
 *
 * Reads "ply", "format ascii 1.0 | binary_little_endian 1.0 | binary_big_endian 1.0", comment and
 * obj_info lines, elements and their properties, "end_header"; then the body. Used: the "vertex"
 * element's x, y, z (any scalar type: char uchar short ushort int uint float double, or the int8 ...
 * float64 names) and the "face" element's list "vertex_indices" (or "vertex_index"; integer count
 * and index types). Every other property and element is skipped (lists by their own counts).
 * Polygons are fan-triangulated from their first vertex; corner normals are the area-weighted
 * average of the face normals around each vertex (PLY normals, if any, are not used).
 *
 * Hostile input: the whole header is checked before the body is read: it must end within
 * QTOOL_PLY_MAX_HEADER bytes, name a known format, at most QTOOL_PLY_MAX_ELEMENTS elements of at most
 * QTOOL_PLY_MAX_PROPS properties, a vertex element with x, y and z and a face element with an integer
 * index list. Element counts are capped (QTOOL_PLY_MAX_VERTICES, QTOOL_PLY_MAX_FACES) and tied to the
 * file's size: every instance needs at least its bytes in the body (binary: the sizes of its scalars
 * and list counts; ascii: two characters per value), so a count a file cannot hold is refused before
 * any allocation. In the body: a face of fewer than 3 or more than QTOOL_PLY_MAX_POLY vertices, an
 * index outside the vertex element, a non-finite coordinate (named with its value), a malformed ascii
 * number and a body shorter than the header promises are each refused with a one-line reason naming
 * the element and instance. The triangles (fan triangulation) are counted by a first pass over the
 * body and checked against QTOOL_PLY_MAX_TRIANGLES (or a caller's lower cap) before the mesh is
 * allocated: memory is the file plus the mesh, never a mesh above the cap.
 */
#ifndef QTOOL_IO_PLY_H
#define QTOOL_IO_PLY_H

#include <stddef.h>
#include <stdint.h>

#include "io/obj.h" /* qtool_obj_mesh, qtool_obj_free */

#define QTOOL_PLY_MAX_HEADER 65536      /* bytes up to and including "end_header\n" */
#define QTOOL_PLY_MAX_ELEMENTS 16
#define QTOOL_PLY_MAX_PROPS 64          /* per element */
#define QTOOL_PLY_MAX_VERTICES 16777216 /* 2^24 */
#define QTOOL_PLY_MAX_FACES 16777216
#define QTOOL_PLY_MAX_POLY 256          /* vertices of one face */
#define QTOOL_PLY_MAX_TRIANGLES 4194304 /* 2^22 after triangulation: 600 MiB of corners and normals */

/* Parses a PLY file image of len bytes; name (may be NULL) is used in messages. 0, or -1 with a
 * one-line reason in err (nothing allocated). The mesh is freed with qtool_obj_free. */
int qtool_ply_parse(const char *name, const uint8_t *buf, size_t len, qtool_obj_mesh *out, char *err, size_t errlen);

/* Reads path. 0, or -1 with a one-line reason naming the file (nothing allocated). */
int qtool_ply_read(const char *path, qtool_obj_mesh *out, char *err, size_t errlen);

/* The same with a caller's triangle cap (at most QTOOL_PLY_MAX_TRIANGLES, which the two above use): a
 * first pass over the body checks every value and counts the triangles the faces fan into; a count
 * above the cap is refused with the exact count ("N triangles after fan triangulation of M faces
 * (at most CAP)") before anything is allocated for the mesh. */
int qtool_ply_parse_max(const char *name, const uint8_t *buf, size_t len, size_t max_triangles, qtool_obj_mesh *out,
                        char *err, size_t errlen);
int qtool_ply_read_max(const char *path, size_t max_triangles, qtool_obj_mesh *out, char *err, size_t errlen);

/* 1 if the len bytes start like a PLY file ("ply" and an end of line), else 0. */
int qtool_ply_sniff(const uint8_t *buf, size_t len);

#endif
