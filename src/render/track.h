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

/* Called at each tentative collision at ray parameter t with the local scalar majorant.
 * Return false to stop tracking. */
typedef bool (*track_fn)(double t, double sigma_maj, void *user);

/* Tracks r (unit direction) over [0, tmax] at the ray's time r.time (moving media are
 * taken where they are at that instant). Returns true when the walk passed tmax (or
 * left every medium) without the callback stopping it. */
bool track_collisions(const brume_scene *s, ray r, double tmax, rng *g, track_fn fn, void *user);

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

/* Ratio-tracking estimate of transmittance along r over [0, tmax] (unbiased, per channel). */
color track_transmittance(const brume_scene *s, ray r, double tmax, rng *g);

#endif
