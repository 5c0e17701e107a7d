/*
 * fuzz_stream.c - libFuzzer target: the streaming API of the asset container (asset.h:
 * qibl_asset_head_size, qibl_asset_open_head, qibl_asset_row, qibl_asset_head_pmap,
 * qibl_asset_head_ylut) and relighting through the one-row views built from the head
 * (qibl_shmaps_row_view, qibl_pmap_row_view, qibl_shmap_relight_span, qibl_shmap_point_prepare/span).
 *
 * The input is a file; a caller that streams it is simulated: the head is read in growing rounds,
 * each round a copy of exactly the bytes read so far (ASan sees any read past them), then the PMAP
 * fields, the whole YLUT payload and each row are copied into buffers of exactly their documented
 * sizes. Each input is streamed twice: as it is, and with every CRC repaired (as fuzz_asset does),
 * so mutated fields reach the field checks. Bytes after file_size choose the lights.
 *
 * Invariants: at most four head rounds, each asking for more than the last; a failing call leaves its
 * output untouched; every offset the head and qibl_asset_row give lies inside file_size; the streamed
 * checks agree with qibl_asset_open_structure on the whole file (when the file holds file_size bytes
 * and has no SHMU chunk, which the head does not stream): the full open succeeds exactly when the
 * head, its PMAP and its YLUT views all succeed on an interleaved asset; the streamed views equal the
 * full open's, and each streamed row relights (directional and point, direct and through the LUT) to
 * the same bytes as that row of the whole asset. A LUT view built by hand from the YLUT's own fields
 * (the way a caller reading asset.h's layout would) is either refused or relights inside its bytes.
 */
#include <string.h>

#include "fuzz.h"
#include "qibl/asset.h"
#include "qibl/shmap.h"

static uint32_t le32(const uint8_t *p)
{
    return qibl_load_u32le(p);
}

static void put32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v, p[1] = (uint8_t)(v >> 8), p[2] = (uint8_t)(v >> 16), p[3] = (uint8_t)(v >> 24);
}

static int fix_crcs(uint8_t *b, size_t n)
{
    if (n < QIBL_ASSET_HEADER_SIZE)
        return 0;
    uint32_t count = le32(b + 12);
    if (count < 1u || count > QIBL_ASSET_MAX_CHUNKS || n < QIBL_ASSET_HEADER_SIZE + QIBL_ASSET_ENTRY_SIZE * count)
        return 0;
    for (uint32_t i = 0; i < count; ++i) {
        uint8_t *e = b + QIBL_ASSET_HEADER_SIZE + QIBL_ASSET_ENTRY_SIZE * i;
        uint64_t off = le32(e + 4), sz = le32(e + 8);
        if (off + sz <= n)
            put32(e + 12, qibl_crc32(0u, b + off, (size_t)sz));
    }
    put32(b + 20, qibl_crc32(0u, b + QIBL_ASSET_HEADER_SIZE, QIBL_ASSET_ENTRY_SIZE * count));
    return 1;
}

/* an exact-size heap copy of b[off, off + len) (len 0: one byte, never read) */
static uint8_t *copy_of(const uint8_t *b, uint64_t off, uint64_t len)
{
    uint8_t *c = malloc(len ? (size_t)len : 1u);
    memcpy(c, b + off, (size_t)len);
    return c;
}

static int has_chunk(const uint8_t *b, uint32_t type)
{
    uint32_t count = le32(b + 12);
    for (uint32_t i = 0; i < count; ++i)
        if (le32(b + QIBL_ASSET_HEADER_SIZE + QIBL_ASSET_ENTRY_SIZE * i) == type)
            return 1;
    return 0;
}

/* the head rounds; returns the head status, *head an exact copy of the bytes it holds */
static qibl_status_t read_head(const uint8_t *b, size_t n, uint8_t **head, size_t *have)
{
    size_t h = 0;
    uint8_t *c = copy_of(b, 0, 0);
    for (int round = 0;; ++round) {
        size_t need = 0x5A5A5A5Au;
        qibl_status_t st = qibl_asset_head_size(c, h, &need);
        if (st != QIBL_OK) {
            FUZZ_CHECK(need == 0x5A5A5A5Au && st > QIBL_OK && st < QIBL_STATUS_COUNT);
            *head = c, *have = h;
            return st;
        }
        if (need <= h)
            break;
        FUZZ_CHECK(round < 4);
        if (need > n) { /* the file ends first */
            *head = c, *have = h;
            return QIBL_E_ASSET_HEAD_SHORT;
        }
        free(c);
        c = copy_of(b, 0, need);
        h = need;
    }
    *head = c, *have = h;
    return QIBL_OK;
}

static void fuzz_light(qibl_shlight_t *l, uint32_t k, fuzz_in *prm)
{
    FUZZ_CHECK(qibl_shlight_init(l, k) == QIBL_OK);
    qibl_q16_t d[3], rgb[3];
    for (int j = 0; j < 3; ++j)
        d[j] = (int32_t)fuzz_u32(prm), rgb[j] = (int32_t)fuzz_u32(prm);
    if ((d[0] | d[1] | d[2]) == 0)
        d[2] = 1;
    FUZZ_CHECK(qibl_shlight_add_dir(l, d, rgb) == QIBL_OK);
}

static void stream(const uint8_t *b, size_t n, int repaired)
{
    fuzz_in prm = {0, 0};
    if (n >= QIBL_ASSET_HEADER_SIZE && le32(b + 16) <= n)
        prm.p = b + le32(b + 16), prm.n = n - le32(b + 16);
    qibl_asset_t a;
    const qibl_status_t full = qibl_asset_open_structure(&a, b, n);
    const int comparable = n >= QIBL_ASSET_HEADER_SIZE && le32(b + 16) <= n;
    uint8_t *head = NULL;
    size_t have = 0;
    qibl_status_t st = read_head(b, n, &head, &have);
    qibl_asset_head_t hd, guard;
    memset(&hd, 0xC3, sizeof hd), guard = hd;
    if (st == QIBL_OK) {
        st = qibl_asset_open_head(&hd, head, have);
        if (have > 0u) {
            qibl_asset_head_t h2 = guard;
            FUZZ_CHECK(qibl_asset_open_head(&h2, head, have - 1u) != QIBL_OK);
            FUZZ_CHECK(memcmp(&h2, &guard, sizeof h2) == 0);
        }
    }
    if (st != QIBL_OK) {
        FUZZ_CHECK(memcmp(&hd, &guard, sizeof hd) == 0);
        /* a head the full open would accept is refused only for its layout */
        if (comparable && full == QIBL_OK)
            FUZZ_CHECK(st == QIBL_E_ASSET_LAYOUT);
        if (repaired && st != QIBL_E_ASSET_HEAD_SHORT)
            FUZZ_CHECK(st != QIBL_E_ASSET_TABLE_CRC);
        free(head);
        return;
    }
    FUZZ_CHECK(hd.maps.layout == QIBL_SHMAPS_INTERLEAVED && hd.maps.planes == NULL);
    FUZZ_CHECK(hd.maps.params >= head && hd.maps.params + 8u * hd.maps.k * hd.maps.channels == head + have);
    FUZZ_CHECK((uint64_t)hd.maps_offset + (uint64_t)hd.row_size * hd.maps.height <= hd.file_size);
    FUZZ_CHECK(hd.row_size == qibl_shmaps_row_size(&hd.maps) && hd.row_size > 0u);

    /* the P map's fields and the whole Y LUT, each from an exact-size copy */
    int ok = 1, have_p = hd.pmap_offset != 0u, have_t = hd.ylut_size != 0u;
    qibl_pmap_t whole_p;
    qibl_ylut_t lut;
    uint8_t *lutb = NULL;
    if (have_p) {
        FUZZ_CHECK(hd.pmap_offset >= 12u && (uint64_t)hd.pmap_offset + 12u * hd.maps.width * hd.maps.height <= hd.file_size);
        if (hd.pmap_offset > n) {
            ok = 0, have_p = 0;
        } else {
            uint8_t *f = copy_of(b, hd.pmap_offset - 12u, 12u);
            memset(&whole_p, 0xC3, sizeof whole_p);
            qibl_pmap_t g = whole_p;
            FUZZ_CHECK(qibl_asset_head_pmap(&hd, f, 11u, &whole_p) == QIBL_E_ASSET_HEAD_SHORT);
            qibl_status_t ps = qibl_asset_head_pmap(&hd, f, 12u, &whole_p);
            if (ps != QIBL_OK) {
                FUZZ_CHECK(memcmp(&whole_p, &g, sizeof g) == 0 && ps > QIBL_OK && ps < QIBL_STATUS_COUNT);
                ok = 0, have_p = 0;
            } else {
                FUZZ_CHECK(whole_p.width == hd.maps.width && whole_p.height == hd.maps.height && whole_p.points == NULL);
            }
            free(f);
        }
    }
    if (have_t) {
        FUZZ_CHECK(hd.ylut_size >= 12u && (uint64_t)hd.ylut_offset + hd.ylut_size <= hd.file_size);
        if ((uint64_t)hd.ylut_offset + hd.ylut_size > n) {
            ok = 0, have_t = 0;
        } else {
            lutb = copy_of(b, hd.ylut_offset, hd.ylut_size);
            memset(&lut, 0xC3, sizeof lut);
            qibl_ylut_t g = lut;
            FUZZ_CHECK(qibl_asset_head_ylut(&hd, lutb, hd.ylut_size - 1u, &lut) == QIBL_E_ASSET_HEAD_SHORT);
            qibl_status_t ys = qibl_asset_head_ylut(&hd, lutb, hd.ylut_size, &lut);
            if (ys != QIBL_OK) {
                FUZZ_CHECK(memcmp(&lut, &g, sizeof g) == 0 && ys > QIBL_OK && ys < QIBL_STATUS_COUNT);
                ok = 0, have_t = 0;
            } else {
                FUZZ_CHECK(lut.k >= hd.maps.k && lut.k <= 25u && lut.values == lutb + 12);
                FUZZ_CHECK(lut.size == qibl_ylut_values_size(lut.face_size, lut.k) && lut.size == hd.ylut_size - 12u);
                FUZZ_CHECK(qibl_ylut_check(&lut) == QIBL_OK);
            }
        }
    }
    /* the streamed checks are the full open's (SHMU is not streamed) */
    if (comparable && !has_chunk(b, QIBL_CHUNK_SHMU))
        FUZZ_CHECK((full == QIBL_OK) == ok);
    if (full == QIBL_OK)
        FUZZ_CHECK(ok);

    /* rows: offsets inside the file; relit through one-row views */
    qibl_asset_row_t r, rg;
    memset(&rg, 0xC3, sizeof rg), r = rg;
    FUZZ_CHECK(qibl_asset_row(&hd, hd.maps.height, &r) == QIBL_E_ASSET_ROW && memcmp(&r, &rg, sizeof r) == 0);
    qibl_shmaps_t whole_m;
    const int cmp = full == QIBL_OK && ok;
    if (cmp) {
        FUZZ_CHECK(qibl_asset_shmaps(&a, &whole_m) == QIBL_OK);
        FUZZ_CHECK(whole_m.width == hd.maps.width && whole_m.height == hd.maps.height && whole_m.k == hd.maps.k &&
                   whole_m.channels == hd.maps.channels && whole_m.layout == hd.maps.layout);
        FUZZ_CHECK(memcmp(whole_m.params, hd.maps.params, 8u * hd.maps.k * hd.maps.channels) == 0);
        qibl_pmap_t fp;
        if (have_p)
            FUZZ_CHECK(qibl_asset_pmap(&a, &fp) == QIBL_OK && fp.points == b + hd.pmap_offset);
        qibl_ylut_t ft;
        if (have_t)
            FUZZ_CHECK(qibl_asset_ylut(&a, &ft) == QIBL_OK && ft.size == lut.size && ft.face_size == lut.face_size &&
                       ft.k == lut.k && memcmp(ft.values, lut.values, lut.size) == 0);
    }
    qibl_shlight_t light;
    fuzz_light(&light, hd.maps.k + fuzz_u8(&prm) % (26u - hd.maps.k), &prm);
    qibl_shmap_weights_t w;
    FUZZ_CHECK(qibl_shmap_weights(&hd.maps, &light, &w) == QIBL_OK);
    qibl_pointlight_t pl;
    memset(&pl, 0, sizeof pl);
    for (int j = 0; j < 3; ++j) {
        pl.pos[j] = (int32_t)fuzz_u32(&prm);
        pl.rgb[j] = (int32_t)(fuzz_u32(&prm) & 0x7FFFFFFFu);
    }
    const uint8_t f = fuzz_u8(&prm);
    pl.falloff = (qibl_falloff_t)(f & 1u);
    pl.filter = (qibl_lut_filter_t)(f >> 1 & 1u);
    pl.min_dist = (int32_t)(fuzz_u32(&prm) & 0x7FFFFFFFu);

    /* the hand-built LUT view: the YLUT's own fields, its payload's own size */
    qibl_ylut_t hand = {0, 0, NULL, 0};
    if (lutb != NULL)
        hand.face_size = le32(lutb), hand.k = le32(lutb + 4), hand.values = lutb + 12, hand.size = hd.ylut_size - 12u;

    const uint32_t W = hd.maps.width;
    const size_t wsz = qibl_shmap_span_workspace_size(W), psz = qibl_shmap_point_workspace_size(hd.maps.k, W);
    int32_t *out = malloc(12u * W), *ref = malloc(12u * W);
    void *ws = malloc(wsz > psz ? wsz : psz);
    for (uint32_t y = 0; y < hd.maps.height; ++y) {
        FUZZ_CHECK(qibl_asset_row(&hd, y, &r) == QIBL_OK);
        FUZZ_CHECK(r.maps_size == hd.row_size && r.maps_offset == hd.maps_offset + (uint64_t)y * hd.row_size);
        FUZZ_CHECK((uint64_t)r.maps_offset + r.maps_size <= hd.file_size);
        FUZZ_CHECK(hd.pmap_offset ? r.pmap_size == 12u * W && (uint64_t)r.pmap_offset + r.pmap_size <= hd.file_size
                                  : r.pmap_size == 0u && r.pmap_offset == 0u);
        if ((uint64_t)r.maps_offset + r.maps_size > n)
            break; /* the file ends: a streaming caller's read fails here */
        uint8_t *row = copy_of(b, r.maps_offset, r.maps_size);
        qibl_shmaps_t mv;
        FUZZ_CHECK(qibl_shmaps_row_view(&hd.maps, row, &mv) == QIBL_OK && mv.height == 1u);
        FUZZ_CHECK(qibl_shmap_relight_span(&mv, &w, 0, 0, W, out, ws, wsz) == QIBL_OK);
        if (cmp) {
            FUZZ_CHECK(qibl_shmap_relight_span(&whole_m, &w, 0, y, W, ref, ws, wsz) == QIBL_OK);
            FUZZ_CHECK(memcmp(out, ref, 12u * W) == 0);
        }
        if (hd.pmap_offset != 0u && (uint64_t)r.pmap_offset + r.pmap_size <= n) {
            uint8_t *prow = copy_of(b, r.pmap_offset, r.pmap_size);
            qibl_pmap_t byhand = {W, hd.maps.height, NULL}, pv;
            FUZZ_CHECK(qibl_pmap_row_view(have_p ? &whole_p : &byhand, prow, &pv) == QIBL_OK);
            qibl_shmap_point_t pt;
            const qibl_ylut_t *luts[3] = {NULL, have_t ? &lut : NULL, lutb ? &hand : NULL};
            for (int li = 0; li < 3; ++li) {
                if (li > 0 && luts[li] == NULL)
                    continue;
                qibl_status_t ps = qibl_shmap_point_prepare(&mv, &pv, luts[li], &pl, &pt);
                if (li < 2)
                    FUZZ_CHECK(ps == QIBL_OK);
                else if (ps == QIBL_OK)
                    FUZZ_CHECK(qibl_ylut_check(&hand) == QIBL_OK && hand.k >= mv.k);
                if (li == 2 && ps != QIBL_OK) {
                    /* refused only for what the fields say */
                    FUZZ_CHECK(ps == QIBL_E_SHMAP_MISMATCH || ps == QIBL_E_SHMAP_LUT_SHORT);
                    FUZZ_CHECK(ps != QIBL_E_SHMAP_LUT_SHORT || hand.size < qibl_ylut_values_size(hand.face_size, hand.k));
                    /* the maps-independent part is qibl_ylut_check's; k below the maps' is prepare's own */
                    FUZZ_CHECK(ps != QIBL_E_SHMAP_LUT_SHORT || qibl_ylut_check(&hand) == QIBL_E_SHMAP_LUT_SHORT);
                    FUZZ_CHECK(ps != QIBL_E_SHMAP_MISMATCH || qibl_ylut_check(&hand) != QIBL_OK || hand.k < mv.k);
                    continue;
                }
                FUZZ_CHECK(qibl_shmap_point_span(&pt, 0, 0, W, out, ws, psz) == QIBL_OK);
                if (cmp && li < 2 && have_p) {
                    qibl_pmap_t fp;
                    qibl_ylut_t ft;
                    FUZZ_CHECK(qibl_asset_pmap(&a, &fp) == QIBL_OK);
                    if (li == 1)
                        FUZZ_CHECK(qibl_asset_ylut(&a, &ft) == QIBL_OK);
                    qibl_shmap_point_t wp;
                    FUZZ_CHECK(qibl_shmap_point_prepare(&whole_m, &fp, li == 1 ? &ft : NULL, &pl, &wp) == QIBL_OK);
                    FUZZ_CHECK(qibl_shmap_point_span(&wp, 0, y, W, ref, ws, psz) == QIBL_OK);
                    FUZZ_CHECK(memcmp(out, ref, 12u * W) == 0);
                }
            }
            free(prow);
        }
        free(row);
    }
    free(out), free(ref), free(ws), free(lutb), free(head);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    uint8_t *buf = copy_of(data, 0, size);
    stream(buf, size, 0);
    if (fix_crcs(buf, size))
        stream(buf, size, 1);
    free(buf);
    return 0;
}
