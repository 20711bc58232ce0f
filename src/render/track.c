/* track.c - merged majorants of all media, tentative collisions, ratio tracking. */
#include "render/track.h"

#include "core/sampling.h"
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

typedef struct track_stream {
    majorant_iter it;
    majorant_seg seg;
    bool live;
    double sigma_t_max;
    double sigma_t_min; /* the medium's: the control's scale */
} track_stream;

bool track_collisions(const brume_scene *s, ray r, double tmax, rng *g, bool residual, track_fn fn, void *user,
                      double *tau_c_end)
{
    track_stream st[SCENE_MAX_MEDIA];
    int n = s->nmedia;
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
        st[m].live = majorant_next(&st[m].it, &st[m].seg);
        st[m].sigma_t_max = s->media[m].sigma_t_max;
        st[m].sigma_t_min = s->media[m].sigma_t_min;
    }
    track_event e = {0.0, 0.0, 0.0, 0.0};
    double t = 0.0, tau = sample_exponential(rng_next(g), 1.0);
    if (tau_c_end)
        *tau_c_end = 0.0;
    for (;;) {
        /* Majorant and control on [t, t_next): media whose current segment covers t. */
        double sigma_maj = 0.0, sigma_c = 0.0, t_next = INFINITY;
        bool any = false;
        for (int m = 0; m < n; m++) {
            while (st[m].live && st[m].seg.t1 <= t)
                st[m].live = majorant_next(&st[m].it, &st[m].seg);
            if (!st[m].live)
                continue;
            any = true;
            if (st[m].seg.t0 > t) {
                t_next = fmin(t_next, st[m].seg.t0);
            } else {
                sigma_maj += st[m].seg.rho_maj * st[m].sigma_t_max;
                sigma_c += st[m].seg.rho_min * st[m].sigma_t_min;
                t_next = fmin(t_next, st[m].seg.t1);
            }
        }
        if (!any || t >= tmax) {
            if (tau_c_end)
                *tau_c_end = e.tau_c;
            return true;
        }
        t_next = fmin(t_next, tmax);
        sigma_c = fmin(sigma_c, sigma_maj);
        /* the rate of tentative collisions */
        double sigma_n = residual ? sigma_maj - sigma_c : sigma_maj;
        e.sigma_maj = sigma_maj;
        e.sigma_c = sigma_c;
        const double tau_c0 = e.tau_c;
        /* tau: optical depth (against the majorant) still to cover before the next
         * tentative collision; one exponential per collision, carried across segments. */
        if (sigma_n > 0.0) {
            /* Distances are measured from the segment's start: u grows from 0, so a step of
             * 1e-18 still advances it where t + 1e-18 == t (a dense medium far from the
             * origin), and it strictly increases (a step below its resolution moves it by
             * one ulp), so the walk reaches the segment's end or stops in a finite number
             * of steps. The range that keeps that number small is checked at commit
             * (medium_check_range, docs/scene-format.md#limits). */
            const double t0 = t, len = t_next - t;
            double u = 0.0;
            for (;;) {
                double du = tau / sigma_n;
                if (!(u + du < len)) {
                    tau = fmax(0.0, tau - sigma_n * (len - u));
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

void media_at(const brume_scene *s, vec3 p, double time, medium_sample *ms)
{
    ms->sigma_a = col(0.0);
    ms->sigma_s = col(0.0);
    ms->emission = col(0.0);
    ms->n = 0;
    for (int m = 0; m < s->nmedia; m++) {
        const medium *md = &s->media[m];
        vec3 pm = p;
        if (md->motion) {
            affine3 to_world = motion_at(md->motion, time), to_local;
            if (!affine3_invert(&to_world, &to_local))
                continue;
            pm = affine3_apply(&to_local, p);
        }
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
 * sigma_maj - sigma_c, T *= exp(-(control optical depth since the last collision)) and
 * T *= 1 - (sigma_t - sigma_c) / (sigma_maj - sigma_c) per channel, with roulette once T is
 * small, so shadow rays through thick media stop early. */
static bool ratio_step(const track_event *e, void *user)
{
    ratio_state *rs = user;
    medium_sample ms;
    media_at(rs->s, ray_at(rs->r, e->t), rs->r.time, &ms);
    color sigma_t = col_add(ms.sigma_a, ms.sigma_s);
    double inv = 1.0 / (e->sigma_maj - e->sigma_c);
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
