/* render.c - brume_render: tiles over the thread pool, samples per pixel, the film; parts
 * of a frame (interleaved tiles) for distributed rendering. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/error.h"
#include "core/pool.h"
#include "core/progress.h"
#include "core/stats.h"
#include "io/image.h"
#include "render/blasi.h"
#include "render/film.h"
#include "render/integrator.h"
#include "render/track.h"

#define TILE 16
#define ALPHA_SAMPLES 8 /* camera samples per pixel that estimate alpha */

typedef struct render_job {
    const brume_scene *s;
    integrator_kind kind;
    const void *state; /* integrator_prepare's */
    brume_image *img;
    int tiles_x;
    int part, nparts; /* this job renders tiles part, part + nparts, ... */
    progress prog;
    stats_counters *counters; /* one per thread when statistics are on, else NULL */
} render_job;

static void render_tile(size_t task, int thread, void *user)
{
    render_job *job = user;
    stats_counters *sc = job->counters ? &job->counters[thread] : NULL;
    stats_tls = sc;
    const brume_scene *s = job->s;
    const brume_render_settings *rs = &s->settings;
    size_t tile = task * (size_t)job->nparts + (size_t)job->part;
    int tx = (int)(tile % (size_t)job->tiles_x), ty = (int)(tile / (size_t)job->tiles_x);
    int x0 = tx * TILE, y0 = ty * TILE;
    int x1 = x0 + TILE < rs->width ? x0 + TILE : rs->width;
    int y1 = y0 + TILE < rs->height ? y0 + TILE : rs->height;
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++) {
            uint64_t pixel = (uint64_t)y * (uint64_t)rs->width + (uint64_t)x;
            color sum = col(0.0);
            double alpha = 0.0;
            for (int sidx = 0; sidx < rs->spp; sidx++) {
                rng g = rng_make(rs->seed, pixel, (uint64_t)sidx);
                double dx, dy;
                film_sample_filter(rs->filter, rs->filter_width, &g, &dx, &dy);
                double u1 = rng_next(&g), u2 = rng_next(&g), ut = rng_next(&g);
                ray r = camera_ray(&s->cam, rs->width, rs->height, x + 0.5 + dx, y + 0.5 + dy, u1, u2, ut);
                bool opaque = false;
                double t0 = sc ? stats_now() : 0.0;
                color L = integrator_Li(job->kind, s, job->state, r, &g, &opaque);
                if (sc) {
                    sc->t_li += stats_now() - t0;
                    sc->camera_rays++;
                }
                if (col_isfinite(L))
                    sum = col_add(sum, L);
                /* alpha: 1 on surfaces, else 1 - mean transmittance of the media along the
                 * ray, estimated by the method on the first ALPHA_SAMPLES samples only: a
                 * smooth estimator that needs few samples, and no cost for the others */
                if (sidx < ALPHA_SAMPLES)
                    alpha += opaque ? 1.0 : 1.0 - col_avg(integrator_transmittance(job->kind, s, job->state, r, &g));
            }
            float *px = job->img->rgba + 4 * pixel;
            double inv = 1.0 / rs->spp;
            for (int c = 0; c < 3; c++)
                px[c] = (float)(sum.c[c] * inv);
            int na = rs->spp < ALPHA_SAMPLES ? rs->spp : ALPHA_SAMPLES;
            px[3] = (float)fmin(1.0, fmax(0.0, alpha / na));
        }
    stats_tls = NULL;
    progress_add(&job->prog, 1);
}

static void render_fill_stats(const brume_scene *s, integrator_kind kind, const void *state, const stats_counters *c,
                              double seconds, double view_seconds, brume_stats *out);

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
    }
    *state = p->state;
    return BRUME_OK;
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
    if (!s->committed)
        return ctx_report(ctx, err_set(BRUME_ERROR_STATE, "%s: render before brume_scene_commit", s->source));
    integrator_kind kind;
    if (!integrator_from_name(s->settings.method, &kind))
        return ctx_report(ctx, err_set(BRUME_ERROR_UNSUPPORTED, "%s: render.method: unknown method '%s' (known: %s)",
                                       s->source, s->settings.method, integrator_names()));
    brume_image *img = brume_image_new(s->settings.width, s->settings.height);
    if (!img)
        return ctx_report(ctx, err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: cannot allocate a %d x %d image", s->source,
                                       s->settings.width, s->settings.height));
    double t_start = stats_now();
    const void *state = NULL;
    brume_status st = prepared_state(s, kind, &state);
    if (st != BRUME_OK) {
        brume_image_release(img);
        return ctx_report(ctx, st);
    }
    render_job job = {s, kind, state, img, (s->settings.width + TILE - 1) / TILE, part, nparts, {0}, NULL};
    int nthreads = s->settings.threads > 0 ? s->settings.threads : pool_default_threads();
    if (s->settings.stats && !(job.counters = calloc((size_t)(nthreads > 0 ? nthreads : 1), sizeof *job.counters))) {
        brume_image_release(img);
        return ctx_report(ctx, err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory for statistics", s->source));
    }
    size_t ntiles = (size_t)job.tiles_x * (size_t)((s->settings.height + TILE - 1) / TILE);
    size_t mine = ntiles / (size_t)nparts + ((size_t)part < ntiles % (size_t)nparts ? 1 : 0);
    double t_view = stats_now();
    progress_begin(&job.prog, "render", mine, s->settings.progress);
    pool_run(s->settings.threads, mine, render_tile, &job);
    progress_end(&job.prog);
    double t_end = stats_now();
    stats_counters sum = {0};
    for (int t = 0; job.counters && t < nthreads; t++)
        stats_merge(&sum, &job.counters[t]);
    free(job.counters);
    render_fill_stats(s, kind, state, &sum, t_end - t_start, t_end - t_view, &s->prepared->stats);
    *out = img;
    return ctx_report(ctx, BRUME_OK);
}

static double per(double a, uint64_t n) { return n ? a / (double)n : 0.0; }

static void render_fill_stats(const brume_scene *s, integrator_kind kind, const void *state, const stats_counters *c,
                              double seconds, double view_seconds, brume_stats *out)
{
    memset(out, 0, sizeof *out);
    snprintf(out->method, sizeof out->method, "%s", s->settings.method);
    out->seconds = seconds;
    out->camera_rays = c->camera_rays;
    out->li_cpu_seconds = c->t_li;
    switch (kind) {
    case INTEGRATOR_BLASI: {
        blasi_stats b;
        blasi_get_stats(state, &b);
        out->blasi_light_seconds = b.light_seconds;
        out->blasi_view_seconds = view_seconds;
        out->blasi_light_rays = b.light_rays;
        out->blasi_interceptions = b.interceptions;
        out->blasi_deposits = b.deposits;
        out->blasi_power_emitted = b.emitted_power;
        out->blasi_power_stored = b.stored_power;
        break;
    }
    case INTEGRATOR_STAM:
        out->stam_blobs_per_ray = per((double)c->stam_camera_blobs, c->camera_rays);
        out->stam_queries_per_ray = per((double)c->blob_queries, c->camera_rays);
        out->stam_nodes_per_query = per((double)c->blob_nodes, c->blob_queries);
        out->stam_blobs_per_query = per((double)c->blob_visits, c->blob_queries);
        break;
    case INTEGRATOR_PATH:
    case INTEGRATOR_SINGLE:
        out->path_vertices = per((double)c->path_vertices, c->camera_rays);
        out->path_collisions = per((double)c->path_scatterings, c->camera_rays);
        out->path_null_collisions = per((double)(c->path_tentative - c->path_scatterings), c->camera_rays);
        out->path_tracking_cpu_seconds = c->t_tracking;
        out->path_nee_cpu_seconds = c->t_nee;
        out->path_shading_cpu_seconds = fmax(0.0, c->t_li - c->t_tracking - c->t_nee);
        break;
    }
}

brume_status brume_scene_get_stats(brume_context *ctx, const brume_scene *scene, brume_stats *out)
{
    err_clear();
    if (!scene || !out)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_scene_get_stats: %s: NULL",
                                       !scene ? "scene" : "out"));
    *out = scene->prepared->stats;
    return ctx_report(ctx, BRUME_OK);
}
