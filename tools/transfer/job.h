/*
 * transfer/job.h - the per-vertex work of `qibl transfer` (internal to tools/transfer): a vertex's
 * mask from its blockers (every triangle plus the crease wedges, or a hierarchy's or PVS's lists),
 * its transfer vector in world space, its shading, and the ray-cast reference; and the SH light of
 * a probe.
 */
#ifndef QTOOL_TRANSFER_JOB_H
#define QTOOL_TRANSFER_JOB_H

#include <stddef.h>
#include <stdint.h>

#include "io/probe_layout.h"
#include "qibl/hemi.h"
#include "render/rt.h"
#include "transfer/transfer.h"

/* the per-vertex figures of qtool_transfer_job.ph */
enum { QTOOL_PH_TRANSFORM, QTOOL_PH_RASTER, QTOOL_PH_INTEGRATE, QTOOL_PH_OTHER, QTOOL_PH_REF, QTOOL_PH_BLOCKERS,
       QTOOL_PH_RASTERIZED, QTOOL_PH_PVS_CPU, QTOOL_PH_PVS_BLOCKERS, QTOOL_PH_PVS_DIFF, QTOOL_PH_N };

typedef struct qtool_transfer_job {
    const qtool_transfer_mesh *m;
    const qibl_hemi_t *h;
    const qtool_rt_scene *rt;      /* the reference's scene (NULL: no reference) */
    const qibl_q16_t (*pos)[3];
    const int32_t (*nrm)[3];
    const int32_t (*light)[25];
    int side;                      /* side x side reference rays */
    qibl_q30_t (*vw)[25];          /* world transfer */
    qibl_q16_t (*e)[3];            /* qibl's shading, Q16.16 */
    double *eq;                    /* qibl shading, 3 per vertex */
    double *er;                    /* reference shading */
    double *l2, *noise;            /* per vertex */
    double *cpu;                   /* per vertex hemi CPU seconds */
    double *ph;                    /* per vertex QTOOL_PH_N: the split of cpu, reference CPU, blockers, ... */
    const uint32_t *adj_off, *adj; /* triangles around each vertex (CSR) */
    int crease;                    /* the solid behind the faces around each vertex blocks */
    const qtool_transfer_hier *hi; /* with a hierarchy: each vertex's vertices and blockers (NULL: every triangle) */
    const qtool_transfer_hier *pvs; /* the same vertex again from its PVS, timed, masks compared (NULL: not) */
} qtool_transfer_job;

/* One vertex of the job (a qtool_rt_parallel row function). */
void qtool_transfer_vertex_job(void *ctx, uint32_t v);

/* The thread CPU seconds of the hemi work of every vertex of the job's frame (frame, mask,
 * transfer, world, shade: what the job times per vertex, without its clocks), as one block on the
 * calling thread: from the PVS lists if pvs (the job must have them), else from every triangle or
 * the hierarchy as the job does. Writes nothing of the job's; -1 if out of memory. */
double qtool_transfer_frame_block(const qtool_transfer_job *j, int pvs);

/* The probe's radiance SH (bands 0..4) as Q16.16, scaled so the largest |coefficient| is in
 * [1/4, 1/2); with nlights > 0, its median-cut lights projected to SH instead. desc: its size and
 * layout. 0, or -1 with a one-line reason in err. */
int qtool_transfer_probe_light(const char *path, qtool_probe_layout_t layout, int nlights, int32_t light[3][25],
                               char *desc, size_t dlen, char *err, size_t errlen);

#endif
