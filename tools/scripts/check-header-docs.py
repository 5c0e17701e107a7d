#!/usr/bin/env python3
"""check-header-docs.py - every status-returning public function has the header-doc skeleton.

The skeleton (as CMSIS-DSP documents every kernel): the comment right above a declaration marked
QIBL_NODISCARD / QTOOL_NODISCARD (or above the group of declarations it opens) holds the four parts
    Formats:     input and output number formats (or "none" for a call that moves no numbers)
    Bound:       the error bound of the result, in LSB or exact
    Errors:      every status returned, in the order checked
    On failure:  what is written when the call fails ("nothing" or exactly what)
Usage: check-header-docs.py [HEADER...]   (default: the public headers of core/ and platform/)
Every public header is checked (issue 29 converted the last ones; there is no pending list).
Exit 0: every checked function has the skeleton; 1: one lacks a part (named on stderr).
"""
import glob
import os
import re
import sys

PARTS = ("Formats:", "Bound:", "Errors:", "On failure:")
# a part is its word then a colon, with at most a short qualifier between ("Errors, in this order:")
PART_RE = {p: re.compile(re.escape(p[:-1]) + r"[^:.;]{0,20}:") for p in PARTS}
DECL = re.compile(r"^(?:static inline )?Q(?:IBL|TOOL)_NODISCARD\s+(?:static inline\s+)?\w+\s+(\w+)\s*\(", re.M)


def comment_before(text, pos):
    """The block comment right above pos, skipping the other declarations of its group; None when a
    blank line (or the file's start) comes first."""
    lines = text[:pos].split("\n")[:-1]
    i = len(lines) - 1
    while i >= 0:
        line = lines[i].rstrip()
        if not line:
            return None
        if line.endswith("*/"):
            j = i
            while j >= 0 and "/*" not in lines[j]:
                j -= 1
            if j >= 0 and lines[j].lstrip().startswith("/*"):
                return "\n".join(lines[j:i + 1])
            # a trailing comment on a declaration line: part of the group, keep going
            i = j - 1 if j >= 0 else -1
            continue
        i -= 1
    return None


def check(path):
    text = open(path, encoding="utf-8").read()
    missing = []
    for m in DECL.finditer(text):
        c = comment_before(text, m.start())
        lacks = [p for p in PARTS if c is None or not PART_RE[p].search(c)]
        if lacks:
            missing.append((m.group(1), lacks))
    return missing


def main(argv):
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
    os.chdir(root)
    headers = argv[1:] or sorted(glob.glob("core/include/qibl/*.h") + glob.glob("platform/*/include/qibl/*.h"))
    bad = 0
    functions = 0
    for h in headers:
        functions += len(DECL.findall(open(h, encoding="utf-8").read()))
        for name, lacks in check(h):
            print("check-header-docs: %s: %s lacks %s" % (h, name, ", ".join(lacks)), file=sys.stderr)
            bad += 1
    print("check-header-docs: %d header(s), %d status-returning function(s) checked, %d problem(s)"
          % (len(headers), functions, bad))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
