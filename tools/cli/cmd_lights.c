/*
 * cmd_lights.c - `qibl lights`: a Radiance .hdr light probe turned into directional lights by the
 * integer core (qibl/lightprobe.h), printed as a table or CSV, optionally drawn over the
 * tone-mapped probe as a PNG (like Madsen & Laursen's Figure 3) and checked against the probe's
 * exact irradiance. Probes in other layouts (angular map, mirror ball, cube crosses) are detected
 * or named with --layout and resampled to lat-long first (io/probe_layout.h). The options are
 * parsed here (its option table, opt/opt.h); relight/lights.h computes, this file prints.
 */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "opt/opt.h"
#include "cli/relight_light.h"
#include "engine/engine.h"
#include "io/png.h"
#include "relight/lights.h"

/* JSON string body: quotes, backslashes and control bytes escaped */
static void json_str(FILE *f, const char *s)
{
    for (const char *q = s; *q; ++q)
        fprintf(f, (*q == '"' || *q == '\\') ? "\\%c" : (unsigned char)*q < 0x20 ? "\\u%04x" : "%c", *q);
}

/* --auto's pick as a document on stdout: what was chosen and every number it needs, the lights
 * (unit direction, RGB irradiance facing the light: the refitted colours where the pick refits)
 * and the SH irradiance coefficients (qibl's real basis, qibl/sh.h order, z-up), together:
 * E(n) = sum_j rgb_j max(0, n . dir_j) + sum_i sh_i Y_i(n). fmt: 1 CSV, 2 JSON, 3 C. */
static void write_pick(int fmt, const char *path, double budget, const qtool_study_pick *pk)
{
    const qtool_study_model *m = &pk->model;
    if (fmt == 1) {
        printf("kind,index,x,y,z,r,g,b\n");
        for (int i = 0; i < m->n; ++i)
            printf("light,%d,%.9f,%.9f,%.9f,%.9g,%.9g,%.9g\n", i, m->dir[i][0], m->dir[i][1], m->dir[i][2],
                   m->rgb[i][0], m->rgb[i][1], m->rgb[i][2]);
        for (int i = 0; i < m->sh_n; ++i)
            printf("sh,%d,,,,%.9g,%.9g,%.9g\n", i, m->sh[0][i], m->sh[1][i], m->sh[2][i]);
    } else if (fmt == 2) {
        printf("{\"probe\": \"");
        json_str(stdout, path);
        printf("\", \"choice\": \"");
        json_str(stdout, pk->what);
        printf("\", \"met\": %s, \"budget\": %.9g, \"mean_error\": %.9g, \"floats\": %d,\n"
               " \"irradiance\": \"E(n) = sum_j rgb_j max(0, n.dir_j) + sum_i sh_i Y_i(n); qibl's real SH basis, "
               "qibl/sh.h order, z up\",\n \"lights\": [",
               pk->met ? "true" : "false", budget, pk->err, pk->floats);
        for (int i = 0; i < m->n; ++i)
            printf("%s\n  {\"dir\": [%.9f, %.9f, %.9f], \"rgb\": [%.9g, %.9g, %.9g]}", i ? "," : "", m->dir[i][0],
                   m->dir[i][1], m->dir[i][2], m->rgb[i][0], m->rgb[i][1], m->rgb[i][2]);
        printf("%s],\n \"sh\": [", m->n ? "\n " : "");
        for (int i = 0; i < m->sh_n; ++i)
            printf("%s\n  [%.9g, %.9g, %.9g]", i ? "," : "", m->sh[0][i], m->sh[1][i], m->sh[2][i]);
        printf("%s]}\n", m->sh_n ? "\n " : "");
    } else {
        /* a C fragment: arrays of at least one element (C has no empty ones), the counts beside */
        printf("/* qibl lights --auto: %s (%d floats, mean irradiance error %.3f %%, budget %g %%%s).\n"
               " * E(n) = sum_j rgb_j max(0, n . dir_j) + sum_i sh_i Y_i(n): qibl's real SH basis, qibl/sh.h order, z up. */\n",
               pk->what, pk->floats, 100 * pk->err, 100 * budget, pk->met ? "" : ", NOT met: the most accurate");
        printf("enum { QIBL_AUTO_LIGHT_COUNT = %d, QIBL_AUTO_SH_COUNT = %d };\n", m->n, m->sh_n);
        printf("static const float qibl_auto_lights[%d][6] = { /* dir x, y, z, rgb r, g, b */", m->n ? m->n : 1);
        for (int i = 0; i < m->n; ++i)
            printf("%s\n    {%.9ef, %.9ef, %.9ef, %.9ef, %.9ef, %.9ef}", i ? "," : "", m->dir[i][0], m->dir[i][1],
                   m->dir[i][2], m->rgb[i][0], m->rgb[i][1], m->rgb[i][2]);
        printf("%s};\n", m->n ? "\n" : "{0}");
        printf("static const float qibl_auto_sh[%d][3] = { /* r, g, b */", m->sh_n ? m->sh_n : 1);
        for (int i = 0; i < m->sh_n; ++i)
            printf("%s\n    {%.9ef, %.9ef, %.9ef}", i ? "," : "", m->sh[0][i], m->sh[1][i], m->sh[2][i]);
        printf("%s};\n", m->sh_n ? "\n" : "{0}");
    }
}

/* The --auto budget is a percentage, with or without the sign: "2%" and "2" are both 2 %, so
 * 0.02 (as a fraction would be written) is 0.02 %. 0 with the fraction in *out; -1: not a number
 * (the argument is something else: --error alone asks for the error line); -2: a number outside
 * (0, 100] %, refused by name (above 100 % any representation, even none, meets it). */
static int parse_budget(const char *s, double *out)
{
    char *end;
    double v = strtod(s, &end);
    if (end == s || !((s[0] >= '0' && s[0] <= '9') || s[0] == '.' || s[0] == '-' || s[0] == '+'))
        return -1;
    if (*end == '%')
        ++end;
    if (*end != '\0')
        return -1;
    if (!(v > 0 && v <= 100))
        return -2;
    *out = v / 100;
    return 0;
}

/* The command's options: the library's struct (its defaults), its enums as the table's ints. */
typedef struct lights_cli {
    qtool_relight_lights_opts o;
    qtool_opt_list probe;
    int method, priority, place, as, layout;
    qcli_turn turn;     /* --yaw / --rotate (relight's rotation) */
} lights_cli;
static const lights_cli lights_defaults = {.o = QTOOL_RELIGHT_LIGHTS_OPTS_DEFAULT,
                                           .method = QIBL_LIGHTPROBE_MEDIANCUT,
                                           .priority = QIBL_LIGHTPROBE_PRIORITY_DEFAULT,
                                           .place = 0,
                                           .as = QTOOL_RELIGHT_LIGHTS_AS_RGBE,
                                           .layout = QTOOL_PROBE_LAYOUT_AUTO,
                                           .turn = QCLI_TURN_DEFAULT};

/* the enums' names, in the order of their values */
static const char *const methods[] = {"mediancut", "adaptive", "varmin", NULL}; /* qibl_lightprobe_method_t */
static const char *const priorities[] = {"default", "energy", "energy-size", "variance", "levels", NULL};
static const char *const places[] = {"centroid", "centre", "center", NULL}; /* center: centre */
static const char *const as_names[] = {"rgbe", "srgbe", "f32", NULL};        /* qtool_relight_lights_as */

/* --format: --auto's pick as a C fragment, or csv / json as their own flags say (cumulative: a
 * second document format is refused with the first, after parsing) */
static const char *format_call(void *opts, const char *v)
{
    qtool_relight_lights_opts *o = &((lights_cli *)opts)->o;
    if (strcmp(v, "c") == 0)
        o->cfmt = 1;
    else if (strcmp(v, "csv") == 0)
        o->csv = 1;
    else if (strcmp(v, "json") == 0)
        o->json = 1;
    else
        return "is not c, csv or json";
    return NULL;
}

/* --error [P%]: the error line, or with a budget --auto's */
static const char *error_call(void *opts, const char *v)
{
    qtool_relight_lights_opts *o = &((lights_cli *)opts)->o;
    if (!v) {
        o->error = 1;
        return NULL;
    }
    switch (parse_budget(v, &o->budget)) {
    case 0:
        o->error = 1;
        return NULL;
    case -1:
        return qtool_opt_no_value;
    default:
        return "is not a budget: it is a percentage in (0, 100] (e.g. 2% or 2)";
    }
}

static const char *preset_call(void *opts, const char *v)
{
    qtool_engine_preset p;
    if (qtool_engine_preset_parse(v, &p) != 0 || (p != QTOOL_ENGINE_GLTF && p != QTOOL_ENGINE_RAW))
        return "is not gltf or raw: lights are written for gltf (KHR_lights_punctual) or raw";
    ((lights_cli *)opts)->o.gltf = p == QTOOL_ENGINE_GLTF;
    return NULL;
}

static const qtool_opt lights_table[] = {
    {.name = "--method", .kind = QTOOL_OPT_ENUM, .off = offsetof(lights_cli, method), .names = methods,
     .help = "median cut (N a power of two), adaptive median cut or variance minimisation (any N)"},
    {.name = "-n", .alias = "--count", .kind = QTOOL_OPT_INT, .off = offsetof(lights_cli, o.n), .lo = 1,
     .hi = 1L << 24, .what = "a light count", .help = "how many lights"},
    {.name = "--priority", .kind = QTOOL_OPT_ENUM, .off = offsetof(lights_cli, priority), .names = priorities,
     .arg = "P", .help = "default, energy, energy-size, variance or levels: which region adaptive / varmin split next"},
    {.name = "--place", .kind = QTOOL_OPT_ENUM, .off = offsetof(lights_cli, place), .names = places,
     .help = "a light at its region's energy centroid or geometric centre"},
    {.name = "--as", .kind = QTOOL_OPT_ENUM, .off = offsetof(lights_cli, as), .names = as_names,
     .help = "feed the core the probe as RGBE bytes, sRGBE or binary32"},
    QCLI_LAYOUT_OPT(lights_cli, layout),
    {.name = "--csv", .kind = QTOOL_OPT_FLAG, .off = offsetof(lights_cli, o.csv),
     .help = "one line per light, x,y,z,r,g,b,u0,v0,u1,v1, after a header (what relight --lights reads)"},
    {.name = "--json", .kind = QTOOL_OPT_FLAG, .off = offsetof(lights_cli, o.json),
     .help = "{\"lights\": [{\"dir\", \"rgb\", \"region\"}...]} with the probe, size, method and count"},
    {.name = "--format", .kind = QTOOL_OPT_CALL, .off = offsetof(lights_cli, o), .arg = "c|csv|json",
     .call = format_call, .help = "--auto's pick as a C fragment (or --csv, --json)"},
    {.name = "--png", .kind = QTOOL_OPT_STR, .off = offsetof(lights_cli, o.png), .arg = "OUT.png",
     .help = "the tone-mapped probe with the regions (green) and light directions (red)"},
    {.name = "--zoom", .kind = QTOOL_OPT_INT, .off = offsetof(lights_cli, o.zoom), .arg = "Z", .lo = 1, .hi = 64,
     .def = "to about 1024 pixels wide", .help = "the picture's scale"},
    {.name = "--error", .kind = QTOOL_OPT_CALL, .optional = 1, .off = offsetof(lights_cli, o), .arg = "P%",
     .call = error_call, .help = "the lights' irradiance error against the probe's; with P% the budget of --auto"},
    {.name = "--auto", .kind = QTOOL_OPT_FLAG, .off = offsetof(lights_cli, o.autom),
     .help = "the cheapest representation with mean irradiance error <= --error P%"},
    {.name = "--preset", .kind = QTOOL_OPT_CALL, .off = offsetof(lights_cli, o), .arg = "gltf|raw",
     .call = preset_call, .def = "raw", .help = "gltf: the lights as KHR_lights_punctual JSON"},
    QCLI_TURN_OPTS(lights_cli, turn, "turn --preset gltf's lights, as qibl relight does",
                   "turn --preset gltf's lights by a rotation matrix (rows)"),
    {0},
};

static const qtool_opt_cmd lights_spec = {
    QTOOL_OPT_CMD("lights", lights_table, lights_defaults, "PROBE.hdr", 1, 1, lights_cli, probe),
    .prose =
        "  Turns a W x H lat-long probe (top row theta = 0 = +z, phi = 0 at the left edge, growing to the\n"
        "  right) into N directional lights with the integer core (qibl/lightprobe.h): median cut\n"
        "  (Debevec; N a power of two, default 64), adaptive median cut (any N) or variance minimisation\n"
        "  (Viriyothai & Debevec; any N). Each light is a unit direction (to its region's energy\n"
        "  centroid), an RGB irradiance (E(n) = sum rgb max(0, n.d) approximates the probe's) and its\n"
        "  region, brightest first. Without --csv or --json: a table.\n"
        "  --png: the picture may have at most 65535 pixels a side and 2^25 in all. --error: the\n"
        "  lights' irradiance against the probe's over 1024 normals.\n"
        "  An all-black probe prints that it has no lights and exits 0.\n"
        "  --layout: by default detected (2:1 latlong, 3:4 vcross, 4:3 hcross with black empty cells)\n"
        "  and printed; a square disc (angular map or mirror ball; a caption may light up to 5 % of the\n"
        "  corners) needs --layout; other shapes are refused. Non-lat-long probes are resampled to\n"
        "  lat-long (io/probe_layout.h).\n"
        "  --preset gltf: one directional light per light (intensity = its largest channel, lux for a\n"
        "  probe in cd/m^2; color = rgb / intensity) and one node each whose rotation turns -z to where\n"
        "  the light travels, in glTF's y-up frame as sh project --preset gltf places the probe.\n"
        "  --auto --error P%: the cheapest representation with mean irradiance error <= P % (the\n"
        "  measure of qibl probe info: |E - E_probe| / max(E_probe, mean E_probe / 10) per normal and\n"
        "  channel, floored so near-black normals cannot blow it up; probes box-averaged to <= 1024 wide)\n"
        "  (tools/study): SH irradiance (4/9/16/25), N varmin lights (as sampled, or RGB refitted by NNLS)\n"
        "  or sun plus sky (k lights + SH9); counted in floats stored (6 per light, 3 per coefficient).\n"
        "  P is a percentage in (0, 100], the sign optional: --error 2 is 2 %, not 200 %. An all-black\n"
        "  probe is refused: its error would be 0 / 0. --format c|csv|json: the pick as a document.\n",
};

/* the table's ints into c->o, then the options together: 0, or 2 after the one line */
static int lights_check(void *opts)
{
    lights_cli *c = opts;
    qtool_relight_lights_opts *o = &c->o;
    o->path = c->probe.v[0];
    o->core.method = (qibl_lightprobe_method_t)c->method;
    o->core.priority = (qibl_lightprobe_priority_t)c->priority;
    o->core.place = c->place == 0 ? QIBL_LIGHTPROBE_PLACE_CENTROID : QIBL_LIGHTPROBE_PLACE_CENTRE;
    o->as = (qtool_relight_lights_as)c->as;
    o->layout = (qtool_probe_layout_t)c->layout;
    o->rotate = c->turn.ll.rotate;
    memcpy(o->r, c->turn.ll.r, sizeof o->r);
    const qtool_opt_cmd *t = &lights_spec;
    if (o->budget >= 0 && !o->autom)
        return qtool_opt_error(t, "--error with a budget (%g%%) needs --auto", 100 * o->budget);
    if (o->autom && o->budget < 0)
        return qtool_opt_error(t, "--auto needs a budget: --error P%% (mean relative irradiance error, e.g. 2%%)");
    if (o->csv && o->json)
        return qtool_opt_error(t, "--csv and --json: give one");
    if (o->cfmt && (o->csv || o->json))
        return qtool_opt_error(t, "--format c and --csv/--json: give one");
    if (o->cfmt && !o->autom)
        return qtool_opt_error(t, "--format c writes the pick of --auto: add --auto --error P%%");
    if (o->gltf && (o->csv || o->json))
        return qtool_opt_error(t, "--preset gltf writes its own JSON: it does not go with --csv or --json");
    if (o->rotate && !o->gltf)
        return qtool_opt_error(t, "--yaw and --rotate turn the lights of --preset gltf");
    if (o->gltf && (o->autom || o->error))
        return qtool_opt_error(t, "--preset gltf writes JSON: it does not go with --auto or --error");
    if (o->json && o->error && !o->autom)
        return qtool_opt_error(t, "--error prints a line of text: it does not go with --json");
    if (o->core.method == QIBL_LIGHTPROBE_MEDIANCUT && (o->n & (o->n - 1)) != 0)
        return qtool_opt_error(t, "median cut makes 2^K lights: -n must be a power of two (or use --method "
                                 "adaptive)");
    return 0;
}

/* --auto: the cheapest representation within the budget; with a document asked for, the table and
 * the choice go to stderr and the pick to stdout */
static int lights_auto(const qtool_relight_lights_opts *o, const qtool_relight_lights_probe *p)
{
    const int fmt = o->csv ? 1 : o->json ? 2 : o->cfmt ? 3 : 0;
    qtool_study_pick *pk = fmt ? malloc(sizeof *pk) : NULL;
    char err[512];
    if (fmt && !pk)
        return fprintf(stderr, "qibl: lights: out of memory\n"), 1;
    if (qtool_relight_lights_auto(p, o->budget, fmt ? stderr : stdout, pk, err, sizeof err) != 0) {
        free(pk);
        return fprintf(stderr, "qibl: lights: %s: %s\n", o->path, err), 1;
    }
    if (fmt)
        write_pick(fmt, o->path, o->budget, pk);
    free(pk);
    return 0;
}

/* the lights as glTF (KHR_lights_punctual), turned by --yaw / --rotate; 0, or 1 after a message */
static int print_gltf(const qtool_relight_lights_opts *o, const qibl_lightprobe_light_t *L,
                      const qibl_lightprobe_result_t *res)
{
    size_t m = res->count ? res->count : 1;
    double (*d)[3] = malloc(sizeof *d * m), (*c)[3] = malloc(sizeof *c * m);
    char eerr[256];
    if (!d || !c) {
        free(d), free(c);
        return fprintf(stderr, "qibl: lights: out of memory\n"), 1;
    }
    qtool_relight_lights_turned(L, res->count, res->rgb_exp, o->rotate, o->r, d, c);
    int bad = qtool_engine_gltf_lights_write(stdout, (const double(*)[3])d, (const double(*)[3])c, res->count, eerr,
                                             sizeof eerr);
    free(d), free(c);
    if (bad)
        return fprintf(stderr, "qibl: lights: %s: %s\n", o->path, eerr), 1;
    return 0;
}

#define DIR3(l) (l).dir[0] / 1073741824.0, (l).dir[1] / 1073741824.0, (l).dir[2] / 1073741824.0
#define RGB3(l, e) ldexp((l).rgb[0], (e)), ldexp((l).rgb[1], (e)), ldexp((l).rgb[2], (e))

/* the lights as JSON, CSV or the table */
static void print_lights(const qtool_relight_lights_opts *o, const qtool_relight_lights_probe *p,
                         const qibl_lightprobe_light_t *L, const qibl_lightprobe_result_t *res)
{
    const int e = res->rgb_exp;
    if (o->json) {
        static const char *jm[] = {"mediancut", "adaptive", "varmin"};
        printf("{\"probe\": \"");
        json_str(stdout, o->path);
        printf("\", \"width\": %d, \"height\": %d, \"method\": \"%s\", \"asked\": %ld, \"count\": %u,\n"
               " \"rgb\": \"irradiance of each region (E(n) = sum rgb max(0, n.dir))\",\n \"lights\": [",
               p->w, p->h, jm[o->core.method], o->n, res->count);
        for (uint32_t i = 0; i < res->count; ++i)
            printf("%s\n  {\"dir\": [%.9f, %.9f, %.9f], \"rgb\": [%.9g, %.9g, %.9g], \"region\": [%u, %u, %u, %u]}",
                   i ? "," : "", DIR3(L[i]), RGB3(L[i], e), L[i].u0, L[i].v0, L[i].u1, L[i].v1);
        printf("\n]}\n");
    } else if (o->csv) {
        printf("x,y,z,r,g,b,u0,v0,u1,v1\n");
        for (uint32_t i = 0; i < res->count; ++i)
            printf("%.9f,%.9f,%.9f,%.9g,%.9g,%.9g,%u,%u,%u,%u\n", DIR3(L[i]), RGB3(L[i], e), L[i].u0, L[i].v0, L[i].u1,
                   L[i].v1);
    } else {
        static const char *mn[] = {"median cut", "adaptive median cut", "variance minimisation"};
        printf("%s: %d x %d, %s, %u lights (asked %ld), brightest first; rgb is irradiance = integer * 2^%d\n",
               o->path, p->w, p->h, mn[o->core.method], res->count, o->n, e);
        printf("%4s %11s %11s %11s %12s %12s %12s  %s\n", "#", "x", "y", "z", "r", "g", "b", "region u0 v0 u1 v1");
        for (uint32_t i = 0; i < res->count; ++i)
            printf("%4u %11.8f %11.8f %11.8f %12.6g %12.6g %12.6g  %u %u %u %u\n", i, DIR3(L[i]), RGB3(L[i], e),
                   L[i].u0, L[i].v0, L[i].u1, L[i].v1);
    }
}

/* --error's line and --png's picture, after the lights; 0, or 1 after a message */
static int lights_extras(const qtool_relight_lights_opts *o, const qtool_relight_lights_probe *p, int z,
                         const qibl_lightprobe_light_t *L, const qibl_lightprobe_result_t *res)
{
    double me, mx;
    if (o->error && qtool_relight_lights_error(p, L, res->count, res->rgb_exp, &me, &mx) != 0)
        fprintf(stderr, "qibl: lights: out of memory for --error\n");
    else if (o->error)
        printf("irradiance error against the full probe over %d normals (of the mean irradiance): mean %.3f%%, "
               "max %.3f%%\n", QTOOL_RELIGHT_LIGHTS_ERROR_NORMALS, 100 * me, 100 * mx);
    if (!o->png)
        return 0;
    uint8_t *img = qtool_relight_lights_draw(p, z, L, res->count);
    char err[512];
    if (!img)
        return fprintf(stderr, "qibl: lights: out of memory for the picture\n"), 1;
    int rc = qtool_png_write_rgb8(o->png, p->w * z, p->h * z, img, err, sizeof err);
    free(img);
    if (rc != 0)
        return fprintf(stderr, "qibl: %s\n", err), 1;
    if (!o->csv && !o->json && !o->gltf)
        printf("wrote %s (%d x %d): regions in green, light directions in red\n", o->png, p->w * z, p->h * z);
    return 0;
}

/* the lights of the probe, printed; 0, or 1 after a message */
static int lights_fit(const qtool_relight_lights_opts *o, const qtool_relight_lights_probe *p, int z)
{
    qibl_lightprobe_light_t *L;
    qibl_lightprobe_result_t res;
    char err[4200 + 600];
    int r = qtool_relight_lights_fit(o, p, &L, &res, err, sizeof err), rc = 1;
    if (r != 0)
        fprintf(stderr, "qibl: %s\n", err);
    if (r == 1) { /* an all-black probe: a valid answer, no lights; still a document */
        if (o->json)
            printf("{\"width\": %d, \"height\": %d, \"count\": 0, \"lights\": []}\n", p->w, p->h);
        if (o->gltf && qtool_engine_gltf_lights_write(stdout, NULL, NULL, 0, err, sizeof err) != 0)
            return fprintf(stderr, "qibl: lights: %s: %s\n", o->path, err), 1;
        return 0;
    }
    if (r == 0 && o->gltf)
        rc = print_gltf(o, L, &res);
    else if (r == 0)
        print_lights(o, p, L, &res), rc = 0;
    if (rc == 0)
        rc = lights_extras(o, p, z, L, &res);
    free(L);
    return rc;
}

static int lights_run(void *opts)
{
    const qtool_relight_lights_opts *o = &((const lights_cli *)opts)->o;
    qtool_relight_lights_probe p;
    char note[4200 + 256], err[4200 + 600];
    if (qtool_relight_lights_load(o->path, o->layout, &p, note, sizeof note, err, sizeof err) != 0)
        return fprintf(stderr, "qibl: %s\n", err), 1;
    /* said out loud (on stderr with a document, which keeps stdout a table) */
    fputs(note, o->csv || o->json || o->gltf || o->cfmt ? stderr : stdout);
    int rc;
    if (o->autom) {
        rc = lights_auto(o, &p);
    } else {
        /* the picture's size is known now: refuse one the PNG writer could not take before any work */
        int z = qtool_relight_lights_zoom(p.w, p.h, o->zoom);
        if (o->png && qtool_relight_lights_zoom_fits(p.w, p.h, z) != 0)
            rc = qcli_usage_error("--zoom %d: a %dx%d probe makes a %llux%llu picture; the limit is %u per side "
                                  "and %u pixels (try --zoom %llu)", z, p.w, p.h,
                                  (unsigned long long)p.w * (unsigned long long)z,
                                  (unsigned long long)p.h * (unsigned long long)z, QTOOL_RELIGHT_LIGHTS_PNG_MAX_SIDE,
                                  QTOOL_RELIGHT_LIGHTS_PNG_MAX_PIXELS,
                                  (unsigned long long)qtool_relight_lights_max_zoom(p.w, p.h));
        else
            rc = lights_fit(o, &p, z);
    }
    qtool_relight_lights_probe_free(&p);
    return rc;
}

const qcli_sub qcli_sub_lights = {.opts = &lights_spec, .check = lights_check, .run = lights_run};
