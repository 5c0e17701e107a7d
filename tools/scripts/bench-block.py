#!/usr/bin/env python3
"""bench-block.py LOG - print README.md's bench block from the committed benchmark log.

LOG is docs/results/bench.txt (make docs-bench). The block names the run (commands, compiler,
flags, machine, date: the log's header) and the few timings a reader needs, from its RESULT lines;
make docs-check compares the README's block with this output, so the figures are the log's.
"""
import sys

KEEP = [  # (RESULT name, what it is, unit)
    ("relight.dir_k16_ms", "a directional light relit by the core, k = 16 SH maps, one frame of `bench relight --quick`", "ms"),
    ("relight.point_over_dir", "a point light (poly Q14) against the directional light, same frame", "times the time"),
    ("relight.dir_over_memcpy", "the directional kernel's speed against a memcpy of the same bytes, in cache", "of memcpy's speed"),
    ("sh.eval25_ns", "the 25 SH basis functions of one direction, integer", "ns"),
]


def main(path):
    head, runs, results = [], [], {}
    with open(path, encoding="utf-8") as f:
        for line in f:
            line = line.rstrip("\n")
            if line.startswith("# ") and ":" in line and not line.startswith("# docs/"):
                head.append(line[2:])
            elif line.startswith("== bench "):
                runs.append(line[3:])
            elif line.startswith("RESULT "):
                parts = line.split()
                results[parts[1]] = parts[2]
    print("| timing (one run, see below) | value |")
    print("|---|---:|")
    for name, what, unit in KEEP:
        if name not in results:
            sys.exit(f"bench-block: {path} has no RESULT {name} (make docs-bench)")
        print(f"| {what} (`{name}`) | {results[name]} {unit} |")
    print()
    print("Measured once by `make docs-bench` (log: `docs/results/bench.txt`); timings vary from run to run and machine to machine:")
    print()
    for h in head:
        key, _, val = h.partition(": ")
        print(f"- {key}: `{val}`" if key in ("command", "flags") else f"- {key}: {val}")
    for r in runs:
        print(f"- {r}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "docs/results/bench.txt"))
