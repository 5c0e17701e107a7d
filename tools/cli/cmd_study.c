/*
 * cmd_study.c - `qibl study PROBES... --out DIR [--quick] [--threads T]`: the light-probe
 * approximation study of tools/study (every method, every N, every probe; CSV, SVG plots, PNG
 * overlays, summary.md, RESULT lines). Without probes it uses procedural skies and says so.
 */
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "cli/cli.h"
#include "opt/opt.h"
#include "study/study.h"

typedef struct study_cli_opts {
    qtool_opt_list probes;
    const char *out;
    long threads;
    int quick;
} study_cli_opts;
static const study_cli_opts study_defaults = {.out = NULL, .threads = 2, .quick = 0};

static const qtool_opt study_table[] = {
    {.name = "--out", .kind = QTOOL_OPT_STR, .off = offsetof(study_cli_opts, out), .arg = "DIR", .required = 1,
     .help = "where study.csv, summary.md, the plots and overlays go"},
    {.name = "--quick", .kind = QTOOL_OPT_FLAG, .off = offsetof(study_cli_opts, quick),
     .help = "half-size probes, 2000 normals, N <= 64"},
    {.name = "--threads", .kind = QTOOL_OPT_INT, .off = offsetof(study_cli_opts, threads), .arg = "T", .lo = 1,
     .hi = 16, .help = "worker threads"},
    {0},
};

static const qtool_opt_cmd study_spec = {
    QTOOL_OPT_CMD("study", study_table, study_defaults, "PROBE.hdr ...", 0, QTOOL_OPT_LIST_MAX, study_cli_opts,
                  probes),
    .prose =
        "  Ground-truth irradiance of each lat-long probe at 20000 spherical-Fibonacci normals (Madsen &\n"
        "  Laursen eq. 4 over every pixel), then median cut, adaptive, variance minimisation, SH 4/9/16/25,\n"
        "  the NNLS refit of median-cut and varmin directions, sun plus sky, LightGen-style k-means and\n"
        "  irradiance optimisation (Levenberg-Marquardt) for N = 1..256; writes DIR/study.csv, summary.md\n"
        "  (N to reach 10/5/2 % mean error), plot_*.svg, time_*.svg and overlay_*.png, and RESULT lines.\n"
        "  Without probes: procedural skies (said so). At most 64 probes.\n",
};

static int study_run(void *opts)
{
    const study_cli_opts *c = opts;
    const qtool_study_opts o = {.quick = c->quick, .threads = (int)c->threads, .out_dir = c->out};
    return qtool_study_run(c->probes.v, c->probes.n, &o);
}

const qcli_sub qcli_sub_study = {.opts = &study_spec, .run = study_run};
