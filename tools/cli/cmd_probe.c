/*
 * cmd_probe.c - `qibl sh project PROBE.hdr`: a Radiance probe (any layout, resampled to lat-long)
 * projected onto SH by the integer core (qibl/probe.h), row by row, printed as a labelled table
 * (l, m, R, G, B), JSON or a C header in qibl's basis (--frame, --yaw/--rotate), or in an engine's
 * own convention with --preset filament|unity|gltf (tools/engine: cmgen's sh.txt, Unity's
 * SphericalHarmonicsL2 and ShadeSH9 constants, EXT_lights_image_based).
 */
#include <ctype.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/relight_light.h"
#include "engine/engine.h"
#include "qibl/probe.h"

#define SH_PROJECT_USAGE                                                                                   \
    "usage: qibl sh project PROBE.hdr [--bands B] [--irradiance] [--window none|hann|lanczos] [--layout L] " \
    "[--format table|json|c] [--name ID] [--frame zup|yup] [--yaw DEG | --rotate a,b,c,d,e,f,g,h,i]\n" \
    "       qibl sh project PROBE.hdr --preset filament|unity|gltf|raw [--window auto|no|CUTOFF (filament)] " \
    "[--yaw DEG | --rotate ...] [--layout L] [--name ID (gltf)]"

enum { FMT_TABLE = 0, FMT_JSON, FMT_CMGEN, FMT_C };

/* s as a JSON string body (quotes and backslashes escaped, control bytes as \u00XX) */
static void json_str(const char *s)
{
    for (; *s; ++s) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\')
            printf("\\%c", c);
        else if (c < 0x20)
            printf("\\u%04x", c);
        else
            putchar(c);
    }
}

/* a float literal C accepts: %.9g, with ".0" when it would read as an integer */
static void c_float(double v)
{
    char b[64];
    if ((float)v == 0) /* below float range: the caller noted it */
        v = 0;
    snprintf(b, sizeof b, "%.9g", v);
    printf("%s%sf", b, strpbrk(b, ".e") ? "" : ".0");
}

/* s inside a C comment: a "*" followed by "/" is split so the comment cannot end early */
static void c_comment_str(const char *s)
{
    for (; *s; ++s) {
        putchar(*s);
        if (*s == '*' && s[1] == '/')
            putchar(' ');
    }
}

static int c_ident(const char *s)
{
    if (!*s || !(isalpha((unsigned char)*s) || *s == '_'))
        return 0;
    for (; *s; ++s)
        if (!(isalnum((unsigned char)*s) || *s == '_'))
            return 0;
    return 1;
}

/* An engine preset (tools/engine) from radiance coefficients c, rotated by r (NULL: none); px the
 * probe (for Unity's SH9 error). 0, or 1 after a message. */
static int preset_out(qtool_engine_preset preset, const char *path, const qibl_probe_coeffs_t *c, const double r[3][3],
                      double window, const char *name, const uint8_t *px, int w, int h)
{
    char err[256];
    qtool_engine_sh e;
    if (qtool_engine_sh_from_core(c, r, &e, err, sizeof err) != 0)
        return fprintf(stderr, "qibl: sh project: %s: %s\n", path, err), 1;
    if (preset == QTOOL_ENGINE_FILAMENT) {
        double out[9][3], cut;
        if (qtool_engine_filament(&e, window, out, &cut, err, sizeof err) != 0)
            return fprintf(stderr, "qibl: sh project: %s: %s\n", path, err), 1;
        if (cut < 0)
            fprintf(stderr, "%s: cmgen's sh.txt (--deploy): irradiance, no window, pre-scaled, y up mirrored in x\n",
                    path);
        else
            fprintf(stderr, "%s: cmgen's sh.txt (--deploy): irradiance, window cutoff %.9g (%s), pre-scaled, y up "
                            "mirrored in x\n", path, cut, window == QTOOL_ENGINE_WINDOW_AUTO ? "auto" : "--window");
        qtool_engine_filament_write(stdout, (const double(*)[3])out);
        return 0;
    }
    if (preset == QTOOL_ENGINE_UNITY) {
        double sh[3][9], packed[7][4], me, mx;
        if (qtool_engine_unity(&e, sh, packed, err, sizeof err) != 0 ||
            qtool_engine_sh9_error(&e, px, w, h, r, &me, &mx, err, sizeof err) != 0)
            return fprintf(stderr, "qibl: sh project: %s: %s\n", path, err), 1;
        printf("// ");
        c_comment_str(path);
        printf(": Unity's SphericalHarmonicsL2 (y up, left-handed; the panoramic skybox's placement), made by `qibl "
               "sh project --preset unity`\n// SH9 truncation error against the probe's irradiance over 1024 normals "
               "(of the mean irradiance): mean %.3f%%, max %.3f%%\n", 100 * me, 100 * mx);
        qtool_engine_unity_write(stdout, (const double(*)[9])sh, (const double(*)[4])packed);
        return 0;
    }
    double coef[9][3];
    if (qtool_engine_gltf(&e, coef, err, sizeof err) != 0)
        return fprintf(stderr, "qibl: sh project: %s: %s\n", path, err), 1;
    qtool_engine_gltf_write(stdout, name, (const double(*)[3])coef);
    return 0;
}

int qcli_cmd_sh_project(int argc, char **argv)
{
    const char *path = NULL, *name = "qibl_probe_sh";
    long bands = QIBL_SH_MAX_BANDS;
    int fmt = FMT_TABLE;
    qtool_probe_layout_t layout = QTOOL_PROBE_LAYOUT_AUTO;
    qibl_probe_sh_opts_t opts = {0, QIBL_PROBE_WINDOW_NONE, 0};
    static const char *wnames[] = {"none", "hann", "lanczos"};
    static const char *fnames[] = {"table", "json", "cmgen", "c"};
    qtool_engine_preset preset = QTOOL_ENGINE_RAW;
    qtool_engine_frame frame = QTOOL_ENGINE_FRAME_ZUP;
    const char *window_arg = NULL;
    int fmt_given = 0, bands_given = 0, name_given = 0, frame_given = 0;
    double ewindow = QTOOL_ENGINE_WINDOW_AUTO;
    qcli_light_list rl; /* only its --yaw / --rotate: relight's parser and rotation */
    qcli_light_list_init(&rl);
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
                frame = QTOOL_ENGINE_FRAME_ZUP;
            else if (i + 1 < argc && strcmp(argv[i + 1], "yup") == 0)
                frame = QTOOL_ENGINE_FRAME_YUP;
            else
                return qcli_usage_error("--frame: '%s' is not zup or yup", i + 1 < argc ? argv[i + 1] : "");
            ++i, frame_given = 1;
        } else if (strcmp(argv[i], "--yaw") == 0 || strcmp(argv[i], "--rotate") == 0) {
            int rc = qcli_light_list_opt(argc, argv, &i, &rl);
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
            if (i + 1 >= argc || qtool_probe_layout_parse(argv[i + 1], &layout) != 0)
                return qcli_usage_error("--layout: '%s' is not auto, latlong, angular, ball, vcross or hcross",
                                        i + 1 < argc ? argv[i + 1] : "");
            ++i;
        } else if (strcmp(argv[i], "--name") == 0) {
            if (i + 1 >= argc || !c_ident(argv[i + 1]))
                return qcli_usage_error("--name: '%s' is not a C identifier", i + 1 < argc ? argv[i + 1] : "");
            name = argv[++i], name_given = 1;
        } else if (argv[i][0] == '-' || path) {
            return qcli_usage_error("sh project: unexpected '%s' (%s)", argv[i], SH_PROJECT_USAGE);
        } else {
            path = argv[i];
        }
    }
    if (!path)
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
        if (window_arg && qtool_engine_window_parse(window_arg, &ewindow) != 0)
            return qcli_usage_error("--window: '%s' is not auto, no or a cutoff band in (0, %g] (cmgen's --sh-window)",
                                    window_arg, QTOOL_ENGINE_WINDOW_MAX);
        bands = 3;
        fmt = FMT_JSON; /* notes on stderr: stdout is only the engine's text */
    } else if (window_arg) {
        int k = -1;
        for (int j = 0; j < 3; ++j)
            if (strcmp(window_arg, wnames[j]) == 0)
                k = j;
        if (k < 0)
            return qcli_usage_error("--window needs none, hann or lanczos");
        opts.window = (qibl_probe_window_t)k;
    }
    if (qcli_parse_only) /* fuzz_cliopts: the options only */
        return 0;
    int w, h;
    uint8_t *px;
    qtool_probe_layout_t used;
    /* the layout note: on stdout as a comment for the table, on stderr otherwise (stdout stays parseable);
     * printed only once the projection has succeeded, so a failure leaves stdout empty */
    char note[4200 + 256];
    if (qcli_probe_load_note(path, layout, note, sizeof note, &w, &h, &px, &used) != 0)
        return 1;
    size_t n = qibl_probe_sh_workspace_size((uint32_t)w, (uint32_t)h);
    void *ws = n ? malloc(n) : NULL;
    if (!ws) {
        free(px);
        return fprintf(stderr, "qibl: sh project: %s: %dx%d is beyond the probe limits or out of memory\n", path, w,
                       h), 1;
    }
    qibl_probe_sh_t ps;
    qibl_probe_coeffs_t c;
    qibl_status_t st = qibl_probe_sh_begin(&ps, (uint32_t)w, (uint32_t)h, QIBL_LIGHTPROBE_RGBE, 0, (int)bands, ws, n);
    for (int v = 0; v < h && st == QIBL_OK; ++v)
        st = qibl_probe_sh_add_row(&ps, (uint32_t)v, px + 4 * (size_t)w * (size_t)v);
    if (st == QIBL_OK)
        st = qibl_probe_sh_finish(&ps, &opts, &c);
    free(ws);
    if (st != QIBL_OK) {
        free(px);
        return fprintf(stderr, "qibl: sh project: %s: %s\n", path, qibl_status_str(st)), 1;
    }
    if (preset != QTOOL_ENGINE_RAW) { /* presets print only the engine's text on stdout */
        fputs(note, stderr);
        int rc = preset_out(preset, path, &c, rl.rotate ? (const double(*)[3])rl.r : NULL, ewindow, name_given ? name : NULL,
                            px, w, h);
        free(px);
        return rc;
    }
    free(px);
    /* raw: qibl's basis, rotated (--yaw, --rotate) and turned to y up (--frame yup) when asked */
    qtool_engine_sh e;
    char eerr[256];
    double fm[3][3];
    qtool_engine_frame_matrix(QTOOL_ENGINE_RAW, frame, fm);
    if (qtool_engine_sh_from_core(&c, rl.rotate ? (const double(*)[3])rl.r : NULL, &e, eerr, sizeof eerr) != 0 ||
        (frame == QTOOL_ENGINE_FRAME_YUP && qtool_engine_sh_remap(&e, (const double(*)[3])fm, &e, eerr, sizeof eerr) != 0))
        return fprintf(stderr, "qibl: sh project: %s: %s\n", path, eerr), 1;
    if (fmt == FMT_TABLE)
        printf("# %s", note);
    else
        fputs(note, stderr);
    const char *fr = frame == QTOOL_ENGINE_FRAME_YUP ? "y up: (x, z, -y) of qibl's" : "z up";
    const char *kind = opts.irradiance ? "irradiance (clamped cosine, A_l)" : "radiance";
    const char *rot = rl.rotate == 1 ? ", turned by --yaw" : rl.rotate == 2 ? ", turned by --rotate" : "";
    if (fmt == FMT_JSON) {
        printf("{\"probe\": \"");
        json_str(path);
        printf("\", \"layout\": \"%s\", \"width\": %d, \"height\": %d, \"bands\": %ld, \"irradiance\": %s, "
               "\"window\": \"%s\",\n \"basis\": \"qibl/sh.h: real SH, index l*l+l+m, %s%s, lat-long phi from +x "
               "toward +y\",\n \"coefficients\": [",
               qtool_probe_layout_name(used), w, h, bands, opts.irradiance ? "true" : "false", wnames[opts.window], fr,
               rot);
        for (int l = 0; l < (int)bands; ++l)
            for (int m = -l; m <= l; ++m) {
                int i = l * l + l + m;
                printf("%s\n  {\"l\": %d, \"m\": %d, \"rgb\": [%.9g, %.9g, %.9g]}", i ? "," : "", l, m,
                       e.c[i][0], e.c[i][1], e.c[i][2]);
            }
        printf("\n]}\n");
        return 0;
    }
    if (fmt == FMT_C) {
        /* a float literal beyond FLT_MAX is inf (or a compile error): refused before anything is
         * printed; one below half the smallest subnormal is written as 0 with a note */
        static const char rgbn[3] = {'R', 'G', 'B'};
        int tiny = 0;
        for (int i = 0; i < (int)(bands * bands); ++i)
            for (int ch = 0; ch < 3; ++ch) {
                double v = ldexp(c.c[ch][i], c.exp);
                if (isinf((float)v)) {
                    int l = 0;
                    while ((l + 1) * (l + 1) <= i)
                        ++l;
                    return fprintf(stderr, "qibl: sh project: %s: coefficient [%d] (l = %d, m = %+d) %c is %.9g, beyond "
                                   "float range (FLT_MAX %.9g): --format c cannot write it (--format json or table "
                                   "can)\n", path, i, l, i - l * l - l, rgbn[ch], v, (double)FLT_MAX), 1;
                }
                tiny += v != 0 && (float)v == 0;
            }
        if (tiny)
            fprintf(stderr, "qibl: sh project: note: %d coefficient%s below float range (under %.3g) written as 0\n",
                    tiny, tiny > 1 ? "s" : "", ldexp(1, -150));
        printf("/* ");
        c_comment_str(path);
        printf(": %dx%d, layout %s, bands %ld, %s, window %s.\n * Made by `qibl sh project --format c`; "
               "basis of qibl/sh.h (real SH, %s%s), index l*l + l + m. */\n",
               w, h, qtool_probe_layout_name(used), bands, kind, wnames[opts.window], fr, rot);
        printf("#define %s_BANDS %ld\nstatic const float %s[%ld][3] = {\n", name, bands, name, bands * bands);
        for (int l = 0; l < (int)bands; ++l)
            for (int m = -l; m <= l; ++m) {
                int i = l * l + l + m;
                printf("    {");
                for (int ch = 0; ch < 3; ++ch) {
                    c_float(e.c[i][ch]);
                    printf("%s", ch < 2 ? ", " : "");
                }
                printf("}, /* [%d] l = %d, m = %+d */\n", i, l, m);
            }
        printf("};\n");
        return 0;
    }
    printf("# %s: %dx%d lat-long, bands %ld, %s, window %s (qibl/sh.h basis, Wong et al.'s convention, %s%s)\n",
           path, w, h, bands, kind, wnames[opts.window], fr, rot);
    printf("# %2s %3s %16s %16s %16s\n", "l", "m", "R", "G", "B");
    for (int l = 0; l < (int)bands; ++l)
        for (int m = -l; m <= l; ++m) {
            int i = l * l + l + m;
            printf("  %2d %3d %16.9g %16.9g %16.9g\n", l, m, e.c[i][0], e.c[i][1],
                   e.c[i][2]);
        }
    return 0;
}
