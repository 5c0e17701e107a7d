#!/usr/bin/env bash
# doc-block.sh NAME DOC.md GENERATED.md --write|--check
# Generated tables in the docs live between "<!-- NAME begin -->" and "<!-- NAME end -->"; --write
# replaces the lines between the markers with GENERATED.md, --check fails (naming the doc) when they
# differ, so a table printed by a command cannot drift from it.
set -euo pipefail
name=$1 doc=$2 gen=$3 mode=$4
grep -q "^<!-- $name begin" "$doc" || { echo "doc-block: $doc has no '<!-- $name begin -->' marker" >&2; exit 1; }
tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT
awk -v name="$name" -v gen="$gen" '
    $0 ~ "^<!-- " name " begin" { print; while ((getline l < gen) > 0) print l; skip = 1; next }
    $0 ~ "^<!-- " name " end" { skip = 0 }
    !skip { print }' "$doc" > "$tmp"
if [ "$mode" = --write ]; then
    cat "$tmp" > "$doc"
    echo "doc-block: $doc: $name rewritten"
elif ! cmp -s "$tmp" "$doc"; then
    diff -u "$doc" "$tmp" | head -40 >&2 || true   # diff's status 1 must not end the script (set -e, pipefail)
    echo "doc-block: $doc: the $name block differs from what the command prints now" >&2
    exit 1
fi
