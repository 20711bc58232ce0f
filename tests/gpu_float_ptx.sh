#!/bin/sh
# gpu_float_ptx.sh - the single-precision device math (gpu/devmath.h, devmath_expf ...)
# compiles for the GPU to no FP64 instruction: a kernel that calls each float function is
# compiled to PTX as kernel.cu is, and any arithmetic of type f64 in it fails the test.
#   gpu_float_ptx.sh CLANG SOURCE_DIR
set -eu
clang=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cat >"$tmp/f.cu" <<'CU'
#include <stdint.h>
#define __global__ __attribute__((global))
#pragma clang force_cuda_host_device begin
#include "gpu/devmath.h"
#pragma clang force_cuda_host_device end
extern "C" __global__ void float_math(const float *in, float *out)
{
    float x = in[0], y = in[1];
    out[0] = devmath_expf(x);
    out[1] = devmath_logf(y);
    out[2] = devmath_powf(x, y);
    out[3] = devmath_sinf(x);
    out[4] = devmath_cosf(y);
    out[5] = devmath_tanf(x);
    out[6] = devmath_log1pf(x);
    out[7] = devmath_atan2f(x, y);
    out[8] = devmath_acosf(x);
    out[9] = devmath_cbrtf(y);
    out[10] = devmath_nextafterf(x, y);
}
CU
"$clang" -x cuda --cuda-device-only -nocudainc -nocudalib --cuda-gpu-arch=sm_70 -O3 -std=c++17 \
    -Wno-unknown-cuda-version -I"$src/src" -S -o "$tmp/f.ptx" "$tmp/f.cu"
f32=$(grep -cE '^[[:space:]]*[a-z]+(\.[a-z0-9]+)*\.f32' "$tmp/f.ptx" || true)
f64=$(grep -cE '^[[:space:]]*[a-z]+(\.[a-z0-9]+)*\.f64' "$tmp/f.ptx" || true)
echo "float device math in PTX: $f32 f32 instructions, $f64 f64 instructions"
if [ "$f32" -lt 100 ]; then
    echo "gpu_float_ptx: the kernel compiled to almost no float arithmetic: the check would prove nothing" >&2
    exit 1
fi
if [ "$f64" -ne 0 ]; then
    grep -nE '^[[:space:]]*[a-z]+(\.[a-z0-9]+)*\.f64' "$tmp/f.ptx" | head -5 >&2
    exit 1
fi
