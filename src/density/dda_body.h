/* dda_body.h - the 3-D DDA's state and steps (density/dda.h) over one real type
 * (core/real_names.h): grid_dda, grid_dda_next ... in double, grid_ddaf, grid_dda_nextf ... in
 * float (the GPU's single-precision majorant walk). The SSE2 selects are the double
 * instantiation's on the CPU; the float one and the GPU's take the portable selects. */
#include "core/real_names.h"

/* Traversal state; lives on the caller's stack, no allocation. */
typedef struct RN(grid_dda) {
    int ijk[3];       /* current cell */
    int step[3];      /* +1, -1 or 0 per axis */
    int n[3];         /* cells per axis */
    R o[3];      /* ray origin in cell space */
    R d[3];      /* ray direction in cell space */
    R inv[3];    /* 1 / direction in cell space (0 where the direction is 0) */
    R t_next[3]; /* ray parameter of the next plane crossing per axis (+inf if none) */
    R delta[3];  /* |inv|: ray parameter across one cell per axis (+inf if no step) */
    R t, tmax;   /* entry of the current cell; end of the walk */
    R t_in, t_out; /* the interval begin clipped to the grid (grid_dda_restart stays in it) */
    bool done;
} RN(grid_dda);

/* One cell crossed on [t0, t1), t0 < t1. */
typedef struct RN(grid_dda_step) {
    int i, j, k;
    R t0, t1;
} RN(grid_dda_step);

/* a < b ? a : b and a > b ? a : b (b when unordered), as selects: a compiler may turn the
 * ternaries into a branch, which mispredicts on data such as a ray's direction */
static inline R RN(dda_min)(R a, R b)
{
#if defined(__SSE2__) && !defined(__CUDA_ARCH__) && !REAL_F
    return _mm_cvtsd_f64(_mm_min_sd(_mm_set_sd(a), _mm_set_sd(b)));
#else
    return a < b ? a : b;
#endif
}

static inline R RN(dda_max)(R a, R b)
{
#if defined(__SSE2__) && !defined(__CUDA_ARCH__) && !REAL_F
    return _mm_cvtsd_f64(_mm_max_sd(_mm_set_sd(a), _mm_set_sd(b)));
#else
    return a > b ? a : b;
#endif
}

/* First cell per axis at t0 (inside the clipped interval): the one whose slab interval
 * [enter, exit) holds t0. Start from the rounded position, then correct with the exact
 * crossing formula. Inlined into both callers, its axes unrolled: it runs once per ray. */
static inline __attribute__((always_inline)) bool RN(dda_seed)(RN(grid_dda) *g, R t0)
{
    bool ok = true;
#pragma GCC unroll 3
    for (int a = 0; a < 3; a++) {
        const R oa = g->o[a];
        const int step = g->step[a], n = g->n[a];
        if (step == 0) {
            g->ijk[a] = (int)R_FLOOR(oa);
            g->t_next[a] = R_INF;
            continue;
        }
        const R inv = g->inv[a];
        /* floor, then clamped to [0, n - 1]: the same cell as clamping first and truncating */
        int c = (int)RN(dda_min)(RN(dda_max)(oa + t0 * g->d[a], RC(0.0)), (R)(n - 1));
        const int up = step > 0; /* plane index of the exit face is c + up */
        R t_exit = ((R)(c + up) - oa) * inv;
        for (int guard = 0; guard < 4; guard++) {
            if (t_exit <= t0 && c + step >= 0 && c + step < n) {
                c += step;
                t_exit = ((R)(c + up) - oa) * inv;
                continue;
            }
            const R t_enter = ((R)(c + 1 - up) - oa) * inv;
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
typedef struct RN(grid_dda_dir) {
    R d[3], inv[3], delta[3]; /* as in grid_dda */
    int step[3];
    bool finite; /* d is finite */
} RN(grid_dda_dir);

static inline __attribute__((always_inline)) void RN(grid_dda_dir_make)(RN(grid_dda_dir) *w, RN(vec3) d)
{
    const R dd[3] = {d.x, d.y, d.z};
    R finite = RC(0.0); /* x - x is 0 for a finite x and NaN otherwise */
#pragma GCC unroll 3
    for (int a = 0; a < 3; a++) {
        w->d[a] = dd[a];
        finite += dd[a] - dd[a];
        if (dd[a] == RC(0.0)) {
            w->step[a] = 0;
            w->inv[a] = RC(0.0);
            w->delta[a] = R_INF;
            continue;
        }
        const R inv = RC(1.0) / dd[a];
        w->inv[a] = inv;
        w->delta[a] = R_FABS(inv);
        w->step[a] = dd[a] > RC(0.0) ? 1 : -1;
    }
    w->finite = finite == RC(0.0);
}

/* The walk of the direction w (grid_dda_dir_make) over the cells that the ray crosses inside
 * the box [lo, hi) of cell space, 0 <= lo < hi <= n per axis, whose faces need not be cell
 * planes (a grid's voxel box in majorant-cell space). The interval is clipped with the
 * formula the steps use, (plane - o) * inv, so a face on a cell plane ends the walk where
 * the steps would. */
static inline __attribute__((always_inline)) bool RN(grid_dda_begin_clip_dir)(RN(grid_dda) *g, const int n[3],
                                                                          const R lo[3], const R hi[3],
                                                                          RN(vec3) o, const RN(grid_dda_dir) *w, R tmin,
                                                                          R tmax)
{
    const R oo[3] = {o.x, o.y, o.z};
    g->done = true;
    g->t = tmin;
    g->tmax = tmax;
    /* the arguments checked first, all axes at once (one branch, not one per test) */
    bool valid = tmin < tmax;
    R finite = RC(0.0);
#pragma GCC unroll 3
    for (int a = 0; a < 3; a++) {
        valid &= (n[a] >= 1) & (RC(0.0) <= lo[a]) & (lo[a] < hi[a]) & (hi[a] <= (R)n[a]);
        finite += oo[a] - oo[a];
    }
    if (!(valid & w->finite & (finite == RC(0.0))))
        return false;
    /* Clip [tmin, tmax] to the box with the same formula as the steps use. */
    R t0 = tmin, t1 = tmax;
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
        R ta = (lo[a] - oo[a]) * w->inv[a], tb = (hi[a] - oo[a]) * w->inv[a];
        /* ordered by selects, not a branch: the sign of a ray's direction is unpredictable */
        const R t_near = RN(dda_min)(tb, ta), t_far = RN(dda_max)(ta, tb);
        t0 = t_near > t0 ? t_near : t0;
        t1 = t_far < t1 ? t_far : t1;
    }
    if (!(t0 < t1))
        return false;
    g->tmax = g->t_out = t1;
    g->t_in = t0;
    return RN(dda_seed)(g, t0);
}

/* The next cell with a positive-length overlap, in increasing t; false when done.
 * The axis to step is picked without branches (the choice is unpredictable, a branch
 * would mispredict about every other step): with SSE2 the comparisons are masks that
 * select the increments, and all three axes are updated every step, so the loop-carried
 * path is min, compare, and, add. On ties x goes first, then y; the zero-length steps a
 * tie leaves are skipped. */
static inline bool RN(grid_dda_next)(RN(grid_dda) *g, RN(grid_dda_step) *s)
{
    while (!g->done) {
        const R t0 = g->t;
        s->i = g->ijk[0];
        s->j = g->ijk[1];
        s->k = g->ijk[2];
        s->t0 = t0;
#if defined(__SSE2__) && !defined(__CUDA_ARCH__) && !REAL_F
        const __m128d X = _mm_set1_pd(g->t_next[0]), Y = _mm_set1_pd(g->t_next[1]), Z = _mm_set1_pd(g->t_next[2]);
        /* three independent masks: x on ties with y or z, y on ties with z */
        const __m128d yz = _mm_min_sd(Y, Z), t1v = _mm_min_sd(X, yz);
        const __m128d mx = _mm_cmple_sd(X, yz), my = _mm_and_pd(_mm_cmplt_sd(Y, X), _mm_cmple_sd(Y, Z));
        const __m128d mz = _mm_cmplt_sd(Z, _mm_min_sd(X, Y));
        R t1 = _mm_cvtsd_f64(t1v);
        const int ax = _mm_cvtsi128_si32(_mm_castpd_si128(mx)), ay = _mm_cvtsi128_si32(_mm_castpd_si128(my)),
                  az = _mm_cvtsi128_si32(_mm_castpd_si128(mz));
        g->t_next[0] = _mm_cvtsd_f64(_mm_add_sd(X, _mm_and_pd(mx, _mm_load_sd(&g->delta[0]))));
        g->t_next[1] = _mm_cvtsd_f64(_mm_add_sd(Y, _mm_and_pd(my, _mm_load_sd(&g->delta[1]))));
        g->t_next[2] = _mm_cvtsd_f64(_mm_add_sd(Z, _mm_and_pd(mz, _mm_load_sd(&g->delta[2]))));
#else
        const R tx = g->t_next[0], ty = g->t_next[1], tz = g->t_next[2];
        const int ax = -(tx <= ty && tx <= tz), ay = -(!ax && ty <= tz), az = -(!ax && !ay);
        R t1 = ax ? tx : (ay ? ty : tz);
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

#include "core/real_names_end.h"
