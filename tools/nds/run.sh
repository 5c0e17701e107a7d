#!/bin/bash
# nds/run.sh - the golden runner on the Nintendo DS (make nds): the ARM9 (ARM946E-S, ARMv5TE, Thumb,
# soft float) running from its 4 MiB of main RAM (crt_nds.S, nds.ld: code, data, heap and 64 KiB of
# stack there), an ARM7 that idles, both in a cartridge ROM that ndsrom.py puts together (header,
# CRC-16s), run headless under DeSmuME's desmume-cli by desmume_run.py, output through DeSmuME's
# debug print (nds_io.c). Every case must print the hash of fixtures/golden/<case>.sha256 and the
# set of cases must be the hosted runner's; a case whose output cannot fit the heap at once is
# counted apart and named. As on the GBA and the MCU boards (tools/baremetal/main.c, heap.c,
# stack.c and the probes): the static stack bound of every public entry point, the measured stack of
# each wrapped one against it, and the run's high-water mark. Ends with the RESULT lines
# nds.golden_match, nds.golden_nofit and nds.golden_total.
# Env: BUILD (default build; output in $BUILD/nds), NDS_SECONDS (the wall-clock limit, 600: a run takes
# about 50 s on an idle machine),
# NDS_TABLES (a file whose generated block to rewrite: make nds-tables passes docs/porting.md).
set -u
cd "$(dirname "$0")/../.." || exit 1
out="${BUILD:-build}/nds"
mkdir -p "$out"
fail=0
err() { echo "nds: FAIL: $*" >&2; fail=1; }
have() { command -v "$1" >/dev/null 2>&1; }

have arm-none-eabi-gcc || err "arm-none-eabi-gcc not found (Debian: apt-get install gcc-arm-none-eabi)"
have python3 || err "python3 not found (Debian: apt-get install python3)"
specs_file=/usr/lib/picolibc/arm-none-eabi/picolibc.specs
[ -f $specs_file ] || err "picolibc for arm-none-eabi not found (Debian: apt-get install picolibc-arm-none-eabi)"
have desmume-cli || [ -x /usr/games/desmume-cli ] || err "desmume-cli not found (Debian: apt-get install desmume)"
[ $fail = 0 ] || exit 1

golden="${BUILD:-build}/bin/qibl-golden"
[ -x "$golden" ] || { err "$golden missing (make golden builds it)"; exit 1; }
"$golden" > "$out/host.txt"
awk '$1 == "case" {print $2}' "$out/host.txt" > "$out/host-cases.txt"

core_warn="-std=c99 -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wundef -Wdouble-promotion -Wmissing-prototypes -Werror"
tool_warn="-std=c99 -Wall -Wextra -Wpedantic -Werror -Wno-format" # (see tools/baremetal/run.sh)
flags="-mcpu=arm946e-s -mthumb -mthumb-interwork -mfloat-abi=soft -DQIBL_CONFIG_SMALL=0"
opt=-O2
specs="-specs=$specs_file"
gcc=arm-none-eabi-gcc
core_src=$(ls core/src/*.c platform/soft/*.c)
tool_src="$(ls tools/golden/cases*.c) tools/io/sha256.c"
bm_src="tools/baremetal/main.c tools/baremetal/stack.c tools/baremetal/heap.c tools/baremetal/tls.c tools/nds/nds_io.c"

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
    $gcc $specs $flags $opt $tool_warn -g -DBM_CONFIG='"nds"' -Icore/include -Iplatform/soft/include -Itools \
        -Itools/baremetal -c "$src" -o "$o" || { err "$src: compile failed"; exit 1; }
done
o="$dir/tools/crt_nds.o"; objs+=("$o")
$gcc $flags -c tools/nds/crt_nds.S -o "$o" || { err "crt_nds.S"; exit 1; }

# stack bounds of every public entry point, then trampolines for the ones the cases call (the
# ARMv4T form: ARMv5TE's Thumb has blx, but no mov between low registers either)
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
elf="$dir/qibl-golden.elf" rom="$dir/qibl-golden.nds"
# shellcheck disable=SC2086
$gcc $specs $flags $opt -nostartfiles -T tools/nds/nds.ld -Wl,--gc-sections,--no-warn-rwx-segments \
    -o "$elf" "${objs[@]}" -lc -lgcc || { err "link failed"; exit 1; }
sym() { arm-none-eabi-nm "$elf" | awk -v n="$1" '$3 == n {print $1}'; }
arm-none-eabi-objcopy -O binary -R .arm7 "$elf" "$dir/arm9.bin" &&
arm-none-eabi-objcopy -O binary -j .arm7 "$elf" "$dir/arm7.bin" &&
python3 tools/nds/ndsrom.py "$rom" "QIBL GOLDEN" "$dir/arm9.bin" 0x02000000 "0x$(sym nds_start)" \
    "$dir/arm7.bin" "0x$(sym nds_arm7_start)" "0x$(sym nds_arm7_start)" > "$dir/rom.txt" || { err "ROM: $(cat "$dir/rom.txt")"; exit 1; }
arm-none-eabi-size -A "$elf" > "$dir/size.txt"

t0=$(date +%s)
python3 tools/nds/desmume_run.py --seconds "${NDS_SECONDS:-600}" --log "$dir/desmume.log" "$rom" > "$dir/run.txt" 2> "$dir/run-err.txt"
rc=$? secs=$(( $(date +%s) - t0 ))

# a case that reports "out of memory: needs N bytes" with N above the whole heap (main RAM less
# the image, .bss and the stack) cannot fit the DS: counted apart (nds.golden_nofit) and named, not
# a failure; any other error or a wrong hash fails
heap_cap=$(( 0x$(sym __heap_end) - 0x$(sym __heap_start) ))
ok=0 bad=0 nofit=0
rm -f "$dir/nofit.txt"
while read -r _ case hash rest; do
    want=$(head -c 64 "fixtures/golden/$case.sha256" 2>/dev/null)
    need=$(echo "$rest" | sed -n 's/^ERROR out of memory: needs \([0-9]*\) bytes$/\1/p')
    if [ "$hash" = "$want" ]; then ok=$((ok + 1))
    elif [ "$hash" = - ] && [ -n "$need" ] && [ "$need" -gt "$heap_cap" ]; then
        nofit=$((nofit + 1)); echo "nds: case $case does not fit: needs $need bytes at once, the heap has $heap_cap" >> "$dir/nofit.txt"
    else bad=$((bad + 1)); err "case $case: $hash $rest, fixtures/golden says ${want:-nothing}"; fi
done < <(grep '^case ' "$dir/run.txt")
awk '$1 == "case" {print $2}' "$dir/run.txt" > "$dir/cases.txt"
total=$(wc -l < "$out/host-cases.txt")
if ! cmp -s "$dir/cases.txt" "$out/host-cases.txt"; then
    err "the cases differ from the hosted runner's: $(diff "$out/host-cases.txt" "$dir/cases.txt" | grep '^[<>]' | head -5 | tr '\n' ' ')"
fi
# when every case fits, the run's digest (tools/golden/runner.c's) must be the hosted runner's
digest=$(sed -n 's/^golden: .* digest \([0-9a-f]*\)$/\1/p' "$dir/run.txt")
host_digest=$(sed -n 's/^golden: .* digest \([0-9a-f]*\)$/\1/p' "$out/host.txt")
if [ $nofit = 0 ] && [ "${digest:-x}" != "${host_digest:-y}" ]; then
    err "the run's digest ${digest:-missing} is not the hosted runner's ${host_digest:-?}"
fi

over=$(awk '$1 == "stack" && $3 + 0 > $5 + 0 {print $2 " used " $3 " > bound " $5}' "$dir/run.txt")
[ -z "$over" ] || err "stack over the computed bound: $over"
probes=$(grep -c '^stack .* bound ' "$dir/run.txt")
deep=$(awk '$1 == "stack" && $4 == "bound" && $3 + 0 > m {m = $3 + 0; f = $2} END {print f " " m}' "$dir/run.txt")
hw=$(sed -n 's/^stack high-water \([0-9]*\) of.*/\1/p' "$dir/run.txt")
size=$(sed -n 's/^stack high-water [0-9]* of \([0-9]*\)$/\1/p' "$dir/run.txt")
[ -n "$hw" ] && [ "$hw" -lt $((size - 512)) ] || err "stack high-water ${hw:-?} of ${size:-?} bytes: too close to the end"
heap=$(awk '$1 == "case" && $4 == "heap" && $5 + 0 > m {m = $5 + 0; c = $2} END {print m + 0 " B (" c ")"}' "$dir/run.txt")
cpu=$(sed -n 's/.* \([0-9.]*\) s of CPU time$/\1/p' "$dir/run-err.txt")
emu=$(awk '$1 == "group" {ms += $(NF - 2)} END {printf "%.1f", ms / 1000}' "$dir/run.txt")
sec() { awk -v n="$1" '$1 == n {print $2}' "$dir/size.txt"; }
image=$(stat -c %s "$dir/arm9.bin")
echo "nds: golden ROM $(stat -c %s "$rom") B (ARM9 binary $image B in main RAM, .bss $(sec .bss) B, heap $heap_cap B, stack $(sec .stack) B)"
# the ROM exits 1 when a case reported an error: allowed only when every error is a case that
# does not fit
errors=$(sed -n 's/^golden: .* \([0-9]*\) errors; digest .*/\1/p' "$dir/run.txt")
if [ $rc != 0 ] && ! { [ $rc = 1 ] && [ "${errors:-x}" = $nofit ]; }; then
    err "the run exited with $rc ($(tail -n 2 "$dir/run.txt" "$dir/run-err.txt" | tr '\n' ' '))"
fi
[ -f "$dir/nofit.txt" ] && cat "$dir/nofit.txt"
echo "nds: $ok ok, $bad bad, $nofit do not fit of $total cases; ${emu} s emulated (ARM9 timers) in ${secs} s of wall-clock time (DeSmuME's CPU time ${cpu:-?} s);" \
     "deepest entry point ${deep} B of $probes measured; run stack high-water ${hw:-?} of ${size:-?} B; largest case heap $heap"

# ---- the generated block of docs/porting.md (NDS_TABLES=docs/porting.md rewrites it there)
{
    echo "<!-- make nds: generated, do not edit -->"
    echo "| DS golden ROM (DeSmuME) | cases matching fixtures/golden | too big for 4 MiB | ROM bytes | ARM9 binary | heap | largest case heap | stack high-water | deepest entry point | emulated s |"
    echo "|---|---:|---:|---:|---:|---:|---|---:|---|---:|"
    echo "| ARM946E-S Thumb -O2, main RAM | $ok of $total | $nofit | $(stat -c %s "$rom") | $image | $heap_cap | $heap | $hw of $size | $deep | $emu |"
    echo "<!-- end make nds -->"
} > "$out/tables.md"
cat "$out/tables.md"
if [ -n "${NDS_TABLES:-}" ] && [ $fail = 0 ]; then
    python3 - "$NDS_TABLES" "$out/tables.md" <<'PY' || err "cannot rewrite the block of $NDS_TABLES"
import sys
doc, block = open(sys.argv[1]).read(), open(sys.argv[2]).read().rstrip("\n")
a, b = doc.find("<!-- make nds: generated"), doc.find("<!-- end make nds -->")
if a < 0 or b < a:
    sys.exit("no generated block (<!-- make nds: generated ... <!-- end make nds -->) in " + sys.argv[1])
open(sys.argv[1], "w").write(doc[:a] + block + doc[b + len("<!-- end make nds -->"):])
PY
fi

[ $((ok + nofit)) = "$total" ] || err "$ok match and $nofit do not fit of $total cases"
echo "nds: $(($(date +%s) - t_start)) s"
if [ $fail = 0 ]; then echo "nds: OK (every case that fits the DS's memory prints the hash of fixtures/golden)"; else echo "nds: FAILED"; fi
echo "RESULT nds.golden_match $ok"
echo "RESULT nds.golden_nofit $nofit"
echo "RESULT nds.golden_total $total"
exit $fail
