/*
 * gba/gba_io.c - what a bare-metal run needs from the Game Boy Advance, behind tools/baremetal/
 * semi.h (so main.c, heap.c, stack.c and the probes serve the GBA as they serve the MCU boards):
 * text out and exit through mGBA's debug registers, a cycle clock from the hardware timers, and
 * the C reset that crt_gba.S enters (its copies; then handheld/hh_start.c: .bss, TLS, stack paint).
 *
 * mGBA's debug port: writing 0xC0DE to 0x04FFF780 enables it; a message is up to 255 bytes at
 * 0x04FFF600, sent by writing 0x100 | level to 0x04FFF700. Protocol with tools/gba/host.c: a line
 * is sent at level INFO (3) without its '\n'; a line longer than the buffer goes out in pieces at
 * level DEBUG (4, "continued"); the exit status is one WARN (2) message "exit <n>", after which the
 * ROM halts. Nothing here runs on real hardware's output path (no debug port there): the ROM still
 * runs, its text goes nowhere.
 */
#include <stdint.h>
#include <string.h>

#include "handheld/hh_start.h"
#include "semi.h"

#define DBG_ENABLE (*(volatile uint16_t *)0x04FFF780u)
#define DBG_FLAGS (*(volatile uint16_t *)0x04FFF700u)
#define DBG_STRING ((volatile char *)0x04FFF600u)
enum { LINE = 255, SEND = 0x100, LV_WARN = 2, LV_INFO = 3, LV_DEBUG = 4 };

static char line[LINE];
static unsigned used;
static int enabled;

static void send(unsigned level)
{
    if (!enabled) {
        DBG_ENABLE = 0xC0DE;
        enabled = 1;
    }
    for (unsigned i = 0; i < used; ++i)
        DBG_STRING[i] = line[i];
    DBG_STRING[used] = '\0';
    DBG_FLAGS = (uint16_t)(SEND | level);
    used = 0;
}

void bm_puts(const char *s)
{
    for (; *s != '\0'; ++s) {
        if (*s == '\n') {
            send(LV_INFO);
            continue;
        }
        if (used == LINE)
            send(LV_DEBUG);
        line[used++] = *s;
    }
}

void bm_exit(int status)
{
    if (used != 0)
        send(LV_DEBUG);
    bm_puts("exit ");
    if (status < 0) {
        bm_puts("-");
        bm_putu(0u - (uint32_t)status);
    } else {
        bm_putu((uint32_t)status);
    }
    send(LV_WARN);
    for (;;)
        ;
}

/* bm_insn_clock (armtimers.c) counts CPU cycles, 16 777 216 Hz; cycles -> ns: 10^9 / 2^24 =
 * 1953125 / 2^15; split so that no product passes 2^64 (c < 2^48) */
uint64_t bm_clock_ns(void)
{
    uint64_t c = bm_insn_clock();
    return (c >> 15) * 1953125u + ((c & 0x7FFFu) * 1953125u >> 15);
}

extern uint32_t __data_load[], __data_start[], __data_end[];
extern uint32_t __iwram_load[], __iwram_start[], __iwram_end[];
void gba_reset(void) __attribute__((noreturn));

void gba_reset(void)
{
    /* cartridge wait states 3/1 with the prefetch buffer (the power-on 4/2 without it makes Thumb
     * code in ROM half as fast); what every GBA game sets first */
    *(volatile uint16_t *)0x04000204u = 0x4317;
    for (uint32_t *s = __data_load, *d = __data_start; d < __data_end;)
        *d++ = *s++;
    for (uint32_t *s = __iwram_load, *d = __iwram_start; d < __iwram_end;)
        *d++ = *s++;
    hh_start();
}
