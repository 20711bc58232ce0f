/* density.h - density fields rho(x) >= 0 (unitless) and their majorants along rays.
 *
 * A density field answers two questions, kept apart (shared/STYLE.md):
 *   - density_eval: rho at a world point (0 outside the field's bounds);
 *   - majorant iteration: along a ray, consecutive segments [t0, t1) on each of which
 *     rho <= rho_maj. Estimators (delta, ratio tracking, ray marching) consume segments and
 *     never look at how the field is stored.
 * Fields are immutable after construction and may be shared by threads. */
#ifndef BRUME_DENSITY_DENSITY_H
#define BRUME_DENSITY_DENSITY_H

#include <stdbool.h>
#include <stdint.h>

#include "core/vec.h"

typedef enum density_kind {
    DENSITY_GRID /* dense float32 voxel grid */
} density_kind;

/* How a grid is read between its samples. */
typedef enum grid_filter {
    GRID_NEAREST,  /* constant over each voxel, as in Blasi et al. */
    GRID_TRILINEAR /* trilinear between cell-centred samples */
} grid_filter;

typedef struct density density;

/* A dense grid of nx * ny * nz values, x fastest (offset i + nx (j + ny k)), covering the
 * world box `bounds`; sample (i, j, k) sits at the centre of its cell. Takes ownership of
 * data (malloc'd) on success; on failure returns NULL with err_set() and frees nothing.
 * Values must be finite and >= 0. */
density *density_new_grid(int nx, int ny, int nz, float *data, box3 bounds, grid_filter filter);
void density_release(density *d);

density_kind density_get_kind(const density *d);
/* rho(p), p in world units; 0 outside the bounds. */
double density_eval(const density *d, vec3 p);
/* World box outside which rho = 0. */
box3 density_bounds(const density *d);
/* max rho over the field. */
double density_max(const density *d);

/* One stretch of a ray with rho <= rho_maj on [t0, t1). */
typedef struct majorant_seg {
    double t0, t1;  /* ray parameters, t0 < t1 */
    double rho_maj; /* upper bound of rho on the segment (unitless) */
} majorant_seg;

/* Iterator state; lives on the caller's stack. Fields are private to density/. */
typedef struct majorant_iter {
    const density *d;
    ray r;
    double t, tmax;
    bool done;
} majorant_iter;

/* Starts iterating the segments of r in [tmin, tmax] inside the field. */
void density_majorant_begin(const density *d, ray r, double tmin, double tmax, majorant_iter *it);
/* The next segment in increasing t; false when the ray has left the field or reached tmax. */
bool majorant_next(majorant_iter *it, majorant_seg *seg);

/* A procedural cloud for the default scene: fBm value noise (seeded) carved by an
 * ellipsoidal falloff and a threshold, sampled on an n^3 grid over `bounds`, max rho 1. */
density *density_new_procedural_cloud(int n, uint64_t seed, box3 bounds);

#endif
