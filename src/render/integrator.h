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
 * The free-flight and scattering steps are exposed (flight_run, path_roulette) so that
 * other estimators (brume slab) run on exactly the code the renderer runs. */
#ifndef BRUME_RENDER_INTEGRATOR_H
#define BRUME_RENDER_INTEGRATOR_H

#include "core/rng.h"
#include "method/method.h"
#include "scene/scene.h"
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
/* Transmittance from p along unit wi over (0, dist) at `time` (seconds): 0 when a surface
 * blocks the segment, else that of the media (ratio tracking). Moving things are taken
 * where they are at that instant, so every estimator that passes the path's time gets
 * motion blur (docs/animation.md). */
color scene_transmittance(const brume_scene *s, vec3 p, vec3 wi, double dist, double time, rng *g);

/* Copies path and single's prepared state (integrator_prepare's, may be NULL) into a
 * (core/arena.h) for the GPU; returns the copy's offset (ARENA_NULL for NULL or on failure). */
struct dev_arena;
size_t path_state_device_put(const void *state, struct dev_arena *a);

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

/* ---- building blocks ---------------------------------------------------------------- */

/* One free flight along r over [0, tmax] (docs/path-tracer.md, "Free flights"). The
 * flight walks every tentative collision against sigma_maj with a ratio-tracking
 * transmittance Tr, adds the emission term at each, and keeps one collision i among them
 * with probability a_i / A, where
 *   a_i = avg(beta Tr(t_i) sigma_s(t_i)) / sigma_maj   and   A = sum_i a_i
 * (a one-element reservoir): beta_s = A (beta Tr sigma_s)(t_i) / (sigma_maj a_i) is then
 * an unbiased weight for scattering there, and beta Tr(tmax) for what lies past tmax. Both
 * branches are estimated from one walk; a path never ends merely because it escaped. */
typedef struct flight {
    const brume_scene *s;
    ray r;
    rng *g;
    color beta;       /* in: path throughput before the flight */
    color L;          /* in/out: emission gathered along the flight, weighted by beta */
    color Tr;         /* out: ratio-tracked transmittance over [0, tmax] (0 once roulette stopped it) */
    double A;         /* out: sum of the collisions' scattering weights a_i (0: none) */
    color beta_s;     /* out: throughput of the scattering branch at the kept collision */
    double t;         /* out: where the kept collision is */
    medium_sample ms; /* out: the media there (n, index and weight, what media_choose_phase reads) */
    medium_sample cur; /* scratch: the media at the current collision */
    double tail_Tr;   /* in: once max Tr is below it, the flight's delta tail (flight_run); 0: none */
    double u;         /* scratch: the reservoir's uniform, rescaled after each choice */
    rng *ug;          /* scratch: the sequence and dimension u is drawn from, at the first */
    uint64_t udim;    /*          collision (a flight that meets none never computes it) */
} flight;

/* Where a flight's delta tail starts (f->tail_Tr) after the first scattering event: measured
 * in docs/performance.md, "The flight's delta tail". */
#define FLIGHT_TAIL_TR 0.6

/* Runs a flight; true when it kept a scattering collision (f->A > 0). f->beta, f->L and
 * f->tail_Tr carry in; f->Tr, f->A, f->beta_s, f->t, f->ms come out. In a medium whose
 * extinction is gray (s->flight_control), once the largest channel of Tr falls below
 * f->tail_Tr each tentative collision is real with probability p = sigma_t / sigma_maj (of
 * the residual), and then the flight's last, its weight divided by p, and otherwise leaves
 * Tr as it is: the delta tail (docs/path-tracer.md), unbiased as the ratio steps are. The
 * next number of ug (its dimension is taken now, the value computed only if the flight
 * meets a collision) makes the reservoir's choices: one number for the whole flight, so a
 * sampler can stratify where flights scatter. The tracking draws from f->g. */
bool flight_run(flight *f, ray r, double tmax, rng *ug);
/* Russian roulette after `depth` scattering events: false = the path ends; otherwise beta
 * may have been divided by its survival probability. */
bool path_roulette(color *beta, int depth, rng *g);

#endif
