#!/usr/bin/env python3
"""doc-toc.py DOC.md - print the table of contents of a Markdown page (its ## and ### headings,
outside code fences), as links to GitHub's heading anchors. make docs writes it between the
page's "<!-- toc begin" and "<!-- toc end -->" lines; make docs-check compares."""
import re
import sys
import unicodedata


def anchor(title, seen):
    text = re.sub(r"[`*_]", lambda m: "_" if m.group(0) == "_" else "", title).strip().lower()
    out = []
    for ch in text:
        cat = unicodedata.category(ch)
        if ch in " -_" or cat[0] in "LMN":
            out.append("-" if ch == " " else ch)
    a = "".join(out)
    n = seen.get(a, 0)
    seen[a] = n + 1
    return a if n == 0 else f"{a}-{n}"


def main(path):
    seen = {}
    fence = False
    lines = []
    for line in open(path, encoding="utf-8"):
        if line.startswith("```"):
            fence = not fence
            continue
        if fence:
            continue
        m = re.match(r"^(#{1,3}) (.+?)\s*$", line)
        if not m:
            continue
        level, title = len(m.group(1)), m.group(2)
        a = anchor(title, seen)
        if level == 1 or title == "Contents":
            continue
        indent = "  " * (level - 2)
        lines.append(f"{indent}- [{title}](#{a})")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
