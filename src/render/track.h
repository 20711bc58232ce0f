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

/* A tentative collision at ray parameter t [world units], on a piece of the ray where
 * sigma_maj >= sigma_t(x) [1 / world unit].
 * - Flights: sigma_c is the control extinction, sum over media of rho_min sigma_t_min (0 for
 *   media with an albedo field, whose sigma_t varies by more than rho), a lower bound of
 *   every channel's sigma_t there; collisions come at the rate sigma_maj.
 * - Residual walks (shadow rays): sigma_c is the control, sum over media of rho_ctl
 *   sigma_t_min (the cells' means), and collisions come at the rate sigma_r, the largest
 *   |sigma_t - sigma_c| the bounds allow, so the residual's ratio 1 - (sigma_t - sigma_c) /
 *   sigma_r lies in [0, 2]; tau_c is the control optical depth from 0 to t (0 otherwise). */
typedef struct track_event {
    double t, sigma_maj, sigma_c, sigma_r, tau_c;
} track_event;

/* Called at each tentative collision. Return false to stop tracking. */
typedef bool (*track_fn)(const track_event *e, void *user);

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

/* Optical coefficients at p summed over the media [1 / world unit]. */
typedef struct medium_sample {
    color sigma_a, sigma_s;
    color emission;         /* sum of the emitted radiance per unit length [radiance / world unit] */
    int n;                  /* media with rho > 0 at p */
    int index[SCENE_MAX_MEDIA];
    double weight[SCENE_MAX_MEDIA]; /* avg sigma_s of each, for choosing a phase function */
} medium_sample;

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

typedef struct track_stream {
    majorant_iter it;
    majorant_seg seg;
    bool live;
    double sigma_t_max;
    double sigma_t_min; /* the medium's: the controls' scale */
} track_stream;

/* Majorant and control on [t, *t_next): the sums over the media whose current segment covers
 * t (the streams moved on to the segment at t), *t_next where the first of them changes;
 * false when no medium is left. */
static inline __attribute__((always_inline)) bool track_streams_at(track_stream *st, const int n, double t,
                                                                   double *sigma_maj, double *sigma_c,
                                                                   double *sigma_ctl, double *t_next)
{
    bool any = false;
    for (int m = 0; m < n; m++) {
        while (st[m].live && st[m].seg.t1 <= t)
            st[m].live = majorant_next(&st[m].it, &st[m].seg);
        if (!st[m].live)
            continue;
        any = true;
        if (st[m].seg.t0 > t) {
            *t_next = dda_min(*t_next, st[m].seg.t0);
        } else {
            *sigma_maj += st[m].seg.rho_maj * st[m].sigma_t_max;
            *sigma_c += st[m].seg.rho_min * st[m].sigma_t_min;
            *sigma_ctl += st[m].seg.rho_ctl * st[m].sigma_t_min;
            *t_next = dda_min(*t_next, st[m].seg.t1);
        }
    }
    return any;
}

/* The rate of tentative collisions on a segment of majorant sigma_maj and controls *sigma_c,
 * sigma_ctl: sigma_maj, or for residual walks, which take the cells' means as their control
 * (then *sigma_c), the bound on |sigma_t - sigma_ctl|, which lies in
 * [sigma_c - sigma_ctl, sigma_maj - sigma_ctl]. */
static inline __attribute__((always_inline)) double track_rate(bool residual, double sigma_maj, double *sigma_c,
                                                               double sigma_ctl)
{
    *sigma_c = dda_min(*sigma_c, sigma_maj);
    double sigma_n = sigma_maj;
    if (residual) {
        sigma_ctl = dda_max(*sigma_c, dda_min(sigma_ctl, sigma_maj));
        sigma_n = dda_max(sigma_maj - sigma_ctl, sigma_ctl - *sigma_c);
        *sigma_c = sigma_ctl;
    }
    return sigma_n;
}

/* --stats: the cells the walk's iterators crossed, added once per walk */
static inline void track_count_cells(const track_stream *st, int n)
{
    if (!stats_tls)
        return;
    for (int m = 0; m < n; m++)
        stats_tls->majorant_cells += st[m].it.cells;
}

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
