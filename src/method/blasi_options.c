/* blasi_options.c - defaults and by-name setting of the blasi integrator's options. */
#include "method/blasi_options.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "method/method_options.h"

void blasi_options_default(blasi_options *o)
{
    memset(o, 0, sizeof *o);
    o->light_rays = 1u << 21; /* "2 million rays" (Section 5) */
    o->r = (double)NAN;
    o->kprime = (double)NAN;
    o->step = 0.0;
    o->threshold = 1e-3;
    o->sources = 16;
    o->exit_deposit = BLASI_EXIT_PAPER;
    o->view_attenuation = BLASI_VIEW_ABSORPTION;
}

const char *blasi_option_names(void)
{
    return "light_rays, r, kprime, step, threshold, sources, exit_deposit, view_attenuation, gather, variant, "
           "voxels, save_light, load_light";
}

/* method_option_number, with hi left out when hi_open. */
static bool parse_double(const char *text, double lo, double hi, bool hi_open, double *out)
{
    double v;
    if (!method_option_number(text, lo, hi, &v) || (hi_open && v >= hi))
        return false;
    *out = v;
    return true;
}

brume_status blasi_options_set(blasi_options *o, const char *key, const char *value)
{
    blasi_options n = *o;
    double v = 0.0;
    if (strcmp(key, "light_rays") == 0) {
        if (!method_option_integer(value, 1.0, 1e12, &v))
            return err_set(BRUME_ERROR_RANGE, "blasi.light_rays: '%s' is not an integer in [1, 1e12]", value);
        n.light_rays = (uint64_t)v;
    } else if (strcmp(key, "r") == 0) {
        if (!parse_double(value, 0.0, 1.0, false, &n.r))
            return err_set(BRUME_ERROR_RANGE, "blasi.r: '%s' is not a number in [0, 1]", value);
    } else if (strcmp(key, "kprime") == 0) {
        if (!parse_double(value, -0.999999, 0.999999, false, &n.kprime))
            return err_set(BRUME_ERROR_RANGE, "blasi.kprime: '%s' is not a number in (-1, 1)", value);
    } else if (strcmp(key, "step") == 0) {
        if (!parse_double(value, 0.0, 1e30, false, &n.step))
            return err_set(BRUME_ERROR_RANGE, "blasi.step: '%s' is not a length >= 0 (0 = voxel by voxel)", value);
    } else if (strcmp(key, "threshold") == 0) {
        if (!parse_double(value, 0.0, 1.0, true, &n.threshold))
            return err_set(BRUME_ERROR_RANGE, "blasi.threshold: '%s' is not a number in [0, 1)", value);
    } else if (strcmp(key, "sources") == 0) {
        if (!method_option_integer(value, 1.0, 65536.0, &v))
            return err_set(BRUME_ERROR_RANGE, "blasi.sources: '%s' is not an integer in [1, 65536]", value);
        n.sources = (int)v;
    } else if (strcmp(key, "exit_deposit") == 0) {
        if (strcmp(value, "paper") == 0)
            n.exit_deposit = BLASI_EXIT_PAPER;
        else if (strcmp(value, "none") == 0)
            n.exit_deposit = BLASI_EXIT_NONE;
        else
            return err_set(BRUME_ERROR_PARSE, "blasi.exit_deposit: '%s' is not one of paper, none", value);
        n.exit_given = true;
    } else if (strcmp(key, "view_attenuation") == 0) {
        if (strcmp(value, "absorption") == 0)
            n.view_attenuation = BLASI_VIEW_ABSORPTION;
        else if (strcmp(value, "extinction") == 0)
            n.view_attenuation = BLASI_VIEW_EXTINCTION;
        else
            return err_set(BRUME_ERROR_PARSE, "blasi.view_attenuation: '%s' is not one of absorption, extinction",
                           value);
        n.view_given = true;
    } else if (strcmp(key, "gather") == 0) {
        if (strcmp(value, "path_length") == 0)
            n.gather = BLASI_GATHER_PATH_LENGTH;
        else if (strcmp(value, "printed") == 0)
            n.gather = BLASI_GATHER_PRINTED;
        else
            return err_set(BRUME_ERROR_PARSE, "blasi.gather: '%s' is not one of path_length, printed", value);
    } else if (strcmp(key, "variant") == 0) {
        bool paper = strcmp(value, "paper") == 0;
        if (!paper && strcmp(value, "physical") != 0)
            return err_set(BRUME_ERROR_PARSE, "blasi.variant: '%s' is not one of paper, physical", value);
        if (!n.exit_given)
            n.exit_deposit = paper ? BLASI_EXIT_PAPER : BLASI_EXIT_NONE;
        if (!n.view_given)
            n.view_attenuation = paper ? BLASI_VIEW_ABSORPTION : BLASI_VIEW_EXTINCTION;
    } else if (strcmp(key, "voxels") == 0) {
        if (!method_option_integer(value, 0.0, 2048.0, &v) || v == 1.0)
            return err_set(BRUME_ERROR_RANGE, "blasi.voxels: '%s' is not 0 or an integer in [2, 2048]", value);
        n.voxels = (int)v;
    } else if (strcmp(key, "save_light") == 0 || strcmp(key, "load_light") == 0) {
        char *dst = key[0] == 's' ? n.save_light : n.load_light;
        if (strlen(value) >= BLASI_PATH_MAX)
            return err_set(BRUME_ERROR_RANGE, "blasi.%s: path longer than %d bytes", key, BLASI_PATH_MAX - 1);
        snprintf(dst, BLASI_PATH_MAX, "%s", value);
    } else {
        return err_set(BRUME_ERROR_PARSE, "blasi.%s: unknown key (known here: %s)", key, blasi_option_names());
    }
    *o = n;
    return BRUME_OK;
}
