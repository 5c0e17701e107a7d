/*
 * golden/cases_lightprobe.c - lightprobe_*: light lists of integer-made probes in every pixel
 * format (median cut 64, adaptive 37, variance minimisation 37), and the sin row-weight table.
 * The four original probes were moved here from tests/lightprobe_test.c (same data, same hashes);
 * their binary32 and int32 copies, made there with ldexp/lrint, are made here with integers
 * (exact conversions either way, so the bytes are the same).
 * The real-probe goldens (lightprobe_real_*) need ../shared/fixtures/probes and a .hdr reader, so
 * they stay in tests/lightprobe_test.c and are not part of the runner.
 */
#include "golden/casesi.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "qibl/lightprobe.h"
#include "qibl/srgbe.h"

#if QIBL_USE_LIGHTPROBE && QIBL_USE_SRGBE /* the group exists only when config.h builds the modules */

size_t qtool_goldens_light_bytes(const qibl_lightprobe_light_t *L, const qibl_lightprobe_result_t *res, uint8_t *out)
{
    size_t n = 0;
    qtool_gput_u32(out + n, res->count), n += 4;
    qtool_gput_s32(out + n, res->rgb_exp), n += 4;
    for (uint32_t i = 0; i < res->count; ++i) {
        for (int c = 0; c < 3; ++c)
            qtool_gput_s32(out + n, L[i].dir[c]), n += 4;
        for (int c = 0; c < 3; ++c)
            qtool_gput_s32(out + n, L[i].rgb[c]), n += 4;
        qtool_gput_u32(out + n, L[i].u0), n += 4;
        qtool_gput_u32(out + n, L[i].v0), n += 4;
        qtool_gput_u32(out + n, L[i].u1), n += 4;
        qtool_gput_u32(out + n, L[i].v1), n += 4;
    }
    return n;
}

/* An integer-only probe: a smooth base of colours from integer gradients and hash noise, and spots
 * whose exponent rises by up to 12 (4096x) towards their centres. RGBE bytes. */
static uint8_t *int_probe(uint64_t seed, int w, int h, int spots)
{
    qtool_grng r = {seed};
    uint8_t *px = malloc(4 * (size_t)w * (size_t)h);
    if (px == NULL)
        return NULL;
    int su[8], sv[8];
    for (int k = 0; k < spots && k < 8; ++k)
        su[k] = (int)(qtool_grng_u32(&r) % (uint32_t)w), sv[k] = (int)(qtool_grng_u32(&r) % (uint32_t)h);
    for (int v = 0; v < h; ++v)
        for (int u = 0; u < w; ++u) {
            uint8_t *q = px + 4 * ((size_t)v * (size_t)w + (size_t)u);
            uint32_t n = qtool_grng_u32(&r);
            q[0] = (uint8_t)(128 + (u * 97 / w + (int)(n & 15)) % 128);
            q[1] = (uint8_t)(128 + (v * 89 / h + (int)((n >> 4) & 15)) % 128);
            q[2] = (uint8_t)(128 + ((u + v) * 61 / (w + h) + (int)((n >> 8) & 31)) % 128);
            int e = 124 + (v < h / 2);
            for (int k = 0; k < spots && k < 8; ++k) {
                int d2 = (u - su[k]) * (u - su[k]) + (v - sv[k]) * (v - sv[k]);
                int b = 12 - d2 / 3;
                if (b > e - 124)
                    e = 124 + b;
            }
            q[3] = (uint8_t)e;
        }
    return px;
}

/* The sun-and-sky probe, 256 x 128 RGBE: two exponents (sky brighter than ground), one hot pixel. */
static uint8_t *sunsky_probe(void)
{
    uint8_t *a = calloc(4 * 256 * 128, 1);
    if (a == NULL)
        return NULL;
    for (int v = 0; v < 128; ++v)
        for (int u = 0; u < 256; ++u) {
            uint8_t *q = a + 4 * (v * 256 + u);
            q[0] = (uint8_t)(140 + (u + v) % 50), q[1] = (uint8_t)(150 + v % 40), q[2] = (uint8_t)(200 + u % 50);
            q[3] = (uint8_t)(v < 64 ? 126 : 124);
        }
    uint8_t *q = a + 4 * (30 * 256 + 77);
    q[0] = 255, q[1] = 250, q[2] = 220, q[3] = 150;
    return a;
}

static unsigned bitlen(uint32_t m)
{
    unsigned n = 0;
    while (m)
        ++n, m >>= 1;
    return n;
}

/* The binary32 bit pattern of the RGBE value m * 2^(e - 136) (e = 0: zero), exactly: at most 8
 * significant bits, so no rounding. */
static uint32_t rgbe_f32_bits(uint32_t m, uint32_t e)
{
    if (m == 0 || e == 0)
        return 0;
    unsigned len = bitlen(m);
    int biased = (int)len + (int)e - 10; /* exponent (len - 1) + (e - 136), plus 127 */
    if (biased <= 0)                     /* subnormal: m * 2^(e - 136) in units of 2^-149 */
        return m << (e + 13);
    return (uint32_t)biased << 23 | ((m << (24 - len)) & 0x7FFFFFu);
}

/* round(m * 2^(e - 136 + frac)), ties to even (what lrint gives in the default rounding mode) */
static int32_t rgbe_fixed(uint32_t m, uint32_t e, int frac)
{
    if (m == 0 || e == 0)
        return 0;
    int sh = (int)e - 136 + frac;
    if (sh >= 0)
        return (int32_t)(m << sh); /* callers keep this below 2^31 */
    if (sh < -9)
        return 0;
    uint32_t q = m >> -sh, rem = m & ((1u << -sh) - 1u), half = 1u << (-sh - 1);
    return (int32_t)(q + (rem > half || (rem == half && (q & 1u))));
}

static int check_lights(const qtool_goldens_sink_t *s, const char *name, const qibl_lightprobe_t *lp,
                        qibl_lightprobe_method_t method, uint32_t n)
{
    static qibl_lightprobe_light_t L[256];
    static uint8_t buf[8 + 256 * 40];
    qibl_lightprobe_result_t res;
    qibl_lightprobe_opts_t o;
    memset(&o, 0, sizeof o);
    o.method = method;
    qibl_status_t st = qibl_lightprobe_lights(lp, &o, L, n, &res);
    if (st != QIBL_OK)
        return qtool_gcase_status_error(s, name, "qibl_lightprobe_lights", st);
    return qtool_gcase_emit(s, name, buf, qtool_goldens_light_bytes(L, &res, buf));
}

/* One light-list case: the probe's tables built for method alone (the lights depend on the
 * method, not on what else the tables hold), then the lights. The SAT's workspace when it can be
 * allocated, else the low-memory path's minimum (the GBA's heap): the same bytes either way. */
static int lights_case(const qtool_goldens_sink_t *s, const char *name, const qibl_lightprobe_image_t *img,
                       qibl_lightprobe_method_t method, uint32_t n)
{
    size_t wn = qibl_lightprobe_workspace_size(img->width, img->height, method);
    void *ws = wn ? malloc(wn) : NULL;
    if (ws == NULL) {
        wn = qibl_lightprobe_workspace_min(img->width, img->height, method);
        ws = wn ? malloc(wn) : NULL;
    }
    if (ws == NULL)
        return qtool_gcase_oom_size(s, name, wn);
    qibl_lightprobe_t lp;
    qibl_status_t st = qibl_lightprobe_build(&lp, img, method, ws, wn);
    int bad = st != QIBL_OK ? qtool_gcase_status_error(s, name, "qibl_lightprobe_build", st)
                            : check_lights(s, name, &lp, method, n);
    free(ws);
    return bad;
}

static int probe_cases(const qtool_goldens_sink_t *s, const char *probe, const qibl_lightprobe_image_t *img)
{
    static const struct {
        const char *suffix;
        qibl_lightprobe_method_t method;
        uint32_t n;
    } m[] = {{"mediancut64", QIBL_LIGHTPROBE_MEDIANCUT, 64},
             {"adaptive37", QIBL_LIGHTPROBE_ADAPTIVE, 37},
             {"varmin37", QIBL_LIGHTPROBE_VARMIN, 37}};
    char name[96];
    int bad = 0;
    for (size_t i = 0; i < sizeof m / sizeof m[0]; ++i) {
        snprintf(name, sizeof name, "lightprobe_%s_%s", probe, m[i].suffix);
        bad += img->pixels != NULL ? lights_case(s, name, img, m[i].method, m[i].n)
                                   : qtool_gcase_oom_size(s, name, img->stride * img->height);
    }
    return bad;
}

static qibl_lightprobe_image_t image(const void *px, uint32_t w, uint32_t h, qibl_lightprobe_format_t f)
{
    qibl_lightprobe_image_t img;
    memset(&img, 0, sizeof img);
    img.pixels = px, img.width = w, img.height = h, img.format = f;
    return img;
}

/* sin row weights of a few heights (rows 0 .. h/2 - 1 plus the middle: the table is symmetric) */
static int row_weights(const qtool_goldens_sink_t *s)
{
    static const uint32_t hs[] = {1, 2, 3, 5, 7, 64, 511, 512, 1000, 2048, 4096, 32768};
    const char *name = "lightprobe_row_weights";
    qtool_gbuf b = {0};
    for (size_t k = 0; k < sizeof hs / sizeof hs[0]; ++k)
        for (uint32_t v = 0; v < (hs[k] + 1) / 2; ++v) {
            uint32_t m;
            int32_t e;
            qibl_status_t st = qibl_lightprobe_row_weight(hs[k], v, &m, &e);
            if (st != QIBL_OK) {
                qtool_gbuf_free(&b);
                return qtool_gcase_status_error(s, name, "qibl_lightprobe_row_weight", st);
            }
            qtool_gbuf_u32(&b, m), qtool_gbuf_s32(&b, e);
        }
    return qtool_gbuf_emit(s, name, &b);
}

/* img over px, or, when px is NULL (its allocation failed), an image whose stride * height says
 * how many bytes it needed (probe_cases reports that for each of its cases) */
static qibl_lightprobe_image_t probe_image(const void *px, uint32_t w, uint32_t h, qibl_lightprobe_format_t f,
                                           size_t bytes_per_px)
{
    qibl_lightprobe_image_t img = image(px, w, h, f);
    if (px == NULL)
        img.stride = bytes_per_px * w;
    return img;
}

/* The probes are made one at a time and each case builds only the tables its method needs, so
 * the group runs where a few hundred KiB is all there is (a probe that cannot fit reports each
 * of its cases as out of memory, with the bytes it needed). */
int qtool_goldens_lightprobe(const qtool_goldens_sink_t *s)
{
    int bad = row_weights(s);
    /* (a) a sun and sky 256 x 128 RGBE, (b) an integer-made 100 x 50 with three hot spots, (c) the
     * same as (b) in sRGBE, (d) int32 with 12 fraction bits, (e) binary32 */
    enum { W = 100, H = 50, N = W * H };
    uint8_t *a = sunsky_probe();
    qibl_lightprobe_image_t img = probe_image(a, 256, 128, QIBL_LIGHTPROBE_RGBE, 4);
    bad += probe_cases(s, "sunsky256", &img);
    free(a);

    uint8_t *bp = int_probe(7, W, H, 3);
    uint32_t *fb = bp ? malloc(sizeof *fb * 3 * (size_t)N) : NULL;
    img = probe_image(bp, W, H, QIBL_LIGHTPROBE_RGBE, 4);
    bad += probe_cases(s, "random100", &img);
    if (fb != NULL)
        for (int i = 0; i < 3 * N; ++i)
            fb[i] = rgbe_f32_bits(bp[4 * (i / 3) + i % 3], bp[4 * (i / 3) + 3]);
    uint8_t *c = fb ? malloc(4 * (size_t)N) : NULL;
    qibl_status_t st = c ? qibl_srgbe_encode_f32_n(fb, N, c) : QIBL_OK;
    if (st != QIBL_OK) {
        bad += qtool_gcase_status_error(s, "lightprobe_random100_srgbe", "qibl_srgbe_encode_f32_n", st);
    } else {
        img = probe_image(c, W, H, QIBL_LIGHTPROBE_SRGBE, 4);
        bad += probe_cases(s, "random100_srgbe", &img);
    }
    free(c);
    int32_t *ib = bp ? malloc(sizeof *ib * 3 * (size_t)N) : NULL;
    if (ib != NULL)
        for (int i = 0; i < 3 * N; ++i)
            ib[i] = rgbe_fixed(bp[4 * (i / 3) + i % 3], bp[4 * (i / 3) + 3], 12);
    img = probe_image(ib, W, H, QIBL_LIGHTPROBE_LINEAR_I32, 12);
    img.frac_bits = 12;
    bad += probe_cases(s, "random100_i32q12", &img);
    free(ib);
    img = probe_image(fb, W, H, QIBL_LIGHTPROBE_LINEAR_F32, 12);
    bad += probe_cases(s, "random100_f32", &img);
    free(fb), free(bp);
    return bad;
}

#else
typedef int qtool_goldens_lightprobe_off; /* ISO C wants a declaration in every file */
#endif /* QIBL_USE_LIGHTPROBE */
