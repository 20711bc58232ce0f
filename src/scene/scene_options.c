/* scene_options.c - brume_scene_set_option: the one option mechanism of the rendering
 * methods, "METHOD.KEY" = text, parsed by the row of that key in its method's table
 * (method/method_options.h). */
#include <string.h>

#include "core/context.h"
#include "core/error.h"
#include "scene/scene.h"

brume_status brume_scene_set_option(brume_context *ctx, brume_scene *s, const char *key, const char *value)
{
    err_clear();
    if (!s || !key || !value)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_scene_set_option: %s: NULL",
                                       !s ? "scene" : !key ? "key" : "value"));
    if (s->committed)
        return ctx_report(ctx, err_set(BRUME_ERROR_STATE, "%s: option %s set after commit", s->source, key));
    method_options_id id;
    const method_options_def *def = method_options_find(key, &id);
    brume_status st;
    if (def)
        st = method_option_set(def, s->options[id], key, value);
    else
        st = err_set(BRUME_ERROR_PARSE, "%.200s: unknown key (known here: METHOD.KEY for METHOD one of %s)", key,
                     method_options_methods());
    if (st != BRUME_OK)
        err_prefix("%s", s->source);
    return ctx_report(ctx, st);
}
