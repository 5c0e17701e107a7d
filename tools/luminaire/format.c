/*
 * luminaire/format.c - the .qnf near-field source file: reader, checker, encoder, atomic writer.
 *
 * Invariants: the header is checked field by field (each its own error), then its CRC, then the
 * payload size against the file, all before the one allocation; a refused file leaves *out as it
 * was. Byte order is explicit (little-endian) whatever the host.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/atomic.h"
#include "luminaire/luminaire.h"
#include "qibl/asset.h" /* qibl_crc32 */

const char *qtool_luminaire_err_str(qtool_luminaire_err e)
{
    switch (e) {
    case QTOOL_LUMINAIRE_OK: return "ok";
    case QTOOL_LUMINAIRE_E_IO: return "cannot be read";
    case QTOOL_LUMINAIRE_E_NOMEM: return "out of memory";
    case QTOOL_LUMINAIRE_E_TRUNCATED: return "truncated (shorter than its header or payload)";
    case QTOOL_LUMINAIRE_E_MAGIC: return "not a near-field source (magic is not QNF1)";
    case QTOOL_LUMINAIRE_E_VERSION: return "unsupported version (this reader knows 1)";
    case QTOOL_LUMINAIRE_E_HEADER_SIZE: return "header size is not 64";
    case QTOOL_LUMINAIRE_E_GRID: return "grid size outside 1..64";
    case QTOOL_LUMINAIRE_E_RES: return "emission texture size outside 2..128";
    case QTOOL_LUMINAIRE_E_TOO_BIG: return "more than 2^21 texels in all";
    case QTOOL_LUMINAIRE_E_BASIS: return "unknown basis (1 box, 2 tent)";
    case QTOOL_LUMINAIRE_E_SPACING: return "grid spacing not finite or outside 1e-6..1e6";
    case QTOOL_LUMINAIRE_E_DISTANCE: return "plane distance not finite or outside 1e-6..1e6";
    case QTOOL_LUMINAIRE_E_WINDOW: return "window half-tangent not finite or outside 0.01..16";
    case QTOOL_LUMINAIRE_E_CHANNELS: return "channels is not 3";
    case QTOOL_LUMINAIRE_E_PAYLOAD_SIZE: return "payload size is not nx ny res res 12";
    case QTOOL_LUMINAIRE_E_RESERVED: return "reserved header bytes not zero";
    case QTOOL_LUMINAIRE_E_HEADER_CRC: return "header CRC mismatch";
    case QTOOL_LUMINAIRE_E_PAYLOAD_CRC: return "payload CRC mismatch";
    case QTOOL_LUMINAIRE_E_VALUE: return "a texel is not finite";
    case QTOOL_LUMINAIRE_E_TRAILING: return "bytes after the payload";
    case QTOOL_LUMINAIRE_E_WRITE: return "cannot be written";
    }
    return "unknown error";
}

size_t qtool_luminaire_texel(const qtool_luminaire *l, uint32_t ix, uint32_t iy, uint32_t i, uint32_t j)
{
    size_t r = l->res;
    return ((((size_t)iy * l->nx + ix) * r + j) * r + i) * 3u;
}

static uint32_t rd32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static void wr32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v, p[1] = (uint8_t)(v >> 8), p[2] = (uint8_t)(v >> 16), p[3] = (uint8_t)(v >> 24);
}

static float rdf(const uint8_t *p)
{
    uint32_t u = rd32(p);
    float f;
    memcpy(&f, &u, 4);
    return f;
}

static void wrf(uint8_t *p, float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    wr32(p, u);
}

static int in_range(float v, double lo, double hi)
{
    return isfinite(v) && v >= lo && v <= hi;
}

/* The header's fields, in the order the reader checks them (so each file gets exactly one error). */
static qtool_luminaire_err check_fields(uint32_t nx, uint32_t ny, uint32_t res, uint32_t basis, float h, float d,
                                        float w)
{
    if (nx < 1 || nx > QTOOL_LUMINAIRE_MAX_GRID || ny < 1 || ny > QTOOL_LUMINAIRE_MAX_GRID)
        return QTOOL_LUMINAIRE_E_GRID;
    if (res < QTOOL_LUMINAIRE_MIN_RES || res > QTOOL_LUMINAIRE_MAX_RES)
        return QTOOL_LUMINAIRE_E_RES;
    /* nx ny <= 2^12, res^2 <= 2^14: the product fits 64 bits (and 32) */
    if ((uint64_t)nx * ny * res * res > QTOOL_LUMINAIRE_MAX_TEXELS)
        return QTOOL_LUMINAIRE_E_TOO_BIG;
    if (basis != QTOOL_LUMINAIRE_BOX && basis != QTOOL_LUMINAIRE_TENT)
        return QTOOL_LUMINAIRE_E_BASIS;
    if (!in_range(h, 1e-6, 1e6))
        return QTOOL_LUMINAIRE_E_SPACING;
    if (!in_range(d, 1e-6, 1e6))
        return QTOOL_LUMINAIRE_E_DISTANCE;
    if (!in_range(w, 0.01, 16))
        return QTOOL_LUMINAIRE_E_WINDOW;
    return QTOOL_LUMINAIRE_OK;
}

static size_t payload_bytes(const qtool_luminaire *l)
{
    return (size_t)l->nx * l->ny * l->res * l->res * 12u;
}

qtool_luminaire_err qtool_luminaire_decode(const uint8_t *data, size_t n, qtool_luminaire *out)
{
    if (!data || n < QTOOL_LUMINAIRE_HEADER)
        return QTOOL_LUMINAIRE_E_TRUNCATED;
    if (memcmp(data, "QNF1", 4) != 0)
        return QTOOL_LUMINAIRE_E_MAGIC;
    if ((data[4] | data[5] << 8) != QTOOL_LUMINAIRE_VERSION)
        return QTOOL_LUMINAIRE_E_VERSION;
    if ((data[6] | data[7] << 8) != QTOOL_LUMINAIRE_HEADER)
        return QTOOL_LUMINAIRE_E_HEADER_SIZE;
    qtool_luminaire l = {.nx = rd32(data + 8), .ny = rd32(data + 12), .res = rd32(data + 16),
                         .basis = rd32(data + 20), .spacing = rdf(data + 24), .distance = rdf(data + 28),
                         .half_tan = rdf(data + 32)};
    qtool_luminaire_err e = check_fields(l.nx, l.ny, l.res, l.basis, l.spacing, l.distance, l.half_tan);
    if (e != QTOOL_LUMINAIRE_OK)
        return e;
    if (rd32(data + 36) != 3u)
        return QTOOL_LUMINAIRE_E_CHANNELS;
    size_t pb = payload_bytes(&l);
    if (rd32(data + 40) != pb)
        return QTOOL_LUMINAIRE_E_PAYLOAD_SIZE;
    for (int i = 52; i < 64; ++i)
        if (data[i])
            return QTOOL_LUMINAIRE_E_RESERVED;
    if (qibl_crc32(0, data, 48) != rd32(data + 48))
        return QTOOL_LUMINAIRE_E_HEADER_CRC;
    if (n - QTOOL_LUMINAIRE_HEADER < pb)
        return QTOOL_LUMINAIRE_E_TRUNCATED;
    if (n - QTOOL_LUMINAIRE_HEADER > pb)
        return QTOOL_LUMINAIRE_E_TRAILING;
    const uint8_t *p = data + QTOOL_LUMINAIRE_HEADER;
    if (qibl_crc32(0, p, pb) != rd32(data + 44))
        return QTOOL_LUMINAIRE_E_PAYLOAD_CRC;
    for (size_t k = 0; k < pb / 4; ++k)
        if (!isfinite(rdf(p + 4 * k)))
            return QTOOL_LUMINAIRE_E_VALUE;
    l.tex = malloc(pb);
    if (!l.tex)
        return QTOOL_LUMINAIRE_E_NOMEM;
    for (size_t k = 0; k < pb / 4; ++k)
        l.tex[k] = rdf(p + 4 * k);
    *out = l;
    return QTOOL_LUMINAIRE_OK;
}

qtool_luminaire_err qtool_luminaire_read(const char *path, qtool_luminaire *out)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return QTOOL_LUMINAIRE_E_IO;
    /* read no more than the largest legal file plus one byte (so a longer one is TRAILING) */
    const size_t cap = QTOOL_LUMINAIRE_HEADER + (size_t)QTOOL_LUMINAIRE_MAX_TEXELS * 12u + 1u;
    uint8_t *buf = malloc(QTOOL_LUMINAIRE_HEADER);
    size_t n = buf ? fread(buf, 1, QTOOL_LUMINAIRE_HEADER, f) : 0;
    qtool_luminaire_err e = QTOOL_LUMINAIRE_OK;
    if (!buf)
        e = QTOOL_LUMINAIRE_E_NOMEM;
    else if (ferror(f))
        e = QTOOL_LUMINAIRE_E_IO;
    if (e == QTOOL_LUMINAIRE_OK && n == QTOOL_LUMINAIRE_HEADER) {
        /* the header's own checks first: its payload size bounds the rest before a large allocation */
        qtool_luminaire_err he = check_fields(rd32(buf + 8), rd32(buf + 12), rd32(buf + 16), rd32(buf + 20),
                                              rdf(buf + 24), rdf(buf + 28), rdf(buf + 32));
        size_t want = he == QTOOL_LUMINAIRE_OK ? QTOOL_LUMINAIRE_HEADER + (size_t)rd32(buf + 8) * rd32(buf + 12) *
                                                                             rd32(buf + 16) * rd32(buf + 16) * 12u + 1u
                                               : QTOOL_LUMINAIRE_HEADER;
        if (want > cap)
            want = cap;
        uint8_t *nb = realloc(buf, want);
        if (!nb)
            e = QTOOL_LUMINAIRE_E_NOMEM;
        else {
            buf = nb;
            n += fread(buf + n, 1, want - n, f);
            if (ferror(f))
                e = QTOOL_LUMINAIRE_E_IO;
        }
    }
    fclose(f);
    if (e == QTOOL_LUMINAIRE_OK)
        e = qtool_luminaire_decode(buf, n, out);
    free(buf);
    return e;
}

qtool_luminaire_err qtool_luminaire_check(const qtool_luminaire *l)
{
    qtool_luminaire_err e = check_fields(l->nx, l->ny, l->res, l->basis, l->spacing, l->distance, l->half_tan);
    if (e != QTOOL_LUMINAIRE_OK)
        return e;
    if (!l->tex)
        return QTOOL_LUMINAIRE_E_VALUE;
    for (size_t k = 0; k < payload_bytes(l) / 4; ++k)
        if (!isfinite(l->tex[k]))
            return QTOOL_LUMINAIRE_E_VALUE;
    return QTOOL_LUMINAIRE_OK;
}

qtool_luminaire_err qtool_luminaire_encode(const qtool_luminaire *l, uint8_t **bytes, size_t *n)
{
    qtool_luminaire_err e = qtool_luminaire_check(l);
    if (e != QTOOL_LUMINAIRE_OK)
        return e;
    size_t pb = payload_bytes(l), total = QTOOL_LUMINAIRE_HEADER + pb;
    uint8_t *b = calloc(1, total);
    if (!b)
        return QTOOL_LUMINAIRE_E_NOMEM;
    memcpy(b, "QNF1", 4);
    b[4] = QTOOL_LUMINAIRE_VERSION, b[6] = QTOOL_LUMINAIRE_HEADER;
    wr32(b + 8, l->nx), wr32(b + 12, l->ny), wr32(b + 16, l->res), wr32(b + 20, l->basis);
    wrf(b + 24, l->spacing), wrf(b + 28, l->distance), wrf(b + 32, l->half_tan);
    wr32(b + 36, 3u), wr32(b + 40, (uint32_t)pb);
    for (size_t k = 0; k < pb / 4; ++k)
        wrf(b + QTOOL_LUMINAIRE_HEADER + 4 * k, l->tex[k]);
    wr32(b + 44, qibl_crc32(0, b + QTOOL_LUMINAIRE_HEADER, pb));
    wr32(b + 48, qibl_crc32(0, b, 48));
    *bytes = b, *n = total;
    return QTOOL_LUMINAIRE_OK;
}

qtool_luminaire_err qtool_luminaire_write(const char *path, const qtool_luminaire *l, char *err, size_t errlen)
{
    uint8_t *b;
    size_t n;
    qtool_luminaire_err e = qtool_luminaire_encode(l, &b, &n);
    if (e != QTOOL_LUMINAIRE_OK)
        return e;
    int rc = qtool_io_write_atomic(path, b, n, err, errlen);
    free(b);
    return rc == 0 ? QTOOL_LUMINAIRE_OK : QTOOL_LUMINAIRE_E_WRITE;
}

void qtool_luminaire_free(qtool_luminaire *l)
{
    if (l) {
        free(l->tex);
        l->tex = NULL;
    }
}
