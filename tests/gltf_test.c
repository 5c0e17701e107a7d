/*
 * gltf_test.c - tools/io/gltf.c: Khronos sample models (fixtures/gltf, see SOURCES.md) checked
 * against the numbers in the files themselves (accessor min/max, counts, node transforms composed
 * by hand here); synthetic files for every index component type, non-indexed, strips and fans,
 * interleaved strides, normalized accessors, TRS hierarchies with a mirror, GLB, external .bin and
 * PNG textures; and hostile files, each refused with its named one-line error, nothing returned.
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

#include "io/gltf.h"
#include "io/mesh.h"
#include "io/png.h"
#include "fileutil.h"
#include "qibl/asset.h" /* qibl_crc32 */

#ifndef QIBL_SOURCE_DIR
#define QIBL_SOURCE_DIR "."
#endif

static int read_fixture(const char *name, qtool_gltf_scene *s, char *err, size_t errlen)
{
    char path[512];
    snprintf(path, sizeof path, "%s/fixtures/gltf/%s", QIBL_SOURCE_DIR, name);
    if (access(path, R_OK) != 0) {
        print_message("skip: %s absent (suites run from the source root)\n", path);
        skip();
    }
    return qtool_gltf_read(path, QTOOL_GLTF_MAX_TRIANGLES, s, err, errlen);
}

static void bounds(const qtool_obj_mesh *m, double lo[3], double hi[3])
{
    for (int j = 0; j < 3; ++j)
        lo[j] = 1e300, hi[j] = -1e300;
    for (size_t i = 0; i < 3 * m->ntri; ++i)
        for (int j = 0; j < 3; ++j)
            lo[j] = fmin(lo[j], m->pos[3 * i + j]), hi[j] = fmax(hi[j], m->pos[3 * i + j]);
}

static void flat(const double *p, double n[3])
{
    double e1[3], e2[3];
    for (int j = 0; j < 3; ++j)
        e1[j] = p[3 + j] - p[j], e2[j] = p[6 + j] - p[j];
    n[0] = e1[1] * e2[2] - e1[2] * e2[1], n[1] = e1[2] * e2[0] - e1[0] * e2[2], n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int j = 0; j < 3; ++j)
        n[j] /= l;
}

/* Box: 36 indices -> 12 triangles, 24 vertices; POSITION min/max +-0.5; the root's matrix turns
 * (x, y, z) into (x, -z, y)... (columns (1,0,0), (0,0,-1), (0,1,0)), so bounds stay +-0.5; every
 * given NORMAL, transformed, must equal the face normal of the transformed, CCW triangle; material
 * baseColorFactor (0.8, 0, 0) */
static void test_box(void **state)
{
    (void)state;
    qtool_gltf_scene s;
    char err[512];
    if (read_fixture("Box.gltf", &s, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(s.mesh.ntri, 12);
    assert_int_equal(s.mesh.nvert, 24);
    assert_int_equal(s.mesh.nnormals_given, 24);
    double lo[3], hi[3];
    bounds(&s.mesh, lo, hi);
    for (int j = 0; j < 3; ++j)
        assert_true(lo[j] == -0.5 && hi[j] == 0.5);
    for (size_t t = 0; t < 12; ++t) {
        double fn[3];
        flat(s.mesh.pos + 9 * t, fn);
        for (int q = 0; q < 3; ++q)
            for (int j = 0; j < 3; ++j)
                assert_true(fabs(s.mesh.nrm[9 * t + 3 * q + j] - fn[j]) < 1e-12);
    }
    /* the +z face of the mesh (normal (0,0,1) in the file) is the world's +y face after the root matrix */
    int up = 0;
    for (size_t t = 0; t < 12; ++t)
        up += s.mesh.nrm[9 * t + 1] == 1.0 && s.mesh.pos[9 * t + 1] == 0.5;
    assert_int_equal(up, 2);
    assert_non_null(s.mesh.albedo);
    assert_null(s.mesh.tex);
    for (size_t t = 0; t < 12; ++t)
        assert_true(s.mesh.albedo[3 * t] == (double)0.800000011920929 && s.mesh.albedo[3 * t + 1] == 0 &&
                    s.mesh.albedo[3 * t + 2] == 0);
    assert_int_equal(s.ncam, 0);
    qtool_gltf_free(&s);
}

static void test_triangle(void **state)
{
    (void)state;
    qtool_gltf_scene s;
    char err[512];
    if (read_fixture("Triangle.gltf", &s, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(s.mesh.ntri, 1);
    static const double want[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    for (int i = 0; i < 9; ++i)
        assert_true(s.mesh.pos[i] == want[i]);
    for (int q = 0; q < 3; ++q) /* no NORMAL: flat normals, +z for this CCW triangle */
        assert_true(s.mesh.nrm[3 * q] == 0 && s.mesh.nrm[3 * q + 1] == 0 && s.mesh.nrm[3 * q + 2] == 1);
    assert_null(s.mesh.albedo); /* no material: the renderer's default */
    qtool_gltf_free(&s);
}

/* Cameras: the square (0..1, 0..1, 0) under rotation (-0.383, 0, 0, 0.92375), a perspective camera
 * (yfov 0.7, aspect 1, znear 0.01) and an orthographic one (xmag = ymag = 1), both at (0.5, 0.5, 3) */
static void test_cameras(void **state)
{
    (void)state;
    qtool_gltf_scene s;
    char err[512];
    if (read_fixture("Cameras.gltf", &s, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(s.mesh.ntri, 2);
    /* a rotation about x by the unit quaternion (x, 0, 0, w): (0, 1, 0) -> (0, 1 - 2x^2, 2xw) */
    double l = sqrt(0.383 * 0.383 + 0.92375 * 0.92375), x = -0.383 / l, w = 0.92375 / l;
    double y1[3] = {0, 1 - 2 * x * x, 2 * x * w};
    double lo[3], hi[3];
    bounds(&s.mesh, lo, hi);
    assert_true(fabs(lo[0]) < 1e-12 && fabs(hi[0] - 1) < 1e-12);
    assert_true(fabs(lo[1]) < 1e-12 && fabs(hi[1] - y1[1]) < 1e-12);
    assert_true(fabs(hi[2]) < 1e-12 && fabs(lo[2] - y1[2]) < 1e-12); /* z goes down to 2xw < 0 */
    assert_int_equal(s.ncam, 2);
    assert_int_equal(s.cams[0].perspective, 1);
    assert_true(s.cams[0].yfov == 0.7 && s.cams[0].aspect == 1.0 && s.cams[0].znear == 0.01 && s.cams[0].zfar == 100);
    assert_int_equal(s.cams[0].node, 1);
    assert_int_equal(s.cams[1].perspective, 0);
    assert_true(s.cams[1].xmag == 1.0 && s.cams[1].ymag == 1.0);
    for (int c = 0; c < 2; ++c) {
        assert_true(s.cams[c].eye[0] == 0.5 && s.cams[c].eye[1] == 0.5 && s.cams[c].eye[2] == 3.0);
        assert_true(s.cams[c].fwd[0] == 0 && s.cams[c].fwd[1] == 0 && s.cams[c].fwd[2] == -1);
        assert_true(s.cams[c].up[0] == 0 && s.cams[c].up[1] == 1 && s.cams[c].up[2] == 0);
    }
    qtool_gltf_free(&s);
}

/* SimpleSparseAccessor: 14 vertices (a 7 x 2 grid, x 0..6, y 0..1), 36 indices -> 12 triangles; the
 * sparse part moves vertices 8, 10 and 12 to (1, 2, 0), (3, 3, 0), (5, 4, 0): POSITION max (6, 4, 0) */
static void test_sparse_accessor(void **state)
{
    (void)state;
    qtool_gltf_scene s;
    char err[512];
    if (read_fixture("SimpleSparseAccessor.gltf", &s, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(s.mesh.ntri, 12);
    double lo[3], hi[3];
    bounds(&s.mesh, lo, hi);
    assert_true(lo[0] == 0 && lo[1] == 0 && lo[2] == 0 && hi[0] == 6 && hi[1] == 4 && hi[2] == 0);
    /* triangle 0 is indices (0, 8, 7): its second corner is the moved vertex 8 */
    assert_true(s.mesh.pos[3] == 1 && s.mesh.pos[4] == 2 && s.mesh.pos[5] == 0);
    qtool_gltf_free(&s);
}

static int read_fixture_at(const char *name, double t, qtool_gltf_scene *s, char *err, size_t errlen)
{
    char path[512];
    snprintf(path, sizeof path, "%s/fixtures/gltf/%s", QIBL_SOURCE_DIR, name);
    if (access(path, R_OK) != 0) {
        print_message("skip: %s absent (suites run from the source root)\n", path);
        skip();
    }
    return qtool_gltf_read_at(path, QTOOL_GLTF_MAX_TRIANGLES, t, s, err, errlen);
}

/* AnimatedTriangle: the triangle (0,0,0) (1,0,0) (0,1,0) turned about z by animation 0, keys at
 * 0, 0.25, 0.5, 0.75, 1 s with rotations 0, 90, 180, 270, 360 degrees (LINEAR: slerp) */
static void test_animation(void **state)
{
    (void)state;
    qtool_gltf_scene s;
    char err[512];
    static const double ts[] = {-1, 0.25, 0.125, 0.6, 7.0};
    static const double deg[] = {0, 90, 45, 216, 0}; /* 7 s is clamped to the last key */
    for (int k = 0; k < 5; ++k) {
        if (read_fixture_at("AnimatedTriangle.gltf", ts[k], &s, err, sizeof err) != 0)
            fail_msg("%s", err);
        assert_int_equal(s.has_anim, 1);
        assert_true(s.anim_start == 0 && s.anim_end == 1);
        double a = deg[k] * 3.14159265358979323846 / 180, c = cos(a), sn = sin(a);
        double want[9] = {0, 0, 0, c, sn, 0, -sn, c, 0};
        for (int i = 0; i < 9; ++i)
            if (fabs(s.mesh.pos[i] - want[i]) > 1e-6)
                fail_msg("t = %g: corner coordinate %d is %.9f, want %.9f", ts[k], i, s.mesh.pos[i], want[i]);
        qtool_gltf_free(&s);
    }
}

/* io/mesh.h: "FILE.gltf@T" is the file's animation at T seconds (the frames of `qibl transfer`) */
static void test_mesh_read_at_time(void **state)
{
    (void)state;
    char path[512], err[512];
    snprintf(path, sizeof path, "%s/fixtures/gltf/AnimatedTriangle.gltf", QIBL_SOURCE_DIR);
    if (access(path, R_OK) != 0)
        skip();
    strcat(path, "@0.25");
    qtool_obj_mesh m;
    assert_int_equal(qtool_mesh_is_gltf_name(path), 1);
    if (qtool_mesh_read_max(path, 100, &m, NULL, NULL, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_true(fabs(m.pos[3]) < 1e-6 && fabs(m.pos[4] - 1) < 1e-6); /* (1, 0, 0) turned to (0, 1, 0) */
    qtool_obj_free(&m);
    /* not a time: the whole name is the path, refused as a missing file */
    snprintf(path, sizeof path, "%s/fixtures/gltf/AnimatedTriangle.gltf@later", QIBL_SOURCE_DIR);
    assert_int_equal(qtool_mesh_read_max(path, 100, &m, NULL, NULL, err, sizeof err), -1);
    assert_non_null(strstr(err, "AnimatedTriangle.gltf@later"));
}

/* SimpleSkin: a strip of 10 vertices (x = -0.5, 0.5; y = 0, 0.5 ... 2), joints node 1 (at y = 1)
 * and its child node 2, both inverse bind matrices T(0, -1, 0); weights (1, 0), (0.75, 0.25),
 * (0.5, 0.5), (0.25, 0.75), (0, 1) up the strip. At rest the mesh is as given; at t = 1 s node 2
 * is turned 90 degrees about z (key 2, (0, 0, 0.707, 0.707)), so a vertex v moves to
 * sum w_j J_j v with J_0 = I and J_1 = T(0,1,0) R T(0,-1,0), composed here by hand. */
static void test_skin(void **state)
{
    (void)state;
    qtool_gltf_scene s;
    char err[512];
    for (int k = 0; k < 2; ++k) {
        if (read_fixture_at("SimpleSkin.gltf", k ? 1.0 : -1.0, &s, err, sizeof err) != 0)
            fail_msg("%s", err);
        assert_int_equal(s.mesh.ntri, 8);
        assert_true(s.anim_start == 0 && s.anim_end == 5.5);
        /* triangle 7 is indices (6, 9, 8): vertices (-0.5, 1.5), (0.5, 2), (-0.5, 2) */
        static const double v[3][2] = {{-0.5, 1.5}, {0.5, 2.0}, {-0.5, 2.0}};
        static const double w1[3] = {0.75, 1.0, 1.0};
        for (int q = 0; q < 3; ++q) {
            double x = v[q][0], y = v[q][1];
            /* J_1 v: down by 1, turn 90 degrees ((x, y) -> (-y, x)), up by 1 */
            double rx = k ? -(y - 1) : x, ry = k ? x + 1 : y;
            double wx = (1 - w1[q]) * x + w1[q] * rx, wy = (1 - w1[q]) * y + w1[q] * ry;
            const double *p = s.mesh.pos + 9 * 7 + 3 * q;
            if (fabs(p[0] - wx) > 1e-6 || fabs(p[1] - wy) > 1e-6 || p[2] != 0)
                fail_msg("t %d: corner %d at (%g, %g, %g), want (%g, %g, 0)", k, q, p[0], p[1], p[2], wx, wy);
        }
        qtool_gltf_free(&s);
    }
}

/* ---- synthetic files ------------------------------------------------------------------------------ */

static void b64enc(const uint8_t *b, size_t n, char *out)
{
    static const char a[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    size_t o = 0;
    for (size_t i = 0; i < n; i += 3) {
        uint32_t v = (uint32_t)b[i] << 16 | (i + 1 < n ? (uint32_t)b[i + 1] << 8 : 0) | (i + 2 < n ? b[i + 2] : 0);
        out[o++] = a[v >> 18 & 63], out[o++] = a[v >> 12 & 63];
        out[o++] = i + 1 < n ? a[v >> 6 & 63] : '=';
        out[o++] = i + 2 < n ? a[v & 63] : '=';
    }
    out[o] = '\0';
}

static void putf(uint8_t *p, float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    p[0] = (uint8_t)u, p[1] = (uint8_t)(u >> 8), p[2] = (uint8_t)(u >> 16), p[3] = (uint8_t)(u >> 24);
}

/* a file of one buffer (data: URI of bin) and the JSON body given (without "buffers" and "asset") */
static int parse_json(const char *body, const uint8_t *bin, size_t n, qtool_gltf_scene *s, char *err, size_t errlen)
{
    static char text[1 << 16];
    char b64[8192];
    b64enc(bin, n, b64);
    snprintf(text, sizeof text,
             "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":%zu,"
             "\"uri\":\"data:application/octet-stream;base64,%s\"}],%s}",
             n, b64, body);
    return qtool_gltf_parse("t.gltf", NULL, (const uint8_t *)text, strlen(text), QTOOL_GLTF_MAX_TRIANGLES, s, err,
                            errlen);
}

/* four vertices of the unit square at offset 0 (48 bytes), then indices at 48 */
static size_t square_bin(uint8_t *b, int ctype, const unsigned *idx, int nidx)
{
    static const float v[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    memset(b, 0, 256);
    for (int i = 0; i < 12; ++i)
        putf(b + 4 * i, v[i]);
    size_t o = 48;
    int cs = ctype == 5121 ? 1 : ctype == 5123 ? 2 : 4;
    for (int i = 0; i < nidx; ++i)
        for (int k = 0; k < cs; ++k)
            b[o++] = (uint8_t)(idx[i] >> (8 * k));
    return (o + 3) & ~(size_t)3;
}

static void check_square(const qtool_gltf_scene *s, size_t ntri)
{
    assert_int_equal(s->mesh.ntri, ntri);
    for (size_t t = 0; t < ntri; ++t) {
        double fn[3];
        flat(s->mesh.pos + 9 * t, fn);
        assert_true(fabs(fn[2] - 1) < 1e-12); /* every triangle CCW seen from +z */
    }
}

/* every index component type: the same square, two triangles */
static void test_index_types(void **state)
{
    (void)state;
    static const int ct[3] = {5121, 5123, 5125};
    static const unsigned idx[6] = {0, 1, 2, 0, 2, 3};
    for (int k = 0; k < 3; ++k) {
        uint8_t bin[256];
        size_t n = square_bin(bin, ct[k], idx, 6);
        char body[1024];
        snprintf(body, sizeof body,
                 "\"bufferViews\":[{\"buffer\":0,\"byteLength\":48},{\"buffer\":0,\"byteOffset\":48,\"byteLength\":%zu}],"
                 "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\"},"
                 "{\"bufferView\":1,\"componentType\":%d,\"count\":6,\"type\":\"SCALAR\"}],"
                 "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}],"
                 "\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}]",
                 n - 48, ct[k]);
        qtool_gltf_scene s;
        char err[512];
        if (parse_json(body, bin, n, &s, err, sizeof err) != 0)
            fail_msg("%d: %s", ct[k], err);
        check_square(&s, 2);
        assert_true(s.mesh.pos[9 + 3] == 1 && s.mesh.pos[9 + 4] == 1); /* triangle 1 corner 1 is vertex 2 */
        qtool_gltf_free(&s);
    }
}

/* TRIANGLE_STRIP (0 1 3 2) and TRIANGLE_FAN (0 1 2 3) both give the square, CCW; a non-indexed
 * TRIANGLES of 6 vertices */
static void test_strip_fan_nonindexed(void **state)
{
    (void)state;
    static const unsigned strip[4] = {0, 1, 3, 2}, fan[4] = {0, 1, 2, 3};
    for (int k = 0; k < 2; ++k) {
        uint8_t bin[256];
        size_t n = square_bin(bin, 5123, k ? fan : strip, 4);
        char body[1024];
        snprintf(body, sizeof body,
                 "\"bufferViews\":[{\"buffer\":0,\"byteLength\":48},{\"buffer\":0,\"byteOffset\":48,\"byteLength\":8}],"
                 "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\"},"
                 "{\"bufferView\":1,\"componentType\":5123,\"count\":4,\"type\":\"SCALAR\"}],"
                 "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1,\"mode\":%d}]}],"
                 "\"nodes\":[{\"mesh\":0}]",
                 k ? 6 : 5);
        qtool_gltf_scene s;
        char err[512];
        if (parse_json(body, bin, n, &s, err, sizeof err) != 0)
            fail_msg("%s", err);
        check_square(&s, 2);
        qtool_gltf_free(&s);
    }
    /* non-indexed: 6 vertices, interleaved with a 2-float pad per vertex (byteStride 20) */
    static const float v[18] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 0, 0, 1, 1, 0, 0, 1, 0};
    uint8_t bin[120];
    memset(bin, 0xFF, sizeof bin); /* the pads hold NaNs: they must never be read */
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 3; ++j)
            putf(bin + 20 * i + 4 * j, v[3 * i + j]);
    const char *body = "\"bufferViews\":[{\"buffer\":0,\"byteLength\":120,\"byteStride\":20}],"
                       "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":6,\"type\":\"VEC3\"}],"
                       "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}},{\"attributes\":{\"POSITION\":0},\"mode\":1}]}],"
                       "\"nodes\":[{\"mesh\":0}]";
    qtool_gltf_scene s;
    char err[512];
    if (parse_json(body, bin, sizeof bin, &s, err, sizeof err) != 0)
        fail_msg("%s", err);
    check_square(&s, 2); /* the LINES primitive adds nothing */
    qtool_gltf_free(&s);
}

/* COLOR_0 (normalized UNSIGNED_BYTE VEC4) times baseColorFactor, averaged over each triangle */
static void test_vertex_colours(void **state)
{
    (void)state;
    uint8_t bin[64] = {0};
    static const float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    for (int i = 0; i < 9; ++i)
        putf(bin + 4 * i, v[i]);
    static const uint8_t col[12] = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255};
    memcpy(bin + 36, col, 12);
    const char *body = "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36},{\"buffer\":0,\"byteOffset\":36,\"byteLength\":12}],"
                       "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"},"
                       "{\"bufferView\":1,\"componentType\":5121,\"normalized\":true,\"count\":3,\"type\":\"VEC4\"}],"
                       "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.5,1,1,1]}}],"
                       "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"COLOR_0\":1},\"material\":0}]}],"
                       "\"nodes\":[{\"mesh\":0}]";
    qtool_gltf_scene s;
    char err[512];
    if (parse_json(body, bin, 48, &s, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_non_null(s.mesh.albedo);
    assert_true(fabs(s.mesh.albedo[0] - 0.5 / 3) < 1e-12 && fabs(s.mesh.albedo[1] - 1.0 / 3) < 1e-12 &&
                fabs(s.mesh.albedo[2] - 1.0 / 3) < 1e-12);
    qtool_gltf_free(&s);
}

/* A TRS hierarchy: root T(10,0,0) R(90 deg about z) S(2,2,2) -> child T(0,1,0) with a mirror S(-1,1,1).
 * The triangle (0,0,0) (1,0,0) (0,1,0) composed by hand: child: (x, y, z) -> (-x, y + 1, z); root:
 * (x, y, z) -> (10 - 2y, 2x, 2z). The mirror flips the winding back to CCW (normal +z). Normalized
 * UNSIGNED_SHORT positions (65535 = 1). */
static void test_trs_hierarchy_mirror_normalized(void **state)
{
    (void)state;
    uint8_t bin[20] = {0};
    static const uint16_t p[9] = {0, 0, 0, 65535, 0, 0, 0, 65535, 0};
    for (int i = 0; i < 9; ++i)
        bin[2 * i] = (uint8_t)p[i], bin[2 * i + 1] = (uint8_t)(p[i] >> 8);
    double s2 = sqrt(0.5);
    char body[1024];
    snprintf(body, sizeof body,
             "\"bufferViews\":[{\"buffer\":0,\"byteLength\":20}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5123,\"normalized\":true,\"count\":3,\"type\":\"VEC3\"}],"
             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],"
             "\"nodes\":[{\"children\":[1],\"translation\":[10,0,0],\"rotation\":[0,0,%.17g,%.17g],\"scale\":[2,2,2]},"
             "{\"mesh\":0,\"translation\":[0,1,0],\"scale\":[-1,1,1]}],\"scene\":0,\"scenes\":[{\"nodes\":[0]}]",
             s2, s2);
    qtool_gltf_scene s;
    char err[512];
    if (parse_json(body, bin, sizeof bin, &s, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(s.mesh.ntri, 1);
    double c[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, want[3][3];
    for (int q = 0; q < 3; ++q) {
        double x = -c[q][0], y = c[q][1] + 1, z = c[q][2];
        want[q][0] = 10 - 2 * y, want[q][1] = 2 * x, want[q][2] = 2 * z;
    }
    /* the winding is reversed: corners 0, 2, 1 */
    static const int order[3] = {0, 2, 1};
    for (int q = 0; q < 3; ++q)
        for (int j = 0; j < 3; ++j)
            assert_true(fabs(s.mesh.pos[3 * q + j] - want[order[q]][j]) < 1e-12);
    double fn[3];
    flat(s.mesh.pos, fn);
    assert_true(fabs(fn[2] - 1) < 1e-12);
    qtool_gltf_free(&s);
}

/* GLB: the Triangle fixture's JSON with its buffer moved to the BIN chunk */
static void test_glb(void **state)
{
    (void)state;
    uint8_t bin[44] = {0, 0, 1, 0, 2, 0, 0, 0};
    static const float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    for (int i = 0; i < 9; ++i)
        putf(bin + 8 + 4 * i, v[i]);
    const char *json = "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":44}],"
                       "\"bufferViews\":[{\"buffer\":0,\"byteLength\":6},{\"buffer\":0,\"byteOffset\":8,\"byteLength\":36}],"
                       "\"accessors\":[{\"bufferView\":0,\"componentType\":5123,\"count\":3,\"type\":\"SCALAR\"},"
                       "{\"bufferView\":1,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"}],"
                       "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":1},\"indices\":0}]}],"
                       "\"nodes\":[{\"mesh\":0}],\"extras\":0}"; /* 387 bytes: one byte of padding */
    size_t jl = (strlen(json) + 3) & ~(size_t)3, total = 12 + 8 + jl + 8 + 44;
    uint8_t *g = calloc(1, total);
    assert_non_null(g);
    memcpy(g, "glTF", 4);
    uint32_t f[6] = {2, (uint32_t)total, (uint32_t)jl, 0x4E4F534Au};
    for (int i = 0; i < 4; ++i)
        for (int k = 0; k < 4; ++k)
            g[4 + 4 * i + k] = (uint8_t)(f[i] >> (8 * k));
    memset(g + 20, ' ', jl);
    memcpy(g + 20, json, strlen(json));
    assert_true(jl > strlen(json));
    g[20 + jl - 1] = 0; /* pad with a NUL instead of a space, as some exporters do: still read */
    uint32_t bh[2] = {44, 0x004E4942u};
    for (int i = 0; i < 2; ++i)
        for (int k = 0; k < 4; ++k)
            g[20 + jl + 4 * i + k] = (uint8_t)(bh[i] >> (8 * k));
    memcpy(g + 28 + jl, bin, 44);
    qtool_gltf_scene s;
    char err[512];
    if (qtool_gltf_parse("t.glb", NULL, g, total, QTOOL_GLTF_MAX_TRIANGLES, &s, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(s.mesh.ntri, 1);
    assert_true(s.mesh.pos[3] == 1 && s.mesh.pos[7] == 1);
    qtool_gltf_free(&s);
    /* a BIN chunk shorter than the buffer's byteLength */
    g[20 + jl] = 40;
    memset(&s, 0x5A, sizeof s);
    assert_int_equal(qtool_gltf_parse("t.glb", NULL, g, total, QTOOL_GLTF_MAX_TRIANGLES, &s, err, sizeof err), -1);
    assert_non_null(strstr(err, "buffers[0]: 40 bytes of data, byteLength says 44"));
    g[20 + jl] = 44;
    /* a version 1 header and a chunk running past the file */
    g[4] = 1;
    assert_int_equal(qtool_gltf_parse("t.glb", NULL, g, total, QTOOL_GLTF_MAX_TRIANGLES, &s, err, sizeof err), -1);
    assert_non_null(strstr(err, "GLB version 1"));
    g[4] = 2;
    g[20 + jl] = 200;
    assert_int_equal(qtool_gltf_parse("t.glb", NULL, g, total, QTOOL_GLTF_MAX_TRIANGLES, &s, err, sizeof err), -1);
    assert_non_null(strstr(err, "runs past the file"));
    free(g);
}

/* an external .bin and a PNG texture beside the .gltf; uv per corner and the texture's pixels */
static void test_external_files_and_texture(void **state)
{
    (void)state;
    char dir[64], path[256], err[512];
    fu_tmpdir(dir);
    uint8_t bin[96] = {0};
    static const float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0}, uv[6] = {0, 1, 1, 1, 0, 0};
    for (int i = 0; i < 9; ++i)
        putf(bin + 4 * i, v[i]);
    for (int i = 0; i < 6; ++i)
        putf(bin + 36 + 4 * i, uv[i]);
    snprintf(path, sizeof path, "%s/tri data.bin", dir);
    fu_write(path, bin, 60);
    uint8_t px[12] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255};
    snprintf(path, sizeof path, "%s/tex.png", dir);
    assert_int_equal(qtool_png_write_rgb8(path, 2, 2, px, err, sizeof err), 0);
    const char *json = "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":60,\"uri\":\"tri%20data.bin\"}],"
                       "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36},{\"buffer\":0,\"byteOffset\":36,\"byteLength\":24}],"
                       "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"},"
                       "{\"bufferView\":1,\"componentType\":5126,\"count\":3,\"type\":\"VEC2\"}],"
                       "\"images\":[{\"uri\":\"tex.png\"}],\"textures\":[{\"source\":0}],"
                       "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.5,0.25,1,1],"
                       "\"baseColorTexture\":{\"index\":0}}}],"
                       "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":1},\"material\":0}]}],"
                       "\"nodes\":[{\"mesh\":0}]}";
    snprintf(path, sizeof path, "%s/scene.gltf", dir);
    fu_write(path, json, strlen(json));
    qtool_gltf_scene s;
    if (qtool_gltf_read(path, QTOOL_GLTF_MAX_TRIANGLES, &s, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(s.mesh.ntri, 1);
    assert_non_null(s.mesh.albedo);
    assert_true(s.mesh.albedo[0] == 0.5 && s.mesh.albedo[1] == 0.25 && s.mesh.albedo[2] == 1);
    assert_non_null(s.mesh.tex);
    assert_int_equal(s.mesh.tex[0], 0);
    assert_int_equal(s.mesh.ntex, 1);
    assert_int_equal(s.mesh.texs[0].w, 2);
    assert_memory_equal(s.mesh.texs[0].rgb, px, 12);
    for (int i = 0; i < 6; ++i)
        assert_true(s.mesh.uv[i] == uv[i]);
    qtool_gltf_free(&s);
    /* a missing texture file is named */
    snprintf(path, sizeof path, "%s/tex.png", dir);
    remove(path);
    snprintf(path, sizeof path, "%s/scene.gltf", dir);
    memset(&s, 0x5A, sizeof s);
    assert_int_equal(qtool_gltf_read(path, QTOOL_GLTF_MAX_TRIANGLES, &s, err, sizeof err), -1);
    assert_non_null(strstr(err, "images[0]:"));
    assert_non_null(strstr(err, "tex.png"));
    snprintf(path, sizeof path, "%s/tri data.bin", dir);
    remove(path);
    remove(strcat(strcpy(path, dir), "/scene.gltf"));
    rmdir(dir);
}

static void refused(const char *body, const uint8_t *bin, size_t n, const char *needle);

/* a PNG of colour type ct (0 grey, 3 palette, 4 grey + alpha), 8-bit, w x 1, zlib stored block */
static size_t tiny_png(uint8_t *o, int ct, const uint8_t *px, int w, const uint8_t *plte, int nplte)
{
    size_t n = 0;
    static const uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    memcpy(o, sig, 8), n = 8;
    uint8_t ihdr[13] = {0, 0, 0, (uint8_t)w, 0, 0, 0, 1, 8, (uint8_t)ct, 0, 0, 0};
    uint8_t raw[64], z[96];
    int ch = ct == 4 ? 2 : 1, rl = 1 + w * ch;
    raw[0] = 0;
    memcpy(raw + 1, px, (size_t)(w * ch));
    uint32_t a = 1, b = 0;
    for (int i = 0; i < rl; ++i)
        a = (a + raw[i]) % 65521, b = (b + a) % 65521;
    size_t zn = 0;
    z[zn++] = 0x78, z[zn++] = 0x01, z[zn++] = 1, z[zn++] = (uint8_t)rl, z[zn++] = 0, z[zn++] = (uint8_t)~rl, z[zn++] = 0xFF;
    memcpy(z + zn, raw, (size_t)rl), zn += (size_t)rl;
    uint32_t ad = b << 16 | a;
    z[zn++] = (uint8_t)(ad >> 24), z[zn++] = (uint8_t)(ad >> 16), z[zn++] = (uint8_t)(ad >> 8), z[zn++] = (uint8_t)ad;
    const struct {
        const char *t;
        const uint8_t *d;
        size_t n;
    } ck[4] = {{"IHDR", ihdr, 13}, {"PLTE", plte, (size_t)nplte * 3}, {"IDAT", z, zn}, {"IEND", NULL, 0}};
    for (int k = 0; k < 4; ++k) {
        if (k == 1 && !nplte)
            continue;
        uint8_t *c = o + n;
        c[0] = (uint8_t)(ck[k].n >> 24), c[1] = (uint8_t)(ck[k].n >> 16), c[2] = (uint8_t)(ck[k].n >> 8), c[3] = (uint8_t)ck[k].n;
        memcpy(c + 4, ck[k].t, 4);
        if (ck[k].n)
            memcpy(c + 8, ck[k].d, ck[k].n);
        uint32_t crc = qibl_crc32(0, c + 4, 4 + ck[k].n);
        c[8 + ck[k].n] = (uint8_t)(crc >> 24), c[9 + ck[k].n] = (uint8_t)(crc >> 16);
        c[10 + ck[k].n] = (uint8_t)(crc >> 8), c[11 + ck[k].n] = (uint8_t)crc;
        n += 12 + ck[k].n;
    }
    return n;
}

/* textures as exporters write them: palette (BoxTextured's), grey and grey + alpha PNGs, from a
 * bufferView, come back as RGB */
static void test_texture_colour_types(void **state)
{
    (void)state;
    static const uint8_t plte[9] = {10, 20, 30, 200, 100, 50, 1, 2, 3};
    static const uint8_t idx[2] = {1, 2}, grey[2] = {77, 200}, ga[4] = {77, 255, 200, 0};
    static const uint8_t want[3][6] = {{200, 100, 50, 1, 2, 3}, {77, 77, 77, 200, 200, 200}, {77, 77, 77, 200, 200, 200}};
    for (int k = 0; k < 4; ++k) {
        uint8_t bin[512] = {0};
        static const float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
        for (int i = 0; i < 9; ++i)
            putf(bin + 4 * i, v[i]);
        for (int i = 0; i < 6; ++i)
            putf(bin + 36 + 4 * i, 0.25f);
        /* k = 3: a palette index past the PLTE (2 entries) */
        size_t pn = k == 0 ? tiny_png(bin + 60, 3, idx, 2, plte, 3)
                    : k == 1 ? tiny_png(bin + 60, 0, grey, 2, NULL, 0)
                    : k == 2 ? tiny_png(bin + 60, 4, ga, 2, NULL, 0)
                             : tiny_png(bin + 60, 3, idx, 2, plte, 2);
        char body[2048];
        snprintf(body, sizeof body,
                 "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36},{\"buffer\":0,\"byteOffset\":36,\"byteLength\":24},"
                 "{\"buffer\":0,\"byteOffset\":60,\"byteLength\":%zu}],"
                 "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"},"
                 "{\"bufferView\":1,\"componentType\":5126,\"count\":3,\"type\":\"VEC2\"}],"
                 "\"images\":[{\"bufferView\":2,\"mimeType\":\"image/png\"}],\"textures\":[{\"source\":0}],"
                 "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}],"
                 "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":1},\"material\":0}]}],"
                 "\"nodes\":[{\"mesh\":0}]",
                 pn);
        if (k == 3) {
            refused(body, bin, 60 + pn, "palette index 2 past the 2 PLTE entries");
            continue;
        }
        qtool_gltf_scene s;
        char err[512];
        if (parse_json(body, bin, 60 + pn, &s, err, sizeof err) != 0)
            fail_msg("colour type case %d: %s", k, err);
        assert_int_equal(s.mesh.ntex, 1);
        assert_true(s.mesh.texs[0].w == 2 && s.mesh.texs[0].h == 1);
        assert_memory_equal(s.mesh.texs[0].rgb, want[k], 6);
        qtool_gltf_free(&s);
    }
}

/* ---- hostile files ----------------------------------------------------------------------------- */

static void refused(const char *body, const uint8_t *bin, size_t n, const char *needle)
{
    qtool_gltf_scene s, before;
    char err[512];
    memset(&s, 0x5A, sizeof s);
    memcpy(&before, &s, sizeof s);
    if (parse_json(body, bin, n, &s, err, sizeof err) != -1)
        fail_msg("accepted; '%s' expected", needle);
    if (!strstr(err, needle))
        fail_msg("error '%s' does not mention '%s'", err, needle);
    assert_null(strchr(err, '\n'));
    assert_non_null(strstr(err, "t.gltf: "));
    assert_memory_equal(&s, &before, sizeof s);
}

#define VIEWS "\"bufferViews\":[{\"buffer\":0,\"byteLength\":48},{\"buffer\":0,\"byteOffset\":48,\"byteLength\":12}],"
#define ACCS                                                                                                        \
    "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\"},"                         \
    "{\"bufferView\":1,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"}],"
#define MESH "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}],"

static void test_hostile(void **state)
{
    (void)state;
    uint8_t bin[256];
    static const unsigned idx[6] = {0, 1, 2, 0, 2, 3}, bad[6] = {0, 1, 2, 0, 2, 4};
    size_t n = square_bin(bin, 5123, idx, 6);
    /* the reference file is accepted */
    qtool_gltf_scene s;
    char err[512];
    assert_int_equal(parse_json(VIEWS ACCS MESH "\"nodes\":[{\"mesh\":0}]", bin, n, &s, err, sizeof err), 0);
    qtool_gltf_free(&s);
    refused(VIEWS ACCS MESH "\"nodes\":[{\"mesh\":0,\"children\":[0]}],\"scenes\":[{\"nodes\":[0]}]", bin, n,
            "nodes[0] reached twice");
    refused(VIEWS ACCS MESH "\"nodes\":[{\"mesh\":0,\"children\":[1]},{\"children\":[0]}],\"scenes\":[{\"nodes\":[0]}]",
            bin, n, "nodes[0] reached twice");
    /* without scenes the roots are the nodes nobody names as a child: a pure cycle has none */
    refused(VIEWS ACCS MESH "\"nodes\":[{\"mesh\":0,\"children\":[1]},{\"children\":[0]}]", bin, n, "no triangles");
    refused(VIEWS ACCS MESH "\"nodes\":[{\"children\":[2]},{\"children\":[2]},{\"mesh\":0}],\"scenes\":[{\"nodes\":[0,1]}]",
            bin, n, "nodes[2] reached twice");
    refused(VIEWS ACCS MESH "\"nodes\":[{\"mesh\":0,\"children\":[7]}]", bin, n, "not a node index");
    refused(VIEWS ACCS MESH "\"nodes\":[{\"mesh\":3}]", bin, n, "nodes[0].mesh: 3 is not an integer in 0..0");
    refused(VIEWS ACCS MESH "\"nodes\":[{\"mesh\":0.5}]", bin, n, "nodes[0].mesh");
    refused(VIEWS ACCS MESH "\"nodes\":[{\"mesh\":0,\"rotation\":[0,0,0,0]}]", bin, n, "not a unit quaternion");
    refused(VIEWS ACCS MESH "\"nodes\":[{\"mesh\":0,\"matrix\":[1,0,0]}]", bin, n, "not an array of 16 numbers");
    refused(VIEWS ACCS MESH "\"nodes\":[]", bin, n, "no triangles");
    size_t nb = square_bin(bin, 5123, bad, 6);
    refused(VIEWS ACCS MESH "\"nodes\":[{\"mesh\":0}]", bin, nb, "index 5 is 4, past the 4 vertices");
    square_bin(bin, 5123, idx, 6);
    refused(VIEWS "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":5,\"type\":\"VEC3\"},"
                  "{\"bufferView\":1,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"}]," MESH
                  "\"nodes\":[{\"mesh\":0}]",
            bin, n, "accessors[0]: byteOffset 0 + 5 elements x stride 12 = 60 bytes, past bufferViews[0]'s 48");
    refused(VIEWS "\"accessors\":[{\"bufferView\":0,\"byteOffset\":4294967296,\"componentType\":5126,\"count\":4,"
                  "\"type\":\"VEC3\"},{\"bufferView\":1,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"}]," MESH
                  "\"nodes\":[{\"mesh\":0}]",
            bin, n, "past bufferViews[0]");
    refused("\"bufferViews\":[{\"buffer\":0,\"byteOffset\":40,\"byteLength\":48},{\"buffer\":0,\"byteOffset\":48,"
            "\"byteLength\":12}]," ACCS MESH "\"nodes\":[{\"mesh\":0}]",
            bin, n, "bufferViews[0]: byteOffset 40 + byteLength 48 past buffers[0]'s 60 bytes");
    refused("\"bufferViews\":[{\"buffer\":0,\"byteLength\":48,\"byteStride\":8},{\"buffer\":0,\"byteOffset\":48,"
            "\"byteLength\":12}]," ACCS MESH "\"nodes\":[{\"mesh\":0}]",
            bin, n, "byteStride 8 is below the element's 12 bytes");
    /* sparse parts: missing, out of order, past the count, past their views; a zero accessor too big */
    static const char *const sparse[][2] = {
        {"{}", "sparse: no count"},
        {"{\"count\":2,\"indices\":{\"bufferView\":1,\"componentType\":5123},\"values\":{\"bufferView\":0}}",
         "sparse: index 1 is 1 (increasing"}, /* indices 0, 1, 2, 0, 2, 3 read as 0, 1: fine; then values */
        {"{\"count\":3,\"indices\":{\"bufferView\":1,\"componentType\":5123},\"values\":{\"bufferView\":0,"
         "\"byteOffset\":24}}",
         "sparse.values: byteOffset 24 + 3 x 12 bytes past bufferViews[0]'s 48"},
        {"{\"count\":4,\"indices\":{\"bufferView\":1,\"componentType\":5123},\"values\":{\"bufferView\":0}}",
         "sparse: index 3 is 0 (increasing, below the count 4)"},
        {"{\"count\":1,\"indices\":{\"bufferView\":1,\"componentType\":5126},\"values\":{\"bufferView\":0}}",
         "sparse.indices.componentType: 5126"},
        {"{\"count\":9,\"indices\":{\"bufferView\":1,\"componentType\":5123},\"values\":{\"bufferView\":0}}",
         "sparse.count: 9 is not an integer in 0..4"},
    };
    for (size_t k = 0; k < sizeof sparse / sizeof sparse[0]; ++k) {
        char body[2048];
        snprintf(body, sizeof body,
                 VIEWS "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\","
                       "\"sparse\":%s},{\"bufferView\":1,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"}]," MESH
                       "\"nodes\":[{\"mesh\":0}]",
                 sparse[k][0]);
        if (k == 1) /* two increasing indices (0, 1) are fine: the square's first two corners rewritten in place */
        {
            assert_int_equal(parse_json(body, bin, n, &s, err, sizeof err), 0);
            check_square(&s, 2);
            qtool_gltf_free(&s);
            continue;
        }
        refused(body, bin, n, sparse[k][1]);
    }
    refused(VIEWS "\"accessors\":[{\"componentType\":5126,\"count\":100000,\"type\":\"VEC3\"},"
                  "{\"bufferView\":1,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"}]," MESH
                  "\"nodes\":[{\"mesh\":0}]",
            bin, n, "sparse or zero-filled elements, 1200000 bytes: more than");
    refused(VIEWS "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\"},"
                  "{\"bufferView\":1,\"componentType\":5126,\"count\":3,\"type\":\"SCALAR\"}]," MESH
                  "\"nodes\":[{\"mesh\":0}]",
            bin, n, "is not SCALAR UNSIGNED_BYTE");
    refused(VIEWS ACCS "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":1},\"indices\":1}]}],"
                       "\"nodes\":[{\"mesh\":0}]",
            bin, n, "POSITION accessors[1] is not VEC3");
    refused(VIEWS ACCS "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1,\"mode\":7}]}],"
                       "\"nodes\":[{\"mesh\":0}]",
            bin, n, "mode: 7 is not an integer in 0..6");
    refused(VIEWS ACCS "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],\"nodes\":[{\"mesh\":0}]", bin,
            n, "TRIANGLES with 4 vertices");
    refused(VIEWS ACCS MESH "\"nodes\":[{\"mesh\":0}],\"cameras\":[{\"type\":\"perspective\",\"perspective\":"
                            "{\"yfov\":0,\"znear\":1}}],\"scenes\":[{\"nodes\":[0,1]}],\"nodes2\":0",
            bin, n, "scenes[0].nodes[1]: not a node index");
    /* instancing: one mesh on many nodes, past QTOOL_GLTF_MAX_INSTANCE_RATIO times its triangles */
    {
        static char body[8192];
        int o = snprintf(body, sizeof body, VIEWS ACCS MESH "\"nodes\":[");
        for (int i = 0; i < 2 * QTOOL_GLTF_MAX_INSTANCE_RATIO; ++i)
            o += snprintf(body + o, sizeof body - (size_t)o, "%s{\"mesh\":0}", i ? "," : "");
        snprintf(body + o, sizeof body - (size_t)o, "]");
        refused(body, bin, n, "QTOOL_GLTF_MAX_INSTANCE_RATIO");
    }
    /* a tree deeper than QTOOL_GLTF_MAX_DEPTH */
    {
        static char body[16384];
        int o = snprintf(body, sizeof body, VIEWS ACCS MESH "\"nodes\":[");
        for (int i = 0; i <= QTOOL_GLTF_MAX_DEPTH; ++i)
            o += snprintf(body + o, sizeof body - (size_t)o, "%s{\"children\":[%d]}", i ? "," : "", i + 1);
        snprintf(body + o, sizeof body - (size_t)o, ",{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}]");
        refused(body, bin, n, "deeper than 128 (QTOOL_GLTF_MAX_DEPTH)");
    }
    /* uris: data without base64, an absolute path, a '..', a scheme, a percent-escaped '..' */
    static const char *const uris[][2] = {
        {"data:text/plain,abc", "not base64"},
        {"/etc/passwd", "an absolute path"},
        {"a/../../b.bin", "a '..'"},
        {"%2e%2e/b.bin", "a '..'"},
        {"http://example.com/b.bin", "a URI scheme"},
        {"a\\\\b.bin", "a backslash"},
        {"b.bin", "no folder to read it from"},
        {"b%zz.bin", "bad percent escape"},
        {"a\\nb.bin", "a control character"},
        {"%0a.bin", "a control character"},
    };
    for (size_t i = 0; i < sizeof uris / sizeof uris[0]; ++i) {
        char text[1024];
        snprintf(text, sizeof text,
                 "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":60,\"uri\":\"%s\"}]," VIEWS ACCS MESH
                 "\"nodes\":[{\"mesh\":0}]}",
                 uris[i][0]);
        memset(&s, 0x5A, sizeof s);
        assert_int_equal(qtool_gltf_parse("t.gltf", NULL, (const uint8_t *)text, strlen(text), QTOOL_GLTF_MAX_TRIANGLES,
                                          &s, err, sizeof err),
                         -1);
        if (!strstr(err, uris[i][1]))
            fail_msg("uri %s: error '%s' does not say '%s'", uris[i][0], err, uris[i][1]);
        assert_null(strchr(err, '\n')); /* the file's own bytes never break the line */
    }
    /* an object with more than QTOOL_GLTF_MAX_MEMBERS keys is refused; inside extras it is not read */
    {
        static char body[16384];
        int o = snprintf(body, sizeof body, VIEWS ACCS MESH "\"nodes\":[{\"mesh\":0");
        for (int i = 0; i < QTOOL_GLTF_MAX_MEMBERS; ++i)
            o += snprintf(body + o, sizeof body - (size_t)o, ",\"k%d\":0", i);
        snprintf(body + o, sizeof body - (size_t)o, "}]");
        refused(body, bin, n, "an object of 257 members at byte");
        o = snprintf(body, sizeof body, VIEWS ACCS MESH "\"nodes\":[{\"mesh\":0,\"extras\":{\"a\":0");
        for (int i = 0; i < QTOOL_GLTF_MAX_MEMBERS; ++i)
            o += snprintf(body + o, sizeof body - (size_t)o, ",\"k%d\":0", i);
        snprintf(body + o, sizeof body - (size_t)o, "}}]");
        assert_int_equal(parse_json(body, bin, n, &s, err, sizeof err), 0);
        qtool_gltf_free(&s);
    }
    /* a required extension the reader does not know is refused by name; known ones pass */
    refused(VIEWS ACCS MESH "\"nodes\":[{\"mesh\":0}],\"extensionsRequired\":[\"KHR_materials_unlit\","
                            "\"KHR_draco_mesh_compression\"]",
            bin, n, "extensionsRequired: KHR_draco_mesh_compression (not read");
    assert_int_equal(parse_json(VIEWS ACCS MESH "\"nodes\":[{\"mesh\":0}],\"extensionsRequired\":[\"KHR_mesh_quantization\"]",
                                bin, n, &s, err, sizeof err),
                     0);
    qtool_gltf_free(&s);
    /* the version, the JSON itself, and a caller's cap */
    const char *v1 = "{\"asset\":{\"version\":\"1.0\"}}";
    assert_int_equal(qtool_gltf_parse("t.gltf", NULL, (const uint8_t *)v1, strlen(v1), 10, &s, err, sizeof err), -1);
    assert_non_null(strstr(err, "asset.version 1.0 (only glTF 2.x is read)"));
    const char *bad_json = "{\"asset\":{\"version\":\"2.0\"},}";
    assert_int_equal(qtool_gltf_parse("t.gltf", NULL, (const uint8_t *)bad_json, strlen(bad_json), 10, &s, err, sizeof err),
                     -1);
    assert_non_null(strstr(err, "t.gltf: json: byte 27: expected a string key"));
    char text[2048], b64[512];
    b64enc(bin, n, b64);
    snprintf(text, sizeof text,
             "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":%zu,\"uri\":\"data:;base64,%s\"}]," VIEWS ACCS
             MESH "\"nodes\":[{\"mesh\":0}]}",
             n, b64);
    assert_int_equal(qtool_gltf_parse("t.gltf", NULL, (const uint8_t *)text, strlen(text), 1, &s, err, sizeof err), -1);
    assert_non_null(strstr(err, "more than 1 triangles in the scene (this command's limit)"));
    assert_int_equal(qtool_gltf_parse("t.gltf", NULL, (const uint8_t *)text, strlen(text), 2, &s, err, sizeof err), 0);
    qtool_gltf_free(&s);
}

static int rd_gltf(const char *path, char *err, size_t errlen)
{
    qtool_gltf_scene s;
    int rc = qtool_gltf_read(path, QTOOL_GLTF_MAX_TRIANGLES, &s, err, errlen);
    if (rc == 0)
        qtool_gltf_free(&s);
    return rc;
}

static void test_hostile_paths(void **state)
{
    (void)state;
    fu_check_not_regular(rd_gltf);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_box),
        cmocka_unit_test(test_triangle),
        cmocka_unit_test(test_cameras),
        cmocka_unit_test(test_sparse_accessor),
        cmocka_unit_test(test_animation),
        cmocka_unit_test(test_skin),
        cmocka_unit_test(test_mesh_read_at_time),
        cmocka_unit_test(test_index_types),
        cmocka_unit_test(test_strip_fan_nonindexed),
        cmocka_unit_test(test_trs_hierarchy_mirror_normalized),
        cmocka_unit_test(test_vertex_colours),
        cmocka_unit_test(test_glb),
        cmocka_unit_test(test_external_files_and_texture),
        cmocka_unit_test(test_hostile),
        cmocka_unit_test(test_texture_colour_types),
        cmocka_unit_test(test_hostile_paths),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
