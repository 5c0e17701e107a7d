/* gba/relight_arm.S - the demo ROM's relight kernel for one channel of one row, ARM code in IWRAM
 * (demo.c relight_dma_arm calls it; the frame's CRC-32 against the host's proves its bytes).
 *
 * The same integers as the core's portable kernel (core/src/shmap.c chan_words, the fast final
 * scaling): for each pixel u = u0 + sum_i w_i * c_i in uint32 (wrapping), out = bb + (u >> r).
 * What it does that GCC does not: the eight accumulators, both map words, the weight, the byte
 * and the source pointer all stay in registers (r0-r12, lr), the map loop is unrolled (entered
 * part-way for k < 9, one computed jump per step), each byte is one AND (lsr folded in) and one
 * MLA with the byte as the multiplier (ARM7TDMI's early termination: 3 cycles), and the planes
 * are read from IWRAM, where demo.c's DMA put them, 240 bytes apart (immediate offsets).
 *
 * void gba_relight8(const uint8_t *src, const uint32_t *frame)
 *   src    map 0's bytes of the row (IWRAM); map at position p (below) at src + 240 p; 8n pixels
 *   frame  15 words: [0] out (int32 *, the channel's first value; pixels 12 bytes apart),
 *          [1] r (1..30), [2] bb, [3] end (src + 8n, n >= 1), [4] u0, [5] k (1..9),
 *          [6 + p] the int32 weight of the map at position p: map 0 at position 0, map j >= 1 at
 *          position 9 - k + j (so that the unrolled positions 10 - k .. 8 are the maps 1 .. k - 1)
 * Stack: 60 bytes of frame copy and 36 of saved registers. Interrupts may stay enabled (no sp
 * tricks); no memory is written but the frame copy and out. */
    .syntax unified
    .section .iwram.gba_relight8, "ax", %progbits
    .arm
    .align 2
    .global gba_relight8
    .type gba_relight8, %function

    .equ PITCH, 240             @ bytes from one map's row piece to the next (demo.c's line buffer)
    .equ F_K, 20                @ frame offsets on the stack
    .equ F_U0, 16
    .equ F_W, 24
    .equ MAP_BYTES, 76          @ the code of one MAP below (19 instructions)

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

@ the map at position p (1..8): weight, both words of the eight pixels, sixteen instructions
    .macro MAP p
    ldr r11, [sp, #F_W + 4 * \p]
    add r10, r12, #PITCH * \p
    ldmia r10, {r8, r9}
    BYTES r8, r0, r1, r2, r3, r0, r1, r2, r3
    BYTES r9, r4, r5, r6, r7, r4, r5, r6, r7
    .endm

@ map 0 starts the sums at u0 (r9 holds it; the words come one at a time), then the jump to the
@ position of map 1
    .macro FIRST
    ldr r11, [sp, #F_W]
    ldr r9, [sp, #F_U0]
    ldr r8, [r12]
    BYTES r8, r0, r1, r2, r3, r9, r9, r9, r9
    ldr r8, [r12, #4]
    BYTES r8, r4, r5, r6, r7, r9, r9, r9, r9
    ldr pc, [sp, #F_K]
    .endm

gba_relight8:
    push {r4-r11, lr}
    sub sp, sp, #60
    ldmia r1!, {r2-r9}          @ the frame onto the stack (sp is the only base register left)
    stmia sp, {r2-r9}
    ldmia r1, {r2-r8}
    add r9, sp, #32
    stmia r9, {r2-r8}
    ldr r2, [sp, #F_K]          @ the entry: map_pos1 + (9 - k) * MAP_BYTES (k = 1: final)
    rsb r2, r2, #9
    mov r3, #MAP_BYTES
    adr r4, map_pos1
    mla r4, r2, r3, r4
    str r4, [sp, #F_K]
    mov r12, r0
    mov lr, #255
    FIRST
map_pos1:
    MAP 1
    MAP 2
    MAP 3
    MAP 4
    MAP 5
    MAP 6
    MAP 7
    MAP 8
    .if . - map_pos1 != 8 * MAP_BYTES
    .error "MAP is not MAP_BYTES long"
    .endif
    @ out = bb + (u >> r) for the eight pixels, then the next eight
    ldmia sp, {r8, r9, r10, r11} @ out, r, bb, end
    add lr, r10, r0, lsr r9
    str lr, [r8], #12
    add lr, r10, r1, lsr r9
    str lr, [r8], #12
    add lr, r10, r2, lsr r9
    str lr, [r8], #12
    add lr, r10, r3, lsr r9
    str lr, [r8], #12
    add lr, r10, r4, lsr r9
    str lr, [r8], #12
    add lr, r10, r5, lsr r9
    str lr, [r8], #12
    add lr, r10, r6, lsr r9
    str lr, [r8], #12
    add lr, r10, r7, lsr r9
    str lr, [r8], #12
    str r8, [sp]
    add r12, r12, #8
    mov lr, #255
    cmp r12, r11
    beq done                    @ (the next step's map 0 here, not behind a taken branch: 2 cycles)
    FIRST
done:
    add sp, sp, #60
    pop {r4-r11, lr}
    bx lr
    .size gba_relight8, . - gba_relight8
