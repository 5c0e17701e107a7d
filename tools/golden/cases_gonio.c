/*
 * golden/cases_gonio.c - gonio_*: goniometric lamps (qibl/gonio.h): lookups through an integer-made
 * table in several lamp frames over directions of every magnitude (zero, axes, diagonals, 2^62),
 * the refusals' statuses, and spans of a P map scaled toward each pixel.
 */
#include "golden/casesi.h"

#include <stdlib.h>

#include "qibl/gonio.h"

#if QIBL_USE_GONIO

#define GN 17u

static void make_table(uint16_t *t, uint32_t n, uint64_t seed)
{
    qtool_grng r = {seed};
    for (uint32_t i = 0; i < n * n; ++i)
        t[i] = (uint16_t)(qtool_grng_u32(&r) % (QIBL_GONIO_ONE + 1u));
    t[0] = 0, t[n * n - 1] = (uint16_t)QIBL_GONIO_ONE;
}

/* an int64 with a random bit length 0..62 and sign */
static int64_t any_s64(qtool_grng *r)
{
    unsigned bits = (unsigned)(qtool_grng_next(r) % 63u);
    uint64_t v = bits ? qtool_grng_next(r) >> (64u - bits) : 0u;
    return qtool_grng_next(r) & 1u ? -(int64_t)v : (int64_t)v;
}

static int lookup_case(const qtool_goldens_sink_t *s, const char *name)
{
    static uint16_t t[GN * GN];
    make_table(t, GN, 0x6017);
    static const int32_t frames[][2][3] = {
        {{0, 0, 65536}, {0, 65536, 0}},               /* identity */
        {{0, -65536, 0}, {65536, 0, 0}},              /* a downlight: aim -y, C0 toward +x */
        {{3 * 65536, -65536, 2 * 65536}, {0, 65536, 0}}, /* tilted */
        {{1, 0, 0}, {5, 0, 1}},                       /* tiny vectors, up with a part along the aim */
        {{-2147483647 - 1, 2147483647, 7}, {0, 0, -2147483647 - 1}},
    };
    qtool_gbuf b = {0};
    qtool_grng r = {0x60710};
    for (size_t f = 0; f < sizeof frames / sizeof frames[0]; ++f) {
        qibl_gonio_t g;
        qibl_status_t st = qibl_gonio_init(&g, GN, t, frames[f][0], frames[f][1]);
        if (st != QIBL_OK) {
            qtool_gbuf_free(&b);
            return qtool_gcase_status_error(s, name, "qibl_gonio_init", st);
        }
        for (int k = 0; k < 3; ++k) {
            qtool_gbuf_s32(&b, g.x[k]);
            qtool_gbuf_s32(&b, g.y[k]);
            qtool_gbuf_s32(&b, g.z[k]);
        }
        static const int64_t fixed[][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, 0, 0}, {0, -1, 0},
                                           {0, 0, -1}, {1, 1, 1}, {-1, -1, -1}, {4611686018427387904, 0, -1},
                                           {-4611686018427387903, 4611686018427387903, 4611686018427387903}};
        for (size_t i = 0; i < sizeof fixed / sizeof fixed[0]; ++i)
            qtool_gbuf_u32(&b, qibl_gonio_lookup(&g, fixed[i]));
        for (int i = 0; i < 2000; ++i) {
            int64_t d[3] = {any_s64(&r), any_s64(&r), any_s64(&r)};
            qtool_gbuf_u32(&b, qibl_gonio_lookup(&g, d));
        }
    }
    return qtool_gbuf_emit(s, name, &b);
}

/* a status as a number that does not move when other modules add statuses before gonio's */
static uint32_t code(qibl_status_t st)
{
    static const qibl_status_t k[] = {QIBL_OK, QIBL_E_NULL_POINTER, QIBL_E_GONIO_SIZE, QIBL_E_GONIO_TABLE,
                                      QIBL_E_GONIO_AIM, QIBL_E_GONIO_UP, QIBL_E_GONIO_BOUNDS};
    for (uint32_t i = 0; i < sizeof k / sizeof k[0]; ++i)
        if (st == k[i])
            return i;
    return 255u;
}

static int refusals_case(const qtool_goldens_sink_t *s, const char *name)
{
    static uint16_t t[GN * GN];
    make_table(t, GN, 1);
    const int32_t z[3] = {0, 0, 65536}, y[3] = {0, 65536, 0}, zero[3] = {0, 0, 0}, par[3] = {0, 0, -3};
    qibl_gonio_t g;
    qtool_gbuf b = {0};
    qtool_gbuf_u32(&b, code(qibl_gonio_init(&g, 1, t, z, y)));
    qtool_gbuf_u32(&b, code(qibl_gonio_init(&g, QIBL_GONIO_MAX_N + 1u, t, z, y)));
    qtool_gbuf_u32(&b, code(qibl_gonio_init(&g, GN, t, zero, y)));
    qtool_gbuf_u32(&b, code(qibl_gonio_init(&g, GN, t, z, zero)));
    qtool_gbuf_u32(&b, code(qibl_gonio_init(&g, GN, t, z, par)));
    t[5] = (uint16_t)(QIBL_GONIO_ONE + 1u);
    qtool_gbuf_u32(&b, code(qibl_gonio_init(&g, GN, t, z, y)));
    for (uint32_t n = 0; n < 300u; n += 7u)
        qtool_gbuf_u32(&b, (uint32_t)qibl_gonio_table_size(n));
    return qtool_gbuf_emit(s, name, &b);
}

static int span_case(const qtool_goldens_sink_t *s, const char *name)
{
    enum { W = 48, H = 3 };
    static uint16_t t[GN * GN];
    static uint8_t pts[12u * W * H];
    make_table(t, GN, 0x5BA7);
    qtool_grng r = {0x5BA9};
    for (uint32_t i = 0; i < W * H; ++i) {
        /* points on a box around the lamp, a few units away, Q16.16 */
        qtool_gput_s32(pts + 12u * i, qtool_gs32((uint32_t)(qtool_grng_u32(&r) % (8u << 16)) - (4u << 16)));
        qtool_gput_s32(pts + 12u * i + 4u, qtool_gs32((uint32_t)(qtool_grng_u32(&r) % (8u << 16)) - (4u << 16)));
        qtool_gput_s32(pts + 12u * i + 8u, qtool_gs32((uint32_t)(qtool_grng_u32(&r) % (8u << 16)) - (4u << 16)));
    }
    qibl_pmap_t pm = {W, H, pts};
    const int32_t aim[3] = {0, -65536, 0}, up[3] = {65536, 0, 0};
    const qibl_q16_t pos[3] = {1 << 14, 2 << 16, -(1 << 15)};
    qibl_gonio_t g;
    qibl_status_t st = qibl_gonio_init(&g, GN, t, aim, up);
    if (st != QIBL_OK)
        return qtool_gcase_status_error(s, name, "qibl_gonio_init", st);
    qtool_gbuf b = {0};
    int32_t out[3 * W];
    for (uint32_t y = 0; y < H; ++y) {
        for (int i = 0; i < 3 * W; ++i)
            out[i] = i % 7 == 0 ? qtool_gs32(qtool_grng_u32(&r)) : (int32_t)(qtool_grng_u32(&r) >> 8);
        st = qibl_gonio_scale_span(&g, &pm, pos, 0, y, W, out);
        if (st != QIBL_OK) {
            qtool_gbuf_free(&b);
            return qtool_gcase_status_error(s, name, "qibl_gonio_scale_span", st);
        }
        for (int i = 0; i < 3 * W; ++i)
            qtool_gbuf_s32(&b, out[i]);
    }
    return qtool_gbuf_emit(s, name, &b);
}

int qtool_goldens_gonio(const qtool_goldens_sink_t *s)
{
    return lookup_case(s, "gonio_lookup") + refusals_case(s, "gonio_refusals") + span_case(s, "gonio_span");
}

#endif /* QIBL_USE_GONIO */
