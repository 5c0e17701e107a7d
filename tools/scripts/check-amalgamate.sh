#!/bin/bash
# check-amalgamate.sh - prove the amalgamated core (make amalgamate: qibl.h + qibl.c, and
# platform/soft as qibl_soft.h + qibl_soft.c) is the core:
#   1. qibl.c compiles with gcc and clang under the core's strict warnings at -O0/-O2/-O3/-Os, native
#      and portable arithmetic paths; qibl.h alone compiles as C99/C11 and C++98/11/17; qibl.c and
#      qibl_soft.c compile as C++98/11/17 with g++ and clang++ (strict warnings, both paths);
#   2. cross-compiled freestanding for Cortex-M0 and Cortex-M4 (and RV64IMAC if present): no
#      undefined symbol, no .data/.bss, as make cross requires of core/;
#   3. the golden runner built on it (the cases see only the amalgamated headers, through -include;
#      platform/soft from qibl_soft.c) prints every hash of fixtures/golden, and the integration
#      example built on it prints the same frames as build/bin/console_port: once with the pair
#      compiled as C, once compiled by g++ as C++11 and once as C++17.
set -u
cd "$(dirname "$0")/../.." || exit 1
build="${BUILD:-build}"
am="$build/amalgamated"
. tools/scripts/check-lib.sh
check_start check-amalgamate "$build/check-amalgamate"
for f in qibl.c qibl.h qibl_soft.c qibl_soft.h; do
    [ -f "$am/$f" ] || { echo "check-amalgamate: $am/$f missing: run make amalgamate first" >&2; exit 1; }
done

warn="-std=c99 -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wundef -Wdouble-promotion -Wmissing-prototypes -Werror"
portable="-DQIBL_CONFIG_NATIVE_MUL64=0 -DQIBL_CONFIG_NATIVE_DIV64=0 -DQIBL_CONFIG_NATIVE_SHIFT64=0"
cxxwarn="-Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wundef -Werror"

# ---- 1. strict warnings, both compilers, both arithmetic paths; the header in five modes --------
for cc in gcc clang; do
    for o in -O0 -O2 -O3 -Os; do
        $cc $warn $o -I"$am" -c "$am/qibl.c" -o "$out/qibl-$cc$o.o" || err "qibl.c with $cc $o"
        $cc $warn $portable $o -I"$am" -c "$am/qibl.c" -o "$out/qibl-$cc$o-portable.o" || err "qibl.c with $cc $o (portable paths)"
        $cc $warn $o -I"$am" -c "$am/qibl_soft.c" -o "$out/soft-$cc$o.o" || err "qibl_soft.c with $cc $o"
    done
    cxx=g++; [ $cc = clang ] && cxx=clang++
    # the pair as C++ (unity builds of C++ engines): the same strict warnings bar the C-only ones
    for std in c++98 c++11 c++17; do
        for o in -O0 -O2; do
            $cxx -x c++ -std=$std $cxxwarn $o -I"$am" -c "$am/qibl.c" -o "$out/qibl-$cxx-$std$o.o" ||
                err "qibl.c as $std with $cxx $o"
            $cxx -x c++ -std=$std $cxxwarn $portable $o -I"$am" -c "$am/qibl.c" -o "$out/qibl-$cxx-$std$o-portable.o" ||
                err "qibl.c as $std with $cxx $o (portable paths)"
            $cxx -x c++ -std=$std $cxxwarn $o -I"$am" -c "$am/qibl_soft.c" -o "$out/soft-$cxx-$std$o.o" ||
                err "qibl_soft.c as $std with $cxx $o"
        done
    done
    printf '#include "qibl.h"\ntypedef int check_nonempty;\n' > "$out/h.c"
    printf '#include "qibl.h"\n' > "$out/h.cpp"
    for std in c99 c11; do $cc -std=$std -Wall -Wextra -Wpedantic -Werror -I"$am" -fsyntax-only "$out/h.c" || err "qibl.h as $std ($cc)"; done
    for std in c++98 c++11 c++17; do $cxx -std=$std -Wall -Wextra -Wpedantic -Werror -I"$am" -fsyntax-only "$out/h.cpp" || err "qibl.h as $std ($cxx)"; done
done
[ $fail = 0 ] && echo "check-amalgamate: qibl.c clean with gcc and clang (-O0/-O2/-O3/-Os, native and portable paths); qibl.h as C99/C11/C++98/11/17; qibl.c and qibl_soft.c as C and as C++98/11/17 (g++, clang++, -O0/-O2)"

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
# -include makes the amalgamated headers come first: their guards then hide core/include's and
# platform/soft's headers. The cases, the runner and the example stay C; the pair under them is
# built as C (gcc) and as C++11 and C++17 (g++, linked by g++).
host="-std=c99 -D_POSIX_C_SOURCE=200809L -Wall -Wextra -Werror -O2 -include $am/qibl.h -include $am/qibl_soft.h -Icore/include -Iplatform/soft/include -Itools"
objs=()
for src in tools/golden/cases*.c tools/golden/runner.c tools/io/sha256.c; do
    o="$out/$(echo "$src" | tr '/' '_' | sed 's/\.c$/.o/')"
    # shellcheck disable=SC2086
    gcc $host -c "$src" -o "$o" || err "$src does not compile against the amalgamated headers"
    objs+=("$o")
done
asset="$out/courtyard.qibl"
have_ref=0
if "$build/bin/qibl" gen -o "$asset" --size 96x24 --k 9 > /dev/null &&
   "$build/bin/console_port" "$asset" 3 > "$out/ref.txt"; then
    have_ref=1
else
    err "no reference: $build/bin/qibl gen or $build/bin/console_port failed"
fi
# name | linker | core object | soft object
builds="C|gcc|$out/qibl-gcc-O2.o|$out/soft-gcc-O2.o
C++11|g++|$out/qibl-g++-c++11-O2.o|$out/soft-g++-c++11-O2.o
C++17|g++|$out/qibl-g++-c++17-O2.o|$out/soft-g++-c++17-O2.o"
while IFS='|' read -r lang ld core soft; do
    if $ld -o "$out/qibl-golden-$lang" "${objs[@]}" "$soft" "$core"; then
        if "$out/qibl-golden-$lang" --root . --config "amalgamated-$lang" > "$out/golden-$lang.txt" 2>&1; then
            echo "check-amalgamate: the pair built as $lang: $(tail -n 1 "$out/golden-$lang.txt")"
        else
            err "the golden runner on the amalgamation built as $lang: $(grep -E ' (MISMATCH|MISSING|ERROR)' "$out/golden-$lang.txt" | head -n 5)"
        fi
    else
        err "the golden runner does not link with the amalgamated core built as $lang"
    fi
    [ $have_ref = 1 ] || continue
    # shellcheck disable=SC2086
    if gcc -std=c99 -Wall -Wextra -Wpedantic -Wconversion -Werror -O2 -I"$am" -Iplatform/soft/include -Icore/include \
           -include "$am/qibl.h" -include "$am/qibl_soft.h" -c tools/examples/console_port.c -o "$out/console_port.o" &&
       $ld "$out/console_port.o" "$soft" "$core" -o "$out/console_port-$lang" &&
       "$out/console_port-$lang" "$asset" 3 > "$out/example-$lang.txt" && cmp -s "$out/ref.txt" "$out/example-$lang.txt"; then
        echo "check-amalgamate: tools/examples/console_port on the pair built as $lang: same frames as build/bin/console_port"
    else
        err "tools/examples/console_port on the amalgamation built as $lang does not build, run or print the same frames"
    fi
done <<< "$builds"

if [ $fail = 0 ]; then echo "check-amalgamate: OK"; else echo "check-amalgamate: FAILED" >&2; fi
exit $fail
