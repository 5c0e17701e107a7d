/*
 * bake/scene.h - the scene and panorama a render or bake works on (what `--scene`, `--zup`, `--raw`,
 * `--size`, `--equirect`, `--threads` choose), its defaults and bounds, and loading it: the built-in
 * courtyard, or a glTF, PLY or OBJ mesh with its materials (io/mesh.h).
 */
#ifndef QTOOL_BAKE_SCENE_H
#define QTOOL_BAKE_SCENE_H

#include <stddef.h>
#include <stdint.h>

#include "render/rt.h"

/* triangles of a mesh scene, checked before the mesh is allocated: the mesh (144 bytes a triangle)
 * and its BVH stay near 0.3 GiB (docs/robustness.md) */
#define QTOOL_SCENE_MAX_TRIANGLES ((size_t)1 << 20)

typedef struct qtool_scene_opts {
    const char *scene; /* NULL or "builtin": the built-in courtyard; else a .gltf/.glb, PLY or OBJ file */
    int zup, raw;      /* the mesh's up axis is +z; no centring and scaling (qtool_rt_scene_from_obj) */
    int kind;          /* qtool_pano_kind */
    int threads;       /* 1..256 (a caller with no preference passes its CPUs) */
    uint32_t w, h;     /* panorama (or camera frame) size, w h <= QIBL_ASSET_MAX_PIXELS */
    /* a fixed perspective camera instead of the panorama from the origin (render/rt.h) */
    int camera;        /* QTOOL_SCENE_PANORAMA, QTOOL_SCENE_CAMERA (eye, target, up, fov) or QTOOL_SCENE_GLTF_CAMERA */
    double eye[3], target[3], up[3];
    double fov;        /* degrees, vertical; the glTF camera's own yfov when 0 */
    int gltf_cam;      /* QTOOL_SCENE_GLTF_CAMERA: the file's camera number (0: the first) */
} qtool_scene_opts;

enum { QTOOL_SCENE_PANORAMA = 0, QTOOL_SCENE_CAMERA, QTOOL_SCENE_GLTF_CAMERA };

/* The one home of the defaults: a 1024 x 256 cylindrical panorama of the built-in courtyard, one
 * thread (the CLI sets its job's CPUs). */
/* the panorama's default size (the CLI's option tables show it from here) */
#define QTOOL_SCENE_W 1024
#define QTOOL_SCENE_H 256
#define QTOOL_SCENE_OPTS_DEFAULT                                                                        \
    {.scene = NULL, .w = QTOOL_SCENE_W, .h = QTOOL_SCENE_H, .kind = QTOOL_PANO_CYLINDRICAL, .threads = 1, \
     .camera = QTOOL_SCENE_PANORAMA, .fov = QTOOL_RT_CAMERA_FOV_DEFAULT}

/* Whether o names a mesh (not the built-in courtyard). */
int qtool_scene_is_mesh(const qtool_scene_opts *o);

/* Loads the scene o names into s (glTF by its name or GLB magic, PLY by its first line whatever the
 * extension, else OBJ; at most QTOOL_SCENE_MAX_TRIANGLES), with its camera when o asks for one (a
 * glTF camera placed as the mesh is: qtool_rt_prop_place). 0, or -1 with a one-line reason in err
 * (a bad camera named: qtool_rt_camera_init; a glTF camera that is missing or orthographic) and s
 * untouched. */
int qtool_scene_load(const qtool_scene_opts *o, qtool_rt_scene *s, char *err, size_t errlen);

#endif
