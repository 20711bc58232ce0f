/* density.h - density fields rho(x) >= 0 (unitless) and their majorants along rays.
 *
 * A density field answers two questions, kept apart:
 *   - density_eval: rho at a world point (0 outside the field's bounds);
 *   - majorant iteration: along a ray, consecutive segments [t0, t1) on each of which
 *     rho <= rho_maj. Estimators (delta, ratio tracking, ray marching) consume segments and
 *     never look at how the field is stored.
 * Fields are immutable after construction and may be shared by threads. */
#ifndef BRUME_DENSITY_DENSITY_H
#define BRUME_DENSITY_DENSITY_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "brume.h"
#include "core/vec.h"
#include "core/xform.h"
#include "density/dda.h"

/* The closed set of representations; each operation is one switch over it. */
typedef enum density_kind {
    DENSITY_GRID,   /* dense float32 voxel grid (grid.c) */
    DENSITY_NANOVDB, /* sparse float grid in a NanoVDB buffer, read through PNanoVDB (nanovdb.c) */
    DENSITY_BLOBS,   /* the mean of a sum of gaussian blobs, Stam 1994 Eq. 3 (blobs.c) */
    DENSITY_PBRT_CLOUD /* pbrt-v4's procedural cloud, evaluated where looked up (pbrt_cloud.c) */
} density_kind;

/* pbrt-v4's CloudMedium density: its parameters, the box [p0, p1] in the cloud's own space. */
typedef struct pbrt_cloud {
    double density, wispiness, frequency; /* pbrt's defaults: 1, 1, 5 */
    double p0[3], p1[3];                  /* pbrt's defaults: (0, 0, 0), (1, 1, 1) */
} pbrt_cloud;



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
/* The same grid placed by an affine map: voxel (i, j, k) covers the box
 * [i, i+1) x [j, j+1) x [k, k+1) of "voxel space", and voxel_to_world maps voxel space to
 * the world (any invertible affine map: scale, rotation, shear, translation). Ownership and
 * failure as density_new_grid. */
density *density_new_grid_affine(int nx, int ny, int nz, float *data, const affine3 *voxel_to_world,
                                 grid_filter filter);
/* A sparse grid from a NanoVDB buffer holding one float grid (nanovdb.c). Takes ownership
 * of buf (malloc'd, 8-byte aligned, size bytes) on success; on failure returns NULL with
 * err_set() naming `name` and frees nothing. The field is the voxels of the grid's index
 * bounding box, placed by the grid's own map, then by `extra` (may be NULL); values are
 * multiplied by scale (> 0). Every value that a lookup can reach is checked finite and
 * >= 0, and every read is bounds-checked, so a hostile buffer cannot crash a lookup.
 * Majorants come from the tree (nanovdb.c): nothing is allocated over the bounding box;
 * max_memory bounds the majorant tables built here (bytes; 0 = no limit). */
density *density_new_nanovdb(void *buf, size_t size, grid_filter filter, const affine3 *extra, double scale,
                             size_t max_memory, const char *name);
/* NanoVDB grids whose index box holds at most this many voxels (default 2^23) get a grid of
 * 4^3-voxel cells with exact bounds; larger ones the tree's nested majorants. Returns the
 * previous limit. For tests and benchmarks that compare the two; set it before loading. */
uint64_t nanovdb_set_cell_grid_limit(uint64_t voxels);
/* One field per component of a NanoVDB buffer: count = 1 needs a float grid (out[0]);
 * count = 3 gives the three components of a vec3f grid (or the float grid three times)
 * in out[0..2], sharing the buffer, which they own together on success (freed with the
 * last). Other arguments as density_new_nanovdb. */
/* any_sign: values may be negative (velocity components: medium.h); only finiteness is
 * checked, and the majorants are then meaningless (such a field is only looked up).
 * edge_zero (trilinear only): pbrt-v4's NanoVDB lookup. Voxels beyond the index box read the
 * tree (its background), so the field falls to 0 one voxel past the outer samples, and it is
 * cut to NanoVDB's world box, index [min, max + 1]: the voxel box is one voxel larger on
 * every side, cropped (density_crop) to voxel space [3/2, n - 1/2]. */
bool density_new_nanovdb_fields(void *buf, size_t size, int count, grid_filter filter, const affine3 *extra,
                                double scale, size_t max_memory, bool any_sign, bool edge_zero, const char *name,
                                density **out);
/* The mean density of a blob field (density/blobs.h), with a majorant grid of at most
 * majorant_cells cells along the longest axis of its bounds; "voxels" are those cells.
 * Takes ownership of f on success; on failure returns NULL with err_set() and frees nothing. */
typedef struct blob_field blob_field;
density *density_new_blobs(blob_field *f, int majorant_cells);
/* The blob field of a DENSITY_BLOBS density, else NULL. */
blob_field *density_get_blobs(const density *d);
/* Moves the blobs to time t at the given velocity (blob_field_at_time) and rebuilds the
 * majorants; only while loading, before the field is shared. */
brume_status density_blobs_at_time(density *d, vec3 velocity, double t);
/* Marks a DENSITY_GRID's values as borrowed: release then calls release(user) instead of
 * free()ing them. The values are only ever read. */
void density_grid_borrow(density *d, void (*release)(void *user), void *user);
void density_release(density *d);
/* For loaders, before the field is shared: replaces the placement of any grid kind by
 * voxel_to_world (bounds follow). false with err_set() when the map is not invertible. */
bool density_place(density *d, const affine3 *voxel_to_world);
/* For loaders, before the field is shared: rho is 0 outside the voxel-space box [lo, hi]
 * (closed), within the voxel box. Walks keep the voxel box and its majorants, which still
 * bound rho: the grid's own values beyond the cut are to be 0 where its minorants reach
 * (the zero layer around a grid with pbrt-v4's edges, scene_json_density.c). */
void density_crop(density *d, const double lo[3], const double hi[3]);

density_kind density_get_kind(const density *d);
/* Bytes of a NanoVDB buffer that d shares with the other components of its grid (0 for
 * other kinds): memory_bytes counts it in each of them. */
size_t density_shared_bytes(const density *d);
/* rho(p), p in world units; 0 outside the bounds. */
double density_eval(const density *d, vec3 p);
/* World box outside which rho = 0. */
box3 density_bounds(const density *d);
/* World box outside which a majorant walk (density_majorant_begin) finds no segment: the
 * non-empty cells within the voxel box (the voxel box for a large NanoVDB box's tree),
 * widened by far more than rounding can move the walk's clip. box3_empty() when every cell
 * is 0. A ray that misses it meets nothing of the field. */
box3 density_reach_bounds(const density *d);
/* max rho over the field. */
double density_max(const density *d);

/* What `brume info` prints. */
typedef struct density_info {
    density_kind kind;
    grid_filter filter;
    int n[3];               /* voxels per axis (the index bounding box for NanoVDB) */
    box3 bounds;            /* world box */
    affine3 voxel_to_world; /* placement; voxel (i, j, k) spans [i, i+1) x ... in voxel space */
    double rho_min, rho_max;
    size_t memory_bytes;    /* voxel data + majorant grid */
    uint64_t active_voxels; /* voxels with rho > 0 (dense); the tree's active count (NanoVDB) */
    int majorant_cell;      /* voxels per majorant cell edge */
    int majorant_n[3];      /* majorant cells per axis (a cell grid; for the tree's majorants,
                               majorant_n[0] counts the 128^3-voxel blocks that have bounds of
                               their own) */
    bool majorant_tree;     /* NanoVDB with a large box: majorants from the tree's nested walk */
} density_info;
void density_get_info(const density *d, density_info *info);

/* The value stored for voxel (i, j, k), 0 <= i < n[0] ...; before any filtering. */
double density_voxel(const density *d, int i, int j, int k);

/* Walks exactly the voxels that r crosses in [tmin, tmax], with entry and exit parameters
 * (Blasi's per-voxel walk). Use grid_dda_next(it, &step) from density/dda.h. Returns false
 * when the ray misses the grid. */
bool density_voxel_dda_begin(const density *d, ray r, double tmin, double tmax, grid_dda *it);

/* One stretch of a ray with rho_min <= rho <= rho_maj on [t0, t1). */
typedef struct majorant_seg {
    double t0, t1;  /* ray parameters, t0 < t1 */
    double rho_maj; /* upper bound of rho on the segment (unitless) */
    double rho_min; /* lower bound of rho on the segment (unitless, >= 0; 0 when none is known) */
    double rho_ctl; /* a typical rho on the segment, in [rho_min, rho_maj]: the shadow rays'
                       control (the cell's mean; rho_min when none is known) */
} majorant_seg;

/* Iterator state; lives on the caller's stack. Fields are private to density/ but by_ctl.
 * It walks the field's coarse majorant grid with a DDA (dense grids, blobs) or the
 * NanoVDB tree's regions, blocks and leaf cells with three nested DDAs (nanovdb.c), and
 * merges consecutive cells of equal majorant into one segment. */
typedef struct majorant_iter {
    grid_dda dda;        /* over majorant cells; NanoVDB: over 4096^3 regions */
    const float *maj;    /* cell majorants, x fastest */
    const float *mino;   /* cell minorants, or NULL (0) */
    const float *mean;   /* cell means, or NULL (the minorant) */
    int mn[3];           /* majorant cells per axis */
    majorant_seg next;   /* looked-ahead segment not returned yet */
    bool has_next;
    uint32_t cells;      /* majorant cells walked so far (--stats; not counted on the GPU) */
    bool by_ctl;         /* the one field a caller sets (after density_majorant_begin; false
                            there): a merged segment's rho_ctl is the length-weighted mean of its
                            cells' (walks that use the control), not the first cell's */
    /* NanoVDB only */
    const struct nanovdb_state *nano; /* NULL for the other kinds */
    int level;           /* 0: regions, 1: blocks in a region, 2: leaf cells in a block */
    grid_dda sub[2];     /* blocks, leaf cells */
    int32_t base[2][3];  /* first region; first block of the current region */
    vec3 o_idx, d_idx;   /* the ray in index space (voxel idx spans [idx, idx + 1)) */
    const float *table;  /* the current block's leaf-cell bounds */
} majorant_iter;

/* Starts iterating the segments of r in [tmin, tmax] inside the field. Stretches where rho
 * is 0 may be left out: a cell grid's walk covers only the box of its non-empty cells. */
void density_majorant_begin(const density *d, ray r, double tmin, double tmax, majorant_iter *it);
/* The next segment in increasing t; false when the ray has left the field or reached tmax.
 * Inline (density/majorant_body.h, the cell grid's walk written once for the double and the
 * float stages): it runs once per majorant cell a ray crosses, the tracking loop's most
 * frequent step on thin media. */
static inline __attribute__((always_inline)) bool majorant_cell_next(majorant_iter *it, majorant_seg *seg);
#define REAL_F 0
#include "density/majorant_body.h"
#undef REAL_F
/* The NanoVDB tree's next leaf cell (nanovdb.c). */
bool nanovdb_majorant_cell(majorant_iter *it, majorant_seg *seg);

static inline __attribute__((always_inline)) bool majorant_cell_next(majorant_iter *it, majorant_seg *seg)
{
    if (it->nano) {
        bool more = nanovdb_majorant_cell(it, seg);
#if !defined(__CUDA_ARCH__)
        it->cells += more ? 1u : 0u;
#endif
        return more;
    }
    return majorant_grid_cell(it, seg);
}

/* Majorants of rho moved by any displacement of length <= radius (world units): a field
 * whose majorant walk bounds rho(x - u) for every |u| <= radius (moved_majorant.c derives
 * it), with no values (density_eval gives 0) and no lower bound or control (0). For velocity
 * motion blur (medium.h). local, when not NULL, bounds the displacement of the points of a
 * world box (<= radius; user passed along): each cell is then dilated by its own bound.
 * NULL with err_set() when out of memory or when the radius spans more than 1e6 voxels. */
typedef double (*moved_radius_fn)(const void *user, box3 world_box);
density *density_new_moved_majorant(const density *rho, double radius, moved_radius_fn local, const void *user);
/* An upper bound of |density_eval(d, p)| for p in the world box (d's values of any sign):
 * from its majorant cells when it has a cell grid, else its whole range (moved_majorant.c). */
double density_abs_bound_in_box(const density *d, box3 world_box);

/* Copies d with everything it points to into a (core/arena.h) for the GPU; returns the
 * copy's offset (ARENA_NULL on failure: a->failed). Blob fields are not copied (the GPU
 * refuses them: gpu/device_scene.c). */
struct dev_arena;
size_t density_device_put(const density *d, struct dev_arena *a);

/* A procedural cloud for the default scene: fBm value noise (seeded) carved by an
 * ellipsoidal falloff and a threshold, sampled on an n^3 grid over `bounds`, max rho 1. */
density *density_new_procedural_cloud(int n, uint64_t seed, box3 bounds);
/* pbrt-v4's cloud (pbrt_cloud.c) over its box [p0, p1], placed at first with the box where
 * it is (density_place moves it); NULL (err_set) for an empty box or an out-of-range value. */
density *density_new_pbrt_cloud(const pbrt_cloud *c);
/* pbrt-v4's Perlin noise (util/noise.cpp) with a permutation of 0 .. 255, and the cloud's
 * density at p in its own space: what density_eval gives, for the tests. */
double pbrt_noise(const unsigned char *perm, vec3 p);
double pbrt_cloud_eval(const pbrt_cloud *c, const unsigned char *perm, vec3 p);

#endif
