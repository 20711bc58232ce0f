/* blobs.h - density as a sum of gaussian blobs (Stam 1994, Eq. 3 and Appendix A):
 *
 *   rho_mean(x) = sum_i m_i W_h_i(x - x_i),   W_h(x) = exp(-|x|^2 / (2 h^2)) / ((2 pi)^(3/2) h^3)
 *
 * with a bounding-volume hierarchy over the blobs for ray and point queries. Each blob is
 * truncated at the radius R_i = cutoff h_i (default 3: there W = exp(-4.5) W(0) = 1.1 % of
 * the peak, and 2.9 % of the mass lies beyond; a cutoff of 4 costs 1.8 times more blobs per
 * ray for 0.03 % of the peak); every query, the renderers and the majorants use the same
 * truncation, so `path`, `single` and `stam` render the same field.
 *
 * The kernel may instead be a tabulated radial profile (blob_kernel.h, `stam.kernel`):
 * rho_i(x) = m_i W(|x - x_i| / h_i) / h_i^3, truncated at min(cutoff, s_max) h_i; every
 * query, the majorants, the voxelizer and Stam's statistics then use that W.
 *
 * A blob field may drift with a constant velocity: blob_field_at_time moves the centres to
 * x_i + v t (Figure 7's clouds). Fields are immutable once built and may be shared by
 * threads. */
#ifndef BRUME_DENSITY_BLOBS_H
#define BRUME_DENSITY_BLOBS_H

#include <stdbool.h>
#include <stddef.h>

#include "brume.h"
#include "core/bvh.h"
#include "core/vec.h"
#include "density/blob_kernel.h"
#include "density/density.h"
#include "density/randfield.h"

#define BLOB_DEFAULT_CUTOFF 3.0
/* Limits of a blob field from a file (docs/scene-format.md, "Limits"): at most this many
 * blobs; each counts BLOB_BYTES against the memory budget (blob, derived terms, hierarchy
 * and its build); and the blob-cell pairs of the majorant grid (blob_majorant_pairs), the
 * work of building it, at most BLOB_MAX_PAIRS (about 2 s). */
#define BLOB_MAX_COUNT (1 << 24)
#define BLOB_BYTES 256
#define BLOB_MAX_PAIRS 3e7

/* One blob: centre x (world), mass m (world units^3: the integral of its density), and
 * radius h (standard deviation of the gaussian kernel, world units). */
typedef struct blob {
    vec3 x;
    double m, h;
} blob;

typedef struct blob_field {
    blob *b;          /* n blobs, owned, in BVH leaf order */
    double *peak;     /* m_i / ((2 pi)^(3/2) h_i^3), or m_i W(0) / h_i^3 with a kernel table: the
                         mean density at the centre */
    double *inv2h2;   /* 1 / (2 h_i^2) */
    double *R2;       /* (blob_field_cutoff(f) h_i)^2 */
    int n;
    double cutoff;    /* as given; the truncation is blob_field_cutoff(f) */
    blob_kernel *kernel; /* NULL: the gaussian; else a tabulated W, shared (reference counted).
                            The GPU needs it and its w[] copied with the field */
    vec3 velocity;    /* world units per unit time */
    double time;      /* centres are at x_i(0) + velocity time */
    box3 bounds;      /* union of the truncation spheres */
    bvh_node *nodes;  /* the hierarchy's nodes (core/bvh.h), root at 0; leaves index b */
    int nnodes;
    bool use_bvh;     /* false: every query scans all blobs (for benchmarks) */
} blob_field;

/* A field of n blobs (copied; n >= 1, finite, m >= 0, h > 0) truncated at cutoff h (> 0).
 * NULL with err_set() naming `who` on bad blobs or no memory. */
blob_field *blob_field_new(const blob *b, int n, double cutoff, const char *who);
void blob_field_release(blob_field *f);
/* How many (blob, cell) pairs building the majorant grid of majorant_cells cells along the
 * longest axis would visit for these n blobs truncated at cutoff h: O(n), before building. */
double blob_majorant_pairs(const blob *b, int n, double cutoff, int majorant_cells);
/* Moves every blob to x_i + velocity t (t measured from the positions given to _new) and
 * rebuilds the hierarchy. BRUME_OK or an out-of-memory error. */
brume_status blob_field_at_time(blob_field *f, vec3 velocity, double t);

struct dev_arena;
/* Copies f for the GPU (core/arena.h); its offset, or ARENA_NULL when out of memory. */
size_t blob_field_device_put(const blob_field *f, struct dev_arena *a);

/* Sets the field's kernel (NULL: the gaussian; k is retained) and rebuilds the hierarchy
 * for the new truncation. BRUME_OK or an out-of-memory error. */
brume_status blob_field_set_kernel(blob_field *f, blob_kernel *k);
/* The same for the field of a DENSITY_BLOBS density, whose majorants it rebuilds; only while
 * loading, before the field is shared (as density_blobs_at_time). */
brume_status density_blobs_set_kernel(density *d, blob_kernel *k);

/* The truncation radius in units of h: the cutoff, or the kernel table's end if smaller. */
static inline double blob_field_cutoff(const blob_field *f)
{
    return f->kernel && f->kernel->s_max < f->cutoff ? f->kernel->s_max : f->cutoff;
}

/* Blob i's mean density m_i W_h_i at squared distance r2 from its centre, not truncated. */
static inline double blob_density_r2(const blob_field *f, int i, double r2)
{
    if (f->kernel)
        return f->peak[i] * blob_kernel_eval(f->kernel, sqrt(r2) / f->b[i].h);
    return f->peak[i] * exp(-r2 * f->inv2h2[i]);
}

/* Mean density at p (Eq. 3), over the truncated blobs. */
double blob_field_mean(const blob_field *f, vec3 p);
/* A single blob's truncated mean density at p. */
static inline double blob_mean_at(const blob_field *f, int i, vec3 p)
{
    vec3 dx = v3_sub(p, f->b[i].x);
    double r2 = v3_dot(dx, dx);
    return r2 < f->R2[i] ? blob_density_r2(f, i, r2) : 0.0;
}

/* Called for every blob whose truncation sphere meets the segment o + t d, t in [tmin,
 * tmax] (d unit): u = (x_i - o).d is the parameter of the ray point closest to the centre
 * (Stam's u_i, possibly outside [tmin, tmax]) and d2 the squared distance of the centre
 * from the line (Stam's d_i^2). Order is unspecified. */
typedef void (*blob_visit_fn)(int i, double u, double d2, void *user);
void blob_field_query_ray(const blob_field *f, vec3 o, vec3 d, double tmin, double tmax, blob_visit_fn fn,
                          void *user);

/* Samples the field at the centres of an n0 x n1 x n2 grid of cells over `bounds` (x fastest)
 * into out: the mean, plus, when q is not NULL, one explicit realization of Stam's random
 * blobs rho = sum_i (rho_i + sigma_i Q) with sigma_i^2 = eps F_eta(rho_i) (Section 4),
 * Q read at x - q_shift, clamped to >= 0 (a density cannot be negative; docs/stam.md). */
void blob_field_voxelize(const blob_field *f, const int n[3], box3 bounds, const randfield *q, vec3 q_shift,
                         double eps, double eta, float *out);

/* The field as a dense trilinear grid (a new density owned by the caller) of `resolution`
 * cells along the longest axis of its bounds (at least 1 on the others), sampled by
 * blob_field_voxelize with the drift shift of the field's own time. NULL on failure with
 * err_set() naming `who`. */
density *blob_field_grid(const blob_field *f, int resolution, const randfield *q, double eps, double eta,
                         const char *who);

/* Stam's clamping function F_eta(t) = min(t, eta). */
static inline double stam_clamp(double t, double eta) { return t < eta ? t : eta; }

/* ---- generators (blob_gen.c) ------------------------------------------------------------ */

/* A growable array of blobs. */
typedef struct blob_list {
    blob *b;
    int n, cap;
} blob_list;
brume_status blob_list_push(blob_list *l, blob b);
void blob_list_free(blob_list *l);

/* A cloud after Gardner and Stam (Section 7): `count` blobs at random in the ellipsoid of
 * semi-axes `radii` around `center`. With s = the blob's normalized distance from the centre
 * (0 at the centre, 1 on the surface), its radius is h = h_max + (h_min - h_max) s and its
 * peak density rho_peak (1 - s^2)^falloff, so size and mass fall with distance. */
typedef struct blob_cloud_params {
    vec3 center, radii;
    int count;
    double h_min, h_max;
    double density; /* rho_peak: peak mean density of a blob at the centre */
    double falloff; /* >= 0 */
    uint64_t seed;
} blob_cloud_params;
brume_status blob_gen_cloud(const blob_cloud_params *p, blob_list *out);

/* `clouds` clouds whose centres are uniform in `box`, semi-axes drawn between `radii_min` and
 * `radii_max` per axis, each a blob_gen_cloud of `count` blobs with the template's h and
 * density scaled by the cloud's size relative to radii_max. */
brume_status blob_gen_cluster(const blob_cloud_params *tmpl, box3 box, vec3 radii_min, vec3 radii_max, int clouds,
                              blob_list *out);

/* A flame (Figure 8): `count` blobs along the axis `up` from `base` to height `height`,
 * scattered sideways within a radius narrowing from `radius` at the base to 0 at the top,
 * their size h and peak density falling with height. Only the blobs whose relative height
 * lies in [band_lo, band_hi) are emitted, so that bands can get their own emission color. */
typedef struct blob_fire_params {
    vec3 base, up;
    double height, radius;
    int count;
    double h;       /* blob radius at the base */
    double density; /* peak density at the base */
    double band_lo, band_hi;
    uint64_t seed;
} blob_fire_params;
brume_status blob_gen_fire(const blob_fire_params *p, blob_list *out);

#endif
