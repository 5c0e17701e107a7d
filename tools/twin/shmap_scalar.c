/*
 * twin/shmap_scalar.c - core/src/shmap.c compiled again as its scalar twin (see shmap_scalar.h):
 * the path forced to QIBL_CONFIG_SIMD=0 and every external name renamed, so it links beside the
 * library's SIMD build. Built with the core's flags (Makefile: $(BUILD)/twin).
 */
#undef QIBL_CONFIG_SIMD
#define QIBL_CONFIG_SIMD 0
#define qibl_shlight_init qtool_shlight_init_scalar
#define qibl_shlight_add_dir qtool_shlight_add_dir_scalar
#define qibl_shmap_check qtool_shmap_check_scalar
#define qibl_shmap_weights qtool_shmap_weights_scalar
#define qibl_shmap_span_workspace_size qtool_shmap_span_workspace_size_scalar
#define qibl_shmap_relight_span qtool_shmap_relight_span_scalar
#define qibl_ylut_values_size qtool_ylut_values_size_scalar
#define qibl_ylut_build qtool_ylut_build_scalar
#define qibl_ylut_check qtool_ylut_check_scalar
#define qibl_ylut_lookup qtool_ylut_lookup_scalar
#define qibl_shmap_point_prepare qtool_shmap_point_prepare_scalar
#define qibl_shmap_point_workspace_size qtool_shmap_point_workspace_size_scalar
#define qibl_shmap_point_span qtool_shmap_point_span_scalar
#include "../../core/src/shmap.c"
