/*
 * x86/probe_avx512.c - core/src/probe.c again as its avx512 copy for run-time dispatch (qibl/isa.h,
 * QIBL_CONFIG_DISPATCH): the AVX2 kernels plus the 16-lane RGBE fold with the conversion fused
 * (QIBLI_PROBE_AVX512), compiled with -mavx2 and AVX-512 F, BW, VL, CD, VNNI (Makefile), reached only
 * when the CPU has them all (isa.c); every external name suffixed _avx512 (x86/rename_internal.h).
 * Built only into the dispatching library.
 */
#define QIBLI_ISA_VARIANT _avx512
#define QIBL_CONFIG_SIMD QIBL_SIMD_AVX2
#define QIBLI_PROBE_AVX512 1
#include "rename_internal.h"
/* lightprobe.c has no avx512 copy: the row decoding and sines it shares come from its avx2 one */
#undef qibli_lightprobe_decode
#undef qibli_lightprobe_pixel_bytes
#undef qibli_lightprobe_sin_frac
#define qibli_lightprobe_decode qibli_lightprobe_decode_avx2
#define qibli_lightprobe_pixel_bytes qibli_lightprobe_pixel_bytes_avx2
#define qibli_lightprobe_sin_frac qibli_lightprobe_sin_frac_avx2
#include "../probe.c"
