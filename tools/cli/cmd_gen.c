/*
 * cmd_gen.c - `qibl gen`: the procedural courtyard's SH maps (analytic, no shadows), packed to 8
 * bits, written as an asset with its P map and an optional cube-map Y LUT.
 */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/bake.h"
#include "gen/scene.h"
#include "io/asset_write.h"
#include "qibl/asset.h"
#include "qibl/shmap.h"
#include "qibl/shmaps.h"
#include "cli/cli.h"
#include "opt/opt.h"

typedef struct gen_opts {
    const char *out;
    long size[2], k, lut;
    int pack, layout, equirect;
} gen_opts;
static const gen_opts gen_defaults = {.out = NULL, .size = {1024, 256}, .k = 16, .lut = 0, .pack = 0, .layout = 0};

/* the enums' names, in the order of the values they stand for */
static const char *const packs[] = {"minmax", "robust", NULL};
static const qtool_pack_scheme pack_schemes[] = {QTOOL_PACK_MINMAX, QTOOL_PACK_ROBUST};
static const char *const layouts[] = {"planar", "interleaved", NULL};
static const uint32_t layout_values[] = {QIBL_SHMAPS_PLANAR, QIBL_SHMAPS_INTERLEAVED};

static const qtool_opt gen_table[] = {
    {.name = "-o", .kind = QTOOL_OPT_STR, .off = offsetof(gen_opts, out), .arg = "FILE", .required = 1,
     .help = "the asset to write"},
    {.name = "--size", .kind = QTOOL_OPT_SIZE, .off = offsetof(gen_opts, size), .hi = 16384,
     .help = "the panorama's width x height, within an asset's pixel limit (qibl/asset.h)"},
    {.name = "--k", .kind = QTOOL_OPT_INT, .off = offsetof(gen_opts, k), .arg = "K", .lo = 1, .hi = 25,
     .help = "the number of SH maps (terms of bands 0..4)"},
    QCLI_LUT_SIZE_OPTS(gen_opts, lut),
    {.name = "--pack", .kind = QTOOL_OPT_ENUM, .off = offsetof(gen_opts, pack), .names = packs,
     .help = "8 bits per map and channel over min/max or the 0.1..99.9 percentile range"},
    {.name = "--equirect", .kind = QTOOL_OPT_FLAG, .off = offsetof(gen_opts, equirect),
     .help = "an equirectangular panorama instead of the cylindrical one"},
    {.name = "--layout", .kind = QTOOL_OPT_ENUM, .off = offsetof(gen_opts, layout), .names = layouts,
     .help = "the maps' byte order in the asset"},
    {0},
};

static const qtool_opt_cmd gen_spec = {
    .name = "gen",
    QTOOL_OPT_TABLE(gen_table, gen_defaults),
    .prose =
        "  Renders the built-in courtyard's light-transport SH maps analytically (Lambert + glossy, no\n"
        "  shadows; the ray-traced bake is a separate command), packs them to 8 bits per map and channel\n"
        "  and writes SHMP + PMAP (+ YLUT with --lut-size N, the cube-map face size).\n"
        "  --layout interleaved: the maps' bytes row by row in groups of 16 pixels (rows stream from disc\n"
        "  one at a time; relights to the same bytes as the default planar layout).\n",
};

static int gen_check(void *opts)
{
    const gen_opts *o = opts;
    if (o->size[0] * o->size[1] > (long)QIBL_ASSET_MAX_PIXELS)
        return qtool_opt_error(&gen_spec, "--size %ldx%ld is above the asset's %u pixels", o->size[0], o->size[1],
                              QIBL_ASSET_MAX_PIXELS);
    return 0;
}

static int gen_run(void *opts)
{
    const gen_opts *o = opts;
    const char *out = o->out;
    long w = o->size[0], h = o->size[1], k = o->k, lut = o->lut;
    uint32_t layout = layout_values[o->layout];
    qtool_pack_scheme scheme = pack_schemes[o->pack];
    qtool_pano_kind kind = o->equirect ? QTOOL_PANO_EQUIRECT : QTOOL_PANO_CYLINDRICAL;
    qtool_gen_maps g;
    if (qtool_gen_scene((uint32_t)w, (uint32_t)h, (uint32_t)k, kind, &g) != 0) {
        fprintf(stderr, "qibl: gen: out of memory\n");
        return 1;
    }
    size_t np = (size_t)w * (size_t)h, nplanes = (size_t)k * 3;
    int32_t *scale = malloc(sizeof(int32_t) * nplanes), *bias = malloc(sizeof(int32_t) * nplanes);
    uint8_t *planes = malloc(np * nplanes);
    int16_t *lutv = NULL;
    qtool_asset_builder b;
    qtool_asset_builder_init(&b);
    int rc = 1;
    qtool_pack_stats st;
    if (!scale || !bias || !planes || qtool_pack_maps(&g, scheme, scale, bias, planes, &st) != 0) {
        fprintf(stderr, "qibl: gen: out of memory\n");
        goto done;
    }
    if (qtool_asset_add_shmp_layout(&b, (uint32_t)w, (uint32_t)h, (uint32_t)k, 3, scale, bias, planes, layout) != 0 ||
        qtool_asset_add_pmap(&b, (uint32_t)w, (uint32_t)h, g.p) != 0) {
        fprintf(stderr, "qibl: gen: %s\n", b.err);
        goto done;
    }
    if (lut) {
        size_t vs = qibl_ylut_values_size((uint32_t)lut, (uint32_t)k);
        uint8_t *le = malloc(vs);
        lutv = malloc(vs);
        if (!le || !lutv || qibl_ylut_build((uint32_t)lut, (uint32_t)k, le, vs) != QIBL_OK) {
            free(le);
            fprintf(stderr, "qibl: gen: out of memory\n");
            goto done;
        }
        for (size_t i = 0; i < vs / 2; ++i)
            lutv[i] = qibl_load_s16le(le + 2 * i);
        free(le);
        if (qtool_asset_add_ylut(&b, (uint32_t)lut, (uint32_t)k, lutv) != 0) {
            fprintf(stderr, "qibl: gen: %s\n", b.err);
            goto done;
        }
    }
    if (qtool_asset_write_file(&b, out, 1) != 0) {
        fprintf(stderr, "qibl: %s\n", b.err);
        goto done;
    }
    printf("wrote %s: %ldx%ld %s courtyard, k = %ld, %s layout, packing %s (rms %.3e, max %.3e, %llu clipped)%s\n", out, w, h,
           kind == QTOOL_PANO_CYLINDRICAL ? "cylindrical" : "equirectangular", k,
           layout == QIBL_SHMAPS_INTERLEAVED ? "interleaved" : "planar", scheme == QTOOL_PACK_MINMAX ? "min/max" : "robust", st.rms, st.max_abs, (unsigned long long)st.clipped,
           lut ? ", with cube-map Y LUT" : "");
    rc = 0;
done:
    qtool_asset_builder_free(&b);
    free(scale), free(bias), free(planes), free(lutv);
    qtool_gen_free(&g);
    return rc;
}

const qcli_sub qcli_sub_gen = {.opts = &gen_spec, .check = gen_check, .run = gen_run};
