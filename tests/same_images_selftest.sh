#!/bin/sh
# same_images_selftest.sh SCRIPT - the comparison step of scripts/same-images.sh (its
# --compare mode, the code its full run uses) on hand-made image folders: identical files
# must read "same" with exit 0; a float one ulp apart, a shorter file, an image missing on one
# side or on both must each be reported, by name, with exit 1. Builds nothing (ctest
# same_images.compare, well under a second).
set -u
SCRIPT=$1
tmp=$(mktemp -d "${TMPDIR:-/tmp}/same-images-selftest.XXXXXX") || exit 1
trap 'rm -rf "$tmp"' EXIT
fails=0
fail() { echo "same_images_selftest: $*"; fails=$((fails + 1)); }
# check NAME EXPECTED_RC PATTERN...: runs --compare A B, wants the exit status and every
# pattern (a grep -E line) in the output
check() {
    name=$1 want=$2
    shift 2
    out=$(bash "$SCRIPT" --compare "$tmp/A" "$tmp/B" 2>&1)
    rc=$?
    [ "$rc" -eq "$want" ] || fail "$name: exit $rc, wanted $want; output:
$out"
    for p in "$@"; do
        printf '%s\n' "$out" | grep -qE -- "$p" || fail "$name: no line matching '$p' in:
$out"
    done
}
one() { printf '\000\000\200\077\000\000\000\100'; }   # float32 1.0, 2.0 (little-endian)
next() { printf '\001\000\200\077\000\000\000\100'; }  # 1.0 one ulp up, 2.0

mkdir -p "$tmp/A" "$tmp/B"
one >"$tmp/A/cloud.exr"; one >"$tmp/B/cloud.exr"
one >"$tmp/A/py.raw"; one >"$tmp/B/py.raw"
check "identical" 0 '^same +cloud$' '^same +py$' '^2 of 2 the same$'

next >"$tmp/B/cloud.exr"
check "one ulp" 1 '^DIFFERENT +cloud ' '^same +py$' '^1 of 2 the same$'

one >"$tmp/B/cloud.exr"
printf '\000\000\200\077' >"$tmp/B/py.raw"
check "shorter" 1 '^same +cloud$' '^DIFFERENT +py ' '^1 of 2 the same$'

one >"$tmp/B/py.raw"
echo "brume: scenes/x.json: camera.fov: 400 outside [0.001, 179]" >"$tmp/B/x.err"
one >"$tmp/A/x.exr"
check "failed on B" 1 '^failed to render on B: x: brume: scenes/x.json: camera.fov' '^2 of 3 the same$'

rm "$tmp/A/x.exr"
echo "timed out after 300 s" >"$tmp/A/x.err"
check "failed on both" 1 '^failed to render on both: x: timed out after 300 s' '^2 of 3 the same$'

rm "$tmp/A/x.err" "$tmp/B/x.err"
check "identical again" 0 '^2 of 2 the same$'

rm -f "$tmp"/A/* "$tmp"/B/*
check "nothing to compare" 1 'no images'

[ "$fails" -eq 0 ] && echo "same_images_selftest: all cases as expected"
[ "$fails" -eq 0 ]
