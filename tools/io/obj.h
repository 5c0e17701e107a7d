/*
 * io/obj.h - Wavefront OBJ reader: v (x y z [w]), vn, vt, f with any of the forms
 * v, v/vt, v//vn, v/vt/vn, 1-based or negative (relative) indices; polygons fan-triangulated from
 * their first vertex; g, o, s, l, p and unknown statements are ignored.
 * Materials (qtool_obj_read_materials, and qtool_obj_parse_dir with a folder; ignored by the other
 * readers, which take geometry only, as before): "mtllib a.mtl [b.mtl ...]" reads material libraries beside the .obj
 * (io/relpath.h: no absolute path, no ".."); in them "newmtl NAME", "Kd r g b" (0..1, default
 * QTOOL_OBJ_DEFAULT_KD) and "map_Kd [options] FILE.png" (the last word is the file, a PNG read by
 * io/pngread.c); every other statement is ignored. "usemtl NAME" gives the following faces that
 * material (a name no library read so far defines is refused). Triangles then carry the albedo Kd
 * (QTOOL_OBJ_DEFAULT_KD before any usemtl) and, for a map_Kd material with vt on all three
 * corners, the texture and the corners' (u, 1 - v).
 * Corners without a normal get the area-weighted average of the face normals around their position.
 * Hosted, double precision.
 *
 * Limits (each a named one-line error giving the line, checked while parsing, before the output is
 * allocated):
 *   - a file: regular, at most QTOOL_OBJ_MAX_FILE_BYTES, read only after stat and only if its first
 *     64 bytes hold no NUL (OBJ is text) (io/file.h);
 *   - a line at most 4095 bytes, a face at most QTOOL_OBJ_MAX_FACE_CORNERS corners;
 *   - at most QTOOL_OBJ_MAX_VERTICES v and as many vn statements, at most QTOOL_OBJ_MAX_TRIANGLES
 *     triangles, and at most one triangle per QIBL_OBJ_MIN_BYTES_PER_TRIANGLE bytes of input (a
 *     plain "f 1 2 3" line is 8 bytes; real meshes spend 35-55): fan faces cannot turn a small
 *     file into a huge mesh;
 *   - every number finite, and every coordinate (x / w for a vertex with w) and normal component
 *     of magnitude at most QIBL_OBJ_MAX_COORD, so that edge cross products stay finite: the value
 *     and line are named otherwise;
 *   - indices resolved without overflow (any 64-bit value is safely refused when out of range).
 * Memory: the file, 24 bytes per v or vn, 24 per triangle while parsing, then the output (144 bytes
 * per triangle): at most ~40x the input and never above the caps. Time linear in the input.
 */
#ifndef QTOOL_IO_OBJ_H
#define QTOOL_IO_OBJ_H

#include <stddef.h>
#include <stdint.h>

#define QTOOL_OBJ_MAX_FILE_BYTES ((size_t)1 << 28)  /* 256 MiB */
#define QTOOL_OBJ_MAX_VERTICES ((size_t)1 << 24)    /* v statements; the same for vn */
#define QTOOL_OBJ_MAX_TRIANGLES ((size_t)1 << 22)   /* 4 Mi triangles: 604 MB of output */
#define QIBL_OBJ_MIN_BYTES_PER_TRIANGLE 4u
#define QTOOL_OBJ_MAX_FACE_CORNERS 256
#define QIBL_OBJ_MAX_COORD 1e15
#define QTOOL_OBJ_MAX_MTL_BYTES ((size_t)1 << 24)       /* one .mtl: 16 MiB */
#define QTOOL_OBJ_MAX_MTLLIBS 16                        /* material libraries per .obj */
#define QTOOL_OBJ_MAX_MATERIALS 1024                    /* newmtl in all of them */
#define QTOOL_OBJ_MAX_NAME 255                          /* material and texture file names, bytes */
#define QTOOL_OBJ_MAX_TEXTURES 16                       /* distinct map_Kd files */
#define QTOOL_OBJ_MAX_TEXTURE_PIXELS ((size_t)1 << 26)  /* all textures together: 192 MiB of RGB */
#define QTOOL_OBJ_DEFAULT_KD 0.8

/* An 8-bit sRGB texture (a material's base colour / map_Kd), rows top to bottom. */
typedef struct qtool_mesh_texture {
    int w, h;
    uint8_t *rgb; /* 3 * w * h bytes */
} qtool_mesh_texture;

typedef struct qtool_obj_mesh {
    size_t ntri;
    double *pos; /* ntri * 9: the three corners of each triangle, x y z */
    double *nrm; /* ntri * 9: unit normal at each corner (zero only for a degenerate triangle in isolation) */
    size_t nvert, nnormals_given; /* v and vn statements read */
    /* Materials, all optional (NULL / 0 when the file has none: a plain grey mesh, as before).
     * albedo: ntri * 3 linear base colours (OBJ Kd, glTF baseColorFactor); NULL means the
     * renderer's default. tex: ntri texture indices (-1: none) into texs[0 .. ntex); uv: ntri * 6
     * texture coordinates per corner (u, v), glTF's convention: (0, 0) the image's top-left corner,
     * v downwards, repeating (an OBJ vt's v is stored as 1 - v). uv and tex are both set or both
     * NULL; a texel's sRGB colour (decoded to linear) multiplies the triangle's albedo. */
    double *albedo;
    double *uv;
    int32_t *tex;
    qtool_mesh_texture *texs;
    size_t ntex;
} qtool_obj_mesh;

/* Reads path. 0, or -1 with a one-line reason naming the file and line in err (nothing allocated). */
int qtool_obj_read(const char *path, qtool_obj_mesh *out, char *err, size_t errlen);
/* The same from text in memory; name is used in error messages (may be NULL). */
int qtool_obj_parse(const char *name, const char *text, size_t len, qtool_obj_mesh *out, char *err, size_t errlen);
/* The same with a caller's triangle cap (at most QTOOL_OBJ_MAX_TRIANGLES): a face that takes the
 * count past it is refused on its line ("more than N triangles (this command's limit)"), so the
 * triangle lists never grow past the cap. */
int qtool_obj_read_max(const char *path, size_t max_triangles, qtool_obj_mesh *out, char *err, size_t errlen);
int qtool_obj_parse_max(const char *name, const char *text, size_t len, size_t max_triangles, qtool_obj_mesh *out,
                        char *err, size_t errlen);
/* The same with materials: reads path and the material libraries and textures its mtllib lines
 * name beside it (the scene loader's call; transfer and the others read geometry only). */
int qtool_obj_read_materials(const char *path, size_t max_triangles, qtool_obj_mesh *out, char *err, size_t errlen);
/* The same from text in memory: dir is the folder mtllib files are resolved against (NULL: mtllib
 * and usemtl ignored, as the parsers above). */
int qtool_obj_parse_dir(const char *name, const char *dir, const char *text, size_t len, size_t max_triangles,
                        qtool_obj_mesh *out, char *err, size_t errlen);
void qtool_obj_free(qtool_obj_mesh *m);

#endif
