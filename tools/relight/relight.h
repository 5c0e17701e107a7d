/*
 * relight/relight.h - what `qibl relight` computes: an asset relit by the light of light.h (its SH
 * part plus point lamps, summed per pixel in 64 bits, optionally shaped by an IES profile), or by a
 * light on one of the asset's baked paths (path.c). The command parses into qtool_relight_opts
 * (defaults: QTOOL_RELIGHT_OPTS_DEFAULT, the one place they live), calls these steps in order and
 * prints what they return; messages come back in err buffers, one line, without the "qibl: ".
 */
#ifndef QTOOL_RELIGHT_RELIGHT_H
#define QTOOL_RELIGHT_RELIGHT_H

#include <stddef.h>
#include <stdint.h>

#include "io/ies.h"
#include "qibl/asset.h"
#include "qibl/gonio.h"
#include "qibl/lightpath.h"
#include "qibl/shmap.h"
#include "relight/light.h"

/* How point lamps are sampled (--lut); zero is the default. */
typedef enum qtool_relight_point_mode {
    QTOOL_RELIGHT_POINT_POLY = 0,  /* QIBL_POINT_POLY: the fastest */
    QTOOL_RELIGHT_POINT_DIRECT,    /* --lut off: direct SH in Q2.30 */
    QTOOL_RELIGHT_POINT_NEAREST,   /* the asset's Y LUT, nearest */
    QTOOL_RELIGHT_POINT_BILINEAR   /* the asset's Y LUT, bilinear */
} qtool_relight_point_mode;

typedef struct qtool_relight_opts {
    qtool_relight_light_list lights; /* --sun, --point, --rgb, --lights, --probe and its options */
    qtool_relight_point_mode point_mode;
    long falloff;        /* 1 (C0/|L|) or 2 (C0/|L|^2) */
    int32_t exposure;    /* Q16.16 */
    int linear;          /* no sRGB curve on the 8-bit frame */
    int gles;            /* platform/gles2 instead of the core + platform/soft (gles.h) */
    const char *ies;     /* --ies FILE.ies: goniometric --point lamps */
    int32_t aim[3], up[3]; /* Q16.16: the lamp's frame */
    long ies_n;          /* the gonio table's size */
} qtool_relight_opts;

#define QTOOL_RELIGHT_OPTS_DEFAULT                                                                            \
    {.lights = QTOOL_RELIGHT_LIGHT_LIST_DEFAULT, .point_mode = QTOOL_RELIGHT_POINT_POLY, .falloff = 1,        \
     .exposure = 65536, .aim = {0, 0, -65536}, .up = {65536, 0, 0}, .ies_n = 64}

/* 1 if the mode samples the asset's Y LUT. */
int qtool_relight_uses_lut(qtool_relight_point_mode m);

/* ---- an IES lamp ------------------------------------------------------------------------------- */

typedef struct qtool_relight_ies {
    qibl_gonio_t gonio;
    uint16_t *table;        /* malloc'd, n x n */
    char type;              /* 'A', 'B' or 'C' */
    qtool_ies_sym sym;
    double peak, lumens;    /* cd, lm */
    qibl_status_t status;   /* qibl_gonio_init's, when it refused aim and up */
} qtool_relight_ies;

/* Reads the profile at path into an n x n gonio table (qibl/gonio.h) framed by aim and up. 0; -1
 * with err set (unreadable file, a dark profile, out of memory); -2 when qibl_gonio_init refused
 * aim and up (out->status says why; err untouched). On failure nothing is left to free. */
int qtool_relight_ies_load(const char *path, uint32_t n, const int32_t aim[3], const int32_t up[3],
                           qtool_relight_ies *out, char *err, size_t errlen);
void qtool_relight_ies_free(qtool_relight_ies *ies);

/* ---- the asset --------------------------------------------------------------------------------- */

typedef struct qtool_relight_asset {
    uint8_t *bytes; /* malloc'd file */
    size_t n;
    qibl_asset_t a;
    qibl_shmaps_t m;    /* the maps (shadowed when the asset has both sets) */
    qibl_shmaps_t mp;   /* the maps free point lamps use: the unshadowed set when there is one */
    qibl_pmap_t pm;
    qibl_ylut_t lut;
    qibl_lampocc_t occ; /* the lamp occlusion (LOCC) of lamps through the unshadowed maps */
    int use_occ;
    int occ_unusable;   /* the asset has SHMU and LOCC, but LOCC did not open (occ_status says why) */
    qibl_status_t occ_status;
} qtool_relight_asset;

/* Reads and opens the asset at path: its maps, and for point lamps (points != 0) the point maps, the
 * P map, the Y LUT (lut != 0) and the lamp occlusion. 0, or -1 with err set (nothing to free). */
int qtool_relight_asset_open(qtool_relight_asset *s, const char *path, int points, int lut, char *err,
                             size_t errlen);
void qtool_relight_asset_free(qtool_relight_asset *s);

/* Reads the asset at path and opens it with its shadowed maps m (a and m may be NULL when only the
 * bytes are wanted); 0, or -1 with err set and *bytes NULL. */
int qtool_relight_asset_read(const char *path, uint8_t **bytes, size_t *n, qibl_asset_t *a, qibl_shmaps_t *m,
                             char *err, size_t errlen);

/* ---- the lights and the frame ------------------------------------------------------------------- */

/* What qtool_relight_points chose for a --point without --rgb. */
typedef struct qtool_relight_point_note {
    int set;      /* 1: this source got the default colour */
    double c0, d; /* the colour and the median distance it came from (qtool_relight_point_default) */
} qtool_relight_point_note;

/* The --point sources of o->lights as the core's lamps (pts, QTOOL_RELIGHT_MAX_SOURCES entries), a
 * source without --rgb coloured by qtool_relight_point_default (written back into o->lights, so
 * --gles draws the same lamp, and noted in notes[j] for source j). 0, or -1 with err set (out of
 * memory: the sources before the failing one may already be coloured and noted; *npts untouched). */
int qtool_relight_points(qtool_relight_opts *o, const qtool_relight_asset *s, qibl_pointlight_t *pts,
                         uint32_t *npts, qtool_relight_point_note *notes, char *err, size_t errlen);

/* A frame relit by the core: sh (NULL: no directional light) on the maps m, plus npoints point
 * lights on the maps mp with the P map pm and the LUT lut (NULL: direct SH), each scaled by the
 * lamp occlusion occ when not NULL (the asset's LOCC, for lamps through its unshadowed maps, as
 * qtool_bake_relight8_lin does); every light's Q16.16 output summed per pixel in 64 bits and
 * saturated to int32 once, then written through platform/soft (exposure, srgb) into rgb8 (w h 3
 * bytes); lin (may be NULL) gets the linear frame as qtool_bake_relight8_lin gives it. One light
 * gives the bytes qtool_bake_relight8_lin gives. 0, or -1 with *status set (QTOOL_E_NOMEM
 * for out of memory). */
int qtool_relight_frame(const qibl_shmaps_t *m, const qibl_shlight_t *sh, const qibl_shmaps_t *mp,
                        const qibl_pmap_t *pm, const qibl_ylut_t *lut, const qibl_lampocc_t *occ,
                        const qibl_pointlight_t *points, uint32_t npoints, uint32_t exposure, int srgb, uint8_t *rgb8,
                        float *lin, double *ms, qibl_status_t *status);
/* The same with goniometric lamps: gonio (may be NULL) holds npoints entries, each NULL for an
 * isotropic lamp or the lamp's table and frame; its scale multiplies the lamp's light toward each
 * pixel (qibl_gonio_scale_span) before the lamp occlusion. All NULL gives qtool_relight_frame's bytes. */
int qtool_relight_frame_gonio(const qibl_shmaps_t *m, const qibl_shlight_t *sh, const qibl_shmaps_t *mp,
                              const qibl_pmap_t *pm, const qibl_ylut_t *lut, const qibl_lampocc_t *occ,
                              const qibl_pointlight_t *points, const qibl_gonio_t *const *gonio, uint32_t npoints,
                              uint32_t exposure, int srgb, uint8_t *rgb8, float *lin, double *ms,
                              qibl_status_t *status);

/* The whole soft relight of an opened asset with o's light (sh: its directional part or NULL; pts:
 * its lamps; ies: the profile shaping every lamp, or NULL) into rgb8 and lin (may be NULL). */
int qtool_relight_render(const qtool_relight_opts *o, const qtool_relight_asset *s, const qibl_shlight_t *sh,
                         const qibl_pointlight_t *pts, uint32_t npts, const qtool_relight_ies *ies, uint8_t *rgb8,
                         float *lin, double *ms, qibl_status_t *status);

/* ---- a light on a baked path (path.c) ----------------------------------------------------------- */

/* The path index of spec in the asset: a number, or the first path of a kind ("sun" directions,
 * "lamp" positions). 0; -1 with err set (no such path); -2 with err set (spec is not an index, sun or
 * lamp: a bad argument). in names the asset in the messages. */
int qtool_relight_pick_path(const qibl_asset_t *a, const char *in, const char *spec, uint32_t *index, char *err,
                            size_t errlen);

/* What --path relights: the light at tq (0..QIBL_LIGHTPATH_T_MAX) on the path, colour rgb. */
typedef struct qtool_relight_path_req {
    uint32_t index, tq, radius;   /* radius: soft shadows' half-width in t, capped to QIBL_LIGHTPATH_MAX_RADIUS */
    double rgb[3];
    const double *sky;            /* NULL, or the sky's RGB (through the shadowed maps) */
    const qibl_gonio_t *gonio;    /* NULL, or the lamp's IES profile (lamp paths only) */
    int lin;                      /* the linear frame is wanted: lin NULL then means out of memory */
} qtool_relight_path_req;

/* Relights the asset (bytes, n; a opened on them; in its name for the messages) with r into rgb8
 * (w h 3; NULL: the caller ran out of memory) and lin; *point says whether the path holds positions.
 * 0, or -1 with err set (the path's light, out of memory, a sun path given a gonio, a core error). */
int qtool_relight_path(const uint8_t *bytes, size_t n, const qibl_asset_t *a, const char *in,
                       const qtool_relight_path_req *r, uint8_t *rgb8, float *lin, double *ms, int *point, char *err,
                       size_t errlen);

#endif
