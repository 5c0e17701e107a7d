/*
 * gen/scene.h - a small procedural scene and its analytic light-transport SH maps, for tests,
 * benchmarks and the CLI while the ray-traced bake (issue "Bake pipeline") is not there.
 *
 * The scene: an open courtyard seen from a viewpoint 1.6 units above the ground (z up): ground,
 * four walls, pillars, a sphere and a box, each with a colour, Lambertian plus an optional glossy
 * (normalised Phong) lobe. Per pixel the transfer function is
 *   T(w) = albedo / pi max(0, n.w) + ks (s + 2) / (2 pi) max(0, r.w)^s
 * (n the normal, r the mirror direction of the view ray), projected onto SH analytically with the
 * Funk-Hecke theorem: T_lm = a_l Y_lm(n) + g_l Y_lm(r). No shadows (the bake does those).
 * Hosted, double precision.
 */
#ifndef QTOOL_GEN_SCENE_H
#define QTOOL_GEN_SCENE_H

#include <stddef.h>
#include <stdint.h>

typedef enum { QTOOL_PANO_CYLINDRICAL = 0, QTOOL_PANO_EQUIRECT } qtool_pano_kind;

/* The unit view direction through pixel (x, y)'s centre of a w x h panorama of the kind
 * (cylindrical: square pixels, so its height spans a tangent of pi h / w). */
void qtool_gen_pano_dir(uint32_t w, uint32_t h, qtool_pano_kind kind, uint32_t x, uint32_t y, double d[3]);

typedef struct qtool_gen_maps {
    uint32_t width, height, k;
    double *t;    /* [i][ch][y * width + x]: k * 3 planes of transfer coefficients */
    int32_t *p;   /* [y * width + x][3]: hit points, Q16.16 scene units, viewpoint at the origin */
    double *dir;  /* [y * width + x][3]: unit view-ray directions */
} qtool_gen_maps;

/* Renders the procedural scene's SH transfer maps (k <= 25). 0, or -1 on a bad size or no memory. */
int qtool_gen_scene(uint32_t width, uint32_t height, uint32_t k, qtool_pano_kind kind, qtool_gen_maps *out);
void qtool_gen_free(qtool_gen_maps *m);

/* Range packing of double maps to 8-bit planes with per map and channel scale and bias in Q8.24. */
typedef enum {
    QTOOL_PACK_MINMAX = 0, /* [min, max] of each plane maps to [0, 255] */
    QTOOL_PACK_ROBUST      /* [0.1th, 99.9th percentile]: finer steps, rare outliers clipped */
} qtool_pack_scheme;

typedef struct qtool_pack_stats {
    double rms, max_abs;  /* of decoded - exact over every coefficient of every pixel */
    uint64_t clipped;     /* coefficients that fell outside the packed range */
} qtool_pack_stats;

/* Packs m into scale/bias (k * 3 each, index i * 3 + ch) and planes (k * 3 * w * h bytes, plane
 * i * 3 + ch). 0, or -1 if memory runs out. */
int qtool_pack_maps(const qtool_gen_maps *m, qtool_pack_scheme scheme, int32_t *scale, int32_t *bias, uint8_t *planes,
                   qtool_pack_stats *stats);

/* One plane's packing, as qtool_pack_maps does it: the range [lo, hi] as scale and bias (Q8.24), and
 * a value's byte against them. A tile of rows packed with the whole image's lo and hi gets the
 * whole image's bytes (bake/tile.h). */
void qtool_pack_range(double lo, double hi, int32_t *scale, int32_t *bias);
uint8_t qtool_pack_code(double t, int32_t scale, int32_t bias);

/* Exact-in-double reconstruction for checks: sum_i T_i L_i at pixel (x, y), channel ch, from the
 * unquantised maps. */
double qtool_gen_eval(const qtool_gen_maps *m, uint32_t x, uint32_t y, uint32_t ch, const double *l);

#endif
