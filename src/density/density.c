/* density.c - what every kind of density field shares (density_impl.h): its placement, its
 * majorant grid's bounds, its active box, the fields any kind answers alike. The kinds
 * (dense_grid.c, nanovdb*.c, blobs.c) build on it; density_kinds.c dispatches to them. */
#include <float.h>
#include <stdlib.h>

#include "core/error.h"
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

void density_crop(density *d, const double lo[3], const double hi[3])
{
    d->crop = true;
    for (int a = 0; a < 3; a++) {
        d->crop_lo[a] = lo[a];
        d->crop_hi[a] = hi[a];
    }
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

density_kind density_get_kind(const density *d) { return d->kind; }
box3 density_bounds(const density *d) { return d->bounds; }

double density_max(const density *d) { return d->rho_max; }

bool density_voxel_dda_begin(const density *d, ray r, double tmin, double tmax, grid_dda *it)
{
    vec3 o = affine3_apply(&d->w2v, r.o), dir = affine3_apply_dir(&d->w2v, r.d);
    return grid_dda_begin(it, d->n, o, dir, tmin, tmax);
}
