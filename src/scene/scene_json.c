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

#define SCENE_FILE_MAX_BYTES (64L << 20)

static const double BIG = 1e30;

/* Helpers between JSON values and the builders' plain arrays. */
static brume_status jvec(const cJSON *j, jloc at, const char *key, int required, double out[3])
{
    vec3 v = v3(out[0], out[1], out[2]);
    brume_status st = json_vec3(j, at, key, required, &v);
    if (st == BRUME_OK)
        v3_to_array(v, out);
    return st;
}

static brume_status jcolor(const cJSON *j, jloc at, const char *key, int required, double hi, double out[3])
{
    color c = col_rgb(out[0], out[1], out[2]);
    brume_status st = json_color(j, at, key, required, 0.0, hi, &c);
    for (int i = 0; st == BRUME_OK && i < 3; i++)
        out[i] = c.c[i];
    return st;
}

/* A builder's failure, prefixed with the file and the key path of what it was building. */
static brume_status built(brume_status st, jloc at)
{
    return st ? err_prefix("%s: %s", at.file, at.path) : BRUME_OK;
}

static brume_status parse_unit_vector(const cJSON *j, jloc at, const char *key, double out[3])
{
    brume_status st = jvec(j, at, key, 1, out);
    if (st)
        return st;
    if (!(v3_length(v3(out[0], out[1], out[2])) > 0.0))
        return err_set(BRUME_ERROR_RANGE, "%s: %s.%s: must not be the zero vector", at.file, at.path, key);
    return BRUME_OK;
}

static brume_status parse_camera(const cJSON *j, jloc at, brume_scene *s)
{
    static const char *const keys[] = {"position", "look_at", "up", "fov", "aperture_radius", "focus_distance",
                                       "shutter", "keyframes", "frame", "frame_margin", NULL};
    brume_status st = json_check_object(j, at, keys);
    if (st) return st;
    brume_camera c;
    brume_camera_default(&c);
    char framed[64] = "";
    double margin = 0.1, box[6];
    const cJSON *fj = cJSON_GetObjectItemCaseSensitive(j, "frame");
    bool framed_box = cJSON_IsArray(fj); /* [[x0, y0, z0], [x1, y1, z1]]: a box, not the media */
    for (int k = 0; framed_box && k < 6; k++) {
        const cJSON *corner = cJSON_GetArraySize(fj) == 2 ? cJSON_GetArrayItem(fj, k / 3) : NULL;
        const cJSON *v = cJSON_IsArray(corner) && cJSON_GetArraySize(corner) == 3 ? cJSON_GetArrayItem(corner, k % 3) : NULL;
        if (!cJSON_IsNumber(v))
            return err_set(BRUME_ERROR_PARSE, "%s: camera.frame: a box is [[x0, y0, z0], [x1, y1, z1]]", at.file);
        box[k] = v->valuedouble;
        snprintf(framed, sizeof framed, "media");
    }
    if (!framed_box && (st = json_string(j, at, "frame", 0, framed, sizeof framed)))
        return st;
    if ((st = json_number(j, at, "frame_margin", 0, 0.0, 0.9, &margin))) return st;
    if ((st = jvec(j, at, "up", 0, c.up))) return st;
    if (!(v3_length(v3(c.up[0], c.up[1], c.up[2])) > 0.0))
        return err_set(BRUME_ERROR_RANGE, "%s: camera.up: must not be the zero vector", at.file);
    if (framed[0] && !cJSON_HasObjectItem(j, "position") && !cJSON_HasObjectItem(j, "look_at"))
        scene_studio_direction(c.up, c.position, c.look_at); /* framed: only the direction counts */
    else if ((st = jvec(j, at, "position", 1, c.position)) || (st = jvec(j, at, "look_at", 1, c.look_at)))
        return st;
    if (!framed[0] && cJSON_HasObjectItem(j, "frame_margin"))
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: camera.frame_margin: only with camera.frame", at.file);
    if ((st = json_number(j, at, "fov", 0, 1e-3, 179.0, &c.fov))) return st;
    if ((st = json_number(j, at, "aperture_radius", 0, 0.0, BIG, &c.aperture_radius))) return st;
    if ((st = json_number(j, at, "focus_distance", 0, 1e-9, BIG, &c.focus_distance))) return st;
    const cJSON *sh = cJSON_GetObjectItemCaseSensitive(j, "shutter");
    if (sh) {
        if (!cJSON_IsArray(sh) || cJSON_GetArraySize(sh) != 2 || !cJSON_IsNumber(cJSON_GetArrayItem(sh, 0)) ||
            !cJSON_IsNumber(cJSON_GetArrayItem(sh, 1)))
            return err_set(BRUME_ERROR_PARSE, "%s: camera.shutter: expected [open, close] in seconds", at.file);
        c.shutter_open = cJSON_GetArrayItem(sh, 0)->valuedouble;
        c.shutter_close = cJSON_GetArrayItem(sh, 1)->valuedouble;
        if (!isfinite(c.shutter_open) || !isfinite(c.shutter_close) || c.shutter_close < c.shutter_open)
            return err_set(BRUME_ERROR_RANGE, "%s: camera.shutter: need finite open <= close, got [%g, %g]", at.file,
                           c.shutter_open, c.shutter_close);
    }
    if ((st = built(brume_scene_set_camera(NULL, s, &c), at))) return st;
    if (framed[0] && !framed_box && (st = built(brume_scene_frame_camera(NULL, s, framed, margin), at))) return st;
    if (framed_box && (st = built(brume_scene_frame_camera_box(NULL, s, box, margin), at))) return st;
    const cJSON *keys_j = cJSON_GetObjectItemCaseSensitive(j, "keyframes");
    if (!keys_j)
        return BRUME_OK;
    /* keys_parse_camera completes each key from the others and from the camera */
    jloc kat = {at.file, "camera.keyframes"};
    camera *tmp = malloc(sizeof *tmp);
    brume_camera_key *bk = malloc(sizeof *bk * CAMERA_MAX_KEYS);
    if (!tmp || !bk) {
        free(tmp);
        free(bk);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", at.file);
    }
    *tmp = s->cam;
    st = keys_parse_camera(keys_j, kat, tmp, cJSON_HasObjectItem(j, "focus_distance"));
    for (int i = 0; st == BRUME_OK && i < tmp->nkeys; i++) {
        const camera_key *k = &tmp->keys[i];
        bk[i].time = k->time;
        v3_to_array(k->position, bk[i].position);
        v3_to_array(k->look_at, bk[i].look_at);
        v3_to_array(k->up, bk[i].up);
        bk[i].fov = k->fov;
        bk[i].aperture_radius = k->aperture_radius;
        bk[i].focus_distance = k->focus_distance;
    }
    if (st == BRUME_OK)
        st = built(brume_scene_set_camera_keys(NULL, s, bk, tmp->nkeys), kat);
    free(tmp);
    free(bk);
    return st;
}

/* A spot's goniometric profile: [[angle_deg, factor], ...] with increasing angles. */
static brume_status parse_profile(const cJSON *j, jloc at, double *angle, double *factor, int *n_out)
{
    const cJSON *pr = cJSON_GetObjectItemCaseSensitive(j, "profile");
    int n = cJSON_GetArraySize(pr);
    if (!cJSON_IsArray(pr) || n < 2 || n > LIGHT_PROFILE_MAX)
        return err_set(BRUME_ERROR_PARSE, "%s: %s.profile: expected 2 to %d pairs [angle_deg, factor]", at.file,
                       at.path, LIGHT_PROFILE_MAX);
    int i = 0;
    for (const cJSON *e = pr->child; e; e = e->next, i++) {
        const cJSON *a = cJSON_GetArrayItem(e, 0), *v = cJSON_GetArrayItem(e, 1);
        if (!cJSON_IsArray(e) || cJSON_GetArraySize(e) != 2 || !cJSON_IsNumber(a) || !cJSON_IsNumber(v))
            return err_set(BRUME_ERROR_PARSE, "%s: %s.profile[%d]: expected [angle_deg, factor]", at.file, at.path, i);
        double ang = a->valuedouble, val = v->valuedouble;
        if (!isfinite(ang) || ang < 0.0 || ang > 180.0 || (i > 0 && !(ang > angle[i - 1])))
            return err_set(BRUME_ERROR_RANGE, "%s: %s.profile[%d]: angle %g must increase within [0, 180]", at.file,
                           at.path, i, ang);
        if (!isfinite(val) || val < 0.0)
            return err_set(BRUME_ERROR_RANGE, "%s: %s.profile[%d]: factor %g must be finite and >= 0", at.file,
                           at.path, i, val);
        angle[i] = ang;
        factor[i] = val;
    }
    *n_out = n;
    return BRUME_OK;
}

static brume_status parse_light(const cJSON *j, jloc at, brume_scene *s)
{
    char type[32];
    brume_status st = json_object_type(j, at, type, sizeof type);
    if (st) return st;
    double pos[3] = {0, 0, 0}, dir[3] = {0, 0, 0}, L[3] = {0, 0, 0};
    if (strcmp(type, "distant") == 0) {
        static const char *const keys[] = {"type", "direction", "irradiance", "angular_radius", NULL};
        if ((st = json_check_object(j, at, keys))) return st;
        if ((st = parse_unit_vector(j, at, "direction", dir))) return st;
        double deg = 0.0;
        if ((st = json_number(j, at, "angular_radius", 0, 0.0, 90.0, &deg))) return st;
        if ((st = jcolor(j, at, "irradiance", 1, BIG, L))) return st;
        return built(brume_scene_add_distant_light(NULL, s, dir, L, deg), at);
    }
    if (strcmp(type, "point") == 0) {
        static const char *const keys[] = {"type", "position", "intensity", NULL};
        if ((st = json_check_object(j, at, keys))) return st;
        if ((st = jvec(j, at, "position", 1, pos))) return st;
        if ((st = jcolor(j, at, "intensity", 1, BIG, L))) return st;
        return built(brume_scene_add_point_light(NULL, s, pos, L), at);
    }
    if (strcmp(type, "spot") == 0) {
        static const char *const keys[] = {"type", "position", "direction", "intensity", "cone_angle",
                                           "falloff_start", "profile", NULL};
        if ((st = json_check_object(j, at, keys))) return st;
        if ((st = jvec(j, at, "position", 1, pos))) return st;
        if ((st = parse_unit_vector(j, at, "direction", dir))) return st;
        if ((st = jcolor(j, at, "intensity", 1, BIG, L))) return st;
        if (cJSON_HasObjectItem(j, "profile")) {
            if (cJSON_HasObjectItem(j, "cone_angle") || cJSON_HasObjectItem(j, "falloff_start"))
                return err_set(BRUME_ERROR_PARSE, "%s: %s: give either profile or cone_angle/falloff_start", at.file,
                               at.path);
            double *ang = malloc(sizeof *ang * 2 * LIGHT_PROFILE_MAX);
            if (!ang)
                return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", at.file);
            int n = 0;
            st = parse_profile(j, at, ang, ang + LIGHT_PROFILE_MAX, &n);
            if (st == BRUME_OK)
                st = built(brume_scene_add_spot_light_profile(NULL, s, pos, dir, L, ang, ang + LIGHT_PROFILE_MAX, n), at);
            free(ang);
            return st;
        }
        double cone = 30.0, start;
        if ((st = json_number(j, at, "cone_angle", 0, 0.01, 180.0, &cone))) return st;
        start = cone;
        if ((st = json_number(j, at, "falloff_start", 0, 0.0, cone, &start))) return st;
        return built(brume_scene_add_spot_light(NULL, s, pos, dir, L, cone, start), at);
    }
    if (strcmp(type, "sphere") == 0 || strcmp(type, "disk") == 0) {
        static const char *const skeys[] = {"type", "position", "radius", "radiance", NULL};
        static const char *const dkeys[] = {"type", "position", "direction", "radius", "radiance", NULL};
        bool sphere = type[0] == 's';
        double radius = 0.0;
        if ((st = json_check_object(j, at, sphere ? skeys : dkeys))) return st;
        if ((st = jvec(j, at, "position", 1, pos))) return st;
        if (!sphere && (st = parse_unit_vector(j, at, "direction", dir))) return st;
        if ((st = json_number(j, at, "radius", 1, 1e-9, BIG, &radius))) return st;
        if ((st = jcolor(j, at, "radiance", 1, BIG, L))) return st;
        return built(sphere ? brume_scene_add_sphere_light(NULL, s, pos, radius, L)
                            : brume_scene_add_disk_light(NULL, s, pos, dir, radius, L),
                     at);
    }
    return err_set(BRUME_ERROR_PARSE,
                   "%s: %s.type: unknown light type '%s' (known: distant, point, spot, sphere, disk)", at.file,
                   at.path, type);
}

/* "background": a color, or {"color": c} or {"file": "env.exr", "scale": s, "up": [...]} */
static brume_status parse_background(const cJSON *root, jloc top, brume_scene *s)
{
    const cJSON *b = cJSON_GetObjectItemCaseSensitive(root, "background");
    jloc at = {top.file, "background"};
    double L[3] = {0, 0, 0};
    if (!b)
        return BRUME_OK;
    brume_status st;
    if (!cJSON_IsObject(b)) {
        if ((st = jcolor(root, top, "background", 0, BIG, L))) return st;
        return built(brume_scene_set_background_color(NULL, s, L), at);
    }
    static const char *const keys[] = {"color", "file", "scale", "up", NULL};
    if ((st = json_check_object(b, at, keys))) return st;
    double scale = 1.0, up[3] = {0, 1, 0};
    if ((st = jcolor(b, at, "color", 0, BIG, L))) return st;
    if ((st = json_number(b, at, "scale", 0, 0.0, BIG, &scale))) return st;
    if (cJSON_HasObjectItem(b, "up") && (st = parse_unit_vector(b, at, "up", up))) return st;
    char name[1024], path[2048];
    name[0] = '\0';
    if ((st = json_string(b, at, "file", 0, name, sizeof name))) return st;
    if (!name[0])
        return built(brume_scene_set_background_color(NULL, s, L), at);
    if (cJSON_HasObjectItem(b, "color"))
        return err_set(BRUME_ERROR_PARSE, "%s: background: give either color or file", top.file);
    json_resolve_path(top.file, name, path, sizeof path);
    brume_context *ctx = brume_context_new();
    brume_image *img = NULL;
    st = ctx ? brume_image_read(ctx, path, &img) : BRUME_ERROR_OUT_OF_MEMORY;
    if (st)
        err_set(st, "%s: background.file: %.1000s", top.file, ctx ? brume_context_last_error(ctx) : "out of memory");
    brume_context_release(ctx);
    if (st) return st;
    st = built(brume_scene_set_background_image(NULL, s, img, scale, up), at);
    brume_image_release(img);
    return st;
}

static brume_status parse_box(const cJSON *j, jloc at, const char *key, double out[6])
{
    char kp[256];
    json_key_path(kp, sizeof kp, at.path, key);
    const cJSON *it = cJSON_GetObjectItemCaseSensitive(j, key);
    if (!it)
        return BRUME_OK;
    if (!cJSON_IsArray(it) || cJSON_GetArraySize(it) != 2)
        return err_set(BRUME_ERROR_PARSE, "%s: %s: expected [[xmin, ymin, zmin], [xmax, ymax, zmax]]", at.file, kp);
    cJSON *wrap = cJSON_CreateObject();
    if (!wrap)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", at.file);
    cJSON_AddItemReferenceToObject(wrap, "lo", cJSON_GetArrayItem(it, 0));
    cJSON_AddItemReferenceToObject(wrap, "hi", cJSON_GetArrayItem(it, 1));
    jloc sub = {at.file, kp};
    double r[6];
    brume_status st = jvec(wrap, sub, "lo", 1, r);
    if (!st)
        st = jvec(wrap, sub, "hi", 1, r + 3);
    cJSON_Delete(wrap);
    if (st)
        return st;
    if (!(r[0] < r[3] && r[1] < r[4] && r[2] < r[5]))
        return err_set(BRUME_ERROR_RANGE, "%s: %s: need min < max on every axis", at.file, kp);
    memcpy(out, r, sizeof r);
    return BRUME_OK;
}

static brume_status parse_filter(const cJSON *j, jloc at, brume_grid_filter *f)
{
    char name[32] = "";
    brume_status st = json_string(j, at, "filter", 0, name, sizeof name);
    if (st || !name[0])
        return st;
    if (strcmp(name, "nearest") == 0)
        *f = BRUME_GRID_NEAREST;
    else if (strcmp(name, "trilinear") == 0)
        *f = BRUME_GRID_TRILINEAR;
    else
        return err_set(BRUME_ERROR_PARSE, "%s: %s.filter: unknown filter '%s' (known: nearest, trilinear)", at.file,
                       at.path, name);
    return BRUME_OK;
}

/* The scene's frame number: the frame it was loaded at, or its time in frames. */
static long scene_frame_number(const brume_scene *s)
{
    return lround(s->time * s->settings.fps);
}

/* A grid file name with a frame pattern (io/grid_sequence.h): the frame's file into path,
 * from frame_offset, frame_step and beyond. Without a pattern those keys are errors. */
static brume_status parse_sequence(const cJSON *j, jloc at, const char *name, long frame_no, char *path, size_t cap)
{
    int pat = seq_is_pattern(name);
    if (pat < 0)
        return err_prefix("%s: %s.file", at.file, at.path);
    if (!pat) {
        static const char *const seq_keys[] = {"frame_offset", "frame_step", "beyond"};
        for (int k = 0; k < 3; k++)
            if (cJSON_HasObjectItem(j, seq_keys[k]))
                return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: %s.%s: only with a frame pattern in file (%%04d, ####, $F4)",
                               at.file, at.path, seq_keys[k]);
        return BRUME_OK;
    }
    seq_options so = {0, 1, SEQ_REFUSE};
    double offset = 0.0, step = 1.0;
    char beyond[16] = "refuse";
    brume_status st;
    if ((st = json_number(j, at, "frame_offset", 0, -1e9, 1e9, &offset))) return st;
    if ((st = json_number(j, at, "frame_step", 0, 1.0, 1e6, &step))) return st;
    if (offset != floor(offset) || step != floor(step))
        return err_set(BRUME_ERROR_RANGE, "%s: %s.%s: must be an integer", at.file, at.path,
                       offset != floor(offset) ? "frame_offset" : "frame_step");
    if ((st = json_string(j, at, "beyond", 0, beyond, sizeof beyond))) return st;
    if (!seq_beyond_from_name(beyond, &so.beyond))
        return err_set(BRUME_ERROR_PARSE, "%s: %s.beyond: unknown '%s' (known: refuse, hold, loop)", at.file, at.path,
                       beyond);
    so.offset = (long)offset;
    so.step = (long)step;
    char pattern[2048];
    snprintf(pattern, sizeof pattern, "%s", path);
    if (seq_file(pattern, &so, frame_no, path, cap) != BRUME_OK)
        return err_prefix("%s: %s.file", at.file, at.path);
    return BRUME_OK;
}

/* The file and loading options of a grid object (a density of type "grid", or a medium's
 * field) at scene frame `frame`; `extra` lists keys the caller handles itself. */
static brume_status parse_grid_options(const cJSON *j, jloc at, const char *const *extra, long frame_no, char *path,
                                       size_t cap, brume_grid_file_options *o, bool *sequence)
{
    static const char *const base[] = {"type", "file", "grid", "format", "dims", "bounds", "transform", "filter",
                                       "scale", "max_memory_mb", "frame_offset", "frame_step", "beyond"};
    const char *keys[24];
    int nk = 0;
    for (size_t k = 0; k < sizeof base / sizeof *base; k++)
        keys[nk++] = base[k];
    for (int k = 0; extra && extra[k] && nk < 23; k++)
        keys[nk++] = extra[k];
    keys[nk] = NULL;
    brume_status st = json_check_object(j, at, keys);
    if (st) return st;
    brume_grid_file_options_default(o);
    char name[1024];
    if ((st = json_string(j, at, "file", 1, name, sizeof name))) return st;
    json_resolve_path(at.file, name, path, cap);
    if ((st = parse_sequence(j, at, name, frame_no, path, cap))) return st;
    *sequence = seq_is_pattern(name) == 1; /* a file per frame: the world is not static */
    if ((st = json_string(j, at, "grid", 0, o->grid, sizeof o->grid))) return st;
    char format[16] = "";
    if ((st = json_string(j, at, "format", 0, format, sizeof format))) return st;
    if (format[0]) {
        o->format = (brume_grid_format)grid_format_from_name(format);
        if (o->format == BRUME_GRID_FORMAT_AUTO && strcmp(format, "auto") != 0)
            return err_set(BRUME_ERROR_PARSE, "%s: %s.format: unknown grid format '%s' (known: auto, raw, df3, vol, "
                           "nvdb, vdb)", at.file, at.path, format);
    }
    if (cJSON_HasObjectItem(j, "dims")) {
        double d[3] = {0, 0, 0};
        if ((st = jvec(j, at, "dims", 1, d))) return st;
        for (int k = 0; k < 3; k++) {
            if (!(d[k] >= 1 && d[k] <= 65536) || d[k] != floor(d[k]))
                return err_set(BRUME_ERROR_RANGE, "%s: %s.dims[%d]: %g is not an integer in [1, 65536]", at.file,
                               at.path, k, d[k]);
            o->dims[k] = (int)d[k];
        }
    }
    if (cJSON_HasObjectItem(j, "bounds")) {
        if ((st = parse_box(j, at, "bounds", o->bounds))) return st;
        o->has_bounds = true;
    }
    const cJSON *tr = cJSON_GetObjectItemCaseSensitive(j, "transform");
    if (tr) {
        char kp[256];
        affine3 xf;
        if ((st = json_transform(tr, (jloc){at.file, json_key_path(kp, sizeof kp, at.path, "transform")}, true, &xf)))
            return st;
        memcpy(o->transform, xf.m, sizeof o->transform);
        o->has_transform = true;
    }
    if ((st = parse_filter(j, at, &o->filter))) return st;
    if ((st = json_number(j, at, "scale", 0, 1e-30, 1e30, &o->scale))) return st;
    if ((st = json_number(j, at, "max_memory_mb", 0, 1.0, 1e9, &o->max_memory_mb))) return st;
    return BRUME_OK;
}

/* A voxel grid from a file (docs/grids.md lists the formats). */
static brume_status parse_grid_density(const cJSON *j, jloc at, const brume_scene *s, brume_density **out)
{
    brume_grid_file_options o;
    char path[2048];
    bool sequence = false;
    brume_status st = parse_grid_options(j, at, NULL, scene_frame_number(s), path, sizeof path, &o, &sequence);
    if (st) return st;
    st = brume_density_load(NULL, path, &o, out);
    if (st == BRUME_OK && sequence)
        (*out)->evolves = true; /* frames differ: the scene is loaded again for each */
    return st ? err_prefix("%s: %s.file", at.file, at.path) : BRUME_OK;
}

/* A voxel grid given inline: `dims` [nx, ny, nz], `data` nx ny nz numbers >= 0, x fastest
 * (brume_density_new_array's layout), placed by `bounds` then `transform` as a grid file is. */
static brume_status parse_array_density(const cJSON *j, jloc at, brume_density **out)
{
    static const char *const keys[] = {"type", "dims", "data", "bounds", "transform", "filter", NULL};
    brume_status st = json_check_object(j, at, keys);
    if (st) return st;
    double d[3] = {0, 0, 0}, b[6] = {-1, -1, -1, 1, 1, 1};
    if ((st = jvec(j, at, "dims", 1, d))) return st;
    for (int k = 0; k < 3; k++)
        if (!(d[k] >= 1 && d[k] <= 65536) || d[k] != floor(d[k]))
            return err_set(BRUME_ERROR_RANGE, "%s: %s.dims[%d]: %g is not an integer in [1, 65536]", at.file, at.path,
                           k, d[k]);
    double count = d[0] * d[1] * d[2];
    if (count > SCENE_INLINE_MAX_VALUES)
        return err_set(BRUME_ERROR_RANGE, "%s: %s.dims: %g x %g x %g voxels, over the %d an inline grid may hold "
                       "(a larger grid belongs in a file)", at.file, at.path, d[0], d[1], d[2], SCENE_INLINE_MAX_VALUES);
    const cJSON *data = cJSON_GetObjectItemCaseSensitive(j, "data");
    if (!cJSON_IsArray(data))
        return err_set(BRUME_ERROR_PARSE, "%s: %s.data: expected an array of nx ny nz numbers", at.file, at.path);
    int n = cJSON_GetArraySize(data);
    if (n != (int)count)
        return err_set(BRUME_ERROR_RANGE, "%s: %s.data: %d values for dims %g x %g x %g (%g)", at.file, at.path, n,
                       d[0], d[1], d[2], count);
    if ((st = parse_box(j, at, "bounds", b))) return st;
    brume_grid_filter filter = BRUME_GRID_TRILINEAR;
    if ((st = parse_filter(j, at, &filter))) return st;
    affine3 xf;
    char kp[256];
    const cJSON *tr = cJSON_GetObjectItemCaseSensitive(j, "transform");
    if (tr && (st = json_transform(tr, (jloc){at.file, json_key_path(kp, sizeof kp, at.path, "transform")}, true, &xf)))
        return st;
    float *v = malloc((size_t)n * sizeof *v);
    if (!v)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: %s.data: out of memory", at.file, at.path);
    int i = 0;
    for (const cJSON *e = data->child; e; e = e->next, i++)
        if (!cJSON_IsNumber(e) || !(e->valuedouble >= 0.0 && e->valuedouble <= 1e30)) {
            free(v);
            return err_set(BRUME_ERROR_RANGE, "%s: %s.data[%d]: expected a number in [0, 1e30]", at.file, at.path, i);
        } else {
            v[i] = (float)e->valuedouble;
        }
    st = brume_density_new_array(NULL, v, (int)d[0], (int)d[1], (int)d[2], b, filter, NULL, NULL, out);
    free(v);
    if (st)
        return err_prefix("%s: %s", at.file, at.path);
    if (tr) { /* after the bounds, as a grid file's `transform` */
        density_info info;
        density_get_info((*out)->d, &info);
        affine3 v2w = affine3_compose(&xf, &info.voxel_to_world);
        if (!density_place((*out)->d, &v2w)) {
            brume_density_release(*out);
            *out = NULL;
            return err_prefix("%s: %s.transform", at.file, at.path);
        }
    }
    return BRUME_OK;
}

/* A fractal cloud grid generated at load time (src/density/fractal.h, Blasi 4.1), at the
 * scene's frame time added to its own `time`: the threshold and the turbulence evolve. */
static brume_status parse_fractal_density(const cJSON *j, jloc at, const brume_scene *s, brume_density **out)
{
    static const char *const keys[] = {"type", "dims", "seed", "method", "hurst", "octaves", "frequency", "shape",
                                       "falloff", "threshold", "threshold_rate", "turbulence",
                                       "turbulence_frequency", "wind", "time", "density", "bounds", "filter", NULL};
    brume_status st = json_check_object(j, at, keys);
    if (st) return st;
    brume_fractal p;
    brume_fractal_default(&p);
    double d[3] = {p.dims[0], p.dims[1], p.dims[2]};
    if ((st = jvec(j, at, "dims", 0, d))) return st;
    for (int k = 0; k < 3; k++) {
        if (!(d[k] >= 1 && d[k] <= 1024) || d[k] != floor(d[k]))
            return err_set(BRUME_ERROR_RANGE, "%s: %s.dims[%d]: %g is not an integer in [1, 1024]", at.file, at.path,
                           k, d[k]);
        p.dims[k] = (int)d[k];
    }
    char m[32] = "", sh[32] = "";
    if ((st = json_u64(j, at, "seed", 0, &p.seed))) return st;
    if ((st = json_string(j, at, "method", 0, m, sizeof m))) return st;
    if (m[0]) {
        if (strcmp(m, "midpoint") == 0) p.method = BRUME_FRACTAL_MIDPOINT;
        else if (strcmp(m, "spectral") == 0) p.method = BRUME_FRACTAL_SPECTRAL;
        else if (strcmp(m, "perlin") == 0) p.method = BRUME_FRACTAL_PERLIN;
        else
            return err_set(BRUME_ERROR_PARSE, "%s: %s.method: unknown method '%s' (known: midpoint, spectral, perlin)",
                           at.file, at.path, m);
    }
    if ((st = json_string(j, at, "shape", 0, sh, sizeof sh))) return st;
    if (sh[0]) {
        if (strcmp(sh, "none") == 0) p.shape = BRUME_FRACTAL_SHAPE_NONE;
        else if (strcmp(sh, "ellipsoid") == 0) p.shape = BRUME_FRACTAL_SHAPE_ELLIPSOID;
        else if (strcmp(sh, "slab") == 0) p.shape = BRUME_FRACTAL_SHAPE_SLAB;
        else
            return err_set(BRUME_ERROR_PARSE, "%s: %s.shape: unknown shape '%s' (known: none, ellipsoid, slab)",
                           at.file, at.path, sh);
    }
    if ((st = json_number(j, at, "hurst", 0, 1e-3, 0.999, &p.hurst))) return st;
    if ((st = json_int(j, at, "octaves", 0, 1, 16, &p.octaves))) return st;
    if ((st = json_number(j, at, "frequency", 0, 1e-3, 1e3, &p.frequency))) return st;
    if ((st = json_number(j, at, "falloff", 0, 1e-3, 1.0, &p.falloff))) return st;
    if ((st = json_number(j, at, "threshold", 0, 0.0, 0.99, &p.threshold))) return st;
    if ((st = json_number(j, at, "threshold_rate", 0, -1e3, 1e3, &p.threshold_rate))) return st;
    if ((st = json_number(j, at, "turbulence", 0, 0.0, 1e3, &p.turbulence))) return st;
    if ((st = json_number(j, at, "turbulence_frequency", 0, 1e-3, 1e3, &p.turbulence_frequency))) return st;
    if ((st = jvec(j, at, "wind", 0, p.wind))) return st;
    if ((st = json_number(j, at, "time", 0, -1e9, 1e9, &p.time))) return st;
    if ((st = json_number(j, at, "density", 0, 1e-9, 1e9, &p.density))) return st;
    if ((st = parse_box(j, at, "bounds", p.bounds))) return st;
    if ((st = parse_filter(j, at, &p.filter))) return st;
    p.time += brume_scene_time(s);
    return built(brume_density_new_fractal(NULL, &p, out), at);
}

static brume_status parse_density(const cJSON *j, jloc at, const brume_scene *s, brume_density **out)
{
    char type[32];
    brume_status st = json_object_type(j, at, type, sizeof type);
    if (st) return st;
    if (strcmp(type, "procedural_cloud") == 0) {
        static const char *const keys[] = {"type", "resolution", "seed", "bounds", NULL};
        if ((st = json_check_object(j, at, keys))) return st;
        int res = 64;
        uint64_t seed = 1;
        double b[6] = {-1, -1, -1, 1, 1, 1};
        if ((st = json_int(j, at, "resolution", 0, 2, 512, &res))) return st;
        if ((st = json_u64(j, at, "seed", 0, &seed))) return st;
        if ((st = parse_box(j, at, "bounds", b))) return st;
        return built(brume_density_new_procedural_cloud(NULL, res, seed, b, out), at);
    }
    if (strcmp(type, "blobs") == 0)
        return scene_parse_blobs(j, at, out); /* Stam's gaussian blobs (scene/scene_stam.c) */
    if (strcmp(type, "constant") == 0) {
        /* homogeneous fog filling a box */
        static const char *const keys[] = {"type", "value", "bounds", NULL};
        if ((st = json_check_object(j, at, keys))) return st;
        double value = 1.0, b[6] = {-1, -1, -1, 1, 1, 1};
        if ((st = json_number(j, at, "value", 0, 0.0, 1e30, &value))) return st;
        if ((st = parse_box(j, at, "bounds", b))) return st;
        return built(brume_density_new_constant(NULL, value, b, out), at);
    }
    if (strcmp(type, "grid") == 0)
        return parse_grid_density(j, at, s, out);
    if (strcmp(type, "array") == 0)
        return parse_array_density(j, at, out);
    if (strcmp(type, "fractal_cloud") == 0)
        return parse_fractal_density(j, at, s, out);
    return err_set(BRUME_ERROR_PARSE,
                   "%s: %s.type: unknown density type '%s' (known: constant, procedural_cloud, grid, array, fractal_cloud, blobs)",
                   at.file, at.path, type);
}

#define PHASE_MAX_LOBES 16

static brume_status parse_phase(const cJSON *j, jloc at, brume_phase **out)
{
    char type[32];
    *out = NULL;
    brume_status st = json_object_type(j, at, type, sizeof type);
    if (st) return st;
    static const char *const type_only[] = {"type", NULL};
    static const struct { const char *name; brume_phase_preset preset; } presets[] = {
        {"isotropic", BRUME_PHASE_ISOTROPIC}, {"rayleigh", BRUME_PHASE_RAYLEIGH}, {"hazy", BRUME_PHASE_HAZY},
        {"murky", BRUME_PHASE_MURKY}};
    for (size_t i = 0; i < sizeof presets / sizeof presets[0]; i++)
        if (strcmp(type, presets[i].name) == 0) {
            if ((st = json_check_object(j, at, type_only))) return st;
            return built(brume_phase_new_preset(NULL, presets[i].preset, out), at);
        }
    if (strcmp(type, "hg") == 0) {
        static const char *const keys[] = {"type", "g", NULL};
        if ((st = json_check_object(j, at, keys))) return st;
        double g = 0.0;
        if ((st = json_number(j, at, "g", 1, -0.999999, 0.999999, &g))) return st;
        return built(brume_phase_new_hg(NULL, g, out), at);
    }
    if (strcmp(type, "schlick") == 0) {
        /* k directly, or g converted by k = 1.55 g - 0.55 g^3 (docs/phase-functions.md) */
        static const char *const keys[] = {"type", "k", "g", NULL};
        if ((st = json_check_object(j, at, keys))) return st;
        int has_k = cJSON_HasObjectItem(j, "k"), has_g = cJSON_HasObjectItem(j, "g");
        if (has_k == has_g)
            return err_set(BRUME_ERROR_PARSE, "%s: %s: give exactly one of k and g", at.file, at.path);
        double v = 0.0;
        if ((st = json_number(j, at, has_k ? "k" : "g", 1, -0.999999, 0.999999, &v))) return st;
        return built(brume_phase_new_schlick(NULL, has_k ? v : phase_schlick_k_from_g(v), out), at);
    }
    if (strcmp(type, "schlick_mix") == 0) {
        /* Blasi Eq. 22: r schlick(k) + (1 - r) schlick(kprime) */
        static const char *const keys[] = {"type", "r", "k", "kprime", NULL};
        if ((st = json_check_object(j, at, keys))) return st;
        double r = 0.0, k = 0.0, kp = 0.0;
        if ((st = json_number(j, at, "r", 1, 0.0, 1.0, &r))) return st;
        if ((st = json_number(j, at, "k", 1, -0.999999, 0.999999, &k))) return st;
        if ((st = json_number(j, at, "kprime", 1, -0.999999, 0.999999, &kp))) return st;
        return built(brume_phase_new_schlick_mix(NULL, r, k, kp, out), at);
    }
    if (strcmp(type, "tabulated") == 0) {
        static const char *const keys[] = {"type", "file", NULL};
        if ((st = json_check_object(j, at, keys))) return st;
        char name[1024], path[2048];
        if ((st = json_string(j, at, "file", 1, name, sizeof name))) return st;
        json_resolve_path(at.file, name, path, sizeof path);
        return built(brume_phase_load(NULL, path, out), at);
    }
    if (strcmp(type, "mixture") == 0) {
        /* Blasi Eq. 20: a normalized sum of lobes, each {"weight": w, "phase": {...}} */
        static const char *const keys[] = {"type", "lobes", NULL};
        static const char *const lobe_keys[] = {"weight", "phase", NULL};
        if ((st = json_check_object(j, at, keys))) return st;
        const cJSON *lobes = cJSON_GetObjectItemCaseSensitive(j, "lobes");
        int n = cJSON_GetArraySize(lobes);
        if (!cJSON_IsArray(lobes) || n < 1 || n > PHASE_MAX_LOBES)
            return err_set(BRUME_ERROR_PARSE, "%s: %s.lobes: expected an array of 1 to %d lobes", at.file, at.path,
                           PHASE_MAX_LOBES);
        brume_phase *ph[PHASE_MAX_LOBES] = {0};
        double w[PHASE_MAX_LOBES];
        int i = 0;
        for (const cJSON *l = lobes->child; l && st == BRUME_OK; l = l->next, i++) {
            char kp[256], kp2[300];
            snprintf(kp, sizeof kp, "%s.lobes[%d]", at.path, i);
            jloc lat = {at.file, kp};
            if ((st = json_check_object(l, lat, lobe_keys))) break;
            if ((st = json_number(l, lat, "weight", 1, 0.0, 1e30, &w[i]))) break;
            const cJSON *lp = cJSON_GetObjectItemCaseSensitive(l, "phase");
            if (!lp) {
                st = err_set(BRUME_ERROR_PARSE, "%s: %s.phase: required key missing", at.file, kp);
                break;
            }
            snprintf(kp2, sizeof kp2, "%s.phase", kp);
            st = parse_phase(lp, (jloc){at.file, kp2}, &ph[i]);
        }
        if (st == BRUME_OK)
            st = built(brume_phase_new_mixture(NULL, w, ph, n, out), at);
        if (st)
            for (int k = 0; k < n; k++)
                brume_phase_release(ph[k]);
        return st;
    }
    return err_set(BRUME_ERROR_PARSE,
                   "%s: %s.type: unknown phase function '%s' (known: isotropic, rayleigh, hazy, murky, hg, "
                   "schlick, schlick_mix, mixture, tabulated)",
                   at.file, at.path, type);
}

/* How a field's grid is read: brume_density_load (one field), _load_rgb or _load_velocity
 * (three). */
typedef brume_status (*field_loader)(brume_context *, const char *, const brume_grid_file_options *, brume_density **);

/* A medium's field object ("albedo", "temperature", "emission_field", "velocity"): a grid
 * object whose keys default to the medium's grid density's (same file, placement, filter),
 * so that {"grid": "temperature"} is the temperature grid of the density's file. Loads the
 * fields by `load`. */
static brume_status parse_field(const cJSON *medium_j, jloc at, const brume_scene *s, const char *key,
                                const char *const *extra, field_loader load, brume_density **out,
                                brume_grid_file_options *used)
{
    char kp[256];
    jloc fat = {at.file, json_key_path(kp, sizeof kp, at.path, key)};
    const cJSON *f = cJSON_GetObjectItemCaseSensitive(medium_j, key);
    if (!cJSON_IsObject(f))
        return err_set(BRUME_ERROR_PARSE, "%s: %s: expected an object such as {\"grid\": \"NAME\"}", at.file, kp);
    cJSON *merged = cJSON_Duplicate(f, 1);
    if (!merged)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", at.file);
    const cJSON *d = cJSON_GetObjectItemCaseSensitive(medium_j, "density");
    const cJSON *dt = d ? cJSON_GetObjectItemCaseSensitive(d, "type") : NULL;
    if (cJSON_IsString(dt) && strcmp(dt->valuestring, "grid") == 0) {
        static const char *const inherit[] = {"file", "format", "dims", "bounds", "transform", "filter",
                                              "max_memory_mb", "frame_offset", "frame_step", "beyond"};
        bool own_place = cJSON_HasObjectItem(f, "bounds") || cJSON_HasObjectItem(f, "transform");
        for (size_t k = 0; k < sizeof inherit / sizeof *inherit; k++) {
            const cJSON *v = cJSON_GetObjectItemCaseSensitive(d, inherit[k]);
            bool place = strcmp(inherit[k], "bounds") == 0 || strcmp(inherit[k], "transform") == 0;
            if (v && !cJSON_HasObjectItem(f, inherit[k]) && !(place && own_place))
                cJSON_AddItemToObject(merged, inherit[k], cJSON_Duplicate(v, 1));
        }
    }
    brume_grid_file_options o;
    char path[2048];
    bool sequence = false;
    brume_status st = parse_grid_options(merged, fat, extra, scene_frame_number(s), path, sizeof path, &o, &sequence);
    cJSON_Delete(merged);
    if (st) return st;
    st = load(NULL, path, &o, out);
    if (used)
        *used = o;
    if (st == BRUME_OK && sequence)
        (*out)->evolves = true; /* the scene's builder marks the world moving (scene_build.c) */
    return st ? err_prefix("%s: %s", at.file, kp) : BRUME_OK;
}

/* "albedo", "temperature" + "blackbody", "emission_field", "velocity": the medium's optional
 * fields. */
static brume_status parse_medium_fields(const cJSON *j, jloc at, brume_scene *s, int index)
{
    brume_status st;
    char kp[256];
    if (cJSON_HasObjectItem(j, "albedo")) {
        brume_density *rgb[3];
        if ((st = parse_field(j, at, s, "albedo", NULL, brume_density_load_rgb, rgb, NULL))) return st;
        if ((st = built(brume_scene_set_medium_albedo(NULL, s, index, rgb),
                        (jloc){at.file, json_key_path(kp, sizeof kp, at.path, "albedo")}))) {
            for (int c = 0; c < 3; c++)
                brume_density_release(rgb[c]);
            return st;
        }
    }
    const cJSON *bbj = cJSON_GetObjectItemCaseSensitive(j, "blackbody");
    if (bbj && !cJSON_HasObjectItem(j, "temperature"))
        return err_set(BRUME_ERROR_PARSE, "%s: %s.blackbody: needs a \"temperature\" grid", at.file, at.path);
    if (cJSON_HasObjectItem(j, "temperature")) {
        brume_blackbody bb;
        brume_blackbody_default(&bb);
        if (bbj) {
            static const char *const bkeys[] = {"scale", "temperature_scale", "temperature_offset", "cutoff", NULL};
            jloc bat = {at.file, json_key_path(kp, sizeof kp, at.path, "blackbody")};
            if ((st = json_check_object(bbj, bat, bkeys))) return st;
            if ((st = json_number(bbj, bat, "scale", 0, 1e-30, 1e30, &bb.scale))) return st;
            if ((st = json_number(bbj, bat, "temperature_scale", 0, 1e-30, 1e30, &bb.temperature_scale))) return st;
            if ((st = json_number(bbj, bat, "temperature_offset", 0, -1e30, 1e30, &bb.temperature_offset))) return st;
            if ((st = json_number(bbj, bat, "cutoff", 0, 0.0, 1e30, &bb.cutoff))) return st;
        }
        brume_density *t = NULL;
        if ((st = parse_field(j, at, s, "temperature", NULL, brume_density_load, &t, NULL))) return st;
        if ((st = built(brume_scene_set_medium_temperature(NULL, s, index, t, &bb),
                        (jloc){at.file, json_key_path(kp, sizeof kp, at.path, "temperature")}))) {
            brume_density_release(t);
            return st;
        }
    }
    if (cJSON_HasObjectItem(j, "emission_field")) {
        static const char *const extra[] = {"color", NULL};
        double c[3] = {1, 1, 1};
        const cJSON *f = cJSON_GetObjectItemCaseSensitive(j, "emission_field");
        jloc eat = {at.file, json_key_path(kp, sizeof kp, at.path, "emission_field")};
        if (cJSON_IsObject(f) && (st = jcolor(f, eat, "color", 0, BIG, c))) return st;
        brume_density *e[3];
        if ((st = parse_field(j, at, s, "emission_field", extra, brume_density_load_rgb, e, NULL))) return st;
        if ((st = built(brume_scene_set_medium_emission_field(NULL, s, index, e, 3, c), eat))) {
            for (int k = 0; k < 3; k++)
                brume_density_release(e[k]);
            return st;
        }
    }
    if (cJSON_HasObjectItem(j, "velocity")) {
        /* "grid" names a vec3 grid or the stem of NAME.x/.y/.z ("" = "vel"); "scale" multiplies
         * the values into world units per second; the grid's transform (its own or the
         * density's) turns and scales the vectors as it places the grid */
        brume_density *v[3];
        brume_grid_file_options o;
        if ((st = parse_field(j, at, s, "velocity", NULL, brume_density_load_velocity, v, &o))) return st;
        double lin[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
        for (int r = 0; r < 3 && o.has_transform; r++)
            for (int c = 0; c < 3; c++)
                lin[3 * r + c] = o.transform[4 * r + c];
        if ((st = built(brume_scene_set_medium_velocity(NULL, s, index, v, lin),
                        (jloc){at.file, json_key_path(kp, sizeof kp, at.path, "velocity")}))) {
            for (int k = 0; k < 3; k++)
                brume_density_release(v[k]);
            return st;
        }
    }
    return BRUME_OK;
}

static brume_status parse_medium(const cJSON *j, jloc at, brume_scene *s)
{
    static const char *const keys[] = {"name", "density", "sigma_a", "sigma_s", "phase", "emission", "keyframes",
                                       "albedo", "temperature", "blackbody", "emission_field", "velocity", NULL};
    brume_status st = json_check_object(j, at, keys);
    if (st) return st;
    brume_medium m = {0};
    if ((st = json_string(j, at, "name", 0, m.name, sizeof m.name))) return st;
    if ((st = jcolor(j, at, "sigma_a", 1, 1e12, m.sigma_a))) return st;
    if ((st = jcolor(j, at, "sigma_s", 1, 1e12, m.sigma_s))) return st;
    if ((st = jcolor(j, at, "emission", 0, BIG, m.emission))) return st;
    char kp[256];
    const cJSON *d = cJSON_GetObjectItemCaseSensitive(j, "density");
    if (!d)
        return err_set(BRUME_ERROR_PARSE, "%s: %s.density: required key missing", at.file, at.path);
    brume_density *rho = NULL;
    brume_phase *ph = NULL;
    if ((st = parse_density(d, (jloc){at.file, json_key_path(kp, sizeof kp, at.path, "density")}, s, &rho)))
        return st;
    const cJSON *p = cJSON_GetObjectItemCaseSensitive(j, "phase");
    if (p && (st = parse_phase(p, (jloc){at.file, json_key_path(kp, sizeof kp, at.path, "phase")}, &ph))) {
        brume_density_release(rho);
        return st;
    }
    if ((st = built(brume_scene_add_medium(NULL, s, &m, rho, ph), at))) {
        brume_density_release(rho);
        brume_phase_release(ph);
        return st;
    }
    if ((st = parse_medium_fields(j, at, s, brume_scene_medium_count(s) - 1))) return st;
    const cJSON *keys_j = cJSON_GetObjectItemCaseSensitive(j, "keyframes");
    if (keys_j) {
        /* the field moves: its placement at time t is the keyed transform after its own */
        brume_transform_key k[MOTION_MAX_KEYS];
        int n = 0;
        jloc kat = {at.file, json_key_path(kp, sizeof kp, at.path, "keyframes")};
        if ((st = keys_parse_motion(keys_j, kat, k, &n))) return st;
        return built(brume_scene_set_medium_motion(NULL, s, brume_scene_medium_count(s) - 1, k, n), kat);
    }
    return BRUME_OK;
}

static brume_status parse_render(const cJSON *j, jloc at, brume_scene *s)
{
    static const char *const keys[] = {"width", "height", "spp", "seed", "threads", "method", "max_depth", "filter",
                                       "fps", "max_memory_mb", "max_work", "noise", "time", "min_spp", "sampler", "device", NULL};
    brume_status st = json_check_object(j, at, keys);
    if (st) return st;
    /* the one memory limit of everything the scene makes brume read or generate (core/budget.h) */
    double mb = (double)(BUDGET_DEFAULT_BYTES >> 20);
    if ((st = json_number(j, at, "max_memory_mb", 0, 1.0, 1e9, &mb))) return st;
    budget_set_limit((size_t)(mb * 1048576.0));
    /* the one work limit: each method estimates its work before it starts (issue 36) */
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

/* The scene at time `time`, or at frame_no / render.fps when frame_no >= 0. Render settings come
 * first: a frame's time needs the frame rate. */
static brume_status parse_scene(const cJSON *root, brume_scene *s, double time, long frame_no)
{
    static const char *const keys[] = {"camera", "lights", "media", "surfaces", "background", "render", "path",
                                       "blasi", "stam", NULL};
    const char *file = s->source;
    jloc top = {file, ""};
    brume_status st = json_check_object(root, top, keys);
    if (st) return st;
    const cJSON *render = cJSON_GetObjectItemCaseSensitive(root, "render");
    if (render && (st = parse_render(render, (jloc){file, "render"}, s))) return st;
    if ((st = built(brume_scene_set_time(NULL, s, frame_no >= 0 ? (double)frame_no / s->settings.fps : time),
                    (jloc){file, "render.fps"})))
        return st;
    const cJSON *cam = cJSON_GetObjectItemCaseSensitive(root, "camera");
    if (!cam)
        return err_set(BRUME_ERROR_PARSE, "%s: camera: required key missing", file);
    if ((st = parse_camera(cam, (jloc){file, "camera"}, s))) return st;
    if ((st = parse_background(root, top, s))) return st;

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
                st = parse_light(now, (jloc){file, kp}, s);
                cJSON_Delete(now);
                if (st) return st;
                if ((st = brume_scene_set_animated(NULL, s))) return st;
            } else if ((st = parse_light(l, (jloc){file, kp}, s))) {
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
            if ((st = parse_medium(m, (jloc){file, kp}, s))) return st;
        }
    }
    const cJSON *surf = cJSON_GetObjectItemCaseSensitive(root, "surfaces");
    if (surf && (st = scene_parse_surfaces(surf, file, s))) return st;
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

static brume_status read_text_file(const char *path, char **out)
{
    *out = NULL;
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return err_set(BRUME_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
    char *buf = NULL;
    size_t len = 0, cap = 0;
    for (;;) {
        if (len + 4096 + 1 > cap) {
            cap = cap ? 2 * cap : 65536;
            if (cap > (size_t)SCENE_FILE_MAX_BYTES + 4096 + 1) {
                free(buf);
                fclose(fp);
                return err_set(BRUME_ERROR_RANGE, "%s: larger than %ld MiB; not a scene file", path,
                               SCENE_FILE_MAX_BYTES >> 20);
            }
            char *nb = realloc(buf, cap);
            if (!nb) {
                free(buf);
                fclose(fp);
                return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
            }
            buf = nb;
        }
        size_t got = fread(buf + len, 1, 4096, fp);
        len += got;
        if (got < 4096)
            break;
    }
    int bad = ferror(fp);
    fclose(fp);
    if (bad) {
        free(buf);
        return err_set(BRUME_ERROR_IO, "%s: read error", path);
    }
    buf[len] = '\0';
    if (strlen(buf) != len) {
        free(buf);
        return err_set(BRUME_ERROR_PARSE, "%s: contains a NUL byte; not a JSON scene file", path);
    }
    *out = buf;
    return BRUME_OK;
}

/* The source's name in messages (and, for a text, the folder its file names resolve against). */
const char *scene_source_name(const brume_source *src)
{
    if (src && src->text)
        return src->path ? src->path : "<json>";
    if (src && src->path)
        return src->path;
    return "<default scene>";
}

static brume_status copy_text(const char *text, const char *name, char **out)
{
    if (!(*out = strdup(text)))
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
    return BRUME_OK;
}

/* The one dispatch from a source to the scene description the reader takes: a text is
 * itself, a grid file becomes its studio scene (scene/scene_studio.c), a .pbrt file its
 * translation (scene/scene_pbrt.c), any other file is read as JSON, no source is the
 * default scene. */
static brume_status scene_source_text(const brume_source *src, const brume_studio_options *studio, char **text)
{
    *text = NULL;
    if (src && src->text)
        return copy_text(src->text, scene_source_name(src), text);
    if (!src || !src->path)
        return copy_text(scene_default_json, scene_source_name(src), text);
    if (scene_studio_is_grid(src->path))
        return scene_studio_json(src->path, studio, text);
    if (scene_pbrt_is_pbrt(src->path))
        return scene_pbrt_json(src->path, text);
    return read_text_file(src->path, text);
}

/* Checks opts (NULL: the defaults) into *o; the message names the source. */
static brume_status load_options(const brume_source *src, const brume_load_options *opts, const char *fn,
                                 brume_load_options *o)
{
    *o = (brume_load_options){0.0, 0, NULL, 0, NULL, 0};
    if (opts)
        *o = *opts;
    if (o->noverrides < 0 || (o->noverrides > 0 && !o->overrides))
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: opts.overrides: NULL or noverrides < 0", fn);
    if (o->frame < 0)
        return err_set(BRUME_ERROR_RANGE, "%s: frame %ld is negative", scene_source_name(src), o->frame);
    if (!isfinite(o->time))
        return err_set(BRUME_ERROR_RANGE, "%s: load time %g is not finite", scene_source_name(src), o->time);
    return BRUME_OK;
}

brume_status brume_scene_load(brume_context *ctx, const brume_source *src, const brume_load_options *opts,
                              brume_scene **out)
{
    err_clear();
    if (!out)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_scene_load: out: NULL"));
    *out = NULL;
    brume_load_options o;
    brume_status st = load_options(src, opts, "brume_scene_load", &o);
    if (st)
        return ctx_report(ctx, st);
    char *text = NULL;
    cancel_load_begin(ctx); /* brume_context_cancel_loads(ctx) ends it */
    budget_hold(o.memory_held);
    if ((st = scene_source_text(src, o.studio, &text)) == BRUME_OK)
        st = scene_parse_json_with(text, scene_source_name(src), o.time, o.frame > 0 ? o.frame : -1, o.overrides,
                                   o.noverrides, out);
    budget_hold(0);
    cancel_load_end();
    if (st == BRUME_OK)
        (*out)->memory_held = o.memory_held; /* commit counts them too */
    free(text);
    return ctx_report(ctx, st);
}

brume_status scene_load_text(const brume_source *src, const brume_load_options *opts, char **json)
{
    err_clear();
    if (!json)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_scene_text: json: NULL");
    *json = NULL;
    return scene_source_text(src, opts ? opts->studio : NULL, json);
}

brume_status brume_scene_text(brume_context *ctx, const brume_source *src, const brume_load_options *opts,
                              char **json)
{
    return ctx_report(ctx, scene_load_text(src, opts, json));
}
