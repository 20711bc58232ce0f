/* path.c - volumetric path tracing with null-collision flights and MIS.
 *
 * Along each flight (flight.c) one collision is kept where the path scatters, and beta Tr
 * at the flight's end weighs what lies past it. At a scattering event every light and the
 * background are sampled (next-event estimation, transmittance by ratio tracking), and
 * the path continues along a phase-function sample; area lights and the background
 * reached by that continuation are weighted against next-event estimation by the power
 * heuristic (Veach 1997). A delta sun's light scattered once more is also sampled from the
 * sun's own scattering lobe (sun-lobe sampling), weighed against phase sampling by the same
 * heuristic. Derivations: docs/path-tracer.md.
 *
 * Single scattering (`single`) is this estimator stopped after one scattering event
 * (path_Li_alpha with max_depth 1, path_prepare without lobe tables), not a second one: it
 * has no file of its own because it has no code of its own. */
#include "render/path_impl.h"

#include "core/stats.h"
#include "surface/surfaces.h"

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

/* A scattering vertex: in a medium (phase function) or on a surface (material). */
typedef struct vertex {
    vec3 p;          /* where light is gathered (offset off the surface for surfaces) */
    vec3 d;          /* propagation direction of the arriving path (unit) */
    const phase *ph; /* medium vertex */
    const material *m; /* surface vertex */
    vec3 n;          /* surface: unit normal on the side of -d */
    uint32_t absent; /* the bounded media the vertex is not in (track_collisions') */
    vec3 ng;         /* surface: its front normal (the media's sides) */
    vec3 ns;         /* surface: its shading normal on ng's side (the BSDF's frame; ng unless bumped) */
    vec3 nsw;        /* surface: ns on the side of -d (the cosine's) */
    vec3 p_back;     /* surface: p's twin on the far side, where transmitted light is gathered */
    uint32_t absent_back; /* surface: the bounded media not on the far side */
    double time;     /* the path's instant: shadow rays see moving things where they are then */
} vertex;

/* Scattering kernel for light arriving from direction wi (towards the light) and leaving
 * back along -d: phase p(cos) between propagation directions -wi and -d, or f cos. */
static color vertex_f(const vertex *v, vec3 wi)
{
    if (v->ph)
        return col(phase_eval(v->ph, v3_dot(wi, v->d)));
    return col_scale(material_eval(v->m, v->ns, v3_neg(v->d), wi), fabs(v3_dot(wi, v->nsw)));
}

/* Where a shadow ray towards wi starts, and the bounded media it starts outside of: on the
 * side of the surface wi leaves by. */
static vec3 vertex_origin(const vertex *v, vec3 wi)
{
    return v->m && v3_dot(wi, v->n) < 0.0 ? v->p_back : v->p;
}
static uint32_t vertex_absent(const vertex *v, vec3 wi)
{
    return v->m && v3_dot(wi, v->n) < 0.0 ? v->absent_back : v->absent;
}

static double vertex_pdf(const vertex *v, vec3 wi)
{
    if (v->ph)
        return phase_pdf(v->ph, v3_dot(wi, v->d));
    return material_pdf(v->m, v->ns, v3_neg(v->d), wi);
}

/* Surfaces a flight or a shadow ray crosses at most: past them, the next one counts as
 * opaque (a bound on the work of a ray caught between coincident surfaces). */
#define PATH_MAX_CROSSINGS 64

uint32_t path_cross_surface(const surface_hit *sh, vec3 d, uint32_t absent)
{
    return surface_media_cross(sh->media, sh->ng, d, absent);
}

/* Transmittance from p along unit wi over (0, dist) at `time`, starting outside the bounded
 * media `absent`: 0 if a surface is in the way, else the media's, by ratio tracking. An
 * interface (a surface with no material that bounds media) is crossed: the media change
 * there (path_cross_surface). */
color scene_transmittance(const brume_scene *s, uint32_t absent, vec3 p, vec3 wi, double dist, double time, rng *g)
{
    if (!s->has_interfaces) {
        if (s->surf && surfaces_occluded(s->surf, p, wi, 0.0, dist * (1.0 - 1e-7), time))
            return col(0.0);
        return track_transmittance(s, absent, (ray){p, wi, time}, dist, g);
    }
    color Tr = col(1.0);
    ray r = {p, wi, time};
    double tmin = 0.0;
    for (int k = 0; k <= PATH_MAX_CROSSINGS; k++) {
        surface_hit sh;
        bool hit = surfaces_intersect(s->surf, r, tmin, dist * (1.0 - 1e-7), &sh);
        if (hit && (!sh.media.interface || k == PATH_MAX_CROSSINGS))
            return col(0.0);
        Tr = col_mul(Tr, track_transmittance(s, absent, r, hit ? sh.t : dist, g));
        if (!hit || col_is_black(Tr))
            break;
        absent = path_cross_surface(&sh, wi, absent);
        dist -= sh.t;
        r.o = sh.p; /* the next piece starts on the surface: no medium skipped */
        tmin = surface_cross_tmin(r.o);
    }
    return Tr;
}

/* Crossings of a camera's line at most (path_camera_absent): past them, the nearest count. */
#define CAMERA_MAX_CROSSINGS 64

uint32_t path_camera_absent(const brume_scene *s, ray r)
{
#if defined(__CUDA_ARCH__)
    (void)r; /* bounded media render on the CPU only (device_scene_check): no frame for this here */
    return s->bounded;
#else
    if (!s->bounded)
        return 0;
    struct {
        surface_media media;
        vec3 ng;
    } h[CAMERA_MAX_CROSSINGS];
    int n = 0;
    ray q = r;
    double tmin = 0.0;
    for (int k = 0; k < 4 * CAMERA_MAX_CROSSINGS && n < CAMERA_MAX_CROSSINGS; k++) {
        surface_hit sh;
        if (!surfaces_intersect(s->surf, q, tmin, INFINITY, &sh))
            break;
        if (sh.media.inside >= 0 || sh.media.outside >= 0) {
            h[n].media = sh.media;
            h[n++].ng = sh.ng;
        }
        q.o = sh.p;
        tmin = surface_cross_tmin(q.o);
    }
    /* from infinity, where no bounded medium is, back along the line to the camera */
    uint32_t absent = s->bounded;
    for (int i = n - 1; i >= 0; i--)
        absent = surface_media_cross(h[i].media, h[i].ng, v3_neg(r.d), absent);
    return absent & ~s->camera_members;
#endif
}

/* Flight f (flight_begin, f->absent set) along r up to tmax (the nearest area light, or
 * INFINITY), crossing interfaces on the way (their media change f->absent): true when it
 * ends on a surface that is not one, whose hit *sh then is (its t counted from the last
 * piece's start, its p exact). The kept collision's f->t counts along r from its origin:
 * each piece starts where the last one crossed. flight_end gives the flight's result. */
static bool path_fly(const brume_scene *s, flight *f, ray r, double tmax, surface_hit *sh, rng *ug)
{
    flight_begin(f, ug);
    double t0 = 0.0, tmin = 0.0;
    for (int k = 0;; k++) {
        bool on = s->surf && surfaces_intersect(s->surf, r, tmin, tmax - t0, sh);
        if (!on || !sh->media.interface || k == PATH_MAX_CROSSINGS) {
            flight_track(f, r, t0, on ? sh->t : tmax - t0);
            return on;
        }
        flight_track(f, r, t0, sh->t);
        f->absent = path_cross_surface(sh, r.d, f->absent);
        t0 += sh->t;
        r.o = sh->p; /* the next piece starts on the surface: no medium skipped */
        tmin = surface_cross_tmin(r.o);
    }
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

/* ---- sun-lobe sampling and the sun roulette (docs/path-tracer.md) ---------------------- */

/* The lobe samples one scattering vertex made (or could have made) for each delta sun: the
 * next vertex weighs its next-event estimate of sun j by phase sampling's MIS weight
 * against them. ph = NULL: the next vertex was not reached by phase sampling from a medium
 * vertex, so nothing was weighed against it. */
typedef struct lobe_prev {
    const phase *ph;   /* the phase function that sampled the direction */
    double pdf;        /* its pdf of that direction (per sr) */
    double P[LOBE_MAX_SUNS]; /* expected number of lobe samples of sun j, in [0, 1] */
} lobe_prev;

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
        color Tr =
            scene_transmittance(s, vertex_absent(v, ls.wi), vertex_origin(v, ls.wi), ls.wi, ls.dist, v->time, g);
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
                    color Tr = scene_transmittance(s, vertex_absent(v, wi), vertex_origin(v, wi), wi,
                                                   dist * (1.0 - 1e-5), v->time, g);
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
                    color Tr =
                        scene_transmittance(s, vertex_absent(v, wi), vertex_origin(v, wi), wi, INFINITY, v->time, g);
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
        flight fb = {.s = s, .g = g, .beta = col_scale(beta, p_a / (P * p_b) * w_b), .L = col(0.0),
                     .tail_Tr = FLIGHT_TAIL_TR, .absent = v->absent};
        path_fly(s, &fb, rb, t_end, &sh, g);
        if (!flight_end(&fb))
            continue; /* (the emission fb.L gathered is the path's own flights' to count) */
        const phase *ph_y = media_choose_phase(s, &fb.ms, rng_next(g));
        const double f_y = phase_eval(ph_y, v3_dot(wi, omega));
        const double q = nee_roulette(col(f_y), 1.0, g);
        if (q == 0.0)
            continue;
        color Tr = scene_transmittance(s, fb.absent_s, ray_at(rb, fb.t), wi, INFINITY, v->time, g);
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

/* ---- the path: one camera sample's walk, event by event ------------------------------ */

/* A camera path in flight (path_Li_alpha) and what its events share. Dimensions
 * (docs/sampling.md, "The path's dimensions"): scattering event `depth` takes four fixed
 * dimensions of the sequence g from dim0 on (the flight's reservoir choice, the branch or
 * phase-function choice, the direction), so that a Sobol sampler stratifies the same
 * decision in every sample of a pixel; the numbers whose count varies (tentative
 * collisions, shadow rays, roulettes, light samples) come from a second sequence gt of the
 * same sample. Splitting (path.split = k > 1): the camera path's first medium vertex is kept
 * in `split`, and once the walk from it ends, the next of its k continuations starts there,
 * with hashed sequences of its own; each carries 1 / k of the throughput. */
typedef struct path_walk {
    const brume_scene *s;
    const path_state *st;   /* NULL: no sun-lobe samples, no sun roulette, no split */
    int max_depth;
    rng *g;                 /* the fixed dimensions' sequence: the camera sample's, then gs */
    uint64_t dim0;          /* its dimension at event 0 */
    rng gt;                 /* the varying numbers' sequence (f.g points to it) */
    rng gs;                 /* a continuation's sequence of fixed dimensions */
    const rng *g_cam;       /* the camera sample's */
    flight f;               /* the current flight; f.beta the path's throughput, f.L its radiance */
    ray r;                  /* the current ray */
    double pdf_dir;         /* solid-angle pdf of r's direction; 0 for camera rays */
    lobe_prev prev;         /* the lobe samples the last medium vertex made */
    int k_split;            /* path.split (1: no split) */
    int pending;            /* continuations of the split still to start */
    double share;           /* 1 / k once split: what path_roulette_share compares beta with */
    struct {
        vertex v;
        color beta;
        lobe_prev prev;
    } split;                /* the split vertex and what its continuations start with */
    /* the camera ray's flight, for alpha (path_Li_alpha's Tr_cam) */
    bool *hit_surface;
    color *Tr_cam;
    double t_cam;           /* where the camera ray's flight ended: a surface or an area light */
    ray r_cam;              /* the camera ray */
    int depth;              /* the next event's */
} path_walk;

/* The flight of event `depth` along w->r up to the nearest surface that is not an interface
 * (*on_surface; its hit *sh) or t_light (an area light, or INFINITY): true when it kept a
 * scattering collision and the path may scatter again. */
static bool path_flight(path_walk *w, int depth, double t_light, surface_hit *sh, bool *on_surface)
{
    stats_counters *sc = stats_tls;
    double t0 = sc ? stats_now() : 0.0;
    w->g->counter = w->dim0 + 4 * (uint64_t)depth;
    /* the camera ray's flight stays ratio tracking throughout: its one reservoir number is
     * what the sampler stratifies, and a tail's coin flips are not */
    w->f.tail_Tr = depth > 0 ? FLIGHT_TAIL_TR : 0.0;
    *on_surface = path_fly(w->s, &w->f, w->r, t_light, sh, w->g);
    bool scattered = flight_end(&w->f) && depth < w->max_depth;
    if (sc)
        sc->t_tracking += stats_now() - t0;
    return scattered;
}

/* What lies past the flight, seen through beta_past = beta Tr: light reached there is added
 * at once (a surface's emission, the area light `hit` with Le_light, or what escaped every
 * medium). Returns whether the path may reflect off the surface sh (NULL: none): a second
 * branch, chosen against the scattering one. */
static bool path_past(path_walk *w, int depth, const surface_hit *sh, int hit, color Le_light, double pdf_light,
                      color beta_past)
{
    const brume_scene *s = w->s;
    flight *f = &w->f;
    if (sh) {
        color Le = surface_emission(sh, v3_neg(w->r.d));
        if (!col_is_black(Le)) {
            double mw = w->pdf_dir > 0.0 ? mis_weight(w->pdf_dir, surfaces_emitter_pdf(s->surf, sh, w->r.o)) : 1.0;
            f->L = col_add(f->L, col_scale(col_mul(beta_past, Le), mw));
        }
        return depth < w->max_depth && !material_is_black(sh->mat) && !col_is_black(beta_past);
    }
    if (hit >= 0) {
        double mw = w->pdf_dir > 0.0 ? mis_weight(w->pdf_dir, pdf_light) : 1.0;
        f->L = col_add(f->L, col_scale(col_mul(beta_past, Le_light), mw));
    } else if (!col_is_black(beta_past)) {
        f->L = col_add(f->L, col_mul(beta_past, escaped_radiance(s, w->r.d, w->pdf_dir)));
    }
    return false;
}

/* A bounce off (or through) the surface sh with throughput beta: next-event estimation
 * unless the material has only delta lobes, then a direction from the material. After a
 * delta lobe pdf_dir is 0: the light the path then reaches is not weighed against light
 * sampling, which could not have found it. false: the path ends. */
static bool path_reflect(path_walk *w, int depth, const surface_hit *sh, color beta)
{
    const brume_scene *s = w->s;
    flight *f = &w->f;
    stats_counters *sc = stats_tls;
    if (sc)
        sc->path_vertices++;
    f->beta = beta;
    vertex v = {.d = w->r.d, .ph = NULL, .m = sh->mat, .absent = f->absent, .ng = sh->ng, .ns = sh->ns,
                .time = w->r.time};
    v.n = v3_dot(sh->ng, w->r.d) < 0.0 ? sh->ng : v3_neg(sh->ng);
    v.nsw = v3_dot(sh->ng, w->r.d) < 0.0 ? sh->ns : v3_neg(sh->ns);
    v.p = surface_offset(sh, v.n);
    v.p_back = surface_offset(sh, v3_neg(v.n));
    v.absent_back = path_cross_surface(sh, v3_neg(v.n), v.absent);
    if (!material_is_delta(sh->mat))
        f->L = col_add(f->L, col_mul(f->beta, direct_light_counted(s, w->st, NULL, &v, &w->gt)));
    w->prev.ph = NULL; /* a surface vertex: no lobe samples, nothing to weigh */
    bsdf_sample bs;
    w->g->counter = w->dim0 + 4 * (uint64_t)depth + 2;
    const vec3 wo = v3_neg(w->r.d);
    double u0 = rng_next(&w->gt), u1 = rng_next(w->g), u2 = rng_next(w->g);
    if (!material_sample(sh->mat, sh->ns, wo, u0, u1, u2, &bs))
        return false;
    f->beta = col_mul(f->beta, col_scale(col_scale(bs.f, fabs(v3_dot(bs.wi, v.nsw))), 1.0 / bs.pdf));
    w->pdf_dir = bs.delta ? 0.0 : (bs.pdf_is_walk ? material_pdf(sh->mat, sh->ns, wo, bs.wi) : bs.pdf);
    /* through the surface (a refraction): the path goes on from its far side, in the media
       there (path_cross_surface) */
    const bool through = v3_dot(bs.wi, v.n) < 0.0;
    if (through)
        f->absent = v.absent_back;
    w->r = (ray){through ? v.p_back : v.p, bs.wi, w->r.time};
    return path_roulette_share(&f->beta, w->share, depth, &w->gt);
}

/* Scattering in a medium at the flight's kept collision: next-event estimation, the sun-lobe
 * samples, the split at the camera path's first vertex, then a phase sample. false: the
 * path ends. */
static bool path_scatter(path_walk *w, int depth)
{
    const brume_scene *s = w->s;
    const path_state *st = w->st;
    flight *f = &w->f;
    f->beta = f->beta_s;
    w->g->counter = w->dim0 + 4 * (uint64_t)depth + 1;
    vertex v = {.p = ray_at(w->r, f->t), .d = w->r.d, .ph = media_choose_phase(s, &f->ms, rng_next(w->g)),
                .m = NULL, .absent = f->absent_s, .time = w->r.time};
    f->absent = f->absent_s; /* the next flight starts where this one scattered */
    stats_counters *sc = stats_tls;
    if (sc) {
        sc->path_scatterings++;
        sc->path_vertices++;
    }
    f->L = col_add(f->L, col_mul(f->beta, direct_light_counted(s, st, &w->prev, &v, &w->gt)));
    w->prev.ph = NULL;
    if (depth + 1 >= w->max_depth && !s->has_indirect_sources)
        return false; /* the last flight could only gather light from another event */
    /* the sun-lobe samples of the next event's estimate, when there is a next event */
    if (st && st->nsuns > 0 && st->kappa > 0.0 && depth + 1 < w->max_depth)
        f->L = col_add(f->L, lobe_samples(s, st, &v, f->beta, &w->gt, &w->prev));
    if (depth == 0 && w->k_split > 1) { /* the first of k continuations: this walk's own */
        w->share = 1.0 / w->k_split;
        f->beta = col_scale(f->beta, w->share);
        w->split.v = v;
        w->split.beta = f->beta;
        w->split.prev = w->prev;
        w->pending = w->k_split - 1;
    }
    w->r = phase_continue(&v, w->g, &w->pdf_dir); /* dimensions dim0 + 4 depth + 2, + 3 */
    w->prev.pdf = w->pdf_dir;
    return path_roulette_share(&f->beta, w->share, depth, &w->gt);
}

/* Scattering event `depth` of the walk: a flight to the nearest surface or area light, the
 * light past it, then a bounce off the surface or a scattering in the media (one branch, in
 * proportion to their weights, when both may be taken). false: the path ends. */
static bool path_event(path_walk *w, int depth)
{
    const brume_scene *s = w->s;
    flight *f = &w->f;
    double t_light, pdf_light = 0.0;
    color Le_light = col(0.0);
    int hit = nearest_area_light(s, w->r.o, w->r.d, &t_light, &Le_light, &pdf_light);
    surface_hit sh;
    bool on_surface;
    bool scattered = path_flight(w, depth, t_light, &sh, &on_surface);
    if (depth == 0 && w->hit_surface)
        *w->hit_surface = on_surface;
    if (depth == 0 && w->Tr_cam) { /* the flight's ratio-tracked Tr over [0, t_cam]: alpha's estimate */
        *w->Tr_cam = on_surface ? col(0.0) : f->Tr;
        w->t_cam = on_surface ? 0.0 : t_light;
    }
    color beta_past = col_mul(f->beta, f->Tr);
    bool reflect = path_past(w, depth, on_surface ? &sh : NULL, hit, Le_light, pdf_light, beta_past);
    if (reflect && scattered) { /* one branch, in proportion to the weights */
        double a_past = col_avg(beta_past), p_past = a_past / (a_past + f->A);
        if (rng_next(w->g) < p_past) { /* dimension dim0 + 4 depth + 1 */
            beta_past = col_scale(beta_past, 1.0 / p_past);
            scattered = false;
        } else {
            f->beta_s = col_scale(f->beta_s, 1.0 / (1.0 - p_past));
            reflect = false;
        }
    }
    if (reflect)
        return path_reflect(w, depth, &sh, beta_past);
    return scattered && path_scatter(w, depth);
}

/* The next continuation from the split vertex: sequences of its own (the pending count tells
 * them apart), its direction drawn as event 0's would be. */
static void path_split_next(path_walk *w)
{
    const uint64_t tag = (uint64_t)w->pending;
    w->gs = rng_make(w->g_cam->key, (uint64_t)0x73706c6974000000 + tag, 0);
    w->gt = rng_make(w->g_cam->key, (uint64_t)0x73706c6974740000 + tag, 0);
    w->g = &w->gs;
    w->dim0 = 0;
    w->pending--;
    w->f.beta = w->split.beta;
    w->f.absent = w->split.v.absent;
    w->prev = w->split.prev;
    w->g->counter = 2;
    w->r = phase_continue(&w->split.v, w->g, &w->pdf_dir);
    w->prev.pdf = w->pdf_dir;
}

/* One camera sample's walk, cut into its start, its events and its end (path_Li_alpha runs
 * them in one call). The GPU runs them from its own loop so that a thread whose walk ended
 * starts the next camera sample while its warp's other walks go on (gpu/kernel.cu,
 * brume_paths): the same walk, cut where its events already are.
 *
 * path_walk_begin sets up *w (which must stay in place: it points into itself) for the
 * camera ray r and sequence g (kept by the caller until the end); false when the walk is
 * already over (a culled camera ray). path_walk_step runs the next event, or starts the
 * split's next continuation; false when nothing is left. path_walk_end completes alpha's
 * transmittance and returns the radiance. */
static bool path_walk_begin(path_walk *w, const brume_scene *s, const void *state, ray r, int max_depth, rng *g,
                            bool *hit_surface, color *Tr_cam)
{
    const path_state *st = (const path_state *)state;
    double t_in, t_out;
    if (hit_surface)
        *hit_surface = false;
    if (st && st->cull && !box3_intersect(st->reach, r, 0.0, INFINITY, &t_in, &t_out)) {
        /* what the walk would come to for this ray, bit for bit: no flight, Tr = 1; only what
         * path_walk_end reads is set (a culled ray is most rays of a sparse frame) */
        if (Tr_cam)
            *Tr_cam = col(1.0);
        w->s = s;
        w->Tr_cam = Tr_cam;
        w->t_cam = INFINITY;
        w->r_cam = r;
        w->f.L = escaped_radiance(s, r.d, 0.0);
        return false;
    }
    *w = (path_walk){.s = s, .st = st, .max_depth = max_depth, .g = g, .dim0 = g->counter,
                     .gt = rng_make(g->key, 0x7472616b5f646d73ULL, 0), .g_cam = g, .r = r, .pdf_dir = 0.0,
                     .prev = {.ph = NULL}, .k_split = st ? st->split : 1, .pending = 0, .share = 1.0,
                     .split = {.v = {.ph = NULL}}, .hit_surface = hit_surface, .Tr_cam = Tr_cam, .t_cam = INFINITY,
                     .r_cam = r, .depth = 0};
    w->f.s = s;
    w->f.g = &w->gt;
    w->f.beta = col(1.0);
    w->f.L = col(0.0);
    w->f.absent = path_camera_absent(s, r);
    return true;
}

static bool path_walk_step(path_walk *w)
{
    if (path_event(w, w->depth)) {
        w->depth++;
        return true;
    }
    if (w->pending == 0)
        return false;
    path_split_next(w);
    w->depth = 1;
    return true;
}

static color path_walk_end(path_walk *w)
{
    /* alpha sees the media along the whole camera ray: past an area light too */
    color *Tr_cam = w->Tr_cam;
    ray r = w->r_cam;
    if (Tr_cam && w->t_cam > 0.0 && isfinite(w->t_cam) && !col_is_black(*Tr_cam))
        *Tr_cam = col_mul(*Tr_cam, track_transmittance(w->s, w->f.absent, (ray){ray_at(r, w->t_cam), r.d, r.time},
                                                       INFINITY, &w->gt));
    return w->f.L;
}

color path_Li_alpha(const brume_scene *s, const void *state, ray r, int max_depth, rng *g, bool *hit_surface,
                    color *Tr_cam)
{
    path_walk w;
    if (path_walk_begin(&w, s, state, r, max_depth, g, hit_surface, Tr_cam))
        while (path_walk_step(&w))
            ;
    return path_walk_end(&w);
}
