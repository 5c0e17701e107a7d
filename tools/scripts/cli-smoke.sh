#!/bin/sh
# cli-smoke.sh QIBL [WORKDIR] - a short run of every qibl subcommand on tiny inputs, good and bad,
# for the sanitizer build (make test-asan): each good run must exit 0, each bad one with its
# documented status (2 bad arguments, 1 bad file) and leave no output. A sanitizer finding makes
# the run exit with another status (or a signal), which fails the script.
set -u
q=${1:?usage: cli-smoke.sh QIBL [WORKDIR]}
w=${2:-$(mktemp -d)}
rm -rf "$w" && mkdir -p "$w" || exit 1
runs=0 fails=0

# want STATUS [OUTPUT|-] ARGS...: run qibl ARGS, expect STATUS and (unless -) OUTPUT not created
want() {
    st=$1 out=$2
    shift 2
    runs=$((runs + 1))
    "$q" "$@" >"$w/stdout.txt" 2>"$w/stderr.txt"
    rc=$?
    if [ "$rc" != "$st" ]; then
        fails=$((fails + 1))
        echo "cli-smoke: FAIL: qibl $* exited $rc, want $st" >&2
        tail -n 20 "$w/stderr.txt" >&2
    elif [ "$out" != - ] && [ -e "$out" ]; then
        fails=$((fails + 1))
        echo "cli-smoke: FAIL: qibl $* left $out behind" >&2
    fi
}

# good runs: every subcommand once
want 0 - --help
want 0 - sh eval 0 0 1
want 0 - srgbe encode 1 0.5 -0.25
want 0 - gen -o "$w/g.qibl" --size 32x8 --k 9 --lut-size 4
want 0 - info "$w/g.qibl"
want 0 - relight "$w/g.qibl" --sun 1 0.5 1 --png "$w/r.png"
want 0 - relight "$w/g.qibl" --point 0.5 0 0 --lut bilinear --png "$w/p.png" --hdr "$w/p.hdr" --pfm "$w/p2.pfm"
want 0 - relight "$w/g.qibl" --point 0.5 0 0 --lut nearest --png "$w/p.png"
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' > "$w/t.ply"
want 0 - render --size 32x8 --scene "$w/t.ply" --point 0 0 0 --png "$w/tp.png"
want 0 - render --size 32x8 --sun 0 0 1 --png "$w/t.png" --pfm "$w/t.pfm" --depth "$w/d.pfm" --threads 2
want 0 - bake --size 32x8 --k 4 --dirs 32 --shard 0/2 --sums "$w/s0" --quiet --threads 2
want 0 - bake --size 32x8 --k 4 --dirs 32 --shard 1/2 --sums "$w/s1" --quiet --threads 2
want 0 - merge -o "$w/m.qibl" --lsq "$w/s0" "$w/s1"
want 0 - check "$w/g.qibl" "$w/m.qibl" "$w/r.png" "$w/t.pfm" "$w/p.hdr"
{ printf '#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 16 +X 32\n'; i=0; while [ $i -lt 512 ]; do printf '\200\144\074\201'; i=$((i + 1)); done; } >"$w/p.hdr"
want 0 - lights "$w/p.hdr" -n 4 --png "$w/l.png" --error
want 0 - sh project "$w/p.hdr" --bands 3 --irradiance --window hann
want 0 - sh project "$w/p.hdr" --preset filament
want 0 - sh project "$w/p.hdr" --preset filament --window 4 --yaw 30
want 0 - sh project "$w/p.hdr" --preset unity
want 0 - sh project "$w/p.hdr" --preset gltf --rotate 0,-1,0,1,0,0,0,0,1
want 0 - sh project "$w/p.hdr" --frame yup --format json
want 0 - lights "$w/p.hdr" -n 4 --preset gltf --yaw 45
want 0 - sh project "$w/p.hdr" --format json
want 0 - sh project "$w/p.hdr" --format c --name sky
want 0 - lights "$w/p.hdr" -n 4 --json
want 0 - probe info "$w/p.hdr"
printf 'x,y,z,r,g,b,u0,v0,u1,v1\n0,0,1,0.5,0.5,0.5,0,0,1,1\n' >"$w/l.csv"
want 0 - relight "$w/g.qibl" --sun 1 0.5 1 --sun 0 0 1 --rgb 2 1 1 --point 0.5 0 0 --point 0 0.5 0 --lut bilinear --lights "$w/l.csv" --png "$w/r2.png"
want 0 - relight "$w/g.qibl" --probe "$w/p.hdr" --yaw 30 --png "$w/r3.png"
want 0 - view "$w/g.qibl" --probe "$w/p.hdr" --bench --headless --frames 3 --turn --record "$w/v.png"
want 0 - relight "$w/g.qibl" --probe "$w/p.hdr" --probe-mode sunsky -n 16 --rotate 0,-1,0,1,0,0,0,0,1 --png "$w/r4.png"
want 0 - relight "$w/g.qibl" --probe "$w/p.hdr" --probe-mode lights -n 8 --png "$w/r5.png"
want 0 - demo --out "$w/demo" --size 32x8 --dirs 16 --frames 2 --threads 2

# bad arguments: exit 2, nothing written
want 2 "$w/x.png" render --size 32x8 --sun 1e308 1e308 1e308 --png "$w/x.png"
want 2 "$w/x.pfm" render --size 32x8 --sun 0 0 1 --rgb 1e308 1 1 --pfm "$w/x.pfm"
want 2 "$w/x.png" relight "$w/g.qibl" --sun 0 0 1 --rgb 40000 1 1 --png "$w/x.png"
want 2 "$w/x.png" relight "$w/g.qibl" --sun 0 0 0 --png "$w/x.png"
want 2 "$w/x.png" view "$w/g.qibl" --record "$w/x.png"
want 2 "$w/x.png" view "$w/g.qibl" --bench --headless --frames 1 --record "$w/x.png"
want 2 - view "$w/g.qibl" --exposure 1000
want 2 - view "$w/g.qibl" --headless
want 1 - view "$w/nonexistent.qibl" --bench --headless
want 2 "$w/x.qibl" gen -o "$w/x.qibl" --size 8x4junk
want 2 "$w/x.qibl" merge -o "$w/x.qibl" --k 9 "$w/s0" "$w/s1"
{ printf '#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 128 +X 256\n'; dd if=/dev/zero bs=4 count=32768 2>/dev/null; } >"$w/big.hdr"
want 2 "$w/x.png" lights "$w/big.hdr" -n 4 --zoom 64 --png "$w/x.png"
want 2 - nosuchcommand
want 2 - sh project "$w/p.hdr" --window sharp
want 2 - sh project "$w/p.hdr" --format xml
want 2 - sh project "$w/p.hdr" --format cmgen
want 2 - sh project "$w/p.hdr" --preset unreal
want 2 - sh project "$w/p.hdr" --preset filament --window 0
want 2 - lights "$w/p.hdr" --preset gltf --csv
want 2 "$w/x.png" relight "$w/g.qibl" --probe "$w/p.hdr" --rotate 1,0,0,0,1,0,0,0,-1 --png "$w/x.png"

# bad files: exit 1, nothing written
want 1 "$w/x.qibl" merge -o "$w/x.qibl" "$w/s0" "$w/s0"
want 1 "$w/x.qibl" merge -o "$w/x.qibl" "$w/p.hdr"
head -c 100 "$w/s1" >"$w/short"
want 1 "$w/x.qibl" merge -o "$w/x.qibl" "$w/s0" "$w/short"
want 1 "$w/x.png" relight "$w/s0" --sun 0 0 1 --png "$w/x.png"
want 1 - info "$w/p.hdr"
want 1 - sh project "$w/g.qibl"
printf 'x,y,z,r,g,b,u0,v0,u1,v1\n0,0,1,nan,1,1,0,0,1,1\n' >"$w/bad.csv"
want 1 "$w/x.png" relight "$w/g.qibl" --lights "$w/bad.csv" --png "$w/x.png"
want 1 - probe info "$w/g.qibl"
printf 'IESNA:LM-63-2002\n[TEST] smoke\nTILT=NONE\n1 -1 1 3 2 1 2 0 0 0\n1 1 10\n0 90 180\n0 90\n5 4 0 5 3 0\n' >"$w/l.ies"
want 0 - ies info "$w/l.ies" --png "$w/ies.png"
printf 'IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 3 2 1 2 0 0 0\n1 1 10\n0 90 180\n0 90\n5 4 0 5 3\n' >"$w/bad.ies"
want 1 "$w/x.png" ies info "$w/bad.ies" --png "$w/x.png"
want 2 - ies info "$w/l.ies" --frob
want 0 - relight "$w/g.qibl" --point 0.5 0 0.3 --ies "$w/l.ies" --aim 0 0 -1 --up 1 0 0 --ies-size 16 --png "$w/ies_r.png"
want 1 "$w/x.png" relight "$w/g.qibl" --point 0.5 0 0.3 --ies "$w/bad.ies" --png "$w/x.png"
want 2 "$w/x.png" relight "$w/g.qibl" --point 0.5 0 0.3 --aim 0 0 -1 --png "$w/x.png"
want 0 - bake -o "$w/lt.qibl" --size 32x8 --k 4 --dirs 32 --quiet --threads 2 --lamp-track "1,1,0.3;-1,1,0.3" --path-steps 4
want 0 - relight "$w/lt.qibl" --path lamp --t 0.5 --ies "$w/l.ies" --ies-size 8 --png "$w/lt.png"
want 1 "$w/x.png" relight "$w/lt.qibl" --path lamp --t 0.5 --ies "$w/bad.ies" --png "$w/x.png"
want 0 - luminaire capture builtin --out "$w/s.qnf" --grid 4 --res 8
want 0 - luminaire info "$w/s.qnf"
want 0 - luminaire render "$w/g.qibl" "$w/s.qnf" --at 0.5 0 0.3 --out "$w/lum.png"
want 1 "$w/x.png" luminaire render "$w/g.qibl" "$w/bad.ies" --at 0.5 0 0.3 --out "$w/x.png"
want 2 - luminaire render "$w/g.qibl" "$w/s.qnf" --out "$w/x.png"
want 0 - luminaire passes --size 8
want 0 - luminaire picture --out "$w/lp.png" --size 8
want 2 "$w/x.png" luminaire picture --out "$w/x.png" --height 0
ln -s g.qibl "$w/link.png"
want 1 - relight "$w/g.qibl" --sun 0 0 1 --png "$w/link.png"
cmp -s "$w/g.qibl" "$w/link.png" || { fails=$((fails + 1)); echo "cli-smoke: FAIL: wrote through a link" >&2; }

echo "cli-smoke: $runs runs of $q, $fails failed"
[ "$fails" = 0 ] && rm -rf "$w"
[ "$fails" = 0 ]
