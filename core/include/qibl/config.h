/*
 * qibl/config.h - compile-time options: which modules are built and how big their tables are.
 *
 * Every option has a default here; override with -D on the compiler command line. Each option
 * states what it costs so a port can model only what its scenes need.
 */
#ifndef QIBL_CONFIG_H
#define QIBL_CONFIG_H

/* QIBL_CONFIG_SMALL: 1 makes the modules a microcontroller rarely runs at run time opt-in: light-probe
 * sampling (QIBL_USE_LIGHTPROBE, and with it QIBL_USE_PROBE), hemispherical rasterization
 * (QIBL_USE_HEMI), light paths (QIBL_USE_LIGHTPATH) and goniometric lamps (QIBL_USE_GONIO) default
 * to 0; each can still be set to 1.
 * What stays is runtime relighting: the asset reader, SH, sRGBE, directional and point-light spans,
 * both map layouts (its .text on Cortex-M4 -Os, against the goal of 16 KiB, and that of every module
 * are in docs/porting.md's size table, which `make cross` checks). Default 1 on ARM M-profile targets (Cortex-M: the compiler
 * defines __ARM_ARCH_PROFILE 'M'), 0 elsewhere. It only changes defaults, so QIBL_CONFIG_ID
 * (version.h) records the modules it leaves out, not this option. */
#ifndef QIBL_CONFIG_SMALL
#if defined(__ARM_ARCH_PROFILE) && __ARM_ARCH_PROFILE == 'M'
#define QIBL_CONFIG_SMALL 1
#else
#define QIBL_CONFIG_SMALL 0
#endif
#endif

/* QIBL_USE_SH: 1 builds the SH basis module (sh.c: basis and rotation; .text and .rodata (the
 * rotation's sample table) per module: docs/porting.md's size table, checked by `make cross`). */
#ifndef QIBL_USE_SH
#define QIBL_USE_SH 1
#endif

/* QIBL_USE_SRGBE: 1 builds the sRGBE signed shared-exponent colour codec (srgbe.c; .text in
 * docs/porting.md's size table, a 1 KiB .rodata table for the binary32 decode, no RAM). */
#ifndef QIBL_USE_SRGBE
#define QIBL_USE_SRGBE 1
#endif

/* QIBL_USE_ASSET: 1 builds the asset container reader (asset.c: validation, CRC-32, chunk views;
 * .text in docs/porting.md's size table, no RAM beyond the caller's structs).
 * The views and little-endian load helpers of shmaps.h stay available either way. */
#ifndef QIBL_USE_ASSET
#define QIBL_USE_ASSET 1
#endif

/* QIBL_USE_LIGHTPROBE: 1 builds light-probe sampling (lightprobe.c: SATs, median cut, adaptive
 * median cut, variance minimisation; .text in docs/porting.md's size table, no RAM beyond the caller's
 * workspace: 8 bytes per probe pixel, 48 with the variance tables). Default 1, 0 with QIBL_CONFIG_SMALL. */
#ifndef QIBL_USE_LIGHTPROBE
#define QIBL_USE_LIGHTPROBE (!QIBL_CONFIG_SMALL)
#endif

/* QIBL_USE_SHMAP: 1 builds the relighting kernels (shmap.c: weights, directional/environment and
 * point-light spans, cube-map LUTs; .text in docs/porting.md's size table, most of it for point
 * lights). Needs QIBL_USE_SH, not QIBL_USE_ASSET: the views it reads (shmaps.h, shmaps.c) are built
 * with either module, so a game that builds or streams its maps itself leaves the parser out.
 * `make cross` prints every module's size and those of combinations. */
#ifndef QIBL_USE_SHMAP
#define QIBL_USE_SHMAP 1
#endif
#if QIBL_USE_SHMAP && !QIBL_USE_SH
#error "QIBL_USE_SHMAP needs QIBL_USE_SH"
#endif

/* QIBL_USE_LIGHTPATH: 1 builds light paths (lightpath.c: LPTH chunk validation, per-pixel
 * visibility spans, key interpolation; .text in docs/porting.md's size table, no RAM). Needs
 * QIBL_USE_SHMAP (path lights are relit through the SH maps); by default on when that is, unless
 * QIBL_CONFIG_SMALL. */
#ifndef QIBL_USE_LIGHTPATH
#define QIBL_USE_LIGHTPATH (QIBL_USE_SHMAP && !QIBL_CONFIG_SMALL)
#endif
#if QIBL_USE_LIGHTPATH && !QIBL_USE_SHMAP
#error "QIBL_USE_LIGHTPATH needs QIBL_USE_SHMAP"
#endif

/* QIBL_USE_GONIO: 1 builds goniometric lamps (gonio.c: the octahedral intensity table's lookup and
 * the per-span scale after a point light; .text in docs/porting.md's size table, no RAM; the table is
 * the caller's, 2 n^2 bytes). Needs QIBL_USE_SHMAP (it scales point-light spans through the P map);
 * by default on when that is, unless QIBL_CONFIG_SMALL. */
#ifndef QIBL_USE_GONIO
#define QIBL_USE_GONIO (QIBL_USE_SHMAP && !QIBL_CONFIG_SMALL)
#endif
#if QIBL_USE_GONIO && !QIBL_USE_SHMAP
#error "QIBL_USE_GONIO needs QIBL_USE_SHMAP"
#endif

/* QIBL_USE_INTERLEAVED: 1 builds the interleaved SH-map layout (shmaps.h): its relight and
 * point-light paths in shmap.c, qibl_shmaps_interleave, and streaming by rows in asset.c
 * (qibl_asset_head_size, _open_head, _row); .text in docs/porting.md's size table, no RAM. 0: planar
 * maps only; an interleaved view is QIBL_E_SHMAP_LAYOUT and an interleaved asset
 * QIBL_E_ASSET_BAD_FLAGS, as for a reader that predates the layout. */
#ifndef QIBL_USE_INTERLEAVED
#define QIBL_USE_INTERLEAVED 1
#endif

/* QIBL_USE_PROBE: 1 builds the SH projection of light probes (probe.c: row-by-row projection into
 * exact wide accumulators, irradiance and windows, lights and sun-plus-sky into a qibl_shlight_t;
 * .text in docs/porting.md's size table, no RAM beyond the caller's workspace:
 * qibl_probe_sh_workspace_size, probe.h). Needs QIBL_USE_SH and QIBL_USE_LIGHTPROBE (pixel decoding); by default on when
 * both are. */
#ifndef QIBL_USE_PROBE
#define QIBL_USE_PROBE (QIBL_USE_SH && QIBL_USE_LIGHTPROBE)
#endif
#if QIBL_USE_PROBE && (!QIBL_USE_SH || !QIBL_USE_LIGHTPROBE)
#error "QIBL_USE_PROBE needs QIBL_USE_SH and QIBL_USE_LIGHTPROBE"
#endif

/* QIBL_SH_MAX_BANDS: largest band count the SH module accepts, 1..5 (bands 0..4, 25 coefficients).
 * Costs nothing in RAM; callers size their output arrays as QIBL_SH_MAX_BANDS squared. */
#ifndef QIBL_SH_MAX_BANDS
#define QIBL_SH_MAX_BANDS 5
#endif
#if QIBL_SH_MAX_BANDS < 1 || QIBL_SH_MAX_BANDS > 5
#error "QIBL_SH_MAX_BANDS must be in 1..5"
#endif

/* QIBL_USE_HEMI: 1 builds hemispherical rasterization (hemi.c: plane LUT, triangle masks, SH
 * transfer, frame rotation; see `make cross` for its .text; no RAM beyond the caller's workspace,
 * qibl_hemi_workspace_size: within 1 MiB for the default 32 x 32 mask and faces, within 256 KiB
 * with 20 x 20 faces, hemi.h). Needs QIBL_USE_SH with 5 bands; by default on when that holds, unless
 * QIBL_CONFIG_SMALL. */
#ifndef QIBL_USE_HEMI
#define QIBL_USE_HEMI (QIBL_USE_SH && QIBL_SH_MAX_BANDS == 5 && !QIBL_CONFIG_SMALL)
#endif
#if QIBL_USE_HEMI && (!QIBL_USE_SH || QIBL_SH_MAX_BANDS != 5)
#error "QIBL_USE_HEMI needs QIBL_USE_SH and QIBL_SH_MAX_BANDS 5 (25-coefficient transfer)"
#endif

/* QIBL_CONFIG_NATIVE_MUL64: 1 if the compiler multiplies 32x32->64 bits without a library call.
 * ARMv6-M/ARMv8-M Baseline (Cortex-M0/M0+/M23) call __aeabi_lmul, so there qibl builds the product
 * from four 16x16 products instead. Both paths give identical results; only speed differs. */
#ifndef QIBL_CONFIG_NATIVE_MUL64
#if defined(__ARM_ARCH_6M__) || defined(__ARM_ARCH_8M_BASE__)
#define QIBL_CONFIG_NATIVE_MUL64 0
#else
#define QIBL_CONFIG_NATIVE_MUL64 1
#endif
#endif

/* QIBL_CONFIG_NATIVE_SHIFT64: 1 if the compiler shifts 64-bit values by a variable count inline.
 * ARMv6-M/ARMv8-M Baseline call __aeabi_llsr/__aeabi_llsl, so there qibl shifts 32-bit halves.
 * Results are identical either way. */
#ifndef QIBL_CONFIG_NATIVE_SHIFT64
#if defined(__ARM_ARCH_6M__) || defined(__ARM_ARCH_8M_BASE__)
#define QIBL_CONFIG_NATIVE_SHIFT64 0
#else
#define QIBL_CONFIG_NATIVE_SHIFT64 1
#endif
#endif

/* QIBL_CONFIG_NATIVE_DIV64: 1 if 64/64-bit unsigned division is a machine instruction (64-bit
 * hosts). Otherwise qibl divides by shift-and-subtract (64 steps) rather than call __udivdi3 or
 * __aeabi_uldivmod, which a freestanding core may not link. Results are identical either way. */
#ifndef QIBL_CONFIG_NATIVE_DIV64
#if defined(__x86_64__) || defined(__aarch64__) || (defined(__riscv_xlen) && __riscv_xlen == 64 && defined(__riscv_div))
#define QIBL_CONFIG_NATIVE_DIV64 1
#else
#define QIBL_CONFIG_NATIVE_DIV64 0
#endif
#endif

/* QIBL_CONFIG_SRGBE_BLOCKS: 1 makes qibl_srgbe_encode_f32_n encode blocks of 16 pixels as 16-bit
 * planes, code that compilers vectorise for SSE2, NEON, AltiVec or RVV (used where QIBL_CONFIG_SIMD
 * is scalar; otherwise its intrinsics kernel runs, faster still) (faster there, a few hundred
 * bytes of stack; forced on for a Cortex-M4 -Os it would add .text and run slower: `qibl bench
 * srgbe` and `make cross` measure both); 0 encodes pixel by pixel. Identical bytes either way. Default: 1 where the compiler
 * targets one of those vector units and multiplies 32x32->64 inline, so the portable flavour of
 * `make test` (QIBL_CONFIG_NATIVE_MUL64=0) covers the other path on the host. */
#ifndef QIBL_CONFIG_SRGBE_BLOCKS
#if QIBL_CONFIG_NATIVE_MUL64 && (defined(__SSE2__) || defined(__ARM_NEON) || defined(__ALTIVEC__) || defined(__riscv_vector))
#define QIBL_CONFIG_SRGBE_BLOCKS 1
#else
#define QIBL_CONFIG_SRGBE_BLOCKS 0
#endif
#endif

/* QIBL_CONFIG_SHMAP_BLOCKS: the portable (QIBL_CONFIG_SIMD scalar) directional kernel on the
 * planar layout. 1: eight pixels a step with all k maps' products summed in registers from
 * aligned 32-bit words (core/src/shmap.c chan_words), made for 32-bit cores without vector units:
 * fewer cycles per pixel on the ARM7TDMI (Game Boy Advance) and fewer instructions on Cortex-M4
 * and Cortex-M0 (docs/porting.md's generated GBA and bare-metal tables). 0: passes of four planes over the span
 * through the int32 workspace, loops that compilers vectorise for SSE2, NEON, AltiVec or RVV
 * (on x86-64 about two thirds of the instructions of 1). Identical bytes either way. Default: 0
 * where the compiler targets one of those vector units and multiplies 32x32->64 inline, so the
 * portable flavour of `make test` (QIBL_CONFIG_NATIVE_MUL64=0) covers 1 on the host. */
#ifndef QIBL_CONFIG_SHMAP_BLOCKS
#if QIBL_CONFIG_NATIVE_MUL64 && (defined(__SSE2__) || defined(__ARM_NEON) || defined(__ALTIVEC__) || defined(__riscv_vector))
#define QIBL_CONFIG_SHMAP_BLOCKS 0
#else
#define QIBL_CONFIG_SHMAP_BLOCKS 1
#endif
#endif

/* QIBL_CONFIG_SIMD: the vector instructions the hot kernels use (relight on the interleaved
 * layout), through the compiler's own intrinsics headers (<emmintrin.h>, <immintrin.h>,
 * <arm_neon.h>: no libc, so the core stays freestanding). QIBL_SIMD_SCALAR is the portable C
 * reference, always built and tested (the portable flavour of `make test`); every path gives the
 * same bytes, since every partial sum is an exact int32 whatever the order. Default: the best the
 * compiler's target macros allow (__AVX2__, __SSE2__, __ARM_NEON); a path the target lacks is an
 * #error. Not part of QIBL_CONFIG_ID: the API and the results are the same on every path. */
#define QIBL_SIMD_SCALAR 0
#define QIBL_SIMD_SSE2 1
#define QIBL_SIMD_AVX2 2
#define QIBL_SIMD_NEON 3
/* AVX-512 (F, BW, VL, CD, VNNI): a run-time dispatch choice only (qibl/isa.h), never a
 * QIBL_CONFIG_SIMD value: its copy of shmap is the AVX2 build plus a 16-lane point-light kernel */
#define QIBL_SIMD_AVX512 4
#ifndef QIBL_CONFIG_SIMD
#if defined(__AVX2__)
#define QIBL_CONFIG_SIMD QIBL_SIMD_AVX2
#elif defined(__SSE2__)
#define QIBL_CONFIG_SIMD QIBL_SIMD_SSE2
#elif defined(__ARM_NEON)
#define QIBL_CONFIG_SIMD QIBL_SIMD_NEON
#else
#define QIBL_CONFIG_SIMD QIBL_SIMD_SCALAR
#endif
#endif
#if (QIBL_CONFIG_SIMD == QIBL_SIMD_AVX2 && !defined(__AVX2__)) || \
    (QIBL_CONFIG_SIMD == QIBL_SIMD_SSE2 && !defined(__SSE2__)) || \
    (QIBL_CONFIG_SIMD == QIBL_SIMD_NEON && !defined(__ARM_NEON)) || QIBL_CONFIG_SIMD < 0 || QIBL_CONFIG_SIMD > 3
#error "QIBL_CONFIG_SIMD names a path the target does not have (0 scalar, 1 SSE2, 2 AVX2, 3 NEON)"
#endif

/* QIBL_CONFIG_DISPATCH: 1 on a hosted x86-64 build (GCC or Clang) that carries the scalar, SSE2
 * and AVX2 copies of the SIMD modules (shmap, srgbe, probe, lightprobe, hemi) and picks one per
 * call from the CPU (qibl/isa.h). The Makefile's native library sets it on x86-64 hosts and adds
 * the copies (core/src/x86/: a copy of those modules per ISA); 0 (default): the one path of
 * QIBL_CONFIG_SIMD, as every freestanding target. Not part of QIBL_CONFIG_ID: same API, same bytes. */
#ifndef QIBL_CONFIG_DISPATCH
#define QIBL_CONFIG_DISPATCH 0
#endif
#if QIBL_CONFIG_DISPATCH && (!defined(__x86_64__) || !(defined(__GNUC__) || defined(__clang__)))
#error "QIBL_CONFIG_DISPATCH needs x86-64 and GCC or Clang (__builtin_cpu_supports, target copies)"
#endif

/* QIBL_RESTRICT: C99's `restrict` in the public headers, which C++ does not have (GCC, Clang and
 * MSVC spell it __restrict there; other C++ compilers get nothing, which only costs speed). The
 * core's own sources are C99 and say `restrict`; the qualifier does not change a function's type. */
#ifndef QIBL_RESTRICT
#if defined(__cplusplus)
#if defined(__GNUC__) || defined(__clang__) || defined(_MSC_VER)
#define QIBL_RESTRICT __restrict
#else
#define QIBL_RESTRICT
#endif
#elif defined(__STDC_VERSION__) && __STDC_VERSION__ >= 199901L
#define QIBL_RESTRICT restrict
#else
#define QIBL_RESTRICT
#endif
#endif

/* QIBL_CAST(T, x): the conversions in the public headers' inline functions and macros, which C++
 * engines compile with -Wold-style-cast: static_cast there, a plain cast in C (the same
 * conversion). The headers never cast where T may already be x's type on some target (int32_t is
 * int on one, long on another), which g++ -Wuseless-cast reports; QIBL_I32_C gives an int32_t
 * literal without a cast in C++ (the compiler's own __INT32_C, which has int32_t's type). */
#ifdef __cplusplus
#define QIBL_CAST(T, x) (static_cast<T>(x))
#if defined(__INT32_C)
#define QIBL_I32_C(v) __INT32_C(v)
#else
#define QIBL_I32_C(v) QIBL_CAST(int32_t, v)
#endif
#else
#define QIBL_CAST(T, x) ((T)(x))
#define QIBL_I32_C(v) ((int32_t)(v))
#endif

#endif /* QIBL_CONFIG_H */
