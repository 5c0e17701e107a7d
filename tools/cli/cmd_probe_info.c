/*
 * cmd_probe_info.c - `qibl probe info PROBE` (its option table, opt/opt.h): what a probe is and which lighting scheme fits it
 * (tools/probe/info.h measures and reports; the sun is relight's choice, qcli_probe_suns). Output is
 * all or nothing: the report is printed once everything has been computed.
 */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "opt/opt.h"
#include "cli/relight_light.h"
#include "probe/info.h"

#if QCLI_SUN_MAX > QTOOL_PROBE_INFO_MAX_SUNS
#error "qcli_probe_suns writes up to QCLI_SUN_MAX indices: QTOOL_PROBE_INFO_MAX_SUNS must hold them"
#endif

typedef struct probe_info_opts {
    qtool_opt_list probe;
    int layout; /* qtool_probe_layout_t */
} probe_info_opts;
static const probe_info_opts probe_info_defaults = {.layout = QTOOL_PROBE_LAYOUT_AUTO};

static const qtool_opt probe_info_table[] = {
    QCLI_LAYOUT_OPT(probe_info_opts, layout),
    {0},
};

static const qtool_opt_cmd probe_info_spec = {
    QTOOL_OPT_CMD("probe info", probe_info_table, probe_info_defaults, "PROBE.hdr", 1, 1, probe_info_opts, probe),
    .prose =
        "  Prints the probe's layout (detected, or --layout) and size, its luminance dynamic range\n"
        "  (max over the smallest non-zero pixel, in stops), the share of the energy in the brightest\n"
        "  0.1 % and 1 % of the sphere (pixels weighed by solid angle), and the irradiance error of four\n"
        "  ways to light with it against the probe's own irradiance (tools/study's one measure, as qibl\n"
        "  lights --auto prints it: |E - E_probe| / max(E_probe, mean E_probe / 10) per normal and\n"
        "  channel, mean and max over 4000 normals; probes wider than 1024 are box-averaged to 1024 x\n"
        "  512 for it, so the cost is one pass over the input plus a fixed amount): its SH (9\n"
        "  coefficients, the core's projection), 16 and 64 median-cut lights (the core's), and sun plus\n"
        "  SH (the sun as relight --probe-mode sunsky picks it, lit exactly; the rest as 9 SH\n"
        "  coefficients). Advice: the cheapest scheme (in that order) whose mean error is within 10 %\n"
        "  of the lowest or at most 1 %, with the relight option that uses it.\n",
};

static int probe_info_run(void *opts)
{
    const probe_info_opts *c = opts;
    const char *path = c->probe.v[0];
    const qtool_probe_layout_t layout = (qtool_probe_layout_t)c->layout;
    /* Nothing is printed until everything has been computed: a failure leaves stdout empty. */
    char note[4200 + 256], err[4800];
    int w, h;
    uint8_t *px;
    if (qcli_probe_load_note(path, layout, note, sizeof note, &w, &h, &px, NULL) != 0)
        return 1;
    qtool_probe_info_opts o = QTOOL_PROBE_INFO_OPTS_DEFAULT;
    o.pick_suns = qcli_probe_suns, o.sun_contrast = QCLI_SUN_CONTRAST;
    qtool_probe_info in;
    int rc = qtool_probe_info_compute(&o, path, px, w, h, &in, err, sizeof err);
    free(px);
    if (rc != 0)
        return fprintf(stderr, "qibl: %s\n", err), 1;
    qtool_probe_info_write(&o, &in, path, note, stdout);
    return 0;
}

const qcli_sub qcli_sub_probe_info = {.opts = &probe_info_spec, .run = probe_info_run};
