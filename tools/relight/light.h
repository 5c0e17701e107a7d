/*
 * relight/light.h - the light of `qibl relight`: any number of suns and point lamps, a light list
 * from `qibl lights --csv`, and a whole probe (its SH, median-cut lights, or sun plus sky),
 * optionally rotated. The directional part becomes one radiance SH light (the asset's maps hold the
 * cosine and visibility, so no irradiance convolution); point lamps are relit one by one and summed
 * per pixel in 64 bits (relight.h). Hosted, double where it helps; the CLI parses the options into
 * qtool_relight_light_list and prints what these functions return.
 */
#ifndef QTOOL_RELIGHT_LIGHT_H
#define QTOOL_RELIGHT_LIGHT_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "io/probe_layout.h"
#include "qibl/lightprobe.h"
#include "qibl/shmap.h"

#define QTOOL_RELIGHT_MAX_SOURCES 64u    /* --sun and --point options together */
#define QTOOL_RELIGHT_PROBE_DEFAULT_N 64L /* median-cut lights of --probe-mode lights and sunsky */
#define QTOOL_RELIGHT_SUN_CONTRAST 32.0  /* sun regions: mean radiance >= 32 x the probe's mean */
#define QTOOL_RELIGHT_SUN_MAX 32u

typedef enum qtool_relight_probe_mode {
    QTOOL_RELIGHT_PROBE_SH = 0, /* the probe's SH */
    QTOOL_RELIGHT_PROBE_LIGHTS, /* its median-cut lights */
    QTOOL_RELIGHT_PROBE_SUNSKY  /* the sun regions as lights, the rest as SH */
} qtool_relight_probe_mode;

typedef struct qtool_relight_source {
    int point;    /* 0: --sun (v a direction), 1: --point (v a position) */
    int32_t v[3]; /* Q16.16 */
    int32_t rgb[3]; /* Q16.16, >= 0 */
    int have_rgb;
} qtool_relight_source;

typedef struct qtool_relight_light_list {
    uint32_t count, suns, points;
    qtool_relight_source src[QTOOL_RELIGHT_MAX_SOURCES];
    int early_rgb; /* an --rgb before the first light: it colours that light */
    int32_t rgb0[3];
    const char *csv;   /* --lights FILE.csv */
    const char *probe; /* --probe FILE.hdr */
    qtool_probe_layout_t layout;
    qtool_relight_probe_mode mode;
    long n;         /* -n: 0 for QTOOL_RELIGHT_PROBE_DEFAULT_N */
    int rotate;     /* 0 none, 1 --yaw, 2 --rotate */
    double yaw;     /* degrees */
    double r[3][3]; /* the rotation (--yaw makes one too) */
} qtool_relight_light_list;

/* The empty list; every default (zero is the default of every field) lives here. */
#define QTOOL_RELIGHT_LIGHT_LIST_DEFAULT {.layout = QTOOL_PROBE_LAYOUT_AUTO, .mode = QTOOL_RELIGHT_PROBE_SH}
void qtool_relight_light_list_init(qtool_relight_light_list *ll);

/* Appends a --sun (point 0) or --point (point 1) at v (Q16.16), white or coloured by an early
 * --rgb. 0, or -1 when the list already holds QTOOL_RELIGHT_MAX_SOURCES (nothing written). */
int qtool_relight_light_list_add(qtool_relight_light_list *ll, int point, const int32_t v[3]);

/* 1 if the list has a directional part (a sun, a CSV file or a probe). */
int qtool_relight_light_list_directional(const qtool_relight_light_list *ll);

/* The rotation of --yaw DEG (about +z: +x turns toward +y). */
void qtool_relight_yaw(double deg, double r[3][3]);
/* Whether the row-major v is a rotation as the core takes one: rows orthonormal within 2^-16 and
 * det > 0. 0 if so, -1 if not; *worst (the largest |r r^T - I| entry) and *det either way. */
int qtool_relight_rotation_check(const double v[9], double *worst, double *det);

/* The directional part as Q16.16 radiance SH for k maps: the suns, the CSV lights, the probe
 * (rotated once with qibl_shlight_rotate). Notes (the probe's layout, the sun regions) go to note
 * (NULL: stderr). *faint (may be NULL) is set when the probe has light that rounds to nothing in
 * Q16.16 SH (the frame comes out exactly black), even when a later sum fails. 0, or -1 with a
 * one-line message in err (an unreadable file, a core error, a sum beyond Q16.16); out untouched. */
int qtool_relight_light_sh(const qtool_relight_light_list *ll, uint32_t k, FILE *note, qibl_shlight_t *out,
                           int *faint, char *err, size_t errlen);

/* A probe file in any layout (want: AUTO detects) as lat-long RGBE bytes (*rgbe malloc'd), with its
 * note (one line with its newline: the layout and how it was found) in note (may be NULL), so a
 * command can print it once everything after the load has succeeded. 0, or -1 with err set. */
int qtool_relight_probe_load(const char *path, qtool_probe_layout_t want, char *note, size_t notelen, int *w,
                             int *h, uint8_t **rgbe, qtool_probe_layout_t *used, char *err, size_t errlen);

/* The note of a probe load: "path: layout L (what, detected|from --layout)", then what was done
 * to the iw x ih input (resampled to lw x lh, or not 2:1), one line with its newline in note. */
void qtool_relight_probe_note(const char *path, qtool_probe_layout_t want, qtool_probe_layout_t used, int iw, int ih,
                              int lw, int lh, char *note, size_t notelen);

/* Picks the sun among the median-cut lights of a w x h probe (all of a list, so they cover the
 * probe's energy): the regions whose mean radiance (luminance / solid angle) is at least
 * QTOOL_RELIGHT_SUN_CONTRAST times the probe's mean radiance, densest first, at most
 * QTOOL_RELIGHT_SUN_MAX. Writes their indices to idx; returns how many (0: no sun, e.g. overcast). */
uint32_t qtool_relight_probe_suns(const qibl_lightprobe_light_t *l, uint32_t count, uint32_t w, uint32_t h,
                                  uint32_t *idx);

/* ---- point lamps without a colour (point.c) ----------------------------------------------------- */

/* --point without --rgb: C0 = QTOOL_RELIGHT_POINT_GREY * d^falloff, d the median distance from pos
 * to the n scene points pts (3 doubles each; points QTOOL_RELIGHT_SKY_DIST or more from the origin
 * are sky and skipped), so the lit scene comes out around mid-grey (Lambert, albedo 0.6, facing the
 * lamp at that distance: 0.6/pi x 2 = 0.38 linear, 166 of 255 through sRGB; the courtyard's median
 * pixel is about 110). *c0 is capped at QTOOL_RELIGHT_Q16_MAX, *dist is d (1 when every point is
 * sky). 0, or -1 (out of memory). */
#define QTOOL_RELIGHT_POINT_GREY 2.0
#define QTOOL_RELIGHT_SKY_DIST 1000.0
#define QTOOL_RELIGHT_Q16_MAX (2147483647.0 / 65536.0)
int qtool_relight_point_default(const double *pts, size_t n, const double pos[3], int falloff, double *c0,
                                double *dist);

/* A P map's points as doubles (w h 3, malloc'd), for qtool_relight_point_default; NULL when out of
 * memory. */
double *qtool_relight_pmap_points(const qibl_pmap_t *pm);

/* The mean of the 8-bit RGB frame (np pixels), and the mean below which a frame is almost black. */
#define QTOOL_RELIGHT_DARK_MEAN 32.0
double qtool_relight_mean8(const uint8_t *rgb, size_t np);

#endif
