/*
 * cmd_demo.c - `qibl demo`: options into a demo_opts, then the demo library (tools/demo) part by
 * part: bake, relight and score (assets, sweeps, contact sheet), light paths, probe-lit rows.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "demo/demo.h"
#include "render/rt.h"

typedef struct demo_opts {
    const qtool_demo_size *size;
    qcli_scene scene;
    const char *dir;
    long ndirs, frames;
    long probe_parts, probe_spp;
} demo_opts;

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

/* the size first (--small, --full), then everything else: --size WxH, --dirs and --frames given on
 * the line override the size's values. 0, or 2 after a message. */
static int parse_opts(int argc, char **argv, demo_opts *o)
{
    const char *size = "default";
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--small") == 0)
            size = "small";
        else if (strcmp(argv[i], "--full") == 0)
            size = "full";
    }
    *o = demo_defaults(qtool_demo_size_named(size));
    for (int i = 1; i < argc; ++i) {
        int r = qcli_scene_opt(argc, argv, &i, &o->scene);
        if (r < 0)
            return 2;
        if (r)
            continue;
        if (strcmp(argv[i], "--out") == 0 && i + 1 < argc)
            o->dir = argv[++i];
        else if (strcmp(argv[i], "--dirs") == 0 && i + 1 < argc) {
            if (qcli_parse_int(argv[++i], 16, 65536, &o->ndirs) != 0)
                return qcli_usage_error("--dirs needs an integer in 16..65536");
        } else if (strcmp(argv[i], "--frames") == 0 && i + 1 < argc) {
            if (qcli_parse_int(argv[++i], 2, 240, &o->frames) != 0)
                return qcli_usage_error("--frames needs an integer in 2..240");
        } else if (strcmp(argv[i], "--small") != 0 && strcmp(argv[i], "--full") != 0) {
            return qcli_usage_error("demo: unknown argument '%s' (see qibl help demo)", argv[i]);
        }
    }
    if (!o->dir)
        return qcli_usage_error("demo needs --out DIR");
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
        printf("\nwrote %s/: scene_k{9,16,25}.qibl, sun_NN.png and sun_sweep.png (APNG), lamp_NN.png and lamp_sweep.png "
               "(APNG), contact_sheet.png (relit | ground truth | error), relit_sun.png, truth_sun.png, paths_sheet.png, "
               "paths_readme.png, probe_sheet.png\n",
               o->dir);
    else
        fprintf(stderr, "qibl: %s\n", err);
    qtool_demo_main_free(&m);
    return rc ? 1 : 0;
}

int qcli_cmd_demo(int argc, char **argv)
{
    demo_opts o;
    int r = parse_opts(argc, argv, &o);
    if (r != 0)
        return r;
    if (qcli_parse_only) /* fuzz_cliopts: the options only */
        return 0;
    char err[1200];
    if (qtool_demo_check_out(o.dir, o.frames, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: %s\n", err);
        return 1;
    }
    qtool_rt_scene s;
    if (qcli_scene_load(&o.scene, &s) != 0)
        return 1;
    int rc = run(&o, &s);
    qtool_rt_scene_free(&s);
    return rc;
}
