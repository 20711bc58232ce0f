/* method_options.c - the table of rendering methods that own options (method_options.h). */
#include "method/method_options.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "method/blasi_options.h"
#include "method/path_options.h"
#include "method/stam_params.h"

static void path_defaults(void *o) { path_options_default(o); }
static brume_status path_set(void *o, const char *k, const char *v) { return path_options_set(o, k, v); }
static void blasi_defaults(void *o) { blasi_options_default(o); }
static brume_status blasi_set(void *o, const char *k, const char *v) { return blasi_options_set(o, k, v); }
static bool blasi_is_path(const char *k) { return strcmp(k, "save_light") == 0 || strcmp(k, "load_light") == 0; }
static void stam_defaults(void *o) { stam_params_default(o); }
static brume_status stam_set(void *o, const char *k, const char *v) { return stam_params_set(o, k, v); }
static bool no_path(const char *k)
{
    (void)k;
    return false;
}

static bool no_path(const char *k);
static const method_options_def table[METHOD_OPTIONS_COUNT] = {
    [METHOD_OPTIONS_PATH] = {"path", sizeof(path_options), path_defaults, path_set, path_option_names, no_path},
    [METHOD_OPTIONS_BLASI] = {"blasi", sizeof(blasi_options), blasi_defaults, blasi_set, blasi_option_names,
                              blasi_is_path},
    [METHOD_OPTIONS_STAM] = {"stam", sizeof(stam_params), stam_defaults, stam_set, stam_param_names, no_path},
};

const method_options_def *method_options_def_get(method_options_id id) { return &table[id]; }

const method_options_def *method_options_find(const char *key, method_options_id *id, const char **rest)
{
    for (int i = 0; i < METHOD_OPTIONS_COUNT; i++) {
        size_t n = strlen(table[i].method);
        if (strncmp(key, table[i].method, n) == 0 && key[n] == '.') {
            *id = (method_options_id)i;
            *rest = key + n + 1;
            return &table[i];
        }
    }
    return NULL;
}

const char *method_options_methods(void) { return "path, blasi, stam"; }

bool method_option_number(const char *text, double lo, double hi, double *out)
{
    char *end = NULL;
    errno = 0;
    double v = strtod(text, &end);
    if (end == text || *end != '\0' || errno != 0 || !isfinite(v) || v < lo || v > hi)
        return false;
    *out = v;
    return true;
}

bool method_option_integer(const char *text, double lo, double hi, double *out)
{
    double v;
    if (!method_option_number(text, lo, hi, &v) || v != floor(v))
        return false;
    *out = v;
    return true;
}
