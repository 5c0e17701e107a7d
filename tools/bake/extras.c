/*
 * bake/extras.c - the extras file of a sharded bake (format in bake/extras.h).
 */
#include "bake/extras.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/asset_write.h"
#include "io/atomic.h"
#include "io/file.h"
#include "qibl/asset.h"
#include "qibl/lightpath.h"

static const char MAGIC[8] = {'Q', 'I', 'B', 'L', 'X', 'T', 'R', '1'};

static int fail(char *err, size_t errlen, const char *name, const char *fmt, ...)
{
    char m[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(m, sizeof m, fmt, ap);
    va_end(ap);
    if (err && errlen)
        snprintf(err, errlen, "%s: %s", name, m);
    return -1;
}

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
    size_t total = 12;
    for (uint32_t i = 0; i < x->count; ++i) {
        if (x->size[i] > UINT32_MAX)
            return -1;
        total += 12 + x->size[i];
    }
    uint8_t *b = malloc(total), *p = b + 12;
    if (!b)
        return -1;
    memcpy(b, MAGIC, 8);
    qtool_store_u32le(b + 8, x->count);
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
    if (n < 12 || memcmp(b, MAGIC, 8) != 0)
        return fail(err, errlen, name, "not a qibl bake extras file (bad magic or shorter than 12 bytes)");
    uint32_t count = qibl_load_u32le(b + 8);
    if (count > QTOOL_EXTRAS_MAX)
        return fail(err, errlen, name, "%u chunks (at most %d)", count, QTOOL_EXTRAS_MAX);
    size_t at = 12;
    for (uint32_t i = 0; i < count; ++i) {
        if (n - at < 12) {
            qtool_extras_free(&t);
            return fail(err, errlen, name, "truncated at chunk %u of %u", i + 1, count);
        }
        uint32_t type = qibl_load_u32le(b + at), size = qibl_load_u32le(b + at + 4), crc = qibl_load_u32le(b + at + 8);
        if (type != QIBL_CHUNK_LPTH && type != QIBL_CHUNK_LOCC) {
            qtool_extras_free(&t);
            return fail(err, errlen, name, "chunk %u has type 0x%08x (only LPTH and LOCC belong here)", i + 1, type);
        }
        if (size > n - at - 12) {
            qtool_extras_free(&t);
            return fail(err, errlen, name, "chunk %u: %u bytes but only %zu left", i + 1, size, n - at - 12);
        }
        if (qibl_crc32(0, b + at + 12, size) != crc) {
            qtool_extras_free(&t);
            return fail(err, errlen, name, "chunk %u: CRC-32 mismatch (damaged file)", i + 1);
        }
        t.data[i] = malloc(size ? size : 1);
        if (!t.data[i]) {
            qtool_extras_free(&t);
            return fail(err, errlen, name, "out of memory");
        }
        memcpy(t.data[i], b + at + 12, size);
        t.type[i] = type, t.size[i] = size, t.count = i + 1;
        at += 12 + (size_t)size;
    }
    if (at != n) {
        qtool_extras_free(&t);
        return fail(err, errlen, name, "%zu bytes after the last chunk", n - at);
    }
    *x = t;
    return 0;
}

int qtool_extras_write(const qtool_extras *x, const char *path, char *err, size_t errlen)
{
    uint8_t *b;
    size_t n;
    if (qtool_extras_encode(x, &b, &n) != 0)
        return fail(err, errlen, path, "out of memory");
    int rc = qtool_io_write_atomic(path, b, n, err, errlen);
    free(b);
    return rc;
}

static const char *extras_magic(const uint8_t *head, size_t n)
{
    return n >= 8 && memcmp(head, MAGIC, 8) == 0 ? NULL : "not a qibl bake extras file (bad magic)";
}

int qtool_extras_read(const char *path, qtool_extras *x, char *err, size_t errlen)
{
    static const qtool_io_kind k = {"a qibl bake extras file", 12, QTOOL_IO_MAX_FILE_BYTES, 8, extras_magic};
    uint8_t *b;
    size_t n;
    if (qtool_io_load(path, &k, &b, &n, err, errlen) != 0)
        return -1;
    int rc = qtool_extras_decode(b, n, path, x, err, errlen);
    free(b);
    return rc;
}
