/*
 * ies_cli_test.c - `qibl ies info`: the report of a synthetic file (lumens = 4 pi I for an isotropic
 * lamp, the header facts), --png writing a readable picture, a refused file giving exit 1, one
 * line on stderr naming it and nothing on stdout (and no picture), bad arguments exit 2.
 * `qibl relight --ies`: an isotropic profile gives exactly the isotropic lamp's bytes (every point
 * mode, any aim); a profile of 1 below the lamp and 1/2 above scales every pixel by 1, 1/2 or in
 * between; the refusals (no --point, --aim alone, zero aim, bad size, up parallel to the aim, a bad
 * file) with nothing written. `relight --ies --gles` (platform/gles2, skipped without EGL unless
 * QIBL_REQUIRE_GLES=1) within the point lamps' limits of the soft frame, its shape visible. Against the ray tracer's goniometric lamp (qibl render --ies,
 * the profile in double): the per-pixel ratio ies / isotropic agrees with the truth's.
 */
#include "cliutil.h"

#include <math.h>

#include "io/png.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static void put(const char *path, const char *s)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fputs(s, f);
    fclose(f);
}

static void test_info_report_and_png(void **state)
{
    (void)state;
    need_qibl();
    assert_int_equal(cli_setup("/tmp/qibl_iescli_XXXXXX"), 0);
    const char *f = at("iso.ies"), *png = at("iso.png");
    /* an isotropic 100 cd lamp, bilateral, 1995 header with a tilt block */
    put(f, "IESNA:LM-63-1995\n[TEST] iso\n[MANUFAC] qibl\nTILT=INCLUDE\n1\n2\n0 90\n1 1\n"
           "1 1000 2 3 3 1 2 0.1 0.1 0\n1 1 25\n0 90 180\n0 90 180\n50 50 50 50 50 50 50 50 50\n");
    int rc = run("ies", "info", f, "--png", png, NULL);
    char *o = text(outlog), *e = text(errlog);
    if (rc != 0)
        fail_msg("exit %d: %s", rc, e);
    double lm = -1;
    const char *l = strstr(o, "\nlumens ");
    assert_non_null(l);
    assert_int_equal(sscanf(l, "\nlumens %lf", &lm), 1);
    assert_true(fabs(lm - 400 * M_PI) < 0.01);
    assert_non_null(strstr(o, "format LM-63-1995"));
    assert_non_null(strstr(o, "symmetry bilateral"));
    assert_non_null(strstr(o, "candela_max 100"));
    assert_non_null(strstr(o, "tilt INCLUDE (2 angles"));
    assert_non_null(strstr(o, "efficiency 125.7 % of the rated lamp flux"));
    free(o), free(e);
    int w, h, fr;
    uint8_t *rgb = NULL;
    char err[256];
    assert_int_equal(qtool_png_read_rgb8(png, &w, &h, &fr, &rgb, err, sizeof err), 0);
    assert_int_equal(w, 512);
    /* the curve: an isotropic lamp draws its circle at full scale (0.4 x 512 px) straight below the
     * centre (264), the blue plane over the red */
    int found = 0;
    for (int y = 264 + 200; y <= 264 + 210 && !found; ++y) {
        const uint8_t *p = rgb + 3 * ((size_t)y * (size_t)w + 256);
        found = p[0] == 30 && p[1] == 60 && p[2] == 210;
    }
    assert_true(found);
    free(rgb);
    rm_rf(dir);
}

static void test_refusals(void **state)
{
    (void)state;
    need_qibl();
    assert_int_equal(cli_setup("/tmp/qibl_iescli_XXXXXX"), 0);
    const char *f = at("bad.ies"), *png = at("bad.png");
    put(f, "IESNA:LM-63-2002\nTILT=lamp.tlt\n1 1000 1 3 1 1 2 0 0 0\n1 1 10\n0 90 180\n0\n1 2 3\n");
    int rc = run("ies", "info", f, "--png", png, NULL);
    char *o = text(outlog), *e = text(errlog);
    if (rc != 1 || o[0] || !strstr(e, f) || !strstr(e, "TILT=lamp.tlt") || strchr(e, '\n') != strrchr(e, '\n'))
        fail_msg("exit %d, stdout '%s', stderr '%s'", rc, o, e);
    assert_int_equal(access(png, F_OK), -1);
    free(o), free(e);
    assert_int_equal(run("ies", "info", NULL), 2);
    assert_int_equal(run("ies", "info", f, "--bogus", NULL), 2);
    assert_int_equal(run("ies", "info", f, "--png", NULL), 2);
    assert_int_equal(run("ies", "frobnicate", f, NULL), 2);
    rm_rf(dir);
}

/* the PFM the relight writes: w h and the linear floats (rows top first), malloc'ed */
static float *read_pfm(const char *path, int *w, int *h)
{
    size_t n;
    uint8_t *b = qtool_io_read_all(path, &n);
    assert_non_null(b);
    char magic[3];
    double sc;
    int off = 0;
    assert_int_equal(sscanf((const char *)b, "%2s %d %d %lf%n", magic, w, h, &sc, &off), 4);
    off += 1;
    size_t np = (size_t)*w * (size_t)*h * 3;
    assert_true((size_t)off + 4 * np <= n);
    float *f = malloc(4 * np);
    assert_non_null(f);
    memcpy(f, b + off, 4 * np); /* little-endian host (the writer's order), as the suite's machines */
    free(b);
    return f;
}

/* a grey PFM (depth): w h floats */
static float *read_pfm1(const char *path, int *w, int *h)
{
    size_t n;
    uint8_t *b = qtool_io_read_all(path, &n);
    assert_non_null(b);
    char magic[3];
    double sc;
    int off = 0;
    assert_int_equal(sscanf((const char *)b, "%2s %d %d %lf%n", magic, w, h, &sc, &off), 4);
    off += 1;
    size_t np = (size_t)*w * (size_t)*h;
    assert_true((size_t)off + 4 * np <= n);
    float *f = malloc(4 * np);
    assert_non_null(f);
    memcpy(f, b + off, 4 * np);
    free(b);
    /* rows bottom first in the file: flip to match the PNG */
    for (int y = 0; y < *h / 2; ++y)
        for (int x = 0; x < *w; ++x) {
            float t = f[(size_t)y * *w + x];
            f[(size_t)y * *w + x] = f[(size_t)(*h - 1 - y) * *w + x];
            f[(size_t)(*h - 1 - y) * *w + x] = t;
        }
    return f;
}

static void test_relight_ies(void **state)
{
    (void)state;
    need_qibl();
    assert_int_equal(cli_setup("/tmp/qibl_iescli_XXXXXX"), 0);
    const char *asset = at("g.qibl"), *iso = at("iso.ies"), *half = at("half.ies");
    assert_int_equal(run("gen", "-o", asset, "--size", "128x32", "--k", "9", "--lut-size", "8", NULL), 0);
    put(iso, "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 10\n0 90 180\n0\n7 7 7\n");
    /* the lower hemisphere (toward the aim) at full intensity, the upper at half */
    put(half, "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 4 1 1 2 0 0 0\n1 1 10\n0 90 91 180\n0\n10 10 5 5\n");
    /* an isotropic profile: exactly today's isotropic lamp, in every point mode */
    static const char *modes[] = {"poly", "bilinear", "off"};
    const char *a = at("a.png"), *b = at("b.png");
    for (int k = 0; k < 3; ++k) {
        assert_int_equal(run("relight", asset, "--point", "0.3", "-0.2", "0.4", "--rgb", "2", "1.5", "1", "--lut",
                             modes[k], "--png", a, NULL), 0);
        assert_int_equal(run("relight", asset, "--point", "0.3", "-0.2", "0.4", "--rgb", "2", "1.5", "1", "--lut",
                             modes[k], "--ies", iso, "--aim", "0.3", "1", "-2", "--up", "0", "0", "1", "--png", b, NULL),
                         0);
        size_t na, nb;
        uint8_t *pa = qtool_io_read_all(a, &na), *pb = qtool_io_read_all(b, &nb);
        assert_non_null(pa), assert_non_null(pb);
        assert_int_equal(na, nb);
        assert_memory_equal(pa, pb, na);
        free(pa), free(pb);
    }
    /* the half profile: every pixel's light is the isotropic lamp's times 1 (below the lamp), 1/2
     * (above) or in between (within a table texel of the horizon); both kinds present */
    const char *fa = at("a.pfm"), *fb = at("b.pfm");
    assert_int_equal(run("relight", asset, "--point", "0", "0", "0.5", "--rgb", "2", "2", "2", "--pfm", fa, NULL), 0);
    assert_int_equal(run("relight", asset, "--point", "0", "0", "0.5", "--rgb", "2", "2", "2", "--ies", half,
                         "--ies-size", "128", "--pfm", fb, NULL), 0);
    int w, h, w2, h2;
    float *A = read_pfm(fa, &w, &h), *B = read_pfm(fb, &w2, &h2);
    assert_int_equal(w, w2), assert_int_equal(h, h2);
    int ones = 0, halves = 0, lit = 0;
    for (size_t i = 0; i < (size_t)w * h * 3; ++i) {
        if (A[i] < 0.02f)
            continue;
        ++lit;
        double r = B[i] / A[i];
        if (r < 0.5 - 0.01 || r > 1 + 0.01)
            fail_msg("pixel value %zu: ratio %.4f outside [0.5, 1]", i, r);
        ones += r > 0.99, halves += r < 0.51;
    }
    printf("  half profile: %d lit values, %d at 1, %d at 1/2\n", lit, ones, halves);
    assert_true(ones > lit / 10 && halves > lit / 10);
    free(A), free(B);
    /* refusals: no --point, --aim without --ies, a bad profile (nothing written) */
    const char *x = at("x.png");
    assert_int_equal(run("relight", asset, "--sun", "0", "0", "1", "--ies", iso, "--png", x, NULL), 2);
    assert_int_equal(run("relight", asset, "--point", "0", "0", "1", "--aim", "0", "0", "-1", "--png", x, NULL), 2);
    assert_int_equal(run("relight", asset, "--point", "0", "0", "1", "--ies", iso, "--aim", "0", "0", "0", "--png", x,
                         NULL), 2);
    assert_int_equal(run("relight", asset, "--point", "0", "0", "1", "--ies", iso, "--ies-size", "1", "--png", x,
                         NULL), 2);
    assert_int_equal(run("relight", asset, "--point", "0", "0", "1", "--ies", iso, "--aim", "0", "0", "1", "--up", "0",
                         "0", "-3", "--png", x, NULL), 1);
    char *e = text(errlog);
    assert_non_null(strstr(e, "parallel"));
    free(e);
    const char *bad = at("bad.ies");
    put(bad, "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 10\n0 90 180\n0\n7 7\n");
    assert_int_equal(run("relight", asset, "--point", "0", "0", "1", "--ies", bad, "--png", x, NULL), 1);
    e = text(errlog);
    assert_non_null(strstr(e, bad));
    free(e);
    assert_int_equal(access(x, F_OK), -1);
    rm_rf(dir);
}

/* a smooth asymmetric type C profile (5-degree grid, full 0..360) */
static void write_profile(const char *path)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fputs("IESNA:LM-63-2002\n[TEST] smooth\nTILT=NONE\n1 -1 1 37 73 1 2 0 0 0\n1 1 10\n", f);
    for (int i = 0; i <= 36; ++i)
        fprintf(f, "%d ", 5 * i);
    fputs("\n", f);
    for (int j = 0; j <= 72; ++j)
        fprintf(f, "%d ", 5 * j);
    fputs("\n", f);
    for (int j = 0; j <= 72; ++j) {
        for (int i = 0; i <= 36; ++i) {
            double v = 5 * i * M_PI / 180, hh = 5 * j * M_PI / 180;
            fprintf(f, "%.4f ", 100 + 80 * cos(v) + 40 * sin(v) * cos(hh) + 20 * sin(v) * sin(2 * hh));
        }
        fputs("\n", f);
    }
    fclose(f);
}

/* The core's goniometric lamp against the ray tracer's (the same profile in double precision,
 * qibl render --ies): per pixel, relit(ies) / relit(isotropic) must match truth(ies) / truth(isotropic),
 * since both scale the same lamp's light by the profile toward the pixel's point; and the relit frame
 * must be as close to its truth as the isotropic lamp's is to its own. */
/* the PNGs' largest and mean difference per channel */
static void png_diff(const char *a, const char *b, int *mx, double *mean)
{
    int w, h, fr, w2, h2;
    uint8_t *pa = NULL, *pb = NULL;
    char err[256];
    assert_int_equal(qtool_png_read_rgb8(a, &w, &h, &fr, &pa, err, sizeof err), 0);
    assert_int_equal(qtool_png_read_rgb8(b, &w2, &h2, &fr, &pb, err, sizeof err), 0);
    assert_int_equal(w, w2), assert_int_equal(h, h2);
    double sum = 0;
    *mx = 0;
    for (size_t i = 0; i < (size_t)w * h * 3; ++i) {
        int d = abs((int)pa[i] - (int)pb[i]);
        *mx = d > *mx ? d : *mx;
        sum += d;
    }
    *mean = sum / ((double)w * h * 3);
    free(pa), free(pb);
}

/* relight --ies --gles: the lamp on platform/gles2 against the soft frame (tests/gles2_test.c's
 * limits for point lamps: max 2, mean 0.5 levels), in the polynomial and LUT modes, and visibly
 * unlike the isotropic lamp */
static void test_relight_ies_gles(void **state)
{
    (void)state;
    need_qibl();
    assert_int_equal(cli_setup("/tmp/qibl_iescli_XXXXXX"), 0);
    const char *asset = at("g.qibl"), *prof = at("p.ies"), *g = at("g.png"), *sp = at("s.png");
    assert_int_equal(run("gen", "-o", asset, "--size", "128x32", "--k", "9", "--lut-size", "8", NULL), 0);
    /* a downlight: bright toward the nadir, falling off to a dim back, brighter in the 90 plane */
    put(prof, "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 7 3 1 2 0 0 0\n1 1 10\n0 30 60 90 120 150 180\n0 90 180\n"
              "100 80 40 15 5 2 1\n100 90 60 30 10 3 1\n100 80 40 15 5 2 1\n");
    const char *r = getenv("QIBL_REQUIRE_GLES");
    if (run("relight", asset, "--gles", "--point", "0.2", "-0.1", "0.6", "--rgb", "3", "3", "3", "--ies", prof, "--aim",
            "0.2", "0.3", "-1", "--png", g, NULL) != 0) {
        char *e = text(errlog);
        if (r != NULL && strcmp(r, "1") == 0)
            fail_msg("QIBL_REQUIRE_GLES=1 and relight --ies --gles failed: %s", e);
        print_message("SKIP relight --ies --gles: %s", e);
        free(e);
        skip();
    }
    static const char *modes[] = {"poly", "bilinear"};
    for (int k = 0; k < 2; ++k) {
        assert_int_equal(run("relight", asset, "--gles", "--point", "0.2", "-0.1", "0.6", "--rgb", "3", "3", "3",
                             "--lut", modes[k], "--ies", prof, "--aim", "0.2", "0.3", "-1", "--png", g, NULL), 0);
        assert_int_equal(run("relight", asset, "--point", "0.2", "-0.1", "0.6", "--rgb", "3", "3", "3", "--lut",
                             modes[k], "--ies", prof, "--aim", "0.2", "0.3", "-1", "--png", sp, NULL), 0);
        int mx;
        double mean;
        png_diff(g, sp, &mx, &mean);
        printf("  relight --ies --gles (%s) against soft: max %d, mean %.4f levels\n", modes[k], mx, mean);
        assert_true(mx <= 2 && mean <= 0.5);
    }
    const char *iso = at("i.png");
    assert_int_equal(run("relight", asset, "--gles", "--point", "0.2", "-0.1", "0.6", "--rgb", "3", "3", "3", "--lut",
                         "bilinear", "--png", iso, NULL), 0);
    int mx;
    double mean;
    png_diff(g, iso, &mx, &mean);
    assert_true(mx > 20 && mean > 2.0); /* the profile really shapes the GPU's lamp */
}

static void test_relight_ies_against_truth(void **state)
{
    (void)state;
    need_qibl();
    assert_int_equal(cli_setup("/tmp/qibl_iescli_XXXXXX"), 0);
    const char *asset = at("bk.qibl"), *prof = at("p.ies");
    write_profile(prof);
    assert_int_equal(run("bake", "--size", "128x32", "--k", "16", "--dirs", "256", "-o", asset, "--quiet", "--threads",
                         "2", NULL), 0);
    const char *ti = at("ti.pfm"), *tg = at("tg.pfm"), *ri = at("ri.pfm"), *rg = at("rg.pfm");
    const char *pos[3] = {"1.2", "0.8", "0.3"};
    assert_int_equal(run("render", "--size", "128x32", "--point", pos[0], pos[1], pos[2], "--rgb", "3", "3", "3",
                         "--pfm", ti, NULL), 0);
    assert_int_equal(run("render", "--size", "128x32", "--point", pos[0], pos[1], pos[2], "--rgb", "3", "3", "3",
                         "--ies", prof, "--aim", "0.2", "0.1", "-1", "--up", "0", "1", "0", "--pfm", tg, NULL), 0);
    assert_int_equal(run("relight", asset, "--point", pos[0], pos[1], pos[2], "--rgb", "3", "3", "3", "--pfm", ri,
                         NULL), 0);
    assert_int_equal(run("relight", asset, "--point", pos[0], pos[1], pos[2], "--rgb", "3", "3", "3", "--ies", prof,
                         "--aim", "0.2", "0.1", "-1", "--up", "0", "1", "0", "--ies-size", "128", "--pfm", rg, NULL), 0);
    int w, h, w2, h2;
    float *TI = read_pfm(ti, &w, &h), *TG = read_pfm(tg, &w2, &h2), *RI, *RG;
    assert_int_equal(w, w2);
    RI = read_pfm(ri, &w2, &h2);
    assert_int_equal(w, w2);
    RG = read_pfm(rg, &w2, &h2);
    assert_int_equal(w, w2);
    size_t n = (size_t)w * h * 3, used = 0, bad = 0;
    double worst = 0, se_g = 0, se_i = 0;
    for (size_t i = 0; i < n; ++i) {
        se_g += (TG[i] - RG[i]) * (double)(TG[i] - RG[i]);
        se_i += (TI[i] - RI[i]) * (double)(TI[i] - RI[i]);
        if (TI[i] < 0.05f || RI[i] < 0.05f)
            continue;
        double rt = TG[i] / TI[i], rc = RG[i] / RI[i], e = fabs(rt - rc);
        ++used;
        bad += e > 0.01;
        worst = e > worst ? e : worst;
    }
    printf("  ratio relit/truth: %zu values, worst |difference| %.4f, %zu above 0.01; rms error ies %.4g, "
           "isotropic %.4g\n", used, worst, bad, sqrt(se_g / n), sqrt(se_i / n));
    assert_true(used > n / 4);
    assert_true(bad <= used / 100 && worst < 0.05);
    /* the profile (peak 1, 0.3 .. 1 elsewhere) only dims: no worse than the isotropic lamp's error */
    assert_true(sqrt(se_g / n) <= sqrt(se_i / n) * 1.05);
    free(TI), free(TG), free(RI), free(RG);
    rm_rf(dir);
}

/* PSNR (8-bit) of a against b over the pixels where mask (a depth PFM) is above 0 */
static double psnr_hit(const char *a, const char *b, const char *depth)
{
    int w, h, w2, h2, fr, wd, hd;
    uint8_t *A = NULL, *B = NULL;
    char err[256];
    assert_int_equal(qtool_png_read_rgb8(a, &w, &h, &fr, &A, err, sizeof err), 0);
    assert_int_equal(qtool_png_read_rgb8(b, &w2, &h2, &fr, &B, err, sizeof err), 0);
    float *D = read_pfm1(depth, &wd, &hd);
    assert_true(w == w2 && h == h2 && w == wd && h == hd);
    double se = 0;
    size_t n = 0;
    for (size_t i = 0; i < (size_t)w * h; ++i) {
        if (!(D[i] > 0))
            continue;
        for (int c = 0; c < 3; ++c) {
            double d = (double)A[3 * i + c] - B[3 * i + c];
            se += d * d;
        }
        n += 3;
    }
    free(A), free(B), free(D);
    assert_true(n > 0);
    return se > 0 ? 10 * log10(255.0 * 255.0 * n / se) : 99;
}

/* An IES lamp on a baked lamp track (relight --path lamp --ies) against the ray tracer's
 * goniometric lamp at the track's first key: the goal of 30 dB, and no worse than the
 * isotropic lamp on the same track against its own truth. */
static void test_ies_on_track(void **state)
{
    (void)state;
    need_qibl();
    assert_int_equal(cli_setup("/tmp/qibl_iescli_XXXXXX"), 0);
    const char *asset = at("bt.qibl"), *prof = at("p.ies"), *dep = at("d.pfm");
    write_profile(prof);
    assert_int_equal(run("bake", "--size", "192x48", "--k", "16", "--dirs", "384", "-o", asset, "--quiet", "--threads",
                         "2", "--lamp-track", "1.2,0.8,0.3;-1.5,1.0,0.5", "--path-steps", "8", NULL), 0);
    double db[2];
    for (int k = 0; k < 2; ++k) {
        const char *r = at("r.png"), *t = at("t.png");
        if (k) {
            assert_int_equal(run("relight", asset, "--path", "lamp", "--t", "0", "--rgb", "3", "3", "3", "--ies", prof,
                                 "--aim", "0.2", "0.1", "-1", "--up", "0", "1", "0", "--ies-size", "128", "--png", r,
                                 NULL), 0);
            assert_int_equal(run("render", "--size", "192x48", "--point", "1.2", "0.8", "0.3", "--rgb", "3", "3", "3",
                                 "--ies", prof, "--aim", "0.2", "0.1", "-1", "--up", "0", "1", "0", "--png", t,
                                 "--depth", dep, NULL), 0);
        } else {
            assert_int_equal(run("relight", asset, "--path", "lamp", "--t", "0", "--rgb", "3", "3", "3", "--png", r,
                                 NULL), 0);
            assert_int_equal(run("render", "--size", "192x48", "--point", "1.2", "0.8", "0.3", "--rgb", "3", "3", "3",
                                 "--png", t, "--depth", dep, NULL), 0);
        }
        db[k] = psnr_hit(r, t, dep);
    }
    printf("  lamp track at t = 0, hit pixels: isotropic %.2f dB, IES profile %.2f dB against the ray tracer\n", db[0],
           db[1]);
    assert_true(db[1] >= 30 && db[1] >= db[0] - 1);
    /* a sun path cannot take a profile; --aim alone is refused */
    assert_int_equal(run("relight", asset, "--path", "lamp", "--t", "0", "--aim", "0", "0", "-1", "--png", at("x.png"),
                         NULL), 2);
    rm_rf(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_info_report_and_png),
        cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_relight_ies),
        cmocka_unit_test(test_relight_ies_gles),
        cmocka_unit_test(test_relight_ies_against_truth),
        cmocka_unit_test(test_ies_on_track),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
