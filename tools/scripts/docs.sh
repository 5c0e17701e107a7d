#!/usr/bin/env bash
# docs.sh --write|--check - the generated parts of README.md and docs/, in one place.
#
#   --write  rewrite every block this script owns (make docs)
#   --check  fail, naming the block, when one differs from what its command prints now, or when a
#            measured figure is typed outside a generated block (make docs-check; CI runs it)
#
# Blocks it owns, each between "<!-- NAME begin" and "<!-- NAME end -->" lines (doc-block.sh):
#   docs/api.md            the API index           tools/scripts/api-index.py (from the headers)
#   README.md  facts       goldens, suites, cases  tools/scripts/docs-facts.sh (sources, qibl-golden)
#   ARCHITECTURE.md lines  lines per folder        tools/scripts/docs-facts.sh --lines
#   ARCHITECTURE.md toc    table of contents       tools/scripts/doc-toc.py (from its headings)
#   README.md  bench       the few timings kept    tools/scripts/bench-block.py docs/results/bench.txt
#                                                  (the committed log of make docs-bench)
#   README.md  probe       a user's probe table    tools/scripts/probe-block.py docs/results/probe.txt
#                                                  (the committed log of make docs-probe)
# Blocks other commands own, checked here from what those commands left in $BUILD (skipped, and
# said so, when they have not run in this build; CI runs them first):
#   docs/porting.md memory-table   tools/scripts/memory-table.sh (qibl bench memory --markdown)
#   docs/porting.md size-table     make cross ($BUILD/cross/size-table.md); make docs-size rewrites
#   docs/porting.md make gba       make gba ($BUILD/gba/tables.md); make gba-tables rewrites
#   docs/porting.md make nds       make nds ($BUILD/nds/tables.md); make nds-tables rewrites
# and, with --check, the header docs' skeleton (tools/scripts/check-header-docs.py).
# Fast by design (no benchmark, no bake, no cross build): it reuses the binaries make built.
set -euo pipefail
cd "$(dirname "$0")/../.."
mode=${1:---check}
case "$mode" in --write|--check) ;; *) echo "usage: docs.sh --write|--check" >&2; exit 2 ;; esac
BUILD=${BUILD:-build}
export QIBL=${QIBL:-$BUILD/bin/qibl} GOLDEN=${GOLDEN:-$BUILD/bin/qibl-golden}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0

# whole file: docs/api.md
python3 tools/scripts/api-index.py > "$tmp/api.md"
if [ "$mode" = --write ]; then
    cmp -s "$tmp/api.md" docs/api.md 2>/dev/null || { cp "$tmp/api.md" docs/api.md; echo "docs: docs/api.md rewritten"; }
elif ! cmp -s "$tmp/api.md" docs/api.md; then
    diff -u docs/api.md "$tmp/api.md" | head -n 40 >&2 || true
    echo "docs: docs/api.md differs from the headers (tools/scripts/api-index.py): make docs" >&2
    fail=1
fi

block() {   # block NAME DOC FILE: FILE's lines are the block's contents
    bash tools/scripts/doc-block.sh "$1" "$2" "$3" "$mode" >/dev/null || { echo "docs: make docs rewrites it" >&2; fail=1; }
}

bash tools/scripts/docs-facts.sh > "$tmp/facts.md"
block facts README.md "$tmp/facts.md"
bash tools/scripts/docs-facts.sh --lines > "$tmp/lines.md"
block lines docs/ARCHITECTURE.md "$tmp/lines.md"
python3 tools/scripts/doc-toc.py docs/ARCHITECTURE.md > "$tmp/toc.md"
block toc docs/ARCHITECTURE.md "$tmp/toc.md"
python3 tools/scripts/bench-block.py docs/results/bench.txt > "$tmp/bench.md"
block bench README.md "$tmp/bench.md"
python3 tools/scripts/probe-block.py docs/results/probe.txt > "$tmp/probe.md"
block probe README.md "$tmp/probe.md"

# the blocks of other commands, from their last run in this build
if [ -x "$QIBL" ]; then
    if [ "$mode" = --write ]; then sh tools/scripts/memory-table.sh --update >/dev/null
    else sh tools/scripts/memory-table.sh --check >/dev/null || fail=1; fi
else
    echo "docs: memory-table not checked: no $QIBL (make)"
fi
if [ -f "$BUILD/cross/size-table.md" ]; then
    bash tools/scripts/doc-block.sh size-table docs/porting.md "$BUILD/cross/size-table.md" "$mode" >/dev/null ||
        { echo "docs: make docs-size rewrites it" >&2; fail=1; }
else
    echo "docs: size-table not checked here: no $BUILD/cross/size-table.md (make cross checks it)"
fi
handheld_block() {   # handheld_block gba|nds: porting.md's "make NAME" block from $BUILD/NAME/tables.md
    local name=$1
    if [ -f "$BUILD/$name/tables.md" ]; then
        python3 - docs/porting.md "$BUILD/$name/tables.md" "$mode" "$name" <<'PY' || { echo "docs: make $name-tables rewrites it" >&2; fail=1; }
import sys
path, mode, name = sys.argv[1], sys.argv[3], sys.argv[4]
doc, block = open(path).read(), open(sys.argv[2]).read().rstrip("\n")
start, stop = "<!-- make %s: generated" % name, "<!-- end make %s -->" % name
a, b = doc.find(start), doc.find(stop)
if a < 0 or b < a:
    sys.exit("docs: no %s ... %s block in %s" % (start, stop, path))
new = doc[:a] + block + doc[b + len(stop):]
if mode == "--write":
    open(path, "w").write(new)
elif new != doc:
    sys.exit("docs: " + path + ": the make " + name + " block differs from the last make " + name + " run")
PY
    else
        echo "docs: the make $name block not checked here: no $BUILD/$name/tables.md (make $name writes it)"
    fi
}
handheld_block gba
handheld_block nds

# the header docs' one skeleton (make check-header-docs), checked here too so CI sees it with the docs
if [ "$mode" = --check ] && [ -f tools/scripts/check-header-docs.py ]; then
    python3 tools/scripts/check-header-docs.py >/dev/null || { python3 tools/scripts/check-header-docs.py >&2 || true; fail=1; }
fi

# no measured figure typed outside a generated block (--write only reports them)
if [ "$mode" = --write ]; then
    python3 tools/scripts/typed-figures.py | tail -n 1 || true
elif ! python3 tools/scripts/typed-figures.py > "$tmp/figures.txt"; then
    cat "$tmp/figures.txt" >&2
    python3 tools/scripts/typed-figures.py --list | grep -v '^typed-figures:' | head -n 40 >&2 || true
    echo "docs: measured figures typed by hand (typed-figures.py --list): put them in a generated block or remove them" >&2
    fail=1
fi

if [ $fail = 0 ]; then
    if [ "$mode" = --write ]; then echo "docs: every generated block rewritten"
    else echo "docs: OK (every generated block equals its command's output; no typed figures)"; fi
else
    echo "docs: FAILED" >&2
fi
exit $fail
