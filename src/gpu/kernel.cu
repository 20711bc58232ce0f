/* kernel.cu - the path tracer compiled for NVIDIA GPUs from the CPU's own source.
 *
 * This translation unit is compiled only for the device (clang -x cuda --cuda-device-only,
 * no CUDA SDK: gpu/README in docs/gpu.md) into PTX, which libbrume embeds and loads through
 * the CUDA driver at run time (gpu/cuda.c). It includes the estimator's C files themselves,
 * inside `#pragma clang force_cuda_host_device`, so the device runs the same functions as
 * the CPU: a change to the estimator changes both. Everything is in an anonymous
 * namespace: only what the kernel reaches is emitted for the device, so the files'
 * construction code (malloc, files, messages) is parsed but never compiled for it.
 *
 * What the device lacks is supplied before the estimator: libm (gpu/devmath.h, tested on
 * the CPU). The solid objects' queries traverse brume's own hierarchy (core/bvh.h), Embree
 * being the CPU's alone. */
#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <stdio.h>
#include <errno.h>
#include <pthread.h>
#include <time.h>
#include <stdatomic.h>

/* No CUDA SDK: the few attributes and built-in variables come from clang itself. */
#define __global__ __attribute__((global))
#define __device__ __attribute__((device))
#define __host__ __attribute__((host))
#define __constant__ __attribute__((constant))
#define __shared__ __attribute__((shared))
#include <__clang_cuda_builtin_vars.h>

/* C converts malloc's void * implicitly, C++ does not: the construction code this unit
 * parses (and never compiles for the device) keeps its C form through this wrapper. */
struct c_alloc {
    void *p;
    template <class T> operator T *() const { return (T *)p; }
};
#define malloc(n) (c_alloc{malloc(n)})
#define calloc(n, m) (c_alloc{calloc(n, m)})
#define realloc(q, n) (c_alloc{realloc(q, n)})
#define aligned_alloc(a, n) (c_alloc{aligned_alloc(a, n)})

/* The blackbody table (medium/blackbody.c), filled by the host when a scene is uploaded. */
extern "C" __device__ double brume_device_blackbody[3 * 1024];

namespace {
/* Host-only declarations: variadic messages, the CPU-only methods. */
#include "core/error.h"

#pragma clang force_cuda_host_device begin
#include "gpu/devmath_names.h"
#include "scene/scene.h"
#include "render/integrator.h"
#include "render/track.h"
#include "render/film.h"
#include "core/stats.h"
#include "render/sample.h"
#pragma clang force_cuda_host_device end

#include "render/blasi.h"
#include "render/stam.h"
#include "method/path_options.h"


#pragma clang force_cuda_host_device begin
#include "core/sampling.c"
#include "core/sobol.c"
#include "core/xform.c"
#include "core/motion.c"
#include "core/distrib.c"
#include "density/dda.c"
#include "density/density.c"
#include "density/density_kinds.c"
#include "density/dense_grid.c"
#include "density/nanovdb.c"
#include "density/blobs.c"
#include "density/pbrt_cloud.c"
#include "medium/blackbody.c"
#include "medium/medium.c"
#include "medium/medium_eval.c"
#include "phase/phase.c"
#include "surface/material.c"
#include "surface/bsdf_microfacet.c"
#include "surface/bsdf_dielectric.c"
#include "surface/bsdf_coated.c"
#include "surface/surface_query.c"
#include "scene/camera.c"
#include "render/film.c"
#include "scene/light.c"
#include "scene/background.c"
#include "render/track.c"
#include "render/flight.c"
#include "render/path_state.c"
#include "render/path.c"
#include "render/first_vertex.c"
#include "render/integrator.c"
#pragma clang force_cuda_host_device end
} /* namespace */

/* ---- the kernels -------------------------------------------------------------------------- *
 * A pass (render/pass.h) adds samples n[p] .. target - 1 to each pixel pixels[p] of its
 * list, its count n[p] and sums at place p, in launches of per_pixel samples a pixel:
 * sample t of a launch is sample t % per_pixel of listed pixel t / per_pixel. brume_paths
 * evaluates the samples into their own slots of `values`; brume_reduce then adds each
 * pixel's samples in their order into its sums, one thread a pixel, and counts those whose
 * estimate was NaN or infinite. The sums are thus made in a fixed order, whatever the
 * scheduling: the image is a function of scene, seed and samples on one GPU, run after run.
 *
 * brume_paths runs `path` and `single` with path regeneration (Novak et al. 2010): each
 * thread takes the next sample of the launch (a counter in device memory) and runs its walk
 * one event per turn of its loop (render/path.c, path_walk_step); when the walk ends, it
 * writes the value and takes the next sample at once. A warp thus keeps its threads busy
 * while its longest path goes on, instead of waiting for it with the others idle (measured
 * against one sample per thread, start to end: docs/gpu.md, "Speed"). Each sample is a
 * function of its index alone and goes to its own slot: the order in which threads take
 * them changes nothing. */
extern "C" __global__ void brume_paths(const brume_scene *s, const void *state, const sample_params *sp,
                                       const uint32_t *pixels, uint32_t npixels, const uint32_t *n, uint32_t target,
                                       uint32_t per_pixel, sample_value *values, uint32_t *next)
{
    const uint32_t total = npixels * per_pixel;
    const int max_depth = sp->kind == INTEGRATOR_PATH ? s->settings.max_depth : 1;
    path_walk w;
    rng g;
    color T;
    bool opaque = false, live = false;
    uint32_t t = 0;
    for (;;) {
        if (live) {
            if (path_walk_step(&w))
                continue;
            sample_set(&values[t], sp, path_walk_end(&w), opaque, T);
            live = false;
        }
        t = (uint32_t)__nvvm_atom_add_gen_i((int *)next, 1);
        if (t >= total)
            return;
        uint32_t p = t / per_pixel, k = t % per_pixel;
        uint32_t i = pixels[p], sidx = n[p] + k;
        if (sidx >= target)
            continue;
        int x = (int)(i % (uint32_t)sp->width), y = (int)(i / (uint32_t)sp->width);
        ray r;
        sample_camera(&s->cam, sp, i, x, y, sidx, &g, &r);
        sample_aovs(s, sp, r, g, &values[t]);
        T = col(1.0);
        opaque = false;
        live = path_walk_begin(&w, s, state, r, max_depth, &g, &opaque, sidx < JOB_ALPHA_SAMPLES ? &T : NULL);
        if (!live)
            sample_set(&values[t], sp, path_walk_end(&w), opaque, T);
    }
}

extern "C" __global__ void brume_reduce(const sample_params *sp, uint32_t npixels, uint32_t *n, uint32_t target,
                                        uint32_t per_pixel, const sample_value *values, double *sum, double *sq,
                                        double *aov, unsigned long long *nonfinite)
{
    uint32_t p = blockIdx.x * blockDim.x + threadIdx.x;
    if (p >= npixels)
        return;
    long long bad = 0;
    for (uint32_t k = 0; k < per_pixel && n[p] + k < target; k++) {
        const sample_value *v = &values[(uint64_t)p * per_pixel + k];
        sample_add(sp, v, n[p] + k, sum + (size_t)JOB_SUMS * p, sq ? sq + (size_t)JOB_SQS * p : NULL,
                   aov ? aov + (size_t)JOB_AOVS * p : NULL);
        bad += v->nonfinite;
    }
    if (bad)
        __nvvm_atom_add_gen_ll((long long *)nonfinite, bad);
    if (n[p] < target)
        n[p] = target;
}
