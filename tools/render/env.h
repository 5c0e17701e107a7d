/*
 * render/env.h - ground truth under a whole light probe: the panorama of a scene (render/rt.h)
 * lit by a lat-long environment, every direction shadowed, by importance-sampled Monte Carlo.
 *
 * Per pixel the renderer estimates  I = integral L(w) T(w) dw  with T the transfer of rt.h
 * (visibility, Lambert, glossy lobe) and L the probe as a piecewise-constant function: pixel (u, v)
 * covers phi in [u, u + 1) 2 pi / W and theta in [v, v + 1) pi / H (qibl's lat-long convention,
 * qibl/lightprobe.h: +z the top row, phi from +x towards +y), with its exact solid angle
 * dw_v = (2 pi / W) (cos(v pi / H) - cos((v + 1) pi / H)).
 *
 * The probe is split in two by luminance Y (Rec. 709):
 *   bright set B: pixels whose radiance Y is at least QTOOL_ENV_BRIGHT times the probe's mean
 *     radiance (sun, lamps, softboxes); sampled alone, proportional to Y dw, with a share of the
 *     samples equal to its share of the energy (at least 1, at most half);
 *   the rest R: the balance heuristic (multiple importance sampling) of sampling R proportional to
 *     Y dw and cosine sampling about the shading normal, half the remaining samples each.
 * Every sample is a stratified draw (the energy CDFs in 1D, the cosine lobe on a jittered grid)
 * with one shadow ray when it can contribute. The estimate is unbiased; its noise is measured by
 * the caller from two renders with different seeds (their difference).
 *
 * Deterministic: each pixel's random numbers come from (seed, pixel index) alone, so the image does
 * not depend on the thread count. jitter 0 places every sample at its pixel's centre (the Riemann
 * sum of the probe, what qibl's projection computes; used by tests).
 */
#ifndef QTOOL_RENDER_ENV_H
#define QTOOL_RENDER_ENV_H

#include <stddef.h>
#include <stdint.h>

#include "render/rt.h"

#define QTOOL_ENV_BRIGHT 32.0

typedef struct qtool_env {
    uint32_t w, h;
    float *rgb;       /* own copy, w h 3, linear radiance */
    double *cdf_b;    /* w h + 1 cumulative Y dw over B (pixels of R add 0) */
    double *cdf_r;    /* the same over R */
    uint32_t *guide_b, *guide_r; /* guide + 1 entries each: the pixel that cdf_find gives for the
                                  * fraction k / guide of the total (cdf_sample's search bounds) */
    size_t guide;     /* a power of two near w h / 4 */
    double *row_dw;   /* h: exact solid angle of a pixel of row v */
    double *row_c;    /* h + 1: cos(v pi / H) */
    uint8_t *in_b;    /* w h: 1 for the pixels of B */
    double e_b, e_r;  /* luminance energy (sum of Y dw) of B and R */
    size_t nb;        /* pixels in B */
} qtool_env;

/* Builds the sampling tables of a w x h lat-long probe (3 floats per pixel, rows top first,
 * finite and >= 0: else -1 with the pixel named in err). 0, or -1 (err says why: bad size, bad
 * sample, an all-black probe, no memory). */
int qtool_env_build(qtool_env *e, uint32_t w, uint32_t h, const float *rgb, char *err, size_t errlen);

/* The pixel that the render's sampling draws for (a, b) in [0, 1]^2 from the bright set's CDF
 * (bright != 0) or the rest's: a picks the row, b the pixel in it; each the first entry whose
 * cumulative energy exceeds the fraction (found between the guide's bounds). */
size_t qtool_env_sample(const qtool_env *e, int bright, double a, double b);
void qtool_env_free(qtool_env *e);

/* Radiance of the probe along unit d (the pixel d falls in). */
void qtool_env_lookup(const qtool_env *e, const double d[3], double rgb[3]);

/* Renders the pw x ph panorama (rt.h's pixel directions) lit by the probe: spp samples per pixel
 * (>= 4), seed, jitter (1: uniform over each probe pixel's solid angle; 0: its centre), threads
 * (>= 1). rgb: 3 doubles per pixel, linear, sky pixels 0. 0 or -1 (bad arguments). */
int qtool_env_render(const qtool_rt_scene *s, uint32_t pw, uint32_t ph, qtool_pano_kind kind, const qtool_env *e,
                     uint32_t spp, uint64_t seed, int jitter, int threads, double *rgb);

#endif
