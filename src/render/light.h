/* light.h - light sources.
 *   distant: light travelling along `direction` with irradiance E on a surface facing it
 *            (W m^-2; a white Lambertian plane facing it has radiance E / pi).
 *   point:   intensity I (W sr^-1) at `position`; irradiance I / r^2 at distance r.
 * The constant background radiance (Blasi's L-infinity) belongs to the scene. */
#ifndef BRUME_RENDER_LIGHT_H
#define BRUME_RENDER_LIGHT_H

#include "core/color.h"
#include "core/vec.h"

typedef enum light_kind {
    LIGHT_DISTANT,
    LIGHT_POINT
} light_kind;

typedef struct light {
    light_kind kind;
    vec3 direction; /* distant: unit propagation direction of the light */
    vec3 position;  /* point: world position */
    color L;        /* distant: irradiance E; point: intensity I */
} light;

/* Direct illumination sample from a delta light at p: unit direction towards the light
 * *wi, the distance to it *dist (INFINITY for distant), and the incident radiance
 * integrated over the delta (irradiance at p, normal to wi). */
color light_sample_delta(const light *l, vec3 p, vec3 *wi, double *dist);

#endif
