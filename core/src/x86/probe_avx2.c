/*
 * x86/probe_avx2.c - core/src/probe.c again as its avx2 copy for run-time dispatch (qibl/isa.h,
 * QIBL_CONFIG_DISPATCH): compiled with -mavx2 (Makefile), reached only when the CPU has AVX2;
 * every external name suffixed _avx2 (x86/rename_internal.h). Built only into the dispatching library.
 */
#define QIBLI_ISA_VARIANT _avx2
#define QIBL_CONFIG_SIMD QIBL_SIMD_AVX2
#include "rename_internal.h"
#include "../probe.c"
