# baremetal/common.sh - sourced by tools/baremetal/run.sh, tools/gba/run.sh and tools/nds/run.sh:
# the steps the MCU boards and the handhelds share, so that one fix reaches every target. The caller
# has done `cd` to the top of the tree, then calls bm_start. Variables pass both ways (flags, opt,
# t_start in; dir, elf, ok, deep, ... out), as between the parts of one script.
# shellcheck shell=bash disable=SC2034,SC2154

# bm_start TAG OUT: the runner's output folder OUT (made), fail = 0; err() reports as TAG
bm_start() {
    bm_tag=$1 out=$2
    mkdir -p "$out"
    fail=0
}
err() { echo "$bm_tag: FAIL: $*" >&2; fail=1; }
have() { command -v "$1" >/dev/null 2>&1; }

core_warn="-std=c99 -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wundef -Wdouble-promotion -Wmissing-prototypes -Werror"
# (-Wno-format: the cases print uint32_t with %u, which is unsigned long on arm-none-eabi; same
# size, so harmless, but -Wformat would flag each one)
tool_warn="-std=c99 -Wall -Wextra -Wpedantic -Werror -Wno-format"
core_src=$(ls core/src/*.c platform/soft/*.c)
tool_src="$(ls tools/golden/cases*.c) tools/io/sha256.c"

# bm_host_golden: the hosted runner's output and case list, what every target must match
bm_host_golden() {
    local golden="${BUILD:-build}/bin/qibl-golden"
    [ -x "$golden" ] || { err "$golden missing (make golden builds it)"; exit 1; }
    "$golden" > "$out/host.txt"
    awk '$1 == "case" {print $2}' "$out/host.txt" > "$out/host-cases.txt"
}

# bm_stack_figures DIR MARGIN [LABEL]: the measured stack of each wrapped entry point against its
# static bound, and the run's high-water mark at least MARGIN bytes from the end; sets probes,
# deep, hw and size
bm_stack_figures() {
    local dir=$1 margin=$2 label=${3:-} over
    over=$(awk '$1 == "stack" && $3 + 0 > $5 + 0 {print $2 " used " $3 " > bound " $5}' "$dir/run.txt")
    [ -z "$over" ] || err "${label}stack over the computed bound: $over"
    probes=$(grep -c '^stack .* bound ' "$dir/run.txt")
    deep=$(awk '$1 == "stack" && $4 == "bound" && $3 + 0 > m {m = $3 + 0; f = $2} END {print f " " m}' "$dir/run.txt")
    hw=$(sed -n 's/^stack high-water \([0-9]*\) of.*/\1/p' "$dir/run.txt")
    size=$(sed -n 's/^stack high-water [0-9]* of \([0-9]*\)$/\1/p' "$dir/run.txt")
    [ -n "$hw" ] && [ "$hw" -lt $((size - margin)) ] || err "${label}stack high-water ${hw:-?} of ${size:-?} bytes: too close to the end"
}

# ---- the handhelds (GBA, DS): one ARM target each, a cartridge ROM, cases that may not fit

# hh_prereqs: the ARM toolchain, python3 and picolibc; sets specs_file
hh_prereqs() {
    have arm-none-eabi-gcc || err "arm-none-eabi-gcc not found (Debian: apt-get install gcc-arm-none-eabi)"
    have python3 || err "python3 not found (Debian: apt-get install python3)"
    specs_file=/usr/lib/picolibc/arm-none-eabi/picolibc.specs
    [ -f $specs_file ] || err "picolibc for arm-none-eabi not found (Debian: apt-get install picolibc-arm-none-eabi)"
}

# hh_build_golden TAG CRT LD IO: the golden runner for $flags/$opt: the core (freestanding, with
# stack and call-graph info), the cases, SHA-256, tools/baremetal's runner with the target's IO
# file and crt, probes for every core entry point the cases call, linked with LD into
# $dir/qibl-golden.elf; sets gcc, specs, dir, objs and elf; exits on failure
hh_build_golden() {
    local tag=$1 crt=$2 ld=$3 io=$4 src o f
    local bm_src="tools/baremetal/main.c tools/baremetal/putu.c tools/baremetal/stack.c tools/baremetal/heap.c tools/baremetal/tls.c tools/baremetal/armtimers.c tools/handheld/hh_start.c $io"
    gcc=arm-none-eabi-gcc specs="-specs=$specs_file"
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
        $gcc $specs $flags $opt $tool_warn -g -DBM_CONFIG="\"$tag\"" -Icore/include -Iplatform/soft/include -Itools \
            -Itools/baremetal -c "$src" -o "$o" || { err "$src: compile failed"; exit 1; }
    done
    o="$dir/tools/$(basename "$crt" .S).o"; objs+=("$o")
    # shellcheck disable=SC2086
    $gcc $flags -c "$crt" -o "$o" || { err "$(basename "$crt")"; exit 1; }

    # stack bounds of every public entry point, then trampolines for the ones the cases call (the
    # ARMv4T form on both: ARMv5TE's Thumb has blx, but no mov between low registers either)
    python3 tools/baremetal/stack.py --objdump arm-none-eabi-objdump --helpers "$($gcc $flags -print-libgcc-file-name)" "$dir/core" > "$dir/stack-bounds.txt" ||
        err "an entry point has no static stack bound: $(grep unbounded "$dir/stack-bounds.txt" | head -3)"
    local probed
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
    local redef=()
    for f in malloc calloc realloc free; do redef+=(--redefine-sym "$f=bm_$f"); done
    for f in $probed; do redef+=(--redefine-sym "$f=bm_probe_$f"); done
    for o in "$dir"/tools/cases*.o; do arm-none-eabi-objcopy "${redef[@]}" "$o" || { err "objcopy $o"; exit 1; }; done
    elf="$dir/qibl-golden.elf"
    # shellcheck disable=SC2086
    $gcc $specs $flags $opt -nostartfiles -T "$ld" -Wl,--gc-sections,--no-warn-rwx-segments \
        -o "$elf" "${objs[@]}" -lc -lgcc || { err "link failed"; exit 1; }
}

# hh_sym NAME: the address of NAME in $elf (hex, no 0x)
hh_sym() { arm-none-eabi-nm "$elf" | awk -v n="$1" '$3 == n {print $1}'; }

# hh_cases TAG: every case of $dir/run.txt against fixtures/golden; a case that reports "out of
# memory: needs N bytes" with N above the whole heap cannot fit the target: counted apart
# (TAG.golden_nofit), named in $dir/nofit.txt, and a failure (every case fits both handhelds);
# any other error or a wrong hash fails; the set of cases and the digest must be the hosted
# runner's. Sets heap_cap, ok, bad, nofit and total.
hh_cases() {
    local tag=$1 case hash rest want need
    heap_cap=$(( 0x$(hh_sym __heap_end) - 0x$(hh_sym __heap_start) ))
    ok=0 bad=0 nofit=0
    rm -f "$dir/nofit.txt"
    while read -r _ case hash rest; do
        want=$(head -c 64 "fixtures/golden/$case.sha256" 2>/dev/null)
        need=$(echo "$rest" | sed -n 's/^ERROR out of memory: needs \([0-9]*\) bytes$/\1/p')
        if [ "$hash" = "$want" ]; then ok=$((ok + 1))
        elif [ "$hash" = - ] && [ -n "$need" ] && [ "$need" -gt "$heap_cap" ]; then
            nofit=$((nofit + 1)); echo "$tag: case $case does not fit: needs $need bytes at once, the heap has $heap_cap" >> "$dir/nofit.txt"
        else bad=$((bad + 1)); err "case $case: $hash $rest, fixtures/golden says ${want:-nothing}"; fi
    done < <(grep '^case ' "$dir/run.txt")
    awk '$1 == "case" {print $2}' "$dir/run.txt" > "$dir/cases.txt"
    total=$(wc -l < "$out/host-cases.txt")
    if ! cmp -s "$dir/cases.txt" "$out/host-cases.txt"; then
        err "the cases differ from the hosted runner's: $(diff "$out/host-cases.txt" "$dir/cases.txt" | grep '^[<>]' | head -5 | tr '\n' ' ')"
    fi
    # every case must run: a workspace that no longer fits is a regression (the core's low-memory
    # paths and the ROM's hemi tables made all of them fit), and then the run's digest
    # (tools/golden/runner.c's) must be the hosted runner's
    [ "$nofit" = 0 ] || err "$nofit cases do not fit the heap ($heap_cap B): $(awk '{print $3}' "$dir/nofit.txt" | tr '\n' ' ')"
    local digest host_digest
    digest=$(sed -n 's/^golden: .* digest \([0-9a-f]*\)$/\1/p' "$dir/run.txt")
    host_digest=$(sed -n 's/^golden: .* digest \([0-9a-f]*\)$/\1/p' "$out/host.txt")
    if [ "$nofit" = 0 ] && [ "${digest:-x}" != "${host_digest:-y}" ]; then
        err "the run's digest ${digest:-missing} is not the hosted runner's ${host_digest:-?}"
    fi
}

# hh_exit RC: the ROM exits 1 when a case reported an error: allowed only when every error is a
# case that does not fit; then the cases that do not fit, named
hh_exit() {
    local rc=$1 errors
    errors=$(sed -n 's/^golden: .* \([0-9]*\) errors; digest .*/\1/p' "$dir/run.txt")
    if [ "$rc" != 0 ] && ! { [ "$rc" = 1 ] && [ "${errors:-x}" = $nofit ]; }; then
        err "the run exited with $rc ($(tail -n 2 "$dir/run.txt" "$dir/run-err.txt" | tr '\n' ' '))"
    fi
    [ -f "$dir/nofit.txt" ] && cat "$dir/nofit.txt"
}

# hh_tables TAG FILE: $out/tables.md printed, and put in place of FILE's generated block
# (<!-- make TAG: generated ... <!-- end make TAG -->) when FILE is set and nothing failed
hh_tables() {
    local tag=$1 file=$2
    cat "$out/tables.md"
    if [ -n "$file" ] && [ $fail = 0 ]; then
        python3 - "$file" "$out/tables.md" "$tag" <<'PY' || err "cannot rewrite the block of $file"
import sys
doc, block, tag = open(sys.argv[1]).read(), open(sys.argv[2]).read().rstrip("\n"), sys.argv[3]
begin, end = "<!-- make %s: generated" % tag, "<!-- end make %s -->" % tag
a, b = doc.find(begin), doc.find(end)
if a < 0 or b < a:
    sys.exit("no generated block (%s ... %s) in %s" % (begin, end, sys.argv[1]))
open(sys.argv[1], "w").write(doc[:a] + block + doc[b + len(end):])
PY
    fi
}

# hh_results TAG OK-TEXT: the closing lines and the RESULT lines; exits with the status
hh_results() {
    local tag=$1 oktext=$2
    [ $((ok + nofit)) = "$total" ] || err "$ok match and $nofit do not fit of $total cases"
    echo "$tag: $(($(date +%s) - t_start)) s"
    if [ $fail = 0 ]; then echo "$tag: OK ($oktext)"; else echo "$tag: FAILED"; fi
    echo "RESULT $tag.golden_match $ok"
    echo "RESULT $tag.golden_nofit $nofit"
    echo "RESULT $tag.golden_total $total"
    exit $fail
}
