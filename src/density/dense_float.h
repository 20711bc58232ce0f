/* dense_float.h - a float view of a dense grid (DENSITY_GRID) for the single-precision
 * stages (render/track_float.h; docs/gpu.md, "Single precision"): its voxels and majorant
 * cells are the grid's own float arrays, its maps rounded to float. The lookups and the
 * majorant walk are the double ones' bodies instantiated in float (density/trilinear_body.h,
 * density/majorant_body.h, density/dda_body.h), so both precisions run one estimator. */
#ifndef BRUME_DENSITY_DENSE_FLOAT_H
#define BRUME_DENSITY_DENSE_FLOAT_H

#include <stddef.h>
#include <stdint.h>

#include "density/density.h"

typedef struct densityf {
    int n[3];            /* voxels per axis */
    const float *data;   /* the grid's voxels (density_impl.h's layout, bricked or rows) */
    bool bricked;
    int nbx, nby;
    float w2v[12];       /* world -> voxel space, 3 x 4 row-major */
    float w2c[12];       /* world -> majorant-cell space */
    int mn[3];           /* majorant cells per axis */
    float wlo[3], whi[3]; /* the walks' box in cell space (density_impl.h) */
    const float *maj, *mino, *mean; /* the cells' bounds and means */
} densityf;

/* The float view of d; false unless d is a trilinear dense grid with majorant cells, or a
 * NanoVDB grid held as such (its small box's dense copy), uncropped, of fewer than 2^32
 * voxels: the float stages do not cover a NanoVDB tree's walk, blobs, procedural fields or
 * nearest filtering. */
bool density_float_view(const density *d, densityf *v);

/* one segment of a float majorant walk, and the walk (density.h's majorant_seg and
 * majorant_iter, the cell grid's fields alone) */
typedef struct majorant_segf {
    float t0, t1, rho_maj, rho_min, rho_ctl;
} majorant_segf;
typedef struct majorant_iterf {
    grid_ddaf dda;
    const float *maj, *mino, *mean;
    int mn[3];
    majorant_segf next;
    bool has_next;
    uint32_t cells;
    bool by_ctl;
} majorant_iterf;

static inline vec3f affine3f_apply(const float m[12], vec3f p)
{
    return v3f(m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3], m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7],
               m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11]);
}
static inline vec3f affine3f_apply_dir(const float m[12], vec3f d)
{
    return v3f(m[0] * d.x + m[1] * d.y + m[2] * d.z, m[4] * d.x + m[5] * d.y + m[6] * d.z,
               m[8] * d.x + m[9] * d.y + m[10] * d.z);
}

#define REAL_F 1
#define TRILINEAR_GRID densityf
#include "density/trilinear_body.h"
#undef TRILINEAR_GRID
static inline __attribute__((always_inline)) bool majorant_cell_nextf(majorant_iterf *it, majorant_segf *seg);
#include "density/majorant_body.h"
#undef REAL_F
static inline __attribute__((always_inline)) bool majorant_cell_nextf(majorant_iterf *it, majorant_segf *seg)
{
    return majorant_grid_cellf(it, seg);
}

/* rho at the world point p (density_eval's dense grid, in float) */
static inline __attribute__((always_inline)) float densityf_eval(const densityf *d, vec3f p)
{
    vec3f u = affine3f_apply(d->w2v, p);
    /* half-open voxel box; the negated test also rejects NaN */
    if (!(u.x >= 0.0f && u.x < (float)d->n[0] && u.y >= 0.0f && u.y < (float)d->n[1] && u.z >= 0.0f &&
          u.z < (float)d->n[2]))
        return 0.0f;
    return dense_trilinearf(d, u);
}

/* The majorant walk of r over [0, tmax] (density_majorant_begin's cell grid, in float). */
static inline __attribute__((always_inline)) void densityf_majorant_begin(const densityf *d, rayf r, float tmax,
                                                                          majorant_iterf *it)
{
    majorant_grid_beginf(it, d->maj, d->mino, d->mean, d->mn, d->wlo, d->whi, affine3f_apply(d->w2c, r.o),
                         affine3f_apply_dir(d->w2c, r.d), 0.0f, tmax);
}

#endif
