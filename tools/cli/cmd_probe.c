/*
 * cmd_probe.c - `qibl sh project PROBE.hdr`: a Radiance probe (any layout, resampled to lat-long)
 * projected onto SH by the integer core (qibl/probe.h), row by row, printed as a labelled table
 * (l, m, R, G, B), JSON or a C header in qibl's basis (--frame, --yaw/--rotate), or in an engine's
 * own convention with --preset filament|unity|gltf (tools/engine: cmgen's sh.txt, Unity's
 * SphericalHarmonicsL2 and ShadeSH9 constants, EXT_lights_image_based). The projection and the
 * writers are tools/engine/project.h's; this file parses the options and loads the probe.
 */
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/relight_light.h"
#include "engine/project.h"
#include "qibl/probe.h"

#define SH_PROJECT_USAGE                                                                                   \
    "usage: qibl sh project PROBE.hdr [--bands B] [--irradiance] [--window none|hann|lanczos] [--layout L] " \
    "[--format table|json|c] [--name ID] [--frame zup|yup] [--yaw DEG | --rotate a,b,c,d,e,f,g,h,i]\n" \
    "       qibl sh project PROBE.hdr --preset filament|unity|gltf|raw [--window auto|no|CUTOFF (filament)] " \
    "[--yaw DEG | --rotate ...] [--layout L] [--name ID (gltf)]"

enum { FMT_TABLE = 0, FMT_JSON, FMT_CMGEN, FMT_C };

static int c_ident(const char *s)
{
    if (!*s || !(isalpha((unsigned char)*s) || *s == '_'))
        return 0;
    for (; *s; ++s)
        if (!(isalnum((unsigned char)*s) || *s == '_'))
            return 0;
    return 1;
}

/* sh project's options into o, the probe's path and layout into *path, *layout; 0, or 2 after a
 * message. rl: only its --yaw / --rotate (relight's parser and rotation). */
static int sh_project_parse(int argc, char **argv, qtool_sh_project_opts *o, const char **path,
                            qtool_probe_layout_t *layout, qcli_light_list *rl)
{
    static const char *fnames[] = {"table", "json", "cmgen", "c"};
    const char *window_arg = NULL;
    int fmt = FMT_TABLE, fmt_given = 0, bands_given = 0, name_given = 0, frame_given = 0;
    long bands = o->bands;
    qtool_engine_preset preset = o->preset;
    qibl_probe_sh_opts_t opts = o->core;
    for (int i = 2; i < argc; ++i) {
        if (strcmp(argv[i], "--bands") == 0) {
            if (i + 1 >= argc || qcli_parse_int(argv[i + 1], 1, QIBL_SH_MAX_BANDS, &bands) != 0)
                return qcli_usage_error("--bands needs an integer in 1..%d", QIBL_SH_MAX_BANDS);
            ++i, bands_given = 1;
        } else if (strcmp(argv[i], "--irradiance") == 0) {
            opts.irradiance = 1;
        } else if (strcmp(argv[i], "--window") == 0) { /* read once --preset is known */
            if (i + 1 >= argc)
                return qcli_usage_error("--window needs none, hann or lanczos (--preset filament: auto, no or a "
                                        "cutoff)");
            window_arg = argv[++i];
        } else if (strcmp(argv[i], "--preset") == 0) {
            if (i + 1 >= argc || qtool_engine_preset_parse(argv[i + 1], &preset) != 0)
                return qcli_usage_error("--preset: '%s' is not filament, unity, gltf or raw",
                                        i + 1 < argc ? argv[i + 1] : "");
            ++i;
        } else if (strcmp(argv[i], "--frame") == 0) {
            if (i + 1 < argc && strcmp(argv[i + 1], "zup") == 0)
                o->frame = QTOOL_ENGINE_FRAME_ZUP;
            else if (i + 1 < argc && strcmp(argv[i + 1], "yup") == 0)
                o->frame = QTOOL_ENGINE_FRAME_YUP;
            else
                return qcli_usage_error("--frame: '%s' is not zup or yup", i + 1 < argc ? argv[i + 1] : "");
            ++i, frame_given = 1;
        } else if (strcmp(argv[i], "--yaw") == 0 || strcmp(argv[i], "--rotate") == 0) {
            int rc = qcli_light_list_opt(argc, argv, &i, rl);
            if (rc != 1)
                return rc == 2 ? 2 : qcli_usage_error("%s needs a value (degrees, or nine numbers a,...,i)", argv[i]);
        } else if (strcmp(argv[i], "--format") == 0) {
            fmt = -1;
            for (int j = 0; i + 1 < argc && j < 4; ++j)
                if (strcmp(argv[i + 1], fnames[j]) == 0)
                    fmt = j;
            if (fmt == FMT_CMGEN) /* it wrote qibl's radiance in cmgen's line layout, which Filament misreads */
                return qcli_usage_error("--format cmgen is gone: it was not what cmgen writes; --preset filament "
                                        "writes cmgen's sh.txt");
            if (fmt < 0)
                return qcli_usage_error("--format: '%s' is not table, json or c", i + 1 < argc ? argv[i + 1] : "");
            ++i, fmt_given = 1;
        } else if (strcmp(argv[i], "--layout") == 0) {
            if (i + 1 >= argc || qtool_probe_layout_parse(argv[i + 1], layout) != 0)
                return qcli_usage_error("--layout: '%s' is not auto, latlong, angular, ball, vcross or hcross",
                                        i + 1 < argc ? argv[i + 1] : "");
            ++i;
        } else if (strcmp(argv[i], "--name") == 0) {
            if (i + 1 >= argc || !c_ident(argv[i + 1]))
                return qcli_usage_error("--name: '%s' is not a C identifier", i + 1 < argc ? argv[i + 1] : "");
            o->name = argv[++i], name_given = 1;
        } else if (argv[i][0] == '-' || *path) {
            return qcli_usage_error("sh project: unexpected '%s' (%s)", argv[i], SH_PROJECT_USAGE);
        } else {
            *path = argv[i];
        }
    }
    if (!*path)
        return qcli_usage_error(SH_PROJECT_USAGE);
    const char *pn = qtool_engine_preset_name(preset);
    if (preset != QTOOL_ENGINE_RAW) { /* each engine has its own scale, frame and layout */
        if (fmt_given)
            return qcli_usage_error("--format is for --preset raw; the %s preset writes its own layout", pn);
        if (opts.irradiance)
            return qcli_usage_error("--irradiance: the %s preset has its own scale (see the README)", pn);
        if (frame_given)
            return qcli_usage_error("--frame: the %s preset writes the engine's own frame; --frame is for --preset raw",
                                    pn);
        if (bands_given && bands < 3)
            return qcli_usage_error("--bands %ld: the %s preset needs 3 bands", bands, pn);
        if (name_given && preset != QTOOL_ENGINE_GLTF)
            return qcli_usage_error("--name names the C array (--format c) or the glTF light, not the %s preset", pn);
        if (window_arg && preset != QTOOL_ENGINE_FILAMENT)
            return qcli_usage_error("--window: the %s preset is not windowed (--window is cmgen's for filament)", pn);
        if (window_arg && qtool_engine_window_parse(window_arg, &o->engine_window) != 0)
            return qcli_usage_error("--window: '%s' is not auto, no or a cutoff band in (0, %g] (cmgen's --sh-window)",
                                    window_arg, QTOOL_ENGINE_WINDOW_MAX);
        bands = 3;
        fmt = FMT_JSON; /* notes on stderr: stdout is only the engine's text */
        if (!name_given)
            o->name = NULL; /* gltf: an unnamed light */
    } else if (window_arg) {
        int k = -1;
        for (int j = 0; j < 3; ++j)
            if (strcmp(window_arg, qtool_sh_window_names[j]) == 0)
                k = j;
        if (k < 0)
            return qcli_usage_error("--window needs none, hann or lanczos");
        opts.window = (qibl_probe_window_t)k;
    }
    o->bands = bands, o->preset = preset, o->core = opts;
    o->format = fmt == FMT_JSON ? QTOOL_SH_FORMAT_JSON : fmt == FMT_C ? QTOOL_SH_FORMAT_C : QTOOL_SH_FORMAT_TABLE;
    return 0;
}

int qcli_cmd_sh_project(int argc, char **argv)
{
    qtool_sh_project_opts o = QTOOL_SH_PROJECT_OPTS_DEFAULT;
    const char *path = NULL;
    qtool_probe_layout_t layout = QTOOL_PROBE_LAYOUT_AUTO;
    qcli_light_list rl;
    qcli_light_list_init(&rl);
    if (sh_project_parse(argc, argv, &o, &path, &layout, &rl) != 0)
        return 2;
    if (qcli_parse_only) /* fuzz_cliopts: the options only */
        return 0;
    o.rot = rl.rotate ? (const double(*)[3])rl.r : NULL, o.rot_kind = rl.rotate;
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
