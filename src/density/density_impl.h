/* density_impl.h - the density object's layout, shared by the files of src/density only.
 *
 * Every grid kind is placed the same way: an affine map from the world to "voxel space",
 * where voxel (i, j, k) is the half-open box [i, i+1) x [j, j+1) x [k, k+1) and the grid
 * covers [0, n0) x [0, n1) x [0, n2). Kinds differ only in how a voxel's value is fetched.
 * rho is 0 outside that box. Samples sit at voxel centres (i + 1/2, ...); the trilinear
 * filter clamps to the outermost samples, so any point's trilinear value is a convex
 * combination of the voxels within one voxel of its own: the majorant of a cell therefore
 * takes the max over the cell dilated by one voxel.
 *
 * Majorant grid: cells of mcell^3 voxels on a lattice offset by moff voxels (so that NanoVDB
 * cells coincide with its 8^3 leaves): voxel-space point u lies in majorant cell
 * floor((u + moff) / mcell). maj[] holds an upper bound of rho over each cell (already
 * multiplied by any density scale), mino[] (when not NULL) a lower bound: the min over the
 * same voxels, which is what the path tracer's control density uses (docs/path-tracer.md,
 * "Control density"), and mean[] (when not NULL) the mean of the cell's own voxels, the
 * shadow rays' control (docs/path-tracer.md, "Shadow rays: the cell's mean as control"). */
#ifndef BRUME_DENSITY_DENSITY_IMPL_H
#define BRUME_DENSITY_DENSITY_IMPL_H

#include <stddef.h>

#include "density/density.h"

/* Voxels per majorant cell edge: 8^3 = one NanoVDB leaf. Measured in docs/grids.md. */
#define DENSITY_MAJORANT_CELL 4

typedef struct nanovdb_state nanovdb_state;

struct density {
    density_kind kind;
    grid_filter filter;
    int n[3];              /* voxels per axis */
    affine3 w2v, v2w;      /* world -> voxel space and back */
    box3 bounds;           /* world AABB of the voxel box */
    bool crop;             /* rho is 0 outside the voxel-space box [crop_lo, crop_hi] (density_crop) */
    double crop_lo[3], crop_hi[3];
    double rho_min, rho_max;
    uint64_t active;       /* see density_info.active_voxels */
    size_t memory;         /* bytes held */
    /* majorant grid */
    int mcell;
    int moff[3];
    int mn[3];
    float *maj;
    float *mino;           /* NULL: no lower bound (0) */
    float *mean;           /* NULL: none (the shadow rays' control is then mino) */
    int clo[3], chi[3];    /* the box of the cells whose majorant is above 0, cells [clo, chi)
                              (clo = chi = 0 when every cell is 0): rho is 0 outside it, so
                              walks start and end at its faces. Set with maj
                              (density_set_active_box). */
    affine3 w2c;           /* world -> majorant-cell space: (w2v(p) + moff) / mcell */
    double wlo[3], whi[3]; /* the walks' box in cell space: the voxel box there, within the
                              cells [clo, chi); empty (wlo >= whi) when every cell is 0 */
    /* DENSITY_GRID */
    float *data; /* n0 * n1 * n2, x fastest, owned (or borrowed: data_release); for a NanoVDB grid
                    the dense copy of a small box (nanovdb.c), or NULL */
    bool bricked; /* data in 4 x 2 x 2 bricks (a small NanoVDB box's copy): dense_brick_x|y|z */
    int nbx, nby; /* bricks along x and y when bricked */
    void (*data_release)(void *user); /* non-NULL: data is borrowed; called instead of free */
    void *data_user;
    /* DENSITY_NANOVDB */
    nanovdb_state *nano;
    /* DENSITY_BLOBS: voxels are the majorant cells (mcell = 1) */
    blob_field *blobs;
    /* DENSITY_PBRT_CLOUD: voxels are the majorant cells (mcell = 1) over the box [p0, p1] */
    pbrt_cloud cloud;
    unsigned char cloud_perm[256]; /* Perlin's permutation, carried by the GPU's byte copy */
};

/* pbrt_cloud.c: the cloud's density at u in voxel space */
double pbrt_cloud_at(const density *d, vec3 u);

/* Bricked voxel arrays: voxel (i, j, k) of brick (i / 4, j / 2, k / 2) sits at
 * 16 brick + (i % 4) + 4 (j % 2) + 8 (k % 2), bricks x fastest, each brick one 64-byte cache
 * line (the array is 64-byte aligned), so a trilinear lookup's 8 voxels span 2.8 lines on
 * average instead of 4.3 with rows. The offsets are separable: x, y and z parts added. */
#define DENSITY_BRICK_FLOATS 16
static inline size_t dense_brick_x(int i) { return (size_t)(i >> 2) * 16 + (size_t)(i & 3); }
static inline size_t dense_brick_y(const density *d, int j)
{
    return (size_t)(j >> 1) * 16 * (size_t)d->nbx + (size_t)((j & 1) << 2);
}
static inline size_t dense_brick_z(const density *d, int k)
{
    return (size_t)(k >> 1) * 16 * (size_t)d->nbx * (size_t)d->nby + (size_t)((k & 1) << 3);
}

/* Fills maj, mino, mean, mn, mcell, moff: the cells' bounds over the voxels fetch reads, and
 * the mean of each cell's own voxels (density.c).
 * false when out of memory. */
bool density_build_cell_bounds(density *d, double (*fetch)(const density *, int, int, int));

/* Sets clo, chi from maj, and w2c, wlo, whi (density.c); after every change of maj. */
void density_set_active_box(density *d);

/* Fills v2w, w2v and bounds from a voxel-to-world map; false (err_set) if not invertible. */
bool density_set_placement(density *d, const affine3 *voxel_to_world, const char *who);

/* nanovdb.c */
size_t nanovdb_device_put(const nanovdb_state *s, struct dev_arena *a);
double nanovdb_eval_voxel(const density *d, vec3 u);
double nanovdb_voxel(const density *d, int i, int j, int k);
void nanovdb_free(density *d);
/* Hierarchical majorants (nanovdb.c): o, dir in voxel space, [t0, t1] inside the box. */
void nanovdb_majorant_begin(const density *d, vec3 o, vec3 dir, double t0, double t1, majorant_iter *it);


/* Trilinear reconstruction between voxel centres, clamped to the outermost samples, shared
 * by every grid kind: trilinear_corners gives the 2 x 2 x 2 corner voxels around u (voxel
 * space) as ijk[axis][0 or 1] and the weights a[axis]; trilinear_blend mixes the corner
 * values c[x + 2 y + 4 z]. */
static inline int trilinear_clamp(int v, int hi) { return v < 0 ? 0 : (v > hi ? hi : v); }
static inline void trilinear_corners(vec3 u, const int n[3], int ijk[3][2], double a[3])
{
    const double x[3] = {u.x - 0.5, u.y - 0.5, u.z - 0.5};
    for (int ax = 0; ax < 3; ax++) {
        double f = floor(x[ax]);
        int i = (int)f;
        a[ax] = x[ax] - f;
        ijk[ax][0] = trilinear_clamp(i, n[ax] - 1);
        ijk[ax][1] = trilinear_clamp(i + 1, n[ax] - 1);
    }
}
static inline double trilinear_blend(const double c[8], const double a[3])
{
    double c00 = c[0] * (1 - a[0]) + c[1] * a[0], c10 = c[2] * (1 - a[0]) + c[3] * a[0];
    double c01 = c[4] * (1 - a[0]) + c[5] * a[0], c11 = c[6] * (1 - a[0]) + c[7] * a[0];
    double c0 = c00 * (1 - a[1]) + c10 * a[1], c1 = c01 * (1 - a[1]) + c11 * a[1];
    return c0 * (1 - a[2]) + c1 * a[2];
}

/* ---- dense voxel arrays (d->data: a dense grid, or a small NanoVDB box's copy) ---------------- *
 * Inline: density_eval (density.c) reads them at every tentative collision. */
static inline double dense_at(const density *d, int i, int j, int k)
{
    if (d->bricked)
        return (double)d->data[dense_brick_x(i) + dense_brick_y(d, j) + dense_brick_z(d, k)];
    return (double)d->data[(size_t)i + (size_t)d->n[0] * ((size_t)j + (size_t)d->n[1] * (size_t)k)];
}

/* Trilinear between voxel centres, clamped to the outermost samples; u in voxel space. */
static inline double dense_trilinear(const density *d, vec3 u)
{
    int ijk[3][2];
    double a[3], c[8];
    trilinear_corners(u, d->n, ijk, a);
    if (d->bricked) {
        const size_t x0 = dense_brick_x(ijk[0][0]), x1 = dense_brick_x(ijk[0][1]);
        const size_t y0 = dense_brick_y(d, ijk[1][0]), y1 = dense_brick_y(d, ijk[1][1]);
        const size_t z0 = dense_brick_z(d, ijk[2][0]), z1 = dense_brick_z(d, ijk[2][1]);
        const float *v = d->data;
        c[0] = v[x0 + y0 + z0], c[1] = v[x1 + y0 + z0], c[2] = v[x0 + y1 + z0], c[3] = v[x1 + y1 + z0];
        c[4] = v[x0 + y0 + z1], c[5] = v[x1 + y0 + z1], c[6] = v[x0 + y1 + z1], c[7] = v[x1 + y1 + z1];
        return trilinear_blend(c, a);
    }
    for (int q = 0; q < 8; q++)
        c[q] = dense_at(d, ijk[0][q & 1], ijk[1][(q >> 1) & 1], ijk[2][q >> 2]);
    return trilinear_blend(c, a);
}

#endif
