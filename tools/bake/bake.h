/*
 * bake/bake.h - the bake pipeline (Wong et al.): reference renders of a scene under N directional
 * lights, each pixel's response projected onto SH (k <= 25), range-packed 8-bit maps + P map (+ Y LUT)
 * as a qibl asset; held-out evaluation against ground-truth renders.
 *
 * Light directions: a spherical Fibonacci set of N points (z_j = 1 - (2j + 1)/N, phi_j = j times the
 * golden angle), equal quadrature weights 4 pi / N. Directions are grouped in blocks of
 * QTOOL_BAKE_BLOCK; per pixel and block the sums T_ch(l_j) Y_i(l_j) are formed in double in j order and
 * rounded to int64 in units of 2^-32, and blocks are added as integers. Integer addition is exact and
 * associative, so the sums -- and the asset -- are bit-identical for any thread count and any split
 * into shards (a shard takes the blocks b with b % nshards == shard).
 *
 * Projection: quadrature c = (4 pi / N) S, or least squares c = G_k^-1 S with G_k the k x k Gram
 * matrix sum_j Y(l_j) Y(l_j)^T of the directions (the best fit at the sample directions).
 */
#ifndef QTOOL_BAKE_BAKE_H
#define QTOOL_BAKE_BAKE_H

#include <stddef.h>
#include <stdint.h>

#include "gen/scene.h"
#include "qibl/fixed.h"
#include "qibl/shmap.h"
#include "qibl/soft.h"
#include "qibl/status.h"
#include "render/rt.h"

#define QTOOL_BAKE_BLOCK 16u

typedef struct qtool_bake_sums {
    uint32_t w, h, k, ndirs, kind, shard, nshards;
    int32_t *pmap; /* w * h * 3, Q16.16 */
    int64_t *acc;  /* [pixel][ch][i], w * h * 3 * k, units of 2^-32 */
} qtool_bake_sums;

typedef enum { QTOOL_PROJ_QUADRATURE = 0, QTOOL_PROJ_LSQ } qtool_proj_method;

void qtool_bake_dir(uint32_t j, uint32_t n, double d[3]);

/* Monotonic time in seconds (what the bake's stages and relights are timed with). */
double qtool_bake_now(void);
/* The relights' framebuffer: w x h RGBA8888 pixels pix, through sRGB, exposure 1. */
qibl_fb_desc_t qtool_bake_fb_srgb(uint8_t *pix, uint32_t w, uint32_t h);
/* The end of a relight into such a framebuffer: *ms (may be NULL) the time since t0 (qtool_bake_now),
 * the RGB of pix into rgb8 when st is QIBL_OK, *status (may be NULL) = st. 0 if st is QIBL_OK, else -1. */
int qtool_bake_frame_done(qibl_status_t st, double t0, double *ms, const uint8_t *pix, uint32_t w, uint32_t h,
                          uint8_t *rgb8, qibl_status_t *status);
/* Row y of a relight's Q16.16 RGB (w pixels) into fb (qibl_soft_fb_write_row) and, when lin is not
 * NULL and the write succeeded, into lin's row y as linear floats (negative as 0): the write's
 * status. */
qibl_status_t qtool_bake_frame_row(const qibl_fb_desc_t *fb, uint32_t y, uint32_t w, const int32_t *row, float *lin);
/* A value in the core's Q16.16: round(v 2^16). */
qibl_q16_t qtool_bake_q16(double v);
/* The directional light l (direction and colour in Q16.16) as a k-coefficient SH light. */
qibl_status_t qtool_bake_dir_shlight(const qtool_rt_light *l, uint32_t k, qibl_shlight_t *out);
/* The point light l (position, colour, falloff) as the core's, looked up through filter. */
qibl_pointlight_t qtool_bake_pointlight(const qtool_rt_light *l, qibl_lut_filter_t filter);
/* The buffers of a relighting loop: the RGBA frame (w h 4 bytes), rows rows of 3 int32 per pixel
 * (w wide), a scratch of the caller's size (may be 0 bytes) and the core's workspace of wsn bytes. */
typedef struct qtool_bake_frame {
    uint8_t *pix;
    int32_t *row;
    void *scratch, *ws;
    size_t wsn;
} qtool_bake_frame;
/* After st, the status of opening the asset: *status (may be NULL) = st, and when st is QIBL_OK the
 * buffers into f. 0, or -1 when st is not QIBL_OK or memory ran out (*status QTOOL_E_NOMEM,
 * tools/qtool.h; nothing is held). */
int qtool_bake_frame_alloc(qibl_status_t st, uint32_t w, uint32_t h, size_t rows, size_t scratch, size_t wsn,
                           qtool_bake_frame *f, qibl_status_t *status);
/* qtool_bake_frame_done on f's frame, then f's buffers freed. */
int qtool_bake_frame_finish(qtool_bake_frame *f, qibl_status_t st, double t0, double *ms, uint32_t w, uint32_t h,
                            uint8_t *rgb8, qibl_status_t *status);

/* Renders and accumulates (shard of nshards; 0 of 1 = everything). progress: 1 = a bar on stderr.
 * 0, or -1 (no memory). */
int qtool_bake_run(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, uint32_t ndirs, uint32_t k,
                  uint32_t shard, uint32_t nshards, int threads, int progress, qtool_bake_sums *out);
/* The unshadowed transfer (cosine x BRDF, no shadow test) for the SHMU chunk: the same sums, in
 * one piece, or (_shard) shard of nshards split into direction blocks as qtool_bake_run (a sharded
 * bake writes them beside its partial sums as SUMS.u; their merge is bit-identical). 0 or -1. */
int qtool_bake_run_unshadowed(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, uint32_t ndirs,
                             uint32_t k, int threads, qtool_bake_sums *out);
int qtool_bake_run_unshadowed_shard(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind,
                                   uint32_t ndirs, uint32_t k, uint32_t shard, uint32_t nshards, int threads,
                                   qtool_bake_sums *out);
/* Either of the two (unshadowed 0 or 1) with progress 0 none, 1 a bar on stderr when it is a
 * terminal, 2 lines for a farm's log: "progress: stage=shadowed|unshadowed done=D total=T
 * fraction=F" (rows; one line per percent and the last, each flushed). 0 or -1. */
int qtool_bake_run_progress(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, uint32_t ndirs,
                            uint32_t k, uint32_t shard, uint32_t nshards, int threads, int progress, int unshadowed,
                            qtool_bake_sums *out);
/* Rows y0 .. y1 - 1 (0 <= y0 < y1 <= h) of the w x h bake, every direction (a tile shard, bake/tile.h):
 * out gets y1 - y0 rows (out->h), each pixel's sums the very integers of the whole bake's. 0 or -1. */
int qtool_bake_run_rows(const qtool_rt_scene *s, uint32_t w, uint32_t h, uint32_t y0, uint32_t y1, qtool_pano_kind kind,
                        uint32_t ndirs, uint32_t k, int threads, int progress, int unshadowed, qtool_bake_sums *out);
void qtool_bake_sums_free(qtool_bake_sums *s);

/* Partial sums file, version 2 (all little-endian):
 *    0  "QIBLSUMS"
 *    8  u32 version (QTOOL_BAKE_SUMS_VERSION)
 *   12  u32 w, h, k, ndirs, kind, shard, nshards
 *   40  u32 CRC-32 (qibl_crc32) of the body
 *   44  u32 CRC-32 of bytes 0..43
 *   48  body: pmap, w * h * 3 i32; then acc, w * h * 3 * k i64
 * Limits (checked at the header, before anything is allocated; the file's size must then be
 * exactly 48 + the body the header claims): w, h in 1..QIBL_ASSET_MAX_DIM with w h <=
 * QIBL_ASSET_MAX_PIXELS (the asset the sums become), k 1..25, ndirs 1..QTOOL_BAKE_MAX_DIRS, kind 0..1,
 * nshards 1..QTOOL_BAKE_MAX_SHARDS and at most one per block of QTOOL_BAKE_BLOCK directions,
 * shard < nshards. Version 1 files ("QIBLSUM1", no checksums) are refused by name. */
#define QTOOL_BAKE_SUMS_VERSION 2u
#define QTOOL_BAKE_SUMS_HEADER 48u
#define QTOOL_BAKE_MAX_DIRS 65536u /* also bounds merge --lsq's Gram matrix: O(ndirs k^2) */
#define QTOOL_BAKE_MAX_SHARDS 4096u

/* Write is atomic (io/atomic.h); read and decode give a one-line error (read's names the file).
 * Decode takes a whole file image in memory (what a fuzzer calls). 0 or -1; *s is set only on 0. */
int qtool_bake_sums_write(const qtool_bake_sums *s, const char *path, char *err, size_t errlen);
int qtool_bake_sums_read(const char *path, qtool_bake_sums *s, char *err, size_t errlen);
int qtool_bake_sums_decode(const uint8_t *buf, size_t len, qtool_bake_sums *s, char *err, size_t errlen);
/* The file image of s in a malloc'ed buffer (*buf, *len). 0 or -1 (out of memory). */
int qtool_bake_sums_encode(const qtool_bake_sums *s, uint8_t **buf, size_t *len);
/* 0 if b can be added to a (same w, h, k, ndirs, kind, nshards and P map), else -1 with the first
 * difference named ("shards of different bakes: k 9 against 16"). Shard indices are not compared:
 * the caller checks the shard set. */
int qtool_bake_sums_compatible(const qtool_bake_sums *a, const qtool_bake_sums *b, char *err, size_t errlen);
/* Adds b into a after qtool_bake_sums_compatible. Every sum is checked first: if any would overflow
 * 64 bits, -1 with the pixel named and a unchanged. 0 or -1 with a reason. */
int qtool_bake_sums_add(qtool_bake_sums *a, const qtool_bake_sums *b, char *err, size_t errlen);

/* SH coefficient maps (the first k <= sums->k) from the sums, as qtool_gen_maps (t and p filled; dir
 * NULL). 0 or -1. */
int qtool_bake_coeffs(const qtool_bake_sums *s, uint32_t k, qtool_proj_method method, qtool_gen_maps *out);

/* Packs maps (min/max) and builds the asset bytes: SHMP + PMAP (+ YLUT of face lut if lut > 0).
 * *bytes malloc'ed. 0 or -1. */
int qtool_bake_asset(const qtool_gen_maps *m, uint32_t lut, uint8_t **bytes, size_t *n);
/* The same plus, when mu is not NULL, the unshadowed maps mu (same size, own k) as SHMU, and one LPTH
 * chunk per payload of the NULL-terminated list paths (sizes in path_sizes; paths may be NULL). */
int qtool_bake_asset_ex(const qtool_gen_maps *m, const qtool_gen_maps *mu, uint32_t lut, uint8_t *const *paths,
                       const size_t *path_sizes, uint8_t **bytes, size_t *n);
/* Everything: SHMP in layout + PMAP (+ YLUT) (+ SHMU, planar, when mu) (+ one LPTH per path). */
int qtool_bake_asset_full(const qtool_gen_maps *m, const qtool_gen_maps *mu, uint32_t lut, uint32_t layout,
                         uint8_t *const *paths, const size_t *path_sizes, uint8_t **bytes, size_t *n);
/* Maps already packed (qtool_pack_maps): w x h, k maps of 3 channels, scale and bias (k * 3 each),
 * planes (k * 3 * w * h bytes, plane i * 3 + ch) and, for the shadowed set, the P map p (w h 3 Q16.16;
 * unused in shu). */
typedef struct qtool_bake_packed {
    uint32_t w, h, k;
    const int32_t *scale, *bias;
    const uint8_t *planes;
    const int32_t *p;
} qtool_bake_packed;
/* qtool_bake_asset_full's asset from packed maps (shu NULL: no SHMU): the one place the chunks are
 * put in order, so a tile merge (bake/tile.h) makes the bytes a single bake makes. 0 or -1. */
int qtool_bake_asset_packed(const qtool_bake_packed *sh, const qtool_bake_packed *shu, uint32_t lut, uint32_t layout,
                            uint8_t *const *paths, const size_t *path_sizes, uint8_t **bytes, size_t *n);
/* The same with the SH maps in a chosen layout (QIBL_SHMAPS_PLANAR or QIBL_SHMAPS_INTERLEAVED). */
int qtool_bake_asset_layout(const qtool_gen_maps *m, uint32_t lut, uint32_t layout, uint8_t **bytes, size_t *n);

/* Evaluation: ground truth of a light as 8-bit sRGB (exposure 1) through platform/soft, and the
 * same light relit by the core from asset bytes. mask (w * h, may be NULL) gets 1 where the scene is
 * hit (PSNR is taken over those pixels). */
int qtool_bake_truth8(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, const qtool_rt_light *l,
                     int threads, uint8_t *rgb8, uint8_t *mask);
/* A linear frame (3 doubles per pixel) as the truth's 8-bit sRGB (platform/soft, exposure 1). */
void qtool_bake_lin_to8(const double *lin, uint32_t w, uint32_t h, uint8_t *rgb8);
/* use_lut: point lights use the asset's YLUT (bilinear). 0 or -1 (bad asset / core error). */
/* The same with every option: lut_mode 0 direct SH, 1 LUT bilinear, 2 LUT nearest, 3 QIBL_POINT_POLY
 * (Q2.14 polynomials, no LUT); exposure UQ16.16
 * (0 = 1.0); srgb 0 = linear output. *status (may be NULL) gets the core's status on failure
 * (QTOOL_E_NOMEM, tools/qtool.h, for out of memory). rgb8 holds width * height * 3 bytes. */
int qtool_bake_relight8_ex(const uint8_t *asset, size_t n, const qtool_rt_light *l, int lut_mode, qibl_uq16_t exposure,
                           int srgb, uint8_t *rgb8, double *ms, qibl_status_t *status);
/* The same, and when lin is not NULL also the linear frame the core computed (3 floats per pixel,
 * rows top to bottom): its Q16.16 output / 65536 before exposure and the transfer curve, with
 * negative values (SH ringing) clamped to 0 as the framebuffer clamps them. */
int qtool_bake_relight8_lin(const uint8_t *asset, size_t n, const qtool_rt_light *l, int lut_mode, qibl_uq16_t exposure,
                           int srgb, uint8_t *rgb8, float *lin, double *ms, qibl_status_t *status);
int qtool_bake_relight8(const uint8_t *asset, size_t n, const qtool_rt_light *l, int use_lut, uint8_t *rgb8,
                       double *ms);
/* MSE of a against b over the masked pixels (8-bit, all three channels); its PSNR (averaged over
 * several lights first, where wanted) is qtool_ref_psnr8 (ref/psnr.h). */
double qtool_bake_mse(const uint8_t *a, const uint8_t *b, const uint8_t *mask, size_t npix);

#endif
