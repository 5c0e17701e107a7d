#!/bin/bash
# gba/run.sh - the golden runner on the Game Boy Advance (make gba): ARM7TDMI code (ARMv4T, Thumb,
# soft float, no divide) in a cartridge ROM (crt_gba.S, gba.ld: code in ROM, stack in IWRAM, data
# and heap in the 256 KiB EWRAM), run headless over libmgba by qibl-gba-run (host.c), output
# through mGBA's debug port (gba_io.c). Every case must print the hash of fixtures/golden/
# <case>.sha256 and the set of cases must be the hosted runner's; cases whose output exceeds the
# memory are hashed as produced (the streaming mode of tools/golden/cases.c). As on the MCU boards
# (tools/baremetal/run.sh, whose main.c, heap.c, stack.c and probes this reuses): the static stack
# bound of every public entry point, the measured stack of each wrapped one against it, and the
# run's high-water mark. Ends with the RESULT lines gba.golden_match and gba.golden_total.
# Env: BUILD (default build; output in $BUILD/gba), GBA_SECONDS (the emulated-time limit, 3600).
set -u
cd "$(dirname "$0")/../.." || exit 1
out="${BUILD:-build}/gba"
mkdir -p "$out"
fail=0
err() { echo "gba: FAIL: $*" >&2; fail=1; }
have() { command -v "$1" >/dev/null 2>&1; }

have arm-none-eabi-gcc || err "arm-none-eabi-gcc not found (Debian: apt-get install gcc-arm-none-eabi)"
have python3 || err "python3 not found (Debian: apt-get install python3)"
specs_file=/usr/lib/picolibc/arm-none-eabi/picolibc.specs
[ -f $specs_file ] || err "picolibc for arm-none-eabi not found (Debian: apt-get install picolibc-arm-none-eabi)"
[ -f /usr/include/mgba/core/core.h ] || err "libmgba headers not found (Debian: apt-get install libmgba-dev)"
[ $fail = 0 ] || exit 1

golden="${BUILD:-build}/bin/qibl-golden"
[ -x "$golden" ] || { err "$golden missing (make golden builds it)"; exit 1; }
"$golden" > "$out/host.txt"
awk '$1 == "case" {print $2}' "$out/host.txt" > "$out/host-cases.txt"

# the host runner over libmgba
${CC:-cc} -std=c99 -D_POSIX_C_SOURCE=200809L -O2 -Wall -Wextra -Werror tools/gba/host.c -lmgba -o "$out/qibl-gba-run" ||
    { err "tools/gba/host.c: build failed (libmgba-dev)"; exit 1; }

core_warn="-std=c99 -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wundef -Wdouble-promotion -Wmissing-prototypes -Werror"
tool_warn="-std=c99 -Wall -Wextra -Wpedantic -Werror -Wno-format" # (see tools/baremetal/run.sh)
flags="-mcpu=arm7tdmi -mthumb -mthumb-interwork -mfloat-abi=soft -DQIBL_CONFIG_SMALL=0"
opt=-O2
specs="-specs=$specs_file"
gcc=arm-none-eabi-gcc
core_src=$(ls core/src/*.c platform/soft/*.c)
tool_src="$(ls tools/golden/cases*.c) tools/io/sha256.c"
bm_src="tools/baremetal/main.c tools/baremetal/stack.c tools/baremetal/heap.c tools/gba/gba_io.c"

t_start=$(date +%s)
dir="$out/golden"
rm -rf "$dir"; mkdir -p "$dir/core" "$dir/tools"
objs=()
for src in $core_src; do
    o="$dir/core/$(basename "$src" .c).o"; objs+=("$o")
    # shellcheck disable=SC2086
    $gcc $flags $opt $core_warn -ffreestanding -fno-builtin -fno-tree-loop-distribute-patterns -g \
        -fstack-usage -fcallgraph-info=su -Icore/include -Iplatform/soft/include -c "$src" -o "$o" \
        -dumpbase "$dir/core/$(basename "$src" .c).c" || { err "$src: compile failed"; exit 1; }
done
for src in $tool_src $bm_src; do
    o="$dir/tools/$(basename "$src" .c).o"; objs+=("$o")
    # shellcheck disable=SC2086
    $gcc $specs $flags $opt $tool_warn -g -DBM_CONFIG='"gba"' -Icore/include -Iplatform/soft/include -Itools \
        -Itools/baremetal -c "$src" -o "$o" || { err "$src: compile failed"; exit 1; }
done
o="$dir/tools/crt_gba.o"; objs+=("$o")
$gcc $flags -c tools/gba/crt_gba.S -o "$o" || { err "crt_gba.S"; exit 1; }

# stack bounds of every public entry point, then trampolines for the ones the cases call
python3 tools/baremetal/stack.py --objdump arm-none-eabi-objdump --helpers "$($gcc $flags -print-libgcc-file-name)" "$dir/core" > "$dir/stack-bounds.txt" ||
    err "an entry point has no static stack bound: $(grep unbounded "$dir/stack-bounds.txt" | head -3)"
probed=$(arm-none-eabi-nm -u "$dir"/tools/cases*.o | awk '$2 ~ /^qibl_/ && $2 !~ /^qibl_(sha256|goldens)/ {print $2}' | sort -u)
# shellcheck disable=SC2086
python3 tools/baremetal/gen_probe.py armv4t "$dir/stack-bounds.txt" "$dir" $probed || { err "gen_probe"; exit 1; }
probed=$(sed -n 's/^bm_probe_\([a-z0-9_]*\):$/\1/p' "$dir/probe.S")
for src in "$dir/probe.S" "$dir/probe_table.c"; do
    o="${src%.*}-$(basename "${src##*.}").o"; objs+=("$o")
    # shellcheck disable=SC2086
    $gcc $specs $flags $opt -g -Itools/baremetal -c "$src" -o "$o" || { err "$src"; exit 1; }
done
# the cases' malloc family to heap.c, their core calls to the probes (as tools/baremetal/run.sh)
redef=()
for f in malloc calloc realloc free; do redef+=(--redefine-sym "$f=bm_$f"); done
for f in $probed; do redef+=(--redefine-sym "$f=bm_probe_$f"); done
for o in "$dir"/tools/cases*.o; do arm-none-eabi-objcopy "${redef[@]}" "$o" || { err "objcopy $o"; exit 1; }; done
elf="$dir/qibl-golden.elf" rom="$dir/qibl-golden.gba"
# shellcheck disable=SC2086
$gcc $specs $flags $opt -nostartfiles -T tools/gba/gba.ld -Wl,--gc-sections,--no-warn-rwx-segments \
    -o "$elf" "${objs[@]}" -lc -lgcc || { err "link failed"; exit 1; }
arm-none-eabi-objcopy -O binary "$elf" "$rom" && python3 tools/gba/fix_header.py "$rom" > /dev/null || { err "ROM"; exit 1; }
arm-none-eabi-size -A "$elf" > "$dir/size.txt"

t0=$(date +%s)
"$out/qibl-gba-run" --seconds "${GBA_SECONDS:-3600}" "$rom" > "$dir/run.txt" 2> "$dir/run-err.txt"
rc=$? secs=$(( $(date +%s) - t0 ))

# a case that reports "out of memory: needs N bytes" with N above the whole heap (EWRAM less
# .data and .bss) cannot fit the GBA: counted apart (gba.golden_nofit), not as a failure; any other
# error or a wrong hash fails
sym() { arm-none-eabi-nm "$elf" | awk -v n="$1" '$3 == n {print $1}'; }
heap_cap=$(( 0x$(sym __heap_end) - 0x$(sym __heap_start) ))
ok=0 bad=0 nofit=0
while read -r _ case hash rest; do
    want=$(head -c 64 "fixtures/golden/$case.sha256" 2>/dev/null)
    need=$(echo "$rest" | sed -n 's/^ERROR out of memory: needs \([0-9]*\) bytes$/\1/p')
    if [ "$hash" = "$want" ]; then ok=$((ok + 1))
    elif [ "$hash" = - ] && [ -n "$need" ] && [ "$need" -gt "$heap_cap" ]; then
        nofit=$((nofit + 1)); echo "gba: case $case does not fit: needs $need bytes at once, the heap has $heap_cap" >> "$dir/nofit.txt"
    else bad=$((bad + 1)); err "case $case: $hash $rest, fixtures/golden says ${want:-nothing}"; fi
done < <(rm -f "$dir/nofit.txt"; grep '^case ' "$dir/run.txt")
awk '$1 == "case" {print $2}' "$dir/run.txt" > "$dir/cases.txt"
total=$(wc -l < "$out/host-cases.txt")
if ! cmp -s "$dir/cases.txt" "$out/host-cases.txt"; then
    err "the cases differ from the hosted runner's: $(diff "$out/host-cases.txt" "$dir/cases.txt" | grep '^[<>]' | head -5 | tr '\n' ' ')"
fi
# (no digest comparison with the hosted runner: the cases that do not fit change it)

over=$(awk '$1 == "stack" && $3 + 0 > $5 + 0 {print $2 " used " $3 " > bound " $5}' "$dir/run.txt")
[ -z "$over" ] || err "stack over the computed bound: $over"
probes=$(grep -c '^stack .* bound ' "$dir/run.txt")
deep=$(awk '$1 == "stack" && $4 == "bound" && $3 + 0 > m {m = $3 + 0; f = $2} END {print f " " m}' "$dir/run.txt")
hw=$(sed -n 's/^stack high-water \([0-9]*\) of.*/\1/p' "$dir/run.txt")
size=$(sed -n 's/^stack high-water [0-9]* of \([0-9]*\)$/\1/p' "$dir/run.txt")
[ -n "$hw" ] && [ "$hw" -lt $((size - 512)) ] || err "stack high-water ${hw:-?} of ${size:-?} bytes: too close to the end"
heap=$(awk '$1 == "case" && $4 == "heap" && $5 + 0 > m {m = $5 + 0; c = $2} END {print m + 0 " B (" c ")"}' "$dir/run.txt")
emu=$(sed -n 's/.* \([0-9.]*\) emulated seconds.*/\1/p' "$dir/run-err.txt" | tail -n 1)
sec() { awk -v n="$1" '$1 == n {print $2}' "$dir/size.txt"; }
echo "gba: golden ROM $(stat -c %s "$rom") B (.text $(sec .text) B in ROM, .iwram $(sec .iwram) B, .data+.bss $(( $(sec .data) + $(sec .bss) )) B in EWRAM)"
# the ROM exits 1 when a case reported an error: allowed only when every error is a case that
# does not fit
errors=$(sed -n 's/^golden: .* \([0-9]*\) errors; digest .*/\1/p' "$dir/run.txt")
if [ $rc != 0 ] && ! { [ $rc = 1 ] && [ "${errors:-x}" = $nofit ]; }; then
    err "the run exited with $rc ($(tail -n 2 "$dir/run.txt" "$dir/run-err.txt" | tr '\n' ' '))"
fi
[ -f "$dir/nofit.txt" ] && cat "$dir/nofit.txt"
echo "gba: $ok ok, $bad bad, $nofit do not fit of $total cases; ${emu:-?} s emulated in ${secs} s; deepest entry point ${deep} B of $probes measured;" \
     "run stack high-water ${hw:-?} of ${size:-?} B (IWRAM); largest case heap $heap (EWRAM)"
echo "RESULT gba.golden_match $ok"
echo "RESULT gba.golden_nofit $nofit"
echo "RESULT gba.golden_total $total"
echo "gba: $(($(date +%s) - t_start)) s"
[ $((ok + nofit)) = "$total" ] || err "$ok match and $nofit do not fit of $total cases"
if [ $fail = 0 ]; then echo "gba: OK (every case that fits the GBA's memory prints the hash of fixtures/golden)"; else echo "gba: FAILED"; fi
exit $fail
