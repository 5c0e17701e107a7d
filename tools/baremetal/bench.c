/*
 * baremetal/bench.c - instructions per relit pixel on the emulated MCU, and the worked example of
 * docs/porting.md: a panorama relit by streaming rows from flash through a one-row RAM buffer.
 *
 * Run under qemu with -icount shift=0: the virtual clock then advances exactly 1 ns per guest
 * instruction, whatever the host does, and the board's timer (semi.h) reads that clock. So a count
 * here is "guest instructions retired", deterministic, not cycles: a real Cortex-M4 spends 1 cycle
 * on most of them, 2+ on loads after loads, taken branches and flash wait states, 1 on MUL/SMLAD.
 * On MPS2 the timer ticks every 40 instructions (25 MHz); each figure spans 100000+ instructions,
 * so the tick costs < 0.05 %. On RISC-V the instret counter gives the count itself (semi.h).
 *
 * Output: "RESULT mcu.<tag>_<what> <value>" lines (tag from BM_TAG: m0, m4, rv32) and lines
 * starting with "stream" for the example. Exit status 1 if a call failed or the streamed rows
 * differ from the directly relit ones.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "io/sha256.h"
#include "qibl/shmap.h"
#include "qibl/soft.h"
#include "semi.h"

#ifndef BM_TAG
#define BM_TAG "mcu"
#endif

enum { W = 320, H = 240, BENCH_ROWS = 8, CH = 3 };

static uint32_t rng_state = 2026u;
static uint32_t rnd(void)
{
    rng_state = rng_state * 1664525u + 1013904223u; /* LCG: the data only has to be busy */
    return rng_state >> 8;
}

static int failed;
static void check(qibl_status_t st, const char *what)
{
    if (st != QIBL_OK) {
        bm_puts("bench: "), bm_puts(what), bm_puts(" failed\n");
        failed = 1;
    }
}

/* "RESULT mcu.<tag>_<name> <insns / px with two decimals>" */
static void result(const char *name, uint64_t insns, uint32_t px)
{
    uint64_t c = (insns * 100u + px / 2u) / px;
    char frac[3] = {(char)('0' + c / 10u % 10u), (char)('0' + c % 10u), 0};
    bm_puts("RESULT mcu." BM_TAG "_"), bm_puts(name), bm_puts(" ");
    bm_putu((uint32_t)(c / 100u)), bm_puts("."), bm_puts(frac), bm_puts("\n");
}

/* maps of W x H (planar, as the asset stores them), params like packed maps, a P map on a cylinder */
static void make_maps(qibl_shmaps_t *m, qibl_pmap_t *p, uint32_t k, uint8_t *params, uint8_t *planes, uint8_t *points)
{
    memset(m, 0, sizeof *m); /* zero = the planar layout and every field yet to come */
    m->width = W, m->height = H, m->k = k, m->channels = CH;
    for (uint32_t i = 0; i < k * CH; ++i) {
        int32_t sc = (int32_t)(rnd() % 131072u) - 65536;
        int32_t bi = -128 * sc + (int32_t)(rnd() % 2001u) - 1000;
        memcpy(params + 8 * i, &sc, 4), memcpy(params + 8 * i + 4, &bi, 4); /* little-endian targets */
    }
    for (size_t i = 0; i < (size_t)W * H * k * CH; ++i)
        planes[i] = (uint8_t)((i * 7u + (i / W) * 3u + (rnd() & 31u)) & 0xFFu);
    m->params = params, m->planes = planes;
    for (uint32_t y = 0; y < H; ++y)
        for (uint32_t x = 0; x < W; ++x) {
            int32_t q[3] = {(int32_t)(x * 40000u) - W * 20000, (int32_t)((x * 7u + y * 3u) % 11u) * 30000 - 150000,
                            (int32_t)(y * 5000u) - H * 2500};
            memcpy(points + ((size_t)y * W + x) * 12u, q, 12);
        }
    p->width = W, p->height = H, p->points = points;
}

/* the bench's light: the sun, and with sky a blue sky straight up; its weights for m */
static void sun_weights(const qibl_shmaps_t *m, uint32_t k, int sky, qibl_shmap_weights_t *w)
{
    qibl_shlight_t l;
    const qibl_q16_t sun[3] = {40000, 25000, 52000}, sun_rgb[3] = {150000, 120000, 90000};
    const qibl_q16_t up[3] = {0, 0, 65536}, sky_rgb[3] = {20000, 30000, 52000};
    check(qibl_shlight_init(&l, k), "shlight_init");
    check(qibl_shlight_add_dir(&l, sun, sun_rgb), "add_dir");
    if (sky)
        check(qibl_shlight_add_dir(&l, up, sky_rgb), "add_dir");
    check(qibl_shmap_weights(m, &l, w), "weights");
}

static uint64_t calibrate(void)
{
    /* 100000 iterations of a two-instruction loop */
    uint64_t t0 = bm_insn_clock();
#if defined(__ARM_ARCH_6M__) /* GCC's Thumb-1 inline assembly is in divided syntax: sub sets flags */
    uint32_t n = 100000u;
    __asm__ volatile("1: sub %0, #1\n bne 1b" : "+l"(n) : : "cc");
#elif defined(__arm__)
    uint32_t n = 100000u;
    __asm__ volatile("1: subs %0, %0, #1\n bne 1b" : "+l"(n) : : "cc");
#else
    uint32_t n = 100000u;
    __asm__ volatile("1: addi %0, %0, -1\n bnez %0, 1b" : "+r"(n));
#endif
    return bm_insn_clock() - t0;
}

int main(void)
{
    static int32_t row[3 * W];
    static int32_t ws[(W * (2 * 25 + 32) + 3) / 4]; /* int32 storage: the span calls need 4-byte alignment */
    static uint16_t fb565[W * BENCH_ROWS];
    uint8_t *params = malloc(8u * 16u * CH), *planes = malloc((size_t)W * H * 16u * CH), *points = malloc((size_t)W * H * 12u);
    size_t vs = qibl_ylut_values_size(16, 16);
    uint8_t *vals = malloc(vs);
    if (params == NULL || planes == NULL || points == NULL || vals == NULL) {
        bm_puts("bench: out of memory\n");
        return 1;
    }
    /* what a handheld-sized panorama needs, from the core's own size functions (docs/porting.md) */
    static const uint32_t sizes[2][2] = {{320, 240}, {480, 272}};
    for (int si = 0; si < 2; ++si)
        for (uint32_t k = 4; k <= 16; k += k == 4 ? 5u : 7u) {
            uint32_t w = sizes[si][0], h = sizes[si][1];
            bm_puts("mem "), bm_putu(w), bm_puts(" "), bm_putu(h), bm_puts(" "), bm_putu(k);
            bm_puts(" maps "), bm_putu(w * h * k * CH + 8u * k * CH);
            bm_puts(" pmap "), bm_putu(w * h * 12u);
            bm_puts(" ylut16 "), bm_putu((uint32_t)qibl_ylut_values_size(16, k));
            bm_puts(" span_ws "), bm_putu((uint32_t)qibl_shmap_span_workspace_size(w));
            bm_puts(" point_ws "), bm_putu((uint32_t)qibl_shmap_point_workspace_size(k, w));
            bm_puts(" row "), bm_putu(3u * w * 4u);
            bm_puts(" stream_row "), bm_putu(w * k * CH);
            bm_puts(" fb565 "), bm_putu(w * h * 2u), bm_puts("\n");
        }
    bm_clock_start();
    uint64_t cal = calibrate();
    bm_puts("bench: a 200000-instruction loop counts "), bm_putu((uint32_t)cal), bm_puts(" (-icount shift=0: 1 ns of emulated time per instruction)\n");

    const uint32_t npx = W * BENCH_ROWS;
    const uint32_t ks[3] = {4, 9, 16};
    for (int ki = 0; ki < 3; ++ki) {
        uint32_t k = ks[ki];
        char tag[24] = "dir_k";
        qibl_shmaps_t m;
        qibl_pmap_t p;
        make_maps(&m, &p, k, params, planes, points);
        /* directional: sun + sky */
        qibl_shmap_weights_t w;
        sun_weights(&m, k, 1, &w);
        uint64_t t0 = bm_insn_clock();
        for (uint32_t y = 0; y < BENCH_ROWS; ++y)
            check(qibl_shmap_relight_span(&m, &w, 0, y, W, row, ws, sizeof ws), "relight_span");
        uint64_t dir = bm_insn_clock() - t0;
        /* the framebuffer write after it (RGB565, sRGB, dithered: the handheld format) */
        qibl_fb_desc_t fb = {0};
        fb.pixels = fb565, fb.width = W, fb.height = BENCH_ROWS, fb.format = QIBL_FB_RGB565, fb.srgb = 1, fb.dither = 1;
        t0 = bm_insn_clock();
        for (uint32_t y = 0; y < BENCH_ROWS; ++y)
            check(qibl_soft_fb_write_row(&fb, 0, y, W, row), "fb_write_row");
        uint64_t fbw = bm_insn_clock() - t0;
        /* point light: direct SH, a 16x16-per-face LUT bilinear and nearest, then Q2.14 polynomials */
        check(qibl_ylut_build(16, k, vals, vs), "ylut_build");
        qibl_ylut_t lut = {16, k, vals, vs};
        uint64_t pt[4];
        for (int mode = 0; mode < 4; ++mode) {
            qibl_pointlight_t pl = {{30000, -90000, 20000}, {200000, 160000, 120000}, QIBL_FALLOFF_INV_DIST2, 0,
                                    mode == 2 ? QIBL_LUT_NEAREST : mode == 3 ? QIBL_POINT_POLY : QIBL_LUT_BILINEAR};
            qibl_shmap_point_t st;
            check(qibl_shmap_point_prepare(&m, &p, mode == 1 || mode == 2 ? &lut : NULL, &pl, &st), "point_prepare");
            t0 = bm_insn_clock();
            for (uint32_t y = 0; y < BENCH_ROWS; ++y)
                check(qibl_shmap_point_span(&st, 0, y, W, row, ws, sizeof ws), "point_span");
            pt[mode] = bm_insn_clock() - t0;
        }
        tag[5] = (char)('0' + (k >= 10 ? k / 10 : k)), tag[6] = k >= 10 ? (char)('0' + k % 10) : 0, tag[7] = 0;
        char name[48];
        const char *suffix[6] = {"_insn_per_px", "_point_direct_insn_per_px", "_point_lut16_insn_per_px",
                                 "_point_lut16_nearest_insn_per_px", "_point_poly_insn_per_px",
                                 "_fb_rgb565_dither_insn_per_px"};
        const uint64_t v[6] = {dir, pt[0], pt[1], pt[2], pt[3], fbw};
        for (int i = 0; i < 6; ++i) {
            strcpy(name, i == 0 ? tag : tag + 4); /* "dir_k9_insn_per_px", "k9_point_..." */
            strcat(name, suffix[i]);
            result(name, v[i], npx);
        }
        if (k == 9) { /* the headline figures of the issue: k = 9, directional and point (the fastest
                       * point mode, QIBL_POINT_POLY; direct SH was the headline before) */
            result("dir_insn_per_px", dir, npx);
            result("point_insn_per_px", pt[3], npx);
        }
    }

    /* The worked example: the k = 9 panorama "in flash" (here: the PSRAM copy above), relit row by
     * row through one RAM row of all planes (W * k * 3 bytes) and a one-row view, against the
     * direct relighting of the whole map. The bytes must be the same. */
    {
        const uint32_t k = 9;
        qibl_shmaps_t m;
        qibl_pmap_t p;
        make_maps(&m, &p, k, params, planes, points);
        qibl_shmap_weights_t w;
        sun_weights(&m, k, 0, &w);
        static uint8_t ramrow[W * 9 * CH];
        qtool_sha256_t direct, streamed;
        qtool_sha256_init(&direct), qtool_sha256_init(&streamed);
        for (uint32_t y = 0; y < H; ++y) {
            check(qibl_shmap_relight_span(&m, &w, 0, y, W, row, ws, sizeof ws), "relight_span");
            qtool_sha256_update(&direct, row, sizeof row);
        }
        uint64_t total = 0, copy = 0;
        for (uint32_t y = 0; y < H; ++y) {
            uint64_t c0 = bm_insn_clock();
            for (uint32_t pl = 0; pl < k * CH; ++pl) /* the flash read: k*3 runs of W bytes */
                memcpy(ramrow + (size_t)pl * W, m.planes + ((size_t)pl * H + y) * W, W);
            uint64_t c1 = bm_insn_clock();
            qibl_shmaps_t view = m; /* same params, one row of planes */
            view.height = 1, view.planes = ramrow;
            check(qibl_shmap_relight_span(&view, &w, 0, 0, W, row, ws, sizeof ws), "relight_span (row view)");
            total += bm_insn_clock() - c0, copy += c1 - c0; /* (the hash below is the check, not the work) */
            qtool_sha256_update(&streamed, row, sizeof row);
        }
        uint8_t a[32], b[32];
        qtool_sha256_final(&direct, a), qtool_sha256_final(&streamed, b);
        int same = memcmp(a, b, 32) == 0;
        bm_puts("stream: 320x240 k=9 panorama, rows through a "), bm_putu(W * 9 * CH), bm_puts("-byte RAM row: ");
        bm_puts(same ? "identical to relighting the whole map\n" : "DIFFERENT from relighting the whole map\n");
        result("stream_k9_insn_per_px", total, W * H);
        result("stream_k9_copy_insn_per_px", copy, W * H);
        failed |= !same;
    }
    free(params), free(planes), free(points), free(vals);
    return failed;
}
