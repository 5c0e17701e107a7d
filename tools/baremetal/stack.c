/*
 * baremetal/stack.c - see stack.h.
 */
#include "stack.h"

extern uint32_t __stack_limit[], __stack_top[];

static uintptr_t current_sp(void)
{
    uintptr_t sp;
#if defined(__arm__)
    __asm__ volatile("mov %0, sp" : "=r"(sp));
#else
    __asm__ volatile("mv %0, sp" : "=r"(sp));
#endif
    return sp;
}

void bm_stack_paint(void)
{
    /* everything below this frame, less a margin for the frame itself */
    volatile uint32_t *p = __stack_limit, *end = (volatile uint32_t *)((current_sp() - 64u) & ~(uintptr_t)3);
    while (p < end)
        *p++ = BM_STACK_PATTERN;
}

size_t bm_stack_size(void)
{
    return (size_t)((uintptr_t)__stack_top - (uintptr_t)__stack_limit);
}

size_t bm_stack_high_water(void)
{
    const volatile uint32_t *p = __stack_limit;
    while (p < __stack_top && *p == BM_STACK_PATTERN)
        ++p;
    return (size_t)((uintptr_t)__stack_top - (uintptr_t)p);
}
