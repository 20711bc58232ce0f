/* blasi_light.c - the first pass of Blasi's method (1993, Section 4): light rays through
 * the voxels, intercepted and stored as each voxel's isotropic source.
 *
 * First pass. Light ray k of light l starts with power W (watts, RGB) chosen so that the
 * rays of a light carry, in expectation, the power that light sends towards the media
 * (docs/blasi.md, "Normalization"). Between two scattering points the ray's weight is
 * multiplied per channel by exp(-(sigma_a + sigma_s - sigma_bar) rho delta) (Eq. 7 in
 * the grey case, where this is exp(-alpha rho delta)), and it is intercepted where the
 * optical depth of sigma_bar = mean over channels of sigma_s (Eq. 10) since the last
 * scattering point reaches -ln(1 - u) (Eq. 9-11, docs/errata.md, erratum 4); at an interception
 * the weight is multiplied by sigma_s / sigma_bar per channel (the RGB weights of a
 * chromatic medium; 1 when grey). The fraction r is stored in the voxel, 1 - r goes on
 * along a direction drawn from the directional lobe (Eq. 22-23). Rays below `threshold`
 * of their initial weight stop; in the paper variant, a ray that leaves the media stores
 * what it carries in the last non-empty voxel it crossed (docs/errata.md, erratum 5).
 *
 * Stored power P_V becomes the isotropic source S_V = P_V / (4 pi |V|): radiance per unit
 * length, the sigma_s phi / 4 pi of the single-scattering integral (docs/errata.md, erratum 6).
 *
 * Determinism: light rays are numbered and draw from their own counter-based stream; the
 * rays are cut into batches that threads take as they come (a slower core gets fewer), and
 * each thread adds its deposits into its own sums in fixed point (integers: the order of the
 * terms does not change their sum), added together at the end. So the sums are the same
 * bits for any thread count. */
#include <math.h>
#include <stdlib.h>

#include "core/cancel.h"
#include "core/error.h"
#include "core/fixsum.h"
#include "core/pool.h"
#include "core/sampling.h"
#include "render/blasi_state.h"
#include "render/blasi_walk.h"
#include "surface/surfaces.h"
#include "render/blasi_rays.h"

#define BLASI_BATCH 1024           /* light rays per task */
#define CANCEL_EVERY 32            /* light rays between two questions to the progress callback */
#define BLASI_MAX_INTERCEPTS 100000 /* interceptions of one light ray: a limit that keeps every walk
                                      finite (docs/scene-format.md#limits) */

/* ---- the light pass's sums -----------------------------------------------------------------
 *
 * Deposited power is summed in fixed point (core/fixsum.h): integer sums do not depend on
 * the order of their terms, so each thread adds its deposits into sums of its own as it
 * makes them, and those added at the end give the same bits for any thread count and any
 * order in which the batches ran, with no record of the deposits, no ordered merge and no
 * barrier between batches. The unit is 2^-40 of a reference power per ray (ray_power_ref,
 * within a few powers of two of what rays start with): a deposit is truncated to a whole
 * unit, about 1e-12 of a ray's power (S is a float, 6e-8 of a voxel's sum), and a sum
 * would wrap only past 2^128 units, 2^88 rays' powers in one voxel: beyond any light-ray
 * count (at most 1e12 ~ 2^40) times any weight a ray reaches (a chromatic medium's weights
 * may exceed the initial power; their mean cannot). */

/* What the rays of one batch make: deposits into the sums of the thread that traces it,
 * counts for the batch's own record. */
typedef struct light_sums {
    fixsum *P;            /* 3 nocc: the thread's stored power per non-empty voxel and channel, in units */
    const uint32_t *slot; /* nvox: a non-empty voxel's place in P (deposits land in no other) */
    double per_unit;      /* units per watt */
    uint64_t intercepts, deposits;
    double emitted;  /* power the batch's rays started with, summed over channels */
} light_sums;

typedef struct pass1_job {
    const brume_scene *s;
    const blasi_state *st;
    uint64_t nrays, nbatch; /* rays traced, over all lights */
    const uint64_t *first;  /* nlights + 1: light l traces rays [first[l], first[l + 1]) */
    fixsum *P;              /* per thread: 3 nocc sums */
    const uint32_t *slot;
    size_t nocc;            /* non-empty voxels */
    double per_unit;
    light_sums *batch;      /* nbatch: each batch's counts (P unused) */
    cancel_poll cancel;     /* the render's progress callback, asked between rays */
} pass1_job;

static inline void deposit(light_sums *out, size_t v, color w, double f)
{
    fixsum *p = out->P + 3 * (size_t)out->slot[v];
#pragma GCC unroll 3
    for (int c = 0; c < 3; c++)
        fixsum_add(&p[c], w.c[c] * f * out->per_unit);
    out->deposits++;
}

/* Coefficients of a piece: sigma_bar rho summed over its media (returned), and in *kx the
 * per-channel (sigma_t - sigma_bar) rho, the rate at which the weight decays between
 * interceptions (alpha rho for a grey medium, Eq. 7). */
static inline double piece_coeffs(const blasi_state *st, const piece *pc, color *kx)
{
    double sb = 0.0;
    *kx = col(0.0);
    for (int i = 0; i < pc->n; i++) {
        const blasi_medium *bm = &st->m[pc->m[i]];
        double rho = pc->rho[i];
        sb += bm->sigma_bar * rho;
        for (int c = 0; c < 3; c++)
            kx->c[c] += (bm->sigma_t.c[c] - bm->sigma_bar) * rho;
    }
    return sb;
}

/* Whether an exit deposit may land in voxel v of bm: the paper's "last non-empty voxel",
 * one with a value of its own. A trilinear medium's voxel whose value is 0 holds some of its
 * neighbours' field, but the power a ray still carries when it leaves does not scale with
 * that density: stored there, the view pass (which gathers a voxel's source in proportion
 * to the density over its mean) would show it as a bright rim. */
static inline bool exit_voxel(const blasi_state *st, const blasi_medium *bm, size_t v)
{
    return !bm->trilinear || st->field[v] != 0.0f;
}

/* A voxel of the piece that holds density and may take an exit deposit (the piece's first
 * medium's voxel may be empty where another medium's is not), in *v; false if none. */
static inline bool piece_exit_voxel(const blasi_state *st, const piece *pc, size_t *v)
{
    for (int i = 0; i < pc->n; i++)
        if (pc->rho[i] != 0.0 && exit_voxel(st, &st->m[pc->m[i]], pc->v[i])) {
            *v = pc->v[i];
            return true;
        }
    return false;
}

/* exp(-x) per channel, once when the channels are equal (a grey medium), and by
 * voxel_exp's series for 0 <= x < 1/16, where most of a light ray's decays are (a
 * chromatic medium's may be negative: exp). */
static inline color col_exp_neg(color x)
{
    color e;
    for (int c = 0; c < BRUME_NSAMPLES; c++) {
        double T = 0.0, f;
        if (c > 0 && x.c[c] == x.c[c - 1])
            T = e.c[c - 1];
        else if (x.c[c] >= 0.0)
            voxel_exp(x.c[c], &T, &f);
        else
            T = exp(-x.c[c]);
        e.c[c] = T;
    }
    return e;
}

/* One flight of a light ray, from the source or a scattering point to the next
 * interception. tau is the sigma_bar optical depth since it began; it scatters where tau
 * reaches the target -ln(1 - u) (Eq. 11), with u the flight's first random number, drawn
 * at the first voxel that can scatter (most light rays miss the media), and its log taken
 * only when tau passes a lower bound of the target, u (1 - 2^-20) (0 for u < 2^-30: the
 * rounding of 1 - u and of the log cannot take the target under it): a flight that leaves
 * the media before needs no log, and the one that takes it scatters where it did. The weight's
 * decay is kept as an optical depth D per channel and exponentiated once, at the
 * interception or the exit; the stop test is D > lim = log(w / w_stop) per channel, with
 * the logs taken only when D passes their lower bound lim_lo = 1 - w_stop / w
 * (log x >= 1 - 1/x), itself found at the first voxel crossed: most flights end long
 * before. */
typedef struct flight {
    double u, bound, target, tau; /* bound: the target's lower bound, then the target */
    bool have_u, have_target, lim_lo_known, lim_known;
    color D, lim, lim_lo; /* a grey flight keeps one D and its bounds in channel 0 */
} flight;

static inline void flight_begin(flight *f)
{
    f->have_u = f->have_target = f->lim_lo_known = f->lim_known = false;
    f->bound = f->target = INFINITY; /* until drawn */
    f->tau = 0.0;
    f->D = col(0.0);
}

/* Draws u, at the first voxel that can scatter. */
static inline void flight_draw(flight *f, rng *g)
{
    f->u = rng_next(g);
    f->bound = f->u >= 0x1p-30 ? f->u * (1.0 - 0x1p-20) : 0.0;
    f->have_u = true;
}

/* True when the optical depth x (>= f->bound) reaches the target, taken now if not yet. */
static inline bool flight_reaches(flight *f, double x)
{
    if (!f->have_target) {
        f->bound = f->target = sample_exponential(f->u, 1.0);
        f->have_target = true;
    }
    return x >= f->target;
}

/* True when a stretch of length dl with sigma_bar rho = sb scatters in it. */
static inline bool flight_scatters(flight *f, double sb, double dl, rng *g)
{
    if (!(sb > 0.0))
        return false;
    if (!f->have_u)
        flight_draw(f, g);
    const double x = f->tau + sb * dl;
    return x >= f->bound && flight_reaches(f, x);
}

/* The stop test after the decay reached D (the while condition: L_R > THRESHOLD): true
 * when the weight is under the threshold in every channel. grey: D's channels are equal
 * (D.c[0] is read), and D exceeds every channel's bound exactly when it exceeds the
 * largest, that of the largest weight (both bounds grow with the weight, and so do their
 * rounded values): one division, one log and one comparison, kept in channel 0. */
static inline __attribute__((always_inline)) bool flight_stops_as(flight *f, color D, const color *wp, double w_stop,
                                                                  bool grey)
{
    const int nc = grey ? 1 : BRUME_NSAMPLES;
    color w = *wp;
    if (!f->lim_lo_known) {
        if (grey)
            w.c[0] = col_max(w);
        for (int c = 0; c < nc; c++)
            f->lim_lo.c[c] = w.c[c] > 0.0 ? 1.0 - w_stop / w.c[c] : -(double)INFINITY;
        f->lim_lo_known = true;
    }
    for (int c = 0; c < nc; c++)
        if (!(D.c[c] > f->lim_lo.c[c]))
            return false;
    if (!f->lim_known) {
        if (grey)
            w.c[0] = col_max(w);
        for (int c = 0; c < nc; c++)
            f->lim.c[c] = w.c[c] > 0.0 ? log(w.c[c] / w_stop) : -(double)INFINITY;
        f->lim_known = true;
    }
    for (int c = 0; c < nc; c++)
        if (!(D.c[c] > f->lim.c[c]))
            return false;
    return true;
}

static inline bool flight_stops(flight *f, color D, color w, double w_stop)
{
    return flight_stops_as(f, D, &w, w_stop, false);
}

/* A stretch of length dl with coefficients sb, kx that the flight crosses whole. True when
 * the weight falls under the threshold there. */
static inline bool flight_cross(flight *f, double sb, color kx, double dl, color w, double w_stop)
{
    f->tau += sb * dl;
    for (int c = 0; c < BRUME_NSAMPLES; c++)
        f->D.c[c] += kx.c[c] * dl;
    return flight_stops(f, f->D, w, w_stop);
}

/* The interception in piece pc, at ds into it (ray parameter t_hit), for a flight that
 * has reached its target there: the RGB weight (Eq. 10) and the decay, the fraction r
 * stored, and the new direction from the lobe (Eq. 23 for Schlick lobes). False when what
 * goes on is under the threshold (the ray ends). */
static bool intercept(const blasi_state *st, const piece *pc, double sb, color kx, const flight *f, double ds,
                      double t_hit, ray *r, color *w, double w_stop, rng *g, light_sums *acc, bool *have_last,
                      size_t *last)
{
    int pick = 0;
    if (pc->n > 1) { /* the medium that scatters, in proportion to its sigma_bar rho */
        double x = rng_next(g) * sb;
        int nonzero = 0; /* the last medium that can scatter here: where rounding in x leaves it */
        for (int i = 0; i < pc->n; i++)
            if (st->m[pc->m[i]].sigma_bar * pc->rho[i] > 0.0)
                nonzero = i;
        for (pick = 0; pick < nonzero; pick++) {
            double wi = st->m[pc->m[pick]].sigma_bar * pc->rho[pick];
            if (x < wi && wi > 0.0)
                break;
            x -= wi;
        }
    }
    color sig_s = col(0.0), dep; /* RGB weight sigma_s / sigma_bar (Eq. 10) */
    for (int i = 0; i < pc->n; i++)
        sig_s = col_madd(sig_s, st->m[pc->m[i]].md->sigma_s, pc->rho[i]);
    for (int c = 0; c < BRUME_NSAMPLES; c++)
        dep.c[c] = f->D.c[c] + kx.c[c] * ds;
    color T = col_exp_neg(dep);
    for (int c = 0; c < BRUME_NSAMPLES; c++)
        w->c[c] *= T.c[c] * sig_s.c[c] / sb;
    const blasi_medium *bm = &st->m[pc->m[pick]];
    deposit(acc, pc->v[pick], *w, bm->r);
    acc->intercepts++;
    if (exit_voxel(st, bm, pc->v[pick])) {
        *have_last = true;
        *last = pc->v[pick];
    }
    *w = col_scale(*w, 1.0 - bm->r);
    if (!(col_max(*w) > w_stop))
        return false;
    double pdf, ua = rng_next(g), ub = rng_next(g);
    vec3 d = phase_sample(bm->dir, r->d, ua, ub, &pdf); /* Eq. 23 for Schlick lobes */
    *r = (ray){ray_at(*r, t_hit), d, 0.0};
    return true;
}

/* What a flight ended with. */
typedef enum flight_end { FLIGHT_LEFT, FLIGHT_SCATTERED, FLIGHT_STOPPED } flight_end;

/* A flight through one small grid (one medium, no block skipping, the voxel walk: the
 * usual case): the general loop of fly() with the piece reduced to one voxel, the walk's
 * and the flight's state in locals the loop keeps in registers, and no branch on whether a
 * voxel is empty: an empty one (sb = 0, kx = 0) adds exactly 0 to tau and D, cannot
 * scatter (tau + 0 < target), is not remembered as the last voxel, and leaves the stop
 * test's answer as it was, so the flight is the same as with the branch. grey: the decay
 * rate kx is the same in every channel (sigma_t - sigma_bar grey, e.g. a grey medium), so
 * D's channels stay equal and the loop keeps one (the same sums: every channel's would be
 * this one). */
static inline __attribute__((always_inline)) flight_end fly_one_as(const blasi_state *st, flight *f, ray *r,
                                                                   double t_end, color *w, double w_stop, rng *g,
                                                                   light_sums *acc, bool *have_last, size_t *last,
                                                                   const grid_dda_dir *sun, color kx1, bool grey)
{
    const blasi_medium *bm = &st->m[0];
    grid_dda g0;
    if (!(sun ? walk_begin_one_dir(bm, *r, t_end, &g0, sun) : walk_begin_one(bm, *r, t_end, &g0, false)))
        return FLIGHT_LEFT;
    grid_dda gd = g0; /* never escapes */
    const float *rho = st->rho;
    const size_t nx = (size_t)bm->n[0], ny = (size_t)bm->n[1];
    const double sigma_bar = bm->sigma_bar;
    const int nc = grey ? 1 : BRUME_NSAMPLES; /* the channels the loop keeps */
    double tau = f->tau, bound = f->bound; /* bound: as f's, kept here */
    bool have_u = f->have_u;
    color D = f->D;
    bool was = *have_last;
    size_t lv = *last;
    flight_end e = FLIGHT_LEFT;
    grid_dda_step c;
    while (grid_dda_next(&gd, &c)) {
        const size_t v = (size_t)c.i + nx * ((size_t)c.j + ny * (size_t)c.k);
        const double rh = (double)rho[v], dl = c.t1 - c.t0, sb = sigma_bar * rh;
        color kx;
#pragma GCC unroll 3
        for (int k = 0; k < nc; k++)
            kx.c[k] = kx1.c[k] * rh;
        if (!have_u && sb > 0.0) { /* the first voxel that can scatter: draw u */
            flight_draw(f, g);
            have_u = true;
            bound = f->bound;
        }
        if (tau + sb * dl >= bound) { /* sb > 0 here: tau < bound before */
            const bool hit = flight_reaches(f, tau + sb * dl);
            bound = f->bound; /* the target, taken now */
            if (hit) {
                double ds = (f->target - tau) / sb;
                piece pc; /* only what intercept reads */
                pc.n = 1;
                pc.m[0] = 0;
                pc.v[0] = v;
                pc.rho[0] = rh;
                f->D = grey ? col(D.c[0]) : D;
                kx = grey ? col(kx.c[0]) : kx;
                return intercept(st, &pc, sb, kx, f, ds, c.t0 + ds, r, w, w_stop, g, acc, have_last, last)
                           ? FLIGHT_SCATTERED
                           : FLIGHT_STOPPED;
            }
        }
        /* !(sb <= 0 && kx == 0), with | so that no branch is mispredicted on it */
        bool counts = !(sb <= 0.0);
#pragma GCC unroll 3
        for (int k = 0; k < nc; k++)
            counts |= kx.c[k] != 0.0;
        tau += counts ? sb * dl : 0.0;
#pragma GCC unroll 3
        for (int k = 0; k < nc; k++)
            D.c[k] += counts ? kx.c[k] * dl : 0.0;
        lv = counts ? v : lv;
        was |= counts;
        if (was && flight_stops_as(f, D, w, w_stop, grey)) {
            e = FLIGHT_STOPPED;
            break;
        }
    }
    f->tau = tau;
    f->D = grey ? col(D.c[0]) : D;
    *have_last = was;
    *last = lv;
    return e;
}

static flight_end fly_one(const blasi_state *st, flight *f, ray *r, double t_end, color *w, double w_stop, rng *g,
                          light_sums *acc, bool *have_last, size_t *last, const grid_dda_dir *sun)
{
    const blasi_medium *bm = &st->m[0];
    color kx1; /* (sigma_t - sigma_bar) per unit density */
    for (int c = 0; c < BRUME_NSAMPLES; c++)
        kx1.c[c] = bm->sigma_t.c[c] - bm->sigma_bar;
    if (col_is_grey(kx1) && col_is_grey(f->D))
        return fly_one_as(st, f, r, t_end, w, w_stop, g, acc, have_last, last, sun, kx1, true);
    return fly_one_as(st, f, r, t_end, w, w_stop, g, acc, have_last, last, sun, kx1, false);
}

/* A flight through any media: the merged voxel walks, or uniform steps (blasi.step). */
static flight_end fly(const blasi_state *st, flight *f, ray *r, double t_end, color *w, double w_stop, rng *g,
                      light_sums *acc, bool *have_last, size_t *last)
{
    walk wk;
    piece pc;
    double t_march = 0.0, t_march_end = 0.0;
    uint64_t k_march = 0; /* steps are placed by index, t_march + k step: never t += step */
    if (st->step > 0.0) {
        if (!box3_intersect(st->bounds, *r, 0.0, t_end, &t_march, &t_march_end))
            t_march = t_march_end = 0.0;
    } else {
        walk_begin(&wk, st, *r, t_end);
    }
    for (;;) {
        double dl, t_mid = 0.0;
        if (st->step > 0.0) { /* uniform steps: the voxels at the step's midpoint */
            double a = t_march + (double)k_march * st->step;
            if (!(a < t_march_end))
                return FLIGHT_LEFT;
            k_march++;
            dl = fmin(st->step, t_march_end - a);
            t_mid = a + 0.5 * dl;
            pc.t0 = a;
            piece_at(st, ray_at(*r, t_mid), &pc);
        } else {
            if (!walk_next(&wk, st, &pc))
                return FLIGHT_LEFT;
            piece_density(st, &pc, *r, false);
            dl = pc.t1 - pc.t0;
        }
        color kx;
        double sb = piece_coeffs(st, &pc, &kx);
        if (flight_scatters(f, sb, dl, g)) {
            /* interception: exactly inside the voxel, or at the step's midpoint */
            double ds = st->step > 0.0 ? dl : (f->target - f->tau) / sb;
            double t_hit = st->step > 0.0 ? t_mid : pc.t0 + ds;
            return intercept(st, &pc, sb, kx, f, ds, t_hit, r, w, w_stop, g, acc, have_last, last) ? FLIGHT_SCATTERED
                                                                                                : FLIGHT_STOPPED;
        }
        if (sb <= 0.0 && kx.c[0] == 0.0 && kx.c[1] == 0.0 && kx.c[2] == 0.0)
            continue; /* empty voxel */
        size_t v;
        if (piece_exit_voxel(st, &pc, &v)) {
            *have_last = true;
            *last = v;
        }
        if (flight_cross(f, sb, kx, dl, *w, w_stop))
            return FLIGHT_STOPPED;
    }
}

/* Follows one light ray through the media (Algorithm of the First Pass), flight by
 * flight. */
/* True when light flights take fly_one: one small grid read per voxel, the voxel walk. */
static inline bool flights_one(const blasi_state *st)
{
    return st->nm == 1 && !st->m[0].skip && !st->m[0].trilinear && !(st->step > 0.0);
}

/* The voxel-space set-up of the direction of a delta sun's rays (light_ray gives them all
 * its direction), for their first flights through one small grid; NULL for another light
 * or other media. */
static const grid_dda_dir *sun_dir(const blasi_state *st, const light *l, grid_dda_dir *out)
{
    if (!flights_one(st) || l->kind != LIGHT_DISTANT || l->angular_radius > 0.0)
        return NULL;
    grid_dda_dir_make(out, affine3_apply_dir(&st->m[0].w2v, l->direction));
    return out;
}

/* sun: sun_dir of the ray's light, or NULL. */
static void trace_light_ray(const brume_scene *s, const blasi_state *st, ray r, color w, rng *g, light_sums *acc,
                            const grid_dda_dir *sun)
{
    const bool one = flights_one(st);
    double w_stop = st->threshold * col_max(w);
    bool have_last = false; /* the last non-empty voxel crossed, for the exit deposit */
    size_t last = 0;
    for (int flights = 0;; flights++) { /* one flight from the source or a scattering point */
        if (flights > BLASI_MAX_INTERCEPTS) {
            /* A walk that neither leaves nor fades (albedo 1, r = 0, an optically huge
             * medium) ends here with a defined result: what it still carries stays in
             * the voxel it has reached, as the paper stores the energy of a ray that
             * leaves in its last voxel. */
            if (have_last)
                deposit(acc, last, w, 1.0);
            return;
        }
        double t_end = INFINITY;
        surface_hit h;
        if (s->surf && surfaces_intersect(s->surf, r, 0.0, INFINITY, &h))
            t_end = h.t;
        flight f;
        flight_begin(&f);
        flight_end e = one ? fly_one(st, &f, &r, t_end, &w, w_stop, g, acc, &have_last, &last, flights == 0 ? sun : NULL)
                           : fly(st, &f, &r, t_end, &w, w_stop, g, acc, &have_last, &last);
        if (e == FLIGHT_SCATTERED)
            continue;
        if (e == FLIGHT_STOPPED || isfinite(t_end)) /* under the threshold, or stopped by a surface */
            return;
        if (st->exit == BLASI_EXIT_PAPER && have_last) { /* "stored in the last non-empty voxel" */
            w = col_mul(w, col_exp_neg(f.D));
            deposit(acc, last, w, 1.0);
        }
        return;
    }
}

static void pass1_batch(size_t task, int thread, void *user)
{
    pass1_job *job = user;
    const brume_scene *s = job->s;
    light_sums sums = {job->P + (size_t)thread * 3 * job->nocc, job->slot, job->per_unit, 0, 0, 0.0}, *out = &sums;
    uint64_t b = task;
    uint64_t first = b * BLASI_BATCH, end = first + BLASI_BATCH < job->nrays ? first + BLASI_BATCH : job->nrays;
    /* the light of the batch's first ray, found once per batch (by bisection: first[] is
     * non-decreasing, first[0] = 0 <= first < first[nlights] = nrays) */
    size_t lo = 0, hi = (size_t)s->nlights;
    while (hi - lo > 1) {
        size_t mid = (lo + hi) / 2;
        if (job->first[mid] <= first)
            lo = mid;
        else
            hi = mid;
    }
    size_t l = lo;
    uint64_t l0 = job->first[l], l1 = job->first[l + 1];
    grid_dda_dir sun_mem;
    const grid_dda_dir *sun = sun_dir(job->st, &s->lights[l], &sun_mem);
    for (uint64_t i = first; i < end; i++) {
        /* every CANCEL_EVERY rays: cancel_poll_stop reads the clock, 65 ns on the EPYC VM's
         * kvm-clock against some 270 ns a traced ray; a ray is bounded (BLASI_MAX_INTERCEPTS),
         * so the callback is still asked every CANCEL_POLL_SECONDS and 32 rays at most */
        if ((i - first) % CANCEL_EVERY == 0 && cancel_poll_stop(&job->cancel))
            return; /* the pass is abandoned: its sums are never read */
        while (i >= l1) { /* the next light's share (a light may own no ray) */
            l++;
            l0 = l1;
            l1 = job->first[l + 1];
            sun = sun_dir(job->st, &s->lights[l], &sun_mem);
        }
        rng g = rng_make(s->settings.seed, i, 0xB1A5100000ULL);
        ray r;
        color W;
        if (blasi_light_ray(s, job->st, &s->lights[l], i - l0, l1 - l0, &g, &r, &W) && col_max(W) > 0.0) {
            out->emitted += W.c[0] + W.c[1] + W.c[2];
            trace_light_ray(s, job->st, r, W, &g, out, sun);
        }
    }
    job->batch[b] = (light_sums){NULL, NULL, 0.0, sums.intercepts, sums.deposits, sums.emitted};
}

/* The job's sums: for the non-empty voxels only (a sixth of picture 1's: fewer pages to
 * touch, each a page fault, and to merge), one copy per thread, as many threads as the
 * memory limit leaves room for (the result is the same with any number): *slot, job->nocc,
 * job->P and job->batch (the caller frees them, also on failure), *threads. */
static brume_status sums_new(const brume_scene *s, const blasi_state *st, pass1_job *job, uint32_t **slot,
                             size_t *threads)
{
    *slot = malloc(st->nvox * sizeof **slot);
    if (*slot)
        for (size_t v = 0; v < st->nvox; v++)
            (*slot)[v] = st->rho[v] != 0.0f ? (uint32_t)job->nocc++ : UINT32_MAX;
    job->slot = *slot;
    const size_t copy = 3 * job->nocc * sizeof(fixsum), left = s->max_memory > s->memory_used ? s->max_memory - s->memory_used : 0;
    size_t n = (size_t)(s->settings.threads > 0 ? s->settings.threads : pool_default_threads());
    n = n < job->nbatch ? n : (size_t)job->nbatch;
    if (copy > left) /* not even one thread's sums fit under the limit */
        return err_set(BRUME_ERROR_OUT_OF_MEMORY,
                       "%s: blasi: the light pass needs %.1f MB for its sums, over what render.max_memory_mb leaves "
                       "(%.1f MB)",
                       s->source, (double)copy / 1048576.0, (double)left / 1048576.0);
    n = n * copy <= left ? n : left / copy;
    *threads = n;
    job->P = calloc(n * 3 * job->nocc + 1, sizeof *job->P);
    job->batch = calloc((size_t)job->nbatch, sizeof *job->batch);
    if (!*slot || !job->P || !job->batch)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: blasi: out of memory for the light pass", s->source);
    return BRUME_OK;
}

/* The batches on the thread pool; cancelled through the render's progress callback. */
static brume_status run_batches(const brume_scene *s, pass1_job *job, size_t threads)
{
    cancel_poll_init(&job->cancel, &s->settings);
    pool_run((int)threads, (size_t)job->nbatch, pass1_batch, job);
    const bool cancelled = cancel_poll_cancelled(&job->cancel), late = cancel_poll_out_of_time(&job->cancel);
    cancel_poll_finish(&job->cancel);
    if (late)
        return err_set(BRUME_ERROR_RANGE,
                       "%s: render.time: the time budget of %.17g s was spent in blasi's light pass, before the first "
                       "sample: raise it, or lower blasi.light_rays",
                       s->source, s->settings.time_budget);
    if (cancelled)
        return err_set(BRUME_ERROR_CANCELLED, "%s: blasi: the light pass was cancelled", s->source);
    return BRUME_OK;
}

/* The batches' counts into st->stats, the threads' sums added, and the power turned into
 * the source per unit length, S = P / (4 pi |V|). */
static void store_sums(blasi_state *st, pass1_job *job, const uint32_t *slot, size_t threads)
{
    for (uint64_t k = 0; k < job->nbatch; k++) { /* batch order: the emitted power's sum is the same bits too */
        st->stats.interceptions += job->batch[k].intercepts;
        st->stats.deposits += job->batch[k].deposits;
        st->stats.emitted_power += job->batch[k].emitted / 3.0;
    }
    for (size_t t = 1; t < threads; t++) /* the threads' sums into the first copy */
        for (size_t i = 0; i < 3 * job->nocc; i++)
            fixsum_merge(&job->P[i], job->P[t * 3 * job->nocc + i]);
    double total = 0.0;
    for (int m = 0; m < st->nm; m++) {
        const blasi_medium *bm = &st->m[m];
        double norm = 1.0 / (4.0 * PI * bm->volume);
        for (size_t v = bm->offset; v < bm->offset + bm->nvox; v++)
            for (int c = 0; slot[v] != UINT32_MAX && c < 3; c++) { /* S stays 0 in empty voxels */
                double p = fixsum_value(job->P[3 * (size_t)slot[v] + (size_t)c]) / job->per_unit;
                total += p;
                st->S[3 * v + (size_t)c] = (float)(p * norm);
            }
    }
    st->stats.traced_rays = job->nrays;
    st->stats.stored_power = total / 3.0;
}

brume_status blasi_light_pass(const brume_scene *s, blasi_state *st)
{
    uint64_t nominal = s->nlights > 0 && st->nm > 0 && st->light_box.lo.x <= st->light_box.hi.x
                           ? blasi_opts(s)->light_rays
                           : 0;
    if (nominal == 0)
        return BRUME_OK;
    uint64_t *first = blasi_rays_per_light(s, st, nominal);
    if (!first)
        return err_status();
    uint64_t nrays = first[s->nlights];
    if (blasi_check_work(s, st, nrays) != BRUME_OK) {
        free(first);
        return err_status();
    }
    pass1_job job = {.s = s, .st = st, .nrays = nrays, .nbatch = (nrays + BLASI_BATCH - 1) / BLASI_BATCH,
                     .first = first, .per_unit = blasi_units_per_watt(s, st, first)};
    uint32_t *slot = NULL;
    size_t threads = 0;
    brume_status rc = sums_new(s, st, &job, &slot, &threads);
    if (rc == BRUME_OK)
        rc = run_batches(s, &job, threads);
    if (rc == BRUME_OK) {
        store_sums(st, &job, slot, threads);
        st->stats.light_rays = nominal;
    }
    free(job.P);
    free(job.batch);
    free(slot);
    free(first);
    return rc;
}
