/* json.c - checked reads from cJSON with file-and-key error messages. */
#include "io/json.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "core/error.h"
#include "core/xform.h"

const char *json_key_path(char *buf, size_t n, const char *path, const char *key)
{
    if (path && path[0])
        snprintf(buf, n, "%s.%s", path, key);
    else
        snprintf(buf, n, "%s", key);
    return buf;
}

brume_status json_check_object(const cJSON *j, jloc at, const char *const *allowed)
{
    if (!cJSON_IsObject(j))
        return err_set(BRUME_ERROR_PARSE, "%s: %s: expected an object", at.file, at.path[0] ? at.path : "(top level)");
    for (const cJSON *c = j->child; c; c = c->next) {
        if (strcmp(c->string, "comment") == 0)
            continue;
        int known = 0;
        for (const char *const *a = allowed; *a; a++)
            if (strcmp(*a, c->string) == 0)
                known = 1;
        if (!known) {
            char list[512] = "", kp[256];
            for (const char *const *a = allowed; *a; a++) {
                strncat(list, *a, sizeof list - strlen(list) - 1);
                if (a[1])
                    strncat(list, ", ", sizeof list - strlen(list) - 1);
            }
            return err_set(BRUME_ERROR_PARSE, "%s: %s: unknown key (known here: %s)", at.file,
                           json_key_path(kp, sizeof kp, at.path, c->string), list);
        }
        /* duplicate keys are ambiguous: refuse them */
        for (const cJSON *d = c->next; d; d = d->next)
            if (strcmp(d->string, c->string) == 0) {
                char kp[256];
                return err_set(BRUME_ERROR_PARSE, "%s: %s: key given twice", at.file,
                               json_key_path(kp, sizeof kp, at.path, c->string));
            }
    }
    return BRUME_OK;
}

const char *json_bad_number(const char *text)
{
    bool in_string = false;
    for (const char *p = text; *p; p++) {
        if (in_string) {
            if (*p == '\\' && p[1])
                p++;
            else if (*p == '"')
                in_string = false;
            continue;
        }
        if (*p == '"') {
            in_string = true;
            continue;
        }
        if (*p != '-' && (*p < '0' || *p > '9'))
            continue;
        const char *q = p + (*p == '-');
        if (*q == '0' && q[1] >= '0' && q[1] <= '9')
            return p;
        while (*q >= '0' && *q <= '9')
            q++;
        if (*q == '.' && !(q[1] >= '0' && q[1] <= '9'))
            return p;
        if (*q == '.')
            for (q++; *q >= '0' && *q <= '9'; q++) {
            }
        if (*q == 'e' || *q == 'E') {
            q += (q[1] == '+' || q[1] == '-') ? 2 : 1;
            if (!(*q >= '0' && *q <= '9'))
                return p;
            while (*q >= '0' && *q <= '9')
                q++;
        }
        p = q - 1;
    }
    return NULL;
}

brume_status json_parse(const char *text, const char *file, cJSON **out)
{
    const char *end = NULL;
    *out = cJSON_ParseWithOpts(text, &end, 1);
    if (*out && (end = json_bad_number(text)) != NULL) {
        cJSON_Delete(*out);
        *out = NULL;
    }
    if (*out)
        return BRUME_OK;
    int line = 1, colno = 1;
    const char *stop = end ? end : text;
    for (const char *p = text; p < stop && *p; p++) {
        if (*p == '\n') {
            line++;
            colno = 1;
        } else {
            colno++;
        }
    }
    return err_set(BRUME_ERROR_PARSE, "%s: line %d, column %d: JSON syntax error", file, line, colno);
}

static const cJSON *json_item(const cJSON *obj, jloc at, const char *key, int required, brume_status *st)
{
    const cJSON *it = cJSON_GetObjectItemCaseSensitive(obj, key);
    *st = BRUME_OK;
    if (!it && required) {
        char kp[256];
        *st = err_set(BRUME_ERROR_PARSE, "%s: %s: required key missing", at.file, json_key_path(kp, sizeof kp, at.path, key));
    }
    return it;
}

brume_status json_object_type(const cJSON *j, jloc at, char *type, size_t n)
{
    if (!cJSON_IsObject(j))
        return err_set(BRUME_ERROR_PARSE, "%s: %s: expected an object", at.file, at.path);
    return json_string(j, at, "type", 1, type, n);
}

brume_status json_number(const cJSON *obj, jloc at, const char *key, int required, double lo, double hi, double *out)
{
    brume_status st;
    const cJSON *it = json_item(obj, at, key, required, &st);
    if (!it)
        return st;
    char kp[256];
    json_key_path(kp, sizeof kp, at.path, key);
    if (!cJSON_IsNumber(it))
        return err_set(BRUME_ERROR_PARSE, "%s: %s: expected a number", at.file, kp);
    double v = it->valuedouble;
    if (!isfinite(v) || v < lo || v > hi)
        return err_set(BRUME_ERROR_RANGE, "%s: %s: %.17g outside [%.17g, %.17g]", at.file, kp, v, lo, hi);
    *out = v;
    return BRUME_OK;
}

/* A whole number in [lo, hi] (absent and optional: *present = 0, nothing read). */
static brume_status json_whole(const cJSON *obj, jloc at, const char *key, int required, double lo, double hi,
                               const char *what, double *v, int *present)
{
    *present = cJSON_GetObjectItemCaseSensitive(obj, key) != NULL;
    brume_status st = json_number(obj, at, key, required, lo, hi, v);
    if (st != BRUME_OK || !*present)
        return st;
    if (*v != floor(*v)) {
        char kp[256];
        return err_set(BRUME_ERROR_PARSE, "%s: %s: expected %s, got %g", at.file,
                       json_key_path(kp, sizeof kp, at.path, key), what, *v);
    }
    return BRUME_OK;
}

brume_status json_int(const cJSON *obj, jloc at, const char *key, int required, long lo, long hi, int *out)
{
    double v = 0.0;
    int present;
    brume_status st = json_whole(obj, at, key, required, (double)lo, (double)hi, "an integer", &v, &present);
    if (st == BRUME_OK && present)
        *out = (int)v;
    return st;
}

brume_status json_u64(const cJSON *obj, jloc at, const char *key, int required, uint64_t *out)
{
    double v = 0.0;
    int present;
    brume_status st =
        json_whole(obj, at, key, required, 0.0, 9007199254740992.0, "a non-negative integer", &v, &present);
    if (st == BRUME_OK && present)
        *out = (uint64_t)v;
    return st;
}

brume_status json_bool(const cJSON *obj, jloc at, const char *key, int required, bool *out)
{
    brume_status st;
    const cJSON *it = json_item(obj, at, key, required, &st);
    if (!it)
        return st;
    if (!cJSON_IsBool(it)) {
        char kp[256];
        return err_set(BRUME_ERROR_PARSE, "%s: %s: expected true or false", at.file, json_key_path(kp, sizeof kp, at.path, key));
    }
    *out = cJSON_IsTrue(it);
    return BRUME_OK;
}

brume_status json_string(const cJSON *obj, jloc at, const char *key, int required, char *buf, size_t n)
{
    brume_status st;
    const cJSON *it = json_item(obj, at, key, required, &st);
    if (!it)
        return st;
    char kp[256];
    json_key_path(kp, sizeof kp, at.path, key);
    if (!cJSON_IsString(it))
        return err_set(BRUME_ERROR_PARSE, "%s: %s: expected a string", at.file, kp);
    if (strlen(it->valuestring) >= n)
        return err_set(BRUME_ERROR_RANGE, "%s: %s: string longer than %zu characters", at.file, kp, n - 1);
    snprintf(buf, n, "%s", it->valuestring);
    return BRUME_OK;
}

static brume_status json_triple(const cJSON *it, jloc at, const char *key, double lo, double hi, double v[3])
{
    char kp[256];
    json_key_path(kp, sizeof kp, at.path, key);
    if (!cJSON_IsArray(it) || cJSON_GetArraySize(it) != 3)
        return err_set(BRUME_ERROR_PARSE, "%s: %s: expected an array of 3 numbers", at.file, kp);
    for (int i = 0; i < 3; i++) {
        const cJSON *e = cJSON_GetArrayItem(it, i);
        if (!cJSON_IsNumber(e))
            return err_set(BRUME_ERROR_PARSE, "%s: %s[%d]: expected a number", at.file, kp, i);
        v[i] = e->valuedouble;
        if (!isfinite(v[i]) || v[i] < lo || v[i] > hi)
            return err_set(BRUME_ERROR_RANGE, "%s: %s[%d]: %.17g outside [%.17g, %.17g]", at.file, kp, i, v[i], lo, hi);
    }
    return BRUME_OK;
}

brume_status json_vec3(const cJSON *obj, jloc at, const char *key, int required, vec3 *out)
{
    brume_status st;
    const cJSON *it = json_item(obj, at, key, required, &st);
    if (!it)
        return st;
    double v[3];
    st = json_triple(it, at, key, -1e30, 1e30, v);
    if (st == BRUME_OK)
        *out = v3(v[0], v[1], v[2]);
    return st;
}

brume_status json_color(const cJSON *obj, jloc at, const char *key, int required, double lo, double hi, color *out)
{
    brume_status st;
    const cJSON *it = json_item(obj, at, key, required, &st);
    if (!it)
        return st;
    if (cJSON_IsNumber(it)) {
        double v = 0.0;
        st = json_number(obj, at, key, 1, lo, hi, &v);
        if (st == BRUME_OK)
            *out = col(v);
        return st;
    }
    double v[3];
    st = json_triple(it, at, key, lo, hi, v);
    if (st == BRUME_OK)
        *out = col_rgb(v[0], v[1], v[2]);
    return st;
}

void json_resolve_path(const char *scene_file, const char *name, char *out, size_t n)
{
    const char *slash = strrchr(scene_file, '/');
    if (name[0] == '/' || !slash || scene_file[0] == '<')
        snprintf(out, n, "%s", name);
    else
        snprintf(out, n, "%.*s/%s", (int)(slash - scene_file), scene_file, name);
}

/* {"translate": [..], "rotate": {"axis": [..], "angle": deg}, "scale": s | [sx, sy, sz]},
 * applied as translate(rotate(scale(x))). */
brume_status json_transform(const cJSON *j, jloc at, bool mirror, affine3 *out)
{
    *out = affine3_identity();
    if (!j)
        return BRUME_OK;
    json_transform_parts parts;
    brume_status st = json_transform_split(j, at, mirror, &parts);
    if (st) return st;
    affine3 ts = affine3_translate(parts.translate), ss = affine3_scale(parts.scale);
    affine3 r = parts.angle != 0.0 ? affine3_rotate(parts.axis, parts.angle) : affine3_identity();
    affine3 rs = affine3_compose(&r, &ss);
    *out = affine3_compose(&ts, &rs);
    return BRUME_OK;
}

brume_status json_transform_split(const cJSON *j, jloc at, bool mirror, json_transform_parts *out)
{
    static const char *const keys[] = {"translate", "rotate", "scale", NULL};
    brume_status st = json_check_object(j, at, keys);
    if (st) return st;
    vec3 t = v3(0, 0, 0), sc = v3(1, 1, 1), axis = v3(0, 0, 1);
    double angle = 0.0;
    if ((st = json_vec3(j, at, "translate", 0, &t))) return st;
    const cJSON *s = cJSON_GetObjectItemCaseSensitive(j, "scale");
    if (cJSON_IsNumber(s)) {
        double k = 1.0;
        if ((st = json_number(j, at, "scale", 1, 1e-12, 1e30, &k))) return st;
        sc = v3(k, k, k);
    } else if (s) {
        if ((st = json_vec3(j, at, "scale", 1, &sc))) return st;
        if (mirror && !(fabs(sc.x) > 0 && fabs(sc.y) > 0 && fabs(sc.z) > 0))
            return err_set(BRUME_ERROR_RANGE, "%s: %s.scale: every factor must be non-zero", at.file, at.path);
        if (!mirror && !(sc.x > 0 && sc.y > 0 && sc.z > 0))
            return err_set(BRUME_ERROR_RANGE, "%s: %s.scale: every factor must be > 0", at.file, at.path);
    }
    const cJSON *rot = cJSON_GetObjectItemCaseSensitive(j, "rotate");
    if (rot) {
        static const char *const rkeys[] = {"axis", "angle", NULL};
        char kp[256];
        jloc rat = {at.file, json_key_path(kp, sizeof kp, at.path, "rotate")};
        if ((st = json_check_object(rot, rat, rkeys))) return st;
        if ((st = json_vec3(rot, rat, "axis", 1, &axis))) return st;
        if (!(v3_length(axis) > 0.0))
            return err_set(BRUME_ERROR_RANGE, "%s: %s.axis: must not be the zero vector", at.file, rat.path);
        if ((st = json_number(rot, rat, "angle", 1, -1e6, 1e6, &angle))) return st;
    }
    *out = (json_transform_parts){t, axis, angle, sc};
    return BRUME_OK;
}

