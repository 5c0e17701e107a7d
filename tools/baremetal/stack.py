#!/usr/bin/env python3
"""baremetal/stack.py - worst-case stack of every public core entry point, from GCC's
-fcallgraph-info=su (.ci files: one node per function with its frame size, one edge per direct
call). The bound of a function is its own frame plus the largest bound among its callees; a call
through a pointer, a recursion or a frame of dynamic size makes the bound unknown, and is named.

A call to a run-time helper outside the core (libgcc's __aeabi_lmul on ARMv4T Thumb, for instance)
is bounded when --helpers LIB names the library that defines it and its code calls nothing: every
push and sp decrement in it is summed (an upper bound).

usage: stack.py [--objdump PROG] [--helpers LIB] DIR...            prints "<function> <bytes>" for every public (qibl_*, non-static)
                                  function defined in DIR/*.ci, or "<function> unbounded <why>"
       stack.py --table NAME=OBJDUMP=DIR ...   a markdown table, one column per target
"""
import glob
import os
import re
import subprocess
import sys

NODE = re.compile(r'node: \{ title: "([^"]+)" label: "([^"]*)"(.*)\}')
EDGE = re.compile(r'edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"')


def pretend(objdump, obj):
    """{function: bytes} stored below the entry sp before the frame (ARM: sub sp, #N first)"""
    out, fn, first = {}, None, False
    text = subprocess.run([objdump, "-d", obj], check=True, capture_output=True, text=True).stdout
    for line in text.splitlines():
        m = re.match(r'^[0-9a-f]+ <([^>]+)>:$', line)
        if m:
            fn, first = m.group(1), True
            continue
        if fn and first and "\t" in line:
            first = False
            m = re.search(r'\tsub(?:\.w)?\tsp, (?:sp, )?#(\d+)', line)
            if m:
                out[fn] = int(m.group(1))
    return out


def helper_frames(objdump, lib):
    """{function: bytes} of the leaf functions of lib: the sum of its pushes and sp decrements"""
    out, fn, calls = {}, None, False
    text = subprocess.run([objdump, "-d", lib], check=True, capture_output=True, text=True).stdout
    for line in text.splitlines() + ["0 <end>:"]:
        m = re.match(r'^[0-9a-f]+ <([^>]+)>:$', line)
        if m:
            if fn is not None and calls:
                out.pop(fn, None)
            fn, calls = m.group(1), False
            out[fn] = 0
            continue
        if fn is None or "\t" not in line:
            continue
        if re.search(r'\t(bl|blx)\t', line):
            calls = True
        p = re.search(r'\t(push|stmdb)\t(?:sp!, )?\{([^}]*)\}', line)
        if p:
            out[fn] += 4 * len(p.group(2).split(","))
        p = re.search(r'\tsub(?:s|\.w)?\tsp, (?:sp, )?#(\d+)', line)
        if p:
            out[fn] += int(p.group(1))
    out.pop("end", None)
    return out


def load(dirs, objdump=None, helpers=None):
    frames, quals, calls = {}, {}, {}
    for d in dirs:
        for path in sorted(glob.glob(os.path.join(d, "*.ci"))):
            extra = {}
            obj = path[:-len(".c.ci")] + ".o"
            if objdump and os.path.exists(obj):
                extra = pretend(objdump, obj)
            with open(path) as f:
                for line in f:
                    m = NODE.match(line)
                    if m:
                        title, label = m.group(1), m.group(2)
                        s = re.search(r'\\n(\d+) bytes \(([^)]*)\)', label)
                        if s:  # defined here (external ones are ellipses without a size)
                            frames[title] = int(s.group(1)) + extra.get(title.split(":")[-1], 0)
                            quals[title] = s.group(2)
                        calls.setdefault(title, [])
                        continue
                    m = EDGE.match(line)
                    if m:
                        calls.setdefault(m.group(1), []).append(m.group(2))
    if helpers:
        for fn, b in helper_frames(objdump or "objdump", helpers).items():
            if fn not in frames and fn in calls:
                frames[fn], quals[fn], calls[fn] = b, "static", []
    return frames, quals, calls


def bounds(frames, quals, calls):
    memo = {}

    def walk(fn, path):
        if fn in memo:
            return memo[fn]
        if fn in path:
            return None, "recursion through " + fn
        if fn == "__indirect_call":
            return None, "call through a pointer"
        if fn not in frames:
            return None, "calls %s, not in core (no stack information)" % fn
        if quals[fn] != "static":
            return None, "%s has a %s frame" % (fn, quals[fn])
        worst, why = 0, ""
        for c in set(calls.get(fn, [])):
            b, w = walk(c, path | {fn})
            if b is None:
                memo[fn] = (None, w)
                return memo[fn]
            worst = max(worst, b)
        memo[fn] = (frames[fn] + worst, why)
        return memo[fn]

    out = {}
    for fn in frames:
        if ":" in fn or not fn.startswith("qibl_"):
            continue  # file-local, or internal (qibli_*)
        out[fn] = walk(fn, frozenset())
    return out


def main(argv):
    objdump = None
    if len(argv) >= 3 and argv[1] == "--objdump":
        objdump = argv[2]
        argv = argv[:1] + argv[3:]
    helpers = None
    if len(argv) >= 3 and argv[1] == "--helpers":
        helpers = argv[2]
        argv = argv[:1] + argv[3:]
    if len(argv) >= 2 and argv[1] == "--table":
        cols = [a.split("=", 2) for a in argv[2:]]  # NAME=OBJDUMP=DIR
        res = [bounds(*load([d], od)) for _, od, d in cols]
        names = sorted(set().union(*[r.keys() for r in res]))
        print("| entry point | " + " | ".join(c for c, _ in cols) + " |")
        print("|---|" + "---:|" * len(cols))
        for n in names:
            cells = []
            for r in res:
                b = r.get(n)
                cells.append("-" if b is None else ("unbounded" if b[0] is None else str(b[0])))
            print("| `%s` | %s |" % (n, " | ".join(cells)))
        worst = [max([b[0] for b in r.values() if b[0] is not None] or [0]) for r in res]
        print("| **largest** | " + " | ".join("**%d**" % w for w in worst) + " |")
        return 0
    if len(argv) < 2:
        sys.stderr.write(__doc__)
        return 2
    res = bounds(*load(argv[1:], objdump, helpers))
    bad = 0
    for n in sorted(res):
        b, why = res[n]
        if b is None:
            print("%s unbounded %s" % (n, why))
            bad = 1
        else:
            print("%s %d" % (n, b))
    return bad


if __name__ == "__main__":
    sys.exit(main(sys.argv))
