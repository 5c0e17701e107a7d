/*
 * io/gltf.h - glTF 2.0 reader (.gltf JSON with external or embedded data: buffers, and .glb),
 * into the same triangle soup as io/obj.h, plus the scene's cameras. Hosted, double precision.
 *
 * Read: the scene (the "scene" property, else scenes[0], else every node that is no node's child),
 * its node tree with each node's matrix or translation/rotation/scale composed from the root down;
 * every mesh primitive of mode TRIANGLES, TRIANGLE_STRIP or TRIANGLE_FAN (strips and fans become
 * triangles with the spec's winding; POINTS and LINES are skipped); POSITION, NORMAL (else flat
 * normals, as the spec asks) and TEXCOORD_n of the material's base-colour texture; indices of
 * component type UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT, or none; accessors of any component
 * type, normalized or not, with their bufferView's byteOffset and byteStride; the material's
 * pbrMetallicRoughness baseColorFactor (rgb, linear) and baseColorTexture (a PNG image, from a
 * uri or a bufferView) into qtool_obj_mesh's albedo / uv / tex; COLOR_0 (VEC3 or VEC4, 0..1)
 * multiplies the albedo by the mean of each triangle's three corner colours (per-triangle albedo). A node whose matrix has a negative
 * determinant has its triangles' winding reversed (the spec's rule). Cameras on the scene's nodes
 * (perspective and orthographic) come back with their world eye point and axes.
 * Sparse accessors (indices of UNSIGNED_BYTE/SHORT/INT, strictly increasing, below the count) and
 * accessors without a bufferView (zeros, then the sparse values) are written out once per accessor;
 * those bytes count against the buffers' budget and may not exceed 64 times the input read.
 * Skins: a node with a mesh and a skin is placed by its joints (each vertex by the weighted sum of
 * its JOINTS_0 joints' world x inverseBindMatrices, WEIGHTS_0 normalised; the node's own transform
 * ignored, as the spec says). Animation 0, sampled at a time (the _at calls; keys clamped; STEP,
 * LINEAR with slerp for rotations, CUBICSPLINE), replaces the translation, rotation and scale of the
 * nodes it targets before the tree is composed: `qibl transfer FILE.gltf@T` frames. Its key range
 * is returned. Not read (ignored): morph targets and "weights" channels, JOINTS_1 / WEIGHTS_1,
 * other animations, every extension, samplers (textures repeat), texCoord transforms.
 *
 * Files: a buffer or image uri is either a data: URI (base64) or a relative path, resolved against
 * the directory of the .gltf, after percent escapes are decoded. Absolute paths, a ".." component,
 * a backslash, a scheme ("http:"), %00 and a bad escape are refused by name: a downloaded scene must not make the tool read
 * files outside its own folder (a texture could carry ~/.ssh into a baked asset). Paths are read
 * through io/file.h (regular files only, size checked before reading).
 *
 * Limits (each a named one-line error naming the file and the offending object, e.g.
 * "accessors[3]: byteOffset 64 + 24 elements x stride 12 = 352 bytes past bufferViews[1]'s 288";
 * nothing is allocated for the mesh before every check has passed):
 *   - the .gltf / .glb at most QTOOL_GLTF_MAX_FILE_BYTES; the JSON within io/json.h's limits; every
 *     object outside "extras" and "extensions" at most QTOOL_GLTF_MAX_MEMBERS keys (each lookup
 *     then costs O(1), so work stays linear however often an accessor or node is consulted);
 *   - at most QTOOL_GLTF_MAX_NODES nodes, a node tree at most QTOOL_GLTF_MAX_DEPTH deep, each node
 *     reached at most once (a cycle or a shared child is refused);
 *   - buffers: at most QTOOL_GLTF_MAX_BUFFERS, each at most QTOOL_GLTF_MAX_BUFFER_BYTES, the data
 *     at least byteLength bytes; every bufferView, accessor (count x stride), index and texture
 *     reference checked against what it points into before use;
 *   - images: at most QTOOL_GLTF_MAX_IMAGES decoded, within io/png.h's limits;
 *   - triangles: at most the caller's cap (<= QTOOL_GLTF_MAX_TRIANGLES), counted before the mesh
 *     is allocated; and instancing (one mesh on many nodes) at most QTOOL_GLTF_MAX_INSTANCE_RATIO
 *     times the triangles the file's primitives hold, so a small file cannot ask for a huge mesh.
 * Memory: the files, the JSON tokens (32 bytes per input byte at most), the decoded images and the
 * output mesh (ntri x (144 + 48 + 24 + 4) bytes at most). Time linear in the input plus the output.
 */
#ifndef QTOOL_IO_GLTF_H
#define QTOOL_IO_GLTF_H

#include <stddef.h>
#include <stdint.h>

#include "io/obj.h"

#define QTOOL_GLTF_MAX_FILE_BYTES ((size_t)1 << 28)   /* a .gltf or .glb: 256 MiB */
#define QTOOL_GLTF_MAX_BUFFER_BYTES ((size_t)1 << 28) /* one buffer: 256 MiB */
#define QTOOL_GLTF_MAX_BUFFERS 64
#define QTOOL_GLTF_MAX_IMAGES 64
#define QTOOL_GLTF_MAX_NODES 65536
#define QTOOL_GLTF_MAX_DEPTH 128
#define QTOOL_GLTF_MAX_CAMERAS 256
#define QTOOL_GLTF_MAX_TRIANGLES ((size_t)1 << 22)
#define QTOOL_GLTF_MAX_INSTANCE_RATIO 64
#define QTOOL_GLTF_MAX_JOINTS 1024 /* joints of one skin */
#define QTOOL_GLTF_MAX_MEMBERS 256 /* keys of any object the reader looks into (extras excepted) */

typedef struct qtool_gltf_camera {
    int perspective;          /* 1 perspective, 0 orthographic */
    double yfov;              /* radians (perspective) */
    double aspect;            /* width / height, 0 when the file leaves it to the viewport */
    double znear, zfar;       /* zfar 0: infinite (perspective) */
    double xmag, ymag;        /* orthographic half sizes */
    double eye[3];            /* the camera node's origin in world (file) space, Y up */
    double fwd[3], up[3];     /* unit -Z and +Y of the camera node in world space */
    uint32_t node;            /* the node carrying it */
} qtool_gltf_camera;

typedef struct qtool_gltf_scene {
    qtool_obj_mesh mesh;      /* world space, Y up as glTF; nvert = vertices read, nnormals_given the NORMAL ones */
    qtool_gltf_camera *cams;  /* in node order of the traversal; NULL when none */
    size_t ncam;
    int has_anim;                  /* the file has an animation (animation 0 is the one sampled) */
    double anim_start, anim_end;   /* its keys' time range, seconds */
} qtool_gltf_scene;

/* Reads a .gltf or .glb (told apart by the GLB magic, whatever the extension). 0, or -1 with a
 * one-line reason naming the file in err and nothing allocated. */
int qtool_gltf_read(const char *path, size_t max_triangles, qtool_gltf_scene *out, char *err, size_t errlen);
/* The same from bytes in memory; name is used in messages (may be NULL); dir the folder external
 * uris are resolved against (NULL: external files are refused, only GLB and data: buffers read). */
int qtool_gltf_parse(const char *name, const char *dir, const uint8_t *buf, size_t len, size_t max_triangles,
                     qtool_gltf_scene *out, char *err, size_t errlen);
/* The same with animation 0 sampled at time seconds (clamped to its keys); time < 0: the nodes'
 * own transforms (the calls above). */
int qtool_gltf_read_at(const char *path, size_t max_triangles, double time, qtool_gltf_scene *out, char *err,
                       size_t errlen);
int qtool_gltf_parse_at(const char *name, const char *dir, const uint8_t *buf, size_t len, size_t max_triangles,
                        double time, qtool_gltf_scene *out, char *err, size_t errlen);
void qtool_gltf_free(qtool_gltf_scene *s);

/* 1 if the bytes start like a GLB ("glTF" magic). */
int qtool_gltf_sniff_glb(const uint8_t *buf, size_t len);

#endif
