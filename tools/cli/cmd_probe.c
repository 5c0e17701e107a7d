/*
 * cmd_probe.c - `qibl sh project PROBE.hdr`: a Radiance lat-long probe projected onto SH by the
 * integer core (qibl/probe.h), row by row, printed as a labelled table (l, m, R, G, B).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/hdr.h"
#include "cli/cli.h"
#include "qibl/probe.h"

#define SH_PROJECT_USAGE "usage: qibl sh project PROBE.hdr [--bands B] [--irradiance] [--window none|hann|lanczos]"

int qcli_cmd_sh_project(int argc, char **argv)
{
    const char *path = NULL;
    long bands = QIBL_SH_MAX_BANDS;
    qibl_probe_sh_opts_t opts = {0, QIBL_PROBE_WINDOW_NONE, 0};
    static const char *wnames[] = {"none", "hann", "lanczos"};
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
    char err[512];
    if (qtool_hdr_read_rgbe(path, &w, &h, &px, err, sizeof err) != 0)
        return fprintf(stderr, "qibl: %s\n", err), 1;
    if (w != 2 * h)
        fprintf(stderr, "qibl: warning: %s is %dx%d, not 2:1; read as lat-long anyway\n", path, w, h);
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
    printf("# %s: %dx%d lat-long, bands %ld, %s, window %s (qibl/sh.h basis, Wong et al.'s convention)\n", path, w,
           h, bands, opts.irradiance ? "irradiance (clamped cosine, A_l)" : "radiance", wnames[opts.window]);
    printf("# %2s %3s %16s %16s %16s\n", "l", "m", "R", "G", "B");
    for (int l = 0; l < (int)bands; ++l)
        for (int m = -l; m <= l; ++m) {
            int i = l * l + l + m;
            printf("  %2d %3d %16.9g %16.9g %16.9g\n", l, m, ldexp(c.c[0][i], c.exp), ldexp(c.c[1][i], c.exp),
                   ldexp(c.c[2][i], c.exp));
        }
    return 0;
}
