/*
 * bake/extras.c - the extras file of a sharded bake (format in bake/extras.h).
 */
#include "bake/extras.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/asset_write.h"
#include "io/atomic.h"
#include "io/file.h"
#include "qibl/asset.h"
#include "qibl/lightpath.h"
#include "qtool.h"

static const char MAGIC[8] = {'Q', 'I', 'B', 'L', 'X', 'T', 'R', '2'};
static const char MAGIC1[8] = {'Q', 'I', 'B', 'L', 'X', 'T', 'R', '1'};
#define HEAD 20u


void qtool_extras_free(qtool_extras *x)
{
    for (uint32_t i = 0; i < x->count && i < QTOOL_EXTRAS_MAX; ++i)
        free(x->data[i]);
    memset(x, 0, sizeof *x);
}

int qtool_extras_encode(const qtool_extras *x, uint8_t **out, size_t *n)
{
    if (x->count > QTOOL_EXTRAS_MAX)
        return -1;
    size_t total = HEAD;
    for (uint32_t i = 0; i < x->count; ++i) {
        if (x->size[i] > UINT32_MAX)
            return -1;
        total += 12 + x->size[i];
    }
    uint8_t *b = malloc(total), *p = b + HEAD;
    if (!b)
        return -1;
    memcpy(b, MAGIC, 8);
    qtool_store_u32le(b + 8, x->shard), qtool_store_u32le(b + 12, x->nshards), qtool_store_u32le(b + 16, x->count);
    for (uint32_t i = 0; i < x->count; ++i) {
        qtool_store_u32le(p, x->type[i]), qtool_store_u32le(p + 4, (uint32_t)x->size[i]);
        qtool_store_u32le(p + 8, qibl_crc32(0, x->data[i], x->size[i]));
        memcpy(p + 12, x->data[i], x->size[i]);
        p += 12 + x->size[i];
    }
    *out = b, *n = total;
    return 0;
}

int qtool_extras_decode(const uint8_t *b, size_t n, const char *name, qtool_extras *x, char *err, size_t errlen)
{
    qtool_extras t;
    memset(&t, 0, sizeof t);
    if (n >= 8 && memcmp(b, MAGIC1, 8) == 0)
        return qtool_errf(err, errlen, "%s: a version 1 extras file (light paths made by shard 0 alone): re-run the bake's "
                    "shards", name);
    if (n < HEAD || memcmp(b, MAGIC, 8) != 0)
        return qtool_errf(err, errlen, "%s: not a qibl bake extras file (bad magic or shorter than %u bytes)", name, HEAD);
    uint32_t shard = qibl_load_u32le(b + 8), nshards = qibl_load_u32le(b + 12), count = qibl_load_u32le(b + 16);
    if (nshards < 1 || nshards > QTOOL_EXTRAS_MAX_SHARDS || shard >= nshards)
        return qtool_errf(err, errlen, "%s: shard %u/%u outside 0 <= shard < shards <= %u", name, shard, nshards,
                    QTOOL_EXTRAS_MAX_SHARDS);
    if (count > QTOOL_EXTRAS_MAX)
        return qtool_errf(err, errlen, "%s: %u chunks (at most %d)", name, count, QTOOL_EXTRAS_MAX);
    t.shard = shard, t.nshards = nshards;
    size_t at = HEAD;
    for (uint32_t i = 0; i < count; ++i) {
        if (n - at < 12) {
            qtool_extras_free(&t);
            return qtool_errf(err, errlen, "%s: truncated at chunk %u of %u", name, i + 1, count);
        }
        uint32_t type = qibl_load_u32le(b + at), size = qibl_load_u32le(b + at + 4), crc = qibl_load_u32le(b + at + 8);
        if (type != QIBL_CHUNK_LPTH && type != QIBL_CHUNK_LOCC) {
            qtool_extras_free(&t);
            return qtool_errf(err, errlen, "%s: chunk %u has type 0x%08x (only LPTH and LOCC belong here)", name, i + 1, type);
        }
        if (size > n - at - 12) {
            qtool_extras_free(&t);
            return qtool_errf(err, errlen, "%s: chunk %u: %u bytes but only %zu left", name, i + 1, size, n - at - 12);
        }
        if (qibl_crc32(0, b + at + 12, size) != crc) {
            qtool_extras_free(&t);
            return qtool_errf(err, errlen, "%s: chunk %u: CRC-32 mismatch (damaged file)", name, i + 1);
        }
        t.data[i] = malloc(size ? size : 1);
        if (!t.data[i]) {
            qtool_extras_free(&t);
            return qtool_errf(err, errlen, "%s: out of memory", name);
        }
        memcpy(t.data[i], b + at + 12, size);
        t.type[i] = type, t.size[i] = size, t.count = i + 1;
        at += 12 + (size_t)size;
    }
    if (at != n) {
        qtool_extras_free(&t);
        return qtool_errf(err, errlen, "%s: %zu bytes after the last chunk", name, n - at);
    }
    *x = t;
    return 0;
}

int qtool_extras_write(const qtool_extras *x, const char *path, char *err, size_t errlen)
{
    uint8_t *b = NULL;
    size_t n = 0;
    int enc = qtool_extras_encode(x, &b, &n);
    return qtool_io_write_encoded(path, enc, b, n, err, errlen);
}

static const char *extras_magic(const uint8_t *head, size_t n)
{
    if (n >= 8 && memcmp(head, MAGIC1, 8) == 0)
        return NULL; /* refused by name in decode */
    return n >= 8 && memcmp(head, MAGIC, 8) == 0 ? NULL : "not a qibl bake extras file (bad magic)";
}

int qtool_extras_read(const char *path, qtool_extras *x, char *err, size_t errlen)
{
    /* 12: a version 1 file's header, so it reaches decode and is refused by name */
    static const qtool_io_kind k = {"a qibl bake extras file", 12, QTOOL_IO_MAX_FILE_BYTES, 8, extras_magic};
    uint8_t *b;
    size_t n;
    if (qtool_io_load(path, &k, &b, &n, err, errlen) != 0)
        return -1;
    int rc = qtool_extras_decode(b, n, path, x, err, errlen);
    free(b);
    return rc;
}

static const char *chunk_name(uint32_t type)
{
    return type == QIBL_CHUNK_LPTH ? "LPTH" : "LOCC";
}

/* chunk i of every given part joined row by row into *out (malloc'ed): row y from part y % n, empty
 * (0 edges, occlusion 0) where that part is absent; r is the first given part. 0 or -1 with the reason */
static int join_chunk(const qtool_extras *const *parts, const char *const *names, uint32_t n, uint32_t r, uint32_t i,
                      uint32_t bw, uint32_t bh, uint8_t **out, size_t *outn, char *err, size_t errlen)
{
    uint32_t type = parts[r]->type[i], w = 0, h = 0, nkeys = 0;
    uint64_t nedges = 0;
    qibl_lightpath_t l0 = {0};
    for (uint32_t s = r; s < n; ++s) {
        const qtool_extras *p = parts[s];
        uint32_t pw = 0, ph = 0;
        if (!p)
            continue;
        if (p->type[i] != type)
            return qtool_errf(err, errlen, "%s: chunk %u is %s, %s's is %s: shards of different bakes", names[s], i + 1,
                        chunk_name(p->type[i]), names[r], chunk_name(type));
        if (type == QIBL_CHUNK_LPTH) {
            qibl_lightpath_t lp;
            qibl_status_t st = qibl_lightpath_parse(p->data[i], p->size[i], &lp);
            if (st != QIBL_OK)
                return qtool_errf(err, errlen, "%s: chunk %u (LPTH) is not usable: %s", names[s], i + 1, qibl_status_str(st));
            if (s == r)
                l0 = lp;
            else if (lp.kind != l0.kind || lp.nkeys != l0.nkeys || memcmp(lp.keys, l0.keys, 16u * lp.nkeys) != 0)
                return qtool_errf(err, errlen, "%s: light path %u is not the one of %s: another --sun-path or "
                            "--lamp-track (shards of different bakes)", names[s], i + 1, names[r]);
            for (uint32_t y = 0; y < lp.height; ++y) {
                uint32_t a = qibl_load_u32le(lp.rows + 4 * (size_t)y), b = qibl_load_u32le(lp.rows + 4 * (size_t)y + 4);
                if (y % n == s)
                    nedges += b - a;
                else if (b != a)
                    return qtool_errf(err, errlen, "%s: light path %u has edges in row %u, which shard %u/%u bakes "
                                "(not a shard of this split)", names[s], i + 1, y, y % n, n);
            }
            nkeys = lp.nkeys;
        } else {
            qibl_lampocc_t lo;
            qibl_status_t st = qibl_lightpath_occl_parse(p->data[i], p->size[i], &lo);
            if (st != QIBL_OK)
                return qtool_errf(err, errlen, "%s: chunk %u (LOCC) is not usable: %s", names[s], i + 1, qibl_status_str(st));
            pw = lo.width, ph = lo.height;
        }
        if (type == QIBL_CHUNK_LPTH) {
            qibl_lightpath_t lp;
            QIBL_DROP_STATUS(qibl_lightpath_parse(p->data[i], p->size[i], &lp)); /* checked above */
            pw = lp.width, ph = lp.height;
        }
        if (bw && (pw != bw || ph != bh))
            return qtool_errf(err, errlen, "%s: chunk %u (%s) is for a %u x %u bake, the shards are %u x %u (the side "
                        "file of another bake)", names[s], i + 1, chunk_name(type), pw, ph, bw, bh);
        if (s == r)
            w = pw, h = ph;
        else if (pw != w || ph != h)
            return qtool_errf(err, errlen, "%s: chunk %u (%s) is for a %u x %u bake, %s's for %u x %u (shards of "
                        "different bakes)", names[s], i + 1, chunk_name(type), pw, ph, names[r], w, h);
    }
    size_t np = (size_t)w * h;
    if (type == QIBL_CHUNK_LOCC) {
        uint8_t *b = calloc(QIBL_LAMPOCC_HEADER + np, 1);
        if (!b)
            return qtool_errf(err, errlen, "%s: out of memory joining the lamp occlusion", names[r]);
        memcpy(b, parts[r]->data[i], QIBL_LAMPOCC_HEADER);
        for (uint32_t y = 0; y < h; ++y)
            if (parts[y % n])
                memcpy(b + QIBL_LAMPOCC_HEADER + (size_t)y * w,
                       parts[y % n]->data[i] + QIBL_LAMPOCC_HEADER + (size_t)y * w, w);
        *out = b, *outn = QIBL_LAMPOCC_HEADER + np;
        return 0;
    }
    if (nedges > QIBL_LIGHTPATH_MAX_EDGES)
        return qtool_errf(err, errlen, "%s: light path %u: %llu edges joined (at most %u)", names[r], i + 1,
                    (unsigned long long)nedges, QIBL_LIGHTPATH_MAX_EDGES);
    size_t head = QIBL_LIGHTPATH_HEADER + 16u * (size_t)nkeys;
    size_t size = head + 4u * ((size_t)h + 1) + np + 2u * (size_t)nedges;
    uint8_t *b = calloc(size, 1);
    if (!b)
        return qtool_errf(err, errlen, "%s: out of memory joining light path %u", names[r], i + 1);
    memcpy(b, parts[r]->data[i], head); /* size, kind, keys: the same in every part (checked) */
    qtool_store_u32le(b + 20, (uint32_t)nedges);
    uint8_t *rows = b + head, *cnt = rows + 4u * ((size_t)h + 1), *ed = cnt + np;
    uint32_t at = 0;
    for (uint32_t y = 0; y < h; ++y) {
        qtool_store_u32le(rows + 4 * (size_t)y, at);
        if (!parts[y % n])
            continue; /* an absent shard's row: no edges (counts stay 0) */
        qibl_lightpath_t lp;
        QIBL_DROP_STATUS(qibl_lightpath_parse(parts[y % n]->data[i], parts[y % n]->size[i], &lp)); /* checked above */
        uint32_t a = qibl_load_u32le(lp.rows + 4 * (size_t)y), e = qibl_load_u32le(lp.rows + 4 * (size_t)y + 4);
        memcpy(cnt + (size_t)y * w, lp.counts + (size_t)y * w, w);
        memcpy(ed + 2 * (size_t)at, lp.edges + 2 * (size_t)a, 2 * (size_t)(e - a));
        at += e - a;
    }
    qtool_store_u32le(rows + 4 * (size_t)h, at);
    *out = b, *outn = size;
    return 0;
}

int qtool_extras_join(const qtool_extras *const *parts, const char *const *names, uint32_t nshards, uint32_t w,
                      uint32_t h, qtool_extras *out, char *err, size_t errlen)
{
    uint32_t r = 0;
    while (r < nshards && !parts[r])
        ++r;
    if (r == nshards)
        return qtool_errf(err, errlen, "merge: no shards to join");
    for (uint32_t s = r; s < nshards; ++s) {
        if (!parts[s])
            continue;
        if (parts[s]->shard != s || parts[s]->nshards != nshards)
            return qtool_errf(err, errlen, "%s: the extras of shard %u/%u where shard %u/%u was expected (side file "
                        "of another split)", names[s], parts[s]->shard, parts[s]->nshards, s, nshards);
        if (parts[s]->count != parts[r]->count)
            return qtool_errf(err, errlen, "%s: %u light path/occlusion chunk%s, %s has %u: shards of different "
                        "bakes (give every shard the same --sun-path, --lamp-track and --lamp-box)", names[s],
                        parts[s]->count, parts[s]->count == 1 ? "" : "s", names[r], parts[r]->count);
    }
    qtool_extras t;
    memset(&t, 0, sizeof t);
    t.shard = 0, t.nshards = 1;
    for (uint32_t i = 0; i < parts[r]->count; ++i) {
        if (join_chunk(parts, names, nshards, r, i, w, h, &t.data[i], &t.size[i], err, errlen) != 0) {
            qtool_extras_free(&t);
            return -1;
        }
        t.type[i] = parts[r]->type[i], t.count = i + 1;
    }
    *out = t;
    return 0;
}
