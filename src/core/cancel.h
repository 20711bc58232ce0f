/* cancel.h - asking a render's progress callback whether to go on, from a phase that
 * renders no sample yet (Blasi's light pass).
 *
 * Tiles call the callback as they finish (job/render.c); a phase before the first tile
 * has no tiles, so its loops call cancel_poll_stop between units of work (a ray): at most
 * every CANCEL_POLL_SECONDS one thread at a time calls the callback with done = 0 and
 * total = 1, and once it returns false every later call returns true. Without a callback
 * nothing is asked and the cost is one atomic load. */
#ifndef BRUME_CORE_CANCEL_H
#define BRUME_CORE_CANCEL_H

#include <pthread.h>
#include <stdatomic.h>
#include <stdbool.h>

#include "brume.h"

#define CANCEL_POLL_SECONDS 0.1

typedef struct cancel_poll {
    brume_progress_fn fn; /* the render's callback, or NULL */
    void *user;
    atomic_bool stop;
    atomic_llong next_ns; /* CLOCK_MONOTONIC time of the next call to fn */
    long long deadline_ns; /* the render's time budget ends here (0: none): the phase stops too */
    atomic_bool out_of_time; /* it stopped because the budget was spent */
    pthread_mutex_t lock; /* fn is never called twice at once */
} cancel_poll;

/* rs->time_budget > 0: the phase is a render's first and its budget starts now; a phase
 * past it stops as if cancelled, and cancel_poll_out_of_time says so. */
void cancel_poll_init(cancel_poll *c, const brume_render_settings *rs);
/* true when the phase must stop: the callback said so, now or before. Thread-safe. */
bool cancel_poll_stop(cancel_poll *c);
/* true when a call to cancel_poll_stop returned true; asks nothing. */
bool cancel_poll_cancelled(const cancel_poll *c);
/* true when it stopped because the time budget was spent. */
bool cancel_poll_out_of_time(const cancel_poll *c);
void cancel_poll_finish(cancel_poll *c);

/* Loading a scene: brume_context_cancel_loads(ctx) (async-signal-safe) ends every
 * load in progress with ctx. Each load notes its context's cancel count when it starts
 * (cancel_load_begin, on its thread; ctx NULL: a load nothing cancels); the generators' loops
 * (procedural cloud, fractal grids) call cancel_load_check at least every second of work,
 * which says BRUME_ERROR_CANCELLED (err_set naming `what`) once the count moved. Outside a
 * load it never cancels. */
void cancel_load_begin(brume_context *ctx);
void cancel_load_end(void);
brume_status cancel_load_check(const char *what);
/* Whether this thread's load was cancelled, as cancel_load_check says, without setting an
 * error (a reader waiting on its sandboxed child: io/sandbox.c). */
bool cancel_load_requested(void);

/* A render's phase that runs a generator's code (Stam's random field, made when a render
 * begins): while c is set on this thread, cancel_load_check also asks it (cancel_poll_stop),
 * so the render's progress callback stops the generator as brume_context_cancel_loads stops
 * a load. NULL unsets it. */
void cancel_load_watch(cancel_poll *c);

#endif
