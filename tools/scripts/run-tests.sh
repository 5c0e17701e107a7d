#!/bin/sh
# run-tests.sh TEST... - run CMocka suites, then print one closing line with the totals.
# Exit status is non-zero if any suite failed or crashed.
passed=0; failed=0; skipped=0; bad=0
log=$(mktemp) || exit 1
trap 'rm -f "$log"' EXIT
for t in "$@"; do
    "$t" >"$log" 2>&1
    rc=$?
    cat "$log"
    p=$(sed -n 's/^\[  PASSED  \] \([0-9]*\) test.*/\1/p' "$log" | tail -n 1)
    f=$(sed -n 's/^\[  FAILED  \] \([0-9]*\) test.*/\1/p' "$log" | tail -n 1)
    s=$(sed -n 's/^\[  SKIPPED \] \([0-9]*\) test.*/\1/p' "$log" | tail -n 1)
    [ -n "$p" ] || p=0
    [ -n "$f" ] || f=0
    [ -n "$s" ] || s=0
    skipped=$((skipped + s))
    if { [ "$p" = 0 ] && [ "$f" = 0 ] && [ "$s" = 0 ]; } || { [ $rc -ne 0 ] && [ "$f" = 0 ]; }; then
        echo "run-tests: $t exited with status $rc without a CMocka failure count (crashed?)" >&2
        bad=$((bad + 1)); f=$((f + 1))
    fi
    passed=$((passed + p)); failed=$((failed + f))
done
echo
echo "suites: $# run, $bad crashed"
echo "tests: $passed passed, $failed failed, $skipped skipped"
[ "$failed" = 0 ] && [ "$bad" = 0 ]
