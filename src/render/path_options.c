/* path_options.c - defaults and by-name setting of the path integrator's options. */
#include "render/path_options.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

/* The default scale of sun-lobe sampling: measured on the comparison clouds of
 * bench/cloud64_vs_cycles.sh (docs/performance.md, "Sun-lobe sampling"). */
#define PATH_SUN_LOBE_DEFAULT 2.0

void path_options_default(path_options *o)
{
    memset(o, 0, sizeof *o);
    o->sun_lobe = PATH_SUN_LOBE_DEFAULT;
}

const char *path_option_names(void) { return "sun_lobe"; }

brume_status path_options_set(path_options *o, const char *key, const char *value)
{
    path_options n = *o;
    if (strcmp(key, "sun_lobe") == 0) {
        char *end = NULL;
        errno = 0;
        double v = strtod(value, &end);
        if (end == value || *end != '\0' || errno != 0 || !isfinite(v) || v < 0.0 || v > 100.0)
            return err_set(BRUME_ERROR_RANGE, "path.sun_lobe: '%s' is not a number in [0, 100]", value);
        n.sun_lobe = v;
    } else {
        return err_set(BRUME_ERROR_PARSE, "path.%s: unknown key (known here: %s)", key, path_option_names());
    }
    *o = n;
    return BRUME_OK;
}
