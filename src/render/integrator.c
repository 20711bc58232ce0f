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
 * are weighted against next-event estimation by the power heuristic (Veach 1997).
 * Derivations: docs/path-tracer.md. */
#include "render/integrator.h"

#include <string.h>

#include "core/error.h"
#include "core/stats.h"
#include "render/blasi.h"
#include "render/stam.h"
#include "surface/surfaces.h"

bool integrator_from_name(const char *name, integrator_kind *out)
{
    if (strcmp(name, "path") == 0)
        *out = INTEGRATOR_PATH;
    else if (strcmp(name, "single") == 0)
        *out = INTEGRATOR_SINGLE;
    else if (strcmp(name, "blasi") == 0)
        *out = INTEGRATOR_BLASI;
    else if (strcmp(name, "stam") == 0)
        *out = INTEGRATOR_STAM;
    else
        return false;
    return true;
}

const char *integrator_names(void) { return "path, single, blasi, stam"; }

/* Offers the collision at t, with the media f->cur and the scattering weight w, to the
 * flight's one-element reservoir. */
static void flight_offer(flight *f, color w, double t)
{
    double a = col_avg(w);
    if (!(a > 0.0))
        return;
    f->A += a;
    /* the i-th candidate replaces the kept one with probability a / A, decided by the one
     * uniform u of the flight, rescaled to a fresh uniform after each decision */
    double pr = a / f->A;
    if (f->u < pr) {
        f->u /= pr;
        f->beta_s = col_scale(w, 1.0 / a);
        f->t = t;
        f->ms = f->cur;
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
    flight *f = user;
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
    flight_offer(f, col_scale(col_mul(beta_Tr, ms->sigma_s), inv_maj), e->t);
    for (int c = 0; c < BRUME_NSAMPLES; c++)
        f->Tr.c[c] *= 1.0 - (ms->sigma_a.c[c] + ms->sigma_s.c[c]) * inv_maj;
    return track_roulette(&f->Tr, f->g);
}

bool flight_run(flight *f, ray r, double tmax, double u)
{
    f->r = r;
    f->u = u;
    f->Tr = col(1.0);
    f->A = 0.0;
    track_collisions(f->s, r, tmax, f->g, false, flight_step, f, NULL);
    if (!(f->A > 0.0))
        return false;
    f->beta_s = col_scale(f->beta_s, f->A);
    return true;
}

bool path_roulette(color *beta, int depth, rng *g)
{
    double q = col_max(*beta);
    if (depth < 3 || q >= 0.25)
        return true;
    if (rng_next(g) >= q)
        return false;
    *beta = col_scale(*beta, 1.0 / q);
    return true;
}

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
 * q = min(1, 4 pi max_c(f)), i.e. always where the kernel is at least an isotropic phase
 * function's 1 / (4 pi), and its estimate divided by q. Returns q, or 0 when the ray is
 * not traced. */
static double nee_roulette(color f, rng *g)
{
    double q = 4.0 * PI * col_max(f);
    if (q >= 1.0)
        return 1.0;
    return rng_next(g) < q ? q : 0.0;
}

/* Next-event estimation at a vertex: every light, emissive surfaces and the background. */
static color direct_light(const brume_scene *s, const vertex *v, rng *g)
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
        double q = nee_roulette(f, g);
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
                double q = nee_roulette(f, g);
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
                double q = nee_roulette(f, g);
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
static color direct_light_counted(const brume_scene *s, const vertex *v, rng *g)
{
    stats_counters *sc = stats_tls;
    if (!sc)
        return direct_light(s, v, g);
    double t0 = stats_now();
    color Ld = direct_light(s, v, g);
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

color path_Li_alpha(const brume_scene *s, ray r, int max_depth, rng *g, bool *hit_surface)
{
    /* Dimensions (docs/sampling.md, "The path's dimensions"): scattering event `depth` takes
     * four fixed dimensions of the camera sample's sequence g from its current one on (the
     * flight's reservoir choice, the branch or phase-function choice, the direction), so
     * that a Sobol sampler stratifies the same decision in every sample of a pixel; the
     * numbers whose count varies (tentative collisions, shadow rays, roulettes, light
     * samples) come from a second sequence of the same sample. */
    const uint64_t dim0 = g->counter;
    rng gt = rng_make(g->key, 0x7472616b5f646d73ULL, 0);
    flight f;
    f.s = s;
    f.g = &gt;
    f.beta = col(1.0);
    f.L = col(0.0);
    double pdf_dir = 0.0; /* solid-angle pdf of the current direction; 0 for camera rays */
    if (hit_surface)
        *hit_surface = false;
    for (int depth = 0;; depth++) {
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
        bool scattered = flight_run(&f, r, on_surface ? sh.t : t_light, rng_next(g)) && depth < max_depth;
        if (sc)
            sc->t_tracking += stats_now() - t0;
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
            f.L = col_add(f.L, col_mul(f.beta, direct_light_counted(s, &v, &gt)));
            vec3 wi;
            g->counter = dim0 + 4 * (uint64_t)depth + 2;
            double u0 = rng_next(&gt), u1 = rng_next(g), u2 = rng_next(g);
            if (!material_sample(sh.mat, v.n, v3_neg(r.d), u0, u1, u2, &wi, &pdf_dir))
                break;
            f.beta = col_mul(f.beta, col_scale(vertex_f(&v, wi), 1.0 / pdf_dir));
            r = (ray){v.p, wi, r.time};
            if (!path_roulette(&f.beta, depth, &gt))
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
        f.L = col_add(f.L, col_mul(f.beta, direct_light_counted(s, &v, &gt)));
        if (depth + 1 >= max_depth && !s->has_indirect_sources)
            break; /* the last flight could only gather light from another event */
        double u1 = rng_next(g), u2 = rng_next(g); /* dimensions dim0 + 4 depth + 2, + 3 */
        vec3 wo = phase_sample(v.ph, r.d, u1, u2, &pdf_dir);
        /* phase sampling is exact (weight p / pdf = 1) for every phase function in brume */
        r = (ray){v.p, wo, r.time};
        if (!path_roulette(&f.beta, depth, &gt))
            break;
    }
    return f.L;
}

color path_Li(const brume_scene *s, ray r, int max_depth, rng *g) { return path_Li_alpha(s, r, max_depth, g, NULL); }

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
    case INTEGRATOR_SINGLE: return BRUME_OK;
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
    case INTEGRATOR_SINGLE: break;
    case INTEGRATOR_BLASI: blasi_finish(state); break;
    case INTEGRATOR_STAM: stam_finish(state); break;
    }
}

color integrator_Li(integrator_kind kind, const brume_scene *s, const void *state, ray r, rng *g,
                    bool *hit_surface)
{
    switch (kind) {
    case INTEGRATOR_PATH: return path_Li_alpha(s, r, s->settings.max_depth, g, hit_surface);
    case INTEGRATOR_SINGLE: return path_Li_alpha(s, r, 1, g, hit_surface);
    case INTEGRATOR_BLASI: return blasi_Li(s, state, r, g, hit_surface);
    case INTEGRATOR_STAM: return stam_Li(state, r, g, hit_surface);
    }
    return col(0.0);
}

color integrator_transmittance(integrator_kind kind, const brume_scene *s, const void *state, ray r, rng *g)
{
    switch (kind) {
    case INTEGRATOR_PATH:
    case INTEGRATOR_SINGLE: return track_transmittance(s, r, INFINITY, g);
    case INTEGRATOR_BLASI: return blasi_transmittance(s, state, r); /* its voxels, exact: no tracking */
    case INTEGRATOR_STAM: return stam_transmittance(state, r.o, r.d, INFINITY);
    }
    return col(1.0);
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
    first_walk *w = user;
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
