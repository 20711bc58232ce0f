/* slab.h - total diffuse reflectance and transmittance of a plane-parallel slab.
 *
 * A homogeneous slab of optical thickness tau (sigma_t = 1 per unit length, thickness tau;
 * tau = 0 means semi-infinite), albedo `albedo`, refractive index 1 on both sides, lit by a
 * collimated beam at normal incidence. Rd is the fraction of the beam's power leaving the
 * lit face; Tt the fraction leaving the other face, including the unscattered exp(-tau).
 * The walk is the renderer's own: a brume scene holding the slab as a medium, free flights
 * by flight_run (ratio-tracked, one kept collision), directions by phase_sample, Russian roulette by
 * path_roulette. Estimates are deterministic for a given seed and sample count, whatever
 * the thread count. */
#ifndef BRUME_RENDER_SLAB_H
#define BRUME_RENDER_SLAB_H

#include <stdint.h>

#include "brume.h"
#include "phase/phase.h"

typedef struct slab_params {
    double albedo;    /* in [0, 1] */
    double tau;       /* optical thickness, > 0; 0 = semi-infinite */
    const phase *ph;  /* borrowed */
    uint64_t samples; /* photons, >= 1 */
    uint64_t seed;
    int threads;      /* 0 = one per core */
    int max_depth;    /* scattering events counted, >= 1 (1 = single scattering) */
    brume_sampler sampler; /* sobol: photon i is sample i of one Sobol sequence (per 2^32) */
} slab_params;

typedef struct slab_result {
    double Rd, Rd_stderr; /* total diffuse reflectance and its standard error */
    double Tt, Tt_stderr; /* total transmittance (with the unscattered part) */
    double Tc;            /* the unscattered part exp(-tau), exact */
} slab_result;

brume_status slab_run(const slab_params *p, slab_result *out);

#endif
