/* light.h - light sources, their direct-illumination sampling and pdfs (for MIS).
 *
 * Units (world units of length, linear RGB):
 *   distant  irradiance E (W m^-2) on a surface facing the light, travelling along
 *            `direction`; with angular_radius > 0 it is a disk of uniform radiance
 *            L = E / (pi sin^2 angular_radius) seen over that cone (a sun).
 *   point    intensity I (W sr^-1).
 *   spot     intensity I(theta) = I * profile(theta), theta from the spot axis: a
 *            goniometric table (angle in degrees, factor) interpolated linearly, or a
 *            smooth cone (full intensity inside cone_inner, zero beyond cone_outer).
 *   sphere   uniform radiance L (W m^-2 sr^-1) leaving a sphere of `radius`.
 *   disk     uniform radiance L leaving one side (along `direction`) of a disk of `radius`.
 * The background (constant radiance or an environment image) is `envmap.h`. */
#ifndef BRUME_SCENE_LIGHT_H
#define BRUME_SCENE_LIGHT_H

#include <stdbool.h>

#include "core/color.h"
#include "core/vec.h"

/* A sun (distant light) narrower than this (radians, about 2 arcseconds) is sampled as the
 * point sun it tends to: the image is continuous in angular_radius down to 0. At this radius
 * 1 - cos is 5e-11, resolved by doubles to a relative 2e-6. docs/scene-format.md. */
#define LIGHT_SUN_POINT_RADIUS 1e-5

typedef enum light_kind {
    LIGHT_DISTANT,
    LIGHT_POINT,
    LIGHT_SPOT,
    LIGHT_SPHERE,
    LIGHT_DISK
} light_kind;

#define LIGHT_PROFILE_MAX 256

typedef struct light {
    light_kind kind;
    vec3 direction;        /* distant: propagation direction; spot: axis; disk: normal (unit) */
    vec3 position;         /* point, spot, sphere, disk: centre */
    color L;               /* E (distant), I (point, spot), radiance (sphere, disk, sun disk) */
    double radius;         /* sphere, disk: world units */
    double angular_radius; /* distant: radians; 0 = a delta direction (also any radius below
                              LIGHT_SUN_POINT_RADIUS, set so by light_init) */
    double cos_inner, cos_outer; /* spot cone without a profile */
    int profile_n;         /* spot: number of (angle, factor) pairs, 0 = use the cone */
    double profile_angle[LIGHT_PROFILE_MAX]; /* degrees, increasing from 0 */
    double profile_value[LIGHT_PROFILE_MAX]; /* factor >= 0 */
    /* derived by light_init */
    double cos_max;        /* distant with a disk: cos(angular_radius) */
    frame f;               /* disk: frame around the normal; spot: around the axis */
} light;

/* Fills derived fields (distant radiance from irradiance, frames). */
void light_init(light *l);
/* True for lights that a ray can hit: sphere, disk, and the sun disk. */
bool light_is_area(const light *l);

/* A direct-illumination sample at p. */
typedef struct light_sample {
    vec3 wi;     /* unit direction from p towards the light */
    double dist; /* distance to the sampled point; INFINITY for distant lights */
    color Li;    /* delta lights: irradiance at p normal to wi; area lights: radiance */
    double pdf;  /* area lights: solid-angle pdf of wi; delta lights: 1 */
    bool delta;
} light_sample;

/* Samples the light as seen from p. False when it sends nothing towards p. */
bool light_sample_at(const light *l, vec3 p, double u1, double u2, light_sample *ls);
/* For an area light: does the ray (p, wi) hit it? If so, *dist, the radiance *Le leaving it
 * towards p, and the solid-angle pdf that light_sample_at would give wi are returned. */
bool light_hit(const light *l, vec3 p, vec3 wi, double *dist, color *Le, double *pdf);

#endif
