#!/usr/bin/env python3
"""png-psnr.py TRUTH.png RELIT.png - PSNR (dB, 8-bit) of RELIT against TRUTH over the scene pixels.

Scene pixels are those not black in either frame (the sky is black in both a relit panorama and
the ray-traced truth), as tests/probe_lit_cli_test.c measures them. RGB8 PNGs without interlace,
as qibl writes them. Prints one number with two decimals.
"""
import math
import struct
import sys
import zlib


def read_png(path):
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        sys.exit(f"png-psnr: {path}: not a PNG")
    at, w, h, idat = 8, 0, 0, b""
    while at < len(data):
        n, kind = struct.unpack(">I4s", data[at:at + 8])
        body = data[at + 8:at + 8 + n]
        at += 12 + n
        if kind == b"IHDR":
            w, h, depth, colour = struct.unpack(">IIBB", body[:10])
            if depth != 8 or colour != 2:
                sys.exit(f"png-psnr: {path}: not RGB8")
        elif kind == b"IDAT":
            idat += body
        elif kind == b"IEND":
            break
    raw, stride, out, prev, j = zlib.decompress(idat), 3 * w, bytearray(), bytearray(3 * w), 0
    for _ in range(h):
        f, line = raw[j], bytearray(raw[j + 1:j + 1 + stride])
        j += 1 + stride
        for x in range(stride):
            a = line[x - 3] if x >= 3 else 0
            b, c = prev[x], prev[x - 3] if x >= 3 else 0
            if f == 1:
                line[x] = (line[x] + a) & 255
            elif f == 2:
                line[x] = (line[x] + b) & 255
            elif f == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        out += line
        prev = line
    return w, h, out


def main(truth, relit):
    w, h, t = read_png(truth)
    w2, h2, r = read_png(relit)
    if (w, h) != (w2, h2):
        sys.exit(f"png-psnr: {truth} is {w}x{h}, {relit} {w2}x{h2}")
    se = n = 0
    for i in range(0, 3 * w * h, 3):
        if any(t[i:i + 3]) or any(r[i:i + 3]):
            se += sum((x - y) ** 2 for x, y in zip(t[i:i + 3], r[i:i + 3]))
            n += 3
    print(f"{10 * math.log10(255 * 255 * n / se) if se else 99:.2f}")
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: png-psnr.py TRUTH.png RELIT.png")
    sys.exit(main(sys.argv[1], sys.argv[2]))
