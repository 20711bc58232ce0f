/* track_loop.h - the body of the tracking loop (render/track.h), included once per bound on
 * the number of media: TRACK_NAME is the function's name, TRACK_NMAX the streams it keeps.
 * One body, so every instance is the same estimator; a small bound keeps the walk's state
 * (a majorant iterator per medium) small, which a GPU thread holds in local memory. Its
 * helpers (track.h) are always inlined, so that the compiler keeps the walk's state in
 * registers across the majorant segments and the collisions (docs/performance.md).
 *
 * Along a segment, distances are measured from the segment's start: u grows from 0, so a
 * step of 1e-18 still advances it where t + 1e-18 == t (a dense medium far from the origin),
 * and it strictly increases (a step below its resolution moves it by one ulp), so the walk
 * reaches the segment's end or stops in a finite number of steps. The range that keeps that
 * number small is checked at commit (medium_check_range, docs/scene-format.md#limits).
 *
 * Written over the real type (core/real_names.h, REAL_F) and the scene TRACK_SCENE (its
 * nmedia and media[m]'s sigma_t_max, sigma_flight, sigma_t_min, and RN(medium_majorant_begin)
 * over them): in double over a brume_scene (render/track.h), in float over the float view of
 * one dense medium (render/track_float.h). */
#include "core/real_names.h"

static inline TRACK_INLINE bool TRACK_NAME(const TRACK_SCENE *s, const int n, uint32_t absent, RN(ray) r,
                                                                     R tmax, rng *g, bool residual, RN(track_fn) fn,
                                                                     void *user, R *tau_c_end)
{
    RN(track_stream) st[TRACK_NMAX];
    for (int m = 0; m < n; m++) {
        if ((absent >> m & 1u) || !RN(medium_majorant_begin)(&s->media[m], r, tmax, &st[m].it)) {
            st[m].live = false;
            st[m].it.cells = 0;
            continue;
        }
        st[m].it.by_ctl = residual;
        st[m].live = RN(majorant_next)(&st[m].it, &st[m].seg);
        /* a flight gathers emission at its collisions: a medium emitting per unit length
         * is walked at its own rate (medium.h); shadow rays need only sigma_t's */
        st[m].sigma_t_max = residual ? s->media[m].sigma_t_max : s->media[m].sigma_flight;
        st[m].sigma_t_min = s->media[m].sigma_t_min;
    }
    RN(track_event) e = {RC(0.0), RC(0.0), RC(0.0), RC(0.0), RC(0.0)};
    /* the first exponential's number is taken now and made at the first segment with
     * tentative collisions: a ray that meets no medium never computes it */
    const uint64_t tau_dim = g->counter++;
    R t = RC(0.0), tau = RC(-1.0);
    if (tau_c_end)
        *tau_c_end = RC(0.0);
    for (;;) {
        /* Majorant and control on [t, t_next): media whose current segment covers t. */
        R sigma_maj = RC(0.0), sigma_c = RC(0.0), sigma_ctl = RC(0.0), t_next = R_INF;
        bool any = RN(track_streams_at)(st, n, t, &sigma_maj, &sigma_c, &sigma_ctl, &t_next);
        if (!any || t >= tmax) {
            if (tau_c_end)
                *tau_c_end = e.tau_c;
            RN(track_count_cells)(st, n);
            return true;
        }
        t_next = RN(dda_min)(t_next, tmax);
        const R sigma_n = RN(track_rate)(residual, sigma_maj, &sigma_c, sigma_ctl);
        e.sigma_maj = sigma_maj;
        e.sigma_c = sigma_c;
        e.sigma_r = sigma_n;
        const R tau_c0 = e.tau_c;
        /* tau: optical depth (against the majorant) still to cover before the next
         * tentative collision; one exponential per collision, carried across segments. */
        if (sigma_n > RC(0.0)) {
            if (tau < RC(0.0))
                tau = RN(track_exponential)(RN(rng_at)(g, tau_dim));
            const R t0 = t, len = t_next - t, inv_n = RC(1.0) / sigma_n;
            R u = RC(0.0);
            for (;;) {
                R du = tau * inv_n;
                if (!(u + du < len)) {
                    tau = RN(dda_max)(RC(0.0), tau - sigma_n * (len - u));
                    break;
                }
                R u_new = u + du;
                u = u_new > u ? u_new : R_NEXTAFTER(u, R_INF);
                e.t = t0 + u;
                if (residual)
                    e.tau_c = tau_c0 + sigma_c * u;
                if (watch_collision() || !fn(&e, user)) { /* the sample's bound or a stop (watch.h) */
                    RN(track_count_cells)(st, n);
                    return false;
                }
                tau = RN(track_exponential)(RN(rng_next)(g));
            }
        }
        if (residual)
            e.tau_c = tau_c0 + sigma_c * (t_next - t);
        t = t_next;
    }
}

#undef TRACK_NAME
#undef TRACK_NMAX
#undef TRACK_INLINE
#include "core/real_names_end.h"
