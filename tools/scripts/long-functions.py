#!/usr/bin/env python3
"""long-functions.py [N] - the C functions outside tests/ longer than N lines (default 150).

A function is a top-level brace block whose opening line (or the line before it) holds a ')' and no
'=': its length counts from the line of its '{' to the line of its '}'. Strings, character
constants and // comments are skipped when braces are counted. Prints one line per function,
longest first ("LINES FILE:LINE"), then "count N"; exits 1 when any is found (issue 29's rule:
no function over 150 lines outside tests and fuzz targets), 0 otherwise.
"""
import re
import subprocess
import sys

limit = int(sys.argv[1]) if len(sys.argv) > 1 else 150
files = subprocess.check_output(["git", "ls-files", "*.c"], text=True).split()
found = []
for f in files:
    if f.startswith("tests/"):
        continue
    lines = open(f, encoding="utf-8", errors="replace").read().split("\n")
    depth, start = 0, None
    for i, line in enumerate(lines):
        s = re.sub(r'"(\\.|[^"\\])*"|\'(\\.|[^\'\\])*\'', "", line)
        s = re.sub(r"//.*", "", s)
        for ch in s:
            if ch == "{":
                if depth == 0:
                    start = i
                depth += 1
            elif ch == "}":
                depth -= 1
                if depth == 0 and start is not None:
                    n = i - start + 1
                    head = lines[start] if ")" in lines[start] else (lines[start - 1] if start > 0 else "")
                    if n > limit and ")" in head and "=" not in head:
                        found.append((n, f, start + 1))
                    start = None
for n, f, s in sorted(found, reverse=True):
    print(f"{n} {f}:{s}")
print("count", len(found))
sys.exit(1 if found else 0)
