/*
 * twin/shmap_scalar.h - the relight kernels' scalar twin (core/src/shmap.c with QIBL_CONFIG_SIMD=0,
 * names renamed, the core's flags), linked beside the library so that a suite or a benchmark runs
 * the SIMD path and its reference in one process.
 */
#ifndef QTOOL_SHMAP_SCALAR_H
#define QTOOL_SHMAP_SCALAR_H

#include "qibl/shmap.h"

QIBL_NODISCARD qibl_status_t qtool_shmap_point_prepare_scalar(const qibl_shmaps_t *m, const qibl_pmap_t *p, const qibl_ylut_t *lut,
                                               const qibl_pointlight_t *light, qibl_shmap_point_t *out);
QIBL_NODISCARD qibl_status_t qtool_shmap_point_span_scalar(const qibl_shmap_point_t *pt, uint32_t x0, uint32_t y, uint32_t n,
                                            int32_t *out, void *ws, size_t ws_size);
QIBL_NODISCARD qibl_status_t qtool_shmap_relight_span_scalar(const qibl_shmaps_t *m, const qibl_shmap_weights_t *w, uint32_t x0,
                                              uint32_t y, uint32_t n, int32_t *out, void *ws, size_t ws_size);

#endif /* QTOOL_SHMAP_SCALAR_H */
