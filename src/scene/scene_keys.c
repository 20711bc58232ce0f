/* scene_keys.c - keyframe arrays of scene files: motions, camera poses, per-frame values. */
#include "scene/scene_keys.h"

#include <stdio.h>
#include <string.h>

#include "core/error.h"

#define KEYS_MAX_DIM 4 /* a keyed value is a number or an array of up to 4 numbers */

/* keys must be an array of 1 .. max objects with strictly increasing numeric "time". */
static brume_status check_keys(const cJSON *keys, jloc at, int max)
{
    int n = cJSON_GetArraySize(keys);
    if (!cJSON_IsArray(keys) || n < 1 || n > max)
        return err_set(BRUME_ERROR_PARSE, "%s: %s: expected an array of 1 to %d keyframe objects", at.file, at.path,
                       max);
    double prev = -INFINITY;
    int i = 0;
    for (const cJSON *k = keys->child; k; k = k->next, i++) {
        const cJSON *t = cJSON_GetObjectItemCaseSensitive(k, "time");
        if (!cJSON_IsObject(k) || !cJSON_IsNumber(t))
            return err_set(BRUME_ERROR_PARSE, "%s: %s[%d]: expected an object with a \"time\" in seconds", at.file,
                           at.path, i);
        if (!isfinite(t->valuedouble) || !(t->valuedouble > prev))
            return err_set(BRUME_ERROR_RANGE, "%s: %s[%d].time: %g must be finite and greater than the previous key's",
                           at.file, at.path, i, t->valuedouble);
        prev = t->valuedouble;
    }
    return BRUME_OK;
}

/* A keyed value as numbers: a number (dim 1) or an array of 1 .. KEYS_MAX_DIM numbers. */
static bool read_value(const cJSON *v, int *dim, double out[KEYS_MAX_DIM])
{
    if (cJSON_IsNumber(v)) {
        *dim = 1;
        out[0] = v->valuedouble;
        return isfinite(out[0]);
    }
    int n = cJSON_GetArraySize(v);
    if (!cJSON_IsArray(v) || n < 1 || n > KEYS_MAX_DIM)
        return false;
    int i = 0;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        if (!cJSON_IsNumber(e) || !isfinite(e->valuedouble))
            return false;
        out[i] = e->valuedouble;
    }
    *dim = n;
    return true;
}

/* The value of property `name` at time t, linear between the keys that give it and held
 * beyond them. *found is false when no key gives it. */
static brume_status track_at(const cJSON *keys, jloc at, const char *name, double t, bool *found, int *dim,
                             double v[KEYS_MAX_DIM])
{
    *found = false;
    double t_prev = 0.0, v_prev[KEYS_MAX_DIM] = {0};
    int i = 0;
    for (const cJSON *k = keys->child; k; k = k->next, i++) {
        const cJSON *item = cJSON_GetObjectItemCaseSensitive(k, name);
        if (!item)
            continue;
        double tk = cJSON_GetObjectItemCaseSensitive(k, "time")->valuedouble, vk[KEYS_MAX_DIM];
        int d;
        if (!read_value(item, &d, vk) || (*found && d != *dim))
            return err_set(BRUME_ERROR_PARSE, "%s: %s[%d].%s: expected a number or an array of up to %d numbers, "
                           "of the same size in every key", at.file, at.path, i, name, KEYS_MAX_DIM);
        if (!*found) {
            *found = true;
            *dim = d;
            memcpy(v, vk, sizeof vk);
        } else if (t > t_prev) {
            if (t >= tk) {
                memcpy(v, vk, sizeof vk);
            } else {
                double u = (t - t_prev) / (tk - t_prev);
                for (int c = 0; c < d; c++)
                    v[c] = v_prev[c] + (vk[c] - v_prev[c]) * u;
            }
        }
        t_prev = tk;
        memcpy(v_prev, vk, sizeof vk);
    }
    return BRUME_OK;
}

brume_status keys_parse_motion(const cJSON *keys, jloc at, brume_transform_key *out, int *n)
{
    static const char *const allowed[] = {"time", "transform", NULL};
    brume_status st = check_keys(keys, at, MOTION_MAX_KEYS);
    if (st) return st;
    *n = 0;
    int i = 0;
    for (const cJSON *k = keys->child; k; k = k->next, i++) {
        char kp[256], tp[300];
        snprintf(kp, sizeof kp, "%s[%d]", at.path, i);
        jloc kat = {at.file, kp};
        if ((st = json_check_object(k, kat, allowed))) return st;
        const cJSON *tr = cJSON_GetObjectItemCaseSensitive(k, "transform");
        if (!tr)
            return err_set(BRUME_ERROR_PARSE, "%s: %s.transform: required key missing", at.file, kp);
        snprintf(tp, sizeof tp, "%s.transform", kp);
        json_transform_parts parts;
        if ((st = json_transform_split(tr, (jloc){at.file, tp}, false, &parts))) return st;
        brume_transform_key *tk = &out[(*n)++];
        tk->time = cJSON_GetObjectItemCaseSensitive(k, "time")->valuedouble;
        v3_to_array(parts.translate, tk->translate);
        v3_to_array(parts.axis, tk->axis);
        tk->angle = parts.angle;
        v3_to_array(parts.scale, tk->scale);
    }
    return BRUME_OK;
}

/* One camera property at time t: from the keys, else the camera's own value. */
static brume_status camera_track(const cJSON *keys, jloc at, const char *name, int want, double t, double *v,
                                 bool *found)
{
    int dim = 0;
    double x[KEYS_MAX_DIM];
    brume_status st = track_at(keys, at, name, t, found, &dim, x);
    if (st) return st;
    if (!*found)
        return BRUME_OK;
    if (dim != want)
        return err_set(BRUME_ERROR_PARSE, "%s: %s: %s: expected %s in every key", at.file, at.path, name,
                       want == 1 ? "a number" : "[x, y, z]");
    memcpy(v, x, sizeof *v * (size_t)want);
    return BRUME_OK;
}

brume_status keys_parse_camera(const cJSON *keys, jloc at, camera *c, bool focus_given)
{
    static const char *const allowed[] = {"time", "position", "look_at", "up", "fov", "aperture_radius",
                                          "focus_distance", NULL};
    brume_status st = check_keys(keys, at, CAMERA_MAX_KEYS);
    if (st) return st;
    int i = 0;
    for (const cJSON *k = keys->child; k; k = k->next, i++) {
        char kp[256];
        snprintf(kp, sizeof kp, "%s[%d]", at.path, i);
        if ((st = json_check_object(k, (jloc){at.file, kp}, allowed))) return st;
    }
    c->nkeys = 0;
    i = 0;
    for (const cJSON *k = keys->child; k; k = k->next, i++) {
        camera_key *ck = &c->keys[c->nkeys++];
        double t = cJSON_GetObjectItemCaseSensitive(k, "time")->valuedouble;
        double pos[3] = {c->position.x, c->position.y, c->position.z};
        double look[3] = {c->look_at.x, c->look_at.y, c->look_at.z}, up[3] = {c->up.x, c->up.y, c->up.z};
        double fov = c->fov, ap = c->aperture_radius, focus = c->focus_distance;
        bool found, focus_keyed;
        if ((st = camera_track(keys, at, "position", 3, t, pos, &found))) return st;
        if ((st = camera_track(keys, at, "look_at", 3, t, look, &found))) return st;
        if ((st = camera_track(keys, at, "up", 3, t, up, &found))) return st;
        if ((st = camera_track(keys, at, "fov", 1, t, &fov, &found))) return st;
        if ((st = camera_track(keys, at, "aperture_radius", 1, t, &ap, &found))) return st;
        if ((st = camera_track(keys, at, "focus_distance", 1, t, &focus, &focus_keyed))) return st;
        ck->time = t;
        ck->position = v3(pos[0], pos[1], pos[2]);
        ck->look_at = v3(look[0], look[1], look[2]);
        ck->up = v3(up[0], up[1], up[2]);
        ck->fov = fov;
        ck->aperture_radius = ap;
        ck->focus_distance = focus_given || focus_keyed ? focus : v3_length(v3_sub(ck->look_at, ck->position));
        if (!(fov >= 1e-3 && fov <= 179.0))
            return err_set(BRUME_ERROR_RANGE, "%s: %s[%d]: fov %.17g outside [0.001, 179]", at.file, at.path, i, fov);
        if (!(ap >= 0.0) || !(ck->focus_distance > 0.0))
            return err_set(BRUME_ERROR_RANGE, "%s: %s[%d]: need aperture_radius >= 0 and focus_distance > 0",
                           at.file, at.path, i);
        if (!(v3_length(v3_sub(ck->look_at, ck->position)) > 0.0) || !(v3_length(ck->up) > 0.0))
            return err_set(BRUME_ERROR_RANGE, "%s: %s[%d]: look_at equals position, or up is zero", at.file, at.path,
                           i);
    }
    return BRUME_OK;
}

brume_status keys_object_at(const cJSON *j, jloc at, double t, cJSON **out)
{
    *out = NULL;
    char kp[256];
    jloc kat = {at.file, json_key_path(kp, sizeof kp, at.path, "keyframes")};
    const cJSON *keys = cJSON_GetObjectItemCaseSensitive(j, "keyframes");
    brume_status st = check_keys(keys, kat, 1 << 16);
    if (st) return st;
    cJSON *o = cJSON_Duplicate(j, 1);
    if (!o)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", at.file);
    cJSON_DeleteItemFromObjectCaseSensitive(o, "keyframes");
    for (const cJSON *k = keys->child; k; k = k->next)
        for (const cJSON *item = k->child; item; item = item->next) {
            if (strcmp(item->string, "time") == 0 || strcmp(item->string, "comment") == 0)
                continue;
            bool found;
            int dim = 0;
            double v[KEYS_MAX_DIM];
            if ((st = track_at(keys, kat, item->string, t, &found, &dim, v))) {
                cJSON_Delete(o);
                return st;
            }
            cJSON *val = dim == 1 ? cJSON_CreateNumber(v[0]) : cJSON_CreateDoubleArray(v, dim);
            if (!val) {
                cJSON_Delete(o);
                return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", at.file);
            }
            cJSON_DeleteItemFromObjectCaseSensitive(o, item->string);
            cJSON_AddItemToObject(o, item->string, val);
        }
    *out = o;
    return BRUME_OK;
}
