/*
 * io/mesh.c - the mesh readers behind one call (io/mesh.h).
 */
#include "io/mesh.h"
#include "io/ply.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

int qtool_mesh_is_gltf_name(const char *path)
{
    const char *e = strrchr(path, '.');
    return e && (strcasecmp(e, ".gltf") == 0 || strcasecmp(e, ".glb") == 0);
}

int qtool_mesh_read_max(const char *path, size_t max_triangles, qtool_obj_mesh *out, qtool_gltf_camera **cams,
                        size_t *ncam, char *err, size_t errlen)
{
    uint8_t head[8] = {0};
    FILE *f = fopen(path, "rb");
    size_t nh = f ? fread(head, 1, sizeof head, f) : 0;
    if (f)
        fclose(f);
    if (cams)
        *cams = NULL;
    if (ncam)
        *ncam = 0;
    if (qtool_mesh_is_gltf_name(path) || qtool_gltf_sniff_glb(head, nh)) {
        qtool_gltf_scene s;
        if (qtool_gltf_read(path, max_triangles, &s, err, errlen) != 0)
            return -1;
        *out = s.mesh;
        if (cams && ncam)
            *cams = s.cams, *ncam = s.ncam;
        else
            free(s.cams);
        return 0;
    }
    if (qtool_ply_sniff(head, nh))
        return qtool_ply_read_max(path, max_triangles, out, err, errlen);
    return qtool_obj_read_max(path, max_triangles, out, err, errlen);
}
