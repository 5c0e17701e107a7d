/*
 * cli_opts_test.c - the option tables of the qibl CLI (tools/cli/opt.h), through the program: for
 * every command in the command table (as `qibl --help` lists it) an unknown flag gets one line
 * `qibl CMD[ SUB]: ... '--no-such-flag' ...; see qibl help CMD` and exit 2; every flag of a command's
 * tables (`qibl help --flags CMD`) appears in `qibl help CMD` and is known to the parser.
 */
#include "cliutil.h"

CLI_FIXTURES("/tmp/qibl_cli_opts_test_XXXXXX")

/* not yet on option tables: their parsers are hand-written (shrink this list as they convert) */
static const char *const not_yet_on_option_tables[] = {
    "bench", "render", "transfer", "bake", "merge", "check", "demo", "relight", "view", "lights", "probe",
};

#define BAD "--no-such-flag"

static int not_yet(const char *cmd)
{
    for (size_t i = 0; i < sizeof not_yet_on_option_tables / sizeof *not_yet_on_option_tables; ++i)
        if (strcmp(not_yet_on_option_tables[i], cmd) == 0)
            return 1;
    return 0;
}

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
    int n = list_commands(names, 64), checked = 0;
    assert_true(n >= 10);
    for (int i = 0; i < n; ++i) {
        if (not_yet(names[i])) {
            /* still hand-written: once it has a table, it must leave the list */
            assert_int_equal(run("help", "--flags", names[i], NULL), 0);
            char *f = text(outlog);
            if (f[0] != '\0')
                fail_msg("%s is on option tables now: remove it from not_yet_on_option_tables", names[i]);
            free(f);
            continue;
        }
        check_command(names[i]);
        ++checked;
    }
    print_message("%d commands on option tables, %d not yet\n", checked, n - checked);
    assert_true(checked >= 6);
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
    assert_int_equal(run("sh", "eval", "-1", "0", "0", NULL), 0);
    assert_int_equal(run("srgbe", "encode", "-inf", "-1", "1", NULL), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_every_command, setup, teardown),
        cmocka_unit_test_setup_teardown(test_global_flags, setup, teardown),
        cmocka_unit_test_setup_teardown(test_values, setup, teardown),
    };
    return cmocka_run_group_tests_name("cli_opts", tests, NULL, NULL);
}
