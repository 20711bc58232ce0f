/* light.c - direct-illumination samples of lights. */
#include "render/light.h"

color light_sample_delta(const light *l, vec3 p, vec3 *wi, double *dist)
{
    switch (l->kind) {
    case LIGHT_DISTANT:
        *wi = v3_neg(l->direction);
        *dist = INFINITY;
        return l->L;
    case LIGHT_POINT: {
        vec3 d = v3_sub(l->position, p);
        double r2 = v3_dot(d, d);
        *dist = sqrt(r2);
        *wi = v3_scale(d, 1.0 / *dist);
        return col_scale(l->L, 1.0 / r2);
    }
    }
    *dist = 0.0;
    return col(0.0);
}
