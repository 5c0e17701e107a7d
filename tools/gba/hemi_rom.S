/* gba/hemi_rom.S - the golden ROM's prebuilt hemi tables (qibl-hemi-tables, hemi_tables.c) for
 * (32, 24) and (64, 8) in cartridge ROM; run.sh bakes them and passes their directory with -Wa,-I.
 * hemi_rom.c hands them to the golden cases. */
#include "handheld/rom_blob.h"
    .section .rodata.hemi_rom, "a", %progbits
QIBL_ROM_BLOB(hemi_rom_32_24, "hemi_32_24.qhmt")
QIBL_ROM_BLOB(hemi_rom_64_8, "hemi_64_8.qhmt")
