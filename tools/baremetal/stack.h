/*
 * baremetal/stack.h - stack painting: the reset code fills the whole stack with a pattern before
 * main; bm_stack_high_water() then finds the deepest word ever written. The wrapped entry points
 * (probe.S) repaint below their caller's stack pointer and measure what the core call alone used.
 */
#ifndef QTOOL_BAREMETAL_STACK_H
#define QTOOL_BAREMETAL_STACK_H

#include <stddef.h>
#include <stdint.h>

#define BM_STACK_PATTERN 0xC5A5C5A5u

void bm_stack_paint(void);
size_t bm_stack_size(void);
size_t bm_stack_high_water(void); /* bytes below the top of the stack ever written */

#endif
