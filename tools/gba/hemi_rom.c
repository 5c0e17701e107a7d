/*
 * gba/hemi_rom.c - the golden runner's hemi_tables hook on the GBA (tools/golden/cases.h): the
 * blobs of hemi_rom.S in cartridge ROM, opened in place by the hemi cases, so the cases whose
 * tables exceed the 256 KiB EWRAM run. Built with -DBM_HEMI_TABLES (tools/baremetal/main.c).
 */
#include <stddef.h>

extern const unsigned char hemi_rom_32_24[], hemi_rom_32_24_end[], hemi_rom_64_8[], hemi_rom_64_8_end[];

const void *bm_hemi_tables(void *user, int n, int face, size_t *size);

const void *bm_hemi_tables(void *user, int n, int face, size_t *size)
{
    (void)user;
    if (n == 32 && face == 24) {
        *size = (size_t)(hemi_rom_32_24_end - hemi_rom_32_24);
        return hemi_rom_32_24;
    }
    if (n == 64 && face == 8) {
        *size = (size_t)(hemi_rom_64_8_end - hemi_rom_64_8);
        return hemi_rom_64_8;
    }
    return NULL;
}
