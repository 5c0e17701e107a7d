/*
 * cli_use_test.c - the qibl CLI's everyday rough edges (issue 11, "The CLI"), run as a program
 * (posix_spawn) with stdout and stderr captured: a mesh prop is not cut by the panorama seam, --point
 * without --rgb is not black, bake --budget prints one verdict, --lut-size / --lut MODE, srgbe encode
 * prints the code it wrote and names the status, check reads .hdr, a PLY mesh renders, sh eval labels
 * l and m, relight writes linear .hdr and .pfm.
 *
 * The binary is found as cliutil.h says; skipped when missing.
 */
#include "cliutil.h"

#include "io/hdr.h"
#include "io/pfm.h"
#include "io/png.h"

CLI_FIXTURES("/tmp/qibl_cli_use_XXXXXX")

/* dir/name; valid for the next 63 calls */

/* exit status want, and each of the (stream, text) expectations: stream 'o' or 'e' must contain the
 * text, 'O' or 'E' must not */
static void check(int rc, int want, const char *what, int nexp, ...)
{
    char *o = text(outlog), *e = text(errlog);
    if (rc != want)
        fail_msg("%s: exit %d, want %d; stdout: %s; stderr: %s", what, rc, want, o, e);
    va_list ap;
    va_start(ap, nexp);
    for (int i = 0; i < nexp; ++i) {
        int s = va_arg(ap, int);
        const char *t = va_arg(ap, const char *);
        const char *in = s == 'o' || s == 'O' ? o : e;
        int has = strstr(in, t) != NULL, must = s == 'o' || s == 'e';
        if (has != must)
            fail_msg("%s: %s %s '%s'; it was: %s", what, s == 'o' || s == 'O' ? "stdout" : "stderr",
                     must ? "does not say" : "says", t, in);
    }
    va_end(ap);
    free(o), free(e);
}

static void write_text(const char *path, const char *s)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fputs(s, f);
    assert_int_equal(fclose(f), 0);
}

/* a unit cube (Y-up, as a mesh from a modelling tool) as OBJ and as an ascii PLY */
static const char *cube_obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                              "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
static const char *cube_ply = "ply\nformat ascii 1.0\ncomment a unit cube\nelement vertex 8\nproperty float x\n"
                              "property float y\nproperty float z\nproperty uchar red\nelement face 6\n"
                              "property list uchar int vertex_indices\nend_header\n"
                              "0 0 0 1\n1 0 0 1\n1 1 0 1\n0 1 0 1\n0 0 1 1\n1 0 1 1\n1 1 1 1\n0 1 1 1\n"
                              "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";

/* Renders a depth panorama of the mesh prop and checks its pixels above the horizon (where only the
 * prop is: the ground is below the eye) form one run of columns that touches neither edge. */
static void prop_not_split(const char *mesh)
{
    const char *d = at("depth.pfm");
    check(run("render", "--scene", mesh, "--size", "64x16", "--sun", "0", "0", "1", "--depth", d, "--threads", "1",
              NULL),
          0, "render --scene mesh", 0);
    int w, h, ch;
    float *px;
    char err[512];
    assert_int_equal(qtool_pfm_read(d, &w, &h, &ch, &px, err, sizeof err), 0);
    assert_int_equal(w, 64);
    int lo = w, hi = -1, cols = 0;
    for (int x = 0; x < w; ++x) {
        int hit = 0;
        for (int y = 0; y < h / 2; ++y)
            hit |= px[(size_t)y * (size_t)w + (size_t)x] > 0;
        if (hit)
            lo = x < lo ? x : lo, hi = x, ++cols;
    }
    free(px);
    if (cols == 0)
        fail_msg("%s: the prop is not seen above the horizon", mesh);
    if (hi - lo + 1 != cols || lo == 0 || hi == w - 1)
        fail_msg("%s: the prop's columns %d..%d (%d of them) are cut by the seam at the panorama's edge", mesh, lo,
                 hi, cols);
}

static void test_mesh_away_from_seam(void **state)
{
    (void)state;
    need_qibl();
    write_text(at("cube.obj"), cube_obj);
    prop_not_split(at("cube.obj"));
}

static void test_ply_scene(void **state)
{
    (void)state;
    need_qibl();
    write_text(at("cube.ply"), cube_ply);
    prop_not_split(at("cube.ply"));
    /* a PLY without faces is named as such, not "no faces" from the OBJ reader */
    write_text(at("pts.ply"), "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                              "property float z\nend_header\n0 0 0\n");
    check(run("render", "--scene", at("pts.ply"), "--size", "16x4", "--sun", "0", "0", "1", "--png", at("x.png"), NULL),
          1, "render --scene points.ply", 1, 'e', "no face element");
    /* neither OBJ nor PLY: the message names the formats meshes may be */
    write_text(at("m.stl"), "solid cube\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nendloop\nendfacet\n");
    check(run("render", "--scene", at("m.stl"), "--size", "16x4", "--sun", "0", "0", "1", "--png", at("x.png"), NULL), 1,
          "render --scene m.stl", 1, 'e', "meshes are Wavefront OBJ or PLY");
}

/* mean of the 8-bit RGB samples of a PNG */
static double png_mean(const char *path)
{
    int w, h, fr;
    uint8_t *rgb;
    char err[512];
    if (qtool_png_read_rgb8(path, &w, &h, &fr, &rgb, err, sizeof err) != 0)
        fail_msg("%s", err);
    double s = 0;
    for (size_t i = 0; i < (size_t)w * (size_t)h * 3; ++i)
        s += rgb[i];
    free(rgb);
    return s / ((double)w * h * 3);
}

static void test_point_default_visible(void **state)
{
    (void)state;
    need_qibl();
    const char *g = at("g.qibl"), *p = at("p.png");
    check(run("gen", "-o", g, "--size", "64x16", "--k", "4", NULL), 0, "gen", 0);
    check(run("relight", g, "--point", "0", "0", "0", "--png", p, NULL), 0, "relight --point (no --rgb)", 2, 'e',
          "--point without --rgb: C0 =", 'E', "almost black");
    double m = png_mean(p);
    if (m < 64)
        fail_msg("relight --point without --rgb: mean %.1f of 255, almost black", m);
    check(run("render", "--size", "64x16", "--point", "0", "0", "0", "--png", p, NULL), 0, "render --point", 1, 'e',
          "--point without --rgb: C0 =");
    m = png_mean(p);
    if (m < 64)
        fail_msg("render --point without --rgb: mean %.1f of 255, almost black", m);
    /* an explicit dim lamp is kept, with a note */
    check(run("relight", g, "--point", "0", "0", "0", "--rgb", "0.1", "0.1", "0.1", "--png", p, NULL), 0,
          "relight --rgb 0.1", 2, 'e', "is almost black", 'E', "without --rgb");
}

static void test_budget_one_verdict(void **state)
{
    (void)state;
    need_qibl();
    const char *b = at("b.qibl");
    /* unreachable: no line may claim a k reached it */
    check(run("bake", "--size", "32x8", "--dirs", "32", "--budget", "98", "--quiet", "--threads", "1", "-o", b, NULL),
          0, "bake --budget 98", 3, 'o', "no k <= 25 reaches 98.00 dB", 'o', "none reaches 98.00 dB", 'O',
          "smallest k whose novel-sun PSNR reaches");
    /* trivially reached by k = 1 */
    check(run("bake", "--size", "32x8", "--dirs", "32", "--budget", "0.5", "--quiet", "--threads", "1", "-o", b, NULL),
          0, "bake --budget 0.5", 3, 'o', "chose k = 1: the smallest k whose novel-sun PSNR reaches 0.50 dB", 'O',
          "no k <= 25", 'O', "none reaches");
}

static void test_lut_spellings(void **state)
{
    (void)state;
    need_qibl();
    const char *g = at("g.qibl"), *p = at("p.png");
    check(run("gen", "-o", g, "--size", "32x8", "--k", "4", "--lut-size", "4", NULL), 0, "gen --lut-size", 1, 'E',
          "deprecated");
    check(run("gen", "-o", at("old.qibl"), "--size", "32x8", "--k", "4", "--lut", "4", NULL), 0, "gen --lut 4", 1,
          'e', "say --lut-size 4");
    check(run("gen", "-o", at("bad.qibl"), "--size", "32x8", "--lut-size", "9999", NULL), 2, "gen --lut-size 9999", 1,
          'e', "--lut-size: '9999' is not a face size in 0..");
    assert_int_equal(access(at("bad.qibl"), F_OK), -1);
    check(run("bake", "-o", at("b.qibl"), "--size", "16x4", "--k", "4", "--dirs", "16", "--lut-size", "8", "--quiet",
              NULL),
          0, "bake --lut-size", 1, 'o', "cube-map Y LUT");
    check(run("relight", g, "--point", "0", "0", "0", "--lut", "nearest", "--png", p, NULL), 0, "relight --lut nearest",
          2, 'o', "point/LUT nearest", 'E', "deprecated");
    check(run("relight", g, "--point", "0", "0", "0", "--lut", "bilinear", "--png", p, NULL), 0,
          "relight --lut bilinear", 1, 'o', "point/LUT bilinear");
    check(run("relight", g, "--point", "0", "0", "0", "--lut", "off", "--png", p, NULL), 0, "relight --lut off", 1,
          'o', "point/direct");
    check(run("relight", g, "--point", "0", "0", "0", "--lut", "--png", p, NULL), 0, "relight bare --lut", 2, 'o',
          "point/LUT bilinear", 'e', "bare --lut is deprecated");
    check(run("relight", g, "--point", "0", "0", "0", "--lut", "cubic", "--png", p, NULL), 2, "relight --lut cubic", 1,
          'e', "--lut: 'cubic' is not a mode");
}

static void test_srgbe_encode_prints_code(void **state)
{
    (void)state;
    need_qibl();
    check(run("srgbe", "encode", "nan", "1", "1", NULL), 1, "srgbe encode nan 1 1", 2, 'o', "80808000\n", 'e',
          "QIBL_E_SRGBE_NAN");
    check(run("srgbe", "encode", "inf", "1", "1", NULL), 0, "srgbe encode inf 1 1", 2, 'o', "ff8080ff\n", 'e',
          "QIBL_E_SRGBE_INF");
    check(run("srgbe", "decode", "ffffffff", NULL), 0, "srgbe decode ffffffff", 2, 'o', "3.40282347e+38", 'e',
          "QIBL_E_SRGBE_DECODE_SAT");
    check(run("srgbe", "encode", "1", "0.5", "-0.25", NULL), 0, "srgbe encode 1 0.5 -0.25", 1, 'E', "QIBL_");
}

static void test_check_hdr(void **state)
{
    (void)state;
    need_qibl();
    const char *h = at("p.hdr"), *t = at("t.hdr");
    FILE *f = fopen(h, "wb");
    assert_non_null(f);
    fprintf(f, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 6\n");
    for (int i = 0; i < 24; ++i)
        fputc(128, f), fputc(64, f), fputc(32, f), fputc(129, f);
    assert_int_equal(fclose(f), 0);
    check(run("check", h, NULL), 0, "check p.hdr", 1, 'o', "Radiance HDR 6x4");
    /* truncated: the reader's reason, exit 1 */
    size_t n;
    uint8_t *b = qtool_io_read_all(h, &n);
    assert_non_null(b);
    f = fopen(t, "wb");
    assert_non_null(f);
    fwrite(b, 1, n - 10, f);
    assert_int_equal(fclose(f), 0);
    free(b);
    check(run("check", t, NULL), 1, "check truncated .hdr", 1, 'e', "t.hdr");
}

static void test_sh_eval_labels(void **state)
{
    (void)state;
    need_qibl();
    check(run("sh", "eval", "1", "0", "0", NULL), 0, "sh eval", 4, 'o', "Y[ 0] l=0 m=+0  0.282094792", 'o',
          "Y[ 3] l=1 m=+1 -0.488602512", 'o', "Y[24] l=4 m=+4", 'O', "Y[25]");
    char *o = text(outlog);
    int lines = 0;
    for (const char *s = o; (s = strstr(s, " l=")) != NULL; ++s)
        ++lines;
    free(o);
    assert_int_equal(lines, 25);
}

static void test_relight_linear_outputs(void **state)
{
    (void)state;
    need_qibl();
    const char *g = at("g.qibl"), *hp = at("r.hdr"), *fp = at("r.pfm");
    check(run("gen", "-o", g, "--size", "64x16", "--k", "9", NULL), 0, "gen", 0);
    check(run("relight", g, "--sun", "0.3", "0.2", "1", "--rgb", "2", "2", "2", "--exposure", "4", "--hdr", hp, "--pfm",
              fp, NULL),
          0, "relight --hdr --pfm", 2, 'o', "r.hdr (64x16 Radiance RGBE, linear, before exposure", 'o', "r.pfm");
    int w, h, w2, h2, ch;
    float *a, *b;
    char err[512];
    assert_int_equal(qtool_hdr_read(hp, &w, &h, &a, err, sizeof err), 0);
    assert_int_equal(qtool_pfm_read(fp, &w2, &h2, &ch, &b, err, sizeof err), 0);
    assert_int_equal(w, 64), assert_int_equal(h, 16), assert_int_equal(w2, 64), assert_int_equal(h2, 16);
    assert_int_equal(ch, 3);
    double mx = 0;
    for (size_t i = 0; i < 64 * 16; ++i) {
        double v = b[3 * i] > b[3 * i + 1] ? b[3 * i] : b[3 * i + 1];
        v = b[3 * i + 2] > v ? b[3 * i + 2] : v;
        mx = v > mx ? v : mx;
        for (int c = 0; c < 3; ++c) {
            assert_true(b[3 * i + (size_t)c] >= 0);
            /* RGBE keeps 8 bits below the pixel's largest channel: low by less than max / 128 */
            double d = b[3 * i + (size_t)c] - a[3 * i + (size_t)c];
            if (!(d >= 0 && d <= v / 128 + 1e-30))
                fail_msg("pixel %zu channel %d: pfm %g, hdr %g", i, c, (double)b[3 * i + (size_t)c],
                         (double)a[3 * i + (size_t)c]);
        }
    }
    /* before exposure: a light of 2 on albedo < 1 cannot reach 4 x that in the linear frame */
    assert_true(mx > 0.05 && mx < 4.0);
    free(a), free(b);
    check(run("relight", g, "--sun", "0", "0", "1", NULL), 2, "relight without output", 1, 'e', "--hdr, --pfm or --exr");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_mesh_away_from_seam, setup, teardown),
        cmocka_unit_test_setup_teardown(test_ply_scene, setup, teardown),
        cmocka_unit_test_setup_teardown(test_point_default_visible, setup, teardown),
        cmocka_unit_test_setup_teardown(test_budget_one_verdict, setup, teardown),
        cmocka_unit_test_setup_teardown(test_lut_spellings, setup, teardown),
        cmocka_unit_test_setup_teardown(test_srgbe_encode_prints_code, setup, teardown),
        cmocka_unit_test_setup_teardown(test_check_hdr, setup, teardown),
        cmocka_unit_test_setup_teardown(test_sh_eval_labels, setup, teardown),
        cmocka_unit_test_setup_teardown(test_relight_linear_outputs, setup, teardown),
    };
    return cmocka_run_group_tests_name("cli_use", tests, NULL, NULL);
}
