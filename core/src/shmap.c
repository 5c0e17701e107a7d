/*
 * shmap.c - relighting kernels for 8-bit SH maps: per-frame weights, directional/environment spans,
 * point-light spans (cube-map LUT or direct SH), cube-map LUT build and lookup.
 *
 * Invariants: integer only, no heap, no state; int32 accumulators whose bounds are proven in
 * shmap.h; every 64-bit product through fixed.h (no library calls on Cortex-M0).
 */
#include "qibl/shmap.h"

#if QIBL_USE_SHMAP

#define SHMAP_MAX_W 32767 /* int16 weights */

/* ---- light coefficients ---------------------------------------------------------------------- */

qibl_status_t qibl_shlight_init(qibl_shlight_t *l, uint32_t k)
{
    if (l == 0)
        return QIBL_E_NULL_POINTER;
    if (k < 1u || k > (uint32_t)QIBL_SH_MAX_COUNT)
        return QIBL_E_SHMAP_K;
    l->k = k;
    for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i < QIBL_SH_MAX_COUNT; ++i)
            l->c[ch][i] = 0;
    return QIBL_OK;
}

static int bands_for(uint32_t k)
{
    int b = 1;
    while ((uint32_t)(b * b) < k)
        ++b;
    return b;
}

qibl_status_t qibl_shlight_add_dir(qibl_shlight_t *l, const qibl_q16_t dir[3], const qibl_q16_t rgb[3])
{
    if (l == 0 || dir == 0 || rgb == 0)
        return QIBL_E_NULL_POINTER;
    if (l->k < 1u || l->k > (uint32_t)QIBL_SH_MAX_COUNT)
        return QIBL_E_SHMAP_K;
    qibl_q30_t y[QIBL_SH_MAX_COUNT];
    qibl_status_t st = qibl_sh_eval(dir, bands_for(l->k), y);
    if (st != QIBL_OK)
        return st;
    for (int ch = 0; ch < 3; ++ch)
        for (uint32_t i = 0; i < l->k; ++i)
            l->c[ch][i] = qibl_add_sat_s32(l->c[ch][i], qibl_rshr_s64(qibl_mul_s32_s64(rgb[ch], y[i]), 30));
    return QIBL_OK;
}

/* ---- maps, weights --------------------------------------------------------------------------- */

qibl_status_t qibl_shmap_check(const qibl_shmaps_t *m)
{
    if (m == 0 || m->params == 0 || m->planes == 0)
        return QIBL_E_NULL_POINTER;
    if (m->k < 1u || m->k > (uint32_t)QIBL_SH_MAX_COUNT)
        return QIBL_E_SHMAP_K;
    if (m->channels != 1u && m->channels != 3u)
        return QIBL_E_SHMAP_CHANNELS;
    if (m->width == 0u || m->height == 0u)
        return QIBL_E_SHMAP_SIZE;
    return QIBL_OK;
}

static uint64_t mag64(int64_t v)
{
    return v < 0 ? 0u - (uint64_t)v : (uint64_t)v;
}

qibl_status_t qibl_shmap_weights(const qibl_shmaps_t *m, const qibl_shlight_t *light, qibl_shmap_weights_t *out)
{
    qibl_status_t st = qibl_shmap_check(m);
    if (st != QIBL_OK)
        return st;
    if (light == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    if (light->k < m->k || light->k > (uint32_t)QIBL_SH_MAX_COUNT)
        return QIBL_E_SHMAP_LIGHT_K;
    /* everything that can fail is checked above: build the weights in place (a struct copy would
     * be a memcpy call on some freestanding targets) */
    out->k = m->k;
    out->channels = m->channels;
    for (uint32_t ch = 0; ch < 3u; ++ch) {
        uint32_t src = m->channels == 3u ? ch : 0u;
        /* exact products scale * L in Q40 (Q8.24 x Q16.16), |.| <= 2^62 */
        int64_t r[QIBL_SH_MAX_COUNT];
        uint64_t maxr = 0u;
        int64_t bias32 = 0; /* sum of bias * L in Q32: each term <= 2^54, 25 terms < 2^59 */
        for (uint32_t i = 0; i < m->k; ++i) {
            qibl_q16_t li = light->c[ch][i];
            r[i] = qibl_mul_s32_s64(qibl_shmaps_scale(m, i, src), li);
            if (mag64(r[i]) > maxr)
                maxr = mag64(r[i]);
            bias32 += qibl_asr_s64(qibl_mul_s32_s64(qibl_shmaps_bias(m, i, src), li), 8);
        }
        /* smallest shift s with round(max / 2^s) <= 32767 */
        unsigned s = 0u;
        while (s < 62u && qibl_shr_u64(maxr + (s ? qibl_shr_u64((uint64_t)1 << 63, 64u - s) : 0u), s) > SHMAP_MAX_W)
            ++s;
        for (uint32_t i = 0; i < (uint32_t)QIBL_SH_MAX_COUNT; ++i) {
            int32_t v = 0;
            if (i < m->k)
                v = s == 0u ? (int32_t)r[i] : qibl_rshr_s64(r[i], s);
            out->w[ch][i] = (int16_t)(v > SHMAP_MAX_W ? SHMAP_MAX_W : v < -SHMAP_MAX_W ? -SHMAP_MAX_W : v);
        }
        /* acc unit is 2^(s-40); Q16.16 output unit is 2^-16: out = acc * 2^(s-24) */
        out->shift[ch] = (int32_t)s - 24;
        out->bias[ch] = qibl_asr_s64(bias32 + ((int64_t)1 << 15), 16); /* Q32 -> Q16.16, round half up */
    }
    return QIBL_OK;
}

size_t qibl_shmap_span_workspace_size(uint32_t n)
{
    return (size_t)n * 3u * sizeof(int32_t);
}

/* acc[p] (+)= sum of up to four planes times their weights. Separate small loops keep the bodies
 * simple enough for auto-vectorisation (bytes widened to 16 bits, 16x16->32 products). */
static void acc_first(int32_t *restrict acc, const uint8_t *restrict a, int32_t wa, uint32_t n)
{
    for (uint32_t p = 0; p < n; ++p)
        acc[p] = wa * a[p];
}

static void acc_add1(int32_t *restrict acc, const uint8_t *restrict a, int32_t wa, uint32_t n)
{
    for (uint32_t p = 0; p < n; ++p)
        acc[p] += wa * a[p];
}

static void acc_add4(int32_t *restrict acc, const uint8_t *restrict a, const uint8_t *restrict b,
                     const uint8_t *restrict c, const uint8_t *restrict d, int32_t wa, int32_t wb, int32_t wc,
                     int32_t wd, uint32_t n)
{
    for (uint32_t p = 0; p < n; ++p)
        acc[p] += wa * a[p] + wb * b[p] + wc * c[p] + wd * d[p];
}

/* out = sat32(acc * 2^shift + bias), interleaving one channel into the RGB output. */
static void finish_channel(const int32_t *acc, int32_t shift, int64_t bias, int32_t *out, uint32_t n)
{
    if (shift > 30) { /* any non-zero acc saturates */
        for (uint32_t p = 0; p < n; ++p)
            out[3u * p] = acc[p] > 0 ? INT32_MAX : acc[p] < 0 ? INT32_MIN : qibl_sat_s32(bias);
    } else if (shift >= 0) {
        int32_t mul = (int32_t)1 << shift;
        for (uint32_t p = 0; p < n; ++p)
            out[3u * p] = qibl_sat_s32(qibl_mul_s32_s64(acc[p], mul) + bias);
    } else {
        unsigned rs = (unsigned)-shift;
        for (uint32_t p = 0; p < n; ++p)
            out[3u * p] = qibl_sat_s32((int64_t)qibl_rshr_s64(acc[p], rs) + bias);
    }
}

qibl_status_t qibl_shmap_relight_span(const qibl_shmaps_t *m, const qibl_shmap_weights_t *w, uint32_t x0, uint32_t y,
                                      uint32_t n, int32_t *out, void *ws, size_t ws_size)
{
    qibl_status_t st = qibl_shmap_check(m);
    if (st != QIBL_OK)
        return st;
    if (w == 0 || out == 0 || ws == 0)
        return QIBL_E_NULL_POINTER;
    if (w->k != m->k || w->channels != m->channels)
        return QIBL_E_SHMAP_MISMATCH;
    if (y >= m->height || x0 > m->width || n > m->width - x0)
        return QIBL_E_SHMAP_BOUNDS;
    if (ws_size < qibl_shmap_span_workspace_size(n))
        return QIBL_E_WORKSPACE;
    if (n == 0u)
        return QIBL_OK;
    int32_t *acc = (int32_t *)ws; /* caller promises int32 alignment of the workspace */
    size_t off = (size_t)y * m->width + x0;
    for (uint32_t ch = 0; ch < 3u; ++ch) {
        uint32_t src = m->channels == 3u ? ch : 0u;
        const int16_t *wc = w->w[ch];
        int32_t *a = acc + (size_t)ch * n;
        acc_first(a, qibl_shmaps_plane(m, 0, src) + off, wc[0], n);
        uint32_t i = 1u;
        for (; i + 4u <= m->k; i += 4u)
            acc_add4(a, qibl_shmaps_plane(m, i, src) + off, qibl_shmaps_plane(m, i + 1u, src) + off,
                     qibl_shmaps_plane(m, i + 2u, src) + off, qibl_shmaps_plane(m, i + 3u, src) + off, wc[i],
                     wc[i + 1u], wc[i + 2u], wc[i + 3u], n);
        for (; i < m->k; ++i)
            acc_add1(a, qibl_shmaps_plane(m, i, src) + off, wc[i], n);
        finish_channel(a, w->shift[ch], w->bias[ch], out + ch, n);
    }
    return QIBL_OK;
}

/* ---- cube-map Y LUTs ------------------------------------------------------------------------- */

size_t qibl_ylut_values_size(uint32_t face_size, uint32_t k)
{
    if (face_size < 1u || face_size > QIBL_ASSET_MAX_LUT || k < 1u || k > (uint32_t)QIBL_SH_MAX_COUNT)
        return 0u;
    return (size_t)6u * face_size * face_size * k * 2u;
}

/* Direction of texel (u, v) of face f, as the OpenGL cube-map convention (asset.h), in units of
 * 1/N: s = (2u + 1 - N) / N is carried as the integer 2u + 1 - N. Each component is
 * a*N + b*s + c*t with {a, b, c} from this table (a table, not a switch: a switch becomes a call to
 * a libgcc case helper on Cortex-M0). */
static const int8_t face_basis[6][3][3] = {
    {{1, 0, 0}, {0, 0, -1}, {0, -1, 0}},  /* +X ( 1, -t, -s) */
    {{-1, 0, 0}, {0, 0, -1}, {0, 1, 0}},  /* -X (-1, -t,  s) */
    {{0, 1, 0}, {1, 0, 0}, {0, 0, 1}},    /* +Y ( s,  1,  t) */
    {{0, 1, 0}, {-1, 0, 0}, {0, 0, -1}},  /* -Y ( s, -1, -t) */
    {{0, 1, 0}, {0, 0, -1}, {1, 0, 0}},   /* +Z ( s, -t,  1) */
    {{0, -1, 0}, {0, 0, -1}, {-1, 0, 0}}, /* -Z (-s, -t, -1) */
};

static void texel_dir(uint32_t f, uint32_t u, uint32_t v, uint32_t n, int32_t d[3])
{
    int32_t s = (int32_t)(2u * u + 1u) - (int32_t)n, t = (int32_t)(2u * v + 1u) - (int32_t)n, one = (int32_t)n;
    for (int j = 0; j < 3; ++j)
        d[j] = face_basis[f][j][0] * one + face_basis[f][j][1] * s + face_basis[f][j][2] * t;
}

qibl_status_t qibl_ylut_build(uint32_t face_size, uint32_t k, uint8_t *values, size_t size)
{
    if (values == 0)
        return QIBL_E_NULL_POINTER;
    if (k < 1u || k > (uint32_t)QIBL_SH_MAX_COUNT)
        return QIBL_E_SHMAP_K;
    if (face_size < 1u || face_size > QIBL_ASSET_MAX_LUT)
        return QIBL_E_SHMAP_LUT_SIZE;
    if (size < qibl_ylut_values_size(face_size, k))
        return QIBL_E_WORKSPACE;
    int bands = bands_for(k);
    uint8_t *o = values;
    for (uint32_t f = 0; f < 6u; ++f)
        for (uint32_t v = 0; v < face_size; ++v)
            for (uint32_t u = 0; u < face_size; ++u) {
                int32_t d[3];
                qibl_q30_t y[QIBL_SH_MAX_COUNT];
                texel_dir(f, u, v, face_size, d);
                (void)qibl_sh_eval(d, bands, y); /* d is never zero: one component is +-N */
                for (uint32_t i = 0; i < k; ++i) {
                    int32_t q = qibl_rshr_s64(y[i], 16); /* Q2.30 -> Q2.14, |Y| < 1 */
                    uint32_t b = (uint32_t)q;
                    *o++ = (uint8_t)b;
                    *o++ = (uint8_t)(b >> 8);
                }
            }
    return QIBL_OK;
}

static int32_t abs32(int32_t v)
{
    return v < 0 ? -v : v; /* callers pass |v| <= 2^30 */
}

/* Texel coordinate in 1/256 texel from a face coordinate sc / ma (Q2.30 both, |sc| <= ma):
 * round(((sc / ma + 1) N / 2 - 0.5) * 256), via 1 / ma = iy / 2^ie. At texel centres it is exact. */
static int32_t face_coord(int32_t sc, uint32_t iy, unsigned ie, uint32_t n)
{
    /* s24 = sc / ma in Q24: |sc| iy / 2^(ie - 24); ie is 60..61 for ma^2 in [2^58.4, 2^60] */
    uint32_t a = (uint32_t)abs32(sc);
    uint32_t m24 = (uint32_t)qibl_shr_u64(qibl_mul_u32_u64(a, iy) + qibl_shr_u64((uint64_t)1 << 63, 88u - ie), ie - 24u);
    if (m24 > (1u << 24))
        m24 = 1u << 24;
    uint32_t s1 = sc < 0 ? (1u << 24) - m24 : (1u << 24) + m24; /* (s + 1) in Q24, 0..2^25 */
    return (int32_t)((qibl_mul_u32_u64(s1, n) + (1u << 16)) >> 17) - 128;
}

void qibl_ylut_lookup(const qibl_ylut_t *t, const qibl_q30_t u[3], uint32_t k, int32_t *y14)
{
    int32_t ax = abs32(u[0]), ay = abs32(u[1]), az = abs32(u[2]);
    uint32_t f;
    int32_t sc, tc, ma;
    if (ax >= ay && ax >= az) {
        ma = ax;
        f = u[0] >= 0 ? 0u : 1u;
        sc = u[0] >= 0 ? -u[2] : u[2];
        tc = -u[1];
    } else if (ay >= az) {
        ma = ay;
        f = u[1] >= 0 ? 2u : 3u;
        sc = u[0];
        tc = u[1] >= 0 ? u[2] : -u[2];
    } else {
        ma = az;
        f = u[2] >= 0 ? 4u : 5u;
        sc = u[2] >= 0 ? u[0] : -u[0];
        tc = -u[1];
    }
    unsigned ie;
    uint32_t iy = qibl_rsqrt_u64(qibl_mul_u32_u64((uint32_t)ma, (uint32_t)ma), &ie); /* 1/ma */
    const uint32_t n = t->face_size;
    int32_t fu = face_coord(sc, iy, ie, n), fv = face_coord(tc, iy, ie, n);
    int32_t iu = qibl_asr_s32(fu, 8), iv = qibl_asr_s32(fv, 8);
    int32_t wu = fu - iu * 256, wv = fv - iv * 256; /* 0..255 */
    /* clamp at the face's edges (no cross-face filtering) */
    if (iu < 0)
        iu = 0, wu = 0;
    if (iu >= (int32_t)n - 1)
        iu = (int32_t)n - 1, wu = 0;
    if (iv < 0)
        iv = 0, wv = 0;
    if (iv >= (int32_t)n - 1)
        iv = (int32_t)n - 1, wv = 0;
    uint32_t du = wu ? 1u : 0u, dv = wv ? (uint32_t)n : 0u;
    size_t stride = (size_t)t->k * 2u;
    const uint8_t *p00 = t->values + (((size_t)f * n + (uint32_t)iv) * n + (uint32_t)iu) * stride;
    const uint8_t *p10 = p00 + du * stride, *p01 = p00 + dv * stride, *p11 = p01 + du * stride;
    int32_t w00 = (256 - wu) * (256 - wv), w10 = wu * (256 - wv), w01 = (256 - wu) * wv, w11 = wu * wv;
    for (uint32_t i = 0; i < k; ++i) {
        /* |Y| <= 0.9 * 2^14 and the weights sum to 2^16: |sum| < 2^30 */
        int32_t s = w00 * qibl_load_s16le(p00 + 2u * i) + w10 * qibl_load_s16le(p10 + 2u * i) +
                    w01 * qibl_load_s16le(p01 + 2u * i) + w11 * qibl_load_s16le(p11 + 2u * i);
        y14[i] = qibl_asr_s32(s + 32768, 16);
    }
}

/* ---- point lights ---------------------------------------------------------------------------- */

#define DEC_MAX 4095 /* |decoded| bound: 25 * 4095 * 0.9 * 2^14 < 2^31 */

size_t qibl_shmap_point_workspace_size(const qibl_shmaps_t *m)
{
    if (qibl_shmap_check(m) != QIBL_OK)
        return 0u;
    return (size_t)m->k * m->channels * 256u * sizeof(int16_t);
}

qibl_status_t qibl_shmap_point_prepare(const qibl_shmaps_t *m, const qibl_pmap_t *p, const qibl_ylut_t *lut,
                                       const qibl_pointlight_t *light, void *ws, size_t ws_size,
                                       qibl_shmap_point_t *out)
{
    qibl_status_t st = qibl_shmap_check(m);
    if (st != QIBL_OK)
        return st;
    if (p == 0 || p->points == 0 || light == 0 || ws == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    if (p->width != m->width || p->height != m->height)
        return QIBL_E_SHMAP_MISMATCH;
    if (lut != 0 && (lut->values == 0 || lut->k < m->k || lut->face_size < 1u || lut->face_size > QIBL_ASSET_MAX_LUT))
        return QIBL_E_SHMAP_MISMATCH;
    if (light->rgb[0] < 0 || light->rgb[1] < 0 || light->rgb[2] < 0 || light->min_dist < 0 ||
        (light->falloff != QIBL_FALLOFF_INV_DIST && light->falloff != QIBL_FALLOFF_INV_DIST2))
        return QIBL_E_SHMAP_LIGHT;
    if (ws_size < qibl_shmap_point_workspace_size(m))
        return QIBL_E_WORKSPACE;
    /* built in place (nothing below can fail): a struct copy would be a memcpy call */
    int16_t *dec = (int16_t *)ws;
    for (uint32_t ch = 0; ch < m->channels; ++ch) {
        /* one unit per channel: the largest |bias + scale c| over maps and bytes maps to <= 4095 */
        uint64_t maxv = 0u;
        for (uint32_t i = 0; i < m->k; ++i) {
            int64_t b = qibl_shmaps_bias(m, i, ch), e = b + qibl_mul_s32_s64(qibl_shmaps_scale(m, i, ch), 255);
            if (mag64(b) > maxv)
                maxv = mag64(b);
            if (mag64(e) > maxv)
                maxv = mag64(e);
        }
        unsigned s = 0u;
        while (qibl_shr_u64(maxv, s) > DEC_MAX - 1u)
            ++s;
        out->dec_shift[ch] = (int32_t)s;
        for (uint32_t i = 0; i < m->k; ++i) {
            int64_t b = qibl_shmaps_bias(m, i, ch);
            int32_t sc = qibl_shmaps_scale(m, i, ch);
            int16_t *d = dec + ((size_t)ch * m->k + i) * 256u;
            for (int32_t c = 0; c < 256; ++c) {
                int64_t v = b + qibl_mul_s32_s64(sc, c); /* |.| < 2^40 */
                d[c] = (int16_t)(s == 0u ? v : qibl_rshr_s64(v, s));
            }
        }
    }
    for (uint32_t ch = m->channels; ch < 3u; ++ch)
        out->dec_shift[ch] = out->dec_shift[0];
    out->maps = m;
    out->pmap = p;
    out->lut = lut;
    out->dec = dec;
    for (int j = 0; j < 3; ++j) {
        out->pos[j] = light->pos[j];
        out->rgb[j] = (uint32_t)light->rgb[j];
    }
    out->falloff = (uint32_t)light->falloff;
    uint32_t md = light->min_dist > 0 ? (uint32_t)light->min_dist : 256u; /* default 1/256 unit */
    out->min_d2 = qibl_mul_u32_u64(md, md);
    out->clamp_y = qibl_rsqrt_u64(out->min_d2, &out->clamp_e);
    out->bands = (uint32_t)bands_for(m->k);
    return QIBL_OK;
}

qibl_status_t qibl_shmap_point_span(const qibl_shmap_point_t *pt, uint32_t x0, uint32_t y, uint32_t n, int32_t *out)
{
    if (pt == 0 || out == 0 || pt->maps == 0)
        return QIBL_E_NULL_POINTER;
    const qibl_shmaps_t *m = pt->maps;
    if (y >= m->height || x0 > m->width || n > m->width - x0)
        return QIBL_E_SHMAP_BOUNDS;
    const uint32_t k = m->k;
    const size_t off = (size_t)y * m->width + x0;
    const uint8_t *pp = pt->pmap->points + off * 12u;
    for (uint32_t px = 0; px < n; ++px, pp += 12) {
        int32_t *o = out + 3u * px;
        /* L = S - P, halved once if it does not fit int32 (both are int32, so once is enough) */
        int64_t l64[3];
        int32_t l[3];
        unsigned r0 = 0u;
        for (int j = 0; j < 3; ++j) {
            l64[j] = pt->pos[j] - (int64_t)qibl_load_s32le(pp + 4 * j);
            if (l64[j] > INT32_MAX || l64[j] < -(int64_t)INT32_MAX)
                r0 = 1u;
        }
        for (int j = 0; j < 3; ++j)
            l[j] = (int32_t)qibl_asr_s64(l64[j], r0);
        uint64_t d2 = 0u;
        for (int j = 0; j < 3; ++j) {
            uint32_t a = l[j] < 0 ? 0u - (uint32_t)l[j] : (uint32_t)l[j];
            d2 += qibl_mul_u32_u64(a, a);
        }
        if (d2 == 0u) { /* the light sits on this pixel's surface point: no direction */
            o[0] = o[1] = o[2] = 0;
            continue;
        }
        unsigned e;
        uint32_t iy = qibl_rsqrt_u64(d2, &e); /* 1/|l| = iy / 2^e */
        qibl_q30_t u[3];
        for (int j = 0; j < 3; ++j) {
            uint32_t a = l[j] < 0 ? 0u - (uint32_t)l[j] : (uint32_t)l[j];
            unsigned sh = e - 30u; /* 1..32 */
            uint64_t q = qibl_shr_u64(qibl_mul_u32_u64(a, iy) + qibl_shr_u64((uint64_t)1 << 63, 64u - sh), sh);
            int32_t mq = (int32_t)(q > 0x40000000u ? 0x40000000u : q);
            u[j] = l[j] < 0 ? -mq : mq;
        }
        int32_t y14[QIBL_SH_MAX_COUNT];
        if (pt->lut) {
            qibl_ylut_lookup(pt->lut, u, k, y14);
        } else {
            qibl_q30_t yq[QIBL_SH_MAX_COUNT];
            (void)qibl_sh_eval_unit(u, (int)pt->bands, yq);
            for (uint32_t i = 0; i < k; ++i)
                y14[i] = qibl_rshr_s64(yq[i], 16);
        }
        /* distance clamp: compare |L|^2 in (2^-16)^2 units with min_dist^2 */
        uint32_t ay = iy;
        unsigned ae = e, rr = r0;
        if ((r0 ? d2 < (pt->min_d2 >> 2) : d2 < pt->min_d2)) {
            ay = pt->clamp_y, ae = pt->clamp_e, rr = 0u;
        }
        int32_t s_right; /* out = T f / 2^s_right, see shmap.h for the derivation of the exponents */
        uint32_t a;
        if (pt->falloff == QIBL_FALLOFF_INV_DIST) {
            a = ay;
            s_right = (int32_t)ae + (int32_t)rr - 10;
        } else {
            a = (uint32_t)(qibl_mul_u32_u64(ay, ay) >> 31);
            s_right = 2 * (int32_t)ae + 2 * (int32_t)rr - 57;
        }
        for (uint32_t ch = 0; ch < 3u; ++ch) {
            uint32_t src = m->channels == 3u ? ch : 0u;
            const int16_t *dec = pt->dec + (size_t)src * k * 256u;
            const uint8_t *plane0 = qibl_shmaps_plane(m, 0, src) + off + px;
            size_t pstride = (size_t)m->width * m->height * m->channels;
            int32_t t = 0;
            for (uint32_t i = 0; i < k; ++i)
                t += y14[i] * dec[i * 256u + plane0[i * pstride]];
            /* f = rgb a / 2^32 <= 2^30, so T f <= 2^61 */
            int32_t f = (int32_t)(qibl_mul_u32_u64(pt->rgb[ch], a) >> 32);
            int64_t prod = qibl_mul_s32_s64(t, f);
            int32_t sr = s_right - pt->dec_shift[src];
            if (sr > 0)
                o[ch] = sr > 62 ? 0 : qibl_rshr_s64(prod, (unsigned)sr);
            else if (prod > INT32_MAX || prod < INT32_MIN || sr < -30)
                o[ch] = prod > 0 ? INT32_MAX : prod < 0 ? INT32_MIN : 0;
            else
                o[ch] = qibl_sat_s32(qibl_mul_s32_s64((int32_t)prod, (int32_t)1 << -sr));
        }
    }
    return QIBL_OK;
}

#else
typedef int qibl_shmap_disabled_t; /* ISO C forbids an empty translation unit */
#endif /* QIBL_USE_SHMAP */
