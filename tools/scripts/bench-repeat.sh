#!/bin/sh
# bench-repeat.sh - `make bench-repeat`: `make bench`'s two programs run twice back to back, and every
# RESULT ratio (a name with _over_, speedup or _x) of the first run set beside the second's, with
# their relative difference |a - b| / min(a, b). A report, not a test: timing never fails a build.
# Usage: QIBL=build/bin/qibl QIBL_BENCH=build/bin/qibl-bench sh tools/scripts/bench-repeat.sh [OUT_DIR]
set -eu
out=${1:-out/bench-repeat}
mkdir -p "$out"
qibl=${QIBL:-build/bin/qibl}
qbench=${QIBL_BENCH:-build/bin/qibl-bench}
for run in 1 2; do
    echo "bench-repeat: run $run of 2 ($(date -u +%H:%M:%SZ), load $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo ?))"
    { "$qibl" bench all && "$qbench" all; } > "$out/run$run.txt" 2>&1 || {
        echo "bench-repeat: run $run failed (see $out/run$run.txt)" >&2
        exit 1
    }
done
awk '
    FNR == 1 { f++ }
    $1 == "RESULT" && ($2 ~ /_over_/ || $2 ~ /speedup/ || $2 ~ /_x$/) && $3 + 0 > 0 {
        if (f == 1) { a[$2] = $3; order[++n] = $2 } else b[$2] = $3
    }
    END {
        printf "%-52s %10s %10s %8s\n", "ratio", "run 1", "run 2", "diff"
        within = 0; m = 0
        for (i = 1; i <= n; i++) {
            k = order[i]
            if (!(k in b)) continue
            lo = a[k] < b[k] ? a[k] : b[k]
            d = (a[k] > b[k] ? a[k] - b[k] : b[k] - a[k]) / lo
            m++; if (d <= 0.15) within++
            printf "%-52s %10s %10s %7.1f%%%s\n", k, a[k], b[k], 100 * d, d <= 0.15 ? "" : "  (over 15 %)"
        }
        printf "RESULT bench.repeat_ratios %d\nRESULT bench.repeat_within_15pct %d\n", m, within
    }' "$out/run1.txt" "$out/run2.txt"
