/* scene_stam.c - scene-file blob densities of Stam's method: explicit blobs, the cloud,
 * cluster and fire generators and the drift velocity, read into brume_density_new_blobs. */
#include "scene/scene_stam.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

static const double BIG = 1e30;

static brume_status parse_pair(const cJSON *j, jloc at, const char *key, double lo, double hi, double out[2])
{
    const cJSON *it = cJSON_GetObjectItemCaseSensitive(j, key);
    if (!it)
        return BRUME_OK;
    const cJSON *a = cJSON_GetArrayItem(it, 0), *b = cJSON_GetArrayItem(it, 1);
    if (!cJSON_IsArray(it) || cJSON_GetArraySize(it) != 2 || !cJSON_IsNumber(a) || !cJSON_IsNumber(b))
        return err_set(BRUME_ERROR_PARSE, "%s: %s.%s: expected [min, max]", at.file, at.path, key);
    double x = a->valuedouble, y = b->valuedouble;
    if (!(x >= lo && y <= hi && x <= y))
        return err_set(BRUME_ERROR_RANGE, "%s: %s.%s: need %.17g <= min <= max <= %.17g, got [%.17g, %.17g]", at.file, at.path,
                       key, lo, hi, x, y);
    out[0] = x;
    out[1] = y;
    return BRUME_OK;
}

/* radii: a number (a sphere) or [rx, ry, rz], each > 0 */
static brume_status parse_radii(const cJSON *j, jloc at, const char *key, int required, double out[3])
{
    const cJSON *it = cJSON_GetObjectItemCaseSensitive(j, key);
    if (cJSON_IsNumber(it)) {
        double r = 0.0;
        brume_status st = json_number(j, at, key, 1, 1e-12, BIG, &r);
        if (st == BRUME_OK)
            out[0] = out[1] = out[2] = r;
        return st;
    }
    vec3 v = v3(out[0], out[1], out[2]);
    brume_status st = json_vec3(j, at, key, required, &v);
    if (st == BRUME_OK && it && !(v.x > 0.0 && v.y > 0.0 && v.z > 0.0))
        return err_set(BRUME_ERROR_RANGE, "%s: %s.%s: every semi-axis must be > 0", at.file, at.path, key);
    if (st == BRUME_OK)
        v3_to_array(v, out);
    return st;
}

static brume_status parse_vec(const cJSON *j, jloc at, const char *key, int required, double out[3])
{
    vec3 v = v3(out[0], out[1], out[2]);
    brume_status st = json_vec3(j, at, key, required, &v);
    if (st == BRUME_OK)
        v3_to_array(v, out);
    return st;
}

static brume_status parse_cloud_params(const cJSON *j, jloc at, brume_blob_generator *g)
{
    brume_status st;
    if ((st = json_int(j, at, "count", 0, 1, 1 << 22, &g->count))) return st;
    if ((st = parse_pair(j, at, "h", 1e-9, BIG, g->h))) return st;
    if ((st = json_number(j, at, "density", 0, 0.0, BIG, &g->density))) return st;
    if ((st = json_number(j, at, "falloff", 0, 0.0, 100.0, &g->falloff))) return st;
    return json_u64(j, at, "seed", 0, &g->seed);
}

static brume_status parse_generator(const cJSON *j, jloc at, brume_blob_generator *g)
{
    char type[32];
    brume_status st = json_object_type(j, at, type, sizeof type);
    if (st) return st;
    if (strcmp(type, "cloud") == 0) {
        static const char *const keys[] = {"type", "center", "radii", "count", "h", "density", "falloff", "seed", NULL};
        if ((st = json_check_object(j, at, keys))) return st;
        brume_blob_generator_default(g, BRUME_BLOBS_CLOUD);
        if ((st = parse_cloud_params(j, at, g))) return st;
        if ((st = parse_vec(j, at, "center", 1, g->center))) return st;
        return parse_radii(j, at, "radii", 1, g->radii);
    }
    if (strcmp(type, "cluster") == 0) {
        static const char *const keys[] = {"type", "bounds_min", "bounds_max", "clouds", "radii_min", "radii_max",
                                           "count", "h", "density", "falloff", "seed", NULL};
        if ((st = json_check_object(j, at, keys))) return st;
        brume_blob_generator_default(g, BRUME_BLOBS_CLUSTER);
        if ((st = parse_cloud_params(j, at, g))) return st;
        if ((st = parse_vec(j, at, "bounds_min", 1, g->bounds_min))) return st;
        if ((st = parse_vec(j, at, "bounds_max", 1, g->bounds_max))) return st;
        if ((st = parse_radii(j, at, "radii_min", 1, g->radii_min))) return st;
        if ((st = parse_radii(j, at, "radii_max", 1, g->radii_max))) return st;
        return json_int(j, at, "clouds", 0, 1, 100000, &g->clouds);
    }
    if (strcmp(type, "fire") == 0) {
        static const char *const keys[] = {"type", "base", "up", "height", "radius", "count", "h", "density", "band",
                                           "seed", NULL};
        if ((st = json_check_object(j, at, keys))) return st;
        brume_blob_generator_default(g, BRUME_BLOBS_FIRE);
        if ((st = parse_vec(j, at, "base", 1, g->base))) return st;
        if ((st = parse_vec(j, at, "up", 0, g->up))) return st;
        if ((st = json_number(j, at, "height", 0, 1e-9, BIG, &g->height))) return st;
        if ((st = json_number(j, at, "radius", 0, 0.0, BIG, &g->radius))) return st;
        if ((st = json_int(j, at, "count", 0, 1, 1 << 22, &g->count))) return st;
        if ((st = json_number(j, at, "h", 0, 1e-9, BIG, &g->fire_h))) return st;
        if ((st = json_number(j, at, "density", 0, 0.0, BIG, &g->density))) return st;
        if ((st = parse_pair(j, at, "band", 0.0, 1.0, g->band))) return st;
        return json_u64(j, at, "seed", 0, &g->seed);
    }
    return err_set(BRUME_ERROR_PARSE, "%s: %s.type: unknown generator '%s' (known: cloud, cluster, fire)", at.file,
                   at.path, type);
}

brume_status scene_parse_blobs(const cJSON *j, jloc at, brume_density **out)
{
    static const char *const keys[] = {"type", "blobs", "generators", "velocity", "cutoff", NULL};
    brume_status st = json_check_object(j, at, keys);
    if (st) return st;
    double cutoff = 0.0, velocity[3] = {0, 0, 0};
    if ((st = json_number(j, at, "cutoff", 0, 1.0, 10.0, &cutoff))) return st;
    if ((st = parse_vec(j, at, "velocity", 0, velocity))) return st;
    const cJSON *arr = cJSON_GetObjectItemCaseSensitive(j, "blobs");
    const cJSON *gens = cJSON_GetObjectItemCaseSensitive(j, "generators");
    if (arr && !cJSON_IsArray(arr))
        return err_set(BRUME_ERROR_PARSE, "%s: %s.blobs: expected an array of [x, y, z, mass, h]", at.file, at.path);
    if (gens && !cJSON_IsArray(gens))
        return err_set(BRUME_ERROR_PARSE, "%s: %s.generators: expected an array", at.file, at.path);
    int n = cJSON_GetArraySize(arr), ng = cJSON_GetArraySize(gens);
    if (n == 0 && ng == 0)
        return err_set(BRUME_ERROR_PARSE, "%s: %s: no blobs (give \"blobs\" or \"generators\")", at.file, at.path);
    double *b = malloc(sizeof *b * 5 * (size_t)(n > 0 ? n : 1));
    brume_blob_generator *g = malloc(sizeof *g * (size_t)(ng > 0 ? ng : 1));
    if (!b || !g) {
        free(b);
        free(g);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", at.file);
    }
    int i = 0;
    for (const cJSON *e = arr ? arr->child : NULL; e && !st; e = e->next, i++) {
        double *v = b + 5 * (size_t)i;
        int k = 0;
        for (const cJSON *c = cJSON_IsArray(e) ? e->child : NULL; c && k < 6; c = c->next, k++)
            if (k < 5)
                v[k] = cJSON_IsNumber(c) ? c->valuedouble : (double)NAN;
        if (k != 5 || !isfinite(v[0] + v[1] + v[2] + v[3] + v[4]) || v[3] < 0.0 || !(v[4] > 0.0))
            st = err_set(BRUME_ERROR_PARSE, "%s: %s.blobs[%d]: expected [x, y, z, mass >= 0, h > 0]", at.file, at.path,
                         i);
    }
    i = 0;
    for (const cJSON *e = gens ? gens->child : NULL; e && !st; e = e->next, i++) {
        char kp[300];
        snprintf(kp, sizeof kp, "%s.generators[%d]", at.path, i);
        st = parse_generator(e, (jloc){at.file, kp}, &g[i]);
    }
    if (!st && (st = brume_density_new_blobs(NULL, b, n, g, ng, cutoff, velocity, out)))
        err_prefix("%s: %s", at.file, at.path);
    free(b);
    free(g);
    return st;
}
