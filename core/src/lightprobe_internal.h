/*
 * lightprobe_internal.h - internal to the core (qibli_*): the light-probe module's exact pixel
 * decoding and rational-angle sine, shared with the SH projection (probe.c) so that both read a
 * probe the same way. Not a public API: it may change with lightprobe.c.
 */
#ifndef QIBL_LIGHTPROBE_INTERNAL_H
#define QIBL_LIGHTPROBE_INTERNAL_H

#include <stddef.h>
#include <stdint.h>
#include "qibl/lightprobe.h"

#ifdef __cplusplus
extern "C" {
#endif

/* flags qibli_lightprobe_decode returns */
#define QIBLI_PROBE_BAD_NEGATIVE 1u
#define QIBLI_PROBE_BAD_NOT_FINITE 2u

/* A probe's status from its pixels' flags (lightprobe and the SH projection refuse alike): a
 * non-finite channel before a negative one. */
static inline qibl_status_t qibli_probe_bad_status(unsigned bad)
{
    if (bad & QIBLI_PROBE_BAD_NOT_FINITE)
        return QIBL_E_PROBE_NOT_FINITE;
    if (bad & QIBLI_PROBE_BAD_NEGATIVE)
        return QIBL_E_PROBE_NEGATIVE;
    return QIBL_OK;
}

/* Bytes per pixel of a format (4 or 12). */
size_t qibli_lightprobe_pixel_bytes(qibl_lightprobe_format_t f);

/* Decodes one pixel exactly: P_c = m[c] 2^*eps / D (D = 510 for SRGBE, else 1); m[c] < 2^8 (RGBE,
 * SRGBE), < 2^31 (LINEAR_I32), < 2^47 (LINEAR_F32, channels aligned to the largest one's exponent
 * with 23 extra bits). Bad channels (negative, NaN, Inf) read as 0 and set the returned flags. p is
 * 4-byte aligned for the 32-bit formats. */
unsigned qibli_lightprobe_decode(qibl_lightprobe_format_t f, const uint8_t *p, int32_t frac_bits, uint64_t m[3],
                                 int32_t *eps);

/* sin(pi n / d) for 0 < n < d < 2^32 as *mant in [2^31, 2^32) times 2^-(32 + *kap), relative error
 * <= 2^-31 (the row-weight table of lightprobe.h). */
void qibli_lightprobe_sin_frac(uint64_t n, uint64_t d, uint32_t *mant, int32_t *kap);

#ifdef __cplusplus
}
#endif

#endif
