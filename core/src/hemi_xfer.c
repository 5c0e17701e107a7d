/*
 * hemi_xfer.c - exported transfer (hemi.h, qibl_hemi_xfer_*): a static mesh's per-vertex transfer
 * vectors, as `qibl transfer --export` writes them, validated once and shaded per span of vertices.
 *
 * Invariants: integer only, no heap, no state; every field is read byte by byte in little-endian
 * order (no cast of the caller's bytes, so any alignment works); the size is computed in 32 bits
 * after the count is capped (2^24 * 25 * 4 < 2^31: no wrap, and no 64-bit multiply helper on
 * targets without one). Magnitudes: |light| < 2^31, |v| < 2^31,
 * each product < 2^62, shifted right by 14: < 2^48; 25 of them: < 2^53 in int64.
 */
#include "qibl/hemi.h"
#include "qibl/asset.h"
#include "qibl/shmaps.h"

#if QIBL_USE_HEMI && QIBL_USE_ASSET

static uint32_t xfer_load_u16le(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8);
}

qibl_status_t qibl_hemi_xfer_open(qibl_hemi_xfer_t *x, const uint8_t *bytes, size_t n)
{
    if (x == 0 || bytes == 0)
        return QIBL_E_NULL_POINTER;
    if (n < QIBL_HEMI_XFER_HEADER_SIZE)
        return QIBL_E_HEMI_XFER_SHORT;
    if (bytes[0] != 'Q' || bytes[1] != 'T' || bytes[2] != 'R' || bytes[3] != 'X')
        return QIBL_E_HEMI_XFER_MAGIC;
    const uint32_t version = xfer_load_u16le(bytes + 4), bands = xfer_load_u16le(bytes + 6);
    const uint32_t count = qibl_load_u32le(bytes + 8), frac = qibl_load_u32le(bytes + 12);
    if (version != QIBL_HEMI_XFER_VERSION || bands < 3u || bands > 5u || frac != 30u ||
        qibl_load_u32le(bytes + 16) != 0u || count == 0u || count > QIBL_HEMI_XFER_MAX_VERTICES)
        return QIBL_E_HEMI_XFER_FORMAT;
    const uint32_t payload = count * bands * bands * 4u; /* count <= 2^24: < 2^24 * 100 < 2^31, no wrap */
    if (n - QIBL_HEMI_XFER_HEADER_SIZE != (size_t)payload) /* n >= the header: no wrap */
        return QIBL_E_HEMI_XFER_SIZE;
    const uint8_t *p = bytes + QIBL_HEMI_XFER_HEADER_SIZE;
    if (qibl_crc32(0u, p, payload) != qibl_load_u32le(bytes + 20))
        return QIBL_E_HEMI_XFER_CRC;
    x->payload = p, x->count = count, x->bands = bands, x->ncoef = bands * bands;
    return QIBL_OK;
}

qibl_status_t qibl_hemi_xfer_shade_span(const qibl_hemi_xfer_t *x, const int32_t light[3][QIBL_HEMI_COEFFS],
                                        uint32_t first, uint32_t count, qibl_q16_t (*out)[3])
{
    if (x == 0 || light == 0 || out == 0 || x->payload == 0)
        return QIBL_E_NULL_POINTER;
    if (first > x->count || count > x->count - first) /* unsigned: no wrap */
        return QIBL_E_HEMI_XFER_BOUNDS;
    const uint32_t nc = x->ncoef;
    for (uint32_t k = 0; k < count; ++k) {
        const uint8_t *v = x->payload + (size_t)(first + k) * nc * 4u;
        for (int ch = 0; ch < 3; ++ch) {
            int64_t s = 0; /* at most 25 terms below 2^48 each */
            for (uint32_t i = 0; i < nc; ++i)
                s += qibl_asr_s64(qibl_mul_s32_s64(light[ch][i], qibl_load_s32le(v + 4u * i)), 14);
            out[k][ch] = qibl_rshr_s64(s, 16);
        }
    }
    return QIBL_OK;
}

#else
typedef int qibl_hemi_xfer_compiled_out; /* ISO C wants a declaration in every translation unit */
#endif /* QIBL_USE_HEMI && QIBL_USE_ASSET */
