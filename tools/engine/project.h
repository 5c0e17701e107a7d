/*
 * engine/project.h - `qibl sh project`'s work: a lat-long RGBE probe projected onto SH by the integer
 * core (qibl/probe.h), row by row, and written in qibl's basis (table, JSON or a C header; --frame,
 * a rotation) or in an engine's own convention (the presets of engine.h: cmgen's sh.txt, Unity's
 * SphericalHarmonicsL2, EXT_lights_image_based).
 */
#ifndef QTOOL_ENGINE_PROJECT_H
#define QTOOL_ENGINE_PROJECT_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "engine/engine.h"
#include "io/probe_layout.h"
#include "qibl/probe.h"

typedef enum qtool_sh_format { QTOOL_SH_FORMAT_TABLE = 0, QTOOL_SH_FORMAT_JSON, QTOOL_SH_FORMAT_C } qtool_sh_format;

typedef struct qtool_sh_project_opts {
    long bands;                  /* 1..QIBL_SH_MAX_BANDS (a preset: 3) */
    qibl_probe_sh_opts_t core;   /* irradiance, window (raw only) */
    qtool_sh_format format;      /* raw only; a preset writes the engine's own text */
    const char *name;            /* the C array (--format c) or the glTF light (NULL: none for gltf) */
    qtool_engine_preset preset;
    qtool_engine_frame frame;    /* raw only */
    double engine_window;        /* filament's window (QTOOL_ENGINE_WINDOW_AUTO, _NO or a cutoff) */
    const double (*rot)[3];      /* a rotation (3 x 3) applied first, NULL for none */
    int rot_kind;                /* for the labels: 1 --yaw, 2 --rotate */
} qtool_sh_project_opts;

#define QTOOL_SH_PROJECT_OPTS_DEFAULT                                                                    \
    {.bands = QIBL_SH_MAX_BANDS, .core = {0, QIBL_PROBE_WINDOW_NONE, 0}, .format = QTOOL_SH_FORMAT_TABLE, \
     .name = "qibl_probe_sh", .preset = QTOOL_ENGINE_RAW, .frame = QTOOL_ENGINE_FRAME_ZUP,                \
     .engine_window = QTOOL_ENGINE_WINDOW_AUTO, .rot = NULL, .rot_kind = 0}

/* The names of the core's windows, by qibl_probe_window_t. */
extern const char *const qtool_sh_window_names[3];

/* Projects the probe (w x h RGBE lat-long px, its layout `used`, named path in labels) and writes
 * the result on out; note (the loader's line about the layout) goes on out as a comment for the
 * table, on log otherwise. Nothing is written on out unless the whole projection succeeded.
 * 0, or -1 with err set. */
int qtool_sh_project(const qtool_sh_project_opts *o, const char *path, const uint8_t *px, int w, int h,
                     qtool_probe_layout_t used, const char *note, FILE *out, FILE *log, char *err, size_t errlen);

#endif
