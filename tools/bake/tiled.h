/*
 * bake/tiled.h - per-tile adaptive k for the unshadowed maps (SHMT, qibl/shmtile.h): choosing each
 * 16x16 tile's bands at bake time, and relighting an asset that holds SHMT through the core's
 * ordinary span kernels, one tile view at a time.
 */
#ifndef QTOOL_BAKE_TILED_H
#define QTOOL_BAKE_TILED_H

#include <stddef.h>
#include <stdint.h>

#include "gen/scene.h"
#include "qibl/shmap.h"
#include "qibl/status.h"
#include "render/rt.h"

/* The SHMT payload of maps m (k = kmax): each tile keeps the fewest band-complete k (1, 4, 9, 16,
 * 25; at most m->k) whose dropped coefficients hold at most `drop` of the tile's coefficient energy
 * (sum of squares over its pixels, maps and channels; drop 0 keeps every band). Packed with the
 * same min/max scale and bias as the whole set (SHMU). tiles_k (may be NULL): 26 counters, tiles
 * per chosen k. *out malloc'ed. 0 or -1 (bad arguments, no memory). */
int qtool_bake_shmt_payload(const qtool_gen_maps *m, double drop, uint8_t **out, size_t *n, uint32_t tiles_k[26]);

/* Relights an asset with SHMT (and SHMP, PMAP, optional YLUT, LPTH, LOCC) under l as
 * qtool_bake_relight_path8: path >= 0 multiplies by that path's visibility at tq (radius soft);
 * path < 0 is a free light (a point light then takes the asset's LOCC when present). Tile by tile:
 * the tile's view, weights for its k (cached per k), a P-map copy of the tile for a point light.
 * 0 or -1 (*status set). */
int qtool_bake_relight_tiled8(const uint8_t *asset, size_t n, const qtool_rt_light *l, int path, uint32_t tq,
                             uint32_t radius, uint8_t *rgb8, double *ms, qibl_status_t *status);

#endif
