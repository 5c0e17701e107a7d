/*
 * golden/cases_asset.c - asset_*: what qibl_asset_open and the views make of a set of assets built
 * in memory: valid ones (every chunk type, an unknown chunk, grey maps, k = 25, 64 chunks, a longer
 * buffer, an odd address), one targeted edit per rejection status (resealed where the edit must get
 * past the CRCs), every truncation and every single-bit flip of a small asset. Each result is the
 * status and, when valid, every parsed field and every value the accessors return, serialised
 * little-endian (pointers as offsets from the asset's first byte). Also CRC-32 vectors and the
 * little-endian load helpers.
 *
 * The container is written here by a few lines of code (header, table, 4-aligned payloads,
 * CRCs), not by tools/io/asset_write.c, so that the runner needs nothing beyond the C library.
 */
#include "golden/casesi.h"

#include <stdlib.h>
#include <string.h>

#include "qibl/asset.h"

#if QIBL_USE_ASSET /* the group exists only when config.h builds the module */

/* ---- an in-memory builder -------------------------------------------------------------------- */

enum { MAXC = 64, ABUF = 4096 };

typedef struct {
    uint32_t count;
    uint32_t type[MAXC];
    uint32_t size[MAXC];
    const uint8_t *data[MAXC];
} chunks;

static void add(chunks *c, uint32_t type, const uint8_t *data, uint32_t size)
{
    c->type[c->count] = type, c->data[c->count] = data, c->size[c->count] = size;
    ++c->count;
}

/* Serialises into out (ABUF bytes): header, table, payloads at the next multiple of 4. Returns
 * the size (0, with out all zero, if it would not fit: every fixture here does). */
static uint32_t serialise(const chunks *c, uint8_t *out)
{
    memset(out, 0, ABUF);
    uint32_t off = QIBL_ASSET_HEADER_SIZE + QIBL_ASSET_ENTRY_SIZE * c->count;
    for (uint32_t i = 0; i < c->count; ++i) {
        off = (off + 3u) & ~3u;
        if (off + c->size[i] > ABUF) {
            memset(out, 0, ABUF);
            return 0;
        }
        uint8_t *e = out + QIBL_ASSET_HEADER_SIZE + QIBL_ASSET_ENTRY_SIZE * i;
        qtool_gput_u32(e, c->type[i]);
        qtool_gput_u32(e + 4, off);
        qtool_gput_u32(e + 8, c->size[i]);
        qtool_gput_u32(e + 12, qibl_crc32(0, c->data[i], c->size[i]));
        if (c->size[i])
            memcpy(out + off, c->data[i], c->size[i]);
        off += c->size[i];
    }
    static const uint8_t magic[8] = {'Q', 'I', 'B', 'L', '\r', '\n', 0x1A, '\n'};
    memcpy(out, magic, 8);
    qtool_gput_u32(out + 8, QIBL_ASSET_VERSION);
    qtool_gput_u32(out + 12, c->count);
    qtool_gput_u32(out + 16, off);
    qtool_gput_u32(out + 20, qibl_crc32(0, out + QIBL_ASSET_HEADER_SIZE, QIBL_ASSET_ENTRY_SIZE * c->count));
    return off;
}

static uint8_t *entry(uint8_t *a, uint32_t i)
{
    return a + QIBL_ASSET_HEADER_SIZE + QIBL_ASSET_ENTRY_SIZE * i;
}

static void reseal_table(uint8_t *a)
{
    uint32_t n = qibl_load_u32le(a + 12);
    qtool_gput_u32(a + 20, qibl_crc32(0, a + QIBL_ASSET_HEADER_SIZE, QIBL_ASSET_ENTRY_SIZE * n));
}

/* payload CRCs (where the entry stays inside the buffer), then the table CRC */
static void reseal_all(uint8_t *a, uint32_t n)
{
    uint32_t count = qibl_load_u32le(a + 12);
    for (uint32_t i = 0; i < count && i < MAXC; ++i) {
        uint8_t *e = entry(a, i);
        uint64_t off = qibl_load_u32le(e + 4), size = qibl_load_u32le(e + 8);
        if (off + size <= n)
            qtool_gput_u32(e + 12, qibl_crc32(0, a + off, (size_t)size));
    }
    reseal_table(a);
}

/* ---- the fixture ----------------------------------------------------------------------------- */

enum { W = 5, H = 3, K = 4, CH = 3, N = 2, LK = 4 };

typedef struct {
    uint8_t shmp[20 + 8 * K * CH + W * H * K * CH];
    uint8_t pmap[12 + 12 * W * H];
    uint8_t ylut[12 + 12 * N * N * LK];
    uint8_t xtra[7];
} fixture;

static void make_fixture(fixture *f)
{
    qtool_grng r = {0xA55E7};
    uint8_t *p = f->shmp;
    qtool_gput_u32(p, W), qtool_gput_u32(p + 4, H), qtool_gput_u32(p + 8, K), qtool_gput_u32(p + 12, CH), qtool_gput_u32(p + 16, 0);
    for (size_t i = 20; i < sizeof f->shmp; ++i)
        p[i] = (uint8_t)qtool_grng_u32(&r);
    p = f->pmap;
    qtool_gput_u32(p, W), qtool_gput_u32(p + 4, H), qtool_gput_u32(p + 8, 0);
    for (size_t i = 12; i < sizeof f->pmap; ++i)
        p[i] = (uint8_t)qtool_grng_u32(&r);
    p = f->ylut;
    qtool_gput_u32(p, N), qtool_gput_u32(p + 4, LK), qtool_gput_u32(p + 8, 0);
    for (size_t i = 12; i < sizeof f->ylut; ++i)
        p[i] = (uint8_t)qtool_grng_u32(&r);
    for (size_t i = 0; i < sizeof f->xtra; ++i)
        f->xtra[i] = (uint8_t)(i * 37u + 1u);
}

#define XTRA QIBL_FOURCC('X', 'T', 'R', 'A')

/* SHMP, an unknown chunk of odd size (so the next payload is padded), PMAP, YLUT */
static uint32_t build_full(const fixture *f, uint8_t *out)
{
    chunks c = {0};
    add(&c, QIBL_CHUNK_SHMP, f->shmp, sizeof f->shmp);
    add(&c, XTRA, f->xtra, sizeof f->xtra);
    add(&c, QIBL_CHUNK_PMAP, f->pmap, sizeof f->pmap);
    add(&c, QIBL_CHUNK_YLUT, f->ylut, sizeof f->ylut);
    return serialise(&c, out);
}

/* ---- what the parser makes of bytes ----------------------------------------------------------- */

static void put_offset(qtool_gbuf *b, const uint8_t *base, const uint8_t *p)
{
    qtool_gbuf_u32(b, p == NULL ? 0xFFFFFFFFu : (uint32_t)(p - base));
}

/* A view accessor's status and, when it succeeded, the view's two sizes and where its data starts
 * (PMAP: width, height; YLUT: face size, k). 1 when it succeeded. */
static int put_view(qtool_gbuf *b, qibl_status_t st, uint32_t u, uint32_t v, const uint8_t *base, const uint8_t *data)
{
    qtool_gbuf_u8(b, (uint32_t)st);
    if (st != QIBL_OK)
        return 0;
    qtool_gbuf_u32(b, u), qtool_gbuf_u32(b, v);
    put_offset(b, base, data);
    return 1;
}

/* Status, and for a valid asset every field and accessor value. */
static void parse(qtool_gbuf *b, const uint8_t *bytes, size_t n)
{
    qibl_asset_t a;
    memset(&a, 0xA5, sizeof a);
    qibl_status_t st = qibl_asset_open(&a, bytes, n);
    qtool_gbuf_u8(b, (uint32_t)st);
    if (st != QIBL_OK)
        return;
    qtool_gbuf_u32(b, a.size), qtool_gbuf_u32(b, a.chunk_count);
    put_offset(b, bytes, a.base);
    static const uint32_t types[] = {QIBL_CHUNK_SHMP, QIBL_CHUNK_PMAP, QIBL_CHUNK_YLUT, XTRA,
                                     QIBL_FOURCC('N', 'O', 'N', 'E')};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; ++i) {
        qibl_chunk_t c = {0, 0, NULL};
        qtool_gbuf_u8(b, (uint32_t)qibl_asset_find(&a, types[i], &c));
        qtool_gbuf_u32(b, c.type), qtool_gbuf_u32(b, c.size);
        put_offset(b, bytes, c.data);
    }
    qibl_shmaps_t m;
    if (qibl_asset_shmaps(&a, &m) == QIBL_OK) {
        qtool_gbuf_u32(b, m.width), qtool_gbuf_u32(b, m.height), qtool_gbuf_u32(b, m.k), qtool_gbuf_u32(b, m.channels);
        put_offset(b, bytes, m.params), put_offset(b, bytes, m.planes);
        for (uint32_t i = 0; i < m.k; ++i)
            for (uint32_t ch = 0; ch < m.channels; ++ch) {
                qtool_gbuf_s32(b, qibl_shmaps_scale(&m, i, ch));
                qtool_gbuf_s32(b, qibl_shmaps_bias(&m, i, ch));
                put_offset(b, bytes, qibl_shmaps_plane(&m, i, ch));
            }
    }
    qibl_pmap_t p = {0};
    qibl_status_t ps = qibl_asset_pmap(&a, &p);
    if (put_view(b, ps, p.width, p.height, bytes, p.points))
        for (uint32_t y = 0; y < p.height; ++y)
            for (uint32_t x = 0; x < p.width; ++x) {
                qibl_q16_t q[3];
                qibl_pmap_point(&p, x, y, q);
                qtool_gbuf_s32(b, q[0]), qtool_gbuf_s32(b, q[1]), qtool_gbuf_s32(b, q[2]);
            }
    qibl_ylut_t y = {0};
    qibl_status_t ys = qibl_asset_ylut(&a, &y);
    (void)put_view(b, ys, y.face_size, y.k, bytes, y.values);
}

/* ---- cases ----------------------------------------------------------------------------------- */

static int valid(const qtool_goldens_sink_t *s, const fixture *f, uint8_t *a, uint8_t *tmp)
{
    qtool_gbuf b = {0};
    uint32_t n = build_full(f, a);
    parse(&b, a, n);
    parse(&b, a, n + 13); /* a longer buffer is fine */
    memcpy(tmp + 1, a, n); /* at an odd address */
    parse(&b, tmp + 1, n);
    chunks c = {0};
    add(&c, QIBL_CHUNK_SHMP, f->shmp, sizeof f->shmp); /* SHMP only */
    n = serialise(&c, a);
    parse(&b, a, n);
    /* grey maps, k = 25, 1 x 1, with an empty unknown chunk before it */
    uint8_t grey[20 + 8 * 25 + 25];
    memset(grey, 0, sizeof grey);
    qtool_gput_u32(grey, 1), qtool_gput_u32(grey + 4, 1), qtool_gput_u32(grey + 8, 25), qtool_gput_u32(grey + 12, 1);
    for (size_t i = 20; i < sizeof grey; ++i)
        grey[i] = (uint8_t)(i * 7u);
    c.count = 0;
    add(&c, XTRA, NULL, 0);
    add(&c, QIBL_CHUNK_SHMP, grey, sizeof grey);
    n = serialise(&c, a);
    parse(&b, a, n);
    /* 64 chunks: the known three and 61 unknown ones of sizes 0..60 */
    static uint8_t junk[64];
    for (size_t i = 0; i < sizeof junk; ++i)
        junk[i] = (uint8_t)(255u - i);
    c.count = 0;
    for (uint32_t i = 0; i < 61; ++i)
        add(&c, QIBL_FOURCC('J', (i / 10) + '0', (i % 10) + '0', 'K'), junk, i);
    add(&c, QIBL_CHUNK_YLUT, f->ylut, sizeof f->ylut);
    add(&c, QIBL_CHUNK_PMAP, f->pmap, sizeof f->pmap);
    add(&c, QIBL_CHUNK_SHMP, f->shmp, sizeof f->shmp);
    n = serialise(&c, a);
    parse(&b, a, n);
    return qtool_gbuf_emit(s, "asset_valid", &b);
}

/* One edit per status, in the order qibl_asset_open checks them, plus a few that must pass. */
typedef struct {
    uint32_t chunk;  /* table entry index, or 0xFF for the header */
    uint32_t at;     /* header: byte offset (0..7: one magic byte, else a u32); chunk: offset inside
                      * its table entry, or 0x100 + offset inside its payload (a u32) */
    uint32_t value;
    int how;         /* then reseal: 0 nothing, 1 the table CRC, 2 every CRC */
    int32_t dn;      /* change of the buffer length passed to qibl_asset_open */
} edit;

static const edit edits[] = {
    {0xFF, 0, 'q', 0, 0},           /* magic */
    {0xFF, 4, '\n', 0, 0},          /* magic: text-mode mangling */
    {0xFF, 6, 0x1B, 0, 0},          /* magic */
    {0xFF, 8, 0, 0, 0},             /* version 0 */
    {0xFF, 8, 2, 0, 0},             /* version 2 */
    {0xFF, 12, 0, 0, 0},            /* chunk_count 0 */
    {0xFF, 12, 65, 0, 0},           /* chunk_count 65 */
    {0xFF, 12, 0xFFFFFFFFu, 0, 0},  /* chunk_count huge */
    {0xFF, 12, 5, 1, 0},            /* table past the payload start, resealed */
    {0xFF, 16, 40, 0, 0},           /* file_size inside the table */
    {0xFF, 16, 0xFFFFFFFFu, 0, 0},  /* file_size past the buffer */
    {0xFF, 0, 'Q', 0, -1},          /* buffer one short */
    {0xFF, 20, 0, 0, 0},            /* table CRC */
    {0, 0, QIBL_CHUNK_PMAP, 0, 0},  /* type changed, not resealed */
    {2, 4, 1, 1, 0},                /* PMAP at offset 1: misaligned (checked before the bounds) */
    {2, 4, 2, 1, 0},                /* at offset 2 */
    {2, 4, 0, 1, 0},                /* offset 0: inside the header */
    {2, 4, 24, 1, 0},               /* inside the table */
    {2, 8, 0x7FFFFFFFu, 1, 0},      /* size past the end */
    {2, 8, 0xFFFFFFFFu, 1, 0},      /* size wraps 32 bits */
    {2, 0, QIBL_CHUNK_SHMP, 1, 0},  /* duplicate SHMP */
    {3, 0, QIBL_CHUNK_PMAP, 1, 0},  /* duplicate PMAP */
    {1, 0, QIBL_CHUNK_YLUT, 1, 0},  /* the unknown chunk becomes a second YLUT */
    {0, 0, XTRA, 1, 0},             /* SHMP missing: two unknown chunks */
    {1, 0, XTRA, 1, 0},             /* duplicate unknown chunks are fine */
    {0, 0x100 + 21, 0, 0, 0},       /* a payload byte: chunk CRC */
    {2, 0x100 + 12, 0, 0, 0},       /* PMAP payload byte: chunk CRC */
    {0, 0x100 + 0, 0, 2, 0},        /* SHMP width 0 */
    {0, 0x100 + 4, 16385, 2, 0},    /* height above the maximum */
    {0, 0x100 + 0, 16384, 2, 0},    /* width at the maximum: SHMP size then differs */
    {0, 0x100 + 8, 0, 2, 0},        /* k = 0 */
    {0, 0x100 + 8, 26, 2, 0},       /* k = 26 */
    {0, 0x100 + 12, 2, 2, 0},       /* channels 2 */
    {0, 0x100 + 16, 1, 2, 0},       /* flags */
    {2, 0x100 + 8, 1, 2, 0},        /* PMAP flags */
    {3, 0x100 + 8, 0x80000000u, 2, 0}, /* YLUT flags */
    {2, 0x100 + 0, W + 1, 2, 0},    /* PMAP width differs */
    {3, 0x100 + 4, K - 1, 2, 0},    /* YLUT k below SHMP k */
    {3, 0x100 + 0, 0, 2, 0},        /* YLUT face size 0 */
    {3, 0x100 + 0, 257, 2, 0},      /* YLUT face size above the maximum */
    {0, 8, 19, 2, 0},               /* SHMP shorter than its fixed fields */
    {0, 8, 20 + 8 * K * CH + W * H * K * CH - 1, 2, 0}, /* SHMP one byte short */
    {2, 8, 11, 2, 0},               /* PMAP shorter than its fixed fields */
    {3, 8, 12 + 12 * N * N * LK - 2, 2, 0}, /* YLUT short */
};

static int damaged(const qtool_goldens_sink_t *s, const fixture *f, uint8_t *a)
{
    qtool_gbuf b = {0};
    for (size_t i = 0; i < sizeof edits / sizeof edits[0]; ++i) {
        const edit *e = &edits[i];
        uint32_t n = build_full(f, a);
        if (e->chunk == 0xFF && e->at < 8) /* a magic byte */
            a[e->at] = (uint8_t)e->value;
        else if (e->chunk == 0xFF)
            qtool_gput_u32(a + e->at, e->value);
        else if (e->at >= 0x100)
            qtool_gput_u32(a + qibl_load_u32le(entry(a, e->chunk) + 4) + (e->at - 0x100), e->value);
        else
            qtool_gput_u32(entry(a, e->chunk) + e->at, e->value);
        if (e->how == 1)
            reseal_table(a);
        else if (e->how == 2)
            reseal_all(a, n);
        parse(&b, a, (size_t)((int64_t)n + e->dn));
    }
    /* SHMP sizes that overflow 32 bits: 8192 x 8192 pixels x 75 planes */
    uint8_t big[20 + 8 * 25 * 3];
    memset(big, 0, sizeof big);
    qtool_gput_u32(big, 8192), qtool_gput_u32(big + 4, 8192), qtool_gput_u32(big + 8, 25), qtool_gput_u32(big + 12, 3);
    chunks c = {0};
    add(&c, QIBL_CHUNK_SHMP, big, sizeof big);
    uint32_t n = serialise(&c, a);
    parse(&b, a, n);
    qtool_gput_u32(big, 16384), qtool_gput_u32(big + 4, 16384); /* 2^28 pixels: above the maximum */
    n = serialise(&c, a);
    parse(&b, a, n);
    return qtool_gbuf_emit(s, "asset_damaged", &b);
}

static int truncations_and_flips(const qtool_goldens_sink_t *s, const fixture *f, uint8_t *a)
{
    qtool_gbuf b = {0};
    uint32_t n = build_full(f, a);
    for (uint32_t len = 0; len <= n; ++len) {
        /* a buffer of exactly len bytes, so that a sanitizer build sees any read past it */
        uint8_t *t = malloc(len ? len : 1);
        if (t == NULL) {
            qtool_gbuf_free(&b);
            return qtool_gcase_oom(s, "asset_truncations");
        }
        memcpy(t, a, len);
        parse(&b, t, len);
        free(t);
    }
    int bad = qtool_gbuf_emit(s, "asset_truncations", &b);
    uint8_t *t = malloc(n); /* exactly n bytes, as above */
    if (t == NULL)
        return bad + qtool_gcase_oom(s, "asset_bit_flips");
    for (uint32_t bit = 0; bit < 8 * n; ++bit) {
        memcpy(t, a, n);
        t[bit / 8] ^= (uint8_t)(1u << (bit % 8));
        qibl_asset_t as;
        qtool_gbuf_u8(&b, (uint32_t)qibl_asset_open(&as, t, n));
    }
    free(t);
    return bad + qtool_gbuf_emit(s, "asset_bit_flips", &b);
}

static int crc_and_loads(const qtool_goldens_sink_t *s)
{
    qtool_gbuf b = {0};
    uint8_t d[256];
    for (size_t i = 0; i < sizeof d; ++i)
        d[i] = (uint8_t)(i * 131u + 7u);
    for (size_t len = 0; len <= sizeof d; ++len)
        qtool_gbuf_u32(&b, qibl_crc32(0, d, len));
    /* continuation: any split gives the one-shot value */
    for (size_t cut = 0; cut <= sizeof d; cut += 17)
        qtool_gbuf_u32(&b, qibl_crc32(qibl_crc32(0, d, cut), d + cut, sizeof d - cut));
    qtool_gbuf_u32(&b, qibl_crc32(0, (const uint8_t *)"123456789", 9)); /* the check value CBF43926 */
    qtool_grng r = {0x10AD};
    for (int i = 0; i < 512; ++i) {
        uint8_t p[4];
        qtool_gput_u32(p, i < 4 ? (uint32_t[]){0u, 0x7FFFFFFFu, 0x80000000u, 0xFFFFFFFFu}[i] : qtool_grng_u32(&r));
        qtool_gbuf_u32(&b, qibl_load_u32le(p));
        qtool_gbuf_s32(&b, qibl_load_s32le(p));
        qtool_gbuf_u16(&b, (uint32_t)(int32_t)qibl_load_s16le(p + 1));
    }
    return qtool_gbuf_emit(s, "asset_crc32_loads", &b);
}

int qtool_goldens_asset(const qtool_goldens_sink_t *s)
{
    static fixture f;
    uint8_t *a = malloc(ABUF), *tmp = malloc(ABUF + 1);
    if (a == NULL || tmp == NULL) {
        free(a), free(tmp);
        return qtool_gcase_oom(s, "asset");
    }
    make_fixture(&f);
    int bad = valid(s, &f, a, tmp) + damaged(s, &f, a) + truncations_and_flips(s, &f, a) + crc_and_loads(s);
    free(a), free(tmp);
    return bad;
}

#else
typedef int qtool_goldens_asset_off; /* ISO C wants a declaration in every file */
#endif /* QIBL_USE_ASSET */
