/*
 * camera_test.c - fixed-camera frames (render/rt.h qtool_rt_camera, bake/scene.h): the pixel rays
 * of a camera looking down an axis, the named errors of a bad camera, a glTF file's camera, and a
 * camera bake whose relit frames (shadowed SH; a sun on a baked path) match the ray-traced render
 * of the same camera within the PSNR stated below.
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

#include "bake/bake.h"
#include "cliutil.h"
#include "bake/path.h"
#include "bake/scene.h"
#include "io/png.h"
#include "ref/psnr.h"

#ifndef QIBL_SOURCE_DIR
#define QIBL_SOURCE_DIR "."
#endif

static void assert_dir(const double d[3], double x, double y, double z)
{
    double l = sqrt(x * x + y * y + z * z);
    assert_true(fabs(d[0] - x / l) < 1e-12 && fabs(d[1] - y / l) < 1e-12 && fabs(d[2] - z / l) < 1e-12);
}

/* eye (1, 2, 3) looking down +x, z up, fov 90 (tan 1): right is -y, so column x of a 3-wide frame is
 * at (2 (x + 0.5) / 3 - 1) along -y, row y at (1 - 2 (y + 0.5) / 3) along +z */
static void test_axis_rays(void **state)
{
    (void)state;
    qtool_rt_scene s;
    memset(&s, 0, sizeof s);
    const double eye[3] = {1, 2, 3}, target[3] = {5, 2, 3}, up[3] = {0, 0, 7};
    char err[128];
    assert_int_equal(qtool_rt_camera_init(&s.cam, eye, target, up, 90, err, sizeof err), 0);
    s.has_cam = 1;
    double d[3];
    qtool_rt_pixel_ray(&s, 3, 3, QTOOL_PANO_CYLINDRICAL, 1, 1, d);
    assert_dir(d, 1, 0, 0);
    qtool_rt_pixel_ray(&s, 3, 3, QTOOL_PANO_CYLINDRICAL, 0, 1, d);
    assert_dir(d, 1, 2.0 / 3, 0);
    qtool_rt_pixel_ray(&s, 3, 3, QTOOL_PANO_CYLINDRICAL, 2, 0, d);
    assert_dir(d, 1, -2.0 / 3, 2.0 / 3);
    /* a 6 x 3 frame: square pixels, so the horizontal extent is twice the vertical */
    qtool_rt_pixel_ray(&s, 6, 3, QTOOL_PANO_CYLINDRICAL, 0, 2, d);
    assert_dir(d, 1, 2 * (1 - 1.0 / 6), -2.0 / 3);
    /* looking straight down -z with y up: the centre pixel is -z, the top row leans to +y */
    const double t2[3] = {1, 2, -10}, up2[3] = {0, 1, 0};
    assert_int_equal(qtool_rt_camera_init(&s.cam, eye, t2, up2, 60, err, sizeof err), 0);
    qtool_rt_pixel_ray(&s, 1, 1, QTOOL_PANO_CYLINDRICAL, 0, 0, d);
    assert_dir(d, 0, 0, -1);
    qtool_rt_pixel_ray(&s, 1, 3, QTOOL_PANO_CYLINDRICAL, 0, 0, d);
    assert_dir(d, 0, 2.0 / 3 * tan(30 * 3.14159265358979323846 / 180), -1);
    /* the primary ray starts at the eye: the sky point is 1000 along the ray from it */
    double p[3];
    qtool_rt_sky_point(&s, d, 1000, p);
    assert_true(fabs(p[0] - (1 + 1000 * d[0])) < 1e-9 && fabs(p[2] - (3 + 1000 * d[2])) < 1e-9);
}

static void expect_error(const double eye[3], const double target[3], const double up[3], double fov, const char *word)
{
    qtool_rt_camera c, before;
    memset(&c, 0x5a, sizeof c);
    before = c;
    char err[128] = "";
    assert_int_equal(qtool_rt_camera_init(&c, eye, target, up, fov, err, sizeof err), -1);
    assert_non_null(strstr(err, word));
    assert_memory_equal(&c, &before, sizeof c); /* nothing written on failure */
}

static void test_bad_cameras(void **state)
{
    (void)state;
    const double o[3] = {0, 0, 0}, x[3] = {1, 0, 0}, z[3] = {0, 0, 1}, zero[3] = {0, 0, 0};
    const double nan3[3] = {NAN, 0, 0}, far[3] = {2e6, 0, 0}, nearly_x[3] = {1, 1e-6, 0};
    expect_error(o, o, z, 60, "the eye is the target");
    expect_error(x, x, z, 60, "the eye is the target");
    expect_error(o, x, zero, 60, "up vector is zero or parallel");
    expect_error(o, x, x, 60, "up vector is zero or parallel");
    expect_error(o, x, nearly_x, 60, "up vector is zero or parallel");
    expect_error(o, x, z, 0, "field of view 0 degrees is outside (0, 180)");
    expect_error(o, x, z, 180, "field of view 180 degrees is outside (0, 180)");
    expect_error(o, x, z, -5, "field of view");
    expect_error(o, x, z, NAN, "field of view");
    expect_error(nan3, x, z, 60, "not a number");
    expect_error(o, far, z, 60, "beyond");
    /* the scene loader refuses them by the same names, and a glTF camera without a glTF scene */
    qtool_scene_opts so = QTOOL_SCENE_OPTS_DEFAULT;
    qtool_rt_scene s;
    char err[256];
    so.camera = QTOOL_SCENE_CAMERA;
    memcpy(so.eye, o, sizeof o), memcpy(so.target, o, sizeof o), memcpy(so.up, z, sizeof z);
    assert_int_equal(qtool_scene_load(&so, &s, err, sizeof err), -1);
    assert_non_null(strstr(err, "the eye is the target"));
    so.camera = QTOOL_SCENE_GLTF_CAMERA;
    assert_int_equal(qtool_scene_load(&so, &s, err, sizeof err), -1);
    assert_non_null(strstr(err, "no camera"));
}

/* A glTF file's camera (fixtures/gltf/Cameras.gltf: a perspective camera 0 in front of a unit
 * square, an orthographic camera 1), placed with the mesh as given (--raw): the centre ray hits the
 * square; the orthographic camera and a missing one are named errors. */
static void test_gltf_camera(void **state)
{
    (void)state;
    char path[1024], err[1400];
    snprintf(path, sizeof path, "%s/fixtures/gltf/Cameras.gltf", QIBL_SOURCE_DIR);
    qtool_scene_opts so = QTOOL_SCENE_OPTS_DEFAULT;
    so.scene = path, so.raw = 1, so.camera = QTOOL_SCENE_GLTF_CAMERA, so.fov = 0;
    qtool_rt_scene s;
    assert_int_equal(qtool_scene_load(&so, &s, err, sizeof err), 0);
    assert_true(s.has_cam);
    double d[3];
    qtool_rt_hit h;
    qtool_rt_pixel_ray(&s, 65, 49, QTOOL_PANO_CYLINDRICAL, 32, 24, d);
    qtool_rt_primary(&s, d, &h);
    assert_true(h.hit);
    qtool_rt_pixel_ray(&s, 65, 49, QTOOL_PANO_CYLINDRICAL, 0, 0, d); /* a corner: beside the square */
    qtool_rt_primary(&s, d, &h);
    assert_false(h.hit);
    qtool_rt_scene_free(&s);
    so.gltf_cam = 1;
    assert_int_equal(qtool_scene_load(&so, &s, err, sizeof err), -1);
    assert_non_null(strstr(err, "orthographic"));
    so.gltf_cam = 2;
    assert_int_equal(qtool_scene_load(&so, &s, err, sizeof err), -1);
    assert_non_null(strstr(err, "the file has 2 cameras"));
}

/* A camera bake of the courtyard relit under a novel sun against the ray-traced render of the same
 * camera: the same kind of agreement as the panorama bake (k = 16: hard shadows blurred), stated as
 * at least 16 dB over the scene's pixels; and the camera must matter (the panorama's truth differs). */
#define CAMERA_PSNR_MIN 16.0
#define CAMERA_PATH_PSNR_MIN 30.0
static void test_camera_bake_matches_render(void **state)
{
    (void)state;
    const uint32_t w = 48, h = 36;
    qtool_scene_opts so = QTOOL_SCENE_OPTS_DEFAULT;
    so.camera = QTOOL_SCENE_CAMERA, so.fov = 70;
    const double eye[3] = {3.5, -3.5, 0.5}, target[3] = {-2.5, 1.5, -1.0}, up[3] = {0, 0, 1};
    memcpy(so.eye, eye, sizeof eye), memcpy(so.target, target, sizeof target), memcpy(so.up, up, sizeof up);
    qtool_rt_scene s;
    char err[256];
    assert_int_equal(qtool_scene_load(&so, &s, err, sizeof err), 0);
    assert_true(s.has_cam);
    qtool_bake_sums sums;
    assert_int_equal(qtool_bake_run(&s, w, h, QTOOL_PANO_CYLINDRICAL, 256, 16, 0, 1, 2, 0, &sums), 0);
    /* the P map holds the camera's hits: the centre pixel's point lies on the ray from the eye */
    const int32_t *pc = sums.pmap + 3 * ((size_t)(h / 2) * w + w / 2);
    double dc[3];
    qtool_rt_pixel_ray(&s, w, h, QTOOL_PANO_CYLINDRICAL, w / 2, h / 2, dc);
    double v[3] = {pc[0] / 65536.0 - eye[0], pc[1] / 65536.0 - eye[1], pc[2] / 65536.0 - eye[2]};
    double vl = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    assert_true(vl > 0.5);
    for (int j = 0; j < 3; ++j)
        assert_true(fabs(v[j] / vl - dc[j]) < 1e-3);
    qtool_gen_maps m;
    uint8_t *asset;
    size_t n;
    assert_int_equal(qtool_bake_coeffs(&sums, 16, QTOOL_PROJ_QUADRATURE, &m), 0);
    assert_int_equal(qtool_bake_asset(&m, 0, &asset, &n), 0);
    qtool_rt_light sun = {0, {0.45, 0.25, 0.86}, {0, 0, 0}, {2.6, 2.4, 2.1}, 1};
    uint8_t *truth = malloc(w * h * 3), *relit = malloc(w * h * 3), *pano = malloc(w * h * 3), *mask = malloc(w * h);
    assert_non_null(truth), assert_non_null(relit), assert_non_null(pano), assert_non_null(mask);
    assert_int_equal(qtool_bake_truth8(&s, w, h, QTOOL_PANO_CYLINDRICAL, &sun, 2, truth, mask), 0);
    assert_int_equal(qtool_bake_relight8(asset, n, &sun, 0, relit, NULL), 0);
    double psnr = qtool_ref_psnr8(qtool_bake_mse(relit, truth, mask, (size_t)w * h));
    print_message("camera bake relit against the camera's ray-traced truth: %.2f dB (at least %.1f)\n", psnr,
                  CAMERA_PSNR_MIN);
    assert_true(psnr >= CAMERA_PSNR_MIN);
    s.has_cam = 0; /* the same scene as a panorama from the origin: a different picture */
    assert_int_equal(qtool_bake_truth8(&s, w, h, QTOOL_PANO_CYLINDRICAL, &sun, 2, pano, NULL), 0);
    assert_true(qtool_ref_psnr8(qtool_bake_mse(relit, pano, mask, (size_t)w * h)) < psnr - 3);
    /* a sun on a baked path from the same camera: unshadowed SH x the path's visibility per pixel of
     * the camera's frame, against the truth of the sun at that t (the panorama's light-path figure,
     * about 30 dB, is the bar) */
    qtool_bake_path p;
    memset(&p, 0, sizeof p);
    p.rgb[0] = p.rgb[1] = p.rgb[2] = 1;
    assert_int_equal(qtool_bake_path_parse_sun("40,15,7,17", &p, err, sizeof err), 0);
    qtool_bake_sums us;
    qtool_gen_maps mu;
    uint8_t *paths[2] = {NULL, NULL}, *passet;
    size_t sizes[2] = {0, 0}, pn;
    assert_int_equal(qtool_bake_run_unshadowed(&s, w, h, QTOOL_PANO_CYLINDRICAL, 256, 9, 2, &us), 0);
    assert_int_equal(qtool_bake_coeffs(&us, 9, QTOOL_PROJ_QUADRATURE, &mu), 0);
    assert_int_equal(qtool_bake_path_chunk(&s, w, h, QTOOL_PANO_CYLINDRICAL, &p, 32, 65, 2, &paths[0], &sizes[0], NULL), 0);
    assert_int_equal(qtool_bake_asset_full(&m, &mu, 0, QIBL_SHMAPS_PLANAR, paths, sizes, &passet, &pn), 0);
    const double t = 0.3;
    qtool_rt_light pl;
    qtool_bake_path_light(&p, t, &pl);
    qibl_status_t st;
    assert_int_equal(qtool_bake_relight_path8(passet, pn, &pl, 0, (uint32_t)(t * 65535 + 0.5), 0, NULL, relit, NULL, NULL,
                                              &st), 0);
    assert_int_equal(qtool_bake_truth8(&s, w, h, QTOOL_PANO_CYLINDRICAL, &pl, 2, truth, mask), 0);
    double ppsnr = qtool_ref_psnr8(qtool_bake_mse(relit, truth, mask, (size_t)w * h));
    print_message("a sun on a baked path from the camera: %.2f dB (at least %.1f)\n", ppsnr, CAMERA_PATH_PSNR_MIN);
    assert_true(ppsnr >= CAMERA_PATH_PSNR_MIN);
    free(paths[0]), free(passet);
    qtool_gen_free(&mu);
    qtool_bake_sums_free(&us);
    free(truth), free(relit), free(pano), free(mask), free(asset);
    qtool_gen_free(&m);
    qtool_bake_sums_free(&sums);
    qtool_rt_scene_free(&s);
}


/* A textured glTF scene from its own camera (fixtures/gltf/TexturedRoom.gltf, made by
 * tools/scripts/gen-gltf-room.py: a checker floor and brick walls as base-colour PNG textures, a box
 * and a pillar, a perspective camera in the open corner): baked from that camera (unshadowed k = 9
 * and a sun path's visibility), relit by the core with the sun between the baked steps, against the
 * ray-traced render of the same camera: at least 30 dB over the scene's pixels (issue 26's goal). */
#define TEXTURED_PATH_PSNR_MIN 30.0
static void test_textured_gltf_from_its_camera(void **state)
{
    (void)state;
    const uint32_t w = 64, h = 48;
    char path[1024], err[1400];
    snprintf(path, sizeof path, "%s/fixtures/gltf/TexturedRoom.gltf", QIBL_SOURCE_DIR);
    qtool_scene_opts so = QTOOL_SCENE_OPTS_DEFAULT;
    so.scene = path, so.camera = QTOOL_SCENE_GLTF_CAMERA, so.fov = 0;
    qtool_rt_scene s;
    if (qtool_scene_load(&so, &s, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_true(s.has_cam);
    assert_int_equal(s.ntex, 2); /* both textures reach the tracer */
    assert_non_null(s.tex);
    /* the camera's frame shows the textures: the floor's checker makes the truth's centre column
     * change colour more than the untextured faces would (at least 4 strong steps down it) */
    qtool_rt_light sun = {0, {0.35, -0.3, 0.89}, {0, 0, 0}, {2.6, 2.4, 2.1}, 1};
    uint8_t *truth = malloc(w * h * 3), *relit = malloc(w * h * 3), *mask = malloc(w * h);
    assert_non_null(truth), assert_non_null(relit), assert_non_null(mask);
    assert_int_equal(qtool_bake_truth8(&s, w, h, QTOOL_PANO_CYLINDRICAL, &sun, 2, truth, mask), 0);
    int steps = 0;
    for (uint32_t y = h / 2; y + 1 < h; ++y) {
        const uint8_t *a = truth + 3 * ((size_t)y * w + w / 4), *b = a + 3 * w;
        steps += abs((int)a[0] - (int)b[0]) + abs((int)a[2] - (int)b[2]) > 40;
    }
    assert_true(steps >= 4);
    qtool_bake_path p;
    memset(&p, 0, sizeof p);
    p.rgb[0] = p.rgb[1] = p.rgb[2] = 1;
    assert_int_equal(qtool_bake_path_parse_sun("40,15,7,17", &p, err, sizeof err), 0);
    qtool_bake_sums us;
    qtool_gen_maps mu;
    uint8_t *paths[2] = {NULL, NULL}, *passet;
    size_t sizes[2] = {0, 0}, pn;
    assert_int_equal(qtool_bake_run_unshadowed(&s, w, h, QTOOL_PANO_CYLINDRICAL, 256, 9, 2, &us), 0);
    assert_int_equal(qtool_bake_coeffs(&us, 9, QTOOL_PROJ_QUADRATURE, &mu), 0);
    assert_int_equal(
        qtool_bake_path_chunk(&s, w, h, QTOOL_PANO_CYLINDRICAL, &p, 32, 65, 2, &paths[0], &sizes[0], NULL), 0);
    assert_int_equal(qtool_bake_asset_full(&mu, &mu, 0, QIBL_SHMAPS_PLANAR, paths, sizes, &passet, &pn), 0);
    double worst = 1e9;
    for (int i = 0; i < 3; ++i) {
        const double t = 0.2 + 0.3 * i; /* between the baked steps */
        qtool_rt_light pl;
        qtool_bake_path_light(&p, t, &pl);
        qibl_status_t st;
        assert_int_equal(qtool_bake_relight_path8(passet, pn, &pl, 0, (uint32_t)(t * 65535 + 0.5), 0, NULL, relit, NULL,
                                                  NULL, &st), 0);
        assert_int_equal(qtool_bake_truth8(&s, w, h, QTOOL_PANO_CYLINDRICAL, &pl, 2, truth, mask), 0);
        double ppsnr = qtool_ref_psnr8(qtool_bake_mse(relit, truth, mask, (size_t)w * h));
        print_message("TexturedRoom.gltf from its camera, a sun on a baked path at t = %.1f: %.2f dB (at least %.1f)\n",
                      t, ppsnr, TEXTURED_PATH_PSNR_MIN);
        worst = ppsnr < worst ? ppsnr : worst;
    }
    assert_true(worst >= TEXTURED_PATH_PSNR_MIN);
    free(paths[0]), free(passet);
    qtool_gen_free(&mu);
    qtool_bake_sums_free(&us);
    free(truth), free(relit), free(mask);
    qtool_rt_scene_free(&s);
}

CLI_FIXTURES("/tmp/qibl_camera_XXXXXX")

/* The CLI: a bad camera is a bad argument (exit 2, named, nothing written); a camera bake relights. */
static void test_cli_camera(void **state)
{
    (void)state;
    need_qibl();
    assert_int_equal(run("render", "--camera", "1,2,3", "1,2,3", "0,0,1", "--size", "16x12", "--sun", "0", "0", "1",
                         "--png", at("x.png"), NULL), 2);
    char *e = text(errlog);
    assert_non_null(strstr(e, "the eye is the target"));
    free(e);
    assert_int_equal(access(at("x.png"), F_OK), -1);
    assert_int_equal(run("bake", "--camera", "0,0,0", "1,0,0", "1,0,0", "-o", at("x.qibl"), NULL), 2);
    e = text(errlog);
    assert_non_null(strstr(e, "up vector is zero or parallel"));
    free(e);
    assert_int_equal(run("bake", "--camera", "0,0,0", "1,0,0", "0,0,1", "--equirect", "-o", at("x.qibl"), NULL), 2);
    assert_int_equal(run("render", "--camera", "0,0,0", "1,0,0", "0,0,1", "--fov", "180", "--sun", "0", "0", "1",
                         "--png", at("x.png"), NULL), 2);
    assert_int_equal(run("render", "--fov", "40", "--sun", "0", "0", "1", "--png", at("x.png"), NULL), 2);
    assert_int_equal(run("render", "--camera", "gltf:x", "--sun", "0", "0", "1", "--png", at("x.png"), NULL), 2);
    assert_int_equal(access(at("x.qibl"), F_OK), -1);
    assert_int_equal(run("bake", "--camera", "3.5,-3.5,0.5", "-2.5,1.5,-1", "0,0,1", "--fov", "70", "--size", "24x18",
                         "--dirs", "16", "--k", "4", "--unshadowed-k", "0", "--lut-size", "0", "--quiet", "--threads",
                         "1", "-o", at("cam.qibl"), NULL), 0);
    assert_int_equal(run("relight", at("cam.qibl"), "--sun", "0.4", "0.3", "0.86", "--png", at("r.png"), NULL), 0);
    assert_int_equal(run("check", at("r.png"), NULL), 0);
    char *o = text(outlog);
    assert_non_null(strstr(o, "PNG 24x18"));
    free(o);
}

/* `qibl relight --gles` on a camera asset (the textured room from its glTF camera) as on a panorama:
 * the GLES2 frame equals the core + platform/soft frame within tests/gles2_test.c's bounds (max 2,
 * mean 0.5 levels of 8-bit sRGB), for a sun and for a lamp (which reads the camera's P map). Skips
 * without a usable EGL context unless QIBL_REQUIRE_GLES=1. */
static void compare_pngs(const char *a, const char *b, const char *what)
{
    char err[512];
    int wa, ha, wb, hb, fa, fb;
    uint8_t *pa, *pb;
    if (qtool_png_read_rgb8(a, &wa, &ha, &fa, &pa, err, sizeof err) != 0 ||
        qtool_png_read_rgb8(b, &wb, &hb, &fb, &pb, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(wa, wb), assert_int_equal(ha, hb);
    unsigned mx = 0;
    double sum = 0;
    size_t n = (size_t)wa * (size_t)ha * 3;
    for (size_t i = 0; i < n; ++i) {
        unsigned d = (unsigned)abs((int)pa[i] - (int)pb[i]);
        mx = d > mx ? d : mx, sum += d;
    }
    print_message("camera asset, relight --gles against the soft frame, %s: max %u, mean %.3f levels\n", what, mx,
                  sum / (double)n);
    assert_true(mx <= 2 && sum / (double)n <= 0.5);
    free(pa), free(pb);
}

static void test_cli_gles_camera(void **state)
{
    (void)state;
    need_qibl();
    char scene[1024];
    snprintf(scene, sizeof scene, "%s/fixtures/gltf/TexturedRoom.gltf", QIBL_SOURCE_DIR);
    assert_int_equal(run("bake", "--scene", scene, "--camera", "gltf", "--size", "40x30", "--dirs", "64", "--k", "9",
                         "--unshadowed-k", "0", "--quiet", "--threads", "2", "-o", at("room.qibl"), NULL), 0);
    const char *r = getenv("QIBL_REQUIRE_GLES");
    if (run("relight", at("room.qibl"), "--gles", "--sun", "0.35", "-0.3", "0.89", "--png", at("g.png"), NULL) != 0) {
        char *e = text(errlog);
        if (r != NULL && strcmp(r, "1") == 0)
            fail_msg("QIBL_REQUIRE_GLES=1 and relight --gles failed: %s", e);
        print_message("SKIP the GLES2 camera frames: %s", e);
        free(e);
        skip();
    }
    assert_int_equal(run("relight", at("room.qibl"), "--sun", "0.35", "-0.3", "0.89", "--png", at("s.png"), NULL), 0);
    compare_pngs(at("g.png"), at("s.png"), "sun");
    assert_int_equal(
        run("relight", at("room.qibl"), "--gles", "--point", "-3", "1", "0.5", "--png", at("g.png"), NULL), 0);
    assert_int_equal(run("relight", at("room.qibl"), "--point", "-3", "1", "0.5", "--png", at("s.png"), NULL), 0);
    compare_pngs(at("g.png"), at("s.png"), "lamp");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_axis_rays),
        cmocka_unit_test(test_bad_cameras),
        cmocka_unit_test(test_gltf_camera),
        cmocka_unit_test(test_camera_bake_matches_render),
        cmocka_unit_test(test_textured_gltf_from_its_camera),
        cmocka_unit_test_setup_teardown(test_cli_camera, setup, teardown),
        cmocka_unit_test_setup_teardown(test_cli_gles_camera, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
