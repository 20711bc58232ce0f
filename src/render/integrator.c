/* integrator.c - volumetric path tracing with null-collision flights and MIS.
 *
 * Along each flight, tentative collisions are drawn against the scalar majorant
 * sigma_maj (track.h) and walked with a ratio-tracking transmittance Tr (per channel). At
 * each, emission beta Tr sigma_a Le / sigma_maj is added, and the collision is offered to
 * a one-element reservoir with weight avg(beta Tr sigma_s) / sigma_maj (the history-aware
 * spectral choice of Kutz et al. 2017); the kept one is where the path scatters, and
 * beta Tr at the flight's end weighs what lies past it. At a scattering event every light
 * and the background are sampled
 * (next-event estimation, transmittance by ratio tracking), and the path continues along
 * a phase-function sample; area lights and the background reached by that continuation
 * are weighted against next-event estimation by the power heuristic (Veach 1997). A delta
 * sun's light scattered once more is also sampled from the sun's own scattering lobe
 * (sun-lobe sampling), weighed against phase sampling by the same heuristic.
 * Derivations: docs/path-tracer.md. */
#include "render/integrator.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/stats.h"
#include "core/arena.h"
#include "render/blasi.h"
#include "method/path_options.h"
#include "render/stam.h"
#include "surface/surfaces.h"

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
        f->t = t;
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
    media_at(f->s, ray_at(f->r, e->t), f->r.time, &f->cur);
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

bool flight_run(flight *f, ray r, double tmax, rng *ug)
{
    f->r = r;
    f->ug = ug;
    f->udim = ug->counter++;
    f->Tr = col(1.0);
    f->A = 0.0;
    track_collisions(f->s, r, tmax, f->g, false, flight_step, f, NULL);
    if (!(f->A > 0.0))
        return false;
    f->beta_s = col_scale(f->beta_s, f->A);
    return true;
}

/* path_roulette for a path that is one of 1 / share splits of a camera path: its throughput
 * beta is compared with its share, so that splitting does not make the roulette end the
 * continuations it made. */
static bool path_roulette_share(color *beta, double share, int depth, rng *g)
{
    double q = col_max(*beta) / share;
    if (depth < 3 || q >= 0.25)
        return true;
    if (rng_next(g) >= q)
        return false;
    *beta = col_scale(*beta, 1.0 / q);
    return true;
}

bool path_roulette(color *beta, int depth, rng *g) { return path_roulette_share(beta, 1.0, depth, g); }

/* Power heuristic with exponent 2. */
static double mis_weight(double pdf_this, double pdf_other)
{
    double a = pdf_this * pdf_this, b = pdf_other * pdf_other;
    return a > 0.0 ? a / (a + b) : 0.0;
}

/* A scattering vertex: in a medium (phase function) or on a surface (material). */
typedef struct vertex {
    vec3 p;          /* where light is gathered (offset off the surface for surfaces) */
    vec3 d;          /* propagation direction of the arriving path (unit) */
    const phase *ph; /* medium vertex */
    const material *m; /* surface vertex */
    vec3 n;          /* surface: unit normal on the side of -d */
    double time;     /* the path's instant: shadow rays see moving things where they are then */
} vertex;

/* Scattering kernel for light arriving from direction wi (towards the light) and leaving
 * back along -d: phase p(cos) between propagation directions -wi and -d, or f cos. */
static color vertex_f(const vertex *v, vec3 wi)
{
    if (v->ph)
        return col(phase_eval(v->ph, v3_dot(wi, v->d)));
    return col_scale(material_eval(v->m, v->n, v3_neg(v->d), wi), fabs(v3_dot(wi, v->n)));
}

static double vertex_pdf(const vertex *v, vec3 wi)
{
    if (v->ph)
        return phase_pdf(v->ph, v3_dot(wi, v->d));
    return material_pdf(v->m, v->n, v3_neg(v->d), wi);
}

/* Transmittance from p along unit wi over (0, dist) at `time`: 0 if a surface is in the
 * way, else the media's, by ratio tracking. */
color scene_transmittance(const brume_scene *s, vec3 p, vec3 wi, double dist, double time, rng *g)
{
    if (s->surf && surfaces_occluded(s->surf, p, wi, 0.0, dist * (1.0 - 1e-7), time))
        return col(0.0);
    return track_transmittance(s, (ray){p, wi, time}, dist, g);
}

/* Russian roulette on a shadow ray by what it can bring (docs/path-tracer.md, "Shadow-ray
 * roulette"): with f the scattering kernel, the ray is traced with probability
 * q = min(1, 4 pi max_c(f)) q_T, i.e. always where the kernel is at least an isotropic phase
 * function's 1 / (4 pi) and q_T = 1, and its estimate divided by q. q_T in (0, 1] is the
 * sun roulette's factor (sun_roulette; 1 for other lights). Returns q, or 0 when the ray is
 * not traced. */
static double nee_roulette(color f, double q_T, rng *g)
{
    double q = fmin(1.0, 4.0 * PI * col_max(f)) * q_T;
    if (q >= 1.0)
        return 1.0;
    return rng_next(g) < q ? q : 0.0;
}

/* ---- sun-lobe sampling (docs/path-tracer.md, "Sun-lobe sampling") ---------------------- */

#define LOBE_TABLE 33  /* S(c) at c = -1 + 2 i / (LOBE_TABLE - 1) */
#define LOBE_MAX_SUNS 4 /* delta suns that get lobe samples (the first ones of the scene) */

/* What integrator_prepare keeps for `path` and `single`: the delta suns; for lobe samples
 * (path), per medium (its phase function), the table of S(c), the relative size of phase
 * sampling's error on a sun's light scattered once more, as a function of the cosine c
 * between the arriving direction and the direction to the sun (lobe_table); the camera
 * rays' cull; and the sun roulette's predictions. */
typedef struct path_state {
    double kappa;                  /* path.sun_lobe */
    int nsuns;                     /* delta suns (lobe samples when kappa > 0; the sun roulette) */
    int split;                     /* path.split: continuations from the camera vertex (path only) */
    int sun[LOBE_MAX_SUNS];        /* indices into s->lights */
    float S[SCENE_MAX_MEDIA][LOBE_TABLE]; /* per medium (its phase function) */
    /* A camera ray that misses `reach`, the world box of every medium's walks
     * (density_reach_bounds), meets nothing but what lies past the media, when the scene has
     * no surfaces, no area lights and no moving media (`cull`): path_Li_alpha then returns
     * the escaped radiance at once, the value the whole path would have come to. */
    bool cull;
    box3 reach;
    /* Sun roulette (docs/path-tracer.md, "Sun rays deep in a cloud"): for each sun j (a
     * delta sun, sun[j]), tau[j] holds the optical depth towards it predicted at a grid of
     * tn nodes spanning `reach` (sun_tau_build), or is NULL (no prediction: sun_roulette 0,
     * moving media, or too little of the media deep enough for it to act). */
    double tau0;               /* -log(path.sun_roulette) */
    int tn[3];                 /* nodes per axis, >= 2 */
    vec3 tscale;               /* (tn - 1) / reach's size, per axis [1 / world unit] */
    float *tau[LOBE_MAX_SUNS]; /* per cell of the grid (tn - 1 per axis, x fastest): the least
                                  tau of its 8 nodes; in tau_data */
    float tau_data[];
} path_state;

/* The lobe samples one scattering vertex made (or could have made) for each delta sun: the
 * next vertex weighs its next-event estimate of sun j by phase sampling's MIS weight
 * against them. ph = NULL: the next vertex was not reached by phase sampling from a medium
 * vertex, so nothing was weighed against it. */
typedef struct lobe_prev {
    const phase *ph;   /* the phase function that sampled the direction */
    double pdf;        /* its pdf of that direction (per sr) */
    double P[LOBE_MAX_SUNS]; /* expected number of lobe samples of sun j, in [0, 1] */
} lobe_prev;

static bool light_is_delta_sun(const light *l) { return l->kind == LIGHT_DISTANT && !(l->angular_radius > 0.0); }

/* Power heuristic for phase sampling (pdf p_a, one sample) against P lobe samples of
 * pdf p_b. */
static double lobe_weight_a(double p_a, double P, double p_b) { return mis_weight(p_a, P * p_b); }

/* Phase sampling's MIS weight for sun j's next-event estimate at a vertex reached along
 * omega from the vertex that made `pv`. */
static double lobe_weight_nee(const lobe_prev *pv, int j, vec3 wi, vec3 omega)
{
    if (!pv || !pv->ph || !(pv->P[j] > 0.0))
        return 1.0;
    return lobe_weight_a(pv->pdf, pv->P[j], phase_pdf(pv->ph, v3_dot(wi, omega)));
}

/* The optical depth towards sun j predicted at p: the least of the 8 nodes of the grid's
 * cell that holds p (one value per cell, sun_tau_build), so the largest transmittance
 * nearby; 0 outside the grid, where a sun ray may meet the media or miss them. */
static double sun_tau_hat(const path_state *st, int j, vec3 p)
{
    const double x[3] = {(p.x - st->reach.lo.x) * st->tscale.x, (p.y - st->reach.lo.y) * st->tscale.y,
                         (p.z - st->reach.lo.z) * st->tscale.z};
    size_t at = 0, stride = 1;
    for (int a = 0; a < 3; a++) {
        const int cells = st->tn[a] - 1;
        if (!(x[a] >= 0.0 && x[a] <= cells)) /* also NaN */
            return 0.0;
        at += (size_t)(int)fmin(x[a], cells - 1) * stride;
        stride *= (size_t)cells;
    }
    return (double)st->tau[j][at];
}

/* The least probability the sun roulette gives a ray: the prediction may be wrong, so no ray
 * that could bring light is given up for good (unbiased); at T0 = 0.03 it takes effect
 * below a predicted T of 3e-8, an optical depth of 17. */
#define SUN_ROULETTE_MIN_Q 1e-6

/* What a ray towards sun j from p is traced with at most: min(1, T-hat / T0), from the
 * predicted transmittance T-hat and T0 = path.sun_roulette, and at least
 * SUN_ROULETTE_MIN_Q (1 without a prediction). */
static double sun_roulette_at(const path_state *st, int j, vec3 p)
{
    const double tau = sun_tau_hat(st, j, p);
    return tau <= st->tau0 ? 1.0 : fmax(SUN_ROULETTE_MIN_Q, exp(st->tau0 - tau)); /* T-hat / T0 */
}

static inline double sun_roulette(const path_state *st, int j, vec3 p)
{
    return st && j >= 0 && st->tau[j] ? sun_roulette_at(st, j, p) : 1.0;
}

double path_sun_transmittance_hat(const void *state, int sun, vec3 p)
{
    const path_state *st = (const path_state *)state;
    if (!st || sun < 0 || sun >= st->nsuns || !st->tau[sun])
        return 1.0;
    return exp(-sun_tau_hat(st, sun, p));
}

/* Next-event estimation at a vertex: every light, emissive surfaces and the background.
 * With st and pv, each delta sun's estimate is weighed against the lobe samples of the
 * vertex before (pv). */
static color direct_light(const brume_scene *s, const path_state *st, const lobe_prev *pv, const vertex *v, rng *g)
{
    color Ld = col(0.0);
    for (int i = 0; i < s->nlights; i++) {
        light_sample ls;
        double u1 = rng_next(g), u2 = rng_next(g);
        if (!light_sample_at(&s->lights[i], v->p, u1, u2, &ls) || col_is_black(ls.Li) || !(ls.pdf > 0.0))
            continue;
        color f = vertex_f(v, ls.wi);
        if (col_is_black(f))
            continue;
        double w = ls.delta ? 1.0 : mis_weight(ls.pdf, vertex_pdf(v, ls.wi));
        int sun = -1;
        for (int j = 0; st && j < st->nsuns; j++)
            if (st->sun[j] == i) {
                sun = j;
                w *= lobe_weight_nee(pv, j, ls.wi, v->d);
            }
        double q = nee_roulette(f, sun_roulette(st, sun, v->p), g);
        if (q == 0.0)
            continue;
        color Tr = scene_transmittance(s, v->p, ls.wi, ls.dist, v->time, g);
        Ld = col_add(Ld, col_scale(col_mul(col_mul(ls.Li, Tr), f), w / (q * ls.pdf)));
    }
    if (surfaces_has_emitters(s->surf)) {
        vec3 wi;
        double dist, pdf;
        color Le;
        double u0 = rng_next(g), u1 = rng_next(g), u2 = rng_next(g);
        if (surfaces_sample_emitter(s->surf, v->p, v->time, u0, u1, u2, &wi, &dist, &Le, &pdf) && pdf > 0.0) {
            color f = vertex_f(v, wi);
            if (!col_is_black(f)) {
                double w = mis_weight(pdf, vertex_pdf(v, wi));
                double q = nee_roulette(f, 1.0, g);
                if (q > 0.0) {
                    color Tr = scene_transmittance(s, v->p, wi, dist * (1.0 - 1e-5), v->time, g);
                    Ld = col_add(Ld, col_scale(col_mul(col_mul(Le, Tr), f), w / (q * pdf)));
                }
            }
        }
    }
    if (!background_is_black(&s->bg)) {
        double pdf;
        color Lb;
        vec3 wi = background_sample(&s->bg, rng_next(g), rng_next(g), &pdf, &Lb);
        if (pdf > 0.0 && !col_is_black(Lb)) {
            color f = vertex_f(v, wi);
            if (!col_is_black(f)) {
                double w = mis_weight(pdf, vertex_pdf(v, wi));
                double q = nee_roulette(f, 1.0, g);
                if (q > 0.0) {
                    color Tr = scene_transmittance(s, v->p, wi, INFINITY, v->time, g);
                    Ld = col_add(Ld, col_scale(col_mul(col_mul(Lb, Tr), f), w / (q * pdf)));
                }
            }
        }
    }
    return Ld;
}

/* direct_light, its time counted when statistics are on. */
static color direct_light_counted(const brume_scene *s, const path_state *st, const lobe_prev *pv, const vertex *v,
                                  rng *g)
{
    stats_counters *sc = stats_tls;
    if (!sc)
        return direct_light(s, st, pv, v, g);
    double t0 = stats_now();
    color Ld = direct_light(s, st, pv, v, g);
    sc->t_nee += stats_now() - t0;
    return Ld;
}

/* The nearest finite area light (sphere, disk) along the ray, or -1. */
static int nearest_area_light(const brume_scene *s, vec3 o, vec3 d, double *t_hit, color *Le, double *pdf)
{
    int best = -1;
    *t_hit = INFINITY;
    for (int i = 0; i < s->nlights; i++) {
        const light *l = &s->lights[i];
        if (l->kind != LIGHT_SPHERE && l->kind != LIGHT_DISK)
            continue;
        double t, p;
        color c;
        if (light_hit(l, o, d, &t, &c, &p) && t < *t_hit) {
            *t_hit = t;
            *Le = c;
            *pdf = p;
            best = i;
        }
    }
    return best;
}

/* S(c) of the medium whose phase function is ph, linear between the table's entries. */
static double lobe_S(const brume_scene *s, const path_state *st, const phase *ph, double c)
{
    int m = 0;
    while (m < s->nmedia - 1 && s->media[m].ph != ph)
        m++;
    double x = (fmin(1.0, fmax(-1.0, c)) + 1.0) * 0.5 * (LOBE_TABLE - 1);
    int i = (int)x;
    if (i > LOBE_TABLE - 2)
        i = LOBE_TABLE - 2;
    double f = x - i;
    return (1.0 - f) * (double)st->S[m][i] + f * (double)st->S[m][i + 1];
}

/* The lobe samples of medium vertex v with throughput beta (docs/path-tracer.md, "Sun-lobe
 * sampling"): for delta sun j, with probability P_j = min(1, kappa S(d . wi)), a direction
 * omega from the sun's lobe p(wi . omega), a flight along it to a scattering collision y,
 * and the sun's light scattered at y back along -omega, weighed by the power heuristic
 * against the phase sampling of the path's next direction. Returns the radiance they add;
 * *pv receives the P_j (its pdf is set once the path's direction is drawn). */
static color lobe_samples(const brume_scene *s, const path_state *st, const vertex *v, color beta, rng *g,
                          lobe_prev *pv)
{
    color L = col(0.0);
    pv->ph = v->ph;
    for (int j = 0; j < st->nsuns; j++) {
        const light *l = &s->lights[st->sun[j]];
        const vec3 wi = v3_neg(l->direction);
        /* deep in a cloud, where the sun's light cannot reach, the lobe sample is rouletted too */
        const double P =
            fmin(1.0, st->kappa * lobe_S(s, st, v->ph, v3_dot(v->d, wi))) * sun_roulette(st, j, v->p);
        pv->P[j] = P;
        if (!(P > 0.0) || !(rng_next(g) < P))
            continue;
        double p_b;
        double u1 = rng_next(g), u2 = rng_next(g);
        const vec3 omega = phase_sample(v->ph, wi, u1, u2, &p_b);
        const double p_a = phase_pdf(v->ph, v3_dot(v->d, omega));
        const double w_b = mis_weight(P * p_b, p_a);
        if (!(w_b > 0.0))
            continue;
        /* the flight stops where the path's would: at a surface or an area light */
        double t_end, pdf_l;
        color Le_l;
        nearest_area_light(s, v->p, omega, &t_end, &Le_l, &pdf_l);
        surface_hit sh;
        const ray rb = {v->p, omega, v->time};
        if (s->surf && surfaces_intersect(s->surf, rb, 0.0, t_end, &sh))
            t_end = sh.t;
        flight fb = {.s = s, .g = g, .beta = col_scale(beta, p_a / (P * p_b) * w_b), .L = col(0.0),
                     .tail_Tr = FLIGHT_TAIL_TR};
        if (!flight_run(&fb, rb, t_end, g))
            continue; /* (the emission fb.L gathered is the path's own flights' to count) */
        const phase *ph_y = media_choose_phase(s, &fb.ms, rng_next(g));
        const double f_y = phase_eval(ph_y, v3_dot(wi, omega));
        const double q = nee_roulette(col(f_y), 1.0, g);
        if (q == 0.0)
            continue;
        color Tr = scene_transmittance(s, ray_at(rb, fb.t), wi, INFINITY, v->time, g);
        L = col_add(L, col_scale(col_mul(col_mul(fb.beta_s, Tr), l->L), f_y / q));
    }
    return L;
}

/* Radiance reaching a flight that escaped every medium towards direction d: the
 * background and any sun disk, weighted against next-event estimation unless the ray
 * came from the camera (pdf_dir = 0). */
static color escaped_radiance(const brume_scene *s, vec3 d, double pdf_dir)
{
    color Le = col(0.0);
    if (!background_is_black(&s->bg)) {
        double w = pdf_dir > 0.0 ? mis_weight(pdf_dir, background_pdf(&s->bg, d)) : 1.0;
        Le = col_scale(background_eval(&s->bg, d), w);
    }
    for (int i = 0; i < s->nlights; i++) {
        const light *l = &s->lights[i];
        double t, pdf_l;
        color c;
        if (l->kind == LIGHT_DISTANT && light_hit(l, v3(0, 0, 0), d, &t, &c, &pdf_l)) {
            double w = pdf_dir > 0.0 ? mis_weight(pdf_dir, pdf_l) : 1.0;
            Le = col_madd(Le, c, w);
        }
    }
    return Le;
}

/* The path's next ray from medium vertex v: a direction from its phase function, from g's
 * next two numbers (phase sampling is exact, weight p / pdf = 1, for every phase function in
 * brume); *pdf_dir its solid-angle pdf. */
static ray phase_continue(const vertex *v, rng *g, double *pdf_dir)
{
    double u1 = rng_next(g), u2 = rng_next(g);
    return (ray){v->p, phase_sample(v->ph, v->d, u1, u2, pdf_dir), v->time};
}

color path_Li_alpha(const brume_scene *s, const void *state, ray r, int max_depth, rng *g, bool *hit_surface,
                    color *Tr_cam)
{
    const path_state *st = (const path_state *)state;
    double t_in, t_out;
    if (st && st->cull && !box3_intersect(st->reach, r, 0.0, INFINITY, &t_in, &t_out)) {
        /* what the loop below comes to for this ray, bit for bit: no flight, Tr = 1 */
        if (hit_surface)
            *hit_surface = false;
        if (Tr_cam)
            *Tr_cam = col(1.0);
        return escaped_radiance(s, r.d, 0.0);
    }
    const ray r_cam = r;
    double t_cam = INFINITY; /* where the camera ray's flight ended: a surface or an area light */
    /* Dimensions (docs/sampling.md, "The path's dimensions"): scattering event `depth` takes
     * four fixed dimensions of the camera sample's sequence g from its current one on (the
     * flight's reservoir choice, the branch or phase-function choice, the direction), so
     * that a Sobol sampler stratifies the same decision in every sample of a pixel; the
     * numbers whose count varies (tentative collisions, shadow rays, roulettes, light
     * samples) come from a second sequence of the same sample. */
    uint64_t dim0 = g->counter;
    rng gt = rng_make(g->key, 0x7472616b5f646d73ULL, 0);
    /* Splitting (path.split = k > 1): the camera path's first medium vertex is kept in sv,
     * and once the walk from it ends, the next of its k continuations starts there, with
     * hashed sequences of its own; each carries 1 / k of the throughput. */
    const int k_split = st ? st->split : 1;
    int pending = 0;       /* continuations of the split still to start */
    double share = 1.0;    /* 1 / k once split: what path_roulette_share compares beta with */
    struct {
        vertex v;
        color beta;
        lobe_prev prev;
    } sv = {.v = {.ph = NULL}};
    rng gs;                /* a continuation's sequence of fixed dimensions */
    const rng *g_cam = g;  /* the camera sample's */
    int depth_start = 0;
    flight f;
    f.s = s;
    f.g = &gt;
    f.beta = col(1.0);
    f.L = col(0.0);
    double pdf_dir = 0.0; /* solid-angle pdf of the current direction; 0 for camera rays */
    lobe_prev prev = {.ph = NULL}; /* the lobe samples the last medium vertex made */
    if (hit_surface)
        *hit_surface = false;
    for (;;) {
        for (int depth = depth_start;; depth++) {
            double t_light, pdf_light = 0.0;
            color Le_light = col(0.0);
            int hit = nearest_area_light(s, r.o, r.d, &t_light, &Le_light, &pdf_light);
            surface_hit sh;
            bool on_surface = s->surf && surfaces_intersect(s->surf, r, 0.0, t_light, &sh);
            if (depth == 0 && hit_surface)
                *hit_surface = on_surface;
            stats_counters *sc = stats_tls;
            double t0 = sc ? stats_now() : 0.0;
            g->counter = dim0 + 4 * (uint64_t)depth;
            /* the camera ray's flight stays ratio tracking throughout: its one reservoir number is
             * what the sampler stratifies, and a tail's coin flips are not */
            f.tail_Tr = depth > 0 ? FLIGHT_TAIL_TR : 0.0;
            bool scattered = flight_run(&f, r, on_surface ? sh.t : t_light, g) && depth < max_depth;
            if (sc)
                sc->t_tracking += stats_now() - t0;
            if (depth == 0 && Tr_cam) { /* the flight's ratio-tracked Tr over [0, t_cam]: alpha's estimate */
                *Tr_cam = on_surface ? col(0.0) : f.Tr;
                t_cam = on_surface ? 0.0 : t_light;
            }
            /* What lies past the flight, seen through Tr: light reached now is added at once;
             * a surface is a second branch, chosen against the scattering one below. */
            color beta_past = col_mul(f.beta, f.Tr);
            bool reflect = false;
            if (on_surface) {
                color Le = surface_emission(&sh, v3_neg(r.d));
                if (!col_is_black(Le)) {
                    double w = pdf_dir > 0.0 ? mis_weight(pdf_dir, surfaces_emitter_pdf(s->surf, &sh, r.o)) : 1.0;
                    f.L = col_add(f.L, col_scale(col_mul(beta_past, Le), w));
                }
                reflect = depth < max_depth && !material_is_black(sh.mat) && !col_is_black(beta_past);
            } else if (hit >= 0) {
                double w = pdf_dir > 0.0 ? mis_weight(pdf_dir, pdf_light) : 1.0;
                f.L = col_add(f.L, col_scale(col_mul(beta_past, Le_light), w));
            } else if (!col_is_black(beta_past)) {
                f.L = col_add(f.L, col_mul(beta_past, escaped_radiance(s, r.d, pdf_dir)));
            }
            if (reflect && scattered) { /* one branch, in proportion to the weights */
                double a_past = col_avg(beta_past), p_past = a_past / (a_past + f.A);
                if (rng_next(g) < p_past) { /* dimension dim0 + 4 depth + 1 */
                    beta_past = col_scale(beta_past, 1.0 / p_past);
                    scattered = false;
                } else {
                    f.beta_s = col_scale(f.beta_s, 1.0 / (1.0 - p_past));
                    reflect = false;
                }
            }
            if (reflect) {
                if (sc)
                    sc->path_vertices++;
                f.beta = beta_past;
                vertex v = {.d = r.d, .ph = NULL, .m = sh.mat, .time = r.time};
                v.n = v3_dot(sh.ng, r.d) < 0.0 ? sh.ng : v3_neg(sh.ng);
                v.p = surface_offset(&sh, v.n);
                f.L = col_add(f.L, col_mul(f.beta, direct_light_counted(s, st, NULL, &v, &gt)));
                prev.ph = NULL; /* a surface vertex: no lobe samples, nothing to weigh */
                vec3 wi;
                g->counter = dim0 + 4 * (uint64_t)depth + 2;
                double u0 = rng_next(&gt), u1 = rng_next(g), u2 = rng_next(g);
                if (!material_sample(sh.mat, v.n, v3_neg(r.d), u0, u1, u2, &wi, &pdf_dir))
                    break;
                f.beta = col_mul(f.beta, col_scale(vertex_f(&v, wi), 1.0 / pdf_dir));
                r = (ray){v.p, wi, r.time};
                if (!path_roulette_share(&f.beta, share, depth, &gt))
                    break;
                continue;
            }
            if (!scattered)
                break;
            /* Scattering in a medium: next-event estimation, then continue along a phase sample. */
            f.beta = f.beta_s;
            g->counter = dim0 + 4 * (uint64_t)depth + 1;
            vertex v = {.p = ray_at(r, f.t), .d = r.d, .ph = media_choose_phase(s, &f.ms, rng_next(g)), .m = NULL,
                        .time = r.time};
            if (sc) {
                sc->path_scatterings++;
                sc->path_vertices++;
            }
            f.L = col_add(f.L, col_mul(f.beta, direct_light_counted(s, st, &prev, &v, &gt)));
            prev.ph = NULL;
            if (depth + 1 >= max_depth && !s->has_indirect_sources)
                break; /* the last flight could only gather light from another event */
            /* the sun-lobe samples of the next event's estimate, when there is a next event */
            if (st && st->nsuns > 0 && st->kappa > 0.0 && depth + 1 < max_depth)
                f.L = col_add(f.L, lobe_samples(s, st, &v, f.beta, &gt, &prev));
            if (depth == 0 && k_split > 1) { /* the first of k continuations: this walk's own */
                share = 1.0 / k_split;
                f.beta = col_scale(f.beta, share);
                sv.v = v;
                sv.beta = f.beta;
                sv.prev = prev;
                pending = k_split - 1;
            }
            r = phase_continue(&v, g, &pdf_dir); /* dimensions dim0 + 4 depth + 2, + 3 */
            prev.pdf = pdf_dir;
            if (!path_roulette_share(&f.beta, share, depth, &gt))
                break;
        }
        if (pending == 0)
            break;
        /* the next continuation from the split vertex: sequences of its own (the pending count
         * tells them apart), its direction drawn as event 0's would be */
        const uint64_t tag = (uint64_t)pending;
        gs = rng_make(g_cam->key, (uint64_t)0x73706c6974000000 + tag, 0);
        gt = rng_make(g_cam->key, (uint64_t)0x73706c6974740000 + tag, 0);
        g = &gs;
        dim0 = 0;
        pending--;
        f.beta = sv.beta;
        prev = sv.prev;
        g->counter = 2;
        r = phase_continue(&sv.v, g, &pdf_dir);
        prev.pdf = pdf_dir;
        depth_start = 1;
    }
    /* alpha sees the media along the whole camera ray: past an area light too */
    if (Tr_cam && t_cam > 0.0 && isfinite(t_cam) && !col_is_black(*Tr_cam))
        *Tr_cam = col_mul(*Tr_cam, track_transmittance(s, (ray){ray_at(r_cam, t_cam), r_cam.d, r_cam.time}, INFINITY, &gt));
    return f.L;
}

/* S(c) of phase function ph at LOBE_TABLE cosines (docs/path-tracer.md, "Sun-lobe
 * sampling"). With p_a(omega) = p(d . omega) (phase sampling), p_b(omega) = p(wi . omega)
 * (the sun's lobe) and d . wi = c, the sun's light scattered once more is the integral of
 * p_a p_b (transmittances set aside), and phase sampling estimates it by p_b, with second
 * moment m2(c) = int p_a p_b^2. S(c) = rho^2 sqrt(m2(c) / m2(1)): the root mean square of
 * that estimate against its largest says where lobe samples pay (it falls by 20 from c = 1
 * to c = -1 for HG 0.8), and rho = min(1, 4 dV(1) / m2(1)) how much they can: dV(1) is the
 * part of m2(1) that one sample of each technique under the power heuristic removes, which
 * tends to m2 / 4 for a peaked lobe and to 0 for an isotropic one (rho is 1 for HG g >= 0.8,
 * 0.84 at 0.6, 0.39 at 0.3, 0 for isotropic). Below rho = 1/2 (HG g under about 0.35) a
 * lobe sample costs more than it removes (docs/performance.md) and S = 0. A midpoint rule
 * over (cos theta, phi) around wi. */
static void lobe_table(const phase *ph, float S[LOBE_TABLE])
{
    enum { NMU = 128, NPHI = 64 };
    const double dw = (2.0 / NMU) * (PI / NPHI) * 2.0; /* phi over [0, pi), twice by symmetry */
    double m2[LOBE_TABLE], dV1 = 0.0;
    for (int i = 0; i < LOBE_TABLE; i++) {
        const double c = -1.0 + 2.0 * i / (LOBE_TABLE - 1), sc = sqrt(fmax(0.0, 1.0 - c * c));
        double C = 0.0, Ca = 0.0, Cb = 0.0, m2a = 0.0, m2b = 0.0;
        m2[i] = 0.0;
        for (int a = 0; a < NMU; a++) {
            const double mu = -1.0 + (a + 0.5) * (2.0 / NMU), sm = sqrt(fmax(0.0, 1.0 - mu * mu));
            const double p_b = phase_pdf(ph, mu);
            for (int b = 0; b < NPHI; b++) {
                const double p_a = phase_pdf(ph, sc * sm * cos((b + 0.5) * (PI / NPHI)) + c * mu);
                const double f = p_a * p_b, w_a = mis_weight(p_a, p_b), w_b = 1.0 - w_a;
                C += f * dw;
                m2[i] += p_a * p_b * p_b * dw;
                if (i == LOBE_TABLE - 1) { /* what one sample of each technique removes at c = 1 */
                    Ca += f * w_a * dw;
                    Cb += f * w_b * dw;
                    m2a += p_a * (p_b * w_a) * (p_b * w_a) * dw;
                    m2b += p_b * (p_a * w_b) * (p_a * w_b) * dw;
                }
            }
        }
        if (i == LOBE_TABLE - 1)
            dV1 = (m2[i] - C * C) - (m2a - Ca * Ca + m2b - Cb * Cb);
    }
    const double m21 = m2[LOBE_TABLE - 1];
    const double rho = m21 > 0.0 ? fmin(1.0, 4.0 * fmax(0.0, dV1) / m21) : 0.0;
    for (int i = 0; i < LOBE_TABLE; i++)
        S[i] = rho >= 0.5 ? (float)(rho * rho * sqrt(m2[i] / m21)) : 0.0f;
}

/* The smallest channel's extinction of all media at p [1 / world unit]. */
static double sigma_t_least(const brume_scene *s, vec3 p)
{
    medium_sample ms;
    media_at(s, p, 0.0, &ms);
    double m = INFINITY;
    for (int c = 0; c < BRUME_NSAMPLES; c++)
        m = fmin(m, ms.sigma_a.c[c] + ms.sigma_s.c[c]);
    return m;
}

/* Fills tau (st->tn nodes spanning st->reach, x fastest) with the optical depth from each
 * node towards the sun (unit ws, towards it) to the grid's faces (docs/path-tracer.md, "Sun
 * rays deep in a cloud"). Swept plane by plane along the axis A nearest ws, from the sun's
 * side, where tau = 0: a node's ray meets the next plane towards the sun after
 * step = h_A / |ws_A|, where tau is bilinear between that plane's nodes, or leaves by a
 * side face first; the depth over the stretch is the midpoint rule with SUN_TAU_LOOKUPS
 * samples of the smallest channel's extinction. A prediction only: any values keep the
 * roulette unbiased. Deterministic (no random numbers, one thread). */
#define SUN_TAU_LOOKUPS 4
static void sun_tau_sweep(const brume_scene *s, const path_state *st, vec3 ws, float *tau)
{
    const int *n = st->tn;
    const double lo[3] = {st->reach.lo.x, st->reach.lo.y, st->reach.lo.z};
    const double hi[3] = {st->reach.hi.x, st->reach.hi.y, st->reach.hi.z};
    const double w[3] = {ws.x, ws.y, ws.z};
    const size_t stride[3] = {1, (size_t)n[0], (size_t)n[0] * (size_t)n[1]};
    double h[3];
    int A = 0;
    for (int a = 0; a < 3; a++) {
        h[a] = (hi[a] - lo[a]) / (n[a] - 1);
        A = fabs(w[a]) > fabs(w[A]) ? a : A;
    }
    const int B = (A + 1) % 3, C = (A + 2) % 3;
    const int first = w[A] > 0.0 ? n[A] - 1 : 0, dir = w[A] > 0.0 ? -1 : 1; /* away from the sun */
    const double step = h[A] / fabs(w[A]);
    for (int pa = first; pa >= 0 && pa < n[A]; pa += dir)
        for (int pc = 0; pc < n[C]; pc++)
            for (int pb = 0; pb < n[B]; pb++) {
                int idx[3];
                idx[A] = pa;
                idx[B] = pb;
                idx[C] = pc;
                double x[3];
                size_t at = 0;
                for (int a = 0; a < 3; a++) {
                    x[a] = idx[a] == n[a] - 1 ? hi[a] : lo[a] + idx[a] * h[a];
                    at += (size_t)idx[a] * stride[a];
                }
                if (pa == first) {
                    tau[at] = 0.0f;
                    continue;
                }
                double len = step, up = 0.0;
                for (int a = B; a != A; a = (a + 1) % 3) /* B, then C: a side face before the plane? */
                    if (w[a] != 0.0)
                        len = fmin(len, fmax(0.0, ((w[a] > 0.0 ? hi[a] : lo[a]) - x[a]) / w[a]));
                if (len == step) { /* the next plane: bilinear there */
                    double ub = (x[B] + step * w[B] - lo[B]) / h[B], uc = (x[C] + step * w[C] - lo[C]) / h[C];
                    int ib = (int)fmin(fmax(floor(ub), 0.0), n[B] - 2), ic = (int)fmin(fmax(floor(uc), 0.0), n[C] - 2);
                    double fb = fmin(fmax(ub - ib, 0.0), 1.0), fc = fmin(fmax(uc - ic, 0.0), 1.0);
                    const float *t = tau + (size_t)(pa - dir) * stride[A] + (size_t)ib * stride[B] + (size_t)ic * stride[C];
                    up = (1 - fc) * ((1 - fb) * (double)t[0] + fb * (double)t[stride[B]]) +
                         fc * ((1 - fb) * (double)t[stride[C]] + fb * (double)t[stride[B] + stride[C]]);
                }
                double sum = 0.0;
                for (int k = 0; k < SUN_TAU_LOOKUPS; k++) {
                    double t = (k + 0.5) * len / SUN_TAU_LOOKUPS;
                    sum += sigma_t_least(s, v3(x[0] + t * w[0], x[1] + t * w[1], x[2] + t * w[2]));
                }
                tau[at] = (float)(up + sum * len / SUN_TAU_LOOKUPS);
            }
}

/* The least tau of each cell's 8 nodes into cell_tau, from the sweep's nodes, and into
 * *deep the share of the media's extinction (at the cells' centres) in cells where that tau
 * is above tau0: where the roulette acts. false when out of memory. */
static bool sun_tau_build(const brume_scene *s, const path_state *st, vec3 ws, float *cell_tau, double *deep)
{
    const int *n = st->tn;
    float *tau = malloc((size_t)n[0] * (size_t)n[1] * (size_t)n[2] * sizeof *tau);
    if (!tau)
        return false;
    sun_tau_sweep(s, st, ws, tau);
    const size_t sy = (size_t)n[0], sz = (size_t)n[0] * (size_t)n[1];
    const vec3 h = v3((st->reach.hi.x - st->reach.lo.x) / (n[0] - 1), (st->reach.hi.y - st->reach.lo.y) / (n[1] - 1),
                      (st->reach.hi.z - st->reach.lo.z) / (n[2] - 1));
    size_t c = 0;
    double all = 0.0, beyond = 0.0;
    for (int k = 0; k < n[2] - 1; k++)
        for (int j = 0; j < n[1] - 1; j++)
            for (int i = 0; i < n[0] - 1; i++) {
                const float *b = tau + (size_t)i + (size_t)j * sy + (size_t)k * sz;
                const float m = fminf(fminf(fminf(b[0], b[1]), fminf(b[sy], b[1 + sy])),
                                      fminf(fminf(b[sz], b[1 + sz]), fminf(b[sy + sz], b[1 + sy + sz])));
                cell_tau[c++] = m >= 0.0f ? m : 0.0f; /* NaN (absurd extents): no prediction there */
                const double sigma = sigma_t_least(
                    s, v3_add(st->reach.lo, v3((i + 0.5) * h.x, (j + 0.5) * h.y, (k + 0.5) * h.z)));
                all += sigma;
                beyond += (double)m > st->tau0 ? sigma : 0.0;
            }
    free(tau);
    *deep = all > 0.0 ? beyond / all : 0.0;
    return true;
}

/* Nodes of the sun roulette's grid along reach's longest side: about a mean free path
 * apart in the comparison clouds (docs/performance.md, "Sun rays deep in a cloud"). */
#define SUN_TAU_NODES 32
/* The share of the media's extinction where the roulette acts (sun_tau_build's *deep) below
 * which a sun gets no prediction: 0.02 in cloud64 and 0.63 in wdas-dense at T0 = 0.03, where
 * the queries cost cloud64 1.5 % of its time and wdas-dense gains 7 % (docs/performance.md). */
#define SUN_ROULETTE_MIN_DEEP 0.1

/* The state of `path` and `single`: the camera rays' cull, the delta suns with, for each, the
 * sun roulette's predicted optical depths (when path.sun_roulette > 0 and no medium moves),
 * and with `lobes` (path) sun-lobe tables when path.sun_lobe > 0. */
static brume_status path_prepare(const brume_scene *s, bool lobes, path_state **out)
{
    *out = NULL;
    const path_options *o = (const path_options *)scene_options(s, METHOD_OPTIONS_PATH);
    path_state st = {.kappa = lobes ? o->sun_lobe : 0.0, .cull = !s->surf, .reach = box3_empty(),
                     .tau0 = o->sun_roulette > 0.0 ? -log(o->sun_roulette) : (double)INFINITY};
    for (int i = 0; i < s->nlights; i++)
        if (s->lights[i].kind == LIGHT_SPHERE || s->lights[i].kind == LIGHT_DISK)
            st.cull = false; /* a camera ray can end on it (nearest_area_light) */
    bool moving = false;
    for (int m = 0; m < s->nmedia; m++) {
        box3 b = density_reach_bounds(s->media[m].rho);
        st.reach = (box3){v3_min(st.reach.lo, b.lo), v3_max(st.reach.hi, b.hi)};
        moving |= s->media[m].motion != NULL;
    }
    st.cull &= !moving;
    /* box3_intersect takes an empty box for a full one: nothing to cull then (no medium) */
    const bool some = st.reach.lo.x < st.reach.hi.x && st.reach.lo.y < st.reach.hi.y && st.reach.lo.z < st.reach.hi.z;
    st.cull &= st.reach.lo.x <= st.reach.hi.x && st.reach.lo.y <= st.reach.hi.y && st.reach.lo.z <= st.reach.hi.z;
    for (int i = 0; s->nmedia > 0 && i < s->nlights && st.nsuns < LOBE_MAX_SUNS; i++)
        if (light_is_delta_sun(&s->lights[i]))
            st.sun[st.nsuns++] = i;
    for (int m = 0; st.nsuns > 0 && st.kappa > 0.0 && m < s->nmedia; m++) {
        int same = 0; /* media sharing a phase function share its table */
        while (same < m && s->media[same].ph != s->media[m].ph)
            same++;
        if (same < m)
            memcpy(st.S[m], st.S[same], sizeof st.S[m]);
        else
            lobe_table(s->media[m].ph, st.S[m]);
    }
    size_t cells = 0;
    if (o->sun_roulette > 0.0 && st.nsuns > 0 && some && !moving) {
        const vec3 ext = v3_sub(st.reach.hi, st.reach.lo);
        const double e[3] = {ext.x, ext.y, ext.z}, L = fmax(e[0], fmax(e[1], e[2]));
        double sc[3];
        cells = 1;
        for (int a = 0; a < 3; a++) {
            st.tn[a] = (int)fmin(SUN_TAU_NODES, fmax(2.0, ceil(SUN_TAU_NODES * e[a] / L)));
            sc[a] = (st.tn[a] - 1) / e[a];
            cells *= (size_t)(st.tn[a] - 1);
        }
        st.tscale = v3(sc[0], sc[1], sc[2]);
    }
    const size_t floats = cells * (size_t)st.nsuns;
    *out = malloc(sizeof **out + floats * sizeof(float));
    if (!*out)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory for the path state", s->source);
    **out = st;
    for (int j = 0; cells > 0 && j < st.nsuns; j++) {
        (*out)->tau[j] = (*out)->tau_data + (size_t)j * cells;
        double deep;
        if (!sun_tau_build(s, *out, v3_neg(s->lights[st.sun[j]].direction), (*out)->tau[j], &deep)) {
            free(*out);
            *out = NULL;
            return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory for the sun roulette's grid", s->source);
        }
        if (deep < SUN_ROULETTE_MIN_DEEP)
            (*out)->tau[j] = NULL; /* a query at every vertex would cost more than the roulette saves */
    }
    (*out)->split = lobes ? (int)o->split : 1;
    return BRUME_OK;
}

brume_status integrator_prepare(integrator_kind kind, const brume_scene *s, void **state)
{
    *state = NULL;
    /* albedo, temperature and emission grids are rendered by path and single only */
    for (int m = 0; (kind == INTEGRATOR_BLASI || kind == INTEGRATOR_STAM) && m < s->nmedia; m++)
        if (medium_has_fields(&s->media[m]))
            return err_set(BRUME_ERROR_UNSUPPORTED,
                           "%s: media[%d]: albedo, temperature and emission grids need the path or single method",
                           s->source, m);
    switch (kind) {
    case INTEGRATOR_PATH:
    case INTEGRATOR_SINGLE: {
        path_state *st = NULL;
        brume_status rc = path_prepare(s, kind == INTEGRATOR_PATH, &st);
        *state = st;
        return rc;
    }
    case INTEGRATOR_BLASI: {
        blasi_state *st = NULL;
        brume_status rc = blasi_prepare(s, &st);
        *state = st;
        return rc;
    }
    case INTEGRATOR_STAM: return stam_prepare(s, state);
    }
    return BRUME_OK;
}

void integrator_finish(integrator_kind kind, void *state)
{
    switch (kind) {
    case INTEGRATOR_PATH:
    case INTEGRATOR_SINGLE: free(state); break;
    case INTEGRATOR_BLASI: blasi_finish((blasi_state *)state); break;
    case INTEGRATOR_STAM: stam_finish(state); break;
    }
}

color integrator_Li(integrator_kind kind, const brume_scene *s, const void *state, ray r, rng *g,
                    bool *hit_surface, color *Tr)
{
    color L = col(0.0);
    switch (kind) {
    case INTEGRATOR_PATH: return path_Li_alpha(s, state, r, s->settings.max_depth, g, hit_surface, Tr);
    case INTEGRATOR_SINGLE: return path_Li_alpha(s, state, r, 1, g, hit_surface, Tr);
#if !defined(__CUDA_ARCH__) /* CPU-only methods: the GPU renders path and single (gpu/device_scene.c) */
    case INTEGRATOR_BLASI:
        L = blasi_Li(s, (const blasi_state *)state, r, g, hit_surface);
        if (Tr)
            *Tr = blasi_transmittance(s, (const blasi_state *)state, r); /* its voxels, exact: no tracking */
        return L;
    case INTEGRATOR_STAM:
        L = stam_Li(state, r, g, hit_surface);
        if (Tr)
            *Tr = stam_transmittance(state, r.o, r.d, INFINITY);
        return L;
#else
    default: break;
#endif
    }
    return L;
}

/* Delta tracking to the first real collision (integrator_first_vertex). */
typedef struct first_walk {
    const brume_scene *s;
    ray r;
    rng *g;
    bool hit;
    double t;
    medium_sample ms;
} first_walk;

static bool first_step(const track_event *e, void *user)
{
    first_walk *w = (first_walk *)user;
    media_at(w->s, ray_at(w->r, e->t), w->r.time, &w->ms);
    double sigma_t = col_avg(col_add(w->ms.sigma_a, w->ms.sigma_s));
    if (rng_next(w->g) * e->sigma_maj < sigma_t) {
        w->hit = true;
        w->t = e->t;
        return false;
    }
    return true;
}

void integrator_first_vertex(const brume_scene *s, ray r, rng *g, first_vertex *v)
{
    memset(v, 0, sizeof *v);
    surface_hit sh;
    bool on_surface = s->surf && surfaces_intersect(s->surf, r, 0.0, INFINITY, &sh);
    first_walk w = {.s = s, .r = r, .g = g, .hit = false};
    track_collisions(s, r, on_surface ? sh.t : (double)INFINITY, g, false, first_step, &w, NULL);
    if (w.hit) {
        v->hit = true;
        v->depth = w.t;
        for (int c = 0; c < BRUME_NSAMPLES; c++) {
            double st = w.ms.sigma_a.c[c] + w.ms.sigma_s.c[c];
            v->albedo.c[c] = st > 0.0 ? w.ms.sigma_s.c[c] / st : 0.0;
        }
    } else if (on_surface) {
        v->hit = true;
        v->depth = sh.t;
        v->albedo = sh.mat ? sh.mat->albedo : col(0.0);
        v->normal = v3_dot(sh.ng, r.d) < 0.0 ? sh.ng : v3_neg(sh.ng);
    }
}

size_t path_state_device_put(const void *state, dev_arena *a)
{
    const path_state *st = (const path_state *)state;
    if (!st)
        return ARENA_NULL;
    size_t cells = st->tn[0] >= 2 ? (size_t)(st->tn[0] - 1) * (size_t)(st->tn[1] - 1) * (size_t)(st->tn[2] - 1) : 0;
    size_t at = arena_put(a, st, sizeof *st + cells * (size_t)st->nsuns * sizeof(float));
    for (int j = 0; j < LOBE_MAX_SUNS && at != ARENA_NULL; j++)
        arena_ptr(a, at + offsetof(path_state, tau) + (size_t)j * sizeof(float *),
                  st->tau[j] ? at + offsetof(path_state, tau_data) + (size_t)(st->tau[j] - st->tau_data) * sizeof(float)
                             : ARENA_NULL);
    return at;
}
