#!/usr/bin/env python3
"""typed-figures.py - count the measured figures typed by hand into the docs and header comments.

usage: typed-figures.py [--list] [--count] [FILE...]
  (no FILE: README.md, docs/*.md, and the comments of core/include/qibl/*.h and
   platform/*/include/qibl/*.h, from the repository root)

A figure typed by hand drifts from the code that measures it; the docs keep such figures only in
generated blocks (between "<!-- NAME begin" and "<!-- NAME end" lines, or the older
"<!-- NAME: generated ... -->" / "<!-- NAME: end -->" and "<!-- make gba: generated" /
"<!-- end make gba -->" pairs), which a command rewrites and `make docs-check` compares.

What counts as a measured figure (outside generated blocks):
  * a number followed by a unit of time, rate, size, ratio or quality: ns us ms s sec seconds min
    minutes h hours fps KiB MiB GiB kB KB MB GB B bytes %, dB, cycles, insn, instructions, x or
    the multiplication sign used as a ratio ("3.9x", "1.25-1.4x"; not a dimension such as 32x32);
  * a number followed by a count of measured things: tests, cases, suites, configurations, lines,
    functions, files, findings, execs, runs;
  * a number in scientific notation (1e-15, 1.5*10^-8, 10 to a superscript power).
What is exempt, by rule (a definition or a command, not a measurement):
  * anything inside inline code (`...`): commands, flags, identifiers (`--error 2%`);
  * hyphenated definitions: "24-byte header", "8-bit maps", "32-bit words", "16-bit" (N-unit);
  * sizes that are a power of two in B/bytes/KiB/MiB/GiB: capacities and limits chosen by design
    (a 256 KiB EWRAM, a 64 MiB cap, a 1 KiB table), never a measured size;
  * goals, limits and defaults: a number right after "at most", "up to", "goal of", "goal:",
    "default", "<=" or "≤" (a setting the design chooses, not a measurement);
  * arithmetic written out: a number after an operator (+ - = * / x ·) and a space, or an exponent (2^26 bytes) ("1216 + 512 = 1728 bytes",
    "13933 R + 46871 G + 4732 B"), a derivation from definitions;
  * zero sizes ("0 bytes of .data": a rule) and clock frequencies (Hz, MHz: the hardware's
    specification, not counted as a unit);
  * Q formats (Q16.16), versions, dimensions (1024x256) and bare numbers: they carry no unit above.
Exit status: 0 when no figure remains, 1 otherwise (with --list: one line per figure, file:line).
"""
import glob
import os
import re
import sys

UNITS = (r"ns|µs|us|ms|s|sec|secs|seconds?|min|minutes?|h|hours?|fps|"
         r"KiB|MiB|GiB|kB|KB|MB|GB|B|bytes?|%|dB|cycles?|insn|instructions?|"
         r"tests|cases|suites|configurations|lines|functions|files|findings|execs|runs|"
         r"CPU[- ](?:minutes?|seconds?|hours?)")
NUM = r"\d+(?:[,\u2009\u202f]\d{3})*(?:\.\d+)?"
# a number (or a range of them) and a unit; the unit must end at a word boundary
FIG = re.compile(r"(?<![\w.\-/])(" + NUM + r")(?:\s?[–\-]\s?" + NUM + r")?(\s?)(" + UNITS +
                 r")(?![\w\-])")
RATIO = re.compile(r"(?<![\w.])(" + NUM + r")(?:\s?[–\-]\s?" + NUM + r")?[x×](?![\w\d])")
SCI = re.compile(r"(?<![\w.])\d+(?:\.\d+)?(?:[eE][-+]?\d+\b|\s?[·*]\s?10[⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+|\s?[·*]\s?10\^-?\d+)"
                 r"|(?<![\w.])10[⁻]?[⁰¹²³⁴⁵⁶⁷⁸⁹]+")
BINARY = {"B", "byte", "bytes", "KiB", "MiB", "GiB"}
BEGIN = re.compile(r"^<!-- ?([\w:.\- ]+?)(?: begin|:? generated)")
END = re.compile(r"^<!-- ?(?:([\w:.\-]+)(?: end|: end)|end [\w .\-]+) ?(?:-->)?")
CODE = re.compile(r"`[^`]*`")


def power_of_two(text):
    try:
        v = float(text.replace(",", "").replace("\u2009", "").replace("\u202f", ""))
    except ValueError:
        return False
    if v != int(v) or v < 1:
        return False
    v = int(v)
    return v & (v - 1) == 0


def figures_in(line):
    """The measured figures of one line of prose (inline code removed)."""
    text = CODE.sub(lambda m: " " * len(m.group(0)), line)
    found = []
    for m in FIG.finditer(text):
        num, unit = m.group(1), m.group(3)
        # "8-bit", "24-byte": a definition (the regex's unit cannot follow '-' directly, but a
        # hyphenated unit word can follow a number: skip it)
        end = m.end()
        if end < len(text) and text[end] == "-":
            continue
        if unit in BINARY and float(num.replace(",", "")) == 0:
            continue   # "0 bytes of .data": a rule (nothing), not a measurement
        if unit in BINARY or unit in ("KiB", "MiB", "GiB"):
            if power_of_two(num) and m.group(0).count(num) == 1 and not re.search(r"[–\-]", m.group(0)):
                continue
        if unit == "s" and m.group(2) == "" and not re.match(r"\d", num):
            continue
        # "1s" alone is rare; "2s" may be a plural of a digit: keep only spaced or decimal seconds
        if unit == "s" and m.group(2) == "" and "." not in num:
            continue
        if unit == "B" and m.group(2) == "" :
            continue   # "8B" is a name (e.g. a model or an offset), not the docs' style for sizes
        if unit == "h" and m.group(2) == "":
            continue
        # a term or the result of arithmetic written out ("1216 + 512 = 1728 bytes", "4732 B" in a
        # weighted sum): a derivation from definitions, not a measurement
        if re.search(r"(?:[+=×*/·]\s+|\s-\s+|\bx\s+|\^)$", text[:m.start()]):
            continue
        # a goal or a limit the design sets, not a measurement: "at most 200 instructions",
        # "the goal of 16 KiB", "<= 600 cycles"
        if re.search(r"(?:\bat most|\bup to|\bgoal of|\bgoal:|\bdefault|≤|<=)\s*$", text[:m.start()]):
            continue
        found.append(m.group(0).strip())
    for m in RATIO.finditer(text):
        start = m.start()
        # a dimension (32x32, 1024 × 256) or a hex literal is not a ratio
        if start > 0 and re.search(r"\d\s?[x×]\s?$", text[:start]):
            continue
        if m.group(1) == "0" and text[m.end() - 1:m.end()] == "x":
            continue
        found.append(m.group(0).strip())
    for m in SCI.finditer(text):
        found.append(m.group(0).strip())
    return found


def doc_lines(path):
    """(line number, text) of a Markdown file outside its generated blocks."""
    out = []
    depth = 0
    with open(path, encoding="utf-8") as f:
        for i, line in enumerate(f, 1):
            s = line.strip()
            if depth == 0 and BEGIN.match(s) and not END.match(s):
                depth = 1
                continue
            if depth and END.match(s):
                depth = 0
                continue
            if not depth:
                out.append((i, line.rstrip("\n")))
    return out


def comment_lines(path):
    """(line number, text) of the comments of a C header."""
    out = []
    in_block = False
    with open(path, encoding="utf-8") as f:
        for i, line in enumerate(f, 1):
            text = ""
            rest = line
            while rest:
                if in_block:
                    j = rest.find("*/")
                    if j < 0:
                        text += rest
                        rest = ""
                    else:
                        text += rest[:j] + " "
                        rest = rest[j + 2:]
                        in_block = False
                else:
                    j = rest.find("/*")
                    k = rest.find("//")
                    if k >= 0 and (j < 0 or k < j):
                        text += rest[k + 2:]
                        rest = ""
                    elif j >= 0:
                        rest = rest[j + 2:]
                        in_block = True
                    else:
                        rest = ""
            if text.strip():
                out.append((i, text.rstrip("\n")))
    return out


def default_files():
    files = ["README.md"] + sorted(glob.glob("docs/*.md"))
    files += sorted(glob.glob("core/include/qibl/*.h"))
    files += sorted(glob.glob("platform/*/include/qibl/*.h"))
    return [f for f in files if os.path.exists(f)]


def main(argv):
    show = "--list" in argv
    only_count = "--count" in argv
    files = [a for a in argv if not a.startswith("--")] or default_files()
    total = 0
    per_file = []
    for path in files:
        lines = comment_lines(path) if path.endswith(".h") else doc_lines(path)
        n = 0
        for lineno, text in lines:
            for fig in figures_in(text):
                n += 1
                if show:
                    print(f"{path}:{lineno}: {fig}")
        per_file.append((path, n))
        total += n
    if only_count:
        print(total)
    else:
        for path, n in per_file:
            if n:
                print(f"typed-figures: {path}: {n}")
        print(f"typed-figures: {total} measured figures outside generated blocks")
    return 1 if total else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
