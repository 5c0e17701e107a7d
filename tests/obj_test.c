/*
 * obj_test.c - tools/io/obj.c: the face forms, negative indices, polygon triangulation, computed
 * normals, ignored statements, malformed files (one-line error naming file and line, nothing
 * returned), and the real meshes from ../shared/fixtures/meshes (skipped when absent). Hostile input
 * (tests/fileutil.h): zeros refused from the first bytes, directories, fifos and devices named,
 * empty and one-byte files, fan faces that would amplify memory, INT64_MIN indices, non-finite and
 * out-of-range coordinates named with the value and line.
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
#include "fileutil.h"

static int parse(const char *text, qtool_obj_mesh *m, char *err, size_t errlen)
{
    return qtool_obj_parse("t.obj", text, strlen(text), m, err, errlen);
}

/* a caller's triangle cap: the face that crosses it is refused on its line, the mesh untouched; a cap
 * above the reader's own is the reader's own */
static void test_caller_triangle_cap(void **state)
{
    (void)state;
    static const char text[] = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 2 0\nf 1 2 3 4 5\nf 1 2 3\n";
    qtool_obj_mesh m;
    char err[256];
    memset(&m, 0x5A, sizeof m);
    assert_int_equal(qtool_obj_parse_max("cap.obj", text, strlen(text), 3, &m, err, sizeof err), -1);
    assert_non_null(strstr(err, "cap.obj:7: more than 3 triangles (this command's limit)"));
    qtool_obj_mesh untouched;
    memset(&untouched, 0x5A, sizeof untouched);
    assert_memory_equal(&m, &untouched, sizeof m); /* a refusal leaves the mesh as it was */
    assert_int_equal(qtool_obj_parse_max("cap.obj", text, strlen(text), 4, &m, err, sizeof err), 0);
    assert_int_equal(m.ntri, 4);
    qtool_obj_free(&m);
    assert_int_equal(qtool_obj_parse_max("cap.obj", text, strlen(text), (size_t)-1, &m, err, sizeof err), 0);
    assert_int_equal(m.ntri, 4);
    qtool_obj_free(&m);
}

static void test_quad_negative_indices_and_normals(void **state)
{
    (void)state;
    const char *text = "# a unit square in z = 0 as a quad, with a w coordinate and junk to ignore\r\n"
                       "mtllib x.mtl\no square\nv 0 0 0\nv 2 0 0 2\nv 1 1 0\nv 0 1 0\nvt 0 0\ns off\n"
                       "usemtl red\nf -4 -3 -2 -1\n";
    qtool_obj_mesh m;
    char err[256];
    assert_int_equal(parse(text, &m, err, sizeof err), 0);
    assert_int_equal(m.ntri, 2);
    assert_int_equal(m.nvert, 4);
    /* fan from the first corner: (0,1,2), (0,2,3); the w = 2 vertex divided out */
    assert_true(m.pos[3] == 1.0 && m.pos[4] == 0.0);
    assert_true(m.pos[9 + 3] == 1.0 && m.pos[9 + 4] == 1.0 && m.pos[9 + 6] == 0.0);
    for (int i = 0; i < 6; ++i) /* computed normals: +z (counter-clockwise) */
        assert_true(fabs(m.nrm[3 * i + 2] - 1.0) < 1e-12);
    qtool_obj_free(&m);
}

static void test_face_forms(void **state)
{
    (void)state;
    const char *text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 2\nvn 1 0 0\nvt 0 0\n"
                       "f 1/1/1 2/1/1 3/1/1\nf 1//2 2//2 3//2\nf 1/1 2/1 3/1\n";
    qtool_obj_mesh m;
    char err[256];
    assert_int_equal(parse(text, &m, err, sizeof err), 0);
    assert_int_equal(m.ntri, 3);
    assert_int_equal(m.nnormals_given, 2);
    assert_true(fabs(m.nrm[2] - 1.0) < 1e-12);      /* given normal, normalised */
    assert_true(fabs(m.nrm[9 + 0] - 1.0) < 1e-12);  /* the second given normal */
    assert_true(fabs(m.nrm[18 + 2] - 1.0) < 1e-12); /* computed */
    qtool_obj_free(&m);
}

static void test_smooth_normals_average(void **state)
{
    (void)state;
    /* two triangles folded 90 degrees along the x axis: the shared corners average the two normals */
    const char *text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\n";
    qtool_obj_mesh m;
    char err[256];
    assert_int_equal(parse(text, &m, err, sizeof err), 0);
    double s = sqrt(0.5);
    assert_true(fabs(m.nrm[0] - 0) < 1e-12 && fabs(m.nrm[1] - s) < 1e-12 && fabs(m.nrm[2] - s) < 1e-12);
    assert_true(fabs(m.nrm[6 + 2] - 1.0) < 1e-12); /* vertex 3 only in the first triangle */
    qtool_obj_free(&m);
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
        qtool_obj_mesh m;
        memset(&m, 0x5A, sizeof m);
        err[0] = '\0';
        assert_int_equal(parse(bad[i].text, &m, err, sizeof err), -1);
        assert_non_null(strstr(err, "t.obj"));
        if (!strstr(err, bad[i].needle))
            fail_msg("case %zu: '%s' lacks '%s'", i, err, bad[i].needle);
        assert_null(strchr(err, '\n'));
        assert_true(m.ntri == (size_t)0x5A5A5A5A5A5A5A5Au); /* nothing returned */
    }
    qtool_obj_mesh m;
    assert_int_equal(qtool_obj_read("/nonexistent/q.obj", &m, err, sizeof err), -1);
    assert_non_null(strstr(err, "/nonexistent/q.obj"));
}

static void test_real_meshes(void **state)
{
    (void)state;
    static const struct {
        const char *file;
        size_t ntri, nvert;
    } real[] = {{"spot_triangulated.obj", 5856, 2930}, {"teapot.obj", 6320, 3644}};
    int missing = 0;
    for (size_t i = 0; i < 2; ++i) {
        char path[256], err[512];
        snprintf(path, sizeof path, "../shared/fixtures/meshes/%s", real[i].file);
        FILE *f = fopen(path, "rb");
        if (!f) {
            printf("obj: real mesh %s missing\n", path);
            ++missing;
            continue;
        }
        fclose(f);
        qtool_obj_mesh m;
        if (qtool_obj_read(path, &m, err, sizeof err) != 0)
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
        qtool_obj_free(&m);
    }
    if (missing)
        skip();
}

/* ---- hostile input ------------------------------------------------------------------------------ */

static int rd_obj(const char *path, char *err, size_t errlen)
{
    qtool_obj_mesh m;
    int rc = qtool_obj_read(path, &m, err, errlen);
    if (rc == 0)
        qtool_obj_free(&m);
    return rc;
}

/* first in the suite: it measures the peak memory */
static void test_zeros_refused_before_reading(void **state)
{
    (void)state;
    fu_check_zeros_not_read(rd_obj, (size_t)64 << 20, "binary data", QTOOL_OBJ_MAX_FILE_BYTES);
}

static void test_not_regular_files_named(void **state)
{
    (void)state;
    fu_check_not_regular(rd_obj);
}

static void test_empty_and_one_byte_files_named(void **state)
{
    (void)state;
    fu_check_empty_and_one_byte(rd_obj, '\n', "no faces");
}

static void parse_fails(const char *text, size_t len, const char *needle, const char *needle2)
{
    qtool_obj_mesh m;
    memset(&m, 0x5A, sizeof m);
    char err[256] = "";
    assert_int_equal(qtool_obj_parse("t.obj", text, len, &m, err, sizeof err), -1);
    assert_true(m.ntri == (size_t)0x5A5A5A5A5A5A5A5Au); /* nothing returned */
    assert_null(strchr(err, '\n'));
    if (!strstr(err, needle) || (needle2 && !strstr(err, needle2)))
        fail_msg("error '%s' does not mention '%s' and '%s'", err, needle, needle2 ? needle2 : "");
}

/* A face of 256 corners written with two-byte indices ("1 2 1 2 ...") fans into 254 triangles of
 * 144 output bytes each: ~70x the input, ~245x with the old parser's bookkeeping. More than one
 * triangle per QIBL_OBJ_MIN_BYTES_PER_TRIANGLE bytes of the whole input is refused, at the line of
 * the face that crosses it. */
static void test_fan_faces_bounded_by_input(void **state)
{
    (void)state;
    size_t lines = 64, cap = 64 + lines * (2 + 2 * QTOOL_OBJ_MAX_FACE_CORNERS + 1);
    char *t = malloc(cap);
    assert_non_null(t);
    size_t n = (size_t)snprintf(t, cap, "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    for (size_t l = 0; l < lines; ++l) {
        t[n++] = 'f';
        for (int c = 0; c < QTOOL_OBJ_MAX_FACE_CORNERS; ++c)
            t[n++] = ' ', t[n++] = (char)('1' + c % 3);
        t[n++] = '\n';
    }
    parse_fails(t, n, "QIBL_OBJ_MIN_BYTES_PER_TRIANGLE", "t.obj:");
    /* the same face once, after a realistic amount of text, is a valid (if degenerate) fan */
    qtool_obj_mesh m;
    char err[256];
    size_t one = (size_t)snprintf(t, cap, "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    t[one++] = 'f';
    for (int c = 0; c < QTOOL_OBJ_MAX_FACE_CORNERS; ++c)
        t[one++] = ' ', t[one++] = (char)('1' + c % 3);
    t[one++] = '\n';
    while (one < 4 * (QTOOL_OBJ_MAX_FACE_CORNERS - 2) + 16)
        one += (size_t)snprintf(t + one, cap - one, "# a comment line\n");
    if (qtool_obj_parse("t.obj", t, one, &m, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(m.ntri, QTOOL_OBJ_MAX_FACE_CORNERS - 2);
    qtool_obj_free(&m);
    free(t);
}

/* every 64-bit index is refused without overflow: INT64_MIN used to be negated (undefined
 * behaviour; make test-asan stops on it) */
static void test_extreme_indices_named(void **state)
{
    (void)state;
    static const char *idx[] = {"-9223372036854775808", "9223372036854775807", "-9223372036854775807",
                                "-4", "4", "99999999999999999999", "-99999999999999999999"};
    for (size_t i = 0; i < sizeof idx / sizeof idx[0]; ++i) {
        char text[256];
        int n = snprintf(text, sizeof text, "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 %s\n", idx[i]);
        parse_fails(text, (size_t)n, "t.obj:4:", i < 5 ? "out of range" : "bad vertex index");
        n = snprintf(text, sizeof text, "v 0 0 0\nv 1 0 0\nv 1 1 0\nvn 0 0 1\nf 1//1 2//1 3//%s\n", idx[i]);
        parse_fails(text, (size_t)n, "t.obj:5:", i < 5 ? "normal index" : "bad normal index");
    }
}

/* a coordinate that is not finite, or whose magnitude (after dividing by w) is above
 * QIBL_OBJ_MAX_COORD, is named with its value and line: `v 1e300 0 0 1e-300` (x / w = inf) used to
 * make the whole mesh vanish with success */
static void test_bad_coordinates_named(void **state)
{
    (void)state;
    static const struct {
        const char *v, *needle, *needle2;
    } bad[] = {
        {"v 1e300 0 0 1e-300", "x = inf", "after dividing by w"},
        {"v 0 1e300 0 1e-300", "y = inf", NULL},
        {"v 0 0 -1e300 1e-300", "z = -inf", NULL},
        {"v 1e16 0 0", "x = 1e+16", "QIBL_OBJ_MAX_COORD"},
        {"v 0 0 1 1e-16", "z = 1e+16", "after dividing by w"},
        {"v inf 0 0", "non-finite number 'inf'", NULL},
        {"v 0 nan 0", "non-finite number 'nan'", NULL},
        {"v 0 0 -INF", "non-finite number '-INF'", NULL},
        {"v 0 0 0 nan", "non-finite number 'nan'", NULL},
        {"v 1e999 0 0", "'1e999'", NULL}, /* strtod overflows to inf */
        {"vn 1e300 0 0", "normal coordinate x = 1e+300", NULL},
        {"vn 0 inf 0", "non-finite number 'inf'", NULL},
        {"v 0 0 0x", "bad number '0x'", NULL},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        char text[256];
        int n = snprintf(text, sizeof text, "v 0 0 0\nv 1 0 0\n%s\nv 0 1 0\nf 1 2 4\n", bad[i].v);
        parse_fails(text, (size_t)n, bad[i].needle, bad[i].needle2);
        parse_fails(text, (size_t)n, "t.obj:3:", NULL);
    }
    /* the limit itself, tiny values and underflow to zero are fine */
    const char *ok = "v 1e15 -1e15 1e-300\nv 1e-400 0 0\nv 0 1 0\nf 1 2 3\n";
    qtool_obj_mesh m;
    char err[256];
    if (qtool_obj_parse("t.obj", ok, strlen(ok), &m, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_true(m.pos[0] == 1e15 && m.pos[3] == 0.0);
    qtool_obj_free(&m);
}

/* a tiny but real triangle keeps a unit normal: its cross product (1e-320) squares to zero, so the
 * normal is taken after scaling; huge given normals too (found by the fuzzer's normal check) */
static void test_tiny_and_huge_normals_unit(void **state)
{
    (void)state;
    const char *text = "v 0 0 0\nv 1e-160 0 0\nv 0 1e-160 0\nvn 0 1e15 1e15\nvn 0 0 1e-200\n"
                       "f 1 2 3\nf 1//1 2//1 3//1\nf 1//2 2//2 3//2\n";
    qtool_obj_mesh m;
    char err[256];
    if (qtool_obj_parse("t.obj", text, strlen(text), &m, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(m.ntri, 3);
    double s = sqrt(0.5);
    for (int c = 0; c < 3; ++c) {
        const double *n0 = m.nrm + 3 * c, *n1 = m.nrm + 9 + 3 * c, *n2 = m.nrm + 18 + 3 * c;
        assert_true(n0[0] == 0.0 && n0[1] == 0.0 && fabs(n0[2] - 1.0) < 1e-15);
        assert_true(n1[0] == 0.0 && fabs(n1[1] - s) < 1e-15 && fabs(n1[2] - s) < 1e-15);
        assert_true(n2[0] == 0.0 && n2[1] == 0.0 && n2[2] == 1.0);
    }
    qtool_obj_free(&m);
}

/* ---- materials: mtllib, usemtl, Kd, map_Kd, vt ------------------------------------------------- */

#include "io/png.h"

static void put(const char *dir, const char *name, const char *text)
{
    char p[256];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    fu_write(p, text, strlen(text));
}

static int read_in(const char *dir, const char *name, qtool_obj_mesh *m, char *err, size_t errlen)
{
    char p[256];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    return qtool_obj_read_materials(p, QTOOL_OBJ_MAX_TRIANGLES, m, err, errlen);
}

/* two materials, one textured; faces before any usemtl get QTOOL_OBJ_DEFAULT_KD; vt stored as
 * (u, 1 - v); a textured material's face without vt keeps its Kd and no texture */
static void test_materials(void **state)
{
    (void)state;
    char dir[64], err[512], p[256];
    fu_tmpdir(dir);
    uint8_t px[12] = {10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 110, 120};
    snprintf(p, sizeof p, "%s/wood.png", dir);
    assert_int_equal(qtool_png_write_rgb8(p, 2, 2, px, err, sizeof err), 0);
    put(dir, "m.mtl", "# two\nnewmtl red\nKd 0.9 0.1 0.2\nKs 1 1 1\nnewmtl wood\r\nKd 1 1 0.5\nmap_Kd -s 1 1 1 wood.png\n");
    put(dir, "a.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25 0.25\nvt 1 0\nvt 0 1\n"
                      "f 1 2 3\nusemtl red\nf 1 2 3\nusemtl wood\nf 1/1 2/2 3/3\nf 1 2 3\n");
    qtool_obj_mesh m;
    if (read_in(dir, "a.obj", &m, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(m.ntri, 4);
    assert_non_null(m.albedo);
    static const double kd[4][3] = {{0.8, 0.8, 0.8}, {0.9, 0.1, 0.2}, {1, 1, 0.5}, {1, 1, 0.5}};
    for (int t = 0; t < 4; ++t)
        for (int j = 0; j < 3; ++j)
            assert_true(m.albedo[3 * t + j] == kd[t][j]);
    assert_non_null(m.tex);
    assert_int_equal(m.ntex, 1);
    assert_true(m.tex[0] == -1 && m.tex[1] == -1 && m.tex[2] == 0 && m.tex[3] == -1);
    static const double uv[6] = {0.25, 0.75, 1, 1, 0, 0};
    for (int i = 0; i < 6; ++i)
        assert_true(m.uv[12 + i] == uv[i]);
    assert_true(m.texs[0].w == 2 && m.texs[0].h == 2);
    assert_memory_equal(m.texs[0].rgb, px, 12);
    qtool_obj_free(&m);
    /* no usemtl: no materials at all, the renderer's default colour */
    put(dir, "b.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    assert_int_equal(read_in(dir, "b.obj", &m, err, sizeof err), 0);
    assert_null(m.albedo);
    assert_null(m.tex);
    qtool_obj_free(&m);
    /* the geometry-only reader (transfer's) ignores them too: no materials, nothing else read */
    char ap[256];
    snprintf(ap, sizeof ap, "%s/a.obj", dir);
    assert_int_equal(qtool_obj_read(ap, &m, err, sizeof err), 0);
    assert_true(m.ntri == 4 && !m.albedo && !m.tex);
    qtool_obj_free(&m);
    /* the in-memory parser without a folder ignores mtllib and usemtl, as before */
    const char *t = "mtllib nothere.mtl\nusemtl nothing\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    assert_int_equal(qtool_obj_parse("t.obj", t, strlen(t), &m, err, sizeof err), 0);
    assert_null(m.albedo);
    qtool_obj_free(&m);
    /* refusals, each named with the file and line */
    static const char *const bad[][3] = {
        {"mtllib nothere.mtl\n", NULL, "c.obj:1: mtllib:"},
        {"mtllib ../m.mtl\n", NULL, "c.obj:1: mtllib '../m.mtl': a '..'"},
        {"mtllib /etc/passwd\n", NULL, "an absolute path"},
        {"mtllib m.mtl\nusemtl blue\n", NULL, "c.obj:2: usemtl 'blue': no such material"},
        {"mtllib x.mtl\n", "newmtl a\nKd 1.5 0 0\n", "x.mtl:2: Kd r = 1.5 out of range (0..1)"},
        {"mtllib x.mtl\n", "Kd 1 0 0\n", "x.mtl:1: 'Kd' before any newmtl"},
        {"mtllib x.mtl\n", "newmtl a\nmap_Kd /etc/passwd\n", "x.mtl:2: map_Kd '/etc/passwd': an absolute path"},
        {"mtllib x.mtl\n", "newmtl a\nmap_Kd missing.png\n", "x.mtl:2: map_Kd:"},
        {"mtllib x.mtl\n", "newmtl a\nmap_Kd m.mtl\n", "x.mtl:2: map_Kd:"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n", NULL, "c.obj:5: texture index 2 out of range (1 vt so far)"},
        {"vt\n", NULL, "c.obj:1: 'vt' needs 1 to 3 numbers"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        if (bad[i][1])
            put(dir, "x.mtl", bad[i][1]);
        char text[256];
        snprintf(text, sizeof text, "%sv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", bad[i][0]);
        put(dir, "c.obj", text);
        memset(&m, 0x5A, sizeof m);
        qtool_obj_mesh before = m;
        assert_int_equal(read_in(dir, "c.obj", &m, err, sizeof err), -1);
        if (!strstr(err, bad[i][2]))
            fail_msg("case %zu: '%s' lacks '%s'", i, err, bad[i][2]);
        assert_null(strchr(err, '\n'));
        assert_memory_equal(&m, &before, sizeof m);
    }
    static const char *const files[] = {"wood.png", "m.mtl", "a.obj", "b.obj", "c.obj", "x.mtl"};
    for (size_t i = 0; i < 6; ++i) {
        snprintf(p, sizeof p, "%s/%s", dir, files[i]);
        remove(p);
    }
    rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_zeros_refused_before_reading),
        cmocka_unit_test(test_caller_triangle_cap),
        cmocka_unit_test(test_not_regular_files_named),
        cmocka_unit_test(test_empty_and_one_byte_files_named),
        cmocka_unit_test(test_fan_faces_bounded_by_input),
        cmocka_unit_test(test_extreme_indices_named),
        cmocka_unit_test(test_bad_coordinates_named),
        cmocka_unit_test(test_tiny_and_huge_normals_unit),
        cmocka_unit_test(test_quad_negative_indices_and_normals),
        cmocka_unit_test(test_face_forms),
        cmocka_unit_test(test_smooth_normals_average),
        cmocka_unit_test(test_malformed),
        cmocka_unit_test(test_real_meshes),
        cmocka_unit_test(test_materials),
    };
    return cmocka_run_group_tests_name("obj", tests, NULL, NULL);
}
