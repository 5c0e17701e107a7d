/*
 * qibl/cli.h - the subcommand table of the qibl CLI and helpers every subcommand shares.
 *
 * Exit status: 0 success, 1 a failure while working (I/O, a core error on good arguments),
 * 2 bad arguments (one line on stderr).
 */
#ifndef QIBL_TOOLS_CLI_H
#define QIBL_TOOLS_CLI_H

#include <stddef.h>
#include <stdint.h>

typedef struct qibl_cli_cmd {
    const char *name;
    const char *summary; /* one line for `qibl --help` */
    const char *usage;   /* full text for `qibl help <cmd>` */
    int (*run)(int argc, char **argv); /* argv[0] is the subcommand name */
} qibl_cli_cmd;

int qibl_cmd_sh(int argc, char **argv);
int qibl_cmd_sh_project(int argc, char **argv); /* cmd_probe.c: `qibl sh project` */
int qibl_cmd_bench(int argc, char **argv);
int qibl_cmd_srgbe(int argc, char **argv);

/* Benchmarks (quick: smaller sizes and fewer repetitions; csv: table as CSV). */
int qibl_bench_relight(int quick, int csv);
int qibl_bench_relight_baselines(int quick); /* the u64-read / memcpy baselines alone */
int qibl_bench_srgbe(int quick); /* bench_srgbe.c */
int qibl_bench_lights(int quick); /* bench_lights.c */
int qibl_bench_paths(int quick);  /* bench_paths.c */
int qibl_bench_asset(int quick);  /* bench_asset.c */
/* The courtyard asset (w x h, k maps, RGB, P map) serialised in memory; *bytes malloc'ed. 0 or -1. */
int qibl_bench_make_asset(uint32_t w, uint32_t h, uint32_t k, uint32_t layout, uint8_t **bytes, size_t *n);
int qibl_bench_memory(int markdown); /* bench_memory.c */

/* What built the benchmarks, for their headers (the Makefile passes the core's flags). */
#ifndef QIBL_BENCH_CORE_FLAGS
#define QIBL_BENCH_CORE_FLAGS "(flags not recorded)"
#endif
#if defined(__clang__)
#define QIBL_BENCH_COMPILER "clang " __clang_version__
#elif defined(__GNUC__)
#define QIBL_BENCH_COMPILER "gcc " __VERSION__
#else
#define QIBL_BENCH_COMPILER "an unknown compiler"
#endif
int qibl_bench_probe(int quick);  /* bench_probe.c */
int qibl_bench_hemi(int quick);   /* bench_hemi.c */
int qibl_cmd_info(int argc, char **argv);
int qibl_cmd_gen(int argc, char **argv);
int qibl_cmd_relight(int argc, char **argv);
int qibl_cmd_lights(int argc, char **argv);

int qibl_cmd_render(int argc, char **argv); /* cmd_bake.c */
int qibl_cmd_bake(int argc, char **argv);
int qibl_cmd_merge(int argc, char **argv);
int qibl_cmd_check(int argc, char **argv);
int qibl_cmd_demo(int argc, char **argv); /* cmd_demo.c */

/* Scene and panorama options shared by render, bake and demo (cmd_bake.c): --scene builtin|FILE.obj|FILE.ply,
 * --zup, --raw, --size WxH, --equirect, --threads N. */
typedef struct qibl_cli_scene {
    const char *scene;
    int zup, raw, kind, threads;
    uint32_t w, h;
} qibl_cli_scene;
void qibl_cli_scene_defaults(qibl_cli_scene *o);
int qibl_cli_scene_opt(int argc, char **argv, int *i, qibl_cli_scene *o);
struct qibl_rt_scene;
int qibl_cli_scene_load(const qibl_cli_scene *o, struct qibl_rt_scene *s);
struct qibl_rt_light;
/* The light-path part of `qibl demo` (demo_paths.c): its table and RESULT lines on stdout,
 * paths_sheet.png in dir. today: the k = 16 shadowed asset (with YLUT). 0, or 1 after a message. */
struct qibl_bake_sums;
int qibl_demo_paths(const struct qibl_rt_scene *s, const qibl_cli_scene *so, uint32_t ndirs, int prop, int small,
                    const struct qibl_bake_sums *sums, const uint8_t *today, size_t today_n, const char *dir);
void qibl_cli_eval_lights(int obj_prop, int ndir, int npoint, struct qibl_rt_light *out);

/* --point without --rgb (point_default.c): C0 = QIBL_CLI_POINT_GREY * d^falloff, d the median
 * distance from pos to the n scene points pts (3 doubles each; points QIBL_CLI_SKY_DIST or more from
 * the origin are sky and skipped), so the lit scene comes out around mid-grey (Lambert, albedo 0.6,
 * facing the lamp at that distance: 0.6/pi x 2 = 0.38 linear, 166 of 255 through sRGB; the
 * courtyard's median pixel is about 110). *c0 is capped at
 * QIBL_CLI_Q16_MAX, *dist is d (1 when every point is sky). 0, or -1 (out of memory). */
#define QIBL_CLI_POINT_GREY 2.0
#define QIBL_CLI_SKY_DIST 1000.0
int qibl_cli_point_default(const double *pts, size_t n, const double pos[3], int falloff, double *c0, double *dist);
/* A note on stderr when the 8-bit RGB frame written to path has a mean below QIBL_CLI_DARK_MEAN. */
#define QIBL_CLI_DARK_MEAN 32.0
void qibl_cli_warn_dark(const char *path, const uint8_t *rgb, size_t np);

/* Prints "qibl: <message>" on stderr and returns 2 (the bad-arguments exit status). */
int qibl_cli_usage_error(const char *fmt, ...);

/* Parses a finite decimal into Q16.16, rounding to nearest; 0 on success, -1 if not a number or
 * out of the Q16.16 range. */
int qibl_cli_parse_q16(const char *s, int32_t *out);

/* Parses a finite decimal in [lo, hi] into *out; 0, or 2 (the bad-arguments exit status) after one
 * line naming the option and the value: "qibl: --rgb: 40000 is outside 0..32767.9999847 (why)"
 * (why may be NULL). */
int qibl_cli_parse_num(const char *opt, const char *s, double lo, double hi, const char *why, double *out);

/* The Q16.16 range the core's lights take, for options relight (and render, its ground truth) parse. */
#define QIBL_CLI_Q16_MAX (2147483647.0 / 65536.0)
#define QIBL_CLI_Q16_WHY "the Q16.16 range of the core's lights"

/* Parses "WxH" (decimal digits only) with both in 1..max; 0, or 2 after one line naming opt. */
int qibl_cli_parse_size(const char *opt, const char *s, long max, long *w, long *h);

/* The cube-map LUT face size of gen, bake and merge: `--lut-size N` (N in lo..QIBL_ASSET_MAX_LUT),
 * or the old `--lut N` with a deprecation note on stderr (relight's --lut is a sampling mode).
 * 1 if argv[*i] was one of them (*i advanced past N), 0 if not, -1 after a message on a bad N. */
int qibl_cli_lut_size_opt(int argc, char **argv, int *i, long lo, long *out);

/* Parses a decimal integer in [lo, hi]; 0 on success, -1 otherwise. */
int qibl_cli_parse_int(const char *s, long lo, long hi, long *out);

/* Parses --layout's argument: "planar" or "interleaved" into a QIBL_SHMAPS_* layout; 0 or -1. */
int qibl_cli_parse_layout(const char *s, uint32_t *layout);

/* Median of n values (sorts v in place). */
double qibl_cli_median(double *v, int n);

/* Monotonic time in seconds, for benchmarks. */
double qibl_cli_now(void);

#endif
