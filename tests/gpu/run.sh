#!/bin/sh
# run.sh - the GPU checks and timings of docs/gpu.md, on a machine with an NVIDIA GPU.
#
#   sh tests/gpu/run.sh [BUNDLE.tar.xz] [OUTDIR]
#
# BUNDLE is a brume build packed by scripts/gpu-bundle.sh (default .gpu/brume.tar.xz): the GPU
# machine needs no Debian package. DATA (default .gpu/data) holds cloud64.raw and the 1/16
# Disney cloud as wdas.nvdb (`brume convert wdas_cloud_sixteenth.vdb wdas.nvdb`) and a flame
# with its velocity as fire-vel.nvdb (`brume gen fire --resolution 64 --velocity 2 -o fire-vel.nvdb`).
#
# 1. The first GPU run, in which the driver compiles the PTX.
# 2. For each check scene it renders on the CPU (all cores) and twice on the GPU with the
#    same seed: the two GPU images must be byte-identical (determinism), and the GPU's must
#    agree with the CPU's within the noise, per channel and per 32^2 block
#    (tests/gpu/compare.c).
# 3. The GPU's speed floors, timed on the GPU and on this machine's own cores, and where
#    the kernel's time goes (ncu, when Nsight Compute is there): bench/gpu.sh; CHECKS_ONLY=1
#    skips it (a check of a change, not a measurement).
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

# 1. the driver's compile of the PTX, once per machine (cached in ~/.nv/ComputeCache); with
# VARIANTS (a folder of brume tools built with other BRUME_PTX_OPT, each in NAME/brume), each
# is compiled too (in parallel), timed on wdas-dense, and the fastest renders everything below.
t0=$(now)
for v in "$br" $(ls -d "${VARIANTS:-/nonexistent}"/*/brume 2>/dev/null); do
    timeout 200 "$v" render $tiny --device cuda -o "$out/jit.exr" 2>/dev/null &
done
wait
echo "== the first GPU run on this machine (the driver compiles the PTX): $(sub "$(now)" "$t0") s"
if ls "${VARIANTS:-/nonexistent}"/*/brume >/dev/null 2>&1; then
    best="$br"; best_t=1e9
    for v in "$br" "${VARIANTS}"/*/brume; do
        t0=$(now)
        line=$(timeout 120 "$v" render $wdas --spp 64 --device cuda -o "$out/v.exr" 2>&1 | tail -1)
        t=$(sub "$(now)" "$t0")
        echo "variant $v: wdas-dense 64 spp $t s whole process; $line"
        if awk -v a="$t" -v b="$best_t" 'BEGIN { exit !(a < b) }' && echo "$line" | grep -q "64 spp"; then
            best="$v"; best_t=$t
        fi
    done
    br="$best"
    echo "== fastest: $br ($best_t s); it renders everything below"
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
check velocity-fire 256 tests/gpu/velocity-fire.json --set "media.0.density.file=$data/fire-vel.nvdb"
check cycles-fire 256 tests/gpu/cycles-fire.json --set "media.0.density.file=$data/fire-vel.nvdb"
check pbrt-media 128 scenes/pbrt-media.pbrt --width 160 --height 100

# The job system on the GPU: an interrupted and resumed render is the uninterrupted one, byte
# for byte; a sequence; the live view.
echo "== checkpoint, Ctrl-C, resume (wdas-dense, 256 spp, as checked above)"
rm -f "$out/ck.brume"
# a signal during start-up (the device's context, the upload) leaves nothing to keep: then
# again with twice the wait
for wait_s in 3 6 12; do
    timeout 100 "$br" render $wdas --spp 256 --seed 12 --aov variance --device cuda --checkpoint "$out/ck.brume" \
        -o "$out/ck.exr" 2>"$out/ck.err" &
    pid=$!
    sleep $wait_s
    kill -INT $pid
    wait $pid
    rc=$?
    echo "interrupted after $wait_s s: exit status $rc (130 expected), checkpoint $(stat -c %s "$out/ck.brume" 2>/dev/null || echo missing) bytes; $(tail -1 "$out/ck.err")"
    [ -s "$out/ck.brume" ] && break
done
timeout 100 "$br" render $wdas --spp 256 --seed 12 --aov variance --device cuda --resume "$out/ck.brume" \
    -o "$out/ck.exr" 2>&1 | tail -1
if cmp -s "$out/ck.exr" "$out/wdas-dense-gpu.exr"; then
    echo "resumed: byte-identical to the uninterrupted render"
else
    echo "resumed: DIFFERS from the uninterrupted render"; fail=1
fi
echo "== a sequence of three frames"
timeout 100 "$br" render scenes/anim-blasi-cloud.json --set render.method=path --frames 0-2 --spp 16 --width 128 \
    --height 96 --device cuda -o "$out/seq_%d.png" 2>&1 | tail -1
for f in 0 1 2; do [ -s "$out/seq_$f.png" ] || { echo "frame $f missing"; fail=1; }; done
echo "== a sequence of grid files with velocity, the next frame read ahead"
mkdir -p "$out/fireseq"
cp scenes/fire-velocity.json "$out/fireseq/"
"$br" gen fire --resolution 48 --velocity 4 --frames 1-3 -o "$out/fireseq/fire_%04d.nvdb" > /dev/null
timeout 100 "$br" render "$out/fireseq/fire-velocity.json" --frames 1-3 --spp 16 --width 96 --height 120 \
    --device cuda --stats -o "$out/fireseq/f_%d.png" 2>&1 | grep -E "read ahead|f_3" | head -3
for f in 1 2 3; do [ -s "$out/fireseq/f_$f.png" ] || { echo "fire frame $f missing"; fail=1; }; done
echo "== the live view"
if command -v curl >/dev/null; then
    timeout 100 "$br" render $wdas --spp 512 --device cuda --serve 127.0.0.1:8765 --serve-exit -o "$out/serve.png" \
        2>/dev/null &
    pid=$!
    sleep 3
    page=$(curl -s http://127.0.0.1:8765/ | head -c 2000)
    kill -INT $pid 2>/dev/null
    wait $pid
    if echo "$page" | grep -qi "<html"; then echo "live view: the page is served during a GPU render"; else echo "live view: NO page"; fail=1; fi
else
    echo "live view: no curl on this machine, not checked"
fi

# 3. and 4.: the timings (bench/gpu.sh)
[ "${CHECKS_ONLY:-0}" = 1 ] || sh bench/gpu.sh "$br" "$out" "$data"

echo "== result: $([ $fail = 0 ] && echo PASS || echo FAIL)"
exit $fail
