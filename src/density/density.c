/* density.c - a density field whatever its kind (density_kind: dense grid, NanoVDB grid,
 * blobs): placement, majorant grid and its walk, lookup, release, the GPU's copy; one
 * switch per operation over the kind. The kinds: dense_grid.c, nanovdb.c, blobs.c. */
#include <float.h>
#include <stdlib.h>

#include "core/error.h"
#include "density/blobs.h"
#include "density/density_impl.h"
#include "core/arena.h"

/* ---- placement and majorants, shared by every kind ---------------------------------------- */

bool density_set_placement(density *d, const affine3 *voxel_to_world, const char *who)
{
    if (!affine3_invert(voxel_to_world, &d->w2v)) {
        err_set(BRUME_ERROR_RANGE, "%s: placement transform is singular or not finite", who);
        return false;
    }
    d->v2w = *voxel_to_world;
    d->bounds = affine3_apply_box(voxel_to_world, (box3){v3(0, 0, 0), v3(d->n[0], d->n[1], d->n[2])});
    if (d->maj) /* placed again after the majorants were built */
        density_set_active_box(d);
    return true;
}

bool density_place(density *d, const affine3 *voxel_to_world)
{
    return density_set_placement(d, voxel_to_world, "grid");
}

/* Max and min over each majorant cell of the voxels a lookup inside it can read: the cell
 * itself (nearest) or the cell dilated by one voxel (trilinear). A trilinear value is a
 * convex combination of those voxels, so it lies between the two. Cells of
 * DENSITY_MAJORANT_CELL^3 voxels from the box's corner; fetch(d, i, j, k) reads voxel
 * (i, j, k) of the box, already scaled. */
bool density_build_cell_bounds(density *d, double (*fetch)(const density *, int, int, int))
{
    int C = DENSITY_MAJORANT_CELL, r = d->filter == GRID_TRILINEAR ? 1 : 0;
    size_t count = 1;
    for (int a = 0; a < 3; a++) {
        d->moff[a] = 0;
        d->mn[a] = (d->n[a] + C - 1) / C;
        count *= (size_t)d->mn[a];
    }
    d->mcell = C;
    d->maj = malloc(count * sizeof *d->maj);
    d->mino = malloc(count * sizeof *d->mino);
    d->mean = malloc(count * sizeof *d->mean);
    if (!d->maj || !d->mino || !d->mean) {
        free(d->maj);
        free(d->mino);
        free(d->mean);
        d->maj = d->mino = d->mean = NULL;
        return false;
    }
    for (int ck = 0; ck < d->mn[2]; ck++)
        for (int cj = 0; cj < d->mn[1]; cj++)
            for (int ci = 0; ci < d->mn[0]; ci++) {
                int lo[3] = {ci * C - r, cj * C - r, ck * C - r};
                int hi[3] = {(ci + 1) * C + r, (cj + 1) * C + r, (ck + 1) * C + r};
                for (int a = 0; a < 3; a++) {
                    lo[a] = lo[a] < 0 ? 0 : lo[a];
                    hi[a] = hi[a] > d->n[a] ? d->n[a] : hi[a];
                }
                double m = 0.0, mi = INFINITY, sum = 0.0;
                for (int k = lo[2]; k < hi[2]; k++)
                    for (int j = lo[1]; j < hi[1]; j++)
                        for (int i = lo[0]; i < hi[0]; i++) {
                            double v = fetch(d, i, j, k);
                            m = v > m ? v : m;
                            mi = v < mi ? v : mi;
                        }
                /* the mean of the cell's own voxels (not its dilation) */
                int own = 0;
                for (int k = ck * C; k < (ck + 1) * C && k < d->n[2]; k++)
                    for (int j = cj * C; j < (cj + 1) * C && j < d->n[1]; j++)
                        for (int i = ci * C; i < (ci + 1) * C && i < d->n[0]; i++, own++)
                            sum += fetch(d, i, j, k);
                size_t c = (size_t)ci + (size_t)d->mn[0] * ((size_t)cj + (size_t)d->mn[1] * (size_t)ck);
                /* rounded outwards to float */
                float fm = (float)m, fmi = (float)mi;
                d->maj[c] = (double)fm < m ? nextafterf(fm, INFINITY) : fm;
                d->mino[c] = (double)fmi > mi ? nextafterf(fmi, -INFINITY) : fmi;
                /* between the two bounds (any value is unbiased; this one keeps the residual
                 * within the rate track_collisions derives from them) */
                float fme = own ? (float)(sum / own) : d->mino[c];
                d->mean[c] = fme < d->mino[c] ? d->mino[c] : (fme > d->maj[c] ? d->maj[c] : fme);
            }
    density_set_active_box(d);
    return true;
}

void density_set_active_box(density *d)
{
    int lo[3] = {d->mn[0], d->mn[1], d->mn[2]}, hi[3] = {0, 0, 0};
    for (int ck = 0; ck < d->mn[2]; ck++)
        for (int cj = 0; cj < d->mn[1]; cj++) {
            const float *row = d->maj + (size_t)d->mn[0] * ((size_t)cj + (size_t)d->mn[1] * (size_t)ck);
            for (int ci = 0; ci < d->mn[0]; ci++) {
                if (!(row[ci] > 0.0f))
                    continue;
                const int c[3] = {ci, cj, ck};
                for (int a = 0; a < 3; a++) {
                    lo[a] = c[a] < lo[a] ? c[a] : lo[a];
                    hi[a] = c[a] + 1 > hi[a] ? c[a] + 1 : hi[a];
                }
            }
        }
    /* The walks' map and box (density_majorant_begin): one affine map and one clip from
     * world to cell space, the voxel box's faces (where rho ends) and the active cells'. */
    const double s = 1.0 / d->mcell;
    for (int a = 0; a < 3; a++) {
        d->clo[a] = hi[0] > 0 ? lo[a] : 0;
        d->chi[a] = hi[0] > 0 ? hi[a] : 0;
        for (int c = 0; c < 3; c++)
            d->w2c.m[4 * a + c] = d->w2v.m[4 * a + c] * s;
        d->w2c.m[4 * a + 3] = (d->w2v.m[4 * a + 3] + d->moff[a]) * s;
        d->wlo[a] = fmax((double)d->clo[a], d->moff[a] * s);
        d->whi[a] = fmin((double)d->chi[a], (d->n[a] + d->moff[a]) * s);
    }
}

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
    }
    free(d->maj);
    free(d->mino);
    free(d->mean);
    free(d);
}

density_kind density_get_kind(const density *d) { return d->kind; }
box3 density_bounds(const density *d) { return d->bounds; }

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
double density_max(const density *d) { return d->rho_max; }

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
    }
    return 0.0;
}

double density_eval(const density *d, vec3 p)
{
    vec3 u = affine3_apply(&d->w2v, p);
    /* half-open voxel box; the negated test also rejects NaN */
    if (!(u.x >= 0.0 && u.x < d->n[0] && u.y >= 0.0 && u.y < d->n[1] && u.z >= 0.0 && u.z < d->n[2]))
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
    }
    return 0.0;
}

/* ---- traversal ---------------------------------------------------------------------------- */

bool density_voxel_dda_begin(const density *d, ray r, double tmin, double tmax, grid_dda *it)
{
    vec3 o = affine3_apply(&d->w2v, r.o), dir = affine3_apply_dir(&d->w2v, r.d);
    return grid_dda_begin(it, d->n, o, dir, tmin, tmax);
}

void density_majorant_begin(const density *d, ray r, double tmin, double tmax, majorant_iter *it)
{
    it->maj = d->maj;
    it->mino = d->mino;
    it->mean = d->mean;
    it->has_next = false;
    it->cells = 0;
    it->by_ctl = false;
    it->nano = NULL;
    for (int a = 0; a < 3; a++)
        it->mn[a] = d->mn[a];
    if (d->kind == DENSITY_NANOVDB && !d->maj) {
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
     * time on cloud64 when it took two maps and two clips (docs/performance.md). */
    grid_dda_dir w;
    grid_dda_dir_make(&w, affine3_apply_dir(&d->w2c, r.d));
    if (!grid_dda_begin_clip_dir(&it->dda, d->mn, d->wlo, d->whi, affine3_apply(&d->w2c, r.o), &w, tmin, tmax))
        it->dda.done = true;
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
