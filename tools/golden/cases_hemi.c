/*
 * golden/cases_hemi.c - hemi_*: the plane LUT and basis table of small configurations (16 x 16,
 * 32 x 32 and 64 x 64 masks), masks of integer-made triangles (random, crossing the horizon,
 * degenerate, 1 LSB above the receiver), their transfer vectors, and frames with the transfer
 * rotated out of them, and exported transfer (hemi_xfer) shaded by span. Each entry records the
 * status; outputs start as a guard pattern. Where the tables' workspace does not fit the heap the
 * tables case builds the same words a chunk at a time, and the cases that use the tables open the
 * port's prebuilt blob (the sink's hemi_tables: cartridge ROM on the GBA) when it has one.
 */
#include "golden/casesi.h"

#include <stdlib.h>

#include "qibl/asset.h"
#include "qibl/hemi.h"

#if QIBL_USE_HEMI /* the group exists only when config.h builds the module */

#define GUARD 0x5A5A5A5Au

/* The tables after init: disk, unblocked transfer, basis, LUT (the blob's payload less the
 * centres), the module's contract with every port. ok: init succeeded (h serves the other cases). */
static int tables_case(const qtool_goldens_sink_t *s, const char *name, int n, int face, qibl_hemi_t *h, void *ws,
                       size_t sz, int *ok)
{
    qibl_status_t st = qibl_hemi_init(h, n, face, ws, sz);
    if (st != QIBL_OK)
        return qtool_gcase_status_error(s, name, "qibl_hemi_init", st);
    *ok = 1;
    qtool_gbuf b = {0};
    const uint32_t lut_words = 3u * (uint32_t)face * (uint32_t)face * h->words;
    for (uint32_t i = 0; i < h->words; ++i)
        qtool_gbuf_u32(&b, h->disk[i]);
    for (uint32_t i = 0; i < 25u; ++i)
        qtool_gbuf_u32(&b, h->full[i]);
    for (uint32_t i = 0; i < (uint32_t)n * (uint32_t)n * 25u; ++i)
        qtool_gbuf_u32(&b, h->basis[i]);
    for (uint32_t i = 0; i < lut_words; ++i)
        qtool_gbuf_u32(&b, h->lut[i]);
    return qtool_gbuf_emit(s, name, &b);
}

#if QIBL_USE_ASSET
/* The same words when the workspace does not fit the heap: the blob's words from the disk to the
 * LUT's end, built a chunk at a time (qibl_hemi_tables_build) into a 16 KiB buffer */
static int tables_chunked_case(const qtool_goldens_sink_t *s, const char *name, int n, int face)
{
    enum { CHUNK = 4096 }; /* words */
    uint32_t *buf = malloc(CHUNK * sizeof(uint32_t));
    if (buf == NULL)
        return qtool_gcase_oom_size(s, name, CHUNK * sizeof(uint32_t));
    const uint32_t un = (uint32_t)n, uf = (uint32_t)face, words = QIBL_HEMI_MASK_WORDS(un);
    const uint32_t first = QIBL_HEMI_TABLES_HEADER_SIZE / 4u, end = first + words + 25u + 25u * un * un + 3u * uf * uf * words;
    qtool_gbuf b = {0};
    for (uint32_t pos = first; pos < end;) {
        const uint32_t cnt = end - pos < CHUNK ? end - pos : CHUNK;
        qibl_status_t st = qibl_hemi_tables_build(n, face, pos, cnt, buf);
        if (st != QIBL_OK) {
            free(buf);
            qtool_gbuf_free(&b);
            return qtool_gcase_status_error(s, name, "qibl_hemi_tables_build", st);
        }
        for (uint32_t i = 0; i < cnt; ++i)
            qtool_gbuf_u32(&b, buf[i]);
        pos += cnt;
    }
    free(buf);
    return qtool_gbuf_emit(s, name, &b);
}
#endif

static int masks_case(const qtool_goldens_sink_t *s, const char *name, const qibl_hemi_t *h, uint64_t seed)
{
    enum { NV = 48, NT = 40 };
    int32_t v[NV][3];
    uint32_t tri[NT][3];
    qtool_grng r = {seed};
    for (int i = 0; i < NV; ++i)
        for (int k = 0; k < 3; ++k) {
            /* mixed scales: near (2^12), mid (2^18), far (2^25) blockers; some below the horizon */
            const int sc = i % 3 == 0 ? 12 : i % 3 == 1 ? 18 : 25;
            v[i][k] = (int32_t)(qtool_grng_u32(&r) >> (31 - sc)) - (int32_t)(1u << (sc - 1));
        }
    for (int t = 0; t < NT; ++t)
        for (int k = 0; k < 3; ++k)
            tri[t][k] = qtool_grng_u32(&r) % NV;
    /* hard cases: a vertex at the receiver, a repeated vertex, 1 LSB above, on the horizon */
    v[0][0] = v[0][1] = v[0][2] = 0;
    tri[0][0] = 0;
    tri[1][1] = tri[1][0];
    v[1][2] = 1, v[2][2] = 1, v[3][2] = 1;
    v[1][0] = -(1 << 25), v[2][0] = 1 << 25, v[3][1] = 1 << 25, v[1][1] = v[2][1] = -(1 << 25);
    tri[2][0] = 1, tri[2][1] = 2, tri[2][2] = 3;
    v[4][2] = 0, v[5][2] = 0;
    tri[3][0] = 4, tri[3][1] = 5;
    qtool_gbuf b = {0};
    uint32_t m[QIBL_HEMI_MAX_WORDS];
    for (int k = 0; k < NT; k += 4) {
        qibl_hemi_stats_t st = {0, 0, 0};
        QIBL_DROP_STATUS(qibl_hemi_clear(h, m));
        qibl_status_t rc = qibl_hemi_raster(h, (const int32_t(*)[3])v, NV, (const uint32_t(*)[3])tri + k, 4, m, &st);
        qtool_gbuf_u8(&b, (uint32_t)rc);
        qtool_gbuf_u32(&b, st.rasterized), qtool_gbuf_u32(&b, st.below), qtool_gbuf_u32(&b, st.through);
        QIBL_DROP_STATUS(qibl_hemi_clip(h, m));
        for (uint32_t i = 0; i < h->words; ++i)
            qtool_gbuf_u32(&b, m[i]);
        qibl_q30_t out[25];
        for (int i = 0; i < 25; ++i)
            out[i] = (qibl_q30_t)GUARD;
        rc = qibl_hemi_transfer(h, m, out);
        qtool_gbuf_u8(&b, (uint32_t)rc);
        for (int i = 0; i < 25; ++i)
            qtool_gbuf_s32(&b, out[i]);
    }
    /* a bad index: status only, mask untouched */
    tri[5][2] = NV;
    for (uint32_t i = 0; i < h->words; ++i)
        m[i] = GUARD;
    qtool_gbuf_u8(&b, (uint32_t)qibl_hemi_raster(h, (const int32_t(*)[3])v, NV, (const uint32_t(*)[3])tri, NT, m, NULL));
    for (uint32_t i = 0; i < h->words; ++i)
        qtool_gbuf_u32(&b, m[i]);
    return qtool_gbuf_emit(s, name, &b);
}

static int frames_case(const qtool_goldens_sink_t *s, const char *name, const qibl_hemi_t *h)
{
    qtool_grng r = {4242};
    qtool_gbuf b = {0};
    for (int t = 0; t < 64; ++t) {
        int32_t n[3];
        qibl_q16_t p[3], pos[4][3];
        for (int k = 0; k < 3; ++k) {
            n[k] = (int32_t)(qtool_grng_u32(&r) >> 8) - (1 << 23);
            p[k] = (int32_t)(qtool_grng_u32(&r) >> 11) - (1 << 20);
            for (int j = 0; j < 4; ++j)
                pos[j][k] = (int32_t)(qtool_grng_u32(&r) >> 10) - (1 << 21);
        }
        if (t < 3)
            n[0] = n[1] = 0, n[2] = t - 1; /* poles and the zero vector */
        qibl_hemi_frame_t fr;
        qibl_status_t st = qibl_hemi_frame_init(&fr, p, n);
        qtool_gbuf_u8(&b, (uint32_t)st);
        if (st != QIBL_OK)
            continue;
        for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k)
                qtool_gbuf_s32(&b, fr.axis[i][k]);
        int32_t loc[4][3];
        qtool_gbuf_u8(&b, (uint32_t)qibl_hemi_transform(&fr, (const qibl_q16_t(*)[3])pos, 4, loc));
        for (int j = 0; j < 4; ++j)
            for (int k = 0; k < 3; ++k)
                qtool_gbuf_s32(&b, loc[j][k]);
        qibl_q30_t in[25], out[25];
        int32_t light[25];
        for (int i = 0; i < 25; ++i)
            in[i] = (int32_t)(qtool_grng_u32(&r) >> 2) - (1 << 29);
        QIBL_DROP_STATUS(qibl_hemi_to_world(h, &fr, in, out));
        for (int i = 0; i < 25; ++i)
            qtool_gbuf_s32(&b, out[i]);
        QIBL_DROP_STATUS(qibl_hemi_to_frame(h, &fr, in, light));
        for (int i = 0; i < 25; ++i)
            qtool_gbuf_s32(&b, light[i]);
    }
    return qtool_gbuf_emit(s, name, &b);
}

/* Group bounds of integer-made vertex sets (one vertex, a flat set, random sets, an index list,
 * the empty group, an index and a range refusal), the culling test and the refinement test at
 * k = 0.75 .. 4 against random frames. */
static int bounds_case(const qtool_goldens_sink_t *s, const char *name)
{
    qtool_grng r = {777};
    qtool_gbuf b = {0};
    for (int t = 0; t < 48; ++t) {
        enum { NV = 9 };
        qibl_q16_t pos[NV][3], p[3];
        int32_t n[3];
        const uint32_t span = 1u << (4 + t % 18);
        for (int k = 0; k < 3; ++k) {
            const int32_t c = (int32_t)(qtool_grng_u32(&r) >> 12) - (1 << 19);
            for (int j = 0; j < NV; ++j)
                pos[j][k] = c + (int32_t)(qtool_grng_u32(&r) % span) - (int32_t)(span / 2u);
            p[k] = (int32_t)(qtool_grng_u32(&r) >> 12) - (1 << 19);
            n[k] = (int32_t)(qtool_grng_u32(&r) >> 8) - (1 << 23);
        }
        if (t % 8 == 3)
            for (int j = 0; j < NV; ++j)
                pos[j][2] = pos[0][2]; /* flat */
        const uint32_t idx[4] = {1, 3, 5, (uint32_t)(t == 7 ? NV : 7)};
        qibl_hemi_bound_t bd = {{(int32_t)GUARD, (int32_t)GUARD, (int32_t)GUARD}, (int32_t)GUARD};
        const uint32_t cnt = t % 6 == 0 ? 1u : t == 5 ? 0u : (uint32_t)NV;
        qtool_gbuf_u8(&b, (uint32_t)(t % 3 == 1 ? qibl_hemi_bound_fit((const qibl_q16_t(*)[3])pos, NV, idx, 4, &bd)
                                          : qibl_hemi_bound_fit((const qibl_q16_t(*)[3])pos, NV, NULL, cnt, &bd)));
        for (int k = 0; k < 3; ++k)
            qtool_gbuf_s32(&b, bd.c[k]);
        qtool_gbuf_s32(&b, bd.r);
        qibl_hemi_frame_t fr;
        if (qibl_hemi_frame_init(&fr, p, n) == QIBL_OK)
            for (int q = 0; q < 4; ++q) { /* the frame moved onto the group's centre and off it */
                qibl_hemi_frame_t g = fr;
                for (int k = 0; k < 3; ++k)
                    g.p[k] = bd.c[k] + (q - 1) * (int32_t)(span / 4u) * (fr.axis[2][k] / (1 << 28));
                qtool_gbuf_u8(&b, (uint32_t)qibl_hemi_bound_above(&g, &bd));
                for (uint32_t kq = 192u; kq <= 1024u; kq += 208u) /* k = 0.75 .. 4 */
                    qtool_gbuf_u8(&b, (uint32_t)qibl_hemi_bound_near(&g, &bd, kq));
            }
    }
    const qibl_q16_t far[1][3] = {{QIBL_HEMI_COORD_MAX + 1, 0, 0}};
    qibl_hemi_bound_t bd = {{1, 2, 3}, 4};
    qtool_gbuf_u8(&b, (uint32_t)qibl_hemi_bound_fit(far, 1, NULL, 1, &bd));
    qtool_gbuf_s32(&b, bd.r);
    return qtool_gbuf_emit(s, name, &b);
}

/* The glossy transfer: random masks, reflection directions (axes, below the horizon, random) and
 * exponents (0, small, large, the limit, one beyond: its status, output untouched) */
static int phong_case(const qtool_goldens_sink_t *s, const char *name, const qibl_hemi_t *h, uint64_t seed)
{
    static const uint32_t es[] = {0u, 1u, 2u, 7u, 64u, QIBL_HEMI_MAX_EXPONENT, QIBL_HEMI_MAX_EXPONENT + 1u};
    qtool_grng r = {seed};
    qtool_gbuf b = {0};
    for (int t = 0; t < 8; ++t) {
        uint32_t m[QIBL_HEMI_MAX_WORDS];
        for (uint32_t i = 0; i < h->words; ++i)
            m[i] = t == 0 ? 0u : qtool_grng_u32(&r) & qtool_grng_u32(&r);
        qibl_q30_t refl[3];
        for (int k = 0; k < 3; ++k)
            refl[k] = (int32_t)(qtool_grng_u32(&r) >> 1) - (1 << 30);
        if (t == 1)
            refl[0] = refl[1] = 0, refl[2] = 1 << 30; /* the normal */
        if (t == 2)
            refl[0] = 1 << 30, refl[1] = refl[2] = 0; /* along the horizon */
        if (t == 3)
            refl[2] = -(1 << 29); /* below */
        for (size_t e = 0; e < sizeof es / sizeof es[0]; ++e) {
            qibl_q30_t out[25];
            for (int i = 0; i < 25; ++i)
                out[i] = (qibl_q30_t)GUARD;
            qtool_gbuf_u8(&b, (uint32_t)qibl_hemi_transfer_phong(h, m, refl, es[e], out));
            for (int i = 0; i < 25; ++i)
                qtool_gbuf_s32(&b, out[i]);
        }
    }
    return qtool_gbuf_emit(s, name, &b);
}

#if QIBL_USE_ASSET
/* Exported transfer (qibl_hemi_xfer_*): 8 vertices of random Q2.30 transfer (the extremes first)
 * written in the documented layout for 3, 4 and 5 bands, opened, shaded under random lights in
 * full and in a middle span; a span past the end, a mangled magic and a flipped payload bit give
 * their statuses. */
static int xfer_case(const qtool_goldens_sink_t *s, const char *name)
{
    enum { NV = 8 };
    qtool_grng r = {31337};
    qtool_gbuf b = {0};
    for (uint32_t bands = 3; bands <= 5; ++bands) {
        const uint32_t nc = bands * bands, size = QIBL_HEMI_XFER_HEADER_SIZE + NV * nc * 4u;
        uint8_t f[QIBL_HEMI_XFER_HEADER_SIZE + NV * 25 * 4];
        const uint32_t hdr[5] = {1u | (bands << 16), NV, 30u, 0u, 0u}; /* version | bands, count, frac, reserved */
        f[0] = 'Q', f[1] = 'T', f[2] = 'R', f[3] = 'X';
        for (uint32_t i = 0; i < NV * nc; ++i) {
            const uint32_t v = i == 0 ? 0x7FFFFFFFu : i == 1 ? 0x80000000u : qtool_grng_u32(&r);
            for (int k = 0; k < 4; ++k)
                f[QIBL_HEMI_XFER_HEADER_SIZE + 4u * i + (uint32_t)k] = (uint8_t)(v >> (8 * k));
        }
        for (int w = 0; w < 4; ++w)
            for (int k = 0; k < 4; ++k)
                f[4 + 4 * w + k] = (uint8_t)(hdr[w] >> (8 * k));
        const uint32_t crc = qibl_crc32(0u, f + QIBL_HEMI_XFER_HEADER_SIZE, NV * nc * 4u);
        for (int k = 0; k < 4; ++k)
            f[20 + k] = (uint8_t)(crc >> (8 * k));
        qibl_hemi_xfer_t x;
        qibl_status_t st = qibl_hemi_xfer_open(&x, f, size);
        qtool_gbuf_u8(&b, (uint32_t)st);
        if (st != QIBL_OK)
            continue;
        for (int t = 0; t < 4; ++t) {
            int32_t light[3][QIBL_HEMI_COEFFS];
            for (int ch = 0; ch < 3; ++ch)
                for (int i = 0; i < QIBL_HEMI_COEFFS; ++i)
                    light[ch][i] = (int32_t)(qtool_grng_u32(&r) >> (9 + t)) - (int32_t)(1u << (22 - t));
            qibl_q16_t out[NV + 3][3]; /* the whole span, then vertices 2..4 again */
            qtool_gbuf_u8(&b, (uint32_t)qibl_hemi_xfer_shade_span(&x, (const int32_t(*)[QIBL_HEMI_COEFFS])light, 0, NV, out));
            qtool_gbuf_u8(&b, (uint32_t)qibl_hemi_xfer_shade_span(&x, (const int32_t(*)[QIBL_HEMI_COEFFS])light, 2, 3,
                                                            out + NV));
            for (int v = 0; v < NV + 3; ++v)
                for (int ch = 0; ch < 3; ++ch)
                    qtool_gbuf_s32(&b, out[v][ch]);
            qtool_gbuf_u8(&b, (uint32_t)qibl_hemi_xfer_shade_span(&x, (const int32_t(*)[QIBL_HEMI_COEFFS])light, 7, 2, out));
        }
        f[QIBL_HEMI_XFER_HEADER_SIZE + 5] ^= 0x10u;
        qtool_gbuf_u8(&b, (uint32_t)qibl_hemi_xfer_open(&x, f, size));
        f[0] = 'q';
        qtool_gbuf_u8(&b, (uint32_t)qibl_hemi_xfer_open(&x, f, size));
    }
    return qtool_gbuf_emit(s, name, &b);
}
#endif

int qtool_goldens_hemi(const qtool_goldens_sink_t *s)
{
    static const struct {
        int n, face;
        const char *tables, *masks, *phong;
    } cfg[] = {{16, 16, "hemi_tables_16_f16", "hemi_masks_16_f16", "hemi_phong_16"},
               {32, 24, "hemi_tables_32_f24", "hemi_masks_32_f24", "hemi_phong_32"},
               {64, 8, "hemi_tables_64_f8", "hemi_masks_64_f8", "hemi_phong_64"}};
    int fails = 0;
    for (size_t c = 0; c < sizeof cfg / sizeof cfg[0]; ++c) {
        const int n = cfg[c].n, face = cfg[c].face;
        const size_t sz = qibl_hemi_workspace_size(n, face);
        qibl_hemi_t h;
        void *ws = malloc(sz), *rws = NULL;
        int ok = 0; /* h serves the cases below */
        if (ws != NULL)
            fails += tables_case(s, cfg[c].tables, n, face, &h, ws, sz, &ok);
        else
#if QIBL_USE_ASSET
            fails += tables_chunked_case(s, cfg[c].tables, n, face);
#else
            fails += qtool_gcase_oom_size(s, cfg[c].tables, sz);
#endif
        qibl_status_t open_st = QIBL_OK;
#if QIBL_USE_ASSET
        /* the port's prebuilt tables (ROM) when it has them: the same bytes, opened in place */
        size_t bsize = 0;
        const void *blob = s->hemi_tables != NULL ? s->hemi_tables(s->user, n, face, &bsize) : NULL;
        if (blob != NULL) {
            rws = malloc(QIBL_HEMI_OPEN_WORKSPACE_SIZE);
            open_st = rws == NULL ? QIBL_E_WORKSPACE
                                  : qibl_hemi_open(&h, n, face, blob, bsize, rws, QIBL_HEMI_OPEN_WORKSPACE_SIZE);
            ok = open_st == QIBL_OK;
        }
#endif
        if (ok) {
            fails += masks_case(s, cfg[c].masks, &h, 1000u + c);
            fails += phong_case(s, cfg[c].phong, &h, 2000u + c);
            if (c == 1)
                fails += frames_case(s, "hemi_frames", &h);
        } else if (open_st != QIBL_OK) {
            fails += qtool_gcase_status_error(s, cfg[c].masks, "qibl_hemi_open", open_st) +
                     qtool_gcase_status_error(s, cfg[c].phong, "qibl_hemi_open", open_st);
            if (c == 1)
                fails += qtool_gcase_status_error(s, "hemi_frames", "qibl_hemi_open", open_st);
        } else if (ws == NULL) {
            /* the tables did not fit and the port has none prebuilt: the cases that use them
             * cannot run either (same need) */
            fails += qtool_gcase_oom_size(s, cfg[c].masks, sz) + qtool_gcase_oom_size(s, cfg[c].phong, sz);
            if (c == 1)
                fails += qtool_gcase_oom_size(s, "hemi_frames", sz);
        }
        if (c == 1)
            fails += bounds_case(s, "hemi_bounds"); /* (needs no tables) */
        free(rws);
        free(ws);
    }
#if QIBL_USE_ASSET
    fails += xfer_case(s, "hemi_xfer"); /* (needs no tables) */
#endif
    return fails;
}

#endif
