/*
 * baremetal/putu.c - bm_putu of semi.h over the target's bm_puts: one decimal writer for the MCU
 * boards (semi.c), the GBA (gba_io.c) and the DS (nds_io.c).
 */
#include "semi.h"

void bm_putu(uint32_t v)
{
    char b[11]; /* 10 digits of 2^32 - 1 and the NUL */
    int i = 10;
    b[i] = '\0';
    do
        b[--i] = (char)('0' + v % 10u);
    while ((v /= 10u) != 0);
    bm_puts(b + i);
}
