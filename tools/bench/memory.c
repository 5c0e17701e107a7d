/*
 * memory.c - `qibl bench memory [--markdown]`: the resident-memory table of docs/porting.md,
 * every figure from the core's own size functions (and sizeof of its state structs on this host),
 * so the document is regenerated, never edited (`make docs-memory`; `make test` checks it matches).
 */
#include <stdio.h>
#include <stdlib.h>

#include "io/asset_write.h"
#include "qibl/asset.h"
#include "bench/bench.h"
#include "qibl/lightprobe.h"
#include "qibl/shmap.h"

enum { MW = 1024, MH = 256, NK = 3 };
static const uint32_t ks[NK] = {9, 16, 25};

/* Head bytes a streaming caller keeps (qibl_asset_head_size) for an interleaved asset with SHMP,
 * PMAP and a YLUT of k maps: independent of the image size, so measured on a 16 x 1 asset. */
static size_t head_bytes(uint32_t k)
{
    int32_t sc[75] = {0}, bi[75] = {0}, xyz[48] = {0};
    uint8_t planes[16 * 75] = {0};
    int16_t *lut = calloc(6u * k, sizeof(int16_t));
    qtool_asset_builder b;
    qtool_asset_builder_init(&b);
    uint8_t *bytes = NULL;
    size_t n = 0, have = 0, need = 0;
    if (lut && qtool_asset_add_shmp_layout(&b, 16, 1, k, 3, sc, bi, planes, QIBL_SHMAPS_INTERLEAVED) == 0 &&
        qtool_asset_add_pmap(&b, 16, 1, xyz) == 0 && qtool_asset_add_ylut(&b, 1, k, lut) == 0 &&
        qtool_asset_serialize(&b, &bytes, &n) == 0)
        while (qibl_asset_head_size(bytes, have, &need) == QIBL_OK && need > have && need <= n)
            have = need;
    qtool_asset_builder_free(&b);
    free(bytes), free(lut);
    return have;
}

static void row(const char *what, const size_t v[NK], const char *how)
{
    printf("| %s |", what);
    for (int i = 0; i < NK; ++i)
        printf(" %zu |", v[i]);
    printf(" %s |\n", how);
}

int qtool_bench_memory(int markdown)
{
    size_t maps[NK], pmap[NK], lut[3][NK], ws[NK], pws[NK], out[NK], wst[NK], pst[NK], head[NK], mrow[NK], prow[NK];
    size_t crc[NK], sdir[NK], spt[NK], rdir[NK], rpt[NK];
    static const uint32_t faces[3] = {16, 32, 64};
    for (int i = 0; i < NK; ++i) {
        qibl_shmaps_t m = {MW, MH, ks[i], 3, NULL, NULL, QIBL_SHMAPS_INTERLEAVED};
        mrow[i] = qibl_shmaps_row_size(&m);
        maps[i] = mrow[i] * MH + 8u * ks[i] * 3u; /* map bytes + params (planar: the same at this width) */
        pmap[i] = 12u * MW * MH;
        for (int f = 0; f < 3; ++f)
            lut[f][i] = qibl_ylut_values_size(faces[f], ks[i]);
        ws[i] = qibl_shmap_span_workspace_size(MW);
        pws[i] = qibl_shmap_point_workspace_size(ks[i], MW);
        out[i] = 3u * sizeof(int32_t) * MW;
        wst[i] = sizeof(qibl_shmap_weights_t);
        pst[i] = sizeof(qibl_shmap_point_t);
        head[i] = head_bytes(ks[i]);
        prow[i] = 12u * MW;
        crc[i] = sizeof(uint32_t) * QIBL_CRC32_TABLE_WORDS;
        rdir[i] = maps[i] + ws[i] + out[i] + wst[i];
        rpt[i] = maps[i] + pmap[i] + lut[1][i] + pws[i] + out[i] + pst[i];
        sdir[i] = head[i] + mrow[i] + ws[i] + out[i] + wst[i];
        spt[i] = head[i] + mrow[i] + prow[i] + lut[1][i] + pws[i] + out[i] + pst[i];
    }
    if (!markdown)
        printf("== bench memory: bytes resident per configuration (exact; struct sizes of this host)\n");
    printf("Relighting a 1024x256 RGB panorama, bytes (`qibl bench memory --markdown`):\n\n");
    printf("| what | k = 9 | k = 16 | k = 25 | from |\n|---|---:|---:|---:|---|\n");
    row("SH maps + params (planar or interleaved)", maps, "`qibl_shmaps_row_size` x height + 8 k channels");
    row("P map (point lights)", pmap, "12 bytes per pixel");
    row("Y LUT, face 16", lut[0], "`qibl_ylut_values_size`");
    row("Y LUT, face 32", lut[1], "`qibl_ylut_values_size`");
    row("Y LUT, face 64", lut[2], "`qibl_ylut_values_size`");
    row("span workspace, directional (one 1024-px span)", ws, "`qibl_shmap_span_workspace_size`");
    row("span workspace, point light (one 1024-px span)", pws, "`qibl_shmap_point_workspace_size`");
    row("output row, Q16.16 RGB (one 1024-px span)", out, "3 int32 per pixel");
    row("weights state", wst, "`sizeof(qibl_shmap_weights_t)`");
    row("point-light state", pst, "`sizeof(qibl_shmap_point_t)` (holds 3 pointers)");
    row("CRC slicing table (optional, open only)", crc, "`QIBL_CRC32_TABLE_WORDS` u32");
    row("**whole asset resident, directional**", rdir, "maps + workspace + row + weights");
    row("**whole asset resident, point light, LUT 32**", rpt, "+ P map, LUT, point workspace and state");
    row("streaming: asset head", head, "`qibl_asset_head_size` (header, table, SHMP fields, params)");
    row("streaming: one map row (interleaved)", mrow, "`qibl_shmaps_row_size`");
    row("streaming: one P-map row", prow, "12 bytes per pixel");
    row("**streaming rows, directional**", sdir, "head + map row + workspace + row + weights");
    row("**streaming rows, point light, LUT 32**", spt, "+ P-map row, LUT, point workspace and state");

    static const uint32_t pw[3] = {1024, 2048, 4096};
    static const char *mn[3] = {"median cut", "adaptive", "variance minimisation"};
    static const qibl_lightprobe_method_t mm[3] = {QIBL_LIGHTPROBE_MEDIANCUT, QIBL_LIGHTPROBE_ADAPTIVE,
                                                   QIBL_LIGHTPROBE_VARMIN};
    printf("\nLight-probe sampling workspace (load time), bytes:\n\n");
    printf("| method | 1024 x 512 | 2048 x 1024 | 4096 x 2048 | from |\n|---|---:|---:|---:|---|\n");
    for (int m = 0; m < 3; ++m) {
        printf("| %s |", mn[m]);
        for (int s = 0; s < 3; ++s)
            printf(" %zu |", qibl_lightprobe_workspace_size(pw[s], pw[s] / 2, mm[m]));
        printf(" `qibl_lightprobe_workspace_size` |\n");
    }
    return 0;
}
