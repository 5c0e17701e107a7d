/*
 * cli/scene_opts.h - the scene, panorama and camera options render, bake and demo share, as
 * entries of their option tables (cli/opt.h): QCLI_SCENE_OPTS(size_def) and QCLI_CAMERA_OPTS
 * splice them into a table; the command's options struct starts with a qcli_scene_cli (the
 * callbacks find it there), and qcli_scene_from turns it into the library's qtool_scene_opts.
 */
#ifndef QTOOL_CLI_SCENE_OPTS_H
#define QTOOL_CLI_SCENE_OPTS_H

#include <stddef.h>

#include "bake/scene.h"
#include "cli/opt.h"
#include "qibl/asset.h"

typedef struct qcli_scene_cli {
    const char *scene;
    int zup, raw, equirect;
    long size[2];    /* 0 0: the command's own (QTOOL_SCENE_W x _H, or the demo size's) */
    long threads;    /* 0: the job's CPUs (qcli_default_threads) */
    /* the fixed camera (render, bake): camera QTOOL_SCENE_PANORAMA when not given */
    int camera, gltf_cam, fov_given;
    double eye[3], target[3], up[3], fov;
    char why[128];
} qcli_scene_cli;

/* the defaults a struct starting with a qcli_scene_cli sets it to */
#define QCLI_SCENE_CLI_DEFAULT {.size = {QTOOL_SCENE_W, QTOOL_SCENE_H}, .camera = QTOOL_SCENE_PANORAMA, \
                                .fov = QTOOL_RT_CAMERA_FOV_DEFAULT}

const char *qcli_camera_call(void *opts, char *const *v, int n, int *used);
const char *qcli_fov_call(void *opts, const char *v);

/* size_def: --size's default as help shows it (NULL: read from the defaults) */
#define QCLI_SCENE_OPTS(size_def)                                                                            \
    {.name = "--scene", .kind = QCLI_OPT_STR, .off = offsetof(qcli_scene_cli, scene),                        \
     .arg = "FILE", .def = "builtin",                                                                          \
     .help = "builtin (the courtyard), or a .gltf/.glb/.obj/.ply mesh placed as a prop on a ground plane"},    \
    {.name = "--zup", .kind = QCLI_OPT_FLAG, .off = offsetof(qcli_scene_cli, zup),                           \
     .help = "the mesh is Z-up already (not turned from Y-up)"},                                               \
    {.name = "--raw", .kind = QCLI_OPT_FLAG, .off = offsetof(qcli_scene_cli, raw),                           \
     .help = "the mesh as given: nothing added, not centred or scaled"},                                        \
    {.name = "--size", .kind = QCLI_OPT_SIZE, .off = offsetof(qcli_scene_cli, size), .hi = QIBL_ASSET_MAX_DIM, \
     .def = (size_def), .help = "the panorama's (or the camera frame's) pixels, within an asset's limit"},    \
    {.name = "--equirect", .kind = QCLI_OPT_FLAG, .off = offsetof(qcli_scene_cli, equirect),                 \
     .help = "an equirectangular panorama instead of the cylindrical one"},                                     \
    {.name = "--threads", .kind = QCLI_OPT_INT, .off = offsetof(qcli_scene_cli, threads), .arg = "N", .lo = 1, \
     .hi = 256, .def = "the CPUs of the process's affinity, or SLURM_CPUS_PER_TASK",                           \
     .help = "worker threads (the result is the same for any)"}

#define QCLI_CAMERA_OPTS                                                                                        \
    {.name = "--camera", .kind = QCLI_OPT_CALL, .nargs = 3, .nargs_min = 1, .call_n = qcli_camera_call,      \
     .arg = "EX,EY,EZ TX,TY,TZ UX,UY,UZ|gltf[:N]",                                                            \
     .help = "a fixed perspective camera from EYE toward TARGET (UP about up), or the scene file's camera N"}, \
    {.name = "--fov", .kind = QCLI_OPT_CALL, .call = qcli_fov_call, .arg = "DEG", .def = "60, or the glTF's",  \
     .help = "the camera's vertical field of view, in (0, 180)"}

/* c (parsed by a table with those entries) into o, over its defaults: 0, or 2 after the line for t
 * (--size above the asset's pixels, --fov or --equirect without a camera, a bad camera). */
int qcli_scene_from(const qcli_opt_cmd *t, const qcli_scene_cli *c, qtool_scene_opts *o);

#endif
