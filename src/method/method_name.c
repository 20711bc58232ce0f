/* method_name.c - the public faces of the methods' closed sets: brume_method (its values are
 * method/method.h's integrator_kind, its names the scene file's render.method) and
 * brume_option_kind (method/method_options.h's method_option_kind). */
#include <stddef.h>

#include "brume.h"
#include "core/context.h"
#include "core/error.h"
#include "method/method.h"
#include "method/method_options.h"

_Static_assert((int)BRUME_METHOD_PATH == (int)INTEGRATOR_PATH && (int)BRUME_METHOD_SINGLE == (int)INTEGRATOR_SINGLE &&
                   (int)BRUME_METHOD_BLASI == (int)INTEGRATOR_BLASI && (int)BRUME_METHOD_STAM == (int)INTEGRATOR_STAM,
               "brume_method and integrator_kind are one enum");

_Static_assert((int)BRUME_OPTION_NUMBER == (int)OPTION_NUMBER && (int)BRUME_OPTION_INTEGER == (int)OPTION_INTEGER &&
                   (int)BRUME_OPTION_ENUM == (int)OPTION_ENUM && (int)BRUME_OPTION_BOOL == (int)OPTION_BOOL &&
                   (int)BRUME_OPTION_COLOR == (int)OPTION_COLOR && (int)BRUME_OPTION_PATH == (int)OPTION_PATH,
               "brume_option_kind and method_option_kind are one enum");

const char *brume_option_kind_name(brume_option_kind kind)
{
    static const char *const names[] = {"number", "integer", "enum", "bool", "color", "path"};
    return (unsigned)kind < sizeof names / sizeof names[0] ? names[kind] : NULL;
}

const char *brume_method_name(brume_method method) { return integrator_name((integrator_kind)method); }

brume_status brume_method_from_name(brume_context *ctx, const char *name, brume_method *method)
{
    err_clear();
    if (!name || !method)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_method_from_name: %s: NULL",
                                       !name ? "name" : "method"));
    integrator_kind k;
    if (!integrator_from_name(name, &k))
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "render.method: unknown method '%s' (known: %s)",
                                       name, integrator_names()));
    *method = (brume_method)k;
    return ctx_report(ctx, BRUME_OK);
}
