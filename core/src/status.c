/*
 * status.c - names of qibl_status_t values.
 */
#include "qibl/status.h"

const char *qibl_status_str(qibl_status_t s)
{
    /* A switch rather than a table indexed by s: no out-of-range read for a forged value. */
    switch (s) {
    case QIBL_OK:             return "ok";
    case QIBL_E_NULL_POINTER: return "null pointer argument";
    case QIBL_E_ZERO_VECTOR:  return "zero vector has no direction";
    case QIBL_E_BAD_BANDS:    return "SH band count out of range";
    case QIBL_E_DIV_BY_ZERO:  return "division by zero";
    case QIBL_E_RANGE:        return "result out of range of the output format";
    case QIBL_E_ASSET_TRUNCATED_HEADER: return "asset: truncated header";
    case QIBL_E_ASSET_MAGIC:            return "asset: bad magic (not a qibl asset)";
    case QIBL_E_ASSET_VERSION:          return "asset: unknown format version";
    case QIBL_E_ASSET_CHUNK_COUNT:      return "asset: chunk count out of range";
    case QIBL_E_ASSET_TRUNCATED_TABLE:  return "asset: truncated chunk table";
    case QIBL_E_ASSET_TRUNCATED:        return "asset: truncated (shorter than its file size)";
    case QIBL_E_ASSET_TABLE_CRC:        return "asset: chunk table CRC mismatch";
    case QIBL_E_ASSET_CHUNK_MISALIGNED: return "asset: chunk offset not a multiple of 4";
    case QIBL_E_ASSET_CHUNK_PAST_END:   return "asset: chunk outside the payload area";
    case QIBL_E_ASSET_DUPLICATE_CHUNK:  return "asset: duplicate chunk";
    case QIBL_E_ASSET_CHUNK_OVERLAP:    return "asset: overlapping chunks";
    case QIBL_E_ASSET_MISSING_CHUNK:    return "asset: missing chunk";
    case QIBL_E_ASSET_CHUNK_CRC:        return "asset: chunk CRC mismatch";
    case QIBL_E_ASSET_BAD_DIMENSIONS:   return "asset: dimensions zero or too large";
    case QIBL_E_ASSET_BAD_K:            return "asset: SH map count k out of range";
    case QIBL_E_ASSET_BAD_CHANNELS:     return "asset: channel count not 1 or 3";
    case QIBL_E_ASSET_BAD_FLAGS:        return "asset: reserved flags set";
    case QIBL_E_ASSET_SIZE_OVERFLOW:    return "asset: chunk size overflows 32 bits";
    case QIBL_E_ASSET_CHUNK_SIZE:       return "asset: chunk size inconsistent with its fields";
    case QIBL_E_ASSET_MISMATCH:         return "asset: chunk inconsistent with SHMP";
    case QIBL_E_ASSET_HEAD_SHORT:       return "asset: head shorter than the fields it must hold";
    case QIBL_E_ASSET_LAYOUT:           return "asset: streaming by rows needs the interleaved layout";
    case QIBL_E_ASSET_ROW:              return "asset: row outside the maps";
    case QIBL_E_SHMAP_LAYOUT:           return "SH maps: unknown layout";
    case QIBL_E_RESERVED_26: return "reserved status 26 (not returned)";
    case QIBL_E_RESERVED_27: return "reserved status 27 (not returned)";
    case QIBL_E_RESERVED_28: return "reserved status 28 (not returned)";
    case QIBL_E_RESERVED_29: return "reserved status 29 (not returned)";
    case QIBL_E_WORKSPACE:       return "workspace too small";
    case QIBL_E_SHMAP_K:         return "SH map count k out of range 1..25";
    case QIBL_E_SHMAP_CHANNELS:  return "SH maps must have 1 or 3 channels";
    case QIBL_E_SHMAP_SIZE:      return "SH maps have zero width or height";
    case QIBL_E_SHMAP_LIGHT_K:   return "light has fewer SH coefficients than the maps";
    case QIBL_E_SHMAP_BOUNDS:    return "span outside the SH maps";
    case QIBL_E_SHMAP_MISMATCH:  return "weights, P map or LUT do not match the SH maps";
    case QIBL_E_SHMAP_LIGHT:     return "bad point light (negative colour or distance, unknown falloff)";
    case QIBL_E_SHMAP_LUT_SIZE:  return "cube-map LUT face size out of range";
    case QIBL_E_SRGBE_NAN:        return "sRGBE: NaN channel (zero code written)";
    case QIBL_E_SRGBE_INF:        return "sRGBE: infinite channel (saturated code written)";
    case QIBL_E_SRGBE_OVERFLOW:   return "sRGBE: value above the largest code (saturated code written)";
    case QIBL_E_SRGBE_DECODE_SAT: return "sRGBE: decoded value beyond the output format (saturated)";
    case QIBL_E_PROBE_SIZE:       return "light probe: width or height zero or too large";
    case QIBL_E_PROBE_OVERFLOW:   return "light probe: pixel count or byte size too large";
    case QIBL_E_PROBE_FORMAT:     return "light probe: bad pixel format, frac_bits, stride or alignment";
    case QIBL_E_PROBE_METHOD:     return "light probe: unknown or invalid method, priority or placement";
    case QIBL_E_PROBE_NEGATIVE:   return "light probe: negative pixel";
    case QIBL_E_PROBE_NOT_FINITE: return "light probe: NaN or infinite pixel";
    case QIBL_E_PROBE_COUNT:      return "light probe: bad light count (0, or not a power of two for median cut)";
    case QIBL_E_PROBE_MISMATCH:   return "light probe: built without the variance tables this call needs";
    case QIBL_E_PROBE_BLACK:      return "light probe: all black, no lights";
    case QIBL_E_PROBE_RECT:       return "light probe: region outside the probe";
    case QIBL_E_CONFIG_MISMATCH:  return "caller built with other config.h options or release than the library";
    case QIBL_E_LIGHTPATH_SIZE:       return "light path: LPTH payload size other than its fields imply";
    case QIBL_E_LIGHTPATH_DIMENSIONS: return "light path: width/height zero, too large or not the SH maps'";
    case QIBL_E_LIGHTPATH_KIND:       return "light path: unknown kind or reserved flags not 0";
    case QIBL_E_LIGHTPATH_KEYS:       return "light path: bad keys (count, t not 0..65535 increasing, zero direction)";
    case QIBL_E_LIGHTPATH_ROWS:       return "light path: row index disagrees with the edge counts";
    case QIBL_E_LIGHTPATH_EDGES:      return "light path: a pixel's edges not strictly increasing";
    case QIBL_E_LIGHTPATH_PARAM:      return "light path: t above 65535 or radius above 32767";
    case QIBL_E_LIGHTPATH_BOUNDS:     return "light path: span outside the path's pixels";
    case QIBL_E_SH_ROTATION:      return "SH rotation: matrix not orthonormal within 2^-16, or a reflection";
    case QIBL_E_PROBE_ROW:        return "probe projection: row outside the probe, or not every row added";
    case QIBL_E_PROBE_SATURATED:  return "probe projection: SH coefficients beyond the Q16.16 light";
    case QIBL_E_HEMI_SIZE:        return "hemi: mask size not 16, 32 or 64, or cube-map face not even in 2..128";
    case QIBL_E_HEMI_RANGE:       return "hemi: coordinate beyond the rasterizer's range";
    case QIBL_E_HEMI_INDEX:       return "hemi: triangle index beyond the vertex count";
    case QIBL_E_HEMI_EXPONENT:    return "hemi: Phong exponent beyond QIBL_HEMI_MAX_EXPONENT";
    case QIBL_E_SHMAP_LUT_SHORT:  return "cube-map LUT view shorter than its face size and k need";
    case QIBL_E_GONIO_SIZE:       return "gonio: table size outside 2..256";
    case QIBL_E_GONIO_TABLE:      return "gonio: a table entry above 32768 (1.0 in Q1.15)";
    case QIBL_E_GONIO_AIM:        return "gonio: aim vector is zero";
    case QIBL_E_GONIO_UP:         return "gonio: up vector zero or parallel to the aim";
    case QIBL_E_GONIO_BOUNDS:     return "gonio: span outside the P map";
    case QIBL_E_WORKSPACE_ALIGN:  return "workspace not 4-byte aligned (declare it as uint32_t or int32_t)";
    case QIBL_E_HEMI_XFER_SHORT:  return "transfer export shorter than its header";
    case QIBL_E_HEMI_XFER_MAGIC:  return "not a transfer export (magic)";
    case QIBL_E_HEMI_XFER_FORMAT: return "transfer export: version, bands, frac_bits, reserved or count unsupported";
    case QIBL_E_HEMI_XFER_SIZE:   return "transfer export size differs from its fields";
    case QIBL_E_HEMI_XFER_CRC:    return "transfer export CRC-32 mismatch";
    case QIBL_E_HEMI_XFER_BOUNDS: return "span outside the exported vertices";
    case QIBL_STATUS_COUNT:   break;
    case QIBL_STATUS_SOFT_BASE: case QIBL_STATUS_GLES2_BASE: case QIBL_STATUS_BACKEND_END: break;
    }
    /* unsigned compare: no assumption about the enum's signedness */
    if ((unsigned)s >= (unsigned)QIBL_STATUS_SOFT_BASE && (unsigned)s < (unsigned)QIBL_STATUS_BACKEND_END)
        return "platform backend status";
    return "unknown status";
}
