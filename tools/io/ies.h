/*
 * io/ies.h - IES LM-63 photometric files (far-field luminaire intensity): reader, the luminous flux
 * integrated from the distribution, and the candela toward a direction in the lamp's frame. Hosted.
 *
 * Accepted: the 1986 (no first-line label), 1991 (IESNA91), 1995 (IESNA:LM-63-1995), 2002
 * (IESNA:LM-63-2002) and 2019 (IES:LM-63-2019) headers; keyword lines ([TEST], [MANUFAC], ...,
 * [MORE] continuations) or the 1986 free text before TILT=; TILT=NONE and TILT=INCLUDE (the tilt
 * block inline, read and checked, not applied: the data are for the luminaire as photometered);
 * TILT=<file> is refused by name (no file beside the .ies is ever opened: inline it as INCLUDE).
 * Photometric types C (1), B (2) and A (3); numbers separated by blanks, commas or line breaks
 * (LF, CR LF or CR; a UTF-8 byte-order mark before the first line is skipped).
 *
 * Angle grids (degrees), checked strictly increasing and within range:
 *   type C: vertical 0..180 (any sub-range; zero intensity outside it); horizontal one of
 *     {0} axial, 0..90 quadrilateral, 0..180 bilateral, 90..270 bilateral about the 90-270 plane,
 *     0..360 full;
 *   types A and B: vertical -90..90 (any sub-range), horizontal -90..90 or 0..90 (laterally
 *     symmetric about 0, mirrored).
 * Candela values: finite, >= 0; each is the file's value times the candela multiplier.
 */
#ifndef QTOOL_IO_IES_H
#define QTOOL_IO_IES_H

#include <stddef.h>
#include <stdint.h>

/* Limits, each a one-line named error: the file at most QTOOL_IES_MAX_FILE_BYTES (refused from its
 * size, before it is read); at most QTOOL_IES_MAX_HEADER_LINES lines before TILT=; each angle count
 * 1..QTOOL_IES_MAX_ANGLES and the candela table (vertical x horizontal) at most QTOOL_IES_MAX_VALUES,
 * checked before any table memory is taken and against what the file can hold (a number takes at
 * least two bytes); tilt angle count 1..QTOOL_IES_MAX_TILT; lamp count 1..QTOOL_IES_MAX_LAMPS; every
 * number finite and below 1e15 in magnitude. Memory: the file plus 8 bytes per angle and value. */
#define QTOOL_IES_MAX_FILE_BYTES ((size_t)16 << 20)
#define QTOOL_IES_MAX_HEADER_LINES 4096u
#define QTOOL_IES_MAX_ANGLES 1441u /* 0.25-degree steps over 0..360 */
#define QTOOL_IES_MAX_VALUES ((uint32_t)1 << 20)
#define QTOOL_IES_MAX_TILT 1441u
#define QTOOL_IES_MAX_LAMPS 1000000

enum { QTOOL_IES_TYPE_C = 1, QTOOL_IES_TYPE_B = 2, QTOOL_IES_TYPE_A = 3 };
enum { QTOOL_IES_TILT_NONE = 0, QTOOL_IES_TILT_INCLUDE = 1 };
/* Horizontal symmetry of the grid (how the integral and the lookup expand it), as X(name, value,
 * label): the one list from which the enum and qtool_ies_sym_name's labels are made. */
#define QTOOL_IES_SYM_LIST(X)                                                                             \
    X(QTOOL_IES_SYM_AXIAL, 1, "axial")                  /* C: one horizontal angle (0) */                 \
    X(QTOOL_IES_SYM_QUAD, 2, "quadrilateral")           /* C: 0..90, mirrored into the four quadrants */ \
    X(QTOOL_IES_SYM_BILATERAL, 3, "bilateral")          /* C: 0..180, mirrored about the 0-180 plane */  \
    X(QTOOL_IES_SYM_BILATERAL90, 4, "bilateral-90-270") /* C: 90..270, mirrored about the 90-270 plane */\
    X(QTOOL_IES_SYM_FULL, 5, "full")                    /* C: 0..360 */                                  \
    X(QTOOL_IES_SYM_AB_HALF, 6, "lateral-half")         /* A, B: horizontal 0..90, mirrored about 0 */   \
    X(QTOOL_IES_SYM_AB_FULL, 7, "lateral-full")         /* A, B: horizontal -90..90 */

typedef enum qtool_ies_sym {
#define QTOOL_IES_SYM_ENUM_(name, value, label) name = value,
    QTOOL_IES_SYM_LIST(QTOOL_IES_SYM_ENUM_)
#undef QTOOL_IES_SYM_ENUM_
} qtool_ies_sym;

#define QTOOL_IES_TEXT 96 /* bytes kept of each keyword's value (longer ones are cut) */

typedef struct qtool_ies {
    int version;                  /* 1986, 1991, 1995, 2002 or 2019 */
    uint32_t nkeywords;           /* keyword lines ([MORE] continuations not counted) */
    char test[QTOOL_IES_TEXT], manufac[QTOOL_IES_TEXT], luminaire[QTOOL_IES_TEXT], lamp[QTOOL_IES_TEXT];
    double stated_lumens;         /* luminaire flux a keyword states ([LUMINAIREOUTPUT], [_ABSOLUTELUMENS],
                                     [_LUMENS]...), or -1 */
    int tilt;                     /* QTOOL_IES_TILT_* */
    int tilt_geometry;            /* INCLUDE: lamp-to-luminaire geometry 1..3, else 0 */
    uint32_t ntilt;               /* INCLUDE: tilt angle count, else 0 */
    double *tilt_angle, *tilt_factor; /* INCLUDE: ntilt each (malloc'ed), else NULL */
    int nlamps;
    double lumens_per_lamp;       /* -1: absolute photometry; 0: not stated */
    double multiplier;            /* candela multiplier (already applied to cd) */
    uint32_t nv, nh;              /* vertical, horizontal angle counts */
    int type;                     /* QTOOL_IES_TYPE_* */
    int units;                    /* 1 feet, 2 metres */
    double width, length, height; /* luminous opening, in units */
    double ballast_factor;
    double factor2;               /* <= 1995: ballast-lamp photometric factor; 2002: future use;
                                     2019: file generation type */
    double watts;
    double *v, *h;                /* nv, nh angles (degrees, increasing) */
    double *cd;                   /* nh x nv candela: cd[j nv + i] at (h[j], v[i]), multiplier applied */
    qtool_ies_sym sym;
    double cd_min, cd_max;
} qtool_ies;

/* Reads path: the file checks of io/file.h, then qtool_ies_decode. 0, or -1 with a one-line reason
 * naming the file in err; *out untouched on failure. */
int qtool_ies_read(const char *path, qtool_ies *out, char *err, size_t errlen);
/* Parses a file image (len bytes). 0 with *out filled (free with qtool_ies_free), or -1 with a
 * one-line reason in err and *out untouched. */
int qtool_ies_decode(const uint8_t *buf, size_t len, qtool_ies *out, char *err, size_t errlen);
void qtool_ies_free(qtool_ies *ies);

/* The symmetry's name ("axial", "quadrilateral", "bilateral", "bilateral-90-270", "full",
 * "lateral-half", "lateral-full"). */
const char *qtool_ies_sym_name(qtool_ies_sym s);

/* Total luminous flux, lumens: the candela (times the ballast factor, and for files up to 1995 the
 * ballast-lamp photometric factor) integrated over the sphere, zone by zone as photometric software
 * does (the zonal-lumen method): along the latitude-like angle (type C vertical from the nadir,
 * type A vertical and type B horizontal from the equator) each zone between two grid angles a, b
 * counts its mean intensity (I_a + I_b) / 2 times cos a - cos b (C) or sin b - sin a (A, B), nothing
 * outside the vertical range; along the plane angle the trapezoid rule over the grid expanded by its
 * symmetry (axial: times 2 pi; quadrilateral: 4 x 0..90; bilateral: 2 x 0..180; a full grid stopping
 * short of 360 wraps to the 0 plane). Exact for isotropic (4 pi I) and cosine (pi I0) lamps; equal
 * to Photometric Toolbox's figure to 0.01 lm on fixtures/ies/SOURCES.md's files. */
double qtool_ies_lumens(const qtool_ies *ies);

/* Candela (same factors as qtool_ies_lumens) toward the unit direction d in the lamp's frame,
 * bilinear in the grid (symmetry expanded, zero outside the vertical range). The frame (x, y, z):
 *   type C: z = vertical angle 0 (nadir: the aim), y = (vertical 90, horizontal 0),
 *           x = (vertical 90, horizontal 90); d = cos V z + sin V (cos H y + sin H x);
 *   type B: z = (0, 0) the beam's centre, x = the polar (lateral) axis, y = (H 0, V 90);
 *           d = sin H x + cos H (cos V z + sin V y);
 *   type A: y the polar axis: d = sin V y + cos V (cos H z + sin H x).
 * Callers build x = y cross z from an aim (z) and an up (y, made orthogonal to z). */
double qtool_ies_candela(const qtool_ies *ies, const double d[3]);

/* The core's goniometric table (qibl/gonio.h: n x n octahedral texels in the lamp frame above,
 * Q1.15) from the profile: each texel centre's candela over the file's peak (cd_max times the
 * factors), rounded to nearest, so the peak is 32768 and an isotropic file gives 32768 everywhere.
 * table holds n n entries; n in QIBL_GONIO_MIN_N .. QIBL_GONIO_MAX_N (2..256). 0, or -1 for a bad n
 * or a file whose peak is 0 (nothing written then). *peak_cd (may be NULL): that peak. */
int qtool_ies_gonio_table(const qtool_ies *ies, uint32_t n, uint16_t *table, double *peak_cd);

/* A profile placed in the world, in double precision (the ray tracer's goniometric lamp, the truth
 * of qibl/gonio.h's tables): the frame as qibl_gonio_init makes it (z = aim, y = up made orthogonal,
 * x = y cross z) and the peak qtool_ies_gonio_table divides by. */
typedef struct qtool_ies_lamp {
    const qtool_ies *ies;
    double x[3], y[3], z[3], peak;
} qtool_ies_lamp;
/* 0, or -1 for a zero aim, an up (anti)parallel to it, or a dark profile. */
int qtool_ies_lamp_init(qtool_ies_lamp *l, const qtool_ies *ies, const double aim[3], const double up[3]);
/* I(d) / I_peak toward unit world direction d (ctx: a qtool_ies_lamp; tools/render/rt.h's gonio). */
double qtool_ies_lamp_scale(const void *ctx, const double d[3]);

#endif
