/*
 * cmd_lights.c - `qibl lights`: a Radiance .hdr light probe turned into directional lights by the
 * integer core (qibl/lightprobe.h), printed as a table or CSV, optionally drawn over the
 * tone-mapped probe as a PNG (like Madsen & Laursen's Figure 3) and checked against the probe's
 * exact irradiance. Probes in other layouts (angular map, mirror ball, cube crosses) are detected
 * or named with --layout and resampled to lat-long first (io/probe_layout.h).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/hdr.h"
#include "io/png.h"
#include "io/probe_layout.h"
#include "cli/cli.h"
#include "cli/relight_light.h"
#include "engine/engine.h"
#include "qibl/lightprobe.h"
#include "qibl/srgbe.h"
#include "ref/lightprobe_ref.h"
#include "study/study.h"

#define USAGE "usage: qibl lights PROBE.hdr [--method mediancut|adaptive|varmin] [-n N] [--csv | --json | --preset gltf] [--png OUT.png] [--layout L]\n" \
              "                  [--yaw DEG | --rotate a,b,c,d,e,f,g,h,i] (with --preset gltf)\n" \
              "       qibl lights PROBE.hdr --auto --error P% [--csv | --json | --format c]"

static int parse_method(const char *s, qibl_lightprobe_method_t *m)
{
    if (strcmp(s, "mediancut") == 0)
        *m = QIBL_LIGHTPROBE_MEDIANCUT;
    else if (strcmp(s, "adaptive") == 0)
        *m = QIBL_LIGHTPROBE_ADAPTIVE;
    else if (strcmp(s, "varmin") == 0)
        *m = QIBL_LIGHTPROBE_VARMIN;
    else
        return -1;
    return 0;
}

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

static int parse_priority(const char *s, qibl_lightprobe_priority_t *p)
{
    static const char *names[] = {"default", "energy", "energy-size", "variance", "levels"};
    for (int i = 0; i < QIBL_LIGHTPROBE_PRIORITY_COUNT; ++i)
        if (strcmp(s, names[i]) == 0) {
            *p = (qibl_lightprobe_priority_t)i;
            return 0;
        }
    return -1;
}

static double rgbe_f(uint8_t m, uint8_t e)
{
    return e ? ldexp(m, e - 136) : 0.0;
}

/* pixel-space position of a direction: u = phi W / 2 pi, v = theta H / pi */
static void dir_to_uv(const qibl_lightprobe_light_t *l, int w, int h, double *u, double *v)
{
    const double pi = 3.14159265358979323846;
    double x = l->dir[0] / 1073741824.0, y = l->dir[1] / 1073741824.0, z = l->dir[2] / 1073741824.0;
    double phi = atan2(y, x);
    if (phi < 0)
        phi += 2 * pi;
    *u = phi * w / (2 * pi);
    *v = acos(fmax(-1.0, fmin(1.0, z))) * h / pi;
}

static void put(uint8_t *img, int W, int H, int x, int y, const uint8_t c[3])
{
    if (x < 0 || y < 0 || x >= W || y >= H)
        return;
    memcpy(img + 3 * ((size_t)y * (size_t)W + (size_t)x), c, 3);
}

/* --png picture limits: the PNG writer's side limit, and 2^25 pixels (96 MB of RGB) */
#define LIGHTS_PNG_MAX_SIDE 65535u
#define LIGHTS_PNG_MAX_PIXELS (1u << 25)

/* the largest zoom (at least 1) that keeps a w x h probe's picture within the limits */
static uint64_t max_zoom(int w, int h)
{
    uint64_t z = 1;
    while ((uint64_t)w * (z + 1) <= LIGHTS_PNG_MAX_SIDE && (uint64_t)h * (z + 1) <= LIGHTS_PNG_MAX_SIDE &&
           (uint64_t)w * (z + 1) * (uint64_t)h * (z + 1) <= LIGHTS_PNG_MAX_PIXELS)
        ++z;
    return z;
}

/* The probe tone-mapped (Reinhard's global operator at the log-average key, sRGB-ish gamma),
 * zoomed by z, with every light's region outlined and its direction marked. */
static int write_png(const char *path, const uint8_t *px, int w, int h, int z, const qibl_lightprobe_light_t *L,
                     uint32_t n)
{
    int W = w * z, H = h * z;
    uint8_t *img = malloc((size_t)W * (size_t)H * 3);
    if (!img)
        return fprintf(stderr, "qibl: lights: out of memory for the picture\n"), 1;
    double logsum = 0;
    for (size_t i = 0; i < (size_t)w * (size_t)h; ++i) {
        const uint8_t *q = px + 4 * i;
        double l = 0.2126 * rgbe_f(q[0], q[3]) + 0.7152 * rgbe_f(q[1], q[3]) + 0.0722 * rgbe_f(q[2], q[3]);
        logsum += log(1e-6 + l);
    }
    double key = exp(logsum / ((double)w * h)), a = 0.18 / key;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const uint8_t *q = px + 4 * ((size_t)(y / z) * (size_t)w + (size_t)(x / z));
            uint8_t *o = img + 3 * ((size_t)y * (size_t)W + (size_t)x);
            for (int c = 0; c < 3; ++c) {
                double s = a * rgbe_f(q[c], q[3]);
                o[c] = (uint8_t)lrint(255.0 * pow(s / (1.0 + s), 1.0 / 2.2));
            }
        }
    const uint8_t edge[3] = {40, 220, 60}, dot[3] = {255, 30, 20}, rim[3] = {0, 0, 0};
    for (uint32_t i = 0; i < n; ++i) {
        int x0 = (int)L[i].u0 * z, x1 = (int)L[i].u1 * z - 1, y0 = (int)L[i].v0 * z, y1 = (int)L[i].v1 * z - 1;
        for (int x = x0; x <= x1; ++x)
            put(img, W, H, x, y0, edge), put(img, W, H, x, y1, edge);
        for (int y = y0; y <= y1; ++y)
            put(img, W, H, x0, y, edge), put(img, W, H, x1, y, edge);
    }
    int r = W >= 512 ? 3 : 2;
    for (uint32_t i = 0; i < n; ++i) {
        double u, v;
        dir_to_uv(&L[i], w, h, &u, &v);
        int cx = (int)lrint(u * z - 0.5), cy = (int)lrint(v * z - 0.5);
        for (int dy = -r - 1; dy <= r + 1; ++dy)
            for (int dx = -r - 1; dx <= r + 1; ++dx) {
                int d2 = dx * dx + dy * dy;
                if (d2 <= r * r)
                    put(img, W, H, cx + dx, cy + dy, dot);
                else if (d2 <= (r + 1) * (r + 1))
                    put(img, W, H, cx + dx, cy + dy, rim);
            }
    }
    char err[512];
    int rc = qtool_png_write_rgb8(path, W, H, img, err, sizeof err);
    free(img);
    if (rc != 0)
        return fprintf(stderr, "qibl: %s\n", err), 1;
    return 0;
}

/* Irradiance of the lights against the probe's own, over the sphere (tools/ref, double). */
static void print_error(const uint8_t *px, int w, int h, const qibl_lightprobe_light_t *L, uint32_t n, int exp2)
{
    double *d = malloc(sizeof *d * 3 * (size_t)w * (size_t)h);
    qtool_ref_light *R = malloc(sizeof *R * (n ? n : 1));
    enum { NN = 1024 };
    double (*nrm)[3] = malloc(sizeof *nrm * NN), *E = malloc(sizeof *E * NN);
    qtool_ref_probe rp;
    if (!d || !R || !nrm || !E) {
        fprintf(stderr, "qibl: lights: out of memory for --error\n");
        goto out;
    }
    for (size_t i = 0; i < (size_t)w * (size_t)h; ++i)
        for (int c = 0; c < 3; ++c)
            d[3 * i + (size_t)c] = rgbe_f(px[4 * i + (size_t)c], px[4 * i + 3]);
    if (qtool_ref_probe_init(&rp, w, h, d) != 0) {
        fprintf(stderr, "qibl: lights: out of memory for --error\n");
        goto out;
    }
    qtool_ref_sphere_dirs(NN, nrm);
    qtool_ref_probe_irradiance(&rp, NN, (const double (*)[3])nrm, E, 4);
    for (uint32_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) {
            R[i].dir[c] = L[i].dir[c] / 1073741824.0;
            R[i].rgb[c] = ldexp(L[i].rgb[c], exp2);
        }
    double me, mx;
    qtool_ref_irradiance_error(R, (int)n, NN, (const double (*)[3])nrm, E, &me, &mx);
    printf("irradiance error against the full probe over %d normals (of the mean irradiance): mean %.3f%%, "
           "max %.3f%%\n", NN, 100 * me, 100 * mx);
    qtool_ref_probe_free(&rp);
out:
    free(d), free(R), free(nrm), free(E);
}

int qcli_cmd_lights(int argc, char **argv)
{
    const char *path = NULL, *png = NULL, *as = "rgbe";
    qibl_lightprobe_opts_t o;
    memset(&o, 0, sizeof o);
    long n = 64, zoom = 0;
    int csv = 0, json = 0, error = 0, autom = 0, gltf = 0, cfmt = 0;
    qcli_light_list rl; /* only its --yaw / --rotate (relight's parser) */
    qcli_light_list_init(&rl);
    double budget = -1;
    qtool_probe_layout_t layout = QTOOL_PROBE_LAYOUT_AUTO;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        int more = i + 1 < argc;
        if (strcmp(a, "--method") == 0 && more) {
            if (parse_method(argv[++i], &o.method) != 0)
                return qcli_usage_error("--method is mediancut, adaptive or varmin");
        } else if ((strcmp(a, "-n") == 0 || strcmp(a, "--count") == 0) && more) {
            if (qcli_parse_int(argv[++i], 1, 1L << 24, &n) != 0)
                return qcli_usage_error("-n needs a light count in 1..16777216");
        } else if (strcmp(a, "--priority") == 0 && more) {
            if (parse_priority(argv[++i], &o.priority) != 0)
                return qcli_usage_error("--priority is default, energy, energy-size, variance or levels");
        } else if (strcmp(a, "--place") == 0 && more) {
            const char *p = argv[++i];
            if (strcmp(p, "centroid") == 0)
                o.place = QIBL_LIGHTPROBE_PLACE_CENTROID;
            else if (strcmp(p, "centre") == 0 || strcmp(p, "center") == 0)
                o.place = QIBL_LIGHTPROBE_PLACE_CENTRE;
            else
                return qcli_usage_error("--place is centroid or centre");
        } else if (strcmp(a, "--as") == 0 && more) {
            as = argv[++i];
            if (strcmp(as, "rgbe") != 0 && strcmp(as, "srgbe") != 0 && strcmp(as, "f32") != 0)
                return qcli_usage_error("--as is rgbe, srgbe or f32");
        } else if (strcmp(a, "--png") == 0 && more) {
            png = argv[++i];
        } else if (strcmp(a, "--zoom") == 0 && more) {
            if (qcli_parse_int(argv[++i], 1, 64, &zoom) != 0)
                return qcli_usage_error("--zoom needs an integer in 1..64");
        } else if (strcmp(a, "--layout") == 0 && more) {
            if (qtool_probe_layout_parse(argv[++i], &layout) != 0)
                return qcli_usage_error("--layout is auto, latlong, angular, ball, vcross or hcross");
        } else if (strcmp(a, "--csv") == 0) {
            csv = 1;
        } else if (strcmp(a, "--json") == 0) {
            json = 1;
        } else if (strcmp(a, "--format") == 0 && more) { /* --auto's pick as a C fragment (or csv/json) */
            const char *f = argv[++i];
            if (strcmp(f, "c") == 0)
                cfmt = 1;
            else if (strcmp(f, "csv") == 0)
                csv = 1;
            else if (strcmp(f, "json") == 0)
                json = 1;
            else
                return qcli_usage_error("--format is c, csv or json");
        } else if (strcmp(a, "--error") == 0) {
            error = 1;
            int pb = more ? parse_budget(argv[i + 1], &budget) : -1;
            if (pb == -2)
                return qcli_usage_error("--error %s: the budget is a percentage in (0, 100] (e.g. 2%% or 2)", argv[i + 1]);
            if (pb == 0) /* --error 2%: the --auto budget */
                ++i;
        } else if (strcmp(a, "--auto") == 0) {
            autom = 1;
        } else if (strcmp(a, "--preset") == 0 && more) { /* tools/engine: KHR_lights_punctual */
            qtool_engine_preset p;
            if (qtool_engine_preset_parse(argv[++i], &p) != 0 || (p != QTOOL_ENGINE_GLTF && p != QTOOL_ENGINE_RAW))
                return qcli_usage_error("--preset: '%s': lights are written for gltf (KHR_lights_punctual) or raw",
                                        argv[i]);
            gltf = p == QTOOL_ENGINE_GLTF;
        } else if ((strcmp(a, "--yaw") == 0 || strcmp(a, "--rotate") == 0) && more) {
            int rc = qcli_light_list_opt(argc, argv, &i, &rl);
            if (rc != 1)
                return rc == 2 ? 2 : qcli_usage_error("%s", USAGE);
        } else if (a[0] != '-' && !path) {
            path = a;
        } else {
            return qcli_usage_error("%s", USAGE);
        }
    }
    if (!path)
        return qcli_usage_error("%s", USAGE);
    if (budget >= 0 && !autom)
        return qcli_usage_error("--error with a budget (%g%%) needs --auto", 100 * budget);
    if (autom && budget < 0)
        return qcli_usage_error("--auto needs a budget: --error P%% (mean relative irradiance error, e.g. 2%%)");
    if (csv && json)
        return qcli_usage_error("--csv and --json: give one");
    if (cfmt && (csv || json))
        return qcli_usage_error("--format c and --csv/--json: give one");
    if (cfmt && !autom)
        return qcli_usage_error("--format c writes the pick of --auto: add --auto --error P%%");
    if (gltf && (csv || json))
        return qcli_usage_error("--preset gltf writes its own JSON: it does not go with --csv or --json");
    if (rl.rotate && !gltf)
        return qcli_usage_error("--yaw and --rotate turn the lights of --preset gltf");
    if (gltf && (autom || error))
        return qcli_usage_error("--preset gltf writes JSON: it does not go with --auto or --error");
    if (json && error && !autom)
        return qcli_usage_error("--error prints a line of text: it does not go with --json");
    if (o.method == QIBL_LIGHTPROBE_MEDIANCUT && (n & (n - 1)) != 0)
        return qcli_usage_error("median cut makes 2^K lights: -n must be a power of two (or use --method "
                                    "adaptive)");

    if (qcli_parse_only) /* fuzz_cliopts: the options only */
        return 0;
    int w, h;
    uint8_t *px;
    char err[512];
    if (qtool_hdr_read_rgbe(path, &w, &h, &px, err, sizeof err) != 0)
        return fprintf(stderr, "qibl: %s\n", err), 1;
    {
        /* any layout to lat-long; said out loud (on stderr with --csv, which keeps stdout a table) */
        qtool_probe_layout_t used;
        int lw, lh;
        uint8_t *ll;
        if (qtool_probe_layout_rgbe_to_latlong(layout, w, h, px, &used, &lw, &lh, &ll, err, sizeof err) != 0) {
            free(px);
            return fprintf(stderr, "qibl: %s: %s\n", path, err), 1;
        }
        FILE *note = csv || json || gltf || cfmt ? stderr : stdout;
        fprintf(note, "%s: layout %s (%s, %s)", path, qtool_probe_layout_name(used), qtool_probe_layout_describe(used),
                layout == QTOOL_PROBE_LAYOUT_AUTO ? "detected" : "from --layout");
        if (used != QTOOL_PROBE_LAYOUT_LATLONG)
            fprintf(note, ", %d x %d resampled to a %d x %d lat-long", w, h, lw, lh);
        else if ((size_t)w != 2 * (size_t)h)
            fprintf(note, ", %d x %d is not 2:1: read as lat-long as asked", w, h);
        fprintf(note, "\n");
        free(px);
        px = ll, w = lw, h = lh;
    }
    if (autom) { /* the cheapest representation within the budget (tools/study/auto.c) */
        qtool_study_probe sp;
        int rc = qtool_study_probe_init(&sp, w, h, px, err, sizeof err);
        free(px);
        if (rc != 0)
            return fprintf(stderr, "qibl: lights: %s: %s\n", path, err), 1;
        /* with a document asked for, the table and the choice go to stderr and the pick to stdout */
        const int fmt = csv ? 1 : json ? 2 : cfmt ? 3 : 0;
        qtool_study_pick *pk = fmt ? malloc(sizeof *pk) : NULL;
        if (fmt && !pk) {
            qtool_study_probe_free(&sp);
            return fprintf(stderr, "qibl: lights: out of memory\n"), 1;
        }
        rc = qtool_study_auto(&sp, budget, 2, fmt ? stderr : stdout, pk, err, sizeof err);
        qtool_study_probe_free(&sp);
        if (rc < 0) {
            free(pk);
            return fprintf(stderr, "qibl: lights: %s: %s\n", path, err), 1;
        }
        if (fmt)
            write_pick(fmt, path, budget, pk);
        free(pk);
        return 0;
    }
    /* the picture's size is known now: refuse one the PNG writer could not take before any work */
    int z = zoom ? (int)zoom : (w >= 512 ? 1 : (1024 + w - 1) / w);
    if (png) {
        uint64_t pw = (uint64_t)w * (uint64_t)z, ph = (uint64_t)h * (uint64_t)z;
        if (pw > LIGHTS_PNG_MAX_SIDE || ph > LIGHTS_PNG_MAX_SIDE || pw * ph > LIGHTS_PNG_MAX_PIXELS) {
            free(px);
            return qcli_usage_error("--zoom %d: a %dx%d probe makes a %llux%llu picture; the limit is %u per side "
                                        "and %u pixels (try --zoom %llu)", z, w, h, (unsigned long long)pw,
                                        (unsigned long long)ph, LIGHTS_PNG_MAX_SIDE, LIGHTS_PNG_MAX_PIXELS,
                                        (unsigned long long)max_zoom(w, h));
        }
    }
    /* the probe as the core reads it: RGBE bytes as stored, or converted (exactly for f32) */
    qibl_lightprobe_image_t img;
    memset(&img, 0, sizeof img);
    img.width = (uint32_t)w;
    img.height = (uint32_t)h;
    img.pixels = px;
    void *conv = NULL;
    size_t np = (size_t)w * (size_t)h;
    if (strcmp(as, "rgbe") != 0) {
        uint32_t *f = malloc(sizeof *f * 3 * np);
        if (!f)
            return free(px), fprintf(stderr, "qibl: lights: out of memory\n"), 1;
        for (size_t i = 0; i < 3 * np; ++i) {
            float x = (float)rgbe_f(px[4 * (i / 3) + i % 3], px[4 * (i / 3) + 3]);
            memcpy(&f[i], &x, sizeof x);
        }
        if (strcmp(as, "f32") == 0) {
            conv = f;
            img.format = QIBL_LIGHTPROBE_LINEAR_F32;
        } else {
            uint8_t *s = malloc(4 * np);
            if (!s || qibl_srgbe_encode_f32_n(f, np, s) != QIBL_OK) {
                free(f), free(s), free(px);
                return fprintf(stderr, "qibl: lights: sRGBE conversion failed\n"), 1;
            }
            free(f);
            conv = s;
            img.format = QIBL_LIGHTPROBE_SRGBE;
        }
        img.pixels = conv;
    }
    qibl_lightprobe_method_t build_for = o.method == QIBL_LIGHTPROBE_VARMIN ||
                                                 o.priority == QIBL_LIGHTPROBE_PRIORITY_VARIANCE
                                             ? QIBL_LIGHTPROBE_VARMIN
                                             : QIBL_LIGHTPROBE_MEDIANCUT;
    size_t wsz = qibl_lightprobe_workspace_size(img.width, img.height, build_for);
    void *ws = wsz ? malloc(wsz) : NULL;
    qibl_lightprobe_light_t *L = malloc(sizeof *L * (size_t)n);
    int rc = 1;
    if (!ws || !L) {
        fprintf(stderr, "qibl: lights: %s\n",
                wsz ? "out of memory" : "probe too large (W, H <= 32768, W H <= 2^26)");
        goto out;
    }
    qibl_lightprobe_t lp;
    qibl_lightprobe_result_t res;
    qibl_status_t st = qibl_lightprobe_build(&lp, &img, build_for, ws, wsz);
    if (st == QIBL_OK)
        st = qibl_lightprobe_lights(&lp, &o, L, (uint32_t)n, &res);
    if (st == QIBL_E_PROBE_BLACK) {
        fprintf(stderr, "qibl: %s: %s\n", path, qibl_status_str(st));
        if (json) /* still a document: no lights */
            printf("{\"width\": %d, \"height\": %d, \"count\": 0, \"lights\": []}\n", w, h);
        if (gltf)
            qtool_engine_gltf_lights_write(stdout, NULL, NULL, 0, NULL, 0);
        rc = 0; /* a valid answer: no lights */
        goto out;
    }
    if (st != QIBL_OK) {
        fprintf(stderr, "qibl: %s: %s\n", path, qibl_status_str(st));
        goto out;
    }
    if (gltf) {
        double (*d)[3] = malloc(sizeof *d * (res.count ? res.count : 1)), (*c)[3] = malloc(sizeof *c * (res.count ? res.count : 1));
        char eerr[256];
        if (!d || !c) {
            free(d), free(c);
            fprintf(stderr, "qibl: lights: out of memory\n");
            goto out;
        }
        for (uint32_t i = 0; i < res.count; ++i)
            for (int k = 0; k < 3; ++k) { /* turned as relight turns the probe: light from d comes from r d */
                double v = 0.0;
                for (int j = 0; j < 3; ++j)
                    v += (rl.rotate ? rl.r[k][j] : (double)(k == j)) * (L[i].dir[j] / 1073741824.0);
                d[i][k] = v;
                c[i][k] = ldexp(L[i].rgb[k], res.rgb_exp);
            }
        int bad = qtool_engine_gltf_lights_write(stdout, (const double(*)[3])d, (const double(*)[3])c, res.count, eerr,
                                                 sizeof eerr);
        free(d), free(c);
        if (bad) {
            fprintf(stderr, "qibl: lights: %s: %s\n", path, eerr);
            goto out;
        }
    } else if (json) {
        static const char *jm[] = {"mediancut", "adaptive", "varmin"};
        printf("{\"probe\": \"");
        for (const char *q = path; *q; ++q) /* a JSON string: quotes, backslashes and control bytes escaped */
            printf((*q == '"' || *q == '\\') ? "\\%c" : (unsigned char)*q < 0x20 ? "\\u%04x" : "%c", *q);
        printf("\", \"width\": %d, \"height\": %d, \"method\": \"%s\", \"asked\": %ld, \"count\": %u,\n"
               " \"rgb\": \"irradiance of each region (E(n) = sum rgb max(0, n.dir))\",\n \"lights\": [",
               w, h, jm[o.method], n, res.count);
        for (uint32_t i = 0; i < res.count; ++i)
            printf("%s\n  {\"dir\": [%.9f, %.9f, %.9f], \"rgb\": [%.9g, %.9g, %.9g], \"region\": [%u, %u, %u, %u]}",
                   i ? "," : "", L[i].dir[0] / 1073741824.0, L[i].dir[1] / 1073741824.0, L[i].dir[2] / 1073741824.0,
                   ldexp(L[i].rgb[0], res.rgb_exp), ldexp(L[i].rgb[1], res.rgb_exp), ldexp(L[i].rgb[2], res.rgb_exp),
                   L[i].u0, L[i].v0, L[i].u1, L[i].v1);
        printf("\n]}\n");
    } else if (csv) {
        printf("x,y,z,r,g,b,u0,v0,u1,v1\n");
        for (uint32_t i = 0; i < res.count; ++i)
            printf("%.9f,%.9f,%.9f,%.9g,%.9g,%.9g,%u,%u,%u,%u\n", L[i].dir[0] / 1073741824.0,
                   L[i].dir[1] / 1073741824.0, L[i].dir[2] / 1073741824.0, ldexp(L[i].rgb[0], res.rgb_exp),
                   ldexp(L[i].rgb[1], res.rgb_exp), ldexp(L[i].rgb[2], res.rgb_exp), L[i].u0, L[i].v0, L[i].u1,
                   L[i].v1);
    } else {
        static const char *mn[] = {"median cut", "adaptive median cut", "variance minimisation"};
        printf("%s: %d x %d, %s, %u lights (asked %ld), brightest first; rgb is irradiance = integer * 2^%d\n",
               path, w, h, mn[o.method], res.count, n, res.rgb_exp);
        printf("%4s %11s %11s %11s %12s %12s %12s  %s\n", "#", "x", "y", "z", "r", "g", "b", "region u0 v0 u1 v1");
        for (uint32_t i = 0; i < res.count; ++i)
            printf("%4u %11.8f %11.8f %11.8f %12.6g %12.6g %12.6g  %u %u %u %u\n", i, L[i].dir[0] / 1073741824.0,
                   L[i].dir[1] / 1073741824.0, L[i].dir[2] / 1073741824.0, ldexp(L[i].rgb[0], res.rgb_exp),
                   ldexp(L[i].rgb[1], res.rgb_exp), ldexp(L[i].rgb[2], res.rgb_exp), L[i].u0, L[i].v0, L[i].u1,
                   L[i].v1);
    }
    rc = 0;
    if (error)
        print_error(px, w, h, L, res.count, res.rgb_exp);
    if (png) {
        rc = write_png(png, px, w, h, z, L, res.count);
        if (rc == 0 && !csv && !json && !gltf)
            printf("wrote %s (%d x %d): regions in green, light directions in red\n", png, w * z, h * z);
    }
out:
    free(ws), free(L), free(conv), free(px);
    return rc;
}
