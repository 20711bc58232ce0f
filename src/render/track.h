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
#include "core/sampling.h"
#include "core/stats.h"
#include "render/watch.h"
#include "scene/scene.h"

/* track_event, track_fn (the callback at each tentative collision), medium_sample (the
 * media's coefficients at a point) and the loop's helpers, written once over the real type
 * (render/track_body.h): here in double; render/track_float.h instantiates them in float. */
#define REAL_F 0
#define TRACK_MAX_MEDIA SCENE_MAX_MEDIA
#include "render/track_body.h"
#undef TRACK_MAX_MEDIA
#undef REAL_F

/* Tracks r (unit direction) over [0, tmax] at the ray's time r.time (moving media are
 * taken where they are at that instant), through the media not in `absent` (bit m set:
 * s->media[m], a bounded medium the ray is not in, is left out of the walk and its
 * majorant; 0: every medium). Tentative collisions come at the rate sigma_maj,
 * or with `residual` at the rate sigma_maj - sigma_c (residual ratio tracking, Novak et al.
 * 2014: the control part is then accounted for analytically by the caller through tau_c;
 * *tau_c_end, when not NULL, receives the control optical depth of the whole walk).
 * Returns true when the walk passed tmax (or left every medium) without the callback
 * stopping it. */
static inline bool track_collisions(const brume_scene *s, uint32_t absent, ray r, double tmax, rng *g, bool residual,
                                    track_fn fn, void *user, double *tau_c_end);

/* At time `time` (seconds): moving media are evaluated where they are then. The media in
 * `absent` (as track_collisions') are left out. */
void media_at(const brume_scene *s, uint32_t absent, vec3 p, double time, medium_sample *ms);
/* The phase function of a medium chosen among those at p in proportion to scattering. */
const phase *media_choose_phase(const brume_scene *s, const medium_sample *ms, double u);

/* Russian roulette on a ratio-tracking product: once max Tr < 0.1 the walk goes on with
 * probability 10 max Tr and Tr is divided by it (unbiased). false = the walk ends (Tr is
 * then 0). */
bool track_roulette(color *Tr, rng *g);

/* Residual ratio-tracking estimate of transmittance along r over [0, tmax] (unbiased, per
 * channel): exp(-tau_c) times the ratio-tracking product of the residual
 * (docs/path-tracer.md, "Control density"). */
color track_transmittance(const brume_scene *s, uint32_t absent, ray r, double tmax, rng *g);

/* ---- the tracking loop, inline: each caller's callback is inlined into its own copy ---- */

#define REAL_F 0
#define TRACK_SCENE brume_scene
#define TRACK_NAME track_collisions_1
#define TRACK_NMAX 1
#define TRACK_INLINE __attribute__((always_inline))
#include "render/track_loop.h"
#define TRACK_NAME track_collisions_n
#define TRACK_NMAX SCENE_MAX_MEDIA
#if defined(__CUDA_ARCH__) /* a GPU thread's walk through one medium keeps its one stream in registers */
#define TRACK_INLINE __attribute__((noinline))
#else
#define TRACK_INLINE __attribute__((always_inline))
#endif
#include "render/track_loop.h"
#undef TRACK_SCENE
#undef REAL_F

/* One medium is the common case: with n a constant the loops over media vanish, and one
 * stream is kept. */
static inline __attribute__((always_inline)) bool track_collisions(const brume_scene *s, uint32_t absent, ray r,
                                                                   double tmax, rng *g, bool residual, track_fn fn,
                                                                   void *user, double *tau_c_end)
{
    if (s->nmedia == 1)
        return track_collisions_1(s, 1, absent, r, tmax, g, residual, fn, user, tau_c_end);
    return track_collisions_n(s, s->nmedia, absent, r, tmax, g, residual, fn, user, tau_c_end);
}

#endif
