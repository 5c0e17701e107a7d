/* gba/crt_gba.S - the cartridge header and reset of the Game Boy Advance ROMs (make gba).
 *
 * The BIOS (or an emulator that skips it) jumps to 0x08000000 in ARM state. The header's 156
 * Nintendo logo bytes are zero here: they cannot come from a Debian package, and emulators do not
 * check them; real hardware does (docs/porting.md: fill them with gbafix from devkitPro). The
 * complement checksum at 0xBD is written by tools/gba/fix_header.py after objcopy. The reset
 * switches to System mode with interrupts off, sets sp and enters gba_reset (C, Thumb) with bx. */
    .syntax unified
    .section .gba_header, "ax", %progbits
    .arm
    .global gba_start
    .type gba_start, %function
gba_start:
    b gba_entry                 @ 0x00: the entry branch
    .fill 156, 1, 0             @ 0x04: Nintendo logo (zero: see above)
    .ascii "QIBL GOLDEN\0"      @ 0xA0: title, 12 bytes
    .ascii "QIBL"               @ 0xAC: game code
    .ascii "00"                 @ 0xB0: maker code
    .byte 0x96                  @ 0xB2: fixed value
    .byte 0                     @ 0xB3: main unit code
    .byte 0                     @ 0xB4: device type
    .fill 7, 1, 0               @ 0xB5: reserved
    .byte 0                     @ 0xBC: software version
    .byte 0                     @ 0xBD: complement checksum (fix_header.py)
    .hword 0                    @ 0xBE: reserved
gba_entry:                      @ 0xC0
    msr cpsr_c, #0xDF           @ System mode, IRQ and FIQ masked
    ldr sp, =__stack_top
    ldr r0, =gba_reset
    bx r0
    .ltorg
