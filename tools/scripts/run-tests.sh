#!/bin/sh
# run-tests.sh TEST... - run CMocka suites, then print one closing line with the totals.
# Each suite is named as it starts and its output streams as it runs, then its time is printed.
# Exit status is non-zero if any suite failed or crashed.
passed=0; failed=0; skipped=0; bad=0
log=$(mktemp) || exit 1
trap 'rm -f "$log"' EXIT
rcf=$(mktemp) || exit 1
trap 'rm -f "$log" "$rcf"' EXIT
now() { date +%s.%N 2>/dev/null || date +%s; }
for t in "$@"; do
    echo "== suite ${t##*/}"
    t0=$(now)
    { "$t" 2>&1; echo $? >"$rcf"; } | tee "$log"
    rc=$(cat "$rcf")
    echo "== suite ${t##*/}: $(awk -v a="$t0" -v b="$(now)" 'BEGIN { printf "%.1f", b - a }') s"
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
