/*
 * io/obj.c - Wavefront OBJ reader. One pass over the lines collects positions, normals and the
 * triangulated faces' index triples; a second computes the missing normals.
 */
#include "io/obj.h"
#include "io/file.h"
#include "io/png.h"
#include "io/relpath.h"
#include "qtool.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    double *v;
    size_t n, cap; /* in doubles */
} dvec;

typedef struct {
    uint32_t *v;
    size_t n, cap;
} uvec;

/* name(a, x): appends x to a, doubling from 1024; 0, or -1 out of memory (a unchanged) */
#define DEFINE_PUSH(name, vec_t, elem_t)                                                              \
    static int name(vec_t *a, elem_t x)                                                               \
    {                                                                                                 \
        if (a->n == a->cap) {                                                                         \
            size_t cap = a->cap ? a->cap * 2 : 1024;                                                  \
            elem_t *nv = realloc(a->v, cap * sizeof *nv);                                             \
            if (!nv)                                                                                  \
                return -1;                                                                            \
            a->v = nv, a->cap = cap;                                                                  \
        }                                                                                             \
        a->v[a->n++] = x;                                                                             \
        return 0;                                                                                     \
    }
DEFINE_PUSH(upush, uvec, uint32_t)
DEFINE_PUSH(dpush, dvec, double)

#define NO_NORMAL UINT32_MAX

/* parses up to max doubles from s; returns how many, or -1 with the offending token in *bad and
 * *why saying what is wrong with it */
static int numbers(const char *s, double *out, int max, const char **bad, const char **why)
{
    int n = 0;
    for (;;) {
        while (*s == ' ' || *s == '\t')
            ++s;
        if (!*s)
            return n;
        *bad = s;
        if (n == max) {
            *why = "too many numbers";
            return -1;
        }
        char *end;
        errno = 0;
        double v = strtod(s, &end);
        if (end == s || (*end && *end != ' ' && *end != '\t')) {
            *why = "bad number";
            return -1;
        }
        /* an overflow comes back as an infinity; an underflow (ERANGE too) to nearly zero is harmless */
        if (!isfinite(v)) {
            *why = "non-finite number";
            return -1;
        }
        out[n++] = v;
        s = end;
    }
}

/* resolves a 1-based or negative OBJ index against count without overflow (any long is safe);
 * 0 on success, -1 not a number, -2 out of range */
static int resolve(const char *tok, size_t count, uint32_t *out)
{
    char *end;
    errno = 0;
    long v = strtol(tok, &end, 10);
    if (end == tok || *end || errno == ERANGE)
        return -1;
    /* count <= QTOOL_OBJ_MAX_VERTICES, so -(long)count cannot overflow; v is never negated */
    if (v > 0 && (unsigned long)v <= count)
        *out = (uint32_t)(v - 1);
    else if (v < 0 && v >= -(long)count)
        *out = (uint32_t)((long)count + v);
    else
        return -2;
    return 0;
}

/* v / |v|, or 0 for a zero vector. Far from 1 in magnitude the vector is first divided by its
 * largest component, so that the squares neither underflow (a tiny but real triangle keeping a
 * zero normal) nor overflow; ordinary vectors take the plain path, bit for bit as before. */
static void unit(const double *v, double *out)
{
    double x = v[0], y = v[1], z = v[2];
    double m = fmax(fabs(x), fmax(fabs(y), fabs(z)));
    if (!(m > 0.0)) {
        out[0] = out[1] = out[2] = 0.0;
        return;
    }
    if (m < 1e-100 || m > 1e100)
        x /= m, y /= m, z /= m;
    double l = sqrt(x * x + y * y + z * z);
    out[0] = x / l, out[1] = y / l, out[2] = z / l;
}


/* ---- lines and keywords (shared by .obj and .mtl) ---------------------------------------------- */

#define LINE_BYTES 4096

/* copies the line at *pos into buf (without its '\n') and moves *pos past it; refuses a line that
 * does not fit and a NUL byte */
static int take_line(const char *text, size_t len, size_t *pos, char *buf, size_t *l, const char *name, long line,
                     char *err, size_t errlen)
{
    size_t e = *pos;
    while (e < len && text[e] != '\n')
        ++e;
    *l = e - *pos;
    if (*l >= LINE_BYTES)
        return qtool_errf_at(err, errlen, name, line, "line longer than %zu bytes", (size_t)LINE_BYTES - 1);
    memcpy(buf, text + *pos, *l);
    buf[*l] = '\0';
    *pos = e + 1;
    if (memchr(buf, '\0', *l))
        return qtool_errf_at(err, errlen, name, line, "NUL byte (binary file?)");
    return 0;
}

/* cuts a '#' comment, then splits off the first word: returns it, *rest the text after its first
 * separator */
static char *keyword(char *buf, char **rest)
{
    char *c = strchr(buf, '#');
    if (c)
        *c = '\0';
    char *s = buf;
    while (*s == ' ' || *s == '\t')
        ++s;
    char *kw = s;
    while (*s && *s != ' ' && *s != '\t')
        ++s;
    if (*s)
        *s++ = '\0';
    *rest = s;
    return kw;
}

/* ---- materials (mtllib / usemtl) ------------------------------------------------------------------ */

typedef struct {
    char name[QTOOL_OBJ_MAX_NAME + 1];
    double kd[3];
    int tex; /* index into the texture list, or -1 */
} obj_mat;

typedef struct {
    const char *dir;
    obj_mat *m;
    size_t n;
    qtool_mesh_texture tex[QTOOL_OBJ_MAX_TEXTURES];
    char texpath[QTOOL_OBJ_MAX_TEXTURES][QTOOL_OBJ_MAX_NAME + 1];
    size_t ntex, texpix;
    int libs;
} mtl_set;

static void mtl_free(mtl_set *ms)
{
    for (size_t i = 0; i < ms->ntex; ++i)
        free(ms->tex[i].rgb);
    free(ms->m);
    ms->m = NULL, ms->n = ms->ntex = 0;
}

/* a texture by its name in the .mtl, decoded once */
static int mtl_texture(mtl_set *ms, const char *mtlname, long line, const char *file, int *out, char *err, size_t errlen)
{
    for (size_t i = 0; i < ms->ntex; ++i)
        if (strcmp(ms->texpath[i], file) == 0) {
            *out = (int)i;
            return 0;
        }
    if (ms->ntex == QTOOL_OBJ_MAX_TEXTURES)
        return qtool_errf_at(err, errlen, mtlname, line, "more than %d map_Kd textures (QTOOL_OBJ_MAX_TEXTURES)",
                    QTOOL_OBJ_MAX_TEXTURES);
    char path[2048], e2[600];
    const char *why;
    if (qtool_io_relpath(ms->dir, file, path, sizeof path, &why) != 0)
        return qtool_errf_at(err, errlen, mtlname, line, "map_Kd '%.60s': %s (only paths inside the .obj's folder are read)", file,
                    why);
    int w, h, frames;
    uint8_t *rgb;
    if (qtool_png_read_rgb8(path, &w, &h, &frames, &rgb, e2, sizeof e2) != 0)
        return qtool_errf_at(err, errlen, mtlname, line, "map_Kd: %s (textures are read as 8-bit PNG)", e2);
    size_t px = (size_t)w * (size_t)h;
    if (px > QTOOL_OBJ_MAX_TEXTURE_PIXELS - ms->texpix) {
        free(rgb);
        return qtool_errf_at(err, errlen, mtlname, line, "more than %zu texture pixels in all (QTOOL_OBJ_MAX_TEXTURE_PIXELS)",
                    (size_t)QTOOL_OBJ_MAX_TEXTURE_PIXELS);
    }
    ms->texpix += px;
    ms->tex[ms->ntex] = (qtool_mesh_texture){.w = w, .h = h, .rgb = rgb};
    memcpy(ms->texpath[ms->ntex], file, strlen(file) + 1); /* at most QTOOL_OBJ_MAX_NAME: checked by the caller */
    *out = (int)ms->ntex++;
    return 0;
}

static const char *mtl_magic(const uint8_t *head, size_t n)
{
    return memchr(head, 0, n) ? "binary data (a NUL byte in the first bytes), not a material library" : NULL;
}

/* reads one material library: newmtl, Kd, map_Kd (its last word: the file); the rest is ignored */
static int mtl_read(mtl_set *ms, const char *objname, long objline, const char *file, char *err, size_t errlen)
{
    static const qtool_io_kind kind = {"a material library (.mtl)", 1, QTOOL_OBJ_MAX_MTL_BYTES, QTOOL_IO_MAX_HEAD_BYTES,
                                      mtl_magic};
    char path[2048];
    const char *why;
    if (++ms->libs > QTOOL_OBJ_MAX_MTLLIBS)
        return qtool_errf_at(err, errlen, objname, objline, "more than %d material libraries (QTOOL_OBJ_MAX_MTLLIBS)",
                    QTOOL_OBJ_MAX_MTLLIBS);
    if (qtool_io_relpath(ms->dir, file, path, sizeof path, &why) != 0)
        return qtool_errf_at(err, errlen, objname, objline, "mtllib '%.60s': %s (only paths inside the .obj's folder are read)",
                    file, why);
    uint8_t *bytes;
    size_t len;
    char e2[600];
    if (qtool_io_load(path, &kind, &bytes, &len, e2, sizeof e2) != 0)
        return qtool_errf_at(err, errlen, objname, objline, "mtllib: %s (without the mtllib line the mesh loads uncoloured)", e2);
    const char *text = (const char *)bytes;
    char buf[LINE_BYTES];
    size_t pos = 0;
    long line = 0;
    int rc = -1;
    obj_mat *cur = NULL;
    while (pos < len) {
        size_t l;
        ++line;
        if (take_line(text, len, &pos, buf, &l, path, line, err, errlen) != 0)
            goto out;
        while (l && (buf[l - 1] == '\r' || buf[l - 1] == ' ' || buf[l - 1] == '\t'))
            buf[--l] = '\0';
        char *s, *kw = keyword(buf, &s);
        while (*s == ' ' || *s == '\t')
            ++s;
        if (strcmp(kw, "newmtl") == 0) {
            if (!*s || strlen(s) > QTOOL_OBJ_MAX_NAME) {
                qtool_errf_at(err, errlen, path, line, "newmtl needs a name of 1..%d bytes", QTOOL_OBJ_MAX_NAME);
                goto out;
            }
            if (ms->n == QTOOL_OBJ_MAX_MATERIALS) {
                qtool_errf_at(err, errlen, path, line, "more than %d materials (QTOOL_OBJ_MAX_MATERIALS)", QTOOL_OBJ_MAX_MATERIALS);
                goto out;
            }
            if (!ms->m && !(ms->m = malloc(QTOOL_OBJ_MAX_MATERIALS * sizeof *ms->m))) {
                qtool_errf_at(err, errlen, path, 0, "out of memory");
                goto out;
            }
            cur = &ms->m[ms->n++];
            memcpy(cur->name, s, strlen(s) + 1); /* at most QTOOL_OBJ_MAX_NAME: checked above */
            cur->kd[0] = cur->kd[1] = cur->kd[2] = QTOOL_OBJ_DEFAULT_KD;
            cur->tex = -1;
        } else if (strcmp(kw, "Kd") == 0 || strcmp(kw, "map_Kd") == 0) {
            if (!cur) {
                qtool_errf_at(err, errlen, path, line, "'%s' before any newmtl", kw);
                goto out;
            }
            if (kw[0] == 'K') {
                double x[3];
                const char *bad = NULL, *why2 = NULL;
                int n = numbers(s, x, 3, &bad, &why2);
                if (n != 3) {
                    qtool_errf_at(err, errlen, path, line, "Kd needs 3 numbers (r g b)");
                    goto out;
                }
                for (int j = 0; j < 3; ++j)
                    if (!(x[j] >= 0 && x[j] <= 1)) {
                        qtool_errf_at(err, errlen, path, line, "Kd %c = %g out of range (0..1)", "rgb"[j], x[j]);
                        goto out;
                    }
                memcpy(cur->kd, x, sizeof x);
            } else {
                /* options (-s, -o, ...) may precede the file: its name is the last word */
                char *f = strrchr(s, ' '), *t = strrchr(s, '\t');
                f = f && (!t || f > t) ? f + 1 : t ? t + 1 : s;
                if (!*f || strlen(f) > QTOOL_OBJ_MAX_NAME) {
                    qtool_errf_at(err, errlen, path, line, "map_Kd needs a file name of 1..%d bytes", QTOOL_OBJ_MAX_NAME);
                    goto out;
                }
                if (mtl_texture(ms, path, line, f, &cur->tex, err, errlen) != 0)
                    goto out;
            }
        }
    }
    rc = 0;
out:
    free(bytes);
    return rc;
}

/* ---- the .obj statements ----------------------------------------------------------------------- */

/* one parse: the lists growing statement by statement, and where a fault is reported */
typedef struct {
    const char *name, *dir;
    size_t len, max_triangles;
    dvec v, vn, vt;
    uvec tri;    /* per corner: position index, normal index or NO_NORMAL, vt index or NO_NORMAL */
    uvec trimat; /* per triangle: material index or NO_NORMAL (dir given only) */
    mtl_set ms;
    uint32_t curmat;
    size_t nv, nn, nt;
    long line;
    char *err;
    size_t errlen;
} obj_parse;

/* a fault on the current line; line 0 (out of memory, the whole file) names only the file */
#define PFAIL(p, ...) qtool_errf_at((p)->err, (p)->errlen, (p)->name, (p)->line, __VA_ARGS__)
#define PNOMEM(p) qtool_errf_at((p)->err, (p)->errlen, (p)->name, 0, "out of memory")

/* u [v [w]]: kept for textured materials, stored as (u, 1 - v) (image rows top down) */
static int obj_vt(obj_parse *p, const char *s)
{
    double x[3] = {0, 0, 0};
    const char *bad = NULL, *why = NULL;
    int n = numbers(s, x, 3, &bad, &why);
    if (n < 1)
        return PFAIL(p, "'vt' needs 1 to 3 numbers");
    if (!(fabs(x[0]) <= 1e9 && fabs(x[1]) <= 1e9))
        return PFAIL(p, "texture coordinate out of range (|c| <= 1e9)");
    if (p->nt >= QTOOL_OBJ_MAX_VERTICES)
        return PFAIL(p, "more than %zu 'vt' statements (QTOOL_OBJ_MAX_VERTICES)", (size_t)QTOOL_OBJ_MAX_VERTICES);
    if (dpush(&p->vt, x[0]) != 0 || dpush(&p->vt, 1.0 - x[1]) != 0)
        return PNOMEM(p);
    ++p->nt;
    return 0;
}

static int obj_mtllib(obj_parse *p, char *s)
{
    char *f = strtok(s, " \t");
    if (!f)
        return PFAIL(p, "mtllib needs a file name");
    for (; f; f = strtok(NULL, " \t"))
        if (mtl_read(&p->ms, p->name, p->line, f, p->err, p->errlen) != 0)
            return -1;
    return 0;
}

static int obj_usemtl(obj_parse *p, char *s)
{
    while (*s == ' ' || *s == '\t')
        ++s;
    size_t sl = strlen(s);
    while (sl && (s[sl - 1] == ' ' || s[sl - 1] == '\t' || s[sl - 1] == '\r'))
        s[--sl] = '\0';
    p->curmat = NO_NORMAL;
    for (size_t k = 0; k < p->ms.n; ++k)
        if (strcmp(p->ms.m[k].name, s) == 0)
            p->curmat = (uint32_t)k;
    if (p->curmat == NO_NORMAL)
        return PFAIL(p, "usemtl '%.60s': no such material in the mtllib files read so far", s);
    return 0;
}

/* v x y z [w] or vn x y z */
static int obj_vertex(obj_parse *p, const char *kw, const char *s)
{
    double x[4];
    const char *bad = NULL, *why = NULL;
    int n = numbers(s, x, 4, &bad, &why);
    int isv = kw[1] == '\0';
    if (n < 0 && strcmp(why, "too many numbers") != 0) {
        size_t bl = strcspn(bad, " \t");
        return PFAIL(p, "%s '%.*s' in '%s'", why, (int)(bl > 40 ? 40 : bl), bad, kw);
    }
    if (n < 3 || (!isv && n != 3))
        return PFAIL(p, "'%s' needs 3 numbers%s", kw, isv ? " (and an optional w)" : "");
    if (isv && n == 4 && x[3] == 0.0)
        return PFAIL(p, "vertex with w = 0");
    if ((isv ? p->nv : p->nn) >= QTOOL_OBJ_MAX_VERTICES)
        return PFAIL(p, "more than %zu '%s' statements (QTOOL_OBJ_MAX_VERTICES)", (size_t)QTOOL_OBJ_MAX_VERTICES, kw);
    dvec *d = isv ? &p->v : &p->vn;
    for (int j = 0; j < 3; ++j) {
        double c = isv && n == 4 ? x[j] / x[3] : x[j];
        /* also catches x / w overflowing: 1e300 / 1e-300 */
        if (!(fabs(c) <= QIBL_OBJ_MAX_COORD))
            return PFAIL(p, "%s coordinate %c = %g%s out of range (|c| <= %g, QIBL_OBJ_MAX_COORD)",
                         isv ? "vertex" : "normal", "xyz"[j], c, isv && n == 4 ? " (after dividing by w)" : "",
                         QIBL_OBJ_MAX_COORD);
        if (dpush(d, c) != 0)
            return PNOMEM(p);
    }
    if (isv)
        ++p->nv;
    else
        ++p->nn;
    return 0;
}

/* one index of a face corner (what: "vertex", "texture", "normal"; have: what the count counts) */
static int corner_index(obj_parse *p, const char *tok, size_t count, const char *what, const char *have,
                        uint32_t *out)
{
    int r = resolve(tok, count, out);
    if (r == -1)
        return PFAIL(p, "bad %s index '%.40s'", what, tok);
    if (r != 0)
        return PFAIL(p, "%s index %.40s out of range (%zu %s so far)", what, tok, count, have);
    return 0;
}

/* the corners v, v/t, v//n or v/t/n of one face, as (position, normal, texture) triples */
static int face_corners(obj_parse *p, char *s, uint32_t *poly, int *ncorners)
{
    int nc = 0;
    for (char *tok = strtok(s, " \t"); tok; tok = strtok(NULL, " \t")) {
        if (nc == QTOOL_OBJ_MAX_FACE_CORNERS)
            return PFAIL(p, "face with more than %d corners (QTOOL_OBJ_MAX_FACE_CORNERS)", QTOOL_OBJ_MAX_FACE_CORNERS);
        char *p1 = strchr(tok, '/'), *p2 = p1 ? strchr(p1 + 1, '/') : NULL;
        if (p1)
            *p1 = '\0';
        uint32_t vi, ni = NO_NORMAL, ti = NO_NORMAL;
        if (corner_index(p, tok, p->nv, "vertex", "vertices", &vi) != 0)
            return -1;
        if (p2)
            *p2 = '\0';
        if (p1 && p1[1] && corner_index(p, p1 + 1, p->nt, "texture", "vt", &ti) != 0)
            return -1;
        if (p2 && p2[1] && corner_index(p, p2 + 1, p->nn, "normal", "normals", &ni) != 0)
            return -1;
        poly[3 * nc] = vi, poly[3 * nc + 1] = ni, poly[3 * nc + 2] = ti;
        ++nc;
    }
    *ncorners = nc;
    return 0;
}

/* f: the face fanned into triangles */
static int obj_face(obj_parse *p, char *s)
{
    uint32_t poly[3 * QTOOL_OBJ_MAX_FACE_CORNERS];
    int nc = 0;
    if (face_corners(p, s, poly, &nc) != 0)
        return -1;
    if (nc < 3)
        return PFAIL(p, "face with %d corner%s (needs at least 3)", nc, nc == 1 ? "" : "s");
    size_t ntri_now = p->tri.n / 9 + (size_t)(nc - 2);
    if (ntri_now > p->max_triangles) /* refused as it is crossed: the lists never outgrow the cap */
        return PFAIL(p, "more than %zu triangles (%s)", p->max_triangles,
                     p->max_triangles == QTOOL_OBJ_MAX_TRIANGLES ? "QTOOL_OBJ_MAX_TRIANGLES" : "this command's limit");
    /* fans: a few bytes of "f 1 1 1 1 ..." must not become megabytes of triangles */
    if (ntri_now > p->len / QIBL_OBJ_MIN_BYTES_PER_TRIANGLE)
        return PFAIL(p, "%zu triangles from %zu bytes of input: more than one per %u bytes (QIBL_OBJ_MIN_BYTES_PER_TRIANGLE)",
                     ntri_now, p->len, QIBL_OBJ_MIN_BYTES_PER_TRIANGLE);
    for (int j = 1; j + 1 < nc; ++j) {
        int cs[3] = {0, j, j + 1};
        for (int q = 0; q < 3; ++q)
            if (upush(&p->tri, poly[3 * cs[q]]) || upush(&p->tri, poly[3 * cs[q] + 1]) ||
                upush(&p->tri, poly[3 * cs[q] + 2]))
                return PNOMEM(p);
        if (p->dir && upush(&p->trimat, p->curmat))
            return PNOMEM(p);
    }
    return 0;
}

/* everything else (vp, g, o, s, l, p, empty; usemtl and mtllib without a folder) is ignored */
static int obj_statement(obj_parse *p, const char *kw, char *s)
{
    if (strcmp(kw, "vt") == 0)
        return obj_vt(p, s);
    if (p->dir && strcmp(kw, "mtllib") == 0)
        return obj_mtllib(p, s);
    if (p->dir && strcmp(kw, "usemtl") == 0)
        return obj_usemtl(p, s);
    if (strcmp(kw, "v") == 0 || strcmp(kw, "vn") == 0)
        return obj_vertex(p, kw, s);
    if (strcmp(kw, "f") == 0)
        return obj_face(p, s);
    return 0;
}

/* ---- the mesh from the lists ------------------------------------------------------------------- */

/* what materials add to the mesh, owned here until it moves to the mesh */
typedef struct {
    double *albedo, *uvs;
    int32_t *texi;
    qtool_mesh_texture *texs;
    int any_tex;
} obj_extras;

/* albedo when any triangle has a material; uv and textures when any textured triangle has vt on
 * all three corners (others get tex -1) */
static int obj_materials(obj_parse *p, size_t ntri, obj_extras *x)
{
    const mtl_set *ms = &p->ms;
    int any_mat = 0;
    for (size_t t = 0; p->dir && t < ntri; ++t) {
        uint32_t mi = p->trimat.v[t];
        if (mi == NO_NORMAL)
            continue;
        any_mat = 1;
        const uint32_t *c = p->tri.v + 9 * t;
        x->any_tex |= ms->m[mi].tex >= 0 && c[2] != NO_NORMAL && c[5] != NO_NORMAL && c[8] != NO_NORMAL;
    }
    if (any_mat && !(x->albedo = malloc(ntri * 3 * sizeof(double))))
        return PNOMEM(p);
    if (x->any_tex && (!(x->uvs = malloc(ntri * 6 * sizeof(double))) || !(x->texi = malloc(ntri * sizeof(int32_t))) ||
                       !(x->texs = malloc(ms->ntex * sizeof *x->texs))))
        return PNOMEM(p);
    for (size_t t = 0; any_mat && t < ntri; ++t) {
        uint32_t mi = p->trimat.v[t];
        const uint32_t *c = p->tri.v + 9 * t;
        for (int j = 0; j < 3; ++j)
            x->albedo[3 * t + j] = mi == NO_NORMAL ? QTOOL_OBJ_DEFAULT_KD : ms->m[mi].kd[j];
        if (!x->any_tex)
            continue;
        int textured = mi != NO_NORMAL && ms->m[mi].tex >= 0 && c[2] != NO_NORMAL && c[5] != NO_NORMAL && c[8] != NO_NORMAL;
        x->texi[t] = textured ? ms->m[mi].tex : -1;
        for (int q = 0; q < 3; ++q)
            for (int j = 0; j < 2; ++j)
                x->uvs[6 * t + 2 * q + j] = textured ? p->vt.v[2 * c[3 * q + 2] + j] : 0.0;
    }
    return 0;
}

/* positions per corner; normals as given, else the area-weighted mean of the faces around the vertex */
static int obj_geometry(obj_parse *p, size_t ntri, qtool_obj_mesh *out)
{
    const double *v = p->v.v;
    out->pos = malloc(ntri * 9 * sizeof(double));
    out->nrm = malloc(ntri * 9 * sizeof(double));
    double *acc = calloc(p->nv * 3, sizeof(double));
    if (!out->pos || !out->nrm || !acc) {
        free(out->pos), free(out->nrm), free(acc);
        out->pos = out->nrm = NULL;
        return PNOMEM(p);
    }
    for (size_t t = 0; t < ntri; ++t) {
        const uint32_t *c = p->tri.v + 9 * t;
        const double *a = v + 3 * c[0], *b = v + 3 * c[3], *d = v + 3 * c[6];
        double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
        double fn[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        for (int q = 0; q < 3; ++q)
            for (int j = 0; j < 3; ++j) {
                out->pos[9 * t + 3 * q + j] = v[3 * c[3 * q] + j];
                acc[3 * c[3 * q] + j] += fn[j]; /* |fn| = 2 area: area-weighted */
            }
    }
    for (size_t t = 0; t < ntri; ++t) {
        const uint32_t *c = p->tri.v + 9 * t;
        for (int q = 0; q < 3; ++q) {
            const double *src = c[3 * q + 1] != NO_NORMAL ? p->vn.v + 3 * c[3 * q + 1] : acc + 3 * c[3 * q];
            unit(src, out->nrm + 9 * t + 3 * q);
        }
    }
    free(acc);
    return 0;
}

int qtool_obj_parse(const char *name, const char *text, size_t len, qtool_obj_mesh *out, char *err, size_t errlen)
{
    return qtool_obj_parse_max(name, text, len, QTOOL_OBJ_MAX_TRIANGLES, out, err, errlen);
}

int qtool_obj_parse_max(const char *name, const char *text, size_t len, size_t max_triangles, qtool_obj_mesh *out,
                        char *err, size_t errlen)
{
    return qtool_obj_parse_dir(name, NULL, text, len, max_triangles, out, err, errlen);
}

int qtool_obj_parse_dir(const char *name, const char *dir, const char *text, size_t len, size_t max_triangles,
                        qtool_obj_mesh *out, char *err, size_t errlen)
{
    obj_parse p = {.name = name ? name : "obj",
                   .dir = dir,
                   .len = len,
                   .max_triangles = max_triangles < QTOOL_OBJ_MAX_TRIANGLES ? max_triangles : QTOOL_OBJ_MAX_TRIANGLES,
                   .ms = {.dir = dir},
                   .curmat = NO_NORMAL,
                   .err = err,
                   .errlen = errlen};
    obj_extras x = {0};
    char buf[LINE_BYTES];
    size_t pos = 0, l;
    int rc = -1;
    while (pos < len) {
        ++p.line;
        if (take_line(text, len, &pos, buf, &l, p.name, p.line, err, errlen) != 0)
            goto out;
        if (l && buf[l - 1] == '\r')
            buf[--l] = '\0';
        char *s, *kw = keyword(buf, &s);
        if (obj_statement(&p, kw, s) != 0)
            goto out;
    }
    size_t ntri = p.tri.n / 9;
    if (ntri == 0) {
        qtool_errf_at(err, errlen, p.name, 0, "no faces");
        goto out;
    }
    if (obj_materials(&p, ntri, &x) != 0 || obj_geometry(&p, ntri, out) != 0)
        goto out;
    out->ntri = ntri, out->nvert = p.nv, out->nnormals_given = p.nn;
    out->albedo = x.albedo, out->uv = x.uvs, out->tex = x.texi, out->texs = x.texs, out->ntex = 0;
    if (x.any_tex) { /* the textures move to the mesh */
        memcpy(x.texs, p.ms.tex, p.ms.ntex * sizeof *x.texs);
        out->ntex = p.ms.ntex;
        p.ms.ntex = 0;
    }
    x = (obj_extras){0};
    rc = 0;
out:
    free(p.v.v), free(p.vn.v), free(p.vt.v), free(p.tri.v), free(p.trimat.v);
    free(x.albedo), free(x.uvs), free(x.texi), free(x.texs);
    mtl_free(&p.ms);
    return rc;
}

/* OBJ has no magic; it is text, so a NUL among the first bytes marks a binary file (the parser
 * refuses NULs anywhere, but only after the whole file is read) */
static const char *obj_magic(const uint8_t *head, size_t n)
{
    return memchr(head, 0, n) ? "binary data (a NUL byte in the first bytes), not a Wavefront OBJ file" : NULL;
}

int qtool_obj_read(const char *path, qtool_obj_mesh *out, char *err, size_t errlen)
{
    return qtool_obj_read_max(path, QTOOL_OBJ_MAX_TRIANGLES, out, err, errlen);
}

static int read_impl(const char *path, size_t max_triangles, int materials, qtool_obj_mesh *out, char *err,
                     size_t errlen);

int qtool_obj_read_max(const char *path, size_t max_triangles, qtool_obj_mesh *out, char *err, size_t errlen)
{
    return read_impl(path, max_triangles, 0, out, err, errlen);
}

int qtool_obj_read_materials(const char *path, size_t max_triangles, qtool_obj_mesh *out, char *err, size_t errlen)
{
    return read_impl(path, max_triangles, 1, out, err, errlen);
}

static int read_impl(const char *path, size_t max_triangles, int materials, qtool_obj_mesh *out, char *err,
                     size_t errlen)
{
    static const qtool_io_kind kind = {"a Wavefront OBJ file", 1, QTOOL_OBJ_MAX_FILE_BYTES, QTOOL_IO_MAX_HEAD_BYTES,
                                      obj_magic};
    size_t n = 0;
    uint8_t *bytes = NULL;
    if (qtool_io_load(path, &kind, &bytes, &n, err, errlen) != 0)
        return -1;
    char *buf = (char *)bytes;
    qtool_obj_mesh m = {0};
    char dir[1024];
    if (qtool_io_dirname(path, dir, sizeof dir) != 0) {
        free(buf);
        return qtool_errf_at(err, errlen, path, 0, "path too long");
    }
    int rc = qtool_obj_parse_dir(path, materials ? dir : NULL, buf, n, max_triangles, &m, err, errlen);
    free(buf);
    if (rc == 0)
        *out = m;
    return rc;
}

void qtool_obj_free(qtool_obj_mesh *m)
{
    free(m->pos);
    free(m->nrm);
    free(m->albedo);
    free(m->uv);
    free(m->tex);
    for (size_t i = 0; m->texs && i < m->ntex; ++i)
        free(m->texs[i].rgb);
    free(m->texs);
    memset(m, 0, sizeof *m);
}
