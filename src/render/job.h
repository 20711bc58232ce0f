/* job.h - the render job behind brume_render_job: per-pixel accumulation state, passes,
 * adaptive sampling (job/render.c), and its checkpoint file (job/checkpoint.c).
 *
 * Invariants (docs/render-jobs.md):
 * - Pixel p's samples are numbered 0, 1, ... in the order they were taken; sample i draws
 *   the random numbers of (seed, p, i). The sums are accumulated in that order in double,
 *   so any split of the samples into passes (or into a run, a checkpoint and a resume)
 *   gives the same bits.
 * - A pixel is written by one tile task at a time. Its stored state changes only under
 *   `lock`, a whole tile at once: a reader holding the lock (job_image, a checkpoint) sees
 *   every finished tile and nothing half done.
 * - A pass brings every active pixel to `target` samples. Pixels already there take none,
 *   so a pass that was cut (cancelled, out of time) is completed by running it again.
 *   Adaptive decisions happen only when a pass completes, from each pixel's own sums. */
#ifndef BRUME_RENDER_JOB_H
#define BRUME_RENDER_JOB_H

#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>

#include "core/progress.h"
#include "core/stats.h"
#include "render/integrator.h"

#define JOB_TILE 16 /* pixels per tile edge: the unit of work of a thread, and of MPI parts */
#define JOB_SUMS 4 /* per pixel: R, G, B, alpha (sum over the first JOB_ALPHA_SAMPLES) */
#define JOB_SQS 4  /* per pixel: R^2, G^2, B^2, y^2 with y = (R + G + B) / 3 */
#define JOB_AOVS 8 /* per pixel: depth sum, depth hits, albedo RGB, normal XYZ */
#define JOB_ALPHA_SAMPLES 8 /* camera samples per pixel that estimate alpha */

struct brume_render_job {
    const brume_scene *s;
    brume_render_settings rs; /* the scene's, copied at begin */
    integrator_kind kind;
    const void *state; /* integrator_prepare's */
    int tiles_x;
    size_t ntiles_all;  /* tiles of the whole image */
    size_t ntiles;      /* tiles of this job's part */
    int part, nparts;   /* the job renders tiles part, part + nparts, ... */
    size_t npix;        /* width * height */
    size_t npart;       /* pixels of this job's part */
    bool trace_aovs;    /* depth, albedo or normal asked: one extra first-vertex walk a sample */

    /* per pixel (npix each; aov only when trace_aovs) */
    uint32_t *n;      /* samples taken */
    uint8_t *active;  /* 1: still receives samples; 0: stopped by adaptive sampling */
    double *sum;      /* JOB_SUMS per pixel */
    double *sq;       /* JOB_SQS per pixel, or NULL when the job keeps no squares */
    double *aov;      /* JOB_AOVS per pixel */

    int spp_done;     /* samples of every active pixel at the last completed pass */
    int target;       /* samples every active pixel reaches at the end of the pass in progress */
    double noise;     /* at the last completed pass: largest relative error on signal pixels */
    uint64_t done;    /* pixel samples taken */
    uint64_t total;   /* estimate of the pixel samples the whole job takes */
    double elapsed;   /* seconds spent in passes before the current one, across resumes */
    double elapsed_saved; /* of elapsed, the seconds the checkpoint this job resumed had spent
                             (0 for a new job): reported, never charged to this run's time
                             budget (a resumed job takes another budget) */
    double t_pass;    /* progress_now() when the current pass started, 0 outside passes */
    bool out_of_time; /* the time budget ran out */
    double prep_seconds;   /* the integrator's preparation at job_create: part of a time budget */
    double sample_seconds; /* wall seconds per pixel sample in the last pass that took any */
    double *tile_cost;     /* per tile of the part: thread-seconds per sample in the last pass
                              that took samples there, 0 before (the ETA weighs the samples a
                              pixel still needs by its tile's cost) */
    double pass_cost;      /* thread-seconds of the tiles of the pass under way */
    double wall_per_cost;  /* the last pass's wall seconds per thread-second of its tiles */
    double left_cost;      /* at the last job_refresh: thread-seconds the samples left take at
                              their tiles' costs, 0 when no tile's cost is known */
    uint64_t left_samples; /* at the last job_refresh: total - done */
    double pass_model;     /* wall seconds the cost model (left_cost's) gave the pass under way at
                              its start, 0 when it had no costs */
    double model_wall, model_given; /* over the passes it priced, each pass's weight halved at the
                              next: their wall seconds and what the model gave them (the
                              ratio corrects the ETA) */

    void *gpu;        /* render.device >= 0: the GPU's gpu_pass for the job (gpu/cuda.h) */

    pthread_mutex_t lock; /* the per-pixel state, done, total, noise, elapsed */
    pthread_mutex_t cb_lock; /* serialises the progress callback */
    atomic_bool stop;        /* set when the callback cancels or time runs out */
    bool cancelled;          /* the callback cancelled the pass in progress (under cb_lock) */
    progress_meter meter;    /* what brume_render_job_progress showed (under lock) */
    double t_start;          /* stats_now() at job_create: the statistics' seconds */
    int nthreads;            /* threads the pool runs */
    struct stats_counters *counters; /* one per thread when rs.stats, else NULL */
    uint64_t collision_bound;        /* a sample's tentative collisions at most (render/watch.h) */
    atomic_ullong samples_cut;       /* samples that reached it */
    uint64_t samples_nonfinite;      /* samples whose estimate was NaN or infinite, added as 0 (under lock) */
    atomic_llong next_poll_ns;       /* CLOCK_MONOTONIC time of the next progress call within a tile */
};

/* Allocates a job for tiles part, part + nparts, ... of the scene's image, with the
 * integrator state prepared; fails with err_set(). squares: keep the squared samples,
 * which serve the per-pixel error (adaptive sampling, progress, checkpoints) and the
 * variance layer only. */
brume_status job_create(const brume_scene *s, int part, int nparts, bool squares, brume_render_job **out);

/* Relative standard error of pixel i's mean as adaptive sampling sees it (docs/render-jobs.md). */
double job_pixel_error(const brume_render_job *job, size_t i);

/* Recomputes done, total, noise and the cost of the samples left from the per-pixel state
 * (at pass boundaries, after a resume). */
void job_refresh(brume_render_job *job);

#endif
