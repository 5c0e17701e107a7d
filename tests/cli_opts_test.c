/*
 * cli_opts_test.c - the option tables of the qibl CLI (tools/cli/opt.h), through the program: for
 * every command in the command table (as `qibl --help` lists it) an unknown flag gets one line
 * `qibl CMD[ SUB]: ... '--no-such-flag' ...; see qibl help CMD` and exit 2; every flag of a command's
 * tables (`qibl help --flags CMD`) appears in `qibl help CMD` and is known to the parser. And the
 * table module itself (tools/cli/opt.c, linked alone): every kind, every refusal's exact line, the
 * defaults and ranges help prints.
 */
#include "cliutil.h"
#include "opt/opt.h"

CLI_FIXTURES("/tmp/qibl_cli_opts_test_XXXXXX")

#define BAD "--no-such-flag"

/* the commands `qibl --help` lists: the first word of each line after "commands:" */
static int list_commands(char names[][32], int max)
{
    assert_int_equal(run("--help", NULL), 0);
    char *t = text(outlog), *p = strstr(t, "\ncommands:\n");
    assert_non_null(p);
    p += strlen("\ncommands:\n");
    int n = 0;
    while (*p == ' ' && n < max) {
        while (*p == ' ')
            ++p;
        size_t len = strcspn(p, " \n");
        assert_true(len > 0 && len < 32);
        memcpy(names[n], p, len);
        names[n++][len] = '\0';
        p = strchr(p, '\n');
        if (!p)
            break;
        ++p;
    }
    free(t);
    return n;
}

/* the exit status is 2, stdout empty, stderr one line "qibl <who>: ...<must>...; see qibl help <cmd>" */
static void one_line(int rc, const char *who, const char *cmd, const char *must, const char *what)
{
    char *o = text(outlog), *e = text(errlog), head[96], tail[96];
    snprintf(head, sizeof head, "qibl %s: ", who);
    snprintf(tail, sizeof tail, "; see qibl help %s\n", cmd);
    size_t n = strlen(e), tn = strlen(tail);
    if (rc != 2 || o[0] != '\0' || strncmp(e, head, strlen(head)) != 0 || n < tn || strcmp(e + n - tn, tail) != 0 ||
        strchr(e, '\n') != e + n - 1 || !strstr(e, must))
        fail_msg("%s: exit %d, stdout '%.80s', stderr '%s' (want exit 2 and one line '%s...%s...%s')", what, rc, o, e,
                 head, must, tail);
    free(o), free(e);
}

/* flag occurs in the help text as a word of its own (so --lut is not found inside --lut-size) */
static int has_flag(const char *help, const char *flag)
{
    size_t n = strlen(flag);
    for (const char *p = strstr(help, flag); p; p = strstr(p + 1, flag)) {
        char after = p[n], before = p == help ? ' ' : p[-1];
        if ((after == '\0' || strchr(" ,]|\n.", after)) && strchr(" [(|\n", before))
            return 1;
    }
    return 0;
}

static void check_command(const char *cmd)
{
    char what[4400];
    /* the unknown flag right after the command */
    snprintf(what, sizeof what, "qibl %s %s", cmd, BAD);
    one_line(run(cmd, BAD, NULL), cmd, cmd, "'" BAD "'", what);
    /* the tables and their flags */
    assert_int_equal(run("help", "--flags", cmd, NULL), 0);
    char *flags = text(outlog);
    if (flags[0] == '\0')
        fail_msg("%s has no option table: put it on one (tools/cli/opt.h)", cmd);
    assert_int_equal(run("help", cmd, NULL), 0);
    char *help = text(outlog);
    for (char *line = flags, *next; *line; line = next) {
        next = strchr(line, '\n');
        assert_non_null(next);
        *next++ = '\0';
        char *flag = strchr(line, '\t'), *kind = NULL;
        if (flag) {
            *flag++ = '\0';
            kind = strchr(flag, '\t');
            assert_non_null(kind);
            *kind++ = '\0';
        }
        /* the table's name is "cmd" or "cmd sub": the arguments that reach it */
        const char *sub = strlen(line) > strlen(cmd) ? line + strlen(cmd) + 1 : NULL;
        assert_int_equal(strncmp(line, cmd, strlen(cmd)), 0);
        if (!flag) { /* a table: an unknown flag after its subcommand */
            snprintf(what, sizeof what, "qibl %s %s", line, BAD);
            int rc = sub ? run(cmd, sub, BAD, NULL) : run(cmd, BAD, NULL);
            one_line(rc, line, cmd, "'" BAD "'", what);
            continue;
        }
        if (!has_flag(help, flag))
            fail_msg("qibl help %s does not name %s (of the table '%s')", cmd, flag, line);
        /* known to the parser: a flag then BAD is refused for BAD; a value flag at the end needs its value */
        int value = strcmp(kind, "value") == 0;
        char must[96];
        if (value)
            snprintf(must, sizeof must, "%s needs ", flag);
        else
            snprintf(must, sizeof must, "'%s'", BAD);
        snprintf(what, sizeof what, "qibl %s %s%s", line, flag, value ? "" : " " BAD);
        int rc = sub ? (value ? run(cmd, sub, flag, NULL) : run(cmd, sub, flag, BAD, NULL))
                     : (value ? run(cmd, flag, NULL) : run(cmd, flag, BAD, NULL));
        one_line(rc, line, cmd, must, what);
    }
    free(flags), free(help);
}

static void test_every_command(void **state)
{
    (void)state;
    need_qibl();
    char names[64][32];
    int n = list_commands(names, 64);
    assert_true(n >= 10);
    /* every command: none keeps a hand-written parser */
    for (int i = 0; i < n; ++i)
        check_command(names[i]);
    print_message("%d commands on option tables\n", n);
}

/* qibl's own flags: an unknown one is named, with where the list is */
static void test_global_flags(void **state)
{
    (void)state;
    need_qibl();
    assert_int_equal(run(BAD, NULL), 2);
    char *e = text(errlog);
    assert_string_equal(e, "qibl: unknown option '" BAD "'; see qibl --help\n");
    free(e);
    assert_int_equal(run("--help", NULL), 0);
    char *h = text(outlog);
    assert_true(has_flag(h, "--version") && has_flag(h, "--isa-list") && has_flag(h, "--help"));
    free(h);
}

/* the table's parser on the values: a bad one is named with its range, a negative number is a value */
static void test_values(void **state)
{
    (void)state;
    need_qibl();
    one_line(run("sh", "eval", "--bands", "9", "1", "0", "0", NULL), "sh eval", "sh", "--bands: '9' is not an integer in 1..5",
             "sh eval --bands 9");
    one_line(run("sh", "eval", "1", "0", NULL), "sh eval", "sh", "needs X Y Z, got 2 arguments", "sh eval 1 0");
    one_line(run("info", "a", "b", NULL), "info", "info", "'b' is one too many", "info a b");
    one_line(run("gen", "-o", at("g.qibl"), "--pack", "zip", NULL), "gen", "gen", "--pack: 'zip' is not minmax or robust",
             "gen --pack zip");
    one_line(run("study", "--quick", NULL), "study", "study", "--out DIR is required", "study --quick");
    assert_int_equal(access(at("g.qibl"), F_OK), -1);
    /* what a range cannot say, through qtool_opt_error (refused before any file is read) */
    one_line(run("transfer", "m.obj", "--probe", "p.hdr", "--mask", "48", NULL), "transfer", "transfer",
             "--mask: '48' is not 16, 32 or 64", "transfer --mask 48");
    one_line(run("transfer", "m.obj", "--probe", "p.hdr", "--lights", "3", NULL), "transfer", "transfer",
             "--lights: 3 is not a power of two", "transfer --lights 3");
    one_line(run("transfer", "m.obj", "--probe", "p.hdr", "--face", "7", NULL), "transfer", "transfer",
             "--face: 7 is not even", "transfer --face 7");
    one_line(run("transfer", "m.obj", "--png", at("t.png"), NULL), "transfer", "transfer",
             "--probe PROBE.hdr is required", "transfer without --probe");
    one_line(run("transfer", "m.obj", "--probe", "p.hdr", "--view", "0,95", NULL), "transfer", "transfer",
             "--view: '0,95' is not AZ,EL", "transfer --view 0,95");
    /* view: each mode refuses the other's options by name, the first on the line */
    one_line(run("view", "a.qibl", "--bench", "--light-yaw", "0", "--zup", NULL), "view", "view",
             "--light-yaw is for a mesh", "view ASSET --light-yaw");
    one_line(run("view", "m.obj", "--probe", "p.hdr", "--gles", "--sun", "0", "0", "1", NULL), "view", "view",
             "--gles is for an asset", "view MESH --gles");
    one_line(run("view", "a.qibl", "--sun", "0", "0", "0", NULL), "view", "view", "--sun: the direction is 0 0 0",
             "view --sun 0 0 0");
    one_line(run("view", "m.obj", NULL), "view", "view", "m.obj needs --probe P.hdr", "view MESH");
    assert_int_equal(access(at("t.png"), F_OK), -1);
    assert_int_equal(run("sh", "eval", "-1", "0", "0", NULL), 0);
    assert_int_equal(run("srgbe", "encode", "-inf", "-1", "1", NULL), 0);
}


/* ---- the table module itself ------------------------------------------------------------------ */

typedef struct t_opts {
    qtool_opt_list pos, files;
    const char *out, *cb;
    long n, size[2];
    double x, v[3];
    int flag, mode;
} t_opts;
static const t_opts t_defaults = {.n = 7, .size = {4, 2}, .x = 0.5, .v = {0, 0, 1}, .mode = 1};
static const char *const modes[] = {"a", "bee", "c", NULL};

static const char *t_call(void *opts, const char *v)
{
    if (strcmp(v, "ok") != 0)
        return "is not ok";
    ((t_opts *)opts)->cb = v;
    return NULL;
}

static const qtool_opt t_table[] = {
    {.name = "--flag", .alias = "-f", .kind = QTOOL_OPT_FLAG, .off = offsetof(t_opts, flag), .help = "a flag"},
    {.name = "--n", .kind = QTOOL_OPT_INT, .off = offsetof(t_opts, n), .arg = "N", .lo = 1, .hi = 9, .why = "why not",
     .help = "an integer"},
    {.name = "--x", .kind = QTOOL_OPT_NUM, .off = offsetof(t_opts, x), .lo = -1, .hi = 1, .help = "a number"},
    {.name = "-o", .kind = QTOOL_OPT_STR, .off = offsetof(t_opts, out), .arg = "FILE", .required = 1,
     .help = "the output"},
    {.name = "--mode", .kind = QTOOL_OPT_ENUM, .off = offsetof(t_opts, mode), .names = modes, .help = "a mode"},
    {.name = "--size", .kind = QTOOL_OPT_SIZE, .off = offsetof(t_opts, size), .hi = 64, .help = "a size"},
    {.name = "--v", .kind = QTOOL_OPT_TRIPLE, .off = offsetof(t_opts, v), .lo = -2, .hi = 2, .help = "a vector"},
    {.name = "--file", .kind = QTOOL_OPT_LIST, .off = offsetof(t_opts, files), .arg = "F", .hi = 2, .help = "a file"},
    {.name = "--cb", .kind = QTOOL_OPT_CALL, .off = 0, .call = t_call, .help = "a callback"},
    {.name = "--old", .kind = QTOOL_OPT_INT, .off = offsetof(t_opts, n), .arg = "N", .lo = 1, .hi = 9,
     .renamed = "--n", .note = "it was renamed"},
    {0},
};
static const qtool_opt_cmd t_cmd = {
    .name = "t sub", /* its help is `qibl help t`: the lines say so (T_REFUSED) */
    .opts = t_table,
    .pos = {.names = "A B", .min = 0, .max = 2, .off = offsetof(t_opts, pos), .numbers = 1},
    .defaults = &t_defaults,
    .size = sizeof(t_opts),
    .prose = "  Prose.\n",
};

/* stderr of the parse of the NULL-terminated arguments (after "t sub") into err; the exit status */
static int t_parse(t_opts *o, char *err, size_t errn, ...)
{
    char *argv[40] = {"t", "sub"};
    int argc = 2;
    va_list ap;
    va_start(ap, errn);
    for (const char *a = va_arg(ap, const char *); a && argc < 39; a = va_arg(ap, const char *))
        argv[argc++] = (char *)a;
    va_end(ap);
    fflush(stderr);
    int saved = dup(2), fd = open(errlog, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    assert_true(saved >= 0 && fd >= 0);
    dup2(fd, 2);
    int rc = qtool_opt_parse(&t_cmd, argc, argv, 2, o);
    fflush(stderr);
    dup2(saved, 2);
    close(fd), close(saved);
    char *e = text(errlog);
    snprintf(err, errn, "%s", e);
    free(e);
    return rc;
}

#define T_REFUSED(line, ...)                                                                       \
    do {                                                                                           \
        assert_int_equal(t_parse(&o, err, sizeof err, __VA_ARGS__, NULL), 2);                      \
        assert_string_equal(err, "qibl t sub: " line "; see qibl help t\n");                       \
    } while (0)

static void test_table_kinds(void **state)
{
    (void)state;
    t_opts o;
    char err[512];
    assert_int_equal(t_parse(&o, err, sizeof err, "-o", "out", "--flag", "--n", "3", "--x", "-0.25", "--mode", "c",
                             "--size", "10x20", "--v", "1", "-1", "0.5", "--file", "a", "--file", "b", "--cb", "ok",
                             "-3", "-", NULL),
                     0);
    assert_string_equal(err, "");
    assert_string_equal(o.out, "out");
    assert_true(o.flag == 1 && o.n == 3 && o.x == -0.25 && o.mode == 2 && o.size[0] == 10 && o.size[1] == 20);
    assert_true(o.v[0] == 1 && o.v[1] == -1 && o.v[2] == 0.5);
    assert_true(o.files.n == 2 && strcmp(o.files.v[1], "b") == 0 && strcmp(o.cb, "ok") == 0);
    assert_true(o.pos.n == 2 && strcmp(o.pos.v[0], "-3") == 0 && strcmp(o.pos.v[1], "-") == 0);
    /* the defaults, from t_defaults; the alias; a later value replaces an earlier one */
    assert_int_equal(t_parse(&o, err, sizeof err, "-o", "a", "-f", "-o", "b", NULL), 0);
    assert_true(o.flag == 1 && strcmp(o.out, "b") == 0 && o.n == 7 && o.size[0] == 4 && o.size[1] == 2);
    assert_true(o.mode == 1 && o.x == 0.5 && o.v[2] == 1 && o.files.n == 0 && o.pos.n == 0 && !o.cb);
    /* the old spelling: its value, and a note naming the new one */
    assert_int_equal(t_parse(&o, err, sizeof err, "-o", "a", "--old", "4", NULL), 0);
    assert_int_equal(o.n, 4);
    assert_string_equal(err, "qibl: note: --old N is deprecated here; say --n 4 (it was renamed)\n");
}

static void test_table_refusals(void **state)
{
    (void)state;
    t_opts o;
    char err[512];
    T_REFUSED("unknown option '--nope'", "-o", "x", "--nope");
    T_REFUSED("unknown option '-1e'", "-o", "x", "-1e");
    T_REFUSED("-o needs FILE", "-o");
    T_REFUSED("-o FILE is required", "--flag");
    T_REFUSED("--n: '10' is not an integer in 1..9 (why not)", "-o", "x", "--n", "10");
    T_REFUSED("--n: '3x' is not an integer in 1..9 (why not)", "-o", "x", "--n", "3x");
    T_REFUSED("--x: 2 is outside -1..1", "-o", "x", "--x", "2");
    T_REFUSED("--x: 'abc' is not a number", "-o", "x", "--x", "abc");
    T_REFUSED("--x: 'inf' is not a finite number", "-o", "x", "--x", "inf");
    T_REFUSED("--mode: 'd' is not a, bee or c", "-o", "x", "--mode", "d");
    T_REFUSED("--size needs WxH with both in 1..64, got '65x1'", "-o", "x", "--size", "65x1");
    T_REFUSED("--size needs WxH with both in 1..64, got '-8x4'", "-o", "x", "--size", "-8x4");
    T_REFUSED("--v needs X Y Z", "-o", "x", "--v", "1", "2");
    T_REFUSED("--v: 3 is outside -2..2", "-o", "x", "--v", "1", "3", "0");
    T_REFUSED("--file: at most 2, and 'c' is one more", "-o", "x", "--file", "a", "--file", "b", "--file", "c");
    T_REFUSED("--cb: 'no' is not ok", "-o", "x", "--cb", "no");
    T_REFUSED("takes at most A B: 'c' is one too many", "-o", "x", "a", "b", "c");
    T_REFUSED("--mode: 'a\\x0ab' is not a, bee or c", "-o", "x", "--mode", "a\nb"); /* still one line */
}

static void test_table_help(void **state)
{
    (void)state;
    char *h = NULL;
    size_t n = 0;
    FILE *f = open_memstream(&h, &n);
    assert_non_null(f);
    qtool_opt_help(f, &t_cmd);
    fclose(f);
    static const char *const want[] = {
        "usage: qibl t sub [--flag] [--n N] [--x X] -o FILE [--mode a|bee|c] [--size WxH] [--v X Y Z]",
        "--flag, -f", "an integer (1..9, why not; default 7)", "a number (-1..1; default 0.5)",
        "the output (required)", "--mode a|bee|c", "a mode (default bee)", "a size (sides 1..64; default 4x2)",
        "a vector (-2..2; default 0 0 1)", "a file (repeatable, at most 2)", "[--file F...]", "--cb VALUE",
        "--old N", "the old spelling of --n: it was renamed", "[A B]\n", "options:\n"};
    for (size_t i = 0; i < sizeof want / sizeof *want; ++i)
        if (!strstr(h, want[i]))
            fail_msg("help lacks '%s':\n%s", want[i], h);
    assert_true(n > 9 && strcmp(h + n - 9, "  Prose.\n") == 0);
    for (const char *p = h, *e; *p; p = e + 1) { /* no line wider than 100 columns */
        e = strchr(p, '\n');
        assert_non_null(e);
        if (e - p > 100)
            fail_msg("a help line of %d columns: %.*s", (int)(e - p), (int)(e - p), p);
    }
    assert_null(strstr(h, "[--old")); /* an old spelling is listed, not offered in the usage line */
    free(h);
}

static void test_table_values(void **state)
{
    (void)state;
    long l = 5, wh[2] = {0, 0};
    double d = 5;
    assert_int_equal(qtool_opt_int_value("9", 1, 9, &l), 0);
    assert_int_equal(l, 9);
    assert_int_equal(qtool_opt_int_value("10", 1, 9, &l), -1);
    assert_int_equal(qtool_opt_int_value("99999999999999999999", 1, 9, &l), -1);
    assert_int_equal(qtool_opt_int_value("", 1, 9, &l), -1);
    assert_int_equal(l, 9); /* nothing written on failure */
    assert_int_equal(qtool_opt_num_value("-1", -1, 1, &d), 0);
    assert_true(d == -1);
    assert_int_equal(qtool_opt_num_value("x", -1, 1, &d), 1);
    assert_int_equal(qtool_opt_num_value("1e999", -1, 1, &d), 2);
    assert_int_equal(qtool_opt_num_value("nan", -1, 1, &d), 2);
    assert_int_equal(qtool_opt_num_value("1.5", -1, 1, &d), 3);
    assert_true(d == -1);
    assert_int_equal(qtool_opt_size_value("3x4", 4, wh), 0);
    assert_true(wh[0] == 3 && wh[1] == 4);
    assert_int_equal(qtool_opt_size_value("5x4", 4, wh), -1);
    assert_int_equal(qtool_opt_size_value("0x4", 4, wh), -1);
    assert_int_equal(qtool_opt_size_value("3x", 4, wh), -1);
    assert_int_equal(qtool_opt_size_value("3x4 ", 4, wh), -1);
    assert_int_equal(qtool_opt_size_value("99999999999999999999x4", 4, wh), -1);
    assert_true(wh[0] == 3 && wh[1] == 4);
}

static void test_table_sub(void **state)
{
    (void)state;
    static const qtool_opt_cmd *const subs[] = {&t_cmd, NULL};
    char *a1[] = {"t", "sub"}, *a2[] = {"t"}, *a3[] = {"t", "--x"}, *a4[] = {"t", "zap"};
    assert_ptr_equal(qtool_opt_sub("t", subs, "other", 2, a1), &t_cmd);
    const struct {
        int argc;
        char **argv;
        const char *line;
    } bad[] = {{1, a2, "qibl t: needs a subcommand: sub or other; see qibl help t\n"},
               {2, a3, "qibl t: unknown option '--x' (a subcommand comes first: sub or other); see qibl help t\n"},
               {2, a4, "qibl t: 'zap' is not a subcommand (sub or other); see qibl help t\n"}};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; ++i) {
        fflush(stderr);
        int saved = dup(2), fd = open(errlog, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        assert_true(saved >= 0 && fd >= 0);
        dup2(fd, 2);
        const qtool_opt_cmd *c = qtool_opt_sub("t", subs, "other", bad[i].argc, bad[i].argv);
        fflush(stderr);
        dup2(saved, 2);
        close(fd), close(saved);
        assert_null(c);
        char *e = text(errlog);
        assert_string_equal(e, bad[i].line);
        free(e);
    }
}

/* an optional value (CALL .optional, as lights --error [P%]): digits are its value, "bad" is refused,
 * anything else is not its value and is parsed as the next argument */
typedef struct o_opts {
    qtool_opt_list pos;
    const char *val;
    int alone;
} o_opts;

static const char *o_call(void *opts, const char *v)
{
    o_opts *o = opts;
    if (!v)
        return o->alone++, NULL;
    if (strcmp(v, "bad") == 0)
        return "is bad";
    if (strspn(v, "0123456789") != strlen(v))
        return qtool_opt_no_value;
    o->val = v;
    return NULL;
}

static const qtool_opt o_table[] = {
    {.name = "--e", .kind = QTOOL_OPT_CALL, .optional = 1, .off = 0, .arg = "V", .call = o_call, .help = "maybe"},
    {.name = "--f", .kind = QTOOL_OPT_FLAG, .off = offsetof(o_opts, alone), .help = "a flag"},
    {0},
};
static const qtool_opt_cmd o_cmd = {.name = "o", .opts = o_table, .size = sizeof(o_opts),
                                   .pos = {.names = "A", .min = 0, .max = 2, .off = offsetof(o_opts, pos)}};

static int o_parse(o_opts *o, char *err, size_t errn, int argc, char **argv)
{
    fflush(stderr);
    int saved = dup(2), fd = open(errlog, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    assert_true(saved >= 0 && fd >= 0);
    dup2(fd, 2);
    int rc = qtool_opt_parse(&o_cmd, argc, argv, 1, o);
    fflush(stderr);
    dup2(saved, 2);
    close(fd), close(saved);
    char *e = text(errlog);
    snprintf(err, errn, "%s", e);
    free(e);
    return rc;
}

static void test_table_optional(void **state)
{
    (void)state;
    o_opts o;
    char err[512];
    char *a1[] = {"o", "--e", "12", "x"}, *a2[] = {"o", "--e", "x"}, *a3[] = {"o", "x", "--e"},
         *a4[] = {"o", "--e", "bad"}, *a5[] = {"o", "--e", "--nope"};
    assert_int_equal(o_parse(&o, err, sizeof err, 4, a1), 0);
    assert_true(o.val && strcmp(o.val, "12") == 0 && o.alone == 0 && o.pos.n == 1);
    assert_int_equal(o_parse(&o, err, sizeof err, 3, a2), 0); /* not its value: a positional */
    assert_true(!o.val && o.alone == 1 && o.pos.n == 1 && strcmp(o.pos.v[0], "x") == 0);
    assert_int_equal(o_parse(&o, err, sizeof err, 3, a3), 0); /* the last argument: alone */
    assert_true(!o.val && o.alone == 1 && o.pos.n == 1);
    assert_int_equal(o_parse(&o, err, sizeof err, 3, a4), 2);
    assert_string_equal(err, "qibl o: --e: 'bad' is bad; see qibl help o\n");
    assert_int_equal(o_parse(&o, err, sizeof err, 3, a5), 2); /* the next flag is parsed as one */
    assert_string_equal(err, "qibl o: unknown option '--nope'; see qibl help o\n");
    /* help shows the value as optional; --flags lists it as a flag (whole alone) */
    FILE *f = fopen(outlog, "w");
    assert_non_null(f);
    qtool_opt_help(f, &o_cmd);
    qtool_opt_flags(f, &o_cmd);
    fclose(f);
    char *h = text(outlog);
    assert_non_null(strstr(h, "usage: qibl o [--e [V]] [--f] [A]\n"));
    assert_non_null(strstr(h, "\n  --e [V]  maybe\n"));
    assert_non_null(strstr(h, "o\t--e\tflag\n"));
    free(h);
}

/* a CALL of three arguments (relight's --sun X Y Z, in the order given) and a FLAG with an action */
typedef struct n_opts {
    int seen[4][3], n, acted, flag;
} n_opts;

static const char *n_call(void *opts, char *const *v, int n, int *used)
{
    (void)n, (void)used;
    n_opts *o = opts;
    for (int k = 0; k < 3; ++k)
        if (strspn(v[k], "0123456789") != strlen(v[k]) || !v[k][0])
            return "wants three digit strings";
    if (o->n >= 4)
        return "at most four";
    for (int k = 0; k < 3; ++k)
        o->seen[o->n][k] = atoi(v[k]);
    ++o->n;
    return NULL;
}

static const char *act_call(void *opts, const char *v)
{
    n_opts *o = opts;
    assert_null(v);
    return o->acted++ ? "once only" : NULL;
}

static const qtool_opt n_table[] = {
    {.name = "--three", .kind = QTOOL_OPT_CALL, .nargs = 3, .call_n = n_call, .arg = "A B C", .help = "three"},
    {.name = "--act", .kind = QTOOL_OPT_FLAG, .off = offsetof(n_opts, flag), .call = act_call, .help = "acts"},
    {0},
};
static const qtool_opt_cmd n_cmd = {.name = "n", .opts = n_table, .size = sizeof(n_opts)};

static int n_parse(n_opts *o, char *err, size_t errn, int argc, char **argv)
{
    fflush(stderr);
    int saved = dup(2), fd = open(errlog, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    assert_true(saved >= 0 && fd >= 0);
    dup2(fd, 2);
    int rc = qtool_opt_parse(&n_cmd, argc, argv, 1, o);
    fflush(stderr);
    dup2(saved, 2);
    close(fd), close(saved);
    char *e = text(errlog);
    snprintf(err, errn, "%s", e);
    free(e);
    return rc;
}

static void test_table_nargs(void **state)
{
    (void)state;
    n_opts o;
    char err[512];
    char *a1[] = {"n", "--three", "1", "2", "3", "--act", "--three", "4", "5", "6"},
         *a2[] = {"n", "--three", "1", "2"}, *a3[] = {"n", "--three", "1", "x", "3"},
         *a4[] = {"n", "--act", "--act"};
    assert_int_equal(n_parse(&o, err, sizeof err, 10, a1), 0);
    assert_true(o.n == 2 && o.seen[0][0] == 1 && o.seen[0][2] == 3 && o.seen[1][0] == 4 && o.seen[1][2] == 6);
    assert_true(o.flag == 1 && o.acted == 1);
    assert_int_equal(n_parse(&o, err, sizeof err, 4, a2), 2);
    assert_string_equal(err, "qibl n: --three needs A B C; see qibl help n\n");
    assert_int_equal(n_parse(&o, err, sizeof err, 5, a3), 2); /* the reason names the values itself */
    assert_string_equal(err, "qibl n: --three: wants three digit strings; see qibl help n\n");
    assert_int_equal(n_parse(&o, err, sizeof err, 3, a4), 2);
    assert_string_equal(err, "qibl n: --act once only; see qibl help n\n");
}

/* --name=VALUE for an option with .eq (bake's --progress=MODE), positionals through a callback
 * (merge's and check's any number of files), and one callback for two fields (.field: --yaw of
 * relight, lights and sh project) */
typedef struct e_part {
    int n;
    const char *last;
} e_part;
typedef struct e_opts {
    int mode, files;
    long n;
    e_part a, b;
} e_opts;

static const char *e_field(void *part, const char *v)
{
    if (strcmp(v, "bad") == 0)
        return "is bad";
    e_part *p = part;
    p->n++, p->last = v;
    return NULL;
}
static const char *const e_modes[] = {"none", "bar", "lines", NULL};

static const char *e_file(void *opts, const char *v)
{
    if (strcmp(v, "bad") == 0)
        return "is bad";
    ((e_opts *)opts)->files++;
    return NULL;
}

static const qtool_opt e_table[] = {
    {.name = "--progress", .kind = QTOOL_OPT_ENUM, .eq = 1, .off = offsetof(e_opts, mode), .names = e_modes,
     .help = "a mode"},
    {.name = "--n", .kind = QTOOL_OPT_INT, .off = offsetof(e_opts, n), .lo = 1, .hi = 9, .help = "no = form"},
    {.name = "--a", .kind = QTOOL_OPT_CALL, .off = offsetof(e_opts, a), .field = 1, .call = e_field, .help = "a"},
    {.name = "--b", .kind = QTOOL_OPT_CALL, .off = offsetof(e_opts, b), .field = 1, .call = e_field, .help = "b"},
    {0},
};
static const qtool_opt_cmd e_cmd = {.name = "e", .opts = e_table, .size = sizeof(e_opts),
                                   .pos = {.names = "F...", .max = QTOOL_OPT_LIST_MAX, .call = e_file}};

static int e_parse(e_opts *o, char *err, size_t errn, int argc, char **argv)
{
    fflush(stderr);
    int saved = dup(2), fd = open(errlog, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    assert_true(saved >= 0 && fd >= 0);
    dup2(fd, 2);
    int rc = qtool_opt_parse(&e_cmd, argc, argv, 1, o);
    fflush(stderr);
    dup2(saved, 2);
    close(fd), close(saved);
    char *e = text(errlog);
    snprintf(err, errn, "%s", e);
    free(e);
    return rc;
}

static void test_table_eq_and_pos_call(void **state)
{
    (void)state;
    e_opts o;
    char err[512];
    char *a1[] = {"e", "--progress=lines"}, *a2[] = {"e", "--progress", "bar"}, *a3[] = {"e", "--progress=zip"},
         *a4[] = {"e", "--n=3"}, *a5[] = {"e", "x", "bad"};
    assert_int_equal(e_parse(&o, err, sizeof err, 2, a1), 0);
    assert_int_equal(o.mode, 2);
    assert_int_equal(e_parse(&o, err, sizeof err, 3, a2), 0);
    assert_int_equal(o.mode, 1);
    assert_int_equal(e_parse(&o, err, sizeof err, 2, a3), 2);
    assert_string_equal(err, "qibl e: --progress: 'zip' is not none, bar or lines; see qibl help e\n");
    assert_int_equal(e_parse(&o, err, sizeof err, 2, a4), 2); /* only where the table says .eq */
    assert_string_equal(err, "qibl e: unknown option '--n=3'; see qibl help e\n");
    /* more files than a list holds */
    char *many[QTOOL_OPT_LIST_MAX + 11];
    many[0] = "e";
    for (int k = 1; k < QTOOL_OPT_LIST_MAX + 11; ++k)
        many[k] = "f";
    assert_int_equal(e_parse(&o, err, sizeof err, QTOOL_OPT_LIST_MAX + 11, many), 0);
    assert_int_equal(o.files, QTOOL_OPT_LIST_MAX + 10);
    assert_int_equal(e_parse(&o, err, sizeof err, 3, a5), 2);
    assert_string_equal(err, "qibl e: 'bad' is bad; see qibl help e\n");
}

static void test_table_field(void **state)
{
    (void)state;
    e_opts o;
    char err[512];
    char *a1[] = {"e", "--b", "x", "--a", "y", "--b", "z"}, *a2[] = {"e", "--b", "bad"};
    assert_int_equal(e_parse(&o, err, sizeof err, 7, a1), 0);
    assert_int_equal(o.a.n, 1);
    assert_string_equal(o.a.last, "y");
    assert_int_equal(o.b.n, 2);
    assert_string_equal(o.b.last, "z");
    assert_int_equal(o.mode, 0); /* the struct's other fields untouched */
    assert_int_equal(o.files, 0);
    assert_int_equal(e_parse(&o, err, sizeof err, 3, a2), 2);
    assert_string_equal(err, "qibl e: --b: 'bad' is bad; see qibl help e\n");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_every_command, setup, teardown),
        cmocka_unit_test_setup_teardown(test_global_flags, setup, teardown),
        cmocka_unit_test_setup_teardown(test_values, setup, teardown),
        cmocka_unit_test_setup_teardown(test_table_kinds, setup, teardown),
        cmocka_unit_test_setup_teardown(test_table_refusals, setup, teardown),
        cmocka_unit_test_setup_teardown(test_table_help, setup, teardown),
        cmocka_unit_test(test_table_values),
        cmocka_unit_test_setup_teardown(test_table_sub, setup, teardown),
        cmocka_unit_test_setup_teardown(test_table_optional, setup, teardown),
        cmocka_unit_test_setup_teardown(test_table_nargs, setup, teardown),
        cmocka_unit_test_setup_teardown(test_table_eq_and_pos_call, setup, teardown),
        cmocka_unit_test_setup_teardown(test_table_field, setup, teardown),
    };
    return cmocka_run_group_tests_name("cli_opts", tests, NULL, NULL);
}
