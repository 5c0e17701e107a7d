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

static int gltf_ext(const char *path, size_t n)
{
    return (n >= 5 && strncasecmp(path + n - 5, ".gltf", 5) == 0) || (n >= 4 && strncasecmp(path + n - 4, ".glb", 4) == 0);
}

/* "FILE.gltf@T" (T seconds, a plain non-negative number): the file part into file, T into *t;
 * anything else: the whole path and -1 */
static int split_time(const char *path, char *file, size_t cap, double *t)
{
    const char *at = strrchr(path, '@');
    *t = -1.0;
    if (at && at[1] && gltf_ext(path, (size_t)(at - path))) {
        char *end;
        double v = strtod(at + 1, &end);
        if (!*end && v >= 0 && v <= 1e9 && (at[1] >= '0' && at[1] <= '9')) {
            if ((size_t)(at - path) >= cap)
                return -1;
            memcpy(file, path, (size_t)(at - path));
            file[at - path] = '\0';
            *t = v;
            return 0;
        }
    }
    if (strlen(path) >= cap)
        return -1;
    strcpy(file, path);
    return 0;
}

int qtool_mesh_is_gltf_name(const char *path)
{
    char file[4096];
    double t;
    return split_time(path, file, sizeof file, &t) == 0 && gltf_ext(file, strlen(file));
}

int qtool_mesh_read_max(const char *path, size_t max_triangles, qtool_obj_mesh *out, qtool_gltf_camera **cams,
                        size_t *ncam, char *err, size_t errlen)
{
    char file[4096];
    double t;
    if (split_time(path, file, sizeof file, &t) != 0) {
        snprintf(err, errlen, "%.200s...: path too long", path);
        return -1;
    }
    uint8_t head[8] = {0};
    FILE *f = fopen(file, "rb");
    size_t nh = f ? fread(head, 1, sizeof head, f) : 0;
    if (f)
        fclose(f);
    if (cams)
        *cams = NULL;
    if (ncam)
        *ncam = 0;
    if (gltf_ext(file, strlen(file)) || qtool_gltf_sniff_glb(head, nh)) {
        qtool_gltf_scene s;
        if (qtool_gltf_read_at(file, max_triangles, t, &s, err, errlen) != 0)
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
    return qtool_obj_read_materials(path, max_triangles, out, err, errlen);
}
