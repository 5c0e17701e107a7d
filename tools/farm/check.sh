#!/usr/bin/env bash
# tools/farm/check.sh - `make check-farm`: a one-node Slurm cluster on this machine, configured
# here in a temporary directory (munge key, slurm.conf with the machine's own hostname, CPUs and
# memory from `slurmd -C`), munged, slurmctld and slurmd started and stopped by this script; a bake
# submitted through tools/farm/submit.sh as an array of 4 shards plus the afterok merge job; the
# merged asset must equal a single-machine bake byte for byte; then the same bake as 4 tile shards
# through tools/farm/submit_tiles.sh (two arrays, a reduce and a merge, chained by afterok), equal
# byte for byte too. Prints RESULT farm.shard_balance (the slowest shard's CPU time over the mean),
# farm.tile_output_over_share (the largest part's bytes over its rows' share of the asset's),
# farm.tile_pass1_cpu_s and farm.tile_pass2_cpu_s (CPU seconds of each pass, all tiles) and
# farm.tile_cpu_over_shards (both passes' CPU over the direction shards'), and with TILE_CACHE (pass 2
# reading pass 1's sums back) farm.tile_cached_cpu_over_shards.
# Every wait is bounded (FARM_TIMEOUT seconds, default 240): it never hangs CI.
# Needs root (slurmd) and Debian's slurm-wlm and munge; skips (exit 0, "SKIP") without them unless
# QIBL_REQUIRE_FARM=1.
set -euo pipefail
BUILD=${BUILD:-build}
QIBL=$(cd "$(dirname "$BUILD/bin/qibl")" && pwd)/qibl
here=$(cd "$(dirname "$0")" && pwd)
limit=${FARM_TIMEOUT:-240}

missing=
for c in munged slurmctld slurmd sbatch scontrol; do
    command -v $c >/dev/null 2>&1 || missing="$missing $c"
done
if [ -n "$missing" ] || [ "$(id -u)" != 0 ]; then
    why=${missing:+missing$missing (apt-get install slurm-wlm munge)}
    why=${why:-not root (slurmd must run as root)}
    if [ "${QIBL_REQUIRE_FARM:-0}" = 1 ]; then echo "check-farm: $why" >&2; exit 1; fi
    echo "SKIP: check-farm: $why"
    exit 0
fi

t=$(mktemp -d /tmp/qibl-farm.XXXXXX)
chmod 755 "$t"
pids=()
cleanup() {
    for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
    for p in "${pids[@]}"; do timeout 10 tail --pid="$p" -f /dev/null 2>/dev/null || kill -9 "$p" 2>/dev/null || true; done
    if [ "${FARM_KEEP:-0}" = 1 ]; then echo "check-farm: kept $t"; else rm -rf "$t"; fi
}
trap cleanup EXIT
fail() {
    echo "check-farm: FAIL: $*" >&2
    for f in "$t"/log/*.log "$t"/work/*.log; do [ -f "$f" ] && { echo "--- $f" >&2; tail -n 15 "$f" >&2; }; done
    exit 1
}
mkdir -p "$t/munge" "$t/log" "$t/state" "$t/spool" "$t/work"
chmod 700 "$t/munge"

# munge: a fresh key and its own socket (a system munged, if any, is left alone)
dd if=/dev/urandom of="$t/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$t/munge/munge.key"
munged --force --key-file="$t/munge/munge.key" --socket="$t/munge/munge.sock" --pid-file="$t/munge/munged.pid" \
    --log-file="$t/log/munged.log" --seed-file="$t/munge/seed" || fail "munged did not start"
pids+=("$(cat "$t/munge/munged.pid")")

host=$(hostname -s)
node=$(slurmd -C | head -n 1) # NodeName=HOST CPUs=... RealMemory=... as slurmd sees the machine
cpus=$(echo "$node" | sed -n 's/.*CPUs=\([0-9]*\).*/\1/p')
port=$((20000 + $$ % 20000))
cat > "$t/slurm.conf" <<CONF
ClusterName=qiblfarm
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$t/munge/munge.sock
StateSaveLocation=$t/state
SlurmdSpoolDir=$t/spool/slurmd-%n
SlurmctldPidFile=$t/slurmctld.pid
SlurmdPidFile=$t/slurmd.pid
SlurmctldLogFile=$t/log/slurmctld.log
SlurmdLogFile=$t/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MpiDefault=none
SwitchType=switch/none
SlurmctldTimeout=30
SlurmdTimeout=30
MinJobAge=600
$node NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=farm Nodes=$host Default=YES MaxTime=INFINITE State=UP OverSubscribe=NO
CONF
export SLURM_CONF=$t/slurm.conf
slurmctld -D -f "$SLURM_CONF" > "$t/log/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" > "$t/log/slurmd.out" 2>&1 &
pids+=($!)

deadline=$(($(date +%s) + limit))
until scontrol show node "$host" 2>/dev/null | grep -Eq 'State=(IDLE|MIXED|ALLOCATED)'; do
    [ "$(date +%s)" -lt "$deadline" ] || fail "the node did not come up within ${limit} s"
    sleep 1
done
echo "check-farm: one-node Slurm cluster up ($host, $cpus CPUs, port $port)"

# a small bake with a sun path and lamp occlusion (the parts that used to stay on shard 0)
args=(--size "${FARM_SIZE:-256x64}" --k 9 --dirs 256 --unshadowed-k 4 --sun-path 40,15,7,17
      --lamp-box -2,-2,-1,2,2,0 --lamp-samples 16 --path-steps 16)
out=$(QIBL=$QIBL CPUS=1 bash "$here/submit.sh" 4 "$t/work/farm.qibl" "$t/work" "${args[@]}") || fail "submit.sh: $out"
echo "$out" | sed 's/^/check-farm: submitted /'
merge=$(echo "$out" | awk '$1 == "merge" {print $2}')
wait_job() { # wait_job ID WHAT: until the job completed (fail on a failed state or the deadline)
    local st
    while :; do
        st=$(scontrol show job "$1" 2>/dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p')
        case $st in
            COMPLETED) return 0 ;;
            FAILED | CANCELLED | TIMEOUT | NODE_FAIL | OUT_OF_MEMORY | BOOT_FAIL | DEADLINE) fail "$2 job $1: $st" ;;
        esac
        if [ "$(date +%s)" -ge "$deadline" ]; then
            scancel "$1" 2>/dev/null || true
            fail "the farm bake did not finish within ${limit} s ($2 job ${st:-unknown})"
        fi
        sleep 1
    done
}
wait_job "$merge" merge
"$QIBL" bake "${args[@]}" --quiet -o "$t/work/one.qibl" > /dev/null || fail "the single-machine bake failed"
cmp "$t/work/one.qibl" "$t/work/farm.qibl" || fail "the merged asset differs from the single-machine bake"
echo "check-farm: the merged asset equals the single-machine bake ($(wc -c < "$t/work/one.qibl") bytes)"
grep -h '^progress: ' "$t/work/shard-0.log" | tail -n 1 | sed 's/^/check-farm: shard 0 log: /'
for i in 0 1 2 3; do
    [ -s "$t/work/shard-$i.cpu" ] || fail "no CPU time from shard $i"
done
awk '{ c = $1 + $2; s += c; if (c > m) m = c; n++ } END {
    printf "check-farm: shard CPU seconds: mean %.3f, slowest %.3f\n", s / n, m;
    printf "RESULT farm.shard_balance %.3f\n", m / (s / n) }' "$t"/work/shard-[0-3].cpu

# the same bake as 4 tile shards (bands of rows): pass-1 array, reduce, pass-2 array, merge
out=$(QIBL=$QIBL CPUS=1 bash "$here/submit_tiles.sh" 4 "$t/work/tiles.qibl" "$t/work/tiles" "${args[@]}") ||
    fail "submit_tiles.sh: $out"
echo "$out" | sed 's/^/check-farm: submitted tiles /'
wait_job "$(echo "$out" | awk '$1 == "merge" {print $2}')" "tile merge"
cmp "$t/work/one.qibl" "$t/work/tiles.qibl" || fail "the merged tile parts differ from the single-machine bake"
echo "check-farm: the merged tile parts equal the single-machine bake"
h=${FARM_SIZE:-256x64}
h=${h#*x}
asset=$(wc -c < "$t/work/one.qibl")
for i in 0 1 2 3; do
    for p in 1 2; do [ -s "$t/work/tiles/tile-$i.cpu$p" ] || fail "no pass-$p CPU time from tile $i"; done
    # part bytes over its share of the asset: asset bytes x its rows / h (rows as bake/tile.h bands them)
    echo "$i $(wc -c < "$t/work/tiles/tile-$i.part") $(cat "$t/work/tiles/tile-$i.cpu1") $(cat "$t/work/tiles/tile-$i.cpu2")"
done | awk -v a="$asset" -v h="$h" -v sh="$(cat "$t"/work/shard-[0-3].cpu | awk '{ s += $1 + $2 } END { print s }')" '{
    rows = int(h * ($1 + 1) / 4) - int(h * $1 / 4); r = $2 / (a * rows / h); if (r > m) m = r
    c1 += $3 + $4; c2 += $5 + $6 } END {
    printf "check-farm: tile parts: at most %.3f of their share of the %d-byte asset; CPU seconds: pass 1 %.3f, pass 2 %.3f (the shards: %.3f)\n", m, a, c1, c2, sh;
    printf "RESULT farm.tile_output_over_share %.3f\n", m;
    printf "RESULT farm.tile_pass1_cpu_s %.3f\nRESULT farm.tile_pass2_cpu_s %.3f\n", c1, c2;
    printf "RESULT farm.tile_cpu_over_shards %.3f\n", (c1 + c2) / sh }'

# again with TILE_CACHE: pass 2 reads pass 1's sums back on this one node (CPU of one bake)
out=$(QIBL=$QIBL CPUS=1 TILE_CACHE="$t/cache" bash "$here/submit_tiles.sh" 4 "$t/work/cached.qibl" "$t/work/cached" \
    "${args[@]}") || fail "submit_tiles.sh (TILE_CACHE): $out"
wait_job "$(echo "$out" | awk '$1 == "merge" {print $2}')" "cached tile merge"
cmp "$t/work/one.qibl" "$t/work/cached.qibl" || fail "the merged tile parts (TILE_CACHE) differ from the single-machine bake"
grep -q "(sums from the cache)" "$t"/work/cached/tile-0.log2 || fail "pass 2 of tile 0 did not read the cache"
cat "$t"/work/cached/tile-[0-3].cpu[12] | awk -v sh="$(cat "$t"/work/shard-[0-3].cpu | awk '{ s += $1 + $2 } END { print s }')" '{
    c += $1 + $2 } END {
    printf "check-farm: with TILE_CACHE the merged parts equal it too; both passes: %.3f CPU seconds\n", c;
    printf "RESULT farm.tile_cached_cpu_over_shards %.3f\n", c / sh }'

