/* integrator.c - volumetric path tracing with spectral tracking (Kutz et al. 2017).
 *
 * Along each flight, tentative collisions are drawn against the scalar majorant
 * sigma_maj (track.h). At a collision with coefficients sigma_a, sigma_s and
 * sigma_n = sigma_maj - sigma_a - sigma_s (per channel, >= 0):
 *   - emission sigma_a Le / sigma_maj is added, weighted by the path throughput beta;
 *   - one event is chosen: absorption, scattering or null, with the history-aware
 *     probabilities P_x = avg(beta sigma_x) / sum_y avg(beta sigma_y), and beta is
 *     multiplied by sigma_x / (sigma_maj P_x). Absorption ends the path.
 * For a gray medium and gray beta this is delta tracking with weights that stay 1; for
 * chromatic media it is unbiased with bounded weights. At scattering events, next-event
 * estimation to each delta light uses ratio tracking for the transmittance; the path then
 * continues in a direction sampled from the phase function, and the background radiance
 * is gathered when a flight leaves the media. Derivation: docs/path-tracer.md. */
#include "render/integrator.h"

#include <string.h>

#include "render/track.h"

bool integrator_from_name(const char *name, integrator_kind *out)
{
    if (strcmp(name, "path") == 0)
        *out = INTEGRATOR_PATH;
    else if (strcmp(name, "single") == 0)
        *out = INTEGRATOR_SINGLE;
    else
        return false;
    return true;
}

const char *integrator_names(void) { return "path, single"; }

typedef enum flight_end {
    FLIGHT_ESCAPED,
    FLIGHT_SCATTERED,
    FLIGHT_ABSORBED
} flight_end;

typedef struct flight {
    const brume_scene *s;
    ray r;
    rng *g;
    color beta; /* path throughput */
    color L;    /* radiance gathered so far */
    flight_end end;
    double t;   /* where it scattered */
    medium_sample ms;
} flight;

static bool flight_step(double t, double sigma_maj, void *user)
{
    flight *f = user;
    vec3 p = ray_at(f->r, t);
    media_at(f->s, p, &f->ms);
    const medium_sample *ms = &f->ms;
    double inv_maj = 1.0 / sigma_maj;
    if (!col_is_black(ms->emission))
        f->L = col_add(f->L, col_scale(col_mul(f->beta, ms->emission), inv_maj));

    color sigma_n;
    for (int c = 0; c < BRUME_NSAMPLES; c++)
        sigma_n.c[c] = fmax(0.0, sigma_maj - ms->sigma_a.c[c] - ms->sigma_s.c[c]);
    double wa = col_avg(col_mul(f->beta, ms->sigma_a));
    double ws = col_avg(col_mul(f->beta, ms->sigma_s));
    double wn = col_avg(col_mul(f->beta, sigma_n));
    double total = wa + ws + wn;
    if (total <= 0.0) {
        f->end = FLIGHT_ABSORBED;
        return false;
    }
    double u = rng_next(f->g) * total;
    if (u < wa) {
        f->end = FLIGHT_ABSORBED;
        return false;
    }
    if (u < wa + ws) {
        f->beta = col_scale(col_mul(f->beta, ms->sigma_s), total / (ws * sigma_maj));
        f->end = FLIGHT_SCATTERED;
        f->t = t;
        return false;
    }
    f->beta = col_scale(col_mul(f->beta, sigma_n), total / (wn * sigma_maj));
    return true;
}

/* Direct light from every delta light, scattered at p towards -wo (wo: propagation
 * direction of the incoming path). */
static color direct_light(const brume_scene *s, vec3 p, vec3 wo, const phase *ph, rng *g)
{
    color Ld = col(0.0);
    for (int i = 0; i < s->nlights; i++) {
        vec3 wi;
        double dist;
        color E = light_sample_delta(&s->lights[i], p, &wi, &dist);
        if (col_is_black(E))
            continue;
        /* light propagates along -wi and leaves along -wo: cos between propagation dirs */
        double cos_theta = v3_dot(v3_neg(wi), v3_neg(wo));
        double ph_val = phase_eval(ph, cos_theta);
        if (ph_val <= 0.0)
            continue;
        color Tr = track_transmittance(s, (ray){p, wi, 0.0}, dist, g);
        Ld = col_add(Ld, col_scale(col_mul(E, Tr), ph_val));
    }
    return Ld;
}

color path_Li(const brume_scene *s, ray r, int max_depth, rng *g)
{
    flight f;
    f.s = s;
    f.g = g;
    f.beta = col(1.0);
    f.L = col(0.0);
    for (int depth = 0;; depth++) {
        f.r = r;
        f.end = FLIGHT_ESCAPED;
        track_collisions(s, r, INFINITY, g, flight_step, &f);
        if (f.end == FLIGHT_ESCAPED) {
            f.L = col_add(f.L, col_mul(f.beta, s->background));
            break;
        }
        if (f.end == FLIGHT_ABSORBED || depth >= max_depth)
            break;
        /* Scattering: next-event estimation, then continue along a phase sample. */
        vec3 p = ray_at(r, f.t);
        const phase *ph = media_choose_phase(s, &f.ms, rng_next(g));
        f.L = col_add(f.L, col_mul(f.beta, direct_light(s, p, r.d, ph, g)));
        if (depth + 1 >= max_depth && col_is_black(s->background) && !s->has_emission)
            break; /* the last flight could only gather light from another event */
        double pdf;
        vec3 wo = phase_sample(ph, r.d, rng_next(g), rng_next(g), &pdf);
        /* phase sampling is exact (weight p / pdf = 1) for every phase function in brume */
        r = (ray){p, wo, r.time};
        /* Russian roulette once the throughput is small. */
        double q = col_max(f.beta);
        if (depth >= 3 && q < 0.5) {
            if (rng_next(g) >= q)
                break;
            f.beta = col_scale(f.beta, 1.0 / q);
        }
    }
    return f.L;
}

color integrator_Li(integrator_kind kind, const brume_scene *s, ray r, rng *g)
{
    switch (kind) {
    case INTEGRATOR_PATH: return path_Li(s, r, s->settings.max_depth, g);
    case INTEGRATOR_SINGLE: return path_Li(s, r, 1, g);
    }
    return col(0.0);
}
