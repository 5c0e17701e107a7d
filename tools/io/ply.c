/*
 * io/ply.c - Stanford PLY reader (io/ply.h): the header into a table of elements and properties,
 * checked whole (limits, counts against the file's size) before the body; then one pass over the
 * body that keeps the vertices' x y z and the faces' index lists and steps over everything else.
 */
#include "io/ply.h"
#include "io/file.h"

#include "qtool.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* larger magnitudes are refused: the renderer's bounds and ray offsets stay finite */
#define COORD_MAX 1e15

typedef enum { T_NONE, T_I8, T_U8, T_I16, T_U16, T_I32, T_U32, T_F32, T_F64 } ptype;
static const uint8_t tsize[] = {0, 1, 1, 2, 2, 4, 4, 4, 8};

enum { F_ASCII, F_LE, F_BE };

typedef struct {
    char name[32];
    ptype type;       /* scalar type, or a list's item type */
    ptype count_type; /* T_NONE: a scalar */
} prop;

typedef struct {
    char name[32];
    uint64_t count;
    int nprop;
    prop p[QTOOL_PLY_MAX_PROPS];
} elem;

typedef struct {
    const uint8_t *p;
    size_t n, pos;
    int fmt;
    const char *name;
    char *err;
    size_t errlen;
} body;

static ptype type_of(const char *s)
{
    static const struct {
        const char *a, *b;
        ptype t;
    } names[] = {{"char", "int8", T_I8},     {"uchar", "uint8", T_U8},     {"short", "int16", T_I16},
                 {"ushort", "uint16", T_U16}, {"int", "int32", T_I32},     {"uint", "uint32", T_U32},
                 {"float", "float32", T_F32}, {"double", "float64", T_F64}};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; ++i)
        if (strcmp(s, names[i].a) == 0 || strcmp(s, names[i].b) == 0)
            return names[i].t;
    return T_NONE;
}

int qtool_ply_sniff(const uint8_t *buf, size_t len)
{
    return len >= 4 && memcmp(buf, "ply", 3) == 0 && (buf[3] == '\n' || buf[3] == '\r');
}

/* ---- body values ------------------------------------------------------------------------------- */

/* the next whitespace-separated ascii token into tok (64 bytes); 0, or -1 at the end / too long */
static int token(body *b, char tok[64])
{
    while (b->pos < b->n && (b->p[b->pos] == ' ' || b->p[b->pos] == '\t' || b->p[b->pos] == '\r' ||
                             b->p[b->pos] == '\n'))
        ++b->pos;
    size_t k = 0;
    while (b->pos < b->n && !(b->p[b->pos] == ' ' || b->p[b->pos] == '\t' || b->p[b->pos] == '\r' ||
                               b->p[b->pos] == '\n')) {
        if (k == 63)
            return -1;
        tok[k++] = (char)b->p[b->pos++];
    }
    tok[k] = '\0';
    return k ? 0 : -1;
}

/* One value of type t: *d always, and *iv for integer types (*isint 1). 0, or -1 with the reason in
 * b->err (what: the element and instance, for the message). */
static int value(body *b, ptype t, double *d, long long *iv, const char *what)
{
    int isint = t != T_F32 && t != T_F64;
    if (b->fmt == F_ASCII) {
        char tok[64], *end;
        if (token(b, tok) != 0)
            return qtool_errf_at(b->err, b->errlen, b->name, 0, "%s: the body ends early (or a value is over 63 characters)", what);
        errno = 0;
        if (isint) {
            long long v = strtoll(tok, &end, 10);
            static const long long lo[] = {0, -128, 0, -32768, 0, -2147483648LL, 0};
            static const long long hi[] = {0, 127, 255, 32767, 65535, 2147483647LL, 4294967295LL};
            if (*end || end == tok || errno == ERANGE || v < lo[t] || v > hi[t])
                return qtool_errf_at(b->err, b->errlen, b->name, 0, "%s: '%s' is not a %d-byte %s integer", what, tok,
                            tsize[t], (t == T_I8 || t == T_I16 || t == T_I32) ? "signed" : "unsigned");
            *iv = v, *d = (double)v;
        } else {
            double v = strtod(tok, &end);
            if (*end || end == tok)
                return qtool_errf_at(b->err, b->errlen, b->name, 0, "%s: '%s' is not a number", what, tok);
            *d = v, *iv = 0;
        }
        return 0;
    }
    size_t sz = tsize[t];
    if (b->n - b->pos < sz)
        return qtool_errf_at(b->err, b->errlen, b->name, 0, "%s: the body ends early (%zu bytes)", what, b->n);
    uint64_t u = 0;
    for (size_t i = 0; i < sz; ++i) /* explicit byte order */
        u |= (uint64_t)b->p[b->pos + (b->fmt == F_LE ? i : sz - 1 - i)] << (8 * i);
    b->pos += sz;
    switch (t) {
    case T_I8:
        *iv = u >= 0x80u ? (long long)u - 0x100 : (long long)u;
        break;
    case T_I16:
        *iv = u >= 0x8000u ? (long long)u - 0x10000 : (long long)u;
        break;
    case T_I32:
        *iv = u >= 0x80000000u ? (long long)u - 0x100000000LL : (long long)u;
        break;
    case T_U8:
    case T_U16:
    case T_U32:
        *iv = (long long)u;
        break;
    case T_F32: {
        uint32_t w = (uint32_t)u;
        float f;
        memcpy(&f, &w, 4);
        *d = f, *iv = 0;
        return 0;
    }
    default: {
        double f;
        memcpy(&f, &u, 8);
        *d = f, *iv = 0;
        return 0;
    }
    }
    *d = (double)*iv;
    return 0;
}

/* ---- header ------------------------------------------------------------------------------------ */

/* Parses the header; sets *fmt, the elements and *hlen (bytes up to the body). 0 or -1. */
static int header(const char *name, const uint8_t *buf, size_t len, int *fmt, elem *el, int *nel, size_t *hlen,
                  char *err, size_t errlen)
{
    size_t pos = 0;
    int line = 0, have_fmt = 0;
    *nel = 0;
    for (;;) {
        size_t s = pos;
        while (pos < len && pos < QTOOL_PLY_MAX_HEADER && buf[pos] != '\n')
            ++pos;
        if (pos >= len || pos >= QTOOL_PLY_MAX_HEADER)
            return qtool_errf_at(err, errlen, name, 0, "no end_header within the first %d bytes (or the file ends in the header)",
                        QTOOL_PLY_MAX_HEADER);
        size_t e = pos++;
        if (e > s && buf[e - 1] == '\r')
            --e;
        ++line;
        if (line == 1) {
            if (e - s != 3 || memcmp(buf + s, "ply", 3) != 0)
                return qtool_errf_at(err, errlen, name, 0, "not a PLY file (the first line is not 'ply')");
            continue;
        }
        if ((e - s >= 8 && memcmp(buf + s, "comment", 7) == 0 && (buf[s + 7] == ' ' || buf[s + 7] == '\t')) ||
            (e - s == 7 && memcmp(buf + s, "comment", 7) == 0) ||
            (e - s >= 9 && memcmp(buf + s, "obj_info", 8) == 0 && (buf[s + 8] == ' ' || buf[s + 8] == '\t')))
            continue;
        char l[256], *tok[8];
        if (e - s >= sizeof l)
            return qtool_errf_at(err, errlen, name, 0, "header line %d is over %zu characters", line, sizeof l - 1);
        memcpy(l, buf + s, e - s);
        l[e - s] = '\0';
        if (memchr(l, '\0', e - s))
            return qtool_errf_at(err, errlen, name, 0, "header line %d holds a NUL byte", line);
        int nt = 0;
        char *save = NULL;
        for (char *p = strtok_r(l, " \t", &save); p && nt < 8; p = strtok_r(NULL, " \t", &save))
            tok[nt++] = p;
        if (nt == 0)
            continue;
        if (strcmp(tok[0], "end_header") == 0 && nt == 1) {
            *hlen = pos;
            break;
        }
        if (strcmp(tok[0], "format") == 0) {
            if (have_fmt || nt != 3 || strcmp(tok[2], "1.0") != 0)
                return qtool_errf_at(err, errlen, name, 0, "header line %d: a format line must come once, as 'format KIND 1.0'",
                            line);
            if (strcmp(tok[1], "ascii") == 0)
                *fmt = F_ASCII;
            else if (strcmp(tok[1], "binary_little_endian") == 0)
                *fmt = F_LE;
            else if (strcmp(tok[1], "binary_big_endian") == 0)
                *fmt = F_BE;
            else
                return qtool_errf_at(err, errlen, name, 0, "header line %d: unknown format '%s'", line, tok[1]);
            have_fmt = 1;
        } else if (strcmp(tok[0], "element") == 0) {
            if (nt != 3)
                return qtool_errf_at(err, errlen, name, 0, "header line %d: 'element NAME COUNT' expected", line);
            if (*nel == QTOOL_PLY_MAX_ELEMENTS)
                return qtool_errf_at(err, errlen, name, 0, "more than %d elements", QTOOL_PLY_MAX_ELEMENTS);
            if (strlen(tok[1]) >= sizeof el->name)
                return qtool_errf_at(err, errlen, name, 0, "header line %d: element name over 31 characters", line);
            uint64_t c = 0;
            const char *q = tok[2];
            for (; *q >= '0' && *q <= '9' && c <= 0xFFFFFFFFu; ++q)
                c = c * 10 + (uint64_t)(*q - '0');
            if (*q || q == tok[2] || c > 0xFFFFFFFFu)
                return qtool_errf_at(err, errlen, name, 0, "header line %d: element %s count '%s' is not a count", line, tok[1],
                            tok[2]);
            elem *x = &el[(*nel)++];
            memset(x, 0, sizeof *x);
            strcpy(x->name, tok[1]);
            x->count = c;
        } else if (strcmp(tok[0], "property") == 0) {
            if (*nel == 0)
                return qtool_errf_at(err, errlen, name, 0, "header line %d: a property before any element", line);
            elem *x = &el[*nel - 1];
            if (x->nprop == QTOOL_PLY_MAX_PROPS)
                return qtool_errf_at(err, errlen, name, 0, "element %s has more than %d properties", x->name, QTOOL_PLY_MAX_PROPS);
            prop *p = &x->p[x->nprop];
            const char *pname;
            if (nt == 5 && strcmp(tok[1], "list") == 0) {
                p->count_type = type_of(tok[2]), p->type = type_of(tok[3]), pname = tok[4];
                if (p->count_type == T_NONE || p->count_type == T_F32 || p->count_type == T_F64)
                    return qtool_errf_at(err, errlen, name, 0, "header line %d: list count type '%s' is not an integer type",
                                line, tok[2]);
            } else if (nt == 3) {
                p->count_type = T_NONE, p->type = type_of(tok[1]), pname = tok[2];
            } else {
                return qtool_errf_at(err, errlen, name, 0, "header line %d: 'property TYPE NAME' or 'property list CTYPE TYPE "
                            "NAME' expected", line);
            }
            if (p->type == T_NONE)
                return qtool_errf_at(err, errlen, name, 0, "header line %d: unknown type '%s'", line,
                            p->count_type ? tok[3] : tok[1]);
            if (strlen(pname) >= sizeof p->name)
                return qtool_errf_at(err, errlen, name, 0, "header line %d: property name over 31 characters", line);
            for (int j = 0; j < x->nprop; ++j) /* which of two x's would be the vertex's x? */
                if (strcmp(x->p[j].name, pname) == 0)
                    return qtool_errf_at(err, errlen, name, 0, "header line %d: element %s has property %s twice", line, x->name,
                                pname);
            strcpy(p->name, pname);
            x->nprop++;
        } else {
            return qtool_errf_at(err, errlen, name, 0, "header line %d: unknown keyword '%s'", line, tok[0]);
        }
        if (!have_fmt && strcmp(tok[0], "format") != 0)
            return qtool_errf_at(err, errlen, name, 0, "header line %d: '%s' before the format line", line, tok[0]);
    }
    if (!have_fmt)
        return qtool_errf_at(err, errlen, name, 0, "no format line");
    return 0;
}

/* ---- the mesh ---------------------------------------------------------------------------------- */

static void face_normal(const double *a, const double *b, const double *c, double n[3])
{
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    n[0] = u[1] * v[2] - u[2] * v[1], n[1] = u[2] * v[0] - u[0] * v[2], n[2] = u[0] * v[1] - u[1] * v[0];
}

/* scaled by the largest component first: a cross product of tiny edges squares to a subnormal
 * (or 0) and its root would leave a vector that is not of unit length */
static void unit(double n[3])
{
    double m = fmax(fabs(n[0]), fmax(fabs(n[1]), fabs(n[2])));
    if (!(m > 0) || !isfinite(m)) {
        n[0] = n[1] = n[2] = 0;
        return;
    }
    double x = n[0] / m, y = n[1] / m, z = n[2] / m, l = sqrt(x * x + y * y + z * z);
    n[0] = x / l, n[1] = y / l, n[2] = z / l;
}

/* triangles (index triples) and vertices into the corner soup with area-weighted vertex normals */
static int build(const double *v, size_t nv, const uint32_t *t, size_t ntri, qtool_obj_mesh *out)
{
    double *vn = calloc(nv * 3 + 1, sizeof *vn);
    out->pos = malloc(ntri * 9 * sizeof(double));
    out->nrm = malloc(ntri * 9 * sizeof(double));
    if (!vn || !out->pos || !out->nrm) {
        free(vn), free(out->pos), free(out->nrm);
        return -1;
    }
    for (size_t i = 0; i < ntri; ++i) {
        double n[3];
        face_normal(v + 3 * t[3 * i], v + 3 * t[3 * i + 1], v + 3 * t[3 * i + 2], n);
        for (int c = 0; c < 3; ++c)
            for (int j = 0; j < 3; ++j)
                vn[3 * t[3 * i + (size_t)c] + (size_t)j] += n[j];
    }
    for (size_t i = 0; i < ntri; ++i) {
        double fn[3];
        face_normal(v + 3 * t[3 * i], v + 3 * t[3 * i + 1], v + 3 * t[3 * i + 2], fn);
        unit(fn);
        for (int c = 0; c < 3; ++c) {
            size_t k = t[3 * i + (size_t)c];
            double n[3] = {vn[3 * k], vn[3 * k + 1], vn[3 * k + 2]};
            unit(n);
            if (n[0] == 0 && n[1] == 0 && n[2] == 0) /* opposite faces cancelled: the face's own */
                memcpy(n, fn, sizeof n);
            memcpy(out->pos + 9 * i + 3 * (size_t)c, v + 3 * k, 3 * sizeof(double));
            memcpy(out->nrm + 9 * i + 3 * (size_t)c, n, sizeof n);
        }
    }
    free(vn);
    out->ntri = ntri, out->nvert = nv, out->nnormals_given = 0;
    return 0;
}

/* One pass over the body: every value checked; with v and tri NULL it only counts the triangles
 * the faces fan into (*ntri, exact, even past max_tri: the message names the right count), else it
 * stores the coordinates and the triangles (the counting pass sized them). 0, or -1 with the reason. */
static int body_pass(const char *name, body b, const elem *el, int nel, int vi, int fi, int px, int py, int pz, int pf,
                     size_t nv, double *v, uint32_t *tri, size_t *ntri_out, char *err, size_t errlen)
{
    size_t ntri = 0;
    int rc = 0;
    for (int i = 0; rc == 0 && i < nel; ++i) {
        const elem *x = &el[i];
        for (uint64_t k = 0; rc == 0 && k < x->count; ++k) {
            char what[96];
            snprintf(what, sizeof what, "%s %llu", x->name, (unsigned long long)k);
            for (int j = 0; rc == 0 && j < x->nprop; ++j) {
                const prop *p = &x->p[j];
                double d;
                long long iv;
                if (!p->count_type) {
                    if ((rc = value(&b, p->type, &d, &iv, what)) != 0)
                        break;
                    if (i == vi && (j == px || j == py || j == pz)) {
                        if (!isfinite(d) || fabs(d) > COORD_MAX) {
                            rc = qtool_errf_at(err, errlen, name, 0, "%s: %s = %g is not a finite coordinate within +-1e15", what,
                                      p->name, d);
                            break;
                        }
                        if (v)
                            v[3 * k + (j == px ? 0 : j == py ? 1 : 2)] = d;
                    }
                    continue;
                }
                if ((rc = value(&b, p->count_type, &d, &iv, what)) != 0)
                    break;
                int is_face = i == fi && j == pf;
                /* every item takes at least one byte (binary: its size): a count the rest cannot hold is bad */
                size_t minb = b.fmt == F_ASCII ? 1 : tsize[p->type];
                if (is_face && (iv < 3 || iv > QTOOL_PLY_MAX_POLY)) {
                    rc = qtool_errf_at(err, errlen, name, 0, "%s: %lld vertices (a face has 3..%d)", what, iv, QTOOL_PLY_MAX_POLY);
                    break;
                }
                if (iv < 0 || (uint64_t)iv > (b.n - b.pos) / minb + 1) {
                    rc = qtool_errf_at(err, errlen, name, 0, "%s: list %s of %lld items runs past the end of the file", what,
                              p->name, iv);
                    break;
                }
                uint32_t idx[QTOOL_PLY_MAX_POLY];
                long long cnt = iv;
                for (long long q = 0; rc == 0 && q < cnt; ++q) {
                    if ((rc = value(&b, p->type, &d, &iv, what)) != 0)
                        break;
                    if (is_face) {
                        if (iv < 0 || (uint64_t)iv >= nv) {
                            rc = qtool_errf_at(err, errlen, name, 0, "%s: vertex index %lld outside 0..%lld", what, iv,
                                      (long long)nv - 1);
                            break;
                        }
                        idx[q] = (uint32_t)iv;
                    }
                }
                if (rc != 0 || !is_face)
                    continue;
                if (!tri) { /* counting: at most 254 per face, 2^32 faces: no overflow */
                    ntri += (size_t)cnt - 2;
                    continue;
                }
                for (long long q = 1; q + 1 < cnt; ++q, ++ntri)
                    tri[3 * ntri] = idx[0], tri[3 * ntri + 1] = idx[q], tri[3 * ntri + 2] = idx[q + 1];
            }
        }
    }
    *ntri_out = ntri;
    return rc;
}

int qtool_ply_parse_max(const char *name, const uint8_t *buf, size_t len, size_t max_triangles, qtool_obj_mesh *out,
                        char *err, size_t errlen)
{
    if (max_triangles > QTOOL_PLY_MAX_TRIANGLES)
        max_triangles = QTOOL_PLY_MAX_TRIANGLES;
    if (!name)
        name = "ply";
    memset(out, 0, sizeof *out);
    int fmt = F_ASCII, nel = 0;
    size_t hlen = 0;
    elem *el = malloc(sizeof *el * QTOOL_PLY_MAX_ELEMENTS);
    if (!el)
        return qtool_errf_at(err, errlen, name, 0, "out of memory");
    if (header(name, buf, len, &fmt, el, &nel, &hlen, err, errlen) != 0) {
        free(el);
        return -1;
    }
    /* what the header promises, checked whole before the body */
    int vi = -1, fi = -1, px = -1, py = -1, pz = -1, pf = -1;
    uint64_t need = 0;
    for (int i = 0; i < nel; ++i) {
        elem *x = &el[i];
        uint64_t per = 0;
        for (int j = 0; j < x->nprop; ++j)
            per += fmt == F_ASCII ? 2 : tsize[x->p[j].count_type ? x->p[j].count_type : x->p[j].type];
        need += x->count * per; /* count < 2^32, per <= 64 * 8: no overflow */
        if (strcmp(x->name, "vertex") == 0 || strcmp(x->name, "face") == 0) {
            int isv = x->name[0] == 'v';
            if ((isv ? vi : fi) >= 0) {
                int r = qtool_errf_at(err, errlen, name, 0, "two %s elements", x->name);
                free(el);
                return r;
            }
            *(isv ? &vi : &fi) = i;
        }
    }
    const char *why = NULL;
    if (vi < 0)
        why = "no vertex element";
    else if (fi < 0)
        why = "no face element (a point cloud, not a mesh)";
    else if (el[vi].count > QTOOL_PLY_MAX_VERTICES)
        why = "too many vertices";
    else if (el[fi].count > QTOOL_PLY_MAX_FACES)
        why = "too many faces";
    for (int j = 0; !why && j < el[vi].nprop; ++j) {
        const prop *p = &el[vi].p[j];
        int *slot = strcmp(p->name, "x") == 0 ? &px
                    : strcmp(p->name, "y") == 0 ? &py
                    : strcmp(p->name, "z") == 0 ? &pz
                                                : NULL;
        if (slot && p->count_type)
            why = "vertex x, y or z is a list";
        else if (slot)
            *slot = j;
    }
    for (int j = 0; !why && j < el[fi].nprop; ++j)
        if (strcmp(el[fi].p[j].name, "vertex_indices") == 0 || strcmp(el[fi].p[j].name, "vertex_index") == 0)
            pf = j;
    if (!why && (px < 0 || py < 0 || pz < 0))
        why = "the vertex element lacks x, y or z";
    else if (!why && (pf < 0 || !el[fi].p[pf].count_type))
        why = "the face element has no vertex_indices list";
    else if (!why && (el[fi].p[pf].type == T_F32 || el[fi].p[pf].type == T_F64))
        why = "vertex_indices are not integers";
    if (why) {
        int r = qtool_errf_at(err, errlen, name, 0, "%s (vertex %llu of at most %d, face %llu of at most %d)", why,
                     vi >= 0 ? (unsigned long long)el[vi].count : 0ull, QTOOL_PLY_MAX_VERTICES,
                     fi >= 0 ? (unsigned long long)el[fi].count : 0ull, QTOOL_PLY_MAX_FACES);
        free(el);
        return r;
    }
    size_t blen = len - hlen;
    if (need > (uint64_t)blen + (fmt == F_ASCII ? 1 : 0)) {
        int r = qtool_errf_at(err, errlen, name, 0, "the header's %llu vertices and %llu faces need at least %llu body bytes; the "
                     "file has %zu", (unsigned long long)el[vi].count, (unsigned long long)el[fi].count,
                     (unsigned long long)need, blen);
        free(el);
        return r;
    }
    size_t nv = (size_t)el[vi].count, ntri = 0;
    body b = {buf + hlen, blen, 0, fmt, name, err, errlen};
    /* the counting pass checks the whole body and counts the fan triangles: the cap is applied to
     * the exact count before anything is allocated for the mesh */
    int rc = body_pass(name, b, el, nel, vi, fi, px, py, pz, pf, nv, NULL, NULL, &ntri, err, errlen);
    if (rc == 0 && ntri == 0)
        rc = qtool_errf_at(err, errlen, name, 0, "no faces (the face element is empty)");
    if (rc == 0 && ntri > max_triangles)
        rc = qtool_errf_at(err, errlen, name, 0, "%zu triangles after fan triangulation of %llu faces (at most %zu)", ntri,
                  (unsigned long long)el[fi].count, max_triangles);
    double *v = NULL;
    uint32_t *tri = NULL;
    if (rc == 0) {
        v = malloc((nv ? nv : 1) * 3 * sizeof *v), tri = malloc(ntri * 3 * sizeof *tri);
        if (!v || !tri)
            rc = qtool_errf_at(err, errlen, name, 0, "out of memory");
    }
    size_t filled = 0;
    if (rc == 0)
        rc = body_pass(name, b, el, nel, vi, fi, px, py, pz, pf, nv, v, tri, &filled, err, errlen);
    if (rc == 0 && build(v, nv, tri, ntri, out) != 0)
        rc = qtool_errf_at(err, errlen, name, 0, "out of memory");
    free(v), free(tri), free(el);
    if (rc != 0)
        memset(out, 0, sizeof *out);
    return rc;
}

int qtool_ply_parse(const char *name, const uint8_t *buf, size_t len, qtool_obj_mesh *out, char *err, size_t errlen)
{
    return qtool_ply_parse_max(name, buf, len, QTOOL_PLY_MAX_TRIANGLES, out, err, errlen);
}

int qtool_ply_read(const char *path, qtool_obj_mesh *out, char *err, size_t errlen)
{
    return qtool_ply_read_max(path, QTOOL_PLY_MAX_TRIANGLES, out, err, errlen);
}

int qtool_ply_read_max(const char *path, size_t max_triangles, qtool_obj_mesh *out, char *err, size_t errlen)
{
    size_t n;
    uint8_t *b = qtool_io_read_all(path, &n);
    if (!b) {
        memset(out, 0, sizeof *out);
        return qtool_errf_at(err, errlen, path, 0, "%s", strerror(errno));
    }
    int rc = qtool_ply_parse_max(path, b, n, max_triangles, out, err, errlen);
    free(b);
    return rc;
}
