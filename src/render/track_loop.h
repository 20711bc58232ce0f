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
 * number small is checked at commit (medium_check_range, docs/scene-format.md#limits). */
static inline TRACK_INLINE bool TRACK_NAME(const brume_scene *s, const int n, uint32_t absent, ray r,
                                                                     double tmax, rng *g, bool residual, track_fn fn,
                                                                     void *user, double *tau_c_end)
{
    track_stream st[TRACK_NMAX];
    for (int m = 0; m < n; m++) {
        if ((absent >> m & 1u) || !medium_majorant_begin(&s->media[m], r, tmax, &st[m].it)) {
            st[m].live = false;
            st[m].it.cells = 0;
            continue;
        }
        st[m].it.by_ctl = residual;
        st[m].live = majorant_next(&st[m].it, &st[m].seg);
        /* a flight gathers emission at its collisions: a medium emitting per unit length
         * is walked at its own rate (medium.h); shadow rays need only sigma_t's */
        st[m].sigma_t_max = residual ? s->media[m].sigma_t_max : s->media[m].sigma_flight;
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
        bool any = track_streams_at(st, n, t, &sigma_maj, &sigma_c, &sigma_ctl, &t_next);
        if (!any || t >= tmax) {
            if (tau_c_end)
                *tau_c_end = e.tau_c;
            track_count_cells(st, n);
            return true;
        }
        t_next = dda_min(t_next, tmax);
        const double sigma_n = track_rate(residual, sigma_maj, &sigma_c, sigma_ctl);
        e.sigma_maj = sigma_maj;
        e.sigma_c = sigma_c;
        e.sigma_r = sigma_n;
        const double tau_c0 = e.tau_c;
        /* tau: optical depth (against the majorant) still to cover before the next
         * tentative collision; one exponential per collision, carried across segments. */
        if (sigma_n > 0.0) {
            if (tau < 0.0)
                tau = sample_exponential(rng_at(g, tau_dim), 1.0);
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
                if (watch_collision() || !fn(&e, user)) { /* the sample's bound or a stop (watch.h) */
                    track_count_cells(st, n);
                    return false;
                }
                tau = sample_exponential(rng_next(g), 1.0);
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
