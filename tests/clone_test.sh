#!/bin/sh
# clone_test.sh - the repository stands on its own: its tracked files (`git ls-files`), copied
# alone into an empty folder, name no file outside that copy, and every scene in scenes/
# renders from the copy with the build's brume (16 x 16, 1 spp: reading the scene and every
# file it names, building it and rendering). The copy's parent folder is empty, so a path
# that leaves the repository (such as the old sibling data folder) fails with "cannot open".
#   clone_test.sh SOURCE_DIR BRUME_EXE
# Exits 77 (ctest: skipped) when SOURCE_DIR is not a git work tree (a release tarball).
set -eu
src=$1
exe=$2
command -v git >/dev/null 2>&1 && git -C "$src" rev-parse --is-inside-work-tree >/dev/null 2>&1 ||
    { echo "clone: $src is not a git work tree, skipped"; exit 77; }
tmp=$(mktemp -d "${TMPDIR:-/tmp}/brume-clone-XXXXXX")
trap 'rm -rf "$tmp"' EXIT
copy="$tmp/brume"
out="$tmp/out"
mkdir "$copy" "$out"
# the tracked files as they are in the work tree (a tracked file deleted there is left out)
(cd "$src" && git ls-files -z | tar --null --ignore-failed-read -T - -cf - 2>/dev/null) | (cd "$copy" && tar xf -)
test -f "$copy/CMakeLists.txt" && test -f "$copy/data/README.md" || { echo "clone: the copy has no CMakeLists.txt or data/README.md"; exit 1; }

# 1. no tracked file names the folder beside the repository, and no file the build, the tests
# or the scenes read names this machine's source path (recorded logs under docs/ may)
up='\.\./shar''ed'
bad=$(cd "$copy" && { grep -rIl -e "$up" . ; grep -rIlF -e "$src/" scenes cmake tests fuzz scripts python \
      CMakeLists.txt Makefile; } || true)
test -z "$bad" || { echo "clone: these files name a path outside the repository:"; echo "$bad"; exit 1; }

# 2. every data file a scene names is in the copy, and every scene renders from it
failed=0
for scene in "$copy"/scenes/*.json; do
    name=$(basename "$scene" .json)
    if grep -q '"file": *"fire.vdb"' "$scene"; then
        # the scene's own comment says to make it first; it needs the OpenVDB writer
        (cd "$copy" && "$exe" gen fire --quiet -o scenes/fire.vdb > "$out/$name.gen" 2>&1) ||
            (cd "$copy" && "$exe" gen fire -o scenes/fire.vdb > "$out/$name.gen" 2>&1) || {
            if grep -q -i 'openvdb' "$out/$name.gen"; then echo "clone: $name skipped (no OpenVDB)"; continue; fi
            echo "clone: brume gen fire failed:"; cat "$out/$name.gen"; failed=1; continue
        }
    fi
    if grep -q '"file": *"fire_%04d.nvdb"' "$scene"; then
        # a flame's cache, a file per frame, made first as its comment says (here frames 0 and 1,
        # small: the scene renders frame 0)
        (cd "$copy" && "$exe" gen fire --resolution 32 --velocity 4 --frames 0-1 -o 'scenes/fire_%04d.nvdb' \
            > "$out/$name.gen" 2>&1) || {
            if grep -q -i 'openvdb' "$out/$name.gen"; then echo "clone: $name skipped (no OpenVDB)"; continue; fi
            echo "clone: brume gen fire --frames failed:"; cat "$out/$name.gen"; failed=1; continue
        }
    fi
    if (cd "$copy" && "$exe" render "scenes/$name.json" --spp 1 --width 16 --height 16 --quiet \
            -o "$out/$name.exr") > "$out/$name.log" 2>&1 && test -s "$out/$name.exr"; then
        echo "clone: $name renders"
    else
        echo "clone: $name FAILED:"; cat "$out/$name.log"; failed=1
    fi
done
test $failed = 0 || exit 1
echo "ok clone: $(ls "$copy"/scenes/*.json | wc -l) scenes render from a copy of the tracked files alone"
