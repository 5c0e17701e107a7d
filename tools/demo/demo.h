/*
 * demo/demo.h - the library behind `qibl demo`: bake a scene, relight it with the core (sun sweep,
 * moving lamp, light paths, whole probes) and score every frame against ray-traced ground truth.
 * Hosted, double. It does not load scenes or parse options (the caller passes the loaded scene and
 * the lights), and it writes only into the output directory it is given.
 *
 * Every part writes its table and RESULT lines to view->out and its pictures into view->dir; a
 * failing call returns -1 with one line in err (errlen bytes) and leaves what it had written.
 */
#ifndef QTOOL_DEMO_H
#define QTOOL_DEMO_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "bake/bake.h"
#include "bake/path.h"
#include "bake/probesun.h"
#include "render/rt.h"

/* The demo's sizes in one place: `small` is CI's (DEMO_SIZE=small), `default` what `make demo` runs
 * for a newcomer (within 90 s on an idle 2-core machine), `full` the README's pictures
 * (`make demo FULL=1`: the probe-lit truths alone are minutes of CPU). */
typedef struct qtool_demo_size {
    const char *name;
    uint32_t w, h;        /* panorama */
    long ndirs, frames;   /* bake directions, frames per sweep */
    uint32_t path_steps;  /* visibility steps along the sun path and lamp track */
    uint32_t sky_dirs;    /* directions of the ray-traced sky truth */
    uint32_t probe_spp;   /* samples per pixel in each of the two probe-lit truth renders */
    uint32_t ies_pos;     /* positions of the IES lamp row on the lamp track (one truth render each) */
    uint32_t nf_grid, nf_size; /* near-field row: capture grid side, ground patch side (< 96: 3 heights) */
} qtool_demo_size;

/* "small", "default" or "full"; NULL for any other name. */
const qtool_demo_size *qtool_demo_size_named(const char *name);

/* What every part works on: the scene (loaded by the caller), its panorama, where results go. */
typedef struct qtool_demo_view {
    const qtool_rt_scene *scene;
    uint32_t w, h;
    qtool_pano_kind kind;
    int threads;
    int prop;        /* a mesh scene: the lamps circle QTOOL_RT_PROP_X, not the courtyard's centre */
    const char *dir; /* output directory (checked by qtool_demo_check_out) */
    FILE *out;       /* tables and RESULT lines */
} qtool_demo_view;

/* The 15-digit pi the sweeps, the lamp track and the soft sun were made with: QTOOL_PI would move
 * their lights by an ulp, and the demo's pictures would no longer be the same bytes. */
#define QTOOL_DEMO_PI15 3.14159265358979

/* The evaluation set of the main part: novel suns, then lamps (the caller picks them). */
#define QTOOL_DEMO_NSUN 8
#define QTOOL_DEMO_NLAMP 4
#define QTOOL_DEMO_NEVAL (QTOOL_DEMO_NSUN + QTOOL_DEMO_NLAMP)
#define QTOOL_DEMO_NK 3 /* the assets baked: k = 9, 16, 25 */

/* The main part's state and results: the bake's sums and the three assets (k = QTOOL_DEMO_KS) stay
 * for the later parts; free with qtool_demo_main_free (also after a failure). */
typedef struct qtool_demo_main {
    qtool_bake_sums sums;
    uint8_t *asset[QTOOL_DEMO_NK];
    size_t asize[QTOOL_DEMO_NK];
    double bake_s;                                 /* wall seconds of the bake */
    double psnr_dir[QTOOL_DEMO_NK], psnr_pt[QTOOL_DEMO_NK]; /* dB over the suns / lamps */
    double ms_dir[QTOOL_DEMO_NK], ms_pt[QTOOL_DEMO_NK];     /* median relight ms per frame */
    double lsq_dir;                                /* k = 16 least-squares projection, suns, dB */
} qtool_demo_main;
extern const uint32_t qtool_demo_ks[QTOOL_DEMO_NK];

/* Makes sure every output can be written before the bake: dir exists (created if missing) and takes
 * a new file, and no output name (frames per sweep) is a link, directory or other non-regular file.
 * 0, or -1 with the reason in err. */
int qtool_demo_check_out(const char *dir, long frames, char *err, size_t errlen);

/* The bake for k <= 25 with ndirs directions into m->sums (m zeroed first). 0 or -1 (err). */
int qtool_demo_bake(const qtool_demo_view *v, uint32_t ndirs, qtool_demo_main *m, char *err, size_t errlen);

/* After qtool_demo_bake: the assets scene_k{9,16,25}.qibl, their PSNR against the ray-traced truth
 * of the QTOOL_DEMO_NEVAL lights ev, the least-squares comparison, the sun and lamp sweeps (frames
 * each: PNGs and an APNG), contact_sheet.png, relit_sun.png and truth_sun.png. Prints nothing. */
int qtool_demo_relight(const qtool_demo_view *v, const qtool_rt_light ev[QTOOL_DEMO_NEVAL], long frames,
                       qtool_demo_main *m, char *err, size_t errlen);
void qtool_demo_main_free(qtool_demo_main *m);

/* The light-path part (paths.c): a sun path and a lamp track baked as per-pixel visibility beside
 * the unshadowed maps, relit at 16 positions between the baked steps; its table and RESULT lines,
 * paths_sheet.png and paths_readme.png. today: the k = 16 shadowed asset (with YLUT). */
int qtool_demo_paths(const qtool_demo_view *v, uint32_t ndirs, const qtool_demo_size *sz,
                     const qtool_bake_sums *sums, const uint8_t *today, size_t today_n, char *err, size_t errlen);

/* The IES lamp row (ies.c), run by qtool_demo_paths after its tables: a built-in LM-63 profile on
 * the lamp track (asset: unshadowed maps and the track as path number path) at npos positions
 * (1..QTOOL_DEMO_MAX_IES_POS) between the baked steps, relit through the goniometric table against
 * the ray-traced lamp of the same profile, and with the profile ignored; its table and RESULT
 * lines (demo.ies_track_*). */
#define QTOOL_DEMO_MAX_IES_POS 64u
int qtool_demo_ies(const qtool_demo_view *v, const uint8_t *asset, size_t n, uint32_t path,
                   const qtool_bake_path *track, uint32_t npos, char *err, size_t errlen);

/* The near-field row (nearfield.c): `qibl luminaire study` sized by sz (nf_grid, nf_size): the
 * built-in luminaire's near-field source and its far-field treatment against the ray-traced
 * luminaire at several heights, the kernel's ms per frame in the courtyard; then CPU ms per frame
 * by pass count (captures on 4x4, 8x8, 16x16 grids) relit on asset (the k = 16 asset, with its P
 * map); its lines and RESULT luminaire.* and demo.nearfield_* lines to v->out. 0, or -1 (err). */
int qtool_demo_nearfield(const qtool_demo_view *v, const qtool_demo_size *sz, const uint8_t *asset, size_t n,
                         char *err, size_t errlen);

/* The "lit by a real probe" part (probe.c): three probes (../shared's, or procedural ones),
 * ray-traced truth with probe_spp samples per pixel per render, SH / median-cut lights / sun + SH
 * relit by the core (each extended source split into kparts, 1..QTOOL_DEMO_MAX_PARTS); its table,
 * RESULT lines and probe_sheet.png. */
#define QTOOL_DEMO_MAX_PARTS QTOOL_PROBESUN_MAX_PARTS
int qtool_demo_probe(const qtool_demo_view *v, uint32_t probe_spp, int kparts, const qtool_bake_sums *sums,
                     uint32_t ndirs, char *err, size_t errlen);
/* The same part for one probe file (`qibl demo --probe P`, a 2:1 lat-long .hdr): its rows under the
 * role "user" (RESULT demo.probe_user_*), truth seeds 1 and 2 (render --probe --seed 0's), and
 * probe_sheet.png with its one row. */
int qtool_demo_probe_file(const qtool_demo_view *v, const char *path, uint32_t probe_spp, int kparts,
                          const qtool_bake_sums *sums, uint32_t ndirs, char *err, size_t errlen);

/* The fixed-camera part (camera.c): the scene from a corner through a 70-degree perspective camera
 * (v->w / 4 wide, at least 4, 4:3), baked with ndirs directions as shadowed SH k = 16 and unshadowed k = 9
 * x a sun path's visibility (sz->path_steps), relit by the core at 8 sun positions between the baked
 * steps against the ray-traced render of the same camera; its table, RESULT lines and
 * camera_sheet.png (relit | truth | error). */
int qtool_demo_camera(const qtool_demo_view *v, uint32_t ndirs, const qtool_demo_size *sz, char *err,
                      size_t errlen);

/* ---- shared by the parts ----------------------------------------------------------------------- */

/* The error heat map of a against b (max channel difference, full scale 48 of 255: 0 black .. 8
 * blue .. 24 red .. 48+ yellow-white; pixels whose cls is 0 black). */
void qtool_demo_heat(const uint8_t *a, const uint8_t *b, const uint8_t *cls, size_t np, uint8_t *out);
/* The payload bytes of the index-th chunk of a type in an asset (0 when absent or the asset is bad). */
double qtool_demo_chunk_bytes(const uint8_t *asset, size_t n, uint32_t type, uint32_t index);
/* An 8-bit sRGB value in linear light. */
double qtool_demo_lin8(int v);
/* Median of n values (sorts v in place). */
double qtool_demo_median(double *v, int n);
/* Monotonic wall time in seconds. */
double qtool_demo_now(void);
/* Copies a w x h RGB8 image into an RGB8 sheet sheet_w pixels wide, top-left corner at (x0, y0). */
void qtool_demo_blit(uint8_t *sheet, size_t sheet_w, size_t x0, size_t y0, const uint8_t *src, uint32_t w, uint32_t h);
/* Writes an RGB8 PNG dir/name (any length of dir). 0 or -1 (err). */
int qtool_demo_save_png(const char *dir, const char *name, int w, int h, const uint8_t *rgb, char *err, size_t errlen);

#endif
