/*
 * probe_lit_cli_test.c - probe-lit bakes through the CLI (issue 26): bake --probe, relight --probe on
 * the asset it writes (sun + SH through the baked paths) and render --probe (the truth under the
 * whole probe) reach the demo's own sun + SH row for that probe (demo --probe) on a small size;
 * and the refusals by name: a probe with no compact source, a yaw out of range, an asset baked with
 * another probe or yaw.
 *
 * The agreement test uses a fixture probe (../shared/fixtures/probes, skipped when absent); the
 * refusals use probes made here (io/hdr_write.h). The binary is found as cliutil.h says.
 */
#include "cliutil.h"

#include <math.h>

#include "io/hdr_write.h"
#include "io/png.h"

#define PI_ 3.14159265358979323846
#define SUNNY "../shared/fixtures/probes/quarry_01_1k.hdr"
/* the chain's PSNR against the demo's printed row (2 decimals): the same frames, so rounding only */
#define MARGIN_DB 0.05

CLI_FIXTURES("/tmp/qibl_probe_lit_test_XXXXXX")

#define OK(...)                                                                                              \
    do {                                                                                                     \
        int rc_ = run(__VA_ARGS__, NULL);                                                                    \
        if (rc_ != 0) {                                                                                      \
            char *m_ = text(errlog);                                                                         \
            fail_msg("qibl exit %d: %s", rc_, m_);                                                           \
        }                                                                                                    \
    } while (0)

/* exit status want_rc, stderr saying want, and out not created */
#define REFUSED(want_rc, want, out, ...)                                                                     \
    do {                                                                                                     \
        int rc_ = run(__VA_ARGS__, NULL);                                                                    \
        char *m_ = text(errlog);                                                                             \
        if (rc_ != (want_rc) || !strstr(m_, want))                                                           \
            fail_msg("exit %d (want %d), stderr '%s' (want '%s')", rc_, want_rc, m_, want);                  \
        if (access(out, F_OK) == 0)                                                                          \
            fail_msg("%s left behind", out);                                                                 \
        free(m_);                                                                                            \
    } while (0)

/* a 64 x 32 lat-long sky of 0.3 over a ground of 0.1; sun > 0: a 3-pixel sun of that radiance
 * at azimuth az (radians) and 40 degrees up */
static void make_probe(const char *path, double sun, double az)
{
    enum { W = 64, H = 32 };
    float *px = malloc(sizeof *px * 3 * W * H);
    assert_non_null(px);
    double sd[3] = {cos(0.7) * cos(az), cos(0.7) * sin(az), sin(0.7)};
    for (int v = 0; v < H; ++v)
        for (int u = 0; u < W; ++u) {
            double t = (v + 0.5) * PI_ / H, p = (u + 0.5) * 2 * PI_ / W;
            double d[3] = {sin(t) * cos(p), sin(t) * sin(p), cos(t)};
            double c = d[2] > 0 ? 0.3 : 0.1;
            if (sun > 0 && d[0] * sd[0] + d[1] * sd[1] + d[2] * sd[2] > cos(5 * PI_ / 180))
                c = sun;
            for (int q = 0; q < 3; ++q)
                px[3 * (v * W + u) + q] = (float)c;
        }
    char err[512];
    if (qtool_hdr_write(path, W, H, px, err, sizeof err) != 0)
        fail_msg("%s", err);
    free(px);
}

/* PSNR of b against a over the pixels where either is not black (the scene: sky pixels are black
 * in both the relit frame and the truth) */
static double psnr_scene(const char *a, const char *b)
{
    int w = 0, h = 0, wb = 0, hb = 0, fr = 0;
    uint8_t *pa = NULL, *pb = NULL;
    char err[512];
    if (qtool_png_read_rgb8(a, &w, &h, &fr, &pa, err, sizeof err) != 0 ||
        qtool_png_read_rgb8(b, &wb, &hb, &fr, &pb, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(w, wb);
    assert_int_equal(h, hb);
    double se = 0, n = 0;
    for (size_t i = 0; i < (size_t)w * (size_t)h; ++i) {
        const uint8_t *x = pa + 3 * i, *y = pb + 3 * i;
        if (!(x[0] | x[1] | x[2] | y[0] | y[1] | y[2]))
            continue;
        for (int c = 0; c < 3; ++c)
            se += (double)(x[c] - y[c]) * (x[c] - y[c]);
        n += 3;
    }
    free(pa), free(pb);
    assert_true(n > 0);
    return se > 0 ? 10 * log10(255.0 * 255.0 * n / se) : 99;
}

/* the value of "RESULT name V" in the captured stdout */
static double result(const char *name)
{
    char *t = text(outlog), key[128];
    snprintf(key, sizeof key, "RESULT %s ", name);
    char *p = strstr(t, key);
    if (!p)
        fail_msg("no %s in the demo's output", key);
    double v = strtod(p + strlen(key), NULL);
    free(t);
    return v;
}

static void test_chain_reaches_demo_row(void **state)
{
    (void)state;
    need_qibl();
    if (access(SUNNY, R_OK) != 0) {
        fprintf(stderr, "SKIP: %s absent\n", SUNNY);
        skip();
    }
    /* the demo's rows at 128x32, 64 directions, 64 samples per pixel in each truth render */
    setenv("QIBL_DEMO_PROBE_SPP", "64", 1);
    OK("demo", "--probe", SUNNY, "--small", "--size", "128x32", "--dirs", "64", "--out", at("demo"));
    unsetenv("QIBL_DEMO_PROBE_SPP");
    double demo_sunsh = result("demo.probe_user_sunsh_psnr"), demo_sh = result("demo.probe_user_sh25_psnr");
    /* the same through bake --probe + relight --probe against render --probe */
    OK("bake", "--probe", SUNNY, "--size", "128x32", "--dirs", "64", "--quiet", "-o", at("p.qibl"));
    OK("relight", at("p.qibl"), "--probe", SUNNY, "--png", at("relit.png"));
    char *o = text(outlog);
    if (!strstr(o, "sun + SH of"))
        fail_msg("relight --probe on a probe-lit asset did not use its paths: %s", o);
    free(o);
    OK("render", "--probe", SUNNY, "--size", "128x32", "--spp", "64", "--png", at("truth.png"));
    double cli = psnr_scene(at("truth.png"), at("relit.png"));
    print_message("sun + SH: CLI %.3f dB, demo row %.2f dB (SH k25 alone %.2f dB)\n", cli, demo_sunsh, demo_sh);
    if (fabs(cli - demo_sunsh) > MARGIN_DB)
        fail_msg("bake + relight --probe: %.3f dB against render --probe, the demo's row says %.2f", cli, demo_sunsh);
    /* what the paths buy over the probe's SH alone (a sunny probe: its hard shadows) */
    assert_true(cli > demo_sh + 5);
}

static void test_refusals(void **state)
{
    (void)state;
    need_qibl();
    make_probe(at("overcast.hdr"), 0, 0);
    make_probe(at("sun_a.hdr"), 3000, 1.0);
    make_probe(at("sun_b.hdr"), 3000, 2.5);
    REFUSED(1, "no compact bright source", at("o.qibl"), "bake", "--probe", at("overcast.hdr"), "--size", "32x8",
            "--dirs", "16", "--quiet", "-o", at("o.qibl"));
    REFUSED(2, "--yaw", at("o.qibl"), "bake", "--probe", at("sun_a.hdr"), "--yaw", "400", "--size", "32x8", "--dirs",
            "16", "--quiet", "-o", at("o.qibl"));
    REFUSED(2, "--yaw turns a --probe", at("o.qibl"), "bake", "--yaw", "10", "--size", "32x8", "--dirs", "16",
            "--quiet", "-o", at("o.qibl"));
    REFUSED(2, "--probe bakes its own", at("o.qibl"), "bake", "--probe", at("sun_a.hdr"), "--sun-path", "40,0,8,16",
            "--size", "32x8", "--dirs", "16", "--quiet", "-o", at("o.qibl"));
    OK("bake", "--probe", at("sun_a.hdr"), "--yaw", "30", "--size", "32x8", "--dirs", "16", "--quiet", "-o",
       at("a.qibl"));
    OK("relight", at("a.qibl"), "--probe", at("sun_a.hdr"), "--yaw", "30", "--png", at("ok.png"));
    REFUSED(1, "is another probe", at("x.png"), "relight", at("a.qibl"), "--probe", at("sun_b.hdr"), "--yaw", "30",
            "--png", at("x.png"));
    REFUSED(1, "give the same --yaw", at("x.png"), "relight", at("a.qibl"), "--probe", at("sun_a.hdr"), "--png",
            at("x.png"));
    REFUSED(1, "outside -360..360", at("x.png"), "relight", at("a.qibl"), "--probe", at("sun_a.hdr"), "--yaw", "400",
            "--png", at("x.png"));
    REFUSED(1, "is probe-lit", at("x.pfm"), "relight", at("a.qibl"), "--probe", at("sun_a.hdr"), "--yaw", "30",
            "--pfm", at("x.pfm"));
    REFUSED(2, "--probe is the whole light", at("x.png"), "render", "--probe", at("sun_a.hdr"), "--sun", "0", "0",
            "1", "--size", "32x8", "--png", at("x.png"));
    REFUSED(2, "shape a --probe truth", at("x.png"), "render", "--sun", "0", "0", "1", "--spp", "16", "--size",
            "32x8", "--png", at("x.png"));
}

/* render --probe --yaw 90 is the truth under the probe turned a quarter: the same frame as the
 * probe turned by hand (columns slid a quarter of the width) */
static void test_render_yaw_turns_probe(void **state)
{
    (void)state;
    need_qibl();
    make_probe(at("s0.hdr"), 3000, 1.0);
    make_probe(at("s90.hdr"), 3000, 1.0 + PI_ / 2);
    OK("render", "--probe", at("s0.hdr"), "--yaw", "90", "--size", "64x16", "--spp", "16", "--png", at("a.png"));
    OK("render", "--probe", at("s90.hdr"), "--size", "64x16", "--spp", "16", "--png", at("b.png"));
    OK("render", "--probe", at("s0.hdr"), "--size", "64x16", "--spp", "16", "--png", at("c.png"));
    double same = psnr_scene(at("a.png"), at("b.png")), other = psnr_scene(at("a.png"), at("c.png"));
    print_message("yaw 90 vs turned by hand %.2f dB, vs not turned %.2f dB\n", same, other);
    assert_true(same > other + 3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_chain_reaches_demo_row, setup, teardown),
        cmocka_unit_test_setup_teardown(test_refusals, setup, teardown),
        cmocka_unit_test_setup_teardown(test_render_yaw_turns_probe, setup, teardown),
    };
    return cmocka_run_group_tests_name("probe_lit_cli", tests, NULL, NULL);
}
