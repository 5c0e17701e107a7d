/*
 * exr_cli_test.c - OpenEXR through the qibl CLI: `render` and `relight` (and `relight --path`) write
 * --exr frames bit for bit equal to their --pfm frames; a probe given as .exr (recognised by its magic)
 * gives `lights` and `relight --probe` exactly what the same pixels as a Radiance .hdr give; `check`
 * validates an .exr and names a damaged one. Runs build/bin/qibl (cliutil.h).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "cliutil.h"
#include "io/exr.h"
#include "io/hdr_write.h"
#include "io/pfm.h"

CLI_FIXTURES("/tmp/qibl_exr_cli_XXXXXX")

static void ok(int rc, const char *what)
{
    if (rc != 0) {
        char *m = text(errlog);
        fail_msg("%s: exit %d: %s", what, rc, m);
    }
}

/* the .exr holds exactly the .pfm's floats */
static void same_frame(const char *pfm, const char *exr)
{
    int w, h, ch;
    float *a, *b;
    qtool_exr_info info;
    char err[512];
    assert_int_equal(qtool_pfm_read(pfm, &w, &h, &ch, &a, err, sizeof err), 0);
    if (qtool_exr_read(exr, &info, &b, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(info.w, w), assert_int_equal(info.h, h), assert_int_equal(ch, 3);
    assert_int_equal(info.compression, QTOOL_EXR_ZIP), assert_int_equal(info.pixel_type, QTOOL_EXR_FLOAT);
    assert_memory_equal(a, b, sizeof(float) * 3 * (size_t)w * (size_t)h);
    free(a), free(b);
}

static void test_frames_as_exr(void **state)
{
    (void)state;
    need_qibl();
    ok(run("render", "--size", "32x8", "--sun", "0.3", "0.2", "1", "--threads", "1", "--pfm", at("r.pfm"), "--exr",
           at("r.exr"), NULL),
       "render");
    same_frame(at("r.pfm"), at("r.exr"));
    ok(run("render", "--size", "32x8", "--sun", "0.3", "0.2", "1", "--threads", "1", "--exr", at("only.exr"), NULL),
       "render --exr alone");
    ok(run("bake", "--size", "24x6", "--k", "4", "--dirs", "64", "--quiet", "--threads", "1", "--sun-path",
           "40,15,7,17", "--path-steps", "8", "-o", at("a.qibl"), NULL),
       "bake");
    ok(run("relight", at("a.qibl"), "--sun", "0.3", "0.2", "1", "--pfm", at("l.pfm"), "--exr", at("l.exr"), NULL),
       "relight");
    same_frame(at("l.pfm"), at("l.exr"));
    ok(run("relight", at("a.qibl"), "--path", "sun", "--t", "0.5", "--pfm", at("p.pfm"), "--exr", at("p.exr"), NULL),
       "relight --path");
    same_frame(at("p.pfm"), at("p.exr"));
    ok(run("check", at("r.exr"), at("l.exr"), NULL), "check");
    /* a directory in the way: refused, named, nothing left */
    assert_int_equal(mkdir(at("d.exr"), 0700), 0);
    assert_int_not_equal(run("render", "--size", "32x8", "--sun", "0", "0", "1", "--exr", at("d.exr"), NULL), 0);
    char *m = text(errlog);
    assert_non_null(strstr(m, "d.exr"));
    free(m);
}

/* a 32 x 16 lat-long probe whose values RGBE holds exactly (8-bit mantissas, the largest channel's
 * at least 128), written as .hdr and as .exr: the CLI must see the same probe */
static void test_probe_as_exr(void **state)
{
    (void)state;
    need_qibl();
    enum { W = 32, H = 16 };
    float px[W * H * 3];
    for (int i = 0; i < W * H; ++i) {
        int e = (i % 7) - 3;
        float s = e >= 0 ? (float)(1 << e) : 1.0f / (float)(1 << -e);
        px[3 * i] = s * (float)(128 + (i * 37) % 128) / 256.0f;
        px[3 * i + 1] = s * (float)((i * 11) % 128) / 256.0f;
        px[3 * i + 2] = s * (float)((i * 5) % 100) / 256.0f;
    }
    px[3 * 40] = 50.0f, px[3 * 40 + 1] = 16.0f, px[3 * 40 + 2] = 0.25f; /* a sun: all three exact at its exponent */
    char err[512];
    assert_int_equal(qtool_hdr_write(at("p.hdr"), W, H, px, err, sizeof err), 0);
    assert_int_equal(qtool_exr_write(at("p.exr"), W, H, px, QTOOL_EXR_HALF, QTOOL_EXR_ZIP, err, sizeof err), 0);
    ok(run("lights", at("p.hdr"), "-n", "4", "--csv", NULL), "lights p.hdr");
    char *a = text(outlog);
    ok(run("lights", at("p.exr"), "-n", "4", "--csv", NULL), "lights p.exr");
    char *b = text(outlog);
    assert_string_equal(a, b);
    free(a), free(b);
    ok(run("bake", "--size", "24x6", "--k", "4", "--dirs", "64", "--quiet", "--threads", "1", "-o", at("a.qibl"), NULL),
       "bake");
    ok(run("relight", at("a.qibl"), "--probe", at("p.hdr"), "--pfm", at("h.pfm"), NULL), "relight --probe p.hdr");
    ok(run("relight", at("a.qibl"), "--probe", at("p.exr"), "--pfm", at("e.pfm"), NULL), "relight --probe p.exr");
    size_t nx, ny;
    uint8_t *x = qtool_io_read_all(at("h.pfm"), &nx), *y = qtool_io_read_all(at("e.pfm"), &ny);
    assert_non_null(x), assert_non_null(y);
    assert_int_equal(nx, ny);
    assert_memory_equal(x, y, nx);
    free(x), free(y);
    /* a damaged EXR probe: named, exit non-zero */
    FILE *f = fopen(at("p.exr"), "r+b");
    fseek(f, 4, SEEK_SET);
    fputc(7, f);
    fclose(f);
    assert_int_not_equal(run("lights", at("p.exr"), NULL), 0);
    char *m = text(errlog);
    if (!strstr(m, "OpenEXR version 7") || !strstr(m, "p.exr"))
        fail_msg("lights on a damaged .exr said: %s", m);
    free(m);
    assert_int_not_equal(run("check", at("p.exr"), NULL), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_frames_as_exr, setup, teardown),
        cmocka_unit_test_setup_teardown(test_probe_as_exr, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
