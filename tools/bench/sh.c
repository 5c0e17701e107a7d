/*
 * sh.c - `qibl bench sh`: the integer SH basis (qibl/sh.h) against the double reference of Wong et
 * al.'s appendix (tools/ref): ns per evaluation, median of repeated runs, and the max |error| over
 * the same fixed-seed sweep of directions.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "bench/bench.h"
#include "qibl/sh.h"
#include "qtool.h"
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

int qtool_bench_sh(int quick)
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
        double p = 2.0 * QTOOL_PI * (double)(rng_next(&s) >> 11) / 9007199254740992.0;
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
            double t0 = qtool_bench_cpu_now();
            int32_t acc = 0;
            for (int i = 0; i < n; ++i) {
                qibl_q30_t y[25];
                qibl_sh_eval(dir[i], b, y);
                acc ^= y[b * b - 1];
            }
            sink_i = acc;
            t[r] = (qtool_bench_cpu_now() - t0) / n * 1e9;
        }
        t_int[b - 1] = qtool_bench_median(t, reps);
        printf("%-40s %6d %12.1f %14.3e\n", "qibl_sh_eval (integer)", b, t_int[b - 1], max_err);
    }
    {
        double t[9];
        for (int r = 0; r < reps; ++r) {
            double t0 = qtool_bench_cpu_now();
            int32_t acc = 0;
            for (int i = 0; i < n; ++i) {
                qibl_q30_t y[25];
                qibl_sh_eval_unit(unit[i], 5, y);
                acc ^= y[24];
            }
            sink_i = acc;
            t[r] = (qtool_bench_cpu_now() - t0) / n * 1e9;
        }
        t_unit = qtool_bench_median(t, reps);
        printf("%-40s %6d %12.1f %14.3e\n", "qibl_sh_eval_unit (pre-normalised)", 5, t_unit, max_err);
    }
    {
        double t[9];
        for (int r = 0; r < reps; ++r) {
            double t0 = qtool_bench_cpu_now();
            double acc = 0;
            for (int i = 0; i < n; ++i) {
                double y[25];
                qtool_ref_sh_eval(ddir[i][0], ddir[i][1], ddir[i][2], 5, y);
                acc += y[24];
            }
            sink_d = acc;
            t[r] = (qtool_bench_cpu_now() - t0) / n * 1e9;
        }
        t_ref = qtool_bench_median(t, reps);
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
