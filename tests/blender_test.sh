#!/bin/sh
# blender_test.sh - the Blender exporter (python/blender/brume_export.py) against Cycles:
# a .blend made here (tests/blender/make_scene.py) is rendered by Cycles and, exported, by
# brume; the mean radiances must agree to their standard error (tests/blender/mean.py).
# Skips (77) without the `blender` command.
#   sh tests/blender_test.sh BRUME_EXE SOURCE_DIR
brume=$1 src=$2
command -v blender >/dev/null 2>&1 || { echo "skipped: no blender command"; exit 77; }
d=$(mktemp -d) || exit 1
trap 'rm -rf "$d"' EXIT
set -e
"$brume" gen cloud --dims 24x24x24 --shape ellipsoid --bounds -1,-1,-1,1,1,1 -o "$d/cloud.vdb"
blender -b --factory-startup --python-exit-code 1 --python "$src/tests/blender/make_scene.py" -- \
    "$d/cloud.vdb" "$d/scene.blend" "$d/cycles.exr" 256 > "$d/cycles.log" 2>&1 || { cat "$d/cycles.log"; exit 1; }
blender -b "$d/scene.blend" --factory-startup --python-exit-code 1 --python "$src/python/blender/brume_export.py" -- \
    "$d/scene.json" "$brume" render --spp 256 --seed 3 -q -o "$d/brume.exr" > "$d/export.log" 2>&1 || { cat "$d/export.log"; exit 1; }
blender -b --factory-startup --python-exit-code 1 --python "$src/tests/blender/mean.py" -- "$d/cycles.exr" "$d/brume.exr" 2>&1 | grep '^mean'
blender -b --factory-startup --python-exit-code 1 --python "$src/tests/blender/mean.py" -- "$d/cycles.exr" "$d/brume.exr" > /dev/null 2>&1
