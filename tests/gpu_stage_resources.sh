#!/bin/sh
# gpu_stage_resources.sh - the single-precision stage kernels (src/gpu/stages.cu) within
# their budgets on sm_90 (docs/gpu.md, "Single precision"): brume_flight_f and
# brume_shadow_f at most 96 registers, no stack frame and no spills, no FP64 arithmetic
# instruction and no f32-f64 conversion in their PTX; every kernel of the PTX at most 128
# registers and 64 KiB of SASS. The figures are bench/gpu_resources.sh's (ptxas -v, readelf,
# its PTX counts): one implementation. Without ptxas the test is skipped (77), except under
# CI=true, where a missing ptxas fails it.
#   gpu_stage_resources.sh PTX SOURCE_DIR
set -u
ptx=$1
src=$2
ptxas=${PTXAS:-$(command -v ptxas || ls /usr/local/cuda/bin/ptxas 2>/dev/null | head -1)}
if [ -z "$ptxas" ] || [ ! -x "$ptxas" ]; then
    if [ "${CI:-}" = true ]; then
        echo "gpu_stage_resources: no ptxas (CUDA's compiler tools), and CI=true needs it" >&2
        exit 1
    fi
    echo "gpu_stage_resources: skipped: no ptxas (CUDA's compiler tools; /usr/local/cuda/bin or \$PTXAS)"
    exit 77
fi
out=$(PTXAS=$ptxas sh "$src/bench/gpu_resources.sh" "$ptx" sm_90) || {
    echo "$out" >&2
    echo "gpu_stage_resources: bench/gpu_resources.sh failed on $ptx" >&2
    exit 1
}
echo "$out"
# kernel | registers | stack frame B | cumulative stack B | spill stores B | spill loads B | SASS KiB |
# SASS instructions | FP64 | FP32 | f32-f64 conversions | PTX instructions | device functions reached
echo "$out" | awk -F' [|] ' '
    $1 ~ /^brume_/ {
        n++
        name = $1; regs = $2; stack = $3; st = $5; ld = $6; sass = $7; f64 = $9; f32 = $10; cvt = $11
        if (regs !~ /^[0-9]+$/ || regs > 128) { print name ": " regs " registers, over 128"; bad = 1 }
        if (sass + 0 > 64) { print name ": " sass " KiB of SASS, over 64"; bad = 1 }
        if (name == "brume_flight_f" || name == "brume_shadow_f") {
            stages++
            if (regs > 96) { print name ": " regs " registers, over 96"; bad = 1 }
            if (stack != 0 || st != 0 || ld != 0) {
                print name ": stack frame " stack " B, spills " st " B stored, " ld " B loaded: must be 0"; bad = 1
            }
            if (f64 != 0 || cvt != 0) {
                print name ": " f64 " FP64 instructions, " cvt " f32-f64 conversions: must be 0"; bad = 1
            }
            if (f32 < 100) { print name ": only " f32 " FP32 instructions: the count proves nothing"; bad = 1 }
        }
    }
    END {
        if (stages != 2) { print "gpu_stage_resources: brume_flight_f and brume_shadow_f not both in the report"; bad = 1 }
        exit bad
    }' >&2 || exit 1
echo "gpu_stage_resources: brume_flight_f and brume_shadow_f within budget"
