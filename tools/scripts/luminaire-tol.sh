#!/usr/bin/env bash
# luminaire-tol.sh - the near-field hierarchy's tolerance against speed and error: `qibl luminaire
# study --tol T` for each T (0: the full sum), its RESULT lines and the interleaved timing, into
# docs/results/luminaire-tol.txt (the committed log docs/ARCHITECTURE.md "Near-field sources" cites;
# figures are not typed into the docs). One study at a time, on one core for the timings.
set -euo pipefail
cd "$(dirname "$0")/../.."
QIBL=${QIBL:-build/bin/qibl}
out=${1:-docs/results/luminaire-tol.txt}
tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT
{
    echo "# docs/results/luminaire-tol.txt: written by tools/scripts/luminaire-tol.sh; do not edit"
    echo "# command: $QIBL luminaire study --tol T (T below; the default grid 16, res 32)"
    echo "# compiler: $(${CC:-cc} --version | head -n 1)"
    echo "# machine: $(uname -m), $(grep -m1 'model name' /proc/cpuinfo 2>/dev/null | sed 's/.*: //'), $(nproc) CPUs, load $(cut -d' ' -f1-3 /proc/loadavg)"
    echo "# date: $(date -u +%Y-%m-%dT%H:%MZ)"
    for t in 0 0.1 0.2 0.25 0.3 0.35 0.4 0.6; do
        echo "## --tol $t"
        "$QIBL" luminaire study --tol "$t" | grep -E '^RESULT|interleaved'
    done
} > "$tmp"
mv "$tmp" "$out"
echo "wrote $out"
