/*
 * luminaire/luminaire.h - near-field light sources (Granier, Goesele, Heidrich and Seidel,
 * "Interactive Visualization of Complex Real-World Light Sources", ../shared/papers): the .qnf file,
 * a simulated acquisition (the paper's Figure 1, ray-traced), and rendering as a grid of textured
 * spotlights, each a goniometric point lamp of the core (qibl/gonio.h), summed pass by pass in
 * integers. Hosted (libc, libm); the rendering kernel itself is integer only.
 *
 * The source's frame (paper section 2): the sampling plane S is z = 0, the light crosses it toward
 * -z, the measurement plane M is z = -D. S carries a grid of nx x ny filter supports of spacing h,
 * centred on the origin: support (ix, iy) has its centre at u = (ix - (nx - 1) / 2) h,
 * v = (iy - (ny - 1) / 2) h. Each support m has an emission texture E'_m(s, t) (eq. 10, the
 * shift-invariant approximation: the irradiance measured behind the filter divided by the geometric
 * term cos^2 / R^2 at the support's centre), res x res RGB texels over the window
 * s in u +- D w, t in v +- D w of M (w = half_tan), texel (i, j) centred at
 * s = u + ((2 i + 1) / res - 1) D w, t = v + ((2 j + 1) / res - 1) D w. A point x below S receives
 * (eq. 14) E(x) ~ sum_m A f_m(x) E'_m(s, t), A = h^2 the basis' integral, (s, t) where the line from
 * the support's centre through x meets M, f_m = cos(theta) cos(theta') / delta^2: spotlight m is a
 * point lamp at its centre whose intensity toward x is I_m = A E'_m(s, t) cos(theta').
 *
 * .qnf layout (little-endian; docs/ARCHITECTURE.md "Near-field sources" has the same table):
 *   0  4  magic "QNF1"
 *   4  2  version (1)              6  2  header bytes (64)
 *   8  4  nx (1..64)              12  4  ny (1..64)
 *  16  4  res (2..128)            20  4  basis (1 box, 2 tent)
 *  24  4  spacing h, float32 (finite, 1e-6..1e6)
 *  28  4  plane distance D, float32 (finite, 1e-6..1e6)
 *  32  4  window half_tan w, float32 (finite, 0.01..16)
 *  36  4  channels (3)            40  4  payload bytes (nx ny res res 12)
 *  44  4  CRC-32 of the payload   48  4  CRC-32 of bytes 0..47
 *  52 12  zero
 *  64 ..  payload: supports in row order (iy, then ix), each res rows (j) of res texels (i) of
 *         3 float32 (R, G, B), every one finite. Nothing may follow the payload.
 * Bounds: nx ny res res <= 2^21 texels (24 MiB of payload), checked from the header before any
 * allocation.
 */
#ifndef QTOOL_LUMINAIRE_H
#define QTOOL_LUMINAIRE_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "qibl/gonio.h"
#include "qibl/shmap.h"

#define QTOOL_LUMINAIRE_HEADER 64u
#define QTOOL_LUMINAIRE_VERSION 1u
#define QTOOL_LUMINAIRE_MAX_GRID 64u
#define QTOOL_LUMINAIRE_MIN_RES 2u
#define QTOOL_LUMINAIRE_MAX_RES 128u
#define QTOOL_LUMINAIRE_MAX_TEXELS (1u << 21)

typedef enum qtool_luminaire_basis {
    QTOOL_LUMINAIRE_BOX = 1, /* piecewise constant basis on S; filter the box / h^2 (its dual) */
    QTOOL_LUMINAIRE_TENT = 2 /* bilinear (tent) basis of support 2h; filter the tent / h^2 (not its
                              * dual: a quasi-interpolant, smoother, slightly blurred) */
} qtool_luminaire_basis;

/* Every way a .qnf can be refused, one per field (qtool_luminaire_err_str names them). */
typedef enum qtool_luminaire_err {
    QTOOL_LUMINAIRE_OK = 0,
    QTOOL_LUMINAIRE_E_IO,          /* the file cannot be opened or read */
    QTOOL_LUMINAIRE_E_NOMEM,
    QTOOL_LUMINAIRE_E_TRUNCATED,   /* shorter than the header, or than header + payload */
    QTOOL_LUMINAIRE_E_MAGIC,
    QTOOL_LUMINAIRE_E_VERSION,
    QTOOL_LUMINAIRE_E_HEADER_SIZE,
    QTOOL_LUMINAIRE_E_GRID,        /* nx or ny outside 1..64 */
    QTOOL_LUMINAIRE_E_RES,         /* res outside 2..128 */
    QTOOL_LUMINAIRE_E_TOO_BIG,     /* nx ny res res above QTOOL_LUMINAIRE_MAX_TEXELS */
    QTOOL_LUMINAIRE_E_BASIS,
    QTOOL_LUMINAIRE_E_SPACING,
    QTOOL_LUMINAIRE_E_DISTANCE,
    QTOOL_LUMINAIRE_E_WINDOW,
    QTOOL_LUMINAIRE_E_CHANNELS,
    QTOOL_LUMINAIRE_E_PAYLOAD_SIZE, /* not nx ny res res 12 */
    QTOOL_LUMINAIRE_E_RESERVED,    /* bytes 52..63 not zero */
    QTOOL_LUMINAIRE_E_HEADER_CRC,
    QTOOL_LUMINAIRE_E_PAYLOAD_CRC,
    QTOOL_LUMINAIRE_E_VALUE,       /* a texel not finite */
    QTOOL_LUMINAIRE_E_TRAILING,    /* bytes after the payload */
    QTOOL_LUMINAIRE_E_WRITE        /* the atomic write failed */
} qtool_luminaire_err;

const char *qtool_luminaire_err_str(qtool_luminaire_err e);

typedef struct qtool_luminaire {
    uint32_t nx, ny, res, basis;
    float spacing, distance, half_tan;
    float *tex; /* nx ny res res 3, the payload's layout (malloc'd) */
} qtool_luminaire;

/* Texel (i, j) of support (ix, iy): tex + qtool_luminaire_texel(l, ix, iy, i, j) (3 floats). */
size_t qtool_luminaire_texel(const qtool_luminaire *l, uint32_t ix, uint32_t iy, uint32_t i, uint32_t j);

/* Decodes a whole file in memory. QTOOL_LUMINAIRE_OK, or the field's error with *out untouched
 * (nothing allocated). The header is checked (every field, then its CRC) before any allocation. */
qtool_luminaire_err qtool_luminaire_decode(const uint8_t *data, size_t n, qtool_luminaire *out);
qtool_luminaire_err qtool_luminaire_read(const char *path, qtool_luminaire *out);
/* Checks l's fields as the reader would (sizes, basis, ranges, finite texels). */
qtool_luminaire_err qtool_luminaire_check(const qtool_luminaire *l);
/* The file's bytes (malloc'd, *n set); l must pass qtool_luminaire_check. */
qtool_luminaire_err qtool_luminaire_encode(const qtool_luminaire *l, uint8_t **bytes, size_t *n);
/* Writes path atomically (io/atomic.h): the destination is whole or untouched. err gets the reason
 * for QTOOL_LUMINAIRE_E_WRITE. */
qtool_luminaire_err qtool_luminaire_write(const char *path, const qtool_luminaire *l, char *err, size_t errlen);
void qtool_luminaire_free(qtool_luminaire *l);

/* ---- the built-in luminaire and the simulated acquisition (capture.c) -------------------------- */

/* The built-in luminaire, in the source's frame: a closed box shade 0.4 wide (its lamp size) and
 * 0.2 high whose bottom plate (z = 0.002, just above S) has a 4 x 4 checkerboard of 0.1 square
 * holes (the holes where ix + iy is even), and a 0.16 x 0.16 Lambertian emitter facing down at
 * z = 0.16, radiance (1, 0.9, 0.75) x QTOOL_LUMINAIRE_LE. All its light crosses S within the
 * plate. */
#define QTOOL_LUMINAIRE_SIZE 0.4
#define QTOOL_LUMINAIRE_LE 4.0

typedef struct qtool_luminaire_model qtool_luminaire_model; /* opaque: shade (rt scene) + emitter */

/* NULL on no memory. */
qtool_luminaire_model *qtool_luminaire_builtin(void);
/* A luminaire from a mesh, taken as it is in the source's frame (z up, every vertex above S), as
 * the shade (opaque, every triangle), around a square emitter of half-size emit_half facing down at
 * height emit_z (radiance as the built-in one's; 0: 0.8 of the mesh's height and 0.4 of its
 * half-width, the built-in one's proportions). The grid will cover the mesh's extent in x and y.
 * NULL with a one-line reason in err (a vertex at or below S, the emitter outside the mesh, no
 * memory). */
struct qtool_obj_mesh;
qtool_luminaire_model *qtool_luminaire_from_mesh(const struct qtool_obj_mesh *mesh, double emit_z, double emit_half,
                                                 char *err, size_t errlen);
void qtool_luminaire_model_free(qtool_luminaire_model *m);
/* The radiance leaving the luminaire along the ray from point o (z <= 0: below S) in unit direction
 * d (d[2] > 0: toward the luminaire): the emitter's radiance when the ray reaches it through a hole,
 * else 0. Traced with tools/render (rt.h) against the shade. */
void qtool_luminaire_model_radiance(const qtool_luminaire_model *m, const double o[3], const double d[3],
                                    double rgb[3]);
/* The true irradiance at point p (below S) on a surface of unit normal nrm: the emitter integrated
 * on an ns x ns stratified grid (cos at both ends over r^2), each sample's visibility through the
 * shade traced with rt. */
void qtool_luminaire_model_irradiance(const qtool_luminaire_model *m, const double p[3], const double nrm[3],
                                      uint32_t ns, double rgb[3]);

/* The truth at a scene hit h (tools/render): the radiance toward the viewer from the luminaire,
 * added to rgb; p is the hit point in the source's frame. The emitter on an ns x ns stratified
 * grid, each sample traced through the shade and through the scene (qtool_rt_response: its
 * shadows, Lambert and gloss, as qtool_rt_render shades a point lamp). */
struct qtool_rt_scene;
struct qtool_rt_hit;
void qtool_luminaire_yard_sample(const qtool_luminaire_model *m, const double p[3], uint32_t ns,
                                 const struct qtool_rt_scene *sc, const struct qtool_rt_hit *h, double rgb[3]);

typedef struct qtool_luminaire_capture_opts {
    uint32_t grid;     /* nx = ny; 0: 8 (64 spotlights over the plate) */
    uint32_t res;      /* 0: 32 */
    uint32_t basis;    /* 0: QTOOL_LUMINAIRE_BOX */
    uint32_t samples;  /* filter quadrature per axis per support cell; 0: 6 */
    double distance;   /* D; 0: 1.0 (filter width / D = 0.05, the paper's 8 % regime) */
    double half_tan;   /* 0: 2.0 (63 degrees: every ray through the built-in plate's holes) */
    int threads;       /* 0: 1 */
} qtool_luminaire_capture_opts;

/* The acquisition of Figure 1 in simulation: for each support m and texel (s, t) of M, the
 * irradiance behind the filter Phi'_m, E_m(s, t) = int_S cos^2 / R^2 Phi'_m(u, v) L(u, v -> s, t)
 * du dv (midpoint quadrature, L traced through the luminaire), then E'_m = E_m R_m^2 / cos^2 at the
 * support's centre (eq. 9-10; M's basis a point sample per texel). The grid covers the luminaire's
 * extent in x and y (the built-in one's 0.4 plate): box cells tile it, tent centres reach its edges.
 * 0, or -1 (no memory). out is the caller's to free. */
int qtool_luminaire_capture(const qtool_luminaire_model *m, const qtool_luminaire_capture_opts *o,
                            qtool_luminaire *out);

/* Total flux below S (W if radiance is W/m^2/sr), sum over supports and texels of A E' cos dA/R^2
 * integrated as seen from the spotlights: an energy check against the emitter's own flux. */
void qtool_luminaire_flux(const qtool_luminaire *l, double rgb[3]);

/* ---- rendering: textured spotlights through the core's gonio module (render.c) -------------- */

#define QTOOL_LUMINAIRE_MAX_LEVEL 6 /* 2^6 = QTOOL_LUMINAIRE_MAX_GRID */
#define QTOOL_LUMINAIRE_MAX_TOL 1.0
#define QTOOL_LUMINAIRE_DEFAULT_TOL 0.3 /* the CLI's: the study's PSNRs within 0.3 dB of tol 0 */
#define QTOOL_LUMINAIRE_BANDS 64     /* merged tables per level, by the receiver's 1 / depth (at most) */
#define QTOOL_LUMINAIRE_MIN_BANDS 16 /* fewer would not fit: the hierarchy is refused */
#define QTOOL_LUMINAIRE_KEYS (1 + QTOOL_LUMINAIRE_MAX_LEVEL * QTOOL_LUMINAIRE_BANDS)

/* The spotlights of a source placed with S's centre at pos (Q16.16 world units), facing -z, its
 * grid's x along world x: per support a gonio table (n x n, Q1.15 of its own peak), the peak
 * intensity per channel (Q16.16) and its position; far: one lamp at pos with the sum of all the
 * supports' intensities (the far field of the same source, IES-like). */
typedef struct qtool_luminaire_spots {
    uint32_t count, n;
    uint16_t *tables;          /* count n n */
    qibl_gonio_t *gonio;       /* count */
    int32_t (*pos)[3];         /* Q16.16 */
    int32_t (*rgb)[3];         /* Q16.16 peak intensity per channel */
    int64_t (*cull)[2];        /* a direction d from the lamp gets 0 when |d_x| > cull[0] |d_z| / 2^16
                                * or |d_y| > cull[1] |d_z| / 2^16 or d_z >= 0 (exact: from the table) */
    int32_t centre[3];         /* pos */
    uint64_t reach[2];         /* max |spot - centre| along x and y, Q16.16 */
    int64_t cullmax[2];        /* max of cull (-1: some spotlight cannot be culled) */
    uint32_t (*occ)[32];       /* per spotlight, QTOOL_LUMINAIRE_OCC^2 bits over its cull rectangle in
                                * (tan_x, tan_y): 0 where its table's lookup is 0 (exact) */
    uint64_t (*kocc)[2];       /* OCC 2^32 / (2 cull + 1): a tangent's cell by one product */
    uint32_t nanchor;          /* shading anchors: 4 (the corners of the spotlights' box), far 1 */
    int32_t anchor[4][3];      /* Q16.16 */
    int32_t (*aw)[4];          /* per spotlight, its bilinear weights among the anchors, Q15 */
    /* the hierarchy (qtool_luminaire_spots_build with tol > 0): the arrays above hold count
     * spotlights (level 0, the passes), then the merged lamps by key (kfirst) */
    uint32_t total;            /* lamps in the arrays */
    uint32_t nlevel;           /* coarser levels (0: none) */
    uint32_t nband;            /* tables per level (QTOOL_LUMINAIRE_BANDS, halved to fit the cap) */
    uint32_t kfirst[QTOOL_LUMINAIRE_KEYS + 1]; /* key k >= 1 (level 1 + (k - 1) / nband, its band
                                * (k - 1) % nband): lamps kfirst[k] .. kfirst[k + 1] - 1 */
    uint64_t lmin[QTOOL_LUMINAIRE_MAX_LEVEL + 1]; /* level L serves a pixel whose distance bound
                                * (1/256 unit) is at least this: the group's side / tol */
    uint64_t bandk[QTOOL_LUMINAIRE_MAX_LEVEL + 1]; /* level L's band: bandk / |dz| (1/256 unit) */
    uint64_t rad256;           /* the farthest spotlight's distance from centre (1/256 unit), rounded up */
    double tol;
} qtool_luminaire_spots;

/* far 0: the near-field spotlights; far 1: one lamp (the far field). n: gonio table size (0: 64).
 * 0, or -1 with a one-line reason in err: no memory, n outside the core's range, the tables above
 * QTOOL_LUMINAIRE_MAX_TABLES bytes, an intensity or position beyond Q16.16. */
#define QTOOL_LUMINAIRE_MAX_TABLES (64u << 20)
#define QTOOL_LUMINAIRE_OCC 32
int qtool_luminaire_spots_make(const qtool_luminaire *l, const int32_t pos[3], uint32_t n, int far,
                               qtool_luminaire_spots *out, char *err, size_t errlen);
void qtool_luminaire_spots_free(qtool_luminaire_spots *s);

/* The same with a hierarchy of merged spotlights (a mip pyramid of lamps, built once per
 * placement): level L merges each 2^L x 2^L group of supports into one lamp at its lit members'
 * flux-weighted centroid whose table is the sum of their intensities as a receiver at depth H below
 * S sees them (member m, offset e_m, at tangent tau - e_m / H), in nband tables by 1 / H; per pixel
 * the span kernel takes the coarsest level whose group side is at most tol times a lower bound on
 * the pixel's distance to the source (max(|dz|, |x - centre| - the spotlights' radius)), and the
 * band of its depth. tol 0: no hierarchy, exactly qtool_luminaire_spots_make's spotlights and sums.
 * The passes (qtool_luminaire_spot_pass) are always level 0's. 0, or -1 with a reason in err (as
 * spots_make; tol outside 0..1; the levels' tables beyond QTOOL_LUMINAIRE_MAX_TABLES even with
 * QTOOL_LUMINAIRE_MIN_BANDS). */
typedef struct qtool_luminaire_spots_opts {
    uint32_t n;   /* gonio table size; 0: 64 */
    int far;      /* 1: the far-field lamp (no hierarchy) */
    double tol;   /* group side / distance bound at which a merged lamp serves a pixel; 0: none */
} qtool_luminaire_spots_opts;
int qtool_luminaire_spots_build(const qtool_luminaire *l, const int32_t pos[3], const qtool_luminaire_spots_opts *o,
                                qtool_luminaire_spots *out, char *err, size_t errlen);

/* One span of n pixels. base: s->nanchor spans (span k at base + 3 n k), each the Q16.16 RGB a
 * unit isotropic point lamp at anchor k gives with 1/d^2 falloff (qibl_shmap_point_span of an
 * asset, or a reference renderer): albedo, cosine and visibility there. p: the pixels' points
 * (Q16.16, 3 per pixel). Pass by pass (one per spotlight), acc (3 per pixel, int64 Q8.24, added
 * to) gets the spotlight's intensity toward the pixel (qibl_gonio_lookup, times its peak) times
 * its shading: the anchors' base_k |x - a_k|^3 (the cosine's numerator n.(a - x), linear in a)
 * interpolated bilinearly at the spotlight and divided by |x - s|^3 (the paper's per-support
 * estimates of rho, V and f; exact for a Lambertian receiver when the anchors agree on
 * visibility). Integer only: distances floored to 1/256 unit, distance ratios cubed saturated at
 * 2^15, each pass's term rounded once to 2^-24 (after its weight is kept to 31 bits), so the sum
 * of many faint passes keeps its precision; qtool_luminaire_q16 rounds the sum once. With a
 * hierarchy (qtool_luminaire_spots_build, tol > 0) each pixel's passes are its level's and band's
 * lamps instead (level 0: the spotlights).
 * ws: qtool_luminaire_span_ws_size(n) bytes of the caller's (int64-aligned). */
#define QTOOL_LUMINAIRE_WS_PER_PIXEL 16u
/* 1 if some spotlight of s can light point q (Q16.16): below S and inside the union of the
 * spotlights' cull cones (exact: a point it says 0 for gets 0 from every pass). */
int qtool_luminaire_reaches(const qtool_luminaire_spots *s, const int32_t q[3]);
size_t qtool_luminaire_span_ws_size(uint32_t n);
void qtool_luminaire_spots_span(const qtool_luminaire_spots *s, const int32_t *base, const int32_t *p, uint32_t n,
                                int64_t *acc, int64_t *ws);

/* floor(sqrt(x)) for x <= 2^52, exactly qibl_isqrt_u64's result (a double estimate corrected in
 * integers): the span kernel's square roots. */
uint64_t qtool_luminaire_isqrt(uint64_t x);

/* qibl_gonio_lookup's result, bit for bit, faster on a host (hardware 64-bit shifts and products, its
 * two divisions a double quotient corrected exactly in integers): the span kernel's lookup. */
uint32_t qtool_luminaire_lookup(const qibl_gonio_t *g, const int64_t d[3]);

/* acc (Q8.24) to Q16.16: rounded to nearest (ties away from zero), saturated to int32. */
int32_t qtool_luminaire_q16(int64_t acc);

/* What qtool_luminaire_relight reads of an asset: its point maps, P map and LUT (lut NULL where the
 * asset has none: direct SH), views into the asset's bytes. */
typedef struct qtool_luminaire_views {
    qibl_shmaps_t mp;
    qibl_pmap_t pm;
    qibl_ylut_t lut_view;
    const qibl_ylut_t *lut; /* &lut_view, or NULL */
} qtool_luminaire_views;

/* The views of the asset bytes (n): QIBL_OK, or the core's status for a bad asset or one without
 * point maps or a P map (*v then all zero). */
qibl_status_t qtool_luminaire_views_open(const uint8_t *asset, size_t n, qtool_luminaire_views *v);

/* An asset frame lit by the source: the anchors' unit lamps from the asset's point maps mp, P map
 * pm and LUT lut (NULL: direct SH) as `qibl relight --point` would draw them with falloff 2, then
 * qtool_luminaire_spots_span, saturated to int32 once per pixel and written through platform/soft
 * (exposure, srgb) into rgb8 (w h 3); lin (may be NULL) the linear frame. ms: the frame's CPU time
 * (this thread's, so a loaded machine does not inflate it).
 * 0, or -1 with *status (QIBL_E_NULL_POINTER for no memory). */
int qtool_luminaire_relight(const qtool_luminaire_spots *s, const qibl_shmaps_t *mp, const qibl_pmap_t *pm,
                            const qibl_ylut_t *lut, uint32_t exposure, int srgb, uint8_t *rgb8, float *lin, double *ms,
                            qibl_status_t *status);

/* ---- passes and sRGBE accumulation (passes.c) ----------------------------------------------- */

/* Spotlight j's pass alone: qtool_luminaire_spots_span for spotlight j only (its terms, Q8.24,
 * added to acc; same ws). The passes' terms sum, in any order, to the one-call sum exactly. */
void qtool_luminaire_spot_pass(const qtool_luminaire_spots *s, uint32_t j, const int32_t *base, const int32_t *p,
                               uint32_t n, int64_t *acc, int64_t *ws);

/* An 8-bit sRGBE target (qibl/srgbe.h, 4 bytes per pixel) of n pixels: clear writes the zero code. */
void qtool_luminaire_srgbe_clear(uint8_t *codes, uint32_t n);
/* The fraction bits (<= 24) at which every partial sum of terms whose magnitudes sum to at most
 * maxabs (Q8.24) stays below 2^30: the target's working format, so it never saturates. */
int qtool_luminaire_srgbe_frac(uint64_t maxabs);
/* One pass added to the target as the paper's GPU adds it, in integers: each pixel's code decoded
 * (qibl_srgbe_decode_s32 at frac_bits), the pass's term (3 per pixel, Q8.24, rounded half away from
 * zero to frac_bits) added, re-encoded (qibl_srgbe_encode_s32). Per pass and channel the value moves
 * from the exact sum by at most 2^e / 510 (e the new code's exponent: at most 4/510 of the pixel's
 * largest channel) plus one LSB of frac_bits (the decode's and the term's roundings).
 * QIBL_OK; QIBL_E_RANGE (frac_bits outside -64..24, a term beyond 2^62, or a sum at or beyond 2^31
 * at frac_bits), or QIBL_E_SRGBE_DECODE_SAT (a code beyond int32 at frac_bits): then nothing is
 * written (every pixel is checked first). */
qibl_status_t qtool_luminaire_srgbe_add(uint8_t *codes, const int64_t *term, uint32_t n, int frac_bits);
/* The same with two targets: hi as above, lo (signed sRGBE: the format's sign is what makes this
 * work) holding what hi's encoding rounded away; each pass adds hi + lo + term, encodes hi, and lo
 * gets the remainder. The sum is decode(hi) + decode(lo); per pass and channel it moves from the
 * exact sum by at most 2^e' / 510 (e' lo's new exponent, lo's largest channel at most half hi's
 * step: about (4/510)^2 / 2 of hi's largest channel) plus 3/2 LSB of frac_bits. Statuses as above. */
qibl_status_t qtool_luminaire_srgbe_add2(uint8_t *hi, uint8_t *lo, const int64_t *term, uint32_t n, int frac_bits);

/* A synthetic source of grid x grid supports, every one lit (a smooth, tinted lobe each): grid^2
 * passes exactly, the same total light for any grid. 0, or -1 (no memory); out is the caller's. */
int qtool_luminaire_synthetic(uint32_t grid, qtool_luminaire *out);

/* A ground plane size x size at height hgt below the source (S's centre above its middle), shaded
 * as the study's, lit pass by pass; the per-pass terms, and the final frame four ways through
 * platform/soft (sRGB, exposure putting the exact sum's peak at 1.0): the exact integer sum (the
 * core's one-call sum), a binary32 accumulation (one rounding per pass), the sRGBE target and the
 * two-target one. */
typedef struct qtool_luminaire_passes {
    uint32_t passes, size;
    int frac_bits;                      /* the sRGBE target's working format */
    int64_t *terms;                     /* passes size^2 3, Q8.24 (malloc'd) */
    uint8_t *shown;                     /* four RGBA8 images stacked: core, float, sRGBE, two sRGBE
                                         * (qtool_luminaire_srgbe_add2) (malloc'd) */
    int srgbe_vs_float, srgbe_vs_core, float_vs_core; /* max |difference| of the 8-bit values */
    int srgbe2_vs_float, srgbe2_vs_core;
    double max_rel, max_rel2;           /* max |sRGBE - exact| / the exact sum's peak, linear */
    uint32_t exposure;                  /* the display's (UQ16.16) */
    int gles;                           /* 1 once qtool_luminaire_passes_gles has run: */
    int gles_vs_core, gles_vs_srgbe2;   /* its frame against the core's and the two-target one */
} qtool_luminaire_passes;
int qtool_luminaire_passes_run(const qtool_luminaire *l, uint32_t size, double hgt, qtool_luminaire_passes *out);
void qtool_luminaire_passes_free(qtool_luminaire_passes *r);
/* The same passes on a GLES2 GPU (passes_gles.c; the caller's context current, e.g. tools/gles/
 * headless.h): accumulated in RGBA8 sRGBE pairs (the sum's code and the code of what it leaves
 * out, as platform/gles2 accumulates), ping-ponged, two draws per pass (GLES2 has one colour
 * attachment), each pass's term uploaded as an sRGBE pair made by the core's codec; read back,
 * decoded by the core's codec, shown as passes_run's images; sets r->gles and the two differences.
 * 0, or -1 with a one-line reason in err (no GL, a shader or framebuffer refused, a GL error). */
int qtool_luminaire_passes_gles(qtool_luminaire_passes *r, char *err, size_t errlen);
/* `qibl luminaire passes`: synthetic sources of 16, 64 and 256 spotlights at one lamp size above
 * a size x size ground; a table and RESULT lines (8-bit units). gpu (NULL: none) is run on each
 * (qtool_luminaire_passes_gles: programs that link GL pass it). 0, or -1 with a reason in err. */
typedef int (*qtool_luminaire_gpu_fn)(qtool_luminaire_passes *r, char *err, size_t errlen);
int qtool_luminaire_passes_report(uint32_t size, qtool_luminaire_gpu_fn gpu, FILE *f, char *err, size_t errlen);

/* ---- the study (study.c) ---------------------------------------------------------------------- */

typedef struct qtool_luminaire_study_opts {
    uint32_t grid, res;   /* capture; 0: 8 and 32 */
    uint32_t size;        /* receiver image side; 0: 96 */
    uint32_t truth_ns;    /* emitter samples per axis for the truth; 0: 24 */
    int quick;            /* fewer distances */
    int threads;          /* 0: 1 */
    double tol;           /* the near field's hierarchy (qtool_luminaire_spots_build); 0: none */
} qtool_luminaire_study_opts;

/* Captures the built-in luminaire, then at several heights above a ground plane (in lamp sizes)
 * compares the near-field and far-field renderings with the ray-traced truth (PSNR, peak the
 * truth's), and times the near-field kernel on a 1024 x 256 frame of the built-in courtyard
 * (tools/render) with the lamp in it. Prints a table and RESULT lines to f. 0, or -1. */
int qtool_luminaire_study(const qtool_luminaire_study_opts *o, FILE *f);

/* The README's picture: the built-in luminaire (captured with o's grid and res) lamps lamp sizes
 * above the study's ground plane, side by side: its near field, the ray-traced truth, its far
 * field; one exposure (the truth's peak at 1.0), sRGB. *rgb (malloc'd, w h 3). 0, or -1. */
int qtool_luminaire_picture(const qtool_luminaire_study_opts *o, double lamps, uint8_t **rgb, uint32_t *w,
                            uint32_t *h);

/* Pixel x of a span of n on the study's ground plane, at p (z = 0, facing up): its point into pts
 * (3 per pixel, Q16.16) and, for each of s's anchors a, a unit isotropic lamp at the anchor (1/d^2,
 * Lambert, albedo 1: what an asset's point maps give) into base (anchor a's span at base + 3 n a),
 * each value rounded to nearest and saturated to int32 (the study's frames and the passes report's). */
void qtool_luminaire_ground_pixel(const qtool_luminaire_spots *s, const double p[3], uint32_t x, uint32_t n,
                                  int32_t *pts, int32_t *base);

#endif
