/* track.h - tentative collisions along a ray through all media of a scene.
 *
 * The one generic tracking loop (pbrt-v4's SampleT_maj in C): the scene's media are
 * walked through their majorant segments, merged into one piecewise-constant scalar
 * majorant sigma_maj(t) = sum over media of rho_maj sigma_t_max [1 / world unit], and
 * tentative collisions are drawn with density sigma_maj exp(-int sigma_maj). The path
 * tracer's free flights and ratio-tracked shadow rays are callbacks; none of them knows
 * how a density is stored. */
#ifndef BRUME_RENDER_TRACK_H
#define BRUME_RENDER_TRACK_H

#include <stdbool.h>

#include "core/color.h"
#include "core/rng.h"
#include "render/scene.h"

/* A tentative collision at ray parameter t [world units]. sigma_maj >= sigma_t(x) >= sigma_c
 * on the piece of the ray around t [1 / world unit]: sigma_c is the control extinction,
 * sum over media of rho_min sigma_t_min (0 for media with an albedo field, whose sigma_t
 * varies by more than rho), a lower bound of every channel's sigma_t there. tau_c is the
 * control optical depth from 0 to t (residual walks only; 0 otherwise). */
typedef struct track_event {
    double t, sigma_maj, sigma_c, tau_c;
} track_event;

/* Called at each tentative collision. Return false to stop tracking. */
typedef bool (*track_fn)(const track_event *e, void *user);

/* Tracks r (unit direction) over [0, tmax] at the ray's time r.time (moving media are
 * taken where they are at that instant). Tentative collisions come at the rate sigma_maj,
 * or with `residual` at the rate sigma_maj - sigma_c (residual ratio tracking, Novak et al.
 * 2014: the control part is then accounted for analytically by the caller through tau_c;
 * *tau_c_end, when not NULL, receives the control optical depth of the whole walk).
 * Returns true when the walk passed tmax (or left every medium) without the callback
 * stopping it. */
bool track_collisions(const brume_scene *s, ray r, double tmax, rng *g, bool residual, track_fn fn, void *user,
                      double *tau_c_end);

/* Optical coefficients at p summed over the media [1 / world unit]. */
typedef struct medium_sample {
    color sigma_a, sigma_s;
    color emission;         /* sum of sigma_a rho Le [radiance / world unit] */
    int n;                  /* media with rho > 0 at p */
    int index[SCENE_MAX_MEDIA];
    double weight[SCENE_MAX_MEDIA]; /* avg sigma_s of each, for choosing a phase function */
} medium_sample;

/* At time `time` (seconds): moving media are evaluated where they are then. */
void media_at(const brume_scene *s, vec3 p, double time, medium_sample *ms);
/* The phase function of a medium chosen among those at p in proportion to scattering. */
const phase *media_choose_phase(const brume_scene *s, const medium_sample *ms, double u);

/* Russian roulette on a ratio-tracking product: once max Tr < 0.1 the walk goes on with
 * probability 10 max Tr and Tr is divided by it (unbiased). false = the walk ends (Tr is
 * then 0). */
bool track_roulette(color *Tr, rng *g);

/* Residual ratio-tracking estimate of transmittance along r over [0, tmax] (unbiased, per
 * channel): exp(-tau_c) times the ratio-tracking product of the residual
 * (docs/path-tracer.md, "Control density"). */
color track_transmittance(const brume_scene *s, ray r, double tmax, rng *g);

#endif
