/*
 * qibl/version.h - which qibl this is: the release version, and the configuration identity that
 * lets a program check once, at start-up, that it was compiled with the same config.h options
 * (and the same release) as the library it links.
 *
 * Why: config.h options size public structs (QIBL_SH_MAX_BANDS sizes qibl_shlight_t and the
 * weights), so a program built with -DQIBL_SH_MAX_BANDS=3 against a default library passes
 * structs smaller than the library writes: memory corruption, not an error. Calling
 * qibl_init_check() once turns that into QIBL_E_CONFIG_MISMATCH.
 *
 * Stability (docs/ARCHITECTURE.md, "Versions and stability"): a patch release changes no public
 * declaration and no struct layout; before 1.0 a minor release may change both, which is why the
 * configuration identity includes the major and minor version.
 */
#ifndef QIBL_VERSION_H
#define QIBL_VERSION_H

#include <stdint.h>
#include "qibl/config.h"
#include "qibl/status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define QIBL_VERSION_MAJOR 0
#define QIBL_VERSION_MINOR 1
#define QIBL_VERSION_PATCH 0
#define QIBL_VERSION_STRING "0.1.0"
/* one comparable number: major * 10000 + minor * 100 + patch */
#define QIBL_VERSION_NUMBER (QIBL_VERSION_MAJOR * 10000 + QIBL_VERSION_MINOR * 100 + QIBL_VERSION_PATCH)

/* The configuration identity: every config.h option that changes a public struct, an array size
 * or which functions exist, plus the release's major and minor version, packed into 32 bits.
 *
 *   bits  0..4   QIBL_USE_SH, _SRGBE, _ASSET, _LIGHTPROBE, _SHMAP (one bit each)
 *   bit   5      QIBL_USE_INTERLEAVED
 *   bit   6      QIBL_USE_PROBE
 *   bit   7      QIBL_USE_HEMI
 *   bits  8..11  QIBL_SH_MAX_BANDS (1..5)
 *   bit  12      QIBL_USE_LIGHTPATH
 *   bit  13      QIBL_USE_GONIO
 *   bits 14..15  reserved (0): further size options
 *   bits 16..23  QIBL_VERSION_MINOR
 *   bits 24..27  QIBL_VERSION_MAJOR (mod 16)
 *   bits 28..31  0xA, so that 0 or a stray small integer is never a valid identity
 *
 * Not included, because they change speed only and give identical results and layouts:
 * QIBL_CONFIG_NATIVE_MUL64, _SHIFT64, _DIV64, QIBL_CONFIG_SRGBE_BLOCKS. A uint32_t constant
 * expression (not for #if: it has casts, static_cast in C++). An option that changes a layout
 * must be added here when it is added to config.h. */
#define QIBL_CONFIG_ID \
    (0xA0000000u | (QIBL_CAST(uint32_t, QIBL_VERSION_MAJOR & 15) << 24) | \
     (QIBL_CAST(uint32_t, QIBL_VERSION_MINOR & 255) << 16) | \
     (QIBL_CAST(uint32_t, QIBL_SH_MAX_BANDS) << 8) | (QIBL_CAST(uint32_t, QIBL_USE_HEMI != 0) << 7) | \
     (QIBL_CAST(uint32_t, QIBL_USE_PROBE != 0) << 6) | \
     (QIBL_CAST(uint32_t, QIBL_USE_SHMAP != 0) << 4) | \
     (QIBL_CAST(uint32_t, QIBL_USE_LIGHTPROBE != 0) << 3) | \
     (QIBL_CAST(uint32_t, QIBL_USE_ASSET != 0) << 2) | \
     (QIBL_CAST(uint32_t, QIBL_USE_SRGBE != 0) << 1) | \
     (QIBL_CAST(uint32_t, QIBL_USE_INTERLEAVED != 0) << 5) | QIBL_CAST(uint32_t, QIBL_USE_SH != 0) | \
     (QIBL_CAST(uint32_t, QIBL_USE_LIGHTPATH != 0) << 12) | \
     (QIBL_CAST(uint32_t, QIBL_USE_GONIO != 0) << 13))

/* QIBL_VERSION_STRING of the library as compiled ("0.1.0"). Never NULL. */
const char *qibl_version(void);

/* QIBL_CONFIG_ID as the library was compiled. */
uint32_t qibl_config_id(void);

/* QIBL_OK if caller_id (the caller's QIBL_CONFIG_ID) equals the library's, else
 * QIBL_E_CONFIG_MISMATCH: the caller's structs may not match the library's, and no other qibl
 * call should be made. Cheap (one comparison); call it once at start-up, as qibl_init_check()
 * does.
 * Formats: none (caller_id is a bit pattern, compared whole). Bound: exact.
 * Errors: QIBL_E_CONFIG_MISMATCH (caller_id != QIBL_CONFIG_ID).
 * On failure: nothing is written (it has no outputs). */
QIBL_NODISCARD qibl_status_t qibl_check_config(uint32_t caller_id);

/* qibl_check_config with the identity of the code that includes this header.
 * Formats: none. Bound: exact.
 * Errors: QIBL_E_CONFIG_MISMATCH (this translation unit's QIBL_CONFIG_ID is not the library's).
 * On failure: nothing is written (it has no outputs). */
static inline QIBL_NODISCARD qibl_status_t qibl_init_check(void)
{
    return qibl_check_config(QIBL_CONFIG_ID);
}

#ifdef __cplusplus
}
#endif

#endif /* QIBL_VERSION_H */
