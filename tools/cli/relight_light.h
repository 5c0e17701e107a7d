/*
 * relight_light.h - the light of `qibl relight`, built from its options: any number of suns and
 * point lamps, a light list from `qibl lights --csv`, and a whole probe (its SH, median-cut lights,
 * or sun plus sky), optionally rotated. The directional part becomes one radiance SH light (the
 * asset's maps hold the cosine and visibility, so no irradiance convolution); point lamps are relit
 * one by one and summed per pixel in 64 bits (relight_light.c).
 */
#ifndef QTOOL_CLI_RELIGHT_LIGHT_H
#define QTOOL_CLI_RELIGHT_LIGHT_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "io/probe_layout.h"
#include "qibl/gonio.h"
#include "qibl/lightprobe.h"
#include "qibl/lightpath.h"
#include "qibl/shmap.h"

#define QCLI_RELIGHT_MAX_SOURCES 64u     /* --sun and --point options together */
#define QCLI_PROBE_DEFAULT_N 64L         /* median-cut lights of --probe-mode lights and sunsky */
#define QCLI_SUN_CONTRAST 32.0           /* sun regions: mean radiance >= 32 x the probe's mean */
#define QCLI_SUN_MAX 32u

typedef enum qcli_probe_mode { QCLI_PROBE_SH = 0, QCLI_PROBE_LIGHTS, QCLI_PROBE_SUNSKY } qcli_probe_mode;

typedef struct qcli_relight_source {
    int point;            /* 0: --sun (v a direction), 1: --point (v a position) */
    int32_t v[3];         /* Q16.16 */
    int32_t rgb[3];       /* Q16.16, >= 0 */
    int have_rgb;
} qcli_relight_source;

typedef struct qcli_light_list {
    uint32_t count, suns, points;
    qcli_relight_source src[QCLI_RELIGHT_MAX_SOURCES];
    int early_rgb;        /* an --rgb before the first light: it colours that light */
    int32_t rgb0[3];
    const char *csv;      /* --lights FILE.csv */
    const char *probe;    /* --probe FILE.hdr */
    qtool_probe_layout_t layout;
    qcli_probe_mode mode;
    long n;               /* -n: 0 for QCLI_PROBE_DEFAULT_N */
    int rotate;           /* 0 none, 1 --yaw, 2 --rotate */
    double yaw;           /* degrees */
    double r[3][3];       /* the rotation (--yaw makes one too) */
} qcli_light_list;

void qcli_light_list_init(qcli_light_list *ll);

/* If argv[*i] is one of relight's light options (--sun, --point, --rgb, --lights, --probe,
 * --layout, --probe-mode, -n, --yaw, --rotate), parses it with its values, advances *i past them
 * and returns 1; 0 if it is none of them; 2 after a one-line message (bad arguments). */
int qcli_light_list_opt(int argc, char **argv, int *i, qcli_light_list *ll);

/* Checks the options together after parsing (an early --rgb with no light, -n without a probe,
 * a rotation without a probe, ...): 0, or 2 after a message. */
int qcli_light_list_check(const qcli_light_list *ll);

/* 1 if the list has a directional part (a sun, a CSV file or a probe). */
int qcli_light_list_directional(const qcli_light_list *ll);

/* The directional part as Q16.16 radiance SH for k maps: the suns, the CSV lights, the probe
 * (rotated once with qibl_shlight_rotate). Notes (the probe's layout, the sun regions) go to note.
 * 0, or 1 after a message (an unreadable file, a core error, a sum beyond Q16.16). */
int qcli_light_list_sh(const qcli_light_list *ll, uint32_t k, FILE *note, qibl_shlight_t *out);

/* A probe file in any layout (want: AUTO detects) as lat-long RGBE bytes (*rgbe malloc'd), with
 * one line on note (may be NULL) saying the layout and how it was found. 0, or 1 after a message. */
int qcli_probe_load(const char *path, qtool_probe_layout_t want, FILE *note, int *w, int *h, uint8_t **rgbe,
                    qtool_probe_layout_t *used);

/* The same with the note (one line, with its newline) written to a buffer instead, so a command can
 * print it only once everything after the load has succeeded (output all or nothing). */
int qcli_probe_load_note(const char *path, qtool_probe_layout_t want, char *note, size_t notelen, int *w, int *h,
                         uint8_t **rgbe, qtool_probe_layout_t *used);

/* Picks the sun among the median-cut lights of a w x h probe (all of a list, so they cover the
 * probe's energy): the regions whose mean radiance (luminance / solid angle) is at least
 * QCLI_SUN_CONTRAST times the probe's mean radiance, densest first, at most QCLI_SUN_MAX. Writes
 * their indices to idx; returns how many (0: no sun, e.g. an overcast sky). */
uint32_t qcli_probe_suns(const qibl_lightprobe_light_t *l, uint32_t count, uint32_t w, uint32_t h, uint32_t *idx);

/* A frame relit by the core: sh (NULL: no directional light) on the maps m, plus npoints point
 * lights on the maps mp with the P map pm and the LUT lut (NULL: direct SH), each scaled by the
 * lamp occlusion occ when not NULL (the asset's LOCC, for lamps through its unshadowed maps, as
 * qtool_bake_relight8_lin does); every light's Q16.16
 * output summed per pixel in 64 bits and saturated to int32 once, then written through
 * platform/soft (exposure, srgb) into rgb8 (w h 3 bytes); lin (may be NULL) gets the linear frame
 * as qtool_bake_relight8_lin gives it. One light gives the bytes qtool_bake_relight8_lin gives.
 * 0, or -1 with *status set (QIBL_E_NULL_POINTER for out of memory). */
int qcli_relight_frame(const qibl_shmaps_t *m, const qibl_shlight_t *sh, const qibl_shmaps_t *mp,
                       const qibl_pmap_t *pm, const qibl_ylut_t *lut, const qibl_lampocc_t *occ,
                       const qibl_pointlight_t *points, uint32_t npoints, uint32_t exposure, int srgb, uint8_t *rgb8,
                       float *lin, double *ms, qibl_status_t *status);
/* The same with goniometric lamps: gonio (may be NULL) holds npoints entries, each NULL for an
 * isotropic lamp or the lamp's table and frame; its scale multiplies the lamp's light toward each
 * pixel (qibl_gonio_scale_span) before the lamp occlusion. All NULL gives qcli_relight_frame's bytes. */
int qcli_relight_frame_gonio(const qibl_shmaps_t *m, const qibl_shlight_t *sh, const qibl_shmaps_t *mp,
                             const qibl_pmap_t *pm, const qibl_ylut_t *lut, const qibl_lampocc_t *occ,
                             const qibl_pointlight_t *points, const qibl_gonio_t *const *gonio, uint32_t npoints,
                             uint32_t exposure, int srgb, uint8_t *rgb8, float *lin, double *ms,
                             qibl_status_t *status);

#endif
