/* stages.h - the queues of path states that the GPU's single-precision stage kernels
 * (gpu/stages.cu: brume_flight_f, brume_shadow_f) read and write, in structure-of-arrays
 * form: entry i of a queue is element i of every array, one thread an entry. Shared by the
 * device code and, once a wavefront driver launches the kernels, the host (docs/gpu.md,
 * "Single precision": nothing launches them yet). */
#ifndef BRUME_GPU_STAGES_H
#define BRUME_GPU_STAGES_H

#include <stdint.h>

typedef struct stage_queue {
    uint32_t n;                /* entries */
    const float *o[3], *d[3];  /* the ray: origin [world units], unit direction */
    const float *tmax;         /* where the ray's piece ends [world units] */
    uint64_t *rng_key;         /* each entry's random sequence (core/rng.h: key and counter, */
    uint64_t *rng_counter;     /* no Sobol dimensions); the counter comes back advanced */
    const float *beta[3];      /* flights: the path throughput before the flight */
    float *L[3];               /* flights: emission gathered, weighted by beta (in and out) */
    float *Tr[3];              /* out: the transmittance over [0, tmax] (flight or shadow ray) */
    float *beta_s[3];          /* flights, out: the scattering branch's throughput */
    float *t;                  /* flights, out: where the flight scatters [world units]; -1: it does not */
} stage_queue;

#endif
