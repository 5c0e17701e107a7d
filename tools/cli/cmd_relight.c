/*
 * cmd_relight.c - `qibl relight` (asset + light -> PNG through the core kernels and the software
 * framebuffer): the options parsed by its option table (opt/opt.h; the light options' callbacks
 * are light_opts.c's), tools/relight called, its results written and printed.
 * `qibl gen` lives in cmd_gen.c.
 */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/bake.h"
#include "bake/probesun.h"
#include "gen/scene.h"
#include "io/asset_write.h"
#include "io/exr.h"
#include "io/hdr_write.h"
#include "io/ies.h"
#include "io/pfm.h"
#include "io/png.h"
#include "qibl/asset.h"
#include "cli/cli.h"
#include "opt/opt.h"
#include "cli/relight_light.h"
#include "qibl/gonio.h"
#include "qibl/shmap.h"
#include "qibl/soft.h"
#include "relight/gles.h"
#include "relight/relight.h"
#include "qtool.h"

/* ---- qibl relight ------------------------------------------------------------------------------ */

/* What `qibl relight --path` was asked besides (relight/relight.h: qtool_relight_path). */
typedef struct path_cli {
    const char *spec;
    double t, rgb[3], sky[3], soft; /* t, soft < 0 and sky[0] < 0: not given */
    int have_sky;
} path_cli;

/* What `qibl relight` was asked: the files, and the library's options (defaults in relight/relight.h). */
typedef struct relight_cli {
    qtool_opt_list file;
    const char *png, *hdr, *pfm, *exr;
    int have_frame; /* --aim or --up given */
    qtool_relight_opts r;
    double exposure; /* r.exposure once parsed */
    int nearest;     /* --nearest (its note and mode come from its call) */
    int path_mode;   /* --path somewhere on the line: --rgb colours the path's light */
    path_cli p;
    const char *notes[4]; /* deprecation notes, printed once the line is accepted */
    int nnotes;
    char why[256];        /* a reason with numbers in it, for the table's line */
    qcli_turn turn;       /* --yaw / --rotate, into r.lights once the line has parsed */
} relight_cli;

void qcli_warn_dark(const char *path, const uint8_t *rgb, size_t np)
{
    double mean = qtool_relight_mean8(rgb, np);
    if (mean < QTOOL_CLI_DARK_MEAN)
        fprintf(stderr, "qibl: note: %s is almost black (mean %.1f of 255): try a larger --rgb or --exposure\n", path,
                mean);
}

/* ---- the option table (opt/opt.h): the order of --sun, --point and --rgb is the light list's ---- */

#define C(opts) ((relight_cli *)(opts))

static void note(relight_cli *c, const char *text)
{
    if (c->nnotes < (int)(sizeof c->notes / sizeof c->notes[0]))
        c->notes[c->nnotes++] = text;
}

static const char *sun_call(void *o, char *const *v, int n, int *used)
{
    (void)n, (void)used;
    return qtool_relight_spec_source(&C(o)->r.lights, 0, v, C(o)->why, sizeof C(o)->why);
}

static const char *point_call(void *o, char *const *v, int n, int *used)
{
    (void)n, (void)used;
    return qtool_relight_spec_source(&C(o)->r.lights, 1, v, C(o)->why, sizeof C(o)->why);
}

/* --rgb colours the light before it (or, first, the first), or with --path the path's light */
static const char *rgb_call(void *o, char *const *v, int n, int *used)
{
    (void)n, (void)used;
    relight_cli *c = o;
    if (!c->path_mode)
        return qtool_relight_spec_rgb(&c->r.lights, v, c->why, sizeof c->why);
    double d[3];
    for (int k = 0; k < 3; ++k) {
        int r = qtool_opt_num_value(v[k], 0, 32767, &d[k]);
        if (r == 1 || r == 2)
            snprintf(c->why, sizeof c->why, "'%s' is not a %snumber", v[k], r == 2 ? "finite " : "");
        else if (r != 0)
            snprintf(c->why, sizeof c->why, "%s is outside 0..32767 (a colour component in 0..32767)", v[k]);
        if (r != 0)
            return c->why;
    }
    memcpy(c->p.rgb, d, sizeof d);
    return NULL;
}

static const char *lights_call(void *o, const char *v)
{
    return qtool_relight_spec_csv(&C(o)->r.lights, v, C(o)->why, sizeof C(o)->why);
}

static const char *probe_call(void *o, const char *v)
{
    return qtool_relight_spec_probe(&C(o)->r.lights, v, C(o)->why, sizeof C(o)->why);
}

static const char *layout_call(void *o, const char *v)
{
    return qtool_relight_spec_layout(&C(o)->r.lights, v);
}

static const char *mode_call(void *o, const char *v)
{
    return qtool_relight_spec_mode(&C(o)->r.lights, v);
}

static const char *count_call(void *o, const char *v)
{
    return qtool_relight_spec_count(&C(o)->r.lights, v);
}

/* --lut MODE; a bare --lut (the old on/off switch) is bilinear: the next word is then an option or
 * the asset, never a mode name, so the two spellings cannot be confused */
static const char *lut_call(void *o, const char *m)
{
    relight_cli *c = o;
    if (!m) {
        c->r.point_mode = QTOOL_RELIGHT_POINT_BILINEAR;
        note(c, "a bare --lut is deprecated; say --lut bilinear");
        return NULL;
    }
    if (strcmp(m, "nearest") == 0 || strcmp(m, "bilinear") == 0 || strcmp(m, "off") == 0 || strcmp(m, "poly") == 0) {
        c->r.point_mode = m[0] == 'n'   ? QTOOL_RELIGHT_POINT_NEAREST
                          : m[0] == 'b' ? QTOOL_RELIGHT_POINT_BILINEAR
                          : m[0] == 'p' ? QTOOL_RELIGHT_POINT_POLY
                                        : QTOOL_RELIGHT_POINT_DIRECT;
        return NULL;
    }
    if (m[0] != '-' && m[0] != '\0' && c->file.n > 0)
        return "is not a mode (poly, nearest, bilinear or off)";
    return qtool_opt_no_value; /* the asset or an option: a bare --lut */
}

static const char *nearest_call(void *o, const char *unused)
{
    (void)unused;
    C(o)->r.point_mode = QTOOL_RELIGHT_POINT_NEAREST;
    note(C(o), "--nearest is deprecated; say --lut nearest");
    return NULL;
}

/* --aim X Y Z, --up X Y Z: the IES lamp's frame, Q16.16 */
static const char *frame_call(relight_cli *c, int32_t *q, char *const *v)
{
    const char *bad = qcli_parse_q16_dir(v, -1, "the zero vector has no direction", q, c->why, sizeof c->why);
    if (!bad)
        c->have_frame = 1;
    return bad;
}

static const char *aim_call(void *o, char *const *v, int n, int *used)
{
    (void)n, (void)used;
    return frame_call(o, C(o)->r.aim, v);
}

static const char *up_call(void *o, char *const *v, int n, int *used)
{
    (void)n, (void)used;
    return frame_call(o, C(o)->r.up, v);
}

static const relight_cli relight_defaults = {.r = QTOOL_RELIGHT_OPTS_DEFAULT, .exposure = 1.0,
                                             .p = {.t = -1, .rgb = {1, 1, 1}, .sky = {-1, -1, -1}, .soft = -1},
                                             .turn = QCLI_TURN_DEFAULT};
static const relight_cli path_defaults = {.r = QTOOL_RELIGHT_OPTS_DEFAULT, .exposure = 1.0, .path_mode = 1,
                                          .p = {.t = -1, .rgb = {1, 1, 1}, .sky = {-1, -1, -1}, .soft = -1},
                                          .turn = QCLI_TURN_DEFAULT};

static const qtool_opt relight_table[] = {
    {.name = "--sun", .kind = QTOOL_OPT_CALL, .nargs = 3, .call_n = sun_call, .arg = "X Y Z",
     .help = "a directional light from (X, Y, Z) (repeatable)"},
    {.name = "--point", .kind = QTOOL_OPT_CALL, .nargs = 3, .call_n = point_call, .arg = "X Y Z",
     .help = "a point lamp at (X, Y, Z) (repeatable)"},
    {.name = "--rgb", .kind = QTOOL_OPT_CALL, .nargs = 3, .call_n = rgb_call, .arg = "R G B",
     .help = "the colour of the --sun or --point before it (before the first: the first's), 0..32767.99998; "
             "with --path the path's light (default 1 1 1)"},
    {.name = "--lights", .kind = QTOOL_OPT_CALL, .call = lights_call, .arg = "FILE.csv",
     .help = "directional lights from a CSV (qibl lights --csv)"},
    {.name = "--probe", .kind = QTOOL_OPT_CALL, .call = probe_call, .arg = "PROBE.hdr",
     .help = "light from a Radiance probe"},
    {.name = "--layout", .kind = QTOOL_OPT_CALL, .call = layout_call, .arg = "L",
     .help = "the probe's layout: auto (default), latlong, angular, ball, vcross or hcross"},
    {.name = "--probe-mode", .kind = QTOOL_OPT_CALL, .call = mode_call, .arg = "sh|lights|sunsky",
     .help = "the probe as SH (default), N median-cut lights, or its suns plus SH"},
    {.name = "-n", .kind = QTOOL_OPT_CALL, .call = count_call, .arg = "N",
     .help = "median-cut lights of --probe-mode lights or sunsky (a power of two in 1..65536)"},
    QCLI_TURN_OPTS(relight_cli, turn, "turn the probe (positive turns +x toward +y)",
                   "turn the probe by a rotation matrix (rows)"),
    {.name = "--lut", .kind = QTOOL_OPT_CALL, .optional = 1, .call = lut_call, .arg = "poly|nearest|bilinear|off",
     .help = "how point lamps are evaluated: polynomial (default), the asset's Y LUT, or direct SH (off)"},
    {.name = "--nearest", .kind = QTOOL_OPT_FLAG, .off = offsetof(relight_cli, nearest), .call = nearest_call,
     .help = "the old spelling of --lut nearest"},
    {.name = "--falloff", .kind = QTOOL_OPT_INT, .off = offsetof(relight_cli, r.falloff), .lo = 1, .hi = 2,
     .why = "1: C0/|L|, 2: C0/|L|^2", .help = "the point lamps' falloff"},
    {.name = "--exposure", .kind = QTOOL_OPT_NUM, .off = offsetof(relight_cli, exposure), .arg = "E",
     .lo = 1.0 / 65536, .hi = QTOOL_CLI_Q16_MAX, .why = "a positive Q16.16 factor", .help = "scales the frame"},
    {.name = "--linear", .kind = QTOOL_OPT_FLAG, .off = offsetof(relight_cli, r.linear),
     .help = "no sRGB curve on the 8-bit frame"},
    {.name = "--gles", .kind = QTOOL_OPT_FLAG, .off = offsetof(relight_cli, r.gles),
     .help = "platform/gles2 on a headless EGL context instead of platform/soft (one light)"},
    {.name = "--ies", .kind = QTOOL_OPT_STR, .off = offsetof(relight_cli, r.ies), .arg = "FILE.ies",
     .help = "the --point lamps (or the path's lamp) are goniometric: C0 I(direction) / I_peak"},
    {.name = "--aim", .kind = QTOOL_OPT_CALL, .nargs = 3, .call_n = aim_call, .arg = "X Y Z", .def = "0 0 -1",
     .help = "where the IES lamp's nadir points"},
    {.name = "--up", .kind = QTOOL_OPT_CALL, .nargs = 3, .call_n = up_call, .arg = "X Y Z", .def = "1 0 0",
     .help = "the IES lamp's C = 0 direction (approximate)"},
    {.name = "--ies-size", .kind = QTOOL_OPT_INT, .off = offsetof(relight_cli, r.ies_n), .lo = QIBL_GONIO_MIN_N,
     .hi = QIBL_GONIO_MAX_N, .what = "a table size", .help = "the goniometric table's side"},
    {.name = "--png", .kind = QTOOL_OPT_STR, .off = offsetof(relight_cli, png), .arg = "OUT",
     .help = "the 8-bit sRGB frame"},
    {.name = "--hdr", .kind = QTOOL_OPT_STR, .off = offsetof(relight_cli, hdr), .arg = "OUT.hdr",
     .help = "the linear frame as Radiance RGBE (not with --path)"},
    {.name = "--pfm", .kind = QTOOL_OPT_STR, .off = offsetof(relight_cli, pfm), .arg = "OUT.pfm",
     .help = "the linear frame as PFM floats"},
    {.name = "--exr", .kind = QTOOL_OPT_STR, .off = offsetof(relight_cli, exr), .arg = "OUT.exr",
     .help = "the linear frame as OpenEXR (FLOAT, ZIP)"},
    {.name = "--path", .kind = QTOOL_OPT_STR, .off = offsetof(relight_cli, p.spec), .arg = "N|sun|lamp",
     .help = "a light on the asset's baked path N (or its first sun path / lamp track)"},
    {.name = "--t", .kind = QTOOL_OPT_NUM, .off = offsetof(relight_cli, p.t), .arg = "T", .lo = 0, .hi = 1,
     .why = "a path parameter in 0..1", .def = "required with --path", .help = "where on the path"},
    {.name = "--soft", .kind = QTOOL_OPT_NUM, .off = offsetof(relight_cli, p.soft), .arg = "R", .lo = 0, .hi = 0.5,
     .why = "a half-width in path units, 0..0.5", .def = "0", .help = "--path: soft over [T - R, T + R]"},
    {.name = "--sky", .kind = QTOOL_OPT_TRIPLE, .off = offsetof(relight_cli, p.sky), .arg = "R G B", .lo = 0,
     .hi = 32767, .why = "a colour component in 0..32767", .def = "none",
     .help = "--path: add the demo's sky through the shadowed maps"},
    {0},
};

static const qtool_opt_cmd relight_spec = {
    QTOOL_OPT_CMD("relight", relight_table, relight_defaults, "FILE", 0, 1, relight_cli, file),
    .prose =
        "  Lights add up: any number of --sun and --point (at most 64 together), --lights and --probe.\n"
        "  --sun: directional light from direction (X, Y, Z), colour --rgb (default 1 1 1).\n"
        "  --point: point light at (X, Y, Z) in scene units, C0 = --rgb (default: 2 d, or 2 d^2 with\n"
        "  --falloff 2, d the median distance from the lamp to the asset's P-map points, with a note);\n"
        "  per-pixel Y from the SH polynomials in Q2.14 (--lut poly, the default and the fastest), the\n"
        "  asset's cube-map LUT (--lut nearest or bilinear) or the Q2.30 SH evaluation (--lut off);\n"
        "  --falloff 1 is C0/|L| (Wong et al.), 2 is C0/|L|^2. (The old\n"
        "  spellings, a bare --lut for bilinear and --nearest, still work with a deprecation note.)\n"
        "  --rgb colours the --sun or --point just before it (one given before the first light colours\n"
        "  that light). Suns sum in SH; each point is relit on its own and the frames sum per pixel in\n"
        "  64 bits, saturated once.\n"
        "  --lights FILE.csv: the output of `qibl lights --csv` (header x,y,z,r,g,b,u0,v0,u1,v1; at most\n"
        "  65536 rows), each row a directional light of colour r,g,b.\n"
        "  --probe PROBE.hdr: the whole environment (layout detected, or --layout) as the radiance SH\n"
        "  (PROBE may be an OpenEXR file, known by its magic number, wherever a .hdr is read: its data\n"
        "  window's R G B or Y, negative samples made 0)\n"
        "  of the asset's k maps (no irradiance convolution: the maps already hold the cosine and the\n"
        "  shadows). --probe-mode sh (default): the core's projection; lights: N median-cut lights\n"
        "  (-n N, a power of two, default 64) projected to SH; sunsky: of N median-cut regions (default\n"
        "  64) the sun (those whose mean radiance is at least 32 times the probe's; none on an overcast\n"
        "  sky) as directional lights, the rest of the probe as its SH (qibl_shlight_add_sun_sky).\n"
        "  --yaw DEG: turns the environment about +z (up): a light at azimuth phi (from +x toward +y)\n"
        "  comes from phi + DEG: positive yaw turns +x toward +y (counter-clockwise seen from above in\n"
        "  the right-handed xyz frame), and the probe's lat-long picture slides DEG/360 of its width to\n"
        "  the right (the picture is mirrored against xyz: seen from inside, +y is left of +x).\n"
        "  --rotate: the 3x3 rotation r row by row (orthonormal within 2^-16, det +1): light from d\n"
        "  comes from r d.\n"
        "  Either is applied once to the probe's SH (qibl_shlight_rotate), not by re-projecting.\n"
        "  On a probe-lit asset (bake --probe) --probe alone (with the bake's --yaw) relights sun + SH\n"
        "  through its baked paths: the probe's compact sources through the unshadowed maps x their\n"
        "  visibility, the rest as SH, the probe scaled as the bake did (PNG at exposure 1); another\n"
        "  probe or yaw than the bake's is refused by name. --probe-mode lights or sunsky: without them.\n"
        "  --png: RGBA8888 with sRGB transfer (or --linear), exposure E (default 1), as an RGB PNG; a\n"
        "  frame whose mean is below 32 of 255 gets a note that it is almost black.\n"
        "  --hdr / --pfm: the same frame linear, before exposure and transfer (the core's Q16.16 output,\n"
        "  negative SH ringing clamped to 0), as Radiance RGBE (RLE) or little-endian PFM, for other\n"
        "  tools; --exr: the same floats as OpenEXR (scanline, ZIP, FLOAT, bit for bit). At least one of\n"
        "  --png/--hdr/--pfm/--exr.\n"
        "  --gles: relight with platform/gles2 on a headless EGL context instead (one --sun or --point,\n"
        "  --png only; the same asset and core weights; within 1 of 255 of the CPU path on Mesa llvmpipe).\n"
        "  --ies FILE.ies [--aim X Y Z] [--up X Y Z] [--ies-size N]: every --point becomes a goniometric\n"
        "  lamp with the IES LM-63 file's profile (see `qibl ies info`): its light toward each pixel's point\n"
        "  of the P map is scaled by I(direction) / I_peak (qibl/gonio.h: the profile resampled into an\n"
        "  N x N octahedral Q1.15 table, default 64, 2..256, bilinear), so --rgb (C0) is the lamp's peak\n"
        "  and an isotropic file gives exactly the isotropic lamp. --aim: the profile's axis (type C nadir,\n"
        "  types A/B the beam centre), default 0 0 -1 (a downlight in the z-up scene); --up: the direction\n"
        "  of horizontal angle 0 (types A/B: vertical angle 90), made orthogonal to the aim, default 1 0 0.\n"
        "  With --gles the table is a texture read per pixel with the core's rounding. With --path lamp\n"
        "  (below) the same options make the track's\n"
        "  lamp goniometric (its light scaled before the track's visibility).\n"
        "  qibl relight FILE --path N|sun|lamp --t T [--rgb R G B] [--soft R] [--sky R G B]\n"
        "               [--ies FILE.ies [--aim X Y Z] [--up X Y Z] [--ies-size N]] (--png|--pfm|--exr OUT):\n"
        "  a light on the asset's baked path N (or its first sun path / lamp track) at T in 0..1: unshadowed\n"
        "  SH x visibility(T), soft over [T - R, T + R]; --sky adds the demo's sky through the shadowed maps.\n"
};
/* the same table when --path is on the line (--rgb is then the path light's colour) */
static const qtool_opt_cmd relight_path_spec = {
    QTOOL_OPT_CMD("relight", relight_table, path_defaults, "FILE", 0, 1, relight_cli, file),
};

/* the first option given that only relight without --path takes, or NULL */
static const char *light_only(const relight_cli *c)
{
    const qtool_relight_light_list *ll = &c->r.lights;
    const qtool_relight_opts d = QTOOL_RELIGHT_OPTS_DEFAULT;
    return ll->count ? (ll->src[0].point ? "--point" : "--sun") : ll->csv ? "--lights" : ll->probe ? "--probe"
           : ll->rotate ? (ll->rotate == 1 ? "--yaw" : "--rotate") : ll->n ? "-n"
           : ll->mode != QTOOL_RELIGHT_PROBE_SH ? "--probe-mode" : ll->layout != QTOOL_PROBE_LAYOUT_AUTO ? "--layout"
           : c->r.point_mode != d.point_mode ? "--lut" : c->exposure != 1.0 ? "--exposure"
           : c->r.falloff != d.falloff ? "--falloff" : c->r.linear ? "--linear" : c->r.gles ? "--gles"
           : c->hdr ? "--hdr" : NULL;
}

/* the options together, after parsing: 0, or 2 after the one line */
static int relight_check(const relight_cli *c)
{
    const qtool_opt_cmd *t = &relight_spec;
    const qtool_relight_opts *o = &c->r;
    const qtool_relight_light_list *ll = &o->lights;
    const char *bad;
    if (c->p.t >= 0 || c->p.soft >= 0 || c->p.sky[0] >= 0)
        return qtool_opt_error(t, "%s is for relight --path", c->p.t >= 0 ? "--t" : c->p.soft >= 0 ? "--soft" : "--sky");
    if (c->file.n == 0 || (!c->png && !c->hdr && !c->pfm && !c->exr))
        return qtool_opt_error(t, "relight needs FILE, a light (--sun, --point, --lights or --probe), and --png, "
                                 "--hdr, --pfm or --exr OUT");
    if (ll->count == 0 && !ll->csv && !ll->probe)
        return qtool_opt_error(t, "relight needs a light: --sun, --point, --lights FILE.csv or --probe PROBE.hdr");
    if ((bad = qtool_relight_spec_check(ll)) != NULL)
        return qtool_opt_error(t, "%s", bad);
    if (o->gles && (ll->count != 1 || ll->csv || ll->probe))
        return qtool_opt_error(t, "--gles takes exactly one --sun or --point (no --lights or --probe)");
    if (c->have_frame && !o->ies)
        return qtool_opt_error(t, "--aim and --up orient an --ies lamp: give --ies FILE.ies");
    if (o->ies && ll->points == 0)
        return qtool_opt_error(t, "--ies shapes the --point lamps: give at least one --point X Y Z");
    return 0;
}

/* --path's line together: 0, or 2 after the one line */
static int path_check(const relight_cli *c)
{
    const qtool_opt_cmd *t = &relight_spec;
    const char *bad = light_only(c);
    if (bad)
        return qtool_opt_error(t, "%s is for relight without --path (the path is the light)", bad);
    if (c->file.n == 0 || !c->p.spec || c->p.t < 0 || (!c->png && !c->pfm && !c->exr))
        return qtool_opt_error(t, "relight --path needs FILE, --path N|sun|lamp, --t T and --png, --pfm or --exr OUT");
    if (c->have_frame && !c->r.ies)
        return qtool_opt_error(t, "--aim and --up orient an --ies lamp: give --ies FILE.ies");
    return 0;
}

/* "1 sun, 2 points, lights.csv, probe.hdr (SH)" for the messages */
static void describe(const qtool_relight_opts *o, char *buf, size_t n)
{
    const qtool_relight_light_list *ll = &o->lights;
    static const char *const how[] = {"point/poly", "point/direct", "point/LUT nearest", "point/LUT bilinear"};
    size_t at = 0;
    buf[0] = '\0';
    if (ll->suns)
        at += (size_t)snprintf(buf + at, n - at, "%u sun%s", ll->suns, ll->suns == 1 ? "" : "s");
    if (ll->points && at < n)
        at += (size_t)snprintf(buf + at, n - at, "%s%u point%s (%s)", at ? ", " : "", ll->points,
                               ll->points == 1 ? "" : "s", how[o->point_mode]);
    if (ll->csv && at < n)
        at += (size_t)snprintf(buf + at, n - at, "%s%s", at ? ", " : "", ll->csv);
    if (ll->probe && at < n)
        snprintf(buf + at, n - at, "%sprobe %s (%s)", at ? ", " : "", ll->probe,
                 ll->mode == QTOOL_RELIGHT_PROBE_SH       ? "SH"
                 : ll->mode == QTOOL_RELIGHT_PROBE_LIGHTS ? "lights"
                                                          : "sun plus sky");
}

/* the linear frame (the core's Q16.16 output before exposure and the transfer curve) to each file
 * asked for, each with its line ending in tail; 0, or 1 after a message */
static int write_linear(const relight_cli *c, uint32_t w, uint32_t h, const float *lin, const char *tail)
{
    char err[1200];
    if (c->hdr && qtool_hdr_write(c->hdr, (int)w, (int)h, lin, err, sizeof err) != 0)
        return fprintf(stderr, "qibl: %s\n", err), 1;
    if (c->hdr)
        printf("wrote %s (%ux%u Radiance RGBE, linear, %s)\n", c->hdr, w, h, tail);
    if (c->pfm && qtool_pfm_write(c->pfm, (int)w, (int)h, 3, lin, err, sizeof err) != 0)
        return fprintf(stderr, "qibl: %s\n", err), 1;
    if (c->pfm)
        printf("wrote %s (%ux%u PFM, linear, %s)\n", c->pfm, w, h, tail);
    if (c->exr && qtool_exr_write(c->exr, (int)w, (int)h, lin, QTOOL_EXR_FLOAT, QTOOL_EXR_ZIP, err, sizeof err) != 0)
        return fprintf(stderr, "qibl: %s\n", err), 1;
    if (c->exr)
        printf("wrote %s (%ux%u OpenEXR FLOAT ZIP, linear, %s)\n", c->exr, w, h, tail);
    return 0;
}

/* the 8-bit frame as c->png (0 when not asked), or 1 after a message */
static int write_png(const relight_cli *c, uint32_t w, uint32_t h, const uint8_t *pix)
{
    char err[1200];
    if (c->png && qtool_png_write_rgb8(c->png, (int)w, (int)h, pix, err, sizeof err) != 0)
        return fprintf(stderr, "qibl: %s\n", err), 1;
    return 0;
}

/* the IES profile of o, its note on stderr (note != 0); 0, or 1 after a message */
static int load_ies(const qtool_relight_opts *o, qtool_relight_ies *ies, int note)
{
    char err[1200];
    int r = qtool_relight_ies_load(o->ies, (uint32_t)o->ies_n, o->aim, o->up, ies, err, sizeof err);
    if (r == -2 && note)
        fprintf(stderr, "qibl: relight: --aim/--up: %s\n", qibl_status_str(ies->status));
    else if (r == -2)
        fprintf(stderr, "qibl: relight: %s: %s\n", o->ies, qibl_status_str(ies->status));
    else if (r != 0)
        fprintf(stderr, "qibl: %s\n", err);
    else if (note)
        fprintf(stderr, "qibl: note: %s: type %c, %s, peak %.6g cd, %.2f lm; each --point lamp scaled by "
                        "I / I_peak (%ldx%ld table)\n", o->ies, ies->type, qtool_ies_sym_name(ies->sym), ies->peak,
                ies->lumens, o->ies_n, o->ies_n);
    return r != 0;
}

/* the light's SH part and lamps, their notes printed; 0, or 1 after a message */
static int relight_lights(relight_cli *c, const qtool_relight_asset *s, qibl_shlight_t *sl, qibl_pointlight_t *pts,
                          uint32_t *npts)
{
    qtool_relight_opts *o = &c->r;
    qtool_relight_point_note notes[QTOOL_RELIGHT_MAX_SOURCES];
    char err[600];
    /* the directional part as one SH light (suns, --lights, --probe); notes on stdout */
    if (qtool_relight_light_list_directional(&o->lights) && qcli_light_list_sh(&o->lights, s->m.k, stdout, sl) != 0)
        return 1;
    memset(notes, 0, sizeof notes);
    int r = qtool_relight_points(o, s, pts, npts, notes, err, sizeof err);
    for (uint32_t j = 0; j < o->lights.count; ++j)
        if (notes[j].set)
            fprintf(stderr, "qibl: note: --point without --rgb: C0 = %.4g (%.2g x d%s, d = %.3g the median distance "
                    "from the lamp to the scene); give --rgb R G B to choose\n", notes[j].c0, QTOOL_RELIGHT_POINT_GREY,
                    o->falloff == 2 ? "^2" : "", notes[j].d);
    if (r != 0)
        fprintf(stderr, "qibl: %s\n", err);
    return r != 0;
}

/* the GPU path: same asset, same core weights, platform/gles2 (one light) */
static int relight_gles(const relight_cli *c, const qtool_relight_asset *s, const qtool_relight_ies *ies,
                        uint8_t *pix)
{
    const qtool_relight_opts *o = &c->r;
    const qtool_relight_source *l = &o->lights.src[0];
    const int point = o->lights.points > 0;
    qtool_gles_relight_req req = {&s->m, point ? &s->pm : NULL,
                                  point && qtool_relight_uses_lut(o->point_mode) ? &s->lut : NULL,
                                  {l->point ? 0 : l->v[0], l->point ? 0 : l->v[1], l->point ? 0 : l->v[2]},
                                  {l->point ? l->v[0] : 0, l->point ? l->v[1] : 0, l->point ? l->v[2] : 0},
                                  {l->rgb[0], l->rgb[1], l->rgb[2]}, (int)o->falloff,
                                  o->point_mode == QTOOL_RELIGHT_POINT_NEAREST, o->linear, (qibl_uq16_t)o->exposure,
                                  point && ies ? &ies->gonio : NULL};
    uint32_t passes = 0;
    char renderer[64] = "", err[1200];
    if (qtool_gles_relight(&req, pix, &passes, renderer) != 0)
        return 1;
    if (qtool_png_write_rgb8(c->png, (int)s->m.width, (int)s->m.height, pix, err, sizeof err) != 0)
        return fprintf(stderr, "qibl: %s\n", err), 1;
    printf("wrote %s (%ux%u, k = %u, GLES2 on %s, %u pass%s)\n", c->png, s->m.width, s->m.height, s->m.k, renderer,
           passes, passes == 1 ? "" : "es");
    return 0;
}

/* the soft path: the frame, then its files and lines */
static int relight_soft(const relight_cli *c, const qtool_relight_asset *s, const qibl_shlight_t *sl,
                        const qibl_pointlight_t *pts, uint32_t npts, const qtool_relight_ies *ies, uint8_t *pix,
                        float *lin)
{
    const qtool_relight_opts *o = &c->r;
    const uint32_t w = s->m.width, h = s->m.height;
    double ms = 0;
    qibl_status_t st;
    if (qtool_relight_render(o, s, qtool_relight_light_list_directional(&o->lights) ? sl : NULL, pts, npts, ies, pix,
                             lin, &ms, &st) != 0) {
        fprintf(stderr, "qibl: relight: %s\n", qtool_status_str(st));
        return 1;
    }
    char how[600], tail[640];
    describe(o, how, sizeof how);
    if (write_png(c, w, h, pix) != 0)
        return 1;
    if (c->png) {
        printf("wrote %s (%ux%u, k = %u, %s, %.1f ms incl. framebuffer conversion)\n", c->png, w, h, s->m.k, how, ms);
        qcli_warn_dark(c->png, pix, (size_t)w * h);
    }
    snprintf(tail, sizeof tail, "before exposure, %s", how);
    return write_linear(c, w, h, lin, tail);
}

/* --probe alone (and --yaw) on a probe-lit asset (bake --probe): sun + SH through its baked paths
 * (relight/relight.h). The exit status, or -1 when that is not the case (the probe as SH). */
static int relight_probe_lit(const relight_cli *c, const qtool_relight_asset *s)
{
    const qtool_relight_opts *o = &c->r;
    const qtool_relight_light_list *ll = &o->lights;
    qibl_chunk_t ch;
    if (!ll->probe || ll->count || ll->csv || ll->mode != QTOOL_RELIGHT_PROBE_SH || ll->rotate == 2 || o->gles ||
        qibl_asset_find(&s->a, QTOOL_PROBESUN_CHUNK, &ch) != QIBL_OK)
        return -1;
    if (c->hdr || c->pfm || c->exr || c->exposure != 1.0 || o->linear)
        return fprintf(stderr, "qibl: relight: %s is probe-lit (bake --probe): its sun + SH frame is --png at exposure "
                               "1 (no --hdr, --pfm, --exr, --exposure or --linear)\n", c->file.v[0]), 1;
    uint32_t w = s->m.width, h = s->m.height;
    uint8_t *pix = malloc((size_t)w * h * 3);
    char err[1200];
    double ms = 0;
    qtool_relight_probe_paths_note note;
    int rc = 1;
    if (!pix)
        fprintf(stderr, "qibl: relight: out of memory\n");
    else if (qtool_relight_probe_paths(s, c->file.v[0], ll->probe, ll->rotate == 1 ? ll->yaw : 0, pix, &ms, &note, err,
                                       sizeof err) != 0)
        fprintf(stderr, "qibl: %s\n", err);
    else if (write_png(c, w, h, pix) == 0) {
        printf("wrote %s (%ux%u, sun + SH of %s: %d compact source%s through %d baked paths, the rest as SH k = %u, "
               "%.1f ms)\n", c->png, w, h, ll->probe, note.nsrc, note.nsrc == 1 ? "" : "s", note.nparts, s->m.k, ms);
        qcli_warn_dark(c->png, pix, (size_t)w * h);
        rc = 0;
    }
    free(pix);
    return rc;
}

static int relight_run(relight_cli *c)
{
    qtool_relight_opts *o = &c->r;
    qtool_relight_ies ies;
    qtool_relight_asset s;
    char err[1200];
    if (o->ies && load_ies(o, &ies, 1) != 0) /* the profile first: a bad file costs no asset read */
        return 1;
    if (qtool_relight_asset_open(&s, c->file.v[0], o->lights.points > 0, qtool_relight_uses_lut(o->point_mode), err,
                                 sizeof err) != 0) {
        fprintf(stderr, "qibl: %s\n", err);
        if (o->ies)
            qtool_relight_ies_free(&ies);
        return 1;
    }
    if (s.occ_unusable) /* never dropped without a word */
        fprintf(stderr, "qibl: note: %s: its LOCC chunk is not usable (%s): the lamps are drawn without lamp "
                        "occlusion\n", c->file.v[0], qibl_soft_status_str(s.occ_status));
    qibl_shlight_t sl;
    qibl_pointlight_t pts[QTOOL_RELIGHT_MAX_SOURCES];
    uint32_t npts = 0;
    size_t np = (size_t)s.m.width * s.m.height;
    uint8_t *pix = NULL;
    float *lin = NULL;
    int rc = relight_probe_lit(c, &s);
    if (rc >= 0)
        goto out;
    rc = 1;
    if (relight_lights(c, &s, &sl, pts, &npts) != 0)
        goto out;
    pix = malloc(np * 3);
    lin = c->hdr || c->pfm || c->exr ? malloc(np * 3 * sizeof(float)) : NULL;
    if (!pix || ((c->hdr || c->pfm || c->exr) && !lin))
        fprintf(stderr, "qibl: relight: out of memory\n");
    else if (o->gles)
        rc = relight_gles(c, &s, o->ies ? &ies : NULL, pix);
    else
        rc = relight_soft(c, &s, &sl, pts, npts, o->ies ? &ies : NULL, pix, lin);
out:
    if (o->ies)
        qtool_relight_ies_free(&ies);
    qtool_relight_asset_free(&s);
    free(pix), free(lin);
    return rc;
}

/* ---- qibl relight --path: a light on one of the asset's baked paths (LPTH) ------------------------- */

/* the frame's files and lines */
static int path_write(const relight_cli *c, const path_cli *p, const qibl_shmaps_t *m, const qtool_relight_path_req *q,
                      int point, const uint8_t *pix, const float *lin, double ms)
{
    const char *what = point ? "lamp" : "sun";
    char tail[64];
    if (write_png(c, m->width, m->height, pix) != 0)
        return 1;
    if (c->png) {
        printf("wrote %s (%ux%u, %s on path %u at t = %.4f (%u/65535)%s%s, %.1f ms)\n", c->png, m->width, m->height,
               what, q->index, p->t, q->tq, q->radius ? ", soft" : "", p->have_sky ? ", over the sky" : "", ms);
        qcli_warn_dark(c->png, pix, (size_t)m->width * m->height); /* as every other relight does */
    }
    snprintf(tail, sizeof tail, "%s on path %u", what, q->index);
    return write_linear(c, m->width, m->height, lin, tail);
}

static int path_run(const relight_cli *c, const path_cli *p)
{
    const qtool_relight_opts *o = &c->r;
    qtool_relight_ies ies;
    uint8_t *bytes;
    size_t n;
    qibl_asset_t a;
    qibl_shmaps_t m;
    char err[1200];
    if (o->ies && load_ies(o, &ies, 0) != 0)
        return 1;
    qtool_relight_path_req q = {.tq = (uint32_t)lrint(p->t * QIBL_LIGHTPATH_T_MAX),
                                .radius = (uint32_t)lrint(p->soft * QIBL_LIGHTPATH_T_MAX),
                                .rgb = {p->rgb[0], p->rgb[1], p->rgb[2]}, .sky = p->have_sky ? p->sky : NULL,
                                .gonio = o->ies ? &ies.gonio : NULL, .lin = c->pfm || c->exr};
    int rc = qtool_relight_asset_read(c->file.v[0], &bytes, &n, &a, &m, err, sizeof err) != 0 ? 1
             : qtool_relight_pick_path(&a, c->file.v[0], p->spec, &q.index, err, sizeof err);
    if (rc != 0) {
        fprintf(stderr, "qibl: %s\n", err);
        rc = rc == -2 ? 2 : 1;
    } else {
        size_t np = (size_t)m.width * m.height;
        uint8_t *pix = malloc(np * 3);
        float *lin = q.lin ? malloc(np * 3 * sizeof(float)) : NULL;
        double ms = 0;
        int point = 0;
        if (qtool_relight_path(bytes, n, &a, c->file.v[0], &q, pix, lin, &ms, &point, err, sizeof err) != 0)
            rc = 1, fprintf(stderr, "qibl: %s\n", err);
        else
            rc = path_write(c, p, &m, &q, point, pix, lin, ms);
        free(pix), free(lin);
    }
    free(bytes);
    if (o->ies)
        qtool_relight_ies_free(&ies);
    return rc;
}

/* --path anywhere on the line: a light on a baked path, the table with path_defaults */
static const qtool_opt_cmd *relight_pick(int argc, char **argv)
{
    for (int i = 1; i < argc; ++i)
        if (strcmp(argv[i], "--path") == 0)
            return &relight_path_spec;
    return &relight_spec;
}

/* relight's or --path's rules (the rotation first into the light list they read); the notes once
 * the line is accepted */
static int check_either(void *opts)
{
    relight_cli *c = opts;
    qcli_light_list *ll = &c->r.lights;
    ll->rotate = c->turn.ll.rotate, ll->yaw = c->turn.ll.yaw;
    memcpy(ll->r, c->turn.ll.r, sizeof ll->r);
    if (c->path_mode ? path_check(c) != 0 : relight_check(c) != 0)
        return 2;
    for (int k = 0; k < c->nnotes; ++k)
        fprintf(stderr, "qibl: note: %s\n", c->notes[k]);
    return 0;
}

/* the exposure into Q16.16, --path's unset values to theirs, then the one or the other */
static int run_either(void *opts)
{
    relight_cli *c = opts;
    c->r.exposure = (qibl_q16_t)nearbyint(c->exposure * 65536.0);
    c->p.soft = c->p.soft < 0 ? 0 : c->p.soft;
    c->p.have_sky = c->p.sky[0] >= 0;
    return c->path_mode ? path_run(c, &c->p) : relight_run(c);
}

const qcli_sub qcli_sub_relight = {.opts = &relight_spec, .pick = relight_pick, .check = check_either,
                                   .run = run_either};
