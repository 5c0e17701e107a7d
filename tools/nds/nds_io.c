/*
 * nds/nds_io.c - what a bare-metal run needs from the Nintendo DS's ARM9, behind tools/baremetal/
 * semi.h (so main.c, heap.c, stack.c and the probes serve the DS as they serve the MCU boards and
 * the GBA): text out and exit through DeSmuME's debug print (nds_print, crt_nds.S), a clock from
 * the ARM9's hardware timers, and the C reset that crt_nds.S enters (then handheld/hh_start.c).
 *
 * Protocol with tools/nds/desmume_run.py: DeSmuME's standard output mixes the emulator's own
 * messages with the ROM's, so every line of the ROM goes out whole, as "nds: <line>\n" (one print
 * per line, 256 bytes at most; a longer line continues in "nds+ <rest>\n" lines); the exit status
 * is one line "nds-exit <n>", after which the ARM9 halts. On real hardware the prints are an
 * unknown SWI: the ROM still runs, its text goes nowhere.
 */
#include <stdint.h>
#include <string.h>

#include "handheld/hh_start.h"
#include "semi.h"

void nds_print(const char *s); /* crt_nds.S: SWI 0xFC */

enum { LINE = 256, PREFIX = 5 };
static char line[PREFIX + LINE + 2] = "nds: ";
static unsigned used;

static void send(void)
{
    line[PREFIX + used] = '\n';
    line[PREFIX + used + 1] = '\0';
    nds_print(line);
    memcpy(line, "nds+ ", PREFIX); /* what follows continues this line, unless a newline came */
    used = 0;
}

void bm_puts(const char *s)
{
    for (; *s != '\0'; ++s) {
        if (*s == '\n') {
            send();
            memcpy(line, "nds: ", PREFIX);
            continue;
        }
        if (used == LINE)
            send();
        line[PREFIX + used++] = *s;
    }
}

void bm_exit(int status)
{
    if (used != 0)
        bm_puts("\n");
    static char msg[24] = "nds-exit ";
    unsigned n = 9;
    uint32_t u = status < 0 ? 0u - (uint32_t)status : (uint32_t)status;
    char b[11];
    int i = 10;
    do
        b[--i] = (char)('0' + u % 10u);
    while ((u /= 10u) != 0);
    if (status < 0)
        msg[n++] = '-';
    while (i < 10)
        msg[n++] = b[i++];
    msg[n++] = '\n', msg[n] = '\0';
    nds_print(msg);
    for (;;)
        __asm__ volatile("swi 0x06"); /* Halt: IME is 0, nothing wakes the ARM9 again */
}

/* bm_insn_clock (armtimers.c) counts the ARM9's bus clock, 33 513 982 Hz (half the CPU's 67 MHz) */
enum { BUS_HZ = 33513982 };

/* ticks -> ns in two parts, so that no product passes 2^64 (ticks < 2^48, remainder < 2^25) */
uint64_t bm_clock_ns(void)
{
    uint64_t c = bm_insn_clock();
    return c / BUS_HZ * 1000000000u + c % BUS_HZ * 1000000000u / BUS_HZ;
}

void nds_reset(void) __attribute__((noreturn));

void nds_reset(void)
{
    *(volatile uint32_t *)0x04000208u = 0; /* IME: no interrupts (there are no handlers) */
    hh_start();
}
