/*
 * relight_test.c - tools/relight, the library behind `qibl relight` and `qibl lights`, called
 * directly: the light list's limit and early colour, the rotation check by name, the suns' SH
 * against the core's own and their sum refused beyond Q16.16 with nothing written, the sun regions
 * of a probe, the point lamps' default colour (median distance, sky skipped, falloff, cap) as
 * qtool_relight_points applies it to an asset's P map, one light's frame against the bake's own
 * relight (the same bytes), the asset's named errors, the light-path
 * pick on an asset without paths, and `qibl lights`' picture limits and fit (a black probe is an
 * answer, a lone bright pixel gives the light toward it).
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "bake/bake.h"
#include "io/asset_write.h"
#include "relight/light.h"
#include "relight/lights.h"
#include "relight/relight.h"

/* ---- the light list ------------------------------------------------------------------------------ */

static void test_light_list(void **state)
{
    (void)state;
    qtool_relight_light_list ll;
    qtool_relight_light_list_init(&ll);
    assert_int_equal(ll.count, 0);
    assert_int_equal(ll.layout, QTOOL_PROBE_LAYOUT_AUTO);
    assert_int_equal(ll.mode, QTOOL_RELIGHT_PROBE_SH);
    assert_false(qtool_relight_light_list_directional(&ll));
    /* an early --rgb colours the first light only */
    ll.early_rgb = 1, ll.rgb0[0] = 3 << 16, ll.rgb0[1] = 2 << 16, ll.rgb0[2] = 1 << 16;
    const int32_t v[3] = {0, 0, 65536};
    for (uint32_t i = 0; i < QTOOL_RELIGHT_MAX_SOURCES; ++i)
        assert_int_equal(qtool_relight_light_list_add(&ll, (int)(i & 1), v), 0);
    assert_int_equal(ll.src[0].rgb[0], 3 << 16);
    assert_true(ll.src[0].have_rgb);
    assert_int_equal(ll.src[1].rgb[0], 65536);
    assert_false(ll.src[1].have_rgb);
    assert_int_equal(ll.suns, QTOOL_RELIGHT_MAX_SOURCES / 2);
    assert_int_equal(ll.points, QTOOL_RELIGHT_MAX_SOURCES / 2);
    assert_true(qtool_relight_light_list_directional(&ll));
    /* full: refused, nothing written */
    qtool_relight_light_list before = ll;
    assert_int_equal(qtool_relight_light_list_add(&ll, 0, v), -1);
    assert_memory_equal(&before, &ll, sizeof ll);
}

static void test_rotation(void **state)
{
    (void)state;
    double r[3][3], v[9], worst, det;
    qtool_relight_yaw(90, r);
    /* +x turns toward +y */
    assert_true(fabs(r[1][0] - 1) < 1e-12 && fabs(r[0][0]) < 1e-12 && fabs(r[2][2] - 1) < 1e-12);
    memcpy(v, r, sizeof v);
    assert_int_equal(qtool_relight_rotation_check(v, &worst, &det), 0);
    assert_true(worst < 1e-12 && fabs(det - 1) < 1e-12);
    /* a mirror: orthonormal, det -1 */
    const double m[9] = {0, 1, 0, 1, 0, 0, 0, 0, 1};
    assert_int_equal(qtool_relight_rotation_check(m, &worst, &det), -1);
    assert_true(fabs(det + 1) < 1e-12);
    /* rows within 2^-16 of orthonormal pass; beyond it they do not */
    double s[9] = {1 + 1.0 / 262144, 0, 0, 0, 1, 0, 0, 0, 1};
    assert_int_equal(qtool_relight_rotation_check(s, &worst, &det), 0);
    s[0] = 1 + 1.0 / 65536;
    assert_int_equal(qtool_relight_rotation_check(s, &worst, &det), -1);
    assert_true(worst > 1.0 / 65536);
}

/* ---- the SH of the suns -------------------------------------------------------------------------- */

static void test_suns_sh(void **state)
{
    (void)state;
    qtool_relight_light_list ll;
    qtool_relight_light_list_init(&ll);
    const int32_t d1[3] = {20000, -30000, 50000}, d2[3] = {-65536, 0, 1000};
    assert_int_equal(qtool_relight_light_list_add(&ll, 0, d1), 0);
    assert_int_equal(qtool_relight_light_list_add(&ll, 0, d2), 0);
    ll.src[1].rgb[0] = 2 << 16, ll.src[1].rgb[2] = 1 << 15;
    qibl_shlight_t got, a, b;
    char err[256] = "";
    int faint = -1;
    assert_int_equal(qtool_relight_light_sh(&ll, 9, NULL, &got, &faint, err, sizeof err), 0);
    assert_int_equal(faint, 0);
    assert_int_equal(qibl_shlight_init(&a, 9), QIBL_OK);
    assert_int_equal(qibl_shlight_add_dir(&a, d1, ll.src[0].rgb), QIBL_OK);
    assert_int_equal(qibl_shlight_init(&b, 9), QIBL_OK);
    assert_int_equal(qibl_shlight_add_dir(&b, d2, ll.src[1].rgb), QIBL_OK);
    for (int c = 0; c < 3; ++c)
        for (uint32_t i = 0; i < 9; ++i)
            assert_int_equal(got.c[c][i], a.c[c][i] + b.c[c][i]);
    /* two suns at the top of Q16.16 add up beyond it: refused by name, out untouched */
    for (int j = 0; j < 2; ++j)
        ll.src[j].rgb[0] = ll.src[j].rgb[1] = ll.src[j].rgb[2] = INT32_MAX, ll.src[j].v[0] = 0, ll.src[j].v[1] = 0,
        ll.src[j].v[2] = 65536;
    qibl_shlight_t out;
    memset(&out, 0x5a, sizeof out);
    qibl_shlight_t copy = out;
    assert_int_equal(qtool_relight_light_sh(&ll, 9, NULL, &out, NULL, err, sizeof err), -1);
    assert_non_null(strstr(err, "the suns add up beyond the Q16.16 light"));
    assert_memory_equal(&out, &copy, sizeof out);
    /* a CSV that is not there: its reader's message */
    qtool_relight_light_list_init(&ll);
    ll.csv = "/nonexistent/lights.csv";
    assert_int_equal(qtool_relight_light_sh(&ll, 4, NULL, &out, NULL, err, sizeof err), -1);
    assert_non_null(strstr(err, "/nonexistent/lights.csv"));
}

/* ---- the sun regions of a probe -------------------------------------------------------------------- */

static void test_probe_suns(void **state)
{
    (void)state;
    /* a 64 x 32 probe's regions: a one-pixel region far denser than the rest, and a sky of equal ones */
    qibl_lightprobe_light_t l[5];
    memset(l, 0, sizeof l);
    for (int i = 0; i < 4; ++i) {
        l[i].u0 = (uint32_t)(16 * i), l[i].u1 = (uint32_t)(16 * i + 16), l[i].v0 = 0, l[i].v1 = 32;
        l[i].rgb[0] = l[i].rgb[1] = l[i].rgb[2] = 1000;
    }
    uint32_t idx[QTOOL_RELIGHT_SUN_MAX];
    assert_int_equal(qtool_relight_probe_suns(l, 4, 64, 32, idx), 0); /* overcast: no sun */
    l[4].u0 = 10, l[4].u1 = 11, l[4].v0 = 8, l[4].v1 = 9;
    l[4].rgb[0] = l[4].rgb[1] = l[4].rgb[2] = 4000;
    assert_int_equal(qtool_relight_probe_suns(l, 5, 64, 32, idx), 1);
    assert_int_equal(idx[0], 4);
}

/* ---- point lamps without a colour ------------------------------------------------------------------ */

static void test_point_default(void **state)
{
    (void)state;
    /* distances 1, 2, 3 from the origin, and two sky points (ignored) */
    const double pts[] = {1, 0, 0, 0, 2, 0, 0, 0, 3, QTOOL_RELIGHT_SKY_DIST, 0, 0, 0, 0, -QTOOL_RELIGHT_SKY_DIST};
    const double o[3] = {0, 0, 0};
    double c0, d;
    assert_int_equal(qtool_relight_point_default(pts, 5, o, 1, &c0, &d), 0);
    assert_true(d == 2 && c0 == QTOOL_RELIGHT_POINT_GREY * 2);
    assert_int_equal(qtool_relight_point_default(pts, 5, o, 2, &c0, &d), 0);
    assert_true(c0 == QTOOL_RELIGHT_POINT_GREY * 4);
    assert_int_equal(qtool_relight_point_default(pts + 9, 2, o, 1, &c0, &d), 0); /* all sky */
    assert_true(d == 1 && c0 == QTOOL_RELIGHT_POINT_GREY);
    const double far[] = {500, 0, 0};
    assert_int_equal(qtool_relight_point_default(far, 1, (const double[3]){-100000, 0, 0}, 2, &c0, &d), 0);
    assert_true(c0 == QTOOL_RELIGHT_Q16_MAX); /* capped to what Q16.16 holds */
}

/* a 6 x 2 asset (SHMP k4, P map at distance 1 + x) at path; lut adds nothing (no YLUT) */
static void write_asset(const char *path)
{
    enum { W = 6, H = 2, K = 4 };
    qtool_asset_builder b;
    int32_t scale[3 * K], bias[3 * K], xyz[3 * W * H];
    uint8_t planes[W * H * K * 3];
    for (int i = 0; i < 3 * K; ++i)
        scale[i] = 1 << 16, bias[i] = 0;
    for (size_t i = 0; i < sizeof planes; ++i)
        planes[i] = (uint8_t)(i * 37);
    for (int i = 0; i < W * H; ++i)
        xyz[3 * i] = (1 + i % W) << 16, xyz[3 * i + 1] = 0, xyz[3 * i + 2] = 0;
    qtool_asset_builder_init(&b);
    assert_int_equal(qtool_asset_add_shmp(&b, W, H, K, 3, scale, bias, planes), 0);
    assert_int_equal(qtool_asset_add_pmap(&b, W, H, xyz), 0);
    assert_int_equal(qtool_asset_write_file(&b, path, 0), 0);
    qtool_asset_builder_free(&b);
}

static void test_asset_and_points(void **state)
{
    (void)state;
    char dir[] = "/tmp/qibl_relight_XXXXXX", path[64], err[600] = "";
    assert_non_null(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/a.qibl", dir);
    write_asset(path);
    qtool_relight_asset s;
    assert_int_equal(qtool_relight_asset_open(&s, "/nonexistent.qibl", 0, 0, err, sizeof err), -1);
    assert_non_null(strstr(err, "/nonexistent.qibl"));
    assert_null(s.bytes);
    /* a LUT asked of an asset that has none: named, nothing left open */
    assert_int_equal(qtool_relight_asset_open(&s, path, 1, 1, err, sizeof err), -1);
    assert_non_null(strstr(err, path));
    assert_null(s.bytes);
    assert_int_equal(qtool_relight_asset_open(&s, path, 1, 0, err, sizeof err), 0);
    assert_int_equal(s.m.width, 6);
    assert_false(s.use_occ || s.occ_unusable);
    /* two lamps at the origin: the first without --rgb gets C0 = 2 x the median distance (4 of 1..6) */
    qtool_relight_opts o = QTOOL_RELIGHT_OPTS_DEFAULT;
    const int32_t at0[3] = {0, 0, 0};
    assert_int_equal(qtool_relight_light_list_add(&o.lights, 1, at0), 0);
    assert_int_equal(qtool_relight_light_list_add(&o.lights, 1, at0), 0);
    o.lights.src[1].have_rgb = 1;
    qibl_pointlight_t pts[QTOOL_RELIGHT_MAX_SOURCES];
    qtool_relight_point_note notes[QTOOL_RELIGHT_MAX_SOURCES];
    uint32_t n = 0;
    assert_int_equal(qtool_relight_points(&o, &s, pts, &n, notes, err, sizeof err), 0);
    assert_int_equal(n, 2);
    assert_true(notes[0].set && notes[0].d == 4 && notes[0].c0 == 8);
    assert_false(notes[1].set);
    assert_int_equal(pts[0].rgb[0], 8 << 16);
    assert_int_equal(o.lights.src[0].rgb[1], 8 << 16); /* written back for --gles */
    assert_int_equal(pts[1].rgb[0], 65536);
    /* the asset has no light paths: said by name */
    uint32_t index = 99;
    assert_int_equal(qtool_relight_pick_path(&s.a, "a.qibl", "sun", &index, err, sizeof err), -1);
    assert_non_null(strstr(err, "a.qibl: no light paths"));
    assert_int_equal(index, 99);
    qtool_relight_asset_free(&s);
    assert_null(s.bytes);
    unlink(path);
    rmdir(dir);
}

/* One light through qtool_relight_frame gives the bytes qtool_bake_relight8_lin gives (relight.h),
 * for a sun and for a lamp in each sampling the asset allows (poly, direct SH). */
static void test_frame_one_light(void **state)
{
    (void)state;
    char dir[] = "/tmp/qibl_relight_XXXXXX", path[64], err[600] = "";
    assert_non_null(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/a.qibl", dir);
    write_asset(path);
    qtool_relight_asset s;
    assert_int_equal(qtool_relight_asset_open(&s, path, 1, 0, err, sizeof err), 0);
    const size_t np = (size_t)s.m.width * s.m.height;
    uint8_t got8[6 * 2 * 3], want8[6 * 2 * 3];
    float got[6 * 2 * 3], want[6 * 2 * 3];
    qibl_status_t st;
    for (int kind = 0; kind < 3; ++kind) {
        qtool_rt_light l = {.point = kind > 0, .dir = {0.25, -0.5, 1}, .pos = {0.5, 0.25, 0.75}, .rgb = {1.5, 1, 0.5},
                            .falloff = 1};
        const qibl_q16_t q[3] = {16384, -32768, 65536}, pos[3] = {32768, 16384, 49152}, rgb[3] = {98304, 65536, 32768};
        qibl_shlight_t sh;
        qibl_pointlight_t pl = {{pos[0], pos[1], pos[2]}, {rgb[0], rgb[1], rgb[2]}, QIBL_FALLOFF_INV_DIST, 0,
                                kind == 1 ? QIBL_POINT_POLY : QIBL_LUT_BILINEAR};
        assert_int_equal(qibl_shlight_init(&sh, s.m.k), QIBL_OK);
        assert_int_equal(qibl_shlight_add_dir(&sh, q, rgb), QIBL_OK);
        memset(got8, 1, sizeof got8), memset(want8, 2, sizeof want8);
        assert_int_equal(qtool_relight_frame(&s.m, kind ? NULL : &sh, &s.mp, &s.pm, NULL, NULL, &pl, kind ? 1 : 0,
                                             65536, 1, got8, got, NULL, &st), 0);
        assert_int_equal(qtool_bake_relight8_lin(s.bytes, s.n, &l, kind == 1 ? 3 : 0, 65536, 1, want8, want, NULL,
                                                 &st), 0);
        assert_memory_equal(got8, want8, np * 3);
        assert_memory_equal(got, want, np * 3 * sizeof(float));
        int lit = 0; /* not two black frames */
        for (size_t i = 0; i < np * 3; ++i)
            lit += got[i] > 0 && got8[i] > 0;
        assert_true(lit > 3);
    }
    qtool_relight_asset_free(&s);
    unlink(path);
    rmdir(dir);
}

/* ---- qibl lights --------------------------------------------------------------------------------- */

static void test_lights_zoom(void **state)
{
    (void)state;
    assert_int_equal(qtool_relight_lights_zoom(1024, 512, 0), 1);
    assert_int_equal(qtool_relight_lights_zoom(100, 50, 0), 11);
    assert_int_equal(qtool_relight_lights_zoom(100, 50, 3), 3);
    const int sizes[][2] = {{1024, 512}, {64, 32}, {65535, 1}, {3000, 1500}};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; ++i) {
        int w = sizes[i][0], h = sizes[i][1];
        uint64_t z = qtool_relight_lights_max_zoom(w, h);
        assert_int_equal(qtool_relight_lights_zoom_fits(w, h, (int)z), z == 1 && w * (int64_t)h > (1 << 25) ? -1 : 0);
        assert_int_equal(qtool_relight_lights_zoom_fits(w, h, (int)z + 1), -1);
    }
}

static void test_lights_fit(void **state)
{
    (void)state;
    enum { W = 32, H = 16 };
    uint8_t px[W * H * 4];
    memset(px, 0, sizeof px);
    qtool_relight_lights_probe p = {W, H, px};
    qtool_relight_lights_opts o = QTOOL_RELIGHT_LIGHTS_OPTS_DEFAULT;
    o.path = "black.hdr", o.n = 4;
    qibl_lightprobe_light_t dummy[1], *L = dummy; /* must be cleared */
    qibl_lightprobe_result_t res;
    char err[256] = "";
    assert_int_equal(qtool_relight_lights_fit(&o, &p, &L, &res, err, sizeof err), 1);
    assert_null(L);
    assert_non_null(strstr(err, "black.hdr"));
    /* one bright pixel on the equator at u = 8 (phi = 8.5 x 2 pi / 32): every light points near it */
    uint8_t *q = px + 4 * (8 * W + 8);
    q[0] = q[1] = q[2] = 200, q[3] = 140;
    o.path = "one.hdr", o.n = 1;
    for (int as = 0; as < 3; ++as) {
        o.as = (qtool_relight_lights_as)as;
        assert_int_equal(qtool_relight_lights_fit(&o, &p, &L, &res, err, sizeof err), 0);
        assert_int_equal(res.count, 1);
        double phi = atan2(L[0].dir[1] / 1073741824.0, L[0].dir[0] / 1073741824.0);
        assert_true(fabs(phi - 8.5 * 2 * 3.14159265358979323846 / W) < 0.05);
        assert_true(fabs(L[0].dir[2] / 1073741824.0) < 0.2);
        uint8_t *img = qtool_relight_lights_draw(&p, 2, L, res.count);
        assert_non_null(img);
        free(img), free(L);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_light_list),
        cmocka_unit_test(test_rotation),
        cmocka_unit_test(test_suns_sh),
        cmocka_unit_test(test_probe_suns),
        cmocka_unit_test(test_point_default),
        cmocka_unit_test(test_asset_and_points),
        cmocka_unit_test(test_frame_one_light),
        cmocka_unit_test(test_lights_zoom),
        cmocka_unit_test(test_lights_fit),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
