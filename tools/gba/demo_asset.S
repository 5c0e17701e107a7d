/* gba/demo_asset.S - the demo's two assets (qibl gen, 240 x 160, k = 4 and k = 9) in cartridge ROM;
 * run.sh passes their directory with -Wa,-I. */
#include "handheld/rom_blob.h"
    .section .rodata.demo_asset, "a", %progbits
QIBL_ROM_BLOB(demo_asset_k4, "courtyard_k4.qibl")
QIBL_ROM_BLOB(demo_asset_k9, "courtyard_k9.qibl")
