/*
 * baremetal/crt_cm.c - reset for Cortex-M (ARMv6-M and ARMv7-M): the vector table, .data copied
 * from flash, .bss zeroed, the TLS block set up (.tdata copied, .tbss zeroed, the thread pointer
 * set with picolibc's _set_tls: errno lives there), the stack painted (stack.h), then main and a
 * semihosting exit. Faults print their name and exit non-zero, so a crash cannot pass for a run.
 */
#include <stdint.h>

#include "semi.h"
#include "stack.h"

extern uint32_t __data_load[], __data_start[], __data_end[], __bss_start[], __bss_end[];
extern uint32_t __stack_top[];
/* the TLS block of cm.ld (word-aligned and word-sized by the script) */
extern uint32_t __tls_base[], __tdata_source[], __tdata_size[], __tbss_start[], __tbss_size[];
void _set_tls(void *tls); /* picolibc: __aeabi_read_tp then returns tls - the TCB offset */
int main(void);
void bm_reset(void) __attribute__((noreturn));
void bm_fault(void) __attribute__((noreturn));

void bm_reset(void)
{
    for (uint32_t *s = __data_load, *d = __data_start; d < __data_end;)
        *d++ = *s++;
    for (uint32_t *d = __bss_start; d < __bss_end;)
        *d++ = 0;
    /* without this the thread pointer is 0 and errno lands at address 8 (the NMI vector) */
    const uint32_t *ts = __tdata_source;
    uint32_t *td = __tls_base;
    for (uintptr_t i = 0; i < (uintptr_t)__tdata_size / 4u; ++i)
        *td++ = *ts++;
    for (uint32_t *d = __tbss_start, i = 0; i < (uintptr_t)__tbss_size / 4u; ++i)
        *d++ = 0;
    _set_tls(__tls_base);
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
