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

#define REAL_F 0
#include "density/dda_body.h"
#undef REAL_F
#define REAL_F 1
#include "density/dda_body.h"
#undef REAL_F

/* Starts walking the ray o + t d (cell space) over t in [tmin, tmax] through a grid of
 * n[0] x n[1] x n[2] cells. Returns false (and a finished iterator) when the ray misses. */
bool grid_dda_begin(grid_dda *g, const int n[3], vec3 o, vec3 d, double tmin, double tmax);


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

#endif
