/*
 * relight.c - `qibl bench relight`: speed against error of the relighting kernels on the
 * procedural courtyard (tools/gen), 1024x256 (the paper's size), k = 4, 9, 16, 25; directional and
 * point lights (cube-map LUT 16^2, 32^2, 64^2 per face, and direct SH evaluation), plus a plain read
 * of the same map bytes timed in the same run, and the two range-packing schemes.
 * Errors are in 8-bit units against the double-precision reconstruction from the same 8-bit maps
 * (kernel error) and against the unquantised maps (kernel + packing).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gen/scene.h"
#include "io/asset_write.h"
#include "bench/bench.h"
#include "qibl/isa.h"
#include "qibl/shmap.h"
#include "ref/psnr.h"
#include "ref/sh_ref.h"

#define REPS_MAX 15

typedef struct {
    qibl_shmaps_t m;
    uint8_t *params, *planes;
    int32_t *scale, *bias;
    qtool_pack_stats st;
} packed;

static int pack(const qtool_gen_maps *g, uint32_t k, qtool_pack_scheme sch, packed *p)
{
    qtool_gen_maps view = *g;
    view.k = k;
    size_t np = (size_t)g->width * g->height;
    p->scale = malloc(sizeof(int32_t) * k * 3);
    p->bias = malloc(sizeof(int32_t) * k * 3);
    p->params = malloc(8u * k * 3);
    p->planes = malloc(np * k * 3);
    if (!p->scale || !p->bias || !p->params || !p->planes || qtool_pack_maps(&view, sch, p->scale, p->bias, p->planes, &p->st))
        return -1;
    for (uint32_t i = 0; i < k * 3; ++i) {
        qtool_store_s32le(p->params + 8 * i, p->scale[i]);
        qtool_store_s32le(p->params + 8 * i + 4, p->bias[i]);
    }
    p->m.width = g->width, p->m.height = g->height, p->m.k = k, p->m.channels = 3, p->m.layout = QIBL_SHMAPS_PLANAR;
    p->m.params = p->params, p->m.planes = p->planes;
    return 0;
}

static void unpack(packed *p)
{
    free(p->scale), free(p->bias), free(p->params), free(p->planes);
}

static volatile uint32_t sink;

/* one plain pass over the bytes the kernel reads, as 64-bit words: the memory-bandwidth floor */
static double time_stream(const packed *p, int reps)
{
    size_t n = (size_t)p->m.width * p->m.height * p->m.k * 3;
    double t[REPS_MAX];
    for (int r = 0; r < reps; ++r) {
        double t0 = qtool_bench_cpu_now();
        sink = (uint32_t)qtool_bench_read_u64(p->planes, n);
        t[r] = qtool_bench_cpu_now() - t0;
    }
    return qtool_bench_median(t, reps);
}

/* 8-bit display value of a linear radiance (1.0 = 255), continuous for the reference */
static double to8(double v)
{
    v *= 255.0;
    return v < 0 ? 0 : v > 255 ? 255 : v;
}

typedef struct {
    double psnr, max_abs;
} err8;

static err8 compare8(const int32_t *img, const double *ref, size_t n)
{
    double se = 0, mx = 0;
    for (size_t i = 0; i < n; ++i) {
        double a = floor(to8(img[i] / 65536.0) + 0.5), e = fabs(a - to8(ref[i]));
        se += e * e;
        mx = e > mx ? e : mx;
    }
    err8 r = {qtool_ref_psnr8(se / n), mx};
    return r;
}

static double decoded(const qibl_shmaps_t *m, uint32_t i, uint32_t ch, size_t px)
{
    return (qibl_shmaps_bias(m, i, ch) + (double)qibl_shmaps_scale(m, i, ch) * qibl_shmaps_plane(m, i, ch)[px]) /
           16777216.0;
}

/* Planar against interleaved layout (shmaps.h), same maps, same light, same run: frames alternate
 * planar, interleaved, planar, ... so load swings hit both; min and median of each. Checks that
 * both give the same bytes. Returns the k = 16 directional ratio interleaved / planar (min times). */
static double bench_layouts(const qtool_gen_maps *g, uint32_t W, uint32_t H, int reps, const qibl_q16_t sun_dir[3],
                            const qibl_q16_t sun_rgb[3], const qibl_pointlight_t *lamp, int32_t *img, void *ws)
{
    static const uint32_t ks[3] = {9, 16, 25};
    const size_t np = (size_t)W * H;
    int32_t *img2 = malloc(sizeof(int32_t) * 3 * np);
    uint8_t *pbytes = malloc(np * 12);
    double ratio16 = 0;
    printf("== layouts: planar against interleaved (16-pixel groups), %ux%u, %d alternating frames each\n", W, H,
           reps);
    printf("   built by %s, core %s\n", QTOOL_BENCH_COMPILER, QIBL_BENCH_CORE_FLAGS);
    printf("%-22s %3s %12s %12s %12s %12s %8s %5s\n", "light", "k", "planar min", "median", "interl. min", "median",
           "ratio", "same");
    for (size_t i = 0; i < np * 3; ++i)
        qtool_store_s32le(pbytes + 4 * i, g->p[i]);
    qibl_pmap_t pm = {W, H, pbytes};
    for (int ki = 0; ki < 3; ++ki) {
        const uint32_t k = ks[ki];
        packed p;
        if (!img2 || !pbytes || pack(g, k, QTOOL_PACK_MINMAX, &p) != 0)
            break;
        qibl_shmaps_t il = p.m;
        il.layout = QIBL_SHMAPS_INTERLEAVED;
        size_t isz = qibl_shmaps_row_size(&il) * H;
        uint8_t *ib = malloc(isz);
        if (!ib || qibl_shmaps_interleave(&p.m, ib, isz) != QIBL_OK)
            break;
        il.planes = ib;
        size_t lvs = qibl_ylut_values_size(32, k), pwn = qibl_shmap_point_workspace_size(k, W);
        uint8_t *lv = malloc(lvs);
        void *pws = malloc(pwn);
        QTOOL_BENCH_CALL(qibl_ylut_build(32, k, lv, lvs));
        qibl_ylut_t lut = {32, k, lv, lvs};
        for (int light = 0; light < 2; ++light) {
            double t[2][REPS_MAX];
            int same = 1;
            for (int r = 0; r < reps; ++r)
                for (int lay = 0; lay < 2; ++lay) {
                    const qibl_shmaps_t *m = lay ? &il : &p.m;
                    int32_t *o = lay ? img2 : img;
                    double t0 = qtool_bench_cpu_now();
                    if (light == 0) {
                        qibl_shlight_t sl;
                        QTOOL_BENCH_CALL(qibl_shlight_init(&sl, 25));
                        QTOOL_BENCH_CALL(qibl_shlight_add_dir(&sl, sun_dir, sun_rgb));
                        qibl_shmap_weights_t w;
                        QTOOL_BENCH_CALL(qibl_shmap_weights(m, &sl, &w));
                        for (uint32_t y = 0; y < H; ++y)
                            QTOOL_BENCH_CALL(qibl_shmap_relight_span(m, &w, 0, y, W, o + 3 * (size_t)y * W, ws,
                                                    qibl_shmap_span_workspace_size(W)));
                    } else {
                        qibl_shmap_point_t st;
                        QTOOL_BENCH_CALL(qibl_shmap_point_prepare(m, &pm, &lut, lamp, &st));
                        for (uint32_t y = 0; y < H; ++y)
                            QTOOL_BENCH_CALL(qibl_shmap_point_span(&st, 0, y, W, o + 3 * (size_t)y * W, pws, pwn));
                    }
                    t[lay][r] = qtool_bench_cpu_now() - t0;
                }
            same = memcmp(img, img2, sizeof(int32_t) * 3 * np) == 0;
            double mp = qtool_bench_min(t[0], reps), mi = qtool_bench_min(t[1], reps);
            printf("%-22s %3u %10.3fms %10.3fms %10.3fms %10.3fms %8.3f %5s\n", light ? "point, LUT 32^2" : "directional",
                   k, mp * 1e3, qtool_bench_median(t[0], reps) * 1e3, mi * 1e3, qtool_bench_median(t[1], reps) * 1e3, mi / mp,
                   same ? "yes" : "NO");
            if (!same) {
                fprintf(stderr, "qibl: bench relight: the layouts gave different bytes (k = %u)\n", k);
                ratio16 = -1;
            }
            if (light == 0 && ratio16 >= 0)
                printf("RESULT relight.interleaved_over_planar_k%u %.3f\n", k, mi / mp);
            if (light == 0 && k == 16 && ratio16 >= 0)
                ratio16 = mi / mp;
        }
        free(lv), free(pws), free(ib);
        unpack(&p);
    }
    free(img2), free(pbytes);
    return ratio16;
}

/* ---- honest baselines: a plain 64-bit word read and memcpy of the same bytes ------------------
 * The directional k = 16 kernel on the interleaved and planar layouts against a u64 word read (sum)
 * and a memcpy of exactly the bytes it reads, (a) in cache: the first rows, about 400 KB, read again and
 * again; (b) in the DRAM regime: copies of the whole asset, 256 MB or more, cycled through so no
 * copy is in any cache when it is read again. Kernels interleaved rep by rep in one process; min
 * and median; ns per pixel beside each ratio. The machine this runs on may be shared and loaded:
 * the minimum is the figure to trust. */
static volatile uint64_t sink64;

/* the same u64 read in the planar kernel's order: row by row, 8 planes side by side (what the
 * planar layout allows a row span at best; see shmap.c's passes) */
static void read_u64_planar(const uint8_t *b, size_t plane, size_t nplanes, size_t W, size_t rows)
{
    uint64_t s = 0;
    for (size_t y = 0; y < rows; ++y)
        for (size_t p0 = 0; p0 < nplanes; p0 += 8)
            for (size_t i = 0; i + 8 <= W; i += 8)
                for (size_t p = p0; p < p0 + 8 && p < nplanes; ++p) {
                    uint64_t v;
                    memcpy(&v, b + p * plane + y * W + i, 8);
                    s += v;
                }
    sink64 = s;
}

/* What the five baseline kinds run on: the interleaved and planar maps, the directional weights, the
 * frame row, the span workspace, memcpy's destination. */
typedef struct baseline {
    const qibl_shmaps_t *il, *pl;
    const qibl_shmap_weights_t *w;
    int32_t *img;
    void *ws;
    uint8_t *dst;
} baseline;

/* One run of a kind over the first rows of src (bytes of them for the plain reads): 0 directional
 * interleaved, 1 u64 read, 2 memcpy, 3 directional planar, 4 u64 read in planar row order. */
static void baseline_kind(const baseline *c, int kind, const uint8_t *src, uint32_t rows, size_t bytes, size_t di)
{
    const uint32_t W = c->il->width, H = c->il->height;
    if (kind == 0 || kind == 3) {
        qibl_shmaps_t m = kind == 3 ? *c->pl : *c->il;
        m.planes = src;
        for (uint32_t y = 0; y < rows; ++y)
            QTOOL_BENCH_CALL(qibl_shmap_relight_span(&m, c->w, 0, y, W, c->img + 3 * (size_t)y * W, c->ws,
                                    qibl_shmap_span_workspace_size(W)));
    } else if (kind == 1) {
        sink64 = qtool_bench_read_u64(src, bytes);
    } else if (kind == 4) {
        read_u64_planar(src, (size_t)W * H, c->il->k * 3u, W, rows);
    } else {
        memcpy(c->dst, src, bytes), sink64 = c->dst[di];
    }
}

static int bench_baselines(const qtool_gen_maps *g, uint32_t W, uint32_t H, int quick, const qibl_q16_t sun_dir[3],
                           const qibl_q16_t sun_rgb[3], int32_t *img, void *ws)
{
    packed p;
    if (pack(g, 16, QTOOL_PACK_MINMAX, &p) != 0)
        return -1;
    qibl_shmaps_t il = p.m;
    il.layout = QIBL_SHMAPS_INTERLEAVED;
    const size_t rs = qibl_shmaps_row_size(&il), asz = rs * H;
    const size_t want = quick ? ((size_t)64 << 20) : ((size_t)256 << 20);
    const size_t ncopy = (want + asz - 1) / asz + 1;
    /* planar copies too (same bytes per pixel: W is a multiple of the group), for the planar kernel */
    const size_t psz = (size_t)W * H * p.m.k * 3u;
    uint8_t *copies = malloc(asz * ncopy), *dst = malloc(asz), *pcopies = malloc(psz * ncopy);
    if (!copies || !dst || !pcopies || qibl_shmaps_interleave(&p.m, copies, asz) != QIBL_OK) {
        free(copies), free(dst), free(pcopies), unpack(&p);
        return -1;
    }
    for (size_t c = 1; c < ncopy; ++c)
        memcpy(copies + c * asz, copies, asz);
    for (size_t c = 0; c < ncopy; ++c)
        memcpy(pcopies + c * psz, p.planes, psz);
    qibl_shmaps_t pl = p.m;
    pl.planes = pcopies;
    qibl_shlight_t sl;
    QTOOL_BENCH_CALL(qibl_shlight_init(&sl, 25));
    QTOOL_BENCH_CALL(qibl_shlight_add_dir(&sl, sun_dir, sun_rgb));
    qibl_shmap_weights_t w;
    il.planes = copies;
    QTOOL_BENCH_CALL(qibl_shmap_weights(&il, &sl, &w));
    /* in cache: the first 8 rows (8 * 1024 px * 48 B = 393 KB at full size), many passes per rep */
    const uint32_t crows = H < 8u ? H : 8u;
    const size_t cbytes = rs * crows, cpx = (size_t)W * crows;
    const int cpass = quick ? 20 : 100, creps = quick ? 5 : 31, dreps = (int)(quick ? ncopy : 2 * ncopy);
    const baseline c = {&il, &pl, &w, img, ws, dst};
    double tc[5][64], td[5][64];
    for (int r = 0; r < creps; ++r)
        for (int kind = 0; kind < 5; ++kind) {
            double t0 = qtool_bench_cpu_now();
            for (int pass = 0; pass < cpass; ++pass) /* 3: planar, the first rows of every plane (same bytes) */
                baseline_kind(&c, kind, kind >= 3 ? pcopies : copies, crows, cbytes, (size_t)pass);
            tc[kind][r] = (qtool_bench_cpu_now() - t0) / cpass;
        }
    for (int r = 0; r < dreps && r < 64; ++r)
        for (int kind = 0; kind < 5; ++kind) {
            /* each kind starts on a different copy, so none reads what another has just loaded */
            const size_t ci = (size_t)((5 * r + kind) % (int)ncopy);
            const uint8_t *src = kind >= 3 ? pcopies + ci * psz : copies + ci * asz;
            double t0 = qtool_bench_cpu_now();
            baseline_kind(&c, kind, src, H, asz, (size_t)r);
            td[kind][r] = qtool_bench_cpu_now() - t0;
        }
    const int nd = dreps < 64 ? dreps : 64;
    static const char *names[5] = {"directional k=16 (interleaved)", "u64 word read", "memcpy",
                                   "directional k=16 (planar)", "u64 read, planar row order"};
    printf("== baselines: the same bytes (k=16, 3 channels, interleaved: %zu B/px), %d interleaved reps\n",
           rs / W, creps);
    printf("   built by %s, core %s; in cache: %u rows (%zu KB) x %d passes; DRAM: %zu copies (%zu MB) cycled\n",
           QTOOL_BENCH_COMPILER, QIBL_BENCH_CORE_FLAGS, crows, cbytes >> 10, cpass, ncopy, (asz * ncopy) >> 20);
    printf("%-32s %12s %12s %12s %12s\n", "", "cache min", "median", "DRAM min", "median");
    /* DRAM ratios paired by repetition (the kinds of one repetition run back to back while the
     * memory bus is shared with whatever else runs): the median of those ratios, taken before the
     * medians below sort the times in place */
    const double dx_read = qtool_bench_paired_ratio(td[1], td[0], nd), dx_memcpy = qtool_bench_paired_ratio(td[2], td[0], nd);
    const double dx_planar = qtool_bench_paired_ratio(td[1], td[3], nd), dx_order = qtool_bench_paired_ratio(td[1], td[4], nd);
    double cmin[5], dmin[5];
    for (int kind = 0; kind < 5; ++kind) {
        cmin[kind] = qtool_bench_min(tc[kind], creps), dmin[kind] = qtool_bench_min(td[kind], nd);
        double cmed = qtool_bench_median(tc[kind], creps), dmed = qtool_bench_median(td[kind], nd);
        printf("%-32s %9.3fns/px %9.3fns/px %9.3fns/px %9.3fns/px\n", names[kind], cmin[kind] / cpx * 1e9,
               cmed / cpx * 1e9, dmin[kind] / ((double)W * H) * 1e9, dmed / ((double)W * H) * 1e9);
    }
    printf("RESULT relight.dir_over_read %.3f  (dir %.3f ns/px, read %.3f ns/px, in cache, min)\n", cmin[1] / cmin[0],
           cmin[0] / cpx * 1e9, cmin[1] / cpx * 1e9);
    printf("RESULT relight.dir_over_memcpy %.3f  (memcpy %.3f ns/px, in cache, min)\n", cmin[2] / cmin[0],
           cmin[2] / cpx * 1e9);
    printf("RESULT relight.dir_over_read_dram %.3f  (dir %.3f ns/px, read %.3f ns/px, DRAM, min; ratio paired)\n", dx_read,
           dmin[0] / ((double)W * H) * 1e9, dmin[1] / ((double)W * H) * 1e9);
    printf("RESULT relight.dir_over_memcpy_dram %.3f  (memcpy %.3f ns/px, DRAM, min; ratio paired)\n", dx_memcpy,
           dmin[2] / ((double)W * H) * 1e9);
    printf("RESULT relight.dir_planar_over_read %.3f  (planar dir %.3f ns/px, in cache, min)\n", cmin[1] / cmin[3],
           cmin[3] / cpx * 1e9);
    printf("RESULT relight.dir_planar_over_read_dram %.3f  (planar dir %.3f ns/px, DRAM, min; ratio paired)\n", dx_planar,
           dmin[3] / ((double)W * H) * 1e9);
    printf("RESULT relight.planar_order_read_over_read_dram %.3f  (u64 read in planar row order %.3f ns/px, DRAM, min:"
           " the best any planar span kernel can do; ratio paired)\n", dx_order, dmin[4] / ((double)W * H) * 1e9);
    free(copies), free(dst), free(pcopies), unpack(&p);
    return 0;
}

typedef struct {
    const char *light;
    uint32_t k;
    double ms, mpix, psnr, maxabs, psnr_exact;
} row;

/* The k = 16 ratios (RESULT relight.point_over_dir and the others) from interleaved minima: one
 * loop times a plain read of the map bytes, the directional frame (weights + every row) and the
 * three point modes (poly, LUT 32^2, direct SH; prepare + every row) in turn, rep after rep, the
 * order rotated each rep, each kind run twice in a row and the second run timed (its own warm caches), so that load swings and frequency changes hit every kind alike; each
 * ratio is a minimum over the minimum of its baseline from the same loop. */
enum { IK_READ, IK_DIR, IK_POLY, IK_LUT32, IK_DIRECT, IK_N };

static int k16_interleaved(const packed *p, const qibl_shlight_t *sl, const qibl_pmap_t *pm,
                           const qibl_pointlight_t *lamp, int32_t *img, void *ws, int reps, double mn[IK_N],
                           double *read_over_dir)
{
    double tr[64], tdir[64]; /* the read and the directional frame of each repetition, paired */
    reps = reps > 64 ? 64 : reps;
    const uint32_t W = p->m.width, H = p->m.height, k = p->m.k;
    const size_t pwn = qibl_shmap_point_workspace_size(k, W), vs = qibl_ylut_values_size(32, k);
    void *pws = malloc(pwn);
    uint8_t *vals = malloc(vs);
    if (!pws || !vals || qibl_ylut_build(32, k, vals, vs) != QIBL_OK) {
        free(pws), free(vals);
        return -1;
    }
    const qibl_ylut_t lut = {32, k, vals, vs};
    qibl_pointlight_t modes[3] = {*lamp, *lamp, *lamp};
    modes[0].filter = QIBL_POINT_POLY;
    for (int i = 0; i < IK_N; ++i)
        mn[i] = 1e30;
    for (int r = 0; r < reps; ++r)
        for (int j = 0; j < 2 * IK_N; ++j) {
            /* each kind twice in a row, the second timed: every kind from its own warm caches */
            const int kind = (j / 2 + r) % IK_N;
            double t0 = qtool_bench_cpu_now();
            if (kind == IK_READ) {
                size_t n = (size_t)W * H * k * 3;
                uint64_t acc = 0;
                for (size_t i = 0; i + 8 <= n; i += 8) {
                    uint64_t v;
                    memcpy(&v, p->planes + i, 8);
                    acc += v;
                }
                sink = (uint32_t)acc;
            } else if (kind == IK_DIR) {
                qibl_shmap_weights_t w;
                QTOOL_BENCH_CALL(qibl_shmap_weights(&p->m, sl, &w));
                for (uint32_t y = 0; y < H; ++y)
                    QTOOL_BENCH_CALL(qibl_shmap_relight_span(&p->m, &w, 0, y, W, img + 3 * (size_t)y * W, ws,
                                            qibl_shmap_span_workspace_size(W)));
            } else {
                const int m = kind - IK_POLY; /* 0 poly, 1 LUT 32^2, 2 direct SH */
                qibl_shmap_point_t st;
                QTOOL_BENCH_CALL(qibl_shmap_point_prepare(&p->m, pm, m == 1 ? &lut : NULL, &modes[m], &st));
                for (uint32_t y = 0; y < H; ++y)
                    QTOOL_BENCH_CALL(qibl_shmap_point_span(&st, 0, y, W, img + 3 * (size_t)y * W, pws, pwn));
            }
            const double dt = qtool_bench_cpu_now() - t0;
            if (j % 2 == 1) {
                mn[kind] = dt < mn[kind] ? dt : mn[kind];
                if (kind == IK_READ)
                    tr[r] = dt;
                else if (kind == IK_DIR)
                    tdir[r] = dt;
            }
        }
    /* the read pass is memory-bound: its minima moved by 19 % between runs on the shared host, the
     * ratio of each repetition's pair does not */
    *read_over_dir = qtool_bench_paired_ratio(tr, tdir, reps);
    free(pws), free(vals);
    return 0;
}

/* The lights of every relight bench: a low sun (directional) and a lamp in the courtyard (point, C0 / |L|). */
static const qibl_q16_t SUN_DIR[3] = {(int32_t)(0.55 * 65536), (int32_t)(0.35 * 65536), (int32_t)(0.76 * 65536)};
static const qibl_q16_t SUN_RGB[3] = {(int32_t)(1.6 * 65536), (int32_t)(1.45 * 65536), (int32_t)(1.2 * 65536)};
static const qibl_pointlight_t LAMP = {{(int32_t)(1.5 * 65536), (int32_t)(-2.0 * 65536), (int32_t)(0.8 * 65536)},
                                       {(int32_t)(4.0 * 65536), (int32_t)(3.4 * 65536), (int32_t)(2.6 * 65536)},
                                       QIBL_FALLOFF_INV_DIST, 0, QIBL_LUT_BILINEAR};

/* One `qibl bench relight` run: the courtyard, the frame and its two references, the table, and
 * the k = 16 figures its summary lines print. */
typedef struct relight_run {
    qtool_gen_maps g;
    uint32_t W, H;
    int reps, quick;
    size_t np;
    int32_t *img;
    double *ref, *refx; /* from the same 8-bit maps; from the unquantised maps */
    void *ws;
    row rows[4 * 6]; /* per k: directional, LUT 16^2 / 32^2 / 64^2, direct SH, poly */
    int nrows;
    double stream_k16, dir_k16, point_k16_lut32, point_k16_direct, psnr_k16;
    double point_k16_poly, psnr_poly_k16, psnr_lut32_k16;
    double ik[IK_N];  /* k = 16 minima of the interleaved loop (k16_interleaved) */
    double ik_stream; /* read / directional, paired by repetition in that loop */
    double psnr_scheme[2];
    qtool_pack_stats pack_st[2]; /* min/max, robust */
} relight_run;

/* The directional light on the first k maps: weights per frame + every row, against the references. */
static void dir_rows(relight_run *r, const packed *p, const qtool_gen_maps *gk, const qibl_shlight_t *sl)
{
    const uint32_t W = r->W, H = r->H, k = p->m.k;
    double t[REPS_MAX];
    for (int i = 0; i < r->reps; ++i) {
        double t0 = qtool_bench_cpu_now();
        qibl_shmap_weights_t w;
        QTOOL_BENCH_CALL(qibl_shmap_weights(&p->m, sl, &w));
        for (uint32_t y = 0; y < H; ++y)
            QTOOL_BENCH_CALL(qibl_shmap_relight_span(&p->m, &w, 0, y, W, r->img + 3 * (size_t)y * W, r->ws, qibl_shmap_span_workspace_size(W)));
        t[i] = qtool_bench_cpu_now() - t0;
    }
    double td = qtool_bench_median(t, r->reps);
    for (size_t px = 0; px < r->np; ++px)
        for (uint32_t ch = 0; ch < 3; ++ch) {
            double s = 0, lc[25];
            for (uint32_t i = 0; i < k; ++i) {
                lc[i] = sl->c[ch][i] / 65536.0;
                s += decoded(&p->m, i, ch, px) * lc[i];
            }
            r->ref[3 * px + ch] = s;
            r->refx[3 * px + ch] = qtool_gen_eval(gk, (uint32_t)(px % W), (uint32_t)(px / W), ch, lc);
        }
    err8 e = compare8(r->img, r->ref, 3 * r->np), ex = compare8(r->img, r->refx, 3 * r->np);
    r->rows[r->nrows++] = (row){"directional", k, td * 1e3, r->np / td * 1e-6, e.psnr, e.max_abs, ex.psnr};
    if (k == 16)
        r->stream_k16 = time_stream(p, r->reps), r->dir_k16 = td, r->psnr_k16 = e.psnr;
}

/* The point light's reference, sum_i T_i Y_i(L) C0 / |L| from the same bytes and from the
 * unquantised maps, in double. */
static void point_reference(relight_run *r, const packed *p, const qtool_gen_maps *gk)
{
    const uint32_t W = r->W, k = p->m.k;
    for (size_t px = 0; px < r->np; ++px) {
        double l[3], d2 = 0, yv[25];
        for (int j = 0; j < 3; ++j) {
            l[j] = (LAMP.pos[j] - (double)r->g.p[3 * px + j]) / 65536.0;
            d2 += l[j] * l[j];
        }
        double dd = fmax(sqrt(d2), 1.0 / 256);
        qtool_ref_sh_eval(l[0], l[1], l[2], 5, yv);
        for (uint32_t ch = 0; ch < 3; ++ch) {
            double s = 0;
            for (uint32_t i = 0; i < k; ++i)
                s += decoded(&p->m, i, ch, px) * yv[i];
            double c0 = LAMP.rgb[ch] / 65536.0 / dd;
            r->ref[3 * px + ch] = s * c0;
            r->refx[3 * px + ch] = qtool_gen_eval(gk, (uint32_t)(px % W), (uint32_t)(px / W), ch, yv) * c0;
        }
    }
}

/* The point light's five modes on the first k maps (LUT 16^2 / 32^2 / 64^2, direct SH, poly):
 * prepare + every row. 0, or -1 out of memory. */
static int point_rows(relight_run *r, const packed *p, const qibl_pmap_t *pm)
{
    static const uint32_t luts[3] = {16, 32, 64};
    static const char *names[5] = {"point, LUT 16^2", "point, LUT 32^2", "point, LUT 64^2", "point, direct SH",
                                   "point, poly Q14"};
    const uint32_t W = r->W, H = r->H, k = p->m.k;
    const size_t pwn = qibl_shmap_point_workspace_size(k, W);
    void *pws = malloc(pwn);
    if (!pws)
        return -1;
    double t[REPS_MAX];
    for (int li = 0; li <= 4; ++li) {
        qibl_ylut_t lut = {0, 0, NULL, 0};
        qibl_pointlight_t lamp_li = LAMP;
        if (li == 4)
            lamp_li.filter = QIBL_POINT_POLY; /* Q2.14 polynomials, no LUT */
        uint8_t *vals = NULL;
        if (li < 3) {
            size_t vs = qibl_ylut_values_size(luts[li], k);
            if (!(vals = malloc(vs)))
                return free(pws), -1;
            QTOOL_BENCH_CALL(qibl_ylut_build(luts[li], k, vals, vs)); /* bake-time work, not timed */
            lut.face_size = luts[li], lut.k = k, lut.values = vals, lut.size = vs;
        }
        for (int i = 0; i < r->reps; ++i) {
            double t0 = qtool_bench_cpu_now();
            qibl_shmap_point_t st;
            QTOOL_BENCH_CALL(qibl_shmap_point_prepare(&p->m, pm, li < 3 ? &lut : NULL, &lamp_li, &st));
            for (uint32_t y = 0; y < H; ++y)
                QTOOL_BENCH_CALL(qibl_shmap_point_span(&st, 0, y, W, r->img + 3 * (size_t)y * W, pws, pwn));
            t[i] = qtool_bench_cpu_now() - t0;
        }
        double tp = qtool_bench_median(t, r->reps);
        err8 pe = compare8(r->img, r->ref, 3 * r->np), pex = compare8(r->img, r->refx, 3 * r->np);
        r->rows[r->nrows++] = (row){names[li], k, tp * 1e3, r->np / tp * 1e-6, pe.psnr, pe.max_abs, pex.psnr};
        if (k == 16 && li == 1)
            r->point_k16_lut32 = tp, r->psnr_lut32_k16 = pe.psnr;
        if (k == 16 && li == 3)
            r->point_k16_direct = tp;
        if (k == 16 && li == 4)
            r->point_k16_poly = tp, r->psnr_poly_k16 = pe.psnr;
        free(vals);
    }
    free(pws);
    return 0;
}

/* Every light on the first k maps (min/max packing): the table's rows, and at k = 16 the
 * interleaved ratios. 0, or -1 out of memory. */
static int k_rows(relight_run *r, uint32_t k)
{
    qtool_gen_maps gk = r->g; /* the first k maps of the unquantised set */
    gk.k = k;
    packed p;
    if (pack(&r->g, k, QTOOL_PACK_MINMAX, &p) != 0)
        return unpack(&p), -1;
    qibl_shlight_t sl;
    QTOOL_BENCH_CALL(qibl_shlight_init(&sl, 25));
    QTOOL_BENCH_CALL(qibl_shlight_add_dir(&sl, SUN_DIR, SUN_RGB));
    dir_rows(r, &p, &gk, &sl);
    qibl_pmap_t pm = {r->W, r->H, NULL};
    uint8_t *pbytes = malloc(r->np * 12);
    if (!pbytes)
        return unpack(&p), -1;
    for (size_t i = 0; i < r->np * 3; ++i)
        qtool_store_s32le(pbytes + 4 * i, r->g.p[i]);
    pm.points = pbytes;
    point_reference(r, &p, &gk);
    int rc = point_rows(r, &p, &pm);
    if (rc == 0 && k == 16)
        rc = k16_interleaved(&p, &sl, &pm, &LAMP, r->img, r->ws, r->quick ? 5 : 21, r->ik, &r->ik_stream);
    free(pbytes);
    unpack(&p);
    return rc;
}

/* The two range-packing schemes at k = 16: relit PSNR against the unquantised maps. 0 or -1. */
static int pack_schemes(relight_run *r)
{
    const uint32_t W = r->W, H = r->H;
    qtool_gen_maps g16 = r->g;
    g16.k = 16;
    for (int s = 0; s < 2; ++s) {
        packed p;
        if (pack(&r->g, 16, s ? QTOOL_PACK_ROBUST : QTOOL_PACK_MINMAX, &p) != 0)
            return unpack(&p), -1;
        qibl_shlight_t sl;
        QTOOL_BENCH_CALL(qibl_shlight_init(&sl, 25));
        QTOOL_BENCH_CALL(qibl_shlight_add_dir(&sl, SUN_DIR, SUN_RGB));
        qibl_shmap_weights_t w;
        QTOOL_BENCH_CALL(qibl_shmap_weights(&p.m, &sl, &w));
        for (uint32_t y = 0; y < H; ++y)
            QTOOL_BENCH_CALL(qibl_shmap_relight_span(&p.m, &w, 0, y, W, r->img + 3 * (size_t)y * W, r->ws, qibl_shmap_span_workspace_size(W)));
        for (size_t px = 0; px < r->np; ++px)
            for (uint32_t ch = 0; ch < 3; ++ch) {
                double lc[25];
                for (uint32_t i = 0; i < 16; ++i)
                    lc[i] = sl.c[ch][i] / 65536.0;
                r->refx[3 * px + ch] = qtool_gen_eval(&g16, (uint32_t)(px % W), (uint32_t)(px / W), ch, lc);
            }
        r->psnr_scheme[s] = compare8(r->img, r->refx, 3 * r->np).psnr;
        r->pack_st[s] = p.st;
        unpack(&p);
    }
    return 0;
}

/* The table (or CSV), the k = 16 summary and the RESULT lines. */
static void print_relight(const relight_run *r, int csv)
{
    const qtool_pack_stats *pm = &r->pack_st[0], *pr = &r->pack_st[1];
    if (csv) {
        printf("light,k,ms_per_frame,mpixel_per_s,psnr_vs_same_bytes_db,max_abs_8bit,psnr_vs_exact_maps_db\n");
        for (int i = 0; i < r->nrows; ++i)
            printf("%s,%u,%.3f,%.2f,%.2f,%.2f,%.2f\n", r->rows[i].light, r->rows[i].k, r->rows[i].ms, r->rows[i].mpix,
                   r->rows[i].psnr, r->rows[i].maxabs, r->rows[i].psnr_exact);
    } else {
        printf("== bench relight: %ux%u procedural courtyard, median of %d frames\n", r->W, r->H, r->reps);
        printf("   error columns: 8-bit units vs the double reconstruction from the same 8-bit maps;\n"
               "   the last column also includes the 8-bit packing (vs the unquantised maps)\n");
        printf("%-18s %3s %10s %10s %10s %9s %12s\n", "light", "k", "ms/frame", "Mpixel/s", "PSNR dB", "max abs",
               "PSNR exact");
        for (int i = 0; i < r->nrows; ++i)
            printf("%-18s %3u %10.3f %10.2f %10.2f %9.2f %12.2f\n", r->rows[i].light, r->rows[i].k, r->rows[i].ms,
                   r->rows[i].mpix, r->rows[i].psnr, r->rows[i].maxabs, r->rows[i].psnr_exact);
        printf("stream (plain read of the k=16 map bytes): %.3f ms; directional k=16: %.3f ms\n", r->stream_k16 * 1e3,
               r->dir_k16 * 1e3);
        printf("range packing, k=16: min/max rms %.3e max %.3e | robust (0.1..99.9%%) rms %.3e max %.3e, %llu clipped\n",
               pm->rms, pm->max_abs, pr->rms, pr->max_abs, (unsigned long long)pr->clipped);
        printf("relit PSNR vs exact maps (sun, k=16): min/max %.2f dB, robust %.2f dB\n", r->psnr_scheme[0],
               r->psnr_scheme[1]);
    }
    /* the ratios: minima of one interleaved loop (k16_interleaved), not the table's medians, which
     * come from separate loops; kernels: the set qibl_isa_active() picks (QIBL_ISA restricts it) */
    const double *ik = r->ik;
    printf("k = 16, minima of %d interleaved reps, kernels %s: read %.3f ms, directional %.3f ms, point poly %.3f ms, "
           "LUT 32^2 %.3f ms, direct SH %.3f ms (table medians: directional %.3f, poly %.3f, LUT 32^2 %.3f, direct %.3f)\n",
           r->quick ? 5 : 21, qibl_isa_name(qibl_isa_active()), ik[IK_READ] * 1e3, ik[IK_DIR] * 1e3, ik[IK_POLY] * 1e3,
           ik[IK_LUT32] * 1e3, ik[IK_DIRECT] * 1e3, r->dir_k16 * 1e3, r->point_k16_poly * 1e3, r->point_k16_lut32 * 1e3,
           r->point_k16_direct * 1e3);
    printf("RESULT relight.dir_stream_ratio %.3f\n", r->ik_stream);
    /* the default point mode (QIBL_POINT_POLY); the LUT 32^2 figure was the headline before */
    printf("RESULT relight.point_over_dir %.3f\n", ik[IK_POLY] / ik[IK_DIR]);
    printf("RESULT relight.point_lut32_over_dir %.3f\n", ik[IK_LUT32] / ik[IK_DIR]);
    printf("RESULT relight.point_psnr_k16 %.2f  (poly Q14; LUT 32^2 %.2f dB)\n", r->psnr_poly_k16, r->psnr_lut32_k16);
    printf("RESULT relight.point_direct_over_dir %.3f\n", ik[IK_DIRECT] / ik[IK_DIR]);
    printf("RESULT relight.psnr_k16 %.2f\n", r->psnr_k16);
    printf("RESULT relight.dir_k16_ms %.3f\n", ik[IK_DIR] * 1e3);
    printf("RESULT relight.pack_minmax_psnr_k16 %.2f\n", r->psnr_scheme[0]);
    printf("RESULT relight.pack_robust_psnr_k16 %.2f\n", r->psnr_scheme[1]);
}

int qtool_bench_relight(int quick, int csv)
{
    static const uint32_t ks[4] = {4, 9, 16, 25};
    relight_run *r = calloc(1, sizeof *r);
    if (!r || qtool_gen_scene(quick ? 256 : 1024, quick ? 64 : 256, 25, QTOOL_PANO_CYLINDRICAL, &r->g) != 0) {
        fprintf(stderr, "qibl: bench relight: out of memory\n");
        return free(r), 1;
    }
    r->W = r->g.width, r->H = r->g.height, r->quick = quick, r->reps = quick ? 3 : 9;
    r->np = (size_t)r->W * r->H;
    r->img = malloc(sizeof(int32_t) * 3 * r->np);
    r->ref = malloc(sizeof(double) * 3 * r->np), r->refx = malloc(sizeof(double) * 3 * r->np);
    r->ws = malloc(qibl_shmap_span_workspace_size(r->W));
    int rc = !r->img || !r->ref || !r->refx || !r->ws;
    for (int ki = 0; !rc && ki < 4; ++ki)
        rc = k_rows(r, ks[ki]) != 0;
    if (!rc)
        rc = pack_schemes(r) != 0;
    if (rc) {
        fprintf(stderr, "qibl: bench relight: out of memory\n");
    } else {
        print_relight(r, csv);
        if (bench_layouts(&r->g, r->W, r->H, quick ? 3 : 15, SUN_DIR, SUN_RGB, &LAMP, r->img, r->ws) < 0)
            rc = 1;
        if (bench_baselines(&r->g, r->W, r->H, quick, SUN_DIR, SUN_RGB, r->img, r->ws) != 0) {
            fprintf(stderr, "qibl: bench relight: out of memory for the baselines\n");
            rc = 1;
        }
    }
    free(r->img), free(r->ref), free(r->refx), free(r->ws);
    qtool_gen_free(&r->g);
    free(r);
    return rc;
}

/* `qibl bench baselines`: only the baselines above, on the full-size courtyard (1024x256; 256x64
 * with --quick), for comparing builds (compilers, flags, QIBL_CONFIG_SIMD) without the error runs. */
int qtool_bench_relight_baselines(int quick)
{
    const uint32_t W = quick ? 256 : 1024, H = quick ? 64 : 256;
    qtool_gen_maps g;
    if (qtool_gen_scene(W, H, 25, QTOOL_PANO_CYLINDRICAL, &g) != 0) {
        fprintf(stderr, "qibl: bench baselines: out of memory\n");
        return 1;
    }
    int32_t *img = malloc(sizeof(int32_t) * 3 * (size_t)W * H);
    void *ws = malloc(qibl_shmap_span_workspace_size(W));
    int rc = !img || !ws || bench_baselines(&g, W, H, quick, SUN_DIR, SUN_RGB, img, ws) != 0;
    if (rc)
        fprintf(stderr, "qibl: bench baselines: out of memory\n");
    free(img), free(ws);
    qtool_gen_free(&g);
    return rc;
}
