/*
 * main.c - the qibl command-line tool: subcommand dispatch, --help, shared argument parsing.
 */
#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "opt/opt.h"
#include "qibl/version.h"
#include "qibl/isa.h"
#include "io/isa_env.h"

int qcli_parse_only; /* see cli.h */

/* a command's own table, or a family's subcommands (cli.h: qcli_sub) */
#define SUBS(...) (const qcli_sub *const[]){__VA_ARGS__, NULL}

const qcli_cmd qcli_commands[] = {
    {"sh", "evaluate the integer SH basis for a direction",
     SUBS(&qcli_sub_sh_eval, &qcli_sub_sh_plot, &qcli_sub_sh_project)},
    {"bench", "benchmarks: speed against error, with RESULT lines",
     SUBS(&qcli_sub_bench)},
    {"gen", "write the procedural courtyard's SH maps (and P map, optional Y LUT) as an asset",
     SUBS(&qcli_sub_gen)},
    {"render", "ray-trace the ground-truth panorama of a scene under one light (PNG, PFM, depth)",
     SUBS(&qcli_sub_render)},
    {"transfer", "a mesh self-shadowed by hemispherical rasterization under a probe, beside the ray-cast truth",
     SUBS(&qcli_sub_transfer)},
    {"bake", "bake a scene into a relightable panorama asset (ray-traced, SH-projected, 8-bit packed)",
     SUBS(&qcli_sub_bake)},
    {"merge", "combine the partial sums of bake shards into an asset",
     SUBS(&qcli_sub_merge)},
    {"check", "validate PNG/APNG, PFM, Radiance HDR, OpenEXR and qibl asset files",
     SUBS(&qcli_sub_check)},
    {"demo", "the main demo: bake the scene, relight it by the core, compare with ground truth",
     SUBS(&qcli_sub_demo)},
    {"relight", "relight an asset by suns, lamps, a light list or a whole probe into a PNG (core + soft framebuffer)",
     SUBS(&qcli_sub_relight)},
    {"view", "a live viewer: drag the sun or a lamp, scrub a baked light path, step probes, yaw, exposure, k (X11)",
     SUBS(&qcli_sub_view)},
    {"info", "validate a qibl asset file and print its contents",
     SUBS(&qcli_sub_info)},
    {"srgbe", "encode/decode one sRGBE colour (signed shared-exponent RGB in 4 bytes)",
     SUBS(&qcli_sub_srgbe_encode, &qcli_sub_srgbe_decode)},
    {"lights", "sample a .hdr light probe (lat-long, angular, ball, cube cross) into directional lights",
     SUBS(&qcli_sub_lights)},
    {"probe", "describe a light probe and advise how to light with it: SH, N lights, or sun plus SH",
     SUBS(&qcli_sub_probe_info)},
    {"ies", "an IES LM-63 photometric file: header facts, candela range, integrated lumens, polar curves",
     SUBS(&qcli_sub_ies_info)},
    {"luminaire", "near-field light sources: capture, info, render as textured spotlights, study, passes, picture",
     SUBS(&qcli_sub_luminaire_capture, &qcli_sub_luminaire_info, &qcli_sub_luminaire_render,
          &qcli_sub_luminaire_study, &qcli_sub_luminaire_passes, &qcli_sub_luminaire_picture)},
    {"study", "the light-probe approximation study: every method, error against N and time",
     SUBS(&qcli_sub_study)},
};
const size_t qcli_ncommands = sizeof qcli_commands / sizeof qcli_commands[0];
#define NCMD qcli_ncommands
#define SUBS_MAX 8 /* the most subcommands a family has, and more */

/* the flags `qibl` itself takes, in place of a command */
typedef struct global_opts {
    int help, version, isa_list;
} global_opts;
static const qtool_opt global_table[] = {
    {.name = "--help", .alias = "-h", .kind = QTOOL_OPT_FLAG, .off = offsetof(global_opts, help),
     .help = "this list (qibl help CMD or qibl CMD --help: a command's options)"},
    {.name = "--version", .kind = QTOOL_OPT_FLAG, .off = offsetof(global_opts, version),
     .help = "the version, the config id and the kernels this CPU runs"},
    {.name = "--isa-list", .kind = QTOOL_OPT_FLAG, .off = offsetof(global_opts, isa_list),
     .help = "the kernel sets this CPU runs, one per line (QIBL_ISA takes one)"},
    {0},
};
/* name "": its refusals read "qibl: ...; see qibl --help" */
static const qtool_opt_cmd global_spec = {.name = "", .opts = global_table, .size = sizeof(global_opts)};

static void print_help(FILE *f)
{
    fprintf(f, "qibl - integer image-based lighting runtime: command-line tool\n\n"
               "usage: qibl <command> [args]\n       qibl help <command>\n       qibl --version\n       qibl --isa-list\n");
    qtool_opt_help_list(f, &global_spec);
    fprintf(f, "\ncommands:\n");
    for (size_t i = 0; i < NCMD; ++i)
        fprintf(f, "  %-8s %s\n", qcli_commands[i].name, qcli_commands[i].summary);
}

/* `qibl help CMD`: each option table's usage, options and prose */
static void print_cmd_help(FILE *f, const qcli_cmd *c)
{
    for (size_t k = 0; c->subs[k]; ++k) {
        if (k > 0)
            fputc('\n', f);
        qtool_opt_help(f, c->subs[k]->opts);
    }
}

const qcli_cmd *qcli_find(const char *name)
{
    for (size_t i = 0; i < NCMD; ++i)
        if (strcmp(qcli_commands[i].name, name) == 0)
            return &qcli_commands[i];
    return NULL;
}

int qcli_run(const qcli_cmd *c, int argc, char **argv)
{
    const qcli_sub *s = c->subs[0];
    int first = 1;
    if (c->subs[1] || strcmp(s->opts->name, c->name) != 0) { /* a family: argv[1] names the subcommand */
        const qtool_opt_cmd *t[SUBS_MAX + 1];
        size_t n = 0;
        for (; c->subs[n] && n < SUBS_MAX; ++n)
            t[n] = c->subs[n]->opts;
        t[n] = NULL;
        const qtool_opt_cmd *sub = qtool_opt_sub(c->name, t, NULL, argc, argv);
        if (!sub)
            return 2;
        for (n = 0; t[n] != sub; ++n)
            ;
        s = c->subs[n], first = 2;
    }
    const qtool_opt_cmd *t = s->pick ? s->pick(argc, argv) : s->opts;
    void *o = calloc(1, t->size);
    if (!o)
        return fprintf(stderr, "qibl: %s: out of memory\n", c->name), 1;
    int rc = qtool_opt_parse(t, argc, argv, first, o);
    if (rc == 0 && s->check)
        rc = s->check(o);
    if (rc == 0 && s->check_line)
        rc = s->check_line(o, argc, argv);
    if (rc == 0 && (!qcli_parse_only || s->whole)) /* fuzz_cliopts: the options only */
        rc = s->run(o);
    if (s->drop)
        s->drop(o);
    free(o);
    return rc;
}

int qcli_usage_error(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fputs("qibl: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    return 2;
}

int qcli_parse_q16(const char *s, int32_t *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end != '\0' || errno == ERANGE || !isfinite(v))
        return -1;
    double q = nearbyint(v * 65536.0);
    if (q > 2147483647.0 || q < -2147483648.0)
        return -1;
    *out = (int32_t)q;
    return 0;
}

const char *qcli_parse_q16_dir(char *const *v, int width, const char *zero_why, int32_t out[3], char *why,
                               size_t whylen)
{
    int32_t t[3];
    for (int k = 0; k < 3; ++k)
        if (qcli_parse_q16(v[k], &t[k]) != 0) {
            snprintf(why, whylen, "'%.*s' is not a number in the Q16.16 range", width, v[k]);
            return why;
        }
    if (t[0] == 0 && t[1] == 0 && t[2] == 0)
        return zero_why;
    memcpy(out, t, sizeof t);
    return NULL;
}

int qcli_parse_azel(const char *s, double el_max, double *az, double *el)
{
    char *end;
    const double a = strtod(s, &end);
    if (end == s || *end != ',' || !isfinite(a))
        return -1;
    const char *t = end + 1;
    const double e = strtod(t, &end);
    if (end == t || *end != '\0' || !isfinite(e) || fabs(e) > el_max)
        return -1;
    *az = a, *el = e;
    return 0;
}

int qcli_parse_int(const char *s, long lo, long hi, long *out)
{
    return qtool_opt_int_value(s, lo, hi, out);
}

int qcli_parse_num(const char *opt, const char *s, double lo, double hi, const char *why, double *out)
{
    switch (qtool_opt_num_value(s, lo, hi, out)) {
    case 0:
        return 0;
    case 1:
        return qcli_usage_error("%s: '%s' is not a number", opt, s);
    case 2:
        return qcli_usage_error("%s: '%s' is not a finite number", opt, s);
    default:
        return qcli_usage_error("%s: %s is outside %.10g..%.10g%s%s%s", opt, s, lo, hi, why ? " (" : "",
                                why ? why : "", why ? ")" : "");
    }
}

int qcli_parse_size(const char *opt, const char *s, long max, long *w, long *h)
{
    long wh[2];
    if (qtool_opt_size_value(s, max, wh) != 0)
        return qcli_usage_error("%s needs WxH with both in 1..%ld, got '%s'", opt, max, s);
    *w = wh[0], *h = wh[1];
    return 0;
}

int main(int argc, char **argv)
{
    /* line by line into a pipe or a log too: a farm or `make demo | tee` sees each step as it ends */
    setvbuf(stdout, NULL, _IOLBF, 0);
    /* qibl's own flags come alone, in place of a command: the table reads argv[1] only */
    global_opts g = {.help = 0};
    if (argc >= 2 && argv[1][0] == '-' && argv[1][1] != '\0' && qtool_opt_parse(&global_spec, 2, argv, 1, &g) != 0)
        return 2;
    if (argc < 2 || g.help) {
        print_help(stdout);
        return argc < 2 ? 2 : 0;
    }
    /* the kernel sets this CPU runs, one per line, lowest first (make golden and make test loop over them) */
    if (g.isa_list) {
        for (unsigned i = 0; i < QIBL_ISA_COUNT; ++i)
            if (qibl_isa_available() & QIBL_ISA_BIT(i))
                printf("%s\n", qibl_isa_name((qibl_isa_t)i));
        return 0;
    }
    /* QIBL_ISA names a kernel set this CPU runs, or nothing runs (io/isa_env.h) */
    char isa_err[160];
    if (qtool_isa_env_check(isa_err, sizeof isa_err) != 0) {
        fprintf(stderr, "qibl: %s\n", isa_err);
        return 2;
    }
    if (g.version) {
        char isa[160];
        qtool_isa_describe(isa, sizeof isa);
        printf("qibl %s (config id %08lx)\nkernels: %s\n", qibl_version(), (unsigned long)qibl_config_id(), isa);
        return qibl_init_check() == QIBL_OK ? 0 : 1;
    }
    if (strcmp(argv[1], "help") == 0) {
        if (argc == 2) {
            print_help(stdout);
            return 0;
        }
        /* --flags CMD: the tables and their flags, as qtool_opt_flags prints them (tests/cli_opts_test.c) */
        int flags = strcmp(argv[2], "--flags") == 0;
        if (flags && argc < 4)
            return qcli_usage_error("help --flags needs a command (see qibl --help)");
        const qcli_cmd *c = qcli_find(argv[2 + flags]);
        if (!c)
            return qcli_usage_error("no such command '%s' (see qibl --help)", argv[2 + flags]);
        for (size_t k = 0; flags && c->subs[k]; ++k)
            qtool_opt_flags(stdout, c->subs[k]->opts);
        if (!flags)
            print_cmd_help(stdout, c);
        return 0;
    }
    const qcli_cmd *c = qcli_find(argv[1]);
    if (!c)
        return qcli_usage_error("no such command '%s' (see qibl --help)", argv[1]);
    for (int i = 2; i < argc; ++i)
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            print_cmd_help(stdout, c);
            return 0;
        }
    return qcli_run(c, argc - 1, argv + 1);
}
