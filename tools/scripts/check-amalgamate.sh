#!/bin/bash
# check-amalgamate.sh - prove the amalgamated core (make amalgamate: qibl.h + qibl.c) is the core:
#   1. qibl.c compiles with gcc and clang under the core's strict warnings at -O0/-O2/-O3/-Os, native
#      and portable arithmetic paths; qibl.h alone compiles as C99/C11 and C++98/11/17;
#   2. cross-compiled freestanding for Cortex-M0 and Cortex-M4 (and RV64IMAC if present): no
#      undefined symbol, no .data/.bss, as make cross requires of core/;
#   3. the golden runner built on it (the cases see only the amalgamated header, through -include)
#      prints every hash of fixtures/golden, and the integration example built on it prints the
#      same frames as build/bin/console_port.
set -u
cd "$(dirname "$0")/../.." || exit 1
build="${BUILD:-build}"
am="$build/amalgamated"
out="$build/check-amalgamate"
rm -rf "$out"; mkdir -p "$out"
fail=0
err() { echo "check-amalgamate: FAIL: $*" >&2; fail=1; }
[ -f "$am/qibl.c" ] && [ -f "$am/qibl.h" ] || { echo "check-amalgamate: run make amalgamate first" >&2; exit 1; }

warn="-std=c99 -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wundef -Wdouble-promotion -Wmissing-prototypes -Werror"
portable="-DQIBL_CONFIG_NATIVE_MUL64=0 -DQIBL_CONFIG_NATIVE_DIV64=0 -DQIBL_CONFIG_NATIVE_SHIFT64=0"

# ---- 1. strict warnings, both compilers, both arithmetic paths; the header in five modes --------
for cc in gcc clang; do
    for o in -O0 -O2 -O3 -Os; do
        $cc $warn $o -I"$am" -c "$am/qibl.c" -o "$out/qibl-$cc$o.o" || err "qibl.c with $cc $o"
        $cc $warn $portable $o -I"$am" -c "$am/qibl.c" -o "$out/qibl-$cc$o-portable.o" || err "qibl.c with $cc $o (portable paths)"
    done
    cxx=g++; [ $cc = clang ] && cxx=clang++
    printf '#include "qibl.h"\ntypedef int check_nonempty;\n' > "$out/h.c"
    printf '#include "qibl.h"\n' > "$out/h.cpp"
    for std in c99 c11; do $cc -std=$std -Wall -Wextra -Wpedantic -Werror -I"$am" -fsyntax-only "$out/h.c" || err "qibl.h as $std ($cc)"; done
    for std in c++98 c++11 c++17; do $cxx -std=$std -Wall -Wextra -Wpedantic -Werror -I"$am" -fsyntax-only "$out/h.cpp" || err "qibl.h as $std ($cxx)"; done
done
[ $fail = 0 ] && echo "check-amalgamate: qibl.c clean with gcc and clang (-O0/-O2/-O3/-Os, native and portable paths); qibl.h as C99/C11/C++98/11/17"

# ---- 2. freestanding cross builds ------------------------------------------------------------
targets="cortex-m0|arm-none-eabi-|-mcpu=cortex-m0 -mthumb -mfloat-abi=soft
cortex-m4|arm-none-eabi-|-mcpu=cortex-m4 -mthumb -mfloat-abi=soft
rv64imac|riscv64-unknown-elf-|-march=rv64imac -mabi=lp64 -mcmodel=medany"
while IFS='|' read -r name prefix flags; do
    gcc="${prefix}gcc"
    if ! command -v "$gcc" >/dev/null 2>&1; then
        [ "$name" = rv64imac ] && continue
        err "$gcc not found (Debian: apt-get install gcc-arm-none-eabi)"; continue
    fi
    inc="-nostdinc -isystem $($gcc -print-file-name=include) -isystem $($gcc -print-file-name=include-fixed)"
    o="$out/qibl-$name.o"
    # shellcheck disable=SC2086
    if $gcc $flags -ffreestanding -fno-builtin -nostdlib -fno-common -Os $warn $inc -I"$am" -c "$am/qibl.c" -o "$o"; then
        undef=$("${prefix}nm" -u "$o" | awk '{print $2}')
        state=$("${prefix}size" -A "$o" | awk '$1 ~ /^\.(s?data|s?bss|tdata|tbss)(\.|$)/ && $2 > 0 {print $1 "=" $2}')
        [ -z "$undef" ] || err "$name: the amalgamation needs symbols it does not define: $(echo $undef)"
        [ -z "$state" ] || err "$name: mutable state in $(echo $state)"
        text=$("${prefix}size" -A "$o" | awk '$1 ~ /^\.text/ {s += $2} END {print s + 0}')
        [ -z "$undef$state" ] && echo "check-amalgamate: $name -Os freestanding: 0 undefined symbols, 0 bytes .data/.bss, .text $text bytes"
    else
        err "$name: qibl.c does not compile freestanding"
    fi
done <<< "$targets"

# ---- 3. the golden cases and the example on the amalgamation ----------------------------------
# -include makes the amalgamated header come first: its guards then hide core/include's headers.
host="-std=c99 -D_POSIX_C_SOURCE=200809L -Wall -Wextra -Werror -O2 -include $am/qibl.h -Icore/include -Iplatform/soft/include -Itools"
objs=()
for src in tools/golden/cases*.c tools/golden/runner.c tools/io/sha256.c platform/soft/*.c; do
    o="$out/$(echo "$src" | tr '/' '_' | sed 's/\.c$/.o/')"
    # shellcheck disable=SC2086
    gcc $host -c "$src" -o "$o" || err "$src does not compile against the amalgamated header"
    objs+=("$o")
done
if gcc -o "$out/qibl-golden" "${objs[@]}" "$out/qibl-gcc-O2.o"; then
    if "$out/qibl-golden" --root . --config amalgamated > "$out/golden.txt" 2>&1; then
        echo "check-amalgamate: $(tail -n 1 "$out/golden.txt")"
    else
        err "the golden runner on the amalgamation: $(grep -E ' (MISMATCH|MISSING|ERROR)' "$out/golden.txt" | head -n 5)"
    fi
else
    err "the golden runner does not link with the amalgamated core"
fi
asset="$out/courtyard.qibl"
if "$build/bin/qibl" gen -o "$asset" --size 96x24 --k 9 > /dev/null &&
   "$build/bin/console_port" "$asset" 3 > "$out/ref.txt"; then
    soft=$(printf '%s\n' "${objs[@]}" | grep platform_soft)
    # shellcheck disable=SC2086
    if gcc -std=c99 -Wall -Wextra -Wpedantic -Wconversion -Werror -O2 -I"$am" -Iplatform/soft/include -Icore/include \
           -include "$am/qibl.h" tools/examples/console_port.c $soft "$out/qibl-gcc-O2.o" -o "$out/console_port" &&
       "$out/console_port" "$asset" 3 > "$out/example.txt" && cmp -s "$out/ref.txt" "$out/example.txt"; then
        echo "check-amalgamate: tools/examples/console_port on the amalgamation: same frames as build/bin/console_port"
    else
        err "tools/examples/console_port on the amalgamation does not build, run or print the same frames"
    fi
else
    err "no reference: $build/bin/qibl gen or $build/bin/console_port failed"
fi

if [ $fail = 0 ]; then echo "check-amalgamate: OK"; else echo "check-amalgamate: FAILED" >&2; fi
exit $fail
