/*
 * twin/lightprobe_scalar.c - core/src/lightprobe.c compiled again as its scalar twin (see
 * lightprobe_scalar.h): the path forced to QIBL_CONFIG_SIMD=0 and every external name renamed, so
 * it links beside the library's SIMD build. Built with the core's flags (Makefile: $(BUILD)/twin).
 */
#undef QIBL_CONFIG_SIMD
#define QIBL_CONFIG_SIMD 0
#define qibl_lightprobe_build qtool_lightprobe_build_scalar
#define qibl_lightprobe_lights qtool_lightprobe_lights_scalar
#define qibl_lightprobe_workspace_size qtool_lightprobe_workspace_size_scalar
#define qibl_lightprobe_workspace_min qtool_lightprobe_workspace_min_scalar
#define qibl_lightprobe_region_energy qtool_lightprobe_region_energy_scalar
#define qibl_lightprobe_row_weight qtool_lightprobe_row_weight_scalar
#define qibli_lightprobe_pixel_bytes qtool_lightprobe_pixel_bytes_scalar
#define qibli_lightprobe_decode qtool_lightprobe_decode_scalar
#define qibli_lightprobe_sin_frac qtool_lightprobe_sin_frac_scalar
#include "../../core/src/lightprobe.c"
