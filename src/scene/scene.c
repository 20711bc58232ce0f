/* scene.c - brume_scene lifecycle: new, settings, release (the commit: scene_commit.c). */
#include "scene/scene.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/budget.h"
#include "core/context.h"
#include "core/error.h"
#include "method/method.h"
#include "scene/film_sensor.h"

void scene_default_settings(brume_render_settings *rs)
{
    memset(rs, 0, sizeof *rs);
    rs->width = 640;
    rs->height = 480;
    rs->spp = 16;
    rs->seed = 1;
    rs->threads = 0;
    rs->method = BRUME_METHOD_PATH;
    rs->max_depth = 256;
    rs->filter = BRUME_FILTER_GAUSSIAN;
    rs->filter_width = 2.0;
    rs->fps = 24.0;
    rs->min_spp = 16;
    rs->device = -1;
    rs->sampler = BRUME_SAMPLER_SOBOL; /* docs/sampling.md and docs/performance.md, "Low-discrepancy sampling" */
}

brume_scene *scene_new(const char *source)
{
    brume_scene *s = calloc(1, sizeof *s);
    if (!s) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", source);
        return NULL;
    }
    snprintf(s->source, sizeof s->source, "%s", source);
    s->prepared = calloc(1, sizeof *s->prepared);
    if (!s->prepared) {
        free(s);
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", source);
        return NULL;
    }
    scene_default_settings(&s->settings);
    s->max_memory = BUDGET_DEFAULT_BYTES;
    s->max_work = SCENE_MAX_WORK_DEFAULT;
    for (int i = 0; i < METHOD_OPTIONS_COUNT; i++) {
        const method_options_def *def = method_options_def_get((method_options_id)i);
        if (!(s->options[i] = malloc(def->size))) {
            brume_scene_release(s);
            err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", source);
            return NULL;
        }
        method_options_default(def, s->options[i]);
    }
    s->cam = (camera){.position = v3(0, 0, 5), .look_at = v3(0, 0, 0), .up = v3(0, 1, 0), .fov = 40.0,
                      .aperture_radius = 0.0, .focus_distance = 1.0, .shutter_open = 0.0, .shutter_close = 0.0};
    s->bg.L = col(0.0);
    s->bg.scale = 1.0;
    s->bg.up = v3(0, 1, 0);
    return s;
}

const void *scene_options(const brume_scene *s, method_options_id id) { return s->options[id]; }

brume_status scene_check_settings(const char *source, const brume_render_settings *rs)
{
    if (rs->width < 1 || rs->width > 65536)
        return err_set(BRUME_ERROR_RANGE, "%s: render.width: %d outside [1, 65536]", source, rs->width);
    if (rs->height < 1 || rs->height > 65536)
        return err_set(BRUME_ERROR_RANGE, "%s: render.height: %d outside [1, 65536]", source, rs->height);
    if ((uint64_t)rs->width * (uint64_t)rs->height > (1ULL << 28))
        return err_set(BRUME_ERROR_RANGE, "%s: render.width x height: %d x %d exceeds 2^28 pixels", source,
                       rs->width, rs->height);
    if (rs->spp < 1 || rs->spp > (1 << 24))
        return err_set(BRUME_ERROR_RANGE, "%s: render.spp: %d outside [1, 16777216]", source, rs->spp);
    if (rs->threads < 0 || rs->threads > 1024)
        return err_set(BRUME_ERROR_RANGE, "%s: render.threads: %d outside [0, 1024]", source, rs->threads);
    if (rs->max_depth < 1 || rs->max_depth > 100000)
        return err_set(BRUME_ERROR_RANGE, "%s: render.max_depth: %d outside [1, 100000]", source, rs->max_depth);
    if (!(rs->filter_width > 0.0 && rs->filter_width <= 16.0))
        return err_set(BRUME_ERROR_RANGE, "%s: render.filter.width: %.17g outside (0, 16]", source, rs->filter_width);
    if (rs->filter != BRUME_FILTER_BOX && rs->filter != BRUME_FILTER_GAUSSIAN)
        return err_set(BRUME_ERROR_RANGE, "%s: render.filter.type: unknown filter %d", source, (int)rs->filter);
    if (!(rs->max_component >= 0.0 && rs->max_component <= 1e30))
        return err_set(BRUME_ERROR_RANGE, "%s: render.max_component: %.17g outside [0, 1e30]", source, rs->max_component);
    if (!(rs->white_balance == 0.0 || (rs->white_balance >= 1000.0 && rs->white_balance <= 1e5)))
        return err_set(BRUME_ERROR_RANGE, "%s: render.white_balance: %.17g K: 0 (none) or in [1000, 100000]", source,
                       rs->white_balance);
    if (!film_sensor_name(rs->sensor))
        return err_set(BRUME_ERROR_RANGE, "%s: render.sensor: %d is not a sensor's number (brume_sensor_name)", source,
                       rs->sensor);
    if (!(rs->fps > 0.0 && rs->fps <= 1e6))
        return err_set(BRUME_ERROR_RANGE, "%s: render.fps: %.17g outside (0, 1e6]", source, rs->fps);
    if (!(rs->time_budget >= 0.0 && rs->time_budget <= 1e9))
        return err_set(BRUME_ERROR_RANGE, "%s: render.time: %.17g outside [0, 1e9] seconds", source, rs->time_budget);
    if (!(rs->noise_target >= 0.0 && rs->noise_target <= 1.0))
        return err_set(BRUME_ERROR_RANGE, "%s: render.noise: %.17g outside [0, 1]", source, rs->noise_target);
    if (rs->device < -1 || rs->device >= 64)
        return err_set(BRUME_ERROR_RANGE, "%s: render.device: %d is not -1 (the CPU) or a GPU 0 .. 63", source, rs->device);
    if (rs->sampler != BRUME_SAMPLER_INDEPENDENT && rs->sampler != BRUME_SAMPLER_SOBOL)
        return err_set(BRUME_ERROR_RANGE, "%s: render.sampler: unknown sampler %d", source, (int)rs->sampler);
    if (rs->min_spp < 1 || rs->min_spp > (1 << 24))
        return err_set(BRUME_ERROR_RANGE, "%s: render.min_spp: %d outside [1, 16777216]", source, rs->min_spp);
    if (rs->aovs & ~(unsigned)(BRUME_AOV_DEPTH | BRUME_AOV_ALBEDO | BRUME_AOV_NORMAL | BRUME_AOV_VARIANCE |
                               BRUME_AOV_SAMPLES))
        return err_set(BRUME_ERROR_RANGE, "%s: render.aovs: unknown bits 0x%x", source, rs->aovs);
    if (!brume_method_name(rs->method))
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: render.method: %d is not a brume_method (known: %s)", source,
                       (int)rs->method, integrator_names());
    return BRUME_OK;
}

void brume_scene_settings(const brume_scene *s, brume_render_settings *rs)
{
    if (rs)
        *rs = s ? s->settings : (brume_render_settings){0};
}

brume_status brume_scene_set_settings(brume_context *ctx, brume_scene *s, const brume_render_settings *rs)
{
    err_clear();
    if (!s || !rs)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_scene_set_settings: %s: NULL",
                                       !s ? "scene" : "settings"));
    if (s->committed)
        return ctx_report(ctx, err_set(BRUME_ERROR_STATE, "%s: settings changed after commit", s->source));
    brume_status st = scene_check_settings(s->source, rs);
    if (st == BRUME_OK)
        s->settings = *rs;
    return ctx_report(ctx, st);
}

bool scene_flight_control(const brume_scene *s)
{
    return s->nmedia == 1 && !medium_has_fields(&s->media[0]) && s->media[0].sigma_t_min == s->media[0].sigma_t_max;
}

double brume_scene_time(const brume_scene *s) { return s ? s->time : 0.0; }

size_t brume_scene_memory(const brume_scene *s, size_t *limit)
{
    if (limit)
        *limit = s ? s->max_memory : 0;
    return s ? s->memory_used : 0;
}

void brume_scene_release(brume_scene *s)
{
    if (!s)
        return;
    if (s->prepared && s->prepared->valid)
        s->prepared->finish(s->prepared->kind, s->prepared->state);
    free(s->prepared);
    io_inputs_free(&s->inputs);
    for (int m = 0; m < s->nmedia; m++)
        medium_release(&s->media[m]);
    free(s->lights);
    background_release(&s->bg);
    surfaces_release(s->surf);
    free(s->bound);
    for (int i = 0; i < METHOD_OPTIONS_COUNT; i++)
        free(s->options[i]);
    for (int i = 0; i < s->nignored; i++)
        free(s->ignored[i]);
    free(s->ignored);
    free(s);
}

int brume_scene_ignored_count(const brume_scene *s) { return s ? s->nignored : 0; }

const char *brume_scene_ignored(const brume_scene *s, int index)
{
    return s && index >= 0 && index < s->nignored ? s->ignored[index] : NULL;
}
