/*
 * transfer/export.c - the transfer export's writer and reader (transfer/export.h); the layout is
 * qibl/hemi.h's, written field by field in little-endian order whatever the host.
 */
#include "transfer/export.h"

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/atomic.h"
#include "io/file.h"
#include "qibl/asset.h"
#include "qtool.h"

static void put_u16(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v, p[1] = (uint8_t)(v >> 8);
}

static void put_u32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v, p[1] = (uint8_t)(v >> 8), p[2] = (uint8_t)(v >> 16), p[3] = (uint8_t)(v >> 24);
}

int qtool_transfer_export_bytes(const qibl_q30_t (*t)[QIBL_HEMI_COEFFS], uint32_t nv, int bands, uint8_t **out,
                                size_t *n, char *err, size_t errlen)
{
    *out = NULL, *n = 0;
    if (bands < 3 || bands > 5)
        return qtool_errf(err, errlen, "export: bands %d (3, 4 or 5: 9, 16 or 25 coefficients)", bands);
    if (nv == 0 || nv > QIBL_HEMI_XFER_MAX_VERTICES)
        return qtool_errf(err, errlen, "export: %u vertices (1 .. %u)", nv, QIBL_HEMI_XFER_MAX_VERTICES);
    const uint32_t nc = (uint32_t)(bands * bands);
    const size_t payload = (size_t)nv * nc * 4u, total = QIBL_HEMI_XFER_HEADER_SIZE + payload;
    uint8_t *b = malloc(total);
    if (!b)
        return qtool_errf(err, errlen, "export: out of memory");
    memcpy(b, "QTRX", 4);
    put_u16(b + 4, QIBL_HEMI_XFER_VERSION), put_u16(b + 6, (uint32_t)bands);
    put_u32(b + 8, nv), put_u32(b + 12, 30u), put_u32(b + 16, 0u);
    uint8_t *p = b + QIBL_HEMI_XFER_HEADER_SIZE;
    for (uint32_t v = 0; v < nv; ++v)
        for (uint32_t i = 0; i < nc; ++i)
            put_u32(p + 4u * ((size_t)v * nc + i), (uint32_t)t[v][i]); /* two's complement bytes */
    put_u32(b + 20, qibl_crc32(0u, p, payload));
    *out = b, *n = total;
    return 0;
}

int qtool_transfer_export_write(const char *path, const qibl_q30_t (*t)[QIBL_HEMI_COEFFS], uint32_t nv, int bands,
                                char *err, size_t errlen)
{
    uint8_t *b;
    size_t n;
    if (qtool_transfer_export_bytes(t, nv, bands, &b, &n, err, errlen) != 0)
        return -1;
    const int rc = qtool_io_write_atomic(path, b, n, err, errlen);
    free(b);
    return rc;
}

/* a C identifier from path's stem */
static void ident_of(const char *path, char *out, size_t cap)
{
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    size_t k = 0;
    if (isdigit((unsigned char)base[0]) || base[0] == '.' || base[0] == '\0')
        k = (size_t)snprintf(out, cap, "qtr_");
    for (const char *c = base; *c && *c != '.' && k + 1 < cap; ++c)
        out[k++] = isalnum((unsigned char)*c) ? *c : '_';
    out[k] = '\0';
}

int qtool_transfer_export_write_c(const char *path, const uint8_t *bytes, size_t n, const char *ident, char *err,
                                  size_t errlen)
{
    char id[96];
    if (ident)
        snprintf(id, sizeof id, "%s", ident);
    else
        ident_of(path, id, sizeof id);
    qtool_io_atomic a;
    if (qtool_io_atomic_open(&a, path, err, errlen) != 0)
        return -1;
    fprintf(a.f, "/* %s: a qibl transfer export (`qibl transfer --export-c`), the layout of qibl/hemi.h;\n"
                 " * validate with qibl_hemi_xfer_open(&x, %s, %s_SIZE), shade with qibl_hemi_xfer_shade_span. */\n"
                 "#define %s_SIZE %zuu\n"
                 "static const unsigned char %s[%s_SIZE] = {",
            path, id, id, id, n, id, id);
    for (size_t i = 0; i < n; ++i)
        fprintf(a.f, "%s0x%02x%s", i % 16 ? " " : "\n    ", bytes[i], i + 1 < n ? "," : "");
    fprintf(a.f, "\n};\n");
    return qtool_io_atomic_commit(&a, err, errlen);
}

static const char *export_magic(const uint8_t *head, size_t n)
{
    return n >= 4 && memcmp(head, "QTRX", 4) == 0 ? NULL : "not a transfer export (magic QTRX)";
}

int qtool_transfer_export_read(const char *path, uint8_t **buf, size_t *n, char *err, size_t errlen)
{
    const qtool_io_kind kind = {
        .what = "a transfer export (.qtr)", .min_bytes = QIBL_HEMI_XFER_HEADER_SIZE,
        .max_bytes = QIBL_HEMI_XFER_HEADER_SIZE + (size_t)QIBL_HEMI_XFER_MAX_VERTICES * 25u * 4u, .head_bytes = 4,
        .magic = export_magic};
    return qtool_io_load(path, &kind, buf, n, err, errlen);
}
