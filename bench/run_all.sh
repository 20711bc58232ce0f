#!/bin/sh
# run_all.sh - most benchmarks in one run, on an otherwise idle machine; docs/performance.md
# says what each measures. Usage: sh bench/run_all.sh [BUILD_DIR] > bench.txt
# Takes about 20 minutes on 2 cores; Blender for the Cycles comparison is installed when
# run as root (bench/cloud64_vs_cycles.sh).
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
cd "$here"
cmake --build "$build" -j2 >/dev/null
cmake --build "$build" --target bench -j2 >/dev/null
echo "### date: $(date -u +%Y-%m-%dT%H:%MZ), load before: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "### start-up (bench/startup.py)"
python3 bench/startup.py --build "$build"
echo "### bench_render (default scene, 240 x 160)"
"$build/bench/bench_render" --width 240 --height 160 --ref-spp 512
echo "### cloud64 vs Blender Cycles"
REF_SPP=${REF_SPP:-512} sh bench/cloud64_vs_cycles.sh "$build"
echo "### render.sampler: sobol against independent (cloud64, wdas-dense)"
python3 bench/efficiency.py --build "$build"
echo "### bench_phase"
"$build/bench/bench_phase"
echo "### bench_grid"
"$build/bench/bench_grid" 5
echo "### bench_surfaces"
"$build/bench/bench_surfaces"
echo "### bench_blasi"
"$build/bench/bench_blasi" --runs 3
echo "### bench_stam"
"$build/bench/bench_stam" 3
echo "### bench_mpi"
sh bench/bench_mpi.sh "$here/$build"
