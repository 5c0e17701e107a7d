/*
 * raster.c - z-buffered Gouraud triangles into a software framebuffer (qibl/raster.h).
 *
 * Invariants: freestanding C99 like core/ (no libc, no float, no heap, no mutable state). Only
 * 32 x 32 -> 64-bit products and 64-bit divisions through the core's helpers at setup, and 64-bit
 * additions per pixel, so Cortex-M0 needs no libgcc. Planes are stepped in modular uint64 (exact:
 * every value that is read back lies within int64), converted to signed only when read.
 */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "qibl/fixed.h"
#include "qibl/raster.h"
#include "qibl/soft.h"

#define RUN 64u              /* pixels per qibl_soft_fb_write_row call at most */
#define GRAD_FRAC 16u        /* fraction bits of an attribute gradient */
#define GRAD_QMAX (1u << 24) /* quotients at or above this are capped (slivers) */
#define NATTR 4              /* z, r, g, b */

static int64_t to_s64(uint64_t u)
{
    return (u >> 63) ? -(int64_t)(~u) - 1 : (int64_t)u;
}

/* g * d modulo 2^64 (g any int64, d any int32) with 32 x 32 -> 64 products only */
static uint64_t mul_mod(int64_t g, int32_t d)
{
    const uint64_t ug = (uint64_t)g;
    const uint32_t m = d < 0 ? 0u - (uint32_t)d : (uint32_t)d;
    uint64_t p = qibl_mul_u32_u64((uint32_t)ug, m) + ((uint64_t)((uint32_t)(ug >> 32) * m) << 32);
    return d < 0 ? 0u - p : p;
}

/* round(num * 2^16 / den), den > 0, magnitude capped at GRAD_QMAX * 2^16 */
static int64_t gradient(int64_t num, int64_t den)
{
    const uint64_t n = num < 0 ? 0u - (uint64_t)num : (uint64_t)num, d = (uint64_t)den;
    uint64_t r, g;
    const uint64_t q = qibl_udiv_u64(n, d, &r);
    if (q >= GRAD_QMAX)
        g = (uint64_t)GRAD_QMAX << GRAD_FRAC;
    else /* r < d <= 2^37: r * 2^16 + d / 2 fits */
        g = (q << GRAD_FRAC) + qibl_udiv_u64((r << GRAD_FRAC) + d / 2u, d, NULL);
    return num < 0 ? -(int64_t)g : (int64_t)g;
}

static int32_t clamp_nonneg(int32_t x)
{
    return x < 0 ? 0 : x;
}

/* width * height depth values fit size_t and the caller's count (no division: Cortex-M0 has none) */
static bool depth_fits(const qibl_raster_target_t *t)
{
    const uint64_t n = qibl_mul_u32_u64(t->fb.width, t->fb.height);
    return n <= (uint64_t)SIZE_MAX && (uint64_t)t->depth_count >= n;
}

static qibl_status_t check_target(const qibl_raster_target_t *t)
{
    if (!t)
        return QIBL_E_NULL_POINTER;
    qibl_status_t s = qibl_soft_fb_check(&t->fb);
    if (s != QIBL_OK)
        return s;
    if (t->fb.format == QIBL_FB_ACCUM32)
        return QIBL_E_FB_FORMAT;
    if (!t->depth)
        return QIBL_E_NULL_POINTER;
    return depth_fits(t) ? QIBL_OK : QIBL_E_FB_SIZE;
}

qibl_status_t qibl_soft_raster_clear_depth(const qibl_raster_target_t *t)
{
    if (!t)
        return QIBL_E_NULL_POINTER;
    qibl_status_t s = qibl_soft_fb_check(&t->fb);
    if (s != QIBL_OK)
        return s;
    if (!t->depth)
        return QIBL_E_NULL_POINTER;
    if (!depth_fits(t))
        return QIBL_E_FB_SIZE;
    const size_t n = (size_t)t->fb.width * t->fb.height;
    for (size_t i = 0; i < n; ++i)
        t->depth[i] = QIBL_RASTER_DEPTH_FAR;
    return QIBL_OK;
}

typedef struct run {
    int32_t rgb[RUN * 3];
    uint32_t x0, n;
} run_t;

static void flush(const qibl_fb_desc_t *fb, run_t *r, uint32_t y)
{
    if (r->n)
        QIBL_DROP_STATUS(qibl_soft_fb_write_row(fb, r->x0, y, r->n, r->rgb)); /* cannot fail: validated, in bounds */
    r->n = 0;
}

static void draw(const qibl_raster_target_t *t, const qibl_raster_vertex_t *a, const qibl_raster_vertex_t *b,
                 const qibl_raster_vertex_t *c, run_t *run)
{
    /* A2 > 0: clockwise on screen (y down) */
    int64_t area = qibl_mul_s32_s64(b->x - a->x, c->y - a->y) - qibl_mul_s32_s64(b->y - a->y, c->x - a->x);
    if (area == 0)
        return;
    if (area > 0 ? t->cull == QIBL_RASTER_CULL_CW : t->cull == QIBL_RASTER_CULL_CCW)
        return;
    if (area < 0) { /* make it clockwise: edges of two neighbours then run in opposite directions */
        const qibl_raster_vertex_t *s = b;
        b = c, c = s, area = -area;
    }
    const qibl_raster_vertex_t *v[3] = {a, b, c};

    /* pixel bounding box: centres i * 16 + 8 within [min, max], clipped to the framebuffer */
    int32_t xmin = a->x, xmax = a->x, ymin = a->y, ymax = a->y;
    for (int k = 1; k < 3; ++k) {
        xmin = v[k]->x < xmin ? v[k]->x : xmin, xmax = v[k]->x > xmax ? v[k]->x : xmax;
        ymin = v[k]->y < ymin ? v[k]->y : ymin, ymax = v[k]->y > ymax ? v[k]->y : ymax;
    }
    int32_t i0 = qibl_asr_s32(xmin + 7, 4), i1 = qibl_asr_s32(xmax - 8, 4);
    int32_t j0 = qibl_asr_s32(ymin + 7, 4), j1 = qibl_asr_s32(ymax - 8, 4);
    i0 = i0 < 0 ? 0 : i0, j0 = j0 < 0 ? 0 : j0;
    if (i1 >= (int32_t)t->fb.width)
        i1 = (int32_t)t->fb.width - 1;
    if (j1 >= (int32_t)t->fb.height)
        j1 = (int32_t)t->fb.height - 1;
    if (i0 > i1 || j0 > j1)
        return;
    const int32_t px = i0 * 16 + 8, py = j0 * 16 + 8;

    /* edges k: from v[k] to v[k+1]; E(p) = dx (py - ya) - dy (px - xa) > 0 inside. A centre on an
     * edge belongs to it when dy > 0, or dy == 0 and dx < 0: the reverse edge gets the opposite
     * answer, so a shared edge's pixels go to exactly one of its two triangles. */
    int64_t e[3], erow[3];
    int32_t estep[3], erowstep[3];
    for (int k = 0; k < 3; ++k) {
        const qibl_raster_vertex_t *p = v[k], *q = v[k == 2 ? 0 : k + 1];
        const int32_t dx = q->x - p->x, dy = q->y - p->y;
        const int own = dy > 0 || (dy == 0 && dx < 0);
        erow[k] = qibl_mul_s32_s64(dx, py - p->y) - qibl_mul_s32_s64(dy, px - p->x) + own;
        estep[k] = -16 * dy, erowstep[k] = 16 * dx;
    }

    /* attribute planes: value * 2^16 + 2^15 at the first centre, steps per pixel and per row */
    uint64_t arow[NATTR], astep[NATTR], arowstep[NATTR];
    int32_t lo[NATTR], hi[NATTR];
    for (int m = 0; m < NATTR; ++m) {
        int32_t val[3];
        for (int k = 0; k < 3; ++k)
            val[k] = m == 0 ? v[k]->z : clamp_nonneg(v[k]->rgb[m - 1]);
        lo[m] = val[0], hi[m] = val[0];
        for (int k = 1; k < 3; ++k)
            lo[m] = val[k] < lo[m] ? val[k] : lo[m], hi[m] = val[k] > hi[m] ? val[k] : hi[m];
        const int32_t d1 = val[1] - val[0], d2 = val[2] - val[0]; /* both values in 0 .. 2^31 - 1 */
        const int64_t gx = gradient(qibl_mul_s32_s64(d1, c->y - a->y) - qibl_mul_s32_s64(d2, b->y - a->y), area);
        const int64_t gy = gradient(qibl_mul_s32_s64(d2, b->x - a->x) - qibl_mul_s32_s64(d1, c->x - a->x), area);
        arow[m] = ((uint64_t)(uint32_t)val[0] << GRAD_FRAC) + (1u << (GRAD_FRAC - 1)) + mul_mod(gx, px - a->x) +
                  mul_mod(gy, py - a->y);
        astep[m] = mul_mod(gx, 16), arowstep[m] = mul_mod(gy, 16);
    }

    const uint32_t w = t->fb.width;
    for (int32_t j = j0; j <= j1; ++j) {
        uint64_t acc[NATTR];
        for (int k = 0; k < 3; ++k)
            e[k] = erow[k];
        for (int m = 0; m < NATTR; ++m)
            acc[m] = arow[m];
        uint32_t *drow = t->depth + (size_t)j * w;
        run->n = 0;
        for (int32_t i = i0; i <= i1; ++i) {
            if (e[0] > 0 && e[1] > 0 && e[2] > 0) {
                int32_t val[NATTR];
                for (int m = 0; m < NATTR; ++m) {
                    const int64_t x = qibl_asr_s64(to_s64(acc[m]), GRAD_FRAC);
                    val[m] = x < lo[m] ? lo[m] : x > hi[m] ? hi[m] : (int32_t)x;
                }
                if ((uint32_t)val[0] < drow[i]) {
                    drow[i] = (uint32_t)val[0];
                    if (run->n == 0)
                        run->x0 = (uint32_t)i;
                    run->rgb[3 * run->n] = val[1], run->rgb[3 * run->n + 1] = val[2];
                    run->rgb[3 * run->n + 2] = val[3];
                    if (++run->n == RUN)
                        flush(&t->fb, run, (uint32_t)j);
                } else {
                    flush(&t->fb, run, (uint32_t)j);
                }
            } else {
                flush(&t->fb, run, (uint32_t)j);
            }
            for (int k = 0; k < 3; ++k)
                e[k] += estep[k];
            for (int m = 0; m < NATTR; ++m)
                acc[m] += astep[m];
        }
        flush(&t->fb, run, (uint32_t)j);
        for (int k = 0; k < 3; ++k)
            erow[k] += erowstep[k];
        for (int m = 0; m < NATTR; ++m)
            arow[m] += arowstep[m];
    }
}

qibl_status_t qibl_soft_raster_triangles(const qibl_raster_target_t *t, const qibl_raster_vertex_t *v, uint32_t nv,
                                    const uint32_t (*tri)[3], uint32_t ntri)
{
    qibl_status_t s = check_target(t);
    if (s != QIBL_OK)
        return s;
    if (ntri == 0)
        return QIBL_OK;
    if (!v || !tri)
        return QIBL_E_NULL_POINTER;
    for (uint32_t k = 0; k < ntri; ++k)
        for (int c = 0; c < 3; ++c)
            if (tri[k][c] >= nv)
                return QIBL_E_RASTER_INDEX;
    for (uint32_t k = 0; k < ntri; ++k)
        for (int c = 0; c < 3; ++c) {
            const qibl_raster_vertex_t *p = &v[tri[k][c]];
            if (p->x < -QIBL_RASTER_COORD_MAX || p->x > QIBL_RASTER_COORD_MAX || p->y < -QIBL_RASTER_COORD_MAX ||
                p->y > QIBL_RASTER_COORD_MAX || p->z < 0)
                return QIBL_E_RASTER_RANGE;
        }
    run_t run;
    for (uint32_t k = 0; k < ntri; ++k)
        draw(t, &v[tri[k][0]], &v[tri[k][1]], &v[tri[k][2]], &run);
    return QIBL_OK;
}
