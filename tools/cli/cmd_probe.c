/*
 * cmd_probe.c - `qibl sh project PROBE.hdr`: a Radiance probe (any layout, resampled to lat-long)
 * projected onto SH by the integer core (qibl/probe.h), row by row, printed as a labelled table
 * (l, m, R, G, B), JSON, the sh.txt lines Filament's cmgen writes, or a C header.
 */
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/relight_light.h"
#include "qibl/probe.h"

#define SH_PROJECT_USAGE                                                                                   \
    "usage: qibl sh project PROBE.hdr [--bands B] [--irradiance] [--window none|hann|lanczos] [--layout L] " \
    "[--format table|json|cmgen|c] [--name ID]"

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

int qcli_cmd_sh_project(int argc, char **argv)
{
    const char *path = NULL, *name = "qibl_probe_sh";
    long bands = QIBL_SH_MAX_BANDS;
    int fmt = FMT_TABLE;
    qtool_probe_layout_t layout = QTOOL_PROBE_LAYOUT_AUTO;
    qibl_probe_sh_opts_t opts = {0, QIBL_PROBE_WINDOW_NONE, 0};
    static const char *wnames[] = {"none", "hann", "lanczos"};
    static const char *fnames[] = {"table", "json", "cmgen", "c"};
    for (int i = 2; i < argc; ++i) {
        if (strcmp(argv[i], "--bands") == 0) {
            if (i + 1 >= argc || qcli_parse_int(argv[i + 1], 1, QIBL_SH_MAX_BANDS, &bands) != 0)
                return qcli_usage_error("--bands needs an integer in 1..%d", QIBL_SH_MAX_BANDS);
            ++i;
        } else if (strcmp(argv[i], "--irradiance") == 0) {
            opts.irradiance = 1;
        } else if (strcmp(argv[i], "--window") == 0) {
            int k = -1;
            for (int j = 0; i + 1 < argc && j < 3; ++j)
                if (strcmp(argv[i + 1], wnames[j]) == 0)
                    k = j;
            if (k < 0)
                return qcli_usage_error("--window needs none, hann or lanczos");
            opts.window = (qibl_probe_window_t)k;
            ++i;
        } else if (strcmp(argv[i], "--format") == 0) {
            fmt = -1;
            for (int j = 0; i + 1 < argc && j < 4; ++j)
                if (strcmp(argv[i + 1], fnames[j]) == 0)
                    fmt = j;
            if (fmt < 0)
                return qcli_usage_error("--format: '%s' is not table, json, cmgen or c", i + 1 < argc ? argv[i + 1] : "");
            ++i;
        } else if (strcmp(argv[i], "--layout") == 0) {
            if (i + 1 >= argc || qtool_probe_layout_parse(argv[i + 1], &layout) != 0)
                return qcli_usage_error("--layout: '%s' is not auto, latlong, angular, ball, vcross or hcross",
                                        i + 1 < argc ? argv[i + 1] : "");
            ++i;
        } else if (strcmp(argv[i], "--name") == 0) {
            if (i + 1 >= argc || !c_ident(argv[i + 1]))
                return qcli_usage_error("--name: '%s' is not a C identifier", i + 1 < argc ? argv[i + 1] : "");
            name = argv[++i];
        } else if (argv[i][0] == '-' || path) {
            return qcli_usage_error("sh project: unexpected '%s' (%s)", argv[i], SH_PROJECT_USAGE);
        } else {
            path = argv[i];
        }
    }
    if (!path)
        return qcli_usage_error(SH_PROJECT_USAGE);
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
    free(ws), free(px);
    if (st != QIBL_OK)
        return fprintf(stderr, "qibl: sh project: %s: %s\n", path, qibl_status_str(st)), 1;
    if (fmt == FMT_TABLE)
        printf("# %s", note);
    else
        fputs(note, stderr);
    const char *kind = opts.irradiance ? "irradiance (clamped cosine, A_l)" : "radiance";
    if (fmt == FMT_JSON) {
        printf("{\"probe\": \"");
        json_str(path);
        printf("\", \"layout\": \"%s\", \"width\": %d, \"height\": %d, \"bands\": %ld, \"irradiance\": %s, "
               "\"window\": \"%s\",\n \"basis\": \"qibl/sh.h: real SH, index l*l+l+m, z up, lat-long phi from +x "
               "toward +y\",\n \"coefficients\": [",
               qtool_probe_layout_name(used), w, h, bands, opts.irradiance ? "true" : "false", wnames[opts.window]);
        for (int l = 0; l < (int)bands; ++l)
            for (int m = -l; m <= l; ++m) {
                int i = l * l + l + m;
                printf("%s\n  {\"l\": %d, \"m\": %d, \"rgb\": [%.9g, %.9g, %.9g]}", i ? "," : "", l, m,
                       ldexp(c.c[0][i], c.exp), ldexp(c.c[1][i], c.exp), ldexp(c.c[2][i], c.exp));
            }
        printf("\n]}\n");
        return 0;
    }
    if (fmt == FMT_CMGEN) {
        /* The line layout of the sh.txt Filament's cmgen writes (google/filament,
         * tools/cmgen/src/cmgen.cpp, outputSh): "(" r ", " g ", " b "); // L" l m, each number
         * std::fixed, precision 15, width 18, with ", irradiance" when the coefficients are
         * irradiance. The values are qibl's (basis of sh.h, z up), not cmgen's shader-ready
         * "pre-scaled base" form nor its y-up frame: the label is never written. */
        for (int l = 0; l < (int)bands; ++l)
            for (int m = -l; m <= l; ++m) {
                int i = l * l + l + m;
                printf("(%18.15f, %18.15f, %18.15f); // L%d%d%s\n", ldexp(c.c[0][i], c.exp), ldexp(c.c[1][i], c.exp),
                       ldexp(c.c[2][i], c.exp), l, m, opts.irradiance ? ", irradiance" : "");
            }
        return 0;
    }
    if (fmt == FMT_C) {
        printf("/* ");
        c_comment_str(path);
        printf(": %dx%d, layout %s, bands %ld, %s, window %s.\n * Made by `qibl sh project --format c`; "
               "basis of qibl/sh.h (real SH, z up), index l*l + l + m. */\n",
               w, h, qtool_probe_layout_name(used), bands, kind, wnames[opts.window]);
        printf("#define %s_BANDS %ld\nstatic const float %s[%ld][3] = {\n", name, bands, name, bands * bands);
        for (int l = 0; l < (int)bands; ++l)
            for (int m = -l; m <= l; ++m) {
                int i = l * l + l + m;
                printf("    {");
                for (int ch = 0; ch < 3; ++ch) {
                    c_float(ldexp(c.c[ch][i], c.exp));
                    printf("%s", ch < 2 ? ", " : "");
                }
                printf("}, /* [%d] l = %d, m = %+d */\n", i, l, m);
            }
        printf("};\n");
        return 0;
    }
    printf("# %s: %dx%d lat-long, bands %ld, %s, window %s (qibl/sh.h basis, Wong et al.'s convention)\n", path, w,
           h, bands, kind, wnames[opts.window]);
    printf("# %2s %3s %16s %16s %16s\n", "l", "m", "R", "G", "B");
    for (int l = 0; l < (int)bands; ++l)
        for (int m = -l; m <= l; ++m) {
            int i = l * l + l + m;
            printf("  %2d %3d %16.9g %16.9g %16.9g\n", l, m, ldexp(c.c[0][i], c.exp), ldexp(c.c[1][i], c.exp),
                   ldexp(c.c[2][i], c.exp));
        }
    return 0;
}
