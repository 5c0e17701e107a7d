/*
 * gba/iwram_relight.h - the demo ROM's own relight of a row (demo_hooks_t.relight): ARM kernels
 * (relight_arm.S) that read the maps from cartridge ROM in sequential bursts. Same bytes as the
 * core's qibl_shmap_relight_span; rows they do not cover go to the core.
 */
#ifndef QTOOL_GBA_IWRAM_RELIGHT_H
#define QTOOL_GBA_IWRAM_RELIGHT_H

#include "demo_frame.h"

/* Row y of maps m with weights w into b->row (b->ws for the core's fallback). QIBL_OK or the
 * core's status for the same call. */
QIBL_NODISCARD qibl_status_t gba_relight_row(const qibl_shmaps_t *m, const qibl_shmap_weights_t *w, uint32_t y,
                                             demo_buffers_t *b);

#endif
