/*
 * luminaire/spots_gles.h - the near-field source's spotlights evaluated on a GLES2 GPU, one pass per
 * spotlight (Granier et al.'s model as the paper runs it): per frame the P map's points and the four
 * shading anchors' numerators are uploaded once (the anchors' unit point lamps computed by the core
 * on the CPU, as qtool_luminaire_relight computes them); per spotlight a fragment shader evaluates
 * its term as qtool_luminaire_spots_span does in meaning (gonio table lookup toward x - s, the
 * anchors' shading interpolated at s and divided by |x - s|^3, times the peak) and adds it to an
 * 8-bit sRGBE pair (hi and what hi leaves out), drawn only over the screen tiles its cull cone may
 * reach. Separate from render.c so that programs without GL need not link it.
 */
#ifndef QTOOL_LUMINAIRE_SPOTS_GLES_H
#define QTOOL_LUMINAIRE_SPOTS_GLES_H

#include <stddef.h>
#include <stdint.h>

#include "luminaire/luminaire.h"

/* What one GPU frame cost (wall clock, and CPU time since llvmpipe rasterises on threads of its own). */
typedef struct qtool_luminaire_gles_stats {
    double prep_ms;  /* CPU: the P map as floats, the anchors' shading (core), the tiles' bounds */
    double gpu_ms;   /* uploads and every pass, to glFinish */
    double read_ms;  /* the pair read back, decoded and written through platform/soft */
    double cpu_ms;   /* the process's CPU time over the frame, every thread (llvmpipe's included): what
                      * the frame costs whatever else the machine runs */
    uint32_t passes; /* spotlights drawn (a spotlight no tile can see is not drawn) */
    double coverage; /* fragments shaded / (passes x pixels): what the tile cull saves */
    int fetch;       /* 1: the extensions' path ran (EXT_draw_buffers, EXT_shader_framebuffer_fetch) */
} qtool_luminaire_gles_stats;

/* How to draw (zero: the defaults). */
typedef struct qtool_luminaire_gles_opts {
    uint32_t frames; /* frames timed after one untimed warm-up (the shader's first compile); 0: 1 */
    int core_only;   /* 1: GLES2's core path even where the GL has EXT_draw_buffers and
                      * EXT_shader_framebuffer_fetch (two pairs ping-ponged, two draws per pass, each
                      * pass drawn over its tiles and the previous pass's); 0: those extensions where
                      * present (the pair read and written in place, one draw per pass) */
} qtool_luminaire_gles_opts;

/* The frame of qtool_luminaire_relight (same s, mp, pm, lut, exposure, srgb; rgb8 w h 3) drawn by the
 * GPU with the caller's context current (tools/gles/headless.h), o (NULL: defaults) saying how; *st
 * (may be NULL) the mean over o's frames.
 * 0, or -1 with a one-line reason in err (no GL, no OES_texture_float, fewer than 8 texture units,
 * spotlights merged by a hierarchy (qtool_luminaire_spots_build with tol > 0: the GPU evaluates every
 * spotlight), a table atlas above GL_MAX_TEXTURE_SIZE, a shader or framebuffer refused, a GL error, no memory,
 * a status of the core's). Nothing is written to rgb8 on failure. */
int qtool_luminaire_relight_gles(const qtool_luminaire_spots *s, const qibl_shmaps_t *mp, const qibl_pmap_t *pm,
                                 const qibl_ylut_t *lut, uint32_t exposure, int srgb,
                                 const qtool_luminaire_gles_opts *o, uint8_t *rgb8, qtool_luminaire_gles_stats *st,
                                 char *err, size_t errlen);

/* The same from the points and the anchors' shading given: pts w h 3 Q16.16 (row-major), base
 * s->nanchor planes of w h 3 Q16.16 (plane k at base + 3 w h k: what the unit lamp at anchor k gives
 * each pixel, as qtool_luminaire_spots_span's base), e.g. a ray tracer's. Statuses as above. */
int qtool_luminaire_spots_gles(const qtool_luminaire_spots *s, uint32_t w, uint32_t h, const int32_t *pts,
                               const int32_t *base, uint32_t exposure, int srgb, const qtool_luminaire_gles_opts *o,
                               uint8_t *rgb8, qtool_luminaire_gles_stats *st, char *err, size_t errlen);

/* The largest and the mean |a - b| over n bytes (8-bit frames). */
void qtool_luminaire_diff8(const uint8_t *a, const uint8_t *b, size_t n, int *max, double *mean);

#endif
