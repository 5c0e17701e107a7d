/*
 * qibl/isa.h - which vector kernels this build carries and which one its calls use.
 *
 * Freestanding targets select their kernels at compile time (config.h's QIBL_CONFIG_SIMD): one
 * path, reported here as it is. A hosted x86-64 build with QIBL_CONFIG_DISPATCH=1 (the Makefile's
 * default library there) carries three copies of the SIMD modules (shmap, srgbe, probe, lightprobe,
 * hemi): the scalar C twin, SSE2 and AVX2, and every call into their kernels picks one from the
 * CPU: AVX-512 (F, BW, VL, CD, VNNI) where the CPU and the OS have it, else AVX2, else SSE2. The
 * AVX-512 choice runs a fourth copy where one gains (shmap's point lights and interleaved
 * directional groups, probe's projection fold, srgbe's bulk encode and decode: 16 lanes a step) and
 * the AVX2 copy elsewhere. Every choice gives the same bytes (the goldens and the suites run under each).
 *
 * No state in the core: the CPU's features come from the compiler runtime's own record of cpuid
 * (libgcc/compiler-rt __builtin_cpu_supports, filled once before main; a cpuid instruction per
 * call would cost a trap under a hypervisor that traps it). An application that wants to
 * restrict the choice (tests, benches: QIBL_ISA in the tools) defines qibl_isa_allowed() below;
 * the core only calls it, it never reads the environment.
 */
#ifndef QIBL_ISA_H
#define QIBL_ISA_H

#include <stdint.h>
#include "qibl/config.h"

#ifdef __cplusplus
extern "C" {
#endif

/* the kernel sets, numbered as config.h's QIBL_SIMD_* */
#define QIBL_ISA_LIST(X) /* X(name, value, label): the enum and qibl_isa_name's labels */                  \
    X(QIBL_ISA_SCALAR, QIBL_SIMD_SCALAR, "scalar") /* portable C (the reference every path equals) */      \
    X(QIBL_ISA_SSE2, QIBL_SIMD_SSE2, "sse2")                                                               \
    X(QIBL_ISA_AVX2, QIBL_SIMD_AVX2, "avx2")                                                               \
    X(QIBL_ISA_NEON, QIBL_SIMD_NEON, "neon")                                                               \
    X(QIBL_ISA_AVX512, QIBL_SIMD_AVX512, "avx512") /* AVX2 kernels plus 16-lane shmap, probe, srgbe */

typedef enum qibl_isa {
#define QIBL_ISA_ENUM_(name, value, label) name = value,
    QIBL_ISA_LIST(QIBL_ISA_ENUM_)
#undef QIBL_ISA_ENUM_
    QIBL_ISA_COUNT /* number of kernel sets (5); not a set */
} qibl_isa_t;

#define QIBL_ISA_BIT(isa) (1u << (unsigned)(isa))

/* Bit QIBL_ISA_BIT(i) set for every kernel set this build carries and this CPU runs: on a
 * dispatching build scalar | SSE2, | AVX2 | AVX512 where the CPU and OS have them; elsewhere the one
 * QIBL_CONFIG_SIMD path. Never 0. */
uint32_t qibl_isa_available(void);

/* The kernel set calls use now: the highest bit of qibl_isa_available() & qibl_isa_allowed()
 * (or of qibl_isa_available() alone when the application defines no qibl_isa_allowed, or when
 * the two masks share no bit: the core never runs code the CPU lacks). */
qibl_isa_t qibl_isa_active(void);

/* "scalar", "sse2", "avx2", "neon", "avx512"; "?" for any other value. */
const char *qibl_isa_name(qibl_isa_t isa);

/* 1 if this build picks its kernels at run time (QIBL_CONFIG_DISPATCH), 0 if at compile time. */
int qibl_isa_dispatches(void);

/* Optional, defined by the application (a weak reference in the core; not defined by qibl): the
 * mask of kernel sets it allows. Called on every dispatched call, so it must be cheap and
 * thread-safe (the tools read QIBL_ISA once). Only dispatching builds call it. */
uint32_t qibl_isa_allowed(void);

#ifdef __cplusplus
}
#endif

#endif /* QIBL_ISA_H */
