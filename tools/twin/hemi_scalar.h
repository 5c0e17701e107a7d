/*
 * twin/hemi_scalar.h - the hemispherical rasterizer's scalar twin (core/src/hemi.c with
 * QIBL_CONFIG_SIMD=0, names renamed, the core's flags), linked beside the library so that a suite
 * or a benchmark runs the x86 lanes and the integer look-ups in one process. A qibl_hemi_t
 * made by qibl_hemi_init or qibl_hemi_open (core/src/hemi_tables.c, not twinned: no lanes) serves
 * both.
 */
#ifndef QTOOL_HEMI_SCALAR_H
#define QTOOL_HEMI_SCALAR_H

#include "qibl/hemi.h"

QIBL_NODISCARD qibl_status_t qtool_hemi_raster_scalar(const qibl_hemi_t *h, const int32_t (*v)[3], uint32_t nv,
                                       const uint32_t (*tri)[3], uint32_t ntri, uint32_t *mask,
                                       qibl_hemi_stats_t *stats);
/* the transform's twin (compared with the library's under every dispatch choice) */
QIBL_NODISCARD qibl_status_t qtool_hemi_transform_scalar(const qibl_hemi_frame_t *f, const qibl_q16_t (*pos)[3],
                                                        uint32_t count, int32_t (*out)[3]);

#endif /* QTOOL_HEMI_SCALAR_H */
