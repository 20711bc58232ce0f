/* grid.c - dense float32 voxel grids: lookup (nearest or trilinear) and majorants. */
#include <stdlib.h>

#include "core/error.h"
#include "density/density.h"

struct density {
    density_kind kind;
    /* DENSITY_GRID */
    int nx, ny, nz;      /* voxels per axis */
    float *data;         /* nx * ny * nz, x fastest, owned */
    box3 bounds;         /* world box covered by the grid */
    vec3 inv_cell;       /* voxels per world unit, per axis */
    grid_filter filter;
    double rho_max;
};

density *density_new_grid(int nx, int ny, int nz, float *data, box3 bounds, grid_filter filter)
{
    if (nx < 1 || ny < 1 || nz < 1) {
        err_set(BRUME_ERROR_INVALID_ARGUMENT, "grid: dimensions %d x %d x %d must be positive", nx, ny, nz);
        return NULL;
    }
    if (!(bounds.hi.x > bounds.lo.x && bounds.hi.y > bounds.lo.y && bounds.hi.z > bounds.lo.z) ||
        !v3_isfinite(bounds.lo) || !v3_isfinite(bounds.hi)) {
        err_set(BRUME_ERROR_INVALID_ARGUMENT, "grid: bounds must be a finite box with lo < hi");
        return NULL;
    }
    size_t n = (size_t)nx * (size_t)ny * (size_t)nz;
    double rho_max = 0.0;
    for (size_t i = 0; i < n; i++) {
        if (!isfinite(data[i]) || data[i] < 0.0f) {
            err_set(BRUME_ERROR_RANGE, "grid: voxel %zu has density %g: need finite and >= 0", i, (double)data[i]);
            return NULL;
        }
        rho_max = fmax(rho_max, (double)data[i]);
    }
    density *d = calloc(1, sizeof *d);
    if (!d) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "grid: out of memory");
        return NULL;
    }
    d->kind = DENSITY_GRID;
    d->nx = nx;
    d->ny = ny;
    d->nz = nz;
    d->data = data;
    d->bounds = bounds;
    vec3 ext = v3_sub(bounds.hi, bounds.lo);
    d->inv_cell = v3(nx / ext.x, ny / ext.y, nz / ext.z);
    d->filter = filter;
    d->rho_max = rho_max;
    return d;
}

void density_release(density *d)
{
    if (!d)
        return;
    free(d->data);
    free(d);
}

density_kind density_get_kind(const density *d) { return d->kind; }
box3 density_bounds(const density *d) { return d->bounds; }
double density_max(const density *d) { return d->rho_max; }

static inline double grid_at(const density *d, int i, int j, int k)
{
    i = i < 0 ? 0 : (i >= d->nx ? d->nx - 1 : i);
    j = j < 0 ? 0 : (j >= d->ny ? d->ny - 1 : j);
    k = k < 0 ? 0 : (k >= d->nz ? d->nz - 1 : k);
    return (double)d->data[(size_t)i + (size_t)d->nx * ((size_t)j + (size_t)d->ny * (size_t)k)];
}

static double grid_eval(const density *d, vec3 p)
{
    if (!box3_contains(d->bounds, p))
        return 0.0;
    /* continuous voxel coordinates: voxel i spans [i, i + 1) */
    double x = (p.x - d->bounds.lo.x) * d->inv_cell.x;
    double y = (p.y - d->bounds.lo.y) * d->inv_cell.y;
    double z = (p.z - d->bounds.lo.z) * d->inv_cell.z;
    if (d->filter == GRID_NEAREST)
        return grid_at(d, (int)x, (int)y, (int)z);
    /* samples at cell centres i + 1/2; clamp to the edge samples outside them */
    x -= 0.5;
    y -= 0.5;
    z -= 0.5;
    double fx = floor(x), fy = floor(y), fz = floor(z);
    int i = (int)fx, j = (int)fy, k = (int)fz;
    double ax = x - fx, ay = y - fy, az = z - fz;
    double c00 = grid_at(d, i, j, k) * (1 - ax) + grid_at(d, i + 1, j, k) * ax;
    double c10 = grid_at(d, i, j + 1, k) * (1 - ax) + grid_at(d, i + 1, j + 1, k) * ax;
    double c01 = grid_at(d, i, j, k + 1) * (1 - ax) + grid_at(d, i + 1, j, k + 1) * ax;
    double c11 = grid_at(d, i, j + 1, k + 1) * (1 - ax) + grid_at(d, i + 1, j + 1, k + 1) * ax;
    double c0 = c00 * (1 - ay) + c10 * ay, c1 = c01 * (1 - ay) + c11 * ay;
    return c0 * (1 - az) + c1 * az;
}

double density_eval(const density *d, vec3 p)
{
    switch (d->kind) {
    case DENSITY_GRID: return grid_eval(d, p);
    }
    return 0.0;
}

void density_majorant_begin(const density *d, ray r, double tmin, double tmax, majorant_iter *it)
{
    double t0, t1;
    it->d = d;
    it->r = r;
    it->done = !box3_intersect(d->bounds, r, tmin, tmax, &t0, &t1) || !(t1 > t0);
    it->t = it->done ? tmax : t0;
    it->tmax = it->done ? tmax : t1;
}

/* One segment over the whole box with the global maximum. */
bool majorant_next(majorant_iter *it, majorant_seg *seg)
{
    if (it->done)
        return false;
    seg->t0 = it->t;
    seg->t1 = it->tmax;
    seg->rho_maj = it->d->rho_max;
    it->done = true;
    return true;
}
