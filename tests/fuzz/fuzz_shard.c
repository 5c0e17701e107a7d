/*
 * fuzz_shard.c - libFuzzer target for the bake's partial-sums files and the merge's add
 * (tools/bake: qtool_bake_sums_decode, qtool_bake_sums_compatible, qtool_bake_sums_add).
 *
 * Input: byte 0 flags (bit 0: recompute the CRCs of the first image, bit 1: of the second, so
 * mutations reach the field checks behind the checksums), bytes 1..4 a little-endian split point
 * (taken modulo the rest's length), then the two file images back to back.
 * Invariants checked (abort on violation): a decoded image re-encodes to exactly its bytes; an add
 * that succeeds equals the exact sum of every pair, an add of compatible sums fails exactly when a
 * sum overflows 64 bits, and a failing add changes nothing. The whole input (after the 5 bytes) also
 * goes to the extras-file decoder (bake/extras.h, version 2: each shard's rows of the LPTH/LOCC
 * beside its sums): it fails with a message or re-encodes to exactly its bytes; a decoded file of a
 * split into one shard goes through qtool_extras_join, which fails with a message or gives chunks
 * the core's parsers accept, of the same count and types. It also goes to the tile shards' decoders
 * (bake/tile.h), as given and with its CRCs made right (flags bit 2): a ranges file fails with a
 * message or re-encodes to exactly its bytes; a part fails with a message or passes.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/bake.h"
#include "bake/extras.h"
#include "bake/tile.h"
#include "qibl/asset.h"
#include "qibl/lightpath.h"

static void store32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v, p[1] = (uint8_t)(v >> 8), p[2] = (uint8_t)(v >> 16), p[3] = (uint8_t)(v >> 24);
}

static void fix_crcs(uint8_t *b, size_t n)
{
    if (n < QTOOL_BAKE_SUMS_HEADER)
        return;
    store32(b + 40, qibl_crc32(0, b + QTOOL_BAKE_SUMS_HEADER, n - QTOOL_BAKE_SUMS_HEADER));
    store32(b + 44, qibl_crc32(0, b, 44));
}

/* decodes image (a private copy, CRCs fixed when asked) and checks the round trip */
static int decode(const uint8_t *data, size_t n, int fix, qtool_bake_sums *s)
{
    uint8_t *b = malloc(n ? n : 1);
    if (!b)
        return -1;
    memcpy(b, data, n);
    if (fix)
        fix_crcs(b, n);
    char err[512];
    int rc = qtool_bake_sums_decode(b, n, s, err, sizeof err);
    if (rc == 0) {
        uint8_t *again;
        size_t m;
        if (qtool_bake_sums_encode(s, &again, &m) != 0)
            abort();
        if (m != n || memcmp(again, b, n) != 0) {
            fprintf(stderr, "fuzz_shard: a decoded image does not re-encode to its bytes\n");
            abort();
        }
        free(again);
    } else if (err[0] == '\0') {
        fprintf(stderr, "fuzz_shard: an error without a message\n");
        abort();
    }
    free(b);
    return rc;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 5)
        return 0;
    uint8_t flags = data[0];
    uint32_t split = (uint32_t)data[1] | (uint32_t)data[2] << 8 | (uint32_t)data[3] << 16 | (uint32_t)data[4] << 24;
    data += 5, size -= 5;
    {
        qtool_extras x;
        char err[512] = "";
        if (qtool_extras_decode(data, size, "fuzz", &x, err, sizeof err) == 0) {
            uint8_t *again;
            size_t m;
            if (qtool_extras_encode(&x, &again, &m) != 0 || m != size || memcmp(again, data, size) != 0)
                abort();
            free(again);
            if (x.nshards == 1) {
                qtool_extras j;
                const char *names[1] = {"fuzz"};
                const qtool_extras *one[1] = {&x};
                err[0] = '\0';
                if (qtool_extras_join(one, names, 1, 0, 0, &j, err, sizeof err) == 0) {
                    if (j.count != x.count)
                        abort();
                    for (uint32_t i = 0; i < j.count; ++i) {
                        qibl_lightpath_t lp;
                        qibl_lampocc_t lo;
                        if (j.type[i] != x.type[i] ||
                            (j.type[i] == QIBL_CHUNK_LPTH ? qibl_lightpath_parse(j.data[i], j.size[i], &lp)
                                                          : qibl_lightpath_occl_parse(j.data[i], j.size[i], &lo)) != QIBL_OK)
                            abort();
                    }
                    qtool_extras_free(&j);
                } else if (err[0] == '\0') {
                    abort();
                }
            }
            qtool_extras_free(&x);
        } else if (err[0] == '\0') {
            abort();
        }
    }
    {
        uint8_t *t = malloc(size ? size : 1);
        if (!t)
            abort();
        memcpy(t, data, size);
        if ((flags >> 2) & 1 && size >= QTOOL_TILE_PART_HEADER && memcmp(t, "QIBLPART", 8) == 0) {
            store32(t + 72, qibl_crc32(0, t + QTOOL_TILE_PART_HEADER, size - QTOOL_TILE_PART_HEADER));
            store32(t + 76, qibl_crc32(0, t, 76));
        } else if ((flags >> 2) & 1 && size >= QTOOL_TILE_RANGES_HEADER) { /* a ranges file's CRC fields */
            store32(t + 48, qibl_crc32(0, t + QTOOL_TILE_RANGES_HEADER, size - QTOOL_TILE_RANGES_HEADER));
            store32(t + 52, qibl_crc32(0, t, 52));
        }
        qtool_tile_ranges r;
        char err[512] = "";
        if (qtool_tile_ranges_decode(t, size, "fuzz", &r, err, sizeof err) == 0) {
            uint8_t *again;
            size_t m;
            if (qtool_tile_ranges_encode(&r, &again, &m) != 0 || m != size || memcmp(again, t, size) != 0)
                abort();
            free(again);
            qtool_tile_ranges_free(&r);
        } else if (err[0] == '\0') {
            abort();
        }
        err[0] = '\0';
        if (qtool_tile_part_check(t, size, "fuzz", err, sizeof err) != 0 && err[0] == '\0')
            abort();
        free(t);
    }
    size_t n1 = size ? split % (size + 1) : 0;
    qtool_bake_sums a, b;
    if (decode(data, n1, flags & 1, &a) != 0)
        return 0;
    if (decode(data + n1, size - n1, (flags >> 1) & 1, &b) != 0) {
        qtool_bake_sums_free(&a);
        return 0;
    }
    char err[512];
    size_t nacc = (size_t)a.w * a.h * 3 * a.k;
    int compatible = qtool_bake_sums_compatible(&a, &b, err, sizeof err) == 0;
    int64_t *before = compatible ? malloc(sizeof(int64_t) * (nacc ? nacc : 1)) : NULL;
    if (compatible && !before)
        abort();
    if (before)
        memcpy(before, a.acc, sizeof(int64_t) * nacc);
    int rc = qtool_bake_sums_add(&a, &b, err, sizeof err);
    if (rc == 0 && !compatible)
        abort();
    if (before) {
        int overflow = 0;
        for (size_t i = 0; i < nacc; ++i) {
            int64_t x = before[i], y = b.acc[i];
            if ((y > 0 && x > INT64_MAX - y) || (y < 0 && x < INT64_MIN - y))
                overflow = 1;
            else if (rc == 0 && a.acc[i] != x + y)
                abort();
        }
        if (overflow != (rc != 0))
            abort(); /* overflow must be exactly what fails a compatible add */
        if (rc != 0 && memcmp(before, a.acc, sizeof(int64_t) * nacc) != 0)
            abort(); /* a failing add changes nothing */
        free(before);
    }
    qtool_bake_sums_free(&a);
    qtool_bake_sums_free(&b);
    return 0;
}
