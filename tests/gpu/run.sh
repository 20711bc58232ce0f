#!/bin/sh
# run.sh - the GPU checks and timings of docs/gpu.md, on a machine with an NVIDIA GPU.
#
#   sh tests/gpu/run.sh [BUNDLE.tar.xz] [OUTDIR]
#
# BUNDLE is a brume build packed by scripts/gpu-bundle.sh (default .gpu/brume.tar.xz): the GPU
# machine needs no Debian package. DATA (default .gpu/data) holds cloud64.raw and the 1/16
# Disney cloud as wdas.nvdb (`brume convert wdas_cloud_sixteenth.vdb wdas.nvdb`).
# For each check scene it renders on the CPU (all cores) and twice on the GPU with the same
# seed: the two GPU images must be byte-identical (determinism), and the GPU's must agree
# with the CPU's within the noise, per channel and per 32^2 block (tests/gpu/compare.c).
# Then it times the GPU. Exit status 0 when every check passed.
set -u
bundle=${1:-.gpu/brume.tar.xz}
out=${2:-${OUT:-/tmp/brume-gpu-out}}
data=$(cd "${DATA:-.gpu/data}" && pwd)
b=/tmp/brume-gpu
mkdir -p "$b" "$out"
tar -C "$b" -xJf "$bundle" || exit 2
export LD_LIBRARY_PATH="$b/lib"
br="$b/bin/brume"
echo "== machine: $(nproc) cores; $(nvidia-smi -L 2>/dev/null | head -1)"
"$br" devices || exit 1
cc -O2 -Iinclude tests/gpu/compare.c -L"$b/lib" -lbrume -lm -o "$out/compare" || exit 2
fail=0
now() { date +%s.%N; }
sub() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.3f", a - b }'; }

# check NAME SPP ARGS...: CPU vs GPU, GPU vs GPU
check() {
    name=$1; spp=$2; shift 2
    t0=$(now)
    "$br" render "$@" --spp "$spp" --seed 11 --aov variance -o "$out/$name-cpu.exr" || { fail=1; return; }
    t1=$(now)
    "$br" render "$@" --spp "$spp" --seed 12 --aov variance --device cuda -o "$out/$name-gpu.exr" || { fail=1; return; }
    t2=$(now)
    "$br" render "$@" --spp "$spp" --seed 12 --aov variance --device cuda -o "$out/$name-gpu2.exr" || { fail=1; return; }
    echo "== $name, $spp spp: CPU $(sub "$t1" "$t0") s, GPU $(sub "$t2" "$t1") s (whole process)"
    if cmp -s "$out/$name-gpu.exr" "$out/$name-gpu2.exr"; then
        echo "$name: two GPU runs byte-identical"
    else
        echo "$name: two GPU runs DIFFER"; fail=1
    fi
    "$out/compare" "$out/$name-cpu.exr" "$out/$name-gpu.exr" || fail=1
}

check cloud64 256 scenes/cloud64.json --set "media.0.density.file=$data/cloud64.raw"
check wdas-dense 256 scenes/wdas-dense.json --set "media.0.density.file=$data/wdas.nvdb"
check chromatic 256 tests/gpu/chromatic-emissive.json
echo "== the default scene (surfaces: refused on the GPU for now)"
"$br" render --device cuda --spp 1 -o "$out/default-gpu.png" && fail=1

echo "== timings: wdas-dense 256 x 256 on the GPU, whole process (start-up, PTX load, prepare, passes, write)"
for spp in 1 64 64 64 256 1024; do
    t0=$(now)
    "$br" render scenes/wdas-dense.json --set "media.0.density.file=$data/wdas.nvdb" --spp $spp --device cuda \
        -o "$out/t.exr" 2>&1 | tail -1
    t1=$(now)
    echo "wdas-dense gpu $spp spp: $(sub "$t1" "$t0") s"
done
for spp in 64; do
    t0=$(now)
    "$br" render scenes/wdas-dense.json --set "media.0.density.file=$data/wdas.nvdb" --spp $spp -o "$out/t.exr" 2>&1 | tail -1
    t1=$(now)
    echo "wdas-dense cpu ($(nproc) cores) $spp spp: $(sub "$t1" "$t0") s"
done
echo "== result: $([ $fail = 0 ] && echo PASS || echo FAIL)"
exit $fail
