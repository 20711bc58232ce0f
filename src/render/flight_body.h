/* flight_body.h - the flight stage (render/flight.h: the free flight's ratio tracking, its
 * one-element reservoir, its delta tail and its control density), over one real type
 * (core/real_names.h), scene FLIGHT_SCENE and medium FLIGHT_MEDIUM with its RN(media_at) and
 * RN(track_collisions). FLIGHT_API is the functions' storage: flight.c defines the double
 * ones (FLIGHT_API empty), render/track_float.h the float ones (static inline) for the
 * GPU's single-precision stages. */
#include "core/real_names.h"

/* Offers the collision at t, with the media f->cur and the scattering weight w, to the
 * flight's one-element reservoir. */
static void RN(flight_offer)(RN(flight) *f, RN(color) w, R t)
{
    R a = RN(col_avg)(w);
    if (!(a > RC(0.0)))
        return;
    if (!(f->A > RC(0.0))) /* the first candidate: the reservoir's number, at its dimension */
        f->u = RN(rng_at)(f->ug, f->udim);
    f->A += a;
    /* the i-th candidate replaces the kept one with probability a / A, decided by the one
     * uniform u of the flight, rescaled to a fresh uniform after each decision */
    R pr = a / f->A;
    if (f->u < pr) {
        f->u /= pr;
        f->beta_s = RN(col_scale)(w, RC(1.0) / a);
        f->t = f->t0 + t;
        f->absent_s = f->absent;
        /* what media_choose_phase reads: the media there and their weights */
        f->ms.n = f->cur.n;
        if (sizeof f->ms.index == sizeof f->ms.index[0]) { /* one medium: constant indices keep
                                                                the flight in registers */
            f->ms.index[0] = f->cur.index[0];
            f->ms.weight[0] = f->cur.weight[0];
        } else {
            for (int i = 0; i < f->cur.n; i++) {
                f->ms.index[i] = f->cur.index[i];
                f->ms.weight[i] = f->cur.weight[i];
            }
        }
    } else {
        f->u = (f->u - pr) / (RC(1.0) - pr);
    }
    if (!(f->u < RC(1.0))) /* rounding */
        f->u = R_ONE_BELOW;
}

/* A tentative collision of a flight. Without a control density (sigma_c = 0), every
 * tentative collision looks the media up and is weighed by ratio tracking. With one (a
 * single medium whose sigma_t is gray: s->flight_control), the collision is a real collision of
 * the control medium sigma_c with probability sigma_c / sigma_maj, which needs no lookup and
 * ends the walk (its Tr factor is 0), or else a collision of the residual
 * sigma_t(x) - sigma_c against sigma_maj - sigma_c (docs/path-tracer.md, "Control density").
 * Both keep every weight's expectation that of plain ratio tracking. */
static bool RN(flight_step)(const RN(track_event) *e, void *user)
{
    RN(flight) *f = (RN(flight) *)user;
    if (stats_tls)
        stats_tls->path_tentative++;
    RN(color) beta_Tr = RN(col_mul)(f->beta, f->Tr);
    R sigma_c = f->s->flight_control ? e->sigma_c : RC(0.0);
    if (sigma_c > RC(0.0) && RN(rng_next)(f->g) * e->sigma_maj < sigma_c) {
        /* the control medium, rho_c = sigma_c / sigma_t: beta Tr sigma_x rho_c / (sigma_maj p_c) */
        const FLIGHT_MEDIUM *md = &f->s->media[0];
        R inv_t = RC(1.0) / md->sigma_t_max;
        if (!RN(col_is_black)(md->Le))
            f->L = RN(col_add)(f->L, RN(col_scale)(RN(col_mul)(beta_Tr, RN(col_mul)(md->sigma_a, md->Le)), inv_t));
        f->cur.n = 1;
        f->cur.index[0] = 0;
        f->cur.weight[0] = RC(1.0);
        RN(flight_offer)(f, RN(col_scale)(RN(col_mul)(beta_Tr, md->sigma_s), inv_t), e->t);
        f->Tr = RN(col)(RC(0.0));
        return false;
    }
    RN(media_at)(f->s, f->absent, RN(ray_at)(f->r, e->t), f->r.time, &f->cur);
    RN(medium_sample) *ms = &f->cur;
    if (sigma_c > RC(0.0)) { /* the residual: rho - rho_c */
        const FLIGHT_MEDIUM *md = &f->s->media[0];
        R rho_c = sigma_c / md->sigma_t_max;
        ms->sigma_a = RN(col_sub)(ms->sigma_a, RN(col_scale)(md->sigma_a, rho_c));
        ms->sigma_s = RN(col_sub)(ms->sigma_s, RN(col_scale)(md->sigma_s, rho_c));
        ms->emission = RN(col_sub)(ms->emission, RN(col_scale)(RN(col_mul)(md->sigma_a, md->Le), rho_c));
    }
    R inv_maj = RC(1.0) / (e->sigma_maj - sigma_c);
    if (!RN(col_is_black)(ms->emission))
        f->L = RN(col_add)(f->L, RN(col_scale)(RN(col_mul)(beta_Tr, ms->emission), inv_maj));
    if (RN(col_max)(f->Tr) < f->tail_Tr && f->s->flight_control) {
        /* the delta tail: a real collision with probability p, weighed 1 / p, ends the flight;
         * a null one leaves Tr: the expectations of the ratio step's offer and Tr factor */
        R p = RN(col_avg)(RN(col_add)(ms->sigma_a, ms->sigma_s)) * inv_maj;
        if (RN(rng_next)(f->g) < p) {
            RN(flight_offer)(f, RN(col_scale)(RN(col_mul)(beta_Tr, ms->sigma_s), inv_maj / p), e->t);
            f->Tr = RN(col)(RC(0.0));
            return false;
        }
        return true;
    }
    RN(flight_offer)(f, RN(col_scale)(RN(col_mul)(beta_Tr, ms->sigma_s), inv_maj), e->t);
    for (int c = 0; c < BRUME_NSAMPLES; c++)
        f->Tr.c[c] *= RC(1.0) - (ms->sigma_a.c[c] + ms->sigma_s.c[c]) * inv_maj;
    return RN(track_roulette)(&f->Tr, f->g);
}

FLIGHT_API void RN(flight_begin)(RN(flight) *f, rng *ug)
{
    f->ug = ug;
    f->udim = ug->counter++;
    f->Tr = RN(col)(RC(1.0));
    f->A = RC(0.0);
}

FLIGHT_API void RN(flight_track)(RN(flight) *f, RN(ray) r, R t0, R tmax)
{
    f->r = r;
    f->t0 = t0;
    if (!RN(col_is_black)(f->Tr))
        RN(track_collisions)(f->s, f->absent, r, tmax, f->g, false, RN(flight_step), f, NULL);
}

FLIGHT_API bool RN(flight_end)(RN(flight) *f)
{
    if (!(f->A > RC(0.0)))
        return false;
    f->beta_s = RN(col_scale)(f->beta_s, f->A);
    return true;
}

FLIGHT_API bool RN(flight_run)(RN(flight) *f, RN(ray) r, R tmax, rng *ug)
{
    RN(flight_begin)(f, ug);
    RN(flight_track)(f, r, RC(0.0), tmax);
    return RN(flight_end)(f);
}

#include "core/real_names_end.h"
