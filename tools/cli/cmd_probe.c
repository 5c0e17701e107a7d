/*
 * cmd_probe.c - `qibl sh project PROBE.hdr`: a Radiance probe (any layout, resampled to lat-long)
 * projected onto SH by the integer core (qibl/probe.h), row by row, printed as a labelled table
 * (l, m, R, G, B), JSON or a C header in qibl's basis (--frame, --yaw/--rotate), or in an engine's
 * own convention with --preset filament|unity|gltf (tools/engine: cmgen's sh.txt, Unity's
 * SphericalHarmonicsL2 and ShadeSH9 constants, EXT_lights_image_based). The projection and the
 * writers are tools/engine/project.h's; this file parses the options (its option table, opt/opt.h)
 * and loads the probe.
 */
#include <ctype.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "opt/opt.h"
#include "cli/relight_light.h"
#include "engine/project.h"
#include "qibl/probe.h"

enum { FMT_TABLE = 0, FMT_JSON, FMT_CMGEN, FMT_C };

typedef struct sh_project_cli {
    qtool_opt_list probe;
    long bands;         /* 0: not given (5, a preset 3) */
    int irradiance;
    const char *window; /* read once --preset is known */
    int preset;         /* qtool_engine_preset */
    int frame;          /* qtool_engine_frame; -1: not given */
    int format;         /* FMT_*; -1: not given */
    const char *name;   /* NULL: not given */
    int layout;         /* qtool_probe_layout_t */
    qcli_turn turn;     /* --yaw / --rotate (relight's rotation) */
    qtool_sh_project_opts o; /* the options together (sh_project_check) */
} sh_project_cli;
static const sh_project_cli sh_project_defaults = {.bands = 0, .preset = QTOOL_ENGINE_RAW, .frame = -1, .format = -1,
                                                   .name = NULL, .layout = QTOOL_PROBE_LAYOUT_AUTO,
                                                   .turn = QCLI_TURN_DEFAULT,
                                                   .o = QTOOL_SH_PROJECT_OPTS_DEFAULT};

static const char *const frames[] = {"zup", "yup", NULL}; /* qtool_engine_frame */

static int c_ident(const char *s)
{
    if (!*s || !(isalpha((unsigned char)*s) || *s == '_'))
        return 0;
    for (; *s; ++s)
        if (!(isalnum((unsigned char)*s) || *s == '_'))
            return 0;
    return 1;
}

static const char *format_call(void *opts, const char *v)
{
    static const char *const fnames[] = {"table", "json", "cmgen", "c"};
    int fmt = -1;
    for (int j = 0; j < 4; ++j)
        if (strcmp(v, fnames[j]) == 0)
            fmt = j;
    if (fmt == FMT_CMGEN) /* it wrote qibl's radiance in cmgen's line layout, which Filament misreads */
        return "is gone: it was not what cmgen writes; --preset filament writes cmgen's sh.txt";
    if (fmt < 0)
        return "is not table, json or c";
    ((sh_project_cli *)opts)->format = fmt;
    return NULL;
}

static const char *name_call(void *opts, const char *v)
{
    if (!c_ident(v))
        return "is not a C identifier";
    ((sh_project_cli *)opts)->name = v;
    return NULL;
}

static const qtool_opt sh_project_table[] = {
    {.name = "--bands", .kind = QTOOL_OPT_INT, .off = offsetof(sh_project_cli, bands), .arg = "B", .lo = 1,
     .hi = QIBL_SH_MAX_BANDS, .def = "5; a preset 3", .help = "bands 0..B-1 (B*B coefficients)"},
    {.name = "--irradiance", .kind = QTOOL_OPT_FLAG, .off = offsetof(sh_project_cli, irradiance),
     .help = "irradiance (times the clamped-cosine A_l) instead of radiance (--preset raw)"},
    {.name = "--window", .kind = QTOOL_OPT_STR, .off = offsetof(sh_project_cli, window), .arg = "W",
     .def = "none; filament auto", .help = "none, hann or lanczos; --preset filament: auto, no or a cutoff band"},
    {.name = "--preset", .kind = QTOOL_OPT_ENUM, .off = offsetof(sh_project_cli, preset),
     .names = qtool_engine_preset_names, .help = "an engine's own convention (below)"},
    {.name = "--format", .kind = QTOOL_OPT_CALL, .off = offsetof(sh_project_cli, format), .arg = "table|json|c",
     .call = format_call, .def = "table", .help = "--preset raw's output: a table, JSON or a C header"},
    {.name = "--name", .kind = QTOOL_OPT_CALL, .off = offsetof(sh_project_cli, name), .arg = "ID", .call = name_call,
     .def = "qibl_probe_sh", .help = "the C array (--format c) or the glTF light (--preset gltf)"},
    {.name = "--frame", .kind = QTOOL_OPT_ENUM, .off = offsetof(sh_project_cli, frame), .names = frames,
     .def = "zup", .help = "yup: the coefficients in a y-up frame ((x, z, -y) of qibl's; --preset raw)"},
    QCLI_TURN_OPTS(sh_project_cli, turn, "turn the probe first (positive turns +x toward +y), as qibl relight does",
                   "turn the probe first by a rotation matrix (rows), as qibl relight does"),
    QCLI_LAYOUT_OPT(sh_project_cli, layout),
    {0},
};

static const qtool_opt_cmd sh_project_spec = {
    QTOOL_OPT_CMD("sh project", sh_project_table, sh_project_defaults, "PROBE.hdr", 1, 1, sh_project_cli, probe),
    .prose =
        "  A Radiance probe (layout detected or --layout, resampled to lat-long as qibl lights does)\n"
        "  projected onto bands 0..B-1 by the integer core, row by row (qibl/probe.h): radiance\n"
        "  coefficients, or irradiance (times the clamped-cosine A_l), with an optional Hann or Lanczos\n"
        "  window. --format table (default: l, m, R, G, B), json, or c (a header: ID_BANDS and\n"
        "  `static const float ID[B*B][3]` with a band/order comment per row; --name ID, default\n"
        "  qibl_probe_sh). --frame yup writes them in a y-up frame ((x, z, -y) of qibl's); --yaw DEG\n"
        "  (positive turns +x toward +y) or --rotate turns the probe first, as qibl relight does.\n"
        "  --preset writes an engine's own convention (tools/engine/engine.h has each formula); it\n"
        "  takes --window (filament), --yaw/--rotate, --layout and --name (gltf), not --format,\n"
        "  --irradiance or --frame:\n"
        "    filament  cmgen's sh.txt (--deploy): 3 bands of irradiance times A_l, windowed (--window\n"
        "              auto (default), no or a cutoff band, as cmgen's --sh-window), times Sloan's\n"
        "              constants / pi, y up mirrored in x as cmgen's cubemap; paste into sh.txt.\n"
        "    unity     C#: SphericalHarmonicsL2 (Unity's scale and frame) and the unity_SHAr..SHC\n"
        "              constants ShadeSH9 reads; prints the SH9 truncation error against the probe.\n"
        "    gltf      an EXT_lights_image_based JSON object (irradianceCoefficients, y up).\n"
        "    raw       the table, as without --preset.\n"
        "  The layout note goes to stderr except for the table. (--format cmgen is refused: it was not\n"
        "  what cmgen writes; use --preset filament.)\n",
};

/* the options together into c->o, once the table has parsed them: 0, or 2 after the one line */
static int sh_project_check(void *cli)
{
    const sh_project_cli *c = cli;
    qtool_sh_project_opts *o = &((sh_project_cli *)cli)->o;
    const qtool_opt_cmd *t = &sh_project_spec;
    const qtool_engine_preset preset = (qtool_engine_preset)c->preset;
    const char *pn = qtool_engine_preset_name(preset);
    long bands = c->bands ? c->bands : o->bands;
    int fmt = c->format >= 0 ? c->format : FMT_TABLE;
    qibl_probe_sh_opts_t opts = o->core;
    opts.irradiance = c->irradiance;
    if (c->frame >= 0)
        o->frame = (qtool_engine_frame)c->frame;
    if (c->name)
        o->name = c->name;
    if (preset != QTOOL_ENGINE_RAW) { /* each engine has its own scale, frame and layout */
        if (c->format >= 0)
            return qtool_opt_error(t, "--format is for --preset raw; the %s preset writes its own layout", pn);
        if (opts.irradiance)
            return qtool_opt_error(t, "--irradiance: the %s preset has its own scale (see the README)", pn);
        if (c->frame >= 0)
            return qtool_opt_error(t, "--frame: the %s preset writes the engine's own frame; --frame is for --preset raw",
                                  pn);
        if (c->bands && bands < 3)
            return qtool_opt_error(t, "--bands %ld: the %s preset needs 3 bands", bands, pn);
        if (c->name && preset != QTOOL_ENGINE_GLTF)
            return qtool_opt_error(t, "--name names the C array (--format c) or the glTF light, not the %s preset", pn);
        if (c->window && preset != QTOOL_ENGINE_FILAMENT)
            return qtool_opt_error(t, "--window: the %s preset is not windowed (--window is cmgen's for filament)", pn);
        if (c->window && qtool_engine_window_parse(c->window, &o->engine_window) != 0)
            return qtool_opt_error(t, "--window: '%s' is not auto, no or a cutoff band in (0, %g] (cmgen's --sh-window)",
                                  c->window, QTOOL_ENGINE_WINDOW_MAX);
        bands = 3;
        fmt = FMT_JSON; /* notes on stderr: stdout is only the engine's text */
        if (!c->name)
            o->name = NULL; /* gltf: an unnamed light */
    } else if (c->window) {
        int k = -1;
        for (int j = 0; j < 3; ++j)
            if (strcmp(c->window, qtool_sh_window_names[j]) == 0)
                k = j;
        if (k < 0)
            return qtool_opt_error(t, "--window: '%s' is not none, hann or lanczos", c->window);
        opts.window = (qibl_probe_window_t)k;
    }
    o->bands = bands, o->preset = preset, o->core = opts;
    o->format = fmt == FMT_JSON ? QTOOL_SH_FORMAT_JSON : fmt == FMT_C ? QTOOL_SH_FORMAT_C : QTOOL_SH_FORMAT_TABLE;
    return 0;
}

static int sh_project_run(void *opts)
{
    sh_project_cli *c = opts;
    qtool_sh_project_opts o = c->o;
    const qcli_light_list *turn = &c->turn.ll;
    o.rot = turn->rotate ? (const double(*)[3])turn->r : NULL, o.rot_kind = turn->rotate;
    const char *path = c->probe.v[0];
    const qtool_probe_layout_t layout = (qtool_probe_layout_t)c->layout;
    int w, h;
    uint8_t *px;
    qtool_probe_layout_t used;
    /* the layout note: on stdout as a comment for the table, on stderr otherwise (stdout stays parseable);
     * printed only once the projection has succeeded, so a failure leaves stdout empty */
    char note[4200 + 256], err[4800];
    if (qcli_probe_load_note(path, layout, note, sizeof note, &w, &h, &px, &used) != 0)
        return 1;
    int rc = qtool_sh_project(&o, path, px, w, h, used, note, stdout, stderr, err, sizeof err);
    free(px);
    if (rc != 0)
        fprintf(stderr, "qibl: %s\n", err);
    return rc != 0;
}

const qcli_sub qcli_sub_sh_project = {.opts = &sh_project_spec, .check = sh_project_check, .run = sh_project_run};
