/* stages.cu - the estimator's flight and shadow stages as GPU kernels in single precision
 * (docs/gpu.md, "Single precision"), over queues of path states (gpu/stages.h), for the
 * specialised shape of render/track_float.h: one medium, a trilinear dense grid.
 *
 * The stage functions are the CPU's own (render/track_float.h instantiates render/
 * track_body.h, track_loop.h, track_steps.h and flight_body.h in float), and this unit
 * includes headers only: what a kernel runs is what the CPU's tests run in float
 * (tests/test_float_stages.c). Voxel and majorant-cell loads take the read-only path
 * (GRID_LOAD: __ldg, ld.global.nc). Compiled like kernel.cu (clang, no CUDA SDK) to
 * build/stages.ptx; ctest gpu.stage_resources holds its kernels to their register, stack,
 * SASS and FP64 budgets with ptxas. Nothing launches them yet. */
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#define __global__ __attribute__((global))
#define __device__ __attribute__((device))
#include <__clang_cuda_builtin_vars.h>

/* the stage kernels' sequences are a hash of key and counter alone (core/rng.h) */
#define RNG_HASH_ONLY 1
/* voxels and majorant cells through the read-only data path, indexed in 32 bits (the float
 * view holds fewer than 2^32 voxels: density_float_view) */
#define GRID_INDEX uint32_t
#define GRID_LOAD(p) __nvvm_ldg_f(p)

/* At most 96 registers a thread (ctest gpu.stage_resources): 128-thread blocks, 5 of them
 * resident on an SM of 65,536 registers, leave ptxas 102, rounded down to 96. */
#define STAGE_BOUNDS __attribute__((launch_bounds(128, 5)))

namespace {
#pragma clang force_cuda_host_device begin
#include "gpu/devmath_names.h"
#include "render/track_float.h"
#include "gpu/stages.h"
#pragma clang force_cuda_host_device end

__device__ static inline __attribute__((always_inline)) rayf stage_ray(const stage_queue *q, uint32_t i)
{
    return (rayf){v3f(q->o[0][i], q->o[1][i], q->o[2][i]), v3f(q->d[0][i], q->d[1][i], q->d[2][i]), 0.0f};
}

__device__ static inline __attribute__((always_inline)) rng stage_rng(const stage_queue *q, uint32_t i)
{
    return (rng){q->rng_key[i], q->rng_counter[i], 0, 0, 0, 0, 0};
}
} /* namespace */

/* One free flight per entry (flight_runf): its transmittance, emission, and where it
 * scatters with what throughput. The flight's reservoir and its tracking draw from the
 * entry's one sequence. */
extern "C" __global__ STAGE_BOUNDS void brume_flight_f(const scenef *s, const stage_queue q)
{
    const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= q.n)
        return;
    rng g = stage_rng(&q, i);
    flightf f;
    f.s = s;
    f.g = &g;
    f.tail_Tr = (float)FLIGHT_TAIL_TR;
    f.absent = 0;
    for (int c = 0; c < BRUME_NSAMPLES; c++) {
        f.beta.c[c] = q.beta[c][i];
        f.L.c[c] = q.L[c][i];
    }
    const bool scattered = flight_runf(&f, stage_ray(&q, i), q.tmax[i], &g);
    for (int c = 0; c < BRUME_NSAMPLES; c++) {
        q.L[c][i] = f.L.c[c];
        q.Tr[c][i] = f.Tr.c[c];
        q.beta_s[c][i] = scattered ? f.beta_s.c[c] : 0.0f;
    }
    q.t[i] = scattered ? f.t : -1.0f;
    q.rng_counter[i] = g.counter;
}

/* One shadow ray per entry (track_transmittancef): residual ratio tracking's estimate. */
extern "C" __global__ STAGE_BOUNDS void brume_shadow_f(const scenef *s, const stage_queue q)
{
    const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= q.n)
        return;
    rng g = stage_rng(&q, i);
    const colorf T = track_transmittancef(s, 0, stage_ray(&q, i), q.tmax[i], &g);
    for (int c = 0; c < BRUME_NSAMPLES; c++)
        q.Tr[c][i] = T.c[c];
    q.rng_counter[i] = g.counter;
}
