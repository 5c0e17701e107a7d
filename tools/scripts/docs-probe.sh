#!/usr/bin/env bash
# docs-probe.sh LOG - the probe table of a user's probe for README.md: `qibl demo --probe P --small`
# on a fixture probe the demo itself does not use, then the same sun + SH frame through the CLI
# (bake --probe, relight --probe) scored against render --probe at the same size and samples
# (tools/scripts/png-psnr.py), written to LOG (docs/results/probe.txt, committed). make docs-probe
# calls it and then make docs; probe-block.py formats the README's block from LOG, and make
# docs-check compares that block with LOG, so the figures can be old but never typed by hand.
set -euo pipefail
cd "$(dirname "$0")/../.."
log=${1:?usage: docs-probe.sh LOG}
QIBL=${QIBL:-build/bin/qibl}
probe=${PROBE:-../shared/fixtures/probes/immenstadter_horn_1k.hdr}
[ -r "$probe" ] || { echo "docs-probe: $probe absent (../shared/fixtures)" >&2; exit 1; }
# the demo's small size (tools/demo/demo.c): 256x64, 128 directions, 512 samples per pixel per render
size=256x64 dirs=128 spp=512
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cmds=("$QIBL demo --probe $probe --small --out OUT"
      "$QIBL bake --probe $probe --size $size --dirs $dirs -o A.qibl"
      "$QIBL relight A.qibl --probe $probe --png RELIT.png"
      "$QIBL render --probe $probe --size $size --spp $spp --png TRUTH.png")
{
    echo "# docs/results/probe.txt: written by make docs-probe (tools/scripts/docs-probe.sh); do not edit"
    for c in "${cmds[@]}"; do echo "# command: $c"; done
    echo "# date: $(date -u +%Y-%m-%dT%H:%MZ)"
    echo "## ${cmds[0]}"
    "$QIBL" demo --probe "$probe" --small --out "$tmp/out"
    echo "## the CLI chain"
    "$QIBL" bake --probe "$probe" --size $size --dirs $dirs --quiet -o "$tmp/a.qibl"
    "$QIBL" relight "$tmp/a.qibl" --probe "$probe" --png "$tmp/relit.png" > /dev/null
    "$QIBL" render --probe "$probe" --size $size --spp $spp --png "$tmp/truth.png" > /dev/null
    echo "RESULT cli.probe_user_sunsh_psnr $(python3 tools/scripts/png-psnr.py "$tmp/truth.png" "$tmp/relit.png")"
} > "$tmp/log"
mv "$tmp/log" "$log"
echo "docs-probe: $log written"
