#!/usr/bin/env bash
# tools/farm/submit.sh - a qibl bake on a Slurm cluster: a job array of N shards
# (`qibl bake --shard $SLURM_ARRAY_TASK_ID/N --sums ...`) and a merge job that starts only when every
# shard succeeded (--dependency=afterok), writing ASSET byte for byte as one `qibl bake -o` would.
#
# usage: tools/farm/submit.sh N ASSET WORKDIR [qibl bake options: scene, --size, --k, --sun-path ...]
#   WORKDIR (on a disc every node sees) gets shard-I.sums (+ .u, .x), shard-I.cpu (user and system
#   CPU seconds), manifest.txt (every shard's files) and the jobs' logs.
# Environment: QIBL (the qibl binary, default: qibl on PATH), CPUS (CPUs per shard, default 1: the
# bake takes its threads from the allocation), SBATCH_ARGS (more sbatch options, e.g. a partition).
# Prints "array JOBID" and "merge JOBID". Exit status: 0 submitted, 2 bad arguments, 1 sbatch failed.
set -euo pipefail
. "$(cd "$(dirname "$0")" && pwd)/args.sh"
farm_args "$0" shards "4096" "$@"
shift 3

# the manifest: every shard's files, named (qibl merge --manifest reads it and checks each I/N)
: > "$work/manifest.txt"
for ((i = 0; i < n; ++i)); do
    echo "shard $i/$n $work/shard-$i.sums $work/shard-$i.sums.u $work/shard-$i.sums.x" >> "$work/manifest.txt"
done

cat > "$work/shard.sbatch" <<JOB
#!/usr/bin/env bash
# one shard: its CPU time (user, system seconds) to shard-I.cpu, qibl's progress lines to the log
set -euo pipefail
i=\$SLURM_ARRAY_TASK_ID
TIMEFORMAT='%U %S'
{ time "$qibl" bake "\$@" --shard "\$i/$n" --sums "$work/shard-\$i.sums" --progress=lines 2>&3 ; } 3>&2 2> "$work/shard-\$i.cpu"
JOB
cat > "$work/merge.sbatch" <<JOB
#!/usr/bin/env bash
set -euo pipefail
exec "$qibl" merge -o "$asset" --manifest "$work/manifest.txt"
JOB
# shellcheck disable=SC2086 # SBATCH_ARGS is a list of options
array=$(sbatch --parsable ${SBATCH_ARGS:-} --job-name=qibl-bake --array=0-$((n - 1)) --cpus-per-task="${CPUS:-1}" \
    --output="$work/shard-%a.log" "$work/shard.sbatch" "$@") || exit 1
array=${array%%;*}
# shellcheck disable=SC2086
merge=$(sbatch --parsable ${SBATCH_ARGS:-} --job-name=qibl-merge --dependency=afterok:"$array" --kill-on-invalid-dep=yes \
    --cpus-per-task=1 --output="$work/merge.log" "$work/merge.sbatch") || exit 1
merge=${merge%%;*}
echo "array $array"
echo "merge $merge"
