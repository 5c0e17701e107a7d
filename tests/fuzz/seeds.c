/*
 * fuzz/seeds.c - writes the seed corpora of the fuzz targets with the project's own writers:
 * `fuzz-seeds DIR` fills DIR/<target>/ (run by `make fuzz`; nothing here is committed).
 *
 *   asset       qibl_asset_* builders (tools/io/asset_write.c): SHMP alone, + PMAP, + YLUT (built by
 *               the core's qibl_ylut_build), an unknown chunk, grey and RGB, parameter bytes after
 *   pfm         qtool_pfm_write (RGB and grey) and one big-endian file in the format's own words
 *   png         qtool_png_write_rgb8 and qtool_apng_write_rgb8
 *   hdr         small .hdr files in the three scanline encodings hdr.h reads (flat, new-style RLE,
 *               old-style runs), pixels from the reference RGBE encoder (tools/ref/ward_rgbe.c)
 *   obj         OBJ text with every face form obj.h reads
 *   srgbe       binary32 edge values (zeros, subnormals, FLT_MAX, Inf, NaN) and Q16.16 colours
 *   fixed       the hard cases of fixed.h (INT32_MIN, 1 and 2 LSB, extremes, directions at a pole)
 *   lightprobe  small probes in each pixel format (sRGBE ones from the core's encoder)
 *   layout      a small sky in each probe layout (qtool_probe_layout_from_latlong, _rgbe_encode)
 *   shard       two shards of one bake (qtool_bake_sums_encode), as fuzz_shard.c reads them, and a
 *               tile's ranges file (qtool_tile_ranges_encode)
 *   lightpath   t and radius, then LPTH payloads baked by the path baker (qtool_bake_path_chunk: a sun
 *               path and a lamp track over the built-in courtyard), a LOCC payload
 *               (qtool_bake_lamp_occlusion, qtool_bake_locc_payload) and an SHMT payload
 *               (qtool_gen_scene, qtool_bake_shmt_payload), as fuzz_lightpath.c reads them
 *   probe       fuzz_probe.c's parameter bytes, then a small sky (dim, with a sun) in each pixel format
 *               (RGBE from the reference encoder, sRGBE from the core's), then row order and lights
 *   hemi        fuzz_hemi.c's bytes for a receiver under a roof, in a box (the cube's 8 corners and 12
 *               triangles) and tilted against a wall (triangles below its horizon); no file writer exists
 *   ply         a cube (8 vertices, 6 quads) in ascii, binary little- and big-endian, with other scalar
 *               types, the int8..float64 names, skipped properties, lists and elements (no PLY writer
 *               exists in the project: written here from the same geometry)
 *   stream      interleaved assets (the asset builders with QIBL_SHMAPS_INTERLEAVED): maps alone, +
 *               PMAP, + YLUT, an unknown chunk, an SHMU, grey and RGB, width past one group of 16;
 *               one planar asset
 *   lightcsv    light lists in the line format `qibl lights --csv` prints (cmd_lights.c), with CRLF,
 *               tiny and huge directions, an empty line
 *   cliopts     argv lines (NUL-separated, the command's name first) for every command, from the
 *               suites' own invocations (tests/cli_test.c, cli_use_test.c, cli_silent_test.c)
 *   exr         qtool_exr_encode: HALF and FLOAT, NONE, ZIPS and ZIP (RLE, PIZ and tiled files written
 *               by OpenEXR itself are in tests/fuzz/corpus/exr)
 * Every seed stays below FUZZ_MAX_LEN (4096 bytes).
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "bake/bake.h"
#include "bake/path.h"
#include "bake/tile.h"
#include "bake/tiled.h"
#include "gen/scene.h"
#include "render/rt.h"
#include "io/asset_write.h"
#include "io/exr.h"
#include "io/pfm.h"
#include "io/png.h"
#include "io/probe_layout.h"
#include "qibl/hemi.h"
#include "qibl/lightpath.h"
#include "qibl/shmap.h"
#include "qibl/srgbe.h"
#include "ref/ward_rgbe.h"
#include "transfer/export.h"

static const char *root;
static int failed;

static void put(const char *target, const char *name, const void *data, size_t n)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", root, target);
    if (mkdir(path, 0777) != 0 && errno != EEXIST) {
        fprintf(stderr, "fuzz-seeds: %s: %s\n", path, strerror(errno));
        failed = 1;
        return;
    }
    snprintf(path, sizeof path, "%s/%s/%s", root, target, name);
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(data, 1, n, f) != n || fclose(f) != 0) {
        fprintf(stderr, "fuzz-seeds: %s: cannot write\n", path);
        failed = 1;
    }
}

static char *path_of(const char *target, const char *name)
{
    static char path[1024];
    char dir[1024];
    snprintf(dir, sizeof dir, "%s/%s", root, target);
    mkdir(dir, 0777);
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return path;
}

static uint32_t rng = 12345u;
static uint32_t next(void)
{
    rng = rng * 1664525u + 1013904223u;
    return rng >> 8;
}

/* ---- asset ----------------------------------------------------------------------------------- */

/* flags: ASSET_INTERLEAVED (SHMP in the interleaved layout), ASSET_SHMU (an unshadowed copy too) */
enum { ASSET_INTERLEAVED = 1, ASSET_SHMU = 2 };

static void asset_seed_to(const char *target, const char *name, uint32_t w, uint32_t h, uint32_t k, uint32_t ch,
                          int pmap, uint32_t lut, int extra, int flags)
{
    qtool_asset_builder b;
    qtool_asset_builder_init(&b);
    int32_t scale[75], bias[75];
    uint8_t *planes = malloc((size_t)w * h * k * ch);
    for (uint32_t i = 0; i < k * ch; ++i) {
        scale[i] = (int32_t)(next() % (1u << 20)) - (1 << 19);
        bias[i] = (int32_t)(next() % (1u << 22)) - (1 << 21);
    }
    for (size_t i = 0; i < (size_t)w * h * k * ch; ++i)
        planes[i] = (uint8_t)next();
    int rc = qtool_asset_add_shmp_layout(&b, w, h, k, ch, scale, bias, planes,
                                         (flags & ASSET_INTERLEAVED) ? QIBL_SHMAPS_INTERLEAVED : QIBL_SHMAPS_PLANAR);
    if (rc == 0 && (flags & ASSET_SHMU))
        rc = qtool_asset_add_shmu(&b, w, h, k, ch, scale, bias, planes);
    if (rc == 0 && pmap) {
        int32_t *xyz = malloc(12u * w * h);
        for (size_t i = 0; i < 3u * w * h; ++i)
            xyz[i] = (int32_t)(next() % (8u << 16)) - (4 << 16);
        rc = qtool_asset_add_pmap(&b, w, h, xyz);
        free(xyz);
    }
    if (rc == 0 && lut) {
        size_t n = qibl_ylut_values_size(lut, k);
        uint8_t *v = malloc(n);
        int16_t *vals = malloc(n);
        if (qibl_ylut_build(lut, k, v, n) != QIBL_OK)
            rc = -1;
        for (size_t i = 0; i < n / 2; ++i)
            vals[i] = qibl_load_s16le(v + 2 * i);
        if (rc == 0)
            rc = qtool_asset_add_ylut(&b, lut, k, vals);
        free(v), free(vals);
    }
    if (rc == 0 && extra)
        rc = qtool_asset_builder_add(&b, QIBL_FOURCC('X', 'T', 'R', 'A'), "extra", 5);
    uint8_t *out = NULL;
    size_t n = 0;
    if (rc == 0)
        rc = qtool_asset_serialize(&b, &out, &n);
    if (rc != 0) {
        fprintf(stderr, "fuzz-seeds: asset %s: %s\n", name, b.err);
        failed = 1;
    } else {
        /* parameter bytes after file_size: lights, point light, framebuffer settings */
        uint8_t *full = malloc(n + 64);
        memcpy(full, out, n);
        for (size_t i = 0; i < 64; ++i)
            full[n + i] = (uint8_t)next();
        put(target, name, full, extra ? n : n + 64);
        free(full);
    }
    free(out);
    free(planes);
    qtool_asset_builder_free(&b);
}

static void asset_seed(const char *name, uint32_t w, uint32_t h, uint32_t k, uint32_t ch, int pmap, uint32_t lut,
                       int extra)
{
    asset_seed_to("asset", name, w, h, k, ch, pmap, lut, extra, 0);
}

/* ---- images ---------------------------------------------------------------------------------- */

static void image_seeds(void)
{
    char err[512];
    float px[3 * 4 * 3];
    for (int i = 0; i < 36; ++i)
        px[i] = (float)(next() % 1000) / 64.0f;
    if (qtool_pfm_write(path_of("pfm", "rgb4x3.pfm"), 4, 3, 3, px, err, sizeof err) != 0 ||
        qtool_pfm_write(path_of("pfm", "grey3x2.pfm"), 3, 2, 1, px, err, sizeof err) != 0) {
        fprintf(stderr, "fuzz-seeds: %s\n", err);
        failed = 1;
    }
    /* big-endian (positive scale): the byte order qibl's writer does not produce */
    uint8_t be[64];
    int o = snprintf((char *)be, sizeof be, "PF\n2 1\n1.0\n");
    for (int i = 0; i < 6; ++i) {
        uint32_t u;
        memcpy(&u, &px[i], 4);
        be[o++] = (uint8_t)(u >> 24), be[o++] = (uint8_t)(u >> 16), be[o++] = (uint8_t)(u >> 8), be[o++] = (uint8_t)u;
    }
    put("pfm", "be2x1.pfm", be, (size_t)o);

    uint8_t rgb[3 * 5 * 4 * 3];
    for (size_t i = 0; i < sizeof rgb; ++i)
        rgb[i] = (uint8_t)(i % 7 == 0 ? next() : i * 13u);
    if (qtool_png_write_rgb8(path_of("png", "rgb5x4.png"), 5, 4, rgb, err, sizeof err) != 0 ||
        qtool_png_write_rgb8(path_of("png", "rgb1x1.png"), 1, 1, rgb, err, sizeof err) != 0 ||
        qtool_apng_write_rgb8(path_of("png", "anim3.png"), 5, 4, 3, rgb, 1, 10, err, sizeof err) != 0) {
        fprintf(stderr, "fuzz-seeds: %s\n", err);
        failed = 1;
    }
}

/* ---- hdr ------------------------------------------------------------------------------------- */

static size_t hdr_header(uint8_t *b, int w, int h)
{
    return (size_t)sprintf((char *)b, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=1.0\n\n-Y %d +X %d\n", h, w);
}

static void hdr_seeds(void)
{
    uint8_t b[2048];
    uint8_t px[4 * 16 * 4];
    for (int i = 0; i < 64; ++i) {
        float c[3] = {(float)(next() % 4000) / 100.0f, (float)(next() % 100) / 100.0f, (float)(i % 5)};
        qtool_ref_rgbe_encode(c, px + 4 * i);
    }
    /* flat 3x2 */
    size_t n = hdr_header(b, 3, 2);
    memcpy(b + n, px, 24);
    put("hdr", "flat3x2.hdr", b, n + 24);
    /* new-style RLE 9x2: per channel a run and a literal */
    n = hdr_header(b, 9, 2);
    for (int y = 0; y < 2; ++y) {
        b[n++] = 2, b[n++] = 2, b[n++] = 0, b[n++] = 9;
        for (int c = 0; c < 4; ++c) {
            b[n++] = 128 + 5, b[n++] = px[4 * y + c];
            b[n++] = 4;
            for (int x = 5; x < 9; ++x)
                b[n++] = px[4 * (x + 9 * y) + c];
        }
    }
    put("hdr", "rle9x2.hdr", b, n);
    /* old-style runs 300x2: a pixel, a run of 42, a run continuing it (1 << 8 more), a pixel */
    n = hdr_header(b, 300, 2);
    for (int y = 0; y < 2; ++y) {
        memcpy(b + n, px + 4 * y, 4), n += 4;
        b[n++] = 1, b[n++] = 1, b[n++] = 1, b[n++] = 42;
        b[n++] = 1, b[n++] = 1, b[n++] = 1, b[n++] = 1; /* 1 << 8 more */
        memcpy(b + n, px + 8, 4), n += 4;
    }
    put("hdr", "oldrle300x2.hdr", b, n);
}

/* ---- exr ------------------------------------------------------------------------------------- */

static void exr_seeds(void)
{
    static const int comps[3] = {QTOOL_EXR_NONE, QTOOL_EXR_ZIPS, QTOOL_EXR_ZIP};
    float px[3 * 12 * 5];
    for (int i = 0; i < 3 * 12 * 5; ++i)
        px[i] = (float)(next() % 4000) / 64.0f - (i % 11 == 0 ? 3.0f : 0.0f);
    for (int t = QTOOL_EXR_HALF; t <= QTOOL_EXR_FLOAT; ++t)
        for (int c = 0; c < 3; ++c) {
            uint8_t *b;
            size_t n;
            char err[256], name[64];
            if (qtool_exr_encode(12, 5, px, t, comps[c], &b, &n, err, sizeof err) != 0) {
                fprintf(stderr, "fuzz-seeds: exr: %s\n", err);
                failed = 1;
                continue;
            }
            snprintf(name, sizeof name, "%s_%s.exr", t == QTOOL_EXR_HALF ? "half" : "float",
                     comps[c] == QTOOL_EXR_NONE ? "none" : comps[c] == QTOOL_EXR_ZIPS ? "zips" : "zip");
            put("exr", name, b, n);
            free(b);
        }
}

/* ---- obj ------------------------------------------------------------------------------------- */

static void obj_seeds(void)
{
    static const char cube[] =
        "# a unit cube with every face form\n"
        "o cube\nmtllib none.mtl\n"
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1 1.0\n"
        "vt 0 0\nvt 1 0\nvt 1 1\n"
        "vn 0 0 -1\nvn 0 0 1\nvn 0 -1 0\n"
        "g sides\nusemtl grey\ns 1\n"
        "f 1 4 3 2\n"
        "f 5/1 6/2 7/3 8/1\n"
        "f 1//3 2//3 6//3 5//3\n"
        "f 2/1/1 3/2/1 7/3/1\n"
        "f -6 -5 -1\n"
        "f 4 1 5 8\n"
        "l 1 2\np 3\n";
    put("obj", "cube.obj", cube, sizeof cube - 1);
    static const char tri[] = "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n";
    put("obj", "tri_crlf.obj", tri, sizeof tri - 1);
}

/* ---- srgbe / lightprobe ------------------------------------------------------------------------ */

static void srgbe_seeds(void)
{
    static const uint32_t edge[] = {0x00000000u, 0x80000000u, 0x00000001u, 0x80200000u, 0x001FFFFFu, 0x3F800000u,
                                    0xBF800000u, 0x7F7FFFFFu, 0xFF7FFFFFu, 0x7F800000u, 0xFF800000u, 0x7FC00000u,
                                    0xFFC00001u, 0x00800000u, 0x40490FDBu, 0x3E99999Au, 0x01000000u, 0x5F000000u};
    uint8_t b[2 + sizeof edge];
    b[0] = 16, b[1] = 0; /* frac_bits 16 */
    memcpy(b + 2, edge, sizeof edge);
    put("srgbe", "edges_fb16", b, sizeof b);
    b[0] = 0x9F, b[1] = 0xFF; /* frac_bits -97: int32 above 2^128 */
    put("srgbe", "edges_fbm97", b, sizeof b);
    /* codes made by the encoder, read back as codes */
    uint8_t c[2 + 12 * 8];
    c[0] = 0x10, c[1] = 0;
    for (int i = 0; i < 24; ++i) {
        int32_t q[3] = {(int32_t)next() - (1 << 23), (int32_t)(next() >> 4), -(int32_t)(next() >> 12)};
        QIBL_DROP_STATUS(qibl_srgbe_encode_q16(q, c + 2 + 4 * i));
    }
    put("srgbe", "codes", c, sizeof c);
}

static void fixed_seeds(void)
{
    /* records of three u32 and one u64: the hard cases of fixed.h (INT32_MIN, 1 and 2 LSB, the
     * largest values, the poles of the SH basis) */
    static const uint32_t rec[][5] = {{0x80000000u, 0x80000000u, 0x80000000u, 0xFFFFFFFFu, 0xFFFFFFFFu},
                                      {1u, 0u, 0u, 1u, 0u},
                                      {2u, 0xFFFFFFFFu, 1u, 0u, 0x40000000u},
                                      {0u, 0u, 0u, 0u, 0u},
                                      {0u, 1u, 0x7FFFFFFFu, 0xFFFFFFFEu, 0x00000001u},
                                      {26u, 0u, 0x82A7A7A7u, 4u, 0u},
                                      {0x00010000u, 0x00010000u, 0x00010000u, 0x12345678u, 0x9ABCDEF0u}};
    put("fixed", "hard_cases", rec, sizeof rec);
}

/* a small sky in every probe layout (qtool_probe_layout_from_latlong), as RGBE bytes after the
 * requested layout (0: detect) and the size */
static void layout_seeds(void)
{
    enum { LW = 16, LH = 8 };
    float sky[3 * LW * LH];
    for (int v = 0; v < LH; ++v)
        for (int u = 0; u < LW; ++u) {
            float sun = (u == 5 && v == 2) ? 400.0f : 0.0f;
            sky[3 * (v * LW + u) + 0] = sun + 0.2f + 0.05f * (float)v;
            sky[3 * (v * LW + u) + 1] = sun + 0.3f;
            sky[3 * (v * LW + u) + 2] = sun + (float)(LH - v) * 0.1f;
        }
    static const struct {
        qtool_probe_layout_t layout;
        int w, h;
        const char *name;
    } L[] = {{QTOOL_PROBE_LAYOUT_LATLONG, 16, 8, "latlong"},
             {QTOOL_PROBE_LAYOUT_ANGULAR, 16, 16, "angular"},
             {QTOOL_PROBE_LAYOUT_BALL, 15, 15, "ball"},
             {QTOOL_PROBE_LAYOUT_VCROSS, 12, 16, "vcross"},
             {QTOOL_PROBE_LAYOUT_HCROSS, 16, 12, "hcross"}};
    for (size_t k = 0; k < sizeof L / sizeof L[0]; ++k) {
        char err[256];
        float *img = NULL;
        if (qtool_probe_layout_from_latlong(L[k].layout, LW, LH, sky, L[k].w, L[k].h, &img, err, sizeof err) != 0) {
            fprintf(stderr, "fuzz-seeds: layout %s: %s\n", L[k].name, err);
            failed = 1;
            continue;
        }
        const size_t n = (size_t)L[k].w * (size_t)L[k].h;
        uint8_t *b = malloc(3 + 4 * n);
        /* the square ones must be named (detection refuses them), the others are detected */
        b[0] = (uint8_t)(L[k].layout == QTOOL_PROBE_LAYOUT_ANGULAR || L[k].layout == QTOOL_PROBE_LAYOUT_BALL
                             ? L[k].layout
                             : QTOOL_PROBE_LAYOUT_AUTO);
        b[1] = (uint8_t)(L[k].w - 1), b[2] = (uint8_t)(L[k].h - 1);
        qtool_probe_layout_rgbe_encode(img, n, b + 3);
        put("layout", L[k].name, b, 3 + 4 * n);
        free(b);
        free(img);
    }
}

/* two shards of one bake (qtool_bake_sums_encode), in fuzz_shard.c's input form: flags (repair both
 * CRCs), the split point, the two file images */
static void shard_seeds(void)
{
    int32_t pmap[2 * 1 * 3] = {65536, 131072, -196608, 0, 32768, 7};
    int64_t acc[2][2 * 1 * 3 * 4];
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 24; ++i)
            acc[j][i] = (int64_t)(next() % 100000u) * (i % 3 ? 4096 : -977) + (j ? INT64_MAX / 4 : 0);
    uint8_t *img[2] = {NULL, NULL};
    size_t len[2] = {0, 0};
    for (int j = 0; j < 2; ++j) {
        qtool_bake_sums sh = {2, 1, 4, 64, 0, (uint32_t)j, 2, pmap, acc[j]};
        if (qtool_bake_sums_encode(&sh, &img[j], &len[j]) != 0) {
            fprintf(stderr, "fuzz-seeds: shard: out of memory\n");
            failed = 1;
        }
    }
    if (img[0] && img[1]) {
        uint8_t *b = malloc(5 + len[0] + len[1]);
        b[0] = 3, b[1] = (uint8_t)len[0], b[2] = (uint8_t)(len[0] >> 8), b[3] = 0, b[4] = 0;
        memcpy(b + 5, img[0], len[0]);
        memcpy(b + 5 + len[0], img[1], len[1]);
        put("shard", "two_shards", b, 5 + len[0] + len[1]);
        free(b);
    }
    free(img[0]), free(img[1]);
    /* a tile's ranges file (bake/tile.h), flags asking fuzz_shard to repair its CRCs */
    double lo[6] = {-1.5, 0, -0.0, 0.25, -3, 1e-9}, hi[6] = {2.5, 0, 0.0, 0.5, 3, 1};
    qtool_tile_ranges r = {.key = {4, 3, 1, 1, 64, 0x1234abcdu}, .tile = 1, .ntiles = 3, .reduced = 0, .lo = lo, .hi = hi};
    uint8_t *rb = NULL;
    size_t rn = 0;
    if (qtool_tile_ranges_encode(&r, &rb, &rn) == 0) {
        uint8_t *b = malloc(5 + rn);
        if (b) {
            b[0] = 4, b[1] = b[2] = b[3] = b[4] = 0;
            memcpy(b + 5, rb, rn);
            put("shard", "tile_ranges", b, 5 + rn);
        }
        free(b);
    }
    free(rb);
}

static void probe_seed(const char *name, uint8_t w, uint8_t h, uint8_t fmt, uint8_t method, uint8_t count,
                       uint8_t frac, uint8_t sb)
{
    uint8_t b[8 + 24 * 16 * 12];
    size_t n = 0;
    b[n++] = (uint8_t)(w - 1), b[n++] = (uint8_t)(h - 1), b[n++] = fmt, b[n++] = method, b[n++] = count;
    b[n++] = frac, b[n++] = sb, b[n++] = 0x35;
    for (int v = 0; v < h; ++v)
        for (int u = 0; u < w; ++u) {
            /* a dim sky with a bright sun near the top */
            float sun = (u == w / 3 && v == h / 4) ? 5000.0f : 0.0f;
            float c[3] = {sun + (float)(next() % 100) / 50.0f, sun + (float)(v + 1) / 4.0f, (float)(u % 3)};
            if (fmt == 0) {
                qtool_ref_rgbe_encode(c, b + n), n += 4;
            } else if (fmt == 1) {
                uint32_t f[3];
                memcpy(f, c, 12);
                QIBL_DROP_STATUS(qibl_srgbe_encode_f32(f, b + n));
                n += 4;
            } else if (fmt == 2) {
                for (int i = 0; i < 3; ++i) {
                    int32_t x = (int32_t)(c[i] * 256.0f);
                    memcpy(b + n, &x, 4), n += 4;
                }
            } else {
                memcpy(b + n, c, 12), n += 12;
            }
        }
    put("lightprobe", name, b, n);
}

/* ---- transfer: fuzz_transfer's layout (flags, coarse target, motion, vertex count, int8 x y z on a
 * 1/8 grid, index triples); closed meshes that make the hierarchy's rings reach far --------------- */

static void transfer_seed(const char *name, uint8_t flags, uint8_t target, uint8_t motion, const int8_t (*v)[3],
                          int nv, const uint8_t (*t)[3], int nt)
{
    uint8_t b[4 + 3 * 40 + 3 * 64];
    size_t n = 0;
    b[n++] = flags, b[n++] = target, b[n++] = motion, b[n++] = (uint8_t)(nv - 3);
    for (int i = 0; i < nv; ++i)
        for (int k = 0; k < 3; ++k)
            b[n++] = (uint8_t)v[i][k];
    for (int i = 0; i < nt; ++i)
        for (int k = 0; k < 3; ++k)
            b[n++] = t[i][k];
    put("transfer", name, b, n);
}

static void transfer_seeds(void)
{
    static const int8_t tet_v[4][3] = {{0, 0, 8}, {8, 0, -4}, {-4, 7, -4}, {-4, -7, -4}};
    static const uint8_t tet_t[4][3] = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}};
    transfer_seed("tetra_ring1_crease.bin", 0x04, 1, 0x38, tet_v, 4, tet_t, 4);
    /* a cone of 30 sides: apex 0, base centre 1, rim 2..31 (the hub of a fan at both ends: the
     * near field of a rim vertex reaches every other rim vertex through the hubs) */
    int8_t cone_v[32][3] = {{0, 0, 16}, {0, 0, 0}};
    uint8_t cone_t[60][3];
    for (int k = 0; k < 30; ++k) {
        const double a = 6.283185307179586 * k / 30;
        cone_v[2 + k][0] = (int8_t)lrint(16 * cos(a)), cone_v[2 + k][1] = (int8_t)lrint(16 * sin(a)), cone_v[2 + k][2] = 0;
        const uint8_t r0 = (uint8_t)(2 + k), r1 = (uint8_t)(2 + (k + 1) % 30);
        cone_t[2 * k][0] = 0, cone_t[2 * k][1] = r0, cone_t[2 * k][2] = r1;
        cone_t[2 * k + 1][0] = 1, cone_t[2 * k + 1][1] = r1, cone_t[2 * k + 1][2] = r0;
    }
    transfer_seed("cone30_coarse1_ring1.bin", 0x04, 1, 0x5A, (const int8_t(*)[3])cone_v, 32,
                  (const uint8_t(*)[3])cone_t, 60);
    transfer_seed("cone30_coarse8_ring3.bin", 0x06, 8, 0xA3, (const int8_t(*)[3])cone_v, 32,
                  (const uint8_t(*)[3])cone_t, 60);
    /* a 4 x 4 grid of quads (open), split into triangles, one corner index past the vertices */
    int8_t grid_v[25][3];
    uint8_t grid_t[32][3];
    for (int j = 0; j < 5; ++j)
        for (int i = 0; i < 5; ++i)
            grid_v[5 * j + i][0] = (int8_t)(8 * i), grid_v[5 * j + i][1] = (int8_t)(8 * j), grid_v[5 * j + i][2] = (int8_t)((i * j) % 3);
    for (int j = 0, n = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i, n += 2) {
            const uint8_t a = (uint8_t)(5 * j + i), b = (uint8_t)(a + 1), c = (uint8_t)(a + 5), d = (uint8_t)(c + 1);
            grid_t[n][0] = a, grid_t[n][1] = b, grid_t[n][2] = d, grid_t[n + 1][0] = a, grid_t[n + 1][1] = d, grid_t[n + 1][2] = c;
        }
    transfer_seed("grid4_ring2.bin", 0x01, 4, 0x11, (const int8_t(*)[3])grid_v, 25, (const uint8_t(*)[3])grid_t, 32);
    grid_t[31][2] = 26;
    transfer_seed("grid4_bad_index_ring17.bin", 0xE5, 4, 0x11, (const int8_t(*)[3])grid_v, 25,
                  (const uint8_t(*)[3])grid_t, 32);
}

/* ---- lightpath ------------------------------------------------------------------------------- */

static void lightpath_put(const char *name, uint16_t t, uint16_t radius, const uint8_t *payload, size_t n)
{
    if (4 + n > 4096) {
        fprintf(stderr, "fuzz-seeds: lightpath %s: %zu bytes, above FUZZ_MAX_LEN\n", name, 4 + n);
        failed = 1;
        return;
    }
    uint8_t *b = malloc(4 + n);
    b[0] = (uint8_t)t, b[1] = (uint8_t)(t >> 8), b[2] = (uint8_t)radius, b[3] = (uint8_t)(radius >> 8);
    memcpy(b + 4, payload, n);
    put("lightpath", name, b, 4 + n);
    free(b);
}

static void lightpath_seeds(void)
{
    qtool_rt_scene sc;
    if (qtool_rt_scene_builtin(&sc) != 0) {
        fprintf(stderr, "fuzz-seeds: lightpath: no scene\n");
        failed = 1;
        return;
    }
    char err[256];
    static const struct {
        const char *name, *spec;
        int kind;
        uint16_t t, radius;
    } P[] = {{"lpth_sun_12x6", "40,15,6,18", 0, 30000, 0},
             {"lpth_sun_soft_12x6", "52,-10,7,17", 0, 21000, 900},
             {"lpth_track_12x6", "-3,2,1.2;0,3,2.5;3,2,1.2", 1, 40000, 0}};
    for (size_t i = 0; i < sizeof P / sizeof P[0]; ++i) {
        qtool_bake_path bp;
        memset(&bp, 0, sizeof bp);
        bp.rgb[0] = bp.rgb[1] = bp.rgb[2] = 1.0;
        int rc = P[i].kind == 0 ? qtool_bake_path_parse_sun(P[i].spec, &bp, err, sizeof err)
                                : qtool_bake_path_parse_track(P[i].spec, &bp, err, sizeof err);
        uint8_t *pl = NULL;
        size_t n = 0;
        if (rc == 0)
            rc = qtool_bake_path_chunk(&sc, 12, 6, QTOOL_PANO_EQUIRECT, &bp, 64, 6, 1, &pl, &n, NULL);
        if (rc != 0) {
            fprintf(stderr, "fuzz-seeds: lightpath %s: %s\n", P[i].name, rc ? "bake failed" : err);
            failed = 1;
        } else {
            lightpath_put(P[i].name, P[i].t, P[i].radius, pl, n);
        }
        free(pl);
    }
    /* lamp occlusion over a box in the courtyard */
    uint8_t occ[10 * 5];
    const double box[6] = {-2, -2, 1, 2, 2, 3};
    uint8_t *pl = NULL;
    size_t n = 0;
    if (qtool_bake_lamp_occlusion(&sc, 10, 5, QTOOL_PANO_EQUIRECT, box, 16, 1, occ) != 0 ||
        qtool_bake_locc_payload(10, 5, occ, &pl, &n) != 0) {
        fprintf(stderr, "fuzz-seeds: lightpath: lamp occlusion failed\n");
        failed = 1;
    } else {
        lightpath_put("locc_10x5", 0, 0, pl, n);
    }
    free(pl);
    qtool_rt_scene_free(&sc);
    /* tiled maps: 20x4 (two tiles across, the second partial), k 9 */
    qtool_gen_maps gm;
    pl = NULL;
    if (qtool_gen_scene(20, 4, 9, QTOOL_PANO_EQUIRECT, &gm) != 0) {
        fprintf(stderr, "fuzz-seeds: lightpath: gen_scene failed\n");
        failed = 1;
        return;
    }
    if (qtool_bake_shmt_payload(&gm, 0.02, &pl, &n, NULL) != 0) {
        fprintf(stderr, "fuzz-seeds: lightpath: SHMT payload failed\n");
        failed = 1;
    } else {
        lightpath_put("shmt_20x4_k9", 0, 0, pl, n);
    }
    free(pl);
    qtool_gen_free(&gm);
}

/* ---- probe (SH projection) --------------------------------------------------------------------- */

/* fuzz_probe.c's input: w-1, h-1, format, bands, frac_bits/2, options (irradiance, window),
 * scale_log2/5, stride byte; the pixels; then the row order, the lights and the rotation (zeros) */
static void sh_probe_seed(const char *name, uint8_t w, uint8_t h, uint8_t fmt, uint8_t bands, int8_t frac2, uint8_t ob,
                          int8_t scale5, uint8_t sb)
{
    uint8_t b[8 + 16 * 8 * 12 + 64];
    size_t n = 0;
    b[n++] = (uint8_t)(w - 1), b[n++] = (uint8_t)(h - 1), b[n++] = fmt, b[n++] = bands;
    b[n++] = (uint8_t)frac2, b[n++] = ob, b[n++] = (uint8_t)scale5, b[n++] = sb;
    const size_t pb = fmt <= 1 ? 4u : 12u;
    for (int v = 0; v < h; ++v)
        for (int u = 0; u < w; ++u) {
            float sun = (u == w / 4 && v == h / 4) ? 900.0f : 0.0f;
            float c[3] = {sun + 0.4f + 0.1f * (float)v, sun + 0.5f, sun + 0.2f * (float)(h - v)};
            if (fmt == 0) {
                qtool_ref_rgbe_encode(c, b + n);
            } else if (fmt == 1) {
                uint32_t f[3];
                memcpy(f, c, 12);
                QIBL_DROP_STATUS(qibl_srgbe_encode_f32(f, b + n));
            } else if (fmt == 2) {
                for (int i = 0; i < 3; ++i) {
                    int32_t x = (int32_t)(c[i] * (float)(1 << (2 * frac2 > 0 ? 2 * frac2 : 0)));
                    memcpy(b + n + 4 * i, &x, 4);
                }
            } else {
                memcpy(b + n, c, 12);
            }
            n += pb;
        }
    /* the row order (a reversal), no extra rows, then light k 9 and rotation bytes */
    for (int v = 0; v + 1 < h; ++v)
        b[n++] = 0;
    b[n++] = 0;
    for (int i = 0; i < 16; ++i)
        b[n++] = (uint8_t)(i * 37 + 9);
    put("probe", name, b, n);
}

static void probe_sh_seeds(void)
{
    sh_probe_seed("rgbe_16x8_b3", 16, 8, 0, 3, 0, 0x00, 0, 0x00);
    sh_probe_seed("srgbe_12x6_b5_irr_hann", 12, 6, 1, 5, 0, 0x01 | 1 << 1, 0, 0x05);
    sh_probe_seed("i32_8x4_b2_lanczos", 8, 4, 2, 2, 4, 2 << 1, -2, 0x02);
    sh_probe_seed("f32_6x3_b4_irr", 6, 3, 3, 4, 0, 0x01, 1, 0x03);
}

/* ---- hemi ------------------------------------------------------------------------------------ */

typedef struct seedbuf {
    uint8_t b[1200];
    size_t n;
} seedbuf;

static void sb_u8(seedbuf *s, uint32_t v) { s->b[s->n++] = (uint8_t)v; }
static void sb_u16(seedbuf *s, uint32_t v) { sb_u8(s, v), sb_u8(s, v >> 8); }
static void sb_u32(seedbuf *s, uint32_t v) { sb_u16(s, v), sb_u16(s, v >> 16); }

/* fuzz_hemi.c's input: size byte; receiver (offset u32 + shift byte per axis, then the normal);
 * vertices as raw Q16.16 (flag 0x80, an unused u16, the u32); triangles; no extra mask bits; a
 * reflection vector and exponent; the light */
static void hemi_seed(const char *name, uint8_t size_byte, const double p[3], const int32_t nrm[3], uint32_t nv,
                      const double (*v)[3], uint32_t nt, const uint8_t (*t)[3], uint32_t exponent)
{
    seedbuf s = {{0}, 0};
    sb_u8(&s, size_byte);
    for (int i = 0; i < 3; ++i) {
        sb_u32(&s, (uint32_t)(int32_t)lrint(p[i] * 65536.0) + 0x80000000u);
        sb_u8(&s, 0);
    }
    for (int i = 0; i < 3; ++i)
        sb_u32(&s, (uint32_t)nrm[i]);
    sb_u8(&s, nv - 1u);
    for (uint32_t k = 0; k < nv; ++k)
        for (int i = 0; i < 3; ++i) {
            sb_u8(&s, 0x80);
            sb_u16(&s, 0);
            sb_u32(&s, (uint32_t)(int32_t)lrint(v[k][i] * 65536.0));
        }
    sb_u8(&s, nt);
    for (uint32_t k = 0; k < nt; ++k)
        for (int i = 0; i < 3; ++i)
            sb_u8(&s, t[k][i]);
    static const uint32_t sizes[3] = {16, 32, 64};
    const uint32_t words = QIBL_HEMI_MASK_WORDS(sizes[size_byte % 3u]); /* zeros: no extra bits */
    for (uint32_t i = 0; i < words; ++i)
        sb_u32(&s, 0);
    sb_u32(&s, 0), sb_u32(&s, 0), sb_u32(&s, 1u << 30); /* reflection +z */
    sb_u32(&s, exponent);
    for (int c = 0; c < 3; ++c)
        for (int i = 0; i < QIBL_HEMI_COEFFS && s.n + 4 <= sizeof s.b; ++i)
            sb_u32(&s, (uint32_t)((c + 1) * (1 << 14) / (i + 1)));
    put("hemi", name, s.b, s.n);
}

static void hemi_seeds(void)
{
    /* size byte sb: mask {16, 32, 64}[sb % 3], face 2 (1 + (sb >> 2) % 8) */
    const double origin[3] = {0, 0, 0};
    const int32_t up[3] = {0, 0, 1 << 16};
    const double roof[4][3] = {{-1, -1, 1}, {1, -1, 1}, {1, 1, 1.5}, {-1, 1, 1.5}};
    const uint8_t roof_t[2][3] = {{0, 1, 2}, {0, 2, 3}};
    hemi_seed("roof_m16_f4", 6, origin, up, 4, roof, 2, roof_t, 8);
    /* the receiver on the floor of a closed box: every direction blocked */
    const double box[8][3] = {{-1, -1, -0.5}, {1, -1, -0.5}, {1, 1, -0.5}, {-1, 1, -0.5},
                              {-1, -1, 2},    {1, -1, 2},    {1, 1, 2},    {-1, 1, 2}};
    const uint8_t box_t[12][3] = {{0, 1, 2}, {0, 2, 3}, {4, 6, 5}, {4, 7, 6}, {0, 4, 5}, {0, 5, 1},
                                  {1, 5, 6}, {1, 6, 2}, {2, 6, 7}, {2, 7, 3}, {3, 7, 4}, {3, 4, 0}};
    hemi_seed("box_m32_f8", 13, origin, up, 8, box, 12, box_t, 0);
    /* a tilted receiver beside a wall that crosses its horizon, far from the origin */
    const double at[3] = {120.5, -40.25, 3};
    const int32_t tilt[3] = {40000, -12000, 30000};
    const double wall[4][3] = {{121.5, -42, 0}, {121.5, -38, 0}, {121.5, -38, 8}, {121.5, -42, 8}};
    const uint8_t wall_t[3][3] = {{0, 1, 2}, {0, 2, 3}, {0, 2, 4}}; /* the last one names a missing vertex */
    hemi_seed("wall_m64_f16", 29, at, tilt, 4, wall, 3, wall_t, 40);
}

/* ---- ply ------------------------------------------------------------------------------------- */

static const double cube_v[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                    {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
static const int cube_f[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};

/* one scalar of PLY type name (char uchar short ushort int uint float double) in the byte order */
static size_t ply_scalar(uint8_t *o, const char *type, double v, int big)
{
    uint8_t raw[8];
    size_t n;
    if (!strcmp(type, "char") || !strcmp(type, "int8")) {
        int8_t x = (int8_t)v;
        memcpy(raw, &x, n = 1);
    } else if (!strcmp(type, "uchar") || !strcmp(type, "uint8")) {
        uint8_t x = (uint8_t)v;
        memcpy(raw, &x, n = 1);
    } else if (!strcmp(type, "short") || !strcmp(type, "int16")) {
        int16_t x = (int16_t)v;
        memcpy(raw, &x, n = 2);
    } else if (!strcmp(type, "ushort") || !strcmp(type, "uint16")) {
        uint16_t x = (uint16_t)v;
        memcpy(raw, &x, n = 2);
    } else if (!strcmp(type, "int") || !strcmp(type, "int32")) {
        int32_t x = (int32_t)v;
        memcpy(raw, &x, n = 4);
    } else if (!strcmp(type, "uint") || !strcmp(type, "uint32")) {
        uint32_t x = (uint32_t)v;
        memcpy(raw, &x, n = 4);
    } else if (!strcmp(type, "float") || !strcmp(type, "float32")) {
        float x = (float)v;
        memcpy(raw, &x, n = 4);
    } else {
        memcpy(raw, &v, n = 8);
    }
    const uint16_t one = 1;
    const int host_big = *(const uint8_t *)&one == 0;
    for (size_t i = 0; i < n; ++i)
        o[i] = raw[big != host_big ? n - 1 - i : i];
    return n;
}

/* the cube in format fmt ("ascii", "binary_little_endian", "binary_big_endian"): vertex x y z of
 * type ct plus an extra property of type xt (skipped), faces as list cnt idx, then an element "edge"
 * of two ints the reader skips */
static void ply_seed(const char *name, const char *fmt, const char *ct, const char *xt, const char *cnt,
                     const char *idx, double scale)
{
    uint8_t b[4096];
    int ascii = !strcmp(fmt, "ascii"), big = !strcmp(fmt, "binary_big_endian");
    size_t n = (size_t)snprintf((char *)b, sizeof b,
                                "ply\nformat %s 1.0\ncomment made by fuzz-seeds\nobj_info a unit cube\n"
                                "element vertex 8\nproperty %s x\nproperty %s y\nproperty %s z\nproperty %s quality\n"
                                "element face 6\nproperty list %s %s vertex_indices\nproperty uchar flags\n"
                                "element edge 2\nproperty int vertex1\nproperty int vertex2\nend_header\n",
                                fmt, ct, ct, ct, xt, cnt, idx);
    for (int i = 0; i < 8; ++i) {
        if (ascii) {
            n += (size_t)snprintf((char *)b + n, sizeof b - n, "%g %g %g %d\n", cube_v[i][0] * scale,
                                  cube_v[i][1] * scale, cube_v[i][2] * scale, i);
        } else {
            for (int j = 0; j < 3; ++j)
                n += ply_scalar(b + n, ct, cube_v[i][j] * scale, big);
            n += ply_scalar(b + n, xt, i, big);
        }
    }
    for (int f = 0; f < 6; ++f) {
        if (ascii) {
            n += (size_t)snprintf((char *)b + n, sizeof b - n, "4 %d %d %d %d 0\n", cube_f[f][0], cube_f[f][1],
                                  cube_f[f][2], cube_f[f][3]);
        } else {
            n += ply_scalar(b + n, cnt, 4, big);
            for (int j = 0; j < 4; ++j)
                n += ply_scalar(b + n, idx, cube_f[f][j], big);
            n += ply_scalar(b + n, "uchar", 0, big);
        }
    }
    for (int e = 0; e < 2; ++e) {
        if (ascii) {
            n += (size_t)snprintf((char *)b + n, sizeof b - n, "%d %d\n", e, e + 1);
        } else {
            n += ply_scalar(b + n, "int", e, big);
            n += ply_scalar(b + n, "int", e + 1, big);
        }
    }
    put("ply", name, b, n);
}

static void ply_seeds(void)
{
    ply_seed("cube_ascii.ply", "ascii", "float", "uchar", "uchar", "int", 1.0);
    ply_seed("cube_le_float.ply", "binary_little_endian", "float", "uchar", "uchar", "int", 2.5);
    ply_seed("cube_be_double.ply", "binary_big_endian", "double", "ushort", "ushort", "uint", -1.0);
    ply_seed("cube_le_short.ply", "binary_little_endian", "short", "float", "uint8", "uint16", 100.0);
    ply_seed("cube_be_int8.ply", "binary_big_endian", "int8", "float64", "int32", "int32", 3.0);
}

/* ---- lightcsv, cliopts ------------------------------------------------------------------------ */

static void lightcsv_seeds(void)
{
    /* the line format of cmd_lights.c's --csv */
    static const double d[4][3] = {{0, 0, 1}, {0.6, 0.8, 0}, {-0.57735027, 0.57735027, -0.57735027}, {1, 0, 0}};
    char b[2048];
    size_t n = (size_t)snprintf(b, sizeof b, "x,y,z,r,g,b,u0,v0,u1,v1\n");
    for (int i = 0; i < 4; ++i)
        n += (size_t)snprintf(b + n, sizeof b - n, "%.9f,%.9f,%.9f,%.9g,%.9g,%.9g,%u,%u,%u,%u\n", d[i][0], d[i][1],
                              d[i][2], 1.5 * (i + 1), 0.25 * i, 1e-3 * i, 4u * (unsigned)i, 0u, 4u * (unsigned)i + 4, 8u);
    put("lightcsv", "four.csv", b, n);
    static const char crlf[] = "x,y,z,r,g,b,u0,v0,u1,v1\r\n1e-300,2e-300,-1e-300,1,2,3,0,0,1,1\r\n\r\n"
                               "0,1e200,-1e200,1e30,0,4e-320,0,0,4294967295,1\r\n";
    put("lightcsv", "extremes_crlf.csv", crlf, sizeof crlf - 1);
    static const char one[] = "x,y,z,r,g,b,u0,v0,u1,v1\n0,0,-1,0,0,0,0,0,0,0";
    put("lightcsv", "one_no_newline.csv", one, sizeof one - 1);
}

static void cliopts_seed(const char *name, const char *const *args)
{
    char b[1024];
    size_t n = 0;
    for (int i = 0; args[i]; ++i) {
        size_t l = strlen(args[i]);
        if (n + l + 1 > sizeof b)
            break;
        memcpy(b + n, args[i], l);
        n += l;
        if (args[i + 1])
            b[n++] = '\0';
    }
    put("cliopts", name, b, n);
}

static void cliopts_seeds(void)
{
#define SEED(name, ...)                                    \
    do {                                                   \
        static const char *const a[] = {__VA_ARGS__, NULL}; \
        cliopts_seed(name, a);                             \
    } while (0)
    SEED("bake_shard", "bake", "--size", "16x4", "--k", "4", "--dirs", "48", "--shard", "0/2", "--sums", "s0", "--quiet",
         "--threads", "1");
    SEED("bake_paths", "bake", "-o", "a.qibl", "--size", "24x6", "--k", "4", "--dirs", "64", "--unshadowed-k", "4",
         "--sun-path", "40,15,7,17", "--lamp-track", "1,1,-0.5;-1,1,-0.5", "--lamp-box", "-2,-2,-1,2,2,0",
         "--lamp-samples", "8", "--path-steps", "8", "--lut-size", "8", "--layout", "interleaved");
    SEED("merge", "merge", "-o", "m.qibl", "--sums", "all", "--k", "9", "--lut", "4", "--lsq", "s0", "s1");
    SEED("render", "render", "--size", "32x8", "--sun", "0.3", "0.2", "1", "--rgb", "1", "1", "1", "--png", "r.png",
         "--pfm", "r.pfm", "--depth", "d.pfm", "--equirect");
    SEED("render_point", "render", "--point", "1", "2", "0.5", "--falloff", "2", "--png", "r.png", "--scene", "x.obj",
         "--zup", "--raw");
    SEED("gen", "gen", "-o", "g.qibl", "--size", "64x16", "--k", "9", "--lut-size", "8", "--pack", "robust",
         "--equirect", "--layout", "planar");
    SEED("relight", "relight", "g.qibl", "--sun", "0", "0", "1", "--rgb", "2", "1", "1", "--point", "1", "1", "1",
         "--png", "o.png", "--exposure", "1.5", "--lut", "bilinear");
    SEED("relight_probe", "relight", "g.qibl", "--probe", "p.hdr", "--probe-mode", "sunsky", "-n", "16", "--rotate",
         "0,0,90", "--layout", "angular", "--hdr", "o.hdr");
    SEED("view", "view", "g.qibl", "--sun", "0", "1", "1", "--probe", "p.hdr", "--exposure", "2", "--truth", "t.png",
         "--lamp-rgb", "3", "--bench", "--frames", "8", "--headless", "--record", "o.png", "--turn");
    SEED("relight_path", "relight", "g.qibl", "--path", "0", "--frames", "8", "--png", "o.png", "--lights", "l.csv");
    SEED("lights", "lights", "p.hdr", "--method", "varmin", "-n", "16", "--priority", "energy-size", "--place",
         "centre", "--as", "srgbe", "--png", "o.png", "--zoom", "2", "--error");
    SEED("lights_auto", "lights", "p.hdr", "--auto", "--error", "2%", "--layout", "latlong");
    SEED("lights_json", "lights", "p.hdr", "--json", "--csv", "-n", "3");
    SEED("sh_eval", "sh", "eval", "--bands", "3", "0.5", "-0.5", "0.7071");
    SEED("sh_project", "sh", "project", "p.hdr", "--bands", "3", "--irradiance", "--window", "hanning", "--format", "c",
         "--name", "grace_sh");
    SEED("sh_plot", "sh", "plot", "--png", "o.png", "--tile", "16");
    SEED("sh_preset", "sh", "project", "p.hdr", "--preset", "filament", "--window", "auto", "--yaw", "30");
    SEED("srgbe", "srgbe", "encode", "1.5", "-0.25", "1e-30");
    SEED("srgbe_decode", "srgbe", "decode", "7f80ff01");
    SEED("probe", "probe", "info", "p.hdr", "--layout", "ball");
    SEED("study", "study", "--quick", "--out", "d", "--threads", "2", "a.hdr", "b.hdr");
    SEED("transfer", "transfer", "m.obj", "--probe", "p.hdr", "--png", "o.png", "--size", "64", "--mask", "32", "--face",
         "8", "--rays", "4", "--coarse", "1", "--ring", "1", "--tween", "4", "--pvs", "--view", "35,20", "--zup",
         "--flip", "--skip-adjacent");
    SEED("transfer_export", "transfer", "m.obj", "--probe", "p.hdr", "--layout", "latlong", "--lights", "4",
         "--threads", "2", "--export", "x.qtr", "--export-c", "x.h", "--export-bands", "4");
    SEED("view_mesh", "view", "m.obj", "--probe", "p.hdr", "--transfer", "x.qtr", "--zup", "--size", "64", "--threads",
         "2", "--light-yaw", "30", "--light-pitch", "-10", "--camera", "20,10", "--exposure", "2", "--png", "o.png");
    SEED("demo", "demo", "--out", "d", "--small", "--scene", "x.obj", "--threads", "2");
    SEED("check", "check", "a.png", "b.pfm", "c.hdr", "d.qibl");
    SEED("info", "info", "a.qibl");
    SEED("bench", "bench", "relight", "--quick", "--csv");
    SEED("ies_info", "ies", "info", "l.ies", "--png", "o.png");
    SEED("relight_ies", "relight", "g.qibl", "--point", "1", "1", "0.5", "--ies", "l.ies", "--aim", "0", "0", "-1", "--up",
         "1", "0", "0", "--ies-size", "32", "--png", "o.png");
    SEED("relight_path_ies", "relight", "g.qibl", "--path", "lamp", "--t", "0.5", "--ies", "l.ies", "--aim", "0", "0",
         "-1", "--up", "1", "0", "0", "--ies-size", "16", "--png", "o.png");
    SEED("render_ies", "render", "--point", "1", "1", "0.5", "--ies", "l.ies", "--aim", "0.2", "0", "-1", "--up", "0",
         "1", "0", "--pfm", "r.pfm");
    SEED("luminaire_capture", "luminaire", "capture", "builtin", "--out", "s.qnf", "--grid", "8", "--res", "16", "--basis",
         "tent", "--threads", "2");
    SEED("luminaire_render", "luminaire", "render", "g.qibl", "s.qnf", "--at", "0", "1", "-0.5", "--out", "o.png", "--far",
         "--table", "32", "--exposure", "2");
#undef SEED
}

/* ---- xfer: fuzz_xfer's layout (first, count as u16, a light seed byte) + a transfer export --- */
static void xfer_seeds(void)
{
    static qibl_q30_t t[5][QIBL_HEMI_COEFFS];
    for (int v = 0; v < 5; ++v)
        for (int i = 0; i < QIBL_HEMI_COEFFS; ++i)
            t[v][i] = (qibl_q30_t)((uint32_t)(v * 25 + i) * 40000003u) | (v == 4 && i == 0 ? INT32_MIN : 0);
    for (int bands = 3; bands <= 5; ++bands) {
        uint8_t *b, buf[5 + QIBL_HEMI_XFER_HEADER_SIZE + 5 * QIBL_HEMI_COEFFS * 4];
        size_t n;
        char err[128], name[32];
        if (qtool_transfer_export_bytes((const qibl_q30_t(*)[QIBL_HEMI_COEFFS])t, 5, bands, &b, &n, err, sizeof err) != 0)
            continue;
        buf[0] = (uint8_t)(bands - 3), buf[1] = 0, buf[2] = (uint8_t)(bands == 4 ? 9 : 2), buf[3] = 0, buf[4] = 7;
        memcpy(buf + 5, b, n);
        snprintf(name, sizeof name, "bands%d_5v.bin", bands);
        put("xfer", name, buf, 5 + n);
        free(b);
    }
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: fuzz-seeds DIR\n");
        return 2;
    }
    root = argv[1];
    if (mkdir(root, 0777) != 0 && errno != EEXIST) {
        fprintf(stderr, "fuzz-seeds: %s: %s\n", root, strerror(errno));
        return 1;
    }
    asset_seed("shmp_rgb.qibl", 4, 3, 4, 3, 0, 0, 0);
    asset_seed("shmp_grey_pmap.qibl", 5, 2, 9, 1, 1, 0, 0);
    asset_seed("full_rgb.qibl", 3, 2, 4, 3, 1, 2, 0);
    asset_seed("full_k9_extra.qibl", 2, 2, 9, 3, 1, 1, 1);
    /* stream: interleaved assets (the layout rows stream in), one planar (refused by layout) */
    asset_seed_to("stream", "il_rgb.qibl", 4, 3, 4, 3, 0, 0, 0, ASSET_INTERLEAVED);
    asset_seed_to("stream", "il_full_rgb.qibl", 3, 2, 4, 3, 1, 2, 0, ASSET_INTERLEAVED);
    asset_seed_to("stream", "il_full_k9_extra.qibl", 17, 2, 9, 3, 1, 1, 1, ASSET_INTERLEAVED);
    asset_seed_to("stream", "il_grey_k16_pmap.qibl", 5, 2, 16, 1, 1, 3, 0, ASSET_INTERLEAVED);
    asset_seed_to("stream", "il_shmu.qibl", 2, 2, 4, 3, 1, 1, 0, ASSET_INTERLEAVED | ASSET_SHMU);
    asset_seed_to("stream", "planar_full.qibl", 3, 2, 4, 3, 1, 2, 0, 0);
    image_seeds();
    hdr_seeds();
    exr_seeds();
    obj_seeds();
    srgbe_seeds();
    fixed_seeds();
    layout_seeds();
    shard_seeds();
    transfer_seeds();
    xfer_seeds();
    lightcsv_seeds();
    cliopts_seeds();
    probe_seed("rgbe_mediancut", 16, 8, 0, 0x00, 3, 0, 0);
    probe_seed("srgbe_adaptive", 12, 6, 1, 0x01 | 2 << 2, 0x80 | 7, 0, 0x09);
    probe_seed("i32_varmin", 8, 4, 2, 0x02 | 1 << 5, 0x80 | 5, 8, 0x01);
    probe_seed("f32_varmin_var", 8, 8, 3, 0x02 | 3 << 2, 4, 0, 0x1A);
    probe_seed("rgbe_levels", 24, 16, 0, 0x01 | 4 << 2, 4, 0, 0x28);
    lightpath_seeds();
    probe_sh_seeds();
    hemi_seeds();
    ply_seeds();
    if (!failed)
        printf("fuzz-seeds: seeds written to %s\n", root);
    return failed;
}
