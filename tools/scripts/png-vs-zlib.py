#!/usr/bin/env python3
# png-vs-zlib.py PNG... - the size of each PNG qibl wrote against the same pixels through zlib -9
# with libpng's adaptive row filters (minimum sum of absolute differences), the reference the PNG
# writer (tools/io/png.c) is measured against. Python's zlib is used here only, outside the build.
# 8-bit RGB, non-interlaced, single-image PNGs (an APNG's default image is measured).
import os
import struct
import sys
import zlib


def pixels(path):
    b = open(path, 'rb').read()
    i, idat, w, h = 8, b'', 0, 0
    while i < len(b):
        n, = struct.unpack('>I', b[i:i + 4])
        t, d = b[i + 4:i + 8], b[i + 8:i + 8 + n]
        if t == b'IHDR':
            w, h = struct.unpack('>II', d[:8])
            if d[8] != 8 or d[9] != 2 or d[12] != 0:
                sys.exit('%s: not 8-bit RGB non-interlaced' % path)
        elif t == b'IDAT':
            idat += d
        i += 12 + n
    raw, row, out, prev = zlib.decompress(idat), w * 3, bytearray(), bytearray(w * 3)
    for y in range(h):
        f, r = raw[y * (row + 1)], bytearray(raw[y * (row + 1) + 1:(y + 1) * (row + 1)])
        for x in range(row):
            r[x] = (r[x] + predict(f, r, prev, x)) & 255
        out += r
        prev = r
    return w, h, bytes(out)


def predict(f, r, up, x):
    a, b, c = (r[x - 3] if x >= 3 else 0), up[x], (up[x - 3] if x >= 3 else 0)
    if f == 0:
        return 0
    if f == 1:
        return a
    if f == 2:
        return b
    if f == 3:
        return (a + b) // 2
    p = a + b - c
    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
    return a if pa <= pb and pa <= pc else (b if pb <= pc else c)


def adaptive(w, h, px):
    n, out, prev = w * 3, bytearray(), bytes(w * 3)
    for y in range(h):
        s, best = px[y * n:(y + 1) * n], None
        for f in range(5):
            r = bytes((s[x] - predict(f, s, prev, x)) & 255 for x in range(n))
            cost = sum(v if v < 128 else 256 - v for v in r)
            if best is None or cost < best[0]:
                best = (cost, f, r)
        out.append(best[1])
        out += best[2]
        prev = s
    return bytes(out)


total = [0, 0]
for p in sys.argv[1:]:
    w, h, px = pixels(p)
    ref = len(zlib.compress(adaptive(w, h, px), 9)) + 8 + 25 + 12 + 12  # signature, IHDR, IDAT, IEND
    size = os.path.getsize(p)
    total[0] += size
    total[1] += ref
    print('%-28s %5dx%-5d qibl %8d  zlib-9 adaptive %8d  ratio %.3f' % (os.path.basename(p), w, h, size, ref, size / ref))
if total[1]:
    print('total qibl %d, zlib-9 adaptive %d, ratio %.3f' % (total[0], total[1], total[0] / total[1]))
