/* scene_json_view.c - the scene file's camera, lights and background (docs/scene-format.md),
 * checked and built through the public builders. */
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

/* camera.medium: the medium the camera sits in (checked at commit, scene_frame.c). */
static brume_status parse_camera_medium(const cJSON *j, jloc at, brume_scene *s)
{
    char name[64] = "";
    brume_status st = json_string(j, at, "medium", 0, name, sizeof name);
    if (st || !name[0])
        return st;
    return scene_json_built(brume_scene_set_camera_medium(NULL, s, name), at);
}

brume_status scene_parse_camera(const cJSON *j, jloc at, brume_scene *s)
{
    static const char *const keys[] = {"position", "look_at", "up", "fov", "aperture_radius", "focus_distance",
                                       "shutter", "keyframes", "frame", "frame_margin", "medium", NULL};
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
    if ((st = scene_json_vec(j, at, "up", 0, c.up))) return st;
    if (!(v3_length(v3(c.up[0], c.up[1], c.up[2])) > 0.0))
        return err_set(BRUME_ERROR_RANGE, "%s: camera.up: must not be the zero vector", at.file);
    if (framed[0] && !cJSON_HasObjectItem(j, "position") && !cJSON_HasObjectItem(j, "look_at"))
        scene_studio_direction(c.up, c.position, c.look_at); /* framed: only the direction counts */
    else if ((st = scene_json_vec(j, at, "position", 1, c.position)) || (st = scene_json_vec(j, at, "look_at", 1, c.look_at)))
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
    if ((st = scene_json_built(brume_scene_set_camera(NULL, s, &c), at))) return st;
    if ((st = parse_camera_medium(j, at, s))) return st;
    if (framed[0] && !framed_box && (st = scene_json_built(brume_scene_frame_camera(NULL, s, framed, margin), at))) return st;
    if (framed_box && (st = scene_json_built(brume_scene_frame_camera_box(NULL, s, box, margin), at))) return st;
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
        st = scene_json_built(brume_scene_set_camera_keys(NULL, s, bk, tmp->nkeys), kat);
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

brume_status scene_parse_light(const cJSON *j, jloc at, brume_scene *s)
{
    char type[32];
    brume_status st = json_object_type(j, at, type, sizeof type);
    if (st) return st;
    double pos[3] = {0, 0, 0}, dir[3] = {0, 0, 0}, L[3] = {0, 0, 0};
    if (strcmp(type, "distant") == 0) {
        static const char *const keys[] = {"type", "direction", "irradiance", "angular_radius", NULL};
        if ((st = json_check_object(j, at, keys))) return st;
        if ((st = scene_parse_unit_vector(j, at, "direction", dir))) return st;
        double deg = 0.0;
        if ((st = json_number(j, at, "angular_radius", 0, 0.0, 90.0, &deg))) return st;
        if ((st = scene_json_color(j, at, "irradiance", 1, BIG, L))) return st;
        return scene_json_built(brume_scene_add_distant_light(NULL, s, dir, L, deg), at);
    }
    if (strcmp(type, "point") == 0) {
        static const char *const keys[] = {"type", "position", "intensity", NULL};
        if ((st = json_check_object(j, at, keys))) return st;
        if ((st = scene_json_vec(j, at, "position", 1, pos))) return st;
        if ((st = scene_json_color(j, at, "intensity", 1, BIG, L))) return st;
        return scene_json_built(brume_scene_add_point_light(NULL, s, pos, L), at);
    }
    if (strcmp(type, "spot") == 0) {
        static const char *const keys[] = {"type", "position", "direction", "intensity", "cone_angle",
                                           "falloff_start", "profile", NULL};
        if ((st = json_check_object(j, at, keys))) return st;
        if ((st = scene_json_vec(j, at, "position", 1, pos))) return st;
        if ((st = scene_parse_unit_vector(j, at, "direction", dir))) return st;
        if ((st = scene_json_color(j, at, "intensity", 1, BIG, L))) return st;
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
                st = scene_json_built(brume_scene_add_spot_light_profile(NULL, s, pos, dir, L, ang, ang + LIGHT_PROFILE_MAX, n), at);
            free(ang);
            return st;
        }
        double cone = 30.0, start;
        if ((st = json_number(j, at, "cone_angle", 0, 0.01, 180.0, &cone))) return st;
        start = cone;
        if ((st = json_number(j, at, "falloff_start", 0, 0.0, cone, &start))) return st;
        return scene_json_built(brume_scene_add_spot_light(NULL, s, pos, dir, L, cone, start), at);
    }
    if (strcmp(type, "sphere") == 0 || strcmp(type, "disk") == 0) {
        static const char *const skeys[] = {"type", "position", "radius", "radiance", NULL};
        static const char *const dkeys[] = {"type", "position", "direction", "radius", "radiance", NULL};
        bool sphere = type[0] == 's';
        double radius = 0.0;
        if ((st = json_check_object(j, at, sphere ? skeys : dkeys))) return st;
        if ((st = scene_json_vec(j, at, "position", 1, pos))) return st;
        if (!sphere && (st = scene_parse_unit_vector(j, at, "direction", dir))) return st;
        if ((st = json_number(j, at, "radius", 1, 1e-9, BIG, &radius))) return st;
        if ((st = scene_json_color(j, at, "radiance", 1, BIG, L))) return st;
        return scene_json_built(sphere ? brume_scene_add_sphere_light(NULL, s, pos, radius, L)
                                       : brume_scene_add_disk_light(NULL, s, pos, dir, radius, L),
                                at);
    }
    return err_set(BRUME_ERROR_PARSE,
                   "%s: %s.type: unknown light type '%s' (known: distant, point, spot, sphere, disk)", at.file,
                   at.path, type);
}

/* background.transform: a rotation (with a mirror when a scale factor is negative) times a
 * uniform scale, as the 3 x 3 brume_scene_set_background_equal_area takes. */
static brume_status background_transform(const cJSON *b, jloc at, double m[9])
{
    const cJSON *t = cJSON_GetObjectItemCaseSensitive(b, "transform");
    char kp[256];
    jloc tat = {at.file, json_key_path(kp, sizeof kp, at.path, "transform")};
    affine3 a;
    brume_status st = json_transform(t, tat, true, &a);
    if (st) return st;
    if (a.m[3] != 0.0 || a.m[7] != 0.0 || a.m[11] != 0.0)
        return err_set(BRUME_ERROR_RANGE, "%s: %s.translate: a map of directions takes no translation", at.file, tat.path);
    json_transform_parts parts;
    if (t && (st = json_transform_split(t, tat, true, &parts))) return st;
    if (t && !(fabs(parts.scale.x) == fabs(parts.scale.y) && fabs(parts.scale.x) == fabs(parts.scale.z)))
        return err_set(BRUME_ERROR_RANGE, "%s: %s.scale: the factors must have one magnitude (a direction map)", at.file,
                       tat.path);
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            m[3 * r + c] = a.m[4 * r + c];
    return BRUME_OK;
}

/* "background": a color, or {"color": c} or {"file": "env.exr", "scale": s, "mapping": ...,
 * "up": [...] (lat-long) or "transform": {...} (equal-area)} */
brume_status scene_parse_background(const cJSON *root, jloc top, brume_scene *s)
{
    const cJSON *b = cJSON_GetObjectItemCaseSensitive(root, "background");
    jloc at = {top.file, "background"};
    double L[3] = {0, 0, 0};
    if (!b)
        return BRUME_OK;
    brume_status st;
    if (!cJSON_IsObject(b)) {
        if ((st = scene_json_color(root, top, "background", 0, BIG, L))) return st;
        return scene_json_built(brume_scene_set_background_color(NULL, s, L), at);
    }
    static const char *const keys[] = {"color", "file", "scale", "up", "mapping", "transform", NULL};
    if ((st = json_check_object(b, at, keys))) return st;
    double scale = 1.0, up[3] = {0, 1, 0}, m[9];
    char name[1024], path[2048], mapping[32] = "latlong";
    name[0] = '\0';
    if ((st = scene_json_color(b, at, "color", 0, BIG, L))) return st;
    if ((st = json_number(b, at, "scale", 0, 0.0, BIG, &scale))) return st;
    if (cJSON_HasObjectItem(b, "up") && (st = scene_parse_unit_vector(b, at, "up", up))) return st;
    if ((st = json_string(b, at, "mapping", 0, mapping, sizeof mapping))) return st;
    bool equal_area = strcmp(mapping, "equal_area") == 0;
    if (!equal_area && strcmp(mapping, "latlong") != 0)
        return err_set(BRUME_ERROR_PARSE, "%s: background.mapping: '%s' (known: latlong, equal_area)", top.file, mapping);
    if (cJSON_HasObjectItem(b, equal_area ? "up" : "transform"))
        return err_set(BRUME_ERROR_PARSE, "%s: background.%s: not read with mapping %s (%s orients it)", top.file,
                       equal_area ? "up" : "transform", mapping, equal_area ? "transform" : "up");
    if (equal_area && (st = background_transform(b, at, m))) return st;
    if ((st = json_string(b, at, "file", 0, name, sizeof name))) return st;
    if (!name[0])
        return scene_json_built(brume_scene_set_background_color(NULL, s, L), at);
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
    st = scene_json_built(equal_area ? brume_scene_set_background_equal_area(NULL, s, img, scale, m)
                                     : brume_scene_set_background_image(NULL, s, img, scale, up),
                          at);
    brume_image_release(img);
    return st;
}
