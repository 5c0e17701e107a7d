/*
 * bake/path.h - light paths at bake time (core/include/qibl/lightpath.h holds the format and the
 * run-time side): sun paths and lamp tracks, per-pixel visibility along the path by ray tracing,
 * its edges refined by bisection, the LPTH payload; relighting a path light through the core.
 *
 * Sun path: latitude and declination in degrees, solar time T0..T1 in hours (12 = noon). Scene
 * frame: +x east, +y north, +z up; hour angle H = 15 (T - 12) degrees;
 *   d = (-cos D sin H, sin D cos L - cos D sin L cos H, sin D sin L + cos D cos L cos H).
 * Lamp track: a polyline of positions, t proportional to arc length.
 * t in 0..1 maps to the stored parameter round(65535 t).
 */
#ifndef QTOOL_BAKE_PATH_H
#define QTOOL_BAKE_PATH_H

#include <stddef.h>
#include <stdint.h>

#include "qibl/gonio.h"
#include "qibl/shmap.h"
#include "qibl/status.h"
#include "render/rt.h"

#define QTOOL_BAKE_PATH_MAX_POINTS 64

typedef struct qtool_bake_path {
    int kind;                  /* 0 sun path (directions), 1 lamp track (positions) */
    double lat, decl, t0, t1;  /* sun: degrees, degrees, hours, hours */
    int npts;                  /* track: 2..QTOOL_BAKE_PATH_MAX_POINTS */
    double pts[QTOOL_BAKE_PATH_MAX_POINTS][3];
    double rgb[3];             /* the light's colour (C0 for a lamp) */
} qtool_bake_path;

/* Parses "LAT,DECL,T0,T1" (sun) or "x,y,z;x,y,z;..." (track) into p (rgb left as it was).
 * 0, or -1 with a one-line reason naming the value. */
int qtool_bake_path_parse_sun(const char *s, qtool_bake_path *p, char *err, size_t errlen);
int qtool_bake_path_parse_track(const char *s, qtool_bake_path *p, char *err, size_t errlen);

/* The exact light at t in [0, 1] (falloff 1 for a lamp). */
void qtool_bake_path_light(const qtool_bake_path *p, double t, qtool_rt_light *out);

/* Bakes the LPTH payload of path p for a w x h panorama: visibility sampled at steps + 1 points,
 * every change refined by bisection to one step of the 16-bit parameter (changes that undo
 * themselves between two samples are missed: choose steps for the thinnest occluder). nkeys keys
 * (2..4096) sampled uniformly in t (sun) or the polyline's vertices (track). *out malloc'ed.
 * stats (may be NULL): [0] mean edges per pixel, [1] pixels clipped at 255 edges.
 * 0 or -1 (no memory, bad arguments). */
int qtool_bake_path_chunk(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, const qtool_bake_path *p,
                         uint32_t steps, uint32_t nkeys, int threads, uint8_t **out, size_t *n, double stats[2]);

/* The same for shard `shard` of nshards: only the rows y % nshards == shard are baked, the others
 * left empty (0 edges); qtool_extras_join puts the shards' rows together, byte for byte the
 * whole chunk. */
int qtool_bake_path_chunk_shard(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind,
                               const qtool_bake_path *p, uint32_t steps, uint32_t nkeys, uint32_t shard, uint32_t nshards,
                               int threads, uint8_t **out, size_t *n, double stats[2]);

/* The same for the band of rows y0 .. y1 - 1 (a tile shard, bake/tile.h); the other rows empty. */
int qtool_bake_path_chunk_band(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind,
                              const qtool_bake_path *p, uint32_t steps, uint32_t nkeys, uint32_t y0, uint32_t y1,
                              int threads, uint8_t **out, size_t *n, double stats[2]);

/* The LPTH payload from plain arrays (keys: nkeys t values and 3 nkeys Q16.16 coordinates; counts
 * w h bytes; edges nedges values, pixel after pixel); the row index is computed from the counts.
 * Checks nothing beyond memory (tests build payloads the core must reject). 0 or -1 (no memory). */
int qtool_bake_path_payload(uint32_t w, uint32_t h, uint32_t kind, uint32_t nkeys, const uint32_t *kt,
                           const int32_t *kv, const uint8_t *counts, const uint16_t *edges, uint32_t nedges,
                           uint8_t **out, size_t *n);

/* Relights a path light through the core: the unshadowed maps (SHMU) under l (directional or point,
 * the light at the path's t; LUT used for a point light when the asset has one) x the visibility of
 * the asset's path number path at tq (0..65535) with soft radius (0 hard). sky (may be NULL): an
 * environment relit first through the shadowed maps (SHMP) and the path light added to it.
 * Output as qtool_bake_relight8_lin (lin may be NULL; sRGB, exposure 1). 0 or -1 (*status set). */
int qtool_bake_relight_path8(const uint8_t *asset, size_t n, const qtool_rt_light *l, uint32_t path, uint32_t tq,
                            uint32_t radius, const qibl_shlight_t *sky, uint8_t *rgb8, float *lin, double *ms,
                            qibl_status_t *status);
/* The same with a goniometric lamp (gonio may be NULL; used for a point light only): the lamp's
 * light toward each pixel's point scaled by qibl_gonio_scale_span before the path's visibility. */
int qtool_bake_relight_path8_gonio(const uint8_t *asset, size_t n, const qtool_rt_light *l, const qibl_gonio_t *gonio,
                                  uint32_t path, uint32_t tq, uint32_t radius, const qibl_shlight_t *sky,
                                  uint8_t *rgb8, float *lin, double *ms, qibl_status_t *status);

/* The demo's sky (radiance rgb (0.3 + 0.7 z) above the horizon, 0 below), ray-traced: per pixel the
 * integral of T(w) L(w) (hard visibility) over ndirs upper-hemisphere directions that are not the
 * bake's, as two independent estimates from the even and the odd directions (their mean is the
 * truth; their difference measures its noise). Linear, 3 doubles per pixel each. 0 or -1. */
void qtool_bake_sky_dir(uint32_t j, uint32_t n, double d[3]);
int qtool_bake_sky_truth(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, const double rgb[3],
                        uint32_t ndirs, int threads, double *half_a, double *half_b);
/* The same sky's SH coefficients (first k, Q16.16), integrated in double on a fine grid; k outside
 * 1..25 writes nothing. */
void qtool_bake_sky_sh(const double rgb[3], uint32_t k, qibl_shlight_t *out);

/* Relights an environment (SH coefficients, k >= the maps') through the shadowed maps (SHMP), as
 * qtool_bake_relight8_lin. 0 or -1 (*status set). */
int qtool_bake_relight_env8(const uint8_t *asset, size_t n, const qibl_shlight_t *env, uint8_t *rgb8, double *ms,
                           qibl_status_t *status);

/* Lamp occlusion (the LOCC chunk's values, qibl/lightpath.h): per pixel the expected visibility of a
 * free point lamp somewhere in the box lo = box[0..2], hi = box[3..5], weighted by what the lamp
 * would add unshadowed (Lambert x C0/|L|), over nsamples positions of a Halton set; 255 = never
 * shadowed (also sky pixels and pixels no sample faces). out: w h bytes, row-major. 0 or -1. */
int qtool_bake_lamp_occlusion(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, const double box[6],
                             uint32_t nsamples, int threads, uint8_t *out);

/* The same for shard `shard` of nshards: the rows y % nshards == shard; the others are set to 0. */
int qtool_bake_lamp_occlusion_shard(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind,
                                   const double box[6], uint32_t nsamples, uint32_t shard, uint32_t nshards, int threads,
                                   uint8_t *out);

/* The same for the band of rows y0 .. y1 - 1; the other rows are set to 0. */
int qtool_bake_lamp_occlusion_band(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind,
                                  const double box[6], uint32_t nsamples, uint32_t y0, uint32_t y1, int threads,
                                  uint8_t *out);

/* The LOCC payload of w h values (*out malloc'ed). 0 or -1 (no memory). */
int qtool_bake_locc_payload(uint32_t w, uint32_t h, const uint8_t *values, uint8_t **out, size_t *n);

/* A copy of a valid asset with one chunk appended (the others in their order, bytes unchanged).
 * *out malloc'ed. 0 or -1 (invalid asset, too many chunks, no memory). */
int qtool_bake_asset_add(const uint8_t *asset, size_t n, uint32_t type, const uint8_t *payload, size_t size,
                        uint8_t **out, size_t *outn);


#endif
