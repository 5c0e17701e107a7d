/*
 * io/gltf.c - glTF 2.0 reader. The JSON is tokenised once (io/json.h) and every top-level array
 * indexed, so each reference is an O(1) lookup. Two walks over the scene's node tree: the first
 * checks everything (each mesh once, each buffer and image loaded once) and counts the triangles;
 * the second, after the caps have passed and the mesh is allocated, writes the triangles.
 */
#include "io/gltf.h"
#include "io/file.h"
#include "io/json.h"
#include "io/png.h"
#include "io/relpath.h"
#include "qtool.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_PATH_BYTES 1024
/* all buffers loaded for one file together */
#define MAX_TOTAL_BUFFER_BYTES ((size_t)1 << 29)
/* all decoded texture pixels together (3 bytes each) */
#define MAX_TEXTURE_PIXELS ((size_t)1 << 26)

typedef const qtool_json_tok tok;

#define NOI ((size_t)-1) /* a context without an index */

typedef struct {
    tok **t;
    size_t n;
} arr;

typedef struct {
    const uint8_t *p;
    size_t len;
    uint8_t *own;
    int loaded;
} bufdata;

typedef struct {
    const uint8_t *base;
    size_t count, stride;
    int ctype, ncomp, norm;
} acc;

typedef struct {
    double rgb[3];
    int tex;       /* index into g->texs, or -1 */
    int texcoord;  /* TEXCOORD_n */
    int checked;
} mat;

typedef struct {
    const char *name, *dir;
    char *err;
    size_t errlen;
    qtool_json_doc d;
    tok *root;
    arr nodes, meshes, accessors, views, buffers, materials, textures, images, cameras, scenes;
    const uint8_t *bin;
    size_t binlen;
    int glb;
    bufdata *bufs;
    size_t total_bytes, inlen;
    uint8_t **accmat; /* per accessor: its sparse or zero-filled values written out, or NULL */
    int *image_tex; /* per image: -2 not loaded, else index into texs */
    qtool_mesh_texture texs[QTOOL_GLTF_MAX_IMAGES];
    size_t ntex, texpix;
    mat *mats;
    long long *mesh_tri; /* per mesh: -1 not checked yet */
    uint8_t *visited;
    double *world;       /* per node: its world matrix from the first walk */
    uint8_t *inscene;    /* per node: reached by the first walk */
    double *anim;        /* per node: animated translation (3), rotation (4), scale (3) */
    uint8_t *animmask;   /* per node: bit 0 T, 1 R, 2 S animated */
    double time;         /* < 0: no animation */
    double anim_start, anim_end;
    int has_anim;
    arr animations, skins;
    size_t unique_tri, total_tri, max_tri, ncam, nvert, nnorm;
    int any_mat, any_tex;
    /* output (second walk) */
    qtool_obj_mesh *m;
    size_t t;
    qtool_gltf_camera *cams;
} G;

static int fail(G *g, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    qtool_verrf_at(g->err, g->errlen, g->name ? g->name : "gltf", 0, fmt, ap);
    va_end(ap);
    return -1;
}

/* ---- JSON helpers ------------------------------------------------------------------------------- */

/* an integer property in 0..max; def < 0: required */
static int get_uint(G *g, tok *obj, const char *key, double max, long long def, const char *ctx, size_t ci,
                    size_t *out)
{
    tok *t = qtool_json_get(&g->d, obj, key);
    *out = 0;
    if (!t) {
        if (def < 0)
            return ci == NOI ? fail(g, "%s: no %s", ctx, key) : fail(g, "%s[%zu]: no %s", ctx, ci, key);
        *out = (size_t)def;
        return 0;
    }
    if (t->type != QTOOL_JSON_NUMBER || !(t->num >= 0) || t->num != floor(t->num) || t->num > max) {
        char where[96];
        if (ci == NOI)
            snprintf(where, sizeof where, "%s", ctx);
        else
            snprintf(where, sizeof where, "%s[%zu]", ctx, ci);
        if (t->type != QTOOL_JSON_NUMBER)
            return fail(g, "%s.%s: not a number", where, key);
        if (max < 0) /* an index into an array the file does not have */
            return fail(g, "%s.%s: %.17g refers to an empty or missing array", where, key, t->num);
        return fail(g, "%s.%s: %.17g is not an integer in 0..%.0f", where, key, t->num, max);
    }
    *out = (size_t)t->num;
    return 0;
}

/* a number array of exactly n entries into out (absent: left as is, returns 0) */
static int get_nums(G *g, tok *obj, const char *key, double *out, int n, const char *ctx, size_t ci)
{
    tok *t = qtool_json_get(&g->d, obj, key);
    if (!t)
        return 0;
    if (t->type != QTOOL_JSON_ARRAY || t->count != (uint32_t)n)
        return fail(g, "%s[%zu].%s: not an array of %d numbers", ctx, ci, key, n);
    tok *e = qtool_json_first(&g->d, t);
    for (int i = 0; i < n; ++i, e = qtool_json_skip(&g->d, e)) {
        if (!e || e->type != QTOOL_JSON_NUMBER)
            return fail(g, "%s[%zu].%s[%d]: not a number", ctx, ci, key, i);
        out[i] = e->num;
    }
    return 0;
}

static int get_num(G *g, tok *obj, const char *key, double def, double *out, const char *ctx, size_t ci)
{
    tok *t = qtool_json_get(&g->d, obj, key);
    if (!t) {
        *out = def;
        return 0;
    }
    if (t->type != QTOOL_JSON_NUMBER)
        return fail(g, "%s[%zu].%s: not a number", ctx, ci, key);
    *out = t->num;
    return 0;
}

static int index_array(G *g, const char *key, arr *a, size_t max)
{
    tok *t = qtool_json_get(&g->d, g->root, key);
    if (!t)
        return 0;
    if (t->type != QTOOL_JSON_ARRAY)
        return fail(g, "'%s' is not an array", key);
    if (t->count > max)
        return fail(g, "%u %s (at most %zu)", t->count, key, max);
    if (t->count == 0)
        return 0;
    a->t = malloc(t->count * sizeof *a->t);
    if (!a->t)
        return fail(g, "out of memory");
    tok *e = qtool_json_first(&g->d, t);
    for (uint32_t i = 0; i < t->count; ++i, e = qtool_json_skip(&g->d, e)) {
        if (!e || e->type != QTOOL_JSON_OBJECT)
            return fail(g, "%s[%u] is not an object", key, i);
        a->t[i] = e;
    }
    a->n = t->count;
    return 0;
}

/* ---- uris, buffers, images ---------------------------------------------------------------------- */

static int b64(int c)
{
    return c >= 'A' && c <= 'Z' ? c - 'A' : c >= 'a' && c <= 'z' ? c - 'a' + 26 : c >= '0' && c <= '9' ? c - '0' + 52
           : c == '+' ? 62 : c == '/' ? 63 : -1;
}

/* decodes the base64 payload of a data: URI (raw JSON string span: base64 has no escapes) */
static int data_uri(G *g, tok *u, const char *ctx, size_t ci, uint8_t **out, size_t *outlen)
{
    const char *s = g->d.text + u->start;
    size_t n = u->len, c = 0;
    while (c < n && s[c] != ',')
        ++c;
    if (c == n || c < 12 || memcmp(s + c - 7, ";base64", 7) != 0)
        return fail(g, "%s[%zu].uri: a data: URI that is not base64", ctx, ci);
    s += c + 1, n -= c + 1;
    while (n && s[n - 1] == '=')
        --n;
    if (n % 4 == 1)
        return fail(g, "%s[%zu].uri: base64 of a bad length", ctx, ci);
    size_t m = n / 4 * 3 + (n % 4 ? n % 4 - 1 : 0);
    if (m > QTOOL_GLTF_MAX_BUFFER_BYTES)
        return fail(g, "%s[%zu].uri: %zu bytes of data (at most %zu, QTOOL_GLTF_MAX_BUFFER_BYTES)", ctx, ci, m,
                    (size_t)QTOOL_GLTF_MAX_BUFFER_BYTES);
    uint8_t *b = malloc(m ? m : 1);
    if (!b)
        return fail(g, "out of memory");
    uint32_t bits = 0;
    size_t o = 0;
    for (size_t i = 0; i < n; ++i) {
        int v = b64((unsigned char)s[i]);
        if (v < 0) {
            free(b);
            return fail(g, "%s[%zu].uri: byte %zu of the base64 data is not base64", ctx, ci, i);
        }
        bits = bits << 6 | (uint32_t)v;
        if (i % 4 == 3) {
            b[o++] = (uint8_t)(bits >> 16), b[o++] = (uint8_t)(bits >> 8), b[o++] = (uint8_t)bits;
            bits = 0;
        }
    }
    if (n % 4 == 2)
        b[o++] = (uint8_t)(bits >> 4);
    else if (n % 4 == 3)
        b[o++] = (uint8_t)(bits >> 10), b[o++] = (uint8_t)(bits >> 2);
    *out = b, *outlen = o;
    return 0;
}

/* a file's string made safe for a one-line message: control bytes become '?', at most 60 bytes */
static const char *shown(const char *in, char out[64])
{
    size_t i = 0;
    for (; in[i] && i < 60; ++i)
        out[i] = (unsigned char)in[i] < 0x20 || in[i] == 0x7f ? '?' : in[i];
    out[i] = '\0';
    return out;
}

static int hexd(char c)
{
    return c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
}

/* a relative uri made a path under g->dir, or a named refusal */
static int uri_path(G *g, tok *u, const char *ctx, size_t ci, char *path, size_t cap)
{
    char raw[MAX_PATH_BYTES], rel[MAX_PATH_BYTES], sh[64];
    if (qtool_json_str(&g->d, u, raw, sizeof raw) < 0)
        return fail(g, "%s[%zu].uri: longer than %d bytes or holds a NUL", ctx, ci, MAX_PATH_BYTES - 1);
    size_t o = 0;
    for (size_t i = 0; raw[i]; ++i) {
        char c = raw[i];
        if (c == '%') {
            int h = raw[i + 1] ? hexd(raw[i + 1]) : -1, l = h >= 0 && raw[i + 2] ? hexd(raw[i + 2]) : -1;
            if (h < 0 || l < 0 || (h == 0 && l == 0))
                return fail(g, "%s[%zu].uri: bad percent escape", ctx, ci);
            c = (char)(h * 16 + l), i += 2;
        }
        rel[o++] = c;
    }
    rel[o] = '\0';
    const char *why;
    if (qtool_io_relpath(g->dir ? g->dir : ".", rel, path, cap, &why) != 0)
        return fail(g, "%s[%zu].uri '%s': %s (only paths inside the file's folder are read)", ctx, ci, shown(rel, sh),
                    why);
    if (!g->dir)
        return fail(g, "%s[%zu].uri '%s': an external file, and no folder to read it from", ctx, ci, shown(rel, sh));
    return 0;
}

static int is_data(G *g, tok *u)
{
    return u->len >= 5 && memcmp(g->d.text + u->start, "data:", 5) == 0;
}

static int load_buffer(G *g, size_t i)
{
    bufdata *b = &g->bufs[i];
    if (b->loaded)
        return 0;
    tok *o = g->buffers.t[i];
    size_t blen;
    if (get_uint(g, o, "byteLength", (double)QTOOL_GLTF_MAX_BUFFER_BYTES, -1, "buffers", i, &blen) != 0)
        return -1;
    if (blen == 0)
        return fail(g, "buffers[%zu].byteLength: 0", i);
    if (blen > MAX_TOTAL_BUFFER_BYTES - g->total_bytes)
        return fail(g, "buffers[%zu]: more than %zu bytes of buffers in all", i, MAX_TOTAL_BUFFER_BYTES);
    tok *u = qtool_json_get(&g->d, o, "uri");
    if (u && u->type != QTOOL_JSON_STRING)
        return fail(g, "buffers[%zu].uri: not a string", i);
    if (!u) {
        if (!g->glb || i != 0 || !g->bin)
            return fail(g, "buffers[%zu]: no uri (only the first buffer of a .glb with a BIN chunk may omit it)", i);
        b->p = g->bin, b->len = g->binlen;
    } else if (is_data(g, u)) {
        if (data_uri(g, u, "buffers", i, &b->own, &b->len) != 0)
            return -1;
        b->p = b->own;
    } else {
        char path[MAX_PATH_BYTES + 512], err[600];
        if (uri_path(g, u, "buffers", i, path, sizeof path) != 0)
            return -1;
        static const qtool_io_kind kind = {"a glTF buffer", 1, QTOOL_GLTF_MAX_BUFFER_BYTES, 0, NULL};
        if (qtool_io_load(path, &kind, &b->own, &b->len, err, sizeof err) != 0)
            return fail(g, "buffers[%zu]: %s", i, err);
        b->p = b->own;
    }
    if (b->len < blen)
        return fail(g, "buffers[%zu]: %zu bytes of data, byteLength says %zu", i, b->len, blen);
    b->len = blen;
    g->total_bytes += blen;
    b->loaded = 1;
    return 0;
}

/* bufferView i's bytes (stride 0 when absent) */
static int view_bytes(G *g, size_t i, const uint8_t **p, size_t *len, size_t *stride)
{
    if (i >= g->views.n)
        return fail(g, "bufferViews[%zu]: no such bufferView (%zu)", i, g->views.n);
    tok *o = g->views.t[i];
    size_t bi, off, bl, st;
    if (get_uint(g, o, "buffer", (double)g->buffers.n - 1, -1, "bufferViews", i, &bi) != 0 ||
        get_uint(g, o, "byteOffset", 9007199254740991.0, 0, "bufferViews", i, &off) != 0 ||
        get_uint(g, o, "byteLength", 9007199254740991.0, -1, "bufferViews", i, &bl) != 0 ||
        get_uint(g, o, "byteStride", 252, 0, "bufferViews", i, &st) != 0)
        return -1;
    if (g->buffers.n == 0)
        return fail(g, "bufferViews[%zu]: no buffers", i);
    if (load_buffer(g, bi) != 0)
        return -1;
    if (off > g->bufs[bi].len || bl > g->bufs[bi].len - off)
        return fail(g, "bufferViews[%zu]: byteOffset %zu + byteLength %zu past buffers[%zu]'s %zu bytes", i, off, bl,
                    bi, g->bufs[bi].len);
    if (st != 0 && st < 4)
        return fail(g, "bufferViews[%zu].byteStride: %zu (4..252)", i, st);
    *p = g->bufs[bi].p + off, *len = bl, *stride = st;
    return 0;
}

static int csize(int ct)
{
    switch (ct) {
    case 5120: case 5121: return 1;
    case 5122: case 5123: return 2;
    case 5125: case 5126: return 4;
    default: return 0;
    }
}

static double acc_get(const acc *a, size_t i, int c);

static void put32(uint8_t *p, uint32_t u)
{
    p[0] = (uint8_t)u, p[1] = (uint8_t)(u >> 8), p[2] = (uint8_t)(u >> 16), p[3] = (uint8_t)(u >> 24);
}

/* one element of a dense copy: an unsigned int (component type 5125) or a float's bits */
static void put_elem(uint8_t *p, int ot, double v)
{
    uint32_t u;
    if (ot == 5125) {
        u = (uint32_t)v;
    } else {
        float f = (float)v;
        memcpy(&u, &f, 4);
    }
    put32(p, u);
}

/* n tightly packed elements of esz bytes from byteOffset in a sparse part's bufferView */
static int sparse_view(G *g, size_t i, tok *o, const char *part, size_t n, size_t esz, const uint8_t **p)
{
    size_t vi, off, vlen, st;
    char ctx[64];
    snprintf(ctx, sizeof ctx, "accessors[%zu].sparse.%s", i, part);
    if (get_uint(g, o, "bufferView", 4294967295.0, -1, ctx, NOI, &vi) != 0 ||
        get_uint(g, o, "byteOffset", 9007199254740991.0, 0, ctx, NOI, &off) != 0 || view_bytes(g, vi, p, &vlen, &st) != 0)
        return -1;
    /* n <= 2^32, esz <= 64: no overflow */
    if (off > vlen || (unsigned long long)n * esz > vlen - off)
        return fail(g, "%s: byteOffset %zu + %zu x %zu bytes past bufferViews[%zu]'s %zu", ctx, off, n, esz, vi, vlen);
    *p += off;
    return 0;
}

/* A sparse accessor, or one without a bufferView (zeros), written out once into a cached array of
 * 32-bit values (UNSIGNED_INT kept as integers, everything else as the float acc_get gives), its
 * bytes counted against the buffers' budget and at most 64 times the input read so far. */
static int materialize(G *g, size_t i, tok *o, acc *a, const acc *dense, int has_view)
{
    if (g->accmat[i]) {
        a->base = g->accmat[i], a->stride = 4 * (size_t)a->ncomp;
        a->ctype = a->ctype == 5125 ? 5125 : 5126, a->norm = 0;
        return 0;
    }
    size_t esz = 4 * (size_t)a->ncomp;
    unsigned long long bytes = (unsigned long long)a->count * esz;
    unsigned long long budget = 64ull * (g->inlen + g->total_bytes);
    if (bytes > MAX_TOTAL_BUFFER_BYTES - g->total_bytes || bytes > budget)
        return fail(g, "accessors[%zu]: %zu sparse or zero-filled elements, %llu bytes: more than the %zu bytes of "
                       "buffers in all or 64 times the input",
                    i, a->count, bytes, MAX_TOTAL_BUFFER_BYTES);
    int ot = a->ctype == 5125 ? 5125 : 5126;
    uint8_t *m = calloc((size_t)bytes, 1);
    if (!m)
        return fail(g, "out of memory");
    for (size_t k = 0; has_view && k < a->count; ++k)
        for (int c = 0; c < a->ncomp; ++c) {
            put_elem(m + k * esz + 4 * (size_t)c, ot, acc_get(dense, k, c));
        }
    tok *sp = qtool_json_get(&g->d, o, "sparse");
    if (sp) {
        size_t n, ict;
        tok *io = qtool_json_get(&g->d, sp, "indices"), *vo = qtool_json_get(&g->d, sp, "values");
        const uint8_t *ip, *vp;
        char ctx[64];
        snprintf(ctx, sizeof ctx, "accessors[%zu].sparse", i);
        if (get_uint(g, sp, "count", (double)a->count, -1, ctx, NOI, &n) != 0)
            goto bad;
        if (n == 0 || !io || !vo) {
            fail(g, "accessors[%zu].sparse: a count of 0, or no indices or values", i);
            goto bad;
        }
        snprintf(ctx, sizeof ctx, "accessors[%zu].sparse.indices", i);
        if (get_uint(g, io, "componentType", 65535, -1, ctx, NOI, &ict) != 0)
            goto bad;
        if (ict != 5121 && ict != 5123 && ict != 5125) {
            fail(g, "accessors[%zu].sparse.indices.componentType: %zu (5121, 5123 or 5125)", i, ict);
            goto bad;
        }
        size_t vesz = (size_t)csize(a->ctype) * (size_t)a->ncomp;
        if (sparse_view(g, i, io, "indices", n, (size_t)csize((int)ict), &ip) != 0 ||
            sparse_view(g, i, vo, "values", n, vesz, &vp) != 0)
            goto bad;
        acc ia = {.base = ip, .count = n, .stride = (size_t)csize((int)ict), .ctype = (int)ict, .ncomp = 1};
        acc va = {.base = vp, .count = n, .stride = vesz, .ctype = a->ctype, .ncomp = a->ncomp, .norm = a->norm};
        double prev = -1;
        for (size_t k = 0; k < n; ++k) {
            double ix = acc_get(&ia, k, 0);
            if (ix >= (double)a->count || ix <= prev) {
                fail(g, "accessors[%zu].sparse: index %zu is %.0f (increasing, below the count %zu)", i, k, ix, a->count);
                goto bad;
            }
            prev = ix;
            for (int c = 0; c < a->ncomp; ++c) {
                put_elem(m + (size_t)ix * esz + 4 * (size_t)c, ot, acc_get(&va, k, c));
            }
        }
    }
    g->total_bytes += (size_t)bytes;
    g->accmat[i] = m;
    a->base = m, a->stride = esz, a->ctype = ot, a->norm = 0;
    return 0;
bad:
    free(m);
    return -1;
}

static int load_acc(G *g, size_t i, acc *a, const char *what)
{
    if (i >= g->accessors.n)
        return fail(g, "%s: accessors[%zu]: no such accessor (%zu)", what, i, g->accessors.n);
    tok *o = g->accessors.t[i];
    size_t ct, cnt, off, vi = 0;
    int has_view = qtool_json_get(&g->d, o, "bufferView") != NULL, sparse = qtool_json_get(&g->d, o, "sparse") != NULL;
    if (get_uint(g, o, "componentType", 65535, -1, "accessors", i, &ct) != 0 ||
        get_uint(g, o, "count", 4294967295.0, -1, "accessors", i, &cnt) != 0 ||
        get_uint(g, o, "byteOffset", 9007199254740991.0, 0, "accessors", i, &off) != 0 ||
        (has_view && get_uint(g, o, "bufferView", 4294967295.0, -1, "accessors", i, &vi) != 0))
        return -1;
    int cs = csize((int)ct);
    if (!cs)
        return fail(g, "accessors[%zu].componentType: %zu (5120, 5121, 5122, 5123, 5125 or 5126)", i, ct);
    if (cnt == 0)
        return fail(g, "accessors[%zu].count: 0", i);
    tok *ty = qtool_json_get(&g->d, o, "type");
    static const char *const names[] = {"SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4"};
    static const int ncomp[] = {1, 2, 3, 4, 4, 9, 16};
    int nc = 0;
    for (int k = 0; k < 7; ++k)
        if (qtool_json_str_eq(&g->d, ty, names[k]))
            nc = ncomp[k];
    if (!nc)
        return fail(g, "accessors[%zu].type: missing or not SCALAR, VEC2, VEC3, VEC4, MAT2, MAT3 or MAT4", i);
    tok *nm = qtool_json_get(&g->d, o, "normalized");
    a->count = cnt, a->ctype = (int)ct, a->ncomp = nc, a->norm = nm && nm->type == QTOOL_JSON_TRUE;
    if (!has_view) /* zeros, and the sparse values if any */
        return materialize(g, i, o, a, NULL, 0);
    const uint8_t *p;
    size_t vlen, st;
    if (view_bytes(g, vi, &p, &vlen, &st) != 0)
        return -1;
    size_t esz = (size_t)cs * (size_t)nc;
    if (st == 0)
        st = esz;
    if (st < esz)
        return fail(g, "accessors[%zu]: bufferViews[%zu].byteStride %zu is below the element's %zu bytes", i, vi, st,
                    esz);
    /* cnt < 2^32, st <= 252, off < 2^53: the sum fits in 64 bits */
    unsigned long long need = (unsigned long long)off + (unsigned long long)(cnt - 1) * st + esz;
    if (need > vlen)
        return fail(g, "accessors[%zu]: byteOffset %zu + %zu elements x stride %zu = %llu bytes, past bufferViews[%zu]'s %zu",
                    i, off, cnt, st, need, vi, vlen);
    a->base = p + off, a->stride = st;
    if (!sparse)
        return 0;
    acc dense = *a;
    return materialize(g, i, o, a, &dense, 1);
}

static double acc_get(const acc *a, size_t i, int c)
{
    const uint8_t *p = a->base + i * a->stride + (size_t)c * (size_t)csize(a->ctype);
    uint32_t u;
    switch (a->ctype) {
    case 5120: {
        int v = p[0] < 128 ? p[0] : p[0] - 256;
        return a->norm ? fmax(v / 127.0, -1.0) : v;
    }
    case 5121: return a->norm ? p[0] / 255.0 : p[0];
    case 5122: {
        int v = p[0] | p[1] << 8;
        v = v < 32768 ? v : v - 65536;
        return a->norm ? fmax(v / 32767.0, -1.0) : v;
    }
    case 5123: return a->norm ? (p[0] | p[1] << 8) / 65535.0 : (p[0] | p[1] << 8);
    case 5125:
        u = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
        return a->norm ? u / 4294967295.0 : u;
    default: {
        float f;
        u = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
        memcpy(&f, &u, 4);
        return f;
    }
    }
}

/* decodes image i once; *tex its index into g->texs */
static int load_image(G *g, size_t i, int *tex)
{
    if (g->image_tex[i] != -2) {
        *tex = g->image_tex[i];
        return 0;
    }
    if (g->ntex >= QTOOL_GLTF_MAX_IMAGES)
        return fail(g, "images[%zu]: more than %d images used (QTOOL_GLTF_MAX_IMAGES)", i, QTOOL_GLTF_MAX_IMAGES);
    tok *o = g->images.t[i];
    tok *u = qtool_json_get(&g->d, o, "uri");
    uint8_t *own = NULL;
    const uint8_t *p;
    size_t len;
    char err[600];
    if (u && u->type != QTOOL_JSON_STRING)
        return fail(g, "images[%zu].uri: not a string", i);
    if (u && is_data(g, u)) {
        if (data_uri(g, u, "images", i, &own, &len) != 0)
            return -1;
        p = own;
    } else if (u) {
        char path[MAX_PATH_BYTES + 512];
        if (uri_path(g, u, "images", i, path, sizeof path) != 0)
            return -1;
        static const qtool_io_kind kind = {"a PNG texture", 8, QTOOL_PNG_MAX_FILE_BYTES, 0, NULL};
        if (qtool_io_load(path, &kind, &own, &len, err, sizeof err) != 0)
            return fail(g, "images[%zu]: %s", i, err);
        p = own;
    } else {
        size_t vi, st;
        if (get_uint(g, o, "bufferView", 4294967295.0, -1, "images", i, &vi) != 0 ||
            view_bytes(g, vi, &p, &len, &st) != 0)
            return -1;
    }
    int w, h, frames;
    uint8_t *rgb;
    int rc = qtool_png_decode_rgb8(p, len, &w, &h, &frames, &rgb, err, sizeof err);
    free(own);
    if (rc != 0)
        return fail(g, "images[%zu]: %s (textures are read as 8-bit PNG)", i, err);
    size_t px = (size_t)w * (size_t)h;
    if (px > MAX_TEXTURE_PIXELS - g->texpix) {
        free(rgb);
        return fail(g, "images[%zu]: more than %zu texture pixels in all", i, MAX_TEXTURE_PIXELS);
    }
    g->texpix += px;
    g->texs[g->ntex] = (qtool_mesh_texture){.w = w, .h = h, .rgb = rgb};
    *tex = g->image_tex[i] = (int)g->ntex++;
    return 0;
}

static int load_material(G *g, size_t i)
{
    mat *m = &g->mats[i];
    if (m->checked)
        return 0;
    m->rgb[0] = m->rgb[1] = m->rgb[2] = 1.0;
    m->tex = -1;
    tok *pbr = qtool_json_get(&g->d, g->materials.t[i], "pbrMetallicRoughness");
    if (pbr) {
        double f[4] = {1, 1, 1, 1};
        if (get_nums(g, pbr, "baseColorFactor", f, 4, "materials", i) != 0)
            return -1;
        for (int c = 0; c < 4; ++c)
            if (!(f[c] >= 0 && f[c] <= 1))
                return fail(g, "materials[%zu].pbrMetallicRoughness.baseColorFactor[%d]: %g (0..1)", i, c, f[c]);
        m->rgb[0] = f[0], m->rgb[1] = f[1], m->rgb[2] = f[2];
        tok *bt = qtool_json_get(&g->d, pbr, "baseColorTexture");
        if (bt) {
            size_t ti, tc, src;
            if (get_uint(g, bt, "index", (double)g->textures.n - 1, -1, "materials", i, &ti) != 0 ||
                get_uint(g, bt, "texCoord", 15, 0, "materials", i, &tc) != 0)
                return -1;
            if (g->textures.n == 0)
                return fail(g, "materials[%zu]: a baseColorTexture and no textures", i);
            if (get_uint(g, g->textures.t[ti], "source", (double)g->images.n - 1, -1, "textures", ti, &src) != 0)
                return -1;
            if (g->images.n == 0)
                return fail(g, "textures[%zu]: a source and no images", ti);
            if (load_image(g, src, &m->tex) != 0)
                return -1;
            m->texcoord = (int)tc;
        }
    }
    m->checked = 1;
    return 0;
}

/* ---- meshes ------------------------------------------------------------------------------------- */

typedef struct {
    acc pos, nrm, uv, idx, jnt, wgt, col;
    int has_nrm, has_uv, has_idx, has_skin, has_col, mode, mat;
    size_t n, ntri;
} prim;

static int load_prim(G *g, size_t mi, size_t pi, tok *p, prim *r, int check)
{
    char what[64];
    snprintf(what, sizeof what, "meshes[%zu].primitives[%zu]", mi, pi);
    memset(r, 0, sizeof *r);
    size_t mode, ai;
    if (get_uint(g, p, "mode", 6, 4, what, NOI, &mode) != 0)
        return -1;
    r->mode = (int)mode, r->mat = -1;
    if (mode < 4)
        return 0; /* points and lines: no triangles */
    tok *at = qtool_json_get(&g->d, p, "attributes");
    if (!at || at->type != QTOOL_JSON_OBJECT)
        return fail(g, "%s: no attributes", what);
    if (get_uint(g, at, "POSITION", 4294967295.0, -1, what, NOI, &ai) != 0 || load_acc(g, ai, &r->pos, what) != 0)
        return -1;
    if (r->pos.ncomp != 3)
        return fail(g, "%s: POSITION accessors[%zu] is not VEC3", what, ai);
    for (size_t v = 0; check && v < r->pos.count; ++v)
        for (int c = 0; c < 3; ++c) {
            double x = acc_get(&r->pos, v, c);
            if (!(fabs(x) <= QIBL_OBJ_MAX_COORD))
                return fail(g, "%s: POSITION accessors[%zu] vertex %zu: %g (|c| <= %g, QIBL_OBJ_MAX_COORD)", what, ai,
                            v, x, QIBL_OBJ_MAX_COORD);
        }
    if (qtool_json_get(&g->d, at, "NORMAL")) {
        if (get_uint(g, at, "NORMAL", 4294967295.0, -1, what, NOI, &ai) != 0 || load_acc(g, ai, &r->nrm, what) != 0)
            return -1;
        if (r->nrm.ncomp != 3 || r->nrm.count != r->pos.count)
            return fail(g, "%s: NORMAL accessors[%zu] is not VEC3 of the POSITION count %zu", what, ai, r->pos.count);
        for (size_t v = 0; check && v < r->nrm.count; ++v)
            for (int c = 0; c < 3; ++c)
                if (!(fabs(acc_get(&r->nrm, v, c)) <= QIBL_OBJ_MAX_COORD))
                    return fail(g, "%s: NORMAL accessors[%zu] vertex %zu: not finite", what, ai, v);
        r->has_nrm = 1;
    }
    if (qtool_json_get(&g->d, at, "COLOR_0")) { /* vertex colours multiply the base colour */
        if (get_uint(g, at, "COLOR_0", 4294967295.0, -1, what, NOI, &ai) != 0 || load_acc(g, ai, &r->col, what) != 0)
            return -1;
        if ((r->col.ncomp != 3 && r->col.ncomp != 4) || r->col.count != r->pos.count)
            return fail(g, "%s: COLOR_0 accessors[%zu] is not VEC3 or VEC4 of the POSITION count %zu", what, ai,
                        r->pos.count);
        for (size_t v = 0; check && v < r->col.count; ++v)
            for (int c = 0; c < 3; ++c)
                if (!(acc_get(&r->col, v, c) >= 0 && acc_get(&r->col, v, c) <= 1))
                    return fail(g, "%s: COLOR_0 accessors[%zu] vertex %zu: a colour outside 0..1", what, ai, v);
        r->has_col = 1;
    }
    if (qtool_json_get(&g->d, at, "JOINTS_0") || qtool_json_get(&g->d, at, "WEIGHTS_0")) {
        size_t aj, aw;
        if (get_uint(g, at, "JOINTS_0", 4294967295.0, -1, what, NOI, &aj) != 0 ||
            get_uint(g, at, "WEIGHTS_0", 4294967295.0, -1, what, NOI, &aw) != 0 || load_acc(g, aj, &r->jnt, what) != 0 ||
            load_acc(g, aw, &r->wgt, what) != 0)
            return -1;
        if (r->jnt.ncomp != 4 || r->wgt.ncomp != 4 || r->jnt.count != r->pos.count || r->wgt.count != r->pos.count ||
            r->jnt.norm || (r->jnt.ctype != 5121 && r->jnt.ctype != 5123))
            return fail(g, "%s: JOINTS_0 / WEIGHTS_0 not VEC4 (UNSIGNED_BYTE or _SHORT joints) of the POSITION count %zu",
                        what, r->pos.count);
        for (size_t v = 0; check && v < r->wgt.count; ++v)
            for (int c = 0; c < 4; ++c)
                if (!(acc_get(&r->wgt, v, c) >= 0 && acc_get(&r->wgt, v, c) <= 1))
                    return fail(g, "%s: WEIGHTS_0 accessors[%zu] vertex %zu: a weight outside 0..1", what, aw, v);
        r->has_skin = 1;
    }
    if (qtool_json_get(&g->d, p, "material")) {
        size_t mt;
        if (get_uint(g, p, "material", (double)g->materials.n - 1, -1, what, NOI, &mt) != 0)
            return -1;
        if (g->materials.n == 0)
            return fail(g, "%s: a material and no materials", what);
        if (load_material(g, mt) != 0)
            return -1;
        r->mat = (int)mt;
        if (g->mats[mt].tex >= 0) {
            char key[16];
            snprintf(key, sizeof key, "TEXCOORD_%d", g->mats[mt].texcoord);
            if (get_uint(g, at, key, 4294967295.0, -1, what, NOI, &ai) != 0 || load_acc(g, ai, &r->uv, what) != 0)
                return -1;
            if (r->uv.ncomp != 2 || r->uv.count != r->pos.count)
                return fail(g, "%s: %s accessors[%zu] is not VEC2 of the POSITION count %zu", what, key, ai,
                            r->pos.count);
            for (size_t v = 0; check && v < r->uv.count; ++v)
                for (int c = 0; c < 2; ++c)
                    if (!(fabs(acc_get(&r->uv, v, c)) <= 1e9))
                        return fail(g, "%s: %s accessors[%zu] vertex %zu: out of range", what, key, ai, v);
            r->has_uv = 1;
        }
    }
    r->n = r->pos.count;
    if (qtool_json_get(&g->d, p, "indices")) {
        if (get_uint(g, p, "indices", 4294967295.0, -1, what, NOI, &ai) != 0 || load_acc(g, ai, &r->idx, what) != 0)
            return -1;
        if (r->idx.ncomp != 1 || r->idx.norm || (r->idx.ctype != 5121 && r->idx.ctype != 5123 && r->idx.ctype != 5125))
            return fail(g, "%s: indices accessors[%zu] is not SCALAR UNSIGNED_BYTE, _SHORT or _INT", what, ai);
        for (size_t k = 0; check && k < r->idx.count; ++k) {
            double v = acc_get(&r->idx, k, 0);
            if (v >= (double)r->pos.count)
                return fail(g, "%s: index %zu is %.0f, past the %zu vertices", what, k, v, r->pos.count);
        }
        r->n = r->idx.count, r->has_idx = 1;
    }
    if (mode == 4) {
        if (r->n % 3)
            return fail(g, "%s: TRIANGLES with %zu vertices (not a multiple of 3)", what, r->n);
        r->ntri = r->n / 3;
    } else {
        r->ntri = r->n >= 3 ? r->n - 2 : 0;
    }
    return 0;
}

static int check_mesh(G *g, size_t mi)
{
    if (g->mesh_tri[mi] >= 0)
        return 0;
    tok *ps = qtool_json_get(&g->d, g->meshes.t[mi], "primitives");
    if (!ps || ps->type != QTOOL_JSON_ARRAY)
        return fail(g, "meshes[%zu]: no primitives array", mi);
    tok *p = qtool_json_first(&g->d, ps);
    size_t total = 0;
    for (uint32_t k = 0; k < ps->count; ++k, p = qtool_json_skip(&g->d, p)) {
        prim r;
        if (!p || p->type != QTOOL_JSON_OBJECT)
            return fail(g, "meshes[%zu].primitives[%u]: not an object", mi, k);
        if (load_prim(g, mi, k, p, &r, 1) != 0)
            return -1;
        total += r.ntri;
        if (total > QTOOL_GLTF_MAX_TRIANGLES)
            return fail(g, "meshes[%zu]: more than %zu triangles (QTOOL_GLTF_MAX_TRIANGLES)", mi,
                        (size_t)QTOOL_GLTF_MAX_TRIANGLES);
        if (r.ntri && (r.mat >= 0 || r.has_col))
            g->any_mat = 1;
        if (r.ntri && r.has_uv)
            g->any_tex = 1;
    }
    g->mesh_tri[mi] = (long long)total;
    g->unique_tri += total;
    return 0;
}

/* ---- transforms --------------------------------------------------------------------------------- */

/* column-major 4x4: m[c * 4 + r] */
static void mul(const double *a, const double *b, double *o)
{
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) {
            double s = 0;
            for (int k = 0; k < 4; ++k)
                s += a[k * 4 + r] * b[c * 4 + k];
            o[c * 4 + r] = s;
        }
}

static int local_matrix(G *g, size_t ni, double *m)
{
    tok *o = g->nodes.t[ni];
    static const double id[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    memcpy(m, id, sizeof id);
    if (qtool_json_get(&g->d, o, "matrix"))
        return get_nums(g, o, "matrix", m, 16, "nodes", ni);
    double t[3] = {0, 0, 0}, q[4] = {0, 0, 0, 1}, s[3] = {1, 1, 1};
    if (get_nums(g, o, "translation", t, 3, "nodes", ni) != 0 || get_nums(g, o, "rotation", q, 4, "nodes", ni) != 0 ||
        get_nums(g, o, "scale", s, 3, "nodes", ni) != 0)
        return -1;
    if (g->animmask && g->animmask[ni]) { /* the animation's values at g->time replace the node's */
        const double *a = g->anim + 10 * ni;
        if (g->animmask[ni] & 1)
            memcpy(t, a, sizeof t);
        if (g->animmask[ni] & 2)
            memcpy(q, a + 3, sizeof q);
        if (g->animmask[ni] & 4)
            memcpy(s, a + 7, sizeof s);
    }
    double l = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!(l > 1e-12) || !isfinite(l))
        return fail(g, "nodes[%zu].rotation: not a unit quaternion", ni);
    double x = q[0] / l, y = q[1] / l, z = q[2] / l, w = q[3] / l;
    double r[9] = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),
                   2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),
                   2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y)}; /* column-major */
    for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k)
            m[c * 4 + k] = r[c * 3 + k] * s[c];
    m[12] = t[0], m[13] = t[1], m[14] = t[2];
    return 0;
}

static void xform_point(const double *m, const double *p, double *o)
{
    for (int r = 0; r < 3; ++r)
        o[r] = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r];
}

static void xform_dir(const double *m, const double *p, double *o)
{
    for (int r = 0; r < 3; ++r)
        o[r] = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2];
}

static void unit3(double *v)
{
    double m = fmax(fabs(v[0]), fmax(fabs(v[1]), fabs(v[2])));
    if (!(m > 0) || !isfinite(m)) {
        v[0] = v[1] = v[2] = 0;
        return;
    }
    v[0] /= m, v[1] /= m, v[2] /= m;
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    v[0] /= l, v[1] /= l, v[2] /= l;
}


/* ---- animation ---------------------------------------------------------------------------------- */

/* slerp of the keys made unit first (files write 0.707 for sqrt(1/2)) */
static void slerp(const double *a0, const double *b0, double u, double *o)
{
    double la = sqrt(a0[0] * a0[0] + a0[1] * a0[1] + a0[2] * a0[2] + a0[3] * a0[3]);
    double lb = sqrt(b0[0] * b0[0] + b0[1] * b0[1] + b0[2] * b0[2] + b0[3] * b0[3]);
    if (!(la > 1e-12) || !(lb > 1e-12)) { /* local_matrix names a zero quaternion */
        memcpy(o, u < 0.5 ? a0 : b0, 4 * sizeof *o);
        return;
    }
    double a[4] = {a0[0] / la, a0[1] / la, a0[2] / la, a0[3] / la};
    double b[4] = {b0[0] / lb, b0[1] / lb, b0[2] / lb, b0[3] / lb};
    double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
    if (d < 0) /* the shorter way round */
        d = -d, b[0] = -b[0], b[1] = -b[1], b[2] = -b[2], b[3] = -b[3];
    double wa = 1 - u, wb = u;
    if (d < 0.9995) {
        double th = acos(d), sn = sin(th);
        wa = sin((1 - u) * th) / sn, wb = sin(u * th) / sn;
    }
    for (int k = 0; k < 4; ++k)
        o[k] = wa * a[k] + wb * b[k];
}

static int channels(G *g, tok *chs, tok *sms, tok **smv);

/* Animation 0 sampled at g->time (clamped to each sampler's keys) into the nodes' translation,
 * rotation and scale; STEP, LINEAR (slerp for rotations) and CUBICSPLINE; "weights" ignored.
 * Every sampler's key range also widens [anim_start, anim_end]. */
static int apply_animation(G *g)
{
    if (g->animations.n == 0)
        return 0;
    tok *an = g->animations.t[0], *chs = qtool_json_get(&g->d, an, "channels"),
        *sms = qtool_json_get(&g->d, an, "samplers");
    if (!chs || chs->type != QTOOL_JSON_ARRAY || !sms || sms->type != QTOOL_JSON_ARRAY)
        return fail(g, "animations[0]: no channels or samplers array");
    g->has_anim = 1;
    g->anim_start = 1e300, g->anim_end = -1e300;
    /* the samplers indexed once, so each channel finds its own in O(1) */
    tok **smv = malloc((sms->count + 1) * sizeof *smv);
    if (!smv)
        return fail(g, "out of memory");
    tok *e = qtool_json_first(&g->d, sms);
    for (uint32_t k = 0; k < sms->count; ++k, e = qtool_json_skip(&g->d, e))
        smv[k] = e;
    int rc = channels(g, chs, sms, smv);
    free(smv);
    return rc;
}

static int channels(G *g, tok *chs, tok *sms, tok **smv)
{
    tok *c = qtool_json_first(&g->d, chs);
    for (uint32_t k = 0; k < chs->count; ++k, c = qtool_json_skip(&g->d, c)) {
        char ctx[64];
        snprintf(ctx, sizeof ctx, "animations[0].channels[%u]", k);
        if (!c || c->type != QTOOL_JSON_OBJECT)
            return fail(g, "%s: not an object", ctx);
        tok *tg = qtool_json_get(&g->d, c, "target"), *path = qtool_json_get(&g->d, tg, "path");
        size_t si, ni;
        int kind = qtool_json_str_eq(&g->d, path, "translation") ? 0 : qtool_json_str_eq(&g->d, path, "rotation") ? 1
                   : qtool_json_str_eq(&g->d, path, "scale")     ? 2
                                                                  : -1;
        if (get_uint(g, c, "sampler", (double)sms->count - 1, -1, ctx, NOI, &si) != 0)
            return -1;
        if (kind < 0 || !qtool_json_get(&g->d, tg, "node"))
            continue; /* weights, or a channel for an extension */
        if (get_uint(g, tg, "node", (double)g->nodes.n - 1, -1, ctx, NOI, &ni) != 0)
            return -1;
        tok *sm = smv[si];
        if (!sm || sm->type != QTOOL_JSON_OBJECT)
            return fail(g, "animations[0].samplers[%zu]: not an object", si);
        size_t ia, oa;
        acc in, out;
        snprintf(ctx, sizeof ctx, "animations[0].samplers[%zu]", si);
        if (get_uint(g, sm, "input", 4294967295.0, -1, ctx, NOI, &ia) != 0 ||
            get_uint(g, sm, "output", 4294967295.0, -1, ctx, NOI, &oa) != 0 || load_acc(g, ia, &in, ctx) != 0 ||
            load_acc(g, oa, &out, ctx) != 0)
            return -1;
        tok *ip = qtool_json_get(&g->d, sm, "interpolation");
        int mode = !ip || qtool_json_str_eq(&g->d, ip, "LINEAR") ? 0 : qtool_json_str_eq(&g->d, ip, "STEP") ? 1
                   : qtool_json_str_eq(&g->d, ip, "CUBICSPLINE")                                         ? 2
                                                                                                           : -1;
        int nc = kind == 1 ? 4 : 3;
        size_t n = in.count, per = mode == 2 ? 3 : 1;
        if (mode < 0)
            return fail(g, "%s.interpolation: not LINEAR, STEP or CUBICSPLINE", ctx);
        if (in.ncomp != 1 || out.ncomp != nc || out.count != n * per)
            return fail(g, "%s: input not SCALAR, or output not %u x VEC%d of the %zu keys", ctx, (unsigned)per, nc, n);
        /* the keys' times increase (binary search below relies on it); checked once per channel */
        double t0 = acc_get(&in, 0, 0), t1 = acc_get(&in, n - 1, 0);
        for (size_t q = 1; q < n; ++q)
            if (!(acc_get(&in, q, 0) > acc_get(&in, q - 1, 0)))
                return fail(g, "%s: input times not increasing at key %zu", ctx, q);
        if (!isfinite(t0) || !isfinite(t1))
            return fail(g, "%s: input times not finite", ctx);
        g->anim_start = fmin(g->anim_start, t0), g->anim_end = fmax(g->anim_end, t1);
        if (g->time < 0)
            continue; /* the rest pose: keys checked, nothing applied */
        double t = g->time < t0 ? t0 : g->time > t1 ? t1 : g->time;
        size_t lo = 0, hi = n - 1; /* the last key at or before t */
        while (lo < hi) {
            size_t mid = (lo + hi + 1) / 2;
            if (acc_get(&in, mid, 0) <= t)
                lo = mid;
            else
                hi = mid - 1;
        }
        size_t k1 = lo + 1 < n ? lo + 1 : lo;
        double ta = acc_get(&in, lo, 0), tb = acc_get(&in, k1, 0), td = tb - ta, u = td > 0 ? (t - ta) / td : 0;
        double v[4], a[4], b[4];
        /* CUBICSPLINE keys are (in-tangent, value, out-tangent) */
        for (int j = 0; j < nc; ++j)
            a[j] = acc_get(&out, lo * per + (per == 3), j), b[j] = acc_get(&out, k1 * per + (per == 3), j);
        if (mode == 1 || k1 == lo) {
            memcpy(v, a, sizeof a);
        } else if (mode == 0) {
            if (kind == 1)
                slerp(a, b, u, v);
            else
                for (int j = 0; j < nc; ++j)
                    v[j] = a[j] + u * (b[j] - a[j]);
        } else {
            double u2 = u * u, u3 = u2 * u;
            for (int j = 0; j < nc; ++j) {
                double m0 = td * acc_get(&out, lo * 3 + 2, j), m1 = td * acc_get(&out, k1 * 3, j);
                v[j] = (2 * u3 - 3 * u2 + 1) * a[j] + (u3 - 2 * u2 + u) * m0 + (-2 * u3 + 3 * u2) * b[j] + (u3 - u2) * m1;
            }
        }
        for (int j = 0; j < nc; ++j)
            if (!(fabs(v[j]) <= QIBL_OBJ_MAX_COORD))
                return fail(g, "%s: a value out of range", ctx);
        memcpy(g->anim + 10 * ni + (kind == 0 ? 0 : kind == 1 ? 3 : 7), v, (size_t)nc * sizeof(double));
        g->animmask[ni] |= (uint8_t)(1 << kind);
    }
    if (g->anim_start > g->anim_end)
        g->anim_start = g->anim_end = 0;
    return 0;
}

/* ---- the walks ---------------------------------------------------------------------------------- */

static size_t corner(const prim *r, size_t t, int q, int flip)
{
    size_t a, b, c;
    if (r->mode == 4)
        a = 3 * t, b = 3 * t + 1, c = 3 * t + 2;
    else if (r->mode == 5)
        a = t, b = t + 1 + (t & 1), c = t + 2 - (t & 1); /* the spec's {i, i + (1 + i%2), i + (2 - i%2)} */
    else
        a = t + 1, b = t + 2, c = 0;
    if (flip) {
        size_t x = b;
        b = c, c = x;
    }
    size_t k = q == 0 ? a : q == 1 ? b : c;
    return r->has_idx ? (size_t)acc_get(&r->idx, k, 0) : k;
}

/* the cofactor matrix of m's upper 3x3 (row-major) and its determinant: normals go by cof n */
static double cofactors(const double *M, double cof[9])
{
    double a = M[0], b = M[4], c = M[8], d = M[1], e = M[5], f = M[9], h = M[2], i = M[6], k = M[10];
    cof[0] = e * k - f * i, cof[1] = -(d * k - f * h), cof[2] = d * i - e * h;
    cof[3] = -(b * k - c * i), cof[4] = a * k - c * h, cof[5] = -(a * i - b * h);
    cof[6] = b * f - c * e, cof[7] = -(a * f - c * d), cof[8] = a * e - b * d;
    return a * cof[0] + b * cof[1] + c * cof[2];
}

/* Skin si's joint matrices (world of each joint x its inverse bind matrix) into *J (malloc'ed,
 * 16 per joint); every joint a node of the scene. */
static int skin_matrices(G *g, size_t si, double **J, size_t *nj)
{
    tok *o = g->skins.t[si], *js = qtool_json_get(&g->d, o, "joints");
    *J = NULL, *nj = 0;
    if (!js || js->type != QTOOL_JSON_ARRAY || js->count == 0 || js->count > QTOOL_GLTF_MAX_JOINTS)
        return fail(g, "skins[%zu].joints: not an array of 1..%d node indices (QTOOL_GLTF_MAX_JOINTS)", si,
                    QTOOL_GLTF_MAX_JOINTS);
    acc ibm = {0};
    int has_ibm = qtool_json_get(&g->d, o, "inverseBindMatrices") != NULL;
    if (has_ibm) {
        size_t ai;
        if (get_uint(g, o, "inverseBindMatrices", 4294967295.0, -1, "skins", si, &ai) != 0 ||
            load_acc(g, ai, &ibm, "skins") != 0)
            return -1;
        if (ibm.ncomp != 16 || ibm.count < js->count)
            return fail(g, "skins[%zu].inverseBindMatrices: not MAT4 for each of the %u joints", si, js->count);
    }
    double *m = malloc(js->count * 16 * sizeof *m);
    if (!m)
        return fail(g, "out of memory");
    tok *e = qtool_json_first(&g->d, js);
    for (uint32_t k = 0; k < js->count; ++k, e = qtool_json_skip(&g->d, e)) {
        if (!e || e->type != QTOOL_JSON_NUMBER || !(e->num >= 0) || e->num != floor(e->num) ||
            e->num >= (double)g->nodes.n || !g->inscene[(size_t)e->num]) {
            free(m);
            return fail(g, "skins[%zu].joints[%u]: not a node of the scene", si, k);
        }
        double B[16];
        for (int c = 0; c < 16; ++c)
            B[c] = has_ibm ? acc_get(&ibm, k, c) : (c % 5 == 0);
        mul(g->world + 16 * (size_t)e->num, B, m + 16 * (size_t)k);
        for (int c = 0; c < 16; ++c)
            if (!(fabs(m[16 * (size_t)k + (size_t)c]) <= QIBL_OBJ_MAX_COORD)) {
                free(m);
                return fail(g, "skins[%zu]: joint %u's matrix out of range", si, k);
            }
    }
    *J = m, *nj = js->count;
    return 0;
}

/* the triangles of mesh mi under world matrix M, or skinned by joint matrices J (nj of them:
 * each vertex by the weighted sum of its four joints' matrices, the node's own M ignored) */
static int emit_mesh(G *g, size_t mi, const double *M, const double *J, size_t nj)
{
    qtool_obj_mesh *out = g->m;
    /* normals by the inverse transpose: the cofactor matrix, signed by the determinant */
    double cof[9];
    double det = cofactors(M, cof);
    int flip = !J && det < 0;
    tok *ps = qtool_json_get(&g->d, g->meshes.t[mi], "primitives");
    tok *p = qtool_json_first(&g->d, ps);
    for (uint32_t pk = 0; pk < ps->count; ++pk, p = qtool_json_skip(&g->d, p)) {
        prim r;
        if (load_prim(g, mi, pk, p, &r, 0) != 0)
            return -1;
        int skinned = J && r.has_skin;
        g->nvert += r.ntri ? r.pos.count : 0;
        g->nnorm += r.ntri && r.has_nrm ? r.nrm.count : 0;
        for (size_t t = 0; t < r.ntri; ++t, ++g->t) {
            double *P = out->pos + 9 * g->t, *N = out->nrm + 9 * g->t;
            size_t vi[3];
            double Mc[3][16], cofc[3][9], detc[3];
            for (int q = 0; q < 3; ++q) {
                vi[q] = corner(&r, t, q, flip);
                const double *Mq = M;
                if (skinned) {
                    double wsum = 0;
                    memset(Mc[q], 0, sizeof Mc[q]);
                    for (int k = 0; k < 4; ++k) {
                        double w = acc_get(&r.wgt, vi[q], k);
                        size_t jk = (size_t)acc_get(&r.jnt, vi[q], k);
                        if (w == 0)
                            continue;
                        if (jk >= nj)
                            return fail(g, "meshes[%zu]: JOINTS_0 of vertex %zu is %zu, past the skin's %zu joints", mi,
                                        vi[q], jk, nj);
                        for (int c = 0; c < 16; ++c)
                            Mc[q][c] += w * J[16 * jk + (size_t)c];
                        wsum += w;
                    }
                    if (!(wsum > 0))
                        return fail(g, "meshes[%zu]: vertex %zu has all its WEIGHTS_0 zero", mi, vi[q]);
                    for (int c = 0; c < 16; ++c)
                        Mc[q][c] /= wsum; /* weights that do not sum to 1 are normalised */
                    Mq = Mc[q];
                    detc[q] = cofactors(Mq, cofc[q]);
                }
                double v[3] = {acc_get(&r.pos, vi[q], 0), acc_get(&r.pos, vi[q], 1), acc_get(&r.pos, vi[q], 2)};
                xform_point(Mq, v, P + 3 * q);
                for (int j = 0; j < 3; ++j)
                    if (!(fabs(P[3 * q + j]) <= QIBL_OBJ_MAX_COORD))
                        return fail(g, "meshes[%zu]: a vertex transformed out of range (|c| <= %g, QIBL_OBJ_MAX_COORD)",
                                    mi, QIBL_OBJ_MAX_COORD);
            }
            double e1[3], e2[3], fn[3];
            for (int j = 0; j < 3; ++j)
                e1[j] = P[3 + j] - P[j], e2[j] = P[6 + j] - P[j];
            fn[0] = e1[1] * e2[2] - e1[2] * e2[1], fn[1] = e1[2] * e2[0] - e1[0] * e2[2],
            fn[2] = e1[0] * e2[1] - e1[1] * e2[0];
            unit3(fn);
            for (int q = 0; q < 3; ++q) {
                double *n = N + 3 * q;
                const double *cq = skinned ? cofc[q] : cof;
                double dq = skinned ? detc[q] : det;
                if (r.has_nrm && dq != 0) {
                    double v[3] = {acc_get(&r.nrm, vi[q], 0), acc_get(&r.nrm, vi[q], 1), acc_get(&r.nrm, vi[q], 2)};
                    double sg = dq < 0 ? -1 : 1;
                    for (int j = 0; j < 3; ++j)
                        n[j] = sg * (cq[3 * j] * v[0] + cq[3 * j + 1] * v[1] + cq[3 * j + 2] * v[2]);
                    unit3(n);
                } else {
                    memcpy(n, fn, sizeof fn);
                }
            }
            if (out->albedo) {
                const double *rgb = r.mat >= 0 ? g->mats[r.mat].rgb : NULL;
                for (int j = 0; j < 3; ++j) {
                    double a = rgb ? rgb[j] : 1.0;
                    if (r.has_col) /* per triangle: the mean of its corners' colours */
                        a *= (acc_get(&r.col, vi[0], j) + acc_get(&r.col, vi[1], j) + acc_get(&r.col, vi[2], j)) / 3;
                    out->albedo[3 * g->t + j] = a;
                }
            }
            if (out->tex) {
                out->tex[g->t] = r.has_uv ? g->mats[r.mat].tex : -1;
                for (int q = 0; q < 3; ++q)
                    for (int j = 0; j < 2; ++j)
                        out->uv[6 * g->t + 2 * q + j] = r.has_uv ? acc_get(&r.uv, vi[q], j) : 0.0;
            }
        }
    }
    return 0;
}

/* node ni's index into the array of what ("mesh", "camera"): in range, and the array not empty */
static int node_ref(G *g, tok *o, size_t ni, const char *what, const arr *a, size_t *out)
{
    if (get_uint(g, o, what, (double)a->n - 1, -1, "nodes", ni, out) != 0)
        return -1;
    if (a->n == 0)
        return fail(g, "nodes[%zu]: a %s and no %ss", ni, what, what);
    return 0;
}

static int visit(G *g, size_t ni, const double *M, int emit)
{
    tok *o = g->nodes.t[ni];
    if (qtool_json_get(&g->d, o, "mesh")) {
        size_t mi;
        if (node_ref(g, o, ni, "mesh", &g->meshes, &mi) != 0)
            return -1;
        if (!emit) {
            if (check_mesh(g, mi) != 0)
                return -1;
            g->total_tri += (size_t)g->mesh_tri[mi];
            if (g->total_tri > g->max_tri)
                return fail(g, "more than %zu triangles in the scene (%s)", g->max_tri,
                            g->max_tri == QTOOL_GLTF_MAX_TRIANGLES ? "QTOOL_GLTF_MAX_TRIANGLES" : "this command's limit");
        } else {
            /* a skinned mesh: placed by its joints (the first walk gave every node's world matrix) */
            double *J = NULL;
            size_t nj = 0;
            if (qtool_json_get(&g->d, o, "skin")) {
                size_t si;
                if (get_uint(g, o, "skin", (double)g->skins.n - 1, -1, "nodes", ni, &si) != 0 ||
                    skin_matrices(g, si, &J, &nj) != 0)
                    return -1;
            }
            int rc = emit_mesh(g, mi, M, J, nj);
            free(J);
            if (rc != 0)
                return -1;
        }
    }
    if (qtool_json_get(&g->d, o, "camera")) {
        size_t ci;
        if (node_ref(g, o, ni, "camera", &g->cameras, &ci) != 0)
            return -1;
        if (!emit && ++g->ncam > QTOOL_GLTF_MAX_CAMERAS)
            return fail(g, "more than %d cameras placed (QTOOL_GLTF_MAX_CAMERAS)", QTOOL_GLTF_MAX_CAMERAS);
        qtool_gltf_camera cam = {.node = (uint32_t)ni};
        tok *co = g->cameras.t[ci], *ty = qtool_json_get(&g->d, co, "type");
        cam.perspective = qtool_json_str_eq(&g->d, ty, "perspective");
        if (!cam.perspective && !qtool_json_str_eq(&g->d, ty, "orthographic"))
            return fail(g, "cameras[%zu].type: not perspective or orthographic", ci);
        tok *pp = qtool_json_get(&g->d, co, cam.perspective ? "perspective" : "orthographic");
        if (!pp || pp->type != QTOOL_JSON_OBJECT)
            return fail(g, "cameras[%zu]: no %s object", ci, cam.perspective ? "perspective" : "orthographic");
        if (cam.perspective) {
            if (get_num(g, pp, "yfov", -1, &cam.yfov, "cameras", ci) != 0 ||
                get_num(g, pp, "aspectRatio", 0, &cam.aspect, "cameras", ci) != 0 ||
                get_num(g, pp, "znear", -1, &cam.znear, "cameras", ci) != 0 ||
                get_num(g, pp, "zfar", 0, &cam.zfar, "cameras", ci) != 0)
                return -1;
            if (!(cam.yfov > 0 && cam.yfov < 3.14159265358979) || !(cam.znear > 0) || cam.aspect < 0 ||
                (cam.zfar != 0 && !(cam.zfar > cam.znear)))
                return fail(g, "cameras[%zu].perspective: yfov %g (0..pi), znear %g (> 0), aspectRatio %g, zfar %g", ci,
                            cam.yfov, cam.znear, cam.aspect, cam.zfar);
        } else {
            if (get_num(g, pp, "xmag", 0, &cam.xmag, "cameras", ci) != 0 ||
                get_num(g, pp, "ymag", 0, &cam.ymag, "cameras", ci) != 0 ||
                get_num(g, pp, "znear", -1, &cam.znear, "cameras", ci) != 0 ||
                get_num(g, pp, "zfar", 0, &cam.zfar, "cameras", ci) != 0)
                return -1;
            if (cam.xmag == 0 || cam.ymag == 0 || cam.znear < 0 || !(cam.zfar > cam.znear))
                return fail(g, "cameras[%zu].orthographic: xmag %g, ymag %g (not 0), znear %g (>= 0), zfar %g (> znear)",
                            ci, cam.xmag, cam.ymag, cam.znear, cam.zfar);
        }
        if (emit) {
            static const double org[3] = {0, 0, 0}, mz[3] = {0, 0, -1}, py[3] = {0, 1, 0};
            xform_point(M, org, cam.eye);
            xform_dir(M, mz, cam.fwd);
            xform_dir(M, py, cam.up);
            unit3(cam.fwd), unit3(cam.up);
            g->cams[g->ncam++] = cam;
        }
    }
    return 0;
}

typedef struct {
    size_t node;
    tok *child;     /* next child token to take */
    uint32_t left;  /* children left */
    double M[16];
} frame;

static int walk(G *g, size_t *roots, size_t nroots, int emit)
{
    frame *st = malloc(QTOOL_GLTF_MAX_DEPTH * sizeof *st);
    if (!st)
        return fail(g, "out of memory");
    memset(g->visited, 0, g->nodes.n);
    int rc = -1;
    for (size_t ri = 0; ri < nroots; ++ri) {
        int sp = 0;
        size_t ni = roots[ri];
        static const double id[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
        const double *parent = id;
        for (;;) {
            /* enter ni */
            if (g->visited[ni]) {
                fail(g, "nodes[%zu] reached twice (a cycle, a shared child or a root that is a child)", ni);
                goto out;
            }
            if (sp == QTOOL_GLTF_MAX_DEPTH) {
                fail(g, "nodes[%zu]: a node tree deeper than %d (QTOOL_GLTF_MAX_DEPTH)", ni, QTOOL_GLTF_MAX_DEPTH);
                goto out;
            }
            g->visited[ni] = 1;
            frame *f = &st[sp++];
            double L[16];
            if (local_matrix(g, ni, L) != 0)
                goto out;
            mul(parent, L, f->M);
            if (!emit)
                memcpy(g->world + 16 * ni, f->M, sizeof f->M);
            f->node = ni;
            if (visit(g, ni, f->M, emit) != 0)
                goto out;
            tok *ch = qtool_json_get(&g->d, g->nodes.t[ni], "children");
            if (ch && ch->type != QTOOL_JSON_ARRAY) {
                fail(g, "nodes[%zu].children: not an array", ni);
                goto out;
            }
            f->left = ch ? ch->count : 0;
            f->child = ch ? qtool_json_first(&g->d, ch) : NULL;
            /* next node: the first child left on the stack, popping finished frames */
            while (sp > 0 && st[sp - 1].left == 0)
                --sp;
            if (sp == 0)
                break;
            frame *top = &st[sp - 1];
            tok *c = top->child;
            if (!c || c->type != QTOOL_JSON_NUMBER || !(c->num >= 0) || c->num != floor(c->num) ||
                c->num >= (double)g->nodes.n) {
                fail(g, "nodes[%zu].children: an entry that is not a node index (0..%zu)", top->node, g->nodes.n - 1);
                goto out;
            }
            ni = (size_t)c->num;
            top->child = qtool_json_skip(&g->d, c);
            --top->left;
            parent = top->M;
        }
    }
    rc = 0;
out:
    free(st);
    return rc;
}

/* the scene's root nodes (malloc'ed) */
static int scene_roots(G *g, size_t **roots, size_t *n)
{
    tok *sc = qtool_json_get(&g->d, g->root, "scene");
    size_t si = 0;
    *roots = NULL, *n = 0;
    if (sc && get_uint(g, g->root, "scene", (double)g->scenes.n - 1, -1, "the file", NOI, &si) != 0)
        return -1;
    if (sc && g->scenes.n == 0)
        return fail(g, "'scene' set and no scenes");
    if (g->scenes.n) {
        tok *ns = qtool_json_get(&g->d, g->scenes.t[si], "nodes");
        if (!ns)
            return 0;
        if (ns->type != QTOOL_JSON_ARRAY)
            return fail(g, "scenes[%zu].nodes: not an array", si);
        *roots = malloc((ns->count ? ns->count : 1) * sizeof **roots);
        if (!*roots)
            return fail(g, "out of memory");
        tok *e = qtool_json_first(&g->d, ns);
        for (uint32_t k = 0; k < ns->count; ++k, e = qtool_json_skip(&g->d, e)) {
            if (!e || e->type != QTOOL_JSON_NUMBER || !(e->num >= 0) || e->num != floor(e->num) ||
                e->num >= (double)g->nodes.n) {
                free(*roots), *roots = NULL;
                return fail(g, "scenes[%zu].nodes[%u]: not a node index", si, k);
            }
            (*roots)[k] = (size_t)e->num;
        }
        *n = ns->count;
        return 0;
    }
    /* no scenes: every node that is nobody's child */
    uint8_t *child = calloc(g->nodes.n ? g->nodes.n : 1, 1);
    *roots = malloc((g->nodes.n ? g->nodes.n : 1) * sizeof **roots);
    if (!child || !*roots) {
        free(child), free(*roots), *roots = NULL;
        return fail(g, "out of memory");
    }
    for (size_t i = 0; i < g->nodes.n; ++i) {
        tok *ch = qtool_json_get(&g->d, g->nodes.t[i], "children");
        tok *e = ch && ch->type == QTOOL_JSON_ARRAY ? qtool_json_first(&g->d, ch) : NULL;
        for (uint32_t k = 0; e && k < ch->count; ++k, e = qtool_json_skip(&g->d, e))
            if (e->type == QTOOL_JSON_NUMBER && e->num >= 0 && e->num < (double)g->nodes.n)
                child[(size_t)e->num] = 1;
    }
    for (size_t i = 0; i < g->nodes.n; ++i)
        if (!child[i])
            (*roots)[(*n)++] = i;
    free(child);
    return 0;
}

/* Every object the reader looks into (any outside "extras" and "extensions", which are never read)
 * has at most QTOOL_GLTF_MAX_MEMBERS members, so each key lookup is O(1) and the work stays linear
 * in the file however often an accessor or node is consulted. */
static int check_members(G *g)
{
    struct {
        tok *c, *child;
        uint32_t left;
    } st[QTOOL_JSON_MAX_DEPTH + 1];
    int sp = 0;
    tok *t = g->d.tok;
    for (;;) {
        if (t->type == QTOOL_JSON_OBJECT && t->count > QTOOL_GLTF_MAX_MEMBERS)
            return fail(g, "an object of %u members at byte %zu (at most %d outside extras, QTOOL_GLTF_MAX_MEMBERS)",
                        t->count, t->start, QTOOL_GLTF_MAX_MEMBERS);
        if ((t->type == QTOOL_JSON_OBJECT || t->type == QTOOL_JSON_ARRAY) && t->count && sp <= QTOOL_JSON_MAX_DEPTH) {
            st[sp].c = t, st[sp].child = qtool_json_first(&g->d, t), st[sp].left = t->count;
            ++sp;
        }
        for (;;) { /* the next value to look at */
            if (sp == 0)
                return 0;
            if (st[sp - 1].left == 0 || !st[sp - 1].child) {
                --sp;
                continue;
            }
            tok *c = st[sp - 1].child;
            --st[sp - 1].left;
            if (st[sp - 1].c->type == QTOOL_JSON_OBJECT) {
                st[sp - 1].child = qtool_json_skip(&g->d, c + 1);
                if (qtool_json_str_eq(&g->d, c, "extras") || qtool_json_str_eq(&g->d, c, "extensions"))
                    continue;
                t = c + 1;
            } else {
                st[sp - 1].child = qtool_json_skip(&g->d, c);
                t = c;
            }
            break;
        }
    }
}

/* extensionsRequired: a file that needs an extension the reader does not know (Draco, meshopt,
 * texture transforms ...) would come out wrong (no geometry, wrong uvs), so it is refused by name.
 * Known: KHR_mesh_quantization (any component type is read) and the KHR_materials_ family (the
 * base colour stays right without them). */
static int check_required(G *g)
{
    tok *r = qtool_json_get(&g->d, g->root, "extensionsRequired");
    if (!r)
        return 0;
    if (r->type != QTOOL_JSON_ARRAY)
        return fail(g, "extensionsRequired: not an array");
    tok *e = qtool_json_first(&g->d, r);
    for (uint32_t k = 0; k < r->count; ++k, e = qtool_json_skip(&g->d, e)) {
        char name[96], sh[64];
        if (qtool_json_str(&g->d, e, name, sizeof name) < 0)
            return fail(g, "extensionsRequired[%u]: not an extension name", k);
        if (strcmp(name, "KHR_mesh_quantization") != 0 && strncmp(name, "KHR_materials_", 14) != 0)
            return fail(g, "extensionsRequired: %s (not read: only KHR_mesh_quantization and KHR_materials_*)",
                        shown(name, sh));
    }
    return 0;
}

static uint32_t le32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

int qtool_gltf_sniff_glb(const uint8_t *buf, size_t len)
{
    return len >= 4 && memcmp(buf, "glTF", 4) == 0;
}

int qtool_gltf_parse(const char *name, const char *dir, const uint8_t *buf, size_t len, size_t max_triangles,
                     qtool_gltf_scene *out, char *err, size_t errlen)
{
    return qtool_gltf_parse_at(name, dir, buf, len, max_triangles, -1.0, out, err, errlen);
}

/* a GLB container: the JSON chunk into [*json, *json + *jlen), the BIN chunk (if any) into g */
static int glb_chunks(G *g, const uint8_t *buf, size_t len, const char **json, size_t *jlen)
{
    if (len < 20)
        return fail(g, "a GLB of %zu bytes (a header and a JSON chunk need 20)", len);
    uint32_t ver = le32(buf + 4), total = le32(buf + 8);
    if (ver != 2)
        return fail(g, "GLB version %u (only 2 is read)", ver);
    if (total > len || total < 20)
        return fail(g, "GLB length %u, the data has %zu bytes", total, len);
    uint32_t cl = le32(buf + 12);
    if (le32(buf + 16) != 0x4E4F534Au)
        return fail(g, "GLB: the first chunk is not JSON");
    if (cl > total - 20)
        return fail(g, "GLB: JSON chunk of %u bytes past the file's %u", cl, total);
    *json = (const char *)buf + 20, *jlen = cl;
    while (*jlen && (*json)[*jlen - 1] == '\0') /* some exporters pad the JSON chunk with NULs, not spaces */
        --*jlen;
    size_t at = 20 + (size_t)cl;
    g->glb = 1;
    while (at + 8 <= total) { /* the BIN chunk, if any; other chunks are skipped */
        uint32_t bl = le32(buf + at), ty = le32(buf + at + 4);
        if (bl > total - at - 8)
            return fail(g, "GLB: a chunk of %u bytes at byte %zu runs past the file's %u", bl, at, total);
        if (ty == 0x004E4942u) {
            g->bin = buf + at + 8, g->binlen = bl;
            break;
        }
        at += 8 + (size_t)bl;
    }
    return 0;
}

/* the top level: an object of known members, glTF 2.x, its arrays indexed */
static int top_level(G *g)
{
    g->root = g->d.tok;
    if (g->root->type != QTOOL_JSON_OBJECT)
        return fail(g, "the JSON is not an object");
    if (check_members(g) != 0 || check_required(g) != 0)
        return -1;
    tok *asset = qtool_json_get(&g->d, g->root, "asset");
    tok *ver = qtool_json_get(&g->d, asset, "version");
    char vs[32];
    if (qtool_json_str(&g->d, ver, vs, sizeof vs) < 0)
        return fail(g, "no asset.version (not a glTF file?)");
    if (strncmp(vs, "2.", 2) != 0) {
        char sh[64];
        return fail(g, "asset.version %s (only glTF 2.x is read)", shown(vs, sh));
    }
    if (index_array(g, "nodes", &g->nodes, QTOOL_GLTF_MAX_NODES) != 0 ||
        index_array(g, "meshes", &g->meshes, QTOOL_JSON_MAX_TOKENS) != 0 ||
        index_array(g, "accessors", &g->accessors, QTOOL_JSON_MAX_TOKENS) != 0 ||
        index_array(g, "bufferViews", &g->views, QTOOL_JSON_MAX_TOKENS) != 0 ||
        index_array(g, "buffers", &g->buffers, QTOOL_GLTF_MAX_BUFFERS) != 0 ||
        index_array(g, "materials", &g->materials, QTOOL_JSON_MAX_TOKENS) != 0 ||
        index_array(g, "textures", &g->textures, QTOOL_JSON_MAX_TOKENS) != 0 ||
        index_array(g, "images", &g->images, QTOOL_JSON_MAX_TOKENS) != 0 ||
        index_array(g, "cameras", &g->cameras, QTOOL_JSON_MAX_TOKENS) != 0 ||
        index_array(g, "scenes", &g->scenes, QTOOL_JSON_MAX_TOKENS) != 0 ||
        index_array(g, "animations", &g->animations, QTOOL_JSON_MAX_TOKENS) != 0 ||
        index_array(g, "skins", &g->skins, QTOOL_JSON_MAX_TOKENS) != 0)
        return -1;
    return 0;
}

/* the per-buffer, per-image, per-material, per-mesh, per-accessor and per-node tables */
static int node_tables(G *g)
{
    g->bufs = calloc(g->buffers.n + 1, sizeof *g->bufs);
    g->image_tex = malloc((g->images.n + 1) * sizeof *g->image_tex);
    g->mats = calloc(g->materials.n + 1, sizeof *g->mats);
    g->mesh_tri = malloc((g->meshes.n + 1) * sizeof *g->mesh_tri);
    g->accmat = calloc(g->accessors.n + 1, sizeof *g->accmat);
    g->visited = malloc(g->nodes.n + 1);
    g->inscene = calloc(g->nodes.n + 1, 1);
    g->world = malloc((g->nodes.n + 1) * 16 * sizeof *g->world);
    g->anim = malloc((g->nodes.n + 1) * 10 * sizeof *g->anim);
    g->animmask = calloc(g->nodes.n + 1, 1);
    if (!g->bufs || !g->image_tex || !g->mats || !g->mesh_tri || !g->visited || !g->accmat || !g->inscene ||
        !g->world || !g->anim || !g->animmask)
        return fail(g, "out of memory");
    for (size_t i = 0; i < g->images.n; ++i)
        g->image_tex[i] = -2;
    for (size_t i = 0; i < g->meshes.n; ++i)
        g->mesh_tri[i] = -1;
    return 0;
}

/* the second walk: the placed triangles (and cameras) written into m, sized by the first walk */
static int fill_mesh(G *g, size_t *roots, size_t nroots, qtool_obj_mesh *m)
{
    if (g->total_tri == 0)
        return fail(g, "no triangles in the scene");
    if (g->total_tri / QTOOL_GLTF_MAX_INSTANCE_RATIO > g->unique_tri)
        return fail(g, "%zu triangles placed from %zu in the meshes: more than %d instances each (QTOOL_GLTF_MAX_INSTANCE_RATIO)",
                    g->total_tri, g->unique_tri, QTOOL_GLTF_MAX_INSTANCE_RATIO);
    size_t nt = g->total_tri;
    m->pos = malloc(nt * 9 * sizeof(double));
    m->nrm = malloc(nt * 9 * sizeof(double));
    int oom = !m->pos || !m->nrm;
    if (g->any_mat)
        oom |= !(m->albedo = malloc(nt * 3 * sizeof(double)));
    if (g->any_tex) {
        oom |= !(m->uv = malloc(nt * 6 * sizeof(double)));
        oom |= !(m->tex = malloc(nt * sizeof(int32_t)));
        oom |= !(m->texs = calloc(g->ntex, sizeof *m->texs));
    }
    if (g->ncam)
        oom |= !(g->cams = calloc(g->ncam, sizeof *g->cams));
    if (oom)
        return fail(g, "out of memory");
    g->m = m, g->ncam = 0;
    if (walk(g, roots, nroots, 1) != 0)
        return -1;
    m->ntri = g->t, m->nvert = g->nvert, m->nnormals_given = g->nnorm;
    if (g->any_tex) { /* the textures move to the mesh */
        memcpy(m->texs, g->texs, g->ntex * sizeof *m->texs);
        m->ntex = g->ntex;
        g->ntex = 0;
    }
    return 0;
}

static void g_free(G *g)
{
    free(g->cams);
    for (size_t i = 0; g->bufs && i < g->buffers.n; ++i)
        free(g->bufs[i].own);
    for (size_t i = 0; g->accmat && i < g->accessors.n; ++i)
        free(g->accmat[i]);
    free(g->accmat);
    for (size_t i = 0; i < g->ntex; ++i)
        free(g->texs[i].rgb);
    free(g->bufs), free(g->image_tex), free(g->mats), free(g->mesh_tri), free(g->visited);
    free(g->inscene), free(g->world), free(g->anim), free(g->animmask), free(g->animations.t), free(g->skins.t);
    free(g->nodes.t), free(g->meshes.t), free(g->accessors.t), free(g->views.t), free(g->buffers.t);
    free(g->materials.t), free(g->textures.t), free(g->images.t), free(g->cameras.t), free(g->scenes.t);
    qtool_json_free(&g->d);
}

int qtool_gltf_parse_at(const char *name, const char *dir, const uint8_t *buf, size_t len, size_t max_triangles,
                        double time, qtool_gltf_scene *out, char *err, size_t errlen)
{
    G g = {.name = name, .dir = dir, .err = err, .errlen = errlen, .inlen = len, .time = isfinite(time) ? time : -1.0};
    g.max_tri = max_triangles < QTOOL_GLTF_MAX_TRIANGLES ? max_triangles : QTOOL_GLTF_MAX_TRIANGLES;
    const char *json = (const char *)buf;
    size_t jlen = len;
    size_t *roots = NULL, nroots = 0;
    qtool_obj_mesh m = {0};
    int rc = -1;
    if (qtool_gltf_sniff_glb(buf, len) && glb_chunks(&g, buf, len, &json, &jlen) != 0)
        return -1;
    if (qtool_json_parse(json, jlen, &g.d, err, errlen) != 0) {
        char tmp[400];
        snprintf(tmp, sizeof tmp, "%s", err);
        return fail(&g, "%s", tmp);
    }
    if (top_level(&g) != 0 || node_tables(&g) != 0)
        goto out;
    if (apply_animation(&g) != 0 || scene_roots(&g, &roots, &nroots) != 0 || walk(&g, roots, nroots, 0) != 0)
        goto out;
    memcpy(g.inscene, g.visited, g.nodes.n);
    if (fill_mesh(&g, roots, nroots, &m) != 0)
        goto out;
    out->mesh = m;
    out->cams = g.cams, out->ncam = g.ncam;
    out->has_anim = g.has_anim, out->anim_start = g.anim_start, out->anim_end = g.anim_end;
    g.cams = NULL;
    memset(&m, 0, sizeof m);
    rc = 0;
out:
    qtool_obj_free(&m);
    free(roots);
    g_free(&g);
    return rc;
}

static const char *gltf_magic(const uint8_t *head, size_t n)
{
    if (qtool_gltf_sniff_glb(head, n))
        return NULL;
    for (size_t i = 0; i < n; ++i) {
        if (head[i] == '{')
            return NULL;
        if (head[i] != ' ' && head[i] != '\t' && head[i] != '\r' && head[i] != '\n' && head[i] != 0xEF &&
            head[i] != 0xBB && head[i] != 0xBF)
            break;
    }
    return "neither a GLB (\"glTF\" magic) nor JSON text starting with '{'";
}

int qtool_gltf_read(const char *path, size_t max_triangles, qtool_gltf_scene *out, char *err, size_t errlen)
{
    return qtool_gltf_read_at(path, max_triangles, -1.0, out, err, errlen);
}

int qtool_gltf_read_at(const char *path, size_t max_triangles, double time, qtool_gltf_scene *out, char *err,
                       size_t errlen)
{
    static const qtool_io_kind kind = {"a glTF file", 2, QTOOL_GLTF_MAX_FILE_BYTES, QTOOL_IO_MAX_HEAD_BYTES, gltf_magic};
    uint8_t *bytes = NULL;
    size_t n = 0;
    if (qtool_io_load(path, &kind, &bytes, &n, err, errlen) != 0)
        return -1;
    char dir[MAX_PATH_BYTES];
    if (qtool_io_dirname(path, dir, sizeof dir) != 0) {
        free(bytes);
        snprintf(err, errlen, "%s: path too long", path);
        return -1;
    }
    qtool_gltf_scene s = {0};
    int rc = qtool_gltf_parse_at(path, dir, bytes, n, max_triangles, time, &s, err, errlen);
    free(bytes);
    if (rc == 0)
        *out = s;
    return rc;
}

void qtool_gltf_free(qtool_gltf_scene *s)
{
    qtool_obj_free(&s->mesh);
    free(s->cams);
    memset(s, 0, sizeof *s);
}
