#!/usr/bin/env bash
# docs-bench.sh LOG - run the benchmarks whose timings the README keeps and write their output to
# LOG (docs/results/bench.txt, committed), headed by what a reader needs to weigh them: the
# commands, the compiler and flags, the machine, its load and the date. make docs-bench calls it
# and then make docs; bench-block.py formats the README's block from LOG, and make docs-check
# compares that block with LOG, so the timings can be old but never typed by hand.
set -euo pipefail
cd "$(dirname "$0")/../.."
log=${1:?usage: docs-bench.sh LOG}
QIBL=${QIBL:-build/bin/qibl}
cmds=("$QIBL bench relight --quick" "$QIBL bench sh")
tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT
{
    echo "# docs/results/bench.txt: written by make docs-bench (tools/scripts/docs-bench.sh); do not edit"
    for c in "${cmds[@]}"; do echo "# command: $c"; done
    echo "# compiler: $(${CC:-cc} --version | head -n 1)"
    echo "# flags: ${HOST_CFLAGS:-unknown}"
    echo "# kernels: $("$QIBL" --version | tr '\n' ' ' | sed 's/ *$//')"
    echo "# machine: $(uname -m), $(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo 2>/dev/null | head -n 1), $(nproc) CPUs, load $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null)"
    echo "# date: $(date -u +%Y-%m-%dT%H:%MZ)"
    for c in "${cmds[@]}"; do echo "## $c"; $c; done
} > "$tmp"
mv "$tmp" "$log"
trap - EXIT
echo "docs-bench: $log written"
