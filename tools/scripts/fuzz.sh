#!/bin/sh
# fuzz.sh [--replay] BIN... - run each libFuzzer target for FUZZ_SECONDS, print one line per target
# (executions, coverage, corpus size, peak RSS) and exit non-zero if any target had a finding.
#
# Corpora per target NAME (BIN is .../fuzz_NAME), B = $FUZZ_DIR (build/fuzz): $B/corpus/NAME (kept
# between runs; new inputs go there), $B/seeds/NAME (made by `make fuzz` from the project's writers) and
# tests/fuzz/corpus/NAME (hand-made, committed); tests/fuzz/NAME.dict is the target's dictionary
# when there is one. A finding leaves its input in
# $B/artifacts/NAME/ and the log in $B/logs/NAME.log.
# FUZZ_SEED: libFuzzer's -seed (the CI smoke run fixes it, so a CI finding reproduces on the same
# machine; `make fuzz` leaves it random to explore).
# --replay: run each target once over tests/fuzz/crashes-found/NAME/* (inputs that once failed) and
# report which still fail.
replay=0
if [ "${1:-}" = --replay ]; then replay=1; shift; fi
B=${FUZZ_DIR:-build/fuzz}
secs=${FUZZ_SECONDS:-60}
limits="-rss_limit_mb=${FUZZ_RSS_MB:-2048} -malloc_limit_mb=${FUZZ_MALLOC_MB:-512} -timeout=${FUZZ_TIMEOUT:-10}"
mkdir -p "$B/logs"
# the first line of a log that says what went wrong
why() {
    w=$(grep -a -m1 -E 'invariant broken|runtime error|Sanitizer: [a-z]|out-of-memory|libFuzzer: timeout' "$1")
    [ -n "$w" ] || w=$(grep -a -m1 -E 'ERROR: ' "$1")
    echo "$w" | sed 's/^.*\(invariant\)/\1/' | cut -c1-140
}
bad=0
for bin in "$@"; do
    name=${bin##*/fuzz_}
    log=$B/logs/$name.log
    if [ $replay = 1 ]; then
        mkdir -p "$B/artifacts"
        set -- tests/fuzz/crashes-found/"$name"/*
        [ -e "$1" ] || { printf 'fuzz-crashes: %-10s no inputs\n' "$name"; continue; }
        for f in "$@"; do
            # shellcheck disable=SC2086
            if "$bin" $limits -artifact_prefix="$B/artifacts/replay-" "$f" >"$log" 2>&1; then
                printf 'fuzz-crashes: %-10s ok    %s\n' "$name" "$f"
            else
                printf 'fuzz-crashes: %-10s FAILS %s: %s\n' "$name" "$f" "$(why "$log")"
                bad=$((bad + 1))
            fi
        done
        continue
    fi
    mkdir -p "$B/corpus/$name" "$B/artifacts/$name" "$B/seeds/$name"
    dirs="$B/corpus/$name $B/seeds/$name"
    [ -d "tests/fuzz/corpus/$name" ] && dirs="$dirs tests/fuzz/corpus/$name"
    dict=
    [ -f "tests/fuzz/$name.dict" ] && dict=-dict=tests/fuzz/$name.dict
    # shellcheck disable=SC2086
    seed=
    [ -n "${FUZZ_SEED:-}" ] && seed=-seed=$FUZZ_SEED
    # shellcheck disable=SC2086
    "$bin" -max_total_time="$secs" -print_final_stats=1 -max_len="${FUZZ_MAX_LEN:-4096}" $limits $dict $seed \
        -artifact_prefix="$B/artifacts/$name/" $dirs >"$log" 2>&1
    rc=$?
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
    rss=$(sed -n 's/^stat::peak_rss_mb: *//p' "$log" | tail -n 1)
    # the last status line of libFuzzer ("#N DONE cov: C ft: F corp: U/S ...")
    last=$(grep -aE '^#[0-9]+' "$log" | tail -n 1)
    cov=$(echo "$last" | sed -n 's/.* cov: \([0-9]*\).*/\1/p')
    ft=$(echo "$last" | sed -n 's/.* ft: \([0-9]*\).*/\1/p')
    corp=$(echo "$last" | sed -n 's/.* corp: \([0-9]*\).*/\1/p')
    if [ $rc = 0 ]; then
        verdict=ok
    else
        verdict="FINDING (exit $rc): $(why "$log"); input:\
 $B/artifacts/$name/$(ls -t "$B/artifacts/$name" 2>/dev/null | head -n 1); log: $log"
        bad=$((bad + 1))
    fi
    printf 'fuzz: %-10s %ss  execs %-9s cov %-5s ft %-6s corpus %-5s rss %sMB  %s\n' "$name" "$secs" \
        "${execs:-?}" "${cov:-?}" "${ft:-?}" "${corp:-?}" "${rss:-?}" "$verdict"
done
if [ $bad != 0 ]; then
    if [ $replay = 1 ]; then echo "fuzz-crashes: $bad input(s) still fail" >&2; else echo "fuzz: $bad finding(s)" >&2; fi
    exit 1
fi
[ $replay = 1 ] || echo "fuzz: $# target(s), no finding"
