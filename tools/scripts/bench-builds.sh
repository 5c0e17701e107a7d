#!/bin/sh
# bench-builds.sh [BENCH] - `qibl bench BENCH` (default: baselines; lights, hemi and all with
# qibl-bench's twin comparisons) in several builds of the core:
# gcc and clang at -O2 and -O3, each with the default kernel path (SSE2 on plain x86-64), -mavx2
# where the CPU has it, and QIBL_CONFIG_SIMD=0 (the scalar reference, the "before" figures).
# Builds go to $BUILD/bench-<cc><opt>-<path>/; RESULT lines are printed with the build's name.
# Run it on a quiet machine; on a shared one, trust the minimum columns only.
# Env: PATHS (default "default avx2 scalar") picks the kernel paths, CCS (default "gcc clang") the
# compilers.
set -u
cd "$(dirname "$0")/../.." || exit 1
what=${1:-baselines}
base=${BUILD:-build}
mkdir -p "$base"
avx2=""; grep -qw avx2 /proc/cpuinfo 2>/dev/null && avx2=avx2
for cc in ${CCS:-gcc clang}; do
    command -v $cc >/dev/null 2>&1 || { echo "bench-builds: $cc not found, skipped"; continue; }
    for o in -O2 -O3; do
        for path in ${PATHS:-default $avx2 scalar}; do
            [ "$path" = avx2 ] && [ -z "$avx2" ] && continue
            case $path in default) f="$o" ;; avx2) f="$o -mavx2" ;; scalar) f="$o -DQIBL_CONFIG_SIMD=0" ;; esac
            name="$cc$o-$path"; b="$base/bench-$name"
            make -s -j2 --no-print-directory BUILD="$b" CC=$cc OPT="$o" CORE_OPT="$f" "$b/bin/qibl" "$b/bin/qibl-bench" \
                >"$b.log" 2>&1 || { echo "bench-builds: $name: build failed (see $b.log)"; continue; }
            echo "== $name (core $f)"
            { "$b/bin/qibl" bench "$what"
              # lights and hemi: also the kernel against its scalar twin (qibl-bench; not in qibl)
              case $what in lights|hemi|all) "$b/bin/qibl-bench" "$what" ;; esac
            } | sed -n "s/^RESULT \([^ ]*\)/RESULT $name.\1/p"
        done
    done
done
