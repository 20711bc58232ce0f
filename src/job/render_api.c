/* render_api.c - the public render calls (brume_render_begin, _add, _run, _image, progress,
 * brume_render, brume_render_part, brume_scene_stats) over the jobs of render.c, and a job's
 * image with its layers. */
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/bigmem.h"
#include "core/context.h"
#include "core/error.h"
#include "core/pool.h"
#include "core/stats.h"
#include "image/image.h"
#include "io/atomic.h"
#include "render/blasi.h"
#include "render/film.h"
#include "render/job.h"
#include "render/sample.h"
#include "gpu/cuda.h"
#include "job/render_impl.h"

static brume_status job_image(const brume_render_job *job, brume_image **out)
{
    const brume_render_settings *rs = &job->rs;
    *out = NULL;
    brume_image *img = image_new(rs->width, rs->height);
    if (!img)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: cannot allocate a %d x %d image", job->s->source, rs->width,
                       rs->height);
    static const char *const rgb[3] = {"R", "G", "B"}, *const xyz[3] = {"X", "Y", "Z"}, *const z[1] = {"Z"},
                             *const yy[1] = {"Y"};
    float *depth = NULL, *albedo = NULL, *normal = NULL, *var = NULL, *count = NULL;
    bool ok = true;
    if (rs->aovs & BRUME_AOV_DEPTH)
        ok &= (depth = image_add_layer(img, "depth", 1, z)) != NULL;
    if (rs->aovs & BRUME_AOV_ALBEDO)
        ok &= (albedo = image_add_layer(img, "albedo", 3, rgb)) != NULL;
    if (rs->aovs & BRUME_AOV_NORMAL)
        ok &= (normal = image_add_layer(img, "normal", 3, xyz)) != NULL;
    if (rs->aovs & BRUME_AOV_VARIANCE)
        ok &= (var = image_add_layer(img, "variance", 3, rgb)) != NULL;
    if (rs->aovs & BRUME_AOV_SAMPLES)
        ok &= (count = image_add_layer(img, "samples", 1, yy)) != NULL;
    if (!ok) {
        brume_image_release(img);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: cannot allocate the image's layers", job->s->source);
    }
    brume_render_job *j = (brume_render_job *)job; /* the lock only */
    pthread_mutex_lock(&j->lock);
    for (size_t i = 0; i < job->npix; i++) {
        uint32_t n = job->n[i];
        if (n == 0)
            continue; /* +0 everywhere: not rendered (yet, or by another part) */
        const double *s = job->sum + JOB_SUMS * i;
        float *px = img->rgba + 4 * i;
        double inv = 1.0 / n;
        for (int c = 0; c < 3; c++)
            px[c] = (float)(s[c] * inv);
        uint32_t na = n < JOB_ALPHA_SAMPLES ? n : JOB_ALPHA_SAMPLES;
        px[3] = (float)fmin(1.0, fmax(0.0, s[3] / na));
        const double *a = job->aov ? job->aov + JOB_AOVS * i : NULL;
        if (depth)
            depth[i] = a[1] > 0.0 ? (float)(a[0] / a[1]) : 0.0f;
        for (size_t c = 0; c < 3; c++) {
            if (albedo)
                albedo[3 * i + c] = (float)(a[2 + c] * inv);
            if (normal)
                normal[3 * i + c] = (float)(a[5 + c] * inv);
            if (var)
                var[3 * i + c] = n < 2 ? 0.0f
                                       : (float)fmax(0.0, (job->sq[JOB_SQS * i + c] - s[c] * s[c] * inv) /
                                                              ((n - 1.0) * n));
        }
        if (count)
            count[i] = (float)n;
    }
    pthread_mutex_unlock(&j->lock);
    *out = img;
    return BRUME_OK;
}

brume_status brume_render_begin(brume_context *ctx, const brume_scene *s, brume_render_job **out)
{
    err_clear();
    if (out)
        *out = NULL;
    if (!out || !s)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_render_begin: %s: NULL", !s ? "scene" : "out"));
    const void *owner = atomic_owner(ctx); /* blasi.save_light's temporary file is ctx's (io/atomic.h) */
    brume_status st = job_create(s, 0, 1, true, out);
    atomic_owner(owner);
    return ctx_report(ctx, st);
}

brume_status brume_render_job_add(brume_context *ctx, brume_render_job *job, int spp)
{
    err_clear();
    if (!job)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_render_job_add: job: NULL"));
    if (spp < 1 || spp > (1 << 24))
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "brume_render_job_add: spp: %d outside [1, 16777216]", spp));
    return ctx_report(ctx, job_add(job, spp, false));
}

brume_status brume_render_job_run(brume_context *ctx, brume_render_job *job)
{
    err_clear();
    if (!job)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_render_job_run: job: NULL"));
    return ctx_report(ctx, job_run(job, false)); /* the caller holds the job: passes as scheduled */
}

brume_status brume_render_job_image(brume_context *ctx, const brume_render_job *job, brume_image **out)
{
    err_clear();
    if (out)
        *out = NULL;
    if (!out || !job)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_render_job_image: %s: NULL", !job ? "job" : "out"));
    return ctx_report(ctx, job_image(job, out));
}

int brume_render_job_samples(const brume_render_job *job)
{
    if (!job)
        return 0;
    brume_render_job *j = (brume_render_job *)job;
    pthread_mutex_lock(&j->lock);
    uint32_t m = 0;
    for (size_t i = 0; i < job->npix; i++)
        m = job->n[i] > m ? job->n[i] : m;
    pthread_mutex_unlock(&j->lock);
    return (int)m;
}

void brume_render_job_progress(const brume_render_job *job, brume_render_progress *out)
{
    if (!out)
        return;
    memset(out, 0, sizeof *out);
    if (!job)
        return;
    brume_render_job *j = (brume_render_job *)job;
    pthread_mutex_lock(&j->lock);
    uint32_t nmin = UINT32_MAX, nmax = 0;
    double ntotal = 0.0;
    size_t npart = 0, stopped = 0;
    for (size_t i = 0; i < job->npix; i++) {
        if (job->nparts > 1 && !job_in_part(job, i))
            continue;
        uint32_t n = job->n[i];
        nmin = n < nmin ? n : nmin;
        nmax = n > nmax ? n : nmax;
        ntotal += n;
        npart++;
        stopped += !job->active[i];
    }
    out->done = job->done;
    out->total = job->total;
    out->spp_min = npart ? (int)nmin : 0;
    out->spp_max = (int)nmax;
    out->spp_mean = npart ? ntotal / (double)npart : 0.0;
    out->noise = job->noise;
    out->converged = npart ? (double)stopped / (double)npart : 0.0;
    int next = job->t_pass == 0.0 ? job_next_pass(job, false) : 1;
    out->finished = next <= 0;
    if (out->finished) /* what ended it: the clock, every pixel at the noise target, or spp */
        out->stopped = job->out_of_time || next < 0 ? BRUME_STOP_TIME
                       : stopped == npart        ? BRUME_STOP_NOISE
                                                 : BRUME_STOP_SPP;
    else if (job->t_pass == 0.0 && atomic_load(&job->stop) && !job->out_of_time)
        out->stopped = BRUME_STOP_CANCELLED; /* the callback stopped the last pass */
    job_figures(j, out->finished, out);
    pthread_mutex_unlock(&j->lock);
}

brume_status brume_render(brume_context *ctx, const brume_scene *s, brume_image **out)
{
    return brume_render_part(ctx, s, 0, 1, out);
}

brume_status brume_render_part(brume_context *ctx, const brume_scene *s, int part, int nparts, brume_image **out)
{
    err_clear();
    if (out)
        *out = NULL;
    if (!out || !s)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_render: %s: NULL", !s ? "scene" : "out"));
    if (nparts < 1 || part < 0 || part >= nparts)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: render part %d of %d: need 0 <= part < parts",
                                       s->source, part, nparts));
    const brume_render_settings *rs = &s->settings;
    const bool unwatched = !rs->progress_fn && !(rs->time_budget > 0.0) && !(rs->noise_target > 0.0);
    /* unwatched and without the variance layer, no one reads the squared samples: they are
     * neither kept nor made (half the job's memory, whose zeroing touches a fresh page, a
     * page fault, per 4 KiB) */
    brume_render_job *job = NULL;
    const void *owner = atomic_owner(ctx); /* blasi.save_light's temporary file is ctx's (io/atomic.h) */
    brume_status st = job_create(s, part, nparts, !unwatched || (rs->aovs & BRUME_AOV_VARIANCE), &job);
    atomic_owner(owner);
    if (st != BRUME_OK)
        return ctx_report(ctx, st);
    st = job_run(job, unwatched);
    if (st == BRUME_OK || st == BRUME_ERROR_CANCELLED) {
        char msg[1024];
        snprintf(msg, sizeof msg, "%s", err_message());
        brume_status sti = job_image(job, out);
        if (sti != BRUME_OK)
            st = sti;
        else if (st != BRUME_OK)
            err_set(st, "%s", msg);
    }
    brume_render_job_release(job);
    return ctx_report(ctx, st);
}

void brume_scene_stats(const brume_scene *scene, brume_stats *out)
{
    if (out)
        *out = scene ? scene->prepared->stats : (brume_stats){0};
}
