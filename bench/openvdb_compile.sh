#!/bin/sh
# openvdb_compile.sh - the CPU time each C++ file of the OpenVDB module takes to compile, with
# the flags the build gave it (its configuration, -g1, warnings), one after another so that
# the figures do not compete: user + system seconds per file, and the sum.
#
#   sh bench/openvdb_compile.sh [BUILD]      # BUILD defaults to build (configured by CMake)
set -eu
build=${1:-build}
src=$(cd "$(dirname "$0")/.." && pwd)
flags="$build/CMakeFiles/brume_openvdb.dir/flags.make"
[ -f "$flags" ] || { echo "openvdb_compile: $flags: not found (configure $build with OpenVDB first)" >&2; exit 1; }
get() { sed -n "s/^$1 = //p" "$flags"; }
cxx=$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$build/CMakeCache.txt")
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "machine: $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg); $($cxx --version | head -1)"
echo "flags: $(get CXX_FLAGS)"
total=0
for f in "$src"/src/io/grid_vdb*.cpp; do
    n=$(basename "$f" .cpp)
    # shellcheck disable=SC2046
    /usr/bin/time -f "%U %S" -o "$out/t" $cxx $(get CXX_DEFINES) $(get CXX_INCLUDES) $(get CXX_FLAGS) -c "$f" -o "$out/$n.o"
    s=$(awk '{printf "%.1f", $1 + $2}' "$out/t")
    total=$(echo "$total $s" | awk '{printf "%.1f", $1 + $2}')
    printf '%-22s %6s s CPU\n' "$n.cpp" "$s"
done
printf '%-22s %6s s CPU\n' "all" "$total"
