/*
 * gonio.c - goniometric lamps: the lamp's frame, the octahedral table lookup and the per-span scale.
 *
 * Invariants: every 64-bit product goes through qibl_mul_s32_s64 / qibl_mul_u32_u64, every 64-bit
 * shift through qibl_shr_u64 / qibl_asr_s64 and the one division per lookup through qibl_udiv_u64,
 * so the Cortex-M0 build calls no runtime helper. Magnitudes are reduced before products: the
 * direction to at most 2^24 per component, its lamp-frame coordinates to an L1 norm below 2^30.
 */
#include "qibl/gonio.h"
#include "qibli.h"

#if QIBL_USE_GONIO /* config.h: needs QIBL_USE_SHMAP (it scales point-light spans through the P map) */

size_t qibl_gonio_table_size(uint32_t n)
{
    if (n < QIBL_GONIO_MIN_N || n > QIBL_GONIO_MAX_N)
        return 0;
    return (size_t)n * n * 2u;
}

/* sum_k a_k b_k of int32 triples, exact in int64 (|a_k|, |b_k| <= 2^31: sum <= 3 * 2^62 would not fit,
 * so callers keep one side at most 2^30: sum <= 3 * 2^61 < 2^63) */
static int64_t dot3(const int32_t a[3], const int32_t b[3])
{
    return qibl_mul_s32_s64(a[0], b[0]) + qibl_mul_s32_s64(a[1], b[1]) + qibl_mul_s32_s64(a[2], b[2]);
}

qibl_status_t qibl_gonio_init(qibl_gonio_t *g, uint32_t n, const uint16_t *table, const int32_t aim[3],
                              const int32_t up[3])
{
    if (g == 0 || table == 0 || aim == 0 || up == 0)
        return QIBL_E_NULL_POINTER;
    if (qibl_gonio_table_size(n) == 0u)
        return QIBL_E_GONIO_SIZE;
    for (uint32_t i = 0; i < n * n; ++i)
        if (table[i] > QIBL_GONIO_ONE)
            return QIBL_E_GONIO_TABLE;
    qibl_q30_t z[3], u[3], y[3], x[3];
    if (qibl_vec3_normalize_q30(aim, z) != QIBL_OK)
        return QIBL_E_GONIO_AIM;
    if (qibl_vec3_normalize_q30(up, u) != QIBL_OK)
        return QIBL_E_GONIO_UP;
    /* y = u - (u.z) z: |u.z| <= 2^60, its Q2.30 value times z_k <= 2^60 again */
    int32_t uz = qibl_rshr_s64(dot3(u, z), 30u);
    int32_t yr[3];
    for (int k = 0; k < 3; ++k)
        yr[k] = u[k] - qibl_rshr_s64(qibl_mul_s32_s64(uz, z[k]), 30u);
    /* |y| = sin(angle between up and aim): refused below 2^-10 (then y is mostly rounding) */
    uint32_t ym = 0;
    for (int k = 0; k < 3; ++k)
        ym = qibli_abs_u32(yr[k]) > ym ? qibli_abs_u32(yr[k]) : ym;
    if (ym < (1u << 19))
        return QIBL_E_GONIO_UP;
    if (qibl_vec3_normalize_q30(yr, y) != QIBL_OK)
        return QIBL_E_GONIO_UP;
    int32_t xr[3] = {
        qibl_rshr_s64(qibl_mul_s32_s64(y[1], z[2]) - qibl_mul_s32_s64(y[2], z[1]), 30u),
        qibl_rshr_s64(qibl_mul_s32_s64(y[2], z[0]) - qibl_mul_s32_s64(y[0], z[2]), 30u),
        qibl_rshr_s64(qibl_mul_s32_s64(y[0], z[1]) - qibl_mul_s32_s64(y[1], z[0]), 30u),
    };
    if (qibl_vec3_normalize_q30(xr, x) != QIBL_OK)
        return QIBL_E_GONIO_UP;
    g->n = n;
    g->table = table;
    for (int k = 0; k < 3; ++k)
        g->x[k] = x[k], g->y[k] = y[k], g->z[k] = z[k];
    return QIBL_OK;
}

/* |v| >> sh with v's sign, for |v| >> sh <= 2^24 */
static int32_t shrink(int64_t v, unsigned sh)
{
    uint32_t m = (uint32_t)qibl_shr_u64(qibli_abs_u64(v), sh);
    return v < 0 ? -(int32_t)m : (int32_t)m;
}

/* the texel coordinate of an octahedral coordinate a / s (a in -s .. s, s in 1 .. 2^30): position of
 * (a / s + 1) / 2 * n - 1/2 in 1/65536 texel, floored, clamped to 0 .. (n - 1) 65536 */
static uint32_t texel_pos(int64_t a, uint64_t s, uint32_t n)
{
    /* (a + s) <= 2^31, times n 2^15 <= 2^23: below 2^54 */
    uint64_t num = qibl_mul_u32_u64((uint32_t)(a + (int64_t)s), n << 15);
    uint64_t q = qibl_udiv_u64(num, s, 0);
    uint64_t hi = (uint64_t)(n - 1u) << 16;
    if (q < 32768u)
        return 0;
    q -= 32768u;
    return (uint32_t)(q > hi ? hi : q);
}

uint32_t qibl_gonio_lookup(const qibl_gonio_t *g, const int64_t d[3])
{
    /* the direction to at most 2^24 per component (only its direction matters) */
    uint64_t m = qibli_abs_u64(d[0]);
    if (qibli_abs_u64(d[1]) > m)
        m = qibli_abs_u64(d[1]);
    if (qibli_abs_u64(d[2]) > m)
        m = qibli_abs_u64(d[2]);
    unsigned bl = qibli_bitlen_u64(m), sh = bl > 24u ? bl - 24u : 0u;
    int32_t w[3] = {shrink(d[0], sh), shrink(d[1], sh), shrink(d[2], sh)};
    /* lamp-frame coordinates: |w_k| <= 2^24, frame components <= 2^30: each <= 3 * 2^54 */
    int64_t l[3] = {dot3(w, g->x), dot3(w, g->y), dot3(w, g->z)};
    uint64_t al[3] = {qibli_abs_u64(l[0]), qibli_abs_u64(l[1]), qibli_abs_u64(l[2])};
    uint64_t s = al[0] + al[1] + al[2];
    unsigned sl = qibli_bitlen_u64(s), sh2 = sl > 30u ? sl - 30u : 0u;
    for (int k = 0; k < 3; ++k)
        al[k] = qibl_shr_u64(al[k], sh2);
    s = al[0] + al[1] + al[2];
    int64_t ax = 0, ay = 0;
    if (s == 0u) {
        s = 1u; /* d = 0, or below the reduced resolution: the aim's texel */
    } else if (l[2] >= 0) {
        ax = (int64_t)al[0], ay = (int64_t)al[1];
    } else {
        ax = (int64_t)(s - al[1]), ay = (int64_t)(s - al[0]);
    }
    if (l[0] < 0)
        ax = -ax;
    if (l[1] < 0)
        ay = -ay;
    const uint32_t n = g->n;
    uint32_t fx = texel_pos(ax, s, n), fy = texel_pos(ay, s, n);
    uint32_t i0 = fx >> 16, j0 = fy >> 16, tx = fx & 0xFFFFu, ty = fy & 0xFFFFu;
    uint32_t i1 = i0 + 1u < n ? i0 + 1u : i0, j1 = j0 + 1u < n ? j0 + 1u : j0;
    const uint16_t *r0 = g->table + (size_t)j0 * n, *r1 = g->table + (size_t)j1 * n;
    /* rows: <= 2^15 * 2^16 = 2^31; columns: <= 2^31 * 2^16 = 2^47 */
    uint32_t a = r0[i0] * (65536u - tx) + r0[i1] * tx;
    uint32_t b = r1[i0] * (65536u - tx) + r1[i1] * tx;
    uint64_t v = qibl_mul_u32_u64(a, 65536u - ty) + qibl_mul_u32_u64(b, ty);
    return (uint32_t)qibl_shr_u64(v + ((uint64_t)1 << 31), 32u);
}

qibl_status_t qibl_gonio_scale_span(const qibl_gonio_t *g, const qibl_pmap_t *p, const qibl_q16_t pos[3],
                                    uint32_t x0, uint32_t y, uint32_t n, int32_t *out)
{
    if (g == 0 || p == 0 || p->points == 0 || pos == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    if (y >= p->height || x0 > p->width || n > p->width - x0)
        return QIBL_E_GONIO_BOUNDS;
    for (uint32_t i = 0; i < n; ++i) {
        qibl_q16_t q[3];
        qibl_pmap_point(p, x0 + i, y, q);
        int64_t d[3] = {(int64_t)q[0] - pos[0], (int64_t)q[1] - pos[1], (int64_t)q[2] - pos[2]};
        uint32_t sc = qibl_gonio_lookup(g, d);
        if (sc == QIBL_GONIO_ONE)
            continue;
        for (int c = 0; c < 3; ++c) {
            int32_t v = out[3u * i + (uint32_t)c];
            /* |v| * sc <= 2^31 * 2^15: the rounded quotient <= |v| */
            uint32_t r = (uint32_t)qibl_shr_u64(qibl_mul_u32_u64(qibli_abs_u32(v), sc) + 16384u, 15u);
            out[3u * i + (uint32_t)c] = v < 0 ? -(int32_t)r : (int32_t)r;
        }
    }
    return QIBL_OK;
}

#endif /* QIBL_USE_GONIO */
