#!/bin/bash
# ports.sh - build the golden runner (tools/golden/runner.c) for every compiler, optimisation level
# and architecture at hand, run each build (under qemu-user for foreign ones) and prove that all of
# them print the same hash for every golden case, and the hashes of fixtures/golden.
#
# Configurations: x86-64 with gcc and clang at -O0/-O2/-O3 (plus -Os, -O3 -march=native, the
# arm-none-eabi ABI defaults, the portable Cortex-M0 arithmetic paths, and clang's ASan + UBSan +
# implicit-conversion checks); 32-bit x86 (gcc -m32 if the multilib works, else the i686-linux-gnu
# cross gcc, also under UBSan); armhf, aarch64 and 32-bit big-endian PowerPC with their Debian cross
# gcc at -O0/-O2/-O3/-Os and with clang --target at -O2, linked statically and run with qemu-arm,
# qemu-aarch64 and qemu-ppc. The integration example (tools/examples/console_port.c) is built in
# every configuration and run on one asset; its output must agree too. Missing required tools
# fail with the package to install; optional ones (32-bit x86, clang cross targets) are skipped
# with a note.
#
# Every build compiles core/ and platform/soft/ with the core's strict warning set and the runner
# with -Wall -Wextra -Wpedantic, -Werror throughout. Output: the case list of the first
# configuration, one table row per configuration, and "ports: OK" or the cases that differ.
# Env: BUILD (build dir, default build; configurations go to $BUILD/ports/<name>), JOBS (parallel
# builds, default: the number of CPUs), PORTS_ONLY and PORTS_EXTRA (below).
set -u
cd "$(dirname "$0")/../.." || exit 1
root=$(pwd)
. tools/scripts/check-lib.sh
check_start ports "${BUILD:-build}/ports"
jobs=${JOBS:-$(getconf _NPROCESSORS_ONLN 2>/dev/null || echo 2)}

core_warn="-std=c99 -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wundef -Wdouble-promotion -Wmissing-prototypes -Werror"
tool_warn="-std=c99 -Wall -Wextra -Wpedantic -Werror"
inc="-Icore/include -Iplatform/soft/include -Itools"
portable="-DQIBL_CONFIG_NATIVE_MUL64=0 -DQIBL_CONFIG_NATIVE_DIV64=0 -DQIBL_CONFIG_NATIVE_SHIFT64=0"
core_src=$(ls core/src/*.c platform/soft/*.c)
tool_src=$(ls tools/golden/cases*.c tools/golden/runner.c tools/io/sha256.c)

have() { command -v "$1" >/dev/null 2>&1; }

# ---- the configuration list: name|compiler|flags|runner prefix ----------------------------------
configs=()
need() { # need TOOL PACKAGE: a required tool
    have "$1" || err "$1 not found (Debian: apt-get install $2)"
}
need gcc gcc; need clang clang
need arm-linux-gnueabihf-gcc gcc-arm-linux-gnueabihf
need aarch64-linux-gnu-gcc gcc-aarch64-linux-gnu
need powerpc-linux-gnu-gcc gcc-powerpc-linux-gnu
need qemu-arm qemu-user; need qemu-aarch64 qemu-user; need qemu-ppc qemu-user
for cc in gcc clang; do
    have $cc || continue
    for o in -O0 -O2 -O3; do configs+=("x86_64-$cc$o|$cc|$o|"); done
done
have gcc && configs+=("x86_64-gcc-Os|gcc|-Os|")
have gcc && configs+=("x86_64-gcc-O3-native|gcc|-O3 -march=native|")
# the ABI defaults of arm-none-eabi (the Cortex-M builds of make cross): enums as small as they fit,
# unsigned plain char
have gcc && configs+=("x86_64-gcc-O2-short-enums|gcc|-O2 -fshort-enums -funsigned-char|")
# a reduced config.h (runtime relighting only): the groups it keeps must give the same hashes
have gcc && configs+=("x86_64-gcc-Os-no-lightprobe|gcc|-Os -DQIBL_USE_LIGHTPROBE=0|")
# the Cortex-M default (QIBL_CONFIG_SMALL=1: no light probes, probe projection, hemi, light paths)
have gcc && configs+=("x86_64-gcc-Os-small|gcc|-Os -DQIBL_CONFIG_SMALL=1|")
have gcc && configs+=("x86_64-gcc-O2-portable|gcc|-O2 $portable|")
have clang && configs+=("x86_64-clang-O3-portable|clang|-O3 $portable|")
# the kernel paths of QIBL_CONFIG_SIMD (config.h): scalar C forced, and AVX2 where the CPU has it
# (the plain x86-64 builds above take SSE2, the aarch64 ones NEON)
have gcc && configs+=("x86_64-gcc-O2-scalar|gcc|-O2 -DQIBL_CONFIG_SIMD=0|")
# the SSE2 sRGBE encoder's integer-only 2^k (srgbe.c, SRGBE_SSE2_HORNER), the measured alternative
have gcc && configs+=("x86_64-gcc-O2-sse2-horner|gcc|-O2 -DSRGBE_SSE2_HORNER|")
if grep -qw avx2 /proc/cpuinfo 2>/dev/null; then
    for cc in gcc clang; do have $cc && for o in -O2 -O3; do configs+=("x86_64-$cc$o-avx2|$cc|$o -mavx2|"); done; done
else
    note_avx2="x86-64 AVX2: SKIPPED (this CPU has no AVX2)"
fi
# sanitizers: any finding stops the runner. clang's implicit-conversion checks also catch conversions
# that C leaves implementation-defined (an out-of-range value into a signed type), which UBSan
# proper does not; the i686 build runs UBSan on the 32-bit, no-native-division paths.
have clang && configs+=("x86_64-clang-O1-sanitize|clang|-O1 -fsanitize=address,undefined,implicit-conversion -fno-sanitize-recover=all|")

# 32-bit x86: gcc -m32 where the multilib is installed; on Debian gcc-multilib conflicts with the
# cross compilers above, so else the i686 cross gcc (gcc-i686-linux-gnu), static, run natively.
probe="$out/probe"; mkdir -p "$probe"; printf '#include <stdio.h>\nint main(void){return puts("")<0;}\n' > "$probe/t.c"
if have gcc && gcc -m32 "$probe/t.c" -o "$probe/m32" 2>/dev/null && "$probe/m32" >/dev/null 2>&1; then
    for o in -O0 -O2; do configs+=("x86_32-gcc-m32$o|gcc|-m32 $o|"); done
    note32="x86 32-bit: gcc -m32"
elif have i686-linux-gnu-gcc && i686-linux-gnu-gcc -static "$probe/t.c" -o "$probe/i686" 2>/dev/null; then
    run32=""; "$probe/i686" >/dev/null 2>&1 || run32="qemu-i386"
    for o in -O0 -O2; do configs+=("x86_32-gcc$o|i686-linux-gnu-gcc|$o -static|$run32"); done
    # libubsan cannot be linked fully statically: a dynamic build run by qemu-i386 with the cross libc
    if have qemu-i386 && i686-linux-gnu-gcc -fsanitize=undefined -static-libubsan "$probe/t.c" -o "$probe/i686u" 2>/dev/null &&
        qemu-i386 -L /usr/i686-linux-gnu "$probe/i686u" >/dev/null 2>&1; then
        configs+=("x86_32-gcc-O1-ubsan|i686-linux-gnu-gcc|-O1 -fsanitize=undefined -fno-sanitize-recover=all -static-libubsan|qemu-i386 -L /usr/i686-linux-gnu")
    fi
    note32="x86 32-bit: gcc -m32 unavailable (gcc-multilib conflicts with the cross compilers on Debian), so i686-linux-gnu-gcc -static"
    if have clang && clang --target=i686-linux-gnu -static "$probe/t.c" -o "$probe/ci686" 2>/dev/null; then
        configs+=("x86_32-clang-O2|clang|--target=i686-linux-gnu -O2 -static|$run32")
    fi
else
    note32="x86 32-bit: SKIPPED (no working gcc -m32 and no i686-linux-gnu-gcc; apt-get install gcc-i686-linux-gnu)"
fi

# name|gcc triple|qemu
for t in "armhf|arm-linux-gnueabihf|qemu-arm" "aarch64|aarch64-linux-gnu|qemu-aarch64" "ppc32be|powerpc-linux-gnu|qemu-ppc"; do
    IFS='|' read -r arch triple q <<< "$t"
    have "$triple-gcc" || continue
    for o in -O0 -O2 -O3; do configs+=("$arch-gcc$o|$triple-gcc|$o -static|$q"); done
    # -Os, as make cross builds; on armhf also the Cortex-M0 arithmetic paths in Thumb-2
    if [ "$arch" = armhf ]; then configs+=("$arch-gcc-Os-portable|$triple-gcc|-Os -mthumb $portable -static|$q")
    else configs+=("$arch-gcc-Os|$triple-gcc|-Os -static|$q"); fi
    # armv7 with NEON: the NEON kernels (Debian armhf's default FPU has none, so the rows above are scalar)
    [ "$arch" = armhf ] && configs+=("$arch-gcc-O2-neon|$triple-gcc|-O2 -mfpu=neon -static|$q")
    if have clang && clang --target="$triple" -static "$probe/t.c" -o "$probe/c-$arch" 2>/dev/null; then
        configs+=("$arch-clang-O2|clang|--target=$triple -O2 -static|$q")
    else
        clang_skip="${clang_skip:-} $arch"
    fi
done

# PORTS_EXTRA adds configurations ("name|compiler|flags|runner prefix", newline-separated);
# PORTS_ONLY (an extended regex) keeps only the configurations whose names match.
while IFS= read -r c; do [ -n "$c" ] && configs+=("$c"); done <<< "${PORTS_EXTRA:-}"
if [ -n "${PORTS_ONLY:-}" ]; then
    kept=()
    for c in "${configs[@]}"; do [[ "${c%%|*}" =~ $PORTS_ONLY ]] && kept+=("$c"); done
    configs=("${kept[@]}")
fi

# ---- build (in parallel), then run (in order) ----------------------------------------------------
build_one() { # name cc flags -> $out/name/qibl-golden and console_port, build.log, build.time
    local name=$1 cc=$2 flags=$3 d="$out/$1" t0 t1 ok=1
    mkdir -p "$d/core" "$d/tools"
    t0=$(date +%s.%N)
    for f in $core_src; do
        # shellcheck disable=SC2086
        $cc $flags $core_warn $inc -c "$f" -o "$d/core/$(basename "$f" .c).o" >> "$d/build.log" 2>&1 || ok=0
    done
    for f in $tool_src; do
        # shellcheck disable=SC2086
        $cc $flags $tool_warn $inc -c "$f" -o "$d/tools/$(basename "$f" .c).o" >> "$d/build.log" 2>&1 || ok=0
    done
    # shellcheck disable=SC2086
    [ $ok = 1 ] && $cc $flags "$d"/core/*.o "$d"/tools/*.o -o "$d/qibl-golden" >> "$d/build.log" 2>&1 || ok=0
    # the integration example: core + platform/soft + libc, nothing else
    # shellcheck disable=SC2086
    [ $ok = 1 ] && $cc $flags $tool_warn $inc tools/examples/console_port.c "$d"/core/*.o -o "$d/console_port" \
        >> "$d/build.log" 2>&1 || ok=0
    t1=$(date +%s.%N)
    echo "$t0 $t1" | awk '{printf "%.1f", $2 - $1}' > "$d/build.time"
    [ $ok = 1 ] || rm -f "$d/qibl-golden" "$d/console_port"
}

# an asset for the example, from the native CLI when it is built (make ports builds it first)
asset=""
cli="${BUILD:-build}/bin/qibl"
if [ -x "$cli" ] && "$cli" gen -o "$out/example.qibl" --size 96x24 --k 9 > "$out/example-gen.log" 2>&1; then
    asset="$out/example.qibl"
else
    note_example="examples: not run ($cli gen failed or is missing); built only"
fi

running=0
for c in "${configs[@]}"; do
    IFS='|' read -r name cc flags q <<< "$c"
    build_one "$name" "$cc" "$flags" &
    running=$((running + 1))
    if [ $running -ge "$jobs" ]; then wait -n; running=$((running - 1)); fi
done
wait

# the NEON paths must really be NEON: the relight kernel's widening multiply-accumulate (smlal on
# aarch64, vmlal on armv7) in shmap.o of every NEON build
for c in "${configs[@]}"; do
    IFS='|' read -r name cc flags q <<< "$c"
    case "$name" in aarch64-gcc-O[23]|aarch64-clang-O2|armhf-gcc-O2-neon) ;; *) continue ;; esac
    o="$out/$name/core/shmap.o"; [ -f "$o" ] || continue
    case "$name" in aarch64*) od=aarch64-linux-gnu-objdump; ins='smlal' ;; *) od=arm-linux-gnueabihf-objdump; ins='vmlal' ;; esac
    nn=$($od -d "$o" 2>/dev/null | grep -c "$ins")
    if [ "${nn:-0}" -gt 0 ]; then echo "ports: $name: NEON relight kernel present ($nn $ins in shmap.o)"
    else err "$name: no $ins in shmap.o: the NEON path was not built"; fi
    # the sRGBE bulk kernels: the encoder's interleaving store and the decoder's leading-zero count
    o="$out/$name/core/srgbe.o"; [ -f "$o" ] || continue
    case "$name" in aarch64*) pat='st4[[:space:]]|clz[[:space:]]+v' ;; *) pat='vst4\.8|vclz\.i32' ;; esac
    nn=$($od -d "$o" 2>/dev/null | grep -cE "$pat")
    if [ "${nn:-0}" -ge 2 ]; then echo "ports: $name: NEON sRGBE kernels present ($nn of /$pat/ in srgbe.o)"
    else err "$name: /$pat/ found $nn times in srgbe.o: the NEON sRGBE path was not built"; fi
    # the light-probe SAT row and colour sums: per-lane 64-bit shifts and widening multiplies
    o="$out/$name/core/lightprobe.o"; [ -f "$o" ] || continue
    case "$name" in aarch64*) pat='ushl[[:space:]]+v|umull[[:space:]]+v' ;; *) pat='vshl\.u64|vmull\.u32' ;; esac
    nn=$($od -d "$o" 2>/dev/null | grep -cE "$pat")
    if [ "${nn:-0}" -ge 2 ]; then echo "ports: $name: NEON light-probe passes present ($nn of /$pat/ in lightprobe.o)"
    else err "$name: /$pat/ found $nn times in lightprobe.o: the NEON light-probe path was not built"; fi
done
ref=""; refname=""; exref=""; n=0; same=0
fmt='%-28s %6s %-14s %-10s %-9s %8s %8s'
rows=()
for c in "${configs[@]}"; do
    IFS='|' read -r name cc flags q <<< "$c"
    d="$out/$name"; n=$((n + 1))
    if [ ! -x "$d/qibl-golden" ]; then
        err "$name: build failed ($cc $flags):"$'\n'"$(tail -n 20 "$d/build.log")"
        # shellcheck disable=SC2059
        rows+=("$(printf "$fmt" "$name" - "BUILD FAILED" no - "$(cat "$d/build.time")" -)")
        continue
    fi
    t0=$(date +%s.%N)
    # shellcheck disable=SC2086
    $q "$d/qibl-golden" --root "$root" --config "$name" > "$d/out.txt" 2> "$d/err.txt"
    rc=$?
    t1=$(date +%s.%N)
    rt=$(echo "$t0 $t1" | awk '{printf "%.2f", $2 - $1}')
    grep '^case ' "$d/out.txt" | awk '{print $2, $3}' > "$d/hashes.txt"
    cases=$(wc -l < "$d/hashes.txt")
    summary=$(grep '^golden: ' "$d/out.txt" | tail -n 1)
    if [ -z "$summary" ]; then
        err "$name: the runner crashed (exit $rc): $(tail -n 3 "$d/err.txt")"
        verdict="CRASHED"
    elif [ $rc -ne 0 ]; then
        verdict="$(echo "$summary" | sed -n 's/.* \([0-9]*\) failed.*/\1/p') FAILED"
        err "$name: cases differ from fixtures/golden:"$'\n'"$(grep -E '^case .* (MISMATCH|MISSING|ERROR)' "$d/out.txt" | head -n 20)"
    else
        verdict="all ok"
    fi
    if [ -z "$ref" ]; then
        ref="$d/hashes.txt"; refname=$name; ident="reference"
        echo "== golden cases ($name; every configuration must print the same):"
        grep -E '^(case|group) ' "$d/out.txt" | sed 's/^/  /'
    elif cmp -s "$ref" "$d/hashes.txt"; then
        ident="yes"
    elif [[ "$flags" == *-DQIBL_USE_* || "$flags" == *-DQIBL_CONFIG_SMALL=1* ]] && [ -s "$d/hashes.txt" ] && ! grep -qvxFf "$ref" "$d/hashes.txt"; then
        ident="subset" # modules compiled out: fewer cases, each as in the reference
    else
        ident="NO"
        err "$name: hashes differ from $refname:"$'\n'"$(diff "$ref" "$d/hashes.txt" | grep '^[<>]' | head -n 20)"
    fi
    # the integration example on the same asset: every configuration must print the same frames
    ex="built"
    if [ -n "$asset" ]; then
        # shellcheck disable=SC2086
        if ! $q "$d/console_port" "$asset" 3 > "$d/example.txt" 2>&1; then
            ex="FAILED"; err "$name: tools/examples/console_port failed: $(tail -n 2 "$d/example.txt")"
        elif [ -z "$exref" ]; then
            exref="$d/example.txt"; ex="reference"
        elif cmp -s "$exref" "$d/example.txt"; then
            ex="same"
        else
            ex="DIFFERS"; err "$name: tools/examples/console_port prints other frames than $refname"
        fi
    fi
    [ "$ident" = NO ] || [ "$ex" = DIFFERS ] || [ "$ex" = FAILED ] || same=$((same + 1))
    # shellcheck disable=SC2059
    rows+=("$(printf "$fmt" "$name" "$cases" "$verdict" "$ident" "$ex" "$(cat "$d/build.time")" "$rt")")
done
echo
# shellcheck disable=SC2059
printf "$fmt\n" configuration cases "vs fixtures" identical example "build s" "run s"
printf '%s\n' "${rows[@]}"
echo
echo "$note32"
[ -n "${note_avx2:-}" ] && echo "$note_avx2"
[ -z "${clang_skip:-}" ] || echo "clang cross targets skipped (clang cannot link for them here):${clang_skip}"
if [ -n "$exref" ]; then
    echo "example: tools/examples/console_port on a 96x24 k=9 courtyard asset, 3 frames, in every configuration:"
    sed 's/^/  /' "$exref"
else
    echo "${note_example:-examples: built only}"
fi
digest=$(grep '^golden: ' "$out/$refname/out.txt" 2>/dev/null | sed -n 's/.*digest //p')
echo "RESULT ports.configurations $n"
echo "RESULT ports.identical $same"
if [ $fail = 0 ]; then
    echo "ports: OK: $n configurations print identical hashes for $(wc -l < "$ref") cases (digest $digest), all as in fixtures/golden"
else
    echo "ports: FAILED" >&2
fi
exit $fail
