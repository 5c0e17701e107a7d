/*
 * qibl/lightprobe.h - light-probe sampling: a lat-long HDR probe turned into N directional lights
 * (median cut, adaptive median cut, variance minimisation), integer only, no heap, deterministic.
 *
 * Conventions (Madsen & Laursen section 3.1; the CLI, the tests and the tools use exactly these):
 *   - The probe is a W x H lat-long image, rows top to bottom. Pixel (u, v) (column u, row v) is
 *     centred on theta = (v + 1/2) pi / H from the top row and phi = (u + 1/2) 2 pi / W from the
 *     left column; its direction is w = (sin theta cos phi, sin theta sin phi, cos theta), so +z is
 *     the top row and phi grows to the right.
 *   - Pixel energy is Madsen's Q(u, v) = P(u, v) sin theta_v 2 pi^2 / (W H), the radiance times
 *     the pixel's solid angle. Regions are split on luminance
 *     L = (13933 R + 46871 G + 4732 B) / 65536 (Rec. 709 weights 0.2126, 0.7152, 0.0722 rounded
 *     to Q16 so that they sum to exactly 1), weighted by sin theta_v.
 *   - A light's rgb is the irradiance it delivers to a surface facing it: the sum of Q over its
 *     region, per channel. Then E(n) = sum_i rgb_i max(0, n . d_i) approximates the probe's
 *     irradiance E(n) = sum_(u,v) Q(u, v) max(0, n . w(u, v)) for every normal n.
 *   - A light's direction d is a Q2.30 unit vector (error <= 3 LSB per component against the exact
 *     direction of its integer centroid, |d| = 1 within 2 LSB) toward the region's energy centroid:
 *     the luminance-energy-weighted mean of the pixel centres' (u, v) inside the region, mapped to
 *     (theta, phi) as above. (Placement QIBL_LIGHTPROBE_PLACE_CENTRE uses the region's geometric
 *     centre instead, for comparison: a larger irradiance error on the real probes.)
 *   - Regions are rectangles of pixels, kept cropped to the bounding box of their luminance energy
 *     (dark margins carry no light); so every region is lit and every split adds a light.
 *   - The longer side of a region is measured on the sphere: its angular width is
 *     (u1 - u0) 2 pi / W times the mean of sin theta over its rows (exactly its solid angle divided
 *     by its angular height), its height (v1 - v0) pi / H. A region near a pole is narrow.
 *
 * Pixel formats (qibl_lightprobe_format_t), each pixel's value P = (R, G, B):
 *   RGBE        Radiance bytes R G B E as stored in .hdr files after RLE decoding:
 *               P = m * 2^(E - 136), E = 0 means black. No +1/2 mantissa offset (the convention of
 *               ../shared/fixtures/SOURCES.md and of most readers).
 *   SRGBE       Granier's sRGBE bytes X X X E (qibl/srgbe.h): P = (2X - 255) 2^(E - 126) / 510.
 *               sRGBE has no exact zero: X = 127 and X = 128 (+-2^(E-126)/510, what the encoder
 *               writes for a zero channel) are read as 0, as srgbe.h recommends; X < 127 is a
 *               negative channel (QIBL_E_PROBE_NEGATIVE).
 *   LINEAR_I32  three int32 per pixel: P = x / 2^frac_bits (frac_bits in -128..128). Negative
 *               values are QIBL_E_PROBE_NEGATIVE.
 *   LINEAR_F32  three IEEE-754 binary32 bit patterns per pixel, read as uint32 (no floating point
 *               is used). +-0 and subnormals are fine; a negative value is QIBL_E_PROBE_NEGATIVE,
 *               NaN or +-Inf is QIBL_E_PROBE_NOT_FINITE.
 * The 32-bit formats need 4-byte aligned pixels and stride; bytes formats have no alignment needs.
 *
 * How it works and what it guarantees (details and proofs in core/src/lightprobe.c):
 *   - qibl_lightprobe_build reads the probe twice (once for its largest exponent and the checks,
 *     once to build the tables) and writes a summed-area table (SAT) of the per-pixel luminance
 *     energy e(u, v) = floor(Y * s_v * 2^k) into the caller's workspace: Y the pixel's exact
 *     integer luminance, s_v the integer sin theta_v table (32-bit mantissa, relative error
 *     <= 2^-30 on every row), k one shift per probe and row chosen so that the brightest pixel has
 *     e < 2^p, p = 64 - ceil(log2(W H)). Every SAT entry is then an exact uint64 sum (the total is
 *     below W H 2^p <= 2^64), so region sums are exact sums of the per-pixel integers and
 *     additive: the two halves of a split add up to their parent bit for bit. Against the real
 *     energy sum(L sin theta) of a region holding n pixels, the only errors are the per-pixel
 *     floor (< 1 unit each, so < n units in all) and s_v: relative error
 *     <= n / (region energy in units) + 2^-30. With p >= 38 at the largest supported size a pixel
 *     2^20 (10^6) times dimmer than the brightest still carries >= 18 significant bits.
 *   - Median cut splits along the longer side at the energy median found by binary search over
 *     the SAT (O(log w) region sums per split), choosing the cut that makes the two halves closest
 *     to equal (ties: the smaller cut), with at least one pixel on each side.
 *   - Variance minimisation (Viriyothai & Debevec 2009) adds five SATs of em, em u, em u^2, em v,
 *     em v^2 (em = e >> k_m, k_m chosen from the probe's total so that no moment overflows) and
 *     scores every cut of both axes in O(1) with exact 128-bit integer arithmetic: the larger of
 *     the two halves' energy-weighted angular variances sum em ((sin theta dphi)^2 + dtheta^2),
 *     sin theta taken as the half's mean, is minimised (ties: the more balanced energy).
 *   - Light colours come from one more pass over the probe pixels, region by region (the regions
 *     are disjoint, so it reads each lit pixel at most once).
 *   - The low-memory path (a workspace below qibl_lightprobe_workspace_size but at least
 *     qibl_lightprobe_workspace_min) builds no SAT. Every decision above reads a region only
 *     through sums over its whole columns or whole rows, so one read of the region's pixels (each
 *     pixel's e decoded exactly as the SAT build does) into its column and row sums, the
 *     marginals, and their prefix sums give every cut's sums, crops, keys and centroids as the
 *     same exact integers: the same lights, bit for bit (tests/lightprobe_test.c compares the two
 *     paths on every format, method, priority and placement).
 *
 * Memory: qibl_lightprobe_workspace_size(W, H, method) bytes, any alignment:
 *   8 (W + 1)(H + 1) for the SAT (48 (W + 1)(H + 1) with the five moment SATs of VARMIN)
 *   + 16 (H + 1) for the row tables + 8 for alignment (docs/porting.md's generated memory
 *   table lists it for three probe sizes). Or, for the low-memory path, as little as
 *   qibl_lightprobe_workspace_min(W, H, method): 8 (W + H + 2) for one column and one row of
 *   sums (32 (W + H + 2) with VARMIN's moment sums) + the same row tables and alignment, O(W + H)
 *   where the SAT is O(W H). The lights array doubles as the list of regions (with their keys and
 *   energies) while splitting; the stack use is a few hundred bytes to a few KiB by target
 *   (docs/porting.md's generated stack tables).
 * Limits: W, H in 1..QIBL_LIGHTPROBE_MAX_DIM (32768), W H <= QIBL_LIGHTPROBE_MAX_PIXELS (2^26).
 * All functions are reentrant; the probe pixels must stay unchanged between build and lights.
 * On the low-memory path qibl_lightprobe_lights uses the workspace's sums as scratch: do not run
 * it on one built probe from two threads at once (the SAT path only reads the workspace).
 */
#ifndef QIBL_LIGHTPROBE_H
#define QIBL_LIGHTPROBE_H

#include <stddef.h>
#include <stdint.h>
#include "qibl/config.h"
#include "qibl/fixed.h"
#include "qibl/status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define QIBL_LIGHTPROBE_MAX_DIM 32768u
#define QIBL_LIGHTPROBE_MAX_PIXELS (QIBL_CAST(uint32_t, 1) << 26)

/* Luminance weights in Q16 (sum 65536). */
#define QIBL_LIGHTPROBE_LUMA_R 13933u
#define QIBL_LIGHTPROBE_LUMA_G 46871u
#define QIBL_LIGHTPROBE_LUMA_B 4732u

typedef enum qibl_lightprobe_format {
    QIBL_LIGHTPROBE_RGBE = 0,   /* 4 bytes per pixel (default) */
    QIBL_LIGHTPROBE_SRGBE,      /* 4 bytes per pixel */
    QIBL_LIGHTPROBE_LINEAR_I32, /* 3 int32 per pixel, frac_bits fraction bits */
    QIBL_LIGHTPROBE_LINEAR_F32, /* 3 binary32 bit patterns (uint32) per pixel */
    QIBL_LIGHTPROBE_FORMAT_COUNT
} qibl_lightprobe_format_t;

typedef enum qibl_lightprobe_method {
    QIBL_LIGHTPROBE_MEDIANCUT = 0, /* Debevec: split every region K times at the energy median:
                                    * 2^K lights (count must be a power of two) (default) */
    QIBL_LIGHTPROBE_ADAPTIVE,      /* median cuts, any count: repeatedly split the region with the
                                    * largest priority key (see qibl_lightprobe_priority_t) */
    QIBL_LIGHTPROBE_VARMIN,        /* Viriyothai & Debevec: cut where the larger of the two halves'
                                    * energy-weighted spatial variances is smallest; any count,
                                    * repeatedly splitting the region with the largest key */
    QIBL_LIGHTPROBE_METHOD_COUNT
} qibl_lightprobe_method_t;

/* Which region ADAPTIVE and VARMIN split next. 0 picks the method's default, the best one measured
 * on the 11 real probes (docs/ARCHITECTURE.md, `qibl bench lights`). */
typedef enum qibl_lightprobe_priority {
    QIBL_LIGHTPROBE_PRIORITY_DEFAULT = 0, /* ADAPTIVE: ENERGY_SIZE; VARMIN: VARIANCE */
    QIBL_LIGHTPROBE_PRIORITY_ENERGY,      /* the most luminance energy */
    QIBL_LIGHTPROBE_PRIORITY_ENERGY_SIZE, /* energy times the region's diagonal on the sphere: a
                                           * bound on how far its energy is moved to one point */
    QIBL_LIGHTPROBE_PRIORITY_VARIANCE,    /* the largest energy-weighted angular variance
                                           * (needs the moment tables: a probe built for VARMIN) */
    QIBL_LIGHTPROBE_PRIORITY_LEVELS,      /* no priority: split every region once per round, as
                                           * MEDIANCUT does (count must be a power of two) */
    QIBL_LIGHTPROBE_PRIORITY_COUNT
} qibl_lightprobe_priority_t;

typedef enum qibl_lightprobe_place {
    QIBL_LIGHTPROBE_PLACE_CENTROID = 0, /* the region's luminance-energy centroid (default) */
    QIBL_LIGHTPROBE_PLACE_CENTRE,       /* the region's geometric centre (for comparison) */
    QIBL_LIGHTPROBE_PLACE_COUNT
} qibl_lightprobe_place_t;

/* The probe. Zero-initialisable: set pixels, width, height; format 0 is RGBE, stride 0 means rows
 * are tightly packed (4-byte or 12-byte pixels by format). */
typedef struct qibl_lightprobe_image {
    const void *pixels;
    uint32_t width, height;
    size_t stride;                   /* bytes from one row to the next, 0 = tightly packed */
    qibl_lightprobe_format_t format;
    int32_t frac_bits;               /* LINEAR_I32 only: P = x / 2^frac_bits, -128..128 */
} qibl_lightprobe_image_t;

/* Options for qibl_lightprobe_lights. Zero-initialisable; a NULL pointer means all defaults. */
typedef struct qibl_lightprobe_opts {
    qibl_lightprobe_method_t method;     /* MEDIANCUT (0), ADAPTIVE or VARMIN */
    qibl_lightprobe_priority_t priority; /* 0: the method's default */
    qibl_lightprobe_place_t place;       /* 0: energy centroid */
} qibl_lightprobe_opts_t;

/* One light. rgb is irradiance: rgb[c] * 2^rgb_exp (rgb_exp shared by the whole list, in the
 * result); region: columns u0 <= u < u1, rows v0 <= v < v1. */
typedef struct qibl_lightprobe_light {
    qibl_q30_t dir[3];               /* unit vector toward the light, Q2.30 */
    int32_t rgb[3];                  /* >= 0 */
    uint32_t u0, v0, u1, v1;
} qibl_lightprobe_light_t;

typedef struct qibl_lightprobe_result {
    uint32_t count;   /* lights written: lights[0 .. count-1], brightest (luminance) first */
    int32_t rgb_exp;  /* every rgb value means rgb * 2^rgb_exp; the largest channel of the list is
                       * in [2^30, 2^31) */
} qibl_lightprobe_result_t;

/* A built probe: the tables in the caller's workspace plus what is needed to read them. Filled by
 * qibl_lightprobe_build; the fields are private except energy_exp and energy_div, which give the
 * unit of qibl_lightprobe_region_energy: one unit = 2^energy_exp / energy_div of
 * (luminance x sin theta) summed over pixels, in the probe's own units. */
typedef struct qibl_lightprobe {
    const uint8_t *pixels;
    size_t stride;
    uint32_t width, height;
    qibl_lightprobe_format_t format;
    int32_t frac_bits;
    qibl_lightprobe_method_t built_for;
    int32_t energy_exp;
    uint32_t energy_div;
    int32_t gshift;        /* k of the per-pixel energy before the row's sin exponent */
    int32_t emax;          /* RGBE: the largest exponent byte of a lit pixel (0: none) */
    uint32_t mshift;       /* moment SATs hold sums of e >> mshift */
    uint64_t *sat;         /* (W + 1) (H + 1): row 0 and column 0 are zero */
    uint64_t *mom;         /* 5 (W + 1) (H + 1) for VARMIN: em, em u, em u^2, em v, em v^2; else NULL */
    uint32_t *row_sig;     /* H: sin theta_v mantissa in [2^31, 2^32) */
    int32_t *row_kap;      /* H: sin theta_v = row_sig * 2^-(32 + row_kap) */
    uint64_t *row_sum;     /* H + 1: prefix sums of sin theta_v in Q31 (for widths on the sphere) */
    uint64_t total;        /* the probe's energy: the sum of every pixel's e */
    uint64_t *marg;        /* the low-memory path (sat NULL): the per-column and per-row marginals
                            * lights() fills as scratch; NULL on the SAT path */
} qibl_lightprobe_t;

/* Bytes of workspace qibl_lightprobe_build needs for a W x H probe and a method (VARMIN needs the
 * moment tables; MEDIANCUT and ADAPTIVE the SAT only). 0 if W or H is 0 or above the limits, if
 * W H > QIBL_LIGHTPROBE_MAX_PIXELS, if the method is unknown, or if the size does not fit size_t. */
size_t qibl_lightprobe_workspace_size(uint32_t width, uint32_t height, qibl_lightprobe_method_t method);

/* Bytes of workspace the low-memory path of qibl_lightprobe_build needs: O(W + H), the marginals
 * 8 (W + H + 2) (32 (W + H + 2) for VARMIN) plus the row tables 16 (H + 1) + 8. A workspace at
 * least this large but below qibl_lightprobe_workspace_size builds no SAT: the same lights, bit
 * for bit, from reads of the probe pixels (see Memory and Cost above). 0 on the arguments
 * qibl_lightprobe_workspace_size refuses. */
size_t qibl_lightprobe_workspace_min(uint32_t width, uint32_t height, qibl_lightprobe_method_t method);

/* Validates img, reads every pixel and builds the tables for method in workspace; lp then refers
 * to img->pixels and the workspace, which must outlive it unchanged.
 * Uses the SAT path when workspace_size >= qibl_lightprobe_workspace_size, else the low-memory
 * path (no tables but the row ones: see Memory above).
 * Cost: two reads of the probe, one write of the SAT (plus one read of it and four moment SAT
 * writes for VARMIN), about 20 integer operations per pixel; the low-memory path: two reads of
 * the probe and no table.
 * A black probe (no pixel has luminance energy) builds: QIBL_OK, lp filled, and
 * qibl_lightprobe_lights reports QIBL_E_PROBE_BLACK.
 * Formats: pixels RGBE bytes, sRGBE bytes, int32 linear (value x / 2^frac_bits) or IEEE binary32
 * bit patterns (qibl_lightprobe_format_t); tables: uint64 SATs of per-pixel luminance x sin theta
 * energies in the unit energy_exp / energy_div give, row weights as qibl_lightprobe_row_weight.
 * Bound: the SATs are exact sums of the per-pixel integers e = floor(Y s_v 2^k) (above: the floor
 * loses < 1 unit per pixel, s_v is within 2^-30 relative).
 * Errors, in this order: QIBL_E_NULL_POINTER (lp, img, img->pixels or workspace),
 * QIBL_E_PROBE_SIZE (W or H zero or above QIBL_LIGHTPROBE_MAX_DIM), QIBL_E_PROBE_OVERFLOW
 * (W H above QIBL_LIGHTPROBE_MAX_PIXELS), QIBL_E_PROBE_FORMAT (unknown format, frac_bits outside
 * -128..128, stride shorter than a row), QIBL_E_PROBE_OVERFLOW (the image's byte span beyond
 * size_t), QIBL_E_PROBE_FORMAT (12-byte pixels, or their stride, not 4-byte aligned),
 * QIBL_E_PROBE_METHOD (unknown method), QIBL_E_PROBE_OVERFLOW (workspace size beyond size_t),
 * QIBL_E_WORKSPACE (workspace_size below what qibl_lightprobe_workspace_min asks),
 * QIBL_E_PROBE_NOT_FINITE, QIBL_E_PROBE_NEGATIVE (one scan of the pixels; a probe with both kinds
 * reports NOT_FINITE).
 * On failure: nothing is written (lp and the workspace untouched: every check precedes the
 * first write). */
QIBL_NODISCARD qibl_status_t qibl_lightprobe_build(qibl_lightprobe_t *lp, const qibl_lightprobe_image_t *img,
                                    qibl_lightprobe_method_t method, void *workspace, size_t workspace_size);

/* Samples up to max_lights lights from a built probe into lights[], brightest first (luminance
 * energy; ties: smaller v0, then u0), and fills *result. MEDIANCUT (and priority LEVELS) needs
 * max_lights to be a power of two and splits every region once per round, log2(max_lights)
 * rounds, then (when one-pixel regions could not split) splits the other regions once more each,
 * in list order, until max_lights; ADAPTIVE and VARMIN take any count >= 1 and split one region
 * at a time, the next best one when the best is a single pixel. So every method returns
 * max_lights lights whenever the probe has that many lit pixels; fewer only when regions run out
 * (one light per lit pixel; for priority VARIANCE, also when every region's energy sits at one
 * point).
 * Cost: O(count log count) region splits, each O(log(w h)) SAT reads (MEDIANCUT, ADAPTIVE) or
 * O(w + h) (VARMIN, each candidate cut costing a few 128-bit operations), then O(w + h) SAT reads
 * per light for its centroid and one read of the probe pixels for the colours. On the
 * low-memory path each new region's pixels are read once (its crop, key and median cut from one
 * set of marginals; VARMIN reads a region again when it splits, for its cut), and each light's
 * twice more (its energy, its centroid): the regions of one split level are disjoint, so
 * O(W H log count) pixel reads in all, about 20 integer operations each (40 with VARMIN's
 * moments), plus the same per-cut work.
 * Formats: dir Q2.30 unit vectors; rgb int32 >= 0 scaled by the list's shared 2^rgb_exp (largest
 * channel in [2^30, 2^31)); regions in pixel columns and rows.
 * Bound: rgb within 1 LSB of the list's scale plus the region-sum error above; dir within
 * 3 LSB (Q2.30) of the exact direction of the integer centroid, which is within 2^-32 pixel of the
 * exact centroid of the region's integer energies (and so within (n / T + 2^-29) of the region's
 * extent of the real-valued centroid, n pixels holding T units).
 * Errors, in this order: QIBL_E_NULL_POINTER (lp, lights or result), QIBL_E_PROBE_METHOD (unknown
 * method, priority or place, or MEDIANCUT with a priority other than DEFAULT or LEVELS),
 * QIBL_E_PROBE_COUNT (max_lights 0, or not a power of two for MEDIANCUT / LEVELS),
 * QIBL_E_PROBE_MISMATCH (VARMIN, or priority VARIANCE with ADAPTIVE, on a probe built without the
 * moment tables), QIBL_E_PROBE_BLACK (an all-black probe: no lights).
 * On failure: nothing is written (lights[] and *result untouched). */
QIBL_NODISCARD qibl_status_t qibl_lightprobe_lights(const qibl_lightprobe_t *lp, const qibl_lightprobe_opts_t *opts,
                                     qibl_lightprobe_light_t *lights, uint32_t max_lights,
                                     qibl_lightprobe_result_t *result);

/* Luminance energy of the region u0 <= u < u1, v0 <= v < v1 in SAT units (see qibl_lightprobe_t),
 * from four SAT reads; on the low-memory path from one read of the region's pixels (O(w h), about
 * 20 integer operations per pixel). An empty region (u0 == u1 or v0 == v1) gives 0.
 * Formats: *energy uint64 in the unit 2^energy_exp / energy_div. Bound: exact (the sum of the
 * per-pixel integers).
 * Errors, in this order: QIBL_E_NULL_POINTER (lp or energy NULL), QIBL_E_PROBE_RECT (u0 > u1,
 * v0 > v1 or past the probe).
 * On failure: nothing is written (*energy untouched). */
QIBL_NODISCARD qibl_status_t qibl_lightprobe_region_energy(const qibl_lightprobe_t *lp, uint32_t u0, uint32_t v0, uint32_t u1,
                                            uint32_t v1, uint64_t *energy);

/* The row weight table entry: sin((v + 1/2) pi / h) = *mant * 2^-(32 + *kap), computed from the
 * exact rational angle with integer polynomials. Identical bits on every port.
 * Formats: *mant unsigned mantissa in [2^31, 2^32), *kap its exponent offset (a float in integers).
 * Bound: relative error <= 2^-30 (the tests measure it against libm for every row of several
 * heights).
 * Errors, in this order: QIBL_E_NULL_POINTER (mant or kap NULL), QIBL_E_PROBE_SIZE (h 0 or above
 * QIBL_LIGHTPROBE_MAX_DIM, v >= h).
 * On failure: nothing is written (*mant, *kap untouched). */
QIBL_NODISCARD qibl_status_t qibl_lightprobe_row_weight(uint32_t h, uint32_t v, uint32_t *mant, int32_t *kap);

#ifdef __cplusplus
}
#endif

#endif /* QIBL_LIGHTPROBE_H */
