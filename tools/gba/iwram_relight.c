/*
 * gba/iwram_relight.c - see iwram_relight.h. Compiled as ARM code into IWRAM (the iwram_ name:
 * gba.ld), as the kernels it calls: from cartridge ROM this glue's Thumb code cost about 2 cycles
 * per pixel of the relight's budget.
 */
#include "iwram_relight.h"

/* relight_arm.S: one channel, 8n pixels, one kernel per k; frame as documented there */
void gba_relight8_k4(const uint8_t *src, const uint32_t *frame);
void gba_relight8_k9(const uint8_t *src, const uint32_t *frame);

enum { FRAME_WORDS = 24 }; /* relight_arm.S copies whole groups of four */

/* chan_fast's condition (core/src/shmap.c): r = -shift in 1..30 and |bias| <= 2^30 */
static int fast_channel(const qibl_shmap_weights_t *w, uint32_t ch)
{
    return w->shift[ch] < 0 && w->shift[ch] > -31 && w->bias[ch] >= -(INT64_C(1) << 30) &&
           w->bias[ch] <= (INT64_C(1) << 30);
}

qibl_status_t gba_relight_row(const qibl_shmaps_t *m, const qibl_shmap_weights_t *w, uint32_t y, demo_buffers_t *b)
{
    const uint32_t n = m->width;
    /* ours: planar RGB maps (what the demo checks), k = 4 or 9, whole steps of 8 pixels,
     * word-aligned planes (then every row piece is: n is a multiple of 8), the fast scaling */
    int ours = qibl_shmap_check(m) == QIBL_OK && w != NULL && m->layout == QIBL_SHMAPS_PLANAR && w->k == m->k &&
               w->channels == m->channels && m->channels == 3u && (m->k == 4u || m->k == 9u) && y < m->height &&
               n % 8u == 0u && ((uintptr_t)m->planes & 3u) == 0u;
    for (uint32_t ch = 0; ours && ch < 3u; ++ch)
        ours = fast_channel(w, ch);
    if (!ours) /* the core checks and says why, or relights it its own way */
        return qibl_shmap_relight_span(m, w, 0, y, n, b->row, b->ws, sizeof b->ws);
    const uint32_t k = m->k;
    const size_t plane = (size_t)n * m->height;
    void (*kernel)(const uint8_t *, const uint32_t *) = k == 4u ? gba_relight8_k4 : gba_relight8_k9;
    for (uint32_t ch = 0; ch < 3u; ++ch) {
        /* chan_fast's constants: u0 = 2^(r-1) + 2^31, bb = bias - 2^(31-r) */
        const uint32_t r = (uint32_t)-w->shift[ch];
        const uint8_t *src = qibl_shmaps_plane(m, 0u, ch) + (size_t)y * n;
        /* filled word by word: an initialiser with zeros is a memset call, and picolibc's (Thumb,
         * in ROM) cost more than 4 cycles per pixel here */
        uint32_t f[FRAME_WORDS], *g = f;
        *g++ = (1u << (r - 1u)) + 0x80000000u, *g++ = (uint32_t)(int32_t)w->w[ch][0];
        for (uint32_t i = 1; i < k; ++i)
            *g++ = (uint32_t)(i * 3u * plane), *g++ = (uint32_t)(int32_t)w->w[ch][i]; /* map i's plane of ch */
        *g++ = (uint32_t)(uintptr_t)(b->row + ch), *g++ = r;
        *g++ = (uint32_t)((int32_t)w->bias[ch] - (int32_t)(0x80000000u >> r));
        *g++ = (uint32_t)(uintptr_t)(src + n);
        while (g < f + FRAME_WORDS)
            *g++ = 0u;
        kernel(src, f);
    }
    return QIBL_OK;
}
