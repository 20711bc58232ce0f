#!/bin/sh
# build_id_test.sh CMAKE SOURCE_DIR - cmake/build_id.cmake, which names the build a checkpoint
# was written by (src/job/checkpoint.c): on a copy of the sources, the id must stay the same
# when nothing changes (the header is not rewritten, so nothing recompiles), and change when
# one byte of one source, the default scene or the compiler flags change.
set -eu
CMAKE=$1
ROOT=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/tree/scenes"
cp -R "$ROOT/src" "$ROOT/include" "$tmp/tree/"
cp "$ROOT/scenes/default.json" "$tmp/tree/scenes/"
id() { # EXTRA -> the id written to $tmp/id.h
    "$CMAKE" -DROOT="$tmp/tree" -DOUT="$tmp/id.h" "-DEXTRA=$1" -P "$ROOT/cmake/build_id.cmake"
    sed -n 's/^#define BRUME_BUILD_ID "\([0-9a-f]*\)"$/\1/p' "$tmp/id.h"
}
fail() { echo "build_id_test: $*"; exit 1; }
a=$(id "GNU 12 Release -O2")
[ ${#a} -eq 16 ] || fail "the id '$a' is not 16 hex digits"
touch -d '2000-01-01' "$tmp/id.h"
[ "$(id "GNU 12 Release -O2")" = "$a" ] || fail "the id changed with nothing changed"
[ -n "$(find "$tmp/id.h" -newermt '2001-01-01')" ] && fail "the header was rewritten with nothing changed"
printf ' ' >>"$tmp/tree/src/render/integrator.c"
b=$(id "GNU 12 Release -O2")
[ "$b" != "$a" ] || fail "one byte more in integrator.c left the id $a"
printf ' ' >>"$tmp/tree/scenes/default.json"
c=$(id "GNU 12 Release -O2")
[ "$c" != "$b" ] || fail "a changed default scene left the id $b"
[ "$(id "GNU 12 Release -O3")" != "$c" ] || fail "other flags left the id $c"
echo "build_id_test: ok ($a, $b, $c)"
