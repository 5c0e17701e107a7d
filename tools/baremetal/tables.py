#!/usr/bin/env python3
"""baremetal/tables.py - rewrites the generated tables of docs/porting.md from a `make baremetal`
build (make baremetal-tables): stack bounds and measurements per entry point, instructions per
pixel, heap per golden case, and the handheld memory table. Each table sits between
<!-- baremetal:NAME begin --> and <!-- baremetal:NAME end --> lines; the rest of the page is kept.

usage: tables.py BUILD_DIR/baremetal DOC
"""
import os
import re
import subprocess
import sys

TARGETS = [("cortex-m0", "Cortex-M0 -Os", "arm-none-eabi-objdump"),
           ("cortex-m4", "Cortex-M4 -O2", "arm-none-eabi-objdump"),
           ("rv32imac", "RV32IMAC -O2", "riscv64-unknown-elf-objdump")]


def read(path):
    with open(path) as f:
        return f.read().splitlines()


def stack_table(out):
    here = os.path.dirname(os.path.abspath(__file__))
    bounds, measured = [], []
    for t, _, od in TARGETS:
        r = subprocess.run([sys.executable, os.path.join(here, "stack.py"), "--objdump", od,
                            os.path.join(out, t, "core")], capture_output=True, text=True)
        b = {}
        for line in r.stdout.splitlines():
            p = line.split()
            b[p[0]] = p[1] if p[1] != "unbounded" else "unbounded"
        bounds.append(b)
        m = {}
        for line in read(os.path.join(out, t, "run.txt")):
            p = line.split()
            if len(p) == 5 and p[0] == "stack" and p[3] == "bound":
                m[p[1]] = p[2]
        measured.append(m)
    names = sorted(set().union(*bounds))
    rows = ["| entry point | " + " | ".join(n for _, n, _ in TARGETS) + " |", "|---|" + "---:|" * len(TARGETS)]
    for n in names:
        cells = []
        for b, m in zip(bounds, measured):
            c = b.get(n, "-")
            if n in m:
                c += " (%s)" % m[n]
            cells.append(c)
        rows.append("| `%s` | %s |" % (n, " | ".join(cells)))
    worst = []
    for b in bounds:
        v = [(int(x), n) for n, x in b.items() if x.isdigit()]
        worst.append("**%d** (`%s`)" % max(v))
    rows.append("| largest | " + " | ".join(worst) + " |")
    return rows


def results(out, t):
    r = {}
    path = os.path.join(out, t, "bench.txt")
    if os.path.exists(path):
        for line in read(path):
            p = line.split()
            if len(p) == 3 and p[0] == "RESULT":
                r[p[1].split("_", 1)[1]] = p[2]
    return r


def insn_table(out):
    res = [results(out, t) for t, _, _ in TARGETS]
    rows = ["| instructions per pixel (span of 320) | " + " | ".join(n for _, n, _ in TARGETS) + " |",
            "|---|" + "---:|" * len(TARGETS)]
    what = []
    for k in (4, 9, 16):
        what += [("dir_k%d_insn_per_px" % k, "directional, k = %d" % k),
                 ("k%d_point_direct_insn_per_px" % k, "point light, direct SH, k = %d" % k),
                 ("k%d_point_lut16_insn_per_px" % k, "point light, 16² LUT bilinear, k = %d" % k),
                 ("k%d_point_lut16_nearest_insn_per_px" % k, "point light, 16² LUT nearest, k = %d" % k),
                 ("k%d_point_poly_insn_per_px" % k, "point light, Q2.14 polynomials (QIBL_POINT_POLY), k = %d" % k)]
    what += [("k9_fb_rgb565_dither_insn_per_px", "`qibl_soft_fb_write_row`, RGB565 sRGB dithered"),
             ("stream_k9_insn_per_px", "streamed rows (below), k = 9, copy included"),
             ("stream_k9_copy_insn_per_px", "of which the row copy (picolibc `memcpy`)")]
    for key, label in what:
        rows.append("| %s | %s |" % (label, " | ".join(r.get(key, "-") for r in res)))
    return rows


def case_table(out):
    rows = ["| golden case | heap bytes at its peak |", "|---|---:|"]
    for line in read(os.path.join(out, "cortex-m4", "run.txt")):
        p = line.split()
        if len(p) == 5 and p[0] == "case" and p[3] == "heap":
            rows.append("| `%s` | %s |" % (p[1], p[4]))
    return rows


def handheld_table(out):
    rows = ["| panorama | k | SH maps (flash) | P map | 16² YLUT | row of planes (streaming) | span workspace dir / point | output row | RGB565 frame |",
            "|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for line in read(os.path.join(out, "cortex-m4", "bench.txt")):
        p = line.split()
        if p and p[0] == "mem":
            w, h, k = p[1:4]
            d = dict(zip(p[4::2], p[5::2]))
            rows.append("| %s×%s | %s | %s | %s | %s | %s | %s / %s | %s | %s |" % (
                w, h, k, d["maps"], d["pmap"], d["ylut16"], d["stream_row"], d["span_ws"], d["point_ws"], d["row"], d["fb565"]))
    return rows


def main(argv):
    out, doc = argv[1], argv[2]
    tables = {"stack": stack_table(out), "insn": insn_table(out), "cases": case_table(out),
              "handheld": handheld_table(out)}
    text = read(doc)
    res, skip, seen = [], None, set()
    for line in text:
        m = re.match(r"<!-- baremetal:(\w+) (begin|end) -->", line)
        if m and m.group(2) == "begin":
            res.append(line)
            res += tables[m.group(1)]
            skip = m.group(1)
            seen.add(skip)
            continue
        if m and m.group(2) == "end":
            skip = None
        if skip is None:
            res.append(line)
    missing = set(tables) - seen
    if missing:
        sys.exit("tables.py: %s has no <!-- baremetal:NAME begin/end --> for %s" % (doc, ", ".join(sorted(missing))))
    with open(doc, "w") as f:
        f.write("\n".join(res) + "\n")
    print("tables.py: %s: %s rewritten" % (doc, ", ".join(sorted(seen))))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
