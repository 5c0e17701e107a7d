/* nds/crt_nds.S - the reset code of the Nintendo DS ROMs (make nds): the ARM9's, the ARM7's, and
 * the one service the ROMs take from the emulator.
 *
 * The cartridge header is not here: tools/nds/ndsrom.py writes it (GBATEK's layout and CRC-16s)
 * from the two binaries objcopy cuts out of the one ELF that tools/nds/nds.ld links.
 * ARM9 (ARM946E-S, ARMv5TE): entered in ARM state at nds_start in main RAM, as the BIOS or an
 * emulator's direct boot leaves it; switches to System mode with interrupts off, sets sp and
 * enters nds_reset (C, Thumb) with bx. ARM7: idles in the BIOS's Halt with every interrupt
 * masked (IME = 0, IE = 0: nothing wakes it), so it costs the emulator next to nothing.
 * nds_print: DeSmuME prints the NUL-terminated string at r0 on its standard output when the ARM9
 * executes SWI 0xFC (no BIOS function has that number; real hardware's BIOS would take it as an
 * undefined SWI, so the golden ROM's text goes nowhere there). */
    .syntax unified
    .arm

    .section .text.nds_start, "ax", %progbits
    .global nds_start
    .type nds_start, %function
nds_start:
    msr cpsr_c, #0xDF           @ System mode, IRQ and FIQ masked
    ldr sp, =__stack_top
    ldr r0, =nds_reset
    bx r0
    .ltorg

    .section .text.nds_print, "ax", %progbits
    .global nds_print
    .type nds_print, %function
nds_print:                      @ void nds_print(const char *s)
    swi 0xFC0000
    bx lr

    .section .arm7, "ax", %progbits
    .global nds_arm7_start
    .type nds_arm7_start, %function
nds_arm7_start:
    mov r0, #0
    ldr r1, =0x04000208         @ IME
    str r0, [r1]
    str r0, [r1, #8]            @ IE (0x04000210)
1:  swi 0x060000                @ Halt
    b 1b
    .ltorg
