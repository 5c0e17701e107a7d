/*
 * baremetal/crt_cm.c - reset for Cortex-M (ARMv6-M and ARMv7-M): the vector table, .data copied
 * from flash, .bss zeroed, the stack painted (stack.h), then main and a semihosting exit. Faults
 * print their name and exit non-zero, so a crash cannot pass for a run.
 */
#include <stdint.h>

#include "semi.h"
#include "stack.h"

extern uint32_t __data_load[], __data_start[], __data_end[], __bss_start[], __bss_end[];
extern uint32_t __stack_top[];
int main(void);
void bm_reset(void) __attribute__((noreturn));
void bm_fault(void) __attribute__((noreturn));

void bm_reset(void)
{
    for (uint32_t *s = __data_load, *d = __data_start; d < __data_end;)
        *d++ = *s++;
    for (uint32_t *d = __bss_start; d < __bss_end;)
        *d++ = 0;
    bm_stack_paint();
    bm_exit(main());
}

/* the exception frame the core stacked: r0-r3, r12, lr, pc, xpsr */
void bm_fault_frame(const uint32_t *frame) __attribute__((noreturn));
void bm_fault_frame(const uint32_t *frame)
{
    bm_puts("baremetal: FAULT (hard fault, bad access or undefined instruction) at pc ");
    bm_putu(frame[6]), bm_puts(", lr "), bm_putu(frame[5]), bm_puts("\n");
    bm_exit(1);
}

__attribute__((naked)) void bm_fault(void)
{
    __asm__ volatile("mrs r0, msp\n b bm_fault_frame");
}

typedef void (*vector_fn)(void);
/* initial SP, reset, NMI, HardFault, MemManage, BusFault, UsageFault */
__attribute__((section(".vectors"), used)) static const vector_fn vectors[7] = {
    (vector_fn)(uintptr_t)__stack_top, bm_reset, bm_fault, bm_fault, bm_fault, bm_fault, bm_fault,
};
