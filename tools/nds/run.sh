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
# shellcheck source=tools/baremetal/common.sh
. tools/baremetal/common.sh
bm_start nds "${BUILD:-build}/nds"

hh_prereqs
have desmume-cli || [ -x /usr/games/desmume-cli ] || err "desmume-cli not found (Debian: apt-get install desmume)"
[ $fail = 0 ] || exit 1

bm_host_golden

flags="-mcpu=arm946e-s -mthumb -mthumb-interwork -mfloat-abi=soft -DQIBL_CONFIG_SMALL=0"
opt=-O2

t_start=$(date +%s)
hh_build_golden nds tools/nds/crt_nds.S tools/nds/nds.ld tools/nds/nds_io.c
rom="$dir/qibl-golden.nds"
arm-none-eabi-objcopy -O binary -R .arm7 "$elf" "$dir/arm9.bin" &&
arm-none-eabi-objcopy -O binary -j .arm7 "$elf" "$dir/arm7.bin" &&
python3 tools/nds/ndsrom.py "$rom" "QIBL GOLDEN" "$dir/arm9.bin" 0x02000000 "0x$(hh_sym nds_start)" \
    "$dir/arm7.bin" "0x$(hh_sym nds_arm7_start)" "0x$(hh_sym nds_arm7_start)" > "$dir/rom.txt" || { err "ROM: $(cat "$dir/rom.txt")"; exit 1; }
arm-none-eabi-size -A "$elf" > "$dir/size.txt"

t0=$(date +%s)
python3 tools/nds/desmume_run.py --seconds "${NDS_SECONDS:-600}" --log "$dir/desmume.log" "$rom" > "$dir/run.txt" 2> "$dir/run-err.txt"
rc=$? secs=$(( $(date +%s) - t0 ))

# the hashes against fixtures/golden, every case fitting the heap (main RAM less the image, .bss
# and the stack; nds.golden_nofit counts and names those that do not), the digest the host's
hh_cases nds

bm_stack_figures "$dir" 512
heap=$(awk '$1 == "case" && $4 == "heap" && $5 + 0 > m {m = $5 + 0; c = $2} END {print m + 0 " B (" c ")"}' "$dir/run.txt")
cpu=$(sed -n 's/.* \([0-9.]*\) s of CPU time$/\1/p' "$dir/run-err.txt")
emu=$(awk '$1 == "group" {ms += $(NF - 2)} END {printf "%.1f", ms / 1000}' "$dir/run.txt")
sec() { awk -v n="$1" '$1 == n {print $2}' "$dir/size.txt"; }
image=$(stat -c %s "$dir/arm9.bin")
echo "nds: golden ROM $(stat -c %s "$rom") B (ARM9 binary $image B in main RAM, .bss $(sec .bss) B, heap $heap_cap B, stack $(sec .stack) B)"
hh_exit $rc
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
hh_tables nds "${NDS_TABLES:-}"

hh_results nds "every case that fits the DS's memory prints the hash of fixtures/golden"
