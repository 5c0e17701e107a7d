/* gba/hemi_rom.S - the golden ROM's prebuilt hemi tables (qibl-hemi-tables, hemi_tables.c) for
 * (32, 24) and (64, 8) in cartridge ROM, 4-byte aligned; run.sh bakes them and passes their
 * directory with -Wa,-I. hemi_rom.c hands them to the golden cases. */
    .section .rodata.hemi_rom, "a", %progbits
    .balign 4
    .global hemi_rom_32_24, hemi_rom_32_24_end, hemi_rom_64_8, hemi_rom_64_8_end
hemi_rom_32_24:
    .incbin "hemi_32_24.qhmt"
hemi_rom_32_24_end:
    .balign 4
hemi_rom_64_8:
    .incbin "hemi_64_8.qhmt"
hemi_rom_64_8_end:
