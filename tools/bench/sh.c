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

/* The fixed-seed sweep: Q16.16 directions, the same pre-normalised (Q2.30) and in double. */
typedef struct sweep {
    int n;
    int32_t (*dir)[3];
    qibl_q30_t (*unit)[3];
    double (*ddir)[3];
} sweep;

static volatile int32_t sink_i;
static volatile double sink_d;

/* One pass of each method over the sweep (bands b); the sinks keep the work. unit is a constant
 * at both calls, so each wrapper times a loop over its own entry point alone. */
static inline void pass_q30(const sweep *sw, int b, int unit)
{
    int32_t acc = 0;
    for (int i = 0; i < sw->n; ++i) {
        qibl_q30_t y[25];
        QTOOL_BENCH_CALL(unit ? qibl_sh_eval_unit(sw->unit[i], b, y) : qibl_sh_eval(sw->dir[i], b, y));
        acc ^= y[b * b - 1];
    }
    sink_i = acc;
}

static void pass_int(const sweep *sw, int b)
{
    pass_q30(sw, b, 0);
}

static void pass_unit(const sweep *sw, int b)
{
    pass_q30(sw, b, 1);
}

static void pass_ref(const sweep *sw, int b)
{
    double acc = 0;
    for (int i = 0; i < sw->n; ++i) {
        double y[25];
        qtool_ref_sh_eval(sw->ddir[i][0], sw->ddir[i][1], sw->ddir[i][2], b, y);
        acc += y[b * b - 1];
    }
    sink_d = acc;
}

/* ns per evaluation: the median over reps (<= 9) passes, thread CPU time */
static double ns_per_eval(void (*pass)(const sweep *, int), const sweep *sw, int b, int reps)
{
    double t[9];
    for (int r = 0; r < reps; ++r) {
        double t0 = qtool_bench_cpu_now();
        pass(sw, b);
        t[r] = (qtool_bench_cpu_now() - t0) / sw->n * 1e9;
    }
    return qtool_bench_median(t, reps);
}

static void make_sweep(sweep *sw)
{
    uint64_t s = 2024;
    for (int i = 0; i < sw->n; ++i) {
        int32_t *d = sw->dir[i];
        double z = 2.0 * (double)(rng_next(&s) >> 11) / 9007199254740992.0 - 1.0;
        double p = 2.0 * QTOOL_PI * (double)(rng_next(&s) >> 11) / 9007199254740992.0;
        double r = sqrt(1.0 - z * z);
        d[0] = (int32_t)lrint(r * cos(p) * 65536.0);
        d[1] = (int32_t)lrint(r * sin(p) * 65536.0);
        d[2] = (int32_t)lrint(z * 65536.0);
        if (!d[0] && !d[1] && !d[2])
            d[2] = 65536;
        for (int k = 0; k < 3; ++k)
            sw->ddir[i][k] = d[k];
        QTOOL_BENCH_CALL(qibl_vec3_normalize_q30(d, sw->unit[i]));
    }
}

int qtool_bench_sh(int quick)
{
    const int n = quick ? 20000 : 200000, reps = quick ? 3 : 7;
    sweep sw = {.n = n,
                .dir = malloc(sizeof *sw.dir * (size_t)n),
                .unit = malloc(sizeof *sw.unit * (size_t)n),
                .ddir = malloc(sizeof *sw.ddir * (size_t)n)};
    if (!sw.dir || !sw.unit || !sw.ddir) {
        fprintf(stderr, "qibl: bench sh: out of memory\n");
        free(sw.dir), free(sw.unit), free(sw.ddir);
        return 1;
    }
    make_sweep(&sw);
    /* accuracy over the same sweep */
    double max_err = 0.0, sum_err = 0.0;
    for (int i = 0; i < n; ++i) {
        qibl_q30_t y[25];
        double ref[25];
        QTOOL_BENCH_CALL(qibl_sh_eval(sw.dir[i], 5, y));
        qtool_ref_sh_eval(sw.ddir[i][0], sw.ddir[i][1], sw.ddir[i][2], 5, ref);
        for (int k = 0; k < 25; ++k) {
            double e = fabs(y[k] / 1073741824.0 - ref[k]);
            sum_err += e;
            if (e > max_err)
                max_err = e;
        }
    }
    printf("== bench sh: SH basis, %d directions (Q16.16 unit-ish vectors), median of %d runs\n", n, reps);
    printf("%-40s %6s %12s %14s\n", "method", "bands", "ns/eval", "max |err|");
    double t_int[5] = {0};
    for (int b = 2; b <= 5; ++b) {
        t_int[b - 1] = ns_per_eval(pass_int, &sw, b, reps);
        printf("%-40s %6d %12.1f %14.3e\n", "qibl_sh_eval (integer)", b, t_int[b - 1], max_err);
    }
    const double t_unit = ns_per_eval(pass_unit, &sw, 5, reps);
    printf("%-40s %6d %12.1f %14.3e\n", "qibl_sh_eval_unit (pre-normalised)", 5, t_unit, max_err);
    const double t_ref = ns_per_eval(pass_ref, &sw, 5, reps);
    printf("%-40s %6d %12.1f %14s\n", "double reference (appendix recursion)", 5, t_ref, "(truth)");
    printf("mean |err| over all 25 functions: %.3e; goal max |err| <= 2^-14 = %.3e\n", sum_err / (25.0 * n),
           1.0 / 16384.0);
    printf("RESULT sh.max_abs_err %.3e\n", max_err);
    printf("RESULT sh.eval25_ns %.1f\n", t_int[4]);
    printf("RESULT sh.eval25_unit_ns %.1f\n", t_unit);
    printf("RESULT sh.ref_over_int_time %.2f\n", t_ref / t_int[4]);
    free(sw.dir), free(sw.unit), free(sw.ddir);
    return 0;
}
