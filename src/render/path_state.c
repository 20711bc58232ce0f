/* path_state.c - what `path` and `single` prepare once per scene (path_prepare): the
 * camera rays' cull, the sun-lobe tables and the sun roulette's predicted optical depths
 * (docs/path-tracer.md, "Sun-lobe sampling", "Sun rays deep in a cloud"), and their copy
 * for the GPU. */
#include "render/path_impl.h"

#include <stdlib.h>
#include <string.h>

#include "core/arena.h"
#include "core/error.h"
#include "method/path_options.h"

static bool light_is_delta_sun(const light *l) { return l->kind == LIGHT_DISTANT && !(l->angular_radius > 0.0); }

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
    media_at(s, 0, p, 0.0, &ms);
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

brume_status path_prepare(const brume_scene *s, bool lobes, path_state **out)
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
        const medium *md = &s->media[m];
        box3 b = density_reach_bounds(md->moved ? md->moved : md->rho);
        st.reach = (box3){v3_min(st.reach.lo, b.lo), v3_max(st.reach.hi, b.hi)};
        moving |= md->motion != NULL || md->moved != NULL;
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
    /* the predictions sum every medium: with bounded media, where a ray sees only some, none */
    if (o->sun_roulette > 0.0 && st.nsuns > 0 && some && !moving && !s->bounded) {
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
