/* track.c - the scene's media at a point, tentative collisions, ratio tracking. */
#include "render/track.h"

#include "core/sampling.h"
#include "core/stats.h"

void media_at(const brume_scene *s, uint32_t absent, vec3 p, double time, medium_sample *ms)
{
    ms->sigma_a = col(0.0);
    ms->sigma_s = col(0.0);
    ms->emission = col(0.0);
    ms->n = 0;
    if (stats_tls)
        stats_tls->density_lookups++;
    /* Velocity motion blur (medium.h): fields are read back along the velocity over the
     * time since the frame's, clamped to the shutter, the interval the moved majorants
     * (md->moved) were built for. */
    double dt = time - s->time;
    dt = dt < s->cam.shutter_open ? s->cam.shutter_open : (dt > s->cam.shutter_close ? s->cam.shutter_close : dt);
    for (int m = 0; m < s->nmedia; m++) {
        medium_coeffs mc;
        if ((absent >> m & 1u) || !medium_coeffs_at(&s->media[m], p, time, dt, &mc))
            continue;
        ms->sigma_a = col_add(ms->sigma_a, mc.sigma_a);
        ms->sigma_s = col_add(ms->sigma_s, mc.sigma_s);
        ms->emission = col_add(ms->emission, mc.emission);
        ms->index[ms->n] = m;
        ms->weight[ms->n] = col_avg(mc.sigma_s);
        ms->n++;
    }
}

const phase *media_choose_phase(const brume_scene *s, const medium_sample *ms, double u)
{
    if (ms->n == 1)
        return s->media[ms->index[0]].ph;
    double total = 0.0;
    for (int i = 0; i < ms->n; i++)
        total += ms->weight[i];
    double x = u * total;
    for (int i = 0; i < ms->n; i++) {
        if (x < ms->weight[i])
            return s->media[ms->index[i]].ph;
        x -= ms->weight[i];
    }
    return s->media[ms->index[ms->n - 1]].ph;
}

typedef struct ratio_state {
    const brume_scene *s;
    uint32_t absent;
    ray r;
    color Tr;     /* the estimate up to the last collision, exp(-tau_c) included */
    double tau_c; /* control optical depth already in Tr */
    rng *g;
} ratio_state;

/* Below this transmittance, ratio tracking plays Russian roulette. */
#define RATIO_RR_THRESHOLD 0.1

bool track_roulette(color *Tr, rng *g)
{
    double m = col_max(*Tr);
    if (m <= 0.0)
        return false;
    if (m < RATIO_RR_THRESHOLD) {
        double q = m / RATIO_RR_THRESHOLD;
        if (rng_next(g) >= q) {
            *Tr = col(0.0);
            return false;
        }
        *Tr = col_scale(*Tr, 1.0 / q);
    }
    return true;
}

/* Residual ratio tracking (Cramer 1978; Novak et al. 2014): with collisions at the rate
 * sigma_r, T *= exp(-(control optical depth since the last collision)) and
 * T *= 1 - (sigma_t - sigma_c) / sigma_r per channel (in [0, 2]), with roulette once T is
 * small, so shadow rays through thick media stop early. */
static bool ratio_step(const track_event *e, void *user)
{
    ratio_state *rs = (ratio_state *)user;
    medium_sample ms;
    media_at(rs->s, rs->absent, ray_at(rs->r, e->t), rs->r.time, &ms);
    color sigma_t = col_add(ms.sigma_a, ms.sigma_s);
    double inv = 1.0 / e->sigma_r;
    double Tc = e->tau_c > rs->tau_c ? exp(rs->tau_c - e->tau_c) : 1.0;
    rs->tau_c = e->tau_c;
    for (int c = 0; c < BRUME_NSAMPLES; c++)
        rs->Tr.c[c] *= Tc * (1.0 - (sigma_t.c[c] - e->sigma_c) * inv);
    return track_roulette(&rs->Tr, rs->g);
}

color track_transmittance(const brume_scene *s, uint32_t absent, ray r, double tmax, rng *g)
{
    ratio_state rs = {s, absent, r, col(1.0), 0.0, g};
    double tau_c;
    if (track_collisions(s, absent, r, tmax, g, true, ratio_step, &rs, &tau_c) && tau_c > rs.tau_c)
        rs.Tr = col_scale(rs.Tr, exp(rs.tau_c - tau_c));
    return rs.Tr;
}
