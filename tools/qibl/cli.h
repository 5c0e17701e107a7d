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
int qibl_bench_srgbe(int quick); /* bench_srgbe.c */
int qibl_bench_lights(int quick); /* bench_lights.c */
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

/* Scene and panorama options shared by render, bake and demo (cmd_bake.c): --scene builtin|FILE.obj,
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
void qibl_cli_eval_lights(int obj_prop, int ndir, int npoint, struct qibl_rt_light *out);

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

/* Parses a decimal integer in [lo, hi]; 0 on success, -1 otherwise. */
int qibl_cli_parse_int(const char *s, long lo, long hi, long *out);

/* Median of n values (sorts v in place). */
double qibl_cli_median(double *v, int n);

/* Monotonic time in seconds, for benchmarks. */
double qibl_cli_now(void);

#endif
