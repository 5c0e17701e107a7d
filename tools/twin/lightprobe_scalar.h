/*
 * twin/lightprobe_scalar.h - the light-probe module's scalar twin, linked beside the library, so a
 * benchmark or a test can run the SIMD path (the library) and the scalar reference in one process.
 * Built from core/src/lightprobe.c itself with QIBL_CONFIG_SIMD=0 and the core's own flags
 * (tools/twin/lightprobe_scalar.c): the same source, the same compiler options, only the path differs.
 */
#ifndef QTOOL_LIGHTPROBE_SCALAR_H
#define QTOOL_LIGHTPROBE_SCALAR_H

#include "qibl/lightprobe.h"

QIBL_NODISCARD qibl_status_t qtool_lightprobe_build_scalar(qibl_lightprobe_t *lp, const qibl_lightprobe_image_t *img,
                                            qibl_lightprobe_method_t method, void *workspace, size_t workspace_size);
QIBL_NODISCARD qibl_status_t qtool_lightprobe_lights_scalar(const qibl_lightprobe_t *lp, const qibl_lightprobe_opts_t *opts,
                                             qibl_lightprobe_light_t *lights, uint32_t max_lights,
                                             qibl_lightprobe_result_t *result);

#endif /* QTOOL_LIGHTPROBE_SCALAR_H */
