/* cuda.h - NVIDIA GPUs through the CUDA driver API, opened at run time.
 *
 * brume links no CUDA library: libcuda.so.1 (the driver's) is opened with dlopen when a
 * GPU is first asked for, and the few entry points used are declared here (gpu/cuda.c),
 * as Cycles' CUEW does. The kernels are PTX that clang made at build time from
 * gpu/kernel.cu, embedded in libbrume (gpu_ptx, generated); the driver compiles it for the
 * GPU at hand when the module loads. Without a driver or a GPU every call fails with one
 * line saying why, and the CPU path is unchanged. */
#ifndef BRUME_GPU_CUDA_H
#define BRUME_GPU_CUDA_H

#include <stddef.h>

#include "brume.h"
#include "render/pass.h"

/* The PTX embedded at build time (a NUL-terminated text), or "" when the build had no
 * clang to make it (BRUME_CUDA=OFF). */
extern const char gpu_ptx[];

/* What a GPU keeps for a render job: the device, the scene's copy, the samples' parameters
 * and room for the pass's pixels. */
typedef struct gpu_pass gpu_pass;

/* Opens GPU `device` for passes shaped like `shape` (its scene, integrator state and
 * sample parameters; its pixels are not read), of at most max_pixels pixels: the driver
 * compiles the PTX on a machine's first run (about 20 s) and the scene is uploaded. The
 * job calls it before it starts timing its first pass, so that the pass's measured cost,
 * and the ETA and budgets made from it, are the GPU's rendering alone. BRUME_OK with *out
 * set, or an error naming the scene and what failed (no driver, a refused feature
 * (gpu/device_scene.h), device memory over render.max_memory_mb or the GPU's). */
brume_status gpu_pass_open(const render_pass *shape, int device, size_t max_pixels, gpu_pass **out);
/* Renders pass p (render/pass.h) on g's device: samples n[j] .. target - 1 of every listed
 * pixel, added to its sums in each sample's order; p->taken and p->nonfinite are added to.
 * The pass shares the scene, state and parameters g was opened with, and has at most its
 * max_pixels pixels. It runs in launches of about 0.1 s (from the last launch's time per
 * sample), and p->cut is asked after each: a cut pass leaves each pixel with the samples its
 * launches added. */
brume_status gpu_pass_render(gpu_pass *g, render_pass *p);
/* Frees what g keeps on the device, and g; nothing for NULL. */
void gpu_pass_close(gpu_pass *g);

#endif
