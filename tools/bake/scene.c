/*
 * bake/scene.c - loading the scene of a render or bake (bake/scene.h).
 */
#include "bake/scene.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/gltf.h"
#include "io/mesh.h"
#include "io/obj.h"
#include "io/ply.h"
#include "qtool.h"

int qtool_scene_is_mesh(const qtool_scene_opts *o)
{
    return o->scene && strcmp(o->scene, "builtin") != 0;
}

/* The glTF camera number o->gltf_cam of cams, placed in the scene as the mesh m is. 0 or -1. */
static int gltf_camera(const qtool_scene_opts *o, const qtool_obj_mesh *m, const qtool_gltf_camera *cams, size_t ncam,
                       qtool_rt_camera *c, char *err, size_t errlen)
{
    if ((size_t)o->gltf_cam >= ncam)
        return qtool_errf(err, errlen, "%s: camera gltf:%d: the file has %zu camera%s", o->scene, o->gltf_cam, ncam,
                          ncam == 1 ? "" : "s");
    const qtool_gltf_camera *g = &cams[o->gltf_cam];
    if (!g->perspective)
        return qtool_errf(err, errlen, "%s: camera gltf:%d is orthographic (a fixed-camera bake is perspective)",
                          o->scene, o->gltf_cam);
    double eye[3], fwd[3], up[3], target[3];
    qtool_rt_prop_place(m, o->zup, o->raw, g->eye, 0, eye);
    qtool_rt_prop_place(m, o->zup, o->raw, g->fwd, 1, fwd);
    qtool_rt_prop_place(m, o->zup, o->raw, g->up, 1, up);
    for (int j = 0; j < 3; ++j)
        target[j] = eye[j] + fwd[j];
    return qtool_rt_camera_init(c, eye, target, up, o->fov > 0 ? o->fov : g->yfov * 180 / QTOOL_PI, err, errlen);
}

static int mesh_load(const qtool_scene_opts *o, qtool_rt_scene *s, char *err, size_t errlen);

int qtool_scene_load(const qtool_scene_opts *o, qtool_rt_scene *s, char *err, size_t errlen)
{
    qtool_rt_camera c;
    memset(&c, 0, sizeof c);
    if (o->camera == QTOOL_SCENE_CAMERA && qtool_rt_camera_init(&c, o->eye, o->target, o->up, o->fov, err, errlen) != 0)
        return -1;
    if (o->camera == QTOOL_SCENE_GLTF_CAMERA && !qtool_scene_is_mesh(o))
        return qtool_errf(err, errlen, "camera gltf: the built-in courtyard has no camera (give a .gltf/.glb scene)");
    if (qtool_scene_is_mesh(o))
        return mesh_load(o, s, err, errlen);
    if (qtool_rt_scene_builtin(s) != 0)
        return qtool_errf(err, errlen, "out of memory building the scene");
    s->has_cam = o->camera == QTOOL_SCENE_CAMERA, s->cam = c;
    return 0;
}

static int mesh_load(const qtool_scene_opts *o, qtool_rt_scene *s, char *err, size_t errlen)
{
    qtool_obj_mesh m;
    qtool_gltf_camera *cams = NULL;
    size_t ncam = 0;
    qtool_rt_camera c;
    memset(&c, 0, sizeof c);
    char merr[1200];
    /* glTF by its name or GLB magic, PLY by its first line (whatever the extension), else OBJ */
    uint8_t head[8] = {0};
    FILE *f = fopen(o->scene, "rb");
    size_t nh = f ? fread(head, 1, sizeof head, f) : 0;
    int opened = f != NULL;
    if (f)
        fclose(f);
    int known = qtool_ply_sniff(head, nh) || qtool_gltf_sniff_glb(head, nh) || qtool_mesh_is_gltf_name(o->scene);
    /* the scene cap before the mesh is allocated (each reader counts its triangles first) */
    int want_cams = o->camera == QTOOL_SCENE_GLTF_CAMERA;
    if (qtool_mesh_read_max(o->scene, QTOOL_SCENE_MAX_TRIANGLES, &m, want_cams ? &cams : NULL, want_cams ? &ncam : NULL,
                            merr, sizeof merr) != 0) {
        const char *ext = strrchr(o->scene, '.');
        return qtool_errf(err, errlen, "%s%s", merr,
                          !opened || known || (ext && strcmp(ext, ".obj") == 0)
                              ? ""
                              : " (read as OBJ: meshes are Wavefront OBJ or PLY, or glTF 2.0 .gltf/.glb)");
    }
    if (o->camera == QTOOL_SCENE_CAMERA)
        qtool_rt_camera_init(&c, o->eye, o->target, o->up, o->fov, NULL, 0); /* checked by the caller */
    else if (want_cams && gltf_camera(o, &m, cams, ncam, &c, err, errlen) != 0) {
        free(cams);
        qtool_obj_free(&m);
        return -1;
    }
    free(cams);
    int rc = qtool_rt_scene_from_obj(s, &m, o->zup, o->raw);
    qtool_obj_free(&m);
    if (rc != 0)
        return qtool_errf(err, errlen, "%s: out of memory building the scene", o->scene);
    s->has_cam = o->camera != QTOOL_SCENE_PANORAMA, s->cam = c;
    return 0;
}
