#!/usr/bin/env bash
# tools/farm/submit_tiles.sh - a qibl bake on a Slurm cluster as N tile shards (bands of rows,
# bake/tile.h), each writing bytes proportional to its rows: a job array of pass 1 (`qibl bake
# --tile I/N --ranges-out`), a reduce job (`qibl merge --ranges`), a job array of pass 2 (`qibl bake
# --tile I/N --ranges --part`) and a merge job (`qibl merge -o ASSET PART...`), each started only
# when the one before succeeded (--dependency=afterok), writing ASSET byte for byte as one
# `qibl bake -o` would.
#
# usage: tools/farm/submit_tiles.sh N ASSET WORKDIR [qibl bake options: scene, --size, --k, --sun-path ...]
#   WORKDIR (on a disc every node sees) gets tile-I.ranges, ranges, tile-I.part, tile-I.cpu1 and
#   tile-I.cpu2 (user and system CPU seconds of each pass) and the jobs' logs.
# Environment: QIBL (the qibl binary, default: qibl on PATH), CPUS (CPUs per tile, default 1),
# SBATCH_ARGS (more sbatch options), TILE_CACHE (a node-local directory: pass 1 keeps its exact sums
# there and pass 2 reuses them when it lands on the same node; elsewhere it bakes again).
# Prints "ranges JOBID", "reduce JOBID", "parts JOBID" and "merge JOBID". Exit status: 0 submitted,
# 2 bad arguments, 1 sbatch failed.
set -euo pipefail
. "$(cd "$(dirname "$0")" && pwd)/args.sh"
farm_args "$0" tiles "the rows" "$@"
shift 3
cache=${TILE_CACHE:+--cache "$TILE_CACHE"}

# one pass of one tile: its CPU time (user, system seconds) to tile-I.cpuP, progress lines to the log
cat > "$work/tile.sbatch" <<JOB
#!/usr/bin/env bash
set -euo pipefail
i=\$SLURM_ARRAY_TASK_ID pass=\$1
shift
if [ "\$pass" = 1 ]; then out=(--ranges-out "$work/tile-\$i.ranges"); else out=(--ranges "$work/ranges" --part "$work/tile-\$i.part"); fi
${TILE_CACHE:+mkdir -p "$TILE_CACHE"}
TIMEFORMAT='%U %S'
{ time "$qibl" bake "\$@" --tile "\$i/$n" "\${out[@]}" $cache --progress=lines 2>&3 ; } 3>&2 2> "$work/tile-\$i.cpu\$pass"
JOB
ranges=() parts=()
for ((i = 0; i < n; ++i)); do ranges+=("$work/tile-$i.ranges"); parts+=("$work/tile-$i.part"); done
cat > "$work/reduce.sbatch" <<JOB
#!/usr/bin/env bash
set -euo pipefail
exec "$qibl" merge --ranges -o "$work/ranges" ${ranges[*]}
JOB
cat > "$work/merge.sbatch" <<JOB
#!/usr/bin/env bash
set -euo pipefail
exec "$qibl" merge -o "$asset" ${parts[*]}
JOB
sb() { # sbatch --parsable with the common options; the job id
    local id
    # shellcheck disable=SC2086 # SBATCH_ARGS is a list of options
    id=$(sbatch --parsable ${SBATCH_ARGS:-} "$@") || exit 1
    echo "${id%%;*}"
}
a1=$(sb --job-name=qibl-ranges --array=0-$((n - 1)) --cpus-per-task="${CPUS:-1}" --output="$work/tile-%a.log1" \
    "$work/tile.sbatch" 1 "$@")
r=$(sb --job-name=qibl-reduce --dependency=afterok:"$a1" --kill-on-invalid-dep=yes --cpus-per-task=1 \
    --output="$work/reduce.log" "$work/reduce.sbatch")
a2=$(sb --job-name=qibl-parts --dependency=afterok:"$r" --kill-on-invalid-dep=yes --array=0-$((n - 1)) \
    --cpus-per-task="${CPUS:-1}" --output="$work/tile-%a.log2" "$work/tile.sbatch" 2 "$@")
m=$(sb --job-name=qibl-merge --dependency=afterok:"$a2" --kill-on-invalid-dep=yes --cpus-per-task=1 \
    --output="$work/merge.log" "$work/merge.sbatch")
echo "ranges $a1"
echo "reduce $r"
echo "parts $a2"
echo "merge $m"
