#!/usr/bin/env python3
# bigprobe.py OUT.hdr N latlong|disc: a large Radiance probe that RLE packs into a small file (rows
# of equal pixels and a small bright spot), the inputs of the probe cost figures in
# docs/robustness.md. latlong: a 2N x N sky gradient with a sun (N = 1024 gives a 143 KB file of
# 2 M pixels); disc: an N x N disc on black with a bright spot (read it with --layout ball).
import math
import sys


def rgbe(r, g, b):
    m = max(r, g, b)
    if m < 1e-32:
        return (0, 0, 0, 0)
    e = math.frexp(m)[1]
    s = 2.0 ** (8 - e)
    return (min(255, int(r * s)), min(255, int(g * s)), min(255, int(b * s)), e + 128)


def runs_rle(runs):
    """new-style RLE of one channel given as (byte, count) runs"""
    o = bytearray()
    for v, n in runs:
        while n > 0:
            k = min(n, 127)
            o += bytes([128 + k, v]) if k >= 2 else bytes([1, v])
            n -= k
    return o


def main():
    out, n, kind = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    w, h = (2 * n, n) if kind == "latlong" else (n, n)
    black = (0, 0, 0, 0)
    with open(out, "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (h, w))
        for y in range(h):
            if kind == "latlong":
                z = math.cos((y + 0.5) / h * math.pi)
                sky = rgbe(*((0.35 + 0.5 * max(z, 0),) * 3))
                runs = [(sky, w)]
                if abs(y - h // 3) < max(1, h // 200):
                    s0, sl = w // 5, max(1, w // 200)
                    runs = [(sky, s0), (rgbe(5000, 4800, 4500), sl), (sky, w - s0 - sl)]
            else:
                c = w / 2
                yy = (y + 0.5 - c) / c
                half = math.sqrt(max(0.0, 1 - yy * yy)) * c
                x0, x1 = int(c - half), int(c + half)
                v = rgbe(0.5 + 0.3 * yy, 0.5, 0.5 - 0.2 * yy)
                runs = [(black, x0), (v, x1 - x0), (black, w - x1)]
                if abs(y - w // 3) < max(1, w // 300):
                    s0, sl = int(c) + w // 8, max(1, w // 300)
                    runs = [(black, x0), (v, s0 - x0), (rgbe(3000, 2900, 2800), sl), (v, x1 - s0 - sl), (black, w - x1)]
            f.write(bytes([2, 2, (w >> 8) & 255, w & 255]))
            for ch in range(4):
                f.write(runs_rle([(p[ch], k) for p, k in runs if k > 0]))


if __name__ == "__main__":
    main()
