/* path_options.c - defaults and by-name setting of the path integrator's options. */
#include "method/path_options.h"

#include <string.h>

#include "core/error.h"
#include "method/method_options.h"

/* The default scale of sun-lobe sampling: measured on the comparison clouds of
 * bench/cloud64_vs_cycles.sh (docs/performance.md, "Sun-lobe sampling"). */
#define PATH_SUN_LOBE_DEFAULT 2.0
/* The default threshold of the sun roulette, measured the same way (docs/performance.md,
 * "Sun rays deep in a cloud"). */
#define PATH_SUN_ROULETTE_DEFAULT 0.03

void path_options_default(path_options *o)
{
    memset(o, 0, sizeof *o);
    o->sun_lobe = PATH_SUN_LOBE_DEFAULT;
    o->sun_roulette = PATH_SUN_ROULETTE_DEFAULT;
    o->split = 1.0;
}

const char *path_option_names(void) { return "sun_lobe, sun_roulette, split"; }

brume_status path_options_set(path_options *o, const char *key, const char *value)
{
    path_options n = *o;
    if (strcmp(key, "sun_lobe") == 0) {
        if (!method_option_number(value, 0.0, 100.0, &n.sun_lobe))
            return err_set(BRUME_ERROR_RANGE, "path.sun_lobe: '%s' is not a number in [0, 100]", value);
    } else if (strcmp(key, "sun_roulette") == 0) {
        if (!method_option_number(value, 0.0, 1.0, &n.sun_roulette))
            return err_set(BRUME_ERROR_RANGE, "path.sun_roulette: '%s' is not a number in [0, 1]", value);
    } else if (strcmp(key, "split") == 0) {
        if (!method_option_integer(value, 1.0, PATH_SPLIT_MAX, &n.split))
            return err_set(BRUME_ERROR_RANGE, "path.split: '%s' is not a whole number in [1, %d]", value,
                           PATH_SPLIT_MAX);
    } else {
        return err_set(BRUME_ERROR_PARSE, "path.%s: unknown key (known here: %s)", key, path_option_names());
    }
    *o = n;
    return BRUME_OK;
}
