/*
 * relight/gles.h - `qibl relight --gles`: one light through platform/gles2 on a headless EGL
 * context, so the GPU path and the core + platform/soft path can be compared by eye or by bytes.
 * Without the EGL/GLES2 headers at build time it prints one line saying so and fails.
 */
#ifndef QTOOL_RELIGHT_GLES_H
#define QTOOL_RELIGHT_GLES_H

#include <stdint.h>

#include "qibl/gonio.h"
#include "qibl/shmap.h"

/* What `qibl relight` asks for, already parsed and taken from the asset. */
typedef struct qtool_gles_relight_req {
    const qibl_shmaps_t *maps;
    const qibl_pmap_t *pmap; /* NULL: directional */
    const qibl_ylut_t *lut;  /* NULL: direct SH (points) */
    qibl_q16_t sun[3], pos[3], rgb[3];
    int falloff, nearest, linear;
    qibl_uq16_t exposure;
    const qibl_gonio_t *gonio; /* a goniometric point lamp (--ies), or NULL */
} qtool_gles_relight_req;

/* Renders the request with platform/gles2 into rgb (w x h x 3 bytes, top row first). 0, or 1 with a
 * one-line message on stderr. *passes and *renderer (64 bytes) describe the run. */
int qtool_gles_relight(const qtool_gles_relight_req *r, uint8_t *rgb, uint32_t *passes, char *renderer);

#endif
