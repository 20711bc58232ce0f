/* scene_json.c - the scene file reader (docs/scene-format.md) and brume_scene_load: a client
 * of the public scene builders (scene/scene_build.c): it checks the JSON's shape and types,
 * naming file and key, and builds the scene through the same calls an application makes. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/budget.h"
#include "core/cancel.h"
#include "core/context.h"
#include "core/error.h"
#include "io/grid_io.h"
#include "io/grid_sequence.h"
#include "io/json.h"
#include "method/method.h"
#include "scene/scene_methods.h"
#include "scene/scene_stam.h"
#include "scene/scene_pbrt.h"
#include "scene/scene_studio.h"
#include "scene/scene_keys.h"
#include "scene/scene_override.h"
#include "scene/scene_surfaces.h"
#include "scene/scene.h"
#include "scene/scene_build.h"
#include "scene/scene_json_common.h"
#include "scene/film_sensor.h"

static brume_status parse_render(const cJSON *j, jloc at, brume_scene *s)
{
    static const char *const keys[] = {"width", "height", "spp", "seed", "threads", "method", "max_depth", "filter",
                                       "fps", "max_memory_mb", "max_work", "noise", "time", "min_spp", "sampler", "device", "max_component", "white_balance", "sensor", NULL};
    brume_status st = json_check_object(j, at, keys);
    if (st) return st;
    /* the one memory limit of everything the scene makes brume read or generate (core/budget.h) */
    double mb = (double)(BUDGET_DEFAULT_BYTES >> 20);
    if ((st = json_number(j, at, "max_memory_mb", 0, 1.0, 1e9, &mb))) return st;
    budget_set_limit((size_t)(mb * 1048576.0));
    /* the one work limit: each method estimates its work before it starts */
    if ((st = json_number(j, at, "max_work", 0, 1.0, 1e18, &s->max_work))) return st;
    budget_set_work_limit(s->max_work); /* the generators below ask it (budget_work) */
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    if ((st = json_int(j, at, "width", 0, 1, 65536, &rs.width))) return st;
    if ((st = json_int(j, at, "height", 0, 1, 65536, &rs.height))) return st;
    if ((st = json_int(j, at, "spp", 0, 1, 1 << 24, &rs.spp))) return st;
    if ((st = json_u64(j, at, "seed", 0, &rs.seed))) return st;
    if ((st = json_int(j, at, "threads", 0, 0, 1024, &rs.threads))) return st;
    char method[32] = "";
    if ((st = json_string(j, at, "method", 0, method, sizeof method))) return st;
    integrator_kind kind = (integrator_kind)rs.method; /* one enum (method/method_name.c) */
    if (method[0] && !integrator_from_name(method, &kind))
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: render.method: unknown method '%s' (known: %s)", at.file, method,
                       integrator_names());
    rs.method = (brume_method)kind;
    if ((st = json_int(j, at, "max_depth", 0, 1, 100000, &rs.max_depth))) return st;
    if ((st = json_number(j, at, "fps", 0, 1e-6, 1e6, &rs.fps))) return st;
    if ((st = json_number(j, at, "noise", 0, 0.0, 1.0, &rs.noise_target))) return st;
    if ((st = json_number(j, at, "time", 0, 0.0, 1e9, &rs.time_budget))) return st;
    if ((st = json_int(j, at, "min_spp", 0, 1, 1 << 24, &rs.min_spp))) return st;
    if ((st = json_number(j, at, "max_component", 0, 0.0, 1e30, &rs.max_component))) return st;
    if ((st = json_number(j, at, "white_balance", 0, 0.0, 1e5, &rs.white_balance))) return st;
    char sensor[64] = "";
    if ((st = json_string(j, at, "sensor", 0, sensor, sizeof sensor))) return st;
    if (sensor[0] && (rs.sensor = film_sensor_find(sensor)) < 0)
        return err_set(BRUME_ERROR_PARSE, "%s: render.sensor: unknown sensor '%s' (known: cie1931 and pbrt-v4's cameras, "
                       "docs/scene-format.md)", at.file, sensor);
    char device[32] = "";
    if ((st = json_string(j, at, "device", 0, device, sizeof device))) return st;
    if (device[0] && brume_device_from_name(NULL, device, &rs.device) != BRUME_OK)
        return err_set(BRUME_ERROR_PARSE, "%s: render.device: unknown device '%s' (known: cpu, cuda, cuda:N)", at.file,
                       device);
    /* spp is the maximum under a budget; a budget given without it has none (docs/render-jobs.md) */
    if (!cJSON_HasObjectItem(j, "spp") && (rs.time_budget > 0.0 || rs.noise_target > 0.0))
        rs.spp = 1 << 24;
    char sampler[32] = "";
    if ((st = json_string(j, at, "sampler", 0, sampler, sizeof sampler))) return st;
    if (strcmp(sampler, "sobol") == 0)
        rs.sampler = BRUME_SAMPLER_SOBOL;
    else if (strcmp(sampler, "independent") == 0)
        rs.sampler = BRUME_SAMPLER_INDEPENDENT;
    else if (cJSON_HasObjectItem(j, "sampler"))
        return err_set(BRUME_ERROR_PARSE, "%s: render.sampler: unknown sampler '%s' (known: sobol, independent)",
                       at.file, sampler);
    const cJSON *f = cJSON_GetObjectItemCaseSensitive(j, "filter");
    if (f) {
        static const char *const fkeys[] = {"type", "width", NULL};
        jloc fat = {at.file, "render.filter"};
        if ((st = json_check_object(f, fat, fkeys))) return st;
        char type[32] = "";
        if ((st = json_string(f, fat, "type", 1, type, sizeof type))) return st;
        if (strcmp(type, "box") == 0) {
            rs.filter = BRUME_FILTER_BOX;
            rs.filter_width = 1.0;
        } else if (strcmp(type, "gaussian") == 0) {
            rs.filter = BRUME_FILTER_GAUSSIAN;
            rs.filter_width = 2.0;
        } else {
            return err_set(BRUME_ERROR_PARSE, "%s: render.filter.type: unknown filter '%s' (known: box, gaussian)",
                           at.file, type);
        }
        if ((st = json_number(f, fat, "width", 0, 1e-3, 16.0, &rs.filter_width))) return st;
    }
    return brume_scene_set_settings(NULL, s, &rs); /* names "FILE: render.KEY" */
}

/* "ignored": what the source asked for and the scene leaves out (a pbrt-v4 file read with
 * --lenient), one line each, kept for brume_scene_ignored. */
static brume_status parse_ignored(const cJSON *list, const char *file, brume_scene *s)
{
    if (!list)
        return BRUME_OK;
    int n = cJSON_IsArray(list) ? cJSON_GetArraySize(list) : -1;
    if (n < 0 || n > SCENE_MAX_IGNORED)
        return err_set(BRUME_ERROR_PARSE, "%s: ignored: expected an array of at most %d strings", file,
                       SCENE_MAX_IGNORED);
    if (!(s->ignored = calloc(n ? (size_t)n : 1, sizeof *s->ignored)))
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", file);
    for (const cJSON *i = list->child; i; i = i->next) {
        if (!cJSON_IsString(i) || strlen(i->valuestring) > 4096)
            return err_set(BRUME_ERROR_PARSE, "%s: ignored[%d]: expected a string of at most 4096 bytes", file,
                           s->nignored);
        size_t len = strlen(i->valuestring) + 1;
        if (!(s->ignored[s->nignored] = malloc(len)))
            return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", file);
        memcpy(s->ignored[s->nignored], i->valuestring, len);
        s->nignored++;
    }
    return BRUME_OK;
}

/* The scene at time `time`, or at frame_no / render.fps when frame_no >= 0. Render settings come
 * first: a frame's time needs the frame rate. */
static brume_status parse_scene(const cJSON *root, brume_scene *s, double time, long frame_no)
{
    static const char *const keys[] = {"camera", "lights", "media", "surfaces", "background", "render", "path",
                                       "blasi", "stam", "ignored", NULL};
    const char *file = s->source;
    jloc top = {file, ""};
    brume_status st = json_check_object(root, top, keys);
    if (st) return st;
    const cJSON *render = cJSON_GetObjectItemCaseSensitive(root, "render");
    if (render && (st = parse_render(render, (jloc){file, "render"}, s))) return st;
    if ((st = scene_json_built(brume_scene_set_time(NULL, s, frame_no >= 0 ? (double)frame_no / s->settings.fps : time),
                               (jloc){file, "render.fps"})))
        return st;
    const cJSON *cam = cJSON_GetObjectItemCaseSensitive(root, "camera");
    if (!cam)
        return err_set(BRUME_ERROR_PARSE, "%s: camera: required key missing", file);
    if ((st = scene_parse_camera(cam, (jloc){file, "camera"}, s))) return st;
    if ((st = scene_parse_background(root, top, s))) return st;

    const cJSON *lights = cJSON_GetObjectItemCaseSensitive(root, "lights");
    if (lights) {
        if (!cJSON_IsArray(lights))
            return err_set(BRUME_ERROR_PARSE, "%s: lights: expected an array", file);
        int n = cJSON_GetArraySize(lights);
        if (n > SCENE_MAX_LIGHTS)
            return err_set(BRUME_ERROR_RANGE, "%s: lights: %d lights, at most %d", file, n, SCENE_MAX_LIGHTS);
        int i = 0;
        for (const cJSON *l = lights->child; l; l = l->next, i++) {
            char kp[64];
            snprintf(kp, sizeof kp, "lights[%d]", i);
            if (cJSON_IsObject(l) && cJSON_HasObjectItem(l, "keyframes")) {
                /* lights are evaluated once per frame, at the frame time */
                cJSON *now = NULL;
                if ((st = keys_object_at(l, (jloc){file, kp}, s->time, &now))) return st;
                st = scene_parse_light(now, (jloc){file, kp}, s);
                cJSON_Delete(now);
                if (st) return st;
                if ((st = brume_scene_set_animated(NULL, s))) return st;
            } else if ((st = scene_parse_light(l, (jloc){file, kp}, s))) {
                return st;
            }
        }
    }
    const cJSON *media = cJSON_GetObjectItemCaseSensitive(root, "media");
    if (media) {
        if (!cJSON_IsArray(media))
            return err_set(BRUME_ERROR_PARSE, "%s: media: expected an array", file);
        int n = cJSON_GetArraySize(media);
        if (n > SCENE_MAX_MEDIA)
            return err_set(BRUME_ERROR_RANGE, "%s: media: %d media, at most %d", file, n, SCENE_MAX_MEDIA);
        int i = 0;
        for (const cJSON *m = media->child; m; m = m->next, i++) {
            char kp[64];
            snprintf(kp, sizeof kp, "media[%d]", i);
            if ((st = scene_parse_medium(m, (jloc){file, kp}, s))) return st;
        }
    }
    const cJSON *surf = cJSON_GetObjectItemCaseSensitive(root, "surfaces");
    if (surf && (st = scene_parse_surfaces(surf, file, s))) return st;
    if ((st = parse_ignored(cJSON_GetObjectItemCaseSensitive(root, "ignored"), file, s))) return st;
    return scene_parse_method_options(root, top, s);
}

brume_status scene_parse_json(const char *text, const char *source, brume_scene **out)
{
    return scene_parse_json_at(text, source, 0.0, -1, out);
}

brume_status scene_parse_json_at(const char *text, const char *source, double time, long frame_no, brume_scene **out)
{
    return scene_parse_json_with(text, source, time, frame_no, NULL, 0, out);
}

brume_status scene_parse_json_with(const char *text, const char *source, double time, long frame_no,
                                   const char *const *overrides, int noverrides, brume_scene **out)
{
    *out = NULL;
    cJSON *root = NULL;
    brume_status st = json_parse(text, source, &root);
    if (st)
        return st;
    /* overrides edit the document, so the one reader below validates them (scene/scene_override.c) */
    if ((st = scene_apply_overrides(root, source, overrides, noverrides))) {
        cJSON_Delete(root);
        return st;
    }
    brume_scene *s = scene_new(source);
    if (!s) {
        cJSON_Delete(root);
        return err_status();
    }
    budget_begin(BUDGET_DEFAULT_BYTES);
    io_inputs_record(&s->inputs);
    st = parse_scene(root, s, time, frame_no);
    io_inputs_record(NULL);
    s->max_memory = budget_limit();
    s->memory_used = budget_used();
    budget_end();
    cJSON_Delete(root);
    if (st) {
        scene_override_annotate(overrides, noverrides);
        brume_scene_release(s);
        return st;
    }
    *out = s;
    return BRUME_OK;
}
