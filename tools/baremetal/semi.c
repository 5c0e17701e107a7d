/*
 * baremetal/semi.c - semihosting output and exit, and the emulated clock (see semi.h; bm_putu
 * is putu.c's).
 */
#include "semi.h"

enum { SYS_WRITE0 = 0x04, SYS_EXIT = 0x18 };
enum { ADP_STOPPED_APPLICATION_EXIT = 0x20026, ADP_STOPPED_RUNTIME_ERROR = 0x20023 };

static uintptr_t semi_call(uintptr_t op, uintptr_t arg)
{
#if defined(__arm__)
    register uintptr_t r0 __asm__("r0") = op;
    register uintptr_t r1 __asm__("r1") = arg;
    __asm__ volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
#elif defined(__riscv)
    register uintptr_t a0 __asm__("a0") = op;
    register uintptr_t a1 __asm__("a1") = arg;
    /* the semihosting trap: an ebreak between these two no-op shifts, uncompressed and in one page */
    __asm__ volatile(".option push\n .option norvc\n .balign 16\n"
                     "slli x0, x0, 0x1f\n ebreak\n srai x0, x0, 7\n .option pop"
                     : "+r"(a0) : "r"(a1) : "memory");
    return a0;
#else
#error "semihosting: ARM or RISC-V only"
#endif
}

void bm_puts(const char *s)
{
    (void)semi_call(SYS_WRITE0, (uintptr_t)s);
}

void bm_exit(int status)
{
    /* 32-bit semihosting: the reason code itself is the argument; qemu exits 0 for
     * ApplicationExit and 1 for anything else */
    for (;;)
        (void)semi_call(SYS_EXIT, status == 0 ? ADP_STOPPED_APPLICATION_EXIT : ADP_STOPPED_RUNTIME_ERROR);
}

#if defined(__arm__)
/* MPS2 (AN385/AN386): CMSDK APB timer 0 at 0x40000000, a 32-bit down-counter at the 25 MHz
 * peripheral clock, which qemu drives from its virtual clock. */
#define TIMER0 ((volatile uint32_t *)0x40000000u)
enum { T_CTRL = 0, T_VALUE = 1, T_RELOAD = 2 };
enum { TICK_NS = 40 };

void bm_clock_start(void)
{
    TIMER0[T_CTRL] = 0;
    TIMER0[T_RELOAD] = 0xFFFFFFFFu;
    TIMER0[T_VALUE] = 0xFFFFFFFFu;
    TIMER0[T_CTRL] = 1; /* enable, no interrupt */
}

uint64_t bm_clock_ns(void)
{
    return (uint64_t)(0xFFFFFFFFu - TIMER0[T_VALUE]) * TICK_NS;
}

uint64_t bm_insn_clock(void)
{
    return bm_clock_ns();
}
#else
/* RISC-V virt: the CLINT mtime at 0x0200BFF8, 10 MHz */
#define MTIME ((volatile uint32_t *)0x0200BFF8u)
static uint64_t rv_mtime(void)
{
    uint32_t hi, lo;
    do {
        hi = MTIME[1];
        lo = MTIME[0];
    } while (hi != MTIME[1]);
    return (uint64_t)hi << 32 | lo;
}
static uint64_t rv_t0;
void bm_clock_start(void)
{
    rv_t0 = rv_mtime();
}
uint64_t bm_clock_ns(void)
{
    return (rv_mtime() - rv_t0) * 100u;
}

/* rdinstret / rdinstreth (CSRs 0xC02, 0xC82: the .insn immediate is their signed 12-bit form),
 * spelled with .insn because the assembler wants zicsr/zicntr for the names */
uint64_t bm_insn_clock(void)
{
    uint32_t hi, lo, hi2;
    do {
        __asm__ volatile(".insn i SYSTEM, 2, %0, x0, -894" : "=r"(hi));
        __asm__ volatile(".insn i SYSTEM, 2, %0, x0, -1022" : "=r"(lo));
        __asm__ volatile(".insn i SYSTEM, 2, %0, x0, -894" : "=r"(hi2));
    } while (hi != hi2);
    return (uint64_t)hi << 32 | lo;
}
#endif
