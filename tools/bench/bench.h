/*
 * tools/bench/bench.h - the benchmarks (speed against error) as a hosted tools library: what
 * `qibl bench` runs (tools/cli/cmd_bench.c parses the options and calls qtool_bench_run) and the
 * timing helpers they share. Every bench prints a human table on stdout and each headline figure
 * as one `RESULT <name> <value>` line; 0, or 1 after a message on stderr.
 *
 * Not here: the comparisons of a kernel against its scalar twin (tools/twin). The shipped `qibl`
 * does not link the twins; those live in twin_*.c, built into their own program
 * (build/bin/qibl-bench, tools/bench/twin_main.c), which `make bench` runs after `qibl bench all`.
 */
#ifndef QTOOL_BENCH_BENCH_H
#define QTOOL_BENCH_BENCH_H

#include <stddef.h>
#include <stdint.h>

#include "qibl/status.h" /* QIBL_OK, for QTOOL_BENCH_CALL */

/* What built the benchmarks, for their headers (the Makefile passes the core's flags). */
#ifndef QIBL_BENCH_CORE_FLAGS
#define QIBL_BENCH_CORE_FLAGS "(flags not recorded)"
#endif
#if defined(__clang__)
#define QTOOL_BENCH_COMPILER "clang " __clang_version__
#elif defined(__GNUC__)
#define QTOOL_BENCH_COMPILER "gcc " __VERSION__
#else
#define QTOOL_BENCH_COMPILER "an unknown compiler"
#endif

/* `qibl bench [what] [--quick] [--csv] [--markdown] [--svg PATH]`, parsed. Zero is the default:
 * what NULL is "all". */
typedef struct qtool_bench_opts {
    const char *what; /* all sh relight baselines srgbe lights paths asset probe hemi memory gles */
    int quick;        /* smaller sizes and fewer repetitions */
    int csv;          /* relight: the table as CSV */
    int markdown;     /* memory: the table as docs/porting.md has it */
    const char *svg;  /* hemi: the cloth's error against frames per second, as an SVG plot */
} qtool_bench_opts;

/* The names qtool_bench_run takes, comma-separated, for usage lines. */
#define QTOOL_BENCH_NAMES "all, sh, relight, baselines, srgbe, lights, paths, asset, probe, hemi, memory, gles"

/* 1 if name is one of QTOOL_BENCH_NAMES, else 0. */
int qtool_bench_known(const char *name);

/* Runs the benchmark o->what names ("all": every timing bench, not memory or gles). 0, 1 if any
 * bench failed (after its message), -1 if o->what is not a known name (nothing run). */
int qtool_bench_run(const qtool_bench_opts *o);

/* A core call inside a timed loop: its status is not dropped but folded into qtool_bench_failed
 * (a compare and an OR, nothing next to the kernel), which qtool_bench_run and qibl-bench check after
 * the benches, so a bench never reports the speed of a call that failed. */
extern int qtool_bench_failed;
#define QTOOL_BENCH_CALL(call) ((void)(qtool_bench_failed |= ((call) != QIBL_OK)))


/* The benches one by one (quick as above). */
int qtool_bench_sh(int quick);                     /* sh.c */
int qtool_bench_relight(int quick, int csv);       /* relight.c */
int qtool_bench_relight_baselines(int quick);      /* relight.c: the u64-read / memcpy baselines alone */
int qtool_bench_srgbe(int quick);                  /* srgbe.c */
int qtool_bench_lights(int quick);                 /* lights.c */
int qtool_bench_paths(int quick);                  /* paths.c */
int qtool_bench_asset(int quick);                  /* asset.c */
int qtool_bench_probe(int quick);                  /* probe.c */
int qtool_bench_hemi(int quick, const char *svg);  /* hemi.c; svg may be NULL */
int qtool_bench_memory(int markdown);              /* memory.c: not timing, exact */
int qtool_bench_gles(int quick);                   /* gles.c: skips without EGL/GLES2 at build time */

/* Runs run(quick, label, px, w, h) on the probe `bench lights` runs on: QIBL_PROBE, else
 * quarry_01_1k.hdr (or the first .hdr) of ../shared/fixtures/probes, else a procedural sun and sky
 * (px: w x h RGBE bytes, label names it; freed after). run's result, or 1 after a message when the
 * probe cannot be had. */
typedef int (*qtool_bench_probe_run)(int quick, const char *label, const uint8_t *px, int w, int h);
int qtool_bench_lights_on_probe(int quick, qtool_bench_probe_run run);

/* The courtyard asset (w x h, k maps, RGB, P map) serialised in memory; *bytes malloc'ed. 0 or -1. */
int qtool_bench_make_asset(uint32_t w, uint32_t h, uint32_t k, uint32_t layout, uint8_t **bytes, size_t *n);

/* ---- timing (timing.c) ---- */

/* Monotonic time in seconds. */
double qtool_bench_now(void);

/* CPU time of the calling thread in seconds: what the benchmarks' ratios are timed with, so that a
 * shared, loaded machine (time slices given to other processes) does not enter them. */
double qtool_bench_cpu_now(void);

/* Every bench's large arrays from fresh mappings whichever bench ran before (call once, first):
 * glibc raises its mmap threshold when a large block is freed, so after the relight bench's DRAM
 * buffers the next benches' arrays came from the reused heap and memory-bound figures depended on
 * the order (docs/results/round5-designs.txt, sRGBE round 7). No effect off glibc. */
void qtool_bench_fresh_arrays(void);

/* Median of n values (sorts v in place). */
double qtool_bench_median(double *v, int n);

/* Median over the repetitions r < n of num[r] / den[r]: a ratio whose two times were taken next
 * to each other in one interleaved loop, so a change of machine load between repetitions (a
 * shared, loaded host) cancels in each pair and outliers fall out of the median. n <= 64. */
double qtool_bench_paired_ratio(const double *num, const double *den, int n);

/* The memory-bandwidth floor the kernels are measured against: every whole 64-bit word of p[0..n)
 * read once (little-endian or not, summed: a sum, not a byte sum, which is instruction-bound). */
uint64_t qtool_bench_read_u64(const uint8_t *p, size_t n);

/* The smallest of n >= 1 values. */
double qtool_bench_min(const double *v, int n);

#endif
