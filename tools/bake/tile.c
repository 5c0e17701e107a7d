/*
 * bake/tile.c - tile shards (bake/tile.h): pass 1 (a band's map ranges), their reduction, pass 2 (a
 * band's final bytes) and the merge of the parts into the asset.
 */
#include "bake/tile.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "bake/bake.h"
#include "bake/job.h"
#include "bake/path.h"
#include "io/asset_write.h"
#include "io/atomic.h"
#include "io/file.h"
#include "qibl/asset.h"
#include "qibl/lightpath.h"
#include "qtool.h"

static const char RMAGIC[8] = {'Q', 'I', 'B', 'L', 'R', 'N', 'G', 'S'};
static const char PMAGIC[8] = {'Q', 'I', 'B', 'L', 'P', 'A', 'R', 'T'};

void qtool_tile_band(uint32_t h, uint32_t tile, uint32_t ntiles, uint32_t *y0, uint32_t *y1)
{
    *y0 = (uint32_t)((uint64_t)h * tile / ntiles);
    *y1 = (uint32_t)((uint64_t)h * (tile + 1) / ntiles);
}

/* ---- the bake's key ------------------------------------------------------------------------------ */

static void fp_u32(uint32_t *crc, uint32_t v)
{
    uint8_t b[4];
    qtool_store_u32le(b, v);
    *crc = qibl_crc32(*crc, b, 4);
}

static void fp_f64(uint32_t *crc, const double *v, size_t n)
{
    for (size_t i = 0; v && i < n; ++i) {
        uint64_t u;
        memcpy(&u, &v[i], sizeof u); /* the IEEE bits, little-endian: the same on every node */
        fp_u32(crc, (uint32_t)u), fp_u32(crc, (uint32_t)(u >> 32));
    }
}

/* CRC-32 of every option that changes a byte of the asset and of the scene's geometry and materials */
static uint32_t fingerprint(const qtool_bake_opts *o, const qtool_rt_scene *s)
{
    const qtool_scene_opts *so = &o->scene;
    uint32_t c = 0;
    uint32_t u[] = {QTOOL_TILE_PART_VERSION, so->w, so->h, (uint32_t)so->kind, (uint32_t)o->k, (uint32_t)o->uk,
                    (uint32_t)o->ndirs, (uint32_t)o->lsq, (uint32_t)o->lut, o->layout, (uint32_t)o->steps,
                    (uint32_t)o->lamp_samples, (uint32_t)o->has_box, (uint32_t)o->npaths, (uint32_t)so->camera,
                    (uint32_t)so->gltf_cam, (uint32_t)so->zup, (uint32_t)so->raw, (uint32_t)s->ntri,
                    (uint32_t)s->nmat, (uint32_t)s->ntex, (uint32_t)s->has_cam};
    for (size_t i = 0; i < sizeof u / sizeof u[0]; ++i)
        fp_u32(&c, u[i]);
    if (o->has_box)
        fp_f64(&c, o->lamp_box, 6);
    for (int p = 0; p < o->npaths; ++p) {
        const qtool_bake_path *pp = &o->paths[p];
        double v[] = {pp->kind, pp->lat, pp->decl, pp->t0, pp->t1, pp->npts, pp->rgb[0], pp->rgb[1], pp->rgb[2]};
        fp_f64(&c, v, sizeof v / sizeof v[0]);
        for (int i = 0; i < pp->npts; ++i)
            fp_f64(&c, pp->pts[i], 3);
    }
    fp_f64(&c, so->eye, 3), fp_f64(&c, so->target, 3), fp_f64(&c, so->up, 3), fp_f64(&c, &so->fov, 1);
    fp_f64(&c, s->v, 9 * s->ntri), fp_f64(&c, s->n, 9 * s->ntri);
    c = qibl_crc32(c, s->mat, s->ntri);
    for (int m = 0; m < s->nmat; ++m)
        fp_f64(&c, s->mats[m].albedo, 3), fp_f64(&c, &s->mats[m].ks, 1), fp_f64(&c, &s->mats[m].shininess, 1);
    fp_f64(&c, s->alb, 3 * s->ntri), fp_f64(&c, s->uv, 6 * s->ntri);
    for (size_t t = 0; s->tex && t < s->ntri; ++t)
        fp_u32(&c, (uint32_t)s->tex[t]);
    return c;
}

static void store_key(uint8_t *b, const qtool_tile_key *k)
{
    uint32_t v[6] = {k->w, k->h, k->k, k->uk, k->ndirs, k->fp};
    for (int i = 0; i < 6; ++i)
        qtool_store_u32le(b + 4 * i, v[i]);
}

/* the key at b, its limits checked (ntiles: 1..h then checked by the caller). 0 or -1. */
static int load_key(const uint8_t *b, const char *name, qtool_tile_key *k, char *err, size_t errlen)
{
    k->w = qibl_load_u32le(b), k->h = qibl_load_u32le(b + 4), k->k = qibl_load_u32le(b + 8);
    k->uk = qibl_load_u32le(b + 12), k->ndirs = qibl_load_u32le(b + 16), k->fp = qibl_load_u32le(b + 20);
    if (k->w < 1 || k->w > QIBL_ASSET_MAX_DIM || k->h < 1 || k->h > QIBL_ASSET_MAX_DIM ||
        (uint64_t)k->w * k->h > QIBL_ASSET_MAX_PIXELS)
        return qtool_errf(err, errlen, "%s: size %ux%u outside 1..%u per side and %u pixels", name, k->w, k->h,
                          QIBL_ASSET_MAX_DIM, QIBL_ASSET_MAX_PIXELS);
    if (k->k < 1 || k->k > 25 || k->uk > 25)
        return qtool_errf(err, errlen, "%s: k %u, unshadowed k %u outside 1..25 and 0..25", name, k->k, k->uk);
    if (k->ndirs < 1 || k->ndirs > QTOOL_BAKE_MAX_DIRS)
        return qtool_errf(err, errlen, "%s: direction count %u outside 1..%u", name, k->ndirs, QTOOL_BAKE_MAX_DIRS);
    return 0;
}

/* What a ranges file and a tile part share at their head: the magic, the header's size, the version
 * at 8, the key at 12 and the header's CRC (the u32 at crc_at, over b[0..crc_at)). */
typedef struct head_kind {
    const char *magic; /* 8 bytes */
    const char *what;  /* "ranges file": the bad-magic line */
    const char *noun;  /* "ranges": the version line */
    uint32_t header, version, crc_at;
} head_kind;

/* b[0..n)'s head checked in that order and its key into *key; 0, or -1 with err set */
static int load_head(const uint8_t *b, size_t n, const char *name, const head_kind *h, qtool_tile_key *key,
                     char *err, size_t errlen)
{
    if (n < 8 || memcmp(b, h->magic, 8) != 0)
        return qtool_errf(err, errlen, "%s: not a qibl %s (bad magic)", name, h->what);
    if (n < h->header)
        return qtool_errf(err, errlen, "%s: truncated header (%zu of %u bytes)", name, n, h->header);
    if (qibl_load_u32le(b + 8) != h->version)
        return qtool_errf(err, errlen, "%s: unsupported %s version %u (this qibl reads version %u)", name, h->noun,
                          qibl_load_u32le(b + 8), h->version);
    if (qibl_load_u32le(b + h->crc_at) != qibl_crc32(0, b, h->crc_at))
        return qtool_errf(err, errlen, "%s: header checksum mismatch: the file is damaged", name);
    return load_key(b + 12, name, key, err, errlen);
}

/* the first difference of two keys, named ("k 4 against 9"), into why; 0 when they are equal */
static int key_diff(const qtool_tile_key *a, const qtool_tile_key *b, char *why, size_t n)
{
    if (a->w != b->w || a->h != b->h)
        snprintf(why, n, "size %ux%u against %ux%u", a->w, a->h, b->w, b->h);
    else if (a->k != b->k)
        snprintf(why, n, "k %u against %u", a->k, b->k);
    else if (a->uk != b->uk)
        snprintf(why, n, "unshadowed k %u against %u", a->uk, b->uk);
    else if (a->ndirs != b->ndirs)
        snprintf(why, n, "%u directions against %u", a->ndirs, b->ndirs);
    else if (a->fp != b->fp)
        snprintf(why, n, "fingerprint %08x against %08x: other options or another scene", a->fp, b->fp);
    else
        return 0;
    return 1;
}

/* ---- the ranges file ----------------------------------------------------------------------------- */

static size_t nranges(const qtool_tile_key *k)
{
    return 3u * ((size_t)k->k + k->uk);
}

void qtool_tile_ranges_free(qtool_tile_ranges *r)
{
    free(r->lo), free(r->hi);
    r->lo = r->hi = NULL;
}

static int ranges_alloc(qtool_tile_ranges *r)
{
    size_t n = nranges(&r->key);
    r->lo = malloc(sizeof(double) * n), r->hi = malloc(sizeof(double) * n);
    if (!r->lo || !r->hi) {
        qtool_tile_ranges_free(r);
        return -1;
    }
    return 0;
}

static void store_f64(uint8_t *b, double v)
{
    uint64_t u;
    memcpy(&u, &v, sizeof u);
    qtool_store_u32le(b, (uint32_t)u), qtool_store_u32le(b + 4, (uint32_t)(u >> 32));
}

static double load_f64(const uint8_t *b)
{
    uint64_t u = (uint64_t)qibl_load_u32le(b) | (uint64_t)qibl_load_u32le(b + 4) << 32;
    double v;
    memcpy(&v, &u, sizeof v);
    return v;
}

int qtool_tile_ranges_encode(const qtool_tile_ranges *r, uint8_t **out, size_t *n)
{
    size_t nr = nranges(&r->key), size = QTOOL_TILE_RANGES_HEADER + 16 * nr;
    uint8_t *b = calloc(size, 1);
    if (!b)
        return -1;
    memcpy(b, RMAGIC, 8);
    qtool_store_u32le(b + 8, QTOOL_TILE_RANGES_VERSION);
    store_key(b + 12, &r->key);
    qtool_store_u32le(b + 36, r->tile), qtool_store_u32le(b + 40, r->ntiles), qtool_store_u32le(b + 44, r->reduced);
    for (size_t i = 0; i < nr; ++i)
        store_f64(b + QTOOL_TILE_RANGES_HEADER + 16 * i, r->lo[i]),
            store_f64(b + QTOOL_TILE_RANGES_HEADER + 16 * i + 8, r->hi[i]);
    qtool_store_u32le(b + 48, qibl_crc32(0, b + QTOOL_TILE_RANGES_HEADER, size - QTOOL_TILE_RANGES_HEADER));
    qtool_store_u32le(b + 52, qibl_crc32(0, b, 52));
    *out = b, *n = size;
    return 0;
}

int qtool_tile_ranges_decode(const uint8_t *b, size_t n, const char *name, qtool_tile_ranges *out, char *err,
                             size_t errlen)
{
    qtool_tile_ranges r;
    memset(&r, 0, sizeof r);
    static const head_kind ranges = {RMAGIC, "ranges file", "ranges", QTOOL_TILE_RANGES_HEADER,
                                     QTOOL_TILE_RANGES_VERSION, 52};
    if (load_head(b, n, name, &ranges, &r.key, err, errlen) != 0)
        return -1;
    r.tile = qibl_load_u32le(b + 36), r.ntiles = qibl_load_u32le(b + 40), r.reduced = qibl_load_u32le(b + 44);
    if (r.ntiles < 1 || r.ntiles > r.key.h || r.tile >= r.ntiles || r.reduced > 1 || (r.reduced && r.tile != 0))
        return qtool_errf(err, errlen, "%s: tile %u/%u (reduced %u) is not a tile of %u rows", name, r.tile, r.ntiles,
                          r.reduced, r.key.h);
    size_t nr = nranges(&r.key), want = QTOOL_TILE_RANGES_HEADER + 16 * nr;
    if (n != want)
        return qtool_errf(err, errlen, "%s: %zu bytes, the header says %zu (%s)", name, n, want,
                          n < want ? "truncated" : "trailing bytes");
    if (qibl_load_u32le(b + 48) != qibl_crc32(0, b + QTOOL_TILE_RANGES_HEADER, n - QTOOL_TILE_RANGES_HEADER))
        return qtool_errf(err, errlen, "%s: checksum mismatch in the ranges: the file is damaged", name);
    if (ranges_alloc(&r) != 0)
        return qtool_errf(err, errlen, "%s: out of memory", name);
    for (size_t i = 0; i < nr; ++i) {
        r.lo[i] = load_f64(b + QTOOL_TILE_RANGES_HEADER + 16 * i);
        r.hi[i] = load_f64(b + QTOOL_TILE_RANGES_HEADER + 16 * i + 8);
        if (!(isfinite(r.lo[i]) && isfinite(r.hi[i]) && r.lo[i] <= r.hi[i])) {
            qtool_tile_ranges_free(&r);
            return qtool_errf(err, errlen, "%s: range %zu is not finite with minimum <= maximum", name, i);
        }
    }
    *out = r;
    return 0;
}

int qtool_tile_ranges_read(const char *path, qtool_tile_ranges *r, char *err, size_t errlen)
{
    static const qtool_io_kind kind = {"a qibl ranges file", 1, QTOOL_TILE_RANGES_HEADER + 16u * 150u, 0, NULL};
    uint8_t *b;
    size_t n;
    if (qtool_io_load(path, &kind, &b, &n, err, errlen) != 0)
        return -1;
    int rc = qtool_tile_ranges_decode(b, n, path, r, err, errlen);
    free(b);
    return rc;
}

int qtool_tile_ranges_write(const qtool_tile_ranges *r, const char *path, char *err, size_t errlen)
{
    uint8_t *b = NULL;
    size_t n = 0;
    int enc = qtool_tile_ranges_encode(r, &b, &n);
    return qtool_io_write_encoded(path, enc, b, n, err, errlen);
}

/* ---- the band's maps ----------------------------------------------------------------------------- */

/* The band's coefficient maps (shadowed, k maps; unshadowed, uk maps when uk) as a single bake makes
 * them for these rows. With --cache DIR pass 1 also keeps the band's exact sums there and pass 2
 * takes them from there when they are this bake's (same name, size, k, directions; CRCs good),
 * else bakes again. 0, or -1 with err set. */
static int band_maps(const qtool_bake_opts *o, const qtool_rt_scene *s, const qtool_tile_key *key, uint32_t y0,
                     uint32_t y1, qtool_gen_maps *m, qtool_gen_maps *mu, int *from_cache, FILE *log, char *err,
                     size_t errlen)
{
    *from_cache = 0;
    const qtool_scene_opts *so = &o->scene;
    qtool_proj_method method = o->lsq ? QTOOL_PROJ_LSQ : QTOOL_PROJ_QUADRATURE;
    for (int u = 0; u < (o->uk > 0 ? 2 : 1); ++u) {
        qtool_bake_sums sums;
        uint32_t k = (uint32_t)(u ? o->uk : o->k);
        char cpath[4200], why[1200];
        int cached = 0;
        if (o->cache)
            snprintf(cpath, sizeof cpath, "%s/qibl-tile-%08x-%ld-of-%ld.sums%s", o->cache, key->fp, o->tile, o->ntiles,
                     u ? ".u" : "");
        if (o->cache && o->ranges_in) {
            if (qtool_bake_sums_read(cpath, &sums, why, sizeof why) != 0) {
                if (!o->quiet)
                    fprintf(log, "bake: no cached sums (%s): baking the tile again\n", why);
            } else if (sums.w != so->w || sums.h != y1 - y0 || sums.k != k || sums.ndirs != (uint32_t)o->ndirs ||
                       sums.kind != (uint32_t)so->kind || sums.nshards != 1) {
                qtool_bake_sums_free(&sums);
                if (!o->quiet)
                    fprintf(log, "bake: %s is not this tile's sums: baking the tile again\n", cpath);
            } else {
                cached = 1, ++*from_cache;
                if (!o->quiet)
                    fprintf(log, "bake: the tile's %s sums from the cache %s\n", u ? "unshadowed" : "shadowed", cpath);
            }
        }
        if (!cached && qtool_bake_run_rows(s, so->w, so->h, y0, y1, (qtool_pano_kind)so->kind, (uint32_t)o->ndirs, k,
                                           so->threads, o->progress, u, &sums) != 0)
            return qtool_errf(err, errlen, "bake: out of memory");
        if (o->cache && o->ranges_out)
            (void)mkdir(o->cache, 0777); /* the node-local directory, made when missing (its parent must exist) */
        int rc = o->cache && o->ranges_out ? qtool_bake_sums_write(&sums, cpath, err, errlen) : 0;
        if (rc == 0 && qtool_bake_coeffs(&sums, k, method, u ? mu : m) != 0)
            rc = qtool_errf(err, errlen, "bake: cannot project%s",
                            o->lsq ? " by least squares (too few directions?)" : ": out of memory");
        qtool_bake_sums_free(&sums);
        if (rc != 0)
            return -1;
    }
    return 0;
}

/* each plane's minimum and maximum over m, as qtool_pack_maps takes them, into lo, hi */
static void plane_ranges(const qtool_gen_maps *m, double *lo, double *hi)
{
    size_t np = (size_t)m->width * m->height;
    for (uint32_t pl = 0; pl < m->k * 3; ++pl) {
        const double *t = m->t + (size_t)pl * np;
        double a = t[0], b = t[0];
        for (size_t i = 1; i < np; ++i)
            a = t[i] < a ? t[i] : a, b = t[i] > b ? t[i] : b;
        lo[pl] = a, hi[pl] = b;
    }
}

/* ---- pass 1 -------------------------------------------------------------------------------------- */

static int tile_pass1(const qtool_bake_opts *o, const qtool_tile_key *key, const qtool_gen_maps *m,
                      const qtool_gen_maps *mu, FILE *out, char *err, size_t errlen)
{
    qtool_tile_ranges r = {.key = *key, .tile = (uint32_t)o->tile, .ntiles = (uint32_t)o->ntiles, .reduced = 0};
    if (ranges_alloc(&r) != 0)
        return qtool_errf(err, errlen, "bake: out of memory");
    plane_ranges(m, r.lo, r.hi);
    if (o->uk > 0)
        plane_ranges(mu, r.lo + 3 * (size_t)key->k, r.hi + 3 * (size_t)key->k);
    int rc = qtool_tile_ranges_write(&r, o->ranges_out, err, errlen);
    qtool_tile_ranges_free(&r);
    if (rc == 0)
        fprintf(out, "wrote %s: the map ranges of tile %ld/%ld\n", o->ranges_out, o->tile, o->ntiles);
    return rc;
}

/* ---- pass 2 -------------------------------------------------------------------------------------- */

/* the band y0..y1 of a whole-height LPTH payload (other rows empty) as an LPTH payload of w x rows */
static int lpth_band(const uint8_t *full, size_t n, uint32_t y0, uint32_t y1, uint8_t **out, size_t *outn)
{
    qibl_lightpath_t lp;
    if (qibl_lightpath_parse(full, n, &lp) != QIBL_OK)
        return -1;
    uint32_t a = qibl_load_u32le(lp.rows + 4 * (size_t)y0), e = qibl_load_u32le(lp.rows + 4 * (size_t)y1);
    uint32_t rows = y1 - y0, w = lp.width;
    size_t head = QIBL_LIGHTPATH_HEADER + 16u * (size_t)lp.nkeys;
    size_t size = head + 4u * ((size_t)rows + 1) + (size_t)w * rows + 2u * (size_t)(e - a);
    uint8_t *b = malloc(size);
    if (!b)
        return -1;
    memcpy(b, full, head);
    qtool_store_u32le(b + 4, rows), qtool_store_u32le(b + 20, e - a);
    for (uint32_t y = 0; y <= rows; ++y)
        qtool_store_u32le(b + head + 4 * (size_t)y, qibl_load_u32le(lp.rows + 4 * ((size_t)y0 + y)) - a);
    uint8_t *cnt = b + head + 4u * ((size_t)rows + 1);
    memcpy(cnt, lp.counts + (size_t)y0 * w, (size_t)w * rows);
    memcpy(cnt + (size_t)w * rows, lp.edges + 2 * (size_t)a, 2 * (size_t)(e - a));
    *out = b, *outn = size;
    return 0;
}

/* the band's light paths and lamp occlusion (payloads of w x rows) into paths/sizes and *locc */
static int band_extras(const qtool_bake_opts *o, const qtool_rt_scene *s, uint32_t y0, uint32_t y1, uint8_t **paths,
                       size_t *sizes, uint8_t **locc, size_t *locc_n, char *err, size_t errlen)
{
    const qtool_scene_opts *so = &o->scene;
    for (int p = 0; p < o->npaths; ++p) {
        uint8_t *full = NULL;
        size_t n = 0;
        double st[2];
        int bad = qtool_bake_path_chunk_band(s, so->w, so->h, (qtool_pano_kind)so->kind, &o->paths[p],
                                             (uint32_t)o->steps, 65, y0, y1, so->threads, &full, &n, st) != 0 ||
                  lpth_band(full, n, y0, y1, &paths[p], &sizes[p]) != 0;
        free(full);
        if (bad)
            return qtool_errf(err, errlen, "bake: out of memory (light path %d)", p + 1);
    }
    if (o->has_box) {
        uint8_t *occ = malloc((size_t)so->w * so->h);
        int bad = !occ ||
                  qtool_bake_lamp_occlusion_band(s, so->w, so->h, (qtool_pano_kind)so->kind, o->lamp_box,
                                                 (uint32_t)o->lamp_samples, y0, y1, so->threads, occ) != 0 ||
                  qtool_bake_locc_payload(so->w, y1 - y0, occ + (size_t)y0 * so->w, locc, locc_n) != 0;
        free(occ);
        if (bad)
            return qtool_errf(err, errlen, "bake: out of memory (lamp occlusion)");
    }
    return 0;
}

/* one map set's scale, bias and bytes against the whole image's ranges at *at */
static uint8_t *put_planes(uint8_t *at, const qtool_gen_maps *m, const double *lo, const double *hi)
{
    size_t np = (size_t)m->width * m->height, nplanes = (size_t)m->k * 3;
    for (size_t pl = 0; pl < nplanes; ++pl) {
        int32_t s, b;
        qtool_pack_range(lo[pl], hi[pl], &s, &b);
        qtool_store_u32le(at + 4 * pl, (uint32_t)s), qtool_store_u32le(at + 4 * (nplanes + pl), (uint32_t)b);
        uint8_t *o = at + 8 * nplanes + pl * np;
        for (size_t i = 0; i < np; ++i)
            o[i] = qtool_pack_code(m->t[pl * np + i], s, b);
    }
    return at + 8 * nplanes + nplanes * np;
}

/* the reduced ranges r for this bake (key, tiles) and covering the band's maps. 0 or -1. */
static int ranges_fit(const qtool_bake_opts *o, const qtool_tile_key *key, const qtool_tile_ranges *r, double *blo,
                      double *bhi, char *err, size_t errlen)
{
    char why[200];
    if (!r->reduced)
        return qtool_errf(err, errlen, "%s: the ranges of tile %u/%u alone: reduce every tile's with qibl merge "
                          "--ranges -o R FILE...", o->ranges_in, r->tile, r->ntiles);
    if (key_diff(&r->key, key, why, sizeof why))
        return qtool_errf(err, errlen, "%s: the ranges of another bake (%s)", o->ranges_in, why);
    if (r->ntiles != (uint32_t)o->ntiles)
        return qtool_errf(err, errlen, "%s: the ranges of %u tiles, this is tile %ld/%ld", o->ranges_in, r->ntiles,
                          o->tile, o->ntiles);
    for (size_t i = 0; i < nranges(key); ++i)
        if (blo[i] < r->lo[i] || bhi[i] > r->hi[i])
            return qtool_errf(err, errlen, "%s: map %zu of this tile reaches %g..%g, outside the ranges %g..%g (the "
                              "ranges of another bake)", o->ranges_in, i, blo[i], bhi[i], r->lo[i], r->hi[i]);
    return 0;
}

static int tile_pass2(const qtool_bake_opts *o, const qtool_rt_scene *s, const qtool_tile_key *key, uint32_t y0,
                      uint32_t y1, const qtool_gen_maps *m, const qtool_gen_maps *mu, int cached, FILE *out, char *err,
                      size_t errlen)
{
    qtool_tile_ranges r;
    if (qtool_tile_ranges_read(o->ranges_in, &r, err, errlen) != 0)
        return -1;
    size_t nr = nranges(key), np = (size_t)key->w * (y1 - y0);
    double *blo = malloc(sizeof(double) * nr), *bhi = malloc(sizeof(double) * nr);
    uint8_t *paths[QTOOL_TILE_MAX_PATHS] = {0}, *locc = NULL, *b = NULL;
    size_t sizes[QTOOL_TILE_MAX_PATHS] = {0}, locc_n = 0;
    int rc = -1;
    if (!blo || !bhi) {
        qtool_errf(err, errlen, "bake: out of memory");
        goto done;
    }
    plane_ranges(m, blo, bhi);
    if (key->uk)
        plane_ranges(mu, blo + 3 * (size_t)key->k, bhi + 3 * (size_t)key->k);
    if (ranges_fit(o, key, &r, blo, bhi, err, errlen) != 0 ||
        band_extras(o, s, y0, y1, paths, sizes, &locc, &locc_n, err, errlen) != 0)
        goto done;
    uint64_t body = 8 * nr + (uint64_t)nr * np + 12 * (uint64_t)np + (locc ? locc_n : 0);
    for (int p = 0; p < o->npaths; ++p)
        body += 4 + sizes[p];
    b = malloc(QTOOL_TILE_PART_HEADER + (size_t)body);
    if (!b) {
        qtool_errf(err, errlen, "bake: out of memory");
        goto done;
    }
    uint8_t *at = put_planes(b + QTOOL_TILE_PART_HEADER, m, r.lo, r.hi);
    for (size_t i = 0; i < np * 3; ++i, at += 4)
        qtool_store_u32le(at, (uint32_t)m->p[i]);
    if (key->uk)
        at = put_planes(at, mu, r.lo + 3 * (size_t)key->k, r.hi + 3 * (size_t)key->k);
    for (int p = 0; p < o->npaths; ++p) {
        qtool_store_u32le(at, (uint32_t)sizes[p]);
        memcpy(at + 4, paths[p], sizes[p]);
        at += 4 + sizes[p];
    }
    if (locc)
        memcpy(at, locc, locc_n);
    uint8_t rb[QTOOL_TILE_RANGES_HEADER];
    uint8_t *renc;
    size_t rn;
    if (qtool_tile_ranges_encode(&r, &renc, &rn) != 0) {
        qtool_errf(err, errlen, "bake: out of memory");
        goto done;
    }
    memcpy(rb, renc, sizeof rb);
    free(renc);
    memcpy(b, PMAGIC, 8);
    qtool_store_u32le(b + 8, QTOOL_TILE_PART_VERSION);
    store_key(b + 12, key);
    uint32_t v[6] = {(uint32_t)o->tile, (uint32_t)o->ntiles, (uint32_t)o->lut, o->layout, (uint32_t)o->npaths,
                     locc ? 1u : 0u};
    for (int i = 0; i < 6; ++i)
        qtool_store_u32le(b + 36 + 4 * i, v[i]);
    qtool_store_u32le(b + 60, qibl_load_u32le(rb + 48));
    qtool_store_u32le(b + 64, (uint32_t)body), qtool_store_u32le(b + 68, (uint32_t)(body >> 32));
    qtool_store_u32le(b + 72, qibl_crc32(0, b + QTOOL_TILE_PART_HEADER, (size_t)body));
    qtool_store_u32le(b + 76, qibl_crc32(0, b, 76));
    rc = qtool_io_write_atomic(o->part_out, b, QTOOL_TILE_PART_HEADER + (size_t)body, err, errlen);
    if (rc == 0)
        fprintf(out, "wrote %s: tile %ld/%ld, rows %u..%u, %llu bytes%s\n", o->part_out, o->tile, o->ntiles, y0, y1 - 1,
                (unsigned long long)(QTOOL_TILE_PART_HEADER + body),
                cached == 0                    ? ""
                : cached == (key->uk ? 2 : 1) ? " (sums from the cache)"
                                               : " (some sums from the cache)");
done:
    for (uint32_t p = 0; p < QTOOL_TILE_MAX_PATHS; ++p)
        free(paths[p]);
    free(locc), free(b), free(blo), free(bhi);
    qtool_tile_ranges_free(&r);
    return rc;
}

int qtool_tile_bake(const qtool_bake_opts *o, FILE *out, FILE *log, char *err, size_t errlen)
{
    const qtool_scene_opts *so = &o->scene;
    qtool_rt_scene s;
    if (qtool_scene_load(so, &s, err, errlen) != 0)
        return -1;
    uint32_t y0, y1;
    qtool_tile_band(so->h, (uint32_t)o->tile, (uint32_t)o->ntiles, &y0, &y1);
    qtool_tile_key key = {so->w, so->h, (uint32_t)o->k, (uint32_t)o->uk, (uint32_t)o->ndirs, fingerprint(o, &s)};
    qtool_gen_maps m = {0}, mu = {0};
    double t0 = qtool_bake_now();
    int cached;
    int rc = band_maps(o, &s, &key, y0, y1, &m, &mu, &cached, log, err, errlen);
    if (rc == 0 && !o->quiet)
        fprintf(log, "bake: tile %ld/%ld, rows %u..%u of %ux%u, %ld directions, %zu triangles, %.1f s on %d threads\n",
                o->tile, o->ntiles, y0, y1 - 1, so->w, so->h, o->ndirs, s.ntri, qtool_bake_now() - t0, so->threads);
    if (rc == 0)
        rc = o->ranges_out ? tile_pass1(o, &key, &m, &mu, out, err, errlen)
                           : tile_pass2(o, &s, &key, y0, y1, &m, &mu, cached, out, err, errlen);
    qtool_gen_free(&m), qtool_gen_free(&mu);
    qtool_rt_scene_free(&s);
    return rc;
}

/* ---- reduce -------------------------------------------------------------------------------------- */

/* Checks that file i (tile t of n, key k) belongs with the first (key k0, n0 tiles) and was not
 * seen; seen[t] = i + 1. 0 or -1 with the reason naming both files. */
static int same_set(char *const *in, int i, const qtool_tile_key *k, const qtool_tile_key *k0, uint32_t t, uint32_t n,
                    uint32_t n0, int *seen, const char *what, char *err, size_t errlen)
{
    char why[200];
    if (key_diff(k, k0, why, sizeof why))
        return qtool_errf(err, errlen, "%s: %s of another bake than %s (%s)", in[i], what, in[0], why);
    if (n != n0)
        return qtool_errf(err, errlen, "%s: tile %u/%u, %s is of %u tiles: overlapping tiles of another split",
                          in[i], t, n, in[0], n0);
    if (seen[t])
        return qtool_errf(err, errlen, "%s: tile %u/%u given twice (also %s)", in[i], t, n, in[seen[t] - 1]);
    seen[t] = i + 1;
    return 0;
}

static int all_seen(const int *seen, uint32_t n, char *err, size_t errlen)
{
    for (uint32_t t = 0; t < n; ++t)
        if (!seen[t])
            return qtool_errf(err, errlen, "merge: tile %u/%u is missing (every tile exactly once)", t, n);
    return 0;
}

int qtool_tile_reduce(const char *out_path, char *const *in, int nin, FILE *out, char *err, size_t errlen)
{
    qtool_tile_ranges total = {0}, r;
    int *seen = NULL, rc = -1;
    for (int i = 0; i < nin; ++i) {
        if (qtool_tile_ranges_read(in[i], &r, err, errlen) != 0)
            goto done;
        int bad = 0;
        if (r.reduced)
            bad = qtool_errf(err, errlen, "%s: already reduced (the ranges of all %u tiles): give every tile's own "
                             "ranges once", in[i], r.ntiles);
        else if (i == 0) {
            total = r;
            seen = calloc(r.ntiles, sizeof *seen);
            if (!seen) {
                qtool_errf(err, errlen, "merge: out of memory");
                goto done;
            }
            seen[r.tile] = 1;
            continue;
        } else if (same_set(in, i, &r.key, &total.key, r.tile, r.ntiles, total.ntiles, seen, "the ranges", err,
                            errlen) != 0)
            bad = -1;
        for (size_t p = 0; !bad && p < nranges(&r.key); ++p) {
            total.lo[p] = r.lo[p] < total.lo[p] ? r.lo[p] : total.lo[p];
            total.hi[p] = r.hi[p] > total.hi[p] ? r.hi[p] : total.hi[p];
        }
        qtool_tile_ranges_free(&r);
        if (bad)
            goto done;
    }
    if (nin < 1 || all_seen(seen, total.ntiles, err, errlen) != 0)
        goto done;
    total.tile = 0, total.reduced = 1;
    rc = qtool_tile_ranges_write(&total, out_path, err, errlen);
    if (rc == 0)
        fprintf(out, "wrote %s: the map ranges of all %u tiles\n", out_path, total.ntiles);
done:
    free(seen);
    qtool_tile_ranges_free(&total);
    return rc;
}

/* ---- merge --------------------------------------------------------------------------------------- */

typedef struct {
    qtool_tile_key key;
    uint32_t tile, ntiles, lut, layout, npaths, has_locc, ranges_crc, y0, y1;
    const uint8_t *sh, *pmap, *shu; /* scale, bias, planes; P map */
    const uint8_t *path[QTOOL_TILE_MAX_PATHS];
    size_t path_n[QTOOL_TILE_MAX_PATHS];
    const uint8_t *locc;
    uint8_t *buf;
} tile_part;

int qtool_tile_is_part(const char *path)
{
    FILE *f = fopen(path, "rb");
    uint8_t b[8];
    int part = f && fread(b, 1, 8, f) == 8 && memcmp(b, PMAGIC, 8) == 0;
    if (f)
        fclose(f);
    return part;
}

/* b[0..n) as a part (the buffer kept in p); every size checked before use. 0 or -1. */
static int part_decode(uint8_t *b, size_t n, const char *name, tile_part *p, char *err, size_t errlen)
{
    memset(p, 0, sizeof *p);
    static const head_kind part = {PMAGIC, "tile part", "part", QTOOL_TILE_PART_HEADER, QTOOL_TILE_PART_VERSION,
                                   76};
    if (load_head(b, n, name, &part, &p->key, err, errlen) != 0)
        return -1;
    p->tile = qibl_load_u32le(b + 36), p->ntiles = qibl_load_u32le(b + 40), p->lut = qibl_load_u32le(b + 44);
    p->layout = qibl_load_u32le(b + 48), p->npaths = qibl_load_u32le(b + 52), p->has_locc = qibl_load_u32le(b + 56);
    p->ranges_crc = qibl_load_u32le(b + 60);
    if (p->ntiles < 1 || p->ntiles > p->key.h || p->tile >= p->ntiles)
        return qtool_errf(err, errlen, "%s: tile %u/%u is not a tile of %u rows", name, p->tile, p->ntiles, p->key.h);
    if (p->npaths > QTOOL_TILE_MAX_PATHS || p->has_locc > 1 || p->lut > 1024 || p->layout > 1 ||
        (p->npaths + p->has_locc && !p->key.uk))
        return qtool_errf(err, errlen, "%s: %u light paths, lamp occlusion %u, LUT %u, layout %u: not a part qibl "
                          "writes", name, p->npaths, p->has_locc, p->lut, p->layout);
    uint64_t body = (uint64_t)qibl_load_u32le(b + 64) | (uint64_t)qibl_load_u32le(b + 68) << 32;
    if (body != n - QTOOL_TILE_PART_HEADER)
        return qtool_errf(err, errlen, "%s: %zu bytes of body, the header says %llu (%s)", name,
                          n - QTOOL_TILE_PART_HEADER, (unsigned long long)body,
                          n - QTOOL_TILE_PART_HEADER < body ? "truncated" : "trailing bytes");
    if (qibl_load_u32le(b + 72) != qibl_crc32(0, b + QTOOL_TILE_PART_HEADER, (size_t)body))
        return qtool_errf(err, errlen, "%s: checksum mismatch in the body: the file is damaged", name);
    qtool_tile_band(p->key.h, p->tile, p->ntiles, &p->y0, &p->y1);
    size_t np = (size_t)p->key.w * (p->y1 - p->y0), rows = p->y1 - p->y0;
    size_t fixed = (8 + np) * 3 * ((size_t)p->key.k + p->key.uk) + 12 * np, left = (size_t)body;
    const uint8_t *at = b + QTOOL_TILE_PART_HEADER;
    if (left < fixed)
        return qtool_errf(err, errlen, "%s: %zu bytes of body, its maps alone take %zu", name, left, fixed);
    p->sh = at, at += (8 + np) * 3 * p->key.k;
    p->pmap = at, at += 12 * np;
    p->shu = p->key.uk ? at : NULL, at += (8 + np) * 3 * p->key.uk;
    left -= fixed;
    for (uint32_t i = 0; i < p->npaths; ++i) {
        qibl_lightpath_t lp;
        size_t sz = left >= 4 ? qibl_load_u32le(at) : 0;
        if (left < 4 || sz > left - 4)
            return qtool_errf(err, errlen, "%s: light path %u runs past the end", name, i + 1);
        qibl_status_t st = qibl_lightpath_parse(at + 4, sz, &lp);
        if (st != QIBL_OK || lp.width != p->key.w || lp.height != rows)
            return qtool_errf(err, errlen, "%s: light path %u is not an LPTH of its %ux%zu band (%s)", name, i + 1,
                              p->key.w, rows, st != QIBL_OK ? qibl_status_str(st) : "size");
        p->path[i] = at + 4, p->path_n[i] = sz;
        at += 4 + sz, left -= 4 + sz;
    }
    if (p->has_locc) {
        qibl_lampocc_t lo;
        if (left != QIBL_LAMPOCC_HEADER + np || qibl_lightpath_occl_parse(at, left, &lo) != QIBL_OK ||
            lo.width != p->key.w || lo.height != rows)
            return qtool_errf(err, errlen, "%s: the lamp occlusion is not a LOCC of its %ux%zu band", name, p->key.w,
                              rows);
        p->locc = at, left = 0;
    }
    if (left)
        return qtool_errf(err, errlen, "%s: %zu bytes after the last chunk", name, left);
    p->buf = b;
    return 0;
}

int qtool_tile_part_check(const uint8_t *b, size_t n, const char *name, char *err, size_t errlen)
{
    tile_part p;
    return part_decode((uint8_t *)(uintptr_t)b, n, name, &p, err, errlen); /* p only points into b */
}

/* a part's other header fields against the first's: the same bake's pass 2 with the same ranges */
static int part_matches(const tile_part *p, const tile_part *p0, const char *name, const char *name0, char *err,
                        size_t errlen)
{
    if (p->ranges_crc != p0->ranges_crc)
        return qtool_errf(err, errlen, "%s: packed against other ranges than %s (give every tile's pass 2 the same "
                          "reduced ranges file)", name, name0);
    if (p->lut != p0->lut || p->layout != p0->layout || p->npaths != p0->npaths || p->has_locc != p0->has_locc)
        return qtool_errf(err, errlen, "%s: LUT, layout, light paths or lamp occlusion differ from %s (another bake)",
                          name, name0);
    if (memcmp(p->sh, p0->sh, 24 * (size_t)p->key.k) != 0 ||
        (p->key.uk && memcmp(p->shu, p0->shu, 24 * (size_t)p->key.uk) != 0))
        return qtool_errf(err, errlen, "%s: scale and bias differ from %s's (the file is damaged)", name, name0);
    for (uint32_t i = 0; i < p->npaths; ++i) {
        qibl_lightpath_t a, b;
        QIBL_DROP_STATUS(qibl_lightpath_parse(p->path[i], p->path_n[i], &a)); /* checked at decode */
        QIBL_DROP_STATUS(qibl_lightpath_parse(p0->path[i], p0->path_n[i], &b));
        if (a.kind != b.kind || a.nkeys != b.nkeys || memcmp(a.keys, b.keys, 16u * a.nkeys) != 0)
            return qtool_errf(err, errlen, "%s: light path %u is not the one of %s (another bake)", name, i + 1, name0);
    }
    return 0;
}

/* one map set (k maps) of every part, whole planes, with the scale and bias of the first */
static void join_planes(tile_part *const *by, uint32_t n, int unshadowed, uint32_t k, size_t np, int32_t *scale,
                        int32_t *bias, uint8_t *planes)
{
    size_t nplanes = 3 * (size_t)k;
    const uint8_t *s0 = unshadowed ? by[0]->shu : by[0]->sh;
    for (size_t pl = 0; pl < nplanes; ++pl)
        scale[pl] = qibl_load_s32le(s0 + 4 * pl), bias[pl] = qibl_load_s32le(s0 + 4 * (nplanes + pl));
    for (uint32_t t = 0; t < n; ++t) {
        const tile_part *p = by[t];
        size_t bn = (size_t)p->key.w * (p->y1 - p->y0), off = (size_t)p->key.w * p->y0;
        const uint8_t *src = (unshadowed ? p->shu : p->sh) + 8 * nplanes;
        for (size_t pl = 0; pl < nplanes; ++pl)
            memcpy(planes + pl * np + off, src + pl * bn, bn);
    }
}

/* light path i of every part as one LPTH payload of the whole image. 0 or -1. */
static int join_path(tile_part *const *by, uint32_t n, uint32_t i, uint8_t **out, size_t *outn, char *err,
                     size_t errlen)
{
    uint32_t w = by[0]->key.w, h = by[0]->key.h;
    uint64_t nedges = 0;
    qibl_lightpath_t lp[1];
    for (uint32_t t = 0; t < n; ++t) {
        QIBL_DROP_STATUS(qibl_lightpath_parse(by[t]->path[i], by[t]->path_n[i], lp)); /* checked at decode */
        nedges += lp->nedges;
    }
    if (nedges > QIBL_LIGHTPATH_MAX_EDGES)
        return qtool_errf(err, errlen, "merge: light path %u: %llu edges joined (at most %u)", i + 1,
                          (unsigned long long)nedges, QIBL_LIGHTPATH_MAX_EDGES);
    size_t head = QIBL_LIGHTPATH_HEADER + 16u * (size_t)lp->nkeys, np = (size_t)w * h;
    size_t size = head + 4u * ((size_t)h + 1) + np + 2u * (size_t)nedges;
    uint8_t *b = malloc(size);
    if (!b)
        return qtool_errf(err, errlen, "merge: out of memory joining light path %u", i + 1);
    memcpy(b, by[0]->path[i], head); /* kind, keys: the same in every part (checked) */
    qtool_store_u32le(b + 4, h), qtool_store_u32le(b + 20, (uint32_t)nedges);
    uint8_t *rows = b + head, *cnt = rows + 4u * ((size_t)h + 1), *ed = cnt + np;
    uint32_t at = 0;
    for (uint32_t t = 0; t < n; ++t) {
        const tile_part *p = by[t];
        QIBL_DROP_STATUS(qibl_lightpath_parse(p->path[i], p->path_n[i], lp));
        for (uint32_t y = 0; y < p->y1 - p->y0; ++y)
            qtool_store_u32le(rows + 4 * ((size_t)p->y0 + y), at + qibl_load_u32le(lp->rows + 4 * (size_t)y));
        memcpy(cnt + (size_t)w * p->y0, lp->counts, (size_t)w * (p->y1 - p->y0));
        memcpy(ed + 2 * (size_t)at, lp->edges, 2 * (size_t)lp->nedges);
        at += lp->nedges;
    }
    qtool_store_u32le(rows + 4 * (size_t)h, at);
    *out = b, *outn = size;
    return 0;
}

/* the asset from every part (by[t]: tile t) into *asset. 0 or -1. */
static int build_asset(tile_part *const *by, uint32_t n, uint8_t **asset, size_t *asset_n, char *err, size_t errlen)
{
    const tile_part *p0 = by[0];
    uint32_t w = p0->key.w, h = p0->key.h, k = p0->key.k, uk = p0->key.uk;
    size_t np = (size_t)w * h, npl = 3 * ((size_t)k + uk);
    int32_t *scale = malloc(sizeof(int32_t) * npl), *bias = malloc(sizeof(int32_t) * npl), *pmap = malloc(12 * np);
    uint8_t *planes = malloc(np * npl), *paths[QTOOL_TILE_MAX_PATHS + 1] = {0}, *locc = NULL, *bytes = NULL;
    size_t sizes[QTOOL_TILE_MAX_PATHS + 1] = {0};
    int rc = -1;
    if (!scale || !bias || !pmap || !planes || (p0->has_locc && !(locc = malloc(QIBL_LAMPOCC_HEADER + np)))) {
        qtool_errf(err, errlen, "merge: out of memory");
        goto done;
    }
    join_planes(by, n, 0, k, np, scale, bias, planes);
    if (uk)
        join_planes(by, n, 1, uk, np, scale + 3 * k, bias + 3 * k, planes + 3 * k * np);
    for (uint32_t t = 0; t < n; ++t) {
        const tile_part *p = by[t];
        size_t off = (size_t)w * p->y0, bn = (size_t)w * (p->y1 - p->y0);
        for (size_t i = 0; i < 3 * bn; ++i)
            pmap[3 * off + i] = qibl_load_s32le(p->pmap + 4 * i);
        if (locc)
            memcpy(locc + QIBL_LAMPOCC_HEADER + off, p->locc + QIBL_LAMPOCC_HEADER, bn);
    }
    if (locc)
        qtool_store_u32le(locc, w), qtool_store_u32le(locc + 4, h);
    for (uint32_t i = 0; i < p0->npaths; ++i)
        if (join_path(by, n, i, &paths[i], &sizes[i], err, errlen) != 0)
            goto done;
    qtool_bake_packed sh = {w, h, k, scale, bias, planes, pmap};
    qtool_bake_packed shu = {w, h, uk, scale + 3 * k, bias + 3 * k, planes + 3 * k * np, NULL};
    size_t bn = 0;
    if (qtool_bake_asset_packed(&sh, uk ? &shu : NULL, p0->lut, p0->layout, paths, sizes, &bytes, &bn) != 0) {
        qtool_errf(err, errlen, "merge: cannot build the asset (out of memory)");
        goto done;
    }
    if (locc) { /* appended as qibl bake appends it (qtool_bake_finish_asset) */
        uint8_t *b2 = NULL;
        size_t n2 = 0;
        int bad = qtool_bake_asset_add(bytes, bn, QIBL_CHUNK_LOCC, locc, QIBL_LAMPOCC_HEADER + np, &b2, &n2);
        free(bytes);
        bytes = b2, bn = n2;
        if (bad) {
            qtool_errf(err, errlen, "merge: cannot build the asset (out of memory)");
            goto done;
        }
    }
    *asset = bytes, *asset_n = bn, bytes = NULL, rc = 0;
done:
    for (uint32_t i = 0; i < QTOOL_TILE_MAX_PATHS; ++i)
        free(paths[i]);
    free(scale), free(bias), free(pmap), free(planes), free(locc), free(bytes);
    return rc;
}

int qtool_tile_merge(const char *out_path, char *const *in, int nin, FILE *out, char *err, size_t errlen)
{
    static const qtool_io_kind kind = {"a qibl tile part", 1, QTOOL_IO_MAX_FILE_BYTES, 0, NULL};
    tile_part *parts = calloc((size_t)(nin > 0 ? nin : 1), sizeof *parts), **by = NULL;
    int *seen = NULL, rc = -1;
    if (!parts)
        return qtool_errf(err, errlen, "merge: out of memory");
    for (int i = 0; i < nin; ++i) {
        uint8_t *b;
        size_t n;
        if (qtool_io_load(in[i], &kind, &b, &n, err, errlen) != 0)
            goto done;
        if (part_decode(b, n, in[i], &parts[i], err, errlen) != 0) {
            free(b);
            goto done;
        }
        if (i == 0) {
            seen = calloc(parts[0].ntiles, sizeof *seen);
            by = calloc(parts[0].ntiles, sizeof *by);
            if (!seen || !by) {
                qtool_errf(err, errlen, "merge: out of memory");
                goto done;
            }
            seen[parts[0].tile] = 1;
        } else if (same_set(in, i, &parts[i].key, &parts[0].key, parts[i].tile, parts[i].ntiles, parts[0].ntiles, seen,
                            "a part", err, errlen) != 0 ||
                   part_matches(&parts[i], &parts[0], in[i], in[0], err, errlen) != 0)
            goto done;
        by[parts[i].tile] = &parts[i];
    }
    uint8_t *asset = NULL;
    size_t an = 0;
    if (nin < 1 || all_seen(seen, parts[0].ntiles, err, errlen) != 0 ||
        build_asset(by, parts[0].ntiles, &asset, &an, err, errlen) != 0)
        goto done;
    rc = qtool_io_write_atomic(out_path, asset, an, err, errlen);
    free(asset);
    if (rc == 0)
        fprintf(out, "wrote %s: %ux%u from %u tile parts, k = %u, unshadowed k = %u, %u light path%s%s, %zu bytes\n",
                out_path, parts[0].key.w, parts[0].key.h, parts[0].ntiles, parts[0].key.k, parts[0].key.uk,
                parts[0].npaths, parts[0].npaths == 1 ? "" : "s", parts[0].has_locc ? ", lamp occlusion" : "", an);
done:
    for (int i = 0; i < nin; ++i)
        free(parts[i].buf);
    free(parts), free(by), free(seen);
    return rc;
}
