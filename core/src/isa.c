/*
 * isa.c - the kernel set of this build and of this call (qibl/isa.h).
 *
 * Dispatching builds (QIBL_CONFIG_DISPATCH, hosted x86-64 with GCC or Clang only): the CPU's
 * features from __builtin_cpu_supports, which reads the compiler runtime's record of cpuid (made
 * once before main, read-only after: a load and a test per call), masked by the application's
 * optional qibl_isa_allowed(). Everywhere else: the one compile-time path, no code beyond a constant.
 */
#include "qibl/isa.h"
#include "qibli.h"

#if QIBL_CONFIG_DISPATCH
/* a weak reference: 0 when the application does not define it (no state of the core's own) */
extern uint32_t qibl_isa_allowed(void) __attribute__((weak));
#endif

uint32_t qibl_isa_available(void)
{
#if QIBL_CONFIG_DISPATCH
    uint32_t m = QIBL_ISA_BIT(QIBL_ISA_SCALAR) | QIBL_ISA_BIT(QIBL_ISA_SSE2);
    if (__builtin_cpu_supports("avx2"))
        m |= QIBL_ISA_BIT(QIBL_ISA_AVX2);
    /* every feature the AVX-512 copy uses (its -m flags in the Makefile); the runtime's record
     * also checks that the OS saves the zmm and mask registers */
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
        __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512cd") &&
        __builtin_cpu_supports("avx512vnni"))
        m |= QIBL_ISA_BIT(QIBL_ISA_AVX512);
    return m;
#else
    return QIBL_ISA_BIT(QIBL_CONFIG_SIMD);
#endif
}

qibl_isa_t qibl_isa_active(void)
{
#if QIBL_CONFIG_DISPATCH
    const uint32_t have = qibl_isa_available();
    const uint32_t allow = qibl_isa_allowed != 0 ? qibl_isa_allowed() : have;
    const uint32_t m = (have & allow) != 0u ? have & allow : have;
    if (m & QIBL_ISA_BIT(QIBL_ISA_AVX512))
        return QIBL_ISA_AVX512;
    if (m & QIBL_ISA_BIT(QIBL_ISA_AVX2))
        return QIBL_ISA_AVX2;
    if (m & QIBL_ISA_BIT(QIBL_ISA_SSE2))
        return QIBL_ISA_SSE2;
    return QIBL_ISA_SCALAR;
#else
    return (qibl_isa_t)QIBL_CONFIG_SIMD;
#endif
}

const char *qibl_isa_name(qibl_isa_t isa)
{
    switch (isa) {
#define QIBL_ISA_CASE_(name, value, label) case name: return label;
    QIBL_ISA_LIST(QIBL_ISA_CASE_)
#undef QIBL_ISA_CASE_
    case QIBL_ISA_COUNT:
        break;
    }
    return "?";
}

int qibl_isa_dispatches(void)
{
    return QIBL_CONFIG_DISPATCH;
}
