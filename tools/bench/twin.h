/*
 * tools/bench/twin.h - the benches of qibl-bench (twin_main.c), which time a core kernel against
 * its scalar twin (tools/twin, libqibl-twin.a) in one process. Kept out of libqibl-bench.a so the
 * shipped qibl never links a twin. 0, or 1 after a message (the twin and the library differ, or
 * out of memory).
 */
#ifndef QTOOL_BENCH_TWIN_H
#define QTOOL_BENCH_TWIN_H

int qtool_bench_twin_hemi(int quick);   /* twin_hemi.c: RESULT hemi.raster_lanes_speedup */
int qtool_bench_twin_lights(int quick); /* twin_lights.c: RESULT lights.simd_speedup */

#endif
