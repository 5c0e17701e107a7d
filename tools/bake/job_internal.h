/*
 * bake/job_internal.h - what bake_job.c and merge.c share inside tools/bake (not an API).
 */
#ifndef QTOOL_BAKE_JOB_INTERNAL_H
#define QTOOL_BAKE_JOB_INTERNAL_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "bake/bake.h"

/* what an asset carries beside the shadowed maps: unshadowed maps (SHMU), light paths (LPTH) and
 * lamp occlusion (LOCC) */
typedef struct qtool_bake_asset_extras {
    const qtool_gen_maps *mu; /* NULL: none */
    uint8_t *paths[9];        /* NULL-terminated */
    size_t sizes[9];
    int npaths;
    uint8_t *locc; /* NULL: none */
    size_t locc_n;
} qtool_bake_asset_extras;

/* SUMS.u (the unshadowed partial sums) and SUMS.x (the extras file) beside a partial-sums file */
void qtool_bake_side_name(char *buf, size_t n, const char *sums, const char *ext);

/* Projects sums (k maps, LUT face lut), builds the asset with x and writes it to out; the "wrote"
 * line on rep. 0, or -1 with err set (errlen >= 1200 for an I/O reason). */
int qtool_bake_finish_asset(const qtool_bake_sums *sums, uint32_t k, uint32_t lut, qtool_proj_method method,
                             uint32_t layout, const char *out, const qtool_bake_asset_extras *x, FILE *rep, char *err,
                             size_t errlen);

#endif
