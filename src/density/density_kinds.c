/* density_kinds.c - a density field whatever its kind (density_kind: dense grid, NanoVDB grid,
 * blobs): lookup, majorant walk, bounds, info, release, the GPU's copy; one switch per
 * operation over the kind, above the kinds (dense_grid.c, nanovdb*.c, blobs.c) and what
 * they share (density.c), so that the field is built in one direction. */
#include <float.h>
#include <stdlib.h>

#include "core/arena.h"
#include "core/error.h"
#include "density/blobs.h"
#include "density/density_impl.h"

void density_release(density *d)
{
    if (!d)
        return;
    switch (d->kind) {
    case DENSITY_GRID:
        if (d->data_release)
            d->data_release(d->data_user);
        else
            free(d->data);
        break;
    case DENSITY_NANOVDB:
        nanovdb_free(d);
        free(d->data); /* a small box's dense copy, or NULL */
        break;
    case DENSITY_BLOBS: blob_field_release(d->blobs); break;
    case DENSITY_PBRT_CLOUD: break;
    }
    free(d->maj);
    free(d->mino);
    free(d->mean);
    free(d);
}

box3 density_reach_bounds(const density *d)
{
    if (d->kind == DENSITY_NANOVDB && !d->maj)
        return d->bounds;
    if (!(d->wlo[0] < d->whi[0] && d->wlo[1] < d->whi[1] && d->wlo[2] < d->whi[2]))
        return box3_empty();
    /* the walk's box, from cell space to voxel space, to the world */
    const double C = d->mcell;
    box3 b = affine3_apply_box(&d->v2w, (box3){v3(d->wlo[0] * C - d->moff[0], d->wlo[1] * C - d->moff[1],
                                                  d->wlo[2] * C - d->moff[2]),
                                               v3(d->whi[0] * C - d->moff[0], d->whi[1] * C - d->moff[1],
                                                  d->whi[2] * C - d->moff[2])});
    /* the clip runs in cell space, this box in the world: a margin of 1e-9 of the box's size
     * and place covers the ulps between the two */
    double size = 0.0;
    const double lo[3] = {b.lo.x, b.lo.y, b.lo.z}, hi[3] = {b.hi.x, b.hi.y, b.hi.z};
    for (int a = 0; a < 3; a++)
        size = fmax(size, fmax(hi[a] - lo[a], fmax(fabs(lo[a]), fabs(hi[a]))));
    const double margin = 1e-9 * size;
    return (box3){v3_sub(b.lo, v3(margin, margin, margin)), v3_add(b.hi, v3(margin, margin, margin))};
}
void density_get_info(const density *d, density_info *info)
{
    info->kind = d->kind;
    info->filter = d->filter;
    info->bounds = d->bounds;
    info->voxel_to_world = d->v2w;
    info->rho_min = d->rho_min;
    info->rho_max = d->rho_max;
    info->memory_bytes = d->memory;
    info->active_voxels = d->active;
    info->majorant_cell = d->mcell;
    info->majorant_tree = d->kind == DENSITY_NANOVDB && !d->maj;
    for (int a = 0; a < 3; a++) {
        info->n[a] = d->n[a];
        info->majorant_n[a] = d->mn[a];
    }
}

double density_voxel(const density *d, int i, int j, int k)
{
    switch (d->kind) {
    case DENSITY_GRID: return dense_at(d, i, j, k);
    case DENSITY_NANOVDB: return d->data ? dense_at(d, i, j, k) : nanovdb_voxel(d, i, j, k);
    case DENSITY_BLOBS: return blob_field_mean(d->blobs, affine3_apply(&d->v2w, v3(i + 0.5, j + 0.5, k + 0.5)));
    case DENSITY_PBRT_CLOUD: return pbrt_cloud_at(d, v3(i + 0.5, j + 0.5, k + 0.5));
    }
    return 0.0;
}

double density_eval(const density *d, vec3 p)
{
    vec3 u = affine3_apply(&d->w2v, p);
    /* half-open voxel box; the negated test also rejects NaN */
    if (!(u.x >= 0.0 && u.x < d->n[0] && u.y >= 0.0 && u.y < d->n[1] && u.z >= 0.0 && u.z < d->n[2]))
        return 0.0;
    if (d->crop && !(u.x >= d->crop_lo[0] && u.x <= d->crop_hi[0] && u.y >= d->crop_lo[1] && u.y <= d->crop_hi[1] &&
                     u.z >= d->crop_lo[2] && u.z <= d->crop_hi[2]))
        return 0.0;
    if (d->data) { /* a dense grid, or a small NanoVDB box's dense copy (nanovdb.c) */
        if (d->filter == GRID_NEAREST)
            return dense_at(d, (int)u.x, (int)u.y, (int)u.z);
        return dense_trilinear(d, u);
    }
    switch (d->kind) {
    case DENSITY_GRID: return 0.0; /* has data */
    case DENSITY_NANOVDB: return nanovdb_eval_voxel(d, u);
    case DENSITY_BLOBS: return blob_field_mean(d->blobs, p);
    case DENSITY_PBRT_CLOUD: return pbrt_cloud_at(d, u);
    }
    return 0.0;
}

/* ---- traversal ---------------------------------------------------------------------------- */

void density_majorant_begin(const density *d, ray r, double tmin, double tmax, majorant_iter *it)
{
    it->nano = NULL;
    if (d->kind == DENSITY_NANOVDB && !d->maj) {
        it->maj = d->maj;
        it->mino = d->mino;
        it->mean = d->mean;
        it->has_next = false;
        it->cells = 0;
        it->by_ctl = false;
        for (int a = 0; a < 3; a++)
            it->mn[a] = d->mn[a];
        /* Clip to the voxel box in voxel space; the tree's walks take it from there. */
        vec3 o = affine3_apply(&d->w2v, r.o), dir = affine3_apply_dir(&d->w2v, r.d);
        box3 vbox = {v3(0, 0, 0), v3(d->n[0], d->n[1], d->n[2])};
        double t0, t1;
        if (!box3_intersect(vbox, (ray){o, dir, r.time}, tmin, tmax, &t0, &t1) || !(t1 > t0)) {
            it->dda.done = true;
            return;
        }
        nanovdb_majorant_begin(d, o, dir, t0, t1, it);
        return;
    }
    /* A cell grid: one map to cell space and one clip, to the voxel box within the box of
     * non-empty cells (clipped as the steps cross planes: no sliver of an empty cell at its
     * faces). The walk's set-up runs once per flight and shadow ray: a tenth of a render's
     * time on cloud64 when it took two maps and two clips (docs/performance.md). The walk is
     * the float stages' too (density/majorant_body.h). */
    majorant_grid_begin(it, d->maj, d->mino, d->mean, d->mn, d->wlo, d->whi, affine3_apply(&d->w2c, r.o),
                        affine3_apply_dir(&d->w2c, r.d), tmin, tmax);
}

size_t density_device_put(const density *d, dev_arena *a)
{
    size_t at = arena_put(a, d, sizeof *d);
    if (at == ARENA_NULL)
        return at;
    const size_t cells = (size_t)d->mn[0] * (size_t)d->mn[1] * (size_t)d->mn[2];
    ARENA_PUT_MEMBER(a, at, density, maj, d->maj, cells * sizeof(float));
    ARENA_PUT_MEMBER(a, at, density, mino, d->mino, cells * sizeof(float));
    ARENA_PUT_MEMBER(a, at, density, mean, d->mean, cells * sizeof(float));
    size_t nvox = d->bricked ? (size_t)d->nbx * (size_t)d->nby * (size_t)((d->n[2] + 1) / 2) * DENSITY_BRICK_FLOATS
                             : (size_t)d->n[0] * (size_t)d->n[1] * (size_t)d->n[2];
    ARENA_PUT_MEMBER(a, at, density, data, d->data, nvox * sizeof(float));
    arena_ptr(a, at + offsetof(density, data_release), ARENA_NULL); /* the host's to call */
    arena_ptr(a, at + offsetof(density, data_user), ARENA_NULL);
    arena_ptr(a, at + offsetof(density, nano), d->nano ? nanovdb_device_put(d->nano, a) : ARENA_NULL);
    arena_ptr(a, at + offsetof(density, blobs), d->blobs ? blob_field_device_put(d->blobs, a) : ARENA_NULL);
    return at;
}
