/* path.h - the path estimator (render/path.c; its per-scene state: path_state.c), also run
 * with its cap on scattering events by other estimators (brume slab): render/integrator.h
 * dispatches to it for the path and single methods. */
#ifndef BRUME_RENDER_PATH_H
#define BRUME_RENDER_PATH_H

#include "core/rng.h"
#include "render/flight.h"
#include "scene/scene.h"

/* The path estimator with an explicit cap on scattering events (>= 1; a bounce off a
 * surface counts as one), also telling whether the camera ray's first hit is a surface
 * (hit_surface may be NULL) and, with Tr_cam, the transmittance along the whole camera ray
 * (integrator_Li). state is integrator_prepare's for INTEGRATOR_PATH or INTEGRATOR_SINGLE
 * (NULL: no sun-lobe sampling and no cull of camera rays that miss every medium). */
color path_Li_alpha(const brume_scene *s, const void *state, ray r, int max_depth, rng *g, bool *hit_surface,
                    color *Tr_cam);
/* The sun roulette's predicted transmittance (docs/path-tracer.md, "Sun rays deep in a
 * cloud") towards the scene's sun-th delta sun (`distant` without angular_radius, in the
 * order of the lights) from the world point p, for tests: 1 where nothing is predicted
 * (outside the media's box; no prediction built). state as path_Li_alpha's. */
double path_sun_transmittance_hat(const void *state, int sun, vec3 p);
/* Transmittance from p along unit wi over (0, dist) at `time` (seconds), from a point
 * outside the bounded media `absent` (track_collisions'; 0: in every medium): 0 when a
 * surface blocks the segment, else that of the media (ratio tracking), crossing the
 * interfaces on the way (docs/surfaces.md, "How surfaces meet media"). Moving things are taken
 * where they are at that instant, so every estimator that passes the path's time gets
 * motion blur (docs/animation.md). */
color scene_transmittance(const brume_scene *s, uint32_t absent, vec3 p, vec3 wi, double dist, double time,
                          rng *g);

/* The bounded media absent where the camera ray r starts (bit m: s->media[m] is not there;
 * 0 when the scene has none): those the crossings of r's line, taken from infinity, where no
 * bounded medium is, back to r.o, leave it outside of, less camera.medium
 * (docs/surfaces.md, "How surfaces meet media"). */
uint32_t path_camera_absent(const brume_scene *s, ray r);

/* Copies path and single's prepared state (integrator_prepare's, may be NULL) into a
 * (core/arena.h) for the GPU; returns the copy's offset (ARENA_NULL for NULL or on failure). */
struct dev_arena;
size_t path_state_device_put(const void *state, struct dev_arena *a);
/* Russian roulette after `depth` scattering events: false = the path ends; otherwise beta
 * may have been divided by its survival probability. */
bool path_roulette(color *beta, int depth, rng *g);

#endif
