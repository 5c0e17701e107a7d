/*
 * cmd_probe_info.c - `qibl probe info PROBE`: what a probe is and which lighting scheme fits it
 * (tools/probe/info.h measures and reports; the sun is relight's choice, qcli_probe_suns). Output is
 * all or nothing: the report is printed once everything has been computed.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/relight_light.h"
#include "probe/info.h"

#if QCLI_SUN_MAX > QTOOL_PROBE_INFO_MAX_SUNS
#error "qcli_probe_suns writes up to QCLI_SUN_MAX indices: QTOOL_PROBE_INFO_MAX_SUNS must hold them"
#endif

int qcli_cmd_probe(int argc, char **argv)
{
    const char *path = NULL;
    qtool_probe_layout_t layout = QTOOL_PROBE_LAYOUT_AUTO;
    if (argc < 2 || strcmp(argv[1], "info") != 0)
        return qcli_usage_error("usage: qibl probe info PROBE.hdr [--layout L]");
    for (int i = 2; i < argc; ++i) {
        if (strcmp(argv[i], "--layout") == 0) {
            if (i + 1 >= argc || qtool_probe_layout_parse(argv[i + 1], &layout) != 0)
                return qcli_usage_error("--layout: '%s' is not auto, latlong, angular, ball, vcross or hcross",
                                        i + 1 < argc ? argv[i + 1] : "");
            ++i;
        } else if (argv[i][0] == '-' || path) {
            return qcli_usage_error("probe info: unexpected '%s' (usage: qibl probe info PROBE.hdr [--layout L])",
                                    argv[i]);
        } else {
            path = argv[i];
        }
    }
    if (!path)
        return qcli_usage_error("usage: qibl probe info PROBE.hdr [--layout L]");
    if (qcli_parse_only) /* fuzz_cliopts: the options only */
        return 0;
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
