/*
 * cli_test.c - the qibl CLI run as a program (posix_spawn) on bad inputs: exit status (2 for bad
 * arguments, 1 for bad files), the one-line message naming the value, and no output file left
 * behind. Covers issue 10's CLI findings: merge on crafted, damaged, overflowing and mismatched
 * shards, absurd numbers for render/relight, gen --size with junk, lights --zoom past the picture
 * limit, demo's output directory and long paths.
 *
 * The binary is found as cliutil.h says; the tests skip when it is missing.
 */
#include "bake/extras.h"
#include "cliutil.h"
#include "io/pfm.h"

#include "bake/bake.h"
#include "qibl/asset.h"
#include "qibl/isa.h"

CLI_FIXTURES("/tmp/qibl_cli_test_XXXXXX")

static char *stderr_text(void)
{
    return text(errlog);
}

/* Runs qibl, then checks the exit status, that stderr says want, and that out (may be NULL) was
 * not created. */
static void expect(int want_rc, const char *want, const char *out, const char *first, ...)
{
    va_list ap;
    va_start(ap, first);
    int rc = run_v(first, ap);
    va_end(ap);
    char *msg = stderr_text();
    if (rc != want_rc)
        fail_msg("qibl %s ...: exit %d, want %d; stderr: %s", first, rc, want_rc, msg);
    if (want && strstr(msg, want) == NULL)
        fail_msg("qibl %s ...: stderr '%s' does not say '%s'", first, msg, want);
    if (out && access(out, F_OK) == 0)
        fail_msg("qibl %s ...: left %s behind", first, out);
    free(msg);
}

/* dir/name; the result stays valid for the next 63 calls (more than any one test makes) */

/* bakes shard I/N of a tiny bake with ndirs directions and k into name */
static void shard(const char *name, const char *in, const char *dirs, const char *k)
{
    int rc = run("bake", "--size", "16x4", "--k", k, "--dirs", dirs, "--shard", in, "--sums", at(name), "--quiet",
                 "--threads", "1", NULL);
    if (rc != 0) {
        char *m = stderr_text();
        fail_msg("bake --shard %s: exit %d: %s", in, rc, m);
    }
}

/* ---- merge (findings 1 and 3, and --k) ---------------------------------------------------------- */

static void test_merge_shards_of_other_splits(void **state)
{
    (void)state;
    need_qibl();
    shard("a0", "0/2", "48", "4");
    shard("a1", "1/2", "48", "4");
    shard("b2", "2/3", "48", "4");
    shard("b0", "0/3", "48", "4");
    shard("c7", "7/9", "144", "4");
    const char *out = at("m.qibl");
    /* a plausible 2/3 after 0/2: once a heap over-read of the shard table */
    expect(1, "shard 2/3 against a split into 2", out, "merge", "-o", out, at("a0"), at("b2"), NULL);
    /* an index far past the first file's table: once a wild read */
    expect(1, "shard 7/9 against a split into 2", out, "merge", "-o", out, at("a0"), at("c7"), NULL);
    /* an in-range index of another split: once "shard given twice" */
    expect(1, "shard 0/3 against a split into 2", out, "merge", "-o", out, at("a0"), at("b0"), NULL);
    expect(1, "shard 0/2 given twice", out, "merge", "-o", out, at("a0"), at("a0"), NULL);
    expect(1, "shard 1/2 is missing", out, "merge", "-o", out, at("a0"), NULL);
    /* and the good merge still works */
    expect(0, NULL, NULL, "merge", "-o", out, at("a0"), at("a1"), NULL);
    expect(0, NULL, NULL, "check", out, NULL);
}

static void test_merge_k_above_shards(void **state)
{
    (void)state;
    need_qibl();
    shard("a0", "0/2", "32", "4");
    shard("a1", "1/2", "32", "4");
    const char *out = at("m.qibl");
    expect(2, "--k 9 is above the shards' k = 4", out, "merge", "--k", "9", "-o", out, at("a0"), at("a1"), NULL);
}

static void flip_byte(const char *path, long off)
{
    FILE *f = fopen(path, "r+b");
    assert_non_null(f);
    assert_int_equal(fseek(f, off, off < 0 ? SEEK_END : SEEK_SET), 0);
    int c = fgetc(f);
    assert_int_equal(fseek(f, -1, SEEK_CUR), 0);
    fputc(c ^ 0x04, f);
    assert_int_equal(fclose(f), 0);
}

static void test_merge_damaged_shard(void **state)
{
    (void)state;
    need_qibl();
    shard("a0", "0/2", "32", "4");
    shard("a1", "1/2", "32", "4");
    const char *out = at("m.qibl");
    flip_byte(at("a1"), -100); /* one bit of one sum */
    expect(1, "checksum mismatch in the sums", out, "merge", "-o", out, at("a0"), at("a1"), NULL);
    flip_byte(at("a0"), 20); /* the header's k */
    expect(1, "header checksum mismatch", out, "merge", "-o", out, at("a0"), at("a1"), NULL);
}

static void test_merge_overflow(void **state)
{
    (void)state;
    need_qibl();
    /* two CRC-valid shards whose sums overflow 64 bits when added: once a wrapped, valid asset */
    enum { W = 4, H = 2, K = 1 };
    int32_t pmap[W * H * 3];
    int64_t acc[2][W * H * 3 * K];
    for (int i = 0; i < W * H * 3; ++i)
        pmap[i] = (i % 3 == 2 ? -65536 : 4096 * i);
    for (int i = 0; i < W * H * 3 * K; ++i)
        acc[0][i] = INT64_MAX - 10, acc[1][i] = 1000;
    for (int s = 0; s < 2; ++s) {
        qtool_bake_sums sums = {W, H, K, 32, 0, (uint32_t)s, 2, pmap, acc[s]};
        char err[256];
        assert_int_equal(qtool_bake_sums_write(&sums, at(s ? "o1" : "o0"), err, sizeof err), 0);
    }
    const char *out = at("m.qibl");
    expect(1, "sums overflow 64 bits at pixel (0, 0)", out, "merge", "-o", out, at("o0"), at("o1"), NULL);
    expect(1, "overflow", at("t.sums"), "merge", "--sums", at("t.sums"), at("o0"), at("o1"), NULL);
}

static void test_merge_huge_direction_count(void **state)
{
    (void)state;
    need_qibl();
    /* a 4-pixel shard claiming 2^31 directions: once `merge --lsq` ran for hours */
    shard("a0", "0/1", "16", "1");
    uint8_t *b;
    size_t n;
    b = qtool_io_read_all(at("a0"), &n);
    assert_non_null(b);
    b[24] = 0, b[25] = 0, b[26] = 0, b[27] = 0x80;
    uint32_t c = qibl_crc32(0, b, 44);
    b[44] = (uint8_t)c, b[45] = (uint8_t)(c >> 8), b[46] = (uint8_t)(c >> 16), b[47] = (uint8_t)(c >> 24);
    FILE *f = fopen(at("a0"), "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(b, 1, n, f), n);
    fclose(f);
    free(b);
    const char *out = at("m.qibl");
    expect(1, "direction count 2147483648 outside 1..65536", out, "merge", "--lsq", "-o", out, at("a0"), NULL);
}

/* ---- numbers (findings 6 and 8) ----------------------------------------------------------------- */

static void test_render_absurd_numbers(void **state)
{
    (void)state;
    need_qibl();
    const char *png = at("r.png"), *pfm = at("r.pfm");
    expect(2, "--sun: 1e308 is outside", png, "render", "--size", "16x4", "--sun", "1e308", "1e308", "1e308", "--png",
           png, NULL);
    expect(2, "--rgb: 1e308 is outside 0..32767.99998", pfm, "render", "--size", "16x4", "--sun", "0", "0", "1",
           "--rgb", "1e308", "1", "1", "--pfm", pfm, NULL);
    expect(2, "'inf' is not a finite number", png, "render", "--size", "16x4", "--point", "inf", "0", "0", "--png",
           png, NULL);
    expect(2, "--sun needs a non-zero direction", png, "render", "--size", "16x4", "--sun", "1e-300", "0", "0",
           "--png", png, NULL);
    expect(0, NULL, NULL, "render", "--size", "16x4", "--sun", "0", "0", "1", "--rgb", "2", "2", "2", "--pfm", pfm,
           NULL);
}

static void test_relight_numbers(void **state)
{
    (void)state;
    need_qibl();
    const char *asset = at("g.qibl"), *png = at("r.png");
    expect(0, NULL, NULL, "gen", "-o", asset, "--size", "16x4", "--k", "4", NULL);
    expect(2, "--rgb: 40000 is outside 0..32767.99998", png, "relight", asset, "--sun", "0", "0", "1", "--rgb",
           "40000", "1", "1", "--png", png, NULL);
    expect(2, "--sun needs a non-zero direction", png, "relight", asset, "--sun", "0", "0", "0", "--png", png, NULL);
    expect(2, "--sun: 'nan' is not a finite number", png, "relight", asset, "--sun", "nan", "0", "1", "--png", png,
           NULL);
    expect(2, "--exposure: -1 is outside", png, "relight", asset, "--sun", "0", "0", "1", "--exposure", "-1", "--png",
           png, NULL);
}

static void test_gen_size_junk(void **state)
{
    (void)state;
    need_qibl();
    const char *out = at("g.qibl");
    expect(2, "got '8x4junk'", out, "gen", "-o", out, "--size", "8x4junk", NULL);
    expect(2, "got '8x'", out, "gen", "-o", out, "--size", "8x", NULL);
    expect(2, "got '-8x4'", out, "gen", "-o", out, "--size", "-8x4", NULL);
    expect(2, "got '99999999999999999999x4'", out, "gen", "-o", out, "--size", "99999999999999999999x4", NULL);
    expect(2, "above the asset's 67108864 pixels", out, "render", "--sun", "0", "0", "1", "--size", "16384x8192",
           "--png", out, NULL);
}

static void test_lights_zoom_capped(void **state)
{
    (void)state;
    need_qibl();
    /* a flat 256 x 128 Radiance probe; --zoom 64 would make a 16384 x 8192 picture (384 MiB) */
    const char *hdr = at("p.hdr"), *png = at("z.png");
    FILE *f = fopen(hdr, "wb");
    assert_non_null(f);
    fprintf(f, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 128 +X 256\n");
    for (int i = 0; i < 256 * 128; ++i)
        fputc(128, f), fputc(100, f), fputc(60, f), fputc(129, f);
    assert_int_equal(fclose(f), 0);
    expect(2, "makes a 16384x8192 picture; the limit is 65535 per side and 33554432 pixels (try --zoom 32)", png,
           "lights", hdr, "-n", "4", "--zoom", "64", "--png", png, NULL);
    expect(0, NULL, NULL, "lights", hdr, "-n", "4", "--zoom", "2", "--png", png, NULL);
}

/* ---- demo (finding 7) and safe output ---------------------------------------------------------- */

static void test_demo_checks_output_before_bake(void **state)
{
    (void)state;
    need_qibl();
    const char *file = at("plain_file");
    FILE *f = fopen(file, "wb");
    assert_non_null(f);
    fclose(f);
    expect(1, "not a directory", NULL, "demo", "--out", file, "--size", "16x4", "--dirs", "16", "--frames", "2",
           NULL);
    const char *d = at("o");
    assert_int_equal(mkdir(d, 0777), 0);
    char fifo[600];
    snprintf(fifo, sizeof fifo, "%s/sun_01.png", d);
    assert_int_equal(mkfifo(fifo, 0666), 0);
    char asset[600];
    snprintf(asset, sizeof asset, "%s/scene_k9.qibl", d);
    expect(1, "sun_01.png: refusing to replace a FIFO", asset, "demo", "--out", d, "--size", "16x4", "--dirs", "16",
           "--frames", "2", NULL);
}

static void test_demo_long_out(void **state)
{
    (void)state;
    need_qibl();
    /* a --out longer than the 1024 bytes the demo once built its paths in */
    char path[2048];
    snprintf(path, sizeof path, "%s", dir);
    for (int i = 0; i < 6; ++i) {
        size_t l = strlen(path);
        path[l] = '/';
        memset(path + l + 1, 'a' + i, 200);
        path[l + 201] = '\0';
        assert_int_equal(mkdir(path, 0777), 0);
    }
    expect(0, NULL, NULL, "demo", "--out", path, "--size", "16x4", "--dirs", "16", "--frames", "2", "--threads", "1",
           NULL);
    static const char *names[] = {"scene_k9.qibl", "scene_k16.qibl", "scene_k25.qibl", "sun_01.png", "lamp_01.png",
                                  "sun_sweep.png", "lamp_sweep.png", "contact_sheet.png", "truth_sun.png"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; ++i) {
        char p[2200];
        snprintf(p, sizeof p, "%s/%s", path, names[i]);
        if (access(p, F_OK) != 0)
            fail_msg("demo with a %zu-byte --out did not write %s", strlen(path), names[i]);
    }
}

static void test_output_to_symlink_refused(void **state)
{
    (void)state;
    need_qibl();
    const char *victim = at("victim"), *link = at("link.qibl");
    FILE *f = fopen(victim, "wb");
    assert_non_null(f);
    fputs("precious", f);
    fclose(f);
    assert_int_equal(symlink(victim, link), 0);
    expect(1, "refusing to replace a symbolic link", NULL, "gen", "-o", link, "--size", "16x4", NULL);
    size_t n;
    uint8_t *b = qtool_io_read_all(victim, &n);
    assert_non_null(b);
    assert_int_equal(n, 8);
    assert_memory_equal(b, "precious", 8);
    free(b);
}

/* ---- shard merges carry SHMU, LPTH and LOCC (issue 15) ----------------------------------------------- */

#define PATH_ARGS "--size", "24x6", "--k", "4", "--dirs", "64", "--unshadowed-k", "4", "--sun-path", "40,15,7,17", \
                  "--lamp-track", "1,1,-0.5;-1,1,-0.5", "--lamp-box", "-2,-2,-1,2,2,0", "--lamp-samples", "8", \
                  "--path-steps", "8", "--quiet", "--threads", "1"

static void file_eq(const char *a, const char *b)
{
    size_t na, nb;
    uint8_t *x = qtool_io_read_all(a, &na), *y = qtool_io_read_all(b, &nb);
    assert_non_null(x), assert_non_null(y);
    assert_int_equal(na, nb);
    assert_memory_equal(x, y, na);
    free(x), free(y);
}

static void test_merge_paths_bit_identical(void **state)
{
    (void)state;
    need_qibl();
    assert_int_equal(run("bake", PATH_ARGS, "-o", at("whole.qibl"), NULL), 0);
    assert_int_equal(run("bake", PATH_ARGS, "--shard", "0/2", "--sums", at("p0"), NULL), 0);
    assert_int_equal(run("bake", PATH_ARGS, "--shard", "1/2", "--sums", at("p1"), NULL), 0);
    assert_int_equal(access(at("p0.u"), F_OK), 0);
    assert_int_equal(access(at("p0.x"), F_OK), 0);
    assert_int_equal(access(at("p1.x"), F_OK), 0); /* every shard bakes its rows of the per-pixel chunks */
    /* any input order: the asset of one bake, byte for byte (SHMU, two LPTH, LOCC) */
    assert_int_equal(run("merge", "-o", at("merged.qibl"), "--k", "4", at("p1"), at("p0"), NULL), 0);
    file_eq(at("whole.qibl"), at("merged.qibl"));
    char *o = text(outlog);
    assert_non_null(strstr(o, "2 light paths, lamp occlusion"));
    free(o);
    /* a damaged extras file, then a missing .u: named, nothing written */
    size_t n;
    uint8_t *b = qtool_io_read_all(at("p0.x"), &n);
    assert_non_null(b);
    b[n - 1] ^= 1;
    FILE *f = fopen(at("p0.x"), "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(b, 1, n, f), n);
    fclose(f);
    expect(1, "CRC-32 mismatch", at("m2.qibl"), "merge", "-o", at("m2.qibl"), "--k", "4", at("p0"), at("p1"), NULL);
    b[n - 1] ^= 1;
    f = fopen(at("p0.x"), "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(b, 1, n - 3, f), n - 3);
    fclose(f);
    free(b);
    expect(1, "only", at("m2.qibl"), "merge", "-o", at("m2.qibl"), "--k", "4", at("p0"), at("p1"), NULL);
    assert_int_equal(unlink(at("p1.u")), 0);
    expect(1, "p1.u is missing", at("m2.qibl"), "merge", "-o", at("m2.qibl"), "--k", "4", at("p0"), at("p1"), NULL);
    /* a shard baked again without paths replaces its stale extras with an empty set (which the merge
     * then holds against the other shards' paths) */
    assert_int_equal(run("bake", "--size", "24x6", "--k", "4", "--dirs", "64", "--quiet", "--threads", "1", "--shard",
                         "0/2", "--sums", at("p0"), NULL), 0);
    qtool_extras ex;
    char xerr[1200];
    assert_int_equal(qtool_extras_read(at("p0.x"), &ex, xerr, sizeof xerr), 0);
    assert_int_equal(ex.count, 0);
    qtool_extras_free(&ex);
    expect(2, "is not X0,Y0,Z0,X1,Y1,Z1 with X0 <= X1", at("bad.qibl"), "bake", "--lamp-box", "1,1,1,0,0,0", "-o", at("bad.qibl"), NULL);
    expect(2, "is not X0,Y0,Z0,X1,Y1,Z1 with X0 <= X1", at("bad.qibl"), "bake", "--lamp-box", "1,2,3", "-o", at("bad.qibl"), NULL);
    expect(2, "need the unshadowed maps", at("bad.qibl"), "bake", "--lamp-box", "0,0,0,1,1,1", "--unshadowed-k", "0",
           "-o", at("bad.qibl"), NULL);
}

/* ---- relight --path (issue 15) --------------------------------------------------------------------- */

static void test_relight_path(void **state)
{
    (void)state;
    need_qibl();
    assert_int_equal(run("bake", PATH_ARGS, "-o", at("p.qibl"), NULL), 0);
    /* the sun alone, then over the sky: the sky only adds light, and somewhere it adds some */
    assert_int_equal(run("relight", at("p.qibl"), "--path", "sun", "--t", "0.5", "--pfm", at("s.pfm"), NULL), 0);
    assert_int_equal(run("relight", at("p.qibl"), "--path", "0", "--t", "0.5", "--sky", "0.25", "0.32", "0.45", "--pfm",
                         at("ss.pfm"), "--png", at("ss.png"), NULL), 0);
    int w, h, ch, w2, h2, ch2;
    float *a, *b;
    char err[512];
    assert_int_equal(qtool_pfm_read(at("s.pfm"), &w, &h, &ch, &a, err, sizeof err), 0);
    assert_int_equal(qtool_pfm_read(at("ss.pfm"), &w2, &h2, &ch2, &b, err, sizeof err), 0);
    assert_int_equal(w, 24), assert_int_equal(h, 6), assert_int_equal(w2, w), assert_int_equal(ch2, ch);
    int more = 0;
    for (int i = 0; i < w * h * ch; ++i) {
        assert_true(b[i] >= a[i] - 1e-4f);
        more += b[i] > a[i] + 1e-3f;
    }
    assert_true(more > 0);
    free(a), free(b);
    /* the lamp track, soft; moving t changes the frame */
    assert_int_equal(run("relight", at("p.qibl"), "--path", "lamp", "--t", "0.1", "--soft", "0.02", "--pfm", at("l1.pfm"),
                         NULL), 0);
    assert_int_equal(run("relight", at("p.qibl"), "--path", "lamp", "--t", "0.9", "--pfm", at("l2.pfm"), NULL), 0);
    assert_int_equal(qtool_pfm_read(at("l1.pfm"), &w, &h, &ch, &a, err, sizeof err), 0);
    assert_int_equal(qtool_pfm_read(at("l2.pfm"), &w, &h, &ch, &b, err, sizeof err), 0);
    assert_true(memcmp(a, b, sizeof(float) * (size_t)(w * h * ch)) != 0);
    free(a), free(b);
    /* named errors, nothing written */
    expect(1, "--path 2, but the asset has 2 light paths", at("x.png"), "relight", at("p.qibl"), "--path", "2", "--t",
           "0.5", "--png", at("x.png"), NULL);
    expect(2, "--path needs an index, sun or lamp", at("x.png"), "relight", at("p.qibl"), "--path", "moon", "--t", "0.5",
           "--png", at("x.png"), NULL);
    expect(2, "outside 0..1", at("x.png"), "relight", at("p.qibl"), "--path", "0", "--t", "1.01", "--png", at("x.png"),
           NULL);
    expect(2, "needs FILE, --path", at("x.png"), "relight", at("p.qibl"), "--path", "0", "--png", at("x.png"), NULL);
    assert_int_equal(run("bake", "--size", "16x4", "--k", "4", "--dirs", "64", "--quiet", "--threads", "1", "-o",
                         at("plain.qibl"), NULL), 0);
    expect(1, "no light paths", at("x.png"), "relight", at("plain.qibl"), "--path", "sun", "--t", "0.5", "--png",
           at("x.png"), NULL);
}

/* ---- the demo's path table on a mesh (issue 15: make demo SCENE=...) -------------------------------- */

static void test_demo_paths_on_mesh(void **state)
{
    (void)state;
    need_qibl();
    const char *mesh = "../shared/fixtures/meshes/teapot.obj";
    if (access(mesh, R_OK) != 0) {
        print_message("skip: %s absent\n", mesh);
        skip();
    }
    assert_int_equal(run("demo", "--out", at("demo"), "--scene", mesh, "--size", "96x24", "--dirs", "64", "--frames", "2",
                         "--threads", "1", NULL), 0);
    char *o = text(outlog);
    assert_non_null(strstr(o, "light paths (mesh)"));
    static const char *want[] = {"path_sun_psnr", "track_lamp_psnr", "free_lamp_psnr", "free_lamp_brightness",
                                 "sky_sun_psnr", "adaptive_sun_psnr"};
    for (size_t i = 0; i < sizeof want / sizeof want[0]; ++i) {
        char key[64];
        snprintf(key, sizeof key, "RESULT demo.%s ", want[i]);
        const char *at_ = strstr(o, key);
        if (!at_)
            fail_msg("demo on %s: no '%s'", mesh, key);
        double v = atof(at_ + strlen(key));
        assert_true(v > 0 && v < 100);
    }
    free(o);
}

/* QIBL_ISA: each kernel set this CPU runs is named by --version when forced; a name that is no
 * set, or a set the CPU lacks, is refused by name with status 2 before any command runs */
static void test_isa_env(void **state)
{
    (void)state;
    need_qibl();
    static const char *const names[] = {"scalar", "sse2", "avx2", "neon", "avx512"};
    /* what the binary can run (--isa-list), not this test's own library: the -portable flavour of
     * this suite links a core without dispatch, the qibl it runs has it */
    unsetenv("QIBL_ISA");
    assert_int_equal(run("--isa-list", NULL), 0);
    char *list = text(outlog);
    uint32_t have = 0;
    for (char *line = strtok(list, "\n"); line; line = strtok(NULL, "\n"))
        for (unsigned i = 0; i < QIBL_ISA_COUNT; ++i)
            if (strcmp(line, names[i]) == 0)
                have |= QIBL_ISA_BIT(i);
    free(list);
    assert_true(have & QIBL_ISA_BIT(0)); /* scalar is always there */
    const char *missing = NULL;
    for (unsigned i = 0; i < QIBL_ISA_COUNT; ++i) {
        if (!(have & QIBL_ISA_BIT(i))) {
            missing = missing ? missing : names[i];
            continue;
        }
        assert_int_equal(setenv("QIBL_ISA", names[i], 1), 0);
        assert_int_equal(run("--version", NULL), 0);
        char *o = text(outlog), want[64];
        snprintf(want, sizeof want, "kernels: %s (", names[i]);
        assert_non_null(strstr(o, want));
        free(o);
    }
    assert_int_equal(setenv("QIBL_ISA", "avx1024", 1), 0);
    assert_int_equal(run("--version", NULL), 2);
    char *e = text(errlog);
    assert_non_null(strstr(e, "QIBL_ISA: unknown value 'avx1024' (scalar, sse2, avx2, avx512, neon, auto)"));
    free(e);
    assert_int_equal(run("info", "/nonexistent", NULL), 2); /* refused before the command */
    if (missing) {
        assert_int_equal(setenv("QIBL_ISA", missing, 1), 0);
        assert_int_equal(run("--version", NULL), 2);
        char *e2 = text(errlog), want[64];
        snprintf(want, sizeof want, "QIBL_ISA: %s: not available here", missing);
        assert_non_null(strstr(e2, want));
        free(e2);
    }
    unsetenv("QIBL_ISA");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_merge_shards_of_other_splits, setup, teardown),
        cmocka_unit_test_setup_teardown(test_merge_k_above_shards, setup, teardown),
        cmocka_unit_test_setup_teardown(test_merge_damaged_shard, setup, teardown),
        cmocka_unit_test_setup_teardown(test_merge_overflow, setup, teardown),
        cmocka_unit_test_setup_teardown(test_merge_huge_direction_count, setup, teardown),
        cmocka_unit_test_setup_teardown(test_render_absurd_numbers, setup, teardown),
        cmocka_unit_test_setup_teardown(test_relight_numbers, setup, teardown),
        cmocka_unit_test_setup_teardown(test_gen_size_junk, setup, teardown),
        cmocka_unit_test_setup_teardown(test_lights_zoom_capped, setup, teardown),
        cmocka_unit_test_setup_teardown(test_demo_checks_output_before_bake, setup, teardown),
        cmocka_unit_test_setup_teardown(test_demo_long_out, setup, teardown),
        cmocka_unit_test_setup_teardown(test_output_to_symlink_refused, setup, teardown),
        cmocka_unit_test_setup_teardown(test_merge_paths_bit_identical, setup, teardown),
        cmocka_unit_test_setup_teardown(test_relight_path, setup, teardown),
        cmocka_unit_test_setup_teardown(test_demo_paths_on_mesh, setup, teardown),
        cmocka_unit_test_setup_teardown(test_isa_env, setup, teardown),
    };
    return cmocka_run_group_tests_name("cli", tests, NULL, NULL);
}
