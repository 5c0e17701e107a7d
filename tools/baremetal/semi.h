/*
 * baremetal/semi.h - the few services a bare-metal run needs from the emulator: text out, exit,
 * an instruction clock. Output and exit go through semihosting (ARM: BKPT 0xAB; RISC-V: the
 * slli/ebreak/srai sequence), which qemu-system-* serves with -semihosting-config enable=on.
 */
#ifndef QTOOL_BAREMETAL_SEMI_H
#define QTOOL_BAREMETAL_SEMI_H

#include <stddef.h>
#include <stdint.h>

void bm_puts(const char *s);                 /* writes s (no newline added) */
void bm_putu(uint32_t v);                    /* decimal */
void bm_exit(int status) __attribute__((noreturn));

/* A free-running counter of emulated time. Under qemu -icount shift=0 one guest instruction is one
 * nanosecond, so bm_clock_ns() counts instructions (in units of the board's timer tick). 0 if the
 * target has no such clock wired. */
void bm_clock_start(void);
uint64_t bm_clock_ns(void);

/* Instructions retired (under -icount shift=0): on ARM bm_clock_ns, quantised to the timer's
 * 40-instruction tick; on RISC-V the instret counter, which qemu derives from the same count
 * exactly (mtime's phase against the start of the run is not fixed, so it would jitter by a tick). */
uint64_t bm_insn_clock(void);

#endif
