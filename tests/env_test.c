/*
 * env_test.c - tools/render/env.c, the ground truth under a whole probe: a lone plane under a
 * constant probe receives pi L (within the noise the test measures), with a bright pixel added it
 * receives that pixel's share too; a one-pixel probe sampled at pixel centres is the directional
 * light of rt.h bit for bit (shadows included), and with jitter within the pixel's footprint;
 * thread-count independence; named errors for bad probes and arguments.
 */
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "io/obj.h"
#include "render/env.h"

#define PI 3.14159265358979323846

static void plane_scene(qtool_rt_scene *s)
{
    const char *text = "v -500 -500 -1\nv 500 -500 -1\nv 500 500 -1\nv -500 500 -1\nf 1 2 3 4\n";
    qtool_obj_mesh mesh;
    char err[256];
    assert_int_equal(qtool_obj_parse("plane.obj", text, strlen(text), &mesh, err, sizeof err), 0);
    assert_int_equal(qtool_rt_scene_from_obj(s, &mesh, 1, 1), 0);
    qtool_obj_free(&mesh);
    s->mats[1].ks = 0; /* Lambert only: the analytic answer is albedo E / pi */
}

static float *probe_fill(uint32_t w, uint32_t h, const float rgb[3])
{
    float *p = malloc(sizeof(float) * 3 * w * h);
    assert_non_null(p);
    for (size_t i = 0; i < (size_t)w * h; ++i)
        memcpy(p + 3 * i, rgb, 3 * sizeof(float));
    return p;
}

/* mean and standard error of the mean of channel c over the pixels that hit the plane */
static void plane_stats(const double *img, const uint8_t *hit, size_t np, int c, double *mean, double *sem)
{
    double s = 0, s2 = 0, n = 0;
    for (size_t i = 0; i < np; ++i)
        if (hit[i])
            s += img[3 * i + (size_t)c], s2 += img[3 * i + (size_t)c] * img[3 * i + (size_t)c], n += 1;
    assert_true(n > 10);
    *mean = s / n;
    *sem = sqrt(fmax(0, s2 / n - *mean * *mean) / (n - 1));
}

static void test_constant_probe_gives_pi_l(void **state)
{
    (void)state;
    qtool_rt_scene s;
    plane_scene(&s);
    const uint32_t pw = 64, ph = 32, w = 32, h = 16;
    const float L[3] = {0.5f, 0.7f, 0.9f};
    float *probe = probe_fill(pw, ph, L);
    /* case 1: constant; case 2: plus one bright pixel above the plane */
    for (int cs = 0; cs < 2; ++cs) {
        uint32_t bu = 20, bv = 6;
        double extra[3] = {0, 0, 0};
        if (cs == 1) {
            float *q = probe + 3 * ((size_t)bv * pw + bu);
            q[0] = q[1] = q[2] = 4000.0f;
            double dw = 2 * PI / pw * (cos(PI * bv / ph) - cos(PI * (bv + 1) / ph));
            /* irradiance of the pixel on an upward plane: L dw cos theta (cos theta averaged over
             * the pixel's rows: the integral of cos over the cell divided by its solid angle) */
            double c0 = cos(PI * bv / ph), c1 = cos(PI * (bv + 1) / ph), mc = 0.5 * (c0 + c1);
            for (int c = 0; c < 3; ++c)
                extra[c] = (4000.0 - L[c]) * dw * mc;
        }
        qtool_env e;
        char err[256];
        assert_int_equal(qtool_env_build(&e, pw, ph, probe, err, sizeof err), 0);
        assert_true(cs == 0 ? e.nb == 0 : e.nb == 1);
        double *img = malloc(sizeof(double) * 3 * w * h);
        uint8_t *hit = malloc((size_t)w * h);
        assert_non_null(img);
        assert_non_null(hit);
        assert_int_equal(qtool_env_render(&s, w, h, QTOOL_PANO_EQUIRECT, &e, 64, 7, 1, 2, img), 0);
        for (uint32_t y = 0; y < h; ++y)
            for (uint32_t x = 0; x < w; ++x) {
                double d[3];
                qtool_rt_hit hh;
                qtool_rt_pixel_dir(w, h, QTOOL_PANO_EQUIRECT, x, y, d);
                qtool_rt_primary(&s, d, &hh);
                /* well inside the plane: the horizon is the probe's, not the plane's edge */
                hit[y * w + x] = hh.hit && hh.t < 20;
                if (!hh.hit)
                    assert_true(img[3 * (y * w + x)] == 0 && img[3 * (y * w + x) + 2] == 0);
            }
        for (int c = 0; c < 3; ++c) {
            double mean, sem, want = s.mats[1].albedo[c] / PI * (PI * L[c] + extra[c]);
            plane_stats(img, hit, (size_t)w * h, c, &mean, &sem);
            /* the noise is measured, and bounded: at most 1 % of the answer per pixel mean */
            if (fabs(mean - want) > 4 * sem + 1e-9 || sem > 0.01 * want)
                fail_msg("case %d channel %d: %.6f, want %.6f (standard error %.2g)", cs, c, mean, want, sem);
        }
        free(img), free(hit);
        qtool_env_free(&e);
    }
    free(probe);
    qtool_rt_scene_free(&s);
}

static void test_one_bright_pixel_is_a_directional_light(void **state)
{
    (void)state;
    qtool_rt_scene s;
    assert_int_equal(qtool_rt_scene_builtin(&s), 0);
    const uint32_t w = 64, h = 16;
    size_t np = (size_t)w * h;
    for (int fine = 0; fine < 2; ++fine) {
        /* coarse probe at pixel centres: exact; fine probe (0.35 degree pixels) jittered: close */
        uint32_t pw = fine ? 1024 : 64, ph = pw / 2, bu = pw * 3 / 10, bv = ph / 4;
        const float zero[3] = {0, 0, 0};
        float *probe = probe_fill(pw, ph, zero);
        float *q = probe + 3 * ((size_t)bv * pw + bu);
        q[0] = 30.0f, q[1] = 20.0f, q[2] = 10.0f;
        double th = (bv + 0.5) * PI / ph, ph_ = (bu + 0.5) * 2 * PI / pw;
        double dw = 2 * PI / pw * (cos(PI * bv / ph) - cos(PI * (bv + 1) / ph));
        qtool_rt_light l = {0, {sin(th) * cos(ph_), sin(th) * sin(ph_), cos(th)}, {0, 0, 0},
                            {30 * dw, 20 * dw, 10 * dw}, 1};
        qtool_env e;
        char err[256];
        assert_int_equal(qtool_env_build(&e, pw, ph, probe, err, sizeof err), 0);
        double *a = malloc(sizeof(double) * 3 * np), *b = malloc(sizeof(double) * 3 * np);
        assert_non_null(a);
        assert_non_null(b);
        assert_int_equal(qtool_rt_render(&s, w, h, QTOOL_PANO_CYLINDRICAL, &l, 2, a, NULL, NULL), 0);
        assert_int_equal(qtool_env_render(&s, w, h, QTOOL_PANO_CYLINDRICAL, &e, 16, 3, fine, 2, b), 0);
        double sa = 0, sd = 0;
        int lit = 0, shadow = 0;
        for (size_t i = 0; i < np * 3; ++i) {
            if (!fine && fabs(a[i] - b[i]) > 1e-12 * (1 + a[i]))
                fail_msg("pixel %zu channel %zu: %.15g against the directional light's %.15g", i / 3, i % 3, b[i], a[i]);
            sa += a[i], sd += fabs(a[i] - b[i]);
            lit += i % 3 == 0 && a[i] > 0, shadow += i % 3 == 0 && a[i] == 0;
        }
        assert_true(lit > 50 && shadow > 50); /* the light casts shadows in this view */
        if (fine && sd > 0.02 * sa)
            fail_msg("jittered over a 0.35 degree pixel: mean |difference| %.3g of the mean", sd / sa);
        free(a), free(b), free(probe);
        qtool_env_free(&e);
    }
    qtool_rt_scene_free(&s);
}

static void test_threads_and_seeds(void **state)
{
    (void)state;
    qtool_rt_scene s;
    assert_int_equal(qtool_rt_scene_builtin(&s), 0);
    const uint32_t pw = 128, ph = 64, w = 48, h = 12;
    float *probe = malloc(sizeof(float) * 3 * pw * ph);
    assert_non_null(probe);
    for (uint32_t i = 0; i < pw * ph; ++i) /* a sky gradient and a sun */
        for (int c = 0; c < 3; ++c)
            probe[3 * i + (uint32_t)c] = (float)(0.2 + 0.1 * c + (i / pw < ph / 2 ? 0.5 : 0) + (i == 20 * pw + 40 ? 5000 : 0));
    qtool_env e;
    char err[256];
    assert_int_equal(qtool_env_build(&e, pw, ph, probe, err, sizeof err), 0);
    size_t n = (size_t)w * h * 3;
    double *a = malloc(n * sizeof(double)), *b = malloc(n * sizeof(double)), *c = malloc(n * sizeof(double));
    assert_non_null(a);
    assert_non_null(b);
    assert_non_null(c);
    assert_int_equal(qtool_env_render(&s, w, h, QTOOL_PANO_CYLINDRICAL, &e, 32, 5, 1, 1, a), 0);
    assert_int_equal(qtool_env_render(&s, w, h, QTOOL_PANO_CYLINDRICAL, &e, 32, 5, 1, 3, b), 0);
    assert_memory_equal(a, b, n * sizeof(double));
    assert_int_equal(qtool_env_render(&s, w, h, QTOOL_PANO_CYLINDRICAL, &e, 32, 6, 1, 2, c), 0);
    assert_true(memcmp(a, c, n * sizeof(double)) != 0); /* another seed: another estimate */
    free(a), free(b), free(c), free(probe);
    qtool_env_free(&e);
    qtool_rt_scene_free(&s);
}

/* the first i with cdf[i + 1] > t, or hi - 1: the inverse CDF by a linear scan */
static size_t linear_find(const double *cdf, size_t lo, size_t hi, double t)
{
    for (size_t i = lo; i < hi; ++i)
        if (cdf[i + 1] > t)
            return i;
    return hi - 1;
}

/* qtool_env_sample's guided search draws exactly the pixel of the plain inverse CDF: probes with
 * long zero runs (flat CDF), one bright pixel, sizes below and above the guide's size, fractions
 * on the guide's boundaries, 0 and the largest below 1 (and 1 itself, which rounding can give) */
static void test_guided_sample_is_the_inverse_cdf(void **state)
{
    (void)state;
    static const uint32_t dims[][2] = {{1, 1}, {2, 1}, {3, 2}, {8, 4}, {64, 32}, {97, 13}, {256, 128}};
    uint64_t x = 12345;
    for (size_t d = 0; d < sizeof dims / sizeof dims[0]; ++d) {
        const uint32_t pw = dims[d][0], ph = dims[d][1];
        const size_t np = (size_t)pw * ph;
        for (int kind = 0; kind < 3; ++kind) {
            float *probe = probe_fill(pw, ph, (const float[3]){0.2f, 0.3f, 0.4f});
            for (size_t i = 0; i < np; ++i) {
                x = x * 6364136223846793005ull + 1442695040888963407ull;
                if (kind == 1 && (x >> 60) < 12) /* three quarters black: flat runs in the CDFs */
                    probe[3 * i] = probe[3 * i + 1] = probe[3 * i + 2] = 0;
                if (kind == 2 && (x >> 58) == 0) /* a few bright pixels: a bright set */
                    probe[3 * i] = probe[3 * i + 1] = probe[3 * i + 2] = 1e4f;
            }
            probe[0] = probe[1] = probe[2] = 0.5f; /* never all black */
            qtool_env e;
            char err[256];
            assert_int_equal(qtool_env_build(&e, pw, ph, probe, err, sizeof err), 0);
            for (int bright = 0; bright < 2; ++bright) {
                const double *cdf = bright ? e.cdf_b : e.cdf_r;
                if (!(cdf[np] > 0))
                    continue;
                for (int k = 0; k < 4000; ++k) {
                    double a, b;
                    x = x * 6364136223846793005ull + 1442695040888963407ull;
                    a = k < 64 ? (double)(k % 32) / 32 + (k >= 32 ? 0x1p-40 : 0) : (double)(x >> 11) * 0x1p-53;
                    if (k == 64)
                        a = 0x1.fffffffffffffp-1;
                    if (k == 65)
                        a = 1.0;
                    x = x * 6364136223846793005ull + 1442695040888963407ull;
                    b = k % 7 == 0 ? 0.0 : (double)(x >> 11) * 0x1p-53;
                    size_t i = linear_find(cdf, 0, np, cdf[np] * a), r0 = i / pw * pw, r1 = r0 + pw;
                    size_t j = linear_find(cdf, r0, r1, cdf[r0] + b * (cdf[r1] - cdf[r0]));
                    const size_t want = cdf[j + 1] > cdf[j] ? j : i;
                    const size_t got = qtool_env_sample(&e, bright, a, b);
                    if (got != want)
                        fail_msg("%ux%u kind %d set %d: (%a, %a) drew %zu, the inverse CDF %zu", pw, ph, kind, bright,
                                 a, b, got, want);
                }
            }
            qtool_env_free(&e);
            free(probe);
        }
    }
}

static void test_bad_inputs_are_named(void **state)
{
    (void)state;
    qtool_env e;
    char err[256];
    float px[3 * 8 * 4];
    for (size_t i = 0; i < sizeof px / sizeof px[0]; ++i)
        px[i] = 1.0f;
    px[3 * (2 * 8 + 5) + 1] = -1.0f;
    assert_int_equal(qtool_env_build(&e, 8, 4, px, err, sizeof err), -1);
    assert_non_null(strstr(err, "(5, 2)"));
    assert_non_null(strstr(err, "negative"));
    px[3 * (2 * 8 + 5) + 1] = NAN;
    assert_int_equal(qtool_env_build(&e, 8, 4, px, err, sizeof err), -1);
    assert_non_null(strstr(err, "non-finite"));
    memset(px, 0, sizeof px);
    assert_int_equal(qtool_env_build(&e, 8, 4, px, err, sizeof err), -1);
    assert_non_null(strstr(err, "black"));
    assert_int_equal(qtool_env_build(&e, 0, 4, px, err, sizeof err), -1);
    assert_non_null(strstr(err, "0x4"));
    px[0] = 1;
    assert_int_equal(qtool_env_build(&e, 8, 4, px, err, sizeof err), 0);
    qtool_rt_scene s;
    assert_int_equal(qtool_rt_scene_builtin(&s), 0);
    double out[3 * 4];
    assert_int_equal(qtool_env_render(&s, 4, 1, QTOOL_PANO_CYLINDRICAL, &e, 3, 1, 1, 1, out), -1); /* spp < 4 */
    assert_int_equal(qtool_env_render(&s, 4, 1, QTOOL_PANO_CYLINDRICAL, &e, 8, 1, 1, 1, NULL), -1);
    assert_int_equal(qtool_env_render(&s, 4, 1, QTOOL_PANO_CYLINDRICAL, &e, 8, 1, 1, 1, out), 0);
    qtool_env_free(&e);
    qtool_rt_scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_constant_probe_gives_pi_l),
        cmocka_unit_test(test_one_bright_pixel_is_a_directional_light),
        cmocka_unit_test(test_threads_and_seeds),
        cmocka_unit_test(test_guided_sample_is_the_inverse_cdf),
        cmocka_unit_test(test_bad_inputs_are_named),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
