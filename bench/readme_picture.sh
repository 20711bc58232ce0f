#!/bin/sh
# readme_picture.sh - README's picture, docs/images/default.png, made by the command that
# `make render` runs (README, "Quick start"): `brume render --time 15 --denoise -o brume.png`,
# the built-in default scene (scenes/default.json, compiled into the binary) after 15 s of
# rendering, denoised. Writes the picture and docs/bench/readme-picture.txt, which records
# the scene file, the commit (and whether the tree differed from it), the denoiser's last
# commit, the machine, its load before and after, and brume's summary (samples reached).
#
#   sh bench/readme_picture.sh [BUILD]      # BUILD defaults to build (brume built there)
#
# The picture depends on the load (15 s of a busy machine give fewer samples): the record
# says what it was. Not part of `make test`.
set -eu
build=${1:-build}
here=$(cd "$(dirname "$0")/.." && pwd)
brume="$build/brume"
[ -x "$brume" ] || { echo "readme_picture: $brume: not found (build it first: make build)" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
load0=$(cut -d' ' -f1-3 /proc/loadavg)
"$brume" render --time 15 --denoise -o "$tmp/brume.png" 2>"$tmp/log"
load1=$(cut -d' ' -f1-3 /proc/loadavg)
bytes=$(wc -c <"$tmp/brume.png")
[ "$bytes" -le 307200 ] || { echo "readme_picture: the picture is $bytes bytes, over 300 KB" >&2; exit 1; }
cp "$tmp/brume.png" "$here/docs/images/default.png"
git() { command git -C "$here" "$@"; }
dirty=$(git status --porcelain --untracked-files=no -- src include cli scenes 2>/dev/null | wc -l)
{
    echo "picture: docs/images/default.png ($bytes bytes)"
    echo "command: brume render --time 15 --denoise -o brume.png (make render's)"
    echo "scene: the built-in default scene, scenes/default.json (compiled into the binary)"
    echo "commit: $(git rev-parse --short HEAD)$([ "$dirty" -gt 0 ] && echo ", with uncommitted changes to src/include/cli/scenes" || true)"
    echo "denoiser: last changed in $(git log -1 --format='%h %s' -- src/image)"
    echo "brume: $("$brume" --version | head -1), the binary $brume"
    echo "date: $(date -u '+%Y-%m-%d %H:%M UTC')"
    echo "machine: $(nproc) x $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), load $load0 before, $load1 after"
    echo "brume's output:"
    sed 's/^/  /' "$tmp/log"
} >"$here/docs/bench/readme-picture.txt"
cat "$here/docs/bench/readme-picture.txt"
