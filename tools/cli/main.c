/*
 * main.c - the qibl command-line tool: subcommand dispatch, --help, shared argument parsing.
 */
#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/opt.h"
#include "qibl/version.h"
#include "qibl/isa.h"
#include "io/isa_env.h"

int qcli_parse_only; /* see cli.h */

/* the option tables of the commands on them (cli/opt.h), one per subcommand */
static const qcli_opt_cmd *const sh_opts[] = {&qcli_opts_sh_eval, &qcli_opts_sh_plot, &qcli_opts_sh_project, NULL};
static const qcli_opt_cmd *const gen_opts[] = {&qcli_opts_gen, NULL};
static const qcli_opt_cmd *const info_opts[] = {&qcli_opts_info, NULL};
static const qcli_opt_cmd *const srgbe_opts[] = {&qcli_opts_srgbe_encode, &qcli_opts_srgbe_decode, NULL};
static const qcli_opt_cmd *const ies_opts[] = {&qcli_opts_ies_info, NULL};
static const qcli_opt_cmd *const study_opts[] = {&qcli_opts_study, NULL};
static const qcli_opt_cmd *const bench_opts[] = {&qcli_opts_bench, NULL};
static const qcli_opt_cmd *const probe_opts[] = {&qcli_opts_probe_info, NULL};
static const qcli_opt_cmd *const lights_opts[] = {&qcli_opts_lights, NULL};
static const qcli_opt_cmd *const relight_opts[] = {&qcli_opts_relight, NULL};
static const qcli_opt_cmd *const merge_opts[] = {&qcli_opts_merge, NULL};
static const qcli_opt_cmd *const check_opts[] = {&qcli_opts_check, NULL};
static const qcli_opt_cmd *const render_opts[] = {&qcli_opts_render, NULL};
static const qcli_opt_cmd *const bake_opts[] = {&qcli_opts_bake, NULL};
static const qcli_opt_cmd *const demo_opts[] = {&qcli_opts_demo, NULL};

/* which commands are on them: `qibl help CMD` is made from these, not from the command's usage */
static const struct {
    const char *cmd;
    const qcli_opt_cmd *const *opts;
} tables[] = {{"sh", sh_opts},       {"gen", gen_opts}, {"info", info_opts},
              {"srgbe", srgbe_opts}, {"ies", ies_opts}, {"study", study_opts},
              {"bench", bench_opts}, {"probe", probe_opts}, {"lights", lights_opts},
              {"relight", relight_opts}, {"merge", merge_opts}, {"check", check_opts},
              {"render", render_opts}, {"bake", bake_opts}, {"demo", demo_opts}};

static const qcli_opt_cmd *const *tables_of(const char *cmd)
{
    for (size_t i = 0; i < sizeof tables / sizeof tables[0]; ++i)
        if (strcmp(tables[i].cmd, cmd) == 0)
            return tables[i].opts;
    return NULL;
}

static const qcli_cmd commands[] = {
    {"sh", "evaluate the integer SH basis for a direction", NULL, qcli_cmd_sh},
    {"bench", "benchmarks: speed against error, with RESULT lines", NULL, qcli_cmd_bench},
    {"gen", "write the procedural courtyard's SH maps (and P map, optional Y LUT) as an asset",
     NULL, qcli_cmd_gen},
    {"render", "ray-trace the ground-truth panorama of a scene under one light (PNG, PFM, depth)",
     NULL, qcli_cmd_render},
    {"transfer", "a mesh self-shadowed by hemispherical rasterization under a probe, beside the ray-cast truth",
     "usage: qibl transfer MESH [MESH...] --probe PROBE.hdr [--layout L] [--png OUT] [--size N] [--mask 16|32|64]\n"
     "                     [--face F] [--rays S] [--coarse T [--ring K]] [--tween N] [--zup] [--flip] [--skip-adjacent]\n"
     "                     [--view AZ,EL] [--threads N]\n"
     "  Per vertex of a glTF (.gltf, .glb: the scene's meshes in world space, skinned; FILE.gltf@T: its\n"
     "  animation at T seconds, so FILE.gltf@0 FILE.gltf@0.5 ... are frames), OBJ or PLY mesh\n"
     "  (welded by position, centred, largest half-extent 1, Y-up turned\n"
     "  to Z-up unless --zup; normals point out of counter-clockwise faces, turned by --flip or when a\n"
     "  mesh with under 2 % open edges has a negative volume), the transfer vector V*\n"
     "  (bands 0..4) from hemispherical rasterization with every triangle a blocker (qibl/hemi.h: mask\n"
     "  --mask, default 32, LUT face --face, default 64), turned to world space and shaded with the\n"
     "  probe's radiance SH (irradiance; pictures at an automatic exposure). --skip-adjacent: the paper's\n"
     "  rule alone (faces around a vertex skipped) instead of also blocking the solid behind them at\n"
     "  creases. Reference: S x S stratified cosine-weighted\n"
     "  rays per vertex (--rays, default 32; 0: none) through a BVH, shaded with the same coefficients.\n"
     "  --coarse T: the paper's two-level hierarchy instead of every triangle: a coarse mesh of about T\n"
     "  triangles (quadric-error half-edge collapses, so its vertices are the mesh's and it animates with\n"
     "  it) plus the full mesh within K edges of each vertex (--ring, default 3).\n"
     "  --png: qibl | ray cast | error (|E - E_ref| / mean E_ref, 0..10 %), drawn by platform/soft's\n"
     "  integer z-buffer rasterizer, orthographic from azimuth / elevation --view (default 35,20);\n"
     "  several MESH files are frames of one animation (same triangles): an animated PNG (--tween N: N - 1\n"
     "  frames interpolated between key frames, the last back into the first). Prints ms per\n"
     "  frame on one core (thread CPU time of the hemi calls) and RESULT transfer.* lines.\n",
     qcli_cmd_transfer},
    {"bake", "bake a scene into a relightable panorama asset (ray-traced, SH-projected, 8-bit packed)",
     NULL, qcli_cmd_bake},
    {"merge", "combine the partial sums of bake shards into an asset",
     NULL, qcli_cmd_merge},
    {"check", "validate PNG/APNG, PFM, Radiance HDR, OpenEXR and qibl asset files",
     NULL, qcli_cmd_check},
    {"demo", "the main demo: bake the scene, relight it by the core, compare with ground truth",
     NULL, qcli_cmd_demo},
    {"relight", "relight an asset by suns, lamps, a light list or a whole probe into a PNG (core + soft framebuffer)",
     NULL, qcli_cmd_relight},
    {"view", "a live viewer: drag the sun or a lamp, scrub a baked light path, step probes, yaw, exposure, k (X11)",
     "usage: qibl view FILE [--sun X Y Z] [--probe P.hdr]... [--lamp-rgb C0] [--exposure E] [--truth PNG|DIR]\n"
     "                 [--gles] [--bench [--frames N] [--headless] [--record OUT.png [--turn]]]\n"
     "  A window (X11) showing the asset relit by the core through platform/soft (--gles: platform/gles2\n"
     "  on a headless EGL context, read back), with an overlay under the frame: scheme, light, k,\n"
     "  exposure, ms per frame, fps and, with --truth, the PSNR against a `qibl render` PNG of the same\n"
     "  size, or (a directory) against the one of its sun_X_Y_Z.png frames (`qibl render --sun X Y Z`;\n"
     "  at most 64) whose sun is nearest the dragged one, named with the angle between them. Schemes (s cycles; those the asset or options cannot show are skipped): SUN (drag\n"
     "  with the left button: a window width turns the sun once around, its height sweeps 180 degrees of\n"
     "  elevation), SH / LIGHTS (each --probe's SH or its median-cut lights, as relight --probe and\n"
     "  --probe-mode lights; p next probe, y / Y yaw -/+15 degrees), SUN+SH, LAMP (a point lamp: the\n"
     "  drag picks the P map under the pointer and hangs the lamp 1/10 of the way toward the viewpoint;\n"
     "  C0 --lamp-rgb, default relight --point's), PATH (a baked light path: t / T step 1/32, a drag\n"
     "  scrubs, P next path; sRGB at exposure 1). Keys: + / - exposure x2 / /2, k fewer SH terms\n"
     "  (cycles), l linear / sRGB, q or Escape quits. Every settled change prints `view: sun X Y Z | ...`\n"
     "  (with `| lamp X Y Z rgb R G B` or `| path N tq T`) on stdout: relight with those values gives\n"
     "  the same frame. --bench: --frames N (default 600) frames with the sun dragged 4 pixels a frame\n"
     "  (--turn: one turn over the frames), then `RESULT view.fps F` (--headless: no window, the\n"
     "  framebuffer and overlay only); --record OUT.png: those frames, overlay included, as an APNG.\n"
     "  The window needs a build with X11 (Debian: apt-get install libx11-dev).\n",
     qcli_cmd_view},
    {"info", "validate a qibl asset file and print its contents",
     NULL, qcli_cmd_info},
    {"srgbe", "encode/decode one sRGBE colour (signed shared-exponent RGB in 4 bytes)",
     NULL, qcli_cmd_srgbe},
    {"lights", "sample a .hdr light probe (lat-long, angular, ball, cube cross) into directional lights", NULL,
     qcli_cmd_lights},
    {"probe", "describe a light probe and advise how to light with it: SH, N lights, or sun plus SH", NULL,
     qcli_cmd_probe},
    {"ies", "an IES LM-63 photometric file: header facts, candela range, integrated lumens, polar curves",
     NULL, qcli_cmd_ies},
    {"study", "the light-probe approximation study: every method, error against N and time",
     NULL, qcli_cmd_study},
};
#define NCMD (sizeof commands / sizeof commands[0])

/* the flags `qibl` itself takes, in place of a command */
typedef struct global_opts {
    int help, version, isa_list;
} global_opts;
static const qcli_opt global_table[] = {
    {.name = "--help", .alias = "-h", .kind = QCLI_OPT_FLAG, .off = offsetof(global_opts, help),
     .help = "this list (qibl help CMD or qibl CMD --help: a command's options)"},
    {.name = "--version", .kind = QCLI_OPT_FLAG, .off = offsetof(global_opts, version),
     .help = "the version, the config id and the kernels this CPU runs"},
    {.name = "--isa-list", .kind = QCLI_OPT_FLAG, .off = offsetof(global_opts, isa_list),
     .help = "the kernel sets this CPU runs, one per line (QIBL_ISA takes one)"},
    {0},
};
/* name "": its refusals read "qibl: ...; see qibl --help" */
static const qcli_opt_cmd global_spec = {.name = "", .opts = global_table, .size = sizeof(global_opts)};

static void print_help(FILE *f)
{
    fprintf(f, "qibl - integer image-based lighting runtime: command-line tool\n\n"
               "usage: qibl <command> [args]\n       qibl help <command>\n       qibl --version\n       qibl --isa-list\n");
    qcli_opt_help_list(f, &global_spec);
    fprintf(f, "\ncommands:\n");
    for (size_t i = 0; i < NCMD; ++i)
        fprintf(f, "  %-8s %s\n", commands[i].name, commands[i].summary);
}

/* `qibl help CMD`: each option table's usage, options and prose, then the text not on a table */
static void print_cmd_help(FILE *f, const qcli_cmd *c)
{
    const qcli_opt_cmd *const *t = tables_of(c->name);
    for (size_t k = 0; t && t[k]; ++k) {
        if (k > 0)
            fputc('\n', f);
        qcli_opt_help(f, t[k]);
    }
    if (c->usage) {
        if (t)
            fputc('\n', f);
        fputs(c->usage, f);
    }
}

static const qcli_cmd *find(const char *name)
{
    for (size_t i = 0; i < NCMD; ++i)
        if (strcmp(commands[i].name, name) == 0)
            return &commands[i];
    return NULL;
}

int qcli_usage_error(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fputs("qibl: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    return 2;
}

int qcli_parse_q16(const char *s, int32_t *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end != '\0' || errno == ERANGE || !isfinite(v))
        return -1;
    double q = nearbyint(v * 65536.0);
    if (q > 2147483647.0 || q < -2147483648.0)
        return -1;
    *out = (int32_t)q;
    return 0;
}

int qcli_parse_int(const char *s, long lo, long hi, long *out)
{
    return qcli_opt_int_value(s, lo, hi, out);
}

int qcli_parse_num(const char *opt, const char *s, double lo, double hi, const char *why, double *out)
{
    switch (qcli_opt_num_value(s, lo, hi, out)) {
    case 0:
        return 0;
    case 1:
        return qcli_usage_error("%s: '%s' is not a number", opt, s);
    case 2:
        return qcli_usage_error("%s: '%s' is not a finite number", opt, s);
    default:
        return qcli_usage_error("%s: %s is outside %.10g..%.10g%s%s%s", opt, s, lo, hi, why ? " (" : "",
                                why ? why : "", why ? ")" : "");
    }
}

int qcli_parse_size(const char *opt, const char *s, long max, long *w, long *h)
{
    long wh[2];
    if (qcli_opt_size_value(s, max, wh) != 0)
        return qcli_usage_error("%s needs WxH with both in 1..%ld, got '%s'", opt, max, s);
    *w = wh[0], *h = wh[1];
    return 0;
}

int main(int argc, char **argv)
{
    /* line by line into a pipe or a log too: a farm or `make demo | tee` sees each step as it ends */
    setvbuf(stdout, NULL, _IOLBF, 0);
    /* qibl's own flags come alone, in place of a command: the table reads argv[1] only */
    global_opts g = {.help = 0};
    if (argc >= 2 && argv[1][0] == '-' && argv[1][1] != '\0' && qcli_opt_parse(&global_spec, 2, argv, 1, &g) != 0)
        return 2;
    if (argc < 2 || g.help) {
        print_help(stdout);
        return argc < 2 ? 2 : 0;
    }
    /* the kernel sets this CPU runs, one per line, lowest first (make golden and make test loop over them) */
    if (g.isa_list) {
        for (unsigned i = 0; i < QIBL_ISA_COUNT; ++i)
            if (qibl_isa_available() & QIBL_ISA_BIT(i))
                printf("%s\n", qibl_isa_name((qibl_isa_t)i));
        return 0;
    }
    /* QIBL_ISA names a kernel set this CPU runs, or nothing runs (io/isa_env.h) */
    char isa_err[160];
    if (qtool_isa_env_check(isa_err, sizeof isa_err) != 0) {
        fprintf(stderr, "qibl: %s\n", isa_err);
        return 2;
    }
    if (g.version) {
        char isa[160];
        qtool_isa_describe(isa, sizeof isa);
        printf("qibl %s (config id %08lx)\nkernels: %s\n", qibl_version(), (unsigned long)qibl_config_id(), isa);
        return qibl_init_check() == QIBL_OK ? 0 : 1;
    }
    if (strcmp(argv[1], "help") == 0) {
        if (argc == 2) {
            print_help(stdout);
            return 0;
        }
        /* --flags CMD: the tables and their flags, as qcli_opt_flags prints them (tests/cli_opts_test.c) */
        int flags = strcmp(argv[2], "--flags") == 0;
        if (flags && argc < 4)
            return qcli_usage_error("help --flags needs a command (see qibl --help)");
        const qcli_cmd *c = find(argv[2 + flags]);
        if (!c)
            return qcli_usage_error("no such command '%s' (see qibl --help)", argv[2 + flags]);
        const qcli_opt_cmd *const *t = tables_of(c->name);
        for (size_t k = 0; flags && t && t[k]; ++k)
            qcli_opt_flags(stdout, t[k]);
        if (!flags)
            print_cmd_help(stdout, c);
        return 0;
    }
    const qcli_cmd *c = find(argv[1]);
    if (!c)
        return qcli_usage_error("no such command '%s' (see qibl --help)", argv[1]);
    for (int i = 2; i < argc; ++i)
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            print_cmd_help(stdout, c);
            return 0;
        }
    return c->run(argc - 1, argv + 1);
}
