/* pass.h - a pass: "render these samples of these pixels into these sums".
 *
 * The one interface between a render job (job/render.c: budgets, adaptive sampling,
 * checkpoints, live view, sequences, MPI parts) and a device that renders samples: the
 * CPU's tiles (pass_render_cpu, render/pass.c, one call a tile on a pool thread) and the
 * GPU (gpu_pass_render, gpu/cuda.h, one call a pass). The job lists the pixels and hands
 * over their counts and sums in list order; the device adds samples n[j] .. target - 1 of
 * pixel pixels[j] to them, each sample drawing the numbers of (seed, pixel, sample index)
 * and added in sample order, so the bits do not depend on the device's scheduling, the
 * split into passes, or the thread count. Neither side sees the other's structures. */
#ifndef BRUME_RENDER_PASS_H
#define BRUME_RENDER_PASS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "render/sample.h"

typedef struct render_pass {
    /* the render: the same for every pass of a job */
    const struct brume_scene *s;
    const void *state;      /* integrator_prepare's */
    sample_params sp;       /* sp.squares: sq is kept; sp.trace_aovs: aov is kept */
    /* the pass: samples n[j] .. target - 1 of pixel pixels[j], for j < npixels */
    const uint32_t *pixels; /* image indices, y * width + x */
    size_t npixels;
    uint32_t target;
    uint32_t *n;                 /* per listed pixel: the samples it holds; raised as they are added */
    double (*sum)[JOB_SUMS];     /* per listed pixel (sample_add) */
    double (*sq)[JOB_SQS];       /* per listed pixel, or NULL without sp.squares */
    double (*aov)[JOB_AOVS];     /* per listed pixel, or NULL without sp.trace_aovs */
    /* asked when set, before each sample on the CPU and after each launch on the GPU; true
     * ends the pass there (a time budget, a stop), the pixels keeping the samples they took */
    bool (*cut)(void *user);
    void *user;
    /* out, added to by the device */
    uint64_t taken;     /* samples added */
    uint64_t nonfinite; /* of them, those whose estimate was NaN or infinite: each added 0 */
} render_pass;

/* Renders pass p on the calling thread (a CPU tile): every listed pixel from n[j] to target,
 * in batches of camera rays, each sample watched by this thread's watch_tls when set
 * (render/watch.h: a sample the watch stops is discarded; one it cuts is counted there). */
void pass_render_cpu(render_pass *p);

#endif
