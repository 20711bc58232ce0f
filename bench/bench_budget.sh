#!/bin/sh
# bench_budget.sh - does `brume render --time T` hold, as a user runs it? For the default
# scene, scenes/cloud64.json and scenes/wdas-dense.json: the whole process's wall time for a
# budget T, beside the start-up and final write (the same command with a 1 ms budget on a
# 16 x 16 image: loading the scene, the threads, writing the file), and the overshoot
# (wall - T - start-up) / T, which the budget promises below 5 %. Medians of 3 runs; the
# machine's load is printed, since a shared machine slows every sample.
#
#   bench/bench_budget.sh BUILD_DIR [T]     (default T = 5; grids from ../shared/data)
set -eu
BUILD=${1:?usage: bench_budget.sh BUILD_DIR [T]}
T=${2:-5}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BRUME="$BUILD/brume"
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
now() { date +%s.%N; }
median() { sort -g | sed -n 2p; }
echo "machine: $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg), $(date -u '+%Y-%m-%d %H:%M UTC')"
printf '%-11s %6s %10s %10s %10s %9s\n' scene T wall start-up overshoot spp
for s in default cloud64 wdas-dense; do
    if [ "$s" = default ]; then scene=""; else scene="$ROOT/scenes/$s.json"; fi
    walls="" ups="" spp=""
    for r in 1 2 3; do
        t0=$(now)
        "$BRUME" render $scene --time 0.001 --width 16 --height 16 -o "$OUT/u.exr" --quiet
        t1=$(now)
        "$BRUME" render $scene --time "$T" --spp 16777216 -o "$OUT/b.exr" 2> "$OUT/err"
        t2=$(now)
        ups="$ups $(echo "$t1 - $t0" | bc -l)"
        walls="$walls $(echo "$t2 - $t1" | bc -l)"
        spp=$(sed -n 's/.*(\([0-9.]*\) on average).*/\1/p' "$OUT/err" | tail -1)
    done
    w=$(echo $walls | tr ' ' '\n' | median)
    u=$(echo $ups | tr ' ' '\n' | median)
    o=$(echo "100 * ($w - $T - $u) / $T" | bc -l)
    printf '%-11s %6s %9.2fs %9.2fs %9.1f%% %9s\n' "$s" "$T" "$w" "$u" "$o" "$spp"
done
