/* blasi_view.c - the second pass of Blasi's method (1993, Section 4): a view ray gathers
 * each voxel's source through the voxels it crosses (blasi_Li), and the transmittance
 * behind a pixel's alpha (blasi_transmittance).
 *
 * Second pass. Along a view ray each voxel crossed over length delta adds
 * A S_V (1 - exp(-kappa delta)) / kappa (the exact integral over the voxel; S_V delta for
 * thin voxels) and scales A by exp(-kappa delta), kappa = sigma_a rho (paper) or
 * (sigma_a + sigma_s) rho (physical). Below `threshold` the ray stops; otherwise the
 * background, a light or a lit surface is added, attenuated by A. */
#include <math.h>

#include "render/blasi_state.h"
#include "render/blasi_walk.h"
#include "surface/surfaces.h"

/* exp(-kappa delta) per channel over [0, tmax] along r: the view attenuation of a segment. */
static color view_attenuation(const blasi_state *st, ray r, double tmax)
{
    color A = col(1.0);
    walk wk;
    piece pc;
    walk_begin(&wk, st, r, tmax);
    while (walk_next(&wk, st, &pc)) {
        piece_density(st, &pc, r, false);
        double dl = pc.t1 - pc.t0;
        for (int i = 0; i < pc.n; i++) {
            double rho = pc.rho[i];
            for (int c = 0; c < 3; c++)
                A.c[c] *= exp(-st->m[pc.m[i]].kappa.c[c] * rho * dl);
        }
    }
    return A;
}

/* The extinction optical depth of the last camera ray blasi_Li walked to its end, per
 * thread: the render asks for the transmittance of the same ray right after (the pixel's
 * alpha), and gets the same sum without a second walk. */
typedef struct tau_cache {
    const blasi_state *st;
    vec3 o, d;
    color tau;
} tau_cache;
static _Thread_local tau_cache last_tau;

static inline bool v3_equal(vec3 a, vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

/* Radiance leaving a surface towards -r.d: emission and direct light from every light,
 * through the media with the view attenuation (the paper has no surfaces; docs/blasi.md). */
static color shade_surface(const brume_scene *s, const blasi_state *st, ray r, const surface_hit *h, rng *g)
{
    vec3 wo = v3_neg(r.d);
    color L = surface_emission(h, wo);
    if (material_is_black(h->mat))
        return L;
    vec3 n = v3_dot(h->ng, r.d) < 0.0 ? h->ns : v3_neg(h->ns); /* the shading normal, on r's side */
    vec3 p = surface_offset(h, n);
    for (int i = 0; i < s->nlights; i++) {
        light_sample ls;
        double u1 = rng_next(g), u2 = rng_next(g);
        if (!light_sample_at(&s->lights[i], p, u1, u2, &ls) || !(ls.pdf > 0.0))
            continue;
        double cosn = v3_dot(ls.wi, n);
        if (cosn <= 0.0 || surfaces_occluded(s->surf, p, ls.wi, 0.0, ls.dist * (1.0 - 1e-7), r.time))
            continue;
        color f = col_scale(material_eval(h->mat, n, wo, ls.wi), cosn / ls.pdf);
        L = col_add(L, col_mul(col_mul(ls.Li, f), view_attenuation(st, (ray){p, ls.wi, r.time}, ls.dist)));
    }
    return L;
}

/* What a view ray has gathered so far: radiance L, view attenuation A, and the extinction
 * optical depth tau_t (the transmittance behind the pixel's alpha). */
typedef struct view_sums {
    color L, A, tau_t;
} view_sums;

/* One voxel of one medium crossed over length dl with density rho and stored source sv
 * along it (the second pass's loop body): its source, attenuated by A and integrated over
 * the voxel, and A attenuated. False when A fell under the threshold ("While A >
 * THRESHOLD"). */
static inline __attribute__((always_inline)) bool view_voxel(const blasi_state *st, const blasi_medium *bm, double rho,
                                                             color sv, double dl, view_sums *s)
{
    color S, kap;
#pragma GCC unroll 3
    for (int c = 0; c < BRUME_NSAMPLES; c++) {
        s->tau_t.c[c] += bm->sigma_t.c[c] * (rho * dl); /* as blasi_transmittance sums it */
        S.c[c] = sv.c[c] + bm->emit.c[c] * rho;
        kap.c[c] = bm->kappa.c[c] * rho;
    }
    if (st->gather_printed) { /* Blasi's second pass as printed: "L_P = L_P + A L_V", then attenuate */
        s->L = col_add(s->L, col_scale(col_mul(s->A, S), bm->chord));
#pragma GCC unroll 3
        for (int c = 0; c < BRUME_NSAMPLES; c++)
            s->A.c[c] *= exp(-kap.c[c] * dl);
        return col_max(s->A) > st->threshold;
    }
    if (kap.c[0] == 0.0 && kap.c[1] == 0.0 && kap.c[2] == 0.0) {
        if (!col_is_black(S)) /* a source without attenuation (e.g. alpha = 0, paper variant) */
            s->L = col_add(s->L, col_scale(col_mul(s->A, S), dl));
        return true;
    }
    bool grey = kap.c[0] == kap.c[1] && kap.c[1] == kap.c[2];
    double T = 0.0, f = 0.0;
#pragma GCC unroll 3
    for (int c = 0; c < BRUME_NSAMPLES; c++) {
        if (c == 0 || !grey) /* the integral of exp(-kappa s) over the voxel is dl f */
            voxel_exp(kap.c[c] * dl, &T, &f);
        s->L.c[c] += s->A.c[c] * S.c[c] * dl * f;
        s->A.c[c] *= T;
    }
    return col_max(s->A) > st->threshold;
}

/* The view walk over [0, t_end) through one small grid (one medium, no block skipping:
 * the usual case). The same sums as view_walk, with the walk's state in locals the loop
 * keeps in registers; for a grey medium (kappa and sigma_t the same in every channel) A
 * and tau_t are one number each, as all their channels are equal. False when the
 * threshold stopped the ray. */
static inline __attribute__((always_inline)) bool view_walk_one_as(const blasi_state *st, ray r, double t_end,
                                                                    view_sums *out, bool grey, bool emits)
{
    const blasi_medium *bm = &st->m[0];
    grid_dda g0;
    if (!walk_begin_one(bm, r, t_end, &g0, true))
        return true;
    grid_dda g = g0; /* never escapes: the compiler keeps it in registers */
    const float *rho = st->rho;
    const size_t nx = (size_t)bm->n[0], ny = (size_t)bm->n[1];
    grid_dda_step c;
    bool on = true;
    if (!grey) {
        view_sums s = *out;
        while (grid_dda_next(&g, &c)) {
            size_t v = (size_t)c.i + nx * ((size_t)c.j + ny * (size_t)c.k);
            if (rho[v] == 0.0f) /* empty: no density, no source */
                continue;
            const float *sv = st->S + 3 * v;
            if (!(on = view_voxel(st, bm, (double)rho[v], col_rgb(sv[0], sv[1], sv[2]), c.t1 - c.t0, &s)))
                break;
        }
        *out = s;
        return on;
    }
    /* grey: view_voxel with A and tau_t one number each, and without its branches: an empty
     * voxel (rho = 0, S = 0: blasi_prepare keeps no source there) adds exactly 0 to L and
     * tau_t and multiplies A by exactly 1 (voxel_exp(0) gives T = f = 1), as does the
     * attenuation-free case of view_voxel with f = 1, so the sums are the same bit for bit,
     * without the mispredicted branch on each voxel's emptiness */
    const double kappa = bm->kappa.c[0], sigma_t = bm->sigma_t.c[0], threshold = st->threshold;
    const color emit = bm->emit;
    double A = out->A.c[0], tau_t = out->tau_t.c[0];
    color L = out->L;
    while (grid_dda_next(&g, &c)) {
        size_t v = (size_t)c.i + nx * ((size_t)c.j + ny * (size_t)c.k);
        const double rh = (double)rho[v], dl = c.t1 - c.t0, kap = kappa * rh;
        const float *sv = st->S + 3 * v;
        color S; /* without emission, the stored source alone (adding 0 changes no sum) */
#pragma GCC unroll 3
        for (int k = 0; k < BRUME_NSAMPLES; k++)
            S.c[k] = emits ? (double)sv[k] + emit.c[k] * rh : (double)sv[k];
        tau_t += sigma_t * (rh * dl);
        double T, f;
        voxel_exp(kap * dl, &T, &f);
#pragma GCC unroll 3
        for (int k = 0; k < BRUME_NSAMPLES; k++)
            L.c[k] += A * S.c[k] * dl * f;
        A *= T;
        if (!(A > threshold)) {
            on = false;
            break;
        }
    }
    out->L = L;
    out->A = col(A);
    out->tau_t = col(tau_t);
    return on;
}

static bool view_walk_one(const blasi_state *st, ray r, double t_end, view_sums *out)
{
    const blasi_medium *bm = &st->m[0];
    if (bm->view_grey && !st->gather_printed && col_is_grey(out->A) && col_is_grey(out->tau_t))
        return bm->emits ? view_walk_one_as(st, r, t_end, out, true, true)
                         : view_walk_one_as(st, r, t_end, out, true, false);
    return view_walk_one_as(st, r, t_end, out, false, true);
}

/* The view walk over [0, t_end) through any media: each piece's voxels summed. */
static bool view_walk(const blasi_state *st, ray r, double t_end, view_sums *out)
{
    walk wk;
    piece pc;
    walk_begin(&wk, st, r, t_end);
    while (walk_next(&wk, st, &pc)) {
        piece_density(st, &pc, r, true);
        double dl = pc.t1 - pc.t0;
        if (pc.n == 1) {
            if (!view_voxel(st, &st->m[pc.m[0]], pc.rho[0], pc.S[0], dl, out))
                return false;
            continue;
        }
        color S = col(0.0), kap = col(0.0);
        for (int i = 0; i < pc.n; i++) {
            const blasi_medium *bm = &st->m[pc.m[i]];
            double rho = pc.rho[i];
            out->tau_t = col_madd(out->tau_t, bm->sigma_t, rho * dl);
            for (int c = 0; c < 3; c++) {
                S.c[c] += pc.S[i].c[c] + bm->emit.c[c] * rho;
                kap.c[c] += bm->kappa.c[c] * rho;
            }
        }
        if (kap.c[0] == 0.0 && kap.c[1] == 0.0 && kap.c[2] == 0.0) {
            if (!col_is_black(S))
                out->L = col_add(out->L, col_scale(col_mul(out->A, S), dl));
            continue;
        }
        bool grey = kap.c[0] == kap.c[1] && kap.c[1] == kap.c[2];
        double T = 0.0, f = 0.0;
        for (int c = 0; c < 3; c++) {
            if (c == 0 || !grey)
                voxel_exp(kap.c[c] * dl, &T, &f);
            out->L.c[c] += out->A.c[c] * S.c[c] * dl * f;
            out->A.c[c] *= T;
        }
        if (!(col_max(out->A) > st->threshold))
            return false;
    }
    return true;
}

color blasi_Li(const brume_scene *s, const blasi_state *st, ray r, rng *g, bool *hit_surface)
{
    last_tau.st = NULL; /* valid again only if this walk reaches the end of the ray */
    if (hit_surface)
        *hit_surface = false;
    /* what ends the walk: a surface, an area light, or nothing (the background) */
    double t_end = INFINITY;
    int hit_light = -1;
    color Le_light = col(0.0);
    for (int i = 0; st->area_lights && i < s->nlights; i++) {
        const light *l = &s->lights[i];
        double t, pdf;
        color c;
        if ((l->kind == LIGHT_SPHERE || l->kind == LIGHT_DISK) && light_hit(l, r.o, r.d, &t, &c, &pdf) && t < t_end) {
            t_end = t;
            hit_light = i;
            Le_light = c;
        }
    }
    surface_hit h;
    bool on_surface = s->surf && surfaces_intersect(s->surf, r, 0.0, t_end, &h);
    if (on_surface)
        t_end = h.t;
    if (hit_surface)
        *hit_surface = on_surface;

    color L = col(0.0), A = col(1.0), tau_t = col(0.0);
    const bool one = st->nm == 1 && !st->m[0].skip && !st->m[0].trilinear;
    /* most view rays miss the non-empty voxels of one grid: those are told here, without a
     * walk or its set-up */
    if (st->nm > 0 && !(one && line_misses_box(st->m[0].occ_c, st->m[0].occ_e, r.o, r.d))) {
        view_sums v = {L, A, tau_t};
        bool on = one ? view_walk_one(st, r, t_end, &v) : view_walk(st, r, t_end, &v);
        L = v.L;
        A = v.A;
        tau_t = v.tau_t;
        if (!on)
            return L;
    }
    if (isinf(t_end)) /* the whole ray walked: its transmittance is known */
        last_tau = (tau_cache){st, r.o, r.d, tau_t};
    if (on_surface)
        return col_add(L, col_mul(A, shade_surface(s, st, r, &h, g)));
    if (hit_light >= 0)
        return col_add(L, col_mul(A, Le_light));
    /* "add the attenuated radiance of the background", and any sun disk seen directly */
    color Lb = background_eval(&s->bg, r.d);
    for (int i = 0; st->sun_disks && i < s->nlights; i++) {
        const light *l = &s->lights[i];
        double t, pdf;
        color c;
        if (l->kind == LIGHT_DISTANT && light_hit(l, r.o, r.d, &t, &c, &pdf))
            Lb = col_add(Lb, c);
    }
    return col_add(L, col_mul(A, Lb));
}

color blasi_transmittance(const brume_scene *s, const blasi_state *st, ray r)
{
    (void)s;
    color tau = col(0.0);
    if (last_tau.st == st && v3_equal(last_tau.o, r.o) && v3_equal(last_tau.d, r.d)) {
        tau = last_tau.tau; /* the render asks right after blasi_Li walked this ray */
        goto done;
    }
    walk wk;
    piece pc;
    walk_begin(&wk, st, r, INFINITY);
    while (walk_next(&wk, st, &pc)) {
        piece_density(st, &pc, r, false);
        double dl = pc.t1 - pc.t0;
        for (int i = 0; i < pc.n; i++)
            tau = col_madd(tau, st->m[pc.m[i]].sigma_t, pc.rho[i] * dl);
    }
done:
    if (tau.c[0] == tau.c[1] && tau.c[1] == tau.c[2]) /* grey; 0 for the rays that miss the media */
        return col(tau.c[0] == 0.0 ? 1.0 : exp(-tau.c[0]));
    return col_rgb(exp(-tau.c[0]), exp(-tau.c[1]), exp(-tau.c[2]));
}
