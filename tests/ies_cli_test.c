/*
 * ies_cli_test.c - `qibl ies info`: the report of a synthetic file (lumens = 4 pi I for an isotropic
 * lamp, the header facts), --png writing a readable picture, a refused file giving exit 1, one
 * line on stderr naming it and nothing on stdout (and no picture), bad arguments exit 2.
 */
#include "cliutil.h"

#include <math.h>

#include "io/png.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static const char *at(const char *name)
{
    static char p[4][256];
    static int k;
    k = (k + 1) % 4;
    snprintf(p[k], sizeof p[k], "%s/%s", dir, name);
    return p[k];
}

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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_info_report_and_png),
        cmocka_unit_test(test_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
