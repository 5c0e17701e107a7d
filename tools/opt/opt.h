/*
 * opt/opt.h - one option table per command: its parser, its `qibl help` text and its errors all
 * come from the table, so help cannot omit a flag and every bad argument gets the same answer:
 *
 *     qibl CMD: <what is wrong, naming the flag and the value>; see qibl help CMD      (exit 2)
 *
 * How to convert a command (this is `qibl study`, tools/cli/cmd_study.c, as it is):
 *
 *  1. An options struct and its defaults, in one place, designated-initialised. Each kind has one
 *     C type (below); the table says where a value goes with offsetof.
 *
 *         typedef struct study_cli_opts {
 *             qtool_opt_list probes;   // the positional arguments
 *             const char *out;        // STR
 *             long threads;           // INT
 *             int quick;              // FLAG: 0 or 1
 *         } study_cli_opts;
 *         static const study_cli_opts study_defaults = {.out = NULL, .threads = 2, .quick = 0};
 *
 *  2. The table: one entry per flag, designated initialisers, ended by {0}. Help shows the default
 *     read from study_defaults (write .def = "..." only for a default computed at run time), the
 *     range from .lo/.hi, and .help; the errors name the flag, the value and the range.
 *
 *         static const qtool_opt study_table[] = {
 *             {.name = "--out", .kind = QTOOL_OPT_STR, .off = offsetof(study_cli_opts, out), .arg = "DIR",
 *              .required = 1, .help = "where study.csv, summary.md, the plots and overlays go"},
 *             {.name = "--quick", .kind = QTOOL_OPT_FLAG, .off = offsetof(study_cli_opts, quick),
 *              .help = "half-size probes, 2000 normals, N <= 64"},
 *             {.name = "--threads", .kind = QTOOL_OPT_INT, .off = offsetof(study_cli_opts, threads),
 *              .arg = "T", .lo = 1, .hi = 16, .help = "worker threads"},
 *             {0},
 *         };
 *         static const qtool_opt_cmd study_spec = {
 *             // .name, .opts, .defaults, .size and .pos (PROBE.hdr ...: 0 to 64 of them, into probes)
 *             QTOOL_OPT_CMD("study", study_table, study_defaults, "PROBE.hdr ...", 0, QTOOL_OPT_LIST_MAX,
 *                           study_cli_opts, probes),
 *             .prose = "  Ground-truth irradiance of each lat-long probe ... (two-space indented lines)\n",
 *         };
 *
 *     More kinds in real tables: ENUM with .names and a SIZE in cmd_gen.c (and a deprecated
 *     spelling, .renamed/.note), subcommands in cmd_sh.c and cmd_srgbe.c, numeric positionals
 *     (.pos.numbers = 1: "-1" and "-inf" are values, not unknown flags) in `sh eval`; callbacks of
 *     three values in order (relight's --sun/--rgb), of one or three (--camera, cli/scene_opts.h),
 *     an optional value (lights --error [P%]), --progress=MODE (bake), any number of files (merge).
 *
 *  3. The command's work takes the parsed struct; the CLI (cli/cli.h: qcli_sub, qcli_run) parses
 *     argv into it, refuses, and stops there for the option fuzzer. What the table cannot say
 *     (cross-option rules) is a check hook, refusing through qtool_opt_error so that line has the
 *     same shape:
 *
 *         static int study_run(void *opts)
 *         {
 *             const study_cli_opts *c = opts;
 *             const qtool_study_opts o = {.quick = c->quick, .threads = (int)c->threads, .out_dir = c->out};
 *             return qtool_study_run(c->probes.v, c->probes.n, &o);
 *         }
 *         const qcli_sub qcli_sub_study = {.opts = &study_spec, .run = study_run}; // cli.h declares it
 *
 *  4. main.c: a row {"study", "<summary>", SUBS(&qcli_sub_study)} in qcli_commands; `qibl help`
 *     and `qibl help --flags` read the same tables, and tests/cli_opts_test.c then checks its
 *     unknown-flag line, that help names every flag, and that the parser knows each one. A command
 *     of subcommands has a table each (.name = "sh eval": `qibl help sh` is its help) and a qcli_sub each in
 *     its row; qcli_run picks one with qtool_opt_sub.
 *
 * Kinds and the C type at .off: FLAG int (set to 1); INT long in [lo, hi]; NUM double in [lo, hi];
 * STR const char *; ENUM int (index into names); SIZE long[2] ("WxH", both in 1..hi); TRIPLE double[3]
 * (three arguments, each in [lo, hi]); LIST qtool_opt_list (the flag repeated, at most hi times, 64 at
 * most); CALL: call(opts, value) parses it and returns NULL, or what is wrong ("is not a rotation").
 * A CALL with .optional: its value may be absent (`lights --error [P%]`): call(opts, next argument)
 * returns qtool_opt_no_value when that argument is not its value, and then call(opts, NULL) says the
 * flag came alone (so does the last argument).
 * A CALL with .nargs = N > 1 takes N arguments: call_n(opts, values, N, &used) (`--sun X Y Z` in the
 * order relight gives the lights), and its reason names the values itself ("--sun: <reason>"). With
 * .nargs_min = M (1..N) it takes M to N: call_n gets the n <= N that follow and sets *used (M..n;
 * `--camera gltf` or `--camera EYE TARGET UP`).
 * A FLAG with .call: call(opts, NULL) once it is set (an action: a deprecated spelling's note).
 * A later repetition of a non-LIST flag replaces the earlier value (as the commands always did).
 * Values are taken verbatim, so `--size -8x4` is a bad size, not a missing value.
 */
#ifndef QTOOL_OPT_OPT_H
#define QTOOL_OPT_OPT_H

#include <stddef.h>
#include <stdio.h>

typedef enum qtool_opt_kind {
    QTOOL_OPT_END = 0, /* the table's terminating {0} */
    QTOOL_OPT_FLAG,
    QTOOL_OPT_INT,
    QTOOL_OPT_NUM,
    QTOOL_OPT_STR,
    QTOOL_OPT_ENUM,
    QTOOL_OPT_SIZE,
    QTOOL_OPT_TRIPLE,
    QTOOL_OPT_LIST,
    QTOOL_OPT_CALL
} qtool_opt_kind;

#define QTOOL_OPT_LIST_MAX 64
typedef struct qtool_opt_list {
    const char *v[QTOOL_OPT_LIST_MAX];
    int n;
} qtool_opt_list;

typedef struct qtool_opt {
    const char *name;   /* "--bands", "-o" */
    const char *alias;  /* another spelling ("-n"), or NULL */
    qtool_opt_kind kind;
    size_t off;         /* offsetof(the options struct, field) */
    const char *arg;    /* the value's name in help ("B", "FILE"); a kind's own when NULL */
    double lo, hi;      /* INT, NUM, TRIPLE: the range; SIZE: the largest side; LIST: at most this many */
    const char *what;   /* INT: what the value is in the error ("a face size"; "an integer" when NULL) */
    const char *why;    /* the range's reason, in the error and in help ("0: no LUT") */
    const char *const *names; /* ENUM: the values, NULL-terminated */
    const char *(*call)(void *opts, const char *value); /* CALL */
    const char *def;    /* the default as help shows it, when the defaults struct cannot say it */
    const char *renamed; /* a deprecated spelling: the name to use (a note on stderr when used) */
    const char *note;   /* with renamed: why, in the note */
    int required;
    int optional;       /* CALL: the value may be absent (above) */
    int eq;             /* one value: also taken as --name=VALUE (bake's --progress=MODE) */
    int nargs;          /* CALL: how many arguments call_n takes (0 or 1: call takes one) */
    int nargs_min;      /* CALL with nargs: the fewest it takes (0: nargs) */
    const char *(*call_n)(void *opts, char *const *values, int n, int *used);
    int field;          /* CALL: call and call_n get the field at .off, not the whole struct (a callback
                         * several tables share: cli/relight_light.h's --yaw and --rotate) */
    const char *help;   /* one line */
} qtool_opt;

/* What an optional CALL returns for an argument that is not its value (compared by address). */
extern const char qtool_opt_no_value[];

typedef struct qtool_opt_pos {
    const char *names; /* as usage shows them: "FILE", "X Y Z", "PROBE.hdr ..." */
    int min, max;      /* how many (max <= QTOOL_OPT_LIST_MAX) */
    size_t off;        /* a qtool_opt_list in the options struct */
    int numbers;       /* they may be negative numbers: "-1", "-inf" are values */
    /* instead of the list (no max: merge's and check's files): call(opts, value) takes each one and
     * returns NULL or what is wrong; min is then the command's to check */
    const char *(*call)(void *opts, const char *value);
} qtool_opt_pos;

typedef struct qtool_opt_cmd {
    const char *name;      /* as the errors and usage name it: "info", "sh eval" ("": qibl's own flags) */
    const char *help_name; /* `qibl help X`: the command (NULL: name's first word, "sh" of "sh eval") */
    const qtool_opt *opts;  /* ended by {0}; NULL: none */
    qtool_opt_pos pos;
    const void *defaults;  /* the options struct's defaults (size bytes) */
    size_t size;
    const char *prose;     /* after the option list: what the command does, two-space indented */
    /* NULL, or the usage line's leading part for what a table cannot say (alternatives: "(-o ASSET |
     * --shard I/N --sums FILE)"); the options it names are left out of the bracketed list after it */
    const char *synopsis;
} qtool_opt_cmd;

/* A command that takes only positionals parses into a qtool_opt_list itself (.pos.off 0):
 * QTOOL_OPT_TABLE(NULL, qtool_opt_args), an empty list its defaults. */
extern const qtool_opt_list qtool_opt_args;

/* A command's table and its defaults struct (NULL table: positionals only); the size the parser
 * copies is taken from the defaults themselves, so the two cannot disagree. */
#define QTOOL_OPT_TABLE(table, defaults_) .opts = (table), .defaults = &(defaults_), .size = sizeof(defaults_)

/* The usual head of a spec in one line: its name, QTOOL_OPT_TABLE, and positionals that fill a
 * qtool_opt_list, min_ to max_ of them, shown as pos_names, at field of the options struct type. */
#define QTOOL_OPT_CMD(name_, table, defaults_, pos_names, min_, max_, type, field)                            \
    .name = (name_), QTOOL_OPT_TABLE(table, defaults_),                                                       \
    .pos = {.names = (pos_names), .min = (min_), .max = (max_), .off = offsetof(type, field)}

/* The program the lines name ("qibl" unless a program sets it first): "usage: PROGRAM CMD ...",
 * "PROGRAM CMD: ...; see PROGRAM help CMD". */
extern const char *qtool_opt_program;

/* Parses argv[first..argc-1] into opts (first set to c->defaults). 0, or 2 after one line on stderr. */
int qtool_opt_parse(const qtool_opt_cmd *c, int argc, char **argv, int first, void *opts);

/* "PROGRAM <c->name>: <fmt ...>; see PROGRAM help <help name>" on stderr; returns 2. */
int qtool_opt_error(const qtool_opt_cmd *c, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* A command made of subcommands: the spec whose name ends in argv[1] (subs NULL-terminated), or
 * NULL after one line on stderr (naming the bad word or flag, listing the subcommands; `others`
 * adds subcommands parsed elsewhere, e.g. "project"; may be NULL). cmd: "sh". */
const qtool_opt_cmd *qtool_opt_sub(const char *cmd, const qtool_opt_cmd *const *subs, const char *others, int argc,
                                 char **argv);

/* The value checks under the table's kinds, for the hand-written parsers too (cli.h's qcli_parse_int,
 * qcli_parse_num and qcli_parse_size are these, with their own lines). int: a decimal in [lo, hi], 0
 * or -1; num: 0, or 1 not a number, 2 not finite, 3 outside [lo, hi]; size: "WxH", decimal digits
 * only, both in 1..max, 0 or -1. Nothing written on failure. opt.c needs only libc (a test links it
 * alone). */
int qtool_opt_int_value(const char *s, long lo, long hi, long *out);
int qtool_opt_num_value(const char *s, double lo, double hi, double *out);
int qtool_opt_size_value(const char *s, long max, long wh[2]);

/* `qibl help CMD`'s part for one table: usage line, the aligned option list, the prose. */
void qtool_opt_help(FILE *f, const qtool_opt_cmd *c);
/* The aligned option list alone ("options:" and a line per flag; nothing for an empty table). */
void qtool_opt_help_list(FILE *f, const qtool_opt_cmd *c);

/* The table's name on a line ("sh eval"), then each flag (aliases too) as "NAME<TAB>--flag<TAB>KIND",
 * KIND flag (takes no value) or value: `qibl help --flags CMD`, which tests/cli_opts_test.c checks
 * against the help text and the parser. */
void qtool_opt_flags(FILE *f, const qtool_opt_cmd *c);

#endif
