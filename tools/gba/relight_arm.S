/* gba/relight_arm.S - the demo ROM's relight kernels for one channel of one row, ARM code in IWRAM
 * (iwram_relight.c calls them; the frame's CRC-32 against the host's proves their bytes).
 *
 * The same integers as the core's portable kernel (core/src/shmap.c chan_words, the fast final
 * scaling): for each pixel u = u0 + sum_i w_i * c_i in uint32 (wrapping), out = bb + (u >> r).
 * What they do that GCC does not: the eight accumulators, both map words, the weight, the byte
 * and the source pointer all stay in registers (r0-r12, lr); the map loop is unrolled for one k;
 * each map's two words of the eight pixels come from cartridge ROM in one LDM (a sequential burst:
 * the second word at the ROM's sequential wait state); each byte is one AND (lsr folded in) and
 * one MLA with the byte as the multiplier (ARM7TDMI's early termination: 3 cycles). The weights
 * and the planes' offsets are walked off the stack (sp is the only base register left), two per
 * map in one LDM. One kernel per k the demo uses (4 and 9); other k go to the core.
 *
 * void gba_relight8_k<k>(const uint8_t *src, const uint32_t *frame)
 *   src    map 0's bytes of the row (word-aligned); map j's at src + off_j; 8n pixels
 *   frame  24 words (those past 2k + 4 copied, not read): [0] u0, [1] map 0's weight (int32),
 *          then for j = 1 .. k-1: off_j, map j's weight; then out (int32 *, the channel's first
 *          value; pixels 12 bytes apart), r (1..30), bb, end (src + 8n, n >= 1)
 * Stack: 96 bytes of frame copy and 36 of saved registers. Interrupts may stay enabled (sp stays
 * a stack pointer, below what it holds); nothing is written but the frame copy and out. */
    .syntax unified
    .section .iwram.gba_relight8, "ax", %progbits
    .arm
    .align 2

    .equ FRAME, 96

@ the four bytes of word v into accumulators a..d from n0..n3 (r11: the weight, r10: scratch,
@ lr: 255)
    .macro BYTES v, a, b, c, d, n0, n1, n2, n3
    and r10, \v, #255
    mla \a, r11, r10, \n0
    and r10, lr, \v, lsr #8
    mla \b, r11, r10, \n1
    and r10, lr, \v, lsr #16
    mla \c, r11, r10, \n2
    mov r10, \v, lsr #24
    mla \d, r11, r10, \n3
    .endm

    .macro KERNEL name, k
    .global \name
    .type \name, %function
\name:
    push {r4-r11, lr}
    sub sp, sp, #FRAME
    mov r12, sp
    .rept (2 * \k + 4 + 3) / 4
    ldmia r1!, {r2-r5}
    stmia r12!, {r2-r5}
    .endr
    mov r12, r0
    mov lr, #255
1:
    @ map 0 starts the sums at u0 (r9); its second word waits in r7, written last
    ldmia sp!, {r9, r11}
    ldmia r12, {r7, r8}
    BYTES r7, r0, r1, r2, r3, r9, r9, r9, r9
    BYTES r8, r4, r5, r6, r7, r9, r9, r9, r9
    .rept \k - 1
    ldmia sp!, {r10, r11}       @ the plane's offset, the weight
    add r10, r12, r10
    ldmia r10, {r8, r9}
    BYTES r8, r0, r1, r2, r3, r0, r1, r2, r3
    BYTES r9, r4, r5, r6, r7, r4, r5, r6, r7
    .endr
    @ out = bb + (u >> r) for the eight pixels, then the next eight
    ldmia sp, {r8, r9, r10, r11} @ out, r, bb, end
    .irp a, r0, r1, r2, r3, r4, r5, r6, r7
    add lr, r10, \a, lsr r9
    str lr, [r8], #12
    .endr
    str r8, [sp]
    sub sp, sp, #(8 * \k)       @ back to map 0's pair
    add r12, r12, #8
    mov lr, #255
    cmp r12, r11
    bne 1b
    add sp, sp, #FRAME
    pop {r4-r11, lr}
    bx lr
    .size \name, . - \name
    .endm

    KERNEL gba_relight8_k4, 4
    KERNEL gba_relight8_k9, 9
