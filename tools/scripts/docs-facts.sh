#!/usr/bin/env bash
# docs-facts.sh [--lines] - the deterministic facts the docs state, printed as Markdown for the
# generated blocks of tools/scripts/docs.sh (make docs writes them, make docs-check compares).
#   (default)  README.md's facts block: golden cases and their digest (qibl-golden), suites, test
#              cases and fuzz targets (counted in the sources), exported functions (docs/api.md)
#   --lines    docs/ARCHITECTURE.md's lines block: lines of C per folder
# Counts come from the sources, never from a run that could skip: a case is one cmocka_unit_test*
# entry of a tests/*_test.c suite.
set -euo pipefail
cd "$(dirname "$0")/../.."
GOLDEN=${GOLDEN:-${BUILD:-build}/bin/qibl-golden}

if [ "${1:-}" = --lines ]; then
    echo "| folder | files | lines of C |"
    echo "|---|---:|---:|"
    for d in core/include core/src platform/soft platform/gles2 $(ls -d tools/*/ | sed 's:/$::') tests; do
        files=$(find "$d" -type f \( -name '*.c' -o -name '*.h' \) | sort)
        [ -n "$files" ] || continue
        n=$(echo "$files" | wc -l)
        # shellcheck disable=SC2086
        l=$(cat $files | wc -l)
        echo "| \`$d\` | $n | $l |"
    done
    exit 0
fi

[ -x "$GOLDEN" ] || { echo "docs-facts: no $GOLDEN (make $GOLDEN)" >&2; exit 1; }
g=$(QIBL_ISA= "$GOLDEN" | grep '^golden: .* cases, ')
cases=$(echo "$g" | sed -n 's/^golden: [^:]*: \([0-9]*\) cases, .*/\1/p')
digest=$(echo "$g" | sed -n 's/.*digest \([0-9a-f]*\).*/\1/p')
suites=$(ls tests/*_test.c | wc -l)
tests=$(cat tests/*_test.c | grep -o 'cmocka_unit_test[a-z_]*(' | wc -l)
fuzz=$(ls tests/fuzz/fuzz_*.c | wc -l)
api=$(python3 tools/scripts/api-index.py | grep -c '^| `qibl_')
echo "| what | how many | where it comes from |"
echo "|---|---:|---|"
echo "| golden cases (one SHA-256 of output bytes each, the same on every port) | $cases | \`make golden\` (\`qibl-golden\`); their digest: \`$digest\` |"
echo "| CMocka suites (each built twice: native kernels and \`-portable\` arithmetic) | $suites | \`tests/*_test.c\` |"
echo "| test cases in those suites | $tests | \`cmocka_unit_test\` entries of \`tests/*_test.c\` |"
echo "| libFuzzer targets | $fuzz | \`tests/fuzz/fuzz_*.c\` (docs/robustness.md) |"
echo "| exported functions of the public headers | $api | [docs/api.md](docs/api.md) |"
