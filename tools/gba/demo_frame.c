/*
 * gba/demo_frame.c - see demo_frame.h.
 */
#include "demo_frame.h"

/* cos(2 pi i / 64) in Q16, i = 0..16 (the rest by symmetry) */
static const int32_t cos64[17] = {65536, 65220, 64277, 62714, 60547, 57798, 54491, 50660, 46341,
                                  41576, 36410, 30893, 25080, 19024, 12785, 6424,  0};

static int32_t cos_step(uint32_t i)
{
    i %= 64u;
    if (i <= 16u)
        return cos64[i];
    if (i <= 32u)
        return -cos64[32u - i];
    if (i <= 48u)
        return -cos64[i - 32u];
    return cos64[64u - i];
}

void demo_sun(uint32_t s, qibl_q16_t dir[3])
{
    dir[0] = cos_step(s);
    dir[1] = cos_step(s + 48u); /* sin */
    dir[2] = 37837;             /* tan(30 deg): a 30-degree elevation (not normalised: the core does) */
}

qibl_status_t demo_frame(const qibl_shmaps_t *m, uint32_t s, uint32_t y0, uint32_t y1, demo_buffers_t *b,
                         demo_hooks_t *h)
{
    const uint32_t w = m->width;
    if (w > DEMO_MAX_W || qibl_shmap_span_workspace_size(w) > sizeof b->ws)
        return QIBL_E_WORKSPACE;
    qibl_q16_t sun[3], rgb[3] = {98304, 91750, 78643}; /* warm white, 1.5 x (1, 0.93, 0.8) */
    qibl_shlight_t light;
    qibl_shmap_weights_t wt;
    demo_sun(s, sun);
    qibl_status_t st = qibl_shlight_init(&light, m->k);
    if (st == QIBL_OK)
        st = qibl_shlight_add_dir(&light, sun, rgb);
    if (st == QIBL_OK)
        st = qibl_shmap_weights(m, &light, &wt);
    /* a four-row framebuffer whose row y & 3 stands for row y: the 4 x 4 ordered dither repeats
     * every four rows, so the bytes are those of the whole frame's framebuffer */
    qibl_fb_desc_t fb = {0};
    fb.pixels = b->rgb565, fb.width = w, fb.height = 4, fb.stride = sizeof b->rgb565[0];
    fb.format = QIBL_FB_RGB565, fb.srgb = 1, fb.dither = 1;
    for (uint32_t y = y0; y < y1 && st == QIBL_OK; ++y) {
        uint32_t t0 = h->clock ? h->clock(h->user) : 0;
        st = h->relight ? h->relight(m, &wt, y, b) : qibl_shmap_relight_span(m, &wt, 0, y, w, b->row, b->ws, sizeof b->ws);
        uint32_t t1 = h->clock ? h->clock(h->user) : 0;
        if (st == QIBL_OK)
            st = qibl_soft_fb_write_row(&fb, 0, y & 3u, w, b->row);
        uint32_t t2 = h->clock ? h->clock(h->user) : 0;
        h->relight_ticks += (uint32_t)(t1 - t0), h->write_ticks += (uint32_t)(t2 - t1);
        if (st == QIBL_OK)
            h->row(h->user, y, b->rgb565[y & 3u], w);
    }
    return st;
}
