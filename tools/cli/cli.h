/*
 * qibl/cli.h - the subcommand table of the qibl CLI and helpers every subcommand shares.
 *
 * Exit status: 0 success, 1 a failure while working (I/O, a core error on good arguments),
 * 2 bad arguments (one line on stderr).
 */
#ifndef QTOOL_TOOLS_CLI_H
#define QTOOL_TOOLS_CLI_H

#include <stddef.h>
#include <stdint.h>

/* Set by the option-parsing fuzz target (tests/fuzz/fuzz_cliopts.c) only: every command returns 0
 * once its options are parsed and checked, before it reads, computes or writes anything. */
extern int qcli_parse_only;

typedef struct qcli_cmd {
    const char *name;
    const char *summary; /* one line for `qibl --help` */
    const char *usage;   /* full text for `qibl help <cmd>` */
    int (*run)(int argc, char **argv); /* argv[0] is the subcommand name */
} qcli_cmd;

int qcli_cmd_sh(int argc, char **argv);
int qcli_cmd_sh_project(int argc, char **argv); /* cmd_probe.c: `qibl sh project` */
int qcli_cmd_bench(int argc, char **argv);
int qcli_cmd_srgbe(int argc, char **argv);

/* Benchmarks (quick: smaller sizes and fewer repetitions; csv: table as CSV). */
int qcli_bench_relight(int quick, int csv);
int qcli_bench_relight_baselines(int quick); /* the u64-read / memcpy baselines alone */
int qcli_bench_srgbe(int quick); /* bench_srgbe.c */
int qcli_bench_lights(int quick); /* bench_lights.c */
int qcli_bench_paths(int quick);  /* bench_paths.c */
int qcli_bench_asset(int quick);  /* bench_asset.c */
/* The courtyard asset (w x h, k maps, RGB, P map) serialised in memory; *bytes malloc'ed. 0 or -1. */
int qcli_bench_make_asset(uint32_t w, uint32_t h, uint32_t k, uint32_t layout, uint8_t **bytes, size_t *n);
int qcli_bench_memory(int markdown); /* bench_memory.c */

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
int qcli_bench_probe(int quick);  /* bench_probe.c */
int qcli_bench_hemi(int quick, const char *svg); /* bench_hemi.c; svg: the cloth's error against fps */
int qcli_cmd_info(int argc, char **argv);
int qcli_cmd_gen(int argc, char **argv);
int qcli_cmd_relight(int argc, char **argv);
int qcli_cmd_view(int argc, char **argv); /* cmd_view.c */
int qcli_cmd_transfer(int argc, char **argv); /* cmd_transfer.c (the computation: transfer/run.h) */
int qcli_cmd_lights(int argc, char **argv);
int qcli_cmd_probe(int argc, char **argv); /* cmd_probe_info.c: `qibl probe info` */
int qcli_cmd_study(int argc, char **argv); /* cmd_study.c */
int qcli_cmd_ies(int argc, char **argv);   /* cmd_ies.c: `qibl ies info` */

int qcli_cmd_render(int argc, char **argv); /* cmd_bake.c */
int qcli_cmd_bake(int argc, char **argv);
int qcli_cmd_merge(int argc, char **argv);
int qcli_cmd_check(int argc, char **argv);
int qcli_cmd_demo(int argc, char **argv); /* cmd_demo.c */

/* Scene and panorama options shared by render, bake and demo (cmd_bake.c): --scene builtin|FILE.obj|FILE.ply,
 * --zup, --raw, --size WxH, --equirect, --threads N. */
typedef struct qcli_scene {
    const char *scene;
    int zup, raw, kind, threads;
    uint32_t w, h;
} qcli_scene;
void qcli_scene_defaults(qcli_scene *o);
/* The default --threads (threads.c): the CPUs of the process's affinity mask (a job's allocation),
 * lowered to SLURM_CPUS_PER_TASK when that is set and smaller; 1..256. _from is the rule on given
 * figures (online CPUs, affinity count or 0 if unknown, the variable or NULL), for tests. */
int qcli_default_threads(void);
int qcli_threads_from(long online, long affinity, const char *slurm);
int qcli_scene_opt(int argc, char **argv, int *i, qcli_scene *o);
struct qtool_rt_scene;
/* triangles of a --scene mesh (render, bake, demo), checked before the mesh is allocated: the mesh
 * (144 bytes a triangle) and its BVH stay near 0.3 GiB (docs/robustness.md) */
#define QCLI_SCENE_MAX_TRIANGLES ((size_t)1 << 20)
int qcli_scene_load(const qcli_scene *o, struct qtool_rt_scene *s);
struct qtool_rt_light;
/* The light-path part of `qibl demo` (demo_paths.c): its table and RESULT lines on stdout,
 * paths_sheet.png in dir. today: the k = 16 shadowed asset (with YLUT). 0, or 1 after a message. */
struct qtool_bake_sums;
/* The demo's sizes in one place (cmd_demo.c): `small` is CI's (DEMO_SIZE=small), `default` what
 * `make demo` runs for a newcomer (within 90 s on an idle 2-core machine), `full` the README's
 * pictures (`make demo FULL=1`: the probe-lit truths alone are minutes of CPU). */
typedef struct qcli_demo_size {
    const char *name;
    uint32_t w, h;        /* panorama */
    long ndirs, frames;   /* bake directions, frames per sweep */
    uint32_t path_steps;  /* visibility steps along the sun path and lamp track */
    uint32_t sky_dirs;    /* directions of the ray-traced sky truth */
    uint32_t probe_spp;   /* samples per pixel in each of the two probe-lit truth renders */
} qcli_demo_size;
int qtool_demo_paths(const struct qtool_rt_scene *s, const qcli_scene *so, uint32_t ndirs, int prop,
                    const qcli_demo_size *sz, const struct qtool_bake_sums *sums, const uint8_t *today,
                    size_t today_n, const char *dir);
/* The "lit by a real probe" part of `qibl demo` (demo_probe.c): three probes (../shared's, or
 * procedural ones), ray-traced truth, SH / median-cut lights / sun + SH relit by the core; its table
 * and RESULT lines on stdout, probe_sheet.png in dir. 0, or 1 after a message. */
/* demo_paths.c, shared with demo_probe.c: the error heat map of a against b (max channel
 * difference, full scale 48 of 255; pixels whose cls is 0 black), and the payload bytes of the
 * index-th chunk of a type in an asset (0 when absent or the asset is bad). */
void qcli_demo_heat(const uint8_t *a, const uint8_t *b, const uint8_t *cls, size_t np, uint8_t *out);
double qcli_asset_chunk_bytes(const uint8_t *asset, size_t n, uint32_t type, uint32_t index);
int qcli_demo_probe(const struct qtool_rt_scene *s, const qcli_scene *so, const qcli_demo_size *sz,
                    const struct qtool_bake_sums *sums, uint32_t ndirs, const char *dir);
void qcli_eval_lights(int obj_prop, int ndir, int npoint, struct qtool_rt_light *out);

/* --point without --rgb (point_default.c): C0 = QTOOL_CLI_POINT_GREY * d^falloff, d the median
 * distance from pos to the n scene points pts (3 doubles each; points QTOOL_CLI_SKY_DIST or more from
 * the origin are sky and skipped), so the lit scene comes out around mid-grey (Lambert, albedo 0.6,
 * facing the lamp at that distance: 0.6/pi x 2 = 0.38 linear, 166 of 255 through sRGB; the
 * courtyard's median pixel is about 110). *c0 is capped at
 * QTOOL_CLI_Q16_MAX, *dist is d (1 when every point is sky). 0, or -1 (out of memory). */
#define QTOOL_CLI_POINT_GREY 2.0
#define QTOOL_CLI_SKY_DIST 1000.0
int qcli_point_default(const double *pts, size_t n, const double pos[3], int falloff, double *c0, double *dist);
/* A note on stderr when the 8-bit RGB frame written to path has a mean below QTOOL_CLI_DARK_MEAN. */
#define QTOOL_CLI_DARK_MEAN 32.0
void qcli_warn_dark(const char *path, const uint8_t *rgb, size_t np);

/* Prints "qibl: <message>" on stderr and returns 2 (the bad-arguments exit status). */
/* relight_path.c: whether a relight command line names a baked light path (--path), and that relight. */
int qcli_relight_has_path(int argc, char **argv);
int qcli_relight_path(int argc, char **argv);

int qcli_usage_error(const char *fmt, ...);

/* Parses a finite decimal into Q16.16, rounding to nearest; 0 on success, -1 if not a number or
 * out of the Q16.16 range. */
int qcli_parse_q16(const char *s, int32_t *out);

/* Parses a finite decimal in [lo, hi] into *out; 0, or 2 (the bad-arguments exit status) after one
 * line naming the option and the value: "qibl: --rgb: 40000 is outside 0..32767.9999847 (why)"
 * (why may be NULL). */
int qcli_parse_num(const char *opt, const char *s, double lo, double hi, const char *why, double *out);

/* The Q16.16 range the core's lights take, for options relight (and render, its ground truth) parse. */
#define QTOOL_CLI_Q16_MAX (2147483647.0 / 65536.0)
#define QTOOL_CLI_Q16_WHY "the Q16.16 range of the core's lights"

/* Parses "WxH" (decimal digits only) with both in 1..max; 0, or 2 after one line naming opt. */
int qcli_parse_size(const char *opt, const char *s, long max, long *w, long *h);

/* The cube-map LUT face size of gen, bake and merge: `--lut-size N` (N in lo..QIBL_ASSET_MAX_LUT),
 * or the old `--lut N` with a deprecation note on stderr (relight's --lut is a sampling mode).
 * 1 if argv[*i] was one of them (*i advanced past N), 0 if not, -1 after a message on a bad N. */
int qcli_lut_size_opt(int argc, char **argv, int *i, long lo, long *out);

/* Parses a decimal integer in [lo, hi]; 0 on success, -1 otherwise. */
int qcli_parse_int(const char *s, long lo, long hi, long *out);

/* Parses --layout's argument: "planar" or "interleaved" into a QIBL_SHMAPS_* layout; 0 or -1. */
int qcli_parse_layout(const char *s, uint32_t *layout);

/* Median of n values (sorts v in place). */
double qcli_median(double *v, int n);

/* Median over the repetitions r < n of num[r] / den[r]: a ratio whose two times were taken next
 * to each other in one interleaved loop, so a change of machine load between repetitions (a
 * shared, loaded host) cancels in each pair and outliers fall out of the median. n <= 64. */
double qcli_paired_ratio(const double *num, const double *den, int n);

/* Monotonic time in seconds, for benchmarks. */
double qcli_now(void);

/* CPU time of the calling thread in seconds: what the benchmarks' ratios are timed with, so that a
 * shared, loaded machine (time slices given to other processes) does not enter them. */
double qcli_cpu_now(void);

#endif
