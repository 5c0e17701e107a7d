/*
 * twin_main.c - qibl-bench: the benches that time a core kernel against its scalar twin
 * (tools/twin) in one process, out of the shipped qibl. `make bench` runs it after `qibl bench all`.
 *
 * usage: qibl-bench [all|hemi|lights] [--quick]
 * Exit status: 0, 1 a bench failed, 2 bad arguments.
 */
#include <stdio.h>
#include <string.h>

#include "bench/bench.h"
#include "bench/twin.h"
#include "io/isa_env.h"

static int usage(const char *why)
{
    fprintf(stderr, "qibl-bench: %s\nusage: qibl-bench [all|hemi|lights] [--quick]\n", why);
    return 2;
}

int main(int argc, char **argv)
{
    const char *what = "all";
    int quick = 0;
    setvbuf(stdout, NULL, _IOLBF, 0);
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--quick") == 0)
            quick = 1;
        else if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0)
            return printf("usage: qibl-bench [all|hemi|lights] [--quick]\n"), 0;
        else if (argv[i][0] != '-')
            what = argv[i];
        else
            return usage("unknown option");
    }
    const int all = strcmp(what, "all") == 0;
    if (!all && strcmp(what, "hemi") != 0 && strcmp(what, "lights") != 0)
        return usage("unknown benchmark (all, hemi, lights)");
    /* QIBL_ISA names a kernel set this CPU runs, or nothing runs (as in qibl) */
    char isa_err[160];
    if (qtool_isa_env_check(isa_err, sizeof isa_err) != 0) {
        fprintf(stderr, "qibl-bench: %s\n", isa_err);
        return 2;
    }
    qtool_bench_fresh_arrays();
    int rc = 0;
    if (all || strcmp(what, "lights") == 0)
        rc |= qtool_bench_twin_lights(quick);
    if (all || strcmp(what, "hemi") == 0)
        rc |= qtool_bench_twin_hemi(quick);
    if (qtool_bench_failed) {
        fprintf(stderr, "qibl-bench: a core call inside a timed loop failed: the figures above are void\n");
        rc = 1;
    }
    return rc != 0;
}
