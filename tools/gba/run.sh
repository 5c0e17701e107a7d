#!/bin/bash
# gba/run.sh - the golden runner on the Game Boy Advance (make gba): ARM7TDMI code (ARMv4T, Thumb,
# soft float, no divide) in a cartridge ROM (crt_gba.S, gba.ld: code in ROM, stack in IWRAM, data
# and heap in the 256 KiB EWRAM), run headless over libmgba by qibl-gba-run (host.c), output
# through mGBA's debug port (gba_io.c). Every case must print the hash of fixtures/golden/
# <case>.sha256 and the set of cases must be the hosted runner's; cases whose output exceeds the
# memory are hashed as produced (the streaming mode of tools/golden/cases.c). As on the MCU boards
# (tools/baremetal/run.sh, whose main.c, heap.c, stack.c and probes this reuses): the static stack
# bound of every public entry point, the measured stack of each wrapped one against it, and the
# run's high-water mark. Then the relighting demo ROM (demo.c) in three placements, its cycles per
# pixel (RESULT gba.sun_*: the port's own relight; _thumb_rom, _arm_iwram: the core's), its frames
# against the host's. Ends with the RESULT lines
# gba.golden_match and gba.golden_total.
# Env: BUILD (default build; output in $BUILD/gba), GBA_SECONDS (the emulated-time limit, 3600),
# GBA_TABLES (a file whose generated block to rewrite: make gba-tables passes docs/porting.md).
set -u
cd "$(dirname "$0")/../.." || exit 1
# shellcheck source=tools/baremetal/common.sh
. tools/baremetal/common.sh
bm_start gba "${BUILD:-build}/gba"

hh_prereqs
[ -f /usr/include/mgba/core/core.h ] || err "libmgba headers not found (Debian: apt-get install libmgba-dev)"
[ $fail = 0 ] || exit 1

bm_host_golden

# the host runner over libmgba
${CC:-cc} -std=c99 -D_POSIX_C_SOURCE=200809L -O2 -Wall -Wextra -Werror tools/gba/host.c -lmgba -o "$out/qibl-gba-run" ||
    { err "tools/gba/host.c: build failed (libmgba-dev)"; exit 1; }

flags="-mcpu=arm7tdmi -mthumb -mthumb-interwork -mfloat-abi=soft -DQIBL_CONFIG_SMALL=0"
opt=-O2

t_start=$(date +%s)
# the hemi tables of (32, 24) and (64, 8), larger than the EWRAM: baked on the host over the core
# (hemi_tables.c) into cartridge ROM (hemi_rom.S), handed to the cases by hemi_rom.c
hemi="$out/hemi"
mkdir -p "$hemi"
${CC:-cc} -std=c99 -O2 -Wall -Wextra -Werror -Icore/include tools/gba/hemi_tables.c "${BUILD:-build}/libqibl.a" \
    -o "$hemi/qibl-hemi-tables" || { err "tools/gba/hemi_tables.c: build failed"; exit 1; }
for hnf in 32:24 64:8; do
    "$hemi/qibl-hemi-tables" "${hnf%:*}" "${hnf#*:}" "$hemi/hemi_${hnf%:*}_${hnf#*:}.qhmt" > /dev/null ||
        { err "qibl-hemi-tables ${hnf/:/ }"; exit 1; }
done
flags="$flags -DBM_HEMI_TABLES -Wa,-I$hemi" \
    hh_build_golden gba tools/gba/crt_gba.S tools/gba/gba.ld "tools/gba/gba_io.c tools/gba/hemi_rom.c tools/gba/hemi_rom.S"
rom="$dir/qibl-golden.gba"
arm-none-eabi-objcopy -O binary "$elf" "$rom" && python3 tools/gba/fix_header.py "$rom" > /dev/null || { err "ROM"; exit 1; }
arm-none-eabi-size -A "$elf" > "$dir/size.txt"

t0=$(date +%s)
"$out/qibl-gba-run" --seconds "${GBA_SECONDS:-3600}" "$rom" > "$dir/run.txt" 2> "$dir/run-err.txt"
rc=$? secs=$(( $(date +%s) - t0 ))

# the hashes against fixtures/golden, every case fitting the heap (EWRAM less .data and .bss;
# gba.golden_nofit counts and names those that do not), the digest the host's
hh_cases gba

bm_stack_figures "$dir" 512
heap=$(awk '$1 == "case" && $4 == "heap" && $5 + 0 > m {m = $5 + 0; c = $2} END {print m + 0 " B (" c ")"}' "$dir/run.txt")
emu=$(sed -n 's/.* \([0-9.]*\) emulated seconds.*/\1/p' "$dir/run-err.txt" | tail -n 1)
sec() { awk -v n="$1" '$1 == n {print $2}' "$dir/size.txt"; }
echo "gba: golden ROM $(stat -c %s "$rom") B (.text $(sec .text) B in ROM, .iwram $(sec .iwram) B, .data+.bss $(( $(sec .data) + $(sec .bss) )) B in EWRAM)"
hh_exit $rc
echo "gba: $ok ok, $bad bad, $nofit do not fit of $total cases; ${emu:-?} s emulated in ${secs} s; deepest entry point ${deep} B of $probes measured;" \
     "run stack high-water ${hw:-?} of ${size:-?} B (IWRAM); largest case heap $heap (EWRAM)"

# ---- the relighting demo (demo.c): the courtyard at 240 x 160 from `qibl gen`, k = 4 and k = 9,
# in three placements of the relight and platform/soft's row write (soft.c): the core's
# (core/src/shmap.c) as Thumb in cartridge ROM, as the golden ROM; the core's and soft.c as ARM in
# IWRAM (compiled -marm as iwram_shmap.o and iwram_soft.o, which gba.ld places there); and, as
# that, with the port's own relight (arm-iwram-asm: iwram_relight.c and the ARM assembly kernels
# of relight_arm.S, reading the maps from ROM; the demo ROM). Buffers in IWRAM for all. Each frame's CRC-32 must be the host's (demo_ref.c, same code), and mGBA's screen
# after the run must be the host frame at the GBA's 5 bits per channel.
demo="$out/demo"
rm -rf "$demo"; mkdir -p "$demo"
qibl="${BUILD:-build}/bin/qibl"
[ -x "$qibl" ] || err "$qibl missing (make qibl builds it)"
for k in 4 9; do
    "$qibl" gen -o "$demo/courtyard_k$k.qibl" --size 240x160 --k $k > /dev/null || err "qibl gen k = $k"
done
${CC:-cc} -std=c99 -D_POSIX_C_SOURCE=200809L -O2 -Wall -Wextra -Werror -Icore/include -Iplatform/soft/include \
    -Itools/gba tools/gba/demo_ref.c tools/gba/demo_frame.c "${BUILD:-build}/libqibl-soft.a" "${BUILD:-build}/libqibl.a" \
    -o "$demo/demo-ref" || err "demo_ref.c: build failed"
for k in 4 9; do
    "$demo/demo-ref" "$demo/courtyard_k$k.qibl" 10 "$demo/ref_k$k.ppm" > "$demo/ref_k$k.txt" || err "demo_ref k = $k"
done
dflags="$flags $opt -Icore/include -Iplatform/soft/include -Itools/gba -Itools/baremetal"
# shellcheck disable=SC2086
$gcc $specs $dflags $tool_warn -c tools/gba/demo.c -o "$demo/demo.o" &&
$gcc $specs $dflags $tool_warn -DDEMO_ARM_KERNEL=1 -c tools/gba/demo.c -o "$demo/demo_asm.o" &&
$gcc $specs ${dflags/-mthumb/-marm} $core_warn -ffreestanding -fno-builtin -fno-tree-loop-distribute-patterns \
    -c tools/gba/iwram_relight.c -o "$demo/iwram_relight.o" &&
$gcc $flags -c tools/gba/relight_arm.S -o "$demo/relight_arm.o" &&
$gcc $specs $dflags $tool_warn -c tools/gba/demo_frame.c -o "$demo/demo_frame.o" &&
$gcc $flags -Itools -Wa,-I"$demo" -c tools/gba/demo_asset.S -o "$demo/demo_asset.o" &&
$gcc ${flags/-mthumb/-marm} $opt $core_warn -ffreestanding -fno-builtin -fno-tree-loop-distribute-patterns \
    -ffunction-sections -Icore/include -c core/src/shmap.c -o "$demo/iwram_shmap.o" &&
$gcc ${flags/-mthumb/-marm} $opt $core_warn -ffreestanding -fno-builtin -fno-tree-loop-distribute-patterns \
    -ffunction-sections -Icore/include -Iplatform/soft/include -c platform/soft/soft.c -o "$demo/iwram_soft.o" ||
    err "demo: compile failed"
demo_common=("$dir/tools/crt_gba.o" "$dir/tools/gba_io.o" "$dir/tools/hh_start.o" "$dir/tools/putu.o" "$dir/tools/armtimers.o" "$dir/tools/stack.o" "$demo/demo_frame.o" "$demo/demo_asset.o")
core_thumb=("$dir"/core/*.o)
core_arm=("$demo/iwram_shmap.o" "$demo/iwram_soft.o")
for o in "$dir"/core/*.o; do case $(basename "$o") in shmap.o | soft.o) ;; *) core_arm+=("$o") ;; esac; done
table_rows=()
for place in thumb-rom arm-iwram arm-iwram-asm; do
    if [ $place = thumb-rom ]; then core_objs=("${core_thumb[@]}"); else core_objs=("${core_arm[@]}"); fi
    demo_objs=("${demo_common[@]}" "$demo/demo.o")
    [ $place = arm-iwram-asm ] && demo_objs=("${demo_common[@]}" "$demo/demo_asm.o" "$demo/iwram_relight.o" "$demo/relight_arm.o")
    delf="$demo/qibl-demo-$place.elf" drom="$demo/qibl-demo-$place.gba"
    # shellcheck disable=SC2086
    $gcc $specs $flags $opt -nostartfiles -T tools/gba/gba.ld -Wl,--gc-sections,--no-warn-rwx-segments \
        -o "$delf" "${demo_objs[@]}" "${core_objs[@]}" -lc -lgcc &&
    arm-none-eabi-objcopy -O binary "$delf" "$drom" && python3 tools/gba/fix_header.py "$drom" > /dev/null ||
        { err "demo $place: link failed"; continue; }
    "$out/qibl-gba-run" --select --seconds 120 --screenshot "$demo/shot-$place.ppm" "$drom" > "$demo/run-$place.txt" 2>&1 ||
        err "demo $place: the run failed: $(tail -n 2 "$demo/run-$place.txt" | tr '\n' ' ')"
    for k in 4 9; do
        want=$(awk '{print $5}' "$demo/ref_k$k.txt")
        got=$(awk -v t="k$k" '$1 == "frame" && $2 == t {print $6}' "$demo/run-$place.txt")
        [ -n "$got" ] && [ "$got" = "$want" ] || err "demo $place k = $k: frame crc32 ${got:-missing}, the host's $want"
    done
    python3 - "$demo/shot-$place.ppm" "$demo/ref_k9.ppm" <<'PY' || err "demo $place: mGBA's screen differs from the host frame"
import sys
def ppm(p):
    b = open(p, "rb").read().split(b"\n", 3)
    return b[1], b[3]
(sa, a), (sb, b) = ppm(sys.argv[1]), ppm(sys.argv[2])
bad = sum(1 for x, y in zip(a, b) if x >> 3 != y >> 3)
print("gba: screenshot %s: %d of %d channels differ from the host frame at 5 bits" % (sys.argv[1], bad, len(b)))
sys.exit(0 if sa == sb and len(a) == len(b) and bad == 0 else 1)
PY
    # the demo's stack shares IWRAM with .iwram: at least 512 bytes to spare
    read -r shw shs < <(sed -n 's/^demo stack high-water \([0-9]*\) of \([0-9]*\)$/\1 \2/p' "$demo/run-$place.txt")
    if [ -z "${shs:-}" ] || [ "$shw" -ge $((shs - 512)) ]; then
        err "demo $place: stack high-water ${shw:-?} of ${shs:-?} bytes: too close to the end"
    fi
    r() { awk -v n="RESULT gba.sun_$1" '$1 " " $2 == n {print $3}' "$demo/run-$place.txt"; }
    iw=$(arm-none-eabi-size -A "$delf" | awk '$1 == ".iwram" {print $2}')
    r2() { awk -v n="RESULT gba.$1" '$1 " " $2 == n {print $3}' "$demo/run-$place.txt"; }
    table_rows+=("| $place | $(r k4_cycles_per_px) | $(r k9_cycles_per_px) | $(r k9_write_cycles_per_px) | $(r k4_frame_ms) | $(r k9_frame_ms) | $(r2 demo_k9_updates_per_s) | $iw |")
    if [ $place = arm-iwram-asm ]; then
        grep '^RESULT ' "$demo/run-$place.txt"
    else
        grep '^RESULT ' "$demo/run-$place.txt" | sed "s/^\(RESULT gba\.[a-z0-9_]*\)/\1_${place//-/_}/"
    fi
done
cp "$demo/shot-arm-iwram-asm.ppm" "$out/qibl-demo.ppm" 2>/dev/null
cp "$demo/qibl-demo-arm-iwram-asm.gba" "$out/qibl-demo.gba" 2>/dev/null && echo "gba: the demo ROM: $out/qibl-demo.gba (mgba-qt $out/qibl-demo.gba)"

# ---- the generated block of docs/porting.md (GBA_TABLES=docs/porting.md rewrites it there)
{
    echo "<!-- make gba: generated, do not edit -->"
    echo "| GBA golden ROM | cases matching fixtures/golden | too big for 256 KiB | ROM bytes | .data+.bss (EWRAM) | largest case heap | stack high-water (IWRAM) | deepest entry point |"
    echo "|---|---:|---:|---:|---:|---|---:|---|"
    echo "| Thumb -O2, ROM | $ok of $total | $nofit | $(stat -c %s "$rom") | $(( $(sec .data) + $(sec .bss) )) | $heap | $hw of $size | $deep |"
    echo
    echo "| demo relight (240 x 160 courtyard, sun) | k = 4 cycles/px | k = 9 cycles/px | RGB565 write cycles/px | k = 4 frame ms | k = 9 frame ms | k = 9 updates/s (1/32 of the rows) | .iwram bytes |"
    echo "|---|---:|---:|---:|---:|---:|---:|---:|"
    for row in "${table_rows[@]}"; do echo "$row"; done
    echo
    echo "<details><summary>Stack per core entry point on the GBA (bytes: the static bound of stack.py, and the deepest use measured in the golden run)</summary>"
    echo
    echo "| entry point | bound | measured |"
    echo "|---|---:|---:|"
    awk '$1 == "stack" && $4 == "bound" {printf "| `%s` | %s | %s |\n", $2, $5, $3}' "$dir/run.txt" | LC_ALL=C sort   # one order whatever the locale (docs-check compares the block)
    echo
    echo "</details>"
    echo "<!-- end make gba -->"
} > "$out/tables.md"
hh_tables gba "${GBA_TABLES:-}"

hh_results gba "every case that fits the GBA's memory prints the hash of fixtures/golden; the demo's frames are the host's"
