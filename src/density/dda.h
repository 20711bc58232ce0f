/* dda.h - 3-D digital differential analyzer: the cells of a regular grid a ray crosses,
 * in order, with the ray parameters where it enters and leaves each (Amanatides and Woo,
 * "A Fast Voxel Traversal Algorithm for Ray Tracing", Eurographics 1987).
 *
 * The grid lives in its own "cell space": cell (i, j, k) is the half-open box
 * [i, i+1) x [j, j+1) x [k, k+1), for 0 <= i < n[0] etc. Callers map a world ray into cell
 * space with an affine map, which leaves the ray parameter t unchanged, so the t0, t1 of a
 * step are world ray parameters.
 *
 * Accuracy: the first crossing per axis is computed as (plane - o) * inv_d from the integer
 * plane coordinate; later ones are accumulated, t_next += |inv_d| per cell, which keeps
 * the step a handful of instructions with no division and no int-to-double conversion
 * on the loop-carried path. A plane crossing therefore carries a rounding error of a few
 * ulps per cell crossed, about 1e-13 of the ray's length through a 1000-cell grid, and a
 * cell whose overlap is shorter than that can be exchanged for its neighbour. The steps
 * are contiguous (each t0 is the previous t1, bit for bit), so the lengths add up exactly
 * to the clipped interval. tests/test_grid_dda.c checks each cell's overlap length against a
 * brute-force slab intersection of every cell to 1e-9 of the ray's length in the grid
 * (docs/grids.md, "Traversal"). Cells the ray only touches (zero-length overlap: grazing
 * an edge or a corner) are skipped; a ray lying in a cell face belongs to the cell on the
 * face's upper side, as the half-open boxes say. */
#ifndef BRUME_DENSITY_DDA_H
#define BRUME_DENSITY_DDA_H

#include <math.h>
#include <stdbool.h>

#include "core/vec.h"

#if defined(__SSE2__) && !defined(__CUDA_ARCH__)
#include <emmintrin.h>
#endif

/* Traversal state; lives on the caller's stack, no allocation. */
typedef struct grid_dda {
    int ijk[3];       /* current cell */
    int step[3];      /* +1, -1 or 0 per axis */
    int n[3];         /* cells per axis */
    double o[3];      /* ray origin in cell space */
    double d[3];      /* ray direction in cell space */
    double inv[3];    /* 1 / direction in cell space (0 where the direction is 0) */
    double t_next[3]; /* ray parameter of the next plane crossing per axis (+inf if none) */
    double delta[3];  /* |inv|: ray parameter across one cell per axis (+inf if no step) */
    double t, tmax;   /* entry of the current cell; end of the walk */
    double t_in, t_out; /* the interval begin clipped to the grid (grid_dda_restart stays in it) */
    bool done;
} grid_dda;

/* One cell crossed on [t0, t1), t0 < t1. */
typedef struct grid_dda_step {
    int i, j, k;
    double t0, t1;
} grid_dda_step;

/* Starts walking the ray o + t d (cell space) over t in [tmin, tmax] through a grid of
 * n[0] x n[1] x n[2] cells. Returns false (and a finished iterator) when the ray misses. */
bool grid_dda_begin(grid_dda *g, const int n[3], vec3 o, vec3 d, double tmin, double tmax);


/* a < b ? a : b and a > b ? a : b (b when unordered), as selects: a compiler may turn the
 * ternaries into a branch, which mispredicts on data such as a ray's direction */
static inline double dda_min(double a, double b)
{
#if defined(__SSE2__) && !defined(__CUDA_ARCH__)
    return _mm_cvtsd_f64(_mm_min_sd(_mm_set_sd(a), _mm_set_sd(b)));
#else
    return a < b ? a : b;
#endif
}

static inline double dda_max(double a, double b)
{
#if defined(__SSE2__) && !defined(__CUDA_ARCH__)
    return _mm_cvtsd_f64(_mm_max_sd(_mm_set_sd(a), _mm_set_sd(b)));
#else
    return a > b ? a : b;
#endif
}

/* First cell per axis at t0 (inside the clipped interval): the one whose slab interval
 * [enter, exit) holds t0. Start from the rounded position, then correct with the exact
 * crossing formula. Inlined into both callers, its axes unrolled: it runs once per ray. */
static inline __attribute__((always_inline)) bool dda_seed(grid_dda *g, double t0)
{
    bool ok = true;
#pragma GCC unroll 3
    for (int a = 0; a < 3; a++) {
        const double oa = g->o[a];
        const int step = g->step[a], n = g->n[a];
        if (step == 0) {
            g->ijk[a] = (int)floor(oa);
            g->t_next[a] = INFINITY;
            continue;
        }
        const double inv = g->inv[a];
        /* floor, then clamped to [0, n - 1]: the same cell as clamping first and truncating */
        int c = (int)dda_min(dda_max(oa + t0 * g->d[a], 0.0), (double)(n - 1));
        const int up = step > 0; /* plane index of the exit face is c + up */
        double t_exit = ((double)(c + up) - oa) * inv;
        for (int guard = 0; guard < 4; guard++) {
            if (t_exit <= t0 && c + step >= 0 && c + step < n) {
                c += step;
                t_exit = ((double)(c + up) - oa) * inv;
                continue;
            }
            const double t_enter = ((double)(c + 1 - up) - oa) * inv;
            if (!(t_enter > t0 && c - step >= 0 && c - step < n))
                break;
            c -= step;
            t_exit = t_enter; /* the new cell's exit plane c + up is the old one's entry plane */
        }
        g->ijk[a] = c;
        g->t_next[a] = t_exit;
        ok &= g->t_next[a] > t0; /* false: leaves the grid at t0 */
    }
    g->t = t0;
    g->done = !ok;
    return ok;
}

/* The part of a walk's set-up that depends on its direction alone (cell space): rays that
 * share a direction (a sun's parallel rays) make it once (grid_dda_begin_box_dir). */
typedef struct grid_dda_dir {
    double d[3], inv[3], delta[3]; /* as in grid_dda */
    int step[3];
    bool finite; /* d is finite */
} grid_dda_dir;

static inline __attribute__((always_inline)) void grid_dda_dir_make(grid_dda_dir *w, vec3 d)
{
    const double dd[3] = {d.x, d.y, d.z};
    double finite = 0.0; /* x - x is 0 for a finite x and NaN otherwise */
#pragma GCC unroll 3
    for (int a = 0; a < 3; a++) {
        w->d[a] = dd[a];
        finite += dd[a] - dd[a];
        if (dd[a] == 0.0) {
            w->step[a] = 0;
            w->inv[a] = 0.0;
            w->delta[a] = INFINITY;
            continue;
        }
        const double inv = 1.0 / dd[a];
        w->inv[a] = inv;
        w->delta[a] = fabs(inv);
        w->step[a] = dd[a] > 0.0 ? 1 : -1;
    }
    w->finite = finite == 0.0;
}

/* The walk of the direction w (grid_dda_dir_make) over the cells that the ray crosses inside
 * the box [lo, hi) of cell space, 0 <= lo < hi <= n per axis, whose faces need not be cell
 * planes (a grid's voxel box in majorant-cell space). The interval is clipped with the
 * formula the steps use, (plane - o) * inv, so a face on a cell plane ends the walk where
 * the steps would. */
static inline __attribute__((always_inline)) bool grid_dda_begin_clip_dir(grid_dda *g, const int n[3],
                                                                          const double lo[3], const double hi[3],
                                                                          vec3 o, const grid_dda_dir *w, double tmin,
                                                                          double tmax)
{
    const double oo[3] = {o.x, o.y, o.z};
    g->done = true;
    g->t = tmin;
    g->tmax = tmax;
    /* the arguments checked first, all axes at once (one branch, not one per test) */
    bool valid = tmin < tmax;
    double finite = 0.0;
#pragma GCC unroll 3
    for (int a = 0; a < 3; a++) {
        valid &= (n[a] >= 1) & (0.0 <= lo[a]) & (lo[a] < hi[a]) & (hi[a] <= (double)n[a]);
        finite += oo[a] - oo[a];
    }
    if (!(valid & w->finite & (finite == 0.0)))
        return false;
    /* Clip [tmin, tmax] to the box with the same formula as the steps use. */
    double t0 = tmin, t1 = tmax;
#pragma GCC unroll 3
    for (int a = 0; a < 3; a++) {
        g->n[a] = n[a];
        g->o[a] = oo[a];
        g->d[a] = w->d[a];
        g->inv[a] = w->inv[a];
        g->delta[a] = w->delta[a];
        g->step[a] = w->step[a];
        if (w->step[a] == 0) {
            if (!(oo[a] >= lo[a] && oo[a] < hi[a]))
                return false;
            continue;
        }
        double ta = (lo[a] - oo[a]) * w->inv[a], tb = (hi[a] - oo[a]) * w->inv[a];
        /* ordered by selects, not a branch: the sign of a ray's direction is unpredictable */
        const double t_near = dda_min(tb, ta), t_far = dda_max(ta, tb);
        t0 = t_near > t0 ? t_near : t0;
        t1 = t_far < t1 ? t_far : t1;
    }
    if (!(t0 < t1))
        return false;
    g->tmax = g->t_out = t1;
    g->t_in = t0;
    return dda_seed(g, t0);
}

/* grid_dda_begin_box for the direction w made by grid_dda_dir_make: the same walk. */
static inline __attribute__((always_inline)) bool grid_dda_begin_box_dir(grid_dda *g, const int n[3], const int lo[3],
                                                                         const int hi[3], vec3 o, const grid_dda_dir *w,
                                                                         double tmin, double tmax)
{
    const double lo_d[3] = {(double)lo[0], (double)lo[1], (double)lo[2]},
                 hi_d[3] = {(double)hi[0], (double)hi[1], (double)hi[2]};
    return grid_dda_begin_clip_dir(g, n, lo_d, hi_d, o, w, tmin, tmax);
}

/* The same walk restricted to the cells of the box [lo, hi) (0 <= lo < hi <= n per axis),
 * e.g. the box of a grid's non-empty cells: the steps are those of grid_dda_begin that lie
 * in the box. Inline: a caller that begins a walk per ray (blasi's loops) keeps the state
 * in registers instead of passing it through memory to a call, and overlaps the set-up's
 * long chain of dependent operations with its own work. */
static inline __attribute__((always_inline)) bool grid_dda_begin_box(grid_dda *g, const int n[3], const int lo[3],
                                                                     const int hi[3], vec3 o, vec3 d, double tmin,
                                                                     double tmax)
{
    grid_dda_dir w;
    grid_dda_dir_make(&w, d);
    return grid_dda_begin_box_dir(g, n, lo, hi, o, &w, tmin, tmax);
}

/* Walks the same ray again over [t0, t1], a part of the interval g was begun with (an
 * empty-space skipper's jump): no clipping and no division. Returns false (and a finished
 * iterator) when the part is empty. g must come from a successful grid_dda_begin. */
bool grid_dda_restart(grid_dda *g, double t0, double t1);

/* The next cell with a positive-length overlap, in increasing t; false when done.
 * The axis to step is picked without branches (the choice is unpredictable, a branch
 * would mispredict about every other step): with SSE2 the comparisons are masks that
 * select the increments, and all three axes are updated every step, so the loop-carried
 * path is min, compare, and, add. On ties x goes first, then y; the zero-length steps a
 * tie leaves are skipped. */
static inline bool grid_dda_next(grid_dda *g, grid_dda_step *s)
{
    while (!g->done) {
        const double t0 = g->t;
        s->i = g->ijk[0];
        s->j = g->ijk[1];
        s->k = g->ijk[2];
        s->t0 = t0;
#if defined(__SSE2__) && !defined(__CUDA_ARCH__)
        const __m128d X = _mm_set1_pd(g->t_next[0]), Y = _mm_set1_pd(g->t_next[1]), Z = _mm_set1_pd(g->t_next[2]);
        /* three independent masks: x on ties with y or z, y on ties with z */
        const __m128d yz = _mm_min_sd(Y, Z), t1v = _mm_min_sd(X, yz);
        const __m128d mx = _mm_cmple_sd(X, yz), my = _mm_and_pd(_mm_cmplt_sd(Y, X), _mm_cmple_sd(Y, Z));
        const __m128d mz = _mm_cmplt_sd(Z, _mm_min_sd(X, Y));
        double t1 = _mm_cvtsd_f64(t1v);
        const int ax = _mm_cvtsi128_si32(_mm_castpd_si128(mx)), ay = _mm_cvtsi128_si32(_mm_castpd_si128(my)),
                  az = _mm_cvtsi128_si32(_mm_castpd_si128(mz));
        g->t_next[0] = _mm_cvtsd_f64(_mm_add_sd(X, _mm_and_pd(mx, _mm_load_sd(&g->delta[0]))));
        g->t_next[1] = _mm_cvtsd_f64(_mm_add_sd(Y, _mm_and_pd(my, _mm_load_sd(&g->delta[1]))));
        g->t_next[2] = _mm_cvtsd_f64(_mm_add_sd(Z, _mm_and_pd(mz, _mm_load_sd(&g->delta[2]))));
#else
        const double tx = g->t_next[0], ty = g->t_next[1], tz = g->t_next[2];
        const int ax = -(tx <= ty && tx <= tz), ay = -(!ax && ty <= tz), az = -(!ax && !ay);
        double t1 = ax ? tx : (ay ? ty : tz);
        g->t_next[0] = ax ? tx + g->delta[0] : tx;
        g->t_next[1] = ay ? ty + g->delta[1] : ty;
        g->t_next[2] = az ? tz + g->delta[2] : tz;
#endif
        /* masks are 0 or -1: step where set */
        const int i = g->ijk[0] + (g->step[0] & ax), j = g->ijk[1] + (g->step[1] & ay),
                  k = g->ijk[2] + (g->step[2] & az);
        g->ijk[0] = i;
        g->ijk[1] = j;
        g->ijk[2] = k;
        /* leaving the grid before tmax happens only through rounding at the far face */
        g->done = (t1 >= g->tmax) | ((unsigned)i >= (unsigned)g->n[0]) | ((unsigned)j >= (unsigned)g->n[1]) |
                  ((unsigned)k >= (unsigned)g->n[2]);
        t1 = t1 < g->tmax ? t1 : g->tmax;
        s->t1 = t1;
        g->t = t1;
        if (t1 > t0)
            return true;
    }
    return false;
}

#endif
