/*
 * fuzz_hemi.c - libFuzzer target: hemispherical rasterization (core/include/qibl/hemi.h) on fuzzed
 * table sizes, receivers, blocker vertices and triangles.
 *
 * Input: a size byte (mask 16/32/64, face 2..16, sometimes an invalid size or a short workspace),
 * the receiver (position and normal, any int32), up to 12 blocker positions (Q16.16, any int32),
 * then triangles as index bytes (some past the vertex count), and a light for the shading call.
 * Every buffer is malloc'ed at exactly its documented size, so ASan sees any access past it. The
 * tables (read-only after init) are built once per size and kept across inputs.
 *
 * Invariants (abort on violation): every call returns OK or one of its documented statuses and a
 * failing call leaves its outputs as they were; rasterizing all triangles at once equals ORing them
 * one at a time, and reversing each triangle's winding gives the same mask; clipping is idempotent;
 * blocking more of the hemisphere never raises the DC transfer coefficient (the per-pixel integrals
 * of Y_00 cos are non-negative); an empty mask's transfer is the unblocked hemisphere's.
 */
#include <stdlib.h>
#include <string.h>

#include "fuzz.h"
#include "qibl/hemi.h"

enum { MAX_V = 12, MAX_T = 24 };

static int same(const void *a, const void *b, size_t n)
{
    return memcmp(a, b, n) == 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_in in = {data, size};
    static const int sizes[3] = {16, 32, 64};
    const uint8_t sb = fuzz_u8(&in);
    int n = sizes[sb % 3u], face = 2 * (1 + (sb >> 2) % 8);
    if ((sb & 0xC0u) == 0xC0u) /* sometimes an invalid size: named status, h untouched */
        n = (sb & 0x20u) ? 24 : n, face = (sb & 0x20u) ? face : face + 1;
    size_t ws = qibl_hemi_workspace_size(n, face);
    qibl_hemi_t h, h0;
    memset(&h, 0xA5, sizeof h), h0 = h;
    if (ws == 0) {
        uint8_t dummy[16];
        FUZZ_CHECK(qibl_hemi_init(&h, n, face, dummy, sizeof dummy) == QIBL_E_HEMI_SIZE);
        FUZZ_CHECK(same(&h, &h0, sizeof h));
        return 0;
    }
    /* the tables are read-only after init: built once per size and reused (init is most of the
     * time otherwise); the first build of each size is checked like any other call */
    static uint8_t *cache_w[3][8];
    static qibl_hemi_t cache_h[3][8];
    uint8_t **w = &cache_w[sb % 3u][(sb >> 2) % 8u];
    if (!*w) {
        *w = malloc(ws);
        FUZZ_CHECK(*w != NULL);
        if ((sb & 0xC0u) == 0x80u) { /* a workspace one byte short */
            FUZZ_CHECK(qibl_hemi_init(&h, n, face, *w, ws - 1) == QIBL_E_WORKSPACE);
            FUZZ_CHECK(same(&h, &h0, sizeof h));
            free(*w), *w = NULL;
            return 0;
        }
        FUZZ_CHECK(qibl_hemi_init(&h, n, face, *w, ws) == QIBL_OK);
        cache_h[sb % 3u][(sb >> 2) % 8u] = h;
    }
    h = cache_h[sb % 3u][(sb >> 2) % 8u];
    const size_t words = h.words;
    FUZZ_CHECK(words >= 1 && words <= QIBL_HEMI_MAX_WORDS);

    /* the receiver: any position and normal */
    qibl_q16_t p[3];
    int32_t nrm[3];
    for (int i = 0; i < 3; ++i) { /* centred, any magnitude up to the whole int32 range */
        int64_t v = (int64_t)fuzz_u32(&in) - 2147483648LL;
        p[i] = (qibl_q16_t)(v / ((int64_t)1 << (fuzz_u8(&in) % 32u)));
    }
    for (int i = 0; i < 3; ++i)
        nrm[i] = (int32_t)fuzz_u32(&in);
    qibl_hemi_frame_t f, f0;
    memset(&f, 0x5A, sizeof f), f0 = f;
    qibl_status_t st = qibl_hemi_frame_init(&f, p, nrm);
    FUZZ_CHECK(st == QIBL_OK || st == QIBL_E_HEMI_RANGE || st == QIBL_E_ZERO_VECTOR);
    if (st != QIBL_OK) {
        FUZZ_CHECK(same(&f, &f0, sizeof f));
        return 0;
    }

    /* blockers: positions near the receiver (and some far beyond the limit) into the frame */
    const uint32_t nv = 1u + fuzz_u8(&in) % MAX_V;
    qibl_q16_t (*pos)[3] = malloc(sizeof *pos * nv);
    int32_t (*loc)[3] = malloc(sizeof *loc * nv);
    FUZZ_CHECK(pos && loc);
    for (uint32_t k = 0; k < nv; ++k)
        for (int i = 0; i < 3; ++i) {
            uint8_t s = fuzz_u8(&in);
            int32_t d = (int32_t)fuzz_u16(&in) - 32768;
            pos[k][i] = (s & 0x80u) ? (qibl_q16_t)fuzz_u32(&in) : p[i] / 2 + d * (1 + (s & 15));
        }
    memset(loc, 0x33, sizeof *loc * nv);
    st = qibl_hemi_transform(&f, (const qibl_q16_t(*)[3])pos, nv, loc);
    FUZZ_CHECK(st == QIBL_OK || st == QIBL_E_HEMI_RANGE);
    if (st != QIBL_OK) {
        for (uint32_t k = 0; k < nv; ++k)
            for (int i = 0; i < 3; ++i)
                FUZZ_CHECK(loc[k][i] == 0x33333333);
        /* raw fuzzed local coordinates instead: the rasterizer checks their range itself */
        for (uint32_t k = 0; k < nv; ++k)
            for (int i = 0; i < 3; ++i)
                loc[k][i] = (int32_t)fuzz_u32(&in) >> (fuzz_u8(&in) % 8u);
    }

    /* triangles, a few with an index past nv */
    const uint32_t nt = fuzz_u8(&in) % (MAX_T + 1);
    uint32_t (*tri)[3] = malloc(sizeof *tri * (nt ? nt : 1));
    uint32_t (*rev)[3] = malloc(sizeof *rev * (nt ? nt : 1));
    FUZZ_CHECK(tri && rev);
    for (uint32_t t = 0; t < nt; ++t) {
        for (int i = 0; i < 3; ++i)
            tri[t][i] = fuzz_u8(&in) % (nv + 1u);
        rev[t][0] = tri[t][0], rev[t][1] = tri[t][2], rev[t][2] = tri[t][1];
    }
    uint32_t *all = malloc(4 * words), *one = malloc(4 * words), *back = malloc(4 * words),
             *empty = malloc(4 * words), *keep = malloc(4 * words);
    FUZZ_CHECK(all && one && back && empty && keep);
    FUZZ_CHECK(qibl_hemi_clear(&h, all) == QIBL_OK && qibl_hemi_clear(&h, one) == QIBL_OK &&
               qibl_hemi_clear(&h, back) == QIBL_OK && qibl_hemi_clear(&h, empty) == QIBL_OK);
    for (size_t i = 0; i < words; ++i)
        FUZZ_CHECK(empty[i] == 0u);
    qibl_hemi_stats_t stats = {0, 0, 0}, stats0 = stats;
    memcpy(keep, all, 4 * words);
    st = qibl_hemi_raster(&h, (const int32_t(*)[3])loc, nv, (const uint32_t(*)[3])tri, nt, all, &stats);
    FUZZ_CHECK(st == QIBL_OK || st == QIBL_E_HEMI_INDEX || st == QIBL_E_HEMI_RANGE);
    if (st != QIBL_OK) {
        FUZZ_CHECK(same(all, keep, 4 * words) && same(&stats, &stats0, sizeof stats));
    } else {
        FUZZ_CHECK(stats.rasterized + stats.below + stats.through <= nt);
        qibl_status_t s1 = QIBL_OK, s2;
        for (uint32_t t = 0; t < nt; ++t) {
            s1 = qibl_hemi_raster(&h, (const int32_t(*)[3])loc, nv, (const uint32_t(*)[3])tri + t, 1, one, NULL);
            FUZZ_CHECK(s1 == QIBL_OK);
        }
        s2 = qibl_hemi_raster(&h, (const int32_t(*)[3])loc, nv, (const uint32_t(*)[3])rev, nt, back, NULL);
        FUZZ_CHECK(s2 == QIBL_OK);
        FUZZ_CHECK(same(all, one, 4 * words));  /* one at a time = all at once */
        FUZZ_CHECK(same(all, back, 4 * words)); /* winding does not matter */
    }

    /* clip (idempotent), transfer, monotone DC term, empty mask = the open hemisphere */
    FUZZ_CHECK(qibl_hemi_clip(&h, all) == QIBL_OK);
    memcpy(keep, all, 4 * words);
    FUZZ_CHECK(qibl_hemi_clip(&h, all) == QIBL_OK);
    FUZZ_CHECK(same(all, keep, 4 * words));
    qibl_q30_t tv[QIBL_HEMI_COEFFS], te[QIBL_HEMI_COEFFS], world[QIBL_HEMI_COEFFS];
    FUZZ_CHECK(qibl_hemi_transfer(&h, all, tv) == QIBL_OK);
    FUZZ_CHECK(qibl_hemi_transfer(&h, empty, te) == QIBL_OK);
    for (int i = 0; i < QIBL_HEMI_COEFFS; ++i)
        FUZZ_CHECK(te[i] == (qibl_q30_t)h.full[i]);
    FUZZ_CHECK(tv[0] <= te[0] && tv[0] >= -64);
    /* a mask that blocks more (all OR fuzzed bits) never lets more DC light through */
    for (size_t i = 0; i < words; ++i)
        one[i] = all[i] | fuzz_u32(&in);
    qibl_q30_t tm[QIBL_HEMI_COEFFS];
    FUZZ_CHECK(qibl_hemi_transfer(&h, one, tm) == QIBL_OK);
    FUZZ_CHECK(tm[0] <= tv[0] + 64);

    /* the glossy transfer: any reflection vector and exponent; e = 0 is the diffuse transfer,
     * a bad exponent or a zero vector is named and writes nothing */
    {
        qibl_q30_t refl[3] = {(int32_t)fuzz_u32(&in), (int32_t)fuzz_u32(&in), (int32_t)fuzz_u32(&in)};
        const uint32_t e = fuzz_u32(&in) % (QIBL_HEMI_MAX_EXPONENT + 2u);
        qibl_q30_t tp[QIBL_HEMI_COEFFS], tp0[QIBL_HEMI_COEFFS];
        for (int i = 0; i < QIBL_HEMI_COEFFS; ++i)
            tp[i] = 0x5A5A5A5A;
        const qibl_status_t sp = qibl_hemi_transfer_phong(&h, all, refl, e, tp);
        const int zero = refl[0] == 0 && refl[1] == 0 && refl[2] == 0;
        FUZZ_CHECK(sp == (e > QIBL_HEMI_MAX_EXPONENT ? QIBL_E_HEMI_EXPONENT : zero ? QIBL_E_ZERO_VECTOR : QIBL_OK));
        for (int i = 0; sp != QIBL_OK && i < QIBL_HEMI_COEFFS; ++i)
            FUZZ_CHECK(tp[i] == 0x5A5A5A5A);
        if (!zero) {
            FUZZ_CHECK(qibl_hemi_transfer_phong(&h, all, refl, 0, tp0) == QIBL_OK);
            for (int i = 0; i < QIBL_HEMI_COEFFS; ++i)
                FUZZ_CHECK(tp0[i] == tv[i]);
        }
    }

    /* out of the frame, the lighting into it, shading: defined for any values */
    FUZZ_CHECK(qibl_hemi_to_world(&h, &f, tv, world) == QIBL_OK);
    int32_t light[3][QIBL_HEMI_COEFFS], lf[QIBL_HEMI_COEFFS];
    for (int c = 0; c < 3; ++c)
        for (int i = 0; i < QIBL_HEMI_COEFFS; ++i)
            light[c][i] = (int32_t)fuzz_u32(&in);
    FUZZ_CHECK(qibl_hemi_to_frame(&h, &f, light[0], lf) == QIBL_OK);
    qibl_q16_t out[3];
    FUZZ_CHECK(qibl_hemi_shade((const int32_t(*)[QIBL_HEMI_COEFFS])light, world, out) == QIBL_OK);

    free(all), free(one), free(back), free(empty), free(keep);
    free(tri), free(rev), free(pos), free(loc);
    return 0;
}
