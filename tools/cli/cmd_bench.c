/*
 * cmd_bench.c - `qibl bench`: the options into a qtool_bench_opts, then the benchmarks library
 * (tools/bench). Timing lives there, never in tests.
 */
#include <string.h>

#include "bench/bench.h"
#include "cli/cli.h"

int qcli_cmd_bench(int argc, char **argv)
{
    qtool_bench_opts o = {.what = "all"};
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--quick") == 0)
            o.quick = 1;
        else if (strcmp(argv[i], "--svg") == 0 && i + 1 < argc)
            o.svg = argv[++i];
        else if (strcmp(argv[i], "--markdown") == 0)
            o.markdown = 1;
        else if (strcmp(argv[i], "--csv") == 0)
            o.csv = 1;
        else if (argv[i][0] != '-')
            o.what = argv[i];
        else
            return qcli_usage_error("bench: unknown option '%s'", argv[i]);
    }
    if (!qtool_bench_known(o.what))
        return qcli_usage_error("bench: unknown benchmark '%s' (" QTOOL_BENCH_NAMES ")", o.what);
    if (qcli_parse_only) /* fuzz_cliopts: the options only */
        return 0;
    return qtool_bench_run(&o);
}
