#!/bin/bash
# cross.sh - prove core/ is freestanding, integer-only and state-free on three targets.
#
# For Cortex-M0, Cortex-M4 (both soft-float ABI) and RV64IMAC (no FPU) it compiles every core/src/*.c
# with -ffreestanding -fno-builtin -nostdlib -nostdinc (only the compiler's own headers), links the
# objects into one relocatable blob and fails if the blob needs any symbol core/ does not define
# (soft-float helpers named as such), if .data/.bss (or small-data twins, or COMMON) are non-empty,
# or if core/ includes a header other than stdint.h, stddef.h, stdbool.h, limits.h and its own.
# Every freestanding platform backend (the backend contract, docs/ARCHITECTURE.md; today
# platform/soft, the software framebuffer shim) must pass the same checks: compiled the same way
# (plus its include dir) and linked with the core objects into a blob of its own. Hosted backends
# (platform/gles2: it needs GL headers) are not listed here; `make gles` and `make warnings` build them.
# Then prints .text per module and in total for Cortex-M4 -Os (core total, then platform/soft).
set -u
cd "$(dirname "$0")/../.." || exit 1
. tools/scripts/check-lib.sh
check_start cross "${BUILD:-build}/cross"
freestanding_backends="soft"

# 1. headers: only the four freestanding ones, and quoted includes of qibl's own headers (core/src's internal ones too).
bdirs=$(for b in $freestanding_backends; do printf 'platform/%s ' "$b"; done)
# Also allowed: the compiler's own intrinsics headers of QIBL_CONFIG_SIMD (config.h), which need no
# libc, included only on their path (SSE2 <emmintrin.h>, AVX2 <immintrin.h>, NEON <arm_neon.h>).
# And the run-time dispatch copies of hosted x86-64 (core/src/x86/<module>_<isa>.c, never built
# here) include their module's source, "../<module>.c".
# shellcheck disable=SC2086
bad=$(grep -rnE '^[[:space:]]*#[[:space:]]*include' core $bdirs |
      grep -vE '<(stdint|stddef|stdbool|limits|emmintrin|immintrin|arm_neon)\.h>|"qibli?(/[a-z0-9_]+)?\.h"|"[a-z0-9_]+_internal\.h"' |
      grep -vE '^core/src/x86/[a-z0-9_]+\.c:[0-9]+:#include "\.\./[a-z0-9]+\.c"$')
[ -z "$bad" ] || err "core/ or a freestanding backend ($bdirs) includes a header outside the freestanding four and the SIMD intrinsics headers:"$'\n'"$bad"
echo "cross: headers: stdint.h stddef.h stdbool.h limits.h, and the intrinsics headers emmintrin.h immintrin.h arm_neon.h on their QIBL_CONFIG_SIMD path only"

warn="-std=c99 -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wundef -Wdouble-promotion -Wmissing-prototypes -Werror"
common="-ffreestanding -fno-builtin -nostdlib -fno-common -Os $warn -Icore/include"

# name | compiler prefix | target flags
# (Cortex-M targets default to QIBL_CONFIG_SMALL=1, config.h: the proof builds every module; the
# default configuration's size is the first row of the combinations below)
targets="cortex-m0|arm-none-eabi-|-mcpu=cortex-m0 -mthumb -mfloat-abi=soft -DQIBL_CONFIG_SMALL=0
cortex-m4|arm-none-eabi-|-mcpu=cortex-m4 -mthumb -mfloat-abi=soft -DQIBL_CONFIG_SMALL=0
cortex-m4-O3|arm-none-eabi-|-mcpu=cortex-m4 -mthumb -mfloat-abi=soft -DQIBL_CONFIG_SMALL=0 -O3 -fno-tree-loop-distribute-patterns
rv64imac|riscv64-unknown-elf-|-march=rv64imac -mabi=lp64 -mcmodel=medany"

softfloat='^(__aeabi_[fd]|__aeabi_[ui]?[23]?[fd]|__(add|sub|mul|div|neg|cmp|eq|ne|lt|le|gt|ge|unord|fix|fixuns|float|floatun|extend|trunc|pow|powi)[a-z]*[sdtx]f[0-9]*$)'

while IFS='|' read -r name prefix flags; do
    gcc="${prefix}gcc"
    if ! command -v "$gcc" >/dev/null 2>&1; then
        err "$gcc not found (Debian: apt-get install gcc-arm-none-eabi gcc-riscv64-unknown-elf)"
        continue
    fi
    inc="-nostdinc -isystem $($gcc -print-file-name=include) -isystem $($gcc -print-file-name=include-fixed)"
    dir="$out/$name"; mkdir -p "$dir"
    ok=1
    for src in core/src/*.c; do
        # shellcheck disable=SC2086
        $gcc $flags $common $inc -c "$src" -o "$dir/$(basename "$src" .c).o" || { err "$name: $src does not compile"; ok=0; }
    done
    [ $ok = 1 ] || continue
    "${prefix}ld" -r "$dir"/*.o -o "$dir/qibl-core.o" || { err "$name: relocatable link failed"; continue; }
    undef=$("${prefix}nm" -u "$dir/qibl-core.o" | awk '{print $2}')
    if [ -n "$undef" ]; then
        sf=$(echo "$undef" | grep -E "$softfloat")
        [ -z "$sf" ] || err "$name: soft-float helpers referenced (core must be integer-only): $(echo $sf)"
        err "$name: undefined symbols core/ does not define: $(echo $undef)"
    fi
    common_syms=$("${prefix}nm" "$dir/qibl-core.o" | awk '$2 == "C" || $2 == "c" {print $3}')
    [ -z "$common_syms" ] || err "$name: COMMON symbols (mutable state): $(echo $common_syms)"
    state=$("${prefix}size" -A "$dir/qibl-core.o" | awk '$1 ~ /^\.(s?data|s?bss|tdata|tbss)(\.|$)/ && $2 > 0 {print $1 "=" $2}')
    [ -z "$state" ] || err "$name: mutable state in $(echo $state) (core must have none)"
    [ -z "$undef$common_syms$state" ] &&
        echo "cross: $name: $(ls "$dir"/*.o | grep -vc qibl-core.o) objects linked, 0 undefined symbols, 0 bytes .data/.bss" 

    # each freestanding backend: same flags plus its include dir, linked with the core blob (its only
    # dependency; backends never depend on each other)
    for b in $freestanding_backends; do
    pdir="$dir/platform/$b"; mkdir -p "$pdir"; pobjs=(); pok=1
    for src in platform/"$b"/*.c; do
        po="$pdir/$(basename "$src" .c).o"; pobjs+=("$po")
        # shellcheck disable=SC2086
        $gcc $flags $common -Iplatform/"$b"/include $inc -c "$src" -o "$po" || { err "$name: $src does not compile"; pok=0; }
    done
    [ $pok = 1 ] || continue
    "${prefix}ld" -r "${pobjs[@]}" "$dir/qibl-core.o" -o "$pdir/qibl-$b.o" || { err "$name: platform/$b link failed"; continue; }
    perr=0
    undef=$("${prefix}nm" -u "$pdir/qibl-$b.o" | awk '{print $2}')
    [ -z "$undef" ] || { err "$name: undefined symbols in platform/$b + core: $(echo $undef)"; perr=1; }
    common_syms=$("${prefix}nm" "$pdir/qibl-$b.o" | awk '$2 == "C" || $2 == "c" {print $3}')
    [ -z "$common_syms" ] || { err "$name: COMMON symbols in platform/$b: $(echo $common_syms)"; perr=1; }
    state=$("${prefix}size" -A "$pdir/qibl-$b.o" | awk '$1 ~ /^\.(s?data|s?bss|tdata|tbss)(\.|$)/ && $2 > 0 {print $1 "=" $2}')
    [ -z "$state" ] || { err "$name: mutable state in platform/$b + core: $(echo $state)"; perr=1; }
    [ $perr = 1 ] || echo "cross: $name: platform/$b (${#pobjs[@]} objects) + core linked, 0 undefined symbols, 0 bytes .data/.bss"
    done
done <<< "$targets"

# 2. size table for Cortex-M4 -Os
if [ -f "$out/cortex-m4/qibl-core.o" ]; then
    echo
    echo "core .text on Cortex-M4 (-Os, thumb, soft-float ABI), every module (QIBL_CONFIG_SMALL=0), bytes:"
    printf '  %-12s %8s %8s\n' module .text .rodata
    md="$out/size-table.md"
    printf '| module | .text | .rodata |\n|---|---:|---:|\n' > "$md"
    # size_rows DIR SKIP NOTE MDNOTE: a row per object of DIR but SKIP.o, its .text* and .rodata*
    # bytes (NOTE after it on the terminal, MDNOTE after its name in the table); sets st and sr,
    # their sums
    size_rows() {
        local o m t r
        st=0; sr=0
        for o in "$1"/*.o; do
            m=$(basename "$o" .o); [ "$m" = "$2" ] && continue
            read -r t r < <(arm-none-eabi-size -A "$o" | awk '$1 ~ /^\.text/ {t += $2} $1 ~ /^\.rodata/ {r += $2} END {print t + 0, r + 0}')
            printf '  %-12s %8d %8d%s\n' "$m" "$t" "$r" "$3"
            printf '| %s%s | %d | %d |\n' "$m" "$4" "$t" "$r" >> "$md"
            st=$((st + t)); sr=$((sr + r))
        done
    }
    size_rows "$out/cortex-m4" qibl-core "" ""
    total=$st rtotal=$sr
    printf '  %-12s %8d %8d\n' "core total" "$total" "$rtotal"
    printf '| **core** | **%d** | %d |\n' "$total" "$rtotal" >> "$md"
    size_rows "$out/cortex-m4/platform/soft" qibl-soft "   (platform/soft, not in the core total)" " (platform/soft, not in the core)"
    stotal=$st
    echo "RESULT cross.m4_text_bytes_every_module $total"
    echo "RESULT cross.m4_soft_text_bytes $stotal"

    # 3. what config.h can compile out: the core's .text for module combinations (Cortex-M4 -Os)
    # against the goal of 16 KiB for the whole core (docs/porting.md explains the choice).
    goal=16384
    echo
    echo "core .text on Cortex-M4 -Os by config.h combination (goal: <= $goal bytes, 0 bytes .data/.bss):"
    printf '\n| config.h combination | .text | goal (%d bytes) |\n|---|---:|---|\n' "$goal" >> "$md"
    gcc=arm-none-eabi-gcc
    inc="-nostdinc -isystem $($gcc -print-file-name=include) -isystem $($gcc -print-file-name=include-fixed)"
    # the first row is the default of a Cortex-M build (config.h: QIBL_CONFIG_SMALL=1 on M-profile
    # targets); the others start from every module (QIBL_CONFIG_SMALL=0) and leave some out
    combos="default on Cortex-M (QIBL_CONFIG_SMALL=1: no lightprobe, probe, hemi, lightpath, gonio)|default|
default on Cortex-M plus light paths (QIBL_USE_LIGHTPATH=1)|small-lightpath|-DQIBL_USE_LIGHTPATH=1
every module (QIBL_CONFIG_SMALL=0)|all|-DQIBL_CONFIG_SMALL=0
runtime relighting (QIBL_CONFIG_SMALL=0 QIBL_USE_LIGHTPROBE=0)|relight|-DQIBL_CONFIG_SMALL=0 -DQIBL_USE_LIGHTPROBE=0
relighting without sRGBE (QIBL_CONFIG_SMALL=0 QIBL_USE_LIGHTPROBE=0 QIBL_USE_SRGBE=0)|relight-nosrgbe|-DQIBL_CONFIG_SMALL=0 -DQIBL_USE_LIGHTPROBE=0 -DQIBL_USE_SRGBE=0
light probes only (QIBL_CONFIG_SMALL=0 QIBL_USE_SHMAP=0 QIBL_USE_SH=0 QIBL_USE_ASSET=0)|lightprobe|-DQIBL_CONFIG_SMALL=0 -DQIBL_USE_SHMAP=0 -DQIBL_USE_SH=0 -DQIBL_USE_ASSET=0
planar relighting (QIBL_CONFIG_SMALL=0 QIBL_USE_LIGHTPROBE=0 QIBL_USE_INTERLEAVED=0)|relight-planar|-DQIBL_CONFIG_SMALL=0 -DQIBL_USE_LIGHTPROBE=0 -DQIBL_USE_INTERLEAVED=0
no asset parser (QIBL_CONFIG_SMALL=0 QIBL_USE_LIGHTPROBE=0 QIBL_USE_ASSET=0)|relight-noasset|-DQIBL_CONFIG_SMALL=0 -DQIBL_USE_LIGHTPROBE=0 -DQIBL_USE_ASSET=0
probe SH lighting (QIBL_CONFIG_SMALL=0 QIBL_USE_SHMAP=0 QIBL_USE_ASSET=0 QIBL_USE_SRGBE=0)|probe|-DQIBL_CONFIG_SMALL=0 -DQIBL_USE_SHMAP=0 -DQIBL_USE_ASSET=0 -DQIBL_USE_SRGBE=0"
    while IFS='|' read -r label tag defs; do
        cdir="$out/cortex-m4-config-$tag"; mkdir -p "$cdir"; ctotal=0; cok=1
        for src in core/src/*.c; do
            o="$cdir/$(basename "$src" .c).o"
            # shellcheck disable=SC2086
            $gcc -mcpu=cortex-m4 -mthumb -mfloat-abi=soft $common $inc $defs -c "$src" -o "$o" || { err "config $tag: $src does not compile"; cok=0; continue; }
            t=$(arm-none-eabi-size -A "$o" | awk '$1 ~ /^\.text/ {s += $2} END {print s + 0}')
            ctotal=$((ctotal + t))
        done
        [ $cok = 1 ] || continue
        state=$(for o in "$cdir"/*.o; do arm-none-eabi-size -A "$o"; done | awk '$1 ~ /^\.(s?data|s?bss)(\.|$)/ && $2 > 0' | wc -l)
        [ "$state" = 0 ] || err "config $tag: mutable state"
        if [ $ctotal -le $goal ]; then verdict="meets the goal ($((goal - ctotal)) bytes to spare)"
        else verdict="over the goal by $((ctotal - goal)) bytes"; fi
        printf '  %-68s %6d  %s\n' "$label" "$ctotal" "$verdict"
        printf '| %s | %d | %s |\n' "$label" "$ctotal" "$verdict" >> "$md"
        echo "RESULT cross.m4_text_bytes.$tag $ctotal" >> "$out/config-results.txt"
        if [ "$tag" = default ]; then
            echo "RESULT cross.m4_text_bytes $ctotal" >> "$out/config-results.txt"
            [ $ctotal -le $goal ] || err "the default Cortex-M4 configuration is $ctotal bytes of .text, over the goal of $goal"
        fi
    done <<< "$combos"
    cat "$out/config-results.txt" 2>/dev/null
    # the tables in docs/porting.md are this run's: `make docs-size` rewrites them, and this check
    # fails when they drifted (GCC arm-none-eabi as installed; other versions give other bytes)
    if [ "${QIBL_SIZE_DOC:-check}" = write ]; then
        bash tools/scripts/doc-block.sh size-table docs/porting.md "$md" --write
    else
        bash tools/scripts/doc-block.sh size-table docs/porting.md "$md" --check || err "docs/porting.md size table differs from this run: make docs-size"
    fi
fi
if [ $fail = 0 ]; then echo "cross: OK"; else echo "cross: FAILED" >&2; fi
exit $fail
