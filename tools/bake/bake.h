/*
 * bake/bake.h - the bake pipeline (Wong et al.): reference renders of a scene under N directional
 * lights, each pixel's response projected onto SH (k <= 25), range-packed 8-bit maps + P map (+ Y LUT)
 * as a qibl asset; held-out evaluation against ground-truth renders.
 *
 * Light directions: a spherical Fibonacci set of N points (z_j = 1 - (2j + 1)/N, phi_j = j times the
 * golden angle), equal quadrature weights 4 pi / N. Directions are grouped in blocks of
 * QIBL_BAKE_BLOCK; per pixel and block the sums T_ch(l_j) Y_i(l_j) are formed in double in j order and
 * rounded to int64 in units of 2^-32, and blocks are added as integers. Integer addition is exact and
 * associative, so the sums -- and the asset -- are bit-identical for any thread count and any split
 * into shards (a shard takes the blocks b with b % nshards == shard).
 *
 * Projection: quadrature c = (4 pi / N) S, or least squares c = G_k^-1 S with G_k the k x k Gram
 * matrix sum_j Y(l_j) Y(l_j)^T of the directions (the best fit at the sample directions).
 */
#ifndef QIBL_BAKE_BAKE_H
#define QIBL_BAKE_BAKE_H

#include <stddef.h>
#include <stdint.h>

#include "gen/scene.h"
#include "qibl/fixed.h"
#include "qibl/status.h"
#include "render/rt.h"

#define QIBL_BAKE_BLOCK 16u

typedef struct qibl_bake_sums {
    uint32_t w, h, k, ndirs, kind, shard, nshards;
    int32_t *pmap; /* w * h * 3, Q16.16 */
    int64_t *acc;  /* [pixel][ch][i], w * h * 3 * k, units of 2^-32 */
} qibl_bake_sums;

typedef enum { QIBL_PROJ_QUADRATURE = 0, QIBL_PROJ_LSQ } qibl_proj_method;

void qibl_bake_dir(uint32_t j, uint32_t n, double d[3]);

/* Renders and accumulates (shard of nshards; 0 of 1 = everything). progress: 1 = a bar on stderr.
 * 0, or -1 (no memory). */
int qibl_bake_run(const qibl_rt_scene *s, uint32_t w, uint32_t h, qibl_pano_kind kind, uint32_t ndirs, uint32_t k,
                  uint32_t shard, uint32_t nshards, int threads, int progress, qibl_bake_sums *out);
void qibl_bake_sums_free(qibl_bake_sums *s);

/* Partial sums file (little-endian): "QIBLSUM1", 7 u32 (w h k ndirs kind shard nshards), pmap i32,
 * acc i64. Write is atomic; read gives a one-line error naming the file. 0 or -1. */
int qibl_bake_sums_write(const qibl_bake_sums *s, const char *path, char *err, size_t errlen);
int qibl_bake_sums_read(const char *path, qibl_bake_sums *s, char *err, size_t errlen);
/* Adds b into a (same w, h, k, ndirs, kind, nshards; different shards); a->shard becomes a bitmask
 * is not kept: the caller checks the shard set. 0 or -1 with a reason. */
int qibl_bake_sums_add(qibl_bake_sums *a, const qibl_bake_sums *b, char *err, size_t errlen);

/* SH coefficient maps (the first k <= sums->k) from the sums, as qibl_gen_maps (t and p filled; dir
 * NULL). 0 or -1. */
int qibl_bake_coeffs(const qibl_bake_sums *s, uint32_t k, qibl_proj_method method, qibl_gen_maps *out);

/* Packs maps (min/max) and builds the asset bytes: SHMP + PMAP (+ YLUT of face lut if lut > 0).
 * *bytes malloc'ed. 0 or -1. */
int qibl_bake_asset(const qibl_gen_maps *m, uint32_t lut, uint8_t **bytes, size_t *n);
/* The same with the SH maps in a chosen layout (QIBL_SHMAPS_PLANAR or QIBL_SHMAPS_INTERLEAVED). */
int qibl_bake_asset_layout(const qibl_gen_maps *m, uint32_t lut, uint32_t layout, uint8_t **bytes, size_t *n);

/* Evaluation: ground truth of a light as 8-bit sRGB (exposure 1) through platform/soft, and the
 * same light relit by the core from asset bytes. mask (w * h, may be NULL) gets 1 where the scene is
 * hit (PSNR is taken over those pixels). */
int qibl_bake_truth8(const qibl_rt_scene *s, uint32_t w, uint32_t h, qibl_pano_kind kind, const qibl_rt_light *l,
                     int threads, uint8_t *rgb8, uint8_t *mask);
/* use_lut: point lights use the asset's YLUT (bilinear). 0 or -1 (bad asset / core error). */
/* The same with every option: lut_mode 0 direct SH, 1 LUT bilinear, 2 LUT nearest; exposure UQ16.16
 * (0 = 1.0); srgb 0 = linear output. *status (may be NULL) gets the core's status on failure
 * (QIBL_E_NULL_POINTER stands for out of memory). rgb8 holds width * height * 3 bytes. */
int qibl_bake_relight8_ex(const uint8_t *asset, size_t n, const qibl_rt_light *l, int lut_mode, qibl_uq16_t exposure,
                           int srgb, uint8_t *rgb8, double *ms, qibl_status_t *status);
int qibl_bake_relight8(const uint8_t *asset, size_t n, const qibl_rt_light *l, int use_lut, uint8_t *rgb8,
                       double *ms);
/* PSNR in dB of a against b over the masked pixels (8-bit, all three channels); 99 if equal. */
double qibl_bake_psnr(const uint8_t *a, const uint8_t *b, const uint8_t *mask, size_t npix);
/* MSE of the same, for averaging over several lights */
double qibl_bake_mse(const uint8_t *a, const uint8_t *b, const uint8_t *mask, size_t npix);

#endif
