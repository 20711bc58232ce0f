#!/bin/sh
# run.sh - the GPU checks and timings of docs/gpu.md, on a machine with an NVIDIA GPU.
#
#   sh tests/gpu/run.sh [BUNDLE.tar.xz] [OUTDIR]
#
# BUNDLE is a brume build packed by scripts/gpu-bundle.sh (default .gpu/brume.tar.xz): the GPU
# machine needs no Debian package. DATA (default .gpu/data) holds cloud64.raw and the 1/16
# Disney cloud as wdas.nvdb (`brume convert wdas_cloud_sixteenth.vdb wdas.nvdb`).
#
# 1. The kernels' variants (bench: docs/gpu.md, "Speed"): the driver compiles the PTX for
#    each register cap at once, then wdas-dense is timed with each kernel and cap; the
#    fastest is used for the rest (TUNE=0 skips this and keeps the defaults).
# 2. For each check scene it renders on the CPU (all cores) and twice on the GPU with the
#    same seed: the two GPU images must be byte-identical (determinism), and the GPU's must
#    agree with the CPU's within the noise, per channel and per 32^2 block
#    (tests/gpu/compare.c).
# 3. The floors of issue 35, timed on the GPU and on this machine's own cores.
# 4. Where the kernel's time goes (ncu), when Nsight Compute is there.
# Exit status 0 when every check passed.
set -u
bundle=${1:-.gpu/brume.tar.xz}
out=${2:-${OUT:-/tmp/brume-gpu-out}}
data=$(cd "${DATA:-.gpu/data}" && pwd)
b=/tmp/brume-gpu
mkdir -p "$b" "$out"
tar -C "$b" -xJf "$bundle" || exit 2
export LD_LIBRARY_PATH="$b/lib"
br="$b/bin/brume"
echo "== machine: $(nproc) cores; $(nvidia-smi -L 2>/dev/null | head -1); $(date -u +%FT%TZ)"
"$br" devices || exit 1
cc -O2 -Iinclude tests/gpu/compare.c -L"$b/lib" -lbrume -lm -o "$out/compare" || exit 2
fail=0
now() { date +%s.%N; }
sub() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.3f", a - b }'; }
wdas="scenes/wdas-dense.json --set media.0.density.file=$data/wdas.nvdb"
tiny="scenes/cloud64.json --set media.0.density.file=$data/cloud64.raw --width 16 --height 16 --spp 1"

# 1. variants
if [ "${TUNE:-1}" = 1 ]; then
    echo "== the driver compiles the PTX for each register cap (two at a time)"
    t0=$(now)
    for pair in "0 128" "96 64"; do
        for m in $pair; do
            BRUME_GPU_MAXREG=$m timeout 120 "$br" render $tiny --device cuda -o "$out/jit$m.exr" 2>/dev/null &
        done
        wait
    done
    echo "compiled in $(sub "$(now)" "$t0") s"
    best=""; best_t=1e9
    for k in paths samples; do
        for m in 0 128 96 64; do
            t0=$(now)
            line=$(BRUME_GPU_KERNEL=$k BRUME_GPU_MAXREG=$m timeout 120 "$br" render $wdas --spp 64 --device cuda \
                   -o "$out/v.exr" 2>&1 | tail -1)
            t=$(sub "$(now)" "$t0")
            echo "variant kernel=$k maxreg=$m: wdas-dense 64 spp $t s whole process; $line"
            if awk -v a="$t" -v b="$best_t" 'BEGIN { exit !(a < b) }' && echo "$line" | grep -q "64 spp"; then
                best="$k $m"; best_t=$t
            fi
        done
    done
    set -- $best
    export BRUME_GPU_KERNEL=$1 BRUME_GPU_MAXREG=$2
    echo "== fastest: kernel=$1 maxreg=$2 ($best_t s); used below"
fi

# 2. check NAME SPP ARGS...: CPU vs GPU, GPU vs GPU
check() {
    name=$1; spp=$2; shift 2
    t0=$(now)
    timeout 200 "$br" render "$@" --spp "$spp" --seed 11 --aov variance -o "$out/$name-cpu.exr" 2>/dev/null || { echo "$name: CPU render failed"; fail=1; return; }
    t1=$(now)
    timeout 100 "$br" render "$@" --spp "$spp" --seed 12 --aov variance --device cuda -o "$out/$name-gpu.exr" 2>/dev/null || { echo "$name: GPU render failed"; fail=1; return; }
    t2=$(now)
    timeout 100 "$br" render "$@" --spp "$spp" --seed 12 --aov variance --device cuda -o "$out/$name-gpu2.exr" 2>/dev/null || { echo "$name: GPU render failed"; fail=1; return; }
    echo "== $name, $spp spp: CPU $(sub "$t1" "$t0") s, GPU $(sub "$t2" "$t1") s (whole process)"
    if cmp -s "$out/$name-gpu.exr" "$out/$name-gpu2.exr"; then
        echo "$name: two GPU runs byte-identical"
    else
        echo "$name: two GPU runs DIFFER"; fail=1
    fi
    "$out/compare" "$out/$name-cpu.exr" "$out/$name-gpu.exr" || fail=1
}

check cloud64 256 scenes/cloud64.json --set "media.0.density.file=$data/cloud64.raw"
check wdas-dense 256 $wdas
check chromatic-ground 256 tests/gpu/chromatic-emissive.json
check default 128 scenes/default.json --width 240 --height 160 --set render.noise=0
check blobs 256 scenes/stam-fig5-a.json --set render.method=path --width 160 --height 120

# 3. floors
echo "== timings: wdas-dense 256 x 256 on the GPU, whole process (start-up, load, prepare, passes, write)"
for spp in 1 64 64 64 256 1024; do
    t0=$(now)
    line=$(timeout 120 "$br" render $wdas --spp $spp --device cuda -o "$out/t.exr" 2>&1 | tail -1)
    echo "wdas-dense gpu $spp spp: $(sub "$(now)" "$t0") s; $line"
done
t0=$(now)
line=$(timeout 120 "$br" render $wdas --spp 64 -o "$out/t.exr" 2>&1 | tail -1)
echo "wdas-dense cpu ($(nproc) cores) 64 spp: $(sub "$(now)" "$t0") s; $line"
echo "== the default scene at its 3 % noise target, whole process"
for dev in cuda cuda cpu; do
    t0=$(now)
    line=$(timeout 150 "$br" render --device $dev -o "$out/default-$dev.png" 2>&1 | tail -1)
    echo "default $dev: $(sub "$(now)" "$t0") s; $line"
done

# 4. ncu
ncu=$(command -v ncu || ls /opt/nvidia/nsight-compute/*/ncu /usr/local/cuda/bin/ncu 2>/dev/null | head -1)
if [ -n "$ncu" ] && [ "${NCU:-1}" = 1 ]; then
    kname=brume_paths
    [ "${BRUME_GPU_KERNEL:-paths}" = samples ] && kname=brume_samples
    echo "== ncu ($ncu) on $kname: wdas-dense 128 x 128, 16 spp"
    timeout 150 "$ncu" --launch-count 1 --kernel-name $kname --section SpeedOfLight --section Occupancy \
        --section LaunchStats --section WarpStateStats --section SchedulerStats --section MemoryWorkloadAnalysis \
        "$br" render $wdas --spp 16 --width 128 --height 128 --device cuda -o "$out/n.exr" 2>&1 |
        grep -v "^==PROF==" | grep -E "Duration|Throughput|Occupancy|Registers|Local|Block Limit|Warp Cycles|Stall|Eligible|Issued|Hit Rate|Threads|Waves|Achieved|Theoretical|Active Warps|No Eligible" | head -60
fi
echo "== result: $([ $fail = 0 ] && echo PASS || echo FAIL)"
exit $fail
