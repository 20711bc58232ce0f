/* stam_params.c - defaults and by-name setting of Stam's renderer options. */
#include "method/stam_params.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "method/method_options.h"

void stam_params_default(stam_params *p)
{
    memset(p, 0, sizeof *p);
    p->eps = 0.0;
    p->eta = 1e30;
    p->alpha = 0.05;
    p->lattice = 0;
    p->cell = 0.0;
    p->seed = 1;
    p->time = 0.0;
    p->rate = 1.0;
    p->ambient = col(0.0);
    p->steps = 16;
    p->light_grid = 32;
    p->bvh = true;
    p->paper = false;
    p->voxelize_resolution = 0;
    p->voxelize_realization = true;
}

const char *stam_param_names(void)
{
    return "eps, eta, alpha, lattice, cell, seed, time, rate, ambient, steps, light_grid, bvh, variant, "
           "voxelize.resolution, voxelize.realization";
}

static bool boolean(const char *text, bool *out)
{
    if (strcmp(text, "true") == 0 || strcmp(text, "1") == 0)
        *out = true;
    else if (strcmp(text, "false") == 0 || strcmp(text, "0") == 0)
        *out = false;
    else
        return false;
    return true;
}

/* "v" (gray) or "r,g,b", each finite and >= 0. */
static bool rgb(const char *text, color *out)
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
        if (n == 3 || !method_option_number(t, 0.0, 1e30, &v[n]))
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

brume_status stam_params_set(stam_params *p, const char *key, const char *value)
{
    stam_params n = *p;
    double v = 0.0;
    static const double BIG = 1e30;
#define NUMBER(name, lo, hi, field, what)                                                                       \
    else if (strcmp(key, name) == 0)                                                                             \
    {                                                                                                            \
        if (!method_option_number(value, lo, hi, &n.field))                                                     \
            return err_set(BRUME_ERROR_RANGE, "stam.%s: '%s' is not %s", key, value, what);                     \
    }
#define INTEGER(name, lo, hi, field)                                                                            \
    else if (strcmp(key, name) == 0)                                                                             \
    {                                                                                                            \
        if (!method_option_integer(value, lo, hi, &v))                                                                           \
            return err_set(BRUME_ERROR_RANGE, "stam.%s: '%s' is not an integer in [%g, %g]", key, value,        \
                           (double)(lo), (double)(hi));                                                          \
        n.field = (int)v;                                                                                        \
    }
    if (0) {
    }
    NUMBER("eps", 0.0, BIG, eps, "a number >= 0")
    NUMBER("eta", 1e-30, BIG, eta, "a number > 0")
    NUMBER("alpha", 1e-9, BIG, alpha, "a length > 0")
    NUMBER("cell", 0.0, BIG, cell, "a length >= 0 (0 = alpha / 3)")
    NUMBER("time", -BIG, BIG, time, "a finite time in seconds")
    NUMBER("rate", 0.0, BIG, rate, "a rate >= 0")
    INTEGER("steps", 1, 256, steps)
    INTEGER("light_grid", 0, 512, light_grid)
    else if (strcmp(key, "lattice") == 0) {
        if (!method_option_integer(value, 0, 512, &v) || v == 1)
            return err_set(BRUME_ERROR_RANGE, "stam.lattice: '%s' is not 0 (automatic) or an integer in [2, 512]", value);
        n.lattice = (int)v;
    } else if (strcmp(key, "variant") == 0) {
        if (strcmp(value, "paper") != 0 && strcmp(value, "corrected") != 0)
            return err_set(BRUME_ERROR_PARSE, "stam.variant: unknown variant '%s' (known: paper, corrected)", value);
        n.paper = value[0] == 'p';
    } else if (strcmp(key, "seed") == 0) {
        if (!method_option_integer(value, 0.0, 9007199254740992.0, &v))
            return err_set(BRUME_ERROR_RANGE, "stam.seed: '%s' is not an integer in [0, 2^53]", value);
        n.seed = (uint64_t)v;
    } else if (strcmp(key, "ambient") == 0) {
        if (!rgb(value, &n.ambient))
            return err_set(BRUME_ERROR_RANGE, "stam.ambient: '%s' is not a radiance >= 0 (v or r,g,b)", value);
    } else if (strcmp(key, "bvh") == 0) {
        if (!boolean(value, &n.bvh))
            return err_set(BRUME_ERROR_PARSE, "stam.bvh: '%s' is not true or false", value);
    } else if (strcmp(key, "voxelize.resolution") == 0) {
        if (!method_option_integer(value, 0, 2048, &v) || v == 1)
            return err_set(BRUME_ERROR_RANGE, "stam.voxelize.resolution: '%s' is not an integer in [2, 2048] (0 = off)",
                           value);
        n.voxelize_resolution = (int)v;
    } else if (strcmp(key, "voxelize.realization") == 0) {
        if (!boolean(value, &n.voxelize_realization))
            return err_set(BRUME_ERROR_PARSE, "stam.voxelize.realization: '%s' is not true or false", value);
    } else {
        return err_set(BRUME_ERROR_PARSE, "stam.%s: unknown key (known here: %s)", key, stam_param_names());
    }
#undef NUMBER
#undef INTEGER
    *p = n;
    return BRUME_OK;
}

void stam_randfield_params(const stam_params *p, double scene_time, vec3 extent, randfield_params *out)
{
    out->cell = p->cell > 0.0 ? p->cell : p->alpha / 3.0;
    if (p->lattice > 0) {
        for (int a = 0; a < 3; a++)
            out->n[a] = p->lattice;
    } else {
        /* one period covers the fields plus 6 alpha: K_Q(6 alpha) = exp(-18) */
        double span[3];
        for (int a = 0; a < 3; a++)
            span[a] = fmin(v3_get(extent, a), 1e12) + 6.0 * p->alpha;
        for (;;) {
            double points = 1.0;
            bool fits = true;
            for (int a = 0; a < 3; a++) {
                double n = ceil(span[a] / out->cell);
                n += fmod(n, 2.0); /* even sizes: the FFT's fast path */
                out->n[a] = n < 8.0 ? 8 : (int)fmin(n, 1e9);
                points *= out->n[a];
                fits = fits && n <= STAM_LATTICE_MAX;
            }
            if (fits && points <= STAM_LATTICE_POINTS_MAX)
                break;
            out->cell *= 1.25; /* a coarser lattice (docs/stam.md: trilinear lowers the variance) */
        }
    }
    out->alpha = p->alpha;
    out->seed = p->seed;
    out->time = p->time + scene_time;
    out->rate = p->rate;
}
