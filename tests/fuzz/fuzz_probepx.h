/*
 * fuzz/fuzz_probepx.h - what the probe targets (fuzz_lightprobe.c, fuzz_probe.c) share: how
 * lightprobe.h reads one pixel of each format, to predict which statuses a probe must get.
 */
#ifndef QTOOL_FUZZ_PROBEPX_H
#define QTOOL_FUZZ_PROBEPX_H

#include <stdint.h>
#include <string.h>

#include "qibl/lightprobe.h"

/* a pixel of the format: zero / has a negative / has a non-finite channel (as lightprobe.h reads them) */
static inline void classify(const uint8_t *px, qibl_lightprobe_format_t f, int *zero, int *neg, int *nonfinite)
{
    *zero = 1, *neg = 0, *nonfinite = 0;
    for (int c = 0; c < 3; ++c) {
        if (f == QIBL_LIGHTPROBE_RGBE) {
            if (px[3] != 0 && px[c] != 0)
                *zero = 0;
        } else if (f == QIBL_LIGHTPROBE_SRGBE) {
            if (px[c] < 127)
                *neg = 1, *zero = 0;
            else if (px[c] > 128)
                *zero = 0;
        } else {
            uint32_t u;
            memcpy(&u, px + 4 * c, 4);
            if (f == QIBL_LIGHTPROBE_LINEAR_I32) {
                if (u >> 31)
                    *neg = 1;
                if (u)
                    *zero = 0;
            } else {
                if ((u & 0x7F800000u) == 0x7F800000u)
                    *nonfinite = 1;
                else if ((u & 0x7FFFFFFFu) && (u >> 31))
                    *neg = 1;
                if (u & 0x7FFFFFFFu)
                    *zero = 0;
            }
        }
    }
}

#endif
