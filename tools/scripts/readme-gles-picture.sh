#!/usr/bin/env bash
# readme-gles-picture.sh - docs/img/gles_vs_soft.png: the same asset relit by platform/soft and by
# platform/gles2 (headless Mesa llvmpipe), with the difference x 64. Needs the qibl CLI built with
# GLES (make) and ImageMagick 6 (apt-get install imagemagick; a documentation tool, not a build one).
set -euo pipefail
cd "$(dirname "$0")/../.."
Q=build/bin/qibl
IM=$(command -v convert-im6.q16 || command -v convert)
t=$(mktemp -d)
trap 'rm -rf "$t"' EXIT
export LIBGL_ALWAYS_SOFTWARE=1
"$Q" gen -o "$t/c.qibl" --size 512x128 --k 16 --lut-size 32 >/dev/null
for s in sun pt; do
    if [ $s = sun ]; then light=(--sun 0.5 0.3 0.8); else light=(--point 0 0 0 --lut bilinear); fi
    "$Q" relight "$t/c.qibl" "${light[@]}" --png "$t/${s}_soft.png" >/dev/null 2>&1
    "$Q" relight "$t/c.qibl" "${light[@]}" --gles --png "$t/${s}_gl.png" >/dev/null
    "$IM" "$t/${s}_soft.png" "$t/${s}_gl.png" -compose difference -composite -evaluate multiply 64 "$t/${s}_diff.png"
    echo "$s: max and mean |soft - gles2| in 8-bit units:" \
        "$("$IM" "$t/${s}_soft.png" "$t/${s}_gl.png" -compose difference -composite -format '%[fx:maxima*255] %[fx:mean*255]' info:)"
    for v in soft gl diff; do
        case $v in soft) L="platform/soft (CPU, integer core)" ;; gl) L="platform/gles2 (llvmpipe, GLSL ES 1.00)" ;;
        diff) L="|difference| x 64" ;; esac
        "$IM" "$t/${s}_$v.png" -gravity north -background '#202020' -fill white -pointsize 15 -splice 0x22 \
            -annotate +0+3 "$L" +repage "$t/l_${s}_$v.png"
    done
    "$IM" "$t/l_${s}_soft.png" "$t/l_${s}_gl.png" "$t/l_${s}_diff.png" -append +repage "$t/col_$s.png"
done
"$IM" "$t/col_sun.png" "$t/col_pt.png" +repage -background '#202020' -splice 8x0 +append +repage "$t/row.png"
w=$("$IM" "$t/row.png" -format %w info:)
"$IM" -size "${w}x26" xc:'#202020' -fill white -pointsize 14 -gravity center -annotate +0+0 \
    "left: sun (directional, k = 16); right: lamp (point light, 32^2 cube-map LUT); same asset, same core weights; max difference 1 of 255" \
    "$t/cap.png"
"$IM" "$t/row.png" "$t/cap.png" -append +repage docs/img/gles_vs_soft.png
echo "wrote docs/img/gles_vs_soft.png"
