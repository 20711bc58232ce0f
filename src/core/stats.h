/* stats.h - per-run counters of the integrators behind brume_scene_stats (docs/stats.md).
 *
 * Each worker thread of a render counts into its own block, reached through a thread-local
 * pointer that is NULL when statistics are off (render.stats false): the hot loops then pay
 * one predictable branch on a thread-local, and no atomics ever. render.c points each
 * thread at its block for the tiles it runs and sums the blocks after the run, so the
 * counts do not depend on the thread count (the times do: they are CPU seconds summed over
 * threads). */
#ifndef BRUME_CORE_STATS_H
#define BRUME_CORE_STATS_H

#include <stdint.h>
#include <time.h>

typedef struct stats_counters {
    uint64_t camera_rays;     /* camera samples traced */
    uint64_t path_vertices;   /* path/single: scattering vertices (media and surfaces) */
    uint64_t path_tentative;  /* path/single: tentative collisions of the camera-path flights */
    uint64_t path_scatterings; /* path/single: flights that ended in a medium scattering event */
    uint64_t majorant_cells;  /* path/single: majorant cells walked by every walk (flights, shadow
                                 rays), each level's steps of a two-level walk counted */
    uint64_t density_lookups; /* path/single: lookups of the media at a point (media_at) */
    uint64_t blob_queries;    /* stam: ray queries of the blob hierarchy (camera, shadow, cache) */
    uint64_t blob_nodes;      /* stam: hierarchy nodes visited by those queries */
    uint64_t blob_visits;     /* stam: blobs whose truncation sphere a query met */
    uint64_t stam_camera_blobs; /* stam: blobs met by camera rays (the transparency walk) */
    double t_li;              /* seconds in the integrator's Li, summed over threads */
    double t_tracking;        /* path: seconds in the camera-path flights (delta tracking) */
    double t_nee;             /* path: seconds in next-event estimation (shadow rays included) */
    char pad[64];             /* keeps two threads' blocks off one cache line */
} stats_counters;

/* This thread's block while it renders with statistics on, else NULL. On the GPU
 * (gpu/kernel.cu) there are no statistics: NULL, and no clock. */
#if defined(__CUDA_ARCH__)
#define stats_tls ((stats_counters *)0)
static inline double stats_now(void) { return 0.0; }
#else
extern _Thread_local stats_counters *stats_tls;

static inline double stats_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}
#endif

/* a += b, field by field. */
void stats_merge(stats_counters *a, const stats_counters *b);

#endif
