/* gba/demo_asset.S - the demo's two assets (qibl gen, 240 x 160, k = 4 and k = 9) in cartridge ROM;
 * run.sh passes their directory with -Wa,-I. */
    .section .rodata.demo_asset, "a", %progbits
    .balign 4
    .global demo_asset_k4, demo_asset_k4_end, demo_asset_k9, demo_asset_k9_end
demo_asset_k4:
    .incbin "courtyard_k4.qibl"
demo_asset_k4_end:
    .balign 4
demo_asset_k9:
    .incbin "courtyard_k9.qibl"
demo_asset_k9_end:
