/* dda.h - 3-D digital differential analyzer: the cells of a regular grid a ray crosses,
 * in order, with the ray parameters where it enters and leaves each (Amanatides and Woo,
 * "A Fast Voxel Traversal Algorithm for Ray Tracing", Eurographics 1987).
 *
 * The grid lives in its own "cell space": cell (i, j, k) is the half-open box
 * [i, i+1) x [j, j+1) x [k, k+1), for 0 <= i < n[0] etc. Callers map a world ray into cell
 * space with an affine map, which leaves the ray parameter t unchanged, so the t0, t1 of a
 * step are world ray parameters.
 *
 * Exactness: every plane crossing is computed as (plane - o) * inv_d, from the integer
 * plane coordinate, never accumulated. A brute-force test that intersects each cell's
 * slabs with the same formula finds the same cells and the same t0, t1 bit for bit
 * (tests/test_grid.c). Cells the ray only touches (zero-length overlap: grazing an edge
 * or a corner) are skipped; a ray lying in a cell face belongs to the cell on the face's
 * upper side, as the half-open boxes say. */
#ifndef BRUME_DENSITY_DDA_H
#define BRUME_DENSITY_DDA_H

#include <math.h>
#include <stdbool.h>

#include "core/vec.h"

/* Traversal state; lives on the caller's stack, no allocation. */
typedef struct grid_dda {
    int ijk[3];       /* current cell */
    int step[3];      /* +1, -1 or 0 per axis */
    int n[3];         /* cells per axis */
    double o[3];      /* ray origin in cell space */
    double inv[3];    /* 1 / direction in cell space (0 where the direction is 0) */
    double t_next[3]; /* ray parameter of the next plane crossing per axis (+inf if none) */
    double t, tmax;   /* entry of the current cell; end of the walk */
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

/* The next cell with a positive-length overlap, in increasing t; false when done.
 * The axis to step is picked without branches (the choice is unpredictable, a branch
 * would mispredict about every other step); the state is copied to locals so that the
 * compiler need not reload it after each store to *s. */
static inline bool grid_dda_next(grid_dda *g, grid_dda_step *s)
{
    while (!g->done) {
        const double tx = g->t_next[0], ty = g->t_next[1], tz = g->t_next[2];
        int a = ty < tx;
        double t1 = a ? ty : tx;
        a = tz < t1 ? 2 : a;
        t1 = tz < t1 ? tz : t1;
        const double t0 = g->t;
        s->i = g->ijk[0];
        s->j = g->ijk[1];
        s->k = g->ijk[2];
        s->t0 = t0;
        if (t1 >= g->tmax) {
            t1 = g->tmax;
            g->done = true;
        } else {
            const int step = g->step[a], c = g->ijk[a] + step;
            g->ijk[a] = c;
            if ((unsigned)c >= (unsigned)g->n[a])
                g->done = true;
            else
                g->t_next[a] = ((double)(c + (step > 0)) - g->o[a]) * g->inv[a];
        }
        s->t1 = t1;
        g->t = t1;
        if (t1 > t0)
            return true;
    }
    return false;
}

#endif
