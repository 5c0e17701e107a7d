/*
 * cmd_luminaire.c - `qibl luminaire capture|info|render|study|passes|picture`: near-field light sources (the
 * library is tools/luminaire: the .qnf file, the simulated acquisition, the textured spotlights).
 *
 * Output is all or nothing: files are written atomically, and a report is printed only once
 * everything it describes has succeeded.
 */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "opt/opt.h"
#include "gles/headless.h"
#include "io/file.h"
#include "io/obj.h"
#include "io/png.h"
#include "luminaire/luminaire.h"
#include "luminaire/spots_gles.h"
#include "qibl/asset.h"
#include "qibl/soft.h"

/* ---- the option tables (opt/opt.h): one per subcommand ------------------------------------- */

typedef struct capture_cli {
    qtool_opt_list src; /* builtin or MESH.obj */
    const char *out;
    long grid, res, threads;
    int basis; /* 0 box, 1 tent */
    double emitter[2];
    int have_emitter;
} capture_cli;
static const capture_cli capture_defaults = {.grid = 16, .res = 32, .threads = 1};
static const char *const bases[] = {"box", "tent", NULL};

static const char *capture_emitter(void *o, char *const *v, int n, int *used)
{
    capture_cli *c = o;
    (void)n, (void)used;
    for (int k = 0; k < 2; ++k) {
        double x;
        if (qtool_opt_num_value(v[k], 1e-6, 1e6, &x) != 0)
            return k ? "HALF (its half-size) is not a number in 1e-06..1e+06"
                     : "Z (its height above S) is not a number in 1e-06..1e+06";
        c->emitter[k] = x;
    }
    c->have_emitter = 1;
    return NULL;
}

static const qtool_opt capture_table[] = {
    {.name = "--out", .kind = QTOOL_OPT_STR, .off = offsetof(capture_cli, out), .arg = "F.qnf", .required = 1,
     .help = "the source file (written atomically)"},
    {.name = "--grid", .kind = QTOOL_OPT_INT, .off = offsetof(capture_cli, grid), .arg = "N", .lo = 1,
     .hi = QTOOL_LUMINAIRE_MAX_GRID, .help = "N x N filter supports on the sampling plane"},
    {.name = "--res", .kind = QTOOL_OPT_INT, .off = offsetof(capture_cli, res), .arg = "R",
     .lo = QTOOL_LUMINAIRE_MIN_RES, .hi = QTOOL_LUMINAIRE_MAX_RES, .help = "R x R texels per emission texture"},
    {.name = "--basis", .kind = QTOOL_OPT_ENUM, .off = offsetof(capture_cli, basis), .names = bases,
     .help = "box: the dual filter of a box basis; tent: a tent filter (a quasi-interpolant)"},
    {.name = "--emitter", .kind = QTOOL_OPT_CALL, .nargs = 2, .call_n = capture_emitter, .arg = "Z HALF",
     .def = "0.8 and 0.4 of the mesh's box", .help = "a mesh's square emitter: its height and half-size"},
    {.name = "--threads", .kind = QTOOL_OPT_INT, .off = offsetof(capture_cli, threads), .arg = "T", .lo = 1, .hi = 256,
     .help = "worker threads (the capture is the same bytes whatever T)"},
    {0},
};

static const qtool_opt_cmd capture_spec = {
    QTOOL_OPT_CMD("luminaire capture", capture_table, capture_defaults, "builtin|MESH.obj", 1, 1, capture_cli, src),
    .help_name = "luminaire",
    .prose =
        "  A near-field light source (Granier et al.): its light on a sampling plane S projected onto a\n"
        "  grid of N x N filter supports, each with an R x R emission texture on a measurement plane,\n"
        "  made by ray-tracing the paper's acquisition (Figure 1: the filter on S, the plane M behind\n"
        "  it). builtin: a 0.4 box shade with a checkerboard of holes in its bottom plate around a square\n"
        "  emitter. MESH.obj: a shade as it is (z up, every vertex above S: z > 0; at most 65536\n"
        "  triangles) around a square emitter facing down (--emitter); the grid covers the mesh's\n"
        "  extent. Format: tools/luminaire/luminaire.h.\n",
};

static const qtool_opt_cmd info_spec = {
    .name = "luminaire info",
    .help_name = "luminaire",
    .pos = {.names = "F.qnf", .min = 1, .max = 1},
    QTOOL_OPT_TABLE(NULL, qtool_opt_args),
    .prose = "  The source's header (grid, basis, texture, planes), its dark supports, texel range and flux.\n",
};

typedef struct render_cli {
    qtool_opt_list files; /* ASSET F.qnf */
    double at[3];
    const char *out;
    int far, gles, gles_core;
    double exposure;
    long table, frames;
    double tol;
} render_cli;
static const render_cli render_defaults = {.at = {0, 0, 0}, .exposure = 1, .table = 64, .frames = 3,
                                           .tol = QTOOL_LUMINAIRE_DEFAULT_TOL};

static const char *render_at(void *o, char *const *v, int n, int *used)
{
    render_cli *c = o;
    (void)n, (void)used;
    for (int k = 0; k < 3; ++k)
        if (qtool_opt_num_value(v[k], -32767, 32767, &c->at[k]) != 0)
            return "X Y Z are numbers in -32767..32767 (Q16.16)";
    return NULL;
}

static const qtool_opt render_table[] = {
    {.name = "--at", .kind = QTOOL_OPT_CALL, .nargs = 3, .call_n = render_at, .arg = "X Y Z", .required = 1,
     .help = "where S's centre hangs (the asset's units, each in the Q16.16 range; the source faces -z)"},
    {.name = "--out", .kind = QTOOL_OPT_STR, .off = offsetof(render_cli, out), .arg = "F.png", .required = 1,
     .help = "the frame (written atomically)"},
    {.name = "--far", .kind = QTOOL_OPT_FLAG, .off = offsetof(render_cli, far),
     .help = "the same source as one far-field lamp (IES-like) instead"},
    {.name = "--exposure", .kind = QTOOL_OPT_NUM, .off = offsetof(render_cli, exposure), .arg = "E", .lo = 1.0 / 65536,
     .hi = 65535, .help = "the frame's exposure"},
    {.name = "--table", .kind = QTOOL_OPT_INT, .off = offsetof(render_cli, table), .arg = "N", .lo = QIBL_GONIO_MIN_N,
     .hi = QIBL_GONIO_MAX_N, .help = "each spotlight's gonio table is N x N"},
    {.name = "--tol", .kind = QTOOL_OPT_NUM, .off = offsetof(render_cli, tol), .arg = "T", .lo = 0,
     .hi = QTOOL_LUMINAIRE_MAX_TOL, .help = "the hierarchy: a group of supports merged into one spotlight where its "
     "side is at most T times its distance (0: every spotlight everywhere)"},
    {.name = "--gles", .kind = QTOOL_OPT_FLAG, .off = offsetof(render_cli, gles),
     .help = "the frame on GLES2 too (a headless EGL context, one pass per spotlight): its times and its "
             "difference from the soft frame (every spotlight, no hierarchy: the soft frame too, as --tol 0)"},
    {.name = "--frames", .kind = QTOOL_OPT_INT, .off = offsetof(render_cli, frames), .arg = "N", .lo = 1, .hi = 1000,
     .help = "--gles: GPU frames timed, after one untimed warm-up"},
    {.name = "--gles-core", .kind = QTOOL_OPT_FLAG, .off = offsetof(render_cli, gles_core),
     .help = "--gles: GLES2's core path only (ping-pong, two draws per pass), even where the GL has "
             "EXT_draw_buffers and EXT_shader_framebuffer_fetch"},
    {0},
};

static const qtool_opt_cmd render_spec = {
    QTOOL_OPT_CMD("luminaire render", render_table, render_defaults, "ASSET F.qnf", 2, 2, render_cli, files),
    .help_name = "luminaire",
    .prose =
        "  An asset frame (its point maps and P map) lit by the source: one textured spotlight per lit\n"
        "  support, each a goniometric lamp of the core (qibl/gonio.h), shaded from four anchors'\n"
        "  point-map spans, summed pass by pass in integers; prints the frame's CPU time. --gles: the\n"
        "  same frame on the GPU, each spotlight evaluated by a fragment shader into 8-bit sRGBE pairs;\n"
        "  its time per frame and per pass and its difference from the soft frame, RESULT lines.\n",
};

typedef struct study_cli {
    long grid, res, size, threads;
    int quick;
    double tol;
} study_cli;
static const study_cli study_defaults = {.grid = 16, .res = 32, .size = 96, .threads = 1,
                                         .tol = QTOOL_LUMINAIRE_DEFAULT_TOL};

static const qtool_opt study_table[] = {
    {.name = "--grid", .kind = QTOOL_OPT_INT, .off = offsetof(study_cli, grid), .arg = "N", .lo = 1,
     .hi = QTOOL_LUMINAIRE_MAX_GRID, .help = "the capture's N x N supports"},
    {.name = "--res", .kind = QTOOL_OPT_INT, .off = offsetof(study_cli, res), .arg = "R", .lo = QTOOL_LUMINAIRE_MIN_RES,
     .hi = QTOOL_LUMINAIRE_MAX_RES, .help = "the capture's R x R texels"},
    {.name = "--size", .kind = QTOOL_OPT_INT, .off = offsetof(study_cli, size), .arg = "S", .lo = 8, .hi = 1024,
     .help = "the ground images are S x S"},
    {.name = "--quick", .kind = QTOOL_OPT_FLAG, .off = offsetof(study_cli, quick), .help = "fewer distances"},
    {.name = "--threads", .kind = QTOOL_OPT_INT, .off = offsetof(study_cli, threads), .arg = "T", .lo = 1, .hi = 256,
     .help = "worker threads for the capture and the truth (the timing is on one)"},
    {.name = "--tol", .kind = QTOOL_OPT_NUM, .off = offsetof(study_cli, tol), .arg = "T", .lo = 0,
     .hi = QTOOL_LUMINAIRE_MAX_TOL, .help = "the near field's hierarchy: a group of supports merged into one spotlight "
     "where its side is at most T times its distance (0: every spotlight everywhere)"},
    {0},
};

static const qtool_opt_cmd study_spec = {
    .name = "luminaire study",
    .help_name = "luminaire",
    QTOOL_OPT_TABLE(study_table, study_defaults),
    .prose =
        "  The built-in luminaire captured, then its near field (textured spotlights) and far field (one\n"
        "  gonio lamp) against the luminaire ray-traced: on a ground plane at 0.5..8 lamp sizes and\n"
        "  hanging in the built-in courtyard (PSNR); the near field's CPU time per 1024x256 frame (the\n"
        "  courtyard panorama, and a ground patch lit everywhere); RESULT lines.\n",
};

typedef struct passes_cli {
    long size;
    int gles;
} passes_cli;
static const passes_cli passes_defaults = {.size = 64};

static const qtool_opt passes_table[] = {
    {.name = "--size", .kind = QTOOL_OPT_INT, .off = offsetof(passes_cli, size), .arg = "S", .lo = 8, .hi = 512,
     .help = "the ground images are S x S"},
    {.name = "--gles", .kind = QTOOL_OPT_FLAG, .off = offsetof(passes_cli, gles),
     .help = "the same passes on GLES2 too (a headless EGL context), against the soft ones"},
    {0},
};

static const qtool_opt_cmd passes_spec = {
    .name = "luminaire passes",
    .help_name = "luminaire",
    QTOOL_OPT_TABLE(passes_table, passes_defaults),
    .prose =
        "  Sources of 16, 64 and 256 spotlights (synthetic, every support lit) one lamp size above a\n"
        "  ground plane, summed pass by pass in an 8-bit sRGBE target (decode, add, re-encode, integers),\n"
        "  in binary32 and as the core's one-call integer sum; the largest differences of the 8-bit sRGB\n"
        "  frames (exposure: the sum's peak at 1.0), RESULT lines.\n",
};

typedef struct picture_cli {
    const char *out;
    long size, threads;
    double lamps;
} picture_cli;
static const picture_cli picture_defaults = {.size = 128, .threads = 1, .lamps = 1};

static const qtool_opt picture_table[] = {
    {.name = "--out", .kind = QTOOL_OPT_STR, .off = offsetof(picture_cli, out), .arg = "F.png", .required = 1,
     .help = "the picture (near field | truth | far field)"},
    {.name = "--height", .kind = QTOOL_OPT_NUM, .off = offsetof(picture_cli, lamps), .arg = "H", .lo = 0.1, .hi = 100,
     .help = "the lamp's height above the ground, in lamp sizes"},
    {.name = "--size", .kind = QTOOL_OPT_INT, .off = offsetof(picture_cli, size), .arg = "S", .lo = 8, .hi = 1024,
     .help = "each image is S x S"},
    {.name = "--threads", .kind = QTOOL_OPT_INT, .off = offsetof(picture_cli, threads), .arg = "T", .lo = 1, .hi = 256,
     .help = "worker threads for the capture and the truth"},
    {0},
};

static const qtool_opt_cmd picture_spec = {
    .name = "luminaire picture",
    .help_name = "luminaire",
    QTOOL_OPT_TABLE(picture_table, picture_defaults),
    .prose = "  The built-in luminaire above a ground plane: its near field (textured spotlights), the\n"
             "  luminaire ray-traced, its far field (one gonio lamp), side by side, one exposure.\n",
};

static int capture_check(void *opts)
{
    const capture_cli *c = opts;
    if (strcmp(c->src.v[0], "builtin") == 0 && c->have_emitter)
        return qtool_opt_error(&capture_spec, "--emitter places the emitter in a mesh, not in 'builtin'");
    return 0;
}

static int cmd_capture(void *opts)
{
    const capture_cli c = *(const capture_cli *)opts;
    const char *src = c.src.v[0], *out = c.out;
    int builtin = strcmp(src, "builtin") == 0;
    qtool_luminaire_capture_opts o = {.grid = (uint32_t)c.grid, .res = (uint32_t)c.res, .threads = (int)c.threads,
                                      .basis = c.basis ? QTOOL_LUMINAIRE_TENT : QTOOL_LUMINAIRE_BOX};
    double ez = c.have_emitter ? c.emitter[0] : 0, eh = c.have_emitter ? c.emitter[1] : 0;
    qtool_luminaire_model *m = NULL;
    char err[512] = "";
    if (builtin) {
        m = qtool_luminaire_builtin();
    } else {
        qtool_obj_mesh mesh;
        if (qtool_obj_read_max(src, 1u << 16, &mesh, err, sizeof err) != 0) {
            fprintf(stderr, "qibl: luminaire capture: %s\n", err);
            return 1;
        }
        m = qtool_luminaire_from_mesh(&mesh, ez, eh, err, sizeof err);
        qtool_obj_free(&mesh);
        if (!m) {
            fprintf(stderr, "qibl: luminaire capture: %s: %s\n", src, err);
            return 1;
        }
    }
    qtool_luminaire l;
    if (!m || qtool_luminaire_capture(m, &o, &l) != 0) {
        qtool_luminaire_model_free(m);
        fprintf(stderr, "qibl: luminaire capture: out of memory\n");
        return 1;
    }
    qtool_luminaire_model_free(m);
    qtool_luminaire_err e = qtool_luminaire_write(out, &l, err, sizeof err);
    if (e != QTOOL_LUMINAIRE_OK) {
        fprintf(stderr, "qibl: luminaire capture: %s: %s\n", out, err[0] ? err : qtool_luminaire_err_str(e));
        qtool_luminaire_free(&l);
        return 1;
    }
    printf("wrote %s: %ux%u supports, %ux%u texels each, %s basis\n", out, l.nx, l.ny, l.res, l.res,
           l.basis == QTOOL_LUMINAIRE_TENT ? "tent" : "box");
    qtool_luminaire_free(&l);
    return 0;
}

static int cmd_info(void *opts)
{
    const char *path = ((const qtool_opt_list *)opts)->v[0];
    qtool_luminaire l;
    qtool_luminaire_err e = qtool_luminaire_read(path, &l);
    if (e != QTOOL_LUMINAIRE_OK) {
        fprintf(stderr, "qibl: luminaire info: %s: %s\n", path, qtool_luminaire_err_str(e));
        return 1;
    }
    uint32_t dark = 0;
    float lo = 0, hi = 0;
    for (uint32_t m = 0; m < l.nx * l.ny; ++m) {
        int lit = 0;
        for (size_t k = 0; k < (size_t)l.res * l.res * 3; ++k) {
            float v = l.tex[(size_t)m * l.res * l.res * 3 + k];
            lit |= v > 0;
            lo = v < lo ? v : lo, hi = v > hi ? v : hi;
        }
        dark += !lit;
    }
    double flux[3];
    qtool_luminaire_flux(&l, flux);
    printf("file %s\nformat QNF version %u\n", path, QTOOL_LUMINAIRE_VERSION);
    printf("grid %ux%u spacing %.6g\n", l.nx, l.ny, (double)l.spacing);
    printf("basis %s\n", l.basis == QTOOL_LUMINAIRE_TENT ? "tent" : "box");
    printf("texture %ux%u window_half_tan %.6g plane_distance %.6g\n", l.res, l.res, (double)l.half_tan,
           (double)l.distance);
    printf("supports %u dark %u\n", l.nx * l.ny, dark);
    printf("texel_min %.6g texel_max %.6g\n", (double)lo, (double)hi);
    printf("flux %.6g %.6g %.6g\n", flux[0], flux[1], flux[2]);
    qtool_luminaire_free(&l);
    return 0;
}

static int cmd_render(void *opts)
{
    const render_cli c = *(const render_cli *)opts;
    const char *asset = c.files.v[0], *qnf = c.files.v[1], *out = c.out;
    int32_t at[3];
    for (int k = 0; k < 3; ++k)
        at[k] = (int32_t)lround(c.at[k] * 65536.0);
    const int far = c.far;
    const uint32_t table = (uint32_t)c.table;
    const double expo = c.exposure;
#if QIBL_HAVE_GLES2
    qt_gles_ctx gl;
    memset(&gl, 0, sizeof gl);
#else
    if (c.gles) { /* the headless context is tools/gles's, built only where the EGL/GLES2 headers are */
        fprintf(stderr, "qibl: luminaire render: --gles: this qibl was built without the EGL/GLES2 headers "
                        "(Debian: apt-get install libegl-dev libgles-dev)\n");
        return 1;
    }
#endif
    qtool_luminaire l;
    qtool_luminaire_err le = qtool_luminaire_read(qnf, &l);
    if (le != QTOOL_LUMINAIRE_OK) {
        fprintf(stderr, "qibl: luminaire render: %s: %s\n", qnf, qtool_luminaire_err_str(le));
        return 1;
    }
    char err[512];
    qtool_luminaire_spots s;
    /* --gles: the GPU evaluates every spotlight, so the soft frame it is compared with does too */
    const qtool_luminaire_spots_opts so = {.n = table, .far = far, .tol = c.gles ? 0 : c.tol};
    if (qtool_luminaire_spots_build(&l, at, &so, &s, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: luminaire render: %s: %s\n", qnf, err);
        qtool_luminaire_free(&l);
        return 1;
    }
    qtool_luminaire_free(&l);
    uint8_t *bytes = NULL;
    size_t n;
    if (qtool_io_read_asset(asset, &bytes, &n, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: %s\n", err);
        qtool_luminaire_spots_free(&s);
        return 1;
    }
    qtool_luminaire_views av;
    qibl_status_t st = qtool_luminaire_views_open(bytes, n, &av);
    const qibl_shmaps_t mp = av.mp;
    uint8_t *rgb = st == QIBL_OK ? malloc((size_t)mp.width * mp.height * 3) : NULL;
    double ms = 0;
    if (st == QIBL_OK && !rgb)
        st = QIBL_E_NULL_POINTER;
    if (st == QIBL_OK)
        qtool_luminaire_relight(&s, &av.mp, &av.pm, av.lut, (uint32_t)lround(expo * 65536), 1, rgb, NULL,
                                &ms, &st);
    if (st != QIBL_OK) {
        fprintf(stderr, "qibl: luminaire render: %s: %s\n", asset, qibl_soft_status_str(st));
        free(rgb), free(bytes), qtool_luminaire_spots_free(&s);
        return 1;
    }
    /* the GPU's frame before anything is written: a refusal leaves no file and no report */
    qtool_luminaire_gles_stats gs = {0};
    int gmax = 0;
    double gmean = 0;
#if QIBL_HAVE_GLES2
    if (c.gles) {
        const size_t nb = (size_t)mp.width * mp.height * 3;
        uint8_t *grgb = malloc(nb);
        int grc = !grgb ? (snprintf(err, sizeof err, "out of memory"), -1) : qt_gles_open(&gl, 1, 1, err, sizeof err);
        if (grc == 0) {
            const qtool_luminaire_gles_opts go = {.frames = (uint32_t)c.frames, .core_only = c.gles_core};
            grc = qtool_luminaire_relight_gles(&s, &av.mp, &av.pm, av.lut, (uint32_t)lround(expo * 65536), 1,
                                               &go, grgb, &gs, err, sizeof err);
            qt_gles_close(&gl);
        }
        if (grc == 0)
            qtool_luminaire_diff8(grgb, rgb, nb, &gmax, &gmean);
        free(grgb);
        if (grc != 0) {
            fprintf(stderr, "qibl: luminaire render: --gles: %s\n", err);
            free(rgb), free(bytes), qtool_luminaire_spots_free(&s);
            return 1;
        }
    }
#endif
    int rc = qtool_png_write_rgb8(out, (int)mp.width, (int)mp.height, rgb, err, sizeof err);
    if (rc != 0) {
        fprintf(stderr, "qibl: luminaire render: %s\n", err);
    } else {
        printf("wrote %s: %ux%u, %u %s, %.1f ms CPU\n", out, mp.width, mp.height, s.count,
               far ? "far-field lamp" : "spotlights", ms);
        if (c.gles) {
            const double frame = gs.prep_ms + gs.gpu_ms + gs.read_ms;
            printf("gles (%s): %u passes (one per spotlight), each over %.1f%% of the frame; per frame %.1f ms (CPU: "
                   "P map and anchors %.1f; GPU passes %.1f; read back %.1f; %.1f ms CPU over all threads), %.3f ms "
                   "per pass; against the soft frame max %d mean %.4f (8-bit sRGB)\n",
                   gs.fetch ? "EXT_draw_buffers + EXT_shader_framebuffer_fetch" : "GLES2 core", gs.passes,
                   100 * gs.coverage, frame, gs.prep_ms, gs.gpu_ms, gs.read_ms, gs.cpu_ms,
                   gs.passes ? gs.gpu_ms / gs.passes : 0, gmax, gmean);
            printf("RESULT luminaire.soft_frame_ms %.3f\n", ms);
            printf("RESULT luminaire.gles_frame_ms %.3f\n", frame);
            printf("RESULT luminaire.gles_frame_cpu_ms %.3f\n", gs.cpu_ms);
            printf("RESULT luminaire.gles_pass_ms %.4f\n", gs.passes ? gs.gpu_ms / gs.passes : 0);
            printf("RESULT luminaire.gles_fps %.3f\n", frame > 0 ? 1000 / frame : 0);
            printf("RESULT luminaire.gles_vs_soft_max %d\n", gmax);
            printf("RESULT luminaire.gles_vs_soft_mean %.5f\n", gmean);
        }
    }
    free(rgb), free(bytes), qtool_luminaire_spots_free(&s);
    return rc == 0 ? 0 : 1;
}

static int cmd_study(void *opts)
{
    const study_cli c = *(const study_cli *)opts;
    qtool_luminaire_study_opts o = {.grid = (uint32_t)c.grid, .res = (uint32_t)c.res, .size = (uint32_t)c.size,
                                    .quick = c.quick, .threads = (int)c.threads, .tol = c.tol};
    if (qtool_luminaire_study(&o, stdout) != 0) {
        fprintf(stderr, "qibl: luminaire study: out of memory\n");
        return 1;
    }
    return 0;
}

static int cmd_passes(void *opts)
{
    const passes_cli c = *(const passes_cli *)opts;
    char err[256] = "";
#if QIBL_HAVE_GLES2
    qt_gles_ctx gl;
    memset(&gl, 0, sizeof gl);
    if (c.gles && qt_gles_open(&gl, 1, 1, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: luminaire passes: --gles: %s\n", err);
        return 1;
    }
#else
    if (c.gles) { /* the headless context is tools/gles's, built only where the EGL/GLES2 headers are */
        fprintf(stderr, "qibl: luminaire passes: --gles: this qibl was built without the EGL/GLES2 headers "
                        "(Debian: apt-get install libegl-dev libgles-dev)\n");
        return 1;
    }
#endif
    int rc = qtool_luminaire_passes_report((uint32_t)c.size, c.gles ? qtool_luminaire_passes_gles : NULL, stdout, err,
                                           sizeof err);
#if QIBL_HAVE_GLES2
    if (c.gles)
        qt_gles_close(&gl);
#endif
    if (rc != 0) {
        fprintf(stderr, "qibl: luminaire passes: %s\n", err);
        return 1;
    }
    return 0;
}

static int cmd_picture(void *opts)
{
    const picture_cli c = *(const picture_cli *)opts;
    qtool_luminaire_study_opts o = {.size = (uint32_t)c.size, .threads = (int)c.threads};
    uint8_t *rgb = NULL;
    uint32_t w = 0, h = 0;
    char err[256] = "out of memory";
    if (qtool_luminaire_picture(&o, c.lamps, &rgb, &w, &h) != 0 ||
        qtool_png_write_rgb8(c.out, (int)w, (int)h, rgb, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: luminaire picture: %s\n", err);
        free(rgb);
        return 1;
    }
    free(rgb);
    printf("wrote %s: %ux%u (near field | truth | far field, %g lamp sizes above the ground)\n", c.out, w, h,
           c.lamps);
    return 0;
}

const qcli_sub qcli_sub_luminaire_capture = {.opts = &capture_spec, .check = capture_check, .run = cmd_capture};
const qcli_sub qcli_sub_luminaire_info = {.opts = &info_spec, .run = cmd_info};
const qcli_sub qcli_sub_luminaire_render = {.opts = &render_spec, .run = cmd_render};
const qcli_sub qcli_sub_luminaire_study = {.opts = &study_spec, .run = cmd_study};
const qcli_sub qcli_sub_luminaire_passes = {.opts = &passes_spec, .run = cmd_passes};
const qcli_sub qcli_sub_luminaire_picture = {.opts = &picture_spec, .run = cmd_picture};
