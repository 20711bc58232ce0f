/* watch.h - the bound on one camera sample's work, and its stop.
 *
 * A sample's walks (its free flights, shadow rays and transmittance estimates) make
 * tentative collisions at the majorant's rate. Their expected number along a chord is the
 * majorant's optical depth, at most the sum over media of sigma_t_max x rho_max x the
 * field's diagonal (tau_maj); a sample makes at most max_depth + 1 flights and a few walks
 * per vertex. watch_bound allows WATCH_MARGIN x (max_depth + 1) x (tau_maj + 1) of them, at
 * least 2^24 and at most 2^40: a Poisson count reaches WATCH_MARGIN times its mean with
 * negligible probability, so no valid scene reaches the bound (the test suite's and docs/'s
 * scenes do not: tests/test_hostile_work.c), and one that does would run for hours. A
 * sample that reaches it ends there, its walks cut (a bias, so it is counted: brume_stats
 * samples_cut, `--stats` and the render's summary).
 *
 * The render job points this thread's watch_tls at its watch while it runs a tile; every
 * WATCH_POLL collisions the watch asks poll() whether the render must stop (SIGINT, the
 * progress callback, the time budget): then the sample ends at once and is discarded, so
 * that a sample of minutes still stops within a second. Without a watch (the light passes,
 * the GPU) nothing is counted. */
#ifndef BRUME_RENDER_WATCH_H
#define BRUME_RENDER_WATCH_H

#include <stdbool.h>
#include <stdint.h>

#define WATCH_MARGIN 1024.0
#define WATCH_POLL ((uint64_t)1 << 16)

typedef struct sample_watch {
    uint64_t collisions;   /* tentative collisions since the watch was set */
    uint64_t sample_start; /* collisions when the current sample began */
    uint64_t check_at;     /* the next count at which watch_slow runs */
    uint64_t next_poll;    /* the next count at which poll is asked */
    uint64_t bound;        /* tentative collisions a sample may make */
    bool cut;              /* the current sample reached the bound */
    bool stopped;          /* poll said stop: the current sample is discarded */
    uint64_t ncut;         /* samples the caller counted as cut */
    bool (*poll)(void *user);
    void *user;
} sample_watch;

struct brume_scene;

/* The bound for a scene rendered with max_depth (above). */
uint64_t watch_bound(const struct brume_scene *s, int max_depth);
/* A new sample on w (its count from 0; cut cleared; a stop stays). */
void watch_sample(sample_watch *w);
/* Whether the walk in progress must end now (the slow path of watch_collision). */
bool watch_slow(sample_watch *w);

#if defined(__CUDA_ARCH__)
static inline bool watch_collision(void) { return false; }
#else
extern _Thread_local sample_watch *watch_tls;
/* One more tentative collision of this thread's sample: true when its walk must end. */
static inline bool watch_collision(void)
{
    sample_watch *w = watch_tls;
    return w && ++w->collisions >= w->check_at && watch_slow(w);
}
#endif

#endif
