/*
 * cli_silent_test.c - issue 24, classes 3 and 5: the qibl CLI run as a program on inputs that used
 * to give a wrong result without a word, or to write through a planted link or leave a truncated
 * file on a full disc. Each case checks the exit status and the one-line message (or note) that
 * names the problem.
 *
 * The binary is found as cliutil.h says; the tests skip when it is missing.
 */
#include <dirent.h>
#include <math.h>
#include <signal.h>
#include <sys/resource.h>

#include "cliutil.h"
#include "bake/path.h"
#include "io/atomic.h"
#include "io/hdr_write.h"
#include "qibl/lightpath.h"

CLI_FIXTURES("/tmp/qibl_silent_test_XXXXXX")

static int has(const char *log, const char *want)
{
    char *m = text(log);
    int ok = strstr(m, want) != NULL;
    free(m);
    return ok;
}

/* has, and prints the log when it does not */
static int says(const char *log, const char *want)
{
    if (has(log, want))
        return 1;
    char *m = text(log);
    fprintf(stderr, "%s says: %s\n(wanted '%s')\n", log, m, want);
    free(m);
    return 0;
}

static void put(const char *path, const char *s)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fputs(s, f);
    assert_int_equal(fclose(f), 0);
}

static int file_is(const char *path, const char *s)
{
    size_t n;
    uint8_t *b = qtool_io_read_all(path, &n);
    int ok = b && n == strlen(s) && memcmp(b, s, n) == 0;
    free(b);
    return ok;
}

/* a 64 x 32 lat-long probe: a bright upper half in rgb (scaled by k), a dim lower half */
static void probe(const char *path, float r, float g, float b, float k)
{
    enum { W = 64, H = 32 };
    static float px[W * H * 3];
    for (int v = 0; v < H; ++v)
        for (int u = 0; u < W; ++u) {
            float *p = px + 3 * (v * W + u);
            float s = v < H / 2 ? 1.0f : 0.25f;
            p[0] = r * s * k, p[1] = g * s * k, p[2] = b * s * k;
        }
    char err[512];
    if (qtool_hdr_write(path, W, H, px, err, sizeof err) != 0)
        fail_msg("%s", err);
}

/* the names in a directory besides . and .., joined by spaces; their count */
static int listing(const char *d, char *out, size_t n)
{
    DIR *dd = opendir(d);
    int c = 0;
    out[0] = '\0';
    if (!dd)
        return -1;
    struct dirent *e;
    while ((e = readdir(dd)) != NULL) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
            continue;
        size_t l = strlen(out);
        snprintf(out + l, n - l, "%s ", e->d_name);
        ++c;
    }
    closedir(dd);
    return c;
}

/* ---- study writes every file through the atomic writer (class 3) ---------------------------- */

/* A link planted at any of study's output names is refused by name, the link's target keeps its
 * bytes, and the study exits 1 (it used to write through the link and exit 0). */
static void test_study_refuses_planted_links(void **state)
{
    (void)state;
    need_qibl();
    probe(at("p.hdr"), 1.0f, 0.8f, 0.6f, 1.0f);
    static const char *names[] = {"overlay_p.png", "plot_p.svg", "study.csv", "plot_average.svg", "time_p.svg",
                                  "summary.md"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; ++i) {
        char od[64], link[600], victim[600];
        snprintf(od, sizeof od, "out%zu", i);
        assert_int_equal(mkdir(at(od), 0777), 0);
        snprintf(link, sizeof link, "%s/%s/%s", dir, od, names[i]);
        snprintf(victim, sizeof victim, "%s/victim%zu", dir, i);
        put(victim, "precious");
        assert_int_equal(symlink(victim, link), 0);
        int rc = run("study", "--quick", "--threads", "1", "--out", at(od), at("p.hdr"), NULL);
        if (rc != 1)
            fail_msg("study with a link at %s: exit %d, want 1", names[i], rc);
        assert_true(says(errlog, "refusing to replace a symbolic link"));
        assert_true(says(errlog, names[i]));
        if (!file_is(victim, "precious"))
            fail_msg("study wrote through the link at %s", names[i]);
        struct stat st;
        assert_int_equal(lstat(link, &st), 0);
        assert_true(S_ISLNK(st.st_mode));
    }
}

/* On a full disc (here: the file size limit, inherited by the child) the study says which file it
 * could not write, exits 1 and leaves no temporary and no truncated file behind. */
static void test_study_full_disc(void **state)
{
    (void)state;
    need_qibl();
    probe(at("p.hdr"), 1.0f, 0.8f, 0.6f, 1.0f);
    assert_int_equal(mkdir(at("out"), 0777), 0);
    struct rlimit old, lim;
    assert_int_equal(getrlimit(RLIMIT_FSIZE, &old), 0);
    void (*prev)(int) = signal(SIGXFSZ, SIG_IGN);
    lim = old;
    lim.rlim_cur = 1500; /* every file study writes is larger; stdout and stderr are smaller */
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &lim), 0);
    int rc = run("study", "--quick", "--threads", "1", "--out", at("out"), at("p.hdr"), NULL);
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &old), 0);
    signal(SIGXFSZ, prev);
    if (rc != 1)
        fail_msg("study on a full disc: exit %d, want 1", rc);
    assert_true(says(errlog, "write failed"));
    char names[4096];
    int n = listing(at("out"), names, sizeof names);
    if (n != 0)
        fail_msg("study on a full disc left: %s", names);
    assert_false(has(outlog, "wrote"));
}

/* ---- class 5: silent wrong results ------------------------------------------------------------- */

/* --auto's budget is a percentage (the sign optional): 5 is 5 %, not 500 %; out of (0, 100] it is
 * refused by name, never read as a path or a fraction. */
static void test_lights_auto_budget_is_a_percentage(void **state)
{
    (void)state;
    need_qibl();
    probe(at("p.hdr"), 1.0f, 0.8f, 0.6f, 1.0f);
    assert_int_equal(run("lights", at("p.hdr"), "--auto", "--error", "5", NULL), 0);
    assert_true(says(outlog, "<= 5.00 %"));
    assert_int_equal(run("lights", at("p.hdr"), "--auto", "--error", "5%", NULL), 0);
    assert_true(says(outlog, "<= 5.00 %"));
    static const char *bad[] = {"500", "500%", "100.5", "0", "-2", "1e9"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        int rc = run("lights", at("p.hdr"), "--auto", "--error", bad[i], NULL);
        if (rc != 2)
            fail_msg("--error %s: exit %d, want 2", bad[i], rc);
        assert_true(says(errlog, "percentage in (0, 100]"));
        assert_true(says(errlog, bad[i]));
    }
}

/* An all-black probe has no relative error: study and --auto refuse it by name instead of printing
 * NaN (a probe with one black channel is measured on the others). */
static void test_black_probe_refused(void **state)
{
    (void)state;
    need_qibl();
    probe(at("black.hdr"), 0, 0, 0, 1);
    probe(at("red.hdr"), 1, 0, 0, 1);
    int rc = run("lights", at("black.hdr"), "--auto", "--error", "2%", NULL);
    assert_int_equal(rc, 1);
    assert_true(says(errlog, "black everywhere"));
    assert_false(has(outlog, "nan"));
    rc = run("lights", at("red.hdr"), "--auto", "--error", "2%", NULL); /* measured on red alone */
    assert_int_equal(rc, 0);
    assert_false(has(outlog, "nan"));
    assert_int_equal(mkdir(at("out"), 0777), 0);
    rc = run("study", "--quick", "--threads", "1", "--out", at("out"), at("black.hdr"), NULL);
    assert_int_equal(rc, 1);
    assert_true(says(errlog, "black everywhere"));
    assert_false(has(outlog, "nan"));
    char names[4096];
    assert_int_equal(listing(at("out"), names, sizeof names), 0);
}

/* CSV light directions are normalised after scaling by the largest component: 1e-300 and 1e200
 * components light the frame as 1 does (they used to square to 0 or inf: a black frame); a NUL byte
 * is named as one, not as an over-long line. */
static void test_csv_directions_and_nul(void **state)
{
    (void)state;
    need_qibl();
    assert_int_equal(run("gen", "-o", at("g.qibl"), "--size", "32x8", NULL), 0);
    static const char *rows[][2] = {{"1,1,1", "-2,0,1"}, {"1e-300,1e-300,1e-300", "-2e-300,0,1e-300"},
                                    {"1e200,1e200,1e200", "-2e200,0,1e200"}, {"4e-320,4e-320,4e-320", "-2e-310,0,1e-310"}};
    char first[600] = "";
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; ++i) {
        char csv[64], png[64], body[400];
        snprintf(csv, sizeof csv, "l%zu.csv", i);
        snprintf(png, sizeof png, "l%zu.png", i);
        snprintf(body, sizeof body, "x,y,z,r,g,b,u0,v0,u1,v1\n%s,3,2,1,0,0,1,1\r\n%s,1,1,1,0,0,1,1\n", rows[i][0],
                 rows[i][1]);
        put(at(csv), body);
        int rc = run("relight", at("g.qibl"), "--lights", at(csv), "--png", at(png), NULL);
        if (rc != 0) {
            char *m = text(errlog);
            fail_msg("relight --lights with %s: exit %d: %s", rows[i][0], rc, m);
        }
        if (i == 0) {
            snprintf(first, sizeof first, "%s", at(png));
            continue;
        }
        size_t na, nb;
        uint8_t *a = qtool_io_read_all(first, &na), *b = qtool_io_read_all(at(png), &nb);
        assert_non_null(a), assert_non_null(b);
        if (na != nb || memcmp(a, b, na) != 0)
            fail_msg("directions %s / %s light the frame differently from %s / %s", rows[i][0], rows[i][1],
                     rows[0][0], rows[0][1]);
        free(a), free(b);
    }
    /* a NUL byte, early in a line or after 1100 bytes */
    static const char head[] = "x,y,z,r,g,b,u0,v0,u1,v1\n0,0";
    FILE *f = fopen(at("nul.csv"), "wb");
    assert_non_null(f);
    fwrite(head, 1, sizeof head - 1, f);
    fputc('\0', f);
    fputs(",1,1,1,1,0,0,1,1\n", f);
    assert_int_equal(fclose(f), 0);
    assert_int_equal(run("relight", at("g.qibl"), "--lights", at("nul.csv"), "--png", at("n.png"), NULL), 1);
    assert_true(says(errlog, "nul.csv:2: a NUL byte at column 4"));
    f = fopen(at("nul2.csv"), "wb");
    assert_non_null(f);
    fputs("x,y,z,r,g,b,u0,v0,u1,v1\n", f);
    for (int i = 0; i < 1100; ++i)
        fputc('1', f);
    fputc('\0', f);
    fputs("\n", f);
    assert_int_equal(fclose(f), 0);
    assert_int_equal(run("relight", at("g.qibl"), "--lights", at("nul2.csv"), "--png", at("n.png"), NULL), 1);
    assert_true(says(errlog, "nul2.csv:2: a NUL byte at column 1101"));
    /* a true zero is refused by name, as before; so is a value beyond double range */
    put(at("z.csv"), "x,y,z,r,g,b,u0,v0,u1,v1\n0,-0,0,1,1,1,0,0,1,1\n");
    assert_int_equal(run("relight", at("g.qibl"), "--lights", at("z.csv"), "--png", at("n.png"), NULL), 1);
    assert_true(says(errlog, "direction 0,0,0 is not a direction"));
    /* --lights and --probe at most once each (relight/spec.c), the first one named */
    assert_int_equal(run("relight", at("g.qibl"), "--lights", at("z.csv"), "--lights", at("big.csv"), "--png", at("n.png"), NULL), 2);
    assert_true(says(errlog, "big.csv' is a second --lights (the first: "));
    assert_int_equal(run("relight", at("g.qibl"), "--probe", at("a.hdr"), "--probe", at("b.hdr"), "--png", at("n.png"), NULL), 2);
    assert_true(says(errlog, "b.hdr' is a second --probe (the first: "));
    put(at("big.csv"), "x,y,z,r,g,b,u0,v0,u1,v1\n0,1e999,0,1,1,1,0,0,1,1\n");
    assert_int_equal(run("relight", at("g.qibl"), "--lights", at("big.csv"), "--png", at("n.png"), NULL), 1);
    assert_true(says(errlog, "y '1e999' is beyond double range"));
    assert_int_equal(access(at("n.png"), F_OK), -1);
}

/* sh project --format c never prints a literal beyond float range: a coefficient above FLT_MAX
 * is refused by name before anything is printed (json and table still write it). */
static void test_sh_format_c_float_range(void **state)
{
    (void)state;
    need_qibl();
    probe(at("huge.hdr"), 1.0f, 1.0f, 0.5f, 1.6e38f); /* c[0] about 3.5 x the radiance */
    assert_int_equal(run("sh", "project", at("huge.hdr"), "--format", "c", NULL), 1);
    assert_true(says(errlog, "coefficient [0] (l = 0, m = +0) R is"));
    assert_true(says(errlog, "beyond float range"));
    char *o = text(outlog);
    assert_string_equal(o, "");
    free(o);
    assert_int_equal(run("sh", "project", at("huge.hdr"), "--format", "json", NULL), 0);
    probe(at("p.hdr"), 1.0f, 0.8f, 0.6f, 1.0f);
    assert_int_equal(run("sh", "project", at("p.hdr"), "--format", "c", NULL), 0);
    assert_true(says(outlog, "static const float"));
}

/* bake --shard: a shard whose side file could not be written exits 1 and never says "wrote" */
static void test_bake_shard_failure_not_wrote(void **state)
{
    (void)state;
    need_qibl();
    put(at("victim"), "precious");
    assert_int_equal(symlink(at("victim"), at("s0.u")), 0);
    int rc = run("bake", "--size", "16x4", "--k", "4", "--dirs", "48", "--unshadowed-k", "4", "--shard", "0/2", "--sums",
                 at("s0"), "--quiet", "--threads", "1", NULL);
    assert_int_equal(rc, 1);
    assert_true(says(errlog, "refusing to replace a symbolic link"));
    assert_false(has(outlog, "wrote"));
    assert_int_equal(access(at("s0"), F_OK), -1);
    assert_true(file_is(at("victim"), "precious"));
}

/* the asset at src with a LOCC chunk of w x h (all 128) appended, written to dst */
static void with_locc(const char *src, const char *dst, uint32_t w, uint32_t h)
{
    size_t n, pn, on;
    uint8_t *a = qtool_io_read_all(src, &n), *vals = malloc((size_t)w * h), *pay = NULL, *out = NULL;
    assert_non_null(a), assert_non_null(vals);
    memset(vals, 128, (size_t)w * h);
    assert_int_equal(qtool_bake_locc_payload(w, h, vals, &pay, &pn), 0);
    assert_int_equal(qtool_bake_asset_add(a, n, QIBL_CHUNK_LOCC, pay, pn, &out, &on), 0);
    char err[1200];
    if (qtool_io_write_atomic(dst, out, on, err, sizeof err) != 0)
        fail_msg("%s", err);
    free(a), free(vals), free(pay), free(out);
}

/* A LOCC chunk relight cannot use is said (it used to be dropped without a word), and info lists
 * LOCC, usable or not. */
static void test_locc_said(void **state)
{
    (void)state;
    need_qibl();
    int rc = run("bake", "-o", at("b.qibl"), "--size", "16x4", "--k", "4", "--dirs", "48", "--unshadowed-k", "4",
                 "--quiet", "--threads", "1", NULL);
    if (rc != 0) {
        char *m = text(errlog);
        fail_msg("bake: exit %d: %s", rc, m);
    }
    with_locc(at("b.qibl"), at("good.qibl"), 16, 4);
    with_locc(at("b.qibl"), at("bad.qibl"), 8, 4); /* not SHMP's size */
    assert_int_equal(run("info", at("good.qibl"), NULL), 0);
    assert_true(says(outlog, "LOCC: lamp occlusion, 16 x 4 pixels"));
    assert_int_equal(run("info", at("bad.qibl"), NULL), 0);
    assert_true(says(outlog, "LOCC: not usable"));
    assert_int_equal(run("relight", at("good.qibl"), "--point", "0", "0", "1", "--png", at("g.png"), NULL), 0);
    assert_false(has(errlog, "LOCC"));
    assert_int_equal(run("relight", at("bad.qibl"), "--point", "0", "0", "1", "--png", at("b.png"), NULL), 0);
    assert_true(says(errlog, "its LOCC chunk is not usable"));
}

/* --path frames get the almost-black note every other relight gets; a sun path that never rises
 * is refused by name before anything is baked */
static void test_path_dark_and_never_rising(void **state)
{
    (void)state;
    need_qibl();
    int rc = run("bake", "-o", at("p.qibl"), "--size", "24x6", "--k", "4", "--dirs", "64", "--unshadowed-k", "4",
                 "--sun-path", "40,15,7,17", "--path-steps", "8", "--quiet", "--threads", "1", NULL);
    if (rc != 0) {
        char *m = text(errlog);
        fail_msg("bake: exit %d: %s", rc, m);
    }
    assert_int_equal(run("relight", at("p.qibl"), "--path", "sun", "--t", "0.5", "--rgb", "0.0001", "0.0001", "0.0001",
                         "--png", at("d.png"), NULL),
                     0);
    assert_true(says(errlog, "almost black"));
    rc = run("bake", "-o", at("n.qibl"), "--size", "24x6", "--k", "4", "--dirs", "64", "--unshadowed-k", "4",
             "--sun-path", "80,-20,0,24", "--quiet", "--threads", "1", NULL);
    assert_int_equal(rc, 2);
    assert_true(says(errlog, "the sun never rises"));
    assert_int_equal(access(at("n.qibl"), F_OK), -1);
}

/* A probe whose light is below the SH light's Q16.16 resolution relights to exact zero: a note
 * says so, whatever the output (it used to be silent with --hdr) */
static void test_tiny_probe_noted(void **state)
{
    (void)state;
    need_qibl();
    assert_int_equal(run("gen", "-o", at("g.qibl"), "--size", "32x8", NULL), 0);
    probe(at("tiny.hdr"), 1.0f, 0.8f, 0.6f, 1e-30f);
    probe(at("p.hdr"), 1.0f, 0.8f, 0.6f, 1.0f);
    static const char *modes[] = {"sh", "lights", "sunsky"};
    for (int i = 0; i < 3; ++i) {
        assert_int_equal(run("relight", at("g.qibl"), "--probe", at("tiny.hdr"), "--probe-mode", modes[i], "--hdr",
                             at("t.hdr"), NULL),
                         0);
        if (!has(errlog, "relights to exact zero"))
            fail_msg("--probe-mode %s: no note for a 1e-30 probe", modes[i]);
    }
    assert_int_equal(run("relight", at("g.qibl"), "--probe", at("p.hdr"), "--hdr", at("t.hdr"), NULL), 0);
    assert_false(has(errlog, "exact zero"));
}

static void bake_shard(const char *size, const char *in, const char *sums)
{
    int rc = run("bake", "--size", size, "--k", "4", "--dirs", "64", "--unshadowed-k", "4", "--sun-path", "40,15,7,17",
                 "--lamp-box", "-2,-2,-1,2,2,0", "--lamp-samples", "4", "--path-steps", "8", "--shard", in, "--sums",
                 at(sums), "--quiet", "--threads", "1", NULL);
    if (rc != 0) {
        char *m = text(errlog);
        fail_msg("bake --shard %s: exit %d: %s", in, rc, m);
    }
}

static void copy_file(const char *from, const char *to)
{
    size_t n;
    uint8_t *b = qtool_io_read_all(from, &n);
    assert_non_null(b);
    char err[1200];
    if (qtool_io_write_atomic(to, b, n, err, sizeof err) != 0)
        fail_msg("%s", err);
    free(b);
}

/* merge refuses shard 0's side file (LPTH, LOCC) from a bake of another size by name; it used to
 * write an asset whose light path no relight could use */
static void test_merge_extras_of_another_size(void **state)
{
    (void)state;
    need_qibl();
    bake_shard("24x6", "0/2", "s0");
    bake_shard("24x6", "1/2", "s1");
    bake_shard("16x6", "0/2", "b0");
    assert_int_equal(run("merge", "-o", at("ok.qibl"), at("s0"), at("s1"), NULL), 0);
    assert_int_equal(run("relight", at("ok.qibl"), "--path", "sun", "--t", "0.5", "--png", at("ok.png"), NULL), 0);
    copy_file(at("b0.x"), at("s0.x"));
    assert_int_equal(run("merge", "-o", at("m.qibl"), at("s0"), at("s1"), NULL), 1);
    assert_true(says(errlog, "is for a 16 x 6 bake, the shards are 24 x 6"));
    assert_int_equal(access(at("m.qibl"), F_OK), -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_study_refuses_planted_links, setup, teardown),
        cmocka_unit_test_setup_teardown(test_study_full_disc, setup, teardown),
        cmocka_unit_test_setup_teardown(test_lights_auto_budget_is_a_percentage, setup, teardown),
        cmocka_unit_test_setup_teardown(test_black_probe_refused, setup, teardown),
        cmocka_unit_test_setup_teardown(test_csv_directions_and_nul, setup, teardown),
        cmocka_unit_test_setup_teardown(test_sh_format_c_float_range, setup, teardown),
        cmocka_unit_test_setup_teardown(test_bake_shard_failure_not_wrote, setup, teardown),
        cmocka_unit_test_setup_teardown(test_locc_said, setup, teardown),
        cmocka_unit_test_setup_teardown(test_path_dark_and_never_rising, setup, teardown),
        cmocka_unit_test_setup_teardown(test_tiny_probe_noted, setup, teardown),
        cmocka_unit_test_setup_teardown(test_merge_extras_of_another_size, setup, teardown),
    };
    return cmocka_run_group_tests_name("cli_silent", tests, NULL, NULL);
}
