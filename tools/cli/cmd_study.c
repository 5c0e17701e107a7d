/*
 * cmd_study.c - `qibl study PROBES... --out DIR [--quick] [--threads T]`: the light-probe
 * approximation study of tools/study (every method, every N, every probe; CSV, SVG plots, PNG
 * overlays, summary.md, RESULT lines). Without probes it uses procedural skies and says so.
 */
#include <stdio.h>
#include <string.h>

#include "cli/cli.h"
#include "study/study.h"

int qcli_cmd_study(int argc, char **argv)
{
    static const char *paths[64];
    int np = 0;
    qtool_study_opts o = {0, 2, NULL};
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--quick") == 0) {
            o.quick = 1;
        } else if (strcmp(argv[i], "--out") == 0) {
            if (++i >= argc)
                return qcli_usage_error("--out needs a directory");
            o.out_dir = argv[i];
        } else if (strcmp(argv[i], "--threads") == 0) {
            long t;
            if (++i >= argc || qcli_parse_int(argv[i], 1, 16, &t) != 0)
                return qcli_usage_error("--threads needs an integer in 1..16");
            o.threads = (int)t;
        } else if (argv[i][0] == '-' && argv[i][1] != '\0') {
            return qcli_usage_error("unknown option '%s'", argv[i]);
        } else {
            if (np == 64)
                return qcli_usage_error("more than 64 probes");
            paths[np++] = argv[i];
        }
    }
    if (!o.out_dir)
        return qcli_usage_error("--out DIR is required");
    if (qcli_parse_only) /* fuzz_cliopts: the options only */
        return 0;
    return qtool_study_run(paths, np, &o);
}
