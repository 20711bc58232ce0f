/* scene_options.c - brume_scene_set_option: named options of the rendering methods,
 * "METHOD.KEY" = text, as a scene file would give them (docs/scene-format.md). */
#include <string.h>

#include "core/context.h"
#include "core/error.h"
#include "render/scene.h"

brume_status brume_scene_set_option(brume_context *ctx, brume_scene *s, const char *key, const char *value)
{
    err_clear();
    if (!s || !key || !value)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_scene_set_option: NULL argument"));
    if (s->committed)
        return ctx_report(ctx, err_set(BRUME_ERROR_STATE, "%s: option %s set after commit", s->source, key));
    brume_status st;
    if (strncmp(key, "blasi.", 6) == 0)
        st = blasi_options_set(&s->blasi, key + 6, value);
    else
        st = err_set(BRUME_ERROR_PARSE, "%s: unknown option (known: blasi.KEY with KEY one of %s)", key,
                     blasi_option_names());
    if (st != BRUME_OK)
        err_prefix("%s", s->source);
    return ctx_report(ctx, st);
}
