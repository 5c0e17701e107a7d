/*
 * cmd_bench.c - `qibl bench`: speed against error for the core's modules. Timing lives here, never
 * in tests. Every figure is a median over repeated runs in this process; headline figures are also
 * printed as `RESULT <name> <value>` lines.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/gles_cli.h"
#include "qibl/sh.h"
#include "ref/sh_ref.h"

static uint64_t rng_next(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15u);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9u;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBu;
    return z ^ (z >> 31);
}

static volatile int32_t sink_i;
static volatile double sink_d;

static int bench_sh(int quick)
{
    const int n = quick ? 20000 : 200000, reps = quick ? 3 : 7;
    int32_t (*dir)[3] = malloc(sizeof *dir * (size_t)n);
    qibl_q30_t (*unit)[3] = malloc(sizeof *unit * (size_t)n);
    double (*ddir)[3] = malloc(sizeof *ddir * (size_t)n);
    if (!dir || !unit || !ddir) {
        fprintf(stderr, "qibl: bench sh: out of memory\n");
        free(dir), free(unit), free(ddir);
        return 1;
    }
    uint64_t s = 2024;
    for (int i = 0; i < n; ++i) {
        double z = 2.0 * (double)(rng_next(&s) >> 11) / 9007199254740992.0 - 1.0;
        double p = 6.283185307179586 * (double)(rng_next(&s) >> 11) / 9007199254740992.0;
        double r = sqrt(1.0 - z * z);
        dir[i][0] = (int32_t)lrint(r * cos(p) * 65536.0);
        dir[i][1] = (int32_t)lrint(r * sin(p) * 65536.0);
        dir[i][2] = (int32_t)lrint(z * 65536.0);
        if (!dir[i][0] && !dir[i][1] && !dir[i][2])
            dir[i][2] = 65536;
        for (int k = 0; k < 3; ++k)
            ddir[i][k] = dir[i][k];
        qibl_vec3_normalize_q30(dir[i], unit[i]);
    }
    /* accuracy over the same sweep */
    double max_err = 0.0, sum_err = 0.0;
    for (int i = 0; i < n; ++i) {
        qibl_q30_t y[25];
        double ref[25];
        qibl_sh_eval(dir[i], 5, y);
        qtool_ref_sh_eval(ddir[i][0], ddir[i][1], ddir[i][2], 5, ref);
        for (int k = 0; k < 25; ++k) {
            double e = fabs(y[k] / 1073741824.0 - ref[k]);
            sum_err += e;
            if (e > max_err)
                max_err = e;
        }
    }
    printf("== bench sh: SH basis, %d directions (Q16.16 unit-ish vectors), median of %d runs\n", n, reps);
    printf("%-40s %6s %12s %14s\n", "method", "bands", "ns/eval", "max |err|");
    double t_int[5] = {0}, t_unit = 0, t_ref = 0;
    for (int b = 2; b <= 5; ++b) {
        double t[9];
        for (int r = 0; r < reps; ++r) {
            double t0 = qcli_cpu_now();
            int32_t acc = 0;
            for (int i = 0; i < n; ++i) {
                qibl_q30_t y[25];
                qibl_sh_eval(dir[i], b, y);
                acc ^= y[b * b - 1];
            }
            sink_i = acc;
            t[r] = (qcli_cpu_now() - t0) / n * 1e9;
        }
        t_int[b - 1] = qcli_median(t, reps);
        printf("%-40s %6d %12.1f %14.3e\n", "qibl_sh_eval (integer)", b, t_int[b - 1], max_err);
    }
    {
        double t[9];
        for (int r = 0; r < reps; ++r) {
            double t0 = qcli_cpu_now();
            int32_t acc = 0;
            for (int i = 0; i < n; ++i) {
                qibl_q30_t y[25];
                qibl_sh_eval_unit(unit[i], 5, y);
                acc ^= y[24];
            }
            sink_i = acc;
            t[r] = (qcli_cpu_now() - t0) / n * 1e9;
        }
        t_unit = qcli_median(t, reps);
        printf("%-40s %6d %12.1f %14.3e\n", "qibl_sh_eval_unit (pre-normalised)", 5, t_unit, max_err);
    }
    {
        double t[9];
        for (int r = 0; r < reps; ++r) {
            double t0 = qcli_cpu_now();
            double acc = 0;
            for (int i = 0; i < n; ++i) {
                double y[25];
                qtool_ref_sh_eval(ddir[i][0], ddir[i][1], ddir[i][2], 5, y);
                acc += y[24];
            }
            sink_d = acc;
            t[r] = (qcli_cpu_now() - t0) / n * 1e9;
        }
        t_ref = qcli_median(t, reps);
        printf("%-40s %6d %12.1f %14s\n", "double reference (appendix recursion)", 5, t_ref, "(truth)");
    }
    printf("mean |err| over all 25 functions: %.3e; goal max |err| <= 2^-14 = %.3e\n", sum_err / (25.0 * n),
           1.0 / 16384.0);
    printf("RESULT sh.max_abs_err %.3e\n", max_err);
    printf("RESULT sh.eval25_ns %.1f\n", t_int[4]);
    printf("RESULT sh.eval25_unit_ns %.1f\n", t_unit);
    printf("RESULT sh.ref_over_int_time %.2f\n", t_ref / t_int[4]);
    free(dir), free(unit), free(ddir);
    return 0;
}

int qcli_cmd_bench(int argc, char **argv)
{
    const char *what = "all";
    int quick = 0, csv = 0, markdown = 0;
    const char *svg = NULL;
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--quick") == 0)
            quick = 1;
        else if (strcmp(argv[i], "--svg") == 0 && i + 1 < argc)
            svg = argv[++i];
        else if (strcmp(argv[i], "--markdown") == 0)
            markdown = 1;
        else if (strcmp(argv[i], "--csv") == 0)
            csv = 1;
        else if (argv[i][0] != '-')
            what = argv[i];
        else
            return qcli_usage_error("bench: unknown option '%s'", argv[i]);
    }
    static const char *const known[] = {"all", "sh", "relight", "baselines", "srgbe", "lights", "paths", "asset",
                                        "probe", "hemi", "memory", "gles"};
    int is_known = 0;
    for (size_t j = 0; j < sizeof known / sizeof known[0]; ++j)
        is_known |= strcmp(what, known[j]) == 0;
    if (!is_known)
        return qcli_usage_error("bench: unknown benchmark '%s' (all, sh, relight, baselines, srgbe, lights, paths, asset, probe, hemi, "
                                    "memory, gles)", what);
    if (qcli_parse_only) /* fuzz_cliopts: the options only */
        return 0;
    int all = strcmp(what, "all") == 0, rc = 0, ran = 0;
    if (all || strcmp(what, "sh") == 0)
        rc |= bench_sh(quick), ran = 1;
    if (all || strcmp(what, "relight") == 0)
        rc |= qcli_bench_relight(quick, csv), ran = 1;
    if (all || strcmp(what, "srgbe") == 0)
        rc |= qcli_bench_srgbe(quick), ran = 1;
    if (all || strcmp(what, "lights") == 0)
        rc |= qcli_bench_lights(quick), ran = 1;
    if (all || strcmp(what, "paths") == 0)
        rc |= qcli_bench_paths(quick), ran = 1;
    if (all || strcmp(what, "asset") == 0)
        rc |= qcli_bench_asset(quick), ran = 1;
    if (all || strcmp(what, "probe") == 0)
        rc |= qcli_bench_probe(quick), ran = 1;
    if (all || strcmp(what, "hemi") == 0)
        rc |= qcli_bench_hemi(quick, svg), ran = 1;
    /* already part of relight; alone for comparing builds */
    if (strcmp(what, "baselines") == 0)
        rc |= qcli_bench_relight_baselines(quick), ran = 1;
    /* not timing: the resident-memory table of docs/porting.md (exact, so not part of "all") */
    if (strcmp(what, "memory") == 0)
        rc |= qcli_bench_memory(markdown), ran = 1;
    if (strcmp(what, "gles") == 0) /* only when asked: a GL context is not part of `all` */
        rc |= qcli_bench_gles(quick), ran = 1;
    if (!ran)
        return qcli_usage_error("bench: unknown benchmark '%s' (all, sh, relight, baselines, srgbe, lights, paths, asset, probe, hemi, "
                                    "memory, gles)", what);
    return rc;
}
