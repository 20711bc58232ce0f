/* scene_blasi.c - the scene file's "blasi" options and "fractal_cloud" density. */
#include "io/scene_blasi.h"

#include <stdio.h>
#include <string.h>

#include "core/error.h"
#include "density/fractal.h"

brume_status scene_parse_blasi(const cJSON *root, jloc top, blasi_options *o)
{
    const cJSON *b = cJSON_GetObjectItemCaseSensitive(root, "blasi");
    if (!b)
        return BRUME_OK;
    static const char *const keys[] = {"light_rays", "r", "kprime", "step", "threshold", "sources", "exit_deposit",
                                       "view_attenuation", "variant", "save_light", "load_light", NULL};
    jloc at = {top.file, "blasi"};
    if (!cJSON_IsObject(b))
        return err_set(BRUME_ERROR_PARSE, "%s: blasi: expected an object", top.file);
    brume_status st = json_check_object(b, at, keys);
    if (st)
        return st;
    /* "variant" first, so that exit_deposit and view_attenuation given beside it win */
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(b, "variant");
    for (int pass = 0; pass < 2; pass++)
        for (const cJSON *it = b->child; it; it = it->next) {
            if (strcmp(it->string, "comment") == 0 || (it == v) != (pass == 0))
                continue;
            char text[2 * BLASI_PATH_MAX];
            if (cJSON_IsNumber(it)) {
                snprintf(text, sizeof text, "%.17g", it->valuedouble);
            } else if (cJSON_IsString(it)) {
                bool is_path = strcmp(it->string, "save_light") == 0 || strcmp(it->string, "load_light") == 0;
                if (is_path)
                    json_resolve_path(top.file, it->valuestring, text, sizeof text);
                else
                    snprintf(text, sizeof text, "%s", it->valuestring);
            } else {
                return err_set(BRUME_ERROR_PARSE, "%s: blasi.%s: expected a number or a string", top.file, it->string);
            }
            if ((st = blasi_options_set(o, it->string, text)))
                return err_prefix("%s", top.file);
        }
    return BRUME_OK;
}

static brume_status parse_bounds(const cJSON *j, jloc at, box3 *out)
{
    const cJSON *b = cJSON_GetObjectItemCaseSensitive(j, "bounds");
    if (!b)
        return BRUME_OK;
    double v[6];
    bool ok = cJSON_IsArray(b) && cJSON_GetArraySize(b) == 2;
    for (int i = 0; ok && i < 2; i++) {
        const cJSON *c = cJSON_GetArrayItem(b, i);
        ok = cJSON_IsArray(c) && cJSON_GetArraySize(c) == 3;
        for (int k = 0; ok && k < 3; k++) {
            const cJSON *x = cJSON_GetArrayItem(c, k);
            ok = cJSON_IsNumber(x) && isfinite(x->valuedouble);
            if (ok)
                v[3 * i + k] = x->valuedouble;
        }
    }
    if (!ok)
        return err_set(BRUME_ERROR_PARSE, "%s: %s.bounds: expected [[xmin, ymin, zmin], [xmax, ymax, zmax]]", at.file,
                       at.path);
    if (!(v[0] < v[3] && v[1] < v[4] && v[2] < v[5]))
        return err_set(BRUME_ERROR_RANGE, "%s: %s.bounds: need min < max on every axis", at.file, at.path);
    *out = (box3){v3(v[0], v[1], v[2]), v3(v[3], v[4], v[5])};
    return BRUME_OK;
}

brume_status scene_parse_fractal_cloud(const cJSON *j, jloc at, density **out)
{
    static const char *const keys[] = {"type", "dims", "seed", "method", "hurst", "shape", "falloff", "threshold",
                                       "density", "octaves", "frequency", "bounds", "filter", NULL};
    brume_status st = json_check_object(j, at, keys);
    if (st) return st;
    fractal_params p;
    fractal_params_default(&p);
    const cJSON *dims = cJSON_GetObjectItemCaseSensitive(j, "dims");
    if (dims) {
        bool ok = cJSON_IsArray(dims) && cJSON_GetArraySize(dims) == 3;
        for (int k = 0; ok && k < 3; k++) {
            const cJSON *x = cJSON_GetArrayItem(dims, k);
            ok = cJSON_IsNumber(x) && x->valuedouble >= 1 && x->valuedouble <= 1024 &&
                 x->valuedouble == (double)(int)x->valuedouble;
            if (ok)
                p.n[k] = (int)x->valuedouble;
        }
        if (!ok)
            return err_set(BRUME_ERROR_PARSE, "%s: %s.dims: expected [nx, ny, nz], integers in [1, 1024]", at.file,
                           at.path);
    }
    char text[32] = "";
    if ((st = json_u64(j, at, "seed", 0, &p.seed))) return st;
    if ((st = json_string(j, at, "method", 0, text, sizeof text))) return st;
    if (text[0]) {
        if (strcmp(text, "midpoint") == 0) p.method = FRACTAL_MIDPOINT;
        else if (strcmp(text, "spectral") == 0) p.method = FRACTAL_SPECTRAL;
        else if (strcmp(text, "perlin") == 0) p.method = FRACTAL_PERLIN;
        else
            return err_set(BRUME_ERROR_PARSE, "%s: %s.method: '%s' is not one of midpoint, spectral, perlin", at.file,
                           at.path, text);
    }
    text[0] = '\0';
    if ((st = json_string(j, at, "shape", 0, text, sizeof text))) return st;
    if (text[0]) {
        if (strcmp(text, "ellipsoid") == 0) p.shape = FRACTAL_SHAPE_ELLIPSOID;
        else if (strcmp(text, "slab") == 0) p.shape = FRACTAL_SHAPE_SLAB;
        else if (strcmp(text, "none") == 0) p.shape = FRACTAL_SHAPE_NONE;
        else
            return err_set(BRUME_ERROR_PARSE, "%s: %s.shape: '%s' is not one of ellipsoid, slab, none", at.file,
                           at.path, text);
    }
    if ((st = json_number(j, at, "hurst", 0, 1e-3, 0.999, &p.hurst))) return st;
    if ((st = json_number(j, at, "falloff", 0, 1e-3, 1.0, &p.falloff))) return st;
    if ((st = json_number(j, at, "threshold", 0, 0.0, 0.99, &p.threshold))) return st;
    if ((st = json_number(j, at, "density", 0, 1e-9, 1e12, &p.density))) return st;
    if ((st = json_int(j, at, "octaves", 0, 1, 16, &p.octaves))) return st;
    if ((st = json_number(j, at, "frequency", 0, 1e-3, 1e3, &p.frequency))) return st;
    box3 b = {v3(-0.5 * p.n[0], -0.5 * p.n[1], -0.5 * p.n[2]), v3(0.5 * p.n[0], 0.5 * p.n[1], 0.5 * p.n[2])};
    if ((st = parse_bounds(j, at, &b))) return st;
    grid_filter filter = GRID_NEAREST;
    text[0] = '\0';
    if ((st = json_string(j, at, "filter", 0, text, sizeof text))) return st;
    if (text[0] && strcmp(text, "nearest") != 0) {
        if (strcmp(text, "trilinear") != 0)
            return err_set(BRUME_ERROR_PARSE, "%s: %s.filter: '%s' is not one of nearest, trilinear", at.file, at.path,
                           text);
        filter = GRID_TRILINEAR;
    }
    *out = fractal_cloud(&p, b, filter);
    if (!*out)
        return err_prefix("%s: %s", at.file, at.path);
    return BRUME_OK;
}
