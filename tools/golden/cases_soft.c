/*
 * golden/cases_soft.c - soft_gradient_*: a fixed gradient (with extreme values) written through
 * platform/soft into every framebuffer format, written as spans of 1..13 pixels; an ACCUM32 buffer
 * after two passes and its resolves. Moved here from tests/soft_test.c (same data, same hashes).
 */
#include "golden/casesi.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include "qibl/soft.h"

#define ONE 65536

enum { GW = 61, GH = 19 }; /* odd sizes: partial dither tiles and resolve chunks */

/* R a horizontal ramp from -0.125 to 1.125, G a vertical ramp 0..1, B a sawtooth from -1/16 to 1,
 * plus a few extreme values; integers only. */
static void gradient(uint32_t x, uint32_t y, int32_t out[3])
{
    out[0] = -8192 + (int32_t)(x * 81920u / (GW - 1));
    out[1] = (int32_t)(y * 65536u / (GH - 1));
    out[2] = (int32_t)((x * 5u + y * 3u) % 17u) * 4096 - 4096;
    if (x == 0 && y == 0)
        out[0] = INT32_MIN, out[1] = INT32_MAX, out[2] = -1;
    if (x == GW - 1 && y == GH - 1)
        out[0] = 1, out[1] = ONE - 1, out[2] = ONE + 1;
}

/* Writes the gradient into fb, each row as spans of 1..13 pixels (starting at a row-dependent x)
 * so that span splitting is part of what the hash covers; pass 1 shifts the pattern for a second
 * accumulation. */
static qibl_status_t write_gradient(const qibl_fb_desc_t *fb, int pass)
{
    int32_t row[3 * GW];
    for (uint32_t y = 0; y < GH; ++y) {
        for (uint32_t x = 0; x < GW; ++x)
            gradient((x + (uint32_t)pass * 7u) % GW, y, row + 3 * x);
        for (uint32_t x = 0, k = y; x < GW; ++k) {
            uint32_t n = 1 + (k * 5u) % 13u;
            if (n > GW - x)
                n = GW - x;
            qibl_status_t st = qibl_soft_fb_write_row(fb, x, y, n, row + 3 * x);
            if (st != QIBL_OK)
                return st;
            x += n;
        }
    }
    return QIBL_OK;
}

static qibl_fb_desc_t fb_make(void *pixels, qibl_fb_format_t f)
{
    qibl_fb_desc_t fb;
    memset(&fb, 0, sizeof fb);
    fb.pixels = pixels, fb.format = f, fb.width = GW, fb.height = GH;
    return fb;
}

int qtool_goldens_soft(const qtool_goldens_sink_t *s)
{
    static const qtool_gcase_fb cases[] = {
        {"soft_gradient_rgba8888_linear", QIBL_FB_RGBA8888, 0, 0, 0},
        {"soft_gradient_rgba8888_srgb", QIBL_FB_RGBA8888, 1, 0, 0},
        {"soft_gradient_bgra8888_linear_exp2", QIBL_FB_BGRA8888, 0, 0, 2 * ONE},
        {"soft_gradient_bgra8888_srgb_exp075", QIBL_FB_BGRA8888, 1, 0, ONE * 3 / 4},
        {"soft_gradient_rgb565_linear", QIBL_FB_RGB565, 0, 0, 0},
        {"soft_gradient_rgb565_dither", QIBL_FB_RGB565, 0, 1, 0},
        {"soft_gradient_rgb565_srgb", QIBL_FB_RGB565, 1, 0, 0},
        {"soft_gradient_rgb565_srgb_dither", QIBL_FB_RGB565, 1, 1, 0},
    };
    int bad = 0;
    uint8_t *px = calloc((size_t)GW * GH, 12), *acc = calloc((size_t)GW * GH, 12);
    if (px == NULL || acc == NULL) {
        free(px), free(acc);
        return qtool_gcase_oom(s, "soft_gradient");
    }
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        qibl_fb_desc_t fb = fb_make(px, cases[i].format);
        qtool_gcase_fb_set(&fb, &cases[i]);
        qibl_status_t st = qibl_soft_fb_clear(&fb);
        if (st == QIBL_OK)
            st = write_gradient(&fb, 0);
        bad += st == QIBL_OK ? qtool_gcase_emit(s, cases[i].name, px, (size_t)GW * GH * qibl_soft_fb_bytes_per_pixel(fb.format))
                             : qtool_gcase_status_error(s, cases[i].name, "clear / write_row", st);
    }
    /* the accumulator after two passes, and its resolves */
    qibl_fb_desc_t src = fb_make(acc, QIBL_FB_ACCUM32);
    qibl_status_t st = qibl_soft_fb_clear(&src);
    if (st == QIBL_OK)
        st = write_gradient(&src, 0);
    if (st == QIBL_OK)
        st = write_gradient(&src, 1);
    if (st != QIBL_OK) {
        free(px), free(acc);
        return bad + qtool_gcase_status_error(s, "soft_gradient_accum32_2pass", "clear / write_row", st);
    }
    bad += qtool_gcase_emit(s, "soft_gradient_accum32_2pass", acc, (size_t)GW * GH * 12);
    qibl_fb_desc_t d = fb_make(px, QIBL_FB_RGBA8888);
    d.srgb = 1, d.exposure = ONE / 2;
    st = qibl_soft_fb_resolve(&d, &src);
    bad += st == QIBL_OK ? qtool_gcase_emit(s, "soft_gradient_resolve_rgba8888_srgb_exp05", px, (size_t)GW * GH * 4)
                         : qtool_gcase_status_error(s, "soft_gradient_resolve_rgba8888_srgb_exp05", "qibl_soft_fb_resolve", st);
    d.format = QIBL_FB_RGB565, d.dither = 1;
    st = qibl_soft_fb_resolve(&d, &src);
    bad += st == QIBL_OK ? qtool_gcase_emit(s, "soft_gradient_resolve_rgb565_srgb_dither_exp05", px, (size_t)GW * GH * 2)
                         : qtool_gcase_status_error(s, "soft_gradient_resolve_rgb565_srgb_dither_exp05", "qibl_soft_fb_resolve", st);
    free(px), free(acc);
    return bad;
}
