/*
 * ply_test.c - tools/io/ply.c: the same cube read from ascii, binary little- and big-endian files
 * (mixed scalar types, extra properties, lists and elements skipped) gives the same triangles and
 * unit normals; hostile headers and bodies are refused by name before anything is allocated; the
 * real bunny in ../shared/fixtures/meshes when present (skipped otherwise).
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

#include "io/ply.h"

static const double cube_v[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                    {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
static const int cube_f[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};

typedef struct {
    uint8_t b[8192];
    size_t n;
} buf;

static void put(buf *b, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int k = vsnprintf((char *)b->b + b->n, sizeof b->b - b->n, fmt, ap);
    va_end(ap);
    b->n += (size_t)k;
}

/* v: bytes of an integer or IEEE value of size sz, in the file's byte order */
static void putv(buf *b, uint64_t v, int sz, int be)
{
    for (int i = 0; i < sz; ++i)
        b->b[b->n++] = (uint8_t)(v >> (8 * (be ? sz - 1 - i : i)));
}

static uint64_t f32bits(float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    return u;
}

static uint64_t f64bits(double d)
{
    uint64_t u;
    memcpy(&u, &d, 8);
    return u;
}

/* The cube as a binary PLY: x double, y int (coordinates are integers), z float, an extra ushort;
 * faces: uchar count, uint indices, then a float list; then an element "edge" with two ints. */
static void binary_cube(buf *b, int be)
{
    b->n = 0;
    put(b, "ply\r\nformat %s 1.0\r\ncomment made by ply_test\r\nobj_info none\r\n", be ? "binary_big_endian" : "binary_little_endian");
    put(b, "element vertex 8\nproperty double x\nproperty int32 y\nproperty float z\nproperty ushort flags\n");
    put(b, "element face 6\nproperty list uchar uint vertex_indices\nproperty list int float texcoord\n");
    put(b, "element edge 2\nproperty int vertex1\nproperty int vertex2\nend_header\n");
    for (int i = 0; i < 8; ++i) {
        putv(b, f64bits(cube_v[i][0]), 8, be);
        putv(b, (uint64_t)(int64_t)cube_v[i][1], 4, be);
        putv(b, f32bits((float)cube_v[i][2]), 4, be);
        putv(b, 0xBEEF, 2, be);
    }
    for (int f = 0; f < 6; ++f) {
        putv(b, 4, 1, be);
        for (int j = 0; j < 4; ++j)
            putv(b, (uint64_t)cube_f[f][j], 4, be);
        putv(b, 2, 4, be);
        putv(b, f32bits(0.5f), 4, be), putv(b, f32bits(0.25f), 4, be);
    }
    for (int e = 0; e < 2; ++e)
        putv(b, 1, 4, be), putv(b, 2, 4, be);
}

static void ascii_cube(buf *b)
{
    b->n = 0;
    put(b, "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
           "property uchar red\nelement face 6\nproperty list uchar int vertex_index\nend_header\n");
    for (int i = 0; i < 8; ++i)
        put(b, "%g %g %g 200\n", cube_v[i][0], cube_v[i][1], cube_v[i][2]);
    for (int f = 0; f < 6; ++f)
        put(b, "4 %d %d %d %d\n", cube_f[f][0], cube_f[f][1], cube_f[f][2], cube_f[f][3]);
}

static void check_cube(const qtool_obj_mesh *m)
{
    assert_int_equal(m->ntri, 12);
    assert_int_equal(m->nvert, 8);
    for (size_t t = 0; t < 12; ++t) {
        const int *f = cube_f[t / 2];
        int c[3] = {f[0], f[t % 2 ? 2 : 1], f[t % 2 ? 3 : 2]}; /* fan from the first vertex */
        for (int k = 0; k < 3; ++k) {
            assert_memory_equal(m->pos + 9 * t + 3 * (size_t)k, cube_v[c[k]], 3 * sizeof(double));
            const double *n = m->nrm + 9 * t + 3 * (size_t)k;
            assert_true(fabs(n[0] * n[0] + n[1] * n[1] + n[2] * n[2] - 1) < 1e-12);
            /* a cube corner's normal points out along the diagonal from the centre */
            double d = (cube_v[c[k]][0] - 0.5) * n[0] + (cube_v[c[k]][1] - 0.5) * n[1] + (cube_v[c[k]][2] - 0.5) * n[2];
            assert_true(d > 0.8);
        }
    }
}

static void test_cube_all_formats(void **state)
{
    (void)state;
    buf b;
    qtool_obj_mesh m;
    char err[256];
    ascii_cube(&b);
    assert_true(qtool_ply_sniff(b.b, b.n));
    if (qtool_ply_parse("a.ply", b.b, b.n, &m, err, sizeof err) != 0)
        fail_msg("%s", err);
    check_cube(&m);
    qtool_obj_free(&m);
    for (int be = 0; be < 2; ++be) {
        binary_cube(&b, be);
        if (qtool_ply_parse("b.ply", b.b, b.n, &m, err, sizeof err) != 0)
            fail_msg("%s", err);
        check_cube(&m);
        qtool_obj_free(&m);
    }
}

/* parses text (strlen) and expects a failure whose message holds want, with nothing allocated */
static void refused(const void *data, size_t n, const char *want)
{
    qtool_obj_mesh m;
    char err[512];
    memset(&m, 0x5A, sizeof m);
    if (qtool_ply_parse("h.ply", data, n, &m, err, sizeof err) == 0)
        fail_msg("accepted; want '%s'", want);
    if (!strstr(err, want))
        fail_msg("message '%s' does not say '%s'", err, want);
    assert_null(m.pos);
    assert_null(m.nrm);
    assert_int_equal(m.ntri, 0);
}

static void refused_s(const char *s, const char *want)
{
    refused(s, strlen(s), want);
}

#define HEAD "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
#define FACE "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
#define FACE_NO_END "element face 1\nproperty list uchar int vertex_indices\n"

static void test_hostile_headers(void **state)
{
    (void)state;
    refused_s("PLY\n", "not a PLY file");
    refused_s("ply\nformat ascii 1.0\nelement vertex 3\n", "no end_header");
    refused_s("ply\nformat ascii 2.0\nend_header\n", "header line 2");
    refused_s("ply\nformat binary_middle_endian 1.0\nend_header\n", "unknown format 'binary_middle_endian'");
    refused_s("ply\nelement vertex 3\nformat ascii 1.0\nend_header\n", "before the format line");
    refused_s("ply\nformat ascii 1.0\nproperty float x\nend_header\n", "a property before any element");
    refused_s(HEAD "property quad w\n" FACE, "unknown type 'quad'");
    refused_s(HEAD "element face 1\nproperty list float int vertex_indices\nend_header\n",
              "list count type 'float' is not an integer type");
    refused_s(HEAD "element face 1\nproperty list uchar float vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
              "vertex_indices are not integers");
    refused_s(HEAD "end_header\n0 0 0\n1 0 0\n0 1 0\n", "no face element");
    refused_s(HEAD "element vertex 1\n" FACE, "two vertex elements"); /* once a use after free (fuzz_ply) */
    refused_s("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n" FACE, "lacks x, y or z");
    refused_s("ply\nformat ascii 1.0\nelement vertex -3\nend_header\n", "count '-3' is not a count");
    refused_s("ply\nformat ascii 1.0\nelement vertex 99999999999\nend_header\n", "is not a count");
    refused_s("ply\nformat ascii 1.0\nelement vertex 16777217\nproperty float x\nproperty float y\nproperty float z\n" FACE,
              "too many vertices");
    /* a count the file cannot hold: refused before the body is read or anything allocated */
    refused_s("ply\nformat ascii 1.0\nelement vertex 1000000\nproperty float x\nproperty float y\nproperty float z\n" FACE
              "0 0 0\n",
              "need at least 6000002 body bytes");
    char big[QTOOL_PLY_MAX_HEADER + 64];
    memset(big, 0, sizeof big);
    strcpy(big, "ply\nformat ascii 1.0\n");
    for (size_t i = strlen(big); i < sizeof big - 1; i += 10)
        memcpy(big + i, "comment x\n", 10 < sizeof big - 1 - i ? 10 : sizeof big - 1 - i);
    refused(big, strlen(big), "no end_header within the first 65536 bytes");
    /* a repeated property (issue 24): which x is the vertex's x was the reader's guess */
    refused_s(HEAD "property float x\n" FACE "0 0 0 5\n1 0 0 5\n0 1 0 5\n3 0 1 2\n",
              "header line 7: element vertex has property x twice");
    refused_s(HEAD "element face 1\nproperty list uchar int vertex_indices\nproperty list uchar int vertex_indices\n"
              "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 3 0 2 1\n",
              "element face has property vertex_indices twice");
    refused_s(HEAD FACE_NO_END "element extra 1\nproperty uchar a\nproperty float a\nend_header\n",
              "element extra has property a twice");
    char nul[] = HEAD "comment\0zz\n";
    refused(nul, sizeof nul - 1, "header line 7 holds a NUL byte");
}

static void test_hostile_bodies(void **state)
{
    (void)state;
    refused_s(HEAD FACE "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "face 0: vertex index 3 outside 0..2");
    refused_s(HEAD FACE "0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", "face 0: vertex index -1 outside 0..2");
    refused_s(HEAD FACE "0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "face 0: 2 vertices (a face has 3..256)");
    refused_s(HEAD FACE "0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n", "vertex 1: x = nan is not a finite coordinate");
    refused_s(HEAD FACE "0 0 0\n1 0 0\n0 1e300 0\n3 0 1 2\n", "vertex 2: y = 1e+300 is not a finite coordinate");
    refused_s(HEAD FACE "0 0 0\n1 0 0\n0 1 zero\n3 0 1 2\n", "vertex 2: 'zero' is not a number");
    refused_s(HEAD FACE "0 0 0\n1 0 0\n0 1 0\n3 0 1.5 2\n", "face 0: '1.5' is not a 4-byte signed integer");
    refused_s(HEAD FACE "0 0 0\n1 0 0\n0 1 0\n300 0 1 2\n", "'300' is not a 1-byte unsigned integer");
    refused_s(HEAD FACE "0 0 0\n1 0 0\n0 1 0\n3 0 1\n", "face 0: the body ends early");
    refused_s(HEAD "element face 0\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n",
              "no faces (the face element is empty)");
    /* binary: a float infinity, and a body cut short */
    buf b;
    binary_cube(&b, 0);
    size_t body = (size_t)(strstr((char *)b.b, "end_header\n") - (char *)b.b) + 11;
    uint8_t save[4];
    memcpy(save, b.b + body + 8 + 4 + 18, 4); /* vertex 1's z */
    float inf = INFINITY;
    memcpy(b.b + body + 8 + 4 + 18, &inf, 4);
    refused(b.b, b.n, "vertex 1: z = inf is not a finite coordinate");
    memcpy(b.b + body + 8 + 4 + 18, save, 4);
    refused(b.b, body + 8 * 18 + 10, "need at least 190 body bytes"); /* 8 x 18 + 6 x (1 + 4) + 2 x 8 */
    refused(b.b, body + 200, "face 1: the body ends early"); /* in face 1 (bytes 173..201) */
    /* a skipped list whose count runs past the end of the file */
    binary_cube(&b, 1);
    body = (size_t)(strstr((char *)b.b, "end_header\n") - (char *)b.b) + 11;
    size_t tc = body + 8 * 18 + 1 + 16; /* face 0's texcoord count (big-endian int) */
    b.b[tc] = 0x7F;
    refused(b.b, b.n, "list texcoord of 2130706434 items runs past the end of the file");
}

/* A caller's cap is checked against the exact count of fan triangles, from a first pass over the
 * body: the message gives that count (two hexagons and a pentagon: 4 + 4 + 3), nothing allocated;
 * at the count itself the mesh is read. A cap above the reader's own is the reader's own. */
static void test_triangle_cap(void **state)
{
    (void)state;
    static const char ply[] = "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\n"
                              "property float z\nelement face 3\nproperty list uchar int vertex_indices\nend_header\n"
                              "0 0 0\n1 0 0\n2 1 0\n1 2 0\n0 2 0\n-1 1 0\n"
                              "6 0 1 2 3 4 5\n6 5 4 3 2 1 0\n5 0 1 2 3 4\n";
    qtool_obj_mesh m;
    char err[512];
    memset(&m, 0x5A, sizeof m);
    assert_int_equal(qtool_ply_parse_max("cap.ply", (const uint8_t *)ply, sizeof ply - 1, 10, &m, err, sizeof err), -1);
    assert_non_null(strstr(err, "cap.ply: 11 triangles after fan triangulation of 3 faces (at most 10)"));
    assert_null(m.pos), assert_null(m.nrm), assert_int_equal(m.ntri, 0);
    assert_int_equal(qtool_ply_parse_max("cap.ply", (const uint8_t *)ply, sizeof ply - 1, 11, &m, err, sizeof err), 0);
    assert_int_equal(m.ntri, 11);
    qtool_obj_free(&m);
    assert_int_equal(qtool_ply_parse_max("cap.ply", (const uint8_t *)ply, sizeof ply - 1, (size_t)-1, &m, err, sizeof err), 0);
    assert_int_equal(m.ntri, 11);
    qtool_obj_free(&m);
}

static void test_bunny(void **state)
{
    (void)state;
    const char *path = "../shared/fixtures/meshes/bun_zipper_res2.ply";
    if (access(path, R_OK) != 0) {
        printf("SKIP ply: %s not found\n", path);
        skip();
    }
    qtool_obj_mesh m;
    char err[512];
    if (qtool_ply_read(path, &m, err, sizeof err) != 0)
        fail_msg("%s", err);
    /* the header's counts: 8171 vertices, 16301 triangles */
    assert_int_equal(m.nvert, 8171);
    assert_int_equal(m.ntri, 16301);
    size_t unit = 0;
    for (size_t i = 0; i < m.ntri * 3; ++i) {
        const double *n = m.nrm + 3 * i;
        double l = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
        unit += fabs(l - 1) < 1e-9;
        assert_true(isfinite(m.pos[3 * i]) && isfinite(m.pos[3 * i + 1]) && isfinite(m.pos[3 * i + 2]));
    }
    assert_true(unit >= m.ntri * 3 - 10); /* only corners of degenerate triangles may be 0 */
    qtool_obj_free(&m);
    refused_s("ply\n", "no end_header");
    assert_int_equal(qtool_ply_read("/nonexistent/x.ply", &m, err, sizeof err), -1);
    assert_non_null(strstr(err, "/nonexistent/x.ply"));
}

/* Edges so short that their cross product squares to a subnormal: the normals are still of unit
 * length (the fuzzer's finding, tests/fuzz/crashes-found/ply/tiny_edges_normal, as bytes) */
static void test_tiny_edges_unit_normals(void **state)
{
    (void)state;
    static const uint8_t ply[] = {
        0x70, 0x6c, 0x79, 0x0a, 0x66, 0x6f, 0x72, 0x6d, 0x61, 0x74, 0x20, 0x62, 0x69, 0x6e, 0x61, 0x72,
        0x79, 0x5f, 0x62, 0x69, 0x67, 0x5f, 0x65, 0x6e, 0x64, 0x69, 0x61, 0x6e, 0x20, 0x31, 0x2e, 0x30,
        0x0a, 0x63, 0x6f, 0x6d, 0x6d, 0x65, 0x6e, 0x74, 0x20, 0x6d, 0x61, 0x64, 0x63, 0x75, 0x62, 0x65,
        0x0a, 0x65, 0x6c, 0x65, 0x6d, 0x65, 0x6e, 0x74, 0x20, 0x76, 0x65, 0x72, 0x74, 0x65, 0x78, 0x20,
        0x38, 0x0a, 0x70, 0x72, 0x6f, 0x70, 0x65, 0x72, 0x74, 0x79, 0x20, 0x64, 0x6f, 0x75, 0x62, 0x6c,
        0x65, 0x20, 0x78, 0x0a, 0x70, 0x72, 0x6f, 0x70, 0x65, 0x72, 0x74, 0x79, 0x20, 0x64, 0x6f, 0x75,
        0x62, 0x6c, 0x65, 0x20, 0x79, 0x0a, 0x70, 0x72, 0x6f, 0x70, 0x65, 0x72, 0x74, 0x79, 0x20, 0x64,
        0x6f, 0x75, 0x62, 0x6c, 0x65, 0x20, 0x7a, 0x0a, 0x70, 0x72, 0x6f, 0x70, 0x65, 0x72, 0x74, 0x79,
        0x20, 0x75, 0x73, 0x68, 0x6f, 0x72, 0x74, 0x20, 0x71, 0x75, 0x61, 0x6c, 0x69, 0x74, 0x79, 0x0a,
        0x65, 0x6c, 0x65, 0x6d, 0x65, 0x6e, 0x74, 0x20, 0x66, 0x61, 0x63, 0x65, 0x20, 0x31, 0x0a, 0x70,
        0x72, 0x6f, 0x70, 0x65, 0x72, 0x74, 0x79, 0x20, 0x6c, 0x69, 0x73, 0x74, 0x20, 0x75, 0x73, 0x68,
        0x6f, 0x72, 0x74, 0x20, 0x75, 0x69, 0x6e, 0x74, 0x20, 0x76, 0x65, 0x72, 0x74, 0x65, 0x78, 0x5f,
        0x69, 0x6e, 0x64, 0x69, 0x63, 0x65, 0x73, 0x0a, 0x70, 0x72, 0x6f, 0x70, 0x65, 0x72, 0x74, 0x79,
        0x20, 0x75, 0x63, 0x68, 0x61, 0x72, 0x20, 0x66, 0x6c, 0x61, 0x67, 0x73, 0x32, 0x0a, 0x70, 0x72,
        0x6f, 0x70, 0x65, 0x72, 0x74, 0x79, 0x20, 0x69, 0x6e, 0x74, 0x20, 0x76, 0x65, 0x72, 0x74, 0x65,
        0x78, 0x31, 0x0a, 0x70, 0x72, 0x6f, 0x70, 0x65, 0x72, 0x74, 0x79, 0x20, 0x69, 0x6e, 0x74, 0x20,
        0x76, 0x65, 0x72, 0x74, 0x65, 0x78, 0x32, 0x0a, 0x65, 0x6e, 0x64, 0x5f, 0x68, 0x65, 0x61, 0x64,
        0x65, 0x72, 0x0a, 0x80, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x2f, 0x00, 0x00, 0x00, 0x00,
        0x00, 0x00, 0x00, 0x80, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xbf, 0xf0, 0x00,
        0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x00, 0x00,
        0x00, 0x00, 0x00, 0x00, 0xff, 0xff, 0x60, 0x30, 0x00, 0x01, 0x6d, 0x36, 0x00, 0x00, 0x00, 0xbf,
        0xf0, 0x00, 0x00, 0x00, 0x29, 0x80, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x00, 0x00,
        0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xbf,
        0xf0, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80,
        0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01, 0xbf, 0xf0, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x00, 0xbf, 0xf0, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x00, 0x00, 0x02, 0x80, 0x00, 0xbf, 0xf0, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x05, 0xbf,
        0xf0, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xbf, 0xf0, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xbf,
        0xf0, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x06, 0x80, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x00, 0xbf, 0xf0, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xbf, 0xef, 0xff, 0xff, 0xff, 0xf9, 0x00,
        0x00, 0x00, 0x07, 0x00, 0x04, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x03, 0x00, 0x00, 0x00,
        0x02, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x04, 0x00, 0x00, 0x00, 0x04, 0x00, 0x00, 0x00, 0x05,
        0x00, 0x00, 0x00, 0x06, 0x00, 0x20, 0x61, 0x20, 0x75, 0x00, 0x00, 0x01, 0x00, 0x02};
    qtool_obj_mesh m;
    char err[256];
    assert_int_equal(qtool_ply_parse("tiny.ply", ply, sizeof ply, &m, err, sizeof err), 0);
    assert_true(m.ntri >= 1);
    for (size_t c = 0; c < 3 * m.ntri; ++c) {
        const double *n = m.nrm + 3 * c;
        double l = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
        assert_true(l == 0 || fabs(l - 1) < 1e-9);
    }
    qtool_obj_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cube_all_formats),
        cmocka_unit_test(test_hostile_headers),
        cmocka_unit_test(test_hostile_bodies),
        cmocka_unit_test(test_triangle_cap),
        cmocka_unit_test(test_tiny_edges_unit_normals),
        cmocka_unit_test(test_bunny),
    };
    return cmocka_run_group_tests_name("ply", tests, NULL, NULL);
}
