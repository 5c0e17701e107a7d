/*
 * gba/iwram_relight.c - see iwram_relight.h. Compiled as ARM code into IWRAM (the iwram_ name:
 * gba.ld), as the kernel it calls: from cartridge ROM this glue's Thumb code cost about 2 cycles
 * per pixel of the relight's budget.
 *
 * Why DMA: the kernel then reads each map word from IWRAM (32-bit bus, no wait states) at
 * immediate offsets, which frees the register a ROM plane stride would take; DMA3 reads the
 * cartridge in sequential 32-bit bursts (3/1 wait states: about 5 cycles a word, the CPU halted),
 * about what the kernel's own loads from ROM would have cost, so the gain is the kernel's.
 */
#include "iwram_relight.h"

#define DMA3SAD (*(volatile uint32_t *)0x040000D4u)
#define DMA3DAD (*(volatile uint32_t *)0x040000D8u)
#define DMA3CNT (*(volatile uint32_t *)0x040000DCu)
#define DMA_ON_32 0x84000000u /* enable, 32-bit units, start now, both addresses increment */

/* relight_arm.S: one channel, 8n pixels, one kernel per k; frame as documented there */
void gba_relight8_k4(const uint8_t *src, const uint32_t *frame);
void gba_relight8_k9(const uint8_t *src, const uint32_t *frame);

enum { KMAX = 9, PITCH = 240 }; /* relight_arm.S's largest k and its piece pitch */

/* one row of every plane: channel c's map i at (c * KMAX + i) * PITCH */
static uint32_t line[3 * KMAX * PITCH / 4] __attribute__((section(".iwram.line")));

static void dma_words(void *dst, const void *src, uint32_t words)
{
    DMA3SAD = (uint32_t)(uintptr_t)src, DMA3DAD = (uint32_t)(uintptr_t)dst;
    DMA3CNT = DMA_ON_32 | words; /* the CPU waits while it runs */
}

/* chan_fast's condition (core/src/shmap.c): r = -shift in 1..30 and |bias| <= 2^30 */
static int fast_channel(const qibl_shmap_weights_t *w, uint32_t ch)
{
    return w->shift[ch] < 0 && w->shift[ch] > -31 && w->bias[ch] >= -(INT64_C(1) << 30) &&
           w->bias[ch] <= (INT64_C(1) << 30);
}

qibl_status_t gba_relight_row(const qibl_shmaps_t *m, const qibl_shmap_weights_t *w, uint32_t y, demo_buffers_t *b)
{
    const uint32_t n = m->width;
    int ours = qibl_shmap_check(m) == QIBL_OK && w != NULL && m->layout == QIBL_SHMAPS_PLANAR && w->k == m->k &&
               w->channels == m->channels && (m->k == 4u || m->k == 9u) && y < m->height && n <= PITCH && n % 8u == 0u &&
               (((uintptr_t)m->planes | m->height) & 3u) == 0u;
    for (uint32_t ch = 0; ours && ch < 3u; ++ch)
        ours = fast_channel(w, ch);
    if (!ours) /* the core checks and says why, or relights it its own way */
        return qibl_shmap_relight_span(m, w, 0, y, n, b->row, b->ws, sizeof b->ws);
    const uint32_t k = m->k, nc = m->channels;
    const size_t plane = (size_t)n * m->height;
    const uint8_t *p0 = m->planes + (size_t)y * n;
    uint8_t *blk = (uint8_t *)line;
    for (uint32_t c = 0; c < nc; ++c)
        for (uint32_t i = 0; i < k; ++i)
            dma_words(blk + (c * KMAX + i) * PITCH, p0 + (i * nc + c) * plane, n / 4u);
    void (*kernel)(const uint8_t *, const uint32_t *) = k == 4u ? gba_relight8_k4 : gba_relight8_k9;
    for (uint32_t ch = 0; ch < 3u; ++ch) {
        /* chan_fast's constants: u0 = 2^(r-1) + 2^31, bb = bias - 2^(31-r) */
        const uint32_t r = (uint32_t)-w->shift[ch];
        const uint8_t *src = blk + (nc == 3u ? ch : 0u) * KMAX * PITCH;
        /* filled field by field: an initialiser with zeros is a memset call, and picolibc's
         * (Thumb, in ROM) cost more than 4 cycles per pixel here */
        uint32_t f[5 + KMAX];
        f[0] = (uint32_t)(uintptr_t)(b->row + ch), f[1] = r;
        f[2] = (uint32_t)((int32_t)w->bias[ch] - (int32_t)(0x80000000u >> r));
        f[3] = (uint32_t)(uintptr_t)(src + n), f[4] = (1u << (r - 1u)) + 0x80000000u;
        for (uint32_t i = 0; i < KMAX; ++i)
            f[5u + i] = i < k ? (uint32_t)(int32_t)w->w[ch][i] : 0u;
        kernel(src, f);
    }
    return QIBL_OK;
}
