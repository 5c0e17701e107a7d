/*
 * twin_lights.c - qibl-bench's part of `bench lights`: the library's light-probe path (the kernel
 * set qibl_isa_active() picks: AVX2 where the CPU has it, on a dispatching build; QIBL_ISA
 * restricts it) against the scalar twin of the same source (tools/twin, the core's flags, forced
 * scalar), build + 64 median-cut lights, interleaved repetitions in one process, minimum and
 * median: RESULT lights.simd_speedup (scalar time / library time, of the minima). On the probe
 * `qibl bench lights` runs on. Not in the shipped qibl: it links the twin.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench.h"
#include "bench/twin.h"
#include "qibl/isa.h"
#include "qibl/lightprobe.h"
#include "twin/lightprobe_scalar.h"

/* The library's path against the scalar twin, interleaved: SAT and cut ms, min and median */
static int simd_vs_scalar(int quick, const char *name, const uint8_t *px, int w, int h)
{
    enum { MAXR = 41 };
    const int reps = quick ? 5 : MAXR;
    const size_t n = qibl_lightprobe_workspace_size((uint32_t)w, (uint32_t)h, QIBL_LIGHTPROBE_MEDIANCUT);
    uint8_t *ws[2] = {malloc(n), malloc(n)};
    qibl_lightprobe_light_t L[2][64];
    if (!ws[0] || !ws[1]) {
        free(ws[0]), free(ws[1]);
        return fprintf(stderr, "qibl: bench lights: out of memory\n"), 1;
    }
    memset(ws[0], 0, n), memset(ws[1], 0, n);
    qibl_lightprobe_image_t img;
    memset(&img, 0, sizeof img);
    img.pixels = px, img.width = (uint32_t)w, img.height = (uint32_t)h;
    const qibl_lightprobe_opts_t mc = {QIBL_LIGHTPROBE_MEDIANCUT, 0, 0};
    double t[2][2][MAXR]; /* [library, twin][SAT, cut][rep] */
    qibl_lightprobe_result_t res[2];
    for (int r = 0; r < reps; ++r)
        for (int p = 0; p < 2; ++p) {
            qibl_lightprobe_t lp;
            double t0 = qtool_bench_cpu_now();
            qibl_status_t st = p == 0 ? qibl_lightprobe_build(&lp, &img, QIBL_LIGHTPROBE_MEDIANCUT, ws[p], n)
                                      : qtool_lightprobe_build_scalar(&lp, &img, QIBL_LIGHTPROBE_MEDIANCUT, ws[p], n);
            double t1 = qtool_bench_cpu_now();
            if (st == QIBL_OK)
                st = p == 0 ? qibl_lightprobe_lights(&lp, &mc, L[p], 64, &res[p])
                            : qtool_lightprobe_lights_scalar(&lp, &mc, L[p], 64, &res[p]);
            double t2 = qtool_bench_cpu_now();
            if (st != QIBL_OK) {
                free(ws[0]), free(ws[1]);
                return fprintf(stderr, "qibl: bench lights: %s\n", qibl_status_str(st)), 1;
            }
            t[p][0][r] = (t1 - t0) * 1e3, t[p][1][r] = (t2 - t1) * 1e3;
        }
    /* the same bits, or the comparison means nothing */
    const int same = res[0].count == res[1].count && res[0].rgb_exp == res[1].rgb_exp &&
                     memcmp(L[0], L[1], sizeof L[0][0] * res[0].count) == 0 && memcmp(ws[0], ws[1], n) == 0;
    double mn[2][3], md[2][3];
    for (int p = 0; p < 2; ++p) {
        double tot[MAXR];
        for (int r = 0; r < reps; ++r)
            tot[r] = t[p][0][r] + t[p][1][r];
        for (int k = 0; k < 3; ++k) {
            double *v = k < 2 ? t[p][k] : tot;
            mn[p][k] = v[0];
            for (int r = 1; r < reps; ++r)
                mn[p][k] = v[r] < mn[p][k] ? v[r] : mn[p][k];
            md[p][k] = qtool_bench_median(v, reps);
        }
    }
    const double px_n = (double)w * (double)h;
    printf("\n== bench lights: SIMD path against the scalar twin, %s, %d x %d, build + median cut 64, %d interleaved reps\n",
           name, w, h, reps);
    printf("   built by %s, core %s; library path: %s\n", QTOOL_BENCH_COMPILER, QIBL_BENCH_CORE_FLAGS,
           qibl_isa_name(qibl_isa_active()));
    printf("%-22s %16s %16s %16s %10s\n", "path", "SAT ns/px", "cut ns/px", "total ms", "");
    printf("%-22s %7.2f (%6.2f) %7.2f (%6.2f) %7.3f (%6.3f)   min (median)\n", "library", 1e6 * mn[0][0] / px_n,
           1e6 * md[0][0] / px_n, 1e6 * mn[0][1] / px_n, 1e6 * md[0][1] / px_n, mn[0][2], md[0][2]);
    printf("%-22s %7.2f (%6.2f) %7.2f (%6.2f) %7.3f (%6.3f)\n", "scalar twin", 1e6 * mn[1][0] / px_n,
           1e6 * md[1][0] / px_n, 1e6 * mn[1][1] / px_n, 1e6 * md[1][1] / px_n, mn[1][2], md[1][2]);
    printf("   identical SAT and lights: %s; speed-up SAT %.2fx, cut %.2fx (medians: total %.2fx)\n", same ? "yes" : "NO",
           mn[1][0] / mn[0][0], mn[1][1] / mn[0][1], md[1][2] / md[0][2]);
    printf("RESULT lights.simd_speedup %.2f\n", mn[1][2] / mn[0][2]);
    free(ws[0]), free(ws[1]);
    return same ? 0 : (fprintf(stderr, "qibl: bench lights: SIMD and scalar differ\n"), 1);
}

int qtool_bench_twin_lights(int quick)
{
    return qtool_bench_lights_on_probe(quick, simd_vs_scalar);
}
