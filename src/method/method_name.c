/* method_name.c - the public face of the methods' closed set (brume.h's brume_method): its
 * values are method/method.h's integrator_kind, its names the scene file's render.method. */
#include <stddef.h>

#include "brume.h"
#include "core/context.h"
#include "core/error.h"
#include "method/method.h"

_Static_assert((int)BRUME_METHOD_PATH == (int)INTEGRATOR_PATH && (int)BRUME_METHOD_SINGLE == (int)INTEGRATOR_SINGLE &&
                   (int)BRUME_METHOD_BLASI == (int)INTEGRATOR_BLASI && (int)BRUME_METHOD_STAM == (int)INTEGRATOR_STAM,
               "brume_method and integrator_kind are one enum");

/* in the order of the enum; integrator_from_name reads the same names back (test_api.c:
 * method_names_round_trip) */
static const char *const method_names[] = {"path", "single", "blasi", "stam"};

const char *brume_method_name(brume_method method)
{
    return (unsigned)method < sizeof method_names / sizeof method_names[0] ? method_names[method] : NULL;
}

brume_status brume_method_from_name(brume_context *ctx, const char *name, brume_method *method)
{
    err_clear();
    if (!name || !method)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_method_from_name: %s: NULL",
                                       !name ? "name" : "method"));
    integrator_kind k;
    if (!integrator_from_name(name, &k))
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "unknown method '%s' (known: %s)", name,
                                       integrator_names()));
    *method = (brume_method)k;
    return ctx_report(ctx, BRUME_OK);
}
