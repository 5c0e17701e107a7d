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

/* QIBL_NODISCARD: marks every function that returns qibl_status_t, so that a caller who drops a
 * status gets a compiler warning (GCC, Clang: warn_unused_result; other compilers: nothing). GCC
 * does not take a (void) cast as a deliberate drop; QIBL_DROP_STATUS(call) is one that every
 * compiler takes. Define QIBL_NODISCARD empty before including a qibl header to turn it off. */
#ifndef QIBL_NODISCARD
#if defined(__GNUC__) || defined(__clang__)
#define QIBL_NODISCARD __attribute__((warn_unused_result))
#else
#define QIBL_NODISCARD
#endif
#endif

/* QIBL_DROP_STATUS(call): evaluates call, a qibl_status_t expression whose status is deliberately
 * ignored (a best-effort call whose failure changes nothing for the caller). */
#define QIBL_DROP_STATUS(call) \
    do { \
        qibl_status_t qibl_dropped_status_ = (call); \
        (void)qibl_dropped_status_; \
    } while (0)

/* QIBL_STATUS_LIST(X): every core status in value order, as X(name, message). The one list from
 * which both the enum below and qibl_status_str's messages are made, so a status cannot lack a
 * message or get another's. Append only: the values are ABI (assets, goldens and callers store them;
 * tests/status_test.c pins some). message is a short, constant English description. */
#define QIBL_STATUS_LIST(X) \
    X(QIBL_OK, "ok")                                                                                    \
    /* a required pointer argument was NULL */                                                          \
    X(QIBL_E_NULL_POINTER, "null pointer argument")                                                     \
    /* a direction was (0, 0, 0): it has no direction */                                                \
    X(QIBL_E_ZERO_VECTOR, "zero vector has no direction")                                               \
    /* SH band count outside 1..QIBL_SH_MAX_BANDS */                                                    \
    X(QIBL_E_BAD_BANDS, "SH band count out of range")                                                   \
    /* a divisor (or the argument of a reciprocal) was zero */                                          \
    X(QIBL_E_DIV_BY_ZERO, "division by zero")                                                           \
    /* the exact result does not fit the output format */                                               \
    X(QIBL_E_RANGE, "result out of range of the output format")                                         \
    /* asset container (asset.h), in the order qibl_asset_open checks them */                           \
    /* buffer shorter than the 24-byte header */                                                        \
    X(QIBL_E_ASSET_TRUNCATED_HEADER, "asset: truncated header")                                         \
    /* not a qibl asset (or mangled by a text-mode transfer) */                                         \
    X(QIBL_E_ASSET_MAGIC, "asset: bad magic (not a qibl asset)")                                        \
    /* format version this build does not read */                                                       \
    X(QIBL_E_ASSET_VERSION, "asset: unknown format version")                                            \
    /* chunk_count outside 1..QIBL_ASSET_MAX_CHUNKS */                                                  \
    X(QIBL_E_ASSET_CHUNK_COUNT, "asset: chunk count out of range")                                      \
    /* chunk table runs past the buffer or past file_size */                                            \
    X(QIBL_E_ASSET_TRUNCATED_TABLE, "asset: truncated chunk table")                                     \
    /* buffer shorter than file_size */                                                                 \
    X(QIBL_E_ASSET_TRUNCATED, "asset: truncated (shorter than its file size)")                          \
    /* chunk table CRC-32 mismatch */                                                                   \
    X(QIBL_E_ASSET_TABLE_CRC, "asset: chunk table CRC mismatch")                                        \
    /* chunk offset not a multiple of 4 */                                                              \
    X(QIBL_E_ASSET_CHUNK_MISALIGNED, "asset: chunk offset not a multiple of 4")                         \
    /* chunk starts inside header/table or ends past file_size */                                       \
    X(QIBL_E_ASSET_CHUNK_PAST_END, "asset: chunk outside the payload area")                             \
    /* a known chunk type appears twice */                                                              \
    X(QIBL_E_ASSET_DUPLICATE_CHUNK, "asset: duplicate chunk")                                           \
    /* two chunk payloads share bytes */                                                                \
    X(QIBL_E_ASSET_CHUNK_OVERLAP, "asset: overlapping chunks")                                          \
    /* a required (or the requested) chunk is absent */                                                 \
    X(QIBL_E_ASSET_MISSING_CHUNK, "asset: missing chunk")                                               \
    /* chunk payload CRC-32 mismatch */                                                                 \
    X(QIBL_E_ASSET_CHUNK_CRC, "asset: chunk CRC mismatch")                                              \
    /* width/height/face size zero or above the format's maximum */                                     \
    X(QIBL_E_ASSET_BAD_DIMENSIONS, "asset: dimensions zero or too large")                               \
    /* SH map count k outside 1..25 */                                                                  \
    X(QIBL_E_ASSET_BAD_K, "asset: SH map count k out of range")                                         \
    /* channels neither 1 nor 3 */                                                                      \
    X(QIBL_E_ASSET_BAD_CHANNELS, "asset: channel count not 1 or 3")                                     \
    /* reserved flags not 0 */                                                                          \
    X(QIBL_E_ASSET_BAD_FLAGS, "asset: reserved flags set")                                              \
    /* payload size implied by the fields does not fit 32 bits */                                       \
    X(QIBL_E_ASSET_SIZE_OVERFLOW, "asset: chunk size overflows 32 bits")                                \
    /* payload size differs from the size its fields imply */                                           \
    X(QIBL_E_ASSET_CHUNK_SIZE, "asset: chunk size inconsistent with its fields")                        \
    /* PMAP/YLUT inconsistent with SHMP (size or k) */                                                  \
    X(QIBL_E_ASSET_MISMATCH, "asset: chunk inconsistent with SHMP")                                     \
    /* four values that were the software framebuffer's before it got its own range (qibl/soft.h);      \
    * kept reserved so that every later value keeps its number (goldens hash statuses) */               \
    X(QIBL_E_RESERVED_26, "reserved status 26 (not returned)")                                          \
    X(QIBL_E_RESERVED_27, "reserved status 27 (not returned)")                                          \
    X(QIBL_E_RESERVED_28, "reserved status 28 (not returned)")                                          \
    X(QIBL_E_RESERVED_29, "reserved status 29 (not returned)")                                          \
    /* relighting kernels (shmap.h) */                                                                  \
    /* caller workspace smaller than *_workspace_size() asked for */                                    \
    X(QIBL_E_WORKSPACE, "workspace too small")                                                          \
    /* SH map / light coefficient count outside 1..25 */                                                \
    X(QIBL_E_SHMAP_K, "SH map count k out of range 1..25")                                              \
    /* SH maps with a channel count other than 1 or 3 */                                                \
    X(QIBL_E_SHMAP_CHANNELS, "SH maps must have 1 or 3 channels")                                       \
    /* SH maps of zero width or height */                                                               \
    X(QIBL_E_SHMAP_SIZE, "SH maps have zero width or height")                                           \
    /* light has fewer SH coefficients than the maps */                                                 \
    X(QIBL_E_SHMAP_LIGHT_K, "light has fewer SH coefficients than the maps")                            \
    /* span outside the maps */                                                                         \
    X(QIBL_E_SHMAP_BOUNDS, "span outside the SH maps")                                                  \
    /* weights, P map or LUT made for other maps */                                                     \
    X(QIBL_E_SHMAP_MISMATCH, "weights, P map or LUT do not match the SH maps")                          \
    /* point light with a negative colour or distance, or unknown falloff */                            \
    X(QIBL_E_SHMAP_LIGHT, "bad point light (negative colour or distance, unknown falloff)")             \
    /* cube-map LUT face size outside 1..QIBL_YLUT_MAX_FACE */                                          \
    X(QIBL_E_SHMAP_LUT_SIZE, "cube-map LUT face size out of range")                                     \
    /* sRGBE codec (srgbe.h); each of these calls writes the code or value its header states */         \
    /* encode: a channel is NaN (the zero code is written) */                                           \
    X(QIBL_E_SRGBE_NAN, "sRGBE: NaN channel (zero code written)")                                       \
    /* encode: a channel is +-Inf (saturated code written) */                                           \
    X(QIBL_E_SRGBE_INF, "sRGBE: infinite channel (saturated code written)")                             \
    /* encode: finite channel >= 2^128, above the largest exponent */                                   \
    X(QIBL_E_SRGBE_OVERFLOW, "sRGBE: value above the largest code (saturated code written)")            \
    /* decode: a channel beyond the output format (saturated) */                                        \
    X(QIBL_E_SRGBE_DECODE_SAT, "sRGBE: decoded value beyond the output format (saturated)")             \
    /* light-probe sampling (lightprobe.h) */                                                           \
    /* probe width or height 0 or above QIBL_LIGHTPROBE_MAX_DIM */                                      \
    X(QIBL_E_PROBE_SIZE, "light probe: width or height zero or too large")                              \
    /* W * H above QIBL_LIGHTPROBE_MAX_PIXELS, or sizes beyond size_t */                                \
    X(QIBL_E_PROBE_OVERFLOW, "light probe: pixel count or byte size too large")                         \
    /* unknown pixel format, frac_bits out of range, bad stride/alignment */                            \
    X(QIBL_E_PROBE_FORMAT, "light probe: bad pixel format, frac_bits, stride or alignment")             \
    /* unknown method, priority or placement, or an invalid mix */                                      \
    X(QIBL_E_PROBE_METHOD, "light probe: unknown or invalid method, priority or placement")             \
    /* a probe pixel has a negative channel */                                                          \
    X(QIBL_E_PROBE_NEGATIVE, "light probe: negative pixel")                                             \
    /* a probe pixel has a NaN or infinite channel */                                                   \
    X(QIBL_E_PROBE_NOT_FINITE, "light probe: NaN or infinite pixel")                                    \
    /* light count 0, or not a power of two for median cut */                                           \
    X(QIBL_E_PROBE_COUNT, "light probe: bad light count (0, or not a power of two for median cut)")     \
    /* variance tables needed but the probe was built without them */                                   \
    X(QIBL_E_PROBE_MISMATCH, "light probe: built without the variance tables this call needs")          \
    /* the probe has no light: zero lights */                                                           \
    X(QIBL_E_PROBE_BLACK, "light probe: all black, no lights")                                          \
    /* region outside the probe or inverted */                                                          \
    X(QIBL_E_PROBE_RECT, "light probe: region outside the probe")                                       \
    /* library identity (version.h) */                                                                  \
    /* caller compiled with other config.h options or another release */                                \
    X(QIBL_E_CONFIG_MISMATCH, "caller built with other config.h options or release than the library")   \
    /* asset streaming by rows (asset.h, qibl_asset_open_head) */                                       \
    /* head bytes end before the fields needed (qibl_asset_head_size) */                                \
    X(QIBL_E_ASSET_HEAD_SHORT, "asset: head shorter than the fields it must hold")                      \
    /* streaming by rows needs the interleaved SHMP layout */                                           \
    X(QIBL_E_ASSET_LAYOUT, "asset: streaming by rows needs the interleaved layout")                     \
    /* row index outside the maps */                                                                    \
    X(QIBL_E_ASSET_ROW, "asset: row outside the maps")                                                  \
    /* SH maps view with an unknown layout (shmaps.h) */                                                \
    X(QIBL_E_SHMAP_LAYOUT, "SH maps: unknown layout")                                                   \
    /* SH rotation (sh.h) and probe projection (probe.h) */                                             \
    /* rotation matrix not orthonormal (within 2^-16) or a reflection */                                \
    X(QIBL_E_SH_ROTATION, "SH rotation: matrix not orthonormal within 2^-16, or a reflection")          \
    /* projection: row index outside the probe, or rows missing at finish */                            \
    X(QIBL_E_PROBE_ROW, "probe projection: row outside the probe, or not every row added")              \
    /* SH coefficients do not fit the Q16.16 light (lower scale_log2) */                                \
    X(QIBL_E_PROBE_SATURATED, "probe projection: SH coefficients beyond the Q16.16 light")              \
    /* light paths (lightpath.h) */                                                                     \
    /* LPTH payload shorter than its header or other than its fields imply */                           \
    X(QIBL_E_LIGHTPATH_SIZE, "light path: LPTH payload size other than its fields imply")               \
    /* LPTH width/height 0, too large, or not the SH maps' */                                           \
    X(QIBL_E_LIGHTPATH_DIMENSIONS, "light path: width/height zero, too large or not the SH maps'")      \
    /* LPTH kind unknown or reserved flags not 0 */                                                     \
    X(QIBL_E_LIGHTPATH_KIND, "light path: unknown kind or reserved flags not 0")                        \
    /* key count outside 2..4096, t not 0 .. strictly up .. 65535, zero direction */                    \
    X(QIBL_E_LIGHTPATH_KEYS, "light path: bad keys (count, t not 0..65535 increasing, zero direction)") \
    /* LPTH row index disagrees with the per-pixel edge counts */                                       \
    X(QIBL_E_LIGHTPATH_ROWS, "light path: row index disagrees with the edge counts")                    \
    /* a pixel's edges not strictly increasing */                                                       \
    X(QIBL_E_LIGHTPATH_EDGES, "light path: a pixel's edges not strictly increasing")                    \
    /* path parameter t above 65535 or radius above 32767 */                                            \
    X(QIBL_E_LIGHTPATH_PARAM, "light path: t above 65535 or radius above 32767")                        \
    /* span outside the path's pixels */                                                                \
    X(QIBL_E_LIGHTPATH_BOUNDS, "light path: span outside the path's pixels")                            \
    /* hemispherical rasterization (hemi.h) */                                                          \
    /* hemi: mask size not 16/32/64, or cube-map face not even in 2..128 */                             \
    X(QIBL_E_HEMI_SIZE, "hemi: mask size not 16, 32 or 64, or cube-map face not even in 2..128")        \
    /* hemi: a coordinate beyond QIBL_HEMI_COORD_MAX / _LOCAL_MAX */                                    \
    X(QIBL_E_HEMI_RANGE, "hemi: coordinate beyond the rasterizer's range")                              \
    /* hemi: a triangle index beyond the vertex count */                                                \
    X(QIBL_E_HEMI_INDEX, "hemi: triangle index beyond the vertex count")                                \
    /* hemi: Phong exponent beyond QIBL_HEMI_MAX_EXPONENT */                                            \
    X(QIBL_E_HEMI_EXPONENT, "hemi: Phong exponent beyond QIBL_HEMI_MAX_EXPONENT")                       \
    /* cube-map LUT views (shmaps.h) */                                                                 \
    /* LUT view's size below the 6 N N k int16 its face size and k need */                              \
    X(QIBL_E_SHMAP_LUT_SHORT, "cube-map LUT view shorter than its face size and k need")                \
    /* goniometric lamps (gonio.h) */                                                                   \
    /* gonio: table size n outside QIBL_GONIO_MIN_N .. QIBL_GONIO_MAX_N */                              \
    X(QIBL_E_GONIO_SIZE, "gonio: table size outside 2..256")                                            \
    /* gonio: a table entry above 32768 (1.0 in Q1.15) */                                               \
    X(QIBL_E_GONIO_TABLE, "gonio: a table entry above 32768 (1.0 in Q1.15)")                            \
    /* gonio: the aim vector is zero */                                                                 \
    X(QIBL_E_GONIO_AIM, "gonio: aim vector is zero")                                                    \
    /* gonio: the up vector is zero or (within 2^-10 rad) parallel to the aim */                        \
    X(QIBL_E_GONIO_UP, "gonio: up vector zero or parallel to the aim")                                  \
    /* gonio: span outside the P map */                                                                 \
    X(QIBL_E_GONIO_BOUNDS, "gonio: span outside the P map")                                             \
    /* workspaces (appended last so no earlier value moves) */                                          \
    /* caller workspace not on the 4-byte boundary the call needs */                                    \
    X(QIBL_E_WORKSPACE_ALIGN, "workspace not 4-byte aligned (declare it as uint32_t or int32_t)")       \
    /* exported transfer (hemi.h, qibl_hemi_xfer_*) */                                                  \
    /* hemi export: shorter than its 24-byte header */                                                  \
    X(QIBL_E_HEMI_XFER_SHORT, "transfer export shorter than its header")                                \
    /* hemi export: not "QTRX" */                                                                       \
    X(QIBL_E_HEMI_XFER_MAGIC, "not a transfer export (magic)")                                          \
    /* hemi export: version, bands, frac_bits, reserved or count not as documented */                   \
    X(QIBL_E_HEMI_XFER_FORMAT, "transfer export: version, bands, frac_bits, reserved or count unsupported") \
    /* hemi export: size not the header plus count * bands^2 * 4 bytes */                               \
    X(QIBL_E_HEMI_XFER_SIZE, "transfer export size differs from its fields")                            \
    /* hemi export: payload CRC-32 mismatch */                                                          \
    X(QIBL_E_HEMI_XFER_CRC, "transfer export CRC-32 mismatch")                                          \
    /* hemi export: span past the vertices */                                                           \
    X(QIBL_E_HEMI_XFER_BOUNDS, "span outside the exported vertices")                                    \
    /* hemi tables blob (hemi.h, qibl_hemi_tables_build, qibl_hemi_open) */                             \
    /* hemi tables: span past the blob's words */                                                      \
    X(QIBL_E_HEMI_TABLES_BOUNDS, "span outside the hemi tables' words")                                 \
    /* hemi tables: blob not on a 4-byte boundary (it is read in place as uint32 words) */              \
    X(QIBL_E_HEMI_TABLES_ALIGN, "hemi tables not 4-byte aligned")                                       \
    /* hemi tables: size not qibl_hemi_tables_size(n, face) (truncated, or trailing bytes) */          \
    X(QIBL_E_HEMI_TABLES_SIZE, "hemi tables size differs from qibl_hemi_tables_size")                   \
    /* hemi tables: not "QHMT" (or another byte order) */                                              \
    X(QIBL_E_HEMI_TABLES_MAGIC, "not hemi tables (magic)")                                              \
    /* hemi tables: version not QIBL_HEMI_TABLES_VERSION */                                            \
    X(QIBL_E_HEMI_TABLES_VERSION, "hemi tables: unsupported version")                                   \
    /* hemi tables: made for another mask size or face size */                                         \
    X(QIBL_E_HEMI_TABLES_SHAPE, "hemi tables made for another mask or face size")                       \
    /* hemi tables: header's size or reserved words not as documented */                               \
    X(QIBL_E_HEMI_TABLES_HEADER, "hemi tables: header size or reserved words wrong")                    \
    /* hemi tables: payload CRC-32 mismatch */                                                         \
    X(QIBL_E_HEMI_TABLES_CRC, "hemi tables CRC-32 mismatch")

typedef enum qibl_status {
#define QIBL_STATUS_ENUM_(name, message) name,
    QIBL_STATUS_LIST(QIBL_STATUS_ENUM_)
#undef QIBL_STATUS_ENUM_
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
