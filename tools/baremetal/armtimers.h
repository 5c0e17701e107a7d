/*
 * baremetal/armtimers.h - the timer block that the Game Boy Advance and the Nintendo DS's ARM9
 * share (0x04000100, four 16-bit timers): timers 0..2 cascaded into a 48-bit tick count, for
 * gba_io.c and nds_io.c's bm_clock_start and bm_insn_clock. Timer 3 stays free.
 */
#ifndef QTOOL_BM_ARMTIMERS_H
#define QTOOL_BM_ARMTIMERS_H

#include <stdint.h>

#define BM_TM_L(i) (*(volatile uint16_t *)(0x04000100u + 4u * (i)))
#define BM_TM_H(i) (*(volatile uint16_t *)(0x04000102u + 4u * (i)))

static inline void bm_armtimers_start(void)
{
    for (unsigned i = 0; i < 3; ++i)
        BM_TM_H(i) = 0, BM_TM_L(i) = 0; /* stop, reload value 0 */
    BM_TM_H(2) = 0x84, BM_TM_H(1) = 0x84; /* enabled, count-up (cascade) */
    BM_TM_H(0) = 0x80;                    /* enabled, prescaler 1 */
}

static inline uint64_t bm_armtimers_read(void)
{
    uint16_t hi, mid, lo;
    do {
        hi = BM_TM_L(2), mid = BM_TM_L(1), lo = BM_TM_L(0);
    } while (hi != BM_TM_L(2) || mid != BM_TM_L(1)); /* a carry between the reads */
    return (uint64_t)hi << 32 | (uint64_t)mid << 16 | lo;
}

#endif
