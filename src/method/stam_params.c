/* stam_params.c - the table of Stam's renderer options, and Q's parameters from them. */
#include "method/stam_params.h"

#include <math.h>

#include "method/option_table.h"

static const method_option options[] = {
    {.key = "stam.eps", .kind = OPTION_NUMBER, .lo = 0.0, .hi = OPTION_BIG, .what = "a number >= 0",
     OPTION_FIELD(stam_params, eps), .def = "0",
     .doc = "magnitude of the density variance of the random blobs rho_i = mean_i + sigma_i Q: sigma_i^2 = eps "
            "min(mean_i, eta) (Stam 1994, Section 4; docs/stam.md)"},
    {.key = "stam.eta", .kind = OPTION_NUMBER, .lo = 1e-30, .hi = OPTION_BIG, .what = "a number > 0",
     OPTION_FIELD(stam_params, eta), .def = "1e30", .doc = "clamping value of the variance"},
    {.key = "stam.alpha", .kind = OPTION_NUMBER, .lo = 1e-9, .hi = OPTION_BIG, .what = "a length > 0",
     OPTION_FIELD(stam_params, alpha), .def = "0.05",
     .doc = "correlation length of Q (world units): correlation exp(-r^2 / (2 alpha^2))"},
    {.key = "stam.lattice", .kind = OPTION_INTEGER, .flags = OPTION_ZERO_OR, .lo = 2.0, .hi = 512.0,
     .what = "0 (automatic) or an integer in [2, 512]", OPTION_FIELD(stam_params, lattice), .def = "0",
     .doc = "Q is synthesized on a periodic lattice^3 lattice (the paper: 32); 0 = a lattice covering the blob "
            "fields plus 6 alpha on each axis, so that Q's period never shows (at most " OPTION_STR(STAM_LATTICE_MAX)
            " points per axis and 2^22 in all, beyond which the cell grows; docs/stam.md)"},
    {.key = "stam.cell", .kind = OPTION_NUMBER, .lo = 0.0, .hi = OPTION_BIG, .what = "a length >= 0 (0 = alpha / 3)",
     OPTION_FIELD(stam_params, cell), .def = "0", .doc = "spacing of Q's lattice (world units); 0 = alpha / 3"},
    {.key = "stam.seed", .kind = OPTION_INTEGER, .lo = 0.0, .hi = 9007199254740992.0,
     .what = "an integer in [0, 2^53]", OPTION_FIELD(stam_params, seed), .def = "1", .doc = "Q's realization"},
    {.key = "stam.time", .kind = OPTION_NUMBER, .lo = -OPTION_BIG, .hi = OPTION_BIG,
     .what = "a finite time in seconds", OPTION_FIELD(stam_params, time), .def = "0",
     .doc = "scene time, added to the frame's: drifting blob fields move, Q evolves (and drifts with them); render "
            "a frame of an animation by setting it"},
    {.key = "stam.rate", .kind = OPTION_NUMBER, .lo = 0.0, .hi = OPTION_BIG, .what = "a rate >= 0",
     OPTION_FIELD(stam_params, rate), .def = "1",
     .doc = "Q's base angular frequency in time (radians per unit time); fine detail changes faster"},
    {.key = "stam.ambient", .kind = OPTION_COLOR, .lo = 0.0, .hi = OPTION_BIG,
     .what = "a radiance >= 0 (v or r,g,b)", OPTION_FIELD(stam_params, ambient), .def = "0",
     .doc = "constant source term standing in for multiple scattering: J += albedo x ambient"},
    {.key = "stam.steps", .kind = OPTION_INTEGER, .lo = 1.0, .hi = 256.0, .what = "an integer in [1, 256]",
     OPTION_FIELD(stam_params, steps), .def = "16",
     .doc = "steps of the average-source-function quadrature per ray"},
    {.key = "stam.light_grid", .kind = OPTION_INTEGER, .lo = 0.0, .hi = 512.0, .what = "an integer in [0, 512]",
     OPTION_FIELD(stam_params, light_grid), .def = "32",
     .doc = "cells along the longest axis of the cache of light transparencies inside the media; 0 = an exact "
            "shadow ray per step"},
    {.key = "stam.bvh", .kind = OPTION_BOOL, .what = "true or false", OPTION_FIELD(stam_params, bvh), .def = "true",
     .doc = "false: each ray tests every blob (benchmarks)"},
    {.key = "stam.variant", .kind = OPTION_ENUM, OPTION_NAMES2("corrected", "paper"), OPTION_FIELD(stam_params, paper),
     .def = "corrected",
     .doc = "`paper`: Eq. 12 and 13 as printed (Var T_i = K_Q(0) eps I_F, realized with a Q of variance K_Q(0)) and "
            "J-bar's shadows from the mean density; `corrected`: the repaired variance and the realized density in "
            "J-bar's shadows (docs/stam.md)"},
    {.key = "stam.kernel", .kind = OPTION_ENUM, OPTION_NAMES2("gaussian", "table"), OPTION_FIELD(stam_params, kernel),
     .def = "gaussian",
     .doc = "the blobs' radial kernel W of Eq. 3: `gaussian` (Appendix A) or `table`, the profile W(r/h) of "
            "stam.kernel_file, normalised by brume to unit mass; every method renders the same field (docs/stam.md)"},
    {.key = "stam.kernel_file", .kind = OPTION_PATH, .what = "a file name", OPTION_FIELD(stam_params, kernel_file),
     .def = "",
     .doc = "with stam.kernel = table: a text file of evenly spaced `r/h W` pairs from r/h = 0, W finite, >= 0 and "
            "not increasing (docs/scene-format.md, \"Radial kernel files\")"},
    {.key = "stam.overlap", .kind = OPTION_ENUM, OPTION_NAMES2("independent", "joint"),
     OPTION_FIELD(stam_params, overlap_joint), .def = "independent",
     .doc = "`independent`: each blob's optical depth perturbed by its own sample Q(x_ui), as printed (Section 6.3); "
            "`joint`: the ray's summed perturbation scaled to the joint variance of overlapping blobs, "
            "sum_ij Cov(T_i, T_j) (docs/stam.md)"},
    {.key = "stam.voxelize.resolution", .kind = OPTION_INTEGER, .flags = OPTION_ZERO_OR, .lo = 2.0, .hi = 2048.0,
     .what = "an integer in [2, 2048] (0 = off)", OPTION_FIELD(stam_params, voxelize_resolution), .def = "0",
     .doc = "N > 0: when the scene is committed (before rendering), every blob field becomes a dense trilinear grid "
            "of N cells along its longest axis, for rendering the same cloud with `path` or `single`; in a scene file "
            "also `\"voxelize\": {\"resolution\": N}`"},
    {.key = "stam.voxelize.realization", .kind = OPTION_BOOL, .what = "true or false",
     OPTION_FIELD(stam_params, voxelize_realization), .def = "true",
     .doc = "the voxelized grid holds one explicit realization mean + sum_i sigma_i Q (clamped to >= 0); false: the "
            "mean"},
};

const method_options_def stam_options_def = {
    .method = "stam", .size = sizeof(stam_params), .options = options, .count = sizeof options / sizeof options[0]};

void stam_randfield_params(const stam_params *p, double scene_time, vec3 extent, randfield_params *out)
{
    out->cell = p->cell > 0.0 ? p->cell : p->alpha / 3.0;
    if (p->lattice > 0) {
        for (int a = 0; a < 3; a++)
            out->n[a] = p->lattice;
    } else {
        /* one period covers the fields plus 6 alpha: K_Q(6 alpha) = exp(-18) */
        double span[3];
        for (int a = 0; a < 3; a++)
            span[a] = fmin(v3_get(extent, a), 1e12) + 6.0 * p->alpha;
        for (;;) {
            double points = 1.0;
            bool fits = true;
            for (int a = 0; a < 3; a++) {
                double n = ceil(span[a] / out->cell);
                n += fmod(n, 2.0); /* even sizes: the FFT's fast path */
                out->n[a] = n < 8.0 ? 8 : (int)fmin(n, 1e9);
                points *= out->n[a];
                fits = fits && n <= STAM_LATTICE_MAX;
            }
            if (fits && points <= STAM_LATTICE_POINTS_MAX)
                break;
            out->cell *= 1.25; /* a coarser lattice (docs/stam.md: trilinear lowers the variance) */
        }
    }
    out->alpha = p->alpha;
    out->seed = p->seed;
    out->time = p->time + scene_time;
    out->rate = p->rate;
}
