/* method.c - the names of the rendering methods (method/method.h). */
#include "method/method.h"

#include <string.h>

bool integrator_from_name(const char *name, integrator_kind *out)
{
    if (strcmp(name, "path") == 0)
        *out = INTEGRATOR_PATH;
    else if (strcmp(name, "single") == 0)
        *out = INTEGRATOR_SINGLE;
    else if (strcmp(name, "blasi") == 0)
        *out = INTEGRATOR_BLASI;
    else if (strcmp(name, "stam") == 0)
        *out = INTEGRATOR_STAM;
    else
        return false;
    return true;
}

const char *integrator_names(void) { return "path, single, blasi, stam"; }
