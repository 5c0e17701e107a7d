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

#include "bench/bench.h"
#include "relight/light.h" /* qtool_relight_point_default, behind qcli_point_default */
#include "bake/job.h"

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

/* Scene and panorama options shared by render, bake and demo: their option-table entries are
 * cli/scene_opts.h's; the struct, its defaults and the loader are tools/bake/scene.h's (qcli_scene
 * is qtool_scene_opts). */
typedef qtool_scene_opts qcli_scene;
/* QTOOL_SCENE_OPTS_DEFAULT with --threads the job's CPUs (qcli_default_threads) */
void qcli_scene_defaults(qcli_scene *o);
/* The default --threads (threads.c): the CPUs of the process's affinity mask (a job's allocation),
 * lowered to SLURM_CPUS_PER_TASK when that is set and smaller; 1..256. _from is the rule on given
 * figures (online CPUs, affinity count or 0 if unknown, the variable or NULL), for tests. */
int qcli_default_threads(void);
int qcli_threads_from(long online, long affinity, const char *slurm);
/* old names of what moved to tools/bake (scene.h, job.h) */
#define QCLI_SCENE_MAX_TRIANGLES QTOOL_SCENE_MAX_TRIANGLES
#define qcli_eval_lights qtool_bake_eval_lights
/* qtool_scene_load with its reason printed: 0, or 1 after printing the error */
int qcli_scene_load(const qcli_scene *o, struct qtool_rt_scene *s);
struct qtool_rt_light;

/* --point without --rgb: relight/light.h (qtool_relight_point_default); the old names for render and
 * bake, which still call them from here. */
#define QTOOL_CLI_POINT_GREY QTOOL_RELIGHT_POINT_GREY
#define QTOOL_CLI_SKY_DIST QTOOL_RELIGHT_SKY_DIST
#define qcli_point_default qtool_relight_point_default
/* A note on stderr when the 8-bit RGB frame written to path has a mean below QTOOL_CLI_DARK_MEAN
 * (cmd_relight.c). */
#define QTOOL_CLI_DARK_MEAN QTOOL_RELIGHT_DARK_MEAN
void qcli_warn_dark(const char *path, const uint8_t *rgb, size_t np);

/* Prints "qibl: <message>" on stderr and returns 2 (the bad-arguments exit status). */
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

/* Parses a decimal integer in [lo, hi]; 0 on success, -1 otherwise. */
int qcli_parse_int(const char *s, long lo, long hi, long *out);

/* The clocks and median of the benchmarks library (tools/bench/bench.h), which the demo and bake
 * commands time themselves with too. */
#define qcli_now qtool_bench_now
#define qcli_median qtool_bench_median

#endif
