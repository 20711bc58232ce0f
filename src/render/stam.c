/* stam.c - the stochastic renderer of Stam 1994 (Section 6.3) with its average source
 * function (Section 6.2) and a ray tracer for what lies behind the media (stam.h).
 * Derivations and measurements: docs/stam.md. */
#include "render/stam.h"

#include <stdlib.h>

#include "core/error.h"
#include "core/pool.h"
#include "core/stats.h"
#include "density/blobs.h"
#include "render/stam_stats.h"
#include "surface/surfaces.h"

/* Light-cache lattice points over all lights, at most (docs/scene-format.md#limits). */
#define STAM_MAX_CACHE_POINTS 6.7e7
#define STAM_MAX_STEPS 256 /* keeps the per-ray tables (16 media x 257 doubles) on the stack */

/* One blob medium: Stam's kappa_t, Omega and E per channel. */
typedef struct stam_medium {
    const blob_field *f;
    color kappa;   /* sigma_a + sigma_s per unit density */
    color albedo;  /* Omega = sigma_s / kappa */
    color emit;    /* (1 - Omega) E = sigma_a Le / kappa: the emission part of J */
    const phase *ph;
    bool scatters;
    vec3 q_shift;  /* Q is read at x - q_shift: the perturbation drifts with the blobs */
} stam_medium;

/* Transparency from the nodes of a grid to one delta light (point, spot, sharp sun). */
typedef struct light_cache {
    int n[3];     /* nodes per axis */
    vec3 lo, cs;  /* node (0, 0, 0) and the spacing */
    float *tau;   /* 3 floats per node, x fastest */
} light_cache;

typedef struct stam_state {
    const brume_scene *s;
    randfield *q;
    stam_medium med[SCENE_MAX_MEDIA];
    int nmed;
    double eps, eta, alpha;
    bool paper;          /* stam.variant = paper: Eq. 12-13 as printed, J-bar's shadows from the mean */
    bool joint;          /* stam.overlap = joint: a ray's perturbation scaled to the joint variance */
    double sigma_paper;  /* paper: K_Q(0) sqrt(eps), the factor of sqrt(I_F) Q */
    int steps;
    bool any_scatter;
    light_cache *cache; /* one per light (n = 0 when the light is not cached), or NULL */
} stam_state;

/* ---- transparency: Eq. 13 summed over the blobs of every medium ----------------------------- */

/* A blob met by a ray, kept for the second pass over the same ray. */
typedef struct blob_hit {
    int i;
    double u, d2;
} blob_hit;

/* Camera rays remember up to this many blobs per medium; beyond, the second pass walks the
 * hierarchy again. */
#define STAM_HIT_BUFFER 256

/* stam.overlap = joint: a perturbed blob met by a ray, kept until the ray's blobs are all
 * known. Beyond STAM_JOINT_MAX blobs per medium on one ray, the others are perturbed
 * independently (their covariances with the rest are left out; docs/stam.md). */
#define STAM_JOINT_MAX 512
typedef struct joint_hit {
    blob_ray br;
    double sigma; /* sqrt(Var T_i) */
    double q;     /* Q(x_ui) */
    double uc;    /* x_ui's parameter on the segment */
} joint_hit;

typedef struct tau_walk {
    const stam_state *st;
    const stam_medium *m;
    vec3 o, d;
    double tmax;
    bool mean_only; /* the mean density's optical depth (paper variant's J-bar shadows) */
    double T;
    double umin, umax; /* span of the chords inside [0, tmax] */
    blob_hit *hits;    /* NULL, or room for STAM_HIT_BUFFER */
    int nhits;         /* blobs met (may exceed the buffer) */
    joint_hit *joint;  /* stam.overlap = joint: room for STAM_JOINT_MAX, else NULL */
    int njoint;
} tau_walk;

static void tau_visit(int i, double u, double d2, void *user)
{
    tau_walk *w = user;
    const stam_state *st = w->st;
    blob_ray br = blob_ray_make(w->m->f, i, u, d2);
    double T = blob_T_mean(&br, 0.0, w->tmax);
    double lo = u - br.half, hi = u + br.half;
    lo = lo > 0.0 ? lo : 0.0;
    hi = hi < w->tmax ? hi : w->tmax;
    w->umin = lo < w->umin ? lo : w->umin;
    w->umax = hi > w->umax ? hi : w->umax;
    if (w->hits && w->nhits < STAM_HIT_BUFFER)
        w->hits[w->nhits] = (blob_hit){i, u, d2};
    w->nhits++;
    if (st->eps > 0.0 && !w->mean_only) {
        /* F_eta(mean) = mean when the blob's peak along the ray is below eta */
        double I = br.peak > st->eta ? blob_T_clamped(&br, st->eta, 0.0, w->tmax) : T;
        double uc = u < 0.0 ? 0.0 : (u > w->tmax ? w->tmax : u); /* x_ui on the segment */
        vec3 x = v3_sub(v3_madd(w->o, w->d, uc), w->m->q_shift);
        /* Eq. 13; sigma_T from the repaired variance, or from Eq. 12-13 as printed */
        double sigma = st->paper ? st->sigma_paper * sqrt(I) : sqrt(blob_T_var_scale(st->eps, st->alpha, br.h) * I);
        double q = randfield_eval(st->q, x);
        if (w->joint && w->njoint < STAM_JOINT_MAX)
            w->joint[w->njoint++] = (joint_hit){br, sigma, q, uc};
        else
            T += sigma * q;
    }
    w->T += T;
}

/* stam.overlap = joint: the ray's perturbation sum_i sigma_i Q(x_ui), scaled so that its
 * variance is the joint variance of the summed depth, sum_ij Cov(T_i, T_j) (blob_T_cov),
 * instead of the variance of the samples themselves, sum_ij sigma_i sigma_j K_Q(x_ui - x_uj)
 * (the points lie on the ray: |x_ui - x_uj| = |uc_i - uc_j|). docs/stam.md. */
static double joint_perturbation(const stam_state *st, const tau_walk *w)
{
    double p = 0.0, v_joint = 0.0, v_samples = 0.0, cut = 6.0 * st->alpha, inv2a2 = 0.5 / (st->alpha * st->alpha);
    for (int i = 0; i < w->njoint; i++) {
        const joint_hit *a = &w->joint[i];
        p += a->sigma * a->q;
        v_joint += a->sigma * a->sigma;
        v_samples += a->sigma * a->sigma;
        double alo = a->br.u - a->br.half, ahi = a->br.u + a->br.half;
        for (int j = i + 1; j < w->njoint; j++) {
            const joint_hit *b = &w->joint[j];
            double dq = a->uc - b->uc;
            if (fabs(dq) < cut)
                v_samples += 2.0 * a->sigma * b->sigma * exp(-dq * dq * inv2a2);
            if (b->br.u - b->br.half < ahi && b->br.u + b->br.half > alo)
                v_joint += 2.0 * blob_T_cov(&a->br, &b->br, st->eps, st->eta, st->alpha, 0.0, w->tmax);
        }
    }
    return v_samples > 0.0 ? p * sqrt(v_joint / v_samples) : p;
}

/* One medium's realized optical depth over w's segment [0, tmax] (Eq. 13) into w->T. */
static void tau_walk_run(tau_walk *w)
{
    blob_field_query_ray(w->m->f, w->o, w->d, 0.0, w->tmax, tau_visit, w);
    if (w->njoint)
        w->T += joint_perturbation(w->st, w);
}

/* exp(-sum_m kappa_m max(0, T_m)) over (0, tmax), media only; of the mean density when
 * mean_only. */
static color media_tau(const stam_state *st, vec3 o, vec3 d, double tmax, bool mean_only)
{
    color depth = col(0.0);
    joint_hit joint[STAM_JOINT_MAX]; /* untouched unless stam.overlap = joint */
    for (int m = 0; m < st->nmed; m++) {
        tau_walk w = {st, &st->med[m], o, d, tmax, mean_only, 0.0, INFINITY, -INFINITY, NULL, 0,
                      st->joint && !mean_only ? joint : NULL, 0};
        tau_walk_run(&w);
        if (w.T > 0.0)
            depth = col_madd(depth, st->med[m].kappa, w.T);
    }
    return col_exp(col_scale(depth, -1.0));
}

/* The camera ray's realized transparency, remembered by stam_Li for the image's alpha (which
 * render.c asks for right after, on the same thread, through stam_transmittance): a pure
 * function of the ray, so reusing it cannot change the image. */
typedef struct tau_memo {
    const void *state;
    vec3 o, d;
    color tau;
    bool valid;
} tau_memo;
static _Thread_local tau_memo last_camera_ray;

color stam_transmittance(const void *state, vec3 o, vec3 d, double tmax)
{
    const stam_state *st = state;
    const tau_memo *mm = &last_camera_ray;
    if (mm->valid && mm->state == state && isinf(tmax) && mm->o.x == o.x && mm->o.y == o.y && mm->o.z == o.z && mm->d.x == d.x &&
        mm->d.y == d.y && mm->d.z == d.z)
        return mm->tau;
    if (st->s->surf && surfaces_occluded(st->s->surf, o, d, 0.0, tmax * (1.0 - 1e-7), st->s->time))
        return col(0.0);
    return media_tau(st, o, d, tmax, false);
}

/* The transparency that lights J-bar (Eq. 8): the realized one (corrected), or the mean
 * density's, as Section 6.2 says J-bar depends on the mean only (paper). */
static color source_transmittance(const stam_state *st, vec3 o, vec3 d, double tmax)
{
    if (!st->paper)
        return stam_transmittance(st, o, d, tmax);
    if (st->s->surf && surfaces_occluded(st->s->surf, o, d, 0.0, tmax * (1.0 - 1e-7), st->s->time))
        return col(0.0);
    return media_tau(st, o, d, tmax, true);
}

/* ---- light transparency cache ------------------------------------------------------------- */

static bool light_cacheable(const light *l)
{
    return l->kind == LIGHT_POINT || l->kind == LIGHT_SPOT || (l->kind == LIGHT_DISTANT && l->angular_radius == 0.0);
}

typedef struct cache_job {
    const stam_state *st;
    const light *l;
    light_cache *c;
} cache_job;

static void cache_slice(size_t task, int thread, void *user)
{
    (void)thread;
    cache_job *job = user;
    light_cache *c = job->c;
    int k = (int)task;
    for (int j = 0; j < c->n[1]; j++)
        for (int i = 0; i < c->n[0]; i++) {
            vec3 p = v3(c->lo.x + i * c->cs.x, c->lo.y + j * c->cs.y, c->lo.z + k * c->cs.z);
            light_sample ls;
            color tau = col(0.0);
            if (light_sample_at(job->l, p, 0.5, 0.5, &ls))
                tau = source_transmittance(job->st, p, ls.wi, ls.dist);
            float *out = c->tau + 3 * ((size_t)i + (size_t)c->n[0] * ((size_t)j + (size_t)c->n[1] * (size_t)k));
            for (int ch = 0; ch < 3; ch++)
                out[ch] = (float)tau.c[ch];
        }
}

static color cache_lookup(const light_cache *c, vec3 p)
{
    double x = (p.x - c->lo.x) / c->cs.x, y = (p.y - c->lo.y) / c->cs.y, z = (p.z - c->lo.z) / c->cs.z;
    x = fmin(fmax(x, 0.0), c->n[0] - 1.000001);
    y = fmin(fmax(y, 0.0), c->n[1] - 1.000001);
    z = fmin(fmax(z, 0.0), c->n[2] - 1.000001);
    int i = (int)x, j = (int)y, k = (int)z;
    double fx = x - i, fy = y - j, fz = z - k;
    color r = col(0.0);
    for (int corner = 0; corner < 8; corner++) {
        int di = corner & 1, dj = (corner >> 1) & 1, dk = corner >> 2;
        double w = (di ? fx : 1 - fx) * (dj ? fy : 1 - fy) * (dk ? fz : 1 - fz);
        const float *v =
            c->tau + 3 * ((size_t)(i + di) + (size_t)c->n[0] * ((size_t)(j + dj) + (size_t)c->n[1] * (size_t)(k + dk)));
        for (int ch = 0; ch < 3; ch++)
            r.c[ch] += w * (double)v[ch];
    }
    return r;
}

/* Caches every delta light over the union of the scattering media's bounds. */
static brume_status build_caches(stam_state *st, int cells)
{
    const brume_scene *s = st->s;
    box3 b = box3_empty();
    for (int m = 0; m < st->nmed; m++)
        if (st->med[m].scatters) {
            b.lo = v3_min(b.lo, st->med[m].f->bounds.lo);
            b.hi = v3_max(b.hi, st->med[m].f->bounds.hi);
        }
    st->cache = calloc((size_t)s->nlights, sizeof *st->cache);
    if (!st->cache)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: stam: out of memory", s->source);
    vec3 ext = v3_sub(b.hi, b.lo);
    double longest = fmax(ext.x, fmax(ext.y, ext.z));
    /* memory and work up front: every cached light's lattice, against render.max_memory_mb
     * and STAM_MAX_CACHE_POINTS (each point integrates the depth towards its light) */
    double points = 0.0;
    for (int l = 0; l < s->nlights; l++)
        if (light_cacheable(&s->lights[l])) {
            double p = 1.0;
            for (int a = 0; a < 3; a++)
                p *= fmax(2.0, ceil(cells * v3_get(ext, a) / longest) + 1.0);
            points += p;
        }
    if (points * 3 * sizeof(double) > (double)s->max_memory || points > STAM_MAX_CACHE_POINTS)
        return err_set(BRUME_ERROR_RANGE,
                       "%s: stam.light_grid: %d cells for %d lights are %.3g points (%.0f MiB), more than the limit of "
                       "%.3g points within render.max_memory_mb %.0f",
                       s->source, cells, s->nlights, points, points * 3 * sizeof(double) / 1048576.0,
                       STAM_MAX_CACHE_POINTS, (double)s->max_memory / 1048576.0);
    /* the work (render.max_work): each point integrates about `cells` steps */
    if (points * (cells + 1.0) > s->max_work)
        return err_set(BRUME_ERROR_RANGE,
                       "%s: stam.light_grid: %.3g points of about %d steps each are %.3g units of work, over "
                       "render.max_work (%.3g): lower stam.light_grid (or raise render.max_work)",
                       s->source, points, cells, points * (cells + 1.0), s->max_work);
    for (int l = 0; l < s->nlights; l++) {
        if (!light_cacheable(&s->lights[l]))
            continue;
        light_cache *c = &st->cache[l];
        for (int a = 0; a < 3; a++)
            c->n[a] = (int)fmax(2.0, ceil(cells * v3_get(ext, a) / longest) + 1.0);
        c->lo = b.lo;
        c->cs = v3(ext.x / (c->n[0] - 1), ext.y / (c->n[1] - 1), ext.z / (c->n[2] - 1));
        c->tau = malloc(3 * (size_t)c->n[0] * (size_t)c->n[1] * (size_t)c->n[2] * sizeof *c->tau);
        if (!c->tau)
            return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: stam: out of memory for the light cache", s->source);
        cache_job job = {st, &s->lights[l], c};
        pool_run(s->settings.threads, (size_t)c->n[2], cache_slice, &job);
    }
    return BRUME_OK;
}

/* ---- prepare and finish ------------------------------------------------------------------- */

static const char *kind_name(density_kind k)
{
    switch (k) {
    case DENSITY_GRID: return "dense voxel grid";
    case DENSITY_NANOVDB: return "NanoVDB grid";
    case DENSITY_BLOBS: return "blob field";
    case DENSITY_PBRT_CLOUD: return "pbrt cloud";
    }
    return "density";
}

brume_status stam_prepare(const brume_scene *s, void **state)
{
    *state = NULL;
    for (int m = 0; m < s->nmedia; m++)
        if (!density_get_blobs(s->media[m].rho))
            return err_set(BRUME_ERROR_UNSUPPORTED,
                           "%s: media[%d]%s%s: method stam renders blob fields only (density type \"blobs\"), this "
                           "medium is a %s: render it with --method path or single",
                           s->source, m, s->media[m].name[0] ? " " : "", s->media[m].name,
                           kind_name(density_get_kind(s->media[m].rho)));
        else if (s->media[m].moved) /* a velocity and an open shutter (medium.h) */
            return err_set(BRUME_ERROR_UNSUPPORTED,
                           "%s: media[%d].velocity: method stam does not blur by a velocity grid (blobs move by "
                           "their own velocity): use --method path or single, or a closed shutter",
                           s->source, m);
    stam_state *st = calloc(1, sizeof *st);
    if (!st)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: stam: out of memory", s->source);
    stam_stats_init();
    const stam_params *p = scene_options(s, METHOD_OPTIONS_STAM);
    st->s = s;
    st->eps = p->eps;
    st->eta = p->eta;
    st->alpha = p->alpha;
    st->paper = p->paper;
    st->joint = p->overlap_joint;
    if (st->joint && st->paper) {
        free(st);
        return err_set(BRUME_ERROR_INVALID_ARGUMENT,
                       "%s: stam.overlap: joint needs stam.variant = corrected (Eq. 12 as printed has no covariances)",
                       s->source);
    }
    st->sigma_paper = blob_T_sigma_paper_scale(p->eps, p->alpha);
    st->steps = p->steps < STAM_MAX_STEPS ? p->steps : STAM_MAX_STEPS;
    for (int m = 0; m < s->nmedia; m++) {
        const medium *md = &s->media[m];
        stam_medium *sm = &st->med[st->nmed++];
        sm->f = density_get_blobs(md->rho);
        sm->kappa = col_add(md->sigma_a, md->sigma_s);
        sm->albedo = col_div(md->sigma_s, sm->kappa);
        sm->emit = col_mul(col_div(md->sigma_a, sm->kappa), md->Le);
        sm->ph = md->ph;
        sm->scatters = !col_is_black(md->sigma_s);
        sm->q_shift = v3_scale(sm->f->velocity, sm->f->time);
        st->any_scatter |= sm->scatters;
    }
    if (st->eps > 0.0) {
        if (!(st->q = stam_scene_randfield(s))) {
            stam_finish(st);
            return err_prefix("%s: stam", s->source);
        }
    }
    if (st->any_scatter && p->light_grid > 0 && s->nlights > 0 && build_caches(st, p->light_grid) != BRUME_OK) {
        stam_finish(st);
        return err_status();
    }
    *state = st;
    return BRUME_OK;
}

void stam_finish(void *state)
{
    stam_state *st = state;
    if (!st)
        return;
    if (st->cache)
        for (int l = 0; l < st->s->nlights; l++)
            free(st->cache[l].tau);
    free(st->cache);
    randfield_release(st->q);
    free(st);
}

/* ---- the ray tracer behind the media: I_b ------------------------------------------------- */

/* Direct light on a surface point, shadow rays through the media by transparency only. */
static color shade_surface(const stam_state *st, const surface_hit *sh, vec3 d, rng *g)
{
    const brume_scene *s = st->s;
    vec3 wo = v3_neg(d);
    vec3 n = v3_dot(sh->ng, d) < 0.0 ? sh->ns : v3_neg(sh->ns); /* the shading normal, on d's side */
    vec3 p = surface_offset(sh, n);
    color L = surface_emission(sh, wo);
    const material *m = sh->mat;
    if (material_is_black(m))
        return L;
    for (int i = 0; i < s->nlights; i++) {
        light_sample ls;
        double u1 = rng_next(g), u2 = rng_next(g);
        if (!light_sample_at(&s->lights[i], p, u1, u2, &ls) || !(ls.pdf > 0.0) || v3_dot(ls.wi, n) <= 0.0)
            continue;
        color f = col_scale(material_eval(m, n, wo, ls.wi), v3_dot(ls.wi, n) / ls.pdf);
        if (col_is_black(f))
            continue;
        L = col_add(L, col_mul(col_mul(f, ls.Li), stam_transmittance(st, p, ls.wi, ls.dist)));
    }
    if (surfaces_has_emitters(s->surf)) {
        vec3 wi;
        double dist, pdf;
        color Le;
        double u0 = rng_next(g), u1 = rng_next(g), u2 = rng_next(g);
        if (surfaces_sample_emitter(s->surf, p, s->time, u0, u1, u2, &wi, &dist, &Le, &pdf) && pdf > 0.0 &&
            v3_dot(wi, n) > 0.0) {
            color f = col_scale(material_eval(m, n, wo, wi), v3_dot(wi, n) / pdf);
            L = col_add(L, col_mul(col_mul(f, Le), stam_transmittance(st, p, wi, dist * (1.0 - 1e-5))));
        }
    }
    /* sky light: the background seen along the normal, unoccluded (a standard ambient term) */
    if (!background_is_black(&s->bg))
        L = col_add(L, col_mul(m->albedo, background_eval(&s->bg, n)));
    return L;
}

/* What the ray meets behind the media, and where: *b = its distance (INFINITY: nothing). */
static color behind(const stam_state *st, ray r, rng *g, double *b, bool *on_surface)
{
    const brume_scene *s = st->s;
    *b = INFINITY;
    *on_surface = false;
    int area = -1;
    color Le_area = col(0.0);
    for (int i = 0; i < s->nlights; i++) {
        const light *l = &s->lights[i];
        double t, pdf;
        color c;
        if ((l->kind == LIGHT_SPHERE || l->kind == LIGHT_DISK) && light_hit(l, r.o, r.d, &t, &c, &pdf) && t < *b) {
            *b = t;
            Le_area = c;
            area = i;
        }
    }
    surface_hit sh;
    if (s->surf && surfaces_intersect(s->surf, r, 0.0, *b, &sh)) {
        *b = sh.t;
        *on_surface = true;
        return shade_surface(st, &sh, r.d, g);
    }
    if (area >= 0)
        return Le_area;
    color L = background_eval(&s->bg, r.d);
    for (int i = 0; i < s->nlights; i++) {
        const light *l = &s->lights[i];
        double t, pdf;
        color c;
        if (l->kind == LIGHT_DISTANT && light_hit(l, r.o, r.d, &t, &c, &pdf))
            L = col_add(L, c);
    }
    return L;
}

/* ---- the average source function (Eq. 8) ---------------------------------------------------- */

/* Cumulative mean optical depth C[k] = integral of one medium's mean over [u_0, u_k] at the
 * step boundaries u_k = u0 + k du, k = 0..n. Each blob adds its erf integral at the
 * boundaries inside its chord and its whole chord (through the difference array D) beyond. */
typedef struct depth_walk {
    const blob_field *f;
    double u0, du, inv_du, b;
    int n;
    double *C, *D;
} depth_walk;

static void depth_visit(int i, double u, double d2, void *user)
{
    depth_walk *w = user;
    blob_ray br = blob_ray_make(w->f, i, u, d2);
    double lo = u - br.half, hi = u + br.half, end = w->u0 + w->n * w->du;
    lo = lo > w->u0 ? lo : w->u0;
    hi = hi < end ? hi : end;
    if (!(hi > lo))
        return;
    int k0 = (int)ceil((lo - w->u0) * w->inv_du), k1 = (int)floor((hi - w->u0) * w->inv_du);
    k0 = k0 < 0 ? 0 : k0;
    k1 = k1 > w->n ? w->n : k1;
    if (br.k) { /* a tabulated kernel: the integrals from its table (Section 6.1) */
        for (int k = k0; k <= k1; k++)
            w->C[k] += blob_T_mean(&br, lo, w->u0 + k * w->du);
        if (k1 + 1 <= w->n)
            w->D[k1 + 1] += blob_T_mean(&br, lo, hi);
        return;
    }
    double inv_h = 1.0 / br.h, scale = br.peak * br.h, base = stam_Phi((lo - u) * inv_h);
    for (int k = k0; k <= k1; k++)
        w->C[k] += scale * (stam_Phi((w->u0 + k * w->du - u) * inv_h) - base);
    if (k1 + 1 <= w->n)
        w->D[k1 + 1] += scale * (stam_Phi((hi - u) * inv_h) - base);
}

/* Light arriving at x from every light, transparency included, as (direction, radiance)
 * pairs weighted for the phase function: sum_l p(wi_l . d) E_l tau_l for one medium. */
typedef struct light_in {
    vec3 wi;
    color E; /* E_l tau_l / pdf */
} light_in;

static int gather_lights(const stam_state *st, vec3 x, rng *g, light_in *out, int cap)
{
    const brume_scene *s = st->s;
    int n = 0;
    for (int l = 0; l < s->nlights && n < cap; l++) {
        light_sample ls;
        double u1 = rng_next(g), u2 = rng_next(g);
        if (!light_sample_at(&s->lights[l], x, u1, u2, &ls) || !(ls.pdf > 0.0) || col_is_black(ls.Li))
            continue;
        color tau = st->cache && st->cache[l].n[0] ? cache_lookup(&st->cache[l], x)
                                                   : source_transmittance(st, x, ls.wi, ls.dist);
        out[n].wi = ls.wi;
        out[n].E = col_scale(col_mul(ls.Li, tau), 1.0 / ls.pdf);
        n++;
    }
    return n;
}

/* The source function gathers at most this many lights (scenes with more lights shade
 * surfaces with all of them but scatter only the first 64 inside the media). */
#define STAM_MAX_LIGHTS_PER_POINT 64

/* Eq. 13 along the camera ray up to b: the realized optical depth of all media, and the
 * span [*umin, *umax] of their blobs; the first media's blob hits are kept in hits (nhits[m]
 * is -1 when they did not fit) for the mean depths. */
static color camera_depth(const stam_state *st, ray r, double b, blob_hit (*hits)[STAM_HIT_BUFFER], int *nhits,
                          joint_hit *joint, double *umin, double *umax)
{
    color depth = col(0.0);
    for (int m = 0; m < st->nmed; m++) {
        const stam_medium *sm = &st->med[m];
        tau_walk w = {st, sm, r.o, r.d, b, false, 0.0, INFINITY, -INFINITY, m < 4 ? hits[m] : NULL, 0,
                      st->joint ? joint : NULL, 0};
        tau_walk_run(&w);
        nhits[m] = m < 4 && w.nhits <= STAM_HIT_BUFFER ? w.nhits : -1;
        if (stats_tls)
            stats_tls->stam_camera_blobs += (uint64_t)w.nhits;
        if (w.T > 0.0)
            depth = col_madd(depth, sm->kappa, w.T);
        *umin = fmin(*umin, w.umin);
        *umax = fmax(*umax, w.umax);
    }
    return depth;
}

/* Eq. 8 from the mean density: each medium's cumulative mean depths C[m][k] at the n + 1
 * step boundaries umin + k du. */
static void mean_depths(const stam_state *st, ray r, double b, double umin, double umax, int n,
                        blob_hit (*hits)[STAM_HIT_BUFFER], const int *nhits, double (*C)[STAM_MAX_STEPS + 1])
{
    double du = (umax - umin) / n;
    double D[STAM_MAX_STEPS + 2];
    for (int m = 0; m < st->nmed; m++) {
        for (int k = 0; k <= n + 1; k++)
            D[k] = 0.0;
        for (int k = 0; k <= n; k++)
            C[m][k] = 0.0;
        depth_walk w = {st->med[m].f, umin, du, 1.0 / du, b, n, C[m], D};
        if (nhits[m] >= 0)
            for (int h = 0; h < nhits[m]; h++)
                depth_visit(hits[m][h].i, hits[m][h].u, hits[m][h].d2, &w);
        else
            blob_field_query_ray(st->med[m].f, r.o, r.d, umin, umax, depth_visit, &w);
        double run = 0.0;
        for (int k = 0; k <= n; k++) {
            run += D[k];
            C[m][k] += run;
        }
    }
}

/* The n steps from umin: the sum num of each step's source J times its share of the
 * attenuation, tau_mean(u_k) (1 - exp(-dtau)), and the mean transmittance *tau_mean at the end. */
static color march(const stam_state *st, ray r, rng *g, double umin, double du, int n,
                   double (*C)[STAM_MAX_STEPS + 1], color *tau_mean)
{
    color num = col(0.0);
    *tau_mean = col(1.0);
    light_in lin[STAM_MAX_LIGHTS_PER_POINT];
    for (int k = 0; k < n; k++) {
        color dtau = col(0.0), src = col(0.0);
        bool any = false;
        int nl = -1;
        for (int m = 0; m < st->nmed; m++) {
            double dT = C[m][k + 1] - C[m][k];
            if (!(dT > 0.0))
                continue;
            const stam_medium *sm = &st->med[m];
            any = true;
            color kd = col_scale(sm->kappa, dT);
            dtau = col_add(dtau, kd);
            color J = sm->emit;
            if (sm->scatters) {
                color S = ((const stam_params *)scene_options(st->s, METHOD_OPTIONS_STAM))->ambient;
                if (nl < 0)
                    nl = gather_lights(st, ray_at(r, umin + (k + 0.5) * du), g, lin, STAM_MAX_LIGHTS_PER_POINT);
                for (int l = 0; l < nl; l++)
                    S = col_madd(S, lin[l].E, phase_eval(sm->ph, v3_dot(lin[l].wi, r.d)));
                J = col_add(J, col_mul(sm->albedo, S));
            }
            src = col_add(src, col_mul(kd, J));
        }
        if (!any)
            continue;
        for (int c = 0; c < BRUME_NSAMPLES; c++) {
            double a = 1.0 - exp(-dtau.c[c]);
            if (dtau.c[c] > 0.0)
                num.c[c] += tau_mean->c[c] * a * src.c[c] / dtau.c[c];
            tau_mean->c[c] *= 1.0 - a;
        }
    }
    return num;
}

color stam_Li(const void *state, ray r, rng *g, bool *hit_surface)
{
    const stam_state *st = state;
    double b;
    bool on_surface;
    color Ib = behind(st, r, g, &b, &on_surface);
    if (hit_surface)
        *hit_surface = on_surface;

    double umin = INFINITY, umax = -INFINITY;
    blob_hit hits[SCENE_MAX_MEDIA > 4 ? 4 : SCENE_MAX_MEDIA][STAM_HIT_BUFFER];
    int nhits[SCENE_MAX_MEDIA];
    joint_hit joint[STAM_JOINT_MAX]; /* untouched unless stam.overlap = joint */
    color depth = camera_depth(st, r, b, hits, nhits, joint, &umin, &umax);
    color tau = col_exp(col_scale(depth, -1.0));
    last_camera_ray = (tau_memo){st, r.o, r.d, tau, isinf(b)};
    if (!(umax > umin))
        return Ib;

    int n = st->steps;
    double C[SCENE_MAX_MEDIA][STAM_MAX_STEPS + 1];
    mean_depths(st, r, b, umin, umax, n, hits, nhits, C);
    color tau_mean;
    color num = march(st, r, g, umin, (umax - umin) / n, n, C, &tau_mean);
    /* J_avg = num / (1 - tau_mean(b)); I = tau I_b + (1 - tau) J_avg */
    color I;
    for (int c = 0; c < BRUME_NSAMPLES; c++) {
        double opacity = 1.0 - tau_mean.c[c];
        double Javg = opacity > 1e-12 ? num.c[c] / opacity : 0.0;
        I.c[c] = tau.c[c] * Ib.c[c] + (1.0 - tau.c[c]) * Javg;
    }
    return I;
}
