#!/bin/sh
# blender_picture.sh - the picture of docs/production.md's Blender section: the .blend of
# tests/blender_test.sh (tests/blender/make_scene.py) at W x H, rendered by Cycles and,
# exported by python/blender/brume_export.py, by brume, side by side (sRGB, no tone curve).
#   sh bench/blender_picture.sh BRUME_EXE OUT.png [WxH [SPP]]     (needs blender and ffmpeg)
set -e
brume=$1 out=$2 size=${3:-320x240} spp=${4:-128}
src=$(cd "$(dirname "$0")/.." && pwd)
d=$(mktemp -d)
trap 'rm -rf "$d"' EXIT
"$brume" gen cloud --dims 24x24x24 --shape ellipsoid --bounds -1,-1,-1,1,1,1 -o "$d/cloud.vdb" > /dev/null
t0=$(date +%s.%N)
blender -b --factory-startup --python-exit-code 1 --python "$src/tests/blender/make_scene.py" -- \
    "$d/cloud.vdb" "$d/scene.blend" "$d/cycles.exr" "$spp" "$size" > "$d/cycles.log" 2>&1 || { cat "$d/cycles.log"; exit 1; }
t1=$(date +%s.%N)
blender -b "$d/scene.blend" --factory-startup --python-exit-code 1 --python "$src/python/blender/brume_export.py" -- \
    "$d/scene.json" "$brume" render --spp "$spp" --seed 3 -q -o "$d/brume.exr" > "$d/export.log" 2>&1 || { cat "$d/export.log"; exit 1; }
t2=$(date +%s.%N)
echo "Cycles (make_scene.py, render included): $(echo "$t1 - $t0" | bc) s; export + brume render: $(echo "$t2 - $t1" | bc) s; load $(cut -d' ' -f1-3 /proc/loadavg)"
blender -b --factory-startup --python-exit-code 1 --python "$src/tests/blender/mean.py" -- "$d/cycles.exr" "$d/brume.exr" 2>&1 | grep '^mean' || true
# linear EXR to sRGB, the two side by side with a 4-pixel gap
ffmpeg -loglevel error -y -apply_trc iec61966_2_1 -i "$d/cycles.exr" -apply_trc iec61966_2_1 -i "$d/brume.exr" \
    -filter_complex "[0:v]pad=iw+4:ih:0:0:white[a];[a][1:v]hstack=inputs=2,format=rgb24" -frames:v 1 "$out"
echo "$out: Cycles (left) and brume (right), $size, $spp spp each"
