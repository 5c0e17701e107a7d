/* handheld/rom_blob.h - QIBL_ROM_BLOB(name, "file"): a file's bytes in cartridge ROM for a .S file,
 * 4-byte aligned (the core reads them as words), between the global symbols name and name_end.
 * The file is found on the assembler's include path (-Wa,-I). */
#ifndef QIBL_HANDHELD_ROM_BLOB_H
#define QIBL_HANDHELD_ROM_BLOB_H

#define QIBL_ROM_BLOB(name, file) \
    .balign 4;                    \
    .global name, name##_end;     \
    name:                         \
    .incbin file;                 \
    name##_end:

#endif
