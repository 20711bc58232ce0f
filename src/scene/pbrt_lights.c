/* pbrt_lights.c - pbrt's LightSource directive as brume's lights. */
#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/vec.h"
#include "io/grid_io.h"
#include "io/json.h"
#include "scene/scene_build.h"
#include "scene/pbrt.h"

brume_status pbrt_light_directive(pbrt_state *S, const char *type, params *ps)
{
    lexer *L = &S->L;
    brume_status st;
    double Lrgb[3] = {1, 1, 1}, scale = 1.0;
    if ((st = pbrt_get_float(L, ps, "scale", &scale))) return st;
    m4 ctm = S->a[S->depth].ctm;
    if (strcmp(type, "distant") == 0) {
        double from[3] = {0, 0, 0}, to[3] = {0, 0, 1};
        if ((st = pbrt_get_color(L, ps, "L", Lrgb)) || (st = pbrt_get_point(L, ps, "from", from)) ||
            (st = pbrt_get_point(L, ps, "to", to)) || (st = pbrt_all_used(L, ps, "LightSource \"distant\"")))
            return st;
        vec3 d = pbrt_m4_vector(ctm, v3(to[0] - from[0], to[1] - from[1], to[2] - from[2]));
        if (!(v3_length(d) > 0.0))
            return pbrt_fail(L, "LightSource \"%s\": from equals to", type);
        d = v3_normalize(d);
        cJSON *l = cJSON_CreateObject();
        double dv[3] = {d.x, d.y, d.z}, E[3] = {Lrgb[0] * scale, Lrgb[1] * scale, Lrgb[2] * scale};
        cJSON_AddStringToObject(l, "type", "distant");
        cJSON_AddItemToObject(l, "direction", cJSON_CreateDoubleArray(dv, 3));
        cJSON_AddItemToObject(l, "irradiance", cJSON_CreateDoubleArray(E, 3));
        cJSON_AddItemToArray(S->lights, l);
    } else if (strcmp(type, "point") == 0) {
        double from[3] = {0, 0, 0};
        if ((st = pbrt_get_color(L, ps, "I", Lrgb)) || (st = pbrt_get_point(L, ps, "from", from)) ||
            (st = pbrt_all_used(L, ps, "LightSource \"point\"")))
            return st;
        vec3 p = pbrt_m4_point(ctm, v3(from[0], from[1], from[2]));
        cJSON *l = cJSON_CreateObject();
        double pv[3] = {p.x, p.y, p.z}, I[3] = {Lrgb[0] * scale, Lrgb[1] * scale, Lrgb[2] * scale};
        cJSON_AddStringToObject(l, "type", "point");
        cJSON_AddItemToObject(l, "position", cJSON_CreateDoubleArray(pv, 3));
        cJSON_AddItemToObject(l, "intensity", cJSON_CreateDoubleArray(I, 3));
        cJSON_AddItemToArray(S->lights, l);
    } else if (strcmp(type, "infinite") == 0) {
        if ((st = pbrt_get_color(L, ps, "L", Lrgb)) || (st = pbrt_all_used(L, ps, "LightSource \"infinite\"")))
            return st;
        for (int c = 0; c < 3; c++) /* several constant skies add */
            S->background[c] += Lrgb[c] * scale;
        S->have_background = true;
    } else {
        return pbrt_fail(L, "LightSource \"%s\": not supported by brume (distant, point, infinite with L)", type);
    }
    return BRUME_OK;
}
