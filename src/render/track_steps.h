/* track_steps.h - the shadow stage: Russian roulette and residual ratio tracking
 * (render/track.h's track_roulette and track_transmittance), over one real type
 * (core/real_names.h) and scene TRACK_SCENE with its RN(media_at). TRACK_API is the
 * functions' storage: track.c defines the double ones (TRACK_API empty), render/
 * track_float.h the float ones (static inline) for the GPU's single-precision stages. */
#include "core/real_names.h"

/* Below this transmittance, ratio tracking plays Russian roulette. */
#define RATIO_RR_THRESHOLD RC(0.1)

TRACK_API bool RN(track_roulette)(RN(color) *Tr, rng *g)
{
    R m = RN(col_max)(*Tr);
    if (m <= RC(0.0))
        return false;
    if (m < RATIO_RR_THRESHOLD) {
        R q = m / RATIO_RR_THRESHOLD;
        if (RN(rng_next)(g) >= q) {
            *Tr = RN(col)(RC(0.0));
            return false;
        }
        *Tr = RN(col_scale)(*Tr, RC(1.0) / q);
    }
    return true;
}

typedef struct RN(ratio_state) {
    const TRACK_SCENE *s;
    uint32_t absent;
    RN(ray) r;
    RN(color) Tr; /* the estimate up to the last collision, exp(-tau_c) included */
    R tau_c;      /* control optical depth already in Tr */
    rng *g;
} RN(ratio_state);

/* Residual ratio tracking (Cramer 1978; Novak et al. 2014): with collisions at the rate
 * sigma_r, T *= exp(-(control optical depth since the last collision)) and
 * T *= 1 - (sigma_t - sigma_c) / sigma_r per channel (in [0, 2]), with roulette once T is
 * small, so shadow rays through thick media stop early. */
static bool RN(ratio_step)(const RN(track_event) *e, void *user)
{
    RN(ratio_state) *rs = (RN(ratio_state) *)user;
    RN(medium_sample) ms;
    RN(media_at)(rs->s, rs->absent, RN(ray_at)(rs->r, e->t), rs->r.time, &ms);
    RN(color) sigma_t = RN(col_add)(ms.sigma_a, ms.sigma_s);
    R inv = RC(1.0) / e->sigma_r;
    R Tc = e->tau_c > rs->tau_c ? R_EXP(rs->tau_c - e->tau_c) : RC(1.0);
    rs->tau_c = e->tau_c;
    for (int c = 0; c < BRUME_NSAMPLES; c++)
        rs->Tr.c[c] *= Tc * (RC(1.0) - (sigma_t.c[c] - e->sigma_c) * inv);
    return RN(track_roulette)(&rs->Tr, rs->g);
}

TRACK_API RN(color) RN(track_transmittance)(const TRACK_SCENE *s, uint32_t absent, RN(ray) r, R tmax, rng *g)
{
    RN(ratio_state) rs = {s, absent, r, RN(col)(RC(1.0)), RC(0.0), g};
    R tau_c;
    if (RN(track_collisions)(s, absent, r, tmax, g, true, RN(ratio_step), &rs, &tau_c) && tau_c > rs.tau_c)
        rs.Tr = RN(col_scale)(rs.Tr, R_EXP(rs.tau_c - tau_c));
    return rs.Tr;
}

#undef RATIO_RR_THRESHOLD
#include "core/real_names_end.h"
