#!/bin/sh
# bench_budget.sh - does `brume render --time T` hold, as a user runs it? For the default
# scene, scenes/cloud64.json and scenes/wdas-dense.json: the whole process's wall time for a
# budget T; the render's own time as brume prints it ("rendering X s of a T s budget": the
# integrator's preparation and the passes); the rest of the process (wall - rendering: start-up,
# loading the scene, building and writing the image); and the render's overshoot
# (rendering - T) / T, which the budget promises below 5 %. Medians of 3 runs; the machine's
# load is printed, since a shared machine slows every sample.
#
#   bench/bench_budget.sh BUILD_DIR [T]     (default T = 5; grids from data/)
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
printf '%-11s %6s %10s %10s %10s %10s %9s\n' scene T wall rendering rest overshoot spp
for s in default cloud64 wdas-dense; do
    if [ "$s" = default ]; then scene=""; else scene="$ROOT/scenes/$s.json"; fi
    walls="" rends="" spp=""
    for r in 1 2 3; do
        t1=$(now)
        "$BRUME" render $scene --time "$T" --spp 16777216 -o "$OUT/b.exr" 2> "$OUT/err"
        t2=$(now)
        walls="$walls $(echo "$t2 - $t1" | bc -l)"
        rends="$rends $(sed -n 's/.*(rendering \([0-9.]*\) s of a.*/\1/p' "$OUT/err" | tail -1)"
        spp=$(sed -n 's/.*(\([0-9.]*\) on average).*/\1/p' "$OUT/err" | tail -1)
    done
    w=$(echo $walls | tr ' ' '\n' | median)
    rd=$(echo $rends | tr ' ' '\n' | median)
    o=$(echo "100 * ($rd - $T) / $T" | bc -l)
    printf '%-11s %6s %9.2fs %9.2fs %9.2fs %9.1f%% %9s\n' "$s" "$T" "$w" "$rd" "$(echo "$w - $rd" | bc -l)" "$o" "$spp"
done
