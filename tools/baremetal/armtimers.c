/*
 * baremetal/armtimers.c - bm_clock_start and bm_insn_clock of semi.h on the timer block that the
 * Game Boy Advance and the Nintendo DS's ARM9 share (0x04000100, four 16-bit timers): timers 0..2
 * cascaded into a 48-bit tick count (the GBA's CPU cycles, the DS's bus clock: gba_io.c and
 * nds_io.c turn ticks into bm_clock_ns). Timer 3 stays free.
 */
#include <stdint.h>

#include "semi.h"

#define TM_L(i) (*(volatile uint16_t *)(0x04000100u + 4u * (i)))
#define TM_H(i) (*(volatile uint16_t *)(0x04000102u + 4u * (i)))

void bm_clock_start(void)
{
    for (unsigned i = 0; i < 3; ++i)
        TM_H(i) = 0, TM_L(i) = 0; /* stop, reload value 0 */
    TM_H(2) = 0x84, TM_H(1) = 0x84; /* enabled, count-up (cascade) */
    TM_H(0) = 0x80;                 /* enabled, prescaler 1 */
}

uint64_t bm_insn_clock(void)
{
    uint16_t hi, mid, lo;
    do {
        hi = TM_L(2), mid = TM_L(1), lo = TM_L(0);
    } while (hi != TM_L(2) || mid != TM_L(1)); /* a carry between the reads */
    return (uint64_t)hi << 32 | (uint64_t)mid << 16 | lo;
}
