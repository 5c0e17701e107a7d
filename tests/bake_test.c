/*
 * bake_test.c - tools/render and tools/bake on tiny sizes: the ray tracer's shadows and P map, the
 * bake's determinism across thread counts, shards merged == one run (bit for bit, also through the
 * sums file), the SH projection against the analytic (unshadowed) transfer of a lone plane, and the
 * asset the bake writes.
 */
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "bake/bake.h"
#include "io/obj.h"
#include "qibl/asset.h"
#include "ref/sh_ref.h"

static void test_determinism_threads_and_shards(void **state)
{
    (void)state;
    qibl_rt_scene s;
    assert_int_equal(qibl_rt_scene_builtin(&s), 0);
    qibl_bake_sums a, b, parts[3];
    assert_int_equal(qibl_bake_run(&s, 32, 8, QIBL_PANO_CYLINDRICAL, 64, 16, 0, 1, 1, 0, &a), 0);
    assert_int_equal(qibl_bake_run(&s, 32, 8, QIBL_PANO_CYLINDRICAL, 64, 16, 0, 1, 3, 0, &b), 0);
    size_t n = 32 * 8 * 3 * 16;
    assert_memory_equal(a.acc, b.acc, n * sizeof(int64_t));
    assert_memory_equal(a.pmap, b.pmap, 32 * 8 * 3 * sizeof(int32_t));
    char path[64], err[256];
    snprintf(path, sizeof path, "/tmp/qibl_bake_sums_%d", (int)getpid());
    for (uint32_t i = 0; i < 3; ++i) {
        qibl_bake_sums p;
        assert_int_equal(qibl_bake_run(&s, 32, 8, QIBL_PANO_CYLINDRICAL, 64, 16, i, 3, 2, 0, &p), 0);
        assert_int_equal(qibl_bake_sums_write(&p, path, err, sizeof err), 0);
        assert_int_equal(qibl_bake_sums_read(path, &parts[i], err, sizeof err), 0);
        assert_memory_equal(parts[i].acc, p.acc, n * sizeof(int64_t));
        qibl_bake_sums_free(&p);
    }
    assert_int_equal(qibl_bake_sums_add(&parts[2], &parts[0], err, sizeof err), 0);
    assert_int_equal(qibl_bake_sums_add(&parts[2], &parts[1], err, sizeof err), 0);
    assert_memory_equal(parts[2].acc, a.acc, n * sizeof(int64_t));
    /* assets byte-identical */
    qibl_gen_maps m1, m2;
    uint8_t *b1, *b2;
    size_t n1, n2;
    assert_int_equal(qibl_bake_coeffs(&a, 16, QIBL_PROJ_QUADRATURE, &m1), 0);
    assert_int_equal(qibl_bake_coeffs(&parts[2], 16, QIBL_PROJ_QUADRATURE, &m2), 0);
    assert_int_equal(qibl_bake_asset(&m1, 8, &b1, &n1), 0);
    assert_int_equal(qibl_bake_asset(&m2, 8, &b2, &n2), 0);
    assert_int_equal(n1, n2);
    assert_memory_equal(b1, b2, n1);
    qibl_asset_t as;
    assert_int_equal(qibl_asset_open(&as, b1, n1), QIBL_OK);
    /* a truncated or foreign sums file: error naming the file */
    FILE *f = fopen(path, "wb");
    fputs("QIBLSUM1 short", f);
    fclose(f);
    qibl_bake_sums bad;
    assert_int_equal(qibl_bake_sums_read(path, &bad, err, sizeof err), -1);
    assert_non_null(strstr(err, path));
    remove(path);
    free(b1), free(b2);
    qibl_gen_free(&m1), qibl_gen_free(&m2);
    for (int i = 0; i < 3; ++i)
        qibl_bake_sums_free(&parts[i]);
    qibl_bake_sums_free(&a), qibl_bake_sums_free(&b);
    qibl_rt_scene_free(&s);
}

/* A single ground plane (raw OBJ, nothing to shadow it): the bake's SH projection of
 * albedo/pi max(0, n.w) must match the analytic Funk-Hecke coefficients (quadrature and LSQ). */
static void test_projection_of_unshadowed_plane(void **state)
{
    (void)state;
    const char *text = "v -50 -50 -1\nv 50 -50 -1\nv 50 50 -1\nv -50 50 -1\nf 1 2 3 4\n";
    qibl_obj_mesh mesh;
    char err[256];
    assert_int_equal(qibl_obj_parse("plane.obj", text, strlen(text), &mesh, err, sizeof err), 0);
    qibl_rt_scene s;
    assert_int_equal(qibl_rt_scene_from_obj(&s, &mesh, 1, 1), 0);
    qibl_obj_free(&mesh);
    s.mats[1].ks = 0;
    qibl_bake_sums a;
    assert_int_equal(qibl_bake_run(&s, 16, 8, QIBL_PANO_EQUIRECT, 1024, 9, 0, 1, 2, 0, &a), 0);
    /* analytic: c_00 = albedo * sqrt(pi)/2 / pi... via a_l Y_l0(n): a_0 = 1, a_1 = 2/3, a_2 = 1/4 */
    double yn[25];
    qibl_ref_sh_eval(0, 0, 1, 3, yn);
    const double al[3] = {1.0, 2.0 / 3.0, 0.25};
    for (int method = 0; method < 2; ++method) {
        qibl_gen_maps m;
        assert_int_equal(qibl_bake_coeffs(&a, 9, (qibl_proj_method)method, &m), 0);
        size_t np = 16 * 8, p = 7 * 16 + 3; /* a pixel looking down */
        for (int i = 0; i < 9; ++i) {
            int l = i == 0 ? 0 : i < 4 ? 1 : 2;
            double want = s.mats[1].albedo[0] * al[l] * yn[i];
            double got = m.t[(size_t)i * 3 * np + p];
            if (fabs(got - want) > 4e-3)
                fail_msg("method %d, coefficient %d: %f, analytic %f", method, i, got, want);
        }
        qibl_gen_free(&m);
    }
    qibl_bake_sums_free(&a);
    qibl_rt_scene_free(&s);
}

static void test_shadow_and_pmap(void **state)
{
    (void)state;
    /* the ground under a floating square is shadowed from above, lit from the side */
    const char *text = "v -50 -50 -1\nv 50 -50 -1\nv 50 50 -1\nv -50 50 -1\nf 1 2 3 4\n"
                       "v -2 -2 1\nv 2 -2 1\nv 2 2 1\nv -2 2 1\nf 5 6 7 8\n";
    qibl_obj_mesh mesh;
    char err[256];
    assert_int_equal(qibl_obj_parse("t.obj", text, strlen(text), &mesh, err, sizeof err), 0);
    qibl_rt_scene s;
    assert_int_equal(qibl_rt_scene_from_obj(&s, &mesh, 1, 1), 0);
    qibl_obj_free(&mesh);
    double down[3] = {0.01, 0.0, -1.0}, up[3] = {0, 0, 1}, side[3] = {1, 0, 0.2}, df, gl;
    qibl_rt_hit h;
    qibl_rt_primary(&s, down, &h);
    assert_true(h.hit);
    assert_true(fabs(h.p[2] + 1.0) < 1e-9 && fabs(h.t - 1.0) < 1e-9);
    assert_int_equal(qibl_rt_response(&s, &h, up, 1e30, &df, &gl), 0);
    double l = sqrt(1.04);
    side[0] /= l, side[2] /= l;
    assert_int_equal(qibl_rt_response(&s, &h, side, 1e30, &df, &gl), 1);
    assert_true(fabs(df - side[2] / 3.14159265358979) < 1e-12);
    qibl_rt_scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_determinism_threads_and_shards),
        cmocka_unit_test(test_projection_of_unshadowed_plane),
        cmocka_unit_test(test_shadow_and_pmap),
    };
    return cmocka_run_group_tests_name("bake", tests, NULL, NULL);
}
