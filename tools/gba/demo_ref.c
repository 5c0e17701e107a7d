/*
 * gba/demo_ref.c - the host's frame of the GBA demo (demo.c): same maps, same sun step, same code
 * (demo_frame.c), so the CRC-32 it prints must be the ROM's; the PPM it writes holds each channel's
 * 5 bits as the GBA shows them (c << 3 | c >> 2), for the comparison with mGBA's screenshot. It
 * also checks demo_frame's four-row framebuffer against one of the whole frame (same bytes).
 *
 * usage: qibl-gba-demo-ref ASSET STEP OUT.ppm     prints "frame step <s> crc32 <8 hex>"
 * (ASSET at most 4 MiB, at most 240 pixels wide: the GBA's screen)
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "demo_frame.h"

typedef struct {
    uint32_t crc, w, h;
    uint16_t *frame;
} state;

static void keep(void *user, uint32_t y, const uint16_t *px, uint32_t n)
{
    state *s = (state *)user;
    for (uint32_t x = 0; x < n; ++x) {
        uint8_t le[2] = {(uint8_t)px[x], (uint8_t)(px[x] >> 8)};
        s->crc = qibl_crc32(s->crc, le, 2);
    }
    memcpy(s->frame + (size_t)y * s->w, px, 2u * n);
}

int main(int argc, char **argv)
{
    if (argc != 4) {
        fprintf(stderr, "usage: qibl-gba-demo-ref ASSET STEP OUT.ppm\n");
        return 2;
    }
    FILE *f = fopen(argv[1], "rb");
    static uint8_t bytes[(4 << 20) + 1]; /* the demo's assets are 1-2 MiB; 4 MiB is the cap */
    size_t n = f ? fread(bytes, 1, sizeof bytes, f) : 0;
    if (f)
        fclose(f);
    if (f == NULL || n == sizeof bytes) {
        fprintf(stderr, "qibl-gba-demo-ref: %s: %s\n", argv[1], f ? "larger than the 4 MiB cap" : "cannot open");
        return 1;
    }
    qibl_asset_t asset;
    qibl_shmaps_t m;
    qibl_status_t st = qibl_asset_open(&asset, bytes, n);
    if (st == QIBL_OK)
        st = qibl_asset_shmaps(&asset, &m);
    if (st != QIBL_OK || m.width > DEMO_MAX_W) {
        fprintf(stderr, "qibl-gba-demo-ref: %s: %s\n", argv[1], st != QIBL_OK ? qibl_soft_status_str(st) : "wider than 240");
        return 1;
    }
    uint32_t step = (uint32_t)strtoul(argv[2], NULL, 10);
    static demo_buffers_t b;
    state s = {0, m.width, m.height, malloc(2u * m.width * m.height)};
    demo_hooks_t h = {.row = keep, .user = &s};
    if (s.frame == NULL || (st = demo_frame(&m, step, 0, m.height, &b, &h)) != QIBL_OK) {
        fprintf(stderr, "qibl-gba-demo-ref: frame: %s\n", s.frame ? qibl_soft_status_str(st) : "out of memory");
        return 1;
    }
    /* the same frame through one framebuffer of the whole size: the four-row trick must agree */
    uint16_t *whole = malloc(2u * m.width * m.height);
    qibl_fb_desc_t fb = {0};
    fb.pixels = whole, fb.width = m.width, fb.height = m.height, fb.format = QIBL_FB_RGB565, fb.srgb = 1, fb.dither = 1;
    qibl_q16_t sun[3], rgb[3] = {98304, 91750, 78643};
    qibl_shlight_t light;
    qibl_shmap_weights_t w;
    demo_sun(step, sun);
    st = whole ? qibl_shlight_init(&light, m.k) : QIBL_E_WORKSPACE;
    if (st == QIBL_OK)
        st = qibl_shlight_add_dir(&light, sun, rgb);
    if (st == QIBL_OK)
        st = qibl_shmap_weights(&m, &light, &w);
    for (uint32_t y = 0; y < m.height && st == QIBL_OK; ++y) {
        st = qibl_shmap_relight_span(&m, &w, 0, y, m.width, b.row, b.ws, sizeof b.ws);
        if (st == QIBL_OK)
            st = qibl_soft_fb_write_row(&fb, 0, y, m.width, b.row);
    }
    if (st != QIBL_OK || memcmp(whole, s.frame, 2u * m.width * m.height) != 0) {
        fprintf(stderr, "qibl-gba-demo-ref: the four-row framebuffer differs from the whole frame's\n");
        return 1;
    }
    FILE *o = fopen(argv[3], "wb");
    int ok = o != NULL && fprintf(o, "P6\n%u %u\n255\n", (unsigned)m.width, (unsigned)m.height) > 0;
    for (size_t i = 0; ok && i < (size_t)m.width * m.height; ++i) {
        uint32_t v = s.frame[i], r = v >> 11, g = (v >> 6) & 31u, bl = v & 31u;
        unsigned char px[3] = {(unsigned char)(r << 3 | r >> 2), (unsigned char)(g << 3 | g >> 2),
                               (unsigned char)(bl << 3 | bl >> 2)};
        ok = fwrite(px, 1, 3, o) == 3;
    }
    if (o == NULL || fclose(o) != 0 || !ok) {
        fprintf(stderr, "qibl-gba-demo-ref: cannot write %s\n", argv[3]);
        return 1;
    }
    printf("frame step %u crc32 %08lx\n", (unsigned)step, (unsigned long)s.crc);
    free(s.frame), free(whole);
    return 0;
}
