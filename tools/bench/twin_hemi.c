/*
 * twin_hemi.c - qibl-bench's part of `bench hemi`: the rasterizer's look-up paths (x86 AVX2: 8
 * int32 / float32 lanes) against the scalar twin (tools/twin/hemi_scalar.c) on frame 0 of the cloth (cloth.h),
 * W = 6, the default tables. Not in the shipped qibl: it links the twin.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench.h"
#include "bench/cloth.h"
#include "bench/twin.h"
#include "qibl/hemi.h"
#include "qibl/isa.h"
#include "twin/hemi_scalar.h"

/* The rasterizer's look-up paths on one cloth frame (W = 6): the library's (x86 AVX2: 8 lanes)
 * against the scalar twin, the raster calls alone over every vertex, interleaved repetitions in one
 * process; prints min and median ns per vertex and per rasterized triangle. */
typedef qibl_status_t (*raster_fn)(const qibl_hemi_t *, const int32_t (*)[3], uint32_t, const uint32_t (*)[3], uint32_t,
                                   uint32_t *, qibl_hemi_stats_t *);

static double raster_pass(const qibl_hemi_t *h, const qtool_bench_cloth *s, const int32_t (*loc)[3], const size_t *loc_off,
                          raster_fn fn, uint32_t *hash)
{
    uint32_t mask[QIBL_HEMI_MAX_WORDS], x = 0;
    const double t0 = qtool_bench_cpu_now();
    for (int v = 0; v < s->nv; ++v) {
        QTOOL_BENCH_CALL(qibl_hemi_clear(h, mask));
        fn(h, loc + loc_off[v], (uint32_t)(loc_off[v + 1] - loc_off[v]), (const uint32_t(*)[3])(s->ringf + s->ring_off[v]),
           (uint32_t)s->nring[v], mask, NULL);
        for (uint32_t k = 0; k < h->words; ++k)
            x = x * 31u + mask[k];
    }
    const double t = qtool_bench_cpu_now() - t0;
    *hash = x;
    return t;
}

static int raster_paths(const qibl_hemi_t *h, const qtool_bench_cloth *s, const qibl_q16_t (*pos)[3], const int32_t (*nrm)[3],
                         int reps)
{
    size_t *off = malloc(sizeof(size_t) * ((size_t)s->nv + 1));
    if (!off)
        return -1;
    off[0] = 0;
    for (int v = 0; v < s->nv; ++v)
        off[v + 1] = off[v] + (size_t)(s->ncv + s->nrv[v]);
    int32_t (*loc)[3] = malloc(sizeof *loc * off[s->nv]);
    qibl_q16_t (*gp)[3] = malloc(sizeof *gp * (size_t)CLOTH_LOCAL_MAX);
    double *ta = malloc(sizeof(double) * (size_t)reps), *tb = malloc(sizeof(double) * (size_t)reps);
    if (!loc || !gp || !ta || !tb) {
        free(off), free(loc), free(gp), free(ta), free(tb);
        return -1;
    }
    qibl_hemi_stats_t st = {0, 0, 0};
    uint32_t mask[QIBL_HEMI_MAX_WORDS];
    for (int v = 0; v < s->nv; ++v) {
        qibl_hemi_frame_t fr;
        QTOOL_BENCH_CALL(qibl_hemi_frame_init(&fr, pos[v], nrm[v]));
        qtool_bench_cloth_gather(s, pos, v, v == 0, gp);
        QTOOL_BENCH_CALL(qibl_hemi_transform(&fr, (const qibl_q16_t(*)[3])gp, (uint32_t)(off[v + 1] - off[v]), loc + off[v]));
        QTOOL_BENCH_CALL(qibl_hemi_clear(h, mask));
        QTOOL_BENCH_CALL(qibl_hemi_raster(h, (const int32_t(*)[3])(loc + off[v]), (uint32_t)(off[v + 1] - off[v]),
                         (const uint32_t(*)[3])(s->ringf + s->ring_off[v]), (uint32_t)s->nring[v], mask, &st));
    }
    uint32_t ha = 0, hb = 0;
    for (int r = 0; r < reps; ++r) {
        ta[r] = raster_pass(h, s, (const int32_t(*)[3])loc, off, qibl_hemi_raster, &ha);
        tb[r] = raster_pass(h, s, (const int32_t(*)[3])loc, off, qtool_hemi_raster_scalar, &hb);
    }
    const double mina = qtool_bench_min(ta, reps), minb = qtool_bench_min(tb, reps);
    const double meda = qtool_bench_median(ta, reps), medb = qtool_bench_median(tb, reps), nvd = (double)s->nv;
    const double nr = (double)st.rasterized;
#if defined(__x86_64__) || defined(__i386__)
    /* the kernel set the library picks now (qibl/isa.h: from the CPU, QIBL_ISA restricts it) */
    const qibl_isa_t isa = qibl_isa_active();
    const char *lib = isa == QIBL_ISA_AVX2   ? "AVX2 int32 / float32 lanes (8)"
                      : isa == QIBL_ISA_SSE2 ? "SSE2 int32 / float32 lanes (4)"
                                             : "library, scalar (integer look-ups)";
#else
    const char *lib = "library (scalar look-ups here)";
#endif
    printf("\nraster look-up paths (cloth frame 0, W = 6, %d x %d mask, %d x %d faces, %.1f rasterized per vertex;\n"
           "  min / median of %d interleaved reps; built by %s, core %s):\n",
           h->n, h->n, h->face, h->face, nr / nvd, reps, QTOOL_BENCH_COMPILER, QIBL_BENCH_CORE_FLAGS);
    printf("  %-34s %9.0f / %-9.0f ns per vertex  %6.1f ns per rasterized triangle\n", lib, mina / nvd * 1e9,
           meda / nvd * 1e9, mina / nr * 1e9);
    printf("  %-34s %9.0f / %-9.0f ns per vertex  %6.1f ns per rasterized triangle\n", "scalar twin (integer look-ups)",
           minb / nvd * 1e9, medb / nvd * 1e9, minb / nr * 1e9);
    printf("  masks %s\n", ha == hb ? "identical" : "DIFFER");
    printf("RESULT hemi.raster_lanes_speedup %.2f\n", minb / mina);
    free(off), free(loc), free(gp), free(ta), free(tb);
    return 0;
}

int qtool_bench_twin_hemi(int quick)
{
    qtool_bench_cloth s;
    memset(&s, 0, sizeof s);
    const size_t sz = qibl_hemi_workspace_size(32, QIBL_HEMI_FACE_DEFAULT);
    void *ws = malloc(sz);
    qibl_q16_t (*pos)[3] = NULL;
    int32_t (*nrm)[3] = NULL;
    qibl_hemi_t h;
    /* frame 0 is the same whatever the frame count: one frame is enough here */
    int rc = !ws || qtool_bench_cloth_make(&s, 1) || qtool_bench_cloth_rings(&s, 6);
    if (!rc) {
        pos = malloc(sizeof *pos * (size_t)s.nv), nrm = malloc(sizeof *nrm * (size_t)s.nv);
        rc = !pos || !nrm || qtool_bench_cloth_frame(&s, 0, pos, nrm) != 0;
    }
    if (rc || qibl_hemi_init(&h, 32, QIBL_HEMI_FACE_DEFAULT, ws, sz) != QIBL_OK ||
        raster_paths(&h, &s, (const qibl_q16_t(*)[3])pos, (const int32_t(*)[3])nrm, quick ? 9 : 31) != 0) {
        fprintf(stderr, "qibl-bench: hemi: out of memory\n");
        rc = 1;
    }
    free(pos), free(nrm), free(ws);
    qtool_bench_cloth_free(&s);
    return rc;
}
