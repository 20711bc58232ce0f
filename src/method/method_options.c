/* method_options.c - the generic setter of the methods' option tables, the list of methods
 * that have options, and the public list of options (method_options.h). */
#include "method/method_options.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/color.h"
#include "core/context.h"
#include "core/error.h"
#include "core/number.h"
#include "method/blasi_options.h"
#include "method/path_options.h"
#include "method/stam_params.h"

static const method_options_def *const methods[METHOD_OPTIONS_COUNT] = {
    [METHOD_OPTIONS_PATH] = &path_options_def,
    [METHOD_OPTIONS_BLASI] = &blasi_options_def,
    [METHOD_OPTIONS_STAM] = &stam_options_def,
};

const method_options_def *method_options_def_get(method_options_id id) { return methods[id]; }

const method_options_def *method_options_find(const char *key, method_options_id *id)
{
    for (int i = 0; i < METHOD_OPTIONS_COUNT; i++) {
        size_t n = strlen(methods[i]->method);
        if (strncmp(key, methods[i]->method, n) == 0 && key[n] == '.') {
            *id = (method_options_id)i;
            return methods[i];
        }
    }
    return NULL;
}

const char *method_options_methods(void) { return "path, blasi, stam"; }

const method_option *method_option_find(const method_options_def *def, const char *key)
{
    for (int i = 0; i < def->count; i++)
        if (strcmp(def->options[i].key, key) == 0)
            return &def->options[i];
    return NULL;
}

bool method_option_number(const char *text, double lo, double hi, double *out)
{
    char *end = NULL;
    errno = 0;
    double v = num_strtod(text, &end);
    /* ERANGE with a small result is an underflow (1e-308, 5e-324): the number is still in range */
    bool underflow = errno == ERANGE && fabs(v) < 1.0;
    if (end == text || *end != '\0' || (errno != 0 && !underflow) || !isfinite(v) || v < lo || v > hi)
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

/* "v" (gray) or "r,g,b", each a number in [lo, hi]. */
static bool parse_color(const char *text, double lo, double hi, color *out)
{
    char buf[256];
    if (strlen(text) >= sizeof buf)
        return false;
    snprintf(buf, sizeof buf, "%s", text);
    double v[3];
    int n = 0;
    for (char *save = NULL, *t = strtok_r(buf, ",", &save); t; t = strtok_r(NULL, ",", &save)) {
        while (*t == ' ')
            t++;
        if (n == 3 || !method_option_number(t, lo, hi, &v[n]))
            return false;
        n++;
    }
    if (n == 1)
        *out = col(v[0]);
    else if (n == 3)
        *out = col_rgb(v[0], v[1], v[2]);
    else
        return false;
    return true;
}

/* A parsed value, before it goes into its field. */
typedef struct option_value {
    double number; /* number, integer, enum index, bool (0 or 1) */
    color rgb;
} option_value;

/* Parses text as row o's value; false when it is not one. */
static bool parse(const method_option *o, const char *text, option_value *v)
{
    switch (o->kind) {
    case OPTION_NUMBER:
        return method_option_number(text, o->lo, o->hi, &v->number) &&
               !((o->flags & OPTION_HI_OPEN) && v->number >= o->hi);
    case OPTION_INTEGER:
        if (o->flags & OPTION_ZERO_OR)
            return method_option_integer(text, 0.0, o->hi, &v->number) && (v->number == 0.0 || v->number >= o->lo);
        return method_option_integer(text, o->lo, o->hi, &v->number);
    case OPTION_ENUM:
        for (int i = 0; o->names[i]; i++)
            if (strcmp(text, o->names[i]) == 0) {
                v->number = i;
                return true;
            }
        return false;
    case OPTION_BOOL:
        if (strcmp(text, "true") == 0 || strcmp(text, "1") == 0)
            v->number = 1.0;
        else if (strcmp(text, "false") == 0 || strcmp(text, "0") == 0)
            v->number = 0.0;
        else
            return false;
        return true;
    case OPTION_COLOR:
        return parse_color(text, o->lo, o->hi, &v->rgb);
    case OPTION_PATH:
        return strlen(text) < o->size;
    }
    return false;
}

/* Stores a value parsed by parse() into row o's field of opts. */
static void store(const method_option *o, const char *text, const option_value *v, void *opts)
{
    void *f = (char *)opts + o->offset;
    switch (o->store) {
    case OPTION_STORE_NONE:
        break;
    case OPTION_STORE_DOUBLE:
        *(double *)f = v->number;
        break;
    case OPTION_STORE_INT:
        *(int *)f = (int)v->number;
        break;
    case OPTION_STORE_UINT:
        *(unsigned *)f = (unsigned)v->number;
        break;
    case OPTION_STORE_U64:
        *(uint64_t *)f = (uint64_t)v->number;
        break;
    case OPTION_STORE_BOOL:
        *(bool *)f = v->number != 0.0;
        break;
    case OPTION_STORE_COLOR:
        *(color *)f = v->rgb;
        break;
    case OPTION_STORE_CHARS:
        snprintf(f, o->size, "%s", text);
        break;
    }
}

void method_options_default(const method_options_def *def, void *opts)
{
    memset(opts, 0, def->size);
    for (int i = 0; i < def->count; i++) {
        const method_option *o = &def->options[i];
        option_value v = {0};
        if (o->def && parse(o, o->def, &v)) /* a default that does not parse: tests/test_options.c */
            store(o, o->def, &v, opts);
    }
    if (def->defaults)
        def->defaults(opts);
}

/* "a, b, c": the keys of def without "METHOD.", for messages. */
static void known_keys(const method_options_def *def, char *out, size_t n)
{
    size_t len = 0, skip = strlen(def->method) + 1;
    out[0] = '\0';
    for (int i = 0; i < def->count && len < n; i++) {
        int w = snprintf(out + len, n - len, "%s%s", i ? ", " : "", def->options[i].key + skip);
        if (w < 0)
            break;
        len += (size_t)w;
    }
}

brume_status method_option_set(const method_options_def *def, void *opts, const char *key, const char *text)
{
    const method_option *o = method_option_find(def, key);
    if (!o) {
        char known[1024];
        known_keys(def, known, sizeof known);
        return err_set(BRUME_ERROR_PARSE, "%s: unknown key (known here: %.1000s)", key, known);
    }
    option_value v = {0};
    if (!parse(o, text, &v)) {
        if (o->kind == OPTION_PATH)
            return err_set(BRUME_ERROR_RANGE, "%s: path longer than %zu bytes", key, o->size - 1);
        bool closed_set = o->kind == OPTION_ENUM || o->kind == OPTION_BOOL;
        return err_set(closed_set ? BRUME_ERROR_PARSE : BRUME_ERROR_RANGE, "%s: '%s' is not %s", key, text, o->what);
    }
    store(o, text, &v, opts);
    if (o->effect)
        o->effect(opts, (int)v.number);
    return BRUME_OK;
}

/* ---- the public list ----------------------------------------------------------------------- */

static int option_total(void)
{
    int n = 0;
    for (int i = 0; i < METHOD_OPTIONS_COUNT; i++)
        n += methods[i]->count;
    return n;
}

int brume_option_count(void) { return option_total(); }

brume_status brume_option_get(brume_context *ctx, int index, brume_option *out)
{
    err_clear();
    if (!out)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_option_get: out: NULL"));
    memset(out, 0, sizeof *out);
    if (index < 0 || index >= option_total())
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "brume_option_get: index %d outside [0, %d)", index,
                                       option_total()));
    int i = 0;
    while (index >= methods[i]->count)
        index -= methods[i++]->count;
    const method_option *o = &methods[i]->options[index];
    out->key = o->key;
    out->kind = (brume_option_kind)o->kind; /* one enum (method_name.c) */
    out->values = o->what;
    out->default_value = o->def ? o->def : o->def_doc ? o->def_doc : "";
    out->doc = o->doc;
    return ctx_report(ctx, BRUME_OK);
}
