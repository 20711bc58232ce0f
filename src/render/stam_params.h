/* stam_params.h - the scene's settings for Stam's stochastic renderer (scene key "stam",
 * docs/scene-format.md): the statistics of the perturbation and the renderer's options. */
#ifndef BRUME_RENDER_STAM_PARAMS_H
#define BRUME_RENDER_STAM_PARAMS_H

#include <stdbool.h>
#include <stdint.h>

#include "core/color.h"

typedef struct stam_params {
    double eps;     /* magnitude of the density variance: sigma^2 = eps F_eta(mean), >= 0 */
    double eta;     /* clamping value of F_eta, > 0 (INFINITY: no clamping) */
    double alpha;   /* correlation length of Q, world units, > 0 */
    int lattice;    /* Q's periodic lattice: lattice^3 points (paper: 32); 0 = covering the blob
                       fields (stam_randfield_params) */
    double cell;    /* Q's lattice spacing, world units; 0 = alpha / 3 */
    uint64_t seed;  /* Q's realization */
    double time;    /* scene time: blobs drift to x + v t, Q evolves */
    double rate;    /* Q's base angular frequency in time, radians per unit time */
    color ambient;  /* constant source term standing in for multiple scattering */
    int steps;      /* steps of the average-source-function quadrature per ray */
    int light_grid; /* cells along the longest axis of the light-transparency cache; 0 = exact shadow rays */
    bool bvh;       /* false: scan every blob for each ray (benchmarks) */
    bool paper;     /* variant "paper": Eq. 12 and 13 as printed (Var T_i = K_Q(0) eps I_F with
                       K_Q(0) = (2 pi)^(-3/2) alpha^-3, realized with a Q of variance K_Q(0)) and
                       J-bar's shadows from the mean density; false = "corrected" (docs/stam.md) */
} stam_params;

static inline void stam_params_default(stam_params *p)
{
    p->eps = 0.0;
    p->eta = 1e30;
    p->alpha = 0.05;
    p->lattice = 0;
    p->cell = 0.0;
    p->seed = 1;
    p->time = 0.0;
    p->rate = 1.0;
    p->ambient = col(0.0);
    p->steps = 16;
    p->light_grid = 32;
    p->bvh = true;
    p->paper = false;
}

#endif
