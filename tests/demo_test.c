/*
 * demo_test.c - the demo library's own pieces (tools/demo): the sizes table, the heat map's scale,
 * the sheet blit, the chunk sizes, the output-directory check, the named refusals and the
 * fixed-camera row. The whole demo
 * runs in cli_test (small sizes) and in CI (`make demo DEMO_SIZE=small`).
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cmocka.h>

#include "demo/demo.h"

/* the three sizes CI, `make demo` and the README use, and nothing else */
static void test_sizes_named(void **state)
{
    (void)state;
    const qtool_demo_size *s = qtool_demo_size_named("small"), *d = qtool_demo_size_named("default"),
                          *f = qtool_demo_size_named("full");
    assert_non_null(s), assert_non_null(d), assert_non_null(f);
    assert_string_equal(s->name, "small");
    assert_int_equal(s->w, 256), assert_int_equal(s->h, 64), assert_int_equal(s->ndirs, 128);
    assert_int_equal(s->frames, 6);
    assert_int_equal(d->w, 512), assert_int_equal(d->h, 128), assert_int_equal(d->ndirs, 256);
    assert_int_equal(f->w, 1024), assert_int_equal(f->h, 256), assert_int_equal(f->ndirs, 512);
    /* each size costs more than the one before it */
    assert_true(s->w * s->h < d->w * d->h && d->w * d->h < f->w * f->h);
    assert_null(qtool_demo_size_named("huge"));
    assert_null(qtool_demo_size_named(""));
    assert_null(qtool_demo_size_named("Small"));
}

/* the heat map's scale: 0 black, 8 of 255 blue, 24 purple, 48 and above the same yellow-white;
 * masked pixels black whatever their error (round half to even: 127.5 is 128) */
static void test_heat_scale(void **state)
{
    (void)state;
    enum { N = 6 };
    uint8_t a[3 * N], b[3 * N] = {0}, out[3 * N];
    static const uint8_t d[N] = {0, 8, 24, 48, 200, 200};
    static const uint8_t cls[N] = {1, 1, 1, 1, 1, 0};
    for (int i = 0; i < N; ++i)
        a[3 * i] = d[i], a[3 * i + 1] = 0, a[3 * i + 2] = 0;
    b[3 * 1 + 2] = 3; /* the largest channel difference counts: still 8 */
    qtool_demo_heat(a, b, cls, N, out);
    assert_memory_equal(out, ((const uint8_t[]){0, 0, 0}), 3);
    assert_int_equal(out[3], 0), assert_int_equal(out[4], 0), assert_int_equal(out[5], 128); /* t = 1/6 */
    assert_int_equal(out[6], 128), assert_int_equal(out[7], 0), assert_int_equal(out[8], 128); /* t = 1/2 */
    assert_memory_equal(out + 9, ((const uint8_t[]){255, 255, 64}), 3);
    assert_memory_equal(out + 12, out + 9, 3); /* saturated */
    assert_memory_equal(out + 15, ((const uint8_t[]){0, 0, 0}), 3);
}

/* a blit lands where it is told and nowhere else */
static void test_blit_in_place(void **state)
{
    (void)state;
    enum { SW = 7, SH = 5, W = 3, H = 2 };
    uint8_t sheet[SW * SH * 3], src[W * H * 3], want[SW * SH * 3];
    memset(sheet, 0xEE, sizeof sheet);
    for (size_t i = 0; i < sizeof src; ++i)
        src[i] = (uint8_t)(i + 1);
    memcpy(want, sheet, sizeof want);
    for (int y = 0; y < H; ++y)
        memcpy(want + ((size_t)(2 + y) * SW + 4) * 3, src + (size_t)y * W * 3, W * 3);
    qtool_demo_blit(sheet, SW, 4, 2, src, W, H);
    assert_memory_equal(sheet, want, sizeof want);
}

/* a bad asset has no chunks: 0 bytes, not a crash */
static void test_chunk_bytes_of_garbage(void **state)
{
    (void)state;
    static const uint8_t junk[64] = {'n', 'o', 't', ' ', 'a', 'n', ' ', 'a', 's', 's', 'e', 't'};
    assert_true(qtool_demo_chunk_bytes(junk, sizeof junk, 0x50414D53u, 0) == 0);
    assert_true(qtool_demo_chunk_bytes(junk, 0, 0x50414D53u, 0) == 0);
}

/* sRGB decoding and the median the tables use */
static void test_lin8_and_median(void **state)
{
    (void)state;
    assert_true(qtool_demo_lin8(0) == 0);
    assert_true(qtool_demo_lin8(255) > 0.999999 && qtool_demo_lin8(255) < 1.000001);
    assert_true(qtool_demo_lin8(10) < qtool_demo_lin8(11)); /* across the linear segment's end */
    double odd[5] = {5, 1, 4, 2, 3}, even[4] = {10, 1, 4, 2};
    assert_true(qtool_demo_median(odd, 5) == 3);
    assert_true(qtool_demo_median(even, 4) == 3);
}

/* the output directory: a file in its place is refused by name, a missing one is created */
static void test_check_out(void **state)
{
    (void)state;
    char base[] = "/tmp/qibl_demo_test_XXXXXX", path[256], err[512];
    assert_non_null(mkdtemp(base));
    snprintf(path, sizeof path, "%s/file", base);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fclose(f);
    err[0] = 0;
    assert_int_equal(qtool_demo_check_out(path, 2, err, sizeof err), -1);
    assert_non_null(strstr(err, "not a directory"));
    snprintf(path, sizeof path, "%s/out", base);
    assert_int_equal(qtool_demo_check_out(path, 2, err, sizeof err), 0);
    struct stat st;
    assert_int_equal(stat(path, &st), 0);
    assert_true(S_ISDIR(st.st_mode));
    /* a directory where a frame goes (lamp_01.png: the last name of 2 frames) */
    char frame[300];
    snprintf(frame, sizeof frame, "%s/lamp_01.png", path);
    assert_int_equal(mkdir(frame, 0777), 0);
    assert_int_equal(qtool_demo_check_out(path, 2, err, sizeof err), -1);
    assert_non_null(strstr(err, "lamp_01.png"));
    /* with one frame fewer the name is not an output: accepted */
    assert_int_equal(qtool_demo_check_out(path, 1, err, sizeof err), 0);
    rmdir(frame), rmdir(path);
    snprintf(path, sizeof path, "%s/file", base);
    unlink(path), rmdir(base);
}

/* parts per extended source outside 1..QTOOL_DEMO_MAX_PARTS: refused by name before any work */
static void test_probe_parts_refused(void **state)
{
    (void)state;
    qtool_demo_view v = {.w = 4, .h = 2, .threads = 1, .dir = "/nonexistent", .out = stdout};
    qtool_bake_sums sums;
    memset(&sums, 0, sizeof sums);
    char err[256];
    err[0] = 0;
    assert_int_equal(qtool_demo_probe(&v, 4, 0, &sums, 16, err, sizeof err), -1);
    assert_non_null(strstr(err, "parts per extended source"));
    err[0] = 0;
    assert_int_equal(qtool_demo_probe(&v, 4, QTOOL_DEMO_MAX_PARTS + 1, &sums, 16, err, sizeof err), -1);
    assert_non_null(strstr(err, "parts per extended source"));
}

/* The fixed-camera row on the courtyard at a tiny size (a 16 x 12 frame): its table and RESULT lines,
 * the light path well above the shadowed SH under the same suns (the panorama's ordering, from a
 * camera), camera_sheet.png written; an output directory that is gone is a failure with the name. */
#define CAMERA_ROW_PATH_MIN 28.0
static void test_camera_row(void **state)
{
    (void)state;
    qtool_rt_scene s;
    assert_int_equal(qtool_rt_scene_builtin(&s), 0);
    char base[] = "/tmp/qibl_demo_cam_XXXXXX", path[300], err[512], *buf = NULL;
    assert_non_null(mkdtemp(base));
    size_t len = 0;
    FILE *out = open_memstream(&buf, &len);
    assert_non_null(out);
    qtool_demo_view v = {.scene = &s, .w = 64, .h = 16, .threads = 2, .dir = base, .out = out};
    const qtool_demo_size *sz = qtool_demo_size_named("small");
    err[0] = 0;
    if (qtool_demo_camera(&v, 64, sz, err, sizeof err) != 0)
        fail_msg("%s", err);
    fclose(out);
    assert_non_null(strstr(buf, "16x12 perspective frame"));
    static const char ksh[] = "RESULT demo.camera_psnr_sh_k16 ", kpath[] = "RESULT demo.camera_psnr_path_k9 ";
    const char *a = strstr(buf, ksh), *b = strstr(buf, kpath);
    assert_non_null(a), assert_non_null(b);
    double sh = atof(a + strlen(ksh)), pth = atof(b + strlen(kpath));
    print_message("camera row at 16x12: shadowed SH %.2f dB, path %.2f dB (at least %.1f)\n", sh, pth,
                  CAMERA_ROW_PATH_MIN);
    assert_true(pth >= CAMERA_ROW_PATH_MIN && pth > sh + 5);
    free(buf);
    snprintf(path, sizeof path, "%s/camera_sheet.png", base);
    assert_int_equal(access(path, R_OK), 0);
    unlink(path), rmdir(base);
    /* the directory removed: the sheet cannot be written, and the error names it */
    out = fopen("/dev/null", "w");
    assert_non_null(out);
    v.out = out;
    err[0] = 0;
    assert_int_equal(qtool_demo_camera(&v, 16, sz, err, sizeof err), -1);
    fclose(out);
    assert_non_null(strstr(err, "camera_sheet.png"));
    qtool_rt_scene_free(&s);
}

/* The IES lamp row, run at the end of the light-path part on the courtyard at a tiny size: its
 * table and RESULT lines, the profile's lamp on the baked track at the 30 dB against the
 * ray-traced lamp of the same profile and well above the same frames with the profile ignored;
 * a position count outside 1..QTOOL_DEMO_MAX_IES_POS refused by name. */
#define IES_ROW_MIN_DB 30.0
static void test_ies_row(void **state)
{
    (void)state;
    qtool_rt_scene s;
    assert_int_equal(qtool_rt_scene_builtin(&s), 0);
    char base[] = "/tmp/qibl_demo_ies_XXXXXX", err[512], *buf = NULL;
    assert_non_null(mkdtemp(base));
    size_t len = 0;
    FILE *out = open_memstream(&buf, &len);
    assert_non_null(out);
    qtool_demo_view v = {.scene = &s, .w = 64, .h = 16, .threads = 2, .dir = base, .out = out};
    qtool_demo_size sz = *qtool_demo_size_named("small");
    sz.path_steps = 16, sz.sky_dirs = 16;
    qtool_bake_sums sums;
    assert_int_equal(qtool_bake_run(&s, v.w, v.h, v.kind, 64, 16, 0, 1, 2, 0, &sums), 0);
    qtool_gen_maps maps;
    uint8_t *today = NULL;
    size_t today_n = 0;
    assert_int_equal(qtool_bake_coeffs(&sums, 16, QTOOL_PROJ_QUADRATURE, &maps), 0);
    assert_int_equal(qtool_bake_asset(&maps, 32, &today, &today_n), 0);
    err[0] = 0;
    if (qtool_demo_paths(&v, 64, &sz, &sums, today, today_n, err, sizeof err) != 0)
        fail_msg("%s", err);
    fclose(out);
    static const char kg[] = "RESULT demo.ies_track_psnr ", ki[] = "RESULT demo.ies_track_isotropic_psnr ";
    const char *a = strstr(buf, kg), *b = strstr(buf, ki);
    assert_non_null(a), assert_non_null(b);
    assert_non_null(strstr(buf, "IES lamp on the lamp track"));
    double g = atof(a + strlen(kg)), iso = atof(b + strlen(ki));
    print_message("IES row at 64x16: profile %.2f dB, profile ignored %.2f dB (at least %.1f)\n", g, iso,
                  IES_ROW_MIN_DB);
    assert_true(g >= IES_ROW_MIN_DB && g > iso + 6);
    free(buf);
    /* the position count is checked before anything is read */
    out = fopen("/dev/null", "w");
    assert_non_null(out);
    v.out = out;
    qtool_bake_path track = {0};
    err[0] = 0;
    assert_int_equal(qtool_demo_ies(&v, today, today_n, 1, &track, 0, err, sizeof err), -1);
    assert_non_null(strstr(err, "IES positions"));
    assert_int_equal(qtool_demo_ies(&v, today, today_n, 1, &track, QTOOL_DEMO_MAX_IES_POS + 1, err, sizeof err), -1);
    fclose(out);
    free(today);
    qtool_gen_free(&maps);
    qtool_bake_sums_free(&sums);
    char cmd[400];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", base);
    assert_int_equal(system(cmd), 0);
    qtool_rt_scene_free(&s);
}

/* the near-field row checks its asset before the study: garbage is refused by name, nothing printed */
static void test_nearfield_refuses_asset(void **state)
{
    (void)state;
    qtool_rt_scene s;
    assert_int_equal(qtool_rt_scene_builtin(&s), 0);
    char *buf = NULL, err[512] = "";
    size_t len = 0;
    FILE *out = open_memstream(&buf, &len);
    assert_non_null(out);
    qtool_demo_view v = {.scene = &s, .w = 64, .h = 16, .threads = 1, .dir = "/tmp", .out = out};
    static const uint8_t junk[64] = {1, 2, 3};
    assert_int_equal(qtool_demo_nearfield(&v, qtool_demo_size_named("small"), junk, sizeof junk, err, sizeof err), -1);
    fclose(out);
    assert_non_null(strstr(err, "point maps and P map"));
    assert_int_equal(len, 0);
    free(buf);
    qtool_rt_scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sizes_named),        cmocka_unit_test(test_heat_scale),
        cmocka_unit_test(test_blit_in_place),      cmocka_unit_test(test_chunk_bytes_of_garbage),
        cmocka_unit_test(test_lin8_and_median),    cmocka_unit_test(test_check_out),
        cmocka_unit_test(test_probe_parts_refused), cmocka_unit_test(test_camera_row),
        cmocka_unit_test(test_ies_row),           cmocka_unit_test(test_nearfield_refuses_asset),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
