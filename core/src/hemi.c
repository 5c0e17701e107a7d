/*
 * hemi.c - hemispherical rasterization: plane LUT, triangle masks, SH transfer, frames.
 *
 * Invariants: integer only, no heap, no state outside the caller's workspace; every table is
 * built from exact integer tests (plane LUT) or from qibl_sh_eval_unit at exact sub-sample points
 * (basis table), so every port builds the same bytes. Magnitudes (proved where used):
 *   positions |x| < 2^22 (Q16.16) -> differences < 2^23 -> local coordinates < 2^26 (Q14.18),
 *   quantised per vertex to |q| <= 512 for the raster setup: edge normals <= 2^19, det < 2^30.
 */
#include "qibl/hemi.h"
#include "qibli.h"

#if QIBL_USE_HEMI

/* the setup and look-ups in 8-wide (x86 AVX2) or 4-wide (x86 SSE2) lanes, one code for both
 * (below); elsewhere the scalar code; the same bits everywhere */
#define HEMI_LANES (QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2 || QIBL_CONFIG_SIMD == QIBL_SIMD_SSE2)

#define NC QIBL_HEMI_COEFFS

/* ---- small integer helpers (only hemi uses them; the shared ones are in qibli.h) --------------- */


static int32_t s32_of_u32(uint32_t u)
{
    /* two's complement bits -> int32 without implementation-defined conversion */
    return u <= 0x7FFFFFFFu ? (int32_t)u : -(int32_t)(~u) - 1;
}


/* bits set in w (SWAR) */
static uint32_t popcount32(uint32_t w)
{
    w = w - ((w >> 1) & 0x55555555u);
    w = (w & 0x33333333u) + ((w >> 2) & 0x33333333u);
    w = (w + (w >> 4)) & 0x0F0F0F0Fu;
    return (w * 0x01010101u) >> 24;
}

/* index of the lowest set bit of w != 0 (de Bruijn) */
static unsigned ctz32(uint32_t w)
{
    static const uint8_t tab[32] = {0,  1,  28, 2,  29, 14, 24, 3, 30, 22, 20, 15, 25, 17, 4,  8,
                                    31, 27, 13, 23, 21, 19, 16, 7, 26, 12, 18, 6,  11, 5,  10, 9};
    return tab[((w & (0u - w)) * 0x077CB531u) >> 27];
}

/* ---- frames ----------------------------------------------------------------------------------- */

/* Is any of c[0..n) beyond [-max, max]? One flat pass with no early exit, which compilers
 * vectorise: |x| <= max is (uint32)(x + max) <= 2 max. n is a size_t: 3 times a uint32_t count
 * may pass 2^32 (an array that large exists only where size_t is wider). */
static uint32_t beyond(const int32_t *c, size_t n, int32_t max)
{
    uint32_t bad = 0;
    for (size_t k = 0; k < n; ++k)
        bad |= (uint32_t)((uint32_t)c[k] + (uint32_t)max > 2u * (uint32_t)max);
    return bad;
}

static int coord_ok(int32_t x)
{
    return x >= -QIBL_HEMI_COORD_MAX && x <= QIBL_HEMI_COORD_MAX;
}

qibl_status_t qibl_hemi_frame_init(qibl_hemi_frame_t *f, const qibl_q16_t p[3], const int32_t nrm[3])
{
    if (f == 0 || p == 0 || nrm == 0)
        return QIBL_E_NULL_POINTER;
    if (!coord_ok(p[0]) || !coord_ok(p[1]) || !coord_ok(p[2]))
        return QIBL_E_HEMI_RANGE;
    qibl_q30_t u[3];
    qibl_status_t st = qibl_vec3_normalize_q30(nrm, u);
    if (st != QIBL_OK)
        return st;
    qibl_q30_t ca = QIBL_Q30_ONE, sa = 0, sb = 0;
    if (u[0] != 0 || u[1] != 0) {
        const int32_t h2[3] = {u[0], u[1], 0};
        qibl_q30_t a[3];
        QIBL_DROP_STATUS(qibl_vec3_normalize_q30(h2, a));
        ca = a[0], sa = a[1];
        const uint64_t r2 = (uint64_t)qibl_mul_s32_s64(u[0], u[0]) + (uint64_t)qibl_mul_s32_s64(u[1], u[1]);
        uint64_t rem;
        uint32_t r = qibl_isqrt_u64(r2, &rem);
        sb = (qibl_q30_t)(r + (rem > r ? 1u : 0u));
    }
    const qibl_q30_t cb = u[2];
    /* nothing can fail from here on: write *f directly (a struct copy may call memcpy) */
    for (int k = 0; k < 3; ++k)
        f->p[k] = p[k];
    f->axis[0][0] = qibl_mul_q30(cb, ca), f->axis[0][1] = qibl_mul_q30(cb, sa), f->axis[0][2] = -sb;
    f->axis[1][0] = -sa, f->axis[1][1] = ca, f->axis[1][2] = 0;
    f->axis[2][0] = u[0], f->axis[2][1] = u[1], f->axis[2][2] = u[2];
    f->ca = ca, f->sa = sa, f->cb = cb, f->sb = sb;
    return QIBL_OK;
}

qibl_status_t qibl_hemi_transform(const qibl_hemi_frame_t *f, const qibl_q16_t (*pos)[3], uint32_t count,
                                  int32_t (*out)[3])
{
    QIBLI_DISPATCH(qibl_hemi_transform, (f, pos, count, out));
    if (f == 0 || (count != 0u && (pos == 0 || out == 0)))
        return QIBL_E_NULL_POINTER;
    if (count != 0u && beyond(&pos[0][0], 3u * (size_t)count, QIBL_HEMI_COORD_MAX))
        return QIBL_E_HEMI_RANGE;
    /* Q30 x Q16 -> Q14.18: a rounding shift by SH = 28, written with a constant shift on an offset
     * unsigned value (no saturation needed: |result| < 2^26) */
    enum { SH = 30 - (QIBL_HEMI_LOCAL_FRAC - 16) };
    const uint64_t bias = ((uint64_t)1 << (SH - 1)) + ((uint64_t)1 << 62);
    const int64_t unbias = (int64_t)1 << (62 - SH);
    for (uint32_t k = 0; k < count; ++k) {
        /* |d| < 2^23: each product < 2^53, the sum < 2^55; the result < sqrt(3) 2^23 2^2 < 2^26;
         * s + 2^27 + 2^62 is positive and below 2^63, so the shift is floor((s + 2^27) / 2^28) */
        const int32_t d0 = pos[k][0] - f->p[0], d1 = pos[k][1] - f->p[1], d2 = pos[k][2] - f->p[2];
        for (int j = 0; j < 3; ++j) {
            const int64_t s = qibl_mul_s32_s64(f->axis[j][0], d0) + qibl_mul_s32_s64(f->axis[j][1], d1) +
                              qibl_mul_s32_s64(f->axis[j][2], d2);
            out[k][j] = (int32_t)((int64_t)(((uint64_t)s + bias) >> SH) - unbias);
        }
    }
    return QIBL_OK;
}

/* ---- group culling ------------------------------------------------------------------------------ */

qibl_status_t qibl_hemi_bound_fit(const qibl_q16_t (*pos)[3], uint32_t nv, const uint32_t *idx, uint32_t n,
                              qibl_hemi_bound_t *out)
{
    if (out == 0 || (n != 0u && pos == 0))
        return QIBL_E_NULL_POINTER;
    int32_t lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    for (uint32_t k = 0; k < n; ++k) {
        const uint32_t i = idx ? idx[k] : k;
        if (i >= nv)
            return QIBL_E_HEMI_INDEX;
        for (int j = 0; j < 3; ++j) {
            const int32_t x = pos[i][j];
            if (!coord_ok(x))
                return QIBL_E_HEMI_RANGE;
            if (k == 0 || x < lo[j])
                lo[j] = x;
            if (k == 0 || x > hi[j])
                hi[j] = x;
        }
    }
    if (n == 0u) {
        out->c[0] = out->c[1] = out->c[2] = 0, out->r = -1;
        return QIBL_OK;
    }
    qibl_q16_t c[3];
    for (int j = 0; j < 3; ++j) /* |lo + hi| < 2^23: floor of the half by an arithmetic shift helper */
        c[j] = qibl_asr_s32(lo[j] + hi[j], 1);
    uint64_t d2max = 0; /* |v - c| < 2^23 per axis: the squared distance < 3 2^46 */
    for (uint32_t k = 0; k < n; ++k) {
        const uint32_t i = idx ? idx[k] : k;
        uint64_t d2 = 0;
        for (int j = 0; j < 3; ++j) {
            const int32_t d = pos[i][j] - c[j];
            d2 += (uint64_t)qibl_mul_s32_s64(d, d);
        }
        d2max = d2 > d2max ? d2 : d2max;
    }
    uint64_t rem;
    const uint32_t r = qibl_isqrt_u64(d2max, &rem);
    for (int j = 0; j < 3; ++j)
        out->c[j] = c[j];
    out->r = (int32_t)(r + (rem != 0u ? 1u : 0u)); /* < 2^24 */
    return QIBL_OK;
}

/* |u| rounded up for the tangent plane's normal u: 2^30 + 256 covers the normaliser's few LSB;
 * otherwise the exact root + 1 */
static uint32_t normal_len_up(const int32_t *u)
{
    const uint64_t u2 = (uint64_t)qibl_mul_s32_s64(u[0], u[0]) + (uint64_t)qibl_mul_s32_s64(u[1], u[1]) +
                        (uint64_t)qibl_mul_s32_s64(u[2], u[2]);
    const uint32_t nb = (1u << 30) + 256u;
    if (u2 <= qibl_mul_u32_u64(nb, nb))
        return nb;
    uint64_t rem;
    return qibl_isqrt_u64(u2, &rem) + 1u;
}

/* qibl_hemi_bound_above for a non-empty b with |u| rounded up given (ul) */
static int above_ul(const qibl_hemi_frame_t *f, uint32_t ul, const qibl_hemi_bound_t *b)
{
    if (!coord_ok(b->c[0]) || !coord_ok(b->c[1]) || !coord_ok(b->c[2])) /* not a qibl_hemi_bound_fit bound: */
        return 1;                                                        /* kept, the safe side */
    /* s = u . (c - p): |c - p| < 2^23, |u_k| <= 2^30 + 256: |s| < 3 2^53; r ul < 2^24 2^31 */
    const int32_t *u = f->axis[2];
    int64_t s = 0;
    for (int k = 0; k < 3; ++k)
        s += qibl_mul_s32_s64(u[k], b->c[k] - f->p[k]);
    return s + (int64_t)qibl_mul_u32_u64((uint32_t)b->r, ul) > 0 ? 1 : 0;
}

int qibl_hemi_bound_above(const qibl_hemi_frame_t *f, const qibl_hemi_bound_t *b)
{
    if (f == 0 || b == 0 || b->r < 0)
        return 0;
    if (!coord_ok(b->c[0]) || !coord_ok(b->c[1]) || !coord_ok(b->c[2]))
        return 1;
    return above_ul(f, normal_len_up(f->axis[2]), b);
}

/* qibl_hemi_bound_near for a non-empty b and k_q8 != 0 */
static int near_k(const qibl_hemi_frame_t *f, const qibl_hemi_bound_t *b, uint32_t k_q8)
{
    if (!coord_ok(b->c[0]) || !coord_ok(b->c[1]) || !coord_ok(b->c[2])) /* not a qibl_hemi_bound_fit bound: */
        return 1;                                                        /* refine, the safe side */
    /* |c - p| <= 2^23 per axis (both within QIBL_HEMI_COORD_MAX): d2 < 3 2^46, d2 2^16 < 2^64 */
    uint64_t d2 = 0;
    for (int k = 0; k < 3; ++k) {
        const int32_t d = b->c[k] - f->p[k];
        d2 += (uint64_t)qibl_mul_s32_s64(d, d);
    }
    const uint64_t kr = qibl_mul_u32_u64((uint32_t)b->r, k_q8); /* Q16.16 x Q8.8 */
    if (kr >= ((uint64_t)1 << 32))                              /* (k r)^2 >= 2^64 > d2 2^16 */
        return 1;
    const uint32_t k32 = (uint32_t)kr;
    return (d2 << 16) < qibl_mul_u32_u64(k32, k32) ? 1 : 0;
}

/* ---- rasterization --------------------------------------------------------------------------- */

int qibl_hemi_bound_near(const qibl_hemi_frame_t *f, const qibl_hemi_bound_t *b, uint32_t k_q8)
{
    if (f == 0 || b == 0 || b->r < 0 || k_q8 == 0u)
        return 0;
    return near_k(f, b, k_q8);
}

qibl_status_t qibl_hemi_bound_cull(const qibl_hemi_frame_t *f, const qibl_hemi_bound_t *near, const qibl_hemi_bound_t *far,
                                   uint32_t n, uint32_t k_q8, uint8_t *out)
{
    if (f == 0 || (n != 0u && (near == 0 || far == 0 || out == 0)))
        return QIBL_E_NULL_POINTER;
    const uint32_t ul = normal_len_up(f->axis[2]); /* once per receiver, not per group */
    for (uint32_t c = 0; c < n; ++c) {
        const int in = k_q8 != 0u && near[c].r >= 0 && near_k(f, &near[c], k_q8);
        const qibl_hemi_bound_t *b = in ? &near[c] : &far[c];
        out[c] = (uint8_t)(b->r >= 0 && above_ul(f, ul, b) ? (in ? 2u : 1u) : 0u);
    }
    return QIBL_OK;
}

qibl_status_t qibl_hemi_clear(const qibl_hemi_t *h, uint32_t *mask)
{
    if (h == 0 || mask == 0)
        return QIBL_E_NULL_POINTER;
    for (uint32_t i = 0; i < h->words; ++i)
        mask[i] = 0u;
    return QIBL_OK;
}

qibl_status_t qibl_hemi_clip(const qibl_hemi_t *h, uint32_t *mask)
{
    QIBLI_DISPATCH(qibl_hemi_clip, (h, mask));
    if (h == 0 || mask == 0)
        return QIBL_E_NULL_POINTER;
    for (uint32_t i = 0; i < h->words; ++i)
        mask[i] &= h->disk[i];
    return QIBL_OK;
}

/* One edge plane's table entry: the stored mask and whether to complement it (XOR with all
 * ones: the - faces). */
typedef struct edge {
    const uint32_t *m;
    uint32_t x;
} edge;

/* mask |= A & B & C with per-entry complement: one straight loop, no branch on the entries
 * (the table folds only the complement, an XOR, so no entry is read in another row order); the
 * word count a constant per mask size, so compilers unroll and vectorise it. */
#define AND3_BODY(W)                                                                             \
    for (uint32_t i = 0; i < (W); ++i)                                                           \
        mask[i] |= (a[i] ^ xa) & (b[i] ^ xb) & (c[i] ^ xc);

static void and3(uint32_t *restrict mask, const edge *ea, const edge *eb, const edge *ec, uint32_t words)
{
    const uint32_t *restrict a = ea->m, *restrict b = eb->m, *restrict c = ec->m;
    const uint32_t xa = ea->x, xb = eb->x, xc = ec->x;
    if (words == 32u)
        AND3_BODY(32u)
    else if (words == 16u)
        AND3_BODY(16u)
    else
        AND3_BODY(words)
}

/* ---- the deterministic setup: quantised vertices, int32 edge normals ------------------------
 *
 * A plane through the receiver and an edge depends only on the directions of the edge's ends, so
 * each vertex is first scaled by its own power of two and rounded to |q| <= 512 (same direction
 * within 2^-9): then every edge normal (|e| <= 2^19) and the orientation (|det| < 2^30) are exact
 * in int32, with no 64-bit product, on every port and in every lane width. The masks are those of
 * the quantised triangle: the same bits from the scalar code below and the x86 lanes. */

#if !HEMI_LANES
/* q = round_half_up(v / 2^s), s the fewest bits with max |v_k| >> s < 512 (|v| < 2^26: s <= 17) */
static void quantise(const int32_t *v, int32_t q[3])
{
    /* the OR of the magnitudes has the bit length of their maximum */
    const uint32_t m = qibli_abs_u32(v[0]) | qibli_abs_u32(v[1]) | qibli_abs_u32(v[2]);
    const unsigned s = qibli_bitlen_u32(m >> 9);
    const int32_t half = (int32_t)((1u << s) >> 1);
    for (int k = 0; k < 3; ++k)
        q[k] = qibl_asr_s32(v[k] + half, s);
}

/* |a|, |b| <= 512: each product <= 2^18, the difference <= 2^19 */
static void cross32(const int32_t *a, const int32_t *b, int32_t out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

#endif

static void cross(const int32_t *a, const int32_t *b, int64_t out[3])
{
    out[0] = qibl_mul_s32_s64(a[1], b[2]) - qibl_mul_s32_s64(a[2], b[1]);
    out[1] = qibl_mul_s32_s64(a[2], b[0]) - qibl_mul_s32_s64(a[0], b[2]);
    out[2] = qibl_mul_s32_s64(a[0], b[1]) - qibl_mul_s32_s64(a[1], b[0]);
}

/* sign of n . c exactly for |n_i| < 2^53, |c_i| < 2^26: n = nh 2^26 + nl (nl in [0, 2^26)), so
 * n . c = H 2^26 + L with |H| < 3 2^53, |L| < 3 2^52; then H + floor(L / 2^26) decides. */
static int dot_sign(const int64_t n[3], const int32_t *c)
{
    int64_t H = 0, L = 0;
    for (int k = 0; k < 3; ++k) {
        const int32_t nh = (int32_t)qibl_asr_s64(n[k], 26);          /* |nh| < 2^27 */
        const int32_t nl = (int32_t)((uint64_t)n[k] & 0x3FFFFFFu);    /* n - nh 2^26 */
        H += qibl_mul_s32_s64(nh, c[k]);
        L += qibl_mul_s32_s64(nl, c[k]);
    }
    const int64_t top = H + qibl_asr_s64(L, 26);
    const uint32_t low = (uint32_t)((uint64_t)L & 0x3FFFFFFu); /* L - floor(L / 2^26) 2^26 */
    return top > 0 || (top == 0 && low > 0u) ? 1 : top < 0 ? -1 : 0;
}

/* TRI_BELOW (every vertex at or below the horizon, on the unquantised z), TRI_THROUGH (the plane
 * passes through the receiver, exactly), or TRI_DRAW with e the three edge normals oriented so
 * the triangle's cone lies on their positive sides. */
enum { TRI_BELOW, TRI_THROUGH, TRI_DRAW };

/* Where the quantised orientation is 0 (the plane through the receiver, or a triangle so flat
 * seen from it that rounding its directions made it so: a huge roof just above), the exact setup
 * on the unquantised vertices: exact int64 normals (< 2^53), the exact sign, each normal then
 * shifted below 2^19 (direction kept within 2^-18). Rare; the same scalar code under every ISA. */
static int tri_exact(const int32_t *a, const int32_t *b, const int32_t *c, int32_t e[3][3])
{
    int64_t x[3][3];
    cross(a, b, x[0]);
    cross(b, c, x[1]);
    cross(c, a, x[2]);
    const int s = dot_sign(x[0], c);
    if (s == 0)
        return TRI_THROUGH;
    for (int i = 0; i < 3; ++i) {
        uint64_t m = 0u;
        for (int k = 0; k < 3; ++k)
            m = qibli_abs_u64(x[i][k]) > m ? qibli_abs_u64(x[i][k]) : m;
        const unsigned bl = qibli_bitlen_u64_inline(m), sh = bl > 19u ? bl - 19u : 0u; /* m >> sh < 2^19 */
        /* orient before the shift: floor(-x / 2^sh) is not -floor(x / 2^sh), and the other
         * winding must give the same normals (|x| < 2^53, so -x is exact) */
        for (int k = 0; k < 3; ++k)
            e[i][k] = (int32_t)qibl_asr_s64(s < 0 ? -x[i][k] : x[i][k], sh);
    }
    return TRI_DRAW;
}

#if !HEMI_LANES
static int tri_setup(const int32_t *a, const int32_t *b, const int32_t *c, int32_t e[3][3])
{
    if (a[2] <= 0 && b[2] <= 0 && c[2] <= 0)
        return TRI_BELOW;
    int32_t qa[3], qb[3], qc[3];
    quantise(a, qa), quantise(b, qb), quantise(c, qc);
    cross32(qa, qb, e[0]);
    cross32(qb, qc, e[1]);
    cross32(qc, qa, e[2]);
    const int32_t d = e[0][0] * qc[0] + e[0][1] * qc[1] + e[0][2] * qc[2]; /* 3 terms <= 2^28 */
    if (d == 0)
        return tri_exact(a, b, c, e);
    if (d < 0)
        for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k)
                e[i][k] = -e[i][k];
    return TRI_DRAW;
}
#endif

/* floor(num / den) for den >= 1 and a quotient below 256 (num < 256 den): 8 shift-subtract steps
 * where there is no divide instruction, so no library call is emitted. */
static uint32_t small_div(uint32_t num, uint32_t den)
{
#if QIBL_CONFIG_NATIVE_DIV64 || defined(__ARM_FEATURE_IDIV) || defined(__riscv_div)
    return num / den;
#else
    uint32_t q = 0;
    for (int k = 7; k >= 0; --k)
        if ((num >> k) >= den) {
            num -= den << k;
            q |= 1u << k;
        }
    return q;
#endif
}

/* Cell of u / m in [-1, 1] on F cells: floor((m + u) F / (2 m)), clamped; num = m + u in
 * [0, 2m], num F < 2^20 2^7 */
static uint32_t cell(uint32_t num, uint32_t m, uint32_t F)
{
    const uint32_t i = small_div(num * F, 2u * m);
    return i >= F ? F - 1u : i;
}

/* The LUT entry of the plane with normal e (not zero): the face of its largest component, the
 * two cells, and the complement for a - face (its u and v change sign). */
static edge lookup(const qibl_hemi_t *h, const int32_t e[3])
{
    const uint32_t ax = qibli_abs_u32(e[0]), ay = qibli_abs_u32(e[1]), az = qibli_abs_u32(e[2]);
    const uint32_t F = (uint32_t)h->face;
    int neg;
    uint32_t m;
    int32_t u, v;
    size_t base;
    if (ax >= ay && ax >= az) /* +-x: u = e1, v = e2 */
        neg = e[0] < 0, m = ax, u = e[1], v = e[2], base = 0u;
    else if (ay >= az) /* +-y: u = e0, v = e2 */
        neg = e[1] < 0, m = ay, u = e[0], v = e[2], base = (size_t)F * F;
    else /* +-z: u = e1, v = e0 */
        neg = e[2] < 0, m = az, u = e[1], v = e[0], base = 2u * (size_t)F * F;
    if (neg) /* the - face is the complement of the + face at -e */
        u = -u, v = -v;
    edge r;
    r.x = neg ? 0xFFFFFFFFu : 0u;
    const size_t idx = base + (size_t)cell((uint32_t)((int32_t)m + u), m, F) * F + cell((uint32_t)((int32_t)m + v), m, F);
    r.m = h->lut + idx * h->words;
    return r;
}

#if HEMI_LANES
/* ---- x86: the same setup and look-ups in lanes, 8 (AVX2) or 4 (SSE2) triangles at a time ------
 *
 * Written once over hv, 8 int32 lanes (AVX2) or 4 (SSE2), and the hv_* / HV_* operations below;
 * where SSE2 lacks an instruction its operation emulates it (abs, max, min, the 32-bit products
 * from two pmuludq, the per-lane shift as a product, gathers as scalar loads) and the horizon cull
 * stays scalar (HV_GATHER 0). int32 lanes for the quantisation (the shift from the exponent of
 * (m >> 9) as a float, exact below 2^24), the cross products and the orientation, all exact as in
 * the scalar code. The cell's divide in float32 lanes: est = trunc(fl(fl(num F) / D)) is within 1
 * of floor(num F / D) (the quotient is at most 128 and its relative error below 2^-22), and one
 * exact int32 step corrects it (r = num F - est D, est += (r >= D) - (r < 0)): the scalar code's
 * cells, bit for bit. */
#define HEMI_BATCH 64u /* triangles set up before their masks are read */

#if QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2
#include <immintrin.h>
typedef __m256i hv;
#define HV_LANES 8u
#define HV_GATHER 1
#define HV_LD(p) _mm256_loadu_si256((const __m256i *)(const void *)(p))
#define HV_ST(p, x) _mm256_storeu_si256((__m256i *)(void *)(p), (x))
#define HV_SET1 _mm256_set1_epi32
#define HV_ZERO _mm256_setzero_si256
#define HV_ADD _mm256_add_epi32
#define HV_SUB _mm256_sub_epi32
#define HV_AND _mm256_and_si256
#define HV_ANDNOT _mm256_andnot_si256
#define HV_OR _mm256_or_si256
#define HV_XOR _mm256_xor_si256
#define HV_SRAI _mm256_srai_epi32
#define HV_SRLI _mm256_srli_epi32
#define HV_GT _mm256_cmpgt_epi32
#define HV_EQ _mm256_cmpeq_epi32
#define HV_MUL _mm256_mullo_epi32 /* the low 32 bits of each product */
#define HV_ABS _mm256_abs_epi32
#define HV_MAX _mm256_max_epi32
#define HV_MIN _mm256_min_epi32
#define HV_FLOAT_BITS(x) _mm256_castps_si256(_mm256_cvtepi32_ps(x))
#define HV_FDIV_TRUNC(a, b) _mm256_cvttps_epi32(_mm256_div_ps(_mm256_cvtepi32_ps(a), _mm256_cvtepi32_ps(b)))
#define HV_SIGNS(x) ((uint32_t)_mm256_movemask_ps(_mm256_castsi256_ps(x)))

/* round_half_up(x / 2^s) per lane, 0 <= s <= 17 */
static inline hv hv_shr_round(hv x, hv s)
{
    const hv half = _mm256_srli_epi32(_mm256_sllv_epi32(_mm256_set1_epi32(1), s), 1);
    return _mm256_srav_epi32(_mm256_add_epi32(x, half), s);
}

/* the vertices v[ix[l]] of HV_LANES triangle corners, by component: gathered where every offset
 * 3 ix[l] fits an int32 (gather_ok: nv < 2^29), else loaded one by one */
static inline void hv_gather3(const int32_t (*v)[3], const uint32_t *ix, int gather_ok, hv *x, hv *y, hv *z)
{
    if (!gather_ok) {
        int32_t c[3][HV_LANES];
        for (uint32_t l = 0; l < HV_LANES; ++l)
            c[0][l] = v[ix[l]][0], c[1][l] = v[ix[l]][1], c[2][l] = v[ix[l]][2];
        *x = HV_LD(c[0]), *y = HV_LD(c[1]), *z = HV_LD(c[2]);
        return;
    }
    const int *vb = (const int *)(const void *)v;
    const hv i3 = _mm256_mullo_epi32(HV_LD(ix), _mm256_set1_epi32(3));
    *x = _mm256_i32gather_epi32(vb, i3, 4), *y = _mm256_i32gather_epi32(vb + 1, i3, 4);
    *z = _mm256_i32gather_epi32(vb + 2, i3, 4);
}

/* (1) in lanes, while eight whole triangles are left and the batch has room for them: their 24
 * indices with three loads deinterleaved by blends and a permute each (cheaper than three strided
 * gathers), their vertices' z gathered, the kept triangles' numbers and indices appended in order.
 * Returns the new k; *t advanced. */
static inline uint32_t hv_cull(const int32_t (*v)[3], const uint32_t (*tri)[3], uint32_t ntri, uint32_t *t, uint32_t k,
                               uint32_t *keep, uint32_t (*ki)[HEMI_BATCH + HV_LANES])
{
    const int *vb = (const int *)(const void *)v;
    const hv zero = HV_ZERO();
    const hv pa = _mm256_setr_epi32(0, 3, 6, 1, 4, 7, 2, 5), pb = _mm256_setr_epi32(1, 4, 7, 2, 5, 0, 3, 6),
             pc = _mm256_setr_epi32(2, 5, 0, 3, 6, 1, 4, 7);
    while (*t + HV_LANES <= ntri && k + HV_LANES <= HEMI_BATCH) {
        const hv L0 = HV_LD(&tri[*t][0]), L1 = HV_LD(&tri[*t][0] + 8), L2 = HV_LD(&tri[*t][0] + 16);
        const hv iw[3] = {_mm256_permutevar8x32_epi32(_mm256_blend_epi32(_mm256_blend_epi32(L0, L1, 0x92), L2, 0x24), pa),
                          _mm256_permutevar8x32_epi32(_mm256_blend_epi32(_mm256_blend_epi32(L0, L1, 0x24), L2, 0x49), pb),
                          _mm256_permutevar8x32_epi32(_mm256_blend_epi32(_mm256_blend_epi32(L0, L1, 0x49), L2, 0x92), pc)};
        uint32_t I[3][HV_LANES];
        hv above = zero;
        for (int w = 0; w < 3; ++w) {
            const hv i = iw[w];
            HV_ST(I[w], i);
            const hv i3 = HV_ADD(i, HV_ADD(i, i));
            above = HV_OR(above, HV_GT(_mm256_i32gather_epi32(vb + 2, i3, 4), zero));
        }
        for (uint32_t bits = HV_SIGNS(above); bits != 0u; bits &= bits - 1u) {
            const uint32_t l = ctz32(bits);
            keep[k] = *t + l, ki[0][k] = I[0][l], ki[1][k] = I[1][l], ki[2][k] = I[2][l];
            ++k;
        }
        *t += HV_LANES;
    }
    return k;
}
#else
#include <emmintrin.h>
typedef __m128i hv;
#define HV_LANES 4u
#define HV_GATHER 0 /* no gathers: the horizon cull scalar */
#define HV_LD(p) _mm_loadu_si128((const __m128i *)(const void *)(p))
#define HV_ST(p, x) _mm_storeu_si128((__m128i *)(void *)(p), (x))
#define HV_SET1 _mm_set1_epi32
#define HV_ZERO _mm_setzero_si128
#define HV_ADD _mm_add_epi32
#define HV_SUB _mm_sub_epi32
#define HV_AND _mm_and_si128
#define HV_ANDNOT _mm_andnot_si128
#define HV_OR _mm_or_si128
#define HV_XOR _mm_xor_si128
#define HV_SRAI _mm_srai_epi32
#define HV_SRLI _mm_srli_epi32
#define HV_GT _mm_cmpgt_epi32
#define HV_EQ _mm_cmpeq_epi32
#define HV_MUL hv_mul
#define HV_ABS hv_abs
#define HV_MAX hv_max
#define HV_MIN hv_min
#define HV_FLOAT_BITS(x) _mm_castps_si128(_mm_cvtepi32_ps(x))
#define HV_FDIV_TRUNC(a, b) _mm_cvttps_epi32(_mm_div_ps(_mm_cvtepi32_ps(a), _mm_cvtepi32_ps(b)))
#define HV_SIGNS(x) ((uint32_t)_mm_movemask_ps(_mm_castsi128_ps(x)))

/* the low 32 bits of each lane's product, from two pmuludq */
static inline hv hv_mul(hv a, hv b)
{
    const hv p02 = _mm_mul_epu32(a, b), p13 = _mm_mul_epu32(_mm_srli_epi64(a, 32), _mm_srli_epi64(b, 32));
    return _mm_unpacklo_epi32(_mm_shuffle_epi32(p02, _MM_SHUFFLE(0, 0, 2, 0)), _mm_shuffle_epi32(p13, _MM_SHUFFLE(0, 0, 2, 0)));
}

static inline hv hv_abs(hv x)
{
    const hv s = _mm_srai_epi32(x, 31);
    return _mm_sub_epi32(_mm_xor_si128(x, s), s);
}

static inline hv hv_max(hv a, hv b)
{
    const hv g = _mm_cmpgt_epi32(a, b);
    return _mm_or_si128(_mm_and_si128(g, a), _mm_andnot_si128(g, b));
}

static inline hv hv_min(hv a, hv b)
{
    const hv g = _mm_cmpgt_epi32(a, b);
    return _mm_or_si128(_mm_and_si128(g, b), _mm_andnot_si128(g, a));
}

/* round_half_up(x / 2^s) per lane, 0 <= s <= 17, |x| < 2^26: no per-lane shift, so a product by
 * 2^(17 - s) (|x + half| < 2^(9 + s): below 2^26) and one shift by 17, 2^(17 - s) and 2^s / 2
 * from float exponents (compilers share them between the three calls with one s) */
static inline hv hv_shr_round(hv x, hv s)
{
    const hv p = _mm_cvttps_epi32(_mm_castsi128_ps(_mm_slli_epi32(_mm_sub_epi32(_mm_set1_epi32(127 + 17), s), 23)));
    const hv half = _mm_srli_epi32(_mm_cvttps_epi32(_mm_castsi128_ps(_mm_slli_epi32(_mm_add_epi32(s, _mm_set1_epi32(127)), 23))), 1);
    return _mm_srai_epi32(hv_mul(_mm_add_epi32(x, half), p), 17);
}

/* the vertices v[ix[l]] of four triangle corners, by component (loads: no offsets to overflow) */
static inline void hv_gather3(const int32_t (*v)[3], const uint32_t *ix, int gather_ok, hv *x, hv *y, hv *z)
{
    (void)gather_ok;
    const int32_t *a = v[ix[0]], *b = v[ix[1]], *c = v[ix[2]], *d = v[ix[3]];
    *x = _mm_setr_epi32(a[0], b[0], c[0], d[0]), *y = _mm_setr_epi32(a[1], b[1], c[1], d[1]);
    *z = _mm_setr_epi32(a[2], b[2], c[2], d[2]);
}
#endif

/* m ? a : b for whole-lane masks, as and / andnot / or: the vpblendvb form gave other masks under
 * gcc 12 with -mavx512bw (-march=native on this host; the ports' native build caught it) */
static inline hv hv_sel(hv m, hv a, hv b)
{
    return HV_OR(HV_AND(m, a), HV_ANDNOT(m, b));
}

/* q = round_half_up(v / 2^s) per lane, s from the float exponent of max |v| >> 9 (exact below
 * 2^24), as the scalar quantise */
static inline void hv_quantise(hv *x, hv *y, hv *z)
{
    const hv m = HV_MAX(HV_MAX(HV_ABS(*x), HV_ABS(*y)), HV_ABS(*z));
    const hv e = HV_SRLI(HV_FLOAT_BITS(HV_SRLI(m, 9)), 23); /* 0 for 0, else 127 + floor(log2) */
    const hv s = HV_MAX(HV_SUB(e, HV_SET1(126)), HV_ZERO());
    *x = hv_shr_round(*x, s), *y = hv_shr_round(*y, s), *z = hv_shr_round(*z, s);
}

static inline hv hv_cell(hv num, hv d, hv vF, hv vF1)
{
    const hv nF = HV_MUL(num, vF); /* < 2^27 */
    hv q = HV_FDIV_TRUNC(nF, d);
    const hv r = HV_SUB(nF, HV_MUL(q, d));
    /* +1 where r >= d, -1 where r < 0 (compare masks are -1) */
    q = HV_SUB(q, HV_GT(r, HV_SUB(d, HV_SET1(1))));
    q = HV_ADD(q, HV_GT(HV_ZERO(), r));
    return HV_MIN(q, vF1);
}

/* LUT entry numbers and complement words of HV_LANES edge normals (none zero) */
static inline void hv_lookup(hv e0, hv e1, hv e2, hv vF, hv vF1, hv vFF, uint32_t *idx, uint32_t *cx)
{
    const hv ax = HV_ABS(e0), ay = HV_ABS(e1), az = HV_ABS(e2);
    const hv ones = HV_SET1(-1);
    const hv isx = HV_XOR(HV_OR(HV_GT(ay, ax), HV_GT(az, ax)), ones);
    const hv yge = HV_XOR(HV_GT(az, ay), ones);
    const hv isy = HV_ANDNOT(isx, yge), isz = HV_XOR(HV_OR(isx, yge), ones);
    const hv m = HV_MAX(HV_MAX(ax, ay), az);
    const hv ng = HV_SRAI(hv_sel(isx, e0, hv_sel(isy, e1, e2)), 31);
    const hv u = HV_SUB(HV_XOR(hv_sel(isy, e0, e1), ng), ng);
    const hv v = HV_SUB(HV_XOR(hv_sel(isz, e0, e2), ng), ng);
    const hv d = HV_ADD(m, m);
    const hv cu = hv_cell(HV_ADD(m, u), d, vF, vF1), cv = hv_cell(HV_ADD(m, v), d, vF, vF1);
    const hv base = HV_ADD(HV_AND(isy, vFF), HV_AND(isz, HV_ADD(vFF, vFF)));
    HV_ST(idx, HV_ADD(base, HV_ADD(HV_MUL(cu, vF), cv)));
    HV_ST(cx, ng);
}

/* The triangles in batches: (1) the horizon cull (in lanes where there are gathers, hv_cull; the
 * rest scalar), the kept triangles' numbers and indices written in order; (2) their vertices
 * gathered, quantisation, edge normals, orientation and look-ups in lanes (a quantised det of 0:
 * the exact scalar setup); (3) the masks, a 32 x 32 one held in registers across the batch. Same
 * masks and counts as the scalar loop. */
static void raster_batches(const qibl_hemi_t *h, const int32_t (*v)[3], uint32_t nv, const uint32_t (*tri)[3],
                           uint32_t ntri, uint32_t *mask, uint32_t *nr, uint32_t *nb, uint32_t *nt)
{
    uint32_t keep[HEMI_BATCH + HV_LANES], ki[3][HEMI_BATCH + HV_LANES], li[3][HEMI_BATCH + HV_LANES],
        lx[3][HEMI_BATCH + HV_LANES];
    uint32_t skip[HEMI_BATCH + HV_LANES];
    const uint32_t words = h->words;
    const int32_t F = h->face;
    const hv vF = HV_SET1(F), vF1 = HV_SET1(F - 1), vFF = HV_SET1(F * F);
    const hv zero = HV_ZERO(), one = HV_SET1(1);
    const int gather_ok = HV_GATHER && nv < (1u << 29); /* the gathers' int32 offsets */
    uint32_t t = 0;
    while (t < ntri) {
        const uint32_t t0 = t;
        uint32_t k = 0;
#if HV_GATHER
        if (gather_ok) /* (1) */
            k = hv_cull(v, tri, ntri, &t, k, keep, ki);
#endif
        if (!gather_ok || t + HV_LANES > ntri)
            for (; t < ntri && k < HEMI_BATCH; ++t) {
                const uint32_t *q = tri[t];
                keep[k] = t, ki[0][k] = q[0], ki[1][k] = q[1], ki[2][k] = q[2];
                k += (uint32_t)((v[q[0]][2] > 0) | (v[q[1]][2] > 0) | (v[q[2]][2] > 0));
            }
        *nb += (t - t0) - k;
        if (k == 0u)
            continue;
        for (uint32_t j = k; j % HV_LANES != 0u; ++j) /* pad with the first kept triangle (ignored) */
            keep[j] = keep[0], ki[0][j] = ki[0][0], ki[1][j] = ki[1][0], ki[2][j] = ki[2][0];
        for (uint32_t j = 0; j < k; j += HV_LANES) { /* (2) */
            hv ax, ay, az, bx, by, bz, cx, cy, cz;
            hv_gather3(v, ki[0] + j, gather_ok, &ax, &ay, &az);
            hv_gather3(v, ki[1] + j, gather_ok, &bx, &by, &bz);
            hv_gather3(v, ki[2] + j, gather_ok, &cx, &cy, &cz);
            hv_quantise(&ax, &ay, &az), hv_quantise(&bx, &by, &bz), hv_quantise(&cx, &cy, &cz);
#define MUL HV_MUL
#define SUB HV_SUB
            hv e00 = SUB(MUL(ay, bz), MUL(az, by)), e01 = SUB(MUL(az, bx), MUL(ax, bz)), e02 = SUB(MUL(ax, by), MUL(ay, bx));
            hv e10 = SUB(MUL(by, cz), MUL(bz, cy)), e11 = SUB(MUL(bz, cx), MUL(bx, cz)), e12 = SUB(MUL(bx, cy), MUL(by, cx));
            hv e20 = SUB(MUL(cy, az), MUL(cz, ay)), e21 = SUB(MUL(cz, ax), MUL(cx, az)), e22 = SUB(MUL(cx, ay), MUL(cy, ax));
            const hv d = HV_ADD(HV_ADD(MUL(e00, cx), MUL(e01, cy)), MUL(e02, cz));
#undef MUL
#undef SUB
            const hv thr = HV_EQ(d, zero);
            const hv sg = HV_SRAI(d, 31); /* orient: every normal negated when det < 0 */
            /* a plane through the receiver gets the normal (1, 0, 0) so that its look-up is harmless */
#define ORIENT(e, r) e = hv_sel(thr, r, HV_SUB(HV_XOR(e, sg), sg))
            ORIENT(e00, one), ORIENT(e01, zero), ORIENT(e02, zero);
            ORIENT(e10, one), ORIENT(e11, zero), ORIENT(e12, zero);
            ORIENT(e20, one), ORIENT(e21, zero), ORIENT(e22, zero);
#undef ORIENT
            hv_lookup(e00, e01, e02, vF, vF1, vFF, li[0] + j, lx[0] + j);
            hv_lookup(e10, e11, e12, vF, vF1, vFF, li[1] + j, lx[1] + j);
            hv_lookup(e20, e21, e22, vF, vF1, vFF, li[2] + j, lx[2] + j);
            for (uint32_t l = 0; l < HV_LANES; ++l)
                skip[j + l] = 0u;
            for (uint32_t bits = HV_SIGNS(thr); bits != 0u; bits &= bits - 1u) {
                const uint32_t l = ctz32(bits);
                if (j + l >= k)
                    break;
                const uint32_t *q = tri[keep[j + l]]; /* the exact setup, as the scalar code */
                int32_t e[3][3];
                if (tri_exact(v[q[0]], v[q[1]], v[q[2]], e) != TRI_DRAW) {
                    skip[j + l] = 1u;
                    continue;
                }
                for (int i = 0; i < 3; ++i) {
                    const edge ed = lookup(h, e[i]);
                    li[i][j + l] = (uint32_t)((size_t)(ed.m - h->lut) / words), lx[i][j + l] = ed.x;
                }
            }
        }
        if (words == 32u) { /* (3), the 32 x 32 mask in registers across the batch */
            hv m[32u / HV_LANES];
            for (uint32_t r = 0; r < 32u / HV_LANES; ++r)
                m[r] = HV_LD(mask + r * HV_LANES);
            for (uint32_t j = 0; j < k; ++j) {
                if (skip[j]) {
                    ++*nt;
                    continue;
                }
                const uint32_t *a = h->lut + (size_t)li[0][j] * 32u, *b = h->lut + (size_t)li[1][j] * 32u,
                               *c = h->lut + (size_t)li[2][j] * 32u;
                const hv xa = HV_SET1((int)lx[0][j]), xb = HV_SET1((int)lx[1][j]), xc = HV_SET1((int)lx[2][j]);
                for (uint32_t r = 0; r < 32u / HV_LANES; ++r) {
                    const uint32_t o = r * HV_LANES;
                    m[r] = HV_OR(m[r], HV_AND(HV_AND(HV_XOR(HV_LD(a + o), xa), HV_XOR(HV_LD(b + o), xb)), HV_XOR(HV_LD(c + o), xc)));
                }
                ++*nr;
            }
            for (uint32_t r = 0; r < 32u / HV_LANES; ++r)
                HV_ST(mask + r * HV_LANES, m[r]);
            continue;
        }
        for (uint32_t j = 0; j < k; ++j) { /* (3) */
            if (skip[j]) {
                ++*nt;
                continue;
            }
            edge ed[3];
            for (int i = 0; i < 3; ++i)
                ed[i].m = h->lut + (size_t)li[i][j] * words, ed[i].x = lx[i][j];
            and3(mask, &ed[0], &ed[1], &ed[2], words);
            ++*nr;
        }
    }
}
#endif

qibl_status_t qibl_hemi_raster(const qibl_hemi_t *h, const int32_t (*v)[3], uint32_t nv, const uint32_t (*tri)[3],
                               uint32_t ntri, uint32_t *mask, qibl_hemi_stats_t *stats)
{
    QIBLI_DISPATCH(qibl_hemi_raster, (h, v, nv, tri, ntri, mask, stats));
    if (h == 0 || mask == 0 || (ntri != 0u && (v == 0 || tri == 0)))
        return QIBL_E_NULL_POINTER;
    /* indices first, then every vertex once (cheaper than per reference for shared vertices), each
     * a flat loop with no early exit */
    uint32_t bad = 0;
    if (ntri != 0u) {
        const uint32_t *ix = &tri[0][0];
        for (size_t k = 0; k < 3u * (size_t)ntri; ++k) /* size_t: 3 ntri may pass 2^32 */
            bad |= (uint32_t)(ix[k] >= nv);
    }
    if (bad)
        return QIBL_E_HEMI_INDEX;
    if (ntri != 0u && beyond(&v[0][0], 3u * (size_t)nv, QIBL_HEMI_LOCAL_MAX))
        return QIBL_E_HEMI_RANGE;
    uint32_t nr = 0, nb = 0, nt = 0;
#if HEMI_LANES
    raster_batches(h, v, nv, tri, ntri, mask, &nr, &nb, &nt);
#else
    const uint32_t words = h->words;
    for (uint32_t t = 0; t < ntri; ++t) {
        int32_t e[3][3];
        const int r = tri_setup(v[tri[t][0]], v[tri[t][1]], v[tri[t][2]], e);
        if (r != TRI_DRAW) {
            if (r == TRI_BELOW)
                ++nb;
            else
                ++nt;
            continue;
        }
        const edge ea = lookup(h, e[0]), eb = lookup(h, e[1]), ec = lookup(h, e[2]);
        and3(mask, &ea, &eb, &ec, words);
        ++nr;
    }
#endif
    if (stats != 0) {
        stats->rasterized += nr;
        stats->below += nb;
        stats->through += nt;
    }
    return QIBL_OK;
}

/* ---- transfer ---------------------------------------------------------------------------------- */

static void add_bits(uint32_t acc[NC], const uint32_t *basis, uint32_t base, uint32_t w)
{
    while (w != 0u) {
        const uint32_t *t = basis + (size_t)(base + ctz32(w)) * NC;
        w &= w - 1u;
        for (int i = 0; i < NC; ++i)
            acc[i] += t[i];
    }
}

qibl_status_t qibl_hemi_transfer(const qibl_hemi_t *h, const uint32_t *mask, qibl_q30_t out[QIBL_HEMI_COEFFS])
{
    QIBLI_DISPATCH(qibl_hemi_transfer, (h, mask, out));
    if (h == 0 || mask == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    uint32_t blocked = 0, inside = 0;
    for (uint32_t i = 0; i < h->words; ++i) {
        blocked += popcount32(mask[i] & h->disk[i]);
        inside += popcount32(h->disk[i]);
    }
    uint32_t acc[NC];
    const int sub = blocked <= inside - blocked; /* fewer blocked pixels: subtract them */
    for (int i = 0; i < NC; ++i)
        acc[i] = 0u;
    const uint32_t bits = h->wpr == 1u ? (uint32_t)h->n : 32u; /* pixels per word */
    for (uint32_t i = 0; i < h->words; ++i) {
        const uint32_t w = sub ? (mask[i] & h->disk[i]) : (~mask[i] & h->disk[i]);
        if (w != 0u)
            add_bits(acc, h->basis, i * bits, w);
    }
    /* wrapping sums are exact modulo 2^32 and the true value fits Q2.30 */
    for (int i = 0; i < NC; ++i)
        out[i] = s32_of_u32(sub ? h->full[i] - acc[i] : acc[i]);
    return QIBL_OK;
}

/* ---- rotation ---------------------------------------------------------------------------------- */

/* z rotation by theta (cos, sin in Q2.30): for f'(w) = f(Rz^T w), the pair (m, -m) of band l turns
 * by m theta: c'_m = cos c_m - sin c_-m, c'_-m = cos c_-m + sin c_m. In place. */
/* b^e in Q30 for b in [0, 2^30] (Q30), by squaring, each product truncated */
static uint32_t pow_q30(uint32_t b, uint32_t e)
{
    uint32_t w = 1u << 30;
    for (; e != 0u && w != 0u; e >>= 1) {
        if (e & 1u)
            w = (uint32_t)(qibl_mul_u32_u64(w, b) >> 30);
        b = (uint32_t)(qibl_mul_u32_u64(b, b) >> 30);
    }
    return w;
}

qibl_status_t qibl_hemi_transfer_phong(const qibl_hemi_t *h, const uint32_t *mask, const qibl_q30_t refl[3],
                                       uint32_t exponent, qibl_q30_t out[QIBL_HEMI_COEFFS])
{
    QIBLI_DISPATCH(qibl_hemi_transfer_phong, (h, mask, refl, exponent, out));
    if (h == 0 || mask == 0 || refl == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    if (exponent > QIBL_HEMI_MAX_EXPONENT)
        return QIBL_E_HEMI_EXPONENT;
    qibl_q30_t r[3];
    if (qibl_vec3_normalize_q30(refl, r) != QIBL_OK)
        return QIBL_E_ZERO_VECTOR;
    const int32_t n = h->n;
    const unsigned lg = n == 16 ? 4u : n == 32 ? 5u : 6u;
    int64_t acc[NC];
    for (int i = 0; i < NC; ++i)
        acc[i] = 0;
    for (int32_t row = 0; row < n; ++row)
        for (uint32_t k = 0; k < h->wpr; ++k) {
            const uint32_t wi = (uint32_t)row * h->wpr + k;
            uint32_t vis = ~mask[wi] & h->disk[wi];
            if (n == 16)
                vis &= 0xFFFFu;
            while (vis) {
                const int32_t c = (int32_t)(k * 32u + ctz32(vis));
                vis &= vis - 1u;
                const uint32_t p = (uint32_t)(row * n + c);
                const int32_t X = 2 * c + 1 - n, Y = 2 * row + 1 - n;
                const int64_t dxy = qibl_mul_s32_s64(r[0], X) + qibl_mul_s32_s64(r[1], Y); /* rx X + ry Y, Q30 */
                int64_t d;
                if (h->zc[p] != 0u) /* r . s = (rx X + ry Y) / n + rz z */
                    d = qibl_asr_s64(dxy, lg) + qibl_asr_s64(qibl_mul_s32_s64(r[2], (int32_t)h->zc[p]), 30);
                else if (dxy > 0) { /* the horizon point (X, Y) / |(X, Y)|: |(X, Y)| 2^20 below */
                    uint64_t rem;
                    const uint32_t len = qibl_isqrt_u64((uint64_t)(uint32_t)(X * X + Y * Y) << 40, &rem);
                    d = (int64_t)qibl_udiv_u64((uint64_t)dxy << 20, len, 0); /* dxy < 2^38 */
                }
                else
                    d = 0;
                const uint32_t w = exponent == 0u ? 1u << 30
                                   : d <= 0       ? 0u
                                                  : pow_q30(d >= (int64_t)1 << 30 ? 1u << 30 : (uint32_t)d, exponent);
                const int32_t w15 = (int32_t)(w >> 15);
                if (w15 == 0)
                    continue;
                const uint32_t *t = h->basis + (size_t)p * NC;
                for (int i = 0; i < NC; ++i)
                    acc[i] += qibl_mul_s32_s64(s32_of_u32(t[i]), w15);
            }
        }
    for (int i = 0; i < NC; ++i)
        out[i] = (qibl_q30_t)qibl_rshr_s64(acc[i], 15);
    return QIBL_OK;
}

static void rot_z(int32_t *c, qibl_q30_t cs, qibl_q30_t sn)
{
    qibl_q30_t cm[5], sm[5];
    cm[1] = cs, sm[1] = sn;
    for (int m = 2; m <= 4; ++m) {
        cm[m] = qibl_rshr_s64(qibl_mul_s32_s64(cm[m - 1], cs) - qibl_mul_s32_s64(sm[m - 1], sn), 30);
        sm[m] = qibl_rshr_s64(qibl_mul_s32_s64(sm[m - 1], cs) + qibl_mul_s32_s64(cm[m - 1], sn), 30);
    }
    for (int l = 1; l <= 4; ++l)
        for (int m = 1; m <= l; ++m) {
            const int ip = l * l + l + m, in = l * l + l - m;
            const int32_t p = c[ip], q = c[in];
            c[ip] = qibl_rshr_s64(qibl_mul_s32_s64(cm[m], p) - qibl_mul_s32_s64(sm[m], q), 30);
            c[in] = qibl_rshr_s64(qibl_mul_s32_s64(cm[m], q) + qibl_mul_s32_s64(sm[m], p), 30);
        }
}

qibl_status_t qibl_hemi_to_world(const qibl_hemi_t *h, const qibl_hemi_frame_t *f, const qibl_q30_t *in,
                                 qibl_q30_t *out)
{
    QIBLI_DISPATCH(qibl_hemi_to_world, (h, f, in, out));
    if (h == 0 || f == 0 || in == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    int32_t t[NC];
    /* D(R) = Dz(alpha) D(Rx(-90)) Dz(beta) D(Rx(90)), applied right to left */
    QIBL_DROP_STATUS(qibl_sh_rotate(h->rx_pos, in, t));
    rot_z(t, f->cb, f->sb);
    QIBL_DROP_STATUS(qibl_sh_rotate(h->rx_neg, t, out));
    rot_z(out, f->ca, f->sa);
    return QIBL_OK;
}

qibl_status_t qibl_hemi_to_frame(const qibl_hemi_t *h, const qibl_hemi_frame_t *f, const int32_t *in,
                                 int32_t *out)
{
    QIBLI_DISPATCH(qibl_hemi_to_frame, (h, f, in, out));
    if (h == 0 || f == 0 || in == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    int32_t t[NC];
    /* D(R)^T = D(Rx(-90)) Dz(-beta) D(Rx(90)) Dz(-alpha), applied right to left */
    for (int i = 0; i < NC; ++i)
        t[i] = in[i];
    rot_z(t, f->ca, -f->sa);
    QIBL_DROP_STATUS(qibl_sh_rotate(h->rx_pos, t, out));
    rot_z(out, f->cb, -f->sb);
    for (int i = 0; i < NC; ++i)
        t[i] = out[i];
    QIBL_DROP_STATUS(qibl_sh_rotate(h->rx_neg, t, out));
    return QIBL_OK;
}

qibl_status_t qibl_hemi_shade(const int32_t light[3][QIBL_HEMI_COEFFS], const qibl_q30_t v[QIBL_HEMI_COEFFS],
                              qibl_q16_t out[3])
{
    if (light == 0 || v == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    for (int ch = 0; ch < 3; ++ch) {
        int64_t s = 0; /* 25 terms below 2^48 each */
        for (int i = 0; i < NC; ++i)
            s += qibl_asr_s64(qibl_mul_s32_s64(light[ch][i], v[i]), 14);
        out[ch] = qibl_rshr_s64(s, 16);
    }
    return QIBL_OK;
}

#else
typedef int qibl_hemi_compiled_out; /* ISO C wants a declaration in every translation unit */
#endif /* QIBL_USE_HEMI */
