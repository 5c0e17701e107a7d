/*
 * twin/hemi_scalar.c - core/src/hemi.c compiled again as its scalar twin (see hemi_scalar.h): the
 * rasterizer's integer setup and look-ups instead of the x86 lanes (QIBL_CONFIG_SIMD=0), every
 * external name renamed, so it links beside the library. Built with the core's flags (Makefile:
 * $(BUILD)/twin).
 */
#undef QIBL_CONFIG_SIMD
#define QIBL_CONFIG_SIMD 0
#define qibl_hemi_frame_init qtool_hemi_frame_init_scalar
#define qibl_hemi_transform qtool_hemi_transform_scalar
#define qibl_hemi_clear qtool_hemi_clear_scalar
#define qibl_hemi_clip qtool_hemi_clip_scalar
#define qibl_hemi_bound_fit qtool_hemi_bound_fit_scalar
#define qibl_hemi_bound_above qtool_hemi_bound_above_scalar
#define qibl_hemi_bound_cull qtool_hemi_bound_cull_scalar
#define qibl_hemi_bound_near qtool_hemi_bound_near_scalar
#define qibl_hemi_raster qtool_hemi_raster_scalar
#define qibl_hemi_transfer qtool_hemi_transfer_scalar
#define qibl_hemi_transfer_phong qtool_hemi_transfer_phong_scalar
#define qibl_hemi_to_world qtool_hemi_to_world_scalar
#define qibl_hemi_to_frame qtool_hemi_to_frame_scalar
#define qibl_hemi_shade qtool_hemi_shade_scalar
#include "../../core/src/hemi.c"
