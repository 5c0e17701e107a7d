/* gba/relight_arm.S - the demo ROM's relight kernels for one channel of one row, ARM code in IWRAM
 * (iwram_relight.c calls them; the frame's CRC-32 against the host's proves their bytes).
 *
 * The same integers as the core's portable kernel (core/src/shmap.c chan_words, the fast final
 * scaling): for each pixel u = u0 + sum_i w_i * c_i in uint32 (wrapping), out = bb + (u >> r).
 * What they do that GCC does not: the eight accumulators, both map words, the weight, the byte
 * and the source pointer all stay in registers (r0-r12, lr), the map loop is unrolled for one k,
 * each byte is one AND (lsr folded in) and one MLA with the byte as the multiplier (ARM7TDMI's
 * early termination: 3 cycles), and the planes are read from IWRAM, where iwram_relight.c's DMA
 * put them, 240 bytes apart (immediate offsets). One kernel per k the demo uses (4 and 9); a
 * generic one entered part-way by a computed jump cost 5 cycles a step more, and other k go to
 * the core.
 *
 * void gba_relight8_k<k>(const uint8_t *src, const uint32_t *frame)
 *   src    map 0's bytes of the row (IWRAM); map j's at src + 240 j; 8n pixels
 *   frame  14 words: [0] out (int32 *, the channel's first value; pixels 12 bytes apart),
 *          [1] r (1..30), [2] bb, [3] end (src + 8n, n >= 1), [4] u0, [5 + j] map j's weight
 *          (int32; words past k are copied, not read)
 * Stack: 56 bytes of frame copy and 36 of saved registers. Interrupts may stay enabled (sp stays
 * the stack); nothing is written but the frame copy and out. */
    .syntax unified
    .section .iwram.gba_relight8, "ax", %progbits
    .arm
    .align 2

    .equ PITCH, 240             @ bytes from one map's row piece to the next (iwram_relight.c)
    .equ F_U0, 16               @ frame offsets on the stack
    .equ F_W, 20

@ the four bytes of word v into accumulators a..d (r11: the weight, r10: scratch, lr: 255)
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

@ map p (1..8): its weight, both words of the eight pixels, sixteen MLA and extractions
    .macro MAP p
    ldr r11, [sp, #F_W + 4 * \p]
    add r10, r12, #PITCH * \p
    ldmia r10, {r8, r9}
    BYTES r8, r0, r1, r2, r3, r0, r1, r2, r3
    BYTES r9, r4, r5, r6, r7, r4, r5, r6, r7
    .endm

@ map 0 starts the sums at u0 (r9 holds it; the words come one at a time)
    .macro FIRST
    ldr r11, [sp, #F_W]
    ldr r9, [sp, #F_U0]
    ldr r8, [r12]
    BYTES r8, r0, r1, r2, r3, r9, r9, r9, r9
    ldr r8, [r12, #4]
    BYTES r8, r4, r5, r6, r7, r9, r9, r9, r9
    .endm

@ out = bb + (u >> r) for the eight pixels, then the next eight
    .macro FINAL
    ldmia sp, {r8, r9, r10, r11} @ out, r, bb, end
    .irp a, r0, r1, r2, r3, r4, r5, r6, r7
    add lr, r10, \a, lsr r9
    str lr, [r8], #12
    .endr
    str r8, [sp]
    add r12, r12, #8
    mov lr, #255
    cmp r12, r11
    .endm

    .macro KERNEL name, k
    .global \name
    .type \name, %function
\name:
    push {r4-r11, lr}
    sub sp, sp, #56
    ldmia r1!, {r2-r9}          @ the frame onto the stack (sp is the only base register left)
    stmia sp, {r2-r9}
    ldmia r1, {r2-r7}
    add r8, sp, #32
    stmia r8, {r2-r7}
    mov r12, r0
    mov lr, #255
1:
    FIRST
    .irp q, 1, 2, 3, 4, 5, 6, 7, 8
    .if \q < \k
    MAP \q
    .endif
    .endr
    FINAL
    bne 1b
    add sp, sp, #56
    pop {r4-r11, lr}
    bx lr
    .size \name, . - \name
    .endm

    KERNEL gba_relight8_k4, 4
    KERNEL gba_relight8_k9, 9
