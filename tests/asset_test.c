/*
 * asset_test.c - qibl/asset.h: the container reader (validation, CRC-32, views) against assets built
 * in memory by tools/io/asset_write.
 *
 * Every rejection has its own test asserting the exact status and that *out was not written. Then:
 * round trip (views return exactly the bytes written), alignment, trailing bytes, every truncation
 * length, every single-bit flip of a small asset, and a fixed-seed fuzz (random byte edits, with and
 * without re-sealed CRCs so the field checks behind the CRCs are reached too).
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cmocka.h>

#include "io/asset_write.h"
#include "qibl/asset.h"
#include "qibl/shmap.h"
#include "testutil.h"

/* ---- fixtures ------------------------------------------------------------------------------- */

/* "full" asset: SHMP 3x2, k 4, RGB; PMAP 3x2; YLUT N 2, k 5; unknown XTRA "hello". Chunks 0..3. */
#define FW 3u
#define FH 2u
#define FK 4u
#define FC 3u
#define FPAIRS (FK * FC)
#define FN 2u
#define FYK 5u
#define FYCOUNT (6u * FN * FN * FYK)

static const int32_t f_scale[FPAIRS] = {INT32_MIN, INT32_MAX, -1, 0, 1, QIBL_Q24_ONE, -QIBL_Q24_ONE,
                                        123456789, -123456789, 0x7F, -0x80, 42};
static const int32_t f_bias[FPAIRS] = {-7, INT32_MIN + 1, 0x01020304, -0x01020304, INT32_MAX, INT32_MIN,
                                       1, -1, 0, 65536, -65536, 99};
static const int32_t f_xyz[3 * FW * FH] = {INT32_MIN, INT32_MAX, -1, 0, 1, -65536, 65536, 0x12345678,
                                           -0x12345678, 7, -7, 100, -100, 1000, -1000, INT32_MIN + 1,
                                           INT32_MAX - 1, 3};
static uint8_t f_planes[FPAIRS * FW * FH];
static int16_t f_lut[FYCOUNT];

static void fill_fixture_arrays(void)
{
    for (size_t i = 0; i < sizeof f_planes; ++i)
        f_planes[i] = (uint8_t)(i * 37u + 11u);
    f_planes[0] = 0;
    f_planes[1] = 255;
    for (size_t i = 0; i < FYCOUNT; ++i)
        f_lut[i] = (int16_t)((int32_t)(i * 2731u % 65536u) - 32768);
    f_lut[0] = INT16_MIN;
    f_lut[1] = INT16_MAX;
    f_lut[2] = -1;
    f_lut[3] = 0;
}

static void serialize_or_die(qtool_asset_builder *b, uint8_t **buf, size_t *n)
{
    int rc = qtool_asset_serialize(b, buf, n);
    if (rc != 0)
        fprintf(stderr, "%s\n", b->err);
    assert_int_equal(rc, 0);
    qtool_asset_builder_free(b);
}

static void build_full(uint8_t **buf, size_t *n)
{
    fill_fixture_arrays();
    qtool_asset_builder b;
    qtool_asset_builder_init(&b);
    assert_int_equal(qtool_asset_add_shmp(&b, FW, FH, FK, FC, f_scale, f_bias, f_planes), 0);
    assert_int_equal(qtool_asset_add_pmap(&b, FW, FH, f_xyz), 0);
    assert_int_equal(qtool_asset_add_ylut(&b, FN, FYK, f_lut), 0);
    assert_int_equal(qtool_asset_builder_add(&b, QIBL_FOURCC('X', 'T', 'R', 'A'), "hello", 5), 0);
    serialize_or_die(&b, buf, n);
}

/* "small" asset for the exhaustive loops: SHMP 2x1 k1 grey, PMAP 2x1, YLUT N1 k1, XTRA "abc". */
static void build_small(uint8_t **buf, size_t *n)
{
    const int32_t scale[1] = {-QIBL_Q24_ONE}, bias[1] = {INT32_MIN};
    const uint8_t planes[2] = {0x00, 0xFF};
    const int32_t xyz[6] = {INT32_MIN, -1, 0, 1, INT32_MAX, 65536};
    int16_t lut[6] = {INT16_MIN, -1, 0, 1, INT16_MAX, 16384};
    qtool_asset_builder b;
    qtool_asset_builder_init(&b);
    assert_int_equal(qtool_asset_add_shmp(&b, 2, 1, 1, 1, scale, bias, planes), 0);
    assert_int_equal(qtool_asset_add_pmap(&b, 2, 1, xyz), 0);
    assert_int_equal(qtool_asset_add_ylut(&b, 1, 1, lut), 0);
    assert_int_equal(qtool_asset_builder_add(&b, QIBL_FOURCC('X', 'T', 'R', 'A'), "abc", 3), 0);
    serialize_or_die(&b, buf, n);
}

/* ---- helpers to edit an asset ---------------------------------------------------------------- */

static uint8_t *entry(uint8_t *buf, uint32_t i) { return buf + QIBL_ASSET_HEADER_SIZE + QIBL_ASSET_ENTRY_SIZE * i; }
static uint32_t rd(const uint8_t *p) { return qibl_load_u32le(p); }
static uint8_t *payload_of(uint8_t *buf, uint32_t i) { return buf + rd(entry(buf, i) + 4); }

/* Recomputes the table CRC (after an edit of the table), if the count is in range. */
static void reseal_table(uint8_t *buf, size_t n)
{
    uint32_t count = rd(buf + 12);
    if (count == 0 || count > QIBL_ASSET_MAX_CHUNKS || 24u + 16u * count > n)
        return;
    qtool_store_u32le(buf + 20, qibl_crc32(0, buf + 24, 16u * count));
}

/* Recomputes every in-bounds chunk CRC and then the table CRC (after an edit of a payload). */
static void reseal_all(uint8_t *buf, size_t n)
{
    uint32_t count = rd(buf + 12);
    if (count == 0 || count > QIBL_ASSET_MAX_CHUNKS || 24u + 16u * count > n)
        return;
    for (uint32_t i = 0; i < count; ++i) {
        uint8_t *e = entry(buf, i);
        uint64_t off = rd(e + 4), size = rd(e + 8);
        if (off + size <= n)
            qtool_store_u32le(e + 12, qibl_crc32(0, buf + off, (size_t)size));
    }
    reseal_table(buf, n);
}

/* Sets the u32 at byte `at` of chunk i's payload and re-seals the CRCs. */
static void patch_field(uint8_t *buf, size_t n, uint32_t chunk, uint32_t at, uint32_t v)
{
    qtool_store_u32le(payload_of(buf, chunk) + at, v);
    reseal_all(buf, n);
}

/* slicing-by-8 tables for qibl_asset_open_crc_table, filled once by main() */
static uint32_t crc_table[QIBL_CRC32_TABLE_WORDS];

/* The other two opens against qibl_asset_open's status `full` on the same bytes: the table open
 * agrees always; the structure-only open agrees on everything but the payload CRCs, where it may
 * accept (a payload bit flip) or report the field check behind the CRC. Returns the latter's status. */
static qibl_status_t check_other_opens(const uint8_t *buf, size_t n, qibl_status_t full)
{
    qibl_asset_t a;
    tu_fill_guard(&a, sizeof a);
    qibl_status_t st = qibl_asset_open_crc_table(&a, buf, n, crc_table);
    assert_int_equal(st, full);
    if (st != QIBL_OK)
        assert_true(tu_guard_intact(&a, sizeof a));
    tu_fill_guard(&a, sizeof a);
    st = qibl_asset_open_structure(&a, buf, n);
    if (full != QIBL_E_ASSET_CHUNK_CRC)
        assert_int_equal(st, full);
    else
        assert_true(st == QIBL_OK || st >= QIBL_E_ASSET_BAD_DIMENSIONS);
    if (st != QIBL_OK)
        assert_true(tu_guard_intact(&a, sizeof a));
    return st;
}

/* qibl_asset_open must fail with exactly `want` and leave *out untouched (and the fast-CRC and
 * structure-only opens must reject it the same way, CRC faults aside). */
static void expect_reject(const uint8_t *buf, size_t n, qibl_status_t want)
{
    qibl_asset_t a;
    tu_fill_guard(&a, sizeof a);
    qibl_status_t st = qibl_asset_open(&a, buf, n);
    if (st != want)
        fprintf(stderr, "expected '%s', got '%s'\n", qibl_status_str(want), qibl_status_str(st));
    assert_int_equal(st, want);
    assert_true(tu_guard_intact(&a, sizeof a));
    check_other_opens(buf, n, want);
}

static void expect_ok(const uint8_t *buf, size_t n, qibl_asset_t *a)
{
    qibl_status_t st = qibl_asset_open(a, buf, n);
    if (st != QIBL_OK)
        fprintf(stderr, "expected ok, got '%s'\n", qibl_status_str(st));
    assert_int_equal(st, QIBL_OK);
    qibl_asset_t b, c;
    assert_int_equal(qibl_asset_open_crc_table(&b, buf, n, crc_table), QIBL_OK);
    assert_int_equal(qibl_asset_open_structure(&c, buf, n), QIBL_OK);
    assert_true(b.base == a->base && b.size == a->size && b.chunk_count == a->chunk_count);
    assert_true(c.base == a->base && c.size == a->size && c.chunk_count == a->chunk_count);
}

static int is_named_asset_status(qibl_status_t st)
{
    return st == QIBL_OK || (st >= QIBL_E_ASSET_TRUNCATED_HEADER && st <= QIBL_E_ASSET_MISMATCH);
}

/* Builds an asset from a builder-ready SHMP payload that the test edits (size, fields). */
static void build_raw_shmp(const uint8_t *pl, size_t pl_size, uint8_t **buf, size_t *n)
{
    qtool_asset_builder b;
    qtool_asset_builder_init(&b);
    assert_int_equal(qtool_asset_builder_add(&b, QIBL_CHUNK_SHMP, pl, pl_size), 0);
    serialize_or_die(&b, buf, n);
}

/* ---- CRC and loads -------------------------------------------------------------------------- */

static uint32_t crc_bitwise(uint32_t crc, const uint8_t *p, size_t n)
{
    crc = ~crc;
    for (size_t i = 0; i < n; ++i) {
        crc ^= p[i];
        for (int k = 0; k < 8; ++k)
            crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

static void test_crc32_vectors(void **state)
{
    (void)state;
    assert_int_equal(qibl_crc32(0, (const uint8_t *)"123456789", 9), 0xCBF43926u);
    assert_int_equal(qibl_crc32(0, NULL, 0), 0u);
    assert_int_equal(qibl_crc32(0, (const uint8_t *)"", 0), 0u);
    assert_int_equal(qibl_crc32(0, (const uint8_t *)"a", 1), 0xE8B7BE43u);
    assert_int_equal(qibl_crc32(0, (const uint8_t *)"The quick brown fox jumps over the lazy dog", 43), 0x414FA339u);
    /* continuation: crc(ab) == crc(b | crc(a)) */
    assert_int_equal(qibl_crc32(qibl_crc32(0, (const uint8_t *)"12345", 5), (const uint8_t *)"6789", 4), 0xCBF43926u);
    tu_rng r = {7};
    uint8_t buf[257];
    for (int it = 0; it < 2000; ++it) {
        size_t n = (size_t)(tu_next(&r) % sizeof buf);
        for (size_t i = 0; i < n; ++i)
            buf[i] = (uint8_t)tu_next(&r);
        uint32_t seed = (it & 1) ? tu_u32(&r) : 0u;
        assert_int_equal(qibl_crc32(seed, buf, n), crc_bitwise(seed, buf, n));
    }
}

static void test_crc32_fast(void **state)
{
    (void)state;
    /* table init: named errors, nothing written */
    uint32_t small[QIBL_CRC32_TABLE_WORDS];
    tu_fill_guard(small, sizeof small);
    assert_int_equal(qibl_crc32_table_init(NULL, QIBL_CRC32_TABLE_WORDS), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_crc32_table_init(small, QIBL_CRC32_TABLE_WORDS - 1), QIBL_E_WORKSPACE);
    assert_true(tu_guard_intact(small, sizeof small));
    assert_int_equal(qibl_crc32_table_init(small, QIBL_CRC32_TABLE_WORDS), QIBL_OK);
    assert_memory_equal(small, crc_table, sizeof small);
    assert_int_equal(crc_table[128], 0xEDB88320u); /* the polynomial: byte 0x80 */
    assert_int_equal(qibl_crc32_fast(crc_table, 0, (const uint8_t *)"123456789", 9), 0xCBF43926u);
    assert_int_equal(qibl_crc32_fast(crc_table, 0, NULL, 0), 0u);
    /* every length 0..300 at every alignment 0..7, random seeds: equal to the nibble CRC */
    tu_rng r = {11};
    uint8_t buf[320];
    for (size_t i = 0; i < sizeof buf; ++i)
        buf[i] = (uint8_t)tu_next(&r);
    for (size_t al = 0; al < 8; ++al)
        for (size_t n = 0; n <= 300; ++n) {
            uint32_t seed = (n & 1) ? tu_u32(&r) : 0u;
            assert_int_equal(qibl_crc32_fast(crc_table, seed, buf + al, n), qibl_crc32(seed, buf + al, n));
        }
}

static void test_load_le_edges(void **state)
{
    (void)state;
    const uint8_t m[4] = {0x00, 0x00, 0x00, 0x80}, m1[4] = {0x01, 0x00, 0x00, 0x80};
    const uint8_t x[4] = {0xFF, 0xFF, 0xFF, 0x7F}, ff[4] = {0xFF, 0xFF, 0xFF, 0xFF}, z[4] = {0};
    const uint8_t o[4] = {0x04, 0x03, 0x02, 0x01};
    assert_int_equal(qibl_load_s32le(m), INT32_MIN);
    assert_int_equal(qibl_load_s32le(m1), INT32_MIN + 1);
    assert_int_equal(qibl_load_s32le(x), INT32_MAX);
    assert_int_equal(qibl_load_s32le(ff), -1);
    assert_int_equal(qibl_load_s32le(z), 0);
    assert_int_equal(qibl_load_s32le(o), 0x01020304);
    assert_int_equal(qibl_load_u32le(ff), 0xFFFFFFFFu);
    assert_int_equal(qibl_load_u32le(m), 0x80000000u);
    assert_int_equal(qibl_load_s16le(m + 2), INT16_MIN);
    assert_int_equal(qibl_load_s16le(x + 2), INT16_MAX);
    assert_int_equal(qibl_load_s16le(ff), -1);
    assert_int_equal(qibl_load_s16le(z), 0);
    assert_int_equal(qibl_load_s16le(o), 0x0304);
    const uint8_t s16[2] = {0x01, 0x80};
    assert_int_equal(qibl_load_s16le(s16), INT16_MIN + 1);
    tu_rng r = {3};
    uint8_t b[8];
    for (int i = 0; i < 100000; ++i) {
        int32_t v = tu_s32(&r);
        int16_t h = (int16_t)((int32_t)(tu_u32(&r) & 0xFFFFu) - 32768);
        qtool_store_s32le(b + 1, v); /* odd addresses: loads need no alignment */
        qtool_store_s16le(b + 5, h);
        assert_int_equal(qibl_load_s32le(b + 1), v);
        assert_int_equal(qibl_load_s16le(b + 5), h);
    }
}

/* ---- valid assets --------------------------------------------------------------------------- */

static void check_full_views(const qibl_asset_t *a)
{
    qibl_shmaps_t m;
    assert_int_equal(qibl_asset_shmaps(a, &m), QIBL_OK);
    assert_int_equal(m.width, FW);
    assert_int_equal(m.height, FH);
    assert_int_equal(m.k, FK);
    assert_int_equal(m.channels, FC);
    for (uint32_t i = 0; i < FK; ++i)
        for (uint32_t ch = 0; ch < FC; ++ch) {
            assert_int_equal(qibl_shmaps_scale(&m, i, ch), f_scale[i * FC + ch]);
            assert_int_equal(qibl_shmaps_bias(&m, i, ch), f_bias[i * FC + ch]);
            assert_memory_equal(qibl_shmaps_plane(&m, i, ch), f_planes + (i * FC + ch) * FW * FH, FW * FH);
        }
    qibl_pmap_t p;
    assert_int_equal(qibl_asset_pmap(a, &p), QIBL_OK);
    assert_int_equal(p.width, FW);
    assert_int_equal(p.height, FH);
    for (uint32_t y = 0; y < FH; ++y)
        for (uint32_t x = 0; x < FW; ++x) {
            qibl_q16_t v[4] = {0, 0, 0, 0x5A5A5A5A};
            qibl_pmap_point(&p, x, y, v);
            for (int c = 0; c < 3; ++c)
                assert_int_equal(v[c], f_xyz[3 * (y * FW + x) + (uint32_t)c]);
            assert_int_equal(v[3], 0x5A5A5A5A); /* writes exactly three values */
        }
    qibl_ylut_t l;
    assert_int_equal(qibl_asset_ylut(a, &l), QIBL_OK);
    assert_int_equal(l.face_size, FN);
    assert_int_equal(l.k, FYK);
    for (uint32_t i = 0; i < FYCOUNT; ++i)
        assert_int_equal(qibl_load_s16le(l.values + 2 * i), f_lut[i]);
}

static void test_round_trip(void **state)
{
    (void)state;
    uint8_t *buf;
    size_t n;
    build_full(&buf, &n);
    qibl_asset_t a;
    expect_ok(buf, n, &a);
    assert_ptr_equal(a.base, buf);
    assert_int_equal(a.size, n);
    assert_int_equal(a.chunk_count, 4);
    check_full_views(&a);
    /* views point into the caller's bytes: zero-copy */
    qibl_chunk_t c;
    assert_int_equal(qibl_asset_find(&a, QIBL_CHUNK_SHMP, &c), QIBL_OK);
    assert_ptr_equal(c.data, payload_of(buf, 0));
    assert_int_equal(c.type, QIBL_CHUNK_SHMP);
    assert_int_equal(c.size, 20 + 8 * FPAIRS + FPAIRS * FW * FH);
    assert_int_equal(qibl_asset_find(&a, QIBL_FOURCC('X', 'T', 'R', 'A'), &c), QIBL_OK);
    assert_int_equal(c.size, 5);
    assert_memory_equal(c.data, "hello", 5);
    /* every payload offset is a multiple of 4 and the header says what the buffer holds */
    for (uint32_t i = 0; i < 4; ++i)
        assert_int_equal(rd(entry(buf, i) + 4) % 4u, 0);
    assert_memory_equal(buf, "QIBL\r\n\x1a\n", 8);
    assert_int_equal(rd(buf + 8), QIBL_ASSET_VERSION);
    assert_int_equal(rd(buf + 16), n);
    free(buf);
}

static void test_unaligned_buffers(void **state)
{
    (void)state;
    uint8_t *buf;
    size_t n;
    build_full(&buf, &n);
    uint8_t *big = malloc(n + 8);
    assert_non_null(big);
    for (size_t shift = 1; shift <= 3; ++shift) {
        memcpy(big + shift, buf, n);
        qibl_asset_t a;
        expect_ok(big + shift, n, &a);
        check_full_views(&a);
    }
    free(big);
    free(buf);
}

static void test_longer_buffer_accepted(void **state)
{
    (void)state;
    uint8_t *buf;
    size_t n;
    build_full(&buf, &n);
    uint8_t *big = malloc(n + 100);
    assert_non_null(big);
    memcpy(big, buf, n);
    memset(big + n, 0xEE, 100);
    qibl_asset_t a;
    expect_ok(big, n + 100, &a);
    assert_int_equal(a.size, n); /* file_size, not the buffer length */
    check_full_views(&a);
    free(big);
    free(buf);
}

static void test_unknown_chunk_ignored_but_crc_checked(void **state)
{
    (void)state;
    uint8_t *buf;
    size_t n;
    build_full(&buf, &n);
    /* unknown types may repeat: turn YLUT into a second unknown XTRA */
    qtool_store_u32le(entry(buf, 2), QIBL_FOURCC('X', 'T', 'R', 'A'));
    reseal_table(buf, n);
    qibl_asset_t a;
    expect_ok(buf, n, &a);
    qibl_ylut_t l;
    tu_fill_guard(&l, sizeof l);
    assert_int_equal(qibl_asset_ylut(&a, &l), QIBL_E_ASSET_MISSING_CHUNK);
    assert_true(tu_guard_intact(&l, sizeof l));
    /* but its bytes are CRC-checked */
    payload_of(buf, 3)[4] ^= 0x01;
    expect_reject(buf, n, QIBL_E_ASSET_CHUNK_CRC);
    free(buf);
}

static void test_optional_chunks_absent(void **state)
{
    (void)state;
    const int32_t s[1] = {1}, bi[1] = {2};
    const uint8_t pl[1] = {3};
    qtool_asset_builder b;
    qtool_asset_builder_init(&b);
    assert_int_equal(qtool_asset_add_shmp(&b, 1, 1, 1, 1, s, bi, pl), 0);
    uint8_t *buf;
    size_t n;
    serialize_or_die(&b, &buf, &n);
    qibl_asset_t a;
    expect_ok(buf, n, &a);
    qibl_pmap_t p;
    qibl_ylut_t l;
    qibl_chunk_t c;
    tu_fill_guard(&p, sizeof p);
    tu_fill_guard(&l, sizeof l);
    tu_fill_guard(&c, sizeof c);
    assert_int_equal(qibl_asset_pmap(&a, &p), QIBL_E_ASSET_MISSING_CHUNK);
    assert_int_equal(qibl_asset_ylut(&a, &l), QIBL_E_ASSET_MISSING_CHUNK);
    assert_int_equal(qibl_asset_find(&a, QIBL_FOURCC('N', 'O', 'N', 'E'), &c), QIBL_E_ASSET_MISSING_CHUNK);
    assert_true(tu_guard_intact(&p, sizeof p));
    assert_true(tu_guard_intact(&l, sizeof l));
    assert_true(tu_guard_intact(&c, sizeof c));
    qibl_shmaps_t m;
    assert_int_equal(qibl_asset_shmaps(&a, &m), QIBL_OK);
    assert_int_equal(qibl_shmaps_scale(&m, 0, 0), 1);
    assert_int_equal(qibl_shmaps_bias(&m, 0, 0), 2);
    assert_int_equal(qibl_shmaps_plane(&m, 0, 0)[0], 3);
    /* a zero-initialised asset holds nothing (and is never dereferenced) */
    qibl_asset_t zero = {0};
    assert_int_equal(qibl_asset_shmaps(&zero, &m), QIBL_E_ASSET_MISSING_CHUNK);
    free(buf);
}

static void test_null_pointers(void **state)
{
    (void)state;
    uint8_t *buf;
    size_t n;
    build_full(&buf, &n);
    qibl_asset_t a;
    assert_int_equal(qibl_asset_open(NULL, buf, n), QIBL_E_NULL_POINTER);
    expect_reject(NULL, n, QIBL_E_NULL_POINTER);
    expect_reject(NULL, 0, QIBL_E_NULL_POINTER);
    expect_ok(buf, n, &a);
    qibl_chunk_t c;
    qibl_shmaps_t m;
    qibl_pmap_t p;
    qibl_ylut_t l;
    assert_int_equal(qibl_asset_find(NULL, QIBL_CHUNK_SHMP, &c), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_asset_find(&a, QIBL_CHUNK_SHMP, NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_asset_shmaps(NULL, &m), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_asset_shmaps(&a, NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_asset_pmap(NULL, &p), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_asset_pmap(&a, NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_asset_ylut(NULL, &l), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_asset_ylut(&a, NULL), QIBL_E_NULL_POINTER);
    free(buf);
}

static void test_hand_filled_shmaps_view(void **state)
{
    (void)state;
    uint8_t params[2 * 3 * 8], planes[2 * 3 * 4 * 2];
    for (uint32_t j = 0; j < 6; ++j) {
        qtool_store_s32le(params + 8 * j, -(int32_t)j - 1);
        qtool_store_s32le(params + 8 * j + 4, (int32_t)j * 1000);
    }
    for (size_t i = 0; i < sizeof planes; ++i)
        planes[i] = (uint8_t)i;
    qibl_shmaps_t m = {4, 2, 2, 3, params, planes, QIBL_SHMAPS_PLANAR};
    for (uint32_t i = 0; i < 2; ++i)
        for (uint32_t ch = 0; ch < 3; ++ch) {
            assert_int_equal(qibl_shmaps_scale(&m, i, ch), -(int32_t)(i * 3 + ch) - 1);
            assert_int_equal(qibl_shmaps_bias(&m, i, ch), (int32_t)(i * 3 + ch) * 1000);
            assert_ptr_equal(qibl_shmaps_plane(&m, i, ch), planes + (i * 3 + ch) * 8);
        }
}

/* ---- rejections, one per status, in the order qibl_asset_open checks them --------------------- */

static void test_reject_truncated_header(void **state)
{
    (void)state;
    uint8_t *buf;
    size_t n;
    build_full(&buf, &n);
    expect_reject(buf, 0, QIBL_E_ASSET_TRUNCATED_HEADER);
    expect_reject(buf, 23, QIBL_E_ASSET_TRUNCATED_HEADER);
    free(buf);
}

static void test_reject_bad_magic(void **state)
{
    (void)state;
    uint8_t *buf;
    size_t n;
    build_full(&buf, &n);
    for (int i = 0; i < 8; ++i) {
        buf[i] ^= 0x20;
        expect_reject(buf, n, QIBL_E_ASSET_MAGIC);
        buf[i] ^= 0x20;
    }
    /* text-mode mangling: "\r\n" -> "\n" shifts everything; "\n" -> "\r\n" likewise */
    buf[4] = '\n';
    expect_reject(buf, n, QIBL_E_ASSET_MAGIC);
    free(buf);
}

static void test_reject_unknown_version(void **state)
{
    (void)state;
    uint8_t *buf;
    size_t n;
    build_full(&buf, &n);
    const uint32_t bad[] = {0, 2, 0x01000000u, UINT32_MAX};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        qtool_store_u32le(buf + 8, bad[i]);
        expect_reject(buf, n, QIBL_E_ASSET_VERSION);
    }
    free(buf);
}

static void test_reject_chunk_count(void **state)
{
    (void)state;
    uint8_t *buf;
    size_t n;
    build_full(&buf, &n);
    const uint32_t bad[] = {0, QIBL_ASSET_MAX_CHUNKS + 1, UINT32_MAX, 0x80000000u};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        qtool_store_u32le(buf + 12, bad[i]);
        expect_reject(buf, n, QIBL_E_ASSET_CHUNK_COUNT);
    }
    free(buf);
}

static void test_reject_truncated_table(void **state)
{
    (void)state;
    uint8_t *buf;
    size_t n;
    build_full(&buf, &n);
    size_t table_end = 24 + 16 * 4;
    expect_reject(buf, 24, QIBL_E_ASSET_TRUNCATED_TABLE);
    expect_reject(buf, table_end - 1, QIBL_E_ASSET_TRUNCATED_TABLE);
    /* a count the buffer cannot hold */
    qtool_store_u32le(buf + 12, QIBL_ASSET_MAX_CHUNKS);
    expect_reject(buf, n, QIBL_E_ASSET_TRUNCATED_TABLE);
    qtool_store_u32le(buf + 12, 4);
    /* file_size claiming less than the table */
    qtool_store_u32le(buf + 16, (uint32_t)table_end - 1);
    expect_reject(buf, n, QIBL_E_ASSET_TRUNCATED_TABLE);
    free(buf);
}

static void test_reject_truncated(void **state)
{
    (void)state;
    uint8_t *buf;
    size_t n;
    build_full(&buf, &n);
    expect_reject(buf, n - 1, QIBL_E_ASSET_TRUNCATED);
    expect_reject(buf, 24 + 16 * 4, QIBL_E_ASSET_TRUNCATED);
    qtool_store_u32le(buf + 16, UINT32_MAX); /* file_size larger than the buffer */
    expect_reject(buf, n, QIBL_E_ASSET_TRUNCATED);
    free(buf);
}

static void test_reject_table_crc(void **state)
{
    (void)state;
    uint8_t *buf;
    size_t n;
    build_full(&buf, &n);
    buf[20] ^= 0x80; /* the stored CRC */
    expect_reject(buf, n, QIBL_E_ASSET_TABLE_CRC);
    buf[20] ^= 0x80;
    for (uint32_t i = 0; i < 16 * 4; i += 5) { /* any table byte */
        buf[24 + i] ^= 0x01;
        expect_reject(buf, n, QIBL_E_ASSET_TABLE_CRC);
        buf[24 + i] ^= 0x01;
    }
    free(buf);
}

static void test_reject_chunk_misaligned(void **state)
{
    (void)state;
    for (uint32_t d = 1; d <= 3; ++d) {
        uint8_t *buf;
        size_t n;
        build_full(&buf, &n);
        qtool_store_u32le(entry(buf, 1) + 4, rd(entry(buf, 1) + 4) + d);
        reseal_table(buf, n);
        expect_reject(buf, n, QIBL_E_ASSET_CHUNK_MISALIGNED);
        free(buf);
    }
}

static void test_reject_chunk_past_end(void **state)
{
    (void)state;
    uint8_t *buf;
    size_t n;
    build_full(&buf, &n);
    uint8_t *e = entry(buf, 3); /* XTRA, the last payload: it ends at file_size */
    uint32_t off = rd(e + 4), size = rd(e + 8);
    struct { uint32_t off, size; } bad[] = {
        {off, size + 1},                  /* one byte past file_size */
        {off + 4, size},                  /* moved past the end */
        {0, 4},                           /* into the header */
        {24, 4},                          /* into the table */
        {24 + 16 * 3, 8},                 /* into the last table entry */
        {0xFFFFFFFCu, 8},                 /* offset + size wraps in 32 bits */
        {off, UINT32_MAX},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        qtool_store_u32le(e + 4, bad[i].off);
        qtool_store_u32le(e + 8, bad[i].size);
        reseal_table(buf, n);
        expect_reject(buf, n, QIBL_E_ASSET_CHUNK_PAST_END);
    }
    /* the limit is file_size, not the buffer: a longer buffer does not make it valid */
    uint8_t *big = calloc(n + 64, 1);
    assert_non_null(big);
    memcpy(big, buf, n);
    qtool_store_u32le(entry(big, 3) + 4, off);
    qtool_store_u32le(entry(big, 3) + 8, size + 1);
    reseal_table(big, n);
    expect_reject(big, n + 64, QIBL_E_ASSET_CHUNK_PAST_END);
    free(big);
    free(buf);
}

static void test_reject_duplicate_chunk(void **state)
{
    (void)state;
    const uint32_t known[] = {QIBL_CHUNK_SHMP, QIBL_CHUNK_PMAP, QIBL_CHUNK_YLUT};
    for (size_t k = 0; k < 3; ++k) {
        uint8_t *buf;
        size_t n;
        build_full(&buf, &n);
        /* the unknown chunk (3) becomes a second copy of a known one */
        qtool_store_u32le(entry(buf, 3), known[k]);
        reseal_table(buf, n);
        expect_reject(buf, n, QIBL_E_ASSET_DUPLICATE_CHUNK);
        free(buf);
    }
}

static void test_reject_chunk_overlap(void **state)
{
    (void)state;
    uint8_t *buf;
    size_t n;
    build_full(&buf, &n);
    uint32_t off0 = rd(entry(buf, 0) + 4), size0 = rd(entry(buf, 0) + 8);
    uint32_t off1 = rd(entry(buf, 1) + 4);
    /* XTRA (5 bytes) moved into SHMP, onto its last bytes, and onto PMAP's start */
    const uint32_t at[] = {off0, off0 + 4, (off0 + size0 - 1) & ~3u, off1};
    for (size_t i = 0; i < sizeof at / sizeof at[0]; ++i) {
        qtool_store_u32le(entry(buf, 3) + 4, at[i]);
        reseal_table(buf, n);
        expect_reject(buf, n, QIBL_E_ASSET_CHUNK_OVERLAP);
    }
    /* an empty payload shares no bytes: accepted anywhere in bounds, even inside another */
    qtool_store_u32le(entry(buf, 3) + 4, off0 + 4);
    qtool_store_u32le(entry(buf, 3) + 8, 0);
    qtool_store_u32le(entry(buf, 3) + 12, 0); /* CRC-32 of nothing */
    reseal_table(buf, n);
    qibl_asset_t a;
    expect_ok(buf, n, &a);
    free(buf);
}

static void test_reject_missing_chunk(void **state)
{
    (void)state;
    uint8_t *buf;
    size_t n;
    build_full(&buf, &n);
    qtool_store_u32le(entry(buf, 0), QIBL_FOURCC('S', 'H', 'M', 'Q')); /* SHMP renamed */
    reseal_table(buf, n);
    expect_reject(buf, n, QIBL_E_ASSET_MISSING_CHUNK);
    free(buf);
    /* and an asset built without one */
    qtool_asset_builder b;
    qtool_asset_builder_init(&b);
    const int32_t xyz[3] = {1, 2, 3};
    assert_int_equal(qtool_asset_add_pmap(&b, 1, 1, xyz), 0);
    serialize_or_die(&b, &buf, &n);
    expect_reject(buf, n, QIBL_E_ASSET_MISSING_CHUNK);
    free(buf);
}

static void test_reject_chunk_crc(void **state)
{
    (void)state;
    for (uint32_t c = 0; c < 4; ++c) {
        uint8_t *buf;
        size_t n;
        build_full(&buf, &n);
        uint32_t size = rd(entry(buf, c) + 8);
        payload_of(buf, c)[size - 1] ^= 0x40; /* last payload byte */
        expect_reject(buf, n, QIBL_E_ASSET_CHUNK_CRC);
        payload_of(buf, c)[size - 1] ^= 0x40;
        qtool_store_u32le(entry(buf, c) + 12, rd(entry(buf, c) + 12) ^ 1u); /* stored CRC */
        reseal_table(buf, n);
        expect_reject(buf, n, QIBL_E_ASSET_CHUNK_CRC);
        free(buf);
    }
}

static void test_reject_bad_dimensions(void **state)
{
    (void)state;
    /* chunk, byte offset of the field, bad value */
    const struct { uint32_t chunk, at, v; } bad[] = {
        {0, 0, 0}, {0, 4, 0}, {0, 0, QIBL_ASSET_MAX_DIM + 1}, {0, 4, QIBL_ASSET_MAX_DIM + 1},
        {0, 0, UINT32_MAX}, {0, 4, 0x80000000u},
        {1, 0, 0}, {1, 4, 0}, {1, 0, QIBL_ASSET_MAX_DIM + 1}, {1, 4, UINT32_MAX},
        {2, 0, 0}, {2, 0, QIBL_ASSET_MAX_LUT + 1}, {2, 0, UINT32_MAX},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        uint8_t *buf;
        size_t n;
        build_full(&buf, &n);
        patch_field(buf, n, bad[i].chunk, bad[i].at, bad[i].v);
        expect_reject(buf, n, QIBL_E_ASSET_BAD_DIMENSIONS);
        free(buf);
    }
    /* each side in range but width * height above QIBL_ASSET_MAX_PIXELS */
    uint8_t *buf;
    size_t n;
    build_full(&buf, &n);
    qtool_store_u32le(payload_of(buf, 0), QIBL_ASSET_MAX_DIM);
    patch_field(buf, n, 0, 4, QIBL_ASSET_MAX_PIXELS / QIBL_ASSET_MAX_DIM + 1);
    expect_reject(buf, n, QIBL_E_ASSET_BAD_DIMENSIONS);
    free(buf);
}

static void test_reject_bad_k(void **state)
{
    (void)state;
    const struct { uint32_t chunk, at, v; } bad[] = {
        {0, 8, 0}, {0, 8, 26}, {0, 8, UINT32_MAX}, {2, 4, 0}, {2, 4, 26}, {2, 4, 0x80000000u},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        uint8_t *buf;
        size_t n;
        build_full(&buf, &n);
        patch_field(buf, n, bad[i].chunk, bad[i].at, bad[i].v);
        expect_reject(buf, n, QIBL_E_ASSET_BAD_K);
        free(buf);
    }
}

static void test_reject_bad_channels(void **state)
{
    (void)state;
    const uint32_t bad[] = {0, 2, 4, UINT32_MAX};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        uint8_t *buf;
        size_t n;
        build_full(&buf, &n);
        patch_field(buf, n, 0, 12, bad[i]);
        expect_reject(buf, n, QIBL_E_ASSET_BAD_CHANNELS);
        free(buf);
    }
}

static void test_reject_bad_flags(void **state)
{
    (void)state;
    const struct { uint32_t chunk, at, v; } bad[] = {
        {0, 16, 1}, {0, 16, 0x80000000u}, {1, 8, 1}, {1, 8, UINT32_MAX}, {2, 8, 2},
        /* SHMP: only 0 and QIBL_SHMP_FLAG_INTERLEAVED (0x10) are layouts */
        {0, 16, 2}, {0, 16, 0x20}, {0, 16, 0x11}, {0, 16, QIBL_SHMP_FLAG_INTERLEAVED | 0x80000000u},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        uint8_t *buf;
        size_t n;
        build_full(&buf, &n);
        patch_field(buf, n, bad[i].chunk, bad[i].at, bad[i].v);
        expect_reject(buf, n, QIBL_E_ASSET_BAD_FLAGS);
        free(buf);
    }
}

static void test_reject_size_overflow(void **state)
{
    (void)state;
    /* 8192 x 8192 = QIBL_ASSET_MAX_PIXELS, k 25, RGB: 75 * 2^26 plane bytes > 4 GiB */
    uint8_t pl[20];
    qtool_store_u32le(pl, 8192);
    qtool_store_u32le(pl + 4, 8192);
    qtool_store_u32le(pl + 8, 25);
    qtool_store_u32le(pl + 12, 3);
    qtool_store_u32le(pl + 16, 0);
    uint8_t *buf;
    size_t n;
    build_raw_shmp(pl, sizeof pl, &buf, &n);
    expect_reject(buf, n, QIBL_E_ASSET_SIZE_OVERFLOW);
    free(buf);
    /* grey with k 25 fits 32 bits (25 * 2^26 < 2^32): then the size is merely wrong */
    qtool_store_u32le(pl + 12, 1);
    build_raw_shmp(pl, sizeof pl, &buf, &n);
    expect_reject(buf, n, QIBL_E_ASSET_CHUNK_SIZE);
    free(buf);
}

static void test_reject_chunk_size(void **state)
{
    (void)state;
    fill_fixture_arrays();
    qtool_asset_builder b;
    qtool_asset_builder_init(&b);
    uint8_t *pl;
    size_t pn;
    assert_int_equal(qtool_asset_shmp_payload(&b, FW, FH, FK, FC, f_scale, f_bias, f_planes, &pl, &pn), 0);
    uint8_t *buf;
    size_t n;
    /* shorter than the fixed fields, one byte short, one byte long */
    const size_t sizes[] = {0, 19, 20, pn - 1, pn + 1};
    uint8_t *longer = calloc(pn + 1, 1);
    assert_non_null(longer);
    memcpy(longer, pl, pn);
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; ++i) {
        build_raw_shmp(longer, sizes[i], &buf, &n);
        expect_reject(buf, n, QIBL_E_ASSET_CHUNK_SIZE);
        free(buf);
    }
    free(longer);
    free(pl);
    /* PMAP and YLUT: size off by one, and shorter than their fixed fields */
    for (int which = 0; which < 2; ++which)
        for (int d = -1; d <= 1; d += 2)
            for (int tiny = 0; tiny < 2; ++tiny) {
                uint8_t *q;
                size_t qn;
                if (which == 0)
                    assert_int_equal(qtool_asset_pmap_payload(&b, FW, FH, f_xyz, &q, &qn), 0);
                else
                    assert_int_equal(qtool_asset_ylut_payload(&b, FN, FYK, f_lut, &q, &qn), 0);
                uint8_t *r = calloc(qn + 1, 1);
                assert_non_null(r);
                memcpy(r, q, qn);
                assert_int_equal(qtool_asset_add_shmp(&b, FW, FH, FK, FC, f_scale, f_bias, f_planes), 0);
                assert_int_equal(qtool_asset_builder_add(&b, which ? QIBL_CHUNK_YLUT : QIBL_CHUNK_PMAP, r,
                                                        tiny ? 11 : (size_t)((long)qn + d)), 0);
                serialize_or_die(&b, &buf, &n);
                expect_reject(buf, n, QIBL_E_ASSET_CHUNK_SIZE);
                free(buf);
                free(r);
                free(q);
            }
}

static void test_reject_mismatch(void **state)
{
    (void)state;
    fill_fixture_arrays();
    /* PMAP of the transposed size (same byte count, so only the comparison can catch it) */
    qtool_asset_builder b;
    qtool_asset_builder_init(&b);
    assert_int_equal(qtool_asset_add_shmp(&b, FW, FH, FK, FC, f_scale, f_bias, f_planes), 0);
    assert_int_equal(qtool_asset_add_pmap(&b, FH, FW, f_xyz), 0);
    uint8_t *buf;
    size_t n;
    serialize_or_die(&b, &buf, &n);
    expect_reject(buf, n, QIBL_E_ASSET_MISMATCH);
    free(buf);
    /* YLUT with fewer values per texel than SHMP has maps */
    qtool_asset_builder_init(&b);
    assert_int_equal(qtool_asset_add_shmp(&b, FW, FH, FK, FC, f_scale, f_bias, f_planes), 0);
    assert_int_equal(qtool_asset_add_ylut(&b, FN, FK - 1, f_lut), 0);
    serialize_or_die(&b, &buf, &n);
    expect_reject(buf, n, QIBL_E_ASSET_MISMATCH);
    free(buf);
    /* YLUT k == SHMP k is fine */
    qtool_asset_builder_init(&b);
    assert_int_equal(qtool_asset_add_shmp(&b, FW, FH, FK, FC, f_scale, f_bias, f_planes), 0);
    assert_int_equal(qtool_asset_add_ylut(&b, FN, FK, f_lut), 0);
    serialize_or_die(&b, &buf, &n);
    qibl_asset_t a;
    expect_ok(buf, n, &a);
    free(buf);
}

/* ---- exhaustive and random damage ------------------------------------------------------------ */

static void test_every_truncation(void **state)
{
    (void)state;
    uint8_t *buf;
    size_t n;
    build_small(&buf, &n);
    size_t table_end = 24 + 16 * rd(buf + 12);
    for (size_t len = 0; len < n; ++len) {
        /* an exact-size heap copy, so a sanitizer sees any read past len */
        uint8_t *cut = malloc(len ? len : 1);
        assert_non_null(cut);
        memcpy(cut, buf, len);
        qibl_status_t want = len < 24 ? QIBL_E_ASSET_TRUNCATED_HEADER
                             : len < table_end ? QIBL_E_ASSET_TRUNCATED_TABLE
                                               : QIBL_E_ASSET_TRUNCATED;
        expect_reject(cut, len, want);
        free(cut);
    }
    qibl_asset_t a;
    expect_ok(buf, n, &a);
    free(buf);
}

/* Reads everything a validated asset's views expose (a sanitizer flags any stray read). */
static uint32_t walk(const qibl_asset_t *a)
{
    uint32_t sum = 0;
    qibl_shmaps_t m;
    assert_int_equal(qibl_asset_shmaps(a, &m), QIBL_OK);
    for (uint32_t i = 0; i < m.k; ++i)
        for (uint32_t ch = 0; ch < m.channels; ++ch) {
            sum += (uint32_t)qibl_shmaps_scale(&m, i, ch) + (uint32_t)qibl_shmaps_bias(&m, i, ch);
            for (uint32_t y = 0; y < m.height; ++y)
                for (uint32_t x = 0; x < m.width; ++x)
                    sum += qibl_shmaps_texel(&m, i, ch, x, y);
        }
    qibl_pmap_t p;
    if (qibl_asset_pmap(a, &p) == QIBL_OK) {
        assert_int_equal(p.width, m.width);
        assert_int_equal(p.height, m.height);
        for (uint32_t y = 0; y < p.height; ++y)
            for (uint32_t x = 0; x < p.width; ++x) {
                qibl_q16_t v[3];
                qibl_pmap_point(&p, x, y, v);
                sum += (uint32_t)v[0] + (uint32_t)v[1] + (uint32_t)v[2];
            }
    }
    qibl_ylut_t l;
    if (qibl_asset_ylut(a, &l) == QIBL_OK) {
        assert_true(l.k >= m.k);
        for (uint32_t i = 0; i < 6 * l.face_size * l.face_size * l.k; ++i)
            sum += (uint32_t)qibl_load_s16le(l.values + 2 * i);
    }
    return sum;
}

static void test_every_bit_flip(void **state)
{
    (void)state;
    uint8_t *buf;
    size_t n;
    build_small(&buf, &n);
    /* bytes covered by a check: header, table, payloads (not the zero padding between payloads) */
    uint8_t covered[512] = {0};
    assert_true(n <= sizeof covered);
    uint32_t count = rd(buf + 12);
    memset(covered, 1, 24 + 16 * count);
    for (uint32_t i = 0; i < count; ++i)
        memset(covered + rd(entry(buf, i) + 4), 1, rd(entry(buf, i) + 8));
    uint8_t *copy = malloc(n);
    assert_non_null(copy);
    unsigned undetected = 0;
    for (size_t i = 0; i < n; ++i)
        for (int bit = 0; bit < 8; ++bit) {
            memcpy(copy, buf, n);
            copy[i] ^= (uint8_t)(1u << bit);
            qibl_asset_t a;
            tu_fill_guard(&a, sizeof a);
            qibl_status_t st = qibl_asset_open(&a, copy, n);
            assert_true(is_named_asset_status(st));
            if (covered[i])
                assert_int_not_equal(st, QIBL_OK);
            if (st == QIBL_OK)
                walk(&a);
            else
                assert_true(tu_guard_intact(&a, sizeof a));
            /* the tools' open (qtool_asset_open: slicing-by-8 CRCs): the same verdict and views */
            qibl_asset_t t;
            tu_fill_guard(&t, sizeof t);
            assert_int_equal(qtool_asset_open(&t, copy, n), st);
            if (st == QIBL_OK)
                assert_memory_equal(&t, &a, sizeof t);
            else
                assert_true(tu_guard_intact(&t, sizeof t));
            /* the structure-only open: same verdict except on payload CRCs; what it accepts is
             * still safe to walk */
            qibl_status_t ss = check_other_opens(copy, n, st);
            if (st == QIBL_E_ASSET_CHUNK_CRC && ss == QIBL_OK) {
                ++undetected;
                assert_int_equal(qibl_asset_open_structure(&a, copy, n), QIBL_OK);
                walk(&a);
            }
        }
    /* documented: the structure-only open does not see bit flips inside payload data */
    printf("asset: structure-only open accepted %u of the single-bit flips the CRCs catch\n", undetected);
    assert_true(undetected > 0);
    free(copy);
    free(buf);
}

static void test_fuzz(void **state)
{
    (void)state;
    uint8_t *buf;
    size_t n;
    build_small(&buf, &n);
    uint8_t *copy = malloc(n);
    assert_non_null(copy);
    tu_rng r = {20240501};
    unsigned long ok = 0, hist[QIBL_STATUS_COUNT] = {0};
    for (int it = 0; it < 100000; ++it) {
        memcpy(copy, buf, n);
        int edits = 1 + (int)(tu_next(&r) % 4);
        for (int e = 0; e < edits; ++e) {
            size_t at = (size_t)(tu_next(&r) % n);
            uint64_t how = tu_next(&r);
            if (how & 1)
                copy[at] ^= (uint8_t)(1u << ((how >> 1) & 7));
            else
                copy[at] = (uint8_t)(how >> 8);
        }
        /* half the time re-seal the CRCs, so the edits reach the table and field checks */
        if (it & 1)
            reseal_all(copy, n);
        size_t len = (it % 7 == 0) ? (size_t)(tu_next(&r) % (n + 1)) : n;
        qibl_asset_t a;
        tu_fill_guard(&a, sizeof a);
        qibl_status_t st = qibl_asset_open(&a, copy, len);
        assert_true(is_named_asset_status(st));
        check_other_opens(copy, len, st);
        hist[st]++;
        if (st == QIBL_OK) {
            ++ok;
            walk(&a);
        } else {
            assert_true(tu_guard_intact(&a, sizeof a));
        }
    }
    int reached = 0;
    for (int s = QIBL_E_ASSET_TRUNCATED_HEADER; s <= QIBL_E_ASSET_MISMATCH; ++s)
        reached += hist[s] > 0;
    printf("asset: fuzz, 10^5 damaged copies of a %zu-byte asset: %lu accepted, %d of %d asset statuses reached\n",
           n, ok, reached, QIBL_E_ASSET_MISMATCH - QIBL_E_ASSET_TRUNCATED_HEADER + 1);
    /* the fuzz reached more than the CRC checks */
    assert_true(ok > 0);
    assert_true(hist[QIBL_E_ASSET_CHUNK_SIZE] > 0 || hist[QIBL_E_ASSET_BAD_DIMENSIONS] > 0);
    free(copy);
    free(buf);
}

/* ---- interleaved layout and streaming by rows ------------------------------------------------ */

/* The full fixture with SHMP interleaved (3 px wide: one group of 16, 13 padding pixels). */
static void build_full_interleaved(uint8_t **buf, size_t *n)
{
    fill_fixture_arrays();
    qtool_asset_builder b;
    qtool_asset_builder_init(&b);
    assert_int_equal(qtool_asset_add_shmp_layout(&b, FW, FH, FK, FC, f_scale, f_bias, f_planes, QIBL_SHMAPS_INTERLEAVED), 0);
    assert_int_equal(qtool_asset_add_pmap(&b, FW, FH, f_xyz), 0);
    assert_int_equal(qtool_asset_add_ylut(&b, FN, FYK, f_lut), 0);
    assert_int_equal(qtool_asset_builder_add(&b, QIBL_FOURCC('X', 'T', 'R', 'A'), "hello", 5), 0);
    serialize_or_die(&b, buf, n);
}

static void test_interleaved_round_trip(void **state)
{
    (void)state;
    uint8_t *buf;
    size_t n;
    build_full_interleaved(&buf, &n);
    qibl_asset_t a;
    expect_ok(buf, n, &a);
    qibl_shmaps_t m;
    assert_int_equal(qibl_asset_shmaps(&a, &m), QIBL_OK);
    assert_int_equal(m.layout, QIBL_SHMAPS_INTERLEAVED);
    assert_int_equal(rd(payload_of(buf, 0) + 16), QIBL_SHMP_FLAG_INTERLEAVED);
    assert_int_equal(qibl_shmaps_row_size(&m), 16u * FK * FC);
    assert_int_equal(rd(entry(buf, 0) + 8), 20u + 8u * FPAIRS + FH * 16u * FK * FC);
    for (uint32_t i = 0; i < FK; ++i)
        for (uint32_t ch = 0; ch < FC; ++ch) {
            assert_int_equal(qibl_shmaps_scale(&m, i, ch), f_scale[i * FC + ch]);
            for (uint32_t y = 0; y < FH; ++y)
                for (uint32_t x = 0; x < 16u; ++x) {
                    /* the layout formula of shmaps.h, padding 0 */
                    uint8_t b = m.planes[y * 16u * FK * FC + (ch * FK + i) * 16u + x];
                    assert_int_equal(b, x < FW ? f_planes[((size_t)(i * FC + ch) * FH + y) * FW + x] : 0);
                    if (x < FW)
                        assert_int_equal(qibl_shmaps_texel(&m, i, ch, x, y), b);
                }
        }
    walk(&a);
    /* a planar-sized payload with the interleaved flag (and the reverse) is the wrong size */
    uint8_t *pl;
    size_t pn;
    build_full(&pl, &pn);
    patch_field(pl, pn, 0, 16, QIBL_SHMP_FLAG_INTERLEAVED);
    expect_reject(pl, pn, QIBL_E_ASSET_CHUNK_SIZE);
    patch_field(buf, n, 0, 16, 0);
    expect_reject(buf, n, QIBL_E_ASSET_CHUNK_SIZE);
    free(pl);
    free(buf);
    /* the writer refuses an unknown layout, naming it */
    qtool_asset_builder b;
    qtool_asset_builder_init(&b);
    assert_int_equal(qtool_asset_add_shmp_layout(&b, FW, FH, FK, FC, f_scale, f_bias, f_planes, 7), -1);
    assert_non_null(strstr(b.err, "layout 7"));
    qtool_asset_builder_free(&b);
}

/* Reads an asset's head the way a streaming caller does: ask, read more, ask again. */
static size_t head_rounds(const uint8_t *file, size_t *rounds)
{
    size_t have = 0, need = 0;
    *rounds = 0;
    for (;;) {
        assert_int_equal(qibl_asset_head_size(file, have, &need), QIBL_OK);
        if (need <= have)
            return have;
        have = need;
        ++*rounds;
        assert_true(*rounds <= 4);
    }
}

static void test_stream_head(void **state)
{
    (void)state;
    uint8_t *buf;
    size_t n;
    build_full_interleaved(&buf, &n);
    size_t rounds;
    size_t head = head_rounds(buf, &rounds);
    assert_int_equal(rounds, 4); /* header, table, SHMP's fields, its params */
    assert_int_equal(head, rd(entry(buf, 0) + 4) + 20u + 8u * FPAIRS);
    assert_true(head < n);
    /* an exact-size copy of the head only: nothing past it may be read */
    uint8_t *h = malloc(head);
    assert_non_null(h);
    memcpy(h, buf, head);
    qibl_asset_head_t hd;
    tu_fill_guard(&hd, sizeof hd);
    assert_int_equal(qibl_asset_open_head(&hd, h, head - 1), QIBL_E_ASSET_HEAD_SHORT);
    assert_true(tu_guard_intact(&hd, sizeof hd));
    assert_int_equal(qibl_asset_open_head(&hd, h, head), QIBL_OK);
    qibl_asset_t a;
    expect_ok(buf, n, &a);
    qibl_shmaps_t m;
    qibl_pmap_t pm;
    qibl_ylut_t yl;
    assert_int_equal(qibl_asset_shmaps(&a, &m), QIBL_OK);
    assert_int_equal(qibl_asset_pmap(&a, &pm), QIBL_OK);
    assert_int_equal(qibl_asset_ylut(&a, &yl), QIBL_OK);
    assert_true(hd.maps.width == m.width && hd.maps.height == m.height && hd.maps.k == m.k &&
                hd.maps.channels == m.channels && hd.maps.layout == m.layout && hd.maps.planes == NULL);
    assert_memory_equal(hd.maps.params, m.params, 8u * FPAIRS);
    assert_int_equal(hd.file_size, n);
    assert_int_equal(hd.ylut_offset + 12u, (uint32_t)(yl.values - buf));
    qibl_asset_row_t row;
    for (uint32_t y = 0; y < FH; ++y) {
        assert_int_equal(qibl_asset_row(&hd, y, &row), QIBL_OK);
        assert_int_equal(row.maps_size, qibl_shmaps_row_size(&m));
        assert_ptr_equal(buf + row.maps_offset, m.planes + y * row.maps_size);
        assert_ptr_equal(buf + row.pmap_offset, pm.points + 12u * FW * y);
        assert_int_equal(row.pmap_size, 12u * FW);
    }
    tu_fill_guard(&row, sizeof row);
    assert_int_equal(qibl_asset_row(&hd, FH, &row), QIBL_E_ASSET_ROW);
    assert_true(tu_guard_intact(&row, sizeof row));
    assert_int_equal(qibl_asset_row(NULL, 0, &row), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_asset_row(&hd, 0, NULL), QIBL_E_NULL_POINTER);
    size_t need;
    assert_int_equal(qibl_asset_head_size(NULL, 5, &need), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_asset_head_size(h, head, NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_asset_open_head(NULL, h, head), QIBL_E_NULL_POINTER);
    free(h);

    /* damage the head: every single-bit flip is a named status or (payload bytes) still opens */
    for (size_t i = 0; i < head; ++i)
        for (int bit = 0; bit < 8; ++bit) {
            uint8_t *c = malloc(head);
            assert_non_null(c);
            memcpy(c, buf, head);
            c[i] ^= (uint8_t)(1u << bit);
            qibl_asset_head_t d;
            qibl_status_t st = qibl_asset_head_size(c, head, &need);
            /* a larger chunk count or file size asks for more bytes: not accepted either */
            int more = st == QIBL_OK && need > head;
            if (st == QIBL_OK && !more)
                st = qibl_asset_open_head(&d, c, head);
            assert_true(is_named_asset_status(st) || st == QIBL_E_ASSET_LAYOUT);
            /* what the table and header checks cover is caught */
            if (i < 24u + 16u * 4u && i != 16 && i != 17 && i != 18 && i != 19)
                assert_true(more || st != QIBL_OK);
            free(c);
        }

    /* planar assets do not stream by rows; a file_size, table or SHMP fault is the full open's status */
    uint8_t *pl;
    size_t pn;
    build_full(&pl, &pn);
    size_t ph = head_rounds(pl, &rounds);
    assert_int_equal(qibl_asset_open_head(&hd, pl, ph), QIBL_E_ASSET_LAYOUT);
    patch_field(pl, pn, 0, 8, 26);
    assert_int_equal(qibl_asset_head_size(pl, ph, &need), QIBL_E_ASSET_BAD_K);
    free(pl);
    build_full_interleaved(&pl, &pn);
    qtool_store_u32le(entry(pl, 1) + 8, rd(entry(pl, 1) + 8) - 12u); /* PMAP one row short */
    reseal_table(pl, pn);
    assert_int_equal(qibl_asset_open_head(&hd, pl, head), QIBL_E_ASSET_CHUNK_SIZE);
    pl[0] = 'q';
    assert_int_equal(qibl_asset_head_size(pl, 24, &need), QIBL_E_ASSET_MAGIC);
    free(pl);
    free(buf);
}

/* The streamed views of one file (buf, n: the whole file, the head its first bytes): the head, then
 * the P map from its 12 field bytes and the Y LUT from an exact-size copy of its payload (so ASan sees
 * any read past it). Returns the first failing status; *yl, *pm written only on success. */
static qibl_status_t stream_views(const uint8_t *buf, size_t n, qibl_ylut_t *yl, qibl_pmap_t *pm, uint8_t **ycopy)
{
    size_t rounds, head = head_rounds(buf, &rounds);
    qibl_asset_head_t hd;
    qibl_status_t st = qibl_asset_open_head(&hd, buf, head);
    if (st != QIBL_OK)
        return st;
    assert_true(hd.pmap_offset >= 12u && hd.ylut_size >= 12u && (size_t)hd.ylut_offset + hd.ylut_size <= n);
    qibl_pmap_t p;
    tu_fill_guard(&p, sizeof p);
    st = qibl_asset_head_pmap(&hd, buf + hd.pmap_offset - 12u, 12u, &p);
    if (st != QIBL_OK) {
        assert_true(tu_guard_intact(&p, sizeof p));
        return st;
    }
    uint8_t *y = malloc(hd.ylut_size);
    assert_non_null(y);
    memcpy(y, buf + hd.ylut_offset, hd.ylut_size);
    qibl_ylut_t t;
    tu_fill_guard(&t, sizeof t);
    assert_int_equal(qibl_asset_head_ylut(&hd, y, hd.ylut_size - 1u, &t), QIBL_E_ASSET_HEAD_SHORT);
    assert_true(tu_guard_intact(&t, sizeof t));
    st = qibl_asset_head_ylut(&hd, y, hd.ylut_size, &t);
    if (st != QIBL_OK) {
        assert_true(tu_guard_intact(&t, sizeof t));
        free(y);
        return st;
    }
    *yl = t, *pm = p, *ycopy = y;
    return QIBL_OK;
}

/* Issue 24 class 2: a streamed head must refuse the YLUT (and P map) fields qibl_asset_open refuses,
 * with the same status, and a LUT view whose fields lie must never reach past its bytes. */
static void test_stream_lying_fields(void **state)
{
    (void)state;
    uint8_t *buf;
    size_t n;
    build_full_interleaved(&buf, &n);
    assert_int_equal(rd(entry(buf, 1)), QIBL_CHUNK_PMAP);
    assert_int_equal(rd(entry(buf, 2)), QIBL_CHUNK_YLUT);
    /* {chunk, field offset, value, the status both paths must give} */
    static const struct { uint32_t chunk, at, v; qibl_status_t want; } lies[] = {
        {2, 0, 256, QIBL_E_ASSET_CHUNK_SIZE},   /* face size 256 in a 2x2 payload */
        {2, 0, 3, QIBL_E_ASSET_CHUNK_SIZE},
        {2, 0, 0, QIBL_E_ASSET_BAD_DIMENSIONS},
        {2, 0, 257, QIBL_E_ASSET_BAD_DIMENSIONS},
        {2, 0, 0xFFFFFFFFu, QIBL_E_ASSET_BAD_DIMENSIONS},
        {2, 4, 25, QIBL_E_ASSET_CHUNK_SIZE},    /* k 25 in a k 5 payload */
        {2, 4, 26, QIBL_E_ASSET_BAD_K},
        {2, 4, 0, QIBL_E_ASSET_BAD_K},
        {2, 4, FK - 1u, QIBL_E_ASSET_MISMATCH}, /* fewer than the maps' k */
        {2, 8, 1, QIBL_E_ASSET_BAD_FLAGS},
        {1, 0, FW + 1u, QIBL_E_ASSET_MISMATCH},  /* P map of another width */
        {1, 4, FH - 1u, QIBL_E_ASSET_MISMATCH},
        {1, 0, 0, QIBL_E_ASSET_BAD_DIMENSIONS},
        {1, 4, QIBL_ASSET_MAX_DIM + 1u, QIBL_E_ASSET_BAD_DIMENSIONS},
        {1, 8, 2, QIBL_E_ASSET_BAD_FLAGS},
    };
    for (size_t i = 0; i < sizeof lies / sizeof lies[0]; ++i) {
        uint8_t *c = malloc(n);
        assert_non_null(c);
        memcpy(c, buf, n);
        patch_field(c, n, lies[i].chunk, lies[i].at, lies[i].v);
        expect_reject(c, n, lies[i].want);
        qibl_ylut_t yl;
        qibl_pmap_t pm;
        uint8_t *y = NULL;
        assert_int_equal(stream_views(c, n, &yl, &pm, &y), lies[i].want);
        free(c);
    }
    /* the YLUT's table size lies instead (a whole 2x2 k 4 LUT short of the fields' k 5) */
    uint8_t *c = malloc(n);
    assert_non_null(c);
    memcpy(c, buf, n);
    qtool_store_u32le(entry(c, 2) + 8, rd(entry(c, 2) + 8) - 12u * FN * FN);
    reseal_all(c, n);
    expect_reject(c, n, QIBL_E_ASSET_CHUNK_SIZE);
    qibl_ylut_t yl;
    qibl_pmap_t pm;
    uint8_t *y = NULL;
    assert_int_equal(stream_views(c, n, &yl, &pm, &y), QIBL_E_ASSET_CHUNK_SIZE);

    /* the LUT view built by hand from those fields, as a caller reading asset.h's layout would:
     * relighting through it must be refused before any lookup (ASan: no read past the copy) */
    size_t rounds, head = head_rounds(c, &rounds);
    qibl_asset_head_t hd;
    assert_int_equal(qibl_asset_open_head(&hd, c, head), QIBL_OK);
    uint8_t *ycopy = malloc(hd.ylut_size), *row = malloc(hd.row_size), *prow = malloc(12u * FW);
    assert_true(ycopy && row && prow);
    memcpy(ycopy, c + hd.ylut_offset, hd.ylut_size);
    qibl_asset_row_t rr;
    assert_int_equal(qibl_asset_row(&hd, 0, &rr), QIBL_OK);
    memcpy(row, c + rr.maps_offset, rr.maps_size);
    memcpy(prow, c + rr.pmap_offset, rr.pmap_size);
    qibl_shmaps_t mv;
    qibl_pmap_t whole = {FW, FH, NULL}, pv;
    assert_int_equal(qibl_shmaps_row_view(&hd.maps, row, &mv), QIBL_OK);
    assert_int_equal(qibl_pmap_row_view(&whole, prow, &pv), QIBL_OK);
    const qibl_pointlight_t light = {{1 << 16, 2 << 16, 3 << 16}, {1 << 16, 1 << 16, 1 << 16}, QIBL_FALLOFF_INV_DIST, 0, 0};
    qibl_shmap_point_t pt;
    static const uint32_t faces[][2] = {{FN, FYK}, {256, FYK}, {FN, 25}, {3, FYK}};
    for (size_t i = 0; i < sizeof faces / sizeof faces[0]; ++i) {
        qibl_ylut_t hand = {faces[i][0], faces[i][1], ycopy + 12, hd.ylut_size - 12u};
        assert_int_equal(qibl_ylut_check(&hand), QIBL_E_SHMAP_LUT_SHORT);
        tu_fill_guard(&pt, sizeof pt);
        assert_int_equal(qibl_shmap_point_prepare(&mv, &pv, &hand, &light, &pt), QIBL_E_SHMAP_LUT_SHORT);
        assert_true(tu_guard_intact(&pt, sizeof pt));
        hand.size = 0; /* a view whose size was never set */
        assert_int_equal(qibl_shmap_point_prepare(&mv, &pv, &hand, &light, &pt), QIBL_E_SHMAP_LUT_SHORT);
    }
    /* k above 25 is out of every LUT's range, whatever the size says */
    qibl_ylut_t big = {FN, 26, ycopy + 12, (size_t)-1};
    assert_int_equal(qibl_shmap_point_prepare(&mv, &pv, &big, &light, &pt), QIBL_E_SHMAP_MISMATCH);
    /* qibl_ylut_check, for callers of qibl_ylut_lookup: each field named */
    assert_int_equal(qibl_ylut_check(&big), QIBL_E_SHMAP_K);
    big.k = 0;
    assert_int_equal(qibl_ylut_check(&big), QIBL_E_SHMAP_K);
    big.k = FYK, big.face_size = 0;
    assert_int_equal(qibl_ylut_check(&big), QIBL_E_SHMAP_LUT_SIZE);
    big.face_size = QIBL_YLUT_MAX_FACE + 1u;
    assert_int_equal(qibl_ylut_check(&big), QIBL_E_SHMAP_LUT_SIZE);
    big.face_size = FN, big.size = 12u * FN * FN * FYK;
    assert_int_equal(qibl_ylut_check(&big), QIBL_OK);
    big.size--;
    assert_int_equal(qibl_ylut_check(&big), QIBL_E_SHMAP_LUT_SHORT);
    big.values = NULL;
    assert_int_equal(qibl_ylut_check(&big), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_ylut_check(NULL), QIBL_E_NULL_POINTER);
    free(ycopy), free(row), free(prow), free(c);

    /* the honest file: the streamed views equal the full open's, and the LUT relights row 0 alike */
    assert_int_equal(stream_views(buf, n, &yl, &pm, &y), QIBL_OK);
    qibl_asset_t a;
    expect_ok(buf, n, &a);
    qibl_ylut_t fy;
    qibl_pmap_t fp;
    assert_int_equal(qibl_asset_ylut(&a, &fy), QIBL_OK);
    assert_int_equal(qibl_asset_pmap(&a, &fp), QIBL_OK);
    assert_true(yl.face_size == fy.face_size && yl.k == fy.k && yl.size == fy.size);
    assert_int_equal(fy.size, 12u * FN * FN * FYK);
    assert_int_equal(qibl_ylut_check(&yl), QIBL_OK);
    assert_int_equal(qibl_ylut_check(&fy), QIBL_OK);
    assert_memory_equal(yl.values, fy.values, fy.size);
    assert_true(pm.width == fp.width && pm.height == fp.height && pm.points == NULL);
    qibl_asset_head_t h2;
    head = head_rounds(buf, &rounds);
    assert_int_equal(qibl_asset_open_head(&h2, buf, head), QIBL_OK);
    assert_int_equal(qibl_asset_head_ylut(NULL, y, 1000, &fy), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_asset_head_ylut(&h2, NULL, 1000, &fy), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_asset_head_ylut(&h2, y, 1000, NULL), QIBL_E_NULL_POINTER);
    assert_int_equal(qibl_asset_head_pmap(&h2, y, 11, &fp), QIBL_E_ASSET_HEAD_SHORT);
    assert_int_equal(qibl_asset_head_pmap(NULL, y, 12, &fp), QIBL_E_NULL_POINTER);
    h2.ylut_offset = 0, h2.ylut_size = 0, h2.pmap_offset = 0;
    assert_int_equal(qibl_asset_head_ylut(&h2, y, 1000, &fy), QIBL_E_ASSET_MISSING_CHUNK);
    assert_int_equal(qibl_asset_head_pmap(&h2, y, 12, &fp), QIBL_E_ASSET_MISSING_CHUNK);
    free(y);

    /* a sweep of face sizes and k around the honest ones, every status the full open's */
    for (uint32_t nn = 0; nn <= 5u; ++nn)
        for (uint32_t kk = 0; kk <= 26u; ++kk) {
            c = malloc(n);
            assert_non_null(c);
            memcpy(c, buf, n);
            qtool_store_u32le(payload_of(c, 2), nn);
            qtool_store_u32le(payload_of(c, 2) + 4, kk);
            reseal_all(c, n);
            qibl_asset_t fa;
            qibl_status_t full = qibl_asset_open(&fa, c, n);
            y = NULL;
            assert_int_equal(stream_views(c, n, &yl, &pm, &y), full);
            free(y);
            free(c);
        }
    free(buf);
}

/* ---- the file writer ------------------------------------------------------------------------ */

static void test_write_file(void **state)
{
    (void)state;
    char dir[] = "/tmp/qibl_asset_test_XXXXXX";
    assert_non_null(mkdtemp(dir));
    char path[256], tmp[300];
    snprintf(path, sizeof path, "%s/a.qibl", dir);
    snprintf(tmp, sizeof tmp, "%s.tmp", path);

    fill_fixture_arrays();
    qtool_asset_builder b;
    qtool_asset_builder_init(&b);
    assert_int_equal(qtool_asset_add_shmp(&b, FW, FH, FK, FC, f_scale, f_bias, f_planes), 0);
    assert_int_equal(qtool_asset_add_pmap(&b, FW, FH, f_xyz), 0);
    assert_int_equal(qtool_asset_write_file(&b, path, 1), 0);
    uint8_t *mem;
    size_t n;
    assert_int_equal(qtool_asset_serialize(&b, &mem, &n), 0);
    qtool_asset_builder_free(&b);

    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    uint8_t *disk = malloc(n + 1);
    assert_non_null(disk);
    assert_int_equal(fread(disk, 1, n + 1, f), n);
    fclose(f);
    assert_memory_equal(disk, mem, n);
    assert_int_not_equal(access(tmp, F_OK), 0); /* no leftover tmp */
    free(disk);
    free(mem);

    /* an invalid asset (no SHMP) is refused and the existing file is left as it was */
    struct stat before, after;
    assert_int_equal(stat(path, &before), 0);
    qtool_asset_builder_init(&b);
    const int32_t xyz[3] = {1, 2, 3};
    assert_int_equal(qtool_asset_add_pmap(&b, 1, 1, xyz), 0);
    assert_int_equal(qtool_asset_write_file(&b, path, 0), -1);
    assert_non_null(strstr(b.err, path));
    assert_non_null(strstr(b.err, qibl_status_str(QIBL_E_ASSET_MISSING_CHUNK)));
    assert_int_equal(stat(path, &after), 0);
    assert_int_equal(before.st_size, after.st_size);
    qtool_asset_builder_free(&b);

    /* an unwritable path: -1, one line naming the file */
    char bad[300];
    snprintf(bad, sizeof bad, "%s/no/such/dir/a.qibl", dir);
    qtool_asset_builder_init(&b);
    const int32_t s[1] = {1}, bi[1] = {2};
    const uint8_t pl[1] = {3};
    assert_int_equal(qtool_asset_add_shmp(&b, 1, 1, 1, 1, s, bi, pl), 0);
    assert_int_equal(qtool_asset_write_file(&b, bad, 0), -1);
    assert_non_null(strstr(b.err, bad));
    assert_null(strchr(b.err, '\n'));
    qtool_asset_builder_free(&b);

    /* builder limits */
    qtool_asset_builder_init(&b);
    assert_int_equal(qtool_asset_serialize(&b, &mem, &n), -1); /* no chunks */
    for (uint32_t i = 0; i < QIBL_ASSET_MAX_CHUNKS; ++i)
        assert_int_equal(qtool_asset_builder_add(&b, QIBL_FOURCC('X', 'X', 'X', 'X'), "x", 1), 0);
    assert_int_equal(qtool_asset_builder_add(&b, QIBL_FOURCC('X', 'X', 'X', 'X'), "x", 1), -1);
    qtool_asset_builder_free(&b);

    remove(path);
    rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_crc32_vectors),
        cmocka_unit_test(test_crc32_fast),
        cmocka_unit_test(test_load_le_edges),
        cmocka_unit_test(test_round_trip),
        cmocka_unit_test(test_unaligned_buffers),
        cmocka_unit_test(test_longer_buffer_accepted),
        cmocka_unit_test(test_unknown_chunk_ignored_but_crc_checked),
        cmocka_unit_test(test_optional_chunks_absent),
        cmocka_unit_test(test_null_pointers),
        cmocka_unit_test(test_hand_filled_shmaps_view),
        cmocka_unit_test(test_reject_truncated_header),
        cmocka_unit_test(test_reject_bad_magic),
        cmocka_unit_test(test_reject_unknown_version),
        cmocka_unit_test(test_reject_chunk_count),
        cmocka_unit_test(test_reject_truncated_table),
        cmocka_unit_test(test_reject_truncated),
        cmocka_unit_test(test_reject_table_crc),
        cmocka_unit_test(test_reject_chunk_misaligned),
        cmocka_unit_test(test_reject_chunk_past_end),
        cmocka_unit_test(test_reject_duplicate_chunk),
        cmocka_unit_test(test_reject_chunk_overlap),
        cmocka_unit_test(test_reject_missing_chunk),
        cmocka_unit_test(test_reject_chunk_crc),
        cmocka_unit_test(test_reject_bad_dimensions),
        cmocka_unit_test(test_reject_bad_k),
        cmocka_unit_test(test_reject_bad_channels),
        cmocka_unit_test(test_reject_bad_flags),
        cmocka_unit_test(test_reject_size_overflow),
        cmocka_unit_test(test_reject_chunk_size),
        cmocka_unit_test(test_reject_mismatch),
        cmocka_unit_test(test_every_truncation),
        cmocka_unit_test(test_every_bit_flip),
        cmocka_unit_test(test_fuzz),
        cmocka_unit_test(test_interleaved_round_trip),
        cmocka_unit_test(test_stream_head),
        cmocka_unit_test(test_stream_lying_fields),
        cmocka_unit_test(test_write_file),
    };
    assert_int_equal(qibl_crc32_table_init(crc_table, QIBL_CRC32_TABLE_WORDS), QIBL_OK);
    return cmocka_run_group_tests_name(QIBL_CONFIG_NATIVE_MUL64 ? "asset (native paths)" : "asset (portable M0 paths)",
                                       tests, NULL, NULL);
}
