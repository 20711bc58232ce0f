/* track_body.h - the tracking loop's types and helpers (render/track.h) over one real type
 * (core/real_names.h): in double (track_event, medium_sample, track_rate ...) for the CPU's
 * estimator over a brume_scene, and in float (track_eventf ... : render/track_float.h) for
 * the GPU's single-precision stages over a float view of a scene's one medium. One body,
 * so both are the same estimator. TRACK_MAX_MEDIA bounds the media a medium_sample holds. */
#include "core/real_names.h"

/* A tentative collision at ray parameter t [world units], on a piece of the ray where
 * sigma_maj >= sigma_t(x) [1 / world unit].
 * - Flights: sigma_c is the control extinction, sum over media of rho_min sigma_t_min (0 for
 *   media with an albedo field, whose sigma_t varies by more than rho), a lower bound of
 *   every channel's sigma_t there; collisions come at the rate sigma_maj.
 * - Residual walks (shadow rays): sigma_c is the control, sum over media of rho_ctl
 *   sigma_t_min (the cells' means), and collisions come at the rate sigma_r, the largest
 *   |sigma_t - sigma_c| the bounds allow, so the residual's ratio 1 - (sigma_t - sigma_c) /
 *   sigma_r lies in [0, 2]; tau_c is the control optical depth from 0 to t (0 otherwise). */
typedef struct RN(track_event) {
    R t, sigma_maj, sigma_c, sigma_r, tau_c;
} RN(track_event);

/* Called at each tentative collision. Return false to stop tracking. */
typedef bool (*RN(track_fn))(const RN(track_event) *e, void *user);

/* Optical coefficients at p summed over the media [1 / world unit]. */
typedef struct RN(medium_sample) {
    RN(color) sigma_a, sigma_s;
    RN(color) emission;     /* sum of the emitted radiance per unit length [radiance / world unit] */
    int n;                  /* media with rho > 0 at p */
    int index[TRACK_MAX_MEDIA];
    R weight[TRACK_MAX_MEDIA]; /* avg sigma_s of each, for choosing a phase function */
} RN(medium_sample);

typedef struct RN(track_stream) {
    RN(majorant_iter) it;
    RN(majorant_seg) seg;
    bool live;
    R sigma_t_max;
    R sigma_t_min; /* the medium's: the controls' scale */
} RN(track_stream);

/* Majorant and control on [t, *t_next): the sums over the media whose current segment covers
 * t (the streams moved on to the segment at t), *t_next where the first of them changes;
 * false when no medium is left. */
static inline __attribute__((always_inline)) bool RN(track_streams_at)(RN(track_stream) *st, const int n, R t,
                                                                       R *sigma_maj, R *sigma_c, R *sigma_ctl,
                                                                       R *t_next)
{
    bool any = false;
    for (int m = 0; m < n; m++) {
        while (st[m].live && st[m].seg.t1 <= t)
            st[m].live = RN(majorant_next)(&st[m].it, &st[m].seg);
        if (!st[m].live)
            continue;
        any = true;
        if (st[m].seg.t0 > t) {
            *t_next = RN(dda_min)(*t_next, st[m].seg.t0);
        } else {
            *sigma_maj += st[m].seg.rho_maj * st[m].sigma_t_max;
            *sigma_c += st[m].seg.rho_min * st[m].sigma_t_min;
            *sigma_ctl += st[m].seg.rho_ctl * st[m].sigma_t_min;
            *t_next = RN(dda_min)(*t_next, st[m].seg.t1);
        }
    }
    return any;
}

/* The rate of tentative collisions on a segment of majorant sigma_maj and controls *sigma_c,
 * sigma_ctl: sigma_maj, or for residual walks, which take the cells' means as their control
 * (then *sigma_c), the bound on |sigma_t - sigma_ctl|, which lies in
 * [sigma_c - sigma_ctl, sigma_maj - sigma_ctl]. */
static inline __attribute__((always_inline)) R RN(track_rate)(bool residual, R sigma_maj, R *sigma_c, R sigma_ctl)
{
    *sigma_c = RN(dda_min)(*sigma_c, sigma_maj);
    R sigma_n = sigma_maj;
    if (residual) {
        sigma_ctl = RN(dda_max)(*sigma_c, RN(dda_min)(sigma_ctl, sigma_maj));
        sigma_n = RN(dda_max)(sigma_maj - sigma_ctl, sigma_ctl - *sigma_c);
        *sigma_c = sigma_ctl;
    }
    return sigma_n;
}

/* --stats: the cells the walk's iterators crossed, added once per walk */
static inline void RN(track_count_cells)(const RN(track_stream) *st, int n)
{
    if (!stats_tls)
        return;
    for (int m = 0; m < n; m++)
        stats_tls->majorant_cells += st[m].it.cells;
}

/* An optical depth of unit rate from a uniform u (sample_exponential(u, 1): 1 - u is exact
 * for u >= 1/2, and log is accurate enough for a sample) */
static inline __attribute__((always_inline)) R RN(track_exponential)(R u) { return -R_LOG(RC(1.0) - u); }

#include "core/real_names_end.h"
