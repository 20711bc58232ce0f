/* scene_json_common.c - what the sections of the scene file reader share (scene_json_common.h):
 * JSON values to the builders' plain arrays, and the builders' statuses to messages that
 * name the file and the key. */
#include "scene/scene_json_common.h"

#include <math.h>

#include "core/error.h"
#include "scene/scene_build.h"

/* Helpers between JSON values and the builders' plain arrays. */
brume_status scene_json_vec(const cJSON *j, jloc at, const char *key, int required, double out[3])
{
    vec3 v = v3(out[0], out[1], out[2]);
    brume_status st = json_vec3(j, at, key, required, &v);
    if (st == BRUME_OK)
        v3_to_array(v, out);
    return st;
}

brume_status scene_json_color(const cJSON *j, jloc at, const char *key, int required, double hi, double out[3])
{
    color c = col_rgb(out[0], out[1], out[2]);
    brume_status st = json_color(j, at, key, required, 0.0, hi, &c);
    for (int i = 0; st == BRUME_OK && i < 3; i++)
        out[i] = c.c[i];
    return st;
}

/* A builder's failure, prefixed with the file and the key path of what it was building. */
brume_status scene_json_built(brume_status st, jloc at)
{
    return st ? err_prefix("%s: %s", at.file, at.path) : BRUME_OK;
}

brume_status scene_parse_unit_vector(const cJSON *j, jloc at, const char *key, double out[3])
{
    brume_status st = scene_json_vec(j, at, key, 1, out);
    if (st)
        return st;
    if (!(v3_length(v3(out[0], out[1], out[2])) > 0.0))
        return err_set(BRUME_ERROR_RANGE, "%s: %s.%s: must not be the zero vector", at.file, at.path, key);
    return BRUME_OK;
}
