#!/usr/bin/env bash
# docs_check_test.sh - make docs-check must fail on a stale generated block or a typed figure.
# Copies the tree (tracked and new files, not build/ or out/) to a scratch directory, checks that
# the copy passes, then corrupts one thing at a time (each block docs.sh owns, docs/api.md, a
# figure typed into prose) and expects docs.sh --check to fail and to name what is stale.
# make docs-check-test runs it; it reuses the binaries of $BUILD (QIBL, GOLDEN).
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${BUILD:-build}
case "$BUILD" in /*) ;; *) BUILD="$root/$BUILD" ;; esac
export QIBL=${QIBL:-$BUILD/bin/qibl} GOLDEN=${GOLDEN:-$BUILD/bin/qibl-golden}
case "$QIBL" in /*) ;; *) QIBL="$root/$QIBL" ;; esac
case "$GOLDEN" in /*) ;; *) GOLDEN="$root/$GOLDEN" ;; esac
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
(cd "$root" && git ls-files -co --exclude-standard -z | tar --null -T - -cf -) | (cd "$scratch" && tar -xf -)
fail=0
pass=0

check() {   # check: docs.sh --check in the copy, its status; output in $scratch/out.txt
    (cd "$scratch" && BUILD="$scratch/build" QIBL="$QIBL" GOLDEN="$GOLDEN" bash tools/scripts/docs.sh --check) \
        > "$scratch/out.txt" 2>&1
}
expect_fail() {   # expect_fail WHAT PATTERN: docs-check fails and its output names PATTERN
    local what=$1 pattern=$2
    if check; then
        echo "docs_check_test: FAIL: $what: docs-check passed on a corrupted copy"; fail=1
    elif ! grep -q -- "$pattern" "$scratch/out.txt"; then
        echo "docs_check_test: FAIL: $what: docs-check failed but did not name '$pattern':"
        sed 's/^/    /' "$scratch/out.txt" | tail -n 5; fail=1
    else
        echo "docs_check_test: ok: $what (docs-check fails, naming '$pattern')"; pass=$((pass + 1))
    fi
}
save() { cp "$scratch/$1" "$scratch/$1.orig"; }
restore() { mv "$scratch/$1.orig" "$scratch/$1"; }
edit() {   # edit FILE PERL-EXPRESSION: change the copy, and fail the test if nothing changed
    save "$1"
    perl -0pi -e "$2" "$scratch/$1"
    if cmp -s "$scratch/$1" "$scratch/$1.orig"; then echo "docs_check_test: FAIL: the edit '$2' changed nothing in $1"; fail=1; fi
}

# the last make cross run's size table, when there is one: the copy checks porting.md against it
if [ -f "$BUILD/cross/size-table.md" ]; then
    mkdir -p "$scratch/build/cross" && cp "$BUILD/cross/size-table.md" "$scratch/build/cross/"
fi
# and the last make nds run's block (docs/porting.md's "make nds" block), when there is one
if [ -f "$BUILD/nds/tables.md" ]; then
    mkdir -p "$scratch/build/nds" && cp "$BUILD/nds/tables.md" "$scratch/build/nds/"
fi

if check; then echo "docs_check_test: ok: the untouched copy passes"
else echo "docs_check_test: FAIL: the untouched copy does not pass docs-check:"; sed 's/^/    /' "$scratch/out.txt" | tail -n 20; exit 1; fi

# a stale count in README's facts block (as if a golden case had been added since make docs)
edit README.md 's/(<!-- facts begin.*?\n(?:.*\n)*?\| golden cases[^|]*\| )(\d+)/$1 . ($2 + 1)/e'
expect_fail "stale facts block (README.md)" "facts block differs"
restore README.md

# a stale timing in README's bench block (typed over the log's value)
edit README.md 's/(<!-- bench begin.*?\n(?:.*\n)*?\| [^\n]*\| )([0-9.]+)( ms \|)/${1}9${2}${3}/'
expect_fail "stale bench block (README.md)" "bench block differs"
restore README.md

# a stale line count in ARCHITECTURE.md's lines block
edit docs/ARCHITECTURE.md 's/(<!-- lines begin.*?\n(?:.*\n)*?\| `core\/src` \| \d+ \| )(\d+)/$1 . ($2 + 7)/e'
expect_fail "stale lines block (docs/ARCHITECTURE.md)" "lines block differs"
restore docs/ARCHITECTURE.md

# a heading renamed without make docs: ARCHITECTURE.md's table of contents is stale
edit docs/ARCHITECTURE.md 's/^## Testing$/## Tests/m'
expect_fail "stale toc block (docs/ARCHITECTURE.md)" "toc block differs"
restore docs/ARCHITECTURE.md

# docs/api.md missing a function
edit docs/api.md 's/^\| `qibl_sh_rotate` \|.*\n//m'
expect_fail "stale docs/api.md" "docs/api.md differs"
restore docs/api.md

# a header comment changed without make docs: the index no longer matches the headers
edit core/include/qibl/sh.h 's/(\/\* Prepares the rotation of SH coefficients)/$1 (changed)/'
expect_fail "a header changed after make docs (docs/api.md)" "docs/api.md differs"
restore core/include/qibl/sh.h

# a measured figure typed into prose
edit README.md 's/(\n## Using the core\n)/\nA frame takes 1.7 ms on the build machine.\n$1/'
expect_fail "a typed figure (README.md)" "typed-figures"
restore README.md

# the memory table of docs/porting.md (memory-table.sh), when the CLI is built
if [ -x "$QIBL" ]; then
    edit docs/porting.md 's/(\| weights state \| )(\d+)/$1 . ($2 + 8)/e'
    expect_fail "stale memory-table block (docs/porting.md)" "memory-table"
    restore docs/porting.md
fi

# the size table of docs/porting.md (make cross's), when a make cross run left its table
if [ -f "$scratch/build/cross/size-table.md" ]; then
    edit docs/porting.md 's/(<!-- size-table begin.*?\n(?:.*\n)*?\| asset \| )(\d+)/$1 . ($2 + 4)/e'
    expect_fail "stale size-table block (docs/porting.md)" "size-table block differs"
    restore docs/porting.md
fi

# the DS block of docs/porting.md (make nds's), when a make nds run left its tables
if [ -f "$scratch/build/nds/tables.md" ]; then
    edit docs/porting.md 's/(\| ARM946E-S[^|]*\| )(\d+)/$1 . ($2 + 1)/e'
    expect_fail "stale make nds block (docs/porting.md)" "make nds block differs"
    restore docs/porting.md
fi

if check; then echo "docs_check_test: ok: the restored copy passes again"
else echo "docs_check_test: FAIL: the restored copy does not pass"; fail=1; fi
echo "docs_check_test: $pass corruptions caught"
[ $fail = 0 ] && echo "docs_check_test: OK" || echo "docs_check_test: FAILED"
exit $fail
