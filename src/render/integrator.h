/* integrator.h - estimators of the radiance arriving along a camera ray.
 *   path    unbiased volumetric path tracing: null-collision free flights that keep
 *           one collision of every flight through a medium (flight_run),
 *           next-event estimation to every light and to the background with multiple
 *           importance sampling against phase sampling, ratio-tracked shadow rays,
 *           Russian roulette, emission
 *   single  the same estimator stopped after one scattering event: single scattering
 *           of every light and of the background
 *   blasi   Blasi, Le Saec and Schlick's two-pass method (render/blasi.h): a light pass
 *           in integrator_prepare, a voxel gather per camera ray
 * The path estimator's own entry points and building blocks are render/path.h's (and its
 * free flight render/flight.h's); this file dispatches by kind above them. */
#ifndef BRUME_RENDER_INTEGRATOR_H
#define BRUME_RENDER_INTEGRATOR_H

#include "core/rng.h"
#include "method/method.h"
#include "scene/scene.h"
#include "render/path.h"
#include "render/track.h"

/* Work an integrator does once per scene before any camera ray (Blasi's light pass, a
 * table of per-blob statistics, ...), kept in an opaque state that integrator_Li reads
 * from every thread. integrator_prepare sets *state (NULL when the method needs none) and
 * returns BRUME_OK, or fails with err_set(); integrator_finish releases the state.
 * brume_render keeps the state with the scene and reuses it for later renders of it,
 * including frames reached by brume_scene_set_camera_time: so prepare must depend on the
 * world (lights, media, surfaces, s->time) only, never on the camera (docs/animation.md). */
brume_status integrator_prepare(integrator_kind kind, const brume_scene *s, void **state);
void integrator_finish(integrator_kind kind, void *state);

/* Radiance along r (unit direction) for the given kind; *hit_surface tells whether the
 * ray's first hit is a solid surface (may be NULL). state is integrator_prepare's. With Tr
 * not NULL, also the transmittance along r over (0, infinity) as the method sees the media
 * (for the image's alpha; unused when *hit_surface): path and single take the camera ray's
 * own flight's ratio-tracked estimate (unbiased, and no second walk), blasi its voxels'
 * exact sum, stam its realized transparency. */
color integrator_Li(integrator_kind kind, const brume_scene *s, const void *state, ray r, rng *g,
                    bool *hit_surface, color *Tr);

/* What the first vertex of a camera ray is, for the image's extra layers (AOVs): found by
 * its own walk, so the estimators above are untouched. In media, the first real collision
 * of delta tracking (a tentative collision is real with probability avg(sigma_t) /
 * sigma_maj); else the first surface hit. */
typedef struct first_vertex {
    bool hit;      /* false: the ray met nothing (other fields 0) */
    double depth;  /* distance from the ray origin, world units */
    color albedo;  /* medium: sigma_s / sigma_t per channel; surface: diffuse albedo */
    vec3 normal;   /* surface: unit normal facing the ray; medium: 0 */
} first_vertex;
void integrator_first_vertex(const brume_scene *s, ray r, rng *g, first_vertex *v);

#endif
