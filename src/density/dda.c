/* dda.c - setting up the 3-D DDA (see dda.h): box clipping, the first cell and its exact
 * plane crossings. */
#include "density/dda.h"

/* a < b ? a : b and a > b ? a : b (b when unordered), as selects: a compiler may turn the
 * ternaries into a branch, which mispredicts on data such as a ray's direction */
static inline double dda_min(double a, double b)
{
#if defined(__SSE2__)
    return _mm_cvtsd_f64(_mm_min_sd(_mm_set_sd(a), _mm_set_sd(b)));
#else
    return a < b ? a : b;
#endif
}

static inline double dda_max(double a, double b)
{
#if defined(__SSE2__)
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
        double x = oa + t0 * g->d[a];
        x = x < 0.0 ? 0.0 : (x > (double)(n - 1) ? (double)(n - 1) : x);
        int c = (int)x;
        const int up = step > 0; /* plane index of the exit face is c + up */
        for (int guard = 0; guard < 4; guard++) {
            double t_exit = ((double)(c + up) - oa) * inv;
            double t_enter = ((double)(c + 1 - up) - oa) * inv;
            if (t_exit <= t0 && c + step >= 0 && c + step < n)
                c += step;
            else if (t_enter > t0 && c - step >= 0 && c - step < n)
                c -= step;
            else
                break;
        }
        g->ijk[a] = c;
        g->t_next[a] = ((double)(c + up) - oa) * inv;
        ok &= g->t_next[a] > t0; /* false: leaves the grid at t0 */
    }
    g->t = t0;
    g->done = !ok;
    return ok;
}

bool grid_dda_restart(grid_dda *g, double t0, double t1)
{
    t0 = t0 > g->t_in ? t0 : g->t_in;
    t1 = t1 < g->t_out ? t1 : g->t_out;
    g->done = true;
    if (!(t0 < t1))
        return false;
    g->tmax = t1; /* t_in, t_out stay: a later run may lie anywhere in them */
    return dda_seed(g, t0);
}

bool grid_dda_begin(grid_dda *g, const int n[3], vec3 o, vec3 d, double tmin, double tmax)
{
    static const int zero[3] = {0, 0, 0};
    return grid_dda_begin_box(g, n, zero, n, o, d, tmin, tmax);
}

bool grid_dda_begin_box(grid_dda *g, const int n[3], const int lo[3], const int hi[3], vec3 o, vec3 d, double tmin,
                        double tmax)
{
    const double oo[3] = {o.x, o.y, o.z}, dd[3] = {d.x, d.y, d.z};
    g->done = true;
    g->t = tmin;
    g->tmax = tmax;
    /* the arguments checked first, all axes at once (one branch, not one per test) */
    bool valid = tmin < tmax;
#pragma GCC unroll 3
    for (int a = 0; a < 3; a++)
        valid &= (n[a] >= 1) & (isfinite(oo[a]) != 0) & (isfinite(dd[a]) != 0) & (0 <= lo[a]) & (lo[a] < hi[a]) &
                 (hi[a] <= n[a]);
    if (!valid)
        return false;
    /* Clip [tmin, tmax] to the box [lo, hi) with the same formula as the steps use. */
    double t0 = tmin, t1 = tmax;
#pragma GCC unroll 3
    for (int a = 0; a < 3; a++) {
        g->n[a] = n[a];
        g->o[a] = oo[a];
        g->d[a] = dd[a];
        if (dd[a] == 0.0) {
            g->step[a] = 0;
            g->inv[a] = 0.0;
            g->delta[a] = INFINITY;
            if (!(oo[a] >= (double)lo[a] && oo[a] < (double)hi[a]))
                return false;
            continue;
        }
        double inv = 1.0 / dd[a];
        g->inv[a] = inv;
        g->delta[a] = fabs(inv);
        g->step[a] = dd[a] > 0.0 ? 1 : -1;
        double ta = ((double)lo[a] - oo[a]) * inv, tb = ((double)hi[a] - oo[a]) * inv;
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
