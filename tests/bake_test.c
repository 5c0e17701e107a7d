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
    qtool_rt_scene s;
    assert_int_equal(qtool_rt_scene_builtin(&s), 0);
    qtool_bake_sums a, b, parts[3];
    assert_int_equal(qtool_bake_run(&s, 32, 8, QTOOL_PANO_CYLINDRICAL, 64, 16, 0, 1, 1, 0, &a), 0);
    assert_int_equal(qtool_bake_run(&s, 32, 8, QTOOL_PANO_CYLINDRICAL, 64, 16, 0, 1, 3, 0, &b), 0);
    size_t n = 32 * 8 * 3 * 16;
    assert_memory_equal(a.acc, b.acc, n * sizeof(int64_t));
    assert_memory_equal(a.pmap, b.pmap, 32 * 8 * 3 * sizeof(int32_t));
    char path[64], err[256];
    snprintf(path, sizeof path, "/tmp/qibl_bake_sums_%d", (int)getpid());
    for (uint32_t i = 0; i < 3; ++i) {
        qtool_bake_sums p;
        assert_int_equal(qtool_bake_run(&s, 32, 8, QTOOL_PANO_CYLINDRICAL, 64, 16, i, 3, 2, 0, &p), 0);
        assert_int_equal(qtool_bake_sums_write(&p, path, err, sizeof err), 0);
        assert_int_equal(qtool_bake_sums_read(path, &parts[i], err, sizeof err), 0);
        assert_memory_equal(parts[i].acc, p.acc, n * sizeof(int64_t));
        qtool_bake_sums_free(&p);
    }
    assert_int_equal(qtool_bake_sums_add(&parts[2], &parts[0], err, sizeof err), 0);
    assert_int_equal(qtool_bake_sums_add(&parts[2], &parts[1], err, sizeof err), 0);
    assert_memory_equal(parts[2].acc, a.acc, n * sizeof(int64_t));
    /* assets byte-identical */
    qtool_gen_maps m1, m2;
    uint8_t *b1, *b2;
    size_t n1, n2;
    assert_int_equal(qtool_bake_coeffs(&a, 16, QTOOL_PROJ_QUADRATURE, &m1), 0);
    assert_int_equal(qtool_bake_coeffs(&parts[2], 16, QTOOL_PROJ_QUADRATURE, &m2), 0);
    assert_int_equal(qtool_bake_asset(&m1, 8, &b1, &n1), 0);
    assert_int_equal(qtool_bake_asset(&m2, 8, &b2, &n2), 0);
    assert_int_equal(n1, n2);
    assert_memory_equal(b1, b2, n1);
    qibl_asset_t as;
    assert_int_equal(qibl_asset_open(&as, b1, n1), QIBL_OK);
    /* a truncated or foreign sums file: error naming the file */
    FILE *f = fopen(path, "wb");
    fputs("QIBLSUM1 short", f);
    fclose(f);
    qtool_bake_sums bad;
    assert_int_equal(qtool_bake_sums_read(path, &bad, err, sizeof err), -1);
    assert_non_null(strstr(err, path));
    remove(path);
    free(b1), free(b2);
    qtool_gen_free(&m1), qtool_gen_free(&m2);
    for (int i = 0; i < 3; ++i)
        qtool_bake_sums_free(&parts[i]);
    qtool_bake_sums_free(&a), qtool_bake_sums_free(&b);
    qtool_rt_scene_free(&s);
}

/* A single ground plane (raw OBJ, nothing to shadow it): the bake's SH projection of
 * albedo/pi max(0, n.w) must match the analytic Funk-Hecke coefficients (quadrature and LSQ). */
static void test_projection_of_unshadowed_plane(void **state)
{
    (void)state;
    const char *text = "v -50 -50 -1\nv 50 -50 -1\nv 50 50 -1\nv -50 50 -1\nf 1 2 3 4\n";
    qtool_obj_mesh mesh;
    char err[256];
    assert_int_equal(qtool_obj_parse("plane.obj", text, strlen(text), &mesh, err, sizeof err), 0);
    qtool_rt_scene s;
    assert_int_equal(qtool_rt_scene_from_obj(&s, &mesh, 1, 1), 0);
    qtool_obj_free(&mesh);
    s.mats[1].ks = 0;
    qtool_bake_sums a;
    assert_int_equal(qtool_bake_run(&s, 16, 8, QTOOL_PANO_EQUIRECT, 1024, 9, 0, 1, 2, 0, &a), 0);
    /* analytic: c_00 = albedo * sqrt(pi)/2 / pi... via a_l Y_l0(n): a_0 = 1, a_1 = 2/3, a_2 = 1/4 */
    double yn[25];
    qtool_ref_sh_eval(0, 0, 1, 3, yn);
    const double al[3] = {1.0, 2.0 / 3.0, 0.25};
    for (int method = 0; method < 2; ++method) {
        qtool_gen_maps m;
        assert_int_equal(qtool_bake_coeffs(&a, 9, (qtool_proj_method)method, &m), 0);
        size_t np = 16 * 8, p = 7 * 16 + 3; /* a pixel looking down */
        for (int i = 0; i < 9; ++i) {
            int l = i == 0 ? 0 : i < 4 ? 1 : 2;
            double want = s.mats[1].albedo[0] * al[l] * yn[i];
            double got = m.t[(size_t)i * 3 * np + p];
            if (fabs(got - want) > 4e-3)
                fail_msg("method %d, coefficient %d: %f, analytic %f", method, i, got, want);
        }
        qtool_gen_free(&m);
    }
    qtool_bake_sums_free(&a);
    qtool_rt_scene_free(&s);
}

static void test_shadow_and_pmap(void **state)
{
    (void)state;
    /* the ground under a floating square is shadowed from above, lit from the side */
    const char *text = "v -50 -50 -1\nv 50 -50 -1\nv 50 50 -1\nv -50 50 -1\nf 1 2 3 4\n"
                       "v -2 -2 1\nv 2 -2 1\nv 2 2 1\nv -2 2 1\nf 5 6 7 8\n";
    qtool_obj_mesh mesh;
    char err[256];
    assert_int_equal(qtool_obj_parse("t.obj", text, strlen(text), &mesh, err, sizeof err), 0);
    qtool_rt_scene s;
    assert_int_equal(qtool_rt_scene_from_obj(&s, &mesh, 1, 1), 0);
    qtool_obj_free(&mesh);
    double down[3] = {0.01, 0.0, -1.0}, up[3] = {0, 0, 1}, side[3] = {1, 0, 0.2}, df, gl;
    qtool_rt_hit h;
    qtool_rt_primary(&s, down, &h);
    assert_true(h.hit);
    assert_true(fabs(h.p[2] + 1.0) < 1e-9 && fabs(h.t - 1.0) < 1e-9);
    assert_int_equal(qtool_rt_response(&s, &h, up, 1e30, &df, &gl), 0);
    double l = sqrt(1.04);
    side[0] /= l, side[2] /= l;
    assert_int_equal(qtool_rt_response(&s, &h, side, 1e30, &df, &gl), 1);
    assert_true(fabs(df - side[2] / 3.14159265358979) < 1e-12);
    qtool_rt_scene_free(&s);
}

/* per-triangle albedo and texture (glTF baseColorFactor / OBJ Kd, base-colour textures): what the
 * primary hit reports and what the renderer multiplies; the ground keeps its material */
static double srgb_dec(int c)
{
    double x = c / 255.0;
    return x <= 0.04045 ? x / 12.92 : pow((x + 0.055) / 1.055, 2.4);
}

static void test_per_triangle_albedo_and_texture(void **state)
{
    (void)state;
    /* two triangles of the plane z = -1: x < 0 (triangle 0) and x > 0 (triangle 1) */
    const char *text = "v -50 -50 -1\nv 0 -50 -1\nv 0 50 -1\nv 50 -50 -1\nf 1 2 3\nf 2 4 3\n";
    qtool_obj_mesh mesh;
    char err[256];
    assert_int_equal(qtool_obj_parse("plane.obj", text, strlen(text), &mesh, err, sizeof err), 0);
    assert_int_equal(mesh.ntri, 2);
    mesh.albedo = malloc(6 * sizeof(double));
    mesh.uv = malloc(12 * sizeof(double));
    mesh.tex = malloc(2 * sizeof(int32_t));
    mesh.texs = calloc(1, sizeof *mesh.texs);
    assert_true(mesh.albedo && mesh.uv && mesh.tex && mesh.texs);
    static const double alb[6] = {0.2, 0.4, 0.6, 1.0, 0.5, 0.25};
    memcpy(mesh.albedo, alb, sizeof alb);
    mesh.tex[0] = -1, mesh.tex[1] = 0;
    for (int i = 0; i < 12; ++i) /* triangle 1's corners all at u = 0.75, v = 0.5: texel (1, 0) exactly */
        mesh.uv[i] = i % 2 ? 0.5 : 0.75;
    mesh.texs[0].w = 2, mesh.texs[0].h = 1, mesh.ntex = 1;
    mesh.texs[0].rgb = malloc(6);
    static const uint8_t px[6] = {255, 255, 255, 255, 128, 0};
    memcpy(mesh.texs[0].rgb, px, 6);
    qtool_rt_scene s;
    assert_int_equal(qtool_rt_scene_from_obj(&s, &mesh, 1, 1), 0);
    qtool_obj_free(&mesh);
    s.mats[1].ks = 0; /* Lambert only, for the analytic check below */
    double left[3] = {-0.3, 0.01, -1.0}, right[3] = {0.3, 0.01, -1.0};
    qtool_rt_hit h;
    qtool_rt_primary(&s, left, &h);
    assert_true(h.hit);
    for (int c = 0; c < 3; ++c)
        assert_true(h.albedo[c] == alb[c]);
    qtool_rt_primary(&s, right, &h);
    assert_true(h.hit);
    double want[3] = {1.0 * srgb_dec(255), 0.5 * srgb_dec(128), 0.25 * srgb_dec(0)};
    for (int c = 0; c < 3; ++c)
        assert_true(fabs(h.albedo[c] - want[c]) < 1e-12);
    /* the renderer: a sun from straight above gives E albedo / pi on the plane */
    qtool_rt_light l = {.dir = {0, 0, 1}, .rgb = {1, 1, 1}};
    double rgb[3 * 64 * 32];
    assert_int_equal(qtool_rt_render(&s, 64, 32, QTOOL_PANO_EQUIRECT, &l, 1, rgb, NULL, NULL), 0);
    int seen_left = 0;
    for (uint32_t y = 16; y < 32; ++y)
        for (uint32_t x = 0; x < 64; ++x) {
            double d[3];
            qtool_rt_pixel_dir(64, 32, QTOOL_PANO_EQUIRECT, x, y, d);
            qtool_rt_primary(&s, d, &h);
            if (!h.hit)
                continue;
            const double *o = rgb + 3 * (y * 64 + x);
            const double *a = h.p[0] < 0 ? alb : want;
            seen_left += h.p[0] < 0;
            for (int c = 0; c < 3; ++c)
                assert_true(fabs(o[c] - a[c] / 3.14159265358979323846) < 1e-9);
        }
    assert_true(seen_left > 0);
    qtool_rt_scene_free(&s);
}

/* qtool_rt_prop_place puts a mesh point exactly where the prop's triangles put it (a glTF camera's
 * eye goes through it to the scene the bake renders) and only turns directions */
static void test_prop_place(void **state)
{
    (void)state;
    const char *text = "v 3 0 1\nv 5 0 1\nv 3 4 2\nf 1 2 3\n";
    qtool_obj_mesh mesh;
    char err[256];
    assert_int_equal(qtool_obj_parse("t.obj", text, strlen(text), &mesh, err, sizeof err), 0);
    for (int zup = 0; zup < 2; ++zup) {
        qtool_rt_scene s;
        assert_int_equal(qtool_rt_scene_from_obj(&s, &mesh, zup, 0), 0);
        for (int q = 0; q < 3; ++q) {
            double w[3];
            qtool_rt_prop_place(&mesh, zup, 0, mesh.pos + 3 * q, 0, w);
            int found = 0;
            for (size_t i = 0; i < 3 * s.ntri; ++i)
                found |= s.v[3 * i] == w[0] && s.v[3 * i + 1] == w[1] && s.v[3 * i + 2] == w[2];
            assert_true(found);
        }
        double up[3] = {0, 1, 0}, d[3];
        qtool_rt_prop_place(&mesh, zup, 0, up, 1, d);
        /* Y-up: +y becomes +z; Z-up: +y is turned a quarter about z to -x */
        assert_true(zup ? (d[0] == -1 && d[1] == 0 && d[2] == 0) : (d[0] == 0 && d[1] == 0 && d[2] == 1));
        qtool_rt_scene_free(&s);
    }
    qtool_obj_free(&mesh);
}

/* ---- partial sums files: every header field checked before use (issue 10, findings 1 and 3) ---- */

/* small synthetic sums: w x h, k, ndirs, shard/nshards; acc filled from seed */
static void make_sums(qtool_bake_sums *s, uint32_t w, uint32_t h, uint32_t k, uint32_t ndirs, uint32_t shard,
                      uint32_t nshards, int64_t seed)
{
    memset(s, 0, sizeof *s);
    s->w = w, s->h = h, s->k = k, s->ndirs = ndirs, s->shard = shard, s->nshards = nshards;
    s->pmap = malloc(sizeof(int32_t) * w * h * 3);
    s->acc = malloc(sizeof(int64_t) * w * h * 3 * k);
    assert_non_null(s->pmap);
    assert_non_null(s->acc);
    for (size_t i = 0; i < (size_t)w * h * 3; ++i)
        s->pmap[i] = (int32_t)(i * 977) - 5000;
    for (size_t i = 0; i < (size_t)w * h * 3 * k; ++i)
        s->acc[i] = seed * (int64_t)(i + 1);
}

static void put32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v, p[1] = (uint8_t)(v >> 8), p[2] = (uint8_t)(v >> 16), p[3] = (uint8_t)(v >> 24);
}

/* recompute both CRCs after an edit, so the edit reaches the field checks */
static void fix_crcs(uint8_t *b, size_t n)
{
    put32(b + 40, qibl_crc32(0, b + QTOOL_BAKE_SUMS_HEADER, n - QTOOL_BAKE_SUMS_HEADER));
    put32(b + 44, qibl_crc32(0, b, 44));
}

static void expect_decode_error(const uint8_t *b, size_t n, const char *want)
{
    qtool_bake_sums s;
    char err[512] = "";
    memset(&s, 0xA5, sizeof s);
    if (qtool_bake_sums_decode(b, n, &s, err, sizeof err) == 0)
        fail_msg("decoded a file that should fail with '%s'", want);
    if (strstr(err, want) == NULL)
        fail_msg("error '%s' does not say '%s'", err, want);
}

static void test_sums_roundtrip_and_version(void **state)
{
    (void)state;
    qtool_bake_sums a, b;
    make_sums(&a, 5, 3, 4, 64, 1, 4, -123456789012345);
    uint8_t *buf;
    size_t n;
    char err[512];
    assert_int_equal(qtool_bake_sums_encode(&a, &buf, &n), 0);
    assert_int_equal(n, QTOOL_BAKE_SUMS_HEADER + 5 * 3 * 12 + 5 * 3 * 3 * 4 * 8);
    assert_memory_equal(buf, "QIBLSUMS", 8);
    assert_int_equal(qibl_load_u32le(buf + 8), QTOOL_BAKE_SUMS_VERSION);
    assert_int_equal(qtool_bake_sums_decode(buf, n, &b, err, sizeof err), 0);
    assert_int_equal(b.w, 5), assert_int_equal(b.h, 3), assert_int_equal(b.k, 4);
    assert_int_equal(b.shard, 1), assert_int_equal(b.nshards, 4), assert_int_equal(b.ndirs, 64);
    assert_memory_equal(a.pmap, b.pmap, 5 * 3 * 12);
    assert_memory_equal(a.acc, b.acc, 5 * 3 * 3 * 4 * 8);
    qtool_bake_sums_free(&b);
    /* the file writer writes the same bytes, the reader reads them back */
    char path[64];
    snprintf(path, sizeof path, "/tmp/qibl_sums_rt_%d", (int)getpid());
    assert_int_equal(qtool_bake_sums_write(&a, path, err, sizeof err), 0);
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    uint8_t *disk = malloc(n + 1);
    assert_int_equal(fread(disk, 1, n + 1, f), n);
    fclose(f);
    assert_memory_equal(disk, buf, n);
    assert_int_equal(qtool_bake_sums_read(path, &b, err, sizeof err), 0);
    assert_memory_equal(a.acc, b.acc, 5 * 3 * 3 * 4 * 8);
    qtool_bake_sums_free(&b);
    /* version 1 files (no checksum) and unknown versions are refused by name */
    memcpy(disk, "QIBLSUM1", 8);
    expect_decode_error(disk, n, "version 1");
    memcpy(disk, "QIBLSUMS", 8);
    put32(disk + 8, 3);
    fix_crcs(disk, n);
    expect_decode_error(disk, n, "unsupported partial-sums version 3");
    remove(path);
    free(disk), free(buf);
    qtool_bake_sums_free(&a);
}

/* A flipped bit anywhere is caught by a checksum before the sums are used. */
static void test_sums_checksums_catch_flips(void **state)
{
    (void)state;
    qtool_bake_sums a, b;
    make_sums(&a, 4, 2, 2, 32, 0, 2, 77);
    uint8_t *buf;
    size_t n;
    char err[512];
    assert_int_equal(qtool_bake_sums_encode(&a, &buf, &n), 0);
    for (size_t i = 0; i < n; i += 3) {
        buf[i] ^= (uint8_t)(1u << (i % 8));
        int rc = qtool_bake_sums_decode(buf, n, &b, err, sizeof err);
        if (rc == 0)
            fail_msg("bit %zu of byte %zu flipped: decoded", i % 8, i);
        if (i >= 12 && strstr(err, "checksum mismatch") == NULL)
            fail_msg("byte %zu flipped: '%s' does not name a checksum mismatch", i, err);
        buf[i] ^= (uint8_t)(1u << (i % 8));
    }
    assert_int_equal(qtool_bake_sums_decode(buf, n, &b, err, sizeof err), 0);
    qtool_bake_sums_free(&b);
    /* through the file reader too: the error names the file */
    char path[64];
    snprintf(path, sizeof path, "/tmp/qibl_sums_flip_%d", (int)getpid());
    buf[n - 1] ^= 0x10;
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(buf, 1, n, f), n);
    fclose(f);
    assert_int_equal(qtool_bake_sums_read(path, &b, err, sizeof err), -1);
    assert_non_null(strstr(err, path));
    assert_non_null(strstr(err, "checksum mismatch in the sums"));
    remove(path);
    free(buf);
    qtool_bake_sums_free(&a);
}

/* Every count in the header is bounded, and the file's size must be what the header claims, before
 * anything is allocated: a 48-byte file cannot ask for gigabytes or hours. */
static void test_sums_header_fields_bounded(void **state)
{
    (void)state;
    qtool_bake_sums a;
    make_sums(&a, 4, 2, 2, 32, 1, 2, 5);
    uint8_t *good;
    size_t n;
    assert_int_equal(qtool_bake_sums_encode(&a, &good, &n), 0);
    static const struct {
        unsigned off;
        uint32_t value;
        const char *want;
    } cases[] = {
        {12, 0, "width 0 outside 1..16384"},
        {12, 16385, "width 16385 outside"},
        {16, 0, "height 0 outside"},
        {16, 70000, "height 70000 outside"},
        {20, 0, "k 0 outside 1..25"},
        {20, 26, "k 26 outside 1..25"},
        {24, 0, "direction count 0 outside"},
        {24, 0x7FFFFFFFu, "direction count 2147483647 outside 1..65536"},
        {24, 65537, "direction count 65537 outside"},
        {28, 2, "panorama kind 2"},
        {36, 0, "shard count 0 outside"},
        {36, 4097, "shard count 4097 outside"},
        {36, 3, "shard count 3 outside"}, /* 32 directions are 2 blocks: at most 2 shards */
        {32, 2, "shard index 2 not below the shard count 2"},
        {32, 0xFFFFFFFFu, "shard index 4294967295 not below"},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        uint8_t *b = malloc(n);
        memcpy(b, good, n);
        put32(b + cases[c].off, cases[c].value);
        fix_crcs(b, n);
        expect_decode_error(b, n, cases[c].want);
        free(b);
    }
    /* w * h above the asset's pixel limit although each side is in range */
    uint8_t hdr[QTOOL_BAKE_SUMS_HEADER];
    memcpy(hdr, good, sizeof hdr);
    put32(hdr + 12, 16384), put32(hdr + 16, 8192);
    fix_crcs(hdr, sizeof hdr);
    expect_decode_error(hdr, sizeof hdr, "size 16384x8192 above 67108864 pixels");
    /* a header that claims a large (valid) body with none behind it: truncated, nothing allocated */
    memcpy(hdr, good, sizeof hdr);
    put32(hdr + 12, 16384), put32(hdr + 16, 4096), put32(hdr + 20, 25), put32(hdr + 24, 65536);
    fix_crcs(hdr, sizeof hdr);
    expect_decode_error(hdr, sizeof hdr, "truncated: 0 bytes of sums, the header says 41070624768");
    char path[64], err[512];
    snprintf(path, sizeof path, "/tmp/qibl_sums_lie_%d", (int)getpid());
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(hdr, 1, sizeof hdr, f), sizeof hdr);
    fclose(f);
    qtool_bake_sums b;
    assert_int_equal(qtool_bake_sums_read(path, &b, err, sizeof err), -1);
    assert_non_null(strstr(err, "truncated: 48 bytes, the header says 41070624816"));
    remove(path);
    /* short, foreign, trailing */
    expect_decode_error(good, 0, "bad magic");
    expect_decode_error((const uint8_t *)"PNG\r\n", 5, "bad magic");
    expect_decode_error(good, 30, "truncated header (30 of 48 bytes)");
    expect_decode_error(good, n - 1, "truncated");
    uint8_t *longer = calloc(n + 5, 1);
    memcpy(longer, good, n);
    expect_decode_error(longer, n + 5, "5 trailing bytes after the sums");
    free(longer);
    /* a directory is not a sums file */
    assert_int_equal(qtool_bake_sums_read("/tmp", &b, err, sizeof err), -1);
    assert_non_null(strstr(err, "not a regular file"));
    free(good);
    qtool_bake_sums_free(&a);
}

/* Adding sums that overflow 64 bits is a named error and changes nothing (no wrapped, CRC-valid
 * garbage asset); mismatched bakes name the first difference. */
static void test_sums_add_overflow_and_mismatch(void **state)
{
    (void)state;
    qtool_bake_sums a, b, c;
    make_sums(&a, 3, 2, 1, 32, 0, 2, 1);
    make_sums(&b, 3, 2, 1, 32, 1, 2, 2);
    char err[512];
    size_t na = 3 * 2 * 3;
    int64_t *before = malloc(sizeof(int64_t) * na);
    a.acc[na - 1] = INT64_MAX - 5;
    b.acc[na - 1] = 6;
    memcpy(before, a.acc, sizeof(int64_t) * na);
    assert_int_equal(qtool_bake_sums_add(&a, &b, err, sizeof err), -1);
    assert_non_null(strstr(err, "overflow 64 bits at pixel (2, 1), channel 2, coefficient 0"));
    assert_memory_equal(a.acc, before, sizeof(int64_t) * na); /* nothing half-added */
    a.acc[na - 1] = INT64_MIN + 5, b.acc[na - 1] = -6;
    assert_int_equal(qtool_bake_sums_add(&a, &b, err, sizeof err), -1);
    assert_non_null(strstr(err, "overflow"));
    a.acc[na - 1] = INT64_MAX - 6, b.acc[na - 1] = 6; /* exactly INT64_MAX: fine */
    assert_int_equal(qtool_bake_sums_add(&a, &b, err, sizeof err), 0);
    assert_true(a.acc[na - 1] == INT64_MAX);
    /* each mismatch by name */
    make_sums(&c, 3, 2, 1, 48, 1, 2, 2);
    assert_int_equal(qtool_bake_sums_add(&a, &c, err, sizeof err), -1);
    assert_non_null(strstr(err, "48 directions against 32"));
    qtool_bake_sums_free(&c);
    make_sums(&c, 3, 2, 1, 48, 2, 3, 2);
    c.ndirs = 32;
    assert_int_equal(qtool_bake_sums_add(&a, &c, err, sizeof err), -1);
    assert_non_null(strstr(err, "shard 2/3 against a split into 2"));
    c.nshards = 2, c.shard = 1, c.pmap[4] ^= 1;
    assert_int_equal(qtool_bake_sums_add(&a, &c, err, sizeof err), -1);
    assert_non_null(strstr(err, "P maps differ"));
    free(before);
    qtool_bake_sums_free(&a), qtool_bake_sums_free(&b), qtool_bake_sums_free(&c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_determinism_threads_and_shards),
        cmocka_unit_test(test_projection_of_unshadowed_plane),
        cmocka_unit_test(test_shadow_and_pmap),
        cmocka_unit_test(test_per_triangle_albedo_and_texture),
        cmocka_unit_test(test_prop_place),
        cmocka_unit_test(test_sums_roundtrip_and_version),
        cmocka_unit_test(test_sums_checksums_catch_flips),
        cmocka_unit_test(test_sums_header_fields_bounded),
        cmocka_unit_test(test_sums_add_overflow_and_mismatch),
    };
    return cmocka_run_group_tests_name("bake", tests, NULL, NULL);
}
