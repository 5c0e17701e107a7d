#!/bin/bash
# baremetal/run.sh - the golden runner on bare metal (make baremetal): Cortex-M0 code (ARMv6-M,
# soft float) on qemu's mps2-an385 (a Cortex-M3, which runs ARMv6-M code), Cortex-M4 code on
# mps2-an386, RV32IMAC on qemu's virt machine; picolibc, semihosting output. Every case must print
# the hash of fixtures/golden/<case>.sha256, and the set of cases must be that of the hosted
# runner (build/bin/qibl-golden). Per target it also: computes the worst-case stack of every
# public entry point from -fstack-usage/-fcallgraph-info (stack.py), measures what each wrapped
# entry point used in the run (probe.S, painting) and fails if a measurement exceeds its bound;
# and counts instructions per relit pixel under qemu -icount (bench.c, RESULT lines; the issue's
# figures are the Cortex-M4 ones), with the streamed-rows example of docs/porting.md checked.
# Env: BUILD (default build; output in $BUILD/baremetal/<target>), BM_ONLY (target names),
# BM_NO_BENCH=1 (skip the instruction counts).
set -u
cd "$(dirname "$0")/../.." || exit 1
# shellcheck source=tools/baremetal/common.sh
. tools/baremetal/common.sh
bm_start baremetal "${BUILD:-build}/baremetal"

need() { have "$1" || { err "$1 not found (Debian: apt-get install $2)"; }; }
need arm-none-eabi-gcc gcc-arm-none-eabi
need riscv64-unknown-elf-gcc gcc-riscv64-unknown-elf
need qemu-system-arm qemu-system-arm
need qemu-system-riscv32 qemu-system-misc
need python3 python3
for t in arm-none-eabi riscv64-unknown-elf; do
    [ -f /usr/lib/picolibc/$t/picolibc.specs ] || err "picolibc for $t not found (Debian: apt-get install picolibc-$t)"
done
[ $fail = 0 ] || exit 1

bm_host_golden
bm_src="tools/baremetal/main.c tools/baremetal/semi.c tools/baremetal/putu.c tools/baremetal/stack.c tools/baremetal/heap.c tools/baremetal/tls.c"

# name | gcc prefix | target flags | -O | qemu command
# (Cortex-M builds default to QIBL_CONFIG_SMALL=1, config.h; here every module is built and run)
targets="cortex-m0|arm-none-eabi-|-mcpu=cortex-m0 -mthumb -mfloat-abi=soft -DQIBL_CONFIG_SMALL=0|-Os|qemu-system-arm -M mps2-an385
cortex-m4|arm-none-eabi-|-mcpu=cortex-m4 -mthumb -mfloat-abi=soft -DQIBL_CONFIG_SMALL=0|-O2|qemu-system-arm -M mps2-an386
rv32imac|riscv64-unknown-elf-|-march=rv32imac -mabi=ilp32 -mcmodel=medany|-O2|qemu-system-riscv32 -M virt -bios none"
qemu_common="-nographic -monitor none -serial none -semihosting-config enable=on,target=native"

# build_objs DIR PREFIX FLAGS OPT: core objects (freestanding, with stack and call-graph info),
# the cases, SHA-256 and the runner (picolibc); sets objs
build_objs() {
    local dir=$1 prefix=$2 flags=$3 opt=$4
    local gcc="${prefix}gcc" triple="${prefix%-}"
    local specs="-specs=/usr/lib/picolibc/$triple/picolibc.specs"
    mkdir -p "$dir/core" "$dir/tools"
    objs=()
    local src o
    for src in $core_src; do
        o="$dir/core/$(basename "$src" .c).o"; objs+=("$o")
        # shellcheck disable=SC2086
        $gcc $flags $opt $core_warn -ffreestanding -fno-builtin -fno-tree-loop-distribute-patterns -g \
            -fstack-usage -fcallgraph-info=su -Icore/include -Iplatform/soft/include -c "$src" -o "$o" \
            -dumpbase "$dir/core/$(basename "$src" .c).c" || return 1
    done
    for src in $tool_src $bm_src; do
        o="$dir/tools/$(basename "$src" .c).o"; objs+=("$o")
        # shellcheck disable=SC2086
        $gcc $specs $flags $opt $tool_warn -g -DBM_CONFIG="\"$name\"" -Icore/include -Iplatform/soft/include -Itools \
            -c "$src" -o "$o" || return 1
    done
}

# link DIR PREFIX FLAGS OPT ELF OBJ...: the cases' calls of the malloc family go to heap.c and
# their calls of the probed core entry points to probe.S (objcopy renames them in the case objects)
link_elf() {
    local dir=$1 prefix=$2 flags=$3 opt=$4 elf=$5; shift 5
    local gcc="${prefix}gcc" triple="${prefix%-}"
    local specs="-specs=/usr/lib/picolibc/$triple/picolibc.specs"
    local ld=tools/baremetal/cm.ld redef=() f o
    [ "$prefix" = riscv64-unknown-elf- ] && ld=tools/baremetal/rv32.ld
    for f in malloc calloc realloc free; do redef+=(--redefine-sym "$f=bm_$f"); done
    for f in $probed; do redef+=(--redefine-sym "$f=bm_probe_$f"); done
    for o in "$dir"/tools/cases*.o; do "${prefix}objcopy" "${redef[@]}" "$o" || return 1; done
    # shellcheck disable=SC2086
    $gcc $specs $flags $opt -nostartfiles -T "$ld" -Wl,--gc-sections,--no-warn-rwx-segments -o "$elf" "$@" -lc -lgcc
}

# link_bench PREFIX FLAGS OPT ELF OBJ...: bench.c with the core, no renaming
link_bench() {
    local prefix=$1 flags=$2 opt=$3 elf=$4; shift 4
    local ld=tools/baremetal/cm.ld triple="${prefix%-}"
    [ "$prefix" = riscv64-unknown-elf- ] && ld=tools/baremetal/rv32.ld
    # shellcheck disable=SC2086
    "${prefix}gcc" -specs=/usr/lib/picolibc/$triple/picolibc.specs $flags $opt -nostartfiles -T "$ld" \
        -Wl,--gc-sections,--no-warn-rwx-segments -o "$elf" "$@" -lc -lgcc
}

t_start=$(date +%s)
rm -f "$out/bench-all.txt"
summary=()
while IFS='|' read -r name prefix flags opt qemu; do
    dir="$out/$name"
    rm -rf "$dir"; mkdir -p "$dir"
    gcc="${prefix}gcc" triple="${prefix%-}"
    specs="-specs=/usr/lib/picolibc/$triple/picolibc.specs"
    arch=arm; [ "$prefix" = riscv64-unknown-elf- ] && arch=riscv
    build_objs "$dir" "$prefix" "$flags" "$opt" || { err "$name: compile failed"; continue; }
    crt=tools/baremetal/crt_cm.c; [ $arch = riscv ] && crt="tools/baremetal/crt_rv.S tools/baremetal/rv_fault.c"
    crt_objs=()
    for src in $crt; do
        o="$dir/tools/$(basename "${src%.*}").o"; objs+=("$o"); crt_objs+=("$o")
        # shellcheck disable=SC2086
        $gcc $specs $flags $opt $tool_warn -g -Itools/baremetal -c "$src" -o "$o" || { err "$name: $src"; continue 2; }
    done
    # stack bounds of every public entry point, then trampolines for the ones the cases call
    python3 tools/baremetal/stack.py --objdump "${prefix}objdump" "$dir/core" > "$dir/stack-bounds.txt" ||
        err "$name: an entry point has no static stack bound: $(grep unbounded "$dir/stack-bounds.txt" | head -3)"
    probed=$("${prefix}nm" -u "$dir"/tools/cases*.o | awk '$2 ~ /^qibl_/ && $2 !~ /^qibl_(sha256|goldens)/ {print $2}' | sort -u)
    python3 tools/baremetal/gen_probe.py $arch "$dir/stack-bounds.txt" "$dir" $probed || { err "$name: gen_probe"; continue; }
    probed=$(sed -n 's/^bm_probe_\([a-z0-9_]*\):$/\1/p' "$dir/probe.S")
    for src in "$dir/probe.S" "$dir/probe_table.c"; do
        o="${src%.*}-$(basename "${src##*.}").o"; objs+=("$o")
        # shellcheck disable=SC2086
        $gcc $specs $flags $opt -g -Itools/baremetal -c "$src" -o "$o" || { err "$name: $src"; continue 2; }
    done
    link_elf "$dir" "$prefix" "$flags" "$opt" "$dir/qibl-golden.elf" "${objs[@]}" || { err "$name: link failed"; continue; }
    "${prefix}size" "$dir/qibl-golden.elf" > "$dir/size.txt"

    # run: semihosting output to stdout, exit status from the runner
    t0=$(date +%s)
    # shellcheck disable=SC2086
    timeout 600 $qemu $qemu_common -kernel "$dir/qibl-golden.elf" > "$dir/run.txt" 2>&1 # (semihosting writes to stderr)
    rc=$? secs=$(( $(date +%s) - t0 ))
    [ $rc = 0 ] || err "$name: the run exited with $rc ($(tail -n 2 "$dir/run.txt" | tr '\n' ' '))"
    # the crt set up picolibc's TLS: a forced failed malloc put errno inside the TLS block (tls.c)
    grep -q '^tls ok' "$dir/run.txt" || err "$name: no TLS check line ($(grep -m1 'TLS' "$dir/run.txt"))"

    # every case: the hash of fixtures/golden; the set of cases: the hosted runner's
    ok=0 bad=0
    while read -r _ case hash _; do
        want=$(head -c 64 "fixtures/golden/$case.sha256" 2>/dev/null)
        if [ "$hash" = "$want" ]; then ok=$((ok + 1)); else bad=$((bad + 1)); err "$name: case $case: $hash, fixtures/golden says ${want:-nothing}"; fi
    done < <(grep '^case ' "$dir/run.txt")
    awk '$1 == "case" {print $2}' "$dir/run.txt" > "$dir/cases.txt"
    if ! cmp -s "$dir/cases.txt" "$out/host-cases.txt"; then
        err "$name: the cases differ from the hosted runner's: $(diff "$out/host-cases.txt" "$dir/cases.txt" | grep '^[<>]' | head -5 | tr '\n' ' ')"
    fi
    hd=$(sed -n 's/^golden: .*digest \([0-9a-f]*\)$/\1/p' "$out/host.txt")
    bd=$(sed -n 's/^golden: .*digest \([0-9a-f]*\)$/\1/p' "$dir/run.txt")
    [ -n "$bd" ] && [ "$hd" = "$bd" ] || err "$name: digest ${bd:-missing}, hosted runner ${hd}"

    # measured stack of each wrapped entry point against its static bound
    bm_stack_figures "$dir" 1024 "$name: "
    text=$(awk 'NR == 2 {print $1}' "$dir/size.txt")
    # instruction counts per relit pixel and the streaming example (bench.c), under -icount shift=0
    if [ "${BM_NO_BENCH:-0}" != 1 ]; then
        tag=${name#cortex-}; tag=${tag%imac}
        # shellcheck disable=SC2086
        $gcc $specs $flags $opt $tool_warn -g -DBM_TAG="\"$tag\"" -Icore/include -Iplatform/soft/include -Itools \
            -Itools/baremetal -c tools/baremetal/bench.c -o "$dir/tools/bench.o" &&
        link_bench "$prefix" "$flags" "$opt" "$dir/bench.elf" "$dir"/core/*.o "$dir/tools/bench.o" "$dir/tools/sha256.o" \
            "$dir/tools/semi.o" "$dir/tools/putu.o" "$dir/tools/stack.o" "${crt_objs[@]}" || err "$name: bench build failed"
        if [ -f "$dir/bench.elf" ]; then
            # shellcheck disable=SC2086
            timeout 300 $qemu $qemu_common -icount shift=0 -kernel "$dir/bench.elf" > "$dir/bench.txt" 2>&1 ||
                err "$name: bench failed: $(grep -v '^RESULT' "$dir/bench.txt" | tail -n 2 | tr '\n' ' ')"
            grep -E '^(RESULT|stream|bench:|mem )' "$dir/bench.txt" | sed "s/^/baremetal: $name: /" >> "$out/bench-all.txt"
        fi
    fi

    summary+=("$(printf '%-10s %4d ok %3d bad  %3ds  %3d entry points measured (deepest: %s B), run high-water %s B, .text %s B' \
        "$name" $ok $bad $secs "$probes" "$deep" "$hw" "$text")")
done <<< "$(if [ -n "${BM_ONLY:-}" ]; then echo "$targets" | grep -E "^(${BM_ONLY// /|})\|"; else echo "$targets"; fi)"

echo "baremetal: target     cases        time  stack (measured per call, and the whole run)"
for s in "${summary[@]}"; do echo "baremetal: $s"; done
[ -f "$out/bench-all.txt" ] && grep -v ': mem ' "$out/bench-all.txt"
# make baremetal-tables: the generated tables of docs/porting.md (tables.py)
if [ -n "${BM_TABLES:-}" ] && [ $fail = 0 ]; then
    python3 tools/baremetal/tables.py "$out" "$BM_TABLES" || err "tables.py failed"
fi
echo "baremetal: $(($(date +%s) - t_start)) s"
if [ $fail = 0 ]; then echo "baremetal: OK (every case prints the hash of fixtures/golden on every target)"; else echo "baremetal: FAILED"; fi
exit $fail
