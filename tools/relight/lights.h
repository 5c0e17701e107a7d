/*
 * relight/lights.h - what `qibl lights` computes: a light probe (any layout, resampled to lat-long)
 * turned into directional lights by the integer core (qibl/lightprobe.h), the picture of its regions
 * and directions over the tone-mapped probe (like Madsen & Laursen's Figure 3), the irradiance error
 * of the lights against the probe's own, and the cheapest representation within a budget (--auto,
 * tools/study). The command parses into qtool_relight_lights_opts (defaults:
 * QTOOL_RELIGHT_LIGHTS_OPTS_DEFAULT), calls these and prints the table, CSV, JSON or glTF.
 */
#ifndef QTOOL_RELIGHT_LIGHTS_H
#define QTOOL_RELIGHT_LIGHTS_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "io/probe_layout.h"
#include "qibl/lightprobe.h"
#include "study/study.h"

/* How the core reads the probe: its RGBE bytes as stored, or converted (exactly for f32). */
typedef enum qtool_relight_lights_as {
    QTOOL_RELIGHT_LIGHTS_AS_RGBE = 0,
    QTOOL_RELIGHT_LIGHTS_AS_SRGBE,
    QTOOL_RELIGHT_LIGHTS_AS_F32
} qtool_relight_lights_as;

/* What a `qibl lights` document is written as. */
typedef enum qtool_relight_lights_fmt {
    QTOOL_RELIGHT_LIGHTS_TABLE = 0,
    QTOOL_RELIGHT_LIGHTS_CSV,
    QTOOL_RELIGHT_LIGHTS_JSON,
    QTOOL_RELIGHT_LIGHTS_C /* --auto's pick as a C fragment */
} qtool_relight_lights_fmt;

typedef struct qtool_relight_lights_opts {
    const char *path, *png;
    qibl_lightprobe_opts_t core; /* method, priority, placement */
    long n;                      /* lights asked for */
    long zoom;                   /* the picture's; 0: qtool_relight_lights_zoom's choice */
    qtool_relight_lights_as as;
    qtool_probe_layout_t layout;
    int csv, json, cfmt, error, autom, gltf;
    double budget;               /* --auto's, a fraction; < 0: none given */
    int rotate;                  /* --preset gltf: turn the lights by r (--yaw or --rotate) */
    double r[3][3];
} qtool_relight_lights_opts;

#define QTOOL_RELIGHT_LIGHTS_OPTS_DEFAULT                                                                     \
    {.n = 64, .as = QTOOL_RELIGHT_LIGHTS_AS_RGBE, .layout = QTOOL_PROBE_LAYOUT_AUTO, .budget = -1}

/* --png picture limits: the PNG writer's side limit, and 2^25 pixels (96 MB of RGB) */
#define QTOOL_RELIGHT_LIGHTS_PNG_MAX_SIDE 65535u
#define QTOOL_RELIGHT_LIGHTS_PNG_MAX_PIXELS (1u << 25)

/* A lat-long probe: w x h RGBE bytes (malloc'd). */
typedef struct qtool_relight_lights_probe {
    int w, h;
    uint8_t *px;
} qtool_relight_lights_probe;

/* Reads the probe at path in any layout (want: AUTO detects) and resamples it to lat-long (a copy
 * even when it is one); note gets one line with its newline saying the layout and how it was found.
 * 0, or -1 with err set (nothing to free). */
int qtool_relight_lights_load(const char *path, qtool_probe_layout_t want, qtool_relight_lights_probe *p,
                              char *note, size_t notelen, char *err, size_t errlen);
void qtool_relight_lights_probe_free(qtool_relight_lights_probe *p);

/* The picture's zoom: zoom when not 0, else 1 for probes 512 wide or more and enough to make the
 * picture about 1024 wide otherwise. */
int qtool_relight_lights_zoom(int w, int h, long zoom);
/* Whether a w x h probe zoomed by z fits the picture limits (0) or not (-1). */
int qtool_relight_lights_zoom_fits(int w, int h, int z);
/* The largest zoom (at least 1) that keeps a w x h probe's picture within the limits. */
uint64_t qtool_relight_lights_max_zoom(int w, int h);

/* The lights of the probe: o->n at most, by o->core, read as o->as; *L malloc'd (o->n entries).
 * 0; 1 for an all-black probe (a valid answer: no lights, *L NULL); -1 with err set (the message
 * names path where the core refused the probe) and *L NULL. */
int qtool_relight_lights_fit(const qtool_relight_lights_opts *o, const qtool_relight_lights_probe *p,
                             qibl_lightprobe_light_t **L, qibl_lightprobe_result_t *res, char *err, size_t errlen);

/* The lights' directions turned by r when rotate (light from d comes from r d, as relight turns the
 * probe) and their colours as doubles: dir and rgb hold n entries each. */
void qtool_relight_lights_turned(const qibl_lightprobe_light_t *L, uint32_t n, int32_t rgb_exp, int rotate,
                                 const double r[3][3], double (*dir)[3], double (*rgb)[3]);

/* The picture: the probe tone-mapped (Reinhard's global operator at the log-average key, sRGB-ish
 * gamma), zoomed by z, every light's region outlined in green and its direction marked in red;
 * (w z) x (h z) RGB bytes malloc'd, NULL when out of memory. */
uint8_t *qtool_relight_lights_draw(const qtool_relight_lights_probe *p, int z, const qibl_lightprobe_light_t *L,
                                   uint32_t n);

/* The lights' irradiance against the probe's own over nn normals (tools/ref, double): mean and max
 * relative error. 0, or -1 (out of memory). */
#define QTOOL_RELIGHT_LIGHTS_ERROR_NORMALS 1024
int qtool_relight_lights_error(const qtool_relight_lights_probe *p, const qibl_lightprobe_light_t *L, uint32_t n,
                               int32_t rgb_exp, double *mean, double *max);

/* --auto: the cheapest representation within the budget (tools/study/auto.c), its table on log.
 * 0, or -1 with err set. */
int qtool_relight_lights_auto(const qtool_relight_lights_probe *p, double budget, FILE *log, qtool_study_pick *pick,
                              char *err, size_t errlen);

#endif
