/*
 * io/probe_layout.h - light-probe layouts: detection, and resampling of an angular map, a mirror
 * ball or a cube cross to the lat-long layout that qibl/lightprobe.h reads (and back, so tests can
 * make probes in every layout). Hosted, double precision.
 *
 * One world, five pictures of it, one frame (the frame convention): every layout pictures the world
 * with (image right, image up, the picture's forward) = (R, U, F) a right-handed triple, so the same
 * scene in any layout reads to the same directions. Directions are qibl's (lightprobe.h): a lat-long pixel at
 * continuous position (x, y) looks along theta = pi y / H from +z (the top row), phi = 2 pi x / W,
 * w = (sin theta cos phi, sin theta sin phi, cos theta). Every other layout is tied to it through
 * the "viewer frame" of a standard panorama: forward F = the centre of the lat-long image (phi = pi,
 * w = -x), up U = +z, right R = what lies to the right of the centre in the lat-long (w = -y).
 *   latlong  W x H, normally 2:1 (W = 2H); any size when --layout latlong is given.
 *   angular  N x N, Debevec's angular map: the disc's centre is F, a point at normalised radius
 *            rho (1 at the disc's edge) is theta = pi rho away from F, image up is U and image right
 *            is R, as in the lat-long (its horizon row runs left to right in the lat-long's order).
 *            Debevec's (u, v) = (Dx r, Dy r), r = acos(Dz) / (pi sqrt(Dx^2 + Dy^2)), u right and
 *            v up, read with D = (R, U, F): (image right, image up, centre) is right-handed, as
 *            in Ramamoorthi & Hanrahan's reading of the same pictures (prefilter.c: x = u right,
 *            y = v up, z the centre), so their published coefficients are qibl's turned by a
 *            rotation (x_RH = R = -y, y_RH = U = +z, z_RH = F = -x), never mirrored (tested
 *            against their Grace Cathedral table). The whole rim is the one direction -F.
 *   ball     N x N, a chrome ball photographed from far away (orthographic): same frame as angular,
 *            radius rho = sin(theta / 2) (the ball's normal is halfway between F and the
 *            reflected direction; a camera on F looking back with image right R and up U sees the
 *            view ray reflected, a right-handed picture). The rim (-F, behind the ball) is
 *            singular and poorly sampled.
 *   vcross   3F x 4F, cube faces of F x F pixels, each the view from the cube's centre through that
 *            face as seen from inside (not mirrored), unfolded as HDRShop and Debevec's crosses are:
 *                 +---+                 +---+
 *                 | T |                 | T |
 *             +---+---+---+         +---+---+---+---+
 *             | L | F | R |         | L | F | R | B |
 *             +---+---+---+         +---+---+---+---+
 *                 | D |                 | D |
 *                 +---+                 +---+
 *                 | B |               hcross 4F x 3F
 *                 +---+
 *              vcross 3F x 4F
 *            F forward, R right, L left, T up (its lower edge touches F), D down (its upper edge
 *            touches F). The back face B continues the strip it hangs from: in the hcross it is
 *            upright, to the right of R; in the vcross it hangs below D and so is upside down (its
 *            top edge touches D's bottom edge). Unused cells are black.
 *   hcross   4F x 3F, the same faces, the back face to the right of R.
 *
 * Detection (qtool_probe_layout_detect) uses the aspect ratio and, for the non-lat-long layouts,
 * checks that the unused area is black: mean luminance of the unused pixels <= 1e-3 of the mean of
 * the used ones (for the disc layouts the unused pixels are those whose centre lies at least one
 * pixel outside the disc). 2:1 is latlong, 3:4 vcross, 4:3 hcross. A square with black corners is
 * an angular map or a ball, which the pixels cannot tell apart: detection refuses it and asks for
 * --layout. Anything else is refused with the names of the layouts. Nothing is guessed silently:
 * the caller prints what was detected.
 *
 * Resampling (qtool_probe_layout_to_latlong): the output is Wo x Wo/2 with Wo the number of input
 * pixels along the horizon circle (the row or diameter through F that spans 360 degrees): N for
 * angular and ball, 4F for the crosses, rounded up to even and capped at QTOOL_PROBE_LAYOUT_MAX_W.
 * Each output pixel is the mean of s x s bilinear samples on a regular sub-grid, s = 2 ceil(Wi / Wo)
 * where Wi is the uncapped width (so a capped output still averages its whole footprint). Bilinear
 * taps only use pixels inside the layout: a disc's taps whose centre lies outside the disc are
 * dropped and the rest renormalised (a point closer than 1.5 pixels to the rim is first pulled in
 * radially), a cube face's taps are clamped to that face. The reverse (qtool_probe_layout_from_latlong)
 * samples the lat-long the same way (wrapping in phi) and leaves the unused area at exactly 0.
 *
 * Errors: every function that can fail returns -1 with one line in err naming the value, and writes
 * no output; 0 on success.
 */
#ifndef QTOOL_IO_PROBE_LAYOUT_H
#define QTOOL_IO_PROBE_LAYOUT_H

#include <stddef.h>
#include <stdint.h>

/* QTOOL_PROBE_LAYOUT_LIST(X): every layout in value order as X(enum name, name, description), the
 * one list the enum, qtool_probe_layout_name/_describe and the parser are made from. */
#define QTOOL_PROBE_LAYOUT_LIST(X) \
    X(QTOOL_PROBE_LAYOUT_AUTO, "auto", "detect") /* default */ \
    X(QTOOL_PROBE_LAYOUT_LATLONG, "latlong", "lat-long (equirectangular)") \
    X(QTOOL_PROBE_LAYOUT_ANGULAR, "angular", "Debevec angular map") \
    X(QTOOL_PROBE_LAYOUT_BALL, "ball", "mirror ball") \
    X(QTOOL_PROBE_LAYOUT_VCROSS, "vcross", "vertical cube cross (3:4)") \
    X(QTOOL_PROBE_LAYOUT_HCROSS, "hcross", "horizontal cube cross (4:3)")

typedef enum qtool_probe_layout {
#define QTOOL_PROBE_LAYOUT_ENUM_(id, name, description) id,
    QTOOL_PROBE_LAYOUT_LIST(QTOOL_PROBE_LAYOUT_ENUM_)
#undef QTOOL_PROBE_LAYOUT_ENUM_
    QTOOL_PROBE_LAYOUT_COUNT
} qtool_probe_layout_t;

/* what every refusal lists */
#define QTOOL_PROBE_LAYOUT_NAMES "latlong (2:1), angular (square), ball (square), vcross (3:4), hcross (4:3)"

/* largest lat-long width the resampler writes (8192 x 4096 = 2^25 pixels, within lightprobe.h) */
#define QTOOL_PROBE_LAYOUT_MAX_W 8192

/* "auto", "latlong", "angular", "ball", "vcross", "hcross"; NULL for an unknown value */
const char *qtool_probe_layout_name(qtool_probe_layout_t layout);

/* One line describing the layout, for the CLI ("Debevec angular map", ...); never NULL. */
const char *qtool_probe_layout_describe(qtool_probe_layout_t layout);

/* Parses a name as qtool_probe_layout_name gives it ("auto" included); 0, or -1 (*out untouched). */
int qtool_probe_layout_parse(const char *s, qtool_probe_layout_t *out);

/* Whether a w x h image can hold the layout: latlong any w, h >= 1 (the CLI warns unless 2:1);
 * angular and ball square, w >= 2; vcross 3F x 4F and hcross 4F x 3F, F >= 1. */
int qtool_probe_layout_check(qtool_probe_layout_t layout, int w, int h, char *err, size_t errlen);

/* The layout of a w x h float RGB image (rows top first), by the rules above. Refuses non-finite or
 * negative samples (naming the pixel), a square with black corners (ambiguous: asks for --layout),
 * and every image that fits no layout (naming them). */
int qtool_probe_layout_detect(int w, int h, const float *rgb, qtool_probe_layout_t *out, char *err, size_t errlen);

/* The lat-long size the resampler writes for a w x h image in the layout (see above). */
int qtool_probe_layout_latlong_size(qtool_probe_layout_t layout, int w, int h, int *ow, int *oh, char *err,
                                   size_t errlen);

/* Resamples a w x h float RGB image in the layout (not AUTO) to an ow x oh lat-long, malloc'd into
 * *out (the caller frees). latlong in, same size out: an exact copy. Samples must be finite and
 * >= 0 (else the pixel is named). */
int qtool_probe_layout_to_latlong(qtool_probe_layout_t layout, int w, int h, const float *rgb, int ow, int oh,
                                 float **out, char *err, size_t errlen);

/* The reverse: a lw x lh lat-long into a w x h image of the layout, malloc'd into *out. */
int qtool_probe_layout_from_latlong(qtool_probe_layout_t layout, int lw, int lh, const float *latlong, int w, int h,
                                   float **out, char *err, size_t errlen);

/* The world direction (unit, qibl's frame) of continuous image position (x, y) (pixel centres at
 * integer + 1/2) of a w x h image in the layout: 0, or -1 where the layout has no picture (outside
 * the disc, unused cross cells, outside the image). */
int qtool_probe_layout_dir(qtool_probe_layout_t layout, int w, int h, double x, double y, double d[3]);

/* The image position of a world direction d (any length > 0); 0, or -1 for a zero d or a layout
 * that is not one. Positions are inside the image; on a disc's rim the point chosen is
 * (rightmost, centre row). */
int qtool_probe_layout_pos(qtool_probe_layout_t layout, int w, int h, const double d[3], double *x, double *y);

/* Radiance RGBE bytes of n float RGB pixels, in the convention of io/hdr.h and qibl/lightprobe.h
 * (P = m 2^(E - 136), no +1/2): the largest channel rounded to nearest on 8 bits, the others on the
 * same exponent. Values below 2^-128 are 0; values are assumed finite and >= 0 (as the resampler
 * writes them), and above 2^127 saturate. */
void qtool_probe_layout_rgbe_encode(const float *rgb, size_t n, uint8_t *rgbe);

/* A w x h RGBE image (4 bytes a pixel) upsampled 4x by nearest neighbour (16 w h pixels, malloc'd;
 * NULL when out of memory): a large probe with real content, for the benchmarks and the study. */
uint8_t *qtool_probe_layout_rgbe_up4(const uint8_t *px, int w, int h);

/* The CLI's path: a Radiance file's RGBE pixels (w x h, 4 bytes each, as qtool_hdr_read_rgbe gives)
 * in the layout `want` (AUTO: detect) to a lat-long of RGBE bytes. *used gets the layout read;
 * for latlong the pixels are copied as they are (bit for bit), otherwise decoded to float,
 * resampled and re-encoded. *out (malloc'd, ow x oh pixels) belongs to the caller. */
int qtool_probe_layout_rgbe_to_latlong(qtool_probe_layout_t want, int w, int h, const uint8_t *rgbe,
                                      qtool_probe_layout_t *used, int *ow, int *oh, uint8_t **out, char *err,
                                      size_t errlen);

#endif
