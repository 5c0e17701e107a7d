#!/usr/bin/env python3
"""probe-block.py LOG - print README.md's probe block from the committed log of make docs-probe.

LOG is docs/results/probe.txt (tools/scripts/docs-probe.sh): `qibl demo --probe P --small`'s
probe table for a user's probe, then the sun + SH frame made through bake/relight/render --probe.
make docs-check compares the README's block with this output, so the figures are the log's.
"""
import sys


def main(path):
    cmds, rows, results, about = [], [], {}, []
    with open(path, encoding="utf-8") as f:
        for line in f:
            line = line.rstrip("\n")
            if line.startswith("# command: "):
                cmds.append(line[len("# command: "):])
            elif line.startswith("# date: "):
                date = line[len("# date: "):]
            elif line.startswith("| "):
                rows.append(line)
            elif line.startswith("user: "):
                about.append(line[len("user: "):])
            elif line.startswith("RESULT "):
                parts = line.split()
                results[parts[1]] = parts[2]
    for name in ("demo.probe_user_sunsh_psnr", "cli.probe_user_sunsh_psnr"):
        if name not in results:
            sys.exit(f"probe-block: {path} has no RESULT {name} (make docs-probe)")
    if len(rows) < 3:
        sys.exit(f"probe-block: {path} has no probe table (make docs-probe)")
    keep = [r.split("|") for r in rows]
    # probe, scheme, PSNR, lit, cast shadow, facing away (the bytes and timings stay in the log)
    for i, cells in enumerate(keep):
        print("|" + "|".join(cells[2:7]) + "|")
        if i == 0:
            print("|---|---:|---:|---:|---:|")
    print()
    print(f"- the probe: {about[0] if about else '?'}")
    print(f"- sun + SH through the CLI (`bake --probe`, `relight --probe` against `render --probe`, same size and "
          f"samples): {results['cli.probe_user_sunsh_psnr']} dB; the demo's row: {results['demo.probe_user_sunsh_psnr']} dB")
    print(f"- measured {date} by `make docs-probe` (log: `docs/results/probe.txt`):")
    for c in cmds:
        print(f"  `{c}`")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "docs/results/probe.txt"))
