/*
 * engine/engine.h - qibl's SH and lights in each engine's own convention (hosted, double).
 *
 * In: radiance SH in qibl's basis and frame (qibl/sh.h: z up, real orthonormal SH with the
 * Condon-Shortley phase, index l*l + l + m; a probe's pixel (u, v) looks along theta from +z,
 * phi from +x toward +y), as `qibl sh project` computes them. Out, per preset:
 *
 *   raw       the coefficients unchanged (qibl's frame, or --frame yup: (x, y, z)_yup =
 *             (x, z, -y)_qibl, the inverse of the Y-up to Z-up turn of `qibl transfer` and the
 *             scene loaders).
 *   filament  what Filament's cmgen writes to sh.txt with --deploy / --sh-shader (google/filament
 *             tools/cmgen/src/cmgen.cpp sphericalHarmonics, libs/ibl/src/CubemapSH.cpp computeSH,
 *             windowSH, preprocessSHForShader): 3 bands,
 *               out_i = L'_i * A_l * w_l * S_i / pi
 *             L' the radiance SH in cmgen's frame (the equirect turned into a cubemap, then
 *             mirrored in x as cmgen does by default: s = (y, z, -x)_qibl), A_l = pi, 2 pi / 3,
 *             pi / 4 (computeTruncatedCosSh), w_l = (sin(pi l / c) / (pi l / c))^4 for l < c and 0
 *             beyond (sincWindow; c from --window: cmgen's auto search by default, "no", or a
 *             cutoff), S_i Sloan's polynomial constants with their signs (1/(2 sqrt pi),
 *             -sqrt3/(2 sqrt pi), ...). The shader (Irradiance_SphericalHarmonics) then gives
 *             E(n) / pi = sum_i out_i poly_i(n), poly = 1, y, z, x, yx, yz, 3z^2 - 1, zx, x^2 - y^2.
 *   unity     SphericalHarmonicsL2 as Unity stores it (RenderSettings.ambientProbe; HDRP's
 *             SphericalHarmonicMath.UndoCosineRescaling documents the scale):
 *               U[c, i] = L'_i * N_i,  N = {c0, -c1, c1, -c1, c2, -c2, c3, -c2, c4},
 *             c0 = 1/(2 sqrt pi), c1 = sqrt3/(3 sqrt pi), c2 = sqrt15/(8 sqrt pi),
 *             c3 = sqrt5/(16 sqrt pi), c4 = sqrt15/(16 sqrt pi) (Y's constants times A_l / pi),
 *             L' in Unity's world frame (y up, left-handed), the frame in which the panoramic
 *             skybox (ToRadialCoords: u = 0.5 - atan2(z, x) / 2 pi, v = 1 - acos(y) / pi) shows
 *             the probe: (x, y, z)_unity = (-x, z, y)_qibl. Packed for ShadeSH9 (UnityCG.cginc;
 *             HDRP PackCoefficients): SHA = (U3, U1, U2, U0 - U6) per channel, SHB = (U4, U5,
 *             3 U6, U7), SHC = (U8 r, U8 g, U8 b, 1); ShadeSH9(n) = SHA.(n, 1) + SHB.(xy, yz, zz,
 *             zx) + SHC (x^2 - y^2) = E(n) / pi.
 *   gltf      EXT_lights_image_based irradianceCoefficients: E_i = A_l L'_i, 9 RGB, index order
 *             l*l + l + m, basis as qibl's (Ramamoorthi and Hanrahan's, the README's reference;
 *             Babylon.js reads them so), in glTF's frame (y up, right-handed) with the probe
 *             placed as Filament's glTF viewer shows cmgen's output: (x, y, z)_gltf =
 *             (y, z, -x)_qibl. Lights as KHR_lights_punctual directional lights: one node per
 *             light whose rotation turns the node's -z into the direction the light travels.
 *
 * Every function checks its arguments and returns 0 or -1 with one line in err (may be NULL).
 */
#ifndef QTOOL_ENGINE_ENGINE_H
#define QTOOL_ENGINE_ENGINE_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "qibl/probe.h"

/* The presets in value order as X(name, text): the one list the enum and the names
 * qtool_engine_preset_parse takes and qtool_engine_preset_name gives are made from. */
#define QTOOL_ENGINE_PRESET_LIST(X)                                                                       \
    X(QTOOL_ENGINE_RAW, "raw") /* default (0) */                                                          \
    X(QTOOL_ENGINE_FILAMENT, "filament")                                                                  \
    X(QTOOL_ENGINE_UNITY, "unity")                                                                        \
    X(QTOOL_ENGINE_GLTF, "gltf")

typedef enum qtool_engine_preset {
#define QTOOL_ENGINE_PRESET_ENUM_(name, text) name,
    QTOOL_ENGINE_PRESET_LIST(QTOOL_ENGINE_PRESET_ENUM_)
#undef QTOOL_ENGINE_PRESET_ENUM_
    QTOOL_ENGINE_PRESET_COUNT
} qtool_engine_preset;

typedef enum qtool_engine_frame {
    QTOOL_ENGINE_FRAME_ZUP = 0, /* qibl's own (default) */
    QTOOL_ENGINE_FRAME_YUP
} qtool_engine_frame;

/* Radiance SH (or any SH) in qibl's basis: c[i][channel], i < bands^2. */
typedef struct qtool_engine_sh {
    int bands; /* 1..5 */
    double c[25][3];
} qtool_engine_sh;

/* cmgen's --sh-window: auto (the default), no, or a cutoff band c > 0 */
#define QTOOL_ENGINE_WINDOW_AUTO 0.0
#define QTOOL_ENGINE_WINDOW_NO (-1.0)
#define QTOOL_ENGINE_WINDOW_MAX 1.0e6 /* the largest cutoff --window takes (w_l = 1 - O(1e-11) there) */
/* cmgen's auto search: cutoff from 3 bands * 4 + 1 down by bisection, at most 16 steps */
#define QTOOL_ENGINE_AUTO_START 13.0
/* The Newton loop of cmgen's SH minimum has no bound; here it stops after this many steps. */
#define QTOOL_ENGINE_NEWTON_MAX 64

/* "raw", "filament", "unity", "gltf" <-> preset; parse: 0 or -1. The names by value, NULL-ended
 * (the CLI's option tables take them as they are). */
extern const char *const qtool_engine_preset_names[QTOOL_ENGINE_PRESET_COUNT + 1];
int qtool_engine_preset_parse(const char *s, qtool_engine_preset *out);
const char *qtool_engine_preset_name(qtool_engine_preset p);

/* "auto", "no" or a cutoff in (0, QTOOL_ENGINE_WINDOW_MAX]: 0 or -1. */
int qtool_engine_window_parse(const char *s, double *out);

/* The direction map of a preset: its direction = m times qibl's. frame applies to raw only. */
void qtool_engine_frame_matrix(qtool_engine_preset p, qtool_engine_frame frame, double m[3][3]);

/* The core's coefficients (c[ch][i] 2^exp) as doubles, rotated first by r (NULL: none) with the
 * core's qibl_sh_rotation_init / qibl_sh_rotate (r as `qibl relight --yaw/--rotate` makes it: light
 * from d comes from r d afterwards). -1 for bad bands, a non-rotation (the core's
 * QIBL_E_SH_ROTATION) or an exponent beyond double. */
int qtool_engine_sh_from_core(const qibl_probe_coeffs_t *c, const double r[3][3], qtool_engine_sh *out, char *err,
                              size_t errlen);

/* out = the coefficients of f(m^T d), f given by in: the same light in the frame d' = m d.
 * m orthogonal (det +1 or -1, checked within 1e-9); in and out may alias. */
int qtool_engine_sh_remap(const qtool_engine_sh *in, const double m[3][3], qtool_engine_sh *out, char *err,
                          size_t errlen);

/* cmgen's auto window on irradiance coefficients f (9, qibl's basis and index, any frame): the
 * cutoff its bisection ends at for one channel, starting from `start` (windowSH). */
double qtool_engine_cmgen_auto_cutoff(const double f[9], double start);
/* cmgen's estimate of the minimum over the sphere of sum f_i Y_i (windowSH's shmin, after
 * Sloan's "Deringing Spherical Harmonics"); NaN where cmgen's own arithmetic gives NaN (no linear
 * part, or the linear part along +-y). */
double qtool_engine_cmgen_shmin(const double f[9]);
/* sincWindow(l, cutoff): 1 for l = 0, 0 for l >= cutoff, (sin x / x)^4 with x = pi l / cutoff. */
double qtool_engine_cmgen_window(int l, double cutoff);

/* The filament preset: out[i][ch] as cmgen's sh.txt, i < 9, from radiance rad (qibl's frame,
 * bands >= 3). window: QTOOL_ENGINE_WINDOW_AUTO, _NO or a cutoff; *cutoff_used (may be NULL) gets
 * the cutoff applied (-1 for none). */
int qtool_engine_filament(const qtool_engine_sh *rad, double window, double out[9][3], double *cutoff_used,
                          char *err, size_t errlen);
/* The nine lines of sh.txt: "(%18.15f, %18.15f, %18.15f); // L<l><m>, irradiance, pre-scaled base" */
void qtool_engine_filament_write(FILE *f, const double out[9][3]);

/* The unity preset: sh[ch][i] (SphericalHarmonicsL2's [channel, index]) and the seven ShadeSH9
 * constants packed[0..6] = SHAr, SHAg, SHAb, SHBr, SHBg, SHBb, SHC, from radiance rad (bands >= 3). */
int qtool_engine_unity(const qtool_engine_sh *rad, double sh[3][9], double packed[7][4], char *err, size_t errlen);
/* C# lines: sh[c, i] assignments into a SphericalHarmonicsL2 and the packed constants as Vector4s. */
void qtool_engine_unity_write(FILE *f, const double sh[3][9], const double packed[7][4]);

/* The gltf preset: irradianceCoefficients[i][ch], i < 9, from radiance rad (bands >= 3). */
int qtool_engine_gltf(const qtool_engine_sh *rad, double coef[9][3], char *err, size_t errlen);
/* A JSON object with EXT_lights_image_based (lights[0], named name) and the scene reference. */
void qtool_engine_gltf_write(FILE *f, const char *name, const double coef[9][3]);
/* s as a JSON string body: quotes and backslashes escaped, control bytes as \u00XX. */
void qtool_engine_json_str(FILE *f, const char *s);

/* Directional lights as a KHR_lights_punctual JSON object: dir[k] the unit direction toward light
 * k in qibl's frame, rgb[k] its irradiance (E(n) = rgb max(0, n . dir)); each becomes a light with
 * intensity = max channel (lux when the probe is in cd/m^2) and color = rgb / intensity, and a node
 * whose rotation (x, y, z, w) turns -z into -dir in glTF's frame. -1 for a non-finite or zero dir. */
int qtool_engine_gltf_lights_write(FILE *f, const double (*dir)[3], const double (*rgb)[3], uint32_t n, char *err,
                                   size_t errlen);
/* The quaternion (x, y, z, w) of the node of a light toward dir (glTF frame, unit). */
void qtool_engine_gltf_light_rotation(const double dir[3], double q[4]);

/* Irradiance of 9 coefficients at unit normal n, E(n) = sum_i A_l L_i Y_i(n), channel ch (qibl's
 * basis; L and n in one frame). */
double qtool_engine_sh9_irradiance(const qtool_engine_sh *rad, int ch, const double n[3]);

/* SH9 truncation error of rad (bands >= 3) against the probe's exact irradiance: a w x h lat-long
 * RGBE probe, rotated by r (NULL: none) as rad was. Over 1024 normals, luminance: mean and max of
 * |E_sh9 - E_probe| / mean E_probe (the measure of `qibl lights --error`). 0 or -1 (out of memory). */
int qtool_engine_sh9_error(const qtool_engine_sh *rad, const uint8_t *rgbe, int w, int h, const double r[3][3],
                           double *mean, double *max, char *err, size_t errlen);

#endif
