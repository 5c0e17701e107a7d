/*
 * asset.c - `qibl bench asset`: what opening a 16 MB asset costs on the three paths of
 * asset.h (nibble-table CRC, slicing-by-8 CRC from a caller table, header and structure only),
 * against a memcpy of the same bytes, timed in one process with the repetitions interleaved
 * (open, fast, structure, memcpy, open, ...) so a load swing hits every path alike; min and median
 * of each. The asset is the procedural courtyard 1024x256, k = 16, RGB, with its P map (the
 * handheld case of the engine-integration issue).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gen/scene.h"
#include "io/asset_write.h"
#include "qibl/asset.h"
#include "bench/bench.h"

#define ASSET_REPS_MAX 41

/* The courtyard asset in memory (serialised, not written): *bytes malloc'ed. 0 or -1. */
int qtool_bench_make_asset(uint32_t w, uint32_t h, uint32_t k, uint32_t layout, uint8_t **bytes, size_t *n)
{
    qtool_gen_maps g;
    if (qtool_gen_scene(w, h, k, QTOOL_PANO_CYLINDRICAL, &g) != 0)
        return -1;
    size_t np = (size_t)w * h;
    int32_t *scale = malloc(sizeof(int32_t) * k * 3), *bias = malloc(sizeof(int32_t) * k * 3);
    uint8_t *planes = malloc(np * k * 3);
    qtool_asset_builder b;
    qtool_asset_builder_init(&b);
    int rc = -1;
    if (scale && bias && planes && qtool_pack_maps(&g, QTOOL_PACK_MINMAX, scale, bias, planes, NULL) == 0 &&
        qtool_asset_add_shmp_layout(&b, w, h, k, 3, scale, bias, planes, layout) == 0 &&
        qtool_asset_add_pmap(&b, w, h, g.p) == 0 && qtool_asset_serialize(&b, bytes, n) == 0)
        rc = 0;
    qtool_asset_builder_free(&b);
    free(scale), free(bias), free(planes);
    qtool_gen_free(&g);
    return rc;
}

int qtool_bench_asset(int quick)
{
    const int reps = quick ? 3 : ASSET_REPS_MAX;
    uint8_t *bytes = NULL;
    size_t n = 0;
    if (qtool_bench_make_asset(1024, 256, 16, QIBL_SHMAPS_PLANAR, &bytes, &n) != 0) {
        fprintf(stderr, "qibl: bench asset: out of memory\n");
        return 1;
    }
    uint32_t *table = malloc(sizeof(uint32_t) * QIBL_CRC32_TABLE_WORDS);
    uint8_t *copy = malloc(n);
    if (!table || !copy) {
        fprintf(stderr, "qibl: bench asset: out of memory\n");
        return 1;
    }
    double t_init = qtool_bench_cpu_now();
    QTOOL_BENCH_CALL(qibl_crc32_table_init(table, QIBL_CRC32_TABLE_WORDS));
    t_init = qtool_bench_cpu_now() - t_init;
    memcpy(copy, bytes, n); /* first touch of the destination, not timed */
    double t[4][ASSET_REPS_MAX];
    int bad = 0;
    for (int r = 0; r < reps; ++r)
        for (int m = 0; m < 4; ++m) {
            qibl_asset_t a;
            qibl_status_t st = QIBL_OK;
            double t0 = qtool_bench_cpu_now();
            if (m == 0)
                st = qibl_asset_open(&a, bytes, n);
            else if (m == 1)
                st = qibl_asset_open_crc_table(&a, bytes, n, table);
            else if (m == 2)
                st = qibl_asset_open_structure(&a, bytes, n);
            else
                memcpy(copy, bytes, n);
            t[m][r] = qtool_bench_cpu_now() - t0;
            bad |= st != QIBL_OK || (m == 3 && copy[n / 2] != bytes[n / 2]);
        }
    if (bad) {
        fprintf(stderr, "qibl: bench asset: an open failed\n");
        return 1;
    }
    double mn[4], md[4];
    for (int m = 0; m < 4; ++m) {
        mn[m] = qtool_bench_min(t[m], reps);
        md[m] = qtool_bench_median(t[m], reps);
    }
    static const char *names[4] = {"qibl_asset_open (nibble CRC)", "qibl_asset_open_crc_table (slice-by-8)",
                                   "qibl_asset_open_structure", "memcpy of the same bytes"};
    printf("== bench asset: open a %.1f MB asset (courtyard 1024x256, k = 16, RGB, P map), %d interleaved reps\n",
           n / 1e6, reps);
    printf("   built by %s, core %s\n", QTOOL_BENCH_COMPILER, QIBL_BENCH_CORE_FLAGS);
    printf("%-40s %10s %10s %10s\n", "path", "min ms", "median ms", "MB/s (min)");
    for (int m = 0; m < 4; ++m)
        printf("%-40s %10.3f %10.3f %10.0f\n", names[m], mn[m] * 1e3, md[m] * 1e3, n / mn[m] / 1e6);
    printf("slicing table init (8 KiB, once): %.1f us\n", t_init * 1e6);
    printf("RESULT asset.open_ms %.3f\n", mn[0] * 1e3);
    printf("RESULT asset.open_fast_crc_ms %.3f\n", mn[1] * 1e3);
    printf("RESULT asset.open_structure_us %.2f\n", mn[2] * 1e6);
    printf("RESULT asset.memcpy_ms %.3f\n", mn[3] * 1e3);
    printf("RESULT asset.fast_crc_speedup %.2f\n", mn[0] / mn[1]);
    printf("RESULT asset.fast_crc_over_memcpy %.2f\n", mn[1] / mn[3]);
    free(bytes), free(copy), free(table);
    return 0;
}
