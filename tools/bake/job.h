/*
 * bake/job.h - the whole jobs behind `qibl render`, `bake`, `merge` and `check`: each takes a
 * designated-initialised options struct whose defaults are the QTOOL_*_OPTS_DEFAULT macro below
 * (the one place they live), does the work, writes its files (atomically, nothing half-written on
 * failure) and its report lines on `out` (notes and progress on `log`). Failures come back as -1
 * (or 2 for a bad combination only the inputs reveal, the CLI's bad-arguments status) with a
 * one-line reason in err; the caller prints it.
 */
#ifndef QTOOL_BAKE_JOB_H
#define QTOOL_BAKE_JOB_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "bake/path.h"
#include "bake/scene.h"
#include "io/ies.h"
#include "qibl/shmap.h"
#include "render/rt.h"

/* ---- render: the ray-traced ground truth of one light ------------------------------------------- */

typedef struct qtool_render_opts {
    qtool_scene_opts scene;
    qtool_rt_light light;     /* one sun or one point lamp */
    int have_rgb;             /* 0 with a point lamp: light.rgb is chosen by the caller (qtool_render_points) */
    const char *png, *pfm, *exr, *depth; /* outputs, NULL for none (at least one) */
    const char *ies;          /* a goniometric profile for the point lamp, NULL for none */
    double aim[3], up[3];     /* its orientation */
    const char *probe;        /* --probe P.hdr: the truth under the whole probe instead of light (probesun.h) */
    double yaw;               /* --yaw DEG: the probe turned (-360..360) */
    long spp, seed;           /* the probe truth: samples per pixel in each of two renders, their seed pair */
} qtool_render_opts;

#define QTOOL_RENDER_OPTS_DEFAULT                                                                       \
    {.scene = QTOOL_SCENE_OPTS_DEFAULT,                                                                 \
     .light = {.point = 0, .dir = {0, 0, 1}, .pos = {0, 0, 0}, .rgb = {1, 1, 1}, .falloff = 1},        \
     .aim = {0, 0, -1}, .up = {1, 0, 0}, .spp = 256}

/* What a render holds between its steps: the profile, the scene and the frames. */
typedef struct qtool_render_job {
    qtool_ies prof;
    qtool_ies_lamp lamp;
    int have_ies, have_scene;
    qtool_rt_scene s;
    double *lin;   /* w h 3, linear */
    float *dep, *f3;
    uint8_t *rgb8; /* w h 3, the PNG's bytes */
    double ms;     /* the render's wall time */
} qtool_render_job;

/* Reads the profile and loads the scene (in that order). 0, or -1 with err set; free j either way. */
int qtool_render_prepare(const qtool_render_opts *o, qtool_render_job *j, char *err, size_t errlen);
/* The points a point lamp's default C0 is measured on: per pixel the primary hit, sky pixels sky_dist
 * along their ray (*pts malloc'ed, w h x 3). 0 or -1 (out of memory). */
int qtool_render_points(const qtool_rt_scene *s, const qtool_scene_opts *so, double sky_dist, double **pts);
/* Renders and writes the outputs o names. *png_written: the PNG is on disk (its bytes in j->rgb8),
 * also when a later output fails. 0, or -1 with err set. */
int qtool_render_run(const qtool_render_opts *o, qtool_render_job *j, int *png_written, char *err, size_t errlen);
void qtool_render_free(qtool_render_job *j);

/* ---- bake: reference renders -> SH sums -> asset (or a shard's partial sums) -------------------- */

#define QTOOL_BAKE_JOB_MAX_PATHS 8

typedef struct qtool_bake_opts {
    qtool_scene_opts scene;
    const char *out, *sums_out;  /* -o ASSET, --sums FILE (at least one) */
    long k, lut, ndirs, shard, nshards, uk, steps, lamp_samples;
    double budget;               /* > 0: pick k and the LUT by held-out PSNR (dB) */
    double lamp_box[6];
    int has_box, lsq, quiet, npaths;
    int progress;                /* 0 none, 1 a bar, 2 lines */
    uint32_t layout;             /* QIBL_SHMAPS_* */
    qtool_bake_path paths[QTOOL_BAKE_JOB_MAX_PATHS];
    const char *probe;           /* --probe P.hdr: a probe-lit (sun + SH) asset, bake/probesun.h */
    double yaw;                  /* --yaw DEG: the probe turned (-360..360) */
    long tile, ntiles;           /* --tile I/N (ntiles 0: not a tile shard), bake/tile.h */
    const char *ranges_out;      /* --ranges-out FILE: pass 1 of a tile */
    const char *ranges_in, *part_out; /* --ranges FILE --part FILE: pass 2 of a tile */
    const char *cache;           /* --cache DIR: pass 1 keeps the tile's sums there, pass 2 reuses them */
} qtool_bake_opts;

#define QTOOL_BAKE_OPTS_DEFAULT                                                                         \
    {.scene = QTOOL_SCENE_OPTS_DEFAULT, .k = 16, .lut = 32, .ndirs = 512, .shard = 0, .nshards = 1,    \
     .uk = 9, .steps = 64, .lamp_samples = 64, .progress = 0, .layout = QIBL_SHMAPS_PLANAR}

/* The option combinations a bake refuses (shards without --sums, more shards than direction blocks,
 * ...). 0, or 2 with the reason in err. */
int qtool_bake_opts_check(const qtool_bake_opts *o, char *err, size_t errlen);
/* The bake o describes (options already checked). 0, or -1 with err set. */
int qtool_bake_job(const qtool_bake_opts *o, FILE *out, FILE *log, char *err, size_t errlen);

/* Novel lights of the held-out evaluation: ndir suns in the upper hemisphere not in the bake's
 * direction set, then npoint lamps in the scene (around the mesh prop when obj_prop). */
void qtool_bake_eval_lights(int obj_prop, int ndir, int npoint, qtool_rt_light *out);

/* ---- merge: shards' partial sums -> total sums and/or asset ----------------------------------- */

typedef struct qtool_merge_opts {
    const char *out, *sums_out, *manifest; /* -o ASSET, --sums OUT (at least one), --manifest FILE */
    char **in;                  /* nin partial-sums files */
    int nin;
    long k;                     /* 0: the shards' k, at most 16 */
    long lut;
    int lsq;
    uint32_t layout;
    int ranges;                 /* --ranges: the inputs are tiles' ranges files, -o the reduced ranges */
} qtool_merge_opts;

#define QTOOL_MERGE_OPTS_DEFAULT {.k = 0, .lut = 32, .lsq = 0, .layout = QIBL_SHMAPS_PLANAR}

/* 0, -1 with err set, or 2 (err set) for a --k above the shards' or options a tile merge refuses.
 * With --ranges, or when the first input is a tile part, the tile steps of bake/tile.h. */
int qtool_bake_merge(const qtool_merge_opts *o, FILE *out, char *err, size_t errlen);

/* ---- check: one file (PNG, PFM, OpenEXR, Radiance HDR, else a qibl asset) fully decoded ---------- */

/* A one-line description ("PNG 64x32, 1 frame, CRCs, zlib and Adler-32 good") into line. 0, or -1
 * with err set. */
int qtool_bake_check_file(const char *path, char *line, size_t linelen, char *err, size_t errlen);

#endif
