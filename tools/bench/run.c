/*
 * run.c - qtool_bench_run: one name to the benches it stands for, in `qibl bench all`'s order.
 */
#include <stdio.h>
#include <string.h>

#include "bench/bench.h"

static const char *const known[] = {"all", "sh", "relight", "baselines", "srgbe", "lights", "paths", "asset",
                                    "probe", "hemi", "memory", "gles"};

int qtool_bench_known(const char *name)
{
    for (size_t j = 0; name && j < sizeof known / sizeof known[0]; ++j)
        if (strcmp(name, known[j]) == 0)
            return 1;
    return 0;
}

int qtool_bench_run(const qtool_bench_opts *o)
{
    const char *what = o->what ? o->what : "all";
    if (!qtool_bench_known(what))
        return -1;
    const int all = strcmp(what, "all") == 0, quick = o->quick;
    qtool_bench_fresh_arrays();
    int rc = 0;
    if (all || strcmp(what, "sh") == 0)
        rc |= qtool_bench_sh(quick);
    if (all || strcmp(what, "relight") == 0)
        rc |= qtool_bench_relight(quick, o->csv);
    if (all || strcmp(what, "srgbe") == 0)
        rc |= qtool_bench_srgbe(quick);
    if (all || strcmp(what, "lights") == 0)
        rc |= qtool_bench_lights(quick);
    if (all || strcmp(what, "paths") == 0)
        rc |= qtool_bench_paths(quick);
    if (all || strcmp(what, "asset") == 0)
        rc |= qtool_bench_asset(quick);
    if (all || strcmp(what, "probe") == 0)
        rc |= qtool_bench_probe(quick);
    if (all || strcmp(what, "hemi") == 0)
        rc |= qtool_bench_hemi(quick, o->svg);
    /* already part of relight; alone for comparing builds */
    if (strcmp(what, "baselines") == 0)
        rc |= qtool_bench_relight_baselines(quick);
    /* not timing: the resident-memory table of docs/porting.md (exact, so not part of "all") */
    if (strcmp(what, "memory") == 0)
        rc |= qtool_bench_memory(o->markdown);
    if (strcmp(what, "gles") == 0) /* only when asked: a GL context is not part of `all` */
        rc |= qtool_bench_gles(quick);
    if (qtool_bench_failed) {
        fprintf(stderr, "qibl bench: a core call inside a timed loop failed: the figures above are void\n");
        rc = 1;
    }
    return rc != 0;
}
