/*
 * obj_test.c - tools/io/obj.c: the face forms, negative indices, polygon triangulation, computed
 * normals, ignored statements, malformed files (one-line error naming file and line, nothing
 * returned), and the real meshes from ../shared/fixtures/meshes when present.
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

static int parse(const char *text, qibl_obj_mesh *m, char *err, size_t errlen)
{
    return qibl_obj_parse("t.obj", text, strlen(text), m, err, errlen);
}

static void test_quad_negative_indices_and_normals(void **state)
{
    (void)state;
    const char *text = "# a unit square in z = 0 as a quad, with a w coordinate and junk to ignore\r\n"
                       "mtllib x.mtl\no square\nv 0 0 0\nv 2 0 0 2\nv 1 1 0\nv 0 1 0\nvt 0 0\ns off\n"
                       "usemtl red\nf -4 -3 -2 -1\n";
    qibl_obj_mesh m;
    char err[256];
    assert_int_equal(parse(text, &m, err, sizeof err), 0);
    assert_int_equal(m.ntri, 2);
    assert_int_equal(m.nvert, 4);
    /* fan from the first corner: (0,1,2), (0,2,3); the w = 2 vertex divided out */
    assert_true(m.pos[3] == 1.0 && m.pos[4] == 0.0);
    assert_true(m.pos[9 + 3] == 1.0 && m.pos[9 + 4] == 1.0 && m.pos[9 + 6] == 0.0);
    for (int i = 0; i < 6; ++i) /* computed normals: +z (counter-clockwise) */
        assert_true(fabs(m.nrm[3 * i + 2] - 1.0) < 1e-12);
    qibl_obj_free(&m);
}

static void test_face_forms(void **state)
{
    (void)state;
    const char *text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 2\nvn 1 0 0\nvt 0 0\n"
                       "f 1/1/1 2/1/1 3/1/1\nf 1//2 2//2 3//2\nf 1/1 2/1 3/1\n";
    qibl_obj_mesh m;
    char err[256];
    assert_int_equal(parse(text, &m, err, sizeof err), 0);
    assert_int_equal(m.ntri, 3);
    assert_int_equal(m.nnormals_given, 2);
    assert_true(fabs(m.nrm[2] - 1.0) < 1e-12);      /* given normal, normalised */
    assert_true(fabs(m.nrm[9 + 0] - 1.0) < 1e-12);  /* the second given normal */
    assert_true(fabs(m.nrm[18 + 2] - 1.0) < 1e-12); /* computed */
    qibl_obj_free(&m);
}

static void test_smooth_normals_average(void **state)
{
    (void)state;
    /* two triangles folded 90 degrees along the x axis: the shared corners average the two normals */
    const char *text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\n";
    qibl_obj_mesh m;
    char err[256];
    assert_int_equal(parse(text, &m, err, sizeof err), 0);
    double s = sqrt(0.5);
    assert_true(fabs(m.nrm[0] - 0) < 1e-12 && fabs(m.nrm[1] - s) < 1e-12 && fabs(m.nrm[2] - s) < 1e-12);
    assert_true(fabs(m.nrm[6 + 2] - 1.0) < 1e-12); /* vertex 3 only in the first triangle */
    qibl_obj_free(&m);
}

static void test_malformed(void **state)
{
    (void)state;
    static const struct {
        const char *text, *needle;
    } bad[] = {
        {"", "no faces"},
        {"v 0 0 0\nv 1 0 0\n", "no faces"},
        {"v 0 0\n", ":1:"},
        {"v 0 0 0 1 5\n", ":1:"},
        {"v 0 0 x\n", ":1:"},
        {"v 0 0 0 0\n", "w = 0"},
        {"vn 0 0\n", ":1:"},
        {"v 0 0 0\nv 1 0 0\nf 1 2\n", "2 corners"},
        {"v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 4\n", "out of range"},
        {"v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 -4\n", "out of range"},
        {"v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 0\n", "out of range"},
        {"v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 a\n", "bad vertex index"},
        {"v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1//1 2//1 3//1\n", "normal index"},
        {"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 1 e99999 0\nf 1 2 3\n", ":4:"},
    };
    char err[256];
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        qibl_obj_mesh m;
        memset(&m, 0x5A, sizeof m);
        err[0] = '\0';
        assert_int_equal(parse(bad[i].text, &m, err, sizeof err), -1);
        assert_non_null(strstr(err, "t.obj"));
        if (!strstr(err, bad[i].needle))
            fail_msg("case %zu: '%s' lacks '%s'", i, err, bad[i].needle);
        assert_null(strchr(err, '\n'));
        assert_true(m.ntri == (size_t)0x5A5A5A5A5A5A5A5Au); /* nothing returned */
    }
    qibl_obj_mesh m;
    assert_int_equal(qibl_obj_read("/nonexistent/q.obj", &m, err, sizeof err), -1);
    assert_non_null(strstr(err, "/nonexistent/q.obj"));
}

static void test_real_meshes(void **state)
{
    (void)state;
    static const struct {
        const char *file;
        size_t ntri, nvert;
    } real[] = {{"spot_triangulated.obj", 5856, 2930}, {"teapot.obj", 6320, 3644}};
    for (size_t i = 0; i < 2; ++i) {
        char path[256], err[512];
        snprintf(path, sizeof path, "../shared/fixtures/meshes/%s", real[i].file);
        FILE *f = fopen(path, "rb");
        if (!f) {
            printf("SKIP obj real mesh %s: not present\n", path);
            continue;
        }
        fclose(f);
        qibl_obj_mesh m;
        if (qibl_obj_read(path, &m, err, sizeof err) != 0)
            fail_msg("%s", err);
        assert_int_equal(m.ntri, real[i].ntri);
        assert_int_equal(m.nvert, real[i].nvert);
        size_t zero = 0;
        for (size_t j = 0; j < m.ntri * 3; ++j) {
            double l = sqrt(m.nrm[3 * j] * m.nrm[3 * j] + m.nrm[3 * j + 1] * m.nrm[3 * j + 1] +
                            m.nrm[3 * j + 2] * m.nrm[3 * j + 2]);
            zero += l < 0.5;
            assert_true(l < 0.5 || fabs(l - 1) < 1e-9);
        }
        assert_true(zero == 0);
        qibl_obj_free(&m);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_quad_negative_indices_and_normals),
        cmocka_unit_test(test_face_forms),
        cmocka_unit_test(test_smooth_normals_average),
        cmocka_unit_test(test_malformed),
        cmocka_unit_test(test_real_meshes),
    };
    return cmocka_run_group_tests_name("obj", tests, NULL, NULL);
}
