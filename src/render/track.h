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
#include "render/scene.h"

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
 * taken where they are at that instant). Tentative collisions come at the rate sigma_maj,
 * or with `residual` at the rate sigma_maj - sigma_c (residual ratio tracking, Novak et al.
 * 2014: the control part is then accounted for analytically by the caller through tau_c;
 * *tau_c_end, when not NULL, receives the control optical depth of the whole walk).
 * Returns true when the walk passed tmax (or left every medium) without the callback
 * stopping it. */
static inline bool track_collisions(const brume_scene *s, ray r, double tmax, rng *g, bool residual, track_fn fn,
                                    void *user, double *tau_c_end);

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

/* ---- the tracking loop, inline: each caller's callback is inlined into its own copy ---- */

typedef struct track_stream {
    majorant_iter it;
    majorant_seg seg;
    bool live;
    double sigma_t_max;
    double sigma_t_min; /* the medium's: the controls' scale */
} track_stream;

static inline __attribute__((always_inline)) bool track_collisions_n(const brume_scene *s, const int n, ray r,
                                                                     double tmax, rng *g, bool residual, track_fn fn,
                                                                     void *user, double *tau_c_end)
{
    track_stream st[SCENE_MAX_MEDIA];
    for (int m = 0; m < n; m++) {
        /* A moving medium: the ray in the field's frame at the ray's instant. An affine map
         * keeps the ray parameter t, so segments need no conversion back. */
        ray rm = r;
        if (s->media[m].motion) {
            affine3 to_world = motion_at(s->media[m].motion, r.time), to_local;
            if (!affine3_invert(&to_world, &to_local)) {
                st[m].live = false;
                continue;
            }
            rm.o = affine3_apply(&to_local, r.o);
            rm.d = affine3_apply_dir(&to_local, r.d);
        }
        density_majorant_begin(s->media[m].rho, rm, 0.0, tmax, &st[m].it);
        st[m].it.by_ctl = residual;
        st[m].live = majorant_next(&st[m].it, &st[m].seg);
        st[m].sigma_t_max = s->media[m].sigma_t_max;
        st[m].sigma_t_min = s->media[m].sigma_t_min;
    }
    track_event e = {0.0, 0.0, 0.0, 0.0, 0.0};
    /* the first exponential's number is taken now and made at the first segment with
     * tentative collisions: a ray that meets no medium never computes it */
    const uint64_t tau_dim = g->counter++;
    double t = 0.0, tau = -1.0;
    if (tau_c_end)
        *tau_c_end = 0.0;
    for (;;) {
        /* Majorant and control on [t, t_next): media whose current segment covers t. */
        double sigma_maj = 0.0, sigma_c = 0.0, sigma_ctl = 0.0, t_next = INFINITY;
        bool any = false;
        for (int m = 0; m < n; m++) {
            while (st[m].live && st[m].seg.t1 <= t)
                st[m].live = majorant_next(&st[m].it, &st[m].seg);
            if (!st[m].live)
                continue;
            any = true;
            if (st[m].seg.t0 > t) {
                t_next = dda_min(t_next, st[m].seg.t0);
            } else {
                sigma_maj += st[m].seg.rho_maj * st[m].sigma_t_max;
                sigma_c += st[m].seg.rho_min * st[m].sigma_t_min;
                sigma_ctl += st[m].seg.rho_ctl * st[m].sigma_t_min;
                t_next = dda_min(t_next, st[m].seg.t1);
            }
        }
        if (!any || t >= tmax) {
            if (tau_c_end)
                *tau_c_end = e.tau_c;
            return true;
        }
        t_next = dda_min(t_next, tmax);
        sigma_c = dda_min(sigma_c, sigma_maj);
        /* the rate of tentative collisions: residual walks take the cells' means as their
         * control, sigma_t - sigma_ctl then lies in [sigma_c - sigma_ctl, sigma_maj - sigma_ctl] */
        double sigma_n = sigma_maj;
        if (residual) {
            sigma_ctl = dda_max(sigma_c, dda_min(sigma_ctl, sigma_maj));
            sigma_n = dda_max(sigma_maj - sigma_ctl, sigma_ctl - sigma_c);
            sigma_c = sigma_ctl;
        }
        e.sigma_maj = sigma_maj;
        e.sigma_c = sigma_c;
        e.sigma_r = sigma_n;
        const double tau_c0 = e.tau_c;
        /* tau: optical depth (against the majorant) still to cover before the next
         * tentative collision; one exponential per collision, carried across segments. */
        if (sigma_n > 0.0) {
            if (tau < 0.0)
                tau = sample_exponential(rng_at(g, tau_dim), 1.0);
            /* Distances are measured from the segment's start: u grows from 0, so a step of
             * 1e-18 still advances it where t + 1e-18 == t (a dense medium far from the
             * origin), and it strictly increases (a step below its resolution moves it by
             * one ulp), so the walk reaches the segment's end or stops in a finite number
             * of steps. The range that keeps that number small is checked at commit
             * (medium_check_range, docs/scene-format.md#limits). */
            const double t0 = t, len = t_next - t, inv_n = 1.0 / sigma_n;
            double u = 0.0;
            for (;;) {
                double du = tau * inv_n;
                if (!(u + du < len)) {
                    tau = dda_max(0.0, tau - sigma_n * (len - u));
                    break;
                }
                double u_new = u + du;
                u = u_new > u ? u_new : nextafter(u, INFINITY);
                e.t = t0 + u;
                if (residual)
                    e.tau_c = tau_c0 + sigma_c * u;
                if (!fn(&e, user))
                    return false;
                tau = sample_exponential(rng_next(g), 1.0);
            }
        }
        if (residual)
            e.tau_c = tau_c0 + sigma_c * (t_next - t);
        t = t_next;
    }
}

/* One medium is the common case: with n a constant the loops over media vanish. */
static inline __attribute__((always_inline)) bool track_collisions(const brume_scene *s, ray r, double tmax, rng *g,
                                                                   bool residual, track_fn fn, void *user,
                                                                   double *tau_c_end)
{
    if (s->nmedia == 1)
        return track_collisions_n(s, 1, r, tmax, g, residual, fn, user, tau_c_end);
    return track_collisions_n(s, s->nmedia, r, tmax, g, residual, fn, user, tau_c_end);
}

#endif
