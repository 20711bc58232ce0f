#!/bin/sh
# blender_fire_test.sh - the Blender exporter's emission (python/blender/brume_export.py)
# against Cycles: a fire made here (tests/blender/make_fire.py: density, temperature and
# flame grids; a Principled Volume with Emission Strength from the flame, an Emission Color
# and blackbody from the temperature) is rendered by Cycles and, exported, by brume; the
# mean radiances must agree to their standard error (tests/blender/mean.py). And the
# exporter's volume-only meshes (tests/blender/export_checks.py): a box as a box medium, a
# sphere as a mesh bounding its medium; and such a sphere with emission (make_ball.py)
# against Cycles, to the same tolerance.
# Skips (77) without the `blender` command or without pyopenvdb.
#   sh tests/blender_fire_test.sh BRUME_EXE SOURCE_DIR
brume=$1 src=$2
command -v blender >/dev/null 2>&1 || { echo "skipped: no blender command"; exit 77; }
d=$(mktemp -d) || exit 1
trap 'rm -rf "$d"' EXIT
rc=0
blender -b --factory-startup --python-exit-code 1 --python "$src/tests/blender/make_fire.py" -- \
    "$d/fire.vdb" "$d/scene.blend" "$d/cycles.exr" 256 > "$d/cycles.log" 2>&1 || rc=$?
grep -q '^skipped: no pyopenvdb' "$d/cycles.log" && { echo "skipped: no pyopenvdb"; exit 77; }
[ "$rc" = 0 ] || { cat "$d/cycles.log"; exit 1; }
set -e
blender -b --factory-startup --python-exit-code 1 --python "$src/tests/blender/export_checks.py" -- \
    "$src/python/blender/brume_export.py" "$d" "$brume" > "$d/checks.log" 2>&1 || { cat "$d/checks.log"; exit 1; }
grep -E '^(box medium|sphere medium|brume renders)' "$d/checks.log"
blender -b "$d/scene.blend" --factory-startup --python-exit-code 1 --python "$src/python/blender/brume_export.py" -- \
    "$d/scene.json" "$brume" render --spp 256 --seed 3 -q -o "$d/brume.exr" > "$d/export.log" 2>&1 || { cat "$d/export.log"; exit 1; }
grep -q '"emission_units": "radiance_per_length"' "$d/scene.json"
grep -q '"model": "blender"' "$d/scene.json"
blender -b --factory-startup --python-exit-code 1 --python "$src/tests/blender/mean.py" -- "$d/cycles.exr" "$d/brume.exr" 2>&1 | grep '^mean'
blender -b --factory-startup --python-exit-code 1 --python "$src/tests/blender/mean.py" -- "$d/cycles.exr" "$d/brume.exr" > /dev/null 2>&1
# a volume-only sphere, exported as a mesh bounding its medium, against Cycles
blender -b --factory-startup --python-exit-code 1 --python "$src/tests/blender/make_ball.py" -- \
    "$d/ball.blend" "$d/ball-cycles.exr" > "$d/ball.log" 2>&1 || { cat "$d/ball.log"; exit 1; }
blender -b "$d/ball.blend" --factory-startup --python-exit-code 1 --python "$src/python/blender/brume_export.py" -- \
    "$d/ball.json" "$brume" render --spp 256 --seed 3 -q -o "$d/ball-brume.exr" > "$d/ball-export.log" 2>&1 || { cat "$d/ball-export.log"; exit 1; }
grep -q '"medium_inside": "fogball"' "$d/ball.json"
blender -b --factory-startup --python-exit-code 1 --python "$src/tests/blender/mean.py" -- "$d/ball-cycles.exr" "$d/ball-brume.exr" 2>&1 | grep '^mean'
blender -b --factory-startup --python-exit-code 1 --python "$src/tests/blender/mean.py" -- "$d/ball-cycles.exr" "$d/ball-brume.exr" > /dev/null 2>&1
