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
#include "render/job.h"

/* The PTX embedded at build time (a NUL-terminated text), or "" when the build had no
 * clang to make it (BRUME_CUDA=OFF). */
extern const char gpu_ptx[];

/* Renders job's pass on GPU job->rs.device: samples n[i] .. job->target - 1 of every active
 * pixel of the job's part, added to the job's sums in each sample's order. The scene is
 * uploaded at the first pass of a job and kept for its later passes (gpu_job_release).
 * BRUME_OK, or an error naming the scene and what failed (no driver, a refused feature
 * (gpu/device_scene.h), device memory over render.max_memory_mb or the GPU's). */
brume_status gpu_job_pass(brume_render_job *job);
/* What gpu_job_pass does first for a job, done now: opens the device (the driver compiles
 * the PTX on a machine's first run, about 20 s) and uploads the scene. The job calls it
 * before it starts timing its first pass, so that the pass's measured cost, and the ETA
 * and budgets made from it, are the GPU's rendering alone. Idempotent. */
brume_status gpu_job_prepare(brume_render_job *job);
/* Frees what gpu_job_pass kept for job on the device. */
void gpu_job_release(brume_render_job *job);

#endif
