/* blasi_walk.h - the voxel walk of Blasi's method (private to src/render/blasi*.c): the
 * exact walks of every medium's voxels (density/dda.h) merged in t, with the empty space of
 * one grid skipped. Both passes walk with it, inlined into their loops. */
#ifndef BRUME_RENDER_BLASI_WALK_H
#define BRUME_RENDER_BLASI_WALK_H

#include <float.h>

#include "density/dda.h"
#include "render/blasi_state.h"

/* One stretch [t0, t1) of a ray inside one voxel of each of n media: their global voxels v,
 * the density each has along the stretch, rho, and (view pass) its stored source there, S
 * (piece_density: the voxel's values, or a trilinear medium's means along the stretch). */
typedef struct piece {
    double t0, t1;
    int n;
    int m[SCENE_MAX_MEDIA];
    size_t v[SCENE_MAX_MEDIA];
    double rho[SCENE_MAX_MEDIA];
    color S[SCENE_MAX_MEDIA];
} piece;

/* pc->rho, and with source pc->S, for the stretch [pc->t0, pc->t1] of ray r. */
static inline void piece_density(const blasi_state *st, piece *pc, ray r, bool source)
{
    for (int i = 0; i < pc->n; i++) {
        const blasi_medium *bm = &st->m[pc->m[i]];
        if (!bm->trilinear) {
            pc->rho[i] = (double)st->rho[pc->v[i]];
            for (int c = 0; source && c < 3; c++)
                pc->S[i].c[c] = (double)st->S[3 * pc->v[i] + (size_t)c];
            continue;
        }
        vec3 o = affine3_apply(&bm->w2v, r.o), d = affine3_apply_dir(&bm->w2v, r.d);
        pc->rho[i] = blasi_crossing_mean(st, bm, v3_madd(o, d, pc->t0), v3_madd(o, d, pc->t1), source ? &pc->S[i] : NULL);
    }
}

/* The exact voxel walks of every medium (density/dda.h), merged in t. With one medium
 * (the usual case) the walk skips empty space: a coarse walk over occupancy blocks, and a
 * voxel walk over each run of occupied blocks only. Empty voxels hold no density and no
 * source (nothing is ever deposited in them), so skipping them changes no sum. */
typedef struct walk {
    int nm;
    grid_dda dda[SCENE_MAX_MEDIA];
    grid_dda_step cur[SCENE_MAX_MEDIA];
    bool live[SCENE_MAX_MEDIA];
    double t;
    grid_dda blocks; /* one medium: the walk over occupancy blocks */
    bool blocks_live;
} walk;

static inline size_t voxel_index(const blasi_medium *bm, int i, int j, int k)
{
    return bm->offset + (size_t)i + (size_t)bm->n[0] * ((size_t)j + (size_t)bm->n[1] * (size_t)k);
}

/* True when the line o + t d (any t) misses the world box of centre c and half-extents e:
 * the separating-axis test of a line against a box, whose only candidate axes are the
 * cross products of d with the box's axes (a line's extent along any other axis that d
 * has a component on is unbounded). No division and one branch, where a walk's set-up
 * maps the ray to voxel space and divides by each component of d. tol covers the rounding
 * of the cross products (a few ulps of |w| |d|); a ray that passes may still miss. */
static inline bool line_misses_box(vec3 c, vec3 e, vec3 o, vec3 d)
{
    const vec3 w = v3_sub(o, c);
    const double ax = fabs(d.x), ay = fabs(d.y), az = fabs(d.z);
    const double tol = 1e-12 * (fabs(w.x) + fabs(w.y) + fabs(w.z)) * (ax + ay + az);
    return (fabs(w.y * d.z - w.z * d.y) > e.y * az + e.z * ay + tol) |
           (fabs(w.z * d.x - w.x * d.z) > e.x * az + e.z * ax + tol) |
           (fabs(w.x * d.y - w.y * d.x) > e.x * ay + e.y * ax + tol);
}

/* The normals of the diagonal slabs, voxel space: with the box of the non-empty voxels
 * they bound them by an 18-sided polyhedron, much closer to a cloud than its box. */
static const int blasi_slab_n[BLASI_SLABS][3] = {{1, 1, 0}, {1, -1, 0}, {1, 0, 1}, {1, 0, -1}, {0, 1, 1}, {0, 1, -1}};

/* [*t0, *t1] of the ray o + t d (voxel space) cut to the medium's diagonal slabs; false
 * when nothing is left. */
static inline __attribute__((always_inline)) bool slabs_clip(const blasi_medium *bm, vec3 o, vec3 d, double *t0,
                                                             double *t1)
{
    double a0 = *t0, a1 = *t1, b[BLASI_SLABS], inv[BLASI_SLABS];
    /* the six reciprocals from one division: inv_q = (product of the other b) / (product
     * of all), the products from both ends (rounding of a few ulps: the slabs' margin is
     * far wider); one at a time when a product is not a normal number (b = 0: parallel) */
    double pre[BLASI_SLABS + 1], suf[BLASI_SLABS + 1];
    pre[0] = suf[BLASI_SLABS] = 1.0;
#pragma GCC unroll 6
    for (int q = 0; q < BLASI_SLABS; q++) {
        const int *n = blasi_slab_n[q];
        b[q] = n[0] * d.x + n[1] * d.y + n[2] * d.z;
        pre[q + 1] = pre[q] * b[q];
    }
#pragma GCC unroll 6
    for (int q = BLASI_SLABS - 1; q >= 0; q--)
        suf[q] = suf[q + 1] * b[q];
    const double all = pre[BLASI_SLABS];
    if (fabs(all) >= DBL_MIN && fabs(all) <= DBL_MAX) {
        const double inv_all = 1.0 / all;
#pragma GCC unroll 6
        for (int q = 0; q < BLASI_SLABS; q++)
            inv[q] = pre[q] * suf[q + 1] * inv_all;
    } else {
#pragma GCC unroll 6
        for (int q = 0; q < BLASI_SLABS; q++)
            inv[q] = 1.0 / b[q];
    }
#pragma GCC unroll 6
    for (int q = 0; q < BLASI_SLABS; q++) {
        const int *n = blasi_slab_n[q];
        const double a = n[0] * o.x + n[1] * o.y + n[2] * o.z;
        if (b[q] == 0.0) { /* parallel to the slab: inside or not at all */
            if (!(a >= bm->slab_lo[q] && a <= bm->slab_hi[q]))
                return false;
            continue;
        }
        /* ordered by selects, as grid_dda_begin_box does (not fmin, fmax: library calls) */
        const double ta = (bm->slab_lo[q] - a) * inv[q], tb = (bm->slab_hi[q] - a) * inv[q];
        const double t_near = dda_min(tb, ta), t_far = dda_max(ta, tb);
        a0 = t_near > a0 ? t_near : a0;
        a1 = t_far < a1 ? t_far : a1;
    }
    *t0 = a0;
    *t1 = a1;
    return a0 < a1;
}

/* One medium and a small grid (!bm->skip): the walk over every voxel of the box of its
 * non-empty voxels (that lies between their diagonal slabs, with slabs), empty ones cost a
 * step. False when the ray misses them. The slabs pay for the view rays (on picture 1,
 * 376 k walks of 6.5 M voxel steps instead of 503 k of 8.1 M, for six divisions a ray),
 * not for the light rays, whose flights mostly start inside the cloud. */
static inline __attribute__((always_inline)) bool walk_begin_one(const blasi_medium *bm, ray r, double tmax, grid_dda *g,
                                                                 bool slabs)
{
    vec3 o = affine3_apply(&bm->w2v, r.o), d = affine3_apply_dir(&bm->w2v, r.d);
    double t0 = 0.0, t1 = tmax;
    return bm->occ_hi[0] > 0 && (!slabs || slabs_clip(bm, o, d, &t0, &t1)) &&
           grid_dda_begin_box(g, bm->n, bm->occ_lo, bm->occ_hi, o, d, t0, t1);
}

/* walk_begin_one without slabs for a ray whose direction's set-up is made (sun: the voxel
 * space direction of a sun's rays, shared by all of them). */
static inline __attribute__((always_inline)) bool walk_begin_one_dir(const blasi_medium *bm, ray r, double tmax,
                                                                     grid_dda *g, const grid_dda_dir *sun)
{
    return bm->occ_hi[0] > 0 && grid_dda_begin_box_dir(g, bm->n, bm->occ_lo, bm->occ_hi,
                                                       affine3_apply(&bm->w2v, r.o), sun, 0.0, tmax);
}

static inline void walk_begin(walk *w, const blasi_state *st, ray r, double tmax)
{
    w->nm = st->nm;
    w->t = INFINITY;
    if (w->nm == 1) {
        /* the voxel walk is begun once over the whole ray; each run of occupied blocks
         * restarts it (grid_dda_restart: no clipping, no division) */
        const blasi_medium *bm = &st->m[0];
        if (!bm->skip) {
            w->live[0] = walk_begin_one(bm, r, tmax, &w->dda[0], true);
            w->blocks_live = false;
            return;
        }
        vec3 o = affine3_apply(&bm->w2v, r.o), d = affine3_apply_dir(&bm->w2v, r.d);
        double s = 1.0 / BLASI_BLOCK;
        w->live[0] = false;
        w->blocks_live = grid_dda_begin(&w->blocks, bm->bn, v3_scale(o, s), v3_scale(d, s), 0.0, tmax) &&
                         grid_dda_begin(&w->dda[0], bm->n, o, d, 0.0, tmax);
        return;
    }
    for (int m = 0; m < st->nm; m++) {
        const blasi_medium *bm = &st->m[m];
        vec3 o = affine3_apply(&bm->w2v, r.o), d = affine3_apply_dir(&bm->w2v, r.d);
        w->live[m] = grid_dda_begin(&w->dda[m], bm->n, o, d, 0.0, tmax) && grid_dda_next(&w->dda[m], &w->cur[m]);
        if (w->live[m])
            w->t = fmin(w->t, w->cur[m].t0);
    }
}

/* One small grid (no block skipping): the next non-empty voxel. Empty voxels hold nothing
 * (no density, no source: nothing is ever deposited in them), so they are stepped over
 * here, in a tight loop that the callers inline. */
static inline bool walk_next_small(walk *w, const blasi_medium *bm, const float *rho, piece *p)
{
    grid_dda_step c;
    size_t v;
    do {
        if (!w->live[0] || !(w->live[0] = grid_dda_next(&w->dda[0], &c)))
            return false;
        v = (size_t)c.i + (size_t)bm->n[0] * ((size_t)c.j + (size_t)bm->n[1] * (size_t)c.k);
    } while (rho[v] == 0.0f);
    p->t0 = c.t0;
    p->t1 = c.t1;
    p->n = 1;
    p->m[0] = 0;
    p->v[0] = bm->offset + v;
    return true;
}

static inline bool walk_next_any(walk *w, const blasi_state *st, piece *p);

static inline bool walk_next(walk *w, const blasi_state *st, piece *p)
{
    if (w->nm == 1 && !st->m[0].skip)
        return walk_next_small(w, &st->m[0], st->rho + st->m[0].offset, p);
    return walk_next_any(w, st, p);
}

static inline bool walk_next_any(walk *w, const blasi_state *st, piece *p)
{
    if (w->nm == 1) { /* the usual case: one grid, its own walk, empty blocks skipped */
        const blasi_medium *bm = &st->m[0];
        while (!w->live[0]) { /* the next run of occupied blocks */
            grid_dda_step b;
            do {
                if (!w->blocks_live || !(w->blocks_live = grid_dda_next(&w->blocks, &b)))
                    return false;
            } while (!bm->occ[(size_t)b.i + (size_t)bm->bn[0] * ((size_t)b.j + (size_t)bm->bn[1] * (size_t)b.k)]);
            double t0 = b.t0, t1 = b.t1;
            while ((w->blocks_live = grid_dda_next(&w->blocks, &b)) &&
                   bm->occ[(size_t)b.i + (size_t)bm->bn[0] * ((size_t)b.j + (size_t)bm->bn[1] * (size_t)b.k)])
                t1 = b.t1;
            w->live[0] = grid_dda_restart(&w->dda[0], t0, t1) && grid_dda_next(&w->dda[0], &w->cur[0]);
        }
        const grid_dda_step *c = &w->cur[0];
        p->t0 = c->t0;
        p->t1 = c->t1;
        p->n = 1;
        p->m[0] = 0;
        p->v[0] = voxel_index(bm, c->i, c->j, c->k);
        w->live[0] = grid_dda_next(&w->dda[0], &w->cur[0]);
        return true;
    }
    for (;;) {
        double t = w->t, t1 = INFINITY;
        bool any = false;
        for (int m = 0; m < w->nm; m++) {
            while (w->live[m] && w->cur[m].t1 <= t)
                w->live[m] = grid_dda_next(&w->dda[m], &w->cur[m]);
            if (!w->live[m])
                continue;
            any = true;
            t1 = fmin(t1, w->cur[m].t0 > t ? w->cur[m].t0 : w->cur[m].t1);
        }
        if (!any)
            return false;
        p->n = 0;
        for (int m = 0; m < w->nm; m++)
            if (w->live[m] && w->cur[m].t0 <= t) {
                p->m[p->n] = m;
                p->v[p->n] = voxel_index(&st->m[m], w->cur[m].i, w->cur[m].j, w->cur[m].k);
                p->n++;
            }
        p->t0 = t;
        p->t1 = t1;
        w->t = t1;
        if (p->n > 0)
            return true;
    }
}

/* The voxels holding point p and their density there (uniform-step marching). */
static inline void piece_at(const blasi_state *st, vec3 p, piece *pc)
{
    pc->n = 0;
    for (int m = 0; m < st->nm; m++) {
        const blasi_medium *bm = &st->m[m];
        vec3 u = affine3_apply(&bm->w2v, p);
        double f[3] = {floor(u.x), floor(u.y), floor(u.z)};
        if (f[0] < 0.0 || f[1] < 0.0 || f[2] < 0.0 || f[0] >= bm->n[0] || f[1] >= bm->n[1] || f[2] >= bm->n[2])
            continue;
        pc->m[pc->n] = m;
        pc->v[pc->n] = voxel_index(bm, (int)f[0], (int)f[1], (int)f[2]);
        pc->rho[pc->n] = bm->trilinear ? blasi_field_point(st, bm, u) : (double)st->rho[pc->v[pc->n]];
        pc->n++;
    }
}

#endif
