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


/* Trilinear reconstruction and the dense voxel arrays' lookups (trilinear_corners,
 * trilinear_blend, dense_at, dense_trilinear), written once over the real type
 * (density/trilinear_body.h): here in double over a density; the float stages instantiate it
 * over their float view of a dense grid (render/track_float.h), whose fields have the same
 * names. */
#define REAL_F 0
#define TRILINEAR_GRID density
#include "density/trilinear_body.h"
#undef TRILINEAR_GRID
#undef REAL_F
static inline size_t dense_brick_y(const density *d, int j) { return dense_brick_yn(d->nbx, j); }
static inline size_t dense_brick_z(const density *d, int k) { return dense_brick_zn(d->nbx, d->nby, k); }

#endif
