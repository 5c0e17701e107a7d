/*
 * atomic_test.c - safe output (tools/io/atomic.h) through every file writer of the tools: PNG,
 * APNG, PFM, asset, bake partial sums, golden hash files and the plain helper. For each writer: a
 * symbolic link planted at the old predictable temporary name ("OUT.tmp") is not written through;
 * a destination that is a symbolic link, a FIFO or a directory is refused by name and left as it
 * was; a write that fails half-way (file size limit) leaves the destination untouched and no
 * temporary file; permissions are those of a new file (0666 less the umask); two writers racing on
 * one path each either fail cleanly or leave a complete file.
 */
#include <dirent.h>
#include <errno.h>
#include <pthread.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>
#include <cmocka.h>

#include "bake/bake.h"
#include "gen/scene.h"
#include "io/asset_write.h"
#include "io/atomic.h"
#include "io/file.h"
#include "io/golden.h"
#include "io/pfm.h"
#include "io/png.h"

/* ---- the writers under test: each writes a variant (0 or 1, different bytes) to path ---------- */

typedef int (*writer_fn)(const char *path, int variant, char *err, size_t errlen);

enum { PW = 256, PH = 128 }; /* big enough that a racing writer is caught mid-file */

static int w_png(const char *path, int variant, char *err, size_t errlen)
{
    static uint8_t px[2][PW * PH * 3];
    for (size_t i = 0; i < sizeof px[0]; ++i)
        px[variant][i] = (uint8_t)(i * (variant ? 7u : 13u) + (uint32_t)variant);
    return qtool_png_write_rgb8(path, PW, PH, px[variant], err, errlen);
}

static int w_apng(const char *path, int variant, char *err, size_t errlen)
{
    static uint8_t px[2][2 * PW * PH * 3];
    for (size_t i = 0; i < sizeof px[0]; ++i)
        px[variant][i] = (uint8_t)(i * (variant ? 5u : 11u));
    return qtool_apng_write_rgb8(path, PW, PH, 2, px[variant], 1, 8, err, errlen);
}

static int w_pfm(const char *path, int variant, char *err, size_t errlen)
{
    static float px[2][PW * PH * 3];
    for (size_t i = 0; i < PW * PH * 3; ++i)
        px[variant][i] = (float)i * (variant ? 0.5f : 0.25f);
    return qtool_pfm_write(path, PW, PH, 3, px[variant], err, errlen);
}

static int w_asset(const char *path, int variant, char *err, size_t errlen)
{
    qtool_gen_maps g;
    uint32_t w = variant ? 128 : 256, h = 64, k = 1;
    if (qtool_gen_scene(w, h, k, QTOOL_PANO_CYLINDRICAL, &g) != 0)
        return snprintf(err, errlen, "gen failed"), -1;
    int32_t scale[3], bias[3];
    uint8_t *planes = malloc((size_t)w * h * 3);
    qtool_asset_builder b;
    qtool_asset_builder_init(&b);
    int rc = !planes || qtool_pack_maps(&g, QTOOL_PACK_MINMAX, scale, bias, planes, NULL) != 0 ||
                     qtool_asset_add_shmp(&b, w, h, k, 3, scale, bias, planes) != 0 ||
                     qtool_asset_add_pmap(&b, w, h, g.p) != 0 || qtool_asset_write_file(&b, path, 1) != 0
                 ? -1
                 : 0;
    if (rc != 0)
        snprintf(err, errlen, "%s", b.err);
    qtool_asset_builder_free(&b);
    free(planes);
    qtool_gen_free(&g);
    return rc;
}

static int w_sums(const char *path, int variant, char *err, size_t errlen)
{
    enum { SW = 64, SH = 32, SK = 4 };
    static int32_t pmap[2][SW * SH * 3]; /* one per variant: the race test runs both at once */
    static int64_t acc[2][SW * SH * 3 * SK];
    for (size_t i = 0; i < SW * SH * 3; ++i)
        pmap[variant][i] = (int32_t)i;
    for (size_t i = 0; i < SW * SH * 3 * SK; ++i)
        acc[variant][i] = (int64_t)i * (variant ? 3 : -5);
    qtool_bake_sums s = {SW, SH, SK, 64, 0, 0, 1, pmap[variant], acc[variant]};
    return qtool_bake_sums_write(&s, path, err, errlen);
}

static int w_plain(const char *path, int variant, char *err, size_t errlen)
{
    static char text[2][20000];
    memset(text[variant], variant ? 'b' : 'a', sizeof text[0]);
    return qtool_io_write_atomic(path, text[variant], sizeof text[0], err, errlen);
}

/* golden hash files: path is ROOT/fixtures/golden/NAME.sha256 with QIBL_ROOT=ROOT */
static int w_golden(const char *path, int variant, char *err, size_t errlen)
{
    char root[512], name[256];
    const char *g = strstr(path, "/fixtures/golden/");
    if (!g)
        return snprintf(err, errlen, "bad golden path"), -1;
    snprintf(root, sizeof root, "%.*s", (int)(g - path), path);
    snprintf(name, sizeof name, "%s", g + strlen("/fixtures/golden/"));
    *strstr(name, ".sha256") = '\0';
    setenv("QIBL_ROOT", root, 1);
    setenv("QIBL_UPDATE_GOLDEN", "1", 1);
    int rc = qtool_golden_check(name, variant ? "bbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbb"
                                             : "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa");
    unsetenv("QIBL_UPDATE_GOLDEN");
    unsetenv("QIBL_ROOT");
    if (rc != 0)
        snprintf(err, errlen, "%s: refused or failed (see stderr)", path);
    return rc;
}

static const struct {
    const char *name, *file;
    writer_fn fn;
} writers[] = {
    {"png", "out.png", w_png},
    {"apng", "out.png", w_apng},
    {"pfm", "out.pfm", w_pfm},
    {"asset", "out.qibl", w_asset},
    {"sums", "out.sums", w_sums},
    {"plain", "out.bin", w_plain},
    {"golden", "fixtures/golden/case.sha256", w_golden},
};
#define NW (sizeof writers / sizeof writers[0])

/* ---- helpers ----------------------------------------------------------------------------------- */

static char *dir_new(void)
{
    char *d = malloc(64);
    assert_non_null(d);
    snprintf(d, 64, "/tmp/qibl_atomic_test_XXXXXX");
    assert_non_null(mkdtemp(d));
    char p[512];
    snprintf(p, sizeof p, "%s/fixtures", d);
    assert_int_equal(mkdir(p, 0777), 0);
    snprintf(p, sizeof p, "%s/fixtures/golden", d);
    assert_int_equal(mkdir(p, 0777), 0);
    return d;
}

static void rm_rf(const char *path)
{
    struct stat st;
    if (lstat(path, &st) != 0)
        return;
    if (S_ISDIR(st.st_mode)) {
        DIR *d = opendir(path);
        struct dirent *e;
        while (d && (e = readdir(d)) != NULL) {
            if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
                continue;
            char p[1024];
            snprintf(p, sizeof p, "%s/%s", path, e->d_name);
            rm_rf(p);
        }
        if (d)
            closedir(d);
        rmdir(path);
    } else {
        unlink(path);
    }
}

/* entries of dir (not . and ..), names joined by spaces into out */
static int list_dir(const char *dir, char *out, size_t n)
{
    DIR *d = opendir(dir);
    assert_non_null(d);
    struct dirent *e;
    int count = 0;
    out[0] = '\0';
    while ((e = readdir(d)) != NULL) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
            continue;
        size_t l = strlen(out);
        snprintf(out + l, n - l, "%s%s", l ? " " : "", e->d_name);
        ++count;
    }
    closedir(d);
    return count;
}

static void put_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fputs(text, f);
    assert_int_equal(fclose(f), 0);
}

static int file_is(const char *path, const char *text)
{
    size_t n;
    uint8_t *b = qtool_io_read_all(path, &n);
    int same = b && n == strlen(text) && memcmp(b, text, n) == 0;
    free(b);
    return same;
}

static void paths(const char *dir, int w, char *out, size_t n)
{
    snprintf(out, n, "%s/%s", dir, writers[w].file);
}

/* the directory holding the output (where temporary files would be left) */
static void out_dir(const char *dir, int w, char *out, size_t n)
{
    paths(dir, w, out, n);
    *strrchr(out, '/') = '\0';
}

/* ---- tests ------------------------------------------------------------------------------------- */

/* A symbolic link planted at OUT.tmp (the name every writer used before) must not be written
 * through: the file it points to stays as it was, and the output is a regular file. */
static void test_planted_symlink_at_predictable_name(void **state)
{
    (void)state;
    for (size_t w = 0; w < NW; ++w) {
        char *d = dir_new(), out[600], tmp[700], victim[600], err[1200];
        paths(d, (int)w, out, sizeof out);
        snprintf(tmp, sizeof tmp, "%s.tmp", out);
        snprintf(victim, sizeof victim, "%s/victim", d);
        put_file(victim, "precious");
        assert_int_equal(symlink(victim, tmp), 0);
        if (writers[w].fn(out, 0, err, sizeof err) != 0)
            fail_msg("%s: %s", writers[w].name, err);
        if (!file_is(victim, "precious"))
            fail_msg("%s: wrote through the symbolic link planted at %s", writers[w].name, tmp);
        struct stat st;
        assert_int_equal(lstat(out, &st), 0);
        if (!S_ISREG(st.st_mode))
            fail_msg("%s: the output is not a regular file (the planted link was renamed over it)", writers[w].name);
        rm_rf(d);
        free(d);
    }
}

/* A destination that is a symbolic link, a FIFO or a directory is refused by name, untouched. */
static void test_refuses_non_regular_destination(void **state)
{
    (void)state;
    static const char *kinds[] = {"symbolic link", "FIFO", "directory"};
    for (size_t w = 0; w < NW; ++w)
        for (int kind = 0; kind < 3; ++kind) {
            char *d = dir_new(), out[600], victim[600], err[1200] = "", listing[4096];
            paths(d, (int)w, out, sizeof out);
            snprintf(victim, sizeof victim, "%s/victim", d);
            put_file(victim, "precious");
            if (kind == 0)
                assert_int_equal(symlink(victim, out), 0);
            else if (kind == 1)
                assert_int_equal(mkfifo(out, 0666), 0);
            else
                assert_int_equal(mkdir(out, 0777), 0);
            if (writers[w].fn(out, 0, err, sizeof err) == 0)
                fail_msg("%s: replaced a %s", writers[w].name, kinds[kind]);
            char want[64];
            snprintf(want, sizeof want, "refusing to replace a %s", kinds[kind]);
            if (strcmp(writers[w].name, "golden") != 0 && strstr(err, want) == NULL)
                fail_msg("%s: a %s as destination: '%s' does not say '%s'", writers[w].name, kinds[kind], err, want);
            struct stat st;
            assert_int_equal(lstat(out, &st), 0);
            assert_true(kind == 0 ? S_ISLNK(st.st_mode) : kind == 1 ? S_ISFIFO(st.st_mode) : S_ISDIR(st.st_mode));
            assert_true(file_is(victim, "precious"));
            char od[600];
            out_dir(d, (int)w, od, sizeof od);
            int n = list_dir(od, listing, sizeof listing);
            /* the destination (and in the top directory the victim and fixtures/) only */
            int expect = strcmp(od, d) == 0 ? 3 : 1;
            if (n != expect)
                fail_msg("%s: %s left behind: %s", writers[w].name, kinds[kind], listing);
            rm_rf(d);
            free(d);
        }
}

/* A write that fails half-way (here: the file size limit) leaves the old destination and no
 * temporary file behind. */
static void test_failed_write_leaves_destination_and_no_temp(void **state)
{
    (void)state;
    struct rlimit old, lim;
    assert_int_equal(getrlimit(RLIMIT_FSIZE, &old), 0);
    void (*prev)(int) = signal(SIGXFSZ, SIG_IGN);
    for (size_t w = 0; w < NW; ++w) {
        if (strcmp(writers[w].name, "golden") == 0)
            continue; /* 65 bytes: smaller than any limit that leaves the test room to work */
        char *d = dir_new(), out[600], err[1200] = "", listing[4096], od[600];
        paths(d, (int)w, out, sizeof out);
        put_file(out, "old contents");
        lim = old;
        lim.rlim_cur = 100; /* every writer's output is larger */
        assert_int_equal(setrlimit(RLIMIT_FSIZE, &lim), 0);
        int rc = writers[w].fn(out, 0, err, sizeof err);
        assert_int_equal(setrlimit(RLIMIT_FSIZE, &old), 0);
        if (rc == 0)
            fail_msg("%s: reported success past the file size limit", writers[w].name);
        if (strstr(err, out) == NULL)
            fail_msg("%s: the message '%s' does not name %s", writers[w].name, err, out);
        assert_true(file_is(out, "old contents"));
        out_dir(d, (int)w, od, sizeof od);
        int n = list_dir(od, listing, sizeof listing);
        if (n != (strcmp(od, d) == 0 ? 2 : 1))
            fail_msg("%s: left behind: %s", writers[w].name, listing);
        rm_rf(d);
        free(d);
    }
    signal(SIGXFSZ, prev);
}

/* A new file gets 0666 less the umask, like any created file (not mkstemp's 0600). */
static void test_permissions_follow_umask(void **state)
{
    (void)state;
    static const mode_t masks[2] = {022, 077};
    for (size_t w = 0; w < NW; ++w)
        for (int m = 0; m < 2; ++m) {
            char *d = dir_new(), out[600], err[1200];
            paths(d, (int)w, out, sizeof out);
            mode_t prev = umask(masks[m]);
            int rc = writers[w].fn(out, 1, err, sizeof err);
            umask(prev);
            if (rc != 0)
                fail_msg("%s: %s", writers[w].name, err);
            struct stat st;
            assert_int_equal(stat(out, &st), 0);
            if ((st.st_mode & 0777) != (0666 & ~masks[m]))
                fail_msg("%s: mode %03o under umask %03o", writers[w].name, (unsigned)(st.st_mode & 0777),
                         (unsigned)masks[m]);
            rm_rf(d);
            free(d);
        }
}

typedef struct {
    writer_fn fn;
    const char *path;
    int variant, rc;
    char err[1200];
} race_arg;

static void *race(void *p)
{
    race_arg *a = p;
    a->rc = a->fn(a->path, a->variant, a->err, sizeof a->err);
    return NULL;
}

/* Two writers racing on one path: each either fails with a message or leaves a complete file, and
 * the file is always exactly one of the two outputs (never a mix, never truncated). */
static void test_concurrent_writers(void **state)
{
    (void)state;
    for (size_t w = 0; w < NW; ++w) {
        if (strcmp(writers[w].name, "golden") == 0)
            continue; /* sets process-wide environment variables: not thread-safe by design */
        char *d = dir_new(), out[600], ref[2][700], listing[4096], err[1200], od[600];
        paths(d, (int)w, out, sizeof out);
        size_t rn[2];
        uint8_t *rb[2];
        for (int v = 0; v < 2; ++v) { /* the two complete outputs, written alone */
            snprintf(ref[v], sizeof ref[v], "%s.ref%d", out, v);
            assert_int_equal(writers[w].fn(ref[v], v, err, sizeof err), 0);
            rb[v] = qtool_io_read_all(ref[v], &rn[v]);
            assert_non_null(rb[v]);
        }
        for (int round = 0; round < 16; ++round) {
            race_arg a[2] = {{writers[w].fn, out, 0, 0, ""}, {writers[w].fn, out, 1, 0, ""}};
            pthread_t t[2];
            for (int i = 0; i < 2; ++i)
                assert_int_equal(pthread_create(&t[i], NULL, race, &a[i]), 0);
            for (int i = 0; i < 2; ++i)
                pthread_join(t[i], NULL);
            for (int i = 0; i < 2; ++i)
                if (a[i].rc != 0 && a[i].err[0] == '\0')
                    fail_msg("%s: a racing writer failed without a message", writers[w].name);
            if (a[0].rc != 0 && a[1].rc != 0)
                continue;
            size_t n;
            uint8_t *b = qtool_io_read_all(out, &n);
            assert_non_null(b);
            int same0 = n == rn[0] && memcmp(b, rb[0], n) == 0, same1 = n == rn[1] && memcmp(b, rb[1], n) == 0;
            free(b);
            if (!same0 && !same1)
                fail_msg("%s, round %d: after two writers reported %d and %d the file (%zu bytes) is neither output "
                         "(%zu or %zu bytes)", writers[w].name, round, a[0].rc, a[1].rc, n, rn[0], rn[1]);
        }
        out_dir(d, (int)w, od, sizeof od);
        int n = list_dir(od, listing, sizeof listing);
        if (n != 4)
            fail_msg("%s: temporary files left: %s", writers[w].name, listing);
        for (int v = 0; v < 2; ++v) {
            free(rb[v]);
            unlink(ref[v]);
        }
        rm_rf(d);
        free(d);
    }
}

/* The helpers' own contract: bad names, a missing directory, replace a regular file, an encoder's
 * bytes or failure. */
static void test_helper_errors(void **state)
{
    (void)state;
    char err[1200];
    assert_int_equal(qtool_io_write_atomic("", "x", 1, err, sizeof err), -1);
    assert_int_equal(qtool_io_write_atomic("/tmp/", "x", 1, err, sizeof err), -1);
    assert_non_null(strstr(err, "refusing to replace a directory"));
    assert_int_equal(qtool_io_write_atomic("/tmp/qibl-no-such-dir-atomic/", "x", 1, err, sizeof err), -1);
    assert_non_null(strstr(err, "no file name"));
    assert_int_equal(qtool_io_write_atomic("/nonexistent-dir-qibl/x", "x", 1, err, sizeof err), -1);
    assert_non_null(strstr(err, "/nonexistent-dir-qibl/x"));
    char *d = dir_new(), out[600], listing[4096];
    snprintf(out, sizeof out, "%s/f", d);
    put_file(out, "old");
    assert_int_equal(qtool_io_write_atomic(out, "new", 3, err, sizeof err), 0);
    assert_true(file_is(out, "new"));
    qtool_io_atomic a;
    assert_int_equal(qtool_io_atomic_open(&a, out, err, sizeof err), 0);
    fputs("abandoned", a.f);
    qtool_io_atomic_abort(&a);
    assert_true(file_is(out, "new"));
    /* qtool_io_write_encoded: a failed encoder is out of memory, named, the file untouched; else
     * the malloc'ed bytes are written and freed (ASan: no leak) */
    assert_int_equal(qtool_io_write_encoded(out, -1, NULL, 0, err, sizeof err), -1);
    assert_non_null(strstr(err, "out of memory"));
    assert_non_null(strstr(err, out));
    assert_true(file_is(out, "new"));
    uint8_t *enc = malloc(7);
    assert_non_null(enc);
    memcpy(enc, "encoded", 7);
    assert_int_equal(qtool_io_write_encoded(out, 0, enc, 7, err, sizeof err), 0);
    assert_true(file_is(out, "encoded"));
    assert_int_equal(list_dir(d, listing, sizeof listing), 2); /* f and fixtures/ */
    rm_rf(d);
    free(d);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_planted_symlink_at_predictable_name),
        cmocka_unit_test(test_refuses_non_regular_destination),
        cmocka_unit_test(test_failed_write_leaves_destination_and_no_temp),
        cmocka_unit_test(test_permissions_follow_umask),
        cmocka_unit_test(test_concurrent_writers),
        cmocka_unit_test(test_helper_errors),
    };
    return cmocka_run_group_tests_name("atomic", tests, NULL, NULL);
}
