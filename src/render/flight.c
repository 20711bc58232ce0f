/* flight.c - one free flight through the media (docs/path-tracer.md, "Free flights").
 *
 * Tentative collisions are drawn against the scalar majorant sigma_maj (track.h) and
 * walked with a ratio-tracking transmittance Tr (per channel). At each, emission
 * beta Tr sigma_a Le / sigma_maj is added, and the collision is offered to a one-element
 * reservoir with weight avg(beta Tr sigma_s) / sigma_maj (the history-aware spectral choice
 * of Kutz et al. 2017); the kept one is where the path scatters, and beta Tr at the
 * flight's end weighs what lies past it. The path tracer (path.c) and brume slab (slab.c)
 * run on it. */
#include "render/flight.h"

#include "core/stats.h"

/* Offers the collision at t, with the media f->cur and the scattering weight w, to the
 * flight's one-element reservoir. */
static void flight_offer(flight *f, color w, double t)
{
    double a = col_avg(w);
    if (!(a > 0.0))
        return;
    if (!(f->A > 0.0)) /* the first candidate: the reservoir's number, at its dimension */
        f->u = rng_at(f->ug, f->udim);
    f->A += a;
    /* the i-th candidate replaces the kept one with probability a / A, decided by the one
     * uniform u of the flight, rescaled to a fresh uniform after each decision */
    double pr = a / f->A;
    if (f->u < pr) {
        f->u /= pr;
        f->beta_s = col_scale(w, 1.0 / a);
        f->t = f->t0 + t;
        f->absent_s = f->absent;
        /* what media_choose_phase reads: the media there and their weights */
        f->ms.n = f->cur.n;
        for (int i = 0; i < f->cur.n; i++) {
            f->ms.index[i] = f->cur.index[i];
            f->ms.weight[i] = f->cur.weight[i];
        }
    } else {
        f->u = (f->u - pr) / (1.0 - pr);
    }
    if (!(f->u < 1.0)) /* rounding */
        f->u = 0x1.fffffffffffffp-1;
}

/* A tentative collision of a flight. Without a control density (sigma_c = 0), every
 * tentative collision looks the media up and is weighed by ratio tracking. With one (a
 * single medium whose sigma_t is gray: s->flight_control), the collision is a real collision of
 * the control medium sigma_c with probability sigma_c / sigma_maj, which needs no lookup and
 * ends the walk (its Tr factor is 0), or else a collision of the residual
 * sigma_t(x) - sigma_c against sigma_maj - sigma_c (docs/path-tracer.md, "Control density").
 * Both keep every weight's expectation that of plain ratio tracking. */
static bool flight_step(const track_event *e, void *user)
{
    flight *f = (flight *)user;
    if (stats_tls)
        stats_tls->path_tentative++;
    color beta_Tr = col_mul(f->beta, f->Tr);
    double sigma_c = f->s->flight_control ? e->sigma_c : 0.0;
    if (sigma_c > 0.0 && rng_next(f->g) * e->sigma_maj < sigma_c) {
        /* the control medium, rho_c = sigma_c / sigma_t: beta Tr sigma_x rho_c / (sigma_maj p_c) */
        const medium *md = &f->s->media[0];
        double inv_t = 1.0 / md->sigma_t_max;
        if (!col_is_black(md->Le))
            f->L = col_add(f->L, col_scale(col_mul(beta_Tr, col_mul(md->sigma_a, md->Le)), inv_t));
        f->cur.n = 1;
        f->cur.index[0] = 0;
        f->cur.weight[0] = 1.0;
        flight_offer(f, col_scale(col_mul(beta_Tr, md->sigma_s), inv_t), e->t);
        f->Tr = col(0.0);
        return false;
    }
    media_at(f->s, f->absent, ray_at(f->r, e->t), f->r.time, &f->cur);
    medium_sample *ms = &f->cur;
    if (sigma_c > 0.0) { /* the residual: rho - rho_c */
        const medium *md = &f->s->media[0];
        double rho_c = sigma_c / md->sigma_t_max;
        ms->sigma_a = col_sub(ms->sigma_a, col_scale(md->sigma_a, rho_c));
        ms->sigma_s = col_sub(ms->sigma_s, col_scale(md->sigma_s, rho_c));
        ms->emission = col_sub(ms->emission, col_scale(col_mul(md->sigma_a, md->Le), rho_c));
    }
    double inv_maj = 1.0 / (e->sigma_maj - sigma_c);
    if (!col_is_black(ms->emission))
        f->L = col_add(f->L, col_scale(col_mul(beta_Tr, ms->emission), inv_maj));
    if (col_max(f->Tr) < f->tail_Tr && f->s->flight_control) {
        /* the delta tail: a real collision with probability p, weighed 1 / p, ends the flight;
         * a null one leaves Tr: the expectations of the ratio step's offer and Tr factor */
        double p = col_avg(col_add(ms->sigma_a, ms->sigma_s)) * inv_maj;
        if (rng_next(f->g) < p) {
            flight_offer(f, col_scale(col_mul(beta_Tr, ms->sigma_s), inv_maj / p), e->t);
            f->Tr = col(0.0);
            return false;
        }
        return true;
    }
    flight_offer(f, col_scale(col_mul(beta_Tr, ms->sigma_s), inv_maj), e->t);
    for (int c = 0; c < BRUME_NSAMPLES; c++)
        f->Tr.c[c] *= 1.0 - (ms->sigma_a.c[c] + ms->sigma_s.c[c]) * inv_maj;
    return track_roulette(&f->Tr, f->g);
}

void flight_begin(flight *f, rng *ug)
{
    f->ug = ug;
    f->udim = ug->counter++;
    f->Tr = col(1.0);
    f->A = 0.0;
}

void flight_track(flight *f, ray r, double t0, double tmax)
{
    f->r = r;
    f->t0 = t0;
    if (!col_is_black(f->Tr))
        track_collisions(f->s, f->absent, r, tmax, f->g, false, flight_step, f, NULL);
}

bool flight_end(flight *f)
{
    if (!(f->A > 0.0))
        return false;
    f->beta_s = col_scale(f->beta_s, f->A);
    return true;
}

bool flight_run(flight *f, ray r, double tmax, rng *ug)
{
    flight_begin(f, ug);
    flight_track(f, r, 0.0, tmax);
    return flight_end(f);
}
