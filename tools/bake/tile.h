/*
 * bake/tile.h - tile shards (docs/farm.md): tile I of N bakes the band of full-width rows
 * I h / N .. (I + 1) h / N - 1 with every direction and writes bytes proportional to its rows.
 * Two passes, because the 8-bit SH maps take each map's minimum and maximum over the whole image:
 *   pass 1  `qibl bake --tile I/N --ranges-out R_I`: the band's shadowed and unshadowed sums (each
 *           pixel's the very integers of a single bake: same directions, same order), their
 *           coefficients, and each map's minimum and maximum over the band: a ranges file;
 *   reduce  `qibl merge --ranges -o R R_0 ... R_{N-1}`: per map the minimum of the minima and the
 *           maximum of the maxima (exact: a min or max of doubles is one of them);
 *   pass 2  `qibl bake --tile I/N --ranges R --part P_I`: the band baked again, packed against the
 *           whole image's ranges (qtool_pack_range, as qtool_pack_maps), with the band's rows of the
 *           P map, light paths and lamp occlusion: a part;
 *   merge   `qibl merge -o ASSET P_0 ... P_{N-1}`: the bands put together and the chunks built by
 *           qtool_bake_asset_packed: byte for byte the asset of one `qibl bake -o`.
 * Global, and how: SHMP and SHMU scale and bias (the ranges above); YLUT (a function of the LUT size
 * and k only, built by the merge); the LPTH header (nedges: the sum of the bands') and row starts
 * (running sums of the bands' rows); the LPTH keys (the path's, the same in every part, checked);
 * the LOCC and SHMP/PMAP headers (the size). Everything else is per pixel. --probe and --budget bakes
 * are one job (the probe's sources and the held-out choice of k look at the whole image): refused.
 *
 * Every file carries the bake's key: w, h, k, unshadowed k, directions and a fingerprint (CRC-32 of
 * every option that changes a byte of the asset and of the loaded scene's geometry and materials),
 * so files of another bake are refused by name.
 *
 * Ranges file, version 1 (little-endian):
 *     0  "QIBLRNGS"
 *     8  u32 version
 *    12  u32 w, h, k, uk, ndirs, fingerprint
 *    36  u32 tile, ntiles, reduced (0: tile's own ranges; 1: every tile's reduced, tile 0)
 *    48  u32 CRC-32 of the body, 52 u32 CRC-32 of bytes 0..51
 *    56  body: 3 (k + uk) pairs of f64 (IEEE bits) minimum, maximum: the shadowed planes i * 3 + ch,
 *        then the unshadowed; size exactly 56 + 48 (k + uk)
 * Part file, version 1 (little-endian):
 *     0  "QIBLPART"
 *     8  u32 version
 *    12  u32 w, h, k, uk, ndirs, fingerprint
 *    36  u32 tile, ntiles, lut, layout, npaths, has_locc
 *    60  u32 CRC-32 of the reduced ranges' body (parts packed against other ranges are refused)
 *    64  u64 body size
 *    72  u32 CRC-32 of the body, 76 u32 CRC-32 of bytes 0..75
 *    80  body (rows = the band's): i32 scale, bias (3 k each); 3 k planes of rows w bytes; the P map
 *        rows w 3 i32; when uk: i32 scale, bias (3 uk each), 3 uk planes of rows w bytes; npaths
 *        times u32 size and an LPTH payload of w x rows; when has_locc a LOCC payload of w x rows
 * Limits checked at the header before anything is allocated or trusted: w, h 1..QIBL_ASSET_MAX_DIM,
 * w h <= QIBL_ASSET_MAX_PIXELS, k 1..25, uk 0..25, ndirs 1..QTOOL_BAKE_MAX_DIRS, ntiles 1..h,
 * tile < ntiles, npaths <= 8, the file's size what the header claims.
 */
#ifndef QTOOL_BAKE_TILE_H
#define QTOOL_BAKE_TILE_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "bake/job.h"

#define QTOOL_TILE_RANGES_VERSION 1u
#define QTOOL_TILE_RANGES_HEADER 56u
#define QTOOL_TILE_PART_VERSION 1u
#define QTOOL_TILE_PART_HEADER 80u
#define QTOOL_TILE_MAX_PATHS 8u

/* what makes two tile files parts of one bake */
typedef struct qtool_tile_key {
    uint32_t w, h, k, uk, ndirs, fp;
} qtool_tile_key;

typedef struct qtool_tile_ranges {
    qtool_tile_key key;
    uint32_t tile, ntiles, reduced;
    double *lo, *hi; /* 3 (k + uk) each, malloc'ed */
} qtool_tile_ranges;

/* The first and one-past-last row of tile of ntiles in h rows (ntiles <= h: no band is empty). */
void qtool_tile_band(uint32_t h, uint32_t tile, uint32_t ntiles, uint32_t *y0, uint32_t *y1);

/* The ranges file: encode (*out malloc'ed), decode (name for messages), read, write (atomic). 0 or -1
 * with a one-line reason in err. */
int qtool_tile_ranges_encode(const qtool_tile_ranges *r, uint8_t **out, size_t *n);
int qtool_tile_ranges_decode(const uint8_t *b, size_t n, const char *name, qtool_tile_ranges *r, char *err,
                             size_t errlen);
int qtool_tile_ranges_read(const char *path, qtool_tile_ranges *r, char *err, size_t errlen);
int qtool_tile_ranges_write(const qtool_tile_ranges *r, const char *path, char *err, size_t errlen);
void qtool_tile_ranges_free(qtool_tile_ranges *r);

/* `qibl bake --tile`: pass 1 (o->ranges_out) or pass 2 (o->ranges_in, o->part_out), options checked.
 * 0, or -1 with err set. */
int qtool_tile_bake(const qtool_bake_opts *o, FILE *out, FILE *log, char *err, size_t errlen);

/* `qibl merge --ranges -o OUT FILE...`: every tile's ranges exactly once, one bake, reduced. */
int qtool_tile_reduce(const char *out_path, char *const *in, int nin, FILE *out, char *err, size_t errlen);

/* `qibl merge -o ASSET PART...`: every tile's part exactly once, one bake, one ranges; the asset. */
int qtool_tile_merge(const char *out_path, char *const *in, int nin, FILE *out, char *err, size_t errlen);

/* Checks a part's file image as the merge does before use (header, sizes, CRCs, every chunk
 * parsed); name for messages. 0, or -1 with the reason in err (what fuzz_shard calls). */
int qtool_tile_part_check(const uint8_t *b, size_t n, const char *name, char *err, size_t errlen);

/* Whether the file at path starts as a part ("QIBLPART"): merge's choice between sums and parts. */
int qtool_tile_is_part(const char *path);

#endif
