/*
 * shmtile_test.c - per-tile adaptive k (qibl/shmtile.h): SHMT validation (every named status, every
 * truncation, *out untouched), tile views (edge tiles, bounds), the asset lookup, the bake's choice
 * of k, and relighting through tile views: with every band kept it gives the same bytes as the
 * whole maps (directional and point light), with bands dropped it stays close.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdlib.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "bake/bake.h"
#include "bake/path.h"
#include "bake/tiled.h"
#include "gen/scene.h"
#include "io/asset_write.h"
#include "qibl/shmtile.h"
#include "ref/psnr.h"

enum { W = 40, H = 20, K = 16 };

/* the procedural scene's k = 16 maps; SHMP and SHMU both from them, YLUT 8; then SHMT (drop) */
static void make_asset(double drop, uint8_t **out, size_t *n, uint8_t **pay, size_t *payn, uint32_t tiles[26])
{
    qtool_gen_maps m;
    uint8_t *base;
    size_t bn;
    assert_int_equal(qtool_gen_scene(W, H, K, QTOOL_PANO_CYLINDRICAL, &m), 0);
    assert_int_equal(qtool_bake_shmt_payload(&m, drop, pay, payn, tiles), 0);
    assert_int_equal(qtool_bake_asset_ex(&m, &m, 8, NULL, NULL, &base, &bn), 0);
    assert_int_equal(qtool_bake_asset_add(base, bn, QIBL_CHUNK_SHMT, *pay, *payn, out, n), 0);
    free(base);
    qtool_gen_free(&m);
}

static void test_parse(void **state)
{
    (void)state;
    uint8_t *asset, *p;
    size_t n, pn;
    uint32_t tiles[26];
    make_asset(0.02, &asset, &n, &p, &pn, tiles);
    free(asset);
    qibl_shmtile_t t, untouched;
    memset(&untouched, 0x5A, sizeof untouched);
    t = untouched;
    assert_int_equal(qibl_shmtile_parse(NULL, pn, &t), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_shmtile_parse(p, pn, NULL), QIBL_E_NULL_POINTER);
    for (size_t cut = 0; cut < pn; cut += cut < 200 ? 1 : 97)
        assert_int_equal(qibl_shmtile_parse(p, cut, &t), QIBL_E_ASSET_CHUNK_SIZE);
    assert_memory_equal(&t, &untouched, sizeof t);
    uint8_t *b = malloc(pn + 1);
    uint32_t nt = 3 * 2, kpad = 8; /* 40 x 20: 3 x 2 tiles, k bytes padded to 8 */
    size_t ks = QIBL_SHMTILE_HEADER + 8 * K * 3, offs = ks + kpad;
    struct {
        size_t at;
        uint32_t v;
        int u8;
        qibl_status_t want;
    } cases[] = {
        {0, 0, 0, QIBL_E_ASSET_BAD_DIMENSIONS},      {4, 20000, 0, QIBL_E_ASSET_BAD_DIMENSIONS},
        {8, 0, 0, QIBL_E_ASSET_BAD_K},               {8, 26, 0, QIBL_E_ASSET_BAD_K},
        {12, 2, 0, QIBL_E_ASSET_BAD_CHANNELS},       {16, 8, 0, QIBL_E_ASSET_BAD_FLAGS},
        {20, 1, 0, QIBL_E_ASSET_BAD_FLAGS},          {ks, 0, 1, QIBL_E_ASSET_BAD_K},
        {ks + 1, K + 1, 1, QIBL_E_ASSET_BAD_K},      {ks + nt, 1, 1, QIBL_E_ASSET_BAD_FLAGS},
        {offs, 1, 0, QIBL_E_ASSET_CHUNK_SIZE},       {offs + 8, 0, 0, QIBL_E_ASSET_CHUNK_SIZE},
        {4, 21, 0, QIBL_E_ASSET_CHUNK_SIZE}, /* one more row: sizes no longer add up */
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        memcpy(b, p, pn);
        if (cases[i].u8)
            b[cases[i].at] = (uint8_t)cases[i].v;
        else
            qtool_store_u32le(b + cases[i].at, cases[i].v);
        if (qibl_shmtile_parse(b, pn, &t) != cases[i].want)
            fail_msg("case %zu: status %d, want %d", i, (int)qibl_shmtile_parse(b, pn, &t), (int)cases[i].want);
        assert_memory_equal(&t, &untouched, sizeof t);
    }
    memcpy(b, p, pn), b[pn] = 0;
    assert_int_equal(qibl_shmtile_parse(b, pn + 1, &t), QIBL_E_ASSET_CHUNK_SIZE);
    assert_int_equal(qibl_shmtile_parse(p, pn, &t), QIBL_OK);
    assert_int_equal(t.tiles_x, 3), assert_int_equal(t.tiles_y, 2), assert_int_equal(t.kmax, K);
    /* views: the edge tiles are smaller; out of range is named, *view untouched */
    qibl_shmaps_t v, vu;
    uint32_t x0, y0;
    assert_int_equal(qibl_shmtile_view(&t, 2, 1, &v, &x0, &y0), QIBL_OK);
    assert_int_equal(v.width, 8), assert_int_equal(v.height, 4), assert_int_equal(x0, 32), assert_int_equal(y0, 16);
    assert_true(v.k == 1 || v.k == 4 || v.k == 9 || v.k == 16);
    memset(&vu, 0x33, sizeof vu);
    v = vu;
    assert_int_equal(qibl_shmtile_view(&t, 3, 0, &v, NULL, NULL), QIBL_E_SHMAP_BOUNDS);
    assert_int_equal(qibl_shmtile_view(&t, 0, 2, &v, NULL, NULL), QIBL_E_SHMAP_BOUNDS);
    assert_int_equal(qibl_shmtile_view(NULL, 0, 0, &v, NULL, NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_shmtile_view(&t, 0, 0, NULL, NULL, NULL), QIBL_E_NULL_POINTER);
    assert_memory_equal(&v, &vu, sizeof v);
    uint32_t sum = 0;
    for (int k = 0; k < 26; ++k)
        sum += tiles[k];
    assert_int_equal(sum, nt);
    free(b), free(p);
}

static void test_asset(void **state)
{
    (void)state;
    uint8_t *asset, *p, *two, *other;
    size_t n, pn, n2, no;
    uint32_t tiles[26];
    make_asset(0, &asset, &n, &p, &pn, tiles);
    assert_int_equal(tiles[K], 6); /* drop 0 keeps every band */
    qibl_asset_t a;
    qibl_shmtile_t t;
    assert_int_equal(qibl_asset_open(&a, asset, n), QIBL_OK);
    assert_int_equal(qibl_shmtile_from_asset(&a, &t), QIBL_OK);
    assert_int_equal(qibl_shmtile_from_asset(NULL, &t), QIBL_E_NULL_POINTER);
    assert_int_equal(qtool_bake_asset_add(asset, n, QIBL_CHUNK_SHMT, p, pn, &two, &n2), 0);
    assert_int_equal(qibl_asset_open(&a, two, n2), QIBL_OK);
    assert_int_equal(qibl_shmtile_from_asset(&a, &t), QIBL_E_ASSET_DUPLICATE_CHUNK);
    /* an SHMT of another size beside these SHMP */
    qtool_gen_maps m;
    uint8_t *base, *p2;
    size_t bn, p2n;
    assert_int_equal(qtool_gen_scene(W, H, 4, QTOOL_PANO_CYLINDRICAL, &m), 0);
    assert_int_equal(qtool_bake_asset(&m, 0, &base, &bn), 0);
    assert_int_equal(qibl_asset_open(&a, base, bn), QIBL_OK);
    assert_int_equal(qibl_shmtile_from_asset(&a, &t), QIBL_E_ASSET_MISSING_CHUNK);
    qtool_gen_free(&m);
    assert_int_equal(qtool_gen_scene(W - 1, H, 4, QTOOL_PANO_CYLINDRICAL, &m), 0);
    assert_int_equal(qtool_bake_shmt_payload(&m, 0, &p2, &p2n, NULL), 0);
    assert_int_equal(qtool_bake_asset_add(base, bn, QIBL_CHUNK_SHMT, p2, p2n, &other, &no), 0);
    assert_int_equal(qibl_asset_open(&a, other, no), QIBL_OK);
    assert_int_equal(qibl_shmtile_from_asset(&a, &t), QIBL_E_ASSET_MISMATCH);
    qtool_gen_free(&m);
    assert_int_equal(qtool_bake_shmt_payload(&m, 1.5, &p2, &p2n, NULL), -1);
    free(asset), free(p), free(two), free(base), free(p2), free(other);
}

static void test_relight(void **state)
{
    (void)state;
    uint8_t *asset, *p, *asset2, *p2;
    size_t n, pn, n2, p2n;
    uint32_t tiles[26], tiles2[26];
    make_asset(0, &asset, &n, &p, &pn, tiles);
    make_asset(0.05, &asset2, &n2, &p2, &p2n, tiles2);
    assert_true(tiles2[K] < 6); /* some tile dropped bands */
    uint8_t whole[W * H * 3], tiled[W * H * 3], fewer[W * H * 3];
    qibl_status_t st;
    qtool_rt_light lights[3] = {{0, {0.3, -0.5, 0.8}, {0, 0, 0}, {1.5, 1.2, 1.0}, 0},
                                {1, {0, 0, 0}, {0.5, 0.2, -0.3}, {2.0, 2.0, 2.0}, 1},
                                {1, {0, 0, 0}, {-1.0, 0.7, 0.4}, {3.0, 2.5, 2.0}, 2}};
    for (int i = 0; i < 3; ++i) {
        /* directional: SHMP (the same maps); point: SHMU with the LUT */
        assert_int_equal(qtool_bake_relight8_lin(asset, n, &lights[i], 1, 0, 1, whole, NULL, NULL, &st), 0);
        assert_int_equal(qtool_bake_relight_tiled8(asset, n, &lights[i], -1, 0, 0, tiled, NULL, &st), 0);
        assert_memory_equal(whole, tiled, sizeof whole);
        assert_int_equal(qtool_bake_relight_tiled8(asset2, n2, &lights[i], -1, 0, 0, fewer, NULL, &st), 0);
        assert_true(qtool_ref_psnr8(qtool_bake_mse(whole, fewer, NULL, W * H)) > 30);
    }
    assert_true(p2n < pn);
    /* no path 0 in these assets: named */
    assert_int_equal(qtool_bake_relight_tiled8(asset, n, &lights[0], 0, 0, 0, tiled, NULL, &st), -1);
    assert_int_equal(st, QIBL_E_ASSET_MISSING_CHUNK);
    free(asset), free(p), free(asset2), free(p2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_parse),
        cmocka_unit_test(test_asset),
        cmocka_unit_test(test_relight),
    };
    return cmocka_run_group_tests_name("shmtile", tests, NULL, NULL);
}
