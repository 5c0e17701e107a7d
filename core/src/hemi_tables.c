/*
 * hemi_tables.c - the rasterizer's read-only tables (disk mask, unblocked transfer, basis table,
 * plane LUT, pixel centres): built into a workspace (qibl_hemi_init), or as one relocatable blob
 * with a versioned header, any span of its words at a time (qibl_hemi_tables_build), and opened in
 * place from ROM, flash or a mapped file (qibl_hemi_open).
 *
 * Invariants: integer only, no heap, no state; every table word is a pure function of (n, face) and
 * of its index, made from exact integer tests (disk, LUT) or from qibl_sh_eval_unit at exact
 * sub-sample points (basis), so any span comes out the same bytes on every port and whichever way
 * the blob is cut. No division by a variable (Cortex-M0 has none): spans are found by stepping.
 * Not dispatched: the tables use no SIMD lanes, one copy serves every kernel choice.
 */
#include "qibl/hemi.h"
#include "qibli.h"
#if QIBL_USE_ASSET
#include "qibl/asset.h"
#endif

#if QIBL_USE_HEMI

#define NC QIBL_HEMI_COEFFS
#define HDR_WORDS (QIBL_HEMI_TABLES_HEADER_SIZE / 4u)

static int sizes_ok(int n, int face)
{
    return (n == 16 || n == 32 || n == 64) && face >= 2 && face <= QIBL_HEMI_MAX_FACE && (face & 1) == 0;
}

/* payload word offsets of each table (the blob's words after its header; init's after the
 * rotations): disk, full, basis, lut, zc, end. At most 3 128^2 128 + 26 64^2 + 153 < 2^23 words. */
typedef struct layout {
    int32_t n, face;
    uint32_t wpr, words;
    uint32_t full, basis, lut, zc, end;
} layout;

static void layout_of(layout *l, int n, int face)
{
    const uint32_t un = (uint32_t)n, uf = (uint32_t)face;
    l->n = n, l->face = face;
    l->wpr = n > 32 ? un / 32u : 1u;
    l->words = un * l->wpr;
    l->full = l->words;
    l->basis = l->full + NC;
    l->lut = l->basis + NC * un * un;
    l->zc = l->lut + 3u * uf * uf * l->words;
    l->end = l->zc + un * un;
}

static uint64_t ws_bytes(int n, int face)
{
    /* the layout's end without the struct (a size query stays cheap in stack); < 2^23 words */
    const uint32_t un = (uint32_t)n, uf = (uint32_t)face, words = (uint32_t)QIBL_HEMI_MASK_WORDS(un);
    const uint32_t end = words + NC + NC * un * un + 3u * uf * uf * words + un * un;
    return (uint64_t)(2u * (uint32_t)sizeof(qibl_sh_rotation_t)) + 4u * (uint64_t)end + 4u; /* + alignment slack */
}

size_t qibl_hemi_workspace_size(int n, int face)
{
    if (!sizes_ok(n, face))
        return 0u;
    uint64_t b = ws_bytes(n, face);
    return b > (uint64_t)SIZE_MAX ? 0u : (size_t)b;
}

/* ---- table words ------------------------------------------------------------------------------- */

/* Is the pixel with centre (X, Y) / n (X, Y odd) above the plane with normal P (integers)?
 * Exact: sign of Px X + Py Y + Pz sqrt(n^2 - X^2 - Y^2); a centre outside the disk takes the
 * horizon point (X, Y, 0) / |(X, Y)|. Magnitudes: |P| <= 128, |X|, |Y| < 64: A^2 < 2^29. */
static int above(const int32_t P[3], int32_t X, int32_t Y, int32_t n)
{
    /* 32-bit products: |A| <= 2 128 63, A^2 < 2^28, B^2 Q <= 2^14 2^12 */
    const int32_t A = P[0] * X + P[1] * Y;
    const int32_t Q = n * n - X * X - Y * Y;
    const int32_t B = P[2];
    if (Q <= 0 || B == 0)
        return A > 0;
    if (A >= 0 && B > 0)
        return 1;
    if (A <= 0 && B < 0)
        return 0;
    if (A > 0) /* B < 0: A > |B| sqrt(Q) */
        return A * A > B * B * Q;
    return B * B * Q > A * A; /* A < 0 < B */
}

/* Does pixel (X, Y) (odd centre coordinates, half-width 1, units 1/n) meet the open disk? */
static int meets_disk(int32_t X, int32_t Y, int32_t n)
{
    int32_t dx = (X < 0 ? -X : X) - 1, dy = (Y < 0 ? -Y : Y) - 1;
    if (dx < 0)
        dx = 0;
    if (dy < 0)
        dy = 0;
    return dx * dx + dy * dy < n * n;
}

/* word k of row r of the disk mask (P NULL) or of the plane P's mask */
static uint32_t mask_word(const int32_t *P, int32_t n, int32_t r, uint32_t k)
{
    uint32_t w = 0;
    for (int32_t b = 0; b < 32 && (int32_t)k * 32 + b < n; ++b) {
        const int32_t c = (int32_t)k * 32 + b;
        const int32_t X = 2 * c + 1 - n, Y = 2 * r + 1 - n;
        if (meets_disk(X, Y, n) && (P == 0 || above(P, X, Y, n)))
            w |= 1u << b;
    }
    return w;
}

/* The basis table's row of pixel (r, c): T[i] = sum over the pixel's S x S sub-samples inside the
 * disk of Y_i times the sub-sample area (2/256)^2 = 2^-14. Sub-sample centres Xs / 256 with Xs
 * odd; z = sqrt(1 - x^2 - y^2) rounded in Q2.30 from an exact integer square root. */
static void basis_row(int32_t n, int32_t r, int32_t c, uint32_t t[NC])
{
    const int32_t S = n == 16 ? 16 : n == 32 ? 8 : 4; /* 256 / n, without a library division */
    int64_t acc[NC];
    for (int i = 0; i < NC; ++i)
        acc[i] = 0;
    for (int32_t k = 0; k < S; ++k)
        for (int32_t l = 0; l < S; ++l) {
            const int32_t Xs = 2 * (c * S + l) + 1 - 256, Ys = 2 * (r * S + k) + 1 - 256;
            const int32_t q = 65536 - Xs * Xs - Ys * Ys;
            if (q <= 0)
                continue;
            uint64_t rem;
            const uint64_t q44 = (uint64_t)q << 44;
            uint32_t z = qibl_isqrt_u64(q44, &rem);
            if (rem > z) /* round: (z + 1/2)^2 = z^2 + z + 1/4 */
                ++z;
            const qibl_q30_t u[3] = {Xs * (1 << 22), Ys * (1 << 22), (qibl_q30_t)z};
            qibl_q30_t y[NC];
            QIBL_DROP_STATUS(qibl_sh_eval_unit(u, 5, y));
            for (int i = 0; i < NC; ++i)
                acc[i] += y[i];
        }
    for (int i = 0; i < NC; ++i)
        t[i] = (uint32_t)qibl_rshr_s64(acc[i], 14); /* |acc| < 2^8 2^31: no saturation */
}

/* z of pixel (r, c)'s centre lifted onto the hemisphere, Q2.30 rounded (0 for a centre outside the
 * disk, whose direction is then the horizon point): the glossy transfer's sample directions */
static uint32_t centre_z(int32_t n, int32_t r, int32_t c)
{
    const int32_t X = 2 * c + 1 - n, Y = 2 * r + 1 - n, q = n * n - X * X - Y * Y; /* in (1/n)^2 */
    uint32_t z = 0u;
    if (q > 0) { /* z = sqrt(q) / n in Q30: isqrt(q 2^60 / n^2), n a power of two */
        /* q 2^60 / n^2 with constant shifts (no 64-bit variable shift on Cortex-M0) */
        const uint64_t q60 = n == 16 ? (uint64_t)q << 52 : n == 32 ? (uint64_t)q << 50 : (uint64_t)q << 48;
        uint64_t rem;
        z = qibl_isqrt_u64(q60, &rem);
        if (rem > z)
            ++z;
    }
    return z;
}

/* does [base, base + len) meet the span [lo, hi)? */
static int meets(uint32_t lo, uint32_t hi, uint32_t base, uint32_t len)
{
    return base < hi && lo < base + len;
}

/* out[k - lo] = src[k - base] for k in [base, base + len) and in [lo, hi) */
static void put(uint32_t *out, uint32_t lo, uint32_t hi, uint32_t base, const uint32_t *src, uint32_t len)
{
    const uint32_t a = base > lo ? base : lo, b = base + len < hi ? base + len : hi;
    for (uint32_t k = a; k < b; ++k)
        out[k - lo] = src[k - base];
}

/* Payload words [lo, hi) into out[0 .. hi - lo). The unblocked transfer is the sum of every basis
 * row: asked for, it costs one pass over all pixels (rows that are asked for too are made once). */
static void payload(const layout *l, uint32_t lo, uint32_t hi, uint32_t *out)
{
    const int32_t n = l->n, F = l->face;
    const uint32_t W = l->words;
    if (meets(lo, hi, 0u, W))
        for (int32_t r = 0; r < n; ++r)
            for (uint32_t k = 0; k < l->wpr; ++k) {
                const uint32_t w = mask_word(0, n, r, k);
                put(out, lo, hi, (uint32_t)r * l->wpr + k, &w, 1u);
            }
    const int want_full = meets(lo, hi, l->full, NC);
    if (want_full || meets(lo, hi, l->basis, l->lut - l->basis)) {
        uint32_t full[NC];
        for (int i = 0; i < NC; ++i)
            full[i] = 0u;
        uint32_t base = l->basis;
        const uint32_t row_len = NC * (uint32_t)n;
        for (int32_t r = 0; r < n; ++r) {
            if (!want_full && !meets(lo, hi, base, row_len)) { /* step over a row no word is asked of */
                base += row_len;
                continue;
            }
            for (int32_t c = 0; c < n; ++c, base += NC)
                if (want_full || meets(lo, hi, base, NC)) {
                    uint32_t t[NC];
                    basis_row(n, r, c, t);
                    put(out, lo, hi, base, t, NC);
                    for (int i = 0; i < NC; ++i)
                        full[i] += t[i]; /* wrapping: exact, the true sum is below 2 (hemi.h) */
                }
        }
        if (want_full)
            put(out, lo, hi, l->full, full, NC);
    }
    /* LUT: faces +X (normal (F, u, v)), +Y (normal (u, F, v)), +Z (normal (v, u, F)); cell
     * centres 2i + 1 - F in units of 1/F; the - faces are complements */
    if (meets(lo, hi, l->lut, l->zc - l->lut)) {
        uint32_t base = l->lut;
        const uint32_t row_len = (uint32_t)F * W;
        for (int f = 0; f < 3; ++f)
            for (int32_t iu = 0; iu < F; ++iu) {
                if (!meets(lo, hi, base, row_len)) {
                    base += row_len;
                    continue;
                }
                for (int32_t iv = 0; iv < F; ++iv, base += W) {
                    if (!meets(lo, hi, base, W))
                        continue;
                    const int32_t u = 2 * iu + 1 - F, v = 2 * iv + 1 - F;
                    const int32_t P[3] = {f == 0 ? F : f == 1 ? u : v, f == 0 ? u : f == 1 ? F : u, f == 2 ? F : v};
                    uint32_t m[QIBL_HEMI_MAX_WORDS];
                    for (int32_t r = 0; r < n; ++r)
                        for (uint32_t k = 0; k < l->wpr; ++k)
                            m[(uint32_t)r * l->wpr + k] = mask_word(P, n, r, k);
                    put(out, lo, hi, base, m, W);
                }
            }
    }
    if (meets(lo, hi, l->zc, l->end - l->zc))
        for (int32_t r = 0; r < n; ++r)
            for (int32_t c = 0; c < n; ++c) {
                const uint32_t z = centre_z(n, r, c);
                put(out, lo, hi, l->zc + (uint32_t)(r * n + c), &z, 1u);
            }
}

/* *h's views of the payload p and the rotations rot[0..2), field by field (a struct copy may become
 * a memcpy call, which the core cannot link) */
static void views(qibl_hemi_t *h, const layout *l, const uint32_t *p, const qibl_sh_rotation_t *rot)
{
    h->n = l->n, h->face = l->face, h->wpr = l->wpr, h->words = l->words;
    h->rx_pos = &rot[0], h->rx_neg = &rot[1];
    h->disk = p, h->full = p + l->full, h->basis = p + l->basis, h->lut = p + l->lut, h->zc = p + l->zc;
}

/* D(Rx(+90)) and D(Rx(-90)) into rot[0..2) */
static qibl_status_t rotations(qibl_sh_rotation_t *rot)
{
    /* Rx(+90): y -> z, z -> -y; Rx(-90) its transpose. Exact in Q2.30. */
    static const qibl_q30_t rp[3][3] = {{QIBL_Q30_ONE, 0, 0}, {0, 0, -QIBL_Q30_ONE}, {0, QIBL_Q30_ONE, 0}};
    static const qibl_q30_t rn[3][3] = {{QIBL_Q30_ONE, 0, 0}, {0, 0, QIBL_Q30_ONE}, {0, -QIBL_Q30_ONE, 0}};
    qibl_status_t st = qibl_sh_rotation_init(&rot[0], rp, 5);
    if (st == QIBL_OK)
        st = qibl_sh_rotation_init(&rot[1], rn, 5);
    return st;
}

/* the rotations at workspace rounded up to 4 bytes */
static qibl_sh_rotation_t *aligned_rotations(void *workspace)
{
    uint8_t *ws = (uint8_t *)workspace;
    ws += (4u - ((uintptr_t)ws & 3u)) & 3u;
    return (qibl_sh_rotation_t *)(void *)ws;
}

qibl_status_t qibl_hemi_init(qibl_hemi_t *h, int n, int face, void *workspace, size_t workspace_size)
{
    if (h == 0 || workspace == 0)
        return QIBL_E_NULL_POINTER;
    if (!sizes_ok(n, face))
        return QIBL_E_HEMI_SIZE;
    if ((uint64_t)workspace_size < ws_bytes(n, face))
        return QIBL_E_WORKSPACE;
    layout l;
    layout_of(&l, n, face);
    qibl_sh_rotation_t *rot = aligned_rotations(workspace);
    qibl_status_t st = rotations(rot);
    if (st != QIBL_OK)
        return st;
    /* the blob's payload, built whole in place: what qibl_hemi_open would view */
    uint32_t *p = (uint32_t *)(void *)(rot + 2);
    payload(&l, 0u, l.end, p);
    views(h, &l, p, rot);
    return QIBL_OK;
}

/* ---- the blob (qibl_hemi_tables_*, qibl_hemi_open): needs the asset's CRC-32 ------------------- */
#if QIBL_USE_ASSET

#define TABLES_MAGIC 0x544D4851u /* "QHMT" as a little-endian word */

size_t qibl_hemi_tables_size(int n, int face)
{
    if (!sizes_ok(n, face))
        return 0u;
    return (size_t)(ws_bytes(n, face) - 2u * sizeof(qibl_sh_rotation_t) - 4u) + QIBL_HEMI_TABLES_HEADER_SIZE; /* < 2^25 */
}

/* CRC-32 of count words continuing from crc, each word's four bytes little-endian (the same value
 * whatever the machine's byte order) */
static uint32_t crc_words(uint32_t crc, const uint32_t *w, uint32_t count)
{
    uint8_t b[256];
    while (count != 0u) {
        const uint32_t m = count < 64u ? count : 64u;
        for (uint32_t i = 0; i < m; ++i)
            for (uint32_t k = 0; k < 4u; ++k)
                b[4u * i + k] = (uint8_t)(w[i] >> (8u * k));
        crc = qibl_crc32(crc, b, 4u * m);
        w += m, count -= m;
    }
    return crc;
}

/* the payload's CRC-32, made piece by piece into a small buffer: the unblocked transfer's piece
 * (with the disk) costs one basis pass, the basis rows another, pieces of whole pixels */
static uint32_t payload_crc(const layout *l)
{
    uint32_t buf[256], crc = 0u, pos = 0u;
    while (pos < l->end) {
        uint32_t stop = pos < l->basis ? l->basis : pos < l->lut ? pos + 10u * NC : pos + 256u;
        const uint32_t cap = pos < l->lut ? l->lut : l->end;
        stop = stop < cap ? stop : cap;
        payload(l, pos, stop, buf);
        crc = crc_words(crc, buf, stop - pos);
        pos = stop;
    }
    return crc;
}

qibl_status_t qibl_hemi_tables_build(int n, int face, uint32_t first, uint32_t count, uint32_t *out)
{
    if (out == 0 && count != 0u)
        return QIBL_E_NULL_POINTER;
    if (!sizes_ok(n, face))
        return QIBL_E_HEMI_SIZE;
    layout l;
    layout_of(&l, n, face);
    const uint32_t total = HDR_WORDS + l.end;
    if (first > total || count > total - first) /* unsigned: no wrap */
        return QIBL_E_HEMI_TABLES_BOUNDS;
    const uint32_t lo = first, hi = first + count;
    /* the payload part first: when it is whole, the header's CRC comes from it */
    const uint32_t plo = lo > HDR_WORDS ? lo - HDR_WORDS : 0u, phi = hi > HDR_WORDS ? hi - HDR_WORDS : 0u;
    if (phi > plo)
        payload(&l, plo, phi, out + (plo + HDR_WORDS - lo));
    if (lo < HDR_WORDS) {
        uint32_t hdr[HDR_WORDS] = {TABLES_MAGIC, QIBL_HEMI_TABLES_VERSION, (uint32_t)n, (uint32_t)face,
                                   4u * total, 0u, 0u, 0u};
        if (lo <= 5u && hi > 5u) /* the CRC word is asked for */
            hdr[5] = plo == 0u && phi == l.end ? crc_words(0u, out + (HDR_WORDS - lo), l.end) : payload_crc(&l);
        put(out, lo, hi, 0u, hdr, HDR_WORDS);
    }
    return QIBL_OK;
}

qibl_status_t qibl_hemi_open(qibl_hemi_t *h, int n, int face, const void *tables, size_t tables_size, void *workspace,
                             size_t workspace_size)
{
    if (h == 0 || tables == 0 || workspace == 0)
        return QIBL_E_NULL_POINTER;
    if (!sizes_ok(n, face))
        return QIBL_E_HEMI_SIZE;
    if (workspace_size < QIBL_HEMI_OPEN_WORKSPACE_SIZE)
        return QIBL_E_WORKSPACE;
    if (((uintptr_t)tables & 3u) != 0u)
        return QIBL_E_HEMI_TABLES_ALIGN;
    if (tables_size != qibl_hemi_tables_size(n, face))
        return QIBL_E_HEMI_TABLES_SIZE;
    const uint32_t *w = (const uint32_t *)tables;
    layout l;
    layout_of(&l, n, face);
    if (w[0] != TABLES_MAGIC)
        return QIBL_E_HEMI_TABLES_MAGIC;
    if (w[1] != QIBL_HEMI_TABLES_VERSION)
        return QIBL_E_HEMI_TABLES_VERSION;
    if (w[2] != (uint32_t)n || w[3] != (uint32_t)face)
        return QIBL_E_HEMI_TABLES_SHAPE;
    if ((size_t)w[4] != tables_size || w[6] != 0u || w[7] != 0u)
        return QIBL_E_HEMI_TABLES_HEADER;
    if (crc_words(0u, w + HDR_WORDS, l.end) != w[5])
        return QIBL_E_HEMI_TABLES_CRC;
    qibl_sh_rotation_t *rot = aligned_rotations(workspace);
    const qibl_status_t st = rotations(rot);
    if (st != QIBL_OK)
        return st;
    views(h, &l, w + HDR_WORDS, rot);
    return QIBL_OK;
}

#endif /* QIBL_USE_ASSET */

#endif /* QIBL_USE_HEMI */
