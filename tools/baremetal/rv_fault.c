/* baremetal/rv_fault.c - what crt_rv.S calls on a trap: say so and exit non-zero. */
#include "semi.h"

void bm_fault(void) __attribute__((noreturn));

void bm_fault(void)
{
    bm_puts("baremetal: TRAP (illegal instruction or bad access)\n");
    bm_exit(1);
}
