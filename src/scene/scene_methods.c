/* scene_methods.c - the scene file's method objects ("path", "blasi", "stam"), read through the one
 * option mechanism, brume_scene_set_option. */
#include "scene/scene_methods.h"

#include <stdio.h>
#include <string.h>

#include "core/error.h"
#include "scene/scene_paths.h"
#include "method/method_options.h"
#include "scene/scene.h"

#define OPTION_TEXT_MAX 2048

/* The option's text form of a JSON value; false when it has none. */
static bool value_text(const cJSON *it, char *text, size_t n)
{
    if (cJSON_IsNumber(it)) {
        snprintf(text, n, "%.17g", it->valuedouble);
    } else if (cJSON_IsString(it)) {
        if (strlen(it->valuestring) >= n)
            return false;
        snprintf(text, n, "%s", it->valuestring);
    } else if (cJSON_IsBool(it)) {
        snprintf(text, n, "%s", cJSON_IsTrue(it) ? "true" : "false");
    } else if (cJSON_IsArray(it) && cJSON_GetArraySize(it) > 0) {
        size_t len = 0;
        text[0] = '\0';
        for (const cJSON *e = it->child; e; e = e->next) {
            if (!cJSON_IsNumber(e))
                return false;
            int w = snprintf(text + len, n - len, "%s%.17g", len ? "," : "", e->valuedouble);
            if (w < 0 || (size_t)w >= n - len)
                return false;
            len += (size_t)w;
        }
    } else {
        return false;
    }
    return true;
}

static brume_status parse_object(const cJSON *obj, jloc top, const method_options_def *def, const char *prefix,
                                 brume_scene *s)
{
    for (const cJSON *it = obj->child; it; it = it->next) {
        if (strcmp(it->string, "comment") == 0)
            continue;
        char key[256], text[OPTION_TEXT_MAX], path[OPTION_TEXT_MAX];
        snprintf(key, sizeof key, "%s.%s", prefix, it->string);
        brume_status st;
        const method_option *o = method_option_find(def, key);
        /* an object is a group of options ("voxelize"): never an option's value, never empty */
        if (cJSON_IsObject(it) && !o && it->child) {
            if ((st = parse_object(it, top, def, key, s)))
                return st;
            continue;
        }
        /* a number is written as a JSON number: the text "1" is not one */
        bool numeric = o && (o->kind == OPTION_NUMBER || o->kind == OPTION_INTEGER || o->kind == OPTION_COLOR ||
                             o->kind == OPTION_BOOL);
        if (!value_text(it, text, sizeof text) || (numeric && cJSON_IsString(it)))
            return err_set(BRUME_ERROR_PARSE, "%s: %s: expected %s", top.file, key,
                           numeric ? (o->kind == OPTION_BOOL ? "true or false" : "a number or an array of numbers")
                                   : "a number, a string, true, false or an array of numbers");
        if (o && o->kind == OPTION_PATH && cJSON_IsString(it)) {
            if (!(o->flags & OPTION_WRITES))
                json_resolve_path(top.file, text, path, sizeof path);
            else if ((st = scene_output_path(top.file, key, text, path, sizeof path)))
                return st; /* a path written because the scene file says so: inside its folder only */
            snprintf(text, sizeof text, "%s", path);
        }
        if ((st = brume_scene_set_option(NULL, s, key, text)))
            return st; /* "FILE: METHOD.KEY: ..." */
    }
    return BRUME_OK;
}

brume_status scene_parse_method_options(const cJSON *root, jloc top, brume_scene *s)
{
    for (int i = 0; i < METHOD_OPTIONS_COUNT; i++) {
        const method_options_def *def = method_options_def_get((method_options_id)i);
        const cJSON *o = cJSON_GetObjectItemCaseSensitive(root, def->method);
        if (!o)
            continue;
        if (!cJSON_IsObject(o))
            return err_set(BRUME_ERROR_PARSE, "%s: %s: expected an object", top.file, def->method);
        brume_status st = parse_object(o, top, def, def->method, s);
        if (st)
            return st;
    }
    return BRUME_OK;
}
