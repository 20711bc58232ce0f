/* dense_grid.c - dense float32 voxel grids (DENSITY_GRID): made from an array, borrowed or
 * owned. Lookups are density.c's, through dense_at and dense_trilinear (density_impl.h),
 * which a small NanoVDB box's dense copy shares. */
#include <stdint.h>
#include <stdlib.h>

#include "core/error.h"
#include "density/dense_float.h"
#include "density/density_impl.h"

static double dense_fetch(const density *d, int i, int j, int k) { return dense_at(d, i, j, k); }

density *density_new_grid_affine(int nx, int ny, int nz, float *data, const affine3 *voxel_to_world,
                                 grid_filter filter)
{
    if (nx < 1 || ny < 1 || nz < 1) {
        err_set(BRUME_ERROR_INVALID_ARGUMENT, "grid: dimensions %d x %d x %d must be positive", nx, ny, nz);
        return NULL;
    }
    size_t n = (size_t)nx * (size_t)ny * (size_t)nz;
    double rho_min = INFINITY, rho_max = 0.0;
    uint64_t active = 0;
    for (size_t i = 0; i < n; i++) {
        if (!isfinite(data[i]) || data[i] < 0.0f) {
            err_set(BRUME_ERROR_RANGE, "grid: voxel %zu (%zu, %zu, %zu) has density %g: need finite and >= 0", i,
                    i % (size_t)nx, i / (size_t)nx % (size_t)ny, i / ((size_t)nx * (size_t)ny), (double)data[i]);
            return NULL;
        }
        rho_min = fmin(rho_min, (double)data[i]);
        rho_max = fmax(rho_max, (double)data[i]);
        active += data[i] > 0.0f;
    }
    density *d = calloc(1, sizeof *d);
    if (!d) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "grid: out of memory");
        return NULL;
    }
    d->kind = DENSITY_GRID;
    d->n[0] = nx;
    d->n[1] = ny;
    d->n[2] = nz;
    d->filter = filter;
    if (!density_set_placement(d, voxel_to_world, "grid")) {
        free(d);
        return NULL;
    }
    d->data = data;
    if (!density_build_cell_bounds(d, dense_fetch)) {
        free(d);
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "grid: out of memory for the majorant grid");
        return NULL;
    }
    d->rho_min = rho_min;
    d->rho_max = rho_max;
    d->active = active;
    d->memory = n * sizeof(float) + 3 * (size_t)d->mn[0] * (size_t)d->mn[1] * (size_t)d->mn[2] * sizeof(float);
    return d;
}

density *density_new_grid(int nx, int ny, int nz, float *data, box3 bounds, grid_filter filter)
{
    if (!(bounds.hi.x > bounds.lo.x && bounds.hi.y > bounds.lo.y && bounds.hi.z > bounds.lo.z) ||
        !v3_isfinite(bounds.lo) || !v3_isfinite(bounds.hi)) {
        err_set(BRUME_ERROR_INVALID_ARGUMENT, "grid: bounds must be a finite box with lo < hi");
        return NULL;
    }
    if (nx < 1 || ny < 1 || nz < 1) {
        err_set(BRUME_ERROR_INVALID_ARGUMENT, "grid: dimensions %d x %d x %d must be positive", nx, ny, nz);
        return NULL;
    }
    vec3 ext = v3_sub(bounds.hi, bounds.lo);
    affine3 v2w = {{ext.x / nx, 0, 0, bounds.lo.x, 0, ext.y / ny, 0, bounds.lo.y, 0, 0, ext.z / nz, bounds.lo.z}};
    density *d = density_new_grid_affine(nx, ny, nz, data, &v2w, filter);
    if (d)
        d->bounds = bounds; /* exactly, not through rounding of the map */
    return d;
}

void density_grid_borrow(density *d, void (*release)(void *user), void *user)
{
    d->data_release = release;
    d->data_user = user;
}

bool density_float_view(const density *d, densityf *v)
{
    /* a dense grid, or a NanoVDB grid small enough for its dense copy and majorant cells
     * (nanovdb.c): density_eval and density_majorant_begin read both alike */
    const bool dense = d->kind == DENSITY_GRID || d->kind == DENSITY_NANOVDB;
    if (!dense || !d->data || !d->maj || d->crop || d->filter != GRID_TRILINEAR)
        return false;
    /* the GPU's stages index voxels and cells in 32 bits (gpu/stages.cu's GRID_INDEX) */
    const size_t nvox = d->bricked
                            ? (size_t)d->nbx * (size_t)d->nby * (size_t)((d->n[2] + 1) / 2) * DENSITY_BRICK_FLOATS
                            : (size_t)d->n[0] * (size_t)d->n[1] * (size_t)d->n[2];
    if (nvox > UINT32_MAX)
        return false;
    for (int a = 0; a < 3; a++) {
        v->n[a] = d->n[a];
        v->mn[a] = d->mn[a];
        v->wlo[a] = (float)d->wlo[a];
        v->whi[a] = (float)d->whi[a];
    }
    for (int q = 0; q < 12; q++) {
        v->w2v[q] = (float)d->w2v.m[q];
        v->w2c[q] = (float)d->w2c.m[q];
    }
    v->data = d->data;
    v->bricked = d->bricked;
    v->nbx = d->nbx;
    v->nby = d->nby;
    v->maj = d->maj;
    v->mino = d->mino;
    v->mean = d->mean;
    return true;
}
