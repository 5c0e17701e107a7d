/*
 * x86/rename_internal.h - every external name of the SIMD modules (shmap, srgbe, probe, lightprobe, hemi)
 * with the suffix QIBLI_ISA_VARIANT (_avx2, _avx512, _scalar), so that their copies link beside the library's
 * own (SSE2) build and call each other. Included by core/src/x86/<module>_<isa>.c before the
 * module's source; a new public function of those modules must be added here (a missing one is a
 * duplicate symbol at link time, never a silent mix).
 */
#ifndef QIBLI_X86_RENAME_H
#define QIBLI_X86_RENAME_H

#define QIBLI_ISA_CAT_(a, b) a##b
#define QIBLI_ISA_CAT(a, b) QIBLI_ISA_CAT_(a, b)
#define QIBLI_ISA_NAME(n) QIBLI_ISA_CAT(n, QIBLI_ISA_VARIANT)

/* shmap.c */
#define qibl_shlight_add_dir QIBLI_ISA_NAME(qibl_shlight_add_dir)
#define qibl_shlight_init QIBLI_ISA_NAME(qibl_shlight_init)
#define qibl_shmap_check QIBLI_ISA_NAME(qibl_shmap_check)
#define qibl_shmap_point_prepare QIBLI_ISA_NAME(qibl_shmap_point_prepare)
#define qibl_shmap_point_span QIBLI_ISA_NAME(qibl_shmap_point_span)
#define qibl_shmap_point_workspace_size QIBLI_ISA_NAME(qibl_shmap_point_workspace_size)
#define qibl_shmap_relight_span QIBLI_ISA_NAME(qibl_shmap_relight_span)
#define qibl_shmap_span_workspace_size QIBLI_ISA_NAME(qibl_shmap_span_workspace_size)
#define qibl_shmap_weights QIBLI_ISA_NAME(qibl_shmap_weights)
#define qibl_ylut_build QIBLI_ISA_NAME(qibl_ylut_build)
#define qibl_ylut_check QIBLI_ISA_NAME(qibl_ylut_check)
#define qibl_ylut_lookup QIBLI_ISA_NAME(qibl_ylut_lookup)
#define qibl_ylut_values_size QIBLI_ISA_NAME(qibl_ylut_values_size)

/* srgbe.c */
#define qibl_srgbe_decode_f32 QIBLI_ISA_NAME(qibl_srgbe_decode_f32)
#define qibl_srgbe_decode_f32_n QIBLI_ISA_NAME(qibl_srgbe_decode_f32_n)
#define qibl_srgbe_decode_q16 QIBLI_ISA_NAME(qibl_srgbe_decode_q16)
#define qibl_srgbe_decode_q16_n QIBLI_ISA_NAME(qibl_srgbe_decode_q16_n)
#define qibl_srgbe_decode_s32 QIBLI_ISA_NAME(qibl_srgbe_decode_s32)
#define qibl_srgbe_decode_s32_n QIBLI_ISA_NAME(qibl_srgbe_decode_s32_n)
#define qibl_srgbe_encode_f32 QIBLI_ISA_NAME(qibl_srgbe_encode_f32)
#define qibl_srgbe_encode_f32_n QIBLI_ISA_NAME(qibl_srgbe_encode_f32_n)
#define qibl_srgbe_encode_q16 QIBLI_ISA_NAME(qibl_srgbe_encode_q16)
#define qibl_srgbe_encode_q16_n QIBLI_ISA_NAME(qibl_srgbe_encode_q16_n)
#define qibl_srgbe_encode_s32 QIBLI_ISA_NAME(qibl_srgbe_encode_s32)
#define qibl_srgbe_encode_s32_n QIBLI_ISA_NAME(qibl_srgbe_encode_s32_n)

/* probe.c */
#define qibl_probe_sh_add_row QIBLI_ISA_NAME(qibl_probe_sh_add_row)
#define qibl_probe_sh_begin QIBLI_ISA_NAME(qibl_probe_sh_begin)
#define qibl_probe_sh_finish QIBLI_ISA_NAME(qibl_probe_sh_finish)
#define qibl_probe_sh_project QIBLI_ISA_NAME(qibl_probe_sh_project)
#define qibl_probe_sh_workspace_size QIBLI_ISA_NAME(qibl_probe_sh_workspace_size)
#define qibl_shlight_add_coeffs QIBLI_ISA_NAME(qibl_shlight_add_coeffs)
#define qibl_shlight_add_lights QIBLI_ISA_NAME(qibl_shlight_add_lights)
#define qibl_shlight_add_probe QIBLI_ISA_NAME(qibl_shlight_add_probe)
#define qibl_shlight_add_sun_sky QIBLI_ISA_NAME(qibl_shlight_add_sun_sky)
#define qibl_shlight_rotate QIBLI_ISA_NAME(qibl_shlight_rotate)

/* lightprobe.c */
#define qibl_lightprobe_build QIBLI_ISA_NAME(qibl_lightprobe_build)
#define qibl_lightprobe_lights QIBLI_ISA_NAME(qibl_lightprobe_lights)
#define qibl_lightprobe_region_energy QIBLI_ISA_NAME(qibl_lightprobe_region_energy)
#define qibl_lightprobe_row_weight QIBLI_ISA_NAME(qibl_lightprobe_row_weight)
#define qibl_lightprobe_workspace_size QIBLI_ISA_NAME(qibl_lightprobe_workspace_size)
#define qibl_lightprobe_workspace_min QIBLI_ISA_NAME(qibl_lightprobe_workspace_min)
#define qibli_lightprobe_decode QIBLI_ISA_NAME(qibli_lightprobe_decode)
#define qibli_lightprobe_pixel_bytes QIBLI_ISA_NAME(qibli_lightprobe_pixel_bytes)
#define qibli_lightprobe_sin_frac QIBLI_ISA_NAME(qibli_lightprobe_sin_frac)

/* hemi.c */
#define qibl_hemi_bound_above QIBLI_ISA_NAME(qibl_hemi_bound_above)
#define qibl_hemi_bound_cull QIBLI_ISA_NAME(qibl_hemi_bound_cull)
#define qibl_hemi_bound_fit QIBLI_ISA_NAME(qibl_hemi_bound_fit)
#define qibl_hemi_bound_near QIBLI_ISA_NAME(qibl_hemi_bound_near)
#define qibl_hemi_clear QIBLI_ISA_NAME(qibl_hemi_clear)
#define qibl_hemi_clip QIBLI_ISA_NAME(qibl_hemi_clip)
#define qibl_hemi_frame_init QIBLI_ISA_NAME(qibl_hemi_frame_init)
#define qibl_hemi_raster QIBLI_ISA_NAME(qibl_hemi_raster)
#define qibl_hemi_shade QIBLI_ISA_NAME(qibl_hemi_shade)
#define qibl_hemi_to_frame QIBLI_ISA_NAME(qibl_hemi_to_frame)
#define qibl_hemi_to_world QIBLI_ISA_NAME(qibl_hemi_to_world)
#define qibl_hemi_transfer QIBLI_ISA_NAME(qibl_hemi_transfer)
#define qibl_hemi_transfer_phong QIBLI_ISA_NAME(qibl_hemi_transfer_phong)
#define qibl_hemi_transform QIBLI_ISA_NAME(qibl_hemi_transform)

#endif /* QIBLI_X86_RENAME_H */
