#!/usr/bin/env python3
"""gen-srgb-table.py - prints the sRGB encode tables of platform/soft/soft.c.

The 8-bit sRGB code of a clamped linear value L (Q16.16, 0..65536) is
    code(L) = floor(255 * srgb(L / 65536) + 1/2)
with srgb() the exact IEC 61966-2-1 curve (12.92 x below 0.0031308, else 1.055 x^(1/2.4) - 0.055),
evaluated here in 60-digit decimal arithmetic so no tie can be misjudged. soft.c finds it with two
tables: srgb_start[i], the code at the start of bucket i (16 wide below L = 4096, 64 wide above),
and srgb_last[k], the largest L whose code is k. Every bucket holds at most one code boundary
(checked below), so code(L) = k + (L > srgb_last[k]) with k = srgb_start[bucket(L)].
Usage: python3 tools/scripts/gen-srgb-table.py > table.inc  (then paste into soft.c)
"""
from decimal import Decimal, getcontext

getcontext().prec = 60
ONE = 65536
K = Decimal(1) / Decimal("2.4")


def srgb(x):
    if x <= Decimal("0.0031308"):
        return Decimal("12.92") * x
    return Decimal("1.055") * (x ** K) - Decimal("0.055")


def code(l):
    y = 255 * srgb(Decimal(l) / ONE) + Decimal("0.5")
    c = int(y)  # floor: y >= 0
    assert abs(y - c) > Decimal("1e-40"), "near-tie at L=%d" % l
    return c


codes = [code(l) for l in range(ONE)]
assert code(ONE) == 255 and codes[-1] == 255
assert all(a <= b <= a + 1 for a, b in zip(codes, codes[1:])), "codes must rise by at most 1"
last = [max(l for l in range(ONE) if codes[l] == k) for k in range(256)]


def bucket(l):
    return l >> 4 if l < 4096 else (l >> 6) + 192


nbuckets = bucket(ONE - 1) + 1
start = [None] * nbuckets
for l in range(ONE):
    b = bucket(l)
    if start[b] is None:
        start[b] = codes[l]
    assert codes[l] - start[b] <= 1, "two boundaries in bucket %d" % b
for l in range(ONE):
    k = start[bucket(l)]
    assert k + (l > last[k]) == codes[l]


def emit(name, ctype, vals, per_line):
    print("static const %s %s[%d] = {" % (ctype, name, len(vals)))
    for i in range(0, len(vals), per_line):
        print("    " + ", ".join(str(v) for v in vals[i:i + per_line]) + ",")
    print("};")


emit("srgb_start", "uint8_t", start, 16)
emit("srgb_last", "uint16_t", last, 12)
