#!/usr/bin/env python3
"""nds/ndsrom.py - makes a Nintendo DS cartridge ROM from an ARM9 and an ARM7 binary.

usage: ndsrom.py OUT.nds TITLE ARM9.bin ARM9_ADDR ARM9_ENTRY ARM7.bin ARM7_ADDR ARM7_ENTRY
(addresses in hex or decimal). The header follows GBATEK's "DS Cartridge Header": title, game
code QIBL, maker 00, the chip capacity; the ARM9 binary at ROM offset 0x4000 (where the secure area
lies: unencrypted here, homebrew's way), the ARM7 after it on a 0x200 boundary, each with its load
address, entry and size; the total used size (the secure area's CRC-16 stays 0: DeSmuME takes a
ROM whose secure area matches it for an encrypted retail ROM and decrypts its ARM9 binary into
garbage); the Nintendo logo's CRC-16 (0xCF56, the value for the real logo) and the header's CRC-16 (of bytes
0x000..0x15D, at 0x15E), all CRC-16/MODBUS as GBATEK gives them. The 156 logo bytes are zero: they
cannot come from a Debian package, and DeSmuME does not check them; real hardware and flash
cards want them (ndstool from devkitPro fills them). Fails, writing nothing, on an address or size
outside GBATEK's ranges (ARM9 in main RAM 0x02000000..0x023BFE00, at most 0x3BFE00 bytes; ARM7 in
main RAM or its WRAM 0x037F8000..0x03807E00, at most 0xFE00 bytes there).
"""
import struct
import sys

LOGO_CRC = 0xCF56
ARM9_OFFSET = 0x4000


def crc16(data, crc=0xFFFF):
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = (crc >> 1) ^ 0xA001 if crc & 1 else crc >> 1
    return crc


def check(what, addr, entry, size, ranges):
    for lo, hi, most in ranges:
        if lo <= addr and addr + size <= hi and addr <= entry < addr + size and size <= most:
            return
    sys.exit("ndsrom: %s: load 0x%08x, entry 0x%08x, %d bytes: outside GBATEK's ranges" % (what, addr, entry, size))


def main(argv):
    if len(argv) != 9:
        sys.exit("usage: ndsrom.py OUT.nds TITLE ARM9.bin ARM9_ADDR ARM9_ENTRY ARM7.bin ARM7_ADDR ARM7_ENTRY")
    out, title = argv[1], argv[2].encode("ascii")
    if len(title) > 12:
        sys.exit("ndsrom: title %r longer than 12 bytes" % argv[2])
    a9, a7 = open(argv[3], "rb").read(), open(argv[6], "rb").read()
    a9_addr, a9_entry, a7_addr, a7_entry = (int(x, 0) for x in (argv[4], argv[5], argv[7], argv[8]))
    check("ARM9", a9_addr, a9_entry, len(a9), [(0x02000000, 0x023BFE00, 0x3BFE00)])
    check("ARM7", a7_addr, a7_entry, len(a7), [(0x02000000, 0x023BFE00, 0x3BFE00), (0x037F8000, 0x03807E00, 0xFE00)])
    a7_off = (ARM9_OFFSET + len(a9) + 0x1FF) & ~0x1FF
    used = a7_off + len(a7)
    body = bytes(ARM9_OFFSET - 0x200) + a9 + bytes(a7_off - ARM9_OFFSET - len(a9)) + a7
    body += bytes(-len(body) % 0x200)  # whole 512-byte blocks
    capacity = 0  # the chip holds 128 KiB << capacity (DeSmuME grows a too-small one and warns)
    while (128 * 1024) << capacity < 0x200 + len(body):
        capacity += 1
    h = bytearray(0x200)
    h[0x000:0x00C] = title.ljust(12, b"\0")
    h[0x00C:0x010] = b"QIBL"  # game code
    h[0x010:0x012] = b"00"    # maker code
    h[0x014] = capacity
    struct.pack_into("<IIII", h, 0x020, ARM9_OFFSET, a9_entry, a9_addr, len(a9))
    struct.pack_into("<IIII", h, 0x030, a7_off, a7_entry, a7_addr, len(a7))
    struct.pack_into("<I", h, 0x060, 0x00586000)  # port 40001A4h, normal commands (GBATEK's usual)
    struct.pack_into("<I", h, 0x064, 0x001808F8)  # port 40001A4h, KEY1 commands
    # 0x06C, the secure area's CRC-16, stays 0: DeSmuME takes a ROM whose secure area matches it
    # for an encrypted retail one and "decrypts" the ARM9 binary into garbage
    struct.pack_into("<II", h, 0x080, used, 0x4000)  # total used ROM size, header size
    struct.pack_into("<H", h, 0x15C, LOGO_CRC)
    struct.pack_into("<H", h, 0x15E, crc16(h[:0x15E]))
    rom = bytes(h) + body
    with open(out, "wb") as f:
        f.write(rom)
    print("ndsrom: %s: %d bytes, ARM9 %d bytes at 0x%08x, ARM7 %d bytes at 0x%08x, header CRC 0x%04x"
          % (out, len(rom), len(a9), a9_addr, len(a7), a7_addr, crc16(h[:0x15E])))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
