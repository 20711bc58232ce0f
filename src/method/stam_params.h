/* stam_params.h - the options of Stam's stochastic renderer, "stam.KEY" through
 * brume_scene_set_option (a scene file's "stam" object, docs/scene-format.md): the
 * statistics of the perturbation, the renderer's options and the voxelization of blob
 * fields for the reference renderers. */
#ifndef BRUME_METHOD_STAM_PARAMS_H
#define BRUME_METHOD_STAM_PARAMS_H

#include <stdbool.h>
#include <stdint.h>

#include "brume.h"
#include "core/color.h"
#include "core/vec.h"
#include "density/randfield.h"

/* The blobs' kernel: Appendix A's gaussian or a radial profile from a file (Section 6.1). */
typedef enum stam_kernel_kind { STAM_KERNEL_GAUSSIAN, STAM_KERNEL_TABLE } stam_kernel_kind;
#define STAM_PATH_MAX 1024

typedef struct stam_params {
    double eps;     /* magnitude of the density variance: sigma^2 = eps F_eta(mean), >= 0 */
    double eta;     /* clamping value of F_eta, > 0 (INFINITY: no clamping) */
    double alpha;   /* correlation length of Q, world units, > 0 */
    int lattice;    /* Q's periodic lattice: lattice^3 points (paper: 32); 0 = covering the blob
                       fields (stam_randfield_params) */
    double cell;    /* Q's lattice spacing, world units; 0 = alpha / 3 */
    uint64_t seed;  /* Q's realization */
    double time;    /* the scene's own time, seconds, added to the frame time: blobs drift to
                       x + v t, Q evolves */
    double rate;    /* Q's base angular frequency in time, radians per unit time */
    color ambient;  /* constant source term standing in for multiple scattering */
    int steps;      /* steps of the average-source-function quadrature per ray */
    int light_grid; /* cells along the longest axis of the light-transparency cache; 0 = exact shadow rays */
    bool bvh;       /* false: scan every blob for each ray (benchmarks) */
    bool paper;     /* variant "paper": Eq. 12 and 13 as printed (Var T_i = K_Q(0) eps I_F with
                       K_Q(0) = (2 pi)^(-3/2) alpha^-3, realized with a Q of variance K_Q(0)) and
                       J-bar's shadows from the mean density; false = "corrected" (docs/stam.md) */
    stam_kernel_kind kernel;   /* the blobs' radial kernel W (Eq. 3; blob_kernel.h) */
    char kernel_file[STAM_PATH_MAX]; /* stam.kernel = table: the file of W(r / h) */
    bool overlap_joint;        /* overlapping blobs' perturbations with their joint covariance
                                  (docs/stam.md); false = independent, as printed */
    int voxelize_resolution;   /* > 0: at commit, every blob field becomes a dense trilinear grid
                                  with this many cells along its longest axis */
    bool voxelize_realization; /* the grid holds one realization (mean + Q) rather than the mean */
} stam_params;

/* The table of "stam.KEY" options (stam_params.c; method/method_options.h). */
extern const struct method_options_def stam_options_def;

/* Q's synthesis parameters from the scene's stam options (lattice, cell, seed, and time:
 * stam.time + scene_time, the frame's) for
 * blob fields within `extent` (world units per axis, the size of the box Q is read over).
 * With lattice 0 (the default) the lattice covers the extent plus 6 alpha on every axis,
 * so that no two points of the fields see the same value of Q (the period does not show:
 * K_Q at the nearest periodic image is below exp(-18)); at most STAM_LATTICE_MAX points per
 * axis and STAM_LATTICE_POINTS_MAX in all, beyond which the cell grows (docs/stam.md). */
#define STAM_LATTICE_MAX 256
#define STAM_LATTICE_POINTS_MAX (1 << 22)
void stam_randfield_params(const stam_params *p, double scene_time, vec3 extent, randfield_params *out);

#endif
