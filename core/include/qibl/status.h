/*
 * qibl/status.h - the one error type of qibl.
 *
 * Every core function that can fail returns qibl_status_t: 0 is success and every other value names
 * one kind of bad input. A call that fails writes nothing to its outputs unless its header says
 * exactly what it writes.
 */
#ifndef QIBL_STATUS_H
#define QIBL_STATUS_H

#ifdef __cplusplus
extern "C" {
#endif

typedef enum qibl_status {
    QIBL_OK = 0,
    QIBL_E_NULL_POINTER,   /* a required pointer argument was NULL */
    QIBL_E_ZERO_VECTOR,    /* a direction was (0, 0, 0): it has no direction */
    QIBL_E_BAD_BANDS,      /* SH band count outside 1..QIBL_SH_MAX_BANDS */
    QIBL_E_DIV_BY_ZERO,    /* a divisor (or the argument of a reciprocal) was zero */
    QIBL_E_RANGE,          /* the exact result does not fit the output format */
    /* asset container (asset.h), in the order qibl_asset_open checks them */
    QIBL_E_ASSET_TRUNCATED_HEADER, /* buffer shorter than the 24-byte header */
    QIBL_E_ASSET_MAGIC,            /* not a qibl asset (or mangled by a text-mode transfer) */
    QIBL_E_ASSET_VERSION,          /* format version this build does not read */
    QIBL_E_ASSET_CHUNK_COUNT,      /* chunk_count outside 1..QIBL_ASSET_MAX_CHUNKS */
    QIBL_E_ASSET_TRUNCATED_TABLE,  /* chunk table runs past the buffer or past file_size */
    QIBL_E_ASSET_TRUNCATED,        /* buffer shorter than file_size */
    QIBL_E_ASSET_TABLE_CRC,        /* chunk table CRC-32 mismatch */
    QIBL_E_ASSET_CHUNK_MISALIGNED, /* chunk offset not a multiple of 4 */
    QIBL_E_ASSET_CHUNK_PAST_END,   /* chunk starts inside header/table or ends past file_size */
    QIBL_E_ASSET_DUPLICATE_CHUNK,  /* a known chunk type appears twice */
    QIBL_E_ASSET_CHUNK_OVERLAP,    /* two chunk payloads share bytes */
    QIBL_E_ASSET_MISSING_CHUNK,    /* a required (or the requested) chunk is absent */
    QIBL_E_ASSET_CHUNK_CRC,        /* chunk payload CRC-32 mismatch */
    QIBL_E_ASSET_BAD_DIMENSIONS,   /* width/height/face size zero or above the format's maximum */
    QIBL_E_ASSET_BAD_K,            /* SH map count k outside 1..25 */
    QIBL_E_ASSET_BAD_CHANNELS,     /* channels neither 1 nor 3 */
    QIBL_E_ASSET_BAD_FLAGS,        /* reserved flags not 0 */
    QIBL_E_ASSET_SIZE_OVERFLOW,    /* payload size implied by the fields does not fit 32 bits */
    QIBL_E_ASSET_CHUNK_SIZE,       /* payload size differs from the size its fields imply */
    QIBL_E_ASSET_MISMATCH,         /* PMAP/YLUT inconsistent with SHMP (size or k) */
    /* four values that were the software framebuffer's before it got its own range (qibl/soft.h);
     * kept reserved so that every later value keeps its number (goldens hash statuses) */
    QIBL_E_RESERVED_26,
    QIBL_E_RESERVED_27,
    QIBL_E_RESERVED_28,
    QIBL_E_RESERVED_29,
    /* relighting kernels (shmap.h) */
    QIBL_E_WORKSPACE,              /* caller workspace smaller than *_workspace_size() asked for */
    QIBL_E_SHMAP_K,                /* SH map / light coefficient count outside 1..25 */
    QIBL_E_SHMAP_CHANNELS,         /* SH maps with a channel count other than 1 or 3 */
    QIBL_E_SHMAP_SIZE,             /* SH maps of zero width or height */
    QIBL_E_SHMAP_LIGHT_K,          /* light has fewer SH coefficients than the maps */
    QIBL_E_SHMAP_BOUNDS,           /* span outside the maps */
    QIBL_E_SHMAP_MISMATCH,         /* weights, P map or LUT made for other maps */
    QIBL_E_SHMAP_LIGHT,            /* point light with a negative colour or distance, or unknown falloff */
    QIBL_E_SHMAP_LUT_SIZE,         /* cube-map LUT face size outside 1..QIBL_YLUT_MAX_FACE */
    /* sRGBE codec (srgbe.h); each of these calls writes the code or value its header states */
    QIBL_E_SRGBE_NAN,              /* encode: a channel is NaN (the zero code is written) */
    QIBL_E_SRGBE_INF,              /* encode: a channel is +-Inf (saturated code written) */
    QIBL_E_SRGBE_OVERFLOW,         /* encode: finite channel >= 2^128, above the largest exponent */
    QIBL_E_SRGBE_DECODE_SAT,       /* decode: a channel beyond the output format (saturated) */
    /* light-probe sampling (lightprobe.h) */
    QIBL_E_PROBE_SIZE,             /* probe width or height 0 or above QIBL_LIGHTPROBE_MAX_DIM */
    QIBL_E_PROBE_OVERFLOW,         /* W * H above QIBL_LIGHTPROBE_MAX_PIXELS, or sizes beyond size_t */
    QIBL_E_PROBE_FORMAT,           /* unknown pixel format, frac_bits out of range, bad stride/alignment */
    QIBL_E_PROBE_METHOD,           /* unknown method, priority or placement, or an invalid mix */
    QIBL_E_PROBE_NEGATIVE,         /* a probe pixel has a negative channel */
    QIBL_E_PROBE_NOT_FINITE,       /* a probe pixel has a NaN or infinite channel */
    QIBL_E_PROBE_COUNT,            /* light count 0, or not a power of two for median cut */
    QIBL_E_PROBE_MISMATCH,         /* variance tables needed but the probe was built without them */
    QIBL_E_PROBE_BLACK,            /* the probe has no light: zero lights */
    QIBL_E_PROBE_RECT,             /* region outside the probe or inverted */
    /* library identity (version.h) */
    QIBL_E_CONFIG_MISMATCH,        /* caller compiled with other config.h options or another release */
    /* asset streaming by rows (asset.h, qibl_asset_open_head) */
    QIBL_E_ASSET_HEAD_SHORT,       /* head bytes end before the fields needed (qibl_asset_head_size) */
    QIBL_E_ASSET_LAYOUT,           /* streaming by rows needs the interleaved SHMP layout */
    QIBL_E_ASSET_ROW,              /* row index outside the maps */
    QIBL_E_SHMAP_LAYOUT,           /* SH maps view with an unknown layout (shmaps.h) */
    /* SH rotation (sh.h) and probe projection (probe.h) */
    QIBL_E_SH_ROTATION,            /* rotation matrix not orthonormal (within 2^-16) or a reflection */
    QIBL_E_PROBE_ROW,              /* projection: row index outside the probe, or rows missing at finish */
    QIBL_E_PROBE_SATURATED,        /* SH coefficients do not fit the Q16.16 light (lower scale_log2) */
    /* light paths (lightpath.h) */
    QIBL_E_LIGHTPATH_SIZE,         /* LPTH payload shorter than its header or other than its fields imply */
    QIBL_E_LIGHTPATH_DIMENSIONS,   /* LPTH width/height 0, too large, or not the SH maps' */
    QIBL_E_LIGHTPATH_KIND,         /* LPTH kind unknown or reserved flags not 0 */
    QIBL_E_LIGHTPATH_KEYS,         /* key count outside 2..4096, t not 0 .. strictly up .. 65535, zero direction */
    QIBL_E_LIGHTPATH_ROWS,         /* LPTH row index disagrees with the per-pixel edge counts */
    QIBL_E_LIGHTPATH_EDGES,        /* a pixel's edges not strictly increasing */
    QIBL_E_LIGHTPATH_PARAM,        /* path parameter t above 65535 or radius above 32767 */
    QIBL_E_LIGHTPATH_BOUNDS,       /* span outside the path's pixels */
    /* hemispherical rasterization (hemi.h) */
    QIBL_E_HEMI_SIZE,              /* hemi: mask size not 16/32/64, or cube-map face not even in 2..128 */
    QIBL_E_HEMI_RANGE,             /* hemi: a coordinate beyond QIBL_HEMI_COORD_MAX / _LOCAL_MAX */
    QIBL_E_HEMI_INDEX,             /* hemi: a triangle index beyond the vertex count */
    QIBL_E_HEMI_EXPONENT,          /* hemi: Phong exponent beyond QIBL_HEMI_MAX_EXPONENT */
    /* cube-map LUT views (shmaps.h) */
    QIBL_E_SHMAP_LUT_SHORT,        /* LUT view's size below the 6 N N k int16 its face size and k need */
    /* goniometric lamps (gonio.h) */
    QIBL_E_GONIO_SIZE,             /* gonio: table size n outside QIBL_GONIO_MIN_N .. QIBL_GONIO_MAX_N */
    QIBL_E_GONIO_TABLE,            /* gonio: a table entry above 32768 (1.0 in Q1.15) */
    QIBL_E_GONIO_AIM,              /* gonio: the aim vector is zero */
    QIBL_E_GONIO_UP,               /* gonio: the up vector is zero or (within 2^-10 rad) parallel to the aim */
    QIBL_E_GONIO_BOUNDS,           /* gonio: span outside the P map */
    /* workspaces (appended last so no earlier value moves) */
    QIBL_E_WORKSPACE_ALIGN,        /* caller workspace not on the 4-byte boundary the call needs */
    /* exported transfer (hemi.h, qibl_hemi_xfer_*) */
    QIBL_E_HEMI_XFER_SHORT,        /* hemi export: shorter than its 24-byte header */
    QIBL_E_HEMI_XFER_MAGIC,        /* hemi export: not "QTRX" */
    QIBL_E_HEMI_XFER_FORMAT,       /* hemi export: version, bands, frac_bits, reserved or count not as documented */
    QIBL_E_HEMI_XFER_SIZE,         /* hemi export: size not the header plus count * bands^2 * 4 bytes */
    QIBL_E_HEMI_XFER_CRC,          /* hemi export: payload CRC-32 mismatch */
    QIBL_E_HEMI_XFER_BOUNDS,       /* hemi export: span past the vertices */
    QIBL_STATUS_COUNT,     /* number of core status values; not a status */
    /* Platform backends (platform/<name>/) return qibl_status_t too, with their errors in their own
     * range of 256 values from their base, defined in the backend's header; the core never returns
     * them. The entries below reserve the ranges and make the enum wide enough to hold them. */
    QIBL_STATUS_SOFT_BASE = 0x100,  /* platform/soft, qibl/soft.h: QIBL_E_FB_* */
    QIBL_STATUS_GLES2_BASE = 0x200, /* platform/gles2, qibl/gles2.h: QIBL_E_GLES2_* */
    QIBL_STATUS_BACKEND_END = 0x1000 /* first value above every backend range; not a status */
} qibl_status_t;

/* A short, constant, English description of s ("ok", "null pointer argument", ...). Never NULL:
 * a backend's values give "platform backend status" (the backend's own *_status_str names them),
 * other values outside the enum "unknown status". */
const char *qibl_status_str(qibl_status_t s);

#ifdef __cplusplus
}
#endif

#endif /* QIBL_STATUS_H */
