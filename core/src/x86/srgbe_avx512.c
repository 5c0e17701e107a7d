/*
 * x86/srgbe_avx512.c - core/src/srgbe.c again as its avx512 copy for run-time dispatch (qibl/isa.h,
 * QIBL_CONFIG_DISPATCH): the AVX2 kernels plus the 16-lane bulk binary32 encoder (QIBLI_SRGBE_AVX512),
 * compiled with -mavx2 and AVX-512 F, BW, VL, CD, VNNI (Makefile), reached only when the CPU has them
 * all (isa.c); every external name suffixed _avx512 (x86/rename_internal.h). Built only into the
 * dispatching library.
 */
#define QIBLI_ISA_VARIANT _avx512
#define QIBL_CONFIG_SIMD QIBL_SIMD_AVX2
#define QIBLI_SRGBE_AVX512 1
#include "rename_internal.h"
#include "../srgbe.c"
