/* flight_type.h - a free flight's state (render/flight.h) over one real type
 * (core/real_names.h) and scene FLIGHT_SCENE: flight in double over a brume_scene, flightf
 * in float over the float view of one medium (render/track_float.h). */
#include "core/real_names.h"

#ifndef FLIGHT_TAIL_TR
/* Where a flight's delta tail starts (f->tail_Tr) after the first scattering event: measured
 * in docs/performance.md, "The flight's delta tail". */
#define FLIGHT_TAIL_TR 0.6
#endif

typedef struct RN(flight) {
    const FLIGHT_SCENE *s;
    RN(ray) r;
    rng *g;
    RN(color) beta;      /* in: path throughput before the flight */
    RN(color) L;         /* in/out: emission gathered along the flight, weighted by beta */
    RN(color) Tr;        /* out: ratio-tracked transmittance over [0, tmax] (0 once roulette stopped it) */
    R A;                 /* out: sum of the collisions' scattering weights a_i (0: none) */
    RN(color) beta_s;    /* out: throughput of the scattering branch at the kept collision */
    R t;                 /* out: where the kept collision is */
    RN(medium_sample) ms; /* out: the media there (n, index and weight, what media_choose_phase reads) */
    RN(medium_sample) cur; /* scratch: the media at the current collision */
    R tail_Tr;           /* in: once max Tr is below it, the flight's delta tail (flight_run); 0: none */
    R u;                 /* scratch: the reservoir's uniform, rescaled after each choice */
    rng *ug;             /* scratch: the sequence and dimension u is drawn from, at the first */
    uint64_t udim;       /*          collision (a flight that meets none never computes it) */
    uint32_t absent;     /* in/out: the bounded media the flight is not in (track_collisions'; 0:
                            none), changed where it crosses a surface (flight_track's pieces) */
    uint32_t absent_s;   /* out: those at the kept collision */
    R t0;                /* scratch: where the piece being tracked starts along the flight */
} RN(flight);

#include "core/real_names_end.h"
