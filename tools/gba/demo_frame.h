/*
 * gba/demo_frame.h - the relighting demo's frame, shared by the GBA ROM (demo.c) and its host
 * reference (demo_ref.c) so both make the same bytes: the courtyard's SH maps relit by a sun
 * moving around the sky, row by row into RGB565 (platform/soft), each row handed to a callback
 * (VRAM on the GBA, a file on the host). Plain C99 + the core and platform/soft; no libc.
 */
#ifndef QTOOL_GBA_DEMO_FRAME_H
#define QTOOL_GBA_DEMO_FRAME_H

#include <stddef.h>
#include <stdint.h>

#include "qibl.h"
#include "qibl/soft.h"

enum { DEMO_MAX_W = 240, DEMO_SUN_STEPS = 64 };

/* What one frame needs besides the maps: caller-owned, DEMO_MAX_W pixels wide at most. */
typedef struct demo_buffers {
    int32_t row[3 * DEMO_MAX_W];   /* Q16.16 RGB of one row */
    uint16_t rgb565[4][DEMO_MAX_W]; /* platform/soft writes row y into rgb565[y & 3] (below) */
    uint32_t ws[(DEMO_MAX_W * 16 + 64) / 4]; /* span workspace (checked against the core's size) */
} demo_buffers_t;

/* Called with each finished row; the cycles the relight of the row took come from the caller's
 * clock through the two hooks (NULL: not timed). relight, when set, replaces the core's
 * qibl_shmap_relight_span of row y into b->row (a port's own data path or kernel: it must give
 * the same bytes, which the frame's CRC-32 against the host's checks); it is timed as the relight. */
typedef struct demo_hooks {
    void (*row)(void *user, uint32_t y, const uint16_t *rgb565, uint32_t n);
    uint32_t (*clock)(void *user); /* a free-running counter */
    void *user;
    qibl_status_t (*relight)(const qibl_shmaps_t *m, const qibl_shmap_weights_t *w, uint32_t y, struct demo_buffers *b);
    uint64_t relight_ticks, write_ticks; /* summed over the frame's rows */
} demo_hooks_t;

/* The sun at step s of DEMO_SUN_STEPS around the sky (integer table: the same on every machine). */
void demo_sun(uint32_t s, qibl_q16_t dir[3]);

/* Relights rows y0 .. y1 - 1 of frame step s into RGB565 (sRGB, dithered). QIBL_OK or the first
 * failing call's status (the rows before it were handed over). */
QIBL_NODISCARD qibl_status_t demo_frame(const qibl_shmaps_t *m, uint32_t s, uint32_t y0, uint32_t y1, demo_buffers_t *b,
                         demo_hooks_t *h);

#endif
