/*
 * cmd_view.c - `qibl view`: the live viewer (tools/view). Parses the options by its option table
 * (opt/opt.h; an asset's and a mesh's options on one) into their struct, reads the asset, has
 * tools/view set it up (qtool_view_open_asset: maps, lamp, sun) and load the truth
 * (qtool_view_truths_load), adds the probes' SH (relight_light.c, as `qibl relight --probe` makes
 * it), then hands over to qtool_view_run and prints the bench's figures.
 */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/relight_light.h"
#include "io/file.h"
#include "io/png.h"
#include "view/view.h"

/* What `qibl view` was asked (the library's defaults: view/view.h). An option of one mode only says
 * so at the start of its help ("a mesh: ...", "an asset: ..."), and the other mode refuses it by name. */
typedef struct view_cli {
    qtool_opt_list file, probes;
    const char *truth, *record, *png;
    int gles, bench, headless, turn, have_sun;
    long frames, size, threads; /* threads 0: the job's CPUs */
    double exposure;            /* 0: not given (an asset's 1, a mesh's automatic) */
    qibl_q16_t sun[3];
    qtool_view_asset_opts asset; /* lamp_c0 */
    qtool_view_mesh_opts mesh;   /* zup, transfer, yaw, pitch, the camera */
    char why[96];
} view_cli;

static const view_cli view_defaults = {.frames = QTOOL_VIEW_BENCH_FRAMES_DEFAULT, .size = QTOOL_VIEW_MESH_SIZE_DEFAULT,
                                       .asset = QTOOL_VIEW_ASSET_OPTS_DEFAULT, .mesh = QTOOL_VIEW_MESH_OPTS_DEFAULT};

static const char *camera_call(void *opts, const char *v)
{
    qtool_view_mesh_opts *m = &((view_cli *)opts)->mesh;
    return qcli_parse_azel(v, QTOOL_VIEW_CAM_EL_MAX, &m->cam_az, &m->cam_el) != 0
               ? "is not AZ,EL in degrees (|EL| <= 89), e.g. 35,20"
               : NULL;
}

static const char *sun_call(void *opts, char *const *v, int n, int *used)
{
    view_cli *c = opts;
    (void)n, (void)used;
    const char *bad = qcli_parse_q16_dir(v, 40, "the direction is 0 0 0 in Q16.16", c->sun, c->why, sizeof c->why);
    if (!bad)
        c->have_sun = 1;
    return bad;
}

#define V_(field) offsetof(view_cli, field)
static const qtool_opt view_table[] = {
    {.name = "--probe", .kind = QTOOL_OPT_LIST, .off = V_(probes), .arg = "P.hdr", .hi = QTOOL_VIEW_MAX_PROBES,
     .help = "a probe's SH and median-cut lights (p steps through them); a mesh needs one"},
    {.name = "--exposure", .kind = QTOOL_OPT_NUM, .off = V_(exposure), .arg = "E",
     .lo = QTOOL_VIEW_EXPOSURE_MIN / 65536.0, .hi = QTOOL_VIEW_EXPOSURE_MAX / 65536.0,
     .why = "the viewer's exposure range", .def = "1; a mesh: the first frame's 99th percentile at 0.6",
     .help = "the starting exposure"},
    {.name = "--bench", .kind = QTOOL_OPT_FLAG, .off = V_(bench),
     .help = "sweep the light over --frames frames, then print the ms per frame and RESULT view.fps"},
    {.name = "--frames", .kind = QTOOL_OPT_INT, .off = V_(frames), .lo = 1, .hi = QTOOL_VIEW_BENCH_FRAMES_MAX,
     .help = "--bench's frames"},
    {.name = "--headless", .kind = QTOOL_OPT_FLAG, .off = V_(headless),
     .help = "--bench without a window: the framebuffer and overlay only"},
    {.name = "--record", .kind = QTOOL_OPT_STR, .off = V_(record), .arg = "OUT.png",
     .help = "--bench's frames, overlay included, as an animated PNG"},
    {.name = "--turn", .kind = QTOOL_OPT_FLAG, .off = V_(turn), .help = "--bench: one turn over the frames"},
    {.name = "--transfer", .kind = QTOOL_OPT_STR, .off = V_(mesh.transfer), .arg = "FILE.qtr",
     .help = "a mesh: its `qibl transfer --export` file instead of computing the transfer"},
    {.name = "--zup", .kind = QTOOL_OPT_FLAG, .off = V_(mesh.zup), .help = "a mesh: Z-up (not turned from Y-up)"},
    {.name = "--size", .kind = QTOOL_OPT_INT, .off = V_(size), .lo = QTOOL_VIEW_MESH_SIZE_MIN,
     .hi = QTOOL_VIEW_MESH_SIZE_MAX, .help = "a mesh: the square frame's side"},
    {.name = "--threads", .kind = QTOOL_OPT_INT, .off = V_(threads), .lo = 1, .hi = 256,
     .def = "the CPUs of the process's affinity, or SLURM_CPUS_PER_TASK", .help = "a mesh: the transfer's threads"},
    {.name = "--light-yaw", .kind = QTOOL_OPT_NUM, .off = V_(mesh.yaw), .arg = "DEG", .lo = -360, .hi = 360,
     .help = "a mesh: the lighting's starting yaw"},
    {.name = "--light-pitch", .kind = QTOOL_OPT_NUM, .off = V_(mesh.pitch), .arg = "DEG", .lo = -360, .hi = 360,
     .help = "a mesh: the lighting's starting pitch"},
    {.name = "--camera", .kind = QTOOL_OPT_CALL, .call = camera_call, .arg = "AZ,EL", .def = "35,20",
     .help = "a mesh: the orbit camera's start, degrees"},
    {.name = "--png", .kind = QTOOL_OPT_STR, .off = V_(png), .arg = "OUT.png",
     .help = "a mesh: the first frame without a window (not with --bench)"},
    {.name = "--sun", .kind = QTOOL_OPT_CALL, .nargs = 3, .call_n = sun_call, .arg = "X Y Z",
     .help = "an asset: the starting sun's direction"},
    {.name = "--lamp-rgb", .kind = QTOOL_OPT_NUM, .off = V_(asset.lamp_c0), .arg = "C0", .lo = 1.0 / 65536,
     .hi = QTOOL_CLI_Q16_MAX, .why = QTOOL_CLI_Q16_WHY, .def = "relight --point's", .help = "an asset: the lamp's C0"},
    {.name = "--truth", .kind = QTOOL_OPT_STR, .off = V_(truth), .arg = "PNG|DIR",
     .help = "an asset: the PSNR against a `qibl render` PNG, or the nearest of a directory's sun_X_Y_Z.png"},
    {.name = "--gles", .kind = QTOOL_OPT_FLAG, .off = V_(gles), .help = "an asset: relit by platform/gles2"},
    {0},
};

static const qtool_opt_cmd view_spec = {
    QTOOL_OPT_CMD("view", view_table, view_defaults, "FILE|MESH", 0, 1, view_cli, file),
    .synopsis = "FILE|MESH",
    .prose =
        "  qibl view FILE [--sun X Y Z] [--probe P.hdr]... [--lamp-rgb C0] [--exposure E] [--truth PNG|DIR]\n"
        "                 [--gles] [--bench [--frames N] [--headless] [--record OUT.png [--turn]]]\n"
        "  A window (X11) showing the asset relit by the core through platform/soft (--gles: platform/gles2\n"
        "  into the window through an EGL window surface; read back from a headless EGL context with\n"
        "  --headless, --record, --truth or without EGL's X11 platform), with an overlay under the frame:\n"
        "  scheme, light, k, exposure, ms per frame, fps and, with --truth, the PSNR against a `qibl\n"
        "  render` PNG of the same size, or (a directory) against the one of its sun_X_Y_Z.png frames\n"
        "  (`qibl render --sun X Y Z`; at most 64) whose sun is nearest the dragged one, named with the\n"
        "  angle between them. Schemes (s cycles; those the asset or options cannot show are skipped): SUN\n"
        "  (drag with the left button: a window width turns the sun once around, its height sweeps 180\n"
        "  degrees of elevation), SH / LIGHTS (each --probe's SH or its median-cut lights, as relight\n"
        "  --probe and --probe-mode lights; p next probe, y / Y yaw -/+15 degrees), SUN+SH, LAMP (a point\n"
        "  lamp: the drag picks the P map under the pointer and hangs the lamp 1/10 of the way toward the\n"
        "  viewpoint; C0 --lamp-rgb, default relight --point's), PATH (a baked light path: t / T step 1/32,\n"
        "  a drag scrubs, P next path; sRGB at exposure 1). Keys: + / - exposure x2 / /2, k fewer SH terms\n"
        "  (cycles), l linear / sRGB, q or Escape quits. Every settled change prints `view: sun X Y Z |\n"
        "  ...` (with `| lamp X Y Z rgb R G B` or `| path N tq T`) on stdout: relight with those values\n"
        "  gives the same frame. --bench: --frames N frames with the sun dragged 4 pixels a frame (--turn:\n"
        "  one turn over the frames), then `RESULT view.fps F` (--headless: no window, the framebuffer and\n"
        "  overlay only); --record OUT.png: those frames, overlay included, as an APNG. The window needs a\n"
        "  build with X11 (Debian: apt-get install libx11-dev).\n"
        "  qibl view MESH.obj|.ply|.gltf --probe P.hdr [--probe P2.hdr]... [--transfer FILE.qtr] [--zup]\n"
        "                 [--size N] [--threads N] [--light-yaw DEG] [--light-pitch DEG] [--camera AZ,EL]\n"
        "                 [--exposure E] [--png OUT.png | --bench [--frames N] [--headless]\n"
        "                 [--record OUT.png [--turn]]]\n"
        "  Mesh mode: the mesh's hemi transfer computed once as `qibl transfer` does (or read from its\n"
        "  --export file: --transfer), shaded per vertex by the core under the probe's SH turned live and\n"
        "  drawn by platform/soft's rasterizer (a --size N square) from an orbit camera\n"
        "  (--camera AZ,EL). Left drag: the lighting's yaw (a width once around) and pitch\n"
        "  (a height 180 degrees); right drag: the camera; y / Y light yaw -/+15, [ / ] camera -/+15, p\n"
        "  next probe, + / - exposure (default: the first frame's 99th percentile at 0.6). Every settled\n"
        "  change prints `view: mesh --light-yaw Y --light-pitch P --camera AZ,EL --exposure E probe N |\n"
        "  ...`: those options with that probe and --png OUT.png write the same frame without a window.\n"
        "  --bench turns the light and prints `RESULT view.mesh_fps F`.\n",
};

/* the first option on the line of a mesh's own and of an asset's own, as their help begins (the line
 * has parsed, so each option's values are where the table took them) */
static void modes_seen(int argc, char **argv, const char **mesh_only, const char **asset_only)
{
    *mesh_only = *asset_only = NULL;
    for (int i = 1; i < argc; ++i)
        for (int k = 0; view_table[k].name; ++k) {
            const qtool_opt *e = &view_table[k];
            if (strcmp(argv[i], e->name) != 0)
                continue;
            const char **first = strncmp(e->help, "an asset:", 9) == 0 ? asset_only
                                 : strncmp(e->help, "a mesh:", 7) == 0    ? mesh_only
                                                                          : NULL;
            if (first && !*first)
                *first = e->name;
            i += e->kind == QTOOL_OPT_FLAG ? 0 : e->nargs > 1 ? e->nargs : 1;
            break;
        }
}

/* what the table cannot say (a mesh's options or an asset's), then c into the library's structs: 0, or 2
 * after the one line */
static int view_check(void *opts, int argc, char **argv)
{
    const qtool_opt_cmd *t = &view_spec;
    view_cli *c = opts;
    const char *mesh_only, *asset_only;
    modes_seen(argc, argv, &mesh_only, &asset_only);
    if (c->file.n == 0)
        return qtool_opt_error(t, "needs an asset FILE (qibl gen or qibl bake makes one) or a MESH");
    const char *in = c->file.v[0];
    const int mesh = qtool_view_is_mesh(in);
    if (mesh && asset_only)
        return qtool_opt_error(t, "%s is for an asset: a mesh is lit by --probe and drawn through platform/soft",
                               asset_only);
    if (!mesh && mesh_only)
        return qtool_opt_error(t, "%s is for a mesh (qibl view MESH.obj --probe P.hdr)", mesh_only);
    if (mesh && c->probes.n == 0)
        return qtool_opt_error(t, "%s needs --probe P.hdr (the lighting of its transfer)", in);
    if (c->png && c->bench)
        return qtool_opt_error(t, "--png writes one frame without a window: not with --bench");
    if (c->headless && !c->bench)
        return qtool_opt_error(t, "--headless is for --bench (a window needs a display)");
    if (c->record && !c->bench)
        return qtool_opt_error(t, "--record needs --bench (it records the frames the bench sweeps)");
    if (c->record && c->frames < 2)
        return qtool_opt_error(t, "--record needs --frames of at least 2 (an animated PNG)");
    if (c->turn && !c->bench)
        return qtool_opt_error(t, "--turn is for --bench (one turn of the sun over the frames)");
    /* into the library's structs */
    if (c->exposure > 0)
        c->asset.exposure = c->mesh.exposure = c->exposure;
    c->asset.sun = c->have_sun ? c->sun : NULL;
    c->mesh.mesh = in, c->mesh.probes = c->probes.v, c->mesh.nprobes = (uint32_t)c->probes.n;
    c->mesh.size = (uint32_t)c->size, c->mesh.threads = (int)c->threads;
    return 0;
}

/* each probe's SH as `qibl relight --probe P` makes it, and its median-cut lights; 0 or -1 */
static int load_probes(const view_cli *o, qtool_view *v)
{
    const uint32_t np = (uint32_t)o->probes.n;
    for (uint32_t j = 0; j < np; ++j) {
        qcli_light_list ll;
        qcli_light_list_init(&ll);
        ll.probe = o->probes.v[j];
        if (qcli_light_list_sh(&ll, v->maps.k, stdout, &v->probe[j]) != 0)
            return -1;
        ll.mode = QCLI_PROBE_LIGHTS; /* and its median-cut lights, as relight --probe-mode lights */
        if (qcli_light_list_sh(&ll, v->maps.k, stdout, &v->probe_lights[j]) != 0)
            return -1;
        const char *slash = strrchr(o->probes.v[j], '/');
        v->probe_name[j] = slash ? slash + 1 : o->probes.v[j]; /* the overlay shows the file's name */
    }
    v->nprobes = np, v->have_lights = np > 0;
    if (np)
        v->scheme = QTOOL_VIEW_SUN_SH;
    return 0;
}

/* --png: the frame alone (no overlay) as the window shows it, in RGB; 0 or -1 with err */
static int write_frame(qtool_view *v, const char *png, char *err, size_t errlen)
{
    const uint32_t w = v->maps.width, h = v->maps.height;
    uint8_t *bgrx = malloc((size_t)w * h * 4), *rgb = malloc((size_t)w * h * 3);
    qibl_status_t st = QIBL_OK;
    int rc = -1;
    if (!bgrx || !rgb)
        snprintf(err, errlen, "view: out of memory");
    else if (qtool_view_render(v, bgrx, (size_t)w * 4, NULL, &st) != 0)
        snprintf(err, errlen, "view: %s", qibl_status_str(st));
    else {
        for (size_t p = 0; p < (size_t)w * h; ++p)
            rgb[3 * p] = bgrx[4 * p + 2], rgb[3 * p + 1] = bgrx[4 * p + 1], rgb[3 * p + 2] = bgrx[4 * p];
        rc = qtool_png_write_rgb8(png, (int)w, (int)h, rgb, err, errlen);
    }
    free(bgrx), free(rgb);
    return rc;
}

/* mesh mode: the transfer once, then the window, the bench or --png; 0 or 1 */
static int view_mesh(view_cli *o)
{
    qtool_view v;
    char err[600], note[600];
    if (o->mesh.threads == 0)
        o->mesh.threads = qcli_default_threads();
    if (qtool_view_open_mesh(&v, &o->mesh, note, sizeof note, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: %s\n", err);
        return 1;
    }
    int rc = 1;
    double fps = 0;
    uint32_t nv, nt, nc;
    qtool_view_mesh_counts(&v, &nv, &nt, &nc);
    qtool_view_run_opts ro = {.title = "qibl view", .bench_frames = o->bench ? o->frames : 0, .bench_fps = &fps,
                              .headless = o->headless, .log = o->bench ? NULL : stdout, .record = o->record,
                              .drag_dx = o->turn ? (int)((v.maps.width + (uint32_t)o->frames - 1) / (uint32_t)o->frames)
                                                 : 0};
    if (o->png ? write_frame(&v, o->png, err, sizeof err) != 0 : qtool_view_run(&v, &ro, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: %s\n", err);
        goto out;
    }
    if (o->png)
        printf("wrote %s (%ux%u: %s, %u vertices, light yaw %.17g pitch %.17g, camera %.17g,%.17g, exposure %.17g)\n",
               o->png, v.maps.width, v.maps.height, o->mesh.mesh, nv, v.yaw, v.pitch, v.cam_az, v.cam_el,
               v.exposure / 65536.0);
    if (o->bench) {
        printf("view bench: %s, %u vertices x %u SH, %u triangles, %ux%u, %ld frames with the light turning, %s: %.2f "
               "ms per frame (last)\n", o->mesh.mesh, nv, nc, nt, v.maps.width, v.maps.height, o->frames,
               o->headless ? "headless (framebuffer and overlay)" : "shown in an X11 window", v.ms);
        printf("RESULT view.mesh_fps %.1f\n", fps);
        if (o->record)
            printf("wrote %s (%ld frames, %ux%u, the viewer's window with its overlay)\n", o->record, o->frames,
                   v.maps.width, v.maps.height + QTOOL_VIEW_OVERLAY_H);
    }
    rc = 0;
out:
    qtool_view_close_mesh(&v);
    return rc;
}

static int view_run(void *opts)
{
    view_cli *o = opts;
    if (!o->bench && !o->png && !qtool_view_have_window()) {
        fprintf(stderr, "qibl: view: this qibl was built without X11 (Debian: apt-get install libx11-dev, then "
                        "rebuild); --bench --headless still runs\n");
        return 1;
    }
    const char *in = o->file.v[0];
    if (qtool_view_is_mesh(in))
        return view_mesh(o);
    uint8_t *bytes = NULL;
    qtool_view_truths tset = {0};
    qtool_view_gles *vg = NULL;
    size_t n;
    char err[600], note[600];
    if (qtool_io_read_asset(in, &bytes, &n, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: %s\n", err);
        return 1;
    }
    int rc = 1;
    qtool_view v;
    o->asset.lamp_default = qcli_point_default;
    const int orc = qtool_view_open_asset(&v, bytes, n, in, &o->asset, note, sizeof note, err, sizeof err);
    if (note[0])
        fprintf(stderr, "qibl: note: %s\n", note);
    if (orc != 0) {
        fprintf(stderr, "qibl: %s\n", err);
        goto out;
    }
    const qibl_shmaps_t m = v.maps;
    if (load_probes(o, &v) != 0)
        goto out;
    if (o->truth && qtool_view_truths_load(o->truth, m.width, m.height, &tset, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: %s\n", err);
        goto out;
    }
    if (o->gles && !(vg = qtool_view_gles_open(&v, err, sizeof err))) {
        fprintf(stderr, "qibl: %s\n", err);
        goto out;
    }
    double fps = 0;
    qtool_view_run_opts ro = {.title = "qibl view", .frame = o->gles ? qtool_view_gles_frame : NULL, .user = vg,
                              .gl = o->gles ? &qtool_view_gles_window : NULL,
                              .truth = tset.one, .ntruths = tset.n, .truths = (const uint8_t *const *)tset.rgb,
                             .truth_dirs = (const double(*)[3])tset.dir, .truth_names = (const char *const *)tset.name,
                             .bench_frames = o->bench ? o->frames : 0, .bench_fps = &fps,
                             .headless = o->headless, .log = o->bench ? NULL : stdout, .record = o->record,
                             .drag_dx = o->turn ? (int)((m.width + (uint32_t)o->frames - 1) / (uint32_t)o->frames) : 0};
    if (qtool_view_run(&v, &ro, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: %s\n", err);
        goto out;
    }
    if (o->bench) {
        printf("view bench: %ux%u, k = %u, %s, %ld frames with the sun dragged, %s: %.2f ms per frame (last)\n",
               m.width, m.height, m.k, o->gles ? "platform/gles2" : "core + platform/soft", o->frames,
               o->headless ? "headless (framebuffer and overlay)" : "shown in an X11 window", v.ms);
        printf("RESULT view.fps %.1f\n", fps);
        if (o->record)
            printf("wrote %s (%ld frames, %ux%u, the viewer's window with its overlay)\n", o->record, o->frames, m.width,
                   m.height + QTOOL_VIEW_OVERLAY_H);
    }
    rc = 0;
out:
    qtool_view_gles_close(vg);
    qtool_view_truths_free(&tset);
    free(bytes);
    return rc;
}

const qcli_sub qcli_sub_view = {.opts = &view_spec, .check_line = view_check, .run = view_run};
