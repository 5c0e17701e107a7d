/*
 * bake/probesun.h - a light probe's compact bright sources (its suns) as baked single-direction
 * light paths, the rest of the probe as SH ("sun + SH"): what `qibl bake --probe`, `relight
 * --probe`, `render --probe` and the demo's probe part (tools/demo/probe.c) share. Hosted, double.
 *
 * A probe is read, turned by a yaw, scaled so that a surface facing up receives
 * QTOOL_PROBESUN_TARGET_E_UP, and split: the compact sources (8-connected bright components, see
 * qtool_probesun_find), each cut into kparts equal-energy parts (a penumbra of that many steps),
 * and the sky (the probe with their pixels zeroed). The bake stores per part the visibility of its
 * direction (an LPTH chunk, path number = part number) and a PSUN chunk naming the probe, so a
 * relight under another probe is refused by name.
 *
 * PSUN payload (version 1, little-endian; doubles as IEEE-754 bits):
 *     0  u32 version (1), u32 id (CRC-32 of the probe's float pixels as read), u32 w, u32 h
 *    16  f64 yaw (degrees), u32 kparts, u32 nsrc, u32 nparts
 *    36  nsrc x (f64 dir[3], f64 rgb[3], f64 share)
 *        nparts x (u32 source, f64 dir[3], f64 rgb[3])
 *        u32 name length (<= 255), the probe file's base name
 */
#ifndef QTOOL_BAKE_PROBESUN_H
#define QTOOL_BAKE_PROBESUN_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "bake/bake.h"
#include "qibl/asset.h"
#include "qibl/lightprobe.h"
#include "qibl/shmap.h"
#include "render/env.h"
#include "render/rt.h"

#define QTOOL_PROBESUN_MAX_SRC 4
#define QTOOL_PROBESUN_MAX_PARTS 8 /* parts per source */
#define QTOOL_PROBESUN_MAX_PATHS (QTOOL_PROBESUN_MAX_SRC * QTOOL_PROBESUN_MAX_PARTS)
/* the demo's exposure: a surface facing up receives this irradiance (mid-grey courtyard) */
#define QTOOL_PROBESUN_TARGET_E_UP 1.6
#define QTOOL_PROBESUN_SHADOWED_K 25   /* the sky's SH through the shadowed maps */
#define QTOOL_PROBESUN_UNSHADOWED_K 16 /* the sources through the unshadowed maps */
#define QTOOL_PROBESUN_YAW_MAX 360.0   /* --yaw in -360..360 degrees */
#define QTOOL_PROBESUN_CHUNK QIBL_FOURCC('P', 'S', 'U', 'N')

typedef struct qtool_probesun_src {
    double dir[3], rgb[3], share, radius_deg; /* unit direction, RGB x solid angle, energy share, extent */
} qtool_probesun_src;

/* Compact bright sources of the env's probe: 8-connected components (wrapping in phi) of the pixels
 * in the env's bright set, each holding >= 1 % of the energy and within 12 degrees of its
 * centroid, largest first, at most QTOOL_PROBESUN_MAX_SRC; each split into kparts (a power of two,
 * 1..QTOOL_PROBESUN_MAX_PARTS) equal-energy parts (parts, part_src its source; *nparts). Their
 * pixels are zeroed in sky (the env's w x h). Returns the count, or -1 (out of memory). */
int qtool_probesun_find(const qtool_env *e, float *sky, qtool_probesun_src *suns, qtool_probesun_src *parts,
                        int *part_src, int *nparts, int kparts);

/* Scales the w x h probe in place so that a surface facing up receives QTOOL_PROBESUN_TARGET_E_UP;
 * returns the factor (1 for a probe with nothing above the horizon). */
double qtool_probesun_scale(float *probe, uint32_t w, uint32_t h);

/* probe (floats) -> the core's LINEAR_F32 image over bits (w h 3 words, the caller's) */
void qtool_probesun_f32_image(const float *p, uint32_t w, uint32_t h, uint32_t *bits, qibl_lightprobe_image_t *img);

/* The probe's radiance SH (k bands) by the core's projection; *ms (may be NULL) its time. 0 or -1. */
int qtool_probesun_sh(const float *p, uint32_t w, uint32_t h, uint32_t k, qibl_shlight_t *l, double *ms);

/* The LPTH payload of one fixed direction (each pixel visible: one edge at 0; or not: none); cls
 * (w h) gets qtool_rt_classify's classes of that direction. 0 or -1 (out of memory). */
int qtool_probesun_path(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, int threads,
                        const qtool_probesun_src *sun, uint8_t *cls, uint8_t **out, size_t *n);

/* Sun + SH through the core: the sky SH through the shadowed maps (SHMP), then per source one relight
 * of the unshadowed maps (SHMU) from its centroid, added per part scaled by the part's share of the
 * source's colour, times the part's visibility (LPTH number k). rgb8: w h 3, sRGB, exposure 1.
 * 0, or -1 with err set. */
int qtool_probesun_relight(const uint8_t *asset, size_t n, const qibl_shlight_t *sky, const qtool_probesun_src *src,
                           int nsrc, const qtool_probesun_src *parts, const int *part_src, int nparts, uint8_t *rgb8,
                           double *ms, char *err, size_t errlen);

/* ---- a whole probe, for the CLI ----------------------------------------------------------------- */

typedef struct qtool_probesun {
    uint32_t w, h;
    float *probe, *sky;  /* turned and scaled; sky without the sources */
    qtool_env env;       /* built on probe */
    double scale, yaw;
    uint32_t id;         /* CRC-32 of the pixels as read */
    int kparts, nsrc, nparts;
    qtool_probesun_src src[QTOOL_PROBESUN_MAX_SRC], parts[QTOOL_PROBESUN_MAX_PATHS];
    int part_src[QTOOL_PROBESUN_MAX_PATHS];
    char name[256];      /* the file's base name */
} qtool_probesun;

/* Reads a lat-long Radiance probe, turns it by yaw degrees (-360..360; +x toward +y: a light at
 * azimuth phi comes from phi + yaw; the picture slides by linear interpolation between columns),
 * scales it and finds its sources (kparts per source). 0, or -1 with err set (unreadable file, a
 * yaw out of range, a probe the truth cannot sample, out of memory); nothing to free on failure. */
int qtool_probesun_load(const char *path, double yaw, int kparts, qtool_probesun *ps, char *err, size_t errlen);
void qtool_probesun_free(qtool_probesun *ps);

/* The PSUN payload of ps (*out malloc'ed). 0 or -1 (out of memory). */
int qtool_probesun_chunk(const qtool_probesun *ps, uint8_t **out, size_t *n);

/* Whether the asset (opened in a, named asset in messages) was baked with ps: 0 yes; 1 it has no
 * PSUN chunk (err untouched); -1 with err naming both probes or both yaws (another probe, another
 * yaw, a bad chunk, paths missing). */
int qtool_probesun_check(const qibl_asset_t *a, const char *asset, const qtool_probesun *ps, char *err,
                         size_t errlen);

/* The ray-traced truth under the whole (turned, scaled) probe: the mean of two renders of spp
 * samples per pixel with seeds 2 seed + 1 and 2 seed + 2 (the demo's), lin w h 3 linear. 0 or -1. */
int qtool_probesun_truth(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, const qtool_probesun *ps,
                         uint32_t spp, uint64_t seed, int threads, double *lin);

/* The bake of `qibl bake --probe`: the shadowed maps k = QTOOL_PROBESUN_SHADOWED_K from sums, the
 * unshadowed ones (k = QTOOL_PROBESUN_UNSHADOWED_K, ndirs directions), one LPTH per part and the
 * PSUN chunk, written atomically to out; one "wrote" line on rep. 0, or -1 with err set. */
int qtool_probesun_bake(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, int threads,
                        const qtool_bake_sums *sums, uint32_t ndirs, uint32_t lut, uint32_t layout, const qtool_probesun *ps,
                        const char *out, FILE *rep, char *err, size_t errlen);

#endif
