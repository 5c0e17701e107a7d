#!/usr/bin/env python3
"""gba/fix_header.py - writes the complement checksum of a GBA ROM's header (byte 0xBD).

usage: fix_header.py ROM
The checksum is -(sum of bytes 0xA0..0xBC) - 0x19, modulo 256; the BIOS refuses a cartridge whose
byte disagrees. The Nintendo logo (0x04..0x9F) is left as it is (zero in tools/gba/crt_gba.S):
emulators do not check it, real hardware does (gbafix from devkitPro fills it). Fails on a file
too short for a header or without the fixed byte 0x96 at 0xB2.
"""
import sys


def main(argv):
    if len(argv) != 2:
        sys.exit("usage: fix_header.py ROM")
    with open(argv[1], "r+b") as f:
        rom = bytearray(f.read())
        if len(rom) < 0xC0:
            sys.exit("fix_header: %s: %d bytes, shorter than the 192-byte header" % (argv[1], len(rom)))
        if rom[0xB2] != 0x96:
            sys.exit("fix_header: %s: byte 0xB2 is 0x%02x, not 0x96: not a GBA header" % (argv[1], rom[0xB2]))
        chk = (-sum(rom[0xA0:0xBD]) - 0x19) & 0xFF
        f.seek(0xBD)
        f.write(bytes([chk]))
    print("fix_header: %s: checksum 0x%02x" % (argv[1], chk))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
