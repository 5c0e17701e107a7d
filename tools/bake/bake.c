/*
 * bake/bake.c - reference renders -> SH sums (exact int64 accumulation) -> coefficients -> asset;
 * held-out evaluation through the core.
 */
#include "bake/bake.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/stat.h>
#include <unistd.h>

#include "io/asset_write.h"
#include "io/atomic.h"
#include "qibl/asset.h"
#include "qibl/lightpath.h"
#include "qibl/shmap.h"
#include "qibl/soft.h"
#include "qtool.h"
#include "ref/sh_ref.h"

#define UNIT 4294967296.0 /* 2^32 */

double qtool_bake_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

qibl_fb_desc_t qtool_bake_fb_srgb(uint8_t *pix, uint32_t w, uint32_t h)
{
    qibl_fb_desc_t fb = {0};
    fb.pixels = pix, fb.width = w, fb.height = h, fb.format = QIBL_FB_RGBA8888, fb.srgb = 1;
    return fb;
}

int qtool_bake_frame_done(qibl_status_t st, double t0, double *ms, const uint8_t *pix, uint32_t w, uint32_t h,
                          uint8_t *rgb8, qibl_status_t *status)
{
    if (ms)
        *ms = (qtool_bake_now() - t0) * 1e3;
    for (size_t i = 0; st == QIBL_OK && i < (size_t)w * h; ++i)
        memcpy(rgb8 + 3 * i, pix + 4 * i, 3);
    if (status)
        *status = st;
    return st == QIBL_OK ? 0 : -1;
}

qibl_status_t qtool_bake_frame_row(const qibl_fb_desc_t *fb, uint32_t y, uint32_t w, const int32_t *row, float *lin)
{
    qibl_status_t st = qibl_soft_fb_write_row(fb, 0, y, w, row);
    if (st == QIBL_OK && lin) {
        float *o = lin + (size_t)y * w * 3;
        for (size_t i = 0; i < (size_t)w * 3; ++i)
            o[i] = row[i] > 0 ? (float)(row[i] / 65536.0) : 0.0f;
    }
    return st;
}

int qtool_bake_frame_alloc(qibl_status_t st, uint32_t w, uint32_t h, size_t rows, size_t scratch, size_t wsn,
                           qtool_bake_frame *f, qibl_status_t *status)
{
    *f = (qtool_bake_frame){0};
    if (status)
        *status = st;
    if (st != QIBL_OK)
        return -1;
    f->pix = malloc((size_t)w * h * 4);
    f->row = malloc(sizeof(int32_t) * 3 * w * rows);
    f->scratch = scratch ? malloc(scratch) : NULL;
    f->ws = malloc(wsn);
    f->wsn = wsn;
    if (f->pix && f->row && (f->scratch || !scratch) && f->ws)
        return 0;
    free(f->pix), free(f->row), free(f->scratch), free(f->ws);
    *f = (qtool_bake_frame){0};
    if (status)
        *status = QTOOL_E_NOMEM;
    return -1;
}

int qtool_bake_frame_finish(qtool_bake_frame *f, qibl_status_t st, double t0, double *ms, uint32_t w, uint32_t h,
                            uint8_t *rgb8, qibl_status_t *status)
{
    int rc = qtool_bake_frame_done(st, t0, ms, f->pix, w, h, rgb8, status);
    free(f->pix), free(f->row), free(f->scratch), free(f->ws);
    *f = (qtool_bake_frame){0};
    return rc;
}

void qtool_bake_dir(uint32_t j, uint32_t n, double d[3])
{
    double z = 1.0 - (2.0 * j + 1.0) / n, r = sqrt(fmax(0.0, 1 - z * z));
    double phi = fmod(j * (QTOOL_PI * (3.0 - sqrt(5.0))), 2 * QTOOL_PI);
    d[0] = r * cos(phi), d[1] = r * sin(phi), d[2] = z;
}

typedef struct {
    const qtool_rt_scene *s;
    uint32_t w, h, k, ndirs, shard, nshards;
    uint32_t row0, fullh; /* out holds image rows row0 .. row0 + h - 1 of a fullh-row image (a tile) */
    qtool_pano_kind kind;
    double *dirs, *y; /* ndirs * 3, ndirs * 25 */
    qtool_bake_sums *out;
    int progress; /* 0 none, 1 bar, 2 lines */
    double t0;
    int unshadowed; /* 1: cosine x BRDF without the shadow test (SHMU) */
} bake_job;

static void bake_row(void *ctx, uint32_t row)
{
    const bake_job *j = ctx;
    uint32_t k = j->k, nblocks = (j->ndirs + QTOOL_BAKE_BLOCK - 1) / QTOOL_BAKE_BLOCK;
    for (uint32_t x = 0; x < j->w; ++x) {
        size_t pi = (size_t)row * j->w + x;
        double d[3];
        qtool_rt_hit h;
        double sky[3];
        qtool_rt_pixel_ray(j->s, j->w, j->fullh, j->kind, x, j->row0 + row, d);
        qtool_rt_primary(j->s, d, &h);
        qtool_rt_sky_point(j->s, d, 1000.0, sky);
        for (int c = 0; c < 3; ++c)
            j->out->pmap[3 * pi + (size_t)c] = (int32_t)lrint((h.hit ? h.p[c] : sky[c]) * 65536.0);
        int64_t *acc = j->out->acc + pi * 3 * k;
        memset(acc, 0, sizeof(int64_t) * 3 * k);
        if (!h.hit)
            continue;
        for (uint32_t b = j->shard; b < nblocks; b += j->nshards) {
            double sum[3][25];
            int any = 0;
            memset(sum, 0, sizeof sum);
            for (uint32_t l = b * QTOOL_BAKE_BLOCK; l < (b + 1) * QTOOL_BAKE_BLOCK && l < j->ndirs; ++l) {
                double df, gl;
                if (!qtool_rt_response(j->s, &h, j->dirs + 3 * l, j->unshadowed ? 0 : 1e30, &df, &gl))
                    continue;
                any = 1;
                const double *y = j->y + 25 * (size_t)l;
                for (int c = 0; c < 3; ++c) {
                    double t = h.albedo[c] * df + h.m->ks * gl;
                    for (uint32_t i = 0; i < k; ++i)
                        sum[c][i] += t * y[i];
                }
            }
            if (any)
                for (int c = 0; c < 3; ++c)
                    for (uint32_t i = 0; i < k; ++i)
                        acc[(size_t)c * k + i] += (int64_t)llrint(sum[c][i] * UNIT);
        }
    }
}

static void bar(void *ctx, uint32_t done, uint32_t rows)
{
    const bake_job *j = ctx;
    if (!j->progress)
        return;
    if (j->progress == 2) { /* a farm's log: one line per percent, flushed (called under the pool's lock) */
        if (done == rows || (uint64_t)done * 100 / rows != ((uint64_t)done - 1) * 100 / rows) {
            fprintf(stderr, "progress: stage=%s done=%u total=%u fraction=%.4f\n",
                    j->unshadowed ? "unshadowed" : "shadowed", done, rows, (double)done / rows);
            fflush(stderr);
        }
        return;
    }
    int n = (int)(40.0 * done / rows);
    char b[41];
    for (int i = 0; i < 40; ++i)
        b[i] = i < n ? '#' : '.';
    b[40] = '\0';
    fprintf(stderr, "\rbake [%s] %3u%% %u/%u rows", b, (unsigned)(100.0 * done / rows), done, rows);
    if (done == rows)
        fputc('\n', stderr);
    fflush(stderr);
}

/* rows y0 .. y1 - 1 of the h-row image (0, h: all of it) into out, which gets y1 - y0 rows */
static int bake_run(const qtool_rt_scene *s, uint32_t w, uint32_t fullh, uint32_t y0, uint32_t y1, qtool_pano_kind kind,
                    uint32_t ndirs, uint32_t k, uint32_t shard, uint32_t nshards, int threads, int progress,
                    int unshadowed, qtool_bake_sums *out)
{
    if (k < 1 || k > 25 || ndirs < 1 || ndirs > QTOOL_BAKE_MAX_DIRS || nshards < 1 || nshards > QTOOL_BAKE_MAX_SHARDS ||
        shard >= nshards || w < 1 || fullh < 1 || y0 >= y1 || y1 > fullh)
        return -1;
    memset(out, 0, sizeof *out);
    uint32_t h = y1 - y0;
    size_t np = (size_t)w * h;
    out->pmap = malloc(np * 3 * sizeof(int32_t));
    out->acc = malloc(np * 3 * k * sizeof(int64_t));
    bake_job j = {s, w, h, k, ndirs, shard, nshards, y0, fullh, kind, malloc(ndirs * 3 * sizeof(double)),
                  malloc(ndirs * 25 * sizeof(double)), out, progress == 2 ? 2 : progress && isatty(2), 0, unshadowed};
    if (!out->pmap || !out->acc || !j.dirs || !j.y) {
        free(j.dirs), free(j.y);
        qtool_bake_sums_free(out);
        return -1;
    }
    for (uint32_t l = 0; l < ndirs; ++l) {
        qtool_bake_dir(l, ndirs, j.dirs + 3 * l);
        qtool_ref_sh_eval(j.dirs[3 * l], j.dirs[3 * l + 1], j.dirs[3 * l + 2], 5, j.y + 25 * (size_t)l);
    }
    out->w = w, out->h = h, out->k = k, out->ndirs = ndirs, out->kind = (uint32_t)kind;
    out->shard = shard, out->nshards = nshards;
    qtool_rt_parallel(threads, h, bake_row, &j, bar);
    free(j.dirs), free(j.y);
    return 0;
}

int qtool_bake_run(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, uint32_t ndirs, uint32_t k,
                  uint32_t shard, uint32_t nshards, int threads, int progress, qtool_bake_sums *out)
{
    return bake_run(s, w, h, 0, h, kind, ndirs, k, shard, nshards, threads, progress, 0, out);
}

int qtool_bake_run_unshadowed(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, uint32_t ndirs,
                             uint32_t k, int threads, qtool_bake_sums *out)
{
    return bake_run(s, w, h, 0, h, kind, ndirs, k, 0, 1, threads, 0, 1, out);
}

int qtool_bake_run_unshadowed_shard(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind,
                                   uint32_t ndirs, uint32_t k, uint32_t shard, uint32_t nshards, int threads,
                                   qtool_bake_sums *out)
{
    return bake_run(s, w, h, 0, h, kind, ndirs, k, shard, nshards, threads, 0, 1, out);
}

int qtool_bake_run_progress(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, uint32_t ndirs,
                            uint32_t k, uint32_t shard, uint32_t nshards, int threads, int progress, int unshadowed,
                            qtool_bake_sums *out)
{
    return bake_run(s, w, h, 0, h, kind, ndirs, k, shard, nshards, threads, progress, unshadowed ? 1 : 0, out);
}

int qtool_bake_run_rows(const qtool_rt_scene *s, uint32_t w, uint32_t h, uint32_t y0, uint32_t y1, qtool_pano_kind kind,
                        uint32_t ndirs, uint32_t k, int threads, int progress, int unshadowed, qtool_bake_sums *out)
{
    return bake_run(s, w, h, y0, y1, kind, ndirs, k, 0, 1, threads, progress, unshadowed ? 1 : 0, out);
}

void qtool_bake_sums_free(qtool_bake_sums *s)
{
    free(s->pmap), free(s->acc);
    memset(s, 0, sizeof *s);
}

/* ---- partial sums files -------------------------------------------------------------------------- */

/* Layout (bake.h): 48-byte header, then the body: pmap (np * 3 i32), acc (np * 3 * k i64). The
 * header is checked (magic, version, CRC, every field against its limit) and the body's length
 * against what the header claims before anything is allocated, so memory and time are linear in
 * the file's size; the body CRC is checked before the sums are handed out. */

static const uint8_t sums_magic[8] = {'Q', 'I', 'B', 'L', 'S', 'U', 'M', 'S'};


/* body bytes the header's fields claim (fields already in range: cannot overflow 64 bits) */
static uint64_t body_bytes(const qtool_bake_sums *s)
{
    uint64_t np = (uint64_t)s->w * s->h;
    return np * 12 + np * 3 * s->k * 8;
}

/* Parses and checks the header in the avail bytes at h; fills the fields of *s (no arrays) and
 * *body. 0 or -1 with the reason (named by name, may be NULL). */
static int parse_header(const char *name, const uint8_t *h, size_t avail, qtool_bake_sums *s, uint64_t *body,
                        char *err, size_t errlen)
{
    memset(s, 0, sizeof *s);
    if (avail >= 8 && memcmp(h, "QIBLSUM1", 8) == 0)
        return qtool_errf(err, errlen, "%s: a version 1 partial-sums file (no checksums): re-run its bake shard", name);
    if (avail < 8 || memcmp(h, sums_magic, 8) != 0)
        return qtool_errf(err, errlen, "%s: not a qibl partial-sums file (bad magic)", name);
    if (avail < 12)
        return qtool_errf(err, errlen, "%s: truncated header (%zu of %u bytes)", name, avail, QTOOL_BAKE_SUMS_HEADER);
    uint32_t version = qibl_load_u32le(h + 8);
    if (version != QTOOL_BAKE_SUMS_VERSION)
        return qtool_errf(err, errlen, "%s: unsupported partial-sums version %u (this qibl reads version %u)", name, version,
                     QTOOL_BAKE_SUMS_VERSION);
    if (avail < QTOOL_BAKE_SUMS_HEADER)
        return qtool_errf(err, errlen, "%s: truncated header (%zu of %u bytes)", name, avail, QTOOL_BAKE_SUMS_HEADER);
    uint32_t stored = qibl_load_u32le(h + 44), crc = qibl_crc32(0, h, 44);
    if (stored != crc)
        return qtool_errf(err, errlen, "%s: header checksum mismatch (stored %08x, computed %08x): the file is damaged", name,
                     stored, crc);
    uint32_t v[7];
    for (int i = 0; i < 7; ++i)
        v[i] = qibl_load_u32le(h + 12 + 4 * i);
    s->w = v[0], s->h = v[1], s->k = v[2], s->ndirs = v[3], s->kind = v[4], s->shard = v[5], s->nshards = v[6];
    if (s->w < 1 || s->w > QIBL_ASSET_MAX_DIM)
        return qtool_errf(err, errlen, "%s: width %u outside 1..%u", name, s->w, QIBL_ASSET_MAX_DIM);
    if (s->h < 1 || s->h > QIBL_ASSET_MAX_DIM)
        return qtool_errf(err, errlen, "%s: height %u outside 1..%u", name, s->h, QIBL_ASSET_MAX_DIM);
    if ((uint64_t)s->w * s->h > QIBL_ASSET_MAX_PIXELS)
        return qtool_errf(err, errlen, "%s: size %ux%u above %u pixels", name, s->w, s->h, QIBL_ASSET_MAX_PIXELS);
    if (s->k < 1 || s->k > 25)
        return qtool_errf(err, errlen, "%s: k %u outside 1..25", name, s->k);
    if (s->ndirs < 1 || s->ndirs > QTOOL_BAKE_MAX_DIRS)
        return qtool_errf(err, errlen, "%s: direction count %u outside 1..%u", name, s->ndirs, QTOOL_BAKE_MAX_DIRS);
    if (s->kind > 1)
        return qtool_errf(err, errlen, "%s: panorama kind %u (0 cylindrical, 1 equirectangular)", name, s->kind);
    uint32_t nblocks = (s->ndirs + QTOOL_BAKE_BLOCK - 1) / QTOOL_BAKE_BLOCK;
    if (s->nshards < 1 || s->nshards > QTOOL_BAKE_MAX_SHARDS || s->nshards > nblocks)
        return qtool_errf(err, errlen, "%s: shard count %u outside 1..%u (and the %u blocks of %u directions)", name,
                     s->nshards, QTOOL_BAKE_MAX_SHARDS, nblocks, QTOOL_BAKE_BLOCK);
    if (s->shard >= s->nshards)
        return qtool_errf(err, errlen, "%s: shard index %u not below the shard count %u", name, s->shard, s->nshards);
    uint64_t b = body_bytes(s);
    if (b > SIZE_MAX - QTOOL_BAKE_SUMS_HEADER)
        return qtool_errf(err, errlen, "%s: %ux%u sums do not fit this machine's address space", name, s->w, s->h);
    *body = b;
    return 0;
}

/* values [first, first + n) of pmap / acc from little-endian bytes */
static void decode_pmap(qtool_bake_sums *s, size_t first, const uint8_t *p, size_t n)
{
    for (size_t i = 0; i < n; ++i)
        s->pmap[first + i] = qibl_load_s32le(p + 4 * i);
}

static void decode_acc(qtool_bake_sums *s, size_t first, const uint8_t *p, size_t n)
{
    for (size_t i = 0; i < n; ++i) {
        uint64_t u = (uint64_t)qibl_load_u32le(p + 8 * i) | (uint64_t)qibl_load_u32le(p + 8 * i + 4) << 32;
        int64_t v;
        memcpy(&v, &u, sizeof v); /* two's complement, no implementation-defined conversion */
        s->acc[first + i] = v;
    }
}

static int alloc_arrays(qtool_bake_sums *s)
{
    size_t np = (size_t)s->w * s->h;
    s->pmap = malloc(np * 3 * sizeof(int32_t));
    s->acc = malloc(np * 3 * s->k * sizeof(int64_t));
    if (!s->pmap || !s->acc) {
        free(s->pmap), free(s->acc);
        s->pmap = NULL, s->acc = NULL;
        return -1;
    }
    return 0;
}

int qtool_bake_sums_decode(const uint8_t *buf, size_t len, qtool_bake_sums *out, char *err, size_t errlen)
{
    qtool_bake_sums s;
    uint64_t body;
    if (!buf || !out)
        return qtool_errf(err, errlen, "null argument");
    if (parse_header(NULL, buf, len, &s, &body, err, errlen) != 0)
        return -1;
    size_t have = len - QTOOL_BAKE_SUMS_HEADER;
    if (have < body)
        return qtool_errf(err, errlen, "truncated: %zu bytes of sums, the header says %llu", have,
                     (unsigned long long)body);
    if (have > body)
        return qtool_errf(err, errlen, "%llu trailing bytes after the sums", (unsigned long long)(have - body));
    const uint8_t *b = buf + QTOOL_BAKE_SUMS_HEADER;
    uint32_t stored = qibl_load_u32le(buf + 40), crc = qibl_crc32(0, b, have);
    if (stored != crc)
        return qtool_errf(err, errlen, "checksum mismatch in the sums (stored %08x, computed %08x): the file is damaged",
                     stored, crc);
    if (alloc_arrays(&s) != 0)
        return qtool_errf(err, errlen, "out of memory");
    size_t np = (size_t)s.w * s.h;
    decode_pmap(&s, 0, b, np * 3);
    decode_acc(&s, 0, b + np * 12, np * 3 * s.k);
    *out = s;
    return 0;
}

int qtool_bake_sums_read(const char *path, qtool_bake_sums *out, char *err, size_t errlen)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return qtool_errf(err, errlen, "%s: %s", path, strerror(errno));
    struct stat st;
    if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) {
        fclose(f);
        return qtool_errf(err, errlen, "%s: not a regular file", path);
    }
    uint8_t hdr[QTOOL_BAKE_SUMS_HEADER];
    size_t got = fread(hdr, 1, sizeof hdr, f);
    qtool_bake_sums s;
    uint64_t body;
    if (parse_header(path, hdr, got, &s, &body, err, errlen) != 0) {
        fclose(f);
        return -1;
    }
    /* the size on disk must be what the header claims before a byte is allocated */
    uint64_t size = (uint64_t)st.st_size, want = QTOOL_BAKE_SUMS_HEADER + body;
    if (size != want) {
        fclose(f);
        return size < want ? qtool_errf(err, errlen, "%s: truncated: %llu bytes, the header says %llu", path,
                                   (unsigned long long)size, (unsigned long long)want)
                           : qtool_errf(err, errlen, "%s: %llu trailing bytes after the sums", path,
                                   (unsigned long long)(size - want));
    }
    enum { CHUNK = 8 * 3 * 4 * 1024 }; /* a multiple of 12 and of 8 */
    uint8_t *buf = malloc(CHUNK);
    if (!buf || alloc_arrays(&s) != 0) {
        free(buf);
        fclose(f);
        return qtool_errf(err, errlen, "%s: out of memory", path);
    }
    size_t nv[2] = {(size_t)s.w * s.h * 3, (size_t)s.w * s.h * 3 * s.k}, vs[2] = {4, 8};
    uint32_t crc = 0;
    int bad = 0;
    for (int r = 0; r < 2 && !bad; ++r)
        for (size_t done = 0; done < nv[r] && !bad;) {
            size_t n = nv[r] - done < CHUNK / vs[r] ? nv[r] - done : CHUNK / vs[r];
            if (fread(buf, vs[r], n, f) != n) {
                bad = 1;
                break;
            }
            crc = qibl_crc32(crc, buf, n * vs[r]);
            if (r == 0)
                decode_pmap(&s, done, buf, n);
            else
                decode_acc(&s, done, buf, n);
            done += n;
        }
    if (!bad && fgetc(f) != EOF)
        bad = 2;
    int rerr = ferror(f);
    fclose(f);
    free(buf);
    if (bad || rerr) {
        qtool_bake_sums_free(&s);
        return qtool_errf(err, errlen, "%s: %s", path, rerr ? "read error" : bad == 1 ? "truncated while reading" : "grew while reading");
    }
    uint32_t stored = qibl_load_u32le(hdr + 40);
    if (stored != crc) {
        qtool_bake_sums_free(&s);
        return qtool_errf(err, errlen, "%s: checksum mismatch in the sums (stored %08x, computed %08x): the file is damaged", path,
                     stored, crc);
    }
    *out = s;
    return 0;
}

/* Calls sink on the body's bytes in order, a chunk at a time; 0 or the first non-zero sink result. */
static int emit_body(const qtool_bake_sums *s, int (*sink)(void *, const uint8_t *, size_t), void *ctx)
{
    enum { CHUNK = 8 * 3 * 4 * 1024 };
    uint8_t *buf = malloc(CHUNK);
    if (!buf)
        return -1;
    size_t np = (size_t)s->w * s->h, nv[2] = {np * 3, np * 3 * s->k}, vs[2] = {4, 8};
    int rc = 0;
    for (int r = 0; r < 2 && rc == 0; ++r)
        for (size_t done = 0; done < nv[r] && rc == 0;) {
            size_t n = nv[r] - done < CHUNK / vs[r] ? nv[r] - done : CHUNK / vs[r];
            for (size_t i = 0; i < n; ++i) {
                if (r == 0) {
                    qtool_store_s32le(buf + 4 * i, s->pmap[done + i]);
                } else {
                    uint64_t u = (uint64_t)s->acc[done + i];
                    qtool_store_u32le(buf + 8 * i, (uint32_t)u);
                    qtool_store_u32le(buf + 8 * i + 4, (uint32_t)(u >> 32));
                }
            }
            rc = sink(ctx, buf, n * vs[r]);
            done += n;
        }
    free(buf);
    return rc;
}

static int sink_crc(void *ctx, const uint8_t *p, size_t n)
{
    uint32_t *crc = ctx;
    *crc = qibl_crc32(*crc, p, n);
    return 0;
}

static int sink_file(void *ctx, const uint8_t *p, size_t n)
{
    return fwrite(p, 1, n, (FILE *)ctx) == n ? 0 : 1;
}

typedef struct {
    uint8_t *p;
    size_t n;
} membuf;

static int sink_mem(void *ctx, const uint8_t *p, size_t n)
{
    membuf *m = ctx;
    memcpy(m->p + m->n, p, n);
    m->n += n;
    return 0;
}

/* the header of s, its body CRC computed by a first pass; 0 or -1 (out of memory) */
static int make_header(const qtool_bake_sums *s, uint8_t hdr[QTOOL_BAKE_SUMS_HEADER])
{
    uint32_t crc = 0;
    if (emit_body(s, sink_crc, &crc) != 0)
        return -1;
    memcpy(hdr, sums_magic, 8);
    qtool_store_u32le(hdr + 8, QTOOL_BAKE_SUMS_VERSION);
    uint32_t f7[7] = {s->w, s->h, s->k, s->ndirs, s->kind, s->shard, s->nshards};
    for (int i = 0; i < 7; ++i)
        qtool_store_u32le(hdr + 12 + 4 * i, f7[i]);
    qtool_store_u32le(hdr + 40, crc);
    qtool_store_u32le(hdr + 44, qibl_crc32(0, hdr, 44));
    return 0;
}

int qtool_bake_sums_encode(const qtool_bake_sums *s, uint8_t **buf, size_t *len)
{
    uint64_t body = body_bytes(s);
    if (body > SIZE_MAX - QTOOL_BAKE_SUMS_HEADER)
        return -1;
    membuf m = {malloc(QTOOL_BAKE_SUMS_HEADER + (size_t)body), QTOOL_BAKE_SUMS_HEADER};
    if (!m.p || make_header(s, m.p) != 0 || emit_body(s, sink_mem, &m) != 0) {
        free(m.p);
        return -1;
    }
    *buf = m.p, *len = m.n;
    return 0;
}

int qtool_bake_sums_write(const qtool_bake_sums *s, const char *path, char *err, size_t errlen)
{
    uint8_t hdr[QTOOL_BAKE_SUMS_HEADER];
    if (make_header(s, hdr) != 0)
        return qtool_errf(err, errlen, "%s: out of memory", path);
    qtool_io_atomic a;
    if (qtool_io_atomic_open(&a, path, err, errlen) != 0)
        return -1;
    if (fwrite(hdr, 1, sizeof hdr, a.f) != sizeof hdr || emit_body(s, sink_file, a.f) != 0) {
        int e = errno;
        qtool_io_atomic_abort(&a);
        return qtool_errf(err, errlen, "%s: write failed: %s", path, strerror(e));
    }
    return qtool_io_atomic_commit(&a, err, errlen);
}

int qtool_bake_sums_compatible(const qtool_bake_sums *a, const qtool_bake_sums *b, char *err, size_t errlen)
{
    /* the split first: it is what a merge of the wrong files most often gets wrong */
    if (a->nshards != b->nshards)
        return qtool_errf(err, errlen, "shards of different bakes: shard %u/%u against a split into %u", b->shard,
                     b->nshards, a->nshards);
    if (a->w != b->w || a->h != b->h)
        return qtool_errf(err, errlen, "shards of different bakes: size %ux%u against %ux%u", b->w, b->h, a->w, a->h);
    if (a->k != b->k)
        return qtool_errf(err, errlen, "shards of different bakes: k %u against %u", b->k, a->k);
    if (a->ndirs != b->ndirs)
        return qtool_errf(err, errlen, "shards of different bakes: %u directions against %u", b->ndirs, a->ndirs);
    if (a->kind != b->kind)
        return qtool_errf(err, errlen, "shards of different bakes: panorama kind %u against %u", b->kind, a->kind);
    if (memcmp(a->pmap, b->pmap, (size_t)a->w * a->h * 12) != 0)
        return qtool_errf(err, errlen, "shards of different scenes (P maps differ)");
    return 0;
}

int qtool_bake_sums_add(qtool_bake_sums *a, const qtool_bake_sums *b, char *err, size_t errlen)
{
    if (qtool_bake_sums_compatible(a, b, err, errlen) != 0)
        return -1;
    size_t n = (size_t)a->w * a->h * 3 * a->k;
    /* check every sum first, so a failing add changes nothing */
    for (size_t i = 0; i < n; ++i) {
        int64_t x = a->acc[i], y = b->acc[i];
        if ((y > 0 && x > INT64_MAX - y) || (y < 0 && x < INT64_MIN - y)) {
            size_t per = 3 * (size_t)a->k, p = i / per;
            return qtool_errf(err, errlen, "sums overflow 64 bits at pixel (%zu, %zu), channel %zu, coefficient %zu: not sums of one bake",
                         p % a->w, p / a->w, i % per / a->k, i % a->k);
        }
    }
    for (size_t i = 0; i < n; ++i)
        a->acc[i] += b->acc[i];
    return 0;
}

/* ---- coefficients, asset ------------------------------------------------------------------------- */

/* inverse of the k x k Gram matrix of the directions, by Gauss-Jordan with partial pivoting */
static int gram_inverse(uint32_t ndirs, uint32_t k, double *inv)
{
    double a[25][50];
    memset(a, 0, sizeof a);
    for (uint32_t l = 0; l < ndirs; ++l) {
        double d[3], y[25];
        qtool_bake_dir(l, ndirs, d);
        qtool_ref_sh_eval(d[0], d[1], d[2], 5, y);
        for (uint32_t i = 0; i < k; ++i)
            for (uint32_t m = 0; m < k; ++m)
                a[i][m] += y[i] * y[m];
    }
    for (uint32_t i = 0; i < k; ++i)
        a[i][k + i] = 1;
    for (uint32_t c = 0; c < k; ++c) {
        uint32_t p = c;
        for (uint32_t r = c + 1; r < k; ++r)
            if (fabs(a[r][c]) > fabs(a[p][c]))
                p = r;
        if (fabs(a[p][c]) < 1e-12)
            return -1; /* too few directions for k */
        for (uint32_t m = 0; m < 2 * k; ++m) {
            double t = a[c][m];
            a[c][m] = a[p][m], a[p][m] = t;
        }
        double piv = a[c][c];
        for (uint32_t m = 0; m < 2 * k; ++m)
            a[c][m] /= piv;
        for (uint32_t r = 0; r < k; ++r)
            if (r != c && a[r][c] != 0) {
                double f = a[r][c];
                for (uint32_t m = 0; m < 2 * k; ++m)
                    a[r][m] -= f * a[c][m];
            }
    }
    for (uint32_t i = 0; i < k; ++i)
        for (uint32_t m = 0; m < k; ++m)
            inv[i * k + m] = a[i][k + m];
    return 0;
}

int qtool_bake_coeffs(const qtool_bake_sums *s, uint32_t k, qtool_proj_method method, qtool_gen_maps *out)
{
    if (k < 1 || k > s->k)
        return -1;
    size_t np = (size_t)s->w * s->h;
    double inv[625];
    if (method == QTOOL_PROJ_LSQ && gram_inverse(s->ndirs, k, inv) != 0)
        return -1;
    memset(out, 0, sizeof *out);
    out->t = malloc(sizeof(double) * np * k * 3);
    out->p = malloc(sizeof(int32_t) * np * 3);
    if (!out->t || !out->p) {
        qtool_gen_free(out);
        return -1;
    }
    out->width = s->w, out->height = s->h, out->k = k;
    memcpy(out->p, s->pmap, sizeof(int32_t) * np * 3);
    double wq = 4 * QTOOL_PI / s->ndirs / UNIT;
    for (size_t p = 0; p < np; ++p)
        for (uint32_t c = 0; c < 3; ++c) {
            const int64_t *a = s->acc + (p * 3 + c) * s->k;
            for (uint32_t i = 0; i < k; ++i) {
                double v;
                if (method == QTOOL_PROJ_QUADRATURE) {
                    v = (double)a[i] * wq;
                } else {
                    v = 0;
                    for (uint32_t m = 0; m < k; ++m)
                        v += inv[i * k + m] * (double)a[m];
                    v /= UNIT;
                }
                out->t[((size_t)i * 3 + c) * np + p] = v;
            }
        }
    return 0;
}

int qtool_bake_asset(const qtool_gen_maps *m, uint32_t lut, uint8_t **bytes, size_t *n)
{
    return qtool_bake_asset_layout(m, lut, QIBL_SHMAPS_PLANAR, bytes, n);
}

int qtool_bake_asset_layout(const qtool_gen_maps *m, uint32_t lut, uint32_t layout, uint8_t **bytes, size_t *n)
{
    return qtool_bake_asset_full(m, NULL, lut, layout, NULL, NULL, bytes, n);
}

int qtool_bake_asset_ex(const qtool_gen_maps *m, const qtool_gen_maps *mu, uint32_t lut, uint8_t *const *paths,
                       const size_t *path_sizes, uint8_t **bytes, size_t *n)
{
    return qtool_bake_asset_full(m, mu, lut, QIBL_SHMAPS_PLANAR, paths, path_sizes, bytes, n);
}

int qtool_bake_asset_full(const qtool_gen_maps *m, const qtool_gen_maps *mu, uint32_t lut, uint32_t layout,
                         uint8_t *const *paths, const size_t *path_sizes, uint8_t **bytes, size_t *n)
{
    size_t np = (size_t)m->width * m->height, nplanes = (size_t)m->k * 3, up = mu ? (size_t)mu->k * 3 : 0;
    int32_t *scale = malloc(sizeof(int32_t) * (nplanes + up)), *bias = malloc(sizeof(int32_t) * (nplanes + up));
    uint8_t *planes = malloc(np * (nplanes + up));
    int rc = -1;
    if (!scale || !bias || !planes || qtool_pack_maps(m, QTOOL_PACK_MINMAX, scale, bias, planes, NULL) != 0)
        goto done;
    /* the unshadowed set, packed on its own (its own k and ranges) */
    if (mu && (mu->width != m->width || mu->height != m->height ||
               qtool_pack_maps(mu, QTOOL_PACK_MINMAX, scale + nplanes, bias + nplanes, planes + np * nplanes, NULL) != 0))
        goto done;
    qtool_bake_packed sh = {m->width, m->height, m->k, scale, bias, planes, m->p};
    qtool_bake_packed shu = {m->width, m->height, mu ? mu->k : 0, scale + nplanes, bias + nplanes, planes + np * nplanes,
                             NULL};
    rc = qtool_bake_asset_packed(&sh, mu ? &shu : NULL, lut, layout, paths, path_sizes, bytes, n);
done:
    free(scale), free(bias), free(planes);
    return rc;
}

int qtool_bake_asset_packed(const qtool_bake_packed *sh, const qtool_bake_packed *shu, uint32_t lut, uint32_t layout,
                            uint8_t *const *paths, const size_t *path_sizes, uint8_t **bytes, size_t *n)
{
    int16_t *lutv = NULL;
    uint8_t *le = NULL;
    qtool_asset_builder b;
    qtool_asset_builder_init(&b);
    int rc = -1;
    if (qtool_asset_add_shmp_layout(&b, sh->w, sh->h, sh->k, 3, sh->scale, sh->bias, sh->planes, layout) != 0 ||
        qtool_asset_add_pmap(&b, sh->w, sh->h, sh->p) != 0)
        goto done;
    if (lut) { /* for the larger k of the two map sets: point lights read either */
        uint32_t lk = shu && shu->k > sh->k ? shu->k : sh->k;
        size_t vs = qibl_ylut_values_size(lut, lk);
        le = malloc(vs);
        lutv = malloc(vs);
        if (!le || !lutv || qibl_ylut_build(lut, lk, le, vs) != QIBL_OK)
            goto done;
        for (size_t i = 0; i < vs / 2; ++i)
            lutv[i] = qibl_load_s16le(le + 2 * i);
        if (qtool_asset_add_ylut(&b, lut, lk, lutv) != 0)
            goto done;
    }
    if (shu && qtool_asset_add_shmu(&b, shu->w, shu->h, shu->k, 3, shu->scale, shu->bias, shu->planes) != 0)
        goto done;
    for (size_t i = 0; paths && paths[i]; ++i)
        if (qtool_asset_builder_add(&b, QIBL_CHUNK_LPTH, paths[i], path_sizes[i]) != 0)
            goto done;
    if (qtool_asset_serialize(&b, bytes, n) != 0)
        goto done;
    rc = 0;
done:
    qtool_asset_builder_free(&b);
    free(lutv), free(le);
    return rc;
}

/* ---- evaluation ---------------------------------------------------------------------------------- */

static void to_fb(const double *lin, uint32_t w, uint32_t h, uint8_t *rgb8)
{
    uint8_t *pix = malloc((size_t)w * 4);
    int32_t *row = malloc(sizeof(int32_t) * 3 * w);
    if (!pix || !row) { /* out of memory: black, never uninitialised bytes */
        memset(rgb8, 0, (size_t)w * h * 3);
        free(pix), free(row);
        return;
    }
    qibl_fb_desc_t fb = {0};
    fb.pixels = pix, fb.width = w, fb.height = 1, fb.format = QIBL_FB_RGBA8888, fb.srgb = 1;
    for (uint32_t y = 0; y < h; ++y) {
        for (size_t i = 0; i < (size_t)w * 3; ++i) {
            double v = lin[(size_t)y * w * 3 + i] * 65536.0;
            row[i] = v > 2e9 ? 2000000000 : v < -2e9 ? -2000000000 : (int32_t)lrint(v);
        }
        if (qibl_soft_fb_write_row(&fb, 0, 0, w, row) != QIBL_OK) /* only for w = 0: nothing to copy */
            memset(pix, 0, (size_t)w * 4);
        for (uint32_t x = 0; x < w; ++x)
            memcpy(rgb8 + ((size_t)y * w + x) * 3, pix + 4 * (size_t)x, 3);
    }
    free(pix), free(row);
}

void qtool_bake_lin_to8(const double *lin, uint32_t w, uint32_t h, uint8_t *rgb8)
{
    to_fb(lin, w, h, rgb8);
}

int qtool_bake_truth8(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, const qtool_rt_light *l,
                     int threads, uint8_t *rgb8, uint8_t *mask)
{
    size_t np = (size_t)w * h;
    double *lin = malloc(np * 3 * sizeof(double));
    float *depth = malloc(np * sizeof(float));
    if (!lin || !depth) {
        free(lin), free(depth);
        return -1;
    }
    qtool_rt_render(s, w, h, kind, l, threads, lin, depth, NULL);
    to_fb(lin, w, h, rgb8);
    if (mask)
        for (size_t i = 0; i < np; ++i)
            mask[i] = depth[i] > 0;
    free(lin), free(depth);
    return 0;
}

qibl_q16_t qtool_bake_q16(double v)
{
    return (qibl_q16_t)lrint(v * 65536.0);
}

qibl_status_t qtool_bake_dir_shlight(const qtool_rt_light *l, uint32_t k, qibl_shlight_t *out)
{
    const qibl_q16_t dir[3] = {qtool_bake_q16(l->dir[0]), qtool_bake_q16(l->dir[1]), qtool_bake_q16(l->dir[2])};
    const qibl_q16_t rgb[3] = {qtool_bake_q16(l->rgb[0]), qtool_bake_q16(l->rgb[1]), qtool_bake_q16(l->rgb[2])};
    qibl_status_t st = qibl_shlight_init(out, k);
    return st == QIBL_OK ? qibl_shlight_add_dir(out, dir, rgb) : st;
}

qibl_pointlight_t qtool_bake_pointlight(const qtool_rt_light *l, qibl_lut_filter_t filter)
{
    qibl_pointlight_t pl = {{qtool_bake_q16(l->pos[0]), qtool_bake_q16(l->pos[1]), qtool_bake_q16(l->pos[2])},
                            {qtool_bake_q16(l->rgb[0]), qtool_bake_q16(l->rgb[1]), qtool_bake_q16(l->rgb[2])},
                            l->falloff == 2 ? QIBL_FALLOFF_INV_DIST2 : QIBL_FALLOFF_INV_DIST, 0, filter};
    return pl;
}

int qtool_bake_relight8_ex(const uint8_t *asset, size_t n, const qtool_rt_light *l, int lut_mode, qibl_uq16_t exposure,
                           int srgb, uint8_t *rgb8, double *ms, qibl_status_t *status)
{
    return qtool_bake_relight8_lin(asset, n, l, lut_mode, exposure, srgb, rgb8, NULL, ms, status);
}

/* the row's Q16.16 values as linear floats, negatives clamped (what the framebuffer shows) */
static void row_linear(float *lin, const int32_t *row, uint32_t w, uint32_t y)
{
    if (!lin)
        return;
    float *o = lin + (size_t)y * w * 3;
    for (size_t i = 0; i < (size_t)w * 3; ++i)
        o[i] = row[i] > 0 ? (float)(row[i] / 65536.0) : 0.0f;
}

int qtool_bake_relight8_lin(const uint8_t *asset, size_t n, const qtool_rt_light *l, int lut_mode, qibl_uq16_t exposure,
                           int srgb, uint8_t *rgb8, float *lin, double *ms, qibl_status_t *status)
{
    qibl_asset_t a;
    qibl_shmaps_t m;
    qibl_pmap_t pm;
    qibl_ylut_t lut;
    qibl_status_t st = qtool_asset_open(&a, asset, n);
    if (st == QIBL_OK) /* free point lights: the unshadowed set when the asset has one */
        st = l->point && lut_mode >= 0 ? qibl_asset_point_shmaps(&a, &m) : qibl_asset_shmaps(&a, &m);
    if (st == QIBL_OK && l->point)
        st = qibl_asset_pmap(&a, &pm);
    if (st == QIBL_OK && l->point && (lut_mode == 1 || lut_mode == 2))
        st = qibl_asset_ylut(&a, &lut);
    uint32_t w = st == QIBL_OK ? m.width : 0, h = st == QIBL_OK ? m.height : 0;
    size_t wsn = st != QIBL_OK ? 0 : l->point ? qibl_shmap_point_workspace_size(m.k, w) : qibl_shmap_span_workspace_size(w);
    qtool_bake_frame f;
    if (qtool_bake_frame_alloc(st, w, h, 1, 0, wsn, &f, status) != 0)
        return -1;
    uint8_t *pix = f.pix;
    int32_t *row = f.row;
    void *ws = f.ws;
    qibl_fb_desc_t fb = {0};
    fb.pixels = pix, fb.width = w, fb.height = h, fb.format = QIBL_FB_RGBA8888;
    fb.srgb = srgb ? 1 : 0, fb.exposure = exposure;
    double t0 = qtool_bake_now();
    if (!l->point) {
        qibl_shlight_t sl;
        qibl_shmap_weights_t wt;
        st = qtool_bake_dir_shlight(l, m.k, &sl);
        if (st == QIBL_OK)
            st = qibl_shmap_weights(&m, &sl, &wt);
        for (uint32_t y = 0; st == QIBL_OK && y < h; ++y) {
            st = qibl_shmap_relight_span(&m, &wt, 0, y, w, row, ws, wsn);
            if (st == QIBL_OK)
                st = qibl_soft_fb_write_row(&fb, 0, y, w, row);
            if (st == QIBL_OK)
                row_linear(lin, row, w, y);
        }
    } else {
        qibl_pointlight_t pl = qtool_bake_pointlight(
            l, lut_mode == 2 ? QIBL_LUT_NEAREST : lut_mode == 3 ? QIBL_POINT_POLY : QIBL_LUT_BILINEAR);
        qibl_shmap_point_t pt;
        qibl_lampocc_t occ;
        qibl_chunk_t shmu;
        /* a free lamp through the unshadowed maps gets the lamp occlusion when the asset has one */
        int use_occ = lut_mode >= 0 && qibl_asset_find_nth(&a, QIBL_CHUNK_SHMU, 0, &shmu) == QIBL_OK &&
                      qibl_lightpath_occl_from_asset(&a, &occ) == QIBL_OK;
        st = qibl_shmap_point_prepare(&m, &pm, lut_mode == 1 || lut_mode == 2 ? &lut : NULL, &pl, &pt);
        for (uint32_t y = 0; st == QIBL_OK && y < h; ++y) {
            st = qibl_shmap_point_span(&pt, 0, y, w, row, ws, wsn);
            if (st == QIBL_OK && use_occ)
                st = qibl_lightpath_occl_span(&occ, 0, y, w, row);
            if (st == QIBL_OK)
                st = qibl_soft_fb_write_row(&fb, 0, y, w, row);
            if (st == QIBL_OK)
                row_linear(lin, row, w, y);
        }
    }
    return qtool_bake_frame_finish(&f, st, t0, ms, w, h, rgb8, status);
}

int qtool_bake_relight8(const uint8_t *asset, size_t n, const qtool_rt_light *l, int use_lut, uint8_t *rgb8, double *ms)
{
    return qtool_bake_relight8_ex(asset, n, l, use_lut ? 1 : 0, 0, 1, rgb8, ms, NULL);
}

double qtool_bake_mse(const uint8_t *a, const uint8_t *b, const uint8_t *mask, size_t npix)
{
    double se = 0;
    size_t n = 0;
    for (size_t i = 0; i < npix; ++i) {
        if (mask && !mask[i])
            continue;
        for (int c = 0; c < 3; ++c) {
            double d = (double)a[3 * i + (size_t)c] - b[3 * i + (size_t)c];
            se += d * d;
        }
        n += 3;
    }
    return n ? se / (double)n : 0;
}

