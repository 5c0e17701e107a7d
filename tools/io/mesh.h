/*
 * io/mesh.h - one entry for every mesh format the tools read: glTF 2.0 (.gltf, or a .glb by its
 * magic), PLY (by its first line) and Wavefront OBJ (everything else), into io/obj.h's triangle soup
 * with its optional materials. Hosted.
 */
#ifndef QTOOL_IO_MESH_H
#define QTOOL_IO_MESH_H

#include <stddef.h>

#include "io/gltf.h"
#include "io/obj.h"

/* Reads path as glTF when its name ends in .gltf or .glb (any case) or it starts with the GLB magic
 * ("FILE.gltf@T" or "FILE.glb@T": its animation 0 at T seconds, io/gltf.h),
 * as PLY when it starts like one, else as OBJ with its materials (qtool_obj_read_materials); at most max_triangles (each reader's own cap is the
 * ceiling). cams / ncam (may be NULL) receive a glTF file's cameras (NULL / 0 for the others; free
 * with free()). 0, or -1 with the reader's one-line reason naming the file (nothing allocated). */
int qtool_mesh_read_max(const char *path, size_t max_triangles, qtool_obj_mesh *out, qtool_gltf_camera **cams,
                        size_t *ncam, char *err, size_t errlen);

/* 1 if path names a glTF file by its extension (.gltf or .glb, any case, with or without "@T"). */
int qtool_mesh_is_gltf_name(const char *path);

#endif
