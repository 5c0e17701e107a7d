/*
 * probe/info.h - `qibl probe info`'s work: what a lat-long probe is (size, dynamic range, how
 * concentrated its energy is) and which lighting scheme fits it: its SH (9 coefficients), N
 * median-cut lights (16, 64) or sun plus SH, each with the irradiance error it gives against the
 * probe's own irradiance, by the one measure of tools/study (study.h: |E - E_gt| / max(E_gt, mean
 * E_gt / 10) per normal and channel, over QTOOL_STUDY_ERR_NORMALS normals, the number `qibl lights
 * --auto` prints for the same representation).
 *
 * The schemes are made as relight makes them: SH by the core's projection (irradiance), lights by
 * the core's median cut, the sun as the caller's pick_suns picks it (relight --probe-mode sunsky's
 * rule) with the rest of the probe's SH from the double reference (tools/ref/probe_ref.c) on the
 * probe with the sun's regions blacked out (what qibl_shlight_add_sun_sky computes in integers).
 *
 * Cost: size and dynamic range are read exactly in one pass over the decoded input; everything else
 * runs on the study's probe, box-averaged to at most QTOOL_STUDY_MAX_W x QTOOL_STUDY_MAX_W / 2 (the
 * ground truth was an exact sum of pixels x 1024 normals: 50 s and 405 MB for a 143 KB RLE file).
 */
#ifndef QTOOL_PROBE_INFO_H
#define QTOOL_PROBE_INFO_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "qibl/lightprobe.h"

/* the suns among count median-cut lights of a w x h probe: their indices into idx (room for
 * QTOOL_PROBE_INFO_MAX_SUNS), densest first; returns how many */
typedef uint32_t (*qtool_probe_sun_pick)(const qibl_lightprobe_light_t *l, uint32_t count, uint32_t w, uint32_t h,
                                         uint32_t *idx);
#define QTOOL_PROBE_INFO_MAX_SUNS 32u

typedef struct qtool_probe_info_opts {
    qtool_probe_sun_pick pick_suns; /* required */
    double sun_contrast;            /* what pick_suns calls a sun (x the mean radiance), for the report */
    double tie;  /* a scheme within this factor of the best error counts as as good; the cheaper one is picked */
    double good; /* so does one with a mean error at or below this (a few 8-bit levels at most) */
} qtool_probe_info_opts;

#define QTOOL_PROBE_INFO_OPTS_DEFAULT {.pick_suns = NULL, .sun_contrast = 0, .tie = 1.10, .good = 0.01}

enum { QTOOL_PROBE_SCHEME_SH = 0, QTOOL_PROBE_SCHEME_SUNSKY, QTOOL_PROBE_SCHEME_L16, QTOOL_PROBE_SCHEME_L64,
       QTOOL_PROBE_SCHEMES };

typedef struct qtool_probe_info {
    int w, h;            /* the input */
    size_t np, black;    /* pixels, black pixels */
    double lmax, lmin;   /* luminance: largest, smallest non-zero */
    int all_black;       /* no light: nothing below is set */
    int sw, sh;          /* the evaluated (box-averaged) size */
    double share[2];     /* energy of the brightest 0.1 % and 1 % of the sphere */
    int normals;         /* normals the error is measured over */
    double me[QTOOL_PROBE_SCHEMES], mx[QTOOL_PROBE_SCHEMES]; /* mean, max relative irradiance error */
    char extra[QTOOL_PROBE_SCHEMES][64];                    /* a note after a scheme's line */
    int best, pick;      /* the lowest mean error; the cheapest about as good */
} qtool_probe_info;

/* Measures the w x h RGBE lat-long probe px (w = 2 h; path names it in messages). 0, or -1 with err
 * set and out untouched. */
int qtool_probe_info_compute(const qtool_probe_info_opts *o, const char *path, const uint8_t *px, int w, int h,
                             qtool_probe_info *out, char *err, size_t errlen);
/* The report (note first: the loader's line about the layout), path naming the probe in the advice. */
void qtool_probe_info_write(const qtool_probe_info_opts *o, const qtool_probe_info *in, const char *path,
                            const char *note, FILE *out);

#endif
