/*
 * bake/scene.c - loading the scene of a render or bake (bake/scene.h).
 */
#include "bake/scene.h"

#include <stdio.h>
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

int qtool_scene_load(const qtool_scene_opts *o, qtool_rt_scene *s, char *err, size_t errlen)
{
    if (!qtool_scene_is_mesh(o))
        return qtool_rt_scene_builtin(s) != 0 ? qtool_errf(err, errlen, "out of memory building the scene") : 0;
    qtool_obj_mesh m;
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
    if (qtool_mesh_read_max(o->scene, QTOOL_SCENE_MAX_TRIANGLES, &m, NULL, NULL, merr, sizeof merr) != 0) {
        const char *ext = strrchr(o->scene, '.');
        return qtool_errf(err, errlen, "%s%s", merr,
                          !opened || known || (ext && strcmp(ext, ".obj") == 0)
                              ? ""
                              : " (read as OBJ: meshes are Wavefront OBJ or PLY, or glTF 2.0 .gltf/.glb)");
    }
    int rc = qtool_rt_scene_from_obj(s, &m, o->zup, o->raw);
    qtool_obj_free(&m);
    return rc != 0 ? qtool_errf(err, errlen, "%s: out of memory building the scene", o->scene) : 0;
}
