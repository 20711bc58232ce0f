/* render.c - render jobs: tiles over the thread pool, passes of samples accumulated per
 * pixel, budgets (samples, time, noise) with adaptive sampling, the image and its layers;
 * brume_render and brume_render_part are one job run to its end (render/job.h states the
 * invariants, docs/render-jobs.md the estimator and the schedule). */
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/bigmem.h"
#include "core/cancel.h"
#include "core/context.h"
#include "core/error.h"
#include "core/pool.h"
#include "core/stats.h"
#include "image/image.h"
#include "io/atomic.h"
#include "render/blasi.h"
#include "render/film.h"
#include "render/job.h"
#include "render/pass.h"
#include "render/watch.h"
#include "gpu/cuda.h"
#include "job/eta.h"
#include "job/render_impl.h"

#define TILE JOB_TILE
#define PASS_MAX 16 /* samples per pixel in one pass at most: a tile stays short, so a
                       cancellation or the end of a time budget takes effect soon */
#define GPU_PASS_SAMPLES (1 << 21) /* samples a GPU pass takes at least after the first: each
                                      launch ends with its longest paths running alone, a cost
                                      that small passes pay again and again (docs/gpu.md), while
                                      a pass this size takes well under a second */
#define PASS_SHORT_REST 1.0 /* seconds: a fixed count whose remaining samples the last pass's cost
                               predicts to take less than this ends in one pass (job_next_pass) */
#define NOISE_PASSES ((progress_passes){4, PASS_MAX}) /* a noise target's passes (job_next_pass) */
#define NOISE_FLOOR 1e-3 /* radiance below which a pixel's mean no longer scales its error:
                            pixels darker than this carry no signal (docs/render-jobs.md) */

/* scene_prepared's finish: the scene releases what the renderer prepared. */
static void prepared_finish(int kind, void *state) { integrator_finish((integrator_kind)kind, state); }

/* The integrator state for s, prepared at the scene's first render and kept with it. */
static brume_status prepared_state(const brume_scene *s, integrator_kind kind, const void **state)
{
    scene_prepared *p = s->prepared;
    if (p->valid && p->kind != (int)kind) {
        integrator_finish((integrator_kind)p->kind, p->state);
        p->valid = false;
    }
    if (!p->valid) {
        void *st = NULL;
        brume_status r = integrator_prepare(kind, s, &st);
        if (r != BRUME_OK)
            return r;
        p->valid = true;
        p->kind = (int)kind;
        p->state = st;
        p->finish = prepared_finish;
    }
    *state = p->state;
    return BRUME_OK;
}

/* ---- the job ------------------------------------------------------------------------------ */

/* The pixel rectangle [x0, x1) x [y0, y1) of the job's task-th tile. */
static void tile_rect(const brume_render_job *job, size_t task, int *x0, int *y0, int *x1, int *y1)
{
    size_t tile = task * (size_t)job->nparts + (size_t)job->part;
    int tx = (int)(tile % (size_t)job->tiles_x), ty = (int)(tile / (size_t)job->tiles_x);
    *x0 = tx * TILE;
    *y0 = ty * TILE;
    *x1 = *x0 + TILE < job->rs.width ? *x0 + TILE : job->rs.width;
    *y1 = *y0 + TILE < job->rs.height ? *y0 + TILE : job->rs.height;
}

/* The job's tiles (this part's of nparts, round robin) and pixels, from its settings. */
static void job_layout(brume_render_job *job)
{
    const brume_render_settings *rs = &job->rs;
    job->tiles_x = (rs->width + TILE - 1) / TILE;
    job->ntiles_all = (size_t)job->tiles_x * (size_t)((rs->height + TILE - 1) / TILE);
    job->ntiles = job->ntiles_all / (size_t)job->nparts + ((size_t)job->part < job->ntiles_all % (size_t)job->nparts);
    job->npix = (size_t)rs->width * (size_t)rs->height;
    job->npart = 0;
    for (size_t t = 0; t < job->ntiles; t++) {
        int x0, y0, x1, y1;
        tile_rect(job, t, &x0, &y0, &x1, &y1);
        job->npart += (size_t)(x1 - x0) * (size_t)(y1 - y0);
    }
}

brume_status job_create(const brume_scene *s, int part, int nparts, bool squares, brume_render_job **out)
{
    *out = NULL;
    if (!s->committed)
        return err_set(BRUME_ERROR_STATE, "%s: render before brume_scene_commit", s->source);
    integrator_kind kind = (integrator_kind)s->settings.method; /* one enum (method/method_name.c) */
    brume_render_job *job = calloc(1, sizeof *job);
    if (!job)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory for a render job", s->source);
    job->s = s;
    job->rs = s->settings;
    job->kind = kind;
    job->part = part;
    job->nparts = nparts;
    const brume_render_settings *rs = &job->rs;
    job_layout(job);
    job->trace_aovs = (rs->aovs & (BRUME_AOV_DEPTH | BRUME_AOV_ALBEDO | BRUME_AOV_NORMAL)) != 0;
    job->t_start = stats_now();
    job->nthreads = rs->threads > 0 ? rs->threads : pool_default_threads();
    /* The film and the image made from it count against render.max_memory_mb, after what
     * reading the scene took: per pixel its count, flag and sums, and the RGBA
     * image with its layers (depth 1, albedo 3, normal 3 floats). */
    uint64_t doubles = JOB_SUMS + (squares ? JOB_SQS : 0u) + (job->trace_aovs ? JOB_AOVS : 0u);
    uint64_t floats = 4u + (job->trace_aovs ? 7u : 0u);
    uint64_t per_pixel = sizeof *job->n + 1u + doubles * sizeof(double) + floats * sizeof(float);
    uint64_t film_bytes = per_pixel * (uint64_t)job->npix;
    size_t left = s->max_memory > s->memory_used ? s->max_memory - s->memory_used : 0;
    if (film_bytes > left) {
        int w = rs->width, h = rs->height;
        free(job);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY,
                       "%s: render.max_memory_mb: a %d x %d render needs %llu bytes for its film and image, over the "
                       "%zu left of the limit of %zu (the scene took %zu)",
                       s->source, w, h, (unsigned long long)film_bytes, left, s->max_memory, s->memory_used);
    }
    if (rs->stats && !(job->counters = calloc((size_t)job->nthreads, sizeof *job->counters))) {
        free(job);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory for statistics", s->source);
    }
    /* the film in huge pages where it is large (core/bigmem.h: 4 KiB page faults cost the
     * project's VM more than a 400 x 400 Blasi view pass) */
    job->n = bigmem_calloc(job->npix, sizeof *job->n);
    job->active = malloc(job->npix);
    job->sum = bigmem_calloc(job->npix * JOB_SUMS, sizeof *job->sum);
    job->sq = squares ? bigmem_calloc(job->npix * JOB_SQS, sizeof *job->sq) : NULL;
    job->aov = job->trace_aovs ? bigmem_calloc(job->npix * JOB_AOVS, sizeof *job->aov) : NULL;
    job->tile_cost = calloc(job->ntiles, sizeof *job->tile_cost);
    progress_meter_init(&job->meter);
    pthread_mutex_init(&job->lock, NULL);
    pthread_mutex_init(&job->cb_lock, NULL);
    atomic_init(&job->stop, false);
    atomic_init(&job->samples_cut, 0);
    atomic_init(&job->next_poll_ns, 0);
    job->collision_bound = watch_bound(s, rs->max_depth);
    if (!job->n || !job->active || !job->sum || (squares && !job->sq) || (job->trace_aovs && !job->aov) ||
        !job->tile_cost) {
        int w = rs->width, h = rs->height; /* rs points into the job, freed below */
        brume_render_job_release(job);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory for a %d x %d render job", s->source, w, h);
    }
    memset(job->active, 1, job->npix);
    double t_prep = progress_now();
    brume_status st = prepared_state(s, kind, &job->state);
    job->prep_seconds = progress_now() - t_prep; /* counts against a time budget */
    if (st != BRUME_OK) {
        brume_render_job_release(job);
        return st;
    }
    job->total = (uint64_t)job->ntiles * TILE * TILE * (uint64_t)rs->spp; /* refined by job_refresh */
    job_refresh(job);
    *out = job;
    return BRUME_OK;
}

void brume_render_job_release(brume_render_job *job)
{
    if (!job)
        return;
    gpu_pass_close(job->gpu);
    pthread_mutex_destroy(&job->lock);
    pthread_mutex_destroy(&job->cb_lock);
    free(job->n);
    free(job->active);
    free(job->sum);
    free(job->sq);
    free(job->aov);
    free(job->tile_cost);
    free(job->counters);
    free(job);
}

double job_pixel_error(const brume_render_job *job, size_t i)
{
    uint32_t n = job->n[i];
    if (n < 2 || !job->sq) /* no squares kept: unknown (brume_render_part) */
        return INFINITY;
    const double *s = job->sum + JOB_SUMS * i;
    double sy = (s[0] + s[1] + s[2]) / 3.0;
    double mean = sy / n;
    double var = (job->sq[JOB_SQS * i + 3] - sy * mean) / (n - 1.0); /* unbiased sample variance of y */
    if (!(var > 0.0))
        return 0.0;
    return sqrt(var / n) / fmax(mean, NOISE_FLOOR);
}

/* Under job->lock (or before any pass): done, total, noise and the cost of the samples left
 * from the per-pixel state. The total is what a fixed count would take, or with a noise
 * target the samples each active pixel is predicted to need (progress_samples_needed). The
 * samples a pixel still needs are weighed by its tile's cost per sample: the pixels left
 * at the end of an adaptive render are the costly ones (a cloud's interior rather than the
 * sky), so the mean cost of the last pass would promise too early an end. */
void job_refresh(brume_render_job *job)
{
    const brume_render_settings *rs = &job->rs;
    uint64_t done = 0, total = 0;
    double noise = 0.0, left_cost = 0.0, mean_cost = job_mean_tile_cost(job);
    for (size_t i = 0; i < job->npix; i++) {
        if (job->nparts > 1 && !job_in_part(job, i))
            continue;
        uint32_t n = job->n[i];
        done += n;
        double err = job_pixel_error(job, i);
        const double *s = job->sum + JOB_SUMS * i;
        if (n >= 2 && (s[0] + s[1] + s[2]) / (3.0 * n) >= NOISE_FLOOR && err > noise)
            noise = err;
        double want = (double)(job->target > rs->spp ? job->target : rs->spp);
        if (!job->active[i]) {
            want = n;
        } else if (rs->noise_target > 0.0 && job->spp_done == 0) {
            want = job->target; /* nothing known before the first pass */
        } else if (rs->noise_target > 0.0 && n >= 2) {
            want = progress_samples_needed(n, err, rs->noise_target, job->target, NOISE_PASSES, (int)want);
        }
        total += (uint64_t)fmax(want, (double)n);
        if (want > n && mean_cost > 0.0) {
            double c = job->tile_cost[job_pixel_task(job, i)];
            left_cost += (want - n) * (c > 0.0 ? c : mean_cost);
        }
    }
    job->done = done;
    job->total = total;
    job->noise = noise;
    job->left_cost = left_cost;
    job->left_samples = total - done;
}

/* What every pass of the job shares (render/pass.h): the scene, the integrator's state and
 * the samples' parameters; the pass's pixels, target and sums are the caller's to set. */
static render_pass job_pass_shape(const brume_render_job *job)
{
    const brume_render_settings *rs = &job->rs;
    const camera *cam = &job->s->cam;
    sample_params sp = {.kind = (int)job->kind,
                        .width = rs->width,
                        .height = rs->height,
                        .seed = rs->seed,
                        .filter = rs->filter,
                        .filter_width = rs->filter_width,
                        .max_component = rs->max_component,
                        .qmc_dims = rs->sampler == BRUME_SAMPLER_SOBOL ? RENDER_SOBOL_DIMS : 0,
                        .lens = cam->aperture_radius > 0.0,
                        .shutter = cam->shutter_close > cam->shutter_open,
                        .trace_aovs = job->trace_aovs,
                        .squares = job->sq != NULL};
    sp.film_map = film_sensor_maps(rs->sensor, rs->white_balance, sp.sensor, sp.film);
    return (render_pass){.s = job->s, .state = job->state, .sp = sp, .target = (uint32_t)job->target};
}

/* Seconds spent: the integrator's preparation (a light pass) and the passes so far, the one
 * in progress included, those of the runs before a resume too. */
static double job_spent(const brume_render_job *job)
{
    return job->prep_seconds + job->elapsed + (job->t_pass > 0.0 ? progress_now() - job->t_pass : 0.0);
}

/* Seconds of this run's time budget used: what was spent since brume_render_begin or
 * brume_render_job_resume (a resumed job takes another budget: the saved seconds are not
 * charged to it). */
static double job_used(const brume_render_job *job) { return job_spent(job) - job->elapsed_saved; }

/* Under a time budget: true, and the job stopped, once the budget is spent. */
static bool job_time_is_up(brume_render_job *job)
{
    if (job_used(job) < job->rs.time_budget)
        return false;
    if (!atomic_exchange(&job->stop, true)) {
        pthread_mutex_lock(&job->lock);
        job->out_of_time = true;
        pthread_mutex_unlock(&job->lock);
    }
    return true;
}

/* Under job->lock: the elapsed time, the ETA and the fraction done a display shows, through
 * the job's meter (core/progress.h: the fraction never goes back, the ETA is smoothed). The
 * render's own estimate of the time left: under a noise target the samples the pixels' own
 * error trend says they still need (job_refresh), each at its tile's cost per sample, the
 * tiles' costs turned into wall seconds as the last pass ran them; unknown before the first
 * estimate. Under a fixed count the same with the exact total; under a time budget at most
 * the time left. Without tile costs (the first pass, a GPU) the wall cost of a sample in
 * the last pass, or so far. */
void job_figures(brume_render_job *job, bool finished, brume_render_progress *out)
{
    const brume_render_settings *rs = &job->rs;
    double used = job_spent(job);
    double rate = job->sample_seconds > 0.0 ? job->sample_seconds
                  : job->done > 0           ? (used - job->prep_seconds) / (double)job->done
                                            : 0.0;
    if (job->left_cost > 0.0 && job->wall_per_cost > 0.0 && job->left_samples > 0)
        rate = job->left_cost * job->wall_per_cost / (double)job->left_samples;
    /* a noise target's total is known once the pixels have error estimates, or when the
     * pass under way reaches the sample maximum */
    bool known = rs->noise_target > 0.0 ? job->spp_done >= 2 || job->target >= rs->spp : true;
    progress_reading r = {used, -1.0, -1.0, finished};
    if (known && rate > 0.0)
        r.left = (double)(job->total > job->done ? job->total - job->done : 0) * rate;
    /* the cost model prices the samples left at their tiles' last costs: under load, and as
     * tiles empty (a tile's fixed costs spread over fewer samples), it misses by a factor that
     * drifts slowly; the passes it priced measure that factor */
    if (r.left > 0.0 && job->model_given > 0.0)
        r.left *= fmin(fmax(job->model_wall / job->model_given, 0.25), 4.0);
    if (rs->time_budget > 0.0)
        r.budget_left = fmax(0.0, rs->time_budget - job_used(job));
    out->elapsed = used;
    progress_meter_read(&job->meter, &r, &out->fraction, &out->eta);
}

/* After a tile: the caller's callback, which may stop the job. Calls are serialized by
 * cb_lock, and the counts are read inside it: two workers that finish tiles together must
 * not report the later count first (lock order: cb_lock, then lock). */
static void job_report_tile(brume_render_job *job)
{
    const brume_render_settings *rs = &job->rs;
    pthread_mutex_lock(&job->cb_lock);
    pthread_mutex_lock(&job->lock);
    uint64_t done = job->done, total = job->total;
    pthread_mutex_unlock(&job->lock);
    if (rs->progress_fn && !atomic_load(&job->stop) && !rs->progress_fn(rs->progress_user, done, total)) {
        atomic_store(&job->stop, true);
        job->cancelled = true;
    }
    pthread_mutex_unlock(&job->cb_lock);
}

/* Asked by a tile's sample watch every WATCH_POLL collisions (render/watch.h): whether the
 * job must stop now. A tile running longer than TILE_SLOW_SECONDS calls the progress
 * callback itself, at most every CANCEL_POLL_SECONDS over all threads, so that SIGINT stops
 * a sample of minutes within a second. */
#define TILE_SLOW_SECONDS 0.5
static _Thread_local long long tile_start_ns; /* when this thread's tile began */

static long long job_now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (long long)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

static bool job_poll(void *user)
{
    brume_render_job *job = user;
    if (job->rs.time_budget > 0.0 && job_time_is_up(job))
        return true;
    /* a tile of usual length ends whole: a stop takes effect between tiles, as the pixels of
     * a cancelled pass have all or none of its samples; only a slow tile is cut */
    long long now = job_now_ns(), due = atomic_load(&job->next_poll_ns);
    if (now - tile_start_ns < (long long)(TILE_SLOW_SECONDS * 1e9))
        return false;
    if (atomic_load(&job->stop))
        return true;
    if (!job->rs.progress_fn)
        return false;
    if (now < due || !atomic_compare_exchange_strong(&job->next_poll_ns, &due,
                                                     now + (long long)(CANCEL_POLL_SECONDS * 1e9)))
        return false;
    job_report_tile(job);
    return atomic_load(&job->stop);
}

/* A CPU pass's time budget (render_pass.cut), asked before every sample. */
static bool job_cut(void *user)
{
    brume_render_job *job = user;
    return atomic_load_explicit(&job->stop, memory_order_relaxed) || job_time_is_up(job);
}

/* Pass p's pixels written back into the job (under its lock), with its taken samples and
 * non-finite estimates counted and the time budget's total extrapolated. */
static void job_store(brume_render_job *job, const render_pass *p)
{
    const brume_render_settings *rs = &job->rs;
    pthread_mutex_lock(&job->lock);
    for (size_t j = 0; j < p->npixels; j++) {
        size_t i = p->pixels[j];
        job->n[i] = p->n[j];
        memcpy(job->sum + JOB_SUMS * i, p->sum[j], sizeof p->sum[j]);
        if (p->sq)
            memcpy(job->sq + JOB_SQS * i, p->sq[j], sizeof p->sq[j]);
        if (p->aov)
            memcpy(job->aov + JOB_AOVS * i, p->aov[j], sizeof p->aov[j]);
    }
    job->done += p->taken;
    job->samples_nonfinite += p->nonfinite;
    double elapsed = job->elapsed + (progress_now() - job->t_pass);
    if (rs->time_budget > 0.0 && elapsed > 0.0) /* a time budget: extrapolate the rate */
        job->total = (uint64_t)fmax((double)job->done,
                                    (double)job->done * (job->elapsed_saved + rs->time_budget) / elapsed);
    if (job->total < job->done)
        job->total = job->done;
    pthread_mutex_unlock(&job->lock);
}

/* Pixel i's count and sums copied into pass p's j-th place. */
static void job_load(const brume_render_job *job, size_t i, render_pass *p, size_t j)
{
    p->n[j] = job->n[i];
    memcpy(p->sum[j], job->sum + JOB_SUMS * i, sizeof p->sum[j]);
    if (p->sq)
        memcpy(p->sq[j], job->sq + JOB_SQS * i, sizeof p->sq[j]);
    if (p->aov)
        memcpy(p->aov[j], job->aov + JOB_AOVS * i, sizeof p->aov[j]);
}

/* One tile: every active pixel of it from its sample count to job->target (or as far as
 * the time budget lets it go), as a pass on this thread (pass_render_cpu). */
static void job_tile(size_t task, int thread, void *user)
{
    brume_render_job *job = user;
    if (atomic_load(&job->stop))
        return;
    const bool timed = job->rs.time_budget > 0.0;
    if (timed && job_time_is_up(job))
        return;
    stats_tls = job->counters && thread < job->nthreads ? &job->counters[thread] : NULL;
    int x0, y0, x1, y1;
    tile_rect(job, task, &x0, &y0, &x1, &y1);
    enum { P = TILE * TILE };
    uint32_t list[P], n[P];
    double sum[P][JOB_SUMS], sq[P][JOB_SQS], aov[P][JOB_AOVS];
    render_pass p = job_pass_shape(job);
    p.pixels = list;
    p.n = n;
    p.sum = sum;
    p.sq = job->sq ? sq : NULL;
    p.aov = job->trace_aovs ? aov : NULL;
    p.cut = timed ? job_cut : NULL;
    p.user = job;
    /* this task alone writes these pixels: read them without the lock */
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++) {
            size_t i = (size_t)y * (size_t)job->rs.width + (size_t)x;
            if (job->active[i]) {
                list[p.npixels] = (uint32_t)i;
                job_load(job, i, &p, p.npixels++);
            }
        }
    sample_watch watch = {.bound = job->collision_bound, .next_poll = WATCH_POLL, .poll = job_poll, .user = job};
    tile_start_ns = job_now_ns();
    watch_tls = &watch; /* the pass's samples are watched (render/watch.h) */
    pass_render_cpu(&p);
    stats_tls = NULL;
    watch_tls = NULL;
    if (watch.ncut)
        atomic_fetch_add(&job->samples_cut, watch.ncut);
    job_store(job, &p);
    job_report_tile(job);
}

/* The samples the pixels of the job's task-th tile hold; read by the task that renders
 * the tile (it alone writes them). */
static uint64_t tile_samples(const brume_render_job *job, size_t task)
{
    int x0, y0, x1, y1;
    tile_rect(job, task, &x0, &y0, &x1, &y1);
    uint64_t n = 0;
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++)
            n += job->n[(size_t)y * (size_t)job->rs.width + (size_t)x];
    return n;
}

/* A tile, timed: its cost per sample weighs the samples its pixels still need in the ETA
 * (job_refresh). The cost is the tile's thread-seconds, the progress callback included. */
static void job_tile_timed(size_t task, int thread, void *user)
{
    brume_render_job *job = user;
    uint64_t before = tile_samples(job, task);
    double t0 = progress_now();
    job_tile(task, thread, user);
    double seconds = progress_now() - t0;
    uint64_t taken = tile_samples(job, task) - before;
    if (taken == 0)
        return;
    pthread_mutex_lock(&job->lock);
    job->tile_cost[task] = seconds / (double)taken;
    job->pass_cost += seconds;
    pthread_mutex_unlock(&job->lock);
}

/* A GPU pass's stop (render_pass.cut), asked after each launch (about GPU_LAUNCH_SECONDS,
 * gpu/cuda.c): the time budget, and the progress callback (which SIGINT answers) at most
 * every CANCEL_POLL_SECONDS, so that either stops the GPU within a second. */
static bool job_gpu_cut(void *user)
{
    brume_render_job *job = user;
    if (job->rs.time_budget > 0.0 && job_time_is_up(job))
        return true;
    long long now = job_now_ns();
    if (job->rs.progress_fn && now >= atomic_load(&job->next_poll_ns)) {
        atomic_store(&job->next_poll_ns, now + (long long)(CANCEL_POLL_SECONDS * 1e9));
        job_report_tile(job);
    }
    return atomic_load(&job->stop);
}

/* The GPU's pass (gpu_pass_render): every active pixel of the job's part below the target,
 * copied into the pass's own arrays and written back whole (job_store) when the device is
 * done or cut (job_gpu_cut), so a reader under the lock (a checkpoint, the live view) never
 * sees half a pass. */
static brume_status job_gpu_pass(brume_render_job *job)
{
    render_pass p = job_pass_shape(job);
    p.cut = job_gpu_cut;
    p.user = job;
    size_t np = 0;
    for (size_t i = 0; i < job->npix; i++)
        np += job->active[i] && job->n[i] < p.target && (job->nparts == 1 || job_in_part(job, i));
    if (np == 0)
        return BRUME_OK;
    uint32_t *list = malloc(np * sizeof *list);
    p.pixels = list;
    p.n = malloc(np * sizeof *p.n);
    p.sum = malloc(np * sizeof *p.sum);
    p.sq = job->sq ? malloc(np * sizeof *p.sq) : NULL;
    p.aov = job->trace_aovs ? malloc(np * sizeof *p.aov) : NULL;
    brume_status st = BRUME_OK;
    if (!list || !p.n || !p.sum || (job->sq && !p.sq) || (job->trace_aovs && !p.aov)) {
        st = err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory for a GPU pass of %zu pixels", job->s->source, np);
    } else {
        for (size_t i = 0; i < job->npix; i++)
            if (job->active[i] && job->n[i] < p.target && (job->nparts == 1 || job_in_part(job, i))) {
                list[p.npixels] = (uint32_t)i;
                job_load(job, i, &p, p.npixels++);
            }
        st = gpu_pass_render(job->gpu, &p);
        if (st == BRUME_OK)
            job_store(job, &p);
    }
    free(list);
    free(p.n);
    free(p.sum);
    free(p.sq);
    free(p.aov);
    return st;
}

/* Runs the pass to job->target. Returns BRUME_OK when it completed, or when time ran out
 * (job->out_of_time), BRUME_ERROR_CANCELLED when the callback stopped it. An unwatched job
 * (job_next_pass) skips the per-pixel statistics before and after the pass (job_refresh:
 * done, total and the largest error, over every pixel, on one thread): no one reads them,
 * and they do not change the image. */
static brume_status job_pass(brume_render_job *job, bool unwatched)
{
    const brume_render_settings *rs = &job->rs;
    atomic_store(&job->stop, false);
    job->cancelled = false;
    if (rs->device >= 0 && !job->gpu) { /* the device's start-up (the driver's compile, the upload) is not the pass's */
        render_pass shape = job_pass_shape(job);
        gpu_pass *g = NULL;
        brume_status st = gpu_pass_open(&shape, rs->device, job->npart, &g);
        if (st != BRUME_OK)
            return st;
        job->gpu = g;
    }
    pthread_mutex_lock(&job->lock);
    job->t_pass = progress_now();
    job->pass_cost = 0.0;
    uint64_t done0 = job->done;
    if (!unwatched)
        job_refresh(job);
    job->pass_model = unwatched || rs->device >= 0 ? 0.0 : job_pass_model(job);
    pthread_mutex_unlock(&job->lock);
    if (rs->device >= 0) { /* the GPU: the whole pass at once, in each pixel's sample order */
        brume_status g = job_gpu_pass(job);
        if (g != BRUME_OK)
            return g;
        if (rs->progress_fn && !rs->progress_fn(rs->progress_user, job->done, job->total > job->done ? job->total : job->done)) {
            atomic_store(&job->stop, true);
            job->cancelled = true;
        }
    } else {
        pool_run(rs->threads, job->ntiles, job_tile_timed, job);
    }
    pthread_mutex_lock(&job->lock);
    double pass_seconds = progress_now() - job->t_pass;
    job->elapsed += pass_seconds;
    job->t_pass = 0.0;
    if (job->done > done0) /* the cost of a pixel sample as the last pass measured it, waits included */
        job->sample_seconds = pass_seconds / (double)(job->done - done0);
    if (job->pass_cost > 0.0)
        job->wall_per_cost = pass_seconds / job->pass_cost;
    bool complete = !atomic_load(&job->stop);
    if (complete && job->pass_model > 0.0) { /* what the ETA's cost model gave the pass, and its time */
        job->model_wall = 0.5 * job->model_wall + pass_seconds;
        job->model_given = 0.5 * job->model_given + job->pass_model;
    }
    if (complete) {
        job->spp_done = job->target;
        if (rs->noise_target > 0.0) /* adaptive sampling: each pixel by its own statistics */
            for (size_t i = 0; i < job->npix; i++)
                if (job->active[i] && job->n[i] >= (uint32_t)rs->min_spp && job->n[i] >= 2 &&
                    job_pixel_error(job, i) <= rs->noise_target)
                    job->active[i] = 0;
    }
    if (!unwatched)
        job_refresh(job);
    pthread_mutex_unlock(&job->lock);
    if (job->cancelled)
        return err_set(BRUME_ERROR_CANCELLED, "%s: render cancelled by the progress callback (%d to %d samples per pixel)",
                       job->s->source, job->spp_done, job->target);
    return BRUME_OK;
}

/* Samples the next pass adds to each active pixel under the settings' budgets, 0 when
 * the job is finished. A pass that was cut is completed first. A noise target starts with
 * min_spp samples, a time budget or a fixed count with 1 (an interrupted render has every
 * pixel soon); then each pass adds a quarter (a noise target, so that a pixel overshoots its
 * need by at most that) or a half of what each pixel has, at least 1 and at most PASS_MAX.
 * An unwatched render (brume_render with no callback and no budget: no
 * one holds the job, sees its progress or can stop it) takes PASS_MAX at once: its passes
 * would only cost (each rereads every pixel's sums and statistics, and waits for the
 * slowest thread), and the image is the same (a pixel's samples are numbered, whatever
 * the passes). On a GPU, a pass after the first takes at least GPU_PASS_SAMPLES samples
 * (more than PASS_MAX a pixel on small images), budgets permitting. A watched render with a
 * fixed count whose first passes show the rest to be short (PASS_SHORT_REST) takes it in one
 * pass too: an interruption in that second leaves tiles with different counts, which
 * the partial image reports anyway. */
int job_next_pass(const brume_render_job *job, bool unwatched)
{
    const brume_render_settings *rs = &job->rs;
    const bool timed = rs->time_budget > 0.0;
    if (job->out_of_time)
        return 0;
    if (job->target > job->spp_done)
        return job->target - job->spp_done;
    if (job->spp_done >= rs->spp)
        return 0;
    size_t nactive = 0;
    for (size_t i = 0; i < job->npix; i++)
        nactive += job->active[i] && (job->nparts == 1 || job_in_part(job, i));
    if (nactive == 0)
        return 0;
    int k;
    if (unwatched)
        k = PASS_MAX;
    else if (job->spp_done == 0)
        k = rs->noise_target > 0.0 && !timed ? rs->min_spp : 1; /* a budget starts at 1: the minimum yields */
    else
        k = job->spp_done / (rs->noise_target > 0.0 ? NOISE_PASSES.divisor : 2);
    if (!timed && !(rs->noise_target > 0.0) && job->spp_done > 0 && job->sample_seconds > 0.0 &&
        job->sample_seconds * (double)nactive * (double)(rs->spp - job->spp_done) <= PASS_SHORT_REST)
        k = rs->spp - job->spp_done; /* the rest is short: in one pass (at most PASS_MAX), not in
                                        several that each reread every pixel and wait for the slowest thread */
    k = k < 1 ? 1 : k;
    if (job->spp_done > 0 && k > PASS_MAX)
        k = PASS_MAX;
    if (rs->device >= 0 && job->spp_done > 0) { /* the GPU: passes of GPU_PASS_SAMPLES */
        size_t k_gpu = (GPU_PASS_SAMPLES + nactive - 1) / nactive;
        k = k_gpu > (size_t)k ? (k_gpu > (size_t)INT_MAX ? INT_MAX : (int)k_gpu) : k;
    }
    if (timed && job->spp_done > 0 && job->sample_seconds > 0.0) {
        /* the passes sized from the measured cost of a pixel sample, so that the last one
         * ends with the budget. A 1-sample pass that would not fit whole is begun when at
         * least half of it fits (the clock cuts it: the tiles it did not reach stay one
         * sample short), else the render ends early by less than half a pass */
        double left = rs->time_budget - job_used(job);
        double fit = left / (job->sample_seconds * (double)nactive);
        if (fit < 0.5)
            return -1;
        if (fit < k)
            k = fit < 1.0 ? 1 : (int)fit;
    }
    return k < rs->spp - job->spp_done ? k : rs->spp - job->spp_done;
}

brume_status job_add(brume_render_job *job, int spp, bool unwatched)
{
    pthread_mutex_lock(&job->lock);
    if (job->target <= job->spp_done) {
        long long t = (long long)job->spp_done + spp;
        job->target = t > (1 << 30) ? (1 << 30) : (int)t;
    }
    pthread_mutex_unlock(&job->lock);
    return job_pass(job, unwatched);
}

static double per(double a, uint64_t n) { return n ? a / (double)n : 0.0; }

/* The scene's statistics (brume_scene_stats) from the job's counters. */
static void job_fill_stats(const brume_render_job *job)
{
    const brume_scene *s = job->s;
    stats_counters sum = {0};
    for (int t = 0; job->counters && t < job->nthreads; t++)
        stats_merge(&sum, &job->counters[t]);
    const stats_counters *c = &sum;
    brume_stats *out = &s->prepared->stats;
    memset(out, 0, sizeof *out);
    out->rendered = true;
    out->method = s->settings.method;
    out->seconds = stats_now() - job->t_start;
    out->camera_rays = c->camera_rays;
    out->li_cpu_seconds = c->t_li;
    out->samples_cut = atomic_load(&job->samples_cut);
    out->samples_nonfinite = job->samples_nonfinite;
    out->collision_bound = job->collision_bound;
    switch (job->kind) {
    case INTEGRATOR_BLASI: {
        blasi_stats b;
        blasi_get_stats(job->state, &b);
        out->blasi.light_seconds = b.light_seconds;
        out->blasi.view_seconds = job->elapsed;
        out->blasi.light_rays = b.light_rays;
        out->blasi.interceptions = b.interceptions;
        out->blasi.deposits = b.deposits;
        out->blasi.power_emitted = b.emitted_power;
        out->blasi.power_stored = b.stored_power;
        break;
    }
    case INTEGRATOR_STAM:
        out->stam.blobs_per_ray = per((double)c->stam_camera_blobs, c->camera_rays);
        out->stam.queries_per_ray = per((double)c->blob_queries, c->camera_rays);
        out->stam.nodes_per_query = per((double)c->blob_nodes, c->blob_queries);
        out->stam.blobs_per_query = per((double)c->blob_visits, c->blob_queries);
        break;
    case INTEGRATOR_PATH:
    case INTEGRATOR_SINGLE:
        out->path.vertices = per((double)c->path_vertices, c->camera_rays);
        out->path.collisions = per((double)c->path_scatterings, c->camera_rays);
        out->path.null_collisions = per((double)(c->path_tentative - c->path_scatterings), c->camera_rays);
        out->path.majorant_cells = per((double)c->majorant_cells, c->camera_rays);
        out->path.density_lookups = per((double)c->density_lookups, c->camera_rays);
        out->path.tracking_cpu_seconds = c->t_tracking;
        out->path.nee_cpu_seconds = c->t_nee;
        out->path.shading_cpu_seconds = fmax(0.0, c->t_li - c->t_tracking - c->t_nee);
        break;
    }
}

brume_status job_run(brume_render_job *job, bool unwatched)
{
    brume_status st_empty = BRUME_OK;
    int k;
    while ((k = job_next_pass(job, unwatched)) > 0) {
        brume_status st = job_add(job, k, unwatched);
        if (st != BRUME_OK)
            return st;
    }
    if (k < 0) { /* the time left holds no whole pass: the budget is spent */
        pthread_mutex_lock(&job->lock);
        job->out_of_time = true;
        pthread_mutex_unlock(&job->lock);
    }
    if (job->out_of_time && job->done == 0) /* an image of no sample is no render */
        st_empty = err_set(BRUME_ERROR_RANGE,
                           "%s: render.time: the time budget of %.17g s was spent before the first sample (%.3g s in "
                           "the method's preparation): raise it",
                           job->s->source, job->rs.time_budget, job->prep_seconds);
    job_fill_stats(job);
    return st_empty;
}
