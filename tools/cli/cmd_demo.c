/*
 * cmd_demo.c - `qibl demo`: options (its option table, opt/opt.h) into a demo_opts, then the demo library (tools/demo) part by
 * part: bake, relight and score (assets, sweeps, contact sheet), light paths, probe-lit rows.
 */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "opt/opt.h"
#include "cli/scene_opts.h"
#include "demo/demo.h"
#include "render/rt.h"

typedef struct demo_opts {
    const qtool_demo_size *size;
    qcli_scene scene;
    const char *dir;
    long ndirs, frames;
    long probe_parts, probe_spp;
    const char *probe; /* --probe P.hdr: the bake and the probe-lit rows for P only */
} demo_opts;

#define DEMO_PROSE \
    "  What `make demo` runs: bakes the scene (built-in courtyard, or --scene FILE.gltf|.glb|.obj|.ply), writes\n" \
    "  the assets for k = 9, 16, 25, relights a sun sweep and a moving lamp with the core (PNG frames and\n" \
    "  APNG), a contact sheet (relit | ground truth | error heat map) for novel lights, and prints the\n" \
    "  table of k, bytes, ms/frame and PSNR with RESULT lines, then the light paths, the probe-lit rows and\n" \
    "  a fixed camera's row (the scene from a corner against the ray-traced frame of that camera), an IES\n" \
    "  lamp (a built-in LM-63 profile) on the lamp track against its ray-traced truth, and the near-field\n" \
    "  source against the luminaire ray-traced beside its far-field treatment (`qibl luminaire study`).\n" \
    "  Sizes: default 512x128, 256 directions, 12 frames (`make demo`); --small 256x64, 128 directions,\n" \
    "  6 frames (CI); --full 1024x256, 512 directions, 24 frames and the full probe-lit truths (`make demo\n" \
    "  FULL=1`, minutes of CPU). --size WxH, --dirs and --frames override the size's values.\n" \
    "  --probe PROBE.hdr: the bake, then the probe-lit table for that probe alone (role \"user\": SH, median-cut\n" \
    "  lights, sun + SH against the truth under the whole probe; what bake/relight/render --probe give).\n"

/* What the line says (opt/opt.h): 0 for a value the demo size gives (--small, --full, else default). */
typedef struct demo_cli {
    qcli_scene_cli sc; /* first, as the scene options' table entries expect */
    const char *dir, *probe;
    long ndirs, frames;
    int small, full, pick; /* pick: the last of --small (1) and --full (2) given */
    demo_opts o;           /* the options together (demo_check) */
} demo_cli;

static const char *small_call(void *opts, const char *unused)
{
    (void)unused;
    ((demo_cli *)opts)->pick = 1;
    return NULL;
}

static const char *full_call(void *opts, const char *unused)
{
    (void)unused;
    ((demo_cli *)opts)->pick = 2;
    return NULL;
}
static const demo_cli demo_cli_defaults = {.sc = {.camera = QTOOL_SCENE_PANORAMA, .fov = QTOOL_RT_CAMERA_FOV_DEFAULT}};

static const qtool_opt demo_table[] = {
    {.name = "--out", .kind = QTOOL_OPT_STR, .off = offsetof(demo_cli, dir), .arg = "DIR", .required = 1,
     .help = "where the assets, frames, sheets and sweeps go"},
    {.name = "--small", .kind = QTOOL_OPT_FLAG, .off = offsetof(demo_cli, small), .call = small_call,
     .help = "the small size (CI; the last of --small and --full counts)"},
    {.name = "--full", .kind = QTOOL_OPT_FLAG, .off = offsetof(demo_cli, full), .call = full_call,
     .help = "the full size and the full probe-lit truths (minutes of CPU)"},
    {.name = "--dirs", .kind = QTOOL_OPT_INT, .off = offsetof(demo_cli, ndirs), .arg = "N", .lo = 16, .hi = 65536,
     .def = "the size's", .help = "bake directions"},
    {.name = "--frames", .kind = QTOOL_OPT_INT, .off = offsetof(demo_cli, frames), .arg = "F", .lo = 2, .hi = 240,
     .def = "the size's", .help = "frames per sweep"},
    {.name = "--probe", .kind = QTOOL_OPT_STR, .off = offsetof(demo_cli, probe), .arg = "PROBE.hdr",
     .help = "the probe-lit table for this probe only"},
    QCLI_SCENE_OPTS("the size's"),
    {0},
};

static const qtool_opt_cmd demo_spec = {
    .name = "demo",
    QTOOL_OPT_TABLE(demo_table, demo_cli_defaults),
    .prose = DEMO_PROSE,
};

/* the defaults in one place: the size's values, the scene options' own defaults */
static demo_opts demo_defaults(const qtool_demo_size *sz)
{
    demo_opts o = {
        .size = sz,
        .dir = NULL,
        .ndirs = sz->ndirs,
        .frames = sz->frames,
        .probe_parts = QTOOL_DEMO_MAX_PARTS,
        .probe_spp = sz->probe_spp,
    };
    qcli_scene_defaults(&o.scene);
    o.scene.w = sz->w, o.scene.h = sz->h;
    return o;
}

/* the size (the last of --small and --full, else the default), then what the line gives over the size's values
 * (--size WxH, --dirs, --frames). 0, or 2 after the one line. */
static int demo_check(void *opts)
{
    demo_cli *c = opts;
    demo_opts *o = &c->o;
    *o = demo_defaults(qtool_demo_size_named(c->pick == 2 ? "full" : c->pick == 1 ? "small" : "default"));
    if (qcli_scene_from(&demo_spec, &c->sc, &o->scene) != 0)
        return 2;
    o->dir = c->dir, o->probe = c->probe;
    o->ndirs = c->ndirs ? c->ndirs : o->ndirs;
    o->frames = c->frames ? c->frames : o->frames;
    /* for studies: parts per extended source, samples per pixel of the probe-lit truths (a value
     * that does not parse leaves the default, as it always has) */
    const char *env_k = getenv("QIBL_DEMO_PROBE_PARTS"), *env_spp = getenv("QIBL_DEMO_PROBE_SPP");
    long v;
    if (env_k && qcli_parse_int(env_k, 1, QTOOL_DEMO_MAX_PARTS, &v) == 0)
        o->probe_parts = v;
    if (env_spp && qcli_parse_int(env_spp, 4, 1 << 20, &v) == 0)
        o->probe_spp = v;
    return 0;
}

static void print_table(const char *scene_name, const demo_opts *o, const qtool_demo_main *m)
{
    const qcli_scene *so = &o->scene;
    printf("\n%s, %ux%u, %ld directions, bake %.1f s on %d threads\n", scene_name, so->w, so->h, o->ndirs, m->bake_s,
           so->threads);
    printf("PSNR: the core's 8-bit relit frames against ray-traced ground truth (sRGB 8-bit, scene pixels),\n"
           "mean MSE over 8 novel suns / 4 lamps (cube-map LUT 32^2, falloff C0/|L|)\n\n");
    printf("|  k | bytes on disk | relight ms/frame (sun / lamp) | PSNR sun dB | PSNR lamp dB |\n");
    printf("|---:|--------------:|------------------------------:|------------:|-------------:|\n");
    for (int q = 0; q < QTOOL_DEMO_NK; ++q)
        printf("| %2u | %13zu | %13.2f / %-13.2f | %11.2f | %12.2f |\n", qtool_demo_ks[q], m->asize[q], m->ms_dir[q],
               m->ms_pt[q], m->psnr_dir[q], m->psnr_pt[q]);
    printf("\nprojection, k = 16, novel suns: quadrature %.2f dB, least squares %.2f dB\n", m->psnr_dir[1], m->lsq_dir);
    for (int q = 0; q < QTOOL_DEMO_NK; ++q) {
        uint32_t k = qtool_demo_ks[q];
        printf("RESULT demo.psnr_k%u_dir %.2f\nRESULT demo.psnr_k%u_point %.2f\nRESULT demo.bytes_k%u %zu\n"
               "RESULT demo.relight_ms_k%u %.3f\n",
               k, m->psnr_dir[q], k, m->psnr_pt[q], k, m->asize[q], k, m->ms_dir[q]);
    }
    printf("RESULT demo.psnr_k16_dir_lsq %.2f\nRESULT demo.bake_s %.2f\n", m->lsq_dir, m->bake_s);
}

/* the demo's parts in order on the loaded scene s; 0, or 1 after a message */
static int run(const demo_opts *o, const qtool_rt_scene *s)
{
    const qcli_scene *so = &o->scene;
    const char *scene_name = so->scene ? so->scene : "the built-in courtyard";
    qtool_demo_view v = {
        .scene = s,
        .w = so->w,
        .h = so->h,
        .kind = (qtool_pano_kind)so->kind,
        .threads = so->threads,
        .prop = so->scene && !so->raw && strcmp(so->scene, "builtin") != 0,
        .dir = o->dir,
        .out = stdout,
    };
    char err[1200];
    qtool_demo_main m;
    printf("== bake %s (demo size %s): %ux%u %s panorama, %ld light directions (spherical Fibonacci), %zu triangles, "
           "%d threads\n",
           scene_name, o->size->name, v.w, v.h, so->kind ? "equirectangular" : "cylindrical", o->ndirs, s->ntri, v.threads);
    int rc = qtool_demo_bake(&v, (uint32_t)o->ndirs, &m, err, sizeof err);
    if (rc == 0 && o->probe) { /* --probe: the probe-lit rows of that probe alone */
        rc = qtool_demo_probe_file(&v, o->probe, (uint32_t)o->probe_spp, (int)o->probe_parts, &m.sums,
                                   (uint32_t)o->ndirs, err, sizeof err);
        if (rc != 0)
            fprintf(stderr, "qibl: %s\n", err);
        qtool_demo_main_free(&m);
        return rc ? 1 : 0;
    }
    if (rc == 0) {
        printf("bake: %.1f s (reference renders and SH sums for k <= 25)\n", m.bake_s);
        /* the evaluation set: novel suns, then lamps (relight_light.c) */
        qtool_rt_light ev[QTOOL_DEMO_NEVAL];
        qcli_eval_lights(v.prop, QTOOL_DEMO_NSUN, QTOOL_DEMO_NLAMP, ev);
        rc = qtool_demo_relight(&v, ev, o->frames, &m, err, sizeof err);
    }
    if (rc == 0) {
        print_table(scene_name, o, &m);
        rc = qtool_demo_paths(&v, (uint32_t)o->ndirs, o->size, &m.sums, m.asset[1], m.asize[1], err, sizeof err);
    }
    if (rc == 0)
        rc = qtool_demo_probe(&v, (uint32_t)o->probe_spp, (int)o->probe_parts, &m.sums, (uint32_t)o->ndirs, err,
                              sizeof err);
    if (rc == 0)
        rc = qtool_demo_camera(&v, (uint32_t)o->ndirs, o->size, err, sizeof err);
    if (rc == 0)
        rc = qtool_demo_nearfield(&v, o->size, m.asset[1], m.asize[1], err, sizeof err);
    if (rc == 0)
        printf("\nwrote %s/: scene_k{9,16,25}.qibl, sun_NN.png and sun_sweep.png (APNG), lamp_NN.png and lamp_sweep.png "
               "(APNG), contact_sheet.png (relit | ground truth | error), relit_sun.png, truth_sun.png, paths_sheet.png, "
               "paths_readme.png, probe_sheet.png, camera_sheet.png\n",
               o->dir);
    else
        fprintf(stderr, "qibl: %s\n", err);
    qtool_demo_main_free(&m);
    return rc ? 1 : 0;
}

static int demo_run(void *opts)
{
    const demo_opts *o = &((const demo_cli *)opts)->o;
    char err[1200];
    if (qtool_demo_check_out(o->dir, o->frames, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: %s\n", err);
        return 1;
    }
    qtool_rt_scene s;
    if (qcli_scene_load(&o->scene, &s) != 0)
        return 1;
    int rc = run(o, &s);
    qtool_rt_scene_free(&s);
    return rc;
}

const qcli_sub qcli_sub_demo = {.opts = &demo_spec, .check = demo_check, .run = demo_run};
