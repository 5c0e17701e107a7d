/*
 * io/obj.h - Wavefront OBJ reader (geometry only): v (x y z [w]), vn, f with any of the forms
 * v, v/vt, v//vn, v/vt/vn, 1-based or negative (relative) indices; polygons fan-triangulated from
 * their first vertex; vt, g, o, s, usemtl, mtllib, l, p and unknown statements are ignored.
 * Corners without a normal get the area-weighted average of the face normals around their position.
 * Hosted, double precision.
 */
#ifndef QIBL_IO_OBJ_H
#define QIBL_IO_OBJ_H

#include <stddef.h>
#include <stdint.h>

typedef struct qibl_obj_mesh {
    size_t ntri;
    double *pos; /* ntri * 9: the three corners of each triangle, x y z */
    double *nrm; /* ntri * 9: unit normal at each corner (zero only for a degenerate triangle in isolation) */
    size_t nvert, nnormals_given; /* v and vn statements read */
} qibl_obj_mesh;

/* Reads path. 0, or -1 with a one-line reason naming the file and line in err (nothing allocated). */
int qibl_obj_read(const char *path, qibl_obj_mesh *out, char *err, size_t errlen);
/* The same from text in memory; name is used in error messages (may be NULL). */
int qibl_obj_parse(const char *name, const char *text, size_t len, qibl_obj_mesh *out, char *err, size_t errlen);
void qibl_obj_free(qibl_obj_mesh *m);

#endif
