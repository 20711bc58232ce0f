#!/bin/sh
# bench_mpi.sh - speed-up of `brume render` from 1 to 2 MPI ranks on this machine, for one
# frame (ranks split its tiles) and a short sequence (ranks split its frames). Each rank
# runs one worker thread, so 1 -> 2 ranks is 1 -> 2 cores. Prints medians of RUNS runs
# (default 3) and the machine. Usage: sh bench/bench_mpi.sh [BUILD_DIR] (default build).
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$here/build}
brume=$build/brume
runs=${RUNS:-3}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
command -v mpirun >/dev/null || { echo "bench_mpi: mpirun not found (openmpi-bin)" >&2; exit 1; }
mpirun="mpirun --oversubscribe"
if [ "$(id -u)" -eq 0 ]; then mpirun="$mpirun --allow-run-as-root"; fi

now() { date +%s.%N; }
# median of the wall times of `runs` runs of the command in "$@"
median() {
    i=0
    : > "$tmp/times"
    while [ $i -lt "$runs" ]; do
        t0=$(now)
        "$@" >/dev/null 2>&1
        t1=$(now)
        echo "$t1 - $t0" | bc -l >> "$tmp/times"
        i=$((i + 1))
    done
    sort -g "$tmp/times" | awk '{a[NR] = $1} END {printf "%.3f", a[int((NR + 1) / 2)]}'
}

frame="render $here/scenes/default.json --width 320 --height 200 --spp 16 --threads 1 --quiet"
seq="render $here/scenes/anim-stam-drift.json --frames 0-7 --width 160 --height 100 --spp 16 --threads 1 --quiet"

echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "mpi: $(mpirun --version 2>/dev/null | head -1)"
echo "medians of $runs runs, wall seconds"
printf '%-42s %10s %12s %12s %9s\n' case "1 process" "mpirun -np 1" "mpirun -np 2" speed-up
row() { # name, out1, out2 (file names), then the brume arguments
    name=$1 o1=$2 o2=$3
    shift 3
    t1=$(median "$brume" "$@" -o "$tmp/$o1")
    m1=$(median $mpirun -np 1 "$brume" "$@" -o "$tmp/m$o1")
    m2=$(median $mpirun -np 2 "$brume" "$@" -o "$tmp/$o2")
    printf '%-42s %10s %12s %12s %8.2fx\n' "$name" "$t1" "$m1" "$m2" "$(echo "$t1 / $m2" | bc -l)"
}
# shellcheck disable=SC2086
row "one frame 320x200, 16 spp (tiles split)" a.exr b.exr $frame
cmp -s "$tmp/a.exr" "$tmp/b.exr" || { echo "bench_mpi: 2 ranks differ from 1 process" >&2; exit 1; }
# shellcheck disable=SC2086
row "8 frames 160x100, 16 spp (frames split)" "a_%d.exr" "b_%d.exr" $seq
for f in 0 1 2 3 4 5 6 7; do
    cmp -s "$tmp/a_$f.exr" "$tmp/b_$f.exr" || { echo "bench_mpi: frame $f differs between 1 and 2 ranks" >&2; exit 1; }
done
