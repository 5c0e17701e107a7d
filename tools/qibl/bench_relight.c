/*
 * bench_relight.c - `qibl bench relight`: speed against error of the relighting kernels on the
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
#include "qibl/cli.h"
#include "qibl/shmap.h"
#include "ref/psnr.h"
#include "ref/sh_ref.h"

#define REPS_MAX 15

typedef struct {
    qibl_shmaps_t m;
    uint8_t *params, *planes;
    int32_t *scale, *bias;
    qibl_pack_stats st;
} packed;

static int pack(const qibl_gen_maps *g, uint32_t k, qibl_pack_scheme sch, packed *p)
{
    qibl_gen_maps view = *g;
    view.k = k;
    size_t np = (size_t)g->width * g->height;
    p->scale = malloc(sizeof(int32_t) * k * 3);
    p->bias = malloc(sizeof(int32_t) * k * 3);
    p->params = malloc(8u * k * 3);
    p->planes = malloc(np * k * 3);
    if (!p->scale || !p->bias || !p->params || !p->planes || qibl_pack_maps(&view, sch, p->scale, p->bias, p->planes, &p->st))
        return -1;
    for (uint32_t i = 0; i < k * 3; ++i) {
        qibl_store_s32le(p->params + 8 * i, p->scale[i]);
        qibl_store_s32le(p->params + 8 * i + 4, p->bias[i]);
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

/* one plain pass over the bytes the kernel reads: the memory-bandwidth floor */
static double time_stream(const packed *p, int reps)
{
    size_t n = (size_t)p->m.width * p->m.height * p->m.k * 3;
    double t[REPS_MAX];
    for (int r = 0; r < reps; ++r) {
        double t0 = qibl_cli_now();
        uint32_t acc = 0;
        for (size_t i = 0; i < n; ++i)
            acc += p->planes[i];
        sink = acc;
        t[r] = qibl_cli_now() - t0;
    }
    return qibl_cli_median(t, reps);
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
    err8 r = {qibl_ref_psnr8(se / n), mx};
    return r;
}

static double decoded(const qibl_shmaps_t *m, uint32_t i, uint32_t ch, size_t px)
{
    return (qibl_shmaps_bias(m, i, ch) + (double)qibl_shmaps_scale(m, i, ch) * qibl_shmaps_plane(m, i, ch)[px]) /
           16777216.0;
}

static double min_of(const double *t, int n)
{
    double m = t[0];
    for (int i = 1; i < n; ++i)
        m = t[i] < m ? t[i] : m;
    return m;
}

/* Planar against interleaved layout (shmaps.h), same maps, same light, same run: frames alternate
 * planar, interleaved, planar, ... so load swings hit both; min and median of each. Checks that
 * both give the same bytes. Returns the k = 16 directional ratio interleaved / planar (min times). */
static double bench_layouts(const qibl_gen_maps *g, uint32_t W, uint32_t H, int reps, const qibl_q16_t sun_dir[3],
                            const qibl_q16_t sun_rgb[3], const qibl_pointlight_t *lamp, int32_t *img, void *ws)
{
    static const uint32_t ks[3] = {9, 16, 25};
    const size_t np = (size_t)W * H;
    int32_t *img2 = malloc(sizeof(int32_t) * 3 * np);
    uint8_t *pbytes = malloc(np * 12);
    double ratio16 = 0;
    printf("== layouts: planar against interleaved (16-pixel groups), %ux%u, %d alternating frames each\n", W, H,
           reps);
    printf("   built by %s, core %s\n", QIBL_BENCH_COMPILER, QIBL_BENCH_CORE_FLAGS);
    printf("%-22s %3s %12s %12s %12s %12s %8s %5s\n", "light", "k", "planar min", "median", "interl. min", "median",
           "ratio", "same");
    for (size_t i = 0; i < np * 3; ++i)
        qibl_store_s32le(pbytes + 4 * i, g->p[i]);
    qibl_pmap_t pm = {W, H, pbytes};
    for (int ki = 0; ki < 3; ++ki) {
        const uint32_t k = ks[ki];
        packed p;
        if (!img2 || !pbytes || pack(g, k, QIBL_PACK_MINMAX, &p) != 0)
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
        qibl_ylut_build(32, k, lv, lvs);
        qibl_ylut_t lut = {32, k, lv};
        for (int light = 0; light < 2; ++light) {
            double t[2][REPS_MAX];
            int same = 1;
            for (int r = 0; r < reps; ++r)
                for (int lay = 0; lay < 2; ++lay) {
                    const qibl_shmaps_t *m = lay ? &il : &p.m;
                    int32_t *o = lay ? img2 : img;
                    double t0 = qibl_cli_now();
                    if (light == 0) {
                        qibl_shlight_t sl;
                        qibl_shlight_init(&sl, 25);
                        qibl_shlight_add_dir(&sl, sun_dir, sun_rgb);
                        qibl_shmap_weights_t w;
                        qibl_shmap_weights(m, &sl, &w);
                        for (uint32_t y = 0; y < H; ++y)
                            qibl_shmap_relight_span(m, &w, 0, y, W, o + 3 * (size_t)y * W, ws,
                                                    qibl_shmap_span_workspace_size(W));
                    } else {
                        qibl_shmap_point_t st;
                        qibl_shmap_point_prepare(m, &pm, &lut, lamp, &st);
                        for (uint32_t y = 0; y < H; ++y)
                            qibl_shmap_point_span(&st, 0, y, W, o + 3 * (size_t)y * W, pws, pwn);
                    }
                    t[lay][r] = qibl_cli_now() - t0;
                }
            same = memcmp(img, img2, sizeof(int32_t) * 3 * np) == 0;
            double mp = min_of(t[0], reps), mi = min_of(t[1], reps);
            printf("%-22s %3u %10.3fms %10.3fms %10.3fms %10.3fms %8.3f %5s\n", light ? "point, LUT 32^2" : "directional",
                   k, mp * 1e3, qibl_cli_median(t[0], reps) * 1e3, mi * 1e3, qibl_cli_median(t[1], reps) * 1e3, mi / mp,
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

typedef struct {
    const char *light;
    uint32_t k;
    double ms, mpix, psnr, maxabs, psnr_exact;
} row;

int qibl_bench_relight(int quick, int csv)
{
    const uint32_t W = quick ? 256 : 1024, H = quick ? 64 : 256;
    const int reps = quick ? 3 : 9;
    const size_t np = (size_t)W * H;
    qibl_gen_maps g;
    if (qibl_gen_scene(W, H, 25, QIBL_PANO_CYLINDRICAL, &g) != 0) {
        fprintf(stderr, "qibl: bench relight: out of memory\n");
        return 1;
    }
    int32_t *img = malloc(sizeof(int32_t) * 3 * np);
    double *ref = malloc(sizeof(double) * 3 * np), *refx = malloc(sizeof(double) * 3 * np);
    void *ws = malloc(qibl_shmap_span_workspace_size(W));
    if (!img || !ref || !refx || !ws) {
        fprintf(stderr, "qibl: bench relight: out of memory\n");
        return 1;
    }
    /* lights: a low sun (directional) and a lamp in the courtyard (point, C0 / |L|) */
    const qibl_q16_t sun_dir[3] = {(int32_t)(0.55 * 65536), (int32_t)(0.35 * 65536), (int32_t)(0.76 * 65536)};
    const qibl_q16_t sun_rgb[3] = {(int32_t)(1.6 * 65536), (int32_t)(1.45 * 65536), (int32_t)(1.2 * 65536)};
    qibl_pointlight_t lamp = {{(int32_t)(1.5 * 65536), (int32_t)(-2.0 * 65536), (int32_t)(0.8 * 65536)},
                              {(int32_t)(4.0 * 65536), (int32_t)(3.4 * 65536), (int32_t)(2.6 * 65536)},
                              QIBL_FALLOFF_INV_DIST, 0, QIBL_LUT_BILINEAR};
    const uint32_t ks[4] = {4, 9, 16, 25};
    const uint32_t luts[3] = {16, 32, 64};
    row rows[4 * 5];
    int nrows = 0;
    double stream_k16 = 0, dir_k16 = 0, point_k16_lut32 = 0, point_k16_direct = 0, psnr_k16 = 0;
    for (int ki = 0; ki < 4; ++ki) {
        uint32_t k = ks[ki];
        qibl_gen_maps gk = g; /* the first k maps of the unquantised set */
        gk.k = k;
        packed p;
        if (pack(&g, k, QIBL_PACK_MINMAX, &p) != 0) {
            fprintf(stderr, "qibl: bench relight: out of memory\n");
            return 1;
        }
        /* ---- directional: weights per frame + every row */
        qibl_shlight_t sl;
        qibl_shlight_init(&sl, 25);
        qibl_shlight_add_dir(&sl, sun_dir, sun_rgb);
        double t[REPS_MAX];
        for (int r = 0; r < reps; ++r) {
            double t0 = qibl_cli_now();
            qibl_shmap_weights_t w;
            qibl_shmap_weights(&p.m, &sl, &w);
            for (uint32_t y = 0; y < H; ++y)
                qibl_shmap_relight_span(&p.m, &w, 0, y, W, img + 3 * (size_t)y * W, ws, qibl_shmap_span_workspace_size(W));
            t[r] = qibl_cli_now() - t0;
        }
        double td = qibl_cli_median(t, reps);
        for (size_t px = 0; px < np; ++px)
            for (uint32_t ch = 0; ch < 3; ++ch) {
                double s = 0, sx = 0, lc[25];
                for (uint32_t i = 0; i < k; ++i) {
                    lc[i] = sl.c[ch][i] / 65536.0;
                    s += decoded(&p.m, i, ch, px) * lc[i];
                }
                sx = qibl_gen_eval(&gk, (uint32_t)(px % W), (uint32_t)(px / W), ch, lc);
                ref[3 * px + ch] = s, refx[3 * px + ch] = sx;
            }
        err8 e = compare8(img, ref, 3 * np), ex = compare8(img, refx, 3 * np);
        rows[nrows++] = (row){"directional", k, td * 1e3, np / td * 1e-6, e.psnr, e.max_abs, ex.psnr};
        if (k == 16) {
            stream_k16 = time_stream(&p, reps);
            dir_k16 = td;
            psnr_k16 = e.psnr;
        }
        /* ---- point light: LUTs and direct */
        qibl_pmap_t pm = {W, H, NULL};
        uint8_t *pbytes = malloc(np * 12);
        for (size_t i = 0; i < np * 3; ++i)
            qibl_store_s32le(pbytes + 4 * i, g.p[i]);
        pm.points = pbytes;
        /* reference: sum_i T_i Y_i(L) C0 / |L| from the same bytes, in double */
        for (size_t px = 0; px < np; ++px) {
            double l[3], d2 = 0, yv[25];
            for (int j = 0; j < 3; ++j) {
                l[j] = (lamp.pos[j] - (double)g.p[3 * px + j]) / 65536.0;
                d2 += l[j] * l[j];
            }
            double dd = fmax(sqrt(d2), 1.0 / 256);
            qibl_ref_sh_eval(l[0], l[1], l[2], 5, yv);
            for (uint32_t ch = 0; ch < 3; ++ch) {
                double s = 0;
                for (uint32_t i = 0; i < k; ++i)
                    s += decoded(&p.m, i, ch, px) * yv[i];
                double c0 = lamp.rgb[ch] / 65536.0 / dd;
                ref[3 * px + ch] = s * c0;
                refx[3 * px + ch] = qibl_gen_eval(&gk, (uint32_t)(px % W), (uint32_t)(px / W), ch, yv) * c0;
            }
        }
        size_t pwn = qibl_shmap_point_workspace_size(k, W);
        void *pws = malloc(pwn);
        for (int li = 0; li <= 3; ++li) {
            qibl_ylut_t lut = {0, 0, NULL};
            uint8_t *vals = NULL;
            if (li < 3) {
                size_t vs = qibl_ylut_values_size(luts[li], k);
                vals = malloc(vs);
                qibl_ylut_build(luts[li], k, vals, vs); /* bake-time work, not timed */
                lut.face_size = luts[li], lut.k = k, lut.values = vals;
            }
            for (int r = 0; r < reps; ++r) {
                double t0 = qibl_cli_now();
                qibl_shmap_point_t st;
                qibl_shmap_point_prepare(&p.m, &pm, li < 3 ? &lut : NULL, &lamp, &st);
                for (uint32_t y = 0; y < H; ++y)
                    qibl_shmap_point_span(&st, 0, y, W, img + 3 * (size_t)y * W, pws, pwn);
                t[r] = qibl_cli_now() - t0;
            }
            double tp = qibl_cli_median(t, reps);
            err8 pe = compare8(img, ref, 3 * np), pex = compare8(img, refx, 3 * np);
            static const char *names[4] = {"point, LUT 16^2", "point, LUT 32^2", "point, LUT 64^2", "point, direct SH"};
            rows[nrows++] = (row){names[li], k, tp * 1e3, np / tp * 1e-6, pe.psnr, pe.max_abs, pex.psnr};
            if (k == 16 && li == 1)
                point_k16_lut32 = tp;
            if (k == 16 && li == 3)
                point_k16_direct = tp;
            free(vals);
        }
        free(pws);
        free(pbytes);
        unpack(&p);
    }
    /* ---- packing schemes, k = 16 */
    packed pm, pr;
    pack(&g, 16, QIBL_PACK_MINMAX, &pm);
    pack(&g, 16, QIBL_PACK_ROBUST, &pr);
    double psnr_scheme[2];
    qibl_gen_maps g16 = g;
    g16.k = 16;
    for (int s = 0; s < 2; ++s) {
        packed *p = s ? &pr : &pm;
        qibl_shlight_t sl;
        qibl_shlight_init(&sl, 25);
        qibl_shlight_add_dir(&sl, sun_dir, sun_rgb);
        qibl_shmap_weights_t w;
        qibl_shmap_weights(&p->m, &sl, &w);
        for (uint32_t y = 0; y < H; ++y)
            qibl_shmap_relight_span(&p->m, &w, 0, y, W, img + 3 * (size_t)y * W, ws, qibl_shmap_span_workspace_size(W));
        for (size_t px = 0; px < np; ++px)
            for (uint32_t ch = 0; ch < 3; ++ch) {
                double lc[25];
                for (uint32_t i = 0; i < 16; ++i)
                    lc[i] = sl.c[ch][i] / 65536.0;
                refx[3 * px + ch] = qibl_gen_eval(&g16, (uint32_t)(px % W), (uint32_t)(px / W), ch, lc);
            }
        psnr_scheme[s] = compare8(img, refx, 3 * np).psnr;
    }

    if (csv) {
        printf("light,k,ms_per_frame,mpixel_per_s,psnr_vs_same_bytes_db,max_abs_8bit,psnr_vs_exact_maps_db\n");
        for (int i = 0; i < nrows; ++i)
            printf("%s,%u,%.3f,%.2f,%.2f,%.2f,%.2f\n", rows[i].light, rows[i].k, rows[i].ms, rows[i].mpix, rows[i].psnr,
                   rows[i].maxabs, rows[i].psnr_exact);
    } else {
        printf("== bench relight: %ux%u procedural courtyard, median of %d frames\n", W, H, reps);
        printf("   error columns: 8-bit units vs the double reconstruction from the same 8-bit maps;\n"
               "   the last column also includes the 8-bit packing (vs the unquantised maps)\n");
        printf("%-18s %3s %10s %10s %10s %9s %12s\n", "light", "k", "ms/frame", "Mpixel/s", "PSNR dB", "max abs",
               "PSNR exact");
        for (int i = 0; i < nrows; ++i)
            printf("%-18s %3u %10.3f %10.2f %10.2f %9.2f %12.2f\n", rows[i].light, rows[i].k, rows[i].ms, rows[i].mpix,
                   rows[i].psnr, rows[i].maxabs, rows[i].psnr_exact);
        printf("stream (plain read of the k=16 map bytes): %.3f ms; directional k=16: %.3f ms\n", stream_k16 * 1e3,
               dir_k16 * 1e3);
        printf("range packing, k=16: min/max rms %.3e max %.3e | robust (0.1..99.9%%) rms %.3e max %.3e, %llu clipped\n",
               pm.st.rms, pm.st.max_abs, pr.st.rms, pr.st.max_abs, (unsigned long long)pr.st.clipped);
        printf("relit PSNR vs exact maps (sun, k=16): min/max %.2f dB, robust %.2f dB\n", psnr_scheme[0],
               psnr_scheme[1]);
    }
    printf("RESULT relight.dir_stream_ratio %.3f\n", stream_k16 / dir_k16);
    printf("RESULT relight.point_over_dir %.3f\n", point_k16_lut32 / dir_k16);
    printf("RESULT relight.point_direct_over_dir %.3f\n", point_k16_direct / dir_k16);
    printf("RESULT relight.psnr_k16 %.2f\n", psnr_k16);
    printf("RESULT relight.dir_k16_ms %.3f\n", dir_k16 * 1e3);
    printf("RESULT relight.pack_minmax_psnr_k16 %.2f\n", psnr_scheme[0]);
    printf("RESULT relight.pack_robust_psnr_k16 %.2f\n", psnr_scheme[1]);
    unpack(&pm), unpack(&pr);
    double lr = bench_layouts(&g, W, H, quick ? 3 : 15, sun_dir, sun_rgb, &lamp, img, ws);
    free(img), free(ref), free(refx), free(ws);
    if (lr < 0) {
        qibl_gen_free(&g);
        return 1;
    }
    qibl_gen_free(&g);
    return 0;
}
