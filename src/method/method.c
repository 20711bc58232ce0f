/* method.c - the names of the rendering methods (method/method.h): one table, in the order
 * of integrator_kind (and of brume.h's brume_method), read by every name lookup. */
#include "method/method.h"

#include <string.h>

static const char *const method_names[] = {"path", "single", "blasi", "stam"};
#define METHOD_COUNT (sizeof method_names / sizeof method_names[0])
_Static_assert(METHOD_COUNT == (size_t)INTEGRATOR_STAM + 1, "a name per integrator_kind");

const char *integrator_name(integrator_kind kind)
{
    return (unsigned)kind < METHOD_COUNT ? method_names[kind] : NULL;
}

bool integrator_from_name(const char *name, integrator_kind *out)
{
    for (size_t i = 0; i < METHOD_COUNT; i++)
        if (strcmp(name, method_names[i]) == 0) {
            *out = (integrator_kind)i;
            return true;
        }
    return false;
}

const char *integrator_names(void) { return "path, single, blasi, stam"; }
