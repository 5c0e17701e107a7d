/*
 * golden/cases_probe.c - probe_*: SH projection of integer-made probes (every pixel format, sizes
 * from 1 x 1, both the folded (W % 4 == 0) and the direct path, irradiance and windows, bad pixels,
 * rows in reverse order) and SH rotation (exact rational rotations from integer quaternions, the
 * axis quarter turns, identity) applied to integer-made coefficient vectors. Each entry records the
 * status and the output, which starts as a guard pattern so that failing calls are hashed too.
 */
#include "golden/casesi.h"

#include <stdlib.h>

#include "qibl/probe.h"
#include "qibl/sh.h"

#if QIBL_USE_PROBE /* the group exists only when config.h builds the module */

#define GUARD 0x5A5A5A5Au

static void put_coeffs(qtool_gbuf *b, qibl_status_t st, const qibl_probe_coeffs_t *c)
{
    qtool_gbuf_u8(b, (uint32_t)st);
    qtool_gbuf_s32(b, c->bands);
    qtool_gbuf_s32(b, c->exp);
    for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i < QIBL_SH_MAX_COUNT; ++i)
            qtool_gbuf_s32(b, c->c[ch][i]);
}

static void guard(qibl_probe_coeffs_t *c)
{
    c->bands = c->exp = qtool_gs32(GUARD);
    for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i < QIBL_SH_MAX_COUNT; ++i)
            c->c[ch][i] = qtool_gs32(GUARD);
}

/* RGBE probe from integers: hash-noise mantissas, exponents 110..140 with a bright spot (2^16 x) */
static uint8_t *make_rgbe(uint64_t seed, uint32_t w, uint32_t h)
{
    qtool_grng r = {seed};
    uint8_t *px = malloc(4 * (size_t)w * h);
    if (px == NULL)
        return NULL;
    const uint32_t su = qtool_grng_u32(&r) % w, sv = qtool_grng_u32(&r) % h;
    for (uint32_t v = 0; v < h; ++v)
        for (uint32_t u = 0; u < w; ++u) {
            uint8_t *q = px + 4 * ((size_t)v * w + u);
            uint32_t n = qtool_grng_u32(&r);
            q[0] = (uint8_t)(128 | n), q[1] = (uint8_t)(128 | (n >> 8)), q[2] = (uint8_t)(n >> 16);
            q[3] = (uint8_t)(125 + (n >> 28) + (u == su && v == sv ? 16 : 0));
            if ((n >> 24 & 15u) == 0u)
                q[3] = 0; /* some black pixels */
        }
    return px;
}

/* the same pixels as binary32 bit patterns (exact: m 2^(E-136) with m < 2^8) */
static uint32_t f32_bits(uint32_t m, uint32_t e)
{
    if (m == 0u || e == 0u)
        return 0u;
    unsigned bl = 0;
    while ((m >> bl) > 1u)
        ++bl; /* m in [2^bl, 2^(bl+1)) */
    uint32_t frac = (m << (23u - bl)) & 0x7FFFFFu;
    return ((uint32_t)((int32_t)e - 136 + (int32_t)bl + 127) << 23) | frac;
}

static int project_case(const qtool_goldens_sink_t *s, const char *name, const qibl_lightprobe_image_t *img,
                        int reverse)
{
    qtool_gbuf b = {0};
    static const qibl_probe_sh_opts_t opts[] = {
        {0, QIBL_PROBE_WINDOW_NONE, 0}, {1, QIBL_PROBE_WINDOW_NONE, 0}, {0, QIBL_PROBE_WINDOW_HANN, 0},
        {1, QIBL_PROBE_WINDOW_LANCZOS, 0}};
    size_t n = qibl_probe_sh_workspace_size(img->width, img->height);
    void *ws = malloc(n ? n : 1);
    if (ws == NULL)
        return qtool_gcase_oom(s, name);
    for (int bands = 1; bands <= QIBL_SH_MAX_BANDS; bands += bands == 1 ? 2 : 2) {
        qibl_probe_sh_t ps;
        qibl_status_t st = qibl_probe_sh_begin(&ps, img->width, img->height, img->format, img->frac_bits, bands,
                                               ws, n);
        const size_t pb = img->format >= QIBL_LIGHTPROBE_LINEAR_I32 ? 12u : 4u;
        for (uint32_t k = 0; k < img->height && st == QIBL_OK; ++k) {
            uint32_t v = reverse ? img->height - 1u - k : k;
            st = qibl_probe_sh_add_row(&ps, v, (const uint8_t *)img->pixels + (size_t)v * img->width * pb);
            qtool_gbuf_u8(&b, (uint32_t)st);
        }
        for (size_t o = 0; o < sizeof opts / sizeof opts[0]; ++o) {
            qibl_probe_coeffs_t c;
            guard(&c);
            qibl_status_t fs = st == QIBL_OK ? qibl_probe_sh_finish(&ps, &opts[o], &c) : st;
            put_coeffs(&b, fs, &c);
        }
    }
    free(ws);
    return qtool_gbuf_emit(s, name, &b);
}

static qibl_lightprobe_image_t image(const void *px, uint32_t w, uint32_t h, qibl_lightprobe_format_t f, int32_t fb)
{
    qibl_lightprobe_image_t img = {px, w, h, 0, f, fb};
    return img;
}

/* the status and coefficients of a w x h RGBE probe's projection at every band (workspace on the heap) */
static void put_rgbe_projection(qtool_gbuf *b, const uint8_t *px, uint32_t w, uint32_t h)
{
    qibl_lightprobe_image_t img = image(px, w, h, QIBL_LIGHTPROBE_RGBE, 0);
    qibl_probe_coeffs_t c;
    guard(&c);
    size_t n = qibl_probe_sh_workspace_size(img.width, img.height);
    void *ws = malloc(n);
    qibl_status_t st = ws ? qibl_probe_sh_project(&img, QIBL_SH_MAX_BANDS, NULL, ws, n, &c) : QIBL_E_WORKSPACE;
    put_coeffs(b, st, &c);
    free(ws);
}

static int projections(const qtool_goldens_sink_t *s)
{
    int bad = 0;
    /* sizes: 1 x 1, odd, W % 4 == 0 and not, a 2:1 probe */
    static const uint32_t sz[][2] = {{1, 1}, {2, 1}, {3, 7}, {4, 2}, {5, 3}, {12, 6}, {30, 15}, {64, 32}};
    qtool_gbuf all = {0};
    for (size_t i = 0; i < sizeof sz / sizeof sz[0]; ++i) {
        uint8_t *px = make_rgbe(100 + i, sz[i][0], sz[i][1]);
        if (px == NULL)
            return qtool_gcase_oom(s, "probe_sh_sizes");
        put_rgbe_projection(&all, px, sz[i][0], sz[i][1]);
        free(px);
    }
    bad += qtool_gbuf_emit(s, "probe_sh_sizes", &all);

    /* widths for the vector paths (QIBL_CONFIG_SIMD): fewer than 8 column pairs, 8, several steps
     * and flushes, a scalar tail, an odd quarter width; every path must give these bytes */
    static const uint32_t wd[] = {16, 64, 68, 192, 200, 204, 1028};
    qtool_gbuf wide = {0};
    for (size_t i = 0; i < sizeof wd / sizeof wd[0]; ++i) {
        uint8_t *px = make_rgbe(200 + i, wd[i], 3);
        if (px == NULL)
            return qtool_gcase_oom(s, "probe_sh_widths");
        for (uint32_t p = 5; p < wd[i] * 3u; p += 13) /* unlit pixels of huge exponent */
            px[4 * p] = px[4 * p + 1] = px[4 * p + 2] = 0, px[4 * p + 3] = 255;
        put_rgbe_projection(&wide, px, wd[i], 3);
        free(px);
    }
    bad += qtool_gbuf_emit(s, "probe_sh_widths", &wide);

    const uint32_t w = 64, h = 32;
    uint8_t *px = make_rgbe(7, w, h);
    uint32_t *f32 = malloc(12 * (size_t)w * h), *i32 = malloc(12 * (size_t)w * h);
    if (px == NULL || f32 == NULL || i32 == NULL) {
        free(px), free(f32), free(i32);
        return bad + qtool_gcase_oom(s, "probe_sh_rgbe64x32");
    }
    for (size_t p = 0; p < (size_t)w * h; ++p)
        for (int c = 0; c < 3; ++c) {
            uint32_t m = px[4 * p + (size_t)c], e = px[4 * p + 3];
            f32[3 * p + (size_t)c] = f32_bits(m, e);
            /* int32 with 3 fraction bits: m 2^(E - 133), truncated (E - 133 in -8..23) */
            int32_t k = (int32_t)e - 133;
            i32[3 * p + (size_t)c] = e == 0u ? 0u : k >= 0 ? m << k : m >> -k;
        }
    qibl_lightprobe_image_t img = image(px, w, h, QIBL_LIGHTPROBE_RGBE, 0);
    bad += project_case(s, "probe_sh_rgbe64x32", &img, 0);
    bad += project_case(s, "probe_sh_rgbe64x32_reverse_rows", &img, 1);
    img = image(f32, w, h, QIBL_LIGHTPROBE_LINEAR_F32, 0);
    bad += project_case(s, "probe_sh_f32_64x32", &img, 0);
    img = image(i32, w, h, QIBL_LIGHTPROBE_LINEAR_I32, 3);
    bad += project_case(s, "probe_sh_i32q3_64x32", &img, 0);
    /* sRGBE: the same bytes read as sRGBE codes */
    img = image(px, w, h, QIBL_LIGHTPROBE_SRGBE, 0);
    bad += project_case(s, "probe_sh_srgbe64x32", &img, 0);
    /* direct path: width not a multiple of 4 */
    img = image(px, w - 1, h, QIBL_LIGHTPROBE_RGBE, 0); /* rows tightly packed at 63 pixels */
    bad += project_case(s, "probe_sh_rgbe63x32", &img, 0);
    free(px), free(f32), free(i32);
    return bad;
}

/* bad pixels, black probe, poles, argument errors: statuses and what gets written */
static int hard_cases(const qtool_goldens_sink_t *s)
{
    qtool_gbuf b = {0};
    enum { W = 8, H = 4 };
    uint32_t f[3 * W * H];
    static const uint32_t bads[] = {0x7FC00000u, 0x7F800000u, 0xFF800000u, 0x80000001u, 0xBF800000u, 0x00000001u,
                                    0x7F7FFFFFu, 0x80000000u};
    size_t n = qibl_probe_sh_workspace_size(W, H);
    void *ws = malloc(n);
    if (ws == NULL)
        return qtool_gcase_oom(s, "probe_sh_hard");
    for (size_t k = 0; k < sizeof bads / sizeof bads[0]; ++k) {
        for (int i = 0; i < 3 * W * H; ++i)
            f[i] = 0x3F800000u; /* 1.0 */
        f[3 * (W * 2 + 5) + 1] = bads[k];
        qibl_lightprobe_image_t img = image(f, W, H, QIBL_LIGHTPROBE_LINEAR_F32, 0);
        qibl_probe_coeffs_t c;
        guard(&c);
        put_coeffs(&b, qibl_probe_sh_project(&img, 3, NULL, ws, n, &c), &c);
    }
    /* black, then only the top row lit (north pole), then only the bottom row */
    for (int k = 0; k < 3; ++k) {
        for (int i = 0; i < 3 * W * H; ++i)
            f[i] = 0u;
        for (int u = 0; k && u < W; ++u)
            for (int c = 0; c < 3; ++c)
                f[3 * ((k == 1 ? 0 : H - 1) * W + u) + c] = 0x40000000u + (uint32_t)c;
        qibl_lightprobe_image_t img = image(f, W, H, QIBL_LIGHTPROBE_LINEAR_F32, 0);
        qibl_probe_coeffs_t c;
        guard(&c);
        put_coeffs(&b, qibl_probe_sh_project(&img, 5, NULL, ws, n, &c), &c);
    }
    /* argument errors */
    qibl_probe_sh_t ps;
    qtool_gbuf_u8(&b, (uint32_t)qibl_probe_sh_begin(&ps, 0, 4, QIBL_LIGHTPROBE_RGBE, 0, 5, ws, n));
    qtool_gbuf_u8(&b, (uint32_t)qibl_probe_sh_begin(&ps, 8, 4, QIBL_LIGHTPROBE_RGBE, 0, 6, ws, n));
    qtool_gbuf_u8(&b, (uint32_t)qibl_probe_sh_begin(&ps, 8, 4, QIBL_LIGHTPROBE_FORMAT_COUNT, 0, 5, ws, n));
    qtool_gbuf_u8(&b, (uint32_t)qibl_probe_sh_begin(&ps, 8, 4, QIBL_LIGHTPROBE_LINEAR_I32, 129, 5, ws, n));
    qtool_gbuf_u8(&b, (uint32_t)qibl_probe_sh_begin(&ps, 8, 4, QIBL_LIGHTPROBE_RGBE, 0, 5, ws, n - 1));
    qtool_gbuf_u8(&b, (uint32_t)qibl_probe_sh_begin(&ps, 32768, 32768, QIBL_LIGHTPROBE_RGBE, 0, 5, ws, n));
    qtool_gbuf_u8(&b, (uint32_t)qibl_probe_sh_begin(&ps, W, H, QIBL_LIGHTPROBE_LINEAR_F32, 0, 5, ws, n));
    qtool_gbuf_u8(&b, (uint32_t)qibl_probe_sh_add_row(&ps, H, f));
    qtool_gbuf_u8(&b, (uint32_t)qibl_probe_sh_add_row(&ps, 0, f));
    qtool_gbuf_u8(&b, (uint32_t)qibl_probe_sh_add_row(&ps, 0, f));
    qibl_probe_coeffs_t c;
    guard(&c);
    put_coeffs(&b, qibl_probe_sh_finish(&ps, NULL, &c), &c);
    free(ws);
    return qtool_gbuf_emit(s, "probe_sh_hard", &b);
}

/* rotations: R from the integer quaternion (a, b, c, d), entries integer / n with n = a^2+b^2+c^2+d^2,
 * rounded to Q2.30 with integer division */
static void quat_rot(int32_t a, int32_t b, int32_t c, int32_t d, qibl_q30_t r[3][3])
{
    int64_t n = (int64_t)a * a + (int64_t)b * b + (int64_t)c * c + (int64_t)d * d;
    int64_t m[3][3] = {
        {a * a + b * b - c * c - d * d, 2 * (b * c - a * d), 2 * (b * d + a * c)},
        {2 * (b * c + a * d), a * a - b * b + c * c - d * d, 2 * (c * d - a * b)},
        {2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d},
    };
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            int64_t x = m[i][j] * ((int64_t)1 << 30), q = (x < 0 ? -x : x) + n / 2; /* |x| < 2^61 */
            q /= n;
            r[i][j] = (int32_t)(x < 0 ? -q : q);
        }
}

static int rotations(const qtool_goldens_sink_t *s)
{
    static const int32_t quats[][4] = {
        {1, 0, 0, 0}, {1, 1, 0, 0}, {1, 0, 1, 0}, {1, 0, 0, 1}, {0, 1, 0, 0}, {0, 0, 0, 1},
        {3, 1, -2, 5}, {7, -3, 2, 1}, {1, 2, 3, 4}, {-5, 4, 1, -2}, {100, 1, 0, 0}, {2, 9, -6, 3}};
    qtool_gbuf b = {0};
    qtool_grng r = {0x707};
    for (size_t q = 0; q < sizeof quats / sizeof quats[0]; ++q) {
        qibl_q30_t m[3][3];
        quat_rot(quats[q][0], quats[q][1], quats[q][2], quats[q][3], m);
        for (int bands = 1; bands <= QIBL_SH_MAX_BANDS; ++bands) {
            qibl_sh_rotation_t rot;
            rot.bands = qtool_gs32(GUARD);
            for (int i = 0; i < QIBL_SH_ROT_ENTRIES; ++i)
                rot.d[i] = qtool_gs32(GUARD);
            qibl_status_t st = qibl_sh_rotation_init(&rot, (const qibl_q30_t(*)[3])m, bands);
            qtool_gbuf_u8(&b, (uint32_t)st);
            qtool_gbuf_s32(&b, rot.bands);
            for (int i = 0; i < QIBL_SH_ROT_ENTRIES; ++i)
                qtool_gbuf_s32(&b, rot.d[i]);
            int32_t in[QIBL_SH_MAX_COUNT], out[QIBL_SH_MAX_COUNT];
            for (int i = 0; i < QIBL_SH_MAX_COUNT; ++i)
                in[i] = qtool_gs32(qtool_grng_u32(&r) >> 2) - (1 << 29), out[i] = qtool_gs32(GUARD);
            qtool_gbuf_u8(&b, (uint32_t)qibl_sh_rotate(&rot, in, out));
            for (int i = 0; i < QIBL_SH_MAX_COUNT; ++i)
                qtool_gbuf_s32(&b, out[i]);
        }
    }
    /* not rotations: a scaled matrix, a reflection, a shear */
    qibl_q30_t m[3][3] = {{1 << 30, 0, 0}, {0, 1 << 30, 0}, {0, 0, 1 << 30}};
    qibl_sh_rotation_t rot;
    rot.bands = 77;
    m[2][2] = -(1 << 30);
    qtool_gbuf_u8(&b, (uint32_t)qibl_sh_rotation_init(&rot, (const qibl_q30_t(*)[3])m, 5));
    m[2][2] = (1 << 30) + (1 << 15);
    qtool_gbuf_u8(&b, (uint32_t)qibl_sh_rotation_init(&rot, (const qibl_q30_t(*)[3])m, 5));
    m[2][2] = 1 << 30, m[0][1] = 1 << 15;
    qtool_gbuf_u8(&b, (uint32_t)qibl_sh_rotation_init(&rot, (const qibl_q30_t(*)[3])m, 5));
    qtool_gbuf_s32(&b, rot.bands);
    return qtool_gbuf_emit(s, "probe_sh_rotate", &b);
}

int qtool_goldens_probe(const qtool_goldens_sink_t *s)
{
    return projections(s) + hard_cases(s) + rotations(s);
}

#else
typedef int qtool_goldens_probe_disabled_t; /* ISO C forbids an empty translation unit */
#endif
