/*
 * x86/srgbe_scalar.c - core/src/srgbe.c again as its scalar copy for run-time dispatch (qibl/isa.h,
 * QIBL_CONFIG_DISPATCH): the portable C kernels (QIBL_CONFIG_SIMD 0), the reference every path equals;
 * every external name suffixed _scalar (x86/rename_internal.h). Built only into the dispatching library.
 */
#define QIBLI_ISA_VARIANT _scalar
#define QIBL_CONFIG_SIMD QIBL_SIMD_SCALAR
#include "rename_internal.h"
#include "../srgbe.c"
