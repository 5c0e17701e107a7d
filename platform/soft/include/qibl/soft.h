/*
 * qibl/soft.h - the software framebuffer shim: writes rows of linear radiance from the core's
 * kernels into a caller-described framebuffer.
 *
 * What it does: exposure, optional sRGB transfer (a table, no pow), clamping, optional ordered
 * dither for RGB565, pixel packing for RGBA8888 / BGRA8888 / RGB565, and saturating accumulation
 * into a 32-bit linear accumulator (several lights or passes summed, then resolved to 8 bits).
 * What it does not do: allocate, open windows, swap buffers, or any lighting maths.
 *
 * Same rules as core/: freestanding C99, integer only, no heap, no mutable state; identical bytes
 * on every port (golden tests hash its output). Every store is a byte store with an explicit byte
 * order, so `pixels` and `stride` may have any alignment. Bytes between the end of a row and the
 * start of the next (stride padding) are never read or written. No call writes anything unless it
 * returns QIBL_OK.
 *
 * Input rows are `n` pixels of 3 int32 (R, G, B) in Q16.16, linear, 1.0 = full white after
 * exposure (negative values, which SH ringing can produce, clamp to 0). `rgb` must not overlap the
 * framebuffer.
 *
 * Conversion of one channel v to the 8-bit formats (every step in 32-bit integers, no division):
 *   e = exposure, or 1.0 when 0
 *   x = clamp(round(v * e), 0, 1.0)                  Q16.16, round half up (x is 0..65536)
 *   linear:  c = round(255 * x)                      exact rounding of x: error <= 0.5 LSB
 *   sRGB:    c = round(255 * srgb(x))                srgb = the exact IEC 61966-2-1 curve; found
 *                                                    with two const tables (1216 + 512 = 1728 bytes
 *                                                    of .rodata), exhaustively verified against the
 *                                                    curve: error <= 0.5 LSB
 * All roundings are half up. Against the unrounded product v * e the 8-bit result is off by at
 * most 0.5 LSB plus the rounding of x (2^-17 of full scale: 0.002 LSB, sRGB near black 0.03 LSB).
 *
 * RGB565 packs q = floor((u * M + d) / 2^16) per channel, M = 31 (R, B) or 63 (G), where
 *   u = x (linear) or, with sRGB, the 8-bit sRGB code c above scaled to 0..65536 as
 *       c * 257 + (c >> 7) (= c * 65536 / 255 within half a Q16.16 LSB),
 *   d = 2^15 without dither: q = round(u * M / 65536), error <= 0.5 LSB linear, <= 0.63 LSB sRGB
 *       (the 8-bit code's own rounding adds up to 0.5 * 63 / 255; measured 0.56 LSB for 5 bits,
 *       0.62 LSB for 6),
 *   d = (2 * b + 1) * 2^11 with dither, b = Bayer[y % 4][x % 4] in 0..15 at the pixel's absolute
 *       framebuffer position (so rows and spans written separately tile seamlessly), with
 *       Bayer = {{0, 8, 2, 10}, {12, 4, 14, 6}, {3, 11, 1, 9}, {15, 7, 13, 5}}. Each pixel
 *       is within 1 LSB, and the mean over any aligned 4x4 block of a flat field is within 1/32 LSB
 *       of u * M / 65536.
 *
 * Cost per 8-bit pixel, 3 channels each: a compare, one 32-bit multiply and three shift/adds
 * (exposure), then a multiply and a shift (linear) or a compare and two table loads (sRGB); then 4
 * byte stores. No division and no 64-bit arithmetic per pixel; one loop per format and transfer,
 * chosen once per call. Per call: validation and one 64/32 division (the exposure's saturation
 * limit) unless exposure is 1.0.
 */
#ifndef QIBL_SOFT_H
#define QIBL_SOFT_H

#include <stddef.h>
#include <stdint.h>
#include "qibl/fixed.h"
#include "qibl/status.h"

#ifdef __cplusplus
extern "C" {
#endif
/* This backend's statuses, in its own range (status.h: QIBL_STATUS_SOFT_BASE); its calls also
 * return the core's QIBL_E_NULL_POINTER. Macros with the enum type, so a switch or a comparison on
 * qibl_status_t takes them as it takes the core's. */
#define QIBL_E_FB_FORMAT QIBL_CAST(qibl_status_t, QIBL_STATUS_SOFT_BASE + 1) /* format unknown, or wrong for the call */
#define QIBL_E_FB_SIZE   QIBL_CAST(qibl_status_t, QIBL_STATUS_SOFT_BASE + 2) /* width or height 0, or sizes that must match differ */
#define QIBL_E_FB_STRIDE QIBL_CAST(qibl_status_t, QIBL_STATUS_SOFT_BASE + 3) /* stride below one row, or the size overflows size_t */
#define QIBL_E_FB_BOUNDS QIBL_CAST(qibl_status_t, QIBL_STATUS_SOFT_BASE + 4) /* row or span outside the framebuffer */
/* the rasterizer's (raster.h) */
#define QIBL_E_RASTER_RANGE QIBL_CAST(qibl_status_t, QIBL_STATUS_SOFT_BASE + 5) /* a vertex beyond the coordinate or depth range */
#define QIBL_E_RASTER_INDEX QIBL_CAST(qibl_status_t, QIBL_STATUS_SOFT_BASE + 6) /* a triangle index >= the vertex count */

/* QIBL_SOFT_STATUS_LIST(X): the statuses above in value order (base + 1, + 2, ...) as X(name,
 * message); qibl_soft_status_str's messages come from it alone. Append only: values are ABI. */
#define QIBL_SOFT_STATUS_LIST(X) \
    X(QIBL_E_FB_FORMAT, "framebuffer: unknown or unsuitable format") \
    X(QIBL_E_FB_SIZE, "framebuffer: zero or mismatched size") \
    X(QIBL_E_FB_STRIDE, "framebuffer: stride too small or buffer too large") \
    X(QIBL_E_FB_BOUNDS, "framebuffer: span outside the framebuffer") \
    X(QIBL_E_RASTER_RANGE, "raster: vertex beyond the coordinate or depth range") \
    X(QIBL_E_RASTER_INDEX, "raster: triangle index beyond the vertex count")

/* qibl_status_str for this backend's statuses too: a short constant description, never NULL. */
const char *qibl_soft_status_str(qibl_status_t s);

typedef enum qibl_fb_format {
    QIBL_FB_RGBA8888 = 0, /* default: bytes R, G, B, A=255 */
    QIBL_FB_BGRA8888,     /* bytes B, G, R, A=255 */
    QIBL_FB_RGB565,       /* little-endian u16: R in bits 15..11, G 10..5, B 4..0 */
    QIBL_FB_ACCUM32,      /* 3 little-endian i32 per pixel (R, G, B), Q16.16 linear, before
                           * exposure/transfer; exposure, srgb and dither are ignored */
    QIBL_FB_FORMAT_COUNT
} qibl_fb_format_t;

/* A caller-owned framebuffer. Zero-initialised fields mean the defaults noted. */
typedef struct qibl_fb_desc {
    void *pixels;              /* first byte of row 0 (any alignment) */
    uint32_t width, height;    /* pixels */
    size_t stride;             /* bytes from one row to the next; 0 = tightly packed */
    qibl_fb_format_t format;   /* default RGBA8888 */
    qibl_uq16_t exposure;      /* multiplier, UQ16.16; 0 = 1.0 */
    uint8_t srgb;              /* nonzero = sRGB transfer (IEC 61966-2-1) via table; 0 = linear */
    uint8_t dither;            /* nonzero = 4x4 ordered (Bayer) dither; honoured for RGB565 only */
} qibl_fb_desc_t;

/* Bytes per pixel of a format: 4, 4, 2, 12 (0 for an unknown one). */
uint32_t qibl_soft_fb_bytes_per_pixel(qibl_fb_format_t f);

/* Validates a descriptor.
 * Formats: none (reads the descriptor only). Bound: exact.
 * Errors, in this order: QIBL_E_NULL_POINTER (fb or fb->pixels NULL), QIBL_E_FB_FORMAT (unknown
 * format), QIBL_E_FB_SIZE (zero width or height), QIBL_E_FB_STRIDE (stride != 0 and < width * bytes
 * per pixel, or a row or the whole buffer, stride * (height - 1) + one row, overflows size_t).
 * On failure: nothing is written (nothing is, ever). */
QIBL_NODISCARD qibl_status_t qibl_soft_fb_check(const qibl_fb_desc_t *fb);

/* Writes n pixels of rgb at (x0, y) .. (x0 + n - 1, y) of fb, converting to fb's format as described
 * at the top. For QIBL_FB_ACCUM32 the row is added to what is there (per channel, saturating at
 * INT32_MIN / INT32_MAX), for the 8-bit formats it replaces it. n == 0 is a valid empty span.
 * Formats: rgb 3n int32, Q16.16 linear; out fb's format (8-bit codes, or Q16.16 for ACCUM32).
 * Bound: 8-bit <= 0.5 LSB (+ the rounding of x), RGB565 as stated at the top; ACCUM32 exact or saturated.
 * Errors, in this order: those of qibl_soft_fb_check, QIBL_E_NULL_POINTER (rgb NULL),
 * QIBL_E_FB_BOUNDS (y >= height or x0 + n > width).
 * On failure: nothing is written. */
QIBL_NODISCARD qibl_status_t qibl_soft_fb_write_row(const qibl_fb_desc_t *fb, uint32_t x0, uint32_t y, uint32_t n,
                                const int32_t *rgb);

/* Converts the accumulator src (QIBL_FB_ACCUM32) into dst (an 8-bit format) with dst's exposure,
 * transfer and dither: the bytes are those qibl_soft_fb_write_row(dst, ...) would write for the
 * accumulated values. dst may resolve in place over src (dst->pixels == src->pixels and dst's row
 * stride <= src's); any other overlap gives unspecified bytes.
 * Formats: src Q16.16 linear (ACCUM32); dst an 8-bit format. Bound: as qibl_soft_fb_write_row.
 * Errors, in this order: those of qibl_soft_fb_check for dst then src, QIBL_E_FB_FORMAT (src not
 * ACCUM32 or dst ACCUM32), QIBL_E_FB_SIZE (different width or height).
 * On failure: nothing is written. */
QIBL_NODISCARD qibl_status_t qibl_soft_fb_resolve(const qibl_fb_desc_t *dst, const qibl_fb_desc_t *src);

/* Clears a framebuffer to zero (ACCUM32) or to black with alpha 255 (8-bit formats).
 * Formats: fb's format. Bound: exact.
 * Errors: those of qibl_soft_fb_check.
 * On failure: nothing is written. */
QIBL_NODISCARD qibl_status_t qibl_soft_fb_clear(const qibl_fb_desc_t *fb);

/* Deprecated since 0.2 (removed in 0.3): the names this backend had before it took one prefix,
 * qibl_soft_. Define QIBL_SOFT_NO_DEPRECATED to leave them out. */
#ifndef QIBL_SOFT_NO_DEPRECATED
#define qibl_fb_bytes_per_pixel qibl_soft_fb_bytes_per_pixel /* deprecated */
#define qibl_fb_check qibl_soft_fb_check                     /* deprecated */
#define qibl_fb_write_row qibl_soft_fb_write_row             /* deprecated */
#define qibl_fb_resolve qibl_soft_fb_resolve                 /* deprecated */
#define qibl_fb_clear qibl_soft_fb_clear                     /* deprecated */
#endif

#ifdef __cplusplus
}
#endif

#endif /* QIBL_SOFT_H */
