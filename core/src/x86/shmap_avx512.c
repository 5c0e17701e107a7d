/*
 * x86/shmap_avx512.c - core/src/shmap.c again as its avx512 copy for run-time dispatch (qibl/isa.h,
 * QIBL_CONFIG_DISPATCH): the AVX2 kernels plus the 16-lane point-light kernel and the vpdpbusd
 * directional kernel for whole interleaved groups (QIBLI_SHMAP_AVX512), compiled with -mavx2 and AVX-512 F, BW, VL, CD, VNNI (Makefile), reached only when the CPU has
 * them all (isa.c); every external name suffixed _avx512 (x86/rename_internal.h). Built only into
 * the dispatching library.
 */
#define QIBLI_ISA_VARIANT _avx512
#define QIBL_CONFIG_SIMD QIBL_SIMD_AVX2
#define QIBLI_SHMAP_AVX512 1
#include "rename_internal.h"
#include "../shmap.c"
