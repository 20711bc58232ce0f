/* track.c - merged majorants of all media, tentative collisions, ratio tracking. */
#include "render/track.h"

#include "core/sampling.h"
#include "core/stats.h"
#include "medium/blackbody.h"

/* The optional fields of a medium at its local point p: albedo scales sigma_s per
 * channel; temperature and emission fields add to Le (medium.h). */
static void medium_fields_at(const medium *md, vec3 p, color *ss, color *Le)
{
    if (md->albedo[0])
        for (int c = 0; c < BRUME_NSAMPLES; c++)
            ss->c[c] *= density_eval(md->albedo[c], p);
    if (md->temperature) {
        double T = (density_eval(md->temperature, p) - md->bb_offset) * md->bb_tscale;
        if (T > md->bb_cutoff)
            *Le = col_madd(*Le, blackbody_rgb(T), md->bb_scale);
    }
    if (md->emission[0]) {
        if (md->emission[1])
            for (int c = 0; c < BRUME_NSAMPLES; c++)
                Le->c[c] += md->emission_color.c[c] * density_eval(md->emission[c], p);
        else
            *Le = col_madd(*Le, md->emission_color, density_eval(md->emission[0], p));
    }
}

/* Velocity motion blur (medium.h; docs/animation.md, "Velocity motion blur"): the point
 * whose frame-time fields a lookup at p and time t reads, p - v(p) (t - t_f), first-order
 * Eulerian back-advection as in Cycles and Arnold. t - t_f is clamped to the shutter, the
 * interval the moved majorants (md->moved) were built for. */
static vec3 velocity_advect(const brume_scene *s, const medium *md, vec3 p, double time)
{
    double dt = time - s->time;
    dt = dt < s->cam.shutter_open ? s->cam.shutter_open : (dt > s->cam.shutter_close ? s->cam.shutter_close : dt);
    if (dt == 0.0 || !md->moved)
        return p;
    const vec3 u = v3(density_eval(md->velocity[0], p), density_eval(md->velocity[1], p),
                      density_eval(md->velocity[2], p));
    const double *M = md->velocity_map;
    const vec3 v = v3(M[0] * u.x + M[1] * u.y + M[2] * u.z, M[3] * u.x + M[4] * u.y + M[5] * u.z,
                      M[6] * u.x + M[7] * u.y + M[8] * u.z);
    return v3_sub(p, v3_scale(v, dt));
}

void media_at(const brume_scene *s, vec3 p, double time, medium_sample *ms)
{
    ms->sigma_a = col(0.0);
    ms->sigma_s = col(0.0);
    ms->emission = col(0.0);
    ms->n = 0;
    if (stats_tls)
        stats_tls->density_lookups++;
    for (int m = 0; m < s->nmedia; m++) {
        const medium *md = &s->media[m];
        vec3 pm = p;
        if (md->motion) {
            affine3 to_world = motion_at(md->motion, time), to_local;
            if (!affine3_invert(&to_world, &to_local))
                continue;
            pm = affine3_apply(&to_local, p);
        }
        if (md->velocity[0])
            pm = velocity_advect(s, md, pm, time);
        double rho = density_eval(md->rho, pm);
        if (rho <= 0.0)
            continue;
        color sa = col_scale(md->sigma_a, rho), ss = col_scale(md->sigma_s, rho);
        color Le = md->Le;
        if (medium_has_fields(md)) {
            medium_fields_at(md, pm, &ss, &Le);
        }
        ms->sigma_a = col_add(ms->sigma_a, sa);
        ms->sigma_s = col_add(ms->sigma_s, ss);
        ms->emission = col_add(ms->emission, col_mul(sa, Le));
        ms->index[ms->n] = m;
        ms->weight[ms->n] = col_avg(ss);
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
    media_at(rs->s, ray_at(rs->r, e->t), rs->r.time, &ms);
    color sigma_t = col_add(ms.sigma_a, ms.sigma_s);
    double inv = 1.0 / e->sigma_r;
    double Tc = e->tau_c > rs->tau_c ? exp(rs->tau_c - e->tau_c) : 1.0;
    rs->tau_c = e->tau_c;
    for (int c = 0; c < BRUME_NSAMPLES; c++)
        rs->Tr.c[c] *= Tc * (1.0 - (sigma_t.c[c] - e->sigma_c) * inv);
    return track_roulette(&rs->Tr, rs->g);
}

color track_transmittance(const brume_scene *s, ray r, double tmax, rng *g)
{
    ratio_state rs = {s, r, col(1.0), 0.0, g};
    double tau_c;
    if (track_collisions(s, r, tmax, g, true, ratio_step, &rs, &tau_c) && tau_c > rs.tau_c)
        rs.Tr = col_scale(rs.Tr, exp(rs.tau_c - tau_c));
    return rs.Tr;
}
