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
#include "relight/spec.h"    /* the light options' rules, QTOOL_RELIGHT_Q16_MAX */
#include "bake/job.h"
#include "opt/opt.h"

/* Set by the option-parsing fuzz target (tests/fuzz/fuzz_cliopts.c) only: every command returns 0
 * once its options are parsed and checked, before it reads, computes or writes anything. */
extern int qcli_parse_only;

/* One command, or one subcommand, as qcli_run runs it: argv parsed by its option table into a fresh
 * options struct (opt/opt.h), then check, then, unless qcli_parse_only, run. So a command file holds
 * its table, its rules and its work, and the parse, the refusals and fuzz_cliopts's stop are here
 * once. */
typedef struct qcli_sub {
    const qtool_opt_cmd *opts;
    /* NULL, or the table (of the same options struct) argv asks for instead: relight --path */
    const qtool_opt_cmd *(*pick)(int argc, char **argv);
    /* NULL, or the rules across options; it may fill the struct's derived fields for run. 0, or 2
     * after the one line */
    int (*check)(void *o);
    /* NULL, or a check that reads the line as spelled too (view: which mode's option came first) */
    int (*check_line)(void *o, int argc, char **argv);
    int (*run)(void *o); /* the work: 0, 1 failed (said on stderr) or 2 */
    void (*drop)(void *o); /* NULL, or frees what parsing allocated, however it ended (merge's SUMS) */
    int whole; /* runs under qcli_parse_only too: it reads nothing and prints a few numbers (sh eval) */
} qcli_sub;

typedef struct qcli_cmd {
    const char *name;
    const char *summary; /* one line for `qibl --help` */
    /* NULL-terminated: the command's own, or a family whose subcommand argv[1] names ("sh eval") */
    const qcli_sub *const *subs;
} qcli_cmd;

/* The commands (main.c), in `qibl --help`'s order, and the one named; NULL if none. */
extern const qcli_cmd qcli_commands[];
extern const size_t qcli_ncommands;
const qcli_cmd *qcli_find(const char *name);
/* Runs c on argv (argv[0] its name): the exit status. */
int qcli_run(const qcli_cmd *c, int argc, char **argv);

extern const qcli_sub qcli_sub_sh_eval, qcli_sub_sh_plot, qcli_sub_sh_project, qcli_sub_srgbe_encode,
    qcli_sub_srgbe_decode, qcli_sub_ies_info, qcli_sub_probe_info;
extern const qcli_sub qcli_sub_luminaire_capture, qcli_sub_luminaire_info, qcli_sub_luminaire_render,
    qcli_sub_luminaire_study, qcli_sub_luminaire_passes, qcli_sub_luminaire_picture;
extern const qcli_sub qcli_sub_bench, qcli_sub_gen, qcli_sub_render, qcli_sub_transfer, qcli_sub_bake,
    qcli_sub_merge, qcli_sub_check, qcli_sub_demo, qcli_sub_relight, qcli_sub_view, qcli_sub_info, qcli_sub_lights,
    qcli_sub_study;

/* --lut-size N of gen, bake and merge (the cube-map Y LUT's face size, a long at member of type), and
 * its old spelling --lut (a note says why it was renamed) */
#define QCLI_LUT_SIZE_OPTS(type, member)                                                                         \
    {.name = "--lut-size", .kind = QTOOL_OPT_INT, .off = offsetof(type, member), .arg = "N", .lo = 0,             \
     .hi = QIBL_ASSET_MAX_LUT, .what = "a face size", .why = "0: no LUT", .help = "the cube-map Y LUT's face size"}, \
    {.name = "--lut", .kind = QTOOL_OPT_INT, .off = offsetof(type, member), .arg = "N", .lo = 0,                  \
     .hi = QIBL_ASSET_MAX_LUT, .what = "a face size", .why = "0: no LUT", .renamed = "--lut-size",               \
     .note = "relight's --lut is the sampling mode"}

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

/* Parses the three words of a direction option (relight's --aim/--up, view's --sun) into Q16.16:
 * NULL with out written, or the reason with out untouched: "'<word>' is not a number in the Q16.16
 * range" in why (at most width characters of the word; -1: all of it), or zero_why when all three
 * round to 0. */
const char *qcli_parse_q16_dir(char *const *v, int width, const char *zero_why, int32_t out[3], char *why,
                               size_t whylen);

/* Parses "AZ,EL" (degrees, finite, |EL| <= el_max: transfer's --view, view's --camera); 0, or -1
 * with nothing written. */
int qcli_parse_azel(const char *s, double el_max, double *az, double *el);

/* Parses a finite decimal in [lo, hi] into *out; 0, or 2 (the bad-arguments exit status) after one
 * line naming the option and the value: "qibl: --rgb: 40000 is outside 0..32767.9999847 (why)"
 * (why may be NULL). */
int qcli_parse_num(const char *opt, const char *s, double lo, double hi, const char *why, double *out);

/* The Q16.16 range the core's lights take, for options relight (and render, its ground truth) parse. */
#define QTOOL_CLI_Q16_MAX QTOOL_RELIGHT_Q16_MAX /* relight/spec.h */
#define QTOOL_CLI_Q16_WHY QTOOL_RELIGHT_Q16_WHY

/* Parses "WxH" (decimal digits only) with both in 1..max; 0, or 2 after one line naming opt. */
int qcli_parse_size(const char *opt, const char *s, long max, long *w, long *h);

/* Parses a decimal integer in [lo, hi]; 0 on success, -1 otherwise. */
int qcli_parse_int(const char *s, long lo, long hi, long *out);

/* The clocks and median of the benchmarks library (tools/bench/bench.h), which the demo and bake
 * commands time themselves with too. */
#define qcli_now qtool_bench_now
#define qcli_median qtool_bench_median

#endif
